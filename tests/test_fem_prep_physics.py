"""Physics of the assembled operators against independent analytic references.

* Cantilever: Euler-Bernoulli frequencies ``omega_k = (beta_k L)^2 sqrt(E I / (rho A L^4))``,
  ``beta_1 L = 1.875104``, ``beta_2 L = 4.694091`` (roots of ``cos x cosh x = -1``).
* Annular plate clamped at the inner edge, free at the outer edge: Kirchhoff theory, the
  frequency determinant of Vogel & Skinner (J. Appl. Mech. 32, 1965) reproduced in Leissa,
  *Vibration of Plates*, NASA SP-160 (1969), Sec. 2.2; the roots are computed here from Bessel
  functions (scipy.special), independently of the finite elements.
* Thin rotating annular disc held at the bore: plane-stress solution ``u = A r + B/r -
  (1 - nu^2) rho w^2 r^3 / (8 E)`` with ``u(a) = 0`` and ``sigma_r(b) = 0`` (Timoshenko &
  Goodier, Theory of Elasticity, Sec. 32).
"""

import math

import numpy as np
import pytest
import scipy.optimize as so
import skfem
from scipy import special

from fem_prep import assemble_operators, factorize, mesh_body, parse_body, shift_invert_modes
from fem_prep._body import Material

E, NU, RHO = 210e9, 0.3, 7800.0


def _eliminate(K, M, fixed):
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    return K[free][:, free], M[free][:, free], free


# ---------------------------------------------------------------------------------- cantilever


def _cantilever_freqs(nx: int, element) -> np.ndarray:
    L, h = 0.4, 0.02
    m1 = skfem.MeshHex.init_tensor(
        np.linspace(0, L, nx + 1), np.linspace(0, h, 2), np.linspace(0, h, 2)
    )
    mesh = skfem.MeshHex2.from_mesh(m1)
    basis = skfem.Basis(mesh, skfem.ElementVector(element), intorder=4)
    ops = assemble_operators(basis, Material(E, NU, RHO))
    x = basis.doflocs
    fixed = np.nonzero(np.isclose(x[0], 0.0))[0]
    K, M, _ = _eliminate(ops.K, ops.M, fixed)
    lam, _ = shift_invert_modes(K, M, 6)
    return np.sqrt(lam) / (2 * math.pi)


def test_cantilever_euler_bernoulli_converges():
    L, h = 0.4, 0.02
    I, A = h**4 / 12, h * h
    ref = [
        (bl**2) * math.sqrt(E * I / (RHO * A * L**4)) / (2 * math.pi) for bl in (1.875104, 4.694091)
    ]
    errs = []
    for nx in (4, 8, 16):
        f = _cantilever_freqs(nx, skfem.ElementHexS2())
        # bending modes come in (y, z) pairs for the square section: modes 0,1 and 2,3
        assert f[0] == pytest.approx(f[1], rel=1e-6)
        errs.append([abs(f[0] / ref[0] - 1), abs(f[2] / ref[1] - 1)])
    errs = np.array(errs)
    assert np.all(np.diff(errs[:, 1]) < 0), errs  # second mode converges monotonically
    # the finest mesh is within 1 % (L/h = 20: shear/rotary inertia effects ~0.3 %)
    assert errs[-1, 0] < 0.01 and errs[-1, 1] < 0.01, errs


def test_cantilever_hex27_euler_bernoulli():
    L, h = 0.4, 0.02
    ref = 1.875104**2 * math.sqrt(E * h**2 / 12 / (RHO * L**4)) / (2 * math.pi)
    f27 = _cantilever_freqs(16, skfem.ElementHex2())
    assert f27[0] == pytest.approx(ref, rel=0.01)


# ------------------------------------------------------------------------------ annular plate


def _disc_text(b_mm, a_mm, h_mm, size_mm, teeth, circ_mm, speed=0.0):
    return f"""
name = "disc"
[body]
bore_radius_mm = {b_mm}
hub_outer_radius_mm = {0.5 * (a_mm + b_mm)}
hub_width_mm = {h_mm}
web_thickness_mm = {h_mm}
rim_inner_radius_mm = {0.5 * (a_mm + b_mm)}
rim_outer_radius_mm = {a_mm}
rim_width_mm = {h_mm}
[[bearings]]
axial_position_mm = 0.0
[mesh]
size_mm = {size_mm}
circumferential_size_mm = {circ_mm}
[condensation]
teeth = {teeth}
axial_master_nodes = 1
[centrifugal]
speed_rad_s = {speed}
"""


def _kirchhoff_clamped_free(n: int, beta: float, nu: float) -> np.ndarray:
    """Roots lambda = k a (first few) of the clamped(inner r = beta a)-free(outer) determinant."""

    def fns(x):
        # w, w', w'', w''' for J, Y, I, K at argument x (derivatives wrt x)
        out = []
        for f, fd in (
            (special.jv, special.jvp),
            (special.yv, special.yvp),
            (special.iv, special.ivp),
            (special.kv, special.kvp),
        ):
            out.append([f(n, x), fd(n, x, 1), fd(n, x, 2), fd(n, x, 3)])
        return np.array(out)  # (4 functions, 4 derivatives)

    def det(lam):
        # radius in units of a, k a = lam: d/dr = lam d/dx
        xb, xa = lam * beta, lam
        Fb, Fa = fns(xb), fns(xa)
        rows = []
        rows.append(Fb[:, 0])  # w(b) = 0
        rows.append(lam * Fb[:, 1])  # w'(b) = 0
        r = 1.0
        w, w1, w2, w3 = Fa[:, 0], lam * Fa[:, 1], lam**2 * Fa[:, 2], lam**3 * Fa[:, 3]
        rows.append(w2 + nu * (w1 / r - n * n * w / r**2))  # M_r(a) = 0
        # V_r = d/dr(lap w) + (1 - nu) n^2 (w/r - w')/r^2 ... with lap w = w'' + w'/r - n^2 w/r^2
        dlap = w3 + w2 / r - w1 / r**2 - n * n * (w1 / r**2 - 2 * w / r**3)
        rows.append(dlap - (1 - nu) * n * n * (w1 / r**2 - w / r**3))  # V_r(a) = 0
        return np.linalg.det(np.array(rows))

    grid = np.linspace(0.5, 12.0, 2000)
    vals = np.array([det(g) for g in grid])
    roots = [
        so.brentq(det, a, b)
        for a, b, va, vb in zip(grid[:-1], grid[1:], vals[:-1], vals[1:])
        if va * vb < 0
    ]
    return np.array(roots)


def _plate_fe(size_mm, circ_mm, teeth):
    a, b, h = 100.0, 50.0, 2.0
    body = parse_body(_disc_text(b, a, h, size_mm, teeth, circ_mm))
    bm = mesh_body(body)
    ops = assemble_operators(bm.basis, body.material)
    r = np.hypot(bm.nodes[:, 0], bm.nodes[:, 1])
    fixed_nodes = np.nonzero(np.isclose(r, b * 1e-3))[0]
    fixed = (3 * fixed_nodes[:, None] + np.arange(3)).ravel()
    K, M, free = _eliminate(ops.K, ops.M, fixed)
    lam, phi = shift_invert_modes(K, M, 8)
    return np.sqrt(lam) / (2 * math.pi), body


def test_annular_plate_against_kirchhoff_and_converges():
    a, h = 0.1, 0.002
    D = E * h**3 / (12 * (1 - NU**2))
    scale = math.sqrt(D / (RHO * h)) / a**2 / (2 * math.pi)  # f = lam^2 * scale
    # lowest out-of-plane modes: n = 0 (single) and n = 1, 2 (pairs)
    ref = sorted([_kirchhoff_clamped_free(n, 0.5, NU)[0] ** 2 * scale for n in (0, 1, 1, 2, 2)])
    errs = []
    for size, circ in ((12.5, 20.0), (6.25, 10.0)):
        f, _ = _plate_fe(size, circ, 16)
        errs.append(np.abs(f[:5] / np.array(ref) - 1))
    errs = np.array(errs)
    assert np.all(errs[1] <= errs[0] + 1e-4), errs  # converges under refinement
    assert np.all(errs[1] < 0.5 * errs[0]), errs
    assert errs[1].max() < 0.02, errs  # 3-D solid vs Kirchhoff (h/a = 0.02)


# -------------------------------------------------------------------------- rotating disc


def test_rotating_disc_plane_stress_within_1_percent():
    a_mm, b_mm, h_mm, w = 20.0, 100.0, 2.0, 1000.0
    body = parse_body(_disc_text(a_mm, b_mm, h_mm, 5.0, 24, 12.0, speed=w))
    bm = mesh_body(body)
    ops = assemble_operators(bm.basis, body.material)
    x = bm.nodes
    r = np.hypot(x[:, 0], x[:, 1])
    bore = np.isclose(r, a_mm * 1e-3)
    # bore held radially and tangentially (u_x = u_y = 0), axial motion free except on the
    # mid-plane (no rigid axial translation): the plane-stress boundary condition u(a) = 0
    fixed = np.concatenate(
        [
            3 * np.nonzero(bore)[0],
            3 * np.nonzero(bore)[0] + 1,
            3 * np.nonzero(bore & np.isclose(x[:, 2], 0.0))[0] + 2,
        ]
    )
    K, _, free = _eliminate(ops.K, ops.M, fixed)
    u = np.zeros(ops.K.shape[0])
    u[free] = factorize(K).solve(w**2 * ops.f_centrifugal[free])
    outer = np.isclose(r, b_mm * 1e-3) & np.isclose(x[:, 2], 0.0)
    uu = u.reshape(-1, 3)[outer]
    ur_fe = np.mean((uu[:, 0] * x[outer, 0] + uu[:, 1] * x[outer, 1]) / r[outer])
    # analytic plane stress
    a, b = a_mm * 1e-3, b_mm * 1e-3
    c = (1 - NU**2) * RHO * w**2 / (8 * E)
    Amat = np.array([[a, 1 / a], [E / (1 - NU**2) * (1 + NU), -E / (1 - NU**2) * (1 - NU) / b**2]])
    rhs = np.array(
        [
            c * a**3,
            (3 + NU) * RHO * w**2 * b**2 / 8
            - E / (1 - NU**2) * (3 + NU) * c * b**2
            + (3 + NU) * RHO * w**2 * b**2 / 8 * 0,
        ]
    )
    # sigma_r = E/(1-nu^2)[(1+nu)A - (1-nu)B/r^2] - (3+nu) rho w^2 r^2 / 8 = 0 at r = b
    rhs[1] = (3 + NU) * RHO * w**2 * b**2 / 8
    A_, B_ = np.linalg.solve(Amat, rhs)
    ur_ref = A_ * b + B_ / b - c * b**3
    assert ur_fe == pytest.approx(ur_ref, rel=0.01)
