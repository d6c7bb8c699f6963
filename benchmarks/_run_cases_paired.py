"""Paired before/after timing of ``jaxgear run`` per embedded case: two source trees of jaxgear
(``--before``, ``--after``: checkouts, e.g. ``git archive COMMIT | tar -x -C DIR``), each case run
once with each tree in fresh processes, one after the other (before, after) so that both see
the same load. Every run starts with an empty persistent compilation cache (its own folder:
a first run, every program compiled) unless ``--second`` adds a second run on the cache the
first wrote.

Recorded per run: wall time, CPU time (user + sys of the process and its threads, from
``os.wait4``: on a loaded machine the figure to compare), peak resident memory, the load
average at start and end, and JAX's compilation events: the number of XLA compilations and
their seconds (``/jax/core/compile/backend_compile_duration``), the programs read back from the
cache, and the compilations per program name (``jax_log_compiles``' "Finished XLA compilation of
NAME" records): what a change of the repeated work removes.

Run from the checkout's root::

    python -m benchmarks._run_cases_paired --before /tmp/before --after . \\
        --cases accessory-spur,accessory-idler-train --out docs/bench/bench_run_cases_paired.json

Benchmarks are not tests: timings are measured, never asserted."""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time

from ._timing import environment

__all__ = ["paired_runs"]

# One CLI run that records JAX's compilation events and the compilations per program name
# into argv[1]; the rest of argv is jaxgear's.
_PROBE = """
import collections, json, logging, re, sys
import jax
jax.config.update("jax_log_compiles", True)
from jax import monitoring
events, seconds = collections.Counter(), collections.Counter()
monitoring.register_event_listener(lambda name, **kw: events.update([name]))
def _duration(name, secs, **kw):
    seconds[name] += secs
monitoring.register_event_duration_secs_listener(_duration)
names, name_s = collections.Counter(), collections.Counter()
pattern = re.compile(r"Finished XLA compilation of (.*?) in ([0-9.e+-]+) s")
class Names(logging.Handler):
    def emit(self, record):
        m = pattern.search(record.getMessage())
        if m:
            names[m.group(1)] += 1
            name_s[m.group(1)] += float(m.group(2))
log = logging.getLogger("jax")
log.addHandler(Names(logging.DEBUG))
log.setLevel(logging.DEBUG)
log.propagate = False
from jaxgear.cli import main
status = main(sys.argv[2:])
by_name = sorted(([k, names[k], name_s[k]] for k in names), key=lambda r: -r[2])
with open(sys.argv[1], "w") as f:
    json.dump({"status": status, "events": events, "seconds": seconds, "by_name": by_name}, f)
"""
_BACKEND = "/jax/core/compile/backend_compile_duration"
_HITS = "/jax/compilation_cache/cache_hits"


def _env(tree: str, cache: str) -> dict:
    env = dict(os.environ)
    for key in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"):
        env.pop(key, None)  # the CLI's own settings
    env["JAXGEAR_XLA_CACHE"] = cache
    env["PYTHONPATH"] = os.path.abspath(tree)  # this tree's jaxgear, whatever is installed
    return env


def _one_run(tree: str, case: str, cache: str, work: str, name: str) -> dict:
    """One ``jaxgear run CASE --quiet`` of ``tree`` with the compilation cache ``cache``."""
    record = os.path.join(work, f"{name}.json")
    cmd = [sys.executable, "-c", _PROBE, record, "run", case, "--quiet"]
    cmd += ["--out", os.path.join(work, name)]
    load0 = list(os.getloadavg())
    t = time.perf_counter()
    proc = subprocess.Popen(
        cmd, env=_env(tree, cache), cwd=work, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE
    )
    err = proc.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(proc.pid, 0)
    wall = time.perf_counter() - t
    if os.waitstatus_to_exitcode(status) != 0:
        raise RuntimeError(f"jaxgear run {case} ({tree}) failed: {err.strip()[-800:]}")
    with open(record) as f:
        rec = json.load(f)
    by_name = rec["by_name"]
    return {
        "wall_s": wall,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "user_s": usage.ru_utime,
        "sys_s": usage.ru_stime,
        "max_rss_MB": usage.ru_maxrss / 1024.0,
        "load_at_start": load0,
        "load_at_end": list(os.getloadavg()),
        "xla_compilations": sum(r[1] for r in by_name),
        "backend_compile_s": float(rec["seconds"].get(_BACKEND, 0.0)),
        "read_back": int(rec["events"].get(_HITS, 0)),
        "compilations_by_program": [r for r in by_name if r[2] >= 0.2],
    }


def paired_runs(trees: dict, cases, *, second: bool = False, verbose: bool = True) -> list:
    """``jaxgear run`` of each case with each tree of ``trees`` ({label: source folder}), one
    after the other per case; ``second``: a second run of each on the cache its first wrote.
    Returns the rows (case, code label, first[, second])."""
    rows = []
    for case in cases:
        for label, tree in trees.items():
            with tempfile.TemporaryDirectory(prefix="jaxgear-run-bench-") as work:
                cache = os.path.join(work, "xla")
                row = {"case": case, "code": label}
                row["first"] = _one_run(tree, case, cache, work, "first")
                if second:
                    row["second"] = _one_run(tree, case, cache, work, "second")
            rows.append(row)
            if verbose:
                f = row["first"]
                line = (
                    f"{case:24s} {label:7s} first: CPU {f['cpu_s']:6.1f} s wall {f['wall_s']:6.1f}"
                    f" s, {f['xla_compilations']} compilations ({f['backend_compile_s']:.1f} s)"
                )
                if second:
                    s = row["second"]
                    line += f"; second: CPU {s['cpu_s']:6.1f} s wall {s['wall_s']:6.1f} s"
                print(line, flush=True)
    return rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--before", required=True, help="source tree of the code before")
    p.add_argument("--after", default=".", help="source tree of the code after (default .)")
    p.add_argument("--cases", required=True, help="embedded case names, comma-separated")
    p.add_argument("--second", action="store_true", help="a second run on the first's cache")
    p.add_argument("--out", required=True, help="the JSON record to write")
    p.add_argument("--note", default="", help="what changed between the trees")
    a = p.parse_args(argv)
    env = environment()
    rows = paired_runs({"before": a.before, "after": a.after}, a.cases.split(","), second=a.second)
    result = {
        "benchmark": "run-cases-paired",
        "what": "CPU time (user + sys, os.wait4), wall time and XLA compilations of `jaxgear "
        "run CASE --quiet` with an empty persistent compilation cache (first run; `second`: "
        "again on the cache the first wrote), fresh processes, the code before and after run "
        "one after the other per case under the same load; wall times follow the load, CPU "
        "times and compilation counts are the figures to compare. compilations_by_program: "
        "[program, compilations, seconds] of the programs that took >= 0.2 s in all",
        "change": a.note,
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "environment": env,
        "results": rows,
    }
    with open(a.out, "w") as f:
        json.dump(result, f, indent=1)
    return 0


if __name__ == "__main__":
    sys.exit(main())
