"""The cost of one carrier-frame Newmark step of a planetary stage, shared by the
``planetary_step`` and ``planetary_spatial_step`` benchmarks.

Method: two runs of ``p1`` and ``p2`` mesh periods, each called once first (compilation), then
the fastest of ``repeats`` calls (wall and process CPU time, each ended by
``jax.block_until_ready``); the step cost is the difference of the two times over the difference
of their step counts, so that compilation and the fixed costs of a call drop out.
"""

from __future__ import annotations

import time

import jax
import jax.numpy as jnp

import jaxgear.planetary as jp

__all__ = ["step_cost", "timed"]


def timed(fn) -> tuple[float, float]:
    """(wall s, process CPU s) of one call of ``fn()``, its result blocked on."""
    t0, c0 = time.perf_counter(), time.process_time()
    jax.block_until_ready(fn())
    return time.perf_counter() - t0, time.process_time() - c0


def step_cost(model, stage, meshes, omega, torque: float, steps_per_period: int,
              periods: tuple[int, int], repeats: int = 3) -> dict:
    """The Newmark step cost of ``jaxgear.planetary.planetary_dynamics(model, stage, meshes,
    run, omega)`` with ``run = PlanetaryRun(torque, steps_per_period, periods=p,
    keep_periods=1)`` for p in ``periods`` = (p1, p2), p2 > p1 (module docstring).

    Returns:
        {"coordinates", "cells" (the contact cells of all meshes), "step_wall_us",
        "step_cpu_us" (µs a step), "first_call_wall_s", "first_call_cpu_s" (the compiling
        call of the p1 run)}.
    """
    p1, p2 = periods
    runs = {p: jp.PlanetaryRun(torque, steps_per_period=steps_per_period, periods=p,
                               keep_periods=1) for p in (p1, p2)}
    first = {p: timed(lambda r=r: jp.planetary_dynamics(model, stage, meshes, r, omega))
             for p, r in runs.items()}
    best = {p: min(timed(lambda r=r: jp.planetary_dynamics(model, stage, meshes, r, omega))
                   for _ in range(repeats)) for p, r in runs.items()}
    steps = (p2 - p1) * steps_per_period
    n = stage.n_planets
    row = meshes.cell_row(model, stage, jnp.asarray(0.0), (jnp.zeros(n), jnp.zeros(n)))
    return {
        "coordinates": int(model.mass_matrix(stage).shape[0]),
        "cells": int(row.k.shape[0]),
        "step_wall_us": (best[p2][0] - best[p1][0]) / steps * 1e6,
        "step_cpu_us": (best[p2][1] - best[p1][1]) / steps * 1e6,
        "first_call_wall_s": first[p1][0],
        "first_call_cpu_s": first[p1][1],
    }
