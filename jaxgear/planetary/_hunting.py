"""Per-tooth deviations of a planetary stage over its hunting period: which sun, planet and ring
teeth are in each of the 2N meshes at each mesh travel, and the meshes' cells with the ISO 1328-1
deviations of those teeth (docs/planetary.md, "Per-tooth deviations and the hunting period").

Tooth numbering (the mesh travel x of :class:`~jaxgear.planetary.ContactMeshes`: the sun's turn
relative to the carrier times r_bs). Every mesh numbers its tooth pairs as a pair does
(:class:`~jaxgear.Deviations`): the contact line of pair j of a mesh whose pinion has turned by
theta lies at ``s = r_b1 theta - j p_b`` (planet n's sun mesh at ``r_bs theta = x - gamma_sn
p_b``, its ring mesh at ``r_bp theta = x + Delta_rs - gamma_rn p_b``). The teeth are numbered
in the order they come into mesh:

* sun tooth t is the one in pair t of planet 1's sun mesh (it enters there at x = t p_b); the
  sun turning counter-clockwise relative to the carrier, it reaches planet n's mesh, Delta psi_n =
  psi_n - psi_1 further on, a travel r_bs Delta psi_n later: pair j of planet n's sun mesh holds
  sun tooth ``(j - S_n) mod z_s``, ``S_n = z_s Delta psi_n / 2 pi - gamma_sn`` (an integer);
* ring tooth u is the one in pair u of planet 1's ring mesh; the ring turning clockwise, it
  reaches planet n's mesh a travel r_br (2 pi - Delta psi_n) later: pair j of planet n's ring
  mesh holds ring tooth ``(j - R_n) mod z_r``, ``R_n = -z_r Delta psi_n / 2 pi - gamma_rn``;
* planet n's tooth k is the one in pair k of its own sun mesh; the same tooth's ring-side flank
  touches the ring mesh's line of action a travel D = :func:`sun_ring_travel` ahead of its
  sun-side flank (exact modulo a planet turn, z_p p_b): pair j of planet n's ring mesh holds its
  tooth ``(j - M_n) mod z_p``, ``M_n = (Delta_rs - D) / p_b + gamma_sn - gamma_rn``.

Hunting period: sun tooth, planet tooth and ring tooth of each mesh advance by one per mesh
period, so the teeth in all 2N meshes are back where they were after H = lcm(z_s, z_p, z_r) mesh
periods and not before (each index repeats only after a multiple of its own count): H / z_s turns
of the sun relative to the carrier; with the ring fixed, H / z_r carrier turns; with the sun
fixed, H / z_s. The planet count does not enter: each planet's teeth are tracked by name.
"""

from __future__ import annotations

import functools
import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, Int

from .._baseplane import CellRow
from .._deviations import GearDeviations
from .._internal import PlanetaryGeometry
from .._modifications import Modifications
from ._stage import check_assembly
from ._analysis import mesh_phases
from ._meshes import AbstractPlanetaryMeshes, ContactMeshes, sun_ring_travel
from .._quasi_static import separation
from .._stiffness_models import AbstractStiffness
from .._util import as_float, check_instance, check_integer, safe_max

__all__ = [
    "DeviationMeshes",
    "PlanetFlanks",
    "PlanetaryDeviations",
    "PlanetaryTeeth",
    "planetary_hunting_periods",
]


def planetary_hunting_periods(z_sun: int, z_planet: int, z_ring: int) -> int:
    """H = lcm(z_s, z_p, z_r): the mesh periods after which every mesh of the stage has the same
    sun, planet and ring teeth in contact again, and not before (module docstring). ``z_ring``:
    the ring's tooth count, positive.

    Raises:
        ValueError: a tooth count that is not an integer >= 1 (one line)."""
    for name, z in (("z_sun", z_sun), ("z_planet", z_planet), ("z_ring", z_ring)):
        check_integer(name, z, 1)
    return math.lcm(int(z_sun), int(z_planet), int(z_ring))


def _pair_index(arc, line, p_b):
    """Tooth pair j = k - line of the contact lines at the pinion's roll ``arc`` = r_b1 theta (m),
    k the whole mesh periods turned (as :meth:`jaxgear.Deviations.deviation`)."""
    k = jnp.round((arc - jnp.mod(arc, p_b)) / p_b)
    return (k - line).astype(jnp.int32)


class PlanetaryTeeth(eqx.Module):
    """Which sun, planet and ring teeth are in contact in each mesh of a stage (module docstring:
    the numbering, the shifts S_n, R_n, M_n and the hunting period).

    Build with :meth:`from_geometry`.

    Attributes:
        teeth: (z_s, z_p, z_r), static (the ring's positive).
        sun_shift, planet_shift, ring_shift: S_n, M_n, R_n, static tuples of ints, one per planet.
        base_pitch: p_b (m). sun_phases, ring_phases: gamma_sn, gamma_rn, (n_planets,).
        ring_offset: Delta_rs (m). sun_radius, planet_radius: r_bs, r_bp (m).
    """

    teeth: tuple[int, int, int] = eqx.field(static=True)
    sun_shift: tuple[int, ...] = eqx.field(static=True)
    planet_shift: tuple[int, ...] = eqx.field(static=True)
    ring_shift: tuple[int, ...] = eqx.field(static=True)
    base_pitch: Float[Array, ""] = eqx.field(converter=as_float)
    sun_phases: Float[Array, " n"] = eqx.field(converter=as_float)
    ring_phases: Float[Array, " n"] = eqx.field(converter=as_float)
    ring_offset: Float[Array, ""] = eqx.field(converter=as_float)
    sun_radius: Float[Array, ""] = eqx.field(converter=as_float)
    planet_radius: Float[Array, ""] = eqx.field(converter=as_float)

    @classmethod
    def from_geometry(cls, geometry: PlanetaryGeometry, planet_angles) -> PlanetaryTeeth:
        """The bookkeeping of the stage ``geometry`` with planets at ``planet_angles`` (rad,
        (n_planets,), planet 1 the reference; the assembly is checked).

        Raises:
            ValueError: planets that cannot be assembled (one line)."""
        check_instance("geometry", geometry, PlanetaryGeometry, "a jaxgear.PlanetaryGeometry",
                       "PlanetaryTeeth.from_geometry")
        sp, pr = geometry.sun_planet, geometry.planet_ring
        z_s, z_p, z_r = int(sp.pinion.teeth), int(sp.gear.teeth), -int(pr.gear.teeth)
        psi = np.asarray(planet_angles, dtype=float)
        check_assembly(z_s, z_r, psi)
        g_s, g_r = mesh_phases(z_s, z_r, psi)
        turns = (psi - psi[0]) / (2.0 * math.pi)
        p_b = float(sp.base_pitch)
        d_raw = sun_ring_travel(geometry)
        d_rs = float(np.mod(d_raw, p_b))
        ints = lambda v: tuple(int(i) for i in np.round(v))  # noqa: E731
        return cls(
            teeth=(z_s, z_p, z_r),
            sun_shift=ints(z_s * turns - g_s),
            planet_shift=ints((d_rs - d_raw) / p_b + g_s - g_r),
            ring_shift=ints(-z_r * turns - g_r),
            base_pitch=p_b,
            sun_phases=g_s,
            ring_phases=g_r,
            ring_offset=d_rs,
            sun_radius=float(sp.base_radii[0]),
            planet_radius=float(pr.base_radii[0]),
        )

    @property
    def n_planets(self) -> int:
        """N (static)."""
        return len(self.sun_shift)

    @property
    def hunting_periods(self) -> int:
        """H = lcm(z_s, z_p, z_r) mesh periods (:func:`planetary_hunting_periods`)."""
        return planetary_hunting_periods(*self.teeth)

    def sun_pair_teeth(self, pair) -> tuple[Int[Array, "n ..."], Int[Array, "n ..."]]:
        """(sun tooth, planet tooth) of the tooth pairs ``pair`` of each planet's sun mesh
        (integers, (n_planets, ...): planet n's pair indices j in row n), each that shape."""
        z_s, z_p, _ = self.teeth
        shift = jnp.asarray(self.sun_shift).reshape((-1,) + (1,) * (jnp.ndim(pair) - 1))
        return jnp.mod(pair - shift, z_s), jnp.mod(pair, z_p)

    def ring_pair_teeth(self, pair) -> tuple[Int[Array, "n ..."], Int[Array, "n ..."]]:
        """(planet tooth, ring tooth) of the tooth pairs ``pair`` of each planet's ring mesh
        (integers, (n_planets, ...)), each that shape."""
        _, z_p, z_r = self.teeth
        shape = (-1,) + (1,) * (jnp.ndim(pair) - 1)
        m = jnp.asarray(self.planet_shift).reshape(shape)
        r = jnp.asarray(self.ring_shift).reshape(shape)
        return jnp.mod(pair - m, z_p), jnp.mod(pair - r, z_r)

    def sun_mesh_teeth(self, x, line) -> tuple[Int[Array, "n ..."], Int[Array, "n ..."]]:
        """(sun tooth, planet tooth) of the contact lines ``line`` (the cells' line indices,
        any shape) of each planet's sun mesh at the mesh travel ``x`` (m), each
        (n_planets, *line.shape)."""
        line = jnp.asarray(line)[None]
        arc = (x - self.sun_phases * self.base_pitch).reshape((-1,) + (1,) * (line.ndim - 1))
        return self.sun_pair_teeth(_pair_index(arc, line, self.base_pitch))

    def ring_mesh_teeth(self, x, line) -> tuple[Int[Array, "n ..."], Int[Array, "n ..."]]:
        """(planet tooth, ring tooth) of the contact lines ``line`` of each planet's ring mesh at
        the mesh travel ``x`` (m), each (n_planets, *line.shape)."""
        line = jnp.asarray(line)[None]
        arc = x + self.ring_offset - self.ring_phases * self.base_pitch
        arc = arc.reshape((-1,) + (1,) * (line.ndim - 1))
        return self.ring_pair_teeth(_pair_index(arc, line, self.base_pitch))


class PlanetFlanks(eqx.Module):
    """A planet's ISO 1328-1 deviations per flank (ISO 1328-1 measures and tolerances the left
    and right flanks separately): a :class:`~jaxgear.GearDeviations` or None (a perfect flank)
    for each.

    The planet's tooth k has two working flanks: the one facing counter-clockwise, which the sun
    loads (read in the planet's sun mesh), and the one facing clockwise, which the ring loads
    (read in its ring mesh); teeth numbered as :class:`PlanetaryTeeth`, the same k on both.
    Each flank's values (m) follow :class:`~jaxgear.GearDeviations` on that flank: positive adds
    material on it, its cumulative pitch F_p,k from its own tooth 0. A tooth thicker by t: +t on
    both flanks (``PlanetFlanks.both``, the same as one ``GearDeviations`` for the planet); a
    tooth moved by f towards its sun-side flank (an indexing error): +f on ``sun_flank``, -f on
    ``ring_flank``. Runout belongs to the stage's :class:`~jaxgear.planetary.Eccentricities` (0 here).

    Attributes:
        sun_flank, ring_flank: :class:`~jaxgear.GearDeviations` or None, with the planet's
            tooth count (checked by :class:`DeviationMeshes`).

    Raises:
        ValueError: a flank that is not a GearDeviations or None (one line).
    """

    sun_flank: GearDeviations | None = None
    ring_flank: GearDeviations | None = None

    def __check_init__(self):
        for name in ("sun_flank", "ring_flank"):
            g = getattr(self, name)
            if g is not None:
                check_instance(name, g, GearDeviations, "a jaxgear.GearDeviations or None",
                               "PlanetFlanks")

    @classmethod
    def both(cls, deviations: GearDeviations | None) -> PlanetFlanks:
        """The same values on both flanks (e.g. tooth-thickness errors)."""
        return cls(deviations, deviations)

    def summary(self) -> dict:
        """Per flank, :meth:`jaxgear.GearDeviations.summary` (None for a perfect flank)."""
        return {name: None if g is None else g.summary()
                for name, g in (("sun_flank", self.sun_flank), ("ring_flank", self.ring_flank))}


@functools.singledispatch
def _planet_flanks(g) -> tuple:
    """(sun flank, ring flank) of a planet entry: None, both None (other types are refused by
    :class:`PlanetaryDeviations`)."""
    return None, None


@_planet_flanks.register
def _(g: GearDeviations) -> tuple:
    return g, g


@_planet_flanks.register
def _(g: PlanetFlanks) -> tuple:
    return g.sun_flank, g.ring_flank


class PlanetaryDeviations(eqx.Module):
    """ISO 1328-1 per-tooth deviations of a stage's gears (``None``: a perfect gear), in the
    conventions of :class:`~jaxgear.GearDeviations` (positive adds material on the working
    flank; teeth numbered as :class:`PlanetaryTeeth`).

    A planet works on both flanks (the sun loads the flanks facing counter-clockwise, the ring
    those facing clockwise). Its entry is either one :class:`~jaxgear.GearDeviations`, read on
    each flank as ISO 1328-1 measures that flank with the same values on both (a tooth's
    thickness error), or a :class:`PlanetFlanks` with each flank's own values (measured flanks
    differ; an indexing error that moves a whole tooth adds material on one flank and removes it
    on the other). Runout is the stage's :class:`~jaxgear.planetary.Eccentricities` (sun, ring and planet
    runout): here it must be 0.

    Attributes:
        sun, ring: :class:`~jaxgear.GearDeviations` or None.
        planets: per planet a :class:`~jaxgear.GearDeviations`, a :class:`PlanetFlanks` or
            None (a tuple; empty: all perfect).

    Raises:
        ValueError: (one line) a member that is not one of those, or a runout that is not 0.
    """

    sun: GearDeviations | None = None
    planets: tuple = ()
    ring: GearDeviations | None = None

    def __check_init__(self):
        for name, g in (("sun", self.sun), ("ring", self.ring)):
            if g is not None:
                check_instance(name, g, GearDeviations, "a jaxgear.GearDeviations or None",
                               "PlanetaryDeviations")
        for i, g in enumerate(self.planets):
            if g is not None:
                check_instance(f"planets[{i}]", g, (GearDeviations, PlanetFlanks),
                               "a jaxgear.GearDeviations, a jaxgear.planetary.PlanetFlanks or None",
                               "PlanetaryDeviations")
        for name, g in self._members():
            try:
                runout = float(g.runout)
            except (TypeError, jax.errors.ConcretizationTypeError):  # traced: not known here
                continue
            if runout != 0.0:
                raise ValueError(
                    f"PlanetaryDeviations: {name}.runout = {runout!r} m is out of range: allowed "
                    "0 (a member's runout is the stage's jaxgear.planetary.Eccentricities)"
                )

    def _members(self):
        """(name, GearDeviations) of every member and planet flank given (not None)."""
        out = [("sun", self.sun), ("ring", self.ring)]
        for i, g in enumerate(self.planets):
            s, r = _planet_flanks(g)
            out += ([(f"planets[{i}]", s)] if s is r else
                    [(f"planets[{i}].sun_flank", s), (f"planets[{i}].ring_flank", r)])
        return [(name, g) for name, g in out if g is not None]

    def check(self, teeth: tuple[int, int, int], n_planets: int) -> None:
        """Refuse, eagerly (one line naming the member), per-tooth arrays whose lengths are not
        the stage's tooth counts ``teeth`` (z_s, z_p, z_r), or a planets tuple that is neither
        empty nor one entry per planet."""
        if self.planets and len(self.planets) != n_planets:
            raise ValueError(
                f"PlanetaryDeviations: planets has {len(self.planets)} entries, out of range: "
                f"allowed 0 or one per planet ({n_planets})"
            )
        count = {"sun": teeth[0], "ring": teeth[2]}
        for name, g in self._members():
            z = count.get(name, teeth[1])
            if g.teeth != z:
                raise ValueError(
                    f"PlanetaryDeviations: {name} has {g.teeth} teeth, out of range: allowed one "
                    f"value per tooth ({z} teeth)"
                )

    def planet(self, n: int) -> GearDeviations | PlanetFlanks | None:
        """Planet n's entry (0-based) as given, None for a perfect planet."""
        return self.planets[n] if self.planets else None

    def planet_flanks(self, n: int) -> tuple[GearDeviations | None, GearDeviations | None]:
        """Planet n's (sun flank, ring flank) deviations (0-based; None: a perfect flank)."""
        return _planet_flanks(self.planet(n))


def _flank(dev: GearDeviations | None, tooth, u, zeta):
    """A member's deviation on the working flank of ``tooth`` (m, along the transverse line of
    action), 0 for a perfect member (runout 0: the angle does not enter)."""
    if dev is None:
        return jnp.zeros(jnp.broadcast_shapes(jnp.shape(tooth), jnp.shape(u)), jnp.result_type(u))
    return dev.line_deviation(tooth, 0.0, u, zeta)


class DeviationMeshes(AbstractPlanetaryMeshes):
    """The 2N meshes from real contact (:class:`~jaxgear.planetary.ContactMeshes`) with the
    per-tooth deviations of the teeth in contact at each mesh travel (:class:`PlanetaryTeeth`): each
    cell's initial separation less the deviations' material e_d of its two teeth (sun mesh: the
    sun's flank at roll fraction u, the planet's sun-side flank at 1 - u; ring mesh: the planet's
    ring-side flank at u, the ring's at 1 - u; u = s / g_alpha, zeta = z / b), e_d along the line of action times cos beta_b as for a
    pair. With every deviation 0 the meshes are the contact meshes exactly.

    Build with :meth:`from_geometry` (or from a :class:`~jaxgear.planetary.ContactMeshes` and its
    :class:`PlanetaryTeeth`).

    Attributes:
        contact: the meshes without deviations (their modifications stay theirs).
        teeth: the tooth bookkeeping. deviations: :class:`PlanetaryDeviations`.

    Raises:
        ValueError: (one line) tooth counts or a planet count that do not match, or a mesh with
            coast flanks.
    """

    contact: ContactMeshes
    teeth: PlanetaryTeeth
    deviations: PlanetaryDeviations
    one_period: ClassVar[bool] = False  # the teeth change from one mesh period to the next

    def other_flanks(self):
        raise ValueError(
            "DeviationMeshes.other_flanks: per-tooth deviations are bookkept on the flanks the "
            "sun drives (allowed: ContactMeshes or ConstantMeshes with the planets driving)"
        )

    def __check_init__(self):
        check_instance("contact", self.contact, ContactMeshes, "a jaxgear.planetary.ContactMeshes",
                       "DeviationMeshes")
        check_instance("teeth", self.teeth, PlanetaryTeeth, "a jaxgear.planetary.PlanetaryTeeth",
                       "DeviationMeshes")
        check_instance("deviations", self.deviations, PlanetaryDeviations,
                       "a jaxgear.planetary.PlanetaryDeviations", "DeviationMeshes")
        if self.teeth.n_planets != self.contact.sun_phases.shape[0]:
            raise ValueError(
                f"DeviationMeshes: teeth has {self.teeth.n_planets} planets, out of range: "
                f"allowed the meshes' {self.contact.sun_phases.shape[0]}"
            )
        self.deviations.check(self.teeth.teeth, self.teeth.n_planets)

    @classmethod
    def from_geometry(
        cls,
        geometry: PlanetaryGeometry,
        planet_angles,
        stiffness: AbstractStiffness,
        deviations: PlanetaryDeviations,
        n_slices: int = 1,
        modifications: tuple[Modifications, Modifications] | None = None,
        **table,
    ) -> DeviationMeshes:
        """:meth:`jaxgear.planetary.ContactMeshes.from_geometry` (same arguments) with
        ``deviations``."""
        contact = ContactMeshes.from_geometry(geometry, planet_angles, stiffness, n_slices,
                                              modifications, **table)
        return cls(contact, PlanetaryTeeth.from_geometry(geometry, planet_angles), deviations)

    @property
    def hunting_periods(self) -> int:
        """H = lcm(z_s, z_p, z_r) mesh periods."""
        return self.teeth.hunting_periods

    def mesh_period(self):
        return self.contact.mesh_period()

    def mesh_forces(self, forces):
        return self.contact.mesh_forces(forces)

    def ring_rows(self, stage, x, cells):
        return self.contact.ring_rows(stage, x, cells)

    def face_positions(self, stage):
        return self.contact.face_positions(stage)

    def mesh_stiffness(self, model, stage, positions):
        return self.contact.mesh_stiffness(model, stage, positions)

    def _material(self, x):
        """Per mesh kind (sun, ring): (mask, e of the modifications, e_d of the deviations),
        each (n_planets, n_lines * n_slices), e_d flank-normal (m); the cells as
        :meth:`jaxgear.planetary.ContactMeshes.cell_row` lays them out."""
        dev, teeth, c = self.deviations, self.teeth, self.contact
        p_b = c.sun_mesh.base_pitch
        t_s = (x - c.sun_phases * p_b) / c.sun_mesh.base_radius_pinion
        t_r = (x + c.ring_offset - c.ring_phases * p_b) / c.ring_mesh.base_radius_pinion
        out = []
        # per mesh kind, the (first, second) member of planet n: the sun and the planet's sun
        # flank; the planet's ring flank and the ring
        sun_members = lambda n: (dev.sun, dev.planet_flanks(n)[0])  # noqa: E731
        ring_members = lambda n: (dev.planet_flanks(n)[1], dev.ring)  # noqa: E731
        for mesh, mods, theta, teeth_of, members in (
            (c.sun_mesh, c.sun_modifications, t_s, teeth.sun_pair_teeth, sun_members),
            (c.ring_mesh, c.ring_modifications, t_r, teeth.ring_pair_teeth, ring_members),
        ):
            cells, e_max, delta0 = jax.vmap(lambda t, mesh=mesh, mods=mods: separation(
                mesh, mods, t))(theta)
            arc = mesh.base_radius_pinion * cells.theta[:, None, None]
            first, second = teeth_of(_pair_index(arc, cells.line, mesh.base_pitch))
            # beyond the theoretical path (extended_contact) a corner carries the path end's
            # deviation (docs/extended-contact.md); on the path the clip changes nothing
            u = jnp.clip(cells.s / mesh.path_of_contact, 0.0, 1.0)
            zeta = cells.z / mesh.face_width
            # the sun mesh: the sun's flank at u, the planet's at 1 - u; the ring mesh: the
            # planet's at u, the ring's at 1 - u (each member's roll from its own root)
            e = []
            for n in range(teeth.n_planets):
                d1, d2 = members(n)
                e.append(_flank(d1, first[n], u[n], zeta[n])
                         + _flank(d2, second[n], 1.0 - u[n], zeta[n]))
            mask = cells.mask.reshape(teeth.n_planets, -1)
            e_mod = jnp.where(cells.mask, e_max[:, None, None] - delta0, 0.0)
            e_dev = jnp.where(cells.mask, jnp.stack(e) * jnp.cos(mesh.base_helix_angle), 0.0)
            out.append((mask, e_mod.reshape(mask.shape), e_dev.reshape(mask.shape)))
        return out

    def cell_row(self, model, stage, x, offsets) -> CellRow:
        row = self.contact.cell_row(model, stage, x, offsets)
        e_dev = jnp.concatenate([e.reshape(-1) for _, _, e in self._material(x)])
        return row._replace(delta0=jnp.where(row.mask, row.delta0 - e_dev, 0.0))

    def te_offsets(self, stage, x):
        """(o_s, o_r) (m, (n_planets,) each): per mesh, (max e - max e_mod) / cos beta_b over
        its cells in contact, e = e_mod + e_d: the material the teeth in contact add beyond the
        modifications' reference."""
        cb = jnp.cos(self.contact.sun_mesh.base_helix_angle)
        out = []
        for mask, e_mod, e_dev in self._material(x):
            top = safe_max(jnp.where(mask, e_mod + e_dev, -jnp.inf), axis=1)
            ref = safe_max(jnp.where(mask, e_mod, -jnp.inf), axis=1)
            out.append(jnp.where(jnp.any(mask, axis=1), (top - ref) / cb, 0.0))
        return out[0], out[1]
