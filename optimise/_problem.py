"""The optimisation problem on the quasi-static model (docs/design.md, "Optimisation").

Design variables (:mod:`optimise._variables`) are named like the case file
(``tip_relief.depth``, ``pinion.crowning.depth``, ...), depths normalised by δ_m = F_n / K̄ (the
mean static deflection of the unmodified mesh at the design torque), extents Γ itself. Bounds are
kept by the reparametrisation x = lo + (hi − lo)·sigmoid(u), u ∈ ℝ free.

The objective is an object (:mod:`optimise._objectives`: :class:`TeRms`, :class:`TePeakToPeak`,
:class:`RobustTeRms`, :class:`MaxLineLoad`, :class:`LoadCentroid`, :class:`LineLoadLp`,
:class:`DynamicFactor`, :class:`LeastSafetyFactor`, the tribology objectives
:class:`MeshPowerLoss`, :class:`EfficiencyLoss`, :class:`MinSpecificFilm`,
:class:`MaxFlashTemperature`, the acoustic :class:`EquivalentRadiatedPower` and
:class:`RadiatedSoundPower`), scaled by its unmodified value at the design torque, so O(1)
(``LoadCentroid`` by a fixed 0.01). Every quasi-static objective works on the rigid mesh and on
any scene, e.g. the hybrid scene of :func:`jaxgear.io.static_scene` at a pinion speed
(centrifugal loads).
"""

from __future__ import annotations

import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

import jaxgear as jg
import jaxgear.scenes as js

from ._acoustics import EquivalentRadiatedPower, RadiatedSoundPower
from ._bearings import BearingDesign
from ._objectives import (
    AbstractObjective,
    DynamicFactor,
    LineLoadLp,
    LoadCentroid,
    MaxLineLoad,
    RobustTeRms,
    TePeakToPeak,
    TeRms,
    line_load_lp,
    load_centroid,
)
from ._safety import LeastSafetyFactor
from ._tribology import EfficiencyLoss, MaxFlashTemperature, MeshPowerLoss, MinSpecificFilm
from ._variables import VARIABLES, Variable, variables_of

__all__ = [
    "OBJECTIVES",
    "OBJECTIVE_DESIGNS_STRUCTURE",
    "OBJECTIVE_UNITS",
    "Problem",
    "Smoothing",
    "make_problem",
    "base_plane",
    "zero_fluctuation_depth",
]

_OBJECTIVE_CLASSES = (
    TeRms,
    TePeakToPeak,
    RobustTeRms,
    MaxLineLoad,
    LoadCentroid,
    LineLoadLp,
    DynamicFactor,
    LeastSafetyFactor,
    MeshPowerLoss,
    EfficiencyLoss,
    MinSpecificFilm,
    MaxFlashTemperature,
    EquivalentRadiatedPower,
    RadiatedSoundPower,
)
# the objectives' names (case files map them to objects in jaxgear.io) and their units
OBJECTIVES = tuple(c.name for c in _OBJECTIVE_CLASSES)
OBJECTIVE_UNITS = {c.name: c.units for c in _OBJECTIVE_CLASSES}
#: whether each objective takes a designed structure (a bearing's clearance):
#: :attr:`AbstractObjective.designs_structure`, by name
OBJECTIVE_DESIGNS_STRUCTURE = {c.name: c.designs_structure for c in _OBJECTIVE_CLASSES}
EXACT = jg.ExactContact()  # the default law of the evaluations (a module without arrays)


# -- the structure's base plane ------------------------------------------------------------------
@functools.singledispatch
def base_plane(structure) -> jg.MeshModel:
    """The base-plane model of the rigid mesh or of a scene of one gear mesh (its first)."""
    raise ValueError(
        f"structure = {type(structure).__name__}: allowed a jaxgear.MeshModel or a jaxgear Scene"
    )


@base_plane.register
def _(structure: jg.MeshModel) -> jg.MeshModel:
    return structure


@base_plane.register
def _(structure: js.Scene) -> jg.MeshModel:
    return structure.base_planes[0]


class Smoothing(eqx.Module):
    """How the objective is made smooth for its gradients: the smooth contact law and the
    rounding of the relief starts.

    Attributes:
        contact: the smooth law (:class:`jaxgear.SmoothContact`); default (None) the objective's
            (``SmoothContact(1e-7)``, 100 Newton steps; 50 for :class:`DynamicFactor`, the
            hybrid dynamics' cap).
        relief_blend: rounding of the relief starts in roll-fraction units (see
            ``MemberModification.relief_blend``); default (None) one position step,
            1/(P ε_α), which makes the sampled objective smooth in the extents. 0 keeps sharp
            relief starts.
        end_relief_blend: rounding of the end relief start in lead-fraction units (see
            ``MemberModification.end_relief_blend``); default (None) one slice, 1/N, when an
            end relief extent is a design variable (it makes the objective sampled at the slice
            centres smooth in the extent), else 0 (sharp: the design as written).

    Raises:
        ValueError: a contact law that is not a :class:`jaxgear.SmoothContact`.
    """

    contact: jg.SmoothContact | None = None
    relief_blend: float | None = eqx.field(default=None, static=True)
    end_relief_blend: float | None = eqx.field(default=None, static=True)

    def __check_init__(self):
        if self.contact is not None and not isinstance(self.contact, jg.SmoothContact):
            raise ValueError(
                f"contact = {self.contact!r}: allowed a jaxgear.SmoothContact (the optimiser "
                "follows the smooth law's gradients)"
            )


class Problem(eqx.Module):
    """An optimisation problem of tooth modifications (and of a rolling bearing's clearance, a
    variable of the structure: :meth:`at_design`) on the quasi-static model. Build with
    :func:`make_problem`.

    Attributes:
        mesh: the structure the evaluations run on: the rigid mesh model, or a scene
            (e.g. the hybrid scene with condensed bodies). base: modifications the
            variables are written into.
        objective: the objective (:class:`AbstractObjective`).
        variables: the design variables (:class:`Variable`), in the order of ``x``.
        speed: pinion speed of the quasi-static objectives (rad/s; the centrifugal loads of
            condensed bodies, 0 at rest).
        torques: torques of the objective (N·m), shape (T,) (``objective.torques``: one entry
            for single-load objectives).
        design_torque: N·m. delta_m: mean static deflection δ_m (m) at the design torque (a
            train's: its first mesh's, the input's).
        scale: the objective's scale (``objective.scale``: its unmodified value at the design
            torque, in its units; ``CENTROID_SCALE`` for ``LoadCentroid``).
        lower, upper: bounds in normalised units, shape (n,).
        contact: the smooth contact law of the objective and its gradients
            (:class:`jaxgear.SmoothContact`).
        face_width: b (m), of the load centroid.
        lp_order: p of the ``line_load_lp`` metric (the objective's order for
            :class:`LineLoadLp`, else 8).
        positions_per_pitch: static.
        bearings: the rolling bearings whose clearances are variables
            (:class:`optimise.BearingDesign`), or None (no variable acts on the structure).
    """

    mesh: jg.MeshModel | js.Scene
    base: jg.Modifications
    objective: AbstractObjective
    variables: tuple[Variable, ...]
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
    positions_per_pitch: int = eqx.field(static=True)
    bearings: BearingDesign | None = None

    @property
    def names(self) -> tuple[str, ...]:
        """The variables' names, in the order of ``x``."""
        return tuple(v.name for v in self.variables)

    # -- variables ---------------------------------------------------------------------------
    def modifications(self, x: Float[Array, " n"]) -> jg.Modifications:
        """Modifications for normalised design values ``x`` (E* for depths, Γ for extents; the
        variables that act on the structure are :meth:`at_design`'s)."""
        mods = self.base
        for i, var in enumerate(self.variables):
            if var.kind.acts_on != "modifications":
                continue
            value = var.kind.to_model(x[i], self.delta_m)
            for m in var.members:
                mods = eqx.tree_at(
                    lambda t, m=m, f=var.field: getattr(getattr(t, m), f), mods, value
                )
        return mods

    def at_design(self, x: Float[Array, " n"]) -> Problem:
        """The problem on the structure of design ``x``: itself where no variable acts on the
        structure; else its structure (``mesh``, and the objective's own,
        :meth:`AbstractObjective.with_structure`) with each designed bearing at its clearance
        (:meth:`optimise.BearingDesign.apply`: its load held), differentiable in ``x``."""
        slots = [i for i, v in enumerate(self.variables) if v.kind.acts_on == "structure"]
        if not slots:
            return self
        variables = [self.variables[i] for i in slots]
        values = [self.variables[i].kind.to_model(x[i], self.delta_m) for i in slots]

        def change(scene):
            return self.bearings.apply(scene, variables, values)

        return eqx.tree_at(lambda p: (p.mesh, p.objective), self,
                           (change(self.mesh), self.objective.with_structure(change)))

    def to_physical(self, x) -> dict:
        """Normalised values → case-file units (``depth_um`` or extent), as a dict by name."""
        dm = float(self.delta_m)
        return {v.name: v.kind.to_file(float(x[i]), dm) for i, v in enumerate(self.variables)}

    def from_physical(self, values: dict) -> np.ndarray:
        """Case-file units (µm for depths) → normalised values, in ``names`` order."""
        dm = float(self.delta_m)
        return np.asarray([v.kind.from_file(float(values[v.name]), dm) for v in self.variables])

    def case_values(self, mods: jg.Modifications) -> dict:
        """The variables' values in ``mods`` (each its first member's), in case-file units, as a
        dict by name; a bearing's: its clearance at the operating point, µm)."""
        return {v.name: v.case_value(mods) if v.kind.acts_on == "modifications"
                else self.bearings.case_value(v) for v in self.variables}

    def lower_is_unmodified(self) -> bool:
        """Whether the lower bounds leave the design unmodified (every depth's lower bound 0)."""
        lower = np.asarray(self.lower, dtype=float)
        return all(v.kind.unmodified_at(lo) for v, lo in zip(self.variables, lower, strict=True))

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
        return self.objective.at_torque(self, mods, torque, self._law(contact))

    def value(
        self, x: Float[Array, " n"], contact: jg.ContactLaw | None = None
    ) -> Float[Array, ""]:
        """Scaled objective at normalised design values ``x`` (1 = unmodified at design load;
        ``LoadCentroid``: (c/0.1)²), in the ``contact`` law (default None: the problem's smooth
        law, whose gradients the optimiser follows; :class:`jaxgear.ExactContact` for the
        design as the exact law sees it). A variable that acts on the structure acts through
        :meth:`at_design`."""
        return self.at_design(x).design_value(self.modifications(x), contact)

    def design_value(
        self, modifications: jg.Modifications, contact: jg.ContactLaw | None = None
    ) -> Float[Array, ""]:
        """Scaled objective of the design ``modifications`` (a whole
        :class:`jaxgear.Modifications`, e.g. :meth:`unmodified`, or the base design) as
        :meth:`value` scales it, in the ``contact`` law (None: the problem's smooth law)."""
        vals = jax.vmap(lambda t: self._single(modifications, t, contact))(self.torques)
        return self.objective.reduce(vals) / self.scale

    def unmodified(self) -> jg.Modifications:
        """The base design without flank modifications: every tip, root and end relief and
        crowning depth 0 on both members (extents, shapes, blends, helix slope and profile
        deviations and per-tooth deviations kept: they are errors of manufacture or mounting,
        not the design's), whatever the variables: the bare flanks a design is compared with."""
        depths = tuple(f for f, kind in VARIABLES.values() if kind == "depth")
        mods = self.base
        for m in ("pinion", "gear"):
            for f in depths:
                mods = eqx.tree_at(
                    lambda t, m=m, f=f: getattr(getattr(t, m), f), mods,
                    jnp.zeros_like(getattr(getattr(mods, m), f)),
                )
        return mods

    def on_bounds(self, x, tolerance: float = 1e-3) -> dict:
        """Which variables of the normalised design ``x`` sit on a bound: ``{name: "lower" |
        "upper" | None}``, a value within ``tolerance`` × (upper − lower) of the bound. The
        reparametrisation reaches a bound only in the limit, so an optimum there is one the
        optimiser was pushing beyond the interval: not an interior (stationary) optimum."""
        x = np.asarray(x, dtype=float)
        lo, hi = np.asarray(self.lower, dtype=float), np.asarray(self.upper, dtype=float)
        tol = tolerance * (hi - lo)
        out = {}
        for i, name in enumerate(self.names):
            out[name] = "lower" if x[i] <= lo[i] + tol[i] else (
                "upper" if x[i] >= hi[i] - tol[i] else None)
        return out

    def held(self) -> dict:
        """The base design's modifications that no variable sets and that act (a relief or
        crowning of non-zero depth, or whose depth is a variable), held at the case's values:
        ``{name: value}`` in case-file units (depths in µm, extents as fractions), named as the
        variables are (unprefixed where both members hold the same value)."""
        per = {}
        for base, (field, _kind) in VARIABLES.items():
            var = Variable.parse(base)
            depth_base = base.split(".")[0] + ".depth"
            depth_field = VARIABLES[depth_base][0]
            for m in ("pinion", "gear"):
                if any(v.base == base and m in v.members for v in self.variables):
                    continue
                member = getattr(self.base, m)
                designed = any(v.base == depth_base and m in v.members for v in self.variables)
                if float(getattr(member, depth_field)) == 0 and not designed:
                    continue  # no such modification: nothing held
                per[m, base] = var.kind.file_value(float(getattr(member, field)))
        out = {}
        for base in VARIABLES:
            p, g = per.get(("pinion", base)), per.get(("gear", base))
            if p is not None and p == g:
                out[base] = p
            else:
                out.update({f"{m}.{base}": v for m, v in (("pinion", p), ("gear", g))
                            if v is not None})
        return out

    def te_rms_vs_torque(
        self, x, torques, contact: jg.ContactLaw | None = EXACT
    ) -> Float[Array, " T"]:
        """TE RMS (m) of design ``x`` at each of ``torques`` (N·m), vmapped: a Harris-map view
        (``contact``: the exact law by default, None the problem's smooth law); a scene of
        several meshes (a train): its first mesh's."""
        mods, mesh = self.modifications(x), self.at_design(x).mesh
        return jax.vmap(
            lambda t: (
                jg.quasi_static(
                    mesh,
                    mods,
                    t,
                    speed=self.speed,
                    contact=self._law(contact),
                    positions_per_pitch=self.positions_per_pitch,
                ).meshes[0].te_rms
            )
        )(jnp.asarray(torques))

    def metrics(self, x, contact: jg.ContactLaw | None = EXACT) -> dict:
        """Every objective's quantity at the design torque for design ``x``, unscaled, as a dict:
        ``te_rms_m``, ``te_ptp_m``, ``max_line_load_N_per_m``, ``line_load_lp_N_per_m`` (order
        ``lp_order``) and the signed ``load_centroid`` (fraction of b, see :func:`load_centroid`),
        in the ``contact`` law (the exact law by default, None the problem's smooth law); a
        scene of several meshes (a train): its first mesh's.
        """
        r = jg.quasi_static(
            self.at_design(jnp.asarray(x)).mesh,
            self.modifications(jnp.asarray(x)),
            self.design_torque,
            speed=self.speed,
            contact=self._law(contact),
            positions_per_pitch=self.positions_per_pitch,
        ).meshes[0]
        return {
            "te_rms_m": r.te_rms,
            "te_ptp_m": r.te_ptp,
            "max_line_load_N_per_m": r.max_line_load,
            "line_load_lp_N_per_m": line_load_lp(r, self.lp_order),
            "load_centroid": load_centroid(r, self.face_width),
        }

    def sharp(self) -> Problem:
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
        """Unscaled objective at each torque (``objective.units``), in the ``contact`` law (the
        exact law by default, None the problem's smooth law)."""
        mods, problem = self.modifications(x), self.at_design(x)
        return jax.vmap(lambda t: problem._single(mods, t, contact))(self.torques)


def _bounds(variables, bounds: dict | None, bearings=None) -> tuple[list, list]:
    lo, hi = [], []
    bounds = dict(bounds or {})
    for v in variables:
        a, b = bounds.pop(v.name, v.kind.default_bounds())
        if not a < b:
            raise ValueError(f"bounds of {v.name!r} = ({a}, {b}) are crossed: need lower < upper")
        v.kind.check_bounds(v.name, a, b)
        if v.kind.acts_on == "structure":
            bearings.check_bounds(v, a, b)
        lo.append(a)
        hi.append(b)
    if bounds:
        raise ValueError(f"bounds given for names not in variables: {sorted(bounds)}")
    return lo, hi


def make_problem(
    scene: jg.MeshModel | js.Scene,
    modifications: jg.Modifications | None,
    torque,
    variables,
    objective: AbstractObjective | None = None,
    *,
    bounds: dict | None = None,
    positions_per_pitch: int = 64,
    speed: float = 0.0,
    smoothing: Smoothing | None = None,
    bearings: BearingDesign | None = None,
) -> Problem:
    """Build a :class:`Problem` on model objects (a case file's problem:
    :func:`jaxgear.io.case_problem`).

    Args:
        scene: the structure the evaluations run on: a :class:`jaxgear.MeshModel` (the rigid
            mesh) or a scene, e.g. the hybrid scene of :func:`jaxgear.io.static_scene`
            (condensed bodies; for a quasi-static objective its window compliance is cached here
            once for every evaluation, :func:`jaxgear.scenes.cache_window_compliance`).
        modifications: the starting design; it holds the values that are not variables (None:
            unmodified).
        torque: the design torque (N·m) > 0: the scale of the objective and of the depths
            (δ_m, the mean static deflection there).
        variables: design-variable names (see module docstring), or a comma-separated string.
        objective: an :class:`AbstractObjective` (default :class:`TeRms`), e.g.
            ``RobustTeRms(torques, Mean())``, ``LineLoadLp(8.0)``, ``DynamicFactor(speeds)``
            (needs a ``scene`` with condensed bodies).
        bounds: optional ``{name: (lo, hi)}`` in normalised units (E* for depths, Γ for extents).
        positions_per_pitch: mesh positions per base pitch of the quasi-static objectives.
        speed: pinion speed (rad/s) >= 0 of the quasi-static objectives: the centrifugal loads
            of the scene's condensed bodies (default 0, at rest).
        smoothing: the smooth contact law and the rounding of the relief starts
            (:class:`Smoothing`; default ``Smoothing()``).
        bearings: the rolling bearings of ``scene`` at their held operating point
            (:func:`optimise.bearing_design`), needed by a variable that acts on the structure
            (``<shaft>.bearings[<k>].clearance``, µm; bounds in µm, default (−5, 20)); the
            scene must be assembled on its shafts.

    Raises:
        ValueError: unknown or duplicated variable, bounds crossed, extents outside (0, 1),
            negative depth bounds, a torque <= 0, an objective or smoothing that is not one, a
            structure the objective cannot run on; a bearing variable without ``bearings``,
            with an objective that does not take a designed structure
            (:attr:`AbstractObjective.designs_structure`), on an unknown shaft or bearing, on
            a linear bearing, or with bounds outside the bearing's range of clearances.
    """
    objective = TeRms() if objective is None else objective
    if not isinstance(objective, AbstractObjective):
        raise ValueError(
            f"objective = {objective!r}: allowed an optimise objective (TeRms(), "
            "TePeakToPeak(), RobustTeRms(torques), ...); case-file names map to them in "
            "jaxgear.io.case_problem"
        )
    smoothing = Smoothing() if smoothing is None else smoothing
    if not isinstance(smoothing, Smoothing):
        raise ValueError(f"smoothing = {smoothing!r}: allowed an optimise.Smoothing")
    variables = variables_of(variables)
    if not float(torque) > 0:
        raise ValueError(f"torque = {torque!r} N·m is out of range: allowed > 0")
    structural = [v.name for v in variables if v.kind.acts_on == "structure"]
    if structural and not isinstance(bearings, BearingDesign):
        raise ValueError(
            f"variables: {structural[0]!r} acts on the structure: allowed with bearings = "
            "optimise.bearing_design(...) (the scene's rolling bearings at their operating "
            "point)")
    if structural and not objective.designs_structure:
        raise ValueError(
            f"variables: {structural[0]!r} acts on the structure: objective = "
            f"{objective.name!r} does not take a designed structure (allowed the quasi-static "
            "and acoustic objectives)")
    for v in variables:
        if v.kind.acts_on == "structure":
            bearings.slot(v)  # a rolling bearing of the scene, or one line
    torques = objective.torques(torque)
    lo, hi = _bounds(variables, bounds, bearings)
    contact = smoothing.contact
    contact = objective.default_contact(1e-7) if contact is None else contact
    ppp = int(positions_per_pitch)
    mesh = objective.prepare(scene, ppp)
    unmod = jg.quasi_static(mesh, None, torque, speed=speed, positions_per_pitch=ppp)
    k_mean = float(jnp.mean(unmod.meshes[0].mesh_stiffness))  # a train's: its first mesh's
    plane = base_plane(mesh)
    delta_m = float(plane.normal_load(torque)) / k_mean
    # round the relief starts over one position step so that the sampled objective is smooth in
    # the extents (a sharp start makes it kink each time the start crosses a sampled point)
    blend = smoothing.relief_blend
    blend = 1.0 / (ppp * float(plane.contact_ratio)) if blend is None else blend
    # likewise the end relief start over one slice when its extent is a variable (the sampled
    # objective kinks each time the start crosses a slice centre)
    end_blend = smoothing.end_relief_blend
    if end_blend is None:
        extent_var = any(v.kind.rounds_end_relief for v in variables)
        end_blend = 1.0 / plane.n_slices if extent_var else 0.0
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
        objective=objective,
        variables=variables,
        torques=jnp.asarray(torques),
        design_torque=jnp.asarray(float(torque)),
        delta_m=jnp.asarray(delta_m),
        scale=jnp.asarray(float(objective.scale(unmod, torque))),
        lower=jnp.asarray(lo),
        upper=jnp.asarray(hi),
        contact=contact.astype(jnp.asarray(delta_m).dtype),
        face_width=jnp.asarray(float(plane.face_width)),
        lp_order=jnp.asarray(objective.metric_order()),
        speed=jnp.asarray(float(speed)),
        positions_per_pitch=ppp,
        bearings=bearings if structural else None,
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
