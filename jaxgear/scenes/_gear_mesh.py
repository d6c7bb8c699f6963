"""A gear mesh placed in a structure: the base-plane mesh model on its line of action, between two
gear members (seed (2.9), (2.30); docs/design.md, "Structure and dynamics").

A scene holds its gear members (the gear bodies of its structure) and a tuple of meshes; each
mesh names its driving and driven gear among the scene's members and gives the structure vectors
of its cells from them (:mod:`._interface`), so that a structure with several meshes (a gear
train, an idler driven in one mesh and driving in the next) is the same code with a longer
tuple. The role of a gear in a mesh (driving or driven, hence its outward normal and the flank
loaded) belongs to the mesh, not to the gear.

Frame: z along the (parallel) axes. The line of action is the unit vector t, tangent to the
driving gear's base circle at T1; a cell at base-plane coordinates (s, z) sits at

    M = T1 + (ρ_A + s) t + (z − b/2) e_z,

ρ_A the driving gear's roll distance of the engagement point, and its flank normal is
n = cos β_b t + sin β_b e_z (the helix-hand convention: a positive β gives a +z axial force on
the driven gear). In a pair's own frame the contact lines run s = r_b1 θ + i p_bt − z tan β_b
(:mod:`jaxgear._baseplane`): the driving pinion, turning about +z, is left-handed and the gear
right-handed (a right-handed pinion turning about +z would push its gear along −z, as a
right-handed screw advances along +z in a fixed nut). A mesh whose driving gear has the other
hand for its sense of rotation is the mirror image through the mid-face plane: its axial sense
a = −h ω_z/|ω_z| (h = +1 right-handed, −1 left-handed) is −1, its cells sit at
M = T1 + (ρ_A + s) t + a (z − b/2) e_z and n = cos β_b t + a sin β_b e_z. For a pair with the pinion axis through the origin and the gear axis through
(a_w, 0) (:func:`line_of_action`): t = (sin α_wt, cos α_wt, 0) and T1 = r_b1 (cos α_wt,
−sin α_wt, 0); the pinion turns about +z and drives, the gear turns about −z.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float, Int

from .._backlash import cell_flank, coast_line
from .._baseplane import Cells, MeshModel
from .._geometry import GearPair
from .._util import as_float, compiled_when_eager
from ._scene import Grounded

__all__ = [
    "GearMesh",
    "contact_points",
    "line_of_action",
    "mesh_line",
    "mesh_zone_load",
    "only_mesh",
    "pair_mesh",
]


def contact_points(
    tangent_point, direction, roll_start, mesh: MeshModel, cells: Cells, axial=1.0
) -> Array:
    """Fixed-frame contact points M = T1 + (ρ_A + s) t + a (z − b/2) e_z of the cells (m),
    shape (L, N, 3) (the frame of the module docstring; ``axial`` a = ±1 the mesh's axial
    sense)."""
    lead = (1,) * cells.s.ndim
    ez = axial * jnp.array([0.0, 0.0, 1.0], cells.s.dtype).reshape(lead + (3,))
    return (
        tangent_point.reshape(lead + (3,))
        + (roll_start + cells.s)[..., None] * direction.reshape(lead + (3,))
        + (cells.z - 0.5 * mesh.face_width)[..., None] * ez
    )


def mesh_line(tangent_point, direction, normal, roll_start, base_plane: MeshModel) -> dict:
    """The line of action as the members see it: ``normal`` n, ``direction`` t and the centre of
    the contact zone ``zone`` = T1 + (ρ_A + g_α/2) t (fixed frame, (3,) each)."""
    zone = tangent_point + (roll_start + 0.5 * base_plane.path_of_contact) * direction
    return {"normal": normal, "direction": direction, "zone": zone}


def line_of_action(
    pair: GearPair, driving_centre=(0.0, 0.0, 0.0), angle=0.0, spin=1.0, hand=None
) -> dict:
    """The line of action of ``pair`` placed in the fixed frame (NumPy, SI): ``centres`` (2, 3)
    of the driving and driven gears, ``tangent_point`` T1 (3,) on the driving gear's base circle,
    ``direction`` t (3,), ``normal`` n (3,), ``roll_start`` ρ_A and ``axial`` a (±1, the
    mesh's axial sense) (the module docstring), and the coast flanks' ``coast_tangent_point``
    T1', ``coast_direction`` t' and ``coast_normal`` n' (3,) each: the π-rotation R v =
    2 (v·d) d − v about the centre line d through the driving centre (docs/backlash.md).

    By default the pair's own frame: the driving gear (the pair's pinion) at the origin turning
    about +z, the driven gear at (a_w, 0, 0): t = (sin α_wt, cos α_wt, 0), T1 = r_b1 (cos α_wt,
    −sin α_wt, 0). ``driving_centre`` (m), ``angle`` (rad: the direction of the driven gear's
    centre seen from the driving one) and ``spin`` (+1: the driving gear turns about +z, −1 about
    −z, the mirror image) place it in a train. ``hand``: the driving gear's helix hand (+1
    right, −1 left; default: left turning about +z, right turning about −z, the hands the
    mirror image keeps: a = +1); the other hand mirrors the mesh through its mid-face plane
    (a = −1). Spur gears take any hand alike.
    """
    alpha = pair.operating_pressure_angle
    bb = pair.base_helix_angle
    sign = 1.0 if spin > 0 else -1.0
    axial = 1.0 if hand is None else -float(np.sign(hand)) * sign
    c, s_ = math.cos(angle), math.sin(angle)

    def place(v, point=True):  # mirror y for spin −1, turn by ``angle``, move to the centre
        x, y = v[0], sign * v[1]
        out = np.array([c * x - s_ * y, s_ * x + c * y, v[2]])
        return out + np.asarray(driving_centre, float) if point else out

    t = place(np.array([math.sin(alpha), math.cos(alpha), 0.0]), point=False)
    centres = np.array([place(np.zeros(3)), place(np.array([pair.center_distance, 0, 0]))])
    tangent = place(pair.base_radii[0] * np.array([math.cos(alpha), -math.sin(alpha), 0.0]))
    normal = math.cos(bb) * t + axial * math.sin(bb) * np.array([0.0, 0.0, 1.0])
    return {
        "centres": centres,
        "tangent_point": tangent,
        "direction": t,
        "normal": normal,
        "roll_start": pair.start_roll,
        "axial": axial,
        # the coast flanks' line (docs/backlash.md)
        **coast_line(centres, tangent, t, normal),
    }


class GearMesh(eqx.Module):
    """One gear mesh of a scene: the base-plane mesh model on its line of action between two of
    the scene's gear members.

    Attributes:
        base_plane: the mesh model (geometry, stiffness table, cell layout; its "pinion" is this
            mesh's driving gear).
        gears: static (driving, driven): the indices of the two gears in the scene's
            ``members`` (each a :class:`~jaxgear.scenes.RigidMember`,
            :class:`~jaxgear.scenes.TorsionalMember` or :class:`~jaxgear.scenes.FlexibleMember`).
            The driving gear's outward flank normal is n, the driven gear's −n.
        tangent_point: T1 (m), (3,). direction: t, (3,). normal: n, (3,). roll_start: ρ_A (m).
        te: the TE vector u of this mesh (n,): u·X is the flank-normal approach of the two gears'
            rigid rotations, cos β_b (r_b1 φ_1 + r_b2 φ_2) with each φ positive in its gear's
            direction of motion (docs/design.md, "Modifications, initial separation and TE").
        ratio, phase: the mesh angle θ_k = ratio θ + phase (rad): the angle of this mesh's
            driving gear, in its own direction of motion, at the scene angle θ (the pinion's, or
            the input gear's in a train), where the mesh takes its cells
            (:meth:`MeshModel.cells`). 1 and 0 for the meshes of one pair; in a train, ratio is
            the input's teeth over the driving gear's (with the idlers between) and phase the
            mesh phasing of the layout.
        axial: a = ±1, the mesh's axial sense (the module docstring): −1 for a mesh mirrored
            through its mid-face plane (a driving gear of the other helix hand).
        coast_tangent_point, coast_direction, coast_normal: T1', t', n' of the coast flanks
            (:func:`line_of_action`), (3,) each, or None; used when the base plane has coast
            flanks (``MeshModel.coast``): their cells sit at T1' + (ρ_A + s') t' − a (z' −
            b/2) e_z with outward normal n' on the driving gear (docs/backlash.md).
    """

    base_plane: MeshModel
    tangent_point: Float[Array, " 3"] = eqx.field(converter=as_float)
    direction: Float[Array, " 3"] = eqx.field(converter=as_float)
    normal: Float[Array, " 3"] = eqx.field(converter=as_float)
    roll_start: Float[Array, ""] = eqx.field(converter=as_float)
    te: Float[Array, " n"] = eqx.field(converter=as_float)
    gears: tuple = eqx.field(static=True, default=(0, 1))
    ratio: Float[Array, ""] = eqx.field(converter=as_float, default=1.0)
    phase: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    axial: Float[Array, ""] = eqx.field(converter=as_float, default=1.0)
    coast_tangent_point: Float[Array, " 3"] | None = None
    coast_direction: Float[Array, " 3"] | None = None
    coast_normal: Float[Array, " 3"] | None = None

    def angle(self, theta):
        """The mesh angle θ_k = ratio θ + phase (rad) at the scene angle θ (rad)."""
        return self.ratio * theta + self.phase

    def points(self, cells: Cells) -> Float[Array, "L N 3"]:
        """Fixed-frame contact points M of the cells (m), shape (L, N, 3)."""
        return contact_points(
            self.tangent_point, self.direction, self.roll_start, self.base_plane, cells, self.axial
        )

    def line(self) -> dict:
        """The line of action: ``normal`` n, ``direction`` t and the zone centre ``zone``
        (fixed frame, (3,) each)."""
        return mesh_line(
            self.tangent_point, self.direction, self.normal, self.roll_start, self.base_plane
        )

    def corner_contact(self, members: tuple, cells: Cells) -> tuple:
        """Where the cells' forces act (docs/extended-contact.md, "Where it acts"): the contact
        points P (L, N, 3), the driving gear's outward normals n' (L, N, 3) and the two gears'
        lever ratios ((L, N) each, driving then driven) from :meth:`MeshModel.corner`. On the
        path P = M, n' = n, ratios 1; beyond it P is the tip owner's corner, n' = cos β_b (cos ε
        t − sin ε v) + a sin β_b e_z, v the unit vector from the driving gear's centre to T1
        (from a member placed in space; a torsional scene needs only the ratios)."""
        plane = self.base_plane
        lever_driving, lever_driven, eps, o_t, o_v = plane.corner(cells.s)
        centre = members[self.gears[0]].axis_point()
        M = self.points(cells)
        if centre is None:  # a torsional member: no place in space, the ratios alone
            return M, self.normal, (lever_driving, lever_driven)
        ez = jnp.array([0.0, 0.0, 1.0], M.dtype)
        d = self.tangent_point - centre
        d = d - (d @ self.direction) * self.direction - (d @ ez) * ez
        lead = (1,) * cells.s.ndim + (3,)
        v = (d / jnp.linalg.norm(d)).reshape(lead)
        t = self.direction.reshape(lead)
        P = M + o_t[..., None] * t + o_v[..., None] * v
        cb = jnp.cos(plane.base_helix_angle)
        turn = (jnp.cos(eps) - 1.0)[..., None] * t - jnp.sin(eps)[..., None] * v
        n = self.normal.reshape(lead) + cb * turn
        return P, n, (lever_driving, lever_driven)

    def _parts(self, members: tuple, cells: Cells, pad: int):
        theta = (cells.theta - self.phase) / self.ratio  # the scene angle: the members' frames
        if not self.base_plane.coast:
            # where the cells act for each member: on the line, or beyond the theoretical path
            # at the corner's point with its turned normal and the member's own lever ratio
            # (docs/extended-contact.md, "Where it acts")
            points, lines = self.base_plane.contact_geometry.member_lines(
                self, members, cells, self.line()
            )
            return [
                members[g].window(points, cells.mask, ln, theta, self.base_plane, side, pad)
                for g, side, ln in zip(self.gears, (1.0, -1.0), lines, strict=True)
            ]
        return self._flank_parts(members, cells, theta, pad)

    def _flank_parts(self, members: tuple, cells: Cells, theta, pad: int):
        """The drive rows' and the coast rows' windows (:meth:`_parts`) joined along the lines:
        the coast rows on the coast line of action (rigid members) or with the sign of the
        flank (torsional members); a member without coast flanks (a condensed body:
        :attr:`~jaxgear.scenes.GearMember.coast_flanks`) is refused (not modelled)."""
        gears = [members[g] for g in self.gears]
        if not all(m.coast_flanks for m in gears):
            raise ValueError(
                "backlash (coast flanks, tooth_thickness_allowance) with condensed FE bodies is "
                "not modelled: use a torsional or lumped 3D scene, or drop the allowances"
            )
        if any(m.needs_coast_line for m in gears) and self.coast_normal is None:
            raise ValueError(
                "backlash (coast flanks) in this scene is not modelled: its mesh has no coast "
                "line of action (build the pair's mesh with pair_mesh)"
            )
        L = self.base_plane.n_drive_lines
        plane = self.base_plane
        halves = [
            jax.tree.map(lambda a, sl=sl: a[sl] if a.ndim >= 2 else a, cells)
            for sl in (slice(0, L), slice(L, None))
        ]
        zero = jnp.zeros((3,), plane.face_width.dtype)
        geometry = [
            (self.tangent_point, self.direction, self.normal, self.axial, 1.0),
            (
                zero if self.coast_tangent_point is None else self.coast_tangent_point,
                zero if self.coast_direction is None else self.coast_direction,
                zero if self.coast_normal is None else self.coast_normal,
                -self.axial,
                -1.0,
            ),
        ]
        out = []
        for g, side in zip(self.gears, (1.0, -1.0), strict=True):
            idx, Vs, over = None, [], []
            for half, (T, t, n, axial, flank) in zip(halves, geometry, strict=True):
                P = contact_points(T, t, self.roll_start, plane, half, axial)
                line = {**mesh_line(T, t, n, self.roll_start, plane), "flank": flank}
                i, V, o = members[g].window(P, half.mask, line, theta, plane, side, pad)
                idx = i
                Vs.append(V)
                over.append(o)
            out.append((idx, jnp.concatenate(Vs, axis=-3), over[0] | over[1]))
        return out

    def window(
        self, members: tuple, cells: Cells, pad: int = 0
    ) -> tuple[Int[Array, " w"], Float[Array, "L N w"]]:
        """The window DOFs (w,) of the mesh's two gears (taken from the scene's ``members``) and
        the structure vectors on them (L, N, w), cells off the flanks zeroed; ``pad`` rim
        stations more on each side of a flexible member's window."""
        parts = self._parts(members, cells, pad)
        idx = jnp.concatenate([p[0] for p in parts])
        V = jnp.concatenate([p[1] for p in parts], axis=-1)
        return idx, jnp.where(cells.mask[..., None], V, 0.0)

    def window_overflow(self, members: tuple, cells: Cells) -> Bool[Array, ""]:
        """True if a cell on the flanks reaches a rim station beyond its member's window."""
        return jnp.any(jnp.stack([p[2] for p in self._parts(members, cells, 0)]))

    def cell_vectors(self, members: tuple, cells: Cells, n: int) -> Float[Array, "L N n"]:
        """The structure vectors V (seed (2.9), (2.30)) of the cells over all n coordinates."""
        idx, Vw = self.window(members, cells)
        V = jnp.zeros(cells.s.shape + (n,), Vw.dtype)
        return V.at[..., idx].add(Vw)


def pair_mesh(base_plane: MeshModel, line: dict, te) -> GearMesh:
    """The mesh of a pair on the line of action ``line`` (:func:`line_of_action`) with TE vector
    ``te`` (n,), between the scene's members 0 (the pinion, driving) and 1 (the gear); its
    coast line of action (``line``'s ``coast_*`` entries) where the base plane has coast
    flanks."""
    coast = {}
    if base_plane.coast:
        coast = {
            k: as_float(line[k]) for k in ("coast_tangent_point", "coast_direction", "coast_normal")
        }
    return GearMesh(
        base_plane,
        line["tangent_point"],
        line["direction"],
        line["normal"],
        line["roll_start"],
        te,
        gears=(0, 1),
        axial=line.get("axial", 1.0),
        **coast,
    )


def only_mesh(meshes: tuple) -> GearMesh:
    """The one mesh of a scene, for the entries that handle a single mesh."""
    if len(meshes) != 1:
        raise ValueError(
            f"the scene has {len(meshes)} gear meshes; this entry handles a scene with one mesh"
        )
    return meshes[0]


def mesh_zone_load(scene, k: int, theta, first: int = 0) -> Float[Array, " m"]:
    """A unit normal force spread over mesh ``k``'s contact zone, as a load on the structure.

    The zone is the mesh's cells on the drive flanks and on the theoretical path of contact
    (0 ≤ s ≤ g_α) at the scene angle ``theta`` (:meth:`GearMesh.angle`,
    :meth:`MeshModel.cells`): with contact beyond the path a corner cell holds its gap and
    carries load only under deflection (docs/extended-contact.md, as the no-load mean mesh
    stiffness counts it), so it is no part of the zone. The unit force is shared among them in
    proportion to their contact lengths l_c (uniform line load), and each cell's share acts
    through its structure vector V_c (seed (2.9) for a rigid or torsional gear, (2.30) through
    the interface of a condensed body): f = Σ_c w_c V_c with w_c = l_c / Σ l. Its work on the
    coordinates X is the zone's mean flank-normal approach, f · X = Σ_c w_c V_c · X; the
    forces it puts on the two gears are the ones that press their flanks together (+n on the
    driving gear, −n on the driven gear: the reaction of a unit contact force). fᵀ K⁻¹ f is
    the zone's compliance (m/N) and f_iᵀ K⁻¹ f_j the cross-compliance between two zones.

    On a rigid 6-DOF gear node O (:class:`~jaxgear.scenes.RigidMember`) the load is the
    resultant [±n, Σ_c w_c (M_c − O) × (±n)]: a unit force along the line of action whose
    moment about the gear axis is its base radius times cos β_b; on a torsional member
    ±r_b cos β_b.

    Args:
        scene: a scene with gear meshes (:class:`~jaxgear.scenes.AssembledScene`: a lumped or
            hybrid pair or train, a torsional train; or a :class:`~jaxgear.scenes.Grounded`
            one, whose base's coordinates are loaded), n coordinates.
        k: the mesh, an index into ``scene.meshes`` (0 to len(meshes) − 1).
        theta: the scene angle θ (rad): the pinion's, or the input gear's in a train.
        first: the first coordinate kept: the load on coordinates ``first`` to n − 1 (0: all
            of them). A hybrid train's shaft coordinates come first
            (``scene.structure.C_bearing.shape[0]`` of them): ``first`` set to that count gives
            the load on the condensed bodies' coordinates alone, the shafts (and so the
            bodies' bearing nodes) held.

    Returns:
        f, shape (n − first,): generalised forces (N on translations, N·m on rotations) per
        newton of total normal force.

    Raises:
        ValueError: ``k`` not a mesh of the scene or ``first`` outside [0, n].
    """
    while isinstance(scene, Grounded):
        scene = scene.base
    meshes, n = scene.meshes, scene.structure.size
    if not 0 <= k < len(meshes):
        raise ValueError(
            f"mesh_zone_load: k = {k}: not a mesh of the scene, allowed 0 to {len(meshes) - 1}"
        )
    if not 0 <= first <= n:
        raise ValueError(f"mesh_zone_load: first = {first}: out of range, allowed [0, {n}]")
    return _zone_load(scene, k, jnp.asarray(theta), first)


@compiled_when_eager
def _zone_load(scene, k: int, theta, first: int):
    """:func:`mesh_zone_load` in one compiled program when called eagerly (``k``, ``first``
    static, the angle traced: one program per scene for every angle; eagerly its few hundred
    operations would each compile on their own); traced inline under a caller's ``jit``."""
    mesh = scene.meshes[k]
    cells = mesh.base_plane.cells(mesh.angle(theta))
    V = mesh.cell_vectors(scene.members, cells, scene.structure.size)[..., first:]
    on = (cells.s >= 0.0) & (cells.s <= mesh.base_plane.path_of_contact)
    w = jnp.where(cells.mask & (cell_flank(cells) > 0) & on, cells.length, 0.0)
    return jnp.einsum("ij,ijm->m", w / jnp.sum(w), V)
