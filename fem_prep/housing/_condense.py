"""The housing condensed at its bearing seats: couplings, clamped feet, Craig–Bampton with the
fixed-interface modes below a cut-off frequency, the cache, receptances and the VTU.

Each seat is a 6-DOF master node (u_x, u_y, u_z, theta_x, theta_y, theta_z) at the seat centre,
coupled to the FE nodes of its bore facets by the gear bodies' bearing couplings
(:class:`~fem_prep.Rigid`: the bore follows the master rigidly; :class:`~fem_prep.Averaging`:
RBE3-like, the master is the least-squares rigid fit of the bore), through the same transformation
``u_full = T q`` (:func:`fem_prep.couple_masters`). The feet's FE nodes are held at zero.

Craig–Bampton ([CRA68], seed (2.3)): ``u = [I 0; G_ib Phi_i] [u_b; q]`` with the static constraint
modes ``G_ib = -K_ii^-1 K_ib`` of the seat masters and every fixed-interface mode ``Phi_i`` (seats
held) whose frequency lies at or below the cut-off ``f_c``. Below ``f_c`` the truncation error of
the seats' receptance is of the order of the dropped modes' share times ``(f / f_k)^2 / (1 - (f /
f_k)^2)`` for the first dropped mode ``f_k > f_c``; the default rule ``f_c = 1.5 x`` the highest
mesh-order frequency (:func:`housing_cutoff_hz`) keeps every housing resonance the meshes can
excite and the first one above them.
"""

from __future__ import annotations

import dataclasses
import hashlib
import math
import time
import warnings
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from tqdm import tqdm

from .._assemble import Operators, assemble_operators
from .._body import Material
from .._condense import Condensed, CraigBampton, condense
from .._couplings import Coupled, MasterSet, Nodal, Rigid, couple_masters
from .._fe_cache import cache_key, load_entry, store_entry, table_dir
from .._kinds import BearingCoupling
from .._solver import (
    SolverError,
    SolverWarning,
    _optional_module,
    _pardiso_solver,
    blas_threads,
    eigenvalue_count,
    factorize,
    phase_bar,
    shift_invert_modes,
)
from ..files import atomic_write
from ..resources import check_memory
from ._estimate import MAX_HOUSING_MODES, check_housing_modes, condensation_bytes
from ._mesh import HousingMesh

__all__ = [
    "CondensedHousing",
    "PreparedHousing",
    "condensed_housing",
    "housing_cutoff_hz",
    "prepare_housing",
    "write_housing_vtu",
]

#: bump when what a cached housing holds changes
HOUSING_FORMAT = 1


def housing_cutoff_hz(highest_mesh_frequency_hz: float, factor: float = 1.5) -> float:
    """The default cut-off of the housing's interior modes: ``factor`` (1.5) times the highest
    mesh-order frequency (Hz) of the speed range: every housing resonance the meshes
    can excite is kept, and the first one above them.

    Raises:
        ValueError: a non-positive frequency or a factor < 1.
    """
    f = highest_mesh_frequency_hz
    if not (isinstance(f, (int, float)) and math.isfinite(f) and f > 0):
        raise ValueError(f"highest_mesh_frequency_hz = {f!r}, allowed > 0 (Hz)")
    if not (isinstance(factor, (int, float)) and math.isfinite(factor) and factor >= 1):
        raise ValueError(f"factor = {factor!r}, allowed >= 1")
    return float(factor * f)


def _omega2(f_hz) -> np.ndarray:
    f = np.atleast_1d(np.asarray(f_hz, dtype=float))
    if f.ndim != 1 or not np.all(np.isfinite(f)) or np.any(f < 0):
        raise ValueError(f"frequencies = {f_hz!r}, allowed finite values >= 0 (Hz)")
    return (2 * math.pi * f) ** 2


def _check_loss(loss_factor) -> float:
    if not (
        isinstance(loss_factor, (int, float)) and math.isfinite(loss_factor) and loss_factor >= 0
    ):
        raise ValueError(f"loss_factor = {loss_factor!r}, allowed >= 0")
    return float(loss_factor)


@dataclass(frozen=True)
class CondensedHousing:
    """A housing condensed at its seats (what the cache holds).

    Attributes:
        K, M: condensed stiffness and mass ``(n_c, n_c)``; rows ``0 .. 6 n_seats - 1`` are the
            seat masters' DOFs (seat ``s``: ``6 s .. 6 s + 5`` = u_x, u_y, u_z (m), theta_x,
            theta_y, theta_z (rad)), the rest the fixed-interface modal coordinates.
        modes_hz: the kept fixed-interface modes' frequencies (Hz), all ``<= cutoff_hz``.
        cutoff_hz: the cut-off (Hz).
        seat_names: ``(n_seats,)`` labels. seat_positions: ``(n_seats, 3)`` master positions (m).
        recovery: ``(n_full, n_c)``: the full FE displacement (m, node k's DOFs 3k..3k+2) of each
            condensed coordinate, ``u_full = recovery @ q_c``.
        key: the cache key.
    """

    K: np.ndarray
    M: np.ndarray
    modes_hz: np.ndarray
    cutoff_hz: float
    seat_names: tuple[str, ...]
    seat_positions: np.ndarray
    recovery: np.ndarray
    key: str = ""

    @property
    def n_seat_dofs(self) -> int:
        return 6 * len(self.seat_names)

    def receptance(self, f_hz, loss_factor: float = 0.0) -> np.ndarray:
        """The seats' receptance ``H(f) = [(K (1 + i eta) - (2 pi f)^2 M)^-1]_bb``, complex
        ``(n_f, 6 n_seats, 6 n_seats)`` (m/N, m/(N m), rad/N, rad/(N m)), DOF order as ``K``.

        Raises:
            ValueError: a negative or non-finite frequency, a negative loss factor.
        """
        w2 = _omega2(f_hz)
        eta = _check_loss(loss_factor)
        nb = self.n_seat_dofs
        E = np.eye(self.K.shape[0])[:, :nb]
        return np.stack([np.linalg.solve(self.K * (1 + 1j * eta) - w * self.M, E)[:nb] for w in w2])

    def seat_stiffness(self) -> np.ndarray:
        """The static stiffness at the seats ``(6 n_seats, 6 n_seats)``: the Schur complement
        ``K_bb - K_bq K_qq^-1 K_qb`` (Craig–Bampton: ``K_bq = 0``, so ``K_bb``)."""
        nb = self.n_seat_dofs
        Kbb, Kbq, Kqq = self.K[:nb, :nb], self.K[:nb, nb:], self.K[nb:, nb:]
        return Kbb - Kbq @ np.linalg.solve(Kqq, Kbq.T) if Kqq.size else Kbb.copy()

    def modes(self, n: int | None = None) -> tuple[np.ndarray, np.ndarray]:
        """The condensed housing's free-seat modes (on its feet, seats unloaded): ``(f (Hz)
        (n,), full FE shapes (n_full, n), mass-normalised)``; ``None``: every mode."""
        lam, v = sla.eigh(self.K, self.M)
        n = lam.size if n is None else min(int(n), lam.size)
        return np.sqrt(np.maximum(lam[:n], 0)) / (2 * math.pi), self.recovery @ v[:, :n]


@dataclass
class PreparedHousing:
    """A housing's full FE model and its condensation (not cached; :func:`condensed_housing` is
    the cached path).

    Attributes:
        mesh: the :class:`~fem_prep.housing.HousingMesh`.
        material: the material.
        coupling: the seats' coupling (:class:`~fem_prep.Rigid`, :class:`~fem_prep.Averaging`).
        operators: the full operators (:func:`fem_prep.assemble_operators`).
        coupled: the seat couplings ``u_full = T q``.
        kept: the coupled DOFs not held by the feet.
        K, M: the coupled, clamped stiffness and mass on ``kept`` (CSR).
        seat_dofs: ``(n_seats, 6)`` indices into ``kept`` of the seat masters' DOFs.
        condensed: the Craig–Bampton model (:class:`~fem_prep.Condensed`, seat DOFs first).
        cutoff_hz: the cut-off (Hz).
        timings: wall seconds of the steps (``assembly_s``: the basis and the operators;
            ``coupling_s``: the seats' coupling and the feet's clamping; ``factorisation_s``
            of ``K_ii``; ``mode_count_s``: the number of interior modes below the cut-off;
            ``eigen_s``; ``constraint_modes_s``; ``projection_s``) and the process's CPU
            seconds of each (``..._cpu_s``, all threads).
    """

    mesh: HousingMesh
    material: Material
    coupling: BearingCoupling
    operators: Operators
    coupled: Coupled
    kept: np.ndarray
    K: sp.csr_matrix
    M: sp.csr_matrix
    seat_dofs: np.ndarray
    condensed: Condensed
    cutoff_hz: float
    timings: dict[str, float] = field(default_factory=dict)

    def full_field(self, x_kept: np.ndarray) -> np.ndarray:
        """Full FE displacements ``(n_full, ...)`` of values on ``kept`` ``(n_kept, ...)``."""
        q = np.zeros((self.coupled.T.shape[1],) + x_kept.shape[1:], dtype=x_kept.dtype)
        q[self.kept] = x_kept
        return self.coupled.T @ q

    def full_receptance(self, f_hz, loss_factor: float = 0.0) -> np.ndarray:
        """The full FE model's receptance at the seats (the reference of
        :meth:`CondensedHousing.receptance`): ``(n_f, 6 n_seats, 6 n_seats)`` complex, by a
        sparse solve of ``K (1 + i eta) - (2 pi f)^2 M`` per frequency: fem_prep's Cholesky
        factor below the first resonance undamped, else MKL PARDISO (``pypardiso``) on the
        real equivalent of the complex system (the block matrix of ``Re A``, ``-Im A`` over
        ``Im A``, ``Re A``; 25 times faster than SciPy's SuperLU on 13 k DOFs), SuperLU
        without ``pypardiso``."""
        w2 = _omega2(f_hz)
        eta = _check_loss(loss_factor)
        b = self.seat_dofs.ravel()
        E = np.zeros((self.K.shape[0], b.size))
        E[b, np.arange(b.size)] = 1.0
        out = []
        for w in w2:
            A = (self.K * (1 + 1j * eta) if eta else self.K) - w * self.M
            try:  # below the first resonance, undamped: positive definite (fem_prep's factor)
                if eta:
                    raise SolverError("complex")
                x = factorize(A.tocsr()).solve(E)
            except SolverError:
                x = _indefinite_solve(A, E)
            out.append(x[b])
        return np.stack(out).astype(complex)

    def full_modes(self, n: int) -> tuple[np.ndarray, np.ndarray]:
        """The full model's lowest ``n`` modes, seats free: ``(f (Hz), full FE shapes (n_full,
        n))``."""
        lam, phi = shift_invert_modes(self.K, self.M, n, sigma=0.0)
        return np.sqrt(np.maximum(lam, 0)) / (2 * math.pi), self.full_field(phi)

    def condensed_housing(self, key: str = "") -> CondensedHousing:
        """The :class:`CondensedHousing` of this preparation."""
        c = self.condensed
        seats = self.mesh.seats
        return CondensedHousing(
            K=np.asarray(c.K),
            M=np.asarray(c.M),
            modes_hz=np.asarray(c.modes_hz),
            cutoff_hz=self.cutoff_hz,
            seat_names=tuple(s.name or f"seat{k}" for k, s in enumerate(seats)),
            seat_positions=np.array([s.centre for s in seats]).reshape(-1, 3),
            recovery=self.full_field(c.basis),
            key=key,
        )


def _indefinite_solve(A: sp.spmatrix, E: np.ndarray) -> np.ndarray:
    """``x`` of ``A x = E`` (``A`` sparse ``(n, n)``, real or complex, not positive definite;
    ``E`` real ``(n, k)``): MKL PARDISO (real unsymmetric) on the real equivalent ``2n``
    system where ``pypardiso`` imports, else SciPy's SuperLU."""
    pypardiso = _optional_module("pypardiso")
    if pypardiso is None:
        return spla.splu(A.tocsc()).solve(E.astype(A.dtype))
    n = A.shape[0]
    real = not np.iscomplexobj(A.data)
    Ar, Ai = sp.csr_matrix(A.real), sp.csr_matrix(A.imag)
    B = Ar if real else sp.bmat([[Ar, -Ai], [Ai, Ar]], format="csr")
    ps = _pardiso_solver(pypardiso, mtype=11)
    try:
        x = ps.solve(B, E if real else np.vstack([E, np.zeros_like(E)]))
    finally:
        ps.free_memory(everything=True)
    return x if real else x[:n] + 1j * x[n:]


def _check(mesh, material, cutoff_hz, coupling):
    if not isinstance(mesh, HousingMesh):
        raise TypeError(f"housing = {mesh!r}, allowed a fem_prep.housing.HousingMesh")
    if not isinstance(material, Material):
        raise TypeError(f"material = {material!r}, allowed a fem_prep.Material")
    if not (isinstance(cutoff_hz, (int, float)) and math.isfinite(cutoff_hz) and cutoff_hz > 0):
        raise ValueError(f"cutoff_hz = {cutoff_hz!r}, allowed > 0 (Hz)")
    if not isinstance(coupling, BearingCoupling):
        raise TypeError(
            f"coupling = {coupling!r}, allowed fem_prep.Rigid() or fem_prep.Averaging()"
        )
    if not mesh.seats:
        raise ValueError("housing has no seats; give it at least one bore (Seat)")


@contextmanager
def _step(timings: dict[str, float], name: str):
    """Record the wall and CPU seconds of a step as ``timings[name + "_s"]`` and
    ``timings[name + "_cpu_s"]`` (added to what is there)."""
    t0, c0 = time.perf_counter(), time.process_time()
    try:
        yield
    finally:
        timings[f"{name}_s"] = timings.get(f"{name}_s", 0.0) + time.perf_counter() - t0
        timings[f"{name}_cpu_s"] = timings.get(f"{name}_cpu_s", 0.0) + time.process_time() - c0


def _modes_below(K, M, i, cutoff_hz, progress) -> int | None:
    """The number of fixed-interface modes (of ``K_ii``, ``M_ii``) at or below the cut-off, by
    the inertia of ``K_ii - (2 pi f_c)^2 M_ii`` (:func:`~fem_prep.eigenvalue_count`); ``None``
    where it cannot be had (no ``pypardiso``, or an eigenvalue at the cut-off itself)."""
    with phase_bar(f"modes below the cut-off: LDL^T (n = {len(i)})", progress):
        try:
            return eigenvalue_count(K[i][:, i], M[i][:, i], (2 * math.pi * cutoff_hz) ** 2)
        except (ImportError, SolverError):
            return None


def _condense_to_cutoff(K, M, b, cutoff_hz, progress, timings) -> Condensed:
    """Craig–Bampton on ``b`` with every fixed-interface mode at or below ``cutoff_hz``.

    The number of those modes is counted first, by the inertia of ``K_ii - (2 pi f_c)^2 M_ii``
    (Sylvester: the negative pivots of its ``L D L^T``, :func:`~fem_prep.eigenvalue_count`), and
    one eigen-solve takes exactly them; a mode the eigen-solver misses shows as a last mode above
    the cut-off (a :class:`~fem_prep.SolverWarning`, and the columns above the cut-off are
    dropped). Without the count (no ``pypardiso``) the number of modes doubles from 16 until one
    lies above the cut-off (or all are taken), the factor of ``K_ii`` reused. The modal columns
    above the cut-off are dropped: the first n modal columns of the basis are Craig–Bampton
    with the lowest n modes."""
    mask = np.ones(K.shape[0], dtype=bool)
    mask[b] = False
    i = np.nonzero(mask)[0]
    n_i = len(i)
    with _step(timings, "mode_count"):  # before K_ii's factor: one factor held at a time
        count = _modes_below(K, M, i, cutoff_hz, progress)
    if count is not None:  # the eigen-solve's size known: refused before it if too large
        check_housing_modes(f"cutoff_hz = {cutoff_hz:g}", count, K.shape[0], len(b) // 6,
                            "counted", "a lower cut-off")
    with _step(timings, "factorisation"), phase_bar(f"factorisation of K_ii (n = {n_i})", progress):
        Fii = factorize(K[i][:, i].tocsr())
    k = min(16, n_i) if count is None else min(count, n_i)
    while True:
        c = condense(
            K, M, b, method=CraigBampton(), n_modes=k, interior_factor=Fii, progress=progress
        )
        for name in ("static_modes", "eigen", "projection"):
            step = "constraint_modes" if name == "static_modes" else name
            for suffix in ("_s", "_cpu_s"):
                key = f"{step}{suffix}"
                timings[key] = timings.get(key, 0.0) + c.timings[f"{name}{suffix}"]
        if count is not None or k >= n_i or (c.modes_hz.size and c.modes_hz[-1] > cutoff_hz):
            break
        k = min(2 * k, n_i)
        if k > MAX_HOUSING_MODES:  # without the count: refused once the doubling passes it
            check_housing_modes(f"cutoff_hz = {cutoff_hz:g}", k, K.shape[0], len(b) // 6,
                                "at least", "a lower cut-off")
    n = int(np.sum(c.modes_hz <= cutoff_hz))
    if count is not None and n < count:
        warnings.warn(
            f"housing: {n} fixed-interface modes found below the cut-off {cutoff_hz:g} Hz, "
            f"{count} counted (the eigen-solver missed {count - n}); condensed without them",
            SolverWarning,
            stacklevel=3,
        )
    m = len(b) + n
    return dataclasses.replace(
        c, K=c.K[:m, :m], M=c.M[:m, :m], basis=c.basis[:, :m], n_modes=n, modes_hz=c.modes_hz[:n]
    )


def prepare_housing(
    housing: HousingMesh,
    material: Material,
    cutoff_hz: float,
    *,
    coupling: BearingCoupling | None = None,
    progress: bool = False,
) -> PreparedHousing:
    """Assemble the housing, couple its seats, clamp its feet and condense it (Craig–Bampton on
    the seat masters with every fixed-interface mode up to ``cutoff_hz``).

    Args:
        housing: the mesh with its seats and feet (:func:`mesh_box`, :func:`mesh_box_gmsh`,
            :func:`read_housing_mesh`).
        material: isotropic material (Pa, -, kg/m^3).
        cutoff_hz: the interior modes' cut-off (Hz); the default rule is
            :func:`housing_cutoff_hz` of the highest mesh-order frequency.
        coupling: the seats' coupling, :class:`~fem_prep.Rigid` (``None``: the default) or
            :class:`~fem_prep.Averaging`.
        progress: progress bars.

    Returns:
        The :class:`PreparedHousing`.

    Raises:
        TypeError/ValueError: bad input (one line); a seat or foot that matches no facet; two
            seats sharing nodes; a foot node on a seat.
    """
    coupling = Rigid() if coupling is None else coupling
    _check(housing, material, cutoff_hz, coupling)
    # the BLAS/OpenMP threads (MKL PARDISO's factorisations too) the machine's load leaves
    with blas_threads():
        return _prepare_housing(housing, material, cutoff_hz, coupling, progress)


def fe_dofs(housing: HousingMesh) -> int:
    """The housing's FE DOFs counted from its mesh without building the basis: 3 × (vertices,
    plus the edges' midpoints with Tet10)."""
    m = housing.mesh
    nodes = m.p.shape[1]
    if housing.element.name == "tet10":
        pairs = np.sort(_edge_pairs(m.t), axis=0)
        nodes += np.unique(pairs[0].astype(np.int64) * nodes + pairs[1]).size
    return 3 * int(nodes)


def _edge_pairs(t: np.ndarray) -> np.ndarray:
    """Each tetrahedron's six edges as vertex pairs (2, 6 n_tets)."""
    a = (0, 0, 0, 1, 1, 2)
    b = (1, 2, 3, 2, 3, 3)
    return np.stack([t[list(a)].ravel(), t[list(b)].ravel()])


def _prepare_housing(housing, material, cutoff_hz, coupling, progress) -> PreparedHousing:
    timings: dict[str, float] = {}
    dofs = fe_dofs(housing)  # the mesh's size checked before the basis and the assembly
    check_memory(f"housing: a mesh of {dofs} DOFs",
                 condensation_bytes(dofs, 0, len(housing.seats)),
                 f"the assembly and factors of {dofs} DOFs", "a coarser mesh (a larger size)")
    # the steps; the bar names the running one, the condensation's inner bars count its long
    # calls (factorisations, the eigen-solve's solves, column blocks) and vanish when done
    steps = tqdm(total=3, desc="housing", disable=not progress, unit="step")
    steps.set_postfix_str(f"assembly ({housing.n_dofs} DOFs)...")
    with _step(timings, "assembly"):
        rings = tuple(housing.seat_nodes(s) for s in housing.seats)
        held_nodes = np.unique(
            np.concatenate([housing.foot_nodes(f) for f in housing.feet] or [np.zeros(0, np.int64)])
        )
        for s, r in zip(housing.seats, rings):
            if np.isin(r, held_nodes).any():
                raise ValueError(f"seat {s.name or s.centre}: its bore touches a foot; move it")
        # the scalar basis (the vector basis would hold 3x its functions: 1.9 GB at 300 k DOFs)
        ops = assemble_operators(housing.scalar_basis, material)
    steps.update()
    steps.set_postfix_str("seat couplings, feet...")
    with _step(timings, "coupling"):
        masters = MasterSet(
            rim_nodes=np.zeros((0, 1), dtype=np.int64),
            bearing_positions=np.array([s.centre for s in housing.seats]),
            bearing_rings=rings,
            couplings=(coupling,) * len(rings),
            rim_coupling=Nodal(),
        )
        cp = couple_masters(housing, ops, masters)
        held = (3 * held_nodes[:, None] + np.arange(3)).ravel()
        mask = np.ones(cp.T.shape[1], dtype=bool)
        mask[cp.full_to_red[held]] = False
        kept = np.nonzero(mask)[0]
        K = cp.K[kept][:, kept].tocsr()
        M = cp.M[kept][:, kept].tocsr()
        red_to_kept = -np.ones(cp.T.shape[1], dtype=np.int64)
        red_to_kept[kept] = np.arange(len(kept))
        seat_dofs = red_to_kept[cp.bearing_dofs]
    steps.update()
    steps.set_postfix_str(f"condensation ({K.shape[0]} DOFs, cut-off {cutoff_hz:g} Hz)...")
    c = _condense_to_cutoff(K, M, seat_dofs.ravel(), float(cutoff_hz), progress, timings)
    steps.update()
    steps.close()
    return PreparedHousing(
        housing, material, coupling, ops, cp, kept, K, M, seat_dofs, c, float(cutoff_hz), timings
    )


def _inputs(housing: HousingMesh, material, cutoff_hz, coupling) -> dict:
    m = housing.mesh
    geo = hashlib.sha256(
        np.ascontiguousarray(m.p, dtype=float).tobytes()
        + np.ascontiguousarray(m.t, dtype=np.int64).tobytes()
    ).hexdigest()
    return {
        "format_version": HOUSING_FORMAT,
        "mesh_sha256": geo,
        "element": str(housing.element),
        "seats": [repr(s) for s in housing.seats],
        "feet": [repr(f) for f in housing.feet],
        "seat_tolerance": repr(float(housing.seat_tolerance)),
        "material": repr(material),
        "cutoff_hz": repr(float(cutoff_hz)),
        "coupling": str(coupling),
    }


def condensed_housing(
    housing: HousingMesh,
    material: Material,
    cutoff_hz: float,
    *,
    coupling: BearingCoupling | None = None,
    cache: bool | str | Path = True,
    progress: bool = False,
) -> CondensedHousing:
    """The condensed housing (:func:`prepare_housing`), built once and then read from fem_prep's
    cache (``fem_prep.cache_dir() / "housing" / <key>.npz``; the key hashes the mesh's
    coordinates and connectivity, the element, seats, feet, material, cut-off, coupling and the
    format version, as the FE tables' cache does).

    Args:
        housing, material, cutoff_hz, coupling, progress: as :func:`prepare_housing`.
        cache: ``True`` (fem_prep's cache folder), ``False`` (build, store nothing) or a folder.

    Returns:
        The :class:`CondensedHousing`.
    """
    coupling = Rigid() if coupling is None else coupling
    _check(housing, material, cutoff_hz, coupling)
    inputs = _inputs(housing, material, cutoff_hz, coupling)
    key = cache_key(inputs)
    path = None
    if cache is not False:
        folder = table_dir("housing") if cache is True else Path(cache)
        path = folder / f"{key}.npz"
        d = load_entry(path, key, HOUSING_FORMAT, inputs)
        if d is not None:
            return CondensedHousing(
                K=d["K"],
                M=d["M"],
                modes_hz=d["modes_hz"],
                cutoff_hz=float(d["cutoff_hz"]),
                seat_names=tuple(str(s) for s in d["seat_names"]),
                seat_positions=d["seat_positions"],
                recovery=d["recovery"],
                key=key,
            )
    out = prepare_housing(
        housing, material, cutoff_hz, coupling=coupling, progress=progress
    ).condensed_housing(key)
    if path is not None:
        import json

        store_entry(
            path,
            {
                "K": out.K,
                "M": out.M,
                "modes_hz": out.modes_hz,
                "cutoff_hz": out.cutoff_hz,
                "seat_names": np.array(out.seat_names),
                "seat_positions": out.seat_positions,
                "recovery": out.recovery,
                "key": key,
                "format_version": HOUSING_FORMAT,
                "inputs": json.dumps(inputs, sort_keys=True),
            },
        )
    return out


def write_housing_vtu(
    housing: HousingMesh, condensed: CondensedHousing, path, n_modes: int = 10
) -> Path:
    """Write the housing mesh (``tetra10`` for :class:`Tet10`, ``tetra`` for :class:`Tet4`) with
    the condensed housing's first ``n_modes`` free-seat mode shapes as point data
    ``mode_XX_<f>Hz`` (mass-normalised, m), the seat nodes (``seat``: seat index + 1, 0 elsewhere)
    and the feet's nodes (``foot``: 1) to a ``.vtu`` (meshio; ParaView), atomically.

    Raises:
        ValueError: ``n_modes`` < 0, or a condensed housing of another mesh (sizes differ).
    """
    import meshio  # lazy: only when a file is written

    if isinstance(n_modes, bool) or not isinstance(n_modes, int) or n_modes < 0:
        raise ValueError(f"n_modes = {n_modes!r}, allowed an integer >= 0")
    if condensed.recovery.shape[0] != housing.n_dofs:
        raise ValueError(
            f"condensed housing of {condensed.recovery.shape[0]} DOFs, mesh of "
            f"{housing.n_dofs}: not the same housing"
        )
    sb = housing.scalar_basis
    cells = np.ascontiguousarray(sb.element_dofs.T)
    kind = "tetra10" if cells.shape[1] == 10 else "tetra"
    f, shapes = condensed.modes(n_modes)
    n_nodes = sb.N
    data = {
        f"mode_{k + 1:02d}_{f[k]:.0f}Hz": shapes[:, k].reshape(n_nodes, 3) for k in range(f.size)
    }
    seat = np.zeros(n_nodes)
    for k, s in enumerate(housing.seats):
        seat[housing.seat_nodes(s)] = k + 1
    foot = np.zeros(n_nodes)
    for ft in housing.feet:
        foot[housing.foot_nodes(ft)] = 1
    data["seat"], data["foot"] = seat, foot
    mesh = meshio.Mesh(sb.doflocs.T, [(kind, cells)], point_data=data)
    return atomic_write(Path(path), lambda p: meshio.write(str(p), mesh, file_format="vtu"))
