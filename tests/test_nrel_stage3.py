"""The embedded ``nrel-5mw-stage3`` (the NREL 5 MW reference gearbox's parallel helical stage,
Nejad et al., Wind Energy 19 (2016) 1089-1106, Table V): the case parses to Table V's geometry
(reference, tip and root diameters, centre distance, ratio), each computed here by hand from the
ISO 21771 formulas, and its operating point is stage 2's output (rated 5 MW at 12.1 rpm, the
total ratio 96.354). Parsing and geometry only (fast)."""

from __future__ import annotations

import math

import numpy as np
import pytest

import jaxgear.io as jio

M_N, ALPHA_N, BETA = 14e-3, math.radians(20.0), math.radians(10.0)
Z, X = (24, 95), (0.480, 0.669)
K = -0.938e-3  # tip alteration k m_n (m), the port's KISSsoft value
# Table V, third stage (mm): reference, tip, root diameters (pinion, wheel); centre distance
D_REF, D_TIP, D_ROOT, A_W = (341.183, 1350.517), (380.751, 1395.372), (319.627, 1334.248), 861.0


def _inv(a: float) -> float:
    return math.tan(a) - a


def _inv_inverse(v: float) -> float:
    """The angle whose involute function is ``v`` (Newton from 0.5 rad)."""
    a = 0.5
    for _ in range(50):
        a -= (_inv(a) - v) / math.tan(a) ** 2
    return a


def test_stage3_geometry_is_table_v():
    case = jio.load_case("nrel-5mw-stage3")
    pair = case.pair
    assert (pair.pinion.teeth, pair.gear.teeth) == Z
    d = [z * M_N / math.cos(BETA) for z in Z]  # reference diameters (ISO 21771 (4))
    np.testing.assert_allclose([1e3 * v for v in d], D_REF, atol=5e-4)
    np.testing.assert_allclose([2 * r for r in pair.pitch_radii], d, rtol=1e-12)
    # tips: d + 2 m_n (1 + x) + 2 k m_n; roots: d - 2 m_n (1.25 - x) (Table V within its rounding)
    tips = [dd + 2 * M_N * (1 + x) + 2 * K for dd, x in zip(d, X, strict=True)]
    np.testing.assert_allclose([2 * r for r in pair.tip_radii], tips, rtol=0, atol=2e-6)
    np.testing.assert_allclose([2e3 * r for r in pair.tip_radii], D_TIP, atol=5e-3)
    np.testing.assert_allclose([2e3 * r for r in pair.root_radii], D_ROOT, atol=5e-3)
    # zero-backlash distance: inv a_wt = inv a_t + 2 tan a_n (x1 + x2) / (z1 + z2)
    a_t = math.atan(math.tan(ALPHA_N) / math.cos(BETA))
    a_wt = _inv_inverse(_inv(a_t) + 2 * math.tan(ALPHA_N) * sum(X) / sum(Z))
    a0 = 0.5 * sum(d) * math.cos(a_t) / math.cos(a_wt)
    assert pair.zero_backlash_center_distance == pytest.approx(a0, rel=1e-9)
    assert 1e3 * a0 == pytest.approx(A_W, abs=2e-3)  # Table V's a_w, 1.1 um above a0
    assert pair.center_distance == pytest.approx(A_W * 1e-3, rel=1e-12)
    assert pair.gear_ratio == pytest.approx(95 / 24, rel=1e-12)
    assert round(95 / 24, 3) == 3.958  # Table V's 1:3.958


def test_stage3_operating_point_is_stage2s_output():
    case = jio.load_case("nrel-5mw-stage3")
    rotor = 12.1 * math.pi / 30
    total = (1 + 56 / 19) * (1 + 93 / 18) * (95 / 24)
    assert total == pytest.approx(96.354, abs=5e-4)  # Table V's 1:96.354
    assert case.speed == pytest.approx(rotor * total, rel=1e-5)
    assert case.torque * case.speed == pytest.approx(5e6, rel=1e-4)  # rated, lossless
    stage2 = jio.load_case("nrel-5mw-stage2")
    wheel_torque = stage2.torque / (1 + 93 / 18)
    assert case.torque == pytest.approx(wheel_torque * 24 / 95, rel=1e-4)
