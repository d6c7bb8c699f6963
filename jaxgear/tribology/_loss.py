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
    "ohlendorf_formula",
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
    return ohlendorf_formula(pair.gear_ratio, pair.pinion.teeth,
                             math.cos(pair.base_helix_angle), pair.transverse_contact_ratio,
                             e1, e2)


def ohlendorf_formula(gear_ratio, pinion_teeth, cos_base_helix, transverse_contact_ratio,
                      e1, e2):
    """Ohlendorf's H_V (-) from its terms (the module docstring): u, z₁, cos β_b, ε_α and the
    addendum contact ratios ε₁ (pinion), ε₂ (gear). Plain arithmetic: floats, NumPy or JAX
    arrays of one shape (a batch of pairs). :func:`ohlendorf_loss_factor` of a pair."""
    u = gear_ratio
    return (
        math.pi
        * (u + 1.0)
        / (pinion_teeth * u * cos_base_helix)
        * (1.0 - transverse_contact_ratio + e1**2 + e2**2)
    )


class AbstractFriction(eqx.Module):
    """The mean coefficient of friction of a mesh: ``coefficient(pair, lubricant, torque,
    speed, roughness)`` (-) of one pair, and ``at_pitch_point(...)`` of a batch of pairs from
    their pitch points' quantities (a sizing's candidates). A new law is a subclass."""

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def coefficient(self, pair, lubricant, torque, speed, roughness) -> Float[Array, ""]:
        """What a kind supplies (the class docstring)."""

    @abc.abstractmethod
    def at_pitch_point(self, load_per_width, sum_speed, radius, viscosity, roughness):
        """μ from the pitch point's quantities, in SI, for a batch of pairs (plain arithmetic:
        NumPy or JAX arrays of one shape): the transverse base-circle load per face width
        F_bt/b (N/m), the sum of the flanks' speeds v_ΣC (m/s), the transverse relative
        radius of curvature ρ_C (m), the oil's dynamic viscosity η (Pa·s) and R_a = (R_a1 +
        R_a2)/2 (m). :meth:`coefficient` of a pair is this at its pitch point."""


class GivenFriction(AbstractFriction):
    """A given coefficient of friction μ in (0, 1] (a measured value, a catalogue's)."""

    name: ClassVar[str] = "given"
    value: Float[Array, ""]

    def __init__(self, value):
        check_real("value", value, lo=0.0, hi=1.0, lo_open=True, where="GivenFriction")
        self.value = as_float(value)

    def coefficient(self, pair, lubricant, torque, speed, roughness):
        return self.value

    def at_pitch_point(self, load_per_width, sum_speed, radius, viscosity, roughness):
        return self.value + 0.0 * load_per_width


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
        v_sum = 2.0 * speed * rho1  # 2 v_t sin α_wt (m/s)
        return self.at_pitch_point(torque / rb1 / pair.face_width, v_sum, rho_c,
                                   lubricant.dynamic_viscosity,
                                   0.5 * (roughness[0] + roughness[1]))

    def at_pitch_point(self, load_per_width, sum_speed, radius, viscosity, roughness):
        f_bt_b = load_per_width * 1e-3  # N/mm
        eta = viscosity * 1e3  # mPa·s
        ra = roughness * 1e6  # µm
        return (
            0.048
            * (f_bt_b / (sum_speed * radius * 1e3)) ** 0.2
            * eta**-0.05
            * ra**0.25
            * self.lubricant_factor
        )
