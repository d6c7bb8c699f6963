"""Runout and mass unbalance of a planetary stage's members (docs/planetary.md,
"Eccentricities").

:class:`Eccentricities`: each member's toothed centre stands off its axis of rotation (radial
runout), in a direction that turns with the member; the meshes see it as offsets of their
deflections (the quasi-static load sharing, the contact solve and the dynamics take it).
:class:`Unbalances`: each member's mass centre stands off its axis, a force m e omega^2 that
turns with the member (the dynamics take it).

Kinematics, in the carrier frame of :class:`~jaxgear.planetary.PlanetaryStage`, at the mesh travel x
(m): relative to the carrier the sun turns by +x / r_bs (the mesh travel's definition), the ring by
-x / r_br, a planet by -x / r_bp (an external mesh with the sun: the other sense), the carrier
not at all. At the carrier speed Omega and the mesh travel speed v a member's absolute speed is
omega = Omega + s v / r_b (s = +1 sun, -1 ring and planets, 0 carrier).
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import as_float, check_real

__all__ = ["Eccentricities", "Unbalances"]

#: the central members' order in the planar coordinates, their sense of rotation relative to
#: the carrier per unit of mesh travel over the base radius
_CENTRAL_SENSE = (("carrier", 0.0), ("ring", -1.0), ("sun", 1.0))


def _per_planet(value, n: int):
    return jnp.broadcast_to(as_float(value), (n,))


def check_per_planet(where: str, name: str, value, unit: str, n: int, lo=None) -> None:
    """Refuse (one line) a per-planet value that is not () or (n,), or out of range."""
    check_real(name, value, unit, lo=lo, where=where)
    if jnp.ndim(value) > 1 or jnp.size(value) not in (1, n):
        raise ValueError(f"{where}: {name} must have shape () or ({n},), got {jnp.shape(value)}")


class _PerMember(eqx.Module):
    """A value and its phase for each member of a planetary stage (the sun, ring and carrier
    one each, the planets one each or one for all), in :attr:`unit` and rad, with their checks:
    the fields of :class:`Eccentricities` and :class:`Unbalances`."""

    sun: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    sun_phase: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    ring: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    ring_phase: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    carrier: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    carrier_phase: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    planet: Float[Array, "*n"] = eqx.field(converter=as_float, default=0.0)
    planet_phase: Float[Array, "*n"] = eqx.field(converter=as_float, default=0.0)
    unit: ClassVar[str]

    def __check_init__(self):
        where, unit = type(self).__name__, self.unit
        for name in ("sun", "ring", "carrier"):
            check_real(name, getattr(self, name), unit, lo=0.0, shape=(), where=where)
            check_real(f"{name}_phase", getattr(self, f"{name}_phase"), "rad", shape=(),
                       where=where)
        check_real("planet", self.planet, unit, lo=0.0, where=where)
        check_real("planet_phase", self.planet_phase, "rad", where=where)

    def check_planets(self, n: int) -> None:
        """Refuse (one line) a planet's value or phase that is not () or (n,)."""
        where = type(self).__name__
        check_per_planet(where, "planet", self.planet, self.unit, n, lo=0.0)
        check_per_planet(where, "planet_phase", self.planet_phase, "rad", n)


class Eccentricities(_PerMember):
    """Eccentricities (radial runout) of the members: each member's toothed centre (the
    carrier's: the centre of its planet-pin circle) stands off its axis of rotation by an
    amplitude E (m) in a direction that turns with the member (docs/planetary.md,
    "Eccentricities").

    Conventions (the carrier frame of :class:`PlanetaryStage`): a central member's phase beta
    (rad) is the direction of the offset at the mesh travel x = 0, counter-clockwise from the
    carrier's x axis (through planet 1's centre when psi_1 = 0); a planet's phase beta_p is
    its offset's direction at x = 0 counter-clockwise from the planet's radial direction
    (zeta_n, outward). The offset turns with its member relative to the carrier: the sun's by
    +x / r_bs, the ring's by -x / r_br, a planet's by -x / r_bp, the carrier's not at all. So a
    sun eccentricity repeats once per turn of the sun relative to the carrier (z_s mesh
    periods), a ring's once per turn of the ring (z_r mesh periods; with the ring fixed, once
    per carrier turn), a planet's once per turn of the planet on its pin (z_p mesh periods),
    and a carrier's is steady in the carrier frame: it moves every pin by the same vector, the
    pin errors ``E sin(beta_c - psi_n)`` (tangential) and ``E cos(beta_c - psi_n)`` (radial). A
    member's offset e adds its projection on each of its meshes' line of action to the mesh's
    compression (the rows of the member's translations in Lin & Parker's deflections):
    ``E_s sin(beta_s + x / r_bs - psi_n + a_s)`` on the sun mesh of planet n,
    ``E_r sin(beta_r - x / r_br - psi_n - a_r)`` on its ring mesh, and a planet's runout, with
    a = beta_p - x / r_bp, ``-E_p sin(a + a_s)`` on its sun mesh and ``-E_p sin(a - a_r)`` on
    its ring mesh (the two meshes sit on either side of the planet: the phase between them is
    the geometry's). The bearings and pins act on the axis (the model's coordinates), the
    meshes on the toothed centre; the mass unbalance is :class:`Unbalances`.

    Attributes:
        sun, ring, carrier: the amplitudes E (m, >= 0), shape ``()``.
        sun_phase, ring_phase, carrier_phase: the phases beta (rad), shape ``()``.
        planet: each planet's runout E_p (m, >= 0), shape ``()`` (every planet) or
            ``(n_planets,)``.
        planet_phase: beta_p (rad), shape ``()`` or ``(n_planets,)``.

    Raises:
        ValueError: an amplitude < 0 or a value not finite (one line naming it); a planet's
            value of the wrong length (:class:`PlanetaryStage`).
    """

    unit: ClassVar[str] = "m"

    def pin_errors(self, stage) -> tuple[Float[Array, " n"], Float[Array, " n"]]:
        """(tangential, radial): the carrier eccentricity as planet-pin errors (m, (n_planets,);
        along eta and zeta, as :func:`~jaxgear.planetary.load_sharing` takes them)."""
        a = self.carrier_phase - stage.planet_angles
        return self.carrier * jnp.sin(a), self.carrier * jnp.cos(a)

    def mesh_offsets(self, stage, travel) -> tuple[Float[Array, " n"], ...]:
        """(d_s, d_r): the sun's, the ring's and the planets' runouts as offsets of the
        sun-planet and ring-planet mesh deflections (m, compression positive, (n_planets,)) at
        the mesh travel ``travel`` (m, ``()``)."""
        psi = stage.planet_angles
        n = psi.shape[0]
        a_s, a_r = stage.sun_pressure_angle, stage.ring_pressure_angle
        x = as_float(travel)
        turn_s = self.sun_phase + x / stage.sun.base_radius
        turn_r = self.ring_phase - x / stage.ring.base_radius
        e_p = _per_planet(self.planet, n)
        turn_p = _per_planet(self.planet_phase, n) - x / stage.planet.base_radius
        return (
            self.sun * jnp.sin(turn_s - psi + a_s) - e_p * jnp.sin(turn_p + a_s),
            self.ring * jnp.sin(turn_r - psi - a_r) - e_p * jnp.sin(turn_p - a_r),
        )


class Unbalances(_PerMember):
    """Mass unbalance of the members: each member's mass centre stands off its axis by e, an
    unbalance U = m e (kg m) that turns with the member; spinning at its absolute speed omega
    it loads its axis with the rotating force U omega^2 (docs/planetary.md, "Eccentricities").
    In the carrier frame the mass centre's offset turns at
    omega - Omega, and the rotating frame's Coriolis and centripetal terms on it add up to
    exactly U omega^2 along the offset (m (d^2/dt^2 + 2 i Omega d/dt - Omega^2) e^(i (omega -
    Omega) t) = -m omega^2 e^(i (omega - Omega) t)), so the load is that force, turning with
    the member in the carrier frame, on the member's translations (the planets': on zeta,
    eta); the offset's small change of the member's inertia and its torque under the
    member's angular acceleration are left out (e small against the radii).

    Phases and senses as :class:`Eccentricities`: beta at the mesh travel x = 0, the central
    members' from the carrier's x axis, a planet's from its radial direction; the offset turns
    with its member relative to the carrier (sun +x / r_bs, ring -x / r_br, planet -x / r_bp,
    carrier not at all: its force U Omega^2 is steady in the carrier frame). The torsional
    model keeps only what reaches its coordinates (a planet's tangential force on u_c: its
    pins are rigid).

    Attributes:
        sun, ring, carrier: U (kg m, >= 0), shape ``()``.
        sun_phase, ring_phase, carrier_phase: beta (rad), shape ``()``.
        planet: each planet's U (kg m, >= 0), shape ``()`` (every planet) or ``(n_planets,)``.
        planet_phase: beta_p (rad), shape ``()`` or ``(n_planets,)``.

    Raises:
        ValueError: an unbalance < 0 or a value not finite (one line naming it).
    """

    unit: ClassVar[str] = "kg m"

    def planar_load(self, stage, travel, carrier_speed, mesh_speed):
        """The rotating forces (N) on the planar coordinates (3 (3 + N),; Lin & Parker's
        order) at the mesh travel ``travel`` (m), the carrier speed ``carrier_speed`` (rad/s)
        and the mesh travel speed ``mesh_speed`` (m/s)."""
        n = stage.n_planets
        x, omega, v = as_float(travel), as_float(carrier_speed), as_float(mesh_speed)
        parts = []
        for name, sense in _CENTRAL_SENSE:
            r_b = getattr(stage, name).base_radius
            turn = getattr(self, f"{name}_phase") + sense * x / r_b
            size = getattr(self, name) * (omega + sense * v / r_b) ** 2
            parts.append(jnp.stack([size * jnp.cos(turn), size * jnp.sin(turn),
                                    jnp.zeros_like(size)]))
        r_p = stage.planet.base_radius
        turn_p = _per_planet(self.planet_phase, n) - x / r_p
        size_p = _per_planet(self.planet, n) * (omega - v / r_p) ** 2
        planets = jnp.stack([size_p * jnp.cos(turn_p), size_p * jnp.sin(turn_p),
                             jnp.zeros_like(size_p)], axis=-1)
        return jnp.concatenate(parts + [planets.reshape(-1)])

    def load(self, model, stage, travel,
             carrier_speed, mesh_speed) -> Float[Array, " n_dof"]:
        """:meth:`planar_load` on the model's coordinates (N, (n_dof,)): T^T f."""
        return model.reduction(stage).T @ self.planar_load(stage, travel, carrier_speed,
                                                           mesh_speed)
