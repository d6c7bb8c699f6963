"""Backlash and the coast flanks: one home for the concept (docs/backlash.md).

A pair with thinned teeth (``Member.tooth_thickness_allowance`` A_sn < 0) or a centre distance
above the zero-backlash one has backlash: the coast flanks (the trailing flank of each tooth) sit
a gap apart while the drive flanks touch, and close when the motion takes the backlash up (a
torque reversal, a rattle). The model lays them out as a second base plane of the same
:class:`~jaxgear.MeshModel` (``coast=True``; cells with ``flank`` −1) and solves both flanks in one
contact problem. Here:

* the pair's backlash numbers (ISO 21771 / DIN 3967), used by :class:`~jaxgear.GearPair`:
  :func:`thinned_involute` (the operating involute function of the zero-backlash distance of
  thinned teeth), :func:`base_thicknesses` and :func:`backlashes` (j_bt, j_wt, j_bn);
* the coast flanks' placement: :func:`coast_phase` (the angle of the coast cells in their base
  plane) and :func:`coast_line` (the coast line of action of a placed pair, for
  :func:`jaxgear.scenes.line_of_action`);
* the coast cells' part in the contact problem: :func:`cell_flank` (+1 drive, −1 coast) and
  :func:`flank_separation` (the initial separation δ0 of both flanks);
* :func:`check_no_coast`: what is not modelled with coast flanks, refused in one line.

Pure functions of floats (NumPy/``math``) and of the base-plane cells (JAX); this module imports
no other module of the model (the geometry and the base plane import it).
"""

from __future__ import annotations

import math

import jax.numpy as jnp
import numpy as np

from ._util import safe_max

__all__ = [
    "backlashes",
    "base_thicknesses",
    "cell_flank",
    "check_no_coast",
    "coast_line",
    "coast_phase",
    "flank_separation",
    "thinned_involute",
]


def thinned_involute(inv_awt0: float, allowances: float, normal_module: float, teeth: int):
    """inv α_wt of the zero-backlash centre distance of the thinned teeth: ISO 21771 (40) with
    2 x tan α_n + A_sn/m_n per member, inv α_wt0 + (A_sn1 + A_sn2)/(m_n (z1 + z2)).

    Args:
        inv_awt0: inv α_wt0 of the nominal teeth (rad). allowances: A_sn1 + A_sn2 (m).
        normal_module: m_n (m). teeth: z1 + z2.
    """
    return inv_awt0 + allowances / normal_module / teeth


def base_thicknesses(members, mt: float, at: float, an: float, mn: float, inv_at: float):
    """The base-circle tooth thicknesses s_bi = m_t cos α_t (π/2 + 2 x_i tan α_n + A_sni/m_n +
    z_i inv α_t) (m) of ``members`` (each a :class:`~jaxgear.Member`), a tuple.

    Args:
        mt: m_t (m). at: α_t (rad). an: α_n (rad). mn: m_n (m). inv_at: inv α_t.
    """
    return tuple(
        mt
        * math.cos(at)
        * (
            math.pi / 2
            + 2 * m.profile_shift * math.tan(an)
            + m.tooth_thickness_allowance / mn
            + m.teeth * inv_at
        )
        for m in members
    )


def backlashes(sb, rb, mt: float, at: float, awt: float, inv_awt: float, beta: float):
    """(j_bt, j_wt, j_bn) (m): the transverse backlash j_bt = p_bt − s_b1 − s_b2 +
    2 (r_b1 + r_b2) inv α_wt (the gap between the coast flanks along the transverse line of
    action; 0 below round-off at the zero-backlash distance), the circumferential j_wt =
    j_bt / cos α_wt (on the operating pitch circle) and the normal j_bn = j_bt cos β_b (normal
    to the flanks, what a feeler gauge reads).

    Args:
        sb: the base thicknesses (:func:`base_thicknesses`) (m). rb: the base radii (m).
        mt: m_t (m). at: α_t, awt: α_wt (rad). inv_awt: inv α_wt. beta: β (rad).
    """
    jbt = math.pi * mt * math.cos(at) - sb[0] - sb[1] + 2 * (rb[0] + rb[1]) * inv_awt
    jbt = max(jbt, 0.0)  # round-off at the zero-backlash distance
    return jbt, jbt / math.cos(awt), jbt * math.cos(math.atan(math.tan(beta) * math.cos(at)))


def coast_phase(pair) -> float:
    """θ_c (rad): the coast cells at pinion angle θ are the layout's cells at θ_c − θ
    (``pair`` a :class:`~jaxgear.GearPair`).

    Tooth i's drive contact sits at roll ρ_1 = ρ_A + r_b1 θ + i p_bt from T1 (s = 0 at the
    engagement point at θ = 0). The same tooth's coast flank (the trailing one, an involute of
    the second base circle tangent) meets the second line of action at ρ'_1 = 2 r_b1 (ψ_b1 +
    α_wt) − ρ_1 from T1' (the tangent points lie at ∓α_wt about the centre line, ψ_b1 = s_b1 /
    (2 r_b1) the half base thickness of the thinned tooth), and the gear's coast flank a
    transverse backlash j_bt further on; the cell sits midway, s' = ρ'_1 + j_bt/2 − ρ_A.
    """
    rb1 = pair.base_radii[0]
    psi = pair.base_thickness[0] / (2 * rb1)
    c = 2 * rb1 * (psi + pair.operating_pressure_angle) - 2 * pair.start_roll
    return (c + 0.5 * pair.transverse_backlash) / rb1


def coast_line(centres, tangent, direction, normal) -> dict:
    """The coast flanks' line of action of a placed pair (NumPy, SI): the π-rotation R v =
    2 (v·d) d − v about the centre line d through the driving centre (mid-face) maps each flank
    of a symmetric tooth onto the other.

    Args:
        centres: (2, 3) the driving and the driven gear's centres (m). tangent: T1 (3,) (m).
        direction: t (3,). normal: n (3,) (the drive line of action).

    Returns:
        ``coast_tangent_point`` T1', ``coast_direction`` t', ``coast_normal`` n', (3,) each.
    """
    d = (centres[1] - centres[0]) / np.linalg.norm(centres[1] - centres[0])

    def turn(v):  # R v = 2 (v·d) d − v
        return 2.0 * np.dot(v, d) * d - v

    return {
        "coast_tangent_point": centres[0] + turn(tangent - centres[0]),
        "coast_direction": turn(direction),
        "coast_normal": turn(normal),
    }


def cell_flank(cells):
    """``cells.flank`` (+1 drive, −1 coast), ones for cells built without it; shape
    (n_lines, n_slices) (``cells`` a :class:`~jaxgear.Cells`)."""
    if cells.flank is None:
        return jnp.ones(cells.s.shape, cells.s.dtype)
    return cells.flank


def flank_separation(mesh, cells, e):
    """(max e, δ0) of the cells (m; δ0 per cell, 0 outside the mask; seed (2.8)) from the
    deviation ``e`` per cell (m) of a :class:`~jaxgear.MeshModel` ``mesh``: δ0 = max e − e on
    the drive flanks; with coast flanks (``mesh.coast``) the maximum is taken over the drive
    flanks and the coast flanks, the same modifications in their own base plane, have the
    backlash less the drive flanks' reference e_max and their own e."""
    if not mesh.coast:
        e_max = safe_max(jnp.where(cells.mask, e, -jnp.inf))
        return e_max, jnp.where(cells.mask, e_max - e, 0.0)
    drive = cell_flank(cells) > 0
    e_max = safe_max(jnp.where(cells.mask & drive, e, -jnp.inf))
    delta0 = jnp.where(drive, e_max - e, mesh.backlash - e_max - e)
    return e_max, jnp.where(cells.mask, delta0, 0.0)


def check_no_coast(mesh, what: str) -> None:
    """A one-line ``ValueError`` where ``what`` meets a mesh (a :class:`~jaxgear.MeshModel`)
    with coast flanks (not modelled together; docs/backlash.md, "Not modelled")."""
    if mesh.coast:
        raise ValueError(
            f"{what} with backlash (coast flanks, tooth_thickness_allowance) are not modelled "
            "together: drop one of them"
        )
