"""Safety factors against the pinion's profile shift, with their gradients: the helical pair of
ISO/TR 6336-30 example 1 (m_n 8 mm, z 17/103, β 15.8°, a_w 500 mm, T₁ 9000 N·m at 360 1/min;
docs/rating.md), rated by ISO 6336-2/-3 method B (:func:`jaxgear.rating.rate`) over x₁ from 0.05
(just above undercut) to 0.8, the gear's x₂ = 0, the centre distance following the shifts (zero
backlash: 499.2 to 505.0 mm; the TR's 500 mm is x₁ = 0.145), every load factor computed.
``jax.vmap`` rates all shifts in one call and ``jax.grad`` gives dS/dx₁ at each, the slope an
optimiser would follow.

Writes rating_profile_shift.png and rating_profile_shift.json into docs/bench/ (or the folder
given). Run from the repository root: ``python examples/rating_profile_shift.py [out_dir]`` (a
few seconds).
"""

from __future__ import annotations

import json
import math
import pathlib
import sys

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

import jaxgear as jg
import jaxgear.rating as jr

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
SHIFTS = jnp.linspace(0.05, 0.8, 31)


def tr_example():
    """The pair (zero-backlash centre distance: it follows x₁), operating point and settings of
    the TR's example 1 (no factor given); every shift of ``SHIFTS`` checked by GearPair (no
    undercut, no pointed tip)."""
    m = {"addendum_coeff": 1.0, "dedendum_coeff": 1.4, "face_width": 0.1}
    m["fillet_radius_coeff"] = 0.39
    pair = jg.GearPair(
        jg.Member(17, 0.145, **m),
        jg.Member(103, 0.0, **m),
        8e-3,
        math.radians(20.0),
        math.radians(15.8),
    )
    for x in (float(SHIFTS[0]), float(SHIFTS[-1])):
        jg.GearPair(jg.Member(17, x, **m), pair.gear, 8e-3, math.radians(20.0), math.radians(15.8))
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 500e6, 206e9, 0.3, 7830.0, jr.CaseHardened()),
        lubrication=jr.Lubrication(320e-6, 6e-6, 10e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 5),
        life=50_000 * 3600.0,
        tip_relief=70e-6,
    )
    return jr.RatingGeometry.of(pair), jr.OperatingPoint(9000.0, 360 * math.pi / 30), settings


def safety(x1, geometry, operating, settings):
    """(S_H pinion, S_H gear, S_F pinion, S_F gear) at pinion profile shift x1."""
    g = geometry.replace(profile_shift=jnp.stack([x1, geometry.profile_shift[1]]))
    r = jr.rate(g, operating, settings)
    return jnp.concatenate([r.pitting.S_H, r.bending.S_F])


def main(out_dir=DOCS, shifts=SHIFTS) -> dict:
    """Rate the pair at each pinion profile shift of ``shifts`` (within 0.05-0.8; default 31
    from 0.05 to 0.8) and write the figure and the record into ``out_dir`` (default
    docs/bench; created if missing); returns the record."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    shifts = jnp.asarray(shifts)
    geometry, operating, settings = tr_example()
    f = jax.jit(jax.vmap(lambda x: safety(x, geometry, operating, settings)))
    df = jax.jit(jax.vmap(jax.jacfwd(lambda x: safety(x, geometry, operating, settings))))
    s, ds = f(shifts), df(shifts)
    names = ("S_H pinion", "S_H gear", "S_F pinion", "S_F gear")
    out = {
        "profile_shift_pinion": [float(x) for x in shifts],
        **{n: [float(v) for v in s[:, i]] for i, n in enumerate(names)},
        **{f"d({n})/dx1": [float(v) for v in ds[:, i]] for i, n in enumerate(names)},
    }
    fig, (a, b) = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    for i, n in enumerate(names):
        a.plot(shifts, s[:, i], label=n)
        b.plot(shifts, ds[:, i], label=n)
    a.set(xlabel="pinion profile shift x₁", ylabel="safety factor", title="ISO 6336 method B")
    b.set(xlabel="pinion profile shift x₁", ylabel="dS/dx₁ (jax.jacfwd)", title="gradients")
    a.legend()
    fig.suptitle("ISO/TR 6336-30 example 1 pair, zero backlash, T₁ = 9000 N·m, 360 1/min")
    fig.savefig(out_dir / "rating_profile_shift.png", dpi=110)
    plt.close(fig)
    (out_dir / "rating_profile_shift.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    main(*sys.argv[1:2])
