"""The condensed matrices against the plain projection ``H^T A H`` of the returned basis.

:func:`fem_prep.condense` projects the stiffness through the Schur complement ``K_bb + K_bi G``
and the other operators by the upper block triangle of ``H^T A H`` mirrored (seed (2.3)-(2.5));
the reference here is the plain dense product of the whole basis, written separately, with the
boundary/modal blocks of ``K`` zero for the modal methods ((2.5): statically uncoupled).
"""

import numpy as np
import pytest
import scipy.sparse as sp

from fem_prep import (
    CraigBampton,
    Guyan,
    Herting,
    RotatingOperators,
    assemble_operators,
    condense,
    couple_masters,
    mesh_body,
    parse_body,
    select_masters,
)
from fem_prep._condense import _append_column, _project

BODY = """
name = "projection-test"
[body]
bore_radius_mm = 8.0
hub_outer_radius_mm = 12.0
hub_width_mm = 12.0
web_thickness_mm = 1.5
rim_inner_radius_mm = 26.0
rim_outer_radius_mm = 30.0
rim_width_mm = 8.0
[[bearings]]
axial_position_mm = -5.0
[[bearings]]
axial_position_mm = 5.0
[mesh]
size_mm = 8.0
circumferential_size_mm = 12.0
[condensation]
teeth = 8
axial_master_nodes = 2
[centrifugal]
speed_rad_s = 2000.0
"""


@pytest.fixture(scope="module")
def coupled():
    body = parse_body(BODY)
    bm = mesh_body(body)
    ops = assemble_operators(bm.basis, body.material)
    cp = couple_masters(bm, ops, select_masters(bm, body))
    mdofs = np.concatenate([cp.rim_dofs.ravel(), cp.bearing_dofs.ravel()])
    # a symmetric stand-in for the stress stiffening: any symmetric sparse matrix is projected
    # the same way
    Ks = sp.csr_matrix(0.5 * (cp.K @ cp.M + cp.M @ cp.K))
    return cp, mdofs, Ks


def _rel(a, b):
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize("method", [Guyan(), CraigBampton(), Herting()], ids=str)
def test_condensed_matrices_equal_the_plain_projection(coupled, method):
    cp, mdofs, Ks = coupled
    rot = RotatingOperators(f=cp.f, S=cp.S, G=cp.G, Ksigma=Ks)
    c = condense(cp.K, cp.M, mdofs, method=method, n_modes=12, rotating=rot)
    H = np.array(c.basis)
    nb = len(mdofs)
    assert H.shape[0] == cp.K.shape[0] and H.shape[1] == c.K.shape[0]
    np.testing.assert_array_equal(H[mdofs, :nb], np.eye(nb))
    assert not np.any(H[mdofs, nb:])
    ref_K = H.T @ (cp.K @ H)
    if H.shape[1] > nb:  # (2.5): boundary and modal DOFs statically uncoupled
        assert np.max(np.abs(ref_K[:nb, nb:])) < 1e-8 * np.max(np.abs(ref_K))
        ref_K[:nb, nb:] = 0.0
        ref_K[nb:, :nb] = 0.0
    assert _rel(c.K, ref_K) < 1e-9
    for got, A in ((c.M, cp.M), (c.spin_softening, cp.S), (c.stress_stiffening, Ks)):
        assert _rel(got, H.T @ (A @ H)) < 1e-9
        np.testing.assert_array_equal(got, got.T)
    assert _rel(c.gyroscopic, H.T @ (cp.G @ H)) < 1e-9
    np.testing.assert_array_equal(c.gyroscopic, -c.gyroscopic.T)
    np.testing.assert_allclose(c.f_centrifugal, H.T @ cp.f, rtol=1e-12, atol=0)


def test_block_projection_of_random_matrices():
    """``_project`` with blocks that do not divide the column count: symmetric and skew."""
    rng = np.random.default_rng(3)
    n, m = 200, 37
    A = sp.random(n, n, density=0.05, random_state=4, format="csr")
    V = rng.standard_normal((n, m))
    sym, skew = (A + A.T).tocsr(), (A - A.T).tocsr()
    for blk in (5, 16, 37, 64):
        np.testing.assert_allclose(_project(sym, V, blk), V.T @ (sym @ V), rtol=1e-12, atol=1e-12)
        got = _project(skew, V, blk, skew=True)
        np.testing.assert_allclose(got, V.T @ (skew @ V), rtol=1e-12, atol=1e-12)
        np.testing.assert_array_equal(got, -got.T)


def test_append_column_fills_the_reserved_column_in_place():
    buf = np.zeros((6, 4))
    H = buf[:, :3]
    H[:] = 1.0
    col = np.arange(6.0)[:, None]
    out = _append_column(H, col)
    assert out.shape == (6, 4) and np.shares_memory(out, buf)
    np.testing.assert_array_equal(out[:, 3], col[:, 0])
    np.testing.assert_array_equal(out[:, :3], 1.0)
    # no spare column: a copy
    full = np.ones((6, 3))
    out2 = _append_column(full, col)
    assert out2.shape == (6, 4) and not np.shares_memory(out2, full)
    np.testing.assert_array_equal(out2[:, 3], col[:, 0])
