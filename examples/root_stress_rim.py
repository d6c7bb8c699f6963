"""The fillet stress of a tooth on a thin rim against ISO 6336-3's rim thickness factor Y_B.

The plane FE tooth model (``fem_prep.fillet_stress``) of the 40-tooth gear of a standard 20/40
pair (m = 2 mm, α = 20°, ISO 53 profile A: ρ_fP = 0.38 m), loaded at its outer point of single
pair contact, on a rim of thickness s_R = s_R/h_t × h_t below the root circle (h_t the tooth
depth): a segment of the rim ring of 3 or 5 pitches, its sides clamped and its bore free
(``fem_prep.RingSegment``), or the whole ring on a web of 0.25 or 0.1 times the face width down
to half the rim's inner radius (``fem_prep.WebbedRim``). The ratio of its largest tensile fillet stress to that of the solid
blank (the ring clamped 3.5 m_n below the root circle, ``fem_prep.ClampedBore``) beside
Y_B = 1.6 ln(2.242 h_t/s_R) (1 from s_R/h_t = 1.2 on; ISO 6336-3:2019).

Writes docs/bench/root_stress_rim.json and docs/img/root_stress_rim.png (both into one folder
if given). Run from the repository root: ``python examples/root_stress_rim.py [out_dir]``
(about a minute on 2 cores).
"""

from __future__ import annotations

import datetime
import json
import math
import pathlib
import platform
import sys

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

import fem_prep
import jaxgear as jg

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"
RATIOS = (0.5, 0.6, 0.8, 1.0, 1.2, 1.5, 2.0)
#: the rim models: a segment with clamped sides and a free bore, or the ring on a web
SUPPORTS = {
    "segment of 3 pitches": fem_prep.RingSegment(3),
    "segment of 5 pitches": fem_prep.RingSegment(5),
    "web 0.25 b": fem_prep.WebbedRim(web=0.25),
    "web 0.1 b": fem_prep.WebbedRim(web=0.1),
}


def y_b(ratio: float) -> float:
    """ISO 6336-3:2019's Y_B of a rim s_R/h_t = ``ratio`` (external gears)."""
    return 1.0 if ratio >= 1.2 else 1.6 * math.log(2.242 / ratio)


def tooth_and_load():
    """The 40-tooth gear of the standard 20/40 pair and the radius (m) of its outer point of
    single pair contact."""
    m = {"addendum_coeff": 1.0, "dedendum_coeff": 1.25, "fillet_radius_coeff": 0.38}
    pair = jg.GearPair(
        jg.Member(20, 0.0, face_width=0.04, **m),
        jg.Member(40, 0.0, face_width=0.04, **m),
        2e-3,
        math.radians(20),
    )
    rb = float(pair.base_radii[1])
    roll = math.sqrt(float(pair.tip_radii[1]) ** 2 - rb**2)
    roll -= (float(pair.transverse_contact_ratio) - 1) * float(pair.base_pitch)
    return jg.tooth_geometry(pair, 1), math.hypot(roll, rb)


def rim_model(size_per_module: float):
    """The tooth of :func:`tooth_and_load` meshed with elements of ``size_per_module`` m_n:
    (σ_solid, h_t, r, rim), σ_solid the solid blank's largest tensile fillet stress (Pa per N/m
    of face), h_t the tooth depth (m), r the load radius (m) and ``rim(s_R/h_t, support)`` the
    ``fem_prep.fillet_stress`` result on a rim of that thickness below the root circle, held by
    ``support`` (a ``fem_prep.RimSupport``), on the same mesh size."""
    tooth, r = tooth_and_load()
    prof = fem_prep.tooth_profile(tooth)
    h_t = prof.tip_radius - prof.root_radius
    size = size_per_module * tooth.normal_module
    solid = fem_prep.fillet_stress(tooth, r, size=size).peak

    def rim(ratio: float, support):
        return fem_prep.fillet_stress(
            tooth, r, size=size, rim_radius=prof.root_radius - ratio * h_t, support=support
        )

    return solid, h_t, r, rim


def sweep(size_per_module: float = 1 / 18, ratios=RATIOS, supports=None) -> dict:
    """{"solid_Pa_per_N_m", "h_t_m", "rows": [{s_R/h_t, Y_B, ratio: {model: σ/σ_solid},
    tangent_angle_deg: {model: angle}}]} for the rim models ``supports`` (default
    :data:`SUPPORTS`)."""
    supports = SUPPORTS if supports is None else supports
    solid, h_t, r, rim = rim_model(size_per_module)
    rows = []
    for x in ratios:
        row = {"s_R_over_h_t": x, "Y_B": y_b(x), "ratio": {}, "tangent_angle_deg": {}}
        for name, support in supports.items():
            fs = rim(x, support)
            row["ratio"][name] = fs.peak / solid
            row["tangent_angle_deg"][name] = math.degrees(fs.peak_tangent_angle)
        rows.append(row)
    return {"solid_Pa_per_N_m": solid, "h_t_m": h_t, "load_radius_m": r, "rows": rows}


def main(out_dir=None, size_per_module: float = 1 / 18) -> dict:
    """The record and the figure into ``out_dir`` (default docs/bench, docs/img)."""
    if out_dir is None:
        bench, img = DOCS / "bench", DOCS / "img"
    else:
        bench = img = pathlib.Path(out_dir)
        bench.mkdir(parents=True, exist_ok=True)
    record = sweep(size_per_module)
    record |= {
        "tooth": "z = 40 of a standard 20/40 pair, m = 2 mm, alpha 20 deg, rho_fP 0.38 m",
        "element_size": f"m_n/{1 / size_per_module:g}",
        "dtype": "float64",
        "machine": platform.processor() or platform.machine(),
        "date": datetime.date.today().isoformat(),
    }
    (bench / "root_stress_rim.json").write_text(json.dumps(record, indent=1) + "\n")
    fig = Figure(figsize=(6.4, 4.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.subplots()
    x = np.array([row["s_R_over_h_t"] for row in record["rows"]])
    fine = np.linspace(0.5, 2.0, 200)
    ax.plot(fine, [y_b(v) for v in fine], "k-", label="ISO 6336-3 Y_B")
    for name, style in zip(SUPPORTS, ("o-", "s--", "^-", "v--"), strict=True):
        ratio = [row["ratio"][name] for row in record["rows"]]
        ax.plot(x, ratio, style, label=f"plane FE, {name} / solid blank")
    ax.axhline(1.0, color="0.6", lw=0.8)
    ax.set_xlabel("rim thickness s_R / tooth depth h_t")
    ax.set_ylabel("root stress / solid blank's")
    ax.set_title("Fillet stress of a tooth on a thin rim (z = 40, m = 2 mm)", fontsize=9)
    ax.legend(fontsize=8)
    ax.grid(alpha=0.3)
    fig.savefig(img / "root_stress_rim.png", dpi=110)
    for row in record["rows"]:
        print(
            row["s_R_over_h_t"],
            round(row["Y_B"], 3),
            {k: round(v, 3) for k, v in row["ratio"].items()},
        )
    return record


if __name__ == "__main__":
    main(*sys.argv[1:2])
