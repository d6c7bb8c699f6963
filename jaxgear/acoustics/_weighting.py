"""The A frequency weighting of IEC 61672-1:2013 (§5.5.2, equations (5)–(6) and Annex E) and the
energetic sum of levels, in JAX.

    A(f) = 20 log10( f₄² f⁴ / ((f² + f₁²) √((f² + f₂²)(f² + f₃²)) (f² + f₄²)) ) + 2.00 dB

with the pole frequencies f₁ = 20.598997 Hz, f₂ = 107.65265 Hz, f₃ = 737.86223 Hz,
f₄ = 12194.217 Hz (Annex E.4) and A₁₀₀₀ = -2.000 dB normalising A(1 kHz) to 0 dB.
"""

from __future__ import annotations

import jax.numpy as jnp

from ._power import W_REF

__all__ = ["a_weighted_power_level", "a_weighting", "level_sum"]

_F1, _F2, _F3, _F4 = 20.598997, 107.65265, 737.86223, 12194.217
_A1000 = -2.000


def a_weighting(frequency_hz):
    """The A weighting (dB) at ``frequency_hz`` (Hz, > 0; any shape): about -19.1 dB at 100 Hz,
    0 at 1 kHz, +1.3 dB near 2.5 kHz (IEC 61672-1, Table 3)."""
    f2 = jnp.asarray(frequency_hz) ** 2
    ra = _F4**2 * f2**2 / ((f2 + _F1**2) * jnp.sqrt((f2 + _F2**2) * (f2 + _F3**2)) * (f2 + _F4**2))
    return 20.0 * jnp.log10(ra) - _A1000


def level_sum(levels, axis=-1):
    """The energetic sum 10 log10 Σ 10^(L/10) (dB) of ``levels`` (dB) along ``axis``."""
    L = jnp.asarray(levels)
    return 10.0 * jnp.log10(jnp.sum(10.0 ** (L / 10.0), axis=axis))


def a_weighted_power_level(power, frequency_hz, axis=-1):
    """The overall A-weighted sound power level L_WA = 10 log10 Σ W_i 10^(A(f_i)/10) / 1 pW
    (dB(A) re 1 pW) of powers ``power`` (W) at ``frequency_hz`` (Hz; the same shape or
    broadcast), summed along ``axis`` (the orders or frequencies)."""
    w = jnp.asarray(power) * 10.0 ** (a_weighting(frequency_hz) / 10.0)
    return 10.0 * jnp.log10(jnp.sum(w, axis=axis) / W_REF)
