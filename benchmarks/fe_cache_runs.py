"""What the disk cache of the FE fillet influence tables saves a ``jaxgear run`` with a
``[rating]`` table: per embedded case, runs in fresh processes one after the other (the same
load), in rounds of three:

* ``before``: a source tree without the disk cache (``--before``, e.g. ``git archive COMMIT |
  tar -x -C DIR``): each run solves the FE tables again;
* ``first``: this tree with the fillet tables' cache folder emptied (the run solves them and
  writes them);
* ``second``: this tree again, the tables read from the cache the first wrote.

Every run shares one persistent compilation cache and one fem_prep cache (the condensed bodies,
the ``fe2d`` tooth tables), both filled by a warm-up run first, so that the rounds differ only
by the fillet tables. Recorded per run: CPU time (user + sys, ``os.wait4``: the figure to
compare on a loaded machine), wall time, the load average, the fillet tables in the cache
after it. Measured, never asserted.

Run from the checkout's root::

    python -m benchmarks.fe_cache_runs --before /tmp/before \\
        --cases nrel-5mw-planetary,nrel-5mw-stage3 --out docs/bench/fe_cache_runs.json
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time

from ._timing import environment

__all__ = ["fe_cache_rounds"]


def _run(tree: str, case: str, env: dict, work: str, name: str) -> dict:
    """One ``jaxgear run CASE --quiet`` of the source tree ``tree``: CPU and wall time."""
    cmd = [sys.executable, "-c", "import sys; from jaxgear.cli import main; sys.exit(main())"]
    cmd += ["run", case, "--quiet"]
    cmd += ["--out", os.path.join(work, name)]
    load0 = list(os.getloadavg())
    t = time.perf_counter()
    proc = subprocess.Popen(
        cmd,
        env={**env, "PYTHONPATH": os.path.abspath(tree)},
        cwd=work,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    err = proc.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"jaxgear run {case} ({tree}) failed: {err.strip()[-800:]}")
    tables = os.path.join(env["FEM_PREP_CACHE"], "fillet_influence")
    return {
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "wall_s": wall,
        "load_at_start": load0,
        "load_at_end": list(os.getloadavg()),
        "fillet_tables_cached": len(os.listdir(tables)) if os.path.isdir(tables) else 0,
    }


def fe_cache_rounds(before: str, after: str, cases, rounds: int = 2) -> list:
    """Per case: a warm-up run, then ``rounds`` rounds of (before, first, second)."""
    rows = []
    for case in cases:
        with tempfile.TemporaryDirectory(prefix="jaxgear-fe-cache-bench-") as work:
            env = dict(os.environ)
            for key in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"):
                env.pop(key, None)
            env["JAXGEAR_XLA_CACHE"] = os.path.join(work, "xla")
            env["FEM_PREP_CACHE"] = os.path.join(work, "fem_prep")
            row = {"case": case, "warm_up": _run(after, case, env, work, "warm-up"), "rounds": []}
            for r in range(rounds):
                got = {"before": _run(before, case, env, work, f"before-{r}")}
                shutil.rmtree(os.path.join(env["FEM_PREP_CACHE"], "fillet_influence"))
                got["first"] = _run(after, case, env, work, f"first-{r}")
                got["second"] = _run(after, case, env, work, f"second-{r}")
                row["rounds"].append(got)
                print(
                    f"{case:22s} round {r}: CPU before {got['before']['cpu_s']:5.1f} s, first "
                    f"{got['first']['cpu_s']:5.1f} s, second {got['second']['cpu_s']:5.1f} s "
                    f"({got['first']['fillet_tables_cached']} tables; load "
                    f"{got['before']['load_at_start'][0]:.1f})",
                    flush=True,
                )
            rows.append(row)
    return rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--before", required=True, help="source tree without the disk cache")
    p.add_argument("--after", default=".", help="source tree with it (default .)")
    p.add_argument("--cases", required=True, help="embedded case names, comma-separated")
    p.add_argument("--rounds", type=int, default=2)
    p.add_argument("--out", required=True, help="the JSON record to write")
    a = p.parse_args(argv)
    env = environment()
    env["runs_dtype"] = "float64 (jaxgear run enables jax_enable_x64)"
    env["lscpu"] = subprocess.run(["lscpu"], capture_output=True, text=True, check=False).stdout
    env["uptime_at_start"] = subprocess.run(
        ["uptime"], capture_output=True, text=True, check=False
    ).stdout
    rows = fe_cache_rounds(a.before, a.after, a.cases.split(","), a.rounds)
    result = {
        "benchmark": "fe-cache-runs",
        "what": "CPU time (user + sys, os.wait4) and wall time of `jaxgear run CASE --quiet` in "
        "fresh processes, one after the other per round: `before` (no disk cache of the FE "
        "fillet tables), `first` (this code, the tables' cache emptied: solved and written), "
        "`second` (this code, read back); compilation cache and fem_prep's other tables warm "
        "in every run (a warm-up run first)",
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "environment": env,
        "uptime_at_end": subprocess.run(
            ["uptime"], capture_output=True, text=True, check=False
        ).stdout,
        "results": rows,
    }
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
