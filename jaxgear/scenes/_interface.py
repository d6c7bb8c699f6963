"""Gear members of a structure and how a contact cell loads them: the interface (seed (2.9),
(2.11)–(2.30)).

A gear mesh (:mod:`._gear_mesh`) acts on the structure through its two gear members, each giving
the structure vector V of a cell (its approach V·X, its load −p l V):

* :class:`RigidMember`: a rigid gear body at a 6-DOF shaft node, V = [n_m, (M − O) × n_m] (seed
  (2.9));
* :class:`FlexibleMember`: a condensed FE body (:mod:`fem_prep`) on its rim master nodes (the
  outer rim face under the teeth, r = root radius, one station per tooth), through the tooth-root
  points and the mortar of the slices.

Interface of a cell M on a flexible member (seed (2.11)–(2.30); docs/hybrid.md, "The interface"):

* the tooth in contact at M is a rigid transverse slice rooted on the rim at two root points
  M_p1, M_p2 (where the tooth's fillets meet the root circle, at ±ψ_f about its centre line);
* the root displacement u(M_p) = (u_1 + u_2)/2 and rotation ω = κ·(u_1 − u_2) (least squares
  (2.12)–(2.18), κ = (M_p1M_p2 × Z)/|M_p1M_p2|², M_p the chord midpoint [R]: a rigid rotation
  about the axis is then reproduced exactly; M_p1, M_p2 are taken on the (flat) rim face, i.e.
  projected on its chord, so that the face interpolation reproduces rigid motions exactly)
  give u(M)·n_m = c_1·u_1 + c_2·u_2 with c_{1,2} = n_m/2 ± λ κ, λ = Z·(M_pM × n_m) (2.19)–(2.20), n_m the member's outward normal
  (n for the pinion, −n for the gear);
* mortar (2.21)–(2.27): u(M_pk) = (5 u(N1) + 20 u(N2) + 5 u(N3))/30 over the slice, N1, N3 at the
  slice ends along the helix;
* u(N) is interpolated on the rim face that contains N. **Faces are bilinear** on the corner
  master nodes (the stations and the axial master planes), consistently for the displacement
  and, by the transposition of V, for the load: fem_prep keeps only the corner nodes of the hex20
  rim faces as masters, and a serendipity face needs all eight (docs/hybrid.md, "Seed typos and
  traps"). The natural coordinate across the face is the orthogonal projection on the face's
  chord (the inverse of its own bilinear map), along the axis the linear one. With the slices
  nested inside the axial faces (slices a multiple of the faces), the mortar average of a
  bilinear field is exact.

The body turns under the fixed mesh: its frame is at angle φ_rot = φ_0 ∓ θ_member from the
fixed frame, and the cells' coefficients c_k are rotated into it, so the stations under each
contact line follow the rotation. K, M and the centrifugal load are constant in the body frame.
"""

from __future__ import annotations

import abc
import dataclasses
import math
from typing import ClassVar, NamedTuple

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float, Int

from .._baseplane import MeshModel
from .._geometry import GearPair, involute
from .._stiffness import _root_angle
from .._util import as_float

__all__ = [
    "FlexibleMember",
    "GearMember",
    "GearPlace",
    "RigidMember",
    "RimStations",
    "TorsionalMember",
    "body_dof_index",
    "body_rims",
    "flexible_member",
    "loaded_flank",
    "mortar_weights",
    "rigid_node_vector",
]

MORTAR = (5.0 / 30.0, 20.0 / 30.0, 5.0 / 30.0)  # (2.26)-(2.27): Simpson on the slice


class RimStations(NamedTuple):
    """The rim stations of a gear member that a run records (:meth:`GearMember.rim_stations`).

    Attributes:
        dofs: the global (x, y, z) DOFs of each station at the axial master plane nearest
            mid-face, (Z, 3) int (body frame).
        angles: each station's angle in the body frame (rad), (Z,).

    A member without a rim (a rigid gear) has Z = 0.
    """

    dofs: Int[Array, "Z 3"]
    angles: Float[Array, " Z"]

    @property
    def count(self) -> int:
        """Z, the number of stations (static)."""
        return int(self.angles.shape[0])


def mortar_weights() -> tuple[float, float, float]:
    """Weights of the slice-end, slice-centre and slice-end nodes of the mortar (2.26):
    [5, 20, 5]/30 (the printed 1/L of (2.27) is a typo for 1/30: docs/hybrid.md, "Seed typos and
    traps")."""
    return MORTAR


def _lead(v, like):
    """``v`` (k,) reshaped to broadcast against ``like`` (..., k) without rank promotion."""
    return v.reshape((1,) * (like.ndim - 1) + v.shape)


def _rot(angle, v):
    """Rotate the in-plane part of ``v`` (..., 3) by ``angle`` (...) about z."""
    c, s = jnp.cos(angle), jnp.sin(angle)
    return jnp.stack([c * v[..., 0] - s * v[..., 1], s * v[..., 0] + c * v[..., 1], v[..., 2]], -1)


def rigid_node_vector(points, centre, normal) -> Array:
    """Structure vector of a rigid gear body at a 6-DOF node O: [n_m, (M − O) × n_m] (seed
    (2.9)), shape (..., 6), for contact points M (..., 3) and the member's outward normal n_m
    (n for the pinion, −n for the gear)."""
    nm = jnp.broadcast_to(normal, points.shape)
    arm = points - centre.reshape((1,) * (points.ndim - 1) + (3,))
    return jnp.concatenate([nm, jnp.cross(arm, nm)], axis=-1)


def tooth_centre_angle(centre, base_radius, base_half_angle, points, flank):
    """Fixed-frame polar angle of the centre line of the tooth in contact at ``points`` (..., 3)
    on the flank ``flank`` (±1, :func:`loaded_flank`) of a gear about ``centre`` (3,) with base
    radius r_b (m) and half base angle ψ_b (rad): φ_c = φ_M + flank ψ(r_M), ψ(r) = ψ_b −
    inv(arccos(r_b/r)) (rad)."""
    m = points - _lead(centre, points)
    r = jnp.maximum(jnp.hypot(m[..., 0], m[..., 1]), base_radius)
    a = jnp.arccos(base_radius / r)
    psi = base_half_angle - involute(a)
    return jnp.arctan2(m[..., 1], m[..., 0]) + flank * psi


class GearMember(eqx.Module):
    """Abstract gear member of a structure: a gear body that the cells of its meshes load
    through their structure vectors V (its :meth:`window`). The protocol attributes below have
    the defaults of a body that neither turns its frame nor deforms (a rigid gear); a condensed
    FE body (:class:`FlexibleMember`) overrides them.

    Class attributes:
        coast_flanks: the member's coast flanks are modelled (backlash): a rigid gear's on the
            coast line of action, a torsional gear's with the flank's sign; not a condensed
            body's.
        needs_coast_line: its coast rows need the mesh's coast line of action (a member placed
            in space).
        turns_frame: the member's coordinates (and its shaft's) are taken in a frame that turns
            with it (:meth:`frame_angle`).
    """

    coast_flanks: ClassVar[bool] = True
    needs_coast_line: ClassVar[bool] = False
    turns_frame: ClassVar[bool] = False

    @property
    @abc.abstractmethod
    def width(self) -> int:
        """The number of DOFs of its window (static)."""

    @abc.abstractmethod
    def window(self, points, mask, line, theta, mesh, side, pad=0):
        """Global DOFs of the window (w,), the structure vectors on them (L, N, w) and whether a
        cell on the flanks reaches beyond the window, for the cells at fixed-frame points
        ``points`` (L, N, 3) with mask (L, N) on the mesh's ``line``
        (:meth:`~jaxgear.scenes.GearMesh.line`) at scene angle θ (rad) of base plane ``mesh``;
        ``side`` +1 the mesh's driving gear, −1 its driven gear; ``pad`` rim stations more on
        each side of a window that follows the contact. With contact beyond the theoretical
        path (``mesh.contact_geometry``) ``points`` are the corners' contact points, ``line``'s
        ``cell_normal`` (L, N, 3) the driving gear's outward normal of each cell (turned by ε
        beyond the path) and its ``lever`` (L, N) this member's lever ratio (λ where it owns
        the tip corner, else 1; docs/extended-contact.md, "Where it acts")."""

    @property
    def contact_dofs(self) -> tuple | None:
        """The global DOFs its cells' structure vectors reach (static), or None: a window that
        follows the contact (a condensed body's rim stations)."""
        return None

    def frame_angle(self, theta):
        """The angle of the member's frame in the fixed frame at the scene angle θ (rad): 0 for
        a member in the fixed frame."""
        return jnp.zeros_like(theta)

    def rim_radial_growth(self, x) -> Float[Array, ""]:
        """The mean radial displacement (m) of its rim under the displacement X (n,): 0 for a
        rigid gear."""
        return jnp.zeros((), x.dtype)

    def widened(self) -> GearMember:
        """The member with its window one station wider: itself when the window is its node's
        DOFs."""
        return self

    def rim_stations(self) -> RimStations:
        """The rim stations a run records (:class:`RimStations`): none (Z = 0) for a gear
        without a deformable rim."""
        return RimStations(jnp.zeros((0, 3), jnp.int32), jnp.zeros((0,)))

    def axis_point(self) -> Float[Array, " 3"] | None:
        """The member's axis point O (m), (3,), where it is placed in space (its ``centre``);
        None for a member that only turns (a torsional gear: no place in space)."""
        return None


class RigidMember(GearMember):
    """A rigid gear body at a 6-DOF shaft node: V = [n_m, (M − O) × n_m] (seed (2.9))."""

    needs_coast_line: ClassVar[bool] = True

    centre: Float[Array, " 3"] = eqx.field(converter=as_float)
    dofs: tuple = eqx.field(static=True)  # the node's 6 global DOFs

    @property
    def width(self) -> int:
        return 6

    def axis_point(self) -> Float[Array, " 3"]:
        """Its ``centre`` (m), (3,)."""
        return self.centre

    @property
    def contact_dofs(self) -> tuple:
        """The global DOFs its cells' structure vectors reach (static): its node's 6."""
        return self.dofs

    def window(self, points, mask, line, theta, mesh, side, pad=0):
        """Global DOFs (6,), structure vectors on them (L, N, 6), no overflow. ``side``: +1 the
        mesh's driving gear (n_m = n), −1 its driven gear (n_m = −n); ``pad``: unused, the
        node's DOFs are the whole window."""
        v = rigid_node_vector(points, self.centre, side * line.get("cell_normal", line["normal"]))
        return jnp.asarray(self.dofs), v, jnp.array(False)


class TorsionalMember(GearMember):
    """A rigid gear body that only turns, one coordinate φ (rad, positive in the gear's direction
    of motion): V = ±cos β_b r_b on it (seed (2.9) reduced to the rotation: the driving gear
    advancing closes the flanks, the driven gear advancing opens them)."""

    dof: int = eqx.field(static=True)  # the rotation's global DOF

    @property
    def width(self) -> int:
        return 1

    @property
    def contact_dofs(self) -> tuple:
        """The global DOFs its cells' structure vectors reach (static): its rotation."""
        return (self.dof,)

    def window(self, points, mask, line, theta, mesh, side, pad=0):
        """Global DOF (1,), structure vectors on it (L, N, 1), no overflow. ``side``: +1 the
        mesh's driving gear (its base radius r_b1), −1 its driven gear (r_b2); ``line``'s
        ``flank`` (−1: coast cells, whose gap the driving gear's advance opens; default +1)
        flips it; ``points`` and ``pad`` unused: the vector is the same for every cell."""
        r = mesh.base_radius_pinion if side > 0 else mesh.base_radius_gear
        v = side * line.get("flank", 1.0) * jnp.cos(mesh.base_helix_angle) * r
        v = jnp.broadcast_to(v, mask.shape + (1,))
        if "lever" in line:  # beyond the theoretical path: the tip owner's lever ratio λ
            v = v * line["lever"][..., None]
        return jnp.asarray([self.dof]), v, jnp.array(False)


class FlexibleMember(GearMember):
    """A condensed FE body: the interface data of docs/hybrid.md, "The interface" (build with
    :func:`hybrid_pair`).

    Attributes:
        centre: the member's axis point O (m), shape (3,). rim_dofs: global DOF of each rim
            master (station, axial node, x/y/z), shape (Z, n_ax, 3). body_dofs: global DOF of
            each condensed DOF of the body (fem_prep order), shape (n_c,). z_nodes: axial master
            positions (m, body frame, z = 0 at mid-rim), shape (n_ax,).
        station0: body angle of station 0 (rad). pitch_angle: 2π/Z. rim_radius: R of the master
            nodes (m). (the root points lie on the rim faces; the gear's r_f is checked to lie within 2 % of R). root_half_angle: ψ_f (rad).
        base_radius: r_b (m). base_half_angle: half the angular tooth thickness at the base
            circle, ψ(r) = ψ_b − inv(arccos(r_b/r)) (rad). offset: φ_0 (rad), the body frame's
            angle at θ = 0. spin: ±1 and ratio: θ_member = ratio θ turned in the ``spin`` sense
            about z. n_window: stations in the window.

    The member is the body; its role in a mesh (driving or driven, the flank loaded) is the
    mesh's (:func:`loaded_flank`), passed to :meth:`window` as ``side``. A point's body z is its
    fixed-frame z less the centre's (z = 0 at mid-rim).
    """

    centre: Float[Array, " 3"] = eqx.field(converter=as_float)
    rim_dofs: Int[Array, "Z n_ax 3"] = eqx.field(converter=jnp.asarray)
    body_dofs: Int[Array, " n_c"] = eqx.field(converter=jnp.asarray)
    z_nodes: Float[Array, " n_ax"] = eqx.field(converter=as_float)
    station0: Float[Array, ""] = eqx.field(converter=as_float)
    pitch_angle: Float[Array, ""] = eqx.field(converter=as_float)
    rim_radius: Float[Array, ""] = eqx.field(converter=as_float)
    root_half_angle: Float[Array, ""] = eqx.field(converter=as_float)
    base_radius: Float[Array, ""] = eqx.field(converter=as_float)
    base_half_angle: Float[Array, ""] = eqx.field(converter=as_float)
    offset: Float[Array, ""] = eqx.field(converter=as_float)
    ratio: Float[Array, ""] = eqx.field(converter=as_float)
    spin: float = eqx.field(static=True)
    n_window: int = eqx.field(static=True)

    coast_flanks: ClassVar[bool] = False
    turns_frame: ClassVar[bool] = True

    @property
    def width(self) -> int:
        return self.n_window * self.z_nodes.shape[0] * 3

    def axis_point(self) -> Float[Array, " 3"]:
        """Its ``centre`` (m), (3,)."""
        return self.centre

    def frame_angle(self, theta):
        """φ_rot: angle of the body frame in the fixed frame at pinion angle θ (rad)."""
        return self.offset + self.spin * self.ratio * theta

    def tooth_centre_angle(self, points, flank):
        """Fixed-frame polar angle of the centre line of the tooth in contact at ``points`` on the
        flank ``flank`` (±1, :func:`loaded_flank`): φ_c = φ_M + flank ψ(r_M)
        (:func:`tooth_centre_angle`)."""
        return tooth_centre_angle(
            self.centre, self.base_radius, self.base_half_angle, points, flank
        )

    def rim_radial_growth(self, x):
        """The mean radial displacement (m) of the rim master nodes under X (n,) (body frame)."""
        u = x[self.rim_dofs]  # (Z, n_ax, 3), body frame
        Z = self.rim_dofs.shape[0]
        ang = self.station0 + self.pitch_angle * jnp.arange(Z)
        ur = u[..., 0] * jnp.cos(ang)[:, None] + u[..., 1] * jnp.sin(ang)[:, None]
        return jnp.mean(ur)

    def widened(self) -> FlexibleMember:
        """The member with one rim station more in its window."""
        return dataclasses.replace(self, n_window=self.n_window + 1)

    def rim_stations(self) -> RimStations:
        """Its Z rim stations (one per tooth, :class:`RimStations`) at the axial master plane
        nearest mid-face, station k at the body angle station0 + k 2π/Z."""
        j_mid = jnp.argmin(jnp.abs(self.z_nodes))
        Z = self.rim_dofs.shape[0]
        return RimStations(
            self.rim_dofs[:, j_mid, :], self.station0 + self.pitch_angle * jnp.arange(Z)
        )

    def coefficients(self, points, outward, p1, p2):
        """c_1, c_2 (fixed frame, (..., 3) each) of (2.19)-(2.20) for contact points M (..., 3),
        the member's outward flank normal n_m (3,) (n for the mesh's driving gear, −n for its
        driven gear) and root points M_p1, M_p2 (fixed frame, in-plane, (..., 2))."""
        mp = 0.5 * (p1 + p2)  # chord midpoint [R]: exact for a rigid rotation
        d = p2 - p1
        kappa = jnp.stack([d[..., 1], -d[..., 0], jnp.zeros_like(d[..., 0])], -1)
        kappa = kappa / jnp.sum(d * d, axis=-1, keepdims=True)  # (M_p1M_p2 × Z)/|M_p1M_p2|²
        nm = jnp.broadcast_to(outward, points.shape)
        arm = points[..., :2] - mp
        lam = arm[..., 0] * nm[..., 1] - arm[..., 1] * nm[..., 0]  # Z·(M_pM × n_m)
        c1 = 0.5 * nm + lam[..., None] * kappa
        c2 = 0.5 * nm - lam[..., None] * kappa
        return c1, c2

    def face_weights(self, phi, z):
        """Station index i (…), axial face j (…), the four bilinear corner weights (…, 2, 2)
        [station i, i+1] × [axial j, j+1] of the rim point at body angle φ, z, and the point of
        the face itself (body frame, in-plane, (…, 2)): the orthogonal projection on the face's
        chord (the inverse of the flat bilinear face's own map)."""
        t = (phi - self.station0) / self.pitch_angle
        i = jnp.floor(t)
        u = (t - i) * self.pitch_angle
        cd = 1.0 - jnp.cos(self.pitch_angle)
        xi = ((1.0 - jnp.cos(u)) * cd + jnp.sin(u) * jnp.sin(self.pitch_angle)) / (2.0 * cd)
        a0 = self.station0 + i * self.pitch_angle
        a1 = a0 + self.pitch_angle
        R = self.rim_radius
        face = jnp.stack(
            [
                R * ((1 - xi) * jnp.cos(a0) + xi * jnp.cos(a1)),
                R * ((1 - xi) * jnp.sin(a0) + xi * jnp.sin(a1)),
            ],
            -1,
        )
        zn = self.z_nodes
        j = jnp.clip(jnp.searchsorted(zn, z, side="right") - 1, 0, zn.shape[0] - 2)
        eta = (z - zn[j]) / (zn[j + 1] - zn[j])
        w = jnp.stack(
            [
                jnp.stack([(1 - xi) * (1 - eta), (1 - xi) * eta], -1),
                jnp.stack([xi * (1 - eta), xi * eta], -1),
            ],
            -2,
        )
        return i.astype(jnp.int32), j, w, face

    def window(self, points, mask, line, theta, mesh: MeshModel, side, pad: int = 0):
        """Global DOFs of the window (w,), the structure vectors on them (L, N, w) and whether a
        cell on the flanks reaches beyond the window (the builder checks that it never does).
        ``side``: +1 the mesh's driving gear, −1 its driven gear. ``pad``: stations added on
        each side of the window (the wider window that holds every window of a mesh period, for
        the mesh damping that turns with the wheel).

        ``line``: the fixed-frame ``normal`` n and ``direction`` t of the line of action and the
        zone centre ``zone`` (3,) (a point where the window is centred).
        """
        rot = self.frame_angle(theta)
        # the three mortar nodes of each slice along the same tooth (helix): moving by δz across
        # the face along a contact line, s → s − δz tan β_b
        dz = mesh.face_width / mesh.n_slices
        tb = jnp.tan(mesh.base_helix_angle)
        ez = jnp.array([0.0, 0.0, 1.0], points.dtype)
        offsets = jnp.array([-0.5, 0.0, 0.5], points.dtype) * dz
        step = offsets[:, None] * (ez - tb * line["direction"])[None, :]  # (3 nodes, xyz)
        pts = points[..., None, :] + step.reshape((1,) * (points.ndim - 1) + step.shape)
        flank = loaded_flank(self.centre, line, side)
        phi_c = self.tooth_centre_angle(pts, flank) - rot  # body frame, (L, N, 3)
        psi = self.root_half_angle
        phi = jnp.stack([phi_c - psi, phi_c + psi], axis=-2)  # (L, N, 2 points, 3 nodes)
        zb = jnp.broadcast_to((pts[..., 2] - self.centre[2])[..., None, :], phi.shape)
        i, j, w, face = self.face_weights(phi, zb)
        # root points M_p1, M_p2 on the face at the slice centre, in the fixed frame
        pk = _rot(rot, jnp.concatenate([face[..., 1, :], jnp.zeros_like(face[..., 1, :1])], -1))
        pk = pk[..., :2] + _lead(self.centre[:2], pk[..., :2])  # (L, N, 2, 2)
        normal = side * line.get("cell_normal", line["normal"])  # per cell beyond the path
        c1, c2 = self.coefficients(points, normal, pk[..., 0, :], pk[..., 1, :])
        # coefficients in the body frame: c·u_fixed = (R(−φ_rot) c)·u_body
        cb = jnp.stack([_rot(-rot, c1), _rot(-rot, c2)], axis=-2)  # (L, N, 2, 3)
        w = w * jnp.asarray(MORTAR, points.dtype).reshape((1,) * (w.ndim - 3) + (3, 1, 1))
        # window: n_window stations from the lowest one touched by a cell on the flanks
        Z = self.rim_dofs.shape[0]
        zc = line["zone"] - self.centre
        ref = jnp.floor(
            (jnp.arctan2(zc[1], zc[0]) - rot - self.station0) / self.pitch_angle
        ).astype(jnp.int32)
        rel = jnp.mod(i - ref + Z // 2, Z) - Z // 2
        start = ref + jnp.min(jnp.where(mask[..., None, None], rel, Z)) - pad
        il = jnp.mod(i - start, Z)  # station in the window, (L, N, 2, 3)
        n_ax = self.z_nodes.shape[0]
        L, N = points.shape[:2]
        n_win = self.n_window + 2 * pad
        V = jnp.zeros((L, N, n_win, n_ax, 3), points.dtype)
        li = jnp.arange(L)[:, None, None, None]
        ni = jnp.arange(N)[None, :, None, None]
        for a in (0, 1):  # station i, i + 1
            for b in (0, 1):  # axial node j, j + 1
                coef = w[..., a, b, None] * cb[..., :, None, :]  # (L, N, 2, 3, xyz)
                V = V.at[li, ni, il + a, j + b].add(coef, mode="drop")
        stations = jnp.mod(start + jnp.arange(n_win), Z)
        idx = self.rim_dofs[stations].reshape(-1)
        overflow = jnp.any(mask[..., None, None] & (il + 1 >= n_win))
        return idx, V.reshape(L, N, -1), overflow


def loaded_flank(centre, line, side):
    """The flank of a gear loaded in a mesh: ±1, the side of the contact point on which the
    centre line of the tooth in contact lies, seen about the gear's axis through ``centre`` (3,)
    (φ_c = φ_M + flank ψ(r_M)). The tooth material is on the side −side·n of the contact (−n for
    the mesh's driving gear, ``side`` = +1; +n for its driven gear, ``side`` = −1), taken at the
    zone centre of ``line`` (:meth:`jaxgear.scenes.GearMesh.line`); an idler is driven on one
    flank in one mesh and drives on the other in the next."""
    rz = jnp.asarray(line["zone"]) - jnp.asarray(centre)
    e_phi = jnp.stack([-rz[1], rz[0]])
    return jnp.sign(-side * (e_phi @ jnp.asarray(line["normal"])[:2]))


def body_rims(body) -> tuple:
    """Each rim's ``(stations, n_axial)`` master-node grid of a condensed body, the wheel's rim
    first (``CondensedBody.rim_grids``: a fem_prep body with a ``[pinion_rim]`` has two)."""
    return tuple(body.rim_grids)


def rim_mid_z(body, rim: int = 0) -> float:
    """The body-frame z (m) of the middle of rim ``rim``'s face (0 for the wheel's rim, whose
    mid-face is the body frame's origin)."""
    z = np.asarray(body.master_coords, float)[body_rims(body)[rim][0], 2]
    return 0.5 * float(z.min() + z.max())


def body_dof_index(body) -> dict:
    """(master, component) → condensed DOF index of a fem_prep body."""
    dm = np.asarray(body.dof_map)
    return {(int(m), int(c)): i for i, (m, c) in enumerate(dm) if m >= 0}


def rim_window(pair: GearPair, member: int) -> int:
    """The default number of rim stations in a condensed member's window for one mesh: the
    total contact ratio ε_α + ε_β plus the root points' span 2ψ_f in pitches, plus 2 (member 0
    the mesh's driving gear, 1 its driven gear)."""
    eps = pair.transverse_contact_ratio + pair.overlap_ratio
    pitch = 2 * math.pi / (pair.pinion, pair.gear)[member].teeth
    return math.ceil(eps + 2 * _root_angle(pair, member) / pitch) + 2


class GearPlace(NamedTuple):
    """Where a condensed gear sits and how its body frame turns (:func:`flexible_member`).

    Attributes:
        centre: the member's axis point O (m), (3,).
        spin, ratio: the body turns by ratio·θ in the ``spin`` sense about z at the scene angle
            θ (default None: a pair's, +1 and 1 for the pinion, −1 and z1/z2 for the gear; in a
            train, the layout's sense and speed ratio of the gear).
        mesh_angle: the angle of the mesh at θ = 0 (rad; a train's mesh phase; 0 for a pair).
        rim: which rim of the body carries the gear (:func:`body_rims`: 0 the wheel's, 1 a
            ``[pinion_rim]``); its axial positions are taken from the middle of its face.
        n_window: rim stations in the window (default None: the contact ratio plus the root
            points' span, plus 2: :func:`rim_window`).
        offset: the body frame's angle φ_0 at θ = 0 (rad), or None (default): the angle that
            puts a tooth in contact on a rim station (the docstring of
            :func:`flexible_member`); a body carrying two gears takes one angle for both.
    """

    centre: object
    spin: float | None = None
    ratio: float | None = None
    mesh_angle: float = 0.0
    rim: int = 0
    n_window: int | None = None
    offset: float | None = None


def flexible_member(
    pair: GearPair, member: int, body, gidx, line: dict, mesh: MeshModel, place: GearPlace
) -> FlexibleMember:
    """The interface of a condensed body: its rim master DOFs, root points and window.

    Args:
        pair: the gear pair. member: 0 pinion, 1 gear. body: the condensed body (see
            :func:`jaxgear.scenes.hybrid_pair`). gidx: global DOF of each condensed DOF (n_c,).
        line: the mesh's line of action (:meth:`jaxgear.scenes.GearMesh.line`). mesh: the
            base-plane mesh model. place: the gear's centre, the turning of its body frame, its
            rim and window (:class:`GearPlace`).

    The body frame is set so that at θ = 0 the centre line of a tooth in contact, at mid-face
    (body z = 0), lies on a rim station: the contact lines of ``mesh`` run
    s = r_b1 θ_mesh + i p_bt − z tan β_b (:meth:`MeshModel.cells`), so at mid-face a flank
    passes through s* = r_b1 θ_mesh − (b/2) tan β_b + i p_bt (i chosen nearest the zone centre).

    Raises:
        ValueError: the body's rim stations do not match the gear's teeth or are not at 2πk/Z,
            the rim radius is not the root radius (2 %), fewer than 2 axial rim master nodes,
            or the mesh's slices do not nest in the body's axial rim faces.
    """
    centre, rim, spin, ratio = place.centre, place.rim, place.spin, place.ratio
    coords = np.asarray(body.master_coords, float)
    rims = body_rims(body)
    if not 0 <= rim < len(rims):
        raise ValueError(f"flexible_member: rim {rim}, the body has {len(rims)} rim(s)")
    grid = np.asarray(rims[rim])
    Z, n_ax = grid.shape
    teeth = (pair.pinion, pair.gear)[member].teeth
    name = ("pinion", "gear")[member]
    if Z != teeth:
        which = ("[condensation] teeth", "[pinion_rim] teeth")[min(rim, 1)]
        raise ValueError(
            f"scene.{name}_body: the body's rim {rim} has {Z} rim stations, the {name} "
            f"{teeth} teeth (fem_prep {which} must equal the gear's teeth)"
        )
    xy = coords[grid[:, 0], :2]
    ang = np.unwrap(np.arctan2(xy[:, 1], xy[:, 0]))
    pitch = 2 * math.pi / Z
    if not np.allclose(np.diff(ang), pitch, atol=1e-6):
        raise ValueError(f"scene.{name}_body: rim stations are not at 2πk/Z (k increasing)")
    radius = float(np.mean(np.hypot(xy[:, 0], xy[:, 1])))
    rf = pair.root_radii[member]
    if abs(radius - rf) > 0.02 * rf:
        raise ValueError(
            f"scene.{name}_body: rim outer radius {radius * 1e3:.6g} mm is not the {name}'s root "
            f"radius {rf * 1e3:.6g} mm (allowed within 2 %)"
        )
    z_nodes = coords[grid[0], 2] - rim_mid_z(body, rim)  # from the rim's mid-face
    if n_ax < 2 or np.any(np.diff(z_nodes) <= 0):
        raise ValueError(
            f"scene.{name}_body: needs >= 2 axial rim master nodes in increasing z "
            f"(fem_prep [condensation] axial_master_nodes), got {n_ax}"
        )
    b = float(mesh.face_width)
    edges = -0.5 * b + b * np.arange(mesh.n_slices + 1) / mesh.n_slices
    inner = z_nodes[(z_nodes > -0.5 * b + 1e-9) & (z_nodes < 0.5 * b - 1e-9)]
    if inner.size and np.min(np.abs(inner[:, None] - edges[None, :]), axis=1).max() > 1e-9 * b:
        raise ValueError(
            f"mesh.slices = {mesh.n_slices}: the slices must nest in the {name} body's "
            f"{n_ax - 1} axial rim faces (the mortar weights are exact only then; "
            "docs/hybrid.md, 'Mortar patch test'): "
            "use a multiple of the face count with the body's rim width equal to the mesh face "
            f"width ({b * 1e3:.6g} mm)"
        )
    dof = body_dof_index(body)
    rim_dofs = np.array(
        [
            [[gidx[dof[(int(grid[k, j]), c)]] for c in range(3)] for j in range(n_ax)]
            for k in range(Z)
        ]
    )
    at = pair.transverse_pressure_angle
    psi_b = pair.reference_thickness[member] / (2 * pair.pitch_radii[member]) + involute(at)
    if ratio is None:
        ratio = 1.0 if member == 0 else pair.pinion.teeth / pair.gear.teeth
    if spin is None:
        spin = 1.0 if member == 0 else -1.0
    psi_f = _root_angle(pair, member)
    n_window = rim_window(pair, member) if place.n_window is None else place.n_window
    offset = place.offset
    if offset is None:
        offset = _station_offset(pair, member, mesh, line, place, (ang[0], pitch, psi_b))
    return FlexibleMember(
        centre=centre,
        rim_dofs=rim_dofs,
        body_dofs=np.asarray(gidx),
        z_nodes=z_nodes,
        station0=float(ang[0]),
        pitch_angle=pitch,
        rim_radius=radius,
        root_half_angle=psi_f,
        base_radius=pair.base_radii[member],
        base_half_angle=psi_b,
        offset=offset,
        ratio=float(ratio),
        spin=float(spin),
        n_window=n_window,
    )


def _station_offset(pair, member, mesh, line, place, stations) -> Float[Array, ""]:
    """The body frame's angle φ_0 at θ = 0 (rad) that puts on a rim station the centre line of
    the tooth whose flank carries a contact line at mid-face (a point of the line of action is
    on a flank only where a contact line is): :func:`flexible_member`'s frame. ``stations``:
    (the angle of station 0, the pitch 2π/Z, ψ_b) (rad)."""
    angle0, pitch, psi_b = stations
    b = float(mesh.face_width)
    pb = float(mesh.base_pitch)
    s_mid = float(mesh.base_radius_pinion) * place.mesh_angle - 0.5 * b * math.tan(
        float(mesh.base_helix_angle)
    )
    s_mid += pb * round((0.5 * float(mesh.path_of_contact) - s_mid) / pb)
    t = np.asarray(line["direction"], float)
    point = np.asarray(line["zone"], float) + (s_mid - 0.5 * float(mesh.path_of_contact)) * t
    flank = loaded_flank(place.centre, line, 1.0 if member == 0 else -1.0)
    phi_c = float(
        tooth_centre_angle(
            as_float(place.centre),
            as_float(pair.base_radii[member]),
            as_float(psi_b),
            jnp.asarray(point),
            flank,
        )
    )
    k = round((phi_c - float(angle0)) / pitch)
    return as_float(phi_c - float(angle0) - k * pitch)
