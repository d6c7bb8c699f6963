"""Structured quadratic hexahedral meshes of gear bodies, swept around the axis.

The meridian section (r, z) is a tensor grid of quadrilaterals; a cell belongs to the body when
it lies in the hub, a shaft stub, the web or the rim.  The grid is swept around the axis with a
number of circumferential elements that is a multiple of the tooth count, so that mesh nodes
exist at every tooth station on the rim.  The web inclination shears the z coordinate with r.
Web holes are approximated by removing the web elements whose centroid falls inside a hole.

Geometry is quadratic (skfem ``MeshHex2``, 27-node mapping, circles exact at the nodes); the
displacement field is either the 20-node serendipity brick (``ElementHexS2``, as in the seed)
or the 27-node Lagrange brick (``ElementHex2``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import skfem

from ._body import Body, Geometry, MeshSettings
from ._kinds import Element

__all__ = [
    "BodyMesh",
    "mesh_body",
    "mesh_from_section",
    "pinion_master_targets",
    "pinion_master_z",
    "rim_master_z",
]

HUB, WEB, RIM, PINION = 0, 1, 2, 3


@dataclass(frozen=True)
class BodyMesh:
    """A hexahedral mesh of a gear body with its scikit-fem basis.

    Attributes:
        mesh: scikit-fem ``MeshHex2`` (coordinates in m, scikit-fem orientation ``(3, n)``).
        basis: vector scikit-fem basis (3 DOFs per node, interleaved: node k has DOFs 3k..3k+2).
        nodes: node coordinates, shape ``(n_nodes, 3)`` in m (vertices first, then mid-edge,
            face and centre nodes in scikit-fem's numbering).
        n_vertices: number of element corner nodes (the first ``n_vertices`` rows of ``nodes``).
        cells: corner connectivity ``(n_elements, 8)`` in VTK hexahedron order.
        region: element region ``(n_elements,)``: 0 hub/stub, 1 web, 2 rim, 3 pinion rim.
        n_theta: number of circumferential element divisions (a multiple of each rim's tooth
            count).
        r_grid: meridian radial grid (m), ``(nr + 1,)``.
        z_grid: meridian axial grid in the unsheared frame (m), ``(nz + 1,)``.
        element: the element (:class:`~fem_prep.Hex20` or :class:`~fem_prep.Hex27`).
        vertex_ijk: structured indices ``(n_vertices, 3)`` of the corner nodes: radial grid
            index, axial grid index, circumferential index (0..n_theta-1, angle k 2 pi/n_theta).
    """

    mesh: skfem.MeshHex2
    basis: skfem.Basis
    nodes: np.ndarray
    n_vertices: int
    cells: np.ndarray
    region: np.ndarray
    n_theta: int
    r_grid: np.ndarray
    z_grid: np.ndarray
    element: Element
    vertex_ijk: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Number of nodes (each with 3 translational DOFs)."""
        return self.nodes.shape[0]

    @property
    def n_dofs(self) -> int:
        """Number of DOFs (3 per node)."""
        return 3 * self.n_nodes


def _divisions(length: float, size: float) -> int:
    return max(1, int(round(length / size)))


def _subdivide(points: list[float], sizes: list[float]) -> np.ndarray:
    out = [points[0]]
    for a, b, s in zip(points[:-1], points[1:], sizes):
        n = _divisions(b - a, s)
        out.extend(list(np.linspace(a, b, n + 1)[1:]))
    return np.array(out)


def _merge(hard: list[float], soft: list[float], tol: float) -> list[float]:
    pts = sorted(set(round(x, 12) for x in hard))
    merged: list[float] = []
    for x in pts:
        if merged and x - merged[-1] < 1e-9:
            continue
        merged.append(x)
    for x in soft:
        if min(abs(x - y) for y in merged) >= tol:
            merged.append(x)
            merged.sort()
    return merged



# skfem's reference corner order (0,0,0),(0,0,1),(0,1,0),(1,0,0),(0,1,1),(1,0,1),(1,1,0),(1,1,1)
# with (xi, eta, zeta) -> (r, theta, z) (right-handed: e_r x e_theta = e_z), stored as (a, b, c) =
# (r step, theta step, z step) offsets of the corner
_CORNERS = ((0, 0, 0), (0, 0, 1), (0, 1, 0), (1, 0, 0), (0, 1, 1), (1, 0, 1), (1, 1, 0), (1, 1, 1))


def revolved_hexes(I, J, K, nz: int, nt: int) -> np.ndarray:
    """Corner vertex ids, shape (8, n), of the hexahedra (I, J, K) (radial, axial, circumferential
    indices, each shape (n,)) of an (r, z) grid with nz axial cells revolved in nt sectors; vertex
    (i, j, k) is numbered (i (nz + 1) + j) nt + k mod nt, so the last sector closes on the first."""

    def vid(i, j, k):
        return (i * (nz + 1) + j) * nt + (k % nt)

    return np.array([vid(I + a, J + c, K + b) for a, b, c in _CORNERS])


def used_vertices(t: np.ndarray, nz: int, nt: int):
    """The vertices that corner ids ``t`` (8, n) use, renumbered 0..m-1: (t renumbered (8, n), and
    the vertices' radial, axial and circumferential grid indices vi, vj, vk, each shape (m,))."""
    used, t = np.unique(t, return_inverse=True)
    t = t.reshape(8, -1)
    return t, used // (nt * (nz + 1)), (used // nt) % (nz + 1), used % nt


def arc_hex2(p: np.ndarray, t: np.ndarray, dth: float) -> skfem.MeshHex2:
    """The quadratic hexahedra of vertices ``p`` (3, m) and corners ``t`` (8, n) of a revolved grid
    of sector angle ``dth`` (rad), with the circumferential mid-nodes (at mid-angle, on the chords
    of the linear mesh) pushed out to the arcs."""
    t = np.ascontiguousarray(t)  # scikit-fem copies (and logs a warning for) any other layout
    loc = skfem.MeshHex2.from_mesh(skfem.MeshHex1(p, t, validate=False)).doflocs.copy()
    phi = np.mod(np.arctan2(loc[1], loc[0]), 2 * math.pi) / dth
    mid = np.abs(phi - np.floor(phi) - 0.5) < 1e-6
    scale = np.where(mid, 1.0 / math.cos(dth / 2), 1.0)
    loc[0] *= scale
    loc[1] *= scale
    return skfem.MeshHex2(loc, t, validate=False)


def mesh_body(body: Body, *, progress: bool = False) -> BodyMesh:
    """Mesh a gear body (see the module docstring for the construction).

    Args:
        body: the validated body.
        progress: unused (meshing is fast); kept for a uniform signature.

    Returns:
        The :class:`BodyMesh`.

    Raises:
        ValueError: an element with a non-positive Jacobian (inverted element).
    """
    del progress
    g = body.geometry
    teeth = body.condensation.teeth
    nax = body.condensation.axial_master_nodes
    s_hub = g.hub_shift
    # bearing planes and the edges of their coupled bands (clipped to the bore: hub and shaft
    # stubs) are grid lines, in the unsheared hub frame
    z_pos = [b.axial_position - s_hub for b in body.bearings]
    lo = min([g.web_offset - g.hub_width / 2, *z_pos])
    hi = max([g.web_offset + g.hub_width / 2, *z_pos])
    z_edges = [min(max(z - s_hub, lo), hi) for b in body.bearings for z in b.z_band]
    z_bear = z_pos + z_edges
    targets = _master_targets(g, nax)
    pin = body.pinion_rim
    if pin is not None:
        targets = targets + list(pinion_master_targets(pin)) + list(pin.band)
    bm = mesh_from_section(
        g, body.mesh, teeth=teeth, z_rim_lines=targets, z_hub_lines=z_bear, pinion=pin
    )
    try:
        rim_master_z(bm, g, nax)
        if pin is not None:
            pinion_master_z(bm, pin)
    except ValueError:
        # not enough rim nodes across the face width: add grid lines at the master positions
        bm = mesh_from_section(
            g,
            body.mesh,
            teeth=teeth,
            z_rim_lines=targets,
            z_tol_factor=0.05,
            z_hub_lines=z_bear,
            pinion=pin,
        )
    return bm


def pinion_master_targets(pin) -> np.ndarray:
    """Axial positions (m, body frame) of a pinion rim's master planes: linspace over its face
    (its middle for one plane)."""
    if pin.axial_master_nodes == 1:
        return np.array([pin.axial_position])
    return np.linspace(*pin.band, pin.axial_master_nodes)


def pinion_master_z(bm: BodyMesh, pin) -> np.ndarray:
    """Axial positions (m) of the pinion rim's master planes: the node planes of its outer face
    nearest :func:`pinion_master_targets` (:func:`rim_master_z` for the wheel's rim).

    Raises:
        ValueError: two targets snap to the same plane.
    """
    return _snap_planes(bm, pin.outer_radius, pin.band, pinion_master_targets(pin))


def _master_targets(g: Geometry, nax: int) -> list[float]:
    if nax == 1:
        return [0.0]
    return list(np.linspace(-g.rim_width / 2, g.rim_width / 2, nax))


def rim_master_z(bm: BodyMesh, g: Geometry, nax: int) -> np.ndarray:
    """Axial positions (m) of the rim master nodes: the node planes nearest to an even spread.

    Targets are ``linspace(-b/2, b/2, nax)`` (``[0]`` for one node); each snaps to the nearest
    node plane (corner or mid-edge) on the rim outer surface.

    Raises:
        ValueError: two targets snap to the same plane (the caller then refines the grid).
    """
    band = (-g.rim_width / 2, g.rim_width / 2)
    return _snap_planes(bm, g.rim_outer_radius, band, _master_targets(g, nax))


def _snap_planes(bm: BodyMesh, radius: float, band, targets) -> np.ndarray:
    """The node planes of the outer face r = ``radius``, z in ``band``, nearest ``targets``."""
    n = bm.nodes
    on = np.abs(np.hypot(n[:, 0], n[:, 1]) - radius) < 1e-9 * radius
    on &= (n[:, 2] > band[0] - 1e-9) & (n[:, 2] < band[1] + 1e-9)
    zs = np.unique(np.round(n[on, 2], 12))
    picked = np.array([zs[np.argmin(np.abs(zs - t))] for t in targets])
    if len(np.unique(picked)) != len(picked):
        raise ValueError("not enough rim node planes for the axial master nodes")
    return picked


def mesh_from_section(
    g: Geometry,
    ms: MeshSettings,
    *,
    teeth: int,
    z_rim_lines: list[float] = (),  # type: ignore[assignment]
    z_hub_lines: list[float] = (),  # type: ignore[assignment]
    z_tol_factor: float = 0.3,
    pinion=None,
) -> BodyMesh:
    """Mesh a meridian section swept around the z axis.

    Args:
        g: section geometry (m).
        ms: mesh settings (element, target sizes in m).
        teeth: the number of circumferential elements is a multiple of this.
        z_rim_lines: axial positions (m, z = 0 at mid-rim) where the grid must have a line
            (exactly: the rim master planes).
        z_hub_lines: same, in the unsheared hub frame (bearing planes; they extend shaft stubs).
        z_tol_factor: snapping tolerance of the soft lines (``z_hub_lines``), in element sizes.
        pinion: a :class:`~fem_prep._body.PinionRim` (a ring from the bore to its outer radius
            over its face) or ``None``; the circumferential divisions are then a multiple of
            both tooth counts.

    Returns:
        The :class:`BodyMesh`.
    """
    size = ms.size
    s_hub = ms.hub_size or size
    s_web = ms.web_size or size
    s_rim = ms.rim_size or size
    s_circ = ms.circumferential_size or size

    # ---- radial breakpoints and region columns
    rb = [g.bore_radius]
    rs: list[float] = []
    if g.shaft_outer_radius < g.hub_outer_radius - 1e-9:
        rb.append(g.shaft_outer_radius)
        rs.append(s_hub)
    rb.append(g.hub_outer_radius)
    rs.append(s_hub)
    if g.rim_inner_radius > g.hub_outer_radius + 1e-9:
        rb.append(g.rim_inner_radius)
        rs.append(s_web)
    rb.append(g.rim_outer_radius)
    rs.append(s_rim)
    if pinion is not None and min(abs(pinion.outer_radius - r) for r in rb) > 1e-9:
        i = int(np.searchsorted(rb, pinion.outer_radius))
        rb.insert(i, pinion.outer_radius)
        rs.insert(i - 1, rs[i - 1])
    r_grid = _subdivide(rb, rs)

    # ---- axial breakpoints (unsheared frame: hub centred on the web mid-plane at z = offset)
    zh = (g.web_offset - g.hub_width / 2, g.web_offset + g.hub_width / 2)
    zw = (g.web_offset - g.web_thickness / 2, g.web_offset + g.web_thickness / 2)
    zr = (-g.rim_width / 2, g.rim_width / 2)
    zs = (min([zh[0]] + list(z_hub_lines)), max([zh[1]] + list(z_hub_lines)))
    # the rim master planes are exact grid lines: the hybrid interface interpolates between
    # them, and its mortar weights are exact only for slices nested in those faces
    hard = [*zh, *zw, *zr, *zs, *z_rim_lines]
    tol = z_tol_factor * min(s_hub, s_web, s_rim)
    zb = _merge(hard, list(z_hub_lines), tol)

    def column_ranges(rmid: float) -> list[tuple[tuple[float, float], int, float]]:
        out = []
        if rmid < g.shaft_outer_radius:
            out.append((zs, HUB, s_hub))
        if rmid < g.hub_outer_radius:
            out.append((zh, HUB, s_hub))
        elif rmid < g.rim_inner_radius:
            out.append((zw, WEB, s_web))
        else:
            out.append((zr, RIM, s_rim))
        if pinion is not None and rmid < pinion.outer_radius:
            out.append((pinion.band, PINION, s_rim))
        return out

    zsizes = []
    for a, b in zip(zb[:-1], zb[1:]):
        m = 0.5 * (a + b)
        cand = [s_hub, s_web, s_rim]
        covering = []
        for rmid in 0.5 * (np.array(rb[:-1]) + np.array(rb[1:])):
            for (lo, hi), _, s in column_ranges(rmid):
                if lo <= m <= hi:
                    covering.append(s)
        zsizes.append(min(covering) if covering else max(cand))
    z_grid = _subdivide(zb, zsizes)

    # ---- meridian cells
    nr, nz = len(r_grid) - 1, len(z_grid) - 1
    rc = 0.5 * (r_grid[:-1] + r_grid[1:])
    zc = 0.5 * (z_grid[:-1] + z_grid[1:])
    cell_region = -np.ones((nr, nz), dtype=int)
    for i in range(nr):
        for (lo, hi), reg, _ in column_ranges(rc[i]):
            inside = (zc > lo) & (zc < hi)
            cell_region[i, inside & (cell_region[i] < 0)] = reg

    # ---- circumferential divisions: multiple of teeth
    base = teeth if pinion is None else math.lcm(teeth, pinion.teeth)
    q = max(1, int(math.ceil(2 * math.pi * g.rim_outer_radius / (base * s_circ) - 0.25)))
    nt = base * q
    dth = 2 * math.pi / nt

    # ---- shear of z with r (web inclination); hub shifted by the full amount
    tan_a = math.tan(g.web_inclination)

    def shear(r: np.ndarray) -> np.ndarray:
        return np.clip(g.rim_inner_radius - r, 0.0, g.rim_inner_radius - g.hub_outer_radius) * tan_a

    # ---- hexahedra
    ii, jj = np.nonzero(cell_region >= 0)
    regs = cell_region[ii, jj]
    kk = np.arange(nt)
    I = np.repeat(ii, nt)
    J = np.repeat(jj, nt)
    K = np.tile(kk, len(ii))
    R = np.repeat(regs, nt)

    t = revolved_hexes(I, J, K, nz, nt)

    # hole removal (web elements whose centroid is inside a hole)
    keep = np.ones(t.shape[1], dtype=bool)
    h = g.holes
    if h.count > 0:
        rcen = 0.5 * (r_grid[I] + r_grid[I + 1])
        thc = (K + 0.5) * dth
        xc, yc = rcen * np.cos(thc), rcen * np.sin(thc)
        for m in range(h.count):
            ph = 2 * math.pi * m / h.count
            d = np.hypot(xc - h.center_radius * math.cos(ph), yc - h.center_radius * math.sin(ph))
            keep &= ~((R == WEB) & (d < h.radius))
    t, R = t[:, keep], R[keep]

    t, vi, vj, vk = used_vertices(t, nz, nt)
    rv = r_grid[vi]
    th = vk * dth
    p = np.array([rv * np.cos(th), rv * np.sin(th), z_grid[vj] + shear(rv)])
    mesh = arc_hex2(p, t, dth)

    el = ms.element.skfem_element()
    basis = skfem.Basis(mesh, skfem.ElementVector(el), intorder=ms.element.intorder)
    # scikit-fem's reference hexahedron is left-handed: its own unit cube has det(DF) = -1, so
    # a valid (non-inverted) element has det(DF) < 0 at every quadrature point.
    det = -mesh._mapping().detDF(basis.quadrature[0])
    if not np.all(det > 0):
        bad = int(np.sum(np.any(det <= 0, axis=1)))
        raise ValueError(
            f"mesh has {bad} inverted element(s) (non-positive Jacobian); reduce "
            "web_inclination_deg or refine [mesh] size_mm"
        )
    nodes = np.ascontiguousarray(basis.doflocs[:, 0::3].T)
    # VTK hexahedron corner order from skfem's reference order
    vtk_order = [0, 3, 6, 2, 1, 5, 7, 4]
    cells = np.ascontiguousarray(t[vtk_order].T)
    return BodyMesh(
        mesh=mesh,
        basis=basis,
        nodes=nodes,
        n_vertices=int(t.max()) + 1,
        cells=cells,
        region=R,
        n_theta=nt,
        r_grid=r_grid,
        z_grid=z_grid,
        element=ms.element,
        vertex_ijk=np.stack([vi, vj, vk], axis=1),
    )
