"""ISO 281 basic rating life, at one load and under a load spectrum (Palmgren–Miner).

The basic rating life (ISO 281:2007, 90 % reliability, a₁ = 1) of a bearing of basic dynamic
load rating C under its equivalent dynamic load P (:meth:`~AbstractRollingBearing.equivalent_load`,
ISO 281's X and Y factors) is::

    L10 = (C / P)^p · 10⁶ revolutions,   p = 3 (ball), 10/3 (roller)

and at a speed ω (rad/s) it lasts L10 · 2π / ω seconds (L10h = that / 3600). Under a load
spectrum of k bins (F_r,i, F_a,i, ω_i, t_i) the bins' damage adds (Palmgren–Miner, as ISO 281
and ISO 6336-6 do for a duty cycle): n_i = ω_i t_i / 2π revolutions in bin i, D = Σ n_i / L10,i
per pass of the spectrum, the life Σ t_i / D seconds, and the equivalent load
P_eq = (Σ n_i P_i^p / Σ n_i)^(1/p) with which one constant load gives the same life in
revolutions. The modified life L_nm = a₁ a_ISO L10 (lubrication, contamination, fatigue load
limit) is not built here.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import as_float, check_instance, check_real
from ._kinds import AbstractRollingBearing

__all__ = ["BearingLife", "BearingSpectrum", "rating_life", "spectrum_life"]


class BearingLife(eqx.Module):
    """A basic rating life (:func:`rating_life`, :func:`spectrum_life`).

    Attributes:
        equivalent_load: P (N), or a spectrum's P_eq.
        revolutions: L10 (revolutions, not millions).
        duration: the life in seconds at the speed(s) given (L10h = duration / 3600).
    """

    equivalent_load: Float[Array, ""]
    revolutions: Float[Array, ""]
    duration: Float[Array, ""]


class BearingSpectrum(eqx.Module):
    """A bearing's load spectrum of k bins, (k,) each: ``radial`` F_r,i (N, >= 0), ``axial``
    F_a,i (N), ``speed`` ω_i (rad/s, >= 0; a scalar for all bins) and ``duration`` t_i (s,
    >= 0), the time run in the bin. (:class:`jaxgear.rating.LoadSpectrum` holds a gear's
    torque bins; a bearing's bins are its own loads, which the model derives from each torque.)

    Raises:
        ValueError: a negative or non-finite entry, arrays not (k,), no bin turning with
            time in it; one line naming the argument.
    """

    radial: Float[Array, " k"]
    axial: Float[Array, " k"]
    speed: Float[Array, " k"]
    duration: Float[Array, " k"]

    def __init__(self, radial, axial, speed, duration):
        w = "BearingSpectrum"
        check_real("radial", radial, "N", lo=0.0, shape=(None,), shape_text="(k,)", where=w)
        k = np.shape(radial)[0]
        check_real("axial", axial, "N", shape=(k,), shape_text=f"({k},), as radial", where=w)
        if np.ndim(speed) == 0:
            check_real("speed", speed, "rad/s", lo=0.0, where=w)
            speed = np.full(k, float(speed))
        check_real("speed", speed, "rad/s", lo=0.0, shape=(k,),
                   shape_text=f"({k},), as radial", where=w)
        check_real("duration", duration, "s", lo=0.0, shape=(k,),
                   shape_text=f"({k},), as radial", where=w)
        if k < 1 or not np.any((np.asarray(speed) > 0) & (np.asarray(duration) > 0)):
            raise ValueError(f"{w}: no bin with speed and duration > 0: allowed at least one")
        self.radial, self.axial = as_float(radial), as_float(axial)
        self.speed, self.duration = as_float(speed), as_float(duration)


def _rated(bearing, where):
    check_instance("bearing", bearing, AbstractRollingBearing, "a jaxgear.bearings kind",
                   where=where)
    if bearing.life_exponent is None or bearing.dynamic_rating is None:
        raise ValueError(
            f"{where}: {type(bearing).__name__} has no dynamic_rating: allowed a rolling kind "
            "with its basic dynamic load rating C (N) given"
        )


def rating_life(bearing: AbstractRollingBearing, radial, axial, speed) -> BearingLife:
    """ISO 281's basic rating life L10 of ``bearing`` under F_r = ``radial`` (N, >= 0) and
    F_a = ``axial`` (N) at ``speed`` ω (rad/s, > 0) (module docstring).

    Raises:
        ValueError: a kind without a rating life or without ``dynamic_rating``; a load or speed
            out of range (one line)."""
    w = "rating_life"
    _rated(bearing, w)
    check_real("radial", radial, "N", lo=0.0, where=w)
    check_real("axial", axial, "N", where=w)
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where=w)
    P = bearing.equivalent_load(radial, axial)
    L = (bearing.dynamic_rating / P) ** bearing.life_exponent * 1e6
    return BearingLife(P, L, L * 2.0 * jnp.pi / speed)


def spectrum_life(bearing: AbstractRollingBearing, spectrum: BearingSpectrum) -> BearingLife:
    """ISO 281's basic rating life under a :class:`BearingSpectrum` (Palmgren–Miner; module
    docstring): the equivalent load P_eq, the life in revolutions and in seconds.

    Raises:
        ValueError: as :func:`rating_life`; ``spectrum`` not a :class:`BearingSpectrum`."""
    w = "spectrum_life"
    _rated(bearing, w)
    check_instance("spectrum", spectrum, BearingSpectrum, "a jaxgear.bearings.BearingSpectrum",
                   where=w)
    p = bearing.life_exponent
    P = bearing.equivalent_load(spectrum.radial, spectrum.axial)
    n = spectrum.speed * spectrum.duration / (2.0 * jnp.pi)
    damage = jnp.sum(n * (P / bearing.dynamic_rating) ** p) / 1e6
    P_eq = (jnp.sum(n * P**p) / jnp.sum(n)) ** (1.0 / p)
    return BearingLife(P_eq, jnp.sum(n) / damage, jnp.sum(spectrum.duration) / damage)
