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
stiffening). Damping (:class:`jaxgear.dynamics.Damping`, :func:`_damping`), with K̄_m(k) the
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

A :class:`~jaxgear.dynamics.HybridModel` is integrated by the same entries as a lumped one
(:func:`jaxgear.dynamics.simulate`, :func:`jaxgear.dynamics.speed_sweep`,
:func:`jaxgear.dynamics.band_dynamic_factor`), which call :func:`sweep` here. Also here: the
mesh stiffness averaged over a mesh period (:func:`mean_mesh_stiffness`), the free vibration at
a fixed mesh position (:func:`hybrid_free_vibration`, the energy check) and the rim's
nodal-diameter waves in a response (:func:`rim_waves`). The wheel's nodal-diameter modes and
their (3.9) resonance speeds live with the modal analysis (:mod:`jaxgear.dynamics._modal`).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, Int

from .._contact import ContactLaw, ExactContact, contact_law
from .._modifications import Modifications
from .._quasi_static import mesh_separations, per_mesh_modifications, quasi_static, separation
from .._results import DynamicsResult
from .._util import check_integer
from ..scenes import FlexibleMember, HybridPair, HybridScene
from ._modal import Damping, modal_analysis
from ._modal_basis import ModalSpace, modal_space_of, reduced_structure
from ._model import (
    HybridModel,
    cell_geometry,
    cells_from_reference,
    mesh_forces,
    mesh_max,
    mesh_te,
    pressure_factors,
    split_cells,
    static_mesh_forces,
)
from ._newmark import MeshDamping, newmark, newmark_modal
from ._result import steady_state
from ._settings import (
    DiffraxIntegrator,
    ModalBasis,
    SteadyState,
    _Config,
    _config,
    _energy_code,
    _force_code,
)

__all__ = [
    "FreeVibration",
    "hybrid_free_vibration",
    "mean_mesh_stiffness",
    "rim_stations",
    "rim_waves",
]


def _newmark_cells(
    scene,
    mods,
    K,
    M,
    C,
    F,
    dt,
    e_ref,
    state,
    thetas,
    law: ContactLaw,
    record,
    mesh_damping: MeshDamping | None = None,
    check=None,
    modal=None,
    block_check=None,
    keep_blocks: int | None = None,
):
    """The Newmark loop (:func:`~jaxgear.dynamics._newmark.newmark`, the contact in the cell
    space) on the hybrid scene, one step per pinion angle of ``thetas`` (P, S) (P blocks of S
    steps: the mesh periods of the mesh damping), from ``state`` = (X, Ẋ, Ẍ); ``check``: the
    divergence check of each step, ``block_check`` the one at the end of each block
    (:func:`~jaxgear.dynamics._newmark.newmark`), or None; ``keep_blocks``: record only the last
    blocks (None: all).

    The cells at each step: every mesh's cells at the pinion angle, their flank gaps from the
    mesh's time-constant reference ``e_ref`` (m,) (δ0 = e_ref,k − e), on the meshes' windows
    of master DOFs under the contact (:meth:`~jaxgear.scenes.HybridPair.window_row`).

    ``modal``: None (the cell space), or (K_r, M_r, C_r, F_r, :class:`ModalStructure`, β_r): the
    model in a modal basis (:func:`~jaxgear.dynamics._newmark.newmark_modal`; ``state`` then
    (q, q̇, q̈, r, ṙ, r̈), ``check`` gets (q, q̇, P); the final state is returned on the
    coordinates).

    Returns the final state (X, Ẋ, Ẍ, result code, most contact passes), θ of every step, and
    per recorded step (flattened over the recorded blocks): the cell forces P (c,) of all
    meshes, each mesh's TE (m,) and ``record(X, Ẋ)``."""
    per_mesh = per_mesh_modifications(mods, len(scene.base_planes))
    te_of = mesh_te(scene, e_ref)

    def cells_at(th):
        return scene.window_row(*cells_from_reference(scene, per_mesh, th, e_ref))

    def kept(X, Xd, P):
        return P, te_of(X), record(X, Xd)

    init = (*state, jnp.array(0), jnp.array(0))
    if modal is None:
        carry, (P, te, rec) = newmark(
            K,
            M,
            C,
            F,
            dt,
            init,
            thetas,
            cells_at,
            law,
            kept,
            check=check,
            block_check=block_check,
            mesh_damping=mesh_damping,
            keep_blocks=keep_blocks,
        )
    else:
        Kr, Mr, Cr, Fr, space, beta_r = modal
        carry, (P, te, rec) = newmark_modal(
            Kr,
            Mr,
            Cr,
            Fr,
            space,
            dt,
            init,
            thetas,
            cells_at,
            law,
            kept,
            check=check,
            block_check=block_check,
            mesh_damping=mesh_damping,
            residual_damping=beta_r,
            keep_blocks=keep_blocks,
        )
        q, qd, qdd, r, rd, rdd, code, it = carry  # the state on the coordinates
        D = space.D
        carry = (D @ q + r, D @ qd + rd, D @ qdd + rdd, code, it)
    return carry, (thetas.reshape(-1), P, te, rec)


class _HybridDamping(NamedTuple):
    """The damping of the hybrid Newmark, C(k) = C + c_m Rᵀ K̄_m(k) R in mesh period k, with
    K̄_m(k) the mesh stiffness averaged over period k's quasi-static positions on the stations
    under the mesh then (it turns with the wheel).

    Attributes:
        C: the constant part (units of K·s), (n, n), the bearings' damping included.
        c_m: the factor of the mesh share (s for Rayleigh, - for the composite), or None when
            the model has no mesh share (modal, "none"): C(k) = C.
        R: the map of the mesh share (n, n) (-), or None: the identity (Rayleigh, C(k) = C +
            β K̄_m(k), exact and sparse on the window).
    """

    C: Float[Array, "n n"]
    c_m: Float[Array, ""] | None
    R: Float[Array, "n n"] | None


def _damping(scene: HybridPair, Km, damping: Damping) -> _HybridDamping:
    """The damping of the hybrid scene (seed (2.34)–(2.36)) as its constant part and its mesh
    share that follows the mesh as the wheel turns (:class:`_HybridDamping`), plus the scene's
    bearing damping. ``Km``: the mesh stiffness averaged round the revolution, K̄ (n, n), whose
    system (M, K + K̄) gives the modes (ω_i, φ_i) of the modal models (unused for Rayleigh).

    - Rayleigh (2.34): C(k) = α M + β (K + K̄_m(k)): C = α M + β K, c_m = β, R = I (exact).
    - Modal (2.35): C = M Φ diag(2 ξ ω_i) Φᵀ M, no mesh share (K̄ the revolution's average:
      the same in every period).
    - Composite (2.36), ξ_i = ξ_m e_i + ξ_s (1 − e_i), e_i = φ_iᵀ K̄_m φ_i / ω_i², in a form
      linear in the mesh stiffness of the period: C(k) = 2 ξ_s M Φ Ω Φᵀ M + 2 (ξ_m − ξ_s)
      Rᵀ K̄_m(k) R, R = Φ' Ω'^(-1/2) Φ'ᵀ M (Φ', Ω' the elastic modes; the rigid ones, which
      the mesh does not strain, left out): c_m = 2 (ξ_m − ξ_s). In modal coordinates its
      diagonal is (2.36)'s, 2 ω_i (ξ_s + (ξ_m − ξ_s) e_i(k)) with the mesh energy share e_i(k)
      of period k; it keeps the modes' coupling 2 (ξ_m − ξ_s) φ_iᵀ K̄_m(k) φ_j / √(ω_i ω_j)
      that (2.36) drops, and stays positive semi-definite in every period (ξ_m >= ξ_s), where
      (2.36) on the modes of one period put the mesh share on the stations under the mesh
      then, and subtracting it to re-add the period's ran away (negative damping on rim-local
      modes).
    """
    M = scene.structure.M
    Cb = scene.bearing_damping()
    if damping.model == "none":
        return _HybridDamping(Cb, None, None)
    if damping.model == "rayleigh":  # no modal analysis needed
        return _HybridDamping(
            damping.alpha * M + damping.beta * scene.structure.K + Cb, damping.beta, None
        )
    modes = modal_analysis(scene, Km)
    Phi, omega = modes.shapes, modes.omega
    MP = M @ Phi
    if damping.model == "modal":
        return _HybridDamping(MP @ ((2.0 * damping.ratio * omega)[:, None] * MP.T) + Cb, None, None)
    C = MP @ ((2.0 * damping.structure_ratio * omega)[:, None] * MP.T) + Cb
    s = jnp.where(modes.rigid, 0.0, 1.0 / jnp.sqrt(jnp.where(modes.rigid, 1.0, omega)))
    R = Phi @ (s[:, None] * MP.T)
    return _HybridDamping(C, 2.0 * (damping.mesh_ratio - damping.structure_ratio), R)


def _revolution_periods(scene: HybridPair) -> int:
    """Mesh periods after which every flexible member's stations are again where they were:
    the least common multiple of their tooth counts (the wheel's teeth for H1; 1 if none)."""
    Z = [m.rim_dofs.shape[0] for m in scene.members if isinstance(m, FlexibleMember)]
    return math.lcm(*Z) if Z else 1


def _revolution_mesh_stiffness(scene: HybridPair, block, periods: int):
    """K̄ (n, n): the mean of the mesh stiffness ``block(p)`` (:func:`_mesh_block`) over the mesh
    periods p = 0 … ``periods`` − 1 (a revolution, :func:`_revolution_periods`)."""
    n = scene.structure.K.shape[0]

    def add(Km, p):
        U, B, _ = block(p)
        return Km.at[U[:, None], U[None, :]].add(B), None

    Km, _ = jax.lax.scan(add, jnp.zeros((n, n), scene.structure.K.dtype), jnp.arange(periods))
    return Km / periods


def _references(scene: HybridPair, mods, theta):
    """e_ref (m,): each mesh's time-constant reference of the flank gaps over the positions
    ``theta`` (S,) of a mesh period (the largest max_M e), and max_M e at each position (S, m).

    The quasi-static δ0 = max_M e(θ) − e moves its reference with the position: in dynamics that
    would be a spurious kinematic excitation of the drive rotation wherever max_M e varies (a
    tip relief), so the dynamics use δ0 = e_ref − e, as the lumped model's mesh table."""
    planes = scene.base_planes
    mods = per_mesh_modifications(mods, len(planes))

    def at(th):
        return jnp.stack([part[1] for part in mesh_separations(scene, mods, th)])

    e_max = jax.vmap(at)(theta)
    return jnp.max(e_max, axis=0), e_max


def _speed_damping(model: HybridModel, speed, law: ContactLaw, spp: int):
    """The quasi-static result at the ``spp`` step positions of the first mesh period at speed
    Ω (:func:`_period_statics`), the mesh stiffness of period p, ``block(p)``
    (:func:`_mesh_block` on the cells loaded there), and the damping (:func:`_damping`; the modal
    models' modes with K̄_m averaged round the wheel)."""
    scene = model.scene
    period_angle = scene.base_planes[0].mesh_period_angle
    qs, _ = _period_statics(scene, model.mods, model.torque, speed, spp, law)
    loaded = _loaded(qs)

    def block(p):  # K̄_m(p) on the stations under the meshes in period p
        return _mesh_block(scene, qs.theta + p * period_angle, loaded)

    Km = None
    if model.damping.model in ("modal", "composite"):
        Km = _revolution_mesh_stiffness(scene, block, _revolution_periods(scene))
    return qs, block, _damping(scene, Km, model.damping)


class RevolutionDamping(NamedTuple):
    """The damping of a hybrid model at one speed over a wheel revolution (seed (2.34)–(2.36)),
    C(k) = C + c_m Wᵀ K̄_m(k) W in mesh period k, with K̄_m(k) the mesh stiffness averaged over
    the period's quasi-static positions on the rim stations under the meshes then (U) and W the
    rows U of R (of the identity when R is None).

    Attributes:
        constant: C, the part that does not follow the mesh, bearings included (N·s/m per
            coordinate), (n, n).
        mesh_factor: c_m (s for Rayleigh, - for the composite), or None: no mesh share.
        mesh_map: R (n, n), or None: the identity.
        periods: mesh periods of a revolution (the least common multiple of the condensed
            members' tooth counts).
        block: k ↦ (U (w,), K̄_m(k) on U (w, w), whether every window of period k lies in U).
    """

    constant: Float[Array, "n n"]
    mesh_factor: Float[Array, ""] | None
    mesh_map: Float[Array, "n n"] | None
    periods: int
    block: Callable

    def at(self, k) -> tuple[Float[Array, "n n"], Array]:
        """C(k) (n, n) in mesh period ``k`` and whether the period's windows lie inside U."""
        if self.mesh_factor is None:
            return self.constant, jnp.array(True)
        U, B, ok = self.block(k)
        n = self.constant.shape[0]
        W = jnp.eye(n, dtype=B.dtype)[U] if self.mesh_map is None else self.mesh_map[U]
        return self.constant + self.mesh_factor * (W.T @ B @ W), ok


def revolution_damping(
    model: HybridModel, speed, *, steps_per_period: int = 16, contact: ContactLaw | None = None
) -> RevolutionDamping:
    """The damping a hybrid model's Newmark run uses at pinion ``speed`` Ω (rad/s) with
    ``steps_per_period`` steps per mesh period and the contact law ``contact`` (default:
    exact), period by period over a wheel revolution (:class:`RevolutionDamping`): to check
    its symmetry and positive semi-definiteness, or its modal diagonal against (2.36)."""
    dtype = model.scene.structure.K.dtype
    law = contact_law(ExactContact() if contact is None else contact, dtype)
    check_integer("steps_per_period", steps_per_period, 1)
    _, block, damp = _speed_damping(model, jnp.asarray(speed, dtype), law, steps_per_period)
    return RevolutionDamping(damp.C, damp.c_m, damp.R, _revolution_periods(model.scene), block)


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
    basis = getattr(cfg.integrator, "basis", None)
    if basis is None:
        return None
    n = model.scene.structure.K.shape[0]
    if basis.modes > n:
        raise ValueError(
            f"modal basis modes = {basis.modes} is out of range: allowed 1 … {n} (the "
            "structure's coordinates)"
        )
    return _modal_space(model, law, cfg.steps_per_period, basis)


@eqx.filter_jit
def _modal_space(model: HybridModel, law: ContactLaw, spp: int, basis: ModalBasis) -> ModalSpace:
    scene = model.scene
    dtype = scene.structure.K.dtype
    speed = jnp.asarray(basis.speed, dtype)
    qs, _ = _period_statics(scene, model.mods, model.torque, speed, spp, law)
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


def _run(model: HybridModel, speed, law: ContactLaw, cfg: _Config, omega_excited, space=None):
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
    qs, block, damp = _speed_damping(model, speed, law, spp)
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
        beta_r = model.damping.beta if model.damping.model == "rayleigh" else 0.0
        modal = (Kr, Mr, Cr, D.T @ F, structure, beta_r)
        if mesh_damping is not None:  # its map on the reduced coordinates: R D (None: D)
            Rm = mesh_damping.R
            mesh_damping = mesh_damping._replace(R=None if Rm is None else Rm @ D)
        q0 = space.T.T @ (M @ X0)  # Tᵀ M D = I, Tᵀ M G = 0
        r0 = X0 - D @ q0  # the static correction at the start (G f there)
        start = (q0, jnp.zeros_like(q0), jnp.zeros_like(q0), r0, zero, zero)

        def block_check(q, qd):
            return _energy_code(qd, Mr, e_scale, blowup)

    (X, Xd, Xdd, code, it), (th, P, te, rec) = _newmark_cells(
        scene,
        mods,
        K,
        M,
        C,
        F,
        dt,
        e_ref,
        start,
        thetas,
        law,
        record,
        mesh_damping,
        check,
        modal,
        block_check,
        cfg.keep_periods,
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


def _joined(qs, name: str):
    """The per-cell field ``name`` of every mesh of a quasi-static result, joined mesh after
    mesh as the contact row joins the cells: (P, c)."""
    P = qs.theta.shape[0]
    return jnp.concatenate([getattr(m, name).reshape(P, -1) for m in qs.meshes], axis=-1)


def _reference_shift(scene: HybridScene, d):
    """The move N α of the free rotations that brings each mesh's flank-normal approach u_k·X
    forward by d_k (m), (meshes,): the start state's move from the quasi-static gaps (reference
    max_M e at the position) to the dynamics' time-constant reference e_ref. α solves
    (U N) α = d in the least-squares sense (U the meshes' TE vectors): one rotation per free
    shaft; a pair's meshes all move with its one drive rotation (u·N = cos β_b)."""
    A = scene.te_vectors() @ scene.N
    alpha = jnp.linalg.lstsq(A, d)[0]
    return scene.N @ alpha


def _loaded(qs):
    """The loaded cells (line load > 0) of every mesh at each position, joined: (P, c)."""
    return _joined(qs, "line_load") > 0


def _rim_of(scene: HybridPair):
    """X ↦ (radial, axial) displacement of the rim stations of every condensed member, member
    after member (each in its own body frame, at the axial master plane nearest mid-face), each
    (Σ Z,); (0,) when every member is rigid. A pair with a flexible wheel: the wheel's Z
    stations; both members flexible: the pinion's z1 stations, then the wheel's
    (:func:`rim_stations` splits them)."""
    dofs, angles = [jnp.zeros((0, 3), jnp.int32)], [jnp.zeros((0,), scene.structure.K.dtype)]
    for member in scene.members:
        if isinstance(member, FlexibleMember):
            j_mid = jnp.argmin(jnp.abs(member.z_nodes))
            dofs.append(member.rim_dofs[:, j_mid, :])  # (Z, 3) global DOFs
            Z = member.rim_dofs.shape[0]
            angles.append(member.station0 + member.pitch_angle * jnp.arange(Z))
    rim, ang = jnp.concatenate(dofs), jnp.concatenate(angles)

    def rim_of(X):
        u = X[rim]
        return u[:, 0] * jnp.cos(ang) + u[:, 1] * jnp.sin(ang), u[:, 2]

    return rim_of


def rim_stations(scene) -> list[tuple[int, slice]]:
    """Where each condensed member's stations sit in a hybrid run's rim records
    (:attr:`~jaxgear.dynamics.DynamicResult.rim_radial`, ``rim_axial``): (member index, the
    slice of its Z stations) per condensed member, in member order; [] for a rigid scene."""
    out, start = [], 0
    for i, member in enumerate(getattr(scene, "members", ())):
        if isinstance(member, FlexibleMember):
            Z = int(member.rim_dofs.shape[0])
            out.append((i, slice(start, start + Z)))
            start += Z
    return out


def mean_mesh_stiffness(
    scene: HybridPair,
    mods,
    torque,
    spp: int,
    contact: ContactLaw = ExactContact(),
    *,
    speed=0.0,
):
    """K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over the ``spp`` quasi-static positions of one mesh
    period (n, n), w_c = 1 on the loaded cells (line load > 0), 0 elsewhere: the mesh part of K̄
    in Rayleigh damping (2.34); at pinion torque T (N·m) and speed Ω (rad/s, the centrifugal
    loads; default at rest), with the ``contact`` law of the quasi-static solve."""
    law = contact_law(contact, scene.structure.K.dtype)
    return _period_statics(scene, mods, torque, speed, spp, law)[1]


def _mesh_block(scene: HybridPair, theta, loaded, pad: int = 1):
    """The mesh stiffness of every mesh averaged over the positions ``theta`` (S,) with the
    cells ``loaded`` (S, c) (weights 0/1, joined mesh after mesh) on the window U of the first
    position widened by ``pad`` stations each side: (U (w,), B (w, w), whether every position's
    window lies inside U). A coordinate that two meshes see appears in U once per mesh; B holds
    its stiffness at one of them (the others' rows and columns are zero)."""
    n = scene.structure.size

    def row(th, pad=0):
        cells = scene.mesh_cells(th)
        return scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells), pad)

    U = row(theta[0], pad).idx
    w = U.shape[0]
    pos = jnp.full((n,), w, jnp.int32).at[U].set(jnp.arange(w, dtype=jnp.int32))

    def add(B, p):
        r = row(theta[p])
        kl = jnp.where(r.mask, r.k * r.length, 0.0) * loaded[p].astype(B.dtype)
        j = pos[r.idx]
        B = B.at[j[:, None], j[None, :]].add(r.V.T @ (kl[:, None] * r.V), mode="drop")
        return B, jnp.all(j < w)

    B, ok = jax.lax.scan(
        add, jnp.zeros((w, w), scene.structure.K.dtype), jnp.arange(theta.shape[0])
    )
    return U, B / theta.shape[0], jnp.all(ok)


def _period_statics(scene: HybridPair, mods, torque, speed, spp, law: ContactLaw):
    """Quasi-static result at pinion speed Ω (centrifugal loads) at the ``spp`` step positions
    of one mesh period, and K̄_m there (all meshes)."""
    theta = (jnp.arange(spp) + 0.5) * scene.base_planes[0].mesh_period_angle / spp
    qs = quasi_static(
        scene,
        mods,
        torque,
        theta,
        speed=speed,
        contact=law,
        throw=False,
    )
    n = scene.structure.size
    U, B, _ = _mesh_block(scene, theta, _loaded(qs))
    Km = jnp.zeros((n, n), scene.structure.K.dtype).at[U[:, None], U[None, :]].add(B)
    return qs, Km


def check_newmark(integrator) -> None:
    """A hybrid model is integrated by Newmark: the contact loop in the cell space has no
    diffrax form (one-line ``ValueError`` otherwise, before any computation)."""
    if isinstance(integrator, DiffraxIntegrator):
        raise ValueError(
            f"integrator = {integrator!r}: a hybrid model takes jaxgear.dynamics.Newmark (the "
            "contact loop in the cell space has no diffrax form)"
        )


def run_config(
    model: HybridModel,
    integrator,
    window: SteadyState,
    steps: int,
    blowup,
    states: bool,
    cell_loads: bool = False,
    pressure=None,
) -> _Config:
    """The settings of a hybrid run of ``steps`` per mesh period (:func:`_config`: one kept
    period is enough), checked to fit: the Newmark loop records the kept steps' cell forces
    (all meshes), TE and mesh force (the transient periods integrate without records; with
    ``cell_loads`` the kept steps' cell loads and coordinates too); ``pressure``: the Hertz
    pressure tracked."""
    cells = sum(p.n_lines * p.n_slices for p in model.scene.base_planes)
    return _config(
        integrator,
        window,
        steps,
        blowup,
        states,
        min_keep=1,
        values_per_step=cells + 2,
        cell_loads=cell_loads,
        pressure=pressure,
        cells=cells,
    )


@eqx.filter_jit
def sweep(model: HybridModel, speeds, law: ContactLaw, cfg: _Config, omega_excited, space=None):
    """The hybrid model at each speed of ``speeds`` (S,), one after the other (``jax.lax.map``:
    one effective compliance of n² in memory at a time), with the run's settings ``cfg``
    (:func:`run_config`) and the highest excited mode ``omega_excited`` (rad/s; NaN: unknown):
    :class:`~jaxgear.dynamics.DynamicResult` with a leading speed axis. ``speeds`` (D, S) runs
    the D rows side by side (``jax.vmap``; rows placed one per device run there in parallel),
    each row's speeds one after the other: leading axes (D, S). ``space``: the modal basis
    (:func:`modal_space`) when the integrator has one, else None."""

    def one_after_another(row):
        return jax.lax.map(lambda w: _run(model, w, law, cfg, omega_excited, space), row)

    if speeds.ndim == 2:
        return jax.vmap(one_after_another)(speeds)
    return one_after_another(speeds)


class FreeVibration(eqx.Module):
    """Free vibration of the hybrid scene about its loaded equilibrium at a fixed mesh position.

    Attributes:
        time: (S,) (s). x: coordinates (S, n). mesh_force: Σ of the cell forces (N), (S,).
        energy: kinetic + strain energy of the vibration about the static equilibrium, over
            the cells in contact there, ½ẊᵀMẊ + ½(X − X_s)ᵀ(K + K_c)(X − X_s) (J), (S,).
        contact_held: True while every cell loaded at equilibrium stays loaded and no other
            cell closes (the system is then linear and the energy a constant of the motion).
        result: as :class:`~jaxgear.dynamics.DynamicResult`.
    """

    time: Float[Array, " S"]
    x: Float[Array, "S n"]
    mesh_force: Float[Array, " S"]
    energy: Float[Array, " S"]
    contact_held: Array
    result: Int[Array, ""]


def hybrid_free_vibration(
    scene: HybridPair,
    modifications: Modifications | None,
    torque,
    theta,
    velocity,
    time_step,
    n_steps: int,
    *,
    steps_per_period: int = 64,
) -> FreeVibration:
    """Newmark of the undamped hybrid scene with the mesh held at pinion angle ``theta`` (rad):
    the static equilibrium under ``torque`` (N·m) there, set moving with the initial
    ``velocity`` Ẋ(0) (n,) (m/s, rad/s), integrated ``n_steps`` steps of ``time_step`` (s) by
    the cell-space step of a hybrid model's :func:`jaxgear.dynamics.speed_sweep` (same contact
    loop and flank reference, from the quasi-static positions of ``steps_per_period`` steps; no
    centrifugal load, C = 0).

    With the contact held (small ``velocity``) the system is linear and time-invariant and the
    average-acceleration scheme conserves the vibration energy exactly: the energy check of the
    hybrid Newmark.

    Raises:
        ValueError: ``n_steps`` < 1, ``time_step`` <= 0, a ``velocity`` of the wrong shape, or
            a scene of several meshes (this check handles one).
    """
    _ = scene.mesh  # one mesh: a one-line error else, before any computation
    dtype = scene.structure.K.dtype
    n = scene.structure.K.shape[0]
    velocity = jnp.asarray(velocity, dtype)
    if velocity.shape != (n,):
        raise ValueError(f"velocity has shape {velocity.shape}: allowed ({n},)")
    if int(n_steps) != n_steps or n_steps < 1:
        raise ValueError(f"n_steps = {n_steps!r} is out of range: allowed an integer >= 1")
    if not float(time_step) > 0:
        raise ValueError(f"time_step = {time_step!r} s is out of range: allowed > 0")
    check_integer("steps_per_period", steps_per_period, 4)
    mods = Modifications() if modifications is None else modifications
    return _free(
        scene,
        mods,
        jnp.asarray(torque, dtype),
        jnp.asarray(theta, dtype),
        velocity,
        jnp.asarray(time_step, dtype),
        int(n_steps),
        int(steps_per_period),
    )


@eqx.filter_jit
def _free(scene, mods, torque, theta, velocity, dt, n_steps, spp):
    mesh = scene.mesh  # the free vibration handles one mesh (a one-line error else)
    period = (jnp.arange(spp) + 0.5) * mesh.mesh_period_angle / spp
    e_ref, _ = _references(scene, mods, period)
    qs = quasi_static(scene, mods, torque, theta[None], throw=False)  # at rest
    e_th = separation(mesh, mods, theta)[1]
    Xs = qs.x[0] + _reference_shift(scene, e_ref - e_th)
    M = scene.structure.M
    C = jnp.zeros_like(M)
    F = torque * scene.f_torque
    # Ẍ(0) = 0: the start is the static equilibrium, where K X + Σ P V = F
    (_, _, _, code, _), (_, P, _, rec) = _newmark_cells(
        scene,
        mods,
        scene.structure.K,
        M,
        C,
        F,
        dt,
        e_ref,
        (Xs, velocity, jnp.zeros_like(Xs)),
        jnp.full((1, n_steps), theta),
        ExactContact(50),
        lambda X, Xd: (X, Xd),
    )
    X, Xd = rec
    cells = mesh.cells(theta)
    idx, Vw = scene.window(cells)
    Vw = Vw.reshape(-1, Vw.shape[-1])
    loaded = qs.line_load[0].reshape(-1) > 0
    kl = jnp.where(loaded, (cells.stiffness * cells.length).reshape(-1), 0.0)
    Kc = jnp.zeros_like(M).at[idx[:, None], idx[None, :]].add(Vw.T @ (kl[:, None] * Vw))
    K = scene.structure.K + Kc
    d = X - Xs[None, :]
    energy = 0.5 * jnp.einsum("si,ij,sj->s", Xd, M, Xd) + 0.5 * jnp.einsum("si,ij,sj->s", d, K, d)
    held = jnp.all((P > 0) == loaded[None, :])
    time = (jnp.arange(n_steps) + 1) * dt
    v0 = 0.5 * velocity @ M @ velocity
    energy = jnp.concatenate([v0[None], energy])
    time = jnp.concatenate([jnp.zeros((1,), time.dtype), time])
    X = jnp.concatenate([Xs[None], X])
    fm = jnp.concatenate([jnp.sum(qs.line_load[0] * cells.length)[None], jnp.sum(P, axis=-1)])
    return FreeVibration(time, X, fm, energy, held, code)


def rim_waves(u, time_step, spin: float = -1.0, band=None) -> dict:
    """Nodal-diameter content of a rim field (the seed's (3.2) Fourier series in the angle, then
    in time): which diameters vibrate, at what frequency, travelling which way.

    Args:
        u: rim displacement at Z equally spaced stations (body frame, station k at angle
            2πk/Z), over equally spaced steps, shape (S, Z)
            (:class:`~jaxgear.dynamics.DynamicResult` ``rim_radial`` or ``rim_axial``, NumPy).
        time_step: Δt (s). spin: the body's rotation sense about z (−1 for the wheel, +1 for the
            pinion): a wave travelling the same way is *forward*.
        band: (f_min, f_max) (Hz): look for each diameter's largest wave in this band only
            (e.g. above half the mesh frequency, to skip the quasi-static load pattern that
            travels round the turning body at n times its rotation frequency). Default: all.

    Returns:
        dict of NumPy arrays over the nodal diameters n = 0 … Z/2: ``nodal_diameter``,
        ``amplitude`` (m, the largest travelling-wave amplitude of that diameter),
        ``frequency_hz`` (of that wave, in the body frame) and ``direction`` (+1 forward,
        −1 backward, 0 for n = 0 or a standing pattern). The mean over time is removed.
    """
    u = np.asarray(u, dtype=float)
    S, Z = u.shape
    if S < 4 or Z < 3:
        raise ValueError(f"rim field of shape {u.shape}: need >= 4 steps and >= 3 stations")
    u = u - u.mean(axis=0, keepdims=True)
    # spatial harmonics U_n(t) = (2/Z) Σ_k u_k e^{−i n φ_k}: a wave A cos(nφ − ωt) (towards +φ)
    # gives U_n = A e^{−iωt}, one towards −φ gives A e^{+iωt}
    U = np.fft.fft(u, axis=1)[:, : Z // 2 + 1] * (2.0 / Z)
    spec = np.fft.fft(U, axis=0) / S  # (S, n): frequency bins ν_j, e^{+i 2π ν t} convention
    freq = np.fft.fftfreq(S, time_step)
    inside = np.ones(S, bool)
    if band is not None:
        inside = (np.abs(freq) >= band[0]) & (np.abs(freq) <= band[1])
        if not inside.any():
            raise ValueError(f"band = {tuple(band)} Hz holds no frequency bin of the record")
    j = np.argmax(np.where(inside[:, None], np.abs(spec), -1.0), axis=0)
    amp = np.abs(spec[j, np.arange(spec.shape[1])])
    f = freq[j]
    # e^{−iωt} (towards +φ) appears at negative ν: direction +φ when ν < 0
    towards_plus = np.where(f < 0, 1.0, np.where(f > 0, -1.0, 0.0))
    direction = towards_plus * np.sign(spin)
    direction[0] = 0.0
    return {
        "nodal_diameter": np.arange(spec.shape[1]),
        "amplitude": amp,
        "frequency_hz": np.abs(f),
        "direction": direction,
    }
