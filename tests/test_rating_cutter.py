"""The internal gear's root section from its pinion-type (shaper) cutter
(jaxgear.ShaperCutterSection) against references written here independently: the ring's tooth
space cut point by point (the cutter's tip rounding swept through the cutting mesh as a cloud
of circle points, the space's boundary as the deepest cut per polar angle), the critical
section and the fillet's radius read off a quartic fitted through that boundary at its 60°
tangent; the cutter's root form diameter against the KISSsoft reports of the NREL
5 MW rings; the rating's derivative through the section against central differences; bad
input in one line.
The rating with this section against the reports' printed values is in
tests/test_rating_kisssoft.py."""

import math

import equinox as eqx
import jax
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
from _rating_cases import rated_accessory_data

MM = 1e-3
A = math.radians(20.0)


@eqx.filter_jit
def _section(geometry):
    """(s_Fn, ρ_F, d_sFn) of ``geometry``'s root section (m), compiled once per shape."""
    return geometry.root_section.section(geometry, geometry.derived())


def inv(a):
    return math.tan(a) - a


def _ring(zr, xr, mn, rho=0.30):
    planet = jg.Member(17 if zr == -56 else 36, 0.8, face_width=0.4)
    ring = jg.Member(zr, xr, dedendum_coeff=1.25, fillet_radius_coeff=rho, face_width=0.4)
    return jg.InternalGearPair(planet, ring, mn * MM, A)


def _cut_space(zr, xr, mn, z0, rho_s, x0=0.0, bins=1201):
    """The ring's tooth space cut by the cutter (mm), drawn here: the cutter's tooth outline
    (involute flanks to the tip rounding, tangent to the tip circle) swept through the cutting
    mesh at the zero-backlash distance, the cutter's tip circle cutting the root circle
    r_f = |z| m/2 + m (1.25 − x); the boundary the outermost cut point per polar angle."""
    zr = abs(zr)
    rho = rho_s * mn
    r_f = zr * mn / 2 + mn * (1.25 - xr)
    a_w = A
    for _ in range(60):  # inv α_w = inv α + 2 tan α (x0 + x)/(z0 − z): Newton by hand
        f = inv(a_w) - inv(A) - 2 * math.tan(A) * (x0 + xr) / (z0 - zr)
        a_w -= f / math.tan(a_w) ** 2
    a0 = mn * (zr - z0) / 2 * math.cos(A) / math.cos(a_w)
    ra0 = r_f - a0
    rb0 = mn * z0 / 2 * math.cos(A)
    # the tip rounding: the circle of radius rho tangent to the tip circle and the involute,
    # found by bisection on the involute's roll (distance of its centre to the tip circle)
    half0 = (math.pi / 2 + 2 * x0 * math.tan(A)) / z0 + inv(A)  # half angle at the base circle
    def centre(t):  # the involute's point at roll t (rad) and the point rho inside it
        phi = half0 - t  # its base-circle tangent point, toward the tooth's centre line
        b = rb0 * np.array([math.sin(phi), math.cos(phi)])
        p = b + rb0 * t * np.array([math.cos(phi), -math.sin(phi)])
        return p, p + rho * (b - p) / np.linalg.norm(b - p)

    lo, hi = 1e-6, 2.0
    for _ in range(200):
        mid = (lo + hi) / 2
        _, c = centre(mid)
        lo, hi = (mid, hi) if np.linalg.norm(c) + rho < ra0 else (lo, mid)
    _, c = centre(lo)
    arc = np.linspace(0, 2 * math.pi, 361)[:-1]
    circle = c[:, None] + rho * np.stack([np.sin(arc), np.cos(arc)])
    psi = np.linspace(-0.5, 0.5, 8001) * 2 * math.pi / z0
    spin = psi * (1 - zr / z0)
    cs, sn = np.cos(spin), np.sin(spin)
    x = a0 * np.sin(psi)[:, None] + cs[:, None] * circle[0] + sn[:, None] * circle[1]
    y = a0 * np.cos(psi)[:, None] - sn[:, None] * circle[0] + cs[:, None] * circle[1]
    r, ang = np.hypot(x, y).ravel(), np.arctan2(x, y).ravel()
    bins = np.linspace(0.0, math.pi / zr, bins)
    k = np.digitize(ang, bins)
    rmax = np.full(bins.size + 1, np.nan)
    np.fmax.at(rmax, k, r)
    mid = (bins[:-1] + bins[1:]) / 2
    return mid, rmax[1:-1]


def _reference_section(zr, xr, mn, z0, rho_s, x0=0.0, bins=1201):
    """(s_Fn, d_sFn, ρ_F) (mm) of the tooth space cut point by point (:func:`_cut_space`): the
    boundary's point where its tangent makes 60° with the centre line of the tooth at π/|z|
    (s_Fn 2 × its distance from that line, d_sFn 2 × its radius) and the fillet's radius of
    curvature there, both from a quartic fitted through the boundary's points of tangent 45°
    to 75°."""
    ang, r = _cut_space(zr, xr, mn, z0, rho_s, x0, bins)
    ok = np.isfinite(r)
    ang, r = ang[ok], r[ok]
    x, y = r * np.sin(ang), r * np.cos(ang)
    c = math.pi / abs(zr)  # into the frame of the tooth beside the space
    u = np.cos(c) * x - np.sin(c) * y
    v = np.sin(c) * x + np.cos(c) * y
    # the fillet, by the root, on the tooth's side of the deepest point (beyond it, toward the
    # space's centre, the tip circle cuts the root circle)
    keep = (v > r.max() - 3 * max(rho_s, 0.3) * mn) & (u > u[np.argmax(r)])
    u, v = u[keep], v[keep]
    tilt = np.degrees(np.arctan2(np.abs(np.gradient(u)), np.abs(np.gradient(v))))
    near = (tilt > 45.0) & (tilt < 75.0)  # a quartic v(u) through the fillet's points there
    fit = np.polynomial.Polynomial.fit(u[near], v[near], 4)
    d1, d2 = fit.deriv(1), fit.deriv(2)
    roots = (d1 - math.tan(math.radians(30.0))).roots()  # |dv/du| = tan 30°: 60° to the line
    roots = np.concatenate([roots, (d1 + math.tan(math.radians(30.0))).roots()])
    u60 = [float(r.real) for r in roots
           if abs(r.imag) < 1e-9 and u[near].min() <= r.real <= u[near].max()]
    assert len(u60) == 1
    u60 = u60[0]
    v60, slope, curve = fit(u60), d1(u60), d2(u60)
    return 2 * abs(u60), 2 * math.hypot(u60, v60), (1 + slope**2) ** 1.5 / abs(curve)


@pytest.mark.parametrize("zr, xr, mn, z0", [(-93, 0.1171, 21.0, 30), (-56, -0.5013, 45.0, 36)])
def test_section_is_the_cut_spaces_60_degree_point(zr, xr, mn, z0):
    """s_Fn, d_sFn and ρ_F of jg.ShaperCutterSection against the tooth space cut point by point
    (:func:`_reference_section`; 1e-3, 1e-5 and 2e-2 for the sampled cut)."""
    ref_s, ref_d, ref_rho = _reference_section(zr, xr, mn, z0, 0.30)
    pair = _ring(zr, xr, mn)
    geometry = jg.InternalRatingGeometry.of(pair, jg.ShaperCutterSection(z0))
    s_fn, rho_f, d_s = (float(t) / MM for t in _section(geometry))
    assert s_fn == pytest.approx(ref_s, rel=1e-3)
    assert d_s == pytest.approx(ref_d, rel=1e-5)
    assert rho_f == pytest.approx(ref_rho, rel=2e-2)


def test_cutter_reproduces_the_reports_root_form_diameters():
    """The cutter as jg.ShaperCutterSection sets it (zero-backlash cutting distance, its tip
    circle cutting the ring's root circle) gives the root form diameter the KISSsoft reports
    print for the NREL 5 MW rings' pinion-type cutters (d_Ff 1987.879 and 2662.682 mm, z0 = 30
    and 36, x0 = 0, ρ_a0 = 0.3 m_n) within 0.01 mm: the ring's point cut by the end of the
    cutter's involute (where its tip rounding starts), on the cutting mesh's line of action."""
    for zr, xr, mn, z0, printed in [(93, 0.1171, 21.0, 30, 1987.879),
                                    (56, -0.5013, 45.0, 36, 2662.682)]:
        rho = 0.3 * mn
        r_f = zr * mn / 2 + mn * (1.25 - xr)
        a_w = A
        for _ in range(60):
            a_w -= (inv(a_w) - inv(A) - 2 * math.tan(A) * xr / (z0 - zr)) / math.tan(a_w) ** 2
        a0 = mn * (zr - z0) / 2 * math.cos(A) / math.cos(a_w)
        rb0 = mn * z0 / 2 * math.cos(A)
        rc = r_f - a0 - rho
        roll0 = math.sqrt(rc**2 - rb0**2) + rho  # the involute's end: the rounding's tangent
        roll2 = roll0 + a0 * math.sin(a_w)
        d_ff = 2 * math.hypot(zr * mn / 2 * math.cos(A), roll2)
        assert d_ff == pytest.approx(printed, abs=0.01)


def test_rating_derivative_through_the_cutter_section_against_central_differences():
    """dS_F/dx2 and dS_H/dx2 of the whole rating (ISO 6336-1 method B factors) with the ring's
    section from its cutter, by jax.jvp (the implicit derivative through the 60° point) against
    central differences (float64, 1e-6); the ring's S_F moves with x2 through its section."""
    pair = _ring(-93, 0.1171, 21.0)
    geometry = jg.InternalRatingGeometry.of(pair, jg.ShaperCutterSection(30))
    settings = jg.RatingSettings(
        material=jg.RatingMaterial(
            (1500e6, 700e6), (430e6, 290e6),
            treatment=jg.PairTreatment(jg.CaseHardened(), jg.ThroughHardened()),
        ),
        lubrication=jg.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jg.GearAccuracy.from_grade(pair, 6),
        life=20_000 * 3600.0,
        application_factor=1.25,
    )
    op = jg.OperatingPoint(2.0e5, 10.0)

    def safety(x2):
        g = geometry.replace(profile_shift=jax.numpy.stack([geometry.profile_shift[0], x2]))
        r = jg.rate(g, op, settings)
        return jax.numpy.concatenate([r.pitting.S_H, r.bending.S_F])

    x2 = geometry.profile_shift[1]
    both = jax.jit(lambda x: jax.jvp(safety, (x,), (jax.numpy.ones_like(x),)))
    grad = np.asarray(both(x2)[1])
    h = 1e-6
    fd = (np.asarray(both(x2 + h)[0]) - np.asarray(both(x2 - h)[0])) / (2 * h)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-9)
    assert abs(grad[3]) > 0.1  # the ring's S_F


def test_bad_cutter_refused_in_one_line():
    with pytest.raises(ValueError, match=r"teeth = 5 is out of range"):
        jg.ShaperCutterSection(5)
    with pytest.raises(ValueError, match=r"tip_radius_coeff = -0.1"):
        jg.ShaperCutterSection(30, tip_radius_coeff=-0.1)
    pair = _ring(-93, 0.1171, 21.0)
    with pytest.raises(ValueError, match=r"teeth = 90 is out of range.*\|z2\| - 10"):
        jg.InternalRatingGeometry.of(pair, jg.ShaperCutterSection(90))


def test_case_file_treatment_per_gear_and_ring_cutter(tmp_path):
    """``[material] treatment`` per gear (a table by gear name) maps to jg.PairTreatment, the
    through-hardened ring's ``brinell_hardness_HB`` to its Z_W (1.2 − (240 − 130)/1700, ISO
    6336-2), ``[rating] ring_cutter_teeth`` to jg.ShaperCutterSection; bad values in one line."""
    case = jio.load_case("nrel-5mw-planetary")
    sun_mesh, ring_mesh = jio.ratings_of(case)
    t = ring_mesh.settings.material.treatment
    assert isinstance(t, jg.PairTreatment) and isinstance(t.gear, jg.ThroughHardened)
    assert t.gear.brinell_hardness == 240.0
    assert t.gear.work_hardening(t.pinion) == pytest.approx(1.2 - 110 / 1700, rel=1e-12)
    assert isinstance(sun_mesh.settings.material.treatment, jg.CaseHardened)
    assert ring_mesh.geometry.root_section.teeth == 36
    text = jio.embedded_case_text("nrel-5mw-planetary")
    for old, new, match in [
        ('ring1 = "through_hardened" }', 'ring1 = "glass" }', r"\[material\] treatment = 'glass'"),
        ("ring_cutter_teeth = 36", "ring_cutter_teeth = 50", r"ring_cutter_teeth = 50.*\[11, 46\]"),
        ("ring1 = 240.0 }", "ring1 = 40.0 }", r"brinell_hardness_HB"),
    ]:
        path = tmp_path / "c.toml"
        path.write_text(text.replace(old, new))
        with pytest.raises(ValueError, match=match):
            jio.load_case(str(path))


def test_pair_case_treatment_list_and_hardness():
    """A pair case's ``treatment = [pinion, gear]`` → jg.PairTreatment with the through-hardened
    gear's ``brinell_hardness_HB`` (its Z_W 1.2 − (200 − 130)/1700 against the case-hardened
    pinion); one name keeps one treatment; a list of three names is refused in one line."""
    d = rated_accessory_data(4, 8)
    d["material"].update(treatment=["case_hardened", "through_hardened"],
                         brinell_hardness_HB=[600.0, 200.0])
    t = jio.rating_of(jio.parse_case(d)).settings.material.treatment
    assert isinstance(t, jg.PairTreatment) and t.gear.brinell_hardness == 200.0
    assert t.gear.work_hardening(t.pinion) == pytest.approx(1.2 - 70 / 1700, rel=1e-12)
    d["material"].update(treatment="nitrided", brinell_hardness_HB=600.0)
    assert isinstance(jio.rating_of(jio.parse_case(d)).settings.material.treatment, jg.Nitrided)
    d["material"]["treatment"] = ["nitrided"] * 3
    with pytest.raises(ValueError, match=r"\[material\] treatment = .*\[pinion, gear\] list"):
        jio.parse_case(d)
