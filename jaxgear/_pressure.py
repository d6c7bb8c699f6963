"""Hertzian contact pressure on the flanks: the maximum pressure and the half-width of the contact
band of every cell, from its line load and the pair's curvature at the cell's point of the line of
action (Hertz line contact; K. L. Johnson, *Contact Mechanics*, 1985, §4.3, eqs. (4.43)–(4.45);
ISO 6336-2:2019 clause 6, whose Z_H Z_E at the pitch point it reproduces).

Two involute flanks in contact at roll distance ρ₁ = ρ_A + s from the driving gear's base-circle
tangent point T₁ (transverse plane, s the cell's base-plane coordinate) have transverse radii of
curvature ρ₁ and ρ₂ = T₁T₂ − ρ₁ (T₁T₂ = a_w sin α_wt) and, in the normal section of a helical
flank, ρ/cos β_b. Their relative radius is R = ρ₁ρ₂/(ρ₁ + ρ₂) (normal plane). With the line load
w (N per metre of contact line) and the contact modulus E* = 1/((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂),

    half-width  a = √(4 w R / (π E*)),   maximum pressure  p₀ = 2 w / (π a) = √(w E* / (π R)).

At the pitch point of a spur pair in single-pair contact (w = F_t/(b cos α_wt)) this is ISO's
nominal contact stress σ_H0 = Z_H Z_E √(F_t (u + 1)/(d₁ b u)) with Z_ε = 1.
"""

from __future__ import annotations

import functools
from typing import NamedTuple

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ._geometry import GearPair

__all__ = [
    "ContactPressure",
    "contact_modulus",
    "contact_pressure",
    "pressure_factor",
    "relative_radius",
]


class ContactPressure(NamedTuple):
    """Hertzian contact of every cell (the shapes of the result's ``line_load``, (P, L, N)).

    Attributes:
        max_pressure: p₀, the maximum (centre) pressure of the contact band (Pa); 0 where the
            cell carries no load or is off the flanks.
        half_width: a, the half-width of the contact band across the contact line (m); 0 there
            likewise.
    """

    max_pressure: Float[Array, "P L N"]
    half_width: Float[Array, "P L N"]


def contact_modulus(youngs_modulus: float, poisson_ratio: float) -> float:
    """E* = E / (2 (1 − ν²)) (Pa): the contact modulus of two bodies of one material (ISO
    6336-2's Z_E = √(E*/π))."""
    return youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))


@functools.singledispatch
def relative_radius(pair: GearPair, s) -> Float[Array, "..."]:
    """R = ρ₁ρ₂/(ρ₁ + ρ₂) (m) in the normal plane at base-plane coordinates ``s`` (m, any shape):
    ρ₁ = (ρ_A + s)/cos β_b, ρ₂ = (a_w sin α_wt − ρ_A − s)/cos β_b (the module docstring). Points
    off the path of contact give the formula's value; callers mask them. Dispatched on the
    pair's type: an :class:`~jaxgear.InternalGearPair`'s concave ring flank gives
    R = ρ₁ρ₂/(ρ₂ − ρ₁) (``jaxgear/_internal.py``)."""
    s = jnp.asarray(s)
    cb = jnp.cos(pair.base_helix_angle)
    length = pair.center_distance * jnp.sin(pair.operating_pressure_angle)
    rho1 = (pair.start_roll + s) / cb
    rho2 = (length - pair.start_roll - s) / cb
    return rho1 * rho2 / (rho1 + rho2)


def pressure_factor(pair: GearPair, s, mask, youngs_modulus: float, poisson_ratio: float) -> Array:
    """E*/(π R) (Pa per N/m) at base-plane coordinates ``s`` (m), 0 where ``mask`` is False: the
    factor that turns a line load w (N/m) into the squared maximum pressure, p₀² = w E*/(π R)
    (the module docstring). A run that only needs the largest pressure over many cells takes
    the largest w E*/(π R) and one square root (the dynamics' in-loop maximum)."""
    R = jnp.where(mask, relative_radius(pair, s), 1.0)
    R = jnp.maximum(R, 1e-12)  # a cell exactly at a base circle: no load there anyway
    e_star = contact_modulus(youngs_modulus, poisson_ratio)
    return jnp.where(mask, e_star / (jnp.pi * R), 0.0)


def contact_pressure(
    pair: GearPair, result, youngs_modulus: float, poisson_ratio: float
) -> ContactPressure:
    """The Hertzian maximum pressure and half-width of every cell of one mesh's quasi-static
    (or dynamic) result.

    Args:
        pair: the mesh's gear pair (its pinion the driving gear).
        result: a result with ``line_load`` (N/m), ``cell_s`` (m) and ``cell_mask`` of equal
            shapes, (P, L, N) (:class:`~jaxgear.MeshResult`, or a
            :class:`~jaxgear.QuasiStaticResult` of one mesh), or (K, L, N) at the K kept
            steps of a dynamic run recorded with ``cell_loads=True``
            (:class:`~jaxgear.dynamics.MeshDynamics`, or a
            :class:`~jaxgear.dynamics.DynamicResponse` of one mesh).
        youngs_modulus, poisson_ratio: the material of both gears (Pa, -).

    Returns:
        :class:`ContactPressure` (Pa, m), the shapes of ``line_load``.
    """
    return _hertz(
        pair, result.line_load, result.cell_s, result.cell_mask, youngs_modulus, poisson_ratio
    )


@eqx.filter_jit
def _hertz(pair, line_load, cell_s, cell_mask, youngs_modulus, poisson_ratio) -> ContactPressure:
    """:func:`contact_pressure` on the result's arrays: one compiled program (its steps eager
    were a dozen small programs per shape of a first run)."""
    w = jnp.where(cell_mask, jnp.maximum(line_load, 0.0), 0.0)
    R = jnp.where(cell_mask, relative_radius(pair, cell_s), 1.0)
    R = jnp.maximum(R, 1e-12)  # a cell exactly at a base circle: no load there anyway
    e_star = contact_modulus(youngs_modulus, poisson_ratio)
    return ContactPressure(
        max_pressure=_sqrt0(w * e_star / (jnp.pi * R)),
        half_width=_sqrt0(4.0 * w * R / (jnp.pi * e_star)),
    )


def _sqrt0(x):
    """√x, and 0 with a zero derivative where x <= 0: an unloaded cell (w = 0; the cells beyond
    the path of contact, a relieved tip) would otherwise give √'(0) · 0 = NaN in a gradient."""
    positive = x > 0
    return jnp.where(positive, jnp.sqrt(jnp.where(positive, x, 1.0)), 0.0)
