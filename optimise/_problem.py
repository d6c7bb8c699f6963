"""Design variables and objectives for tooth-modification optimisation (docs/design.md,
"Optimisation").

Design variables are named like the case file: ``tip_relief.depth``, ``tip_relief.extent``,
``root_relief.depth``, ``root_relief.extent``, ``crowning.depth``, ``end_relief.depth``,
``end_relief.extent``, each optionally prefixed by ``pinion.`` or ``gear.``; without a prefix a
variable acts on both members at once (symmetric modification).

Normalisation: depths are E* = E/δ_m with δ_m = F_n / K̄ the mean static deflection of the
unmodified mesh at the design torque (K̄ its mean mesh stiffness); extents are Γ itself. Bounds are
kept by the reparametrisation x = lo + (hi − lo)·sigmoid(u), u ∈ ℝ free.

Objectives (scaled by the unmodified value at the design torque, so O(1); ``load_centroid`` by
a fixed 0.01):
``te_rms``, ``te_ptp``, ``robust_te_rms`` (mean or max of TE RMS over a torque range, vmapped),
``max_line_load`` (maximum line load over the mesh cycle), ``load_centroid`` (the square c² of
the load centroid's offset from mid-face, :func:`load_centroid`; 0 = centred load) and
``line_load_lp`` (the L_p norm of the line load over the load map, :func:`line_load_lp`, a smooth
surrogate of the maximum). Every objective works on the rigid mesh and on any scene, e.g. the
hybrid scene of :func:`jaxgear.dynamics.static_scene` at a pinion speed (centrifugal loads).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

import jaxgear as jg
from jaxgear.dynamics import Newmark, SteadyState, band_dynamic_factor, dynamic_model
from jaxgear.scenes import HybridPair, cache_window_compliance

__all__ = [
    "VARIABLES",
    "OBJECTIVES",
    "OBJECTIVE_UNITS",
    "Problem",
    "make_problem",
    "load_centroid",
    "line_load_lp",
]

# variable -> (MemberModification field, kind)
VARIABLES = {
    "tip_relief.depth": ("tip_relief_depth", "depth"),
    "tip_relief.extent": ("tip_relief_extent", "extent"),
    "root_relief.depth": ("root_relief_depth", "depth"),
    "root_relief.extent": ("root_relief_extent", "extent"),
    "crowning.depth": ("crowning_depth", "depth"),
    "end_relief.depth": ("end_relief_depth", "depth"),
    "end_relief.extent": ("end_relief_extent", "end_extent"),
}
OBJECTIVES = (
    "te_rms",
    "te_ptp",
    "robust_te_rms",
    "max_line_load",
    "load_centroid",
    "line_load_lp",
    "dynamic_factor",
)
# units of each (unscaled) objective, as used in report keys
OBJECTIVE_UNITS = {
    "te_rms": "m",
    "te_ptp": "m",
    "robust_te_rms": "m",
    "max_line_load": "N_per_m",
    "load_centroid": "face_fraction_squared",
    "line_load_lp": "N_per_m",
    "dynamic_factor": "dimensionless",
}
# the load_centroid objective is c²/CENTROID_SCALE = (c / 0.1)²: 1 for a centroid 10 % of the
# face width off centre (the unmodified pair is often centred, c = 0: no scale to take from it)
CENTROID_SCALE = 0.01
LP_ORDER_RANGE = (1.0, 64.0)
EXACT = jg.ExactContact()  # the default law of the evaluations (a module without arrays)
DEFAULT_BOUNDS = {"depth": (0.0, 3.0), "extent": (0.02, 0.98), "end_extent": (0.02, 0.5)}


def _split(name: str) -> tuple[tuple[str, ...], str]:
    parts = name.strip().split(".")
    members: tuple[str, ...] = ("pinion", "gear")
    if parts[0] in ("pinion", "gear"):
        members, parts = (parts[0],), parts[1:]
    base = ".".join(parts)
    if base not in VARIABLES:
        allowed = ", ".join(sorted(VARIABLES))
        raise ValueError(
            f"variables: {name!r} is an unknown design variable, allowed {allowed}, optionally "
            "prefixed by 'pinion.' or 'gear.'"
        )
    return members, base


def load_centroid(res: jg.QuasiStaticResult, face_width) -> Float[Array, ""]:
    """Load centroid across the face over the mesh positions, as a fraction of the face width.

    c = (z̄ − b/2)/b with z̄ = Σ q z / Σ q, the sums over every cell on the flanks at every
    position of ``res`` (q the line load, N/m; the cells have equal lengths, so q weights like
    the cell force). z is the base-plane face coordinate (docs/design.md, "Base plane and sign
    conventions"), z ∈ [0, b]: c > 0 means
    the load sits towards the z = b edge, c < 0 towards the z = 0 edge, c = 0 centred; |c| <= 1/2.
    On the hybrid scenes the body's axial coordinate is z − b/2 (for the power wheel
    ``power-helical-wheel`` the web meets the rim at z = 8 mm and z = b is the cantilevered edge).

    Args:
        res: a quasi-static result (any scene; exact or smooth contact).
        face_width: b (m).

    Returns:
        c, dimensionless, differentiable in the modifications (smooth contact everywhere, exact
        contact away from changes of the contact set).
    """
    q = jnp.where(res.cell_mask, res.line_load, 0.0)
    zbar = jnp.sum(q * res.cell_z) / jnp.sum(q)
    return zbar / face_width - 0.5


def line_load_lp(res: jg.QuasiStaticResult, p=8.0) -> Float[Array, ""]:
    """L_p norm of the line load over the load map (N/m): a smooth surrogate of its maximum.

    ‖q‖_p = (mean over the flank cells and positions of q^p)^(1/p), the mean taken over every
    cell on the flanks at every position of ``res`` (loaded or not; a count fixed by the
    geometry). It rises towards ``max q`` as p grows (‖q‖_p <= max q, and ‖q‖_∞ = max q) and,
    unlike the maximum, has a gradient that sees every loaded cell.

    Args:
        res: a quasi-static result.
        p: the order, >= 1 (default 8).

    Returns:
        ‖q‖_p in N/m.
    """
    q = jnp.maximum(jnp.where(res.cell_mask, res.line_load, 0.0), 0.0)
    ref = jax.lax.stop_gradient(jnp.max(q))  # ‖q‖_p is 1-homogeneous: no gradient is lost
    ref = jnp.where(ref > 0, ref, 1.0)
    n = jnp.sum(res.cell_mask)
    return ref * (jnp.sum((q / ref) ** p) / n) ** (1.0 / p)


class Problem(eqx.Module):
    """A tooth-modification optimisation problem on the quasi-static model.

    Attributes:
        mesh: the structure the quasi-static solve runs on: the rigid mesh model, or a scene
            (e.g. the hybrid scene with condensed bodies). base: modifications the
            variables are written into.
        speed: pinion speed of the quasi-static objectives (rad/s; the centrifugal loads of
            condensed bodies, 0 at rest).
        torques: torques of the objective (N·m), shape (T,) (one entry for single-load objectives).
        design_torque: N·m. delta_m: mean static deflection δ_m (m) at the design torque.
        scale: unmodified objective value at the design torque (objective units);
            ``CENTROID_SCALE`` for ``load_centroid``.
        lower, upper: bounds in normalised units, shape (n,).
        contact: the smooth contact law of the objective and its gradients
            (:class:`jaxgear.SmoothContact`).
        face_width: b (m), of the load centroid.
        lp_order: p of ``line_load_lp``.
        names: variable names (static). objective: objective name (static).
        reduce: "mean" | "max" over torques (static). positions_per_pitch: static.
        speeds: the speed band of the ``dynamic_factor`` objective (rad/s), (S,), else None.
        integrator, window: that objective's Newmark and steady-state window, else None.
    """

    mesh: jg.MeshModel | jg.Scene
    base: jg.Modifications
    torques: Float[Array, " T"]
    design_torque: Float[Array, ""]
    delta_m: Float[Array, ""]
    scale: Float[Array, ""]
    lower: Float[Array, " n"]
    upper: Float[Array, " n"]
    contact: jg.SmoothContact
    face_width: Float[Array, ""]
    lp_order: Float[Array, ""]
    speed: Float[Array, ""]
    names: tuple[str, ...] = eqx.field(static=True)
    objective: str = eqx.field(static=True)
    reduce: str = eqx.field(static=True)
    positions_per_pitch: int = eqx.field(static=True)
    speeds: Float[Array, " S"] | None = None
    integrator: Newmark | None = None
    window: SteadyState | None = None

    # -- variables ---------------------------------------------------------------------------
    def modifications(self, x: Float[Array, " n"]) -> jg.Modifications:
        """Modifications for normalised design values ``x`` (E* for depths, Γ for extents)."""
        mods = self.base
        for i, name in enumerate(self.names):
            members, base = _split(name)
            field, kind = VARIABLES[base]
            value = x[i] * self.delta_m if kind == "depth" else x[i]
            for m in members:
                mods = eqx.tree_at(lambda t, m=m, f=field: getattr(getattr(t, m), f), mods, value)
        return mods

    def to_physical(self, x) -> dict:
        """Normalised values → case-file units (``depth_um`` or extent), as a dict by name."""
        out = {}
        for i, name in enumerate(self.names):
            kind = VARIABLES[_split(name)[1]][1]
            v = float(x[i])
            out[name] = v * float(self.delta_m) * 1e6 if kind == "depth" else v
        return out

    def from_physical(self, values: dict) -> np.ndarray:
        """Case-file units (µm for depths) → normalised values, in ``names`` order."""
        x = []
        for name in self.names:
            kind = VARIABLES[_split(name)[1]][1]
            v = float(values[name])
            x.append(v * 1e-6 / float(self.delta_m) if kind == "depth" else v)
        return np.asarray(x)

    def bounded(self, u: Float[Array, " n"]) -> Float[Array, " n"]:
        """Unconstrained u → x in [lower, upper]."""
        return self.lower + (self.upper - self.lower) * jax.nn.sigmoid(u)

    def unbounded(self, x) -> Float[Array, " n"]:
        """x in (lower, upper) → u (inverse of :meth:`bounded`; clipped just inside the bounds)."""
        t = (jnp.asarray(x) - self.lower) / (self.upper - self.lower)
        t = jnp.clip(t, 1e-6, 1 - 1e-6)
        return jnp.log(t) - jnp.log1p(-t)

    # -- objectives --------------------------------------------------------------------------
    def _law(self, contact: jg.ContactLaw | None) -> jg.ContactLaw:
        """``contact``, or the problem's smooth law when None."""
        if contact is None:
            return self.contact
        if not isinstance(contact, jg.ExactContact | jg.SmoothContact):
            raise ValueError(
                f"contact = {contact!r}: allowed jaxgear.ExactContact(...), "
                "jaxgear.SmoothContact(...) or None (the problem's smooth law)"
            )
        return contact.astype(self.delta_m.dtype)

    def _single(self, mods, torque, contact):
        if self.objective == "dynamic_factor":
            return self._dynamic(mods, torque, contact)
        r = jg.quasi_static(
            self.mesh,
            mods,
            torque,
            speed=self.speed,
            contact=self._law(contact),
            positions_per_pitch=self.positions_per_pitch,
        )
        if self.objective in ("te_rms", "robust_te_rms"):
            return r.te_rms
        if self.objective == "te_ptp":
            return r.te_ptp
        if self.objective == "load_centroid":
            return load_centroid(r, self.face_width) ** 2
        if self.objective == "line_load_lp":
            return line_load_lp(r, self.lp_order)
        return r.max_line_load

    def _dynamic(self, mods, torque, contact):
        """The smooth dynamic factor over the speed band (hybrid Newmark, p-means; the seed's
        Rayleigh damping D1)."""
        return band_dynamic_factor(
            dynamic_model(self.mesh, mods, torque),
            self.speeds,
            integrator=self.integrator,
            contact=self._law(contact),
            window=self.window,
        )

    def value(
        self, x: Float[Array, " n"], contact: jg.ContactLaw | None = None
    ) -> Float[Array, ""]:
        """Scaled objective at normalised design values ``x`` (1 = unmodified at design load;
        ``load_centroid``: (c/0.1)²), in the ``contact`` law (default None: the problem's smooth
        law, whose gradients the optimiser follows; :class:`jaxgear.ExactContact` for the
        design as the exact law sees it)."""
        mods = self.modifications(x)
        vals = jax.vmap(lambda t: self._single(mods, t, contact))(self.torques)
        v = jnp.max(vals) if self.reduce == "max" else jnp.mean(vals)
        return v / self.scale

    def te_rms_vs_torque(
        self, x, torques, contact: jg.ContactLaw | None = EXACT
    ) -> Float[Array, " T"]:
        """TE RMS (m) of design ``x`` at each of ``torques`` (N·m), vmapped: a Harris-map view
        (``contact``: the exact law by default, None the problem's smooth law)."""
        mods = self.modifications(x)
        return jax.vmap(
            lambda t: (
                jg.quasi_static(
                    self.mesh,
                    mods,
                    t,
                    speed=self.speed,
                    contact=self._law(contact),
                    positions_per_pitch=self.positions_per_pitch,
                ).te_rms
            )
        )(jnp.asarray(torques))

    def metrics(self, x, contact: jg.ContactLaw | None = EXACT) -> dict:
        """Every objective's quantity at the design torque for design ``x``, unscaled, as a dict:
        ``te_rms_m``, ``te_ptp_m``, ``max_line_load_N_per_m``, ``line_load_lp_N_per_m`` (order
        ``lp_order``) and the signed ``load_centroid`` (fraction of b, see :func:`load_centroid`),
        in the ``contact`` law (the exact law by default, None the problem's smooth law).
        """
        r = jg.quasi_static(
            self.mesh,
            self.modifications(jnp.asarray(x)),
            self.design_torque,
            speed=self.speed,
            contact=self._law(contact),
            positions_per_pitch=self.positions_per_pitch,
        )
        return {
            "te_rms_m": r.te_rms,
            "te_ptp_m": r.te_ptp,
            "max_line_load_N_per_m": r.max_line_load,
            "line_load_lp_N_per_m": line_load_lp(r, self.lp_order),
            "load_centroid": load_centroid(r, self.face_width),
        }

    def sharp(self) -> "Problem":
        """The same problem with sharp relief starts (``relief_blend`` and ``end_relief_blend``
        0): the design as the case file writes it, for evaluations in exact contact."""
        zero = jnp.asarray(0.0)
        return eqx.tree_at(
            lambda p: (
                p.base.pinion.relief_blend,
                p.base.gear.relief_blend,
                p.base.pinion.end_relief_blend,
                p.base.gear.end_relief_blend,
            ),
            self,
            (zero, zero, zero, zero),
        )

    def per_torque(self, x, contact: jg.ContactLaw | None = EXACT) -> Float[Array, " T"]:
        """Unscaled objective at each torque (objective units, ``OBJECTIVE_UNITS``), in the
        ``contact`` law (the exact law by default, None the problem's smooth law)."""
        mods = self.modifications(x)
        return jax.vmap(lambda t: self._single(mods, t, contact))(self.torques)


def make_problem(
    scene: jg.MeshModel | jg.Scene,
    modifications: jg.Modifications,
    torque,
    variables,
    objective: str = "te_rms",
    *,
    torques=None,
    reduce: str = "max",
    bounds: dict | None = None,
    positions_per_pitch: int = 64,
    relief_blend: float | None = None,
    end_relief_blend: float | None = None,
    lp_order: float = 8.0,
    speed: float = 0.0,
    speeds=None,
    contact: jg.SmoothContact | None = None,
    integrator: Newmark | None = None,
    window: SteadyState | None = None,
) -> Problem:
    """Build a :class:`Problem` on model objects (a case file's problem:
    :func:`jaxgear.io.case_problem`).

    Args:
        scene: the structure the quasi-static solve runs on: a :class:`jaxgear.MeshModel` (the
            rigid mesh) or a scene, e.g. the hybrid scene of
            :func:`jaxgear.dynamics.static_scene` (condensed bodies; its window compliance is
            cached here once for every evaluation, :func:`jaxgear.scenes.cache_window_compliance`).
        modifications: the starting design; it holds the values that are not variables.
        torque: the design torque (N·m) > 0: the scale of the objective and of the depths
            (δ_m, the mean static deflection there).
        variables: design-variable names (see module docstring), or a comma-separated string.
        objective: one of ``OBJECTIVES``.
        torques: torques (N·m) of ``robust_te_rms``, shape (T,), T >= 1; default ``torque``.
        reduce: "max" (worst case) or "mean" over the torques (robust objective).
        bounds: optional ``{name: (lo, hi)}`` in normalised units (E* for depths, Γ for extents).
        positions_per_pitch: mesh positions per base pitch of the quasi-static objectives.
        relief_blend: rounding of the relief starts in roll-fraction units (see
            ``MemberModification.relief_blend``); default one position step, 1/(P ε_α), which
            makes the sampled objective smooth in the extents. 0 keeps sharp relief starts.
        end_relief_blend: rounding of the end relief start in lead-fraction units (see
            ``MemberModification.end_relief_blend``); default one slice, 1/N, when an end relief
            extent is a design variable (it makes the objective sampled at the slice centres
            smooth in the extent), else 0 (sharp: the design as written).
        lp_order: p of the ``line_load_lp`` objective, in [1, 64] (default 8).
        speed: pinion speed (rad/s) >= 0 of the quasi-static objectives: the centrifugal loads
            of the scene's condensed bodies (default 0, at rest).
        speeds: pinion speeds (rad/s) of the ``dynamic_factor`` objective, shape (S,): its speed
            band (needs a ``scene`` with condensed bodies: the hybrid Newmark of
            :func:`jaxgear.dynamics.band_dynamic_factor`, a smooth worst dynamic factor over the
            band, centrifugal loads at each speed).
        contact: the smooth law of the objective and its gradients (default
            ``SmoothContact(1e-7)``, with 50 Newton steps for ``dynamic_factor``, the hybrid
            dynamics' cap).
        integrator, window: the Newmark and the steady-state window of ``dynamic_factor``
            (default ``Newmark(32)`` and ``SteadyState(20, 4)``).

    The ``load_centroid`` objective is c² (:func:`load_centroid`) scaled by ``CENTROID_SCALE``
    = 0.01: (c/0.1)², 1 for a centroid 10 % of the face width off centre (the unmodified pair,
    the scale of the other objectives, is often centred).

    Raises:
        ValueError: unknown variable or objective, duplicated variable, empty torque range,
            bounds crossed, extents outside (0, 1), negative depth bounds, ``lp_order`` outside
            [1, 64], a contact law that is not smooth, settings that are not settings objects.
    """
    if isinstance(variables, str):
        variables = [v for v in variables.split(",") if v.strip()]
    names = tuple(v.strip() for v in variables)
    if not names:
        raise ValueError("variables is empty: give at least one design variable")
    if len(set(names)) != len(names):
        raise ValueError(f"variables = {','.join(names)!r} names a variable twice")
    for n in names:
        _split(n)
    if objective not in OBJECTIVES:
        raise ValueError(f"objective = {objective!r} is unknown: allowed {', '.join(OBJECTIVES)}")
    lp_order = float(lp_order)
    if not LP_ORDER_RANGE[0] <= lp_order <= LP_ORDER_RANGE[1]:
        raise ValueError(
            f"lp_order = {lp_order:g}: out of range, allowed [{LP_ORDER_RANGE[0]:g}, "
            f"{LP_ORDER_RANGE[1]:g}]"
        )
    if reduce not in ("mean", "max"):
        raise ValueError(f"reduce = {reduce!r}: allowed 'mean', 'max'")
    if not float(torque) > 0:
        raise ValueError(f"torque = {torque!r} N·m is out of range: allowed > 0")
    if torques is None or objective != "robust_te_rms":
        torques = np.array([float(torque)])
    torques = np.asarray(torques, dtype=float).reshape(-1)
    if torques.size == 0:
        raise ValueError("torques is empty: give at least one torque (N·m)")
    if np.any(torques <= 0):
        raise ValueError(f"torques = {torques.tolist()} N·m: allowed > 0 N·m only")
    lo, hi = [], []
    bounds = dict(bounds or {})
    for n in names:
        kind = VARIABLES[_split(n)[1]][1]
        a, b = bounds.pop(n, DEFAULT_BOUNDS[kind])
        if not a < b:
            raise ValueError(f"bounds of {n!r} = ({a}, {b}) are crossed: need lower < upper")
        if kind in ("extent", "end_extent") and not (0 < a and b < 1):
            raise ValueError(f"bounds of {n!r} = ({a}, {b}): an extent must stay inside (0, 1)")
        if kind == "depth" and a < 0:
            raise ValueError(f"bounds of {n!r} = ({a}, {b}): a depth must be >= 0")
        lo.append(a)
        hi.append(b)
    if bounds:
        raise ValueError(f"bounds given for names not in variables: {sorted(bounds)}")
    mesh = scene
    dynamic = objective == "dynamic_factor"
    if contact is None:
        contact = jg.SmoothContact(1e-7, 50 if dynamic else 100)
    if not isinstance(contact, jg.SmoothContact):
        raise ValueError(
            f"contact = {contact!r}: allowed a jaxgear.SmoothContact (the optimiser follows "
            "the smooth law's gradients)"
        )
    integrator = Newmark(32) if integrator is None else integrator
    window = SteadyState(20, 4) if window is None else window
    if not isinstance(window, SteadyState):
        raise ValueError(f"window = {window!r}: allowed a jaxgear.dynamics.SteadyState")
    if dynamic:
        speeds = np.asarray([] if speeds is None else speeds, dtype=float).reshape(-1)
        if not isinstance(mesh, HybridPair):
            raise ValueError(
                "objective = 'dynamic_factor' needs a scene with condensed bodies (a "
                "jaxgear.scenes.HybridPair): the hybrid Newmark runs over the speed band"
            )
        if speeds.size == 0 or np.any(~(speeds > 0)) or np.any(speeds > 1e5):
            raise ValueError(
                f"speeds = {speeds.tolist()} rad/s: the dynamic_factor band needs pinion speeds in "
                "(0, 1e+05] rad/s"
            )
        if not isinstance(integrator, Newmark) or integrator.steps_per_period is None:
            raise ValueError(
                f"integrator = {integrator!r}: the dynamic_factor objective takes "
                "Newmark(steps_per_period=N)"
            )
    ppp = int(positions_per_pitch)
    if not dynamic:  # a hybrid scene's window compliance, once for every iteration
        mesh = cache_window_compliance(mesh, positions_per_pitch=ppp)
    unmod = jg.quasi_static(mesh, None, torque, speed=speed, positions_per_pitch=ppp)
    k_mean = float(jnp.mean(unmod.mesh_stiffness))
    mesh_model = mesh if isinstance(mesh, jg.MeshModel) else mesh.mesh
    delta_m = float(mesh_model.normal_load(torque)) / k_mean
    face_width = float(mesh_model.face_width)
    if objective == "load_centroid":
        scale = CENTROID_SCALE
    elif objective == "line_load_lp":
        scale = float(line_load_lp(unmod, lp_order))
    elif objective == "dynamic_factor":
        scale = 1.0  # a dynamic factor is already relative to the static mesh force
    else:
        scale = {
            "te_rms": unmod.te_rms,
            "robust_te_rms": unmod.te_rms,
            "te_ptp": unmod.te_ptp,
            "max_line_load": unmod.max_line_load,
        }[objective]
    # round the relief starts over one position step so that the sampled objective is smooth in
    # the extents (a sharp start makes it kink each time the start crosses a sampled point)
    blend = 1.0 / (ppp * float(mesh_model.contact_ratio)) if relief_blend is None else relief_blend
    # likewise the end relief start over one slice when its extent is a variable (the sampled
    # objective kinks each time the start crosses a slice centre)
    end_blend = end_relief_blend
    if end_blend is None:
        extent_var = any(_split(n)[1] == "end_relief.extent" for n in names)
        end_blend = 1.0 / mesh_model.n_slices if extent_var else 0.0
    base = eqx.tree_at(
        lambda m: (
            m.pinion.relief_blend,
            m.gear.relief_blend,
            m.pinion.end_relief_blend,
            m.gear.end_relief_blend,
        ),
        jg.Modifications() if modifications is None else modifications,
        tuple(jnp.asarray(v) for v in (blend, blend, end_blend, end_blend)),
    )
    return Problem(
        mesh=mesh,
        base=base,
        torques=jnp.asarray(torques),
        design_torque=jnp.asarray(float(torque)),
        delta_m=jnp.asarray(delta_m),
        scale=jnp.asarray(float(scale)),
        lower=jnp.asarray(lo),
        upper=jnp.asarray(hi),
        contact=contact.astype(jnp.asarray(delta_m).dtype),
        face_width=jnp.asarray(face_width),
        lp_order=jnp.asarray(lp_order),
        speed=jnp.asarray(float(speed)),
        names=names,
        objective=objective,
        reduce=reduce,
        positions_per_pitch=ppp,
        speeds=jnp.asarray(speeds) if dynamic else None,
        integrator=integrator if dynamic else None,
        window=window if dynamic else None,
    )


def zero_fluctuation_depth(extent, contact_ratio):
    """Zero-fluctuation tip relief family E*(Γ) (spur, uniform stiffness, ε_α < 2; docs/design.md,
    "Optimisation").

    ``E* = Γ ε_α² / (2Γε_α − ε_α + 1)`` for ``(ε_α−1)/(2ε_α) < Γ <= (ε_α−1)/ε_α``; NaN outside.
    """
    g = np.asarray(extent, dtype=float)
    e = float(contact_ratio)
    valid = (g > (e - 1) / (2 * e)) & (g <= (e - 1) / e + 1e-12) & (e < 2)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = g * e**2 / (2 * g * e - e + 1)
    return np.where(valid, out, math.nan)
