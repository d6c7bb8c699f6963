"""Rolling bearings from their geometry (jaxgear.bearings) against independent references.

- Stribeck's and Sjövall's load distribution: zero clearance, a radial load, Q_max Z cos α / F_r
  = 4.37 (point contact) and 4.08 (line contact), and at a half-loaded raceway (ε = 0.5)
  F_a = 1.216 F_r tan α (point) and 1.260 F_r tan α (line): the published factors (NSK
  technical report, "Bearing internal load distribution and displacement", Table 1 and
  eqs. 4–5; Harris & Kotzalas ch. 7), and the integrals behind them by quadrature here.
- The Hertz constant of a ball contact against the exact Hertz theory (the ellipticity from its
  transcendental equation with scipy's complete elliptic integrals), the curvatures written
  here from Harris & Kotzalas's definitions: Brewe and Hamrock's approximations hold to 3 %.
- The 5×5 stiffness (``jax.jacfwd``) against central finite differences of the load and
  against Lim & Singh's closed forms for ball and (sliced) roller bearings, written out here;
  the load against the gradient of the contact energy (two formulas).
- The inverse solve: load(solve(F)) = F, its convergence, its derivative against inv(K).
- ISO 281 basic rating life by hand (the table's interpolation written out); Palmgren–Miner
  over two bins by hand; the tones against the CWRU Bearing Data Center's published defect
  frequencies of the 6205-2RS JEM; the linear spring against :class:`jaxgear.scenes.Bearing`.
- The refusals, one line each naming the argument.

Lim & Singh's (1990) example stiffness coefficients and a worked Harris & Kotzalas example with
its figures were not at hand: not transcribed (docs/bearings.md, "Evidence").
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy import integrate, optimize, special

import jaxgear.bearings as jb
import jaxgear.scenes as js


def many_balls(**kw):
    """A deep groove ball bearing with many small balls (the continuous limit of the
    distribution integrals): 72 balls of 2 mm on a 100 mm pitch circle."""
    args = dict(bore=0.09, outer_diameter=0.11, width=0.01, elements=72,
                element_diameter=0.002, pitch_diameter=0.1)
    return jb.DeepGrooveBall(**{**args, **kw})


def many_rollers(kind=jb.CylindricalRoller, **kw):
    args = dict(bore=0.09, outer_diameter=0.11, width=0.01, elements=72,
                element_diameter=0.002, pitch_diameter=0.1, effective_length=0.004, slices=1)
    return kind(**{**args, **kw})


def sjovall(n, eps=0.5):
    """The Sjövall integrals J_r(ε), J_a(ε) for Q = K δ^n (by quadrature): the load zone
    δ(ψ) ∝ 1 − (1 − cos ψ)/(2ε)."""
    lim = math.acos(max(1 - 2 * eps, -1.0))
    g = lambda psi: max(1 - (1 - math.cos(psi)) / (2 * eps), 0.0) ** n
    Jr = integrate.quad(lambda p: g(p) * math.cos(p), -lim, lim)[0] / (2 * math.pi)
    Ja = integrate.quad(g, -lim, lim)[0] / (2 * math.pi)
    return Jr, Ja


# the bearing's load, element loads, contact pressures and energy gradient compiled, one program
# per kind and element count shared by the tests here (run primitive by primitive, each test
# compiled dozens of small programs of its own); the same functions, the same numbers
@eqx.filter_jit
def _load(bearing, d):
    return bearing.load(d)


@eqx.filter_jit
def _element_loads(bearing, d):
    return bearing.element_loads(d)


@eqx.filter_jit
def _contact_pressure(bearing, d):
    return bearing.contact_pressure(d)


@eqx.filter_jit
def _load_by_gradient(bearing, d):
    """∇U(d) of the bearing's contact energy (jax.grad of :meth:`potential`)."""
    return jax.grad(bearing.potential)(d)


# ---------------------------------------------------------------- load distribution


def test_stribeck_zero_clearance_ball_bearing_q_max_factor():
    """Q_max Z / F_r of a radially loaded zero-clearance ball bearing: 4.37 (Stribeck;
    NSK eq. 4), the 6205's nine balls within 1 %, and 72 balls within 0.05 % of 1/J_r(0.5)
    (quadrature), which rounds to the published 4.37."""
    Jr, _ = sjovall(1.5)
    assert round(1 / Jr, 2) == 4.37
    for bearing, tol in ((jb.catalogue("6205"), 1e-2), (many_balls(), 5e-4)):
        for dx in (2e-6, 1e-5):  # independent of the load for zero clearance
            d = jnp.array([dx, 0, 0, 0, 0])
            Q = _element_loads(bearing, d)
            Fr = _load(bearing, d)[0]
            factor = float(Q.max() * bearing.elements / Fr)
            ref = 4.37 if tol > 1e-3 else 1 / Jr
            assert factor == pytest.approx(ref, rel=tol)


def test_line_contact_zero_clearance_q_max_factor():
    """The same for line contact: 4.08 (NSK eq. 5), 72 rollers against 1/J_r(0.5) for
    n = 10/9."""
    Jr, _ = sjovall(10 / 9)
    assert round(1 / Jr, 2) == 4.08
    b = many_rollers()
    d = jnp.array([5e-6, 0, 0, 0, 0])
    factor = float(_element_loads(b, d).max() * b.elements / _load(b, d)[0])
    assert factor == pytest.approx(1 / Jr, rel=5e-4)
    assert factor == pytest.approx(4.08, rel=2e-3)


def test_half_loaded_raceway_axial_to_radial_ratio():
    """ε = 0.5 (the rings shifted radially only, zero clearance): F_a = 1.216 F_r tan α for
    point contact and 1.260 F_r tan α for line contact (NSK, Table 1), a 40° ball bearing (its
    contact angle moves by δ/A, so a light load: 1 nm of approach) and a 15° tapered roller
    bearing; 72 elements against the quadrature of the integrals to 2e-4."""
    Jr, Ja = sjovall(1.5)
    ratio_point = Ja / Jr
    alpha = math.radians(40)
    ball = jb.AngularContactBall(bore=0.09, outer_diameter=0.11, width=0.01, elements=72,
                                 element_diameter=0.002, pitch_diameter=0.1,
                                 contact_angle=alpha)
    f = _load(ball, jnp.array([1e-9 / math.cos(alpha), 0, 0, 0, 0]))
    assert float(f[2] / (f[0] * math.tan(alpha))) == pytest.approx(1.216, rel=5e-4)
    assert float(f[2] / (f[0] * math.tan(alpha))) == pytest.approx(ratio_point, rel=2e-4)
    alpha = math.radians(15)
    taper = many_rollers(jb.TaperedRoller, contact_angle=alpha)
    f = _load(taper, jnp.array([1e-6, 0, 0, 0, 0]))
    assert float(f[2] / (f[0] * math.tan(alpha))) == pytest.approx(1.260, rel=2e-3)
    Jr, Ja = sjovall(10 / 9)
    assert float(f[2] / (f[0] * math.tan(alpha))) == pytest.approx(Ja / Jr, rel=5e-4)


def test_uniform_approach_gives_the_whole_roller():
    """A roller's slices share its constant: a uniform approach gives Q = K_n δ^(10/9)
    whatever the slice count."""
    b = jb.catalogue("NU 205")
    d = jnp.array([4e-6, 0, 0, 0, 0])
    Q = _element_loads(b, d).sum(axis=1)[0]
    assert float(Q) == pytest.approx(float(b.hertz_constant * 4e-6 ** (10 / 9)), rel=1e-12)


@pytest.mark.slow  # three programs (10, 40, 160 slices), ~6 s on the loaded 2-core machine
def test_tilt_moment_converges_as_the_slices_refine():
    """A tilt's moment converges as the slices refine (10 → 40 → 160: the change falls by more
    than 4 each time, below 1e-3 at the end)."""
    tilt = jnp.array([4e-6, 0, 0, 0, 2e-4])
    m = [float(jb.catalogue("NU 205", slices=s).load(tilt)[4]) for s in (10, 40, 160)]
    assert abs(m[2] - m[1]) < abs(m[1] - m[0]) / 4
    assert abs(m[2] - m[1]) < 1e-3 * abs(m[2])


# ---------------------------------------------------------------- Hertz constant


def exact_hertz(D, d_m, alpha, f, inner):
    """(κ, ℰ, ℱ, R) of one ball–raceway contact by the exact Hertz theory: curvatures from
    Harris & Kotzalas's definitions, the ellipticity κ solving
    F(ρ) = ((κ² + 1) ℰ − 2 ℱ) / ((κ² − 1) ℰ) with scipy's complete elliptic integrals."""
    g = D * math.cos(alpha) / d_m
    rho_I = 2 / D
    rho_II1 = (2 / D) * (g / (1 - g) if inner else -g / (1 + g))
    rho_II2 = -1 / (f * D)
    total = 2 * rho_I + rho_II1 + rho_II2
    F_rho = (rho_II1 - rho_II2) / total

    def eqn(kappa):
        m = 1 - 1 / kappa**2
        Ek, Fk = special.ellipe(m), special.ellipk(m)
        return ((kappa**2 + 1) * Ek - 2 * Fk) / ((kappa**2 - 1) * Ek) - F_rho

    kappa = optimize.brentq(eqn, 1.0001, 100.0, xtol=1e-14)
    m = 1 - 1 / kappa**2
    return kappa, special.ellipe(m), special.ellipk(m), 1 / total


def exact_hertz_K(D, d_m, alpha, f, E, nu, inner):
    """One ball–raceway contact's K (N/m^1.5) by the exact Hertz theory:
    δ = ℱ [(9 / (2 ℰ R)) (Q / (π κ E'))²]^(1/3)  ->  Q = K δ^1.5."""
    kappa, Ek, Fk, R = exact_hertz(D, d_m, alpha, f, inner)
    Ep = E / (1 - nu**2)
    return math.pi * kappa * Ep * math.sqrt(2 * Ek * R / (9 * Fk**3))


@pytest.mark.parametrize("alpha_deg,f", [(0.0, 0.52), (40.0, 0.52), (15.0, 0.515), (25.0, 0.53)])
def test_hertz_constant_against_exact_hertz(alpha_deg, f):
    """Each contact's K and the ball's series K_n within 3 % of the exact Hertz theory (Brewe
    and Hamrock's stated accuracy), the 6205's ball and pitch circle."""
    D, dm, E, nu = 0.3126 * 0.0254, 1.537 * 0.0254, 2.075e11, 0.3
    a = math.radians(alpha_deg)
    Ki = exact_hertz_K(D, dm, a, f, E, nu, True)
    Ko = exact_hertz_K(D, dm, a, f, E, nu, False)
    assert float(jb.point_contact(D, dm, a, f, E, nu, inner=True)[0]) == pytest.approx(
        Ki, rel=0.03)
    assert float(jb.point_contact(D, dm, a, f, E, nu, inner=False)[0]) == pytest.approx(
        Ko, rel=0.03)
    Kn = (Ki ** (-2 / 3) + Ko ** (-2 / 3)) ** -1.5
    assert float(jb.point_contact_constant(D, dm, a, f, f, E, nu)) == pytest.approx(Kn, rel=0.03)


def test_contact_pressure_against_exact_hertz():
    """The 6205's most loaded ball under 2 kN: each contact's p_max = 3Q/(2πab) within 2 % of
    the exact Hertz ellipse (a = (6κ²ℰQR/(πE'))^(1/3), b = (6ℰQR/(πκE'))^(1/3) with the exact
    κ, ℰ), the inner contact the higher; at F_r = C₀ the inner contact near ISO 76's 4200 MPa;
    a roller slice's p_max
    against the Hertz line contact's half width b = √(8wR/(πE')), p_max = 2w/(πb)."""
    b = jb.catalogue("6205")
    s = jb.solve_displacement(b, jnp.array([2000.0, 0, 0, 0, 0]))
    p = np.asarray(_contact_pressure(b, s.displacement))
    Q = float(_element_loads(b, s.displacement)[0])
    Ep = 2.075e11 / (1 - 0.3**2)
    for col, inner in ((0, True), (1, False)):
        kappa, Ek, _, R = exact_hertz(float(b.element_diameter), float(b.pitch_diameter), 0.0,
                                      0.52, inner)
        a = (6 * kappa**2 * Ek * Q * R / (math.pi * Ep)) ** (1 / 3)
        bb = (6 * Ek * Q * R / (math.pi * kappa * Ep)) ** (1 / 3)
        assert p[0, col] == pytest.approx(3 * Q / (2 * math.pi * a * bb), rel=0.02)
    assert p[0, 0] > p[0, 1]
    assert np.all(p[np.asarray(_element_loads(b, s.displacement)) == 0] == 0)
    # ISO 76: a radial ball bearing's static rating C0 is the load at which the most loaded
    # contact reaches 4200 MPa (its Q_max = 5 F_r / Z; zero clearance gives 4.37: (4.37/5)^(1/3)
    # = 0.956 of it): the 6205 under F_r = C0 = 7.8 kN within 8 %
    s0 = jb.solve_displacement(b, jnp.array([7800.0, 0, 0, 0, 0]))
    assert float(_contact_pressure(b, s0.displacement)[0, 0]) == pytest.approx(4.2e9, rel=0.08)
    r = jb.catalogue("NU 205")
    d = jnp.array([5e-6, 0, 0, 0, 0])
    w = float(_element_loads(r, d)[0, 0]) / (float(r.effective_length) / r.slices)
    g = float(r.element_diameter) / float(r.pitch_diameter)
    R = 0.5 * float(r.element_diameter) * (1 - g)
    half = math.sqrt(8 * w * R / (math.pi * Ep))
    assert float(_contact_pressure(r, d)[0, 0, 0]) == pytest.approx(2 * w / (math.pi * half),
                                                                  rel=1e-12)


# ---------------------------------------------------------------- stiffness


OPERATING = {
    "6205": [12e-6, 3e-6, 20e-6, 2e-4, -1e-4],
    "7205 B": [10e-6, 0, 25e-6, 0, 1e-4],
    "NU 205": [8e-6, 2e-6, 0, 1e-4, 2e-4],
    "30205": [8e-6, -2e-6, 12e-6, 1e-4, 2e-4],
}


@pytest.fixture(scope="module", params=[
    "6205", "30205",
    # default tier: a ball kind (with clearance) and a roller kind (tilted, sliced); the 7205 B's
    # stiffness is checked in the default tier against the closed form below
    pytest.param("7205 B", marks=pytest.mark.slow),
    pytest.param("NU 205", marks=pytest.mark.slow),
])
def kind_at_point(request):
    b = jb.catalogue(request.param, clearance=4e-6 if request.param == "6205" else 0.0)
    return b, jnp.array(OPERATING[request.param])


def test_stiffness_is_the_jacobian_of_the_load(kind_at_point):
    """K = jacfwd(load) against central differences (steps 1e-4 of the displacement scale):
    within 1e-5 of the largest entry of each row, and symmetric."""
    b, d = kind_at_point
    K = np.asarray(b.stiffness(d))
    scale = np.array([1e-6, 1e-6, 1e-6, 1e-4, 1e-4]) * 1e-3
    fd = np.zeros((5, 5))
    for j in range(5):
        e = np.zeros(5)
        e[j] = scale[j]
        fd[:, j] = (np.asarray(_load(b, d + e)) - np.asarray(_load(b, d - e))) / (2 * scale[j])
    row = np.abs(K).max(axis=1, keepdims=True)
    assert np.all(np.abs(K - fd) <= 1e-5 * row + 1e-9)
    assert np.allclose(K, K.T, rtol=0, atol=1e-9 * np.abs(K).max())


def test_load_is_the_gradient_of_the_contact_energy(kind_at_point):
    """The load written out and the gradient of the contact energy agree (two formulas)."""
    b, d = kind_at_point
    np.testing.assert_allclose(_load_by_gradient(b, d), _load(b, d), rtol=1e-10,
                               atol=1e-10 * float(jnp.abs(_load(b, d)).max()))


def lim_singh_ball_stiffness(b, d):
    """Lim & Singh's closed-form stiffness of a ball bearing (Part I: the element stiffness
    ∂(Q cos α, Q sin α)/∂(δ_r, δ_z) with the contact angle following the load, mapped by the
    element's kinematics), written out here with numpy."""
    K, A, rp, Z = float(b.hertz_constant), float(b.curvature_distance), b.pitch_diameter / 2, \
        b.elements
    # the grooves' centres at first touch: a deep groove bearing's at α = 0 less half its
    # clearance radially, an angular contact bearing's at its contact angle
    a0 = 0.0 if isinstance(b, jb.DeepGrooveBall) else float(b.contact_angle)
    out = np.zeros((5, 5))
    for j in range(Z):
        psi = 2 * math.pi * j / Z
        c, s = math.cos(psi), math.sin(psi)
        dr = d[0] * c + d[1] * s
        dz = d[2] + rp * (d[3] * s - d[4] * c)
        ar = A * math.cos(a0) - b.clearance / 2 + dr
        az = A * math.sin(a0) + dz
        L = math.hypot(ar, az)
        delta = L - A
        if delta <= 0:
            continue
        ca, sa = ar / L, az / L
        k1, q = 1.5 * K * delta**0.5, K * delta**1.5
        # element: [Q cos α, Q sin α] against [δ_r, δ_z]
        kin = np.array([[k1 * ca**2 + q * sa**2 / L, (k1 - q / L) * ca * sa],
                        [(k1 - q / L) * ca * sa, k1 * sa**2 + q * ca**2 / L]])
        # δ_r, δ_z from d; (F_x, F_y, F_z, M_x, M_y) from (Q cos α, Q sin α)
        B = np.array([[c, s, 0, 0, 0], [0, 0, 1, rp * s, -rp * c]])
        out += B.T @ kin @ B
    return out


def test_ball_bearing_stiffness_against_lim_and_singh_closed_form():
    """The 6205 (with clearance) and a 40° bearing at combined loads: jacfwd against the
    closed form within 1e-9."""
    for b, d in ((jb.catalogue("6205", clearance=4e-6), OPERATING["6205"]),
                 (jb.catalogue("7205 B"), OPERATING["7205 B"])):
        np.testing.assert_allclose(b.stiffness(jnp.array(d)), lim_singh_ball_stiffness(b, d),
                                   rtol=1e-9, atol=1e-9 * np.abs(b.stiffness(jnp.array(d))).max())


def lim_singh_roller_stiffness(b, d):
    """Lim & Singh's closed form for a roller bearing (fixed contact angle), slice by slice:
    K = Σ (10/9) (K_n/S) δ_jk^(1/9) b_jk b_jkᵀ with b_jk the slice's approach direction
    (cos α cos ψ, cos α sin ψ, sin α, (r_p sin α − x_k cos α) sin ψ,
    (x_k cos α − r_p sin α) cos ψ), written out here with numpy."""
    K, S, Z = float(b.hertz_constant), b.slices, b.elements
    a, rp, length = float(b.nominal_angle), float(b.pitch_diameter) / 2, float(b.effective_length)
    ca, sa = math.cos(a), math.sin(a)
    out = np.zeros((5, 5))
    for j in range(Z):
        psi = 2 * math.pi * j / Z
        c, s = math.cos(psi), math.sin(psi)
        for k in range(S):
            x = ((k + 0.5) / S - 0.5) * length * ca
            theta = d[4] * c - d[3] * s
            delta = (d[0] * c + d[1] * s + x * theta - float(b.clearance) / 2) * ca \
                + (d[2] - rp * theta) * sa
            if delta <= 0:
                continue
            bb = np.array([ca * c, ca * s, sa, (rp * sa - x * ca) * s, (x * ca - rp * sa) * c])
            out += 10 / 9 * K / S * delta ** (1 / 9) * np.outer(bb, bb)
    return out


def test_roller_bearing_stiffness_against_the_sliced_closed_form():
    """The tilted 30205 and NU 205: jacfwd against the closed form within 1e-9."""
    for name in ("30205", "NU 205"):
        b, d = jb.catalogue(name), OPERATING[name]
        K = np.asarray(b.stiffness(jnp.array(d)))
        np.testing.assert_allclose(K, lim_singh_roller_stiffness(b, d), rtol=1e-9,
                                   atol=1e-9 * np.abs(K).max())


def test_radial_stiffness_grows_with_load_as_hertz_says():
    """A zero-clearance ball bearing's radial stiffness ∝ F_r^(1/3) (δ ∝ F^(2/3)): the ratio
    over an 8-fold load is 2 within 1e-6."""
    b = jb.catalogue("6205")
    k = [float(b.stiffness(jnp.array([dx, 0, 0, 0, 0]))[0, 0]) for dx in (1e-6, 4e-6)]
    f = [float(_load(b, jnp.array([dx, 0, 0, 0, 0]))[0]) for dx in (1e-6, 4e-6)]
    assert f[1] / f[0] == pytest.approx(8.0, rel=1e-9)
    assert k[1] / k[0] == pytest.approx(2.0, rel=1e-6)


def test_stiffness6_is_a_scene_bearing_matrix():
    """The 6×6 at an operating point is what :class:`jaxgear.scenes.Bearing` takes (symmetric,
    positive semi-definite, row φ_z zero), and the linear spring's is the scene bearing's own."""
    b = jb.catalogue("30205")
    K6 = np.asarray(b.stiffness6(jnp.array(OPERATING["30205"])))
    scene = js.Bearing(z=0.0, stiffness=K6.tolist())
    np.testing.assert_allclose(scene.stiffness_matrix(), K6, rtol=1e-12)
    spring = jb.LinearSpring(radial=3e8, axial=1e8, tilt=2e5)
    np.testing.assert_array_equal(
        spring.stiffness6(jnp.zeros(5)),
        js.Bearing(z=0.0, radial=3e8, axial=1e8, tilt=2e5).stiffness_matrix())


def test_stiffness_derivative_by_the_clearance_is_finite_and_right():
    """∂K_xx/∂P_d at a displacement where some balls are out of contact (their δ^(n−k) terms
    must not make NaN): against a central difference, within 1e-6."""
    b = jb.catalogue("6205", clearance=10e-6)
    d = jnp.array(OPERATING["6205"])
    assert float(_element_loads(b, d).min()) == 0.0
    kxx = lambda c: eqx.tree_at(lambda x: x.clearance, b, c).stiffness(d)[0, 0]
    g = float(jax.grad(kxx)(jnp.asarray(10e-6)))
    h = 1e-8
    fd = (float(kxx(jnp.asarray(10e-6 + h))) - float(kxx(jnp.asarray(10e-6 - h)))) / (2 * h)
    assert math.isfinite(g) and g == pytest.approx(fd, rel=1e-6)


# ---------------------------------------------------------------- inverse solve


LOADS = {
    "6205": [1500.0, -400.0, 300.0, 4.0, -2.0],
    "7205 B": [1000.0, 0.0, 1500.0, 0.0, 5.0],
    "NU 205": [3000.0, 1000.0, 0.0, 2.0, 0.0],
    "30205": [3000.0, 0.0, 2000.0, 5.0, 0.0],
}


@pytest.mark.parametrize("name", [
    "6205", "30205",
    # default tier: the 6205 (point contact, clearance) and 30205 (line contact, one-way axial)
    # compile the solve of each contact law; the other two kinds in the slow tier
    pytest.param("7205 B", marks=pytest.mark.slow),
    pytest.param("NU 205", marks=pytest.mark.slow),
])
def test_solve_carries_the_load(name):
    """load(solve(F)) = F to 1e-9 of the largest load (moments over the pitch radius), in
    fewer than 100 BFGS and 8 Newton steps; the state's stiffness is the Jacobian there."""
    b = jb.catalogue(name, clearance=10e-6 if name == "6205" else 0.0)
    F = jnp.array(LOADS[name])
    s = jb.solve_displacement(b, F)
    r = b.pitch_diameter / 2
    scaled = lambda f: np.concatenate([np.asarray(f)[:3], np.asarray(f)[3:] / r])
    assert float(s.residual) < 1e-9
    np.testing.assert_allclose(scaled(_load(b, s.displacement)), scaled(F), rtol=0,
                               atol=1e-9 * np.abs(scaled(F)).max())
    assert int(s.steps[0]) < 100 and int(s.steps[1]) < 8
    np.testing.assert_allclose(s.stiffness, b.stiffness(s.displacement), rtol=1e-12,
                               atol=1e-12 * float(jnp.abs(s.stiffness).max()))


@pytest.mark.slow  # its own compiled solve
def test_solve_of_the_linear_spring_is_load_over_stiffness():
    """The spring kind through the same solve: d = F / k on the DOFs it carries, a tilt left
    at 0 where it has no tilt stiffness."""
    s = jb.solve_displacement(jb.LinearSpring(radial=2e8, axial=1e8),
                              jnp.array([1000.0, -300.0, 500.0, 0, 0]))
    np.testing.assert_allclose(s.displacement, [5e-6, -1.5e-6, 5e-6, 0, 0], rtol=1e-10,
                               atol=1e-18)


@pytest.mark.slow  # differentiates through the solve: its own program, ~8 s loaded
def test_solve_derivative_is_the_compliance():
    """∂d/∂F of the solve (optimistix's implicit derivative) is inv(K) at the solution, and
    agrees with a finite difference of two solves; ∂K_xx/∂P_d through the solve agrees with a
    finite difference."""
    b = jb.catalogue("6205", clearance=10e-6)
    F = jnp.array(LOADS["6205"])
    d_of = lambda F: jb.solve_displacement(b, F).displacement
    J = np.asarray(jax.jacfwd(d_of)(F))
    K = np.asarray(b.stiffness(d_of(F)))
    np.testing.assert_allclose(J @ K, np.eye(5), atol=1e-6)
    h = 1.0
    fd = (np.asarray(d_of(F.at[0].add(h))) - np.asarray(d_of(F.at[0].add(-h)))) / (2 * h)
    np.testing.assert_allclose(fd, J[:, 0], rtol=1e-4, atol=1e-6 * np.abs(J[:, 0]).max())
    # the clearance as a design variable: the operating stiffness's derivative through the solve
    kxx = lambda c: jb.solve_displacement(
        eqx.tree_at(lambda x: x.clearance, b, c), F).stiffness[0, 0]
    g = float(jax.grad(kxx)(jnp.asarray(10e-6)))
    h = 1e-8
    fd = (float(kxx(jnp.asarray(10e-6 + h))) - float(kxx(jnp.asarray(10e-6 - h)))) / (2 * h)
    assert g == pytest.approx(fd, rel=1e-5)


def test_stribeck_with_clearance_q_max_is_near_five():
    """With a normal clearance the load zone shrinks below half the raceway (ε < 0.5) and
    Q_max Z / F_r rises above 4.37 towards Stribeck's design value 5 (Harris & Kotzalas):
    the 6205 with 10 µm under 1 kN lies between 4.4 and 5.5 and grows as the clearance does."""
    vals = []
    for c in (0.0, 10e-6, 20e-6):
        b = jb.catalogue("6205", clearance=c)
        s = jb.solve_displacement(b, jnp.array([1000.0, 0, 0, 0, 0]))
        vals.append(float(_element_loads(b, s.displacement).max() * b.elements / 1000.0))
    assert vals[0] == pytest.approx(4.37, rel=1e-2)
    assert 4.4 < vals[1] < 5.5 and vals[0] < vals[1] < vals[2]


# ---------------------------------------------------------------- life and tones


def test_iso281_life_by_hand():
    """ISO 281 L10 of the 6205 (C 14.8 kN, C0 7.8 kN, f0 14) by hand: F_r 2000 N, F_a 500 N:
    f0 F_a/C0 = 0.8974, e = 0.26 + (0.8974 − 0.689)/(1.03 − 0.689) · 0.02 = 0.2722 > 0.25, so
    P = F_r and L10 = 7.4³ = 405.224 million revolutions, 4502.5 h at 1500 rpm; F_r 1000 N,
    F_a 800 N: f0 F_a/C0 = 1.4359, e = 0.3032 < 0.8, Y = 1.45 − 0.0810 · 0.14 = 1.43866,
    P = 560 + 1150.93 = 1710.93 N."""
    b = jb.catalogue("6205")
    life = jb.rating_life(b, 2000.0, 500.0, 1500 * 2 * math.pi / 60)
    assert float(life.equivalent_load) == pytest.approx(2000.0, rel=1e-12)
    assert float(life.revolutions) == pytest.approx(405.224e6, rel=1e-6)
    assert float(life.duration) / 3600 == pytest.approx(4502.49, rel=1e-5)
    x = 14 * 800 / 7800
    Y = 1.45 - (x - 1.38) / (2.07 - 1.38) * (1.45 - 1.31)
    assert Y == pytest.approx(1.43866, rel=1e-5)
    P = float(b.equivalent_load(1000.0, 800.0))
    assert P == pytest.approx(0.56 * 1000 + Y * 800, rel=1e-12)
    assert P == pytest.approx(1710.93, rel=1e-5)
    taper = jb.catalogue("30205", dynamic_rating=35e3)
    # e = 0.37, Y = 0.4 cot α = 0.4 · 1.5 / 0.37 = 1.62162
    assert float(taper.equivalent_load(1000.0, 300.0)) == pytest.approx(1000.0)
    assert float(taper.equivalent_load(1000.0, 500.0)) == pytest.approx(400 + 1.62162 * 500,
                                                                       rel=1e-5)
    life = jb.rating_life(taper, 5000.0, 0.0, 100.0)
    assert float(life.revolutions) == pytest.approx(7.0 ** (10 / 3) * 1e6, rel=1e-12)
    ac = jb.catalogue("7205 B", dynamic_rating=15e3)
    assert float(ac.equivalent_load(1000.0, 2000.0)) == pytest.approx(350 + 0.57 * 2000)


def test_spectrum_life_palmgren_miner_by_hand():
    """Two bins of the 6205 (radial only): 1000 h at 2 kN and 1500 rpm, 500 h at 4 kN and
    750 rpm: n = 9e7 and 2.25e7 revolutions, L10 = 405.224e6 and 50.653e6, damage per pass
    0.222100 + 0.444199, life = 1500 h / 0.666299 = 2251.25 h, P_eq = ((9e7 · 2000³ + 2.25e7
    · 4000³) / 1.125e8)^(1/3) = (1.92e10)^(1/3) = 2677.73 N; one bin is :func:`rating_life`."""
    b = jb.catalogue("6205")
    w = lambda rpm: rpm * 2 * math.pi / 60
    spec = jb.BearingSpectrum([2000.0, 4000.0], [0.0, 0.0], [w(1500), w(750)],
                              [1000 * 3600.0, 500 * 3600.0])
    life = jb.spectrum_life(b, spec)
    D = 9e7 / 405.224e6 + 2.25e7 / 50.653e6
    assert float(life.duration) / 3600 == pytest.approx(1500 / D, rel=1e-5)
    assert float(life.duration) / 3600 == pytest.approx(2251.25, rel=1e-4)
    assert float(life.equivalent_load) == pytest.approx(2677.73, rel=1e-5)
    one = jb.spectrum_life(b, jb.BearingSpectrum([2000.0], [500.0], w(1500), [3600.0]))
    ref = jb.rating_life(b, 2000.0, 500.0, w(1500))
    assert float(one.duration) == pytest.approx(float(ref.duration), rel=1e-12)


def test_tones_against_the_cwru_6205():
    """The 6205-2RS JEM's defect frequencies as multiples of the shaft speed, as the CWRU
    Bearing Data Center publishes them: BPFI 5.4152, BPFO 3.5848, FTF 0.39828, and 4.7135 for
    the ball (twice the spin: a ball defect strikes both races each spin turn)."""
    t = jb.bearing_tones(jb.catalogue("6205"))
    assert float(t.bpfi) == pytest.approx(5.4152, abs=1e-4)
    assert float(t.bpfo) == pytest.approx(3.5848, abs=1e-4)
    assert float(t.ftf) == pytest.approx(0.39828, abs=5e-5)
    assert 2 * float(t.bsf) == pytest.approx(4.7135, abs=1e-4)
    hz = t.at(1797 * 2 * math.pi / 60)  # the rig's 1797 rpm
    assert float(hz.bpfi) == pytest.approx(5.4152 * 1797 / 60, rel=2e-5)


# ---------------------------------------------------------------- refusals


GEOM = dict(bore=0.025, outer_diameter=0.052, width=0.015, elements=9,
            element_diameter=0.008, pitch_diameter=0.0385)


@pytest.mark.parametrize("build,words", [
    (lambda: jb.DeepGrooveBall(**{**GEOM, "element_diameter": 0.015}),
     "element_diameter = 0.015 m is out of range"),
    (lambda: jb.AngularContactBall(**GEOM, contact_angle=math.pi / 2), "contact_angle"),
    (lambda: jb.DeepGrooveBall(**GEOM, clearance=0.009), "clearance = 0.009 m"),
    (lambda: jb.DeepGrooveBall(**{**GEOM, "elements": 20}), "elements = 20"),
    (lambda: jb.DeepGrooveBall(**{**GEOM, "pitch_diameter": 0.03}), "pitch_diameter = 0.03"),
    (lambda: jb.DeepGrooveBall(**GEOM, inner_conformity=0.5), "inner_conformity = 0.5"),
    (lambda: jb.CylindricalRoller(**GEOM, effective_length=0.02), "effective_length = 0.02"),
    (lambda: jb.CylindricalRoller(**GEOM, effective_length=0.01, slices=0), "slices = 0"),
    (lambda: jb.TaperedRoller(**GEOM, effective_length=0.01, contact_angle=0.0),
     "contact_angle = 0"),
    (lambda: jb.LinearSpring(radial=-1.0), "radial = -1"),
    (lambda: jb.catalogue("6206"), "designation = '6206'"),
    (lambda: jb.solve_displacement(jb.catalogue("NU 205"), [1000.0, 0, 50.0, 0, 0]),
     "load[2] (F_z) = 50"),
    (lambda: jb.solve_displacement(jb.catalogue("7205 B"), [1000.0, 0, 100.0, 0, 0]),
     "load[2] (F_z) = 100 N"),
    (lambda: jb.rating_life(jb.LinearSpring(), 1000.0, 0.0, 100.0), "LinearSpring"),
    (lambda: jb.rating_life(jb.catalogue("NU 205"), 1000.0, 0.0, 100.0), "dynamic_rating"),
    (lambda: jb.bearing_tones(jb.LinearSpring()), "no rolling elements"),
    (lambda: jb.catalogue("6205", iso281_f0=None).equivalent_load(1.0, 1.0), "iso281_f0"),
    (lambda: jb.catalogue("7205 B", contact_angle=0.5).equivalent_load(1.0, 1.0),
     "contact_angle = 28.6479 deg"),
    (lambda: jb.LinearSpring().element_loads(jnp.zeros(5)), "no rolling elements"),
    (lambda: jb.LinearSpring().contact_pressure(jnp.zeros(5)), "no rolling elements"),
    (lambda: jb.solve_displacement(jb.LinearSpring(), [1.0, 0, 0, 2.0, 0]),
     "load[3] (M_x) = 2 on a DOF LinearSpring does not carry"),
    (lambda: jb.solve_displacement(jb.catalogue("6205"), [1.0, 0, 0]), "load"),
    (lambda: jb.BearingSpectrum([1.0, 2.0], [0.0], 10.0, [1.0, 1.0]), "axial"),
])
def test_bad_bearing_data_is_refused_in_one_line(build, words):
    refused_in_one_line(build, words)


def refused_in_one_line(call, words: str) -> None:
    """``call()`` raises a one-line ValueError holding ``words`` and the allowed range (or the
    shape asked); the bearing life tests use it too."""
    with pytest.raises(ValueError) as err:
        call()
    msg = str(err.value)
    assert words in msg and "\n" not in msg, msg
    assert "allowed" in msg or "must have shape" in msg, msg


#: SKF's "Rolling bearings" (PUB BU/P1 17000/1 EN, 2018) rows as github.com/gumyr/bd_warehouse
#: (9d0dc94) transcribes them: designation -> (d, D, B or T mm, C kN, C0 kN, e or None)
_SKF_ROWS = {"7305 BE": (25, 62, 17, 26.5, 15.3, None),  # 7305 BECBPH, 40°
             "30305": (25, 62, 18.25, 44.6, 43.0, 0.3),  # 30305 J2/Q
             "32205": (25, 52, 19.25, 35.8, 44.0, 0.57)}  # 32205 BJ2/Q


@pytest.mark.parametrize("name", sorted(_SKF_ROWS))
def test_catalogue_rows_transcribe_skf(name):
    """The 7305 BE, 30305 and 32205 entries: d, D, B (a tapered row's T), C, C0 and the contact
    angle (40°; a tapered row's α = atan(e/1.5)) as SKF's table gives them (1e-12); their
    rolling elements by the stated estimates (balls D_w = 0.3 (D - d), rollers (D - d)/4,
    d_m = (D + d)/2, Z the whole part of 0.8 π d_m / D_w; a roller's l = 0.7 T); each a 25 mm
    bore."""
    d, D, B, C, C0, e = _SKF_ROWS[name]
    b = jb.catalogue(name)
    got = [float(x) for x in (b.bore, b.outer_diameter, b.width, b.dynamic_rating,
                              b.static_rating, b.pitch_diameter)]
    np.testing.assert_allclose(got, [d * 1e-3, D * 1e-3, B * 1e-3, C * 1e3, C0 * 1e3,
                                     (D + d) / 2 * 1e-3], rtol=1e-12)
    angle = math.radians(40.0) if e is None else math.atan(e / 1.5)
    assert float(b.contact_angle) == pytest.approx(angle, rel=1e-12)
    Dw = (0.3 if e is None else 0.25) * (D - d)
    assert float(b.element_diameter) * 1e3 == pytest.approx(Dw, rel=1e-12)
    assert b.elements == int(0.8 * math.pi * (D + d) / 2 / Dw)
    if e is not None:
        assert isinstance(b, jb.TaperedRoller)
        assert float(b.effective_length) * 1e3 == pytest.approx(0.7 * B, rel=1e-12)
    else:
        assert isinstance(b, jb.AngularContactBall)


def test_estimated_balls_near_the_6205s():
    """The ball rule against a published ball set: the 6205 (CWRU's d 0.9843, D 2.0472 in;
    ball 0.3126 in, pitch 1.537 in): D_w = 0.3 (D - d) within 2.5 % of the ball, d_m = (D + d)/2
    within 2 % of the pitch."""
    d, D = 0.9843 * 0.0254, 2.0472 * 0.0254
    est = jb.estimated_balls(d, D)
    assert est["element_diameter"] == pytest.approx(0.3126 * 0.0254, rel=0.025)
    assert est["pitch_diameter"] == pytest.approx(1.537 * 0.0254, rel=0.02)
