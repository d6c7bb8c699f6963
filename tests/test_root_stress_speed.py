"""The root-stress map at speed (docs/rating.md, "Root stress at speed"): jaxgear.rating.root_stress_map
takes a dynamic run's cell loads (K kept steps × L lines × N slices) as it takes a quasi-static
load map. Fast: the map is linear in the loads (loads scaled by c give c × the map, 1e-12) and,
for a record whose loads at each step are the static ones scaled by a factor f_k (the loads a
rigid dynamic model gives: every cell scaled by the mesh force ratio), the largest root stress
is max_k f_k × (the static map's largest stress at step k): the DF-weighted expectation, ≤ the
static maximum × max f (by hand on a stub FE table). Slow: ``jaxgear run``'s
``rating.root_stress.at_speed`` on the rated accessory pair with its lumped scene."""

import math
import tomllib

import jax
import numpy as np
import pytest
from _rating_cases import Cells, rated_accessory_data, stub_table

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import rating_outputs, root_stress_at_speed, root_stress_outputs

jax.config.update("jax_enable_x64", True)


def _pair():
    m = {"addendum_coeff": 1.0, "dedendum_coeff": 1.25, "fillet_radius_coeff": 0.38}
    m["face_width"] = 0.02
    return jg.GearPair(jg.Member(20, 0.0, **m), jg.Member(40, 0.0, **m), 2e-3, math.radians(20))


def _static_record(pair, positions=6, slices=4, seed=0):
    """A quasi-static-like load map over one base pitch: two contact lines a base pitch apart,
    loads of a few 1e5 N/m, the cells off the path of contact masked."""
    rng = np.random.default_rng(seed)
    s0 = np.linspace(0.0, pair.base_pitch, positions, endpoint=False)[:, None, None]
    s = s0 + np.array([0.0, pair.base_pitch])[None, :, None] + np.zeros((1, 1, slices))
    mask = s <= pair.path_of_contact
    load = rng.uniform(1e5, 4e5, s.shape)
    z = np.broadcast_to(np.linspace(0, 0.02, slices), s.shape)
    return Cells(load, s, np.array(z), mask)


def test_root_stress_map_is_linear_and_follows_scaled_dynamic_loads():
    pair = _pair()
    static = _static_record(pair)
    for member in (0, 1):
        tooth = jg.tooth_geometry(pair, member)
        rb = pair.base_radii[member]
        roll = np.asarray(pair.roll_distance(static.cell_s, member))
        table = stub_table(tooth, np.hypot(np.linspace(roll.min(), roll.max(), 9), rb))
        base = jg.rating.root_stress_map(pair, static, member, table.roll, table.peak)
        # linear: c × the loads, c × the map
        for c in (0.5, 1.7):
            scaled = Cells(c * static.line_load, static.cell_s, static.cell_z, static.cell_mask)
            got = jg.rating.root_stress_map(pair, scaled, member, table.roll, table.peak)
            np.testing.assert_allclose(got.stress, c * np.asarray(base.stress), rtol=1e-12)
        # a dynamic record: each step the static loads of its position × f_k
        f = np.array([1.0, 1.3, 0.8, 1.45, 1.1, 0.9])
        dyn = Cells(
            f[:, None, None] * static.line_load, static.cell_s, static.cell_z, static.cell_mask
        )
        got = jg.rating.root_stress_map(pair, dyn, member, table.roll, table.peak)
        # the stub table g(ρ) = 1e3 ρ by hand: stress = w g(ρ) on the loaded flank cells
        by_hand = np.where(static.cell_mask, f[:, None, None] * static.line_load, 0) * 1e3 * roll
        np.testing.assert_allclose(got.stress, by_hand, rtol=1e-12)
        per_step = np.asarray(base.stress).reshape(len(f), -1).max(axis=1)
        assert float(got.max) == pytest.approx(float(np.max(f * per_step)), rel=1e-12)
        assert float(got.max) <= f.max() * float(base.max) * (1 + 1e-12)


@pytest.mark.slow
def test_run_reports_the_root_stress_at_speed(tmp_path):
    """root_stress_at_speed (jaxgear run's step after the sweep) on the rated accessory pair
    with its lumped scene at 1000 rad/s (8 slices; the stub FE table): the at-speed maximum of
    each gear over the kept steps is above the static one and at most the static one times the
    run's tooth dynamic factor (the DF-weighted bound: the loads at speed of this stiff
    lumped model are close to the static ones scaled), and rating.md gets the two rows. About
    70 s on a loaded 2-core machine (the fast test above checks the map's linearity)."""
    d = rated_accessory_data(8, 16)
    d["scene"] = tomllib.loads(jio.embedded_case_text("accessory-spur"))["scene"]
    case = jio.parse_case(d)
    res = jg.quasi_static(case.mesh_model(), case.modifications, case.torque)
    section = rating_outputs(case, str(tmp_path), result=res)
    root_stress_outputs(case, str(tmp_path), res, section, table=stub_table)
    summary = {"rating": section}
    root_stress_at_speed(
        case, str(tmp_path), summary, {"speed_of_max_rad_s": 1000.0, "slices": 8}, stub_table
    )
    fast = summary["rating"]["root_stress"]["at_speed"]
    assert fast["result"] == 0 and fast["speed_rad_s"] == 1000.0
    for a, b, r in zip(fast["max_Pa"], fast["static_max_Pa"], fast["ratio"], strict=True):
        assert r == pytest.approx(a / b, rel=1e-12)
        assert 1.0 < r <= fast["dynamic_factor_tooth"] * (1 + 1e-9)
    text = (tmp_path / "rating.md").read_text()
    assert "σ_F,FE max at speed" in text and "σ_F,FE at speed / static" in text
