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
