"""Bearing tones: the cage, ball-pass and ball-spin frequencies of a rolling bearing.

With the outer ring held and the inner ring turning at f_s (rev/s), γ = D cos α / d_m
(Randall & Antoni, Mech. Syst. Signal Process. 25 (2011) 485–520, eqs. 1–4)::

    FTF  = f_s/2 (1 − γ)              cage (fundamental train)
    BPFO = Z f_s/2 (1 − γ)            an outer-race point passed by the elements
    BPFI = Z f_s/2 (1 + γ)            an inner-race point passed by the elements
    BSF  = f_s d_m/(2D) (1 − γ²)      an element's spin (a defect on it strikes twice a turn)

D the element (mean) diameter, α its nominal contact angle; rolling without slip.
"""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import check_instance
from ._kinds import AbstractRollingBearing

__all__ = ["BearingTones", "bearing_tones"]


class BearingTones(eqx.Module):
    """A bearing's tones as orders (per revolution of the inner ring relative to the outer):
    ``ftf``, ``bpfo``, ``bpfi``, ``bsf``; :meth:`at` gives them in Hz at a shaft speed."""

    ftf: Float[Array, ""]
    bpfo: Float[Array, ""]
    bpfi: Float[Array, ""]
    bsf: Float[Array, ""]

    def at(self, speed) -> BearingTones:
        """The tones in Hz at the inner ring's speed ω (rad/s) relative to the outer ring."""
        f = jnp.asarray(speed) / (2.0 * jnp.pi)
        return BearingTones(self.ftf * f, self.bpfo * f, self.bpfi * f, self.bsf * f)


def bearing_tones(bearing: AbstractRollingBearing) -> BearingTones:
    """FTF, BPFO, BPFI and BSF of ``bearing`` as orders of the shaft speed (module docstring).

    Raises:
        ValueError: a kind without rolling elements (one line)."""
    check_instance("bearing", bearing, AbstractRollingBearing, "a jaxgear.bearings kind",
                   where="bearing_tones")
    if not bearing.rolling_elements:
        raise ValueError(
            f"bearing_tones: {type(bearing).__name__} has no rolling elements: allowed a "
            "rolling bearing kind"
        )
    D, dm, Z = bearing.element_diameter, bearing.pitch_diameter, bearing.elements
    g = D * jnp.cos(bearing.nominal_angle) / dm
    return BearingTones(0.5 * (1 - g), 0.5 * Z * (1 - g), 0.5 * Z * (1 + g),
                        dm / (2 * D) * (1 - g**2))
