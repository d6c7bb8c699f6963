"""Mean mesh stiffness of six gear pairs under the stiffness models (docs/stiffness.md table).

Models: ``weber`` (Weber's half-plane foundation), ``weber+sainsot`` (Sainsot et al. 2004 body
term), ``weber`` without foundation, ``fe2d`` (plane-strain FE tooth + body; docs/stiffness.md, "FE tooth model"),
``fe2d`` tooth only (root section held) and the ISO 6336-1 method B c_γα b.

The mean mesh stiffness is the c_γα-equivalent ``K̄ = (b cos β_b / p_bt) ∫₀^{g_α} k(s) ds``
(N/m; for a spur pair the mean over a base pitch of Σ k(s_j) b, for ``iso6336`` exactly c_γα b).
The FE compliance tables are computed in a fresh cache so that the recorded times are those of a
first run (2 members, default density m_n / 6).

Run: ``python examples/stiffness_table.py [docs/bench/stiffness_table.json]`` (about 15 s).
"""

from __future__ import annotations

import json
import math
import os
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

import jaxgear as jg
import jaxgear.io as jio

# (key, label) of the columns, in order
MODELS = (
    ("weber", "weber"),
    ("weber_sainsot", "weber+sainsot"),
    ("weber_none", "weber, no foundation"),
    ("fe2d", "fe2d"),
    ("fe2d_tooth", "fe2d, tooth only"),
    ("iso6336", "ISO 6336 c_γα b"),
)


def _member(z, b, **kw):
    return jg.Member(teeth=z, face_width=b, **kw)


def pairs() -> dict[str, dict]:
    """The compared pairs: ``{name: {"pair", "E", "nu", "line_load", "note"}}`` (SI units)."""
    out = {}
    for name in ("accessory-spur", "power-helical"):
        case = jio.load_case(name)
        out[name] = {
            "pair": case.pair,
            "E": case.youngs_modulus,
            "nu": case.poisson_ratio,
            "line_load": case.nominal_line_load(),
            "note": "embedded case, nominal line load",
        }
    nasa = _member(28, 6.35e-3)
    out["nasa-28-28"] = {
        "pair": jg.GearPair(nasa, nasa, normal_module=3.175e-3, normal_pressure_angle=0.349066),
        "E": 207e9,
        "nu": 0.3,
        "line_load": 2e5,
        "note": "NASA Glenn test gears, m 3.175 mm (8 DP), 20°, b 6.35 mm; h_f* 1.25, ρ_fP* 0.25",
    }
    for tag, bore in (("ross-62-62", 17.5e-3), ("ross-62-62-bore-half-root", None)):
        m = _member(62, 20e-3, bore_radius=bore)
        out[tag] = {
            "pair": jg.GearPair(m, m, normal_module=2e-3, normal_pressure_angle=math.radians(20)),
            "E": 206e9,
            "nu": 0.3,
            "line_load": 2e5,
            "note": "ROSS 62/62, m 2 mm, 20°, b 20 mm, bore "
            + ("17.5 mm (ROSS)" if bore else "0.5 × root radius"),
        }
    hcr = {"addendum_coeff": 1.25, "dedendum_coeff": 1.5}
    out["hcr-40-60"] = {
        "pair": jg.GearPair(
            _member(40, 20e-3, **hcr),
            _member(60, 20e-3, **hcr),
            normal_module=2e-3,
            normal_pressure_angle=math.radians(18),
        ),
        "E": 210e9,
        "nu": 0.3,
        "line_load": 2e5,
        "note": "high contact ratio, m 2 mm, 18°, h_a* 1.25, h_f* 1.5, b 20 mm",
    }
    return out


def mean_mesh_stiffness(pair: jg.GearPair, s: np.ndarray, k: np.ndarray) -> float:
    """K̄ = (b cos β_b / p_bt) ∫ k ds (N/m), trapezoidal rule on the table."""
    integral = float(np.sum(0.5 * (k[1:] + k[:-1]) * np.diff(s)))
    return pair.face_width * math.cos(pair.base_helix_angle) * integral / pair.base_pitch


def row(spec: dict, fe2d_size: float | None = None, n_points: int = 257) -> dict:
    """Mean mesh stiffness (N/m) of one pair under every model, and the table times (s)."""
    pair = spec["pair"]
    kw = {
        "youngs_modulus": spec["E"],
        "poisson_ratio": spec["nu"],
        "line_load": spec["line_load"],
        "n_points": n_points,
    }
    runs = {
        "weber": ("weber", "weber"),
        "weber_sainsot": ("weber", "sainsot"),
        "weber_none": ("weber", "none"),
        "fe2d": ("fe2d", "weber"),
        "fe2d_tooth": ("fe2d", "none"),
        "iso6336": ("iso6336", "weber"),
    }
    out, times = {}, {}
    for key, (model, foundation) in runs.items():
        t0 = time.perf_counter()
        stiffness = jio.stiffness_from_name(model, foundation=foundation, fe2d_size=fe2d_size)
        s, k = jg.stiffness_table(pair, stiffness, **kw)
        times[key] = time.perf_counter() - t0
        out[key] = mean_mesh_stiffness(pair, s, k)
    return {
        "mean_mesh_stiffness_N_per_m": out,
        "table_seconds": times,
        "contact_ratio": pair.transverse_contact_ratio,
        "line_load_N_per_m": spec["line_load"],
        "youngs_modulus_Pa": spec["E"],
        "note": spec["note"],
    }


def table(fe2d_size: float | None = None) -> dict:
    """The comparison table for every pair of :func:`pairs`, FE tables computed afresh."""
    old = os.environ.get("FEM_PREP_CACHE")
    with tempfile.TemporaryDirectory() as tmp:
        os.environ["FEM_PREP_CACHE"] = tmp
        try:
            rows = {name: row(spec, fe2d_size) for name, spec in pairs().items()}
        finally:
            if old is None:
                del os.environ["FEM_PREP_CACHE"]
            else:
                os.environ["FEM_PREP_CACHE"] = old
    return {"models": dict(MODELS), "pairs": rows}


def markdown(result: dict) -> str:
    """The table in Markdown (N/µm), one row per pair."""
    head = "| pair | ε_α | " + " | ".join(lab for _, lab in MODELS) + " |"
    lines = [head, "|" + "---|" * (len(MODELS) + 2)]
    for name, r in result["pairs"].items():
        k = r["mean_mesh_stiffness_N_per_m"]
        cells = " | ".join(f"{k[key] / 1e6:.1f}" for key, _ in MODELS)
        lines.append(f"| {name} | {r['contact_ratio']:.3f} | {cells} |")
    return "\n".join(lines)


def main(out: str | os.PathLike = "docs/bench/stiffness_table.json") -> dict:
    result = table()
    Path(out).parent.mkdir(parents=True, exist_ok=True)
    Path(out).write_text(json.dumps(result, indent=2) + "\n", encoding="utf-8")
    print(markdown(result))
    return result


if __name__ == "__main__":
    main(*sys.argv[1:])
