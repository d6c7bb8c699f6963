"""Hybrid scene: condensed FE gear bodies coupled to the contact cells (seed II-2).

A gear member of the lumped 3D scene (:mod:`._lumped3d`) is either a rigid gear node (seed (2.9))
or a *flexible body* condensed by :mod:`fem_prep` on its rim master nodes (the outer rim face under
the teeth, r = root radius, one station per tooth), its bearing nodes and modal coordinates; the
interface of a cell with either is :mod:`._interface` (docs/hybrid.md, "The interface"). The
body's bearing master nodes are merged with the shaft nodes at the gear position plus their
axial offset; its rigid gear node and inertia go.

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
from typing import NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import scipy.linalg as sla
from jaxtyping import Array, Bool, Float, Int

from .._baseplane import CellRow, Cells, MeshModel, mesh_positions
from .._cell_factor import line_factors, solve_factored_cells
from .._contact import ContactLaw, ExactContact, solve_contact_cells
from .._geometry import GearPair
from .._stiffness import tooth_mass as one_tooth_mass
from ._gear_mesh import line_of_action, mesh_line, only_mesh, pair_mesh
from ._interface import (
    FlexibleMember,
    RigidMember,
    body_dof_index,
    body_rims,
    flexible_member,
    rim_mid_z,
    rim_window,
)
from ._lumped3d import ShaftSpec, _lumped_arrays, _train_arrays, train_meshes
from ._structure import AssembledScene, Structure

__all__ = [
    "HybridPair",
    "HybridScene",
    "WindowCompliance",
    "cache_window_compliance",
    "hybrid_pair",
    "hybrid_train",
    "window_compliance",
]


class WindowCompliance(eqx.Module):
    """The parts of the cell-space contact problem that depend on the scene and the position
    only, at P positions (:func:`window_compliance`): not on the modifications, the torque, the
    speed or the contact law, so a map, a torque sweep or an optimisation reuses them
    (docs/hybrid.md, "Statics in the cell space"). A quasi-static solve at these positions
    reads one slice per position (the leading axis P; a slice has ``theta`` of shape ()).

    Attributes:
        theta: the scene angles (rad), (P,). idx: each position's window W (P, w).
        V: the structure vectors on it (P, c, w). C: V_W G_WW V_Wᵀ (m/N), (P, c, c).
        E: V_W N_W, (P, c, r). a_torque, a_centrifugal: V_W x_W of the unit torque and of the
            unit speed² centrifugal load (m), (P, c).
        kl: k l of each cell (N/m), zero off the flanks, (P, c). mask: cells on the flanks,
            (P, c).
        B: (I + S C S)⁻¹ with S = diag √(k l) (every cell on the flanks in contact; identity
            off them), (P, c, c): the exact law's first active-set pass is a product with it and
            a later one a Schur complement on it (:mod:`jaxgear._cell_factor`).
        te_rows: V_W (G u)_W of each mesh's TE vector u (m/N), (P, meshes, c): u·X =
            u·G F − te_rows·P + (u·N) α without recovering X.
        lines: each contact line's cells (P, G, g) (G lines of all meshes, g the most slices;
            padding c). K_line: B_:D (B_DD)⁻¹ for D each line's cells on the flanks
            (P, G, c, g): a pass with one whole line out of contact is then products only.
            YF: the solution for the rigid-body columns S E on the full set and with each line
            out, (P, 1 + G, c, r).
    """

    theta: Float[Array, " P"]
    idx: Int[Array, "P w"]
    V: Float[Array, "P c w"]
    C: Float[Array, "P c c"]
    E: Float[Array, "P c r"]
    a_torque: Float[Array, "P c"]
    a_centrifugal: Float[Array, "P c"]
    kl: Float[Array, "P c"]
    mask: Bool[Array, "P c"]
    B: Float[Array, "P c c"]
    te_rows: Float[Array, "P m c"]
    lines: Int[Array, "P G g"]
    K_line: Float[Array, "P G c g"]
    YF: Float[Array, "P G1 c r"]


class HybridScene(AssembledScene):
    """The lumped 3D scene with condensed FE bodies: a pair (H1: flexible wheel; H2: both
    flexible) or a gear train with flexible gears (a flexible idler meshing twice).

    Build with :func:`hybrid_pair` or :func:`hybrid_train`. Generalised coordinates: the shafts
    (6 per node), then each body's rim master and modal DOFs (its bearing nodes are shaft
    nodes). The scene speed Ω is the pinion's (a train's input's).

    Attributes:
        structure: the assembled shafts, bearings, rigid gear nodes and condensed bodies with
            their teeth lumped on the rim nodes (:class:`~jaxgear.scenes.Structure`, one stiffness
            part ``structure``). Its bearing damping acts on a flexible member's shaft in the
            body frame (the bearings there are axisymmetric, checked by :func:`hybrid_pair`; the
            rotating-frame term Ω C J of a fixed damper is neglected, as the seed neglects
            gyroscopic terms). Its rotating-frame matrices are those of the members whose frames
            turn (a flexible body and its shaft): the dynamics add Ω·gyroscopic·Ẋ (Coriolis, skew)
            and Ω²·spin_stiffness·X at pinion speed Ω.
        meshes: the gear meshes (:class:`~jaxgear.scenes.GearMesh`).
        members: the gear members (pinion, gear), each a
            :class:`~jaxgear.scenes.RigidMember` or a :class:`~jaxgear.scenes.FlexibleMember`.
        G: compliance on the complement of the free rotations with the output rotation held
            (n, n). N: the free rotations (n, r): a pair's drive rotation (the pinion chain),
            scaled to a unit base-plane approach (r = 1); a train's every shaft but the output
            (per unit base-plane advance of the input).
        member_shafts: static, each member's shaft (its bearings turn with a flexible body).
        periods: static, first-mesh periods after which every mesh's cells repeat
            (:meth:`scene_periods`; 1 for a pair or an idler train).
        compliance: the window compliance at a set of positions
            (:func:`cache_window_compliance`), or None: formed at each position.
        f_torque: load per unit pinion torque (n,) (:class:`AssembledScene`).
        x_torque, x_centrifugal: G f_torque,
            G f_centrifugal (the pinion speed Ω is an argument of the methods and solvers that
            load the scene, never a field of it). Each mesh's TE vector u is its
            :attr:`GearMesh.te` (at the gear positions of the shafts).
    """

    G: Float[Array, "n n"]
    N: Float[Array, "n r"]
    x_torque: Float[Array, " n"]
    x_centrifugal: Float[Array, " n"]
    member_shafts: tuple = eqx.field(static=True, default=(0, 1))
    periods: int = eqx.field(static=True, default=1)
    compliance: WindowCompliance | None = None

    def scene_periods(self) -> int:
        """:attr:`periods`."""
        return self.periods

    def external_load(self, torque, speed=0.0):
        """Generalised external forces (n,) at pinion torque T (N·m) and pinion speed Ω (rad/s):
        T f_torque + Ω² f_centrifugal (each body at its own speed, (2.37))."""
        return torque * self.f_torque + speed**2 * self.structure.f_centrifugal

    def points(self, cells: Cells):
        """Fixed-frame contact points M of the cells (m), shape (L, N, 3)."""
        return only_mesh(self.meshes).points(cells)

    def window(self, cells: Cells, pad: int = 0):
        """Window DOFs (w,) and structure vectors on them (L, N, w), masked cells zeroed;
        ``pad`` rim stations more on each side of a flexible member's window."""
        return only_mesh(self.meshes).window(self.members, cells, pad)

    def window_overflow(self, cells: Cells):
        """True if a cell on the flanks reaches a rim station beyond its member's window."""
        return only_mesh(self.meshes).window_overflow(self.members, cells)

    # -- the cell space -----------------------------------------------------------------------
    def cell_space(self, row: CellRow, torque, speed=0.0):
        """C = V_W G_WW V_Wᵀ, a0 = V_W x0_W, E = V_W N_W, b = Nᵀ F and x0 = G F on the window
        of ``row`` (:meth:`window_row`; the cells of all meshes), F the external load at pinion
        torque T (N·m) and speed Ω (rad/s)."""
        idx, Vw = row.idx, row.V
        Gw = self.G[idx[:, None], idx[None, :]]
        x0 = torque * self.x_torque + speed**2 * self.x_centrifugal
        C = Vw @ Gw @ Vw.T
        a0 = Vw @ x0[idx]
        E = Vw @ self.N[idx]
        b = self.N.T @ self.external_load(torque, speed)
        return C, a0, E, b, x0

    def static_contact(self, cells: tuple, delta0: tuple, torque, speed, law: ContactLaw):
        """The static contact of all meshes at one position in the space of the cells
        (:func:`jaxgear.solve_contact_cells` on :meth:`cell_space`, the centrifugal load at
        pinion speed ``speed``): (the contact solution, X (n,), u·X of each mesh (m),
        (meshes,)); the arguments are those of :meth:`jaxgear.scenes.Scene.static_contact`.
        With :attr:`compliance` the position's cached slice is read instead, and the exact law
        is solved on its factor (:mod:`jaxgear._cell_factor`); the smooth law starts its
        Newton iteration from that exact answer."""
        if self.compliance is None:
            r = self.window_row(cells, delta0)
            C, a0, E, b, x0 = self.cell_space(r, torque, speed)
            sol, force, alpha = solve_contact_cells(
                C, a0 - r.delta0, E, b, r.k, r.length, r.mask, law
            )
            return sol, self.recover(r, x0, force, alpha), self.te_recover(r, x0, force, alpha)
        cs = self._position_slice(cells)
        r = CellRow(
            cs.idx,
            cs.V,
            *(_flat(x) for x in ([c.stiffness for c in cells], [c.length for c in cells])),
            _flat(delta0),
            cs.mask,
        )
        x0 = torque * self.x_torque + speed**2 * self.x_centrifugal
        a = torque * cs.a_torque + speed**2 * cs.a_centrifugal - r.delta0
        b = self.N.T @ self.external_load(torque, speed)
        exact = isinstance(law, ExactContact)
        sg = jax.lax.stop_gradient
        sol, force, alpha = solve_factored_cells(
            cs.B,
            cs.C,
            cs.E,
            cs.kl,
            cs.mask,
            a if exact else sg(a),
            b if exact else sg(b),
            r.k,
            law.max_iterations,
            cs.lines,
            cs.K_line,
            cs.YF,
        )
        if not exact:  # Newton from the factored exact answer
            start = (sol.gap, alpha, sol.iterations)
            sol, force, alpha = solve_contact_cells(
                cs.C, a, cs.E, b, r.k, r.length, r.mask, law, start
            )
        u = self.te_vectors()
        te = u @ x0 - cs.te_rows @ force + (u @ self.N) @ alpha
        return sol, self.recover(r, x0, force, alpha), te

    def map_positions(self, fn, theta):
        """``fn(scene, θ)`` vmapped over the positions θ (P,); with :attr:`compliance` at P
        positions, each call gets the scene holding its position's slice (no gather)."""
        cache = self.compliance
        if cache is None or cache.theta.shape != theta.shape:
            return super().map_positions(fn, theta)

        def one(th, cs):
            return fn(eqx.tree_at(lambda s: s.compliance, self, cs), th)

        return jax.vmap(one)(theta, cache)

    def _position_slice(self, cells: tuple) -> WindowCompliance:
        """The slice of :attr:`compliance` at the cells' scene angle: the slice itself (checked)
        or the nearest cached position (gathered); an error if it is not within 1e-9 of a mesh
        period."""
        cache = self.compliance
        mesh = self.meshes[0]
        theta = (cells[0].theta - mesh.phase) / mesh.ratio
        tol = 1e-9 * mesh.base_plane.mesh_period_angle / mesh.ratio
        msg = (
            "HybridScene.compliance: the position is not one of the cached positions (cache "
            "the positions the solve takes: cache_window_compliance(scene, theta))"
        )
        if cache.theta.ndim == 0:
            # the check rides on k l, which every solve reads
            return eqx.tree_at(
                lambda c: c.kl,
                cache,
                eqx.error_if(cache.kl, jnp.abs(cache.theta - theta) > tol, msg),
            )
        i = jnp.argmin(jnp.abs(cache.theta - theta))
        i = eqx.error_if(i, jnp.abs(cache.theta[i] - theta) > tol, msg)
        return jax.tree_util.tree_map(lambda x: x[i], cache)

    def bearing_forces_fixed_frame(self, theta, F):
        """The bearing force components R X (N), shape (P, r), at pinion angles θ (P,) in the
        fixed frame: a flexible member's shaft turns with its body, so the in-plane pair of a
        bearing on it (taken in the turning body frame) is rotated back by the body frame
        angle; the others are unchanged."""
        names = self.reaction_names
        turned = set()  # a body carrying two gears turns its shaft once
        for m, member in enumerate(self.members):
            if not isinstance(member, FlexibleMember) or self.member_shafts[m] in turned:
                continue
            turned.add(self.member_shafts[m])
            ang = member.frame_angle(theta)
            for i, name in enumerate(names):
                if self.structure.reaction_member[i] != self.member_shafts[m] or not name.endswith(
                    "Fx"
                ):
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
        Returns a tuple, one per member."""
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

    def recover(self, row: CellRow, x0, P, alpha):
        """X = G (F − V_Wᵀ P) + N α from the cell forces P (c,) on the window of ``row`` and the
        rigid amplitudes α (x0 = G F)."""
        z = jnp.zeros_like(x0).at[row.idx].add(row.V.T @ P)
        return x0 - self.G @ z + self.N @ alpha

    def te_recover(self, row: CellRow, x0, P, alpha):
        """u·X (m) of each mesh, (meshes,), without recovering X:
        u·x0 − (G u)_W·(V_Wᵀ P) + (u·N) α."""
        u = self.te_vectors()
        # (G u)ᵀ from the scene alone (G symmetric): under a vmap over positions it is not
        # batched, so it is formed once per call; only its window is gathered per position
        Gu = u @ self.G
        return u @ x0 - Gu[:, row.idx] @ (row.V.T @ P) + (u @ self.N) @ alpha


# ------------------------------------------------------------------------------------------
# builder (NumPy, once per scene)


class _BodyPlace(NamedTuple):
    """A condensed body placed on a shaft: its shaft (index), the position along it of the
    body frame's origin (m; the wheel rim's mid-face, a single-rim body's gear position), its
    spin speed per unit scene speed (signed Ω_z/Ω: the pinion's +1, a pair's gear −z1/z2), and
    for each of its rims a gear pair with its member index there (its tooth data for the tooth
    masses)."""

    body: object
    shaft: int
    gear_z: float
    speed: float
    rims: tuple  # ((GearPair, member), ...) per rim of the body


def _body_bearing_z(body, shaft: ShaftSpec, where: str, origin: float | None = None) -> tuple:
    """The shaft positions (m) where ``body``'s bearing nodes attach (the body origin's
    position ``origin``, default the shaft's gear position, plus their axial positions), after
    checking that the shaft's bearings are axisymmetric (the
    shaft of a flexible body turns with the body frame: they must look the same from every
    angle, i.e. commute with a quarter turn about z: K_xx = K_yy, ...)."""
    q = np.zeros((6, 6))
    q[0, 1] = q[3, 4] = -1.0
    q[1, 0] = q[4, 3] = q[2, 2] = q[5, 5] = 1.0
    for i, b in enumerate(shaft.bearings):
        for what, a in (("stiffness", b.stiffness_matrix()), ("damping", b.damping_matrix())):
            dg = np.abs(np.diag(a))
            scale = np.maximum(np.sqrt(np.outer(dg, dg)), np.abs(a))
            if np.any(np.abs(q @ a @ q.T - a) > 1e-6 * np.maximum(scale, scale.T)):
                raise ValueError(
                    f"{where}.bearings[{i}]: its {what} matrix is not axisymmetric about the "
                    "shaft axis (allowed on the shaft of a flexible body, which turns with the "
                    "body frame: e.g. K_xx = K_yy, K_xy = 0, K[3][3] = K[4][4], "
                    "K[0][4] = -K[1][3], no x/y-z coupling)"
                )
    coords = np.asarray(body.master_coords, float)
    bz = coords[np.asarray(body.master_kind) == 1]
    if bz.size == 0 or np.any(np.hypot(bz[:, 0], bz[:, 1]) > 1e-9):
        raise ValueError(f"{where}: the body on it needs bearing nodes on its axis")
    return tuple((shaft.gear_z if origin is None else origin) + bz[:, 2])


def _place_bodies(d: dict, places: list, tooth_density: float | None) -> dict:
    """The shafts of ``d`` (:func:`_shaft_arrays`) with condensed bodies: each body's bearing
    master DOFs merged with its shaft's nodes, its other condensed DOFs appended (NumPy).

    Args:
        d: the shaft arrays. places: a :class:`_BodyPlace` or ``None`` per member.
        tooth_density: add the mass and centrifugal load of the teeth (not in the FE body, which
            ends at the root circle) on the rim master nodes at this density [R]; ``None``: no.

    Returns:
        dict of ``K``, ``M`` (n, n), ``fc`` (n,) per unit scene speed², ``gyroscopic`` and
        ``spin_stiffness`` (:func:`_rotating_frame`), ``gidx`` (each member's global DOF of each
        condensed DOF, or ``None``), ``n``.
    """
    n_sh = d["M"].shape[0]
    n = n_sh
    blocks, rot_parts, gidxs = [], [], []
    for place in places:
        if place is None:
            gidxs.append(None)
            continue
        body = place.body
        coords = np.asarray(body.master_coords, float)
        kind = np.asarray(body.master_kind)
        dm = np.asarray(body.dof_map)
        gidx = np.full(dm.shape[0], -1)
        zs, off = d["shaft_z"][place.shaft], d["shaft_offsets"][place.shaft]
        for i, (mi, c) in enumerate(dm):
            if mi >= 0 and kind[mi] == 1:
                node = int(np.argmin(np.abs(zs - (place.gear_z + coords[mi, 2]))))
                gidx[i] = off + 6 * node + int(c)
        free = np.flatnonzero(gidx < 0)
        gidx[free] = n + np.arange(free.size)
        n += free.size
        K_b = np.array(body.K, float)
        M_b = np.array(body.M, float)
        f_b = np.array(body.f_centrifugal, float)
        Mb0 = M_b.copy()
        for grid, (pair, member) in zip(body_rims(body), place.rims, strict=True):
            if tooth_density is None:
                break
            width = float(np.ptp(coords[grid[0], 2]))
            mt, rt = one_tooth_mass(pair, member, tooth_density, width)
            zn = coords[grid[0], 2]
            share = np.zeros(zn.size)  # trapezoid weights across the face
            share[:-1] += 0.5 * np.diff(zn)
            share[1:] += 0.5 * np.diff(zn)
            share /= share.sum()
            dof = body_dof_index(body)
            for k in range(grid.shape[0]):
                for j in range(zn.size):
                    mi = int(grid[k, j])
                    e = coords[mi, :2] / np.hypot(*coords[mi, :2])
                    for c in range(3):
                        M_b[dof[(mi, c)], dof[(mi, c)]] += mt * share[j]
                    for c in range(2):
                        f_b[dof[(mi, c)]] += mt * share[j] * rt * e[c]
        blocks.append((gidx, K_b, M_b, f_b * place.speed**2))
        rot_parts.append((place.shaft, place.speed, gidx, _body_rotating(body, M_b - Mb0)))
        gidxs.append(gidx)
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    K[:n_sh, :n_sh] = d["parts"].sum(axis=0)
    M[:n_sh, :n_sh] = d["M"]
    fc = np.zeros(n)
    for g, Kb, Mb, fb in blocks:
        K[np.ix_(g, g)] += Kb
        M[np.ix_(g, g)] += Mb
        fc[g] += fb
    gyro, spin_K = _rotating_frame(n, d, rot_parts)
    return dict(K=K, M=M, fc=fc, gyroscopic=gyro, spin_stiffness=spin_K, gidx=gidxs, n=n)


def _body_structure(d: dict, placed: dict, nodes: tuple) -> Structure:
    """The :class:`Structure` of shafts ``d`` with their condensed bodies ``placed``
    (:func:`_place_bodies`): one stiffness part, the bearing rows padded over the bodies'
    coordinates, the rotating-frame matrices of the turning bodies."""
    n = placed["n"]
    R = d["reaction"]
    return Structure(
        K=jnp.asarray(placed["K"]),
        M=jnp.asarray(placed["M"]),
        parts_K=None,
        C_bearing=jnp.asarray(d["bearing_C"]),
        reaction=jnp.asarray(np.concatenate([R, np.zeros((R.shape[0], n - R.shape[1]))], 1)),
        gyroscopic=jnp.asarray(placed["gyroscopic"]),
        spin_stiffness=jnp.asarray(placed["spin_stiffness"]),
        f_centrifugal=jnp.asarray(placed["fc"]),
        part_names=("structure",),
        reaction_names=d["reaction_names"],
        reaction_member=d["reaction_member"],
        nodes=nodes,
    )


def _shaft_rotation(d: dict, shaft: int, n: int, body=None, gidx=None) -> np.ndarray:
    """The rigid rotation about +z of shaft ``shaft`` and the condensed body on it (n,): 1 on
    each rotation φ_z of its nodes, (−y, x) on the in-plane DOFs of the body's rim masters
    (its bearing masters are shaft DOFs; its modal coordinates do not move)."""
    v = np.zeros(n)
    a = d["shaft_offsets"][shaft]
    v[a + 5 : a + 6 * d["shaft_z"][shaft].size : 6] = 1.0
    if body is not None:
        coords = np.asarray(body.master_coords, float)
        for i, (mi, c) in enumerate(np.asarray(body.dof_map)):
            if mi >= 0 and body.master_kind[mi] == 0 and c < 2:
                x, y = coords[mi, :2]
                v[gidx[i]] = -y if c == 0 else x
    return v


def _drive_compliance(K: np.ndarray, N: np.ndarray, held: int) -> np.ndarray:
    """G (n, n): the compliance on the complement of the free rotations N (n, r) with the
    output rotation ``held`` held (its row and column zero), K G b = b for every load b with
    Nᵀ b = 0 (the columns of N have disjoint supports).

    Raises:
        ValueError: a column of N that is not a free rotation of K (internal error), or a
            rigid-body mode of the structure besides them (its supports).
    """
    n = K.shape[0]
    scale = np.max(np.abs(np.diag(K)))
    for j in range(N.shape[1]):
        if np.linalg.norm(K @ N[:, j]) > 1e-7 * scale * np.linalg.norm(N[:, j]):
            raise ValueError("hybrid scene: a shaft does not turn freely (internal error)")
    keep = np.setdiff1d(np.arange(n), [held])
    Nh = N[keep] / np.linalg.norm(N[keep], axis=0)
    A = K[np.ix_(keep, keep)] + np.mean(np.diag(K)) * Nh @ Nh.T
    try:
        factor = sla.cho_factor(A)
    except np.linalg.LinAlgError:
        raise ValueError(
            "hybrid scene: the structure has a rigid-body mode besides the shafts' rotations "
            "(check the bearings: radial and axial support of every shaft)"
        ) from None
    G = np.zeros((n, n))
    G[np.ix_(keep, keep)] = sla.cho_solve(factor, np.eye(keep.size))
    return 0.5 * (G + G.T)


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
) -> HybridScene:
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
    where = ("scene.pinion_shaft", "scene.gear_shaft")
    for m, body in enumerate(bodies):
        if body is not None and len(body_rims(body)) > 1:
            raise ValueError(
                f"scene.{('pinion', 'gear')[m]}_body: the body has {len(body_rims(body))} rims "
                "(a [pinion_rim]): a body carrying two gears belongs in a train case "
                "([scene.bodies.<shaft>])"
            )
    extra = tuple(
        () if body is None else _body_bearing_z(body, shafts[m], where[m])
        for m, body in enumerate(bodies)
    )
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
        extra_z=extra,
    )
    ratio = pair.pinion.teeth / pair.gear.teeth
    placed = _place_bodies(
        d,
        [
            None if body is None else _BodyPlace(body, m, shafts[m].gear_z, w, ((pair, m),))
            for m, (body, w) in enumerate(zip(bodies, (1.0, -ratio), strict=True))
        ],
        density if tooth_mass else None,
    )
    n, gidxs = placed["n"], placed["gidx"]
    rb1, rb2 = pair.base_radii
    cb = math.cos(pair.base_helix_angle)
    g1, g2 = d["gear_dofs"]
    t_in, t_out = (dict(d["nodes"])[k] + 5 for k in ("input", "output"))
    f_t = np.zeros(n)
    f_t[t_in] += 1.0
    f_t[t_out] += rb2 / rb1
    te = np.zeros(n)
    te[g1 + 5], te[g2 + 5] = cb * rb1, cb * rb2
    # the drive rotation (pinion chain), scaled to a unit base-plane approach
    Nv = _shaft_rotation(d, 0, n, bodies[0], gidxs[0]) / rb1
    G = _drive_compliance(placed["K"], Nv[:, None], t_out)
    line = line_of_action(pair)
    zone = mesh_line(
        line["tangent_point"], line["direction"], line["normal"], line["roll_start"], mesh
    )
    zone = {k: np.asarray(v) for k, v in zone.items()}
    members = []
    for m, body in enumerate(bodies):
        centre = jnp.asarray(line["centres"][m])
        if body is None:
            g = d["gear_dofs"][m]
            members.append(RigidMember(centre, tuple(range(g, g + 6))))
        else:
            members.append(flexible_member(pair, m, body, gidxs[m], centre, zone, mesh))
    structure = _body_structure(d, placed, d["nodes"])
    scene = HybridScene(
        structure=structure,
        meshes=(pair_mesh(mesh, line, te),),
        members=tuple(members),
        G=jnp.asarray(G),
        N=jnp.asarray(Nv[:, None]),
        f_torque=jnp.asarray(f_t),
        x_torque=jnp.asarray(G @ f_t),
        x_centrifugal=jnp.asarray(G @ placed["fc"]),
    )
    return fit_windows(scene)


def hybrid_train(
    pairs,
    meshes,
    layout,
    shafts: tuple,
    gear_shafts: tuple,
    *,
    bodies: tuple,
    masses,
    inertias,
    shares=None,
    wrenches: tuple = (),
    shaft_names: tuple | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    density: float = 7800.0,
    tooth_mass: bool = True,
    rims: tuple | None = None,
    gear_names: tuple | None = None,
) -> HybridScene:
    """A lumped 3D gear train (:func:`~jaxgear.scenes.lumped_train`) whose flexible gears are
    condensed FE bodies: a flexible idler meshes twice, its two contact zones on one rim, both
    through the interface of :mod:`._interface`; a body with two rims (a fem_prep
    ``[pinion_rim]``) carries the two gears of its shaft, each mesh on its gear's rim
    (docs/trains.md, "Flexible gears in a train", "A body carrying two gears").

    Each body is placed on its shaft as in :func:`hybrid_pair` (bearing masters merged with the
    shaft nodes at the body origin's position plus their axial positions; the origin is the
    mid-face of its wheel rim, rim 0, at that gear's position); its frame turns at the shaft's
    speed ratio and sense (the layout's), and a tooth centre of each of its gears sits on a
    station of that gear's rim (the gear's first mesh's phase). The statics run in the cell
    space with one free rotation per shaft but the output's, which is held
    (:class:`HybridScene`).

    Args:
        pairs: each mesh's :class:`~jaxgear.GearPair` (its pinion the driving gear).
        meshes, layout, shafts, gear_shafts, masses, inertias, shares, wrenches, shaft_names,
            youngs_modulus, poisson_ratio, density: as :func:`~jaxgear.scenes.lumped_train`
            (masses and inertias are ignored for a flexible gear).
        bodies: each gear's condensed body or ``None`` (a rigid gear node), (n,); the gears of
            one shaft are all rigid or all on one body (the same object); its mesh models must
            leave out the foundation term of a flexible gear (as :func:`hybrid_pair`).
        tooth_mass: add the teeth's mass and centrifugal load on the rim masters.
        rims: each gear's rim on its body (0 the wheel's rim, 1 the ``[pinion_rim]``), (n,);
            default 0 for every gear. The gears of a body take distinct rims, every rim one.
        gear_names: each gear's name, for the messages (default ``gear<g>``).

    Raises:
        ValueError (one line, lengths in mm): a shaft carrying a flexible gear and a rigid one or
            two bodies (the shaft turns with the body frame); a body's rims not matching its
            gears (count, rim taken twice), a gear position that is not where the body puts its
            rim, a rim width that is not the face width of the gear's meshes; what
            :func:`hybrid_pair` and :func:`lumped_train` refuse.
    """
    n_shafts = len(shafts)
    names = shaft_names or tuple(f"shaft{i}" for i in range(n_shafts))
    gname = gear_names or tuple(f"gear{g}" for g in range(len(bodies)))
    rims = tuple(rims) if rims is not None else (0,) * len(bodies)
    on = [[g for g, sh in enumerate(gear_shafts) if sh == i] for i in range(n_shafts)]
    # one body per shaft: its gears, each on its rim; the body origin along the shaft
    shaft_body: dict = {}  # shaft -> (body, origin z (m))
    bodies_z = [[] for _ in range(n_shafts)]
    for s_ in range(n_shafts):
        flex = [g for g in on[s_] if bodies[g] is not None]
        if not flex:
            continue
        where = f"shaft {names[s_]!r}"
        rigid = [g for g in on[s_] if bodies[g] is None]
        if rigid:
            raise ValueError(
                f"{where}: carries the flexible gear {gname[flex[0]]!r} and the rigid gear "
                f"{gname[rigid[0]]!r} (allowed: a shaft's gears all on one condensed body, "
                "which turns with the shaft)"
            )
        body = bodies[flex[0]]
        if any(bodies[g] is not body for g in flex):
            raise ValueError(
                f"{where}: its gears {', '.join(repr(gname[g]) for g in flex)} name different "
                "bodies (allowed: one condensed body per shaft, carrying all its gears)"
            )
        n_rims = len(body_rims(body))
        used = [rims[g] for g in flex]
        if len(flex) != n_rims or sorted(used) != list(range(n_rims)):
            raise ValueError(
                f"{where}: its body has {n_rims} rim(s) and the shaft {len(flex)} gear(s) on "
                f"rims {used} (allowed: one gear on each rim, rim 0 the webbed wheel's, rim 1 "
                "the [pinion_rim])"
            )
        pos = shafts[s_].gear_positions
        g0 = next(g for g in flex if rims[g] == 0)
        origin = pos[on[s_].index(g0)]
        for g in flex:
            want = origin + rim_mid_z(body, rims[g])
            got = pos[on[s_].index(g)]
            if abs(got - want) > 1e-6:
                raise ValueError(
                    f"{where}: gear_positions_mm {gname[g]} = {got * 1e3:.6g}, but its body puts "
                    f"rim {rims[g]} at {want * 1e3:.6g} mm ({gname[g0]} at {origin * 1e3:.6g} mm "
                    f"+ {rim_mid_z(body, rims[g]) * 1e3:.6g} mm in the body frame)"
                )
        shaft_body[s_] = (body, origin)
        bodies_z[s_].extend(_body_bearing_z(body, shafts[s_], where, origin))
    t = _train_arrays(
        meshes,
        layout,
        shafts,
        gear_shafts,
        [None if b is not None else m for b, m in zip(bodies, masses, strict=True)],
        inertias,
        shares,
        wrenches,
        names,
        (youngs_modulus, poisson_ratio, density),
        tuple(map(tuple, bodies_z)),
    )
    d, first = t["d"], t["first"]
    n_sh = d["M"].shape[0]
    spin = np.asarray(layout.spins, float)
    ratio = np.asarray(layout.ratios, float)
    role = {}  # each gear's first mesh and its member index there (0 driving, 1 driven)
    for k, (_, (g, h)) in enumerate(meshes):
        role.setdefault(g, (k, 0))
        role.setdefault(h, (k, 1))
    for g, body in enumerate(bodies):  # each rim as wide as the faces of its gear's meshes
        if body is None:
            continue
        z = np.asarray(body.master_coords, float)[body_rims(body)[rims[g]][0], 2]
        for k, (plane, (a, b)) in enumerate(meshes):
            face = float(plane.face_width)
            if g in (a, b) and abs(np.ptp(z) - face) > 1e-6 * face:
                raise ValueError(
                    f"{gname[g]!r}: its body's rim {rims[g]} is {np.ptp(z) * 1e3:.6g} mm wide, "
                    f"the face of mesh {gname[a]}-{gname[b]} {face * 1e3:.6g} mm (allowed: equal; "
                    "fem_prep rim_width_mm or [pinion_rim] width_mm)"
                )
    places, body_shafts = [], []
    for s_, (body, origin) in shaft_body.items():
        per_rim = [None] * len(body_rims(body))
        for g in on[s_]:
            k, member = role[g]
            per_rim[rims[g]] = (pairs[k], member)
        g0 = on[s_][0]
        places.append(_BodyPlace(body, s_, origin, spin[g0] * ratio[g0], tuple(per_rim)))
        body_shafts.append(s_)
    placed = _place_bodies(d, places, density if tooth_mass else None)
    n = placed["n"]
    gidx_of = dict(zip(body_shafts, placed["gidx"], strict=True))  # shaft -> body DOFs
    f_t = np.concatenate([t["f_torque"], np.zeros(n - n_sh)])
    rb0 = float(meshes[0][0].base_radius_pinion)
    Nv = np.stack(
        [
            _shaft_rotation(
                d,
                i,
                n,
                shaft_body[i][0] if i in shaft_body else None,
                gidx_of.get(i),
            )
            / rb0
            for i in range(n_shafts)
            if i != t["out"]
        ],
        axis=1,
    )
    G = _drive_compliance(placed["K"], Nv, dict(t["nodes"])["output"] + 5)
    out_meshes = train_meshes(meshes, layout, first, n)
    members = []
    for g, body in enumerate(bodies):
        centre = jnp.asarray(layout.centres[g])
        if body is None:
            members.append(RigidMember(centre, tuple(range(first[g], first[g] + 6))))
            continue
        k, member = role[g]
        zone = {key: np.asarray(v) for key, v in out_meshes[k].line().items()}
        window = max(  # the widest window of the meshes it is in
            rim_window(pairs[j], 0 if g == a else 1)
            for j, (_, (a, b)) in enumerate(meshes)
            if g in (a, b)
        )
        members.append(
            flexible_member(
                pairs[k],
                member,
                body,
                gidx_of[gear_shafts[g]],
                centre,
                zone,
                meshes[k][0],
                window,
                spin=float(spin[g]),
                ratio=float(ratio[g]),
                mesh_angle=float(layout.phases[k]),
                rim=rims[g],
            )
        )
    for s_ in shaft_body:  # a body carrying two gears has one frame
        flex = [g for g in on[s_] if bodies[g] is not None]
        if len(flex) > 1:
            offset = _common_offset([members[g] for g in flex], [gname[g] for g in flex])
            for g in flex:
                members[g] = eqx.tree_at(lambda m: m.offset, members[g], jnp.asarray(offset))
    structure = _body_structure(d, placed, t["nodes"])
    scene = HybridScene(
        structure=structure,
        meshes=out_meshes,
        members=tuple(members),
        G=jnp.asarray(G),
        N=jnp.asarray(Nv),
        f_torque=jnp.asarray(f_t),
        x_torque=jnp.asarray(G @ f_t),
        x_centrifugal=jnp.asarray(G @ placed["fc"]),
        member_shafts=tuple(int(s_) for s_ in gear_shafts),
        periods=t["periods"],
    )
    return fit_windows(scene)


def _common_offset(members: list, names: list) -> float:
    """The one frame angle φ_0 (rad, at θ = 0) of a body carrying several gears: each member's
    :func:`flexible_member` offset puts its gear's teeth on its rim's stations, modulo that
    rim's pitch 2π/Z_r; the body's frame must satisfy every rim at once, φ_0 ≡ φ_r (mod 2π/Z_r),
    which has a solution when the gears' clocking on the shaft agrees with the rims' stations.

    Raises:
        ValueError: no common angle: the teeth of a later gear would sit off its stations
            (its ``clocking_deg`` against the body's stations, one line).
    """
    phis = [float(m.offset) for m in members]
    pitches = [float(m.pitch_angle) for m in members]
    Z0 = int(round(2 * math.pi / pitches[0]))
    for a in range(Z0):
        phi = phis[0] + a * pitches[0]
        off = [((phi - p) / q + 0.5) % 1.0 - 0.5 for p, q in zip(phis, pitches, strict=True)]
        if max(abs(o) for o in off) < 1e-6:
            return phi
    Zs = [int(round(2 * math.pi / q)) for q in pitches]
    best = min(
        range(Z0),
        key=lambda a: abs(((phis[0] + a * pitches[0] - phis[1]) / pitches[1] + 0.5) % 1.0 - 0.5),
    )
    frac = ((phis[0] + best * pitches[0] - phis[1]) / pitches[1] + 0.5) % 1.0 - 0.5
    step = 360.0 / math.lcm(*Zs)
    raise ValueError(
        f"gears {names[0]!r} and {names[1]!r} on one body: with the teeth of {names[0]!r} on "
        f"their rim stations, those of {names[1]!r} sit {abs(frac):.3g} of a pitch off theirs "
        f"(allowed: a clocking_deg of {names[1]!r} at which both sit on their stations, which "
        f"moves by multiples of {step:.6g} deg = 360/lcm({', '.join(map(str, Zs))}))"
    )


HybridPair = HybridScene  # the name of the pair's scene (a hybrid train is the same class)


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
    dof = body_dof_index(body)
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


def _rotating_frame(n, d, parts):
    """Gyroscopic (n, n) per unit scene speed and spin stiffness (n, n) per unit scene speed² of
    the members whose frames turn: each flexible body at Ω_z = w Ω (``parts``: (shaft, w,
    global DOFs, (Gy, S)) per body; a pair's pinion w = +1, its gear −z1/z2) and the shaft that
    carries it.

    The rotating-frame equations of a body turning at Ω_z about +z: M Ẍ + 2 Ω_z Gy Ẋ + (K +
    Ω_z² (S + Kσ)) X = … (Coriolis, spin softening, centrifugal stress stiffening; fem_prep
    condenses Gy, S, Kσ of the FE body). A shaft on the axis is axisymmetric: its fixed-frame
    model seen from the turning frame gives Gy = M J and S = −M P (J = ez × on the translations
    and the rotation vector, P = J ᵀJ), with no polar gyroscopic term (as the lumped model)."""
    gyro = np.zeros((n, n))
    spin_K = np.zeros((n, n))
    offsets = (*d["shaft_offsets"], d["M"].shape[0])
    for shaft, w, gidx, (gy, sk) in parts:
        gyro[np.ix_(gidx, gidx)] += 2.0 * w * gy
        spin_K[np.ix_(gidx, gidx)] += w * w * sk
        a, b = offsets[shaft], offsets[shaft + 1]
        Ms = d["M"][a:b, a:b]
        J = np.kron(np.eye((b - a) // 6), _J6)
        if np.abs(Ms @ J - J @ Ms).max() > 1e-9 * np.abs(Ms).max():
            raise ValueError("hybrid scene: a flexible body's shaft mass is not axisymmetric")
        gyro[a:b, a:b] += 2.0 * w * Ms @ J
        spin_K[a:b, a:b] += w * w * (Ms @ J @ J)
    return gyro, spin_K


def _flat(parts):
    """Every mesh's cell array, mesh after mesh (:meth:`CellRow.concat`'s order)."""
    return jnp.concatenate([x.reshape(-1) for x in parts])


def window_compliance(scene: HybridScene, theta) -> WindowCompliance:
    """The position-only parts of the cell-space contact problem of ``scene`` at the scene
    angles ``theta`` (rad), (P,): the windows, structure vectors, C = V_W G_WW V_Wᵀ, E = V_W N_W,
    the free gaps of the unit loads, k l and the mask, the inverse B of the full contact set and
    the TE rows (:class:`WindowCompliance`), vmapped over the positions. Memory:
    P (2 c² + G c g + c w + (2 + G) c r + (4 + meshes) c) floats."""
    theta = jnp.asarray(theta, scene.structure.K.dtype)
    Gu = scene.te_vectors() @ scene.G  # (meshes, n): G symmetric, (G u)ᵀ

    def one(th):
        cells = scene.mesh_cells(th)
        r = scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells))
        Gw = scene.G[r.idx[:, None], r.idx[None, :]]
        C = r.V @ Gw @ r.V.T
        kl = jnp.where(r.mask, r.k * r.length, 0.0)
        s = jnp.sqrt(kl)
        A = jnp.eye(C.shape[0], dtype=C.dtype) + s[:, None] * C * s[None, :]
        B = jax.scipy.linalg.cho_solve(jax.scipy.linalg.cho_factor(A), jnp.eye(A.shape[0]))
        return (
            r.idx,
            r.V,
            C,
            r.V @ scene.N[r.idx],
            r.V @ scene.x_torque[r.idx],
            r.V @ scene.x_centrifugal[r.idx],
            kl,
            r.mask,
            0.5 * (B + B.T),
            Gu[:, r.idx] @ r.V.T,
        )

    parts = jax.vmap(one)(theta)
    # the contact lines: each mesh's (n_lines, n_slices) cells, flattened mesh after mesh
    shapes = [c.mask.shape for c in jax.eval_shape(scene.mesh_cells, theta[0])]
    c_all = sum(n * m for n, m in shapes)
    g = max(m for _, m in shapes)
    rows, start = [], 0
    for n, m in shapes:
        for j in range(n):
            rows.append(list(range(start + j * m, start + (j + 1) * m)) + [c_all] * (g - m))
        start += n * m
    lines = jnp.broadcast_to(jnp.asarray(rows, jnp.int32), (theta.shape[0], len(rows), g))
    K_line, YF = jax.vmap(line_factors)(parts[8], parts[3], parts[6], parts[7], lines)
    return WindowCompliance(theta, *parts, lines, K_line, YF)


def cache_window_compliance(scene, theta=None, *, positions_per_pitch: int = 64, periods: int = 1):
    """``scene`` holding its :func:`window_compliance` at the positions ``theta`` (rad, (P,);
    default the positions :func:`jaxgear.quasi_static` takes for ``positions_per_pitch`` and
    ``periods``), built once per scene and reused by every solve at those positions: a relief
    map, a torque sweep (:func:`jaxgear.harris_map`), an optimisation (``optimise``).

    A solve then reads the windows and their compliance instead of forming them, and in exact
    contact it solves the first active-set pass as a product with the cached inverse of the full
    contact set and a later pass by a Schur complement (docs/hybrid.md, "Statics in the cell
    space"): the same result as the uncached scene (tested to 1e-12), the same gradients with
    respect to the modifications, the torque and the speed (none flows into the cache itself).
    A solve at another position raises (:class:`equinox.EquinoxRuntimeError`).

    Any other scene (and a :class:`jaxgear.MeshModel`), and a hybrid scene already cached at
    these positions, is returned as it is, so callers may apply it to whatever they are given.
    Cost: one contact solve's linear algebra per position, once; memory
    P (2 c² + c w + (c + meshes + 4) c) floats (6 + 3 MiB for accessory-spur-flexible at 64
    positions).
    """
    if not isinstance(scene, HybridScene):
        return scene
    if theta is None:
        theta = mesh_positions(scene.base_planes[0], positions_per_pitch, periods)
    theta = jnp.asarray(theta, scene.structure.K.dtype)
    held = scene.compliance
    if held is not None and held.theta.shape == theta.shape and bool(jnp.all(held.theta == theta)):
        return scene
    return eqx.tree_at(
        lambda s: s.compliance,
        scene,
        window_compliance(
            eqx.tree_at(lambda s: s.compliance, scene, None, is_leaf=lambda x: x is None), theta
        ),
        is_leaf=lambda x: x is None,
    )


def fit_windows(scene: HybridScene, tries: int = 4) -> HybridScene:
    """``scene`` with rim windows that hold its contact zones: each condensed member's window
    (``n_window`` rim stations spanned by a contact zone and the root points) is checked over
    two periods of every mesh (96 positions each) and widened by one station while a cell
    reaches beyond it. :func:`hybrid_pair` and :func:`hybrid_train` call it; call it again
    after changing a member by hand.

    Raises:
        ValueError: the zones do not fit after ``tries`` widenings.
    """
    for _ in range(tries):
        if not _windows_overflow(scene):
            return scene
        members = tuple(
            dataclasses.replace(m, n_window=m.n_window + 1) if isinstance(m, FlexibleMember) else m
            for m in scene.members
        )
        scene = eqx.tree_at(lambda s: s.members, scene, members)
    raise ValueError("hybrid scene: the contact zone does not fit a rim window (internal error)")


def _windows_overflow(scene: HybridScene, samples: int = 48) -> bool:
    """Whether a cell on the flanks of any mesh reaches beyond its member's window over two of
    that mesh's periods."""
    for mesh in scene.meshes:
        plane = mesh.base_plane
        angles = (np.arange(2 * samples) + 0.5) * float(plane.mesh_period_angle) / samples
        over = jax.jit(
            jax.vmap(
                lambda a, mesh=mesh: mesh.window_overflow(scene.members, mesh.base_plane.cells(a))
            )
        )(jnp.asarray(angles + float(mesh.phase), scene.structure.K.dtype))
        if bool(np.any(np.asarray(over))):
            return True
    return False
