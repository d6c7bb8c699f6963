"""The band a condensed housing's response holds and the rule a housed model's frequencies keep
to, as the housing (:mod:`jaxgear.scenes`) states them: f_b = f_c / 1.5 (docs/housing.md, "What
the condensation keeps"), a frequency f held where f_c >= 1.5 f up to round-off, and the speed
limit Ω_b = 2π f_b / max |o_k| of meshes of orders o_k.

References: fem_prep's default cut-off rule (:func:`fem_prep.housing.housing_cutoff_hz`, 1.5 x
the highest mesh-order frequency: written apart, in fem_prep), which must hold the frequency it
was derived from; the two-stage train's numbers by hand (docs/housing.md, "The first-look
sweep")."""

from __future__ import annotations

import math

import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.scenes as js
from fem_prep.housing import housing_cutoff_hz


def test_the_default_cut_off_holds_the_frequency_it_was_derived_from():
    """fem_prep's cut-off of f holds f (round-off included) and a cut-off 1e-9 below it does
    not; the band's top is the cut-off over 1.5 and the least cut-off 1.5 f."""
    for f in np.geomspace(1.0, 2e5, 97):
        c = housing_cutoff_hz(float(f))
        assert js.band_holds(c, f)
        assert not js.band_holds(c * (1 - 1e-9), f)
        assert js.housing_band_hz(c) == pytest.approx(f, rel=1e-15)
        assert js.band_cutoff_hz(f) == pytest.approx(c, rel=1e-15)
    assert js.HOUSING_BAND == 1.5  # docs/housing.md
    assert js.housing_band_hz(3450.0) == pytest.approx(2300.0, rel=1e-15)


def test_the_speed_limit_puts_the_fastest_mesh_on_the_band_edge():
    """The two-stage train by hand (tests/test_housed_first_look.py): meshes of 28 and
    35 x 28/127 teeth per input turn, cut-off 3450 Hz: Ω_b = 2π 2300 / 28 = 516.1 rad/s, where
    the first mesh's order 1 sits on the band's edge (held), 0.1 % faster it leaves it; the
    sign of an order does not count (a planetary stage's carrier-frame orders)."""
    orders = [28.0, 35 * 28 / 127]
    limit = js.band_speed_limit(3450.0, orders)
    assert limit == pytest.approx(2 * math.pi * 2300 / 28, rel=1e-14)
    assert js.band_holds(3450.0, 28 * limit / (2 * math.pi))
    assert not js.band_holds(3450.0, 28 * 1.001 * limit / (2 * math.pi))
    assert js.band_speed_limit(3450.0, [-28.0, 7.7]) == limit


def test_the_case_band_is_the_housings():
    """``jaxgear.io.housing_band`` of the embedded two-stage-housed case gives the housing's
    band and speed limit (and one HOUSING_BAND serves io and the model)."""
    hb = jio.housing_band(jio.load_case("two-stage-housed"))
    assert hb.cutoff_hz == pytest.approx(3450.0)
    assert hb.band_hz == pytest.approx(2300.0, rel=1e-15)
    assert hb.speed_limit == pytest.approx(2 * math.pi * 2300 / 28, rel=1e-14)
    assert jio.HOUSING_BAND is js.HOUSING_BAND
