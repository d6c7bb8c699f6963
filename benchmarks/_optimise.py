"""``jaxgear bench optimise``: gradient cost, optimiser vs SciPy and vs the 41×41 grid search.

All figures come from one run on one machine: jaxgear's jitted objective and gradient, the
optimistix L-BFGS solve (after compile), ``scipy.optimize.minimize`` (Nelder–Mead, and L-BFGS-B
with finite differences) calling the same jitted objective, and the vmapped 41×41 grid. Ratios are
what count.
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

from ._timing import environment, min_time

__all__ = ["bench_optimise"]


def _best_time(fn, repeats=5):
    return min_time(fn, repeats, warmup=False)


def bench_optimise(out_dir: str, quick: bool = False) -> dict:
    """Run the optimisation benchmark on the accessory-spur case; write ``bench_optimise.json``."""
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp
    import scipy
    import scipy.optimize
    from tqdm.auto import tqdm

    from jaxgear.io import atomic_open, case_problem, load_case
    from optimise import contour_map, minimise

    case = load_case("accessory-spur")
    ppp = 24 if quick else case.positions_per_pitch
    slices = 4 if quick else 10  # spur: every slice carries the same load, 10 is plenty
    n_grid = 11 if quick else 41
    problem = case_problem(
        case, "tip_relief.depth,tip_relief.extent", "te_rms", positions_per_pitch=ppp, slices=slices
    )
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    f = jax.jit(lambda x: problem.value(x))
    vg = jax.jit(jax.value_and_grad(lambda x: problem.value(x)))
    x0 = np.array([0.5, 0.12])
    steps = tqdm(total=4, desc="bench optimise")
    f(jnp.asarray(x0)).block_until_ready()
    vg(jnp.asarray(x0))[1].block_until_ready()
    t_f = _best_time(lambda: f(jnp.asarray(x0)).block_until_ready(), 20)
    t_vg = _best_time(lambda: vg(jnp.asarray(x0))[1].block_until_ready(), 20)
    steps.update()

    minimise(problem, x0, progress=False)  # compile
    t0 = time.perf_counter()
    ours = minimise(problem, x0, progress=False)
    t_ours = time.perf_counter() - t0
    steps.update()

    def scalar(x):
        return float(f(jnp.asarray(np.clip(x, lo, hi))))

    t0 = time.perf_counter()
    nm = scipy.optimize.minimize(
        scalar, x0, method="Nelder-Mead", options={"xatol": 1e-5, "fatol": 1e-8, "maxfev": 4000}
    )
    t_nm = time.perf_counter() - t0
    t0 = time.perf_counter()
    lb = scipy.optimize.minimize(
        scalar, x0, method="L-BFGS-B", bounds=list(zip(lo, hi)), options={"maxfun": 4000}
    )
    t_lb = time.perf_counter() - t0
    steps.update()

    G = np.linspace(lo[1], hi[1], n_grid)
    E = np.linspace(lo[0], hi[0], n_grid)
    contour_map(problem, G, E, None)  # compile for these shapes
    t0 = time.perf_counter()
    grid = contour_map(problem, G, E, None)
    t_grid = time.perf_counter() - t0
    k = np.unravel_index(np.argmin(grid), grid.shape)
    steps.update()
    steps.close()

    row = lambda name, x, v, n, t: {
        "method": name,
        "extent": float(x[1]),  # noqa: E731
        "depth_um": float(x[0]) * float(problem.delta_m) * 1e6,
        "objective": float(v),
        "evaluations": int(n),
        "wall_time_s": t,
    }
    methods = [
        row("jaxgear L-BFGS (optimistix, gradients)", ours.x, ours.value, ours.evaluations, t_ours),
        row("scipy Nelder-Mead", nm.x, nm.fun, nm.nfev, t_nm),
        row("scipy L-BFGS-B (finite differences)", lb.x, lb.fun, lb.nfev, t_lb),
        row(f"grid {n_grid}x{n_grid} (vmap)", [E[k[1]], G[k[0]]], grid[k], grid.size, t_grid),
    ]
    report = {
        "case": case.name,
        "positions_per_pitch": ppp,
        "slices": slices,
        "objective_time_s": t_f,
        "value_and_grad_time_s": t_vg,
        "gradient_cost_ratio": t_vg / t_f,
        "methods": methods,
        "speedup_vs_nelder_mead": t_nm / t_ours,
        "speedup_vs_lbfgsb_fd": t_lb / t_ours,
        "speedup_vs_grid": t_grid / t_ours,
        "environment": {
            **environment(),
            "backend": jax.default_backend(),
            "scipy": scipy.__version__,
        },
    }
    # more variables: per-member tip relief and crowning on the helical pair (5 variables), where
    # derivative-free methods need many more evaluations per step
    names5 = (
        "pinion.tip_relief.depth,pinion.tip_relief.extent,gear.tip_relief.depth,"
        "gear.tip_relief.extent,crowning.depth"
    )
    steps5 = tqdm(total=3, desc="bench optimise, 5 variables")
    hel = load_case("power-helical")
    p5 = case_problem(hel, names5, "te_rms", positions_per_pitch=ppp, slices=8 if quick else 20)
    lo5, hi5 = np.asarray(p5.lower), np.asarray(p5.upper)
    x05 = np.array([0.5, 0.15, 0.5, 0.15, 0.1])
    f5 = jax.jit(lambda x: p5.value(x))
    f5(jnp.asarray(x05)).block_until_ready()
    minimise(p5, x05, progress=False)  # compile
    t0 = time.perf_counter()
    ours5 = minimise(p5, x05, progress=False, max_iterations=200)
    t_ours5 = time.perf_counter() - t0
    steps5.update()
    t0 = time.perf_counter()
    nm5 = scipy.optimize.minimize(
        lambda x: float(f5(jnp.asarray(np.clip(x, lo5, hi5)))),
        x05,
        method="Nelder-Mead",
        options={"xatol": 1e-5, "fatol": 1e-8, "maxfev": 20000},
    )
    t_nm5 = time.perf_counter() - t0
    steps5.update()
    t0 = time.perf_counter()
    lb5 = scipy.optimize.minimize(
        lambda x: float(f5(jnp.asarray(x))),
        x05,
        method="L-BFGS-B",
        bounds=list(zip(lo5, hi5)),
        options={"maxfun": 20000},
    )
    t_lb5 = time.perf_counter() - t0
    steps5.update()
    steps5.close()
    five = {
        "case": hel.name,
        "variables": names5.split(","),
        "methods": [
            {
                "method": "jaxgear L-BFGS (optimistix, gradients)",
                "objective": ours5.value,
                "evaluations": ours5.evaluations,
                "wall_time_s": t_ours5,
            },
            {
                "method": "scipy Nelder-Mead",
                "objective": float(nm5.fun),
                "evaluations": int(nm5.nfev),
                "wall_time_s": t_nm5,
            },
            {
                "method": "scipy L-BFGS-B (finite differences)",
                "objective": float(lb5.fun),
                "evaluations": int(lb5.nfev),
                "wall_time_s": t_lb5,
            },
        ],
        "speedup_vs_nelder_mead": t_nm5 / t_ours5,
        "speedup_vs_lbfgsb_fd": t_lb5 / t_ours5,
    }
    report["five_variables"] = five
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "bench_optimise.json"), "w") as fh:
        json.dump(report, fh, indent=2)
    print(
        f"objective {t_f * 1e3:.2f} ms, value+gradient {t_vg * 1e3:.2f} ms (ratio {t_vg / t_f:.2f})"
    )
    print(f"{'method':40s}{'Γ':>8s}{'E µm':>9s}{'objective':>11s}{'evals':>7s}{'time s':>9s}")
    for m in methods:
        print(
            f"{m['method']:40s}{m['extent']:8.4f}{m['depth_um']:9.3f}{m['objective']:11.5f}"
            f"{m['evaluations']:7d}{m['wall_time_s']:9.3f}"
        )
    print(
        f"speed-up of the gradient optimiser: {report['speedup_vs_nelder_mead']:.1f}x vs Nelder-Mead, "
        f"{report['speedup_vs_lbfgsb_fd']:.1f}x vs L-BFGS-B/FD, {report['speedup_vs_grid']:.1f}x vs grid"
    )
    print(f"5 variables on {hel.name} ({names5}):")
    for m in five["methods"]:
        print(
            f"  {m['method']:40s} objective {m['objective']:.5f}, {m['evaluations']} evaluations, "
            f"{m['wall_time_s']:.3f} s"
        )
    print(
        f"  speed-up: {five['speedup_vs_nelder_mead']:.1f}x vs Nelder-Mead, "
        f"{five['speedup_vs_lbfgsb_fd']:.1f}x vs L-BFGS-B/FD"
    )
    return report
