"""The internal gear's root section from its pinion-type (shaper) cutter
(jaxgear.rating.ShaperCutterSection) against references written here independently: the ring's tooth
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
from _rating_cases import rated_accessory_data
from test_ring_cutter_keys import older_spelling

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr

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


def _cutting(zr, xr, mn, z0, rho_s, x0=0.0):
    """The cutting mesh drawn here (mm): (a0, c, ρ) the zero-backlash cutting distance, the
    centre of the cutter's right tip rounding in its own frame (tooth on +y) and its radius:
    the cutter's tip circle cuts the root circle r_f = |z| m/2 + m (1.25 − x), the rounding
    tangent to the tip circle and the involute."""
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
    return a0, centre(lo)[1], rho


def _cut_space(zr, xr, mn, z0, rho_s, x0=0.0, bins=1201):
    """The ring's tooth space cut by the cutter (mm), drawn here: the cutter's tip rounding
    (:func:`_cutting`) swept through the cutting mesh as a cloud of circle points; the
    boundary the outermost cut point per polar angle."""
    a0, c, rho = _cutting(zr, xr, mn, z0, rho_s, x0)
    zr = abs(zr)
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


def _envelope_section(zr, xr, mn, z0, rho_s, x0=0.0, n=40001):
    """(s_Fn, d_sFn, ρ_F) (mm) of the fillet taken as the numerical envelope of the cutter's
    tip rounding (:func:`_cutting`): the rounding's circle placed at ``n`` positions of the
    cutting mesh over one cutter pitch (the cutter turned about its centre, its centre about
    the ring's), the envelope the outer intersection of each two neighbouring circles; the
    point where the envelope's chord direction makes 60° with the centre line of the tooth
    at π/|z| (interpolated), on the tooth's side of its deepest point, and the radius of the
    circle through the envelope points a few steps either side of it."""
    a0, c, rho = _cutting(zr, xr, mn, z0, rho_s, x0)
    zr = abs(zr)
    psi = np.linspace(-0.5, 0.5, n) * 2 * math.pi / z0
    spin = psi * (1 - zr / z0)
    q = np.stack([a0 * np.sin(psi) + np.cos(spin) * c[0] + np.sin(spin) * c[1],
                  a0 * np.cos(psi) - np.sin(spin) * c[0] + np.cos(spin) * c[1]], -1)
    mid, step = (q[1:] + q[:-1]) / 2, q[1:] - q[:-1]
    d = np.linalg.norm(step, axis=-1)
    h = np.sqrt(np.maximum(rho**2 - d**2 / 4, 0.0))
    perp = np.stack([step[:, 1], -step[:, 0]], -1) / d[:, None]
    one, two = mid + h[:, None] * perp, mid - h[:, None] * perp
    env = np.where((np.linalg.norm(one, axis=-1) > np.linalg.norm(two, axis=-1))[:, None],
                   one, two)
    k = math.pi / zr  # into the frame of the tooth beside the space: u across, v along
    u = math.cos(k) * env[:, 0] - math.sin(k) * env[:, 1]
    v = math.sin(k) * env[:, 0] + math.cos(k) * env[:, 1]
    deepest = np.argmax(np.hypot(u, v))
    side = np.arange(u.size)
    side = side[u > u[deepest]]  # toward the tooth
    side = side[np.argsort(u[side])]
    u, v = u[side], v[side]
    tilt = np.degrees(np.arctan2(np.abs(np.diff(u)), np.abs(np.diff(v))))  # to the centre line
    j = int(np.nonzero((tilt[:-1] - 60.0) * (tilt[1:] - 60.0) <= 0)[0][0])
    w = (tilt[j] - 60.0) / (tilt[j] - tilt[j + 1])
    um = ((u[j] + u[j + 1]) / 2) * (1 - w) + ((u[j + 1] + u[j + 2]) / 2) * w
    vm = ((v[j] + v[j + 1]) / 2) * (1 - w) + ((v[j + 1] + v[j + 2]) / 2) * w
    # the circle through three envelope points about the 60° point (their arc ~ ρ/3)
    arc = np.cumsum(np.hypot(np.diff(u), np.diff(v)))
    span = max(1, int(np.searchsorted(arc, arc[j] + rho / 3) - j))
    p1, p2, p3 = (np.array([u[i], v[i]]) for i in (max(j - span, 0), j, j + span))
    a, b = p2 - p1, p3 - p1
    radius = np.linalg.norm(a) * np.linalg.norm(b) * np.linalg.norm(p3 - p2) / (
        2 * abs(a[0] * b[1] - a[1] * b[0]))
    return 2 * abs(um), 2 * math.hypot(um, vm), radius


@pytest.mark.parametrize("zr, xr, mn, z0", [(-93, 0.1171, 21.0, 30), (-56, -0.5013, 45.0, 36)])
def test_section_is_the_cut_spaces_60_degree_point(zr, xr, mn, z0):
    """s_Fn, d_sFn and ρ_F of jg.rating.ShaperCutterSection against the tooth space cut point by point
    (:func:`_reference_section`; 1e-3, 1e-5 and 2e-2 for the sampled cut)."""
    ref_s, ref_d, ref_rho = _reference_section(zr, xr, mn, z0, 0.30)
    pair = _ring(zr, xr, mn)
    geometry = jr.InternalRatingGeometry.of(pair, jg.rating.ShaperCutterSection(z0))
    s_fn, rho_f, d_s = (float(t) / MM for t in _section(geometry))
    assert s_fn == pytest.approx(ref_s, rel=1e-3)
    assert d_s == pytest.approx(ref_d, rel=1e-5)
    assert rho_f == pytest.approx(ref_rho, rel=2e-2)


@pytest.mark.parametrize(
    "zr, xr, mn, z0, x0, rho_s",
    [
        (-93, 0.1171, 21.0, 30, 0.0, 0.30),  # the reports' cutters
        (-56, -0.5013, 45.0, 36, 0.0, 0.30),
        (-56, -0.5013, 45.0, 41, 0.0, 0.10),  # sections once found on the wrong branch:
        (-56, -0.5013, 45.0, 41, 0.0, 0.02),  # s_Fn 58.3, 27.6, 17.2 and 82.4 m_n
        (-56, -0.5013, 45.0, 35, -0.2, 0.10),
        (-93, 0.1171, 21.0, 83, -0.2, 0.30),
    ],
)
def test_section_is_the_numerical_envelope_of_the_tip_rounding(zr, xr, mn, z0, x0, rho_s):
    """s_Fn, d_sFn and ρ_F of jg.rating.ShaperCutterSection against the fillet taken as the envelope
    of the cutter's tip rounding numerically (:func:`_envelope_section`: 40001 circle
    positions, neighbouring circles intersected, the 60° point interpolated, the curvature
    from three points): 1e-6, 1e-8 and 2e-3. Among them the large cutters (z0 close to
    |z2| − 10) whose rounding's centre passes just outside the cutting pitch circle, where
    the 60° point lies after the carrier angle's zero and a search on the negative side only
    returned sections tens of modules wide."""
    ref_s, ref_d, ref_rho = _envelope_section(zr, xr, mn, z0, rho_s, x0)
    geometry = jr.InternalRatingGeometry.of(
        _ring(zr, xr, mn, rho_s), jg.rating.ShaperCutterSection(z0, x0, rho_s)
    )
    s_fn, rho_f, d_s = (float(t) / MM for t in _section(geometry))
    assert s_fn == pytest.approx(ref_s, rel=1e-6)
    assert d_s == pytest.approx(ref_d, rel=1e-8)
    assert rho_f == pytest.approx(ref_rho, rel=2e-3)
    assert s_fn / mn < 3.5 and rho_f >= rho_s * mn  # (was 58.3, 27.6, 17.2 and 82.4 m_n)


def _probe_grid(rings, sectioned):
    """The check of the tests below over ``rings`` ((case name, cutter teeth z0), ...): every
    section refused or physical, the points of ``sectioned`` sectioned, some refused."""
    xs = jax.numpy.array([-0.2, -0.1, 0.0, 0.25, 0.5, 1.0, 1.5])
    rs = jax.numpy.array([0.02, 0.1, 0.3, 0.6])
    seen = set()
    refused = 0
    for name, teeth in rings:
        pair = jio.load_case(name).pairs[1]
        geometry = jr.InternalRatingGeometry.of(pair)
        g = geometry.derived()
        mn = float(geometry.normal_module)
        zr = abs(pair.gear.teeth)
        x2 = float(geometry.profile_shift[1])
        r_f = abs(float(g.root_diameter[1])) / 2
        for z0 in teeth:
            @jax.jit
            def grid(xs, rs, z0=z0, geometry=geometry, g=g):
                def one(x0, r):
                    cutter = jg.rating.ShaperCutterSection(z0, x0, r)
                    return jax.numpy.stack(cutter.section(geometry, g)), cutter.result(geometry)

                return jax.vmap(jax.vmap(one, (None, 0)), (0, None))(xs, rs)

            out, codes = (np.asarray(t) for t in grid(xs, rs))
            ok = codes == 0
            refused += int((~ok).sum())
            assert np.isnan(out[~ok]).all() and np.isfinite(out[ok]).all()
            s, rho, d_s = out[ok].T
            r_s = d_s / 2
            rho_a0 = np.broadcast_to(np.asarray(rs)[None, :], ok.shape)[ok] * mn
            assert (s > mn * (math.pi / 2 + 2 * x2 * math.tan(A))).all()
            assert (s < 2 * r_s * np.sin(math.pi / zr)).all()
            assert (rho >= rho_a0 * (1 - 1e-9)).all() and (rho < 2 * mn).all()
            assert (r_s <= r_f * (1 + 1e-12)).all() and (r_s > r_f - 1.25 * mn).all()
            for i, j in zip(*np.nonzero(ok)):
                seen.add((name, z0, round(float(xs[i]), 2), round(float(rs[j]), 2)))
    assert sectioned <= seen and refused > 0


def test_probe_grid_is_physical_or_refused():
    """The grid of the slow test below on stage 2's ring with its largest cutter (z0 = 83):
    every section either refused or physical against the ring's own bounds, the probe's
    wrong-branch points there sectioned, some cutters refused."""
    _probe_grid((("nrel-5mw-stage2", (83,)),),
                {("nrel-5mw-stage2", 83, -0.2, 0.02), ("nrel-5mw-stage2", 83, -0.2, 0.1),
                 ("nrel-5mw-stage2", 83, -0.2, 0.3)})


# default tier: tests/test_rating_cutter.py::test_probe_grid_is_physical_or_refused (the same
# claim on one ring and one cutter size)
@pytest.mark.slow
def test_probe_grid_over_both_rings_is_physical_or_refused():
    """Over a grid of cutters on the rings of the NREL 5 MW cases (z0 = 11, 47, 83 on stage 2's
    ring, 11, 35, 41 on stage 1's, the largest where the probe found sections tens of modules
    wide; x0 in {−0.2, −0.1, 0, 0.25, 0.5, 1, 1.5}; ρ_a0/m_n in {0.02, 0.1, 0.3, 0.6}) every
    section is either refused (jg.rating.ShaperCutterSection.result nonzero, the section NaN) or
    physical against bounds drawn from the ring alone: the chord s_Fn between the ring's tooth
    thickness on its reference circle m (π/2 + 2 x2 tan α) and the pitch chord at its radius,
    ρ_F at least the rounding's ρ_a0 and under 2 m_n, the chord's ends within the dedendum
    (r_f − 1.25 m, r_f]. The probe's wrong-branch points are sectioned, not refused; the
    refusals are the cutters that cannot generate the fillet (pointed at the tip circle that
    cuts the root, no cutting mesh, or the rounding's centre inside the cutting pitch
    circle)."""
    _probe_grid((("nrel-5mw-stage2", (11, 47, 83)), ("nrel-5mw-planetary", (11, 35, 41))),
                {("nrel-5mw-planetary", 41, 0.0, 0.02), ("nrel-5mw-planetary", 41, 0.0, 0.1),
                 ("nrel-5mw-planetary", 35, -0.2, 0.1), ("nrel-5mw-stage2", 83, -0.2, 0.02),
                 ("nrel-5mw-stage2", 83, -0.2, 0.1), ("nrel-5mw-stage2", 83, -0.2, 0.3)})


@pytest.mark.slow
def test_probe_grid_rating_form_factors():
    """The probe itself (its Y_F through jg.rating.tooth_form_factors, vmapped over x0 and ρ_a0 per
    z0): 0 < Y_F < 5 and 1 < s_Fn/m_n < 6 wherever the section is finite; NaN exactly where
    jg.rating.ShaperCutterSection.result is nonzero, and jg.rating.InternalRatingGeometry.of refuses
    those cutters in one line."""
    xs = jax.numpy.array([0.0, 0.25, 0.5, 1.0, 1.5, -0.1, -0.2])
    rs = jax.numpy.array([0.02, 0.1, 0.3, 0.6])
    for name in ("nrel-5mw-stage2", "nrel-5mw-planetary"):
        pair = jio.load_case(name).pairs[1]
        mn = pair.normal_module
        zr = abs(pair.gear.teeth)
        plain = jr.InternalRatingGeometry.of(pair)
        for z0 in range(11, zr - 9, 6):
            def f(x0, rho, z0=z0, plain=plain, mn=mn):
                cutter = jg.rating.ShaperCutterSection(z0, x0, rho)
                t = jg.rating.tooth_form_factors(jr.InternalRatingGeometry(
                    **{k: getattr(plain, k) for k in plain.__dataclass_fields__
                       if k != "root_section"}, root_section=cutter))
                return jax.numpy.stack([t.s_Fn[1] / mn, t.Y_F[1]]), cutter.result(plain)

            grid = jax.jit(jax.vmap(jax.vmap(f, (None, 0)), (0, None)))
            out, codes = (np.asarray(t) for t in grid(xs, rs))
            bad = codes != 0
            assert np.isnan(out[bad]).all() and np.isfinite(out[~bad]).all()
            assert ((out[~bad][:, 0] > 1) & (out[~bad][:, 0] < 6)).all()
            assert ((out[~bad][:, 1] > 0) & (out[~bad][:, 1] < 5)).all()
            for i, j in zip(*np.nonzero(bad)):
                cutter = jg.rating.ShaperCutterSection(z0, float(xs[i]), float(rs[j]))
                with pytest.raises(ValueError, match=r"cannot generate the ring's fillet"):
                    jr.InternalRatingGeometry.of(pair, cutter)


def test_cutter_that_cannot_cut_the_fillet_refused_in_one_line():
    """Stage 1's ring with z0 = 41, x0 = −0.1, ρ_a0 = 0.1 m_n (the rounding's centre inside
    the cutting pitch circle): refused at construction naming x0 and the x0 that work with
    z0 = 41 and ρ_a0 = 0.1 m_n, their edges checked one step either side (beyond 0.80 no
    cutting mesh: inv α_w0 <= 0); under jit the
    section is NaN and jg.rating.ShaperCutterSection.result gives the code."""
    pair = jio.load_case("nrel-5mw-planetary").pairs[1]
    bad = jg.rating.ShaperCutterSection(41, -0.1, 0.1)
    with pytest.raises(ValueError, match=r"^ShaperCutterSection: profile_shift = -0\.1 cannot "
                       r"generate.*pitch circle.*; allowed \[-0\.02, 0\.80\]$") as info:
        jr.InternalRatingGeometry.of(pair, bad)
    assert "\n" not in str(info.value)
    plain = jr.InternalRatingGeometry.of(pair)
    codes = [int(jg.rating.ShaperCutterSection(41, x, 0.1).result(plain)) for x in (-0.03, -0.02,
                                                                              0.80, 0.81)]
    assert codes == [jg.CutterResult.rounding_inside_pitch_circle, 0, 0,
                     jg.CutterResult.no_cutting_mesh]

    @jax.jit
    def traced(x0):
        cutter = jg.rating.ShaperCutterSection(41, x0, 0.1)
        return cutter.section(plain, plain.derived()), cutter.result(plain)

    section, code = traced(-0.1)
    assert np.isnan(np.asarray(section)).all()
    assert jg.CutterResult(int(code)) is jg.CutterResult.rounding_inside_pitch_circle
    assert np.isfinite(np.asarray(traced(0.0)[0])).all()


def test_cutter_reproduces_the_reports_root_form_diameters():
    """The cutter as jg.rating.ShaperCutterSection sets it (zero-backlash cutting distance, its tip
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
    geometry = jr.InternalRatingGeometry.of(pair, jg.rating.ShaperCutterSection(30))
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(
            (1500e6, 700e6), (430e6, 290e6),
            treatment=jr.PairTreatment(jr.CaseHardened(), jr.ThroughHardened()),
        ),
        lubrication=jr.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=20_000 * 3600.0,
        application_factor=1.25,
    )
    op = jr.OperatingPoint(2.0e5, 10.0)

    def safety(x2):
        g = geometry.replace(profile_shift=jax.numpy.stack([geometry.profile_shift[0], x2]))
        r = jr.rate(g, op, settings)
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
        jg.rating.ShaperCutterSection(5)
    with pytest.raises(ValueError, match=r"tip_radius_coeff = -0.1"):
        jg.rating.ShaperCutterSection(30, tip_radius_coeff=-0.1)
    pair = _ring(-93, 0.1171, 21.0)
    with pytest.raises(ValueError, match=r"teeth = 90 is out of range.*\|z2\| - 10"):
        jr.InternalRatingGeometry.of(pair, jg.rating.ShaperCutterSection(90))


def test_case_file_treatment_per_gear_and_ring_cutter(tmp_path):
    """``[material] treatment`` per gear (a table by gear name) maps to jg.rating.PairTreatment, the
    through-hardened ring's ``brinell_hardness_HB`` to its Z_W (1.2 − (240 − 130)/1700, ISO
    6336-2), ``[rating] ring_cutter_teeth`` to jg.rating.ShaperCutterSection; bad values in one line."""
    case = jio.load_case("nrel-5mw-planetary")
    sun_mesh, ring_mesh = jio.ratings_of(case)
    t = ring_mesh.settings.material.treatment
    assert isinstance(t, jr.PairTreatment) and isinstance(t.gear, jr.ThroughHardened)
    assert t.gear.brinell_hardness == 240.0
    assert t.gear.work_hardening(t.pinion) == pytest.approx(1.2 - 110 / 1700, rel=1e-12)
    assert isinstance(sun_mesh.settings.material.treatment, jr.CaseHardened)
    assert ring_mesh.geometry.root_section.teeth == 36
    text = older_spelling(jio.embedded_case_text("nrel-5mw-planetary"))  # [rating] ring_cutter_*
    for old, new, match in [
        ('ring1 = "through_hardened" }', 'ring1 = "glass" }', r"\[material\] treatment = 'glass'"),
        ("ring_cutter_teeth = 36", "ring_cutter_teeth = 50", r"ring_cutter_teeth = 50.*\[11, 46\]"),
        ("ring_cutter_profile_shift = 0.0", "ring_cutter_profile_shift = -0.6",
         (r"^\[rating\] ring_cutter_profile_shift = -0\.6: this cutter \(z0 = 36, .*cannot "
          r"generate the ring's fillet: .*pitch circle.*; allowed \[-0\.10, 0\.44\]$")),
        ("ring1 = 240.0 }", "ring1 = 40.0 }", r"brinell_hardness_HB"),
    ]:
        path = tmp_path / "c.toml"
        path.write_text(text.replace(old, new))
        with pytest.raises(ValueError, match=match):
            jio.load_case(str(path))


def test_pair_case_treatment_list_and_hardness():
    """A pair case's ``treatment = [pinion, gear]`` → jg.rating.PairTreatment with the
    through-hardened gear's ``brinell_hardness_HB`` (its Z_W 1.2 − (200 − 130)/1700 against the
    case-hardened pinion); one name keeps one treatment; a list of three names is refused in one
    line."""
    d = rated_accessory_data(4, 8)
    d["material"].update(treatment=["case_hardened", "through_hardened"],
                         brinell_hardness_HB=[600.0, 200.0])
    t = jio.rating_of(jio.parse_case(d)).settings.material.treatment
    assert isinstance(t, jr.PairTreatment) and t.gear.brinell_hardness == 200.0
    assert t.gear.work_hardening(t.pinion) == pytest.approx(1.2 - 70 / 1700, rel=1e-12)
    d["material"]["treatment"] = "nitrided"  # (its hardness unread: refused, see round 5)
    del d["material"]["brinell_hardness_HB"]
    assert isinstance(jio.rating_of(jio.parse_case(d)).settings.material.treatment, jr.Nitrided)
    d["material"]["treatment"] = ["nitrided"] * 3
    with pytest.raises(ValueError, match=r"\[material\] treatment = .*\[pinion, gear\] list"):
        jio.parse_case(d)
