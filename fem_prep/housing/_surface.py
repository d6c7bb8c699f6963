"""The housing's outer surface for its vibration and radiated power: the boundary facets of the
outer skin, their areas and outward normals, the operator from the FE displacement to each
facet's mean normal displacement, named points on the skin, and operating deflection shapes to
VTU.

The outer skin is the connected set of boundary facets (facets sharing a vertex) that holds the
boundary facet farthest along +x, the bearing seats' bore facets left out: a closed box's inner
wall faces form a set of their own (the bores through the walls are the only paths between
them), so they are not counted. The mean normal displacement of a facet is exact for the
element's shape functions: on a quadratic triangle the vertex functions integrate to zero and
each edge-midpoint function to A / 3, so the mean is the average of the three edge-midpoint
nodes (:class:`~fem_prep.housing.Tet10`); on a linear one, of the three vertices. The mean
square normal displacement is integrated exactly as well: ∫_f |u·n|² dS = wᵀ M_f w with w the
normal displacements of the facet's nodes (six on a quadratic triangle, three on a linear one)
and M_f the triangle's mass matrix of those shape functions (Zienkiewicz, Taylor & Zhu, *The
Finite Element Method*, 7th ed., §6.7: A/180 · [6 on the vertices' diagonal, −1 between
vertices, −4 between a vertex and the midside node facing it, 32 and 16 among midside nodes];
A/12 · [2, 1] for the linear one), written as ‖C w‖² with C = √A · chol(M_f / A)ᵀ.

NumPy/SciPy/scikit-fem; never imports JAX.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from ..acoustics import RadiatingSurface
from ..files import atomic_write
from ._mesh import HousingMesh

__all__ = [
    "HousingSurface",
    "RadiatingSkin",
    "closed_outer_surface",
    "outer_surface",
    "write_housing_ods_vtu",
]


@dataclass(frozen=True)
class HousingSurface:
    """The outer skin of a housing mesh (:func:`outer_surface`).

    Attributes:
        facets: ``(F,)`` indices of the skin's facets in ``mesh.facets``.
        centroids: ``(F, 3)`` facet centroids (m).
        normals: ``(F, 3)`` outward unit normals.
        areas: ``(F,)`` facet areas (m^2).
        normal_operator: ``(F, n_dofs)`` sparse: the facets' mean outward normal displacement
            (m) of a full FE displacement ``u`` (m; node k's DOFs ``3k .. 3k + 2``).
        point_names: the named points' labels ``(P,)``.
        point_positions: ``(P, 3)`` the skin node nearest each named point (m).
        point_operator: ``(P, n_dofs)`` sparse: the outward normal displacement (m) at those
            nodes, along the normal of the skin facet nearest each point.
        square_operator: ``(m F, n_dofs)`` sparse (m = 6 on quadratic elements, 3 on linear):
            ‖square_operator u‖² = ∫_skin |u·n|² dS exactly (m⁴) for the elements' shape
            functions (the module's note; the facet means' Σ_f |ū_f|² A_f is lower).
    """

    facets: np.ndarray
    centroids: np.ndarray
    normals: np.ndarray
    areas: np.ndarray
    normal_operator: sp.csr_matrix
    point_names: tuple[str, ...] = ()
    point_positions: np.ndarray | None = None
    point_operator: sp.csr_matrix | None = None
    square_operator: sp.csr_matrix | None = None

    @property
    def area(self) -> float:
        """The skin's total area (m^2)."""
        return float(np.sum(self.areas))


def _outward(mesh, facets: np.ndarray) -> np.ndarray:
    """Unit normals of boundary facets, pointing out of their element."""
    v = mesh.p[:, mesh.facets[:, facets]]  # (3, 3, F)
    n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0], axis=0)
    tet = mesh.t[:, mesh.f2t[0, facets]]  # (4, F)
    inner = mesh.p[:, tet].mean(axis=1)  # the element's centroid, inside
    c = v.mean(axis=1)
    n = n * np.sign(np.sum(n * (c - inner), axis=0))
    return (n / np.linalg.norm(n, axis=0)).T


def _point(name, p) -> np.ndarray:
    """A named point as a (3,) array (m), or one line naming it."""
    try:
        q = np.asarray(p, dtype=float) if not isinstance(p, str) else np.zeros(0)
    except (TypeError, ValueError):
        q = np.zeros(0)
    if q.shape != (3,) or not np.all(np.isfinite(q)):
        raise ValueError(f"points[{name!r}] = {p!r}, allowed (x, y, z): 3 finite numbers (m)")
    return q


def outer_surface(housing: HousingMesh, points: dict | None = None) -> HousingSurface:
    """The outer skin of ``housing`` (the module's rule), with the operator to each facet's
    mean outward normal displacement and the named ``points``.

    Args:
        housing: a :class:`~fem_prep.housing.HousingMesh`.
        points: ``{name: (x, y, z)}`` (m): points where the normal vibration is read (an
            accelerometer's place); each is moved to the nearest node of the skin.

    Returns:
        The :class:`HousingSurface`.

    Raises:
        TypeError: not a housing mesh. ValueError: ``points`` not a dict (or None), or a point
            that is not three finite numbers (one line naming the argument).
    """
    if not isinstance(housing, HousingMesh):
        raise TypeError(f"housing = {housing!r}, allowed a fem_prep.housing.HousingMesh")
    if points is not None and not isinstance(points, dict):
        shown = repr(points) if len(repr(points)) <= 60 else repr(points)[:57] + "..."
        raise ValueError(
            f"outer_surface: points = {shown} ({type(points).__name__}) is out of range: allowed "
            "a dict {name: (x, y, z)} (m) or None"
        )
    xyz = [_point(k, p) for k, p in (points or {}).items()]  # checked before the skin is built
    mesh = housing.mesh
    f, c, _ = housing._boundary()
    seat = np.zeros(mesh.nfacets, bool)
    for s in housing.seats:
        a = np.asarray(s.axis)[:, None]
        d = c - np.asarray(s.centre)[:, None]
        along = np.sum(d * a, axis=0)
        radial = np.linalg.norm(d - along * a, axis=0)
        v = mesh.p[:, mesh.facets[:, f]]
        n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0], axis=0)
        n = n / np.linalg.norm(n, axis=0)
        sel = (
            (np.abs(np.sum(n * a, axis=0)) < 0.5)
            & (radial <= s.radius + housing.seat_tolerance)
            & (np.abs(along) <= s.width / 2 + 1e-9 * (s.width + s.radius))
        )
        seat[f[sel]] = True
    f = f[~seat[f]]
    # facets sharing a vertex are connected; the skin is the set holding the largest x
    vert = mesh.facets[:, f]  # (3, F)
    rows = np.repeat(np.arange(f.size), 3)
    inc = sp.csr_matrix((np.ones(rows.size), (rows, vert.T.ravel())), (f.size, mesh.nvertices))
    _, label = connected_components(inc @ inc.T, directed=False)
    cx = mesh.p[0, vert].mean(axis=0)
    f = f[label == label[int(np.argmax(cx))]]
    normals = _outward(mesh, f)
    v = mesh.p[:, mesh.facets[:, f]]
    areas = 0.5 * np.linalg.norm(np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0], axis=0), axis=0)
    centroids = v.mean(axis=1).T
    # the nodes whose mean is the facet's mean: edge midpoints (P2) or vertices (P1)
    nodes = housing.nodes
    tree = cKDTree(nodes)
    if housing.scalar_basis.N > mesh.nvertices:
        mids = 0.5 * (v + np.roll(v, -1, axis=1))  # (3, 3 edges, F)
        _, idx = tree.query(mids.transpose(2, 1, 0).reshape(-1, 3))
        idx = idx.reshape(f.size, 3)
    else:
        idx = mesh.facets[:, f].T
    F = f.size
    r = np.repeat(np.arange(F), 9)
    cols = (3 * idx[:, :, None] + np.arange(3)[None, None, :]).reshape(F, 9).ravel()
    vals = (np.repeat(normals[:, None, :], 3, axis=1) / 3.0).reshape(F, 9).ravel()
    op = sp.csr_matrix((vals, (r, cols)), shape=(F, housing.n_dofs))
    quadratic = housing.scalar_basis.N > mesh.nvertices
    sq = _square_operator(tree, v, idx if quadratic else None, normals, areas, housing.n_dofs)
    names, pos, pop = (), None, None
    if points:
        names = tuple(str(k) for k in points)
        xyz = np.array(xyz)
        skin = np.unique(housing.scalar_basis.get_dofs(f).flatten())
        _, j = cKDTree(nodes[skin]).query(xyz)
        node = skin[j]
        _, near = cKDTree(centroids).query(nodes[node])
        nn = normals[near]
        P = len(names)
        pop = sp.csr_matrix(
            (nn.ravel(), (np.repeat(np.arange(P), 3), (3 * node[:, None] + np.arange(3)).ravel())),
            shape=(P, housing.n_dofs),
        )
        pos = nodes[node]
    return HousingSurface(f, centroids, normals, areas, op, names, pos, pop, sq)


#: the mass matrix of a triangle of unit area: quadratic (vertices 0, 1, 2, then the midside
#: nodes of edges 01, 12, 20) and linear shape functions
_MASS_P2 = np.array([
    [6, -1, -1, 0, -4, 0],
    [-1, 6, -1, 0, 0, -4],
    [-1, -1, 6, -4, 0, 0],
    [0, 0, -4, 32, 16, 16],
    [-4, 0, 0, 16, 32, 16],
    [0, -4, 0, 16, 16, 32],
]) / 180.0
_MASS_P1 = np.array([[2, 1, 1], [1, 2, 1], [1, 1, 2]]) / 12.0


def _square_operator(tree, v, mids, normals, areas, n_dofs):
    """``(m F, n_dofs)``: rows √A_f chol(M)ᵀ on the facet's nodes' normal displacements, so
    that the squared norm of its product with u is ∫ |u·n|² dS (the module's note). ``v``
    (3, 3, F) the facets' corners, ``mids`` (F, 3) the midside nodes or ``None`` (linear)."""
    F = v.shape[2]
    _, corners = tree.query(v.transpose(2, 1, 0).reshape(-1, 3))
    nodes = corners.reshape(F, 3) if mids is None else np.hstack([corners.reshape(F, 3), mids])
    m = nodes.shape[1]
    C = np.linalg.cholesky(_MASS_P2 if m == 6 else _MASS_P1).T  # (m, m): M = Cᵀ C
    # entry (f, row a, node b, direction d) = √A_f C[a, b] n_f,d
    vals = np.sqrt(areas)[:, None, None, None] * C[None, :, :, None] * normals[:, None, None, :]
    rows = np.broadcast_to((np.arange(F)[:, None] * m + np.arange(m))[:, :, None, None],
                           vals.shape)
    cols = np.broadcast_to((3 * nodes[:, None, :, None] + np.arange(3)), vals.shape)
    return sp.csr_matrix((vals.ravel(), (rows.ravel(), cols.ravel())), shape=(m * F, n_dofs))


@dataclass(frozen=True, eq=False)
class RadiatingSkin:
    """The housing's outer skin closed by caps over its openings: the closed surface the
    exterior BEM takes (:func:`closed_outer_surface`).

    Attributes:
        surface: the closed :class:`~fem_prep.acoustics.RadiatingSurface` (m), normals outward;
            its vertices are the skin's mesh vertices (in ``mesh_vertices`` order), then one
            vertex per cap (its centre).
        normal_operator: ``(n, n_dofs)`` sparse: each surface vertex's normal displacement (m)
            of a full FE displacement ``u`` (m), along the surface's area-weighted vertex
            normal; a cap's centre row is the mean of its rim's rows (the normal velocity is
            interpolated across the cap: see :func:`closed_outer_surface`).
        mesh_vertices: ``(n_skin,)`` the housing's FE node (:attr:`HousingMesh.nodes`: a
            mesh vertex, or a midside node with ``midside_nodes``) of each skin vertex of
            ``surface`` (its first ``n_skin`` vertices).
        cap_vertices: ``(n_caps,)`` the caps' centre vertices in ``surface``.
        cap_triangles: ``(m_caps,)`` the caps' triangles in ``surface`` (the last ones).
        skin: the :func:`outer_surface` the skin came from.
    """

    surface: RadiatingSurface
    normal_operator: sp.csr_matrix
    mesh_vertices: np.ndarray
    cap_vertices: np.ndarray
    cap_triangles: np.ndarray
    skin: HousingSurface

    @property
    def cap_area(self) -> float:
        """The caps' total area (m^2)."""
        return float(np.sum(self.surface.areas[self.cap_triangles]))


def closed_outer_surface(
    housing: HousingMesh, skin: HousingSurface | None = None, *, midside_nodes: bool = False
) -> RadiatingSkin:
    """The outer skin of ``housing`` (:func:`outer_surface`) as a closed radiating surface for
    the exterior BEM (:func:`fem_prep.acoustics.radiation_resistance`): the skin's straight
    triangles, each opening of the skin (a bearing bore's mouth, an open bottom) closed by a
    cap, a fan of triangles from the centroid of the opening's rim.

    The BEM's velocity is linear on each triangle (P1). By default the triangles are the mesh's
    facets on its vertices, so a Tet10's quadratic field is kept at the corners only: on the
    embedded housings' 40 mm cells that P1 field carries 8–11 % less mean square velocity than
    the FE field (0.35–0.49 dB less power). With ``midside_nodes`` each quadratic facet is cut
    into four triangles on its corner and midside nodes, the P1 field then interpolating every
    FE node of the skin (the mean square within about 1 % there), at four times the vertices:
    the dense BEM's assembly costs about 16 times, its solve 64 times as much.

    The cap stands for what fills the bore (the bearing's outer ring and the shaft end, or a
    cover): its normal velocity is **interpolated**, linear from the rim's vertices to the
    centre, whose value is the rim's mean (a bore that moves with its wall as a plug). Set the
    rows ``cap_vertices`` of a velocity to zero for a rigid, still cover instead.

    Args:
        housing: a :class:`~fem_prep.housing.HousingMesh`.
        skin: its :func:`outer_surface` (``None``: computed).
        midside_nodes: cut each quadratic facet into four on its midside nodes (no effect on
            a linear mesh).

    Returns:
        The :class:`RadiatingSkin`: on a box housing, area and enclosed volume those of the
        box (the caps lie in the walls' outer planes).

    Raises:
        TypeError: not a housing mesh. ValueError: a skin of another mesh, an opening whose
            rim is not star-shaped about its centroid (its fan would fold over).
    """
    if not isinstance(housing, HousingMesh):
        raise TypeError(f"housing = {housing!r}, allowed a fem_prep.housing.HousingMesh")
    skin = outer_surface(housing) if skin is None else skin
    mesh = housing.mesh
    if skin.normal_operator.shape[1] != housing.n_dofs:
        raise ValueError(
            f"skin: {skin.normal_operator.shape[1]} DOFs, housing of {housing.n_dofs}: allowed "
            "the outer_surface of this housing"
        )
    tri = mesh.facets[:, skin.facets].T.astype(np.int64)  # (F, 3) mesh vertices = FE nodes
    p = housing.nodes  # the FE nodes: the mesh's vertices first, in its order
    n = np.cross(p[tri[:, 1]] - p[tri[:, 0]], p[tri[:, 2]] - p[tri[:, 0]])
    flip = np.sum(n * skin.normals, axis=1) < 0  # counter-clockwise seen from outside
    tri[flip] = tri[flip][:, ::-1]
    if midside_nodes and housing.scalar_basis.N > mesh.nvertices:
        mids = 0.5 * (p[tri] + p[np.roll(tri, -1, axis=1)])  # (F, 3 edges 01 12 20, 3)
        _, m = cKDTree(p).query(mids.reshape(-1, 3))
        m = m.reshape(-1, 3)
        a, b, c, ab, bc, ca = tri[:, 0], tri[:, 1], tri[:, 2], m[:, 0], m[:, 1], m[:, 2]
        # four triangles of the parent's orientation: three at the corners, one in the middle
        tri = np.concatenate([np.column_stack(t) for t in
                              ((a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca))])
    verts, local = np.unique(tri, return_inverse=True)
    local = local.reshape(tri.shape)
    # directed boundary edges: (a, b) of a skin triangle with no (b, a) in another
    e = np.concatenate([local[:, [0, 1]], local[:, [1, 2]], local[:, [2, 0]]])
    key = e[:, 0] * len(verts) + e[:, 1]
    rev = e[:, 1] * len(verts) + e[:, 0]
    open_e = e[~np.isin(key, rev)]
    xyz = p[verts]
    tris = [local]
    rows = []
    cap_v, cap_t = [], []
    if open_e.size:
        nb = len(verts)
        g = sp.csr_matrix((np.ones(len(open_e)), (open_e[:, 0], open_e[:, 1])), (nb, nb))
        _, lab = connected_components(g, directed=False)
        for loop in np.unique(lab[open_e[:, 0]]):
            edges = open_e[lab[open_e[:, 0]] == loop]
            rim = np.unique(edges)
            centre = len(verts) + len(cap_v)
            c = xyz[rim].mean(axis=0)
            fan = np.column_stack([edges[:, 1], edges[:, 0], np.full(len(edges), centre)])
            a, b = xyz[fan[:, 0]], xyz[fan[:, 1]]
            fn = np.cross(b - a, c - a)
            mean_n = fn.sum(axis=0)
            if np.any(fn @ mean_n <= 0):
                raise ValueError(
                    f"closed_outer_surface: the opening with rim centroid {c.tolist()} m is not "
                    "star-shaped about it (a fan cap would fold over)"
                )
            cap_t.append(fan)
            cap_v.append(centre)
            rows.append((centre, rim))
            xyz = np.vstack([xyz, c])
    n_tri_skin = len(local)
    all_t = np.concatenate(tris + cap_t) if cap_t else local
    surface = RadiatingSurface(xyz, all_t)
    # area-weighted vertex normals of the closed surface
    v3 = surface.vertices[surface.triangles]
    cross = np.cross(v3[:, 1] - v3[:, 0], v3[:, 2] - v3[:, 0])
    vn = np.zeros((surface.n_vertices, 3))
    for k in range(3):
        np.add.at(vn, surface.triangles[:, k], cross)
    vn /= np.linalg.norm(vn, axis=1, keepdims=True)
    ns = len(verts)
    r = np.repeat(np.arange(ns), 3)
    cols = (3 * verts[:, None] + np.arange(3)).ravel()
    op = sp.csr_matrix((vn[:ns].ravel(), (r, cols)), shape=(surface.n_vertices, housing.n_dofs))
    if rows:
        # a cap's centre: the mean of its rim's normal displacements
        ri, ci, vals = [], [], []
        for centre, rim in rows:
            ri += [centre] * len(rim)
            ci += list(rim)
            vals += [1.0 / len(rim)] * len(rim)
        avg = sp.csr_matrix((vals, (ri, ci)), shape=(surface.n_vertices, surface.n_vertices))
        op = (op + avg @ op).tocsr()
    return RadiatingSkin(
        surface=surface,
        normal_operator=op,
        mesh_vertices=verts,
        cap_vertices=np.asarray(cap_v, dtype=np.int64),
        cap_triangles=np.arange(n_tri_skin, len(all_t)),
        skin=skin,
    )


def write_housing_ods_vtu(housing: HousingMesh, condensed, shapes: dict, path) -> Path:
    """Write operating deflection shapes of a housing to a ``.vtu`` (meshio; ParaView),
    atomically: for each ``{label: q}`` (``q`` the condensed coordinates' complex amplitudes
    ``(n_c,)``, one order at one speed: :attr:`~jaxgear.acoustics.HousingResponse.coordinates`)
    the full FE displacement ``u = recovery q`` (m) as point data ``<label>_real``,
    ``<label>_imag`` (``u(t) = Re(u e^{i w t})``: the shape at t = 0 and a quarter period
    earlier) and ``<label>_amplitude`` (``|u|`` per node, m).

    Raises:
        ValueError: a condensed housing of another mesh, a shape of the wrong size.
    """
    import meshio  # lazy: only when a file is written

    if condensed.recovery.shape[0] != housing.n_dofs:
        raise ValueError(
            f"condensed housing of {condensed.recovery.shape[0]} DOFs, mesh of "
            f"{housing.n_dofs}: not the same housing"
        )
    sb = housing.scalar_basis
    n_nodes = sb.N
    data = {}
    for label, q in shapes.items():
        q = np.asarray(q)
        if q.shape != (condensed.recovery.shape[1],):
            raise ValueError(
                f"shapes[{label!r}]: shape {q.shape}, allowed ({condensed.recovery.shape[1]},) "
                "(the condensed coordinates)"
            )
        u = (condensed.recovery @ q).reshape(n_nodes, 3)
        data[f"{label}_real"] = np.real(u)
        data[f"{label}_imag"] = np.imag(u)
        data[f"{label}_amplitude"] = np.sqrt(np.sum(np.abs(u) ** 2, axis=1))
    cells = np.ascontiguousarray(sb.element_dofs.T)
    kind = "tetra10" if cells.shape[1] == 10 else "tetra"
    mesh = meshio.Mesh(sb.doflocs.T, [(kind, cells)], point_data=data)
    return atomic_write(Path(path), lambda p: meshio.write(str(p), mesh, file_format="vtu"))
