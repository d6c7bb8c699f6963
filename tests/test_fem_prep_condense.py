"""Condensation (seed (2.3)-(2.5)) and modal identification ((3.2), (3.9)) on small bodies."""

import numpy as np
import pytest
import scipy.linalg as sla
from _fem_prep_wheel import prepared_wheel, wheel_text

from fem_prep import (
    CraigBampton,
    Guyan,
    Herting,
    RotatingOperators,
    assemble_operators,
    condense,
    couple_masters,
    factorize,
    mesh_body,
    nodal_diameter_spectrum,
    parse_body,
    prepare,
    resonance_orders,
    select_masters,
)


@pytest.fixture(scope="module")
def coupled():
    """The small wheel's body, mesh, masters and coupled operators (those of the wheel prepared
    once per process, tests/_fem_prep_wheel.py), and its master DOFs."""
    p = prepared_wheel()
    body, bm, ms, cp = p.body, p.mesh, p.masters, p.coupled
    rim = cp.rim_dofs.ravel()
    mdofs = np.concatenate([rim, cp.bearing_dofs.ravel()])
    return body, bm, ms, cp, mdofs


# the wheel with distributing rim masters and 100 modes (test_first_20_frequencies_within_1_percent)
DISTRIBUTING = {"modes": 100, "rim_coupling": "distributing"}


@pytest.fixture(scope="module")
def held_full(coupled):
    """The full model with its bearing DOFs held (the reference of the condensed solves): the
    free DOFs, their K and M (sparse) and K's factor (the default sparse Cholesky), formed once
    for the module's tests."""
    cp = coupled[3]
    free = np.setdiff1d(np.arange(cp.K.shape[0]), cp.bearing_dofs.ravel())
    K, M = cp.K[free][:, free], cp.M[free][:, free]
    return free, K, M, factorize(K)


# default tier: [craig-bampton] and [herting] here (the same claim; Guyan's condensation runs in test_condensed_stiffness_has_rigid_body_modes)
@pytest.mark.parametrize(
    "method",
    [pytest.param(Guyan(), marks=pytest.mark.slow), CraigBampton(), Herting()],
    ids=str,
)
def test_static_response_at_masters_is_exact(coupled, held_full, method):
    """Guyan property: loads on master DOFs give the full model's master displacements."""
    body, bm, ms, cp, mdofs = coupled
    c = condense(cp.K, cp.M, mdofs, method=method, n_modes=10)
    nb = len(mdofs)
    held = cp.bearing_dofs.ravel()
    rng = np.random.default_rng(1)
    F = rng.standard_normal(nb)
    F[nb - held.size :] = 0.0
    # full model, bearings held
    n = cp.K.shape[0]
    free, factor = held_full[0], held_full[3]
    f_full = np.zeros(n)
    f_full[mdofs] = F
    u = np.zeros(n)
    u[free] = factor.solve(f_full[free])
    # condensed model, same support
    keep = np.ones(c.K.shape[0], bool)
    keep[nb - held.size : nb] = False
    fc = np.zeros(c.K.shape[0])
    fc[:nb] = F
    q = np.zeros(c.K.shape[0])
    q[keep] = np.linalg.solve(c.K[np.ix_(keep, keep)], fc[keep])
    ub_full, ub_c = u[mdofs], q[:nb]
    assert np.linalg.norm(ub_c - ub_full) <= 1e-8 * np.linalg.norm(ub_full)


# default tier: [craig-bampton] here (the same claim; Herting's condensation runs in test_static_response_at_masters_is_exact[herting])
@pytest.mark.parametrize(
    "method", [CraigBampton(), pytest.param(Herting(), marks=pytest.mark.slow)], ids=str
)
def test_centrifugal_field_is_recovered_with_the_static_correction_vector(
    coupled, held_full, method
):
    """Interior displacements recovered from the condensed solve under the centrifugal load
    (bearings held) match the full solve (relative L2 over all DOFs) once the static correction
    vector K_ii⁻¹ f_i is in the basis; the retained bending modes alone miss the in-plane
    response."""
    body, bm, ms, cp, mdofs = coupled
    held = cp.bearing_dofs.ravel()
    n = cp.K.shape[0]
    free, factor = held_full[0], held_full[3]
    u = np.zeros(n)
    u[free] = factor.solve(cp.f[free])
    nb = len(mdofs)
    errors = {}
    for sc in (True, False):
        c = condense(
            cp.K,
            cp.M,
            mdofs,
            method=method,
            n_modes=10,
            rotating=RotatingOperators(f=cp.f),
            static_correction=sc,
        )
        keep = np.ones(c.K.shape[0], bool)
        keep[nb - held.size : nb] = False
        q = np.zeros(c.K.shape[0])
        q[keep] = np.linalg.solve(c.K[np.ix_(keep, keep)], c.f_centrifugal[keep])
        errors[sc] = np.linalg.norm(c.basis @ q - u) / np.linalg.norm(u)
        assert c.modes_hz.shape == (c.n_modes,)
    # with ψ the static solution lies in the basis: exact up to rounding (the issue asks 1 %)
    assert errors[True] < 1e-6, errors
    assert errors[False] > 0.05, errors  # measured 38 % on this wheel without ψ


@pytest.mark.parametrize(
    "coupling, rim", [("rigid", "distributing"), ("averaging", "distributing"), ("rigid", "nodal")]
)
def test_condensed_stiffness_has_rigid_body_modes(coupling, rim):
    """Rigid motions built from the master coordinates cost no strain energy (free body); with
    the distributing rim coupling the masters sit at their fitted positions (``_rim``)."""
    if coupling == "rigid":  # the module's wheels, prepared once (the rim's modes do not count)
        p = prepared_wheel(**DISTRIBUTING) if rim == "distributing" else prepared_wheel()
        ops, ms, cp = p.operators, p.masters, p.coupled
    else:
        body = parse_body(wheel_text(coupling=coupling, rim_coupling=rim))
        bm = mesh_body(body)
        ops = assemble_operators(bm.basis, body.material)
        ms = select_masters(bm, body)
        cp = couple_masters(bm, ops, ms)
    rim = cp.rim_dofs.ravel()
    mdofs = np.concatenate([rim, cp.bearing_dofs.ravel()])
    c = condense(cp.K, cp.M, mdofs, method=Guyan())
    x = cp.rim_positions.reshape(-1, 3)
    rb = []
    for k in range(6):
        v = np.zeros(c.K.shape[0])
        t = np.zeros(3)
        w = np.zeros(3)
        (t if k < 3 else w)[k % 3] = 1.0
        v[: 3 * len(x)] = (t + np.cross(w, x)).ravel()
        for ib, xb in enumerate(ms.bearing_positions):
            v[3 * len(x) + 6 * ib : 3 * len(x) + 6 * ib + 6] = np.concatenate(
                [t + np.cross(w, xb), w]
            )
        rb.append(v)
    R = np.array(rb).T
    scale = np.abs(c.K).max()
    assert np.abs(c.K @ R).max() < 1e-7 * scale
    # and the rigid-body mass is the body's mass
    assert (R[:, 0] @ c.M @ R[:, 0]) == pytest.approx(ops.mass, rel=1e-10)


@pytest.fixture(scope="module")
def prepared_cb():
    return prepared_wheel()


def test_first_20_frequencies_within_1_percent(prepared_cb):
    """Craig-Bampton with 50 modes on the nodal rim masters; the distributing masters hold the
    rim face only in its fitted field, and on this 12-station rim (30 degrees between stations)
    the face keeps more freedom: 100 modes for the same 1 % (the 86-station accessory wheel is
    within 0.27 % with 50, docs/fem_prep.md)."""
    distributing = prepared_wheel(**DISTRIBUTING)
    for p in (prepared_cb, distributing):
        assert len(p.frequencies_full_hz) == 20
        assert np.all(np.abs(p.frequencies_condensed_hz / p.frequencies_full_hz - 1) < 0.01)
    p = prepared_cb
    # centrifugal: the condensed rim displacement is close to the full one
    assert p.rim_radial_displacement > 0
    assert p.rim_radial_displacement_condensed == pytest.approx(p.rim_radial_displacement, rel=0.05)


def test_nodal_diameters_come_in_pairs(prepared_cb):
    fam = prepared_cb.families
    f = np.array([m.frequency_hz for m in fam])
    nd = np.array([m.nodal_diameters for m in fam])
    for k, m in enumerate(fam[:-1]):
        if m.nodal_diameters >= 1 and m.harmonic_share > 0.9:
            partners = [
                j
                for j in range(len(fam))
                if j != k and nd[j] == nd[k] and abs(f[j] / f[k] - 1) < 1e-6
            ]
            # the last computed mode may have its partner just beyond the computed range
            if k < len(fam) - 1:
                assert partners, (k, m)
        if m.nodal_diameters == 0:
            close = [
                j for j in range(len(fam)) if j != k and abs(f[j] / f[k] - 1) < 1e-6 and nd[j] == 0
            ]
            assert not close


def test_fourier_identification_of_a_synthetic_shape(prepared_cb):
    """(3.2): a field u_z = cos(3 theta) r has all its energy in harmonic 3."""
    bm = prepared_cb.mesh
    x = bm.nodes
    th = np.arctan2(x[:, 1], x[:, 0])
    u = np.zeros((len(x), 3))
    u[:, 2] = np.cos(3 * th + 0.4) * np.hypot(x[:, 0], x[:, 1])
    spec = nodal_diameter_spectrum(bm, u.ravel())
    assert np.argmax(spec) == 3 and spec[3] > 0.999


def test_resonance_orders_table_III_11():
    back, fwd = resonance_orders(127, np.arange(5, 12))
    assert list(back) == [132, 133, 134, 135, 136, 137, 138]
    assert list(fwd) == [122, 121, 120, 119, 118, 117, 116]


@pytest.mark.slow
def test_error_decreases_with_modes(coupled):
    body, bm, ms, cp, mdofs = coupled
    held = cp.bearing_dofs.ravel()
    free = np.setdiff1d(np.arange(cp.K.shape[0]), held)
    from fem_prep import shift_invert_modes

    lam, _ = shift_invert_modes(cp.K[free][:, free], cp.M[free][:, free], 20)
    f_ref = np.sqrt(lam)
    nb = len(mdofs)
    for method in (CraigBampton(), Herting()):
        errs = []
        for m in (0, 10, 30, 60):
            c = condense(cp.K, cp.M, mdofs, method=method, n_modes=m)
            keep = np.ones(c.K.shape[0], bool)
            keep[nb - held.size : nb] = False
            lc = sla.eigh(c.K[np.ix_(keep, keep)], c.M[np.ix_(keep, keep)], eigvals_only=True)[:20]
            errs.append(np.max(np.abs(np.sqrt(lc) / f_ref - 1)))
        errs = np.array(errs)
        assert np.all(errs[1:] <= errs[:-1] * 1.05 + 1e-9), (method, errs)
        assert errs[-1] < 0.3 * errs[0], (method, errs)


def test_web_holes_shift_frequencies_and_keep_families(prepared_cb):
    p0 = prepared_cb
    p6 = prepare(parse_body(wheel_text(holes=6)))
    assert p6.operators.mass < p0.operators.mass
    f0, f6 = p0.frequencies_full_hz[:8], p6.frequencies_full_hz[:8]
    assert np.max(np.abs(f6 / f0 - 1)) > 0.005  # frequencies shift (Tab. IV-6)
    nd0 = sorted(m.nodal_diameters for m in p0.families[:6])
    nd6 = sorted(m.nodal_diameters for m in p6.families[:6])
    assert nd0 == nd6  # the nodal-diameter families are kept


def test_cholmod_matches_superlu_and_eigsh_returns_both_members_of_nd_pairs(coupled, held_full):
    """Shift-invert eigsh on the CHOLMOD (cholespy) factor returns eigenpairs of (K, M) and both
    members of every degenerate nodal-diameter pair (the reason the hand-written block solver
    once existed: it does not reproduce); the free structure's six rigid-body modes. SuperLU
    against CHOLMOD on this structure: test_cholmod_and_superlu_agree_on_the_held_structure
    (slow; every backend's solves against a dense Cholesky: tests/test_fem_prep_backends.py)."""
    from fem_prep import CholmodFactor, factorize, shift_invert_modes

    cp = coupled[3]
    K, M = held_full[1], held_full[2]
    cf = factorize(K, method=CholmodFactor)
    l1, p1 = shift_invert_modes(K, M, 12, factor=cf)
    # each returned pair is an eigenpair of (K, M) (the dense reference of every eigenvalue
    # with its multiplicity: the slow test below)
    r = K @ p1 - (M @ p1) * l1
    assert np.all(np.linalg.norm(r, axis=0) < 1e-8 * np.linalg.norm(K @ p1, axis=0))
    # degenerate pairs (ND >= 1) come out twice: adjacent eigenvalues equal to 1e-6
    ratios = l1[1:] / l1[:-1] - 1
    assert np.sum(ratios < 1e-6) >= 3, l1
    # free structure (rigid-body modes) with a negative shift, as the pipeline does: six
    # rigid-body modes, then the elastic ones (SuperLU's on the same shift: the slow test below)
    l3 = _free_structure_modes(cp, CholmodFactor)
    assert np.all(np.abs(l3[:6]) < 1e-6 * l3[6])


# default tier: tests/test_fem_prep_backends.py::test_solves_match_a_dense_cholesky[scipy] and [cholespy] (SuperLU's and CHOLMOD's solves against a dense Cholesky) and test_condensation_equals_the_cholespy_path[scipy] (SuperLU's modes in a condensation)
@pytest.mark.slow
def test_cholmod_and_superlu_agree_on_the_held_structure(coupled, held_full):
    """CHOLMOD (cholespy) and SuperLU give the same solves (1e-9) and the same 12 lowest modes
    (1e-9) of the held wheel, each an eigenpair of (K, M)."""
    from fem_prep import CholmodFactor, SparseFactor, factorize, shift_invert_modes

    K, M = held_full[1], held_full[2]
    cf, sf = factorize(K, method=CholmodFactor), factorize(K, method=SparseFactor)
    B = np.random.default_rng(2).standard_normal((K.shape[0], 7))
    x1, x2 = cf.solve(B), sf.solve(B)
    assert np.linalg.norm(x1 - x2) < 1e-9 * np.linalg.norm(x2)
    assert np.linalg.norm(cf.solve(B[:, 0]) - x2[:, 0]) < 1e-9 * np.linalg.norm(x2[:, 0])
    l1, p1 = shift_invert_modes(K, M, 12, factor=cf)
    l2, p2 = shift_invert_modes(K, M, 12, factor=sf)
    assert np.allclose(l1, l2, rtol=1e-9)
    for lam, phi in ((l1, p1), (l2, p2)):
        r = K @ phi - (M @ phi) * lam
        assert np.all(np.linalg.norm(r, axis=0) < 1e-8 * np.linalg.norm(K @ phi, axis=0))


def _free_structure_modes(cp, method):
    """The 12 lowest modes of the free structure (no bearing held) by shift-invert with the
    pipeline's negative shift, the shifted matrix factored by ``method``: eigenvalues (12,)."""
    from fem_prep import factorize, shift_invert_modes

    sig = -1e-4 * float(np.median(cp.K.diagonal() / cp.M.diagonal()))
    factor = factorize((cp.K - sig * cp.M).tocsr(), method=method)
    return shift_invert_modes(cp.K, cp.M, 12, sigma=sig, factor=factor)[0]


@pytest.mark.slow
def test_cholmod_and_superlu_give_the_free_structures_modes(coupled):
    """(Slow: the SuperLU factor and shift-invert of the free structure; CHOLMOD against SuperLU
    on the held structure stays in the default run,
    test_cholmod_matches_superlu_and_eigsh_returns_both_members_of_nd_pairs.) With the negative
    shift of the free structure both factors give the same elastic modes (1e-8) and six
    rigid-body modes."""
    from fem_prep import CholmodFactor, SparseFactor

    cp = coupled[3]
    l3, l4 = (_free_structure_modes(cp, m) for m in (CholmodFactor, SparseFactor))
    np.testing.assert_allclose(l3[6:], l4[6:], rtol=1e-8)
    for lam in (l3, l4):
        assert np.all(np.abs(lam[:6]) < 1e-6 * lam[6])


@pytest.mark.slow  # a dense generalized eigh of the 9216 free DOFs: about 2.5 min of CPU
def test_shift_invert_modes_are_the_dense_eigh_lowest(coupled):
    """The twelve lowest modes shift-invert gives (CHOLMOD's factor) are the dense generalized
    eigenproblem's twelve lowest, each with its multiplicity (nothing missed, nothing twice)."""
    from fem_prep import CholmodFactor, factorize, shift_invert_modes

    body, bm, ms, cp, mdofs = coupled
    free = np.setdiff1d(np.arange(cp.K.shape[0]), cp.bearing_dofs.ravel())
    K, M = cp.K[free][:, free], cp.M[free][:, free]
    lam, _ = shift_invert_modes(K, M, 12, factor=factorize(K, method=CholmodFactor))
    ref = sla.eigh(K.toarray(), M.toarray(), eigvals_only=True, subset_by_index=[0, 11])
    np.testing.assert_allclose(lam, ref, rtol=1e-8)


def test_solvers_fail_loudly():
    """Not positive definite → SolverError (never a silent wrong answer); the SuperLU fallback
    announces itself with a SolverWarning when no sparse Cholesky library (cholespy,
    scikit-sparse, pypardiso) imports."""
    import sys

    import scipy.sparse as sp

    from fem_prep import SolverError, SolverWarning, factorize

    n = 50
    A = sp.diags(np.r_[np.ones(n - 1), -1.0]).tocsr()
    with pytest.raises(SolverError, match="not positive definite"):
        factorize(A)
    hidden = ("cholespy", "sksparse.cholmod", "pypardiso")  # every sparse Cholesky library
    saved = {name: sys.modules.get(name) for name in hidden}
    for name in hidden:
        sys.modules[name] = None  # import fails
    try:
        with pytest.warns(SolverWarning, match="SuperLU"):
            f = factorize(sp.eye(n).tocsr())
        assert f.method == "superlu"
    finally:
        for name, module in saved.items():
            if module is None:
                del sys.modules[name]
            else:
                sys.modules[name] = module
    assert factorize(sp.eye(n).tocsr()).method in ("cholmod", "pardiso")
