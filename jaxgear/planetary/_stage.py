"""A planetary stage in the literature's lumped form: sun, ring, carrier and N identical planets,
their matrices in the frame turning with the carrier, the Willis speed ratios and the assembly
condition (docs/planetary.md).

Sources: J. Lin and R. G. Parker, "Analytical characterization of the unique properties of
planetary gear free vibration", J. Vib. Acoust. 121 (1999) 316-321 (the planar model, its
equations (1)-(4) and the mode structure); R. G. Parker and J. Lin, "Mesh phasing relationships
in planetary and epicyclic gears", J. Mech. Des. 126 (2004) 365-370 (the mesh phases);
A. Kahraman, "Natural modes of planetary gear trains", J. Sound Vib. 173 (1994) (the torsional
model).

Conventions (the carrier frame): the x axis is fixed to the carrier, angles are positive
counter-clockwise seen from the side the planets are numbered on; planet n sits at the angle
``psi_n`` from the x axis, on the circle of radius ``carrier.base_radius``. Coordinates, in this
order (Lin & Parker's): the carrier ``(x_c, y_c, u_c)``, the ring ``(x_r, y_r, u_r)``, the sun
``(x_s, y_s, u_s)``, then each planet ``(zeta_n, eta_n, u_n)``. ``x, y`` are translations (m) in
the carrier frame; ``zeta_n, eta_n`` the planet's radial and tangential translations (m), along
``(cos psi_n, sin psi_n)`` and ``(-sin psi_n, cos psi_n)``; ``u = r theta`` a rotation (rad)
times the member's base radius (m; the carrier's: the planet-centre radius), positive
counter-clockwise. The mesh deflections, positive in compression (Lin & Parker 1999):

    delta_sn = -x_s sin psi_sn + y_s cos psi_sn - zeta_n sin a_s - eta_n cos a_s + u_s + u_n
    delta_rn = -x_r sin psi_rn + y_r cos psi_rn + zeta_n sin a_r - eta_n cos a_r + u_r - u_n

with ``psi_sn = psi_n - a_s`` and ``psi_rn = psi_n + a_r`` (a_s, a_r: the pressure angles of
the sun-planet and ring-planet meshes), and the planet-pin deflections
``delta_zeta = x_c cos psi_n + y_c sin psi_n - zeta_n``,
``delta_eta = -x_c sin psi_n + y_c cos psi_n + u_c - eta_n``.
The equations of motion at the carrier speed Omega (rad/s):
``M q'' + Omega G q' + (K - Omega^2 K_Omega) q = f``.
"""

from __future__ import annotations

import abc
import enum
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ..scenes import ALL_ROWS, AXIS_ROWS, Housing, HousingMount
from ._runout import Eccentricities, Unbalances
from .._util import (
    as_float,
    check_instance,
    check_integer,
    check_real,
    closest_circles,
    is_traced,
)


__all__ = [
    "AbstractPlanetaryModel",
    "Central",
    "Eccentricities",
    "PlanarPlanetary",
    "PlanetaryMember",
    "PlanetaryOnMount",
    "PlanetaryStage",
    "TorsionalPlanetary",
    "Unbalances",
    "check_assembly",
    "central_speeds",
    "central_torques",
    "closest_planets",
    "speed_ratio",
]


def _optional(value) -> Float[Array, ""] | None:
    """None stays None (the field's default), a number becomes a float array."""
    return None if value is None else as_float(value)


def _pair(value) -> Float[Array, " 2"]:
    """One stiffness for both directions, or two."""
    return jnp.broadcast_to(as_float(value), (2,))


class PlanetaryMember(eqx.Module):
    """One member of a planetary stage in the lumped form: a rigid body on its bearing.

    Attributes:
        mass: mass (kg), shape ``()``.
        polar_inertia: polar moment of inertia about its axis (kg m^2), shape ``()``.
        base_radius: base radius (m), shape ``()``; for the carrier the radius of the circle of
            the planet centres.
        bearing_stiffness: translational bearing stiffnesses (N/m), shape ``(2,)``: along the
            carrier frame's x and y for a central member, along the pin's radial (zeta) and
            tangential (eta) directions for a planet (the planet pin on the carrier).
        torsional_stiffness: torsional stiffness to ground (N m/rad), shape ``()``: 0 for a free
            member, a large value for a fixed one (Lin & Parker's ``k_u`` is this over the
            base radius squared).
        axial_stiffness: axial bearing stiffness (N/m), shape ``()``, along the stage axis (the
            pin's, for a planet); used by :class:`~jaxgear.planetary.SpatialPlanetary` only.
        tilt_stiffness: tilting bearing stiffnesses (N m/rad), shape ``(2,)``: about the
            carrier frame's x and y (a central member), about the pin's zeta and eta (a planet,
            relative to the carrier); :class:`~jaxgear.planetary.SpatialPlanetary` only.
        diametral_inertia: moment of inertia about a diameter through the centre (kg m^2),
            shape ``()``, for the tilts of :class:`~jaxgear.planetary.SpatialPlanetary`; ``None``
            (default): half the polar inertia (a thin disc).

    Raises:
        ValueError: a mass, inertia or radius <= 0, a stiffness < 0 (one line naming it).
    """

    mass: Float[Array, ""] = eqx.field(converter=as_float)
    polar_inertia: Float[Array, ""] = eqx.field(converter=as_float)
    base_radius: Float[Array, ""] = eqx.field(converter=as_float)
    bearing_stiffness: Float[Array, " 2"] = eqx.field(converter=_pair, default=0.0)
    torsional_stiffness: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    axial_stiffness: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    tilt_stiffness: Float[Array, " 2"] = eqx.field(converter=_pair, default=0.0)
    diametral_inertia: Float[Array, ""] | None = None

    def __check_init__(self):
        for name, unit in (("axial_stiffness", "N/m"), ("tilt_stiffness", "N m/rad")):
            value = getattr(self, name)
            check_real(name, value, unit, lo=0.0, shape=jnp.shape(value), where="PlanetaryMember")
        if self.diametral_inertia is not None:
            check_real("diametral_inertia", self.diametral_inertia, "kg m^2", lo=0.0,
                       lo_open=True, shape=(), where="PlanetaryMember")
        for name in ("mass", "polar_inertia", "base_radius"):
            check_real(
                name, getattr(self, name), lo=0.0, lo_open=True, shape=(), where="PlanetaryMember"
            )
        check_real(
            "bearing_stiffness",
            self.bearing_stiffness,
            "N/m",
            lo=0.0,
            shape=(2,),
            where="PlanetaryMember",
        )
        check_real(
            "torsional_stiffness",
            self.torsional_stiffness,
            "N m/rad",
            lo=0.0,
            shape=(),
            where="PlanetaryMember",
        )

    @classmethod
    def lumped(cls, mass, inertia_over_r2, base_radius, bearing, torsional_u=0.0, **spatial):
        """The member in Lin & Parker's units: ``inertia_over_r2`` = I/r^2 (kg), ``bearing``
        (N/m, one value for both directions or two), ``torsional_u`` = k_u (N/m, on the
        coordinate u = r theta); converted to I = (I/r^2) r^2 and k_theta = k_u r^2.
        ``spatial``: ``axial_stiffness``, ``tilt_stiffness``, ``diametral_inertia`` (SI)."""
        r = as_float(base_radius)
        return cls(
            mass=mass,
            polar_inertia=as_float(inertia_over_r2) * r**2,
            base_radius=r,
            bearing_stiffness=bearing,
            torsional_stiffness=as_float(torsional_u) * r**2,
            **spatial,
        )

    @property
    def tilt_inertia(self) -> Float[Array, ""]:
        """The diametral inertia (kg m^2): ``diametral_inertia``, or half the polar inertia."""
        if self.diametral_inertia is None:
            return 0.5 * self.polar_inertia
        return as_float(self.diametral_inertia)

    @property
    def inertia_over_r2(self) -> Float[Array, ""]:
        """I / r_b^2 (kg): the mass on the coordinate u = r_b theta."""
        return self.polar_inertia / self.base_radius**2

    @property
    def torsional_u(self) -> Float[Array, ""]:
        """k_theta / r_b^2 (N/m): the torsional stiffness on the coordinate u = r_b theta."""
        return self.torsional_stiffness / self.base_radius**2


class PlanetaryStage(eqx.Module):
    """A simple planetary stage: sun, ring, carrier and N identical planets (the lumped form of
    Lin & Parker 1999; their Table 1 gives a worked example).

    Attributes:
        sun, ring, carrier: the central members (:class:`PlanetaryMember`).
        planet: one planet (all N alike); its ``bearing_stiffness`` is the pin's (radial,
            tangential) stiffness on the carrier.
        planet_angles: angle psi_n of each planet centre from the carrier's x axis (rad),
            shape ``(n_planets,)``, counter-clockwise (``equally_spaced`` builds 2 pi n / N).
        sun_pressure_angle, ring_pressure_angle: operating pressure angles a_s, a_r (rad) of the
            sun-planet and ring-planet meshes, in (0, pi/2).
        sun_mesh_stiffness, ring_mesh_stiffness: constant mesh stiffness (N/m) on the line of
            action, shape ``()`` (every planet) or ``(n_planets,)``.
        eccentricities: the members' eccentricities (radial runout; :class:`Eccentricities`;
            none by default), used by the load sharing, the quasi-static solve and the dynamics.
        unbalances: the members' mass unbalances (:class:`Unbalances`), rotating forces in the
            dynamics; None (default): none (the dynamics then carry no time-varying load).
        helix_angle: base helix angle beta_b of the planets (rad), shape ``()``, in
            (-pi/2, pi/2): positive for right-hand planets (then the sun is left-hand and the
            ring right-hand), 0 (default) for a spur stage. Only
            :class:`~jaxgear.planetary.SpatialPlanetary` uses it (the planar and torsional models
            are spur).
        face_width: the meshes' face width b (m), shape ``()``, >= 0 (default 0: the mesh
            stiffness at one point): :class:`~jaxgear.planetary.SpatialPlanetary` spreads each mesh
            stiffness k (along the tooth normal) uniformly over it, which gives the mesh the
            tilting stiffness k b^2 cos^2(beta_b) / 12 (N m/rad) about the axis e_perp = d x
            e_z normal to its plane of action (d the line of action's transverse direction):
            a tilt theta_perp moves a point z across the face by -z cos(beta_b) theta_perp
            along the normal (23 % less than k b^2 / 12 at beta_b = 28.5 deg).
        sun_mesh_tilt_stiffness, ring_mesh_tilt_stiffness: each mesh's tilting stiffness
            kappa (N m/rad, about e_perp), shape ``()``, >= 0, as published models give one
            (Eritenel & Parker 2009); None (default): k b^2 cos^2(beta_b) / 12. Given, k is
            spread over b_kappa with k b_kappa^2 cos^2(beta_b) / 12 = kappa
            (:meth:`mesh_face_widths`; the 3D matrix and ConstantMeshes' springs).

    Raises:
        ValueError: fewer than one planet, an angle or stiffness out of range, planets whose
            base circles overlap (adjacent centres closer than 2 r_bp, coinciding planets;
            :func:`closest_planets`) (one line).

    Example:
        >>> lumped = PlanetaryMember.lumped  # Lin & Parker's Table 1 system, 4 planets
        >>> stage = PlanetaryStage.equally_spaced(
        ...     4, sun=lumped(0.4, 0.39, 0.0387, 1e8), ring=lumped(2.35, 3.0, 0.1375, 1e8, 1e9),
        ...     carrier=lumped(5.43, 6.29, 0.0884, 1e8), planet=lumped(0.66, 0.61, 0.05015, 1e8),
        ...     sun_pressure_angle=0.4294, ring_pressure_angle=0.4294,
        ...     sun_mesh_stiffness=5e8, ring_mesh_stiffness=5e8)
        >>> modes = planetary_modes(PlanarPlanetary(), stage)  # 21 frequencies (Hz)
    """

    sun: PlanetaryMember
    ring: PlanetaryMember
    carrier: PlanetaryMember
    planet: PlanetaryMember
    planet_angles: Float[Array, " n_planets"] = eqx.field(converter=as_float)
    sun_pressure_angle: Float[Array, ""] = eqx.field(converter=as_float)
    ring_pressure_angle: Float[Array, ""] = eqx.field(converter=as_float)
    sun_mesh_stiffness: Float[Array, "*n_planets"] = eqx.field(converter=as_float)
    ring_mesh_stiffness: Float[Array, "*n_planets"] = eqx.field(converter=as_float)
    eccentricities: Eccentricities = eqx.field(default_factory=Eccentricities)
    helix_angle: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    face_width: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    unbalances: Unbalances | None = None
    sun_mesh_tilt_stiffness: Float[Array, ""] | None = eqx.field(converter=_optional,
                                                                  default=None)
    ring_mesh_tilt_stiffness: Float[Array, ""] | None = eqx.field(converter=_optional,
                                                                   default=None)

    def __check_init__(self):
        check_real("helix_angle", self.helix_angle, "rad", lo=-np.pi / 2, hi=np.pi / 2,
                   lo_open=True, hi_open=True, shape=(), where="PlanetaryStage")
        check_real("face_width", self.face_width, "m", lo=0.0, shape=(), where="PlanetaryStage")
        for name in ("sun_mesh_tilt_stiffness", "ring_mesh_tilt_stiffness"):
            if getattr(self, name) is not None:
                check_real(name, getattr(self, name), "N m/rad", lo=0.0, shape=(),
                           where="PlanetaryStage")
        check_instance("eccentricities", self.eccentricities, Eccentricities,
                       "a jaxgear.planetary.Eccentricities", "PlanetaryStage")
        if self.unbalances is not None:
            check_instance("unbalances", self.unbalances, Unbalances, "a jaxgear.planetary.Unbalances",
                           "PlanetaryStage")
        for name in ("sun", "ring", "carrier", "planet"):
            check_instance(
                name,
                getattr(self, name),
                PlanetaryMember,
                "a jaxgear.planetary.PlanetaryMember",
                "PlanetaryStage",
            )
        check_real(
            "planet_angles",
            self.planet_angles,
            "rad",
            shape=(None,),
            shape_text="(n_planets,)",
            where="PlanetaryStage",
        )
        if self.planet_angles.shape[0] < 1:
            raise ValueError("PlanetaryStage: planet_angles has 0 planets: allowed >= 1")
        self.eccentricities.check_planets(self.planet_angles.shape[0])
        if self.unbalances is not None:
            self.unbalances.check_planets(self.planet_angles.shape[0])
        for name in ("sun_pressure_angle", "ring_pressure_angle"):
            check_real(
                name,
                getattr(self, name),
                "rad",
                lo=0.0,
                hi=np.pi / 2,
                lo_open=True,
                hi_open=True,
                shape=(),
                where="PlanetaryStage",
            )
        n = self.planet_angles.shape[0]
        for name in ("sun_mesh_stiffness", "ring_mesh_stiffness"):
            value = getattr(self, name)
            if jnp.ndim(value) not in (0, 1) or jnp.size(value) not in (1, n):
                raise ValueError(
                    f"PlanetaryStage: {name} must have shape () or ({n},), got {jnp.shape(value)}"
                )
            check_real(name, value, "N/m", lo=0.0, where="PlanetaryStage")
        self._check_spacing()

    def _check_spacing(self) -> None:
        """Refuse planets whose base circles overlap (the tip circles, larger, overlap more):
        adjacent centres 2 a sin(Δψ/2) apart on the carrier's circle of radius a must be at
        least 2 r_bp apart (:func:`closest_planets`); coinciding planets are 0 apart."""
        a, r_p = self.carrier.base_radius, self.planet.base_radius
        if self.n_planets < 2 or any(is_traced(v) for v in (self.planet_angles, a, r_p)):
            return
        i, j, d = closest_planets(self.planet_angles, float(a))
        if d < 2.0 * float(r_p):
            raise ValueError(
                f"PlanetaryStage: planets {i + 1} and {j + 1} (planet_angles "
                f"{float(self.planet_angles[i]):.6g}, {float(self.planet_angles[j]):.6g} rad) "
                f"overlap: their centres are {d:.6g} m apart on the carrier's circle of radius "
                f"{float(a):.6g} m, allowed >= 2 x the planet's base radius = "
                f"{2.0 * float(r_p):.6g} m (their base circles must not intersect)"
            )

    @classmethod
    def equally_spaced(cls, n_planets: int, **members_and_meshes) -> PlanetaryStage:
        """The stage with ``n_planets`` planets at psi_n = 2 pi (n - 1) / N (planet 1 on the
        x axis); the other fields as keywords."""
        check_integer("n_planets", n_planets, 1)
        carrier, planet = members_and_meshes.get("carrier"), members_and_meshes.get("planet")
        if isinstance(carrier, PlanetaryMember) and isinstance(planet, PlanetaryMember):
            most = max_planets(carrier.base_radius, planet.base_radius)
            if most is not None and n_planets > most:
                raise ValueError(
                    f"PlanetaryStage.equally_spaced: n_planets = {n_planets} is out of range: "
                    f"allowed [1, {most}] (planets of base radius "
                    f"{float(planet.base_radius):.6g} m on the circle of radius "
                    f"{float(carrier.base_radius):.6g} m: more would overlap)"
                )
        angles = 2.0 * np.pi * np.arange(n_planets) / n_planets
        return cls(planet_angles=angles, **members_and_meshes)

    @property
    def n_planets(self) -> int:
        """Number of planets N (static)."""
        return self.planet_angles.shape[0]

    def mesh_face_widths(self) -> tuple[Float[Array, " n"], Float[Array, " n"]]:
        """(b_s, b_r), each (n_planets,): the width (m) across the face over which each
        planet's sun and ring mesh stiffness is spread
        (:class:`~jaxgear.planetary.SpatialPlanetary`'s two Gauss points at +-b / (2 sqrt 3),
        :class:`~jaxgear.planetary.ConstantMeshes`' points): the face width, or where the mesh's
        tilting stiffness kappa is given, sqrt(12 kappa / (k cos^2 beta_b)), so that its tilting
        stiffness k b^2 cos^2(beta_b) / 12 is kappa (0 where k = 0)."""
        n = (self.n_planets,)
        c2 = jnp.cos(self.helix_angle) ** 2

        def width(k, kappa):
            if kappa is None:
                return jnp.broadcast_to(self.face_width, n)
            loaded = k > 0
            return jnp.where(loaded, jnp.sqrt(12.0 * kappa / jnp.where(loaded, k * c2, 1.0)),
                             0.0)

        k_s, k_r = self.mesh_stiffnesses()
        return (width(k_s, self.sun_mesh_tilt_stiffness),
                width(k_r, self.ring_mesh_tilt_stiffness))

    def mesh_stiffnesses(self) -> tuple[Float[Array, " n"], Float[Array, " n"]]:
        """(k_sn, k_rn): the sun-planet and ring-planet mesh stiffness of each planet (N/m)."""
        n = (self.n_planets,)
        return (
            jnp.broadcast_to(self.sun_mesh_stiffness, n),
            jnp.broadcast_to(self.ring_mesh_stiffness, n),
        )


# -- the planar model's pieces (Lin & Parker 1999) ---------------------------------------------

CENTRAL = 3  # carrier, ring, sun: 3 coordinates each, then the planets


def _planar_size(stage: PlanetaryStage) -> int:
    return 3 * (CENTRAL + stage.n_planets)


def _rows(stage: PlanetaryStage, central: int, central_part, planet_part) -> Float[Array, "n d"]:
    """One row per planet of a linear form of the planar coordinates: ``central_part`` (n, 3) on
    the central member ``central`` (0 carrier, 1 ring, 2 sun), ``planet_part`` (n, 3) on the
    planet's own coordinates."""
    n = stage.n_planets
    rows = jnp.zeros((n, _planar_size(stage)), dtype=stage.planet_angles.dtype)
    rows = rows.at[:, 3 * central : 3 * central + 3].set(central_part)
    planet_cols = 3 * CENTRAL + 3 * jnp.arange(n)[:, None] + jnp.arange(3)[None, :]
    return rows.at[jnp.arange(n)[:, None], planet_cols].set(planet_part)


def mesh_rows(stage: PlanetaryStage) -> tuple[Float[Array, "n d"], Float[Array, "n d"]]:
    """(V_s, V_r), each (n_planets, 3 (3 + n_planets)): the mesh deflections are
    ``delta_s = V_s q`` and ``delta_r = V_r q`` (m, positive in compression) for the planar
    coordinates q (module docstring)."""
    psi = stage.planet_angles
    a_s, a_r = stage.sun_pressure_angle, stage.ring_pressure_angle
    one = jnp.ones_like(psi)
    psi_s, psi_r = psi - a_s, psi + a_r
    sun = jnp.stack([-jnp.sin(psi_s), jnp.cos(psi_s), one], axis=-1)
    p_sun = jnp.stack([-jnp.sin(a_s) * one, -jnp.cos(a_s) * one, one], axis=-1)
    ring = jnp.stack([-jnp.sin(psi_r), jnp.cos(psi_r), one], axis=-1)
    p_ring = jnp.stack([jnp.sin(a_r) * one, -jnp.cos(a_r) * one, -one], axis=-1)
    return _rows(stage, 2, sun, p_sun), _rows(stage, 1, ring, p_ring)


def corner_rows(stage: PlanetaryStage) -> tuple:
    """The pieces of :func:`mesh_rows` that a corner contact beyond the theoretical path turns
    (docs/extended-contact.md, "Where it acts"), per mesh (sun, ring), each four (n_planets,
    3 (3 + N)) rows of the planar coordinates: the driving member's rotation entry, the driven
    member's, the translation entries (σ t on each member, its own frame; t the pinion's push
    along the line of action, σ = +1 on the driving member, −1 on the driven) and the same
    members' σ v, v the unit vector from the pinion's centre to its tangent point. A corner
    cell's row is the mesh row with the tip owner's rotation entry times λ and each
    translation entry σ t turned to σ (cos ε t − sin ε v) (:meth:`jaxgear.MeshModel.corner`).
    The sun mesh's pinion is the sun (driving the planet), the ring mesh's the planet (driving
    the ring)."""
    psi = stage.planet_angles
    a_s, a_r = stage.sun_pressure_angle, stage.ring_pressure_angle
    zero, one = jnp.zeros_like(psi), jnp.ones_like(psi)
    psi_s, psi_r = psi - a_s, psi + a_r

    def part(*cols):
        return jnp.stack(cols, axis=-1)

    no = part(zero, zero, zero)
    sun = (
        _rows(stage, 2, part(zero, zero, one), no),  # the sun's rotation (driving)
        _rows(stage, 2, no, part(zero, zero, one)),  # the planet's (driven)
        _rows(stage, 2, part(-jnp.sin(psi_s), jnp.cos(psi_s), zero),
              part(-jnp.sin(a_s) * one, -jnp.cos(a_s) * one, zero)),
        _rows(stage, 2, part(jnp.cos(psi_s), jnp.sin(psi_s), zero),
              part(-jnp.cos(a_s) * one, jnp.sin(a_s) * one, zero)),
    )
    ring = (
        _rows(stage, 1, no, part(zero, zero, -one)),  # the planet's rotation (driving)
        _rows(stage, 1, part(zero, zero, one), no),  # the ring's (driven)
        _rows(stage, 1, part(-jnp.sin(psi_r), jnp.cos(psi_r), zero),
              part(jnp.sin(a_r) * one, -jnp.cos(a_r) * one, zero)),
        _rows(stage, 1, part(-jnp.cos(psi_r), -jnp.sin(psi_r), zero),
              part(jnp.cos(a_r) * one, jnp.sin(a_r) * one, zero)),
    )
    return sun, ring


def pin_rows(stage: PlanetaryStage) -> tuple[Float[Array, "n d"], Float[Array, "n d"]]:
    """(P_zeta, P_eta): the planet-pin deflections (m) ``P q``, radial and tangential."""
    psi = stage.planet_angles
    zero, one = jnp.zeros_like(psi), jnp.ones_like(psi)
    radial = jnp.stack([jnp.cos(psi), jnp.sin(psi), zero], axis=-1)
    tangential = jnp.stack([-jnp.sin(psi), jnp.cos(psi), one], axis=-1)
    p_rad = jnp.stack([-one, zero, zero], axis=-1)
    p_tan = jnp.stack([zero, -one, zero], axis=-1)
    return _rows(stage, 0, radial, p_rad), _rows(stage, 0, tangential, p_tan)


def _members(stage: PlanetaryStage) -> tuple[PlanetaryMember, ...]:
    return (stage.carrier, stage.ring, stage.sun) + (stage.planet,) * stage.n_planets


def _planar_mass(stage):
    return jnp.diag(
        jnp.concatenate([jnp.stack([m.mass, m.mass, m.inertia_over_r2]) for m in _members(stage)])
    )


def _planar_mesh_stiffness(stage):
    v_s, v_r = mesh_rows(stage)
    k_s, k_r = stage.mesh_stiffnesses()
    return v_s.T @ (k_s[:, None] * v_s) + v_r.T @ (k_r[:, None] * v_r)


def _planar_stiffness(stage):
    """K = K_b + K_m (N/m): bearings of the central members, the planet pins, the meshes."""
    central = [m for m in _members(stage)[:CENTRAL]]
    b = jnp.concatenate(
        [jnp.concatenate([m.bearing_stiffness, m.torsional_u[None]]) for m in central]
    )
    planet_u = jnp.broadcast_to(stage.planet.torsional_u, (stage.n_planets,))
    diag = jnp.zeros(_planar_size(stage), dtype=b.dtype).at[: 3 * CENTRAL].set(b)
    diag = diag.at[3 * CENTRAL + 2 :: 3].set(planet_u)
    p_rad, p_tan = pin_rows(stage)
    k_pin = stage.planet.bearing_stiffness
    return (
        jnp.diag(diag)
        + k_pin[0] * p_rad.T @ p_rad
        + k_pin[1] * p_tan.T @ p_tan
        + _planar_mesh_stiffness(stage)
    )


def _planar_gyroscopic(stage):
    blocks = [
        jnp.array([[0.0, -2.0, 0.0], [2.0, 0.0, 0.0], [0.0, 0.0, 0.0]]) * m.mass
        for m in _members(stage)
    ]
    return _block_diag(blocks)


def _planar_centripetal(stage):
    return jnp.diag(
        jnp.concatenate([jnp.stack([m.mass, m.mass, 0.0 * m.mass]) for m in _members(stage)])
    )


def _block_diag(blocks):
    return jax.scipy.linalg.block_diag(*blocks)


# -- model kinds -------------------------------------------------------------------------------


class AbstractPlanetaryModel(eqx.Module):
    """A model kind of a planetary stage: which coordinates it keeps and its matrices.

    Every matrix is (n_dof, n_dof) in the model's coordinates (:meth:`dof_names`), in the
    carrier frame, SI units on the coordinates (m for a translation or u = r theta); at the
    carrier speed Omega (rad/s) the free motion obeys
    ``M q'' + Omega G q' + (K - Omega^2 K_Omega) q = f``, f in N.

    ``contact_solve``: whether the contact solve and the dynamics (cells on the transverse
    lines of action: ``planetary_quasi_static``, ``planetary_dynamics``) take the model.
    """

    contact_solve: ClassVar[bool] = True
    #: the Gauss points across the face at which the model's constant mesh springs act
    #: (:class:`~jaxgear.planetary.ConstantMeshes` ``face_points``): 1, the springs at mid-face
    face_points: ClassVar[int] = 1

    @abc.abstractmethod
    def reduction(self, stage: PlanetaryStage) -> Float[Array, "n_planar n_dof"]:
        """T: the planar coordinates of the model's coordinates, q_planar = T q."""

    @abc.abstractmethod
    def dof_names(self, stage: PlanetaryStage) -> tuple[str, ...]:
        """One name per coordinate, in order (``"x_c"``, ``"u_s"``, ``"eta_2"``...)."""

    @abc.abstractmethod
    def central_translations(self, stage: PlanetaryStage) -> tuple[int, ...]:
        """Indices of the central members' translations (x, y of carrier, ring, sun)."""

    @abc.abstractmethod
    def central_rotations(self, stage: PlanetaryStage) -> tuple[int, ...]:
        """Indices of the central members' rotations (u_c, u_r, u_s)."""

    @abc.abstractmethod
    def gyroscopic_matrix(self, stage: PlanetaryStage) -> Float[Array, "n_dof n_dof"]:
        """G (kg), skew-symmetric: the Coriolis term is Omega G q'."""

    @abc.abstractmethod
    def centripetal_matrix(self, stage: PlanetaryStage) -> Float[Array, "n_dof n_dof"]:
        """K_Omega (kg): the centripetal softening is -Omega^2 K_Omega q."""

    @abc.abstractmethod
    def pin_error_terms(self, stage: PlanetaryStage, tangential_errors, radial_errors):
        """(f, d_s, d_r): the load f (N, (n_dof,)) and the mesh-deflection offsets d_s, d_r
        (m, (n_planets,)) that planet-pin position errors cause: ``tangential_errors`` along
        eta, ``radial_errors`` along zeta (outward), both (m, (n_planets,))."""

    # -- the housing (a kind on a mount) ---------------------------------------------------

    def mount(self) -> HousingMount | None:
        """The :class:`~jaxgear.scenes.HousingMount` the kind's members stand on (its housing's
        h coordinates end :meth:`dof_names`), or None (the default): the stage on the ground."""
        return None

    def unmounted(self) -> AbstractPlanetaryModel:
        """The kind on the ground: itself (a kind on a mount: the kind it stands on)."""
        return self

    def on(self, mount: HousingMount | None) -> AbstractPlanetaryModel:
        """The kind on ``mount`` (docs/planetary.md, "On a housing"): its coordinates then the
        housing's, the supports the mount's joints take (``"ring"``, ``"carrier"``, ``"sun"``
        at the stage centre: :meth:`~jaxgear.scenes.HousingMount.on_axis`) moved from the
        ground onto their seats; None: the kind on the ground (:meth:`unmounted`).

        Raises:
            ValueError: a kind on a mount already (one mount per stage: ``unmounted().on``),
                a mount of another type, or one whose joints are not central members on the
                stage axis (one line)."""
        if self.mount() is not None:
            raise ValueError(f"{type(self).__name__}.on: the kind stands on a mount already, "
                             "allowed a kind on the ground (kind.unmounted().on(mount))")
        return self if mount is None else PlanetaryOnMount(self, mount)

    def mode_types(self) -> tuple[str, str]:
        """The names (:class:`~jaxgear.planetary.ModeType` values) of the modes in which only the
        :meth:`central_rotations` move, and only the :meth:`central_translations`."""
        return ("rotational", "translational")

    @eqx.filter_jit
    def mass_matrix(self, stage: PlanetaryStage) -> Float[Array, "n_dof n_dof"]:
        """M (kg): diag(m, m, I/r^2) per member reduced to the model's coordinates."""
        t = self.reduction(stage)
        return t.T @ _planar_mass(stage) @ t

    @eqx.filter_jit
    def stiffness_matrix(self, stage: PlanetaryStage) -> Float[Array, "n_dof n_dof"]:
        """K (N/m): bearings, planet pins and the constant mesh stiffnesses."""
        t = self.reduction(stage)
        return t.T @ _planar_stiffness(stage) @ t

    def error_terms(self, stage: PlanetaryStage, tangential_errors, radial_errors, travel=0.0):
        """(f, d_s, d_r) of :meth:`pin_error_terms` with the stage's eccentricities at the mesh
        travel ``travel`` (m) added (:class:`Eccentricities`): the carrier's as pin errors, the
        sun's and the ring's (and the planets' runouts) as offsets of the deflections of
        :meth:`mesh_deflection_rows` (their constant meshes' reaction in f, as the torsional
        model's pin errors). Those offsets are in-plane: a deflection along a helical tooth
        normal sees :meth:`spring_cos` (cos beta_b) times the transverse offset."""
        ecc = stage.eccentricities
        e_t, e_r = ecc.pin_errors(stage)
        f, d_s, d_r = self.pin_error_terms(stage, tangential_errors + e_t, radial_errors + e_r)
        c = self.spring_cos(stage)
        o_s, o_r = (c * o for o in ecc.mesh_offsets(stage, travel))
        v_s, v_r = self.mesh_deflection_rows(stage)
        k_s, k_r = stage.mesh_stiffnesses()
        return f - v_s.T @ (k_s * o_s) - v_r.T @ (k_r * o_r), d_s + o_s, d_r + o_r

    def mesh_deflection_rows(self, stage: PlanetaryStage):
        """(V_s, V_r), each (n_planets, n_dof): delta = V q (m, compression positive)."""
        t = self.reduction(stage)
        v_s, v_r = mesh_rows(stage)
        return v_s @ t, v_r @ t

    def face_rows(self, stage: PlanetaryStage):
        """((V_s, W_s), (V_r, W_r)), each (n_planets, n_dof): the transverse mesh deflection
        (m, compression positive) at the axial position z (m from the mesh mid-plane, along
        the stage axis) is ``(V + z W) q`` (a cell's normal approach: cos beta_b times it).
        Here the mid-face rows of :meth:`mesh_deflection_rows` and W = 0 (a model without
        tilts sees the same deflection across the face)."""
        v_s, v_r = self.mesh_deflection_rows(stage)
        return (v_s, jnp.zeros_like(v_s)), (v_r, jnp.zeros_like(v_r))

    def corner_rows(self, stage: PlanetaryStage) -> tuple:
        """:func:`corner_rows` in the model's coordinates (each row times :meth:`reduction`):
        per mesh (sun, ring) the driving and driven members' rotation rows, the translation
        rows σ t and the rows σ v, each (n_planets, n_dof). For a model with tilts (the 3D
        one) these are the in-plane coordinates' part: the corner's turned normal and its
        contact point do not change the tilting columns (not modelled)."""
        t = self.reduction(stage)
        return tuple(tuple(r @ t for r in mesh) for mesh in corner_rows(stage))

    def line_rows(self, stage: PlanetaryStage):
        """(X_s, X_r), each (n_planets, n_dof): the change of :meth:`face_rows`' deflection per
        metre of a cell's offset along the line of action from the transverse pitch point
        (``(V + z W + sigma X) q``). Zero here: a point moved along the line of action keeps
        its moment arm about the axis, and a model without tilts has no other."""
        v_s, v_r = self.mesh_deflection_rows(stage)
        return jnp.zeros_like(v_s), jnp.zeros_like(v_r)

    def spring_cos(self, stage: PlanetaryStage) -> Float[Array, ""]:
        """c (-): the stage's constant mesh stiffnesses act on c times the transverse
        deflection of :meth:`face_rows` (1: on the transverse line of action)."""
        return jnp.ones((), dtype=stage.planet_angles.dtype)

    def spin_matrices(self, stage: PlanetaryStage):
        """(G_v, K_v), each (n_dof, n_dof): the gyroscopic terms of the members' spin relative
        to the carrier, which the mesh travel speed v (m/s) sets (the sun turns at v / r_bs
        relative to the carrier): ``v G_v q'`` and ``Omega v K_v q`` join the left-hand side of
        the equations of motion (N, or N m on a tilt). Zero here (no tilting coordinates)."""
        n = self.reduction(stage).shape[1]
        z = jnp.zeros((n, n), dtype=stage.planet_angles.dtype)
        return z, z


class PlanarPlanetary(AbstractPlanetaryModel):
    """The planar lumped model of Lin & Parker (1999): three coordinates per member (two
    translations, one rotation), 3 (3 + N) in all, in the carrier frame, with the Coriolis and
    centripetal terms of the rotating frame (per member ``G = [[0, -2m, 0], [2m, 0, 0], 0]``,
    ``K_Omega = diag(m, m, 0)``)."""

    def reduction(self, stage):
        n = _planar_size(stage)
        return jnp.eye(n, dtype=stage.planet_angles.dtype)

    def dof_names(self, stage):
        central = tuple(f"{c}_{m}" for m in "crs" for c in "xyu")
        return central + tuple(
            f"{c}_{i + 1}" for i in range(stage.n_planets) for c in ("zeta", "eta", "u")
        )

    def central_translations(self, stage):
        return (0, 1, 3, 4, 6, 7)

    def central_rotations(self, stage):
        return (2, 5, 8)

    def gyroscopic_matrix(self, stage):
        return _planar_gyroscopic(stage)

    def centripetal_matrix(self, stage):
        return _planar_centripetal(stage)

    def pin_error_terms(self, stage, tangential_errors, radial_errors):
        # the pin stands e further along eta (eps along zeta): delta_eta = P_eta q + e,
        # delta_zeta = P_zeta q + eps; K q = -k_eta e P_eta - k_zeta eps P_zeta
        e = jnp.broadcast_to(as_float(tangential_errors), (stage.n_planets,))
        eps = jnp.broadcast_to(as_float(radial_errors), (stage.n_planets,))
        p_rad, p_tan = pin_rows(stage)
        k_pin = stage.planet.bearing_stiffness
        f = -k_pin[1] * (e @ p_tan) - k_pin[0] * (eps @ p_rad)
        zero = jnp.zeros_like(e)
        return f, zero, zero


class TorsionalPlanetary(AbstractPlanetaryModel):
    """The torsional model (Kahraman 1994): one rotation per member, ``(u_c, u_r, u_s, u_1..
    u_N)``; the members' centres and the planet pins are rigid (the planet centre moves with the
    carrier, eta_n = u_c). A rotation about the stage axis has no Coriolis nor centripetal term:
    G = K_Omega = 0.

    Conventions (the matrices are T^T M T, T^T K T of :class:`PlanarPlanetary`'s, T the
    constraint, :meth:`reduction`): u = r_b theta, the carrier's u_c = r_c theta_c at the
    planet circle; the carrier enters each mesh as the planet centre's eta_n = u_c on the line
    of action, delta_sn = u_s + u_n - u_c cos a_s, delta_rn = u_r - u_n - u_c cos a_r (forms
    without the cos a differ by it); the planets' mass rides on the carrier (their centres move
    with it): its mass on u_c is I_c / r_c^2 + N m_p, a planet keeps I_p / r_p^2 on u_n (a
    model without it has a higher carrier mode). Source: A. Kahraman, J. Sound Vib. 173 (1994)
    125-130; Lin & Parker (1999) for the deflections."""

    def reduction(self, stage):
        n = stage.n_planets
        t = jnp.zeros((_planar_size(stage), CENTRAL + n), dtype=stage.planet_angles.dtype)
        t = t.at[jnp.array([2, 5, 8]), jnp.arange(CENTRAL)].set(1.0)
        t = t.at[3 * CENTRAL + 3 * jnp.arange(n) + 1, 0].set(1.0)  # eta_n = u_c
        return t.at[3 * CENTRAL + 3 * jnp.arange(n) + 2, CENTRAL + jnp.arange(n)].set(1.0)

    def dof_names(self, stage):
        return ("u_c", "u_r", "u_s") + tuple(f"u_{i + 1}" for i in range(stage.n_planets))

    def central_translations(self, stage):
        return ()

    def central_rotations(self, stage):
        return (0, 1, 2)

    def gyroscopic_matrix(self, stage):
        n = CENTRAL + stage.n_planets
        return jnp.zeros((n, n), dtype=stage.planet_angles.dtype)

    def centripetal_matrix(self, stage):
        return self.gyroscopic_matrix(stage)

    def pin_error_terms(self, stage, tangential_errors, radial_errors):
        # rigid pin at eta_n = u_c + e_n, zeta_n = eps_n: the meshes see the offsets
        # -e cos a_s - eps sin a_s and -e cos a_r + eps sin a_r (Lin & Parker's deltas with the
        # planet shifted), the load is -T^T K_m q0 with q0 the shift alone
        e = jnp.broadcast_to(as_float(tangential_errors), (stage.n_planets,))
        eps = jnp.broadcast_to(as_float(radial_errors), (stage.n_planets,))
        q0 = jnp.zeros(_planar_size(stage), dtype=e.dtype).at[3 * CENTRAL + 1 :: 3].set(e)
        q0 = q0.at[3 * CENTRAL :: 3].set(eps)
        f = -self.reduction(stage).T @ (_planar_mesh_stiffness(stage) @ q0)
        v_s, v_r = mesh_rows(stage)
        return f, v_s @ q0, v_r @ q0


# -- a kind on a housing mount ---------------------------------------------------------------
# (docs/planetary.md, "On a housing"; docs/housing.md, "Planetary stages")
#
# A kind on a mount (:class:`PlanetaryOnMount`) is a kind (torsional, planar or 3D) on a
# :class:`~jaxgear.scenes.HousingMount` (``kind.on(mount)``, or the kind and the mount of a
# :class:`~jaxgear.planetary.PlanetaryModel`): it appends the mount's housing's h coordinates
# (its seats' 6-DOF masters and interior modal coordinates, fixed frame) after the stage's. Every
# matrix the engines read is the base kind's, grown by h zero columns (meshes, pins, Coriolis and
# centripetal terms act on the stage only), except
#
# - M: the housing's M_h on its coordinates;
# - K: the housing's K_h, and each joined support's spring taken off the ground and put between
#   the member and its seat through the seat's rigid lever G
#   (:meth:`~jaxgear.scenes.Housing.seat_spring`, the lumped scenes' coupling
#   d = u − G q restricted to the joined rows).
#
# Why only the axis. The stage's coordinates are taken in the frame turning with the carrier;
# the seat stands still. A member's rotation about the stage axis (θ_z = u / r_b) and its motion
# along it (z) are the same in both frames, so those springs join the seat with constant blocks.
# An in-plane translation or tilt seen from the seat is R(Ωt) times its carrier-frame one: its
# blocks would carry cos Ωt and sin Ωt, which the engines' constant structure matrices
# (:func:`~jaxgear.planetary.planetary_dynamics`, :func:`~jaxgear.planetary.planetary_whine`)
# cannot hold; they stay on their grounded springs. A stage whose carrier does not turn (a star
# stage, Ω = 0) has its carrier frame fixed: there a mount of all six rows
# (``HousingMount.on_axis(..., fixed_frame=True)``) joins every support of the joined members
# (x, y, z, tilts, θ_z) and the dynamics must run at Ω = 0.
#
# The stage axis is the scene's +z through the joints' point (m, scene frame), the frame
# :meth:`~jaxgear.scenes.Housing.of` places the housing in; the carrier frame's x axis is the
# scene's x (at Ω = 0, or for the axis rows, which do not depend on it).
#
# Source: Craig & Bampton, AIAA J. 6 (1968) for the condensed housing; the rigid seat lever is
# the lumped scenes' (docs/housing.md, "The coupling"). ``HousedPlanetary`` (``_housed.py``,
# deprecated) builds the same kind from a housing, seats, a centre and ``carrier_held``.

#: the central members' coordinate suffixes (their names in ``dof_names``)
_SUFFIX = {"carrier": "c", "ring": "r", "sun": "s"}
#: a member's 6-vector (u_x, u_y, u_z, θ_x, θ_y, θ_z) from its coordinates: name prefix per row
_NODE = ("x", "y", "z", "theta_x", "theta_y", "u")


def _pad(a, h: int, rows: bool = False):
    """``a`` (..., n) with h zero columns appended (and h zero rows where ``rows``)."""
    a = jnp.asarray(a)
    out = jnp.concatenate([a, jnp.zeros(a.shape[:-1] + (h,), a.dtype)], axis=-1)
    if rows:
        out = jnp.concatenate([out, jnp.zeros((h,) + out.shape[1:], a.dtype)], axis=0)
    return out


class PlanetaryOnMount(AbstractPlanetaryModel):
    """A planetary model kind on a housing mount (the section's comment above): ``model``'s
    coordinates (n) then the mount's housing's (h), the supports its joints take between the
    member and its seat. Built by a kind's :meth:`~jaxgear.planetary.AbstractPlanetaryModel.on` (the
    functional entries' form) and by :class:`~jaxgear.planetary.PlanetaryModel` ``(...,
    mount=)`` (the dynamic model's); not constructed by hand.

    Attributes:
        model: the kind on the ground (:class:`~jaxgear.planetary.TorsionalPlanetary`,
            :class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.SpatialPlanetary`).
        housing_mount: the :class:`~jaxgear.scenes.HousingMount` (:meth:`mount`): its housing
            placed in the stage's scene frame (the stage axis +z through its joints' point),
            its joints the central members ``"ring"``, ``"carrier"``, ``"sun"``, each at the
            stage centre on the axis rows (u_z, θ_z; the carrier frame turns) or on all six
            (the carrier held, a star stage: the dynamics at Ω = 0)
            (:meth:`~jaxgear.scenes.HousingMount.on_axis`).

    Coordinates: ``model.dof_names`` then the housing's
    (:meth:`~jaxgear.scenes.Housing.coordinate_names`: ``"housing <seat> u_x" .. "housing
    <seat> phi_z"`` per seat and ``"housing mode <k>"`` per kept interior mode). The joined springs'
    reactions (:func:`~jaxgear.planetary.support_reactions`) are what the member puts on its
    seat: the ring's reaction torque k_θ (θ_r − θ_seat) about the axis.

    Raises:
        ValueError: a kind on a mount or of another type, a mount of another type, a joint
            whose member is not a central member, whose rows are neither the axis rows nor
            all six (or differ between joints), whose frame is turned, or whose point is not
            the joints' one stage centre (one line).
    """

    model: AbstractPlanetaryModel
    housing_mount: HousingMount

    def __check_init__(self):
        where = "a planetary kind on a mount"
        check_instance("model", self.model, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary, "
                       "SpatialPlanetary)", where)
        if self.model.mount() is not None:
            raise ValueError(f"{where}: model = {self.model!r}, allowed a kind on the ground "
                             "(one mount per stage)")
        check_instance("mount", self.housing_mount, HousingMount,
                       "a jaxgear.scenes.HousingMount", where)
        joints = self.housing_mount.joints
        for j in joints:
            if j.member not in _SUFFIX:
                raise ValueError(f"{where}: joint member {j.member!r}, allowed one each of "
                                 "'ring', 'carrier', 'sun'")
            if j.rows not in (AXIS_ROWS, ALL_ROWS) or j.rows != joints[0].rows:
                raise ValueError(f"{where}: joint {j.member!r} rows = {j.rows!r}, allowed the "
                                 f"axis rows {AXIS_ROWS} (the carrier turns) or all six "
                                 f"{ALL_ROWS} (the carrier held), the same for every joint")
            if j.frame != 0.0 or j.point != joints[0].point:
                raise ValueError(f"{where}: joint {j.member!r} at {j.point!r} in a frame "
                                 f"turned {j.frame!r} rad, allowed every joint at the one "
                                 "stage centre in the scene frame (HousingMount.on_axis)")

    # -- the kind's mount (AbstractPlanetaryModel) ------------------------------------------

    def mount(self) -> HousingMount:
        """The :class:`~jaxgear.scenes.HousingMount` the kind stands on."""
        return self.housing_mount

    def unmounted(self) -> AbstractPlanetaryModel:
        """The kind on the ground (:attr:`model`)."""
        return self.model

    @property
    def housing(self) -> Housing:
        """The mount's :class:`~jaxgear.scenes.Housing`."""
        return self.housing_mount.housing

    @property
    def carrier_held(self) -> bool:
        """Whether the joints take all six rows (a star stage: the carrier does not turn)."""
        return self.housing_mount.fixed_frame

    def seat_indices(self) -> tuple:
        """``((member, seat index), ...)``: the joints' members and their seats' indices in the
        housing's :attr:`~jaxgear.scenes.Housing.seat_names`."""
        mount = self.housing_mount
        return tuple((j.member, mount.seat_index(k)) for k, j in enumerate(mount.joints))

    # -- the coupling ----------------------------------------------------------------------

    def _unjoined(self, stage: PlanetaryStage) -> PlanetaryStage:
        """The stage with the supports the joints take off the ground (set to 0): on the axis
        rows the axial and torsional springs, on all six also the bearings and the tilts."""
        for j in self.housing_mount.joints:
            m = getattr(stage, j.member)
            zero = jnp.zeros_like(m.torsional_stiffness)
            if j.rows == ALL_ROWS:
                m = eqx.tree_at(
                    lambda m: (m.bearing_stiffness, m.axial_stiffness, m.tilt_stiffness,
                               m.torsional_stiffness),
                    m, (jnp.zeros_like(m.bearing_stiffness), zero,
                        jnp.zeros_like(m.tilt_stiffness), zero))
            else:
                m = eqx.tree_at(lambda m: (m.axial_stiffness, m.torsional_stiffness), m,
                                (zero, zero))
            stage = eqx.tree_at(lambda s, member=j.member: getattr(s, member), stage, m)
        return stage

    def _joint(self, stage: PlanetaryStage, member: str, rows: tuple):
        """(T, K_b): T (6, n) the member's node (u_x, u_y, u_z, θ_x, θ_y, θ_z) from the base
        coordinates (θ_z = u / r_b), zero on rows the base kind has not or the joint does not
        take (``rows``, its mount joint's); K_b (6, 6) the member's support springs on those
        rows (N/m, N m/rad)."""
        m = getattr(stage, member)
        names = self.model.dof_names(stage)
        n = len(names)
        dtype = stage.planet_angles.dtype
        k_all = jnp.concatenate([m.bearing_stiffness, m.axial_stiffness[None], m.tilt_stiffness,
                                 m.torsional_stiffness[None]]).astype(dtype)
        T = jnp.zeros((6, n), dtype)
        keep = jnp.zeros(6, dtype)
        for row in rows:
            name = f"{_NODE[row]}_{_SUFFIX[member]}"
            if name not in names:
                continue
            scale = 1.0 / m.base_radius if row == 5 else 1.0
            T = T.at[row, names.index(name)].set(scale)
            keep = keep.at[row].set(1.0)
        return T, jnp.diag(k_all * keep)

    def coupling(self, stage: PlanetaryStage):
        """K_c (n + h, n + h): the joined springs between the members and their seats, the
        mount's seat coupling (:meth:`~jaxgear.scenes.HousingMount.coupling`) of each joined
        member's node T q (:meth:`_joint`) and its support springs K_b on the joined rows:
        K_c = Σ [[Tᵀ A T, Tᵀ B], [Bᵀ T, D]], (A, B, D) the blocks of
        :meth:`~jaxgear.scenes.Housing.seat_spring` (the lumped scenes' seat coupling)."""
        mount = self.housing_mount
        if not mount.joints:
            n = len(self.model.dof_names(stage)) + mount.size
            return jnp.zeros((n, n), stage.planet_angles.dtype)
        joints = [self._joint(stage, j.member, j.rows) for j in mount.joints]
        return mount.coupling([T for T, _ in joints], [k for _, k in joints])

    # -- the model kind --------------------------------------------------------------------

    @property
    def contact_solve(self) -> bool:
        return self.model.contact_solve

    @property
    def face_points(self) -> int:
        return self.model.face_points

    def reduction(self, stage):
        return _pad(self.model.reduction(stage), self.housing_mount.size)

    def dof_names(self, stage):
        return tuple(self.model.dof_names(stage)) + self.housing_mount.coordinate_names()

    def central_translations(self, stage):
        return self.model.central_translations(stage)

    def central_rotations(self, stage):
        return self.model.central_rotations(stage)

    def mode_types(self):
        return self.model.mode_types()

    def gyroscopic_matrix(self, stage):
        return _pad(self.model.gyroscopic_matrix(stage), self.housing_mount.size, rows=True)

    def centripetal_matrix(self, stage):
        return _pad(self.model.centripetal_matrix(stage), self.housing_mount.size, rows=True)

    def spin_matrices(self, stage):
        return tuple(_pad(a, self.housing_mount.size, rows=True)
                     for a in self.model.spin_matrices(stage))

    def pin_error_terms(self, stage, tangential_errors, radial_errors):
        f, d_s, d_r = self.model.pin_error_terms(stage, tangential_errors, radial_errors)
        return _pad(f, self.housing_mount.size), d_s, d_r

    def error_terms(self, stage, tangential_errors, radial_errors, travel=0.0):
        f, d_s, d_r = self.model.error_terms(stage, tangential_errors, radial_errors, travel)
        return _pad(f, self.housing_mount.size), d_s, d_r

    def mass_matrix(self, stage):
        m = _pad(self.model.mass_matrix(stage), self.housing_mount.size, rows=True)
        n = m.shape[0] - self.housing_mount.size
        return m.at[n:, n:].set(jnp.asarray(self.housing_mount.M, m.dtype))

    def stiffness_matrix(self, stage):
        h = self.housing_mount.size
        k = _pad(self.model.stiffness_matrix(self._unjoined(stage)), h, rows=True)
        n = k.shape[0] - self.housing_mount.size
        return k.at[n:, n:].add(jnp.asarray(self.housing_mount.K, k.dtype)) + self.coupling(stage)

    def mesh_deflection_rows(self, stage):
        h = self.housing_mount.size
        return tuple(_pad(v, h) for v in self.model.mesh_deflection_rows(stage))

    def face_rows(self, stage):
        return tuple(tuple(_pad(v, self.housing_mount.size) for v in mesh)
                     for mesh in self.model.face_rows(stage))

    def corner_rows(self, stage):
        return tuple(tuple(_pad(v, self.housing_mount.size) for v in mesh)
                     for mesh in self.model.corner_rows(stage))

    def line_rows(self, stage):
        return tuple(_pad(v, self.housing_mount.size) for v in self.model.line_rows(stage))

    def spring_cos(self, stage):
        return self.model.spring_cos(stage)


# -- kinematics --------------------------------------------------------------------------------


class Central(enum.IntEnum):
    """The central members of a simple planetary stage."""

    SUN = 0
    RING = 1
    CARRIER = 2


def central_speeds(
    z_sun: int, z_ring: int, fixed: Central, driver: Central, speed: float = 1.0
) -> np.ndarray:
    """The central members' speeds (rad/s, fixed frame; (3,): sun, ring, carrier, in
    :class:`Central`'s order) with ``fixed`` at rest and ``driver`` at ``speed``: the Willis
    relation ``z_s omega_s + z_r omega_r = (z_s + z_r) omega_c`` (``z_ring`` the ring's number of
    internal teeth, positive here), solved here once for the library and the case files
    (:func:`speed_ratio`, :meth:`jaxgear.io.PlanetarySpec.speeds`).

    Raises:
        ValueError: a tooth count < 3, ``z_ring <= z_sun``, or ``fixed`` the ``driver``.
    """
    check_integer("z_sun", z_sun, 3)
    check_integer("z_ring", z_ring, int(z_sun) + 1)
    fixed, driver = Central(fixed), Central(driver)
    if fixed == driver:
        raise ValueError(
            f"central_speeds: fixed = driver = {fixed.name}: allowed two different members"
        )
    a = np.zeros((3, 3))
    a[0] = [z_sun, z_ring, -(z_sun + z_ring)]  # Willis
    a[1, fixed] = 1.0
    a[2, driver] = 1.0
    w = np.linalg.solve(a, [0.0, 0.0, float(speed)])
    w[fixed] = 0.0
    return w


def central_torques(z_sun: int, z_ring: int, driver: Central, torque: float) -> np.ndarray:
    """The central members' torques (N m; (3,): sun, ring, carrier) with ``torque`` on the
    ``driver``: the lossless balance T_s : T_r : T_c = z_s : z_r : -(z_s + z_r) that goes with
    Willis' speeds (:func:`central_speeds`; the torques sum to 0, their power too).

    Raises:
        ValueError: a tooth count < 3, ``z_ring <= z_sun``.
    """
    check_integer("z_sun", z_sun, 3)
    check_integer("z_ring", z_ring, int(z_sun) + 1)
    z = (z_sun, z_ring, -(z_sun + z_ring))
    z_in = z[Central(driver)]
    return np.array([torque * z_m / z_in for z_m in z])


def speed_ratio(z_sun: int, z_ring: int, fixed: Central, driver: Central, driven: Central) -> float:
    """The Willis speed ratio omega_driver / omega_driven with ``fixed`` held
    (:func:`central_speeds`). Ring fixed, sun driving the carrier: 1 + z_r/z_s; carrier fixed,
    sun to ring: -z_r/z_s; sun fixed, ring to carrier: 1 + z_s/z_r.

    Raises:
        ValueError: a tooth count < 3, ``z_ring <= z_sun``, or two of the members the same.
    """
    check_integer("z_sun", z_sun, 3)
    check_integer("z_ring", z_ring, int(z_sun) + 1)
    roles = (Central(fixed), Central(driver), Central(driven))
    if len(set(roles)) != 3:
        raise ValueError(
            f"speed_ratio: fixed, driver, driven = {tuple(r.name for r in roles)}"
            " must be three different members"
        )
    w = central_speeds(z_sun, z_ring, roles[0], roles[1])
    return float(w[roles[1]] / w[roles[2]])


def check_assembly(z_sun: int, z_ring: int, planet_angles) -> None:
    """Refuse (one line) planets that cannot be assembled: a planet at psi_n needs
    ``(z_s + z_r) psi_n / (2 pi)`` integer (Parker & Lin 2004; for N equally spaced planets
    ``(z_s + z_r) / N`` integer). ``planet_angles`` in rad, shape ``(n_planets,)``, planet 1
    as the reference."""
    check_integer("z_sun", z_sun, 3)
    check_integer("z_ring", z_ring, int(z_sun) + 1)
    psi = np.asarray(planet_angles, dtype=float)
    check_real("planet_angles", psi, "rad", shape=(None,), where="check_assembly")
    turns = (z_sun + z_ring) * (psi - psi[0]) / (2.0 * np.pi)
    bad = np.abs(turns - np.round(turns)) > 1e-6 * (z_sun + z_ring)  # float32 angles too
    if np.any(bad):
        i = int(np.argmax(bad))
        raise ValueError(
            f"check_assembly: planet {i + 1} at {np.degrees(psi[i] - psi[0]):g} deg cannot be "
            f"assembled: (z_sun + z_ring) psi/360 = {turns[i]:.6g} must be an integer "
            f"(z_sun = {z_sun}, z_ring = {z_ring})"
        )


def closest_planets(planet_angles, carrier_radius: float) -> tuple[int, int, float]:
    """The two closest planets of a stage and their centres' distance: (i, j, d), planets i
    and j (0-based, i < j) at angles psi (rad, (n_planets,), n_planets >= 2) on the circle of
    radius ``carrier_radius`` a (m), d (m) their centres' distance, 2 a |sin((psi_j - psi_i)/2)|
    (:func:`jaxgear._util.closest_circles`, the rule of every gear layout: two gears in one
    plane that do not mesh must not overlap). Two planets of radius r overlap where d < 2 r:
    the stage's spacing check (:class:`PlanetaryStage` with the base radius; the case files and
    :class:`~jaxgear.planetary.ContactMeshes` with the tip radius)."""
    psi = np.asarray(planet_angles, dtype=float).reshape(-1)
    a = float(carrier_radius)
    centres = a * np.stack([np.cos(psi), np.sin(psi)], axis=-1)
    return closest_circles(centres, np.zeros(psi.size))


def max_planets(carrier_radius, planet_radius) -> int | None:
    """The most equally spaced planets of radius r (m) whose circles do not overlap on the
    circle of radius a (m): the largest N with 2 a sin(pi/N) >= 2 r (None: values traced or
    not finite)."""
    if is_traced(carrier_radius) or is_traced(planet_radius):
        return None
    a, r = float(carrier_radius), float(planet_radius)
    if not (np.isfinite(a) and np.isfinite(r)) or a <= 0 or r <= 0:
        return None
    if r >= a:
        return 1
    n = int(np.floor(np.pi / np.arcsin(r / a)))
    while n > 1 and 2 * a * np.sin(np.pi / n) < 2 * r:  # rounding at the boundary
        n -= 1
    return max(n, 1)
