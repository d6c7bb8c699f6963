"""ISO/TS 16281's basic reference rating life from the internal load distribution (balls).

ISO 281's L10 = (C/P)³ assumes the load distribution of a bearing without clearance, tilt or
misalignment under its equivalent load. ISO/TS 16281:2008 rates the distribution the bearing
actually has (:meth:`~AbstractRollingBearing.element_loads` at the operating point, from
:func:`~jaxgear.bearings.solve_displacement`): with the balls' loads Q_j (j = 1..Z),

- the dynamic equivalent rolling element loads of the two rings: the ring that turns relative
  to the load sees every ball, Q_e = (Σ Q_j³ / Z)^(1/3); the ring that stands still relative to
  the load sees each ball at its own place, Q_e = (Σ Q_j^(10/3) / Z)^(3/10). With the inner ring
  turning (``rotating="inner"``) the first is the inner ring's Q_ei, the second the outer's Q_ee;
  with the outer ring turning (a planet's bearing) the other way round;
- the rolling element loads for the rings' basic dynamic load ratings, from the bearing's C
  (the Lundberg–Palmgren relation behind ISO 281's C, as ISO/TS 16281 writes it)::

      Q_ci = C / (0.407 Z i^0.7 cos α) · [1 + (1.044 X)^(10/3)]^0.3
      Q_ce = C / (0.389 Z i^0.7 cos α) · [1 + (1.044 X)^(−10/3)]^0.3
      X = ((1 − γ)/(1 + γ))^1.72 · (f_i (2 f_o − 1) / (f_o (2 f_i − 1)))^0.41,   γ = D cos α / d_m

  (one row, i = 1; α the nominal contact angle; X is Lundberg and Palmgren's Q_ci/Q_ce);
- the basic reference rating life, the two rings in series (Weibull slope 10/9)::

      L10r = [(Q_ci/Q_ei)^(−10/3) + (Q_ce/Q_ee)^(−10/3)]^(−9/10) · 10⁶ revolutions

  and the dynamic equivalent reference load P_ref = C / (L10r / 10⁶)^(1/3), the load with
  which ISO 281's (C/P)³ gives the same life.

Under a radial load and zero clearance this is ISO 281's L10 up to the discreteness of the Z
balls (the constants 0.407, 0.389 and 1.044 are Lundberg and Palmgren's integrals of the
continuous half-loaded distribution); a clearance loads fewer balls harder and shortens it, a
tilt or an axial load changes it as the distribution says. Q_c is taken at the nominal
contact angle (the loaded angles enter through the loads Q_j).

Under a load spectrum of k bins (each bin's ring displacement d_i, the shaft speed ω_i and the
time t_i run in it) the bins' damage adds by Palmgren–Miner as ISO 281's spectrum life does
(:func:`~jaxgear.bearings.spectrum_life`): n_i = ω_i t_i / 2π revolutions, D = Σ n_i / L10r,i
per pass, L10r = Σ n_i / D revolutions, Σ t_i / D seconds, and P_ref = C / (L10r / 10⁶)^(1/3)
(:func:`spectrum_reference_life`); a bin that loads no ball does no damage.

Not built: roller bearings (ISO/TS 16281's laminae, edge stresses and roller profile), the
modified reference life (a_ISO from the contact pressures).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import check_instance, check_real, is_traced
from ._kinds import AbstractRollingBearing
from ._life import BearingLife

__all__ = ["ReferenceLife", "reference_life", "spectrum_reference_life"]

#: which ring turns relative to the load: the inner (a shaft's bearing) or the outer (a planet's)
ROTATING = ("inner", "outer")


class ReferenceLife(eqx.Module):
    """ISO/TS 16281's basic reference rating life (:func:`reference_life`).

    Attributes:
        revolutions: L10r (revolutions, not millions); at a speed ω it lasts L10r · 2π/ω s.
        equivalent_load: P_ref (N), the load with which ISO 281's (C/P)³ gives L10r.
        inner_rating, outer_rating: Q_ci, Q_ce (N), the rings' element load ratings.
        inner_load, outer_load: Q_ei, Q_ee (N), the rings' dynamic equivalent element loads.
    """

    revolutions: Float[Array, ""]
    equivalent_load: Float[Array, ""]
    inner_rating: Float[Array, ""]
    outer_rating: Float[Array, ""]
    inner_load: Float[Array, ""]
    outer_load: Float[Array, ""]


def _ratings(bearing):
    """(Q_ci, Q_ce) (N) of a ball bearing from its C (module docstring)."""
    D, dm, a = bearing.element_diameter, bearing.pitch_diameter, bearing.nominal_angle
    fi, fo = bearing.inner_conformity, bearing.outer_conformity
    g = D * jnp.cos(a) / dm
    X = ((1.0 - g) / (1.0 + g)) ** 1.72 * (fi * (2.0 * fo - 1.0) / (fo * (2.0 * fi - 1.0))) ** 0.41
    base = bearing.dynamic_rating / (bearing.elements * jnp.cos(a))
    Q_ci = base / 0.407 * (1.0 + (1.044 * X) ** (10.0 / 3.0)) ** 0.3
    Q_ce = base / 0.389 * (1.0 + (1.044 * X) ** (-10.0 / 3.0)) ** 0.3
    return Q_ci, Q_ce


def reference_life(bearing: AbstractRollingBearing, displacement, rotating: str = "inner"
                   ) -> ReferenceLife:
    """ISO/TS 16281's basic reference rating life L10r of a ball bearing at the ring
    displacement ``displacement`` d (5,) (m, rad; the operating point, e.g.
    ``solve_displacement(bearing, load).displacement``), its balls' loads rated against the
    rings' ratings from its C (module docstring). Differentiable in d and the geometry.

    Args:
        rotating: ``"inner"`` (the inner ring turns relative to the load; default) or
            ``"outer"``.

    Raises:
        ValueError: not a ball kind with ``dynamic_rating``; d not (5,) finite; ``rotating``
            not one of the two; no ball loaded at d (one line)."""
    w = "reference_life"
    _check_ball_kind(w, bearing, rotating)
    check_real("displacement", displacement, "m, rad", shape=(5,), shape_text="(5,)", where=w)
    Q = bearing.element_loads(jnp.asarray(displacement, float))
    if not is_traced(Q) and not np.any(np.asarray(Q) > 0):
        raise ValueError(f"{w}: no ball is loaded at displacement = {np.asarray(displacement)}: "
                         "allowed an operating point that loads the bearing")
    Q_ei, Q_ee = _equivalent_loads(bearing, Q, rotating)
    Q_ci, Q_ce = _ratings(bearing)
    L = ((Q_ci / Q_ei) ** (-10.0 / 3.0) + (Q_ce / Q_ee) ** (-10.0 / 3.0)) ** -0.9
    return ReferenceLife(L * 1e6, bearing.dynamic_rating / L ** (1.0 / 3.0), Q_ci, Q_ce, Q_ei,
                         Q_ee)


def _check_ball_kind(where, bearing, rotating):
    check_instance("bearing", bearing, AbstractRollingBearing, "a jaxgear.bearings kind",
                   where=where)
    if bearing.life_exponent != 3.0 or bearing.dynamic_rating is None:
        raise ValueError(
            f"{where}: {type(bearing).__name__} (dynamic_rating = {bearing.dynamic_rating}) is "
            "out of range: allowed a ball kind (DeepGrooveBall, AngularContactBall) with its "
            "dynamic_rating C given (rollers' laminae are not built)"
        )
    if rotating not in ROTATING:
        raise ValueError(f"{where}: rotating = {rotating!r} is out of range: allowed 'inner' or "
                         "'outer' (the ring that turns relative to the load)")


def _equivalent_loads(bearing, Q, rotating):
    """(Q_ei, Q_ee) (N) of the balls' loads Q (..., Z) (module docstring)."""
    Z = bearing.elements
    turning = jnp.sum(Q**3 / Z, axis=-1) ** (1.0 / 3.0)
    standing = jnp.sum(Q ** (10.0 / 3.0) / Z, axis=-1) ** 0.3
    return (turning, standing) if rotating == "inner" else (standing, turning)


def spectrum_reference_life(bearing: AbstractRollingBearing, displacements, speed, duration,
                            rotating: str = "inner") -> BearingLife:
    """ISO/TS 16281's basic reference rating life of a ball bearing under a load spectrum of k
    bins, the bins' damage added by Palmgren–Miner (module docstring).

    Args:
        displacements: each bin's ring displacement d_i (m, rad), (k, 5) (its operating point,
            as :func:`reference_life` takes it); a bin that loads no ball does no damage.
        speed: ω_i (rad/s, >= 0), (k,) or a scalar for all bins.
        duration: t_i (s, >= 0), (k,), the time run in each bin.
        rotating: as :func:`reference_life`.

    Returns:
        :class:`~jaxgear.bearings.BearingLife`: ``equivalent_load`` P_ref = C / (L10r /
        10⁶)^(1/3) (N), ``revolutions`` L10r (revolutions), ``duration`` its seconds at the
        bins' speeds and times. Differentiable in the displacements and the geometry.

    Raises:
        ValueError: as :func:`reference_life`; arrays not shaped by the bins, a negative or
            non-finite speed or time, no bin that turns, loads a ball and has time (one line).
    """
    w = "spectrum_reference_life"
    _check_ball_kind(w, bearing, rotating)
    check_real("displacements", displacements, "m, rad", shape=(None, 5), shape_text="(k, 5)",
               where=w)
    k = np.shape(displacements)[0]
    if np.ndim(speed) == 0:
        check_real("speed", speed, "rad/s", lo=0.0, where=w)
        speed = jnp.full(k, jnp.asarray(speed, float))
    check_real("speed", speed, "rad/s", lo=0.0, shape=(k,), shape_text=f"({k},), one per bin",
               where=w)
    check_real("duration", duration, "s", lo=0.0, shape=(k,), shape_text=f"({k},), one per bin",
               where=w)
    Q = jax.vmap(bearing.element_loads)(jnp.asarray(displacements, float))  # (k, Z)
    loaded = jnp.any(Q > 0, axis=-1)
    n = jnp.asarray(speed, float) * jnp.asarray(duration, float) / (2.0 * jnp.pi)
    if not is_traced(Q) and not np.any(np.asarray(loaded) & (np.asarray(n) > 0)):
        raise ValueError(f"{w}: no bin loads a ball while it turns with time in it: allowed at "
                         "least one loaded bin with speed and duration > 0")
    safe = jnp.where(loaded[:, None], Q, 1.0)  # an unloaded bin: no damage, finite derivatives
    Q_ei, Q_ee = _equivalent_loads(bearing, safe, rotating)
    Q_ci, Q_ce = _ratings(bearing)
    L = ((Q_ci / Q_ei) ** (-10.0 / 3.0) + (Q_ce / Q_ee) ** (-10.0 / 3.0)) ** -0.9 * 1e6
    damage = jnp.sum(jnp.where(loaded, n / L, 0.0))
    revolutions = jnp.sum(n) / damage
    return BearingLife(bearing.dynamic_rating / (revolutions / 1e6) ** (1.0 / 3.0), revolutions,
                       jnp.sum(jnp.asarray(duration, float)) / damage)
