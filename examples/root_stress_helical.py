"""The root-stress map of the power-helical pair over a tooth's passage × the face width, in ISO
6336-3's normal section: each cell's load of the quasi-static load map (exact contact, 310 N·m)
times the fillet stress per unit load of the plane FE model of the virtual spur tooth (z_n =
z/(cos² β_b cos β)), with the load at its height on the tooth (``fem_prep.NormalSection``);
beside it ISO's σ_F0 = F_t/(b m_n) Y_F Y_S Y_β of the same virtual gear, the FE stress of the
virtual tooth under ISO's own load (F_t/(b cos α_n) per unit length at the outer point of single
pair contact of the virtual spur pair: ISO's σ_F0/Y_β computed by FE) and the map of the
transverse section (the model used for helical teeth before).

Two load maps: the pair without modifications (the load spread evenly over the face) and with
the case's tip relief and crowning. Writes docs/bench/root_stress_helical.json and
docs/img/root_stress_helical.png (the unmodified map; both into one folder if given). Run from
the repository root: ``python examples/root_stress_helical.py [out_dir]`` (about a minute on 2
cores).
"""

from __future__ import annotations

import datetime
import json
import math
import pathlib
import platform
import sys
import tomllib

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"
RATING = {
    "application_factor": 1.25,
    "life_h": 20000.0,
    "viscosity_40C_mm2_s": 220.0,
    "roughness_Rz_flank_um": 4.8,
    "roughness_Rz_root_um": 20.0,
    "accuracy_grade": 6,
}


def rated_case(slices: int | None = None) -> jio.Case:
    """The embedded power-helical pair with the rating keys of the user guide's example."""
    data = tomllib.loads(jio.embedded_case_text("power-helical"))
    data["material"] |= {"sigma_H_lim_MPa": 1500.0, "sigma_F_lim_MPa": 500.0}
    data["operating"] |= {"speed_rpm": 3000.0}
    data["rating"] = dict(RATING)
    if slices is not None:
        data["mesh"]["slices"] = slices
    return jio.parse_case(data)


def iso_load_radius(pair: jg.GearPair, member: int) -> float:
    """r_en (m): ISO 6336-3 method B's outer point of single pair contact on the virtual spur
    gear, d_en/2 = √((√(r_an² − r_bn²) − p_bn (ε_αn − 1))² + r_bn²)."""
    v = jg.tooth_geometry(pair, member).virtual_spur()
    rn = v.teeth * v.normal_module / 2
    rbn = rn * math.cos(v.normal_pressure_angle)
    ran = rn + float(pair.tip_radii[member]) - float(pair.pitch_radii[member])
    eps_an = float(pair.transverse_contact_ratio) / math.cos(float(pair.base_helix_angle)) ** 2
    pbn = math.pi * v.normal_module * math.cos(v.normal_pressure_angle)
    return math.hypot(math.sqrt(ran**2 - rbn**2) - pbn * (eps_an - 1), rbn)


def main(out_dir=None, n_radii: int = 17, slices: int | None = None) -> dict:
    """The record root_stress_helical.json and the figure root_stress_helical.png into
    ``out_dir`` (created if missing), by default docs/bench and docs/img; returns the record.
    ``n_radii`` FE load radii per member; ``slices`` the load map's (default the case's)."""
    if out_dir is None:
        bench, img = DOCS / "bench", DOCS / "img"
    else:
        bench = img = pathlib.Path(out_dir)
        bench.mkdir(parents=True, exist_ok=True)
    case = rated_case(slices)
    pair = case.pair
    rc = jio.rating_of(case)
    rating = jr.rate(rc.geometry, rc.operating, rc.settings).summary()["bending"]
    y_beta = float(rating["Y_beta"])
    ft = case.torque / float(pair.pitch_radii[0])
    b = min(float(pair.pinion.face_width), float(pair.gear.face_width))
    an = float(pair.normal_pressure_angle)
    results = {
        "unmodified": jg.quasi_static(case.mesh_model(), jg.Modifications(), case.torque),
        "modified": jg.quasi_static(case.mesh_model(), case.modifications, case.torque),
    }
    record = {
        "case": case.name,
        "torque_Nm": float(case.torque),
        "helix_angle_deg": math.degrees(float(pair.helix_angle)),
        "eps_alpha": float(pair.transverse_contact_ratio),
        "eps_beta": float(pair.overlap_ratio),
        "Y_beta": y_beta,
        "slices": int(results["modified"].cell_s.shape[-1]),
        "n_load_radii": n_radii,
        "element_size": "m_n/18",
        "dtype": "float64",
        "jax": jax.__version__,
        "machine": platform.processor() or platform.machine(),
        "date": datetime.date.today().isoformat(),
    }
    maps = []
    for i, tag in enumerate(("pinion", "gear")):
        tooth = jg.tooth_geometry(pair, i)
        ends = [float(pair.roll_distance(s, i)) for s in (0.0, float(pair.path_of_contact))]
        radii = np.hypot(np.linspace(min(ends), max(ends), n_radii), float(pair.base_radii[i]))
        normal = fem_prep.fillet_influence(tooth, radii, section=fem_prep.NormalSection())
        transverse = fem_prep.fillet_influence(tooth, radii)
        r_en = iso_load_radius(pair, i)
        at_iso = fem_prep.fillet_stress(tooth.virtual_spur(), r_en).peak
        sigma_f0 = float(rating["sigma_F0_Pa"][i])
        entry = {
            "virtual_teeth": tooth.virtual_spur().teeth,
            "iso_sigma_F0_Pa": sigma_f0,
            "iso_sigma_F0_over_Y_beta_Pa": sigma_f0 / y_beta,
            "iso_load_radius_virtual_m": r_en,
            "fe_at_iso_load_Pa": at_iso * ft / (b * math.cos(an)),
            "Y_F": float(rating["Y_F"][i]),
            "Y_S": float(rating["Y_S"][i]),
        }
        for name, res in results.items():
            rmap = jg.rating.root_stress_map(pair, res, i, normal.roll, normal.peak)
            old = jg.rating.root_stress_map(pair, res, i, transverse.roll, transverse.peak)
            k = int(np.argmax(np.asarray(rmap.stress)))
            roll = float(np.asarray(rmap.roll).ravel()[k])
            r = math.hypot(roll, float(pair.base_radii[i]))
            entry[name] = {
                "fe_max_Pa": float(rmap.max),
                "fe_over_iso": float(rmap.max) / sigma_f0,
                "fe_transverse_max_Pa": float(old.max),
                "line_load_at_max_N_m": float(np.asarray(res.line_load).ravel()[k]),
                "mean_line_load_N_m": float(
                    np.sum(res.line_load) / np.sum(np.asarray(res.line_load) > 0)
                ),
                "load_radius_at_max_m": r,
                "z_at_max_m": float(np.asarray(rmap.cell_z).ravel()[k]),
            }
            if name == "unmodified":
                maps.append(rmap)
        record[tag] = entry
        print(
            f"{tag}: z_n {entry['virtual_teeth']:.2f}; ISO σ_F0 {sigma_f0 / 1e6:.1f} MPa "
            f"(σ_F0/Y_β {sigma_f0 / y_beta / 1e6:.1f}), FE at ISO's load "
            f"{entry['fe_at_iso_load_Pa'] / 1e6:.1f}; map max unmodified "
            f"{entry['unmodified']['fe_max_Pa'] / 1e6:.1f} MPa, modified "
            f"{entry['modified']['fe_max_Pa'] / 1e6:.1f} MPa"
        )
    (bench / "root_stress_helical.json").write_text(json.dumps(record, indent=1) + "\n")
    cli.plots.root_stress_plot(
        img / "root_stress_helical.png",
        maps,
        f"{case.name} (β = {record['helix_angle_deg']:g}°), no modifications: root stress over "
        f"a tooth passage at {case.torque:g} N·m (plane FE, normal section × quasi-static cell "
        "loads)",
    )
    return record


if __name__ == "__main__":
    main(*sys.argv[1:2])
