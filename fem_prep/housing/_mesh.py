"""Housing meshes: the parametric box (a structured mesher in NumPy/scikit-fem, or gmsh when it
is installed), a plate (the mesher's check against Leissa's plate) and a mesh file read by meshio.

Every mesh is a straight-sided four-node tetrahedral mesh (scikit-fem ``MeshTet1``) on which the
element (:class:`Tet10`, quadratic, the default; :class:`Tet4`, linear) builds its basis; the
quadratic element's edge nodes lie on the straight edges. Coordinates in m; the box stands on
``z = 0`` (its bottom face) and spans ``[0, length] x [0, width] x [0, height]``.

Bearing seats (:class:`Seat`) are the boundary facets of a bore: facets whose normal is at more
than 60° from the bore axis, whose centroid lies within ``radius + tolerance`` of the axis and
within ``width / 2`` of the seat's centre along it (a structured mesh's bore is a staircase of
cells: its tolerance is one cell diagonal; a gmsh bore's facets are chords of the circle). Feet (:class:`Foot`) are the
boundary facets of the lowest plane ``z = z_min`` of the mesh whose centroid lies in a rectangle.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import ClassVar, final

import numpy as np
import skfem

from .._kinds import TetElement
from ..resources import check_memory
from ._estimate import box_grids, estimate_box, grid_points

__all__ = [
    "Bore",
    "Foot",
    "HousingBox",
    "HousingMesh",
    "Seat",
    "Tet4",
    "Tet10",
    "mesh_box",
    "mesh_box_gmsh",
    "mesh_plate",
    "read_housing_mesh",
]

WALLS = ("x-", "x+", "y-", "y+", "z+")
"""The walls a bore may pierce: the box's side walls (normal to x or y) and its top (z+); the
bottom carries the feet."""


@final
class Tet4(TetElement):
    """The four-node linear tetrahedron (scikit-fem ``ElementTetP1``): stiff in bending, for
    comparisons only."""

    name: ClassVar[str] = "tet4"
    intorder: ClassVar[int] = 2

    def skfem_element(self) -> skfem.Element:
        return skfem.ElementTetP1()


@final
class Tet10(TetElement):
    """The ten-node quadratic tetrahedron (scikit-fem ``ElementTetP2``; the default): bending of
    thin walls with one element through the thickness."""

    name: ClassVar[str] = "tet10"
    intorder: ClassVar[int] = 4

    def skfem_element(self) -> skfem.Element:
        return skfem.ElementTetP2()


def _positive(owner: str, name: str, value) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TypeError(f"{owner}: {name} = {value!r}, allowed a number > 0 (m)")
    if not (math.isfinite(value) and value > 0):
        raise ValueError(f"{owner}: {name} = {value!r}, allowed > 0 (m)")
    return float(value)


def _vector(owner: str, name: str, value, n: int) -> tuple[float, ...]:
    v = np.asarray(value, dtype=float) if not isinstance(value, str) else np.zeros(0)
    if v.shape != (n,) or not np.all(np.isfinite(v)):
        raise ValueError(f"{owner}: {name} = {value!r}, allowed {n} finite numbers (m)")
    return tuple(float(x) for x in v)


@dataclass(frozen=True)
class Seat:
    """A bearing seat of a housing mesh: the bore surface a 6-DOF master node holds.

    Attributes:
        centre: the master node's position ``(3,)`` (m), on the bore axis at the middle of the
            seat.
        axis: the bore axis ``(3,)`` (normalised on construction).
        radius: the bore radius (m).
        width: the seat's axial extent (m): the facets within ``width / 2`` of ``centre``.
        name: a label (``"seat0"``, ...).
    """

    centre: tuple[float, float, float]
    axis: tuple[float, float, float]
    radius: float
    width: float
    name: str = ""

    def __post_init__(self):
        object.__setattr__(self, "centre", _vector("Seat", "centre", self.centre, 3))
        a = np.asarray(_vector("Seat", "axis", self.axis, 3))
        if not np.linalg.norm(a) > 0:
            raise ValueError(f"Seat: axis = {self.axis!r}, allowed a non-zero vector")
        object.__setattr__(self, "axis", tuple(float(x) for x in a / np.linalg.norm(a)))
        _positive("Seat", "radius", self.radius)
        _positive("Seat", "width", self.width)


@dataclass(frozen=True)
class Bore:
    """A bearing bore of the box housing, through one wall.

    Attributes:
        wall: ``"x-"``, ``"x+"`` (the walls at x = 0 and x = length), ``"y-"``, ``"y+"`` or
            ``"z+"`` (the top).
        centre: the bore centre in the wall's plane (m): ``(y, z)`` on an x wall, ``(x, z)`` on
            a y wall, ``(x, y)`` on the top.
        radius: bore radius (m).
    """

    wall: str
    centre: tuple[float, float]
    radius: float

    def __post_init__(self):
        if self.wall not in WALLS:
            raise ValueError(f"Bore: wall = {self.wall!r}, allowed one of {', '.join(WALLS)}")
        object.__setattr__(self, "centre", _vector("Bore", "centre", self.centre, 2))
        _positive("Bore", "radius", self.radius)


@dataclass(frozen=True)
class Foot:
    """A bolted foot: the rectangle ``x in x_range``, ``y in y_range`` (m) of the housing's
    lowest plane ``z = z_min``, clamped (every DOF of its facets held)."""

    x_range: tuple[float, float]
    y_range: tuple[float, float]

    def __post_init__(self):
        for name in ("x_range", "y_range"):
            r = _vector("Foot", name, getattr(self, name), 2)
            if not r[1] > r[0]:
                raise ValueError(f"Foot: {name} = {getattr(self, name)!r}, allowed (min, max)")
            object.__setattr__(self, name, r)


@dataclass(frozen=True)
class HousingBox:
    """A parametric box housing: a closed box of constant wall thickness standing on ``z = 0``.

    Attributes:
        length, width, height: outer dimensions along x, y, z (m).
        wall_thickness: t (m), < half of each dimension.
        bores: the bearing bores (:class:`Bore`); each becomes a :class:`Seat` over the wall's
            thickness.
        feet: the bolted feet (:class:`Foot`) on the bottom face.

    Raises:
        ValueError/TypeError: a non-positive dimension, a wall too thick for the box, a bore
            not inside its wall, a foot outside the bottom face (one line each).
    """

    length: float
    width: float
    height: float
    wall_thickness: float
    bores: tuple[Bore, ...] = ()
    feet: tuple[Foot, ...] = ()

    def __post_init__(self):
        for name in ("length", "width", "height", "wall_thickness"):
            _positive("HousingBox", name, getattr(self, name))
        t = self.wall_thickness
        if not 2 * t < min(self.length, self.width, self.height):
            raise ValueError(
                f"HousingBox: wall_thickness = {t!r} m, allowed < half the smallest dimension "
                f"({min(self.length, self.width, self.height) / 2!r} m)"
            )
        object.__setattr__(self, "bores", tuple(self.bores))
        object.__setattr__(self, "feet", tuple(self.feet))
        for k, b in enumerate(self.bores):
            if not isinstance(b, Bore):
                raise TypeError(f"HousingBox: bores[{k}] = {b!r}, allowed a fem_prep.housing.Bore")
            (lo0, hi0), (lo1, hi1) = self._wall_extent(b.wall)
            u, v = b.centre
            if not (
                lo0 + t <= u - b.radius
                and u + b.radius <= hi0 - t
                and lo1 + t <= v - b.radius
                and v + b.radius <= hi1 - t
            ):
                raise ValueError(
                    f"HousingBox: bores[{k}] (centre {b.centre}, radius {b.radius} m) leaves wall "
                    f"{b.wall}'s inner face (allowed within ({lo0 + t}, {hi0 - t}) x "
                    f"({lo1 + t}, {hi1 - t}) m)"
                )
        for k, f in enumerate(self.feet):
            if not isinstance(f, Foot):
                raise TypeError(f"HousingBox: feet[{k}] = {f!r}, allowed a fem_prep.housing.Foot")
            if not (
                0 <= f.x_range[0]
                and f.x_range[1] <= self.length
                and 0 <= f.y_range[0]
                and f.y_range[1] <= self.width
            ):
                raise ValueError(
                    f"HousingBox: feet[{k}] = {f!r} leaves the bottom face [0, {self.length}] x "
                    f"[0, {self.width}] m"
                )

    def outer_distance(self, points) -> np.ndarray:
        """The signed distance (m) of each point ``(n, 3)`` (m, the box's frame) to the box's
        outer faces, (n,): positive outside the box, negative inside it (in a wall or in the
        cavity), zero on its outer skin."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        half = 0.5 * np.array([self.length, self.width, self.height])
        q = np.abs(p - half) - half
        return np.linalg.norm(np.maximum(q, 0.0), axis=1) + np.minimum(q.max(axis=1), 0.0)

    def in_cavity(self, points) -> np.ndarray:
        """Whether each point ``(n, 3)`` (m, the box's frame) lies in the box's cavity, within
        its walls' inner faces, (n,) bool."""
        p = np.asarray(points, dtype=float).reshape(-1, 3)
        t = self.wall_thickness
        size = np.array([self.length, self.width, self.height])
        return np.all((p > t) & (p < size - t), axis=1)

    def _wall_extent(self, wall: str):
        L, W, H = self.length, self.width, self.height
        return {"x": ((0, W), (0, H)), "y": ((0, L), (0, H)), "z": ((0, L), (0, W))}[wall[0]]

    def seats(self) -> tuple[Seat, ...]:
        """The bores as :class:`Seat` s: centre at the wall's mid-thickness, axis the wall's
        normal, width the wall thickness."""
        t = self.wall_thickness
        out = []
        for k, b in enumerate(self.bores):
            u, v = b.centre
            i = "xyz".index(b.wall[0])
            w = t / 2 if b.wall[1] == "-" else (self.length, self.width, self.height)[i] - t / 2
            c = [u, v]
            c.insert(i, w)
            axis = [0.0, 0.0, 0.0]
            axis[i] = 1.0
            out.append(Seat(tuple(c), tuple(axis), b.radius, t, name=f"seat{k}"))
        return tuple(out)


@dataclass
class HousingMesh:
    """A tetrahedral housing mesh with its element, seats and feet.

    Attributes:
        mesh: the straight-sided four-node mesh (scikit-fem ``MeshTet1``), coordinates in m.
        element: :class:`Tet10` (the default) or :class:`Tet4`.
        seats: the bearing seats (:class:`Seat`).
        feet: the clamped feet (:class:`Foot`).
        seat_tolerance: the distance (m) a seat facet may lie beyond the bore radius (a
            structured mesh's bore is a staircase of cells).
        source: where it came from (``"structured box"``, ``"gmsh box"``, a file path).
    """

    mesh: skfem.MeshTet1
    element: TetElement = field(default_factory=Tet10)
    seats: tuple[Seat, ...] = ()
    feet: tuple[Foot, ...] = ()
    seat_tolerance: float = 0.0
    source: str = ""

    def __post_init__(self):
        if not isinstance(self.element, TetElement):
            raise TypeError(
                f"HousingMesh: element = {self.element!r}, allowed fem_prep.housing.Tet10() or "
                "Tet4()"
            )
        self._basis = None
        self._scalar = None

    @property
    def basis(self) -> skfem.Basis:
        """The vector basis (node k has DOFs 3k..3k+2 = u_x, u_y, u_z)."""
        if self._basis is None:
            e = skfem.ElementVector(self.element.skfem_element())
            self._basis = skfem.Basis(self.mesh, e, intorder=self.element.intorder)
        return self._basis

    @property
    def scalar_basis(self) -> skfem.Basis:
        """The scalar basis of the element: its DOFs are the FE nodes."""
        if self._scalar is None:
            self._scalar = skfem.Basis(
                self.mesh, self.element.skfem_element(), intorder=self.element.intorder
            )
        return self._scalar

    @property
    def nodes(self) -> np.ndarray:
        """FE node coordinates ``(n_nodes, 3)`` (m): vertices, then (Tet10) edge midpoints."""
        return self.scalar_basis.doflocs.T

    @property
    def n_dofs(self) -> int:
        return 3 * self.scalar_basis.N

    def _boundary(self):
        m = self.mesh
        f = m.boundary_facets()
        v = m.p[:, m.facets[:, f]]  # (3, 3 vertices, n_f)
        n = np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0], axis=0)
        n = n / np.linalg.norm(n, axis=0)
        return f, v.mean(axis=1), n

    def _facet_nodes(self, facets: np.ndarray) -> np.ndarray:
        return np.unique(self.scalar_basis.get_dofs(facets).flatten())

    def seat_nodes(self, seat: Seat) -> np.ndarray:
        """The FE nodes (indices) of a seat's facets.

        Raises:
            ValueError: no facet of the mesh matches the seat.
        """
        f, c, n = self._boundary()
        a = np.asarray(seat.axis)[:, None]
        d = c - np.asarray(seat.centre)[:, None]
        along = np.sum(d * a, axis=0)
        radial = np.linalg.norm(d - along * a, axis=0)
        tol = self.seat_tolerance
        sel = (
            (np.abs(np.sum(n * a, axis=0)) < 0.5)
            & (radial <= seat.radius + tol)
            & (np.abs(along) <= seat.width / 2 + 1e-9 * (seat.width + seat.radius))
        )
        if not sel.any():
            raise ValueError(
                f"seat {seat.name or seat.centre}: no bore facet within radius {seat.radius} m "
                f"(+ {tol} m) of the axis through {seat.centre}"
            )
        return self._facet_nodes(f[sel])

    def foot_nodes(self, foot: Foot) -> np.ndarray:
        """The FE nodes (indices) of a foot's facets on the plane ``z = z_min``.

        Raises:
            ValueError: no facet of that plane in the foot's rectangle.
        """
        f, c, n = self._boundary()
        z0 = float(self.mesh.p[2].min())
        scale = float(np.ptp(self.mesh.p, axis=1).max())
        sel = (
            (np.abs(n[2]) > 0.99)
            & (np.abs(c[2] - z0) < 1e-9 * scale)
            & (c[0] >= foot.x_range[0])
            & (c[0] <= foot.x_range[1])
            & (c[1] >= foot.y_range[0])
            & (c[1] <= foot.y_range[1])
        )
        if not sel.any():
            raise ValueError(f"foot {foot}: no facet of the bottom plane z = {z0} m in it")
        return self._facet_nodes(f[sel])


def _structured(x, y, z, keep_cell) -> skfem.MeshTet1:
    """The tensor grid's hexahedra for which ``keep_cell(centroids (3, n_cells))`` is true, each
    split into six tetrahedra along its main diagonal (scikit-fem's ``init_tensor``: the same
    split in every cell, so the faces match), unused nodes removed."""
    m = skfem.MeshTet1.init_tensor(x, y, z)
    # every tetrahedron of init_tensor's split holds its cell's main diagonal as its first and
    # last vertices: their midpoint is the cell's centroid
    cent = 0.5 * (m.p[:, m.t[0]] + m.p[:, m.t[3]])
    half = 0.5 * np.array([np.diff(g).max() for g in (x, y, z)])[:, None]
    inside = np.all(
        np.abs(m.p[:, m.t] - cent[:, None, :]) <= half[:, None, :] * (1 + 1e-9), axis=(0, 1)
    )
    if not inside.all():
        raise RuntimeError("structured mesher: scikit-fem's init_tensor split changed")
    keep = np.asarray(keep_cell(cent), dtype=bool)
    t = m.t[:, keep]
    used = np.unique(t)
    new = -np.ones(m.p.shape[1], dtype=np.int64)
    new[used] = np.arange(len(used))
    return skfem.MeshTet1(np.ascontiguousarray(m.p[:, used]), np.ascontiguousarray(new[t]))


def _check_element(element):
    if not isinstance(element, TetElement):
        raise TypeError(
            f"element = {element!r}, allowed fem_prep.housing.Tet10() or fem_prep.housing.Tet4()"
        )


def mesh_plate(
    a: float,
    b: float,
    thickness: float,
    divisions: tuple[int, int],
    *,
    layers: int = 1,
    element: TetElement | None = None,
) -> HousingMesh:
    """A flat plate ``[0, a] x [0, b] x [0, thickness]`` by the box's structured mesher (one wall
    of it): ``divisions = (n_x, n_y)`` cells in the plane, ``layers`` through the thickness, each
    cell split into six tetrahedra. The mesher's check against Leissa's plate.

    Raises:
        ValueError/TypeError: a non-positive size or count.
    """
    for name, v in (("a", a), ("b", b), ("thickness", thickness)):
        _positive("mesh_plate", name, v)
    nx, ny = divisions
    for name, v in (("divisions[0]", nx), ("divisions[1]", ny), ("layers", layers)):
        if isinstance(v, bool) or not isinstance(v, int) or v < 1:
            raise ValueError(f"mesh_plate: {name} = {v!r}, allowed an integer >= 1")
    element = Tet10() if element is None else element
    _check_element(element)
    mesh = _structured(
        np.linspace(0, a, nx + 1),
        np.linspace(0, b, ny + 1),
        np.linspace(0, thickness, layers + 1),
        lambda c: np.ones(c.shape[1], bool),
    )
    return HousingMesh(mesh, element, source="structured plate")


def _check_size(fn: str, size, layers=1):
    _positive(fn, "size", size)
    if isinstance(layers, bool) or not isinstance(layers, int) or layers < 1:
        raise ValueError(f"{fn}: layers = {layers!r}, allowed an integer >= 1")


def _box_grids(box: HousingBox, size: float, layers: int) -> tuple[list, float]:
    """:func:`mesh_box`'s tensor grid lines along x, y, z (m) and the largest cell across a
    bore (m): :func:`~fem_prep.housing.box_grids`' counts built into points."""
    counts, h_bore = box_grids(box, size, layers)
    return [grid_points(b, c) for b, c in counts], h_bore


def box_skin_edge(box: HousingBox, size: float, *, layers: int = 1) -> float:
    """The longest facet edge (m) of the outer faces of :func:`mesh_box`'s mesh of ``box``
    (``size``, ``layers`` as there), from its grid lines alone (nothing is meshed): each face
    cell is split along a diagonal, so the longest edge is the diagonal of the face's widest
    cell, sqrt(max Δu² + max Δv²) over the face's two grid directions.

    Raises:
        ValueError/TypeError: bad ``box``, ``size`` or ``layers`` (as :func:`mesh_box`).
    """
    if not isinstance(box, HousingBox):
        raise TypeError(f"box_skin_edge: box = {box!r}, allowed a fem_prep.housing.HousingBox")
    _check_size("box_skin_edge", size, layers)
    widest = [float(np.diff(g).max()) for g in _box_grids(box, size, layers)[0]]
    return max(math.hypot(widest[j], widest[k]) for j, k in ((1, 2), (0, 2), (0, 1)))


def mesh_box(
    box: HousingBox, size: float, *, layers: int = 1, element: TetElement | None = None
) -> HousingMesh:
    """Mesh a :class:`HousingBox` with the structured mesher (NumPy/scikit-fem, no gmsh).

    The box's tensor grid has lines at the walls' faces and the feet's edges, ``layers`` cells
    through each wall and cells of at most ``size`` elsewhere; the cells of the walls are kept,
    those whose centroid lies in a bore are removed (the bore is a staircase of cells: its seat
    takes the facets within one cell diagonal of the bore radius), and each cell is split into
    six tetrahedra. Refining ``size`` by halves nests the meshes of a box without bores (the
    frequencies then decrease monotonically: Rayleigh–Ritz on nested spaces).

    Args:
        box: the housing.
        size: the largest cell edge in the walls' planes (m).
        layers: cells through the wall thickness.
        element: :class:`Tet10` (``None``: the default) or :class:`Tet4`.

    Returns:
        The :class:`HousingMesh` with the box's seats and feet.

    Raises:
        ValueError/TypeError: bad ``size``, ``layers`` or ``element``; a ``size`` whose tensor
            grid needs more than half this machine's memory (:func:`estimate_box`, before any
            array is built; one line with the estimate and the limit).
    """
    if not isinstance(box, HousingBox):
        raise TypeError(f"mesh_box: box = {box!r}, allowed a fem_prep.housing.HousingBox")
    _check_size("mesh_box", size, layers)
    element = Tet10() if element is None else element
    _check_element(element)
    t = box.wall_thickness
    dims = (box.length, box.width, box.height)
    seats = box.seats()
    # the grid's size first (its counts alone): a grid this machine cannot hold is refused
    size_of = estimate_box(box, size, layers=layers, quadratic=element.name == "tet10",
                           bores=False)
    check_memory(f"mesh_box: size = {size!r} m", size_of.mesher_bytes,
                 f"the structured mesher's {size_of.grid_cells:.3g} grid cells (about "
                 f"{size_of.cells:.3g} tetrahedra, {size_of.dofs:.3g} DOFs)", "a larger size")
    grids, h_bore = _box_grids(box, size, layers)

    def keep(c):
        inside = np.ones(c.shape[1], bool)
        for i, L in enumerate(dims):
            inside &= (c[i] > t) & (c[i] < L - t)
        k = ~inside
        for bore, s in zip(box.bores, seats):
            i = "xyz".index(bore.wall[0])
            d = c - np.asarray(s.centre)[:, None]
            d[i] = 0
            in_wall = np.abs(c[i] - s.centre[i]) < t / 2
            k &= ~(in_wall & (np.linalg.norm(d, axis=0) < bore.radius))
        return k

    mesh = _structured(*grids, keep)
    # a hole facet's centroid lies within one diagonal of the bore's cells of its radius
    return HousingMesh(
        mesh,
        element,
        seats,
        box.feet,
        seat_tolerance=math.sqrt(2.0) * h_bore,
        source="structured box",
    )


#: gmsh's memory per tetrahedron while it meshes and this module reads the mesh back (its own
#: mesh data and the node and element arrays): an order of magnitude, for the size check
GMSH_BYTES_PER_CELL = 1024


def _gmsh():
    try:
        import gmsh
    except ImportError as e:  # one line, naming the extra
        raise ImportError(
            f"mesh_box_gmsh needs gmsh: pip install 'jaxgear[housing]' (or gmsh>=4.11) ({e})"
        ) from None
    return gmsh


def mesh_box_gmsh(
    box: HousingBox, size: float, *, element: TetElement | None = None
) -> HousingMesh:
    """Mesh a :class:`HousingBox` with gmsh (the optional dependency, ``pip install
    'jaxgear[housing]'``): the OpenCASCADE solid (outer box minus inner box minus the bores'
    cylinders) meshed by gmsh's Delaunay tetrahedra of target size ``size`` (m); the bores are
    round (facets on the cylinder).

    Raises:
        ImportError: gmsh is not installed (one line naming the extra).
        ValueError/TypeError: bad ``size`` or ``element``; a ``size`` whose mesh would need
            more than half this machine's memory (the structured mesher's count of the same
            box, :func:`estimate_box`, at :data:`GMSH_BYTES_PER_CELL`: an order of magnitude).
    """
    if not isinstance(box, HousingBox):
        raise TypeError(f"mesh_box_gmsh: box = {box!r}, allowed a fem_prep.housing.HousingBox")
    _check_size("mesh_box_gmsh", size)
    element = Tet10() if element is None else element
    _check_element(element)
    size_of = estimate_box(box, size, quadratic=element.name == "tet10", bores=False)
    check_memory(f"mesh_box_gmsh: size = {size!r} m", size_of.cells * GMSH_BYTES_PER_CELL,
                 f"about {size_of.cells:.3g} tetrahedra ({size_of.dofs:.3g} DOFs)",
                 "a larger size")
    gmsh = _gmsh()
    t = box.wall_thickness
    L, W, H = box.length, box.width, box.height
    seats = box.seats()
    started = gmsh.isInitialized() if hasattr(gmsh, "isInitialized") else False
    if not started:
        gmsh.initialize(interruptible=False)
    try:
        gmsh.option.setNumber("General.Terminal", 0)
        gmsh.model.add("housing")
        occ = gmsh.model.occ
        outer = occ.addBox(0, 0, 0, L, W, H)
        inner = occ.addBox(t, t, t, L - 2 * t, W - 2 * t, H - 2 * t)
        tools = [(3, inner)]
        for s in seats:
            c = np.asarray(s.centre) - np.asarray(s.axis) * t
            d = np.asarray(s.axis) * 2 * t
            tools.append((3, occ.addCylinder(*c, *d, s.radius)))
        occ.cut([(3, outer)], tools)
        # the feet's outlines on the bottom face, so that their facets are exact
        for f in box.feet:
            rect = occ.addRectangle(
                f.x_range[0],
                f.y_range[0],
                0.0,
                f.x_range[1] - f.x_range[0],
                f.y_range[1] - f.y_range[0],
            )
            occ.fragment(occ.getEntities(3), [(2, rect)])
        occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeMin", 0.05 * size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 16)  # bores: 16 chords or more
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        _, _, elem_nodes = gmsh.model.mesh.getElements(3)
        gmsh.model.remove()
    finally:
        if not started:
            gmsh.finalize()
    p = coords.reshape(-1, 3)
    index = -np.ones(int(tags.max()) + 1, dtype=np.int64)
    index[tags.astype(np.int64)] = np.arange(len(tags))
    tets = np.concatenate([n.reshape(-1, 4) for n in elem_nodes]).astype(np.int64)
    mesh = _compact(p, index[tets])
    return HousingMesh(
        mesh, element, seats, box.feet, seat_tolerance=0.05 * size, source="gmsh box"
    )


def _compact(p: np.ndarray, tets: np.ndarray) -> skfem.MeshTet1:
    used = np.unique(tets)
    new = -np.ones(len(p), dtype=np.int64)
    new[used] = np.arange(len(used))
    return skfem.MeshTet1(np.ascontiguousarray(p[used].T), np.ascontiguousarray(new[tets].T))


def read_housing_mesh(
    path,
    seats: tuple[Seat, ...] = (),
    feet: tuple[Foot, ...] = (),
    *,
    scale: float = 1.0,
    seat_tolerance: float | None = None,
    element: TetElement | None = None,
) -> HousingMesh:
    """A housing mesh from a file meshio reads (gmsh ``.msh``, ``.vtu``, ``.inp``, ...): its
    tetrahedra (``tetra``, or ``tetra10`` whose corner nodes are kept: the element rebuilds
    straight edges).

    Args:
        path: the mesh file.
        seats: the bearing seats (:class:`Seat`, in m, after ``scale``).
        feet: the clamped feet (:class:`Foot`, m) on the mesh's lowest plane.
        scale: the file's length unit in m (``1e-3`` for a mesh in mm).
        seat_tolerance: how far (m) a seat facet may lie beyond the bore radius; ``None``: 2 %
            of the smallest seat radius.
        element: :class:`Tet10` (``None``: the default) or :class:`Tet4`.

    Raises:
        FileNotFoundError: no such file. ValueError: a file meshio does not read (its reason
            in the message), no tetrahedra in it, a bad ``scale``.
    """
    import meshio  # lazy: only when a file is read

    path = Path(path)
    if not path.is_file():
        raise FileNotFoundError(f"read_housing_mesh: {str(path)!r} is not a file")
    _positive("read_housing_mesh", "scale", scale)
    element = Tet10() if element is None else element
    _check_element(element)
    try:
        m = meshio.read(path)
    except Exception as err:  # meshio's readers raise what their parsers meet  # noqa: BLE001
        reason = " ".join(str(err).split())[:160] or type(err).__name__
        raise ValueError(f"read_housing_mesh: {str(path)!r} is not a mesh meshio reads "
                         f"({reason})") from None
    tets = [c.data[:, :4] for c in m.cells if c.type in ("tetra", "tetra10")]
    if not tets:
        kinds = sorted({c.type for c in m.cells})
        raise ValueError(f"read_housing_mesh: {str(path)!r} has no tetrahedra (cells: {kinds})")
    seats = tuple(seats)
    tol = seat_tolerance
    if tol is None:
        tol = 0.02 * min((s.radius for s in seats), default=0.0)
    mesh = _compact(
        np.asarray(m.points[:, :3], dtype=float) * scale, np.concatenate(tets).astype(np.int64)
    )
    return HousingMesh(
        mesh, element, seats, tuple(feet), seat_tolerance=float(tol), source=str(path)
    )
