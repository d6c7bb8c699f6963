"""Shafts on bearings: Timoshenko beam elements, bearing matrices and the block-diagonal assembly
of a scene's shafts (seed I-3; the 6-DOF shaft nodes of :mod:`._lumped3d` and :mod:`._hybrid`).

Shaft element: 2-node Timoshenko beam (Przemieniecki; shear parameter Φ = 12 E I/(κ G A L²)),
consistent Euler-Bernoulli translational mass plus rotary inertia, axial and torsional bars. The
seed's annex (1.9) has typos; this follows the textbook (Przemieniecki, *Theory of Matrix
Structural Analysis*, 1968, §5.6; Friedman & Kosmatka, Comput. Struct. 47, 1993 for the
shear-deformable stiffness).

Bearings (:class:`Bearing`) tie a shaft node to the ground through a 6×6 stiffness (diagonal
radial/axial/tilt values or a full symmetric matrix, radial–tilt and cross couplings included) and
an optional 6×6 viscous damping, both in the node's DOF order; the damping is assembled into
:meth:`~jaxgear.scenes.LumpedPair.bearing_damping`, which the dynamic model adds to its damping
matrix.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ..bearings import AbstractRollingBearing
from ._structure import Structure

__all__ = [
    "Bearing",
    "Material",
    "ShaftMatrices",
    "ShaftSpec",
    "bearing_dofs",
    "bearing_matrix",
    "shaft_matrices",
    "timoshenko_element",
]



class Material(NamedTuple):
    """The shafts' material (a settings tuple: ``E, nu, rho = material``).

    Attributes:
        youngs_modulus: E (Pa). poisson_ratio: ν (-). density: ρ (kg/m³), also the teeth's on
            a condensed body.
    """

    youngs_modulus: float = 210e9
    poisson_ratio: float = 0.3
    density: float = 7800.0


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
        value: 6 rows of 6 finite numbers (nested lists/tuples or a 2-D array, read row by row
            alike).

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
    rows = [tuple(r) if np.iterable(r) else r for r in value] if np.iterable(value) else [value]
    sizes = [len(r) if np.iterable(r) else "-" for r in rows]
    if sizes != [6] * 6:
        raise ValueError(f"{shape}, got {len(rows)} rows of {sizes} entries")
    entries = [x for r in rows for x in r]
    if any(isinstance(x, (bool, np.bool_)) or not isinstance(x, numbers.Real) for x in entries):
        raise ValueError(f"{shape}, got a non-number entry")
    a = np.array(rows, dtype=float)
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


def _rolling_key(kind) -> tuple | None:
    """A rolling bearing kind as a hashable value (a :class:`Bearing`'s equality and hash):
    its class and each of its fields by name, a number or an array by its shape and values
    (the elements' count, the slices, the geometry and the ratings; None where a rating is not
    given), a kind held inside it (a pair's row) by its own key, a traced value (under ``jit``
    or ``grad``) by its identity. None for no kind."""
    if kind is None:
        return None

    def value(v):
        if v is None or isinstance(v, (bool, int, str)):
            return v
        if isinstance(v, AbstractRollingBearing):
            return _rolling_key(v)
        if isinstance(v, jax.core.Tracer):
            return ("traced", id(v))
        a = np.asarray(v)
        return (a.shape, tuple(a.ravel().tolist()))

    return (type(kind), tuple((f.name, value(getattr(kind, f.name)))
                              for f in dataclasses.fields(kind)))


@dataclasses.dataclass(frozen=True)
class Bearing:
    """A bearing at axial position ``z`` (m): stiffness and damping from a shaft node to the ground.

    The stiffness is either diagonal (``radial``, ``axial``, ``tilt``), a full 6×6 matrix
    (``stiffness``), or a rolling bearing's from its geometry (``rolling``, a
    :class:`jaxgear.bearings.AbstractRollingBearing` kind), never two of them: with
    ``stiffness`` or ``rolling`` given, ``radial``/``axial``/``tilt`` must be left out (they
    stay ``None``). Matrices are in the shaft node's frame, DOF order u_x, u_y, u_z, φ_x, φ_y,
    φ_z (φ_x, φ_y the tilts with du_y/dz = −φ_x, du_x/dz = φ_y), SI per DOF pair, and are
    checked by :func:`bearing_matrix` (symmetric, positive semi-definite, row/column φ_z zero)
    and stored symmetrised as nested tuples (the dataclass stays hashable). Two bearings are
    equal, and hash alike, when their fields are and their rolling kinds are of one class with
    the same static fields and numbers (compared by value, not identity: a scene or a compiled
    program keyed by its bearings sees a different kind as a different bearing).

    A rolling bearing has a stiffness only at an operating point: ``Bearing(z, rolling=kind)``
    holds none (:meth:`stiffness_matrix` refuses it) until :meth:`at` puts it at the ring
    displacement d that carries its load (``operating``; its ``stiffness`` the kind's
    :meth:`~jaxgear.bearings.AbstractRollingBearing.stiffness6` there, the tangent stiffness
    about d). :func:`jaxgear.dynamics.bearings_at_operating_point` finds each rolling
    bearing's operating point from the quasi-static solve of its scene (docs/bearings.md).

    Attributes:
        z: position along the shaft (m).
        radial: stiffness on u_x and u_y (N/m); default 2e8 without ``stiffness``/``rolling``.
        axial: stiffness on u_z (N/m); default 1e8 without ``stiffness``/``rolling``.
        tilt: stiffness on φ_x and φ_y (N·m/rad); default 0 without ``stiffness``/``rolling``.
        stiffness: 6×6 stiffness matrix (N/m between translations, N/rad = N between a
            translation and a rotation, N·m/rad between rotations), or ``None``; with
            ``rolling`` set by :meth:`at` only.
        damping: 6×6 viscous damping matrix (N·s/m, N·s/rad, N·m·s/rad), or ``None`` (none).
        rolling: the rolling bearing kind, or ``None`` (a linear spring).
        operating: with ``rolling``, its operating point d = (δ_x, δ_y, δ_z, γ_x, γ_y) (m,
            rad; the shaft node's displacement relative to the ground, ring displacement of
            :mod:`jaxgear.bearings`), or ``None`` (none yet).

    Raises:
        ValueError: two stiffness forms together; ``rolling`` not a bearing kind; ``operating``
            without ``rolling`` or not 5 finite numbers; a matrix that fails
            :func:`bearing_matrix` (one line each).
    """

    z: float
    radial: float | None = None
    axial: float | None = None
    tilt: float | None = None
    stiffness: tuple | None = None
    damping: tuple | None = None
    # compared by value (an array module has no hash): :meth:`__eq__`, :meth:`__hash__`
    rolling: AbstractRollingBearing | None = dataclasses.field(default=None, compare=False)
    operating: tuple | None = None

    def _key(self) -> tuple:
        """What equality and the hash compare: the compared fields and the rolling kind's
        value (:func:`_rolling_key`, taken once at construction)."""
        return (*(getattr(self, f.name) for f in dataclasses.fields(self) if f.compare),
                self._rolling)

    def __eq__(self, other):
        if other.__class__ is not self.__class__:
            return NotImplemented
        return self._key() == other._key()

    def __hash__(self):
        return hash(self._key())

    def __post_init__(self):
        where = self.where
        if self.rolling is not None and not isinstance(self.rolling, AbstractRollingBearing):
            raise ValueError(
                f"{where}: rolling = {type(self.rolling).__name__}: allowed a "
                "jaxgear.bearings kind (DeepGrooveBall, ..., LinearSpring)"
            )
        object.__setattr__(self, "_rolling", _rolling_key(self.rolling))
        if self.rolling is not None:
            given = [n for n in ("radial", "axial", "tilt") if getattr(self, n) is not None]
            if given:
                raise ValueError(
                    f"{where}: give either radial/axial/tilt or a rolling bearing, not both "
                    f"(got {', '.join(given)} and rolling)"
                )
            if self.operating is None and self.stiffness is not None:
                raise ValueError(f"{where}: a rolling bearing's stiffness comes from its "
                                 "operating point: give operating= (Bearing.at), not stiffness")
            if self.operating is not None:
                d = tuple(float(x) for x in np.ravel(self.operating))
                if len(d) != 5 or not all(math.isfinite(x) for x in d):
                    raise ValueError(f"{where}: operating = {self.operating!r}: allowed 5 finite "
                                     "numbers (δ_x, δ_y, δ_z in m, γ_x, γ_y in rad)")
                object.__setattr__(self, "operating", d)
                if self.stiffness is None:
                    k = np.asarray(self.rolling.stiffness6(np.asarray(d)), float)
                    object.__setattr__(self, "stiffness", k)
        elif self.operating is not None:
            raise ValueError(f"{where}: operating = {self.operating!r} without a rolling "
                             "bearing: allowed None (or give rolling=)")
        elif self.stiffness is None:
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

    @property
    def where(self) -> str:
        """The bearing's name in a message (``Bearing at z = 12 mm``)."""
        return f"Bearing at z = {self.z * 1e3:.6g} mm"

    def at(self, displacement) -> Bearing:
        """This rolling bearing at the operating point ``displacement`` d (5,) (m, rad): its
        ``stiffness`` the kind's tangent stiffness there (``stiffness6(d)``).

        Raises:
            ValueError: not a rolling bearing; d not 5 finite numbers (one line)."""
        if self.rolling is None:
            raise ValueError(f"{self.where}: Bearing.at needs a rolling bearing (rolling=), "
                             "allowed on a bearing from geometry")
        return dataclasses.replace(self, stiffness=None, operating=tuple(
            float(x) for x in np.ravel(np.asarray(displacement, float))))

    def carried(self) -> tuple[bool, ...]:
        """Which of the DOFs u_x, u_y, u_z, φ_x, φ_y the bearing resists: a rolling bearing's
        declaration (:meth:`~jaxgear.bearings.AbstractRollingBearing.carried`), a linear one's
        non-zero diagonal."""
        if self.rolling is not None:
            return tuple(self.rolling.carried())
        return tuple(bool(x > 0) for x in np.diag(self.stiffness_matrix())[:5])

    def holds_tilt(self) -> bool:
        """The bearing holds its shaft against tilting on its own: it resists φ_x and φ_y
        (:meth:`carried`) and, a rolling bearing, its kind declares ``carries_moment`` (a
        :class:`~jaxgear.bearings.TaperedRollerPair`; a single-row kind's tilt stiffness comes
        from its load only, so a shaft on it needs a second radial bearing apart)."""
        c = self.carried()
        return bool(c[3] and c[4] and (self.rolling is None or self.rolling.carries_moment))

    def stiffness_matrix(self) -> np.ndarray:
        """The 6×6 stiffness (SI, node frame): ``stiffness`` or diag(radial, radial, axial,
        tilt, tilt, 0).

        Raises:
            ValueError: a rolling bearing not at an operating point (one line)."""
        if self.stiffness is not None:
            return np.array(self.stiffness)
        if self.rolling is not None:
            raise ValueError(
                f"{self.where}: the rolling bearing {type(self.rolling).__name__} has a "
                "stiffness only at an operating point: allowed Bearing.at(displacement), or "
                "its scene through jaxgear.dynamics.bearings_at_operating_point"
            )
        return np.diag([self.radial, self.radial, self.axial, self.tilt, self.tilt, 0.0])

    def force_rows(self) -> tuple[int, ...]:
        """The translational DOFs (0 u_x, 1 u_y, 2 u_z) whose elastic force k u the assembly
        gives a bearing force row (:attr:`~jaxgear.scenes.Structure.reaction`): the non-zero
        rows of :meth:`stiffness_matrix`'s first three."""
        kb = self.stiffness_matrix()
        return tuple(d for d in range(3) if np.any(kb[d] != 0))

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
        return tuple(np.atleast_1d(np.asarray(self.gear_z, float)).tolist())


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


def shaft_nodes(spec: ShaftSpec, extra_z=()) -> np.ndarray:
    """The node positions (m from the shaft start) of :func:`shaft_matrices`: nodes at the
    shaft ends, the gears, the torque, each bearing and ``extra_z``, each segment refined to
    about ``spec.elements`` elements over the length (positions that differ by rounding only,
    60 + 10 mm against 70 mm, are one node).

    Raises:
        ValueError: a position outside the shaft (mm in the message).
    """
    zs = {0.0, spec.length, *spec.gear_positions, spec.torque_z, *(b.z for b in spec.bearings),
          *extra_z}
    for z in zs:
        if not -1e-12 <= z <= spec.length + 1e-12:
            raise ValueError(
                f"shaft position {z * 1e3:.6g} mm is outside the shaft [0, {spec.length * 1e3:.6g}] mm"
            )
    base = []
    for z in sorted(zs):
        if not base or z - base[-1] > 1e-9 * max(spec.length, 1.0):
            base.append(z)
    nodes = []
    for a, b in zip(base[:-1], base[1:], strict=True):
        k = max(1, round(spec.elements * (b - a) / spec.length))
        nodes.extend(np.linspace(a, b, k + 1)[:-1].tolist())
    nodes.append(base[-1])
    return np.array(nodes)


def node_at(nodes: np.ndarray, z: float) -> int:
    """The index of the node of ``nodes`` (m) nearest the position ``z`` (m)."""
    return int(np.argmin(np.abs(nodes - z)))


def bearing_dofs(shafts, extra_z=None) -> tuple[tuple[int, ...], ...]:
    """Each bearing's node's first DOF in the block-diagonal assembly of ``shafts`` (shaft
    after shaft, 6 DOFs per node; :func:`_shaft_arrays`' order), one tuple per shaft.
    ``extra_z``: more node positions per shaft (m), as given to :func:`_shaft_arrays`."""
    extra_z = extra_z or ((),) * len(shafts)
    out, offset = [], 0
    for spec, z in zip(shafts, extra_z, strict=True):
        nodes = shaft_nodes(spec, z)
        out.append(tuple(offset + 6 * node_at(nodes, b.z) for b in spec.bearings))
        offset += 6 * nodes.size
    return tuple(out)


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
    nodes = shaft_nodes(spec, extra_z)
    n = 6 * nodes.size
    K = np.zeros((n, n))
    M = np.zeros((n, n))
    for e in range(nodes.size - 1):
        ke, me = timoshenko_element(E, G, rho, spec.diameter, nodes[e + 1] - nodes[e])
        sl = slice(6 * e, 6 * e + 12)
        K[sl, sl] += ke
        M[sl, sl] += me
    idx = lambda z: node_at(nodes, z)
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
        for d in b.force_rows():
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
        mount=d.get("mount"),
        mount_offset=d.get("housing_offset", 0),
    )


def _add_gear_body(M: np.ndarray, first: int, mass, inertia) -> None:
    """A rigid gear body (mass (kg), (I_diametral, I_polar) (kg·m²)) on the 6-DOF node whose
    first DOF is ``first`` (in place)."""
    idia, ipol = inertia
    M[first : first + 3, first : first + 3] += mass * np.eye(3)
    M[first + 3, first + 3] += idia
    M[first + 4, first + 4] += idia
    M[first + 5, first + 5] += ipol
