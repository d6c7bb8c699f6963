"""``jaxgear run``'s root-stress map for a case with ``[rating]``
(``jaxgear.cli.root_stress_outputs``): the largest root stress of each gear beside ISO 6336-3's
σ_F0, the plot, the rating table's rows, the FE influence cached per tooth form.

Reference, independent of the map's interpolation: on an unmodified spur pair under a rigid,
exact quasi-static mesh, one pair carries the whole normal load F_bn = T/r_b1 over the single
contact zone, so the pinion's largest root stress is F_bn/b times the FE fillet stress per unit
load with the load at its outer point of single pair contact (a separate FE solve,
``fem_prep.fillet_stress``): within the step of the mesh positions (1 %)."""

import math

import jax
import numpy as np
import pytest
from _rating_cases import Cells, rated_accessory_case, rated_accessory_data, stub_table

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
from jaxgear import cli

jax.config.update("jax_enable_x64", True)


def _case():
    return rated_accessory_case(2, 48)


def test_root_stress_outputs_section_plot_and_table(tmp_path):
    """The plumbing, fast: a stub fillet table g(ρ) = 1e3 ρ (Pa per N/m, linear: exact under
    the map's interpolation) and three cells; the largest stress of each gear by hand is the
    largest w g(ρ_member(s)) of the loaded cells on the flanks."""
    case = _case()
    pair = case.pair
    calls = []

    def stub(tooth, radii):
        calls.append(tooth.teeth)
        return stub_table(tooth, radii)

    g = float(pair.path_of_contact)
    s = np.array([[[0.2 * g, 0.2 * g], [0.7 * g, 0.7 * g], [-1e-3, -1e-3]]])
    cells = Cells(
        line_load=np.array([[[1e5, 2e5], [3e5, 0.0], [9e5, 9e5]]]),
        cell_s=s,
        cell_z=np.array([[[1e-3, 5e-3]] * 3]),
        cell_mask=np.array([[[True, True], [True, True], [False, False]]]),
    )
    section = cli.rating_outputs(case, str(tmp_path))
    cli.root_stress_outputs(case, str(tmp_path), cells, section, table=stub)
    rs = section["root_stress"]
    assert calls == [45, 86]
    want = [
        max(w * 1e3 * float(pair.roll_distance(x, i)) for w, x in ((2e5, 0.2 * g), (3e5, 0.7 * g)))
        for i in (0, 1)
    ]
    np.testing.assert_allclose(rs["max_Pa"], want, rtol=1e-9)
    iso = section["bending"]["sigma_F0_Pa"]
    assert rs["iso_sigma_F0_Pa"] == iso
    np.testing.assert_allclose(rs["fe_over_iso"], np.divide(want, iso), rtol=1e-9)
    assert (tmp_path / "root_stress_map.png").stat().st_size > 10_000
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "| σ_F,FE max |" in table and "| σ_F,FE max / σ_F0 |" in table


@pytest.mark.slow
def test_root_stress_outputs_against_the_single_contact_load_by_hand(tmp_path):
    """About 20 s on a loaded 2-core machine (three FE solves; the fast test above checks the
    outputs with a stub table, tests/test_root_stress.py the map against a direct FE solve).
    The reference's premise, one pair carrying the whole load over the single contact zone,
    holds on the theoretical path: the case pins it (``extended_contact = false``). With the
    cells beyond it (the case files' default) the leaving pair's tip corner still carries load
    at the outer point of single pair contact: the map's largest stress is lower, asserted."""
    d = rated_accessory_data(2, 48)
    d["mesh"]["extended_contact"] = False
    case = jio.parse_case(d)
    pair = case.pair
    res = jg.quasi_static(case.mesh_model(), jg.Modifications(), case.torque)
    section = cli.rating_outputs(case, str(tmp_path))
    before = cli.fillet_table.cache_info().misses
    cli.root_stress_outputs(case, str(tmp_path), res, section)
    rs = section["root_stress"]
    # by hand: F_bn / b at the pinion's outer point of single pair contact
    rb = pair.base_radii[0]
    roll = math.sqrt(pair.tip_radii[0] ** 2 - rb**2)
    roll -= (pair.transverse_contact_ratio - 1) * pair.base_pitch
    unit = fem_prep.fillet_stress(jg.tooth_geometry(pair, 0), math.hypot(roll, rb)).peak
    w = case.torque / rb / pair.face_width
    assert rs["max_Pa"][0] == pytest.approx(w * unit, rel=1e-2)
    assert rs["max_Pa"][0] <= w * unit * (1 + 5e-3)  # the map's positions reach it from below
    iso = section["bending"]["sigma_F0_Pa"]
    assert rs["iso_sigma_F0_Pa"] == iso
    np.testing.assert_allclose(rs["fe_over_iso"], np.divide(rs["max_Pa"], iso), rtol=1e-12)
    assert (tmp_path / "root_stress_map.png").stat().st_size > 10_000
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "| σ_F,FE max |" in table and "| σ_F,FE max / σ_F0 |" in table
    # a second run of the same tooth forms: no FE solve
    cli.root_stress_outputs(case, str(tmp_path), res, section)
    assert cli.fillet_table.cache_info().misses == before + 2
    # beyond the path (the default): the single contact zone shortens, its peak load falls
    beyond = _case()
    res = jg.quasi_static(beyond.mesh_model(), jg.Modifications(), beyond.torque)
    section = cli.rating_outputs(beyond, str(tmp_path))
    cli.root_stress_outputs(beyond, str(tmp_path), res, section)
    assert section["root_stress"]["max_Pa"][0] < 0.97 * rs["max_Pa"][0]
