"""The coupled gearbox (jaxgear.gearbox.gearbox_dynamics and its modes; docs/gearbox.md): the
inter-stage shaft's limits, the torsional chain's modes, a stage excited alone against its own
dynamics, and the quasi-static limit, on the two-stage example (examples/gearbox_two_stage.py:
a planetary stage, ring held, carrier in, sun out, whose sun drives a spur pair)."""

import math
import pathlib

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _examples import load_example

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear import gearbox as gb

EX = load_example("gearbox_two_stage")
K_U = EX.K_U
Z_S, Z_P, Z_R, Z_G, Z_PIN = 20, 30, 80, 32, 24
RB = 0.5 * 4e-3 * math.cos(math.radians(20.0))  # base radius per tooth (m)
# transverse contact ratios of the standard spur pairs (tips r + m; the ring's r - m): the
# rectangular waves' means, k_u b eps
EPS_SP = (math.sqrt(44**2 - (40 * math.cos(math.radians(20))) ** 2)
          + math.sqrt(64**2 - (60 * math.cos(math.radians(20))) ** 2)
          - 100 * math.sin(math.radians(20))) / (math.pi * 4 * math.cos(math.radians(20)))
EPS_RP = (math.sqrt(64**2 - (60 * math.cos(math.radians(20))) ** 2)
          - math.sqrt(156**2 - (160 * math.cos(math.radians(20))) ** 2)
          + 100 * math.sin(math.radians(20))) / (math.pi * 4 * math.cos(math.radians(20)))
EPS_PAIR = (math.sqrt(52**2 - (48 * math.cos(math.radians(20))) ** 2)
            + math.sqrt(68**2 - (64 * math.cos(math.radians(20))) ** 2)
            - 112 * math.sin(math.radians(20))) / (math.pi * 4 * math.cos(math.radians(20)))


def _hz(m, k):
    lam = scipy.linalg.eigh(k, m, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)


def _reference_blocks(shaft, output=5e5):
    """The two-stage system's (M, K) on (theta_c, theta_r, theta_s, theta_1..4, theta_pinion,
    theta_gear), written here from the spec: Kahraman's torsional deflections
    delta_sn = r_s th_s + r_p th_n - r_c cos(a) th_c, delta_rn = r_r th_r - r_p th_n - r_c cos(a)
    th_c (pressure angle 20 deg both), each mesh at its mean k_u b eps, the ring's hold, the
    pair's k_u b eps on r_pin th_pin + r_gear th_gear, the shaft sun-gear and the pinion's hold."""
    r_s, r_p, r_r, r_c = Z_S * RB, Z_P * RB, Z_R * RB, 0.1
    ca = math.cos(math.radians(20.0))
    n = 9
    m = np.diag([0.5 + 4 * 4.44 * r_c**2, 2.0, 1.6e-3, 8e-3, 8e-3, 8e-3, 8e-3, 5.2e-3, 0.0165])
    k = np.zeros((n, n))
    k_s, k_r = K_U * 0.05 * EPS_SP, K_U * 0.05 * EPS_RP
    for j in range(4):
        v = np.zeros(n)
        v[[0, 2, 3 + j]] = [-r_c * ca, r_s, r_p]
        k += k_s * np.outer(v, v)
        v = np.zeros(n)
        v[[0, 1, 3 + j]] = [-r_c * ca, r_r, -r_p]
        k += k_r * np.outer(v, v)
    k[1, 1] += 1e9
    v = np.zeros(n)
    v[[7, 8]] = [Z_PIN * RB, Z_G * RB]
    k += K_U * 0.08 * EPS_PAIR * np.outer(v, v)
    v = np.zeros(n)
    v[[2, 8]] = [1.0, -1.0]
    k += shaft * np.outer(v, v)
    k[7, 7] += output
    return m, k


def test_contact_ratios_of_the_example_are_the_spec_ones():
    chain, _ = EX.two_stage()
    meshes = chain.stages[0].meshes
    pair = chain.stages[1].mesh
    for mesh, eps in ((meshes.sun_mesh, EPS_SP), (meshes.ring_mesh, EPS_RP), (pair, EPS_PAIR)):
        assert float(mesh.path_of_contact / mesh.base_pitch) == pytest.approx(eps, rel=1e-9)


@pytest.mark.parametrize("factor", [1e-3, 1e3])
def test_shaft_limits(factor):
    """Soft shaft (k_t -> 0): the stages' own modes (stage 1 with its carrier and sun free, ring
    held: the train's kinematic freedom, a mode -> 0 Hz as sqrt(k_t); stage 2 with its gear
    free, pinion held); stiff
    (k_t -> inf): the sun and the gear one body (the constrained system) and one mode -> inf.
    The coupled model's mesh-averaged modes tend to them, closer at 1e3 than at 1e1."""
    errors, low = [], []
    for f in (factor ** (1 / 3), factor):
        shaft = 5e5 * f
        chain, run = EX.two_stage(shaft=shaft, mean_positions=4096)
        got = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)
        m, k = _reference_blocks(shaft)
        if f < 1:  # the blocks without the shaft, and the shaft mode
            k0 = k.copy()
            k0[2, 2] -= shaft
            k0[8, 8] -= shaft
            k0[2, 8] += shaft
            k0[8, 2] += shaft
            limit = np.sort(np.concatenate([_hz(m[:7, :7], k0[:7, :7]),
                                            _hz(m[7:, 7:], k0[7:, 7:])]))
            # stage 1 alone keeps its kinematic freedom (ring held, carrier, planets and sun
            # turning as the train): limit[0] = 0, the coupled mode -> 0 as sqrt(k_t)
            assert limit[0] < 1e-6 * limit[-1]
            low.append(got[0])
            errors.append(np.max(np.abs(got[1:] / limit[1:] - 1)))
        else:  # theta_gear = theta_s: T maps 8 coordinates to 9
            t = np.zeros((9, 8))
            t[:8, :8] = np.eye(8)
            t[8, 2] = 1.0
            limit = _hz(t.T @ m @ t, t.T @ k @ t)
            errors.append(np.max(np.abs(got[:-1] / limit - 1)))
    assert errors[1] < 3e-3, errors
    assert errors[1] < 0.1 * errors[0], errors
    if low:  # sqrt(k_t): 100 x softer, 10 x lower
        assert low[1] / low[0] == pytest.approx(0.1, rel=5e-2)


def test_a_planetary_model_is_a_stage():
    """The one stage contract (jaxgear.dynamics.AbstractStage): the example's planetary stage as
    the PlanetaryModel that runs alone, given its input and output members, stands in the
    gearbox. Its speeds per input speed are Willis' from the tooth counts (carrier in, ring
    held: the carrier at 1, the meshes at r_br, the sun at 1 + z_r / z_s = 5; sun in, carrier
    out: the carrier at z_s / (z_s + z_r) = 0.2; a star stage, sun in, ring out: the carrier at
    0, the ring at -z_s / z_r), and the coupled model's mesh-averaged modes are the blocks
    written from the spec (_reference_blocks) to 1e-3 (the cells averaged over 4096 positions
    against the rectangular waves' means)."""
    import jaxgear.dynamics as jd

    chain, run = EX.two_stage(mean_positions=4096)
    p = chain.stages[0]
    C = jp.Central
    model = jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, input=C.CARRIER, output=C.SUN)
    assert isinstance(model, jd.AbstractStage) and type(model) is jp.PlanetaryModel
    r_s, r_r = Z_S * RB, Z_R * RB
    assert float(model.carrier_per_input) == pytest.approx(1.0, rel=1e-12)
    assert float(model.mesh_speed_per_input) == pytest.approx(r_r, rel=1e-9)
    w_out, t_out, v, _ = model.kinematics(1.0, 1.0)
    assert (float(w_out), float(t_out), float(v)) == pytest.approx((5.0, 0.2, r_r), rel=1e-9)
    sun_in = jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, input=C.SUN, output=C.CARRIER)
    assert float(sun_in.carrier_per_input) == pytest.approx(Z_S / (Z_S + Z_R), rel=1e-9)
    assert float(sun_in.mesh_speed_per_input) == pytest.approx(r_s * Z_R / (Z_S + Z_R), rel=1e-9)
    star = jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, input=C.SUN, output=C.RING)
    assert float(star.carrier_per_input) == pytest.approx(0.0, abs=1e-12)
    assert float(star.kinematics(1.0, 1.0)[0]) == pytest.approx(-Z_S / Z_R, rel=1e-9)

    coupled = gb.GearboxTorsional((model, chain.stages[1]), chain.shaft_stiffnesses)
    got = np.asarray(gb.gearbox_coupled_modes(coupled, run).analysis.frequency)
    np.testing.assert_allclose(got, _hz(*_reference_blocks(5e5)), rtol=1e-3)


@pytest.mark.parametrize("build, message", [
    (lambda p: gb.GearboxTorsional((jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run),), []),
     r"^GearboxTorsional: stages\[0\]: a PlanetaryModel without its input and output members"),
    (lambda p: gb.GearboxTorsional(("stage",), []),
     r"^GearboxTorsional: stages\[0\] = .*\(str\) is out of range: allowed a gearbox stage"),
    (lambda p: jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, 0.5,
                                 input=jp.Central.SUN, output=jp.Central.CARRIER),
     r"^PlanetaryModel: carrier_per_input or mesh_speed_per_input given with the input"),
    (lambda p: jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, input=jp.Central.SUN),
     r"^PlanetaryModel: input = <Central.SUN: 0>, output = None: allowed both"),
    (lambda p: jp.PlanetaryModel(p.kind, p.stage, p.meshes, p.run, input=jp.Central.SUN,
                                 output=jp.Central.SUN),
     r"^PlanetaryModel: input = output = <Central.SUN: 0>: allowed two different"),
], ids=["no-roles", "not-a-stage", "roles-and-ratio", "one-role", "same-roles"])
def test_a_stage_that_cannot_stand_is_refused_in_one_line(build, message):
    p = EX.two_stage()[0].stages[0]
    with pytest.raises((ValueError, TypeError), match=message) as err:
        build(p)
    assert "\n" not in str(err.value)


def test_torsional_stages_give_the_torsional_chain():
    """Constant meshes (no cells): the coupled modes of nrel-5mw-gearbox's chain are
    jaxgear.gearbox.gearbox_modes' (the torsional chain's) to 1e-9, the output hold nearly free."""
    chain = jio.load_case("nrel-5mw-gearbox").form.torsional()
    want = np.asarray(gb.gearbox_modes(chain).frequencies)
    run = gb.GearboxRun(1e6, 1e-6)
    got = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)
    elastic = want > 1e-3
    assert got[0] < 1e-3 and want[0] < 1e-3
    np.testing.assert_allclose(got[elastic], want[elastic], rtol=1e-9)


# default tier: tests/test_gearbox_reference.py::test_coupled_dynamic_factors_match_the_independent_reference_at_two_speeds (the planetary stage's dynamics in the chain, every mesh against an independent reference, 2 %)
@pytest.mark.slow
def test_stage_alone_equals_its_own_dynamics():
    """Stage 1 alone (sun in, carrier out held by a spring): the coupled run's mesh forces are
    jaxgear.planetary.planetary_dynamics' of the stage with its carrier held by that spring."""
    chain, _ = EX.two_stage()
    p = chain.stages[0]
    k_c = 2e7
    one = gb.GearboxTorsional((gb.PlanetaryGearboxStage(p.stage, jp.Central.SUN,
                                                         jp.Central.CARRIER, p.meshes),), [])
    run = gb.GearboxRun(1000.0, k_c, steps_per_period=32, periods=30, keep_periods=2,
                        mean_positions=32)  # planetary_dynamics averages over its steps
    omega_c = 40.0
    r_s, r_r = float(p.stage.sun.base_radius), float(p.stage.ring.base_radius)
    got = gb.gearbox_dynamics(one, run, omega_c * (1 + r_r / r_s))
    held = eqx.tree_at(lambda st: st.carrier, p.stage,
                       jp.PlanetaryMember(10.0, 0.5, 0.1, torsional_stiffness=k_c))
    own = jg.planetary.planetary_dynamics(jp.TorsionalPlanetary(), held, p.meshes,
                                jg.planetary.PlanetaryRun(1000.0, 32, 30, 2), omega_c)
    want = np.concatenate([own.sun_mesh_forces, own.ring_mesh_forces], axis=1)
    assert int(got.result) == 0 and int(own.result) == 0
    np.testing.assert_allclose(np.asarray(got.mesh_forces), want, rtol=1e-7,
                               atol=1e-9 * float(np.max(want)))


# default tier: tests/test_gearbox_compound.py::test_quasi_static_torque_balance_of_a_coupled_run (mean mesh forces the static ones at 0.5 rad/s, a stepped stage) and tests/test_gearbox_coupled.py::test_jaxgear_runs_coupled_section (this chain's static forces from the torque ratios, 1e-12)
@pytest.mark.slow
def test_quasi_static_limit_gives_the_torque_ratios():
    """At a carrier speed whose mesh frequencies lie far below every mode (0.5 rad/s: 6.4 and
    12.7 Hz against 448 Hz and up), each mesh force is the static one from the torque ratios
    (the chain is statically determinate: the planets' equilibrium sets the sun's torque
    5000 / (1 + z_r / z_s)) but for the short ring after each change of the number of tooth
    pairs (a stiffness step, which no speed smooths: the deflection must jump, so that the
    maximum is not the static force at any speed): the median over the recorded window
    within 1e-4 (at 2 rad/s, 1.5e-3: the ring's share of the period grows with the speed),
    the mean within 1e-6 (the inertia forces average out over a steady period)."""
    chain, run = EX.two_stage(steps_per_period=2048, periods=3, keep_periods=2)
    out = gb.gearbox_dynamics(chain, run, 0.5)
    t_sun = 5000.0 / (1 + Z_R / Z_S)
    want = np.array([t_sun / (4 * Z_S * RB)] * 8 + [t_sun / (Z_G * RB)])
    np.testing.assert_allclose(np.asarray(out.static_forces), want, rtol=1e-12)
    f = np.asarray(out.mesh_forces)
    assert int(out.result) == 0
    np.testing.assert_allclose(np.median(f, axis=0), want, rtol=1e-4)
    np.testing.assert_allclose(np.mean(f, axis=0), want, rtol=1e-6)


# default tier: tests/test_planetary_sweep.py::test_the_lumped_sweep_is_planetary_dynamics_at_each_speed (the sweep is the single runs, the planetary kind); the gearbox's sweep over two speeds: tests/test_gearbox_coupled.py::test_jaxgear_runs_coupled_section
@pytest.mark.slow
def test_sweep_is_each_speed_run_alone():
    """The vmapped sweep is the single runs at its speeds (the engine's vectorisation), on
    tests/test_gearbox_whine.py's two spur pairs joined by a shaft at 32 steps per period (the
    vectorisation is the chain's kind's, whatever its stages; on the two-stage example's nine
    meshes at 2048 steps per period its sweep's compilation and runs took 9 CPU s, here the
    single run's and the sweep's together 6)."""
    from test_gearbox_whine import _two_pairs

    chain, run = _two_pairs(steps_per_period=32, periods=6, keep_periods=2)
    speeds = jnp.array([30.0, 70.0])
    sweep = gb.gearbox_speed_sweep(chain, run, speeds)
    for i, w in enumerate(speeds):
        one = gb.gearbox_dynamics(chain, run, w)
        np.testing.assert_allclose(sweep.dynamic_factors[i], one.dynamic_factors, rtol=1e-9)


def test_bad_inputs_one_line():
    chain, run = EX.two_stage()
    with pytest.raises(ValueError, match="output_stiffness"):
        gb.GearboxRun(1.0, 0.0)
    with pytest.raises(ValueError, match="input_speed"):
        gb.gearbox_dynamics(chain, run, 0.0)
    with pytest.raises(ValueError, match="chain"):
        gb.gearbox_dynamics("box", run, 1.0)


@pytest.fixture(scope="module")
def case_modes():
    """The two-stage case file's coupled chain (contact on the theoretical path, as the case
    file states) and its coupled modes (Hz) on the example's default run: shared by the
    case-file and extended-contact tests (one modal solve)."""
    _, run = EX.two_stage()
    chain = jio.load_case(str(pathlib.Path(__file__).parent / "data" / "gearbox"
                              / "two-stage-gearbox.toml")).form.coupled()
    return chain, np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)


# default tier: tests/test_gearbox_case_housing.py::test_a_planar_planetary_stage_on_the_ground (this file, its planetary stage planar, against the example's build, 1e-10) and tests/test_gearbox_coupled.py::test_jaxgear_runs_coupled_section (this file's torsional chain: static forces, highest mode)
@pytest.mark.slow
def test_the_case_file_builds_the_example(case_modes):
    """tests/data/gearbox/two-stage-gearbox.toml (the same gearbox as case files: a planetary
    case, a pair case, the gearbox's [[stages]]) gives, through jaxgear.io's GearboxForm.coupled,
    the model the example builds in Python: the same coupled modes and the same cells."""
    chain, f_case = case_modes
    ex, run = EX.two_stage()
    f_ex = np.asarray(gb.gearbox_coupled_modes(ex, run).analysis.frequency)
    np.testing.assert_allclose(f_case, f_ex, rtol=1e-10)
    # the rows of both builds by one compiled program per kind of stage (the same function of
    # the stage's leaves; cell_row called eagerly compiled some 200 small programs)
    rows = eqx.filter_jit(lambda stage, x: stage.cell_row(x))
    for a, b in zip(chain.stages, ex.stages, strict=True):
        for x in (0.0, 3.1e-3, 7.7e-3):
            ra, rb = rows(a, jnp.asarray(x)), rows(b, jnp.asarray(x))
            np.testing.assert_array_equal(np.asarray(ra.mask), np.asarray(rb.mask))
            np.testing.assert_allclose(np.asarray(ra.V), np.asarray(rb.V), rtol=1e-12)
            np.testing.assert_allclose(np.asarray(ra.k * ra.length), np.asarray(rb.k * rb.length),
                                       rtol=1e-12)


def test_extended_contact_leaves_the_mesh_averaged_modes(tmp_path, case_modes):
    """The gearbox case files with contact beyond the theoretical path (the case files' default,
    here the pin removed): the coupled modes (M, K + K̄_m) are those on the theoretical path to
    1e-10 (K̄_m averages the cells on the path: beyond it a corner's cell holds a gap and
    carries load only under deflection, docs/extended-contact.md); counting them as springs
    put the modes up to 18 % higher."""
    data = pathlib.Path(__file__).parent / "data" / "gearbox"
    for f in data.glob("two-stage-gearbox*.toml"):
        text = f.read_text(encoding="utf-8")
        keep = [ln for ln in text.splitlines(keepends=True)
                if "extended_contact" not in ln and "the Python example it mirrors" not in ln]
        (tmp_path / f.name).write_text("".join(keep), encoding="utf-8")
    extended = jio.load_case(str(tmp_path / "two-stage-gearbox.toml")).form.coupled()
    assert extended.stages[1].mesh.contact_geometry == jg.BeyondPath()  # the default, on
    path, f_path = case_modes  # the case file itself: on the theoretical path
    assert path.stages[1].mesh.contact_geometry == jg.TheoreticalPath()
    _, run = EX.two_stage()
    f_ext = np.asarray(gb.gearbox_coupled_modes(extended, run).analysis.frequency)
    np.testing.assert_allclose(f_ext, f_path, rtol=1e-10)


# default tier: tests/test_dynamics_resolution.py::test_default_step_matches_continuous_reference (the automatic step against a continuous reference) and tests/test_gearbox_model.py::test_automatic_step_is_the_engines_rule_on_the_highest_excited_mode (the gearbox's step is that rule)
@pytest.mark.slow
def test_automatic_time_plan_converges_on_two_pairs():
    """The automatic plan (40 steps per period of the highest mode the meshes excite, 8 time
    constants of the lowest to settle) against twice its steps on the same blocks: every
    mesh's dynamic factor within 1.5 %, on tests/test_gearbox_whine.py's two relieved spur pairs
    joined by a shaft at 60 rad/s (first mesh 229 Hz; measured 0.03 %; a quarter of the
    automatic step: 7 %)."""
    from test_gearbox_whine import _two_pairs

    chain, run = _two_pairs(steps_per_period=None, periods=None, keep_periods=1)
    speed = 60.0
    steps = int(jd.auto_steps_per_period(gb.GearboxModel(chain, run), np.array([speed]))[0])
    auto = gb.gearbox_dynamics(chain, run, speed)
    per_block = auto.time.shape[0]  # one recorded block: the second pair's mesh period
    blocks = int(auto.steps) // per_block
    _, finer = _two_pairs(steps_per_period=2 * steps, periods=blocks, keep_periods=1)
    fine = gb.gearbox_dynamics(chain, finer, speed)
    assert int(auto.result) == 0 and int(fine.result) == 0
    assert abs(fine.time.shape[0] - 2 * per_block) <= 1
    np.testing.assert_allclose(np.asarray(auto.dynamic_factors),
                               np.asarray(fine.dynamic_factors), rtol=1.5e-2)


# default tier: tests/test_dynamics_resolution.py::test_default_step_matches_continuous_reference (the automatic step against a continuous reference) and tests/test_gearbox_model.py::test_automatic_step_is_the_engines_rule_on_the_highest_excited_mode (the gearbox's step is that rule)
@pytest.mark.slow
def test_automatic_time_plan_converges():
    """The automatic plan (40 steps per period of the highest mode the meshes excite, 8 time
    constants of the lowest to settle) against twice its steps: every mesh's dynamic factor
    within 1.5 % (the peaks of the ring after each stiffness step converge as the step's
    square), at 100 rad/s, near the pair's resonance."""
    chain, run = EX.two_stage(steps_per_period=None, periods=None, keep_periods=1)
    auto = gb.gearbox_dynamics(chain, run, 100.0)
    per_block = auto.time.shape[0]  # one recorded block: 2 S steps (stage 2 meshes twice as fast)
    # the same blocks as the automatic span (given: no second modal solve for the plan)
    blocks = int(auto.steps) // per_block
    _, finer = EX.two_stage(steps_per_period=per_block, periods=blocks, keep_periods=1)
    fine = gb.gearbox_dynamics(chain, finer, 100.0)
    assert int(auto.result) == 0 and int(fine.result) == 0
    assert fine.time.shape[0] == 2 * per_block
    np.testing.assert_allclose(np.asarray(auto.dynamic_factors),
                               np.asarray(fine.dynamic_factors), rtol=1.5e-2)


def test_jaxgear_runs_coupled_section(tmp_path, monkeypatch):
    """jaxgear run's coupled section of a gearbox (jaxgear.cli.gearbox.coupled_sweep) on the
    two-stage case file: coupled.json and coupled.png written, the nine meshes named, their
    static forces the torque ratios', the modes typed, the resolution reported (at the ends of
    the operating range alone: the lowest speed sets the step, the highest the span)."""
    import jaxgear.cli.gearbox as cli_gearbox
    from jaxgear.cli.gearbox import coupled_sweep

    monkeypatch.setattr(cli_gearbox, "COUPLED_SPEEDS", cli_gearbox.COUPLED_SPEEDS[[0, -1]])

    case = jio.load_case(str(pathlib.Path(__file__).parent / "data" / "gearbox"
                             / "two-stage-gearbox.toml"))
    c = coupled_sweep(case.form, str(tmp_path))
    assert (tmp_path / "coupled.png").is_file() and (tmp_path / "coupled.json").is_file()
    assert len(c["mesh_names"]) == 9 and c["mesh_names"][-1] == "2:pair"
    t_sun = 5000.0 / (1 + Z_R / Z_S)
    np.testing.assert_allclose(c["static_force_N"], [t_sun / (4 * Z_S * RB)] * 8
                               + [t_sun / (Z_G * RB)], rtol=1e-12)
    assert set(c["result"]) == {0}
    assert np.asarray(c["dynamic_factor_mesh"]).shape == (len(c["input_speeds_rad_s"]), 9)
    # the sun-planet mode (11036 Hz with the meshes averaged finely; the command averages over
    # 32 positions a period)
    assert c["highest_excited_mode_Hz"] == pytest.approx(11036.06, rel=1e-2)
    assert {m["type"] for m in c["modes"]} <= {"mesh", "structure", "shaft 1-2", "output hold",
                                               "rigid body"}
    # the stages' K_v beside these meshes (jaxgear.cli.gearbox.rating_dynamic_factors; the
    # matching by hand-made ratings in tests/test_gearbox_rating_kv.py): the planetary stage's
    # two rated meshes read its four sun-planet and four ring-planet meshes, the pair its one;
    # the rated speed lies between the two speeds run here: interpolated linearly
    kv = {"value": [1.1, 1.2], "source": ["ISO 6336-1 method B"] * 2}
    stages = [{"stage": "stage1", "case": "p", "summary": {"rating": {
                  "meshes": ["sun-planet", "planet-ring"], "factors": {"K_v": kv}}}},
              {"stage": "stage2", "case": "q", "summary": {"rating": {
                  "factors": {"K_v": {"value": 1.3, "source": "given"}}}}}]
    rated = case.form.stages[0].input_speed
    rows = cli_gearbox.rating_dynamic_factors(stages, c, rated)
    assert [r["coupled_meshes"] for r in rows] == [c["mesh_names"][:4], c["mesh_names"][4:8],
                                                   ["2:pair"]]
    speeds, df = np.asarray(c["input_speeds_rad_s"]), np.asarray(c["dynamic_factor_mesh"])
    at = [np.interp(rated, speeds, df[:, j]) for j in range(9)]
    np.testing.assert_allclose([r["coupled_dynamic_factor"] for r in rows],
                               [max(at[:4]), max(at[4:8]), at[8]], rtol=1e-14)


# default tier: tests/test_gearbox_coupled.py::test_shaft_limits (the soft-shaft limit, torsional stages); the planar stage in a chain: tests/test_gearbox_case_housing.py::test_a_planar_planetary_stage_on_the_ground
@pytest.mark.slow
def test_planar_stage_soft_shaft_limit():
    """A planar planetary stage (PlanarPlanetary: translations in its carrier frame, bearings
    1e8 N/m) joined by a shaft 10³ softer than the example's: the coupled modes tend to the
    stage's own mesh-averaged modes (jaxgear.planetary.planetary_mesh_modes, its kinematic
    freedom the one mode -> 0) and the pair's two (gear free, pinion held; the 2 x 2 problem
    written here)."""
    chain, run = EX.two_stage(shaft=5e2, mean_positions=64)
    p = chain.stages[0]

    def bear(m):
        return eqx.tree_at(lambda x: x.bearing_stiffness, m, jnp.array([1e8, 1e8]))

    st = eqx.tree_at(lambda s: (s.sun, s.ring, s.carrier, s.planet), p.stage,
                     tuple(bear(m) for m in (p.stage.sun, p.stage.ring, p.stage.carrier,
                                             p.stage.planet)))
    planar = gb.PlanetaryGearboxStage(st, p.input, p.output, p.meshes, jp.PlanarPlanetary())
    coupled = gb.GearboxTorsional((planar, chain.stages[1]), chain.shaft_stiffnesses)
    got = np.asarray(gb.gearbox_coupled_modes(coupled, run).analysis.frequency)
    own = np.asarray(jg.planetary.planetary_mesh_modes(jp.PlanarPlanetary(), st, p.meshes,
                                             jg.planetary.PlanetaryRun(0.0, 64)).frequency)
    r = np.array([Z_PIN * RB, Z_G * RB])
    k_pair = K_U * 0.08 * EPS_PAIR * np.outer(r, r) + np.diag([5e5, 0.0])
    limit = np.sort(np.concatenate([own, _hz(np.diag([5.2e-3, 0.0165]), k_pair)]))
    assert own[0] < 1e-6 * own[-1] and got[0] < 0.1 * got[1]  # ~ sqrt(k_t): 20 Hz
    np.testing.assert_allclose(got[1:], limit[1:], rtol=3e-3)


@pytest.mark.slow
def test_nrel_coupled_plan_is_resolved():
    """jaxgear run nrel-5mw-gearbox's coupled sweep (jaxgear.cli.gearbox's COUPLED_RUN: the
    automatic plan at 24 steps per period of the highest mode the meshes excite at the lowest
    speed, 3 time constants to settle, 4 blocks of stage 1's mesh period recorded) against
    (a) twice its steps, the same window: every mesh's dynamic factor at every speed within
    2 % (measured: 0.73 % at most, at 0.2 × rated); (b) twice its steps, settling and window:
    within 5 % (measured 4.3 %): the response is quasi-periodic (the three stages' mesh periods
    are incommensurate, 4625/112 pair periods a stage-1 period), so that the maximum over a
    window samples it, and a window twice as long and placed later finds other peaks
    (docs/gearbox.md, "Resolution and cost")."""
    from jaxgear.cli.gearbox import COUPLED_RUN, COUPLED_SPEEDS

    form = jio.load_case("nrel-5mw-gearbox").form
    chain, first = form.coupled(), form.stages[0]
    speeds = first.input_speed * COUPLED_SPEEDS
    hold = form.stages[-1].shaft_stiffness

    def sweep(**change):
        run = gb.GearboxRun(first.input_torque, hold, **{**COUPLED_RUN, **change})
        out = gb.gearbox_speed_sweep(chain, run, speeds)
        assert set(np.asarray(out.result).tolist()) == {0}
        return np.asarray(out.dynamic_factors), int(np.asarray(out.steps)[0])

    plan, n = sweep()
    finer, n_fine = sweep(steps_per_mode=2 * COUPLED_RUN["steps_per_mode"])
    longer, n_long = sweep(steps_per_mode=2 * COUPLED_RUN["steps_per_mode"],
                           settle=2 * COUPLED_RUN["settle"],
                           keep_periods=2 * COUPLED_RUN["keep_periods"])
    # twice the steps per block, twice the blocks: each block the slowest mesh's period rounded
    # to whole steps at its own step (4625/112 pair periods), so within a step per block
    assert n_fine == pytest.approx(2 * n, rel=1e-4) and n_long == pytest.approx(4 * n, rel=1e-4)
    np.testing.assert_allclose(plan, finer, rtol=2e-2)
    np.testing.assert_allclose(plan, longer, rtol=5e-2)
