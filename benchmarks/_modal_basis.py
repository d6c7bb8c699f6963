"""Benchmark and chart of the hybrid dynamics in the modal basis: the time of a
speed sweep and the largest dynamic-factor error against the cell-space result, against the
number of modes m.

``bench_modal_basis(out_dir)`` is the body of ``jaxgear bench modal-basis``. On the
``accessory-spur-flexible`` case (the embedded ``accessory-wheel`` body from fem_prep's cache),
float64, exact contact (50 passes), the seed's Rayleigh damping (D1), 64 steps per mesh period,
20 periods with 4 kept, it runs :func:`jaxgear.dynamics.speed_sweep` over ``n_speeds`` pinion
speeds of the seed's range (100–3000 rad/s) plus the torsional resonance of the pair (866 rad/s,
the largest dynamic factor of the 100-speed sweep) in the cell space and with
``Newmark(64, basis=ModalBasis(m))`` for each m. Per setting: the wall time of the sweep
(a warm-up call compiles; the time is the second call's, ``jax.block_until_ready``), split
into the basis (once per sweep: eigen-analyses of the n coordinates, timed alone) and the
speeds; the 100-speed time extrapolated as basis + 100 × per speed (the shared 2-core machine
does not allow the 100 speeds for every m); the largest |DF_m / DF_cell − 1| and TE-RMS error
over the speeds.

Writes ``modal_basis.json`` and ``modal_basis.png``. Benchmarks are not tests: machine, dtype,
versions and the load average before and after are recorded.
"""

from __future__ import annotations

import os
import time

import numpy as np

from ._timing import environment

__all__ = ["bench_modal_basis", "modal_basis_chart"]

_SPEED_RANGE = (100.0, 3000.0)
_RESONANCE = 866.0  # the pair's torsional resonance (rad/s), docs/hybrid.md
_TARGET_S = 60.0  # the aim: 100 speeds below 60 s on the 2-core CPU
_DF_TOL = 0.01  # and the dynamic factor within 1 % of the cell-space one


def _load() -> list | None:
    return list(os.getloadavg()) if hasattr(os, "getloadavg") else None


def bench_modal_basis(
    out_dir,
    quick: bool = False,
    case: str = "accessory-spur-flexible",
    *,
    n_speeds: int = 12,
    modes: tuple = (20, 40, 80, 160, 320),
    periods: int = 20,
    keep_periods: int = 4,
    steps_per_period: int = 64,
    verbose: bool = True,
) -> dict:
    """Run the modal-basis benchmark and write ``modal_basis.json`` and ``modal_basis.png``
    into ``out_dir``.

    Args:
        out_dir: output folder (created if missing).
        quick: a smoke run (3 speeds, 16 steps per period, 4 periods, m = 20 and 80).
        case: embedded case name or TOML path of a case with a condensed body.
        n_speeds: speeds of the seed's range (the resonance is added).
        modes: the m of the modal bases.
        periods, keep_periods, steps_per_period: the run's window and step.

    Returns:
        the JSON record (dict).
    """
    import jax
    import jax.numpy as jnp

    jax.config.update("jax_enable_x64", True)
    import fem_prep
    from jaxgear import io as jio
    from jaxgear import ExactContact
    from jaxgear.dynamics import (
        ModalBasis,
        Newmark,
        Outputs,
        SteadyState,
        dynamic_model,
        speed_sweep,
    )

    env = environment()
    load0 = _load()
    if quick:
        n_speeds, periods, keep_periods, steps_per_period = 3, 4, 2, 16
        modes = (20, 80)
    c = jio.load_case(case)
    bodies = tuple(
        None if r is None else fem_prep.condensed(fem_prep.load_body(r)) for r in c.scene.bodies
    )
    sc, _ = jio.static_scene(c, bodies=bodies)
    model = dynamic_model(sc, c.modifications, c.torque)
    n = int(sc.structure.K.shape[0])
    speeds = np.unique(np.append(np.linspace(*_SPEED_RANGE, n_speeds), _RESONANCE))
    window = SteadyState(periods, keep_periods)
    law = ExactContact(50)  # the exact law has no width to cast to the model's dtype

    def sweep(basis):
        def call():
            r = speed_sweep(
                model,
                jnp.asarray(speeds),
                integrator=Newmark(steps_per_period, basis=basis),
                contact=ExactContact(50),
                window=window,
            ).results
            return jax.block_until_ready(r)

        t0 = time.perf_counter()
        call()
        first = time.perf_counter() - t0
        t0 = time.perf_counter()
        r = call()
        return r, first, time.perf_counter() - t0

    rows = []
    ref, first, wall = sweep(None)
    df_ref = np.asarray(ref.dynamic_factor)
    te_ref = np.asarray(ref.te_rms)
    cell = {
        "first_call_s": first,
        "sweep_s": wall,
        "per_speed_s": wall / speeds.size,
        "extrapolated_100_speeds_s": 100 * wall / speeds.size,
        "dynamic_factor": df_ref.tolist(),
        "result": np.asarray(ref.result).tolist(),
    }
    if verbose:
        print(f"cell space: {wall:.1f} s for {speeds.size} speeds", flush=True)
    for m in modes:
        if m > n:
            continue
        basis = ModalBasis(int(m))
        integrator = Newmark(steps_per_period, basis=basis)
        outputs = Outputs(blowup=10.0)
        # the run's speed-independent part: the modal basis (HybridModel.prepare)
        jax.block_until_ready(model.prepare(integrator, law, window, steps_per_period, outputs))
        t0 = time.perf_counter()
        jax.block_until_ready(model.prepare(integrator, law, window, steps_per_period, outputs))
        basis_s = time.perf_counter() - t0
        r, first, wall = sweep(basis)
        df = np.asarray(r.dynamic_factor)
        per_speed = max(wall - basis_s, 0.0) / speeds.size
        row = {
            "modes": int(m),
            "first_call_s": first,
            "sweep_s": wall,
            "basis_s": basis_s,
            "per_speed_s": per_speed,
            "extrapolated_100_speeds_s": basis_s + 100 * per_speed,
            "ratio_per_speed_vs_cell_space": per_speed / cell["per_speed_s"],
            "max_abs_df_error": float(np.max(np.abs(df / df_ref - 1))),
            "max_abs_te_rms_error": float(np.max(np.abs(np.asarray(r.te_rms) / te_ref - 1))),
            "dynamic_factor": df.tolist(),
            "result": np.asarray(r.result).tolist(),
        }
        rows.append(row)
        if verbose:
            print(
                f"m = {m}: {wall:.1f} s (basis {basis_s:.1f} s), max |DF err| "
                f"{row['max_abs_df_error']:.4f}",
                flush=True,
            )
    out = {
        "case": c.name,
        "quick": bool(quick),
        "machine": env,
        "dtype": env["dtype"],
        "jax": env["jax"],
        "settings": {
            "speeds_rad_s": speeds.tolist(),
            "steps_per_period": steps_per_period,
            "periods": periods,
            "keep_periods": keep_periods,
            "contact": "exact (50 passes)",
            "damping": "rayleigh (the seed's D1, dynamic_model's default)",
            "structure_dofs": n,
            "timing": "second call of speed_sweep (the first compiles), block_until_ready; the "
            "basis (once per sweep) timed alone; per speed = (sweep - basis) / speeds; the "
            "100-speed time extrapolated as basis + 100 per speed (cell space: 100 per speed)",
            "target_100_speeds_s": _TARGET_S,
            "target_df_error": _DF_TOL,
        },
        "cell_space": cell,
        "modal": rows,
        "load_average_start": load0,
        "load_average_end": _load(),
    }
    os.makedirs(out_dir, exist_ok=True)
    from jaxgear.io import static_scene, write_json

    write_json(os.path.join(out_dir, "modal_basis.json"), out)
    modal_basis_chart(out, os.path.join(out_dir, "modal_basis.png"))
    return out


def modal_basis_chart(out: dict, path: str) -> None:
    """Draw modal_basis.png from the record ``out`` of :func:`bench_modal_basis`: (a) the
    largest dynamic-factor error and (b) the extrapolated 100-speed time against m, (c) the
    dynamic factor against speed."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    from jaxgear.io import atomic_open

    rows = out["modal"]
    cell = out["cell_space"]
    st = out["settings"]
    m = np.array([r["modes"] for r in rows], float)
    fig = Figure(figsize=(14, 4.4))
    FigureCanvasAgg(fig)
    ax1, ax2, ax3 = fig.subplots(1, 3)
    err = np.array([r["max_abs_df_error"] for r in rows])
    ax1.loglog(m, 100 * err, "o-", color="C3", label="max |DF error| over the speeds")
    ax1.loglog(
        m,
        100 * np.array([r["max_abs_te_rms_error"] for r in rows]),
        "s--",
        color="C0",
        label="max |TE-RMS error|",
    )
    ax1.axhline(100 * st["target_df_error"], color="k", ls="--", lw=1, label="target 1 %")
    ax1.set_xlabel(f"modes m (of n = {st['structure_dofs']})")
    ax1.set_ylabel("error against the cell space (%)")
    ax1.set_title("accuracy (static correction on)", fontsize=9)
    ax1.legend(fontsize=7)
    ax1.grid(True, which="both", alpha=0.3)
    t = np.array([r["extrapolated_100_speeds_s"] for r in rows])
    b = np.array([r["basis_s"] for r in rows])
    ax2.loglog(m, t, "o-", color="C3", label="modal basis (basis + 100 × per speed)")
    ax2.loglog(m, b, "^:", color="C2", label="of which the basis (once)")
    ax2.axhline(cell["extrapolated_100_speeds_s"], color="C0", lw=1.5, label="cell space")
    ax2.axhline(st["target_100_speeds_s"], color="k", ls="--", lw=1, label="target 60 s")
    ax2.set_xlabel("modes m")
    ax2.set_ylabel("100-speed sweep, extrapolated (s)")
    ax2.set_title(
        f"time ({len(st['speeds_rad_s'])} speeds measured; load {out['load_average_start'][0]:.1f}"
        f"→{out['load_average_end'][0]:.1f} on {out['machine'].get('cpu_count')} cores)",
        fontsize=9,
    )
    ax2.legend(fontsize=7)
    ax2.grid(True, which="both", alpha=0.3)
    for ax in (ax1, ax2):  # the measured m as plain tick labels
        ax.xaxis.set_major_locator(FixedLocator(m))
        ax.xaxis.set_major_formatter(ScalarFormatter())
        ax.xaxis.set_minor_formatter(NullFormatter())
    sp = np.array(st["speeds_rad_s"])
    ax3.plot(sp, cell["dynamic_factor"], "k-", lw=2, label="cell space")
    for i, r in enumerate(rows):
        ax3.plot(sp, r["dynamic_factor"], "o--", ms=3, color=f"C{i + 1}", label=f"m = {r['modes']}")
    ax3.set_xlabel("pinion speed (rad/s)")
    ax3.set_ylabel(f"dynamic factor (last {st['keep_periods']} of {st['periods']} periods)")
    ax3.set_title(
        f"{out['case']}, {st['steps_per_period']} steps/period, {out['dtype']}", fontsize=9
    )
    ax3.legend(fontsize=7)
    ax3.grid(True, alpha=0.3)
    fig.tight_layout()
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png", dpi=110)
