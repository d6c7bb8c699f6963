"""``jaxgear sweep``: dynamic factor against pinion speed for a case's ``[scene]`` (its schema:
:func:`jaxgear.io.parse_scene` and docs/dynamics.md), written as ``sweep.json``,
``dynamic_factor.png``, ``campbell.png``, ``contact_pressure.png`` (the largest Hertzian
pressure per speed) and ``pressure_map_dynamic.png`` (the pressure over a tooth's passage at
the speed of the largest dynamic factor; a train: ``pressure_map_dynamic_<mesh>.png``)."""

from __future__ import annotations

import argparse
import dataclasses
import math
import os
import platform
import time
import warnings
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # importing this module stays free of JAX (the CLI builds its parser early)
    from .. import Case

__all__ = ["add_sweep_parser", "default_sweep_dir", "run_sweep", "sweep_case"]

# a hybrid run without the rotating-frame terms warns when the modes move more than this by the
# top speed (the critical speeds at rest are then off by about as much)
STIFFENING_WARN = 0.05
# pinion speeds (0 to 1.05 x the top speed) at which a hybrid sweep follows the modes
CAMPBELL_GRID = 43
# the lowest elastic modes of a hybrid structure searched for each condensed gear's
# nodal-diameter families (seed (3.9))
ND_MODES = 40


def _clean(values) -> list:
    return [float(v) if np.isfinite(v) else None for v in np.asarray(values, dtype=float)]


def _rim_content(sw, i, f_mesh, stations: slice, spin: float) -> dict:
    """The largest rim wave n >= 1 of speed ``i`` above half the mesh frequency ``f_mesh``
    (Hz), axial and radial, of the condensed gear whose stations are ``stations`` of the rim
    records, turning in the ``spin`` sense (direction +1: forward, with its rotation)."""
    from ..dynamics import rim_waves

    out = {}
    for comp in ("axial", "radial"):
        u = np.asarray(getattr(sw, f"rim_{comp}")[i])[:, stations]
        w = rim_waves(u, float(sw.time_step[i]), spin, (0.5 * f_mesh, np.inf))
        n = 1 + int(np.argmax(w["amplitude"][1:]))
        out[comp] = {
            "nodal_diameter": n,
            "amplitude_m": float(w["amplitude"][n]),
            "frequency_Hz": float(w["frequency_hz"][n]),
            "direction": int(w["direction"][n]),
        }
    return out


def _flexible_gears(case, scene) -> list[dict]:
    """Every condensed gear of a hybrid scene, in member order: ``name`` (a pair's "pinion" or
    "gear", a train's gear name), ``member`` (its index in ``scene.members``), ``teeth`` Z,
    ``speed_ratio`` (its turns per turn of the pinion or input, > 0), ``spin`` (its sense about
    z, ±1), ``stations`` (the slice of its stations in the rim records) and ``meshes`` (the
    names of the meshes it is in)."""
    from .. import TrainCase
    from ..dynamics import rim_stations

    train = isinstance(case, TrainCase)
    names = case.gear_names if train else ("pinion", "gear")
    out = []
    for m, stations in rim_stations(scene):
        member = scene.members[m]
        if train:
            meshes = [case.mesh_name(k) for k, gears in enumerate(case.gears) if m in gears]
        else:
            meshes = [case.name]
        out.append(
            {
                "name": names[m],
                "member": m,
                "teeth": int(member.rim_dofs.shape[0]),
                "speed_ratio": float(member.ratio),
                "spin": float(member.spin),
                "stations": stations,
                "meshes": meshes,
            }
        )
    return out


def _passing_rate(gear: dict, z1: float) -> float:
    """The condensed ``gear``'s tooth-passing frequency over the first mesh's (z1 the first
    mesh's order): Z × its speed ratio / z1; exactly 1 where they agree to 1e-9 (a pair's
    wheel, an idler train's gears)."""
    rate = gear["teeth"] * gear["speed_ratio"] / z1
    return 1.0 if abs(rate - 1.0) < 1e-9 else rate


def sweep_spec(
    case,
    *,
    direction: str = "independent",
    solver: str | None = None,
    contact: str | None = None,
    periods: int | None = None,
    steps_per_period: int | None = None,
    keep_periods: int | None = None,
    vtu_speed: float | None = None,
):
    """The :class:`~jaxgear.dynamics.SceneSpec` a sweep of ``case`` runs (its ``[scene]``, the
    options given replacing its settings), checked before any work: one-line ``ValueError``
    naming the option (``--periods``) or the case-file key (``[scene.integration] periods``),
    its value and the allowed range."""
    from .. import TrainCase
    # MAX_STEPS_PER_SPEED: jaxgear.dynamics' bound (its runs refuse more, but only once the
    # model is built); checked here before any work
    from ..dynamics import MAX_STEPS_PER_SPEED, MIN_STEPS_PER_PERIOD, SceneSpec

    spec = case.scene if case.scene is not None else SceneSpec()
    given = dict(
        solver=solver,
        contact=contact,
        periods=periods,
        steps_per_period=steps_per_period,
        keep_periods=keep_periods,
    )
    over = {k: v for k, v in given.items() if v is not None}
    spec = dataclasses.replace(spec, **over)

    def name(key: str) -> str:
        if key in over:
            return "--" + key.replace("_", "-")
        return f"[scene.integration] {key}"

    if spec.keep_periods > spec.periods:
        raise ValueError(
            f"{name('keep_periods')} = {spec.keep_periods}: out of range, allowed <= "
            f"{name('periods')} = {spec.periods}"
        )
    if isinstance(case, TrainCase) and spec.keep_periods < case.span_periods:
        q = case.span_periods
        raise ValueError(
            f"{name('keep_periods')} = {spec.keep_periods}: out of range, allowed >= {q} (the "
            f"meshes of {case.name} repeat together every {q} periods of the first mesh: the "
            "kept periods must hold every mesh position)"
        )
    steps = spec.steps_per_period or MIN_STEPS_PER_PERIOD
    if spec.periods * steps > MAX_STEPS_PER_SPEED:
        at = (
            f"{steps} time steps per mesh period ({name('steps_per_period')})"
            if spec.steps_per_period
            else f"at least {steps} time steps per mesh period (automatic)"
        )
        raise ValueError(
            f"{name('periods')} = {spec.periods}: out of range, allowed <= "
            f"{MAX_STEPS_PER_SPEED // steps} at {at}: {spec.periods * steps:.3g} time steps "
            f"per speed, allowed <= {MAX_STEPS_PER_SPEED:.3g} (fewer periods or steps per period)"
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


def sweep_case(
    case: Case,
    speeds,
    out_dir: str,
    *,
    direction: str = "independent",
    solver: str | None = None,
    contact: str | None = None,
    periods: int | None = None,
    steps_per_period: int | None = None,
    keep_periods: int | None = None,
    slices: int | None = None,
    show_progress: bool = True,
    vtu_speed: float | None = None,
) -> dict:
    """Speed sweep of a case's scene, lumped or with condensed bodies (one
    :func:`jaxgear.dynamics.speed_sweep` for both, tracking the largest Hertzian pressure per
    speed); writes ``sweep.json``, ``dynamic_factor.png``, ``campbell.png``,
    ``contact_pressure.png`` and the dynamic pressure map(s) (:func:`_dynamic_pressure_map`) to
    ``out_dir`` (atomically) and returns the JSON dict. A scene with condensed bodies adds, for
    each condensed gear (a pair's pinion and/or wheel, a train's flexible gears), its
    nodal-diameter resonances (3.9) at its teeth and speed and its rim waves per speed;
    ``vtu_speed`` (condensed bodies only): a VTU time series of every body at that pinion
    (input) speed, one file set per body named by its gear."""
    import jax
    from tqdm.auto import tqdm

    from .. import DynamicsResult, TrainCase
    from ..dynamics import (
        HertzPressure,
        build_dynamic_model,
        campbell_coincidences,
        load_bodies,
        mesh_averaged_modes,
        modes_at_speed,
        spec_integrator,
        spec_window,
        speed_sweep,
    )

    spec = sweep_spec(
        case,
        direction=direction,
        solver=solver,
        contact=contact,
        periods=periods,
        steps_per_period=steps_per_period,
        keep_periods=keep_periods,
        vtu_speed=vtu_speed,
    )
    speeds = np.asarray(speeds, dtype=float)
    hybrid = spec.hybrid
    t0 = time.perf_counter()
    n_dirs = 2 if direction == "both" else 1
    bar = tqdm(
        total=n_dirs * speeds.size,
        desc=f"jaxgear sweep {case.name}" + (" (hybrid)" if hybrid else ""),
        unit="speed",
        disable=not show_progress,
    )
    bodies = None
    if hybrid:
        bar.set_postfix_str("condensed bodies (fem-prep: built once, then cached), the scene")
        bodies = load_bodies(spec, progress=show_progress)
    else:
        bar.set_postfix_str("building the model (modes, damping)")
    model, spec = build_dynamic_model(case, spec, slices=slices, bodies=bodies)
    law = case.contact_law(spec.contact)
    # modes of the mesh-averaged system and their mesh energy shares (Campbell, critical
    # speeds): a lumped model's own; a hybrid model's at the case's speed, the mesh stiffness
    # averaged over 64 positions unless the step is fixed
    bar.set_postfix_str("modes of the mesh-averaged system")
    modes = mesh_averaged_modes(
        model, speed=case.speed, positions_per_pitch=spec.steps_per_period or 64, contact=law
    )
    bar.set_postfix_str("")
    last = [0]

    def progress(n):
        bar.update(n - last[0] if n >= last[0] else n)
        last[0] = n

    # a hybrid model one speed per call (a speed takes seconds: the bar moves per speed and
    # Ctrl-C stops the sweep after the speed in progress); a lumped one in about ten chunks
    chunk = 1 if hybrid else max(1, min(32, -(-speeds.size // 10)))
    pairs = tuple(case.pairs) if isinstance(case, TrainCase) else (case.pair,)
    hertz = HertzPressure(pairs, case.youngs_modulus, case.poisson_ratio)
    res = speed_sweep(
        model,
        speeds,
        direction=direction,
        chunk_size=chunk,
        progress=progress,
        integrator=spec_integrator(spec),
        contact=law,
        window=spec_window(spec),
        pressure=hertz,
    )
    jax.block_until_ready(res)
    bar.close()
    r = res.results
    # the lowest modes reported: every mode of a lumped model, the 20 lowest of a hybrid one
    # (thousands of coordinates); 0 Hz for the drive rotation
    n_modes = 20 if hybrid else None
    omega = np.asarray(modes.omega)[:n_modes]
    energy = np.asarray(modes.mesh_energy)[:n_modes]
    z1 = 2 * math.pi / float(model.scene.base_planes[0].mesh_period_angle)
    summary = {
        "case": case.name,
        "model": "hybrid" if hybrid else spec.model,
        "reduction": spec.reduction,
        "solver": spec.solver,
        "contact": spec.contact,
        "direction": direction,
        "steps_per_period": spec.steps_per_period or "auto",
        "periods": spec.periods,
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
    # the condensed gears whose nodal diameters and rim waves are reported: every one
    flexible = _flexible_gears(case, model.scene) if hybrid else []
    if hybrid:
        summary.update(
            {
                "rayleigh_alpha_per_s": spec.rayleigh_alpha,
                "rayleigh_beta_s": spec.rayleigh_beta,
                "damping_ratio_mesh_structure": [spec.mesh_ratio, spec.structure_ratio],
                "rotating_frame": spec.rotating_frame,
            }
        )
        if not isinstance(case, TrainCase):
            summary.update(pinion_teeth=case.pair.pinion.teeth, wheel_teeth=case.pair.gear.teeth)
        summary["flexible_gears"] = [g["name"] for g in flexible]
        summary["flexible_gear_teeth"] = [g["teeth"] for g in flexible]
        summary["flexible_gear_speed_ratio"] = [g["speed_ratio"] for g in flexible]
        summary["flexible_gear_meshes"] = [g["meshes"] for g in flexible]
    elif n_meshes == 1:
        summary["mesh_stiffness_mean_N_per_m"] = float(model.mesh_stiffness_mean)
    else:  # each mesh's time-averaged loaded stiffness
        from ..dynamics import mesh_stiffness_means

        ppp = spec.steps_per_period or 64
        summary["mesh_stiffness_mean_N_per_m"] = [
            float(k) for k in np.asarray(mesh_stiffness_means(model, positions_per_pitch=ppp))
        ]
    summary.update(
        {
            "natural_frequencies_Hz": _clean(omega / (2 * math.pi)),
            "mesh_energy_share": _clean(energy),
        }
    )
    if n_meshes > 1 and not hybrid:  # each mesh's share of each mode's strain energy
        from ..dynamics import mesh_energy_shares

        shares = np.asarray(
            mesh_energy_shares(model, positions_per_pitch=spec.steps_per_period or 64)
        )
        summary["mesh_energy_share_mesh"] = [_clean(row) for row in shares.T[:n_modes]]
    if not hybrid:
        summary["modal_energy_parts"] = list(modes.parts)
        summary["modal_energy"] = [_clean(row) for row in np.asarray(modes.energy)]
    # a hybrid scene's modes at speed (spin softening and stress stiffening, checked at the top
    # speed): the Campbell diagram and the critical speeds follow them when the run has the
    # rotating-frame terms
    grid = None
    if hybrid:
        at = modes_at_speed(
            model.scene, modes, np.linspace(0.0, 1.05 * speeds.max(), CAMPBELL_GRID)
        )
        summary.update(_at_speed_keys(at, n_modes, model.rotating_frame))
        if model.rotating_frame:
            grid = np.asarray(at.speeds)
            omega = np.asarray(at.omega)[:, :n_modes]
        elif at.shift > STIFFENING_WARN:
            warnings.warn(
                f"the structure's modes move by up to {at.shift:.1%} at "
                f"{float(at.speeds[-1]):.6g} rad/s (spin softening, stress stiffening), which "
                "this run leaves out: [scene."
                "integration] rotating_frame = true adds them (the critical speeds and the "
                "Campbell diagram then follow the modes at speed)",
                stacklevel=2,
            )
    summary["critical_speeds"] = campbell_coincidences(
        omega, energy, z1, float(speeds.max()), n_modes=3, speeds=grid
    )
    if n_meshes > 1:  # each mesh's order (its teeth per input turn) and its coincidences
        orders = [
            2 * math.pi * float(m.ratio) / float(m.base_plane.mesh_period_angle)
            for m in model.scene.meshes
        ]
        summary["mesh_orders"] = orders
        summary["critical_speeds_mesh"] = [
            campbell_coincidences(omega, energy, z, float(speeds.max()), n_modes=3, speeds=grid)
            for z in orders
        ]
    if hybrid:
        summary["nodal_diameter_resonances"] = [
            row
            for g in flexible
            for row in _nodal_diameter_resonances(
                model.scene, modes, speeds, g, at if grid is not None else None
            )
        ]
    summary.update({"speeds_rad_s": _clean(speeds), "mesh_frequency_Hz": _clean(r.mesh_frequency)})
    summary.update(_mesh_responses(model, r, speeds))
    summary.update(_pressure_responses(model, r, law, hybrid, hertz))
    summary.update(
        {
            "steps_per_period_used": [int(v) for v in np.asarray(r.steps_per_period)],
            "steps_per_mode_period": _clean(r.steps_per_mode_period),
            "under_resolved": [bool(v) for v in np.asarray(r.under_resolved)],
            "result": [int(v) for v in np.asarray(r.result)],
        }
    )
    if hybrid:  # each condensed gear's, per speed, above half its own tooth-passing frequency
        summary["rim_waves"] = {
            g["name"]: [
                _rim_content(r, i, float(f) * _passing_rate(g, z1), g["stations"], g["spin"])
                for i, f in enumerate(np.asarray(r.mesh_frequency))
            ]
            for g in flexible
        }
    summary.update(
        {
            "bearing_names": list(getattr(model.scene, "reaction_names", ())),
            "bearing_force_max_N": [_clean(row) for row in np.asarray(r.bearing_force_max)],
            # at the first speed (a hybrid model's: its centrifugal load)
            "bearing_force_static_N": _clean(np.asarray(r.bearing_force_static)[0])
            if np.asarray(r.bearing_force_static).size
            else [],
            "result_messages": {str(k): v for k, v in DynamicsResult.messages().items()},
        }
    )
    if res.down is not None:
        d = res.down
        summary.update(
            {
                "dynamic_factor_down": _clean(_worst(d, "dynamic_factor")),
                "dynamic_factor_tooth_down": _clean(_worst(d, "dynamic_factor_tooth")),
                "te_rms_m_down": _clean(_of_worst(d, "te_rms")),
                "contact_loss_down": _clean(_worst(d, "contact_loss")),
                "max_contact_pressure_Pa_down": _clean(_worst(d, "max_pressure")),
                "result_down": [int(v) for v in np.asarray(d.result)],
                **(_backlash_responses(d, "_down") if len(d.meshes) == 1 else {}),
            }
        )
    # the pressure map at the speed of the largest dynamic factor: one more run, cell loads on
    dyn_map = _dynamic_pressure_map(case, model, spec, law, r, speeds, hertz)
    if hybrid:
        vtu = _vtu_series(model, bodies, spec, law, modes, vtu_speed, out_dir, flexible)
        summary["vtu_series"] = {"speed_rad_s": vtu_speed, "files": vtu} if vtu else None
        summary["notes"] = (
            "hybrid model (condensed bodies): Newmark in the cell space, centrifugal loads on, "
            "damping on the mesh-averaged system ([scene.damping]); steps_per_period_used per "
            "speed (automatic unless [scene.integration] sets it; with several, the kept records "
            "are subsampled to the smallest); rim_waves: each condensed gear's largest rim wave "
            "above half the mesh frequency per nodal diameter (its body frame, direction +1 "
            "forward, with its rotation); nodal_diameter_resonances: (3.9) for each condensed "
            "gear at its teeth and speed (gear, teeth, speed_ratio); bearing "
            "forces in the fixed frame, the static ones at the first speed (its centrifugal load)"
        )
    summary["elapsed_s"] = time.perf_counter() - t0
    summary["platform"] = {
        "jax": jax.__version__,
        "device": str(jax.devices()[0].platform),
        "devices": len(jax.local_devices()),
        "python": platform.python_version(),
    }
    if dyn_map is not None:
        summary["pressure_map_dynamic"] = dyn_map["summary"]
    _write(summary, out_dir, z1, dyn_map)
    return summary


def _worst(r, field: str) -> np.ndarray:
    """``field`` of the results ``r`` per speed, the largest over the meshes (S,)."""
    return np.max(np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], -1), -1)


def _of_worst(r, field: str) -> np.ndarray:
    """``field`` of the results ``r`` per speed, of the mesh of the highest dynamic factor (S,)."""
    per = np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], -1)
    df = np.stack([np.asarray(m.dynamic_factor, float) for m in r.meshes], -1)
    return per[np.arange(per.shape[0]), np.argmax(df, -1)]


def _mesh_responses(model, r, speeds) -> dict:
    """The per-speed responses of ``sweep.json``: a pair's as they were; a train's scene-level
    keys take its worst mesh (dynamic factors, TE RMS of the mesh of the highest dynamic
    factor, contact loss and periodicity the largest) beside each mesh's (speeds × meshes):
    ``dynamic_factor_mesh``, ``dynamic_factor_tooth_mesh``, ``te_rms_mesh_m``,
    ``te_mean_mesh_m``, ``contact_loss_mesh`` and ``mesh_frequency_mesh_Hz`` (each mesh's
    tooth-passing frequency, from its driving gear's speed)."""
    keys = (
        ("dynamic_factor", "dynamic_factor"),
        ("dynamic_factor_tooth", "dynamic_factor_tooth"),
        ("te_rms", "te_rms_m"),
        ("te_mean", "te_mean_m"),
        ("contact_loss", "contact_loss"),
        ("periodicity", "periodicity"),
    )
    if len(r.meshes) == 1:
        return {name: _clean(getattr(r, field)) for field, name in keys} | _backlash_responses(r)
    out = {
        "dynamic_factor": _clean(_worst(r, "dynamic_factor")),
        "dynamic_factor_tooth": _clean(_worst(r, "dynamic_factor_tooth")),
        "te_rms_m": _clean(_of_worst(r, "te_rms")),
        "te_mean_m": _clean(_of_worst(r, "te_mean")),
        "contact_loss": _clean(_worst(r, "contact_loss")),
        "periodicity": _clean(_worst(r, "periodicity")),
    }
    for field, name in keys[:5]:  # (S, m)
        per = np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], axis=-1)
        out[name.removesuffix("_m") + "_mesh" + ("_m" if name.endswith("_m") else "")] = [
            _clean(row) for row in per
        ]
    freq = [
        float(mesh.ratio) / float(mesh.base_plane.mesh_period_angle) for mesh in model.scene.meshes
    ]  # cycles per radian of the input
    out["mesh_frequency_mesh_Hz"] = [_clean(w * np.asarray(freq)) for w in np.asarray(speeds)]
    return out


def _backlash_responses(r, suffix: str = "") -> dict:
    """With coast flanks (backlash; docs/backlash.md): the share of the kept steps on the coast
    flank and the re-contacts (impacts) on the drive and the coast flank per speed; {} without."""
    if r.meshes[0].coast_share is None:
        return {}
    return {
        f"coast_share{suffix}": _clean(r.coast_share),
        f"impacts_drive{suffix}": [int(v) for v in np.asarray(r.impacts_drive)],
        f"impacts_coast{suffix}": [int(v) for v in np.asarray(r.impacts_coast)],
    }


def _at_speed_keys(at, n_modes: int, used: bool) -> dict:
    """sweep.json's keys of the modes at speed (:func:`jaxgear.dynamics.modes_at_speed`)."""
    return {
        "campbell_at_speed": bool(used),
        "campbell_speeds_rad_s": _clean(at.speeds),
        "natural_frequencies_at_speed_Hz": [
            _clean(row) for row in np.asarray(at.omega)[:, :n_modes] / (2 * math.pi)
        ],
        "modes_at_speed_error": at.error,
        "modes_at_speed_shift": at.shift,
    }


def _pressure_responses(model, r, law, hybrid: bool, hertz) -> dict:
    """The Hertzian pressures of ``sweep.json`` (Pa): per speed the largest over the kept steps
    and the cells (``max_contact_pressure_Pa``; a train's worst mesh, with each mesh's under
    ``max_contact_pressure_mesh_Pa``, speeds × meshes), and the quasi-static maximum at rest
    for reference (``max_contact_pressure_static_Pa``; a train's per mesh under
    ``max_contact_pressure_static_mesh_Pa``): a lumped model's from its own static solution at
    the table positions (the largest over the speeds' tables), a hybrid model's from
    :func:`jaxgear.quasi_static` of its scene at rest (64 positions per mesh period)."""
    if hybrid:
        from .. import contact_pressure, quasi_static

        qs = quasi_static(model.scene, model.mods, model.torque, contact=law, throw=False)
        static = [
            float(
                np.max(
                    np.asarray(
                        contact_pressure(
                            pair, m, hertz.youngs_modulus, hertz.poisson_ratio
                        ).max_pressure
                    )
                )
            )
            for pair, m in zip(hertz.pairs, qs.meshes, strict=True)
        ]
    else:
        static = [float(np.nanmax(np.asarray(m.max_pressure_static))) for m in r.meshes]
    out = {
        "max_contact_pressure_Pa": _clean(_worst(r, "max_pressure")),
        "max_contact_pressure_static_Pa": max(static),
    }
    if len(r.meshes) > 1:
        per = np.stack([np.asarray(m.max_pressure, float) for m in r.meshes], axis=-1)
        out["max_contact_pressure_mesh_Pa"] = [_clean(row) for row in per]
        out["max_contact_pressure_static_mesh_Pa"] = static
    return out


def _dynamic_pressure_map(case, model, spec, law, r, speeds, hertz) -> dict | None:
    """The run at the speed of the largest dynamic factor (of the worst mesh, among the speeds
    that ran to the end), from the static equilibrium with the sweep's settings and its cell
    loads recorded (:func:`jaxgear.dynamics.simulate` with ``cell_loads=True``), and each
    mesh's Hertzian pressure over the kept steps (:func:`jaxgear.contact_pressure`). Returns
    ``{"summary": ..., "maps": [(file name, mesh result, pressure (K, L, N), pair,
    positions per its pitch, title)]}``, or None when no speed ran to the end."""
    from .. import TrainCase, contact_pressure
    from ..dynamics import simulate, spec_integrator, spec_window

    df = _worst(r, "dynamic_factor")
    ok = (np.asarray(r.result) == 0) & np.isfinite(df)
    if not ok.any():
        return None
    i = int(np.argmax(np.where(ok, df, -np.inf)))
    speed = float(speeds[i])
    one = simulate(
        model,
        speed,
        integrator=spec_integrator(spec),
        contact=law,
        window=spec_window(spec),
        cell_loads=True,
        throw=False,
    )
    n_s = int(one.steps_per_period)
    scene = model.scene
    angle0 = float(scene.base_planes[0].mesh_period_angle)
    maps, files, p_max = [], [], []
    train = isinstance(case, TrainCase)
    for k, (pair, m) in enumerate(zip(hertz.pairs, one.meshes, strict=True)):
        p = contact_pressure(pair, m, hertz.youngs_modulus, hertz.poisson_ratio).max_pressure
        p_max.append(float(np.max(np.asarray(p))))
        # mesh k's periods per period of the first mesh: its steps per own period N_s / rate
        a0, a1 = scene.mesh_angles(0.0)[k], scene.mesh_angles(1.0)[k]
        rate = (float(a1) - float(a0)) * angle0 / float(scene.base_planes[k].mesh_period_angle)
        name = (
            f"pressure_map_dynamic_{case.mesh_name(k)}.png"
            if train
            else ("pressure_map_dynamic.png")
        )
        what = f"{case.name}'s {case.mesh_name(k)}" if train else case.name
        title = (
            f"dynamic Hertzian contact pressure at {speed:.4g} rad/s over a tooth passage\n"
            f"{what}, largest dynamic factor; max over {m.line_load.shape[0]} kept steps"
        )
        maps.append((name, m, p, pair, n_s / rate, title))
        files.append(name)
    summary = {
        "speed_rad_s": speed,
        "dynamic_factor": float(df[i]),
        "steps_per_period": n_s,
        "result": int(one.result),
        "max_contact_pressure_Pa": max(p_max),
        "files": files,
    }
    if train:
        summary["max_contact_pressure_mesh_Pa"] = p_max
    return {"summary": summary, "maps": maps}


def _nodal_diameter_resonances(scene, modes, speeds, gear: dict, at=None) -> list:
    """The (3.9) resonances of the condensed ``gear`` (:func:`_flexible_gears`), up to 1.05 ×
    the top speed, first and second mesh harmonics
    (:func:`jaxgear.dynamics.gear_nodal_diameter_resonances` on the lowest ``ND_MODES``
    modes), each row named by the gear (``gear``, ``teeth``, ``speed_ratio``). ``at``: the
    modes at speed, or None (the frequencies at rest)."""
    from ..dynamics import gear_nodal_diameter_resonances

    rows = gear_nodal_diameter_resonances(
        scene, modes, gear["member"], at=at, max_speed=1.05 * float(speeds.max()), n_modes=ND_MODES
    )
    return [{"gear": gear["name"]} | {k: v for k, v in r.items() if k != "member"} for r in rows]


def _vtu_series(model, bodies, spec, law, modes, vtu_speed, out_dir, flexible) -> list:
    """With ``vtu_speed``, the run at that speed with its states recorded, written as a VTU
    time series of every deformed body in ``out_dir``/vtu (a previous series removed), one
    file set per body named by its gear (``flexible``: :func:`_flexible_gears`): the files,
    relative to ``out_dir``; [] without."""
    if vtu_speed is None:
        return []
    from ..dynamics import Newmark, auto_steps_per_period, simulate, spec_window
    from .scene import write_body_series

    n_vtu = spec.steps_per_period or auto_steps_per_period(model, [vtu_speed], modes)[0]
    one = simulate(
        model,
        float(vtu_speed),
        states=True,
        integrator=Newmark(int(n_vtu)),
        window=spec_window(spec),
        contact=law,
    )
    folder = os.path.join(out_dir, "vtu")
    os.makedirs(folder, exist_ok=True)
    for old in os.listdir(folder):  # a previous series may have had more frames
        if old.startswith("body_") and old.endswith((".vtu", ".pvd")):
            os.unlink(os.path.join(folder, old))
    names = {g["member"]: g["name"] for g in flexible}
    files = write_body_series(folder, model.scene, bodies, one, names)
    return [os.path.join("vtu", f) for f in files]


def _write(summary: dict, out_dir: str, z1: int, dyn_map: dict | None = None) -> None:
    """``sweep.json`` (atomically), then the dynamic factor, Campbell and contact pressure
    plots and the dynamic pressure maps of ``dyn_map`` (:func:`_dynamic_pressure_map`)."""
    from ..io import write_json

    write_json(os.path.join(out_dir, "sweep.json"), summary)
    write_sweep_csv(os.path.join(out_dir, "sweep.csv"), summary)
    _plots(summary, out_dir, z1=z1, dyn_map=dyn_map)


def write_sweep_csv(path: str, summary: dict) -> list[str]:
    """``sweep.csv`` beside ``sweep.json``: a row per speed, a column per per-speed number of the
    summary (its key, SI units as the key says; a per-mesh or per-gear list gives a column per
    entry, ``<key>_<mesh name>`` or ``<key>_<index>``); empty values (NaN) where a speed has
    none. Returns the header."""
    from ..io import write_csv

    speeds = summary["speeds_rad_s"]
    n = len(speeds)
    names = summary.get("mesh_names")

    def number(v) -> float:
        return float("nan") if v is None else float(v)

    header, cols = ["speed_rad_s"], [[float(v) for v in speeds]]
    for key, v in summary.items():
        if key == "speeds_rad_s" or not isinstance(v, list) or len(v) != n:
            continue
        if all(isinstance(e, int | float) and not isinstance(e, bool) or e is None for e in v):
            header.append(key)
            cols.append([number(e) for e in v])
        elif all(isinstance(e, list) for e in v) and len({len(e) for e in v}) == 1:
            width = len(v[0])
            if not all(isinstance(x, int | float) or x is None for e in v for x in e):
                continue
            tags = names if names and len(names) == width else [str(j) for j in range(width)]
            for j in range(width):
                header.append(f"{key}_{tags[j]}")
                cols.append([number(e[j]) for e in v])
    write_csv(path, header, cols)
    return header


def _plots(summary: dict, out_dir: str, z1: int, dyn_map: dict | None = None) -> None:
    from . import _plots as plots

    plots.dynamic_factor_plot(os.path.join(out_dir, "dynamic_factor.png"), summary)
    plots.campbell_plot(os.path.join(out_dir, "campbell.png"), summary, z1)
    if "max_contact_pressure_Pa" in summary:
        plots.pressure_speed_plot(os.path.join(out_dir, "contact_pressure.png"), summary)
    for name, mesh, pressure, pair, ppp, title in (dyn_map or {}).get("maps", ()):
        plots.face_map(
            os.path.join(out_dir, name),
            mesh,
            pressure,
            pair,
            ppp,
            title=title,
            label="max contact pressure (MPa)",
            unit=1e6,
        )


_SOLVER_NAMES = [
    "newmark",
    "tsit5",
    "dopri5",
    "dopri8",
    "bosh3",
    "heun",
    "midpoint",
    "ralston",
    "euler",
    "kvaerno3",
    "kvaerno4",
    "kvaerno5",
    "implicit_euler",
]


def add_sweep_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``jaxgear sweep`` on an argparse subparsers object."""
    s = subparsers.add_parser(
        "sweep", help="dynamic factor vs speed (Newmark/diffrax, [scene] table)"
    )
    s.add_argument("case", help="TOML case file or embedded case name")
    s.add_argument("--speeds", required=True, help="START:STOP:N pinion speeds (rad/s)")
    s.add_argument(
        "--direction",
        default="independent",
        choices=["independent", "up", "down", "both"],
        help="independent speeds (vmap) or continuation sweeps (default: independent)",
    )
    s.add_argument(
        "--solver",
        choices=_SOLVER_NAMES,
        help="time integrator (default: [scene.integration] solver, else newmark)",
    )
    s.add_argument("--contact", choices=["exact", "smooth"], help="contact law")
    s.add_argument("--periods", type=int, help="mesh periods per speed")
    s.add_argument("--keep-periods", type=int, help="steady-state periods kept")
    s.add_argument(
        "--steps-per-period",
        type=int,
        help="time steps per mesh period (default: [scene.integration], else automatic: 40 per "
        "period of the highest mode the mesh excites, at least 64 per mesh period)",
    )
    s.add_argument("--slices", type=int, help="override [mesh] slices")
    s.add_argument(
        "--vtu-speed",
        type=float,
        help="pinion speed (rad/s): VTU time series (vtu/body_<member>.pvd) of the condensed "
        "bodies over the kept periods at that speed",
    )
    s.add_argument(
        "--out",
        help="output folder (default: jaxgear-out/<case>/sweep-START-STOP-N/, apart from the "
        "sweep/ of jaxgear run, which its summary.json describes)",
    )
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    return s


def default_sweep_dir(case_name: str, speeds) -> str:
    """``jaxgear sweep``'s default folder, ``jaxgear-out/<case>/sweep-START-STOP-N``: its own,
    so that it never replaces the ``sweep/`` of ``jaxgear run`` (which the run's
    ``summary.json`` describes under ``dynamics``), and sweeps over other speeds stay."""
    a, b = float(speeds[0]), float(speeds[-1])
    return os.path.join("jaxgear-out", case_name, f"sweep-{a:g}-{b:g}-{len(speeds)}")


def run_sweep(args) -> int:
    """Run ``jaxgear sweep`` (float64 must already be on: the CLI does it). Returns 0."""
    from ..io import load_case
    from ._options import range_values
    from ._paths import check_output_dir, staged_outputs

    speeds = range_values(args.speeds, "--speeds", positive=True, min_points=2)
    case = load_case(args.case)
    out = check_output_dir(args.out or default_sweep_dir(case.name, speeds))
    options = dict(
        direction=args.direction,
        solver=args.solver,
        contact=args.contact,
        periods=args.periods,
        steps_per_period=args.steps_per_period,
        keep_periods=args.keep_periods,
        vtu_speed=args.vtu_speed,
    )
    sweep_spec(case, **options)  # every check before any file is touched
    # written into a staging folder, moved in place when the sweep completes
    with staged_outputs(out, "sweep") as work:
        s = sweep_case(
            case,
            speeds,
            work,
            slices=args.slices,
            show_progress=not args.quiet,
            **options,
        )
    df = np.asarray([np.nan if v is None else v for v in s["dynamic_factor"]])
    i = int(np.nanargmax(df)) if np.isfinite(df).any() else 0
    n_bad = sum(1 for v in s["result"] if v)
    print(
        f"{case.name}: {len(df)} speeds, max dynamic factor {df[i]:.3f} at "
        f"{s['speeds_rad_s'][i]:.1f} rad/s; first natural frequencies "
        f"{', '.join(f'{f:.0f}' for f in [f for f in s['natural_frequencies_Hz'] if f][:6])} Hz; "
        f"{n_bad} diverged; {s['elapsed_s']:.1f} s"
    )
    n_under = sum(s.get("under_resolved", ()))
    if n_under:
        import warnings

        from ..dynamics import UNDER_RESOLVED_STEPS

        warnings.warn(
            f"{n_under} of {len(df)} speeds are under-resolved (< {UNDER_RESOLVED_STEPS} time "
            "steps per period of the "
            "highest mode the mesh excites; see sweep.json steps_per_mode_period): raise "
            "--steps-per-period or leave it automatic",
            stacklevel=2,
        )
    print(f"written to {out}/")
    return 0
