"""``jaxgear run``'s radiated noise, for a housed case with ``[acoustics]`` (docs/acoustics.md,
"Outputs"): from the housing skin's normal velocity at every order and speed, the sound power
per order and speed and the pressure at the microphones computed in the library
(:func:`jaxgear.io.surface_sound_power`: the radiation operators once per frequency of the
band, cached, a progress bar over the frequencies, each a BEM solve; then
:func:`jaxgear.acoustics.radiated_sound_power` in JAX). Writes ``acoustics/``:

- ``sound_power.csv`` / ``.json`` / ``.png``: L_W (dB re 1 pW) against speed per order and
  overall, linear and A-weighted (dB(A), IEC 61672-1), with W (W) and each order's frequency;
- ``microphones.csv`` / ``.png``: L_p (dB re 20 µPa) at each microphone per order and speed
  (and its frequency), the overall A-weighted L_pA per speed;
- ``intensity.vtu`` / ``.png``: the radiated intensity on the surface at the loudest speed,
  per order (W/m², point data, ParaView).

Called by ``jaxgear run``'s housing outputs (:mod:`jaxgear.cli._housing_run`) with the
closed skin placed in the scene's frame and v = iω N_v Φ q of the housed whine's condensed
housing coordinates q, at the orders in the housing's band.
"""

from __future__ import annotations

import os
import warnings

import numpy as np

from ..acoustics import radiated_intensity_at
from ..io import (
    CaseWarning,
    parse_acoustics,
    surface_sound_power,
    write_csv,
    write_json,
    write_vtu,
)
from ._plots import intensity_map_plot, microphone_plot, sound_power_plot

__all__ = ["ACOUSTICS_FILES", "acoustic_outputs", "acoustics_run_line"]

#: files of the acoustics/ folder (the microphones' only with microphones)
ACOUSTICS_FILES = (
    "sound_power.json",
    "sound_power.csv",
    "sound_power.png",
    "microphones.csv",
    "microphones.png",
    "intensity.vtu",
    "intensity.png",
)
#: orders drawn on the intensity map's figure (every order is in intensity.vtu)
MAP_ORDERS = 3


def _absent(a) -> list:
    """``a`` as nested lists, NaN (an order outside the band, a level of no power) as None:
    a value absent on purpose (null in JSON, an empty CSV cell)."""
    a = np.asarray(a, dtype=float)
    return np.where(np.isnan(a), None, a).tolist()


def acoustic_outputs(
    surface,
    velocities,
    speeds,
    orders,
    out_dir: str,
    table,
    *,
    frequencies=None,
    name: str = "",
    progress: bool = False,
) -> dict:
    """The radiated noise of a vibrating surface over speeds and orders into
    ``out_dir/acoustics`` (the module docstring's files; the sound power and the microphones'
    pressure by :func:`jaxgear.io.surface_sound_power`).

    Args:
        surface: the :class:`fem_prep.acoustics.RadiatingSurface` (m): closed for ``bem``
            (:func:`fem_prep.housing.closed_outer_surface`), a flat panel for ``rayleigh``.
        velocities: ``(S, O, n)`` complex normal velocity amplitudes at the surface's vertices
            (m/s, one-sided, v(t) = Re v e^{iωt}: jaxgear's whine and housing convention;
            conjugated here to fem_prep.acoustics' e^{-iωt}).
        speeds: ``(S,)`` input speeds (rad/s, > 0).
        orders: ``(O,)`` the orders (> 0): order o at speed Ω sounds at o Ω / 2π Hz unless
            ``frequencies`` says otherwise.
        out_dir: the run's folder (``acoustics/`` is made in it).
        table: :class:`jaxgear.io.AcousticsInputs` or the raw ``[acoustics]`` table.
        frequencies: ``(S, O)`` Hz of each order at each speed (a whine sweep's
            ``frequency[:, None] * orders[None, :]``), or ``None``.
        name: the case's name (titles).
        progress: progress bars over the frequencies' radiation solves.

    Returns:
        The ``acoustics`` section (dict) of the run's summary, with the files written.

    Raises:
        TypeError: a surface that is not a RadiatingSurface, a table of another type.
        ValueError: shapes that do not fit, a speed, order or frequency ≤ 0 or not finite.
    """
    if isinstance(table, dict):
        table = parse_acoustics(table, progress)
    sp = surface_sound_power(surface, velocities, speeds, orders, table,
                             frequencies=frequencies, progress=progress)
    v = np.asarray(velocities)
    speeds = np.asarray(speeds, dtype=float).reshape(-1)
    orders = np.asarray(orders, dtype=float).reshape(-1)
    S, O = len(speeds), len(orders)
    band, grid, f, W, A = sp.band, sp.grid, sp.frequency, sp.power, sp.a_weighting
    rr = sp.radiation
    LW, LWA, total, total_a = sp.level, sp.level_a, sp.overall, sp.overall_a
    mics = table.microphones
    head = f"{name}: " if name else ""
    folder = os.path.join(out_dir, "acoustics")
    os.makedirs(folder, exist_ok=True)
    title = f"{head}radiated sound power ({table.method}, {len(grid)} frequencies)"
    sound_power_plot(os.path.join(folder, "sound_power.png"), speeds, orders, LW, LWA, total,
                     total_a, title=title)
    outside = int(np.sum(np.isnan(W)))
    if outside:  # orders whose frequency lies outside band_Hz: no R there, no power
        warnings.warn(
            f"[acoustics] band_Hz = [{band[0]:g}, {band[1]:g}]: {outside} of {W.size} order "
            "frequencies lie outside it, their sound power not computed (null in "
            "sound_power.json, empty in the CSV files; leave band_Hz out for the orders' range)",
            CaseWarning,
            stacklevel=2,
        )
    cols = {"speed_rad_s": speeds}
    for j, o in enumerate(orders):
        cols[f"order_{o:g}_frequency_Hz"] = f[:, j]
        cols[f"order_{o:g}_W_W"] = _absent(W[:, j])
        cols[f"order_{o:g}_LW_dB"] = _absent(LW[:, j])
        cols[f"order_{o:g}_LWA_dBA"] = _absent(LWA[:, j])
    cols["overall_LW_dB"], cols["overall_LWA_dBA"] = _absent(total), _absent(total_a)
    write_csv(os.path.join(folder, "sound_power.csv"), list(cols), list(cols.values()))
    section = {
        "method": str(table.method),
        "band_Hz": list(band),
        "grid_Hz": grid.tolist(),
        "rank": table.rank,
        "radiation_cache_key": rr.key,
        "velocity_convention": "one-sided, v(t) = Re v exp(i w t)",
        "speeds_rad_s": speeds.tolist(),
        "orders": orders.tolist(),
        "frequency_Hz": f.tolist(),
        "power_W": _absent(W),
        "LW_dB": _absent(LW),
        "LWA_dBA": _absent(LWA),
        "overall_LW_dB": _absent(total),
        "overall_LWA_dBA": _absent(total_a),
        "outside_band": outside,
    }
    if mics:
        Lp, LpA = sp.pressure_level, sp.overall_pressure_level_a  # (S, O, q), (S, q)
        names = [m for m, _ in mics]
        microphone_plot(os.path.join(folder, "microphones.png"), names, speeds, f, orders, Lp, LpA,
                        title=f"{head}sound pressure at the microphones ({table.method})")
        mcols = {"speed_rad_s": np.repeat(speeds, O), "order": np.tile(orders, S),
                 "frequency_Hz": f.reshape(-1)}
        for k, m in enumerate(names):
            mcols[f"{m}_Lp_dB"] = _absent(Lp[:, :, k].reshape(-1))
            mcols[f"{m}_LpA_dBA"] = _absent((Lp[:, :, k] + A).reshape(-1))
        write_csv(os.path.join(folder, "microphones.csv"), list(mcols), list(mcols.values()))
        section["microphones"] = {
            m: {"position_m": list(p), "Lp_dB": _absent(Lp[:, :, k]),
                "overall_LpA_dBA": _absent(LpA[:, k])}
            for k, (m, p) in enumerate(mics)
        }
    # the radiated intensity at the loudest speed, every order
    s_max = int(np.nanargmax(np.where(np.isnan(total_a), -np.inf, total_a)))
    areas = surface.vertex_areas  # the surface's lumped area per vertex (m²)
    data, maps = {}, {}
    loud = np.argsort(-np.nan_to_num(W[s_max], nan=-1.0))
    for j in range(O):
        if np.isnan(W[s_max, j]):
            continue
        q = np.asarray(radiated_intensity_at(np.conj(v[s_max, j]), f[s_max, j], rr.factors,
                                             grid, areas))
        label = f"order_{orders[j]:g}"
        data[f"{label}_intensity_W_m2"] = q
        data[f"{label}_normal_velocity_m_s"] = np.abs(v[s_max, j])
        if j in loud[:MAP_ORDERS]:
            maps[f"order {orders[j]:g} at {speeds[s_max]:.0f} rad/s, {f[s_max, j]:.0f} Hz: "
                 f"L_W = {LW[s_max, j]:.1f} dB"] = q
    write_vtu(os.path.join(folder, "intensity.vtu"), surface.vertices,
              [("triangle", surface.triangles)], data)
    if maps:
        intensity_map_plot(os.path.join(folder, "intensity.png"), surface.vertices,
                           surface.triangles, maps,
                           title=f"{head}radiated intensity at the loudest speed")
    section["map_speed_rad_s"] = float(speeds[s_max])
    section["files"] = [f"acoustics/{x}" for x in ACOUSTICS_FILES
                        if x == "sound_power.json" or os.path.exists(os.path.join(folder, x))]
    write_json(os.path.join(folder, "sound_power.json"), {"case": name, **section})
    return section


def acoustics_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of the ``acoustics`` section (nothing without one)."""
    if not section:
        return []
    top = np.nanmax(np.asarray(section["overall_LWA_dBA"], dtype=float))
    line = (
        f"acoustics ({section['method']}, {len(section['grid_Hz'])} frequencies): overall "
        f"L_WA up to {top:.1f} dB(A) re 1 pW at {section['map_speed_rad_s']:.0f} rad/s "
        "(acoustics/)"
    )
    return [line]
