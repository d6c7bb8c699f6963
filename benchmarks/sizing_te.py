"""How many transmission-error curves a second the sizing's TE stage computes: the batched
program of ``jaxgear.sizing.te_curves`` (the candidates' rigid meshes grouped by their static
layout, each group one ``jax.vmap`` over candidates of the library's torque sweep
``jaxgear._quasi_static.at_torques``) against a loop over the same candidates, one at a time
(the same sweep, one candidate per call), in one process so that the ratio holds under any load.
A curve is one candidate's quasi-static TE over one mesh period at one torque (exact contact,
the candidate mesh's 16 positions per pitch). Both are checked equal (rtol 1e-12).

Also timed: building the meshes (the Weber stiffness tables, NumPy, one candidate at a time)
and the whole stage (:func:`jaxgear.sizing.te_stage`: plain curves, the start grid, the
optimiser, the modified curves) per candidate, compile included and not. The batched and the
looped curves are timed interleaved (``REPEATS`` times each, the best of each kept). The
stage's optimiser batched (``te_stage(batched=True)``: :func:`optimise.minimise_batch`, the
candidates of one mesh layout in one vmapped solve) against one candidate at a time (the
default), on ``OPT_CANDIDATES`` candidates, interleaved ``STAGE_REPEATS`` times, the best of
each kept, their columns checked equal to the optimiser's rounding (1e-6 of each column's
largest value, the iterations exactly).

The candidates: the feasible ones of examples/sizing/helical.toml, best ranked first
(``CANDIDATES`` of them), at the spec's stage torques (25, 50, 75, 100 % of the rated torque).
Writes docs/bench/sizing_te.json (or the file given) with the machine, dtype and JAX version
(benchmarks/_timing.py's ``environment()``) and the load average. From the repository root:
``python -m benchmarks.sizing_te [FILE]``.
"""

from __future__ import annotations

import os
import pathlib
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np

import jaxgear.io as jio
import jaxgear.sizing as js
from benchmarks._timing import environment, write_record

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_te.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
CANDIDATES = 32
STAGE_CANDIDATES = 4
OPT_CANDIDATES = 8
REPEATS = 7
STAGE_REPEATS = 3


def _best(fn, repeats):
    runs = []
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        runs.append(time.perf_counter() - t)
    return min(runs), out


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    spec, tables = jio.load_sizing_spec(str(SPEC))
    settings = jio.sizing_te_settings(tables)
    table = js.size(spec)
    chosen = table.ranked()[:CANDIDATES]
    rows = [{k: v[i] for k, v in table.columns.items()} for i in chosen]
    t = time.perf_counter()
    meshes = [js.candidate_mesh(spec, js.candidate_pair(spec, r)) for r in rows]
    mesh_s = time.perf_counter() - t
    layouts = {(m.n_lines, m.first_line) for m in meshes}
    torques = float(spec.operating.torque) * np.asarray(settings.torque_fractions)
    n, curves = len(meshes), len(meshes) * torques.size

    t = time.perf_counter()
    js.te_curves(meshes, None, torques)
    batched_first = time.perf_counter() - t
    t = time.perf_counter()
    js.te_curves(meshes, None, torques, batched=False)
    loop_first = time.perf_counter() - t
    # interleaved, the best of each: the machine's load moves both alike
    b_runs, l_runs = [], []
    for _ in range(REPEATS):
        b, out_b = _best(lambda: js.te_curves(meshes, None, torques), 1)
        b_runs.append(b)
        b, out_l = _best(lambda: js.te_curves(meshes, None, torques, batched=False), 1)
        l_runs.append(b)
    batched, loop = min(b_runs), min(l_runs)
    agree = bool(np.allclose(out_b, out_l, rtol=1e-12, atol=1e-20))

    stage_settings = js.TeSettings(STAGE_CANDIDATES, settings.torque_fractions,
                                   settings.max_iterations)
    t = time.perf_counter()
    js.te_stage(spec, table, stage_settings)
    stage_first = time.perf_counter() - t
    t = time.perf_counter()
    staged = js.te_stage(spec, table, stage_settings)
    stage = time.perf_counter() - t
    c = staged.columns
    done = np.flatnonzero(c["stage"] == "te")

    opt_settings = js.TeSettings(OPT_CANDIDATES, settings.torque_fractions,
                                 settings.max_iterations)
    firsts, runs, outs = {}, {"one": [], "batched": []}, {}
    for name, b in (("one", False), ("batched", True)):
        t = time.perf_counter()
        outs[name] = js.te_stage(spec, table, opt_settings, batched=b)
        firsts[name] = time.perf_counter() - t
    for _ in range(STAGE_REPEATS):
        for name, b in (("one", False), ("batched", True)):
            s_, outs[name] = _best(lambda b=b: js.te_stage(spec, table, opt_settings,
                                                           batched=b), 1)
            runs[name].append(s_)
    keys = ("te_ppk_modified_m", "tip_relief_depth_m", "tip_relief_extent", "crowning_depth_m",
            "te_iterations")
    # equal to the optimiser's rounding: 1e-6 of each column's largest value (a depth near its
    # lower bound 0 differs by far more than 1e-6 of itself), the iterations exactly
    differences = {k: float(np.nanmax(np.abs(outs["one"].columns[k] - outs["batched"].columns[k]))
                            / np.nanmax(np.abs(outs["one"].columns[k]))) for k in keys}
    opt_equal = all(v <= 1e-6 for v in differences.values()) and differences["te_iterations"] == 0
    opt_layouts = len({(m.n_lines, m.first_line) for m in meshes[:OPT_CANDIDATES]})
    stage_curves = 2 * OPT_CANDIDATES * torques.size  # plain and modified, each torque
    record = {
        "what": "the sizing's transmission-error stage: TE curves per second, jaxgear.sizing."
                "te_curves' vmap over candidates (grouped by mesh layout) against a loop over "
                "the same candidates, one call each; the whole stage per candidate",
        "machine": machine,
        "spec": "examples/sizing/helical.toml, its best feasible candidates (ranked: lightest "
                "first), the stage's torques",
        "candidates": n,
        "layouts": len(layouts),
        "torques_Nm": torques.tolist(),
        "curve": "one candidate's quasi-static TE over one mesh period at one torque: exact "
                 "contact, contact beyond the path, 20 slices, 16 positions per pitch",
        "meshes_s": round(mesh_s, 3),
        "batched": {"first_call_s": round(batched_first, 3), "best_s": round(batched, 4),
                    "curves_per_s": round(curves / batched, 1)},
        "loop": {"first_call_s": round(loop_first, 3), "best_s": round(loop, 4),
                 "curves_per_s": round(curves / loop, 1),
                 "equal_to_batched_rtol_1e-12": agree},
        "speed_ratio": round(loop / batched, 2),
        "runs_s": {"batched": [round(v, 4) for v in b_runs],
                   "loop": [round(v, 4) for v in l_runs]},
        "stage": {"candidates": STAGE_CANDIDATES, "max_iterations": settings.max_iterations,
                  "first_s": round(stage_first, 2), "second_s": round(stage, 2),
                  "per_candidate_s": round(stage / STAGE_CANDIDATES, 3),
                  "te_ppk_um": (c["te_ppk_m"][done] * 1e6).round(4).tolist(),
                  "te_ppk_modified_um": (c["te_ppk_modified_m"][done] * 1e6).round(4).tolist()},
        "stage_optimiser": {
            "what": "te_stage over OPT_CANDIDATES candidates, the optimiser batched per mesh "
                    "layout (optimise.minimise_batch, padded to a power of two) against one "
                    "candidate at a time (the default); curves: plain and modified at each torque",
            "candidates": OPT_CANDIDATES, "layouts": opt_layouts,
            "one": {"first_s": round(firsts["one"], 2), "best_s": round(min(runs["one"]), 3),
                    "curves_per_s": round(stage_curves / min(runs["one"]), 2)},
            "batched": {"first_s": round(firsts["batched"], 2),
                        "best_s": round(min(runs["batched"]), 3),
                        "curves_per_s": round(stage_curves / min(runs["batched"]), 2)},
            "speed_ratio_batched_to_one": round(min(runs["one"]) / min(runs["batched"]), 2),
            "equal_to_1e-6_of_each_columns_largest": opt_equal,
            "largest_difference_over_columns_largest": differences,
            "iterations": outs["one"].columns["te_iterations"][
                np.isfinite(outs["one"].columns["te_iterations"])].astype(int).tolist(),
            "runs_s": {k: [round(v, 3) for v in r] for k, r in runs.items()},
        },
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
