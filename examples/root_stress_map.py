"""The root-stress map of the accessory spur pair over a tooth's passage: each cell's load of the
quasi-static load map (exact contact, the case's tip relief, 80 N·m) times the plane FE tooth's
fillet stress per unit load at the cell's position (``fem_prep.fillet_influence``, 17 load radii
over each member's active profile, element size m_n/18), :func:`jaxgear.rating.root_stress_map`.

Prints the largest root stress of each gear beside ISO 6336-3's nominal σ_F0 (method B, load at
the outer point of single pair contact, no load factor) and writes docs/img/root_stress_map.png
(the stress of each member's tooth against the line-of-action coordinate s of its load and the
face width) and docs/bench/root_stress_map.json (both into one folder if given). Run from the
repository root: ``python examples/root_stress_map.py [out_dir]`` (about half a minute on 2
cores).
"""

from __future__ import annotations

import json
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"


def active_radii(pair: jg.GearPair, member: int, n: int = 17) -> np.ndarray:
    """Radii (m) over the member's active profile: roll distances of s = 0 and s = g_α."""
    ends = [pair.roll_distance(s, member) for s in (0.0, pair.path_of_contact)]
    roll = np.linspace(min(ends), max(ends), n)
    return np.hypot(roll, pair.base_radii[member])


def main(out_dir=None, n_radii: int = 17, size_per_module: float | None = None) -> dict:
    """The map of each member with ``n_radii`` FE load radii over its active profile and FE
    elements of ``size_per_module`` m_n (default fem_prep's, m_n/18): the record
    root_stress_map.json and the figure root_stress_map.png written into ``out_dir`` (created
    if missing), or by default into docs/bench and docs/img; returns the record."""
    if out_dir is None:
        bench, img = DOCS / "bench", DOCS / "img"
    else:
        bench = img = pathlib.Path(out_dir)
        bench.mkdir(parents=True, exist_ok=True)
    case = jio.load_case("accessory-spur")
    pair = case.pair
    res = jg.quasi_static(case.mesh_model(), case.modifications, case.torque)
    form = jg.rating.tooth_form_factors(jr.RatingGeometry.of(pair))
    ft = 2 * case.torque / (2 * pair.pitch_radii[0])
    b = pair.face_width
    out, maps = {}, {}
    for i, tag in enumerate(("pinion", "gear")):
        radii = active_radii(pair, i, n_radii)
        size = None if size_per_module is None else size_per_module * pair.normal_module
        table = fem_prep.fillet_influence(jg.tooth_geometry(pair, i), radii, size=size)
        rmap = jg.rating.root_stress_map(pair, res, i, table.roll, table.peak)
        maps[tag] = rmap
        sigma_f0 = ft / (b * pair.normal_module) * float(form.Y_F[i] * form.Y_S[i])
        out[tag] = {
            "fe_max_root_stress_Pa": float(rmap.max),
            "iso_sigma_F0_Pa": sigma_f0,
            "fe_over_iso": float(rmap.max) / sigma_f0,
            "n_load_radii": len(table.roll),
            "n_dofs": table.n_dofs,
        }
        print(
            f"{tag}: FE max root stress {float(rmap.max) / 1e6:.1f} MPa, ISO σ_F0 "
            f"{sigma_f0 / 1e6:.1f} MPa (FE/ISO {float(rmap.max) / sigma_f0:.3f})"
        )
    (bench / "root_stress_map.json").write_text(json.dumps(out, indent=1) + "\n")
    cli.plots.root_stress_plot(
        img / "root_stress_map.png",
        list(maps.values()),
        f"{case.name}: root stress over a tooth passage at {case.torque:g} N·m (plane FE × "
        "quasi-static cell loads)",
    )
    return out


if __name__ == "__main__":
    main(*sys.argv[1:2])
