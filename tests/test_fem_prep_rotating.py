"""Rotating-frame matrices of the condensed body: gyroscopic G, spin softening S, stress
stiffening K_sigma, against references that do not go through the code under test.

For a body spinning at Omega about +z the body-frame equations are
``M q'' + 2 Omega G q' + (K + Omega^2 (S + K_sigma)) q = Omega^2 f_c + f``.

References:

* G from scikit-fem's own vector ``BilinearForm`` ``rho v . (e_z x u)`` (not the Kronecker
  product of the code); for rigid translations the exact identity
  ``kron(Ms, J) (1 x e_x) = M (1 x e_y)``; ``t_x^T S t_x = -mass`` with the mass from the
  quadrature volume.
* K_sigma by virtual work: for a linear field ``v = B x`` (in the quadratic FE space exactly)
  ``v^T K_sigma v = int sigma0 : (B^T B) dV`` and, for any FE field w, ``int sigma0 : grad w dV =
  w^T K u0 = w^T f + w^T r`` (the discrete equilibrium of the prestress solve, r its support
  reactions).  For the rigid tilt about x, ``B^T B = A = diag(0, 1, 1)`` (symmetric), so
  ``theta^T K_sigma theta = (A x)^T f + (A x)^T r = int rho y^2 dV + r . (A x)`` and
  ``theta^T S theta = -int rho z^2 dV``.  The prestress u0 (1 rad/s, bearings held) and its
  reactions come from an independent solve: Lagrange multipliers on the bearing-band constraints
  (every band DOF for the rigid coupling, the least-squares rigid fit of the band for the
  averaging one), not from the code's ``u = T q`` elimination; ``int rho y^2`` and
  ``int rho z^2`` from the scalar mass matrix and the node coordinates.  The reactions act on the
  bore-band nodes and must be paired with ``A x`` there: their bearing resultants (force and
  moment) vanish on the axisymmetric wheel, yet their work on ``A x`` is several % of
  ``int rho y^2``.
* Coriolis coefficient ``g = phi_1^T G phi_2`` of each degenerate nodal-diameter pair (the 2x2
  matrix over the pair is ``[[0, g], [-g, 0]]``, eigenvalues ``+-i g``; first-order split
  ``omega = omega_0 +- Omega g``) of the condensed model against the full FE model, both held at
  the bearings.  Bound: with the condensed pair ``Q = P C + E`` (P the full pair, E M-orthogonal
  to P, ``s = ||E||_M`` the sine of the largest principal angle) and ``||M^-1/2 G M^-1/2|| = 1``,
  ``|g_Q - g_P| <= 2 s + (1 + |g_P|) s^2``.
"""

import math

import numpy as np
import pytest
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla
import skfem
from _fem_prep_wheel import prepared_wheel, wheel_text
from test_fem_prep_io import _rewrite

from fem_prep import FORMAT_VERSION, load_condensed, parse_body, save_condensed


@pytest.fixture(scope="module")
def prepared():
    """``prepared(coupling)``: the small Craig-Bampton wheel of test_fem_prep_condense with both
    bearings rigid or averaging, prepared once per process (tests/_fem_prep_wheel.py: the rigid
    one is test_fem_prep_condense's)."""
    cache = {}

    def get(coupling):
        if coupling not in cache:
            cache[coupling] = prepared_wheel(coupling=coupling)
        return cache[coupling]

    yield get
    cache.clear()


# default tier: the [rigid] cases of test_rigid_tilt_virtual_work and test_drive_rotation_is_neutral (the same claims; the rotating operators do not depend on the coupling) with tests/test_fem_prep_condense.py::test_condensed_stiffness_has_rigid_body_modes[averaging-distributing] (the averaging coupling's rows)
@pytest.fixture(params=["rigid", pytest.param("averaging", marks=pytest.mark.slow)])
def prep(request, prepared):
    return prepared(request.param)


@pytest.fixture
def prep_rigid(prepared):
    return prepared("rigid")


def _rigid_condensed(p, t, w) -> np.ndarray:
    """Condensed vector of the rigid motion ``t + w x x``: rim masters ``t + w x x``, bearing
    nodes ``(t + w x x_b, w)``, modal coordinates 0."""
    ms = p.masters
    x = p.coupled.rim_positions.reshape(-1, 3)
    v = np.zeros(p.condensed.K.shape[0])
    n = 3 * len(x)
    v[:n] = (t + np.cross(w, x)).ravel()
    for ib, xb in enumerate(ms.bearing_positions):
        v[n + 6 * ib : n + 6 * ib + 6] = np.r_[t + np.cross(w, xb), w]
    return v


def _expand(p, q) -> np.ndarray:
    """Full-DOF field of condensed coordinates: ``T basis q``."""
    return p.coupled.T @ (p.condensed.basis @ q)


def _band_constraints(p) -> sp.csr_matrix:
    """Rows C with ``C u = 0`` for held bearings: every band DOF (rigid) or the least-squares
    rigid fit of the band (averaging), written from the node coordinates."""
    x = p.mesh.nodes
    n = p.mesh.n_dofs
    rows = []
    for ring, kind, xb in zip(
        p.masters.bearing_rings, p.masters.couplings, p.masters.bearing_positions
    ):
        dofs = (3 * ring[:, None] + np.arange(3)).ravel()
        if kind == "rigid":
            C = np.eye(len(dofs))
        else:
            R = np.zeros((len(ring), 3, 6))
            R[:, :, :3] = np.eye(3)
            for k in range(3):  # rotation about e_k: e_k x d
                R[:, :, 3 + k] = np.cross(np.eye(3)[k], x[ring] - xb)
            C = np.linalg.pinv(R.reshape(-1, 6))
        full = np.zeros((C.shape[0], n))
        full[:, dofs] = C
        rows.append(full)
    return sp.csr_matrix(np.vstack(rows))


def _independent_prestress(p):
    """Centrifugal prestress at 1 rad/s with the bearings held (Lagrange multipliers) and the
    support reactions ``r = K u - f`` (full DOFs); solved once per prepared wheel (the wheels
    live for the process, tests/_fem_prep_wheel.py) and read by the tests of this module."""
    key = id(p)
    if _PRESTRESS.get(key, (None,))[0] is not p:
        _PRESTRESS[key] = (p, _solve_prestress(p))
    return _PRESTRESS[key][1]


_PRESTRESS: dict = {}  # id(prepared wheel) -> (the wheel, (u, r))


def _solve_prestress(p):
    ops = p.operators
    # constraint rows scaled to the stiffness (a well-balanced saddle-point matrix for SuperLU)
    C = _band_constraints(p) * float(np.median(ops.K.diagonal()))
    n = ops.K.shape[0]
    A = sp.bmat([[ops.K, C.T], [C, None]], format="csc")
    u = spla.spsolve(A, np.r_[ops.f_centrifugal, np.zeros(C.shape[0])])[:n]
    r = ops.K @ u - ops.f_centrifugal
    for a in (u, r):  # shared by the tests: read only
        a.setflags(write=False)
    return u, r


# ------------------------------------------------------------------------- structure


def test_gyroscopic_is_scikit_fem_coriolis_form_and_skew(prep_rigid):
    p = prep_rigid
    rho = p.body.material.density

    @skfem.BilinearForm
    def coriolis(u, v, w):  # rho v . (e_z x u), e_z x u = (-u_y, u_x, 0)
        return rho * (-v[0] * u[1] + v[1] * u[0])

    G_ref = coriolis.assemble(p.mesh.basis)
    G = p.operators.gyroscopic
    assert abs(G - G_ref).max() <= 1e-12 * abs(G_ref).max()
    # the condensed one: skew, and the plain projection H^T T^T G T H (no skew-symmetrising)
    H, T = p.condensed.basis, p.coupled.T
    raw = H.T @ (T.T @ (G_ref @ (T @ H)))
    Gc = p.condensed.gyroscopic
    assert np.array_equal(Gc, -Gc.T)
    assert np.abs(raw + raw.T).max() <= 1e-12 * np.abs(raw).max()
    assert np.abs(Gc - raw).max() <= 1e-12 * np.abs(raw).max()


def test_spin_softening_and_stress_stiffening_are_symmetric(prep_rigid):
    p = prep_rigid
    c = p.condensed
    H, T = c.basis, p.coupled.T
    # the coupled K_sigma is the body's T^T K_sigma T plus the shaft's share of the bore-band
    # reactions, which lives on the bearing DOFs only (its values: the tilt and turn tests)
    # (read on the sparse entries: a dense copy of the 9k x 9k difference took ~20 s)
    extra = (p.coupled.Ksigma - T.T @ p.stress_stiffening @ T).tocoo()
    on_bearing = np.zeros(extra.shape[0], dtype=bool)
    on_bearing[p.coupled.bearing_dofs.ravel()] = True
    off = ~(on_bearing[extra.row] & on_bearing[extra.col])  # a row or a column off the bearings
    assert np.abs(extra.data[off]).max(initial=0.0) <= 1e-12 * np.abs(extra.data).max()
    for name, full in (
        ("spin_softening", T.T @ p.operators.spin_softening @ T),
        ("stress_stiffening", p.coupled.Ksigma),
    ):
        A = getattr(c, name)
        raw = H.T @ (full @ H)
        assert np.array_equal(A, A.T), name
        assert np.abs(raw - raw.T).max() <= 1e-12 * np.abs(raw).max(), name
        assert np.abs(A - raw).max() <= 1e-12 * np.abs(raw).max(), name
        assert abs(full - full.T).max() <= 1e-12 * abs(full).max(), name
    full = p.stress_stiffening
    assert abs(full - full.T).max() <= 1e-12 * abs(full).max()
    # spin softening is -kron(Ms, diag(1, 1, 0)): negative semi-definite
    ev = np.linalg.eigvalsh(c.spin_softening)
    assert ev.max() <= 1e-12 * abs(ev).max()


# ------------------------------------------------------------------- rigid translation


def test_rigid_translation(prep_rigid):
    p = prep_rigid
    c = p.condensed
    e, z = np.eye(3), np.zeros(3)
    tx, ty = _rigid_condensed(p, e[0], z), _rigid_condensed(p, e[1], z)
    # the condensed vector reproduces the translation and costs no strain energy
    ux = np.zeros(p.mesh.n_dofs)
    ux[0::3] = 1.0
    assert np.linalg.norm(_expand(p, tx) - ux) <= 1e-10 * np.linalg.norm(ux)
    assert np.abs(c.K @ tx).max() <= 1e-12 * np.abs(c.K).max()
    # kron(Ms, J)(1 x e_x) = M (1 x e_y): exact identity
    My = c.M @ ty
    assert np.linalg.norm(c.gyroscopic @ tx - My) <= 1e-12 * np.linalg.norm(My)
    # spin softening of a translation: minus the mass (volume from the quadrature weights)
    mass = p.body.material.density * p.mesh.basis.dx.sum()
    assert tx @ c.spin_softening @ tx == pytest.approx(-mass, rel=1e-12)
    assert ty @ c.spin_softening @ ty == pytest.approx(-mass, rel=1e-12)
    tz = _rigid_condensed(p, e[2], z)
    assert abs(tz @ c.spin_softening @ tz) <= 1e-12 * mass
    # a translation has no gradient: no stress stiffening
    Ks = c.stress_stiffening
    scale = np.linalg.norm(Ks, 2)
    for t in (tx, ty, tz):
        assert np.linalg.norm(Ks @ t) <= 1e-11 * scale * np.linalg.norm(t)


# ------------------------------------------------------------------------- rigid tilt


def test_rigid_tilt_virtual_work(prep):
    """theta^T (S_c + K_sigma,c) theta = int rho (y^2 - z^2) dV + r . (A x) (see module doc)."""
    p = prep
    c, ops = p.condensed, p.operators
    x = p.mesh.nodes
    th = _rigid_condensed(p, np.zeros(3), np.eye(3)[0])
    tilt = np.cross(np.eye(3)[0], x).ravel()  # (0, -z, y)
    assert np.linalg.norm(_expand(p, th) - tilt) <= 1e-10 * np.linalg.norm(tilt)
    assert np.abs(c.K @ th).max() <= 1e-12 * np.abs(c.K).max()

    u0, r = _independent_prestress(p)
    # the pipeline's prestress is the same solve (there through u = T q)
    assert np.linalg.norm(p.prestress_displacement - u0) <= 1e-9 * np.linalg.norm(u0)
    band = np.concatenate(p.masters.bearing_rings)
    bd = (3 * band[:, None] + np.arange(3)).ravel()
    off = np.setdiff1d(np.arange(len(r)), bd)
    assert np.abs(r[off]).max() <= 1e-9 * np.abs(r).max()  # reactions only on the bands

    Ms = ops.M[0::3, 0::3]
    int_rho_y2 = x[:, 1] @ (Ms @ x[:, 1])
    int_rho_z2 = x[:, 2] @ (Ms @ x[:, 2])
    Ax = (x * np.array([0.0, 1.0, 1.0])).ravel()
    reaction_work = r[bd] @ Ax[bd]
    ref_sigma = int_rho_y2 + reaction_work
    ref_spin = -int_rho_z2

    assert th @ c.spin_softening @ th == pytest.approx(ref_spin, rel=1e-10)
    # the body's own stress stiffening (full DOFs) does the reactions' work too ...
    assert tilt @ (p.stress_stiffening @ tilt) == pytest.approx(ref_sigma, rel=1e-10)
    # ... which the shaft that carries them takes back: the stored K_sigma gives the rigid
    # body's tilt stiffness, int rho (y^2 - z^2) = I_p - I_d with S
    assert th @ c.stress_stiffening @ th == pytest.approx(int_rho_y2, rel=1e-10)
    total = th @ (c.spin_softening + c.stress_stiffening) @ th
    assert total == pytest.approx(int_rho_y2 + ref_spin, rel=1e-10)
    # the reaction term matters, and only as the distributed band forces: paired with A x at
    # the bearing nodes instead (their 6-DOF resultants: no in-plane force, no moment, equal and
    # opposite axial forces) it would miss part of it, since A x is not a rigid motion of a band
    assert abs(reaction_work) > 0.02 * int_rho_y2
    resultant_work = 0.0
    F_z = []
    for ring, xb in zip(p.masters.bearing_rings, p.masters.bearing_positions):
        rr = r.reshape(-1, 3)[ring]
        F, Mb = rr.sum(0), np.cross(x[ring] - xb, rr).sum(0)
        scale = np.abs(rr).sum()
        assert np.abs(F[:2]).max() <= 1e-9 * scale
        assert np.abs(Mb).max() <= 1e-9 * scale * np.abs(x[ring]).max()
        F_z.append(F[2])
        resultant_work += F @ (np.array([0.0, 1.0, 1.0]) * xb)  # A x_b
    assert F_z[0] == pytest.approx(-F_z[1], rel=1e-9)
    assert abs(resultant_work - reaction_work) > 0.01 * int_rho_y2


def test_drive_rotation_is_neutral(prep):
    """A rigid turn about the axis changes nothing in the turning frame: (S + K_sigma) of the
    condensed body (stress stiffening with the shaft's share of the bore-band reactions) maps it
    to zero, every row, while the body's own K_sigma alone does not (the reactions' moment)."""
    p = prep
    c = p.condensed
    th = _rigid_condensed(p, np.zeros(3), np.eye(3)[2])
    A = c.spin_softening + c.stress_stiffening
    scale = np.abs(c.spin_softening).max() * np.abs(th).max()
    assert np.abs(A @ th).max() <= 1e-8 * scale
    spin = _expand(p, th)
    x = p.mesh.nodes
    assert np.linalg.norm(spin - np.cross(np.eye(3)[2], x).ravel()) <= 1e-10 * np.linalg.norm(spin)
    # without the shaft's share: the full-DOF K_sigma + S on the same turn is the reactions'
    # moment r_i x (e_z x ...) -- not zero where a bearing band is clamped (rigid coupling)
    raw = spin @ ((p.stress_stiffening + p.operators.spin_softening) @ spin)
    _, r = _independent_prestress(p)
    band = np.concatenate(p.masters.bearing_rings)
    rr, xb = r.reshape(-1, 3)[band], x[band]
    ref = np.sum(rr[:, :2] * xb[:, :2])  # (e_z x x) . (e_z x r) = x_perp . r_perp
    assert abs(raw - ref) <= 1e-8 * np.abs(rr).sum() * np.abs(xb).max()
    if p.masters.couplings[0] == "rigid":  # a clamped band: the moment is a real share
        assert abs(ref) > 0.01 * abs(spin @ (p.operators.spin_softening @ spin))


def test_stress_stiffening_on_linear_fields(prep_rigid):
    """Full-DOF K_sigma on v = B x, B general: int sigma0 : (B^T B) = ((B^T B) x)^T (f + r) --
    every component of the prestress, not only the tilt's sigma_yy + sigma_zz."""
    p = prep_rigid
    x = p.mesh.nodes
    _, r = _independent_prestress(p)
    fr = p.operators.f_centrifugal + r
    rng = np.random.default_rng(3)
    for _ in range(3):
        B = rng.standard_normal((3, 3))
        v = (x @ B.T).ravel()
        w = (x @ (B.T @ B).T).ravel()  # (B^T B) x, B^T B symmetric
        got = v @ (p.stress_stiffening @ v)
        assert got == pytest.approx(w @ fr, rel=1e-10)


# ------------------------------------------------------------------ Coriolis coupling


def test_coriolis_coefficients_of_nd_pairs_condensed_vs_full(prep_rigid):
    p = prep_rigid
    c, ops, cp = p.condensed, p.operators, p.coupled
    nb = len(p.master_dofs)
    keep = np.ones(c.K.shape[0], bool)
    keep[nb - cp.bearing_dofs.size : nb] = False
    lam, V = sla.eigh(c.K[np.ix_(keep, keep)], c.M[np.ix_(keep, keep)])
    Vc = np.zeros((c.K.shape[0], V.shape[1]))
    Vc[keep] = V
    f_full = p.frequencies_full_hz
    f_c = np.sqrt(lam[: len(f_full)]) / (2 * math.pi)
    Phi = p.mode_shapes  # full-DOF, mass-normalised, bearings held
    G = ops.gyroscopic
    rows = []
    k = 0
    while k < len(f_full) - 1:
        if abs(f_full[k + 1] / f_full[k] - 1) > 1e-6:
            k += 1
            continue
        assert p.families[k].nodal_diameters >= 1
        assert abs(f_c[k + 1] / f_c[k] - 1) < 1e-5  # the condensed pair is (nearly) degenerate
        P, Q = Phi[:, k : k + 2], Vc[:, k : k + 2]
        gP = (P.T @ G @ P)[0, 1]
        Gq = Q.T @ c.gyroscopic @ Q
        gQ = Gq[0, 1]
        # eigenvalues of the 2x2 skew matrices: +-i|g|
        assert np.allclose(np.abs(np.linalg.eigvals(Gq).imag), abs(gQ), rtol=1e-12)
        Qf = _expand(p, Q)
        E = Qf - P @ (P.T @ (ops.M @ Qf))
        s = math.sqrt(np.linalg.eigvalsh(E.T @ (ops.M @ E)).max())
        rows.append((p.families[k].nodal_diameters, abs(gP), abs(gQ), s))
        k += 2
    rows = np.array(rows)
    assert len(rows) >= 6, rows
    _, gP, gQ, s = rows.T
    err = np.abs(gQ - gP)
    # a priori bound from the subspace angle (module doc)
    assert np.all(err <= 2 * s + (1 + gP) * s**2), rows
    # measured on this wheel (Craig-Bampton, 50 modes + psi, first 20 modes): relative error
    # 4e-5 (ND1) ... 1.2 % (ND4, g = 0.12), 0.12 % / 0.6 % on the strongly gyroscopic
    # in-plane pairs (g = 0.87 / 0.90)
    assert np.all(err / gP < 0.02), rows
    strong = gP > 0.5
    assert strong.sum() >= 2 and np.all(err[strong] / gP[strong] < 0.01), rows


# ------------------------------------------------------------------------------ file


def test_npz_holds_the_rotating_frame_matrices(prep_rigid, tmp_path):
    p = prep_rigid
    path = save_condensed(p, tmp_path / "w.npz")
    cb = load_condensed(path)
    assert FORMAT_VERSION == 4
    for name in ("gyroscopic", "spin_softening", "stress_stiffening"):
        np.testing.assert_array_equal(getattr(cb, name), getattr(p.condensed, name))
    with np.load(path) as z:
        G = z["gyroscopic"]
    bad = tmp_path / "bad.npz"
    _rewrite(path, bad, gyroscopic=None)
    with pytest.raises(ValueError, match="missing key.*gyroscopic"):
        load_condensed(bad)
    _rewrite(path, bad, stress_stiffening=G[:-1])
    with pytest.raises(ValueError, match="stress_stiffening has shape"):
        load_condensed(bad)
    _rewrite(path, bad, format_version=np.array(2))
    with pytest.raises(ValueError, match="format_version 2"):
        load_condensed(bad)
    # the former switch of the body file is still accepted
    assert parse_body(wheel_text().replace("[centrifugal]", "[centrifugal]\nspin_softening = true"))
