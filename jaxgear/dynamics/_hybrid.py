"""Dynamics of the hybrid scene (condensed FE bodies on the cells): Newmark in the cell space.

Equations of motion (seed (2.31)–(2.37); docs/hybrid.md, "Global system"), in the body frames of
the members that carry condensed bodies (K, M and the centrifugal load are constant there; the rim
stations pass under the fixed mesh as the bodies turn):

    M Ẍ + C Ẋ + K X + Σ_c P_c(V_c·X − δ0_c) V_c = T f_T + Ω² f_c,

with P_c = k_c l_c φ(Δ_c) the cell forces, δ0_c = e_ref − e_c the flank gaps from one
time-constant reference, and Ω the pinion speed (each body at its own speed, f_c scaled
accordingly; the centrifugal load is always on in dynamics). On request
(``rotating_frame=True``; the seed leaves it out) the turning frames add their inertia:
C += Ω Gy (Coriolis, skew) and K += Ω² (S + Kσ) (spin softening and centrifugal stress
stiffening). Damping (:class:`jaxgear.io.Damping`, :mod:`._hybrid_damping`), with K̄_m(k) the
mesh stiffness matrix averaged over the quasi-static positions of mesh period k on the stations
under the mesh then (it turns with the wheel): Rayleigh α M + β (K + K̄_m(k)) (2.34); modal
(2.35) on the modes of (M, K + K̄), K̄ the mean of K̄_m(k) round the revolution; composite
(2.36) on the same modes in a form linear in K̄_m(k), whose mesh share follows the mesh:
2 ξ_s M Φ Ω Φᵀ M + 2 (ξ_m − ξ_s) Rᵀ K̄_m(k) R, R = Φ Ω^(-1/2) Φᵀ M; plus the bearings' damping.

Newmark average acceleration (β = 1/4, γ = 1/2). The effective stiffness K_eff = K + a₀M + a₁C
is constant at one speed: it is inverted once, G_eff = K_eff⁻¹, and every step is a contact
problem in the space of the cells (:func:`jaxgear.solve_contact_cells`, no rigid mode: M makes
K_eff definite): X* = G_eff F_eff, Δ = V_W X*_W − δ0 − C_eff P with C_eff = V_W G_eff,WW V_Wᵀ on
the window of master DOFs under the contact, then X = X* − G_eff Vᵀ P. A step costs the window
compliance (cells × window²) and a matrix-vector product with G_eff (n²), not a factorisation.

:class:`HybridModel` is the hybrid engine of :class:`~jaxgear.dynamics.AbstractDynamicModel`:
the same entries as a lumped model integrate it (:func:`jaxgear.dynamics.simulate`,
:func:`jaxgear.dynamics.speed_sweep`, :func:`jaxgear.dynamics.band_dynamic_factor`), through
its :meth:`~HybridModel.prepare` and :meth:`~HybridModel.independent` (:func:`sweep` here).
Beside it: the mesh stiffness averaged over a mesh period and the cell-space loop on the
scene's cells (:mod:`._hybrid_mesh`), the damping (:mod:`._hybrid_damping`), the free
vibration at a fixed mesh position (:mod:`._hybrid_free`, the energy check) and the rim's
nodal-diameter waves (:mod:`._rim`). The wheel's nodal-diameter modes and their (3.9)
resonance speeds live with the modal analysis (:mod:`jaxgear.dynamics._modal`).
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact
from .._modifications import Modifications
from .._quasi_static import per_mesh_modifications
from .._results import DynamicsResult
from .._util import check_integer, compiled_when_eager, is_traced
from ..scenes import HybridPair
from ._damping import AbstractDamping
from ._devices import several_devices, shard_speeds
from ._hybrid_damping import _speed_damping
from ._hybrid_mesh import (
    CellSystem,
    SceneCells,
    _joined,
    _loaded,
    _mesh_block,
    _newmark_cells,
    _period_statics,
    _reference_shift,
    _references,
    _revolution_mesh_stiffness,
    _revolution_periods,
    mean_mesh_stiffness,
)
from ._hybrid_whine import hybrid_whine
from ._modal import excited_omega, modal_analysis
from ._modal_basis import ModalSpace, modal_space_of, reduced_structure
from ._model import (
    AbstractDynamicModel,
    cell_geometry,
    mesh_forces,
    mesh_max,
    mesh_te,
    pressure_factors,
    split_cells,
    static_mesh_forces,
)
from ._newmark import MeshDamping, ModalSystem
from ._result import Records, steady_state
from ._rim import _rim_of
from ._settings import (
    DiffraxIntegrator,
    ModalBasis,
    Newmark,
    Outputs,
    SteadyState,
    _Config,
    _config,
    _energy_code,
    _force_code,
)
from ._whine_methods import HarmonicBalance, TransmissionErrorSource

__all__ = ["HybridModel"]


class HybridModel(AbstractDynamicModel):
    """A hybrid scene (condensed FE bodies on the cells) at an operating torque, with its damping
    settings (build with :func:`~jaxgear.dynamics.dynamic_model`): the hybrid engine, Newmark in
    the cell space (or a modal basis, :class:`~jaxgear.dynamics.ModalBasis`). Its damping
    matrices depend on the speed (the centrifugal load moves the loaded cells; the composite
    and modal models take the modes of the mesh stiffness averaged round the wheel's
    revolution at each speed): the runs build them per speed (docs/hybrid.md, "Global
    system"). Each speed starts from its quasi-static state (no continuation, no given start).

    Attributes:
        scene: the :class:`jaxgear.scenes.HybridPair` (each simulated speed sets its
            centrifugal load). mods: flank modifications, one for every mesh or a tuple of one
            per mesh (differentiable). torque: pinion torque T (N·m).
        damping: the damping model (:class:`~jaxgear.dynamics.AbstractDamping`: Rayleigh
            (2.34), modal (2.35) or composite (2.36)); the scene's bearing damping is always
            added.
        rotating_frame: add the inertia of the turning body frames (Coriolis Ω·gyroscopic, spin
            softening and centrifugal stress stiffening Ω²·spin_stiffness; off in the seed).
            Static.
    """

    scene: HybridPair
    mods: Modifications | tuple
    torque: Float[Array, ""]
    damping: AbstractDamping
    rotating_frame: bool = eqx.field(default=False, static=True)

    continues: ClassVar[bool] = False
    #: the harmonic balance over one mesh period (no torus of several mesh frequencies)
    whine_methods: ClassVar[tuple[type, ...]] = (HarmonicBalance, TransmissionErrorSource)
    #: its response records each mesh's force and static force (a DynamicResponse)
    band_factor: ClassVar[bool] = True
    #: the housing its hybrid scene's bearings sit in
    takes_housing: ClassVar[bool] = True

    def default_settings(self):
        """Newmark with the seed's 64 steps per mesh period (IV-27), the exact law (50
        passes), 20 periods with 4 kept."""
        return Newmark(64), ExactContact(50), SteadyState(20, 4)

    def check_integrator(self, integrator) -> None:
        """A hybrid model is integrated by Newmark: the contact loop in the cell space has no
        diffrax form."""
        if isinstance(integrator, DiffraxIntegrator):
            raise ValueError(
                f"integrator = {type(integrator).__name__}(...): a hybrid model takes "
                "jaxgear.dynamics.Newmark (the "
                "contact loop in the cell space has no diffrax form)"
            )

    def span_periods(self) -> int:
        """The scene's period (the table is rebuilt at each step: no deviation span)."""
        return self.scene.scene_periods()

    def steps_multiple(self) -> int:
        return 1

    def averaged_modes(self, *, speed=0.0, positions_per_pitch=64, contact=ExactContact()):
        """A dense eigen-analysis of the n structure coordinates: K̄_m over
        ``positions_per_pitch`` quasi-static positions at pinion ``speed`` (rad/s, the
        centrifugal load) with the ``contact`` law (:func:`mean_mesh_stiffness`)."""
        check_integer("positions_per_pitch", positions_per_pitch, 4)
        Km = mean_mesh_stiffness(
            self.scene, self.mods, self.torque, int(positions_per_pitch), contact, speed=speed
        )
        return modal_analysis(self.scene, Km)

    def mesh_force_ratios(self, response):
        """:meth:`jaxgear.dynamics.DynamicResponse.force_ratios` of ``response``."""
        return response.force_ratios()

    def whine(self, speeds, method, *, positions: int = 64, contact=ExactContact()):
        """The frequency-domain steady state (:func:`~jaxgear.dynamics.whine_response`) of the
        pair in the twisted coordinates of its cyclic bodies (:func:`._hybrid_whine.hybrid_whine`;
        docs/whine.md, "Hybrid model")."""
        return hybrid_whine(self, speeds, method, positions=positions, contact=contact)

    def prepare(self, integrator, law, window, steps_per_period, outputs, modes=None):
        """The run's settings (:func:`run_config`) and its modal basis, if the integrator has
        one (:func:`modal_space`, once for every speed); the highest excited mode of ``modes``
        (NaN without: a fixed step count has no modal analysis)."""
        cfg = run_config(self, integrator, window, int(steps_per_period), outputs)
        omega = jnp.asarray(jnp.nan, self.dtype) if modes is None else excited_omega(modes)
        return HybridRun(law, omega, modal_space(self, law, cfg), cfg)

    def independent(self, prepared, speeds, *, start=None, shard=False):
        if start is not None:
            raise ValueError(
                "state0: a hybrid model starts from its quasi-static state (allowed None)"
            )
        law, cfg, omega, space = prepared.law, prepared.cfg, prepared.omega, prepared.space
        # concrete: the torque (when the model was built), law and speeds (by the callers) are
        # checked on the host, so the program holds no eqx.error_if of them
        checked = not is_traced((self, law, speeds))
        if jnp.ndim(speeds) == 0:
            r = sweep(self, jnp.reshape(speeds, (1,)), law, cfg, omega, space, checked)
            return _first(r)
        if not several_devices(shard, speeds):
            return sweep(self, speeds, law, cfg, omega, space, checked)
        # one row of speeds per device, each row one speed after the other
        rows, _ = shard_speeds(speeds, rows=True)
        r = sweep(self, rows, law, cfg, omega, space, checked)
        return jax.tree.map(lambda a: a.reshape((-1,) + a.shape[2:])[: speeds.shape[0]], r)


@compiled_when_eager
def _first(r):
    """The first speed's entry of every array of a sweep's result (one compiled program when
    called eagerly: each leaf's indexing compiled on its own otherwise)."""
    return jax.tree.map(lambda x: x[0], r)


class HybridRun(eqx.Module):
    """A hybrid run prepared at one step count (:meth:`HybridModel.prepare`): the contact law,
    the highest excited mode (rad/s; NaN: unknown), the modal basis (or None) and the run's
    settings."""

    law: ContactLaw
    omega: Float[Array, ""]
    space: ModalSpace | None
    cfg: _Config  # static settings, and the divergence bound as data


def modal_space(model: HybridModel, law: ContactLaw, cfg: _Config) -> ModalSpace | None:
    """The modal basis of a run with settings ``cfg`` (None when its integrator has none):
    the modes of (M, K + K̄), K̄ the loaded mesh stiffness averaged round a wheel revolution
    at the basis's speed (the quasi-static cells of the run's step positions there, the
    model's torque and ``law``; :func:`_revolution_mesh_stiffness`), with the members' free
    rotations, and their static correction for the structure's K (per speed with
    ``rotating_frame``): :func:`jaxgear.dynamics._modal_basis.modal_space_of`, dense
    eigen-analyses of the n coordinates, once per sweep.

    Raises:
        ValueError: more modes than the structure's coordinates (one line, before any work).
    """
    basis = cfg.integrator.basis
    if basis is None:
        return None
    n = model.scene.structure.K.shape[0]
    if basis.modes > n:
        raise ValueError(
            f"modal basis modes = {basis.modes} is out of range: allowed 1 … {n} (the "
            "structure's coordinates)"
        )
    checked = not is_traced((model, law, basis))  # as HybridModel.independent's
    return _modal_space(model, law, cfg.steps_per_period, basis, checked)


@eqx.filter_jit
def _modal_space(
    model: HybridModel, law: ContactLaw, spp: int, basis: ModalBasis, host_checked: bool = False
) -> ModalSpace:
    scene = model.scene
    dtype = scene.structure.K.dtype
    speed = jnp.asarray(basis.speed, dtype)
    qs, _ = _period_statics(scene, model.mods, model.torque, speed, spp, law, host_checked)
    loaded = _loaded(qs)
    period_angle = scene.base_planes[0].mesh_period_angle

    def block(p):
        return _mesh_block(scene, qs.theta + p * period_angle, loaded)

    Km = _revolution_mesh_stiffness(scene, block, _revolution_periods(scene))
    K, M = scene.structure.K, scene.structure.M
    return modal_space_of(
        K,
        M,
        Km,
        basis.modes,
        len(scene.members),
        static=basis.static_correction,
        per_speed=model.rotating_frame,
    )


def _run(
    model: HybridModel,
    speed,
    law: ContactLaw,
    cfg: _Config,
    omega_excited,
    space=None,
    host_checked: bool = False,
):
    scene, mods, torque = model.scene, model.mods, model.torque
    spp, states, blowup = cfg.steps_per_period, cfg.states, cfg.blowup
    n_steps, keep = spp * cfg.periods, spp * cfg.keep_periods
    planes = scene.base_planes
    period_angle = planes[0].mesh_period_angle
    dtype = scene.structure.K.dtype
    dt = period_angle / speed / spp
    M = scene.structure.M
    # the quasi-static states at the step positions of the first period (the start: row 0, at
    # speed Ω, centrifugal load on, at rest) and the damping with its mesh share per period
    qs, block, damp = _speed_damping(model, speed, law, spp, host_checked)
    C = damp.C
    # the mesh share of C follows the mesh: c_m Rᵀ K̄_m(k) R in period k
    mesh_damping = None if damp.c_m is None else MeshDamping(block, damp.c_m, damp.R)

    K = scene.structure.K
    if model.rotating_frame:  # the turning frames' Coriolis, spin softening and stress stiffening
        K = K + speed**2 * scene.structure.spin_stiffness
        C = C + speed * scene.structure.gyroscopic
    F = scene.external_load(torque, speed)
    e_ref, e_max = _references(scene, mods, qs.theta)
    X0 = qs.x[0] + _reference_shift(scene, e_ref - e_max[0])
    zero = jnp.zeros_like(X0)
    # qs.theta[0] is half a step: contact-line ends off the edges
    thetas = qs.theta[0] + (jnp.arange(n_steps) + 1) * period_angle / spp
    thetas = thetas.reshape(-1, spp)  # one block per mesh period
    rim_of = _rim_of(scene)

    R = scene.reaction_matrix()
    # each mesh's static force and largest quasi-static force on one contact line
    sizes = tuple((p.n_lines, p.n_slices) for p in planes)
    length = jnp.concatenate([p.cells(0.0).length.reshape(-1) for p in planes])
    static_fm, static_lines = mesh_forces(_joined(qs, "line_load") * length[None], sizes)
    fs = static_mesh_forces(scene, torque, static_fm)
    # divergence, as the lumped models: mesh force > blowup F_s or kinetic energy >
    # blowup² F_s²/2k̄ (F_s and k̄ over all meshes, k̄ the mean quasi-static mesh stiffness at
    # the speed)
    fs_all = jnp.sum(fs)
    k_mean = jnp.mean(sum(m.mesh_stiffness for m in qs.meshes))
    e_scale = 0.5 * fs_all**2 / k_mean

    # the mesh force at every step, the kinetic energy (an n² product) once per mesh period
    def check(X, Xd, P):
        return _force_code(Xd, X, jnp.sum(P), fs_all, blowup)

    def block_check(X, Xd):
        return _energy_code(Xd, M, e_scale, blowup)

    def record(X, Xd):
        return (*rim_of(X), R @ X, X) if states else (*rim_of(X), R @ X)

    modal, start = None, (X0, zero, zero)
    if space is not None:  # the modal basis with the static correction (docs/hybrid.md)
        Kr, Mr, Cr, structure = reduced_structure(
            space, K, M, C, F, cfg.integrator.basis.static_correction, model.rotating_frame
        )
        D = structure.D
        # Rayleigh's β K on the static correction (the residual's Kelvin–Voigt lag)
        beta_r = model.damping.residual_damping()
        reduced_damping = None
        if mesh_damping is not None:  # its map on the reduced coordinates: R D (None: D)
            Rm = mesh_damping.R
            reduced_damping = mesh_damping._replace(R=None if Rm is None else Rm @ D)
        modal = ModalSystem(Kr, Mr, Cr, D.T @ F, structure, beta_r, reduced_damping)
        q0 = space.T.T @ (M @ X0)  # Tᵀ M D = I, Tᵀ M G = 0
        r0 = X0 - D @ q0  # the static correction at the start (G f there)
        start = (q0, jnp.zeros_like(q0), jnp.zeros_like(q0), r0, zero, zero)

        def block_check(q, qd):
            return _energy_code(qd, Mr, e_scale, blowup)

    (X, Xd, Xdd, code, it), (th, P, te, rec) = _newmark_cells(
        SceneCells(scene, per_mesh_modifications(mods, len(planes)), e_ref, law),
        CellSystem(K, M, C, F, mesh_damping, modal),
        dt,
        start,
        thetas,
        record,
        checks=(check, block_check),
        keep_blocks=cfg.keep_periods,
    )

    fm, lines = mesh_forces(P[-keep:], sizes)
    # the kept steps end at the positions (k + 1) mod N_s of the first period (whole periods)
    j = (jnp.arange(keep) + 1) % spp
    # (spp, m), each position with its own reference max_M e, as the quasi-static solve
    static_te = jax.vmap(lambda x, e: mesh_te(scene, e)(x))(qs.x, e_max)
    code = jnp.where(
        qs.result[0] != 0, jnp.maximum(code, DynamicsResult.contact_not_converged), code
    )
    pressure = cells = None
    if cfg.pressure is not None or cfg.cell_loads:
        # the kept steps' cells (every step's forces are recorded: reduced here, not in the loop)
        cell_s, cell_z, mask = cell_geometry(scene, th[-keep:])
        line_load = jnp.where(mask, P[-keep:] / length[None], 0.0)  # (K, c) (N/m)
        if cfg.pressure is not None:
            p2 = mesh_max(line_load * pressure_factors(cfg.pressure, sizes, cell_s, mask), sizes)
            w0, s0, m0 = (_joined(qs, f) for f in ("line_load", "cell_s", "cell_mask"))
            w0 = jnp.where(m0, w0, 0.0)
            pressure = (p2, mesh_max(w0 * pressure_factors(cfg.pressure, sizes, s0, m0), sizes))
        if cfg.cell_loads:
            cells = split_cells(line_load, cell_s, cell_z, mask, sizes)
    return steady_state(
        Records(
            speed=jnp.asarray(speed, dtype),
            time_step=dt,
            mesh_period_angle=period_angle,
            steps_per_period=spp,
            transient_steps=n_steps - keep,
            theta=th[-keep:],
            mesh_force=fm,
            static_force=fs,
            transmission_error=te[-keep:],
            line_force=lines,
            static_line_force=jnp.stack([jnp.max(f) for f in static_lines]),
            static_te=static_te[j],
            bearing_force=scene.bearing_forces_fixed_frame(th[-keep:], rec[2][-keep:]),
            bearing_force_static=scene.bearing_forces(qs.theta, qs.x),
            omega_excited=omega_excited,
            final_state=(X, Xd, Xdd),
            iterations=it,
            code=code,
            rim=(rec[0][-keep:], rec[1][-keep:]),
            states=rec[3][-keep:] if states else None,
            pressure=pressure,
            cells=cells,
        )
    )


def run_config(
    model: HybridModel, integrator, window: SteadyState, steps: int, outputs: Outputs = Outputs()
) -> _Config:
    """The settings of a hybrid run of ``steps`` per mesh period (:func:`_config`: one kept
    period is enough), checked to fit: the Newmark loop records the kept steps' cell forces
    (all meshes), TE and mesh force (the transient periods integrate without records; with
    ``outputs.cell_loads`` the kept steps' cell loads and coordinates too)."""
    cells = sum(p.n_lines * p.n_slices for p in model.scene.base_planes)
    return _config(
        integrator, window, steps, outputs, min_keep=1, values_per_step=cells + 2, cells=cells
    )


@eqx.filter_jit
def sweep(
    model: HybridModel,
    speeds,
    law: ContactLaw,
    cfg: _Config,
    omega_excited,
    space=None,
    host_checked: bool = False,
):
    """The hybrid model at each speed of ``speeds`` (S,), one after the other (``jax.lax.map``:
    one effective compliance of n² in memory at a time), with the run's settings ``cfg``
    (:func:`run_config`) and the highest excited mode ``omega_excited`` (rad/s; NaN: unknown):
    :class:`~jaxgear.dynamics.DynamicResponse` with a leading speed axis. ``speeds`` (D, S) runs
    the D rows side by side (``jax.vmap``; rows placed one per device run there in parallel),
    each row's speeds one after the other: leading axes (D, S). ``space``: the modal basis
    (:func:`modal_space`) when the integrator has one, else None. ``host_checked``: the
    model's torque, the law and the speeds were checked on the host (concrete before this
    program): the program then holds no ``eqx.error_if`` of them, whose Python callback
    would keep it out of JAX's persistent compilation cache."""

    def one_after_another(row):
        return jax.lax.map(
            lambda w: _run(model, w, law, cfg, omega_excited, space, host_checked), row
        )

    if speeds.ndim == 2:
        return jax.vmap(one_after_another)(speeds)
    return one_after_another(speeds)
