"""Component-mode condensation (seed (2.3)-(2.5)): the methods as classes and :func:`condense`.

Notation (seed (2.3)): the reduced DOF vector is split into boundary (master) DOFs ``b`` and
interior DOFs ``i``.

* :class:`Guyan`: ``u = [I; G_ib] u_b`` with ``G_ib = -K_ii^-1 K_ib`` (static constraint modes).
* :class:`CraigBampton` (fixed interface, [CRA68]): ``u = [I 0; G_ib Phi_i] [u_b; q]`` with
  ``Phi_i`` the first modes of ``(K_ii, M_ii)`` (interface held), mass-normalised.
* :class:`Herting` (free interface, [HER85], seed (2.4)): ``u = [I 0; G_ib (phi_i - G_ib phi_b)]
  [u_b; q]`` with ``phi`` the first elastic modes of the free structure (rigid-body modes are
  already spanned by the constraint modes and are dropped).  The modal block is then
  re-orthonormalised (mass-orthonormal, stiffness-diagonal) so that ``K_s = [[K_bb, 0], [0,
  K_nn]]`` (2.5): boundary and modal DOFs are statically uncoupled.  The inertia-relief term
  ``H_i0`` of (2.4) is not needed because the rigid-body motion is exactly represented by the
  constraint modes.

The master nodes and their couplings (bearings, rims) are in :mod:`._couplings`.
"""

from __future__ import annotations

import ctypes
import dataclasses
import functools
import math
import time
from dataclasses import dataclass, field
from typing import ClassVar, final

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from tqdm import tqdm

from ._kinds import CondensationMethod
from ._solver import (
    BlockLanczos,
    EigenSolver,
    Factor,
    blas_threads,
    factorize,
    phase_bar,
    shift_invert_modes,
    solve_bar,
)

__all__ = [
    "Condensed",
    "CraigBampton",
    "Guyan",
    "Herting",
    "RotatingOperators",
    "condense",
    "frequency_error_vs_modes",
]


@dataclass(frozen=True)
class RotatingOperators:
    """The operators of the rotating body that :func:`condense` projects on its basis.

    Attributes:
        f: centrifugal vector per unit speed squared ``(n,)`` (condensed as ``H^T f``, (2.37);
            with it the modal methods add the static correction vector, see :func:`condense`).
        S: spin-softening matrix ``(n, n)`` per unit speed squared.
        G: gyroscopic matrix ``(n, n)`` per unit spin speed (skew-symmetric).
        Ksigma: stress-stiffening matrix ``(n, n)`` per unit speed squared.

    Each may be ``None`` (not condensed). ``S``, ``G``, ``Ksigma`` are projected on the basis
    (``H^T A H``) and do not change it (the modes and ψ are those of ``K``, ``M`` and ``f``).
    """

    f: np.ndarray | None = None
    S: sp.spmatrix | None = None
    G: sp.spmatrix | None = None
    Ksigma: sp.spmatrix | None = None


class InteriorBlock(spla.LinearOperator):
    """The interior block ``A[i][:, i]`` of a sparse ``A`` as an operator on the full matrix
    (``x ↦ (A x̂)[i]``, ``x̂`` the interior vector ``x`` padded with zeros): the eigen-solve and
    the static correction use ``K_ii`` and ``M_ii`` only through products, so no copy of the
    blocks (each as large as ``A``) is held. ``toarray()``: the dense block (small problems)."""

    def __init__(self, A: sp.csr_matrix, i: np.ndarray):
        super().__init__(dtype=A.dtype, shape=(len(i), len(i)))
        self._A, self._i = A, i

    def _matmat(self, X: np.ndarray) -> np.ndarray:
        full = np.zeros((self._A.shape[0],) + X.shape[1:])
        full[self._i] = X
        return (self._A @ full)[self._i]

    def _matvec(self, x: np.ndarray) -> np.ndarray:
        return self._matmat(np.ravel(x))

    def _adjoint(self) -> InteriorBlock:
        return self  # A symmetric

    def toarray(self) -> np.ndarray:
        return self._A[self._i][:, self._i].toarray()


@dataclass(frozen=True)
class Partition:
    """A structure split into boundary DOFs ``b`` and interior DOFs ``i``, with the factor of
    ``K_ii``: what a :class:`~fem_prep._kinds.CondensationMethod` builds its modes from.

    Attributes:
        K, M: CSR stiffness and mass ``(n, n)``.
        b, i: boundary and interior DOF indices.
        Fii: the factorisation of ``K_ii``.
        progress: show progress bars.
        modes: the method's :meth:`~fem_prep._kinds.CondensationMethod.early_modes`, or
            ``None``.
    """

    K: sp.csr_matrix
    M: sp.csr_matrix
    b: np.ndarray
    i: np.ndarray
    Fii: Factor
    progress: bool = False
    modes: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def n(self) -> int:
        return self.K.shape[0]

    @property
    def nb(self) -> int:
        return len(self.b)

    @property
    def Kii(self) -> InteriorBlock:
        """``K[i][:, i]`` as an operator (:class:`InteriorBlock`)."""
        return InteriorBlock(self.K, self.i)

    @property
    def Mii(self) -> InteriorBlock:
        """``M[i][:, i]`` as an operator (:class:`InteriorBlock`)."""
        return InteriorBlock(self.M, self.i)


@dataclass
class Condensed:
    """A condensed substructure.

    Attributes:
        method: the method (:class:`Guyan`, :class:`CraigBampton`, :class:`Herting`; it prints
            as its body-file name).
        K, M: condensed stiffness (N/m, N/rad, N m/rad) and mass ``(n_c, n_c)``.
        f_centrifugal: condensed centrifugal vector per unit speed squared ``(n_c,)``.
        spin_softening: condensed spin-softening matrix ``H^T S H`` per unit speed squared
            (symmetric) or ``None`` (no ``S`` given).
        gyroscopic: condensed gyroscopic matrix ``H^T G H`` per unit spin speed (skew) or
            ``None``.
        stress_stiffening: condensed stress-stiffening matrix ``H^T K_sigma H`` per unit speed
            squared (symmetric) or ``None``.
        master_dofs: reduced indices ``(n_b,)`` of the boundary DOFs (condensed rows 0..n_b-1).
        n_modes: number of modal coordinates (condensed rows n_b..n_c-1).
        basis: reduced-space transformation ``(n_red, n_c)``: ``q_red = basis @ q_c`` (the
            transfer matrix H of (2.4)); ``u_full = T @ basis @ q_c``.
        timings: wall times (s) of the steps (``factorisation_s``, ``static_modes_s``,
            ``eigen_s``, ``projection_s``) and the process's CPU times (all threads) of the
            same steps (``..._cpu_s``).
        modes_hz: natural frequencies of the modes kept in the basis (Hz).
    """

    method: CondensationMethod
    K: np.ndarray
    M: np.ndarray
    f_centrifugal: np.ndarray
    spin_softening: np.ndarray | None
    master_dofs: np.ndarray
    n_modes: int
    basis: np.ndarray
    timings: dict[str, float] = field(default_factory=dict)
    modes_hz: np.ndarray = field(default_factory=lambda: np.zeros(0))
    gyroscopic: np.ndarray | None = None
    stress_stiffening: np.ndarray | None = None


def _project(
    A: sp.spmatrix, V: np.ndarray, block: int = 128, *, skew: bool = False, bar=None
) -> np.ndarray:
    """``V^T A V`` by column blocks (bounded memory), for ``A`` symmetric (``skew=False``) or
    skew-symmetric (``skew=True``). Only the blocks on and above the diagonal are computed
    (``V[:, :c1]^T A V[:, c0:c1]``, about 0.55 of the products for a thousand columns) and the
    lower triangle is their (skew-)mirror, which also removes the rounding asymmetry. ``bar``: a
    tqdm bar advanced by one per column block."""
    m = V.shape[1]
    out = np.empty((m, m))
    for c0 in range(0, m, block):
        c1 = min(m, c0 + block)
        out[:c1, c0:c1] = V[:, :c1].T @ (A @ V[:, c0:c1])
        if bar is not None:
            bar.update()
    return _mirror(out, block, skew=skew)


def _mirror(out: np.ndarray, block: int, *, skew: bool) -> np.ndarray:
    """Complete a matrix whose column blocks hold rows ``[:c1]`` (the upper block triangle):
    the diagonal blocks are (skew-)symmetrised, the lower triangle is the (skew-)mirror."""
    m = out.shape[0]
    sign = -1.0 if skew else 1.0
    for c0 in range(0, m, block):
        c1 = min(m, c0 + block)
        d = out[c0:c1, c0:c1]
        out[c0:c1, c0:c1] = 0.5 * (d + sign * d.T)
        out[c1:, c0:c1] = sign * out[c0:c1, c1:].T
    return out


def _project_stiffness(K: sp.spmatrix, H: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``H^T K H`` for a basis whose boundary rows are ``H[b] = [I 0]`` and whose first ``n_b``
    columns are the static constraint modes (``K_ii G_ib = -K_ib``), seed (2.5): the boundary
    block is the Schur complement ``K_bb + K_bi G_ib = (K H)[b, :n_b]`` (the interior rows of
    ``K H_b`` vanish to the solve's residual), the modal block ``Φ^T K Φ``, and the
    boundary/modal blocks are zero (statically uncoupled). Cost: ``nnz(K[b]) n_b + nnz(K) k``
    instead of ``nnz(K) m + n m^2`` for the plain projection (``m = n_b + k`` columns)."""
    nb, m = len(b), H.shape[1]
    out = np.zeros((m, m))
    Kb = K[b]
    # only the DOFs coupled to the boundary (the columns of K[b]) enter: gathering their rows of
    # H avoids the contiguous copy of the whole n x n_b block that the sparse product makes of a
    # column slice (1.5 GB at 186 k DOFs); the same products in the same order
    J = np.unique(Kb.indices)
    out[:nb, :nb] = Kb[:, J] @ H[J, :nb]
    out[:nb, :nb] = 0.5 * (out[:nb, :nb] + out[:nb, :nb].T)
    if m > nb:
        Phi = H[:, nb:]
        out[nb:, nb:] = Phi.T @ (K @ Phi)
        out[nb:, nb:] = 0.5 * (out[nb:, nb:] + out[nb:, nb:].T)
    return out


def _append_column(H: np.ndarray, col: np.ndarray) -> np.ndarray:
    """``H`` with one more column ``col`` ``(n, 1)``: written in place when ``H`` is the
    leading columns of a wider C-ordered buffer (:func:`_condense` reserves the static
    correction's column so that a 1.6 GB basis is not copied to add it), else a copy."""
    base = H.base
    if (
        base is not None
        and np.ndim(base) == 2
        and base.flags.c_contiguous
        and base.shape[0] == H.shape[0]
        and base.shape[1] > H.shape[1]
        and H.strides == base.strides
        and H.__array_interface__["data"][0] == base.__array_interface__["data"][0]
    ):
        out = base[:, : H.shape[1] + 1]
        out[:, -1] = col[:, 0]
        return out
    return np.hstack([H, col])


# ------------------------------------------------------------------------------------------
# the methods


def _psi_column(part: Partition, H: np.ndarray, f: np.ndarray):
    """The static correction column (residual-flexibility attachment of the body load): ψ =
    K_ii⁻¹ f_i, M-orthogonalised against the modal columns of ``H`` (CGS2), unit modal mass, as
    ``(column (n, 1), k_psi, m_psi)``; ``None`` when ψ lies in the modes' span."""
    i, nb = part.i, part.nb
    Mii = part.Mii
    psi0 = part.Fii.solve(np.asarray(f, dtype=float)[i])
    psi = psi0
    modal = H[i, nb:]
    for _ in range(2):  # M-orthogonalise against the retained modes (CGS2)
        psi = psi - modal @ (modal.T @ (Mii @ psi))
    m_psi = float(psi @ (Mii @ psi))
    k_psi = float(psi @ (part.Kii @ psi))
    if not (m_psi > 0 and np.linalg.norm(psi) > 1e-8 * np.linalg.norm(psi0)):
        return None
    col = np.zeros((part.n, 1))
    col[i, 0] = psi / math.sqrt(m_psi)
    return col, k_psi, m_psi


@final
class Guyan(CondensationMethod):
    """Static condensation on the boundary DOFs only (``method = "guyan"``): no modal DOFs."""

    name: ClassVar[str] = "guyan"

    def n_columns(self, n_modes):
        return 0

    def modal_block(self, part, H, n_modes):
        return H, np.zeros(0)

    def add_static_correction(self, part, H, modes_hz, f):
        return H, modes_hz


@final
class CraigBampton(CondensationMethod):
    """Fixed-interface modes ([CRA68], ``method = "craig-bampton"``, the default).

    Args:
        eigen_solver: the eigen-solver of the modes: :class:`~fem_prep.BlockLanczos` (a block
            of 8 vectors per factor solve; ``None``: the default, ``BlockLanczos()``) or
            :class:`~fem_prep.Lanczos` (ARPACK ``eigsh``, one vector per solve).
    """

    name: ClassVar[str] = "craig-bampton"

    def __init__(self, eigen_solver: EigenSolver | None = None):
        self.eigen_solver = eigen_solver

    @property
    def solver(self) -> EigenSolver:
        """The eigen-solver that runs: ``eigen_solver``, or ``BlockLanczos()`` by default (on
        the 169 k-DOF power wheel 1.3x less CPU than ``eigsh`` for the same modes: see
        ``docs/bench/bench_body_build_eigen.json``)."""
        return BlockLanczos() if self.eigen_solver is None else self.eigen_solver

    def n_columns(self, n_modes):
        return n_modes

    def early_modes(self, part, n_modes):
        """The fixed-interface modes ``(lam (n_modes,), phi (n_i, n_modes))`` of ``(K_ii,
        M_ii)``: they need only the interior blocks, so :func:`condense` computes them before
        it allocates the basis (on the 169 k-DOF power wheel the block Lanczos workspace, about
        0.5 GB, and the 1.5 GB basis are then never held together)."""
        with solve_bar(f"fixed-interface modes ({n_modes})", part.progress) as bar:
            return shift_invert_modes(
                part.Kii,
                part.Mii,
                n_modes,
                sigma=0.0,
                factor=part.Fii,
                on_solve=bar.update,
                solver=self.solver,
            )

    def modal_block(self, part, H, n_modes):
        lam, phi = part.modes if part.modes is not None else self.early_modes(part, n_modes)
        H[part.i, part.nb :] = phi
        return H, np.sqrt(np.maximum(lam, 0)) / (2 * math.pi)

    def add_static_correction(self, part, H, modes_hz, f):
        psi = _psi_column(part, H, f)
        if psi is None:
            return H, modes_hz
        col, k_psi, m_psi = psi
        # fixed-interface modes are K_ii-orthogonal to an M-orthogonal ψ: block stays diagonal
        H = _append_column(H, col)
        return H, np.r_[modes_hz, math.sqrt(max(k_psi / m_psi, 0.0)) / (2 * math.pi)]


@final
class Herting(CondensationMethod):
    """Free-interface modes ([HER85], seed (2.4), ``method = "herting"``).

    Args:
        free_shift: shift (rad/s)^2 (negative) of the free-interface eigen-solve; default
            ``-1e-4`` x the median of ``diag(K)/diag(M)``.
        eigen_solver: as :class:`CraigBampton`'s, but ``None`` runs :func:`shift_invert_modes`'
            default (:class:`~fem_prep.Lanczos`, ARPACK ``eigsh``).
    """

    name: ClassVar[str] = "herting"

    def __init__(self, free_shift: float | None = None, eigen_solver: EigenSolver | None = None):
        self.free_shift = free_shift
        self.eigen_solver = eigen_solver

    def n_columns(self, n_modes):
        return n_modes

    def modal_block(self, part, H, n_modes):
        K, M, b, nb, n = part.K, part.M, part.b, part.nb, part.n
        free_shift = self.free_shift
        if free_shift is None:
            free_shift = -float(np.median(K.diagonal() / np.maximum(M.diagonal(), 1e-300))) * 1e-4
        with phase_bar(f"factorisation of K - s M (n = {n})", part.progress):
            Ffree = factorize((K - free_shift * M).tocsr())
        n_rigid = 6
        with solve_bar(f"free-interface modes ({n_modes + n_rigid})", part.progress) as bar:
            lam, phi = shift_invert_modes(
                K,
                M,
                n_modes + n_rigid,
                sigma=free_shift,
                factor=Ffree,
                on_solve=bar.update,
                solver=self.eigen_solver,
            )
        del Ffree
        # drop rigid-body modes (captured by the constraint modes)
        lam_ref = max(abs(lam[-1]), 1.0)
        elastic = lam > 1e-8 * lam_ref
        lam, phi = lam[elastic][:n_modes], phi[:, elastic][:, :n_modes]
        modes_hz = np.sqrt(lam) / (2 * math.pi)
        chi = phi - H[:, :nb] @ phi[b]  # (2.4): [0; phi_i - G_ib phi_b]
        chi[b] = 0.0
        Mcc = _project(M, chi)
        Kcc = _project(K, chi)
        d, V = np.linalg.eigh(Mcc)
        keep = d > 1e-10 * d.max()
        Q = V[:, keep] / np.sqrt(d[keep])
        lam2, U = np.linalg.eigh(Q.T @ Kcc @ Q)
        chi = chi @ (Q @ U)
        H = H[:, : nb + chi.shape[1]]
        H[:, nb:] = chi
        return H, modes_hz

    def add_static_correction(self, part, H, modes_hz, f):
        psi = _psi_column(part, H, f)
        if psi is None:
            return H, modes_hz
        col = psi[0]
        nb = part.nb
        # the Herting block is not K_ii-orthogonal to ψ: re-diagonalise it with ψ
        chi = np.hstack([H[:, nb:], col])
        d, V = np.linalg.eigh(_project(part.M, chi))
        keep = d > 1e-10 * d.max()
        Q = V[:, keep] / np.sqrt(d[keep])
        lam2, U = np.linalg.eigh(Q.T @ _project(part.K, chi) @ Q)
        H = np.hstack([H[:, :nb], chi @ (Q @ U)])
        return H, np.sqrt(np.maximum(lam2, 0)) / (2 * math.pi)


# ------------------------------------------------------------------------------------------
# condensation


def _condense(
    K: sp.spmatrix,
    M: sp.spmatrix,
    master_dofs: np.ndarray,
    *,
    method: CondensationMethod | None = None,
    n_modes: int = 50,
    rotating: RotatingOperators | None = None,
    progress: bool = False,
    interior_factor: Factor | None = None,
    static_correction: bool = True,
) -> Condensed:
    """Condense ``(K, M)`` onto ``master_dofs`` (+ ``n_modes`` modal DOFs), seed (2.3)-(2.5).

    Args:
        K, M: sparse symmetric stiffness and mass ``(n, n)`` of the (coupled) structure.
        master_dofs: boundary DOF indices ``(n_b,)``; they must restrain the rigid-body modes
            (``K_ii`` non-singular).
        method: :class:`Guyan`, :class:`CraigBampton` (``None``: the default) or
            :class:`Herting` (a modal method with its eigen-solver: ``CraigBampton(
            eigen_solver=fem_prep.BlockLanczos())``).
        n_modes: number of retained modes (ignored by Guyan).
        rotating: the centrifugal vector and rotating-frame matrices to condense
            (:class:`RotatingOperators`), or ``None``.
        progress: show tqdm progress bars.
        interior_factor: a factorisation of ``K_ii`` to reuse.
        static_correction: with ``rotating.f`` given and a modal method, add the static
            correction vector ψ = K_ii⁻¹ f_i of the body load (M-orthogonalised against the
            retained modes, unit modal mass) as one more modal DOF: the fixed-interface modes are
            bending modes and do not carry the in-plane static response to the centrifugal load,
            so without ψ the recovered interior field misses it (its frequency is listed in
            ``modes_hz``).

    Returns:
        The :class:`Condensed` model; boundary DOFs first in the order of ``master_dofs``.

    Raises:
        ValueError: a method that is not a condensation method, or a negative ``n_modes``.
    """
    method = CraigBampton() if method is None else method
    if not isinstance(method, CondensationMethod):
        raise ValueError(
            f"method = {method!r}; use fem_prep.Guyan(), fem_prep.CraigBampton() or "
            "fem_prep.Herting()"
        )
    if n_modes < 0:
        raise ValueError(f"n_modes = {n_modes} must be >= 0")
    rot = RotatingOperators() if rotating is None else rotating
    f, S, G, Ksigma = rot.f, rot.S, rot.G, rot.Ksigma
    K = sp.csr_matrix(K)
    M = sp.csr_matrix(M)
    n = K.shape[0]
    b = np.asarray(master_dofs, dtype=np.int64)
    mask = np.ones(n, dtype=bool)
    mask[b] = False
    i = np.nonzero(mask)[0]
    timings: dict[str, float] = {}
    t0, c0 = time.perf_counter(), time.process_time()
    Ki = K[i]
    Kib = Ki[:, b].tocsc()
    if interior_factor is None:
        with phase_bar(f"factorisation of K_ii (n = {len(i)})", progress):
            Fii = factorize(Ki[:, i])
    else:
        Fii = interior_factor
    # the factor holds K_ii; the eigen-solve takes products (InteriorBlock): no copy kept
    del Ki
    _trim_heap()
    timings["factorisation_s"] = time.perf_counter() - t0
    timings["factorisation_cpu_s"] = time.process_time() - c0
    part = Partition(K, M, b, i, Fii, progress)
    # modes that need only K_ii and M_ii (Craig-Bampton's) before the basis is allocated: the
    # eigen-solver's workspace is freed before the n x (n_b + n_modes) basis exists
    t0, c0 = time.perf_counter(), time.process_time()
    if n_modes > 0:
        part = dataclasses.replace(part, modes=method.early_modes(part, n_modes))
    eigen_s, eigen_cpu_s = time.perf_counter() - t0, time.process_time() - c0
    _trim_heap()  # the eigen-solver's freed blocks, before the basis and the solve blocks

    # static constraint modes G_ib = -K_ii^-1 K_ib, by column blocks; one column more is
    # reserved for the static correction vector (appended in place, not by a copy of H)
    t0, cpu0 = time.perf_counter(), time.process_time()
    nb = len(b)
    wants_psi = static_correction and f is not None and bool(np.any(f[i] != 0))
    width = nb + method.n_columns(n_modes)
    H = np.zeros((n, width + int(wants_psi)))[:, :width]
    H[b, np.arange(nb)] = 1.0
    blk = Fii.block  # columns per solve: the factor's throughput at bounded memory
    it = range(0, nb, blk)
    for c0 in tqdm(it, desc="constraint modes", disable=not progress, unit="block", leave=False):
        c1 = min(nb, c0 + blk)
        # Fortran order: the layout CHOLMOD and PARDISO take (no converted copy of each block)
        H[i, c0:c1] = Fii.solve((-Kib[:, c0:c1]).toarray(order="F"))
    del Kib
    timings["static_modes_s"] = time.perf_counter() - t0
    timings["static_modes_cpu_s"] = time.process_time() - cpu0

    t0, c0 = time.perf_counter(), time.process_time()
    modes_hz = np.zeros(0)
    if n_modes > 0:
        H, modes_hz = method.modal_block(part, H, n_modes)
    if wants_psi:
        H, modes_hz = method.add_static_correction(part, H, modes_hz, f)
    timings["eigen_s"] = eigen_s + time.perf_counter() - t0
    # the process's CPU time (all threads) of the eigen-solve: comparable on a shared machine
    timings["eigen_cpu_s"] = eigen_cpu_s + time.process_time() - c0
    # the factor and the interior blocks are not needed by the projections: free them first
    del part, Fii

    t0, c0 = time.perf_counter(), time.process_time()
    n_mat = 2 + sum(A is not None for A in (S, G, Ksigma))
    with tqdm(
        total=1 + (n_mat - 1) * -(-H.shape[1] // 128),
        desc=f"projection H^T A H ({n_mat} matrices, {H.shape[1]} columns)",
        disable=not progress,
        unit="block",
        leave=False,
    ) as bar:
        # K: the Schur complement and the modal block, boundary/modal blocks zero, (2.5)
        Kc = _project_stiffness(K, H, b)
        bar.update()
        Mc, Sc, Gc, Ksc = (
            _project(A, H, skew=skew, bar=bar) if A is not None else None
            for A, skew in ((M, False), (S, False), (G, True), (Ksigma, False))
        )
        fc = H.T @ f if f is not None else np.zeros(H.shape[1])
    timings["projection_s"] = time.perf_counter() - t0
    timings["projection_cpu_s"] = time.process_time() - c0
    return Condensed(
        method=method,
        K=Kc,
        M=Mc,
        f_centrifugal=fc,
        spin_softening=Sc,
        master_dofs=b,
        n_modes=H.shape[1] - nb,
        basis=H,
        timings=timings,
        modes_hz=modes_hz,
        gyroscopic=Gc,
        stress_stiffening=Ksc,
    )


def _trim_heap() -> None:
    """Return the C heap's free pages to the operating system (glibc's ``malloc_trim``; nothing
    where the C library has none). NumPy's mid-sized arrays live on that heap, and glibc keeps
    what they freed: after the 186 k-DOF wheel's assembly and coupling the process held 1.40 GiB
    of which 0.56 GiB was alive (tracemalloc), 0.63 GiB after the trim. The condensation's large
    arrays are mapped apart from the heap and cannot reuse those pages, so without the trim they
    add to the peak."""
    try:
        trim = ctypes.CDLL(None).malloc_trim
    except (OSError, AttributeError, TypeError):  # no glibc (macOS, Windows, musl)
        return
    trim(0)


@functools.wraps(_condense)
def condense(*args, **kwargs) -> Condensed:
    _trim_heap()
    with blas_threads():
        return _condense(*args, **kwargs)


def frequency_error_vs_modes(prep, modes, methods=(CraigBampton(), Herting())) -> dict:
    """Largest relative error of the full model's first frequencies (bearings held) against the
    number of retained modes, for each condensation method (Fig. III-13's question).

    Args:
        prep: a :class:`~fem_prep.Prepared` body (its ``frequencies_full_hz`` are the reference).
        modes: numbers of retained modes to try. methods: condensation methods.

    Returns:
        ``{method name: [error for each entry of modes]}``.
    """
    f_full = np.asarray(prep.frequencies_full_hz)
    cp = prep.coupled
    bearing_c = len(prep.master_dofs) - cp.bearing_dofs.size + np.arange(cp.bearing_dofs.size)
    curves = {}
    for method in methods:
        errs = []
        for m in modes:
            c = condense(cp.K, cp.M, prep.master_dofs, method=method, n_modes=m)
            keep = np.ones(c.K.shape[0], bool)
            keep[bearing_c] = False
            lam = sla.eigh(c.K[np.ix_(keep, keep)], c.M[np.ix_(keep, keep)], eigvals_only=True)
            fc = np.sqrt(np.maximum(lam[: len(f_full)], 0)) / (2 * math.pi)
            errs.append(float(np.max(np.abs(fc / f_full - 1))))
        curves[str(method)] = errs
    return curves
