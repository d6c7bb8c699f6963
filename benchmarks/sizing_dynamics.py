"""The sizing's dynamics stage on the example spec's front: what it costs and the design rule it
shows. ``jaxgear.sizing.dynamics_stage`` runs ``CANDIDATES`` candidates of the first Pareto
fronts of examples/sizing/helical.toml (its objectives: mass, mesh loss, margin) over the
default speed range (40 speeds through every candidate's mesh resonance, the spec's speed
added): each candidate's lumped torsional model swept until each speed settles
(``jaxgear.dynamics.settled_sweep``) and its whine by the harmonic balance
(``jaxgear.dynamics.whine_response``).

Timed: the stage's first call (the programs of each mesh layout compiled) and a second call
of ``AGAIN`` of its candidates (compiled); for one candidate, the time-domain sweep and the
harmonic balance over the same speeds, interleaved ``REPEATS`` times (the best of each): the
ratio of the two ways to a speed's response, which holds under any load.

The design rule: the whine (the dynamic mesh force's RMS over the mesh orders 1-3, the
largest over the range) and the largest K_v against how far the overlap ratio ε_β lies from a
whole number (a helical mesh's stiffness varies least there), as Spearman rank correlations
over the candidates, and the figure docs/bench/sizing_dynamics.png (both against ε_β, the
whole numbers dashed).

Writes docs/bench/sizing_dynamics.json (or the file given; the figure beside it, same stem)
with the machine, dtype and JAX version (benchmarks/_timing.py's ``environment()``) and the
load average. From the repository root: ``python -m benchmarks.sizing_dynamics [FILE]``.
"""

from __future__ import annotations

import math
import os
import pathlib
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np
from scipy.stats import spearmanr

import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.sizing as js
from benchmarks._timing import environment, write_record

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_dynamics.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
CANDIDATES = 40
AGAIN = 4
REPEATS = 3


def _figure(path: pathlib.Path, rows: list[dict], title: str) -> None:
    """The whine and the largest K_v of the candidates against ε_β (colour: the module), the
    whole numbers of ε_β dashed."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(8.0, 7.0), layout="constrained")
    FigureCanvasAgg(fig)
    top, low = fig.subplots(2, 1, sharex=True)
    eb = np.asarray([r["eps_beta"] for r in rows])
    mn = np.asarray([r["normal_module_mm"] for r in rows])
    labels = {"whine_force_N": "whine: dynamic mesh force, orders 1-3,\nRMS, the largest "
                               "over the speeds (N)",
              "dynamic_factor_max": "largest dynamic factor K_v over the speeds"}
    for ax, key in ((top, "whine_force_N"), (low, "dynamic_factor_max")):
        label = labels[key]
        v = np.asarray([r[key] for r in rows])
        sc = ax.scatter(eb, v, c=mn, cmap="viridis", s=36, zorder=3)
        for w in range(math.floor(eb.min()), math.ceil(eb.max()) + 1):
            ax.axvline(w, color="0.5", ls="--", lw=0.9)
        ax.set_ylabel(label)
        ax.grid(alpha=0.3)
    fig.colorbar(sc, ax=[top, low], location="right", shrink=0.8).set_label("normal module (mm)")
    low.set_xlabel("overlap ratio ε_β (whole numbers dashed)")
    top.set_title(title, fontsize=10)
    fig.savefig(path, dpi=120)


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    spec, _ = jio.load_sizing_spec(str(SPEC))
    table = js.size(spec)
    settings = js.DynamicsSettings(candidates=CANDIDATES)
    t = time.perf_counter()
    staged, curves = js.dynamics_stage(spec, table, settings)
    first = time.perf_counter() - t
    t = time.perf_counter()
    _, again = js.dynamics_stage(spec, table, js.DynamicsSettings(candidates=AGAIN))
    second = time.perf_counter() - t
    c = staged.columns
    speeds = curves.speeds
    # one candidate: the settled time-domain sweep against the harmonic balance, interleaved
    row = {k: v[curves.rows[0]] for k, v in c.items()}
    model = js.candidate_dynamic_model(spec, row)
    sweep_runs, whine_runs = [], []
    for _ in range(REPEATS):
        t = time.perf_counter()
        run = jd.settled_sweep(model, speeds)
        jax.block_until_ready(run.sweep.results.dynamic_factor)
        sweep_runs.append(time.perf_counter() - t)
        t = time.perf_counter()
        jax.block_until_ready(jd.whine_response(model, speeds).mesh_force)
        whine_runs.append(time.perf_counter() - t)
    rows = []
    for j, i in enumerate(curves.rows):
        rows.append({
            "row": int(i), "normal_module_mm": round(float(c["normal_module_m"][i]) * 1e3, 4),
            "z1": int(c["z1"][i]), "z2": int(c["z2"][i]),
            "eps_alpha": round(float(c["eps_alpha"][i]), 4),
            "eps_beta": round(float(c["eps_beta"][i]), 4),
            "mass_kg": round(float(c["mass_kg"][i]), 3),
            "dynamic_factor_max": round(float(c["dynamic_factor_max"][i]), 5),
            "dynamic_factor_at_speed": round(float(c["dynamic_factor_at_speed"][i]), 5),
            "resonance_speed_rpm": round(float(c["resonance_speed_rad_s"][i]) * 30 / math.pi, 1),
            "speed_of_max_dynamic_factor_rpm": round(
                float(speeds[np.nanargmax(curves.dynamic_factor[j])]) * 30 / math.pi, 1),
            "whine_force_N": round(float(c["whine_force_N"][i]), 2),
            "unsettled": int(c["dynamics_unsettled"][i]),
        })
    off = np.asarray([abs(r["eps_beta"] - round(r["eps_beta"])) for r in rows])
    off_alpha = np.asarray([abs(r["eps_alpha"] - round(r["eps_alpha"])) for r in rows])
    rule = {}
    for key in ("whine_force_N", "dynamic_factor_max"):
        v = np.asarray([r[key] for r in rows])
        for name, x in (("eps_beta", off), ("eps_alpha", off_alpha)):
            rho, p = spearmanr(x, v)
            rule[f"{key}__{name}_from_whole"] = {"spearman": round(float(rho), 3),
                                                 "p_value": float(f"{p:.3g}")}
    n_speeds = speeds.size
    record = {
        "what": "the sizing's dynamics stage on the example spec's first Pareto fronts: its cost "
                "(compile and after), the settled time-domain sweep against the harmonic "
                "balance per speed, and the whine and K_v against the overlap ratio's distance "
                "from a whole number",
        "machine": machine,
        "spec": "examples/sizing/helical.toml (front: mass, mesh loss, least margin; helix "
                "15 deg fixed), the stage's default speed range",
        "candidates": len(rows),
        "speeds": n_speeds,
        "speed_range_rpm": [round(float(speeds[0]) * 30 / math.pi, 1),
                            round(float(speeds[-1]) * 30 / math.pi, 1)],
        "stage": {"first_call_s": round(first, 2),
                  "first_call_per_candidate_s": round(first / len(rows), 2),
                  "again_candidates": int(again.rows.size), "again_s": round(second, 2),
                  "again_per_candidate_speed_s": round(second / (again.rows.size * n_speeds),
                                                       4)},
        "one_candidate": {"row": int(curves.rows[0]),
                          "settled_sweep_s": round(min(sweep_runs), 3),
                          "whine_response_s": round(min(whine_runs), 4),
                          "time_domain_over_harmonic_balance": round(
                              min(sweep_runs) / min(whine_runs), 1),
                          "runs_s": {"settled_sweep": [round(v, 3) for v in sweep_runs],
                                     "whine_response": [round(v, 4) for v in whine_runs]}},
        "design_rule": rule,
        "rows": rows,
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)
    w = rule["whine_force_N__eps_beta_from_whole"]["spearman"]
    _figure(path.with_suffix(".png"), rows,
            f"{len(rows)} candidates of examples/sizing/helical.toml's front: the whine and K_v "
            f"against ε_β\n(Spearman's ρ of the whine and |ε_β − nearest whole number|: {w})")


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
