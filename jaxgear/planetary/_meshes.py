"""The 2N meshes of a planetary stage as contact cells, phased per planet, and the quasi-static
solve of the stage over the carrier turn with the cells' unilateral contact (docs/planetary.md,
"Meshes from real contact").

Each sun–planet mesh is a :class:`~jaxgear.GearPair` (the sun drives) and each planet–ring mesh
an :class:`~jaxgear.InternalGearPair` (the planet drives, in the carrier frame), laid out in the
base plane by :meth:`jaxgear.MeshModel.from_pair` with jaxgear's stiffness model and the case's
modifications. The stage's meshes advance together: with the sun turning counter-clockwise
relative to the carrier by phi, every mesh's contact lines travel ``x = r_bs phi`` (m) along its
line of action (the ring's, turning the other way, as fast: r_bp phi_p = r_bs phi). At the mesh
travel x, planet n's sun mesh has its contact lines at ``s = x - gamma_sn p_b`` and its ring mesh
at ``s = x + Delta_rs - gamma_rn p_b`` (mod p_b; s from each pair's engagement point, as
:meth:`~jaxgear.MeshModel.cells`), gamma_sn, gamma_rn from :func:`~jaxgear.planetary.mesh_phases` (Parker &
Lin 2004), and Delta_rs the sun–ring offset within a planet (:func:`sun_ring_offset`).

A cell's approach is the transverse mesh deflection of Lin & Parker's model times cos beta_b
(the normal approach of a slice; the planar model keeps the transverse plane only), so the
model's ``mesh_deflection_rows`` are the cells' structure vectors; a model with tilts (the 3D
:class:`~jaxgear.planetary.SpatialPlanetary`) gives each cell the deflection at its own axial
position across the face (``model.face_rows``: (V + z W) q, z from the mesh mid-plane).
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import CellRow, Cells, MeshModel, on_the_path
from .._contact_geometry import AbstractContactGeometry, TheoreticalPath, rolling_lever
from .._contact import AbstractContactLaw, ExactContact, solve_contact
from .._internal import PlanetaryGeometry
from .._modifications import Modifications
from ._stage import AbstractPlanetaryModel, PlanetaryStage, check_assembly, closest_planets
from ._analysis import mesh_phases
from ._ring import AbstractRingModel, RigidRing
from .._quasi_static import quasi_static, separation
from .._stiffness_models import AbstractStiffness, stiffness_table
from .._util import as_float, check_instance, check_integer, check_real

__all__ = [
    "AbstractPlanetaryMeshes",
    "ConstantMeshes",
    "ContactMeshes",
    "PlanetMeshLoads",
    "PlanetaryQuasiStatic",
    "LUMPED_STIFFNESS_POSITIONS",
    "face_load_factor",
    "lumped_mesh_stiffness",
    "planet_mesh_loads",
    "planetary_mesh_stiffness",
    "planetary_quasi_static",
    "structure_stiffness",
    "sun_ring_offset",
]


def sun_ring_offset(geometry: PlanetaryGeometry) -> float:
    """Delta_rs (m, in [0, p_b)): how far planet 1's ring mesh runs ahead of its sun mesh, as a
    travel along the line of action (divide by p_b for Parker & Lin's sun–ring phase gamma_rs).

    Derivation (docs/planetary.md, "The sun–ring phase within a planet"): in the planet's frame
    (x outward from the carrier centre) the sun mesh's line of action touches the planet's base
    circle at the angle pi - a_s, the ring mesh's at a_r; the sun loads the planet's flanks that
    face counter-clockwise (base points at c_j + psi_b), the ring those facing clockwise
    (c_j - psi_b), psi_b = s_bp / (2 r_bp) the half base thickness. Measured from each pair's
    engagement point (jaxgear's s), the contact lines are at
    ``s_s = a sin a_s - rho_As - r_bp (c + psi_b + phi_p - pi + a_s)`` and
    ``s_r = r_bp (a_r - c + psi_b - phi_p) - rho_Ar`` (mod p_b), rho_A the pinions' start rolls,
    so that

        Delta_rs = s_r - s_s = s_bp - pi r_bp + r_bp (a_s + a_r) + rho_As - rho_Ar - a sin a_s

    (mod p_b), whatever the planet's angle: the planet's tooth count enters through pi r_bp =
    z_p p_b / 2 (half a pitch for an odd count), its thickness through s_bp.

    Args:
        geometry: the stage's two pairs (:func:`~jaxgear.planetary_geometry`).

    Returns:
        Delta_rs (m), a float in [0, p_b).
    """
    check_instance("geometry", geometry, PlanetaryGeometry, "a jaxgear.PlanetaryGeometry",
                   "sun_ring_offset")
    return float(np.mod(sun_ring_travel(geometry), float(geometry.planet_ring.base_pitch)))


def sun_ring_travel(geometry: PlanetaryGeometry) -> float:
    """Delta_rs before its reduction modulo p_b (m): for one planet tooth, how far its contact
    line on the ring mesh runs ahead of its contact line on the sun mesh (exact modulo a planet
    turn, z_p p_b: the tooth bookkeeping of :class:`~jaxgear.planetary.PlanetaryTeeth`)."""
    sp, pr = geometry.sun_planet, geometry.planet_ring
    r_bp = float(pr.base_radii[0])
    s_bp = float(sp.base_thickness[1])
    a_s, a_r = float(sp.operating_pressure_angle), float(pr.operating_pressure_angle)
    delta = (
        s_bp
        - math.pi * r_bp
        + r_bp * (a_s + a_r)
        + float(sp.start_roll)
        - float(pr.start_roll)
        - float(geometry.center_distance) * math.sin(a_s)
    )
    return float(delta)


def _check_stage(geometry: PlanetaryGeometry, planet_angles) -> np.ndarray:
    """The planet angles (rad, (n_planets,)) of a stage that assembles, whose planets' tip
    circles do not intersect (adjacent centres 2 a_w sin(Δψ/2) >= 2 r_ap apart,
    :func:`~jaxgear.planetary._stage.closest_planets`), its pairs of one base pitch; one line
    otherwise."""
    sp, pr = geometry.sun_planet, geometry.planet_ring
    psi = np.asarray(planet_angles, dtype=float)
    check_assembly(int(sp.pinion.teeth), -int(pr.gear.teeth), psi)
    if psi.size > 1:
        r_a = float(sp.tip_radii[1])
        i, j, d = closest_planets(psi, float(geometry.center_distance))
        if d < 2.0 * r_a:
            raise ValueError(
                f"ContactMeshes: planets {i + 1} and {j + 1} (planet_angles {psi[i]:.6g}, "
                f"{psi[j]:.6g} rad) overlap: their centres are {d:.6g} m apart, allowed >= 2 x "
                f"the planet's tip radius = {2.0 * r_a:.6g} m (their tip circles must not "
                "intersect)"
            )
    if not math.isclose(float(sp.base_pitch), float(pr.base_pitch), rel_tol=1e-9):
        raise ValueError(
            f"ContactMeshes: the base pitches differ ({float(sp.base_pitch)!r} m, "
            f"{float(pr.base_pitch)!r} m): allowed one module and pressure angle"
        )
    return psi


def structure_stiffness(model: AbstractPlanetaryModel, stage: PlanetaryStage):
    """K_b (N/m, (n_dof, n_dof)): the model's stiffness without the meshes (bearings, pins,
    torsional supports); the meshes come from the cells."""
    if not model.contact_solve:
        raise ValueError(
            f"{type(model).__name__}: not in the contact solve nor the dynamics yet (allowed "
            "PlanarPlanetary, TorsionalPlanetary)"
        )
    zero = jnp.zeros((), dtype=stage.planet_angles.dtype)
    bare = eqx.tree_at(
        lambda s: (s.sun_mesh_stiffness, s.ring_mesh_stiffness), stage, (zero, zero)
    )
    return model.stiffness_matrix(bare)


class AbstractPlanetaryMeshes(eqx.Module):
    """How the 2N meshes of a stage are represented: contact cells at each mesh travel x (m).

    The cells are ordered mesh after mesh: the N sun–planet meshes (planets 1..N), then the N
    ring–planet meshes. ``one_period`` (class constant): whether the cells repeat every mesh
    period (what the dynamics assume, laying out one period's rows).
    """

    one_period: ClassVar[bool] = True

    @abc.abstractmethod
    def cell_row(self, model, stage, x, offsets) -> CellRow:
        """The cells of the 2N meshes at the mesh travel ``x`` (m) on all coordinates: structure
        vectors (c, n_dof), stiffness per length, length, delta0 and mask (c,). ``offsets``:
        (d_s, d_r), each (n_planets,): transverse mesh-deflection offsets (m) that the pin
        errors add (compression positive)."""

    @abc.abstractmethod
    def mesh_period(self) -> Float[Array, ""]:
        """p_b (m): the mesh travel of one mesh period."""

    def other_flanks(self) -> AbstractPlanetaryMeshes:
        """The meshes with the load on the other flanks (the planets driving the sun); the
        default, for meshes that do not depend on where the contact lines are (ConstantMeshes):
        the same meshes. Meshes whose phasing depends on the loaded flanks override it
        (:meth:`ContactMeshes.other_flanks`); a kind that cannot raises ``ValueError``."""
        return self

    @abc.abstractmethod
    def mesh_forces(self, forces) -> Float[Array, "... 2n"]:
        """Transverse mesh forces (N, compression positive), (..., 2N), from the cell forces
        ``forces`` (N, (..., c)): sun meshes then ring meshes (the cells' normal forces times
        cos beta_b)."""

    def ring_rows(self, stage, x, cells: int) -> Float[Array, "n c"]:
        """(n_planets, c) at the mesh travel ``x`` (m), for ``cells`` cells: how each ring
        mesh's ring displacement along its force (the flexible ring's coordinates,
        :meth:`~jaxgear.planetary.AbstractRingModel.augment`) enters the cells' rows, per metre
        (-): the transverse ring-mesh force of each planet per cell force (:meth:`mesh_forces`
        is linear; cos β_b on that planet's ring cells), the cells' forces on the ring by the
        same rows."""
        n = stage.n_planets
        return jax.jacobian(lambda f: self.mesh_forces(f)[n:])(
            jnp.zeros(cells, jnp.result_type(x, float)))

    @abc.abstractmethod
    def mesh_stiffness(self, model, stage, positions) -> tuple[Array, Array]:
        """(k_s, k_r): each mesh's transverse stiffness on its line of action (N/m, the cells
        in contact on the flanks, rigid teeth otherwise: cos^2 beta_b sum k l) at each mesh
        travel ``positions`` (m, (p,)), each (p, n_planets): k_sn(x), k_rn(x) of every planet,
        phased."""

    def face_positions(self, stage):
        """(z, b): each cell's axial position across the face (m from the mesh mid-plane, along
        the stage axis), (c,), and each mesh's face width (m), (2N,); None where the kind does
        not place its cells across the face (then no face load factor is reported)."""
        return None

    def te_offsets(self, stage, x) -> tuple[Array, Array]:
        """(o_s, o_r): what each mesh's transmission error leaves out at the mesh travel ``x``
        (m, transverse, (n_planets,) each): 0 here; the per-tooth deviations' material on the
        teeth in contact for :class:`~jaxgear.planetary.DeviationMeshes` (the pair's TE less max e)."""
        zero = jnp.zeros((stage.n_planets,), jnp.result_type(x, float))
        return zero, zero

    def positions(self, per_period: int, periods: int = 1) -> Float[Array, " p"]:
        """Mesh travels x (m) at the mid-points of ``per_period`` equal steps per mesh period,
        over ``periods`` periods."""
        check_integer("per_period", per_period, 1)
        check_integer("periods", periods, 1)
        p_b = self.mesh_period()
        k = jnp.arange(per_period * periods, dtype=jnp.result_type(p_b)) + 0.5
        return k * p_b / per_period


class ConstantMeshes(AbstractPlanetaryMeshes):
    """The stage's own constant mesh stiffnesses as one unilateral spring per mesh (the lumped
    form of Lin & Parker 1999): with every mesh loaded, :func:`planetary_quasi_static` is
    :func:`~jaxgear.planetary.load_sharing` at every position.

    Attributes:
        base_pitch: p_b (m), the mesh travel of one period (it sets only the time scale of the
            dynamics).
        face_points: static, the Gauss-Legendre points across the stage's face width at which
            each spring acts (weights summing to 1; default 1: at mid-face). The 3D model
            (:class:`~jaxgear.planetary.SpatialPlanetary`) needs 2 for its meshes' tilting stiffness
            (its matrix's two points, across
            :meth:`~jaxgear.planetary.PlanetaryStage.mesh_face_widths`); the planar and torsional
            models see the same deflection across the face. A model whose springs act along the
            tooth normal (``model.spring_cos`` = cos beta_b) has its cells carry k cos^2 beta_b on
            the transverse deflection, so that the forces are transverse.
    """

    base_pitch: Float[Array, ""] = eqx.field(converter=as_float, default=0.01)
    face_points: int = eqx.field(static=True, default=1)

    def __check_init__(self):
        check_real("base_pitch", self.base_pitch, "m", lo=0.0, lo_open=True, shape=(),
                   where="ConstantMeshes")
        check_integer("face_points", self.face_points, 1)

    def _gauss(self, stage):
        """The Gauss-Legendre points across each mesh's spread width (m from the mid-plane,
        (face_points, 2N), sun meshes then ring) and their weights, summing to 1."""
        z, w = np.polynomial.legendre.leggauss(self.face_points)
        return (0.5 * jnp.asarray(z)[:, None] * jnp.concatenate(stage.mesh_face_widths())[None],
                jnp.asarray(0.5 * w))

    def cell_row(self, model, stage, x, offsets):
        # one cell per mesh and face point, point after point; the spring k acts on c times
        # the transverse deflection (model.spring_cos): the cells carry it as k c^2 on the
        # transverse deflection, so that their forces are the transverse mesh forces
        (v_s, w_s), (v_r, w_r) = model.face_rows(stage)
        k_s, k_r = stage.mesh_stiffnesses()
        d_s, d_r = offsets
        z, weight = self._gauss(stage)
        V0, W = jnp.concatenate([v_s, v_r]), jnp.concatenate([w_s, w_r])
        V = (V0[None] + z[:, :, None] * W[None]).reshape(-1, V0.shape[-1])
        k = jnp.concatenate([k_s, k_r]) * model.spring_cos(stage) ** 2
        k = (weight[:, None] * k[None]).reshape(-1)
        d0 = jnp.tile(-jnp.concatenate([d_s, d_r]), self.face_points)
        return CellRow(None, V, k, jnp.ones_like(k), d0, jnp.ones(k.shape, bool))

    def mesh_period(self):
        return self.base_pitch

    def mesh_stiffness(self, model, stage, positions):
        k_s, k_r = stage.mesh_stiffnesses()
        p = (jnp.size(positions), stage.n_planets)
        c2 = model.spring_cos(stage) ** 2
        return jnp.broadcast_to(k_s * c2, p), jnp.broadcast_to(k_r * c2, p)

    def mesh_forces(self, forces):
        return forces.reshape(forces.shape[:-1] + (self.face_points, -1)).sum(-2)

    def face_positions(self, stage):
        return (self._gauss(stage)[0].reshape(-1),
                jnp.broadcast_to(stage.face_width, (2 * stage.n_planets,)))


def _hand(stage):
    """+1 for right-hand planets (the stage's helix_angle >= 0), -1 for left-hand: the pairs lay
    their contact lines out as s = roll - z |tan beta_b| (z from the face's side), which in the
    stage's frame runs along +e_z for right-hand planets and along -e_z for left-hand ones (the
    lines lie in the plane of action perpendicular to the tooth normal)."""
    return jnp.where(stage.helix_angle < 0, -1.0, 1.0)


class ContactMeshes(AbstractPlanetaryMeshes):
    """The 2N meshes from real contact: the sun–planet pair's and the planet–ring pair's cells
    (:class:`~jaxgear.MeshModel`), with their modifications, phased per planet.

    Build with :meth:`from_geometry`.

    Attributes:
        sun_mesh: the sun–planet mesh (pinion: the sun). ring_mesh: the planet–ring mesh
            (pinion: the planet). Both must have the same base pitch.
        sun_modifications, ring_modifications: their flank modifications (no per-tooth
            deviations: a pair's deviations do not follow the stage's teeth; the stage's
            are :class:`~jaxgear.planetary.DeviationMeshes`).
        sun_phases, ring_phases: gamma_sn, gamma_rn (fractions of a mesh period), (n_planets,)
            (:func:`~jaxgear.planetary.mesh_phases`).
        ring_offset: Delta_rs (m), :func:`sun_ring_offset`.
        pitch_points: (2,): where each pair's transverse pitch point sits on its path of
            contact (m, s from the pair's engagement point: the pinion's roll r_b1 tan a_w less
            its start roll), the sun pair's then the ring pair's; a cell at s lies
            s - pitch_point along the line of action from the pitch point (the 3D model's
            moment arms, ``model.line_rows``).
    """

    sun_mesh: MeshModel
    ring_mesh: MeshModel
    sun_modifications: Modifications
    ring_modifications: Modifications
    sun_phases: Float[Array, " n_planets"] = eqx.field(converter=as_float)
    ring_phases: Float[Array, " n_planets"] = eqx.field(converter=as_float)
    ring_offset: Float[Array, ""] = eqx.field(converter=as_float)
    pitch_points: Float[Array, " 2"] = eqx.field(converter=as_float)

    def __check_init__(self):
        for name in ("sun_mesh", "ring_mesh"):
            check_instance(name, getattr(self, name), MeshModel, "a jaxgear.MeshModel",
                           "ContactMeshes")
        for name in ("sun_modifications", "ring_modifications"):
            mods = getattr(self, name)
            check_instance(name, mods, Modifications, "a jaxgear.Modifications", "ContactMeshes")
            if mods.deviations is not None:
                raise ValueError(
                    f"ContactMeshes: {name}.deviations is set: a pair's deviations do not "
                    "follow a stage's teeth (allowed None; jaxgear.planetary.DeviationMeshes takes "
                    "every sun, planet and ring tooth's)"
                )
        if self.sun_mesh.coast or self.ring_mesh.coast:
            raise ValueError("ContactMeshes: coast flanks are not modelled (allowed coast=False)")

    @classmethod
    def from_geometry(
        cls,
        geometry: PlanetaryGeometry,
        planet_angles,
        stiffness: AbstractStiffness,
        n_slices: int = 1,
        modifications: tuple[Modifications, Modifications] | None = None,
        contact_geometry: AbstractContactGeometry = TheoreticalPath(),
        **table,
    ) -> ContactMeshes:
        """The meshes of the stage ``geometry`` with planets at ``planet_angles`` (rad,
        (n_planets,), assembly checked), both tables from ``stiffness`` and the same keywords
        ``table`` (:func:`~jaxgear.stiffness_table`), ``n_slices`` slices per contact line,
        ``modifications`` (sun pair's, ring pair's; None: none), both meshes' cells laid out
        on ``contact_geometry`` (:meth:`jaxgear.MeshModel.from_pair`'s: the theoretical path by
        default, as there; :class:`~jaxgear.BeyondPath` as a case file's default ``[mesh]
        extended_contact``). Each mesh at its own load (a case's pairs,
        :meth:`jaxgear.io.Case.mesh_model`): :meth:`from_models`.

        Raises:
            ValueError: planets that cannot be assembled or whose tip circles overlap, a bad
                stiffness model for internal teeth, or the pairs' base pitches different (one
                line each).
        """
        check_instance("geometry", geometry, PlanetaryGeometry, "a jaxgear.PlanetaryGeometry",
                       "ContactMeshes.from_geometry")
        _check_stage(geometry, planet_angles)
        meshes = tuple(MeshModel.from_pair(p, *stiffness_table(p, stiffness, **table), n_slices,
                                           contact_geometry=contact_geometry)
                       for p in (geometry.sun_planet, geometry.planet_ring))
        return cls.from_models(geometry, planet_angles, meshes, modifications)

    @classmethod
    def from_models(
        cls,
        geometry: PlanetaryGeometry,
        planet_angles,
        meshes: tuple[MeshModel, MeshModel],
        modifications: tuple[Modifications, Modifications] | None = None,
    ) -> ContactMeshes:
        """The meshes of the stage ``geometry`` with planets at ``planet_angles`` (rad,
        (n_planets,), assembly checked) from ready mesh models ``meshes`` (the sun pair's, the
        ring pair's :class:`~jaxgear.MeshModel`, built by :meth:`jaxgear.MeshModel.from_pair` on
        ``geometry.sun_planet`` and ``geometry.planet_ring``: their stiffness tables and slices
        as given) and ``modifications`` (sun pair's, ring pair's; None: none).

        Raises:
            ValueError: planets that cannot be assembled or whose tip circles overlap, the
                pairs' base pitches different, a
                model whose pinion base radius or path of contact is not its pair's (one line).
        """
        where = "ContactMeshes.from_models"
        check_instance("geometry", geometry, PlanetaryGeometry, "a jaxgear.PlanetaryGeometry",
                       where)
        psi = _check_stage(geometry, planet_angles)
        sp, pr = geometry.sun_planet, geometry.planet_ring
        if len(meshes) != 2:
            raise ValueError(f"{where}: meshes has {len(meshes)} entries: allowed 2 (sun, ring)")
        for i, (mesh, pair) in enumerate(zip(meshes, (sp, pr), strict=True)):
            check_instance(f"meshes[{i}]", mesh, MeshModel, "a jaxgear.MeshModel", where)
            for field, want in (("base_radius_pinion", float(pair.base_radii[0])),
                                ("path_of_contact", float(pair.path_of_contact))):
                got = float(getattr(mesh, field))
                if not math.isclose(got, want, rel_tol=1e-6):
                    raise ValueError(f"{where}: meshes[{i}].{field} = {got!r} m: allowed its "
                                     f"pair's {want!r} m (another pair's model)")
        mods = (Modifications(), Modifications()) if modifications is None else modifications
        g_s, g_r = mesh_phases(int(sp.pinion.teeth), -int(pr.gear.teeth), psi)
        pitch = [float(p.base_radii[0]) * math.tan(float(p.operating_pressure_angle))
                 - float(p.start_roll) for p in (sp, pr)]
        return cls(meshes[0], meshes[1], mods[0], mods[1], g_s, g_r, sun_ring_offset(geometry),
                   pitch)

    def mesh_period(self):
        return self.sun_mesh.base_pitch

    def _extended(self) -> bool:
        """Whether a mesh has cells beyond the theoretical path (the corner rows and the free
        drive modes are then needed)."""
        return any(
            m.contact_geometry.reaches_beyond_path for m in (self.sun_mesh, self.ring_mesh)
        )

    def other_flanks(self) -> ContactMeshes:
        """The meshes with the load on the other flanks: the planets driving the sun (carrier
        in and sun out, ring held; or the sun's torque reversed), where :meth:`from_geometry`
        loads the flanks the sun drives.

        For teeth whose two flanks are alike (symmetric tooth form and modifications), the
        other-flank picture is the drive-flank one mirrored and run backwards in time, which
        maps every contact line's s (from its engagement point) to g - s, g the pair's path of
        contact: each mesh's stiffness pattern and the planets' phases gamma_sn, gamma_rn keep
        their form, and only the sun–ring offset within a planet changes,

            Delta_rs' = g_r - g_s - Delta_rs   (mod p_b),

        (checked against a direct derivation on the loaded flanks, the independent two-stage
        reference of docs/gearbox.md: 6.4751 mm = 0.5483 p_b for its 20/30/80 stage, against
        9.2638 mm with the sun driving). The cells keep their drive-flank rows; the
        caller flips their sign (the force along the other line of action). Asymmetric
        modifications are not mirrored (the drive flank's stand for the other's)."""
        g_s, g_r = self.sun_mesh.path_of_contact, self.ring_mesh.path_of_contact
        offset = jnp.mod(g_r - g_s - self.ring_offset, self.mesh_period())
        return eqx.tree_at(lambda m: m.ring_offset, self, offset)

    def mesh_stiffness(self, model, stage, positions):
        zero = jnp.zeros((stage.n_planets,), dtype=self.ring_offset.dtype)
        path = on_the_path(self)  # unloaded: the cells on the theoretical path (extended_contact)

        def one(x):
            row = path.cell_row(model, stage, x, (zero, zero))
            return self.mesh_forces(jnp.where(row.mask, row.k * row.length, 0.0))

        k = jnp.cos(self.sun_mesh.base_helix_angle) * jax.vmap(one)(as_float(positions))
        n = stage.n_planets
        return k[:, :n], k[:, n:]

    def mesh_forces(self, forces):
        f_s, f_r = (f.sum(axis=(-2, -1)) for f in self.split_cells(forces))
        return jnp.cos(self.sun_mesh.base_helix_angle) * jnp.concatenate([f_s, f_r], axis=-1)

    def ring_rows(self, stage, x, cells):
        """:meth:`AbstractPlanetaryMeshes.ring_rows`; beyond the path a ring corner cell's
        entry carries the factor c of its rotation entries (:func:`rolling_lever`):
        the ring's turning on its stations is its rotation there, so that the ring mesh's
        rolling with the ring turning on its housing moves no corner gap either."""
        rows = super().ring_rows(stage, x, cells)
        if not self.ring_mesh.contact_geometry.reaches_beyond_path:
            return rows
        cells_r = self.planet_cells(x)[1][0]
        lever_driving, lever_driven, *_ = self.ring_mesh.corner(cells_r.s)
        factor = rolling_lever(lever_driving, lever_driven, self._radii()[1]).reshape(-1)
        factor = jnp.concatenate([jnp.ones(cells - factor.shape[0], factor.dtype), factor])
        return rows * factor[None, :]

    def _radii(self) -> tuple:
        """Each mesh's signed base radii (r_b1, r_b2) (m): the sun's and the planet's, the
        planet's and minus the ring's (an internal gear)."""
        return ((self.sun_mesh.base_radius_pinion, self.sun_mesh.base_radius_gear),
                (self.ring_mesh.base_radius_pinion, -self.ring_mesh.base_radius_gear))

    def split_cells(self, values) -> tuple[Array, Array]:
        """A per-cell array of the stage's cell rows (..., c) (:meth:`cell_row`'s order: every
        planet's sun-mesh cells, then every planet's ring-mesh cells, each mesh's
        (n_lines, n_slices) read row by row; e.g. :attr:`PlanetaryQuasiStatic.cell_line_load`)
        split into the sun meshes' (..., n_planets, n_lines, n_slices) and the ring meshes'."""
        n = self.sun_phases.shape[0]
        c_s = n * self.sun_mesh.n_lines * self.sun_mesh.n_slices
        lead = values.shape[:-1]
        return tuple(
            part.reshape(lead + (n, mesh.n_lines, mesh.n_slices))
            for part, mesh in ((values[..., :c_s], self.sun_mesh),
                               (values[..., c_s:], self.ring_mesh))
        )

    def planet_cells(self, x) -> tuple[tuple[Cells, Array], tuple[Cells, Array]]:
        """Every planet's cells at the mesh travel ``x`` (m, a scalar): ((cells, δ0) of the sun
        meshes, (cells, δ0) of the ring meshes), each field of shape (n_planets, n_lines,
        n_slices): each pair's :class:`~jaxgear.Cells` at the planet's mesh angle (module
        docstring: the phases gamma_sn, gamma_rn and the sun–ring offset) with its
        modifications' initial separation δ0 (m)."""
        p_b = self.sun_mesh.base_pitch
        t_s = (x - self.sun_phases * p_b) / self.sun_mesh.base_radius_pinion
        t_r = (x + self.ring_offset - self.ring_phases * p_b) / self.ring_mesh.base_radius_pinion
        out = []
        for mesh, mods, theta in ((self.sun_mesh, self.sun_modifications, t_s),
                                  (self.ring_mesh, self.ring_modifications, t_r)):
            cells, _, delta0 = jax.vmap(lambda t, mesh=mesh, mods=mods: separation(mesh, mods, t))(
                theta
            )
            out.append((cells, delta0))
        return tuple(out)

    def face_positions(self, stage):
        z = []
        for mesh in (self.sun_mesh, self.ring_mesh):
            cells_z = mesh.cells(jnp.zeros_like(mesh.face_width)).z
            across = _hand(stage) * (cells_z - 0.5 * mesh.face_width)
            z.append(jnp.tile(across.reshape(-1), stage.n_planets))
        n = (stage.n_planets,)
        b = jnp.concatenate([jnp.broadcast_to(m.face_width, n)
                             for m in (self.sun_mesh, self.ring_mesh)])
        return jnp.concatenate(z), b

    def cell_row(self, model, stage, x, offsets):
        (cells_s, d0_s), (cells_r, d0_r) = self.planet_cells(x)
        # the transverse deflection at each cell's contact point (the cells' z runs along the
        # stage axis from the face's side at z = 0, against it for left-hand planets; their s
        # along the path of contact): (V + (z - b/2) W + (s - s_pitch) X) q
        rows_s, rows_r = model.face_rows(stage)
        x_s, x_r = model.line_rows(stage)
        d_s, d_r = offsets
        corner = model.corner_rows(stage) if self._extended() else (None, None)
        drive = _drive_modes(model, stage) if self._extended() else None
        parts = []
        for mesh, cells, delta0, (v, w), x_line, pitch, d, rows, radii in (
            (self.sun_mesh, cells_s, d0_s, rows_s, x_s, self.pitch_points[0], d_s, corner[0],
             self._radii()[0]),
            (self.ring_mesh, cells_r, d0_r, rows_r, x_r, self.pitch_points[1], d_r, corner[1],
             self._radii()[1]),
        ):
            cb = jnp.cos(mesh.base_helix_angle)
            # (n_lines, n_slices), every planet's; mirrored for left-hand planets
            across = _hand(stage) * (cells.z[0] - 0.5 * mesh.face_width)
            along = cells.s - pitch  # (n_planets, n_lines, n_slices)
            V = cb * (v[:, None, None, :] + across[None, :, :, None] * w[:, None, None, :]
                      + along[..., None] * x_line[:, None, None, :])
            # the corner cells' geometry (docs/extended-contact.md), less their part along the
            # stage's free drive rotation (_drive_modes)
            V = mesh.contact_geometry.beyond_path_vectors(
                mesh, cells.s, V,
                lambda V: V - (V @ drive[0]) @ drive[1].T,
                lambda mesh=mesh, cells=cells, rows=rows, cb=cb, radii=radii: cb
                * _corner_terms(mesh, cells, rows, radii),
            )
            d0 = jnp.where(cells.mask, delta0 - cb * d[:, None, None], 0.0)
            parts.append((V.reshape(-1, v.shape[-1]), cells.stiffness.reshape(-1),
                          cells.length.reshape(-1), d0.reshape(-1), cells.mask.reshape(-1)))
        return CellRow(None, *(jnp.concatenate(f) for f in zip(*parts, strict=True)))


def _drive_modes(model, stage) -> tuple:
    """(Φ_r, M Φ_r), each (n_dof, n_dof): the stage's rigid-body modes (the free drive rotation
    of a stage whose sun and carrier turn freely, the ring held), mass-normalised (Φᵀ M Φ = I)
    in the model's coordinates, other columns zero: the modes of K (the stage's constant mesh
    springs) and M with ω² ≤ 1e-9 of the largest (the rule of
    :class:`~jaxgear.planetary.PlanetaryModes`). A corner cell's row beyond the theoretical path
    drops its part along them, V − (V Φ_r)(M Φ_r)ᵀ, so that V·φ = 0 for every rigid mode φ (the
    rule the lumped and hybrid scenes follow, :meth:`jaxgear.scenes.AssembledScene._free_drive`;
    docs/extended-contact.md, "The free drive rotation"): the corner's gap changes as the
    stage turns as a whole, and without this step the corners would give the drive rotation a
    weak positional stiffness. The modes are held constant under differentiation
    (``stop_gradient``: the rigid rotation's direction is the kinematics', and the eigenvector
    derivatives of the stage's repeated modes are not finite)."""
    K = model.stiffness_matrix(stage)
    M = model.mass_matrix(stage)
    L = jnp.linalg.cholesky(M)
    Li = jax.scipy.linalg.solve_triangular(L, jnp.eye(M.shape[0], dtype=M.dtype), lower=True)
    lam, Y = jnp.linalg.eigh(Li @ K @ Li.T)
    phi = Li.T @ Y
    rigid = lam <= 1e-9 * jnp.max(jnp.abs(lam))
    phi = jnp.where(rigid[None, :], phi, 0.0)
    return jax.lax.stop_gradient(phi), jax.lax.stop_gradient(M @ phi)


def _corner_terms(mesh, cells, rows, radii) -> Array:
    """What a corner cell beyond the theoretical path adds to its mesh row (n_planets, n_lines,
    n_slices, n_dof), before the factor cos β_b: the two members' rotation entries times c − 1
    (:func:`rolling_lever`; ``radii`` the pair's signed base radii) and the translation
    entries turned by ε (:meth:`~jaxgear.MeshModel.corner`, the rows of
    :meth:`AbstractPlanetaryModel.corner_rows`); zero on the path."""
    lever_driving, lever_driven, eps, _, _ = mesh.corner(cells.s)
    r_driving, r_driven, trans, perp = (r[:, None, None, :] for r in rows)
    c = rolling_lever(lever_driving, lever_driven, radii)
    return (
        (c - 1.0)[..., None] * (r_driving + r_driven)
        + (jnp.cos(eps) - 1.0)[..., None] * trans
        - jnp.sin(eps)[..., None] * perp
    )


class PlanetMeshLoads(NamedTuple):
    """One planet's one mesh of a stage's quasi-static solve or dynamic run, with the fields of
    a one-mesh result (what :func:`jaxgear.rating.transverse_load_factor` and
    :func:`jaxgear.rating.root_stress_map` read): ``line_load`` (N/m), ``cell_s``, ``cell_z``
    (m) and ``cell_mask``, each of shape (P, n_lines, n_slices) over the travels (or a dynamic
    run's kept steps); s, z in the mesh pair's base plane (the sun–planet
    :class:`~jaxgear.GearPair`, the planet–ring :class:`~jaxgear.InternalGearPair`);
    ``cell_length`` (m, the cells' lengths along their contact lines: line load × length is the
    cell's force, N) or None. Built by :func:`planet_mesh_loads`."""

    line_load: np.ndarray
    cell_s: np.ndarray
    cell_z: np.ndarray
    cell_mask: np.ndarray
    cell_length: np.ndarray | None = None

    def tooth_force(self) -> float:
        """The largest force of one tooth pair over the travels (N, flank-normal: its
        contact line's cells' forces summed across the face)."""
        f = np.where(self.cell_mask, self.line_load * self.cell_length, 0.0)
        return float(np.max(np.sum(f, axis=-1)))


@eqx.filter_jit
def _planet_cells(meshes, x):
    """``meshes.planet_cells`` at every travel of ``x`` (one compiled program: eagerly, its
    vmap costs seconds of dispatch)."""
    return jax.vmap(meshes.planet_cells)(x)


def planet_mesh_loads(meshes, travel, cell_values, *, per_length: bool = False) -> tuple:
    """Every planet's sun-mesh and ring-mesh cell loads of a stage's solve, each placed on its
    own mesh's cells: (sun/planet, planet/ring), each a tuple of one :class:`PlanetMeshLoads`
    per planet.

    Args:
        meshes: the solve's meshes kind with cells (:class:`ContactMeshes`: its
            ``planet_cells`` place each planet's cells at a travel, its ``split_cells`` splits
            the cell rows).
        travel: the mesh travels x (m), (P,), of the solve's positions or a run's kept steps.
        cell_values: (P, c) per cell row (:meth:`ContactMeshes.cell_row`'s order): line loads
            (N/m, :attr:`PlanetaryQuasiStatic.cell_line_load`), or with ``per_length`` the
            cells' forces (N, a dynamic run's ``cell_forces``), divided here by their lengths
            (0 where a cell is off the flank or of no length).

    Returns:
        ((PlanetMeshLoads of planet 1..N of the sun meshes), (… of the ring meshes))."""
    kinds = []
    for (cells, _), w in zip(_planet_cells(meshes, travel), meshes.split_cells(cell_values),
                             strict=True):
        w, s, z, m, c = (np.asarray(a) for a in (w, cells.s, cells.z, cells.mask, cells.length))
        if per_length:
            w = np.where(m & (c > 0), w / np.where(c > 0, c, 1.0), 0.0)
        kinds.append(tuple(PlanetMeshLoads(w[:, i], s[:, i], z[:, i], m[:, i], c[:, i])
                           for i in range(w.shape[1])))
    return tuple(kinds)


#: positions per mesh period at which :func:`lumped_mesh_stiffness` solves a mesh
LUMPED_STIFFNESS_POSITIONS = 16


def lumped_mesh_stiffness(
    mesh: MeshModel,
    modifications: Modifications | None,
    torque,
    *,
    positions_per_pitch: int = LUMPED_STIFFNESS_POSITIONS,
) -> float:
    """The constant stiffness a lumped planetary model takes for one of the stage's meshes (a
    sun–planet or a planet–ring mesh): the mean over one mesh period of the mesh's quasi-static
    stiffness K(θ) = Σ k l over its loaded cells (:func:`jaxgear.quasi_static` on the rigid
    mesh, exact contact, ``positions_per_pitch`` positions), at the driving member's torque of
    one planet path (the mean planet load).

    Args:
        mesh: the mesh's :class:`~jaxgear.MeshModel` (a :class:`~jaxgear.GearPair`'s or an
            :class:`~jaxgear.InternalGearPair`'s, jaxgear's stiffness model).
        modifications: its flank modifications (``None``: perfect involutes).
        torque: the driving member's torque on that mesh (N·m, > 0): T_s/N for the sun mesh,
            the planet's share for the ring mesh.
        positions_per_pitch: positions over the mesh period (>= 1).

    Returns:
        k (N/m), flank-normal in the base plane; for rigid spur teeth of uniform stiffness k0
        per unit length on the theoretical path k0 b ε_α (to one position's share).

    Raises:
        ValueError: what :func:`jaxgear.quasi_static` raises for its inputs (one line).
    """
    r = quasi_static(mesh, modifications, torque, positions_per_pitch=positions_per_pitch)
    return float(np.mean(np.asarray(r.mesh_stiffness)))


@eqx.filter_jit
def planetary_mesh_stiffness(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    positions: Float[Array, " p"],
) -> tuple[Float[Array, "p n"], Float[Array, "p n"]]:
    """k_sn(x), k_rn(x): every planet's sun-mesh and ring-mesh stiffness (N/m, transverse, on
    the line of action) at each mesh travel x (m, (p,); ``meshes.positions(per_period,
    periods)`` for a mesh period or a hunting period), phased per planet (Parker & Lin 2004) and
    within a planet (:func:`sun_ring_offset`): jaxgear's stiffness model over the cells on the
    flanks, with rigid teeth otherwise (cos^2 beta_b sum k l; the load-dependent stiffness is
    :func:`planetary_quasi_static`'s). Each (p, n_planets)."""
    check_instance("meshes", meshes, AbstractPlanetaryMeshes, "a planetary meshes kind",
                   "planetary_mesh_stiffness")
    return meshes.mesh_stiffness(model, stage, positions)


class PlanetaryQuasiStatic(eqx.Module):
    """The stage's quasi-static state at each mesh position (unilateral contact of the cells).

    Attributes:
        travel: mesh travel x (m), (p,): the sun's rotation relative to the carrier times r_bs.
        displacement: coordinates (m), (p, n_dof).
        sun_mesh_forces, ring_mesh_forces: transverse force on each planet's meshes (N,
            compression positive), (p, n_planets).
        sun_te, ring_te: each mesh's transmission error, its transverse deflection V q + d (m,
            compression positive, the pin errors' offsets d included; mid-face, the 3D model's
            normal deflection over cos beta_b), (p, n_planets); with per-tooth deviations
            (:class:`~jaxgear.planetary.DeviationMeshes`) less their largest material on the cells in
            contact over cos beta_b, as a pair's TE (u X - max e) / cos beta_b.
        k_gamma: the mesh load factor at each position (ISO 6336-1, AGMA 6123): the most
            loaded planet's sun-mesh force over their mean, (p,).
        result: the contact solver's code at each position (0: converged), (p,).
        ring_deflection: the flexible ring's elastic displacement at each ring mesh along its
            force (m, relieving the mesh), (p, n_planets); zero for a rigid ring.
        face_moments: the first moment of each mesh's transverse force across the face,
            sum z F (N m; z the cells' axial positions from the mesh mid-plane, along the stage
            axis), (p, 2N): sun meshes, then ring meshes; None where the meshes kind does not
            place its cells across the face. face_widths: the meshes' face widths b (m), (2N,)
            (None with it).
        cell_line_load: each cell's line load (N/m, the contact solution's force per unit
            contact length, 0 off contact), (p, c) in the order of the meshes kind's cell rows
            (:class:`ContactMeshes`: split per mesh and planet by
            :meth:`ContactMeshes.split_cells`, placed by :meth:`ContactMeshes.planet_cells`).
    """

    travel: Float[Array, " p"]
    displacement: Float[Array, "p n_dof"]
    sun_mesh_forces: Float[Array, "p n"]
    ring_mesh_forces: Float[Array, "p n"]
    sun_te: Float[Array, "p n"]
    ring_te: Float[Array, "p n"]
    k_gamma: Float[Array, " p"]
    result: Array
    ring_deflection: Float[Array, "p n"] | None = None
    face_moments: Float[Array, "p 2n"] | None = None
    face_widths: Float[Array, " 2n"] | None = None
    cell_line_load: Float[Array, "p c"] | None = None

    @property
    def k_h_beta(self) -> Float[Array, " 2n"] | None:
        """Each mesh's face load factor K_Hbeta (sun meshes, then ring meshes), (2N,), of its
        mean line load distribution over the positions (a mesh period, or a hunting period:
        the positions taken evenly), on ISO 6336-1's linear distribution
        (:func:`face_load_factor`, from the mean force and mean first moment); None without
        ``face_moments``."""
        if self.face_moments is None:
            return None
        f = jnp.concatenate([self.sun_mesh_forces, self.ring_mesh_forces], axis=-1)
        return face_load_factor(jnp.mean(f, axis=0), jnp.mean(self.face_moments, axis=0),
                                self.face_widths)

    @property
    def k_gamma_max(self) -> Float[Array, ""]:
        """K_gamma over the positions: the largest."""
        return jnp.max(self.k_gamma)


def pin_terms(model, stage, tangential_pin_errors, radial_pin_errors, where: str, travel=0.0):
    """(f, d_s, d_r) of the pin errors and the stage's eccentricities at the mesh travel
    ``travel`` (m) for the cells, after the shape checks (one-line errors naming the argument):
    the offsets d_s, d_r of :meth:`~jaxgear.planetary.AbstractPlanetaryModel.error_terms` made
    transverse (over ``model.spring_cos``) and its load f
    without the meshes' share (the torsional model's f is -V^T k d, the constant meshes'
    reaction to the offsets, which the cells make themselves: f + V_s^T k_s d_s + V_r^T k_r d_r
    is the pins' share; it does not depend on the travel, the offsets do)."""
    n = stage.n_planets
    for name, value in (("tangential_pin_errors", tangential_pin_errors),
                        ("radial_pin_errors", radial_pin_errors)):
        check_real(name, value, "m", where=where)
        if jnp.size(value) not in (1, n) or jnp.ndim(value) > 1:
            raise ValueError(f"{where}: {name} must have shape () or ({n},), got "
                             f"{jnp.shape(value)}")
    e = jnp.broadcast_to(as_float(tangential_pin_errors), (n,))
    eps = jnp.broadcast_to(as_float(radial_pin_errors), (n,))
    f, d_s, d_r = model.error_terms(stage, e, eps, travel)
    v_s, v_r = model.mesh_deflection_rows(stage)
    k_s, k_r = stage.mesh_stiffnesses()
    # the cells take transverse offsets: error_terms' are on the model's mesh deflections
    # (the 3D model's along the tooth normal, spring_cos times the transverse ones)
    c = model.spring_cos(stage)
    return f + v_s.T @ (k_s * d_s) + v_r.T @ (k_r * d_r), d_s / c, d_r / c


#: the spring (relative to the mean mesh stiffness) that holds a planet's rotation when both its
#: meshes open (else the stiffness is singular there); it changes the forces by ~1e-12
FLOATING_PLANET = 1e-12


def held_structure(model, stage, meshes, offsets):
    """K_b (:func:`structure_stiffness`) with the planets' rotations held by
    :data:`FLOATING_PLANET` times the meshes' mean stiffness (one cell row at x = 0)."""
    k_b = structure_stiffness(model, stage)
    row = meshes.cell_row(model, stage, jnp.zeros_like(meshes.mesh_period()), offsets)
    kl = jnp.where(row.mask, row.k * row.length, 0.0)
    scale = jnp.sum(kl * jnp.sum(row.V**2, axis=-1)) / (2 * stage.n_planets)
    names = model.dof_names(stage)
    idx = jnp.array([names.index(f"u_{i + 1}") for i in range(stage.n_planets)])
    return k_b.at[idx, idx].add(FLOATING_PLANET * scale)


def sun_load(model, stage, sun_torque, f_err):
    """The load vector (N): the pin errors' ``f_err`` plus the sun torque (N m, positive
    counter-clockwise) on u_s."""
    i = model.dof_names(stage).index("u_s")
    return f_err.at[i].add(as_float(sun_torque) / stage.sun.base_radius)


def planetary_quasi_static(
    model: AbstractPlanetaryModel,
    stage: PlanetaryStage,
    meshes: AbstractPlanetaryMeshes,
    sun_torque: Float[Array, ""],
    positions: Float[Array, " p"],
    tangential_pin_errors: Float[Array, "*n"] | float = 0.0,
    radial_pin_errors: Float[Array, "*n"] | float = 0.0,
    law: AbstractContactLaw = ExactContact(),
    ring: AbstractRingModel = RigidRing(),
) -> PlanetaryQuasiStatic:
    """The stage's quasi-static state at each mesh travel: ``K_b q + V^T P = f`` with the
    unilateral contact of the 2N meshes' cells (a mesh may lose contact), K_b the bearings,
    pins and supports (:func:`structure_stiffness`; a planet whose meshes both open is held in
    rotation by :data:`FLOATING_PLANET`), f the sun torque and the pin errors' load.

    Args:
        model: the model kind (:class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.TorsionalPlanetary`).
        stage: the stage (its mesh stiffnesses are used only by :class:`ConstantMeshes`); the
            ring or the carrier must be held in rotation (else K_b + meshes is singular).
        meshes: :class:`ContactMeshes` (real pairs) or :class:`ConstantMeshes`.
        sun_torque: torque on the sun (N m), positive counter-clockwise (it loads the drive
            flanks of the sun meshes).
        positions: mesh travels x (m), (p,) (``meshes.positions(per_period, periods)``; over a
            hunting period: as many mesh periods as it holds).
        tangential_pin_errors, radial_pin_errors: planet-pin position errors (m), () or
            (n_planets,), as :func:`~jaxgear.planetary.load_sharing`; the stage's eccentricities
            (:class:`~jaxgear.planetary.Eccentricities`) are added at each position, turning with their
            members.
        law: the contact law.
        ring: the ring gear: :class:`~jaxgear.planetary.RigidRing` (the lumped ring, the default) or a
            flexible :class:`~jaxgear.planetary.CondensedRing`, whose compliance at the ring meshes
            follows the planets around it (its N displacements join the contact problem).

    Returns:
        :class:`PlanetaryQuasiStatic`.

    Raises:
        ValueError: pin errors of the wrong shape, a concrete ``sun_torque`` that is not a
            finite number > 0 (a negative one unloads the drive flanks) or ``positions`` not a
            (p,) array of finite travels (one line naming the argument; traced values are not
            checked).
    """
    where = "planetary_quasi_static"
    check_instance("meshes", meshes, AbstractPlanetaryMeshes, "a planetary meshes kind", where)
    check_real("sun_torque", sun_torque, "N·m", lo=0.0, lo_open=True, shape=(), where=where)
    check_real("positions", positions, "m", shape=(None,), shape_text="(p,)", where=where)
    check_instance("ring", ring, AbstractRingModel, "a jaxgear.planetary.RigidRing or CondensedRing",
                   "planetary_quasi_static")
    for name, value in (("tangential_pin_errors", tangential_pin_errors),
                        ("radial_pin_errors", radial_pin_errors)):
        check_real(name, value, "m", where=where)
    # checked: Python numbers enter the program as arrays (eqx.filter_jit holds a Python
    # number as a constant of the program, one program per value: a CLI run's torque)
    sun_torque, tangential_pin_errors, radial_pin_errors = (
        as_float(v) if isinstance(v, int | float) else v
        for v in (sun_torque, tangential_pin_errors, radial_pin_errors))
    return _planetary_quasi_static(model, stage, meshes, sun_torque, positions,
                                   tangential_pin_errors, radial_pin_errors, law, ring)


@eqx.filter_jit
def _planetary_quasi_static(model, stage, meshes, sun_torque, positions, tangential_pin_errors,
                            radial_pin_errors, law, ring) -> PlanetaryQuasiStatic:
    """:func:`planetary_quasi_static`'s program (the arguments checked there)."""
    f_err, d_s, d_r = pin_terms(model, stage, tangential_pin_errors, radial_pin_errors,
                                "planetary_quasi_static")
    f = sun_load(model, stage, sun_torque, f_err)
    k_b = held_structure(model, stage, meshes, (d_s, d_r))
    (v_s, _), (v_r, _) = model.face_rows(stage)  # the transverse deflections at mid-face
    n = stage.n_planets
    face = meshes.face_positions(stage)

    n_dof = k_b.shape[0]

    def one(x):
        # the sun's and ring's eccentricities turn with their members: offsets at x
        _, d_sx, d_rx = pin_terms(model, stage, tangential_pin_errors, radial_pin_errors,
                                  "planetary_quasi_static", x)
        row = meshes.cell_row(model, stage, x, (d_sx, d_rx))
        # the ring meshes' transverse force per cell force (mesh_forces is linear)
        ring_rows = meshes.ring_rows(stage, x, row.k.shape[0])
        K, fx, V = ring.augment(stage, k_b, f, row.V, ring_rows, x)
        sol = solve_contact(K, fx, V, row.k, row.length, row.delta0, row.mask, law)
        cell_forces = sol.force_density * row.length
        forces = meshes.mesh_forces(cell_forces)
        w = jnp.zeros(n, sol.x.dtype) if sol.x.shape[0] == n_dof else sol.x[n_dof:]
        moments = (jnp.zeros(0, forces.dtype) if face is None
                   else meshes.mesh_forces(cell_forces * face[0]))
        o_s, o_r = meshes.te_offsets(stage, x)  # material on the teeth in contact (0: none)
        return (sol.x[:n_dof], forces, sol.result, w, d_sx - o_s, d_rx - o_r, moments,
                sol.force_density)

    q, forces, result, w, d_s, d_r, moments, loads = jax.vmap(one)(as_float(positions))
    f_s, f_r = forces[:, :n], forces[:, n:]
    return PlanetaryQuasiStatic(
        travel=as_float(positions),
        displacement=q,
        sun_mesh_forces=f_s,
        ring_mesh_forces=f_r,
        sun_te=q @ v_s.T + d_s,
        ring_te=q @ v_r.T + d_r,
        k_gamma=jnp.max(f_s, axis=-1) / jnp.mean(f_s, axis=-1),
        result=result,
        ring_deflection=w,
        face_moments=None if face is None else moments,
        face_widths=None if face is None else face[1],
        cell_line_load=loads,
    )


def face_load_factor(forces, moments, widths):
    """K_Hbeta (-) of a mesh from its force F and the first moment M = sum z F_c of its cells'
    forces about the mid-plane (any consistent unit), across the face width b (m), on ISO
    6336-1's face load factor (the line load linear across the face, the contact unilateral): the linear distribution of that F and M has the largest line load
    F/b (1 + 6 |M| / (F b)) = F/b K_lin; where K_lin > 2 it would go negative at the other
    end, and the contact shortens to a triangle of length L = b (4 - K_lin) / 2 with the same
    F and M, whose K_Hbeta = 2 b / L = 4 / (4 - K_lin) (ISO 6336-1's two branches of
    K_Hbeta: 1 + F_beta_y c / (2 F_m / b) and sqrt(2 F_beta_y c / (F_m / b)) for a mesh
    misalignment F_beta_y on a spring bed c). 1 where F <= 0 or b = 0. Shapes broadcast, (..., 2N)."""
    ok = (forces > 0) & (widths > 0)
    safe = jnp.where(ok, forces * widths, 1.0)
    k_lin = jnp.minimum(1.0 + 6.0 * jnp.abs(moments) / safe, 4.0 - 1e-12)
    k = jnp.where(k_lin <= 2.0, k_lin, 4.0 / (4.0 - k_lin))
    return jnp.where(ok, k, 1.0)
