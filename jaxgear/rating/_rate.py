"""A rating at one operating point: :func:`rate` (the load factors, pitting and bending of the
settings' standard, :attr:`jaxgear.rating.RatingSettings.standard`, ISO 6336:2019 method B by
default) and its parts :func:`load_factors`, :func:`pitting_rating`, :func:`bending_rating`; the
arguments checked here, once, before the standard computes (:func:`check_rating_arguments`)."""

from __future__ import annotations

import equinox as eqx

from .._util import check_instance
from ._factors import LoadFactors
from ._geometry import AbstractRatingGeometry
from ._settings import OperatingPoint, RatingSettings
from ._standard import AbstractRatingStandard

__all__ = [
    "Rating",
    "bending_rating",
    "check_rating_arguments",
    "load_factors",
    "pitting_rating",
    "rate",
]


class Rating(eqx.Module):
    """A whole rating: ``factors`` (:class:`jaxgear.rating.LoadFactors`), ``pitting`` and
    ``bending`` (the standard's results: :class:`jaxgear.rating.PittingRating`,
    :class:`jaxgear.rating.BendingRating` for ISO 6336), ``standard`` (the
    :class:`jaxgear.rating.AbstractRatingStandard` it follows); :attr:`method` its label (e.g.
    "ISO 6336:2019 method B"), :meth:`summary` the JSON section, :meth:`scope_notes` where the
    inputs leave the standard's scope."""

    factors: LoadFactors
    pitting: eqx.Module
    bending: eqx.Module
    standard: AbstractRatingStandard

    @property
    def method(self) -> str:
        """The standard's label (:attr:`jaxgear.rating.AbstractRatingStandard.label`)."""
        return self.standard.label

    @property
    def unconfirmed(self) -> tuple[str, ...]:
        """The factors whose formula in this standard (:attr:`method`) no published worked
        example confirms (:attr:`jaxgear.rating.AbstractRatingStandard.unconfirmed`:
        ``("Y_beta",)`` for :class:`jaxgear.rating.Edition2019`, ``()`` for
        :class:`jaxgear.rating.Edition2006`), attribute names of :attr:`pitting`,
        :attr:`bending` and :attr:`factors`, for the report to state."""
        return tuple(self.standard.unconfirmed)

    def scope_notes(self) -> list[str]:
        """Where the inputs leave the standard's scope, one line each
        (:meth:`jaxgear.rating.AbstractRatingStandard.scope_notes`; ISO 6336's: Y_S's
        1 <= q_s < 8, K_v's main resonance range, Y_B's rim). Concrete values only."""
        return self.standard.scope_notes(self)

    def summary(self) -> dict:
        """The ``rating`` section of ``summary.json``: SI units (stresses in Pa), per-gear values
        as [pinion, gear] lists, each load factor with its source
        (:meth:`jaxgear.rating.AbstractRatingStandard.summary`)."""
        return self.standard.summary(self)


def check_rating_arguments(where: str, geometry, operating, settings) -> None:
    """Refuse, in one ``ValueError`` line naming the argument, a rating's ``geometry`` that is
    not a :class:`jaxgear.rating.AbstractRatingGeometry` (:class:`jaxgear.rating.RatingGeometry`,
    :class:`jaxgear.rating.InternalRatingGeometry`), an
    ``operating`` point that is not an :class:`jaxgear.rating.OperatingPoint` or ``settings`` that
    are not :class:`jaxgear.rating.RatingSettings` (before any of their fields is read)."""
    check_instance("geometry", geometry, AbstractRatingGeometry,
                   "a jaxgear.rating.RatingGeometry or jaxgear.rating.InternalRatingGeometry", where)
    check_instance("operating", operating, OperatingPoint,
                   "a jaxgear.rating.OperatingPoint(torque, speed)", where)
    check_instance("settings", settings, RatingSettings, "a jaxgear.rating.RatingSettings", where)


def load_factors(geometry, operating, settings) -> LoadFactors:
    """The load factors K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα at the operating point, of the
    settings' standard (:meth:`jaxgear.rating.AbstractRatingStandard.load_factors`; ISO
    6336-1:2019 clauses 6, 7, 8, method B: :func:`jaxgear.rating.iso6336_load_factors`); given
    factors replace computed ones.

    Args:
        geometry: :class:`jaxgear.rating.RatingGeometry` or
            :class:`jaxgear.rating.InternalRatingGeometry`.
        operating: :class:`jaxgear.rating.OperatingPoint` (N·m, rad/s). settings:
            :class:`jaxgear.rating.RatingSettings`.

    Raises:
        ValueError: an argument of the wrong kind (:func:`check_rating_arguments`)."""
    check_rating_arguments("load_factors", geometry, operating, settings)
    return settings.standard.load_factors(geometry, operating, settings)


def pitting_rating(geometry, operating, settings, factors: LoadFactors | None = None):
    """The pitting rating of the settings' standard at the operating point
    (:meth:`jaxgear.rating.AbstractRatingStandard.pitting`; ISO 6336-2 method B:
    :class:`jaxgear.rating.PittingRating`, stresses in Pa, Z_E in √Pa). ``factors``: the load
    factors (default :func:`load_factors` of the same arguments).

    Raises:
        ValueError: an argument of the wrong kind (:func:`check_rating_arguments`)."""
    check_rating_arguments("pitting_rating", geometry, operating, settings)
    if factors is None:
        factors = settings.standard.load_factors(geometry, operating, settings)
    return settings.standard.pitting(geometry, operating, settings, factors)


def bending_rating(geometry, operating, settings, factors: LoadFactors | None = None):
    """The bending rating of the settings' standard at the operating point
    (:meth:`jaxgear.rating.AbstractRatingStandard.bending`; ISO 6336-3 method B:
    :class:`jaxgear.rating.BendingRating`, stresses in Pa; Y_β of the edition:
    :class:`jaxgear.rating.Edition2019` (1 − ε_β β/120°)/cos³ β,
    :class:`jaxgear.rating.Edition2006` 1 − ε_β β/120°, ε_β <= 1, β <= 30°). ``factors``: the
    load factors (default :func:`load_factors` of the same arguments).

    Raises:
        ValueError: an argument of the wrong kind (:func:`check_rating_arguments`)."""
    check_rating_arguments("bending_rating", geometry, operating, settings)
    if factors is None:
        factors = settings.standard.load_factors(geometry, operating, settings)
    return settings.standard.bending(geometry, operating, settings, factors)


def rate(geometry, operating, settings) -> Rating:
    """The whole rating at one operating point, of the settings' standard
    (:attr:`jaxgear.rating.RatingSettings.standard`, ISO 6336:2019 method B by default): its load
    factors, pitting and bending (:func:`load_factors`, :func:`pitting_rating`,
    :func:`bending_rating`).

    Args:
        geometry: a pair's ``RatingGeometry.of(pair)``; an internal pair's
            ``InternalRatingGeometry.of(pair)``, member 0 the pinion, member 1 the internal
            gear, with the standard's internal-gear rules.
        operating: :class:`jaxgear.rating.OperatingPoint` (torque T₁ on the pinion, N·m; its speed,
            rad/s). settings: :class:`jaxgear.rating.RatingSettings`.

    Returns:
        :class:`Rating`. Pure and jit-able (``eqx.filter_jit``); differentiable with respect to
        the array fields of the geometry, the operating point and the settings.

    Raises:
        ValueError: an argument of the wrong kind (:func:`check_rating_arguments`)."""
    check_rating_arguments("rate", geometry, operating, settings)
    standard = settings.standard
    factors = standard.load_factors(geometry, operating, settings)
    return Rating(
        factors,
        standard.pitting(geometry, operating, settings, factors),
        standard.bending(geometry, operating, settings, factors),
        standard,
    )
