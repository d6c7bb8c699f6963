"""A planetary stage as a dynamics engine (jaxgear.planetary.PlanetaryModel, an
AbstractDynamicModel): jaxgear.dynamics.simulate at a very low input speed gives each mesh's
force of the quasi-static solve (jaxgear.planetary.planetary_quasi_static, a separate contact solve
of K_b q + V^T P = f) at the same mesh travels; the automatic step of the engine is the stage's
time plan's (jaxgear.planetary.plan_sweep); simulate and speed_sweep at speed give what
planetary_dynamics gives with the same settings (consistency); the refusals."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
from _planetary_stage import K0, SEQ, geometry, stage

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0


@pytest.fixture(scope="module")
def seq():
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    run = jp.PlanetaryRun(TORQUE, damping_ratio=0.05)
    return st, meshes, run, jp.PlanetaryModel(jp.TorsionalPlanetary(), st, meshes, run)


def _direct(st, meshes, run, speed):
    """planetary_dynamics at the input speed ``speed`` (rad/s, a float64: the carrier's, the
    ring held) with every argument spelled out: the mesh speed v = r_br |Ω| by hand, the exact
    law, the rigid ring (the arguments' form of the model's own calls, so that simulate at one
    speed reruns this compiled program instead of compiling its own)."""
    carrier = jnp.asarray(speed, jnp.float64)
    mesh_speed = st.ring.base_radius * jnp.abs(carrier)
    return jp.planetary_dynamics(jp.TorsionalPlanetary(), st, meshes, run, carrier, mesh_speed,
                                 jg.ExactContact(), jp.RigidRing())


def test_simulate_at_a_very_low_speed_is_the_quasi_static_solve(seq):
    """At 1e-3 rad/s (the carrier the input, the ring held: a mesh period lasts 119 s) the
    inertia is nil: every mesh's median force over the kept periods equals the median of the
    quasi-static forces at the same travels within 1e-3, and each recorded force the
    quasi-static one within 1e-3 of the nominal mesh force (measured 1.6e-4 and 2.1e-4 at 384
    steps per mesh period, 6e-7 and 9e-7 at 48 over one kept period; at 30 rad/s, near the
    stage's modes, 2.4e-2 and 0.35)."""
    st, meshes, run, model = seq
    # N_s = 384 over 4 periods, 2 kept: the run of _direct in the tests below (simulate at one
    # speed compiles nothing of its own: one planetary_dynamics program for the file's direct
    # runs at N_s = 384); the quasi-static solve at every 16th recorded travel (48 of them: the
    # program of tests/test_planetary_dynamics.py's zero-speed and transducer tests)
    r = jd.simulate(model, 1e-3, integrator=jd.Newmark(384), window=jd.SteadyState(4, 2))
    assert isinstance(r, jp.PlanetaryDynamics) and int(r.result) == 0
    static = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, meshes,
                                       np.asarray(TORQUE), r.travel[::16], np.zeros(3))
    got = np.concatenate([r.sun_mesh_forces, r.ring_mesh_forces], axis=1)[::16]
    want = np.concatenate([static.sun_mesh_forces, static.ring_mesh_forces], axis=1)
    np.testing.assert_allclose(np.median(got, axis=0), np.median(want, axis=0), rtol=1e-3)
    fs = float(model.static_force)
    assert fs == pytest.approx(TORQUE / (3 * float(st.sun.base_radius)), rel=1e-14)
    assert np.max(np.abs(got - want)) < 1e-3 * fs
    # consistency: simulate's records are planetary_dynamics' with the same run, the carrier
    # at the input speed and the mesh speed r_br Ω spelled out (_direct: the program simulate
    # ran, so this check compiles nothing)
    direct = jp.PlanetaryRun(TORQUE, steps_per_period=384, periods=4, keep_periods=2,
                             damping_ratio=0.05, ring_cell_space=True)
    one = _direct(st, meshes, direct, 1e-3)
    for f in ("sun_mesh_forces", "ring_mesh_forces", "dynamic_factors"):
        np.testing.assert_allclose(np.asarray(getattr(r, f)), np.asarray(getattr(one, f)),
                                   rtol=1e-9)


def test_the_automatic_step_is_the_time_plans(seq):
    """jaxgear.dynamics.auto_steps_per_period of the model (the pairs' rule on the model's
    mesh-averaged modes, N_s a multiple of the planet count) is the step of the stage's time
    plan (plan_sweep at the same mesh frequency: z_r / 2π Hz per rad/s of the carrier)."""
    st, meshes, run, model = seq
    speeds = np.array([20.0, 60.0, 200.0])
    got = jd.auto_steps_per_period(model, speeds)
    f_mesh = 1.0 / float(model.mesh_period_angle())  # Hz per rad/s
    assert f_mesh == pytest.approx(53 / (2 * np.pi), rel=1e-12)  # z_r = 53
    plan, _ = jp.plan_sweep(jp.TorsionalPlanetary(), st, meshes, run, speeds, f_mesh)
    np.testing.assert_array_equal(got, plan.steps)
    assert np.all(got % 3 == 0)


@pytest.mark.slow  # a fixed-step vmapped sweep program of its own (~9 CPU s); the claims in
# the default suite: simulate = planetary_dynamics in
# test_simulate_at_a_very_low_speed_is_the_quasi_static_solve, speed_sweep = planetary_dynamics
# at each speed in test_a_sweep_of_several_automatic_steps_runs_each_at_its_own
def test_simulate_and_speed_sweep_are_planetary_dynamics(seq):
    """Consistency: at speed, simulate and speed_sweep with Newmark(N_s) and a window give the
    records of planetary_dynamics with the same run (the carrier at the input speed, the mesh
    speed r_br Ω)."""
    st, meshes, run, model = seq
    speeds = np.array([80.0, 160.0])
    window = jd.SteadyState(4, 2)
    # N_s = 384 over 4 periods: the direct run of test_a_sweep_of_several_automatic_steps_runs_
    # each_at_its_own at N_s = 384 (one compiled planetary_dynamics for both), and simulate's
    # one-speed run below (_direct's arguments: simulate compiles nothing of its own)
    sweep = jd.speed_sweep(model, speeds, integrator=jd.Newmark(384), window=window)
    direct = jp.PlanetaryRun(TORQUE, steps_per_period=384, periods=4, keep_periods=2,
                             damping_ratio=0.05, ring_cell_space=True)
    for k, w in enumerate(speeds):
        want = _direct(st, meshes, direct, w)
        np.testing.assert_allclose(sweep.results.sun_mesh_forces[k], want.sun_mesh_forces,
                                   rtol=1e-9)
        np.testing.assert_allclose(sweep.results.ring_mesh_forces[k], want.ring_mesh_forces,
                                   rtol=1e-9)
    one = jd.simulate(model, speeds[1], integrator=jd.Newmark(384), window=window)
    np.testing.assert_allclose(one.dynamic_factors[0], sweep.results.dynamic_factors[0][1],
                               rtol=1e-9)


def test_refusals(seq):
    st, meshes, run, model = seq
    with pytest.raises(ValueError, match="integrator"):
        jd.simulate(model, 10.0, integrator=jd.DiffraxIntegrator("tsit5", 32))
    with pytest.raises(ValueError, match="state0"):
        jd.simulate(model, 10.0, integrator=jd.Newmark(48), state0=(0.0, 0.0))
    with pytest.raises(ValueError, match="outputs"):
        jd.simulate(model, 10.0, integrator=jd.Newmark(48), outputs=jd.Outputs(states=True))
    with pytest.raises(ValueError, match="direction"):
        jd.speed_sweep(model, [10.0, 20.0], integrator=jd.Newmark(48), direction=jd.Up())
    with pytest.raises(ValueError, match="carrier_per_input"):
        jp.PlanetaryModel(jp.TorsionalPlanetary(), st, meshes, run, carrier_per_input=0.0)
    with pytest.raises(ValueError, match="meshes"):
        jp.PlanetaryModel(jp.TorsionalPlanetary(), st, None, run)


def test_build_dynamic_model_of_a_planetary_case_is_the_sweeps_stage():
    """jaxgear.io.build_dynamic_model on the embedded lin-parker-1999 stage (sun input, ring
    fixed) gives a PlanetaryModel: its mesh frequency per input speed is z_s |ω_s − ω_c| / 2π
    from Willis by tooth counts (28, 92: ω_c = 28/120 ω_s), its nominal force |T_s| / (N r_bs),
    and its automatic steps the planetary sweep's time plan's (jaxgear sweep's)."""
    from jaxgear.cli.planetary_sweep import sweep_time_plan

    case = jio.load_case("lin-parker-1999")
    model, _ = jio.build_dynamic_model(case)
    assert isinstance(model, jp.PlanetaryModel)
    assert isinstance(model.kind, jp.PlanarPlanetary)
    f_mesh = 28 * (1.0 - 28 / 120) / (2 * np.pi)  # Hz per rad/s of the sun
    assert 1.0 / float(model.mesh_period_angle()) == pytest.approx(f_mesh, rel=1e-12)
    assert float(model.carrier_per_input) == pytest.approx(28 / 120, rel=1e-12)
    n = model.stage.n_planets
    want = abs(float(case.torque)) / (n * float(model.stage.sun.base_radius))
    assert float(model.static_force) == pytest.approx(want, rel=1e-12)
    speeds = np.array([0.5, 1.0]) * float(case.speed)
    plan = sweep_time_plan(case.form, case, speeds)
    np.testing.assert_array_equal(jd.auto_steps_per_period(model, speeds), plan.steps)


def test_a_sweep_of_several_automatic_steps_runs_each_at_its_own(seq):
    """speed_sweep with automatic steps at two speeds of other N_s (384, 192): one compiled
    program (PlanetaryRun.mesh_steps), each speed's records those of planetary_dynamics at its
    own N_s over the same steps, within 1e-3 of the nominal force (measured 1.8e-4 at N_s =
    384: the program's modal damping averages the meshes over the smallest N_s's positions;
    0 at 192)."""
    st, meshes, run, model = seq
    speeds = np.array([150.0, 320.0])
    ns = jd.auto_steps_per_period(model, speeds)
    np.testing.assert_array_equal(ns, [384, 192])
    sweep = jd.speed_sweep(model, speeds, window=jd.SteadyState(4, 2))
    assert np.all(np.asarray(sweep.results.result) == 0)
    fs = float(model.static_force)
    for k, n in enumerate(ns):
        n, top = int(n), int(ns.max())
        direct = jp.PlanetaryRun(TORQUE, steps_per_period=n, periods=4 * top // n,
                                 keep_periods=2 * top // n, damping_ratio=0.05,
                                 ring_cell_space=True)
        want = _direct(st, meshes, direct, speeds[k])
        got = np.asarray(sweep.results.sun_mesh_forces[k])
        assert got.shape == want.sun_mesh_forces.shape
        assert np.max(np.abs(got - np.asarray(want.sun_mesh_forces))) < 1e-3 * fs
