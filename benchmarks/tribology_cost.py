"""What the film, flash temperature and sliding loss along the path of contact add to ``jaxgear
run`` on a rated pair case: the FZG C14 gears (examples/fzg-c14-lubricated.toml, 4 slices, 64
positions per pitch) with a ``[rating]`` (ISO 6336 method B) and the oil's FZG load stage (the
scuffing keys), run with and without its ``[lubricant]`` table, everything else identical.

Each pair of runs is ``jaxgear run CASE --quiet`` in fresh processes, each case first with an
empty persistent compilation cache (a first run: every program compiled, the tribology's
included) and then again on the cache that run wrote (a second run: a user's next run), the case
without ``[lubricant]`` and the case with it one right after the other, so that both see the
same load; the ratio with/without is taken pair by pair (CPU seconds, user + sys of
the process from ``os.wait4``: the figure to compare on a shared machine; wall seconds beside)
and the median over the pairs is the figure quoted. Recorded: every run (CPU, wall, peak
memory, load average, XLA compilations: benchmarks/_run_cases_paired.py's probe), the machine
(benchmarks/_timing.py's ``environment()``), dtype and JAX version.

Run from the repository root: ``python -m benchmarks.tribology_cost [--pairs N] [--out FILE]``
(default 3 pairs, docs/bench/tribology_cost.json; a few minutes). Timings are measured, never
asserted.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import statistics
import tempfile
import tomllib

import jax

from ._run_cases_paired import _one_run
from ._timing import environment

# the runs are jaxgear's CLI, which computes in float64: the record says so
jax.config.update("jax_enable_x64", True)

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "tribology_cost.json"
SOURCE = ROOT / "examples" / "fzg-c14-lubricated.toml"

# the rating's inputs added to the lubricated case: a case-hardened steel, 20 000 h, the oil's
# ν₄₀, R_z of flank and root; the oil's FZG load stage (the flash temperature and scuffing)
RATING = """
[rating]
life_h = 20000.0
viscosity_40C_mm2_s = 316.0
roughness_Rz_flank_um = 3.0
roughness_Rz_root_um = 10.0
"""
MATERIAL = "sigma_H_lim_MPa = 1500.0\nsigma_F_lim_MPa = 430.0\n"
SCUFFING = "fzg_load_stage = 12\n"


def case_texts() -> tuple[str, str]:
    """(with, without) ``[lubricant]``: the rated FZG C14 case files."""
    text = SOURCE.read_text()
    text = text.replace("[material]\n", "[material]\n" + MATERIAL, 1)
    with_oil = text.rstrip("\n") + "\n" + SCUFFING + RATING
    head, tail = with_oil.split("[lubricant]\n", 1)
    # the [lubricant] table runs to [rating]
    without = head + "[rating]\n" + tail.split("[rating]\n", 1)[1]
    for t in (with_oil, without):
        tomllib.loads(t)  # both parse
    assert "[lubricant]" not in without and "[rating]" in without
    return with_oil, without


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--pairs", type=int, default=3, help="pairs of runs (default 3)")
    p.add_argument("--out", default=str(OUT), help="the JSON record to write")
    p.add_argument("--note", default="", help="the load on the machine, in words")
    a = p.parse_args(argv)
    env = environment()
    with_oil, without = case_texts()
    rows = []
    with tempfile.TemporaryDirectory(prefix="jaxgear-tribology-bench-") as folder:
        cases = {}
        for label, text in (("without_lubricant", without), ("with_lubricant", with_oil)):
            path = os.path.join(folder, f"fzg-c14-rated-{label}.toml")
            with open(path, "w") as f:
                f.write(text)
            cases[label] = path
        for k in range(a.pairs):
            pair = {}
            for label, path in cases.items():
                with tempfile.TemporaryDirectory(prefix="run-", dir=folder) as work:
                    cache = os.path.join(work, "xla")
                    runs = {"first": _one_run(str(ROOT), path, cache, work, "first")}
                    # the same run again on the cache the first wrote (a user's next run)
                    runs["second"] = _one_run(str(ROOT), path, cache, work, "second")
                for run in runs.values():
                    run.pop("compilations_by_program", None)
                pair[label] = runs
            for which in ("first", "second"):
                on, off = pair["with_lubricant"][which], pair["without_lubricant"][which]
                pair[f"{which}_cpu_ratio"] = on["cpu_s"] / off["cpu_s"]
                pair[f"{which}_wall_ratio"] = on["wall_s"] / off["wall_s"]
                print(
                    f"pair {k + 1}, {which} run: CPU {off['cpu_s']:.1f} s -> {on['cpu_s']:.1f} s "
                    f"(x{pair[f'{which}_cpu_ratio']:.3f}), wall {off['wall_s']:.1f} s -> "
                    f"{on['wall_s']:.1f} s (x{pair[f'{which}_wall_ratio']:.3f})",
                    flush=True,
                )
            rows.append(pair)
    figures = {}
    for which in ("first", "second"):
        cpu = [r[f"{which}_cpu_ratio"] for r in rows]
        wall = [r[f"{which}_wall_ratio"] for r in rows]
        figures[which] = {
            "cpu_ratio_median": statistics.median(cpu),
            "cpu_ratio_min": min(cpu),
            "cpu_ratio_max": max(cpu),
            "wall_ratio_median": statistics.median(wall),
            "added_cpu_fraction_median": statistics.median(cpu) - 1.0,
        }
    record = {
        "benchmark": "tribology-cost",
        "what": "CPU time (user + sys, os.wait4) and wall time of `jaxgear run CASE --quiet`"
        " (fresh processes: a first run on an empty persistent compilation cache, then a "
        "second on the cache it wrote) on the rated FZG C14 case "
        "(4 slices, 64 positions per pitch, [rating] ISO 6336 method B) with its [lubricant] "
        "(film, lambda, sliding loss, flash temperature and scuffing along the path of contact:"
        " tribology.json/.csv/.png) and without it, run one after the other in pairs; the "
        "ratio with/without is taken pair by pair and its median quoted",
        "case": "examples/fzg-c14-lubricated.toml + [rating] + fzg_load_stage = 12",
        "machine_note": "a shared machine (2 cores, about 9 agents' jobs at once): the pairs "
        "see the same load, the ratios hold, the seconds do not"
        + (f"; {a.note}" if a.note else ""),
        "environment": env,
        "dtype": env.get("dtype"),
        "jax": env.get("jax"),
        "pairs": rows,
        "first_run": figures["first"],
        "second_run": figures["second"],
    }
    pathlib.Path(a.out).write_text(json.dumps(record, indent=2) + "\n")
    for which, f in figures.items():
        print(
            f"with/without [lubricant], {which} run: CPU x{f['cpu_ratio_median']:.3f} (median of "
            f"{a.pairs} pairs, {f['cpu_ratio_min']:.3f}..{f['cpu_ratio_max']:.3f}), wall "
            f"x{f['wall_ratio_median']:.3f}"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
