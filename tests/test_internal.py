"""Internal gear pairs (jaxgear/_internal.py, docs/planetary.md "Internal gears"): the ISO 21771
geometry against the formulas written here in the textbook sign convention (positive tooth
count and opposite profile shift of the ring, plain Python, own bisection for inv⁻¹), the
trochoid-interference condition against a kinematic simulation of the tooth corners, each
interference check on a constructed bad pair, the quasi-static TE against a rigid-tooth
constant-stiffness count of the contact lines, the rack limit of a large tooth-count
difference, ISO 6336-1's c' with the internal gear's rule and ISO 6336-2's Z_H pressure with
u < 0."""

import math
import types
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg

M = 3e-3
ALPHA = math.radians(20.0)


def _inv(a):
    return math.tan(a) - a


def _inv_inverse(value):
    lo, hi = 0.0, 1.5  # inv is increasing on (0, π/2): bisection, independent of the library's
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _inv(mid) < value else (lo, mid)
    return 0.5 * (lo + hi)


def _textbook(z1, z2p, x1, x2p, mn=M, an=ALPHA, beta=0.0, ha=(1.0, 1.0), hf=(1.25, 1.25)):
    """Internal pair in the textbook/KHK convention: the ring's z2' = |z2| > 0 and x2' = −x2
    (positive x2' thins the ring's teeth): inv α_wt = inv α_t + 2 tan α_n (x2' − x1)/(z2' − z1),
    a = m_t (z2' − z1)/2 cos α_t/cos α_wt, d_a2 = d2 − 2 m_n (h_a2 − x2'),
    d_f2 = d2 + 2 m_n (h_f2 + x2'), g_α = ½[√(d_a1² − d_b1²) − √(d_a2² − d_b2²)] + a sin α_wt."""
    mt = mn / math.cos(beta)
    at = math.atan(math.tan(an) / math.cos(beta))
    awt = _inv_inverse(_inv(at) + 2 * math.tan(an) * (x2p - x1) / (z2p - z1))
    a = mt * (z2p - z1) / 2 * math.cos(at) / math.cos(awt)
    d1, d2 = z1 * mt, z2p * mt
    db1, db2 = d1 * math.cos(at), d2 * math.cos(at)
    da1, da2 = d1 + 2 * mn * (ha[0] + x1), d2 - 2 * mn * (ha[1] - x2p)
    df1, df2 = d1 - 2 * mn * (hf[0] - x1), d2 + 2 * mn * (hf[1] + x2p)
    g = 0.5 * (math.sqrt(da1**2 - db1**2) - math.sqrt(da2**2 - db2**2)) + a * math.sin(awt)
    pbt = math.pi * mt * math.cos(at)
    return types.SimpleNamespace(
        a=a,
        awt=awt,
        at=at,
        d=(d1, d2),
        db=(db1, db2),
        da=(da1, da2),
        df=(df1, df2),
        g=g,
        pbt=pbt,
        eps=g / pbt,
        mt=mt,
        st=(
            mt * (math.pi / 2 + 2 * x1 * math.tan(an)),
            mt * (math.pi / 2 - 2 * x2p * math.tan(an)),
        ),
    )


def _pair(z1=20, z2=-90, x1=0.3, x2=0.0, beta=0.0, a=None, p1=None, p2=None, b=0.02):
    return jg.InternalGearPair(
        jg.Member(z1, x1, face_width=b, **(p1 or {})),
        jg.Member(z2, x2, face_width=b, **(p2 or {})),
        M,
        ALPHA,
        beta,
        a,
    )


@pytest.mark.parametrize(
    "z1, z2, x1, x2, beta",
    [
        (20, -90, 0.3, 0.0, 0.0),
        (17, -56, 0.3, -0.3, 0.0),
        (24, -80, 0.4, 0.2, 0.0),
        (20, -90, 0.3, -0.1, 0.25),
    ],
)
def test_geometry_against_the_textbook_formulas(z1, z2, x1, x2, beta):
    p = _pair(z1, z2, x1, x2, beta)
    t = _textbook(z1, -z2, x1, -x2, beta=beta)
    rel = lambda u, v: abs(u - v) / abs(v)
    assert rel(p.operating_pressure_angle, t.awt) < 1e-12
    assert rel(p.center_distance, t.a) < 1e-12
    for i in (0, 1):
        assert rel(2 * p.pitch_radii[i], t.d[i]) < 1e-13
        assert rel(2 * p.base_radii[i], t.db[i]) < 1e-13
        assert rel(2 * p.tip_radii[i], t.da[i]) < 1e-13
        assert rel(2 * p.root_radii[i], t.df[i]) < 1e-13
        assert rel(p.reference_thickness[i], t.st[i]) < 1e-13
    assert p.tip_radii[1] < p.pitch_radii[1] < p.root_radii[1]  # tip inside, root outside
    assert rel(p.path_of_contact, t.g) < 1e-11
    assert rel(p.transverse_contact_ratio, t.eps) < 1e-11
    assert rel(p.base_pitch, t.pbt) < 1e-13
    assert p.gear_ratio == z2 / z1 < 0
    # clearances at the line of centres, and the same-sense kinematics: a pinion roll of
    # r_b1 dθ moves the contact r_b1 dθ along the line = a ring roll of r_b2 dθ2, dθ2 = dθ z1/|z2|
    assert rel(p.tip_root_clearances[0], t.df[1] / 2 - t.a - t.da[0] / 2) < 1e-9
    assert rel(p.tip_root_clearances[1], t.da[1] / 2 - t.a - t.df[0] / 2) < 1e-9
    s = np.linspace(0, p.path_of_contact, 5)
    np.testing.assert_allclose(
        p.roll_distance(s, 1) - p.roll_distance(s, 0), t.a * math.sin(t.awt), rtol=1e-12
    )


def test_center_distance_and_backlash_of_an_internal_pair():
    """Closer than the zero-backlash distance an internal pair has backlash (farther apart it
    jams): j_wt = e_w2 − s_w1 on the operating pitch circles, the ring's space width less the
    pinion's tooth thickness, both from the textbook tooth thicknesses (s = r_w (s_t/r +
    2 (inv α_t − inv α_wt)) on the pinion, the ring's space e = r_w (e_t/r − 2 (inv α_t −
    inv α_wt)), e_t = p_t − s_t2)."""
    p0 = _pair(x2=-0.3)
    a = p0.center_distance - 0.1e-3
    p = _pair(x2=-0.3, a=a)
    # cos α_wt = (r_b2 − r_b1)/a for an internal pair
    awt = math.acos((p.base_radii[1] - p.base_radii[0]) / a)
    assert p.operating_pressure_angle == pytest.approx(awt, rel=1e-14)
    assert p.operating_pressure_angle < p0.operating_pressure_angle
    t = _textbook(20, 90, 0.3, 0.3)
    r1, r2 = t.d[0] / 2, t.d[1] / 2
    rw1, rw2 = r1 * math.cos(t.at) / math.cos(awt), r2 * math.cos(t.at) / math.cos(awt)
    s_w1 = rw1 * (t.st[0] / r1 + 2 * (_inv(t.at) - _inv(awt)))
    e_w2 = rw2 * ((math.pi * t.mt - t.st[1]) / r2 + 2 * (_inv(t.at) - _inv(awt)))
    assert p.circumferential_backlash == pytest.approx(e_w2 - s_w1, rel=1e-9)
    assert p.circumferential_backlash > 10e-6
    assert p.transverse_backlash == pytest.approx((e_w2 - s_w1) * math.cos(awt), rel=1e-9)
    assert abs(p0.transverse_backlash) < 1e-18
    with pytest.raises(ValueError, match="farther apart, the teeth of an internal pair jam"):
        _pair(x2=-0.3, a=p0.center_distance + 1e-6)
    # thinned teeth (A_sn1 = −20 µm, A_sn2 = −30 µm; spur: m_t = m_n): more backlash, and the
    # pair may now sit farther apart, up to its backlash_center_distance
    A = (-20e-6, -30e-6)
    pa = _pair(
        x2=-0.3, a=a, p1={"tooth_thickness_allowance": A[0]}, p2={"tooth_thickness_allowance": A[1]}
    )
    s_w1 = rw1 * ((t.st[0] + A[0]) / r1 + 2 * (_inv(t.at) - _inv(awt)))
    e_w2 = rw2 * ((math.pi * t.mt - t.st[1] - A[1]) / r2 + 2 * (_inv(t.at) - _inv(awt)))
    assert pa.circumferential_backlash == pytest.approx(e_w2 - s_w1, rel=1e-9)
    assert pa.backlash_center_distance > p0.center_distance
    pb = _pair(
        x2=-0.3,
        a=pa.backlash_center_distance,
        p1={"tooth_thickness_allowance": A[0]},
        p2={"tooth_thickness_allowance": A[1]},
    )
    assert abs(pb.transverse_backlash) < 1e-12


def test_coast_flanks_sit_a_backlash_below():
    """With coast flanks and a negative torque the TE sits the backlash j_bn/cos β_b below the
    drive side's mirror: a spur pair of Uniform stiffness has two TE levels, single and double
    contact, F_n/(k0 b n); on the coast side they are −F_n/(k0 b n) − j_bn, and the share of
    double contact is the same (within one position)."""
    p0 = _pair(x2=-0.3)
    pair = _pair(x2=-0.3, a=p0.center_distance - 0.05e-3)
    s, k = jg.stiffness_table(pair, jg.Uniform(1.2e10))
    mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=1, coast=True)
    te = {
        sign: np.asarray(
            jg.quasi_static(mesh, None, sign * 150.0, positions_per_pitch=64).transmission_error
        )
        for sign in (1.0, -1.0)
    }
    fn = 150.0 / pair.base_radii[0]
    levels = np.array([fn / (1.2e10 * pair.face_width * n) for n in (1, 2)])
    for sign, shift in ((1.0, 0.0), (-1.0, pair.normal_backlash)):
        level = sign * levels[None, :] - shift
        dist = np.abs(te[sign][:, None] - level).min(axis=1)
        assert dist.max() < 1e-12 * levels[0]  # every position on one of the two levels
    double = [
        np.mean(np.isclose(te[sign], sign * levels[1] - shift, rtol=0, atol=1e-12 * levels[0]))
        for sign, shift in ((1.0, 0.0), (-1.0, pair.normal_backlash))
    ]
    assert abs(double[0] - double[1]) <= 1 / 64 + 1e-12
    assert pair.normal_backlash > 5e-6


def _penetration(g, n=20000):
    """Largest depth (m) by which a tooth's tip corner enters the other member's involute tooth
    while the pinion (teeth z1, turning θ) and the ring (z2', turning θ z1/z2', the same sense)
    mesh at the centre distance a: a kinematic simulation in the transverse plane, written
    from the tooth shapes only (half angular thicknesses ψ1(ρ) = s1/(2r1) + inv α_t − inv α_ρ,
    ψ2(R) = s2/(2r2) − inv α_t + inv α_R of the ring's tooth, the ring's space centred on the
    pinion's tooth on the line of centres at θ = 0). About 0 (touching) for conjugate meshing."""
    z1, z2, a, at = g.z1, g.z2p, g.a, g.at
    r1, r2 = g.d[0] / 2, g.d[1] / 2
    rb1, rb2 = g.db[0] / 2, g.db[1] / 2
    ra1, ra2 = g.da[0] / 2, g.da[1] / 2
    rf2 = g.df[1] / 2
    inv = lambda x: np.tan(x) - x
    psi1 = lambda r: g.st[0] / (2 * r1) + _inv(at) - inv(np.arccos(np.clip(rb1 / r, -1, 1)))
    psi2 = lambda r: g.st[1] / (2 * r2) - _inv(at) + inv(np.arccos(np.clip(rb2 / r, -1, 1)))
    theta = np.linspace(-8 * np.pi / z1, 8 * np.pi / z1, n)
    ring = theta * z1 / z2
    worst = -np.inf
    for sign in (-1.0, 1.0):  # the pinion's tip corners against the ring's teeth
        ang = theta + sign * psi1(ra1)
        x, y = a + ra1 * np.cos(ang), ra1 * np.sin(ang)
        R = np.hypot(x, y)
        d = np.mod(np.arctan2(y, x) - ring - np.pi / z2, 2 * np.pi / z2)
        d = np.minimum(d, 2 * np.pi / z2 - d)
        depth = np.where((R >= ra2) & (R <= rf2), (psi2(np.maximum(R, rb2)) - d) * R, -np.inf)
        worst = max(worst, depth.max())
        for j in range(-3, 4):  # the ring's tip corners against the pinion's involute teeth
            ang = ring + np.pi / z2 + 2 * np.pi * j / z2 + sign * psi2(ra2)
            x, y = ra2 * np.cos(ang) - a, ra2 * np.sin(ang)
            rho = np.hypot(x, y)
            d = np.mod(np.arctan2(y, x) - theta, 2 * np.pi / z1)
            d = np.minimum(d, 2 * np.pi / z1 - d)
            inside = (rho >= g.r_form1) & (rho <= ra1)
            depth = np.where(inside, (psi1(np.maximum(rho, rb1)) - d) * rho, -np.inf)
            worst = max(worst, depth.max())
    return worst


@pytest.mark.parametrize(
    "z1, dz, ha1, ha2, x2",
    [
        (20, 3, 1.0, 0.6, 0.0),
        (20, 5, 1.0, 0.6, 0.0),
        (20, 6, 1.0, 0.6, 0.0),  # KHK margin −0.00054 rad: 23 µm of penetration
        (20, 7, 1.0, 0.6, 0.0),
        (20, 3, 1.0, 0.7, -0.2),
        (20, 4, 1.0, 0.7, -0.2),
        (30, 5, 0.8, 0.6, 0.0),
        (30, 6, 0.8, 0.6, 0.0),
        (30, 8, 1.0, 0.8, 0.0),
    ],
)
def test_trochoid_check_agrees_with_a_kinematic_simulation(z1, dz, ha1, ha2, x2):
    z2 = -(z1 + dz)
    g = _textbook(z1, -z2, 0.0, -x2, ha=(ha1, ha2))
    # the pinion's form circle (rack generation: dedendum 1.25, fillet 0.25): ISO 21771 (88)
    h = M * (1.25 - 0.25 * (1 - math.sin(ALPHA)))
    g.z1, g.z2p, g.r_form1 = (
        z1,
        -z2,
        math.hypot(g.d[0] / 2 * math.sin(ALPHA) - h / math.sin(ALPHA), g.db[0] / 2),
    )
    depth = _penetration(g)
    try:
        _pair(z1, z2, 0.0, x2, p1={"addendum_coeff": ha1}, p2={"addendum_coeff": ha2})
        refused = False
    except ValueError as err:
        assert "trochoid interference" in str(err)
        refused = True
    assert refused == (depth > 1e-9), depth
    if not refused:
        assert depth < 1e-12  # conjugate flanks touch, nothing enters


@pytest.mark.parametrize(
    "kwargs, words",
    [
        ({"z2": -20}, "gear.teeth = -20 is out of range: allowed an integer < -20"),
        ({"z2": 90}, "gear.teeth = 90 is out of range"),
        ({"z1": 4}, "pinion.teeth = 4 is out of range"),
        ({"z2": -30, "x1": 0.0}, "the ring's tip circle must stay outside its base circle"),
        ({"z2": -60, "x1": 0.0}, "involute interference"),
        (
            {"p1": {"addendum_coeff": 1.3}, "p2": {"dedendum_coeff": 1.2}},
            "tip-to-root clearance c1",
        ),
        ({"z1": 20, "z2": -23, "x1": 0.0, "p2": {"addendum_coeff": 0.6}}, "trochoid interference"),
        ({"a": 0.2}, "center_distance = 0.2 is out of range: allowed (98.667725, 104.067727] mm"),
        ({"x1": 1.4}, "pointed tooth"),
        (
            {"p1": {"addendum_coeff": 0.5}, "p2": {"addendum_coeff": 0.4}},
            "total contact ratio",
        ),
        ({"z2": -24, "x1": 0.1}, "profile_shift (x1 + x2) = 0.1 is out of range: allowed < 0.08"),
        ({"p2": {"bore_radius": 0.1}}, "gear.bore_radius = 0.1 is out of range: allowed None"),
        (
            {"p2": {"tooth_thickness_allowance": 1e-3}},
            "gear.tooth_thickness_allowance = 0.001 is out of range: allowed [-0.00075, 0.00075]",
        ),
        (
            {"p1": {"tooth_thickness_allowance": 1e-5}},
            "tooth_thickness_allowance (pinion + gear) without a center_distance = 1e-05",
        ),
        ({"x1": float("nan")}, "pinion.profile_shift"),
    ],
)
def test_each_check_is_one_line_naming_the_parameter(kwargs, words):
    with pytest.raises(ValueError, match="out of range") as err:
        _pair(**kwargs)
    assert words in str(err.value)
    assert "\n" not in str(err.value)


def test_an_internal_gear_is_refused_by_the_external_pair():
    with pytest.raises(ValueError, match="gear.teeth = -90 is out of range"):
        jg.GearPair(jg.Member(20), jg.Member(-90), M, ALPHA)


def _lines_count(pair, theta):
    """Contact lines of a spur pair inside [0, g_α] at pinion angle θ (rigid teeth): line i at
    s = (r_b1 θ mod p_bt) + i p_bt."""
    roll = (pair.base_radii[0] * theta) % pair.base_pitch
    n = 0
    for i in range(10):
        s = roll + i * pair.base_pitch
        n += 0.0 <= s <= pair.path_of_contact
    return n


def test_quasi_static_te_against_rigid_teeth_and_constant_stiffness():
    pair = _pair()
    k0 = 1.2e10  # N/m per m of contact line
    s, k = jg.stiffness_table(pair, jg.Uniform(k0))
    mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=2)
    torque = 150.0
    res = jg.quasi_static(mesh, None, torque, positions_per_pitch=32)
    fn = torque / pair.base_radii[0]  # spur: F_n = T/r_b1
    te = [fn / (k0 * pair.face_width * _lines_count(pair, float(t))) for t in res.theta]
    np.testing.assert_allclose(np.asarray(res.transmission_error), te, rtol=1e-10)
    # the share of positions in double contact is ε_α − 1 (within one position)
    double = np.mean([_lines_count(pair, float(t)) == 2 for t in res.theta])
    assert abs(double - (pair.transverse_contact_ratio - 1)) <= 1 / 32
    # the load: each loaded line carries F_n/n per unit face width
    w = np.asarray(res.line_load)
    np.testing.assert_allclose(w.sum(axis=(1, 2)) * pair.face_width / 2, fn, rtol=1e-10)


def test_helical_internal_te_against_the_loaded_contact_length():
    pair = _pair(beta=math.radians(15))
    k0 = 1.0e10
    s, k = jg.stiffness_table(pair, jg.Uniform(k0))
    n = 8
    mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=n)
    torque = 120.0
    res = jg.quasi_static(mesh, None, torque, positions_per_pitch=16)
    cb = math.cos(pair.base_helix_angle)
    fn = torque / (pair.base_radii[0] * cb)
    dz = pair.face_width / n
    for t, te in zip(np.asarray(res.theta), np.asarray(res.transmission_error)):
        roll = (pair.base_radii[0] * t) % pair.base_pitch
        length = 0.0
        for i in range(12):
            for j in range(n):
                sc = roll + i * pair.base_pitch - (j + 0.5) * dz * math.tan(pair.base_helix_angle)
                length += (dz / cb) * (0.0 <= sc <= pair.path_of_contact)
        assert te == pytest.approx(fn / (k0 * length) / cb, rel=1e-10)


def _rack_contact_ratio(z1, x1, ha2=1.0, ha1=1.0):
    """Pinion and rack (ISO 21771's limit of an infinite gear): from the pitch point to the
    pinion tip √(r_a1² − r_b1²) − r_b1 tan α, to the rack's tip line (h_a2 − x1) m / sin α."""
    r1 = z1 * M / 2
    rb1, ra1 = r1 * math.cos(ALPHA), r1 + M * (ha1 + x1)
    g = math.sqrt(ra1**2 - rb1**2) - rb1 * math.tan(ALPHA) + (ha2 - x1) * M / math.sin(ALPHA)
    return g / (math.pi * M * math.cos(ALPHA))


def test_large_tooth_count_difference_tends_to_the_rack():
    rack = _rack_contact_ratio(20, 0.3)
    err = []
    for z2 in (-500, -2000):
        p = _pair(20, z2, 0.3, 0.2)
        e = jg.GearPair(
            jg.Member(20, 0.3, face_width=0.02), jg.Member(-z2, -0.2, face_width=0.02), M, ALPHA
        )
        err.append(abs(p.transverse_contact_ratio - rack))
        # external and internal gears approach the rack from the two sides
        assert (p.transverse_contact_ratio - rack) * (e.transverse_contact_ratio - rack) < 0
        # α_wt − α = 2 (x1 + x2)/((z1 + z2) tan α) to first order in 1/|z2|
        first = 2 * (0.3 + 0.2) / ((20 + z2) * math.tan(ALPHA))
        assert p.operating_pressure_angle - ALPHA == pytest.approx(first, rel=0.02)
    assert err[1] < 4e-3 and 3.5 < err[0] / err[1] < 4.5  # first order in 1/|z2|
    # the quasi-static TE (ISO 6336 stiffness) of the internal pair and of the external one
    # agree at |z2| = 2000 (ring unshifted: ISO's q' keeps its x2 terms at z_n2 = ∞)
    ext = jg.GearPair(
        jg.Member(20, 0.3, face_width=0.02), jg.Member(2000, face_width=0.02), M, ALPHA
    )
    tes = []
    for pair in (_pair(20, -2000, 0.3, 0.0), ext):
        s, k = jg.stiffness_table(pair, jg.ISO6336())
        mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=2)
        tes.append(
            np.asarray(
                jg.quasi_static(mesh, None, 100.0, positions_per_pitch=32).transmission_error
            )
        )
    assert abs(tes[0].mean() / tes[1].mean() - 1) < 5e-3


def test_iso6336_single_stiffness_with_the_internal_gear_rule():
    p = _pair(17, -56, 0.3, -0.3)
    # ISO 6336-1 method B, q' with z_n2 infinite (C3/z_n2 = C7 x2/z_n2 = 0), spur, solid blanks
    c = (0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529, 0.00182)
    x1, x2, zn1 = 0.3, -0.3, 17.0
    q = c[0] + c[1] / zn1 + c[3] * x1 + c[4] * x1 / zn1 + c[5] * x2 + c[7] * x1**2 + c[8] * x2**2
    cb = 1 + 0.5 * (1.2 - 1.25)  # C_B with h_fP/m_n = 1.25, α_n = 20°
    c_single = 1 / q * 0.8 * cb * 1e9  # N/m²
    assert jg.iso6336_single_stiffness(p) == pytest.approx(c_single, rel=1e-13)
    c_mesh = c_single * (0.75 * p.transverse_contact_ratio + 0.25)
    assert jg.iso6336_mesh_stiffness(p) == pytest.approx(c_mesh, rel=1e-13)
    _, k = jg.stiffness_table(p, jg.ISO6336(), youngs_modulus=206e9)
    np.testing.assert_allclose(k, c_mesh / p.transverse_contact_ratio, rtol=1e-13)
    # Weber needs the ring's cutter for an internal pair (tests/test_weber_internal.py)
    with pytest.raises(ValueError, match="ring_cutter = None is out of range for an InternalGearPair"):
        jg.stiffness_table(p, jg.Weber())
    # a model without an internal-gear form (a user's, internal_teeth False) is refused
    class ExternalOnly(jg.AbstractStiffness):
        name: ClassVar[str] = "external-only"

        def profile(self, pair, s, conditions):
            return np.full_like(s, 1e10)

    with pytest.raises(ValueError, match="model = 'external-only' is out of range for an Internal"):
        jg.stiffness_table(p, ExternalOnly())


def test_hertz_pressure_on_the_concave_flank_against_iso6336_2():
    p = _pair(17, -56, 0.3, -0.3)
    E, nu, b = 206e9, 0.3, p.face_width
    ft = 4000.0  # N, tangential at the reference circle
    awt, at = p.operating_pressure_angle, p.transverse_pressure_angle
    # the pitch point in single contact: the normal load F_t/cos α_t over the face width b
    w = ft / (b * math.cos(at))
    s_c = p.base_radii[0] * math.tan(awt) - p.start_roll
    res = types.SimpleNamespace(
        line_load=jnp.array([[[w]]]), cell_s=jnp.array([[[s_c]]]), cell_mask=jnp.array([[[True]]])
    )
    p0 = float(jg.contact_pressure(p, res, E, nu).max_pressure[0, 0, 0])
    u = p.gear.teeth / p.pinion.teeth  # < 0 for an internal pair (ISO 6336-2)
    zh = math.sqrt(2 * math.cos(awt) / (math.cos(at) ** 2 * math.sin(awt)))
    ze = math.sqrt(E / (2 * math.pi * (1 - nu**2)))
    d1 = 2 * p.pitch_radii[0]
    sigma = zh * ze * math.sqrt(ft / (d1 * b) * (u + 1) / u)
    assert p0 == pytest.approx(sigma, rel=1e-12)
    # the concave ring flank lowers the pressure below the external pair's (convex) one
    assert (u + 1) / u < (-u + 1) / -u


def test_contact_pressure_of_an_internal_quasi_static_result():
    p = _pair(17, -56, 0.3, -0.3)
    s, k = jg.stiffness_table(p, jg.ISO6336())
    res = jg.quasi_static(
        jg.MeshModel.from_pair(p, s, k, n_slices=2), None, 200.0, positions_per_pitch=32
    )
    cp = jg.contact_pressure(p, res, 206e9, 0.3)
    loaded = np.asarray(res.line_load) > 0
    assert loaded.any() and np.all(np.asarray(cp.max_pressure)[loaded] > 0)
    # R = ρ1 ρ2 / (ρ2 − ρ1): the ring's radius of curvature from its own circle, ρ2 = √(r² − r_b2²)
    sc = np.asarray(res.cell_s)[loaded]
    rho1 = p.start_roll + sc
    r_contact = np.hypot(
        rho1 + p.center_distance * math.sin(p.operating_pressure_angle), p.base_radii[1]
    )
    rho2 = np.sqrt(r_contact**2 - p.base_radii[1] ** 2)
    R = rho1 * rho2 / (rho2 - rho1)
    e_star = jg.contact_modulus(206e9, 0.3)
    w = np.asarray(res.line_load)[loaded]
    np.testing.assert_allclose(
        np.asarray(cp.max_pressure)[loaded], np.sqrt(w * e_star / (np.pi * R)), rtol=1e-10
    )


# NREL 5 MW reference gearbox, planetary stages 1 and 2 (Nejad, Guo, Gao, Moan, Wind Energy 19
# (2016) 1089-1106, doi:10.1002/we.1884, Table V; as carried by gfsReboucas/Drivetrain-python,
# drivetrain/models/nrel_5mw.py): m_n, face width, a_w, z (sun, planet, ring), x (ISO signs)
NREL_STAGES = [
    (45e-3, 0.491, 0.863, (19, 17, -56), (0.617, 0.802, -0.501)),
    (21e-3, 0.550, 0.584, (18, 36, -93), (0.389, 0.504, 0.117)),
]


@pytest.mark.parametrize("mn, b, aw, z, x", NREL_STAGES)
def test_nrel_5mw_planetary_stages_are_concentric_at_the_published_distance(mn, b, aw, z, x):
    """The published shifts make both meshes of each stage zero-backlash at the published centre
    distance (rounded to 1 mm): the sun pair's and the ring pair's zero-backlash distances agree
    to 5 µm and lie within 0.01 mm of a_w. Read with the opposite (textbook) sign of the ring's
    shift, stage 1 is refused and stage 2 lands 5.9 mm off. With 0.1 mm thinned teeth the stage
    assembles at a_w with backlash in both meshes."""
    members = [jg.Member(zi, xi, face_width=b) for zi, xi in zip(z, x)]
    ext = jg.GearPair(members[0], members[1], mn, ALPHA)
    ring = jg.InternalGearPair(members[1], members[2], mn, ALPHA)
    assert abs(ring.center_distance - ext.center_distance) < 5e-6
    assert abs(ring.center_distance - aw) < 1e-5 and abs(ext.center_distance - aw) < 1e-5
    # the ring's tip and root diameters (ISO: d_a2 = |d2| − 2 m_n (1 + x2), d_f2 = |d2| +
    # 2 m_n (1.25 − x2)); stage 1: 2475.09 and 2677.59 mm
    d2 = -z[2] * mn
    assert 2 * ring.tip_radii[1] == pytest.approx(d2 - 2 * mn * (1 + x[2]), rel=1e-14)
    assert 2 * ring.root_radii[1] == pytest.approx(d2 + 2 * mn * (1.25 - x[2]), rel=1e-14)
    flipped = jg.Member(z[2], -x[2], face_width=b)
    if x[2] < 0:
        with pytest.raises(ValueError, match="profile_shift"):
            jg.InternalGearPair(members[1], flipped, mn, ALPHA)
    else:
        assert jg.InternalGearPair(members[1], flipped, mn, ALPHA).center_distance - aw > 5e-3
    thin = [
        jg.Member(zi, xi, face_width=b, tooth_thickness_allowance=-0.1e-3) for zi, xi in zip(z, x)
    ]
    g = jg.planetary_geometry(*thin, mn, ALPHA, center_distance=aw)
    assert g.sun_planet.normal_backlash > 0.1e-3 and g.planet_ring.normal_backlash > 0.1e-3


def test_planetary_geometry_at_one_centre_distance():
    # a concentric tooth set z_r = z_s + 2 z_p: both zero-backlash distances agree when the
    # ring's shift is x_r = −(x_s + 2 x_p) (ISO sign; the inv α_wt of both pairs coincide)
    sun, planet = jg.Member(19, 0.3, face_width=0.02), jg.Member(17, 0.3, face_width=0.02)
    g = jg.planetary_geometry(sun, planet, jg.Member(-53, -0.9, face_width=0.02), M, ALPHA)
    assert abs(g.mismatch) < 1e-15
    assert g.sun_pressure_angle == pytest.approx(g.ring_pressure_angle, rel=1e-12)
    assert abs(g.sun_planet.normal_backlash) < 1e-15
    assert abs(g.planet_ring.normal_backlash) < 1e-15
    # thinner ring teeth: the ring pair's zero-backlash distance is larger; at the sun pair's
    # the ring pair has backlash
    g = jg.planetary_geometry(sun, planet, jg.Member(-53, -1.0, face_width=0.02), M, ALPHA)
    assert g.mismatch > 0 and g.center_distance == g.sun_planet.center_distance
    rb = (19 * M / 2 * math.cos(ALPHA), 17 * M / 2 * math.cos(ALPHA), 53 * M / 2 * math.cos(ALPHA))
    assert math.cos(g.sun_pressure_angle) == pytest.approx((rb[0] + rb[1]) / g.center_distance)
    assert math.cos(g.ring_pressure_angle) == pytest.approx((rb[2] - rb[1]) / g.center_distance)
    assert g.planet_ring.normal_backlash > 0 and abs(g.sun_planet.normal_backlash) < 1e-15
    # thicker ring teeth: no common distance (one mesh jams)
    with pytest.raises(ValueError, match="ring.profile_shift = -0.8 is out of range"):
        jg.planetary_geometry(sun, planet, jg.Member(-53, -0.8, face_width=0.02), M, ALPHA)
    with pytest.raises(ValueError, match="total contact ratio"):  # far from concentric
        jg.planetary_geometry(sun, planet, jg.Member(-56, -0.3, face_width=0.02), M, ALPHA)


def test_ring_tip_relief_acts_at_the_start_of_contact():
    """A linear tip relief on the ring (the ``gear`` member) opens the flanks near s = 0, where
    the ring's tip meets the pinion: each cell's separation is the relief depth times the ramp
    (1 − s/(extent g_α))₊, less its smallest value on the flanks (δ0 = max e − e)."""
    pair = _pair()
    s, k = jg.stiffness_table(pair, jg.Uniform(1.2e10))
    mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=2)
    depth, extent = 10e-6, 0.3
    mods = jg.Modifications(
        gear=jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=extent)
    )
    separation = eqx.filter_jit(jg.separation)  # one compilation (eager: ~5x slower)
    for frac in (0.13, 0.35):
        cells, _, delta0 = separation(mesh, mods, jnp.asarray(frac * float(mesh.mesh_period_angle)))
        mask = np.asarray(cells.mask)
        relief = np.clip(1 - np.asarray(cells.s) / (extent * pair.path_of_contact), 0, None) * depth
        expected = np.where(mask, relief - relief[mask].min(), 0.0)  # e = −relief
        np.testing.assert_allclose(np.asarray(delta0), expected, atol=1e-15)
        assert expected.max() > 1e-6  # a relieved cell at each position


def test_internal_mesh_runs_in_float32():
    """With x64 off, the quasi-static TE of the internal mesh is float32 and matches the
    rigid-tooth count F_n/(k0 b n(θ)) to float32 accuracy."""
    pair = _pair()
    k0, torque = 1.2e10, 150.0
    with jax.enable_x64(False):
        s, k = jg.stiffness_table(pair, jg.Uniform(k0))
        mesh = jg.MeshModel.from_pair(pair, s, k, n_slices=2)
        res = jg.quasi_static(mesh, None, torque, positions_per_pitch=8)
        te, theta = np.asarray(res.transmission_error), np.asarray(res.theta)
    assert te.dtype == np.float32
    fn = torque / pair.base_radii[0]
    expected = [fn / (k0 * pair.face_width * _lines_count(pair, float(t))) for t in theta]
    np.testing.assert_allclose(te, expected, rtol=1e-5)
