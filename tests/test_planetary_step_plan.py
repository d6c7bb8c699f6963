"""The planetary sweep's time discretisation from the stage's modes
(:func:`jaxgear.planetary.time_plan`): N_s = the smallest N × 2^j >= max(64,
40 f_max / f_mesh) per speed, periods = keep + ceil(t_s f_mesh) with t_s = ln(1e3) / (ζ ω_min);
the settled state (the last kept mesh period against the one before); the ring spectrum's turn
from one settled mesh period where the stage repeats every mesh period in the carrier frame;
the default's dynamic factor against finer steps (slow).

The references are written here: the modes of the lumped lin-parker-1999 from the public
:func:`jaxgear.planetary.planetary_modes` on its dynamic stage, the mesh's share of each mode's
strain energy from the stage's stiffness with and without its mesh springs, the formulas of the rule
from the constants (64, 40, 5 %, 20, ζ = 0.05, 1e-3); the spectrum's turn integrated over z_r
mesh periods; the dynamic factor extrapolated from two finer steps (Richardson, first order:
the teeth entering mesh switch the stiffness, Newmark is first order at those instants)."""

from __future__ import annotations

import math
import tomllib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import planetary_sweep as ps


def reference_plan(case, speeds):
    """(N_s (s,), periods (s,), f_max, f_min, every frequency) of lin-parker-1999 (constant mesh
    springs: the mesh-averaged stiffness is the springs') written here: the planar modes of the
    stage the sweep integrates (ring and carrier held, the sun free), the mesh's strain-energy
    share phi^T (K - K_b) phi / omega^2 with K_b the stage without its mesh springs; f_max and
    f_min the highest and lowest of the modes with a share >= 5 %."""
    spec = case.form.spec
    stage = spec.sharing_stage(spec.stage(case))
    model = jp.PlanarPlanetary()
    modes = jp.planetary_modes(model, stage)
    f = np.asarray(modes.frequencies)
    phi = np.asarray(modes.shapes)
    bare = eqx.tree_at(lambda s: (s.sun_mesh_stiffness, s.ring_mesh_stiffness), stage,
                       (0.0 * stage.sun_mesh_stiffness, 0.0 * stage.ring_mesh_stiffness))
    k_mesh = np.asarray(model.stiffness_matrix(stage)) - np.asarray(model.stiffness_matrix(bare))
    elastic = f > 1e-6 * f.max()
    share = np.einsum("ij,ik,kj->j", phi, k_mesh, phi) / np.where(elastic, (2 * np.pi * f)**2, 1)
    excited = elastic & (share >= 0.05)
    f_max = float(f[excited].max())
    f_min = float(f[excited].min())
    z_s, z_r = 28, 92
    f_mesh = np.asarray(speeds) * z_s * (1.0 - z_s / (z_s + z_r)) / (2 * math.pi)  # Willis
    steps = []
    for fm in f_mesh:
        n = 3
        while n < max(64, 40 * f_max / fm):
            n *= 2
        steps.append(n)
    t_s = math.log(1e3) / (0.05 * 2 * math.pi * f_min)
    periods = 2 + np.ceil(t_s * f_mesh).astype(int)
    return np.array(steps), periods, f_max, f_min, f


def test_the_default_step_and_span_follow_the_stage_modes():
    """lin-parker-1999 at three sun speeds: the sweep's N_s and periods per speed are the
    formulas written here on the modes of the public planetary_modes (f_max to 1e-9; the
    ring's and carrier's stiff holds, the two highest modes, store < 5 % in the meshes and are
    not resolved); two kept periods (no eccentricity, a rigid ring). An explicit step and span
    are used at every speed."""
    case = jio.load_case("lin-parker-1999")
    speeds = np.array([30.0, 100.0, 300.0])
    steps, periods, f_max, f_min, f = reference_plan(case, speeds)
    plan = ps.sweep_time_plan(case.form, case, speeds)
    assert plan.f_max_Hz == pytest.approx(f_max, rel=1e-9)
    assert plan.f_min_Hz == pytest.approx(f_min, rel=1e-9)
    assert f_max < f[-2]  # the holds' modes are above the resolved one
    np.testing.assert_array_equal(plan.steps, steps)
    np.testing.assert_array_equal(plan.periods, periods)
    assert plan.keep == 2 and plan.automatic == (True, True)
    assert np.all(plan.steps % 3 == 0) and np.all(plan.steps * speeds >= 0)
    given = ps.sweep_time_plan(case.form, case, speeds, steps_per_period=48, periods=5)
    np.testing.assert_array_equal(given.steps, [48, 48, 48])
    np.testing.assert_array_equal(given.periods, [5, 5, 5])
    assert given.automatic == (False, False)


def test_the_engines_automatic_span_is_the_rule():
    """The case's dynamic model (jaxgear.io.build_dynamic_model, what jaxgear sweep runs)
    resolves the engine's automatic window, SteadyState(periods=None), its default, at the
    steps written here to the periods written here (keep + ceil(t_s f_mesh)), and its sweep
    window keeps two periods (a rigid ring, no eccentricity), at most the periods given."""
    case = jio.load_case("lin-parker-1999")
    model, _ = jio.build_dynamic_model(case)
    speeds = np.array([30.0, 100.0, 300.0])
    steps, periods, *_ = reference_plan(case, speeds)
    window = model.sweep_window()
    assert window == jd.SteadyState(None, 2) and model.sweep_window(3, 5).keep_periods == 3
    assert model.default_settings()[2] == window  # a run with no window: jaxgear sweep's
    span = model.resolve_window(window, speeds, steps)
    assert span.steps == tuple(int(n) for n in steps)
    assert span.periods == tuple(int(p) for p in periods) and span.keep_periods == 2


def test_eccentricities_keep_four_periods_and_integrate_the_turn():
    """A sun eccentricity turns relative to the carrier: the stage is no longer periodic in
    the mesh period (carrier_periodic False, nor with a flexible ring), four periods are kept,
    and the ring spectrum's turn is integrated at a step that keeps it within 2^16 steps."""
    case = jio.load_case("lin-parker-1999")
    spec = case.form.spec
    stage = spec.sharing_stage(spec.stage(case))
    assert jp.carrier_periodic(stage, False) and not jp.carrier_periodic(stage, True)
    ecc = eqx.tree_at(lambda s: s.eccentricities,
                      stage, jp.Eccentricities(sun=20e-6, sun_phase=0.3))
    assert not jp.carrier_periodic(ecc, False)
    modes = jp.planetary_mesh_modes(jp.PlanarPlanetary(), stage,
                                    jp.ConstantMeshes(2 * math.pi * 38.7e-3 / 28),
                                    jp.PlanetaryRun(10.0))
    plan = jp.time_plan(modes, [100.0], spec.mesh_frequency(1.0), 3, 0.05, False)
    assert plan.keep == 4
    # such a stage's ring spectrum integrates its turn (z_r mesh periods) within 2^16 steps:
    # the largest 3 x 2^j <= 65536 / 53 = 1236.5 is 768; a step within it is kept
    assert ps.turn_steps(6144, 53, 3) == 768 and ps.turn_steps(96, 53, 3) == 96


# steps per mesh period of the spectrum's check: few (the identity holds at any step), but not
# so few that the damping of the modes the step does not resolve fails (average acceleration
# is not L-stable: at 24 steps the transient still moved the forces by 1e-8 after 50 periods)
SMALL_S = 96


@pytest.fixture(scope="module")
def small_case(tmp_path_factory):
    import test_planetary_sweep as small

    path = tmp_path_factory.mktemp("case") / "small-stage.toml"
    path.write_text(small.CASE)
    return jio.load_case(str(path))


def test_the_spectrum_turn_is_one_settled_period_repeated(small_case, tmp_path, no_figures):
    """The small contact-cell stage (19/17/-53, 3 planets, a 10 um pin error: periodic in the
    carrier frame) at 30 rad/s, 96 steps per mesh period: the ring-mesh forces integrated over
    a whole carrier turn (z_r = 53 mesh periods after a transient of 1e-9 by the damping,
    t_s = ln(1e9) / (zeta omega_min)) equal the last mesh period repeated to 1e-9 of the
    nominal force, and ring_spectrum's amplitudes from the repeated period equal those of the
    integrated turn to 1e-9 of the largest."""
    case = small_case
    plan = ps.sweep_time_plan(case.form, case, [30.0], steps_per_period=SMALL_S)
    settle = math.ceil(math.log(1e9) / (0.05 * 2 * math.pi * plan.f_min_Hz)
                       * 30.0 * case.form.spec.mesh_frequency(1.0))
    spec = case.form.spec
    stage = spec.sharing_stage(spec.stage(case))
    meshes = spec.dynamic_meshes(case, 1)
    model, ring = jp.PlanarPlanetary(), jp.RigidRing()
    assert jp.carrier_periodic(stage, False)
    z_r = 53
    run = jp.PlanetaryRun(abs(spec.torques(case.torque)["sun"]), steps_per_period=SMALL_S,
                          periods=settle + 1, keep_periods=1,
                          tangential_pin_errors=np.array([10e-6, 0.0, 0.0]),
                          radial_pin_errors=np.zeros(3))
    # the turn as ring_spectrum integrates it: the stage's engine (jaxgear.dynamics.simulate)
    # at the same step, settling and kept periods, so that ring_spectrum's integration below
    # reuses this compiled run
    engine = jp.PlanetaryModel(model, stage, meshes, run, spec.speeds(1.0)["carrier"],
                               spec.mesh_speed(1.0), ring)
    d = jd.simulate(engine, 30.0, integrator=jd.Newmark(SMALL_S),
                    window=jd.SteadyState(settle + z_r, z_r))
    f = np.asarray(d.ring_mesh_forces)
    nominal = float(d.static_force)
    last = f[-SMALL_S:]
    assert np.max(np.abs(f - np.tile(last, (z_r, 1)))) < 1e-9 * nominal
    settled = (np.asarray(d.time[-SMALL_S:]), last)
    a = ps.ring_spectrum(case, stage, meshes, run, 30.0, str(tmp_path / "a.png"),
                         ring, model, settled)
    b = ps.ring_spectrum(case, stage, meshes, run, 30.0, str(tmp_path / "b.png"),
                         ring, model, None)
    assert a["turn"] != b["turn"]
    top = max(b["sideband_amplitudes_N"] + [b["mean_N"]])
    for key in ("mesh_order_amplitude_N", "mean_N"):
        assert abs(a[key] - b[key]) < 1e-9 * top
    np.testing.assert_allclose(a["sideband_amplitudes_N"], b["sideband_amplitudes_N"],
                               rtol=0, atol=1e-9 * top)


@pytest.mark.slow  # three compiled runs of the contact-cell stage, ~30 s of CPU; fast twin:
# the rule against its formula above (what the default step is), this one what it achieves
def test_the_default_step_converges_at_a_low_speed(small_case):
    """The small contact-cell stage at 10 rad/s of the carrier, a third of its operating speed
    (f_max / f_mesh = 109: the default gives 6144 steps per mesh period, 67 per period of
    f_max): its largest dynamic factor is within 2 % of the Richardson extrapolation of the
    runs at 2 and 4 times its step (first order; converging), settled (the last kept period
    repeats the one before to 1e-3 of the nominal force) and its four-period dynamic factor is
    the two-period one. Measured (float64, CPU): 2.3029, 2.3051, 2.3059 at 6144, 12288, 24576
    steps, extrapolated 2.3068 (the default 0.17 % low); periodicity 4.5e-8; the former
    default of 66 steps over 40 periods gave 1.392 (40 % low), 264 steps 1.673."""
    case = small_case
    speed = np.array([10.0])
    default, _ = ps.sweep_summary(case.form, case, speed)
    n = default["steps_per_period"][0]
    periods = default["periods"][0]
    assert n == 6144 and default["steps_resolution"]["resolved"]
    assert default["settled"] and default["periodicity"][0] < 1e-3
    df = {n: default["max_dynamic_factor"]}
    for k in (2, 4):
        s, _ = ps.sweep_summary(case.form, case, speed, steps_per_period=k * n,
                                periods=periods, keep_periods=2)
        df[k * n] = s["max_dynamic_factor"]
    ref = 2 * df[4 * n] - df[2 * n]
    assert abs(df[n] - ref) < 0.02 * ref
    assert abs(df[2 * n] - ref) < abs(df[n] - ref) + 1e-3 * ref  # converging
    four, _ = ps.sweep_summary(case.form, case, speed, keep_periods=4)
    assert four["max_dynamic_factor"] == pytest.approx(df[n], rel=1e-3)
    jax.clear_caches()


def _lumped_sweep_parts(speeds):
    """The lumped lin-parker-1999 (constant mesh springs) with a turning sun eccentricity and
    a pin error, as the sweep sets it up: (model, stage, meshes, base run, carrier (s,), mesh
    speed (s,), ring)."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"].update(tangential_pin_errors_um=[10.0, 0.0, 0.0],
                             sun_eccentricity_um=20.0, sun_eccentricity_phase_deg=30.0)
    case = jio.parse_train(data)
    spec, model = case.form.spec, jp.PlanarPlanetary()
    stage = spec.sharing_stage(spec.stage(case))
    meshes = spec.dynamic_meshes(case, 1)
    base = ps.planetary_run(case.form, case)
    speeds = np.asarray(speeds)
    return (model, stage, meshes, base, speeds * spec.speeds(1.0)["carrier"],
            speeds * spec.mesh_speed(1.0), spec.ring_model.dynamic_ring())


def test_the_speeds_are_grouped_by_their_step():
    """speed_groups (what steps_sweep compiles): not grouped, every speed in one program;
    grouped, one program per N_s in increasing N_s, the speeds of that N_s in it (each group's
    records: tests/test_planetary_model.py's sweep of two automatic steps, each speed's records
    planetary_dynamics' at its own N_s)."""
    plan = jp.TimePlan(np.array([24, 12, 48, 12]), np.array([6, 4, 8, 3]), 2, 1.0, 1.0, 0.0,
                       (False, False))
    assert [g.tolist() for g in jp.speed_groups(plan, False)] == [[0, 1, 2, 3]]
    assert [g.tolist() for g in jp.speed_groups(plan, True)] == [[1, 3], [0], [2]]


# default tier: tests/test_planetary_step_plan.py::test_the_speeds_are_grouped_by_their_step (the groups) and tests/test_planetary_model.py::test_a_sweep_of_several_automatic_steps_runs_each_at_its_own (each speed at its own N_s = planetary_dynamics)
@pytest.mark.slow
def test_a_grouped_sweep_runs_each_speed_on_its_own_plan():
    """Grouped by N_s (the flexible ring's sweep), each speed integrates its own group's span
    at its own step: its kept forces equal planetary_dynamics called here on a run of the
    speed's N_s, the group's periods and the kept periods (the lumped lin-parker-1999 with a turning sun
    eccentricity, so that the kept window's place matters), to 1e-9 of the nominal force; one
    program per N_s (not grouped: one)."""
    speeds = [150.0, 300.0, 900.0]
    model, stage, meshes, base, carrier, v, ring = _lumped_sweep_parts(speeds)
    # the group of 12 steps spans 4 periods, 2 kept, two speeds: the program of
    # tests/test_planetary_sweep.py's lumped sweep, and its reference's below (one compiled
    # program each for the two files)
    plan = jp.TimePlan(np.array([24, 12, 12]), np.array([6, 4, 3]), 2, 1.0, 1.0, 0.0,
                       (False, False))
    got = jp.steps_sweep(model, stage, meshes, base, plan, carrier, v, ring, grouped=True)
    # the two speeds of 12 steps share a program: both integrate the longer span, 4 periods
    own = [6, 4, 4]
    assert got.programs == 2 and list(got.periods) == own

    def direct(k):
        run = jp.PlanetaryRun(base.sun_torque, steps_per_period=int(plan.steps[k]),
                              periods=own[k], keep_periods=2,
                              tangential_pin_errors=base.tangential_pin_errors,
                              radial_pin_errors=base.radial_pin_errors)
        return lambda om, vi: jp.planetary_dynamics(model, stage, meshes, run, om, vi)

    first = direct(0)(jnp.asarray(carrier[0]), jnp.asarray(v[0]))
    pair = jax.vmap(direct(1))(jnp.asarray(carrier[1:]), jnp.asarray(v[1:]))
    for k in range(3):
        d = first if k == 0 else jax.tree.map(lambda a, k=k: a[k - 1], pair)
        f = np.concatenate([np.asarray(d.sun_mesh_forces), np.asarray(d.ring_mesh_forces)], 1)
        nominal = float(d.static_force)
        assert got.static_force == pytest.approx(nominal, rel=1e-12)
        assert got.forces[k].shape == f.shape == (2 * int(plan.steps[k]), 6)
        assert np.max(np.abs(got.forces[k] - f)) < 1e-9 * nominal
        np.testing.assert_allclose(got.time[k], np.asarray(d.time), rtol=1e-12)
    assert jp.speed_groups(plan, False)[0].tolist() == [0, 1, 2]
    assert [g.tolist() for g in jp.speed_groups(plan, True)] == [[1, 2], [0]]


@pytest.mark.slow  # three compiled runs of the contact-cell stage, ~30 s of CPU; fast twin:
# test_a_grouped_sweep_runs_each_speed_on_its_own_plan (the grouped records, the lumped stage)
def test_a_grouped_sweep_gives_the_one_program_dynamic_factors(small_case):
    """The small contact-cell stage (a 10 um pin error: periodic in the carrier frame) at 15
    and 45 rad/s, 192 and 96 steps per mesh period, the rule's periods: grouped by N_s (two
    programs, each speed its own span) and in one program (the fast speed integrating the
    slow one's span, about 3 x its own), each mesh's dynamic factor agrees to the settled
    tolerance (SETTLED_TOL of the nominal force): what is left of the transient after the
    rule's settling time, not the schedule, sets the difference (measured: 1.2e-4, float64)."""
    case = small_case
    spec, model = case.form.spec, jp.PlanarPlanetary()
    stage = spec.sharing_stage(spec.stage(case))
    meshes = spec.dynamic_meshes(case, 1)  # spur: one slice per contact line
    base = ps.planetary_run(case.form, case)
    speeds = np.array([15.0, 45.0])
    plan = ps.sweep_time_plan(case.form, case, speeds)._replace(steps=np.array([192, 96]))
    carrier = speeds * spec.speeds(1.0)["carrier"]
    v = speeds * spec.mesh_speed(1.0)
    ring = spec.ring_model.dynamic_ring()
    df = {}
    for grouped in (True, False):
        rec = jp.steps_sweep(model, stage, meshes, base, plan, carrier, v, ring, grouped)
        assert rec.programs == (2 if grouped else 1) and not rec.result.any()
        df[grouped] = np.array([f.max(axis=0) / rec.static_force for f in rec.forces])
    # dynamic: the teeth entering mesh ring the stage (1.43 with the cells beyond the
    # theoretical path, the default, where each entering pair takes its load gradually; over
    # 1.5 on the path)
    assert df[True].max() > 1.3
    np.testing.assert_allclose(df[True], df[False], rtol=0, atol=jd.SETTLED_TOL)


@pytest.mark.slow  # two compiled runs of the station model (~10 s of CPU each)
def test_the_ring_cell_space_is_the_coordinate_solve_at_a_sweep_step(tmp_path):
    """The flexible ring's station model (the small stage with the coarse test ring, 53
    stations, massless) at 21 rad/s of the carrier and 768 steps per mesh period (the
    spectrum turn's step, the coarsest a sweep takes here): each step's contact solved in the
    cell space (``ring_cell_space``, the sweep's) gives the coordinate solve's mesh forces and
    ring deflections to 1e-8 of the nominal force and of the largest deflection."""
    from _planetary_stage import seq_ring_case
    from _toml import case_toml

    path = tmp_path / "seq.toml"
    path.write_text(case_toml(seq_ring_case()))
    case = jio.load_case(str(path))
    spec, model = case.form.spec, jp.PlanarPlanetary()
    stage = spec.sharing_stage(spec.stage(case))
    meshes = spec.dynamic_meshes(case, 1)  # spur: one slice per contact line
    ring = spec.ring_model.dynamic_ring()
    base = ps.planetary_run(case.form, case)
    w = spec.speeds(21.0)
    out = {}
    for cells in (False, True):
        run = jp.PlanetaryRun(base.sun_torque, steps_per_period=768, periods=3, keep_periods=1,
                              tangential_pin_errors=base.tangential_pin_errors,
                              radial_pin_errors=base.radial_pin_errors, ring_cell_space=cells)
        out[cells] = jp.planetary_dynamics(model, stage, meshes, run, jnp.asarray(w["carrier"]),
                                           jnp.asarray(spec.mesh_speed(21.0)), ring=ring)
    a, b = out[False], out[True]
    nominal = float(a.static_force)
    for f in ("sun_mesh_forces", "ring_mesh_forces"):
        assert np.max(np.abs(np.asarray(getattr(a, f)) - np.asarray(getattr(b, f)))) \
            < 1e-8 * nominal
    w_a = np.asarray(a.ring_deflection)
    assert np.max(np.abs(w_a)) > 0
    assert np.max(np.abs(w_a - np.asarray(b.ring_deflection))) < 1e-8 * np.max(np.abs(w_a))
    assert int(a.result) == int(b.result) == 0
