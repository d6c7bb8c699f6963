"""Master nodes, bearing couplings and component-mode condensation (seed (2.3)-(2.5)).

Notation (seed (2.3)): the reduced DOF vector is split into boundary (master) DOFs ``b`` and
interior DOFs ``i``.

* Guyan: ``u = [I; G_ib] u_b`` with ``G_ib = -K_ii^-1 K_ib`` (static constraint modes).
* Craig-Bampton (fixed interface, [CRA68]): ``u = [I 0; G_ib Phi_i] [u_b; q]`` with ``Phi_i`` the
  first modes of ``(K_ii, M_ii)`` (interface held), mass-normalised.
* Herting (free interface, [HER85], seed (2.4)): ``u = [I 0; G_ib (phi_i - G_ib phi_b)] [u_b;
  q]`` with ``phi`` the first elastic modes of the free structure (rigid-body modes are already
  spanned by the constraint modes and are dropped).  The modal block is then re-orthonormalised
  (mass-orthonormal, stiffness-diagonal) so that ``K_s = [[K_bb, 0], [0, K_nn]]`` (2.5): boundary
  and modal DOFs are statically uncoupled.  The inertia-relief term ``H_i0`` of (2.4) is not
  needed because the rigid-body motion is exactly represented by the constraint modes.

Bearings are 6-DOF nodes on the axis coupled to every bore node of an axial band (the bearing
width, ``BearingSeat.z_band``) by a kinematic transformation ``u = T q``: rigid (every band node
follows the rigid motion of the bearing node, a clamped bore over the bearing width) or
averaging (RBE3-like: the bearing node moves as the least-squares rigid fit of the band; six
band DOFs are eliminated).  Coupling a whole band rather than one node ring makes the support a
surface constraint, whose result converges under mesh refinement (a ring is a line constraint:
its stresses are singular and the deflection it allows grows logarithmically as the mesh is
refined).  The rim masters are the FE nodes at the tooth stations (``"nodal"``) or, by the same
kind of transformation, the least-squares fit of the rim face (``"distributing"``, :mod:`._rim`).
"""

from __future__ import annotations

import functools
import math
import time
from dataclasses import dataclass, field

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from tqdm import tqdm

from ._assemble import Operators
from ._body import Body
from ._mesh import BodyMesh, pinion_master_z, rim_master_z
from ._rim import rim_fit
from ._solver import (
    CholmodFactor,
    SparseFactor,
    blas_threads,
    factorize,
    phase_bar,
    shift_invert_modes,
    solve_bar,
)

__all__ = [
    "Condensed",
    "Coupled",
    "MasterSet",
    "RimMasters",
    "band_reaction_stiffness",
    "condense",
    "couple_masters",
    "frequency_error_vs_modes",
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
        couplings: ``"rigid"`` or ``"averaging"`` per bearing.
        rim_coupling: ``"distributing"`` or ``"nodal"`` (:mod:`._rim`), for every rim.
        rim_radius: the outer rim radius (m).
        rim_band: the rim's outer face's axial extent (m), or ``None``: all of that radius.
        more_rims: the body's other rims (:class:`RimMasters`: a ``[pinion_rim]``), whose
            masters follow the wheel rim's.
    """

    rim_nodes: np.ndarray
    bearing_positions: np.ndarray
    bearing_rings: tuple[np.ndarray, ...]
    couplings: tuple[str, ...]
    rim_coupling: str = "distributing"
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
        if kind == "rigid":
            # every band DOF follows the bearing node: u = R q_B
            r_loc, c = np.nonzero(R)
            elim_rows.append(ring_dofs[r_loc])
            elim_keys.append(6 * ib + c)
            elim_vals.append(R[r_loc, c])
            eliminated[ring_dofs] = True
        else:
            # RBE3-like: q_B = W u_band, the least-squares rigid fit of the band (equal weights);
            # six band DOFs become dependent: u_dep = Wd^-1 q_B + A u_ind
            W = np.linalg.pinv(R)  # (6, 3 n_r)
            _, _, piv = sla.qr(W, pivoting=True, mode="economic")
            dep = np.sort(piv[:6])
            ind = np.setdiff1d(np.arange(len(ring_dofs)), dep)
            Wd_inv = np.linalg.inv(W[:, dep])
            A = -Wd_inv @ W[:, ind]
            a_loc, c = np.nonzero(Wd_inv)
            elim_rows.append(ring_dofs[dep[a_loc]])
            elim_keys.append(6 * ib + c)
            elim_vals.append(Wd_inv[a_loc, c])
            a_loc, j = np.nonzero(A)
            elim_rows.append(ring_dofs[dep[a_loc]])
            elim_keys.append(-1 - ring_dofs[ind[j]])
            elim_vals.append(A[a_loc, j])
            eliminated[ring_dofs[dep]] = True
    rims = masters.rims
    distributing = masters.rim_coupling == "distributing"
    positions = []
    column = 6 * n_b  # the first column key of the next rim's distributing masters
    for rim in rims:
        rim_full = 3 * rim.nodes[..., None] + np.arange(3)
        if eliminated[rim_full].any():
            raise ValueError("a rim master node is also a bearing-ring or another rim's node")
        positions.append(bm.nodes[rim.nodes])
        if distributing:
            rows, keys, vals, positions[-1] = _rim_rows(bm, rim, column)
            column += 3 * rim.nodes.size
            touched = np.unique(-1 - keys[keys < 0])
            if eliminated[touched].any():
                raise ValueError("a rim master node is also a bearing-ring or another rim's node")
            elim_rows.append(rows)
            elim_keys.append(keys)
            elim_vals.append(vals)
            eliminated[rim_full.ravel()] = True
    kept = np.nonzero(~eliminated)[0]
    full_to_red = -np.ones(n, dtype=np.int64)
    full_to_red[kept] = np.arange(len(kept))
    n_new = column if distributing else 6 * n_b
    n_red = len(kept) + n_new
    new_cols = len(kept) + np.arange(n_new)
    bearing_dofs = new_cols[: 6 * n_b].reshape(n_b, 6)
    rim_dofs = []
    start = 6 * n_b
    for rim in rims:
        if distributing:
            rim_dofs.append(
                new_cols[start : start + 3 * rim.nodes.size].reshape(*rim.nodes.shape, 3)
            )
            start += 3 * rim.nodes.size
        else:
            rim_dofs.append(full_to_red[3 * rim.nodes[..., None] + np.arange(3)])
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
# condensation


@dataclass
class Condensed:
    """A condensed substructure.

    Attributes:
        method: ``"guyan"``, ``"craig-bampton"`` or ``"herting"``.
        K, M: condensed stiffness (N/m, N/rad, N m/rad) and mass ``(n_c, n_c)``.
        f_centrifugal: condensed centrifugal vector per unit speed squared ``(n_c,)``.
        spin_softening: condensed spin-softening matrix ``H^T S H`` per unit speed squared
            (symmetric) or ``None`` (no ``S`` given).
        gyroscopic: condensed gyroscopic matrix ``H^T G H`` per unit spin speed (skew) or
            ``None``.
        stress_stiffening: condensed stress-stiffening matrix ``H^T K_sigma H`` per unit speed
            squared (symmetric) or ``None``.
        master_dofs: reduced indices ``(n_b,)`` of the boundary DOFs (condensed rows 0..n_b-1).
        n_modes: number of modal coordinates (condensed rows n_b..n_c-1).
        basis: reduced-space transformation ``(n_red, n_c)``: ``q_red = basis @ q_c`` (the
            transfer matrix H of (2.4)); ``u_full = T @ basis @ q_c``.
        timings: wall times (s) of the steps.
        modes_hz: natural frequencies of the modes kept in the basis (Hz).
    """

    method: str
    K: np.ndarray
    M: np.ndarray
    f_centrifugal: np.ndarray
    spin_softening: np.ndarray | None
    master_dofs: np.ndarray
    n_modes: int
    basis: np.ndarray
    timings: dict[str, float] = field(default_factory=dict)
    modes_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    gyroscopic: np.ndarray | None = None
    stress_stiffening: np.ndarray | None = None


def _project(
    A: sp.spmatrix, V: np.ndarray, block: int = 256, *, skew: bool = False, bar=None
) -> np.ndarray:
    """``V^T A V`` by column blocks (bounded memory), symmetrised (``skew=False``: A symmetric)
    or skew-symmetrised (``skew=True``: A skew-symmetric) to remove the rounding. ``bar``: a
    tqdm bar advanced by one per column block."""
    out = np.empty((V.shape[1], V.shape[1]))
    for c0 in range(0, V.shape[1], block):
        c1 = min(V.shape[1], c0 + block)
        out[:, c0:c1] = V.T @ (A @ V[:, c0:c1])
        if bar is not None:
            bar.update()
    return 0.5 * (out - out.T) if skew else 0.5 * (out + out.T)


def _condense(
    K: sp.spmatrix,
    M: sp.spmatrix,
    master_dofs: np.ndarray,
    *,
    method: str = "craig-bampton",
    n_modes: int = 50,
    f: np.ndarray | None = None,
    S: sp.spmatrix | None = None,
    G: sp.spmatrix | None = None,
    Ksigma: sp.spmatrix | None = None,
    progress: bool = False,
    interior_factor: CholmodFactor | SparseFactor | None = None,
    free_shift: float | None = None,
    static_correction: bool = True,
) -> Condensed:
    """Condense ``(K, M)`` onto ``master_dofs`` (+ ``n_modes`` modal DOFs), seed (2.3)-(2.5).

    Args:
        K, M: sparse symmetric stiffness and mass ``(n, n)`` of the (coupled) structure.
        master_dofs: boundary DOF indices ``(n_b,)``; they must restrain the rigid-body modes
            (``K_ii`` non-singular).
        method: ``"guyan"``, ``"craig-bampton"`` or ``"herting"``.
        n_modes: number of retained modes (ignored by Guyan).
        f: centrifugal vector per unit speed squared ``(n,)`` (condensed as ``H^T f``, (2.37)).
        S: spin-softening matrix ``(n, n)`` per unit speed squared or ``None``.
        G: gyroscopic matrix ``(n, n)`` per unit spin speed (skew-symmetric) or ``None``.
        Ksigma: stress-stiffening matrix ``(n, n)`` per unit speed squared or ``None``.
            ``S``, ``G``, ``Ksigma`` are projected on the basis (``H^T A H``) and do not
            change it (the modes and ψ are those of ``K``, ``M`` and ``f``).
        progress: show tqdm progress bars.
        interior_factor: a factorisation of ``K_ii`` to reuse.
        free_shift: shift (rad/s)^2 (negative) for the free-interface eigen-solve of Herting;
            default ``-1e-4`` x the median of ``diag(K)/diag(M)``.
        static_correction: with ``f`` given and a modal method, add the static correction
            vector ψ = K_ii⁻¹ f_i of the body load (M-orthogonalised against the retained modes,
            unit modal mass) as one more modal DOF: the fixed-interface modes are bending modes
            and do not carry the in-plane static response to the centrifugal load, so without
            ψ the recovered interior field misses it (its frequency is listed in ``modes_hz``).

    Returns:
        The :class:`Condensed` model; boundary DOFs first in the order of ``master_dofs``.

    Raises:
        ValueError: unknown method or negative ``n_modes``.
    """
    if method not in ("guyan", "craig-bampton", "herting"):
        raise ValueError(f"method = {method!r}; use 'guyan', 'craig-bampton' or 'herting'")
    if n_modes < 0:
        raise ValueError(f"n_modes = {n_modes} must be >= 0")
    K = sp.csr_matrix(K)
    M = sp.csr_matrix(M)
    n = K.shape[0]
    b = np.asarray(master_dofs, dtype=np.int64)
    mask = np.ones(n, dtype=bool)
    mask[b] = False
    i = np.nonzero(mask)[0]
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    Kii = K[i][:, i]
    Kib = K[i][:, b]
    if interior_factor is None:
        with phase_bar(f"factorisation of K_ii (n = {len(i)})", progress):
            Fii = factorize(Kii)
    else:
        Fii = interior_factor
    timings["factorisation_s"] = time.perf_counter() - t0

    # static constraint modes G_ib = -K_ii^-1 K_ib, by column blocks
    t0 = time.perf_counter()
    H = np.zeros((n, len(b) + (0 if method == "guyan" else n_modes)))
    H[b, np.arange(len(b))] = 1.0
    blk = 128
    it = range(0, len(b), blk)
    for c0 in tqdm(it, desc="constraint modes", disable=not progress, unit="block", leave=False):
        c1 = min(len(b), c0 + blk)
        H[i, c0:c1] = -Fii.solve(Kib[:, c0:c1].toarray())
    timings["static_modes_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    modes_hz = np.zeros(0)
    nb = len(b)
    if method == "craig-bampton" and n_modes > 0:
        Mii = M[i][:, i]
        with solve_bar(f"fixed-interface modes ({n_modes})", progress) as bar:
            lam, phi = shift_invert_modes(
                Kii, Mii, n_modes, sigma=0.0, factor=Fii, on_solve=bar.update
            )
        H[i, nb:] = phi
        modes_hz = np.sqrt(np.maximum(lam, 0)) / (2 * math.pi)
    elif method == "herting" and n_modes > 0:
        if free_shift is None:
            free_shift = -float(np.median(K.diagonal() / np.maximum(M.diagonal(), 1e-300))) * 1e-4
        with phase_bar(f"factorisation of K - s M (n = {n})", progress):
            Ffree = factorize((K - free_shift * M).tocsr())
        n_rigid = 6
        with solve_bar(f"free-interface modes ({n_modes + n_rigid})", progress) as bar:
            lam, phi = shift_invert_modes(
                K, M, n_modes + n_rigid, sigma=free_shift, factor=Ffree, on_solve=bar.update
            )
        del Ffree
        # drop rigid-body modes (captured by the constraint modes)
        lam_ref = max(abs(lam[-1]), 1.0)
        elastic = lam > 1e-8 * lam_ref
        lam, phi = lam[elastic][:n_modes], phi[:, elastic][:, :n_modes]
        modes_hz = np.sqrt(lam) / (2 * math.pi)
        chi = phi - H[:, :nb] @ phi[b]  # (2.4): [0; phi_i - G_ib phi_b]
        chi[b] = 0.0
        Mcc = _project(M, chi)
        Kcc = _project(K, chi)
        d, V = np.linalg.eigh(Mcc)
        keep = d > 1e-10 * d.max()
        Q = V[:, keep] / np.sqrt(d[keep])
        lam2, U = np.linalg.eigh(Q.T @ Kcc @ Q)
        chi = chi @ (Q @ U)
        H = H[:, : nb + chi.shape[1]]
        H[:, nb:] = chi
    if static_correction and f is not None and method != "guyan" and np.any(f[i] != 0):
        # static correction vector (residual-flexibility attachment of the body load)
        Mii = M[i][:, i]
        psi = Fii.solve(np.asarray(f, dtype=float)[i])
        modal = H[i, nb:]
        for _ in range(2):  # M-orthogonalise against the retained modes (CGS2)
            psi = psi - modal @ (modal.T @ (Mii @ psi))
        m_psi = float(psi @ (Mii @ psi))
        k_psi = float(psi @ (Kii @ psi))
        if m_psi > 0 and np.linalg.norm(psi) > 1e-8 * np.linalg.norm(Fii.solve(f[i])):
            col = np.zeros((n, 1))
            col[i, 0] = psi / math.sqrt(m_psi)
            if method == "herting":
                # the Herting block is not K_ii-orthogonal to ψ: re-diagonalise it with ψ
                chi = np.hstack([H[:, nb:], col])
                d, V = np.linalg.eigh(_project(M, chi))
                keep = d > 1e-10 * d.max()
                Q = V[:, keep] / np.sqrt(d[keep])
                lam2, U = np.linalg.eigh(Q.T @ _project(K, chi) @ Q)
                H = np.hstack([H[:, :nb], chi @ (Q @ U)])
                modes_hz = np.sqrt(np.maximum(lam2, 0)) / (2 * math.pi)
            else:
                # fixed-interface modes are K_ii-orthogonal to an M-orthogonal ψ: block stays diagonal
                H = np.hstack([H, col])
                modes_hz = np.r_[modes_hz, math.sqrt(max(k_psi / m_psi, 0.0)) / (2 * math.pi)]
    timings["eigen_s"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    n_mat = 2 + sum(A is not None for A in (S, G, Ksigma))
    with tqdm(
        total=n_mat * -(-H.shape[1] // 256),
        desc=f"projection H^T A H ({n_mat} matrices, {H.shape[1]} columns)",
        disable=not progress,
        unit="block",
        leave=False,
    ) as bar:
        Kc = _project(K, H, bar=bar)
        Mc = _project(M, H, bar=bar)
        # exact structure (2.5): boundary/modal blocks statically uncoupled
        if H.shape[1] > nb:
            Kc[:nb, nb:] = 0.0
            Kc[nb:, :nb] = 0.0
        fc = H.T @ f if f is not None else np.zeros(H.shape[1])
        Sc = _project(S, H, bar=bar) if S is not None else None
        Gc = _project(G, H, skew=True, bar=bar) if G is not None else None
        Ksc = _project(Ksigma, H, bar=bar) if Ksigma is not None else None
    timings["projection_s"] = time.perf_counter() - t0
    return Condensed(
        method=method,
        K=Kc,
        M=Mc,
        f_centrifugal=fc,
        spin_softening=Sc,
        master_dofs=b,
        n_modes=H.shape[1] - nb,
        basis=H,
        timings=timings,
        modes_hz=modes_hz,
        gyroscopic=Gc,
        stress_stiffening=Ksc,
    )


@functools.wraps(_condense)
def condense(*args, **kwargs) -> Condensed:
    with blas_threads():
        return _condense(*args, **kwargs)


def frequency_error_vs_modes(prep, modes, methods=("craig-bampton", "herting")) -> dict:
    """Largest relative error of the full model's first frequencies (bearings held) against the
    number of retained modes, for each condensation method (Fig. III-13's question).

    Args:
        prep: a :class:`~fem_prep.Prepared` body (its ``frequencies_full_hz`` are the reference).
        modes: numbers of retained modes to try. methods: condensation methods.

    Returns:
        ``{method: [error for each entry of modes]}``.
    """
    import scipy.linalg as sla

    f_full = np.asarray(prep.frequencies_full_hz)
    cp = prep.coupled
    bearing_c = len(prep.master_dofs) - cp.bearing_dofs.size + np.arange(cp.bearing_dofs.size)
    curves = {}
    for method in methods:
        errs = []
        for m in modes:
            c = condense(cp.K, cp.M, prep.master_dofs, method=method, n_modes=m)
            keep = np.ones(c.K.shape[0], bool)
            keep[bearing_c] = False
            lam = sla.eigh(c.K[np.ix_(keep, keep)], c.M[np.ix_(keep, keep)], eigvals_only=True)
            fc = np.sqrt(np.maximum(lam[: len(f_full)], 0)) / (2 * math.pi)
            errs.append(float(np.max(np.abs(fc / f_full - 1))))
        curves[method] = errs
    return curves
