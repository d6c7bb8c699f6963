"""The ball kinds' quasi-statics under a combined load against a separately written reference.

No published figure of a ball bearing's 5×5 stiffness under a combined load was at hand
(tests/test_bearing_published.py, docs/bearings.md "Evidence"), so this file writes the
quasi-static (no speed) Jones–Harris ball bearing of Harris & Kotzalas (*Advanced Concepts of
Bearing Technology*, 5th ed., §1.2: each ball between its two groove curvature centres, the
contact angle following the rings' displacement) with numpy and solves it with scipy, without
jaxgear: the inner ring's groove-centre locus point of ball j at p_j = r (cos ψ_j, sin ψ_j, 0)
moves by the ring's translation t plus γ × p_j (γ = (γ_x, γ_y, 0), small tilts), the groove
centres' distance is a_j = (A cos α₀ − P_d/2 + u_r, A sin α₀ + u_z), the ball's load
Q_j = K_n max(|a_j| − A, 0)^1.5 along a_j, and the bearing's load is the sum of those forces
and of their moments p_j × F_j about the bearing's centre. The displacement carrying a load F
is the minimum of the convex U(d) − F·d (scipy's BFGS) polished by scipy's root finder, the
stiffness central differences of the load there.

The bearing's numbers (Z, D, d_m, f_i, f_o, α₀, P_d) and its Hertz constant K_n are read from the
jaxgear bearing: K_n is checked separately against the exact Hertz theory (within 3 %,
tests/test_bearings.py). The tilt's lever r is the pitch radius d_m/2 as in jaxgear (Lim &
Singh's convention); Harris writes the radius of the inner groove curvature centres' locus,
d_m/2 + (f_i − 1/2) D cos α₀, a lever about 1 % longer for these bearings (a convention this
reference does not test).

Asserted, for the 6205 with 10 µm of clearance and the 7205 B (40°), each under a radial load
both ways, an axial load and moments about both axes: at the reference's displacement carrying
the load jaxgear's load is that load (10⁻⁹) and its stiffness the reference's central
differences (10⁻⁶ of each row's largest entry); in the slow tier jaxgear's
``solve_displacement`` finds the reference's displacement (10⁻⁷ of the largest translation).
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from scipy import optimize

import jaxgear.bearings as jb


def jones_harris_load(Z, A, alpha0, clearance, K, lever, d):
    """The load (F_x, F_y, F_z, M_x, M_y) the inner ring passes to the outer ring for its
    displacement d = (δ_x, δ_y, δ_z, γ_x, γ_y) (numpy; SI)."""
    psi = 2 * np.pi * np.arange(Z) / Z
    e_r = np.stack([np.cos(psi), np.sin(psi), np.zeros(Z)], axis=1)
    p = lever * e_r
    t, gamma = np.array([d[0], d[1], d[2]]), np.array([d[3], d[4], 0.0])
    u = t + np.cross(gamma, p)
    a_r = A * math.cos(alpha0) - clearance / 2 + np.sum(u * e_r, axis=1)
    a_z = A * math.sin(alpha0) + u[:, 2]
    length = np.hypot(a_r, a_z)
    Q = K * np.maximum(length - A, 0.0) ** 1.5
    F = (Q * a_r / length)[:, None] * e_r + np.outer(Q * a_z / length, [0.0, 0.0, 1.0])
    M = np.cross(p, F)
    return np.concatenate([F.sum(axis=0), M.sum(axis=0)[:2]])


def jones_harris_energy(Z, A, alpha0, clearance, K, lever, d):
    """The contact energy Σ K_n/2.5 max(δ_j, 0)^2.5 whose gradient is the load."""
    psi = 2 * np.pi * np.arange(Z) / Z
    c, s = np.cos(psi), np.sin(psi)
    a_r = A * math.cos(alpha0) - clearance / 2 + d[0] * c + d[1] * s
    a_z = A * math.sin(alpha0) + d[2] + lever * (d[3] * s - d[4] * c)
    return K / 2.5 * np.sum(np.maximum(np.hypot(a_r, a_z) - A, 0.0) ** 2.5)


def reference_solve(args, F, scale):
    """The displacement carrying F: BFGS on U(d) − F·d in scaled units (translations over
    ``scale``, tilts over scale / lever), then scipy's root finder on load(d) − F."""
    lever = args[-1]
    S = np.array([scale] * 3 + [scale / lever] * 2)
    Fs = np.concatenate([F[:3], F[3:] / lever])
    f_ref = np.abs(Fs).max()
    Pi = lambda x: (jones_harris_energy(*args, S * x) - F @ (S * x)) / (f_ref * scale)
    grad = lambda x: S * (jones_harris_load(*args, S * x) - F) / (f_ref * scale)
    x = optimize.minimize(Pi, np.full(5, 0.1), jac=grad, method="BFGS",
                          options={"gtol": 1e-10, "maxiter": 2000}).x

    def res(x):
        f = jones_harris_load(*args, S * x) - F
        return np.concatenate([f[:3], f[3:] / lever]) / f_ref

    sol = optimize.root(res, x, method="hybr", options={"xtol": 1e-13})
    assert np.abs(res(sol.x)).max() < 1e-11  # converged (hybr may stop at its xtol first)
    return S * sol.x


def reference_stiffness(args, d, scale):
    """Central differences of the reference's load (steps 10⁻⁴ of the displacement scale)."""
    lever = args[-1]
    h = 1e-4 * np.array([scale] * 3 + [scale / lever] * 2)
    K = np.zeros((5, 5))
    for j in range(5):
        e = np.zeros(5)
        e[j] = h[j]
        K[:, j] = (jones_harris_load(*args, d + e) - jones_harris_load(*args, d - e)) / (2 * h[j])
    return K


@eqx.filter_jit
def _load_and_stiffness(bearing, d):
    return bearing.load(d), bearing.stiffness(d)


CASES = {
    "6205": ({"clearance": 10e-6}, [1500.0, -400.0, 300.0, 4.0, -2.0]),
    "7205 B": ({}, [1200.0, -300.0, 2500.0, 3.0, 6.0]),
}
SCALE = 1e-5  # the displacement scale of the reference's solve (m)


@pytest.fixture(scope="module", params=list(CASES))
def case(request):
    """(bearing, F, the reference's arguments and its displacement carrying F)."""
    kw, F = CASES[request.param]
    b = jb.catalogue(request.param, **kw)
    a0 = float(b.contact_angle) if isinstance(b, jb.AngularContactBall) else 0.0
    A = (float(b.inner_conformity) + float(b.outer_conformity) - 1) * float(b.element_diameter)
    args = (b.elements, A, a0, float(b.clearance), float(b.hertz_constant),
            0.5 * float(b.pitch_diameter))
    F = np.array(F)
    d_ref = reference_solve(args, F, SCALE)
    np.testing.assert_allclose(jones_harris_load(*args, d_ref), F, rtol=0,
                               atol=1e-9 * np.abs(F).max())
    return b, F, args, d_ref


def test_load_and_stiffness_at_the_reference_equilibrium(case):
    """At the reference's displacement carrying F, jaxgear's load is F (10⁻⁹ of the largest
    component, moments over the pitch radius): the reference's equilibrium is jaxgear's (the
    minimum of the convex U(d) − F·d is unique where the balls are loaded); its 5×5 stiffness
    there against the reference's central differences (10⁻⁶ of each row's largest entry)."""
    b, F, args, d_ref = case
    lever = args[-1]
    scaled = lambda f: np.concatenate([f[:3], f[3:] / lever])
    f, K = (np.asarray(x) for x in _load_and_stiffness(b, jnp.asarray(d_ref)))
    np.testing.assert_allclose(scaled(f), scaled(F), rtol=0, atol=1e-9 * np.abs(scaled(F)).max())
    K_ref = reference_stiffness(args, d_ref, SCALE)
    row = np.abs(K_ref).max(axis=1, keepdims=True)
    assert np.all(np.abs(K - K_ref) <= 1e-6 * row)


@pytest.mark.slow  # compiles the solve of each bearing (~10 s loaded)
def test_solve_against_the_reference(case):
    """jaxgear's ``solve_displacement`` against the reference's displacement (10⁻⁷ of the largest
    translation, tilts times the pitch radius) and its state's stiffness against the
    reference's (10⁻⁶ of each row's largest entry)."""
    b, F, args, d_ref = case
    lever = args[-1]
    s = jb.solve_displacement(b, jnp.asarray(F))
    scaled = lambda x: np.concatenate([x[:3], x[3:] * lever])
    np.testing.assert_allclose(scaled(np.asarray(s.displacement)), scaled(d_ref), rtol=0,
                               atol=1e-7 * np.abs(d_ref[:3]).max())
    K_ref = reference_stiffness(args, d_ref, SCALE)
    row = np.abs(K_ref).max(axis=1, keepdims=True)
    assert np.all(np.abs(np.asarray(s.stiffness) - K_ref) <= 1e-6 * row)
