"""``jaxgear run`` on a case with ``[deviations]``: the quasi-static TE over whole revolutions with
the manufacturing deviations per tooth, and its order spectrum (docs/deviations.md)."""

from __future__ import annotations

import os

import numpy as np

from .. import Modifications, mesh_positions, quasi_static, te_spectrum
from ..io import write_csv, write_json
from ._plots import te_spectrum_plot

__all__ = ["CHUNK_POSITIONS", "deviation_line", "deviation_outputs"]

#: positions solved per call over a long span (one compiled shape, reused chunk after chunk)
CHUNK_POSITIONS = 8192


def deviation_outputs(case, mesh, out_dir: str, *, mesh_harmonics: int = 3) -> dict:
    """Solve the exact quasi-static contact of ``case`` (its modifications and deviations) over
    its deviation span and write ``te_span.csv``, ``spectrum.csv``, ``spectrum.json`` and
    ``te_spectrum.png`` into ``out_dir``.

    Returns:
        ``summary.json``'s ``deviations``: the settings, the values used per gear (µm), the
        ISO tolerances of the grade, the span and the TE's figures over it, the labelled
        spectrum lines.
    """
    os.makedirs(out_dir, exist_ok=True)
    st = case.deviation_settings
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    ppp, revs = st["positions_per_pitch"], st["revolutions_count"]
    theta = np.asarray(mesh_positions(mesh, ppp, revs * z1))
    mods = Modifications(
        case.modifications.pinion, case.modifications.gear, deviations=case.deviations
    )
    te = np.empty_like(theta)
    n = min(CHUNK_POSITIONS, theta.size)
    for start in range(0, theta.size, n):
        part = theta[start : start + n]
        pad = n - part.size  # the last chunk padded to the compiled shape
        th = np.concatenate([part, np.full(pad, part[-1])]) if pad else part
        res = quasi_static(mesh, mods, case.torque, th, contact=case.contact_law("exact"))
        te[start : start + part.size] = np.asarray(res.transmission_error)[: part.size]
    spec = te_spectrum(te, ppp, (z1, z2))
    lines = spec.lines(mesh_harmonics)
    period = 2 * np.pi / z1
    write_csv(os.path.join(out_dir, "te_span.csv"), ["theta_rad", "te_exact_m"], [theta, te])
    keep = spec.orders <= (mesh_harmonics + 0.5) * z1
    write_csv(
        os.path.join(out_dir, "spectrum.csv"),
        ["pinion_order", "amplitude_m"],
        [spec.orders[keep], spec.amplitude[keep]],
    )
    write_json(
        os.path.join(out_dir, "spectrum.json"),
        {"revolutions": revs, "teeth": [z1, z2], "lines": lines},
    )
    te_spectrum_plot(
        os.path.join(out_dir, "te_spectrum.png"),
        theta / period / z1,
        te,
        spec,
        title=(
            f"{case.name}: TE with deviations"
            + (f" (grade {st['grade']}, seed {st['seed']})" if st["grade"] is not None else "")
            + f", {revs} pinion revolutions"
        ),
        mesh_harmonics=mesh_harmonics,
    )
    values = {
        tag: (None if g is None else g.summary())
        for tag, g in (("pinion", case.deviations.pinion), ("gear", case.deviations.gear))
    }
    out = {
        "grade": st["grade"],
        "seed": st["seed"],
        "revolutions": st["revolutions"],
        "revolutions_count": revs,
        "positions_per_pitch": ppp,
        "positions": int(theta.size),
        "values": values,
        "te_mean_m": float(te.mean()),
        "te_ptp_m": float(te.max() - te.min()),
        "te_rms_m": float(np.sqrt(np.mean((te - te.mean()) ** 2))),
        "spectrum_lines": lines,
        "files": "deviations/te_span.csv, deviations/spectrum.csv, deviations/spectrum.json, "
        "deviations/te_spectrum.png",
    }
    if "tolerances_um" in st:
        out["tolerances_um"] = st["tolerances_um"]
    return out


def deviation_line(d: dict) -> str:
    """The printed line of :func:`deviation_outputs`' summary ``d``: the grade or "given", the
    TE's peak-to-peak and its mesh-order amplitude."""
    grade = f"grade {d['grade']}, seed {d['seed']}" if d["grade"] is not None else "given"
    mesh = next(ln for ln in d["spectrum_lines"] if ln["label"] == "mesh")
    return (
        f"deviations ({grade}): TE over {d['revolutions_count']} pinion revolutions, "
        f"ptp {d['te_ptp_m'] * 1e6:.4f} µm, mesh order {mesh['amplitude_m'] * 1e6:.4f} µm "
        "(spectrum: deviations/te_spectrum.png)"
    )
