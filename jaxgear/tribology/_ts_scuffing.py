"""The closed-form scuffing rating of ISO/TS 6336-20 (flash-temperature method) and the
integral temperature of ISO/TS 6336-21 for an external cylindrical pair of one material, from
its geometry and operating point alone (no contact solve): the TS's load-sharing factor X_Γ,
its mean coefficient of friction μ_mC and its closed-form θ_fl(Γ)
(:func:`jaxgear.tribology.ts_flash_temperature`'s formula) along the path of contact.
Traceable and batched (``jax.vmap``): the sizing rates every candidate with it
(:func:`ts_scuffing`; docs/tribology.md § "The closed form of ISO/TS 6336-20", docs/sizing.md).

Positions on the path (ISO/TR 13989-1 eqs. (30)–(33), the TS's Γ, 0 at the pitch point C):

    Γ_A = −u (tan α_a2/tan α_wt − 1),           Γ_E = tan α_a1/tan α_wt − 1,
    Γ_B = Γ_E − 2π/(z₁ tan α_wt),               Γ_D = Γ_A + 2π/(z₁ tan α_wt).

Load-sharing factor X_Γ (ISO/TR 13989-1 clause 9, DIN 3990-4; :func:`ts_load_sharing`):

- spur, unmodified profiles (the buttress form): X_Γ = X_Q + (Γ − Γ_A)/(3 (Γ_B − Γ_A)) from A
  to B, 1 from B to D, X_Q + (Γ_E − Γ)/(3 (Γ_E − Γ_D)) from D to E, X_Q = (Q − 2)/15 with Q the
  ISO 1328 grade (7 where finer): 1/3 at A and E, 2/3 just before B and after D for Q <= 7, so
  that the two pairs in double contact carry the load between them (X_Γ(Γ) + X_Γ(Γ + 2π/(z₁
  tan α_wt)) = 1); a less accurate grade loads the tips more (a sum above 1, as the TR);
- helical with ε_β >= 1: X_Γ = 1/ε_α (the load spread evenly over the contact lines);
- 0 < ε_β < 1: the two interpolated linearly in ε_β, X_Γ = (1 − ε_β) X_Γ,spur + ε_β/ε_α
  (jaxgear's interpolation: the TS's text for this range was not available);
- helical (β_b > 0): × the buttressing factor X_but, 1 + 0.3 min(ε_β, 1) at A and E falling
  linearly to 1 over Δ_Γ = 0.2 sin β_b (ISO/TR 13989-1 eqs. (49)–(56)).

Where ε_α < 1 the spur form has no double contact: X_Γ,spur = 1.

Mean coefficient of friction (ISO/TS 6336-20's μ_mC; :func:`ts_friction_coefficient`):

    μ_mC = 0.045 (w_Bt K_Bγ/(v_ΣC ρ_redC))^0.2 η_oil^−0.05 X_R X_L,  X_R = 2.2 (R_a/ρ_redC)^0.25,

w_Bt = K_A K_v K_Hβ K_Hα F_t/b (N/mm, F_t = 2 T₁/d₁ the nominal tangential load at the
reference circle), v_ΣC = 2 v_t sin α_wt (m/s, v_t the operating pitch-line speed, taken as 50
m/s above it as ISO/TR 13989-1 eq. (26)), ρ_redC = a sin α_wt u/(1 + u)² (mm, transverse),
η_oil the oil's dynamic viscosity at θ_oil (mPa·s), R_a = (R_a1 + R_a2)/2 (µm), X_L the TS's
lubricant factor (1 mineral oil; :class:`ScuffingLimits`' ``lubricant_factor``, the one θ_S
takes) and K_Bγ the helical load factor: 1 for ε_γ <= 2, 1 + 0.2 √((ε_γ − 2)(5 − ε_γ)) to
ε_γ = 3.5, 1.3 beyond (:func:`helical_load_factor`).

The flash temperature θ_fl(Γ) = :func:`ts_flash_temperature`'s closed form with X_Γ, μ_mC and
the torque T₁ K_A K_v K_Hβ K_Hα K_Bγ; θ_fl,max its largest on A…E and θ_flm its mean over A…E
(the trapezoidal rule on each of A…B, B…D, D…E, the steps of X_Γ at B and D taken from either
side); the bulk temperature, θ_B,max, θ_S, S_B and the
integral method's θ_int, θ_intS, S_intS as :func:`mesh_scuffing`'s (the same bulk kinds, the
same :class:`ScuffingLimits`; θ_fla,int = θ_flm, the TS-21's closed form θ_flaE X_ε is not
carried).

Sources: the TS texts were not available. The positions, X_but, v_ΣC's cap and the structure
of μ_m are ISO/TR 13989-1:2000's as an independent implementation transcribes them
(hakangunes258/mekanika, ``Services/Iso13989FlashTemperature.cs``, eqs. (25)–(33), (49)–(56));
the spur X_Γ's 1/3 steps are DIN 3990-4's (that implementation ramps X_Γ to 1 at B instead,
which loads the two pairs in double contact by more than the whole load); μ_mC's 0.045, its
η_oil^−0.05 X_R X_L split and X_R = 2.2 (R_a/ρ_redC)^0.25 are ISO/TS 6336-20:2017's as the
sizing's requirements state them (not checked against the TS's text); K_Bγ is ISO/TR
13989-1's. docs/tribology.md says how far each is confirmed.
"""

from __future__ import annotations

import jax.numpy as jnp
from jaxtyping import Array, Float

from .._pressure import contact_modulus
from .._util import check_instance, check_real
from ._flash import (
    STEEL_THERMAL_CONTACT_COEFFICIENT,
    AbstractBulkTemperature,
    FlashBulkTemperature,
    ScuffingLimits,
    _ScuffingRating,
    _ts_flash,
    scuffing_scalars,
)
from ._lubricant import Lubricant

__all__ = ["SCUFFING_POINTS", "TSScuffing", "helical_load_factor", "ts_friction_coefficient",
           "ts_load_sharing", "ts_scuffing"]

#: the positions θ_fl is sampled at on each of the path's three pieces A…B, B…D, D…E (equally
#: spaced, both ends included: B and D once from either side)
SCUFFING_POINTS = 64


def ts_load_sharing(gamma, gamma_a, gamma_b, gamma_d, gamma_e, eps_alpha, eps_beta,
                    base_helix_angle, grade=7, piece=None) -> Float[Array, ...]:
    """The TS's load-sharing factor X_Γ (-) at the positions ``gamma`` (the module docstring;
    traceable, arrays broadcast together).

    Args:
        gamma: Γ (-), any shape. gamma_a, gamma_b, gamma_d, gamma_e: Γ_A, Γ_B, Γ_D, Γ_E.
        eps_alpha, eps_beta: ε_α > 0, ε_β >= 0. base_helix_angle: β_b (rad).
        grade: the ISO 1328 accuracy grade Q (a Python int; 7 where finer).
        piece: which piece of the spur form each position takes (0: A…B, 1: B…D, 2: D…E,
            broadcast with ``gamma``), or None: from Γ (B and D on the middle piece). Given,
            it picks the side of the steps at B and D.

    Returns:
        X_Γ, the broadcast shape; not validated (traced callers).
    """
    g = jnp.asarray(gamma)
    if piece is None:
        piece = jnp.where(g < gamma_b, 0, jnp.where(g > gamma_d, 2, 1))
    x_q = (max(int(grade), 7) - 2) / 15.0
    double = eps_alpha > 1.0  # else single contact: no steps
    span_ab = jnp.where(double & (gamma_b > gamma_a), gamma_b - gamma_a, 1.0)
    span_de = jnp.where(double & (gamma_e > gamma_d), gamma_e - gamma_d, 1.0)
    spur = jnp.where(piece == 0, x_q + (g - gamma_a) / (3.0 * span_ab),
                     jnp.where(piece == 2, x_q + (gamma_e - g) / (3.0 * span_de), 1.0))
    spur = jnp.where(double, jnp.minimum(spur, 1.0), 1.0)
    f = jnp.clip(eps_beta, 0.0, 1.0)
    x = (1.0 - f) * spur + f / eps_alpha
    width = jnp.maximum(0.2 * jnp.sin(base_helix_angle), 1e-12)
    ramp = jnp.maximum(jnp.maximum(1.0 - (g - gamma_a) / width, 1.0 - (gamma_e - g) / width), 0.0)
    return x * (1.0 + 0.3 * f * ramp)


def helical_load_factor(eps_gamma) -> Float[Array, ...]:
    """K_Bγ (-) of the total contact ratio ε_γ (the module docstring; traceable): 1 to ε_γ = 2,
    1 + 0.2 √((ε_γ − 2)(5 − ε_γ)) to 3.5, 1.3 beyond (ISO/TR 13989-1)."""
    e = jnp.clip(eps_gamma, 2.0, 3.5)
    above = e > 2.0  # the root's argument kept off 0 where it is 0 (a finite gradient)
    return jnp.where(above, 1.0 + 0.2 * jnp.sqrt(jnp.where(above, (e - 2.0) * (5.0 - e), 1.0)),
                     1.0)


def ts_friction_coefficient(line_load, sum_speed, radius, viscosity, roughness,
                            lubricant_factor=1.0) -> Float[Array, ...]:
    """ISO/TS 6336-20's μ_mC (-) (the module docstring; traceable), SI in, the TS's units
    inside.

    Args:
        line_load: w_Bt K_Bγ (N/m) > 0. sum_speed: v_ΣC (m/s) > 0 (capped by the caller).
        radius: ρ_redC (m) > 0. viscosity: η_oil (Pa·s) > 0. roughness: R_a (m) > 0, the
            flanks' mean. lubricant_factor: X_L (1 mineral oil).
    """
    rho_mm = radius * 1e3
    x_r = 2.2 * (roughness * 1e6 / rho_mm) ** 0.25
    return (0.045 * (line_load * 1e-3 / (sum_speed * rho_mm)) ** 0.2
            * (viscosity * 1e3) ** -0.05 * x_r * lubricant_factor)


class TSScuffing(_ScuffingRating):
    """The closed-form scuffing rating of one pair (:func:`ts_scuffing`); temperatures in °C,
    rises in K.

    Attributes:
        gamma: the positions Γ sampled on A…B, B…D, D…E (-), :data:`SCUFFING_POINTS` on each
            (B and D twice, once from either side), (3 :data:`SCUFFING_POINTS`,).
        load_sharing: X_Γ there. flash_temperature: θ_fl (K) there.
        positions: (Γ_A, Γ_B, Γ_D, Γ_E). friction_coefficient: μ_mC. load_factor: K_Bγ.
        max_flash_temperature, …, oil_temperature: the rating's scalars, as
            :class:`MeshScuffing`'s: θ_fl,max (at B and D too), θ_flm, θ_M, θ_B,max, θ_S, S_B =
            (θ_S − θ_oil)/(θ_B,max − θ_oil), θ_M,int, θ_int, θ_intS, S_intS = θ_intS/θ_int,
            θ_oil.
    """

    gamma: Float[Array, " K"]
    load_sharing: Float[Array, " K"]
    flash_temperature: Float[Array, " K"]
    positions: Float[Array, 4]
    friction_coefficient: Float[Array, ""]
    load_factor: Float[Array, ""]


def ts_scuffing(
    teeth_1,
    gear_ratio,
    centre_distance,
    operating_pressure_angle,
    base_helix_angle,
    reference_diameter_1,
    tip_diameters,
    face_width,
    contact_ratios,
    torque,
    speed,
    load_factor,
    lubricant: Lubricant,
    roughness,
    limits: ScuffingLimits,
    youngs_modulus,
    poisson_ratio,
    *,
    bulk: AbstractBulkTemperature | None = None,
    grade: int = 7,
    thermal_coefficient=STEEL_THERMAL_CONTACT_COEFFICIENT,
    points: int = SCUFFING_POINTS,
) -> TSScuffing:
    """The closed-form scuffing rating of ISO/TS 6336-20 (and the integral temperature of
    ISO/TS 6336-21) of an external pair of one material, its pinion driving (the module
    docstring). Traceable in every number (``jax.vmap`` over candidates, ``jax.grad``); a
    traced number has only its shape checked (a sizing spec's reader checks its keys).

    Args:
        teeth_1: z₁. gear_ratio: u = z₂/z₁ > 0. centre_distance: a (m).
        operating_pressure_angle: α_wt (rad). base_helix_angle: β_b (rad).
        reference_diameter_1: d₁ (m) (F_t = 2 T₁/d₁). tip_diameters: (d_a1, d_a2) (m).
        face_width: b (m). contact_ratios: (ε_α, ε_β).
        torque: T₁ (N·m) > 0. speed: ω₁ (rad/s) > 0.
        load_factor: K_A K_v K_Hβ K_Hα (-) of ISO 6336-1 (the TS's K_Bβ = K_Hβ, K_Bα = K_Hα).
        lubricant: the oil at θ_oil (:class:`Lubricant`: η_oil, ν₄₀). roughness: (R_a1, R_a2)
            (m). limits: θ_S and θ_intS (:class:`ScuffingLimits`; its X_L enters μ_mC too).
        youngs_modulus, poisson_ratio: both gears' (Pa, -).
        bulk: the bulk-temperature rule (None: :class:`FlashBulkTemperature`, X_S = 1).
        grade: the ISO 1328 grade of X_Γ (a Python int).
        thermal_coefficient: B_M (W s^½/(m² K)), default steel's.
        points: the positions sampled on each piece of the path (a Python integer, 2 or more).

    Returns:
        :class:`TSScuffing`.

    Raises:
        ValueError: a kind of the wrong class, a number not > 0, ``points`` < 2; one line
            naming the argument.
    """
    w_ = "ts_scuffing"
    check_instance("lubricant", lubricant, Lubricant, "a jaxgear.tribology.Lubricant", w_)
    check_instance("limits", limits, ScuffingLimits, "a jaxgear.tribology.ScuffingLimits", w_)
    bulk = FlashBulkTemperature() if bulk is None else bulk
    check_instance("bulk", bulk, AbstractBulkTemperature, "a bulk-temperature kind", w_)
    for name, v, unit in (("teeth_1", teeth_1, ""), ("gear_ratio", gear_ratio, ""),
                          ("centre_distance", centre_distance, "m"),
                          ("reference_diameter_1", reference_diameter_1, "m"),
                          ("face_width", face_width, "m"), ("torque", torque, "N·m"),
                          ("speed", speed, "rad/s"), ("load_factor", load_factor, "")):
        check_real(name, v, unit, lo=0.0, lo_open=True, where=w_)
    check_real("tip_diameters", tip_diameters, "m", lo=0.0, lo_open=True, shape=(2,), where=w_)
    check_real("roughness", roughness, "m", lo=0.0, lo_open=True, shape=(2,), where=w_)
    if isinstance(points, bool) or not isinstance(points, int) or points < 2:
        raise ValueError(f"{w_}: points = {points!r} is out of range: allowed an integer >= 2")
    z1, u, a = teeth_1, gear_ratio, centre_distance
    awt, bb = operating_pressure_angle, base_helix_angle
    ea, eb = contact_ratios[0], contact_ratios[1]
    tan_w = jnp.tan(awt)
    rb1 = a * jnp.cos(awt) / (1.0 + u)
    rb = jnp.stack([rb1, u * rb1])
    tan_a = jnp.sqrt(jnp.maximum((jnp.asarray(tip_diameters) / (2.0 * rb)) ** 2 - 1.0, 0.0))
    g_e = tan_a[0] / tan_w - 1.0
    g_a = -u * (tan_a[1] / tan_w - 1.0)
    pitch = 2.0 * jnp.pi / (z1 * tan_w)
    g_b, g_d = g_e - pitch, g_a + pitch
    k_by = helical_load_factor(ea + eb)
    t_load = torque * load_factor * k_by
    # μ_mC at the pitch point
    v_t = speed * a / (1.0 + u)
    sin_w = jnp.sin(awt)
    rho_c = a * sin_w * u / (1.0 + u) ** 2
    w_bt = 2.0 * t_load / (reference_diameter_1 * face_width)
    ra = 0.5 * (roughness[0] + roughness[1])
    mu = ts_friction_coefficient(w_bt, 2.0 * jnp.minimum(v_t, 50.0) * sin_w, rho_c,
                                 lubricant.dynamic_viscosity, ra, limits.lubricant_factor)
    x_m = (2.0 * contact_modulus(youngs_modulus, poisson_ratio)) ** 0.25 / thermal_coefficient
    # the three pieces A…B, B…D, D…E (B, D kept on the path and in order: ε_α < 1 leaves
    # one piece, X_Γ = 1; ε_α >= 2, outside the form's range, swaps them)
    b_, d_ = jnp.clip(g_b, g_a, g_e), jnp.clip(g_d, g_a, g_e)
    b_, d_ = jnp.minimum(b_, d_), jnp.maximum(b_, d_)
    ends = jnp.stack([g_a, b_, d_, g_e])
    frac = jnp.linspace(0.0, 1.0, points, dtype=jnp.result_type(a, float))
    gamma = (ends[:3, None] + (ends[1:] - ends[:3])[:, None] * frac[None, :]).reshape(-1)
    piece = jnp.repeat(jnp.arange(3), points)
    x_gamma = ts_load_sharing(gamma, g_a, g_b, g_d, g_e, ea, eb, bb, grade, piece=piece)
    fl = _ts_flash(u, a, sin_w, jnp.cos(bb), rb1 * face_width, gamma, x_gamma, mu, t_load,
                   speed, x_m)
    fl_max = jnp.max(fl)
    each = fl.reshape(3, points)
    area = jnp.sum((ends[1:] - ends[:3]) * jnp.mean(0.5 * (each[:, 1:] + each[:, :-1]), axis=1))
    fl_mean = area / jnp.maximum(g_e - g_a, 1e-12)
    oil = lubricant.oil_temperature
    theta_int_s = limits.integral(lubricant.viscosity_40)
    rating = scuffing_scalars(bulk, oil, fl_max, fl_mean, limits.flash(), theta_int_s,
                              fl.dtype)
    return TSScuffing(gamma=gamma, load_sharing=x_gamma, flash_temperature=fl,
                      positions=jnp.stack([g_a, g_b, g_d, g_e]), friction_coefficient=mu,
                      load_factor=k_by, **rating)
