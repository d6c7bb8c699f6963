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
    RotatingOperators,
    assemble_operators,
    condense,
    couple_masters,
    mesh_body,
    parse_body,
    select_masters,
)

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


@pytest.mark.parametrize("method", [Guyan(), CraigBampton()], ids=str)
def test_condensed_matrices_equal_the_plain_projection(coupled, method):
    cp, mdofs, Ks = coupled
    rot = RotatingOperators(f=cp.f, S=cp.S, G=cp.G, Ksigma=Ks)
    # 75 modes: with the 60 boundary DOFs and the static correction, 136 columns, more than one
    # column block of the projection (128)
    c = condense(cp.K, cp.M, mdofs, method=method, n_modes=75, rotating=rot)
    H = np.array(c.basis)
    nb = len(mdofs)
    assert H.shape[0] == cp.K.shape[0] and H.shape[1] == c.K.shape[0]
    assert nb == 60 and H.shape[1] == (60 if str(method) == "guyan" else 136)
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
