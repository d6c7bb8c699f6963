"""The one Willis relation (:func:`jaxgear.planetary.central_speeds`,
:func:`jaxgear.planetary.central_torques`) and the one overlap rule of a gear layout
(:func:`jaxgear.planetary.closest_planets`, the train case files).

References written here: the textbook ratios of a simple stage (ring fixed, sun in, carrier
out: ω_c = ω_s z_s/(z_s + z_r); carrier fixed: ω_r = −ω_s z_s/z_r; sun fixed, ring in:
ω_c = ω_r z_r/(z_s + z_r)), a lossless stage's power balance Σ T ω = 0 and torque balance
Σ T = 0, and the chord 2 a sin(Δψ/2) between planets on their circle.
"""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.planetary as jp

SUN, RING, CARRIER = jp.Central.SUN, jp.Central.RING, jp.Central.CARRIER


@pytest.mark.parametrize("z_s, z_r", [(30, 92), (17, 73), (19, 81)])
def test_central_speeds_are_the_textbook_ratios(z_s, z_r):
    w = jp.central_speeds(z_s, z_r, RING, SUN, 10.0)
    assert w[RING] == 0.0
    assert w[CARRIER] == pytest.approx(10.0 * z_s / (z_s + z_r), rel=1e-14)
    w = jp.central_speeds(z_s, z_r, CARRIER, SUN, 10.0)
    assert w[RING] == pytest.approx(-10.0 * z_s / z_r, rel=1e-14) and w[CARRIER] == 0.0
    w = jp.central_speeds(z_s, z_r, SUN, RING, 10.0)
    assert w[CARRIER] == pytest.approx(10.0 * z_r / (z_s + z_r), rel=1e-14)


@pytest.mark.parametrize("fixed, driver", [(RING, SUN), (CARRIER, SUN), (SUN, RING),
                                           (SUN, CARRIER), (RING, CARRIER), (CARRIER, RING)])
def test_central_torques_balance_and_carry_no_power(fixed, driver):
    w = jp.central_speeds(30, 92, fixed, driver, 7.0)
    t = jp.central_torques(30, 92, driver, 100.0)
    assert t[driver] == pytest.approx(100.0, rel=1e-15)
    assert abs(t.sum()) < 1e-12 * 100.0
    assert abs(t @ w) < 1e-12 * 100.0 * 7.0
    assert jp.speed_ratio(30, 92, fixed, driver, 3 - fixed - driver) == pytest.approx(
        w[driver] / w[3 - fixed - driver], rel=1e-15)


def test_the_case_speeds_and_torques_are_the_models():
    """The case file's member speeds and torques (:class:`jaxgear.io.PlanetarySpec`) follow the
    textbook ratios of its roles: no second Willis solve in jaxgear.io."""
    case = jio.parse_train(tomllib.loads(jio.embedded_case_text("lin-parker-1999")))
    spec = case.form.spec
    z_s, _, z_r = spec.teeth
    speeds, torques = spec.speeds(3.0), spec.torques(5.0)
    w = jp.central_speeds(z_s, z_r, spec.fixed, spec.input, 3.0)
    t = jp.central_torques(z_s, z_r, spec.input, 5.0)
    for m in jp.Central:
        assert speeds[m.name.lower()] == w[m] and torques[m.name.lower()] == t[m]
    assert spec.ratio() == pytest.approx(w[spec.input] / w[spec.output], rel=1e-15)


def test_willis_refuses_a_fixed_driver():
    with pytest.raises(ValueError, match=r"^central_speeds: fixed = driver = SUN"):
        jp.central_speeds(30, 92, SUN, SUN, 1.0)


@pytest.mark.parametrize("deg", [[0, 120, 240], [0, 3, 120, 240], [0, 60, 180, 240],
                                 [0, 0, 240], [10, 100, 200, 290, 330]])
def test_closest_planets_is_the_smallest_chord(deg):
    a = 0.0884
    psi = np.radians(deg)
    i, j, d = jp.closest_planets(psi, a)
    chords = {(m, n): 2 * a * abs(math.sin((psi[n] - psi[m]) / 2))
              for m in range(len(psi)) for n in range(m + 1, len(psi))}
    least = min(chords.values())
    assert d == pytest.approx(least, abs=1e-15) and chords[(i, j)] == pytest.approx(least,
                                                                                   abs=1e-15)
    # ties go to the first pair in (i, j) order
    assert (i, j) == min(k for k, v in chords.items() if abs(v - least) < 1e-12)
