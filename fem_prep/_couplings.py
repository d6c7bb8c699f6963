"""Master nodes and the couplings that hold them: bearings and rims (seed (2.3), (2.9)).

Bearings are 6-DOF nodes on the axis coupled to every bore node of an axial band (the bearing
width, ``BearingSeat.z_band``) by a kinematic transformation ``u = T q``: :class:`Rigid` (every
band node follows the rigid motion of the bearing node, a clamped bore over the bearing width) or
:class:`Averaging` (RBE3-like: the bearing node moves as the least-squares rigid fit of the band;
six band DOFs are eliminated).  Coupling a whole band rather than one node ring makes the support
a surface constraint, whose result converges under mesh refinement (a ring is a line constraint:
its stresses are singular and the deflection it allows grows logarithmically as the mesh is
refined).  The rim masters are the FE nodes at the tooth stations (:class:`Nodal`) or, by the
same kind of transformation, the least-squares fit of the rim face (:class:`Distributing`,
:mod:`._rim`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import ClassVar, final

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ._assemble import Operators
from ._body import Body
from ._kinds import BearingCoupling, RimCoupling
from ._mesh import BodyMesh, pinion_master_z, rim_master_z
from ._rim import RIM_FIT_REVISION, rim_fit

__all__ = [
    "Averaging",
    "Coupled",
    "Distributing",
    "MasterSet",
    "Nodal",
    "Rigid",
    "RimMasters",
    "band_reaction_stiffness",
    "couple_masters",
    "select_masters",
]


# ------------------------------------------------------------------------------------------
# master nodes


@dataclass(frozen=True)
class RimMasters:
    """The masters of one rim: FE node at each station and axial master plane ``(teeth,
    n_axial)`` (station k at 2 pi k / teeth), the outer face's radius (m) and axial extent
    ``band`` (m): the face the distributing coupling fits (:mod:`._rim`)."""

    nodes: np.ndarray
    radius: float
    band: tuple[float, float] | None = None


@dataclass(frozen=True)
class MasterSet:
    """Master nodes of a gear body.

    Attributes:
        rim_nodes: node indices ``(teeth, n_axial)`` on the rim outer radius, tooth ``k`` at
            angle ``2 pi k / teeth`` from the x axis, axial positions increasing (the rim
            masters' FE nodes; with the distributing coupling the nodes it eliminates).
        bearing_positions: bearing node coordinates ``(n_bearings, 3)`` (m), on the axis.
        bearing_rings: for each bearing, the bore node indices it is coupled to (every bore node
            of its axial band, ``BearingSeat.z_band`` snapped to the nearest bore-node planes).
        couplings: :class:`Rigid` or :class:`Averaging` per bearing.
        rim_coupling: :class:`Distributing` or :class:`Nodal` (:mod:`._rim`), for every rim.
        rim_radius: the outer rim radius (m).
        rim_band: the rim's outer face's axial extent (m), or ``None``: all of that radius.
        more_rims: the body's other rims (:class:`RimMasters`: a ``[pinion_rim]``), whose
            masters follow the wheel rim's.
    """

    rim_nodes: np.ndarray
    bearing_positions: np.ndarray
    bearing_rings: tuple[np.ndarray, ...]
    couplings: tuple[BearingCoupling, ...]
    rim_coupling: RimCoupling
    rim_radius: float = 0.0
    rim_band: tuple[float, float] | None = None
    more_rims: tuple[RimMasters, ...] = ()

    @property
    def rims(self) -> tuple[RimMasters, ...]:
        """Every rim's masters, the wheel rim first."""
        return (RimMasters(self.rim_nodes, self.rim_radius, self.rim_band), *self.more_rims)


def select_masters(bm: BodyMesh, body: Body) -> MasterSet:
    """Pick the rim master grid and the bore-node bands of the bearings.

    Args:
        bm: the body mesh.
        body: the body (teeth, axial master count, bearings).

    Returns:
        The :class:`MasterSet`.

    Raises:
        ValueError: a tooth station has no mesh node, or a bearing band has fewer than 3.
    """
    g = body.geometry
    zm = rim_master_z(bm, g, body.condensation.axial_master_nodes)
    x = bm.nodes
    rho = np.hypot(x[:, 0], x[:, 1])
    rim = _station_nodes(x, g.rim_outer_radius, body.condensation.teeth, zm)
    more = ()
    pin = body.pinion_rim
    if pin is not None:
        nodes = _station_nodes(x, pin.outer_radius, pin.teeth, pinion_master_z(bm, pin))
        more = (RimMasters(nodes, pin.outer_radius, pin.band),)

    on_bore = np.nonzero(np.abs(rho - g.bore_radius) < 1e-7 * g.rim_outer_radius)[0]
    zb = x[on_bore, 2]
    planes = np.unique(np.round(zb, 10))

    def snap(z: float) -> float:
        return float(planes[np.argmin(np.abs(planes - z))])

    taken = np.zeros(len(x), dtype=bool)
    rings, pos = [], []
    for b in body.bearings:
        # the band's edges snap to the nearest bore-node planes; it always holds the bearing plane
        zp = snap(b.axial_position)
        lo, hi = b.z_band
        lo, hi = min(snap(lo), zp), max(snap(hi), zp)
        band = on_bore[(zb > lo - 1e-9) & (zb < hi + 1e-9)]
        band = band[~taken[band]]  # a plane shared by two touching bands: the first bearing's
        if len(band) < 3:
            raise ValueError(f"bearing at z = {b.axial_position * 1e3:g} mm: bore band too small")
        taken[band] = True
        rings.append(band)
        pos.append([0.0, 0.0, b.axial_position])
    return MasterSet(
        rim_nodes=rim,
        bearing_positions=np.array(pos),
        bearing_rings=tuple(rings),
        couplings=tuple(b.coupling for b in body.bearings),
        rim_coupling=body.condensation.rim_coupling,
        rim_radius=g.rim_outer_radius,
        rim_band=(-g.rim_width / 2, g.rim_width / 2),
        more_rims=more,
    )


def _station_nodes(x: np.ndarray, radius: float, teeth: int, zm: np.ndarray) -> np.ndarray:
    """The FE node at each station (angle 2 pi k / teeth) and master plane ``zm`` of the outer
    face r = ``radius``, ``(teeth, len(zm))``.

    Raises:
        ValueError: a station without a node.
    """
    rho = np.hypot(x[:, 0], x[:, 1])
    on_rim = np.nonzero(np.abs(rho - radius) < 1e-7 * radius)[0]
    ang = np.arctan2(x[on_rim, 1], x[on_rim, 0])
    rim = np.empty((teeth, len(zm)), dtype=np.int64)
    lookup = {}
    kk = np.round(np.mod(ang, 2 * math.pi) / (2 * math.pi / teeth)).astype(int) % teeth
    exact = np.abs(np.mod(ang, 2 * math.pi) - kk * 2 * math.pi / teeth)
    exact = np.minimum(exact, 2 * math.pi - exact) < 1e-9
    for node, k, ok in zip(on_rim, kk, exact):
        if ok:
            lookup[(k, round(float(x[node, 2]), 10))] = node
    for k in range(teeth):
        for j, z in enumerate(zm):
            key = (k, round(float(z), 10))
            if key not in lookup:
                raise ValueError(
                    f"no rim node at tooth {k}, z = {z * 1e3:g} mm (r = {radius * 1e3:g} mm)"
                )
            rim[k, j] = lookup[key]
    return rim


def _skew(d: np.ndarray) -> np.ndarray:
    """``skew(d) @ w == cross(d, w)`` for each row of ``d`` (n, 3) -> (n, 3, 3)."""
    z = np.zeros(len(d))
    return np.stack(
        [
            np.stack([z, -d[:, 2], d[:, 1]], -1),
            np.stack([d[:, 2], z, -d[:, 0]], -1),
            np.stack([-d[:, 1], d[:, 0], z], -1),
        ],
        1,
    )


@dataclass(frozen=True)
class Coupled:
    """Operators after the master couplings (bearings and rim), ``u_full = T q``.

    Attributes:
        T: ``(n_full, n_red)`` sparse transformation.
        K, M: reduced stiffness/mass ``(n_red, n_red)``.
        f: reduced centrifugal vector per unit speed squared ``(n_red,)``.
        G: reduced gyroscopic matrix per unit spin speed ``(n_red, n_red)`` (skew, kg).
        S: reduced spin-softening matrix per unit speed squared ``(n_red, n_red)`` (kg).
        bearing_dofs: reduced indices ``(n_bearings, 6)`` of the bearing DOFs
            (u_x, u_y, u_z, theta_x, theta_y, theta_z).
        rim_dofs: reduced indices ``(teeth, n_axial, 3)`` of the rim master DOFs (x, y, z).
        rim_positions: the rim masters' positions ``(teeth, n_axial, 3)`` (m): their FE nodes
            (nodal coupling) or the fitted positions (distributing, :mod:`._rim`).
        full_to_red: ``(n_full,)`` reduced index of each full DOF kept as such, -1 if
            eliminated by a coupling.
        Ksigma: reduced stress-stiffening matrix per unit speed squared ``(n_red, n_red)``,
            or ``None``: it needs the prestress solve, so :func:`~fem_prep.prepare` fills it
            in (``dataclasses.replace``) after that solve; :func:`couple_masters` leaves it out.
        more_rims: for each of the body's other rims (``MasterSet.more_rims``), its
            ``(rim_dofs, rim_positions)`` as above.
    """

    T: sp.csr_matrix
    K: sp.csr_matrix
    M: sp.csr_matrix
    f: np.ndarray
    G: sp.csr_matrix
    S: sp.csr_matrix
    bearing_dofs: np.ndarray
    rim_dofs: np.ndarray
    rim_positions: np.ndarray
    full_to_red: np.ndarray
    Ksigma: sp.csr_matrix | None = None
    more_rims: tuple = ()

    @property
    def all_rim_dofs(self) -> np.ndarray:
        """The reduced indices of every rim's master DOFs, the wheel rim first, flattened."""
        return np.concatenate([self.rim_dofs.ravel(), *(d.ravel() for d, _ in self.more_rims)])

    def reduce(self, A: sp.spmatrix) -> sp.csr_matrix:
        """A full-DOF operator on the coupled DOFs: ``T^T A T``."""
        return (self.T.T @ A @ self.T).tocsr()


def _rim_rows(bm: BodyMesh, rim: RimMasters, first_column: int):
    """Eliminated rows of the distributing rim coupling (:mod:`._rim`) of one rim: ``(full
    rows, column keys, values)`` in :func:`couple_masters`' key convention (rim master ``c``
    component ``a`` is the column key ``first_column + 3 c + a``), and the fitted master
    positions."""
    fit = rim_fit(bm, rim.nodes, rim.radius, rim.band)
    m_nodes = rim.nodes.ravel()
    is_master = np.isin(fit.nodes, m_nodes)
    a_m = fit.areas[np.searchsorted(fit.nodes, m_nodes)]
    # u_c = [(G q)_c - sum_{n not a master} N_c(x_n) a_n u_n] / a_c, per component
    Gc = fit.G.tocoo()
    Nc = (sp.diags(np.where(is_master, 0.0, fit.areas)) @ fit.N).tocoo()
    Nc.eliminate_zeros()
    rows, keys, vals = [], [], []
    for a in range(3):
        rows.append(3 * m_nodes[Gc.row] + a)
        keys.append(first_column + 3 * Gc.col + a)
        vals.append(Gc.data / a_m[Gc.row])
        rows.append(3 * m_nodes[Nc.col] + a)
        keys.append(-1 - (3 * fit.nodes[Nc.row] + a))
        vals.append(-Nc.data / a_m[Nc.col])
    return np.concatenate(rows), np.concatenate(keys), np.concatenate(vals), fit.positions


def couple_masters(bm: BodyMesh, ops: Operators, masters: MasterSet) -> Coupled:
    """Add the 6-DOF bearing nodes (rigid or averaging) and the rim masters (nodal or
    distributing, :mod:`._rim`) by a kinematic transformation ``u_full = T q``.

    Args:
        bm: the mesh (node coordinates).
        ops: full operators.
        masters: the master set (rim nodes and coupling, bearing bands and couplings).

    Returns:
        The :class:`Coupled` operators.

    Raises:
        ValueError: two bearings share bore nodes, or a rim master node is a bore-band node.
    """
    n = bm.n_dofs
    # rows of T for the eliminated DOFs: (full row, column key, value); column key >= 0 is a
    # new column (bearing 6 ib + c, then the distributing rim masters 3 c + a), key < 0 is the
    # kept full DOF -1 - key
    elim_rows, elim_keys, elim_vals = [], [], []
    eliminated = np.zeros(n, dtype=bool)
    n_b = len(masters.bearing_rings)
    for ib, (ring, kind, xb) in enumerate(
        zip(masters.bearing_rings, masters.couplings, masters.bearing_positions)
    ):
        d = bm.nodes[ring] - xb
        # rigid kinematics: u_node = u_B + theta_B x d = [I, -skew(d)] [u_B; theta_B]
        R = np.concatenate([np.broadcast_to(np.eye(3), (len(ring), 3, 3)), -_skew(d)], axis=2)
        R = R.reshape(3 * len(ring), 6)
        ring_dofs = (3 * ring[:, None] + np.arange(3)).ravel()
        if eliminated[ring_dofs].any():
            raise ValueError("two bearings share bore nodes; move them apart")
        rows, keys, vals, gone = kind.rows(R, ring_dofs, 6 * ib)
        elim_rows.extend(rows)
        elim_keys.extend(keys)
        elim_vals.extend(vals)
        eliminated[gone] = True
    rims = masters.rims
    positions = []
    columns = []  # the new columns of each rim's masters (none for FE-node masters)
    column = 6 * n_b  # the first column key of the next rim's new masters
    for rim in rims:
        rim_full = 3 * rim.nodes[..., None] + np.arange(3)
        if eliminated[rim_full].any():
            raise ValueError("a rim master node is also a bearing-ring or another rim's node")
        rows, keys, vals, pos, n_cols, gone = masters.rim_coupling.masters(bm, rim, column)
        positions.append(pos)
        columns.append((column, n_cols))
        column += n_cols
        for k in keys:
            touched = np.unique(-1 - k[k < 0])
            if eliminated[touched].any():
                raise ValueError("a rim master node is also a bearing-ring or another rim's node")
        elim_rows.extend(rows)
        elim_keys.extend(keys)
        elim_vals.extend(vals)
        eliminated[gone] = True
    kept = np.nonzero(~eliminated)[0]
    full_to_red = -np.ones(n, dtype=np.int64)
    full_to_red[kept] = np.arange(len(kept))
    n_new = column
    n_red = len(kept) + n_new
    new_cols = len(kept) + np.arange(n_new)
    bearing_dofs = new_cols[: 6 * n_b].reshape(n_b, 6)
    rim_dofs = [
        masters.rim_coupling.master_dofs(rim, new_cols[c0 : c0 + n_c], full_to_red)
        for rim, (c0, n_c) in zip(rims, columns)
    ]
    keys = np.concatenate(elim_keys) if elim_keys else np.zeros(0, dtype=np.int64)
    ncols = new_cols[np.clip(keys, 0, max(n_new - 1, 0))] if n_new else keys
    fcols = full_to_red[np.maximum(-1 - keys, 0)]
    rows = np.concatenate([kept, *elim_rows])
    cols = np.concatenate([np.arange(len(kept)), np.where(keys >= 0, ncols, fcols)])
    vals = np.concatenate([np.ones(len(kept)), *elim_vals])
    T = sp.csr_matrix((vals, (rows, cols)), shape=(n, n_red))
    Tt = T.T.tocsr()
    K = (Tt @ ops.K @ T).tocsr()
    M = (Tt @ ops.M @ T).tocsr()
    G = (Tt @ ops.gyroscopic @ T).tocsr()
    S = (Tt @ ops.spin_softening @ T).tocsr()
    f = Tt @ ops.f_centrifugal
    return Coupled(
        T=T,
        K=K,
        M=M,
        f=f,
        G=G,
        S=S,
        bearing_dofs=bearing_dofs,
        rim_dofs=rim_dofs[0],
        rim_positions=positions[0],
        full_to_red=full_to_red,
        more_rims=tuple(zip(rim_dofs[1:], positions[1:])),
    )


def band_reaction_stiffness(
    cp: Coupled, masters: MasterSet, nodes: np.ndarray, r: np.ndarray
) -> sp.csr_matrix:
    """Load stiffness of the bearing-band reactions of the prestress, carried by the shaft.

    The centrifugal prestress is solved with the bearing nodes held, so the shaft (the rigid or
    averaging coupling) pushes on the bore-band nodes with forces ``r = K u0 - f_c``,
    self-equilibrated on an axisymmetric body but not zero.  The stress stiffening of that
    prestress then obeys, for any rigid rotation ``u_R = w x x`` of the body,
    ``(K_sigma + S) u_R = w x r`` node by node (S the spin softening): a rigid turn about the
    axis would meet a spurious stiffness ``sum_i x_i . r_i`` (in-plane parts) unless the shaft,
    which turns with the body and carries the opposite forces in its own stress, brings the
    opposite term.  The reactions turn with their bearing node, ``delta r_i = theta_b x r_i``,
    and do the work ``(theta_b x x_i) . (theta_b x r_i) = theta_b^T A_i theta_b`` on a rigid
    rotation, ``A_i = (x_i . r_i) I - r_i x_i^T`` (``x_i`` from the body origin on the axis: the
    bands' axial forces, an axial pair between two bearings, are included through it).  The
    shaft's term is ``-sym(sum_i A_i)`` on each bearing node's rotations (the skew part of the
    sum is the reactions' resultant moment, zero on an axisymmetric body): zero on rigid
    translations, and with it ``K_sigma + S`` is neutral to the drive rotation and gives the
    rigid body's tilt stiffness ``int rho (y^2 - z^2) dV`` about x (``I_p - I_d``) per unit
    speed squared.

    Args:
        cp: the coupled operators (``bearing_dofs``, the size).
        masters: the bearing bands (``bearing_rings``).
        nodes: mesh node coordinates ``(n_nodes, 3)`` (m).
        r: full-DOF reactions of the prestress per unit speed squared ``(n_full,)`` (N).

    Returns:
        ``(n_red, n_red)`` CSR, symmetric, non-zero on the bearing rotations only (N m per unit
        speed squared).
    """
    rows, cols, vals = [], [], []
    for ib, ring in enumerate(masters.bearing_rings):
        x = nodes[ring]
        rr = r.reshape(-1, 3)[ring]
        A = np.sum(np.einsum("ij,ij->i", x, rr)) * np.eye(3) - rr.T @ x
        rot = cp.bearing_dofs[ib, 3:]
        rows.append(np.repeat(rot, 3))
        cols.append(np.tile(rot, 3))
        vals.append((-0.5 * (A + A.T)).ravel())
    n_red = cp.K.shape[0]
    return sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))), shape=(n_red, n_red)
    )


# ------------------------------------------------------------------------------------------
# the couplings


@final
class Rigid(BearingCoupling):
    """Every band DOF follows the bearing node: ``u = R q_B`` (``coupling = "rigid"``)."""

    name: ClassVar[str] = "rigid"

    def rows(self, R, ring_dofs, first_column):
        r_loc, c = np.nonzero(R)
        return [ring_dofs[r_loc]], [first_column + c], [R[r_loc, c]], ring_dofs


@final
class Averaging(BearingCoupling):
    """RBE3-like (``coupling = "averaging"``): ``q_B = W u_band``, the least-squares rigid fit of
    the band (equal weights); six band DOFs become dependent: ``u_dep = Wd^-1 q_B + A u_ind``."""

    name: ClassVar[str] = "averaging"

    def rows(self, R, ring_dofs, first_column):
        W = np.linalg.pinv(R)  # (6, 3 n_r)
        _, _, piv = sla.qr(W, pivoting=True, mode="economic")
        dep = np.sort(piv[:6])
        ind = np.setdiff1d(np.arange(len(ring_dofs)), dep)
        Wd_inv = np.linalg.inv(W[:, dep])
        A = -Wd_inv @ W[:, ind]
        a_loc, c = np.nonzero(Wd_inv)
        b_loc, j = np.nonzero(A)
        return (
            [ring_dofs[dep[a_loc]], ring_dofs[dep[b_loc]]],
            [first_column + c, -1 - ring_dofs[ind[j]]],
            [Wd_inv[a_loc, c], A[b_loc, j]],
            ring_dofs[dep],
        )


@final
class Distributing(RimCoupling):
    """The rim masters are the least-squares fit of the whole outer face, the tooth loads spread
    as a traction (``rim_coupling = "distributing"``, :mod:`._rim`): new DOFs, the masters' FE
    nodes eliminated."""

    name: ClassVar[str] = "distributing"

    def masters(self, bm, rim, first_column):
        rows, keys, vals, positions = _rim_rows(bm, rim, first_column)
        gone = (3 * rim.nodes[..., None] + np.arange(3)).ravel()
        return [rows], [keys], [vals], positions, 3 * rim.nodes.size, gone

    def master_dofs(self, rim, columns, full_to_red):
        return columns.reshape(*rim.nodes.shape, 3)

    def cache_revision(self) -> str:
        return f":rim{RIM_FIT_REVISION}"


@final
class Nodal(RimCoupling):
    """The rim masters are the FE nodes at the stations (``rim_coupling = "nodal"``), kept as
    such."""

    name: ClassVar[str] = "nodal"

    def masters(self, bm, rim, first_column):
        return [], [], [], bm.nodes[rim.nodes], 0, np.zeros(0, dtype=np.int64)

    def master_dofs(self, rim, columns, full_to_red):
        return full_to_red[3 * rim.nodes[..., None] + np.arange(3)]

    def cache_revision(self) -> str:
        return ""
