"""Flash temperature and scuffing of one mesh along its path of contact: Blok's flash temperature
from jaxgear's local line loads (the flash-temperature method of ISO/TS 6336-20, formerly
ISO/TR 13989-1) and the integral-temperature method (ISO/TS 6336-21, formerly ISO/TR 13989-2),
with their safety factors. docs/tribology.md § "Flash temperature and scuffing".

Blok's flash temperature of a band heat source of semi-width b_H moving over both flanks at
high Péclet number, the frictional heat μ w v_g shared so that both surfaces reach the same
temperature (H. Blok, Proc. General Discussion on Lubrication, IMechE 1937, vol. 2, 222–235;
the form ISO/TS 6336-20 starts from):

    θ_fl = 1.11 μ w |v₁ − v₂| / ((B_M1 √v₁ + B_M2 √v₂) √(2 b_H)),

μ the coefficient of friction, w the normal line load (N/m), v₁, v₂ the flanks' speeds normal to
the contact line (m/s; the transverse speeds × cos β_b), b_H = √(4 w R/(π E*)) the Hertzian
semi-width (R the relative radius in the normal section, E* the contact modulus) and
B_M = √(λ_M ρ_M c_M) each flank's thermal contact coefficient (W s^½/(m² K); ISO/TS 6336-20's
steel value 13.795 N/(mm s^½ K)). The constant 1.11 is the maximum over the band of Jaeger's
surface temperature under a semi-elliptical (Hertzian) flux (the tests evaluate it by quadrature).

With involute kinematics (Γ = ρ₁/(r_b1 tan α_wt) − 1 the position on the path, 0 at the pitch
point) and Hertz's b_H substituted, Blok's formula becomes the TS's closed form

    θ_fl = 0.62 X_M μ (X_Γ w_Bn)^¾ (v_t sin α_wt)^½ cos^¾ β_b / (a sin α_wt)^¼
           × (1 + u)^½ |√(1 + Γ) − √(1 − Γ/u)| / ((1 + Γ)(u − Γ))^¼,

X_M = E_r^¼ / B_M the thermo-elastic factor (E_r = 2E*; 50 K N^−¾ s^½ m^−½ mm for steel in the
TS's units), X_Γ the TS's load-sharing factor, w_Bn = T/(r_b1 b) the normal load per unit length
of one contact line carrying it all, v_t = ω₁ a/(1 + u) the pitch-line speed
(:func:`ts_flash_temperature`). The TS's approach factor X_J (an empirical rise in the approach
of unmodified gears) is taken as 1. :func:`mesh_scuffing` uses jaxgear's own line loads in
place of X_Γ w_Bn: the load sharing comes from the contact solve, not from the TS's X_Γ.

Flash-temperature method (ISO/TS 6336-20): θ_flm the mean of θ_fl along the path of contact,
the bulk temperature θ_M = θ_oil + 0.47 X_S X_mp θ_flm (:class:`FlashBulkTemperature`),
the contact temperature θ_B = θ_M + θ_fl, the scuffing temperature from the lubricant's FZG
load stage θ_S = 80 °C + (0.85 + 1.4 X_W) X_L S_FZG² K (:func:`fzg_scuffing_temperature`) and
the safety factor S_B = (θ_S − θ_oil)/(θ_B,max − θ_oil).

Integral-temperature method (ISO/TS 6336-21): θ_fla,int the mean flash temperature along the
path (here θ_flm, from jaxgear's loads; the TS's closed form θ_flaE X_ε is not carried), the
bulk temperature θ_M,int = θ_oil + C₁ X_S X_mp θ_fla,int (C₁ = 0.7; X_S, X_mp those of
:class:`FlashBulkTemperature`), the integral temperature
θ_int = θ_M,int + C₂ θ_fla,int (C₂ = 1.5), the allowable one from the FZG test
θ_intS = θ_MT + X_WrelT C₂ θ_flaintT with T₁T = 3.726 S_FZG² N·m, θ_MT = 80 + 0.23 T₁T X_L,
θ_flaintT = 0.2 T₁T (100/ν₄₀)^0.02 X_L (ν₄₀ in mm²/s) (:func:`fzg_integral_scuffing_temperature`),
and the safety factor S_intS = θ_intS/θ_int.

Sources of the constants: no text of the TSs was available. 0.47 X_S X_mp, θ_S = 80 + (0.85 +
1.4 X_W) X_L S², S_B, C₁ = 0.7 (with X_S X_mp), C₂ = 1.5, T₁T = 3.726 S², 0.23, 0.2, (100/ν₄₀)^0.02,
θ_intS = θ_MT + X_WrelT C₂ θ_flaintT (X_WrelT = X_W/X_WT, X_WT = 1) and S_intS are those of ISO/TR
13989-1/-2:2000, the TSs' predecessors, as an independent public implementation transcribes them
(hakangunes258/mekanika, ``Services/Iso13989FlashTemperature.cs`` eqs. (22), (99), (100);
``Services/Iso13989IntegralTemperature.cs`` eqs. (14), (17), (20), (21), (94)–(97), (102)); the
same C₂ = 1.5 and the two methods' structure in the GB/Z 6413.1/.2 comparison at
zhygear.com/comparative-study-on-cylindrical-gear-scuffing-capacity-standards. docs/tribology.md
says which are confirmed and how far.
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .._geometry import AbstractGearPair
from .._pressure import contact_modulus
from .._quasi_static import MeshResult, QuasiStaticResult
from .._util import as_float, check_instance, check_real, is_traced, safe_max
from ._lubricant import Lubricant
from ._mesh import MeshTribology

__all__ = [
    "STEEL_THERMAL_CONTACT_COEFFICIENT",
    "AbstractBulkTemperature",
    "FlashBulkTemperature",
    "GivenBulkTemperature",
    "MeshScuffing",
    "ScuffingLimits",
    "blok_flash_temperature",
    "fzg_integral_scuffing_temperature",
    "fzg_pinion_torque",
    "fzg_scuffing_temperature",
    "mesh_flash_temperature",
    "mesh_scuffing",
    "thermal_contact_coefficient",
    "ts_flash_temperature",
]

#: B_M of steel (W s^½/(m² K)): ISO/TS 6336-20's 13.795 N/(mm s^½ K)
STEEL_THERMAL_CONTACT_COEFFICIENT = 13795.0

_C1, _C2 = 0.7, 1.5  # ISO/TS 6336-21: bulk and weighting factors of the integral temperature


def thermal_contact_coefficient(conductivity, density, specific_heat) -> Float[Array, ...]:
    """B_M = √(λ_M ρ_M c_M) (W s^½/(m² K)) from the conductivity λ_M (W/(m K)), the density
    ρ_M (kg/m³) and the specific heat c_M (J/(kg K)), each > 0."""
    w = "thermal_contact_coefficient"
    for name, v, unit in (
        ("conductivity", conductivity, "W/(m K)"),
        ("density", density, "kg/m³"),
        ("specific_heat", specific_heat, "J/(kg K)"),
    ):
        check_real(name, v, unit, lo=0.0, lo_open=True, where=w)
    return jnp.sqrt(jnp.asarray(conductivity) * density * specific_heat)


def blok_flash_temperature(
    friction_coefficient, line_load, speed_1, speed_2, half_width, coefficient_1, coefficient_2
) -> Float[Array, ...]:
    """Blok's flash temperature θ_fl (K) (the module docstring), arrays broadcast together.

    Args:
        friction_coefficient: μ (-). line_load: w (N/m) ≥ 0.
        speed_1, speed_2: the flanks' speeds normal to the contact line (m/s) > 0.
        half_width: b_H (m) > 0, the Hertzian semi-width.
        coefficient_1, coefficient_2: B_M1, B_M2 (W s^½/(m² K)).

    Returns:
        θ_fl (K), the shape of the broadcast inputs. Not validated (traced callers); zero speeds
        or width give inf or NaN, callers mask them (:func:`mesh_scuffing` does).
    """
    v1, v2 = jnp.asarray(speed_1), jnp.asarray(speed_2)
    return (
        1.11
        * friction_coefficient
        * line_load
        * jnp.abs(v1 - v2)
        / ((coefficient_1 * jnp.sqrt(v1) + coefficient_2 * jnp.sqrt(v2)) * jnp.sqrt(2 * half_width))
    )


def ts_flash_temperature(
    pair: AbstractGearPair,
    gamma,
    load_sharing,
    friction_coefficient,
    torque,
    speed,
    youngs_modulus,
    poisson_ratio,
    thermal_coefficient=STEEL_THERMAL_CONTACT_COEFFICIENT,
) -> Float[Array, ...]:
    """ISO/TS 6336-20's closed form θ_fl(Γ) (K) with its load-sharing factor X_Γ (the module
    docstring; X_J = 1), for an external pair of one material.

    Args:
        pair: an external gear pair, its pinion driving.
        gamma: Γ, the positions on the path of contact (-), any shape.
        load_sharing: X_Γ at those positions (-), broadcast with ``gamma``.
        friction_coefficient: μ (-). torque: pinion torque T (N·m). speed: ω₁ (rad/s).
        youngs_modulus, poisson_ratio: of both gears (Pa, -).
        thermal_coefficient: B_M of both gears (W s^½/(m² K)), default steel's.

    Returns:
        θ_fl (K), the broadcast shape of ``gamma`` and ``load_sharing``.

    Raises:
        ValueError: an internal pair; torque or speed not > 0.
    """
    w_ = "ts_flash_temperature"
    check_instance("pair", pair, AbstractGearPair, "a GearPair", w_)
    if pair.gear_ratio < 0:
        raise ValueError(
            f"{w_}: pair = internal (u = {pair.gear_ratio:g}): allowed an external pair"
        )
    check_real("torque", torque, "N·m", lo=0.0, lo_open=True, where=w_)
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where=w_)
    x_m = (2.0 * contact_modulus(youngs_modulus, poisson_ratio)) ** 0.25 / thermal_coefficient
    return _ts_flash(
        pair.gear_ratio,
        pair.center_distance,
        math.sin(pair.operating_pressure_angle),
        math.cos(pair.base_helix_angle),
        pair.base_radii[0] * pair.face_width,
        jnp.asarray(gamma),
        load_sharing,
        friction_coefficient,
        torque,
        speed,
        x_m,
    )


def _ts_flash(u, a, sin_awt, cos_bb, rb1_b, gamma, load_sharing, mu, torque, speed, x_m):
    """:func:`ts_flash_temperature`'s closed form on numbers (traceable): u, a (m), sin α_wt,
    cos β_b, r_b1 b (m²), Γ, X_Γ, μ, T (N·m), ω₁ (rad/s), X_M = E_r^¼/B_M (SI). Shared by
    :func:`ts_flash_temperature` and :func:`ts_scuffing`."""
    g = gamma
    w_bn = torque / rb1_b
    v_t = speed * a / (1.0 + u)
    # the positions are kept on the flanks (Γ in (−1, u)): an invalid pair gives 0, not NaN
    x_g = (1.0 + u) ** 0.5 * jnp.abs(
        jnp.sqrt(jnp.maximum(1.0 + g, 0.0)) - jnp.sqrt(jnp.maximum(1.0 - g / u, 0.0)))
    x_g = x_g / jnp.maximum((1.0 + g) * (u - g), 1e-12) ** 0.25
    c = 1.11 / math.sqrt(2.0) * (math.pi / 8.0) ** 0.25  # 0.62
    return (
        c
        * x_m
        * mu
        * (load_sharing * w_bn) ** 0.75
        * (v_t * sin_awt) ** 0.5
        * cos_bb**0.75
        / (a * sin_awt) ** 0.25
        * x_g
    )


def fzg_pinion_torque(load_stage) -> float:
    """T₁T = 3.726 S_FZG² (N·m): the pinion torque of FZG load stage ``load_stage`` (1 to 14;
    ISO/TS 6336-21's fit to the A/8.3/90 test's load stages of ISO 14635-1)."""
    check_real("load_stage", load_stage, lo=1.0, hi=14.0, where="fzg_pinion_torque")
    return 3.726 * float(load_stage) ** 2


def fzg_scuffing_temperature(load_stage, lubricant_factor=1.0, structural_factor=1.0) -> float:
    """ISO/TS 6336-20's scuffing temperature θ_S (°C) of an oil that passed FZG load stage
    ``load_stage`` (A/8.3/90 test, 1 to 14): 80 + (0.85 + 1.4 X_W) X_L S_FZG², X_L the TS's
    lubricant factor (1 for mineral oil), X_W the structural factor (1 for through-hardened
    steel)."""
    w = "fzg_scuffing_temperature"
    check_real("load_stage", load_stage, lo=1.0, hi=14.0, where=w)
    check_real("lubricant_factor", lubricant_factor, lo=0.0, hi=2.0, lo_open=True, where=w)
    check_real("structural_factor", structural_factor, lo=0.0, hi=2.0, lo_open=True, where=w)
    return 80.0 + (0.85 + 1.4 * structural_factor) * lubricant_factor * float(load_stage) ** 2


def fzg_integral_scuffing_temperature(
    load_stage, viscosity_40, lubricant_factor=1.0, relative_structural_factor=1.0
) -> float:
    """ISO/TS 6336-21's allowable integral temperature θ_intS (°C) from the FZG test (the module
    docstring): load stage 1 to 14, ν₄₀ (m²/s) > 0, X_L (1 for mineral oil), X_WrelT."""
    w = "fzg_integral_scuffing_temperature"
    check_real("load_stage", load_stage, lo=1.0, hi=14.0, where=w)
    check_real("viscosity_40", viscosity_40, "m²/s", lo=0.0, hi=0.1, lo_open=True, where=w)
    check_real("lubricant_factor", lubricant_factor, lo=0.0, hi=2.0, lo_open=True, where=w)
    check_real(
        "relative_structural_factor",
        relative_structural_factor,
        lo=0.0,
        hi=2.0,
        lo_open=True,
        where=w,
    )
    t1t = fzg_pinion_torque(load_stage)
    theta_mt = 80.0 + 0.23 * t1t * lubricant_factor
    nu40 = viscosity_40 if is_traced(viscosity_40) else float(viscosity_40)
    theta_fl = 0.2 * t1t * (100.0 / (nu40 * 1e6)) ** 0.02 * lubricant_factor
    return theta_mt + relative_structural_factor * _C2 * theta_fl


class AbstractBulkTemperature(eqx.Module):
    """The flash-temperature method's bulk temperature θ_M (°C) from the oil temperature and the
    mean flash temperature θ_flm: ``bulk(oil_temperature, mean_flash)``. A new rule is a
    subclass."""

    name: eqx.AbstractClassVar[str]

    @abc.abstractmethod
    def bulk(self, oil_temperature, mean_flash):
        """What a kind supplies (the class docstring)."""

    def integral_bulk(self, oil_temperature, mean_flash):
        """The integral-temperature method's bulk temperature θ_M,int (°C): ISO/TS 6336-21's
        θ_oil + C₁ θ_flm (C₁ = 0.7) unless the kind says otherwise."""
        return oil_temperature + _C1 * mean_flash


class FlashBulkTemperature(AbstractBulkTemperature):
    """ISO/TS 6336-20's θ_M = θ_oil + 0.47 X_S X_mp θ_flm: ``lubrication_factor`` X_S (1.0 dip
    lubrication, 1.2 spray), ``meshes`` n_p, the gear's meshes (X_mp = (1 + n_p)/2)."""

    name: ClassVar[str] = "ts-6336-20"
    lubrication_factor: Float[Array, ""]
    meshes: int = eqx.field(static=True)

    def __init__(self, lubrication_factor=1.0, meshes=1):
        w = "FlashBulkTemperature"
        check_real("lubrication_factor", lubrication_factor, lo=0.0, hi=2.0, lo_open=True, where=w)
        if isinstance(meshes, bool) or not isinstance(meshes, int) or meshes < 1:
            raise ValueError(f"{w}: meshes = {meshes!r} is out of range: allowed an integer >= 1")
        self.lubrication_factor = as_float(lubrication_factor)
        self.meshes = meshes

    def bulk(self, oil_temperature, mean_flash):
        return (
            oil_temperature + 0.47 * self.lubrication_factor * 0.5 * (1 + self.meshes) * mean_flash
        )

    def integral_bulk(self, oil_temperature, mean_flash):
        """θ_oil + C₁ X_S X_mp θ_flm: X_S and X_mp enter both methods' rules."""
        x = self.lubrication_factor * 0.5 * (1 + self.meshes)
        return oil_temperature + _C1 * x * mean_flash


class GivenBulkTemperature(AbstractBulkTemperature):
    """A given (measured) bulk temperature θ_M (°C), in (−50, 400); both methods use it."""

    name: ClassVar[str] = "given"
    value: Float[Array, ""]

    def __init__(self, value):
        check_real(
            "value",
            value,
            "°C",
            lo=-50.0,
            hi=400.0,
            lo_open=True,
            hi_open=True,
            where="GivenBulkTemperature",
        )
        self.value = as_float(value)

    def bulk(self, oil_temperature, mean_flash):
        return self.value

    def integral_bulk(self, oil_temperature, mean_flash):
        """The given θ_M: both methods use it."""
        return self.value


class ScuffingLimits(eqx.Module):
    """The lubricant's and the material's scuffing limits: θ_S and θ_intS (°C), given or from
    the oil's FZG load stage (:func:`fzg_scuffing_temperature`,
    :func:`fzg_integral_scuffing_temperature`).

    Args:
        fzg_load_stage: the FZG A/8.3/90 load stage the oil passed, in [1, 14], or None.
        scuffing_temperature: θ_S (°C), in (0, 1000), or None (from the load stage).
        integral_scuffing_temperature: θ_intS (°C), in (0, 1000), or None (from the load stage).
        lubricant_factor: the TS's X_L (1 mineral oil), (0, 2]. structural_factor: X_W, (0, 2].
        relative_structural_factor: X_WrelT, (0, 2].

    Raises:
        ValueError: a value out of range; neither a load stage nor both temperatures.
    """

    fzg_load_stage: float | None = eqx.field(static=True)
    scuffing_temperature: float | None = eqx.field(static=True)
    integral_scuffing_temperature: float | None = eqx.field(static=True)
    lubricant_factor: float = eqx.field(static=True)
    structural_factor: float = eqx.field(static=True)
    relative_structural_factor: float = eqx.field(static=True)

    def __init__(
        self,
        fzg_load_stage=None,
        scuffing_temperature=None,
        integral_scuffing_temperature=None,
        lubricant_factor=1.0,
        structural_factor=1.0,
        relative_structural_factor=1.0,
    ):
        w = "ScuffingLimits"
        if fzg_load_stage is not None:
            check_real("fzg_load_stage", fzg_load_stage, lo=1.0, hi=14.0, where=w)
        for name, v in (
            ("scuffing_temperature", scuffing_temperature),
            ("integral_scuffing_temperature", integral_scuffing_temperature),
        ):
            if v is not None:
                check_real(name, v, "°C", lo=0.0, hi=1000.0, lo_open=True, hi_open=True, where=w)
        for name, v in (
            ("lubricant_factor", lubricant_factor),
            ("structural_factor", structural_factor),
            ("relative_structural_factor", relative_structural_factor),
        ):
            check_real(name, v, lo=0.0, hi=2.0, lo_open=True, where=w)
        if fzg_load_stage is None and (
            scuffing_temperature is None or integral_scuffing_temperature is None
        ):
            raise ValueError(
                f"{w}: fzg_load_stage = None: allowed a load stage in [1, 14], or both"
                " scuffing_temperature and integral_scuffing_temperature"
            )
        self.fzg_load_stage = None if fzg_load_stage is None else float(fzg_load_stage)
        self.scuffing_temperature = (
            None if scuffing_temperature is None else float(scuffing_temperature)
        )
        self.integral_scuffing_temperature = (
            None if integral_scuffing_temperature is None else float(integral_scuffing_temperature)
        )
        self.lubricant_factor = float(lubricant_factor)
        self.structural_factor = float(structural_factor)
        self.relative_structural_factor = float(relative_structural_factor)

    def flash(self) -> float:
        """θ_S (°C): the given one or the FZG load stage's."""
        if self.scuffing_temperature is not None:
            return self.scuffing_temperature
        return fzg_scuffing_temperature(
            self.fzg_load_stage, self.lubricant_factor, self.structural_factor
        )

    def integral(self, viscosity_40) -> float:
        """θ_intS (°C): the given one or the FZG load stage's with the oil's ν₄₀ (m²/s)."""
        if self.integral_scuffing_temperature is not None:
            return self.integral_scuffing_temperature
        return fzg_integral_scuffing_temperature(
            self.fzg_load_stage,
            viscosity_40,
            self.lubricant_factor,
            self.relative_structural_factor,
        )


class _ScuffingRating(eqx.Module):
    """The scalars of a scuffing rating, both methods' (the module docstring): temperatures in
    °C, rises in K. :class:`MeshScuffing`'s and :class:`~jaxgear.tribology.TSScuffing`'s.

    Attributes:
        max_flash_temperature: θ_fl,max (K). mean_flash_temperature: θ_flm = θ_fla,int (K).
        bulk_temperature: θ_M (°C) of the flash-temperature method.
        max_contact_temperature: θ_B,max = θ_M + θ_fl,max (°C).
        scuffing_temperature: θ_S (°C). safety_factor: S_B (-).
        integral_bulk_temperature: θ_M,int (°C). integral_temperature: θ_int (°C).
        integral_scuffing_temperature: θ_intS (°C). integral_safety_factor: S_intS (-).
        oil_temperature: θ_oil (°C).
    """

    max_flash_temperature: Float[Array, ""]
    mean_flash_temperature: Float[Array, ""]
    bulk_temperature: Float[Array, ""]
    max_contact_temperature: Float[Array, ""]
    scuffing_temperature: float
    safety_factor: Float[Array, ""]
    integral_bulk_temperature: Float[Array, ""]
    integral_temperature: Float[Array, ""]
    integral_scuffing_temperature: float
    integral_safety_factor: Float[Array, ""]
    oil_temperature: Float[Array, ""]

    def summary(self) -> dict:
        """Scalars as a JSON-ready dict (°C, K)."""
        return {
            "max_flash_temperature_K": float(self.max_flash_temperature),
            "mean_flash_temperature_K": float(self.mean_flash_temperature),
            "bulk_temperature_C": float(self.bulk_temperature),
            "max_contact_temperature_C": float(self.max_contact_temperature),
            "scuffing_temperature_C": float(self.scuffing_temperature),
            "scuffing_safety_factor": float(self.safety_factor),
            "integral_bulk_temperature_C": float(self.integral_bulk_temperature),
            "integral_temperature_C": float(self.integral_temperature),
            "integral_scuffing_temperature_C": float(self.integral_scuffing_temperature),
            "integral_scuffing_safety_factor": float(self.integral_safety_factor),
        }


def scuffing_scalars(bulk, oil, fl_max, fl_mean, theta_s, theta_int_s, dtype) -> dict:
    """The fields of :class:`_ScuffingRating` (the module docstring's methods) from θ_oil (°C),
    θ_fl,max and θ_flm (K), θ_S and θ_intS (°C): the bulk temperatures, θ_B,max, θ_int and the
    safety factors. Traced; shared by :func:`mesh_scuffing` and
    :func:`~jaxgear.tribology.ts_scuffing`."""
    theta_m = jnp.asarray(bulk.bulk(oil, fl_mean), dtype)
    theta_b_max = theta_m + fl_max
    theta_m_int = jnp.asarray(bulk.integral_bulk(oil, fl_mean), dtype)  # the kind's own rule
    theta_int = theta_m_int + _C2 * fl_mean
    return {
        "max_flash_temperature": fl_max,
        "mean_flash_temperature": fl_mean,
        "bulk_temperature": theta_m,
        "max_contact_temperature": theta_b_max,
        "scuffing_temperature": theta_s,
        "safety_factor": (theta_s - oil) / (theta_b_max - oil),
        "integral_bulk_temperature": theta_m_int,
        "integral_temperature": theta_int,
        "integral_scuffing_temperature": theta_int_s,
        "integral_safety_factor": theta_int_s / theta_int,
        "oil_temperature": jnp.asarray(oil, dtype),
    }


class MeshScuffing(_ScuffingRating):
    """Flash temperature and scuffing of one mesh (the module docstring). Cell arrays (P, L, N)
    like the result's line loads; temperatures in °C, rises in K.

    Attributes:
        on_path: the cells on the flanks (the result's ``cell_mask``), (P, L, N).
        loaded: the cells with a positive line load, (P, L, N).
        flash_temperature: θ_fl (K), 0 off the loaded cells.
        contact_temperature: θ_B = θ_M + θ_fl (°C) on the loaded cells, θ_M elsewhere.
        max_flash_temperature: the largest θ_fl (K) (:func:`safe_max`: differentiable).
        mean_flash_temperature: θ_flm = θ_fla,int, the mean of θ_fl over the cells on the path.
        bulk_temperature, …, oil_temperature: the rating's scalars (as the module docstring's
            methods): θ_M, θ_B,max, θ_S, S_B, θ_M,int, θ_int, θ_intS, S_intS, θ_oil.
    """

    on_path: Bool[Array, "P L N"]
    loaded: Bool[Array, "P L N"]
    flash_temperature: Float[Array, "P L N"]
    contact_temperature: Float[Array, "P L N"]


def check_thermal_coefficients(thermal_coefficients, where: str) -> None:
    """(B_M1, B_M2) (W s^½/(m² K)): two values, each > 0; one-line ValueError otherwise. Shared
    by the flash-temperature, scuffing and micropitting entry points."""
    check_real(
        "thermal_coefficients",
        thermal_coefficients,
        "W s^½/(m² K)",
        lo=0.0,
        lo_open=True,
        shape=(2,),
        where=where,
    )

def mesh_scuffing(
    pair: AbstractGearPair,
    result,
    tribology: MeshTribology,
    lubricant: Lubricant,
    youngs_modulus,
    poisson_ratio,
    limits: ScuffingLimits,
    *,
    bulk: AbstractBulkTemperature | None = None,
    thermal_coefficients=(STEEL_THERMAL_CONTACT_COEFFICIENT, STEEL_THERMAL_CONTACT_COEFFICIENT),
) -> MeshScuffing:
    """Blok's flash temperature along the path of contact from jaxgear's local line loads, and
    the scuffing safety factors of the flash- and integral-temperature methods (the module
    docstring). Differentiable (jit, grad) in the line loads, μ and the lubricant's leaves.

    Args:
        pair: the mesh's gear pair. result: the contact solve's result (``cell_mask``), the one
            ``tribology`` came from.
        tribology: :func:`mesh_tribology`'s output (line loads, speeds, R, μ).
        lubricant: :class:`Lubricant` (θ_oil, ν₄₀).
        youngs_modulus, poisson_ratio: both gears' (Pa, -).
        limits: :class:`ScuffingLimits`.
        bulk: the flash method's bulk-temperature rule (None: :class:`FlashBulkTemperature`).
        thermal_coefficients: (B_M1, B_M2) (W s^½/(m² K)), each > 0; default steel's.

    Returns:
        :class:`MeshScuffing`.

    Raises:
        ValueError: one line naming the argument, its value and the allowed range.
    """
    w_ = "mesh_scuffing"
    check_instance("pair", pair, AbstractGearPair, "a GearPair or InternalGearPair", w_)
    check_instance("tribology", tribology, MeshTribology, "a MeshTribology", w_)
    check_instance("lubricant", lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w_)
    check_instance("limits", limits, ScuffingLimits, "a jaxgear.tribology.ScuffingLimits", w_)
    bulk = FlashBulkTemperature() if bulk is None else bulk
    check_instance("bulk", bulk, AbstractBulkTemperature, "a bulk-temperature kind", w_)
    check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, where=w_)
    check_real("poisson_ratio", poisson_ratio, lo=0.0, hi=0.5, hi_open=True, where=w_)
    check_thermal_coefficients(thermal_coefficients, w_)
    check_instance("result", result, (MeshResult, QuasiStaticResult),
                   "a jaxgear.MeshResult or a one-mesh jaxgear.QuasiStaticResult", w_)
    theta_s = limits.flash()
    nu40 = lubricant.viscosity_40  # traced when the lubricant is a leaf of a jitted objective
    theta_int_s = limits.integral(nu40 if is_traced(nu40) else float(nu40))
    return _scuffing(
        pair,
        result.cell_mask,
        tribology,
        lubricant.oil_temperature,
        contact_modulus(youngs_modulus, poisson_ratio),
        jnp.asarray(thermal_coefficients),
        bulk,
        theta_s,
        theta_int_s,
    )


def mesh_flash_temperature(
    pair: AbstractGearPair,
    tribology: MeshTribology,
    youngs_modulus,
    poisson_ratio,
    *,
    thermal_coefficients=(STEEL_THERMAL_CONTACT_COEFFICIENT, STEEL_THERMAL_CONTACT_COEFFICIENT),
) -> Float[Array, "P L N"]:
    """Blok's flash temperature θ_fl (K) at every cell along the path of contact (the module
    docstring), from :func:`mesh_tribology`'s line loads, speeds, radii and μ: what
    :func:`mesh_scuffing` rates, without the scuffing limits (the flash temperature does not
    depend on them). Differentiable (jit, grad).

    Args:
        pair: the mesh's gear pair. tribology: :func:`mesh_tribology`'s output.
        youngs_modulus, poisson_ratio: both gears' (Pa, -).
        thermal_coefficients: (B_M1, B_M2) (W s^½/(m² K)), each > 0; default steel's.

    Returns:
        θ_fl (K), shape (P, L, N) of the result's line loads; 0 off the loaded cells.

    Raises:
        ValueError: one line naming the argument, its value and the allowed range.
    """
    w_ = "mesh_flash_temperature"
    check_instance("pair", pair, AbstractGearPair, "a GearPair or InternalGearPair", w_)
    check_instance("tribology", tribology, MeshTribology, "a MeshTribology", w_)
    check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, where=w_)
    check_real("poisson_ratio", poisson_ratio, lo=0.0, hi=0.5, hi_open=True, where=w_)
    check_thermal_coefficients(thermal_coefficients, w_)
    return cell_flash_temperature(
        pair,
        tribology,
        contact_modulus(youngs_modulus, poisson_ratio),
        jnp.asarray(thermal_coefficients),
    )


def cell_flash_temperature(pair, trib: MeshTribology, e_star, b_m) -> Float[Array, "P L N"]:
    """Blok's θ_fl (K) at every loaded cell of ``trib`` (0 elsewhere): each flank's own speed
    normal to the contact line with its own B_M (the pinion's v₁ with B_M1, the gear's v₂ with
    B_M2: the pinion flank is the faster one in the recess, the slower one in the approach),
    Hertz's b_H from E* (Pa), (B_M1, B_M2) ``b_m``. Traced; shared by :func:`mesh_scuffing`
    and :func:`jaxgear.tribology.mesh_micropitting`."""
    dtype = trib.line_load.dtype
    loaded = trib.loaded
    w = jnp.where(loaded, trib.line_load, 1.0)
    R = jnp.where(loaded, trib.radius, 1.0)
    cb = jnp.cos(pair.base_helix_angle)
    u, vg = trib.entrainment_speed, trib.sliding_speed
    # which flank is faster: v₁ = ω₁ ρ₁ against v₂ = ω₁ ρ₂/|u| (MeshTribology's kinematics),
    # from the cells' roll distances; then v₁, v₂ = u ± v_g/2 with the sign of v₁ − v₂
    s = jnp.where(loaded, trib.cell_s, 0.5 * pair.path_of_contact)
    pinion_faster = pair.roll_distance(s, 0) * abs(pair.gear_ratio) >= pair.roll_distance(s, 1)
    half = jnp.where(pinion_faster, 0.5, -0.5) * vg
    v1 = jnp.where(loaded, jnp.maximum((u + half) * cb, 1e-9), 1.0)
    v2 = jnp.where(loaded, jnp.maximum((u - half) * cb, 1e-9), 1.0)
    b_h = jnp.sqrt(4.0 * w * R / (jnp.pi * e_star))
    mu = trib.friction_coefficient
    fl = blok_flash_temperature(mu, w, v1, v2, b_h, b_m[0], b_m[1])
    return jnp.where(loaded, fl, jnp.zeros((), dtype))


@eqx.filter_jit
def _scuffing(pair, mask, trib, oil, e_star, b_m, bulk, theta_s, theta_int_s):
    """:func:`mesh_scuffing` on arrays: one compiled program."""
    dtype = trib.line_load.dtype
    zero = jnp.zeros((), dtype)
    loaded = trib.loaded
    fl = cell_flash_temperature(pair, trib, e_star, b_m)
    fl_max = safe_max(jnp.where(loaded, fl, -jnp.inf))
    n_path = jnp.maximum(jnp.sum(mask), 1)
    fl_mean = jnp.sum(jnp.where(mask, fl, zero)) / n_path
    rating = scuffing_scalars(bulk, oil, fl_max, fl_mean, theta_s, theta_int_s, dtype)
    return MeshScuffing(
        on_path=mask,
        loaded=loaded,
        flash_temperature=fl,
        contact_temperature=rating["bulk_temperature"] + fl,
        **rating,
    )

