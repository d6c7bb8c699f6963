"""``jaxgear bench trains``: the model's cost against the number of meshes of a gear train.

Chains of external spur gears of one tooth system (m = 2 mm, 20°, b = 15 mm): one mesh (23-37),
two (23-37-29) and three (23-37-29-41), each gear driving the next, solid-disc inertias, as two
models: the torsional train of one rotation per gear, and the lumped 3D train of each gear on a
shaft of its own (60 mm, ø 30 mm, 4 elements, two bearings of 200 N/µm, 6 DOFs per node), the
meshes at 60° from one another. Measured in one run, per chain and model: the public quasi-static
call per position (the output held; min of 30 calls) and the Newmark step of one speed (compiled
once; the difference of runs of 20 and 60 periods over the 40 periods' steps, so that the static
start and the records, a fixed cost per call, drop out), and their ratios to the one-mesh
chain. There is no baseline: the figure is how the one
contact solver and the one Newmark loop scale with the cells of several meshes.
"""

from __future__ import annotations

import json
import math
import os

import jax
import jax.numpy as jnp
from tqdm.auto import tqdm

import jaxgear as jg
import jaxgear.dynamics as jd
from jaxgear.io import atomic_open
from jaxgear.scenes import (
    Bearing,
    ShaftSpec,
    disc_inertia,
    grounded,
    lumped_train,
    torsional_train,
    train_layout,
)

from ._timing import environment, min_time

__all__ = ["bench_trains", "train_cost_chart"]

TEETH = (23, 37, 29, 41)
MODULE, ALPHA, FACE, TORQUE = 2e-3, math.radians(20.0), 15e-3, 120.0


MODELS = ("torsional", "lumped3d")
SHAFT = ShaftSpec(0.06, 0.03, 0.03, (Bearing(0.0, 2e8, 1e8), Bearing(0.06, 2e8, 0.0)))


def _chain(n_meshes: int, slices: int, model: str = "torsional"):
    """The chain of ``n_meshes`` meshes, torsional or lumped 3D: (train, its held static scene,
    cells)."""
    teeth = TEETH[: n_meshes + 1]
    pairs = [
        jg.GearPair(jg.Member(a, face_width=FACE), jg.Member(b, face_width=FACE), MODULE, ALPHA)
        for a, b in zip(teeth[:-1], teeth[1:], strict=True)
    ]
    planes = [jg.MeshModel.from_pair(p, *jg.stiffness_table(p, "weber"), slices) for p in pairs]
    radii = [pairs[0].tip_radii[0], *(p.tip_radii[1] for p in pairs)]
    inertias = [disc_inertia(7800.0, r, FACE) for r in radii]
    meshes = tuple((plane, (k, k + 1)) for k, plane in enumerate(planes))
    if model == "torsional":
        train = torsional_train(meshes, inertias)
    else:
        links = [(k, k + 1) for k in range(n_meshes)]
        n = n_meshes + 1
        layout = train_layout(pairs, links, [math.radians(60.0 * k) for k in range(n_meshes)], n)
        masses = [7800.0 * math.pi * r * r * FACE for r in radii]
        train = lumped_train(
            meshes,
            layout,
            (SHAFT,) * n,
            tuple(range(n)),
            masses=masses,
            inertias=[(j / 2 + m * FACE**2 / 12, j) for m, j in zip(masses, inertias, strict=True)],
        )
    held = grounded(train, (train.torque_dofs[1],), factor=1e9)
    cells = sum(p.n_lines * p.n_slices for p in planes)
    return train, held, cells


def bench_trains(out_dir: str, *, quick: bool = False) -> dict:
    """Time the quasi-static position and the Newmark step against 1, 2, 3 meshes; write
    ``bench_trains.json`` and ``bench_trains.png`` to ``out_dir``. Returns the JSON dict."""
    jax.config.update("jax_enable_x64", True)  # accuracy work: float64, as the CLI sets it
    os.makedirs(out_dir, exist_ok=True)
    slices = 4 if quick else 8
    positions = 16 if quick else 64
    # the step's cost is the difference of two runs (the static start and the records are a
    # fixed cost per call); one quasi-static call is short: many repeats
    steps, periods = (32, (4, 8)) if quick else (64, (20, 60))
    repeats = 2 if quick else 5
    qs_repeats = 3 if quick else 30
    rows = []
    bar = tqdm(total=3 * len(MODELS), desc="jaxgear bench trains", unit="chain")
    for kind, n in ((kind, n) for kind in MODELS for n in (1, 2, 3)):
        bar.set_postfix_str(f"{kind}, {n} mesh{'es' if n > 1 else ''}: model")
        train, held, cells = _chain(n, slices, kind)
        mods = jg.Modifications()

        def solve(held=held, mods=mods):
            return jg.quasi_static(held, mods, TORQUE, positions_per_pitch=positions).x

        bar.set_postfix_str(f"{kind}, {n} mesh{'es' if n > 1 else ''}: quasi-static")
        t_qs = min_time(solve, qs_repeats)
        model = jd.dynamic_model(train, mods, TORQUE)
        speed = 0.5 * float(model.modes.omega[1]) / TEETH[0]
        bar.set_postfix_str(f"{kind}, {n} mesh{'es' if n > 1 else ''}: Newmark")
        t_runs = []
        for p in periods:
            kw = {"integrator": jd.Newmark(steps), "window": jd.SteadyState(p, 2)}

            def run(model=model, speed=speed, kw=kw):
                return jd.simulate(model, jnp.asarray(speed), **kw).meshes[0].mesh_force

            t_runs.append(min_time(run, repeats))
        t_step = (t_runs[1] - t_runs[0]) / (steps * (periods[1] - periods[0]))
        rows.append(
            {
                "model": kind,
                "dofs": int(train.structure.size),
                "meshes": n,
                "gears": n + 1,
                "cells": int(cells),
                "quasi_static_per_position_s": t_qs / positions,
                "newmark_per_step_s": t_step,
                "newmark_call_s": t_runs,
            }
        )
        bar.update()
    bar.close()
    for r in rows:  # ratios to the one-mesh chain of the same model
        first = next(q for q in rows if q["model"] == r["model"] and q["meshes"] == 1)
        r["quasi_static_ratio"] = (
            r["quasi_static_per_position_s"] / first["quasi_static_per_position_s"]
        )
        r["newmark_ratio"] = r["newmark_per_step_s"] / first["newmark_per_step_s"]
    out = {
        "benchmark": "trains",
        "quick": bool(quick),
        "settings": {
            "teeth": list(TEETH),
            "slices": slices,
            "positions_per_pitch": positions,
            "steps_per_period": steps,
            "periods": list(periods),
            "repeats": repeats,
            "quasi_static_repeats": qs_repeats,
            "timing": "min over repeats after a warm-up call, block_until_ready; the Newmark "
            "step from the difference of the runs of the two period counts",
        },
        "rows": rows,
        "environment": environment(),
    }
    with atomic_open(os.path.join(out_dir, "bench_trains.json"), "w") as f:
        json.dump(out, f, indent=2)
    train_cost_chart(out, os.path.join(out_dir, "bench_trains.png"))
    for r in rows:
        print(
            f"{r['model']}, {r['meshes']} mesh(es), {r['dofs']} DOFs, {r['cells']} cells: "
            "quasi-static "
            f"{r['quasi_static_per_position_s'] * 1e6:.1f} µs/position (× {r['quasi_static_ratio']:.2f}), "
            f"Newmark {r['newmark_per_step_s'] * 1e6:.2f} µs/step (× {r['newmark_ratio']:.2f})"
        )
    return out


def train_cost_chart(result: dict, path: str) -> None:
    """Cost per quasi-static position and per Newmark step against the number of meshes, one
    line per model and quantity."""
    from jaxgear.cli import plots

    fig, ax = plots.new_figure()
    for kind, style in zip(MODELS, ("-", "--"), strict=True):
        rows = [r for r in result["rows"] if r.get("model", "torsional") == kind]
        if not rows:
            continue
        n = [r["meshes"] for r in rows]
        for key, ratio, marker, what, dy in (
            (
                "quasi_static_per_position_s",
                "quasi_static_ratio",
                "o",
                "quasi-static, per position",
                -10,
            ),
            ("newmark_per_step_s", "newmark_ratio", "s", "Newmark, per time step", 4),
        ):
            ys = [r[key] * 1e6 for r in rows]
            (line,) = ax.plot(n, ys, marker + style, label=f"{kind}: {what}")
            for r, y in zip(rows, ys, strict=True):
                ax.annotate(
                    f"× {r[ratio]:.2f}",
                    (r["meshes"], y),
                    xytext=(6, dy),
                    textcoords="offset points",
                    fontsize=8,
                    color=line.get_color(),
                )
    env = result["environment"]
    ax.set_yscale("log")  # torsional (µs) and lumped 3D (a hundred µs) on one chart
    ax.set_xticks([1, 2, 3])
    ax.set_xlabel("meshes of the chain (23-37, 23-37-29, 23-37-29-41)")
    ax.set_ylabel("wall time (µs, log scale)")
    ax.set_title(
        f"cost against the number of meshes ({env['platform']}, {env['dtype']}, JAX {env['jax']})",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    plots.savefig(fig, path)
