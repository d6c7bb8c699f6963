"""Start-up time of the ``jaxgear`` command line: ``--help``, ``--version``, ``cases`` and a
few subcommands' ``--help``, each run in fresh processes as the console script runs it, in this
source tree and, with ``--before DIR``, in another (e.g. ``git archive COMMIT | tar -x -C DIR``),
the two alternating so that both see the same load.

The script: ``import jaxgear_start; jaxgear_start.entry()`` where the tree has
``jaxgear_start.py`` (the model deferred), else ``from jaxgear.cli import entry; entry()`` (the
script of earlier trees). Recorded per command and tree: the minimum and median wall time over
``--repeats`` runs, the CPU seconds (user + sys, ``os.wait4``) of the fastest, whether JAX was
imported (``-X importtime``'s lines), and the load average.

Run from the checkout's root::

    python -m benchmarks._startup --before /tmp/before --out docs/bench/bench_startup.json

Benchmarks are not tests: timings are measured, never asserted."""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time

__all__ = ["COMMANDS", "startup_times"]

#: the command lines timed (after ``jaxgear``)
COMMANDS = (
    ("--help",),
    ("--version",),
    ("cases",),
    ("run", "--help"),
    ("sweep", "--help"),
    ("robust", "--help"),
    ("optimise", "--help"),
)

_NEW = "import jaxgear_start; jaxgear_start.entry()"
_OLD = "from jaxgear.cli import entry; entry()"


def _script(tree: str) -> str:
    return _NEW if os.path.isfile(os.path.join(tree, "jaxgear_start.py")) else _OLD


def _one(tree: str, args: tuple[str, ...]) -> dict:
    env = dict(os.environ, PYTHONPATH=os.path.abspath(tree))
    cmd = [sys.executable, "-X", "importtime", "-c", _script(tree), *args]
    t = time.perf_counter()
    proc = subprocess.Popen(
        cmd, env=env, cwd=tree, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    err = proc.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"jaxgear {' '.join(args)} failed in {tree}: {err[-500:]}")
    modules = {
        line.rsplit("|", 1)[1].strip()
        for line in err.splitlines()
        if line.startswith("import time:")
    }
    return {
        "wall_s": wall,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "imports_jax": "jax" in modules,
    }


def startup_times(trees: dict[str, str], repeats: int = 5) -> dict:
    """{command line: {tree label: record}} over ``repeats`` alternating runs per tree."""
    out = {}
    for args in COMMANDS:
        runs = {label: [] for label in trees}
        for _ in range(repeats):
            for label, tree in trees.items():
                runs[label].append(_one(tree, args))
        key = "jaxgear " + " ".join(args)
        out[key] = {}
        for label, rs in runs.items():
            walls = [r["wall_s"] for r in rs]
            best = min(rs, key=lambda r: r["wall_s"])
            out[key][label] = {
                "min_wall_s": best["wall_s"],
                "median_wall_s": statistics.median(walls),
                "cpu_s_of_min": best["cpu_s"],
                "imports_jax": any(r["imports_jax"] for r in rs),
            }
        print(
            f"{key:26s} "
            + "  ".join(
                f"{label}: {v['min_wall_s']:.2f} s (median {v['median_wall_s']:.2f}, "
                f"jax {'yes' if v['imports_jax'] else 'no'})"
                for label, v in out[key].items()
            ),
            flush=True,
        )
    return out


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(prog="python -m benchmarks._startup")
    p.add_argument("--before", help="another source tree to time alongside this one")
    p.add_argument("--repeats", type=int, default=5, help="runs per command and tree")
    p.add_argument("--out", help="write the record (JSON) to this file")
    args = p.parse_args(argv)
    trees = {"after": os.getcwd()}
    if args.before:
        trees = {"before": args.before, **trees}
    load = os.getloadavg()
    results = startup_times(trees, repeats=args.repeats)
    record = {
        "benchmark": "startup",
        "what": "wall time of `jaxgear ARGS` in fresh processes (the console script's own "
        "code: jaxgear_start.entry, or jaxgear.cli.entry in trees without it), min and median "
        f"over {args.repeats} alternating runs per tree; cpu_s_of_min: user + sys of the "
        "fastest run; imports_jax: whether JAX was imported (python -X importtime)",
        "trees": trees,
        "cpu_count": os.cpu_count(),
        "load_average_at_start": list(load),
        "load_average_at_end": list(os.getloadavg()),
        "python": sys.version.split()[0],
        "results": results,
    }
    if args.out:
        with open(args.out, "w", encoding="utf-8") as f:
            json.dump(record, f, indent=2)
    return 0


if __name__ == "__main__":
    sys.exit(main())
