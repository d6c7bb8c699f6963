"""Benchmark of the dynamic model: the vmapped Newmark sweep against the best baselines.

The 1-DOF relative-approach model of the accessory spur pair (4 slices, its 15 µm tip relief,
composite damping), exact contact, every speed from the static equilibrium, 200 speeds from 0.2× to
3× the critical speed, 60 mesh periods (the last 4 kept), the automatic time step (64-256 steps per
mesh period). Against:

* Numba: the same Newmark and active-set contact loop on the same matrices and cell table
  (:func:`~benchmarks._baseline_dynamics.numba_newmark_sweep`; serial, and ``prange`` over
  speeds), if Numba is installed (``pip install jaxgear[bench]``), else reported as skipped;
* ``solve_ivp`` (LSODA, DOP853, Radau) segmented at the stiffness discontinuities with a vectorised
  right-hand side (:func:`~benchmarks._baseline_dynamics.segmented_response`), at the loosest
  tolerance of a ladder whose dynamic-factor error is <= jaxgear's; run on a subset of the speeds
  and interpolated (time against speed) to all of them.

Accuracy: the dynamic factor of every method against the fine continuous-time reference
(:func:`~benchmarks._baseline_dynamics.reference_response`, DOP853 rtol 1e-10 segmented at every
discontinuity, kink and contact event) at the probe speeds, max absolute error reported.

Benchmarks are not tests: compile time separated (first call − best run), warmed up,
``block_until_ready``, min of repeats.
"""

from __future__ import annotations

import json
import os
import time

import numpy as np

from jaxgear.io import contact_law_from_name
from jaxgear.dynamics import DiffraxIntegrator, Newmark, SteadyState

from ._charts import thin_tick_labels
from ._timing import environment, first_call, min_time

__all__ = ["bench_dynamics", "stability_map"]

RTOL_LADDER = (1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7)


def _bench_model():
    from jaxgear.dynamics import dynamic_model
    from jaxgear.io import load_case
    from jaxgear.scenes import TorsionalDynamics, disc_inertia

    case = load_case("accessory-spur").replace(slices=4)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2).reduced()
    return case, dynamic_model(scene, case.modifications, case.torque)


def bench_dynamics(
    out_dir: str,
    *,
    quick: bool = False,
    progress: bool = True,
    verbose: bool = True,
    stability: bool = True,
    numba: bool = True,
) -> dict:
    """jaxgear's vmapped Newmark sweep vs Numba Newmark and segmented ``solve_ivp``.

    Writes ``bench_dynamics.json`` (and, with ``stability``, the stability map) to ``out_dir``
    and returns the summary. ``numba=False`` (or Numba not installed) skips the Numba rows.
    """
    from tqdm.auto import tqdm

    from jaxgear.dynamics import auto_steps_per_period, speed_sweep
    from jaxgear.io import atomic_open

    from . import _baseline_dynamics as bd

    env = environment()
    case, model = _bench_model()
    wc = float(model.critical_speeds(1)[0])
    if quick:
        n_speeds, lo, hi, periods, keep, n_probe = 16, 0.7, 3.0, 20, 2, 2
    else:
        n_speeds, lo, hi, periods, keep, n_probe = 200, 0.2, 3.0, 60, 4, 5
    speeds = np.linspace(lo, hi, n_speeds) * wc
    ns = auto_steps_per_period(model, speeds)
    angle = float(model.mesh.mesh_period_angle)
    probe = np.unique(np.round(np.linspace(0, n_speeds - 1, n_probe)).astype(int))
    kw = {"periods": periods, "keep_periods": keep}
    bar = tqdm(total=4 + (1 if stability else 0), desc="bench dynamics", disable=not progress)

    # fine reference at the probe speeds (same start as simulate: static at θ0 = Δθ/2)
    bar.set_postfix_str("reference")
    t0 = time.perf_counter()
    ref = np.array(
        [
            bd.reference_response(model, speeds[i], theta0=angle / (2 * ns[i]), **kw)[
                "dynamic_factor"
            ]
            for i in probe
        ]
    )
    t_ref = time.perf_counter() - t0
    bar.update()

    # jaxgear: compile (one per distinct N_s) separated from the run
    bar.set_postfix_str("jaxgear")

    def sweep():
        return speed_sweep(model, speeds, window=SteadyState(periods, keep)).dynamic_factor

    first = first_call(sweep)
    t_jax = min_time(sweep, 2, warmup=False)
    df_jax = np.asarray(sweep())
    err_jax = float(np.max(np.abs(df_jax[probe] - ref)))
    rows = [
        {
            "method": "jaxgear Newmark (vmap)",
            "error": err_jax,
            "compile_s": max(first - t_jax, 0.0),
            "run_s": t_jax,
            "measured_speeds": n_speeds,
            "extrapolated": False,
        }
    ]
    bar.update()

    # Numba Newmark (same tables, not timed: they are jaxgear's cell table)
    bar.set_postfix_str("Numba")
    if numba and bd.numba_available():
        tables = {int(n): bd.numba_tables(model, int(n)) for n in np.unique(ns)}
        for kind in ("serial", "parallel"):
            one = tables[int(ns[-1])]
            t0 = time.perf_counter()  # compile: a first call on one step
            bd._kernels()[kind](*one, np.array([1e-5]), 1, 1, 100)
            t_comp = time.perf_counter() - t0

            def run(kind=kind):
                return bd.numba_newmark_sweep(
                    model, speeds, steps_per_period=ns, kind=kind, tables=tables, **kw
                )

            t_nb = min_time(run, 3, block=lambda r: r, warmup=False)
            df_nb = run()
            rows.append(
                {
                    "method": f"Numba Newmark ({kind}"
                    + (f", {numba_threads()} threads)" if kind == "parallel" else ")"),
                    "error": float(np.max(np.abs(df_nb[probe] - ref))),
                    "compile_s": t_comp,
                    "run_s": t_nb,
                    "measured_speeds": n_speeds,
                    "extrapolated": False,
                    "max_abs_diff_vs_jaxgear": float(np.max(np.abs(df_nb - df_jax))),
                }
            )
    else:
        rows.append({"method": "Numba Newmark", "skipped": "numba not installed"})
    bar.update()

    # segmented solve_ivp at the loosest tolerance of the ladder as accurate as jaxgear
    bar.set_postfix_str("solve_ivp")
    t0 = time.perf_counter()
    setup = bd.SegmentedModel(model)
    t_setup = time.perf_counter() - t0
    for method in ("LSODA", "DOP853", "Radau"):
        chosen, tried = None, []
        for rtol in RTOL_LADDER[:3] if quick else RTOL_LADDER:
            times, dfs, ok = [], [], True
            for i in probe:
                t0 = time.perf_counter()
                try:
                    o = bd.segmented_response(
                        setup, speeds[i], theta0=angle / (2 * ns[i]), method=method, rtol=rtol, **kw
                    )
                except RuntimeError:
                    ok = False
                    break
                times.append(time.perf_counter() - t0)
                dfs.append(o["dynamic_factor"])
            if not ok:
                tried.append({"rtol": rtol, "failed": True})
                continue
            err = float(np.max(np.abs(np.array(dfs) - ref)))
            tried.append({"rtol": rtol, "error": err, "probe_times_s": times})
            if err <= err_jax:
                # time per speed interpolated (in speed) from the probes, summed over the sweep
                total = float(np.sum(np.interp(speeds, speeds[probe], times)))
                chosen = {
                    "method": f"solve_ivp {method} segmented",
                    "rtol": rtol,
                    "error": err,
                    "compile_s": t_setup,
                    "run_s": total,
                    "measured_speeds": int(probe.size),
                    "extrapolated": True,
                    "probe_times_s": times,
                }
                break
        rows.append(
            {
                **(
                    chosen or {"method": f"solve_ivp {method} segmented", "skipped": "no tolerance"}
                ),
                "ladder": tried,
            }
        )
    bar.update()

    for r in rows[1:]:
        if "run_s" in r:
            r["ratio"] = r["run_s"] / t_jax
            r["ratio_with_compile"] = (r["run_s"] + r["compile_s"]) / (t_jax + rows[0]["compile_s"])
    timed = [r for r in rows[1:] if "run_s" in r]
    best = min(timed, key=lambda r: r["run_s"]) if timed else None
    summary = {
        "case": case.name,
        "model": "1-DOF relative approach (torsional pair reduced), 4 slices, tip relief 15 µm, "
        "exact contact",
        "speeds": n_speeds,
        "speed_range_rad_s": [float(speeds[0]), float(speeds[-1])],
        "critical_speed_rad_s": wc,
        "periods": periods,
        "keep_periods": keep,
        "steps_per_period": {int(n): int(np.sum(ns == n)) for n in np.unique(ns)},
        "probe_speeds_rad_s": speeds[probe].tolist(),
        "df_reference": ref.tolist(),
        "reference_time_s": t_ref,
        "rows": rows,
        "best_baseline": None if best is None else best["method"],
        "speedup_vs_best": None if best is None else best["run_s"] / t_jax,
        "target_speedup": 20.0,
        "dynamic_factor_max": float(df_jax.max()),
        "quick": bool(quick),
        "timing": "compile = first call - best run; run = min of repeats (jaxgear, Numba), "
        "block_until_ready; solve_ivp: one run per probe speed, time interpolated over the sweep",
        "platform": {**env, "dtype": str(df_jax.dtype), "numba": _numba_version()},
    }
    if stability:
        bar.set_postfix_str("stability map")
        summary["stability_map"] = stability_map(out_dir, quick=quick)
        bar.update()
    bar.close()
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "bench_dynamics.json"), "w") as f:
        json.dump(summary, f, indent=2)
    if verbose:
        print(_table(summary))
    return summary


def numba_threads():
    import numba

    return numba.get_num_threads()


def _numba_version():
    try:
        import numba
    except ImportError:
        return None
    return numba.__version__


def _table(s: dict) -> str:
    """A short plain-text table of the dynamics benchmark (like ``bench quasi-static``)."""
    env = s["platform"]
    n = s["speeds"]
    lines = [
        (
            f"dynamics benchmark: {s['case']}, {s['model']}, {n} speeds "
            f"({s['speed_range_rad_s'][0]:.0f}-{s['speed_range_rad_s'][1]:.0f} rad/s) × "
            f"{s['periods']} periods, N_s {s['steps_per_period']}, {env['dtype']}, JAX "
            f"{env['jax']}, Numba {env['numba']}, {env['device']}, {env['cpu_count']} CPU "
            f"({env['cpu_model']}), load {env['load_average_at_start']}"
        ),
        f"{'method':36s}{'DF error':>10s}{'compile s':>11s}{'run s':>10s}{'ratio':>9s}",
    ]
    for r in s["rows"]:
        if "run_s" not in r:
            lines.append(f"{r['method']:36s}  skipped ({r.get('skipped', '')})")
            continue
        name = r["method"] + (f" rtol {r['rtol']:g}" if "rtol" in r else "")
        run = f"{r['run_s']:.3f}" + ("*" if r["extrapolated"] else "")
        ratio = f"{r['ratio']:.2f}" if "ratio" in r else "1"
        lines.append(f"{name:36s}{r['error']:10.1e}{r['compile_s']:11.2f}{run:>10s}{ratio:>9s}")
    lines.append(
        f"ratio = baseline run s / jaxgear run s; * = interpolated from "
        f"{len(s['probe_speeds_rad_s'])} probe speeds; DF error = max |DF - reference| at them; "
        f"best baseline: {s['best_baseline']} (jaxgear {s['speedup_vs_best']:.2f}× faster, "
        f"target ≥ {s['target_speedup']:g}×)"
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
    else:
        lines.append("written: bench_dynamics.json")
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

    from jaxgear.dynamics import dynamic_model, speed_sweep
    from jaxgear.io import Damping, atomic_open, load_case
    from jaxgear.scenes import TorsionalDynamics, disc_inertia

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
    base = dict(window=SteadyState(periods, keep))
    ref = speed_sweep(model, speeds, integrator=Newmark(512 if not quick else 256), **base)
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
                    integrator=(
                        Newmark(spp)
                        if solver == "newmark"
                        else DiffraxIntegrator(solver, spp, adaptive=False)
                    ),
                    contact=contact_law_from_name(contact, 1e-7 if w is None else w),
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
    thin_tick_labels(fig)
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
