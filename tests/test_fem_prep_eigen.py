"""The eigen-solver kinds of fem_prep (``Lanczos``: ARPACK eigsh; ``BlockLanczos``: a block of
vectors per factor solve) against a dense ``scipy.linalg.eigh`` of the same (K, M).

The body: a 27-node-hex cantilever of rectangular section (20 x 30 mm, so that the bending
families in y and z do not coincide), 648 DOFs once the clamped face is removed: small enough
for the dense reference, large enough (n >= 400) for the sparse path.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import skfem

import fem_prep
from fem_prep import (
    BlockLanczos,
    CraigBampton,
    Lanczos,
    Material,
    SolverWarning,
    assemble_operators,
    condense,
    shift_invert_modes,
)

K_MODES = 10


@pytest.fixture(scope="module")
def beam():
    m1 = skfem.MeshHex.init_tensor(
        np.linspace(0, 0.4, 13), np.linspace(0, 0.02, 2), np.linspace(0, 0.03, 2)
    )
    mesh = skfem.MeshHex2.from_mesh(m1)
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementHex2()), intorder=4)
    ops = assemble_operators(basis, Material(210e9, 0.3, 7800.0))
    fixed = np.nonzero(np.isclose(basis.doflocs[0], 0.0))[0]
    free = np.setdiff1d(np.arange(ops.K.shape[0]), fixed)
    K = sp.csr_matrix(ops.K)[free][:, free].tocsr()
    M = sp.csr_matrix(ops.M)[free][:, free].tocsr()
    lam, phi = sla.eigh(K.toarray(), M.toarray())  # the dense reference, mass-normalised
    return {"K": K, "M": M, "lam": lam, "phi": phi, "Kfull": ops.K, "Mfull": ops.M,
            "fixed": fixed}


def _mac(a: np.ndarray, b: np.ndarray, M: sp.spmatrix) -> np.ndarray:
    """Modal assurance criterion (M-weighted) of matching columns: 1 for equal shapes up to
    sign and scale."""
    ab = np.einsum("ij,ij->j", a, M @ b)
    return ab**2 / (np.einsum("ij,ij->j", a, M @ a) * np.einsum("ij,ij->j", b, M @ b))


@pytest.mark.parametrize("solver", [BlockLanczos(block=4), BlockLanczos(block=8), Lanczos()])
def test_lowest_modes_match_the_dense_eigh(beam, solver):
    assert beam["K"].shape[0] >= 400  # the sparse path, not shift_invert_modes' dense shortcut
    lam, phi = shift_invert_modes(beam["K"], beam["M"], K_MODES, solver=solver)
    ref = beam["lam"][:K_MODES]
    assert np.min(np.diff(ref) / ref[1:]) > 1e-3  # distinct: shapes defined up to sign
    np.testing.assert_allclose(lam, ref, rtol=1e-8)
    assert np.all(_mac(phi, beam["phi"][:, :K_MODES], beam["M"]) > 0.999999)
    # mass-normalised, as documented
    np.testing.assert_allclose(np.einsum("ij,ij->j", phi, beam["M"] @ phi), 1.0, rtol=1e-10)


def test_block_and_arpack_agree_and_the_block_solves_count_once_per_block(beam):
    calls = []
    lb, pb = shift_invert_modes(
        beam["K"], beam["M"], K_MODES, solver=BlockLanczos(block=8),
        on_solve=lambda: calls.append(1),
    )
    la, pa = shift_invert_modes(beam["K"], beam["M"], K_MODES, solver=Lanczos())
    np.testing.assert_allclose(lb, la, rtol=1e-8)
    assert np.all(_mac(pb, pa, beam["M"]) > 0.999999)
    # one hook call per solve of 8 right-hand sides (the 648-DOF beam: at most 9 blocks)
    assert 2 <= len(calls) <= (4 * K_MODES + 4 * 8) // 8


def test_free_structure_with_a_negative_shift(beam):
    """The free cantilever (no clamp): six zero eigenvalues, then the elastic modes."""
    K, M = sp.csr_matrix(beam["Kfull"]), sp.csr_matrix(beam["Mfull"])
    ref = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True)[:12]
    sigma = -1e-4 * float(np.median(K.diagonal() / M.diagonal()))
    lam, _ = shift_invert_modes(K, M, 12, sigma=sigma, solver=BlockLanczos(block=6))
    scale = ref[-1]
    np.testing.assert_allclose(lam[:6], 0.0, atol=1e-8 * scale)  # rigid-body modes
    np.testing.assert_allclose(lam[6:], ref[6:], rtol=1e-8)


def test_a_block_solver_that_cannot_converge_falls_back_loudly(beam):
    tight = BlockLanczos(block=2, max_columns=12)  # 12 vectors: not 10 modes to 1e-10
    with pytest.warns(SolverWarning, match=r"BlockLanczos.*did not converge.*falling back"):
        lam, phi = shift_invert_modes(beam["K"], beam["M"], K_MODES, solver=tight)
    np.testing.assert_allclose(lam, beam["lam"][:K_MODES], rtol=1e-8)  # eigsh's result


def test_craig_bampton_with_the_block_solver_keeps_the_interior_modes(beam):
    """Craig-Bampton's modal DOFs are the fixed-interface modes: with the clamped face as the
    boundary they are the modes of the clamped beam (the dense reference)."""
    K, M = sp.csr_matrix(beam["Kfull"]), sp.csr_matrix(beam["Mfull"])
    with warnings.catch_warnings():
        warnings.simplefilter("error", SolverWarning)  # converges: no fallback
        c = condense(
            K, M, beam["fixed"], n_modes=K_MODES,
            method=CraigBampton(eigen_solver=BlockLanczos(block=8)),
        )
    ref_hz = np.sqrt(beam["lam"][:K_MODES]) / (2 * np.pi)
    np.testing.assert_allclose(c.modes_hz, ref_hz, rtol=1e-8)


def test_eigen_solver_arguments_are_checked():
    with pytest.raises(ValueError, match=r"block = 0: an integer >= 1"):
        BlockLanczos(block=0)
    with pytest.raises(ValueError, match=r"max_columns = 0: an integer >= 1 or None"):
        BlockLanczos(max_columns=0)
    K = sp.identity(500, format="csr")
    with pytest.raises(ValueError, match=r"solver = 'block'; use fem_prep.Lanczos\(\)"):
        shift_invert_modes(K, K, 3, solver="block")
    assert isinstance(Lanczos(), fem_prep.EigenSolver)


def test_block_modes_are_m_orthonormal_and_k_diagonal(beam):
    """The block recurrence keeps M V beside V (no product with M in the Gram-Schmidt passes):
    the modes it returns are still M-orthonormal and K-orthogonal (Φᵀ M Φ = I, Φᵀ K Φ = Λ), as
    exact eigenvectors are."""
    lam, phi = shift_invert_modes(beam["K"], beam["M"], K_MODES, solver=BlockLanczos(block=4))
    np.testing.assert_allclose(phi.T @ (beam["M"] @ phi), np.eye(K_MODES), atol=1e-9)
    Kq = phi.T @ (beam["K"] @ phi)
    np.testing.assert_allclose(Kq, np.diag(lam), atol=1e-9 * lam.max())


def test_craig_bampton_defaults_to_the_block_solver(beam):
    """CraigBampton() without an eigen-solver runs BlockLanczos (block of 8); its modal DOFs are
    the clamped beam's modes (the dense reference), without a fallback."""
    assert isinstance(CraigBampton().solver, BlockLanczos)
    assert isinstance(CraigBampton(eigen_solver=Lanczos()).solver, Lanczos)
    K, M = sp.csr_matrix(beam["Kfull"]), sp.csr_matrix(beam["Mfull"])
    with warnings.catch_warnings():
        warnings.simplefilter("error", SolverWarning)
        c = condense(K, M, beam["fixed"], n_modes=K_MODES)
    np.testing.assert_allclose(c.modes_hz, np.sqrt(beam["lam"][:K_MODES]) / (2 * np.pi), rtol=1e-8)


def test_eigenvalue_count_is_the_number_of_dense_eigenvalues_below(beam):
    # Sylvester's inertia of K - sigma M (PARDISO's L D L^T) against the dense eigh's count, at
    # shifts midway between consecutive eigenvalues, below the first and past the tenth
    pytest.importorskip("pypardiso")
    lam = beam["lam"]
    shifts = np.r_[0.5 * lam[0], 0.5 * (lam[:10] + lam[1:11])]
    counts = [fem_prep.eigenvalue_count(beam["K"], beam["M"], s) for s in shifts]
    assert counts == [int(np.sum(lam < s)) for s in shifts] == list(range(11))
