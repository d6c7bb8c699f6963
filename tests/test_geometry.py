"""Involute pair geometry against published worked examples and textbook identities.

References (independent of this code):
* KHK, *Gear Technical Reference*, "Profile shifted spur gears" (Table 4.6 in the KHK text; also
  reproduced at bolsover.com/utilitiesforalibre/profile-shifted-external-spur-gears.html):
  m 3, α 20°, z 12/24, x 0.6/0.36, a = 56.4999 mm, α_w 26.0888°, d_b 33.8289/67.6579 mm,
  d_a 44.840/79.400 mm, d_f 32.100/66.660 mm, ε_α 1.202.
* KHK, "Profile shifted helical gears, normal system" (reproduced at
  bolsover.com/utilitiesforalibre/profile-shifted-external-helical-gear-normal.html):
  m_n 3, α_n 20°, β 30°, z 12/60, x_n 0.09809/0, a = 125 mm, α_t 22.79588°, α_wt 23.1126°,
  d 41.569/207.846 mm, d_b 38.322/191.611 mm, d_a 48.154/213.842 mm, d_f 34.658/200.346 mm,
  b = 20 mm, ε_α 1.294, ε_β 1.061.
KHK shortens the tips (addendum (1 + y − x_other) m); the tip diameters of the tables are turned
into our addendum coefficients with r_a = r + m_n (h_a* + x), i.e. h_a* = (d_a/2 − r)/m_n − x.
"""

import math

import pytest

from jaxgear import GearPair, Member, inverse_involute, involute

DEG = math.pi / 180


def _khk_spur(**kw) -> GearPair:
    m = 3.0  # mm
    ha1 = (44.840 / 2 - 12 * m / 2) / m - 0.6  # = 0.87333 (KHK: 1 + y − x2 with y = 0.83333)
    ha2 = (79.400 / 2 - 24 * m / 2) / m - 0.36
    return GearPair(
        Member(12, 0.6, ha1, 1.25, 20e-3),
        Member(24, 0.36, ha2, 1.25, 20e-3),
        m * 1e-3,
        20 * DEG,
        **kw,
    )


def _khk_helical(**kw) -> GearPair:
    mn, beta = 3.0, 30 * DEG
    mt = mn / math.cos(beta)
    ha1 = (48.154 / 2 - 12 * mt / 2) / mn - 0.09809
    ha2 = (213.842 / 2 - 60 * mt / 2) / mn - 0.0
    return GearPair(
        Member(12, 0.09809, ha1, 1.25, 20e-3),
        Member(60, 0.0, ha2, 1.25, 20e-3),
        mn * 1e-3,
        20 * DEG,
        beta,
        **kw,
    )


def test_khk_profile_shifted_spur():
    p = _khk_spur()
    # KHK rounds inv α_w to 0.034317 before inverting (exact: 0.0343161), which moves α_w by
    # +2.2e-4°; hence the 3e-4° tolerance here and the involute check below.
    assert p.operating_pressure_angle / DEG == pytest.approx(26.0888, abs=3e-4)
    assert p.center_distance * 1e3 == pytest.approx(56.4999, abs=1e-4)
    assert p.transverse_contact_ratio == pytest.approx(1.202, abs=5e-4)
    assert [2e3 * r for r in p.base_radii] == pytest.approx([33.8289, 67.6579], abs=1e-4)
    assert [2e3 * r for r in p.pitch_radii] == pytest.approx([36.0, 72.0], abs=1e-12)
    assert [2e3 * r for r in p.tip_radii] == pytest.approx([44.840, 79.400], abs=1e-9)
    assert [2e3 * r for r in p.root_radii] == pytest.approx([32.100, 66.660], abs=1e-9)
    assert p.overlap_ratio == 0.0
    # KHK gives inv α = 0.014904 and inv α_w = 0.034317
    assert involute(20 * DEG) == pytest.approx(0.014904, abs=5e-7)
    assert involute(p.operating_pressure_angle) == pytest.approx(0.034317, abs=1e-6)


def test_khk_profile_shifted_spur_given_center_distance():
    p = _khk_spur(center_distance=56.4999e-3)
    assert p.operating_pressure_angle / DEG == pytest.approx(26.0888, abs=3e-4)
    assert p.transverse_contact_ratio == pytest.approx(1.202, abs=5e-4)


def test_khk_profile_shifted_helical_normal_system():
    p = _khk_helical()
    assert p.transverse_pressure_angle / DEG == pytest.approx(22.79588, abs=5e-6)
    assert p.operating_pressure_angle / DEG == pytest.approx(23.1126, abs=5e-5)
    assert p.center_distance * 1e3 == pytest.approx(125.0, abs=1e-4)
    assert [2e3 * r for r in p.pitch_radii] == pytest.approx([41.569, 207.846], abs=5e-4)
    assert [2e3 * r for r in p.base_radii] == pytest.approx([38.322, 191.611], abs=5e-4)
    assert [2e3 * r for r in p.root_radii] == pytest.approx([34.658, 200.346], abs=5e-4)
    assert p.face_width == pytest.approx(20e-3)
    assert p.transverse_contact_ratio == pytest.approx(1.294, abs=5e-4)
    assert p.overlap_ratio == pytest.approx(1.061, abs=5e-4)


def test_base_pitch_and_base_helix_identities():
    """p_bt = 2π r_b / z on both members; sin β_b = sin β cos α_n (ISO 21771 identity, not the
    tan β_b = tan β cos α_t form the code uses); normal base pitch p_bn = p_bt cos β_b =
    π m_n cos α_n."""
    for p in (_khk_spur(), _khk_helical()):
        for rb, z in zip(p.base_radii, (p.pinion.teeth, p.gear.teeth)):
            assert p.base_pitch == pytest.approx(2 * math.pi * rb / z, rel=1e-14)
        assert math.sin(p.base_helix_angle) == pytest.approx(
            math.sin(p.helix_angle) * math.cos(p.normal_pressure_angle), abs=1e-15
        )
        assert p.base_pitch * math.cos(p.base_helix_angle) == pytest.approx(
            math.pi * p.normal_module * math.cos(p.normal_pressure_angle), rel=1e-14
        )
        # the path of contact spans ε_α base pitches; the pitch point lies on it
        assert p.path_of_contact == pytest.approx(p.transverse_contact_ratio * p.base_pitch)
        s_pitch = p.base_radii[0] * math.tan(p.operating_pressure_angle) - p.start_roll
        assert 0 < s_pitch < p.path_of_contact


@pytest.mark.parametrize("deg", [0.5, 5.0, 14.5, 20.0, 26.0888, 35.0, 60.0, 80.0, 89.0])
def test_inverse_involute(deg):
    a = deg * DEG
    assert inverse_involute(math.tan(a) - a) == pytest.approx(a, rel=1e-13)


def test_inverse_involute_reference_values():
    assert inverse_involute(0.034317) / DEG == pytest.approx(26.0888, abs=1e-4)  # KHK spur
    assert inverse_involute(0.0) == 0.0
    with pytest.raises(ValueError, match="inverse_involute"):
        inverse_involute(-1e-3)


@pytest.mark.parametrize(
    "x1,x2,beta",
    [
        (0.6, 0.36, 0.0),
        (0.09809, 0.0, 30.0),
        (0.341, 0.481, 0.0),
        (-0.2, 0.5, 12.0),
        (0.0, 0.0, 0.0),
    ],
)
def test_zero_backlash_center_distance(x1, x2, beta):
    """At the default centre distance the transverse tooth thicknesses on the two operating pitch
    circles fill the operating circular pitch exactly (no backlash), ISO 21771 §5.3."""
    z1, z2, mn, an = 25, 47, 2e-3, 20 * DEG
    p = GearPair(Member(z1, x1, 1.0, 1.25), Member(z2, x2, 1.0, 1.25), mn, an, beta * DEG)
    at, awt = p.transverse_pressure_angle, p.operating_pressure_angle
    mt = mn / math.cos(beta * DEG)
    dw1 = 2 * p.center_distance * z1 / (z1 + z2)
    dw2 = 2 * p.center_distance * z2 / (z1 + z2)
    s = []
    for z, x, dw in ((z1, x1, dw1), (z2, x2, dw2)):
        d = z * mt
        st = mt * (math.pi / 2 + 2 * x * math.tan(an))  # transverse thickness at d
        s.append(dw * (st / d + involute(at) - involute(awt)))
    assert s[0] + s[1] == pytest.approx(math.pi * dw1 / z1, rel=1e-12)
    if x1 + x2 == 0:
        assert p.center_distance == pytest.approx((z1 + z2) * mt / 2, rel=1e-14)
    # a larger centre distance is accepted (backlash) and raises the operating pressure angle
    q = GearPair(p.pinion, p.gear, mn, an, beta * DEG, center_distance=p.center_distance + 1e-4)
    assert q.operating_pressure_angle > awt
    assert math.cos(q.operating_pressure_angle) == pytest.approx(
        (p.base_radii[0] + p.base_radii[1]) / q.center_distance, rel=1e-14
    )


def test_undercut_limit_matches_rack_formula():
    """No undercut iff x >= h_aP0/m − z sin²α/2 with the rack's effective addendum
    h_aP0 = h_f* − ρ_fP*(1 − sin α) (ISO 21771 generating rack with a tip radius)."""
    z, an, hf, rho = 12, 20 * DEG, 1.25, 0.25
    x_min = hf - rho * (1 - math.sin(an)) - z * math.sin(an) ** 2 / 2
    gear = Member(40, 0.0, 0.8, 1.25)
    GearPair(Member(z, x_min + 1e-6, 0.8, hf, fillet_radius_coeff=rho), gear, 2e-3, an)
    with pytest.raises(ValueError, match=r"pinion\.profile_shift \(undercut"):
        GearPair(Member(z, x_min - 1e-6, 0.8, hf, fillet_radius_coeff=rho), gear, 2e-3, an)


def _pair(p1=None, p2=None, **kw):
    d = dict(
        pinion=p1 or Member(20, 0.0, 1.0, 1.25, 0.01),
        gear=p2 or Member(40, 0.0, 1.0, 1.25, 0.01),
        normal_module=2e-3,
        normal_pressure_angle=20 * DEG,
    )
    d.update(kw)
    return GearPair(**d)


@pytest.mark.parametrize(
    "kwargs,pattern",
    [
        (dict(p1=Member(8, 0.0, 1.0, 1.25)), r"pinion\.profile_shift \(undercut"),
        (dict(p1=Member(10, 1.0, 1.3, 1.25)), r"pinion\.addendum_coeff \(tip thickness .*pointed"),
        (
            dict(p1=Member(17, 0.1, 1.0, 1.25), p2=Member(80, -0.1, 1.25, 1.25)),
            r"gear\.addendum_coeff \(interference",
        ),
        (
            dict(p1=Member(20, 0.0, 0.45, 1.25), p2=Member(40, 0.0, 0.45, 1.25)),
            r"total contact ratio = 0\.8\d* is out of range: allowed >= 1",
        ),
        (dict(p1=Member(20, -1.0, 0.05, 1.25)), r"pinion\.tip radius .* allowed > base radius"),
        (dict(normal_module=0.0), r"normal_module = 0\.0 is out of range: allowed > 0"),
        (dict(normal_module=-1e-3), r"normal_module = -0\.001 is out of range"),
        (
            dict(p1=Member(20, 0.0, 1.0, 1.25, 0.0)),
            r"pinion\.face_width = 0\.0 is out of range: allowed > 0",
        ),
        (dict(p2=Member(40, 0.0, 1.0, 1.25, -0.01)), r"gear\.face_width = -0\.01 is out of range"),
        (
            dict(center_distance=59.9e-3),
            r"center_distance = 0\.0599 is out of range: allowed >= 60\.000000 mm",
        ),
    ],
)
def test_invalid_geometry_raises(kwargs, pattern):
    with pytest.raises(ValueError, match=pattern):
        _pair(**kwargs)


def test_valid_neighbours_of_error_cases():
    """The error cases above are genuine: small changes towards safety pass."""
    _pair(Member(17, 0.1, 1.0, 1.25), Member(80, -0.1, 1.0, 1.25))  # normal gear addendum
    assert (
        _pair(Member(20, 0.0, 0.6, 1.25), Member(40, 0.0, 0.6, 1.25)).transverse_contact_ratio > 1
    )
    _pair(center_distance=60.0e-3)
    _pair(center_distance=60.1e-3)
