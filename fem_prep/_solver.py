"""Sparse symmetric factorisation and eigen-solves: library calls, with a pure-SciPy fallback.

* :func:`factorize`: sparse Cholesky by a supernodal library when one imports, the first of:
  CHOLMOD through the optional ``scikit-sparse`` (``pip install scikit-sparse``, built against
  the system's SuiteSparse; the ``cholmod`` extra; :class:`SupernodalFactor`); Intel MKL PARDISO
  through the ``pypardiso`` wheel (a dependency on x86-64; :class:`PardisoFactor`). Both factor
  and solve many right-hand sides as dense BLAS-3 block operations on the supernodes. Else
  CHOLMOD's simplicial factorisation through the ``cholespy`` wheel (:class:`CholmodFactor`:
  METIS ordering, a dependency); if none imports, SciPy's SuperLU (symmetric mode,
  minimum-degree ordering) with a :class:`SolverWarning` saying so (SuperLU is slower: 1.4x on
  the 34 k-DOF benchmark wheel, more on larger factors). Every factor has ``solve(B)`` for ``B``
  of shape ``(n,)`` or ``(n, k)``, a ``method`` attribute naming the algorithm that ran
  (``"cholmod"``, ``"pardiso"`` or ``"superlu"``, recorded in ``summary.json``), ``library``
  (the package that ran it) and ``block`` (the number of right-hand sides a caller should pass
  per ``solve`` for throughput at bounded memory).
* :func:`shift_invert_modes`: SciPy's ``eigsh`` (ARPACK, implicitly restarted Lanczos) in
  shift-invert mode with the factor as ``OPinv``. Non-convergence raises
  :class:`SolverError`; every returned mode is checked by its residual
  ``‖K φ − λ M φ‖ / (|λ| ‖M φ‖)``.
* :class:`blas_threads`: BLAS thread count through ``threadpoolctl``.
"""

from __future__ import annotations

import abc
import contextlib
import ctypes
import importlib
import os
import warnings
from collections.abc import Callable, Iterator
from typing import ClassVar, final

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from threadpoolctl import threadpool_limits
from tqdm import tqdm

__all__ = [
    "BlockLanczos",
    "CholmodFactor",
    "EigenSolver",
    "Lanczos",
    "PardisoFactor",
    "SolverError",
    "SolverWarning",
    "SparseFactor",
    "SupernodalFactor",
    "blas_threads",
    "eigenvalue_count",
    "factorize",
    "phase_bar",
    "shift_invert_modes",
    "solve_bar",
]


class SolverWarning(UserWarning):
    """A slower fallback solver ran (the result is still correct)."""


class SolverError(RuntimeError):
    """A factorisation or eigen-solve did not succeed (not positive definite, no convergence)."""


class _Factor:
    """What every factor shares: ``A^-1`` as a LinearOperator from the factor's own ``solve``
    and ``shape``."""

    shape: tuple[int, int]

    def operator(self) -> spla.LinearOperator:
        """``A^-1`` as a LinearOperator."""
        return spla.LinearOperator(self.shape, matvec=self.solve, matmat=self.solve, dtype=float)


class SparseFactor(_Factor):
    """SuperLU factorisation (symmetric mode) of a sparse symmetric matrix (SciPy)."""

    method = "superlu"
    library = "scipy"
    block = 32

    def __init__(self, A: sp.spmatrix):
        A = sp.csc_matrix(A)
        self.shape = A.shape
        try:
            self._lu = spla.splu(
                A,
                permc_spec="MMD_AT_PLUS_A",
                diag_pivot_thresh=0.0,
                options={"SymmetricMode": True},
            )
        except RuntimeError as exc:  # "Factor is exactly singular"
            raise SolverError(f"SuperLU factorisation failed: {exc}") from exc
        self.nnz = int(self._lu.L.nnz + self._lu.U.nnz)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        return self._lu.solve(np.asarray(b, dtype=float))


class CholmodFactor(_Factor):
    """Sparse Cholesky ``A = L Lᵀ`` by CHOLMOD (``cholespy``: simplicial, METIS ordering) of a
    symmetric positive-definite matrix; the lower triangle of ``A`` is used.

    Raises:
        SolverError: ``A`` is not positive definite.
    """

    method = "cholmod"
    library = "cholespy"
    block = 32  # CHOLMOD's simplicial solve takes 4 columns at a time; bounded memory

    def __init__(self, A: sp.spmatrix):
        cholespy = _optional_module("cholespy")
        if cholespy is None:
            raise ImportError("fem_prep.CholmodFactor needs cholespy: pip install cholespy")
        L = sp.tril(sp.coo_matrix(A)).tocoo()
        n = A.shape[0]
        self.shape = A.shape
        try:
            self._chol = cholespy.CholeskySolverD(
                n,
                L.row.astype(np.int32),
                L.col.astype(np.int32),
                L.data.astype(np.float64),
                cholespy.MatrixType.COO,
            )
        except ValueError as exc:  # "Matrix is not positive definite!"
            raise SolverError(f"CHOLMOD factorisation failed: {exc}") from exc
        self.nnz = int(L.nnz)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        b = np.ascontiguousarray(b, dtype=np.float64)
        x = np.zeros_like(b)
        self._chol.solve(b, x)
        return x


class SupernodalFactor(_Factor):
    """Supernodal sparse Cholesky ``P A Pᵀ = L Lᵀ`` by CHOLMOD through ``scikit-sparse``
    (``sksparse.cholmod.cholesky``, ``mode="supernodal"``, CHOLMOD's choice of ordering) of a
    symmetric positive-definite matrix. The factorisation and the solves with many right-hand
    sides run as dense BLAS-3 block operations on the supernodes (on the 122 k-DOF interior of
    the power wheel: factorisation 9x, a 128-column solve 3.3x faster per column than
    :class:`CholmodFactor`, one load-shared run); one ``L`` is held.

    Raises:
        SolverError: ``A`` is not positive definite.
        ImportError: ``scikit-sparse`` is not installed (one line).
    """

    method = "cholmod"
    library = "scikit-sparse"
    block = 128  # columns per solve: BLAS-3 throughput, n x 128 doubles per block

    def __init__(self, A: sp.spmatrix):
        cholmod = _optional_module("sksparse.cholmod")
        if cholmod is None:
            raise ImportError(
                "fem_prep.SupernodalFactor needs scikit-sparse (and SuiteSparse): "
                "pip install scikit-sparse"
            )
        A = sp.csr_matrix(A)
        # A symmetric: its CSR arrays are the CSC arrays of Aᵀ = A (no converted copy; CHOLMOD
        # reads one triangle)
        A = sp.csc_matrix((A.data, A.indices, A.indptr), shape=A.shape)
        self.shape = A.shape
        try:
            self._factor = cholmod.cholesky(A, mode="supernodal")
        except cholmod.CholmodError as exc:  # CholmodNotPositiveDefiniteError and others
            raise SolverError(
                f"CHOLMOD factorisation failed: matrix not positive definite or singular ({exc})"
            ) from exc
        self.nnz = int(A.nnz)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        return self._factor(np.asarray(b, dtype=np.float64))


class PardisoFactor(_Factor):
    """Supernodal sparse Cholesky ``P A Pᵀ = L Lᵀ`` by Intel MKL PARDISO through ``pypardiso``
    (the ``mkl`` wheel; matrix type 2, real symmetric positive definite: the upper triangle of
    ``A`` is passed, METIS nested-dissection ordering, OpenMP threads as set by
    :class:`blas_threads`). The factorisation and the solves with many right-hand sides run as
    dense block operations on the supernodes. No iterative refinement (PARDISO's default adds
    two refinement steps, three solves per call; a Cholesky solve of a positive-definite matrix
    needs none: the residual ``‖A x − b‖/‖b‖`` is 8e-16 without them on the 168 k-DOF interior of
    the power wheel). There, against :class:`CholmodFactor`: factorisation 9 s against 82 s CPU,
    a 128-column solve 4.1 s against 8.2 s CPU (one load-shared run,
    ``docs/bench/bench_body_build_backends.json``). The factor is released (PARDISO phase −1)
    when the object is collected.

    Raises:
        SolverError: ``A`` is not positive definite (PARDISO error −4) or PARDISO failed.
        ImportError: ``pypardiso`` or MKL is not installed (one line).
    """

    method = "pardiso"
    library = "pypardiso"
    # columns per solve: on the 168 k interior DOFs of the power wheel 256 columns took 8.1 s
    # of CPU in blocks of 64, 8.4 s in blocks of 128 (0.33 GiB more peak), 9.8 s in blocks of 32
    block = 64
    _ps = None  # PARDISO's handle (pypardiso.PyPardisoSolver) once made

    def __init__(self, A: sp.spmatrix):
        pypardiso = _optional_module("pypardiso")
        if pypardiso is None:
            raise ImportError(
                "fem_prep.PardisoFactor needs pypardiso (Intel MKL, x86-64): pip install pypardiso"
            )
        # the upper triangle in CSR (PARDISO's layout for symmetric types), sorted, float64,
        # with PARDISO's one-based int32 index arrays made once (pypardiso's _call_pardiso
        # would convert them, and copy the solution to C order, at every solve)
        U = sp.triu(sp.csr_matrix(A, dtype=np.float64), format="csr")
        U.sort_indices()
        if np.any(U.diagonal() <= 0):  # PARDISO's symmetric types need the whole diagonal
            raise SolverError(
                "PARDISO factorisation failed: matrix not positive definite (a diagonal entry <= 0)"
            )
        self.shape = U.shape
        self.nnz = int(U.nnz)
        self._data = U.data
        self._ia = (U.indptr + 1).astype(np.int32)
        self._ja = (U.indices + 1).astype(np.int32)
        del U
        self._ps = _pardiso_solver(pypardiso)  # loads MKL, holds PARDISO's handle
        self._call(12, np.zeros((self.shape[0], 1), order="F"))  # analysis and factorisation
        self._ps.iparm[7] = 0  # iparm(8): no iterative refinement in the solves

    def _call(self, phase: int, b: np.ndarray) -> np.ndarray:
        """One PARDISO call of ``phase`` on the held matrix and handle (the entry point and
        argument types as ``pypardiso.PyPardisoSolver`` declares them); ``b`` Fortran-ordered
        ``(n, k)``; returns ``x`` of the same shape and order."""
        ps = self._ps
        x = np.zeros_like(b, order="F")
        err = ctypes.c_int32(0)
        i32, f64 = ctypes.POINTER(ctypes.c_int32), ctypes.POINTER(ctypes.c_double)
        ps._mkl_pardiso(
            ps.pt.ctypes.data_as(ctypes.POINTER(ps._pt_type[0])),
            ctypes.byref(ctypes.c_int32(1)),  # maxfct
            ctypes.byref(ctypes.c_int32(1)),  # mnum
            ctypes.byref(ctypes.c_int32(2)),  # mtype: real symmetric positive definite
            ctypes.byref(ctypes.c_int32(phase)),
            ctypes.byref(ctypes.c_int32(self.shape[0])),
            self._data.ctypes.data_as(f64),
            self._ia.ctypes.data_as(i32),
            self._ja.ctypes.data_as(i32),
            ps.perm.ctypes.data_as(i32),
            ctypes.byref(ctypes.c_int32(b.shape[1] if b.ndim == 2 else 1)),  # nrhs
            ps.iparm.ctypes.data_as(i32),
            ctypes.byref(ctypes.c_int32(0)),  # msglvl
            b.ctypes.data_as(f64),
            x.ctypes.data_as(f64),
            ctypes.byref(err),
        )
        if err.value != 0:
            why = "matrix not positive definite" if err.value == -4 else "PARDISO failed"
            raise SolverError(f"PARDISO factorisation failed: {why} (error {err.value})")
        return x

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        b = np.asfortranarray(b, dtype=np.float64)
        if b.size == 0:
            return np.zeros(b.shape)
        return self._call(33, b)

    def __del__(self):
        if self._ps is not None:
            self._call(-1, np.zeros((0, 1), order="F"))  # release PARDISO's memory
            self._ps = None


#: the MKL runtime library (its path) of pypardiso's import-time handle, named to the handles
#: made here through pypardiso's PYPARDISO_MKL_RT
_MKL_RT: list[str] = []


def _pardiso_solver(pypardiso, mtype: int = 2):
    """``pypardiso.PyPardisoSolver(mtype=2)`` with MKL located once per process: pypardiso looks
    for ``mkl_rt`` at each construction and, where the linker does not find it (the ``mkl``
    wheel in a virtual environment), searches the environment's library folders recursively
    (0.2-0.4 s of CPU per handle; 25 handles took 6 of the 24 CPU s of three fem_prep test
    files). ``mtype``: PARDISO's matrix type (2: symmetric positive definite; -2: symmetric
    indefinite). The handles get the library of the one pypardiso makes as it is imported
    (``pypardiso.ps``) through ``PYPARDISO_MKL_RT``, set only while they are made; a
    ``PYPARDISO_MKL_RT`` of the caller's is left as it is and used."""
    if not _MKL_RT:
        _MKL_RT.append(pypardiso.ps.libmkl._name)
    if os.environ.get("PYPARDISO_MKL_RT"):
        return pypardiso.PyPardisoSolver(mtype=mtype)
    os.environ["PYPARDISO_MKL_RT"] = _MKL_RT[0]
    try:
        return pypardiso.PyPardisoSolver(mtype=mtype)
    finally:
        del os.environ["PYPARDISO_MKL_RT"]


def eigenvalue_count(K: sp.spmatrix, M: sp.spmatrix, sigma: float) -> int:
    """The number of eigenvalues of ``K φ = λ M φ`` below ``sigma`` (``M`` positive definite):
    by Sylvester's law of inertia, the number of negative pivots of the ``L D Lᵀ``
    factorisation of ``K − σ M`` (the Sturm sequence check of FE eigen-solvers). The
    factorisation is MKL PARDISO's for real symmetric indefinite matrices (``pypardiso``, matrix
    type −2: Bunch–Kaufman pivoting, METIS ordering); PARDISO reports the inertia
    (``iparm(23)``: negative eigenvalues). The factor is released before the return.

    Args:
        K, M: sparse symmetric ``(n, n)``.
        sigma: the shift ((rad/s)²).

    Returns:
        The count, ``0 <= count <= n``.

    Raises:
        ImportError: ``pypardiso`` is not installed (one line).
        SolverError: PARDISO failed, ``K − σ M`` is singular to working precision (a pivot
            was perturbed: an eigenvalue at ``sigma``), or the inertia does not add up to
            ``n``.
    """
    pypardiso = _optional_module("pypardiso")
    if pypardiso is None:
        raise ImportError(
            "fem_prep.eigenvalue_count needs pypardiso (Intel MKL): pip install pypardiso"
        )
    A = sp.triu(sp.csr_matrix(K, dtype=np.float64) - sigma * sp.csr_matrix(M), format="csr")
    A.sort_indices()
    n = A.shape[0]
    ps = _pardiso_solver(pypardiso, mtype=-2)
    try:
        ps.factorize(A)  # phases 1-2: analysis and numerical factorisation
    except pypardiso.pardiso_wrapper.PyPardisoError as exc:
        raise SolverError(f"PARDISO LDL^T factorisation failed ({exc})") from exc
    finally:
        del A
        ps.remove_stored_factorization()
    positive, negative, perturbed = (int(ps.get_iparm(i)) for i in (22, 23, 14))
    ps.free_memory(everything=True)
    if perturbed or positive + negative != n:
        raise SolverError(
            f"PARDISO LDL^T of K - sigma M: {perturbed} perturbed pivots, inertia "
            f"({positive}, {negative}) of n = {n}: an eigenvalue at sigma = {sigma:g}?"
        )
    return negative


def _optional_module(name: str):
    """The module ``name`` of an optional dependency, or ``None`` when it cannot be imported
    (looked up at each call, so that a test can hide it through ``sys.modules``)."""
    try:
        return importlib.import_module(name)
    except ImportError:
        return None


_FACTORS = (CholmodFactor, PardisoFactor, SparseFactor, SupernodalFactor)
Factor = CholmodFactor | PardisoFactor | SparseFactor | SupernodalFactor


def factorize(A: sp.spmatrix, *, method: type[Factor] | None = None) -> Factor:
    """Factorise a sparse symmetric positive-definite matrix.

    Args:
        A: ``(n, n)`` sparse matrix.
        method: the factor class, :class:`SupernodalFactor` (CHOLMOD by scikit-sparse),
            :class:`PardisoFactor` (MKL PARDISO by pypardiso), :class:`CholmodFactor` (CHOLMOD
            by cholespy) or :class:`SparseFactor` (SuperLU); ``None``: the first of these whose
            library imports (SuperLU with a :class:`SolverWarning`).

    Returns:
        A factor with ``solve(B)``, ``operator()``, ``method`` (the algorithm that ran:
        ``"cholmod"``, ``"pardiso"`` or ``"superlu"``), ``library`` and ``block``.

    Raises:
        SolverError: the matrix is not positive definite (CHOLMOD, PARDISO) or singular
            (SuperLU).
        ValueError: ``method`` is not a factor class.
    """
    if method is not None and method not in _FACTORS:
        raise ValueError(
            f"method = {method!r}; use fem_prep.SupernodalFactor, fem_prep.PardisoFactor, "
            "fem_prep.CholmodFactor, fem_prep.SparseFactor or None"
        )
    return (method or _available_factor())(A)


def _available_factor() -> type[Factor]:
    """CHOLMOD by scikit-sparse (supernodal) when it imports, else MKL PARDISO by ``pypardiso``
    (supernodal), else CHOLMOD by ``cholespy`` (simplicial), else SuperLU with a
    :class:`SolverWarning`."""
    if _optional_module("sksparse.cholmod") is not None:
        return SupernodalFactor
    if _optional_module("pypardiso") is not None:
        return PardisoFactor
    if _optional_module("cholespy") is not None:
        return CholmodFactor
    warnings.warn(
        "neither pypardiso (MKL PARDISO) nor cholespy (CHOLMOD) is installed: using SciPy's "
        "SuperLU, slower on large bodies (pip install pypardiso cholespy)",
        SolverWarning,
        stacklevel=3,
    )
    return SparseFactor


class EigenSolver(abc.ABC):
    """An algorithm for the lowest modes of ``K φ = λ M φ`` in shift-invert mode (a kind: pass
    an instance as :func:`shift_invert_modes`' ``solver``). Subclasses implement
    :meth:`ritz`."""

    name: ClassVar[str]

    @abc.abstractmethod
    def ritz(
        self, K, M, k: int, sigma: float, op: spla.LinearOperator, tol: float
    ) -> tuple[np.ndarray, np.ndarray]:
        """``k`` approximate eigenpairs ``(lam (k,), phi (n, k))`` (any order, any scaling);
        ``op`` applies ``(K − σ M)⁻¹`` to a vector or a block ``(n, p)``.

        Raises:
            SolverError: no convergence.
        """

    def __repr__(self) -> str:
        return f"fem_prep.{type(self).__name__}()"


@final
class Lanczos(EigenSolver):
    """SciPy's ``eigsh`` (ARPACK, implicitly restarted Lanczos) in shift-invert mode with the
    factor as ``OPinv``: one vector per factor solve, ``ncv = max(2k + 1, k + 40)``. The
    default."""

    name: ClassVar[str] = "lanczos"

    def ritz(self, K, M, k, sigma, op, tol):
        n = K.shape[0]
        ncv = min(n, max(2 * k + 1, k + 40))
        try:
            return spla.eigsh(K, k=k, M=M, sigma=sigma, OPinv=op, which="LM", ncv=ncv, tol=tol)
        except spla.ArpackNoConvergence as exc:
            raise SolverError(
                f"eigsh did not converge: {len(exc.eigenvalues)} of {k} modes after the "
                f"iteration limit (ncv = {ncv})"
            ) from exc


@final
class BlockLanczos(EigenSolver):
    """Block shift-invert Lanczos: the Krylov space of ``(K − σ M)⁻¹ M`` grown ``block``
    vectors per factor solve (one ``solve`` call on an ``(n, block)`` right-hand side: BLAS-3 on
    a supernodal factor): the block three-term recurrence, then one classical Gram-Schmidt pass
    against the whole basis (full M-reorthogonalisation) and Cholesky QR twice within the block,
    with ``M V`` kept beside the basis ``V`` (one product with ``M`` per block), no restart;
    after each block a Rayleigh-Ritz step on the basis, stopped when the lowest ``k`` Ritz pairs
    meet ARPACK's criterion (the Ritz estimate ``‖(K − σM)⁻¹Mφ − θφ‖_M ≤ tol θ``, ``θ = 1/(λ −
    σ)``, from the residual block: no extra products). Without convergence within
    ``max_columns`` basis vectors (default ``max(8 k, 256) + 8 block``; memory ``2 n`` doubles
    per basis vector reached: ``V`` and ``M V``) it raises :class:`SolverError`, and
    :func:`shift_invert_modes` falls back to :class:`Lanczos` with a :class:`SolverWarning`.
    The default eigen-solver of :class:`~fem_prep.CraigBampton`.

    Args:
        block: vectors per factor solve (>= 1).
        max_columns: basis size limit (>= 1), or ``None``.

    Raises:
        ValueError: ``block < 1`` or ``max_columns < 1``.
    """

    name: ClassVar[str] = "block-lanczos"

    def __init__(self, block: int = 8, max_columns: int | None = None):
        if not (isinstance(block, int | np.integer) and block >= 1):
            raise ValueError(f"block = {block!r}: an integer >= 1 (vectors per factor solve)")
        if max_columns is not None and not (
            isinstance(max_columns, int | np.integer) and max_columns >= 1
        ):
            raise ValueError(f"max_columns = {max_columns!r}: an integer >= 1 or None")
        self.block, self.max_columns = int(block), max_columns

    def __repr__(self) -> str:
        return f"fem_prep.BlockLanczos(block={self.block}, max_columns={self.max_columns})"

    def ritz(self, K, M, k, sigma, op, tol):
        n = K.shape[0]
        p = min(self.block, n)
        cap = min(n, self.max_columns or max(8 * k, 256) + 8 * p)
        # the M-orthonormal basis V and M V (kept: one product with M per block, on the new
        # residual block; the coefficients V^T M X are (M V)^T X); np.empty: the columns not
        # reached take no memory
        V, MV = np.empty((n, cap), order="F"), np.empty((n, cap), order="F")
        T = np.zeros((cap, cap))  # V^T M op M V (the projected operator)
        X = np.random.default_rng(0).standard_normal((n, p))
        MX = M @ X
        m, worst = 0, np.inf
        while m + p <= cap:
            X, MX = _m_orthonormalise(X, MX, m)
            V[:, m : m + p], MV[:, m : m + p] = X, MX
            W = op @ MX  # one solve of p right-hand sides
            # the block three-term recurrence (T is block tridiagonal): the last two blocks
            lo = max(0, m - p)
            C = np.zeros((m + p, p))
            C[lo:] = MV[:, lo : m + p].T @ W  # V^T M W
            m += p
            X = W - V[:, lo:m] @ C[lo:]  # op M V = V T + R E^T (block Krylov): the residual R
            # the block's one product with M, on the residual itself: M W − (M V) C would
            # lose the residual's digits to cancellation once the Ritz pairs converge
            MX = M @ X
            # full reorthogonalisation: one classical Gram-Schmidt pass against all of V (the
            # recurrence's loss of orthogonality grows as the Ritz pairs converge)
            D = MV[:, :m].T @ X
            X -= V[:, :m] @ D
            MX -= MV[:, :m] @ D
            C += D
            T[:m, m - p : m] = C
            T[m - p : m, : m - p] = C[: m - p].T
            if m >= k:
                theta, Y = np.linalg.eigh(0.5 * (T[:m, :m] + T[:m, :m].T))
                theta, Y = theta[::-1][:k], Y[:, ::-1][:, :k]
                Yl = Y[m - p : m]  # the last block's rows: the Ritz estimates ‖R Yl‖_M
                est = np.sqrt(np.maximum(np.einsum("ij,ij->j", Yl, (X.T @ MX) @ Yl), 0))
                worst = float(np.max(est / np.abs(theta)))
                if worst <= tol:
                    return sigma + 1.0 / theta, V[:, :m] @ Y
        raise SolverError(
            f"block Lanczos did not converge: largest Ritz estimate {worst:.3g} > tol = "
            f"{tol:g} after {m} basis vectors (max_columns = {cap})"
        )


def _m_orthonormalise(X: np.ndarray, MX: np.ndarray, m: int) -> tuple[np.ndarray, np.ndarray]:
    """``X`` (with ``M X``), already M-orthogonal to the basis, M-orthonormalised within
    (Cholesky QR, twice), with its ``M X`` by the same combination (``M (X R⁻¹) = (M X) R⁻¹``:
    no product with ``M``).

    Raises:
        SolverError: the block lost rank (an invariant subspace, or a dependent block).
    """
    for _ in range(2):
        try:
            R = np.linalg.cholesky(0.5 * (X.T @ MX + MX.T @ X)).T
        except np.linalg.LinAlgError as exc:
            raise SolverError(
                f"block Lanczos: the block of {X.shape[1]} vectors lost rank after {m} basis "
                "vectors"
            ) from exc
        X = sla.solve_triangular(R, X.T, trans="T").T
        MX = sla.solve_triangular(R, MX.T, trans="T").T
    return X, MX


def _relative_residuals(K, M, lam: np.ndarray, phi: np.ndarray, sigma: float) -> np.ndarray:
    """``‖K φ − λ M φ‖ / (max(|λ|, |σ|) ‖M φ‖)`` per column (scale-free)."""
    Mphi = M @ phi
    scale = np.maximum(np.abs(lam), max(abs(sigma), 1e-30))
    return np.linalg.norm(K @ phi - Mphi * lam, axis=0) / (scale * np.linalg.norm(Mphi, axis=0))


def shift_invert_modes(
    K: sp.spmatrix,
    M: sp.spmatrix,
    k: int,
    *,
    sigma: float = 0.0,
    factor: Factor | None = None,
    tol: float = 1e-10,
    check: float = 1e-6,
    on_solve: Callable[[], None] | None = None,
    solver: EigenSolver | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``k`` modes of ``K φ = λ M φ`` in shift-invert mode.

    Degenerate pairs (nodal-diameter modes of an axisymmetric body) are returned with both
    members: ARPACK's implicitly restarted Lanczos with ``ncv ≥ 2k + 1`` resolves them (checked
    by the tests on an exactly axisymmetric disc), and so does the block Lanczos (a block of
    ``p ≥ 2`` vectors).

    Args:
        K, M: sparse symmetric stiffness/mass ``(n, n)``.
        k: number of modes.
        sigma: shift ((rad/s)²), negative for free structures (rigid-body modes).
        factor: a factorisation of ``K − σ M`` to reuse.
        tol: ARPACK relative tolerance on the Ritz values (:class:`Lanczos`).
        check: bound on the relative residual of every returned mode.
        on_solve: called after each factor solve (one per Lanczos step, one per block of the
            block Lanczos: a progress bar's hook).
        solver: the eigen-solver, :class:`Lanczos` (ARPACK ``eigsh``; ``None``: the default)
            or :class:`BlockLanczos` (``block`` vectors per solve); a block solver that does not
            converge falls back to :class:`Lanczos` with a :class:`SolverWarning` saying why.

    Returns:
        ``(lam, phi)``: eigenvalues ``(k,)`` ascending ((rad/s)²) and mass-normalised modes
        ``(n, k)``.

    Raises:
        SolverError: ARPACK did not converge, or a mode's residual exceeds ``check``.
        ValueError: ``solver`` is not an eigen-solver.
    """
    solver = Lanczos() if solver is None else solver
    if not isinstance(solver, EigenSolver):
        raise ValueError(
            f"solver = {solver!r}; use fem_prep.Lanczos(), fem_prep.BlockLanczos() or None"
        )
    n = K.shape[0]
    if k <= 0:
        return np.zeros(0), np.zeros((n, 0))
    if k >= n - 1 or n < 400:
        lam, phi = sla.eigh(K.toarray(), M.toarray())
        return lam[:k], phi[:, :k]
    if factor is None:
        factor = factorize((K - sigma * M).tocsr())
    op = _counted(factor.operator(), on_solve)

    def modes(tol):
        try:
            lam, phi = solver.ritz(K, M, k, sigma, op, tol)
        except SolverError as exc:
            if isinstance(solver, Lanczos):
                raise
            warnings.warn(
                f"{solver!r} failed ({exc}): falling back to fem_prep.Lanczos (ARPACK eigsh)",
                SolverWarning,
                stacklevel=3,
            )
            lam, phi = Lanczos().ritz(K, M, k, sigma, op, tol)
        order = np.argsort(lam)
        lam, phi = lam[order], phi[:, order]
        Mphi = M @ phi
        mm = np.einsum("ij,ij->j", phi, Mphi)
        return lam, phi / np.sqrt(mm), Mphi / np.sqrt(mm)

    lam, phi, Mphi = modes(tol)
    res = _relative_residuals(K, M, lam, phi, sigma)
    if np.any(res > check) and not isinstance(solver, Lanczos):
        # the block solver stops on its Ritz estimates in the shifted-inverted space, which
        # bound the residual of K phi - lam M phi only up to the spectrum's spread (on a
        # 4176-DOF disc: estimates <= 1e-10 left residuals of 8e-7 to 1.5e-6, by the
        # factorisation's library and the machine; 1e-13 left 1e-10, ARPACK's): once more,
        # 1000x tighter, before the check refuses
        lam, phi, Mphi = modes(tol * 1e-3)
        res = _relative_residuals(K, M, lam, phi, sigma)
    if np.any(res > check):
        raise SolverError(
            f"{solver.name} returned modes with relative residual up to {res.max():.3g} > "
            f"{check:g}"
        )
    if sigma < 0 and k < n - 50:
        # a free structure: Lanczos can miss a member of the six-fold zero eigenvalue (it sees a
        # multiple eigenvalue once; rounding brings the others back, usually); search again
        # M-orthogonally to the modes found and merge anything lower

        def deflated(x: np.ndarray) -> np.ndarray:
            y = op @ x
            return y - phi @ (Mphi.T @ y)

        k2 = min(6, n - k - 2)
        A = spla.LinearOperator((n, n), matvec=deflated, dtype=float)
        try:
            lam2, phi2 = spla.eigsh(
                K, k=k2, M=M, sigma=sigma, OPinv=A, which="LM", ncv=min(n, 2 * k2 + 20), tol=tol
            )
        except spla.ArpackNoConvergence:  # pragma: no cover - the first pass converged
            return lam, phi
        m2 = np.einsum("ij,ij->j", phi2, M @ phi2)
        lost = lam2 < lam[-1] - 1e-9 * max(abs(lam[-1]), abs(sigma))
        if np.any(lost):
            lam = np.concatenate([lam, lam2[lost]])
            phi = np.hstack([phi, phi2[:, lost] / np.sqrt(m2[lost])])
            order = np.argsort(lam)[:k]
            lam, phi = lam[order], phi[:, order]
    return lam, phi


@contextlib.contextmanager
def phase_bar(desc: str, progress: bool) -> Iterator[tqdm]:
    """A one-step bar (removed when done) naming a long single call, a factorisation, while
    it runs."""
    with tqdm(total=1, desc=desc, disable=not progress, leave=False, unit="call") as bar:
        yield bar
        bar.update()


def solve_bar(desc: str, progress: bool) -> tqdm:
    """A bar (removed when done) counting the solves of an eigen-solve, whose number is not
    known in advance: pass its ``update`` as :func:`shift_invert_modes`' ``on_solve``."""
    return tqdm(desc=desc, disable=not progress, unit="solve", leave=False)


def _counted(op: spla.LinearOperator, on_solve: Callable[[], None] | None):
    """``op`` itself, or the same operator calling ``on_solve`` after each application."""
    if on_solve is None:
        return op

    def apply(x: np.ndarray) -> np.ndarray:
        y = op @ x
        on_solve()
        return y

    return spla.LinearOperator(op.shape, matvec=apply, matmat=apply, dtype=op.dtype)


class blas_threads:
    """Context manager setting the BLAS thread count (``threadpoolctl``).

    ``n=None`` picks the CPUs the other processes leave, ``cpu_count − (load average − 1)``
    (at least 1; the calling process, busy until now, is one unit of the load average):
    multithreaded BLAS on a busy machine spin-waits and can be much slower than one thread.
    Does nothing when ``OPENBLAS_NUM_THREADS`` or ``OMP_NUM_THREADS`` is set by the user.
    """

    def __init__(self, n: int | None = None):
        self._n = n
        if n is None:
            cpus = os.cpu_count() or 1
            try:
                load = os.getloadavg()[0]
            except OSError:
                load = 0.0
            self._n = max(1, min(cpus, int(cpus - max(load - 1.0, 0.0) + 0.5)))
        self._limits = None

    def __enter__(self) -> blas_threads:
        if os.environ.get("OPENBLAS_NUM_THREADS") or os.environ.get("OMP_NUM_THREADS"):
            return self
        # the limit reaches the BLAS libraries loaded now: load the supernodal CHOLMOD's and
        # MKL's (PARDISO's threads) first (its BLAS spin-waits on a busy machine: the
        # eigen-solve of a 30 k-DOF wheel took 4.7x longer with two threads than with one at
        # load 9)
        _optional_module("sksparse.cholmod")
        _optional_module("pypardiso")
        self._limits = threadpool_limits(limits=int(self._n), user_api="blas")
        return self

    def __exit__(self, *exc) -> None:
        if self._limits is not None:
            self._limits.restore_original_limits()
            self._limits = None
