"""``jaxgear run`` on every embedded pair and train case whose sweep settles
(docs/dynamics.md "Settled sweeps"), in two source trees (before: the fixed 60, 30 or, for
two-stage, 160 periods; after: ``periods = "auto"``, each speed by continuation until it
settles), each run a fresh process with an empty compilation cache of its own: wall and CPU seconds (user + system of the
child, ``resource.getrusage``) and the 1-minute load average before and after each run (the
machine may be shared: CPU seconds are the comparable figure). Writes
the JSON given by ``--json`` (machine, dtype, JAX version; docs/bench/bench_settled_sweeps.json
holds the figures measured by hand before).

    python benchmarks/settled_sweeps.py --before /tmp/base --after . [--cases a b ...]

Each run takes 0.5-10 min on a 2-core machine: this is not a test."""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

#: the embedded cases whose ``jaxgear run`` sweeps (a ``[scene]`` without condensed bodies;
#: power-helical and nrel-5mw-stage3 have none: ``jaxgear sweep`` runs theirs)
CASES = ["accessory-spur", "accessory-idler-train", "two-stage"]


def one_run(src: str, case: str) -> dict:
    """``jaxgear run CASE`` from the source tree ``src`` in a fresh process (empty cache)."""
    with tempfile.TemporaryDirectory() as tmp:
        env = dict(os.environ, PYTHONPATH=src, JAX_COMPILATION_CACHE_DIR=os.path.join(tmp, "xla"))
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        load0 = os.getloadavg()[0]
        t0 = time.perf_counter()
        subprocess.run(
            [
                sys.executable,
                "-c",
                "import sys; from jaxgear.cli import main; sys.exit(main(sys.argv[1:]))",
                "run",
                case,
                "--out",
                os.path.join(tmp, "o"),
                "--quiet",
            ],
            cwd=src,
            env=env,
            check=True,
            capture_output=True,
        )
        wall = time.perf_counter() - t0
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        sweep = json.loads(Path(tmp, "o", "sweep", "sweep.json").read_text())
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    settled = sweep.get("settled") or []
    return {
        "wall_s": wall,
        "cpu_s": cpu,
        "load_1min": [load0, os.getloadavg()[0]],
        "speeds": len(sweep["speeds_rad_s"]),
        "periods": sweep["periods"],
        "settled": sum(1 for v in settled if v),
        "max_dynamic_factor": max(v for v in sweep["dynamic_factor"] if v is not None),
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--before", required=True, help="source tree of the fixed spans")
    p.add_argument("--after", default=".", help="source tree of the settled sweeps")
    p.add_argument("--cases", nargs="*", default=CASES)
    p.add_argument("--json", default="bench_settled_sweeps_run.json")
    a = p.parse_args()
    import jax

    out = {
        "machine": {
            "cpus": os.cpu_count(),
            "platform": platform.platform(),
            "processor": platform.processor(),
        },
        "jax": jax.__version__,
        "dtype": "float64",
        "note": "CPU seconds of each fresh process (empty compilation cache); the load average "
        "says how busy the machine was",
        "cases": {},
    }
    for case in a.cases:
        out["cases"][case] = {"before": one_run(a.before, case), "after": one_run(a.after, case)}
        print(case, out["cases"][case], flush=True)
    Path(a.json).write_text(json.dumps(out, indent=2) + "\n")


if __name__ == "__main__":
    main()
