"""The pair geometry both kinds share (jaxgear.AbstractGearPair): an external and an internal
pair against one set of ISO 21771 formulas written here in ISO 21771's signed form (an internal
gear's tooth count, diameters and the centre distance negative), so that the same lines of this
file give both kinds; the code keeps radii and the centre distance positive. Independent of the
package: the inverse involute by bisection, every formula from the standard's text."""

import math

import pytest

import jaxgear as jg

AN = math.radians(20.0)


def _inv(a):
    return math.tan(a) - a


def _inv_inverse(v):
    lo, hi = 0.0, math.radians(89.0)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _inv(mid) < v else (lo, mid)
    return 0.5 * (lo + hi)


def _iso21771(p1, p2, mn, an, beta, a=None):
    """ISO 21771 in signed form: z2 < 0 for an internal gear, d2, d_b2, d_a2 and a_w then < 0."""
    z1, z2 = p1.teeth, p2.teeth
    x1, x2 = p1.profile_shift, p2.profile_shift
    mt = mn / math.cos(beta)
    at = math.atan(math.tan(an) / math.cos(beta))
    d = [z * mt for z in (z1, z2)]
    db = [di * math.cos(at) for di in d]
    da = [di + 2 * mn * (m.addendum_coeff + m.profile_shift) for di, m in zip(d, (p1, p2))]
    awt0 = _inv_inverse(_inv(at) + 2 * math.tan(an) * (x1 + x2) / (z1 + z2))
    a0 = (d[0] + d[1]) / 2 * math.cos(at) / math.cos(awt0)  # signed: < 0 for an internal pair
    allow = (p1.tooth_thickness_allowance + p2.tooth_thickness_allowance) / mn
    awtA = _inv_inverse(_inv(at) + (2 * math.tan(an) * (x1 + x2) + allow) / (z1 + z2))
    aw = a0 if a is None else math.copysign(a, z2)
    awt = math.acos((db[0] + db[1]) / (2 * aw))
    sign2 = math.copysign(1.0, z2)
    roll_tip = [math.sqrt(da[i] ** 2 - db[i] ** 2) / 2 for i in (0, 1)]
    g = roll_tip[0] + sign2 * roll_tip[1] - aw * math.sin(awt)
    pbt = math.pi * mn * math.cos(at) / math.cos(beta)
    return {
        "center_distance": abs(aw),
        "operating_pressure_angle": awt,
        "base_radii": (abs(db[0]) / 2, abs(db[1]) / 2),
        "tip_radii": (abs(da[0]) / 2, abs(da[1]) / 2),
        "path_of_contact": g,
        "base_pitch": pbt,
        "transverse_contact_ratio": g / pbt,
        "start_roll": aw * math.sin(awt) - sign2 * roll_tip[1],
        "transverse_backlash": (db[0] + db[1]) / 2 * 2 * (_inv(awt) - _inv(awtA)),
        "overlap_ratio": min(p1.face_width, p2.face_width) * math.sin(beta) / (math.pi * mn),
        "gear_ratio": z2 / z1,
    }


CASES = {
    # name: (pinion, gear, m_n, β, centre distance factor on the zero-backlash one)
    "external spur": (jg.Member(19, 0.2), jg.Member(45, -0.1), 2e-3, 0.0, None),
    "external helical, thinned, apart": (
        jg.Member(23, 0.3, face_width=0.03, tooth_thickness_allowance=-4e-5),
        jg.Member(61, 0.1, face_width=0.028, tooth_thickness_allowance=-6e-5),
        3e-3,
        math.radians(15.0),
        1.001,
    ),
    "internal spur": (jg.Member(20, 0.3), jg.Member(-90), 3e-3, 0.0, None),
    "internal helical, thinned, closer": (
        jg.Member(21, 0.25, face_width=0.04, tooth_thickness_allowance=-5e-5),
        jg.Member(-79, 0.1, 0.8, face_width=0.04, tooth_thickness_allowance=-8e-5),
        2.5e-3,
        math.radians(12.0),
        0.999,
    ),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_both_kinds_follow_one_set_of_iso21771_formulas(name):
    p1, p2, mn, beta, factor = CASES[name]
    kind = jg.InternalGearPair if p2.teeth < 0 else jg.GearPair
    a = None
    if factor is not None:
        a = factor * kind(p1, p2, mn, AN, beta).zero_backlash_center_distance
    pair = kind(p1, p2, mn, AN, beta, a)
    assert isinstance(pair, jg.AbstractGearPair)
    assert isinstance(pair, jg.GearPair) == (p2.teeth > 0)  # the kinds are siblings
    ref = _iso21771(p1, p2, mn, AN, beta, a)
    for key, value in ref.items():
        assert getattr(pair, key) == pytest.approx(value, rel=1e-10, abs=1e-15), key
    assert pair.total_contact_ratio == pytest.approx(
        ref["transverse_contact_ratio"] + ref["overlap_ratio"], rel=1e-12
    )
    if factor is None:  # zero-backlash distance, nominal teeth: no backlash
        assert pair.transverse_backlash == pytest.approx(0.0, abs=1e-12)
    else:
        assert pair.transverse_backlash > 1e-6


@pytest.mark.parametrize("name", sorted(CASES))
def test_the_path_of_contact_runs_from_the_gear_tip_to_the_pinion_tip(name):
    """The roll distances at s = 0 and s = g_α put the contact point on the gear's and the
    pinion's tip circles (r = √(ρ² + r_b²)); along the path both stay on their involutes (the
    contact point the same point of the plane: |ρ2 ∓ ρ1| = T1T2 with the tangent points on
    either side of the pitch point, or on the same side for the internal pair)."""
    p1, p2, mn, beta, _ = CASES[name]
    pair = (jg.InternalGearPair if p2.teeth < 0 else jg.GearPair)(p1, p2, mn, AN, beta)
    rb, ra = pair.base_radii, pair.tip_radii
    g = pair.path_of_contact
    assert math.hypot(pair.roll_distance(0.0, 1), rb[1]) == pytest.approx(ra[1], rel=1e-12)
    assert math.hypot(pair.roll_distance(g, 0), rb[0]) == pytest.approx(ra[0], rel=1e-12)
    t1t2 = pair.center_distance * math.sin(pair.operating_pressure_angle)
    for s in (0.0, 0.3 * g, g):
        rho1, rho2 = pair.roll_distance(s, 0), pair.roll_distance(s, 1)
        joined = rho2 - rho1 if p2.teeth < 0 else rho2 + rho1
        assert joined == pytest.approx(t1t2, rel=1e-12)


def test_the_shared_base_is_not_a_pair_itself():
    with pytest.raises(TypeError):
        jg.AbstractGearPair(jg.Member(20), jg.Member(40), 2e-3, AN)
