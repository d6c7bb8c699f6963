"""FE tooth-root stress against ISO 6336-3's σ_F0 (method B) for spur teeth: the embedded
accessory pair, the DIN 3990 cross-check pair of docs/rating.md, the spur sun/planet mesh of a
published KISSsoft report and a standard 20/40 pair.

For each tooth the load (1 N per m of face width, along the line of action) acts at the outer
point of single pair tooth contact of its pair; :func:`fem_prep.fillet_stress` gives the surface
stress along the tensile fillet of the plane-strain FE tooth (element size m_n/18; its peak is
the largest principal stress there),
ISO's method B the nominal stress σ_F0 per unit normal load, 6 cos α_Fen h_Fe / s_Fn² · Y_S (the
beam stress at the 30° tangent section times the stress correction factor; :func:`jaxgear.
tooth_form_factors`). Writes docs/bench/root_stress_iso.json and
docs/img/root_stress_fillet.png (both into one folder if given). Run from the repository root:
``python examples/root_stress_iso.py [out_dir]`` (about 20 s on 2 cores).

The embedded helical pair is left out: ISO rates a helical tooth on its virtual spur gear in the
normal section (z_n = 37.10 and 72.08 for power-helical), which the 2-D model of an integer tooth
count cannot mesh exactly; the transverse section is a different problem.
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from fem_prep.tooth_form import ToothGeometry

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def _spur(z, x, mn, rack=(1.0, 1.25, 0.38), alpha_deg=20.0):
    ha, hf, rho = rack
    m = {"addendum_coeff": ha, "dedendum_coeff": hf, "fillet_radius_coeff": rho}
    m["face_width"] = 20 * mn
    return jg.GearPair(
        jg.Member(z[0], x[0], **m), jg.Member(z[1], x[1], **m), mn, math.radians(alpha_deg)
    )


PAIRS = {
    "accessory-spur (embedded case)": jio.load_case("accessory-spur").pair,
    "DIN 3990 cross-check (z 19/104)": _spur((19, 104), (0.5, 0.15), 4e-3, (1.0, 1.25, 0.25)),
    "KISSsoft stage_02 sun/planet": _spur(
        (18, 36), (0.389, 0.5039), 21e-3, (1 - 1.75 / 21, 1.25, 0.38)
    ),
    "standard 20/40, x = 0": _spur((20, 40), (0.0, 0.0), 2e-3),
}


def tooth_geometry(pair: jg.GearPair, i: int) -> ToothGeometry:
    """Member ``i``'s tooth (spur) for fem_prep."""
    m = (pair.pinion, pair.gear)[i]
    return ToothGeometry(
        teeth=m.teeth,
        normal_module=pair.normal_module,
        normal_pressure_angle=pair.normal_pressure_angle,
        profile_shift=m.profile_shift,
        addendum_coeff=m.addendum_coeff,
        dedendum_coeff=m.dedendum_coeff,
        fillet_radius_coeff=m.fillet_radius_coeff,
    )


def outer_single_contact_radius(pair: jg.GearPair, i: int) -> float:
    """Radius (m) of the outer point of single pair tooth contact of member ``i`` (spur): its
    roll distance is the tip's less (ε_α − 1) p_b."""
    rb = pair.base_radii[i]
    roll = (
        math.sqrt(pair.tip_radii[i] ** 2 - rb**2)
        - (pair.transverse_contact_ratio - 1) * pair.base_pitch
    )
    return math.hypot(roll, rb)


def main(out_dir=None, pairs=None) -> list[dict]:
    """The FE/ISO rows of ``pairs`` (names of :data:`PAIRS`; default all): the record
    root_stress_iso.json and the figure root_stress_fillet.png written into ``out_dir``
    (created if missing), or by default into docs/bench and docs/img; returns the rows."""
    if out_dir is None:
        bench, img = DOCS / "bench", DOCS / "img"
    else:
        bench = img = pathlib.Path(out_dir)
        bench.mkdir(parents=True, exist_ok=True)
    rows, curves = [], {}
    for name in PAIRS if pairs is None else pairs:
        pair = PAIRS[name]
        form = jg.rating.tooth_form_factors(jr.RatingGeometry.of(pair))
        for i, tag in enumerate(("pinion", "gear")):
            iso = (
                6
                * math.cos(float(form.alpha_Fen[i]))
                * float(form.h_Fe[i])
                / float(form.s_Fn[i]) ** 2
                * float(form.Y_S[i])
            )
            fs = fem_prep.fillet_stress(
                tooth_geometry(pair, i), outer_single_contact_radius(pair, i)
            )
            rows.append(
                {
                    "pair": name,
                    "member": tag,
                    "teeth": int((pair.pinion, pair.gear)[i].teeth),
                    "iso_sigma_F0_per_load_1_per_m": iso,
                    "fe_peak_per_load_1_per_m": fs.peak,
                    "fe_over_iso": fs.peak / iso,
                    "fe_peak_tangent_angle_deg": math.degrees(fs.peak_tangent_angle),
                    "Y_S": float(form.Y_S[i]),
                    "q_s": float(form.q_s[i]),
                    "n_dofs": fs.n_dofs,
                }
            )
            curves[f"{name}, {tag}"] = (np.degrees(fs.tangent_angle), fs.sigma_t / iso)
            print(
                f"{name:38s} {tag:6s} FE/ISO = {fs.peak / iso:.4f}  peak at "
                f"{math.degrees(fs.peak_tangent_angle):.1f}°"
            )
    (bench / "root_stress_iso.json").write_text(json.dumps(rows, indent=1) + "\n")
    fig, ax = plt.subplots(figsize=(7, 4))
    for label, (a, s) in curves.items():
        ax.plot(a, s, label=label)
    ax.axvline(30.0, color="k", lw=0.8, ls="--")
    ax.text(29.5, 0.25, "ISO's 30° tangent", fontsize=8)
    ax.set_xlabel("angle between the fillet tangent and the tooth centre line (°)")
    ax.set_ylabel("FE fillet surface stress σ_t / ISO σ_F0")
    ax.set_xlim(90, 0)
    ax.legend(fontsize=6)
    ax.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(img / "root_stress_fillet.png", dpi=130)
    plt.close(fig)
    return rows


if __name__ == "__main__":
    main(*sys.argv[1:2])
