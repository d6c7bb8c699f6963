"""Linear solvers and eigen-solvers for swept gear bodies.

Two factorisations share one interface (``solve(B)`` for ``B`` of shape ``(n,)`` or ``(n, k)``):

* :class:`SparseFactor`: SciPy's SuperLU (``splu``) with a symmetric minimum-degree ordering;
  used for any matrix (beams, plates, tests) and as the fallback.
* :class:`CyclicFactor`: dense-block Cholesky (LAPACK through ``scipy.linalg``) exploiting the
  structure of a body swept around its axis.  Ordering the DOFs by angular slab makes the matrix
  block-tridiagonal with cyclic closure, plus a dense "tail" (the last slab, the bearing DOFs and
  any DOF coupled beyond its neighbouring slabs).  The factor costs about ``5 P s^3`` flops
  (``P`` slabs of ``s`` DOFs) and its triangular solves are BLAS-3 on many right-hand sides,
  which is what the ~1300 constraint modes of a condensation need: 5-10x faster than SuperLU's
  multi-RHS solve on the wheels of the benchmark.

Eigen-solves: :func:`shift_invert_modes` uses SciPy's shift-invert ``eigsh`` with a
:class:`SparseFactor`, and a block shift-invert Krylov / Rayleigh-Ritz iteration with a
:class:`CyclicFactor` (BLAS-3 solves, same answer to the residual tolerance).
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["CyclicFactor", "SparseFactor", "factorize", "shift_invert_modes"]


class SparseFactor:
    """SuperLU factorisation (symmetric mode) of a sparse symmetric matrix."""

    def __init__(self, A: sp.spmatrix):
        A = sp.csc_matrix(A)
        self.shape = A.shape
        self._lu = spla.splu(
            A, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
        )
        self.nnz = int(self._lu.L.nnz + self._lu.U.nnz)

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        return self._lu.solve(np.asarray(b, dtype=float))

    def operator(self) -> spla.LinearOperator:
        """``A^-1`` as a LinearOperator."""
        return spla.LinearOperator(self.shape, matvec=self.solve, dtype=float)


class CyclicFactor:
    """Block Cholesky of a symmetric positive-definite matrix with cyclic slab structure.

    Args:
        A: sparse symmetric positive-definite ``(n, n)``.
        slabs: slab label ``(n,)`` of each DOF in ``0..P-1`` (angular sector of its node), or -1
            for DOFs that belong to the dense tail (bearing nodes).

    Raises:
        ValueError: fewer than 4 slabs, or a tail larger than ``max_tail`` DOFs.
        numpy.linalg.LinAlgError: the matrix is not positive definite.
    """

    def __init__(self, A: sp.spmatrix, slabs: np.ndarray, *, max_tail: int = 6000):
        A = sp.csr_matrix(A)
        n = A.shape[0]
        self.shape = A.shape
        lab = np.asarray(slabs, dtype=np.int64).copy()
        P = int(lab.max()) + 1
        if P < 4:
            raise ValueError("CyclicFactor needs at least 4 slabs")
        # DOFs coupled beyond their neighbouring slabs go to the tail
        coo = A.tocoo()
        r, c = coo.row, coo.col
        both = (lab[r] >= 0) & (lab[c] >= 0)
        d = np.mod(lab[r] - lab[c], P)
        bad = both & (d != 0) & (d != 1) & (d != P - 1)
        lab[np.unique(r[bad])] = -1
        lab[lab == P - 1] = -1
        if np.sum(lab < 0) > max_tail:
            raise ValueError(f"tail of {np.sum(lab < 0)} DOFs > max_tail = {max_tail}")
        groups = [np.nonzero(lab == p)[0] for p in range(P - 1)]
        groups = [g for g in groups if len(g)]
        tail = np.nonzero(lab < 0)[0]
        perm = np.concatenate(groups + [tail])
        bounds = np.cumsum([0] + [len(g) for g in groups] + [len(tail)])
        self._perm = perm
        self._bounds = bounds
        Ap = A[perm][:, perm].tocsr()
        t0, t1 = bounds[-2], bounds[-1]
        At = Ap[t0:t1].tocsc()
        nb = len(groups)
        Dt = At[:, t0:t1].toarray()
        self._L, self._Ln, self._LT = [], [], []
        Dp = Ap[bounds[0] : bounds[1], bounds[0] : bounds[1]].toarray()
        Ct = At[:, bounds[0] : bounds[1]].toarray()
        for p in range(nb):
            a0, a1 = bounds[p], bounds[p + 1]
            L = sla.cholesky(Dp, lower=True, overwrite_a=True, check_finite=False)
            LT = sla.solve_triangular(L, Ct.T, lower=True, check_finite=False).T
            Dt -= LT @ LT.T
            if p < nb - 1:
                b1 = bounds[p + 2]
                E = Ap[a1:b1, a0:a1].toarray()
                Ln = sla.solve_triangular(L, E.T, lower=True, check_finite=False).T
                Dp = Ap[a1:b1, a1:b1].toarray() - Ln @ Ln.T
                Ct = At[:, a1:b1].toarray() - LT @ Ln.T
            else:
                Ln = np.zeros((0, a1 - a0))
            self._L.append(L)
            self._Ln.append(Ln)
            self._LT.append(LT)
        self._LTT = sla.cholesky(Dt, lower=True, check_finite=False)
        self.nnz = int(
            sum(x.size for x in self._L)
            + sum(x.size for x in self._Ln)
            + sum(x.size for x in self._LT)
            + self._LTT.size
        )
        del n

    def solve(self, b: np.ndarray) -> np.ndarray:
        """Solve ``A x = b``, ``b`` of shape ``(n,)`` or ``(n, k)``."""
        b = np.asarray(b, dtype=float)
        vec = b.ndim == 1
        B = b[self._perm].reshape(len(self._perm), -1)
        bd = self._bounds
        nb = len(self._L)
        y = [None] * nb
        bt = B[bd[-2] : bd[-1]].copy()
        prev = None
        for p in range(nb):
            rhs = B[bd[p] : bd[p + 1]]
            if prev is not None:
                rhs = rhs - self._Ln[p - 1] @ prev
            yp = sla.solve_triangular(self._L[p], rhs, lower=True, check_finite=False)
            bt -= self._LT[p] @ yp
            y[p] = yp
            prev = yp
        yt = sla.solve_triangular(self._LTT, bt, lower=True, check_finite=False)
        xt = sla.solve_triangular(self._LTT, yt, lower=True, trans="T", check_finite=False)
        X = np.empty_like(B)
        X[bd[-2] : bd[-1]] = xt
        nxt = None
        for p in range(nb - 1, -1, -1):
            rhs = y[p] - self._LT[p].T @ xt
            if nxt is not None:
                rhs -= self._Ln[p].T @ nxt
            xp = sla.solve_triangular(self._L[p], rhs, lower=True, trans="T", check_finite=False)
            X[bd[p] : bd[p + 1]] = xp
            nxt = xp
        out = np.empty_like(X)
        out[self._perm] = X
        return out[:, 0] if vec else out

    def operator(self) -> spla.LinearOperator:
        """``A^-1`` as a LinearOperator."""
        return spla.LinearOperator(self.shape, matvec=self.solve, dtype=float)


def factorize(A: sp.spmatrix, slabs: np.ndarray | None = None) -> SparseFactor | CyclicFactor:
    """Factorise a sparse symmetric positive-definite matrix.

    Args:
        A: ``(n, n)`` sparse matrix.
        slabs: angular slab label per DOF (see :class:`CyclicFactor`) or ``None`` for SuperLU.

    Returns:
        A factor with ``solve(B)``.
    """
    if slabs is not None and A.shape[0] > 20000:
        try:
            return CyclicFactor(A, slabs)
        except ValueError:
            pass
    return SparseFactor(A)


def _block_krylov(
    K: sp.spmatrix,
    M: sp.spmatrix,
    k: int,
    factor: CyclicFactor,
    sigma: float,
    tol: float,
    max_dim: int,
    seed: int = 0,
) -> tuple[np.ndarray, np.ndarray]:
    n = K.shape[0]
    bs = min(n, k + max(8, k // 4))
    rng = np.random.default_rng(seed)
    W = factor.solve(M @ rng.standard_normal((n, bs)))
    V = np.zeros((n, 0))
    MV = np.zeros((n, 0))
    Kr = np.zeros((0, 0))
    while True:
        for _ in range(2):  # M-orthogonalise against the basis (CGS2)
            if V.shape[1]:
                W -= V @ (MV.T @ W)
        G = W.T @ (M @ W)
        d, U = np.linalg.eigh(0.5 * (G + G.T))
        keep = d > 1e-12 * d.max()
        W = W @ (U[:, keep] / np.sqrt(d[keep]))
        MW = M @ W
        KW = K @ W
        # incremental Rayleigh-Ritz matrix V^T K V
        cross = V.T @ KW
        Kr = np.block([[Kr, cross], [cross.T, W.T @ KW]])
        del KW
        V = np.hstack([V, W])
        MV = np.hstack([MV, MW])
        theta, Y = np.linalg.eigh(0.5 * (Kr + Kr.T))
        lam = theta[:k]
        phi = V @ Y[:, :k]
        Mphi = MV @ Y[:, :k]
        R = K @ phi - Mphi * lam
        scale = max(abs(theta[k - 1]), abs(sigma), 1e-30)
        res = np.linalg.norm(R, axis=0) / (scale * np.linalg.norm(Mphi, axis=0))
        if np.all(res < tol) or V.shape[1] + bs > max_dim:
            return lam, phi
        del phi, Mphi, R
        W = factor.solve(MW)


def shift_invert_modes(
    K: sp.spmatrix,
    M: sp.spmatrix,
    k: int,
    *,
    sigma: float = 0.0,
    factor: SparseFactor | CyclicFactor | None = None,
    tol: float = 1e-10,
    solver: str = "block",
) -> tuple[np.ndarray, np.ndarray]:
    """Lowest ``k`` modes of ``K phi = lambda M phi`` by shift-invert.

    ``solver="block"`` (default): block shift-invert Krylov iteration with Rayleigh-Ritz
    (BLAS-3 solves with the factor of ``K - sigma M``; a block method resolves the degenerate
    pairs of nodal-diameter modes, which single-vector Lanczos may return only once).
    ``solver="eigsh"``: SciPy's ``eigsh`` in shift-invert mode with the factor as ``OPinv``.

    Args:
        K, M: sparse symmetric stiffness/mass ``(n, n)``.
        k: number of modes.
        sigma: shift ((rad/s)^2), negative for free structures (rigid-body modes).
        factor: a factorisation of ``K - sigma M`` to reuse.
        tol: relative tolerance (eigsh); the block iteration stops at a relative residual
            ``max(1e4 tol, 1e-6)`` (eigenvalue error ~ residual squared).
        solver: ``"block"`` or ``"eigsh"``.

    Returns:
        ``(lam, phi)``: eigenvalues ``(k,)`` ascending ((rad/s)^2) and mass-normalised modes
        ``(n, k)``.
    """
    n = K.shape[0]
    if k <= 0:
        return np.zeros(0), np.zeros((n, 0))
    if k >= n - 1 or n < 400:
        lam, phi = sla.eigh(K.toarray(), M.toarray())
        return lam[:k], phi[:, :k]
    if factor is None:
        factor = factorize(K - sigma * M)
    if solver == "block":
        lam, phi = _block_krylov(
            K, M, k, factor, sigma, tol=max(tol * 1e4, 1e-6), max_dim=min(n, 8 * (k + 10))
        )
    else:
        ncv = min(n, max(2 * k + 1, k + 40))
        lam, phi = spla.eigsh(
            K, k=k, M=M, sigma=sigma, OPinv=factor.operator(), which="LM", ncv=ncv, tol=tol
        )
    order = np.argsort(lam)
    lam, phi = lam[order], phi[:, order]
    mm = np.einsum("ij,ij->j", phi, M @ phi)
    return lam, phi / np.sqrt(mm)


# ------------------------------------------------------------------------------------------
# BLAS thread control (no threadpoolctl dependency)


def _openblas_setters() -> list:
    """``(get, set)`` ctypes pairs of the OpenBLAS libraries bundled with NumPy and SciPy."""
    import ctypes
    import glob
    import os

    import scipy

    pairs = []
    for mod in (np, scipy):
        libdir = os.path.join(os.path.dirname(mod.__file__), "..", f"{mod.__name__}.libs")
        for path in glob.glob(os.path.join(libdir, "*openblas*")):
            try:
                lib = ctypes.CDLL(path)
            except OSError:
                continue
            for get, set_ in (
                ("scipy_openblas_get_num_threads64_", "scipy_openblas_set_num_threads64_"),
                ("scipy_openblas_get_num_threads", "scipy_openblas_set_num_threads"),
                ("openblas_get_num_threads64_", "openblas_set_num_threads64_"),
                ("openblas_get_num_threads", "openblas_set_num_threads"),
            ):
                if hasattr(lib, get) and hasattr(lib, set_):
                    pairs.append((getattr(lib, get), getattr(lib, set_)))
                    break
    return pairs


_SETTERS: list | None = None


class blas_threads:
    """Context manager setting the OpenBLAS thread count of NumPy and SciPy.

    ``n=None`` picks ``cpu_count - load average`` (at least 1): multithreaded BLAS on a busy
    machine spin-waits and can be 10x slower than one thread on the small dense blocks of
    :class:`CyclicFactor`.  Does nothing when ``OPENBLAS_NUM_THREADS`` is set by the user or
    the libraries cannot be found.
    """

    def __init__(self, n: int | None = None):
        import os

        self._n = n
        if n is None:
            cpus = os.cpu_count() or 1
            try:
                load = os.getloadavg()[0]
            except OSError:
                load = 0.0
            self._n = max(1, min(cpus, int(cpus - load + 0.5)))
        self._old: list[int] = []

    def __enter__(self) -> blas_threads:
        import os

        global _SETTERS
        if os.environ.get("OPENBLAS_NUM_THREADS"):
            return self
        if _SETTERS is None:
            _SETTERS = _openblas_setters()
        self._old = [int(get()) for get, _ in _SETTERS]
        for _, set_ in _SETTERS:
            set_(int(self._n))
        return self

    def __exit__(self, *exc) -> None:
        if _SETTERS and self._old:
            for (_, set_), n in zip(_SETTERS, self._old):
                set_(n)
