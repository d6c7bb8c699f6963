"""Hybrid scene: condensed FE gear bodies coupled to the contact cells (seed II-2).

A member of the lumped 3D scene (:mod:`._lumped3d`) is either a rigid gear node (seed (2.9)) or a
*flexible body* condensed by :mod:`fem_prep` on its rim master nodes (the outer rim face under
the teeth, r = root radius, one station per tooth), its bearing nodes and modal coordinates. The
body's bearing master nodes are merged with the shaft nodes at the gear position plus their
axial offset; its rigid gear node and inertia go.

Interface of a cell M on a flexible member (seed (2.11)–(2.30); docs/hybrid.md, "The interface"):

* the tooth in contact at M is a rigid transverse slice rooted on the rim at two root points
  M_p1, M_p2 (where the tooth's fillets meet the root circle, at ±ψ_f about its centre line);
* the root displacement u(M_p) = (u_1 + u_2)/2 and rotation ω = κ·(u_1 − u_2) (least squares
  (2.12)–(2.18), κ = (M_p1M_p2 × Z)/|M_p1M_p2|², M_p the chord midpoint [R]: a rigid rotation
  about the axis is then reproduced exactly; M_p1, M_p2 are taken on the (flat) rim face, i.e.
  projected on its chord, so that the face interpolation reproduces rigid motions exactly) give u(M)·n_m = c_1·u_1 + c_2·u_2 with
  c_{1,2} = n_m/2 ± λ κ, λ = Z·(M_pM × n_m) (2.19)–(2.20), n_m the member's outward normal
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
The shaft that carries a body is taken in the same rotating frame (shafts and bearings are
axisymmetric: their stiffness does not change), so the structure is factored once.

Statics in the space of the cells (:func:`jaxgear.solve_contact_cells`): the structure is
factored once (the compliance G on the complement of the drive rotation, the output torque
rotation held), and a position only needs the compliance of the window of master DOFs under the
contact, C = V_W G_WW V_Wᵀ: an active-set pass costs cells², not masters³.
"""

from __future__ import annotations

import dataclasses
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.linalg as sla
from jaxtyping import Array, Float, Int

from .._baseplane import CellRow, Cells, MeshModel
from .._contact import ContactLaw, solve_contact_cells
from .._geometry import GearPair, involute
from .._stiffness import _chordal_thickness, _root_angle
from .._util import as_float
from ._lumped3d import ShaftSpec, _lumped_arrays, contact_points, rigid_node_vector
from ._scene import Scene

__all__ = ["FlexibleMember", "HybridPair", "RigidMember", "hybrid_pair", "mortar_weights"]

MORTAR = (5.0 / 30.0, 20.0 / 30.0, 5.0 / 30.0)  # (2.26)-(2.27): Simpson on the slice


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


class RigidMember(eqx.Module):
    """A rigid gear body at a 6-DOF shaft node: V = [n_m, (M − O) × n_m] (seed (2.9))."""

    centre: Float[Array, " 3"] = eqx.field(converter=as_float)
    sign: float = eqx.field(static=True)  # +1 pinion (n_m = n), -1 gear (n_m = -n)
    dofs: tuple = eqx.field(static=True)  # the node's 6 global DOFs

    @property
    def width(self) -> int:
        return 6

    def window(self, points, mask, line, theta, mesh, pad=0):
        """Global DOFs (6,), structure vectors on them (L, N, 6), no overflow (``pad``: unused,
        the node's DOFs are the whole window)."""
        v = rigid_node_vector(points, self.centre, self.sign * line["normal"])
        return jnp.asarray(self.dofs), v, jnp.array(False)


class FlexibleMember(eqx.Module):
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
            circle, ψ(r) = ψ_b − inv(arccos(r_b/r)) (rad). offset: φ_0 (rad). z_offset: body z
            of the mesh face centre (m).
        sign: +1 pinion, −1 gear. flank: ±1, the side of the contact point where the tooth
            centre line lies (angle φ_c = φ_M + flank ψ(r_M)). spin: ±1 and ratio: θ_member =
            ratio θ turned in the ``spin`` sense about z. n_window: stations in the window.
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
    z_offset: Float[Array, ""] = eqx.field(converter=as_float)
    ratio: Float[Array, ""] = eqx.field(converter=as_float)
    sign: float = eqx.field(static=True)
    flank: float = eqx.field(static=True)
    spin: float = eqx.field(static=True)
    n_window: int = eqx.field(static=True)

    @property
    def width(self) -> int:
        return self.n_window * self.z_nodes.shape[0] * 3

    def frame_angle(self, theta):
        """φ_rot: angle of the body frame in the fixed frame at pinion angle θ (rad)."""
        return self.offset + self.spin * self.ratio * theta

    def tooth_centre_angle(self, points):
        """Fixed-frame polar angle of the centre line of the tooth in contact at ``points``."""
        m = points - _lead(self.centre, points)
        r = jnp.maximum(jnp.hypot(m[..., 0], m[..., 1]), self.base_radius)
        a = jnp.arccos(self.base_radius / r)
        psi = self.base_half_angle - (jnp.tan(a) - a)
        return jnp.arctan2(m[..., 1], m[..., 0]) + self.flank * psi

    def coefficients(self, points, normal, p1, p2):
        """c_1, c_2 (fixed frame, (..., 3) each) of (2.19)-(2.20) for contact points M (..., 3)
        and root points M_p1, M_p2 (fixed frame, in-plane, (..., 2))."""
        mp = 0.5 * (p1 + p2)  # chord midpoint [R]: exact for a rigid rotation
        d = p2 - p1
        kappa = jnp.stack([d[..., 1], -d[..., 0], jnp.zeros_like(d[..., 0])], -1)
        kappa = kappa / jnp.sum(d * d, axis=-1, keepdims=True)  # (M_p1M_p2 × Z)/|M_p1M_p2|²
        nm = self.sign * jnp.broadcast_to(normal, points.shape)
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

    def window(self, points, mask, line, theta, mesh: MeshModel, pad: int = 0):
        """Global DOFs of the window (w,), the structure vectors on them (L, N, w) and whether a
        cell on the flanks reaches beyond the window (the builder checks that it never does).
        ``pad``: stations added on each side of the window (the wider window that holds every
        window of a mesh period, for the mesh damping that turns with the wheel).

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
        phi_c = self.tooth_centre_angle(pts) - rot  # body frame, (L, N, 3)
        psi = self.root_half_angle
        phi = jnp.stack([phi_c - psi, phi_c + psi], axis=-2)  # (L, N, 2 points, 3 nodes)
        zb = jnp.broadcast_to((pts[..., 2] + self.z_offset)[..., None, :], phi.shape)
        i, j, w, face = self.face_weights(phi, zb)
        # root points M_p1, M_p2 on the face at the slice centre, in the fixed frame
        pk = _rot(rot, jnp.concatenate([face[..., 1, :], jnp.zeros_like(face[..., 1, :1])], -1))
        pk = pk[..., :2] + _lead(self.centre[:2], pk[..., :2])  # (L, N, 2, 2)
        c1, c2 = self.coefficients(points, line["normal"], pk[..., 0, :], pk[..., 1, :])
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


class HybridPair(Scene):
    """The lumped 3D scene with condensed FE bodies (H1: flexible wheel; H2: both flexible).

    Build with :func:`hybrid_pair`. Generalised coordinates: pinion shaft, gear shaft (6 per
    node), then each body's rim master and modal DOFs (its bearing nodes are shaft nodes).

    Attributes:
        mesh: the gear mesh. members: (pinion, gear) as :class:`RigidMember` or
            :class:`FlexibleMember`. K, M: structure stiffness and mass (n, n) (bodies, shafts,
            rigid gear nodes, the teeth lumped on the rim nodes). G: compliance on the
            complement of the drive rotation with the output rotation held (n, n). N: the drive
            rotation, scaled to a unit base-plane approach (n, 1). f_torque: load per unit pinion
            torque (n,). f_centrifugal: load per unit (pinion speed)² (n,). x_torque, x_centrifugal:
            G f_torque, G f_centrifugal (the pinion speed Ω is an argument of the methods
            and solvers that load the scene, never a field of it). te: TE vector u (u·X, m) at the gear positions of the shafts. te_compliance: G u.
            reaction: bearing force
            rows (r, n). tangent_point, direction, normal, roll_start: the line of action.
            C_bearing: assembled bearing damping on the shaft DOFs (the first s coordinates),
            shape (s, s) (:meth:`bearing_damping` pads it to (n, n)).
            gyroscopic, spin_stiffness: the rotating-frame inertia of the members whose frames
            turn (a flexible body and its shaft): the dynamics add Ω·gyroscopic·Ẋ (Coriolis,
            skew) and Ω²·spin_stiffness·X (spin softening plus the centrifugal stress
            stiffening) at pinion speed Ω, both (n, n) per unit pinion speed (squared)
            (:func:`rotating_frame_matrices`).
    """

    mesh: MeshModel
    members: tuple
    K: Float[Array, "n n"]
    M: Float[Array, "n n"]
    G: Float[Array, "n n"]
    N: Float[Array, "n 1"]
    f_torque: Float[Array, " n"]
    f_centrifugal: Float[Array, " n"]
    x_torque: Float[Array, " n"]
    x_centrifugal: Float[Array, " n"]
    te: Float[Array, " n"]
    te_compliance: Float[Array, " n"]
    reaction: Float[Array, "r n"]
    tangent_point: Float[Array, " 3"]
    direction: Float[Array, " 3"]
    normal: Float[Array, " 3"]
    roll_start: Float[Array, ""]
    C_bearing: Float[Array, "s s"]
    gyroscopic: Float[Array, "n n"]
    spin_stiffness: Float[Array, "n n"]
    reaction_names: tuple = eqx.field(static=True)
    reaction_member: tuple = eqx.field(static=True)
    torque_dofs: tuple = eqx.field(static=True)

    # -- the generic Scene interface (X space; for checks and small problems) --------------
    def stiffness(self):
        return self.K

    def mass(self):
        """Mass matrix (n, n) (kg, kg·m²) of the assembled structure (bodies, teeth, shafts)."""
        return self.M

    def stiffness_parts(self):
        """The structure stiffness as one part (the modal analysis's energy shares: mesh vs
        structure, seed (2.36))."""
        return {"structure": self.K}

    def bearing_damping(self) -> Float[Array, "n n"]:
        """Assembled bearing damping matrix (units of K·s), shape (n, n), zeros without bearing
        damping; to be added to the damping matrix C of the dynamics. On the shaft of a flexible
        member it acts in the body frame (the bearings there are axisymmetric, checked by
        :func:`hybrid_pair`); the rotating-frame term Ω C J of a fixed damper is neglected, as the
        seed neglects gyroscopic terms."""
        n, s = self.K.shape[0], self.C_bearing.shape[0]
        return jnp.zeros((n, n), self.K.dtype).at[:s, :s].set(self.C_bearing)

    def external_load(self, torque, speed=0.0):
        """Generalised external forces (n,) at pinion torque T (N·m) and pinion speed Ω (rad/s):
        T f_torque + Ω² f_centrifugal (each body at its own speed, (2.37))."""
        return torque * self.f_torque + speed**2 * self.f_centrifugal

    def points(self, cells: Cells):
        """Fixed-frame contact points M of the cells (m), shape (L, N, 3)."""
        return contact_points(self.tangent_point, self.direction, self.roll_start, self.mesh, cells)

    def line(self):
        """The line of action: ``normal`` n, ``direction`` t and the zone centre (fixed frame)."""
        zone = self.tangent_point + (self.roll_start + 0.5 * self.mesh.path_of_contact) * (
            self.direction
        )
        return {"normal": self.normal, "direction": self.direction, "zone": zone}

    def window(self, cells: Cells, pad: int = 0):
        """Window DOFs (w,) and structure vectors on them (L, N, w), masked cells zeroed;
        ``pad`` rim stations more on each side of a flexible member's window."""
        P = self.points(cells)
        line = self.line()
        parts = [m.window(P, cells.mask, line, cells.theta, self.mesh, pad) for m in self.members]
        idx = jnp.concatenate([p[0] for p in parts])
        V = jnp.concatenate([p[1] for p in parts], axis=-1)
        return idx, jnp.where(cells.mask[..., None], V, 0.0)

    def window_overflow(self, cells: Cells):
        """True if a cell on the flanks reaches a rim station beyond its member's window."""
        P = self.points(cells)
        line = self.line()
        return jnp.any(
            jnp.stack(
                [m.window(P, cells.mask, line, cells.theta, self.mesh)[2] for m in self.members]
            )
        )

    def cell_vectors(self, cells):
        idx, Vw = self.window(cells)
        V = jnp.zeros(cells.s.shape + (self.K.shape[0],), self.K.dtype)
        return V.at[..., idx].add(Vw)

    def te_vector(self):
        return self.te

    # -- the cell space -----------------------------------------------------------------------
    def cell_space(self, cells: Cells, torque, speed=0.0):
        """C, a0 = V G F, E = V N, b = Nᵀ F and the window (for the recovery of X), F the
        external load at pinion torque T (N·m) and speed Ω (rad/s)."""
        idx, Vw = self.window(cells)
        c = Vw.shape[0] * Vw.shape[1]
        Vw = Vw.reshape(c, -1)
        Gw = self.G[idx[:, None], idx[None, :]]
        x0 = torque * self.x_torque + speed**2 * self.x_centrifugal
        C = Vw @ Gw @ Vw.T
        a0 = Vw @ x0[idx]
        E = Vw @ self.N[idx]
        b = self.N.T @ self.external_load(torque, speed)
        return C, a0, E, b, (idx, Vw, x0)

    def static_contact(self, cells: Cells, delta0, torque, speed, law: ContactLaw):
        """The static contact at one mesh position in the space of the cells
        (:func:`jaxgear.solve_contact_cells` on :meth:`cell_space`, the centrifugal load at
        pinion speed ``speed``): (the contact solution, X (n,), u·X (m)); the arguments are
        those of :meth:`jaxgear.scenes.Scene.static_contact`."""
        C, a0, E, b, window = self.cell_space(cells, torque, speed)
        r = CellRow.of(cells, window[1], delta0, window[0])
        sol, force, alpha = solve_contact_cells(C, a0 - r.delta0, E, b, r.k, r.length, r.mask, law)
        return sol, self.recover(window, force, alpha), self.te_recover(window, force, alpha)

    def bearing_forces(self, theta, x):
        """Bearing force components k u (N), fixed frame, shape (P, r), at pinion angles θ (P,)
        and coordinates x (P, n): a flexible member's shaft turns with its body, so its in-plane
        forces are rotated back by the body frame angle."""
        F = x @ self.reaction.T
        names = self.reaction_names
        for m, member in enumerate(self.members):
            if not isinstance(member, FlexibleMember):
                continue
            ang = member.frame_angle(theta)
            for i, name in enumerate(names):
                if self.reaction_member[i] != m or not name.endswith("Fx"):
                    continue
                j = names.index(name[:-1] + "y") if name[:-1] + "y" in names else None
                if j is None:
                    continue
                fx, fy = F[:, i], F[:, j]
                c, s_ = jnp.cos(ang), jnp.sin(ang)
                F = F.at[:, i].set(c * fx - s_ * fy).at[:, j].set(s_ * fx + c * fy)
        return F

    def rim_radial_growth(self, speed):
        """Mean radial displacement (m) of each flexible member's rim master nodes under the
        centrifugal load alone at pinion speed ``speed`` (rad/s); 0 for a rigid member.
        Returns a tuple (pinion, gear)."""
        x = speed**2 * self.x_centrifugal
        out = []
        for member in self.members:
            if not isinstance(member, FlexibleMember):
                out.append(jnp.zeros((), x.dtype))
                continue
            u = x[member.rim_dofs]  # (Z, n_ax, 3), body frame
            Z = member.rim_dofs.shape[0]
            ang = member.station0 + member.pitch_angle * jnp.arange(Z)
            ur = u[..., 0] * jnp.cos(ang)[:, None] + u[..., 1] * jnp.sin(ang)[:, None]
            out.append(jnp.mean(ur))
        return tuple(out)

    def recover(self, window, P, alpha):
        """X = G (F − Vᵀ P) + N α from the cell forces P (c,) and the rigid amplitudes α."""
        idx, Vw, x0 = window
        z = jnp.zeros_like(x0).at[idx].add(Vw.T @ P)
        return x0 - self.G @ z + self.N @ alpha

    def te_recover(self, window, P, alpha):
        """u·X (m) without recovering X: u·X0 − (G u)_W·(V_Wᵀ P) + (u·N) α."""
        idx, Vw, x0 = window
        return self.te @ x0 - self.te_compliance[idx] @ (Vw.T @ P) + (self.te @ self.N) @ alpha


# ------------------------------------------------------------------------------------------
# builder (NumPy, once per scene)


def _body_dof_index(body) -> dict:
    """(master, component) → condensed DOF index of a fem_prep body."""
    dm = np.asarray(body.dof_map)
    return {(int(m), int(c)): i for i, (m, c) in enumerate(dm) if m >= 0}


def _tooth_mass(pair: GearPair, member: int, density: float, width: float):
    """Mass (kg) and centroid radius (m) of one tooth above the root circle (the part of the
    gear that the FE body, meshed up to the root circle, does not have) [R]."""
    rf, ra = pair.root_radii[member], pair.tip_radii[member]
    x, w = np.polynomial.legendre.leggauss(64)
    r = rf + 0.5 * (x + 1) * (ra - rf)
    w = 0.5 * w * (ra - rf)
    d = _chordal_thickness(pair, member, r)
    area = float(np.sum(w * d))
    return density * area * width, float(np.sum(w * d * r)) / area


def _flexible_member(pair, member, body, gidx, centre, line, mesh, n_window=None):
    coords = np.asarray(body.master_coords, float)
    grid = np.asarray(body.rim_grid)
    Z, n_ax = grid.shape
    teeth = (pair.pinion, pair.gear)[member].teeth
    name = ("pinion", "gear")[member]
    if Z != teeth:
        raise ValueError(
            f"scene.{name}_body: the body has {Z} rim stations, the {name} {teeth} teeth "
            "(fem_prep [condensation] teeth must equal the gear's teeth)"
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
    z_nodes = coords[grid[0], 2]
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
    dof = _body_dof_index(body)
    rim_dofs = np.array(
        [
            [[gidx[dof[(int(grid[k, j]), c)]] for c in range(3)] for j in range(n_ax)]
            for k in range(Z)
        ]
    )
    at = pair.transverse_pressure_angle
    psi_b = pair.reference_thickness[member] / (2 * pair.pitch_radii[member]) + involute(at)
    sign = 1.0 if member == 0 else -1.0
    normal = np.asarray(line["normal"])
    zone = np.asarray(line["zone"])
    # tooth material side of the contact: -n for the driving pinion, +n for the gear
    side = -sign * normal
    rz = zone - centre
    e_phi = np.array([-rz[1], rz[0], 0.0]) / math.hypot(rz[0], rz[1])
    flank = float(np.sign(e_phi @ side))
    ratio = 1.0 if member == 0 else pair.pinion.teeth / pair.gear.teeth
    spin = 1.0 if member == 0 else -1.0
    eps = pair.transverse_contact_ratio + pair.overlap_ratio
    psi_f = _root_angle(pair, member)
    if n_window is None:
        n_window = math.ceil(eps + 2 * psi_f / pitch) + 2
    fm = FlexibleMember(
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
        offset=0.0,
        z_offset=0.0,
        ratio=ratio,
        sign=sign,
        flank=flank,
        spin=spin,
        n_window=n_window,
    )
    # frame offset: at θ = 0 the tooth in contact at the zone centre (mid-face) is on a station
    phi_c = float(fm.tooth_centre_angle(jnp.asarray(zone)))
    k = round((phi_c - float(ang[0])) / pitch)
    return eqx.tree_at(lambda f: f.offset, fm, as_float(phi_c - float(ang[0]) - k * pitch))


def hybrid_pair(
    pair: GearPair,
    mesh: MeshModel,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    *,
    bodies: tuple,
    masses: tuple,
    inertias: tuple,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    density: float = 7800.0,
    tooth_mass: bool = True,
) -> HybridPair:
    """Assemble the hybrid scene: the lumped 3D scene with condensed bodies (H1, H2).

    Args:
        pair, mesh: the gear pair and its mesh model (its stiffness table must leave out the
            foundation term of a flexible member: the FE rim replaces it, seed after (2.31)).
        pinion_shaft, gear_shaft: the shafts (:class:`ShaftSpec`).
        bodies: (pinion, gear): ``None`` (rigid gear node) or a condensed body
            (:class:`fem_prep.CondensedBody` or any object with ``K``, ``M``, ``f_centrifugal``,
            ``master_coords``, ``master_kind``, ``rim_grid``, ``dof_map``; SI, body frame: axis
            z, z = 0 at mid-rim, rim station k at angle 2πk/Z). Each bearing node of a body is
            merged with the shaft node at ``gear_z`` + its axial position.
        masses, inertias: rigid gear bodies (as :func:`lumped_pair`); ignored for a flexible one.
        youngs_modulus, poisson_ratio, density: shaft material (density also for the teeth).
        tooth_mass: add the mass and centrifugal load of the teeth (not in the FE body, which
            ends at the root circle) on the rim master nodes [R].

    Raises:
        ValueError: body/gear mismatch (teeth, root radius), a bearing node off the axis or
            outside its shaft, a structure with a rigid-body mode other than the drive rotation,
            a bearing stiffness or damping matrix on a flexible body's shaft that is not
            axisymmetric about z (that shaft turns with the body frame).
    """
    shafts = (pinion_shaft, gear_shaft)
    extra = []
    for m, body in enumerate(bodies):
        if body is None:
            extra.append(())
            continue
        # the shaft of a flexible body is in the turning body frame: its bearings must look the
        # same from every angle, i.e. commute with a quarter turn about z (K_xx = K_yy, ...)
        q = np.zeros((6, 6))
        q[0, 1] = q[3, 4] = -1.0
        q[1, 0] = q[4, 3] = q[2, 2] = q[5, 5] = 1.0
        for i, b in enumerate(shafts[m].bearings):
            for what, a in (("stiffness", b.stiffness_matrix()), ("damping", b.damping_matrix())):
                dg = np.abs(np.diag(a))
                scale = np.maximum(np.sqrt(np.outer(dg, dg)), np.abs(a))
                if np.any(np.abs(q @ a @ q.T - a) > 1e-6 * np.maximum(scale, scale.T)):
                    raise ValueError(
                        f"scene.{('pinion', 'gear')[m]}_shaft.bearings[{i}]: its {what} matrix "
                        "is not axisymmetric about the shaft axis (allowed on the shaft of a "
                        "flexible body, which turns with the body frame: e.g. K_xx = K_yy, "
                        "K_xy = 0, K[3][3] = K[4][4], K[0][4] = -K[1][3], no x/y-z coupling)"
                    )
        coords = np.asarray(body.master_coords, float)
        kind = np.asarray(body.master_kind)
        bz = coords[kind == 1]
        if bz.size == 0 or np.any(np.hypot(bz[:, 0], bz[:, 1]) > 1e-9):
            raise ValueError(
                f"scene.{('pinion', 'gear')[m]}_body: the body needs bearing nodes on its axis"
            )
        extra.append(tuple(shafts[m].gear_z + bz[:, 2]))
    masses = tuple(None if b is not None else ms for b, ms in zip(bodies, masses, strict=True))
    d = _lumped_arrays(
        pair,
        pinion_shaft,
        gear_shaft,
        masses,
        inertias,
        youngs_modulus,
        poisson_ratio,
        density,
        extra_z=tuple(extra),
    )
    n_sh = d["M"].shape[0]
    blocks_K, blocks_M, fc_parts, gidxs, rot_parts = [], [], [], [], []
    n = n_sh
    ratio = pair.pinion.teeth / pair.gear.teeth
    for m, body in enumerate(bodies):
        if body is None:
            gidxs.append(None)
            continue
        coords = np.asarray(body.master_coords, float)
        kind = np.asarray(body.master_kind)
        dm = np.asarray(body.dof_map)
        nc = dm.shape[0]
        gidx = np.full(nc, -1)
        zs, off = d["shaft_z"][m], d["shaft_offsets"][m]
        for i, (mi, c) in enumerate(dm):
            if mi >= 0 and kind[mi] == 1:
                node = int(np.argmin(np.abs(zs - (shafts[m].gear_z + coords[mi, 2]))))
                gidx[i] = off + 6 * node + int(c)
        free = np.flatnonzero(gidx < 0)
        gidx[free] = n + np.arange(free.size)
        n += free.size
        K_b = np.array(body.K, float)
        M_b = np.array(body.M, float)
        f_b = np.array(body.f_centrifugal, float)
        Mb0 = M_b.copy()
        if tooth_mass:
            mt, rt = _tooth_mass(pair, m, density, float(np.ptp(coords[body.rim_grid[0], 2])))
            zn = coords[body.rim_grid[0], 2]
            share = np.zeros(zn.size)  # trapezoid weights across the face
            share[:-1] += 0.5 * np.diff(zn)
            share[1:] += 0.5 * np.diff(zn)
            share /= share.sum()
            dof = _body_dof_index(body)
            for k in range(body.rim_grid.shape[0]):
                for j in range(zn.size):
                    mi = int(body.rim_grid[k, j])
                    e = coords[mi, :2] / np.hypot(*coords[mi, :2])
                    for c in range(3):
                        M_b[dof[(mi, c)], dof[(mi, c)]] += mt * share[j]
                    for c in range(2):
                        f_b[dof[(mi, c)]] += mt * share[j] * rt * e[c]
        blocks_K.append((gidx, K_b))
        blocks_M.append((gidx, M_b))
        rot_parts.append((m, gidx, _body_rotating(body, M_b - Mb0)))
        fc_parts.append((gidx, f_b * (1.0 if m == 0 else ratio) ** 2))
        gidxs.append(gidx)
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    K[:n_sh, :n_sh] = d["parts"].sum(axis=0)
    M[:n_sh, :n_sh] = d["M"]
    fc = np.zeros(n)
    for (g, Kb), (_, Mb), (_, fb) in zip(blocks_K, blocks_M, fc_parts, strict=True):
        K[np.ix_(g, g)] += Kb
        M[np.ix_(g, g)] += Mb
        fc[g] += fb
    gyro, spin_K = _rotating_frame(n, d, rot_parts, ratio)
    pad = lambda a: np.concatenate([a, np.zeros(a.shape[:-1] + (n - n_sh,))], axis=-1)
    rb1, rb2 = pair.base_radii
    cb = math.cos(pair.base_helix_angle)
    g1, g2 = d["gear_dofs"]
    t_in, t_out = d["torque_dofs"]
    f_t = np.zeros(n)
    f_t[t_in] += 1.0
    f_t[t_out] += rb2 / rb1
    te = np.zeros(n)
    te[g1 + 5], te[g2 + 5] = cb * rb1, cb * rb2
    # the drive rotation (pinion chain), scaled to a unit base-plane approach
    Nv = np.zeros(n)
    n1 = d["shaft_offsets"][1]
    Nv[5:n1:6] = 1.0 / rb1
    if bodies[0] is not None:
        body, g = bodies[0], gidxs[0]
        coords = np.asarray(body.master_coords, float)
        for i, (mi, c) in enumerate(np.asarray(body.dof_map)):
            if mi >= 0 and body.master_kind[mi] == 0 and c < 2:
                x, y = coords[mi, :2]
                Nv[g[i]] = (-y if c == 0 else x) / rb1
    scale = np.max(np.abs(np.diag(K)))
    if np.linalg.norm(K @ Nv) > 1e-7 * scale * np.linalg.norm(Nv):
        raise ValueError("hybrid scene: the pinion chain does not turn freely (internal error)")
    keep = np.setdiff1d(np.arange(n), [t_out])
    Nh = Nv[keep] / np.linalg.norm(Nv)
    A = K[np.ix_(keep, keep)] + np.mean(np.diag(K)) * np.outer(Nh, Nh)
    try:
        factor = sla.cho_factor(A)
    except np.linalg.LinAlgError:
        raise ValueError(
            "hybrid scene: the structure has a rigid-body mode besides the drive rotation "
            "(check the bearings: radial and axial support of both shafts)"
        ) from None
    G = np.zeros((n, n))
    G[np.ix_(keep, keep)] = sla.cho_solve(factor, np.eye(keep.size))
    G = 0.5 * (G + G.T)
    react_member = tuple(0 if nm.startswith("pinion") else 1 for nm in d["reaction_names"])
    centres = d["centres"]
    scene = HybridPair(
        mesh=mesh,
        members=(None, None),
        K=jnp.asarray(K),
        M=jnp.asarray(M),
        G=jnp.asarray(G),
        N=jnp.asarray(Nv[:, None]),
        f_torque=jnp.asarray(f_t),
        f_centrifugal=jnp.asarray(fc),
        x_torque=jnp.asarray(G @ f_t),
        x_centrifugal=jnp.asarray(G @ fc),
        te=jnp.asarray(te),
        te_compliance=jnp.asarray(G @ te),
        reaction=jnp.asarray(pad(d["reaction"])),
        tangent_point=jnp.asarray(d["tangent_point"]),
        direction=jnp.asarray(d["direction"]),
        normal=jnp.asarray(d["normal"]),
        roll_start=jnp.asarray(pair.start_roll),
        C_bearing=jnp.asarray(d["bearing_C"]),
        gyroscopic=jnp.asarray(gyro),
        spin_stiffness=jnp.asarray(spin_K),
        reaction_names=d["reaction_names"],
        reaction_member=react_member,
        torque_dofs=d["torque_dofs"],
    )
    line = {k: np.asarray(v) for k, v in scene.line().items()}
    members = []
    for m, body in enumerate(bodies):
        if body is None:
            g = d["gear_dofs"][m]
            members.append(
                RigidMember(
                    jnp.asarray(centres[m]), 1.0 if m == 0 else -1.0, tuple(range(g, g + 6))
                )
            )
        else:
            members.append(
                _flexible_member(pair, m, body, gidxs[m], jnp.asarray(centres[m]), line, mesh)
            )
    scene = eqx.tree_at(lambda s: s.members, scene, tuple(members), is_leaf=lambda x: x is None)
    return _fit_windows(scene)


_J6 = np.zeros((6, 6))
_J6[1, 0] = _J6[4, 3] = 1.0  # ez × (.) on the translations and on the rotation vector
_J6[0, 1] = _J6[3, 4] = -1.0


def _body_rotating(body, added_mass):
    """The body's rotating-frame matrices per unit spin speed about +z (condensed DOFs):
    (Coriolis Gy, spin softening + stress stiffening S + Kσ), from fem_prep, plus the lumped
    tooth masses ``added_mass`` (n_c, n_c) on the rim nodes: Gy += m J, and S −= m e eᵀ on the
    radial direction e only. A tooth's centrifugal force turns with the rim that carries it
    (the load stiffness of the rim's hoop prestress from the teeth, which the body's Kσ does not
    hold), so a rigid turn about the axis stays neutral; the rest of that prestress's stiffening
    is left out. A duck-typed body without the fem_prep matrices contributes only its teeth."""
    nc = np.asarray(body.K).shape[0]
    gy = np.array(getattr(body, "gyroscopic", np.zeros((nc, nc))), float)
    sk = np.zeros((nc, nc))
    for key in ("spin_softening", "stress_stiffening"):
        part = getattr(body, key, None)
        if part is not None:
            sk += np.asarray(part, float)
    dof = _body_dof_index(body)
    kind = np.asarray(body.master_kind)
    coords = np.asarray(body.master_coords, float)
    for (mi, c), i in dof.items():
        if c != 0 or kind[mi] != 0:
            continue
        j = dof[(mi, 1)]
        mt = added_mass[i, i]
        gy[j, i] += mt
        gy[i, j] -= mt
        e = coords[mi, :2] / np.hypot(*coords[mi, :2])
        sk[np.ix_([i, j], [i, j])] -= mt * np.outer(e, e)
    return gy, sk


def _rotating_frame(n, d, parts, ratio):
    """Gyroscopic (n, n) per unit pinion speed and spin stiffness (n, n) per unit pinion speed²
    of the members whose frames turn: each flexible body at Ω_z = spin·ratio·Ω (the pinion +Ω,
    the gear −Ω z1/z2) and the shaft that carries it.

    The rotating-frame equations of a body turning at Ω_z about +z: M Ẍ + 2 Ω_z Gy Ẋ + (K +
    Ω_z² (S + Kσ)) X = … (Coriolis, spin softening, centrifugal stress stiffening; fem_prep
    condenses Gy, S, Kσ of the FE body). A shaft on the axis is axisymmetric: its fixed-frame
    model seen from the turning frame gives Gy = M J and S = −M P (J = ez × on the translations
    and the rotation vector, P = J ᵀJ), with no polar gyroscopic term (as the lumped model)."""
    gyro = np.zeros((n, n))
    spin_K = np.zeros((n, n))
    offsets = (*d["shaft_offsets"], d["M"].shape[0])
    for m, gidx, (gy, sk) in parts:
        w = 1.0 if m == 0 else -ratio  # Ω_z per unit pinion speed
        gyro[np.ix_(gidx, gidx)] += 2.0 * w * gy
        spin_K[np.ix_(gidx, gidx)] += w * w * sk
        a, b = offsets[m], offsets[m + 1]
        Ms = d["M"][a:b, a:b]
        J = np.kron(np.eye((b - a) // 6), _J6)
        if np.abs(Ms @ J - J @ Ms).max() > 1e-9 * np.abs(Ms).max():
            raise ValueError("hybrid scene: a flexible body's shaft mass is not axisymmetric")
        gyro[a:b, a:b] += 2.0 * w * Ms @ J
        spin_K[a:b, a:b] += w * w * (Ms @ J @ J)
    return gyro, spin_K


def _fit_windows(scene: HybridPair, tries: int = 4) -> HybridPair:
    """The window estimate (stations spanned by the contact zone and the root points) checked
    over two mesh periods and widened while a cell reaches beyond it."""
    for _ in range(tries):
        if not _windows_overflow(scene):
            return scene
        members = tuple(
            dataclasses.replace(m, n_window=m.n_window + 1) if isinstance(m, FlexibleMember) else m
            for m in scene.members
        )
        scene = eqx.tree_at(lambda s: s.members, scene, members)
    raise ValueError("hybrid scene: the contact zone does not fit a rim window (internal error)")


def _windows_overflow(scene: HybridPair, samples: int = 48) -> bool:
    """Whether a cell on the flanks reaches beyond its member's window over two mesh periods."""
    mesh = scene.mesh
    thetas = (np.arange(2 * samples) + 0.5) * float(mesh.mesh_period_angle) / samples
    over = jax.jit(jax.vmap(lambda th: scene.window_overflow(mesh.cells(th))))(
        jnp.asarray(thetas, scene.K.dtype)
    )
    return bool(np.any(np.asarray(over)))
