"""Elastohydrodynamic film thickness of a line contact: the film formula is a kind passed as an
object (:class:`DowsonHigginson`, :class:`PanHamrock`, :class:`Grubin`).

Dimensionless groups (Dowson & Higginson's, with the reduced modulus E' = 2E*,
E* = 1/((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂) the contact modulus of :func:`jaxgear.contact_modulus`):

    U = η₀ u / (E' R),   G = α E',   W = w / (E' R),   H = h / R,

η₀ the dynamic viscosity at the inlet temperature and ambient pressure (Pa·s), u = (u₁ + u₂)/2
the entrainment (mean rolling) speed (m/s), R the relative radius of curvature (m), w the load
per unit length of contact line (N/m), α the pressure–viscosity coefficient (1/Pa).

Isothermal formulas; none carries an inlet shear-heating factor (GEARpie's φ_T, 0.996 to 0.999 at
the FZG points of docs/tribology.md, is left out).

The load group is taken no smaller than ``_MIN_LOAD_PARAMETER``, W >= 1e-12: the formulas'
W^−0.1 … W^−0.17 have a derivative ∝ W^−1.1 … W^−1.17 that overflows to inf below W ≈ 1e-270
(float64) or 1e-34 (float32), and a masked cell's zero cotangent times inf is NaN. A contact
solve in the smooth law gives such loads (1e-276 N/m) to cells far from contact, the corner
cells of contact beyond the path of contact. Gear contacts have W ≈ 1e-5 … 1e-3, the range the
formulas were fitted to; a cell at W = 1e-12 carries 1e-8 of a typical line load and its film
is about ten times the mesh's smallest, so the floor leaves every film that matters unchanged
and gives such a cell a finite film with a zero derivative (``jnp.maximum`` evaluates the power
only at the safe value: the double-``where`` pattern).
"""

from __future__ import annotations

import abc
from typing import ClassVar, NamedTuple

import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import NamedKind, check_instance, check_real

_MIN_LOAD_PARAMETER = 1e-12
"""The smallest load group W = w/(E'R) the film formulas are evaluated at (the module docstring)."""

__all__ = [
    "AbstractFilmFormula",
    "DowsonHigginson",
    "FilmThickness",
    "Grubin",
    "PanHamrock",
    "film_thickness",
]


class FilmThickness(NamedTuple):
    """Central and minimum film thickness h_c, h_min (m), the shapes of the inputs."""

    central: Float[Array, ...]
    minimum: Float[Array, ...]


class AbstractFilmFormula(NamedKind):
    """A line-contact film formula: H_c(U, G, W) and H_min(U, G, W) (the module docstring). A
    new formula is a subclass with ``name``, ``central`` and ``minimum``."""

    name: ClassVar[str]

    @abc.abstractmethod
    def central(self, U, G, W):
        """What a kind supplies (the class docstring)."""

    @abc.abstractmethod
    def minimum(self, U, G, W):
        """What a kind supplies (the class docstring)."""


class DowsonHigginson(AbstractFilmFormula):
    """Dowson's regression of the Dowson–Higginson numerical solutions: minimum film
    H_min = 2.65 U^0.70 G^0.54 W^−0.13 (D. Dowson, Proc. IMechE 182(3A), 1968, 151–167;
    D. Dowson & G. R. Higginson, *Elasto-hydrodynamic Lubrication*, SI ed., Pergamon 1977, §7);
    central film H_c = 3.06 U^0.69 G^0.56 W^−0.10 (D. Dowson & G. R. Toyoda, Proc. 5th
    Leeds–Lyon Symposium, 1979, 60–65), the pair AGMA 925 and most gear texts use."""

    name: ClassVar[str] = "dowson-higginson"

    def central(self, U, G, W):
        return 3.06 * U**0.69 * G**0.56 * W**-0.10

    def minimum(self, U, G, W):
        return 2.65 * U**0.70 * G**0.54 * W**-0.13


class PanHamrock(AbstractFilmFormula):
    """Hamrock's line-contact (rectangular) formulas: H_min = 1.714 W^−0.128 U^0.694 G^0.568,
    H_c = 2.922 W^−0.166 U^0.692 G^0.470 (P. Pan & B. J. Hamrock, J. Tribol. 111(2), 1989,
    246–251; B. J. Hamrock, S. R. Schmid & B. O. Jacobson, *Fundamentals of Fluid Film
    Lubrication*, 2nd ed. 2004, eqs. (18.71)–(18.72)). The Hamrock–Dowson formulas proper are
    for elliptical (point) contacts, their load a force, not a line load; this is their
    line-contact counterpart from the same group, fitted to Hamrock's own numerical solutions."""

    name: ClassVar[str] = "pan-hamrock"

    def central(self, U, G, W):
        return 2.922 * W**-0.166 * U**0.692 * G**0.470

    def minimum(self, U, G, W):
        return 1.714 * W**-0.128 * U**0.694 * G**0.568


class Grubin(AbstractFilmFormula):
    """Grubin's inlet analysis (A. N. Grubin, Central Sci. Res. Inst. Tech. Mech. Eng., Moscow,
    book 30, 1949; DSIR transl. 337): central film H_c = 1.95 (G U)^(8/11) W^(−1/11). Grubin's
    analysis gives no minimum film; ``minimum`` is Dowson's H_min (:class:`DowsonHigginson`), the
    pair GEARpie reports."""

    name: ClassVar[str] = "grubin"

    def central(self, U, G, W):
        return 1.95 * (G * U) ** (8.0 / 11.0) * W ** (-1.0 / 11.0)

    def minimum(self, U, G, W):
        return DowsonHigginson().minimum(U, G, W)


def film_thickness(
    formula: AbstractFilmFormula,
    radius,
    entrainment_speed,
    line_load,
    viscosity,
    pressure_viscosity,
    contact_modulus,
) -> FilmThickness:
    """h_c and h_min (m) of a line contact by ``formula`` (arrays broadcast together).

    Args:
        formula: an :class:`AbstractFilmFormula` kind (an object: ``Grubin()``, not the case
            file's name ``"grubin"``).
        radius: R (m) > 0, the relative radius of curvature in the section normal to the contact
            line. entrainment_speed: u (m/s) > 0. line_load: w (N/m) >= 0.
        viscosity: η₀ (Pa·s) > 0. pressure_viscosity: α (1/Pa) > 0.
        contact_modulus: E* (Pa) > 0 (E' = 2E* in the formulas).

    Returns:
        :class:`FilmThickness` (m). W = w/(E'R) below 1e-12 (a zero
        or vanishing load) is taken as 1e-12: a finite film with a zero derivative in w (the
        module docstring).

    Raises:
        ValueError: a formula that is not a kind, or a concrete input (any entry of an array)
            that is NaN, infinite or out of the range above; one line naming the argument. Traced
            values (under ``jit``, ``vmap``, ``grad``) are not checked: a non-positive radius or
            speed there gives inf or NaN, which callers mask
            (:func:`jaxgear.tribology.mesh_tribology` does).
    """
    where = "film_thickness"
    check_instance(
        "formula",
        formula,
        AbstractFilmFormula,
        "a film formula kind: jaxgear.tribology.DowsonHigginson(), PanHamrock(), Grubin(), ...",
        where,
    )
    for name, value, unit, lo_open in (
        ("radius", radius, "m", True),
        ("entrainment_speed", entrainment_speed, "m/s", True),
        ("line_load", line_load, "N/m", False),
        ("viscosity", viscosity, "Pa·s", True),
        ("pressure_viscosity", pressure_viscosity, "1/Pa", True),
        ("contact_modulus", contact_modulus, "Pa", True),
    ):
        check_real(name, value, unit, lo=0.0, lo_open=lo_open, where=where)
    e_prime = 2.0 * jnp.asarray(contact_modulus)
    U = viscosity * entrainment_speed / (e_prime * radius)
    G = pressure_viscosity * e_prime
    W = jnp.maximum(line_load / (e_prime * radius), _MIN_LOAD_PARAMETER)
    return FilmThickness(radius * formula.central(U, G, W), radius * formula.minimum(U, G, W))
