"""The cost of one objective evaluation with its gradient when a rolling bearing's clearance is
the design variable (docs/bearings.md, "As a design variable"): the ERP objective (mean over
the speeds) of the housed rolling example (examples/accessory-lumped3d-rolling.toml, 4 slices,
in the soft box of the housing tests, condensed to 6 kHz, 3 whine speeds, 2 harmonics:
tests/_housing.py's HOUSING_TABLE and WHINE_TABLE, as tests/test_optimise_bearings.py builds
it) with ``pinion_shaft.bearings[0].clearance`` the variable, at the case's 10 µm: the jitted value and
gradient, timed by :func:`benchmarks._timing.min_time` (one warm-up call that compiles, then
the minimum over repeats); the problem's build (:func:`jaxgear.io.case_problem`: the operating
point, the bearings' design, the model and the acoustic path) timed once, and the compiling
call.

Run from the checkout's root (one record per code version, e.g. before and after a change)::

    python -m benchmarks.bearing_clearance_objective --out docs/bench/NAME.json

Benchmarks are not tests: timings are measured, never asserted."""

from __future__ import annotations

import argparse
import os
import pathlib
import subprocess
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
ROLLING = ROOT / "examples" / "accessory-lumped3d-rolling.toml"
VAR = "pinion_shaft.bearings[0].clearance"


def _commit() -> str:
    try:
        return subprocess.run(["git", "-C", str(ROOT), "rev-parse", "HEAD"], check=True,
                              capture_output=True, text=True).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--repeats", type=int, default=5, help="timed calls after the warm-up")
    p.add_argument("--out", required=True, help="the JSON record to write")
    p.add_argument("--label", default="", help="the code version measured, in words")
    a = p.parse_args(argv)

    import equinox as eqx
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    import jaxgear.io as jio

    sys.path.insert(0, str(ROOT / "tests"))  # the housing tests' box and whine, one home
    from _housing import HOUSING_TABLE, WHINE_TABLE

    from ._timing import environment, first_call, min_time, write_record

    env = environment()
    with tempfile.TemporaryDirectory() as tmp:
        path = os.path.join(tmp, "housed-rolling.toml")
        pathlib.Path(path).write_text(ROLLING.read_text() + HOUSING_TABLE + WHINE_TABLE)
        case = jio.load_case(path)
        t = time.perf_counter()
        problem = jio.case_problem(case, VAR, "erp", reduce="mean")
        t_build = time.perf_counter() - t
    x = jnp.asarray(problem.from_physical(problem.case_values(case.modifications)))
    value_and_grad = eqx.filter_jit(lambda p, x: jax.value_and_grad(p.value)(x))
    t_first = first_call(lambda: value_and_grad(problem, x))
    t_eval = min_time(lambda: value_and_grad(problem, x), repeats=a.repeats, warmup=False)
    value, grad = value_and_grad(problem, x)
    print(f"build {t_build:.2f} s, first (compiling) value+grad {t_first:.2f} s, "
          f"value+grad min {t_eval:.3f} s over {a.repeats}; value {float(value):.12g}, "
          f"grad {float(grad[0]):.12g}; load {os.getloadavg()}", flush=True)
    write_record(a.out, {
        "benchmark": "bearing-clearance-objective",
        "what": "jitted value and gradient of the ERP objective (mean over 3 speeds) of the "
        "housed rolling example with pinion_shaft.bearings[0].clearance the variable, at "
        "10 um; build: jaxgear.io.case_problem; first: the compiling call; eval: min over "
        "repeats after it",
        "date": time.strftime("%Y-%m-%d", time.gmtime()),
        "commit": _commit(),
        "label": a.label,
        "environment": env,
        "load_average_at_end": list(os.getloadavg()),
        "repeats": a.repeats,
        "seconds": {"build": t_build, "first_value_and_grad": t_first,
                    "value_and_grad": t_eval},
        "value": float(value),
        "gradient": [float(g) for g in grad],
    })
    return 0


if __name__ == "__main__":
    sys.exit(main())
