"""The radiated sound of a vibrating surface over speeds and orders: its sound power per order and
speed, linear and A-weighted, the overall levels summed over the orders, and the pressure at the
field points (microphones), from the radiation operators computed at a grid of frequencies
(:func:`fem_prep.acoustics.radiation_resistance`) and interpolated log-log between them
(:mod:`jaxgear.acoustics._band`). What ``jaxgear run``'s ``[acoustics]`` writes and the sizing's
sound stage ranks (docs/acoustics.md, "Outputs"); the caller builds the operators
(:func:`jaxgear.io.surface_sound_power` from a case's ``[acoustics]`` table).
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from ._band import mean_square_pressure_at, radiated_power_at
from ._power import P_REF, W_REF
from ._weighting import a_weighting

__all__ = ["SoundPower", "radiated_sound_power"]


def _level(x, ref: float) -> np.ndarray:
    """10 log10(x / ref) (dB) of powers or mean squares ``x`` (any shape; W re 1 pW, Pa² re
    (20 µPa)²), NaN where x is not > 0 (no power: an order outside the band)."""
    x = np.asarray(x, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.where(x > 0, 10 * np.log10(np.where(x > 0, x, 1.0) / ref), np.nan)


class SoundPower(NamedTuple):
    """The radiated sound of :func:`radiated_sound_power`, over S speeds and O orders.

    Attributes:
        band: (lo, hi) Hz the radiation operators span; grid: (G,) their frequencies (Hz).
        frequency: (S, O) Hz of each order at each speed.
        power: (S, O) W (NaN: outside the grid's range); a_weighting: (S, O) dB (IEC 61672-1).
        level, level_a: (S, O) L_W (dB re 1 pW) and L_WA (dB(A) re 1 pW).
        overall, overall_a: (S,) the energetic sums over the orders (the NaN ones left out),
            L_W and L_WA (NaN: no power at that speed).
        radiation: the operators radiated with (:class:`fem_prep.acoustics.RadiationResistance`:
            its factors, transfer and cache key).
        pressure: (S, O, q) the mean square pressure p_rms² (Pa²) at the radiation's q field
            points, or None without points; pressure_level: (S, O, q) L_p (dB re 20 µPa);
            overall_pressure_level_a: (S, q) the A-weighted sum over the orders L_pA
            (dB(A) re 20 µPa); both None without points.
    """

    band: tuple[float, float]
    grid: np.ndarray
    frequency: np.ndarray
    power: np.ndarray
    a_weighting: np.ndarray
    level: np.ndarray
    level_a: np.ndarray
    overall: np.ndarray
    overall_a: np.ndarray
    radiation: object
    pressure: np.ndarray | None = None
    pressure_level: np.ndarray | None = None
    overall_pressure_level_a: np.ndarray | None = None


def radiated_sound_power(velocity, frequency_hz, radiation, *, band=None) -> SoundPower:
    """The sound power a vibrating surface radiates at each speed and order, W = vᴴ R v at the
    orders' frequencies, interpolated log-log between the grid frequencies R was computed at
    (:func:`radiated_power_at`), its level L_W = 10 log10(W / 1 pW) (ISO 3744 §3.6), its
    A-weighted level (A(f) of IEC 61672-1 §5.5.2, :func:`a_weighting`), the overall sums over
    the orders, and with field points the pressure there (:func:`mean_square_pressure_at`).

    Args:
        velocity: ``(S, O, n)`` complex normal velocity amplitudes at the surface's n vertices
            (m/s, one-sided, v(t) = Re v e^{iωt}: jaxgear's whine and housing convention;
            conjugated here to :mod:`fem_prep.acoustics`' e^{-iωt}; positive outward).
        frequency_hz: ``(S, O)`` the frequency of each order at each speed (Hz, > 0).
        radiation: the operators at G grid frequencies (a
            :class:`fem_prep.acoustics.RadiationResistance`: ``frequencies_hz`` (G,) increasing,
            ``factors`` (G, n, r) with R ≈ L Lᴴ, ``transfer`` (G, q, n) or None).
        band: the (lo, hi) Hz the grid was chosen for (recorded; default its first and last).

    Returns:
        The :class:`SoundPower`; an order whose frequency lies outside the grid's range has NaN
        power and levels (no extrapolation) and is left out of the overall sums.

    Raises:
        ValueError: a velocity that is not (S, O, n), frequencies that are not (S, O) finite
            values > 0, operators of another vertex count (one line each).
    """
    v = np.asarray(velocity)
    f = np.asarray(frequency_hz, dtype=float)
    grid = np.asarray(radiation.frequencies_hz, dtype=float)
    n = int(np.shape(radiation.factors)[1])
    if v.ndim != 3 or v.shape[-1] != n:
        raise ValueError(f"radiated_sound_power: velocity = {v.shape}, allowed (S, O, {n}) "
                         "(speeds, orders, the surface's vertices)")
    if f.shape != v.shape[:2] or not np.all(np.isfinite(f)) or f.min() <= 0:
        raise ValueError(f"radiated_sound_power: frequency_hz {f.shape}, allowed {v.shape[:2]} "
                         "finite values > 0 (Hz)")
    vc = jnp.asarray(np.conj(v))  # e^{iωt} → e^{-iωt}
    W = np.asarray(radiated_power_at(vc, f, radiation.factors, grid))  # (S, O)
    A = np.asarray(a_weighting(f))
    Wa = W * 10 ** (A / 10)
    band = (float(grid[0]), float(grid[-1])) if band is None else band
    pressure = p_level = p_level_a = None
    if radiation.transfer is not None:
        pressure = np.asarray(mean_square_pressure_at(vc, f, radiation.transfer, grid))
        p_level = _level(pressure, P_REF**2)  # (S, O, q)
        p_level_a = _level(np.nansum(pressure * 10 ** (A / 10)[..., None], axis=1), P_REF**2)
    return SoundPower(band, grid, f, W, A, _level(W, W_REF), _level(Wa, W_REF),
                      _level(np.nansum(W, axis=1), W_REF),
                      _level(np.nansum(Wa, axis=1), W_REF), radiation, pressure, p_level,
                      p_level_a)
