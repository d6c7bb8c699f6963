"""The cost of the load-capacity rating beside a TE curve, and of the root-stress map per mesh
position, on the accessory spur pair (40 slices, 64 positions per pitch, two mesh periods: the
case's own quasi-static run), in one process so that the ratios hold under any load.

Timed, each compiled first and then the best of ``REPEATS`` runs (``block_until_ready``):
the quasi-static TE curve (``jaxgear.quasi_static``, exact contact), the rating
(``jaxgear.rating.rate`` under ``eqx.filter_jit``), the measured K_Hβ and K_Hα on the load map, the
FE influence tables of both members (``fem_prep.fillet_influence``, 9 load radii each: once per
tooth form) and the root-stress map of both members (``jaxgear.rating.root_stress_map``, jitted) per
mesh position. Writes docs/bench/rating_cost.json (or the file given), the machine as
benchmarks/_timing.py's ``environment()``. Run from the repository root:
``python -m benchmarks.rating_cost [FILE]`` (about half a minute).
"""

from __future__ import annotations

import json
import pathlib
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx
import numpy as np

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from benchmarks._timing import environment
from jaxgear.cli import fillet_table

REPEATS = 5
OUT = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench" / "rating_cost.json"
RADII = 9


def best(fn, *args) -> tuple[float, float]:
    """(first call s, best of REPEATS s) of ``fn(*args)``, results blocked on."""
    t = time.perf_counter()
    jax.block_until_ready(fn(*args))
    first = time.perf_counter() - t
    times = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        jax.block_until_ready(fn(*args))
        times.append(time.perf_counter() - t)
    return first, min(times)


def active_radii(pair: jg.GearPair, member: int) -> tuple:
    ends = [pair.roll_distance(s, member) for s in (0.0, float(pair.path_of_contact))]
    roll = np.linspace(min(ends), max(ends), RADII)
    return tuple(float(r) for r in np.hypot(roll, float(pair.base_radii[member])))


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    case = jio.load_case("accessory-spur")
    pair, mods, torque = case.pair, case.modifications, case.torque
    mesh = case.mesh_model()
    te = eqx.filter_jit(lambda m: jg.quasi_static(mesh, m, torque))
    t = time.perf_counter()
    res = jax.block_until_ready(te(mods))
    te_compile = time.perf_counter() - t
    positions = int(np.asarray(res.line_load).shape[0])
    geometry = jr.RatingGeometry.of(pair)
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 430e6),
        lubrication=jr.Lubrication(46e-6, 3e-6, 10e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=20000 * 3600.0,
    )
    operating = jr.OperatingPoint(torque, 6000 * 2 * np.pi / 60)
    rate = eqx.filter_jit(jr.rate)
    measured = eqx.filter_jit(lambda r: (jg.rating.face_load_factor(r), jg.rating.transverse_load_factor(r)))
    t = time.perf_counter()
    tables = [fillet_table(jg.tooth_geometry(pair, i), active_radii(pair, i)) for i in (0, 1)]
    fe = time.perf_counter() - t
    maps = eqx.filter_jit(
        lambda r: [jg.rating.root_stress_map(pair, r, i, tb.roll, tb.peak).max for i, tb in
                   zip((0, 1), tables, strict=True)]
    )
    out = {
        "case": "accessory-spur",
        "slices": case.slices,
        "positions": positions,
        "repeats": REPEATS,
        "note": "wall seconds on a shared machine (load varies): compare the ratios",
        "machine": machine,
    }
    for key, fn, arg in (
        ("te_curve", te, mods),
        ("rating", lambda g: rate(g, operating, settings), geometry),
        ("measured_K_Hbeta_K_Halpha", measured, res),
        ("root_stress_map_both_members", maps, res),
    ):
        first, b = best(fn, arg)
        out[key] = {"first_call_s": first, "best_s": b}
    out["te_curve"]["first_call_s"] = te_compile  # its first call was the one above
    out["fe_influence_both_members_s"] = fe
    out["fe_load_radii_per_member"] = RADII
    te_s = out["te_curve"]["best_s"]
    out["rating_over_te_curve"] = out["rating"]["best_s"] / te_s
    out["root_stress_map_per_position_s"] = out["root_stress_map_both_members"]["best_s"] / positions
    out["root_stress_map_over_te_curve"] = out["root_stress_map_both_members"]["best_s"] / te_s
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main(*map(pathlib.Path, sys.argv[1:2]))
