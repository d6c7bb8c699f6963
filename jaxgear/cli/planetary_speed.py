"""``jaxgear run`` on a planetary stage with ``[rating]``: after the first-look sweep and the
stage's files (:func:`jaxgear.cli.planetary_sweep.planetary_run_files`), the tooth-root stress
at speed: the sweep's dynamic model run once more at the operating input speed with its cells'
forces recorded (:class:`jaxgear.planetary.PlanetaryRun` ``cell_loads=True``), the most loaded
planet's meshes mapped with the FE fillet tables of the quasi-static map, beside the stage's
quasi-static solve at the same slices and travels (docs/rating.md, "Root stress at speed"):
``rating.root_stress.at_speed`` per mesh, two rows per mesh in ``rating.md`` and
``root_stress_map_<mesh>_speed.png``.
"""

from __future__ import annotations

import os

import numpy as np

from ..dynamics import Newmark, Outputs, SteadyState, simulate
from ..io import build_dynamic_model, write_json
from ._planetary_rating import (
    STAGE_AT_SPEED,
    MeshLoads,
    StageAtSpeed,
    StageLoads,
    rating_at_speed,
    stage_at_speed,
)

from ._stress_outputs import fillet_table
from .planetary import sharing_models
from .planetary_sweep import (
    _plan,
    model_words,
    planetary_run,
    planetary_run_files,
)

__all__ = [
    "STAGE_AT_SPEED",
    "MeshLoads",
    "StageAtSpeed",
    "StageLoads",
    "planetary_rated_run_files",
    "rating_at_speed",
    "run_at_speed",
    "stage_at_speed",
]


def run_at_speed(form, case, speed: float, steps_per_period: int | None = None,
                 periods: int | None = None, keep_periods: int | None = None,
                 slices: int | None = None) -> StageAtSpeed:
    """The stage's cell loads at the input speed ``speed`` (rad/s, fixed frame, as the case's
    ``[operating] speed_rad_s``): the planetary sweep's dynamic stage, meshes, model and ring
    (:func:`jaxgear.cli.planetary_sweep.sweep_summary`'s: ``slices`` None: 1 for spur gears,
    else the case's) and the sweep's run at that speed (the options given, None: the sweep's
    rule, :func:`jaxgear.cli.planetary_sweep.sweep_time_plan`) with ``cell_loads=True``, at
    the carrier speed and mesh speed of ``speed`` (Willis), then :func:`stage_at_speed` (the
    quasi-static solve beside it with the same ring: a flexible ring's static condensed
    ring)."""
    spec = form.spec
    planetary_run(form, case, steps_per_period, periods, keep_periods)  # the options' checks
    model, _ = build_dynamic_model(case, slices=slices)
    plan = _plan(spec, model, np.array([float(speed)]), (steps_per_period, periods, keep_periods))
    window = SteadyState(int(plan.periods[0]), plan.keep)
    dyn = simulate(model, float(speed), integrator=Newmark(int(plan.steps[0])), window=window,
                   outputs=Outputs(cell_loads=True))
    meshes = model.meshes
    full = spec.stage(case)
    words = {"model": model_words(model.mounted_kind), "ring": spec.ring_model.words(),
             "periods": window.periods, "keep": window.keep_periods, "speed": float(speed)}
    return stage_at_speed(case, spec, full, sharing_models(spec, full, case), dyn, meshes, words,
                          spec.ring_model.ring())


def planetary_rated_run_files(form, case, out: str, args, complete: bool,
                              table=fillet_table) -> dict:
    """``jaxgear run`` on a planetary case (:func:`jaxgear.cli.planetary_sweep.
    planetary_run_files`), then, where the stage's rating has its quasi-static root-stress
    map, the root stress at speed at the operating input speed (:func:`run_at_speed` with the
    sweep's time step and span at that speed, :func:`rating_at_speed`): ``summary.json`` and ``rating.md``
    rewritten. ``table``: the FE fillet stress per unit load (:func:`jaxgear.cli.fillet_table`)."""
    summary = planetary_run_files(form, case, out, args, complete)
    rating = summary.get("rating")
    if rating is None or rating.get("root_stress") is None:
        return summary
    at = run_at_speed(form, case, case.speed)
    summary["rating"] = rating_at_speed(case, out, rating, at, table)
    write_json(os.path.join(out, "summary.json"), summary)
    return summary
