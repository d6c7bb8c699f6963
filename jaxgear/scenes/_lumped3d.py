"""3D lumped-parameter scene: rigid gear nodes on Timoshenko shafts with bearings (seed I-3, (2.9)).

Frame: z along the (parallel) axes, pinion axis through the origin, gear axis through (a_w, 0);
the line of action and the contact points are those of :mod:`._gear_mesh`. Each shaft node has 6
DOF (u_x, u_y, u_z, φ_x, φ_y, φ_z). The approach of cell M is (d1(M) − d2(M))·n with
d_i(M) = u_i + φ_i × (M − O_i) at the gear nodes, i.e. the structure vector

    V(M) = [n, (M − O1) × n, −n, −(M − O2) × n]      (seed (2.9), at the two gear nodes:
                                                      :class:`~jaxgear.scenes.RigidMember`),

and for a pure rotation it reduces to the torsional V = cos β_b (r_b1, −r_b2) with θ1 = φ_z1 and
θ2 = −φ_z2.

Shaft element: 2-node Timoshenko beam (Przemieniecki; shear parameter Φ = 12 E I/(κ G A L²)),
consistent Euler-Bernoulli translational mass plus rotary inertia, axial and torsional bars. The
seed's annex (1.9) has typos; this follows the textbook (Przemieniecki, *Theory of Matrix
Structural Analysis*, 1968, §5.6; Friedman & Kosmatka, Comput. Struct. 47, 1993 for the
shear-deformable stiffness).

Bearings (:class:`Bearing`) tie a shaft node to the ground through a 6×6 stiffness (diagonal
radial/axial/tilt values or a full symmetric matrix, radial–tilt and cross couplings included) and
an optional 6×6 viscous damping, both in the node's DOF order; the damping is assembled into
:meth:`LumpedPair.bearing_damping`, which the dynamic model adds to its damping matrix.
"""

from __future__ import annotations

import dataclasses
import math
from typing import NamedTuple

import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import MeshModel
from .._geometry import GearPair
from ._gear_mesh import GearMesh, line_of_action, mesh_line, pair_mesh
from ._interface import RigidMember
from ._scene import DynamicScene
from ._structure import AssembledScene, Structure
from ._train import GearTrain, mesh_period_ratios, mesh_teeth, scene_span, shaft_torques

__all__ = [
    "Bearing",
    "LumpedPair",
    "ShaftMatrices",
    "ShaftSpec",
    "bearing_matrix",
    "Wrench",
    "lumped_pair",
    "lumped_train",
    "mesh_wrench",
    "shaft_matrices",
    "timoshenko_element",
]


def timoshenko_element(
    E: float, G: float, rho: float, diameter: float, length: float, kappa: float = 0.9
) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and mass (12, 12) of a solid circular shaft element along z.

    DOF order per node: u_x, u_y, u_z, φ_x, φ_y, φ_z (m, rad); node 1 then node 2.
    Bending in the x–z plane uses (u_x, φ_y) with du_x/dz = φ_y, in the y–z plane (u_y, φ_x)
    with du_y/dz = −φ_x.

    Args:
        E, G: Young's and shear moduli (Pa). rho: density (kg/m³). diameter, length: (m).
        kappa: shear coefficient (0.9 for a solid circle, Cowper 6(1+ν)/(7+6ν)).
    """
    L = length
    A = math.pi * diameter**2 / 4
    I = math.pi * diameter**4 / 64
    J = 2 * I
    phi = 12 * E * I / (kappa * G * A * L**2)
    c = E * I / ((1 + phi) * L**3)
    kb = c * np.array(
        [
            [12, 6 * L, -12, 6 * L],
            [6 * L, (4 + phi) * L**2, -6 * L, (2 - phi) * L**2],
            [-12, -6 * L, 12, -6 * L],
            [6 * L, (2 - phi) * L**2, -6 * L, (4 + phi) * L**2],
        ]
    )
    mt = (
        rho
        * A
        * L
        / 420
        * np.array(
            [
                [156, 22 * L, 54, -13 * L],
                [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                [54, 13 * L, 156, -22 * L],
                [-13 * L, -3 * L**2, -22 * L, 4 * L**2],
            ]
        )
    )
    mr = (
        rho
        * I
        / (30 * L)
        * np.array(
            [
                [36, 3 * L, -36, 3 * L],
                [3 * L, 4 * L**2, -3 * L, -(L**2)],
                [-36, -3 * L, 36, -3 * L],
                [3 * L, -(L**2), -3 * L, 4 * L**2],
            ]
        )
    )
    mb = mt + mr
    K = np.zeros((12, 12))
    M = np.zeros((12, 12))
    # bending x–z: (u_x, φ_y) = DOF (0, 4), (6, 10), slope +φ_y
    # bending y–z: (u_y, φ_x) = DOF (1, 3), (7, 9), slope −φ_x
    for idx, sign in (((0, 4, 6, 10), 1.0), ((1, 3, 7, 9), -1.0)):
        s = np.diag([1.0, sign, 1.0, sign])
        K[np.ix_(idx, idx)] += s @ kb @ s
        M[np.ix_(idx, idx)] += s @ mb @ s
    bar = np.array([[1.0, -1.0], [-1.0, 1.0]])
    bar_m = np.array([[2.0, 1.0], [1.0, 2.0]]) / 6
    for idx, k, m in (((2, 8), E * A / L, rho * A * L), ((5, 11), G * J / L, rho * J * L)):
        K[np.ix_(idx, idx)] += k * bar
        M[np.ix_(idx, idx)] += m * bar_m
    return K, M


BEARING_DOFS = ("ux", "uy", "uz", "rx", "ry", "rz")
BEARING_RTOL = 1e-6  # relative tolerance of the symmetry and semi-definiteness checks


def bearing_matrix(value) -> np.ndarray:
    """A bearing's 6×6 stiffness or damping matrix, checked and symmetrised ((K + Kᵀ)/2).

    DOF order u_x, u_y, u_z, φ_x, φ_y, φ_z of the shaft node (SI per DOF pair: N/m, N/rad,
    N·m/rad for a stiffness; N·s/m, N·s/rad, N·m·s/rad for a damping).

    Args:
        value: 6 rows of 6 finite numbers (nested lists/tuples or an array).

    Returns:
        The symmetrised matrix, shape (6, 6), float64.

    Raises:
        ValueError: one line without a key path (the caller adds it): not 6×6 finite numbers;
            not symmetric (|K_ij − K_ji| > 1e-6 max(|K_ij|, |K_ji|, √(K_ii K_jj))); row or column
            φ_z (rz) not zero (a bearing carries no torque about the shaft axis: the drive
            rotation must stay free); not positive semi-definite (a negative diagonal, a zero
            diagonal with a non-zero entry in its row, or a smallest eigenvalue of the diagonally
            scaled K_ij/√(K_ii K_jj) below −1e-6: a test independent of the mixed units).
    """
    shape = "must be 6 rows of 6 finite numbers (SI; DOF order ux, uy, uz, rx, ry, rz)"
    if isinstance(value, (list, tuple)):
        if len(value) != 6 or any(not isinstance(r, (list, tuple)) or len(r) != 6 for r in value):
            sizes = [len(r) if isinstance(r, (list, tuple)) else "-" for r in value]
            raise ValueError(f"{shape}, got {len(value)} rows of {sizes} entries")
        if any(isinstance(x, bool) or not isinstance(x, (int, float)) for r in value for x in r):
            raise ValueError(f"{shape}, got a non-number entry")
        a = np.array(value, dtype=float)
    else:
        a = np.asarray(value)
        if a.dtype.kind not in "iuf" or a.shape != (6, 6):
            raise ValueError(f"{shape}, got shape {a.shape} of {a.dtype}")
        a = a.astype(float)
    if not np.all(np.isfinite(a)):
        i, j = np.argwhere(~np.isfinite(a))[0]
        raise ValueError(f"{shape}, got [{i}][{j}] = {a[i, j]}")
    d = np.diag(a)
    scale = np.maximum(np.maximum(np.abs(a), np.abs(a.T)), np.sqrt(np.abs(np.outer(d, d))))
    excess = np.abs(a - a.T) - BEARING_RTOL * scale
    if np.any(excess > 0):
        i, j = np.unravel_index(np.argmax(excess), a.shape)
        raise ValueError(
            f"not symmetric: [{i}][{j}] = {a[i, j]:.6g} but [{j}][{i}] = {a[j, i]:.6g} (allowed "
            f"|K_ij - K_ji| <= {BEARING_RTOL:g} max(|K_ij|, |K_ji|, sqrt(K_ii K_jj)))"
        )
    a = 0.5 * (a + a.T)
    if np.any(a[5] != 0):
        j = int(np.flatnonzero(a[5])[0])
        raise ValueError(
            f"row and column 5 (rz) must be 0, got [5][{j}] = {a[5, j]:.6g} (a bearing carries "
            "no torque about the shaft axis: the drive rotation stays free)"
        )
    d = np.diag(a)
    if np.any(d < 0):
        i = int(np.flatnonzero(d < 0)[0])
        raise ValueError(
            f"not positive semi-definite: [{i}][{i}] = {d[i]:.6g} (allowed diagonal >= 0)"
        )
    for i in np.flatnonzero(d == 0):
        if np.any(a[i] != 0):
            j = int(np.flatnonzero(a[i])[0])
            raise ValueError(
                f"not positive semi-definite: [{i}][{i}] = 0 but [{i}][{j}] = {a[i, j]:.6g} "
                "(allowed |K_ij| <= sqrt(K_ii K_jj))"
            )
    pos = d > 0
    if np.any(pos):
        s = 1.0 / np.sqrt(d[pos])
        lam = float(np.linalg.eigvalsh(a[np.ix_(pos, pos)] * np.outer(s, s)).min())
        if lam < -BEARING_RTOL:
            raise ValueError(
                "not positive semi-definite: smallest eigenvalue of K_ij/sqrt(K_ii K_jj) is "
                f"{lam:.6g} (allowed >= {-BEARING_RTOL:g})"
            )
    return a


def _as_tuple(a: np.ndarray) -> tuple:
    return tuple(tuple(float(x) for x in row) for row in a)


@dataclasses.dataclass(frozen=True)
class Bearing:
    """A bearing at axial position ``z`` (m): stiffness and damping from a shaft node to the ground.

    The stiffness is either diagonal (``radial``, ``axial``, ``tilt``) or a full 6×6 matrix
    (``stiffness``), never both: with ``stiffness`` given, ``radial``/``axial``/``tilt`` must be
    left out (they stay ``None``). Matrices are in the shaft node's frame, DOF order u_x, u_y, u_z,
    φ_x, φ_y, φ_z (φ_x, φ_y the tilts with du_y/dz = −φ_x, du_x/dz = φ_y), SI per DOF pair, and
    are checked by :func:`bearing_matrix` (symmetric, positive semi-definite, row/column φ_z
    zero) and stored symmetrised as nested tuples (the dataclass stays hashable).

    Attributes:
        z: position along the shaft (m).
        radial: stiffness on u_x and u_y (N/m); default 2e8 without ``stiffness``.
        axial: stiffness on u_z (N/m); default 1e8 without ``stiffness``.
        tilt: stiffness on φ_x and φ_y (N·m/rad); default 0 without ``stiffness``.
        stiffness: 6×6 stiffness matrix (N/m between translations, N/rad = N between a
            translation and a rotation, N·m/rad between rotations), or ``None``.
        damping: 6×6 viscous damping matrix (N·s/m, N·s/rad, N·m·s/rad), or ``None`` (none).

    Raises:
        ValueError: ``stiffness`` together with ``radial``/``axial``/``tilt``; a matrix that
            fails :func:`bearing_matrix`.
    """

    z: float
    radial: float | None = None
    axial: float | None = None
    tilt: float | None = None
    stiffness: tuple | None = None
    damping: tuple | None = None

    def __post_init__(self):
        where = f"Bearing at z = {self.z * 1e3:.6g} mm"
        if self.stiffness is None:
            for name, default in (("radial", 2e8), ("axial", 1e8), ("tilt", 0.0)):
                if getattr(self, name) is None:
                    object.__setattr__(self, name, default)
        else:
            given = [n for n in ("radial", "axial", "tilt") if getattr(self, n) is not None]
            if given:
                raise ValueError(
                    f"{where}: give either radial/axial/tilt or a stiffness matrix, not both "
                    f"(got {', '.join(given)} and stiffness)"
                )
        for name in ("stiffness", "damping"):
            value = getattr(self, name)
            if value is None:
                continue
            try:
                a = bearing_matrix(value)
            except ValueError as err:
                raise ValueError(f"{where}: {name} {err}") from None
            object.__setattr__(self, name, _as_tuple(a))

    def stiffness_matrix(self) -> np.ndarray:
        """The 6×6 stiffness (SI, node frame): ``stiffness`` or diag(radial, radial, axial,
        tilt, tilt, 0)."""
        if self.stiffness is not None:
            return np.array(self.stiffness)
        return np.diag([self.radial, self.radial, self.axial, self.tilt, self.tilt, 0.0])

    def damping_matrix(self) -> np.ndarray:
        """The 6×6 damping (SI, node frame); zeros without ``damping``."""
        return np.zeros((6, 6)) if self.damping is None else np.array(self.damping)


@dataclasses.dataclass(frozen=True)
class ShaftSpec:
    """A solid shaft along z from 0 to ``length`` (m), diameter (m), gear centre at ``gear_z``
    (m; a train's shaft carrying several gears: a tuple of their centres, in gear order),
    bearings, and the torque node (input for the pinion, output for the gear) at ``torque_z``."""

    length: float
    diameter: float
    gear_z: float | tuple
    bearings: tuple[Bearing, ...]
    torque_z: float = 0.0
    elements: int = 4

    @property
    def gear_positions(self) -> tuple:
        """The centres of the shaft's gears (m from the shaft start), in gear order."""
        return tuple(self.gear_z) if isinstance(self.gear_z, tuple) else (self.gear_z,)


class LumpedPair(AssembledScene, DynamicScene):
    """Two shafts with rigid gear nodes and bearings (build with :func:`lumped_pair`).

    Attributes:
        structure: the assembled shafts, bearings and gear bodies
            (:class:`~jaxgear.scenes.Structure`; its parts ``pinion_shaft``, ``gear_shaft``,
            ``bearings``).
        meshes: the gear meshes (:class:`~jaxgear.scenes.GearMesh`).
        members: the gear members (pinion, gear), :class:`~jaxgear.scenes.RigidMember`.
        rigid: the rigid-body rotation mode (n,) (V·r = 0, F·r = 0).
    """

    rigid: Float[Array, " n"]

    def rigid_modes(self):
        return self.rigid[:, None]


class ShaftMatrices(NamedTuple):
    """One shaft's FE model on its own 6 DOFs per node (u_x, u_y, u_z, φ_x, φ_y, φ_z), before
    assembly (:func:`shaft_matrices`).

    Attributes:
        nodes: node positions along the shaft (m from its start), (k,).
        K, M: Timoshenko stiffness and consistent mass, (6k, 6k) (N/m, N, N·m/rad; kg, kg·m).
        K_bearing, C_bearing: the bearings' 6×6 stiffness and damping at their nodes, (6k, 6k).
        gear_node, torque_node: node index of the (first) gear and of the external torque.
        reactions: ((name, row (6k,)), ...): the bearing force components k u (N), the
            translational rows of each bearing's stiffness.
        gear_nodes: node index of each gear (:attr:`ShaftSpec.gear_positions`).
    """

    nodes: np.ndarray
    K: np.ndarray
    M: np.ndarray
    K_bearing: np.ndarray
    gear_node: int
    torque_node: int
    reactions: list
    C_bearing: np.ndarray
    gear_nodes: tuple = ()


def shaft_matrices(spec: ShaftSpec, E, G, rho, extra_z=()) -> ShaftMatrices:
    """The FE model of one shaft: Timoshenko elements (:func:`timoshenko_element`) between nodes
    at the shaft ends, the gear, the torque, each bearing and ``extra_z`` (m from the shaft
    start), each segment refined to about ``spec.elements`` elements over the length, plus its
    bearings.

    Args:
        spec: the shaft. E, G: Young's and shear moduli (Pa). rho: density (kg/m³).
        extra_z: more node positions (m), for example where a condensed body's bearing nodes
            attach.

    Raises:
        ValueError: a position outside the shaft (mm in the message).
    """
    gears = spec.gear_positions
    zs = {0.0, spec.length, *gears, spec.torque_z, *(b.z for b in spec.bearings), *extra_z}
    for z in zs:
        if not -1e-12 <= z <= spec.length + 1e-12:
            raise ValueError(
                f"shaft position {z * 1e3:.6g} mm is outside the shaft [0, {spec.length * 1e3:.6g}] mm"
            )
    # refine every segment into about `elements` elements over the whole length; positions that
    # differ by rounding only (60 + 10 mm vs 70 mm) are one node
    base = []
    for z in sorted(zs):
        if not base or z - base[-1] > 1e-9 * max(spec.length, 1.0):
            base.append(z)
    nodes = []
    for a, b in zip(base[:-1], base[1:], strict=True):
        k = max(1, round(spec.elements * (b - a) / spec.length))
        nodes.extend(np.linspace(a, b, k + 1)[:-1].tolist())
    nodes.append(base[-1])
    nodes = np.array(nodes)
    n = 6 * nodes.size
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    for e in range(nodes.size - 1):
        ke, me = timoshenko_element(E, G, rho, spec.diameter, nodes[e + 1] - nodes[e])
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += ke
        M[sl, sl] += me
    idx = lambda z: int(np.argmin(np.abs(nodes - z)))
    # bearings: the 6×6 stiffness and damping on the node's DOFs; the force rows are the
    # translational rows of the stiffness (elastic force k u, couplings to the tilts included)
    Kb = np.zeros((n, n))
    Cb = np.zeros((n, n))
    rows = []
    for b in spec.bearings:
        sl = slice(6 * idx(b.z), 6 * idx(b.z) + 6)
        kb = b.stiffness_matrix()
        Kb[sl, sl] += kb
        Cb[sl, sl] += b.damping_matrix()
        for d in range(3):
            if np.any(kb[d] != 0):
                r = np.zeros(n)
                r[sl] = kb[d]
                rows.append((f"z={b.z * 1e3:g}mm F{'xyz'[d]}", r))
    gear_nodes = tuple(idx(z) for z in gears)
    return ShaftMatrices(nodes, K, M, Kb, gear_nodes[0], idx(spec.torque_z), rows, Cb, gear_nodes)


def _shaft_arrays(shafts, names, E: float, nu: float, rho: float, extra_z=None) -> dict:
    """The shafts of a scene assembled block-diagonally, shaft after shaft (NumPy): their FE
    models (:func:`shaft_matrices`), the bearings and the bearing force rows.

    Args:
        shafts: the :class:`ShaftSpec` of each shaft. names: each shaft's name (the stiffness
            part ``<name>_shaft`` and the prefix of its bearing force names).
        E, nu, rho: shaft material (Pa, -, kg/m³). extra_z: more node positions per shaft (m).

    Returns:
        dict of ``M`` (n, n); ``parts`` (shafts + 1, n, n): each shaft's stiffness, then the
        bearings'; ``bearing_C`` (n, n); ``reaction`` (r, n), ``reaction_names``,
        ``reaction_member`` (each row's shaft); ``mats`` (each shaft's :class:`ShaftMatrices`);
        ``shaft_offsets`` (each shaft's first DOF); ``shaft_z`` (each shaft's node positions).
    """
    G = E / (2 * (1 + nu))
    extra_z = extra_z or ((),) * len(shafts)
    mats = [shaft_matrices(s, E, G, rho, z) for s, z in zip(shafts, extra_z, strict=True)]
    sizes = [6 * m.nodes.size for m in mats]
    offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
    n = int(offsets[-1])
    M = np.zeros((n, n))
    parts = np.zeros((len(shafts) + 1, n, n))
    Cb = np.zeros((n, n))
    reaction, reaction_names, member = [], [], []
    for i, (m, name) in enumerate(zip(mats, names, strict=True)):
        sl = slice(offsets[i], offsets[i + 1])
        M[sl, sl] = m.M
        parts[i][sl, sl] = m.K
        parts[-1][sl, sl] = m.K_bearing
        Cb[sl, sl] = m.C_bearing
        for label, r in m.reactions:
            full = np.zeros(n)
            full[sl] = r
            reaction.append(full)
            reaction_names.append(f"{name} {label}")
            member.append(i)
    return dict(
        M=M,
        parts=parts,
        bearing_C=Cb,
        reaction=np.array(reaction).reshape(-1, n),
        reaction_names=tuple(reaction_names),
        reaction_member=tuple(member),
        mats=mats,
        shaft_offsets=tuple(int(o) for o in offsets[:-1]),
        shaft_z=tuple(m.nodes for m in mats),
    )


def _shaft_structure(d: dict, part_names: tuple, nodes: tuple) -> Structure:
    """The :class:`Structure` of :func:`_shaft_arrays`' parts (rigid-node scenes in the fixed
    frame: no rotating-frame terms)."""
    n = d["M"].shape[0]
    zeros = jnp.zeros((n, n))
    return Structure(
        K=jnp.asarray(d["parts"].sum(axis=0)),
        M=jnp.asarray(d["M"]),
        parts_K=jnp.asarray(d["parts"]),
        C_bearing=jnp.asarray(d["bearing_C"]),
        reaction=jnp.asarray(d["reaction"]),
        gyroscopic=zeros,
        spin_stiffness=zeros,
        f_centrifugal=jnp.zeros(n),
        part_names=part_names,
        reaction_names=d["reaction_names"],
        reaction_member=d["reaction_member"],
        nodes=nodes,
    )


def _add_gear_body(M: np.ndarray, first: int, mass, inertia) -> None:
    """A rigid gear body (mass (kg), (I_diametral, I_polar) (kg·m²)) on the 6-DOF node whose
    first DOF is ``first`` (in place)."""
    idia, ipol = inertia
    M[first : first + 3, first : first + 3] += mass * np.eye(3)
    M[first + 3, first + 3] += idia
    M[first + 4, first + 4] += idia
    M[first + 5, first + 5] += ipol


def _lumped_arrays(
    pair: GearPair,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    masses,
    inertias,
    E: float,
    nu: float,
    rho: float,
    extra_z=((), ()),
) -> dict:
    """NumPy parts of the lumped pair (shared by :func:`lumped_pair` and the hybrid scene):
    :func:`_shaft_arrays` of the two shafts ``pinion`` and ``gear``, the gear bodies and the
    pair's rigid rotation.

    ``extra_z``: additional shaft node positions per shaft (m from the shaft start), e.g. where a
    condensed body's bearing nodes attach. A member whose mass is ``None`` gets no rigid gear
    body at its gear node (a condensed body replaces it).
    """
    d = _shaft_arrays((pinion_shaft, gear_shaft), ("pinion", "gear"), E, nu, rho, extra_z)
    s1, s2 = d["mats"]
    n1 = d["shaft_offsets"][1]
    n = d["M"].shape[0]
    g1, g2 = 6 * s1.gear_node, n1 + 6 * s2.gear_node
    for g, m, inertia in ((g1, masses[0], inertias[0]), (g2, masses[1], inertias[1])):
        if m is not None:
            _add_gear_body(d["M"], g, m, inertia)
    rigid = np.zeros(n)
    rigid[5:n1:6] = 1.0 / pair.base_radii[0]
    rigid[n1 + 5 :: 6] = -1.0 / pair.base_radii[1]
    return dict(
        d,
        rigid=rigid,
        gear_dofs=(g1, g2),  # first DOF of each gear node
        nodes=(
            ("pinion", g1),
            ("gear", g2),
            ("input", 6 * s1.torque_node),
            ("output", n1 + 6 * s2.torque_node),
        ),
    )


def lumped_pair(
    pair: GearPair,
    mesh: MeshModel,
    pinion_shaft: ShaftSpec,
    gear_shaft: ShaftSpec,
    *,
    masses: tuple[float, float],
    inertias: tuple[tuple[float, float], ...],
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    density: float = 7800.0,
) -> LumpedPair:
    """Assemble the 3D lumped scene.

    Args:
        pair, mesh: the gear pair and its mesh model.
        pinion_shaft, gear_shaft: :class:`ShaftSpec` of each shaft (z from the shaft start).
        masses: gear body masses (kg), added at the gear nodes.
        inertias: ((I_diametral, I_polar) pinion, (…) gear) (kg·m²) of the gear bodies.
        youngs_modulus, poisson_ratio, density: shaft material.
    """
    d = _lumped_arrays(
        pair, pinion_shaft, gear_shaft, masses, inertias, youngs_modulus, poisson_ratio, density
    )
    line = line_of_action(pair)
    members = tuple(
        RigidMember(line["centres"][m], tuple(range(g, g + 6)))
        for m, g in enumerate(d["gear_dofs"])
    )
    n = d["M"].shape[0]
    # angular TE at the gear bodies, cos β_b (r_b1 φ_z1 + r_b2 φ_z2) (the gear turns about −z)
    te = np.zeros(n)
    cb = math.cos(pair.base_helix_angle)
    te[members[0].dofs[5]], te[members[1].dofs[5]] = (
        cb * pair.base_radii[0],
        cb * pair.base_radii[1],
    )
    # input torque about +z on the pinion shaft; the load resists the gear's −z rotation
    t_in, t_out = (dict(d["nodes"])[k] + 5 for k in ("input", "output"))
    f_torque = np.zeros(n)
    f_torque[t_in] += 1.0
    f_torque[t_out] += pair.base_radii[1] / pair.base_radii[0]
    structure = _shaft_structure(d, ("pinion_shaft", "gear_shaft", "bearings"), d["nodes"])
    return LumpedPair(
        structure=structure,
        meshes=(pair_mesh(mesh, line, te),),
        members=members,
        f_torque=jnp.asarray(f_torque),
        rigid=jnp.asarray(d["rigid"]),
    )


@dataclasses.dataclass(frozen=True)
class Wrench:
    """An external force and moment on a shaft node, per unit input torque (the loads of a
    train scale with its input torque, as its output torques do).

    Attributes:
        shaft: the shaft's index. z: the node's position along the shaft (m from its start).
        force: (F_x, F_y, F_z) per unit input torque (N per N·m), fixed frame.
        moment: (M_x, M_y, 0) per unit input torque (N·m per N·m), fixed frame. A torque about
            the shaft axis is an output torque (a share of the input power), not a wrench.

    Raises:
        ValueError: a moment about the shaft axis, or a non-finite component.
    """

    shaft: int
    z: float
    force: tuple = (0.0, 0.0, 0.0)
    moment: tuple = (0.0, 0.0, 0.0)

    def __post_init__(self):
        f, m = (tuple(float(v) for v in x) for x in (self.force, self.moment))
        if len(f) != 3 or len(m) != 3 or not all(math.isfinite(v) for v in f + m):
            raise ValueError(f"Wrench: force {f} and moment {m} must be 3 finite numbers each")
        if m[2] != 0.0:
            raise ValueError(
                f"Wrench: moment z = {m[2]:.6g} must be 0 (a torque about the shaft axis is an "
                "output torque: a share of the input power)"
            )
        object.__setattr__(self, "force", f)
        object.__setattr__(self, "moment", m)


def mesh_wrench(line: dict, base_plane: MeshModel, normal_force: float, centre) -> tuple:
    """The mean mesh force on a mesh's driving gear as a wrench at its centre (NumPy): the force
    −F_n n acting at the centre of the contact zone (:func:`~jaxgear.scenes.mesh_line`), which
    an engineer puts in place of a stage left out of a model (the seed, III-3.1: the low-speed
    stage as external forces and couples on the intermediate shaft).

    Args:
        line: the mesh's :func:`line_of_action` (as placed). base_plane: its mesh model.
        normal_force: F_n (N). centre: the driving gear's centre (m), (3,).

    Returns:
        (force (3,) in N, moment (3,) in N·m about ``centre``, its z component the torque
        −F_n cos β_b r_b1 (the driving gear's input torque reacted), fixed frame).
    """
    zone = np.asarray(
        mesh_line(
            line["tangent_point"],
            line["direction"],
            line["normal"],
            line["roll_start"],
            base_plane,
        )["zone"]
    )
    force = -normal_force * np.asarray(line["normal"], float)
    return force, np.cross(zone - np.asarray(centre, float), force)


def lumped_train(
    meshes,
    layout,
    shafts: tuple,
    gear_shafts: tuple,
    *,
    masses,
    inertias,
    shares=None,
    wrenches: tuple = (),
    shaft_names: tuple | None = None,
    youngs_modulus: float = 210e9,
    poisson_ratio: float = 0.3,
    density: float = 7800.0,
):
    """A lumped 3D gear train: parallel shafts on bearings carrying rigid gear nodes, one mesh
    per pair of gears in contact (seed I-3 and (2.9) with several meshes).

    Each shaft is a Timoshenko beam (:func:`shaft_matrices`) on its bearings, along +z through
    its gears' centre in the layout; its gears sit at their positions along it
    (:attr:`ShaftSpec.gear_positions`) and each mesh's cells act on the two gear nodes through
    V = [n, (M − O) × n] (:class:`~jaxgear.scenes.RigidMember`) on the mesh's line of action
    with its helix hands (:func:`~jaxgear.scenes.train_layout`). The input torque acts at the
    input shaft's torque node, each loaded shaft's and the balancing output's at theirs
    (:func:`~jaxgear.scenes.shaft_torques`), each about the shaft's sense of rotation; wrenches
    add forces and tilting moments at shaft nodes.

    Args:
        meshes: ((mesh model, (driving gear, driven gear)), ...), gear indices 0 … n−1 (gear 0
            the input), listed from the input outwards, each model with its driving gear as
            pinion.
        layout: the train's :class:`~jaxgear.scenes.TrainLayout` (centres, spins, lines with
            their hands, phases, speed ratios).
        shafts: each shaft's :class:`ShaftSpec` (shaft 0 the input's), its ``gear_z`` the
            positions of its gears in gear order.
        gear_shafts: each gear's shaft, (n,).
        masses: each gear body's mass (kg), (n,). inertias: each gear body's (I_diametral,
            I_polar) (kg·m²), (n,).
        shares: ``{shaft: share of the input power}`` (:func:`shaft_torques`).
        wrenches: :class:`Wrench` loads (per unit input torque).
        shaft_names: each shaft's name (bearing force names, stiffness parts); default
            ``shaft<i>``.
        youngs_modulus, poisson_ratio, density: shaft material.

    Returns:
        a :class:`~jaxgear.scenes.GearTrain` of 6 DOFs per shaft node.

    Raises:
        ValueError: gears and shafts that do not match (a shaft's ``gear_z`` count against its
            gears), a wrench on no shaft, or what :func:`shaft_speeds`, :func:`shaft_torques`
            and :func:`scene_span` refuse.
    """
    t = _train_arrays(
        meshes,
        layout,
        shafts,
        gear_shafts,
        masses,
        inertias,
        shares,
        wrenches,
        shaft_names,
        (youngs_modulus, poisson_ratio, density),
    )
    d, first, n = t["d"], t["first"], t["d"]["M"].shape[0]
    offsets, mats = d["shaft_offsets"], d["mats"]
    rb0 = float(meshes[0][0].base_radius_pinion)
    rigid = np.zeros(n)
    for i in range(len(shafts)):
        rigid[offsets[i] + 5 : offsets[i] + 6 * mats[i].nodes.size : 6] = (
            t["spins"][i] * t["omega"][i] / rb0
        )
    members = tuple(
        RigidMember(layout.centres[g], tuple(range(first[g], first[g] + 6)))
        for g in range(len(gear_shafts))
    )
    structure = _shaft_structure(
        d, (*(f"{name}_shaft" for name in t["names"]), "bearings"), t["nodes"]
    )
    return GearTrain(
        structure=structure,
        meshes=train_meshes(meshes, layout, first, n),
        members=members,
        f_torque=jnp.asarray(t["f_torque"]),
        rigid=jnp.asarray(rigid),
        periods=t["periods"],
        period_ratios=t["period_ratios"],
    )


def _train_arrays(
    meshes,
    layout,
    shafts,
    gear_shafts,
    masses,
    inertias,
    shares,
    wrenches,
    shaft_names,
    material,
    bodies_z=None,
) -> dict:
    """The NumPy parts of a lumped 3D train shared by :func:`lumped_train` and the hybrid train
    (:func:`~jaxgear.scenes.hybrid_train`): the shafts with a node at each wrench and each
    condensed body's bearing node (``bodies_z``: more positions per shaft), a rigid disc at each
    gear whose mass is not ``None``, each gear node's first DOF, the loads per unit input torque
    (shaft torques and wrenches), the structure's named nodes and the scene span.

    Returns:
        dict of ``d`` (:func:`_shaft_arrays`), ``names``, ``on`` (each shaft's gears),
        ``first``, ``f_torque`` (shaft DOFs), ``out`` (the balancing output's shaft),
        ``spins`` and ``omega`` (each shaft's sense and speed per unit input speed),
        ``nodes``, ``periods``, ``period_ratios``.

    Raises:
        ValueError: gears and shafts that do not match, a wrench on no shaft, or what
            :func:`shaft_torques` and :func:`scene_span` refuse.
    """
    n_shafts = len(shafts)
    names = shaft_names or tuple(f"shaft{i}" for i in range(n_shafts))
    on = [[g for g, s in enumerate(gear_shafts) if s == i] for i in range(n_shafts)]
    for i, spec in enumerate(shafts):
        if len(spec.gear_positions) != len(on[i]):
            raise ValueError(
                f"shaft {names[i]!r}: {len(spec.gear_positions)} gear positions for its "
                f"{len(on[i])} gears {on[i]}"
            )
    for w in wrenches:
        if not 0 <= w.shaft < n_shafts:
            raise ValueError(f"Wrench: shaft {w.shaft} does not exist (0 to {n_shafts - 1})")
    bodies_z = bodies_z or ((),) * n_shafts
    extra = tuple((*(w.z for w in wrenches if w.shaft == i), *bodies_z[i]) for i in range(n_shafts))
    d = _shaft_arrays(shafts, names, *material, extra)
    offsets, mats = d["shaft_offsets"], d["mats"]
    first = [None] * len(gear_shafts)  # each gear node's first DOF
    for i, gears in enumerate(on):
        for g, node in zip(gears, mats[i].gear_nodes, strict=True):
            first[g] = offsets[i] + 6 * node
            if masses[g] is not None:
                _add_gear_body(d["M"], first[g], masses[g], inertias[g])
    links = [(gear_shafts[g], gear_shafts[h]) for _, (g, h) in meshes]
    omega = [float(layout.ratios[on[i][0]]) for i in range(n_shafts)]
    spins = [float(layout.spins[on[i][0]]) for i in range(n_shafts)]
    torques, out = shaft_torques(links, omega, shares)
    n = d["M"].shape[0]
    f_torque = np.zeros(n)
    for i, t in torques.items():
        f_torque[offsets[i] + 6 * mats[i].torque_node + 5] += spins[i] * t
    for w in wrenches:
        node = offsets[w.shaft] + 6 * int(np.argmin(np.abs(mats[w.shaft].nodes - w.z)))
        f_torque[node : node + 3] += w.force
        f_torque[node + 3 : node + 6] += w.moment
    # from the tooth counts (layout.ratios are ratios of them): exact in float32 too
    periods = [
        2.0 * math.pi / mesh_teeth(plane)[0] / float(layout.ratios[g]) for plane, (g, _) in meshes
    ]
    nodes = (
        ("input", offsets[0] + 6 * mats[0].torque_node),
        ("output", offsets[out] + 6 * mats[out].torque_node),
        *((f"gear{g}", first[g]) for g in range(len(gear_shafts))),
    )
    return dict(
        d=d,
        names=names,
        on=on,
        first=first,
        f_torque=f_torque,
        out=out,
        spins=spins,
        omega=omega,
        nodes=nodes,
        periods=scene_span(periods),
        period_ratios=mesh_period_ratios(periods),
    )


def train_meshes(meshes, layout, first, n: int) -> tuple:
    """Each mesh of a train as a :class:`~jaxgear.scenes.GearMesh` on its line of action, with
    its phase, speed ratio, axial sense and TE vector cos β_b (r_b1 θ_g − r_b2 θ_h) (n,) at the
    gear nodes (``first``: each gear node's first DOF; θ = spin φ_z)."""
    out = []
    for k, (plane, (g, h)) in enumerate(meshes):
        line = layout.lines[k]
        cb = math.cos(float(plane.base_helix_angle))
        te = np.zeros(n)
        te[first[g] + 5] = cb * float(plane.base_radius_pinion) * layout.spins[g]
        te[first[h] + 5] = -cb * float(plane.base_radius_gear) * layout.spins[h]
        out.append(
            GearMesh(
                plane,
                line["tangent_point"],
                line["direction"],
                line["normal"],
                line["roll_start"],
                te,
                gears=(g, h),
                ratio=float(layout.ratios[g]),
                phase=float(layout.phases[k]),
                axial=line["axial"],
            )
        )
    return tuple(out)
