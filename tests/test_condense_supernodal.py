"""The factor libraries of the condensation: CHOLMOD's supernodal factor (scikit-sparse, when
installed), cholespy's simplicial CHOLMOD and SciPy's SuperLU give the same solves, and the same
Craig-Bampton condensation as a dense reference (Schur complement, fixed-interface modes by
``scipy.linalg.eigh``) on a small grid Laplacian."""

import sys

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from fem_prep import (
    CholmodFactor,
    CraigBampton,
    SolverError,
    SparseFactor,
    SupernodalFactor,
    condense,
    factorize,
)

try:
    import sksparse.cholmod  # noqa: F401 - the optional supernodal CHOLMOD
except ImportError:
    HAVE_SKSPARSE = False
else:
    HAVE_SKSPARSE = True

needs_sksparse = pytest.mark.skipif(not HAVE_SKSPARSE, reason="scikit-sparse is not installed")
FACTORS = [
    pytest.param(SupernodalFactor, marks=needs_sksparse, id="supernodal"),
    pytest.param(CholmodFactor, id="cholespy"),
    pytest.param(SparseFactor, id="superlu"),
]


def grid(m: int = 10):
    """Stiffness (a 3D grid Laplacian plus a small multiple of the identity) and a consistent
    1D-mass-like tridiagonal-product mass of an m^3 grid; the master DOFs: the face z = 0."""
    e = np.ones(m)
    lap = sp.diags([-e[1:], 2 * e, -e[1:]], [-1, 0, 1])
    mass = sp.diags([e[1:] / 6, 4 * e / 6, e[1:] / 6], [-1, 0, 1])
    eye = sp.eye(m)
    K = (
        sp.kron(sp.kron(lap, eye), eye)
        + sp.kron(sp.kron(eye, lap), eye)
        + sp.kron(sp.kron(eye, eye), lap)
    )
    K = (K + 1e-3 * sp.eye(m**3)).tocsr()
    M = sp.kron(sp.kron(mass, mass), mass).tocsr()
    masters = np.arange(m * m) * m  # the z = 0 face (the last index runs fastest)
    return K, M, masters


@pytest.mark.parametrize("cls", FACTORS)
def test_factor_solves_match_dense(cls):
    """One and 130 right-hand sides (more than one 128-column block) against a dense solve;
    ``block``, ``method`` and ``library`` name what ran."""
    K, _, _ = grid(8)
    f = factorize(K, method=cls)
    rng = np.random.default_rng(0)
    B = rng.standard_normal((K.shape[0], 130))
    ref = sla.solve(K.toarray(), B, assume_a="pos")
    np.testing.assert_allclose(f.solve(B), ref, rtol=0, atol=1e-10 * np.abs(ref).max())
    np.testing.assert_allclose(f.solve(B[:, 0]), ref[:, 0], rtol=0, atol=1e-10 * np.abs(ref).max())
    assert f.method in ("cholmod", "superlu") and f.library and f.block >= 1


@needs_sksparse
def test_supernodal_factor_refuses_an_indefinite_matrix():
    A = sp.diags(np.r_[np.ones(49), -1.0]).tocsr()
    with pytest.raises(SolverError, match="not positive definite"):
        factorize(A, method=SupernodalFactor)


def test_supernodal_factor_without_scikit_sparse_says_so():
    saved = sys.modules.get("sksparse.cholmod")
    sys.modules["sksparse.cholmod"] = None  # import fails
    try:
        with pytest.raises(ImportError, match="pip install scikit-sparse"):
            factorize(sp.eye(10).tocsr(), method=SupernodalFactor)
    finally:
        if saved is None:
            del sys.modules["sksparse.cholmod"]
        else:
            sys.modules["sksparse.cholmod"] = saved


@pytest.mark.parametrize("cls", FACTORS)
def test_craig_bampton_matches_the_dense_reference(cls):
    """The condensed stiffness's boundary block is the Schur complement K_bb - K_bi K_ii⁻¹ K_ib,
    the boundary mass block H_bᵀ M H_b, and the modal frequencies are the first eigenvalues of
    (K_ii, M_ii), each computed densely; the interior factor of each library."""
    K, M, b = grid(9)
    n, k = K.shape[0], 12
    i = np.setdiff1d(np.arange(n), b)
    c = condense(
        K, M, b, method=CraigBampton(), n_modes=k, interior_factor=factorize(K[i][:, i], method=cls)
    )
    Kd, Md = K.toarray(), M.toarray()
    G = -sla.solve(Kd[np.ix_(i, i)], Kd[np.ix_(i, b)], assume_a="pos")
    schur = Kd[np.ix_(b, b)] + Kd[np.ix_(b, i)] @ G
    Hb = np.zeros((n, len(b)))
    Hb[b, np.arange(len(b))] = 1.0
    Hb[i] = G
    nb = len(b)
    np.testing.assert_allclose(c.K[:nb, :nb], schur, rtol=0, atol=1e-9 * np.abs(schur).max())
    mb = Hb.T @ Md @ Hb
    np.testing.assert_allclose(c.M[:nb, :nb], mb, rtol=0, atol=1e-9 * np.abs(mb).max())
    lam = sla.eigh(
        Kd[np.ix_(i, i)], Md[np.ix_(i, i)], eigvals_only=True, subset_by_index=[0, k - 1]
    )
    np.testing.assert_allclose(c.modes_hz, np.sqrt(lam) / (2 * np.pi), rtol=1e-9)
    # mass-normalised fixed-interface modes: the modal blocks are I and diag(λ)
    np.testing.assert_allclose(c.M[nb:, nb:], np.eye(k), atol=1e-9)
    np.testing.assert_allclose(c.K[nb:, nb:], np.diag(lam), rtol=0, atol=1e-9 * lam.max())
