"""What a first ``jaxgear run`` on a fresh install costs beyond the run itself: the building of
the case's FE parts that fem_prep caches (``$FEM_PREP_CACHE``), its condensed bodies
(``load_bodies`` of its ``[scene]``) and its housing (``housing_body``; a gearbox's own
``[housing]`` too). Each embedded case that has one, in a fresh process with an empty cache
folder of its own: wall and CPU seconds (user + sys of the process and its threads) of the
build alone (the import and the case's loading not counted), the load average beside them.
``jaxgear cases`` prints the first run plus this build as its COLD column
(:data:`jaxgear.cli.cases.FE_BUILD`).

From the repository root::

    python -m benchmarks.cold_builds [--out docs/bench/bench_cold_builds.json]

Benchmarks are not tests: timings are measured, never asserted; on a loaded machine the CPU
seconds are the robust figure (the wall time waits for the other processes)."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile

from ._timing import environment

__all__ = ["cold_builds"]

# One case's build in this fresh process (argv[1]: the case), its record as one JSON line.
_PROBE = """
import json, os, resource, sys, time
import jaxgear.io as jio
case = jio.load_case(sys.argv[1])
r0, t0 = resource.getrusage(resource.RUSAGE_SELF), time.perf_counter()
load = os.getloadavg()
parts = []
if case.scene is not None and case.scene.hybrid:
    jio.load_bodies(case.scene)
    parts.append("bodies")
if case.housing is not None:
    case.housing_body()
    parts.append("housing")
if isinstance(case.form, jio.GearboxForm) and case.form.housing is not None:
    case.form.housing_body
    parts.append("gearbox housing")
wall = time.perf_counter() - t0
r1 = resource.getrusage(resource.RUSAGE_SELF)
cpu = r1.ru_utime - r0.ru_utime + r1.ru_stime - r0.ru_stime
print(json.dumps({"case": sys.argv[1], "parts": parts, "wall_s": wall, "cpu_s": cpu,
                  "load_average_at_start": load, "load_average_at_end": os.getloadavg()}))
"""


def _has_fe_parts(case) -> bool:
    import jaxgear.io as jio

    gearbox_housing = isinstance(case.form, jio.GearboxForm) and case.form.housing is not None
    return (case.scene is not None and case.scene.hybrid) or case.housing is not None or (
        gearbox_housing)


def cold_builds(cases=None) -> dict:
    """The record: each case's build (:data:`_PROBE`) with an empty fem_prep cache."""
    import jaxgear.io as jio

    names = cases or [n for n in jio.list_cases() if _has_fe_parts(jio.load_case(n))]
    results = []
    for name in names:
        with tempfile.TemporaryDirectory(prefix="cold-builds-") as cache:
            env = dict(os.environ, FEM_PREP_CACHE=cache)
            out = subprocess.run([sys.executable, "-c", _PROBE, name], env=env, check=True,
                                 capture_output=True, text=True).stdout
            results.append(json.loads(out.strip().splitlines()[-1]))
    return {
        "benchmark": "cold-builds",
        "what": "wall and CPU seconds (user + sys, the process's threads) of building a case's "
        "condensed bodies and housing with an empty fem_prep cache, in a fresh process (the "
        "import and the loading of the case not counted)",
        "environment": environment(),
        "results": results,
    }


def main(argv=None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--out", default="docs/bench/bench_cold_builds.json")
    p.add_argument("cases", nargs="*", help="embedded cases (default: every one with FE parts)")
    args = p.parse_args(argv)
    record = cold_builds(args.cases)
    with open(args.out, "w", encoding="utf-8") as f:
        json.dump(record, f, indent=2)
        f.write("\n")


if __name__ == "__main__":
    main()
