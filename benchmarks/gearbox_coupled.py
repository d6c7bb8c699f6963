"""What the coupled gearbox costs (jaxgear.gearbox, docs/gearbox.md "Cost").

1. ``jaxgear run nrel-5mw-gearbox --quiet`` twice in fresh processes sharing one persistent
   compilation cache folder (``JAXGEAR_XLA_CACHE``), empty before the first run: the whole
   command's wall and CPU seconds (user + sys of the process and its threads, ``os.wait4``),
   and inside it the coupled section (:func:`jaxgear.cli.gearbox.coupled_sweep`: the resolved
   sweep, every stage's cells in one Newmark run per input speed, and the coupled modes) timed
   by a wrapper (wall, and the process's CPU seconds over the call); the rest of the command
   (start-up, each stage's own run, the torsional chain's modes) beside it as the difference.
2. The two-stage example's single run (examples/gearbox_two_stage.py), first and second call in
   this process.

Writes docs/bench/bench_gearbox_coupled.json and docs/img/gearbox_coupled_df.png (the second
run's coupled.png) (the machine as benchmarks/_timing.py's
``environment()``, with the 1-minute load average before each run: the timings are only as
idle as the machine was). From the repository root: ``python -m benchmarks.gearbox_coupled``.
"""

from __future__ import annotations

import json
import os
import pathlib
import runpy
import shutil
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]

# One `jaxgear run` whose coupled section is timed (wall, process CPU) into argv[1].
_PROBE = """
import json, sys, time
import jaxgear.cli.gearbox as g
_orig = g.coupled_sweep
rec = {}
def _timed(form, out):
    t, c = time.perf_counter(), time.process_time()
    res = _orig(form, out)
    rec.update(coupled_wall_s=time.perf_counter() - t, coupled_cpu_s=time.process_time() - c,
               speeds=len(res["input_speeds_rad_s"]), time_plan=res["time_plan"],
               max_dynamic_factor=res["max_dynamic_factor"], worst_mesh=res["worst_mesh"],
               result=res["result"])
    return res
g.coupled_sweep = _timed
from jaxgear.cli import main
status = main(sys.argv[2:])
rec["status"] = status
with open(sys.argv[1], "w") as f:
    json.dump(rec, f)
"""


def _cli_run(case: str, cache: str, work: str, name: str) -> dict:
    from benchmarks._xla_cache import _env, _timed

    record = os.path.join(work, f"{name}.json")
    cmd = [sys.executable, "-c", _PROBE, record, "run", case, "--quiet",
           "--out", os.path.join(work, name)]
    load = os.getloadavg()[0]
    wall, cpu, err, code = _timed(cmd, _env(cache))
    if code != 0:
        raise RuntimeError(f"jaxgear run {case} failed: {err.strip()[-500:]}")
    with open(record) as f:
        rec = json.load(f)
    out = {"wall_s": wall, **cpu, "load_average_1min_at_start": load, **rec}
    out["rest_wall_s"] = wall - rec["coupled_wall_s"]
    out["rest_cpu_s"] = cpu["cpu_s"] - rec["coupled_cpu_s"]
    return out


def main() -> dict:
    import jax

    jax.config.update("jax_enable_x64", True)
    from benchmarks._timing import environment
    from jaxgear import gearbox as gb

    out: dict = {
        "what": "jaxgear run nrel-5mw-gearbox --quiet: first run (empty compilation cache) and "
        "second (the cache the first wrote), fresh processes; coupled_*: the coupled section "
        "(resolved sweep + coupled modes) inside the run; rest_*: the rest of the command "
        "(start-up, the per-stage runs, the chain's modes); cpu_s: user + sys of the process "
        "and its threads. Then the two-stage example's single coupled run in this process.",
        "machine": environment(),
    }
    with tempfile.TemporaryDirectory(prefix="jaxgear-coupled-bench-") as work:
        cache = os.path.join(work, "xla")
        for call in ("first", "second"):
            row = _cli_run("nrel-5mw-gearbox", cache, work, call)
            if call == "second":  # the docs' figure (docs/gearbox.md) from this run
                shutil.copyfile(os.path.join(work, call, "coupled.png"),
                                ROOT / "docs" / "img" / "gearbox_coupled_df.png")
            out[f"nrel_run_{call}"] = row
            print(f"nrel-5mw-gearbox {call}: {row['wall_s']:.1f} s wall ({row['cpu_s']:.1f} s "
                  f"CPU); coupled section {row['coupled_wall_s']:.1f} s wall "
                  f"({row['coupled_cpu_s']:.1f} s CPU); the rest {row['rest_wall_s']:.1f} s "
                  f"({row['rest_cpu_s']:.1f} s CPU); load {row['load_average_1min_at_start']:.2f}",
                  flush=True)
    two_stage = runpy.run_path(str(ROOT / "examples" / "gearbox_two_stage.py"))["two_stage"]
    chain, run = two_stage()
    for call in ("first", "second"):
        t = time.perf_counter()
        r = gb.gearbox_dynamics(chain, run, 100.0)
        r.dynamic_factors.block_until_ready()
        out[f"two_stage_run_{call}_wall_s"] = time.perf_counter() - t
    out["load_average_at_end"] = list(os.getloadavg())
    path = ROOT / "docs" / "bench" / "bench_gearbox_coupled.json"
    path.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    return out


if __name__ == "__main__":
    main()
