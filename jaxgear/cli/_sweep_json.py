"""The sections of ``sweep.json`` and ``sweep.csv`` and the sweep's figures, from a
:class:`jaxgear.dynamics.SweepResult` (:func:`jaxgear.cli.sweep.sweep_case` computes, these
describe): the per-speed responses (a train's worst mesh beside each mesh's), the Hertzian
pressures, the rim waves and nodal-diameter resonances of condensed gears, the dynamic pressure
map and the VTU series at a chosen speed."""

from __future__ import annotations

import functools
import math
import os
import re

import jax
import numpy as np

from .. import contact_pressure, quasi_static
from ..dynamics import (
    Newmark,
    Outputs,
    SteadyState,
    auto_steps_per_period,
    gear_nodal_diameter_resonances,
    rim_stations,
    rim_waves,
    simulate,
)
from ..io import spec_integrator, spec_window, write_csv, write_json
from ..scenes import AssembledScene
from ._case_kinds import (
    gear_meshes,
    mesh_file_tag,
    mesh_title,
    per_mesh_keys,
    pressure_curves,
)
from ._plots import (
    DYNAMIC_ZERO,
    campbell_plot,
    dynamic_factor_plot,
    face_map,
    pressure_speed_plot,
)
from .scene import write_body_series

__all__ = [
    "ND_MODES",
    "at_speed_keys",
    "backlash_responses",
    "bearing_names",
    "clean",
    "column_tag",
    "dynamic_pressure_map",
    "flexible_gears",
    "hybrid_static_pressures",
    "lumped_static_pressures",
    "mesh_responses",
    "nodal_diameter_resonances",
    "of_worst",
    "passing_rate",
    "pressure_responses",
    "rim_content",
    "vtu_series",
    "worst",
    "write_sweep",
    "write_sweep_csv",
]

# the lowest elastic modes of a hybrid structure searched for each condensed gear's
# nodal-diameter families (seed (3.9))
ND_MODES = 40


@functools.singledispatch
def bearing_names(scene) -> tuple:
    """The names of a scene's bearing force components (``sweep.json``'s ``bearing_names``):
    an assembled scene's reactions; none for a scene without bearings (the 1-DOF relative
    approach)."""
    return ()


@bearing_names.register
def _(scene: AssembledScene) -> tuple:
    return tuple(scene.reaction_names)


def clean(values) -> list:
    return [float(v) if np.isfinite(v) else None for v in np.asarray(values, dtype=float)]


def rim_content(sw, i, f_mesh, stations: slice, spin: float) -> dict:
    """The largest rim wave n >= 1 of speed ``i`` above half the mesh frequency ``f_mesh``
    (Hz), axial and radial, of the condensed gear whose stations are ``stations`` of the rim
    records, turning in the ``spin`` sense (direction +1: forward, with its rotation)."""
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


def flexible_gears(case, scene) -> list[dict]:
    """Every condensed gear of a hybrid scene, in member order: ``name`` (a pair's "pinion" or
    "gear", a train's gear name), ``member`` (its index in ``scene.members``), ``teeth`` Z,
    ``speed_ratio`` (its turns per turn of the pinion or input, > 0), ``spin`` (its sense about
    z, ±1), ``stations`` (the slice of its stations in the rim records) and ``meshes`` (the
    names of the meshes it is in)."""
    names = case.gear_names
    out = []
    for m, stations in rim_stations(scene):
        member = scene.members[m]
        meshes = gear_meshes(case, m)
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


def passing_rate(gear: dict, z1: float) -> float:
    """The condensed ``gear``'s tooth-passing frequency over the first mesh's (z1 the first
    mesh's order): Z × its speed ratio / z1; exactly 1 where they agree to 1e-9 (a pair's
    wheel, an idler train's gears)."""
    rate = gear["teeth"] * gear["speed_ratio"] / z1
    return 1.0 if abs(rate - 1.0) < 1e-9 else rate


def worst(r, field: str) -> np.ndarray:
    """``field`` of the results ``r`` per speed, the largest over the meshes (S,)."""
    return np.max(np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], -1), -1)


def of_worst(r, field: str) -> np.ndarray:
    """``field`` of the results ``r`` per speed, of the mesh of the highest dynamic factor (S,)."""
    per = np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], -1)
    df = np.stack([np.asarray(m.dynamic_factor, float) for m in r.meshes], -1)
    return per[np.arange(per.shape[0]), np.argmax(df, -1)]


def mesh_responses(model, r, speeds) -> dict:
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
        return {name: clean(getattr(r, field)) for field, name in keys} | backlash_responses(r)
    out = {
        "dynamic_factor": clean(worst(r, "dynamic_factor")),
        "dynamic_factor_tooth": clean(worst(r, "dynamic_factor_tooth")),
        "te_rms_m": clean(of_worst(r, "te_rms")),
        "te_mean_m": clean(of_worst(r, "te_mean")),
        "contact_loss": clean(worst(r, "contact_loss")),
        "periodicity": clean(worst(r, "periodicity")),
    }
    for field, name in keys[:5]:  # (S, m)
        per = np.stack([np.asarray(getattr(m, field), float) for m in r.meshes], axis=-1)
        out[name.removesuffix("_m") + "_mesh" + ("_m" if name.endswith("_m") else "")] = [
            clean(row) for row in per
        ]
    freq = [
        float(mesh.ratio) / float(mesh.base_plane.mesh_period_angle) for mesh in model.scene.meshes
    ]  # cycles per radian of the input
    out["mesh_frequency_mesh_Hz"] = [clean(w * np.asarray(freq)) for w in np.asarray(speeds)]
    return out


def backlash_responses(r, suffix: str = "") -> dict:
    """With coast flanks (backlash; docs/backlash.md): the share of the kept steps on the coast
    flank and the re-contacts (impacts) on the drive and the coast flank per speed; {} without."""
    if r.meshes[0].coast_share is None:
        return {}
    return {
        f"coast_share{suffix}": clean(r.coast_share),
        f"impacts_drive{suffix}": [int(v) for v in np.asarray(r.impacts_drive)],
        f"impacts_coast{suffix}": [int(v) for v in np.asarray(r.impacts_coast)],
    }


def at_speed_keys(at, n_modes: int, used: bool) -> dict:
    """sweep.json's keys of the modes at speed (:func:`jaxgear.dynamics.modes_at_speed`)."""
    return {
        "campbell_at_speed": bool(used),
        "campbell_speeds_rad_s": clean(at.speeds),
        "natural_frequencies_at_speed_Hz": [
            clean(row) for row in np.asarray(at.omega)[:, :n_modes] / (2 * math.pi)
        ],
        "modes_at_speed_error": at.error,
        "modes_at_speed_shift": at.shift,
    }


def hybrid_static_pressures(model, law, hertz) -> list[float]:
    """Each mesh's largest quasi-static Hertzian pressure at rest (Pa) of a hybrid model: from
    :func:`jaxgear.quasi_static` of its scene at rest (64 positions per mesh period)."""
    qs = quasi_static(model.scene, model.mods, model.torque, contact=law, throw=False)
    out = []
    for pair, m in zip(hertz.pairs, qs.meshes, strict=True):
        p = contact_pressure(pair, m, hertz.youngs_modulus, hertz.poisson_ratio).max_pressure
        out.append(float(np.max(np.asarray(p))))
    return out


def lumped_static_pressures(r) -> list[float]:
    """Each mesh's largest quasi-static Hertzian pressure at rest (Pa) of a lumped model: from
    its own static solution at the table positions (the largest over the speeds' tables)."""
    return [float(np.nanmax(np.asarray(m.max_pressure_static))) for m in r.meshes]


def pressure_responses(r, static: list[float]) -> dict:
    """The Hertzian pressures of ``sweep.json`` (Pa): per speed the largest over the kept steps
    and the cells (``max_contact_pressure_Pa``; a train's worst mesh, with each mesh's under
    ``max_contact_pressure_mesh_Pa``, speeds × meshes), and the quasi-static maximum at rest
    ``static`` of each mesh for reference (``max_contact_pressure_static_Pa``; a train's per
    mesh under ``max_contact_pressure_static_mesh_Pa``;
    :meth:`jaxgear.cli._sweep_kinds.SweepKind.static_pressures`)."""
    out = {
        "max_contact_pressure_Pa": clean(worst(r, "max_pressure")),
        "max_contact_pressure_static_Pa": max(static),
    }
    if len(r.meshes) > 1:
        per = np.stack([np.asarray(m.max_pressure, float) for m in r.meshes], axis=-1)
        out["max_contact_pressure_mesh_Pa"] = [clean(row) for row in per]
        out["max_contact_pressure_static_mesh_Pa"] = static
    return out


def dynamic_pressure_map(
    case, model, spec, law, r, speeds, hertz, states=False, window=None, phase=None
) -> dict | None:
    """The run at the speed of the largest dynamic factor (of the worst mesh, among the speeds
    that ran to the end), from the static equilibrium with the sweep's settings and its cell
    loads recorded (:func:`jaxgear.dynamics.simulate` with ``cell_loads=True``), and each
    mesh's Hertzian pressure over the kept steps (:func:`jaxgear.contact_pressure`). Returns
    ``{"summary": ..., "maps": [(file name, mesh result, pressure (K, L, N), pair,
    positions per its pitch, title)], "run": the run (its ``speed``, rad/s)}``, or None when
    no speed ran to the end. The run is the one a caller needing the cell loads at that speed
    with the same settings reuses (``jaxgear run``'s root stress at speed,
    :func:`jaxgear.cli.root_stress_at_speed`) instead of simulating it again. ``states``: record
    the states too (with ``--vtu-speed``: the outputs of :func:`vtu_series`'s run, so that the
    two runs are one compiled program). ``window``: a settled sweep's window (periods; None:
    the case's span from the static equilibrium): the run starts from the sweep's final state
    at that speed and runs one window (its steady state, already settled); ``phase``: the
    sweep's :attr:`~jaxgear.dynamics.SettledSweep.phase` (the mesh position of each speed's
    final state, None: 0)."""
    df = worst(r, "dynamic_factor")
    ok = (np.asarray(r.result) == 0) & np.isfinite(df)
    if not ok.any():
        return None
    i = int(np.argmax(np.where(ok, df, -np.inf)))
    speed = float(speeds[i])
    start, span, at = None, spec_window(spec), 0
    if window is not None:  # one more window from the settled state at that speed
        start = tuple(jax.device_put(np.asarray(a)[i]) for a in r.final_state[:2])
        span = SteadyState(max(int(window), 2), spec.keep_periods)
        at = 0 if phase is None else int(phase[i])
    one = simulate(
        model,
        speed,
        integrator=spec_integrator(spec),
        contact=law,
        window=span,
        state0=start,
        outputs=Outputs(cell_loads=True, states=states),
        throw=False,
        start_period=at,
    )
    n_s = int(one.steps_per_period)
    scene = model.scene
    angle0 = float(scene.base_planes[0].mesh_period_angle)
    maps, files, p_max = [], [], []
    for k, (pair, m) in enumerate(zip(hertz.pairs, one.meshes, strict=True)):
        p = contact_pressure(pair, m, hertz.youngs_modulus, hertz.poisson_ratio).max_pressure
        p_max.append(float(np.max(np.asarray(p))))
        # mesh k's periods per period of the first mesh: its steps per own period N_s / rate
        a0, a1 = scene.mesh_angles(0.0)[k], scene.mesh_angles(1.0)[k]
        rate = (float(a1) - float(a0)) * angle0 / float(scene.base_planes[k].mesh_period_angle)
        name = f"pressure_map_dynamic{mesh_file_tag(case, k)}.png"
        what = mesh_title(case, k)
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
    summary.update(per_mesh_keys(case, {"max_contact_pressure_mesh_Pa": p_max}))
    return {"summary": summary, "maps": maps, "run": one}


def nodal_diameter_resonances(scene, modes, speeds, gear: dict, at=None) -> list:
    """The (3.9) resonances of the condensed ``gear`` (:func:`flexible_gears`), up to 1.05 ×
    the top speed, first and second mesh harmonics
    (:func:`jaxgear.dynamics.gear_nodal_diameter_resonances` on the lowest ``ND_MODES``
    modes), each row named by the gear (``gear``, ``teeth``, ``speed_ratio``). ``at``: the
    modes at speed, or None (the frequencies at rest)."""
    rows = gear_nodal_diameter_resonances(
        scene, modes, gear["member"], at=at, max_speed=1.05 * float(speeds.max()), n_modes=ND_MODES
    )
    return [{"gear": gear["name"]} | {k: v for k, v in r.items() if k != "member"} for r in rows]


def vtu_series(model, bodies, spec, law, modes, vtu_speed, out_dir, flexible) -> list:
    """With ``vtu_speed``, the run at that speed with its states recorded, written as a VTU
    time series of every deformed body in ``out_dir``/vtu (a previous series removed), one
    file set per body named by its gear (``flexible``: :func:`flexible_gears`): the files,
    relative to ``out_dir``; [] without. The run records the cell loads too: the outputs of
    :func:`dynamic_pressure_map`'s run with ``states``, whose compiled program it reuses when
    the steps per period are the same."""
    if vtu_speed is None:
        return []
    n_vtu = spec.steps_per_period or auto_steps_per_period(model, [vtu_speed], modes)[0]
    one = simulate(
        model,
        float(vtu_speed),
        outputs=Outputs(states=True, cell_loads=True),
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


def write_sweep(case, summary: dict, out_dir: str, z1: int, dyn_map: dict | None = None) -> None:
    """``sweep.json`` (atomically), then the dynamic factor, Campbell and contact pressure
    plots (each of the case's meshes: :func:`~jaxgear.cli._case_kinds.pressure_curves`) and
    the dynamic pressure maps of ``dyn_map`` (:func:`dynamic_pressure_map`)."""
    write_json(os.path.join(out_dir, "sweep.json"), summary)
    write_sweep_csv(os.path.join(out_dir, "sweep.csv"), summary)
    pressure = pressure_curves(case, summary)
    sweep_plots(summary, out_dir, z1=z1, dyn_map=dyn_map, pressure=pressure)


def column_tag(name: str) -> str:
    """A mesh or gear name as a CSV column's part: lower snake case, every run of characters
    other than letters and digits one ``_`` (``sun-planet 1`` -> ``sun_planet_1``)."""
    return re.sub(r"[^0-9a-z]+", "_", name.lower()).strip("_")


def write_sweep_csv(path: str, summary: dict) -> list[str]:
    """``sweep.csv`` beside ``sweep.json``: a row per speed, a column per per-speed number of the
    summary (its key, SI units as the key says; a per-mesh or per-gear list gives a column per
    entry, ``<key>_<mesh name>`` or ``<key>_<index>``, the mesh name in snake case:
    :func:`column_tag`); an empty cell where a speed has no value. Returns the header."""
    speeds = summary["speeds_rad_s"]
    n = len(speeds)
    names = summary.get("mesh_names")

    def number(v) -> float | None:
        return None if v is None else float(v)

    header, cols = ["speed_rad_s"], [[float(v) for v in speeds]]
    for key, v in summary.items():
        if key == "speeds_rad_s" or not isinstance(v, list) or len(v) != n:
            continue
        if key.startswith("settled") and all(isinstance(e, bool) or e is None for e in v):
            header.append(key)  # whether each speed settled: 1 or 0 (empty: not checked)
            cols.append([number(None if e is None else int(e)) for e in v])
        elif all(isinstance(e, int | float) and not isinstance(e, bool) or e is None for e in v):
            header.append(key)
            cols.append([number(e) for e in v])
        elif all(isinstance(e, list) for e in v) and len({len(e) for e in v}) == 1:
            width = len(v[0])
            if not all(isinstance(x, int | float) or x is None for e in v for x in e):
                continue
            tags = (
                [column_tag(t) for t in names]
                if names and len(names) == width
                else [str(j) for j in range(width)]
            )
            for j in range(width):
                header.append(f"{key}_{tags[j]}")
                cols.append([number(e[j]) for e in v])
    write_csv(path, header, cols)
    return header


def sweep_plots(
    summary: dict, out_dir: str, z1: int, dyn_map: dict | None = None, *, pressure: list
) -> None:
    """The figures of a sweep ``summary`` into ``out_dir``; ``pressure``: the contact
    pressure curves (:func:`~jaxgear.cli._case_kinds.pressure_curves`)."""
    dynamic_factor_plot(os.path.join(out_dir, "dynamic_factor.png"), summary)
    campbell_plot(os.path.join(out_dir, "campbell.png"), summary, z1)
    pressure_speed_plot(os.path.join(out_dir, "contact_pressure.png"), summary, pressure)
    for name, mesh, pressure, pair, ppp, title in (dyn_map or {}).get("maps", ()):
        face_map(
            os.path.join(out_dir, name),
            mesh,
            pressure,
            pair,
            ppp,
            title=title,
            label="max contact pressure (MPa)",
            unit=1e6,
            zero_label=DYNAMIC_ZERO,
        )
