"""Sizes of a housing before it is meshed or condensed, so that work that cannot finish on this
machine is refused in one line first (:mod:`fem_prep.resources`; docs/fem_prep.md, "Housing
sizes").

* The structured box mesh (:func:`estimate_box`): its counts follow from the box's tensor grid
  alone (one dimension at a time; the bores from their in-plane window), so they cost nothing
  whatever the size: the tetrahedra and the FE nodes (vertices, and the edges' midpoints of
  :class:`~fem_prep.housing.Tet10`) exactly. The mesher's peak memory is that of the whole
  tensor grid it splits (:data:`MESHER_BYTES_PER_GRID_CELL` per grid cell).
* The interior modes below a cut-off (:func:`box_modes_below`): the asymptotic modal count of
  each wall as a clamped plate, Weyl's law with its edge term,
  N(k) ≈ A k² / 4π − P k / 2π, k = (ω² ρ t / D)^¼ the bending wavenumber, D = E t³ / 12(1 − ν²)
  (Courant & Hilbert; Xie, Thompson & Jones 2004 for plates), summed over the six walls.
* The condensation's peak memory (:func:`condensation_bytes`): the benchmark's rate per FE DOF
  of the assembly and the sparse factors (:data:`CONDENSE_BYTES_PER_DOF`), plus the dense
  arrays that grow with the modes: the Lanczos basis (2k + 1 vectors of the interior DOFs),
  the constraint and modal columns and their full-field recovery (6 per seat + k, each of
  every DOF); its CPU time (:func:`condensation_seconds`) from the benchmark's rates too.
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass

import numpy as np

from ..resources import check_memory

__all__ = [
    "BENCH_CONDENSATION",
    "CONDENSE_BYTES_PER_DOF",
    "MAX_HOUSING_MODES",
    "MESHER_BYTES_PER_GRID_CELL",
    "BoxEstimate",
    "box_modes_below",
    "check_housing_modes",
    "condensation_bytes",
    "condensation_seconds",
    "estimate_box",
]

#: the structured mesher's peak bytes per hexahedron of the box's whole tensor grid (its six
#: tetrahedra as float64 and int32 arrays, their corner coordinates and centroids while the
#: cells are kept or dropped); checked against the traced peak in the tests
MESHER_BYTES_PER_GRID_CELL = 2048
#: the condensation's bytes per FE DOF (the scalar basis and operators, the coupled and clamped
#: matrices, the sparse factors of the mode count and of K_ii): the benchmark's peak resident
#: memory over its DOFs, 16.1 kB at 296 k DOFs to 19 kB at 39 k (the process's own included;
#: docs/bench/housing_condensation.json), 11-13 kB more than the process held before on the
#: 15.6 k to 179 k DOF single-layer boxes of the embedded cases
CONDENSE_BYTES_PER_DOF = 16_000
#: the benchmark's condensation (docs/bench/housing_condensation.json, the idle 2-core
#: machine): CPU seconds at DOFs, with modes, and of its eigen-solve; the time grows as
#: DOFs^1.3 (its two sparse factorisations) and the eigen-solve's as DOFs × modes^1.4 (measured
#: side by side on the 15.6 k DOF box at 12, 112 and 326 modes)
BENCH_CONDENSATION = {"dofs": 295_755, "modes": 38, "cpu_s": 98.7, "eigen_cpu_s": 39.8}
#: the most interior modes a housing keeps: the eigen-solve's time grows as n k² and every
#: scene that carries the housing holds dense matrices of its 6 s + k coordinates
MAX_HOUSING_MODES = 1000


@dataclass(frozen=True)
class BoxEstimate:
    """A structured box mesh's sizes before it is built (:func:`estimate_box`).

    Attributes:
        cells: tetrahedra (exact).
        nodes: FE nodes: vertices, and edge midpoints with Tet10 (exact; ``bores`` False: the
            box's without its bores, an upper bound).
        dofs: 3 × nodes.
        grid_cells: hexahedra of the tensor grid the mesher splits (the whole grid, the
            cavity's too).
        mesher_bytes: the mesher's peak memory (bytes): grid_cells ×
            :data:`MESHER_BYTES_PER_GRID_CELL`.
    """

    cells: int
    nodes: int
    dofs: int
    grid_cells: int
    mesher_bytes: float


def grid_counts(breaks, size: float, layers_between=()) -> tuple[np.ndarray, list[int]]:
    """The structured mesher's grid along one axis without its points: the sorted breaks and
    the cells in each interval between them (``ceil(length / size)``, or more inside an
    interval ``(lo, hi, k)`` of ``layers_between``: at most ``(hi - lo) / k`` there)."""
    b = np.unique(np.round(np.asarray(breaks, dtype=float), 12))
    counts = []
    for lo, hi in itertools.pairwise(b):
        n = max(1, math.ceil((hi - lo) / size - 1e-9))
        for a, c, k in layers_between:
            if a - 1e-12 <= lo and hi <= c + 1e-12:  # inside a fixed interval: its cell size
                n = max(n, math.ceil((hi - lo) / (c - a) * k - 1e-9))
        counts.append(n)
    return b, counts


def box_grids(box, size: float, layers: int):
    """Each axis's (breaks, cells per interval) of :func:`~fem_prep.housing.mesh_box`'s tensor
    grid (:func:`grid_counts`), and the cell size across the bores (m)."""
    t = box.wall_thickness
    dims = (box.length, box.width, box.height)
    seats = box.seats()
    out, h_bore = [], 0.0
    for i, L in enumerate(dims):
        br = [0.0, t, L - t, L]
        fixed = [(0.0, t, layers), (L - t, L, layers)]
        for f in box.feet:
            if i < 2:
                br += list((f.x_range, f.y_range)[i])
        for bore, s in zip(box.bores, seats, strict=True):
            if "xyz".index(bore.wall[0]) != i:
                # across the bore: lines at its edges and at least 4 cells over its diameter
                c, r = s.centre[i], bore.radius
                n = max(4, math.ceil(2 * r / size - 1e-9))
                br += [c - r, c + r]
                fixed.append((c - r, c + r, n))
                h_bore = max(h_bore, 2 * r / n)
        out.append(grid_counts(br, size, fixed))
    return out, h_bore


def grid_points(breaks, counts, lo=-math.inf, hi=math.inf) -> np.ndarray:
    """The grid's points (:func:`grid_counts`), only the intervals within [lo, hi] built."""
    pts = [breaks[:1]] if breaks[0] >= lo else []
    for (a, c), n in zip(itertools.pairwise(breaks), counts, strict=True):
        if a >= lo - 1e-12 and c <= hi + 1e-12:
            pts.append(np.linspace(a, c, n + 1)[1:] if pts else np.linspace(a, c, n + 1))
    return np.concatenate(pts) if pts else np.zeros(0)


def _inside(breaks, counts, lo, hi) -> int:
    """Cells of the intervals within [lo, hi]."""
    return sum(n for (a, c), n in zip(itertools.pairwise(breaks), counts, strict=True)
               if a >= lo - 1e-12 and c <= hi + 1e-12)


def _bores_removed(box, grids, seats) -> tuple[int, int, int]:
    """What the bores remove from the box without them: (hexahedra, Tet10 nodes, Tet4 nodes).

    A bore takes the wall's cells through its thickness whose in-plane centre lies in its
    circle (as the mesher keeps them): a prism S × the wall's 1D grid (P points, I intervals).
    An FE node goes with it when every cell round it is gone: an in-plane entity inside S (a
    vertex whose four cells, an edge whose two cells are in S; each cell of S, whose diagonals
    carry nodes) at any point or interval of the wall's grid (the cells beyond both faces are
    outside the box or in the cavity). The structured split puts one Tet10 node on each
    (vertex, edge, cell) × (point, interval) pair: (V° + E° + |S|)(P + I) nodes; Tet4's are the
    vertices, V° P."""
    t = box.wall_thickness
    dims = (box.length, box.width, box.height)
    hexes = quad = lin = 0
    for bore, s in zip(box.bores, seats, strict=True):
        i = "xyz".index(bore.wall[0])
        lo = 0.0 if bore.wall[1] == "-" else dims[i] - t
        through = _inside(*grids[i], lo, lo + t)
        j, k = (a for a in range(3) if a != i)
        r = bore.radius
        cj = grid_points(*grids[j], s.centre[j] - r, s.centre[j] + r)
        ck = grid_points(*grids[k], s.centre[k] - r, s.centre[k] + r)
        mj, mk = 0.5 * (cj[1:] + cj[:-1]), 0.5 * (ck[1:] + ck[:-1])
        inside = (mj[:, None] - s.centre[j]) ** 2 + (mk[None, :] - s.centre[k]) ** 2 < r * r
        S = np.pad(inside, 1)  # the window's cells, none of S beyond it
        verts = np.count_nonzero(S[:-1, :-1] & S[1:, :-1] & S[:-1, 1:] & S[1:, 1:])
        edges = np.count_nonzero(S[:-1, :] & S[1:, :]) + np.count_nonzero(S[:, :-1] & S[:, 1:])
        cells = int(np.count_nonzero(inside))
        hexes += through * cells
        quad += (verts + edges + cells) * (2 * through + 1)
        lin += verts * (through + 1)
    return hexes, quad, lin


def estimate_box(box, size: float, *, layers: int = 1, quadratic: bool = True,
                 bores: bool = True) -> BoxEstimate:
    """The sizes of ``mesh_box(box, size, layers=layers)`` (module docstring) from the box's
    tensor grid, without building it: cells, FE nodes (``quadratic``: Tet10, else Tet4), DOFs,
    the grid's cells and the mesher's peak bytes. ``bores`` False leaves the bores' cells in
    (the bound the memory check needs, before the bores are counted)."""
    grids, _ = box_grids(box, size, layers)
    t = box.wall_thickness
    dims = (box.length, box.width, box.height)
    N = [sum(c) for _, c in grids]  # cells per axis
    P = [n + 1 for n in N]
    n_in = [_inside(b, c, t, L - t) for (b, c), L in zip(grids, dims, strict=True)]
    p_in = [n - 1 for n in n_in]  # points strictly inside (t, L - t)
    hexes = math.prod(N) - math.prod(n_in)
    verts = math.prod(P) - math.prod(p_in)
    edges = hexes  # each cell's main diagonal (the six tetrahedra share it)
    for i in range(3):  # the axis edges along i, the face diagonals normal to i
        j, k = (a for a in range(3) if a != i)
        edges += N[i] * P[j] * P[k] - n_in[i] * p_in[j] * p_in[k]
        edges += N[j] * N[k] * P[i] - n_in[j] * n_in[k] * p_in[i]
    grid = math.prod(N)
    mesher = float(grid) * MESHER_BYTES_PER_GRID_CELL
    nodes = verts + edges if quadratic else verts
    if bores and box.bores and mesher <= 1e12:  # an absurd grid is refused on the bound first
        gone, quad, lin = _bores_removed(box, grids, box.seats())
        hexes -= gone
        nodes -= quad if quadratic else lin
    return BoxEstimate(6 * hexes, nodes, 3 * nodes, grid, mesher)


def box_modes_below(box, material, cutoff_hz: float) -> float:
    """The housing's interior modes at or below ``cutoff_hz`` (Hz), estimated (module
    docstring): Σ over the six walls max(0, A k² / 4π − P k / 2π), each wall a clamped plate of
    the box's outer face (A, P its area and perimeter), k its bending wavenumber at the
    cut-off. An order of magnitude (within a factor of about 2 on the embedded boxes); the
    exact count comes from the LDLᵀ inertia before the eigen-solve."""
    t = box.wall_thickness
    E, nu, rho = material.youngs_modulus, material.poisson_ratio, material.density
    D = E * t**3 / (12 * (1 - nu**2))
    w = 2 * math.pi * cutoff_hz
    k = (w * w * rho * t / D) ** 0.25
    L, W, H = box.length, box.width, box.height
    total = 0.0
    for a, b in ((L, W), (L, H), (W, H)):
        total += 2 * max(0.0, a * b * k * k / (4 * math.pi) - (a + b) * k / math.pi)
    return total


def condensation_bytes(dofs: int, modes: float, seats: int) -> float:
    """The condensation's peak memory (bytes; module docstring) for ``dofs`` FE DOFs,
    ``modes`` interior modes and ``seats`` seats: :data:`CONDENSE_BYTES_PER_DOF` per DOF plus
    8 bytes × DOFs × ((2 modes + 1) Lanczos vectors + 2 (6 seats + modes) columns)."""
    k = max(float(modes), 0.0)
    return float(dofs) * (CONDENSE_BYTES_PER_DOF + 8.0 * ((2 * k + 1) + 2 * (6 * seats + k)))


def condensation_seconds(dofs: int, modes: float) -> float:
    """The condensation's CPU seconds estimated from the benchmark's rates
    (:data:`BENCH_CONDENSATION`): t (n / n_b)^1.3 + t_eig (n / n_b) ((k / k_b)^1.4 − 1)^+, n
    the DOFs and k the modes; an order of magnitude (a loaded machine takes longer in wall
    time)."""
    b = BENCH_CONDENSATION
    x = float(dofs) / b["dofs"]
    more = max((max(float(modes), 0.0) / b["modes"]) ** 1.4 - 1.0, 0.0)
    return b["cpu_s"] * x**1.3 + b["eigen_cpu_s"] * x * more


def check_housing_modes(subject: str, modes: float, dofs: int, seats: int, how: str,
                        fix: str) -> None:
    """Refuse a condensation of ``modes`` interior modes (``how``: "counted", "estimated")
    above :data:`MAX_HOUSING_MODES`, or whose memory (:func:`condensation_bytes`) exceeds
    :func:`fem_prep.resources.memory_allowed`: one-line ``ValueError`` naming ``subject``."""
    if modes > MAX_HOUSING_MODES:
        raise ValueError(
            f"{subject}: out of range: {modes:.0f} interior housing modes below the cut-off "
            f"({how}), allowed <= {MAX_HOUSING_MODES}: {fix}"
        )
    check_memory(subject, condensation_bytes(dofs, modes, seats),
                 f"the condensation of {dofs} DOFs with {modes:.0f} modes ({how})", fix)
