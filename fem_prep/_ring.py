"""A thin-rimmed ring gear with internal teeth: its FE body, its housing support, its condensation
on the tooth-root masters and its nodal-diameter modes (docs/planetary.md, "A flexible ring gear").

The body is the annulus between the root circle ``r = R_f`` (the inner face, where the internal
teeth stand) and the outer radius ``R_o``, over the face width ``b``. As for the wheels, the teeth
are outside the FE body: they load the rim through the root patches of the inner face, the
distributing coupling of :mod:`._rim` (one master station per tooth, ``n_axial`` master planes
across the face), so that a tooth's load is spread over one pitch of the root circle and the
compliance at the masters converges under mesh refinement. The ring is held by the housing
through a :class:`~fem_prep.RingSupport` (clamped bolt seats on the outer face, a uniform elastic
foundation, or none) and condensed by Craig–Bampton on the masters (seed (2.3)-(2.5)).

Reference for the free ring's in-plane flexural modes (Hoppe 1871; Love, *Mathematical Theory of
Elasticity* §293; Blevins, *Formulas for Natural Frequency and Mode Shape*, Table 9-2): a thin
ring of mean radius R, section A = b h and in-plane second moment I = b h^3 / 12 vibrates with n
nodal diameters at

    omega_n^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1)),   n = 2, 3, ...

(inextensional curved beam, shear and rotary inertia neglected: the FE ring is lower by terms of
order (n h / R)^2 / 12 times the shear flexibility ratio).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass
from pathlib import Path
from typing import ClassVar, final

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import skfem

from ._assemble import Operators, assemble_operators
from ._body import Condensation, Material, MeshSettings
from ._condense import Condensed, condense
from ._couplings import Coupled, MasterSet, _station_nodes, couple_masters
from ._kinds import RingSupport
from ._mesh import RIM, BodyMesh, arc_hex2, revolved_hexes, used_vertices
from ._modal import nodal_diameter_spectrum
from ._solver import shift_invert_modes
from .files import atomic_open

__all__ = [
    "BoltedFlange",
    "ElasticFoundation",
    "FreeRing",
    "PreparedRing",
    "RingBody",
    "mesh_ring",
    "mode_nodal_diameter",
    "prepare_ring",
    "ring_master_compliance",
    "thin_ring_frequency",
    "write_ring_vtu",
]


@dataclass(frozen=True)
class RingBody:
    """A ring gear body (SI units).

    Attributes:
        name: the body's name.
        root_radius: R_f (m), the root circle of the internal teeth: the inner face, which
            carries the rim masters.
        outer_radius: R_o (m), > R_f: the outer face (where a bolted flange holds it).
        width: b (m), the face width (z from -b/2 to b/2).
        material: the elastic material.
        mesh: the element and target sizes (m): ``rim_size`` radially and axially (``size`` if
            None), ``circumferential_size`` around (``size`` if None).
        condensation: the method (:class:`~fem_prep.CraigBampton`), the rim coupling
            (:class:`~fem_prep.Distributing`), the retained modes, ``teeth``: one master
            station per tooth (station k at 2 pi k / teeth from +x), ``axial_master_nodes``.
        support: how the housing holds it (:class:`BoltedFlange`, :class:`ElasticFoundation`,
            :class:`FreeRing`).
    """

    name: str
    root_radius: float
    outer_radius: float
    width: float
    material: Material
    mesh: MeshSettings
    condensation: Condensation
    support: RingSupport

    def __post_init__(self):
        for name in ("root_radius", "width"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v > 0):
                raise ValueError(f"RingBody: {name} = {v!r} m, allowed > 0")
        if not self.outer_radius > self.root_radius:
            raise ValueError(
                f"RingBody: outer_radius = {self.outer_radius!r} m, allowed > root_radius = "
                f"{self.root_radius!r} m"
            )
        if self.condensation.teeth < 3:
            raise ValueError(
                f"RingBody: condensation.teeth = {self.condensation.teeth!r}, allowed >= 3"
            )

    @property
    def mean_radius(self) -> float:
        """R = (R_f + R_o) / 2 (m)."""
        return 0.5 * (self.root_radius + self.outer_radius)

    @property
    def thickness(self) -> float:
        """h = R_o - R_f (m), the rim's radial thickness."""
        return self.outer_radius - self.root_radius


def thin_ring_frequency(ring: RingBody, n) -> np.ndarray:
    """f_n (Hz) of the thin ring's in-plane n-nodal-diameter flexural modes (module docstring:
    omega_n^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1)), I = b h^3 / 12, A = b h, R the
    mean radius), for ``n >= 2`` (array or int)."""
    n = np.asarray(n, dtype=float)
    m = ring.material
    h, b, R = ring.thickness, ring.width, ring.mean_radius
    EI, rhoA = m.youngs_modulus * b * h**3 / 12, m.density * b * h
    w2 = EI * n**2 * (n**2 - 1) ** 2 / (rhoA * R**4 * (n**2 + 1))
    return np.sqrt(w2) / (2 * math.pi)


# ------------------------------------------------------------------------------------------
# the mesh


def _axial_grid(ring: RingBody, size: float) -> np.ndarray:
    """z grid (m) with the axial master planes as lines (linspace over the face)."""
    nax = ring.condensation.axial_master_nodes
    b = ring.width
    planes = np.array([0.0]) if nax == 1 else np.linspace(-b / 2, b / 2, nax)
    breaks = np.unique(np.concatenate([[-b / 2, b / 2], planes]))
    z = [breaks[0]]
    for a, c in itertools.pairwise(breaks):
        k = max(1, round((c - a) / size))
        z.extend(np.linspace(a, c, k + 1)[1:])
    return np.array(z)


def mesh_ring(ring: RingBody) -> BodyMesh:
    """The ring's structured mesh: the meridian rectangle [R_f, R_o] x [-b/2, b/2] swept around
    the axis with a multiple of ``teeth`` circumferential divisions (a node at every station),
    quadratic geometry (circles exact at the nodes), every element in region 2 (rim).

    Raises:
        ValueError: an inverted element.
    """
    ms = ring.mesh
    s_rad = ms.rim_size or ms.size
    s_circ = ms.circumferential_size or ms.size
    nr = max(1, round(ring.thickness / s_rad))
    r_grid = np.linspace(ring.root_radius, ring.outer_radius, nr + 1)
    z_grid = _axial_grid(ring, s_rad)
    nz = len(z_grid) - 1
    teeth = ring.condensation.teeth
    q = max(1, math.ceil(2 * math.pi * ring.mean_radius / (teeth * s_circ) - 0.25))
    nt = teeth * q
    dth = 2 * math.pi / nt

    I, J, K = (
        a.ravel() for a in np.meshgrid(np.arange(nr), np.arange(nz), np.arange(nt), indexing="ij")
    )

    t, vi, vj, vk = used_vertices(revolved_hexes(I, J, K, nz, nt), nz, nt)
    rv, th = r_grid[vi], vk * dth
    p = np.array([rv * np.cos(th), rv * np.sin(th), z_grid[vj]])
    mesh = arc_hex2(p, t, dth)
    basis = skfem.Basis(
        mesh, skfem.ElementVector(ms.element.skfem_element()), intorder=ms.element.intorder
    )
    det = -mesh._mapping().detDF(basis.quadrature[0])
    if not np.all(det > 0):
        raise ValueError("mesh_ring: inverted elements; refine [mesh] size_mm")
    nodes = np.ascontiguousarray(basis.doflocs[:, 0::3].T)
    return BodyMesh(
        mesh=mesh,
        basis=basis,
        nodes=nodes,
        n_vertices=int(t.max()) + 1,
        cells=np.ascontiguousarray(t[[0, 3, 6, 2, 1, 5, 7, 4]].T),
        region=np.full(t.shape[1], RIM),
        n_theta=nt,
        r_grid=r_grid,
        z_grid=z_grid,
        element=ms.element,
        vertex_ijk=np.stack([vi, vj, vk], axis=1),
    )


def _outer_facets(bm: BodyMesh, radius: float) -> np.ndarray:
    facets = bm.mesh.boundary_facets()
    corners = bm.mesh.facets[:, facets]
    rho = np.hypot(bm.nodes[corners, 0], bm.nodes[corners, 1])
    return facets[np.all(np.abs(rho - radius) < 1e-7 * radius, axis=0)]


def _outer_nodes(bm: BodyMesh, radius: float) -> np.ndarray:
    rho = np.hypot(bm.nodes[:, 0], bm.nodes[:, 1])
    return np.nonzero(np.abs(rho - radius) < 1e-7 * radius)[0]


# ------------------------------------------------------------------------------------------
# housing supports


@final
@dataclass(frozen=True, eq=True)
class FreeRing(RingSupport):
    """No support: the free ring (its six rigid-body modes are kept; the modal check of the
    thin-ring formula)."""

    name: ClassVar[str] = "free"

    def foundation(self, ring, bm):
        return sp.csr_matrix((bm.n_dofs, bm.n_dofs))

    def clamped(self, ring, bm):
        return np.zeros(0, dtype=np.int64)


@final
@dataclass(frozen=True, eq=True)
class BoltedFlange(RingSupport):
    """Discrete clamped bolt seats on the outer face: every node of the outer face within
    ``seat_arc / 2`` (m, along the outer circle) of a bolt's angle ``phase + 2 pi i / bolts``
    is held in its three translations (a rigid housing, the bolt's clamped patch).

    Attributes:
        bolts: the number of bolts (>= 1).
        seat_arc: the seat's circumferential length on the outer circle (m, > 0).
        phase: the first bolt's angle from +x (rad).
    """

    name: ClassVar[str] = "bolted_flange"
    bolts: int = 12
    seat_arc: float = 0.01
    phase: float = 0.0

    def __post_init__(self):
        if int(self.bolts) != self.bolts or self.bolts < 1:
            raise ValueError(f"BoltedFlange: bolts = {self.bolts!r}, allowed an integer >= 1")
        if not (math.isfinite(self.seat_arc) and self.seat_arc > 0):
            raise ValueError(f"BoltedFlange: seat_arc = {self.seat_arc!r} m, allowed > 0")

    def foundation(self, ring, bm):
        return sp.csr_matrix((bm.n_dofs, bm.n_dofs))

    def clamped(self, ring, bm):
        nodes = _outer_nodes(bm, ring.outer_radius)
        x = bm.nodes[nodes]
        th = np.arctan2(x[:, 1], x[:, 0]) - self.phase
        pitch = 2 * math.pi / self.bolts
        d = np.abs(np.mod(th + pitch / 2, pitch) - pitch / 2) * ring.outer_radius
        held = nodes[d <= self.seat_arc / 2 + 1e-9 * ring.outer_radius]
        if len(held) == 0:
            raise ValueError(
                f"BoltedFlange: seat_arc = {self.seat_arc!r} m holds no node of the outer face; "
                "allowed >= the circumferential element size"
            )
        return (3 * held[:, None] + np.arange(3)).ravel()


@final
@dataclass(frozen=True, eq=True)
class ElasticFoundation(RingSupport):
    """A uniform elastic support of the outer face (a Winkler foundation: the housing seen as a
    bed of springs), traction ``t = -(k_r u_r e_r + k_t u_t e_t + k_a u_z e_z)`` (Pa) for the
    displacement ``u`` (m) of the outer face, assembled as the consistent boundary matrix
    ``int_S (k_r u_r v_r + k_t u_t v_t + k_a u_z v_z) dS``.

    Attributes:
        radial, tangential, axial: k_r, k_t, k_a (N/m per m^2 = Pa/m, >= 0; together they must
            hold the rigid motions: k_t > 0 and k_a > 0).
    """

    name: ClassVar[str] = "elastic_foundation"
    radial: float = 1e12
    tangential: float = 1e12
    axial: float = 1e12

    def __post_init__(self):
        for name in ("radial", "tangential", "axial"):
            v = getattr(self, name)
            if not (math.isfinite(v) and v >= 0):
                raise ValueError(f"ElasticFoundation: {name} = {v!r} Pa/m, allowed >= 0")
        if self.tangential <= 0 or self.axial <= 0:
            raise ValueError(
                f"ElasticFoundation: tangential = {self.tangential!r}, axial = {self.axial!r} "
                "Pa/m; allowed > 0 (else the ring turns or slides freely)"
            )

    def foundation(self, ring, bm):
        # the scalar facet matrices int phi_i phi_j c_ab dS of the springs' Cartesian tensor
        # c = k_r e_r e_r + k_t e_t e_t + k_a e_z e_z, by NumPy products on the quadrature
        fb = skfem.FacetBasis(
            bm.mesh,
            bm.element.skfem_element(),
            facets=_outer_facets(bm, ring.outer_radius),
            intorder=bm.element.intorder + 1,
        )
        phi = np.stack([np.asarray(b[0]) for b in fb.basis])  # (n_loc, n_f, n_q)
        x = np.asarray(fb.global_coordinates())  # (3, n_f, n_q)
        r = np.hypot(x[0], x[1])
        c, s = x[0] / r, x[1] / r
        kr, kt = self.radial, self.tangential
        tensor = {
            (0, 0): kr * c * c + kt * s * s,
            (1, 1): kr * s * s + kt * c * c,
            (0, 1): (kr - kt) * c * s,
            (1, 0): (kr - kt) * c * s,
            (2, 2): self.axial * np.ones_like(r),
        }
        dofs = fb.element_dofs  # (n_loc, n_f) scalar = node indices
        rows = np.broadcast_to(dofs[:, None, :], (dofs.shape[0],) + dofs.shape)
        cols = np.broadcast_to(dofs[None, :, :], (dofs.shape[0],) + dofs.shape)
        parts = []
        for (a, b), cab in tensor.items():
            local = np.einsum("ifq,jfq,fq->ijf", phi, phi, cab * fb.dx)
            parts.append((local.ravel(), 3 * rows.ravel() + a, 3 * cols.ravel() + b))
        v, i, j = (np.concatenate(p) for p in zip(*parts))
        return sp.csr_matrix((v, (i, j)), shape=(bm.n_dofs, bm.n_dofs))

    def clamped(self, ring, bm):
        return np.zeros(0, dtype=np.int64)


# ------------------------------------------------------------------------------------------
# the prepared ring


@dataclass(frozen=True)
class PreparedRing:
    """A ring meshed, supported, coupled to its masters and condensed.

    Attributes:
        ring: the body.
        mesh: its :class:`~fem_prep.BodyMesh`.
        operators: the full operators (without the support).
        foundation: the support's full stiffness ``(n_full, n_full)`` (N/m; zero when clamped
            or free).
        coupled: the master coupling ``u_full = T q`` (:class:`~fem_prep._couplings.Coupled`).
        kept: the coupled DOFs not clamped by the support (indices into ``coupled``).
        K, M: the supported coupled stiffness and mass on ``kept`` (CSR).
        master_dofs: indices into ``kept`` of the master DOFs ``(teeth, n_axial, 3)``.
        condensed: the condensed ring (:class:`~fem_prep.Condensed`; masters first, in the
            order of ``master_dofs`` flattened).
    """

    ring: RingBody
    mesh: BodyMesh
    operators: Operators
    foundation: sp.csr_matrix
    coupled: Coupled
    kept: np.ndarray
    K: sp.csr_matrix
    M: sp.csr_matrix
    master_dofs: np.ndarray
    condensed: Condensed

    def full_modes(self, n: int, sigma: float = -1.0) -> tuple[np.ndarray, np.ndarray]:
        """The supported full model's lowest ``n`` modes: ``(f (Hz), shapes (n_full, n))``,
        the shapes as full FE displacements (m, mass-normalised). ``sigma`` ((rad/s)^2, < 0
        for a free ring): the shift."""
        lam, phi = shift_invert_modes(self.K, self.M, n, sigma=sigma)
        return _hz(lam), self.full_field(phi)

    def condensed_frequencies(self) -> np.ndarray:
        """f (Hz) of every mode of the condensed model (ascending)."""
        c = self.condensed
        return _hz(sla.eigh(c.K, c.M, eigvals_only=True))

    def full_field(self, x_kept: np.ndarray) -> np.ndarray:
        """Full FE displacements ``(n_full, ...)`` of coupled DOFs on ``kept`` ``(n_kept, ...)``."""
        q = np.zeros((self.coupled.T.shape[1],) + x_kept.shape[1:])
        q[self.kept] = x_kept
        return self.coupled.T @ q

    def static(self, master_forces: np.ndarray) -> np.ndarray:
        """The full FE displacement (m, ``(n_full,)``) under forces (N) on the masters
        ``(teeth, n_axial, 3)``, by the condensed model (exact for Craig–Bampton statics)."""
        c = self.condensed
        f = np.zeros(c.K.shape[0])
        f[: c.master_dofs.size] = np.asarray(master_forces, dtype=float).ravel()
        qc = np.linalg.solve(c.K, f)
        return self.full_field(c.basis @ qc)

    def support_reactions(self, u_full: np.ndarray) -> np.ndarray:
        """The forces (N, ``(n_full,)``) the support puts on the ring at the displacement
        ``u_full``: ``-K_s u`` of a foundation, and at clamped DOFs the equilibrium residual
        ``(K u)`` there (the loads act on the masters only, which are never clamped)."""
        r = -(self.foundation @ u_full)
        held = self.ring.support.clamped(self.ring, self.mesh)
        r[held] += (self.operators.K @ u_full)[held]
        return r


def _hz(lam: np.ndarray) -> np.ndarray:
    return np.sqrt(np.maximum(lam, 0.0)) / (2 * math.pi)


def prepare_ring(ring: RingBody) -> PreparedRing:
    """Mesh, assemble, couple the root-patch masters (:mod:`._rim`), add the support and condense
    the ring (Craig–Bampton on the masters, ``ring.condensation``).

    Returns:
        The :class:`PreparedRing`.
    """
    bm = mesh_ring(ring)
    ops = assemble_operators(bm.basis, ring.material)
    cond = ring.condensation
    nax = cond.axial_master_nodes
    zm = np.array([0.0]) if nax == 1 else np.linspace(-ring.width / 2, ring.width / 2, nax)
    rim = _station_nodes(bm.nodes, ring.root_radius, cond.teeth, zm)
    masters = MasterSet(
        rim_nodes=rim,
        bearing_positions=np.zeros((0, 3)),
        bearing_rings=(),
        couplings=(),
        rim_coupling=cond.rim_coupling,
        rim_radius=ring.root_radius,
        rim_band=(-ring.width / 2, ring.width / 2),
    )
    cp = couple_masters(bm, ops, masters)
    ks = ring.support.foundation(ring, bm)
    held = ring.support.clamped(ring, bm)
    held_red = cp.full_to_red[held]
    if np.any(held_red < 0):
        raise ValueError("prepare_ring: a clamped node is a master (move the bolt seats)")
    mask = np.ones(cp.T.shape[1], dtype=bool)
    mask[held_red] = False
    kept = np.nonzero(mask)[0]
    K = (cp.K + cp.reduce(ks))[kept][:, kept].tocsr()
    M = cp.M[kept][:, kept].tocsr()
    red_to_kept = -np.ones(cp.T.shape[1], dtype=np.int64)
    red_to_kept[kept] = np.arange(len(kept))
    mdofs = red_to_kept[cp.rim_dofs]
    c = condense(K, M, mdofs.ravel(), method=cond.method, n_modes=cond.modes)
    return PreparedRing(ring, bm, ops, ks, cp, kept, K, M, mdofs, c)


def ring_master_compliance(prep: PreparedRing) -> tuple[np.ndarray, np.ndarray]:
    """The supported ring's static in-plane compliance at its stations, for loads spread
    uniformly across the face width: ``(F, angles)``, F ``(teeth, 2, teeth, 2)`` (m/N) with
    ``u_k = sum_k' F[k, :, k', :] P_k'`` for the in-plane forces ``P_k'`` (x, y, N) at station
    k' and the face-averaged in-plane displacement ``u_k`` (m) of station k, and the station
    angles ``(teeth,)`` (rad from +x).

    The force of a station goes to its axial masters with the weights of a uniform line load on
    the linear axial field (trapezoid weights), and the displacement is read with the same
    weights (work-conjugate). A free ring has no compliance (its stiffness is singular).

    Raises:
        ValueError: a free ring.
    """
    if prep.ring.support == FreeRing():
        raise ValueError("ring_master_compliance: support = FreeRing(); allowed a held ring")
    c = prep.condensed
    nb = c.master_dofs.size
    teeth, nax, _ = prep.master_dofs.shape
    # the boundary block of a Craig-Bampton model is statically decoupled from its modes (2.5)
    Kbb = c.K[:nb, :nb]
    Kmm = c.K[nb:, nb:]
    Kbm = c.K[:nb, nb:]
    S = Kbb - Kbm @ np.linalg.solve(Kmm, Kbm.T) if Kmm.size else Kbb
    w = np.ones(nax) if nax == 1 else np.r_[0.5, np.ones(nax - 2), 0.5]
    w = w / w.sum()
    E = np.zeros((teeth, nax, 3, teeth, 2))  # master DOFs from station forces
    for a in range(2):
        E[np.arange(teeth), :, a, np.arange(teeth), a] = w
    E = E.reshape(nb, 2 * teeth)
    F = E.T @ np.linalg.solve(S, E)
    F = 0.5 * (F + F.T)
    return F.reshape(teeth, 2, teeth, 2), 2 * math.pi * np.arange(teeth) / teeth


def mode_nodal_diameter(prep: PreparedRing, shape: np.ndarray) -> tuple[int, float]:
    """``(n, in-plane fraction)`` of a full FE mode shape: its dominant circumferential
    harmonic (seed (3.2)) and the share of its squared displacement that is in the plane."""
    spectrum = nodal_diameter_spectrum(prep.mesh, shape)
    u = shape.reshape(-1, 3)
    inplane = float(np.sum(u[:, :2] ** 2) / np.sum(u**2))
    return int(np.argmax(spectrum)), inplane


def _vtu_array(name: str, values: np.ndarray, components: int) -> str:
    text = " ".join(repr(float(v)) for v in np.ravel(values))
    return (
        f'<DataArray type="Float64" Name="{name}" NumberOfComponents="{components}" '
        f'format="ascii">{text}</DataArray>'
    )


def write_ring_vtu(
    prep: PreparedRing, path, n_modes: int = 10, sigma: float = -1.0, point_data=None
) -> Path:
    """Write the ring's mesh (corner nodes, linear hexahedra) with its first ``n_modes`` full
    FE mode shapes as point data ``mode_XX_<f>Hz_ND<n>`` (mass-normalised, m) to an ASCII
    ``.vtu`` (ParaView). ``sigma``: the eigen-solve's shift ((rad/s)^2, < 0 for a free ring).
    ``point_data``: more vector fields ``{name: (n_nodes, 3)}`` (full FE nodes; the corner
    nodes' values are written), e.g. a deflected shape.

    Returns:
        The path written.
    """
    bm = prep.mesh
    nv = bm.n_vertices
    f, shapes = prep.full_modes(n_modes, sigma=sigma)
    arrays = []
    for k in range(n_modes):
        nd, _ = mode_nodal_diameter(prep, shapes[:, k])
        name = f"mode_{k + 1:02d}_{f[k]:.0f}Hz_ND{nd}"
        arrays.append(_vtu_array(name, shapes[:, k].reshape(-1, 3)[:nv], 3))
    for name, values in (point_data or {}).items():
        arrays.append(_vtu_array(name, np.asarray(values).reshape(-1, 3)[:nv], 3))
    n_cells = len(bm.cells)
    connectivity = " ".join(str(int(i)) for i in bm.cells.ravel())
    offsets = " ".join(str(8 * (i + 1)) for i in range(n_cells))
    types = " ".join(["12"] * n_cells)  # VTK_HEXAHEDRON
    xml = (
        '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" '
        'byte_order="LittleEndian">\n<UnstructuredGrid>\n'
        f'<Piece NumberOfPoints="{nv}" NumberOfCells="{n_cells}">\n'
        f"<Points>{_vtu_array('points', bm.nodes[:nv], 3)}</Points>\n"
        f'<Cells><DataArray type="Int64" Name="connectivity" format="ascii">'
        f"{connectivity}</DataArray>"
        f'<DataArray type="Int64" Name="offsets" format="ascii">{offsets}</DataArray>'
        f'<DataArray type="UInt8" Name="types" format="ascii">{types}</DataArray></Cells>\n'
        f"<PointData>{''.join(arrays)}</PointData>\n"
        "</Piece>\n</UnstructuredGrid>\n</VTKFile>\n"
    )
    with atomic_open(path) as fh:
        fh.write(xml)
    return Path(path)
