"""ISO/TS 16281's basic reference rating life from the internal load distribution.

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

Roller kinds (:class:`~jaxgear.bearings.CylindricalRoller`, ``TaperedRoller``,
``SphericalRoller``, ``TaperedRollerPair``): ISO/TS 16281:2008's laminae. Each roller is cut
into S laminae (the kind's ``slices``, with its optional logarithmic ``crown`` in the laminae's
approach), lamina k of roller j loaded q_jk (``element_loads``); a spherical roller bearing's
two rows and a tapered pair's two rows add their laminae (i = 2 rows). With Z rollers a row:

- each lamina's dynamic equivalent loads, the ring turning relative to the load with exponent
  4 and the standing one with 9/2::

      q_e,k = (Σ_j q_jk⁴ / Z)^(1/4)   (turning),   q_e,k = (Σ_j q_jk^(9/2) / Z)^(2/9)  (standing)

- the rings' roller load ratings from C (the Lundberg–Palmgren line-contact relation behind
  ISO 281's roller C, with its λν = 0.83) and the laminae's::

      Q_ci = C / (0.83 · 0.378 Z i^(7/9) cos α) · [1 + (1.038 X)^(9/2)]^(2/9)
      Q_ce = C / (0.83 · 0.364 Z i^(7/9) cos α) · [1 + (1.038 X)^(−9/2)]^(2/9)
      X = ((1 − γ)/(1 + γ))^(143/108),   γ = D_w cos α / d_m,   q_c,k = Q_c S^(−7/9)

- the life, every lamina of both rings in series (Weibull slope 9/8)::

      L10r = [Σ_k ((q_ci,k/q_ei,k)^(−9/2) + (q_ce,k/q_ee,k)^(−9/2))]^(−8/9) · 10⁶ revolutions

  and P_ref = C / (L10r / 10⁶)^(3/10) (ISO 281's roller exponent 10/3).

Source: ISO/TS 16281:2008 eqs. (47)–(65) for radial roller bearings as transcribed in
github.com/minzhun/ISO16281@220b2feb ``RollerBearing.py`` (``__capacity``, ``__load``,
``__basic_ref_life``); the constants 0.378, 0.364, 1.038, 143/108 and λν = 0.83 are that
transcription's. Under a radial load with zero clearance an unprofiled roller's laminae are
loaded alike and the S^(−7/9) cancels: L10r does not depend on S. It then scales as (C/F_r)⁴
(the laminae's exponent), not as ISO 281's (C/P)^(10/3): with λν taken out of C
(L10r λν⁴) they agree at P = C within the rounding of the constants and the rollers'
discreteness (docs/bearings.md states the measured gap). ISO/TS 16281's edge-stress factor
for rollers without a profile is not applied (an unprofiled roller's edge laminae are rated as
they are loaded).

Not built: the TS's edge-stress concentration factor, its crown for l > 2.5 D_w (a flat middle),
thrust roller bearings, the modified reference life (a_ISO from the contact pressures).
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

#: the rollers' ratio of ISO 281's C to Lundberg and Palmgren's (λν; ISO/TS 16281, radial)
ROLLER_LAMBDA_NU = 0.83

#: which ring turns relative to the load: the inner (a shaft's bearing) or the outer (a planet's)
ROTATING = ("inner", "outer")


class ReferenceLife(eqx.Module):
    """ISO/TS 16281's basic reference rating life (:func:`reference_life`).

    Attributes:
        revolutions: L10r (revolutions, not millions); at a speed ω it lasts L10r · 2π/ω s.
        equivalent_load: P_ref (N), the load with which ISO 281's (C/P)^p gives L10r (p = 3
            balls, 10/3 rollers).
        inner_rating, outer_rating: Q_ci, Q_ce (N), the rings' element load ratings; a
            lamina's q_ci, q_ce for rollers.
        inner_load, outer_load: Q_ei, Q_ee (N), the rings' dynamic equivalent element loads,
            shape (); each lamina's q_ei,k, q_ee,k for rollers, (rows · slices,) (a tapered
            pair's row 0 first).
    """

    revolutions: Float[Array, ""]
    equivalent_load: Float[Array, ""]
    inner_rating: Float[Array, ""]
    outer_rating: Float[Array, ""]
    inner_load: Float[Array, "*laminae"]
    outer_load: Float[Array, "*laminae"]


def _ratings(bearing):
    """(Q_ci, Q_ce) (N) of a ball bearing, a lamina's (q_ci, q_ce) of a roller bearing, from
    its C (module docstring)."""
    if bearing.contact_exponent != 1.5:
        return _roller_ratings(bearing)
    D, dm, a = bearing.element_diameter, bearing.pitch_diameter, bearing.nominal_angle
    fi, fo = bearing.inner_conformity, bearing.outer_conformity
    g = D * jnp.cos(a) / dm
    X = ((1.0 - g) / (1.0 + g)) ** 1.72 * (fi * (2.0 * fo - 1.0) / (fo * (2.0 * fi - 1.0))) ** 0.41
    base = bearing.dynamic_rating / (bearing.elements * jnp.cos(a))
    Q_ci = base / 0.407 * (1.0 + (1.044 * X) ** (10.0 / 3.0)) ** 0.3
    Q_ce = base / 0.389 * (1.0 + (1.044 * X) ** (-10.0 / 3.0)) ** 0.3
    return Q_ci, Q_ce


def _roller_ratings(bearing):
    """A lamina's (q_ci, q_ce) (N) of a roller bearing from its C (module docstring)."""
    a = bearing.nominal_angle
    g = bearing.element_diameter * jnp.cos(a) / bearing.pitch_diameter
    X = 1.038 * ((1.0 - g) / (1.0 + g)) ** (143.0 / 108.0)
    base = bearing.dynamic_rating / (ROLLER_LAMBDA_NU * bearing.elements
                                     * bearing.rows ** (7.0 / 9.0) * jnp.cos(a))
    lamina = float(bearing.slices) ** (-7.0 / 9.0)
    Q_ci = base / 0.378 * (1.0 + X**4.5) ** (2.0 / 9.0)
    Q_ce = base / 0.364 * (1.0 + X**-4.5) ** (2.0 / 9.0)
    return Q_ci * lamina, Q_ce * lamina


def _exponents(bearing):
    """(w, e): the turning ring's exponent of the equivalent load and the Weibull slope (3,
    10/9 balls; 4, 9/8 rollers); the standing ring's exponent is w e (module docstring)."""
    return (3.0, 10.0 / 9.0) if bearing.contact_exponent == 1.5 else (4.0, 9.0 / 8.0)


def _laminae(Q):
    """The element loads as (Z, laminae) (N): a ball's (Z,) one column, a roller kind's (Z,
    slices) or (Z, 2) (spherical: a row a column) as they are, a tapered pair's (2, Z, slices)
    its rows' laminae side by side (row 0 first)."""
    if Q.ndim == 1:
        return Q[:, None]
    if Q.ndim == 3:
        return jnp.moveaxis(Q, 0, 1).reshape(Q.shape[1], -1)
    return Q


def _life(bearing, Q, rotating):
    """(L10r (10⁶ revolutions), Q_ei, Q_ee (laminae,), Q_ci, Q_ce) of the loads Q (Z,
    laminae) (module docstring)."""
    w, e = _exponents(bearing)
    Z = bearing.elements
    # (Q_e/Q_c)^(w e) from the sums Σ Q^w, Σ Q^(w e): a lamina no roller loads (a tilt, a
    # spherical bearing's idle row) adds 0 with finite derivatives
    turning = (jnp.sum(Q**w, axis=-2) / Z) ** e
    standing = jnp.sum(Q ** (w * e), axis=-2) / Z
    inner, outer = (turning, standing) if rotating == "inner" else (standing, turning)
    Q_ci, Q_ce = _ratings(bearing)
    L = jnp.sum(inner / Q_ci ** (w * e) + outer / Q_ce ** (w * e), axis=-1) ** (-1.0 / e)
    Q_ei, Q_ee = _equivalent_loads(bearing, Q, rotating)
    return L, Q_ei, Q_ee, Q_ci, Q_ce


def reference_life(bearing: AbstractRollingBearing, displacement, rotating: str = "inner"
                   ) -> ReferenceLife:
    """ISO/TS 16281's basic reference rating life L10r of a rolling bearing at the ring
    displacement ``displacement`` d (5,) (m, rad; the operating point, e.g.
    ``solve_displacement(bearing, load).displacement``): a ball kind's balls' loads, a roller
    kind's laminae's loads (its ``slices``, its ``crown``), rated against the rings' ratings
    from its C (module docstring). Differentiable in d and the geometry.

    Args:
        rotating: ``"inner"`` (the inner ring turns relative to the load; default) or
            ``"outer"``.

    Raises:
        ValueError: not a rolling kind with ``dynamic_rating``; d not (5,) finite;
            ``rotating`` not one of the two; no element loaded at d (one line)."""
    w = "reference_life"
    _check_kind(w, bearing, rotating)
    check_real("displacement", displacement, "m, rad", shape=(5,), shape_text="(5,)", where=w)
    Q = _laminae(bearing.element_loads(jnp.asarray(displacement, float)))
    if not is_traced(Q) and not np.any(np.asarray(Q) > 0):
        raise ValueError(f"{w}: no rolling element is loaded at displacement = "
                         f"{np.asarray(displacement)}: allowed an operating point that loads "
                         "the bearing")
    L, Q_ei, Q_ee, Q_ci, Q_ce = _life(bearing, Q, rotating)
    if Q_ei.shape == (1,):  # a ball kind: one column
        Q_ei, Q_ee = Q_ei[0], Q_ee[0]
    return ReferenceLife(L * 1e6, bearing.dynamic_rating / L ** (1.0 / bearing.life_exponent),
                         Q_ci, Q_ce, Q_ei, Q_ee)


def _check_kind(where, bearing, rotating):
    check_instance("bearing", bearing, AbstractRollingBearing, "a jaxgear.bearings kind",
                   where=where)
    if bearing.life_exponent is None or bearing.dynamic_rating is None:
        rating = None if bearing.life_exponent is None else bearing.dynamic_rating
        raise ValueError(
            f"{where}: {type(bearing).__name__} (dynamic_rating = {rating}) is "
            "out of range: allowed a rolling kind (ball or roller) with its dynamic_rating C "
            "given"
        )
    if rotating not in ROTATING:
        raise ValueError(f"{where}: rotating = {rotating!r} is out of range: allowed 'inner' or "
                         "'outer' (the ring that turns relative to the load)")


def _equivalent_loads(bearing, Q, rotating):
    """(Q_ei, Q_ee) (N) of the elements' loads Q (..., Z, laminae), each (..., laminae)
    (module docstring)."""
    Z = bearing.elements
    w, e = _exponents(bearing)
    turning = jnp.sum(Q**w / Z, axis=-2) ** (1.0 / w)
    standing = jnp.sum(Q ** (w * e) / Z, axis=-2) ** (1.0 / (w * e))
    return (turning, standing) if rotating == "inner" else (standing, turning)


def spectrum_reference_life(bearing: AbstractRollingBearing, displacements, speed, duration,
                            rotating: str = "inner") -> BearingLife:
    """ISO/TS 16281's basic reference rating life of a rolling bearing (ball or roller kind)
    under a load spectrum of k bins, the bins' damage added by Palmgren–Miner (module docstring).

    Args:
        displacements: each bin's ring displacement d_i (m, rad), (k, 5) (its operating point,
            as :func:`reference_life` takes it); a bin that loads no element does no damage.
        speed: ω_i (rad/s, >= 0), (k,) or a scalar for all bins.
        duration: t_i (s, >= 0), (k,), the time run in each bin.
        rotating: as :func:`reference_life`.

    Returns:
        :class:`~jaxgear.bearings.BearingLife`: ``equivalent_load`` P_ref = C / (L10r /
        10⁶)^(1/p) (N, p = 3 balls, 10/3 rollers), ``revolutions`` L10r (revolutions),
        ``duration`` its seconds at the bins' speeds and times. Differentiable in the
        displacements and the geometry.

    Raises:
        ValueError: as :func:`reference_life`; arrays not shaped by the bins, a negative or
            non-finite speed or time, no bin that turns, loads an element and has time (one
            line).
    """
    w = "spectrum_reference_life"
    _check_kind(w, bearing, rotating)
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
    Q = jax.vmap(lambda d: _laminae(bearing.element_loads(d)))(
        jnp.asarray(displacements, float))  # (k, Z, laminae)
    loaded = jnp.any(Q > 0, axis=(-2, -1))
    n = jnp.asarray(speed, float) * jnp.asarray(duration, float) / (2.0 * jnp.pi)
    if not is_traced(Q) and not np.any(np.asarray(loaded) & (np.asarray(n) > 0)):
        raise ValueError(f"{w}: no bin loads an element while it turns with time in it: "
                         "allowed at least one loaded bin with speed and duration > 0")
    safe = jnp.where(loaded[:, None, None], Q, 1.0)  # unloaded: no damage, finite derivatives
    L = _life(bearing, safe, rotating)[0] * 1e6
    damage = jnp.sum(jnp.where(loaded, n / L, 0.0))
    revolutions = jnp.sum(n) / damage
    return BearingLife(
        bearing.dynamic_rating / (revolutions / 1e6) ** (1.0 / bearing.life_exponent),
        revolutions, jnp.sum(jnp.asarray(duration, float)) / damage)
