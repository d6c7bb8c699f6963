"""``jaxgear run`` on a planetary case with ``[deviations]``: the stage's quasi-static with the
ISO 1328-1 deviations of every sun, planet and ring tooth over its span (by default the hunting
period, lcm(z_s, z_p, z_r) mesh periods): K_γ and each mesh's TE at every position
(docs/planetary.md, "Per-tooth deviations and the hunting period")."""

from __future__ import annotations

import math
import os

import numpy as np

from .. import PlanetaryGeometry
from ..planetary import DeviationMeshes, PlanarPlanetary, PlanetaryTeeth, planetary_quasi_static
from ..io import write_csv
from ._plots._hunting import hunting_plot

__all__ = ["CHUNK_POSITIONS", "hunting_line", "hunting_section"]

#: positions solved per call over a long span (one compiled shape, reused chunk after chunk)
CHUNK_POSITIONS = 2048


def hunting_section(case, spec, stage, out: str) -> dict:
    """Solve the planar model of the stage of the load sharing (:meth:`PlanetarySpec.
    sharing_stage`: sun free, ring and carrier held) under the sun's torque, with the pin errors
    and eccentricities, its 2N meshes from real contact with every tooth's deviations
    (:class:`~jaxgear.planetary.DeviationMeshes`, exact contact), over the case's deviation span, and
    write ``hunting.csv`` and ``hunting.png`` into ``out``.

    Returns:
        ``summary.json``'s ``hunting``: the settings, the span (mesh periods, sun turns relative
        to the carrier, carrier turns relative to the fixed member), K_γ over the span (max,
        mean) and per planet its largest sun-mesh force, each mesh's TE peak-to-peak and rms,
        the values used per member (µm), the ISO tolerances of the grade (None without).
    """
    st = case.deviation_settings
    ppp, periods = st["positions_per_pitch"], st["mesh_periods"]
    spur = float(case.pairs[0].helix_angle) == 0.0
    contact = spec.dynamic_meshes(case, 1 if spur else case.slices)
    geometry = PlanetaryGeometry(case.pairs[0], case.pairs[1], spec.center_distance, 0.0)
    teeth = PlanetaryTeeth.from_geometry(geometry, np.asarray(spec.planet_angles))
    meshes = DeviationMeshes(contact, teeth, case.deviations)
    held = spec.sharing_stage(stage)
    torque = np.asarray(abs(spec.torques(case.torque)["sun"]))
    e = np.asarray(spec.tangential_pin_errors)
    eps = np.asarray(spec.radial_pin_errors)
    x = np.asarray(contact.positions(ppp, periods))
    n = spec.n_planets
    k_gamma = np.empty(x.size)
    f_s, te_s, te_r = (np.empty((x.size, n)) for _ in range(3))
    size = min(CHUNK_POSITIONS, x.size)
    bad = 0
    for start in range(0, x.size, size):
        part = x[start : start + size]
        pad = size - part.size  # the last chunk padded to the compiled shape
        xs = np.concatenate([part, np.full(pad, part[-1])]) if pad else part
        r = planetary_quasi_static(PlanarPlanetary(), held, meshes, torque, xs, e, eps)
        keep = slice(start, start + part.size)
        k_gamma[keep] = np.asarray(r.k_gamma)[: part.size]
        f_s[keep] = np.asarray(r.sun_mesh_forces)[: part.size]
        te_s[keep] = np.asarray(r.sun_te)[: part.size]
        te_r[keep] = np.asarray(r.ring_te)[: part.size]
        bad += int(np.count_nonzero(np.asarray(r.result)[: part.size]))
    r_bs = float(case.pairs[0].base_radii[0])
    sun_turns = x / (2 * math.pi * r_bs)
    fixed = spec.fixed.name.lower()
    r_fixed = {"sun": r_bs, "ring": float(case.pairs[1].base_radii[1])}.get(fixed)
    columns = {"mesh_travel_m": x, "sun_turns_relative_to_carrier": sun_turns}
    if r_fixed is not None:
        columns["carrier_turns"] = x / (2 * math.pi * r_fixed)
    columns["k_gamma"] = k_gamma
    for name, v in (("sun_mesh_force_N", f_s), ("sun_te_m", te_s), ("ring_te_m", te_r)):
        for i in range(n):
            columns[f"{name}_planet_{i + 1}"] = v[:, i]
    write_csv(os.path.join(out, "hunting.csv"), list(columns), list(columns.values()))
    grade = f"grade {st['grade']}, seed {st['seed']}" if st["grade"] is not None else "given"
    hunting_plot(
        os.path.join(out, "hunting.png"), sun_turns, k_gamma, te_s, te_r,
        title=f"{case.name}: deviations per tooth ({grade}), {periods} mesh periods "
        f"(hunting period {st['hunting_periods']})",
        xlabel="sun turns relative to the carrier",
    )
    ptp = lambda v: (v.max(axis=0) - v.min(axis=0)).tolist()  # noqa: E731
    rms = lambda v: np.sqrt(np.mean((v - v.mean(axis=0)) ** 2, axis=0)).tolist()  # noqa: E731
    devs = case.deviations
    values = {"sun": None if devs.sun is None else devs.sun.summary(),
              "ring": None if devs.ring is None else devs.ring.summary()}
    for i in range(n):
        g = devs.planet(i)
        values[f"planet_{i + 1}"] = None if g is None else g.summary()
    out_d = {
        "model": "planar, meshes from real contact (exact), deviations per tooth",
        "grade": st["grade"],
        "seed": st["seed"],
        "revolutions": st["revolutions"],
        "revolutions_count": st["revolutions_count"],
        "mesh_periods": periods,
        "hunting_periods": st["hunting_periods"],
        "carrier_turns": None if r_fixed is None else periods * float(
            contact.mesh_period()) / (2 * math.pi * r_fixed),
        "positions_per_pitch": ppp,
        "positions": int(x.size),
        "unconverged_positions": bad,
        "k_gamma_max": float(k_gamma.max()),
        "k_gamma_mean": float(k_gamma.mean()),
        "sun_mesh_force_max_N": f_s.max(axis=0).tolist(),
        "sun_te_ptp_m": ptp(te_s),
        "sun_te_rms_m": rms(te_s),
        "ring_te_ptp_m": ptp(te_r),
        "ring_te_rms_m": rms(te_r),
        "values": values,
        "files": "hunting.csv, hunting.png",
        "tolerances_um": st.get("tolerances_um"),  # the grade's (None without one)
    }
    return out_d


def hunting_line(h: dict) -> str:
    """The printed line of :func:`hunting_section`'s summary ``h``."""
    grade = f"grade {h['grade']}, seed {h['seed']}" if h["grade"] is not None else "given"
    return (
        f"deviations per tooth ({grade}): {h['mesh_periods']} mesh periods (hunting period "
        f"{h['hunting_periods']}), K_γ max {h['k_gamma_max']:.4f}, sun-mesh TE ptp "
        f"{max(h['sun_te_ptp_m']) * 1e6:.3f} µm (hunting.png)"
    )
