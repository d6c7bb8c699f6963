"""Gear whine of a planetary stage in the frequency domain (docs/whine.md, "Planetary stage"):
the harmonic balance of :func:`jaxgear.dynamics.whine_response` on the carrier-frame system of
:func:`~jaxgear.planetary.planetary_dynamics`,

    M q'' + C(Ω, v) q' + K(Ω, v) q + Σ_c w_c k_c l_c V_c (V_c·q − δ0_c) = f,

C = C_modal + Ω G + v G_v and K = K_b − Ω² K_Ω + Ω v K_v at the carrier speed Ω and mesh travel
speed v (constant: time-invariant), the 2N meshes' cells at the travel x = v t, periodic in the
base pitch p_b. Linearised about the quasi-static solution x_qs(x) (the static contact solve at
``positions`` travels of one mesh period with K(Ω, v), the active set held) the vibration y =
q − x_qs obeys the pair's equation, and its harmonics of the mesh frequency ω = 2π v / p_b come
from :func:`~jaxgear.dynamics.harmonic_balance` (seed (2.31)–(2.37) with the carrier-frame
terms of docs/planetary.md; Blankenship & Kahraman 1995 for the multi-harmonic balance).

Phases are on the mesh travel: q(x) = Re Σ_h q_h e^{2πi h x / p_b}, x the travel that
:class:`~jaxgear.planetary.PlanetaryDynamics` records (``travel``).
"""

from __future__ import annotations

import dataclasses
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Complex, Float

from .._contact import ContactLaw, ExactContact, contact_law, solve_contact
from .._util import check_instance, check_integer, is_traced
from ..dynamics import (
    AbstractWhineMethod,
    HarmonicBalance,
    cell_stiffness,
    fourier_coefficients,
    harmonic_balance,
)
from ._dynamics import PlanetaryRun, planetary_cell_row, planetary_stage_system
from ._housed import check_carrier_speed
from ._meshes import AbstractPlanetaryMeshes, pin_terms, structure_stiffness
from ._plan import carrier_periodic
from ._ring import AbstractRingModel, RigidRing, modal_damping
from ._stage import AbstractPlanetaryModel, PlanetaryStage

__all__ = ["PlanetaryWhine", "SupportReactions", "planetary_whine", "support_reactions"]


#: the central members' coordinate suffixes (:meth:`AbstractPlanetaryModel.dof_names`)
_MEMBERS = {"c": "carrier", "r": "ring", "s": "sun"}
#: a central coordinate's component, its label and whether it is a force (else a moment)
_COMPONENTS = {"x": ("x", True), "y": ("y", True), "z": ("z", True),
               "theta_x": ("moment x", False), "theta_y": ("moment y", False),
               "u": ("torque", False)}


class SupportReactions(NamedTuple):
    """What the central members (sun, carrier, ring) put on their supports
    (:func:`support_reactions`), linear in the stage's coordinates q (n,).

    Attributes:
        force_names: ``"<member> x"``, ``"<member> y"`` (and ``"<member> z"`` in the 3D model),
            (r,): the in-plane components along the **carrier frame's** axes.
        forces: (r, n) (N per coordinate unit): the force F = forces @ q the member puts on its
            translational support (positive along the axis: +k q, the spring's pull on the
            member reversed).
        moment_names: ``"<member> torque"`` (about the stage axis; the held members' reaction
            torque), ``"<member> moment x"``, ``"<member> moment y"`` (the 3D model's tilts),
            (r_m,).
        moments: (r_m, n) (N m per coordinate unit), the same for the torsional and tilting
            supports (a u = r_b θ coordinate's force k_u u times the member's base radius).
    """

    force_names: tuple
    forces: Array
    moment_names: tuple
    moments: Array


def support_reactions(model: AbstractPlanetaryModel, stage: PlanetaryStage) -> SupportReactions:
    """The central members' support reactions of ``stage`` in ``model``'s coordinates: the
    grounded springs of its stiffness without the meshes, K_b − K_b(the central members'
    bearings, axial, tilting and torsional supports removed), row by row on the central
    coordinates (:class:`SupportReactions`). A coordinate whose support is zero (a floating
    sun) has no row where the stage is concrete (traced: every central coordinate keeps its
    row). The planet pins are inside the stage (planet on carrier) and give no row.

    In the carrier frame (docs/planetary.md): a fixed-frame support (the held ring's) sees an
    in-plane component of order h at h f_m ± f_c, f_c the carrier's rotation frequency; the
    torque about the axis is the same in both frames.

    Raises:
        ValueError: a model or stage of another type (one line)."""
    check_instance("model", model, AbstractPlanetaryModel,
                   "a planetary model kind (TorsionalPlanetary, PlanarPlanetary, "
                   "SpatialPlanetary)", "support_reactions")
    check_instance("stage", stage, PlanetaryStage, "a jaxgear.planetary.PlanetaryStage", "support_reactions")
    k_full = structure_stiffness(model, stage)
    zero = jnp.zeros((), dtype=stage.planet_angles.dtype)

    def free(m):
        return eqx.tree_at(
            lambda m: (m.bearing_stiffness, m.torsional_stiffness, m.axial_stiffness,
                       m.tilt_stiffness),
            m, (jnp.zeros(2, zero.dtype), zero, zero, jnp.zeros(2, zero.dtype)),
        )

    bare = eqx.tree_at(lambda s: (s.sun, s.ring, s.carrier), stage,
                       (free(stage.sun), free(stage.ring), free(stage.carrier)))
    k_g = k_full - structure_stiffness(model, bare)
    radius = {"c": stage.carrier.base_radius, "r": stage.ring.base_radius,
              "s": stage.sun.base_radius}
    concrete = not is_traced(k_g)
    forces, moments = ([], []), ([], [])
    for i, name in enumerate(model.dof_names(stage)):
        comp, _, member = name.rpartition("_")
        if member not in _MEMBERS or comp not in _COMPONENTS:
            continue
        if concrete and float(k_g[i, i]) == 0.0:
            continue
        label, is_force = _COMPONENTS[comp]
        row = k_g[i] if comp != "u" else k_g[i] * radius[member]
        names, rows = forces if is_force else moments
        names.append(f"{_MEMBERS[member]} {label}")
        rows.append(row)
    n = k_g.shape[0]

    def stack(rows):
        return jnp.stack(rows) if rows else jnp.zeros((0, n), k_g.dtype)

    return SupportReactions(tuple(forces[0]), stack(forces[1]), tuple(moments[0]),
                            stack(moments[1]))


class PlanetaryWhine(eqx.Module):
    """The frequency-domain steady state of a planetary stage (:func:`planetary_whine`) at S
    input speeds, H + 1 orders of the mesh frequency, n coordinates, N planets.

    One-sided amplitudes on the mesh travel (module docstring); order 0 the mean.

    Attributes:
        speed: the speeds (rad/s), (S,): the carrier's of :func:`planetary_whine`, the input
            member's of :func:`jaxgear.dynamics.whine_response`.
        frequency: the mesh frequency v / p_b (Hz), (S,).
        orders: 0..H, (H + 1,).
        coordinates: q_h (m; the stage's coordinates), (S, H + 1, n), complex.
        sun_mesh_force, ring_mesh_force: transverse mesh forces (N, compression positive,
            :class:`~jaxgear.planetary.PlanetaryDynamics`' ``sun_mesh_forces``,
            ``ring_mesh_forces``), reconstructed over the period, (S, H + 1, N), complex.
        static_force: the nominal transverse mesh force T_s / (N r_bs) (N), ().
        min_mesh_force: each mesh's smallest reconstructed force over the period (N),
            (S, 2N).
        contact_loss: min_mesh_force <= 0 (S, 2N): the linear result does not hold there.
        nonlinearity: the contact force the held active set misplaces over the static force,
            the largest over the period, (S, 2N) (as :class:`~jaxgear.dynamics.WhineResponse`).
        transmission_error: each mesh's transmission error, its transverse deflection V q + d
            at mid-face (m, compression positive, the pin errors' offsets d in order 0: as
            :class:`~jaxgear.planetary.PlanetaryQuasiStatic`'s ``sun_te``, ``ring_te``),
            (S, H + 1, 2N): the sun meshes, then the ring meshes.
        bearing_force: the central members' support forces (N, carrier-frame components,
            :func:`support_reactions`), (S, H + 1, r). support_moment: their torques about the
            axis and tilting moments (N m), (S, H + 1, r_m).
        bearing_names, moment_names: static, the components' labels (r,), (r_m,).
        mesh_names: static, ``"sun-planet <n>"`` then ``"ring-planet <n>"`` (2N,).
        carrier_speed: Ω (rad/s, signed, fixed frame), (S,).

    ``mesh_force`` (S, H + 1, 2N): the sun meshes' forces, then the ring meshes' (the order of
    ``transmission_error``, :class:`~jaxgear.dynamics.WhineResponse`'s attribute).
    """

    speed: Float[Array, " S"]
    frequency: Float[Array, " S"]
    orders: Float[Array, " h"]
    coordinates: Complex[Array, "S h n"]
    sun_mesh_force: Complex[Array, "S h N"]
    ring_mesh_force: Complex[Array, "S h N"]
    static_force: Float[Array, ""]
    min_mesh_force: Float[Array, "S m"]
    contact_loss: Bool[Array, "S m"]
    nonlinearity: Float[Array, "S m"]
    transmission_error: Complex[Array, "S h m"]
    bearing_force: Complex[Array, "S h r"]
    support_moment: Complex[Array, "S h rm"]
    bearing_names: tuple = eqx.field(static=True, default=())
    moment_names: tuple = eqx.field(static=True, default=())
    mesh_names: tuple = eqx.field(static=True, default=())
    carrier_speed: Float[Array, " S"] | None = None

    @property
    def mesh_force(self) -> Complex[Array, "S h m"]:
        """The sun meshes' forces, then the ring meshes' (N), (S, H + 1, 2N)."""
        return jnp.concatenate([self.sun_mesh_force, self.ring_mesh_force], axis=-1)

    def fixed_frame_lines(self) -> tuple[tuple, Array, Array]:
        """The support forces as a support fixed in space (a housing's seat) receives them: each
        member's in-plane force, carrier-frame x + i y = Σ_h (c^x_h + i c^y_h) e^{i h ω t}
        (two-sided c_h, h = −H..H, from the one-sided orders), turned by the carrier angle Ω t,
        is the sum of circular whirls Σ_h d_h e^{i (h ω + Ω) t}, d_h = c^x_h + i c^y_h: one
        line per h at the frequency |h f + f_c| (f_c = Ω / 2π), of which the fixed x and y
        components each carry |d_h| (order h of the carrier frame at h f ± f_c, the
        planet-pass sidebands; order 0 at f_c).

        Returns:
            (members, frequency, amplitude): the members with an x and a y force component
            (names), the lines' frequencies (Hz, (S, 2H + 1), h = −H..H: |h f + f_c|) and
            their amplitudes (N, (S, 2H + 1, members)).
        """
        names = list(self.bearing_names)
        members = tuple(n[:-2] for n in names if n.endswith(" x") and f"{n[:-2]} y" in names)
        F = self.bearing_force
        half = jnp.concatenate([F[:, :1], 0.5 * F[:, 1:]], axis=1)  # c_h, h = 0..H
        both = jnp.concatenate([jnp.conj(half[:, :0:-1]), half], axis=1)  # h = −H..H
        ix = jnp.array([names.index(f"{m} x") for m in members], dtype=int)
        iy = jnp.array([names.index(f"{m} y") for m in members], dtype=int)
        d = both[..., ix] + 1j * both[..., iy]
        H = F.shape[1] - 1
        h = jnp.arange(-H, H + 1, dtype=self.frequency.dtype)
        f_c = self.carrier_speed / (2 * jnp.pi)
        freq = jnp.abs(h[None, :] * self.frequency[:, None] + f_c[:, None])
        return members, freq, jnp.abs(d)


def _one_sided(c, H):
    return jnp.concatenate([c[H : H + 1], 2.0 * c[H + 1 :]], axis=0)


def planetary_whine(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    run: PlanetaryRun,
    carrier_speeds,
    method: AbstractWhineMethod = HarmonicBalance(),
    *,
    mesh_speeds=None,
    ring: AbstractRingModel = RigidRing(),
    positions: int = 256,
    contact: ContactLaw = ExactContact(),
) -> PlanetaryWhine:
    """Gear whine of a planetary stage in the frequency domain (module docstring), with the
    arguments of :func:`~jaxgear.planetary.planetary_dynamics`;
    :func:`jaxgear.dynamics.whine_response` of a :class:`~jaxgear.planetary.PlanetaryModel`
    calls it at the model's carrier and mesh speeds.

    The damping is the run's (modal, ``run.damping_ratio`` on the modes of M and K_b + K̄_m,
    K̄_m the meshes' stiffness averaged over the ``positions`` travels, as
    :func:`~jaxgear.planetary.planetary_dynamics` takes it over its steps), the pin errors'
    offsets and load as the run's.

    Args:
        model: the model kind (:class:`~jaxgear.planetary.TorsionalPlanetary`,
            :class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.SpatialPlanetary`).
        stage: the stage, without eccentricity, runout or unbalance (its steady state repeats
            every mesh period in the carrier frame). meshes: the meshes kind. run: the
            :class:`~jaxgear.planetary.PlanetaryRun` (torque, damping ratio, pin errors; its
            step counts are not read).
        carrier_speeds: Ω (rad/s), scalar or (S,); 0 (a star stage: the carrier held, the
            carrier frame the fixed one) with ``mesh_speeds`` given, else != 0.
        method: :class:`~jaxgear.dynamics.HarmonicBalance` or
            :class:`~jaxgear.dynamics.TransmissionErrorSource`, with its H.
        mesh_speeds: v (m/s) > 0, as ``carrier_speeds``; None: the ring held, v = r_br |Ω|.
        ring: :class:`~jaxgear.planetary.RigidRing` only (a flexible ring's stations turn
            relative to the carrier).
        positions: travels per mesh period (int >= 4H + 1).
        contact: the static solve's contact law.

    Returns:
        :class:`PlanetaryWhine` (``speed``: the carrier speeds).

    Raises:
        TypeError: another method. ValueError: a flexible ring, eccentricities or unbalances,
            a carrier speed of 0 without ``mesh_speeds``, a mesh speed <= 0, too few
            positions.
    """
    if not isinstance(method, AbstractWhineMethod):
        raise TypeError(
            f"method = {method!r}: allowed HarmonicBalance(...) or TransmissionErrorSource(...)"
        )
    if not carrier_periodic(stage, not isinstance(ring, RigidRing)):
        raise ValueError(
            "stage: a flexible ring, an eccentricity, runout or unbalance: the whine needs a "
            "stage that repeats every mesh period in the carrier frame (allowed a rigid ring, "
            "no eccentricities, no unbalances)"
        )
    check_carrier_speed(model, carrier_speeds, "planetary_whine")
    check_integer("positions", positions, 4)
    H = int(method.harmonics)
    if positions < 4 * H + 1:
        raise ValueError(f"positions = {positions}: allowed >= 4 harmonics + 1 = {4 * H + 1}")
    for name, value in (("speeds", carrier_speeds), ("mesh_speeds", mesh_speeds)):
        if value is None:
            continue
        if np.ndim(value) > 1 or np.size(value) == 0:
            raise ValueError(f"{name} = {value!r}: allowed a scalar or (S,) (rad/s, m/s)")
        if not is_traced(value):
            v = np.asarray(value, dtype=float)
            # a held carrier (a star stage, Ω = 0) runs at its given mesh speeds; without
            # them the mesh speed is the ring's r_br |Ω|, which Ω = 0 would stop
            if name == "mesh_speeds":
                bad, what = v <= 0, "> 0 m/s"
            elif mesh_speeds is None:
                bad, what = v == 0, "!= 0 rad/s where mesh_speeds is None (the ring held)"
            else:
                bad, what = np.zeros(v.shape, bool), "rad/s"
            if not np.all(np.isfinite(v)) or np.any(bad):
                raise ValueError(f"{name} = {value!r}: allowed finite values {what}")
    dtype = run.sun_torque.dtype
    law = contact_law(contact, dtype)
    omega = jnp.atleast_1d(jnp.asarray(carrier_speeds, dtype))
    v = (stage.ring.base_radius * jnp.abs(omega) if mesh_speeds is None
         else jnp.broadcast_to(jnp.asarray(mesh_speeds, dtype), omega.shape))
    w = _whine(model, stage, meshes, run, omega, v, method, int(positions), law)
    # the TE (V q + d, as planetary_quasi_static's) and the supports' reactions per order
    (v_s, _), (v_r, _) = model.face_rows(stage)
    _, d_s, d_r = pin_terms(model, stage, run.tangential_pin_errors, run.radial_pin_errors,
                            "planetary_whine")
    X = w.coordinates
    te = jnp.einsum("shn,mn->shm", X, jnp.concatenate([v_s, v_r]).astype(X.dtype))
    te = te.at[:, 0, :].add(jnp.concatenate([d_s, d_r]))
    sup = support_reactions(model, stage)
    n_pl = stage.n_planets
    return dataclasses.replace(
        w,
        transmission_error=te,
        bearing_force=jnp.einsum("shn,rn->shr", X, sup.forces.astype(X.dtype)),
        support_moment=jnp.einsum("shn,rn->shr", X, sup.moments.astype(X.dtype)),
        bearing_names=sup.force_names,
        moment_names=sup.moment_names,
        mesh_names=tuple(f"{m}-planet {k + 1}" for m in ("sun", "ring") for k in range(n_pl)),
        carrier_speed=omega,
    )


@eqx.filter_jit
def _whine(kind, stage, meshes, run, speeds, mesh_speeds, method, P, law) -> PlanetaryWhine:
    H = method.harmonics
    m, k_b, f, k_mean, _ = planetary_stage_system(kind, stage, meshes, run, P)
    c_modal = modal_damping(m, k_b + k_mean, run.damping_ratio)
    g_v, k_v = kind.spin_matrices(stage)
    G, K_om = kind.gyroscopic_matrix(stage), kind.centripetal_matrix(stage)
    p_b = meshes.mesh_period()
    x_one = meshes.positions(P, 1)  # mid-points: s_r = (r + 1/2) / P
    rows = jax.vmap(lambda x: planetary_cell_row(kind, stage, meshes, run, x))(x_one)
    V = rows.V  # (P, c, n) (the rigid ring: every coordinate)
    kl_all = jnp.where(rows.mask, rows.k * rows.length, 0.0)
    n_pl = stage.n_planets
    h = jnp.arange(-H, H + 1)
    s = (jnp.arange(P, dtype=p_b.dtype) + 0.5) / P
    E = jnp.exp(2j * jnp.pi * s[:, None] * h[None, :])  # (P, 2H+1)

    def at(speed_v):
        omega_c, v = speed_v
        K = k_b - omega_c**2 * K_om + omega_c * v * k_v
        C = c_modal + omega_c * G + v * g_v
        static = jax.vmap(
            lambda Vr, kr, lr, dr, mr: solve_contact(K, f, Vr, kr, lr, dr, mr, law)
        )(V, rows.k, rows.length, rows.delta0, rows.mask)
        x_qs = static.x  # (P, n)
        kl = jnp.where(rows.mask, static.weight * kl_all, 0.0)  # tangent (P, c)
        Km = jax.vmap(cell_stiffness)(V, kl)  # the tangent mesh stiffness (P, n, n)
        Kh = fourier_coefficients(Km, 2 * H)  # (4H+1, n, n)
        Xh = fourier_coefficients(x_qs, H)  # (2H+1, n)
        w0 = 2 * jnp.pi * v / p_b
        w = (h * w0)[:, None]
        F = (w**2) * (Xh @ m.T) - 1j * w * (Xh @ C.T)
        Y = harmonic_balance(m, C, K, Kh, F, w0, parametric=method.parametric, real=True)
        y = jnp.real(E @ Y)  # (P, n)
        vy = jnp.einsum("pci,pi->pc", V, y)
        cell = static.force_density * rows.length + kl * vy
        fm = meshes.mesh_forces(cell)  # (P, 2N)
        g = static.gap + vy
        wrong = kl_all * jnp.maximum(g, 0.0) - kl * g
        misplaced = jnp.max(jnp.abs(meshes.mesh_forces(wrong)), axis=0)
        fh = _one_sided(fourier_coefficients(fm, H), H)  # (H+1, 2N)
        X = _one_sided(Xh + Y, H)
        return w0, X, fh, jnp.min(fm, axis=0), misplaced

    w0, X, fh, fmin, misplaced = jax.lax.map(at, (speeds, mesh_speeds))
    fs = run.sun_torque / (n_pl * stage.sun.base_radius)
    return PlanetaryWhine(
        speed=speeds,
        frequency=w0 / (2 * jnp.pi),
        orders=jnp.arange(H + 1, dtype=speeds.dtype),
        coordinates=X,
        sun_mesh_force=fh[..., :n_pl],
        ring_mesh_force=fh[..., n_pl:],
        static_force=fs,
        min_mesh_force=fmin,
        contact_loss=fmin <= 0.0,
        nonlinearity=misplaced / fs,
        transmission_error=None,
        bearing_force=None,
        support_moment=None,
    )
