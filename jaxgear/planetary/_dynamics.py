"""Dynamics of a planetary stage in the carrier frame, every mesh at once (docs/planetary.md,
"Dynamics in the carrier frame"): the one Newmark engine (:func:`jaxgear.dynamics.newmark`) on

    M q'' + (C + Omega G + v G_v) q' + (K_b - Omega^2 K_Omega + Omega v K_v) q
        + V^T P(V q - delta0) = f,

the 2N meshes' contact cells P (:class:`~jaxgear.planetary.ContactMeshes`: time-varying stiffness,
loss of contact; or :class:`~jaxgear.planetary.ConstantMeshes`) at the mesh travel x = v t, the
Coriolis and centripetal terms at the carrier speed Omega (and, in the 3D model, the gyroscopic
moments of the members' spin relative to the carrier, which v sets: ``model.spin_matrices``); the
dynamic factor and dynamic load sharing per mesh; a speed sweep (``jax.vmap`` over the carrier
speeds); the signal of a transducer fixed on the ring (the planet-pass modulation, McFadden & Smith
1985) and its order spectrum.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, on_the_path
from .._contact import AbstractContactLaw, ExactContact, solve_contact
from .._util import as_float, check_instance, check_integer, check_real
from ..dynamics import (
    LinearSystem,
    ModalAnalysis,
    ModalSpace,
    ModalSystem,
    StepCells,
    cell_stiffness,
    matrix_modal_analysis,
    newmark,
    newmark_modal,
    reduced_structure,
)
from ._housed import check_carrier_speed
from ._meshes import (
    AbstractPlanetaryMeshes,
    held_structure,
    pin_terms,
    sun_load,
)
from ._ring import AbstractRingModel, RigidRing, modal_damping
from ._stage import AbstractPlanetaryModel, PlanetaryStage

__all__ = [
    "DynamicLoadSharing",
    "PlanetaryDynamics",
    "PlanetaryRun",
    "PlanetaryStageSystem",
    "order_spectrum",
    "planetary_cell_row",
    "dynamic_load_sharing",
    "planetary_dynamics",
    "planetary_mesh_modes",
    "planetary_speed_sweep",
    "planetary_stage_system",
    "ring_transducer_signal",
]


class PlanetaryRun(eqx.Module):
    """How a planetary run is integrated and what it loads.

    Attributes:
        sun_torque: torque on the sun (N m), positive counter-clockwise.
        steps_per_period: Newmark steps per mesh period (static, >= 8).
        periods: mesh periods integrated (static, >= 1).
        keep_periods: the last mesh periods recorded (static, 1..periods).
        damping_ratio: modal damping ratio (-) on the modes of (M, K_b + mean mesh stiffness):
            C = M Phi diag(2 zeta omega) Phi^T M (seed (2.35)).
        tangential_pin_errors, radial_pin_errors: planet-pin errors (m), () or (n_planets,), as
            :func:`~jaxgear.planetary.load_sharing` (the stage's eccentricities,
            :class:`~jaxgear.planetary.Eccentricities`, are added at each step, turning with their
            members).
        cell_loads: also record every cell's force at the kept steps
            (:attr:`PlanetaryDynamics.cell_forces`; static, default False: a sweep keeps none,
            memory ∝ kept steps × cells × speeds).
        mesh_steps: Newmark steps per mesh period (a traced number, so that runs of other
            steps share one compiled program: a sweep's speeds each at its own step), or None:
            ``steps_per_period``. Given, ``periods`` and ``keep_periods`` count blocks of
            ``steps_per_period`` steps, not mesh periods (the time step p_b / (mesh_steps v)).
        ring_cell_space: a flexible ring's station model (no ``modes``) solves each step's
            contact in the cell space (G = K_eff⁻¹ once, two n² products a step) instead of
            factoring all its coordinates per contact pass (static, default False). For the
            short steps of a resolved sweep (the sweep sets it: forces within 4·10⁻⁹ of the
            coordinate solve's, half the CPU time of a speed); at long steps (carrier speeds near
            zero) the explicit inverse loses accuracy (docs/planetary.md, "The flexible ring
            in the dynamics").

    Raises:
        ValueError: a count or ratio out of range (one line).
    """

    sun_torque: Float[Array, ""] = eqx.field(converter=as_float)
    steps_per_period: int = eqx.field(static=True, default=64)
    periods: int = eqx.field(static=True, default=40)
    keep_periods: int = eqx.field(static=True, default=4)
    damping_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.05)
    tangential_pin_errors: Float[Array, "*n"] = eqx.field(converter=as_float, default=0.0)
    radial_pin_errors: Float[Array, "*n"] = eqx.field(converter=as_float, default=0.0)
    cell_loads: bool = eqx.field(static=True, default=False)
    mesh_steps: Float[Array, ""] | None = None
    ring_cell_space: bool = eqx.field(static=True, default=False)

    def __check_init__(self):
        check_integer("steps_per_period", self.steps_per_period, 8)
        check_integer("periods", self.periods, 1)
        check_integer("keep_periods", self.keep_periods, 1)
        if self.keep_periods > self.periods:
            raise ValueError(
                f"PlanetaryRun: keep_periods = {self.keep_periods} is out of range: allowed "
                f"1..periods = {self.periods}"
            )
        check_real("damping_ratio", self.damping_ratio, lo=0.0, hi=1.0, shape=(),
                   where="PlanetaryRun")


class DynamicLoadSharing(NamedTuple):
    """The load sharing factor K_γ of a dynamic run (:func:`dynamic_load_sharing`).

    Attributes:
        k_gamma: the peak-based K_γ, the dynamic one reported: max_j P_j / mean_j P_j, P_j the
            largest sun-mesh force of planet path j over the records (-), () (leading axes of
            the forces kept).
        k_gamma_mean_load: the mean-load K_γ: max_j M_j / mean_j M_j, M_j path j's time-mean
            sun-mesh force over the records (-), same shape.
    """

    k_gamma: Any
    k_gamma_mean_load: Any


def dynamic_load_sharing(sun_mesh_forces) -> DynamicLoadSharing:
    """The load sharing factor K_γ of a planetary stage's dynamic run, from its planet paths'
    sun-mesh forces over the kept window (the records: whole mesh periods at steady state).

    K_γ is ISO 6336-1's mesh load factor (clause 4, the general influence factors: F_t K_A K_γ
    is the load of the most loaded path of a multiple-path drive; AGMA 6123 the same), the
    most loaded path's load over the mean path's. A dynamic run gives two (one definition, one
    home: every dynamic K_γ of jaxgear is this function's):

    * the peak-based K_γ = max_j P_j / mean_j P_j, P_j = max_t F_j(t), each path's dynamic
      factor P_j / F_0 relative to the mean path's (F_0 cancels). This is the dynamic K_γ
      reported: with the dynamic factor K_v applied to each path's load as ISO does
      (F_t K_A K_γ K_v), K_γ must not hold the dynamic overload a second time. The per-instant
      ratio max_t (max_j F_j(t) / mean_j F_j(t)) does: with unmodified teeth each planet's
      sun-mesh force peaks at k_after/k_before ≈ 2 F_0 when its entering pair takes its share
      (the planets at different instants), the others at F_0, so it gives 3 DF/(DF + 2) ≈ 1.5
      for three planets at quasi-static speeds where every path carries the same load and the
      same peak (the diagnostic that showed the double count); the peak-based one gives 1 there;
    * the mean-load K_γ = max_j M_j / mean_j M_j, M_j = mean_t F_j(t): the time-mean shares.

    Both equal the quasi-static K_γ where the forces are constant in time (constant mesh
    stiffness with pin errors, at low speed).

    Args:
        sun_mesh_forces: each planet path's sun-mesh force (N, compression positive) at each
            recorded step, (..., t, n_planets) (:attr:`PlanetaryDynamics.sun_mesh_forces`; a
            sweep's (s, t, n) gives (s,) factors). NumPy or JAX arrays (differentiable).

    Returns:
        :class:`DynamicLoadSharing` (each (...,)).

    Raises:
        ValueError: fewer than 2 dimensions, no recorded step or no planet, in one line.
    """
    shape = tuple(np.shape(sun_mesh_forces))
    if len(shape) < 2 or shape[-2] < 1 or shape[-1] < 1:
        raise ValueError(
            f"dynamic_load_sharing: sun_mesh_forces shape {shape} is out of range: allowed "
            "(..., t, n_planets) with t >= 1 and n_planets >= 1")
    f = (sun_mesh_forces if isinstance(sun_mesh_forces, (jax.Array, np.ndarray))
         else np.asarray(sun_mesh_forces, dtype=float))  # an array kept (JAX: differentiable)
    peak = f.max(axis=-2)  # (..., n): each path's largest force over the window
    mean = f.mean(axis=-2)  # (..., n): each path's time-mean force
    return DynamicLoadSharing(peak.max(axis=-1) / peak.mean(axis=-1),
                              mean.max(axis=-1) / mean.mean(axis=-1))


class PlanetaryDynamics(eqx.Module):
    """The recorded steady state of a planetary run (the last ``keep_periods`` mesh periods).

    Attributes:
        time: time (s) of each recorded step, (t,).
        travel: mesh travel x = x_0 + v t (m), (t,).
        displacement: coordinates (m), (t, n_dof + m): the model's, then a flexible ring's m
            = 2Z station displacements (x, y in the ring's frame; :class:`~jaxgear.planetary.CondensedRing`)
            and, for a :class:`~jaxgear.planetary.CraigBamptonRing`, its fixed-interface modes' amplitudes
            (m kg^(1/2), mass-normalised).
        sun_mesh_forces, ring_mesh_forces: transverse mesh forces (N, compression positive),
            (t, n_planets).
        static_force: the nominal transverse mesh force T_s / (N r_bs) (N), ().
        result: the run's result code (0: successful; a
            :class:`~jaxgear.DynamicsResult`), ().
        ring_deflection: the flexible ring's elastic displacement at each ring mesh along its
            force (m, relieving the mesh), (t, n_planets); zero for a rigid ring.
        cell_forces: each cell's contact force (N, flank-normal, compression positive; 0 off
            contact), (t, c), in the order of the meshes kind's cell rows
            (:meth:`~jaxgear.planetary.ContactMeshes.split_cells` splits it per mesh and planet,
            :meth:`~jaxgear.planetary.ContactMeshes.planet_cells` at ``travel`` places the cells and
            gives their lengths: the line load is force / length); ``meshes.mesh_forces`` of it
            is the mesh forces above. None unless the run asks for it
            (``PlanetaryRun(cell_loads=True)``).
    """

    time: Float[Array, " t"]
    travel: Float[Array, " t"]
    displacement: Float[Array, "t n_dof"]
    sun_mesh_forces: Float[Array, "t n"]
    ring_mesh_forces: Float[Array, "t n"]
    static_force: Float[Array, ""]
    result: Array
    ring_deflection: Float[Array, "t n"]
    cell_forces: Float[Array, "t c"] | None = None

    @property
    def dynamic_factors(self) -> tuple[Float[Array, " n"], Float[Array, " n"]]:
        """(sun meshes', ring meshes') dynamic factors: each mesh's largest force over the
        nominal one T_s / (N r_bs), each (n_planets,) (a sweep's: (n_speeds, n_planets))."""
        return (
            jnp.max(self.sun_mesh_forces, axis=-2) / self.static_force[..., None],
            jnp.max(self.ring_mesh_forces, axis=-2) / self.static_force[..., None],
        )

    @property
    def k_gamma(self) -> Float[Array, ""]:
        """The dynamic load sharing factor K_γ, peak-based: the largest planet path's peak
        sun-mesh force over the recorded steps over the mean of the paths' peaks, () (a
        sweep's: (n_speeds,)); :func:`dynamic_load_sharing` (ISO 6336-1's mesh load factor, the
        dynamic factor not counted twice)."""
        return dynamic_load_sharing(self.sun_mesh_forces).k_gamma

    @property
    def k_gamma_mean_load(self) -> Float[Array, ""]:
        """The mean-load K_γ: the largest planet path's time-mean sun-mesh force over the
        recorded steps over the mean of the paths' means, () (a sweep's: (n_speeds,));
        :func:`dynamic_load_sharing`."""
        return dynamic_load_sharing(self.sun_mesh_forces).k_gamma_mean_load


def _with_ring(A, B):
    """The block-diagonal [[A, 0], [0, B]] (the stage's coordinates, then the ring's)."""
    if B.shape[0] == 0:
        return A
    n, m = A.shape[0], B.shape[0]
    out = jnp.zeros((n + m, n + m), A.dtype)
    return out.at[:n, :n].set(A).at[n:, n:].set(B.astype(A.dtype))


def _run(model, stage, meshes, run, carrier_speed, mesh_speed, law, ring):
    if not meshes.one_period:  # one period's rows are laid out and repeated below
        raise ValueError(
            f"planetary_dynamics: meshes {type(meshes).__name__} change from one mesh period to "
            "the next (per-tooth deviations), out of range: allowed meshes that repeat every "
            "mesh period (ContactMeshes, ConstantMeshes); planetary_quasi_static takes them"
        )
    S, B = run.steps_per_period, run.periods
    m, k_b, f, k_mean, _ = planetary_stage_system(model, stage, meshes, run, S)
    p_b = meshes.mesh_period()
    omega = as_float(carrier_speed)
    c = modal_damping(m, k_b + k_mean, run.damping_ratio)
    k_u, m_u, c_u = ring.dynamic_matrices(k_b.dtype, run.damping_ratio)
    n_dof, n_u = k_b.shape[0], k_u.shape[0]
    # the members' spin relative to the carrier (its gyroscopic moments; zero but in the 3D
    # model): v G_v q' and Omega v K_v q
    g_v, k_v = model.spin_matrices(stage)
    system = LinearSystem(
        K=_with_ring(k_b - omega**2 * model.centripetal_matrix(stage) + omega * mesh_speed * k_v,
                     k_u),
        M=_with_ring(m, m_u),
        C=_with_ring(c + omega * model.gyroscopic_matrix(stage) + mesh_speed * g_v, c_u),
        F=jnp.concatenate([f, jnp.zeros(n_u, f.dtype)]),
    )
    per_mesh = S if run.mesh_steps is None else run.mesh_steps  # steps per mesh period
    dt = p_b / (per_mesh * mesh_speed)
    # step i at the travel x = (i + 1/2) p_b / S, mid-points as :func:`jaxgear.mesh_positions`:
    # never on the instant a line enters (s = 0) when the planets' phases are multiples of
    # 1/S, where rounding would decide planet by planet; the run starts from the quasi-static
    # state at x = p_b / (2 S), at rest
    def travel(i):
        return (i + 0.5) * (p_b / per_mesh)

    basis = ring.modal_basis(k_b.dtype)

    def cell_row(i):
        # the pins' offsets, and the sun's and ring's eccentricities turning with their members
        row = planetary_cell_row(model, stage, meshes, run, travel(i))
        if n_u == 0:
            return row
        # the ring meshes' displacement's entries in the cells' rows, (n, c)
        ring_rows = meshes.ring_rows(stage, travel(i), row.k.shape[0])
        if basis is None:  # the station model: the contact on every coordinate
            E = ring.contact_rows(stage, travel(i))
            idx = jnp.arange(n_dof + n_u) if run.ring_cell_space else None  # the cell space
            return row._replace(idx=idx, V=jnp.concatenate([row.V, -ring_rows.T @ E], axis=1))
        # modal: the ring cells reach the stage's coordinates and their planet's two
        # stations, a window of coordinates (newmark_modal's cell space)
        iu, E = ring.window(stage, travel(i))
        idx = jnp.concatenate([jnp.arange(n_dof, dtype=iu.dtype), n_dof + iu])
        return row._replace(idx=idx, V=jnp.concatenate([row.V, -ring_rows.T @ E], axis=1))

    def full(row):  # a window's rows on every coordinate
        if row.idx is None:
            return row.V
        return jnp.zeros((row.V.shape[0], n_dof + n_u), row.V.dtype).at[:, row.idx].add(row.V)

    load = _unbalance_load(model, stage, omega, mesh_speed, travel, n_u)
    row0 = cell_row(jnp.zeros_like(p_b))
    F0 = system.F if load is None else system.F + load(jnp.zeros_like(p_b))
    static = solve_contact(system.K, F0, full(row0), row0.k, row0.length, row0.delta0,
                           row0.mask, law)
    zero = jnp.zeros_like(static.x)
    steps = (jnp.arange(B * S, dtype=p_b.dtype) + 1.0).reshape(B, S)
    cells = StepCells(cell_row, law)

    def record(X, Xd, P, i):
        w = ring.contact_rows(stage, travel(i)) @ X[n_dof:]
        return X, meshes.mesh_forces(P), i, w, (P if run.cell_loads else None)

    code = (jnp.array(0, jnp.int32), jnp.array(0, jnp.int32))
    if basis is None:
        final, (X, forces, i, w, P) = newmark(system, dt, (static.x, zero, zero, *code), steps,
                                           cells, record, keep_blocks=run.keep_periods,
                                           load=load)
    else:  # the ring's kept modes and the static correction of the others
        T_u, D_u, G_u = basis
        D = jax.scipy.linalg.block_diag(jnp.eye(n_dof, dtype=k_b.dtype), D_u)
        G = _with_ring(jnp.zeros((n_dof, n_dof), k_b.dtype), G_u)
        Kr, Mr, Cr, structure = reduced_structure(ModalSpace(D, D[:, :0], D, G), *system[:4],
                                                  True, True)
        q0 = jnp.concatenate([static.x[:n_dof], T_u.T @ (m_u @ static.x[n_dof:])])
        r0 = static.x - D @ q0  # G f of the static state: the residual's part
        zq, zr = jnp.zeros_like(q0), jnp.zeros_like(r0)
        final, (X, forces, i, w, P) = newmark_modal(
            ModalSystem(Kr, Mr, Cr, D.T @ system.F, structure), dt,
            (q0, zq, zq, r0, zr, zr, *code), steps, cells, record,
            keep_blocks=run.keep_periods, load=load)
    n = stage.n_planets
    return PlanetaryDynamics(
        time=i * dt,
        travel=travel(i),
        displacement=X,
        sun_mesh_forces=forces[:, :n],
        ring_mesh_forces=forces[:, n:],
        static_force=run.sun_torque / (n * stage.sun.base_radius),
        result=final[-2],  # (the state's result code, before the contact passes)
        ring_deflection=w,
        cell_forces=P,
    )


def _mean_mesh_stiffness(model, stage, meshes, offsets, positions: int):
    """(K̄_m, the cell rows): the meshes' stiffness matrix averaged over ``positions``
    mid-points of one mesh period (N/m, (n_dof, n_dof)), the matrix the run's modal damping
    and :func:`planetary_mesh_modes` add to K_b."""
    x_one = meshes.positions(positions, 1)
    rows = jax.vmap(lambda x: meshes.cell_row(model, stage, x, offsets))(x_one)
    # the cells on the theoretical path: beyond it a corner's cell carries load only under
    # deflection (docs/extended-contact.md)
    path = on_the_path(meshes)
    on = rows
    if path is not meshes:
        on = jax.vmap(lambda x: path.cell_row(model, stage, x, offsets))(x_one)
    kl = jnp.where(on.mask, on.k * on.length, 0.0)
    return cell_stiffness(on.V, kl) / kl.shape[0], rows


class PlanetaryStageSystem(NamedTuple):
    """A planetary stage's linear parts in its model's coordinates (:func:`planetary_stage_system`).

    Attributes:
        m: M (kg), (n_dof, n_dof).
        k_b: K_b (N/m): bearings, pins, the held members' holds and the floating planets' hold
            (no mesh), (n_dof, n_dof).
        f: the load (N): the run's sun torque on u_s and the pin errors' share, (n_dof,).
        k_mean: K̄_m (N/m), the 2N meshes' cell stiffness averaged over a mesh period,
            (n_dof, n_dof).
        rows: the cell rows at those positions (a :class:`~jaxgear.CellRow` with a leading
            axis (positions,)).
    """

    m: Array
    k_b: Array
    f: Array
    k_mean: Array
    rows: Any


def planetary_stage_system(model, stage, meshes, run, positions: int) -> PlanetaryStageSystem:
    """The stage's M, K_b, load f and mean mesh stiffness K̄_m over ``positions`` mid-points of
    a mesh period (static int): the linear part of :func:`planetary_dynamics`' system, which a
    gearbox (:mod:`jaxgear.gearbox`) joins to other stages. ``run``: :class:`PlanetaryRun`
    (its sun torque and pin errors)."""
    m = model.mass_matrix(stage)
    f_err, d_s, d_r = pin_terms(model, stage, run.tangential_pin_errors, run.radial_pin_errors,
                                "planetary_dynamics")
    f = sun_load(model, stage, run.sun_torque, f_err)
    offsets = (d_s, d_r)
    k_b = held_structure(model, stage, meshes, offsets)
    k_mean, rows = _mean_mesh_stiffness(model, stage, meshes, offsets, positions)
    return PlanetaryStageSystem(m, k_b, f, k_mean, rows)


def planetary_cell_row(model, stage, meshes, run, x) -> CellRow:
    """The 2N meshes' cells at the mesh travel ``x`` (m) on the stage's coordinates, with the
    run's pin errors and the stage's eccentricities turning with their members at that
    travel: one step's cell row of :func:`planetary_dynamics` (a rigid ring's)."""
    _, d_s, d_r = pin_terms(model, stage, run.tangential_pin_errors, run.radial_pin_errors,
                            "planetary_dynamics", x)
    return meshes.cell_row(model, stage, x, (d_s, d_r))


@eqx.filter_jit
def planetary_mesh_modes(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    run: PlanetaryRun,
    positions: int = 64,
) -> ModalAnalysis:
    """The modes of the mesh-averaged system of a planetary run, (M, K_b + K̄_m): K_b the
    stage's structure with the run's pin errors (bearings, pins, the held members' holds),
    K̄_m the 2N meshes' cell stiffness averaged over ``positions`` points of a mesh period
    (the system whose modes the run's modal damping C takes; the pairs' mesh-averaged modes,
    docs/dynamics.md "Time step and accuracy"), through
    :func:`~jaxgear.dynamics.modal_analysis`: ``energy`` rows ``("mesh", "structure")``, the
    mesh's share of each mode's strain energy (seed (2.36)), so that
    :func:`~jaxgear.dynamics.excited_omega` picks the highest mode the meshes excite (a held
    member turning against its stiff hold stores < 5 % in the meshes and is not one). Shapes
    (n_dof,) and (n_dof, n_dof), the stage's coordinates (a flexible ring's are not in it)."""
    m = model.mass_matrix(stage)
    _, d_s, d_r = pin_terms(model, stage, run.tangential_pin_errors, run.radial_pin_errors,
                            "planetary_mesh_modes")
    k_b = held_structure(model, stage, meshes, (d_s, d_r))
    k_mean, _ = _mean_mesh_stiffness(model, stage, meshes, (d_s, d_r), positions)
    return matrix_modal_analysis(m, k_b, k_mean)


def _unbalance_load(model, stage, omega, mesh_speed, travel, n_u):
    """Step i ↦ the stage's mass unbalances' rotating forces (:class:`~jaxgear.planetary.Unbalances`)
    on the coordinates (N; none on a flexible ring's), at the step's travel; None without."""
    if stage.unbalances is None:
        return None

    def load(i):
        f = stage.unbalances.load(model, stage, travel(i), omega, mesh_speed)
        return jnp.concatenate([f, jnp.zeros(n_u, f.dtype)])

    return load


def _mesh_speed(stage, carrier_speed, mesh_speed):
    """The mesh travel speed (m/s): given, or the ring held: r_br Omega (the ring turns at
    -Omega in the carrier frame; r_bs (omega_s - Omega) with Willis)."""
    if mesh_speed is None:
        return stage.ring.base_radius * jnp.abs(as_float(carrier_speed))
    return as_float(mesh_speed)


@eqx.filter_jit
def planetary_dynamics(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    run: PlanetaryRun,
    carrier_speed: Float[Array, ""],
    mesh_speed: Float[Array, ""] | None = None,
    law: AbstractContactLaw = ExactContact(),
    ring: AbstractRingModel = RigidRing(),
) -> PlanetaryDynamics:
    """The steady response of a stage at one carrier speed, in the carrier frame.

    Newmark average acceleration (:func:`jaxgear.dynamics.newmark`, the contact in coordinates)
    on ``M q'' + (C + Omega G) q' + (K_b - Omega^2 K_Omega) q + V^T P = f`` with the 2N meshes'
    cells at the mesh travel ``x = x_0 + v t``, x_0 = p_b / (2 S) (time-varying mesh stiffness,
    contact loss), from the quasi-static state at x_0 at rest; the last ``run.keep_periods``
    mesh periods recorded. With ``run.steps_per_period`` a multiple of N (equally spaced
    planets) the planets' phases fall on the steps and the discrete system keeps the stage's
    cyclic symmetry.

    Args:
        model: the model kind (:class:`~jaxgear.planetary.PlanarPlanetary`: Coriolis and centripetal
            terms; :class:`~jaxgear.planetary.TorsionalPlanetary`: none;
            :class:`~jaxgear.planetary.SpatialPlanetary`: the 3D model, its cells across the face,
            the axial and tilting coordinates, and the gyroscopic moments of the members' spin
            relative to the carrier at the mesh speed v).
        stage: the stage (ring or carrier held in rotation); its ``unbalances``
            (:class:`~jaxgear.planetary.Unbalances`) add their rotating forces at each step's travel.
        meshes: :class:`~jaxgear.planetary.ContactMeshes` or
            :class:`~jaxgear.planetary.ConstantMeshes`.
        run: :class:`PlanetaryRun` (torque, steps, periods, damping, pin errors).
        carrier_speed: Omega (rad/s), counter-clockwise positive.
        mesh_speed: v (m/s), the mesh travel speed; None: the ring held, v = r_br |Omega|
            (mesh frequency v / p_b = z_r |Omega| / 2 pi).
        law: the contact law.
        ring: :class:`~jaxgear.planetary.RigidRing` (the lumped ring, the default) or a flexible
            :class:`~jaxgear.planetary.CondensedRing`: its 2Z station displacements join the coordinates
            (stiffness F^-1, its stations' mass if given), and each ring mesh's cells see the
            ring's displacement at the planet's moving position (the hats at the angle
            :func:`~jaxgear.planetary.ring_contact_angles`), so that the ring compliance coupling the
            ring meshes follows the carrier; a massless ring gives the quasi-static
            compliance of :func:`~jaxgear.planetary.planetary_quasi_static` at every step; a
            :class:`~jaxgear.planetary.CraigBamptonRing` adds its fixed-interface modes as coordinates
            (mass and stiffness only: the ring cells reach the stations alone).

    Returns:
        :class:`PlanetaryDynamics`.
    """
    check_instance("meshes", meshes, AbstractPlanetaryMeshes, "a planetary meshes kind",
                   "planetary_dynamics")
    check_instance("run", run, PlanetaryRun, "a jaxgear.planetary.PlanetaryRun",
                   "planetary_dynamics")
    check_instance("ring", ring, AbstractRingModel,
                   "a jaxgear ring model (RigidRing, CondensedRing, CraigBamptonRing)",
                   "planetary_dynamics")
    check_carrier_speed(model, carrier_speed, "planetary_dynamics")
    v = _mesh_speed(stage, carrier_speed, mesh_speed)
    return _run(model, stage, meshes, run, carrier_speed, v, law, ring)


@eqx.filter_jit
def planetary_speed_sweep(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    run: PlanetaryRun,
    carrier_speeds: Float[Array, " s"],
    law: AbstractContactLaw = ExactContact(),
    ring: AbstractRingModel = RigidRing(),
) -> PlanetaryDynamics:
    """:func:`planetary_dynamics` at each carrier speed (rad/s, (s,), > 0; the ring held),
    vectorised with ``jax.vmap``: every field gains a leading axis (s,); ``ring`` as there."""
    check_instance("ring", ring, AbstractRingModel,
                   "a jaxgear ring model (RigidRing, CondensedRing, CraigBamptonRing)",
                   "planetary_speed_sweep")
    check_carrier_speed(model, 1.0, "planetary_speed_sweep (the ring held, the carrier turns)")
    speeds = jnp.reshape(as_float(carrier_speeds), (-1,))

    def one(omega):
        return _run(model, stage, meshes, run, omega, stage.ring.base_radius * omega, law, ring)

    return jax.vmap(one)(speeds)


def ring_transducer_signal(
    ring_mesh_forces: Float[Array, "t n"],
    carrier_angle: Float[Array, " t"],
    planet_angles: Float[Array, " n"],
    sensor_angle: float = 0.0,
    window_power: int = 4,
) -> Float[Array, " t"]:
    """What a transducer fixed on the ring (or the housing) at ``sensor_angle`` sees: each
    planet's ring-mesh force weighted by how near the planet passes,
    ``y(t) = sum_n w(psi_n + theta_c(t) - theta_T) F_rn(t)`` with the planet-pass window
    ``w(a) = ((1 + cos a) / 2)^p`` (McFadden & Smith 1985's amplitude modulation; Inalpolat &
    Kahraman 2009).

    Args:
        ring_mesh_forces: F_rn (N), (t, n_planets), in the carrier frame's time.
        carrier_angle: theta_c (rad) of the carrier in the fixed frame at each sample, (t,).
        planet_angles: psi_n (rad), (n_planets,). sensor_angle: theta_T (rad).
        window_power: p (>= 1): the window's sharpness.

    Returns:
        y (N), (t,).
    """
    check_integer("window_power", window_power, 1)
    a = planet_angles[None, :] + carrier_angle[:, None] - sensor_angle
    w = ((1.0 + jnp.cos(a)) / 2.0) ** window_power
    return jnp.sum(w * ring_mesh_forces, axis=-1)


def order_spectrum(signal, samples_per_turn: int) -> tuple[np.ndarray, np.ndarray]:
    """The one-sided amplitude spectrum of a signal sampled ``samples_per_turn`` times per
    carrier turn over a whole number of turns (host-side, NumPy): (orders (-), amplitudes, in
    the signal's unit); order k is k times the carrier frequency."""
    y = np.asarray(signal, dtype=float)
    check_integer("samples_per_turn", samples_per_turn, 2)
    if y.size % samples_per_turn:
        raise ValueError(
            f"order_spectrum: {y.size} samples is not a whole number of turns of "
            f"samples_per_turn = {samples_per_turn}"
        )
    turns = y.size // samples_per_turn
    amp = np.abs(np.fft.rfft(y)) / y.size
    amp[1:] *= 2.0
    return np.arange(amp.size) / turns, amp
