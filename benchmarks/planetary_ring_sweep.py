"""Cost of the dynamic-factor sweep of a planetary stage with a flexible ring: the embedded
``nrel-5mw-stage2`` (three planets, 18/36/-93, the ring the embedded ``nrel-5mw-stage2-ring``
condensed on its 93 tooth stations: 186 ring coordinates beside the stage's 18), planar model in
the carrier frame, the meshes from real contact (ISO 6336), 40 mesh periods of 66 steps per
speed (``jaxgear run``'s defaults).

Part 1 (``jaxgear run``'s first-look sweep, :func:`jaxgear.cli.planetary_sweep.sweep_summary`,
8 input speeds): the rigid ring against the condensed ring massless (``dynamics =
"quasi-static"``), with its stations' mass (``"mass"``) and in 24 modes plus the static
correction (``"modal"``): process CPU seconds, wall seconds and the XLA compilations of each
(``jax.monitoring``), the largest ring deflection and DF. The station models (massless and with
mass: 204 coordinates, the contact solved on all of them, a dense factorisation per contact
pass) cost over a minute of CPU per speed: they run the first of the 8 speeds only (``speeds``
gives how many) and the 8-speed figure is an estimate (the speeds are vmapped: the cost is per
speed, after one compilation).

Part 2: the 100-speed sweep (0.2 to 1.2 x the operating speed) with the modal ring, its CPU and
wall seconds (a first call compiles; the time of a second call is given too), or, with
``--speeds 10``, 10 speeds and the extrapolation to 100 stated as an estimate.

Writes docs/bench/bench_planetary_ring_sweep.json (or ``--out``), the machine as
benchmarks/_timing.py's ``environment()``. From the repository root:
``python -m benchmarks.planetary_ring_sweep [--speeds 100] [--skip-part1] [--out FILE]``.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import time
import tomllib

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

import jaxgear.io as jio  # noqa: E402
from benchmarks._timing import CompileCounter, environment  # noqa: E402
from jaxgear.cli.planetary_sweep import run_speeds, sweep_summary  # noqa: E402

OUT = pathlib.Path(__file__).parents[1] / "docs" / "bench" / "bench_planetary_ring_sweep.json"
CASE, BODY, MODES = "nrel-5mw-stage2", "nrel-5mw-stage2-ring", 24
COMPILES = CompileCounter()


def case(dynamics: str | None):
    """The embedded stage-2 case with its ring rigid (None) or condensed with ``dynamics``."""
    data = tomllib.loads(jio.embedded_case_text(CASE))
    if dynamics is not None:
        ring = data["planetary"]["ring"]
        ring.update(model="condensed", body=BODY, dynamics=dynamics)
        if dynamics == "modal":
            ring["modes"] = MODES
    return jio.parse_train(data)


#: the station models' speeds in part 1 (of the 8): the rest is extrapolated
STATION_SPEEDS = 1


def timed(c, speeds) -> dict:
    """One sweep_summary of case ``c`` at ``speeds``: CPU, wall, compilations, its numbers."""
    s, timing = COMPILES.timed(lambda: sweep_summary(c.form, c, speeds)[0])
    out = {
        **timing,
        "speeds": len(speeds),
        "max_dynamic_factor": s["max_dynamic_factor"],
        "max_dynamic_factor_mesh": s["max_dynamic_factor_mesh"],
        "max_k_gamma": s["max_k_gamma"],
        "dynamic_factor_mesh_first_speed": s["dynamic_factor_mesh"][0],
        "result_nonzero": int(sum(1 for r in s["result"] if r)),
    }
    if "max_ring_deflection_m" in s:
        out["max_ring_deflection_m"] = s["max_ring_deflection_m"]
    return out


def compare(p1: dict, part2: dict) -> dict:
    """The modal ring against the station model with mass: the DF per mesh at the first speed
    (relative difference) and the CPU per speed (the station run's less its compilation, the
    modal sweep's second call: no compilation)."""
    a = np.asarray(p1["modal"]["dynamic_factor_mesh_first_speed"])
    b = np.asarray(p1["mass"]["dynamic_factor_mesh_first_speed"])
    station = (p1["mass"]["cpu_s"] - p1["mass"]["compile_s"]) / p1["mass"]["speeds"]
    modal = part2["second_call"]["cpu_s"] / part2["speeds"]
    return {
        "modal_vs_mass_first_speed_df_rel_diff": float(np.max(np.abs(a / b - 1))),
        "station_mass_cpu_s_per_speed": station,
        "modal_cpu_s_per_speed": modal,
        "station_vs_modal_cpu_ratio_per_speed": station / modal,
    }


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--speeds", type=int, default=100)
    ap.add_argument("--skip-part1", action="store_true")
    ap.add_argument("--out", type=pathlib.Path, default=OUT)
    args = ap.parse_args()
    machine = environment()
    loads = [machine["load_average_at_start"][0]]
    result = {
        "what": __doc__.split("\n\n")[0],
        "case": CASE, "ring_body": BODY, "modes": MODES,
        "machine": machine,
        "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
    }
    if not args.skip_part1:
        part1 = {}
        for name, dyn in (("rigid", None), ("quasi-static", "quasi-static"), ("mass", "mass"),
                          ("modal", "modal")):
            c = case(dyn)
            speeds = run_speeds(c)
            if name in ("quasi-static", "mass"):
                part1[name] = timed(c, speeds[:STATION_SPEEDS])
                part1[name]["estimate_8_speeds_cpu_s"] = (
                    part1[name]["cpu_s"] * len(speeds) / STATION_SPEEDS)
            else:
                part1[name] = timed(c, speeds)
            loads.append(os.getloadavg()[0])
            print(name, json.dumps(part1[name]), flush=True)
        result["part1_run_sweep_8_speeds"] = part1
    c = case("modal")
    lo, hi, _ = (0.2, 1.2, 0)
    speeds = np.linspace(lo, hi, args.speeds) * c.speed
    first = timed(c, speeds)
    loads.append(os.getloadavg()[0])
    second = timed(c, speeds)
    loads.append(os.getloadavg()[0])
    part2 = {"speeds": args.speeds, "first_call": first, "second_call": second}
    if args.speeds != 100:
        part2["estimate_100_speeds_cpu_s"] = second["cpu_s"] * 100 / args.speeds
        part2["estimate_note"] = ("an estimate: the second call's CPU time scaled linearly to 100 "
                                  "speeds (the speeds are vmapped: the cost is per speed)")
    if "part1_run_sweep_8_speeds" in result:
        result.update(compare(result["part1_run_sweep_8_speeds"], part2))
    print("part2", json.dumps(part2), flush=True)
    result["part2_modal_sweep"] = part2
    result["load_average_1min"] = loads
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(result, indent=1) + "\n")
    print("written", args.out)


if __name__ == "__main__":
    main()
