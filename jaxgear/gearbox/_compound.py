"""A compound planetary stage with stepped planets as a gearbox stage kind (docs/gearbox.md,
"A compound planetary stage"): the whole kind in this one module, on the
:class:`~jaxgear.dynamics.AbstractStage` interface.

Each of the N planets is two gears rigidly joined on one shaft: gear p1 (z_p1 teeth, base radius
r_bp1) meshes the sun, gear p2 (z_p2, r_bp2) meshes the ring. The torsional lumped model
(Kahraman 1994's, one rotation per member, extended to the stepped planet) has the coordinates

    q = (theta_c, theta_r, theta_s, theta_1 .. theta_N)   (rad, absolute, all positive in the
                                                            same sense about the stage axis),

the planet centres riding on the carrier (their mass m_p on the carrier at the centre distance a).
The mesh deflections along the lines of action (compression positive, the sun driving) are

    delta_sn = r_bs theta_s + r_bp1 theta_n - (r_bs + r_bp1) theta_c,
    delta_rn = r_br theta_r - r_bp2 theta_n - (r_br - r_bp2) theta_c,

whose carrier terms r_bs + r_bp1 = a cos a_ws and r_br - r_bp2 = a cos a_wr make a rigid turn of
the whole stage strain-free. With z_p1 = z_p2 and r_bp1 = r_bp2 they are
:class:`~jaxgear.planetary.TorsionalPlanetary`'s (Lin & Parker 1999's deflections in rotations).

Kinematics (no deflection): Willis' relation for stepped planets,

    z_s z_p2 omega_s + z_r z_p1 omega_r = (z_s z_p2 + z_r z_p1) omega_c,

so that with the ring held and the sun driving the carrier omega_s / omega_c = 1 + z_r z_p1 /
(z_s z_p2) (e.g. H. W. Müller, Epicyclic Drive Trains, 1982, the stepped-planet 2K-H train).
Statics: each planet's moment balance F_rn r_bp2 = F_sn r_bp1.

Mesh travel and phasing: the stage's mesh travel x (m) is the sun mesh's, x = r_bs phi with phi
the sun's turn relative to the carrier; the ring meshes travel rho x, rho = r_bp2 / r_bp1 (one
planet shaft). At x planet n's sun mesh has its contact lines at s = x - gamma_sn p_bs and its
ring mesh at s = rho x + Delta - gamma_rn p_br (each mesh's s from its engagement point, p_b its
base pitch), with Parker & Lin's (2004) sequential phases taken mesh by mesh,

    gamma_sn = frac(z_s psi_n / 2 pi),   gamma_rn = frac(-z_r psi_n / 2 pi),

(each depends on the central member's teeth alone; with stepped planets they differ in general),
and Delta the sun–ring offset within a planet: for stepped planets it is set by how the two
gears are clocked on the planet shaft (a design choice, ``ring_offset``), not by the tooth counts.
Identical planets (the same clocking) assemble when (z_s z_p2 + z_r z_p1) psi_n / (2 pi g) is
an integer for every planet, g = gcd(z_p1, z_p2) (derived in docs/gearbox.md; for equal spacing
the known (z_s z_p2 + z_r z_p1) / (N g) integer).

Its two meshes have two mesh frequencies (ratio z_p1 : z_p2). The gearbox interface gives a stage
one :meth:`~jaxgear.dynamics.AbstractStage.mesh_period`: this stage reports the shorter
(the time step follows the faster mesh); the stage averages its own K̄_m over each mesh's own
period, but the coupled model's mesh energy shares average both over the shorter one and its
recorded window counts blocks of the gearbox's slowest reported period (raise ``keep_periods``
to cover the slower of the two meshes).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, MeshModel, on_the_path
from .._geometry import GearPair
from .._internal import InternalGearPair
from .._modifications import Modifications
from .._quasi_static import separation
from .._util import as_float, check_instance, check_integer, check_real
from ..dynamics import AbstractStage, mean_cell_stiffness
from ..planetary import Central

__all__ = ["CompoundPlanetaryStage", "stepped_planet_phases"]

_INDEX = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}


def stepped_planet_phases(teeth, planet_angles) -> tuple[Array, Array]:
    """(gamma_s, gamma_r): each planet's sun-mesh and ring-mesh phase relative to planet 1's
    (fractions of that mesh's period, in [0, 1), shape (n_planets,)), with the sun turning
    counter-clockwise relative to the carrier: gamma_sn = frac(z_s psi_n / 2 pi), gamma_rn =
    frac(-z_r psi_n / 2 pi) (Parker & Lin 2004, mesh by mesh; module docstring).

    Args:
        teeth: (z_s, z_p1, z_p2, z_r), integers >= 3 (z_r the ring's internal count, positive).
        planet_angles: psi_n (rad), (n_planets,), planet 1 the reference.

    Raises:
        ValueError: a tooth count not an integer >= 3, or a bad angle (one line)."""
    z_s, _, _, z_r = _check_teeth(teeth)
    check_real("planet_angles", planet_angles, "rad", shape=(None,),
               where="stepped_planet_phases")
    psi = as_float(planet_angles)
    turns = (psi - psi[0]) / (2.0 * jnp.pi)
    return _frac(z_s * turns), _frac(-z_r * turns)


def _frac(x):
    """frac(x) in [0, 1), within 1e-9 of a whole number taken as 0 (traceable)."""
    r = jnp.mod(x, 1.0)
    return jnp.where((r < 1e-9) | (r > 1.0 - 1e-9), 0.0, r)


def _check_teeth(teeth):
    if len(tuple(teeth)) != 4:
        raise ValueError(f"teeth = {teeth!r}: allowed four integers (z_s, z_p1, z_p2, z_r)")
    for name, z in zip(("z_s", "z_p1", "z_p2", "z_r"), teeth, strict=True):
        check_integer(f"teeth {name}", z, 3)
    return tuple(int(z) for z in teeth)


class CompoundPlanetaryStage(AbstractStage):
    """A planetary stage with stepped planets (module docstring): sun, ring, carrier and N
    identical planets, each two gears on one shaft (p1 meshes the sun, p2 the ring); ``input``
    and ``output`` any two central members, the third held to ground by ``held_stiffness``.

    Attributes:
        teeth: static (z_s, z_p1, z_p2, z_r), z_r the ring's internal count (positive).
        base_radii: (r_bs, r_bp1, r_bp2, r_br) (m), shape (4,), in the tooth counts' ratios per
            mesh (r_bp1 / r_bs = z_p1 / z_s, r_br / r_bp2 = z_r / z_p2, within 1e-6).
        center_distance: a (m), the planet circle (the planets' mass acts there on the carrier).
        inertias: polar inertias (kg m^2) of the carrier (without the planets), ring, sun and one
            stepped planet (both gears), shape (4,).
        planet_mass: m_p (kg), one stepped planet.
        planet_angles: psi_n (rad), (n_planets,), counter-clockwise; they must assemble.
        mesh_stiffnesses: (k_s, k_r) (N/m), the sun and ring meshes' mean stiffness along the
            line of action: the torsional chain's meshes (:meth:`matrices`), and the coupled
            model's when ``sun_mesh`` is None.
        held_stiffness: the held member's torsional stiffness to ground (N m/rad, > 0).
        input, output: static, two different :class:`~jaxgear.planetary.Central` members.
        sun_mesh, ring_mesh: the sun–p1 pair's (pinion: the sun) and the p2–ring pair's (pinion:
            the planet) :class:`~jaxgear.MeshModel`, both or neither: with them the coupled model
            takes their contact cells (the pair machinery's ``separation``), phased per planet.
        sun_modifications, ring_modifications: their flank modifications.
        ring_offset: Delta (m): planet 1's ring-mesh contact lines at s = rho x + Delta when its
            sun-mesh lines are at s = x (the planet gears' clocking).

    Raises:
        ValueError: input = output, a radius or inertia <= 0, base radii not in the tooth ratios,
            planets that do not assemble, one mesh model without the other or not the stage's
            (its pinion base radius), coast flanks, per-tooth deviations (one line each).
    """

    teeth: tuple[int, int, int, int] = eqx.field(static=True, converter=tuple)
    base_radii: Float[Array, " 4"] = eqx.field(converter=as_float)
    center_distance: Float[Array, ""] = eqx.field(converter=as_float)
    inertias: Float[Array, " 4"] = eqx.field(converter=as_float)
    planet_mass: Float[Array, ""] = eqx.field(converter=as_float)
    planet_angles: Float[Array, " n_planets"] = eqx.field(converter=as_float)
    mesh_stiffnesses: Float[Array, " 2"] = eqx.field(converter=as_float)
    held_stiffness: Float[Array, ""] = eqx.field(converter=as_float)
    input: Central = eqx.field(static=True)
    output: Central = eqx.field(static=True)
    sun_mesh: MeshModel | None = None
    ring_mesh: MeshModel | None = None
    sun_modifications: Modifications = eqx.field(default_factory=Modifications)
    ring_modifications: Modifications = eqx.field(default_factory=Modifications)
    ring_offset: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)

    def __check_init__(self):
        where = "CompoundPlanetaryStage"
        z_s, z_p1, z_p2, z_r = _check_teeth(self.teeth)
        if z_r <= z_p2:
            raise ValueError(f"{where}: teeth z_r = {z_r} is out of range: allowed > z_p2 = "
                             f"{z_p2}")
        if self.input == self.output:
            raise ValueError(f"{where}: input = output = {self.input!r}: allowed two different "
                             "central members")
        check_real("base_radii", self.base_radii, "m", lo=0.0, lo_open=True, shape=(4,),
                   where=where)
        check_real("center_distance", self.center_distance, "m", lo=0.0, lo_open=True,
                   shape=(), where=where)
        check_real("inertias", self.inertias, "kg m^2", lo=0.0, lo_open=True, shape=(4,),
                   where=where)
        check_real("planet_mass", self.planet_mass, "kg", lo=0.0, shape=(), where=where)
        check_real("planet_angles", self.planet_angles, "rad", shape=(None,), where=where)
        check_real("mesh_stiffnesses", self.mesh_stiffnesses, "N/m", lo=0.0, shape=(2,),
                   where=where)
        check_real("held_stiffness", self.held_stiffness, "N m/rad", lo=0.0, lo_open=True,
                   shape=(), where=where)
        check_real("ring_offset", self.ring_offset, "m", shape=(), where=where)
        if self.planet_angles.shape[0] < 1:
            raise ValueError(f"{where}: planet_angles is empty: allowed at least one planet")
        r = np.asarray(self.base_radii, dtype=float)
        for name, got, want in (("r_bp1 / r_bs", r[1] / r[0], z_p1 / z_s),
                                ("r_br / r_bp2", r[3] / r[2], z_r / z_p2)):
            if not math.isclose(got, want, rel_tol=1e-6):
                raise ValueError(f"{where}: base_radii {name} = {got!r} is out of range: "
                                 f"allowed the tooth ratio {want!r} (within 1e-6)")
        # assembly of identical planets: (z_s z_p2 + z_r z_p1) psi_n / (2 pi g) an integer
        psi = np.asarray(self.planet_angles, dtype=float)
        g = math.gcd(z_p1, z_p2)
        count = (z_s * z_p2 + z_r * z_p1) * (psi - psi[0]) / (2.0 * np.pi * g)
        bad = np.abs(count - np.round(count)) > 1e-6
        if np.any(bad):
            i = int(np.argmax(bad))
            raise ValueError(
                f"{where}: planet_angles[{i}] = {psi[i]!r} rad is out of range: identical "
                f"stepped planets assemble where (z_s z_p2 + z_r z_p1) psi / (2 pi g) = "
                f"{count[i]:.6g} is an integer (g = gcd(z_p1, z_p2) = {g})")
        if (self.sun_mesh is None) != (self.ring_mesh is None):
            raise ValueError(f"{where}: sun_mesh and ring_mesh: one is None: allowed both "
                             "MeshModels or both None")
        for name in ("sun_modifications", "ring_modifications"):
            mods = getattr(self, name)
            check_instance(name, mods, Modifications, "a jaxgear.Modifications", where)
            if mods.deviations is not None:
                raise ValueError(f"{where}: {name}.deviations is set: allowed None (per-tooth "
                                 "deviations do not follow a stage's teeth)")
        if self.sun_mesh is not None:
            for name, mesh, want in (("sun_mesh", self.sun_mesh, r[0]),
                                     ("ring_mesh", self.ring_mesh, r[2])):
                check_instance(name, mesh, MeshModel, "a jaxgear.MeshModel or None", where)
                if mesh.coast:
                    raise ValueError(f"{where}: {name}.coast = True: allowed False (the coupled "
                                     "model carries the loaded flanks)")
                got = float(mesh.base_radius_pinion)
                if not math.isclose(got, want, rel_tol=1e-6):
                    raise ValueError(f"{where}: {name}.base_radius_pinion = {got!r} m: allowed "
                                     f"the stage's {want!r} m (another pair's model)")

    @classmethod
    def from_pairs(cls, sun_pair: GearPair, ring_pair: InternalGearPair, planet_angles,
                   inertias, planet_mass, mesh_stiffnesses, held_stiffness, input: Central,
                   output: Central, meshes: tuple[MeshModel, MeshModel] | None = None,
                   modifications: tuple[Modifications, Modifications] | None = None,
                   ring_offset=0.0) -> CompoundPlanetaryStage:
        """The stage of the sun–p1 pair ``sun_pair`` (:class:`~jaxgear.GearPair`, pinion the
        sun) and the p2–ring pair ``ring_pair`` (:class:`~jaxgear.InternalGearPair`, pinion the
        planet's p2) at one centre distance: the teeth, base radii and centre distance from the
        pairs; ``meshes`` their :class:`~jaxgear.MeshModel` (``MeshModel.from_pair`` on the two
        pairs) or None; the rest as the attributes.

        Raises:
            ValueError: a pair of another kind, the pairs' centre distances differing by more
                than 1e-9 relative, or any check of the class (one line)."""
        where = "CompoundPlanetaryStage.from_pairs"
        check_instance("sun_pair", sun_pair, GearPair, "a jaxgear.GearPair", where)
        check_instance("ring_pair", ring_pair, InternalGearPair, "a jaxgear.InternalGearPair",
                       where)
        a_s, a_r = float(sun_pair.center_distance), float(ring_pair.center_distance)
        if not math.isclose(a_s, a_r, rel_tol=1e-9):
            raise ValueError(f"{where}: ring_pair.center_distance = {a_r!r} m: allowed the sun "
                             f"pair's {a_s!r} m (one planet circle)")
        teeth = (int(sun_pair.pinion.teeth), int(sun_pair.gear.teeth),
                 int(ring_pair.pinion.teeth), -int(ring_pair.gear.teeth))
        radii = [float(sun_pair.base_radii[0]), float(sun_pair.base_radii[1]),
                 float(ring_pair.base_radii[0]), float(ring_pair.base_radii[1])]
        mesh_s, mesh_r = (None, None) if meshes is None else meshes
        mods = (Modifications(), Modifications()) if modifications is None else modifications
        return cls(teeth, radii, a_s, inertias, planet_mass, planet_angles, mesh_stiffnesses,
                   held_stiffness, input, output, mesh_s, mesh_r, mods[0], mods[1], ring_offset)

    # -- geometry ----------------------------------------------------------------------------

    @property
    def n_planets(self) -> int:
        return int(self.planet_angles.shape[0])

    def _held(self) -> Central:
        return ({Central.CARRIER, Central.RING, Central.SUN} - {self.input, self.output}).pop()

    def _rows(self) -> tuple[Float[Array, "n N"], Float[Array, "n N"]]:
        """(v_s, v_r): each planet's sun- and ring-mesh deflection row on the rotations, (N, n)
        (module docstring's delta_sn, delta_rn)."""
        r_s, r_p1, r_p2, r_r = self.base_radii
        n = self.n_planets
        eye = jnp.eye(n, dtype=self.base_radii.dtype)
        one = jnp.ones((n, 1), self.base_radii.dtype)
        zero = jnp.zeros((n, 1), self.base_radii.dtype)
        v_s = jnp.concatenate([-(r_s + r_p1) * one, zero, r_s * one, r_p1 * eye], axis=1)
        v_r = jnp.concatenate([-(r_r - r_p2) * one, r_r * one, zero, -r_p2 * eye], axis=1)
        return v_s, v_r

    def _mass(self):
        i_c, i_r, i_s, i_p = self.inertias
        n = self.n_planets
        carrier = i_c + n * self.planet_mass * self.center_distance**2
        return jnp.diag(jnp.concatenate([jnp.stack([carrier, i_r, i_s]),
                                         jnp.broadcast_to(i_p, (n,))]))

    def _hold(self):
        n = 3 + self.n_planets
        i = _INDEX[self._held()]
        return jnp.zeros((n, n), self.base_radii.dtype).at[i, i].set(self.held_stiffness)

    def _pitches(self):
        """(p_bs, p_br, rho): the two meshes' base pitches (m) and the ring meshes' travel per
        unit sun-mesh travel."""
        z_s, _, z_p2, _ = self.teeth
        r_s, r_p1, r_p2, _ = self.base_radii
        return 2 * jnp.pi * r_s / z_s, 2 * jnp.pi * r_p2 / z_p2, r_p2 / r_p1

    # -- the torsional chain -----------------------------------------------------------------

    def dof_names(self):
        return ("theta_c", "theta_r", "theta_s") + tuple(
            f"theta_{i + 1}" for i in range(self.n_planets))

    def matrices(self):
        v_s, v_r = self._rows()
        k_s, k_r = self.mesh_stiffnesses
        k = k_s * v_s.T @ v_s + k_r * v_r.T @ v_r + self._hold()
        return self._mass(), k

    def ends(self):
        return _INDEX[self.input], _INDEX[self.output]

    # -- the coupled dynamic model -----------------------------------------------------------

    def _sun_row(self, x) -> CellRow:
        v_s, _ = self._rows()
        if self.sun_mesh is None:
            one = jnp.ones((self.n_planets,), v_s.dtype)
            return CellRow(None, v_s, self.mesh_stiffnesses[0] * one, one, 0.0 * one,
                           jnp.ones_like(one, bool))
        p_s, _, _ = self._pitches()
        gamma, _ = stepped_planet_phases(self.teeth, self.planet_angles)
        theta = (x - gamma * p_s) / self.sun_mesh.base_radius_pinion
        return self._mesh_row(self.sun_mesh, self.sun_modifications, theta, v_s)

    def _ring_row(self, x_r) -> CellRow:
        """The ring meshes' cells at the ring-mesh travel ``x_r`` = rho x (m)."""
        _, v_r = self._rows()
        if self.ring_mesh is None:
            one = jnp.ones((self.n_planets,), v_r.dtype)
            return CellRow(None, v_r, self.mesh_stiffnesses[1] * one, one, 0.0 * one,
                           jnp.ones_like(one, bool))
        _, p_r, _ = self._pitches()
        _, gamma = stepped_planet_phases(self.teeth, self.planet_angles)
        theta = ((x_r + self.ring_offset - gamma * p_r)
                 / self.ring_mesh.base_radius_pinion)
        return self._mesh_row(self.ring_mesh, self.ring_modifications, theta, v_r)

    @staticmethod
    def _mesh_row(mesh, mods, theta, v):
        cells, _, delta0 = jax.vmap(lambda t: separation(mesh, mods, t))(theta)  # (N, l, s)
        V = jnp.cos(mesh.base_helix_angle) * v[:, None, None, :]
        V = jnp.broadcast_to(V, cells.s.shape + (v.shape[1],))
        return CellRow.of(cells, V, delta0)

    def cell_row(self, x):
        _, _, rho = self._pitches()
        s, r = self._sun_row(x), self._ring_row(rho * x)
        return CellRow(None, *(jnp.concatenate([a, b]) for a, b in zip(s[1:], r[1:],
                                                                          strict=True)))

    def dynamic_parts(self, positions):
        p_s, p_r, _ = self._pitches()
        k_mean = 0.0
        path = on_the_path(self)  # the cells on the theoretical path (the mesh model's contact geometry)
        for row, period in ((path._sun_row, p_s), (path._ring_row, p_r)):  # each its own period
            k_mean = k_mean + mean_cell_stiffness(row, period, positions)
        m = self._mass()
        return m, self._hold(), k_mean, jnp.zeros(m.shape[0], m.dtype)

    def on_flanks(self, sign):
        """The stage on the other flanks when ``sign`` < 0 (the planets drive the sun): for
        symmetric teeth the other-flank picture is the drive-flank one mirrored (s -> g - s on
        each mesh, g its path of contact, the planets' phases keeping their form), which maps
        planet 1's offset to Delta' = g_r - rho g_s - Delta (mod p_br) (with rho = 1 the simple
        stage's :meth:`~jaxgear.planetary.ContactMeshes.other_flanks`)."""
        if self.sun_mesh is None:
            return self
        _, p_r, rho = self._pitches()
        other = jnp.mod(self.ring_mesh.path_of_contact - rho * self.sun_mesh.path_of_contact
                        - self.ring_offset, p_r)
        return eqx.tree_at(lambda s: s.ring_offset, self,
                           jnp.where(sign < 0, other, self.ring_offset))

    def _cells_per_mesh(self):
        if self.sun_mesh is None:
            return 1, 1
        return (self.sun_mesh.n_lines * self.sun_mesh.n_slices,
                self.ring_mesh.n_lines * self.ring_mesh.n_slices)

    def mesh_forces(self, forces):
        n = self.n_planets
        c_s, c_r = self._cells_per_mesh()
        lead = forces.shape[:-1]
        f_s = forces[..., :n * c_s].reshape(lead + (n, c_s)).sum(-1)
        f_r = forces[..., n * c_s:].reshape(lead + (n, c_r)).sum(-1)
        if self.sun_mesh is not None:
            f_s = jnp.cos(self.sun_mesh.base_helix_angle) * f_s
            f_r = jnp.cos(self.ring_mesh.base_helix_angle) * f_r
        return jnp.concatenate([f_s, f_r], axis=-1)

    def mesh_names(self):
        n = self.n_planets
        return (tuple(f"sun-planet {i + 1}" for i in range(n))
                + tuple(f"ring-planet {i + 1}" for i in range(n)))

    def mesh_period(self):
        """The shorter of the two meshes' periods as sun-mesh travel (m): 2 pi r_bp1 /
        max(z_p1, z_p2) (the sun mesh's p_bs = 2 pi r_bp1 / z_p1, the ring mesh's p_br / rho
        = 2 pi r_bp1 / z_p2)."""
        _, z_p1, z_p2, _ = self.teeth
        return 2 * jnp.pi * self.base_radii[1] / max(z_p1, z_p2)

    def excited(self):
        return self.sun_mesh is not None

    def speeds(self, input_speed) -> Float[Array, " 3"]:
        """(omega_c, omega_r, omega_s) (rad/s): Willis for stepped planets on base radii
        (r_bs r_bp2 omega_s + r_br r_bp1 omega_r = (r_bs r_bp2 + r_br r_bp1) omega_c, the
        radii in the tooth counts' ratios), the held member at rest and the input at
        ``input_speed``."""
        r_s, r_p1, r_p2, r_r = self.base_radii
        a_s, a_r = r_s * r_p2, r_r * r_p1
        w = as_float(input_speed)
        rows = jnp.array([[-(a_s + a_r), a_r, a_s], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]],
                         dtype=self.base_radii.dtype)
        rows = rows.at[1, _INDEX[self._held()]].set(1.0).at[2, _INDEX[self.input]].set(1.0)
        return jnp.linalg.solve(rows, jnp.stack([0.0 * w, 0.0 * w, w]))

    def carrier_speed(self, input_speed):
        """The carrier's speed (rad/s) at the input member's ``input_speed`` (:meth:`speeds`)."""
        return self.speeds(input_speed)[0]

    def kinematics(self, input_speed, input_torque):
        r_s, r_p1, r_p2, r_r = self.base_radii
        w = self.speeds(input_speed)
        out_speed = w[_INDEX[self.output]]
        # a sun-mesh force F per planet: the sun's torque N r_bs F, the ring's N r_br F r_bp1 /
        # r_bp2 (the planet's balance), the carrier's their sum
        ring = r_r * r_p1 / r_p2
        lever = {Central.SUN: r_s, Central.RING: ring, Central.CARRIER: r_s + ring}[self.input]
        torque = jnp.abs(as_float(input_torque))
        f = torque / (lever * self.n_planets)
        n = self.n_planets
        static = jnp.concatenate([jnp.full((n,), f), jnp.full((n,), f * r_p1 / r_p2)])
        v = r_s * jnp.abs(w[2] - w[0])
        return out_speed, torque * jnp.abs(as_float(input_speed) / out_speed), v, static
