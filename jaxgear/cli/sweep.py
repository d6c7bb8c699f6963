"""``jaxgear sweep``: dynamic factor against speed for a case of any form, one command
(:func:`sweep_command`): the case's dynamic model (:func:`jaxgear.io.build_dynamic_model`)
swept by :func:`jaxgear.dynamics.speed_sweep` with the same options, what the model cannot run
refused at load by asking its kind's contract, from the class before any model is built
(:func:`~jaxgear.cli._sweep_kinds.check_model_options`),
the files written by the form (:func:`check_sweep`, :func:`sweep_files`, :func:`sweep_report`:
a planetary stage's in :mod:`jaxgear.cli.planetary_sweep`, a gearbox's in
:mod:`jaxgear.cli.gearbox`).

A case's ``[scene]`` (pairs and trains; its schema: :func:`jaxgear.io.parse_scene` and
docs/dynamics.md) is written as ``sweep.json``, ``dynamic_factor.png``, ``campbell.png``,
``contact_pressure.png`` (the largest Hertzian pressure per speed) and
``pressure_map_dynamic.png`` (the pressure over a tooth's passage at the speed of the largest
dynamic factor; a train: ``pressure_map_dynamic_<mesh>.png``)."""

from __future__ import annotations

import dataclasses
import functools
import math
import os
import platform
import sys
import time
import warnings

import jax
import numpy as np

from .. import DynamicsResult, dynamics, io as case_io
from ..io import Case
from ._bearing_report import bearing_tone_orders
from ._options import range_values
from ._paths import check_case_outputs, staged_outputs
from ._progress import inner_bars, progress as progress_bar
from ._sweep_json import (
    ND_MODES,
    backlash_responses,
    bearing_names,
    clean,
    dynamic_pressure_map,
    mesh_responses,
    of_worst,
    pressure_responses,
    worst,
    write_sweep,
    write_sweep_csv,
)
from ._sweep_kinds import check_case_options, check_model_options, sweep_kind
from .gearbox import check_gearbox_sweep, gearbox_sweep_files, gearbox_sweep_lines
from .planetary_sweep import check_planetary_sweep, planetary_sweep_files, sweep_lines

__all__ = [
    "ND_MODES",
    "check_model_options",
    "check_sweep",
    "default_sweep_dir",
    "run_sweep",
    "sweep_case",
    "sweep_case_run",
    "sweep_command",
    "sweep_files",
    "sweep_report",
    "sweep_spec",
    "write_sweep_csv",
]

#: the sweeps of each ``--direction``: independent speeds, one continuation, or up and down
SWEEPS_PER_DIRECTION = {"independent": 1, "up": 1, "down": 1, "both": 2}


def sweep_spec(
    case,
    *,
    direction: str = "independent",
    solver: str | None = None,
    contact: str | None = None,
    periods: int | str | None = None,
    steps_per_period: int | None = None,
    keep_periods: int | None = None,
    vtu_speed: float | None = None,
):
    """The :class:`~jaxgear.io.SceneSpec` a sweep of ``case`` runs (its ``[scene]``, the
    options given replacing its settings; ``periods`` ``"auto"``: each speed until it settles,
    whatever the case's), checked before any work: one-line ``ValueError``
    naming the option (``--periods``) or the case-file key (``[scene.integration] periods``),
    its value and the allowed range."""
    # MAX_STEPS_PER_SPEED: jaxgear.dynamics' bound (its runs refuse more, but only once the
    # model is built); checked here before any work
    spec = case.scene if case.scene is not None else case_io.SceneSpec()
    given = dict(
        solver=solver,
        contact=contact,
        periods=periods,
        steps_per_period=steps_per_period,
        keep_periods=keep_periods,
    )
    over = {k: v for k, v in given.items() if v is not None}
    if periods == "auto":  # the case's fixed periods replaced by the settled sweep's
        over["periods"] = None
    spec = dataclasses.replace(spec, **over)

    def name(key: str) -> str:
        if key in over:
            return "--" + key.replace("_", "-")
        return f"[scene.integration] {key}"

    if spec.periods is not None and spec.keep_periods > spec.periods:
        raise ValueError(
            f"{name('keep_periods')} = {spec.keep_periods}: out of range, allowed <= "
            f"{name('periods')} = {spec.periods}"
        )
    q = case.span_periods
    if spec.keep_periods < q:
        raise ValueError(
            f"{name('keep_periods')} = {spec.keep_periods}: out of range, allowed >= {q} (the "
            f"meshes of {case.name} repeat together every {q} periods of the first mesh: the "
            "kept periods must hold every mesh position)"
        )
    steps = spec.steps_per_period or dynamics.MIN_STEPS_PER_PERIOD
    # periods "auto": a settled sweep bounds each speed's windows itself
    if spec.periods is not None and spec.periods * steps > dynamics.MAX_STEPS_PER_SPEED:
        at = (
            f"{steps} time steps per mesh period ({name('steps_per_period')})"
            if spec.steps_per_period
            else f"at least {steps} time steps per mesh period (automatic)"
        )
        raise ValueError(
            f"{name('periods')} = {spec.periods}: out of range, allowed <= "
            f"{dynamics.MAX_STEPS_PER_SPEED // steps} at {at}: {spec.periods * steps:.3g} time "
            f"steps per speed, allowed <= {dynamics.MAX_STEPS_PER_SPEED:.3g} (fewer periods or "
            "steps per period)"
        )
    if direction not in ("independent", "up", "down", "both"):
        raise ValueError(f"--direction {direction!r}: allowed independent, up, down, both")
    hybrid = spec.hybrid
    if vtu_speed is not None and not hybrid:
        raise ValueError(
            f"--vtu-speed {vtu_speed}: only a scene with condensed bodies has a deformed body "
            "to export ([scene.gear_body] or [scene.pinion_body] of a pair, [scene.bodies.<gear>] "
            "of a train)"
        )
    if vtu_speed is not None and not vtu_speed > 0:
        raise ValueError(f"--vtu-speed {vtu_speed}: out of range, allowed > 0 rad/s")
    if hybrid and (direction != "independent" or spec.solver != "newmark"):
        raise ValueError(
            "a scene with condensed bodies sweeps independent speeds with Newmark only "
            f"(got --direction {direction}, solver {spec.solver})"
        )
    return spec


def sweep_case(case: Case, speeds, out_dir: str, **options) -> dict:
    """The summary of :func:`sweep_case_run` (same arguments, same files): the ``sweep.json``
    dict."""
    return sweep_case_run(case, speeds, out_dir, **options)[0]


def sweep_case_run(
    case: Case,
    speeds,
    out_dir: str,
    *,
    direction: str = "independent",
    slices: int | None = None,
    show_progress: bool = True,
    vtu_speed: float | None = None,
    **integration,
) -> tuple[dict, object]:
    """Speed sweep of a case's scene, lumped or with condensed bodies (one
    :func:`jaxgear.dynamics.speed_sweep` for both, tracking the largest Hertzian pressure per
    speed); writes ``sweep.json``, ``dynamic_factor.png``, ``campbell.png``,
    ``contact_pressure.png`` and the dynamic pressure map(s) (:func:`dynamic_pressure_map`) to
    ``out_dir`` (atomically) and returns the JSON dict. A scene with condensed bodies adds, for
    each condensed gear (a pair's pinion and/or wheel, a train's flexible gears), its
    nodal-diameter resonances (3.9) at its teeth and speed and its rim waves per speed
    (:mod:`jaxgear.cli._sweep_kinds`: the sections by the kind of model);
    ``vtu_speed`` (condensed bodies only): a VTU time series of every body at that pinion
    (input) speed, one file set per body named by its gear.

    ``integration``: the case's ``[scene.integration]`` settings replaced
    (:func:`sweep_spec`'s ``solver``, ``contact``, ``periods``, ``steps_per_period``,
    ``keep_periods``; None keeps the case's); ``slices``: the ``[mesh]`` slices replaced.

    Returns (the JSON dict, the run at the speed of the largest dynamic factor with its cell
    loads: :func:`jaxgear.dynamics.simulate`'s result, the one the dynamic pressure map
    reads, for a caller that needs those loads again; None when no speed ran to the end)."""
    spec = sweep_spec(case, direction=direction, vtu_speed=vtu_speed, **integration)
    speeds = np.asarray(speeds, dtype=float)
    hybrid = spec.hybrid  # condensed bodies to load before the model is built
    t0 = time.perf_counter()
    n_dirs = SWEEPS_PER_DIRECTION[direction]
    bar = progress_bar(
        total=n_dirs * speeds.size,
        desc=f"jaxgear sweep {case.name}" + (" (hybrid)" if hybrid else ""),
        unit="speed",
        disable=not show_progress,
    )
    bodies = None
    if hybrid:
        bar.set_postfix_str("condensed bodies (fem-prep: built once, then cached), the scene")
        bodies = case_io.load_bodies(spec, progress=inner_bars(show_progress))
    else:
        bar.set_postfix_str("building the model (modes, damping)")
    model, spec = case_io.build_dynamic_model(case, spec, slices=slices, bodies=bodies)
    check_model_options(  # what the model cannot run, asked of its kind's contract
        type(model), direction=direction, solver=integration.get("solver"), vtu_speed=vtu_speed,
        integrator_of=lambda name: (
            case_io.spec_integrator(dataclasses.replace(spec, solver=name))),
    )
    kind = sweep_kind(model)
    law = case.contact_law(spec.contact)
    # modes of the mesh-averaged system and their mesh energy shares (Campbell, critical
    # speeds): a lumped model's own; a hybrid model's at the case's speed, the mesh stiffness
    # averaged over 64 positions unless the step is fixed
    bar.set_postfix_str("modes of the mesh-averaged system")
    modes = dynamics.mesh_averaged_modes(
        model, speed=case.speed, positions_per_pitch=spec.steps_per_period or 64, contact=law
    )
    # the first chunk compiles the sweep's program before any speed is done (no estimate yet)
    bar.set_postfix_str("compiling the sweep, then the first speeds")
    last = [0]

    def progress(n):
        if last[0] == 0:
            bar.set_postfix_str("")
        bar.update(n - last[0] if n >= last[0] else n)
        last[0] = n

    hertz = dynamics.HertzPressure(tuple(case.pairs), case.youngs_modulus, case.poisson_ratio)
    outputs = dynamics.Outputs(pressure=hertz)
    settled = None
    if spec.periods is None and model.settles:  # run each speed until it settles
        res, settled = settled_sweeps(model, speeds, spec, law, outputs, direction, progress)
    else:
        res = dynamics.speed_sweep(
            model,
            speeds,
            direction=dynamics.DIRECTIONS[direction],
            batching=dynamics.Batching(kind.chunk_size(speeds.size), progress),
            integrator=case_io.spec_integrator(spec),
            contact=law,
            window=case_io.spec_window(spec),
            outputs=outputs,
        )
    jax.block_until_ready(res)
    bar.close()
    # what follows the speeds: a bar over its three stages (a second run at the worst speed)
    post = progress_bar(
        total=3, desc=f"jaxgear sweep {case.name}: outputs", disable=not show_progress
    )
    post.set_postfix_str("modes at the speeds, static pressures")
    r = res.results
    # the lowest modes reported (0 Hz for the drive rotation)
    omega = np.asarray(modes.omega)[: kind.n_modes]
    energy = np.asarray(modes.mesh_energy)[: kind.n_modes]
    z1 = 2 * math.pi / float(model.scene.base_planes[0].mesh_period_angle)
    summary = {
        "case": case.name,
        "model": kind.model_name(spec),
        "reduction": spec.reduction,
        "solver": spec.solver,
        "contact": spec.contact,
        "direction": direction,
        "steps_per_period": spec.steps_per_period or "auto",
        "periods": spec.periods or "auto",
        "keep_periods": spec.keep_periods,
        "damping": spec.damping_model,
        "torque_Nm": case.torque,
    }
    n_meshes = len(r.meshes)  # the results' (a 1-DOF relative scene has no .meshes)
    if n_meshes == 1:
        summary["static_mesh_force_N"] = float(model.static_force)
    else:  # a train: each mesh's, from its first speed
        summary["speed_of"] = "input"  # speeds of the input gear
        summary["mesh_names"] = [case.mesh_name(k) for k in range(n_meshes)]
        summary["static_mesh_force_N"] = [float(m.static_force[0]) for m in r.meshes]
    flexible = kind.flexible_gears(case, model)
    summary.update(kind.structure_keys(case, model, spec, n_meshes, flexible))
    summary.update(
        {
            "natural_frequencies_Hz": clean(omega / (2 * math.pi)),
            "mesh_energy_share": clean(energy),
        }
    )
    summary.update(kind.modal_keys(model, spec, modes, n_meshes))
    at_speed, grid, omega, at = kind.campbell_modes(model, modes, speeds, omega)
    summary.update(at_speed)
    summary["critical_speeds"] = dynamics.campbell_coincidences(
        omega, energy, z1, float(speeds.max()), n_modes=3, speeds=grid
    )
    if n_meshes > 1:  # each mesh's order (its teeth per input turn) and its coincidences
        orders = [
            2 * math.pi * float(m.ratio) / float(m.base_plane.mesh_period_angle)
            for m in model.scene.meshes
        ]
        summary["mesh_orders"] = orders
        summary["critical_speeds_mesh"] = [
            dynamics.campbell_coincidences(
                omega, energy, z, float(speeds.max()), n_modes=3, speeds=grid
            )
            for z in orders
        ]
    tones = bearing_tone_orders(case)  # rolling bearings' tones, orders of the pinion speed
    if tones:
        summary["bearing_tones"] = tones
    summary.update(kind.resonance_keys(model, modes, speeds, flexible, at))
    summary.update({"speeds_rad_s": clean(speeds), "mesh_frequency_Hz": clean(r.mesh_frequency)})
    summary.update(mesh_responses(model, r, speeds))
    summary.update(pressure_responses(r, kind.static_pressures(model, r, law, hertz)))
    summary.update(
        {
            "steps_per_period_used": [int(v) for v in np.asarray(r.steps_per_period)],
            "steps_per_mode_period": clean(r.steps_per_mode_period),
            "under_resolved": [bool(v) for v in np.asarray(r.under_resolved)],
            "result": [int(v) for v in np.asarray(r.result)],
        }
    )
    summary.update(settled_keys(r, settled, speeds, spec))
    summary.update(kind.rim_keys(r, flexible, z1))
    summary.update(
        {
            "bearing_names": list(bearing_names(model.scene)),
            "bearing_force_max_N": [clean(row) for row in np.asarray(r.bearing_force_max)],
            # at the first speed (a hybrid model's: its centrifugal load)
            "bearing_force_static_N": clean(np.asarray(r.bearing_force_static)[0])
            if np.asarray(r.bearing_force_static).size
            else [],
            "result_messages": {str(k): v for k, v in DynamicsResult.messages().items()},
        }
    )
    if res.down is not None:
        d = res.down
        summary.update(
            {
                "dynamic_factor_down": clean(worst(d, "dynamic_factor")),
                "dynamic_factor_tooth_down": clean(worst(d, "dynamic_factor_tooth")),
                "te_rms_m_down": clean(of_worst(d, "te_rms")),
                "contact_loss_down": clean(worst(d, "contact_loss")),
                "max_contact_pressure_Pa_down": clean(worst(d, "max_pressure")),
                "result_down": [int(v) for v in np.asarray(d.result)],
                **(backlash_responses(d, "_down") if len(d.meshes) == 1 else {}),
            }
        )
    post.update()
    post.set_postfix_str("pressure map at the worst speed (one more run)")
    # the pressure map at the speed of the largest dynamic factor: one more run, cell loads on
    # with a VTU series, the map's run records the states too: one program for both runs
    dyn_map = dynamic_pressure_map(
        case,
        model,
        spec,
        law,
        r,
        speeds,
        hertz,
        states=vtu_speed is not None,
        window=None if settled is None else settled[0].window,
        phase=None if settled is None else settled[0].phase,
    )
    summary.update(kind.closing_keys(model, bodies, spec, law, modes, vtu_speed, out_dir, flexible))
    post.update()
    post.set_postfix_str("files and plots")
    summary["elapsed_s"] = time.perf_counter() - t0
    summary["platform"] = {
        "jax": jax.__version__,
        "device": str(jax.devices()[0].platform),
        "devices": len(jax.local_devices()),
        "python": platform.python_version(),
    }
    if dyn_map is not None:
        summary["pressure_map_dynamic"] = dyn_map["summary"]
    write_sweep(case, summary, out_dir, z1, dyn_map)
    post.update()
    post.close()
    return summary, None if dyn_map is None else dyn_map["run"]


def settled_sweeps(model, speeds, spec, law, outputs, direction: str, progress) -> tuple:
    """The sweep of a case whose ``periods`` are ``"auto"``: each speed run until it settles,
    by continuation (:func:`jaxgear.dynamics.settled_sweep`): up for ``independent`` and ``up``
    (the first speed from the static equilibrium, the slowest: it pays the settling once), down
    for ``down``, both for ``both``. Returns (:class:`~jaxgear.dynamics.SweepResult`, the
    :class:`~jaxgear.dynamics.SettledSweep` of each pass: (up or down,) or (up, down))."""
    passes = {"independent": (False,), "up": (False,), "down": (True,), "both": (False, True)}
    n = speeds.size
    runs = []
    for k, descending in enumerate(passes[direction]):
        runs.append(
            dynamics.settled_sweep(
                model,
                speeds,
                integrator=case_io.spec_integrator(spec),
                contact=law,
                keep_periods=spec.keep_periods,
                outputs=outputs,
                descending=descending,
                progress=lambda i, base=k * n: progress(base + i),
            )
        )
    for run in runs:  # one line per speed at its cap unsettled (stderr, as the CLI's warnings)
        for line in dynamics.unsettled_lines(run):
            print(f"jaxgear: warning: {line}", file=sys.stderr, flush=True)
    down = runs[1].sweep.results if len(runs) == 2 else None
    return dynamics.SweepResult(runs[0].sweep.speeds, runs[0].sweep.results, down), tuple(runs)


def settled_keys(r, settled, speeds, spec) -> dict:
    """``sweep.json``'s keys of whether each speed settled: ``settled`` (bool per speed),
    ``periods_run`` (mesh periods each speed ran) and, for a settled sweep (``periods =
    "auto"``, ``settled`` its :class:`~jaxgear.dynamics.SettledSweep` passes), ``settle_change``
    (the change of the kept forces from one window to the next, or of the last kept period
    from the one before where larger, over the static mesh force) and ``settle`` (the rule's
    numbers: t_s, the mode that sets it, the window, the tolerance, each speed's cap). Where
    ``periods`` are given, the span is honoured and ``settled`` is the records' periodicity
    (the last kept period against the one before, None where the kept periods hold fewer than
    two of the scene's) within :data:`jaxgear.dynamics.SETTLED_TOL` (``jaxgear sweep`` prints
    how many are not; a settled sweep warns at a speed that reaches its cap unsettled)."""
    tol = dynamics.SETTLED_TOL
    if settled is None:
        per = worst(r, "periodicity")
        flags = [None if not math.isfinite(v) else bool(v <= tol) for v in per]
        span = case_io.spec_window(spec).periods
        return {"settled": flags, "periods_run": [int(span)] * len(flags)}
    up = settled[0]
    out = {
        "settled": [bool(v) for v in up.settled],
        "periods_run": [int(v) for v in up.periods],
        "settle_change": clean(up.change),
        "settle": {
            "settle_s": up.settle_s,
            "f_min_Hz": up.f_min_Hz,
            "tolerance": dynamics.SETTLE_TOL,
            "settled_tolerance": tol,
            "window_periods": up.window,
            "cap_periods": [int(v) for v in up.cap],
        },
    }
    if len(settled) == 2:
        out["settled_down"] = [bool(v) for v in settled[1].settled]
        out["periods_run_down"] = [int(v) for v in settled[1].periods]
    return out


def default_sweep_dir(case_name: str, speeds) -> str:
    """``jaxgear sweep``'s default folder, ``jaxgear-out/<case>/sweep-START-STOP-N``: its own,
    so that it never replaces the ``sweep/`` of ``jaxgear run`` (which the run's
    ``summary.json`` describes under ``dynamics``), and sweeps over other speeds stay."""
    a, b = float(speeds[0]), float(speeds[-1])
    return os.path.join("jaxgear-out", case_name, f"sweep-{a:g}-{b:g}-{len(speeds)}")


def run_sweep(args) -> int:
    """Run ``jaxgear sweep`` (float64 must already be on: the CLI does it): one command for
    every case form (:func:`sweep_command`). Returns 0."""
    speeds = range_values(args.speeds, "--speeds", positive=True, min_points=2)
    case = case_io.load_case(args.case)
    return sweep_command(case, speeds, args)


def sweep_options(args) -> dict:
    """The options of ``jaxgear sweep`` that every form's sweep takes, by their Python names
    (:func:`sweep_spec`'s; ``periods`` ``"auto"``: the automatic span)."""
    return dict(  # noqa: C408 - the keyword names are sweep_spec's
        direction=args.direction,
        solver=args.solver,
        contact=args.contact,
        periods=args.periods,
        steps_per_period=args.steps_per_period,
        keep_periods=args.keep_periods,
        vtu_speed=args.vtu_speed,
    )


def sweep_command(case, speeds, args) -> int:
    """``jaxgear sweep`` on a case of any form (:class:`~jaxgear.io.CaseForm`): the options
    checked before any file is touched (the form's own ranges, :func:`check_sweep`, and what
    the case's dynamic model kind cannot do asked of its contract, :func:`check_model_options`),
    the form's sweep written into a staging folder moved in place when it completes
    (:func:`sweep_files`: :func:`jaxgear.dynamics.speed_sweep` of the case's
    :func:`~jaxgear.io.build_dynamic_model`), then its lines printed (:func:`sweep_report`).
    Returns 0."""
    out = check_case_outputs(case, "sweep", args.out or default_sweep_dir(case.name, speeds),
                             force=args.force)
    options = sweep_options(args)
    check_sweep(case.form, case, slices=args.slices, **options)  # before any file
    with staged_outputs(out, "sweep") as work:
        s = sweep_files(
            case.form, case, speeds, work, slices=args.slices, show_progress=not args.quiet,
            **options,
        )
    for line in sweep_report(case.form, case, s):
        print(line)
    print(f"written to {out}/")
    return 0


@functools.singledispatch
def check_sweep(form, case, *, slices=None, **options) -> None:
    """Every check of ``jaxgear sweep``'s options on a case of ``form`` before any file is
    touched: a case's ``[scene]`` (pairs and trains): :func:`sweep_spec`, then what its
    model's kind cannot run, asked of the kind's contract before any model is built
    (:func:`~jaxgear.cli._sweep_kinds.check_case_options`)."""
    sweep_spec(case, **options)
    check_case_options(case, **options)


@functools.singledispatch
def sweep_files(form, case, speeds, out_dir: str, **options) -> dict:
    """The sweep of a case of ``form`` written into ``out_dir``; returns ``sweep.json``'s
    dict. A case's ``[scene]`` (pairs and trains): :func:`sweep_case`."""
    return sweep_case(case, speeds, out_dir, **options)


@functools.singledispatch
def sweep_report(form, case, s: dict) -> list[str]:
    """What ``jaxgear sweep`` prints after the sweep of a case of ``form`` (``s``: its
    ``sweep.json``); a pair's and a train's, with a warning where speeds are under-resolved."""
    df = np.asarray([np.nan if v is None else v for v in s["dynamic_factor"]])
    i = int(np.nanargmax(df)) if np.isfinite(df).any() else 0
    n_bad = sum(1 for v in s["result"] if v)
    natural = [f for f in s["natural_frequencies_Hz"] if f][:6]
    lines = [(
        f"{case.name}: {len(df)} speeds, max dynamic factor {df[i]:.3f} at "
        f"{s['speeds_rad_s'][i]:.1f} rad/s; first natural frequencies "
        f"{', '.join(f'{f:.0f}' for f in natural)} Hz; {n_bad} diverged; {s['elapsed_s']:.1f} s"
    )]
    n_open = sum(1 for v in s.get("settled", ()) if v is False)
    if n_open:
        lines.append(
            f"{n_open} of {len(df)} speeds not settled (sweep.json settled, periodicity: the "
            f"last kept period against the one before > {dynamics.SETTLED_TOL:g} of the static "
            f'mesh force): raise --periods, or leave periods "auto" (each speed until it '
            "settles)"
        )
    lines += housing_band_lines(case, s["speeds_rad_s"])  # a housed case's band
    n_under = sum(s.get("under_resolved", ()))
    if n_under:
        warnings.warn(
            f"{n_under} of {len(df)} speeds are under-resolved "
            f"(< {dynamics.UNDER_RESOLVED_STEPS} time steps per period of the "
            "highest mode the mesh excites; see sweep.json steps_per_mode_period): raise "
            "--steps-per-period or leave it automatic",
            stacklevel=4,  # run_sweep's line (the dispatch adds a frame)
        )
    return lines


check_sweep.register(case_io.PlanetaryForm, check_planetary_sweep)
sweep_files.register(case_io.PlanetaryForm, planetary_sweep_files)
sweep_report.register(case_io.PlanetaryForm, lambda form, case, s: sweep_lines(case, s))


check_sweep.register(case_io.GearboxForm, check_gearbox_sweep)
sweep_files.register(case_io.GearboxForm, gearbox_sweep_files)
sweep_report.register(case_io.GearboxForm, gearbox_sweep_lines)


def housing_band_lines(case, speeds) -> list[str]:
    """One line where speeds of a housed case's sweep lie above its housing's speed limit
    (:func:`jaxgear.io.housing_band`: a mesh's order-1 frequency beyond the housing's
    band), nothing otherwise (no ``[housing]``, or every speed within)."""
    hb = case_io.housing_band(case)
    above = [] if hb is None else [v for v in speeds if v > hb.speed_limit]
    if not above:
        return []
    line = (
        f"{len(above)} of {len(speeds)} speeds above {hb.speed_limit:.4g} rad/s, where the "
        f"order-1 mesh frequency leaves the housing's band ({hb.band_hz:.4g} Hz = cut-off / "
        f"{case_io.HOUSING_BAND:g}): the housing's modes beyond its cut-off are not in the model "
        "there (a higher [housing] cut-off holds them)"
    )
    return [line]
