"""Gear whine in the frequency domain (:func:`jaxgear.dynamics.whine_response`, docs/whine.md).

References, each written apart from the code:

* a 1-DOF oscillator with a sinusoidal stiffness k(t) = k0 (1 + ε cos ωt): the harmonic balance
  truncated at one harmonic solved by hand (substitution in three complex unknowns); the
  untruncated multi-harmonic solution by continued fractions (the balance is tridiagonal:
  beyond the forced harmonics Y_{h+1}/Y_h is a continued fraction); a DOP853 integration to
  its periodic steady state;
* the lumped pair's linear periodic system (the active set of the static solve held, its
  stiffness piecewise constant over the table's positions) integrated exactly over one period
  with matrix exponentials, its periodic orbit from the monodromy matrix (fixed point);
* the time-domain Newmark with unilateral contact (:func:`jaxgear.dynamics.simulate`) on the
  same model where it stays in contact.
"""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.integrate as si
import scipy.linalg as sl

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import (
    HarmonicBalance,
    Newmark,
    SteadyState,
    TransmissionErrorSource,
    dynamic_model,
    excited_omega,
    harmonic_balance,
    mesh_table,
    simulate,
    whine_response,
)
from jaxgear.scenes import TorsionalDynamics, disc_inertia

# the 1-DOF oscillator: m x'' + c x' + k0 (1 + eps cos wt) x = F0 + F1 cos(wt + phi)
M1, K0, EPS, ZETA = 2.0, 8.0e6, 0.3, 0.03
C1 = 2 * ZETA * math.sqrt(K0 * M1)
F0, F1, PHI = 1.0e3, 400.0, 0.7


def _oscillator(omega, H, parametric=True, real=False):
    k = np.zeros((4 * H + 1, 1, 1), complex)
    k[2 * H] = K0
    k[2 * H - 1] = k[2 * H + 1] = K0 * EPS / 2
    f = np.zeros((2 * H + 1, 1), complex)
    f[H] = F0
    f[H + 1] = F1 * np.exp(1j * PHI) / 2
    f[H - 1] = np.conj(f[H + 1])
    m, c, z = (jnp.array([[v]]) for v in (M1, C1, 0.0))
    Y = harmonic_balance(
        m, c, z, jnp.asarray(k), jnp.asarray(f), omega, parametric=parametric, real=real
    )
    return np.asarray(Y)[:, 0]


def _a(h, omega):
    return K0 - (h * omega) ** 2 * M1 + 1j * h * omega * C1


def _by_substitution(omega, ratio_up=0.0, ratio_down=0.0):
    """Y_{-1}, Y_0, Y_1 of the balance closed by Y_{±2} = ratio × Y_{±1} (0: truncation at one
    harmonic): a_{±1}' Y_{±1} + b Y_0 = F_{±1}, a_0 Y_0 + b (Y_1 + Y_-1) = F_0, solved by
    substituting Y_{±1} = (F_{±1} − b Y_0) / a_{±1}'."""
    b = K0 * EPS / 2
    f1 = F1 * np.exp(1j * PHI) / 2
    ap = _a(1, omega) + b * ratio_up
    am = _a(-1, omega) + b * ratio_down
    y0 = (F0 - b * (f1 / ap + np.conj(f1) / am)) / (_a(0, omega) - b * b * (1 / ap + 1 / am))
    return (np.conj(f1) - b * y0) / am, y0, (f1 - b * y0) / ap


def _continued_fraction(omega, sign, depth=400):
    """Y_{2s}/Y_{s} (s = ±1) of the unforced tail: r_h = −b / (a_{h+1} + b r_{h+1})."""
    b = K0 * EPS / 2
    r = 0.0
    for h in range(depth, 0, -1):
        r = -b / (_a(sign * (h + 1), omega) + b * r)
    return r


@pytest.mark.parametrize("ratio", [0.35, 0.8, 1.6])
def test_one_harmonic_truncation_equals_the_hand_solution(ratio):
    """H = 1: the 3 × 3 complex balance equals its solution by substitution to 1e-12."""
    omega = ratio * math.sqrt(K0 / M1)
    Y = _oscillator(omega, 1)
    np.testing.assert_allclose(Y, _by_substitution(omega), rtol=1e-12)


@pytest.mark.parametrize("ratio", [0.35, 0.8, 1.6])
def test_oscillator_converges_to_the_continued_fraction_solution(ratio):
    """H = 24 against the untruncated solution (continued fractions): Y_0, Y_1 to 1e-10; the
    time-invariant model (K̂_0 only) is off by more than 1 % (it drops the coupling of the
    harmonics through ε = 0.3)."""
    omega = ratio * math.sqrt(K0 / M1)
    exact = _by_substitution(omega, _continued_fraction(omega, 1), _continued_fraction(omega, -1))
    Y = _oscillator(omega, 24)
    np.testing.assert_allclose(Y[23:26], exact, rtol=1e-10)
    # a real system: the harmonics h < 0 as the conjugates of h > 0
    np.testing.assert_allclose(_oscillator(omega, 24, real=True), Y, rtol=1e-12, atol=0)
    mean = _oscillator(omega, 24, parametric=False)
    assert abs(abs(mean[25]) / abs(exact[2]) - 1) > 0.01


def test_multi_dof_balance_on_a_basis_equals_the_dense_system_over_a_speed_map():
    """A random 6-DOF real system, its time-varying stiffness on a rank-2 basis (H = 5), mapped
    over 4 speeds with ``jax.lax.map`` (one unbatched LU per harmonic and speed, as the whine
    sweep runs): each speed's Y_h equals the dense (2H + 1) n complex balance assembled from
    its block definition and solved by numpy, to 1e-12."""
    rng = np.random.default_rng(7)
    n, r, H = 6, 2, 5
    A = rng.standard_normal((n, n))
    M = np.eye(n) + 0.1 * (A @ A.T)
    K = 1e4 * (np.eye(n) + 0.1 * (A + A.T))
    C = 1e-3 * K + 0.5 * M
    B = np.linalg.qr(rng.standard_normal((n, r)))[0]
    Kr = np.zeros((4 * H + 1, r, r), complex)
    for k in range(2 * H + 1):
        S = rng.standard_normal((r, r)) + 1j * rng.standard_normal((r, r))
        Kr[2 * H + k] = (S + S.T) * 300.0 / (1 + k) ** 2
        Kr[2 * H - k] = np.conj(Kr[2 * H + k])
    Kr[2 * H] = np.real(Kr[2 * H]) + 2e3 * np.eye(r)
    F = rng.standard_normal((2 * H + 1, n)) + 1j * rng.standard_normal((2 * H + 1, n))
    F = (F + np.conj(F[::-1])) / 2  # real in time
    speeds = np.array([20.0, 55.0, 90.0, 140.0])
    Ys = jax.lax.map(
        lambda w: harmonic_balance(*(jnp.asarray(a) for a in (M, C, K, Kr, F)), w,
                                   basis=jnp.asarray(B), real=True),
        jnp.asarray(speeds),
    )
    for w, Y in zip(speeds, np.asarray(Ys), strict=True):
        big = np.zeros(((2 * H + 1) * n, (2 * H + 1) * n), complex)
        for i, h in enumerate(range(-H, H + 1)):
            big[i * n:(i + 1) * n, i * n:(i + 1) * n] = K - (h * w) ** 2 * M + 1j * h * w * C
            for j, q in enumerate(range(-H, H + 1)):
                big[i * n:(i + 1) * n, j * n:(j + 1) * n] += B @ Kr[2 * H + h - q] @ B.T
        ref = np.linalg.solve(big, F.reshape(-1)).reshape(2 * H + 1, n)
        np.testing.assert_allclose(Y, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


# default tier: tests/test_whine.py::test_oscillator_converges_to_the_continued_fraction_solution (same claim, the untruncated balance of the oscillator against a solution written apart, the continued fraction)
@pytest.mark.slow
def test_oscillator_against_time_integration():
    """H = 24 against DOP853 (rtol 1e-12) after 400 periods: the first three harmonics'
    amplitudes to 1e-6 of the fundamental's, phases to 1e-4 rad."""
    omega = 0.8 * math.sqrt(K0 / M1)
    T = 2 * math.pi / omega

    def rhs(t, z):
        k = K0 * (1 + EPS * math.cos(omega * t))
        f = F0 + F1 * math.cos(omega * t + PHI)
        return [z[1], (f - C1 * z[1] - k * z[0]) / M1]

    z = si.solve_ivp(rhs, (0, 400 * T), [F0 / K0, 0.0], method="DOP853", rtol=1e-12, atol=1e-16)
    t = 400 * T + np.arange(512) * T / 512
    sol = si.solve_ivp(
        rhs, (400 * T, 401 * T), z.y[:, -1], method="DOP853", rtol=1e-12, atol=1e-16, t_eval=t
    )
    x = sol.y[0]
    ref = np.array([np.mean(x * np.exp(-1j * h * omega * t)) for h in range(4)])
    Y = _oscillator(omega, 24)[24:28]
    scale = abs(ref[1])
    np.testing.assert_allclose(np.abs(Y), np.abs(ref), rtol=0, atol=1e-6 * scale)
    np.testing.assert_allclose(np.angle(Y[1:] / ref[1:]), 0.0, atol=1e-4)


# -------------------------------------------------------------------------------------------
# the lumped accessory pair (tip relief: no contact loss at these speeds)


def _pair(relief=True, reduced=False, scale=1.0):
    case = jio.load_case("accessory-spur").replace(slices=4)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2)
    if reduced:
        scene = scene.reduced()
    mods = case.modifications if relief else None
    if relief and scale != 1.0:
        mods = jax.tree.map(lambda a: a * scale, mods)
    return dynamic_model(scene, mods, case.torque)


def _critical(model):
    return float(jnp.max(model.critical_speeds(1)))


def _linear_periodic_reference(model, speed, P, orders=4, sub=8):
    """The TE harmonics of the linear periodic system of ``model`` (1 coordinate): on the row
    r interval [r, r+1) Δt the stiffness K_s + Σ w k l V Vᵀ and the static solution x_r of row
    r (the active set of the static solve held), integrated exactly (matrix exponentials),
    the periodic orbit from the monodromy matrix; TE sampled at ``sub`` points per row."""
    scene = model.scene
    table = mesh_table(scene, model.mods, P)
    M, Ks, C = (np.asarray(a) for a in (scene.mass(), scene.stiffness(), model.damping))
    F = scene.external_load(model.torque)
    n = M.shape[0]
    Mi = np.linalg.inv(M)
    dt = float(model.mesh.mesh_period_angle) / speed / P
    rows = [table.at(r) for r in range(P)]
    V, k, ln, d0, mask = (
        jnp.stack([getattr(r, f) for r in rows]) for f in ("V", "k", "length", "delta0", "mask")
    )
    sol = jax.vmap(lambda *a: jg.solve_contact(jnp.asarray(Ks), F, *a))(V, k, ln, d0, mask)
    kl = np.where(np.asarray(mask), np.asarray(sol.weight * k * ln), 0.0)
    V = np.asarray(V)
    steps, x, A = [], [], []
    for r in range(P):
        K = Ks + np.einsum("c,ci,cj->ij", kl[r], V[r], V[r])
        A.append(np.block([[np.zeros((n, n)), np.eye(n)], [-Mi @ K, -Mi @ C]]))
        x.append(np.concatenate([np.asarray(sol.x[r]), np.zeros(n)]))
        steps.append(sl.expm(A[-1] * dt / sub))
    # z(t) − z_r evolves freely on row r's interval: z ↦ E (z − z_r) + z_r
    Phi, c = np.eye(2 * n), np.zeros(2 * n)
    for r in range(P):
        E = np.linalg.matrix_power(steps[r], sub)
        c, Phi = E @ (c - x[r]) + x[r], E @ Phi
    z = np.linalg.solve(np.eye(2 * n) - Phi, c)
    u = np.asarray(scene.te_vectors())[0]
    half = [sl.expm(a * dt / sub / 2) for a in A]
    t, te = [], []
    for r in range(P):
        for k in range(sub):
            t.append((r + (k + 0.5) / sub) * dt)
            te.append(u @ (half[r] @ (z - x[r]) + x[r])[:n])
            z = steps[r] @ (z - x[r]) + x[r]
    t, te = np.array(t), np.array(te) / math.cos(float(model.mesh.base_helix_angle))
    w = 2 * math.pi / (P * dt)
    return np.array([2 * np.mean(te * np.exp(-1j * h * w * t)) for h in range(orders)])


# default tier: tests/test_whine.py::test_pair_against_newmark_in_its_linear_regime (same claim, the balance's orders equal the pair's periodic response, against Newmark's; the relative scene's dynamics run in tests/test_every_kind.py's pair-relative runs)
@pytest.mark.slow
@pytest.mark.parametrize("ratio", [0.15, 0.45])
def test_pair_equals_the_exact_linear_periodic_solution(ratio):
    """The relieved pair (1-DOF relative approach), 256 positions: orders 1-3 of the TE from
    the harmonic balance (H = 64) equal the exact periodic solution of the same linear
    periodic system to 1e-3 in amplitude and 0.05° in phase (measured: 1e-4 and 0.02°)."""
    model = _pair(reduced=True)
    speed = ratio * _critical(model)
    ref = _linear_periodic_reference(model, speed, 256)
    w = whine_response(model, speed, HarmonicBalance(63), positions=256)
    te = np.asarray(w.transmission_error[0, 1:4, 0])
    np.testing.assert_allclose(np.abs(te) / np.abs(ref[1:]), 1.0, atol=1e-3)
    np.testing.assert_allclose(np.degrees(np.angle(te / ref[1:])), 0.0, atol=0.05)


def _orders(r, speed, model, x):
    t = np.asarray(r.time)
    w = 2 * math.pi * speed / float(model.mesh_period_angle())
    x = np.asarray(x)
    return np.array([2 * np.mean(x * np.exp(-1j * h * w * t)) for h in range(4)])


def test_pair_against_newmark_in_its_linear_regime():
    """The relieved torsional pair (2 DOF with its free rotation) at 0.2 of its critical
    speed, no contact loss: orders 1-3 of the TE and of the mesh force within 1 % in amplitude
    and 1° in phase of Newmark's (256 steps per period, 60 periods, 4 kept; measured ≤ 0.9 %
    and 0.4°, the third order the farthest). The TE as a displacement source (mean stiffness)
    misses the mesh force's second order by more than 10 % (measured 42 %)."""
    model = _pair()
    speed = 0.2 * _critical(model)
    w = whine_response(model, speed, HarmonicBalance(64), positions=512)
    ts = whine_response(model, speed, TransmissionErrorSource(64), positions=512)
    r = simulate(model, speed, integrator=Newmark(256), window=SteadyState(60, 4))
    assert float(r.contact_loss) == 0.0 and not bool(w.contact_loss[0, 0])
    for fd, td in (
        (w.transmission_error, r.transmission_error),
        (w.mesh_force, r.mesh_force),
    ):
        ref = _orders(r, speed, model, td)[1:]
        got = np.asarray(fd[0, 1:4, 0])
        np.testing.assert_allclose(np.abs(got) / np.abs(ref), 1.0, atol=0.01)
        np.testing.assert_allclose(np.degrees(np.angle(got / ref)), 0.0, atol=1.0)
    ref = _orders(r, speed, model, r.mesh_force)[2]
    assert abs(abs(complex(ts.mesh_force[0, 2, 0])) / abs(ref) - 1) > 0.1


def test_contact_loss_is_flagged_where_newmark_loses_contact():
    """The unrelieved pair at its resonance loses contact in the time domain; the linear
    result says so there, and not at 0.2 of it where Newmark keeps contact."""
    model = _pair(relief=False)
    crit = _critical(model)
    speeds = np.array([0.2, 1.0]) * crit
    w = whine_response(model, speeds, HarmonicBalance(24), positions=128)
    assert np.asarray(w.contact_loss[:, 0]).tolist() == [False, True]
    for s, flag in zip(speeds, np.asarray(w.contact_loss[:, 0]), strict=True):
        r = simulate(model, s, integrator=Newmark(128), window=SteadyState(60, 4))
        assert bool(flag) == (float(r.contact_loss) > 0.0)


def test_float32():
    """float32 runs: the orders of the TE within 1e-3 of float64's (relative to order 1)."""
    speed = 0.3 * _critical(_pair())
    w64 = whine_response(_pair(), speed, HarmonicBalance(16), positions=128)
    with jax.enable_x64(False):
        m32 = _pair()
        w32 = whine_response(m32, np.float32(speed), HarmonicBalance(16), positions=128)
        assert w32.transmission_error.dtype == np.complex64
        te32 = np.asarray(w32.transmission_error[0, 1:4, 0])
    te64 = np.asarray(w64.transmission_error[0, 1:4, 0])
    np.testing.assert_allclose(te32, te64, rtol=0, atol=1e-3 * abs(te64[0]))


def test_bad_inputs():
    model = _pair(reduced=True)
    with pytest.raises(ValueError, match="speeds"):
        whine_response(model, [100.0, -1.0])
    with pytest.raises(ValueError, match="positions"):
        whine_response(model, 100.0, HarmonicBalance(64), positions=64)
    with pytest.raises(ValueError, match="harmonics"):
        HarmonicBalance(0)
    with pytest.raises(TypeError, match="method"):
        whine_response(model, 100.0, "harmonic-balance")
    with pytest.raises(TypeError, match="model"):
        whine_response(model.scene, 100.0)


# default tier: tests/test_whine.py::test_pair_against_newmark_in_its_linear_regime (same claim on the torsional pair); a lumped 3D scene's whine runs in test_a_train_spanning_several_mesh_periods_reports_the_first_meshs_frequency (the lumped two-stage train of tests/_kinds.py)
@pytest.mark.slow
def test_lumped3d_pair_against_newmark():
    """The case's own lumped 3D scene of ``accessory-spur`` (60 coordinates: shafts, bearings,
    the mesh spanning 2 of them) at 0.2 of the speed where order 1 meets its most excited
    mode: orders 1-3 of the TE and mesh force within 1 % and 1° of Newmark's (256 steps, 60
    periods; measured ≤ 0.6 % and 0.2°)."""
    case = jio.load_case("accessory-spur")
    model, _ = jio.build_dynamic_model(case, slices=4)
    omega = float(excited_omega(model.modes))
    speed = 0.2 * omega * float(model.mesh.mesh_period_angle) / (2 * math.pi)
    w = whine_response(model, speed, HarmonicBalance(32), positions=256)
    r = simulate(model, speed, integrator=Newmark(256), window=SteadyState(60, 4))
    assert float(r.contact_loss) == 0.0 and float(w.nonlinearity[0, 0]) < 1e-3
    for fd, td in (
        (w.transmission_error, r.transmission_error),
        (w.mesh_force, r.mesh_force),
    ):
        ref = _orders(r, speed, model, td)[1:]
        got = np.asarray(fd[0, 1:4, 0])
        np.testing.assert_allclose(np.abs(got) / np.abs(ref), 1.0, atol=0.01)
        np.testing.assert_allclose(np.degrees(np.angle(got / ref)), 0.0, atol=1.0)


# default tier: tests/test_whine.py::test_gradient_wrt_speed_under_jit (same claim, jax.grad of an order's amplitude equals the central difference, through a traced speed)
@pytest.mark.slow
def test_gradient_wrt_tip_relief_matches_central_differences():
    """d|F_m,1|/d(tip relief depth of both members) at 0.3 of the critical speed by jax.grad
    equals the central difference (step 1e-7 of the depth) to 1e-5 (measured 1e-8): the
    static solve, the stiffness harmonics and the balance are differentiated through."""
    model = _pair()
    speed = 0.3 * _critical(model)
    d0 = float(model.mods.pinion.tip_relief_depth)

    def order_one(d):
        mods = eqx.tree_at(
            lambda m: (m.pinion.tip_relief_depth, m.gear.tip_relief_depth), model.mods, (d, d)
        )
        m = eqx.tree_at(lambda m: m.mods, model, mods)
        w = whine_response(m, speed, HarmonicBalance(16), positions=128)
        return jnp.abs(w.mesh_force[0, 1, 0])

    grad = float(jax.grad(order_one)(jnp.asarray(d0)))
    step = 1e-7 * d0
    fd = float(order_one(d0 + step) - order_one(d0 - step)) / (2 * step)
    assert grad != 0.0
    np.testing.assert_allclose(grad, fd, rtol=1e-5)


# default tier: tests/test_whine.py::test_pair_against_newmark_in_its_linear_regime (same claim, the balance's orders within 1 % and 1° of Newmark's, on the torsional pair); a train's whine runs in test_a_train_spanning_several_mesh_periods_reports_the_first_meshs_frequency
@pytest.mark.slow
def test_idler_train_against_newmark_mesh_by_mesh():
    """The torsional ``accessory-idler-train`` (3 shafts, 2 meshes in their phases) at 0.2 of
    the speed where order 1 meets its most excited mode: each mesh's orders 1 and 2 of the TE
    and mesh force within 1 % and 1° of Newmark's (256 steps, 60 periods; measured ≤ 0.8 % and
    0.44°); order 3, which the moving contact boundary of the relieved cells reaches most
    (``nonlinearity`` 1.8 % of F_s on the first mesh), within 5 % and 5° (measured 4.4 % and
    4.2°, on the first mesh's TE)."""
    model, _ = jio.build_dynamic_model(jio.load_case("accessory-idler-train"), slices=4)
    assert model.mesh_count() == 2
    omega = float(excited_omega(model.modes))
    speed = 0.2 * omega * float(model.mesh_period_angle()) / (2 * math.pi)
    w = whine_response(model, speed, HarmonicBalance(32), positions=256)
    r = simulate(model, speed, integrator=Newmark(256), window=SteadyState(60, 4))
    assert not np.any(np.asarray(w.contact_loss))
    for k, mesh in enumerate(r.meshes):
        assert float(mesh.contact_loss) == 0.0
        for fd, td in (
            (w.transmission_error, mesh.transmission_error),
            (w.mesh_force, mesh.mesh_force),
        ):
            ref = _orders(r, speed, model, td)[1:]
            got = np.asarray(fd[0, 1:4, k])
            ratio, phase = np.abs(got) / np.abs(ref), np.degrees(np.angle(got / ref))
            np.testing.assert_allclose(ratio[:2], 1.0, atol=0.01)
            np.testing.assert_allclose(phase[:2], 0.0, atol=1.0)
            np.testing.assert_allclose(ratio[2], 1.0, atol=0.05)
            np.testing.assert_allclose(phase[2], 0.0, atol=5.0)


def test_gradient_wrt_speed_under_jit():
    """Traced speeds (jit, grad): d|TE_1|/dΩ by jax.grad equals the central difference to 1e-5."""
    model = _pair()
    s0 = 0.3 * _critical(model)

    @jax.jit
    def order_one(s):
        w = whine_response(model, s, HarmonicBalance(16), positions=128)
        return jnp.abs(w.transmission_error[0, 1, 0])

    grad = float(jax.grad(order_one)(jnp.asarray(s0)))
    step = 1e-6 * s0
    fd = float(order_one(s0 + step) - order_one(s0 - step)) / (2 * step)
    np.testing.assert_allclose(grad, fd, rtol=1e-5)


def test_a_train_spanning_several_mesh_periods_reports_the_first_meshs_frequency(tmp_path):
    """A train whose meshes repeat together every q = 2 periods of the first (20 → 30, then
    15 → 24 on the intermediate shaft): the span's harmonics are orders h / 2 of the first
    mesh, and ``frequency`` is the first mesh's, z_1 Ω / 2π, so that ``frequency * orders`` is
    each output's frequency in Hz (the run's CSV, the housing's iω and the acoustic band read
    it so)."""
    from _kinds import KINDS

    path = tmp_path / "train-two-stage.toml"
    path.write_text(KINDS["train-two-stage"])
    model, _ = jio.build_dynamic_model(jio.load_case(str(path)))
    speed = 50.0
    w = whine_response(model, speed, HarmonicBalance(4), positions=16)
    np.testing.assert_allclose(np.asarray(w.orders), np.arange(5) / 2.0)
    np.testing.assert_allclose(float(w.frequency[0]), 20 * speed / (2 * np.pi), rtol=1e-12)
    # order 1 of the first mesh at its mesh frequency
    np.testing.assert_allclose(float(w.frequency[0] * w.orders[2]), 20 * speed / (2 * np.pi),
                               rtol=1e-12)


def test_the_balanced_stiffness_and_static_te_are_quasi_statics_and_the_slow_limit():
    """What the balance linearises about is public: ``mesh_angle`` is the positions (r + ½) Δθ,
    Δθ = 2π/(z1 P), written out here; ``mesh_stiffness`` and ``static_transmission_error``
    equal an independent :func:`jaxgear.quasi_static` of the same scene at those angles (1e-12;
    measured 3e-16). Far below the first mode the whine's order 1 tends to the static TE's first
    harmonic, taken here from the quasi-static run: within 1e-4 at 1e-4 of the critical speed
    (measured 1.5e-5: the damping's i hω C, first order in the speed), ten times closer than at
    1e-3; the order 0 is its mean."""
    model = _pair()
    case = jio.load_case("accessory-spur")
    P = 64
    crit = _critical(model)
    w = whine_response(model, jnp.asarray([1e-4, 1e-3]) * crit, HarmonicBalance(8), positions=P)
    theta = (np.arange(P) + 0.5) * 2 * math.pi / (case.pair.pinion.teeth * P)
    np.testing.assert_allclose(np.asarray(w.mesh_angle), theta, rtol=1e-13)
    r = jg.quasi_static(model.scene, case.modifications, case.torque, theta=jnp.asarray(theta))
    te = np.asarray(r.transmission_error)
    assert w.static_transmission_error.shape == w.mesh_stiffness.shape == (P, 1)
    np.testing.assert_allclose(np.asarray(w.static_transmission_error[:, 0]), te, rtol=1e-12,
                               atol=1e-12 * np.max(np.abs(te)))
    np.testing.assert_allclose(np.asarray(w.mesh_stiffness[:, 0]),
                               np.asarray(r.mesh_stiffness), rtol=1e-12)
    h1 = 2 * np.mean(te * np.exp(-2j * np.pi * (np.arange(P) + 0.5) / P))
    err = np.abs(np.asarray(w.transmission_error[:, 1, 0]) - h1) / abs(h1)
    assert err[0] < 1e-4
    assert 5 < err[1] / err[0] < 20
    assert float(jnp.real(w.transmission_error[0, 0, 0])) == pytest.approx(te.mean(), rel=1e-6)
