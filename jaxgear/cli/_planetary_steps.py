"""The command line's side of a planetary sweep's time plan (the plan itself is the model's:
:mod:`jaxgear.planetary`, :func:`~jaxgear.planetary.plan_sweep`): a plan that cannot run
refused naming the option, and the warning of an under-resolved step naming
``--steps-per-period``."""

from __future__ import annotations

import warnings

import numpy as np

from fem_prep.resources import check_memory

from ..dynamics import MAX_STEPS_PER_SPEED
from ..io import CaseWarning
from ..planetary import STEPS_PER_TOP_PERIOD, TimePlan, step_resolution

__all__ = ["check_plan_size", "resolution_checked"]


def resolution_checked(plan: TimePlan, f_mesh, n_planets: int) -> dict:
    """:func:`jaxgear.planetary.step_resolution` (``sweep.json``'s ``steps_resolution``), with
    one ``CaseWarning`` line where the step does not resolve the highest natural frequency the
    meshes excite at some speed (fewer than :data:`~jaxgear.planetary.STEPS_PER_TOP_PERIOD`
    steps per its period): naming ``--steps-per-period`` (a planetary case has no key for it),
    its value, f_max and the rule's step at the lowest speed (which resolves every speed)."""
    r = step_resolution(plan, f_mesh, n_planets)
    if not r["resolved"]:
        f = np.asarray(f_mesh, dtype=float)
        i = int(np.argmin(f))
        warnings.warn(
            f"--steps-per-period = {int(plan.steps[0])}: time step under-resolved, n = "
            f"{r['steps_per_top_period_min']:.3g} steps per period of the highest natural "
            f"frequency the meshes excite {plan.f_max_Hz:.4g} Hz at the lowest speed's mesh "
            f"frequency {f[i]:.4g} Hz (< {STEPS_PER_TOP_PERIOD}: the dynamic factor comes out "
            f"low); --steps-per-period >= {r['steps_per_period_resolved']} resolves it (or "
            "leave it out: the default does)",
            CaseWarning, stacklevel=3)
    return r


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
        check_memory(blame, 8.0 * plan.keep * top * len(idx) * values,
                     f"the kept records of {len(idx)} speeds",
                     "fewer --keep-periods, --steps-per-period or speeds")
