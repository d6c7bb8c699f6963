"""How the tooth roots load the rim: the rim master coupling (issue: a hybrid interface that
converges under mesh refinement; docs/fem_prep.md, "Rim masters").

The hybrid interface (``jaxgear.scenes``, docs/hybrid.md, "The interface") reads the rim as a
bilinear master field on the outer rim face ``r = R`` (the root radius, no teeth):

    v(x) = sum_c N_c(x) q_c,

one master ``c = (k, j)`` per tooth station ``k`` (angle ``2 pi k / Z``) and axial master plane
``z_j``; across a face between stations ``k`` and ``k + 1`` the coordinate is the orthogonal
projection on the face's chord, along the axis the linear one (a constant when there is one
axial master plane).  The tooth roots load that field at their root points with the bilinear
weights, so the master DOFs must be *what the interface interpolates*.  Two couplings:

``"nodal"``
    ``q_c`` is the displacement of the FE node at the station (the corner of the hex faces).
    A tooth's load is then a concentrated nodal force on a 3-D continuum, whose local
    indentation grows without bound as the elements under it shrink: the compliance at the
    masters depends on the mesh (kept for comparison).

``"distributing"`` (the default)
    ``q`` is a weighted least-squares fit of the FE displacement of the whole outer rim face,
    station by station: the masters ``(k, j)`` of station ``k`` minimise

        sum_n a_n N_k(theta_n) |sum_j N_j(z_n) q_kj - u_n|^2,

    the face nodes ``n`` weighted by their consistent nodal areas ``a_n = int phi_n dS`` (the
    nodal loads of a unit uniform traction: negative at the corners of serendipity faces) and
    by the station's circumferential hat ``N_k(theta)`` (1 at the station, 0 at its
    neighbours).  Circumferentially each station is the hat-weighted *average* of the face
    over its two neighbouring pitches; along the axis it is a least-squares fit on the axial
    master planes.  The normal equations are

        G q = N^T A u_S,    G_(kj),(kj') = sum_n N_k(theta_n) N_j(z_n) N_j'(z_n) a_n,

    with ``N_nc = N_c(x_n) = N_k(theta_n) N_j(z_n)``: ``G`` is block diagonal, one
    ``n_ax x n_ax`` block per station (the consistent Gram ``N^T A N`` summed over the
    stations, which ``sum_k N_k = 1`` allows).  By virtual work a master force vector ``F``
    loads the face with the nodal forces ``A N G^-1 F``: station ``k``'s forces as the
    traction ``N_k(theta) sum_j N_j(z) (G^-1 F)_kj`` (a hat over the two pitches, linear
    between the axial planes) put on the nodes as ``t(x_n) a_n``, the consistent load of ``t``
    up to its variation over an element.  The tooth's load is thus spread over a band one
    pitch wide at half height, about the root patch a tooth occupies on the rim (root and
    fillets span a pitch at the root circle), and the result converges as the mesh is refined
    (an RBE3-like distributing coupling; the averaging bearing coupling is its rigid-body
    analogue).

    ``G`` is positive definite: along a line of constant ``z`` the weights ``N_k(theta_n) a_n``
    of a face row sum to a positive number (for a serendipity face ``-1/12 - 1/12 + 1/3`` per
    edge row, ``2/3`` on its middle row: Simpson's weights), so each block is a 1-D Gram of
    the axial hats under a positive rule.  :func:`rim_fit` checks it.

    Two other projections were measured (docs/fem_prep.md, "Rim masters") and rejected: the
    full consistent Gram ``N^T A N`` (exact for bilinear master fields, but indefinite with
    negative corner areas: on the accessory wheel 70 of its 430 eigenvalues were negative, the
    masters' checkerboard patterns nearly free, spurious soft mesh modes at 2.7 and 4.2 kHz),
    and positive lumped areas (Hinton-Rock-Zienkiewicz: corners loaded against the consistent
    pattern, the disc's rim displacement converging only as h^0.8, +4.9, +2.8, +1.5 % off
    Lamé).

Elimination: the FE node at master ``c`` has ``N_c = 1`` and ``N_d = 0`` for every other master,
so row ``c`` of ``G q = N^T A u_S`` reads ``a_c u_c + sum_{n not a master} N_c(x_n) a_n u_n =
(G q)_c``; the master node's three DOFs become dependent,

    u_c = [(G q)_c - sum_n N_c(x_n) a_n u_n] / a_c,

a sparse row (``G`` couples the masters of one station only).  Rigid motions: ``G 1 = N^T A 1``
(the axial hats sum to one), so the fit reproduces a field affine in ``x`` exactly with each
master at its fitted position ``x_hat = G^-1 N^T A x_S``: on its axial plane exactly, and
radially the hat-weighted mean of the arc (inside it by about ``R p^2 / 12`` for the pitch
angle ``p``).  ``u = a + w x x`` then gives ``q_c = a + w x x_hat_c``, so the condensed body is
free of rigid motions with the masters at ``x_hat`` (stored as the master coordinates).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem

from ._mesh import BodyMesh

__all__ = ["RIM_FIT_REVISION", "RimFit", "rim_fit"]

# the distributing coupling's revision, part of fem_prep's cache key for bodies that use it
# (1: the consistent Gram N^T A N, indefinite, withdrawn; 2: the station Gram)
RIM_FIT_REVISION = 2


@dataclass(frozen=True)
class RimFit:
    """The distributing rim coupling of :func:`rim_fit` (module docstring).

    Attributes:
        nodes: FE node index of every node of the outer rim face, shape ``(n_S,)``.
        areas: their consistent nodal areas ``a_n`` (m^2), shape ``(n_S,)``, summing to the
            face area (negative at serendipity corners, never zero).
        N: master weights ``N_c(x_n)``, sparse ``(n_S, Z n_ax)`` (masters in station-major
            order, ``c = k n_ax + j``).
        G: the station Gram (block diagonal, one ``n_ax x n_ax`` block per station, positive
            definite), sparse ``(Z n_ax, Z n_ax)`` (m^2).
        positions: fitted master positions ``x_hat`` (m), shape ``(Z, n_ax, 3)``.
    """

    nodes: np.ndarray
    areas: np.ndarray
    N: sp.csr_matrix
    G: sp.csr_matrix
    positions: np.ndarray


def _face_facets(bm: BodyMesh, radius: float, band=None) -> np.ndarray:
    """Boundary facets whose corners all lie on the cylinder ``r = radius`` (and, with
    ``band``, within that axial extent (m): one rim's face of a body with two)."""
    facets = bm.mesh.boundary_facets()
    corners = bm.mesh.facets[:, facets]  # (4, n_f) vertex indices
    rho = np.hypot(bm.nodes[corners, 0], bm.nodes[corners, 1])
    on = np.all(np.abs(rho - radius) < 1e-7 * radius, axis=0)
    if band is not None:
        z = bm.nodes[corners, 2]
        tol = 1e-9 + 1e-9 * radius
        on &= np.all((z > band[0] - tol) & (z < band[1] + tol), axis=0)
    return facets[on]


def _nodal_areas(bm: BodyMesh, facets: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Face nodes and their consistent nodal areas ``a_n = int_face phi_n dS`` (the load of a
    unit uniform traction; negative at the corners of serendipity faces, -1/12 of a flat face
    each).

    Integrated on each facet's reference face of its element (Gauss order 6 on the face, the
    area element of Nanson's formula ``dS = |det F| |F^-T n_ref| dS_ref`` of the element's
    isoparametric map), never by inverting that map at points found in space: skfem's
    ``FacetBasis`` does (a Newton iteration to 1e-12 per point), which fails on the thin, curved
    quadratic elements of a ring with three or more elements through its thickness."""
    el = bm.element.skfem_element()
    mesh = bm.mesh
    mapping = mesh._mapping()
    element_dofs = skfem.Dofs(mesh, el).element_dofs
    facets = np.asarray(facets)
    t = mesh.f2t[0, facets]
    # the facet's vertices among its element's: the reference coordinate constant on them
    local = np.argmax(mesh.t[:, t][None, :, :] == mesh.facets[:, facets][:, None, :], axis=1)
    corners = mesh.init_refdom().p[:, local]  # (dim, 4, n_f)
    axis = np.argmax(np.ptp(corners, axis=1) == 0, axis=0)
    value = corners[axis, 0, np.arange(facets.size)]
    xq, wq = skfem.quadrature.get_quadrature(skfem.refdom.RefQuad, 6)
    share = np.zeros((element_dofs.shape[0], facets.size))  # (n_loc, n_f)
    for a, v in itertools.product(range(3), (0.0, 1.0)):
        sel = np.nonzero((axis == a) & (value == v))[0]
        if sel.size:
            X = np.insert(xq, a, v, axis=0)
            inv = mapping.invDF(X, tind=t[sel])
            ds = np.abs(mapping.detDF(X, tind=t[sel])) * np.sqrt(np.sum(inv[a] ** 2, axis=0))
            phi = np.stack([np.asarray(el.lbasis(X, i)[0]) for i in range(share.shape[0])])
            share[:, sel] = phi @ (ds * wq).T
    dofs = element_dofs[:, t]
    a_n = np.bincount(dofs.ravel(), weights=share.ravel(), minlength=bm.n_nodes)
    # the face's nodes: those whose shape function is not zero on it (a corner's area may be
    # small but is not zero)
    on_face = np.abs(share) > 1e-12 * np.abs(share).max()
    nodes = np.unique(dofs[on_face])
    return nodes, a_n[nodes]


def _weights(
    x: np.ndarray, teeth: int, station0: float, radius: float, z_nodes: np.ndarray
) -> sp.csr_matrix:
    """Bilinear master weights ``N_c(x)`` of points ``x`` (n, 3) on the face: across a face the
    orthogonal projection on its chord, along the axis linear (constant for one plane)."""
    n = len(x)
    pitch = 2 * math.pi / teeth
    t = np.mod(np.arctan2(x[:, 1], x[:, 0]) - station0, 2 * math.pi) / pitch
    k = np.minimum(np.floor(t).astype(np.int64), teeth - 1)
    a0 = station0 + k * pitch
    p0 = radius * np.stack([np.cos(a0), np.sin(a0)], 1)
    p1 = radius * np.stack([np.cos(a0 + pitch), np.sin(a0 + pitch)], 1)
    d = p1 - p0
    xi = np.clip(np.sum((x[:, :2] - p0) * d, 1) / np.sum(d * d, 1), 0.0, 1.0)
    n_ax = len(z_nodes)
    if n_ax == 1:
        j = np.zeros(n, dtype=np.int64)
        eta = np.zeros(n)
        zw = [(j, np.ones(n))]
    else:
        j = np.clip(np.searchsorted(z_nodes, x[:, 2], side="right") - 1, 0, n_ax - 2)
        eta = np.clip((x[:, 2] - z_nodes[j]) / (z_nodes[j + 1] - z_nodes[j]), 0.0, 1.0)
        zw = [(j, 1 - eta), (j + 1, eta)]
    rows, cols, vals = [], [], []
    for ks, wk in ((k, 1 - xi), ((k + 1) % teeth, xi)):
        for js, wj in zw:
            rows.append(np.arange(n))
            cols.append(ks * n_ax + js)
            vals.append(wk * wj)
    W = sp.csr_matrix(
        (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
        shape=(n, teeth * n_ax),
    )
    W.eliminate_zeros()
    return W


def rim_fit(bm: BodyMesh, rim_nodes: np.ndarray, radius: float, band=None) -> RimFit:
    """The distributing rim coupling of a body mesh (module docstring).

    Args:
        bm: the body mesh.
        rim_nodes: FE node at each master ``(Z, n_ax)`` (stations at ``2 pi k / Z`` from the
            first, axial master planes increasing): the nodes the coupling eliminates.
        radius: the outer rim radius R (m).
        band: the face's axial extent (m), or ``None``: every boundary face at ``radius``
            (a body with a pinion rim has two faces to tell apart).

    Returns:
        The :class:`RimFit`.

    Raises:
        ValueError: a master node is not on the outer rim face, or carries the weight of
            another master (the mesh's stations or axial planes do not match the masters), or
            the station Gram is not positive definite.
    """
    teeth, n_ax = rim_nodes.shape
    nodes, areas = _nodal_areas(bm, _face_facets(bm, radius, band))
    x_m = bm.nodes[rim_nodes]
    station0 = float(np.arctan2(x_m[0, 0, 1], x_m[0, 0, 0]))
    z_nodes = x_m[0, :, 2]
    N = _weights(bm.nodes[nodes], teeth, station0, radius, z_nodes)
    pos = np.searchsorted(nodes, rim_nodes.ravel())
    if np.any(pos >= len(nodes)) or np.any(
        nodes[np.minimum(pos, len(nodes) - 1)] != rim_nodes.ravel()
    ):
        raise ValueError("a rim master node is not on the outer rim face")
    at_masters = N[pos].toarray()
    if not np.allclose(at_masters, np.eye(teeth * n_ax), atol=1e-9):
        raise ValueError("the rim master nodes are not at the stations and axial master planes")
    if np.any(areas[pos] == 0):
        raise ValueError("a rim master node has no area on the outer rim face")
    AN = sp.diags(areas) @ N
    full = (N.T @ AN).tocoo()  # the consistent Gram N^T A N, summed over the stations:
    station = full.row // n_ax  # entry ((k, j), (k', j')) goes to ((k, j), (k, j'))
    G = sp.csr_matrix((full.data, (full.row, station * n_ax + full.col % n_ax)), shape=full.shape)
    rhs = AN.T @ bm.nodes[nodes]
    positions = np.column_stack([spla.spsolve(G.tocsc(), rhs[:, c]) for c in range(3)])
    g = G.tocoo()
    blocks = np.zeros((teeth, n_ax, n_ax))
    np.add.at(blocks, (g.row // n_ax, g.row % n_ax, g.col % n_ax), g.data)
    lam = np.linalg.eigvalsh(blocks)  # (Z, n_ax)
    if not np.all(lam > 0):
        raise ValueError(
            f"the rim fit's station Gram is not positive definite (smallest eigenvalue "
            f"{lam.min():.3e} m^2): the outer rim face's mesh does not resolve the axial master "
            "planes; use rim_coupling = 'nodal' (fem_prep._rim)"
        )
    return RimFit(
        nodes=nodes,
        areas=areas,
        N=N.tocsr(),
        G=G,
        positions=positions.reshape(teeth, n_ax, 3),
    )
