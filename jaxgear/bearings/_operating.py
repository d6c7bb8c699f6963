"""A bearing's life at its operating point: the load the model gives it, rated by ISO 281 and
ISO/TS 16281 together.

A rolling bearing at an operating point (its ring displacement d and the load f(d) =
(F_x, F_y, F_z, M_x, M_y) it carries, :func:`~jaxgear.bearings.solve_displacement` or a
scene's :func:`jaxgear.dynamics.bearings_at_operating_point`) has the radial load
F_r = √(F_x² + F_y²) and the axial load F_a = F_z (the shaft's axis z) that ISO 281 rates:
the basic rating life L10 (:func:`~jaxgear.bearings.rating_life`), the modified rating life
L_nm = a₁ a_ISO L10 (:func:`~jaxgear.bearings.modified_life`) where the lubricant and the
contamination are given, and ISO/TS 16281's basic reference rating life L10r
(:func:`~jaxgear.bearings.reference_life`) of the balls' or the rollers' laminae's loads at d,
which a clearance, a tilt or a moment moves and ISO 281's F_r, F_a do not see. The moments
M_x, M_y enter L10r only.
"""

from __future__ import annotations

from typing import NamedTuple

import jax.numpy as jnp
import numpy as np

from .._util import check_instance, check_real
from ._kinds import AbstractRollingBearing
from ._life import ModifiedLife, modified_life, rating_life
from ._reference import ReferenceLife, reference_life

__all__ = ["OperatingLife", "operating_life"]


class OperatingLife(NamedTuple):
    """A rolling bearing's lives at its operating point (:func:`operating_life`).

    Attributes:
        radial: F_r = √(F_x² + F_y²) (N).
        axial: F_a = F_z (N; + along the shaft's z).
        equivalent_load: ISO 281's P (N).
        revolutions: the basic rating life L10 (revolutions, not millions).
        duration: L10 in seconds at ``speed`` (L10h = duration / 3600); None without a speed.
        modified: ISO 281's :class:`~jaxgear.bearings.ModifiedLife` (L_nm, a₁, a_ISO, κ,
            C_u), or None where the lubricant or the contamination is not given.
        reference: ISO/TS 16281's :class:`~jaxgear.bearings.ReferenceLife` (L10r, P_ref): the
            balls' loads, or the rollers' laminae's (their ``slices`` and ``crown``).
    """

    radial: float
    axial: float
    equivalent_load: float
    revolutions: float
    duration: float | None
    modified: ModifiedLife | None
    reference: ReferenceLife | None


def operating_life(bearing: AbstractRollingBearing, load, displacement, speed=None, *,
                   viscosity=None, reliability=0.9, contamination=None,
                   rotating: str = "inner") -> OperatingLife:
    """The lives of ``bearing`` carrying ``load`` f = (F_x, F_y, F_z, M_x, M_y) (N, N·m), (5,),
    at its ring displacement ``displacement`` d (m, rad), (5,) (module docstring).

    Args:
        speed: the inner ring's speed relative to the outer ring ω (rad/s, > 0), or None (the
            lives in revolutions only, no L_nm: ISO 281's rated viscosity needs the speed).
        viscosity: the lubricant's operating kinematic viscosity ν (m²/s), for L_nm.
        reliability: R, 0.9 to 0.9995 (ISO 281's a₁), for L_nm.
        contamination: e_C, 0 to 1, for L_nm; None: no L_nm.
        rotating: the ring that turns relative to the load, for L10r (``"inner"``, ``"outer"``).

    Raises:
        ValueError: a kind without a rating life or without its ratings; load or displacement
            not (5,) finite; a speed <= 0; L_nm asked (``contamination`` given) without
            ``viscosity`` or ``speed``; what :func:`~jaxgear.bearings.modified_life` refuses
            (one line each).
    """
    w = "operating_life"
    check_instance("bearing", bearing, AbstractRollingBearing, "a jaxgear.bearings kind",
                   where=w)
    check_real("load", load, "N, N·m", shape=(5,), shape_text="(5,)", where=w)
    check_real("displacement", displacement, "m, rad", shape=(5,), shape_text="(5,)", where=w)
    if speed is not None:
        check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, where=w)
    if contamination is not None and (viscosity is None or speed is None):
        missing = "viscosity" if viscosity is None else "speed"
        raise ValueError(f"{w}: {missing} = None with contamination = {contamination!r}: "
                         "allowed given (ISO 281's modified life needs the lubricant's "
                         "viscosity and the speed)")
    f = np.asarray(load, float)
    radial, axial = float(np.hypot(f[0], f[1])), float(f[2])
    basic = rating_life(bearing, radial, axial, 1.0 if speed is None else speed)
    modified = None
    if contamination is not None:
        modified = modified_life(bearing, radial, axial, speed, viscosity=viscosity,
                                 reliability=reliability, contamination=contamination)
    reference = reference_life(bearing, jnp.asarray(displacement, float), rotating)
    return OperatingLife(radial, axial, float(basic.equivalent_load), float(basic.revolutions),
                         None if speed is None else float(basic.duration), modified, reference)
