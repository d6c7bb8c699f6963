"""What the Craig–Bampton ring adds and costs: the embedded ``nrel-5mw-stage2`` with its ring
``nrel-5mw-stage2-ring`` (93 stations; 378 fixed-interface DOFs of which 99 modes couple to the
stations), planar model, the meshes from real contact (ISO 6336), ``jaxgear run``'s first-look
sweep (8 input speeds, 40 mesh periods of 66 steps).

Part 1: the ring's nodal-diameter frequencies (the lowest 40 modes of each model) of the
station model (Guyan) and of the Craig–Bampton ring with every coupled fixed-interface mode,
against the condensed FE ring's own eigen-solution (relative errors per ND).

Part 2: the 8-speed sweep with the station ring in 24 modes plus the static correction
(``dynamics = "modal"``) against the Craig–Bampton ring (``"craig-bampton"``, every coupled
fixed-interface mode, 24 modes integrated plus the static correction), run back to back in one
process, each twice (modal, CB, modal, CB: the first call of the first compiles the programs
they share, the second calls compile nothing): CPU and wall seconds, XLA compilations, the DF
per mesh and speed (largest relative difference).

Writes docs/bench/bench_planetary_ring_cb.json (the machine as benchmarks/_timing.py's
``environment()``: CPU, dtype, JAX version, load; the load average after each part). From the
repository root: ``python -m benchmarks.planetary_ring_cb``.
"""

from __future__ import annotations

import json
import os
import pathlib
import time
import tomllib

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np  # noqa: E402

import fem_prep  # noqa: E402
import jaxgear.io as jio  # noqa: E402
from benchmarks._timing import CompileCounter, environment  # noqa: E402
from jaxgear.cli.planetary_sweep import run_speeds, sweep_summary  # noqa: E402

OUT = pathlib.Path(__file__).parents[1] / "docs" / "bench" / "bench_planetary_ring_cb.json"
CASE, BODY, N_MODES = "nrel-5mw-stage2", "nrel-5mw-stage2-ring", 40
COMPILES = CompileCounter()


def case(dynamics: str):
    data = tomllib.loads(jio.embedded_case_text(CASE))
    data["planetary"]["ring"].update(model="condensed", body=BODY, dynamics=dynamics)
    return jio.parse_train(data)


def nd_errors() -> dict:
    prep = fem_prep.prepare_ring(fem_prep.load_ring_body(BODY))
    ref = fem_prep.ring_nd_frequencies(prep, N_MODES)
    _, _, T = fem_prep.ring_craig_bampton(prep)
    z2 = 2 * prep.master_dofs.shape[0]
    out = {"condensed_hz": {str(n): f for n, f in ref.items()}, "coupled_modes": T.shape[1] - z2}
    for name, basis in (("guyan", T[:, :z2]), ("craig_bampton", T)):
        got = fem_prep.ring_nd_frequencies(prep, N_MODES, basis)
        out[f"{name}_rel_error"] = {str(n): got[n] / f - 1 for n, f in ref.items() if n in got}
    return out


def timed(c, speeds) -> dict:
    s, timing = COMPILES.timed(lambda: sweep_summary(c.form, c, speeds)[0])
    return {
        **timing,
        "ring_model": s["ring_model"],
        "dynamic_factor_mesh": s["dynamic_factor_mesh"],
        "max_dynamic_factor": s["max_dynamic_factor"],
        "max_ring_deflection_m": s.get("max_ring_deflection_m"),
        "result_nonzero": int(sum(1 for r in s["result"] if r)),
    }


def main() -> None:
    machine = environment()
    loads = [machine["load_average_at_start"]]
    result = {
        "what": __doc__.split("\n\n")[0],
        "case": CASE, "ring_body": BODY,
        "machine": machine,
        "date_utc": time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
    }
    t = time.process_time()
    result["part1_nd_frequencies"] = nd_errors()
    result["part1_cpu_s"] = time.process_time() - t
    loads.append(list(os.getloadavg()))
    part2 = {}
    for call in ("first", "second"):
        for name in ("modal", "craig-bampton"):
            c = case(name)
            key = f"{name}_{call}_call"
            part2[key] = timed(c, run_speeds(c))
            loads.append(list(os.getloadavg()))
            print(key, {k: v for k, v in part2[key].items() if k != "dynamic_factor_mesh"},
                  flush=True)
    a = np.asarray(part2["craig-bampton_second_call"]["dynamic_factor_mesh"])
    b = np.asarray(part2["modal_second_call"]["dynamic_factor_mesh"])
    part2["df_rel_diff_max"] = float(np.max(np.abs(a / b - 1)))
    part2["cpu_ratio_cb_over_modal_second_calls"] = (
        part2["craig-bampton_second_call"]["cpu_s"] / part2["modal_second_call"]["cpu_s"])
    result["part2_sweep_8_speeds"] = part2
    result["load_average"] = loads
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text(json.dumps(result, indent=1) + "\n")
    print("written", OUT, "df diff", part2["df_rel_diff_max"])


if __name__ == "__main__":
    main()
