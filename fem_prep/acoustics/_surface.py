"""The radiating surface: a triangulated surface whose vertices carry the normal velocity
(piecewise linear, the P1 space), the fluid, and the surfaces the checks use (a sphere refined
from an octahedron, a flat rectangular panel, a flat disc).

NumPy only.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = [
    "AIR",
    "Fluid",
    "RadiatingSurface",
    "box_surface",
    "disc_panel",
    "rectangular_panel",
    "sphere_surface",
]


def _positive(owner: str, name: str, value) -> float:
    if isinstance(value, bool) or not np.isscalar(value) or not np.isfinite(value) or value <= 0:
        raise ValueError(f"{owner}: {name} must be a finite number > 0, got {value!r}")
    return float(value)


@dataclass(frozen=True)
class Fluid:
    """The acoustic medium: ``density`` ρ (kg/m³) and ``sound_speed`` c (m/s), both > 0.

    Raises:
        ValueError: a value that is not a finite number > 0."""

    density: float = 1.21
    sound_speed: float = 343.0

    def __post_init__(self):
        object.__setattr__(self, "density", _positive("Fluid", "density", self.density))
        object.__setattr__(self, "sound_speed", _positive("Fluid", "sound_speed", self.sound_speed))

    @property
    def impedance(self) -> float:
        """ρc (kg/(m² s)), the characteristic impedance."""
        return self.density * self.sound_speed

    def wavenumber(self, frequency_hz: float) -> float:
        """k = 2πf/c (1/m)."""
        return (
            2
            * np.pi
            * _positive("Fluid.wavenumber", "frequency_hz", frequency_hz)
            / (self.sound_speed)
        )


#: air at 20 °C (ρ = 1.21 kg/m³, c = 343 m/s; ρc = 415 kg/(m² s))
AIR = Fluid()


@dataclass(frozen=True, eq=False)
class RadiatingSurface:
    """A triangulated surface: ``vertices`` ``(n, 3)`` (m) and ``triangles`` ``(m, 3)`` (vertex
    indices). The normal velocity lives on the vertices (linear on each triangle); a positive
    velocity moves the surface along its normal, which points into the fluid: the triangles are
    ordered counter-clockwise seen from the fluid. A closed surface (the BEM's) is reoriented
    on construction so that its enclosed volume is positive (normals outward); an open one
    (a flat panel for the Rayleigh integral) keeps the order it is given.

    Raises:
        ValueError: arrays of the wrong shape or with non-finite values, an index out of range,
            a degenerate (zero-area) triangle.
    """

    vertices: np.ndarray
    triangles: np.ndarray

    def __post_init__(self):
        v = np.asarray(self.vertices, dtype=float)
        t = np.asarray(self.triangles)
        if v.ndim != 2 or v.shape[1] != 3 or len(v) < 3 or not np.all(np.isfinite(v)):
            raise ValueError(
                f"RadiatingSurface: vertices must be finite (n >= 3, 3), got {v.shape}"
            )
        if t.ndim != 2 or t.shape[1] != 3 or len(t) < 1 or not np.issubdtype(t.dtype, np.integer):
            raise ValueError(f"RadiatingSurface: triangles must be integers (m, 3), got {t.shape}")
        if t.min() < 0 or t.max() >= len(v):
            raise ValueError(
                f"RadiatingSurface: triangle indices must lie in [0, {len(v) - 1}], "
                f"got [{t.min()}, {t.max()}]"
            )
        t = t.astype(np.int64)
        cross = np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])
        if np.any(np.linalg.norm(cross, axis=1) <= 1e-14 * np.ptp(v, axis=0).max() ** 2):
            raise ValueError("RadiatingSurface: a triangle has zero area")
        if self._closed(t) and np.einsum("ij,ij->", v[t[:, 0]], cross) < 0:
            t = t[:, ::-1].copy()
        object.__setattr__(self, "vertices", v)
        object.__setattr__(self, "triangles", t)

    @staticmethod
    def _closed(t) -> bool:
        edges = np.sort(np.concatenate([t[:, [0, 1]], t[:, [1, 2]], t[:, [2, 0]]]), axis=1)
        _, counts = np.unique(edges, axis=0, return_counts=True)
        return bool(np.all(counts == 2))

    @property
    def closed(self) -> bool:
        """Whether every edge is shared by exactly two triangles (a closed surface)."""
        return self._closed(self.triangles)

    @property
    def n_vertices(self) -> int:
        return len(self.vertices)

    @property
    def areas(self) -> np.ndarray:
        """``(m,)`` triangle areas (m²)."""
        return 0.5 * np.linalg.norm(self._cross(), axis=1)

    @property
    def vertex_areas(self) -> np.ndarray:
        """``(n,)`` each vertex's share of the surface's area (m²): a third of every triangle
        round it (the row sums of :meth:`mass_matrix`, the lumped P1 mass), summing to the
        surface's area; what a vertex power divides by for an intensity (W/m²,
        :func:`jaxgear.acoustics.radiated_intensity_at`)."""
        a = np.zeros(self.n_vertices)
        for k in range(3):
            np.add.at(a, self.triangles[:, k], self.areas / 3)
        return a

    @property
    def normals(self) -> np.ndarray:
        """``(m, 3)`` unit normals of the triangles (into the fluid)."""
        c = self._cross()
        return c / np.linalg.norm(c, axis=1, keepdims=True)

    @property
    def centroids(self) -> np.ndarray:
        """``(m, 3)`` triangle centroids (m)."""
        return self.vertices[self.triangles].mean(axis=1)

    def _cross(self):
        v, t = self.vertices, self.triangles
        return np.cross(v[t[:, 1]] - v[t[:, 0]], v[t[:, 2]] - v[t[:, 0]])

    def mass_matrix(self) -> np.ndarray:
        """``(n, n)`` the P1 mass matrix M (m²): ∫ φᵢ φⱼ dS, so that ∫ a* b dS = aᴴ M b for
        vertex values a, b."""
        n = self.n_vertices
        local = (np.ones((3, 3)) + np.eye(3)) / 12.0
        M = np.zeros((n, n))
        a = self.areas
        for i in range(3):
            for j in range(3):
                np.add.at(M, (self.triangles[:, i], self.triangles[:, j]), a * local[i, j])
        return M

    def quadrature(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """A 3-point rule per triangle (the points at barycentric (2/3, 1/6, 1/6) and
        permutations; exact for quadratics): ``points (3m, 3)``, ``weights (3m,)`` (m²) and the
        interpolation ``(3m, n)`` from vertex values to the points."""
        bary = np.array([[2 / 3, 1 / 6, 1 / 6], [1 / 6, 2 / 3, 1 / 6], [1 / 6, 1 / 6, 2 / 3]])
        v, t = self.vertices, self.triangles
        pts = np.einsum("qk,mkd->mqd", bary, v[t]).reshape(-1, 3)
        w = np.repeat(self.areas / 3.0, 3)
        m = len(t)
        interp = np.zeros((3 * m, self.n_vertices))
        rows = np.arange(3 * m)
        for k in range(3):
            np.add.at(interp, (rows, np.repeat(t[:, k], 1).repeat(3)), np.tile(bary[:, k], m))
        return pts, w, interp

    def normal_velocity_of(self, velocity: np.ndarray) -> np.ndarray:
        """``(n,)`` the normal component of a vertex velocity field ``(n, 3)`` (m/s, complex
        allowed) along the area-weighted vertex normals.

        Raises:
            ValueError: ``velocity`` not of shape ``(n_vertices, 3)``."""
        vel = np.asarray(velocity)
        if vel.shape != (self.n_vertices, 3):
            raise ValueError(
                f"normal_velocity_of: velocity must be ({self.n_vertices}, 3), got {vel.shape}"
            )
        vn = np.zeros((self.n_vertices, 3))
        c = self._cross()
        for k in range(3):
            np.add.at(vn, self.triangles[:, k], c)
        vn /= np.linalg.norm(vn, axis=1, keepdims=True)
        return np.einsum("ij,ij->i", vel, vn)


def sphere_surface(radius: float, level: int, center=(0.0, 0.0, 0.0)) -> RadiatingSurface:
    """A sphere of ``radius`` (m): an octahedron refined ``level`` times (each triangle into
    four, the new vertices projected onto the sphere): ``8·4^level`` triangles,
    ``4·4^level + 2`` vertices.

    Raises:
        ValueError: ``radius`` ≤ 0, ``level`` not an integer in [0, 6]."""
    r = _positive("sphere_surface", "radius", radius)
    if isinstance(level, bool) or not isinstance(level, (int, np.integer)) or not 0 <= level <= 6:
        raise ValueError(f"sphere_surface: level must be an integer in [0, 6], got {level!r}")
    v = [
        np.array(p, float)
        for p in [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    ]
    tris = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    for _ in range(level):
        mid: dict[tuple[int, int], int] = {}

        def midpoint(a, b, mid=mid):
            key = (min(a, b), max(a, b))
            if key not in mid:
                p = v[a] + v[b]
                v.append(p / np.linalg.norm(p))
                mid[key] = len(v) - 1
            return mid[key]

        new = []
        for a, b, c in tris:
            ab, bc, ca = midpoint(a, b), midpoint(b, c), midpoint(c, a)
            new += [(a, ab, ca), (ab, b, bc), (ca, bc, c), (ab, bc, ca)]
        tris = new
    return RadiatingSurface(r * np.array(v) + np.asarray(center, float), np.array(tris))


def _grid_triangles(nx: int, ny: int) -> np.ndarray:
    idx = np.arange((nx + 1) * (ny + 1)).reshape(ny + 1, nx + 1)
    a, b = idx[:-1, :-1].ravel(), idx[:-1, 1:].ravel()
    c, d = idx[1:, 1:].ravel(), idx[1:, :-1].ravel()
    return np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])


def rectangular_panel(lx: float, ly: float, nx: int, ny: int) -> RadiatingSurface:
    """A flat ``lx`` × ``ly`` panel (m) in the plane z = 0, corner at the origin, normal +z,
    on an ``nx`` × ``ny`` grid of rectangles each cut into two triangles.

    Raises:
        ValueError: a size ≤ 0 or a count not an integer ≥ 1."""
    lx, ly = _positive("rectangular_panel", "lx", lx), _positive("rectangular_panel", "ly", ly)
    for name, n in (("nx", nx), ("ny", ny)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"rectangular_panel: {name} must be an integer >= 1, got {n!r}")
    x, y = np.meshgrid(np.linspace(0, lx, nx + 1), np.linspace(0, ly, ny + 1))
    v = np.stack([x.ravel(), y.ravel(), np.zeros(x.size)], 1)
    return RadiatingSurface(v, _grid_triangles(nx, ny))


def disc_panel(radius: float, n_rings: int) -> RadiatingSurface:
    """A flat disc of ``radius`` (m) in the plane z = 0, centred at the origin, normal +z:
    ``n_rings`` rings of vertices (ring i has 6i, so the triangles stay near-equilateral).

    Raises:
        ValueError: ``radius`` ≤ 0, ``n_rings`` not an integer ≥ 1."""
    r = _positive("disc_panel", "radius", radius)
    if isinstance(n_rings, bool) or not isinstance(n_rings, (int, np.integer)) or n_rings < 1:
        raise ValueError(f"disc_panel: n_rings must be an integer >= 1, got {n_rings!r}")
    pts = [np.zeros(2)]
    start = [0]
    for i in range(1, n_rings + 1):
        start.append(len(pts))
        ang = 2 * np.pi * np.arange(6 * i) / (6 * i)
        pts += list(r * i / n_rings * np.stack([np.cos(ang), np.sin(ang)], 1))
    tris = []
    for i in range(1, n_rings + 1):
        outer = [start[i] + j for j in range(6 * i)]
        inner = [0] if i == 1 else [start[i - 1] + j for j in range(6 * (i - 1))]
        # walk both rings by angle and stitch them (an advancing front over two rings)
        ao = np.arange(len(outer)) / len(outer)
        ai = np.arange(len(inner)) / len(inner)
        io = ii = 0
        while io < len(outer) or (len(inner) > 1 and ii < len(inner)):
            nxt_o = ao[io + 1] if io + 1 <= len(outer) - 1 else 1.0
            nxt_i = ai[ii + 1] if ii + 1 <= len(inner) - 1 else 1.0
            if len(inner) == 1 or (io < len(outer) and (nxt_o <= nxt_i or ii >= len(inner))):
                tris.append((inner[ii % len(inner)], outer[io], outer[(io + 1) % len(outer)]))
                io += 1
            else:
                tris.append((inner[ii], outer[io % len(outer)], inner[(ii + 1) % len(inner)]))
                ii += 1
    p = np.asarray(pts)
    return RadiatingSurface(np.column_stack([p, np.zeros(len(p))]), np.array(tris))


def box_surface(lx: float, ly: float, lz: float, nx: int, ny: int, nz: int) -> RadiatingSurface:
    """The closed surface of the box [0, lx] × [0, ly] × [-lz/2, lz/2] (m) on a structured grid
    of ``nx`` × ``ny`` × ``nz`` divisions, every rectangle cut into two triangles, normals
    outward. Its top face (z = lz/2) carries the vertices of :func:`rectangular_panel` with the
    same ``lx, ly, nx, ny`` lifted by lz/2, in the same order, first.

    Raises:
        ValueError: a size ≤ 0 or a count not an integer ≥ 1."""
    sizes = [_positive("box_surface", n, x) for n, x in (("lx", lx), ("ly", ly), ("lz", lz))]
    for name, n in (("nx", nx), ("ny", ny), ("nz", nz)):
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
            raise ValueError(f"box_surface: {name} must be an integer >= 1, got {n!r}")
    axes = [
        np.linspace(0, sizes[0], nx + 1),
        np.linspace(0, sizes[1], ny + 1),
        np.linspace(-sizes[2] / 2, sizes[2] / 2, nz + 1),
    ]
    counts = (nx, ny, nz)
    verts: list[np.ndarray] = []
    tris: list[np.ndarray] = []
    # the top face first, then the other five; shared edge vertices merged below
    faces = [(2, 1), (2, 0), (0, 0), (0, 1), (1, 0), (1, 1)]
    for axis, side in faces:
        a, b = [i for i in range(3) if i != axis]
        ua, ub = np.meshgrid(axes[a], axes[b])
        p = np.zeros((ua.size, 3))
        p[:, a], p[:, b] = ua.ravel(), ub.ravel()
        p[:, axis] = axes[axis][-1] if side else axes[axis][0]
        t = _grid_triangles(counts[a], counts[b]) + sum(len(x) for x in verts)
        nrm = np.cross(
            p[t[:, 1] - t.min()] - p[t[:, 0] - t.min()], p[t[:, 2] - t.min()] - p[t[:, 0] - t.min()]
        )[:, axis]
        if (nrm[0] > 0) != bool(side):
            t = t[:, ::-1]
        verts.append(p)
        tris.append(t)
    allv = np.concatenate(verts)
    scale = max(sizes)
    keys = np.round(allv / scale * 1e9).astype(np.int64)
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    order = np.argsort(first)  # keep first-seen order: the top face's vertices come first
    rank = np.empty_like(order)
    rank[order] = np.arange(len(order))
    new_index = rank[inverse.ravel()]
    return RadiatingSurface(allv[np.sort(first)], new_index[np.concatenate(tris)])
