"""Exact rack-generated tooth form (fem_prep.tooth_form) and its use in the Weber stiffness.

Independent references written here, not taken from the module:

* the fillet as the offset by ρ_fP of the path of the rack tip-rounding centre (the trochoid,
  Litvin & Fuentes ch. 10), placed with ISO 6336-3:2006 (20)-(21) E and G; for helical gears the
  envelope of the transverse rack's elliptical rounding found by a brute-force minimisation;
* the involute ψ(r) = s_t/(2r) + inv α_t − inv α_r (ISO 21771) and s_t = m_n (π/2 + 2x tan α_n)/cos β;
* ISO 6336-3 method B: θ iterated from (23), s_Fn (17), ρ_F (19) and the fillet part of h_Fe (18)
  at the 30° tangent, compared with the chord read off the outline;
* per-member foundation: the series combination of the member compliances;
* Weber's cantilever (the thesis's (1.2)) integrated on the generated tooth, against the model's
  member compliance.
"""

import ast
import math
import pathlib

import numpy as np
import pytest
from scipy.optimize import brentq, minimize_scalar

import jaxgear as jg
import jaxgear.io as jio
from fem_prep.tooth_form import ToothForm, ToothGeometry, generate_tooth

ROOT = pathlib.Path(__file__).resolve().parents[1]
DEG = math.pi / 180

# (z, x, h_fP/m_n, ρ_fP/m_n, α_n deg): the accessory pair's members, a standard 20° rack with a
# full-ish rounding, a negative shift, a sharp rack corner (ρ = 0: the corner's own trochoid)
SPUR = [
    (45, 0.341, 1.1933, 0.25, 25.0),
    (86, 0.481, 1.1933, 0.25, 25.0),
    (20, 0.2, 1.25, 0.38, 20.0),
    (30, -0.2, 1.25, 0.3, 20.0),
    (40, 0.0, 1.25, 0.0, 20.0),
]


def _inv(a):
    return np.tan(a) - a


def _spur(z, x, hf, rc, an_deg, m=2e-3, **kw):
    return generate_tooth(ToothGeometry(z, m, an_deg * DEG, 0.0, x, 1.0, hf, rc), **kw)


def _iso_e_g(x, hf, rc, an):
    """ISO 6336-3 (20), (21) per unit module, no protuberance: E = distance of the rack's tip
    rounding centre from the rack tooth's centre line, G = its height above the rolling line."""
    e = math.pi / 4 - hf * math.tan(an) - (1 - math.sin(an)) * rc / math.cos(an)
    return e, rc - hf + x


def _centre_path(z, m, x, hf, rc, an):
    """Path C(φ) of the rack rounding centre in the gear frame (tooth centre line +y) and C'(φ):
    the rack rolls on the reference circle; at φ the rolling line touches it at angle φ."""
    r = z * m / 2
    e, g = _iso_e_g(x, hf, rc, an)
    xi, eta = (math.pi / 2 - e) * m, g * m  # from the gear tooth centre line / rolling line

    def c(phi):
        ur, ut = np.array([np.sin(phi), np.cos(phi)]), np.array([np.cos(phi), -np.sin(phi)])
        return (r + eta) * ur + (xi - r * phi) * ut

    def dc(phi):
        ur = np.array([np.sin(phi), np.cos(phi)])
        ut = np.array([np.cos(phi), -np.sin(phi)])
        return eta * ut - (xi - r * phi) * ur  # (r+η) ut − r ut − (ξ − rφ) ur

    return c, dc, xi / r


@pytest.mark.parametrize("z, x, hf, rc, an", SPUR)
def test_spur_fillet_is_the_offset_of_the_rounding_centre_trochoid(z, x, hf, rc, an):
    m = 2e-3
    form = _spur(z, x, hf, rc, an, m=m, n_fillet=60)
    c, dc, phi_root = _centre_path(z, m, x, hf, rc, an * DEG)
    rho = rc * m
    pts = form.fillet  # right flank, root junction → form point
    # the root junction: C(φ_root) straight above it, ρ away, on the root circle
    assert form.root_half_angle == pytest.approx(phi_root, rel=1e-13)
    np.testing.assert_allclose(pts[0], c(phi_root) * (1 - rho / np.hypot(*c(phi_root))), atol=1e-15)
    # every fillet point: foot of the perpendicular on C at distance ρ, on the tooth's side
    grid = phi_root + np.linspace(-0.01, 0.3, 3101)
    path = np.array([c(p) for p in grid])
    phis = []
    for y in pts:
        j = int(np.argmin(np.hypot(*(path - y).T)))
        foot = lambda p, y=y: float(np.dot(y - c(p), dc(p)))
        phi = brentq(foot, grid[j - 1], grid[j + 1], xtol=1e-15)
        if rc == 0:  # sharp rack corner: the fillet is the corner's own path C(φ)
            np.testing.assert_allclose(y, c(phi), rtol=0, atol=1e-12 * m)
        else:
            assert np.hypot(*(y - c(phi))) == pytest.approx(rho, rel=1e-9)
            assert np.hypot(*y) < np.hypot(*c(phi))  # towards the gear centre (the tooth)
        phis.append(phi)
    assert phis[0] == pytest.approx(phi_root, abs=1e-12)
    assert np.all(np.diff(phis) > 0)  # the rack rolls on as the fillet climbs
    # the radius grows monotonically from r_f to r_F (no undercut)
    rr = np.hypot(pts[:, 0], pts[:, 1])
    assert rr[0] == pytest.approx(form.root_radius, rel=1e-14)
    assert rr[-1] == pytest.approx(form.form_radius, rel=1e-12)
    assert np.all(np.diff(rr) > 0)


def test_root_half_angle_closed_form():
    """θ_f = (π/2 + 2 tan α_n (h_fP* − ρ*) + 2 ρ*/cos α_n) / z for spur gears, independent of x
    (the form used by ROSS's GearElementTVMS)."""
    for z, x, hf, rc, an in SPUR:
        a = an * DEG
        ref = (math.pi / 2 + 2 * math.tan(a) * (hf - rc) + 2 * rc / math.cos(a)) / z
        assert _spur(z, x, hf, rc, an).root_half_angle == pytest.approx(ref, rel=1e-13)


def _rack_ellipse_gap(y, z, mn, an, beta, x, hf, rc):
    """min over the rolling angle φ of the transverse rack rounding's implicit function at the
    gear point y, f = ((ξ−ξ_c) cos β)² + (η−η_c)² − ρ² (ξ, η: y in rack coordinates): 0 on the
    envelope, > 0 outside every position of the rounding. Built from the normal rack (ISO 53):
    its rounding circle is the ellipse in the transverse section."""
    cb = math.cos(beta)
    r = z * mn / cb / 2
    e, g = _iso_e_g(x, hf, rc, an)
    xi_c = (math.pi / 2 - e) * mn / cb  # tangential distances scale by 1/cos β
    eta_c, rho = g * mn, rc * mn

    def f(phi):
        ur = np.array([math.sin(phi), math.cos(phi)])
        ut = np.array([math.cos(phi), -math.sin(phi)])
        eta = float(np.dot(y, ur)) - r
        xi = float(np.dot(y, ut)) + r * phi
        return ((xi - xi_c) * cb) ** 2 + (eta - eta_c) ** 2 - rho**2

    phi0 = xi_c / r
    res = minimize_scalar(
        f, bounds=(phi0 - 0.5, phi0 + 0.5), method="bounded", options={"xatol": 1e-14}
    )
    return res.fun / rho**2


@pytest.mark.parametrize("name", ["power-helical", "accessory-spur"])
def test_helical_fillet_is_the_envelope_of_the_transverse_rack_rounding(name):
    pair = jio.load_case(name).pair
    for member in (pair.pinion, pair.gear):
        args = (
            member.teeth,
            pair.normal_module,
            pair.normal_pressure_angle,
            pair.helix_angle,
            member.profile_shift,
            member.dedendum_coeff,
            member.fillet_radius_coeff,
        )
        geometry = ToothGeometry(*args[:5], member.addendum_coeff, *args[5:])
        form = generate_tooth(geometry, n_fillet=12)
        gaps = [_rack_ellipse_gap(y, *args) for y in form.fillet]
        np.testing.assert_allclose(gaps, 0.0, atol=1e-9)


@pytest.mark.parametrize("name", ["accessory-spur", "power-helical"])
def test_radii_and_form_circle_agree_with_gear_pair(name):
    """r_f, r_a, r_b, r and the form circle (ISO 21771 (88)-(90), ``GearPair.form_roll``) of
    the tooth generated from the pair's :func:`jaxgear.tooth_geometry` as the Weber model
    generates it (200 fillet points per flank), and the root angle θ_f the Sainsot foundation
    reads (:func:`jaxgear.sainsot_fit_check`) is its root half angle."""
    pair = jio.load_case(name).pair
    theta_f = [m["theta_f"] for m in jg.sainsot_fit_check(pair)]
    for i, member in enumerate((pair.pinion, pair.gear)):
        form = generate_tooth(jg.tooth_geometry(pair, i), n_fillet=200, n_involute=2, n_tip=0)
        assert form.root_radius == pytest.approx(pair.root_radii[i], rel=1e-14)
        assert form.tip_radius == pytest.approx(pair.tip_radii[i], rel=1e-14)
        assert form.base_radius == pytest.approx(pair.base_radii[i], rel=1e-14)
        assert form.pitch_radius == pytest.approx(pair.pitch_radii[i], rel=1e-14)
        ref = math.hypot(pair.form_roll[i], pair.base_radii[i])
        assert form.form_radius == pytest.approx(ref, rel=1e-14)
        assert theta_f[i] == form.root_half_angle
        # the generated form point is on the involute (the rounding meets the straight flank)
        pt = form.fillet[-1]
        assert np.hypot(*pt) == pytest.approx(ref, rel=1e-13)


@pytest.mark.parametrize(
    "z, mn, an, beta, x, ha",
    [
        (45, 1.5e-3, 25.0, 0.0, 0.341, 0.9447),
        (35, 2.5e-3, 25.0, 12.0, 0.275, 0.976),
        (24, 3e-3, 20.0, 30.0, -0.1, 1.0),
    ],
)
def test_involute_points_and_reference_thickness(z, mn, an, beta, x, ha):
    form = generate_tooth(ToothGeometry(z, mn, an * DEG, beta * DEG, x, ha, 1.25, 0.25))
    s_t = mn * (math.pi / 2 + 2 * x * math.tan(an * DEG)) / math.cos(beta * DEG)
    at = math.atan(math.tan(an * DEG) / math.cos(beta * DEG))
    r = z * mn / math.cos(beta * DEG) / 2
    rb = r * math.cos(at)
    pts = form.outline[form.segments == 2]
    rr = np.hypot(pts[:, 0], pts[:, 1])
    psi = s_t / (2 * r) + _inv(at) - _inv(np.arccos(rb / rr))
    np.testing.assert_allclose(np.abs(pts[:, 0]), rr * np.sin(psi), rtol=1e-12, atol=0)
    np.testing.assert_allclose(pts[:, 1], rr * np.cos(psi), rtol=1e-12, atol=0)
    # arc thickness at the reference circle from the half chord
    s_ref = 2 * r * math.asin(float(form.half_thickness(r)) / r)
    assert s_ref == pytest.approx(s_t, rel=1e-9)
    assert 2 * r * float(form.involute_half_angle(r)) == pytest.approx(s_t, rel=1e-12)
    assert rr.min() == pytest.approx(form.form_radius, rel=1e-14)
    assert rr.max() == pytest.approx(r + mn * (ha + x), rel=1e-14)


def test_outline_layout():
    n_f, n_i, n_t = 17, 23, 5
    form = _spur(45, 0.341, 1.1933, 0.25, 25.0, n_fillet=n_f, n_involute=n_i, n_tip=n_t)
    assert isinstance(form, ToothForm)
    out, seg = form.outline, form.segments
    assert out.shape == (2 * (n_f + n_i) + n_t, 2) and seg.shape == (out.shape[0],)
    half = n_f + n_i
    expected = [0] + [1] * (n_f - 1) + [2] * n_i
    assert seg.tolist() == expected + [3] * n_t + expected[::-1]
    # starts on the root circle at −θ_f, ends at +θ_f; mirror image about the centre line
    th = form.root_half_angle
    rf = form.root_radius
    np.testing.assert_allclose(out[0], [-rf * math.sin(th), rf * math.cos(th)], rtol=1e-14)
    np.testing.assert_allclose(out[-1], [rf * math.sin(th), rf * math.cos(th)], rtol=1e-14)
    np.testing.assert_allclose(out[::-1] * [-1, 1], out, atol=1e-18)
    # ordered along the curve: radius up the left flank, down the right one; no duplicates
    d = np.hypot(*np.diff(out, axis=0).T)
    assert d.min() > 1e-4 * d.max()  # no duplicate points
    r = np.hypot(out[:, 0], out[:, 1])
    assert np.all(np.diff(r[:half]) > 0) and np.all(np.diff(r[-half:]) < 0)
    np.testing.assert_allclose(r[seg == 3], form.tip_radius, rtol=1e-14)
    # left flank up, tip left → right, right flank down: clockwise (negative signed area)
    area = 0.5 * np.sum(out[:-1, 0] * out[1:, 1] - out[1:, 0] * out[:-1, 1])
    assert area < 0
    assert not out.flags.writeable


def _chord_angle(a, b, c):
    u, v = b - a, c - b
    return abs(math.atan2(u[0] * v[1] - u[1] * v[0], float(np.dot(u, v))))


def test_tangency_at_root_and_tangent_continuity_at_the_form_point():
    """The fillet leaves the root circle tangentially, and meets the involute with a continuous
    tangent (not undercut): the discrete kink angles vanish under refinement (first order at the
    root, where the chord of a tangent curve makes an angle O(h); the same at the form point)."""
    kinks_root, kinks_form = [], []
    for n in (20, 40, 80, 160):
        form = _spur(20, 0.2, 1.25, 0.38, 20.0, n_fillet=n, n_involute=n)
        p = form.outline
        th = form.root_half_angle
        tangent_root = np.array([math.cos(th), math.sin(th)])  # circle's tangent at −θ_f, up
        chord = (p[1] - p[0]) / np.hypot(*(p[1] - p[0]))
        kinks_root.append(math.acos(min(float(np.dot(chord, tangent_root)), 1.0)))
        i = n  # the form point (first involute point on the left flank)
        assert form.segments[i] == 2 and form.segments[i - 1] == 1
        kinks_form.append(_chord_angle(p[i - 1], p[i], p[i + 1]))
    kinks_root, kinks_form = np.array(kinks_root), np.array(kinks_form)
    assert np.all(kinks_root[1:] / kinks_root[:-1] < 0.55)
    assert np.all(kinks_form[1:] / kinks_form[:-1] < 0.55)
    assert kinks_root[-1] < 2e-2 and kinks_form[-1] < 5e-3


def test_tangent_continuity_exact_at_the_form_point():
    """The trochoid's tangent at the form point (C'(φ_F) of the independent centre path) is the
    involute's tangent there (perpendicular to the line to the base circle's tangent point)."""
    z, x, hf, rc, an, m = 45, 0.341, 1.1933, 0.25, 25.0, 2e-3
    form = _spur(z, x, hf, rc, an, m=m)
    c, dc, phi_root = _centre_path(z, m, x, hf, rc, an * DEG)
    y = form.fillet[-1]
    grid = phi_root + np.linspace(0.0, 0.3, 3001)
    j = int(np.argmin([np.hypot(*(c(p) - y)) for p in grid]))
    phi = brentq(lambda p: float(np.dot(y - c(p), dc(p))), grid[j - 1], grid[j + 1], xtol=1e-15)
    t_fillet = dc(phi) / np.hypot(*dc(phi))
    rb = form.base_radius
    r = np.hypot(*y)
    # involute tangent: its normal touches the base circle, so the tangent makes the pressure
    # angle α_r = acos(r_b/r) with the radius, turned towards the centre line (ψ falls with r)
    ang = math.atan2(y[0], y[1])  # polar angle from +y
    alpha = math.acos(rb / r)
    t_inv = np.array([math.sin(ang - alpha), math.cos(ang - alpha)])
    assert float(np.dot(t_fillet, t_inv)) > 0
    cross = t_fillet[0] * t_inv[1] - t_fillet[1] * t_inv[0]
    assert abs(cross) < 1e-9


def _iso_30_degree(z, x, hf, rc, an):
    """ISO 6336-3:2006 method B (spur, external, no protuberance), per unit module: θ from (23)
    by fixed-point iteration, s_Fn (17), ρ_F (19), and the height above the gear centre of the
    30° tangent point, the fillet part of h_Fe (18): 0.5 z cos(π/3 − θ) + 0.5 (G/cos θ − ρ*)."""
    e, g = _iso_e_g(x, hf, rc, an)
    h = 2 / z * (math.pi / 2 - e) - math.pi / 3
    th = math.pi / 6
    for _ in range(200):
        th = 2 * g / z * math.tan(th) - h
    s_fn = z * math.sin(math.pi / 3 - th) + math.sqrt(3) * (g / math.cos(th) - rc)
    rho_f = rc + 2 * g**2 / (math.cos(th) * (z * math.cos(th) ** 2 - 2 * g))
    y30 = 0.5 * z * math.cos(math.pi / 3 - th) + 0.5 * (g / math.cos(th) - rc)
    return s_fn, rho_f, y30


@pytest.mark.parametrize("z, x, hf, rc, an", [s for s in SPUR if s[3] > 0])
def test_iso6336_3_root_chord_at_the_30_degree_tangent(z, x, hf, rc, an):
    """The chord between the points where the 30° tangents touch the fillets (s_Fn), the fillet
    radius there (ρ_F) and their height, read off a fine outline (m_n = 1)."""
    form = _spur(z, x, hf, rc, an, m=1.0, n_fillet=4000)
    p = form.fillet
    d = np.gradient(p, axis=0)
    dd = np.gradient(d, axis=0)
    incl = -np.degrees(np.arctan2(d[:, 0], d[:, 1]))  # tangent's angle to the centre line
    i = int(np.nonzero(np.diff(np.sign(incl - 30.0)))[0][0])
    w = (30.0 - incl[i]) / (incl[i + 1] - incl[i])
    pt = p[i] + w * (p[i + 1] - p[i])
    kappa = (d[:, 0] * dd[:, 1] - d[:, 1] * dd[:, 0]) / np.hypot(d[:, 0], d[:, 1]) ** 3
    s_fn, rho_f, y30 = _iso_30_degree(z, x, hf, rc, an * DEG)
    assert 2 * pt[0] == pytest.approx(s_fn, rel=1e-6)
    assert pt[1] == pytest.approx(y30, rel=1e-6)
    assert 1 / abs(kappa[i] + w * (kappa[i + 1] - kappa[i])) == pytest.approx(rho_f, rel=1e-3)
    # the half thickness at that radius is the same point
    assert float(form.half_thickness(np.hypot(*pt))) == pytest.approx(pt[0], rel=1e-6)


def test_half_thickness_down_the_fillet_converges_second_order():
    """``half_thickness`` interpolates between the outline's fillet points (linearly in
    √(r − r_f)); against the exact trochoid (n = 20 000) the error falls ≈ 4× per doubling."""
    args = (20, 0.2, 1.25, 0.38, 20.0)
    ref = _spur(*args, n_fillet=20000)
    r = np.linspace(ref.root_radius, ref.form_radius, 1001)
    errs = [
        np.max(np.abs(_spur(*args, n_fillet=n).half_thickness(r) - ref.half_thickness(r)))
        for n in (10, 20, 40, 80)
    ]
    rates = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(rates > 1.7), rates
    # at the junctions, the exact values
    assert float(ref.half_thickness(ref.root_radius)) == pytest.approx(
        ref.root_radius * math.sin(ref.root_half_angle), rel=1e-14
    )
    with pytest.raises(ValueError, match=r"half_thickness: radius .* is out of range"):
        ref.half_thickness(ref.root_radius * 0.99)


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"teeth": 4}, r"^teeth = 4 is out of range: allowed an integer >= 5$"),
        ({"normal_module": 0.0}, r"^normal_module = 0.0 is out of range"),
        (
            {"fillet_radius_coeff": 0.6},
            r"^fillet_radius_coeff = 0.6 is out of range: allowed \[0, ",
        ),
        ({"fillet_radius_coeff": -0.1}, r"^fillet_radius_coeff = -0.1 is out of range"),
        ({"teeth": 10, "profile_shift": 0.0}, r"^profile_shift \(undercut: form circle roll"),
        ({"addendum_coeff": 2.0}, r"^addendum_coeff \(tip thickness .*: pointed tooth\)"),
        ({"n_fillet": 1}, r"^n_fillet = 1 is out of range: allowed an integer >= 2$"),
        ({"dedendum_coeff": 12.0}, r"^dedendum_coeff \(root radius"),
    ],
)
def test_validation_messages(kwargs, match):
    args = {
        "teeth": 20,
        "normal_module": 2e-3,
        "normal_pressure_angle": 20 * DEG,
        "helix_angle": 0.0,
        "profile_shift": 0.2,
        "addendum_coeff": 1.0,
        "dedendum_coeff": 1.25,
        "fillet_radius_coeff": 0.38,
    }
    args.update(kwargs)
    n_fillet = args.pop("n_fillet", 40)
    with pytest.raises(ValueError, match=match) as info:
        generate_tooth(ToothGeometry(**args), n_fillet=n_fillet)
    assert "\n" not in str(info.value)


def _imports(name):
    tree = ast.parse((ROOT / "fem_prep" / name).read_text(encoding="utf-8"))
    mods = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            mods |= {a.name.split(".")[0] for a in node.names}
        elif isinstance(node, ast.ImportFrom):
            mods.add("." * node.level + (node.module or "").split(".")[0])
    return mods


def test_module_imports_numpy_only():
    """The tooth form and its involute function (fem_prep.involute, the one home of both
    packages') need NumPy at most: no JAX, no SciPy."""
    assert _imports("tooth_form.py") <= {"__future__", "math", "dataclasses", "numpy", ".involute"}
    assert _imports("involute.py") <= {"__future__", "math"}


# ---------------------------------------------------------------------------------------------
# the Weber model on the exact tooth


def _old_circular_arc_thickness(pair, member, r):
    """The circular-arc fillet this replaced: an arc of radius min(ρ_fP, r_F − r_f) tangent to
    the root circle, added to the involute thickness continued below the form circle."""
    rb, rf = pair.base_radii[member], pair.root_radii[member]
    r_form = max(math.hypot(pair.form_roll[member], rb), rb)
    r = np.asarray(r, dtype=float)
    r_inv = np.maximum(r, r_form)
    # the involute's half angle ψ(r) = s_t/(2 r_p) + inv α_t − inv α_r (ISO 21771; s_t the
    # transverse tooth thickness on the pitch circle r_p, cos α_r = r_b/r)
    alpha_r = np.arccos(np.clip(rb / r_inv, -1.0, 1.0))
    alpha_t = pair.transverse_pressure_angle
    psi = (
        pair.reference_thickness[member] / (2 * pair.pitch_radii[member])
        + (math.tan(alpha_t) - alpha_t)
        - (np.tan(alpha_r) - alpha_r)
    )
    half = r_inv * np.sin(psi)
    m = (pair.pinion, pair.gear)[member]
    rho = min(m.fillet_radius_coeff * pair.normal_module, max(r_form - rf, 0.0))
    t = np.clip(r - rf, 0.0, rho)
    arc = rho - np.sqrt(np.maximum(rho**2 - (rho - t) ** 2, 0.0))
    return 2 * (half + np.where(r < rf + rho, arc, 0.0))


def _involute_thickness(pair, member, r):
    """2 r sin ψ(r), ψ(r) = s_t/(2 r_p) + inv α_t − inv α_r (ISO 21771; cos α_r = r_b/r)."""
    rb = pair.base_radii[member]
    alpha_r = np.arccos(np.clip(rb / r, -1.0, 1.0))
    alpha_t = pair.transverse_pressure_angle
    psi = pair.reference_thickness[member] / (2 * pair.pitch_radii[member]) + _inv(alpha_t)
    return 2 * r * np.sin(psi - _inv(alpha_r))


def _generated_thickness(pair, member, n_fillet):
    """d(r): the involute above the form circle, the rack-generated fillet of ``n_fillet``
    points per flank (fem_prep.generate_tooth) below it."""
    form = generate_tooth(jg.tooth_geometry(pair, member), n_fillet=n_fillet, n_involute=2,
                          n_tip=0)

    def d(r):
        r_inv = np.maximum(r, form.form_radius)
        below = np.clip(r, form.root_radius, form.form_radius)
        return np.where(r >= form.form_radius, _involute_thickness(pair, member, r_inv),
                        2 * form.half_thickness(below))

    return d


def _weber_tooth(pair, member, rho, E, nu, thickness, n=400):
    """Weber's cantilever (the thesis's (1.2)), written here: a tooth of unit width loaded at
    the roll distance ρ, at α_p = α_r − ψ to the centre line's normal where the line of action
    crosses the centre line (r_b/cos α_p, u from the root circle): cos²α_p/E [12 (1 − ν²)
    ∫ (u − y)²/d³ dy + (2.4 (1 + ν) + (1 − ν²) tan²α_p) ∫ dy/d] over y in [0, u]
    (Gauss–Legendre), d(r_f + y) = ``thickness``. (m/N)·m."""
    rb, rf = pair.base_radii[member], pair.root_radii[member]
    rc = np.hypot(rho, rb)
    half_angle = np.arcsin(_involute_thickness(pair, member, rc) / (2 * rc))
    alpha_p = np.arctan2(rho, rb) - half_angle
    u = rb / np.cos(alpha_p) - rf
    x, w = np.polynomial.legendre.leggauss(n)
    y = 0.5 * (x[None, :] + 1) * u[:, None]
    w = 0.5 * w[None, :] * u[:, None]
    d = thickness(rf + y)
    bend = np.sum(w * (u[:, None] - y) ** 2 / d**3, axis=1)
    shear = np.sum(w / d, axis=1)
    tan2 = np.tan(alpha_p) ** 2
    return np.cos(alpha_p) ** 2 / E * (
        12 * (1 - nu**2) * bend + (2.4 * (1 + nu) + (1 - nu**2) * tan2) * shear
    )


def _pair_compliance(case, thickness_of):
    """The mean over the path of contact of both teeth's cantilever compliances (the tooth
    form's whole share of the mesh compliance; no foundation, no Hertz)."""
    pair = case.pair
    s = np.linspace(0.0, pair.path_of_contact, 101)
    return float(np.mean(sum(
        _weber_tooth(pair, i, pair.roll_distance(s, i), case.youngs_modulus,
                     case.poisson_ratio, thickness_of(pair, i))
        for i in (0, 1)
    )))  # fmt: skip


def test_weber_converges_with_fillet_points_and_moves_little_from_the_arc():
    """The cantilever integrated on the generated fillet converges at second order in its
    points per flank; the model (jaxgear.member_compliance, without a foundation) is that
    integral within 1e-6 of n = 1600 (its 200 points); the exact fillet is wider than the
    circular arc it replaced (the arc's radius cut to r_F − r_f), which lowers the accessory
    pair's tooth compliance by 0.55 % on average."""
    case = jio.load_case("accessory-spur")
    pair = case.pair
    values = {
        n: _pair_compliance(case, lambda p, i, n=n: _generated_thickness(p, i, n))
        for n in (25, 50, 100, 200, 1600)
    }
    ref = values[1600]
    errs = np.array([abs(values[n] - ref) for n in (25, 50, 100)])
    assert np.all(errs[1:] / errs[:-1] < 0.35), errs / ref
    s = np.linspace(0.0, pair.path_of_contact, 101)
    model = float(np.mean(sum(
        jg.member_compliance(pair, i, pair.roll_distance(s, i), case.youngs_modulus,
                             case.poisson_ratio, jg.NoFoundation())
        for i in (0, 1)
    )))  # fmt: skip
    assert abs(model - ref) < 1e-6 * ref
    assert abs(model - values[200]) < 1e-9 * ref  # its resolution: 200 points per flank
    arc = _pair_compliance(
        case, lambda p, i: lambda r: _old_circular_arc_thickness(p, i, r)
    )
    change = 1 - values[200] / arc
    assert 0.004 < change < 0.007, change  # measured 0.55 %


def test_per_member_foundation_is_the_series_combination():
    case = jio.load_case("accessory-spur")
    pair = case.pair
    s = np.linspace(0.0, pair.path_of_contact, 41)
    E, nu, w = case.youngs_modulus, case.poisson_ratio, case.nominal_line_load()
    name = jio.foundation_from_name
    k = {f: jg.weber_profile(pair, s, E, nu, w, foundation=name(f)) for f in ("weber", "none")}
    np.testing.assert_array_equal(
        jg.weber_profile(pair, s, E, nu, w, foundation=name(("none", "none"))), k["none"]
    )
    np.testing.assert_array_equal(
        jg.weber_profile(pair, s, E, nu, w, foundation=name(("weber", "weber"))), k["weber"]
    )
    mixed = jg.weber_profile(pair, s, E, nu, w, foundation=name(("weber", "none")))
    assert np.all(k["weber"] < mixed) and np.all(mixed < k["none"])
    # series: 1/k = cos β_b (c_Hertz + c_1 + c_2); adding the pinion's foundation compliance only
    rho1 = pair.roll_distance(s, 0)
    dc1 = jg.member_compliance(
        pair, 0, rho1, E, nu, jg.WeberFoundation()
    ) - jg.member_compliance(pair, 0, rho1, E, nu, jg.NoFoundation())
    expected = 1 / (1 / k["none"] + math.cos(pair.base_helix_angle) * dc1)
    np.testing.assert_allclose(mixed, expected, rtol=1e-12)
    # the table and the helper accept the same forms
    _, k_t = jg.stiffness_table(pair, jg.Weber(name(["weber", "none"])), n_points=41)
    _, k_r = jg.stiffness_table(pair, jg.Weber(name(("weber", False))), n_points=41)
    np.testing.assert_array_equal(k_t, k_r)
    assert name("sainsot") == jg.SainsotFoundation()
    assert name(True) == jg.WeberFoundation()
    both = jg.MemberFoundations(jg.SainsotFoundation(), jg.NoFoundation())
    assert name(("sainsot", None)) == both
    with pytest.raises(ValueError, match=r"mesh.foundation = 'winkler' is unknown"):
        name(("weber", "winkler"))
    with pytest.raises(ValueError, match=r"has 3 entries"):
        name(("weber", "none", "none"))


def test_tooth_form_errors_name_the_member():
    """A rack rounding too large for the rack tooth is caught when the Weber table is built and
    named by member (GearPair only checks ρ_fP < h_fP)."""
    pair = jg.GearPair(
        jg.Member(teeth=30, fillet_radius_coeff=0.2),
        jg.Member(teeth=40, fillet_radius_coeff=0.6),
        normal_module=2e-3,
        normal_pressure_angle=20 * DEG,
    )
    with pytest.raises(ValueError, match=r"^gear\.fillet_radius_coeff = 0\.6 is out of range"):
        jg.stiffness_table(pair, jg.Weber())
