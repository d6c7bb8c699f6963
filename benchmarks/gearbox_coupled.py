"""What the coupled gearbox costs (jaxgear.gearbox, docs/gearbox.md "Cost"): the coupled sweep of
the embedded ``nrel-5mw-gearbox`` as ``jaxgear run``'s coupled section runs it
(:func:`jaxgear.cli.gearbox.coupled_sweep`: every stage's cells in one Newmark run per input
speed, vmapped, and the coupled modes), called twice in one process (the first compiles, the
second does not), and the two-stage example's single run (examples/gearbox_two_stage.py) beside
it. The per-stage runs of ``jaxgear run nrel-5mw-gearbox`` are not repeated here (their own
benchmarks time them).

Writes docs/bench/bench_gearbox_coupled.json (the machine as benchmarks/_timing.py's
``environment()``). From the repository root: ``python -m benchmarks.gearbox_coupled``.
"""

from __future__ import annotations

import json
import pathlib
import runpy
import tempfile
import time

import jax

jax.config.update("jax_enable_x64", True)

import jaxgear.io as jio
from benchmarks._timing import environment
from jaxgear import gearbox as gb
from jaxgear.cli.gearbox import coupled_sweep

ROOT = pathlib.Path(__file__).resolve().parents[1]


def main() -> dict:
    out: dict = {"machine": environment()}
    form = jio.load_case("nrel-5mw-gearbox").form
    with tempfile.TemporaryDirectory() as tmp:
        for call in ("first", "second"):
            t, c = time.perf_counter(), time.process_time()
            res = coupled_sweep(form, tmp)
            out[f"nrel_coupled_sweep_{call}"] = {
                "wall_s": time.perf_counter() - t, "cpu_s": time.process_time() - c,
                "speeds": len(res["input_speeds_rad_s"]),
                "max_dynamic_factor": res["max_dynamic_factor"]}
    two_stage = runpy.run_path(str(ROOT / "examples" / "gearbox_two_stage.py"))["two_stage"]
    chain, run = two_stage()
    for call in ("first", "second"):
        t = time.perf_counter()
        r = gb.gearbox_dynamics(chain, run, 100.0)
        r.dynamic_factors.block_until_ready()
        out[f"two_stage_run_{call}_wall_s"] = time.perf_counter() - t
    path = ROOT / "docs" / "bench" / "bench_gearbox_coupled.json"
    path.write_text(json.dumps(out, indent=1) + "\n", encoding="utf-8")
    print(json.dumps(out, indent=1))
    return out


if __name__ == "__main__":
    main()
