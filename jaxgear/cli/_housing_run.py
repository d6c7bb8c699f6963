"""``jaxgear run``'s housing outputs, for a pair, train or planetary case with ``[housing]`` and
``[whine]`` (docs/housing.md, "In jaxgear run"): the housing is a body of the case's lumped 3D
scene (a planetary stage's: of its :class:`~jaxgear.planetary.PlanetaryModel` on its mount, its
coordinates after the stage's), so the whine response holds its condensed coordinates; their
full-field recovery on the outer skin (:func:`jaxgear.io.housed_erp`, computed in the library)
gives the normal velocity at the named points of ``[housing.points_mm]`` and the equivalent
radiated power per order and speed; this module writes and draws them. Into
``whine/``: ``housing.json``, ``housing.csv``, the order plots and waterfalls of the ERP and of
each point's velocity, and the operating deflection shapes at each drawn order's loudest speed
(``housing_ods.vtu``)."""

from __future__ import annotations

import os
import re

import numpy as np

from ..io import (
    HousedAcoustics,
    HousedErp,
    TrainForm,
    acoustics_of,
    housed_erp,
    housed_radiation,
    write_csv,
    write_json,
)
from ..scenes import HOUSING_BAND
from ._bearing_report import bearing_tone_lines
from ._plots import whine_level_plot, whine_order_plot, whine_waterfall_plot

__all__ = ["housing_outputs", "housing_run_line", "hybrid_seats_line", "hybrid_seats_section"]

#: integer orders drawn in the order plots and written as operating deflection shapes
ORDERS_DRAWN = 4
#: orders drawn in the waterfalls (the higher ones are in housing.csv)
WATERFALL_ORDERS = 8
#: the condensed housing's band: the orders at frequencies up to cut-off / BAND
#: (:func:`jaxgear.scenes.housing_band_hz`)
BAND = HOUSING_BAND


def _file_key(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_-]+", "_", name).strip("_") or "point"


def _drawn_orders(w, keep, orders):
    """The lines the housing's figures draw, as indices into ``orders`` (the whine's orders
    above the mean, ``keep``): the order plots' (:data:`ORDERS_DRAWN`) and the waterfalls'
    (:data:`WATERFALL_ORDERS`), with their legend and waterfall names (None: by the order).
    A response of one mesh frequency: its first integer orders. One of several mesh-frequency
    groups (``order_group``, :class:`~jaxgear.dynamics.QuasiPeriodicBalance`): each group's
    orders 1 to ORDERS_DRAWN of its own frequency (the waterfalls' count shared among the
    groups), named by the group (from 1) and the order."""
    groups = getattr(w, "order_group", None)
    K = orders.size
    if groups is None or len(set(np.asarray(groups)[keep].tolist())) < 2:
        drawn = [j for j in range(K) if orders[j] == round(orders[j])][:ORDERS_DRAWN]
        return drawn, list(range(min(K, WATERFALL_ORDERS))), None, None
    g = np.asarray(groups)[keep]
    o = np.asarray(w.group_order)[keep]
    n = len(set(g.tolist()))
    drawn = [j for j in range(K) if o[j] <= ORDERS_DRAWN]
    wf = [j for j in range(K) if o[j] <= max(1, WATERFALL_ORDERS // n)]
    labels = [f"mesh frequency {g[j] + 1}, order {o[j]}" for j in range(K)]
    tags = [f"f{g[j] + 1} {o[j]}x" for j in range(K)]
    return drawn, wf, labels, tags


def housing_outputs(run: HousedAcoustics, case, w, folder: str, invalid) -> dict:
    """The housing's files of the whine response ``w`` (of the housed scene) into ``folder``;
    returns the ``housing`` section of the whine summary. ``invalid``: (S,) the speeds with
    contact loss (shaded, listed)."""
    ac, body = run.acoustics, run.body
    n_c = int(ac.K.shape[0])
    speeds = np.asarray(w.speed, dtype=float)
    f1 = np.asarray(w.frequency, dtype=float)
    erp = housed_erp(run, w)
    keep, orders, freq, r = erp.keep, erp.orders, erp.frequency, erp.vibration
    power, level, band, in_band = erp.power, erp.level, erp.band, erp.in_band
    overall_w, overall_db = erp.overall_w, erp.overall_db
    pv = np.asarray(r.point_velocity)  # (S, k, P) m/s
    shown = np.where(in_band, level, np.nan)
    R = np.asarray(body.housing.rotation)
    names = list(ac.point_names)
    points = {}
    pop = run.surface.point_operator
    for k, name in enumerate(names):
        requested = dict(case.housing.points)[name]
        node = R @ run.surface.point_positions[k] + body.offset  # scene frame
        normal = R @ pop[k].toarray().reshape(-1, 3).sum(axis=0)
        points[name] = {
            "requested_mm": (np.asarray(requested) * 1e3).tolist(),
            "node_mm": (node * 1e3).tolist(),
            "moved_mm": float(np.linalg.norm(node - np.asarray(requested)) * 1e3),
            "normal": normal.tolist(),
            "velocity_m_s": {"amplitude": np.abs(pv[:, :, k]).tolist(),
                             "phase_deg": np.degrees(np.angle(pv[:, :, k])).tolist()},
        }
    # housing.csv: one row per speed and order
    S, K = freq.shape
    cols = {
        "speed_rad_s": np.repeat(speeds, K),
        "order": np.tile(orders, S),
        "frequency_Hz": freq.ravel(),
        "in_band": in_band.astype(float).ravel(),
        "erp_W": power.ravel(),
        "erp_dB": level.ravel(),
        # a speed with no order in the band has no overall level: an empty cell
        "overall_erp_dB": [None if np.isnan(v) else v for v in np.repeat(overall_db, K)],
    }
    for k, name in enumerate(names):
        key = _file_key(name)
        cols[f"point_{key}_mm_s"] = np.abs(pv[:, :, k]).ravel() * 1e3
        cols[f"point_{key}_phase_deg"] = np.degrees(np.angle(pv[:, :, k])).ravel()
    cols["contact_loss"] = np.repeat(np.asarray(invalid, dtype=float), K)
    write_csv(os.path.join(folder, "housing.csv"), list(cols), list(cols.values()))
    # the figures: the first integer orders, in the band; a whine of several mesh-frequency
    # groups (QuasiPeriodicBalance): each group's first orders of its own frequency, named
    drawn, wf, labels, tags = _drawn_orders(w, keep, orders)
    named = None if labels is None else [labels[j] for j in drawn]
    marks = None if tags is None else [tags[j] for j in wf]
    files = []
    title = f"{case.name}: housing ERP ({len(body.condensed.modes_hz)} housing modes to "
    title += f"{body.condensed.cutoff_hz:.0f} Hz)"
    note = (f"½ρc Σ|v_n|²A of the outer skin ({run.surface.area:.3g} m²), dB re 1 pW; orders "
            f"above {band:.0f} Hz (cut-off / {BAND:g}) not drawn nor in the overall")
    if in_band.any():
        whine_level_plot(os.path.join(folder, "erp_orders.png"), speeds, shown[:, drawn],
                         orders[drawn], overall_db, ylabel="ERP level (dB re 1 pW)", title=title,
                         invalid=invalid, note=note, order_labels=named)
        whine_waterfall_plot(os.path.join(folder, "erp_waterfall.png"), speeds, f1, orders[wf],
                             np.where(in_band, power, np.nan)[:, wf], label="ERP (W)",
                             title=case.name, invalid=invalid, power=True, limit_hz=band,
                             order_labels=marks, tones=bearing_tone_lines(case))
        files += ["erp_orders.png", "erp_waterfall.png"]
        for k, name in enumerate(names):
            key = _file_key(name)
            v = np.where(in_band, np.abs(pv[:, :, k]), np.nan) * 1e3
            whine_order_plot(os.path.join(folder, f"point_{key}_orders.png"), speeds,
                             v[:, drawn], orders[drawn], ylabel="normal velocity (mm/s)",
                             title=f"{case.name}: housing point {name!r}", invalid=invalid,
                             note="outward normal velocity at the skin node nearest the point; "
                             "one-sided amplitudes", order_labels=named)
            whine_waterfall_plot(os.path.join(folder, f"point_{key}_waterfall.png"), speeds, f1,
                                 orders[wf], v[:, wf], label=f"{name} velocity (mm/s)",
                                 title=case.name, invalid=invalid, limit_hz=band,
                                 order_labels=marks, tones=bearing_tone_lines(case))
            files += [f"point_{key}_orders.png", f"point_{key}_waterfall.png"]
    # the operating deflection shapes: each drawn order at its loudest speed in the band
    from fem_prep.housing import write_housing_ods_vtu  # lazy: meshio, for this file only

    shapes, ods = {}, []
    for j in drawn:
        if not in_band[:, j].any():
            continue
        s = int(np.nanargmax(shown[:, j]))
        label = f"order{orders[j]:g}" if tags is None else tags[j].replace(" ", "_")
        label += f"_{speeds[s]:.0f}rad_s"
        shapes[label] = np.asarray(r.coordinates[s, j])
        ods.append({"label": label, "order": float(orders[j]), "speed_rad_s": float(speeds[s]),
                    "frequency_Hz": float(freq[s, j]), "erp_dB": float(level[s, j])})
    if shapes:
        write_housing_ods_vtu(body.mesh, body.condensed, shapes,
                              os.path.join(folder, "housing_ods.vtu"))
        files.append("housing_ods.vtu")
    files = ["housing.json", "housing.csv", *files]
    peak = erp.peak() or 0
    section = {
        "cutoff_Hz": float(body.condensed.cutoff_hz),
        # the key that gave it, or the [whine] it was derived from (docs/housing.md)
        "cutoff_source": getattr(case.housing, "cutoff_source", "cutoff_Hz"),
        "band_limit_Hz": band,
        "housing_modes": len(body.condensed.modes_hz),
        "housing_dofs": int(body.mesh.n_dofs),
        "condensed_coordinates": n_c,
        "skin_area_m2": float(run.surface.area),
        "skin_facets": int(run.surface.facets.size),
        "density_kg_m3": float(ac.density),
        "sound_speed_m_s": float(ac.sound_speed),
        "loss_factor": float(case.housing.loss_factor),
        "speeds_rad_s": speeds.tolist(),
        "fundamental_Hz": f1.tolist(),
        "orders": orders.tolist(),
        "frequency_Hz": freq.tolist(),
        "in_band": in_band.tolist(),
        "erp_W": power.tolist(),
        "erp_level_dB": level.tolist(),
        "overall_erp_W": overall_w.tolist(),
        "overall_erp_level_dB": [None if np.isnan(v) else v for v in overall_db.tolist()],
        "points": points,
        "operating_deflection_shapes": ods,
        "contact_loss_at_rad_s": speeds[np.asarray(invalid, bool)].tolist(),
        "method": (
            "the housing's condensed coordinates of the coupled whine response, recovered on "
            "the outer skin: v_n = i ω N Φ q; ERP = ½ ρ c Σ |v_n|² A per order, the overall "
            "the sum over the orders in the band (frequency <= cut-off / 1.5); points: the "
            "outward normal velocity at the skin node nearest each named point"
        ),
        "files": [f"whine/{n}" for n in files],
    }
    write_json(os.path.join(folder, "housing.json"), {"case": case.name, **section})
    table = acoustics_of(case, progress=True)
    if table is not None:  # [acoustics]: the radiated sound of the same skin's motion
        section["acoustics"] = _radiation(run, case, w, erp, folder, table)
    return {
        k: section[k] for k in ("cutoff_Hz", "band_limit_Hz", "housing_modes", "files")
    } | {
        "max_overall_erp_dB": float(overall_db[peak]) if in_band.any() else None,
        "speed_of_max_overall_erp_rad_s": float(speeds[peak]) if in_band.any() else None,
        "points": names,
    } | ({"acoustics": section["acoustics"]} if "acoustics" in section else {})


def housing_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of the whine's ``housing`` section (nothing without one)."""
    if section is None:
        return []
    top = section["max_overall_erp_dB"]
    head = (f"housing ({section['housing_modes']} modes to {section['cutoff_Hz']:.0f} Hz): ")
    if top is None:
        return [head + f"no order below {section['band_limit_Hz']:.0f} Hz (cut-off / 1.5)"]
    pts = f", {len(section['points'])} named point(s)" if section["points"] else ""
    return [head + f"overall ERP max {top:.1f} dB re 1 pW at "
            f"{section['speed_of_max_overall_erp_rad_s']:.0f} rad/s{pts} (whine/housing.*)"]


def _radiation(run: HousedAcoustics, case, w, erp: HousedErp, folder: str, table) -> dict:
    """``[acoustics]``'s files (:func:`jaxgear.cli._acoustics_run.acoustic_outputs`) of the
    housed whine ``w``'s radiating skin (:func:`housed_radiation`)."""
    from ._acoustics_run import acoustic_outputs

    h = housed_radiation(run, w, erp)
    return acoustic_outputs(h.surface, h.velocity, h.speeds, h.orders, os.path.dirname(folder),
                            table, frequencies=h.frequency, name=case.name, progress=True)


def hybrid_seats_section(case) -> dict | None:
    """The ``housing`` entry of a hybrid case's quasi-static summary (a case with condensed
    bodies and ``[housing]``; None otherwise): the condensed housing's size, modes and cut-off,
    and where each bearing sits (:meth:`jaxgear.io.Case.hybrid_housing`: the rigid gears'
    every shaft's bearings in the nearest seats, a condensed body's shaft's too)."""
    if case.housing is None or case.scene is None or not case.scene.hybrid:
        return None
    kw = case.hybrid_housing()
    housing, seats = kw["housing"], iter(kw["seats"])
    if isinstance(case.form, TrainForm):
        shafts, names = case.scene.shafts, case.shaft_names
    else:
        shafts, names = (case.scene.pinion_shaft, case.scene.gear_shaft), ("pinion", "gear")
    bearings = [
        {"shaft": name, "position_mm": float(b.z) * 1e3,
         "seat": None if (s := next(seats)) is None else housing.seat_names[s]}
        for name, spec in zip(names, shafts, strict=True)
        for b in spec.bearings
    ]
    return {
        "housing_modes": len(housing.modes_hz),
        "cutoff_Hz": float(housing.cutoff_hz),
        "condensed_coordinates": int(housing.size),
        "bearings": bearings,
    }


def hybrid_seats_line(section: dict | None) -> list[str]:
    """The printed line of :func:`hybrid_seats_section` (nothing without one)."""
    if section is None:
        return []
    seated = sum(b["seat"] is not None for b in section["bearings"])
    n = section["housing_modes"]
    line = (f"  on a flexible housing ({n} mode{'' if n == 1 else 's'} to "
            f"{section['cutoff_Hz']:.0f} Hz): {seated} of {len(section['bearings'])} bearings in "
            "its seats")
    return [line]
