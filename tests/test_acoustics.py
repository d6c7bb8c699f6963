"""Radiated noise: the Rayleigh integral (fem_prep.acoustics) against the baffled piston's
radiation resistance and Wallace's (1972) plate radiation efficiencies, the power against the
far-field intensity integrated over a hemisphere, the cache, and the JAX power, its gradient,
levels and the A weighting (jaxgear.acoustics) against IEC 61672-1's table and central
differences. The BEM's checks (bempp-cl, a numba compile of about 60 s of CPU per process) are in
tests/test_acoustics_bem.py."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy import integrate, special

import fem_prep.acoustics as fa
import jaxgear.acoustics as ja

AIR = fa.AIR


def _freq(ka, a=1.0):
    return ka * AIR.sound_speed / (2 * np.pi * a)


# -- the baffled circular piston (Rayleigh) ------------------------------------------------------


@pytest.mark.parametrize(("ka", "published"), [(0.5, 0.1199), (1.0, 0.4233), (2.0, 1.0330)])
def test_baffled_piston_radiation_resistance(ka, published):
    """R₁(ka) = W / (½ρc πa² v²) = 1 - J₁(2ka)/(ka) (Kinsler et al. §7.5) for a rigid piston in a
    baffle, by the Rayleigh resistance matrix on a disc of 10 rings (600 triangles) and the
    JAX quadratic form: within 1 % of the tabulated values (and of the Bessel formula)."""
    assert 1 - special.j1(2 * ka) / ka == pytest.approx(published, abs=6e-5)
    disc = fa.disc_panel(1.0, 10)
    R = fa.rayleigh_resistance(disc, _freq(ka))
    W = ja.radiated_power(jnp.ones(disc.n_vertices, complex), R)
    R1 = float(W) / (0.5 * AIR.impedance * np.pi)
    assert R1 == pytest.approx(published, rel=0.01)


@pytest.mark.slow
def test_baffled_piston_converges():
    """The piston's error falls with refinement (about as h²: the disc's polygon area) and is
    below 0.2 % at 16 rings."""
    ka = 1.0
    exact = 1 - special.j1(2 * ka) / ka
    errs = []
    for rings in (4, 8, 16):
        d = fa.disc_panel(1.0, rings)
        W = np.sum(fa.rayleigh_resistance(d, _freq(ka)))
        errs.append(abs(W / (0.5 * AIR.impedance * np.pi) / exact - 1))
    assert errs[0] > 3 * errs[1] > 9 * errs[2]
    assert errs[2] < 2e-3


# -- the simply supported plate against Wallace (1972) ------------------------------------------


def _wallace_sigma(m, n, ka, kb):
    """Wallace, JASA 51 (1972) 946, eq. (8): the radiation efficiency of the (m, n) mode of a
    baffled simply supported a × b plate, from its far field, by adaptive quadrature."""

    def term(x, j):
        return (np.cos(x / 2) if j % 2 else np.sin(x / 2)) / ((x / (j * np.pi)) ** 2 - 1)

    def f(phi, theta):
        al, be = ka * np.sin(theta) * np.cos(phi), kb * np.sin(theta) * np.sin(phi)
        return (term(al, m) * term(be, n)) ** 2 * np.sin(theta)

    val, _ = integrate.dblquad(f, 0, np.pi / 2, 0, np.pi / 2, epsabs=0, epsrel=1e-9)
    return 64 * ka * kb / (np.pi**6 * m**2 * n**2) * val


def _wallace_low_ka(m, n, ka, kb):
    """Wallace (1972), eq. (12): the low-frequency asymptote for odd m, n."""
    a_b = ka / kb
    return (
        32
        * ka
        * kb
        / (np.pi**5 * m**2 * n**2)
        * (1 - ka * kb / 12 * ((1 - 8 / (m * np.pi) ** 2) * a_b + (1 - 8 / (n * np.pi) ** 2) / a_b))
    )


def _plate_sigma(m, n, ka, a=1.0, b=0.8, cells=(20, 16)):
    plate = fa.rectangular_panel(a, b, *cells)
    x, y = plate.vertices[:, 0], plate.vertices[:, 1]
    v = jnp.asarray(np.sin(m * np.pi * x / a) * np.sin(n * np.pi * y / b) + 0j)
    R = fa.rayleigh_resistance(plate, _freq(ka, a))
    M = plate.mass_matrix()
    return float(ja.radiation_efficiency(v, R, M, AIR.density, AIR.sound_speed))


@pytest.mark.parametrize(("m", "n", "ka"), [(1, 1, 0.5), (1, 1, 3.0), (2, 1, 6.0), (1, 1, 12.0)])
def test_plate_radiation_efficiency_against_wallace(m, n, ka):
    """A baffled simply supported 1 m × 0.8 m plate's modal radiation efficiency (Rayleigh
    resistance on 20 × 16 cells) against Wallace's exact far-field integral, eq. (8), within
    1 % (the issue asks for 5 %; measured ≤ 0.011 %): below coincidence (ka = 0.5, 3), near it and above (ka = 6 for (2, 1); 12 for (1, 1),
    σ → 1)."""
    ref = _wallace_sigma(m, n, ka, 0.8 * ka)
    assert _plate_sigma(m, n, ka) == pytest.approx(ref, rel=0.01)


def test_plate_low_frequency_against_wallace_asymptote():
    """Well below coincidence Wallace's eq. (12) holds: the (1, 1) and (3, 1) modes at
    ka = 0.3 within 1 % of it (measured ≤ 0.06 %; eq. (8) agrees with eq. (12) there within
    1 %, measured 3e-5)."""
    for m, n in ((1, 1), (3, 1)):
        ka = 0.3
        ref = _wallace_low_ka(m, n, ka, 0.8 * ka)
        assert _wallace_sigma(m, n, ka, 0.8 * ka) == pytest.approx(ref, rel=0.01)
        assert _plate_sigma(m, n, ka) == pytest.approx(ref, rel=0.01)


# -- energy: power = far-field intensity over a hemisphere --------------------------------------


def _hemisphere(radius, n_theta=40, n_phi=80):
    """Gauss–Legendre in cos θ on (0, 1) × the trapezoid rule in φ: points ``(q, 3)`` and
    weights (m²) of the hemisphere z > 0."""
    u, wu = np.polynomial.legendre.leggauss(n_theta)
    c, wc = 0.5 * (u + 1), 0.5 * wu
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    C, P = np.meshgrid(c, phi, indexing="ij")
    s = np.sqrt(1 - C**2)
    pts = radius * np.stack([s * np.cos(P), s * np.sin(P), C], -1).reshape(-1, 3)
    w = (radius**2 * np.outer(wc, np.full(n_phi, 2 * np.pi / n_phi))).ravel()
    return pts, w


def test_rayleigh_power_equals_far_field_intensity():
    """The power of a panel vibrating in an asymmetric complex pattern, vᴴ R v, equals
    ∫ |p|²/(2ρc) dS over a hemisphere of radius 50 m (kr ≈ 900) with p by the Rayleigh
    integral, within 1 %."""
    plate = fa.rectangular_panel(0.6, 0.4, 12, 8)
    x, y = plate.vertices[:, 0], plate.vertices[:, 1]
    v = np.sin(np.pi * x / 0.6) * np.sin(2 * np.pi * y / 0.4) + 0.5j * x * y
    f = 1000.0
    W = float(ja.radiated_power(jnp.asarray(v), fa.rayleigh_resistance(plate, f)))
    pts, w = _hemisphere(50.0)
    p = fa.rayleigh_pressure(plate, f, v, pts + [0.3, 0.2, 0.0])
    W_far = np.sum(w * np.abs(p) ** 2) / (2 * AIR.impedance)
    assert W_far == pytest.approx(W, rel=0.01)


def test_rayleigh_pressure_on_axis_of_piston():
    """On the axis of a baffled piston |p| = 2ρc v |sin(k(√(z²+a²) - z)/2)| (Kinsler §7.4) at
    z = 2a and ka = 2 within 1 %."""
    disc = fa.disc_panel(0.1, 12)
    ka, z = 2.0, 0.2
    f, k = _freq(ka, 0.1), ka / 0.1
    p = fa.rayleigh_pressure(disc, f, np.ones(disc.n_vertices), [[0.0, 0.0, z]])
    ref = 2 * AIR.impedance * abs(np.sin(k * (np.hypot(z, 0.1) - z) / 2))
    assert abs(p[0]) == pytest.approx(ref, rel=0.01)


# -- the cache -----------------------------------------------------------------------------------


def test_radiation_resistance_cache_and_low_rank(tmp_path):
    """radiation_resistance stores one entry and reads it back unchanged; the full factor
    rebuilds R (against rayleigh_resistance directly); the rank-r form's power error is bounded
    by the dropped eigenvalues, λ_{r+1} ‖v‖² (Elliott & Johnson's radiation modes)."""
    plate = fa.rectangular_panel(0.5, 0.5, 8, 8)
    freqs = [200.0, 800.0]
    full = fa.radiation_resistance(plate, freqs, method=fa.Rayleigh(), cache=tmp_path)
    assert len(list(tmp_path.glob("*.npz"))) == 1
    again = fa.radiation_resistance(plate, freqs, method=fa.Rayleigh(), cache=tmp_path)
    np.testing.assert_array_equal(again.factors, full.factors)
    R = fa.rayleigh_resistance(plate, 800.0)
    np.testing.assert_allclose(full.matrix(1), R, atol=1e-9 * np.abs(R).max())
    rng = np.random.default_rng(0)
    v = rng.normal(size=plate.n_vertices) + 1j * rng.normal(size=plate.n_vertices)
    low = fa.radiation_resistance(plate, freqs, method=fa.Rayleigh(), rank=6, cache=False)
    W = np.asarray(ja.radiated_power(v, jnp.stack([full.matrix(0), full.matrix(1)])))
    W6 = np.asarray(ja.radiated_power_low_rank(v, low.factors))
    bound = low.eigenvalues[:, 6] * np.vdot(v, v).real
    assert np.all(W6 <= W * (1 + 1e-12)) and np.all(W - W6 <= bound)
    assert W6[0] == pytest.approx(W[0], rel=1e-3)  # at 200 Hz (ka ≈ 1) 6 modes carry it all


def test_bad_input_is_named():
    with pytest.raises(ValueError, match="frequencies_hz"):
        fa.radiation_resistance(fa.rectangular_panel(1, 1, 2, 2), [0.0], cache=False)
    with pytest.raises(ValueError, match="closed"):
        fa.bem_impedance(fa.rectangular_panel(1, 1, 2, 2), 100.0)
    with pytest.raises(ValueError, match="flat open panel"):
        fa.rayleigh_resistance(fa.sphere_surface(1.0, 1), 100.0)
    with pytest.raises(ValueError, match="density"):
        fa.Fluid(density=-1.0)
    with pytest.raises(TypeError, match="formulation"):
        fa.BEM("burton-miller")
    with pytest.raises(TypeError, match="backend"):
        fa.BEM(backend="opencl")
    with pytest.raises(TypeError, match="backend"):
        fa.bem_impedance(fa.sphere_surface(1.0, 1), 100.0, backend="numba")


# -- JAX: power, gradient, levels, A weighting ---------------------------------------------------


def test_power_gradient_matches_central_differences():
    """dW/dθ of W(θ) = Re(v(θ)ᴴ R v(θ)), v(θ) = v₀ + θ e^{iθ} u through the Rayleigh R, by
    jax.grad against central differences (h = 1e-5) within 1e-6 relative."""
    plate = fa.rectangular_panel(0.4, 0.3, 6, 5)
    R = jnp.asarray(fa.rayleigh_resistance(plate, 700.0))
    x = plate.vertices[:, 0]
    v0, u = jnp.asarray(np.sin(np.pi * x / 0.4) + 0j), jnp.asarray(x * (0.4 - x) + 0.3j)

    def W(t):
        return ja.radiated_power(v0 + t * jnp.exp(1j * t) * u, R)

    t, h = 0.7, 1e-5
    fd = (W(t + h) - W(t - h)) / (2 * h)
    assert float(jax.grad(W)(t)) == pytest.approx(float(fd), rel=1e-6)


# IEC 61672-1:2013 Table 3, the A weighting at the nominal frequencies (dB, to 0.1 dB)
IEC_A = {
    10: -70.4,
    31.5: -39.4,
    63: -26.2,
    100: -19.1,
    125: -16.1,
    250: -8.6,
    500: -3.2,
    1000: 0.0,
    2000: 1.2,
    4000: 1.0,
    8000: -1.1,
    10000: -2.5,
    16000: -6.6,
}


def test_a_weighting_against_iec_61672_table():
    """The A weighting at the exact base-ten frequencies 1000·10^(i/10) (Table 3's nominal
    frequencies are rounded) against the table within 0.05 dB."""
    nominal = np.array(list(IEC_A))
    exact = 1000 * 10 ** (np.round(10 * np.log10(nominal / 1000)) / 10)
    got = np.asarray(ja.a_weighting(exact))
    np.testing.assert_allclose(got, list(IEC_A.values()), atol=0.051)


def test_levels():
    """L_W of 1 W is 120 dB re 1 pW; two equal sources add 3.01 dB; the A-weighted sum of
    1 mW at 1 kHz and 1 mW at 100 Hz is 10 log10(1e9 Σ 10^(A/10)) dB(A); L_p of a
    1 Pa rms tone is 93.98 dB re 20 µPa."""
    assert float(ja.sound_power_level(1.0)) == pytest.approx(120.0)
    assert float(ja.level_sum(jnp.array([80.0, 80.0]))) == pytest.approx(80 + 10 * np.log10(2))
    lwa = ja.a_weighted_power_level(jnp.array([1e-3, 1e-3]), jnp.array([1000.0, 100.0]))
    a = np.asarray(ja.a_weighting(jnp.array([1000.0, 100.0])))  # A(1 kHz) is 0 to 2 mdB
    assert float(lwa) == pytest.approx(10 * np.log10(1e9 * np.sum(10 ** (a / 10))))
    assert float(ja.sound_pressure_level(np.sqrt(2.0))) == pytest.approx(20 * np.log10(1 / 20e-6))


def test_normal_velocity_of_a_rigid_translation():
    """On a sphere the area-weighted vertex normals tend to the radius: the normal component
    of a rigid translation v₀ e_z tends to v₀ z/a (the oscillating sphere's), the largest
    error halving per refinement (first order in h; measured 6 % and 3 % of v₀ at 66 and 258
    vertices)."""
    errs = []
    for level in (2, 3):
        s = fa.sphere_surface(1.0, level)
        vel = np.tile([0.0, 0.0, 1e-3], (s.n_vertices, 1))
        errs.append(np.max(np.abs(s.normal_velocity_of(vel) - 1e-3 * s.vertices[:, 2])) / 1e-3)
    assert errs[0] > 1.8 * errs[1] and errs[1] < 0.04
    with pytest.raises(ValueError, match="velocity"):
        s.normal_velocity_of(np.zeros((3, 3)))
