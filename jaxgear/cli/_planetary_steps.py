"""The time discretisation of a planetary sweep (:mod:`jaxgear.cli.planetary_sweep`) from the
stage's modes, with the pairs' rule and constants (docs/planetary.md, "Time step and span of a
sweep"; docs/dynamics.md, "Time step and accuracy"): the steps per mesh period at each speed,
the span from the damping's settling time, the kept periods, the check of the step against the
highest mode the meshes excite, and every speed run in one compiled program at its own step."""

from __future__ import annotations

import math
import os
import warnings
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from ..dynamics import (
    MAX_STEPS_PER_SPEED,
    SETTLE_TOL,
    SETTLED_TOL,
    UNDER_RESOLVED_STEPS,
    excited_omega,
    settling_time,
    steps_for_mode,
)
from ..planetary import AbstractPlanetaryMeshes, PlanetaryRun, planetary_dynamics
from ..io import CaseWarning

__all__ = [
    "EXCITATION_POSITIONS",
    "KEEP_OTHER",
    "KEEP_PERIODIC",
    "NO_EXCITATION_TOL",
    "SETTLED_TOL",
    "SETTLE_TOL",
    "STEPS_PER_TOP_PERIOD",
    "SweepRecords",
    "TimePlan",
    "carrier_periodic",
    "check_plan_size",
    "excitation",
    "speed_groups",
    "speed_run",
    "step_resolution",
    "steps_sweep",
    "time_plan",
]

#: the fewest Newmark steps per period of the highest mode the meshes excite below which a
#: sweep warns (:func:`step_resolution`): the pairs' ``under_resolved`` bound
#: (:data:`jaxgear.dynamics.UNDER_RESOLVED_STEPS`); the default step gives at least
#: :data:`jaxgear.dynamics.STEPS_PER_MODE` (:func:`time_plan`)
STEPS_PER_TOP_PERIOD = UNDER_RESOLVED_STEPS
#: SETTLE_TOL (the transient's amplitude left when the kept periods begin) and SETTLED_TOL (the
#: periodicity above which a speed is not settled): the pairs' and trains' rule,
#: :func:`jaxgear.dynamics.settling_time` (docs/dynamics.md, "Settled sweeps"); the run starts
#: from the quasi-static state, an error of about the dynamic part of the mesh force, so the
#: kept forces carry ~0.1 % of it (checked: the last kept period against the one before)
#: kept mesh periods of a stage whose steady state repeats every mesh period in the carrier
#: frame (:func:`carrier_periodic`): the last one against the one before is the settled check
KEEP_PERIODIC = 2
#: kept mesh periods otherwise (eccentricities, unbalances and a flexible ring turn relative to
#: the carrier: the forces repeat over a member's turn, not a mesh period)
KEEP_OTHER = 4

def carrier_periodic(stage, flexible_ring: bool) -> bool:
    """Whether the stage's steady state repeats every mesh period in the carrier frame: a
    rigid ring (not ``flexible_ring``: a condensed ring's stations turn relative to the
    carrier), no eccentricity or runout of any member and no unbalance (concrete values).
    Then the only time dependence left is each mesh's stiffness along its travel, periodic in
    the base pitch whatever the planets' angles and pin errors (constant offsets in that
    frame); the forces of one settled mesh period give any number of them
    (:func:`~jaxgear.cli.planetary_sweep.ring_spectrum`)."""
    if flexible_ring or stage.unbalances is not None:
        return False
    e = stage.eccentricities
    if e is None:
        return True
    return all(not np.any(np.asarray(a)) for a in (e.sun, e.ring, e.carrier, e.planet))


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
        pe = keep + np.ceil(settle * f_mesh).astype(int)
    else:
        pe = np.full(sp.shape, int(periods))
    return TimePlan(ns.astype(int), pe.astype(int), int(keep), w_max / (2 * math.pi),
                    w_min / (2 * math.pi), settle, (steps is None, periods is None))


def step_resolution(plan: TimePlan, f_mesh, n_planets: int) -> dict:
    """Whether the sweep's time step resolves the highest natural frequency the meshes excite
    (``plan.f_max_Hz``, :func:`time_plan`): at mesh frequency f_mesh (Hz, the swept speeds',
    (s,)) and ``plan.steps`` per mesh period, n = N_s f_mesh / f_max steps per period of
    f_max. Below :data:`STEPS_PER_TOP_PERIOD` (20, the pairs' bound) at some speed,
    Newmark's average acceleration (no numerical damping, period elongation) filters those
    modes (the impacts of teeth entering mesh) and the dynamic factor comes out low: one
    ``CaseWarning`` line naming ``--steps-per-period`` (a planetary case has no key for it),
    its value, f_max and the default step at the lowest speed (which resolves every speed).
    The default (no ``--steps-per-period``) gives n >= 40 at every speed.

    Returns ``sweep.json``'s ``steps_resolution``: ``f_max_Hz``, ``steps_per_top_period_min``
    (the least n over the speeds), ``resolved`` (bool), ``steps_per_period_resolved`` (the
    rule's N_s at the lowest speed), ``automatic`` (the rule's steps)."""
    f = np.asarray(f_mesh, dtype=float)
    n = plan.steps * f / plan.f_max_Hz
    i = int(np.argmin(f))
    need = int(steps_for_mode(2 * math.pi * plan.f_max_Hz, 1.0, f[i:i + 1], 1.0, n_planets)[0])
    n_min = float(np.min(n))
    resolved = bool(n_min >= STEPS_PER_TOP_PERIOD)
    if not resolved:
        warnings.warn(
            f"--steps-per-period = {int(plan.steps[0])}: time step under-resolved, n = "
            f"{n_min:.3g} steps per period of the highest natural frequency the meshes excite "
            f"{plan.f_max_Hz:.4g} Hz at the lowest speed's mesh frequency {f[i]:.4g} Hz "
            f"(< {STEPS_PER_TOP_PERIOD}: the dynamic factor comes out low); "
            f"--steps-per-period >= {need} resolves it (or leave it out: the default does)",
            CaseWarning, stacklevel=3)
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
    s = np.asarray(plan.steps).size
    periods, result = np.zeros(s), np.zeros(s, dtype=int)
    time, forces, deflection = [None] * s, [None] * s, [None] * s
    groups = speed_groups(plan, grouped)
    for idx in groups:
        run, r = _one_program(model, stage, meshes, base, plan, idx, np.asarray(carrier)[idx],
                              np.asarray(mesh_speed)[idx], ring)
        f = np.concatenate([np.asarray(r.sun_mesh_forces), np.asarray(r.ring_mesh_forces)], -1)
        t, w, code = np.asarray(r.time), np.asarray(r.ring_deflection), np.asarray(r.result)
        fs = float(np.asarray(r.static_force).reshape(-1)[0])
        for j, k in enumerate(idx):
            kept = slice(-plan.keep * int(plan.steps[k]), None)
            time[k], forces[k], deflection[k] = t[j, kept], f[j, kept], w[j, kept]
            periods[k] = run.periods * run.steps_per_period / plan.steps[k]
            result[k] = int(code[j])
    return SweepRecords(periods, time, forces, deflection, result, fs, len(groups))


def _one_program(model, stage, meshes, base, plan: TimePlan, idx, carrier, mesh_speed, ring):
    """(the run of the blocks, the :class:`~jaxgear.planetary.PlanetaryDynamics` with a leading
    speed axis) of the speeds ``idx`` in one compiled program (:func:`steps_sweep`)."""
    steps_i = np.asarray(plan.steps)[idx]
    block = int(steps_i.min())
    top = int(steps_i.max())
    settle = int(np.max((np.asarray(plan.periods)[idx] - plan.keep) * steps_i))
    keep_blocks = plan.keep * top // block
    run = PlanetaryRun(
        base.sun_torque, steps_per_period=block, periods=-(-settle // block) + keep_blocks,
        keep_periods=keep_blocks, damping_ratio=base.damping_ratio,
        tangential_pin_errors=base.tangential_pin_errors,
        radial_pin_errors=base.radial_pin_errors, ring_cell_space=True,
    )
    one = jax.vmap(lambda om, v, n_s: planetary_dynamics(
        model, stage, meshes, eqx.tree_at(lambda r: r.mesh_steps, run, n_s,
                                          is_leaf=lambda x: x is None), om, v, ring=ring))
    steps = jnp.asarray(steps_i, dtype=jnp.asarray(carrier).dtype)
    return run, one(jnp.asarray(carrier), jnp.asarray(mesh_speed), steps)


def _memory_bytes() -> float:
    """The machine's physical memory (bytes); inf where the platform does not tell."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return float("inf")


def check_plan_size(plan: TimePlan, speeds, groups, values: int, given: dict) -> None:
    """Refuse, before any integration, a sweep that cannot finish: the Newmark steps a speed
    takes in its program (:func:`steps_sweep`: the group's longest settling plus ``keep``
    periods of its largest N_s) above :data:`~jaxgear.dynamics.MAX_STEPS_PER_SPEED` (the
    pairs' bound), or the kept records of a program (``keep`` × its largest N_s steps × its
    speeds × ``values`` float64) above half the machine's memory. ``groups``:
    :func:`speed_groups`; ``given``: the command-line options given (``--periods`` ...: value,
    None where not given). One line naming the option (``--speeds`` where the steps and span
    are all the automatic rule's), its value and the allowed range."""
    name = next((k for k, v in given.items() if v is not None), None)
    blame = f"{name} = {given[name]}" if name else "--speeds (the automatic time plan)"
    sp = np.asarray(speeds, dtype=float)
    for idx in groups:
        steps = np.asarray(plan.steps)[idx]
        top = int(steps.max())
        settle = (np.asarray(plan.periods)[idx] - plan.keep) * steps
        total = int(settle.max()) + plan.keep * top
        if total > MAX_STEPS_PER_SPEED:
            k = idx[int(np.argmax(settle + plan.keep * steps))]
            raise ValueError(
                f"{blame}: out of range: {total:.3g} time steps per speed ({int(plan.periods[k])} "
                f"mesh periods of {int(plan.steps[k])} steps at {sp[k]:.6g} rad/s), allowed <= "
                f"{MAX_STEPS_PER_SPEED:.3g} (fewer --periods or --steps-per-period, or leave them "
                "out: the automatic plan)")
        need = 8.0 * plan.keep * top * len(idx) * values
        have = 0.5 * _memory_bytes()
        if need > have:
            raise ValueError(
                f"{blame}: out of range: the kept records of {len(idx)} speeds need about "
                f"{need / 1e9:.3g} GB, allowed <= {have / 1e9:.3g} GB (half this machine's "
                "memory): fewer --keep-periods, --steps-per-period or speeds")


def speed_run(base, plan: TimePlan, i: int) -> PlanetaryRun:
    """Speed ``i``'s own run: its N_s, periods and the kept ones (the integrated spectrum's)."""
    return PlanetaryRun(
        base.sun_torque, steps_per_period=int(plan.steps[i]), periods=int(plan.periods[i]),
        keep_periods=plan.keep, damping_ratio=base.damping_ratio,
        tangential_pin_errors=base.tangential_pin_errors,
        radial_pin_errors=base.radial_pin_errors, ring_cell_space=True,
    )


#: "no excitation": the meshes' stiffness varies over a mesh period by less than this relative
#: to its mean (round-off: the lumped form's constant springs) and no pin error moves a planet:
#: nothing excites the stage, its dynamic factors and K_γ are 1 (:func:`excitation`)
NO_EXCITATION_TOL = 1e-9
#: mesh travels per mesh period at which :func:`excitation` reads the meshes' stiffness
EXCITATION_POSITIONS = 16


def excitation(model, stage, meshes, spec) -> dict:
    """Whether anything excites the sweep's stage: ``mesh_stiffness_variation`` (the largest
    (max − min)/mean of a mesh's stiffness over one mesh period, at
    :data:`EXCITATION_POSITIONS` travels, :meth:`~jaxgear.planetary.AbstractPlanetaryMeshes.mesh_stiffness`),
    ``pin_errors`` (any non-zero pin error), ``eccentricities`` (a member's or a planet's
    runout), ``flexible_ring`` (a condensed ring: the planets pass its cells), ``te_offsets``
    (meshes whose TE leaves material out: the deviations per tooth) and ``excited``: False
    where the variation is below :data:`NO_EXCITATION_TOL` (round-off) and none of the others
    is there, the lumped form's constant springs: the stage then answers its static load, every dynamic factor and K_γ
    is 1 and ``words`` says so (``sweep.json``'s ``excitation``)."""
    k_s, k_r = meshes.mesh_stiffness(model, stage, meshes.positions(EXCITATION_POSITIONS))
    k = np.concatenate([np.asarray(k_s), np.asarray(k_r)], axis=1)
    mean = np.abs(k.mean(axis=0))
    variation = float(np.max((k.max(axis=0) - k.min(axis=0)) / np.where(mean > 0, mean, 1.0)))
    pins = bool(np.any(np.asarray(spec.tangential_pin_errors) != 0)
                or np.any(np.asarray(spec.radial_pin_errors) != 0))
    others = {"eccentricities": bool(spec.eccentric),  # turning once per turn
              "flexible_ring": bool(spec.ring_model.flexible),  # the planets pass its cells
              "te_offsets": type(meshes).te_offsets is not AbstractPlanetaryMeshes.te_offsets}
    excited = pins or any(others.values()) or not variation < NO_EXCITATION_TOL
    return {
        "mesh_stiffness_variation": variation,
        "pin_errors": pins,
        **others,
        "excited": excited,
        "words": None if excited else (
            "no excitation (constant mesh stiffness, no pin errors): dynamic factor = 1, "
            "K_γ = 1"),
    }
