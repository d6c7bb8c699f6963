"""A planetary stage's time plan, the model's own preparation step of a run over speeds
(docs/planetary.md, "Time step and span of a sweep"; docs/dynamics.md, "Time step and
accuracy"), with the pairs' rule and constants: the steps per mesh period at each speed from
the stage's modes, the span from the damping's settling time, the kept periods, the check of
the step against the highest mode the meshes excite; every speed run in one compiled program
at its own step (:func:`steps_sweep`), the dynamic factors and K_γ read from its records
(:func:`sweep_factors`), whether anything excites the stage (:func:`excitation`) and the
lumped model a stage's supports allow (:func:`planetary_model_for`).

``jaxgear run`` and ``jaxgear sweep`` on a planetary case (:mod:`jaxgear.cli.planetary_sweep`)
take them from here and add only their command-line checks, warnings and outputs."""

from __future__ import annotations

import math
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._util import check_integer
from ..dynamics import (
    SETTLE_TOL,
    UNDER_RESOLVED_STEPS,
    ModalAnalysis,
    excited_omega,
    settling_time,
    steps_for_mode,
)
from ._dynamics import (
    PlanetaryRun,
    dynamic_load_sharing,
    planetary_dynamics,
    planetary_mesh_modes,
)
from ._meshes import (
    AbstractPlanetaryMeshes,
    ConstantMeshes,
    PlanetaryQuasiStatic,
    planetary_quasi_static,
)
from ._spatial import SpatialPlanetary
from ._stage import AbstractPlanetaryModel, PlanarPlanetary, PlanetaryStage, TorsionalPlanetary

__all__ = [
    "EXCITATION_POSITIONS",
    "HOLDS_3D",
    "KEEP_OTHER",
    "KEEP_PERIODIC",
    "LUMPED_MODELS",
    "NO_EXCITATION_TOL",
    "STEPS_PER_TOP_PERIOD",
    "TURN_POSITIONS",
    "SweepFactors",
    "SweepRecords",
    "TimePlan",
    "carrier_periodic",
    "constant_mesh_sharing",
    "eccentric",
    "excitation",
    "grouped_records",
    "holds_stage",
    "lumped_mode_models",
    "lumped_sharing_models",
    "plan_sweep",
    "planetary_model_for",
    "program_span",
    "rating_sharing_model",
    "speed_groups",
    "settled_periods",
    "sharing_over_turn",
    "speed_run",
    "step_resolution",
    "steps_sweep",
    "sweep_factors",
    "time_plan",
    "turn_travel",
]

#: the fewest Newmark steps per period of the highest mode the meshes excite below which a
#: plan is under-resolved (:func:`step_resolution`): the pairs' ``under_resolved`` bound
#: (:data:`jaxgear.dynamics.UNDER_RESOLVED_STEPS`); the default step gives at least
#: :data:`jaxgear.dynamics.STEPS_PER_MODE` (:func:`time_plan`)
STEPS_PER_TOP_PERIOD = UNDER_RESOLVED_STEPS
#: kept mesh periods of a stage whose steady state repeats every mesh period in the carrier
#: frame (:func:`carrier_periodic`): the last one against the one before is the settled check
#: (SETTLE_TOL, the transient's amplitude left when the kept periods begin, and SETTLED_TOL,
#: the periodicity above which a speed is not settled, are the pairs' and trains' rule,
#: :func:`jaxgear.dynamics.settling_time`, docs/dynamics.md, "Settled sweeps"; the run starts
#: from the quasi-static state, an error of about the dynamic part of the mesh force, so the
#: kept forces carry ~0.1 % of it)
KEEP_PERIODIC = 2
#: kept mesh periods otherwise (eccentricities, unbalances and a flexible ring turn relative to
#: the carrier: the forces repeat over a member's turn, not a mesh period)
KEEP_OTHER = 4
#: the smallest eigenvalue of a stage's 3D stiffness, relative to its largest, below which a
#: free motion is left (an axial or tilting support missing): :func:`holds_stage`
HOLDS_3D = 1e-12


def carrier_periodic(stage, flexible_ring: bool) -> bool:
    """Whether the stage's steady state repeats every mesh period in the carrier frame: a
    rigid ring (not ``flexible_ring``: a condensed ring's stations turn relative to the
    carrier), no eccentricity or runout of any member and no unbalance (concrete values).
    Then the only time dependence left is each mesh's stiffness along its travel, periodic in
    the base pitch whatever the planets' angles and pin errors (constant offsets in that
    frame); the forces of one settled mesh period give any number of them
    (``jaxgear run``'s ring spectrum)."""
    return not (flexible_ring or stage.unbalances is not None or eccentric(stage))


def eccentric(stage) -> bool:
    """Whether a member of ``stage`` runs out: an eccentricity of the sun, ring or carrier or a
    planet's runout, non-zero (:class:`~jaxgear.planetary.Eccentricities`, concrete values)."""
    e = stage.eccentricities
    if e is None:
        return False
    return any(np.any(np.asarray(a)) for a in (e.sun, e.ring, e.carrier, e.planet))


class TimePlan(NamedTuple):
    """The time discretisation of a sweep (:func:`time_plan`), per input speed.

    Attributes:
        steps: Newmark steps per mesh period N_s, int (s,).
        periods: mesh periods integrated, int (s,) (the settling ones, then ``keep``).
        keep: mesh periods kept (the steady-state window).
        f_max_Hz: the highest natural frequency the meshes excite (Hz).
        f_min_Hz: the lowest natural frequency the meshes excite (Hz).
        settle_s: the settling time t_s (s).
        automatic: (steps, periods) from the rule (not given).
    """

    steps: np.ndarray
    periods: np.ndarray
    keep: int
    f_max_Hz: float
    f_min_Hz: float
    settle_s: float
    automatic: tuple


def time_plan(modes, speeds, mesh_frequency: float, n_planets: int, damping_ratio: float,
              periodic: bool, steps=None, periods=None, keep=None) -> TimePlan:
    """The sweep's steps and span at each input speed, from the stage's modes (``modes``:
    :func:`~jaxgear.planetary.planetary_mesh_modes` of the run, the mesh-averaged system):

    * N_s = the smallest N × 2^j >= max(64, 40 f_max / f_mesh) (the pairs' rule,
      :func:`~jaxgear.dynamics.steps_for_mode`; N = ``n_planets``, so that the planets'
      phases fall on the steps), f_max the highest mode storing >= 5 % of its strain energy
      in the meshes (:func:`~jaxgear.dynamics.excited_omega`), f_mesh = ``mesh_frequency``
      (Hz per rad/s of the input) × speed;
    * periods = keep + ceil(t_s f_mesh), t_s = ln(1 / :data:`SETTLE_TOL`) / (ζ ω_min), ω_min
      the lowest mode the meshes excite (>= 5 % of its strain energy in them, as f_max: a
      mode of the members on their bearings that the meshes barely strain is barely started
      by the run's quasi-static start, and the settled check measures what is left),
      ζ = ``damping_ratio``;
    * keep = :data:`KEEP_PERIODIC` where ``periodic`` (:func:`carrier_periodic`), else
      :data:`KEEP_OTHER`.

    ``steps``, ``periods``, ``keep`` given (the command line's): used at every speed.

    Raises:
        ValueError: a speed would need more than 2^22 steps per mesh period (one line).
    """
    sp = np.asarray(speeds, dtype=float)
    w_max = float(excited_omega(modes))
    settle, w_min = settling_time(modes, float(damping_ratio))
    f_mesh = sp * float(mesh_frequency)
    if steps is None:
        ns = steps_for_mode(w_max, 1.0 / float(mesh_frequency), sp, 1.0, n_planets)
    else:
        ns = np.full(sp.shape, int(steps))
    keep = keep or (KEEP_PERIODIC if periodic else KEEP_OTHER)
    if periods is not None:
        keep = min(keep, int(periods))
    if periods is None:
        pe = settled_periods(settle, f_mesh, keep)
    else:
        pe = np.full(sp.shape, int(periods))
    return TimePlan(ns.astype(int), pe.astype(int), int(keep), w_max / (2 * math.pi),
                    w_min / (2 * math.pi), settle, (steps is None, periods is None))


def settled_periods(settle_s: float, f_mesh, keep: int) -> np.ndarray:
    """The automatic span of :func:`time_plan` at mesh frequencies ``f_mesh`` (Hz, (s,)):
    ``keep`` + ceil(t_s f_mesh) mesh periods, t_s = ``settle_s`` the settling time (s)."""
    return keep + np.ceil(settle_s * np.asarray(f_mesh, dtype=float)).astype(int)


def program_span(steps, periods, keep: int) -> tuple[int, int, int]:
    """The one compiled program of speeds at the step counts ``steps`` (N_s, (s,)) and spans
    ``periods`` (mesh periods, (s,)) with ``keep`` kept periods (:func:`steps_sweep`):
    (block, blocks integrated, blocks kept), a block the smallest N_s steps: as many blocks as
    the longest settling ((periods − keep) N_s, the largest over the speeds) plus ``keep``
    periods of the largest N_s, whose last ``keep`` N_top steps are recorded (every speed's
    last ``keep`` mesh periods in them)."""
    steps_i = np.asarray(steps)
    block, top = int(steps_i.min()), int(steps_i.max())
    settle = int(np.max((np.asarray(periods) - keep) * steps_i))
    keep_blocks = keep * top // block
    return block, -(-settle // block) + keep_blocks, keep_blocks


def plan_sweep(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    run: PlanetaryRun,
    speeds,
    mesh_frequency: float,
    flexible_ring: bool = False,
    steps=None,
    periods=None,
    keep=None,
    min_steps: int = 64,
) -> tuple[TimePlan, ModalAnalysis]:
    """The preparation step of a run over the input ``speeds`` (rad/s, (s,)): the modes of the
    mesh-averaged stage (:func:`~jaxgear.planetary.planetary_mesh_modes` of ``run`` at
    ``min_steps`` positions per mesh period) and the :func:`time_plan` they give, the stage
    :func:`carrier_periodic` or not (``flexible_ring``: a condensed ring's stations turn
    relative to the carrier); ``mesh_frequency``: Hz per rad/s of the input (Willis, the case's
    roles). ``steps``, ``periods``, ``keep`` as :func:`time_plan`'s. Returns (the plan, the
    modes)."""
    modes = planetary_mesh_modes(model, stage, meshes, run, min_steps)
    plan = time_plan(modes, speeds, mesh_frequency, stage.n_planets, float(run.damping_ratio),
                     carrier_periodic(stage, flexible_ring), steps, periods, keep)
    return plan, modes


def step_resolution(plan: TimePlan, f_mesh, n_planets: int) -> dict:
    """Whether the plan's time step resolves the highest natural frequency the meshes excite
    (``plan.f_max_Hz``, :func:`time_plan`): at mesh frequency f_mesh (Hz, the swept speeds',
    (s,)) and ``plan.steps`` per mesh period, n = N_s f_mesh / f_max steps per period of
    f_max. Below :data:`STEPS_PER_TOP_PERIOD` (20, the pairs' bound) at some speed,
    Newmark's average acceleration (no numerical damping, period elongation) filters those
    modes (the impacts of teeth entering mesh) and the dynamic factor comes out low (the
    command line warns). The rule's step (:func:`time_plan` without ``steps``) gives n >= 40
    at every speed.

    Returns ``f_max_Hz``, ``steps_per_top_period_min`` (the least n over the speeds),
    ``resolved`` (bool), ``steps_per_period_resolved`` (the rule's N_s at the lowest speed),
    ``automatic`` (the rule's steps)."""
    f = np.asarray(f_mesh, dtype=float)
    n = plan.steps * f / plan.f_max_Hz
    i = int(np.argmin(f))
    need = int(steps_for_mode(2 * math.pi * plan.f_max_Hz, 1.0, f[i:i + 1], 1.0, n_planets)[0])
    n_min = float(np.min(n))
    resolved = bool(n_min >= STEPS_PER_TOP_PERIOD)
    return {"f_max_Hz": plan.f_max_Hz, "steps_per_top_period_min": n_min,
            "resolved": resolved, "steps_per_period_resolved": need,
            "automatic": bool(plan.automatic[0])}


class SweepRecords(NamedTuple):
    """Each speed's kept record of :func:`steps_sweep` (its last ``keep`` mesh periods).

    Attributes:
        periods: mesh periods each speed integrated, float (s,) (the rule's, or more where
            it shares a program with a slower speed).
        time: per speed, the kept steps' times (s), (keep N_s,).
        forces: per speed, the sun-mesh then ring-mesh transverse forces (N), (keep N_s, 2N).
        deflection: per speed, the ring's elastic displacement at the ring meshes (m),
            (keep N_s, N) (zeros for a rigid ring).
        result: each speed's result code, int (s,).
        static_force: the nominal mesh force T_s / (N r_bs) (N).
        programs: the compiled programs the sweep ran (1, or one per N_s where grouped).
    """

    periods: np.ndarray
    time: list
    forces: list
    deflection: list
    result: np.ndarray
    static_force: float
    programs: int


def speed_groups(plan: TimePlan, grouped: bool) -> list:
    """The speeds' indices per compiled program of :func:`steps_sweep`: all in one, or, where
    ``grouped``, one program per N_s (increasing N_s), so that only the slow speeds pay their
    long kept windows and settling in the largest N_s's steps. Grouped is the flexible ring's
    (a step costs more than a rigid ring's, a compilation about the same: 62 s of CPU against
    79 s in one program on the small test stage's 9 speeds; a rigid ring's sweep is cheaper in
    one program: docs/planetary.md, "Time step and span of a sweep")."""
    steps = np.asarray(plan.steps)
    if not grouped:
        return [np.arange(steps.size)]
    return [np.flatnonzero(steps == n) for n in np.unique(steps)]


def steps_sweep(model, stage, meshes, base, plan: TimePlan, carrier, mesh_speed, ring,
                grouped: bool = False) -> SweepRecords:
    """The speeds of each group of :func:`speed_groups` in one compiled program, each at its
    own step (``PlanetaryRun.mesh_steps`` = N_s, traced): blocks of the group's smallest N_s,
    as many as its longest settling (t_s over the speed's step, the largest over the group's
    speeds) plus ``keep`` periods of its largest N_s, the last ``keep`` of the largest N_s
    recorded (every speed's last ``keep`` mesh periods in them). ``carrier``, ``mesh_speed``:
    (s,), rad/s and m/s. Returns each speed's last ``keep`` mesh periods
    (:class:`SweepRecords`)."""
    groups = speed_groups(plan, grouped)

    def program(idx):
        run, r = _one_program(model, stage, meshes, base, plan, idx, np.asarray(carrier)[idx],
                              np.asarray(mesh_speed)[idx], ring)
        return r

    return grouped_records(plan, groups, program)


def grouped_records(plan: TimePlan, groups, program) -> SweepRecords:
    """The :class:`SweepRecords` of the speeds of ``groups`` (index arrays, each one compiled
    program, :func:`program_span`): ``program(idx)`` the group's
    :class:`~jaxgear.planetary.PlanetaryDynamics` (leading speed axis), each speed's own last
    ``plan.keep`` mesh periods of ``plan.steps`` steps taken from its kept records."""
    s = np.asarray(plan.steps).size
    periods, result = np.zeros(s), np.zeros(s, dtype=int)
    time, forces, deflection = [None] * s, [None] * s, [None] * s
    fs = None
    for idx in groups:
        r = program(idx)
        block, blocks, _ = program_span(np.asarray(plan.steps)[idx],
                                        np.asarray(plan.periods)[idx], plan.keep)
        f = np.concatenate([np.asarray(r.sun_mesh_forces), np.asarray(r.ring_mesh_forces)], -1)
        t, w, code = np.asarray(r.time), np.asarray(r.ring_deflection), np.asarray(r.result)
        fs = float(np.asarray(r.static_force).reshape(-1)[0])
        for j, k in enumerate(idx):
            kept = slice(-plan.keep * int(plan.steps[k]), None)
            time[k], forces[k], deflection[k] = t[j, kept], f[j, kept], w[j, kept]
            periods[k] = blocks * block / plan.steps[k]
            result[k] = int(code[j])
    return SweepRecords(periods, time, forces, deflection, result, fs, len(groups))


def _one_program(model, stage, meshes, base, plan: TimePlan, idx, carrier, mesh_speed, ring):
    """(the run of the blocks, the :class:`~jaxgear.planetary.PlanetaryDynamics` with a leading
    speed axis) of the speeds ``idx`` in one compiled program (:func:`steps_sweep`)."""
    steps_i = np.asarray(plan.steps)[idx]
    block, blocks, keep_blocks = program_span(steps_i, np.asarray(plan.periods)[idx], plan.keep)
    run = PlanetaryRun(
        base.sun_torque, steps_per_period=block, periods=blocks, keep_periods=keep_blocks, damping_ratio=base.damping_ratio,
        tangential_pin_errors=base.tangential_pin_errors,
        radial_pin_errors=base.radial_pin_errors, ring_cell_space=True,
    )
    one = jax.vmap(lambda om, v, n_s: planetary_dynamics(
        model, stage, meshes, eqx.tree_at(lambda r: r.mesh_steps, run, n_s,
                                          is_leaf=lambda x: x is None), om, v, ring=ring))
    steps = jnp.asarray(steps_i, dtype=jnp.asarray(carrier).dtype)
    return run, one(jnp.asarray(carrier), jnp.asarray(mesh_speed), steps)


def speed_run(base, plan: TimePlan, i: int) -> PlanetaryRun:
    """Speed ``i``'s own run: its N_s, periods and the kept ones (the integrated spectrum's)."""
    return PlanetaryRun(
        base.sun_torque, steps_per_period=int(plan.steps[i]), periods=int(plan.periods[i]),
        keep_periods=plan.keep, damping_ratio=base.damping_ratio,
        tangential_pin_errors=base.tangential_pin_errors,
        radial_pin_errors=base.radial_pin_errors, ring_cell_space=True,
    )


class SweepFactors(NamedTuple):
    """The factors of a run over speeds (:func:`sweep_factors`), from each speed's kept
    records.

    Attributes:
        dynamic_factor_mesh: (s, 2N) each mesh's largest transverse force over the kept
            periods over the nominal T_s / (N r_bs) (sun meshes, then ring meshes).
        k_gamma: (s,) the dynamic load sharing factor K_γ, peak-based: the largest planet
            path's peak sun-mesh force over the kept steps over the mean of the paths' peaks
            (:func:`~jaxgear.planetary.dynamic_load_sharing`).
        periodicity: (s,) max |F(last kept period) − F(the one before)| over the nominal force
            (NaN with one kept period).
        ring_deflection_max: (s,) the largest elastic ring displacement at a ring mesh (m; 0
            for a rigid ring).
        k_gamma_mean_load: (s,) the mean-load K_γ: the largest planet path's time-mean
            sun-mesh force over the kept steps over the mean of the paths' means.
    """

    dynamic_factor_mesh: np.ndarray
    k_gamma: np.ndarray
    periodicity: np.ndarray
    ring_deflection_max: np.ndarray
    k_gamma_mean_load: np.ndarray


def sweep_factors(records: SweepRecords, plan: TimePlan, n_planets: int) -> SweepFactors:
    """The dynamic factor of every mesh, K_γ (peak-based and mean-load:
    :func:`~jaxgear.planetary.dynamic_load_sharing`), the periodicity and the ring deflection
    at each speed of :func:`steps_sweep`'s ``records`` (its own last ``plan.keep`` mesh
    periods of ``plan.steps`` steps; :class:`SweepFactors`)."""
    n = n_planets
    fs = records.static_force
    n_s = len(records.forces)
    per_mesh, k_gamma, k_mean = np.zeros((n_s, 2 * n)), np.zeros(n_s), np.zeros(n_s)
    periodicity, deflection = np.full(n_s, np.nan), np.zeros(n_s)
    for k in range(n_s):  # each speed's own last `keep` mesh periods
        S = int(plan.steps[k])
        f = records.forces[k]
        per_mesh[k] = f.max(axis=0) / fs
        k_gamma[k], k_mean[k] = dynamic_load_sharing(f[:, :n])
        if plan.keep >= 2:
            periodicity[k] = np.max(np.abs(f[-S:] - f[-2 * S:-S])) / fs
        deflection[k] = np.max(np.abs(records.deflection[k]))
    return SweepFactors(per_mesh, k_gamma, periodicity, deflection, k_mean)


def holds_stage(model: AbstractPlanetaryModel, stage: PlanetaryStage,
                rel: float = HOLDS_3D) -> bool:
    """Whether the supports of ``stage`` hold every motion of ``model``'s coordinates: the
    smallest eigenvalue of its stiffness (:meth:`AbstractPlanetaryModel.stiffness_matrix`, the
    mean meshes') above ``rel`` times the largest. A member without an axial support screws
    freely along its helix in the 3D model (:class:`SpatialPlanetary`)."""
    lam = np.linalg.eigvalsh(np.asarray(model.stiffness_matrix(stage)))
    return bool(lam[0] > rel * lam[-1])


def planetary_model_for(stage: PlanetaryStage) -> AbstractPlanetaryModel:
    """The lumped model a stage's dynamics and load sharing take: the 3D model
    (:class:`SpatialPlanetary`: axial and tilting motions, a helical mesh's axial forces and
    moments) for a helical stage whose axial and tilting supports hold it
    (:func:`holds_stage`), else the planar one (:class:`PlanarPlanetary`). ``stage``: the stage
    as it is loaded (held where its reactions are taken)."""
    if float(stage.helix_angle) != 0.0:
        spatial = SpatialPlanetary()
        if holds_stage(spatial, stage):
            return spatial
    return PlanarPlanetary()


#: the lumped models every stage's analysis runs, by their case-file names, in report order
#: (:func:`lumped_mode_models` and :func:`lumped_sharing_models` add the 3D model where it applies)
LUMPED_MODELS = {"planar": PlanarPlanetary(), "torsional": TorsionalPlanetary()}


def lumped_mode_models(stage: PlanetaryStage) -> dict[str, AbstractPlanetaryModel]:
    """The lumped models whose modes a stage's analysis lists, by name (in this order):
    ``"planar"`` (:class:`PlanarPlanetary`), ``"torsional"`` (:class:`TorsionalPlanetary`) and,
    for a helical stage (``stage.helix_angle`` != 0), ``"spatial"`` (:class:`SpatialPlanetary`:
    the axial and tilting modes the planar model lacks). ``stage``: the stage as given (its
    modes need no support to hold it)."""
    models = dict(LUMPED_MODELS)
    if float(stage.helix_angle) != 0.0:
        models["spatial"] = SpatialPlanetary()
    return models


def lumped_sharing_models(stage: PlanetaryStage) -> dict[str, AbstractPlanetaryModel]:
    """The lumped models whose load sharing a stage's analysis solves, by name (in this order):
    ``"planar"``, ``"torsional"`` and ``"spatial"`` where :func:`planetary_model_for` takes the
    3D model (a helical stage whose axial and tilting supports hold it); the rating takes the
    3D model's K_γ where it is there, else the planar one's (:func:`rating_sharing_model`).
    ``stage``: the load-sharing stage (the sun loaded, the reacting members held)."""
    models = dict(LUMPED_MODELS)
    model = planetary_model_for(stage)
    if isinstance(model, SpatialPlanetary):
        models["spatial"] = model
    return models


def rating_sharing_model(models) -> str:
    """Of a stage's load-sharing models by name (:func:`lumped_sharing_models`' names, or any
    of them), the one whose K_γ, static mesh forces and quasi-static loads a rating takes: the
    3D model's, ``"spatial"``, where it is there (a helical stage on its axial and tilting
    supports: :func:`planetary_model_for`'s choice), else the planar model's, ``"planar"``.

    Raises:
        ValueError: ``models`` has neither (one line)."""
    for name in ("spatial", "planar"):
        if name in models:
            return name
    raise ValueError(f"rating_sharing_model: models = {list(models)}, allowed names that "
                     "include 'planar' or 'spatial'")


#: mesh travels over one turn of the ring relative to the carrier at which an eccentric
#: stage's load sharing is solved (:func:`sharing_over_turn`)
TURN_POSITIONS = 72


def turn_travel(stage: PlanetaryStage, positions: int = TURN_POSITIONS) -> np.ndarray:
    """The mesh travels x (m, (positions,)) of one turn of the ring relative to the carrier,
    equally spaced from 0 and the turn's end left out: x_i = 2π r_br i / positions (r_br the
    ring's base radius: x / r_br is the carrier's angle relative to the ring; one carrier turn
    when the ring is fixed, the sun turning z_r/z_s times relative to the carrier).

    Raises:
        ValueError: ``positions`` not an integer >= 1 (one line)."""
    check_integer("turn_travel: positions", positions, 1)
    r_r = float(stage.ring.base_radius)
    return np.arange(positions) * 2 * math.pi * r_r / positions


def constant_mesh_sharing(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    sun_torque,
    tangential_pin_errors,
    radial_pin_errors=0.0,
    travel=(0.0,),
) -> PlanetaryQuasiStatic:
    """A stage's load sharing with one unilateral spring per mesh at the mesh travels
    ``travel``: the quasi-static solve (:func:`planetary_quasi_static`) on
    :class:`ConstantMeshes` at the model's ``face_points`` Gauss points across the face (the
    stage's mesh stiffness; the 3D model's face load factor K_Hβ from the members' tilts and
    the helical axial forces), the eccentricities turning with their members.

    Args:
        model: the model kind; stage: the load-sharing stage (sun loaded, the reacting members
            held); sun_torque: the sun's torque (N m, > 0); tangential_pin_errors,
            radial_pin_errors: per planet (m), (n_planets,) or scalar; travel: mesh travels
            x (m), (p,).

    Raises:
        ValueError: what :func:`planetary_quasi_static` raises (one line)."""
    return planetary_quasi_static(model, stage, ConstantMeshes(face_points=model.face_points),
                                  np.asarray(sun_torque), np.asarray(travel),
                                  tangential_pin_errors, radial_pin_errors)


def sharing_over_turn(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    sun_torque,
    tangential_pin_errors,
    radial_pin_errors=0.0,
    positions: int = TURN_POSITIONS,
) -> PlanetaryQuasiStatic:
    """An eccentric stage's load sharing over one turn of the ring relative to the carrier:
    :func:`constant_mesh_sharing` at the travels of :func:`turn_travel`; K_γ at each travel is
    the result's ``k_gamma`` (p,). Arguments as :func:`constant_mesh_sharing`'s, ``positions``
    the travels over the turn.

    Raises:
        ValueError: what :func:`turn_travel` and :func:`planetary_quasi_static` raise (one
            line)."""
    return constant_mesh_sharing(model, stage, sun_torque, tangential_pin_errors,
                                 radial_pin_errors, turn_travel(stage, positions))


#: "no excitation": the meshes' stiffness varies over a mesh period by less than this relative
#: to its mean (round-off: the lumped form's constant springs) and no pin error moves a planet:
#: nothing excites the stage, its dynamic factors and K_γ are 1 (:func:`excitation`)
NO_EXCITATION_TOL = 1e-9
#: mesh travels per mesh period at which :func:`excitation` reads the meshes' stiffness
EXCITATION_POSITIONS = 16


def excitation(model, stage, meshes, run, flexible_ring: bool) -> dict:
    """Whether anything excites the sweep's stage: ``mesh_stiffness_variation`` (the largest
    (max − min)/mean of a mesh's stiffness over one mesh period, at
    :data:`EXCITATION_POSITIONS` travels, :meth:`~jaxgear.planetary.AbstractPlanetaryMeshes.mesh_stiffness`),
    ``pin_errors`` (any non-zero pin error of ``run``, a :class:`PlanetaryRun`),
    ``eccentricities`` (a member's or a planet's runout, :func:`eccentric`), ``flexible_ring``
    (a condensed ring: the planets pass its cells), ``te_offsets`` (meshes whose TE leaves
    material out: the deviations per tooth) and ``excited``: False where the variation is below
    :data:`NO_EXCITATION_TOL` (round-off) and none of the others is there, the lumped form's
    constant springs: the stage then answers its static load, every dynamic factor and K_γ is
    1 (``jaxgear run``'s ``sweep.json``'s ``excitation``, with its words)."""
    k_s, k_r = meshes.mesh_stiffness(model, stage, meshes.positions(EXCITATION_POSITIONS))
    k = np.concatenate([np.asarray(k_s), np.asarray(k_r)], axis=1)
    mean = np.abs(k.mean(axis=0))
    variation = float(np.max((k.max(axis=0) - k.min(axis=0)) / np.where(mean > 0, mean, 1.0)))
    pins = bool(np.any(np.asarray(run.tangential_pin_errors) != 0)
                or np.any(np.asarray(run.radial_pin_errors) != 0))
    others = {"eccentricities": eccentric(stage),  # turning once per turn
              "flexible_ring": bool(flexible_ring),  # the planets pass its cells
              "te_offsets": type(meshes).te_offsets is not AbstractPlanetaryMeshes.te_offsets}
    excited = pins or any(others.values()) or not variation < NO_EXCITATION_TOL
    return {
        "mesh_stiffness_variation": variation,
        "pin_errors": pins,
        **others,
        "excited": excited,
    }
