"""The one involute function and its inverse (fem_prep.involute) on floats, NumPy and JAX:
against SciPy's brentq on the defining equation, the round trip over 0..60°, and the JAX
derivatives against central finite differences."""

import math
from decimal import Decimal, localcontext

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import brentq

import jaxgear as jg
from fem_prep.involute import SERIES_BELOW, inverse_involute, involute

ANGLES = np.linspace(0.0, math.radians(60.0), 241)


def _reference_inv(a: float) -> float:
    """tan α − α in 60-digit decimal arithmetic (sin and cos from their Taylor series): no
    cancellation at small α, and independent of the module's series and its split."""
    with localcontext() as ctx:
        ctx.prec = 60
        return _decimal_inv(Decimal(a))


def _decimal_inv(x):
    sums = []
    for term, k in ((x, 1), (Decimal(1), 0)):  # sin, cos
        total = Decimal(0)
        while abs(term) > Decimal(10) ** -80:
            total += term
            term = -term * x * x / ((k + 1) * (k + 2))
            k += 2
        sums.append(total)
    return float(sums[0] / sums[1] - x)


def test_involute_against_decimal_arithmetic():
    """Relative error: rounding (5e-15) on the series below SERIES_BELOW; above, tan α − α's
    cancellation, ~ε/α² (3e-14 at 0.1 rad, 5e-15 from 0.25 rad on)."""
    ref = np.array([_reference_inv(float(a)) for a in ANGLES])
    rel = np.where(
        ANGLES < SERIES_BELOW, 5e-15, np.maximum(5e-15, 3e-16 / np.maximum(ANGLES, 0.05) ** 2)
    )
    for values, ulps in (
        (np.array([involute(float(a)) for a in ANGLES]), 1.0),
        (involute(ANGLES), 1.0),
        (np.asarray(involute(jnp.asarray(ANGLES))), 4.0),  # XLA's tan: a few ulp off libm's
    ):
        assert np.all(np.abs(values - ref) <= ulps * rel * ref)


def test_inverse_against_brentq():
    """The inverse against SciPy's brentq on tan α − α = v (an independent root finder; the
    function in decimal arithmetic, so that the root is not the cancellation's)."""
    values = np.array([1e-9, 1e-6, 1e-4, 0.003, 0.0149, 0.05, 0.2, 0.6, 1.0])
    ref = np.array(
        [brentq(lambda a, v=v: _reference_inv(a) - v, 1e-5, 1.2, xtol=1e-17) for v in values]
    )
    for v, r in zip(values, ref):
        assert inverse_involute(float(v)) == pytest.approx(r, abs=2e-15)
    np.testing.assert_allclose(inverse_involute(values), ref, atol=2e-15, rtol=0)
    np.testing.assert_allclose(
        np.asarray(inverse_involute(jnp.asarray(values))), ref, atol=2e-15, rtol=0
    )


@pytest.mark.parametrize("kind", ["float", "numpy", "jax"])
def test_round_trip_to_1e_14_rad_over_0_to_60_degrees(kind):
    if kind == "float":
        back = np.array([inverse_involute(involute(float(a))) for a in ANGLES])
    elif kind == "numpy":
        back = inverse_involute(involute(ANGLES))
    else:
        back = np.asarray(jax.jit(lambda a: inverse_involute(involute(a)))(jnp.asarray(ANGLES)))
    err = np.max(np.abs(back - ANGLES))
    assert err < 1e-14, err


def test_jax_derivatives_against_finite_differences():
    a = jnp.asarray([0.02, 0.2, 0.35, 0.7, 1.0])
    d_inv = jax.jit(jax.vmap(jax.grad(involute)))(a)
    h = 1e-6
    fd = (involute(a + h) - involute(a - h)) / (2 * h)
    np.testing.assert_allclose(np.asarray(d_inv), np.asarray(fd), rtol=1e-8)
    np.testing.assert_allclose(np.asarray(d_inv), np.tan(np.asarray(a)) ** 2, rtol=1e-12)
    v = involute(a)
    d_back = jax.jit(jax.vmap(jax.grad(inverse_involute)))(v)
    hv = 1e-7 * v
    fd = (inverse_involute(v + hv) - inverse_involute(v - hv)) / (2 * hv)
    np.testing.assert_allclose(np.asarray(d_back), np.asarray(fd), rtol=1e-6)


def test_float_inverse_refuses_a_negative_value_and_arrays_give_zero():
    with pytest.raises(ValueError, match="must be >= 0"):
        inverse_involute(-1e-3)
    assert inverse_involute(0.0) == 0.0
    np.testing.assert_array_equal(inverse_involute(np.array([-1.0, 0.0])), [0.0, 0.0])


def test_jaxgear_names_are_the_one_home():
    assert jg.involute is involute and jg.inverse_involute is inverse_involute
