"""Benchmark of the dynamic model: vmapped Newmark over speeds against SciPy's ``solve_ivp``.

The same smooth model on both sides: torsional pinion-gear pair, smooth contact law of width w,
the same cells (positions, stiffnesses, deviations) at θ(t) = Ω t + Δθ/2. SciPy integrates the
first-order form with LSODA and Radau; the deviation e(s, z) is tabulated along s for each slice
(cells keep their slice, only s moves), which is exact for profile modifications up to the table
step. Accuracy is matched on the dynamic factor against a converged reference (Newmark, 8× finer
steps): SciPy's tolerance is the loosest of a ladder reaching the Newmark error.

Benchmarks are not tests: compiled separately, warmed up, ``block_until_ready``, min of repeats.
"""

from __future__ import annotations

import json
import math
import os
import time

import numpy as np

from ._timing import environment, first_call, min_time

__all__ = ["bench_dynamics", "stability_map"]


def _numpy_model(model, width):
    """NumPy right-hand side of the first-order smooth model (for solve_ivp)."""
    import jax.numpy as jnp

    from ..dynamics import mesh_table

    scene = model.scene
    mesh = scene.mesh
    n_lines, n_slices = mesh.n_lines, mesh.n_slices
    g = float(mesh.path_of_contact)
    pbt = float(mesh.base_pitch)
    rb1 = float(mesh.base_radius_pinion)
    tanb = math.tan(float(mesh.base_helix_angle))
    b = float(mesh.face_width)
    dz = b / n_slices
    z = (np.arange(n_slices) + 0.5) * dz
    lines = np.arange(n_lines) + mesh.first_line
    s_tab = np.asarray(mesh.stiffness_s)
    k_tab = np.asarray(mesh.stiffness_k)
    s_grid = np.linspace(0.0, g, 4001)
    e_grid = np.asarray(
        model.mods.deviation(jnp.asarray(s_grid / g)[:, None], jnp.asarray(z / b)[None, :])
    )  # (4001, N)
    e_ref = float(mesh_table(scene, model.mods, 64).e_max[0])
    length = dz / math.cos(float(mesh.base_helix_angle))
    V = np.asarray(scene.te_vector())  # torsional: the same V for every cell
    M = np.asarray(scene.mass())
    Minv = np.linalg.inv(M)
    C = np.asarray(model.damping)
    Ks = np.asarray(scene.stiffness())
    F = np.asarray(scene.external_load(model.torque))
    n = M.shape[0]
    dtheta_half = 0.5 * float(mesh.mesh_period_angle) / 64

    def deviation(s):
        out = np.empty_like(s)
        for j in range(n_slices):
            out[:, j] = np.interp(s[:, j], s_grid, e_grid[:, j])
        return out

    def rhs(t, y, speed):
        X, Xd = y[:n], y[n:]
        theta = speed * t + dtheta_half
        roll = np.mod(rb1 * theta, pbt)
        s = roll + lines[:, None] * pbt - z[None, :] * tanb
        mask = (s >= 0) & (s <= g)
        k = np.interp(s, s_tab, k_tab)
        d0 = e_ref - deviation(s)
        gap = V @ X - d0
        x = gap / width
        phi = width * (np.maximum(x, 0) + np.log1p(np.exp(-np.abs(x))))
        f = np.sum(np.where(mask, k * length * phi, 0.0))
        A = Minv @ (F - C @ Xd - Ks @ X - V * f)
        return np.concatenate([Xd, A])

    def observe(t, X, speed):
        theta = speed * t + dtheta_half
        roll = np.mod(rb1 * theta, pbt)
        s = roll + lines[:, None] * pbt - z[None, :] * tanb
        mask = (s >= 0) & (s <= g)
        k = np.interp(s, s_tab, k_tab)
        x = (V @ X - (e_ref - deviation(s))) / width
        phi = width * (np.maximum(x, 0) + np.log1p(np.exp(-np.abs(x))))
        return np.sum(np.where(mask, k * length * phi, 0.0))

    return rhs, observe


def bench_dynamics(
    out_dir: str, *, quick: bool = False, progress: bool = True, verbose: bool = True
) -> dict:
    """Vmapped Newmark (200 speeds × 100 mesh periods × 64 steps) vs ``solve_ivp`` (LSODA, Radau).

    Writes ``bench_dynamics.json`` to ``out_dir`` and returns it.
    """
    import scipy.integrate

    from ..dynamics import build_dynamic_model, simulate, speed_sweep, static_start
    from ..io import atomic_open, load_case, parse_scene

    case = load_case("accessory-spur").replace(slices=10)
    n_speeds, periods, spp, keep = (16, 20, 64, 4) if quick else (200, 100, 64, 4)
    spec = parse_scene({"integration": {"steps_per_period": spp, "contact": "smooth"}})
    model, _ = build_dynamic_model(case, spec)
    width = case.smooth_width
    speeds = np.linspace(100.0, 3000.0, n_speeds)
    kw = dict(
        contact="smooth", width=width, steps_per_period=spp, periods=periods, keep_periods=keep
    )
    from tqdm.auto import tqdm

    probe = [500.0, 860.0, 2000.0] if not quick else [860.0]
    # steps: JAX sweep, one per SciPy probe speed, the stability map
    bar = tqdm(total=2 + len(probe), desc="bench dynamics", disable=not progress)
    # compile (same shapes), then time: min of repeats, block_until_ready
    first = first_call(lambda: speed_sweep(model, speeds, **kw).dynamic_factor)
    t_jax = min_time(lambda: speed_sweep(model, speeds, **kw).dynamic_factor, 2, warmup=False)
    df_jax = np.asarray(speed_sweep(model, speeds, **kw).dynamic_factor)
    bar.set_postfix_str("SciPy probes")
    bar.update()

    # SciPy on a few speeds (one resonant), extrapolated to all of them
    rhs, observe = _numpy_model(model, width)
    x0, _ = static_start(model, contact="smooth", width=width, steps_per_period=spp)
    y0 = np.concatenate([np.asarray(x0), np.zeros_like(np.asarray(x0))])
    rows = []
    for sp in probe:
        ref = simulate(model, sp, **{**kw, "steps_per_period": 8 * spp})
        df_ref = float(ref.dynamic_factor)
        nm = simulate(model, sp, **kw)
        err_nm = abs(float(nm.dynamic_factor) - df_ref)
        period = float(model.mesh.mesh_period_angle) / sp
        t_end = periods * period
        t_keep = np.linspace(t_end - keep * period, t_end, keep * spp + 1)[1:]
        for method in ("LSODA", "Radau"):
            chosen = None
            for rtol in (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8):
                t0 = time.perf_counter()
                sol = scipy.integrate.solve_ivp(
                    rhs,
                    (0.0, t_end),
                    y0,
                    method=method,
                    rtol=rtol,
                    atol=rtol * 1e-6,
                    t_eval=t_keep,
                    args=(sp,),
                )
                dt_run = time.perf_counter() - t0
                if not sol.success:
                    continue
                fm = np.array(
                    [observe(t, y[: x0.shape[0]], sp) for t, y in zip(sol.t, sol.y.T, strict=True)]
                )
                err = abs(fm.max() / float(model.static_force) - df_ref)
                chosen = {
                    "method": method,
                    "rtol": rtol,
                    "time_s": dt_run,
                    "error": err,
                    "nfev": int(sol.nfev),
                }
                if err <= max(err_nm, 1e-4):
                    break
            rows.append(
                {
                    "speed_rad_s": sp,
                    "df_reference": df_ref,
                    "newmark_error": err_nm,
                    **(chosen or {"method": method, "failed": True}),
                }
            )
        bar.update()
    bar.set_postfix_str("stability map")
    per_speed = {
        m: float(np.mean([r["time_s"] for r in rows if r.get("method") == m and "time_s" in r]))
        for m in ("LSODA", "Radau")
    }
    summary = {
        "case": case.name,
        "model": "torsional 2-DOF, smooth contact",
        "speeds": n_speeds,
        "periods": periods,
        "steps_per_period": spp,
        "jax_newmark_vmap_s": t_jax,
        "jax_first_call_s": first,
        "jax_per_speed_s": t_jax / n_speeds,
        "scipy_probe": rows,
        "scipy_per_speed_s": per_speed,
        "scipy_total_estimate_s": {m: v * n_speeds for m, v in per_speed.items()},
        "speedup": {m: v * n_speeds / t_jax for m, v in per_speed.items()},
        "dynamic_factor_max": float(df_jax.max()),
        "quick": bool(quick),
        "timing": "min of repeats after a compiling call, jax.block_until_ready on the result",
        "platform": {**environment(), "dtype": str(df_jax.dtype)},
    }
    summary["stability_map"] = stability_map(out_dir, quick=quick)
    bar.update()
    bar.close()
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "bench_dynamics.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if verbose:
        print(_table(summary))
    return summary


def _table(s: dict) -> str:
    """A short plain-text table of the dynamics benchmark (like ``bench quasi-static``)."""
    env = s["platform"]
    lines = [
        (
            f"dynamics benchmark: {s['case']}, {s['model']}, {s['speeds']} speeds × "
            f"{s['periods']} periods × {s['steps_per_period']} steps, {env['dtype']}, JAX "
            f"{env['jax']}, {env['device']}, {env['cpu_count']} CPU ({env['cpu_model']})"
        ),
        f"{'':28s}{'total s':>10s}{'per speed ms':>14s}{'speed-up':>10s}",
        (
            f"{'jaxgear Newmark (vmap)':28s}{s['jax_newmark_vmap_s']:10.3f}"
            f"{s['jax_per_speed_s'] * 1e3:14.2f}{'1':>10s}"
        ),
    ]
    for m, per in s["scipy_per_speed_s"].items():
        if per == per:  # not NaN
            lines.append(
                f"{'SciPy ' + m + ' (estimate)':28s}{per * s['speeds']:10.3f}"
                f"{per * 1e3:14.2f}{s['speedup'][m]:10.1f}"
            )
        else:
            lines.append(f"{'SciPy ' + m:28s}{'failed':>10s}")
    lines.append(
        f"first call (compile + run): {s['jax_first_call_s']:.2f} s; "
        f"max dynamic factor {s['dynamic_factor_max']:.3f}"
    )
    rows = s.get("stability_map", {}).get("rows", [])
    if rows:
        lines.append(
            f"{'stability map':28s}{'steps':>6s}{'time s':>9s}{'err res.':>10s}{'err non-res.':>13s}"
        )
        for r in rows:
            name = f"{r['solver']}/{r['contact']}" + (
                "" if r["width_m"] is None else f" w={r['width_m'] * 1e6:g}µm"
            )
            err = lambda v: f"{v:.1e}" if v is not None else "diverged"  # noqa: E731
            lines.append(
                f"{name:28s}{r['steps_per_period']:6d}{r['time_s']:9.3f}"
                f"{err(r['error_resonant']):>10s}{err(r['error_nonresonant']):>13s}"
            )
    lines.append("written: bench_dynamics.json, stability_map.json, stability_map.png")
    return "\n".join(lines)


def stability_map(out_dir: str, *, quick: bool = False) -> dict:
    """Error against a converged reference and run time, per solver and contact law, over steps per
    mesh period and smoothing widths, at a resonant and a non-resonant speed (accessory pair with
    its tip relief, modal damping 3 %: contact loss at the resonant speed). Diverged runs
    (result != 0) are marked.

    Writes ``stability_map.json`` and ``stability_map.png``; returns the dict.
    """
    import jax
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..dynamics import Damping, dynamic_model, speed_sweep
    from ..io import atomic_open, load_case
    from ..scenes import TorsionalDynamics, disc_inertia

    case = load_case("accessory-spur").replace(slices=4)
    p = case.pair
    scene = TorsionalDynamics(
        case.mesh_model(),
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    )
    model = dynamic_model(
        scene, case.modifications, case.torque, Damping("modal", ratio=0.03), positions_per_pitch=32
    )
    cs = float(model.critical_speeds()[1])
    speeds = np.array([0.98 * cs, 1.5 * cs])  # resonant (contact loss), non-resonant
    periods, keep = (12, 2) if quick else (30, 4)
    steps = (16, 64) if quick else (8, 16, 32, 64, 128)
    widths = (1e-7,) if quick else (1e-8, 1e-7, 1e-6)
    base = dict(periods=periods, keep_periods=keep)
    ref = speed_sweep(model, speeds, steps_per_period=512 if not quick else 256, **base)
    df_ref = np.asarray(ref.dynamic_factor)
    methods = [
        ("newmark", "exact", (None,)),
        ("newmark", "smooth", widths),
        ("tsit5", "smooth", widths),
        ("kvaerno5", "smooth", widths[:1]),
    ]
    rows = []
    for solver, contact, ws in methods:
        for spp in steps:
            for w in ws:
                kw = dict(
                    solver=solver,
                    contact=contact,
                    steps_per_period=spp,
                    width=1e-7 if w is None else w,
                    adaptive=False,
                    **base,
                )
                try:
                    jax.block_until_ready(speed_sweep(model, speeds, **kw).dynamic_factor)
                    t0 = time.perf_counter()
                    r = speed_sweep(model, speeds, **kw)
                    jax.block_until_ready(r.dynamic_factor)
                    dt = time.perf_counter() - t0
                    df = np.asarray(r.dynamic_factor)
                    res = np.asarray(r.results.result)
                except Exception as err:  # noqa: BLE001 - a failing configuration is a data point
                    df, res, dt = np.full(2, np.nan), np.full(2, -1), float("nan")
                    print(f"stability map: {solver}/{contact}/{spp}/{w}: {err}")
                err_rel = np.abs(df - df_ref) / df_ref
                rows.append(
                    {
                        "solver": solver,
                        "contact": contact,
                        "width_m": w,
                        "steps_per_period": spp,
                        "time_s": dt,
                        "error_resonant": None
                        if not np.isfinite(err_rel[0])
                        else float(err_rel[0]),
                        "error_nonresonant": None
                        if not np.isfinite(err_rel[1])
                        else float(err_rel[1]),
                        "result": [int(v) for v in res],
                        "contact_loss": [float(v) for v in np.asarray(r.results.contact_loss)]
                        if np.all(res >= 0)
                        else None,
                    }
                )
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.5))
    styles = {}
    for row in rows:
        key = (row["solver"], row["contact"], row["width_m"])
        styles.setdefault(key, f"C{len(styles) % 10}")
    for k, (label, speed) in enumerate(
        (("error_resonant", speeds[0]), ("error_nonresonant", speeds[1]))
    ):
        ax = axes[k]
        for key, color in styles.items():
            sel = [r for r in rows if (r["solver"], r["contact"], r["width_m"]) == key]
            x = np.array([r["steps_per_period"] for r in sel], float)
            y = np.array([np.nan if r[label] is None else r[label] for r in sel], float)
            bad = np.array([r["result"][k] != 0 for r in sel])
            name = f"{key[0]}/{key[1]}" + ("" if key[2] is None else f" w={key[2] * 1e6:g} µm")
            ax.loglog(x[~bad], np.maximum(y[~bad], 1e-12), "o-", color=color, label=name, ms=4)
            if bad.any():
                ax.loglog(x[bad], np.ones(bad.sum()), "x", color=color, ms=9, mew=2)
        ax.set_title(
            f"{'resonant' if k == 0 else 'non-resonant'}: {speed:.0f} rad/s "
            f"(DF ref {df_ref[k]:.3f}); x = diverged"
        )
        ax.set_xlabel("steps per mesh period")
        ax.set_ylabel("relative error of the dynamic factor")
        ax.grid(alpha=0.3, which="both")
    axes[0].legend(fontsize=7)
    ax = axes[2]
    for key, color in styles.items():
        sel = [r for r in rows if (r["solver"], r["contact"], r["width_m"]) == key]
        t = np.array([r["time_s"] for r in sel], float)
        y = np.array([np.nan if r["error_resonant"] is None else r["error_resonant"] for r in sel])
        ax.loglog(t, np.maximum(y, 1e-12), "o-", color=color, ms=4)
    ax.set_xlabel("run time, 2 speeds (s)")
    ax.set_ylabel("relative error at the resonant speed")
    ax.grid(alpha=0.3, which="both")
    fig.tight_layout()
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "stability_map.png"), "wb") as f:
        fig.savefig(f, format="png", dpi=110)
    plt.close(fig)
    out = {
        "speeds_rad_s": speeds.tolist(),
        "df_reference": df_ref.tolist(),
        "reference_contact_loss": np.asarray(ref.results.contact_loss).tolist(),
        "periods": periods,
        "rows": rows,
    }
    with atomic_open(os.path.join(out_dir, "stability_map.json"), "w") as f:
        json.dump(out, f, indent=2)
    return out
