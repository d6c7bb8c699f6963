"""Sweeps that settle before they are read (docs/dynamics.md "Settled sweeps"): the
settling time of the slowest decaying mode the meshes excite, the modal damping ratios it reads,
a pair's settled sweep against runs four times longer, and the case file's ``periods = "auto"``
with sweep.json's ``settled`` per speed."""

import json
import math
from typing import NamedTuple

import numpy as np
import pytest

import jaxgear.dynamics as jd
import jaxgear.io as jio
from jaxgear.cli import main
from jaxgear.dynamics import Newmark, SteadyState
from jaxgear.io import build_dynamic_model, parse_scene


class _Modes(NamedTuple):
    omega: np.ndarray
    rigid: np.ndarray
    mesh_energy: np.ndarray


def test_settling_time_is_the_slowest_decay_of_the_modes_the_meshes_excite():
    # a rigid mode, a slow mode with 3 % of its strain energy in the meshes (not excited), and
    # two excited modes: t_s = ln(1000) / min(ξ ω) over the two excited ones
    modes = _Modes(
        omega=np.array([0.0, 100.0, 2000.0, 5000.0]),
        rigid=np.array([True, False, False, False]),
        mesh_energy=np.array([0.0, 0.03, 0.5, 0.2]),
    )
    xi = np.array([np.nan, 0.001, 0.05, 0.01])
    t_s, w = jd.settling_time(modes, xi)
    assert w == 5000.0  # ξω: 100 (2000 × 0.05) against 50 (5000 × 0.01)
    assert t_s == pytest.approx(math.log(1000.0) / 50.0, rel=1e-12)
    # one ratio for every mode (the planetary stages'): the lowest excited mode
    t_s, w = jd.settling_time(modes, 0.02)
    assert (w, t_s) == (2000.0, pytest.approx(math.log(1000.0) / 40.0, rel=1e-12))
    # undamped: never settles
    assert jd.settling_time(modes, 0.0)[0] == math.inf
    # a settled sweep's cap also counts the modes with >= 1 % share: the slow 3 % mode sets it
    t_c, w = jd.settling_time(modes, xi, 1e-2)
    assert (w, t_c) == (100.0, pytest.approx(math.log(1000.0) / 0.1, rel=1e-12))


def test_modal_damping_ratios_of_a_rayleigh_damping():
    # two masses on springs, C = a M + b K: ξ_i = a / (2 ω_i) + b ω_i / 2 (Rayleigh)
    m = np.diag([2.0, 3.0])
    k = np.array([[5e6, -2e6], [-2e6, 2e6]])
    a, b = 40.0, 2e-5
    w2, v = np.linalg.eigh(np.linalg.solve(np.sqrt(m), np.linalg.solve(np.sqrt(m), k).T).T)
    shapes = np.linalg.solve(np.sqrt(m), v)  # mass-normalised
    omega = np.sqrt(w2)
    modes = _Modes(omega, np.array([False, False]), np.array([1.0, 1.0]))

    class WithShapes(NamedTuple):
        omega: np.ndarray
        rigid: np.ndarray
        mesh_energy: np.ndarray
        shapes: np.ndarray

    xi = jd.modal_damping_ratios(WithShapes(*modes, shapes), a * m + b * k)
    np.testing.assert_allclose(xi, a / (2 * omega) + b * omega / 2, rtol=1e-12)


@pytest.fixture(scope="module")
def pair_model():
    case = jio.load_case("accessory-spur").replace(slices=2)
    spec = parse_scene({"integration": {"steps_per_period": 32}})  # composite damping
    return build_dynamic_model(case, spec)[0], case


def test_settled_dynamic_factor_agrees_with_a_run_four_times_longer(pair_model):
    model, case = pair_model
    law = case.contact_law("exact")
    speeds = np.linspace(300.0, 1800.0, 6)
    s = jd.settled_sweep(model, speeds, integrator=Newmark(32), contact=law, keep_periods=4)
    assert s.settled.all() and (s.change <= 1e-2).all()
    assert (s.periods % s.window == 0).all() and (s.periods <= s.cap).all()
    # every speed from the static equilibrium for four times the most periods a speed ran
    long = jd.speed_sweep(
        model,
        speeds,
        integrator=Newmark(32),
        contact=law,
        window=SteadyState(4 * int(s.periods.max()), 4),
    ).results
    df = np.asarray(s.sweep.results.dynamic_factor)
    # the tolerance: the settled check's, 1e-2 of the static mesh force
    np.testing.assert_allclose(df, np.asarray(long.dynamic_factor), atol=1e-2, rtol=0)
    # the span the rule gives an independent run: keep + ceil(t_s f_mesh), f_mesh = Ω z1 / 2π
    z1 = case.pairs[0].pinion.teeth
    rule = 4 + np.ceil(s.settle_s * speeds * z1 / (2 * math.pi))
    assert (s.cap >= 2 * rule).all()
    # and the span that lets every mode with >= 1 % of its strain energy in the meshes decay to
    # 1e-3, t_c = ln(1000) / min(ξ ω) over those modes (ξ = φᵀCφ / 2ω, from the modes here)
    modes = model.averaged_modes()
    omega, share = np.asarray(modes.omega), np.asarray(modes.mesh_energy)
    phi = np.asarray(modes.shapes)
    c = np.einsum("ji,jk,ki->i", phi, np.asarray(model.damping), phi)
    xi = c / (2 * np.where(omega > 0, omega, 1.0))
    counted = ~np.asarray(modes.rigid) & (share >= 1e-2)
    t_c = math.log(1000.0) / float(np.min((xi * omega)[counted]))
    assert (s.cap >= 4 + np.ceil(t_c * speeds * z1 / (2 * math.pi))).all()


def test_a_speed_that_never_settles_runs_to_its_cap_and_is_named_on_stderr(
    pair_model, monkeypatch, capsys
):
    # a bound no run meets (1e-12 of the static force): the speed runs every window of its cap,
    # comes back unsettled, and jaxgear sweep's settled pass prints one line naming it
    from functools import partial

    from jaxgear.cli.sweep import settled_sweeps

    model, case = pair_model
    spec = parse_scene({"integration": {"steps_per_period": 32}})
    monkeypatch.setattr(jd, "settled_sweep", partial(jd.settled_sweep, tol=1e-12))
    _, (s,) = settled_sweeps(
        model, np.array([600.0]), spec, case.contact_law("exact"), None, "up", lambda n: None
    )
    assert not s.settled[0] and s.periods[0] == s.cap[0] and s.change[0] > 1e-12
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith(f"jaxgear: warning: speed 600 rad/s: not settled after {s.cap[0]} ")


def test_settled_sweep_refuses_speeds_not_ascending(pair_model):
    with pytest.raises(ValueError, match="ascending"):
        jd.settled_sweep(pair_model[0], [900.0, 300.0])


def test_case_file_periods_auto_and_bad_values():
    assert parse_scene({}).periods is None  # the default: each speed until it settles
    assert parse_scene({"integration": {"periods": "auto"}}).periods is None
    assert parse_scene({"integration": {"periods": 40}}).periods == 40
    with pytest.raises(ValueError, match=r"periods.*'auto' or an integer"):
        parse_scene({"integration": {"periods": "long"}})


@pytest.mark.slow
def test_sweep_json_says_whether_each_speed_settled(tmp_path):
    out = tmp_path / "sw"
    argv = ["sweep", "accessory-spur", "--speeds", "400:800:2", "--slices", "2"]
    main([*argv, "--out", str(out), "--quiet"])
    s = json.loads((out / "sweep.json").read_text())
    assert s["periods"] == "auto"
    assert s["settled"] == [True, True]
    assert all(c <= 1e-2 for c in s["settle_change"])
    assert all(p % s["settle"]["window_periods"] == 0 for p in s["periods_run"])
    header = (out / "sweep.csv").read_text().splitlines()[0].split(",")
    assert {"settled", "periods_run", "settle_change", "periodicity"} <= set(header)
    # explicit periods: honoured, and whether each speed settled reported
    main(
        [
            *argv,
            "--periods",
            "6",
            "--keep-periods",
            "2",
            "--out",
            str(tmp_path / "fixed"),
            "--quiet",
        ]
    )
    f = json.loads((tmp_path / "fixed" / "sweep.json").read_text())
    assert f["periods"] == 6 and f["periods_run"] == [6, 6]
    assert f["settled"] == [p <= 1e-2 for p in f["periodicity"]]


def test_a_speed_at_its_cap_unsettled_gets_one_line_naming_it_and_the_option():
    from types import SimpleNamespace

    s = jd.SettledSweep(
        sweep=SimpleNamespace(speeds=np.array([300.0, 600.0, 900.0])),
        periods=np.array([8, 40, 12]),
        change=np.array([0.004, 0.031, np.nan]),  # the third failed (its result code says so)
        settled=np.array([True, False, False]),
        cap=np.array([16, 40, 48]),
        settle_s=0.01,
        f_min_Hz=100.0,
        window=4,
        keep=4,
    )
    (line,) = jd.unsettled_lines(s)
    assert line.startswith("speed 600 rad/s: not settled after 40 mesh periods")
    assert "0.031" in line and "--periods 80" in line and "[scene.integration] periods" in line


@pytest.mark.slow
def test_two_stage_settled_dynamic_factor_agrees_with_a_run_four_times_longer():
    # the embedded two-stage train (its meshes repeat together every 127 periods of the first:
    # one window = 127 periods), coarse (2 slices, 35 steps per HST period: a whole 127 per LST
    # period), at three of jaxgear run's top speeds, where its settling time is longest
    case = jio.load_case("two-stage").replace(slices=2)
    model = build_dynamic_model(case)[0]
    law = case.contact_law("exact")
    speeds = np.array([2800.0, 2900.0, 3000.0])
    s = jd.settled_sweep(model, speeds, integrator=Newmark(35), contact=law, keep_periods=127)
    assert s.window == 127 and s.settled.all() and (s.change <= 1e-2).all()
    # every speed from the static equilibrium for four times the most periods a speed ran, or
    # longer where the rule asks more: the long runs are settled by the rule (t_s f_mesh
    # periods, f_mesh = Ω z1 / 2π, the input's 28 teeth, decay the transient to 1e-3), their
    # kept window starting after it (the lead and the windows' modal estimate let the settled
    # sweep run fewer periods than a quarter of that)
    rule = math.ceil((s.settle_s * speeds * 28 / (2 * math.pi)).max())
    span = max(4 * int(s.periods.max()), 127 * -(-(rule + 127) // 127))
    long = jd.speed_sweep(
        model,
        speeds,
        integrator=Newmark(35),
        contact=law,
        window=SteadyState(span, 127),
    ).results
    assert span - 127 >= rule
    for settled, reference in zip(s.sweep.results.meshes, long.meshes, strict=True):
        df, ref = np.asarray(settled.dynamic_factor), np.asarray(reference.dynamic_factor)
        np.testing.assert_allclose(df, ref, atol=1e-2, rtol=0)


@pytest.mark.slow
def test_a_run_split_at_a_mesh_position_follows_the_unsplit_run():
    # simulate(start_period=p) from the state a run ends in at mesh position p continues that
    # run: p + 2 × 127 periods in one run (the reference) against p + 127 (ending at position
    # p of the 127-period scene), then 127 from position p, on a train whose meshes repeat
    # together only after 127 periods (two-stage, coarse)
    case = jio.load_case("two-stage").replace(slices=2)
    model = build_dynamic_model(case)[0]
    law = case.contact_law("exact")
    speed, p, k = 1500.0, 5, 127
    kw = {"integrator": Newmark(35), "contact": law}
    whole = jd.simulate(model, speed, window=SteadyState(p + 2 * k, k), **kw)
    first = jd.simulate(model, speed, window=SteadyState(p + k, k), **kw)
    rest = jd.simulate(
        model,
        speed,
        window=SteadyState(k, k),
        state0=first.final_state[:2],
        start_period=p,
        **kw,
    )
    scale = float(np.max(np.abs(np.asarray(whole.final_state[0]))))
    np.testing.assert_allclose(rest.final_state[0], whole.final_state[0], rtol=0, atol=1e-9 * scale)
    for a, b in zip(rest.meshes, whole.meshes, strict=True):
        f_s = float(b.static_force)
        np.testing.assert_allclose(a.mesh_force, b.mesh_force, rtol=0, atol=1e-9 * f_s)
    np.testing.assert_allclose(rest.theta, whole.theta, rtol=1e-12)
    # and started at position 0 instead, the same state is off the run (the position matters)
    off = jd.simulate(model, speed, window=SteadyState(k, k), state0=first.final_state[:2], **kw)
    assert float(np.max(np.abs(np.asarray(off.final_state[0]) - whole.final_state[0]))) > (
        1e-6 * scale
    )
    # from the static start (no state0) or a negative position: refused before any work
    with pytest.raises(ValueError, match="start_period"):
        jd.simulate(model, speed, window=SteadyState(k, k), start_period=3, **kw)
    with pytest.raises(ValueError, match="start_period"):
        jd.simulate(
            model,
            speed,
            window=SteadyState(k, k),
            **kw,
            state0=first.final_state[:2],
            start_period=-1,
        )


@pytest.mark.slow
def test_the_default_case_settles_through_its_shaft_mode_resonance():
    # jaxgear run's sweep of the embedded default case (README's first command, 8 slices as
    # jaxgear run's sweep), its first six
    # speeds: at 296.6 rad/s the mesh frequency (2124 Hz) drives its 1933 Hz shaft mode (3.8 %
    # of its strain energy in the mesh, ξ 1.2 %), which decays 18 times slower than the mesh
    # mode that sets the rule; the speed settles within its cap (it reached a cap of 20 periods
    # unsettled, 0.04 of the static force, when the cap counted only the rule's modes) and
    # every dynamic factor agrees with an independent run of 200 periods from rest (settled:
    # its last two kept periods agree to 1e-7 of the static force)
    case = jio.load_case("accessory-spur")
    model = build_dynamic_model(case, slices=8)[0]
    law = case.contact_law("exact")
    speeds = np.linspace(100.0, 3000.0, 60)[:6]
    s = jd.settled_sweep(model, speeds, contact=law)
    assert s.settled.all() and (s.change <= 1e-2).all() and (s.periods <= s.cap).all()
    long = jd.speed_sweep(model, speeds, contact=law, window=SteadyState(200, 4)).results
    assert float(np.max(np.asarray(long.periodicity))) < 1e-6
    df = np.asarray(s.sweep.results.dynamic_factor)
    np.testing.assert_allclose(df, np.asarray(long.dynamic_factor), atol=1e-2, rtol=0)
