"""Convergence under refinement, shared by the FE tests."""

import math

import numpy as np


def assert_monotone_richardson(values, min_rate: float = 0.8, tol: float = 0.01) -> float:
    """``values`` on three meshes, each twice as fine as the one before: they rise monotonically,
    at an observed order above ``min_rate``, and the middle one lies within ``tol`` (relative) of
    the Richardson limit extrapolated from the three. Returns the observed order."""
    values = np.asarray(values, dtype=float)
    d = np.diff(values)
    assert np.all(d > 0), values
    rate = math.log2(d[0] / d[1])
    assert rate > min_rate, rate
    limit = values[-1] + d[1] / (2**rate - 1)
    assert abs(values[1] / limit - 1) < tol, (values, limit)
    return rate


def gradient_and_differences(problem, x0, steps=(0.02, 0.01)) -> tuple[float, float]:
    """The derivative of a one-variable ``optimise.Problem``'s value at ``x0`` by ``jax.grad``
    and by central differences at the two ``steps`` h and h/2 (the variable's units),
    Richardson-extrapolated ((4 D(h/2) − D(h))/3); each evaluation compiled once."""
    import equinox as eqx
    import jax

    value = eqx.filter_jit(lambda p, x: p.value(x))
    grad = float(eqx.filter_jit(lambda p, x: jax.grad(p.value)(x))(problem, x0)[0])
    fd = [(float(value(problem, x0 + h)) - float(value(problem, x0 - h))) / (2 * h)
          for h in steps]
    return grad, (4 * fd[1] - fd[0]) / 3
