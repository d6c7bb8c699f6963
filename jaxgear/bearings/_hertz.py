"""Hertz load–deflection constants of a rolling element between its two raceways.

Point contact (balls), Q = K_n δ^(3/2), with δ the element's total approach (inner plus outer
contact) and Q its normal load. Each contact's curvature sum Σρ and curvature difference
F(ρ) follow Harris & Kotzalas (Rolling Bearing Analysis, 5th ed., vol. 1, ch. 2 and 6), with
γ = D cos α / d_m and the groove conformities f = r_groove / D::

    inner: Σρ = (4 − 1/f_i + 2γ/(1 − γ)) / D,   1/R_x = 2/(D(1 − γ)),     1/R_y = (2 − 1/f_i)/D
    outer: Σρ = (4 − 1/f_o − 2γ/(1 + γ)) / D,   1/R_x = 2/(D(1 + γ)),     1/R_y = (2 − 1/f_o)/D

The ellipticity κ = a/b and the complete elliptic integrals ℱ (first kind) and ℰ (second kind)
are Brewe and Hamrock's approximations (J. Lubr. Technol. 99 (1977) 485–487; within about 3 %
of the exact values for 1 <= R_y/R_x <= 100, the range of ball bearings)::

    κ = 1.0339 (R_y/R_x)^0.636,   ℰ = 1.0003 + 0.5968 R_x/R_y,   ℱ = 1.5277 + 0.6023 ln(R_y/R_x)

and one contact's approach (Hamrock & Dowson; Harris & Kotzalas eq. 6.41 in this form)::

    δ = ℱ [ (9 / (2 ℰ R)) (Q / (π κ E'))² ]^(1/3),   R = 1/Σρ,   E' = E / (1 − ν²)

so that K = π κ E' √(2 ℰ R / (9 ℱ³)). The inner and outer contacts in series:
K_n = (K_i^(−2/3) + K_o^(−2/3))^(−3/2).

Line contact (rollers), Q = K_n δ^(10/9): Palmgren's steel-on-steel relation for one contact of
a roller of effective length l (Harris & Kotzalas eq. 6.42: δ = 3.84·10⁻⁵ Q^0.9 / l^0.8 in
mm and N), the inner and outer contact alike, in series: K_n = 2^(−10/9) (3.84·10⁻⁵)^(−10/9)
l^(8/9) in N, mm, converted to SI here (N/m^(10/9)).
"""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["line_contact_constant", "line_pressure", "point_contact", "point_contact_constant"]

#: Palmgren's line-contact compliance for one steel contact: δ = c Q^0.9 / l^0.8 (mm, N)
PALMGREN_MM = 3.84e-5


def _curvatures(D, d_m, alpha, f, inner: bool):
    """(1/R_x, 1/R_y) of one ball–raceway contact (1/m): the rolling direction and across the
    groove (a concave groove's curvature counted negative)."""
    gamma = D * jnp.cos(alpha) / d_m
    g = 1.0 - gamma if inner else 1.0 + gamma
    return 2.0 / (D * g), (2.0 - 1.0 / f) / D


def point_contact(D, d_m, alpha, f, E, nu, inner: bool):
    """One ball–raceway contact's Hertz quantities by Brewe and Hamrock's approximations.

    Args:
        D: ball diameter (m). d_m: pitch diameter (m). alpha: contact angle (rad).
        f: the groove's conformity r/D (> 0.5). E, nu: Young's modulus (Pa) and Poisson's
            ratio of ball and ring (one material). inner: the inner raceway (else the outer).

    Returns:
        ``(K, kappa, E2, F1, R)``: the contact's constant K (N/m^1.5, Q = K δ^1.5), the
        ellipticity a/b, the elliptic integrals ℰ and ℱ, the effective radius R = 1/Σρ (m).
    """
    inv_rx, inv_ry = _curvatures(D, d_m, alpha, f, inner)
    ratio = inv_rx / inv_ry  # R_y / R_x
    kappa = 1.0339 * ratio**0.636
    E2 = 1.0003 + 0.5968 / ratio
    F1 = 1.5277 + 0.6023 * jnp.log(ratio)
    R = 1.0 / (inv_rx + inv_ry)
    Ep = E / (1.0 - nu**2)
    K = jnp.pi * kappa * Ep * jnp.sqrt(2.0 * E2 * R / (9.0 * F1**3))
    return K, kappa, E2, F1, R


def point_contact_constant(D, d_m, alpha, f_i, f_o, E, nu):
    """K_n (N/m^1.5) of a ball between its inner and outer raceways, Q = K_n δ^1.5 with δ the
    total approach (module docstring: Harris & Kotzalas, Brewe & Hamrock)."""
    K_i = point_contact(D, d_m, alpha, f_i, E, nu, inner=True)[0]
    K_o = point_contact(D, d_m, alpha, f_o, E, nu, inner=False)[0]
    return (K_i ** (-2.0 / 3.0) + K_o ** (-2.0 / 3.0)) ** -1.5


def line_contact_constant(length):
    """K_n (N/m^(10/9)) of a steel roller of effective length ``length`` (m) between its two
    raceways, Q = K_n δ^(10/9) with δ the total approach (Palmgren; module docstring)."""
    k_mm = 2.0 ** (-10.0 / 9.0) * PALMGREN_MM ** (-10.0 / 9.0) * (length * 1e3) ** (8.0 / 9.0)
    return k_mm * 1e3 ** (10.0 / 9.0)  # N/mm^(10/9) -> N/m^(10/9)


def line_pressure(w, R, E=2.075e11, nu=0.3):
    """The largest Hertz pressure (Pa) of a line contact of load per length ``w`` (N/m) and
    effective radius ``R`` (m) in the rolling direction: p_max = √(w E' / (2π R)),
    E' = E / (1 − ν²) (two bodies of one material; steel by default)."""
    return jnp.sqrt(w * E / (1.0 - nu**2) / (2.0 * jnp.pi * R))
