"""``jaxgear bench robust``: Monte Carlo throughput over deviation realisations (docs/robust.md,
"Benchmark"): realisations per second (quasi-static) and realisations × speeds per second
(dynamics) of :func:`jaxgear.robust_samples` on one process and on two processes joined by
``jax.distributed`` on the loopback address (one CPU device each), against a careful baseline:
a Python loop over the realisations calling the same jit-compiled model, one realisation per
call. Timing rule (benchmarks/_timing.py): a warm-up call, then the minimum over repeats."""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
from jaxgear.scenes import TorsionalDynamics, disc_inertia

from ._processes import free_port, run_processes
from ._timing import environment, min_time

__all__ = ["bench_robust"]

ROOT = Path(__file__).resolve().parents[1]
GRADE = 6


def _problems(quick: bool):
    """The quasi-static and the dynamic problem of the accessory spur pair (Weber, 8 slices;
    4 quick), its tip relief, grade-6 deviations of both gears, one pinion revolution."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=4 if quick else 8)
    p = case.pair
    z1 = p.pinion.teeth
    theta = jg.mesh_positions(mesh, 8, z1)
    qs = jg.QuasiStaticMetrics(mesh, case.modifications, jnp.asarray(case.torque), theta)
    inertia = [
        disc_inertia(case.density, r, m.face_width)
        for r, m in zip(p.tip_radii, (p.pinion, p.gear), strict=True)
    ]
    model = jd.dynamic_model(
        TorsionalDynamics(mesh, *inertia), case.modifications, case.torque, revolutions=1
    )
    crit = float(model.critical_speeds()[-1])
    speeds = jnp.asarray(crit * np.linspace(0.6, 1.2, 2 if quick else 4))
    steps = 16 if quick else 32
    dyn = jd.DynamicMetrics(model, speeds, jd.Newmark(steps), jd.SteadyState(z1 + 5, z1))
    sampler = jg.DeviationSampler.for_grade(p, GRADE)
    return qs, dyn, sampler, {"slices": mesh.n_slices, "steps_per_period": steps}


def _throughput(problem, sampler, samples, batch, repeats):
    key = jax.random.key(0)
    return min_time(
        lambda: jg.robust_samples(problem, sampler, key, samples, batch_size=batch),
        repeats,
        block=lambda r: r,  # robust_samples returns NumPy arrays: already done
    )


def _loop(problem, sampler, samples, repeats):
    """The baseline: one jit-compiled realisation per call from a Python loop."""
    one = eqx.filter_jit(lambda p, s, k: p(s(k)))
    key = jax.random.key(0)

    def run():
        return [
            jax.block_until_ready(one(problem, sampler, jax.random.fold_in(key, i)))
            for i in range(samples)
        ]

    return min_time(run, repeats, block=lambda r: r)


def _worker(argv):
    """One process of the two-process measurement: joins jax.distributed, times robust_samples
    on both problems, process 0 writes the times."""
    pid, n, port, out, quick = int(argv[0]), int(argv[1]), argv[2], argv[3], argv[4] == "1"
    jax.config.update("jax_enable_x64", True)
    jax.distributed.initialize(
        coordinator_address=f"127.0.0.1:{port}", num_processes=n, process_id=pid
    )
    qs, dyn, sampler, _ = _problems(quick)
    s_qs, s_dyn, reps = _sizes(quick)
    t_qs = _throughput(qs, sampler, s_qs, 16, reps)
    t_dyn = _throughput(dyn, sampler, s_dyn, 4, reps)
    if pid == 0:
        Path(out).write_text(json.dumps({"qs": t_qs, "dyn": t_dyn, "devices": jax.device_count()}))


def _sizes(quick):
    return (16, 4, 1) if quick else (128, 16, 3)


def _two_processes(quick: bool) -> dict:
    port = free_port()
    out = Path(os.environ.get("TMPDIR", "/tmp")) / f"jaxgear-bench-robust-{os.getpid()}.json"
    env = dict(os.environ, JAX_PLATFORMS="cpu", PYTHONPATH=str(ROOT))
    env.pop("XLA_FLAGS", None)
    argv = [sys.executable, "-m", "benchmarks._robust"]
    try:
        run_processes(
            [argv + [str(i), "2", str(port), str(out), "1" if quick else "0"] for i in range(2)],
            env=env,
            cwd=ROOT,
            timeout=3600,
        )
    except RuntimeError as err:
        raise RuntimeError(f"bench robust: {err}") from None
    data = json.loads(out.read_text())
    out.unlink()
    return data


def bench_robust(out_dir: str, *, quick: bool = False) -> dict:
    """Measure and write ``bench_robust.json`` to ``out_dir``. Returns the JSON dict."""
    jax.config.update("jax_enable_x64", True)
    os.makedirs(out_dir, exist_ok=True)
    qs, dyn, sampler, info = _problems(quick)
    s_qs, s_dyn, reps = _sizes(quick)
    n_speeds = int(dyn.speeds.shape[0])
    t0 = time.perf_counter()
    one = {
        "qs": _throughput(qs, sampler, s_qs, 16, reps),
        "dyn": _throughput(dyn, sampler, s_dyn, 4, reps),
    }
    loop = {"qs": _loop(qs, sampler, s_qs, reps), "dyn": _loop(dyn, sampler, s_dyn, reps)}
    two = _two_processes(quick)

    def rates(t):
        return {
            "quasi_static_samples_per_s": s_qs / t["qs"],
            "dynamic_samples_x_speeds_per_s": s_dyn * n_speeds / t["dyn"],
        }

    result = {
        "what": "Monte Carlo throughput of jaxgear.robust_samples over grade-6 deviation "
        "realisations of the accessory spur pair (tip relief), one pinion revolution",
        "case": {
            "pair": "accessory-spur (45/86), Weber stiffness",
            **info,
            "quasi_static_positions": 8 * 45,
            "quasi_static_samples": s_qs,
            "dynamic_samples": s_dyn,
            "speeds": n_speeds,
            "dynamic_periods": "45 kept + 5 transient mesh periods per speed",
        },
        "baseline": "Python loop over realisations, one eqx.filter_jit-compiled realisation "
        "(sampler + model) per call, same dtype and device, compiled before timing",
        "one_process": rates(one),
        "two_processes": {**rates(two), "devices": two["devices"]},
        "loop_baseline": rates(loop),
        "speedup_one_process_vs_loop": {
            "quasi_static": loop["qs"] / one["qs"],
            "dynamics": loop["dyn"] / one["dyn"],
        },
        "speedup_two_vs_one_process": {
            "quasi_static": one["qs"] / two["qs"],
            "dynamics": one["dyn"] / two["dyn"],
        },
        "seconds": {"one": one, "two": {k: two[k] for k in ("qs", "dyn")}, "loop": loop},
        "wall_s": time.perf_counter() - t0,
        "environment": environment(),
        "note": "timing rule: one warm-up call, then the minimum over repeats; the two "
        "processes share this machine's cores (with 2 cores and other load the two-process "
        "figure shows the overhead of jax.distributed, not a cluster's scaling)",
    }
    jio.write_json(os.path.join(out_dir, "bench_robust.json"), result)
    return result


if __name__ == "__main__":
    _worker(sys.argv[1:])
