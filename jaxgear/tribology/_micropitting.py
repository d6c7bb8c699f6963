"""Micropitting safety factor of one mesh by ISO/TS 6336-22 (formerly ISO/TR 15144-1), with
jaxgear's local line loads along the whole path of contact. docs/tribology.md § "Micropitting".

The TS compares the smallest local specific film thickness with a permissible one:

    S_λ = λ_GF,min / λ_GFP,     λ_GF,Y = h_Y / R_a,   R_a = (R_a1 + R_a2)/2,

h_Y the local film thickness at a point Y of the path. Its film formula is Dowson and
Higginson's with a sliding (thermal) parameter S_GF:

    h_Y = ρ_n,Y · 1.6 G_M^0.6 U_Y^0.7 W_Y^−0.13 S_GF,Y^0.22,

G_M = α_θM E_r, U_Y = η_θM v_Σ,Y/(2 E_r ρ_n,Y), W_Y = 2π p_dyn,Y²/E_r² (E_r = 2E*, v_Σ = v₁ + v₂
the sum of the flanks' tangential speeds, ρ_n the normal relative radius), the oil's properties
at the flanks' bulk temperature θ_M; with p_dyn the Hertz pressure of the local line load w,
W_Y = w/(E_r ρ_n) and U_Y = η u/(E_r ρ_n) (u the entrainment speed): Dowson's groups of
:func:`jaxgear.tribology.film_thickness` with the constant 1.6 and the exponents 0.6, 0.7, −0.13
of Dowson & Higginson's 1961 regression (:class:`TSMicropittingFilm`). The sliding parameter
S_GF,Y = α_θB,Y η_θB,Y/(α_θM η_θM) thins the film where the local contact temperature
θ_B,Y = θ_M + θ_fl,Y exceeds the bulk one; the pressure–viscosity coefficient varies with the
temperature as α_θ ∝ 1 + 516 K (1/(θ + 273 K) − 1/311 K) (the given α is the one at the oil
temperature; the viscosity comes from the lubricant's Walther line). The bulk temperature is
the TS's θ_M = θ_oil + 7400 (P_VZP/(a b))^0.72 X_S/(1.2 X_Ca) (P_VZP in kW = P μ_m H_V, a and b in
mm; :func:`micropitting_bulk_temperature`), here with jaxgear's own mesh power loss, X_Ca = 1 (tip
relief acts through jaxgear's line loads), or a given θ_M.

Method: the TS's Method B evaluates λ_GF,Y at seven points A, AB, B, C, D, DE, E with its own
load-sharing factor X_Y; jaxgear evaluates it at every loaded cell of its contact solve (the load
sharing, the relief and the face-load distribution come from the solve, which is the TS's
Method A idea: the local loads from a contact analysis) and takes the smallest.

Permissible λ_GFP: given (from the oil's micropitting test and the gear maker's experience), or
read from the TS's informative Figure A.1 (λ_GFP against the failure load stage SKS of the
FVA-FZG GF-C/8.3/90 test, one curve per ISO VG grade, mineral oils, drawn for R_a = 0.5 µm) with
the points a third party digitised (:func:`figure_a1_permissible_film`).

Sources (no TS text was available): the formulas as transcribed in the public implementation of
ISO/TR 15144-1:2014 Method B in hakangunes258/mekanika (``Services/Iso15144Micropitting.cs``,
formulae (1)–(4), (8), (12), (22), (27), (84)); the safety-factor definition S_λ = λ_GF,min/λ_GFP
also in "Results of ISO/TS 6336-22 evaluating full contact zone" (Gear Technology,
geartechnology.com/articles/30360). The TS's conversion of the test's λ_GFT to λ_GFP with its
material factor W_W was not found in any stored source and is not carried.
"""

from __future__ import annotations

import itertools
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .._geometry import AbstractGearPair
from .._pressure import contact_modulus
from .._util import check_instance, check_real, safe_max
from ._film import AbstractFilmFormula, DowsonHigginson, film_thickness
from ._flash import (
    STEEL_THERMAL_CONTACT_COEFFICIENT,
    cell_flash_temperature,
    check_thermal_coefficients,
)
from ._lubricant import Lubricant
from ._mesh import MeshTribology

__all__ = [
    "MeshMicropitting",
    "TSMicropittingFilm",
    "figure_a1_permissible_film",
    "mesh_micropitting",
    "micropitting_bulk_temperature",
    "pressure_viscosity_temperature_factor",
]

#: ISO/TR 15144-1:2014 Figure A.1 as digitised in hakangunes258/mekanika: ISO VG ν₄₀ (mm²/s),
#: λ_GFP at failure load stage SKS 5 and at SKS 10 (mineral oils, R_a 0.5 µm)
FIGURE_A1 = (
    (32.0, 0.130, 0.055),
    (100.0, 0.250, 0.090),
    (220.0, 0.400, 0.145),
    (460.0, 0.570, 0.200),
)


class TSMicropittingFilm(AbstractFilmFormula):
    """ISO/TS 6336-22's film, isothermal part: H = 1.6 G^0.6 U^0.7 W^−0.13 (D. Dowson &
    G. R. Higginson, Engineering 192, 1961, 158–159, the form ISO/TR 15144-1 formula (4) uses; :func:`mesh_micropitting` adds the TS's S_GF^0.22).
    ``central`` is Dowson–Toyoda's (:class:`DowsonHigginson`): the TS gives one film only."""

    name: ClassVar[str] = "iso-ts-6336-22"

    def central(self, U, G, W):
        return DowsonHigginson().central(U, G, W)

    def minimum(self, U, G, W):
        return 1.6 * G**0.6 * U**0.7 * W**-0.13


def pressure_viscosity_temperature_factor(temperature) -> Float[Array, ...]:
    """1 + 516 K (1/(θ + 273 K) − 1/311 K) at θ (°C, any shape): α_θ/α_38 of ISO/TR 15144-1
    formula (8) (the TS's α at θ is α_38 times this)."""
    return 1.0 + 516.0 * (1.0 / (jnp.asarray(temperature) + 273.0) - 1.0 / 311.0)


def micropitting_bulk_temperature(
    power_loss,
    center_distance,
    face_width,
    oil_temperature,
    lubrication_factor=1.0,
    tip_relief_factor=1.0,
) -> Float[Array, ""]:
    """ISO/TR 15144-1 formula (84): θ_M = θ_oil + 7400 (P_VZP/(a b))^0.72 X_S/(1.2 X_Ca) (°C),
    P_VZP = P μ_m H_V the mesh's power loss in kW, a and b in mm.

    Args:
        power_loss: P_VZP (W) ≥ 0. center_distance: a (m) > 0. face_width: b (m) > 0.
        oil_temperature: θ_oil (°C). lubrication_factor: X_S (1.0 dip, 1.2 spray), (0, 2].
        tip_relief_factor: X_Ca ≥ 1 (1 without the TS's tip-relief credit).
    """
    w = "micropitting_bulk_temperature"
    check_real("center_distance", center_distance, "m", lo=0.0, lo_open=True, where=w)
    check_real("face_width", face_width, "m", lo=0.0, lo_open=True, where=w)
    check_real("lubrication_factor", lubrication_factor, lo=0.0, hi=2.0, lo_open=True, where=w)
    check_real("tip_relief_factor", tip_relief_factor, lo=1.0, hi=10.0, where=w)
    p_kw = jnp.maximum(jnp.asarray(power_loss), 0.0) * 1e-3
    ab = center_distance * 1e3 * face_width * 1e3
    return oil_temperature + 7400.0 * (p_kw / ab) ** 0.72 * lubrication_factor / (
        1.2 * tip_relief_factor
    )


def figure_a1_permissible_film(load_stage, viscosity_40) -> float:
    """λ_GFP read from ISO/TR 15144-1:2014 (ISO/TS 6336-22) Figure A.1 for a mineral oil of
    kinematic viscosity ``viscosity_40`` (m²/s) whose FVA-FZG GF-C/8.3/90 micropitting test
    failed at load stage ``load_stage`` (SKS): each VG curve log-linear in the load stage between
    its SKS 5 and SKS 10 points (:data:`FIGURE_A1`), then linear in log ν₄₀ between the curves.
    An informative figure read by a third party: an estimate.

    Raises:
        ValueError: a load stage outside [5, 10] or ν₄₀ outside [32, 460] mm²/s (the figure's
            range; no extrapolation).
    """
    w = "figure_a1_permissible_film"
    check_real("load_stage", load_stage, lo=5.0, hi=10.0, where=w)
    check_real("viscosity_40", viscosity_40, "m²/s", lo=32e-6, hi=460e-6, where=w)
    s = float(load_stage)
    nu = float(viscosity_40) * 1e6

    def curve(row):
        _, at5, at10 = row
        return at5 * (at10 / at5) ** ((s - 5.0) / 5.0)

    for lo, hi in itertools.pairwise(FIGURE_A1):
        if nu <= hi[0]:
            f = (math.log(nu) - math.log(lo[0])) / (math.log(hi[0]) - math.log(lo[0]))
            return curve(lo) + f * (curve(hi) - curve(lo))
    return curve(FIGURE_A1[-1])


class MeshMicropitting(eqx.Module):
    """Micropitting of one mesh by ISO/TS 6336-22 (the module docstring). Cell arrays (P, L, N)
    like the result's line loads, 0 off the loaded cells.

    Attributes:
        loaded: the cells with a positive line load.
        film: h_Y (m), the TS's local film. specific_film: λ_GF,Y = h_Y/R_a (-).
        contact_temperature: θ_B,Y = θ_M + θ_fl,Y (°C). sliding_parameter: S_GF,Y (-).
        bulk_temperature: θ_M (°C). min_specific_film: λ_GF,min (-) (:func:`safe_max`'s rule:
            differentiable). permissible_specific_film: λ_GFP (-). safety_factor: S_λ (-).
    """

    loaded: Bool[Array, "P L N"]
    film: Float[Array, "P L N"]
    specific_film: Float[Array, "P L N"]
    contact_temperature: Float[Array, "P L N"]
    sliding_parameter: Float[Array, "P L N"]
    bulk_temperature: Float[Array, ""]
    min_specific_film: Float[Array, ""]
    permissible_specific_film: Float[Array, ""]
    safety_factor: Float[Array, ""]

    def summary(self) -> dict:
        """Scalars as a JSON-ready dict."""
        return {
            "bulk_temperature_C": float(self.bulk_temperature),
            "min_specific_film": float(self.min_specific_film),
            "permissible_specific_film": float(self.permissible_specific_film),
            "safety_factor": float(self.safety_factor),
        }


def mesh_micropitting(
    pair: AbstractGearPair,
    tribology: MeshTribology,
    lubricant: Lubricant,
    roughness,
    youngs_modulus,
    poisson_ratio,
    permissible_specific_film,
    *,
    bulk_temperature=None,
    lubrication_factor=1.0,
    thermal_coefficients=(STEEL_THERMAL_CONTACT_COEFFICIENT, STEEL_THERMAL_CONTACT_COEFFICIENT),
) -> MeshMicropitting:
    """ISO/TS 6336-22's micropitting safety factor S_λ = λ_GF,min/λ_GFP along jaxgear's path of
    contact (the module docstring). Differentiable (jit, grad) in the line loads, μ, λ_GFP and
    the lubricant's leaves.

    Args:
        pair: the mesh's gear pair.
        tribology: :func:`jaxgear.tribology.mesh_tribology`'s output (line loads, speeds, R, μ,
            P_VZP).
        lubricant: :class:`Lubricant` (θ_oil, the Walther line, ρ, α at θ_oil).
        roughness: (R_a1, R_a2) (m), each in (0, 1e-5].
        youngs_modulus, poisson_ratio: both gears' (Pa, -).
        permissible_specific_film: λ_GFP (-), in (0, 10] (given, or
            :func:`figure_a1_permissible_film`).
        bulk_temperature: a given θ_M (°C) in (−50, 400), or None: the TS's rule
            (:func:`micropitting_bulk_temperature` with the mesh's P_VZP, X_Ca = 1).
        lubrication_factor: X_S of that rule (1.0 dip, 1.2 spray), (0, 2].
        thermal_coefficients: (B_M1, B_M2) (W s^½/(m² K)) for Blok's θ_fl; default steel's.

    Returns:
        :class:`MeshMicropitting`.

    Raises:
        ValueError: one line naming the argument, its value and the allowed range.
    """
    w_ = "mesh_micropitting"
    check_instance("pair", pair, AbstractGearPair, "a GearPair or InternalGearPair", w_)
    check_instance("tribology", tribology, MeshTribology, "a MeshTribology", w_)
    check_instance("lubricant", lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w_)
    check_real("roughness", roughness, "m", lo=0.0, hi=1e-5, lo_open=True, shape=(2,), where=w_)
    check_real("youngs_modulus", youngs_modulus, "Pa", lo=0.0, lo_open=True, where=w_)
    check_real("poisson_ratio", poisson_ratio, lo=0.0, hi=0.5, hi_open=True, where=w_)
    check_real(
        "permissible_specific_film",
        permissible_specific_film,
        lo=0.0,
        hi=10.0,
        lo_open=True,
        where=w_,
    )
    if bulk_temperature is not None:
        check_real(
            "bulk_temperature",
            bulk_temperature,
            "°C",
            lo=-50.0,
            hi=400.0,
            lo_open=True,
            hi_open=True,
            where=w_,
        )
        theta_m = jnp.asarray(bulk_temperature, tribology.line_load.dtype)
    else:
        theta_m = micropitting_bulk_temperature(
            tribology.mean_power_loss,
            pair.center_distance,
            pair.face_width,
            lubricant.oil_temperature,
            lubrication_factor,
        )
    check_thermal_coefficients(thermal_coefficients, w_)
    return _micropitting(
        pair,
        tribology,
        lubricant,
        jnp.asarray(roughness),
        contact_modulus(youngs_modulus, poisson_ratio),
        jnp.asarray(thermal_coefficients),
        jnp.asarray(permissible_specific_film),
        theta_m,
    )


@eqx.filter_jit
def _micropitting(pair, trib, lub, ra, e_star, b_m, lam_p, theta_m):
    """:func:`mesh_micropitting` on arrays: one compiled program."""
    dtype = trib.line_load.dtype
    zero = jnp.zeros((), dtype)
    loaded = trib.loaded
    fl = cell_flash_temperature(pair, trib, e_star, b_m)
    theta_b = theta_m + fl

    def eta(theta):
        return lub.kinematic_viscosity(theta) * lub.density_at(theta)

    def alpha(theta):
        f = pressure_viscosity_temperature_factor
        return lub.pressure_viscosity * f(theta) / f(lub.oil_temperature)

    eta_m, alpha_m = eta(theta_m), alpha(theta_m)
    s_gf = jnp.where(loaded, alpha(theta_b) * eta(theta_b) / (alpha_m * eta_m), 1.0)
    R = jnp.where(loaded, trib.radius, 1.0)
    w = jnp.where(loaded, trib.line_load, 1.0)
    u = jnp.where(loaded, trib.entrainment_speed, 1.0)
    h = film_thickness(TSMicropittingFilm(), R, u, w, eta_m, alpha_m, e_star).minimum
    h = jnp.where(loaded, h * s_gf**0.22, zero)
    lam = h / (0.5 * (ra[0] + ra[1]))
    lam_min = -safe_max(jnp.where(loaded, -lam, -jnp.inf))
    return MeshMicropitting(
        loaded=loaded,
        film=h,
        specific_film=lam,
        contact_temperature=jnp.where(loaded, theta_b, zero),
        sliding_parameter=jnp.where(loaded, s_gf, zero),
        bulk_temperature=jnp.asarray(theta_m, dtype),
        min_specific_film=lam_min,
        permissible_specific_film=jnp.asarray(lam_p, dtype),
        safety_factor=lam_min / lam_p,
    )
