"""ISO 281's basic and modified rating life, at one load and under a load spectrum.

The basic rating life (ISO 281:2007, 90 % reliability, a₁ = 1) of a bearing of basic dynamic
load rating C under its equivalent dynamic load P (:meth:`~AbstractRollingBearing.equivalent_load`,
ISO 281's X and Y factors) is::

    L10 = (C / P)^p · 10⁶ revolutions,   p = 3 (ball), 10/3 (roller)

and at a speed ω (rad/s) it lasts L10 · 2π / ω seconds (L10h = that / 3600). Under a load
spectrum of k bins (F_r,i, F_a,i, ω_i, t_i) the bins' damage adds (Palmgren–Miner, as ISO 281
and ISO 6336-6 do for a duty cycle): n_i = ω_i t_i / 2π revolutions in bin i, D = Σ n_i / L10,i
per pass of the spectrum, the life Σ t_i / D seconds, and the equivalent load
P_eq = (Σ n_i P_i^p / Σ n_i)^(1/p) with which one constant load gives the same life in
revolutions.

The modified rating life (ISO 281:2007) is L_nm = a₁ a_ISO L10:

- a₁, the life modification factor for reliability (ISO 281's table, 90 % to 99.95 %; between
  the table's rows interpolated along the Weibull form behind it, ln(a₁ − 0.05) linear in
  ln ln(1/R): ISO/TR 1281-2's a₁ = 0.95 (ln(1/R) / ln(1/0.9))^(2/3) + 0.05).
- a_ISO, the factor of the systems approach (ISO 281), from the viscosity ratio
  κ = ν/ν₁ and e_C C_u / P, for radial ball (p = 3) and radial roller (p = 10/3) bearings::

      ball:   a_ISO = 0.1 [1 − (2.5671 − b/κ^c)^0.83 (e_C C_u / P)^(1/3)]^(−9.3)
      roller: a_ISO = 0.1 [1 − (1.5859 − b/κ^c) (e_C C_u / P)^0.4]^(−9.185)

  with (b, c) = (2.2649, 0.054381) ball, (1.3993, 0.054381) roller for 0.1 <= κ < 0.4;
  (1.9987, 0.19087) ball, (1.2348, 0.19087) roller for 0.4 <= κ < 1; (1.9987, 0.071739) ball,
  (1.2348, 0.071739) roller for 1 <= κ <= 4; κ > 4 taken as 4 (ISO 281); a_ISO <= 50.
- ν₁, the rated viscosity (mm²/s) at the speed n (r/min) and the pitch diameter d_m (mm)
  (ISO 281): ν₁ = 45000 n^(−0.83) d_m^(−0.5) for n < 1000 r/min, else
  ν₁ = 4500 n^(−0.5) d_m^(−0.5).
- C_u, the fatigue load limit: the maker's value (a kind's ``fatigue_limit``, or
  ``fatigue_limit=``), or ISO 281's simplified estimate from C₀:
  C₀/22 (balls) and C₀/8.2 (rollers) for d_m <= 100 mm, times (100/d_m)^0.5 (balls) and
  (100/d_m)^0.3 (rollers) above.
- e_C, the contamination factor, 0 to 1 (ISO 281's table gives its guideline ranges by
  cleanliness: :data:`ISO281_CONTAMINATION`).

Under a load spectrum the bins' damage adds by Palmgren–Miner with each bin's own a_ISO (its
load and its κ): D = Σ n_i / (a₁ a_ISO,i L10,i) (ISO 281: L_nm = 1 / Σ U_i / L_nm,i,
U_i the share of revolutions). Not built: ISO 281's note allowing κ = 1 for EP-additive oils
with κ < 1 and e_C >= 0.2, thrust bearings' formulas, ISO 281's detailed e_C by oil
cleanliness class and filtration.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import as_float, check_instance, check_real, is_traced
from ._kinds import AbstractRollingBearing

__all__ = [
    "ISO281_CONTAMINATION",
    "ISO281_RELIABILITY",
    "BearingLife",
    "BearingSpectrum",
    "ModifiedLife",
    "fatigue_load_limit",
    "life_modification_factor",
    "modified_life",
    "rated_viscosity",
    "rating_life",
    "reliability_factor",
    "spectrum_life",
    "spectrum_modified_life",
]


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


# ---------------------------------------------------------------- ISO 281 modified life

#: ISO 281:2007's table of reliability (%) and the life modification factor a₁
ISO281_RELIABILITY: tuple[tuple[float, float], ...] = (
    (90.0, 1.0), (95.0, 0.64), (96.0, 0.55), (97.0, 0.47), (98.0, 0.37), (99.0, 0.25),
    (99.2, 0.22), (99.4, 0.19), (99.6, 0.16), (99.8, 0.12), (99.9, 0.093), (99.92, 0.087),
    (99.94, 0.080), (99.95, 0.077),
)

#: ISO 281:2007's table of the contamination factor e_C's guideline ranges by cleanliness:
#: level -> ((low, high) for d_m < 100 mm, (low, high) for d_m >= 100 mm)
ISO281_CONTAMINATION: dict[str, tuple[tuple[float, float], tuple[float, float]]] = {
    "extreme cleanliness": ((1.0, 1.0), (1.0, 1.0)),
    "high cleanliness": ((0.6, 0.8), (0.8, 0.9)),
    "normal cleanliness": ((0.5, 0.6), (0.6, 0.8)),
    "slight contamination": ((0.3, 0.5), (0.4, 0.6)),
    "typical contamination": ((0.1, 0.3), (0.2, 0.4)),
    "severe contamination": ((0.0, 0.1), (0.0, 0.1)),
    "very severe contamination": ((0.0, 0.0), (0.0, 0.0)),
}

#: ISO 281's a_ISO constants of radial bearings, by life exponent p:
#: (lead, ((b, c) for κ in [0.1, 0.4), [0.4, 1), [1, 4]), bracket power, load power, exponent)
_AISO = {
    3.0: (2.5671, ((2.2649, 0.054381), (1.9987, 0.19087), (1.9987, 0.071739)), 0.83,
          1.0 / 3.0, -9.3),
    10.0 / 3.0: (1.5859, ((1.3993, 0.054381), (1.2348, 0.19087), (1.2348, 0.071739)), 1.0,
                 0.4, -9.185),
}
#: the largest a_ISO (ISO 281)
AISO_MAX = 50.0
#: the viscosity ratios ISO 281's a_ISO covers; above KAPPA_MAX κ is taken as KAPPA_MAX
KAPPA_MIN, KAPPA_MAX = 0.1, 4.0


class ModifiedLife(eqx.Module):
    """ISO 281's modified rating life L_nm = a₁ a_ISO L10 (:func:`modified_life`,
    :func:`spectrum_modified_life`).

    Attributes:
        equivalent_load: P (N), or a spectrum's P_eq.
        revolutions: L_nm (revolutions, not millions).
        duration: the life in seconds at the speed(s) given (L_nmh = duration / 3600).
        basic_revolutions: the basic rating life L10 (revolutions) under the same loads.
        reliability_factor: a₁ (-).
        life_factor: a_ISO (-): a scalar, (k,) per bin under a spectrum.
        viscosity_ratio: κ = ν/ν₁ as used (at most 4), shaped as ``life_factor``.
        fatigue_limit: C_u (N), given or estimated (:func:`fatigue_load_limit`).
    """

    equivalent_load: Float[Array, ""]
    revolutions: Float[Array, ""]
    duration: Float[Array, ""]
    basic_revolutions: Float[Array, ""]
    reliability_factor: Float[Array, ""]
    life_factor: Array
    viscosity_ratio: Array
    fatigue_limit: Float[Array, ""]


def reliability_factor(reliability):
    """ISO 281's life modification factor a₁ for a reliability R (a fraction, 0.9 to 0.9995:
    90 % to 99.95 %): ISO 281's table (:data:`ISO281_RELIABILITY`) at its rows, between them along
    its Weibull form (module docstring).

    Raises:
        ValueError: R outside 0.9 to 0.9995 or not finite (one line)."""
    check_real("reliability", reliability, "", lo=0.9, hi=0.9995,
               where="reliability_factor (a fraction: 0.9 to 0.9995 is 90 % to 99.95 %)")
    R = np.asarray([r for r, _ in ISO281_RELIABILITY]) / 100.0
    a = np.asarray([v for _, v in ISO281_RELIABILITY])
    x = jnp.log(jnp.log(1.0 / jnp.asarray(R)))  # decreasing in R
    y = jnp.log(jnp.asarray(a) - 0.05)
    xr = jnp.log(jnp.log(1.0 / jnp.asarray(reliability, float)))
    return 0.05 + jnp.exp(jnp.interp(xr, x[::-1], y[::-1]))


def rated_viscosity(speed, pitch_diameter):
    """ISO 281's rated viscosity ν₁ (m²/s) at the speed ω (rad/s, > 0) of a bearing of pitch
    diameter d_m (m, > 0): ν₁ = 45000 n^(−0.83) d_m^(−0.5) below 1000 r/min, 4500 n^(−0.5)
    d_m^(−0.5) above (n in r/min, d_m in mm, ν₁ in mm²/s; module docstring).

    Raises:
        ValueError: a speed or diameter not > 0 (one line)."""
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where="rated_viscosity")
    check_real("pitch_diameter", pitch_diameter, "m", lo=0.0, lo_open=True,
               where="rated_viscosity")
    n = jnp.asarray(speed, float) * 30.0 / jnp.pi
    dm = jnp.asarray(pitch_diameter, float) * 1e3
    slow = 45000.0 * n**-0.83 * dm**-0.5
    fast = 4500.0 * n**-0.5 * dm**-0.5
    return jnp.where(n < 1000.0, slow, fast) * 1e-6


def _life_set(bearing, where):
    """The a_ISO constants of ``bearing``'s formula set (its ISO 281 life exponent)."""
    _rated(bearing, where)
    return _AISO[float(bearing.life_exponent)]


def fatigue_load_limit(bearing: AbstractRollingBearing):
    """The fatigue load limit C_u (N) of ``bearing``: the maker's, where the kind holds it
    (its ``fatigue_limit``), else ISO 281's simplified estimate from the static rating C₀:
    C₀/22 for ball and C₀/8.2 for roller bearings up to d_m = 100 mm, times (100/d_m)^0.5
    (balls) or (100/d_m)^0.3 (rollers) above (d_m in mm). ``fatigue_limit=`` of
    :func:`modified_life` overrides both.

    Raises:
        ValueError: a kind without a rating life; neither ``fatigue_limit`` nor
            ``static_rating`` given (one line)."""
    w = "fatigue_load_limit"
    _life_set(bearing, w)
    if bearing.fatigue_limit is not None:
        return bearing.fatigue_limit
    if bearing.static_rating is None:
        raise ValueError(
            f"{w}: {type(bearing).__name__} has static_rating = None and fatigue_limit = None: "
            "allowed C0 (N) or the maker's fatigue load limit C_u (N) given"
        )
    ball = float(bearing.life_exponent) == 3.0
    dm = bearing.pitch_diameter * 1e3
    size = jnp.minimum(1.0, 100.0 / dm) ** (0.5 if ball else 0.3)
    return bearing.static_rating / (22.0 if ball else 8.2) * size


def _check_factor_inputs(where, contamination, fatigue_limit):
    check_real("contamination", contamination, "", lo=0.0, hi=1.0,
               where=f"{where} (ISO 281's contamination factor e_C)")
    if fatigue_limit is not None:
        check_real("fatigue_limit", fatigue_limit, "N", lo=0.0, where=where)


def _check_kappa(where, kappa, source):
    if not is_traced(kappa) and np.any(np.asarray(kappa) < KAPPA_MIN):
        bad = float(np.min(np.asarray(kappa)))
        raise ValueError(
            f"{where}: viscosity ratio kappa = {bad:.6g}{source} is out of range: allowed "
            f">= {KAPPA_MIN} (ISO 281's a_ISO; above {KAPPA_MAX} it is taken as {KAPPA_MAX})"
        )


def _a_iso(consts, kappa, load_ratio):
    """a_ISO (module docstring) at κ and e_C C_u / P, capped at :data:`AISO_MAX`."""
    lead, rows, q, r, s = consts
    k = jnp.clip(kappa, KAPPA_MIN, KAPPA_MAX)
    b = jnp.where(k < 0.4, rows[0][0], rows[1][0])
    c = jnp.where(k < 0.4, rows[0][1], jnp.where(k < 1.0, rows[1][1], rows[2][1]))
    base = jnp.maximum(lead - b / k**c, 0.0)
    term = jnp.where(base > 0, jnp.where(base > 0, base, 1.0) ** q, 0.0)
    x = 1.0 - term * jnp.maximum(load_ratio, 0.0) ** r
    x = jnp.maximum(x, (AISO_MAX / 0.1) ** (1.0 / s))  # 0.1 x^s <= AISO_MAX
    return 0.1 * x**s


def life_modification_factor(bearing: AbstractRollingBearing, equivalent_load, viscosity_ratio,
                             contamination=1.0, fatigue_limit=None):
    """ISO 281's a_ISO of ``bearing`` (its formula set: ball or roller, by its life exponent)
    at the equivalent load P (N, > 0), the viscosity ratio κ = ν/ν₁ (>= 0.1; above 4 taken as
    4), the contamination factor e_C (0 to 1) and the fatigue load limit C_u (N; ``None``:
    :func:`fatigue_load_limit`), capped at 50 (module docstring). Arrays broadcast.

    Raises:
        ValueError: a kind without a rating life; κ < 0.1; e_C outside 0..1; P not > 0; no
            C_u and no static rating (one line)."""
    w = "life_modification_factor"
    consts = _life_set(bearing, w)
    check_real("equivalent_load", equivalent_load, "N", lo=0.0, lo_open=True, where=w)
    check_real("viscosity_ratio", viscosity_ratio, "", lo=0.0, where=w)
    _check_kappa(w, viscosity_ratio, "")
    _check_factor_inputs(w, contamination, fatigue_limit)
    Cu = fatigue_load_limit(bearing) if fatigue_limit is None else as_float(fatigue_limit)
    return _a_iso(consts, jnp.asarray(viscosity_ratio, float),
                  contamination * Cu / jnp.asarray(equivalent_load, float))


def _kappa(where, bearing, speed, viscosity, viscosity_ratio):
    """κ from exactly one of ``viscosity`` (ν, m²/s, with ν₁ at ``speed``) and
    ``viscosity_ratio``; ``speed`` (k,) where a bin may stand still (κ there = KAPPA_MAX:
    no revolutions, no damage)."""
    if (viscosity is None) == (viscosity_ratio is None):
        raise ValueError(
            f"{where}: viscosity = {viscosity!r} and viscosity_ratio = {viscosity_ratio!r}: "
            "allowed exactly one of them (the operating kinematic viscosity nu in m^2/s, or "
            "kappa = nu/nu_1)"
        )
    if viscosity_ratio is not None:
        check_real("viscosity_ratio", viscosity_ratio, "", lo=0.0, where=where)
        _check_kappa(where, viscosity_ratio, "")
        return jnp.broadcast_to(jnp.asarray(viscosity_ratio, float), jnp.shape(speed))
    check_real("viscosity", viscosity, "m^2/s", lo=0.0, lo_open=True, where=where)
    w = jnp.asarray(speed, float)
    turning = w > 0
    nu1 = rated_viscosity(jnp.where(turning, w, 1.0), bearing.pitch_diameter)
    kappa = jnp.where(turning, jnp.asarray(viscosity, float) / nu1, KAPPA_MAX)
    if not is_traced(kappa) and np.any(np.asarray(kappa) < KAPPA_MIN):
        k = np.asarray(kappa).reshape(-1)
        i = int(np.argmin(k))
        nu_i = float(np.broadcast_to(np.asarray(viscosity, float), np.shape(kappa)).reshape(-1)[i])
        nu1_i = float(np.broadcast_to(np.asarray(nu1), np.shape(kappa)).reshape(-1)[i])
        bin_ = f"[{i}]" if np.ndim(viscosity) else ""
        w_i = float(np.broadcast_to(np.asarray(w), np.shape(kappa)).reshape(-1)[i])
        raise ValueError(
            f"{where}: viscosity{bin_} = {nu_i:.6g} m^2/s gives kappa = nu/nu_1 = "
            f"{float(k[i]):.4g} (nu_1 = {nu1_i * 1e6:.4g} mm^2/s at speed = {w_i:.6g} rad/s "
            f"and this pitch_diameter): allowed >= {KAPPA_MIN * nu1_i:.4g} m^2/s "
            f"(kappa >= {KAPPA_MIN}, ISO 281's a_ISO)"
        )
    return kappa


def modified_life(bearing: AbstractRollingBearing, radial, axial, speed, *, viscosity=None,
                  viscosity_ratio=None, reliability=0.9, contamination=1.0,
                  fatigue_limit=None) -> ModifiedLife:
    """ISO 281's modified rating life L_nm = a₁ a_ISO L10 of ``bearing`` under F_r = ``radial``
    (N, >= 0) and F_a = ``axial`` (N) at ``speed`` ω (rad/s, > 0) (module docstring).

    Args:
        viscosity: the lubricant's operating kinematic viscosity ν (m²/s; 1 mm²/s = 1e-6),
            κ = ν / ν₁ with :func:`rated_viscosity`; or ``viscosity_ratio`` κ itself (exactly
            one of the two).
        reliability: R, 0.9 to 0.9995 (a₁: :func:`reliability_factor`).
        contamination: e_C, 0 to 1 (ISO 281's guideline ranges: :data:`ISO281_CONTAMINATION`).
        fatigue_limit: C_u (N); ``None``: the kind's ``fatigue_limit``, else estimated from C₀
            (:func:`fatigue_load_limit`).

    Raises:
        ValueError: as :func:`rating_life`; R outside 0.9..0.9995; κ < 0.1; e_C outside
            0..1; both or neither of viscosity and viscosity_ratio (one line)."""
    w = "modified_life"
    consts = _life_set(bearing, w)
    check_real("radial", radial, "N", lo=0.0, where=w)
    check_real("axial", axial, "N", where=w)
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where=w)
    _check_factor_inputs(w, contamination, fatigue_limit)
    a1 = reliability_factor(reliability)
    basic = rating_life(bearing, radial, axial, speed)
    kappa = _kappa(w, bearing, jnp.asarray(speed, float), viscosity, viscosity_ratio)
    Cu = fatigue_load_limit(bearing) if fatigue_limit is None else as_float(fatigue_limit)
    P = basic.equivalent_load
    a = _a_iso(consts, kappa, contamination * Cu / P)
    f = a1 * a
    return ModifiedLife(P, f * basic.revolutions, f * basic.duration, basic.revolutions, a1, a,
                        jnp.minimum(kappa, KAPPA_MAX), Cu)


def spectrum_modified_life(bearing: AbstractRollingBearing, spectrum: BearingSpectrum, *,
                           viscosity=None, viscosity_ratio=None, reliability=0.9,
                           contamination=1.0, fatigue_limit=None) -> ModifiedLife:
    """ISO 281's modified rating life under a :class:`BearingSpectrum`: each bin's a_ISO from
    its own load and κ (its speed's ν₁; ``viscosity`` a scalar or (k,) per bin, or
    ``viscosity_ratio``), the damage by Palmgren–Miner, D = Σ n_i / (a₁ a_ISO,i L10,i)
    (module docstring). Arguments as :func:`modified_life`.

    Raises:
        ValueError: as :func:`modified_life` and :func:`spectrum_life`."""
    w = "spectrum_modified_life"
    consts = _life_set(bearing, w)
    check_instance("spectrum", spectrum, BearingSpectrum, "a jaxgear.bearings.BearingSpectrum",
                   where=w)
    _check_factor_inputs(w, contamination, fatigue_limit)
    a1 = reliability_factor(reliability)
    k = spectrum.radial.shape[0]
    if viscosity is not None and np.ndim(viscosity) > 0:
        check_real("viscosity", viscosity, "m^2/s", lo=0.0, lo_open=True, shape=(k,),
                   shape_text=f"({k},), one per bin, or a scalar", where=w)
    kappa = _kappa(w, bearing, spectrum.speed, viscosity, viscosity_ratio)
    Cu = fatigue_load_limit(bearing) if fatigue_limit is None else as_float(fatigue_limit)
    p = bearing.life_exponent
    P = bearing.equivalent_load(spectrum.radial, spectrum.axial)
    n = spectrum.speed * spectrum.duration / (2.0 * jnp.pi)
    safe_P = jnp.where(P > 0, P, 1.0)
    a = jnp.where(P > 0, _a_iso(consts, kappa, contamination * Cu / safe_P), AISO_MAX)
    L10 = (bearing.dynamic_rating / safe_P) ** p * 1e6
    damage_basic = jnp.sum(jnp.where(P > 0, n / L10, 0.0))
    damage = jnp.sum(jnp.where(P > 0, n / (a1 * a * L10), 0.0))
    P_eq = (jnp.sum(n * P**p) / jnp.sum(n)) ** (1.0 / p)
    return ModifiedLife(P_eq, jnp.sum(n) / damage, jnp.sum(spectrum.duration) / damage,
                        jnp.sum(n) / damage_basic, a1, a, jnp.minimum(kappa, KAPPA_MAX), Cu)
