"""ISO/TS 6336-22 micropitting along jaxgear's path of contact
(jaxgear.tribology.mesh_micropitting).

References: the TS's film formula, bulk temperature and pressure–viscosity law written again here
in the TS's own units (mm, µm, N/mm², kW; ISO/TR 15144-1:2014 formulae (4), (8), (12), (22),
(84) as transcribed in hakangunes258/mekanika, Services/Iso15144Micropitting.cs); the analytic
ratio of the TS's film to Dowson's 1968 minimum film; the points of the TS's Figure A.1 as that
source digitised them; S_λ and λ_GF,min from the per-cell λ.
"""

from __future__ import annotations

import functools
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_tribology import _mesh  # the same pair table (Weber at 200 N·m)

import jaxgear as jg
import jaxgear.tribology as tr

E, NU = 206e9, 0.3
RA = (0.5e-6, 0.5e-6)
SPEED = 1500 * 2 * math.pi / 60
TORQUE = 200.0


def _e_star():
    return E / (2.0 * (1.0 - NU**2))


@pytest.mark.parametrize(
    "R, u, w, eta, alpha",
    [
        (6e-3, 5.0, 3.0e5, 0.05, 20e-9),  # a gear contact
        (2e-3, 0.5, 8.0e5, 0.01, 15e-9),  # tight, slow, heavy
        (20e-3, 20.0, 1.5e5, 0.2, 25e-9),  # large, fast, viscous
    ],
)
def test_ts_film_in_the_ts_units(R, u, w, eta, alpha):
    """The TS's h_Y = 1600 ρ_n G^0.6 U^0.7 W^−0.13 (µm, ρ_n in mm) with U = η v_Σ/(2000 E_r ρ_n),
    G = 10⁶ α E_r, W = 2π p²/E_r² (E_r, p in N/mm²) against jaxgear's SI film kind."""
    e_r = 2.0 * _e_star() * 1e-6  # N/mm²
    rho = R * 1e3  # mm
    p = math.sqrt(w * _e_star() / (math.pi * R)) * 1e-6  # Hertz, N/mm²
    U = eta * (2.0 * u) / (2000.0 * e_r * rho)
    G = 1e6 * alpha * e_r
    W = 2.0 * math.pi * p**2 / e_r**2
    h_um = 1600.0 * rho * G**0.6 * U**0.7 * W**-0.13
    h = tr.film_thickness(tr.TSMicropittingFilm(), R, u, w, eta, alpha, _e_star()).minimum
    assert float(h) * 1e6 == pytest.approx(h_um, rel=1e-12)


def test_ts_film_against_dowson_1968():
    """1.6 G^0.6 U^0.7 W^−0.13 over Dowson's 2.65 U^0.70 G^0.54 W^−0.13 is (1.6/2.65) G^0.06,
    whatever U and W: the two agree at α 20 GPa⁻¹ (G ≈ 4500) and the TS's is 8 % thicker at
    α 70 GPa⁻¹."""
    for alpha in (10e-9, 20e-9, 70e-9):
        args = (5e-3, 4.0, 2e5, 0.03, alpha, _e_star())
        ts = tr.film_thickness(tr.TSMicropittingFilm(), *args).minimum
        dh = tr.film_thickness(tr.DowsonHigginson(), *args).minimum
        G = alpha * 2.0 * _e_star()
        assert float(ts / dh) == pytest.approx(1.6 / 2.65 * G**0.06, rel=1e-12)
    assert 1.6 / 2.65 * (20e-9 * 2.0 * _e_star()) ** 0.06 == pytest.approx(1.0, abs=0.005)
    assert 1.6 / 2.65 * (70e-9 * 2.0 * _e_star()) ** 0.06 == pytest.approx(1.08, abs=0.005)


def test_bulk_temperature_in_the_ts_units():
    """θ_M = θ_oil + 7400 (P_VZP/(a b))^0.72 X_S/(1.2 X_Ca), P_VZP in kW, a and b in mm."""
    for p_w, xs, xca in ((291.0, 1.0, 1.0), (2500.0, 1.2, 1.0), (800.0, 1.0, 1.3)):
        ref = 75.0 + 7400.0 * (p_w / 1000.0 / (91.5 * 14.0)) ** 0.72 * xs / (1.2 * xca)
        got = tr.micropitting_bulk_temperature(p_w, 0.0915, 0.014, 75.0, xs, xca)
        assert float(got) == pytest.approx(ref, rel=1e-12)
    with pytest.raises(ValueError, match=r"lubrication_factor = 3") as err:
        tr.micropitting_bulk_temperature(100.0, 0.0915, 0.014, 75.0, 3.0)
    assert "\n" not in str(err.value)


def test_pressure_viscosity_temperature_law():
    """α_θ/α_38 = 1 + 516 (1/(θ + 273) − 1/311): 1 at 38 °C, falling with the temperature."""
    assert float(tr.pressure_viscosity_temperature_factor(38.0)) == pytest.approx(1.0)
    f = np.asarray(tr.pressure_viscosity_temperature_factor(jnp.array([40.0, 90.0, 150.0])))
    assert np.all(np.diff(f) < 0)
    assert f[1] == pytest.approx(1.0 + 516.0 * (1.0 / 363.0 - 1.0 / 311.0))


#: ISO/TR 15144-1:2014 Figure A.1 as digitised in hakangunes258/mekanika (ν₄₀ mm²/s: λ_GFP at
#: SKS 5, at SKS 10)
FIGURE_A1 = {
    32.0: (0.130, 0.055),
    100.0: (0.250, 0.090),
    220.0: (0.400, 0.145),
    460.0: (0.570, 0.200),
}


def test_figure_a1_points_and_shape():
    for nu, (at5, at10) in FIGURE_A1.items():
        assert tr.figure_a1_permissible_film(5, nu * 1e-6) == pytest.approx(at5)
        assert tr.figure_a1_permissible_film(10, nu * 1e-6) == pytest.approx(at10)
    stages = [tr.figure_a1_permissible_film(s, 316e-6) for s in (5, 6, 7, 8, 9, 10)]
    assert np.all(np.diff(stages) < 0)  # a stronger oil (later failure) tolerates a thinner film
    vgs = [tr.figure_a1_permissible_film(8, nu * 1e-6) for nu in (32, 68, 150, 320, 460)]
    assert np.all(np.diff(vgs) > 0)
    for bad, match in (((4, 316e-6), r"load_stage = 4"), ((8, 680e-6), r"viscosity_40 = 0.00068")):
        with pytest.raises(ValueError, match=match) as err:
            tr.figure_a1_permissible_film(*bad)
        assert "\n" not in str(err.value)


@functools.cache
def _c14_result():
    """The FZG C-type pair (m 4.5, z 16/24, b 14 mm) at 200 N·m: its pair and contact solve."""
    members = [jg.Member(z, x, 1.0, 1.25, 0.014, 0.38) for z, x in ((16, 0.1817), (24, 0.1715))]
    pair = jg.GearPair(*members, 4.5e-3, math.radians(20.0), 0.0)
    return pair, jg.quasi_static(_mesh(pair, 1), None, TORQUE, positions_per_pitch=32).mesh


@functools.cache
def _c14():
    """That pair at 1500 rpm with an ISO VG 320 oil at 75 °C: its film and loss along the path."""
    pair, res = _c14_result()
    lub = tr.Lubricant(316e-6, 22.2e-6, 902.0, 25e-9, 75.0, 5.8e-4)
    trib = tr.mesh_tribology(pair, res, lub, TORQUE, SPEED, RA, E, NU)
    return pair, lub, trib


def test_isothermal_limit_is_the_ts_film_of_the_path():
    """With θ_M = θ_oil given and no flash temperature (huge B_M), S_GF = 1 and λ_GF,Y is the TS
    film at the oil temperature from jaxgear's R, u and w over the mean R_a."""
    pair, lub, trib = _c14()
    mp = tr.mesh_micropitting(
        pair, trib, lub, RA, E, NU, 0.2, bulk_temperature=75.0, thermal_coefficients=(1e12, 1e12)
    )
    L = np.asarray(trib.loaded)
    h = tr.film_thickness(
        tr.TSMicropittingFilm(),
        np.asarray(trib.radius)[L],
        np.asarray(trib.entrainment_speed)[L],
        np.asarray(trib.line_load)[L],
        float(lub.dynamic_viscosity),
        float(lub.pressure_viscosity),
        _e_star(),
    ).minimum
    np.testing.assert_allclose(np.asarray(mp.sliding_parameter)[L], 1.0, atol=1e-9)
    np.testing.assert_allclose(np.asarray(mp.specific_film)[L], np.asarray(h) / 0.5e-6, rtol=1e-6)


def test_sliding_parameter_and_safety_factor():
    """S_GF,Y = α_B η_B/(α_M η_M) from the lubricant's Walther line and the TS's α law at the
    cells' contact temperatures; λ_GF,min the smallest λ over the loaded cells; S_λ its ratio to
    λ_GFP; the TS's bulk rule with the mesh's P_VZP."""
    pair, lub, trib = _c14()
    mp = tr.mesh_micropitting(pair, trib, lub, RA, E, NU, 0.25)
    L = np.asarray(mp.loaded)
    a_mm = pair.center_distance * 1e3  # 91.5 mm
    theta_m = 75.0 + 7400.0 * (float(trib.mean_power_loss) / 1e3 / (a_mm * 14.0)) ** 0.72 / 1.2
    assert float(mp.bulk_temperature) == pytest.approx(theta_m, rel=1e-9)
    theta_b = np.asarray(mp.contact_temperature)[L]

    def eta(t):
        return np.asarray(lub.kinematic_viscosity(t)) * 902.0 * (1 - 5.8e-4 * (t - 15.0))

    def alpha(t):
        return 1.0 + 516.0 * (1.0 / (t + 273.0) - 1.0 / 311.0)

    ref = alpha(theta_b) * eta(theta_b) / (alpha(theta_m) * eta(np.array(theta_m)))
    np.testing.assert_allclose(np.asarray(mp.sliding_parameter)[L], ref, rtol=1e-9)
    assert np.all(ref <= 1.0 + 1e-12)  # hotter contacts thin the film
    lam = np.asarray(mp.specific_film)[L]
    assert float(mp.min_specific_film) == pytest.approx(lam.min())
    assert float(mp.safety_factor) == pytest.approx(lam.min() / 0.25)
    with pytest.raises(
        ValueError, match=r"permissible_specific_film = 0 .*allowed \(0, 10\]"
    ) as err:
        tr.mesh_micropitting(pair, trib, lub, RA, E, NU, 0.0)
    assert "\n" not in str(err.value)


def test_gradient_wrt_oil_temperature_and_float32():
    """S_λ and λ_GF,min through the oil temperature (viscosity, bulk and contact temperatures,
    S_GF, the smallest cell): jax.grad against central differences; float32 against float64."""
    pair, res = _c14_result()

    def f(t_oil):
        oil = tr.Lubricant(316e-6, 22.2e-6, 902.0, 25e-9, t_oil, 5.8e-4)
        trib = tr.mesh_tribology(pair, res, oil, TORQUE, SPEED, RA, E, NU)
        mp = tr.mesh_micropitting(pair, trib, oil, RA, E, NU, 0.25)
        return mp.safety_factor

    t0, h = 75.0, 1e-3
    g = float(jax.grad(f)(jnp.asarray(t0)))
    fd = (float(f(jnp.asarray(t0 + h))) - float(f(jnp.asarray(t0 - h)))) / (2 * h)
    assert g < 0  # a hotter oil, a thinner film
    assert g == pytest.approx(fd, rel=1e-5)
    want = float(f(jnp.asarray(t0)))
    with jax.enable_x64(False):
        res32 = jax.tree.map(lambda x: x.astype(np.float32) if x.dtype == np.float64 else x, res)
        oil = tr.Lubricant(316e-6, 22.2e-6, 902.0, 25e-9, 75.0, 5.8e-4)
        trib = tr.mesh_tribology(pair, res32, oil, TORQUE, SPEED, RA, E, NU)
        mp = tr.mesh_micropitting(pair, trib, oil, RA, E, NU, 0.25)
        assert mp.specific_film.dtype == np.float32
        assert float(mp.safety_factor) == pytest.approx(want, rel=1e-4)
