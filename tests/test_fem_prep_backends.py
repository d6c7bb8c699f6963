"""Every installed factor backend gives the same Craig-Bampton condensation as cholespy's
simplicial CHOLMOD (the reference backend, a hard dependency) on a small elastic body, and the
same solves as a dense Cholesky: condensed stiffness and mass within 1e-9 (relative Frobenius
norm), the first 20 fixed-interface frequencies within 1e-10 (relative). A backend whose library
is not installed is skipped with the reason."""

import importlib.util

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp

from fem_prep import (
    CholmodFactor,
    CraigBampton,
    PardisoFactor,
    RotatingOperators,
    SolverError,
    SparseFactor,
    SupernodalFactor,
    condense,
    factorize,
)


def _installed(module: str) -> bool:
    try:
        return importlib.util.find_spec(module) is not None
    except ModuleNotFoundError:  # a parent package missing
        return False


def _backend(cls, module: str, why: str):
    skip = pytest.mark.skipif(not _installed(module), reason=f"{module} is not installed ({why})")
    return pytest.param(cls, marks=skip, id=cls.library)


BACKENDS = [
    _backend(PardisoFactor, "pypardiso", "MKL PARDISO; x86-64 wheels only"),
    _backend(SupernodalFactor, "sksparse", "optional: no wheel, built against SuiteSparse"),
    pytest.param(SparseFactor, id="scipy"),
]


def elastic_body(nx: int = 14, ny: int = 6, nz: int = 4):
    """A clamped-free 3D linear-elastic hexahedral brick assembled with scikit-fem (steel, SI
    units, 3 DOFs per node): stiffness, consistent mass and a body-load vector ``f``; the master
    DOFs are those of the face x = 0 and of the face x = L (a ring of boundary DOFs on both ends,
    as a gear body's bearing seat and rim)."""
    import skfem
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    mesh = skfem.MeshHex.init_tensor(
        np.linspace(0, 0.14, nx + 1), np.linspace(0, 0.03, ny + 1), np.linspace(0, 0.02, nz + 1)
    )
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementHex1()))
    K = skfem.asm(linear_elasticity(*lame_parameters(2.1e11, 0.3)), basis).tocsr()

    @skfem.BilinearForm
    def mass(u, v, w):
        return 7850.0 * skfem.helpers.dot(u, v)

    @skfem.LinearForm
    def load(v, w):
        return 7850.0 * w.x[0] * v[0]  # a centrifugal-like radial body load per unit speed^2

    M = skfem.asm(mass, basis).tocsr()
    f = skfem.asm(load, basis)
    ends = mesh.nodes_satisfying(lambda x: np.isclose(x[0], 0) | np.isclose(x[0], 0.14))
    masters = basis.nodal_dofs[:, ends].T.ravel()
    return K, M, f, np.sort(masters)


@pytest.fixture(scope="module")
def body():
    K, M, f, b = elastic_body()
    i = np.setdiff1d(np.arange(K.shape[0]), b)
    ref = condense(
        K,
        M,
        b,
        method=CraigBampton(),
        n_modes=20,
        rotating=RotatingOperators(f=f),
        interior_factor=factorize(K[i][:, i], method=CholmodFactor),
    )
    return K, M, f, b, i, ref


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.linalg.norm(a - b) / np.linalg.norm(b))


@pytest.mark.parametrize("cls", BACKENDS)
def test_condensation_equals_the_cholespy_path(body, cls):
    """Condensed K and M within 1e-9 (relative Frobenius) and the 20 fixed-interface
    frequencies (plus the static correction's) within 1e-10 of the cholespy path; the backend
    that ran is the one asked for."""
    K, M, f, b, i, ref = body
    fac = factorize(K[i][:, i], method=cls)
    assert isinstance(fac, cls) and fac.library == cls.library
    c = condense(
        K,
        M,
        b,
        method=CraigBampton(),
        n_modes=20,
        rotating=RotatingOperators(f=f),
        interior_factor=fac,
    )
    assert c.K.shape == ref.K.shape == (len(b) + 21,) * 2
    assert _rel(c.K, ref.K) < 1e-9
    assert _rel(c.M, ref.M) < 1e-9
    np.testing.assert_allclose(c.modes_hz, ref.modes_hz, rtol=1e-10)


@pytest.mark.parametrize("cls", [*BACKENDS, pytest.param(CholmodFactor, id="cholespy")])
def test_solves_match_a_dense_cholesky(body, cls):
    """One and 130 right-hand sides (more than one 128-column block) against a dense Cholesky
    solve of the interior stiffness."""
    K, _, _, _, i, _ = body
    Kii = K[i][:, i]
    fac = factorize(Kii, method=cls)
    B = np.random.default_rng(1).standard_normal((len(i), 130))
    ref = sla.cho_solve(sla.cho_factor(Kii.toarray()), B)
    atol = 1e-9 * np.abs(ref).max()
    np.testing.assert_allclose(fac.solve(B), ref, rtol=0, atol=atol)
    np.testing.assert_allclose(fac.solve(B[:, 0]), ref[:, 0], rtol=0, atol=atol)
    assert fac.solve(B[:, 0]).shape == (len(i),)


@pytest.mark.skipif(not _installed("pypardiso"), reason="pypardiso is not installed")
def test_pardiso_refuses_an_indefinite_matrix():
    """A negative pivot (PARDISO's error -4) and a non-positive diagonal entry both raise
    SolverError naming the cause, never a silent wrong answer."""
    n = 60
    rng = np.random.default_rng(0)
    R = sp.random(n, n, 0.1, random_state=rng)
    A = (R + R.T + sp.eye(n) * 0.01).tocsr()  # indefinite, positive diagonal
    A.setdiag(np.abs(A.diagonal()) + 0.01)
    assert np.linalg.eigvalsh(A.toarray()).min() < 0
    with pytest.raises(SolverError, match="not positive definite"):
        factorize(A, method=PardisoFactor)
    with pytest.raises(SolverError, match="not positive definite"):
        factorize(sp.diags(np.r_[np.ones(n - 1), -1.0]).tocsr(), method=PardisoFactor)


def test_default_backend_order():
    """factorize's default: scikit-sparse's supernodal CHOLMOD when it imports, else MKL
    PARDISO, else cholespy's CHOLMOD."""
    f = factorize(sp.eye(20).tocsr())
    if _installed("sksparse"):
        expected = SupernodalFactor
    elif _installed("pypardiso"):
        expected = PardisoFactor
    else:
        expected = CholmodFactor
    assert type(f) is expected
