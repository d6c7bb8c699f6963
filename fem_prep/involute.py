"""The involute function inv α = tan α − α and its inverse: the one home of both for fem_prep
and jaxgear (jaxgear imports fem_prep; fem_prep never imports JAX).

Each takes a Python float (→ a Python float, by :mod:`math`), a NumPy array or a JAX array
(traced, under ``jit``, ``grad`` and ``vmap`` alike) and computes in that array's own namespace
(the array API's ``__array_namespace__``), so one body serves the pair's geometry, the tooth
form's meshes and the differentiable rating.

Near α = 0, tan α − α cancels: its absolute error is the rounding of tan α (~1e-16 α), which,
relative to inv α ≈ α³/3, grows as 1/α² and would cost the inverse 1e-10 rad at α = 1e-3.
Below :data:`SERIES_BELOW` the Taylor series of tan α − α (to α¹⁵; Abramowitz & Stegun 4.3.67)
is used instead, exact to rounding there, so the round trip inverse(inv(α)) holds α to 1e-15
rad over 0..60°.
"""

from __future__ import annotations

import math

__all__ = ["SERIES_BELOW", "inverse_involute", "involute"]

#: below this angle (rad) the involute is summed from its Taylor series (the omitted α¹⁷ term
#: is below 1e-17 of inv α there)
SERIES_BELOW = 0.1
#: the Taylor coefficients of tan α − α = Σ c_k α^(2k+3), k = 0..6 (the tangent numbers over
#: (2k+3)!: 1/3, 2/15, 17/315, 62/2835, 1382/155925, 21844/6081075, 929569/638512875)
_SERIES = (
    1 / 3,
    2 / 15,
    17 / 315,
    62 / 2835,
    1382 / 155925,
    21844 / 6081075,
    929569 / 638512875,
)
#: Newton steps of the array inverse (fixed, so that it traces): from the start below, within
#: 3e-15 rad after 5 steps for α in [0.05, 1.3] rad
NEWTON_STEPS = 8


def _series(a, a2):
    out = _SERIES[-1]
    for c in _SERIES[-2::-1]:
        out = out * a2 + c
    return out * a2 * a


def involute(alpha):
    """inv α = tan α − α (rad) of ``alpha`` (rad): a Python float, or elementwise on a NumPy or
    JAX array (differentiable; d inv/dα = tan² α). Below :data:`SERIES_BELOW` in magnitude from
    its Taylor series (no cancellation). Source: ISO 21771:2007, eq. (23)."""
    if isinstance(alpha, (int, float)):
        alpha = float(alpha)
        if abs(alpha) < SERIES_BELOW:
            return _series(alpha, alpha * alpha)
        return math.tan(alpha) - alpha
    xp = alpha.__array_namespace__()
    small = xp.abs(alpha) < SERIES_BELOW
    # the series on the small angles only; the other branch's value is discarded by where
    return xp.where(small, _series(alpha, alpha * alpha), xp.tan(alpha) - alpha)


def _start(value, xp):
    """A start right of the root and below π/2 (inv α >= α³/3, and α = atan(inv α + α) <
    atan(value + π/2)): inv is convex and increasing on (0, π/2), so Newton descends onto the
    root monotonically."""
    return xp.minimum(xp.cbrt(3.0 * value), xp.atan(value + math.pi / 2))


def inverse_involute(value):
    """α ∈ [0, π/2) with inv α = ``value`` (rad) by Newton's method: a Python float (to 1e-15
    rad, at most 60 steps; ValueError for a negative value), or elementwise on a NumPy or JAX
    array (:data:`NEWTON_STEPS` fixed steps: it traces, and its derivative, that of the
    unrolled steps, converges to the implicit one 1/tan² α; negative values give 0).

    Raises:
        ValueError: a negative Python float.
    """
    if isinstance(value, (int, float)):
        value = float(value)
        if value < 0.0:
            raise ValueError(f"inverse_involute: value {value!r} must be >= 0")
        if value == 0.0:
            return 0.0
        alpha = min((3.0 * value) ** (1.0 / 3.0), math.atan(value + math.pi / 2))
        for _ in range(60):
            step = (involute(alpha) - value) / math.tan(alpha) ** 2
            alpha -= step
            if abs(step) < 1e-15:
                break
        return alpha
    xp = value.__array_namespace__()
    positive = value > 0.0
    v = xp.where(positive, value, 1.0)  # a safe stand-in, replaced below (no 0/0 in the steps)
    alpha = _start(v, xp)
    for _ in range(NEWTON_STEPS):
        alpha = alpha - (involute(alpha) - v) / xp.tan(alpha) ** 2
    return xp.where(positive, alpha, 0.0)
