"""``jaxgear bench device``: the batched workloads on the CPU and on an accelerator, in one run.

The six workloads where a user waits for many independent evaluations, each timed on every
platform JAX sees (the CPU always; a GPU when one is present), in the same process, with the
same inputs, so that the ratios are measured in one run:

1. **TE curves**: exact-contact transmission-error curves of the accessory spur pair over random
   (extent, depth) tip reliefs, ``jax.lax.map(..., batch_size=B)`` (vmap within chunks of B).
2. **Lumped speed sweep**: the torsional accessory pair (``benchmarks/_dynamics.py``'s model),
   Newmark with a fixed step count, every speed from the static equilibrium in one ``vmap``.
3. **Monte Carlo**: ISO 1328 grade-6 deviations of both gears (``benchmarks/_robust.py``'s
   problems): quasi-static TE metrics and dynamic factors per realisation, ``robust_samples``.
4. **Hybrid sweep**: the test pair with its condensed flexible wheel (287 condensed DOFs), the
   modal-basis Newmark over speeds (``jax.lax.map``: one speed's effective compliance at a time).
5. **Planetary sweep**: a 3-planet planar stage (``benchmarks/planetary_step.py``'s: 18
   coordinates, the contact cells of its 6 meshes, exact contact), the carrier-frame Newmark
   over carrier speeds in one ``vmap`` (``planetary_speed_sweep``), fixed steps.
6. **Gearbox sweep**: the two-stage coupled gearbox (``examples/gearbox_two_stage.py``: a
   4-planet torsional stage whose sun drives a spur pair through a shaft, 9 meshes' cells in one
   Newmark run), ``gearbox_speed_sweep`` (one ``vmap`` over carrier speeds), fixed steps.

Each row: wall time of the workload after a compiling call (min of repeats,
``jax.block_until_ready``), the compile time (first call minus the steady time), the throughput,
and the largest relative difference of the results from the CPU's (the same computation on
both: agreement is the accuracy check). ``bench_device.json`` is rewritten after each workload,
so an interrupted run keeps the finished rows.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from ._timing import environment, min_time

__all__ = ["bench_device"]

ROOT = Path(__file__).resolve().parents[1]
_HYBRID_CASE = ROOT / "tests" / "data" / "hybrid-test-case.toml"


def _timed(fn, repeats):
    """(first-call s, steady s, result) of ``fn()``: the first call compiles."""
    import jax

    t0 = time.perf_counter()
    result = jax.block_until_ready(fn())
    first = time.perf_counter() - t0
    steady = min_time(fn, repeats, warmup=False)
    return first, steady, result


def _where(result) -> str:
    """The device holding a JAX result (the check that a platform's row ran there)."""
    import jax

    leaf = jax.tree_util.tree_leaves(result)[0]
    return str(next(iter(leaf.devices()))) if isinstance(leaf, jax.Array) else "numpy"


def _row(items, unit, first, steady, values, **extra):
    return {
        "ran_on": _where(values),
        "items": int(items),
        "unit": unit,
        "time_s": steady,
        "compile_s": max(first - steady, 0.0),
        "per_s": items / steady,
        **extra,
    }, np.asarray(values, dtype=float)


def _te_curves(quick, dev):
    import jax
    import jax.numpy as jnp

    from jaxgear import LinearRelief, MemberModification, Modifications, quasi_static
    from jaxgear.io import load_case

    case = load_case("accessory-spur")
    mesh, torque = case.mesh_model(), case.torque
    n = 128 if quick else 8192
    rng = np.random.default_rng(1)
    ge = (jnp.asarray(rng.uniform(0.05, 0.6, n)), jnp.asarray(rng.uniform(0.0, 40e-6, n)))

    def curve(x):
        m = MemberModification(
            tip_relief_depth=x[1], tip_relief_extent=x[0], tip_relief_shape=LinearRelief()
        )
        return quasi_static(mesh, Modifications.symmetric(m), torque).te_rms

    rows, best, values = [], None, None
    for b in (32,) if quick else (64, 1024, 8192):
        g = jax.jit(lambda a, b=b: jax.lax.map(curve, a, batch_size=b))
        first, steady, te = _timed(lambda g=g: g(ge), 1 if quick else 2)
        row, values = _row(n, "TE curves", first, steady, te, batch_size=b)
        row["te_rms_m_every_%d" % (n // 8)] = np.asarray(te)[:: n // 8].tolist()
        rows.append(row)
        best = row if best is None or row["per_s"] > best["per_s"] else best
    return {**best, "rows": rows}, values


def _lumped_sweep(quick, dev):
    import jax.numpy as jnp

    from jaxgear.dynamics import Newmark, SteadyState, speed_sweep

    from ._dynamics import _bench_model

    _, model = _bench_model()
    wc = float(model.critical_speeds(1)[0])
    rows, values = [], None
    for n in (16,) if quick else (256, 4096, 16384):
        speeds = jnp.asarray(np.linspace(0.2, 3.0, n) * wc)

        def sweep(speeds=speeds):
            return speed_sweep(
                model, speeds, integrator=Newmark(32), window=SteadyState(20, 4)
            ).dynamic_factor

        first, steady, df = _timed(sweep, 1 if quick else 2)
        row, values = _row(n, "speeds", first, steady, df, steps_per_speed=32 * 20)
        rows.append(row)
    return {**rows[-1], "rows": rows}, values


def _monte_carlo(quick, dev):
    import jax

    import jaxgear as jg

    from ._robust import _problems

    qs, dyn, sampler, _ = _problems(quick)
    key = jax.random.key(0)
    rows, values = [], []
    for what, problem, n, batch in (
        ("quasi-static", qs, 64 if quick else 4096, 16 if quick else 512),
        ("dynamic", dyn, 8 if quick else 256, 4 if quick else 64),
    ):

        def run(problem=problem, n=n, batch=batch):
            return jg.robust_samples(problem, sampler, key, n, batch_size=batch, devices=[dev])

        first, steady, out = _timed(run, 1)
        leaves = [np.ravel(np.asarray(a, dtype=float)) for a in jax.tree_util.tree_leaves(out)]
        row, v = _row(n, f"{what} realisations", first, steady, np.concatenate(leaves))
        rows.append({**row, "ran_on": str(dev), "problem": what, "batch_size": batch})
        values.append(v)
    return {**rows[0], "rows": rows}, np.concatenate(values)


def _hybrid_sweep(quick, dev):
    import fem_prep
    import jax
    import jax.numpy as jnp

    from jaxgear.dynamics import ModalBasis, Newmark, SteadyState, dynamic_model, speed_sweep
    from jaxgear.io import load_case, static_scene

    case = load_case(_HYBRID_CASE)
    bodies = tuple(
        None if ref is None else fem_prep.condensed(fem_prep.load_body(ref))
        for ref in case.scene.bodies
    )
    scene, _ = static_scene(case, bodies=bodies)
    model = dynamic_model(scene, case.modifications, case.torque)
    n = 4 if quick else 64
    speeds = jnp.asarray(np.linspace(200.0, 1500.0, n))
    settings = {
        "integrator": Newmark(16 if quick else 32, basis=ModalBasis(20)),
        "window": SteadyState(4 if quick else 20, 2 if quick else 4),
    }

    def one_after_another():  # speed_sweep's own order (jax.lax.map: memory of one speed)
        return speed_sweep(model, speeds, **settings).dynamic_factor

    # the speeds side by side: jax.vmap over one-speed sweeps (memory of all speeds at once)
    side_by_side = jax.jit(
        jax.vmap(lambda w: speed_sweep(model, w[None], **settings).dynamic_factor[0])
    )
    rows, values = [], None
    for how, fn in (("lax.map", one_after_another), ("vmap", lambda: side_by_side(speeds))):
        first, steady, df = _timed(fn, 1)
        row, v = _row(n, "speeds", first, steady, df, order=how)
        rows.append(row)
        values = v if values is None else np.concatenate([values, v])
    best = min(rows, key=lambda r: r["time_s"])
    return {**best, "rows": rows, "condensed_dofs": int(bodies[-1].K.shape[0])}, values


def _planetary_sweep(quick, dev):
    import jax.numpy as jnp

    import jaxgear as jg

    from .planetary_step import stage

    st, meshes = stage(3)
    sweep_fn = jg.planetary.planetary_speed_sweep
    run_cls = jg.planetary.PlanetaryRun
    run = run_cls(sun_torque=800.0, steps_per_period=64, periods=4 if quick else 40,
                  keep_periods=2, damping_ratio=0.05)
    # carrier speeds whose mesh frequency spans 0.2..2 kHz (z_r = 84 teeth, ring held)
    rows, values = [], None
    for n in (8,) if quick else (64, 512, 2048):
        speeds = jnp.asarray(np.linspace(0.2e3, 2.0e3, n) * 2.0 * np.pi / 84.0)

        def sweep(speeds=speeds):
            out = sweep_fn(jg.planetary.PlanarPlanetary(), st, meshes, run, speeds)
            return jnp.concatenate(out.dynamic_factors, axis=-1)

        first, steady, df = _timed(sweep, 1)
        row, values = _row(n, "speeds", first, steady, df, steps_per_speed=64 * run.periods)
        rows.append(row)
    return {**rows[-1], "rows": rows}, values


def _gearbox_sweep(quick, dev):
    import importlib.util

    import jax.numpy as jnp

    from jaxgear import gearbox as gb

    spec = importlib.util.spec_from_file_location(
        "gearbox_two_stage", ROOT / "examples" / "gearbox_two_stage.py")
    example = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(example)
    chain, run = example.two_stage(steps_per_period=64, periods=2 if quick else 20,
                                   keep_periods=1)
    rows, values = [], None
    for n in (4,) if quick else (64, 256, 1024):
        speeds = jnp.asarray(np.linspace(150.0, 520.0, n))  # carrier rad/s: 1.9-6.6 kHz meshes

        def sweep(speeds=speeds):
            return gb.gearbox_speed_sweep(chain, run, speeds).dynamic_factors

        first, steady, df = _timed(sweep, 1)
        row, values = _row(n, "speeds", first, steady, df,
                           steps_per_speed=2 * 64 * run.periods)
        rows.append(row)
    return {**rows[-1], "rows": rows}, values


WORKLOADS = {
    "te_curves": _te_curves,
    "lumped_sweep": _lumped_sweep,
    "monte_carlo": _monte_carlo,
    "hybrid_sweep": _hybrid_sweep,
    "planetary_sweep": _planetary_sweep,
    "gearbox_sweep": _gearbox_sweep,
}


def bench_device(out_dir, *, quick: bool = False, only=None, verbose: bool = True) -> dict:
    """Time :data:`WORKLOADS` on every platform (CPU, GPU when present) in one run; write
    ``bench_device.json`` into ``out_dir`` after each workload and return the summary.

    ``only``: names of :data:`WORKLOADS` to run (default all).
    """
    import jax

    jax.config.update("jax_enable_x64", True)  # entry point: float64
    from jaxgear.io import write_json

    platforms = {"cpu": jax.devices("cpu")[0]}
    try:
        platforms["gpu"] = jax.devices("gpu")[0]
    except RuntimeError:
        pass
    out = {
        "quick": bool(quick),
        "machine": environment(),
        "platforms": {k: f"{d} ({getattr(d, 'device_kind', '')})" for k, d in platforms.items()},
        "timing": "first call compiles; then min wall time of repeats with "
        "jax.block_until_ready; ratio = CPU time / GPU time, same process, same inputs",
        "workloads": {},
    }
    path = Path(out_dir) / "bench_device.json"
    for name in only or WORKLOADS:
        rows, ref = {}, None
        for plat, dev in platforms.items():
            t0 = time.perf_counter()
            with jax.default_device(dev):
                row, values = WORKLOADS[name](quick, dev)
            row["wall_s"] = time.perf_counter() - t0
            if ref is None:
                ref = values
            scale = max(float(np.max(np.abs(ref))), 1e-300)
            row["max_rel_diff_from_cpu"] = float(np.max(np.abs(values - ref)) / scale)
            rows[plat] = row
            if verbose:
                print(
                    f"{name:13s} {plat}: {row['items']} {row['unit']} in {row['time_s']:.3g} s "
                    f"({row['per_s']:.4g}/s), compile {row['compile_s']:.3g} s, "
                    f"diff {row['max_rel_diff_from_cpu']:.2e}",
                    flush=True,
                )
        if "gpu" in rows:
            rows["gpu_speedup"] = rows["cpu"]["time_s"] / rows["gpu"]["time_s"]
        out["workloads"][name] = rows
        write_json(path, out)
    return out


if __name__ == "__main__":  # python -m benchmarks._device OUT [--quick] [names...]
    import sys

    args = [a for a in sys.argv[1:] if a != "--quick"]
    bench_device(args[0], quick="--quick" in sys.argv, only=args[1:] or None)
