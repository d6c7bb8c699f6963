"""Dynamic model: modal analysis, damping, Newmark + contact, diffrax, sweeps.

Each test has an independent reference: the closed-form torsional frequency sqrt(k̄/m_eq) and a
SciPy generalised eigensolver, the quasi-static solver at low speed, exact energy conservation of
the average-acceleration rule on a linear system, the closed-form free vibration for the
convergence order, the mesh-frequency coincidence for the critical speed, central finite
differences for the gradient.
"""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _scene_solve import half_face_meshes

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import (
    Both,
    DiffraxIntegrator,
    LinearSystem,
    Newmark,
    Outputs,
    SteadyState,
    StepCells,
    band_dynamic_factor,
    damping_matrix,
    dynamic_model,
    mesh_table,
    newmark,
    simulate,
    speed_sweep,
)
from jaxgear.io import Damping
from jaxgear.scenes import TorsionalDynamics, disc_inertia


def _inertias(case):
    p = case.pair
    return (
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    )


@pytest.fixture(scope="module")
def accessory():
    case = jio.load_case("accessory-spur").replace(slices=2)
    i1, i2 = _inertias(case)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2)
    return case, scene


@pytest.fixture(scope="module")
def linear_case():
    """Uniform stiffness, long tip relief near the Master-Curve design load: small excitation,
    no contact loss, a linear response (docs/design.md, "Optimisation")."""
    case = jio.load_case("accessory-spur").replace(
        stiffness=jg.Uniform(14e9), slices=2
    )
    p = case.pair
    eps = p.transverse_contact_ratio
    dm = 1.03 * case.normal_load / (14e9 * eps * p.face_width)
    mods = jg.Modifications.symmetric(
        jg.MemberModification(tip_relief_depth=eps * dm, tip_relief_extent=(eps - 1) / eps)
    )
    i1, i2 = _inertias(case)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2)
    return case, scene, mods


def test_disc_inertia_and_torsional_frequency(accessory):
    case, scene = accessory
    p = case.pair
    # solid disc by hand: m r²/2 with m = ρ π r² b
    r, b = p.tip_radii[0], p.pinion.face_width
    mass = case.density * math.pi * r**2 * b
    assert float(scene.inertia_pinion) == pytest.approx(mass * r**2 / 2, rel=1e-12)
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=32)
    rb1, rb2 = p.base_radii
    m_eq = 1.0 / (rb1**2 / float(scene.inertia_pinion) + rb2**2 / float(scene.inertia_gear))
    f_ref = math.sqrt(float(model.mesh_stiffness_mean) / m_eq) / (2 * math.pi)
    f = np.asarray(model.modes.frequency)
    assert f[0] == 0.0 and bool(model.modes.rigid[0])  # free-free chain: one rigid-body mode
    assert f[1] == pytest.approx(f_ref, rel=1e-10)
    assert 4e3 < f_ref < 8e3  # order of magnitude: a few kHz for this accessory pair
    # the 1-DOF relative-approach reduction has the same frequency
    red = dynamic_model(scene.reduced(), case.modifications, case.torque, positions_per_pitch=32)
    assert float(red.modes.frequency[0]) == pytest.approx(f_ref, rel=1e-10)
    assert float(red.modes.mesh_energy[0]) == pytest.approx(1.0)
    # critical speed: mesh frequency Ω z1 / 2π = f
    assert float(model.critical_speeds()[1]) == pytest.approx(2 * math.pi * f_ref / p.pinion.teeth)


def test_torsional_model_is_a_structure_of_rotations_with_one_mesh(accessory):
    """The torsional model is a structure plus its mesh, like the 3D scenes: one-rotation nodes
    (motor, pinion, gear, load), the torque on the first and last, the mesh's members giving
    V = cos β_b (r_b1, −r_b2) on the pinion and gear rotations for every cell on the flanks
    (none off them); M and K as written out by hand (diagonal inertias, shafts e eᵀ k)."""
    scene = accessory[1]
    s4 = TorsionalDynamics(
        scene.mesh, 1e-3, 2e-3, 5e-3, 4e-2, 2e4, 6e4, has_motor=True, has_load=True
    )
    st = s4.structure
    assert [st.node(k) for k in ("input", "pinion", "gear", "output")] == [0, 1, 2, 3]
    assert s4.torque_dofs == (0, 3)
    m = scene.mesh
    cb, r1, r2 = (
        float(v) for v in (jnp.cos(m.base_helix_angle), m.base_radius_pinion, m.base_radius_gear)
    )

    # the cells at one position and their vectors in one compiled program (op by op they were
    # some 90 small programs)
    @eqx.filter_jit
    def cells_and_vectors(s4, m, angle):
        cells = m.cells(angle)
        return cells, s4.cell_vectors(cells)

    cells, V = cells_and_vectors(s4, m, 0.3 * float(m.mesh_period_angle))
    V = np.asarray(V)
    on = np.asarray(cells.mask)
    np.testing.assert_allclose(
        V[on], np.broadcast_to([0.0, cb * r1, -cb * r2, 0.0], V[on].shape), rtol=1e-15
    )
    assert not V[~on].any()
    np.testing.assert_allclose(np.asarray(s4.mass()), np.diag([5e-3, 1e-3, 2e-3, 4e-2]), rtol=1e-15)
    K = np.zeros((4, 4))
    K[np.ix_([0, 1], [0, 1])] += 2e4 * np.array([[1, -1], [-1, 1]])
    K[np.ix_([2, 3], [2, 3])] += 6e4 * np.array([[1, -1], [-1, 1]])
    np.testing.assert_allclose(np.asarray(s4.stiffness()), K, rtol=1e-15)
    np.testing.assert_allclose(
        np.asarray(s4.external_load(2.0)), [2.0, 0.0, 0.0, -2.0 * r2 / r1], rtol=1e-15
    )


def test_torsional_pair_cut_into_two_half_face_meshes_gives_the_pair_response(accessory):
    """The torsional structure runs every mesh of a scene: the pair cut across the face into two
    half-face meshes on the same rotations has the pair's modes and mean mesh stiffness and, at
    1000 rad/s (Newmark 32, 4 periods, 2 kept), each half the pair's dynamic factor, tooth factor
    and TE RMS, its static force half of T/(r_b1 cos β_b), to 1e-9."""
    case, scene = accessory
    two = eqx.tree_at(lambda s: s.meshes, scene, half_face_meshes(scene.meshes[0]))
    whole = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=32)
    split = dynamic_model(two, case.modifications, case.torque, positions_per_pitch=32)
    np.testing.assert_allclose(
        float(split.mesh_stiffness_mean), float(whole.mesh_stiffness_mean), rtol=1e-9
    )
    np.testing.assert_allclose(
        np.asarray(split.modes.omega)[1:], np.asarray(whole.modes.omega)[1:], rtol=1e-9
    )
    run = {"integrator": Newmark(32), "window": SteadyState(4, 2)}
    a, b = simulate(whole, 1000.0, **run), simulate(split, 1000.0, **run)
    assert len(b.meshes) == 2
    for half in b.meshes:
        for name in ("dynamic_factor", "dynamic_factor_tooth", "te_rms"):
            np.testing.assert_allclose(
                float(getattr(half, name)), float(getattr(a, name)), rtol=1e-9, err_msg=name
            )
        np.testing.assert_allclose(float(half.static_force), 0.5 * case.normal_load, rtol=1e-9)


def test_four_dof_modes_energy_and_damping(accessory):
    case, scene = accessory
    s4 = TorsionalDynamics(
        scene.mesh,
        scene.inertia_pinion,
        scene.inertia_gear,
        5e-3,
        4e-2,
        2e4,
        6e4,
        has_motor=True,
        has_load=True,
    )
    model = dynamic_model(
        s4, case.modifications, case.torque, Damping("composite"), positions_per_pitch=32
    )
    M = np.asarray(s4.mass())
    K = np.asarray(model.modes.mesh_stiffness + s4.stiffness())
    lam = scipy.linalg.eigh(K, M, eigvals_only=True)
    lam[np.abs(lam) < 1e-9 * lam.max()] = 0.0
    np.testing.assert_allclose(np.asarray(model.modes.omega) ** 2, lam, rtol=1e-9, atol=1e-6)
    e = np.asarray(model.modes.energy)
    assert model.modes.parts == ("mesh", "motor_shaft", "load_shaft")
    elastic = ~np.asarray(model.modes.rigid)
    assert elastic.sum() == 3
    np.testing.assert_allclose(e[:, elastic].sum(axis=0), 1.0, rtol=1e-12)
    # composite damping (2.36): Φᵀ C Φ = diag(2 ξ_i ω_i), ξ_i = 0.07 e_i + 0.01 (1 − e_i)
    Phi = np.asarray(model.modes.shapes)
    C = np.asarray(model.damping)
    xi = 0.07 * e[0] + 0.01 * (1 - e[0])
    modal = Phi.T @ C @ Phi
    scale = np.abs(modal).max()
    np.testing.assert_allclose(
        modal, np.diag(2 * xi * np.asarray(model.modes.omega)), atol=1e-10 * scale
    )
    # Rayleigh (2.34): a M + b K̄
    Cr = damping_matrix(s4, model.modes, Damping("rayleigh", alpha=30.0, beta=2e-6))
    np.testing.assert_allclose(np.asarray(Cr), 30.0 * M + 2e-6 * K, rtol=1e-12)
    # rigid-body mode carries no mesh deflection and no net load
    r = np.asarray(s4.rigid_modes())[:, 0]
    assert abs(np.asarray(s4.te_vector()) @ r) < 1e-12
    assert abs(np.asarray(s4.external_load(jnp.asarray(80.0))) @ r) < 1e-9


# slow: the same run (2 rad/s, Newmark 2000, SteadyState(3, 2)) on 4 slices is
# tests/test_dynamic_pressure.py's default test_low_speed_cell_loads_and_pressures_are_the_quasi_
# static_ones, which asserts these limits of it too
@pytest.mark.slow
def test_low_speed_limit_matches_quasi_static(accessory):
    case, scene = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=32)
    # 2 rad/s: mesh frequency 14 Hz against a 6 kHz mode; Δt ≈ T_n / 10
    r = simulate(model, 2.0, integrator=Newmark(2000), window=SteadyState(3, 2))
    assert int(r.result) == 0
    assert abs(float(r.dynamic_factor) - 1.0) < 5e-3
    assert abs(float(r.dynamic_factor_tooth) - 1.0) < 5e-3
    qs = jg.quasi_static(scene.mesh, case.modifications, case.torque, theta=r.theta)
    te_qs = np.asarray(qs.transmission_error)
    err = np.max(np.abs(np.asarray(r.transmission_error) - te_qs))
    assert err < 5e-3 * np.mean(te_qs)
    assert float(r.te_rms) == pytest.approx(float(qs.te_rms), rel=0.05)


def test_recorded_states_and_the_band_dynamic_factor_bounds(accessory):
    """A lumped model records its coordinates with ``states=True`` (they end at the final
    state), and :func:`band_dynamic_factor`, the p-mean over speeds of the p-mean over the K kept
    steps, lies between the p-mean's bounds: max DF · (K S)^(-1/p) <= band <= max DF (the
    dynamic factors of the same sweep)."""
    case, scene = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    kw = dict(contact=jg.SmoothContact(2e-7), integrator=Newmark(16), window=SteadyState(6, 2))
    r = simulate(model, 900.0, outputs=Outputs(states=True), **kw)
    assert r.states.shape == (32, scene.mass().shape[0])
    np.testing.assert_array_equal(np.asarray(r.states[-1]), np.asarray(r.final_state[0]))
    assert r.rim_radial.shape == (32, 0)
    speeds = [700.0, 900.0]
    df = np.asarray(speed_sweep(model, speeds, **kw).results.dynamic_factor)
    p, K, S = 32.0, 32, 2
    band = float(band_dynamic_factor(model, speeds, p=p, **kw))
    assert df.max() * (K * S) ** (-1.0 / p) <= band <= df.max() * (1 + 1e-12)
    with pytest.raises(ValueError, match="integrator"):  # a band needs a fixed step
        band_dynamic_factor(model, speeds, integrator=Newmark())


def _linear_problem(case, scene):
    """The time-averaged system as a linear, time-invariant contact problem: one row of the
    mesh table (all its cells in contact) held for every step, δ0 = 0, for the checks of the
    integration rule by :func:`jaxgear.dynamics.newmark`."""
    model = dynamic_model(
        scene, jg.Modifications(), case.torque, Damping("none"), positions_per_pitch=16
    )
    t = mesh_table(model.scene, model.mods, 16)
    row = jg.CellRow(None, t.V[4], t.k[4], t.length[4], jnp.zeros_like(t.delta0[4]), t.mask[4])
    return model, row


def _linear_energy(model, row, X, Xd):
    M = model.scene.mass()
    kl = jnp.where(row.mask, row.k * row.length, 0.0)
    K = model.scene.stiffness() + jnp.einsum("c,ci,cj->ij", kl, row.V, row.V)
    F = model.scene.external_load(model.torque)
    return 0.5 * Xd @ M @ Xd + 0.5 * X @ K @ X - F @ X, K


def _integrate(model, row, dt, X0, A0, n_steps):
    """``n_steps`` Newmark steps of Δt from (X0, 0, A0) with the row's cells: the states
    (n_steps, n) and velocities (n_steps, n)."""
    scene = model.scene
    state = (X0, jnp.zeros_like(X0), A0, jnp.array(0), jnp.array(0))
    system = LinearSystem(
        scene.stiffness(),
        scene.mass(),
        jnp.zeros_like(scene.mass()),
        scene.external_load(model.torque),
    )
    _, (X, Xd) = newmark(
        system,
        dt,
        state,
        jnp.zeros((1, n_steps), jnp.int32),
        StepCells(lambda _: row, jg.ExactContact()),
        lambda X, Xd, P, _: (X, Xd),
    )
    return X, Xd


def test_newmark_conserves_energy_undamped_linear(accessory):
    case, scene = accessory
    model, row = _linear_problem(case, scene)
    _, K = _linear_energy(model, row, jnp.zeros(2), jnp.zeros(2))
    M = model.scene.mass()
    F = model.scene.external_load(model.torque)
    Xs = jnp.linalg.lstsq(K, F)[0]
    X0 = Xs * 1.3  # 30 % off equilibrium: large free vibration, contact kept (δ0 = 0)
    A0 = jnp.linalg.solve(M, F - K @ X0)
    w = float(model.modes.omega[1])
    dt = 2 * math.pi / w / 7.3  # coarse on purpose

    X, Xd = _integrate(model, row, jnp.asarray(dt), X0, A0, 3000)
    e = np.asarray(jax.vmap(lambda x, v: _linear_energy(model, row, x, v)[0])(X, Xd))
    e0 = float(_linear_energy(model, row, X0, jnp.zeros(2))[0])
    amp = 0.5 * float((X0 - Xs) @ K @ (X0 - Xs))  # vibration energy scale
    # docs/dynamics.md: "keeps the energy to 1e-11 of the vibration energy" (measured 1.6e-13)
    assert np.max(np.abs(e - e0)) < 1e-11 * amp


def test_newmark_second_order(accessory):
    case, scene = accessory
    model, row = _linear_problem(case, scene)
    _, K = _linear_energy(model, row, jnp.zeros(2), jnp.zeros(2))
    M = model.scene.mass()
    F = model.scene.external_load(model.torque)
    Xs = jnp.linalg.lstsq(K, F)[0]
    X0 = Xs * 1.1
    u = np.asarray(model.scene.te_vector())
    w = math.sqrt(scipy.linalg.eigh(np.asarray(K), np.asarray(M), eigvals_only=True)[-1])
    T = 3.25 * 2 * math.pi / w  # a quarter period off: the phase error shows at first order
    # closed form: the approach u·X oscillates about its static value at ω, from rest
    x_exact = float(u @ Xs) + float(u @ (X0 - Xs)) * math.cos(w * T)

    A0 = jnp.linalg.solve(M, F - K @ X0)
    run = jax.jit(lambda dt: _integrate(model, row, dt, X0, A0, 240)[0])

    def approach(n):  # state after n steps of T/n (one compilation: Δt is traced)
        return float(u @ run(jnp.asarray(T / n))[n - 1])

    errs = [abs(approach(n) - x_exact) for n in (60, 120, 240)]
    orders = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    np.testing.assert_allclose(orders, 2.0, atol=0.1)


def test_main_critical_speed_linear_case(linear_case):
    case, scene, mods = linear_case
    model = dynamic_model(
        scene, mods, case.torque, Damping("modal", ratio=0.1), positions_per_pitch=32
    )
    cs = float(model.critical_speeds()[1])
    speeds = cs * np.linspace(0.85, 1.15, 16)
    s = speed_sweep(model, speeds, integrator=Newmark(32), window=SteadyState(40))
    assert np.all(np.asarray(s.results.result) == 0)
    assert np.all(np.asarray(s.results.contact_loss) == 0)  # linear: no contact loss
    df = np.asarray(s.dynamic_factor)
    peak = speeds[np.argmax(df)]
    assert abs(peak / cs - 1.0) < 0.05
    assert df.max() > 1.05 and df.max() > df[0] and df.max() > df[-1]


def test_jump_and_hysteresis_with_contact_loss(accessory):
    case, _ = accessory
    # theoretical path: the softening jump of contact loss alone; the corner contact beyond the
    # path stiffens the overloaded mesh and moves the branches (docs/extended-contact.md)
    case = case.replace(contact_geometry=jg.TheoreticalPath())
    scene = TorsionalDynamics(case.mesh_model(), *_inertias(case))
    model = dynamic_model(
        scene, case.modifications, case.torque, Damping("modal", ratio=0.03), positions_per_pitch=32
    )
    cs = float(model.critical_speeds()[1])
    speeds = cs * np.linspace(0.86, 1.0, 8)
    s = speed_sweep(model, speeds, direction=Both(), integrator=Newmark(32), window=SteadyState(40))
    up, down = np.asarray(s.results.dynamic_factor), np.asarray(s.down.dynamic_factor)
    assert np.all(np.asarray(s.results.result) == 0) and np.all(np.asarray(s.down.result) == 0)
    gap = down - up
    assert gap.max() > 0.3  # the down sweep stays on the upper branch: hysteresis
    i = int(np.argmax(gap))
    assert float(s.down.contact_loss[i]) > 0  # ... with contact loss (nonlinear, softening)
    assert float(s.results.contact_loss[i]) == 0
    # away from the jump both directions agree
    assert abs(gap[0]) < 1e-3 and abs(gap[-1]) < 1e-3


def test_gradient_wrt_tip_relief_matches_finite_differences(accessory):
    case, scene = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    kw = dict(contact=jg.SmoothContact(2e-7), integrator=Newmark(16), window=SteadyState(6, 2))

    def df(depth_um):
        member = eqx.tree_at(lambda m: m.tip_relief_depth, model.mods.pinion, depth_um * 1e-6)
        m = eqx.tree_at(lambda m: m.mods.pinion, model, member)
        return simulate(m, 700.0, throw=False, **kw).dynamic_factor

    def value_and_tangent(e):  # one compilation serves the tangent and the finite differences
        return jax.jvp(df, (jnp.asarray(e),), (jnp.asarray(1.0),))

    e0, h = 15.0, 0.05
    _, grad = value_and_tangent(e0)
    fd = (float(value_and_tangent(e0 + h)[0]) - float(value_and_tangent(e0 - h)[0])) / (2 * h)
    assert abs(float(grad)) > 1e-4
    assert float(grad) == pytest.approx(fd, rel=2e-3, abs=1e-6)


def test_held_table_serves_only_its_own_inputs(accessory):
    """A built model holds its static rows (DynamicModel.held) for its runs at the build's law
    and N_s; a model whose mods were replaced must not run on them: its static TE is that of
    a model built afresh with the new mods (an independent build) and differs from the
    original's (the stale rows would give the original's)."""
    case, scene = accessory
    kw = dict(contact=jg.ExactContact(), integrator=Newmark(16), window=SteadyState(6, 2))
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    assert model.held is not None
    member = eqx.tree_at(lambda m: m.tip_relief_depth, model.mods.pinion, 30e-6)
    swapped = eqx.tree_at(lambda m: m.mods.pinion, model, member)
    fresh = dynamic_model(scene, swapped.mods, case.torque, positions_per_pitch=16)
    te = {
        name: np.asarray(simulate(m, 700.0, throw=False, **kw).static_te)
        for name, m in (("own", model), ("swapped", swapped), ("fresh", fresh))
    }
    np.testing.assert_allclose(te["swapped"], te["fresh"], rtol=1e-12, atol=1e-18)
    assert np.max(np.abs(te["swapped"] - te["own"])) > 1e-8


def test_divergence_is_reported_not_silent(accessory):
    case, scene = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    # explicit Euler, constant steps far beyond its stability limit (ω Δt ≈ 7)
    kw = dict(
        integrator=DiffraxIntegrator("euler", 16, adaptive=False),
        contact=jg.SmoothContact(),
        window=SteadyState(3, 2),
    )
    r = simulate(model, 30.0, throw=False, **kw)
    assert int(r.result) in (2, 3)
    with pytest.raises(eqx.EquinoxRuntimeError, match="diverged|blow-up"):
        simulate(model, 30.0, **kw)
    # loud under a caller's transforms (it was silent under a caller's jit): plain jax.jit
    # around jax.vmap, one compiled program for both transforms (simulate's own filter_jit is
    # the first check above)
    with pytest.raises(Exception, match="diverged|blow-up"):  # plain jax.jit: JaxRuntimeError
        f = jax.jit(jax.vmap(lambda s: simulate(model, s, **kw).dynamic_factor))
        jax.block_until_ready(f(jnp.array([30.0, 31.0])))


def test_dynamic_model_checks_are_jittable(accessory):
    """dynamic_model runs under jax.jit (no host checks) and reports a bad torque loudly."""
    case, scene = accessory
    build = eqx.filter_jit(
        lambda t: dynamic_model(scene, case.modifications, t, positions_per_pitch=16)
    )
    m = build(jnp.asarray(case.torque))  # traced: the program of the bad torque below
    assert float(m.mesh_stiffness_mean) > 0
    with pytest.raises(eqx.EquinoxRuntimeError, match="torque must be > 0"):  # traced
        jax.block_until_ready(build(jnp.asarray(-1.0)).mesh_stiffness_mean)
    with pytest.raises(ValueError, match="dynamic_model: torque = -1 N·m is out of range"):
        build(-1.0)  # a Python float is static under filter_jit: refused before tracing


# slow (newmark): the default suite covers forward mode through the Newmark dynamics against a
# central difference in test_gradient_wrt_tip_relief_matches_finite_differences (jax.jvp)
@pytest.mark.parametrize("solver", [pytest.param("newmark", marks=pytest.mark.slow), "tsit5"])
def test_forward_mode_through_the_dynamics_matches_finite_differences(solver):
    """jax.jvp of the dynamic TE RMS w.r.t. the relief depth, Newmark and diffrax paths (the
    diffrax path needs ``adjoint="forward"``: the default checkpointed adjoint is a custom_vjp),
    against a central difference."""
    case = jio.load_case("accessory-spur").replace(slices=2)
    p = case.pair
    scene = TorsionalDynamics(
        case.mesh_model(),
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    ).reduced()
    # constant steps: the finite difference sees the same discrete scheme
    integrator = (
        Newmark(16)
        if solver == "newmark"
        else DiffraxIntegrator(solver, 16, rtol=1e-9, atol=1e-9, adaptive=False, adjoint="forward")
    )
    kw = dict(contact=jg.SmoothContact(), integrator=integrator, window=SteadyState(4, 2))

    def te_rms_um(depth_um):
        mm = jg.MemberModification(tip_relief_depth=depth_um * 1e-6, tip_relief_extent=0.25)
        model = dynamic_model(
            scene, jg.Modifications.symmetric(mm), case.torque, positions_per_pitch=16
        )
        return simulate(model, 700.0, **kw).te_rms * 1e6

    # one compiled program serves the tangent and the finite differences (its primal output;
    # the depth traced: a Python float would be static under filter_jit, a program per value)
    value_and_tangent = eqx.filter_jit(lambda e: jax.jvp(te_rms_um, (e,), (jnp.ones_like(e),)))
    _, tangent = value_and_tangent(jnp.asarray(15.0))
    h = 1e-3
    fd = (
        float(value_and_tangent(jnp.asarray(15.0 + h))[0])
        - float(value_and_tangent(jnp.asarray(15.0 - h))[0])
    ) / (2 * h)
    assert abs(float(tangent)) > 1e-3
    assert float(tangent) == pytest.approx(fd, rel=1e-4)


def test_a_window_that_keeps_every_period_runs_without_a_transient(accessory):
    """``SteadyState(p, keep_periods=p)`` (the docstring allows keep_periods = periods) records
    from the first step: no transient run before it (it failed with an IndexError on the empty
    transient); its last two periods are the records of ``SteadyState(p, 2)``, the same steps."""
    case, scene = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=32)
    # the run of test_torsional_pair_cut_into_two_half_face_meshes_gives_the_pair_response
    # (SteadyState(4, 2), one compiled program for both tests; the speed is traced)
    run = {"integrator": Newmark(32)}
    whole = simulate(model, 1000.0, window=SteadyState(4, 4), **run)
    tail = simulate(model, 1000.0, window=SteadyState(4, 2), **run)
    assert int(whole.result) == 0 and int(tail.result) == 0
    te_whole, te_tail = np.asarray(whole.transmission_error), np.asarray(tail.transmission_error)
    assert te_whole.shape[-1] == 4 * 32 and te_tail.shape[-1] == 2 * 32
    np.testing.assert_allclose(
        te_whole[..., 64:], te_tail, rtol=0, atol=1e-12 * np.abs(te_tail).max()
    )
