"""Weber's thin-slice model, seed (1.1)-(1.3), for an internal pair (:class:`InternalGearPair`):
the external pinion's tooth as for external pairs, the internal gear's (a ring's) tooth on its
generated form (:func:`fem_prep.generate_internal_tooth`, by the ring's pinion-type cutter), the
Hertzian approach on the concave ring flank. Registered on :func:`jaxgear.member_compliance`
and :func:`jaxgear.weber_profile` (docs/stiffness.md, docs/planetary.md "Internal gears").

The ring's tooth as Weber's cantilever: the tooth stands on the root circle r_f (outside) and
points inwards. The contact at roll distance ρ2 (radius r = √(ρ2² + r_b²), on the concave
flank at the tooth's half angle ψ(r) = s_t/(2|r|) − inv α_t + inv α_r, ISO 21771) is loaded
along the line of action, tangent to the base circle at the polar angle ψ(r) + α_r (on the far
side of the flank from the centre line, where the external tooth's lies on the near side): the
load's line crosses the tooth centre line at r_load = r_b/cos(α_r + ψ) > r, at the angle
α_p = α_r + ψ to the centre line's normal (external: α_r − ψ), its radial component pressing
the tooth onto its root as on an external tooth. The beam runs from the root circle inwards to
that crossing, u = r_f − r_load (the part of the tooth between the crossing and the contact,
whose moment has the other sign, is left out as Weber leaves it out of external teeth: the
crossing lies between the root and the contact's section on both; near the root of a small ring
the crossing can fall outside the root circle, and u is then 0: no bending, the shear,
compression and foundation terms of a load at the root), with the chordal thickness d(y) = 2 x(r_f − y) of the
generated tooth; the integrals are (1.2)'s (:func:`jaxgear._stiffness.beam_compliance`). The
foundation is Weber's half plane (1.3) with S the ring's root chord (the ring's rim is the body
below, i.e. outside, the root circle; a thin rim adds its own compliance, which the FE ring of
``jaxgear.planetary.PlanetaryStage`` models); Sainsot et al.'s fit is derived for external bodies on
a bore and refused.
"""

from __future__ import annotations

import functools
import math

import numpy as np

from ._internal import InternalGearPair, internal_tooth_geometry
from ._stiffness import (
    WeberFoundation,
    _half_thickness_angle,
    beam_compliance,
    hertz_compliance,
    member_compliance,
    weber_profile,
)

__all__: list[str] = []


@functools.lru_cache(maxsize=32)
def _generated(geometry):
    from fem_prep import generate_internal_tooth  # lazy: fem_prep imports SciPy

    return generate_internal_tooth(geometry, n_fillet=200, n_involute=2, n_tip=0)


def ring_form(pair: InternalGearPair, ring_cutter):
    """The ring's generated tooth (:class:`fem_prep.InternalToothForm`, cached) of ``pair`` cut
    by ``ring_cutter``.

    Raises:
        ValueError: ``ring_cutter`` None, or one that cannot cut the ring (one line, prefixed
            ``gear.``).
    """
    if ring_cutter is None:
        raise ValueError(
            "Weber: ring_cutter = None is out of range for an InternalGearPair: allowed a "
            "fem_prep.ShaperCutter(teeth, profile_shift, tip_radius_coeff), the pinion-type "
            "cutter that generates the ring's teeth (jaxgear.Weber(ring_cutter=...))"
        )
    geometry = internal_tooth_geometry(pair, ring_cutter)
    try:
        return _generated(geometry)
    except ValueError as err:
        raise ValueError(f"gear.{err}") from None


def ring_load(pair: InternalGearPair, form, rho):
    """(u, α_p): the cantilever length u = r_f − r_b/cos(α_r + ψ(r)) (m, 0 where the load's
    line crosses the centre line outside the root circle) and the load's angle α_p = α_r + ψ(r)
    to the centre line's normal (rad) at the ring's roll distances ``rho``."""
    rb, rf = pair.base_radii[1], pair.root_radii[1]
    r = np.hypot(rho, rb)
    alpha_p = np.arctan2(rho, rb) + form.involute_half_angle(r)
    return np.maximum(rf - rb / np.cos(alpha_p), 0.0), alpha_p


@member_compliance.register
def _internal_member_compliance(
    pair: InternalGearPair,
    member: int,
    rho: np.ndarray,
    E: float,
    nu: float,
    foundation,
    n_quad: int = 400,
    *,
    ring_cutter=None,
) -> np.ndarray:
    if member == 0:  # the external pinion: the external tooth, unchanged
        return member_compliance.dispatch(object)(pair, 0, rho, E, nu, foundation, n_quad)
    form = ring_form(pair, ring_cutter)
    rho = np.asarray(rho, dtype=float)
    u, alpha_p = ring_load(pair, form, rho)
    rf = form.root_radius
    c = beam_compliance(u, lambda y: 2 * form.half_thickness(rf - y), alpha_p, E, nu, n_quad)
    s_root = 2 * float(form.half_thickness(rf))
    cos2, tan2 = np.cos(alpha_p) ** 2, np.tan(alpha_p) ** 2
    return foundation.ring_compliance(c, s_root, u, cos2 / E, tan2)


@weber_profile.register
def _internal_weber_profile(
    pair: InternalGearPair,
    s: np.ndarray,
    youngs_modulus: float,
    poisson_ratio: float,
    line_load: float,
    foundation=None,
    *,
    ring_cutter=None,
) -> np.ndarray:
    foundation = WeberFoundation() if foundation is None else foundation
    s = np.asarray(s, dtype=float)
    E, nu = youngs_modulus, poisson_ratio
    form = ring_form(pair, ring_cutter)
    rho1, rho2 = pair.roll_distance(s, 0), pair.roll_distance(s, 1)
    c = member_compliance(pair, 0, rho1, E, nu, foundation.member(0)) + member_compliance(
        pair, 1, rho2, E, nu, foundation.member(1), ring_cutter=ring_cutter
    )
    r1, r2 = np.hypot(rho1, pair.base_radii[0]), np.hypot(rho2, pair.base_radii[1])
    d1 = r1 * np.sin(_half_thickness_angle(pair, 0, r1))
    d2 = r2 * np.sin(form.involute_half_angle(r2))
    rho_eq = rho1 * rho2 / (rho2 - rho1)  # the concave ring flank
    k_transverse = 1.0 / (c + hertz_compliance(rho_eq, d1, d2, line_load, E, nu))
    return k_transverse / math.cos(pair.base_helix_angle)
