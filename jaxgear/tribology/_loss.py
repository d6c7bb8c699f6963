"""Tooth friction: the mean coefficient of friction of the mesh as a kind passed as an object
(:class:`Schlenk`, :class:`GivenFriction`), and Ohlendorf's tooth loss factor H_V.

Schlenk's mean coefficient of friction of the mesh, as ISO/TR 14179-2:2001 gives it (L. Schlenk,
Dissertation TU München 1994; FVA 345), in the formula's own units:

    μ_mZ = 0.048 (F_bt/b / (v_ΣC ρ_C))^0.2 η_oil^−0.05 R_a^0.25 X_L,

F_bt/b the transverse base-circle load per face width (N/mm), v_ΣC = 2 v_t sin α_wt the sum of
the flanks' speeds at the pitch point (m/s), ρ_C the relative radius of curvature at the pitch
point in the transverse section (mm), η_oil the dynamic viscosity at the oil temperature
(mPa·s), R_a = (R_a1 + R_a2)/2 (µm), X_L the lubricant factor (1.0 mineral oil; GEARpie's
fitted 0.85 for its mineral oil, 0.65 for its PAO).

Ohlendorf's tooth loss factor (H. Ohlendorf, Dissertation TU München 1958; ISO/TR 14179-2:2001
§ 4.3.2; B.-R. Höhn, K. Michaelis, A. Wimmer, AGMA 07FTM14, 2007): the mean sliding power
over μ P_in for a load shared evenly among the pairs in contact, in closed form

    H_V = π (u + 1)/(z₁ u cos β_b) (1 − ε_α + ε₁² + ε₂²),

ε₁, ε₂ the addendum contact ratios of pinion and gear (the parts of ε_α from the pitch point
to the pinion's and the gear's end of the path of contact). Exact for spur pairs with
ε_α < 2 (the limit docs/tribology.md shows the integrated loss reaching); for helical pairs
an approximation (the sum of contact-line lengths varies through the mesh).
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
from jaxtyping import Array, Float

from .._geometry import AbstractGearPair
from .._util import as_float, check_real

__all__ = [
    "AbstractFriction",
    "GivenFriction",
    "Schlenk",
    "ohlendorf_loss_factor",
    "pitch_point_roll",
]


def pitch_point_roll(pair: AbstractGearPair) -> float:
    """s_C (m): the base-plane coordinate of the pitch point, r_b1 tan α_wt − ρ_A."""
    return pair.base_radii[0] * math.tan(pair.operating_pressure_angle) - pair.start_roll


def ohlendorf_loss_factor(pair: AbstractGearPair) -> float:
    """Ohlendorf's H_V (-) of ``pair`` (the module docstring; ISO/TR 14179-2:2001 § 4.3.2)."""
    s_c = pitch_point_roll(pair)
    e2 = s_c / pair.base_pitch
    e1 = (pair.path_of_contact - s_c) / pair.base_pitch
    u = pair.gear_ratio
    return (
        math.pi
        * (u + 1.0)
        / (pair.pinion.teeth * u * math.cos(pair.base_helix_angle))
        * (1.0 - pair.transverse_contact_ratio + e1**2 + e2**2)
    )


class AbstractFriction(eqx.Module):
    """The mean coefficient of friction of a mesh: ``coefficient(pair, lubricant, torque,
    speed, roughness)`` (-). A new law is a subclass."""

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def coefficient(self, pair, lubricant, torque, speed, roughness) -> Float[Array, ""]:
        """What a kind supplies (the class docstring)."""


class GivenFriction(AbstractFriction):
    """A given coefficient of friction μ in (0, 1] (a measured value, a catalogue's)."""

    name: ClassVar[str] = "given"
    value: Float[Array, ""]

    def __init__(self, value):
        check_real("value", value, lo=0.0, hi=1.0, lo_open=True, where="GivenFriction")
        self.value = as_float(value)

    def coefficient(self, pair, lubricant, torque, speed, roughness):
        return self.value


class Schlenk(AbstractFriction):
    """Schlenk's μ_mZ (ISO/TR 14179-2; the module docstring) with the lubricant factor
    ``lubricant_factor`` X_L in (0, 2] (default 1.0, mineral oil)."""

    name: ClassVar[str] = "schlenk"
    lubricant_factor: Float[Array, ""]

    def __init__(self, lubricant_factor=1.0):
        check_real(
            "lubricant_factor", lubricant_factor, lo=0.0, hi=2.0, lo_open=True, where="Schlenk"
        )
        self.lubricant_factor = as_float(lubricant_factor)

    def coefficient(self, pair, lubricant, torque, speed, roughness):
        rb1, rb2 = pair.base_radii
        t = math.tan(pair.operating_pressure_angle)
        rho1, rho2 = rb1 * t, rb2 * t
        # transverse relative radius at the pitch point (internal: the concave ring flank)
        rho_c = rho1 * rho2 / (rho2 + (1.0 if pair.gear.teeth > 0 else -1.0) * rho1)
        f_bt_b = torque / rb1 / pair.face_width * 1e-3  # N/mm
        v_sum = 2.0 * speed * rho1  # 2 v_t sin α_wt (m/s)
        eta = lubricant.dynamic_viscosity * 1e3  # mPa·s
        ra = 0.5 * (roughness[0] + roughness[1]) * 1e6  # µm
        return (
            0.048
            * (f_bt_b / (v_sum * rho_c * 1e3)) ** 0.2
            * eta**-0.05
            * ra**0.25
            * self.lubricant_factor
        )
