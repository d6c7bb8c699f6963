"""The cost of bearings from their geometry: ``jaxgear run`` of the lumped 3D accessory pair on
rolling bearings (examples/accessory-lumped3d-rolling.toml: the fixed point of their operating
point, a few more quasi-static solves) against the same case on linear springs
(examples/accessory-lumped3d.toml), paired: fresh processes of this tree, the two cases one
after the other, in the order linear, rolling, rolling, linear (``--repeats`` such rounds), so
that both see the same load. Each run starts on an empty persistent compilation cache (a first
run) and runs again on the cache it wrote (a second run, as a user's next run):
:func:`benchmarks._run_cases_paired.paired_runs` records wall and CPU time (user + sys from
``os.wait4``: on a loaded machine the figure to compare) and the XLA compilations.

Run from the checkout's root::

    python -m benchmarks.bearings_run_cost --out docs/bench/bearings_run_cost.json

Benchmarks are not tests: timings are measured, never asserted (the issue's bound, at most
+20 % CPU, is read off the record)."""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

from ._run_cases_paired import paired_runs
from ._timing import environment, write_record

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CASES = {
    "linear": os.path.join(ROOT, "examples", "accessory-lumped3d.toml"),
    "rolling": os.path.join(ROOT, "examples", "accessory-lumped3d-rolling.toml"),
}


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeats", type=int, default=1, help="rounds of four runs (default 1)")
    p.add_argument("--out", required=True, help="the JSON record to write")
    a = p.parse_args(argv)
    rows = []
    for _ in range(a.repeats):
        for name in ("linear", "rolling", "rolling", "linear"):
            row = paired_runs({"this": ROOT}, [CASES[name]], second=True)[0]
            rows.append(dict(row, bearings=name))
    summary = {}
    for run in ("first", "second"):
        cpu = {n: statistics.mean(r[run]["cpu_s"] for r in rows if r["bearings"] == n)
               for n in CASES}
        wall = {n: statistics.mean(r[run]["wall_s"] for r in rows if r["bearings"] == n)
                for n in CASES}
        summary[run] = {"cpu_s": cpu, "wall_s": wall,
                        "cpu_ratio": cpu["rolling"] / cpu["linear"],
                        "wall_ratio": wall["rolling"] / wall["linear"]}
        print(f"{run}: CPU linear {cpu['linear']:.1f} s, rolling {cpu['rolling']:.1f} s "
              f"(x{summary[run]['cpu_ratio']:.3f}); wall x{summary[run]['wall_ratio']:.3f}",
              flush=True)
    result = {
        "benchmark": "bearings-run-cost",
        "what": "jaxgear run --quiet of examples/accessory-lumped3d-rolling.toml (bearings from "
        "geometry at their operating point) against examples/accessory-lumped3d.toml (linear "
        "springs), fresh processes, order linear, rolling, rolling, linear; first: an empty "
        "compilation cache, second: on the cache the first wrote; means per case",
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "environment": environment(),
        "summary": summary,
        "results": rows,
    }
    write_record(a.out, result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
