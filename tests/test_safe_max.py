"""jaxgear.safe_max: jnp.max's values, and its derivative (the mean of the tangents at
the elements equal to the maximum) against central differences and the tie rule written out."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

from jaxgear import safe_max


def test_safe_max_values_are_jnp_max():
    x = np.random.default_rng(0).normal(size=(5, 7))
    x[1, :] = -np.inf  # a fully masked row
    for axis in (None, 0, 1, -1):
        np.testing.assert_array_equal(safe_max(jnp.asarray(x), axis), np.max(x, axis=axis))


def test_safe_max_gradient_without_ties_is_central_differences():
    """Distinct elements: d max / dx is 1 at the maximum, 0 elsewhere; checked against central
    differences of the NumPy maximum (h = 1e-6) along each axis and overall."""
    x = np.random.default_rng(1).normal(size=(4, 6))
    w = np.random.default_rng(2).normal(size=6)
    for axis in (None, 0, 1):

        def f(v, axis=axis):
            m = safe_max(v, axis)
            return jnp.sum(m * (w[: m.size] if m.ndim else 1.0))

        def f_np(v, axis=axis):
            m = np.max(v, axis=axis)
            return np.sum(m * (w[: m.size] if m.ndim else 1.0))

        g = np.asarray(jax.grad(f)(jnp.asarray(x)))
        h = 1e-6
        fd = np.zeros_like(x)
        for i in np.ndindex(x.shape):
            e = np.zeros_like(x)
            e[i] = h
            fd[i] = (f_np(x + e) - f_np(x - e)) / (2 * h)
        np.testing.assert_allclose(g, fd, atol=1e-8)


def test_safe_max_gradient_splits_ties_evenly():
    """Three elements at the maximum share the cotangent (1/3 each), as jnp.max's rule; a
    masked (-inf) element and the others get 0; one axis: per column."""
    x = jnp.asarray([1.0, 3.0, -jnp.inf, 3.0, 2.0, 3.0])
    np.testing.assert_array_equal(jax.grad(safe_max)(x), [0, 1 / 3, 0, 1 / 3, 0, 1 / 3])
    y = jnp.asarray([[1.0, 2.0], [1.0, 0.5]])
    g = jax.grad(lambda v: jnp.sum(safe_max(v, 0) * jnp.asarray([1.0, 10.0])))(y)
    np.testing.assert_array_equal(g, [[0.5, 10.0], [0.5, 0.0]])
