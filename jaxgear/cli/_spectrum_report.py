"""``jaxgear run``'s load-spectrum outputs for a pair case with ``[rating.spectrum]`` (ISO
6336-6:2019): the ``rating.spectrum`` section of ``summary.json``, ``spectrum.csv`` (one row per
bin), the ``rating.md`` section and the lines the run prints (the damage per bin)."""

from __future__ import annotations

import csv
import os
import warnings

import equinox as eqx
import numpy as np

from ..io import CaseWarning, RatingCase, atomic_open
from ..rating import rate_spectrum, with_load_sharing

__all__ = [
    "mesh_spectrum_run_lines",
    "spectrum_csv_rows",
    "spectrum_lines",
    "spectrum_run_lines",
    "spectrum_section",
]

#: what the spectrum is rated with, as the report states it
NOTE = (
    "each bin rated at its own torque and speed (its K_v, K_Hβ, Z_v) with K_A = 1 (ISO 6336-6: "
    "the spectrum holds the machines' loads); the S-N lines are the rating's Z_NT and Y_NT, the "
    "first segment continued up to the static strength (Z_L Z_v Z_R = 1, Y_RrelT = Y_X = 1 "
    "there), no damage below the curves' end at 1e10 cycles"
)


def spectrum_section(rc: RatingCase, out_dir: str | None = None, name: str = "spectrum.csv",
                     k_gamma: float = 1.0) -> dict | None:
    """The ``rating.spectrum`` section of a mesh's :class:`jaxgear.io.RatingCase` (``None``
    without a spectrum; a train's or a planetary stage's mesh: the input's spectrum carried to
    it): :meth:`jaxgear.rating.SpectrumRating.summary` of :func:`jaxgear.rating.rate_spectrum`
    with K_A = 1 (a planetary mesh: times its load sharing factor ``k_gamma``,
    :func:`jaxgear.rating.with_load_sharing`), and the CSV ``name`` written atomically into
    ``out_dir`` when given."""
    if rc.spectrum is None:
        return None
    settings = eqx.tree_at(lambda s: s.application_factor, rc.settings, 1.0)
    if k_gamma != 1.0:
        settings = with_load_sharing(settings, k_gamma)
    rated = rate_spectrum(rc.geometry, rc.spectrum, settings)
    _warn_beyond_static(rated, rc.spectrum)
    section = rated.summary() | {"note": NOTE}
    if out_dir is not None:
        with atomic_open(os.path.join(out_dir, name), "w") as f:
            w = csv.writer(f)
            for row in spectrum_csv_rows(section):
                w.writerow(row)
    return section


def _warn_beyond_static(rated, spectrum) -> None:
    """One :class:`jaxgear.io.CaseWarning` naming the bins of ``[rating.spectrum]`` whose
    stress is beyond the S-N line's static strength (no cycles to failure: an infinite damage,
    null in ``summary.json``, ``inf`` in ``spectrum.csv``)."""
    both = np.isinf(np.asarray(rated.damage_H, float)) | np.isinf(np.asarray(rated.damage_F, float))
    bad = np.flatnonzero(both.reshape(both.shape[0], -1).any(axis=1))
    if bad.size:
        torque = np.asarray(spectrum.torque, float)
        shown = ", ".join(f"bin {i + 1} at {torque[i]:.6g} N·m" for i in bad[:3])
        more = f" and {bad.size - 3} more" if bad.size > 3 else ""
        warnings.warn(
            f"[rating.spectrum] torque_Nm: {shown}{more} load the flanks beyond their static "
            "strength: no cycles to failure, an infinite damage (null in summary.json, inf in "
            "spectrum.csv); check the bin's torque",
            CaseWarning,
            stacklevel=2,
        )


def _g(v) -> str:
    return "inf" if v is None else f"{v:.6g}"


def spectrum_csv_rows(section: dict) -> list[list]:
    """``spectrum.csv``'s rows: a header, then one row per bin (torque N·m, speed rpm, hours,
    cycles, σ_H (Pa), N_H, D_H, σ_F (Pa), N_F, D_F, per gear 1 = pinion and 2 = gear; an
    infinite N as ``inf``)."""
    b, p, f = section["bins"], section["pitting"], section["bending"]
    head = ["bin", "torque_Nm", "speed_rpm", "hours"]
    for j in (1, 2):
        head += [f"cycles{j}", f"sigma_H{j}_Pa", f"cycles_to_failure_H{j}", f"damage_H{j}",
                 f"sigma_F{j}_Pa", f"cycles_to_failure_F{j}", f"damage_F{j}"]
    rows = [head]
    for i, torque in enumerate(b["torque_Nm"]):
        row = [i + 1, _g(torque), _g(b["speed_rpm"][i]), _g(b["hours"][i])]
        for j in (0, 1):
            row += [_g(b["cycles"][i][j]), _g(p["sigma_H_Pa"][i][j]),
                    _g(p["cycles_to_failure"][i][j]), _g(p["damage"][i][j]),
                    _g(f["sigma_F_Pa"][i][j]), _g(f["cycles_to_failure"][i][j]),
                    _g(f["damage"][i][j])]
        rows.append(row)
    return rows


def _pair(values, fmt="{:.4g}") -> str:
    return " / ".join("inf" if v is None else fmt.format(v) for v in values)


def spectrum_lines(section: dict, heading: str = "##") -> list[str]:
    """``rating.md``'s load-spectrum section: the method, the result per gear (damage sum, S_H,
    S_F, life) and a table of every bin (torque, speed, hours, stresses and damage, pinion /
    gear)."""
    b, p, f = section["bins"], section["pitting"], section["bending"]
    out = [
        f"{heading} Load spectrum and life (ISO 6336-6:2019, Palmgren-Miner)",
        "",
        f"{len(b['torque_Nm'])} bins; {section['note']}.",
        "",
        "| | pinion / gear |",
        "|---|---|",
        f"| damage sum, pitting D_H | {_pair(p['damage_sum'])} |",
        f"| damage sum, bending D_F | {_pair(f['damage_sum'])} |",
        f"| safety factor under the spectrum S_H | {_pair(p['S_H'])} |",
        f"| safety factor under the spectrum S_F | {_pair(f['S_F'])} |",
        f"| life to D_H = 1 (h) | {_pair(p['life_h'])} |",
        f"| life to D_F = 1 (h) | {_pair(f['life_h'])} |",
        "",
        "| bin | T₁ (N·m) | n₁ (1/min) | hours | σ_H (N/mm²) | D_H | σ_F (N/mm²) | D_F |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for i, torque in enumerate(b["torque_Nm"]):
        sh = [s * 1e-6 for s in p["sigma_H_Pa"][i]]
        sf = [s * 1e-6 for s in f["sigma_F_Pa"][i]]
        out.append(
            f"| {i + 1} | {torque:.4g} | {b['speed_rpm'][i]:.4g} | {b['hours'][i]:.4g} | "
            f"{_pair(sh)} | {_pair(p['damage'][i], '{:.3g}')} | {_pair(sf)} | "
            f"{_pair(f['damage'][i], '{:.3g}')} |"
        )
    return out


def spectrum_run_lines(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of a spectrum: S_H, S_F and the lives, then the damage per
    bin (pitting and bending, pinion / gear)."""
    if section is None:
        return []
    p, f, b = section["pitting"], section["bending"], section["bins"]
    head = (
        f"load spectrum (ISO 6336-6, {len(b['torque_Nm'])} bins, pinion / gear): S_H "
        f"{_pair(p['S_H'], '{:.3g}')}, S_F {_pair(f['S_F'], '{:.3g}')}; damage D_H "
        f"{_pair(p['damage_sum'], '{:.3g}')}, D_F {_pair(f['damage_sum'], '{:.3g}')}; life "
        f"{_pair(p['life_h'], '{:.3g}')} h (pitting), {_pair(f['life_h'], '{:.3g}')} h "
        "(bending) (spectrum.csv)"
    )
    lines = [
        head,
        "  bin   T1 (N·m)  n1 (1/min)     hours    D_H pinion / gear      D_F pinion / gear",
    ]
    for i, torque in enumerate(b["torque_Nm"]):
        lines.append(
            f"  {i + 1:>3} {torque:>10.4g} {b['speed_rpm'][i]:>11.4g} {b['hours'][i]:>9.4g}    "
            f"{_pair(p['damage'][i], '{:.3g}'):<22} {_pair(f['damage'][i], '{:.3g}')}"
        )
    return lines


def mesh_spectrum_run_lines(names: list[str], section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of a train's or a planetary stage's spectrum (the stacked
    ``rating.spectrum`` of its meshes; nothing without one): per mesh S_H, S_F and the damage
    sums, driving / driven."""
    if section is None:
        return []
    p, f = section["pitting"], section["bending"]
    per = "; ".join(
        f"{n} S_H {_pair(p['S_H'][k], '{:.3g}')}, S_F {_pair(f['S_F'][k], '{:.3g}')}, D_H "
        f"{_pair(p['damage_sum'][k], '{:.3g}')}, D_F {_pair(f['damage_sum'][k], '{:.3g}')}"
        for k, n in enumerate(names)
    )
    bins = len(section["bins"]["torque_Nm"][0])
    line = (f"load spectrum (ISO 6336-6, {bins} bins of the input, driving / driven): {per} "
            "(spectrum_<mesh>.csv)")
    return [line]
