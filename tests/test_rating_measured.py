"""K_Hα measured on the load map (jaxgear.rating.transverse_load_factor: ISO 6336-1:2019 clause 8's
load sharing between the pairs in contact, as the largest mean line load of one tooth pair over
that of all loaded cells) and ``[rating] use_measured``: the rating redone with the measured
factors in place of ISO's.

References: a hand count on a few cells; the closed form of a spur pair of uniform stiffness k
per unit contact length with a linear tip relief on the pinion: in double contact the relieved
pair's line load is short of the other's by k e(s) (both close by one approach), their sum
F_n/b, so K_Hα = 1 + k b max e/F_n over the positions of double contact; and ISO 6336-2's
σ_H ∝ √(K_Hβ K_Hα), through which S_H scales when the measured factors replace ISO's."""

import math
from typing import NamedTuple

import jax
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli

from test_rating_case import _case

jax.config.update("jax_enable_x64", True)


class _Loads(NamedTuple):
    line_load: np.ndarray
    cell_mask: np.ndarray


def test_transverse_load_factor_by_hand():
    """Position 0: two lines of two slices, line means 2 and 1, all 1.5 -> 4/3; position 1: one
    line (the other off the flank, masked) -> 1; position 2: an unloaded line (lost contact)
    does not count -> 1. K_Hα = 4/3."""
    w = np.array([[[2.0, 2.0], [1.0, 1.0]], [[3.0, 3.0], [7.0, 7.0]], [[4.0, 4.0], [0.0, 0.0]]])
    mask = np.array([[[1, 1], [1, 1]], [[1, 1], [0, 0]], [[1, 1], [1, 1]]], dtype=bool)
    assert float(jg.rating.transverse_load_factor(_Loads(w, mask))) == pytest.approx(4 / 3, rel=1e-12)
    even = np.ones((2, 2, 3))
    assert float(jg.rating.transverse_load_factor(_Loads(even, even > 0))) == 1.0


class _Cells(NamedTuple):
    line_load: np.ndarray
    cell_s: np.ndarray
    cell_mask: np.ndarray


def test_transverse_load_factor_beyond_the_path_by_hand():
    """One position, two lines of two slices, g_α = 1: a pair on the path carrying 0.87 of
    the load (line load 87 on both cells) and a tip corner beyond the path (s = -0.1) carrying
    0.13 (13): the corner is not a pair, the pair on the path carries less than the whole load
    over its length: ratio 87/100 -> K_Hα 1. The same corner placed on the path (s = 0.1, a
    second pair in the double contact zone taking 13 %): 87 over the mean 50 -> 1.74, as
    without path_of_contact (every cell a pair's). A result whose cell_s is None is refused with
    path_of_contact, and g_α <= 0 too, in one line."""
    w = np.array([[[87.0, 87.0], [13.0, 13.0]]])
    mask = np.ones(w.shape, dtype=bool)
    s = lambda corner: np.array([[[0.5, 0.5], [corner, corner]]])
    k = jg.rating.transverse_load_factor
    assert float(k(_Cells(w, s(-0.1), mask), path_of_contact=1.0)) == 1.0
    assert float(k(_Cells(w, s(1.1), mask), path_of_contact=1.0)) == 1.0  # late disengagement
    assert float(k(_Cells(w, s(0.1), mask), path_of_contact=1.0)) == pytest.approx(1.74, rel=1e-12)
    assert float(k(_Cells(w, s(-0.1), mask))) == pytest.approx(1.74, rel=1e-12)
    # two pairs on the path sharing 60/40 and a corner of 10 beyond: 60 over 110/4 (the corner's
    # load in the total, its cells not in the length)
    w3 = np.array([[[60.0, 60.0], [40.0, 40.0], [10.0, 10.0]]])
    s3 = np.array([[[0.3, 0.3], [0.8, 0.8], [1.05, 1.05]]])
    got = float(k(_Cells(w3, s3, np.ones(w3.shape, bool)), path_of_contact=1.0))
    assert got == pytest.approx(60.0 / (220.0 / 4), rel=1e-12)
    with pytest.raises(ValueError, match="_Cells has cell_s = None"):
        k(_Cells(w, None, mask), path_of_contact=1.0)
    with pytest.raises(ValueError, match=r"path_of_contact = 0 m is out of range: allowed > 0 m"):
        k(_Cells(w, s(0.1), mask), path_of_contact=0.0)


def test_transverse_load_factor_of_a_tip_relieved_uniform_spur_pair():
    # theoretical path: the hand count below takes the path's cells (two lines in double contact)
    case = jio.load_case("accessory-spur").replace(
        slices=2, positions_per_pitch=64, contact_geometry=jg.TheoreticalPath()
    )
    k0, depth, extent = 1.5e10, 10e-6, 0.3
    case = case.replace(stiffness=jg.Uniform(k0))
    pair = case.pair
    tip = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=extent)
    res = jg.quasi_static(
        case.mesh_model(), jg.Modifications(tip, jg.MemberModification()), case.torque
    )
    f_n = case.torque / pair.base_radii[0]
    assert k0 * depth < f_n / pair.face_width  # the relieved pair stays loaded
    g = float(pair.path_of_contact)
    s = np.asarray(res.cell_s)[:, :, 0]
    m = np.asarray(res.cell_mask)[:, :, 0]
    e = depth * np.clip((s - (1 - extent) * g) / (extent * g), 0.0, None)  # the pinion's tip
    double = m.sum(axis=1) == 2
    want = 1 + k0 * pair.face_width * np.max(np.where(m & double[:, None], e, 0.0)) / f_n
    assert float(jg.rating.transverse_load_factor(res)) == pytest.approx(want, rel=1e-9)


def _loads():
    """K_Hβ = 2.5/(7/3) (tests/test_rating_case.py's hand count), K_Hα: position 0 line means
    2 and 1 (of loaded cells: line 1's third cell is negative) over 8/5 -> 5/4; position 1
    one line -> 1."""
    w = np.array([[[1.0, 2.0, 3.0], [1.0, 1.0, -5.0]], [[2.0, 2.0, 2.0], [9.0, 9.0, 9.0]]])
    mask = np.array([[[1, 1, 1], [1, 1, 1]], [[1, 1, 1], [0, 0, 0]]], dtype=bool)
    return _Loads(w, mask), 2.5 / (7 / 3), 2.0 / (8 / 5)


def test_use_measured_rates_with_the_measured_factors(tmp_path):
    loads, k_hb, k_ha = _loads()
    assert float(jg.rating.transverse_load_factor(loads)) == pytest.approx(k_ha, rel=1e-12)
    iso = cli.rating_outputs(jio.parse_case(_case(**{"rating/K_Hbeta": None})), str(tmp_path))
    d = _case(**{"rating/K_Hbeta": None, "rating/use_measured": ["K_Hbeta", "K_Halpha"]})
    section = cli.rating_outputs(jio.parse_case(d), str(tmp_path), result=loads)
    f = section["factors"]
    assert f["K_Hbeta"]["value"] == pytest.approx(k_hb, rel=1e-12)
    assert f["K_Halpha"]["value"] == pytest.approx(k_ha, rel=1e-12)
    assert f["K_Falpha"]["value"] == pytest.approx(k_ha, rel=1e-12)  # method B: K_Fα = K_Hα
    for key in ("K_Hbeta", "K_Halpha", "K_Falpha"):
        assert f[key]["source"].startswith("measured")
    assert f["K_v"] == iso["factors"]["K_v"]
    # σ_H ∝ √(K_Hβ K_Hα), σ_HG unchanged: S_H scales by the inverse root of the product's ratio
    ratio = (k_hb * k_ha) / (iso["factors"]["K_Hbeta"]["value"] * iso["factors"]["K_Halpha"]["value"])
    np.testing.assert_allclose(
        section["pitting"]["S_H"], np.asarray(iso["pitting"]["S_H"]) / math.sqrt(ratio), rtol=1e-9
    )
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "| K_Hα measured | 1.250 |" in table and "| yes: [rating] use_measured |" in table
    assert section["measured"]["K_Halpha"]["value"] == pytest.approx(k_ha, rel=1e-12)


def test_use_measured_k_v_from_the_sweep(tmp_path):
    d = _case(**{"rating/use_measured": ["K_v"]})
    case = jio.parse_case(d)
    section = cli.rating_outputs(case, str(tmp_path))
    dynamics = {"model": "torsional", "slices": 8, "speeds_rad_s": [30.0, 40.0, 50.0]}
    dynamics["dynamic_factor"] = [1.10, 1.30, 1.20]
    summary = {"rating": section}
    cli.measured_dynamic_factor(case, str(tmp_path), summary, dynamics)
    want = 1.10 + (360.0 * 2 * math.pi / 60 - 30.0) / 10.0 * 0.20
    k_v = summary["rating"]["factors"]["K_v"]
    assert k_v["value"] == pytest.approx(want, rel=1e-12) and k_v["source"].startswith("measured")
    assert summary["rating"]["pitting"]["sigma_H_Pa"] != section["pitting"]["sigma_H_Pa"]


def test_use_measured_keeps_a_given_transverse_factor(tmp_path):
    """A given K_Hα is rated as given when another factor is measured: ISO 6336-1's clause 8
    limits bound the measured K_Hα (and ISO's own), not a value the case gives."""
    d = _case(**{"rating/use_measured": ["K_v"], "rating/K_Halpha": 3.0})
    case = jio.parse_case(d)
    section = cli.rating_outputs(case, str(tmp_path))
    assert section["factors"]["K_Halpha"]["value"] == pytest.approx(3.0, rel=1e-12)
    dynamics = {"model": "torsional", "slices": 8, "speeds_rad_s": [30.0, 40.0, 50.0]}
    dynamics["dynamic_factor"] = [1.10, 1.30, 1.20]
    summary = {"rating": section}
    cli.measured_dynamic_factor(case, str(tmp_path), summary, dynamics)
    f = summary["rating"]["factors"]
    assert f["K_v"]["source"].startswith("measured")
    assert f["K_Halpha"]["value"] == pytest.approx(3.0, rel=1e-12)  # above ISO's 2.63
    # σ_H ∝ √(K_v K_Hα): only K_v changed
    ratio = f["K_v"]["value"] / section["factors"]["K_v"]["value"]
    np.testing.assert_allclose(summary["rating"]["pitting"]["sigma_H_Pa"],
                               np.asarray(section["pitting"]["sigma_H_Pa"]) * math.sqrt(ratio),
                               rtol=1e-9)


@pytest.mark.parametrize(
    ("use", "message"),
    [
        (["K_Hgamma"], "use_measured = ['K_Hgamma']: unknown 'K_Hgamma', allowed 'K_Hbeta', "
         "'K_Halpha', 'K_v'"),
        (["K_Hbeta"], "K_Hbeta is given as a value too"),  # the case gives K_Hbeta = 1.16
        (["K_v", "K_v"], "a factor named twice"),
        ("K_v", "use_measured = 'K_v': must be an array of 'K_Hbeta', 'K_Halpha', 'K_v'"),
    ],
)
def test_bad_use_measured_is_one_line(use, message):
    with pytest.raises(jio.SchemaError) as err:
        jio.parse_case(_case(**{"rating/use_measured": use}))
    assert message in str(err.value) and "\n" not in str(err.value)


def test_2019_helix_angle_factor_holds_beta_at_30_degrees():
    """ISO 6336-3:2019 Y_β = (1 − ε_β β/120°)/cos³ β with ε_β ≤ 1 and β ≤ 30° in both terms:
    by hand at 10° and ε_β 0.6, and above the limits (35°, ε_β 1.4) the value of 30° and 1."""
    e = jg.rating.Edition2019()
    b10 = math.radians(10.0)
    assert float(e.helix_angle_factor(0.6, b10)) == pytest.approx(
        (1 - 0.6 * 10 / 120) / math.cos(b10) ** 3, rel=1e-12
    )
    assert float(e.helix_angle_factor(1.4, math.radians(35.0))) == pytest.approx(
        (1 - 30 / 120) / math.cos(math.radians(30.0)) ** 3, rel=1e-12
    )


def test_transverse_factor_limits_by_hand():
    """ISO 6336-1 clause 8: K_Hα <= ε_γ/(ε_α Z_ε²), K_Fα <= ε_γ/(0.25 ε_α + 0.75); a spur pair:
    Z_ε² = (4 − ε_α)/3."""
    pair = jio.load_case("accessory-spur").pair
    ea = float(pair.transverse_contact_ratio)
    h, f = jg.rating.transverse_factor_limits(jr.RatingGeometry.of(pair))
    assert float(h) == pytest.approx(3 / (4 - ea), rel=1e-9)
    assert float(f) == pytest.approx(ea / (0.25 * ea + 0.75), rel=1e-9)
