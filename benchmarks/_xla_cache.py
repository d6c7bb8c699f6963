"""``jaxgear bench xla-cache``: how long ``jaxgear run`` takes on each embedded case, first run
included, and what JAX's persistent compilation cache (jaxgear/cli/xla_cache.py) saves a user
who runs a case again. For each embedded case, two identical ``jaxgear run CASE --quiet`` in
fresh processes sharing a fresh, empty cache folder: the first compiles and writes the cache,
the second reads it back. A case with condensed FE bodies has them built (or read from
fem_prep's cache, ``$FEM_PREP_CACHE``) in a process of its own before the first run, so that
both runs time the main job with its bodies cached (``bodies_s``: that preparation).
Recorded per case: both wall times (the whole process, start-up included) and CPU times (user +
sys of the process and its threads: on a loaded machine the robust figure), the peak resident
memory, their ratio (second / first), JAX's compilation events of each run (programs written to
and read from the cache, backend compile seconds) and the cache's size.

Benchmarks are not tests: timings are measured, never asserted; machine, load, dtype and
versions are recorded (benchmarks/_timing.py)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time

from jaxgear.cli.xla_cache import MIN_COMPILE_SECS
from jaxgear.io import atomic_open, list_cases

from ._timing import environment

__all__ = ["bench_xla_cache", "xla_cache_chart"]

# One CLI run that records JAX's compilation events (jax.monitoring) into argv[1].
_PROBE = """
import collections, json, sys
from jax import monitoring
events = collections.Counter()
seconds = collections.Counter()
monitoring.register_event_listener(lambda name, **kw: events.update([name]))
def _duration(name, secs, **kw):
    seconds[name] += secs
monitoring.register_event_duration_secs_listener(_duration)
# the programs JAX compiled but did not write, by its reason (its debug log records)
import logging
not_cached = collections.Counter()
class _NotCached(logging.Handler):
    def emit(self, record):
        text = record.getMessage()
        if text.startswith("Not writing persistent cache entry"):
            reason = text.split(" because ", 1)[-1].split(" (", 1)[0] if " because " in text else "size"
            not_cached[reason] += 1
for _name in ("jax._src.compiler", "jax._src.compilation_cache"):
    _log = logging.getLogger(_name)
    _log.setLevel(logging.DEBUG)
    _log.addHandler(_NotCached())
    _log.propagate = False
from jaxgear.cli import main
status = main(sys.argv[2:])
with open(sys.argv[1], "w") as f:
    json.dump({"status": status, "events": events, "seconds": seconds, "not_cached": not_cached}, f)
"""
_EVENTS = {
    "written": "/jax/compilation_cache/cache_misses",
    "read_back": "/jax/compilation_cache/cache_hits",
    "compile_requests": "/jax/compilation_cache/compile_requests_use_cache",
}
_BACKEND = "/jax/core/compile/backend_compile_duration"

# The case's condensed bodies built or read from fem_prep's cache (none for a rigid scene).
_BODIES = """
import sys
from jaxgear.io import load_bodies, load_case
case = load_case(sys.argv[1])
if case.scene is not None:
    load_bodies(case.scene)
"""


def _timed(cmd: list[str], env: dict) -> tuple[float, dict, str, int]:
    """Run ``cmd``: (wall s, {user_s, sys_s, cpu_s, max_rss_MB} of the process and its threads
    from ``os.wait4``, stderr, exit status)."""
    t = time.perf_counter()
    proc = subprocess.Popen(cmd, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    err = proc.stderr.read().decode(errors="replace")
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = os.waitstatus_to_exitcode(status)
    wall = time.perf_counter() - t
    cpu = {
        "user_s": usage.ru_utime,
        "sys_s": usage.ru_stime,
        "cpu_s": usage.ru_utime + usage.ru_stime,
        "max_rss_MB": usage.ru_maxrss / 1024.0,  # Linux: kB
    }
    return wall, cpu, err, proc.returncode


def _env(cache: str) -> dict:
    env = dict(os.environ)
    for key in ("JAX_COMPILATION_CACHE_DIR", "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"):
        env.pop(key, None)  # the CLI's own settings
    env["JAXGEAR_XLA_CACHE"] = cache
    return env


def _bodies(case: str, cache: str) -> float:
    """Wall time (s) of building or reading the case's condensed bodies, in a process of its
    own (so that the timed runs find them in fem_prep's cache)."""
    wall, _, err, code = _timed([sys.executable, "-c", _BODIES, case], _env(cache))
    if code != 0:
        raise RuntimeError(f"the bodies of {case} failed: {err.strip()[-500:]}")
    return wall


def _one_run(case: str, cache: str, work: str, name: str) -> dict:
    record = os.path.join(work, f"{name}.json")
    cmd = [sys.executable, "-c", _PROBE, record, "run", case, "--quiet"]
    cmd += ["--out", os.path.join(work, name)]
    load = os.getloadavg()[0] if hasattr(os, "getloadavg") else None
    wall, cpu, err, code = _timed(cmd, _env(cache))
    if code != 0:
        raise RuntimeError(f"jaxgear run {case} failed: {err.strip()[-500:]}")
    with open(record) as f:
        rec = json.load(f)
    out = {"wall_s": wall, **cpu, "load_average_1min_at_start": load}
    out.update({k: int(rec["events"].get(v, 0)) for k, v in _EVENTS.items()})
    # programs compiled in this run (asked of the cache, not read back): a second run's cache
    # misses, each with the reason it was not written (not_cached)
    out["compiled"] = out["compile_requests"] - out["read_back"]
    out["not_cached"] = dict(rec.get("not_cached", {}))
    out["backend_compile_s"] = float(rec["seconds"].get(_BACKEND, 0.0))
    return out


def bench_xla_cache(out_dir, quick: bool = False, cases=None, verbose: bool = True) -> dict:
    """Time a first (empty cache) and a second (warm cache) ``jaxgear run`` of each case and
    write ``bench_xla_cache.json`` and ``bench_xla_cache.png`` into ``out_dir``.

    Args:
        out_dir: output folder (created if missing).
        quick: ``accessory-spur`` only (unless ``cases`` names others).
        cases: embedded case names (default: every embedded case; the flexible ones and
            ``two-stage`` take minutes per run on a loaded 2-core CPU; a flexible case's
            bodies are built first when fem_prep's cache does not hold them).
    """
    known = list_cases()
    if cases is None:
        cases = ["accessory-spur"] if quick else known
    for c in cases:
        if c not in known:
            raise ValueError(f"bench xla-cache: unknown case {c!r} (embedded: {', '.join(known)})")
    os.makedirs(out_dir, exist_ok=True)
    rows = []
    env = environment()
    for case in cases:
        with tempfile.TemporaryDirectory(prefix="jaxgear-xla-bench-") as work:
            cache = os.path.join(work, "xla")
            bodies = _bodies(case, os.path.join(work, "xla-bodies"))
            first = _one_run(case, cache, work, "first")
            second = _one_run(case, cache, work, "second")
            names = [n for n in os.listdir(cache) if n.endswith("-cache")]
            size = sum(os.path.getsize(os.path.join(cache, n)) for n in names)
        row = {
            "case": case,
            "first": first,
            "second": second,
            "ratio_second_to_first": second["wall_s"] / first["wall_s"],
            "ratio_second_to_first_cpu": second["cpu_s"] / first["cpu_s"],
            "bodies_s": bodies,
            "cache_entries": len(names),
            "cache_bytes": size,
        }
        rows.append(row)
        if verbose:
            print(
                f"{case:24s} first {first['wall_s']:7.1f} s (CPU {first['cpu_s']:6.1f} s)  second "
                f"{second['wall_s']:7.1f} s (CPU {second['cpu_s']:6.1f} s)  "
                f"ratio {row['ratio_second_to_first']:.2f}  ({len(names)} programs, "
                f"{size / 2**20:.1f} MB; backend compile {first['backend_compile_s']:.1f} s → "
                f"{second['backend_compile_s']:.1f} s; second run: {second['compiled']} of "
                f"{second['compile_requests']} programs compiled again, not cached: "
                f"{second['not_cached'] or 'none'})",
                flush=True,
            )
    result = {
        "benchmark": "xla-cache",
        "what": "wall time of a first `jaxgear run CASE --quiet` (empty persistent compilation "
        "cache) and of a second identical one (the cache the first wrote), fresh processes, "
        "the case's condensed bodies built or read beforehand in a process of their own "
        "(bodies_s); cpu_s: user + sys of the run's process and threads (os.wait4), "
        "max_rss_MB its peak resident memory; "
        "written/read_back: JAX's /jax/compilation_cache/cache_misses and cache_hits events; "
        "backend_compile_s: the sum of /jax/core/compile/backend_compile_duration (a cache "
        "read counts there too); compiled: compile_requests - read_back, the programs a run "
        "compiled (in the second run: its cache misses), not_cached: the programs JAX "
        "compiled but did not write, by its reason (its debug log)",
        "min_compile_time_s": MIN_COMPILE_SECS,
        "cases_not_measured": [c for c in known if c not in cases],
        "environment": env,
        "results": rows,
    }
    with atomic_open(os.path.join(out_dir, "bench_xla_cache.json"), "w") as f:
        json.dump(result, f, indent=2)
    xla_cache_chart(result, os.path.join(out_dir, "bench_xla_cache.png"))
    return result


def xla_cache_chart(result: dict, path: str) -> None:
    """Bars of the first and second run's wall time per case, the ratio written above."""
    import numpy as np

    from jaxgear.cli import plots

    rows = result["results"]
    fig, ax = plots.new_figure()
    x = np.arange(len(rows))
    first = [r["first"]["wall_s"] for r in rows]
    second = [r["second"]["wall_s"] for r in rows]
    ax.bar(x - 0.2, first, 0.4, label="first run (empty cache)")
    ax.bar(x + 0.2, second, 0.4, label="second run (cache read back)")
    for k, r in enumerate(rows):
        ax.annotate(
            f"× {r['ratio_second_to_first']:.2f}",
            (k + 0.2, second[k]),
            xytext=(0, 3),
            textcoords="offset points",
            ha="center",
            fontsize=8,
        )
    ax.set_xticks(x)
    ax.set_xticklabels([r["case"] for r in rows], fontsize=8)
    ax.set_ylabel("wall time of `jaxgear run CASE --quiet` (s)")
    env = result["environment"]
    load = env.get("load_average_at_start")
    ax.set_title(
        f"persistent compilation cache ({env['platform']}, {env['cpu_affinity']} cores, "
        f"load {load[0]:.1f}, {env['dtype']}, JAX {env['jax']})"
        if load
        else f"persistent compilation cache ({env['platform']}, JAX {env['jax']})",
        fontsize=9,
    )
    ax.grid(alpha=0.3, axis="y")
    ax.legend(fontsize=8)
    plots.savefig(fig, path)
