"""Optimise, then rate: one design, one workflow, on the embedded power-helical pair.

1. Load the case: its ``[modifications]`` (10 µm tip relief over 0.2 of the path of contact,
   5 µm crowning) and its ``[rating]`` (ISO 6336:2019 method B, 930 kW at 28 648 1/min).
2. Rate it as ``jaxgear run`` does: ISO's tip relief C_a (K_v) and crowning C_β (K_Hβ) are the
   case's modifications (``rc.modification_inputs`` says so).
3. Raise its least safety factor under a TE limit (``jio.case_problem(case, ...,
   "least_safety")``: ``optimise.LeastSafetyFactor``, the K_Hβ measured on each design's load
   map, the design's own tip relief and crowning as ISO's C_a and C_β, K_Hα ISO's), the tip
   relief depth and the crowning depth as the variables, the TE RMS held at the case design's.
4. Write the optimum as a case file (``jio.write_design_case``, what ``jaxgear optimise
   --write`` does), load it back and rate it as ``jaxgear run`` would: ISO's factors with the
   new design's C_a and C_β, and with the K_Hβ measured on its load map (``[rating]
   use_measured = ["K_Hbeta"]``).

Every safety factor is above 1 at the start and at the optimum (the case is a sound design:
the least is the pinion's S_H, about 1.4 with the measured K_Hβ). Prints start → optimum;
writes ``rating_optimise.json``, ``rating_optimise.png`` (the safety factors and the TE RMS)
and ``power-helical-optimum.toml`` (``jaxgear run`` takes it) into the output folder, by
default ``jaxgear-out/rating_optimise`` (nothing under docs/ unless that is the folder given).
Run from anywhere: ``python examples/rating_optimise.py [out_dir]`` (about 3.5 minutes on 2
loaded cores at the default 10 slices and 16 positions per pitch).
"""

from __future__ import annotations

import json
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx
import jax.numpy as jnp
import matplotlib

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
import optimise as op

matplotlib.use("Agg")
import matplotlib.pyplot as plt

OUT = pathlib.Path("jaxgear-out") / "rating_optimise"
CASE = "power-helical"
VARIABLES = ["tip_relief.depth", "crowning.depth"]


def coarse_text(slices: int, positions: int) -> str:
    """The embedded case's TOML text on a coarser mesh (``slices`` per contact line,
    ``positions`` per pitch)."""
    return (
        jio.embedded_case_text(CASE)
        .replace("slices = 40", f"slices = {slices}")
        .replace("positions_per_pitch = 64", f"positions_per_pitch = {positions}")
    )


def rate_case(case: jio.Case) -> dict:
    """The case rated as ``jaxgear run`` rates it: ISO 6336's factors (C_a and C_β from its
    modifications), and with the K_Hβ measured on its exact-contact load map given."""
    rc = jio.rating_of(case)
    iso = jr.rate(rc.geometry, rc.operating, rc.settings)
    res = jg.quasi_static(
        case.mesh_model(), case.modifications, case.torque,
        positions_per_pitch=case.positions_per_pitch,
    )
    khb = float(jg.rating.face_load_factor(res))
    given = eqx.tree_at(lambda s: s.given, rc.settings, jr.GivenFactors(K_Hbeta=khb))
    measured = jr.rate(rc.geometry, rc.operating, given)

    def factors(r):
        return {
            "K_v": float(r.factors.K_v),
            "K_Hbeta": float(r.factors.K_Hbeta),
            "K_Halpha": float(r.factors.K_Halpha),
            "S_H": [float(v) for v in r.pitting.S_H],
            "S_F": [float(v) for v in r.bending.S_F],
        }

    inputs = rc.modification_inputs
    return {
        "tip_relief_um": float(iso.factors.details["C_a_m"]) * 1e6,  # the running-in C_ay if none
        "tip_relief_source": inputs["tip_relief_source"],
        "crowning_um": (inputs["crowning_m"] or 0.0) * 1e6,
        "crowning_source": inputs["crowning_source"],
        "iso": factors(iso),
        "measured_K_Hbeta": factors(measured),
        "te_rms_m": float(res.te_rms),
    }


def main(out_dir=OUT, max_iterations: int = 30, slices: int = 10, positions: int = 16) -> dict:
    """Optimise (at most ``max_iterations`` L-BFGS steps) on the ``slices`` × ``positions``
    model, write the optimum as a case file, rate start and optimum, and write the record and
    the figure into ``out_dir`` (created if missing); returns the record."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    text = coarse_text(slices, positions)
    source = out_dir / f"{CASE}.toml"  # the start, as a file beside the optimum
    source.write_text(text, encoding="utf-8")
    case = jio.load_case(str(source))
    # the TE limit: the start's TE RMS in the smooth law the objective is evaluated in
    te = jio.case_problem(case, VARIABLES, "te_rms")
    start_x = jnp.asarray(te.from_physical(te.case_values(case.modifications)))
    te_start = float(te.value(start_x)) * float(te.scale)
    problem = jio.case_problem(case, VARIABLES, "least_safety", te_limit=te_start)
    result = op.minimise(problem, start_x, max_iterations=max_iterations, progress=False)
    optimum = problem.to_physical(result.x)
    written = out_dir / f"{CASE}-optimum.toml"
    new_case = jio.write_design_case(written, text, case, problem, optimum)
    record = {
        "start": {"design_um": problem.case_values(case.modifications)} | rate_case(case),
        "optimum": {"design_um": optimum} | rate_case(new_case),
        "te_limit_m": te_start,
        "iterations": int(result.iterations),
        "objective_smooth": [float(result.value0), float(result.value)],
        "case_file": written.name,
    }
    for label in ("start", "optimum"):
        r = record[label]
        m, iso = r["measured_K_Hbeta"], r["iso"]
        design = ", ".join(f"{k} {v:.2f}" for k, v in r["design_um"].items())
        print(
            f"{label}: {design} µm; ISO: K_Hβ {iso['K_Hbeta']:.3f}, S_H "
            f"{iso['S_H'][0]:.3f}/{iso['S_H'][1]:.3f}, S_F {iso['S_F'][0]:.3f}/"
            f"{iso['S_F'][1]:.3f}; measured K_Hβ {m['K_Hbeta']:.3f}: S_H {m['S_H'][0]:.3f}/"
            f"{m['S_H'][1]:.3f}, S_F {m['S_F'][0]:.3f}/{m['S_F'][1]:.3f}; TE RMS "
            f"{r['te_rms_m'] * 1e6:.3f} µm (C_a {r['tip_relief_um']:.2f} µm, C_β "
            f"{r['crowning_um']:.2f} µm from {r['tip_relief_source'].split(',')[0]})"
        )
    print(
        f"objective {result.value0:.4f} -> {result.value:.4f} (smooth law), "
        f"{result.iterations} iterations; the optimum as a case file: {written} "
        f"(jaxgear run {written})"
    )
    (out_dir / "rating_optimise.json").write_text(json.dumps(record, indent=1) + "\n")
    plot(record, out_dir / "rating_optimise.png")
    return record


def plot(record: dict, path) -> None:
    """The four safety factors (measured K_Hβ) and the TE RMS against its limit, start and
    optimum."""
    fig, (ax, ax_te) = plt.subplots(1, 2, figsize=(8, 4), width_ratios=(3, 1), layout="constrained")
    names = ["S_H pinion", "S_H gear", "S_F pinion", "S_F gear"]
    x = range(len(names))
    for k, (label, shift) in enumerate((("start", -0.2), ("optimum", 0.2))):
        r = record[label]["measured_K_Hbeta"]
        ax.bar([i + shift for i in x], r["S_H"] + r["S_F"], width=0.4, label=label, color=f"C{k}")
        iso = record[label]["iso"]
        ax.plot([i + shift for i in x], iso["S_H"] + iso["S_F"], "k_", ms=14,
                label="ISO's K_Hβ" if k == 0 else None)
        ax_te.bar(k, record[label]["te_rms_m"] * 1e6, color=f"C{k}")
    ax.axhline(1.0, color="0.3", ls=":", label="S = 1")
    ax.set_xticks(list(x), names)
    ax.set_ylabel("ISO 6336 safety factor (-), measured K_Hβ")
    least = [min(record[k]["measured_K_Hbeta"]["S_H"] + record[k]["measured_K_Hbeta"]["S_F"])
             for k in ("start", "optimum")]
    ax.set_title(f"{CASE}: the least safety factor {least[0]:.3f} → {least[1]:.3f}")
    ax.legend()
    ax_te.axhline(record["te_limit_m"] * 1e6, color="0.3", ls="--", label="TE limit")
    ax_te.set_xticks([0, 1], ["start", "optimum"])
    ax_te.set_ylabel("TE RMS (µm), exact contact")
    ax_te.legend()
    fig.savefig(path, dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main(*sys.argv[1:2])
