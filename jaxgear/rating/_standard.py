"""The seam of the load-capacity rating: a rating standard is a kind, passed as an object
(:attr:`jaxgear.rating.RatingSettings.standard`), as a solver is in diffrax. The rating pipeline
(:func:`jaxgear.rating.rate`, ``jaxgear run``'s rating section) asks a standard for its load
factors, its pitting and its bending results and the ``summary.json`` section of them; ISO 6336:2006
and ISO 6336:2019 are two of its kinds (:class:`jaxgear.rating.Edition2006`,
:class:`jaxgear.rating.Edition2019`), a second standard (AGMA 2001, say) is a third one written
beside them. The names a case file spells (``[rating] edition = 2006``) map to these objects in
:mod:`jaxgear.io` only."""

from __future__ import annotations

import abc
import dataclasses
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp

__all__ = ["AbstractRatingStandard"]

#: the load factors every standard's :class:`jaxgear.rating.LoadFactors` holds, in the order the
#: ``summary.json`` section lists them
FACTOR_NAMES = ("K_A", "K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")


def _value(a):
    a = jnp.asarray(a)
    return [float(t) for t in a] if a.ndim else float(a)


class AbstractRatingStandard(eqx.Module):
    """A load-capacity standard (and its edition) a rating follows.

    A kind: subclass it, give it a :attr:`label` and the three computations below, and pass an
    instance as :attr:`jaxgear.rating.RatingSettings.standard` (a case in Python:
    ``case.replace(rating_standard=...)``, :class:`jaxgear.io.Case`). Every method is given the
    rating's checked arguments: ``geometry`` (:class:`jaxgear.rating.RatingGeometry` or
    :class:`jaxgear.rating.InternalRatingGeometry`), ``operating``
    (:class:`jaxgear.rating.OperatingPoint`: torque T₁ on the pinion, N·m, and its speed, rad/s) and
    ``settings`` (:class:`jaxgear.rating.RatingSettings`), all in SI units.

    Results. :meth:`pitting` returns an ``equinox.Module`` with at least ``sigma_H`` (Pa) and
    ``S_H`` (-), per gear (2,) [pinion, gear]; :meth:`bending` one with ``sigma_F`` (Pa) and
    ``S_F`` (-), per gear. :meth:`summary` turns them into the ``summary.json`` section
    ``{"method", "factors": {name: {"value", "source"}}, "pitting": {...}, "bending": {...}}``
    (the default: every array field, a field ``x`` in pascals named ``x_Pa`` when its name
    starts with ``sigma``).

    Attributes:
        label: the standard's name and edition, e.g. "ISO 6336:2019 method B"
            (:attr:`jaxgear.rating.Rating.method`).
        unconfirmed: the names of the results whose formula in this standard no published
            worked example confirms (empty: all confirmed), for the report to state.
    """

    label: eqx.AbstractClassVar[str]
    unconfirmed: ClassVar[tuple[str, ...]] = ()

    @abc.abstractmethod
    def load_factors(self, geometry, operating, settings):
        """The load factors at the operating point: a :class:`jaxgear.rating.LoadFactors`
        (K_A, K_v, K_Hβ, K_Fβ, K_Hα, K_Fα as the standard defines them, each with its source;
        a factor given in ``settings.given`` replaces the computed one)."""

    @abc.abstractmethod
    def pitting(self, geometry, operating, settings, factors):
        """The surface durability (pitting) results under the load ``factors``."""

    @abc.abstractmethod
    def bending(self, geometry, operating, settings, factors):
        """The tooth bending results under the load ``factors``."""

    def scope_notes(self, rating) -> list[str]:
        """Where the inputs of ``rating`` (a :class:`jaxgear.rating.Rating` of this standard) leave
        the standard's scope, one line each (default: none). Concrete values only."""
        return []

    def summary(self, rating) -> dict:
        """The ``rating`` section of ``summary.json`` of ``rating`` (SI units; per-gear values
        as [pinion, gear] lists; each load factor with its source)."""
        f = rating.factors

        def fields(m):
            out = {}
            for field in dataclasses.fields(m):
                v = getattr(m, field.name)
                if isinstance(v, jnp.ndarray | float | int):
                    key = f"{field.name}_Pa" if field.name.startswith("sigma") else field.name
                    out[key] = _value(v)
            return out

        return {
            "method": self.label,
            "factors": {
                k: {"value": _value(getattr(f, k)), "source": f.sources[k]} for k in FACTOR_NAMES
            },
            "pitting": fields(rating.pitting),
            "bending": fields(rating.bending),
        }

    def measured_factors(self, name: str) -> tuple[str, ...]:
        """The load factors (of :data:`FACTOR_NAMES`) that a factor ``name`` measured by
        jaxgear gives in place of the standard's (default: itself alone)."""
        return (name,)

    def with_measured(self, geometry, settings, measured: dict):
        """``settings`` with the load factors ``measured`` (name → value, of
        :data:`FACTOR_NAMES`, measured by jaxgear: :func:`jaxgear.rating.with_measured`)
        given in place of the standard's (each of :meth:`measured_factors`), each at least 1
        (default; a standard may bound a factor too, as ISO 6336 does)."""
        given = {}
        for name, value in measured.items():
            given.update(dict.fromkeys(self.measured_factors(name), max(float(value), 1.0)))
        return eqx.tree_at(lambda s: s.given, settings,
                           dataclasses.replace(settings.given, **given))
