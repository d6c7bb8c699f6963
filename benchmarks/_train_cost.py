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

A long span (``span`` in the JSON): the embedded ``two-stage`` case (lumped 3D; its second mesh's
period is 127/35 of the first's, so the meshes repeat together after 127 first-mesh periods) at
one speed, ``steps_per_period`` a multiple of 35, the table of each mesh's own period (rows
N_s and N_s × 127/35) against the long table of the span (127 N_s rows, every mesh at every
step, as before the own-period tables), in one run: the table's rows and bytes, the time to
build the table (``jaxgear.dynamics.mesh_table``) and to simulate one speed on it
(``jaxgear.dynamics.simulate_on_table``: the table, the static rows over the span and the
Newmark run; first call and best of repeats), and the ratios long / own. The static rows (the
quasi-static reference at each of the span's 127 N_s steps) are solved on the structure
condensed onto the coordinates the cells reach; ``own_full`` solves them on every coordinate
(``condensed=False``, as before), on the own-period table: ``ratios_full_over_condensed``.
The span section can run alone on an idle machine, replacing ``span`` in a written JSON:
``python -c "from benchmarks._train_cost import bench_span_only; bench_span_only('docs/bench')"``.
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
from jaxgear.io import atomic_open, build_dynamic_model, load_case
from jaxgear.scenes import (
    Bearing,
    ShaftSpec,
    TrainSpec,
    disc_inertia,
    grounded,
    lumped_train,
    torsional_train,
    train_layout,
)

from ._timing import environment, first_call, min_time

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
    planes = [jg.MeshModel.from_pair(p, *jg.stiffness_table(p, jg.Weber()), slices) for p in pairs]
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
            TrainSpec(
                meshes,
                layout,
                (SHAFT,) * n,
                tuple(range(n)),
                masses=masses,
                inertias=[
                    (j / 2 + m * FACE**2 / 12, j) for m, j in zip(masses, inertias, strict=True)
                ],
            )
        )
    held = grounded(train, (train.torque_dofs[1],), factor=1e9)
    cells = sum(p.n_lines * p.n_slices for p in planes)
    return train, held, cells


def bench_span(quick: bool = False) -> dict:
    """The long span of the embedded ``two-stage`` case: the own-period table against the long
    table of the span at one speed (see the module docstring). Returns the JSON's ``span``."""
    slices, steps, repeats = (4, 35, 1) if quick else (8, 140, 2)
    case = load_case("two-stage")
    model, _ = build_dynamic_model(case, slices=slices)
    q = case.span_periods
    window = jd.SteadyState(q + 1, q)
    speed = jnp.asarray(0.5 * float(model.modes.omega[1]) / case.pairs[0].pinion.teeth)
    out = {
        "case": "two-stage",
        "model": "lumped3d",
        "dofs": int(model.scene.structure.size),
        "slices": slices,
        "steps_per_period": steps,
        "span_periods": q,
        "periods": int(window.periods),
        "keep_periods": int(window.keep_periods),
        "speed_rad_s": float(speed),
        "repeats": repeats,
        "what": "table: jaxgear.dynamics.mesh_table (cells, δ0, structure vectors) alone; "
        "simulate: jaxgear.dynamics.simulate_on_table at one speed, the table, the static rows "
        "over the span and the Newmark run together; first call and best of the repeats",
    }
    for name, own, condensed in (
        ("long", False, True),
        ("own", True, True),
        ("own_full", True, False),
    ):

        def table(own=own):
            return jd.mesh_table(model.scene, model.mods, steps, q, own_periods=own)

        def simulate(own=own, condensed=condensed):
            return jd.simulate_on_table(
                model, speed, steps, window, own_periods=own, condensed=condensed
            )[0]

        t_first = first_call(table)
        t_table = min_time(table, repeats, warmup=False)
        tab = table()
        s_first = first_call(simulate)
        t_sim = min_time(simulate, repeats, warmup=False)
        out[name] = {
            "static_rows": "condensed" if condensed else "every coordinate",
            "load_average": list(os.getloadavg()),
            "rows": [int(r) for r in tab.rows],
            "table_rows": int(tab.theta.shape[0]),
            "table_bytes": int(sum(x.nbytes for x in jax.tree.leaves(tab))),
            "table_first_s": t_first,
            "table_s": t_table,
            "simulate_first_s": s_first,
            "simulate_s": t_sim,
            "dynamic_factor_mesh": [float(m.dynamic_factor) for m in simulate().meshes],
        }
    long, own = out["long"], out["own"]
    out["ratios_long_over_own"] = {
        k: long[k] / own[k]
        for k in (
            "table_rows",
            "table_bytes",
            "table_first_s",
            "table_s",
            "simulate_first_s",
            "simulate_s",
        )
    }
    out["dynamic_factor_rel_diff"] = max(
        abs(a / b - 1) for a, b in zip(own["dynamic_factor_mesh"], long["dynamic_factor_mesh"])
    )
    full = out["own_full"]
    out["ratios_full_over_condensed"] = {
        k: full[k] / own[k] for k in ("simulate_first_s", "simulate_s")
    }
    out["dynamic_factor_rel_diff_condensed"] = max(
        abs(a / b - 1) for a, b in zip(own["dynamic_factor_mesh"], full["dynamic_factor_mesh"])
    )
    return out


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
    bar = tqdm(total=3 * len(MODELS) + 1, desc="jaxgear bench trains", unit="chain")
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
    bar.set_postfix_str("two-stage span: own-period and long tables")
    span = bench_span(quick)
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
        "span": span,
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
    _print_span(span)
    return out


def _print_span(span: dict) -> None:
    for name in ("long", "own", "own_full"):
        t = span[name]
        print(
            f"two-stage span, {name} table ({t['static_rows']} static rows): {t['table_rows']} "
            f"rows ({t['table_bytes'] / 1e6:.1f} MB), table {t['table_first_s']:.2f} s first / "
            f"{t['table_s']:.2f} s, simulate {t['simulate_first_s']:.2f} s first / "
            f"{t['simulate_s']:.2f} s (load {t['load_average'][0]:.1f})"
        )
    print(f"long / own: {span['ratios_long_over_own']}")
    print(f"static rows on every coordinate / condensed: {span['ratios_full_over_condensed']}")


def bench_span_only(out_dir: str, *, quick: bool = False) -> dict:
    """Re-run the span section alone and replace ``span`` in ``out_dir``'s existing
    ``bench_trains.json`` (written by :func:`bench_trains`). Returns the JSON's ``span``."""
    jax.config.update("jax_enable_x64", True)
    path = os.path.join(out_dir, "bench_trains.json")
    with open(path, encoding="utf-8") as f:
        out = json.load(f)
    span = bench_span(quick)
    span["machine"] = environment()
    out["span"] = span
    with atomic_open(path, "w") as f:
        json.dump(out, f, indent=2)
    _print_span(span)
    return span


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
