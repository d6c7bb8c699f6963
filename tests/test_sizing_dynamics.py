"""The dynamics stage of a sizing (jaxgear.sizing.dynamics_stage, jaxgear size --dynamics): a
candidate's dynamic factor curve, its columns and its whine equal the library's dynamics run on
its written case file as ``jaxgear sweep`` runs it (the case reader's model, the settled sweep,
the harmonic balance) to 1e-9; the resonance speed lies within the speed grid's step of the
torsional pair's natural frequency sqrt(k̄/m_eq) written here (disc inertias, the quasi-static
mean mesh stiffness); the candidates come from the first fronts (a brute-force domination
written here); objectives without their stage and bad keys are refused in one line; the
command writes the columns and curves. One small spec, two candidates, 14 speeds: one compiled
program of each kind (model, sweep, whine) serves every test here."""

from __future__ import annotations

import copy
import csv
import json
import math
import tomllib

import numpy as np
import pytest
from test_sizing import _refused, _spec as _small_spec, _toml

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.sizing as js
from jaxgear import dynamics
from jaxgear.cli import main

RPM = math.pi / 30

# the small helical reducer of tests/test_sizing.py narrowed to one module and three pinions
# (8 feasible candidates), no transmission-error stage, two candidates of the dynamics stage
# over few speeds; the front over the mass, the largest dynamic factor and the margin
SPEC = _small_spec(normal_module_min_mm=2.5, normal_module_max_mm=2.5, z1_min=18, z1_max=20,
                   te_candidates=0, dynamics_candidates=2, dynamics_speeds=13)
SPEC["name"] = "small-dynamics"
SPEC["pareto"] = {"minimise": ["mass_kg", "dynamic_factor_max"], "maximise": ["least_margin"]}


def _spec(**sizing):
    data = copy.deepcopy(SPEC)
    data["sizing"].update(sizing)
    return data


def _natural_speed(spec, row) -> float:
    """The pinion speed (rad/s) whose mesh frequency is the torsional pair's natural frequency
    ω_n = sqrt(k̄ / m_eq), written here: m_eq = 1/(cos²β_b (r_b1²/I_1 + r_b2²/I_2)), I = ρ π
    b r_a⁴/2 (solid discs of the tip radius), k̄ the mean over a mesh period of the loaded
    mesh stiffness of the quasi-static solve at the rated torque (flank-normal, N/m);
    Ω = ω_n / z1."""
    pair = js.candidate_pair(spec, row)
    mesh = js.candidate_mesh(spec, pair)
    qs = jg.quasi_static(mesh, None, float(spec.operating.torque), positions_per_pitch=16,
                         periods=2)
    k = float(np.mean(np.asarray(qs.mesh_stiffness)))
    rho = float(spec.settings.material.density)
    inertia = [rho * math.pi * m.face_width * r**4 / 2
               for m, r in zip((pair.pinion, pair.gear), pair.tip_radii, strict=True)]
    cb = math.cos(float(pair.base_helix_angle))
    rb = pair.base_radii
    omega = math.sqrt(k * cb**2 * (rb[0] ** 2 / inertia[0] + rb[1] ** 2 / inertia[1]))
    return omega / int(row["z1"])


@pytest.fixture(scope="module")
def staged():
    """The stage over a range around the first candidate's natural speed (0.72 to 1.32 of it,
    13 speeds: steps of 5 %, none on it), the spec's speed added."""
    spec, tables = jio.parse_sizing_spec(_spec())
    table = js.size(spec)
    first = int(js.dynamics_selection(spec, table, 2)[0])
    natural = _natural_speed(spec, {n: v[first] for n, v in table.columns.items()})
    data = _spec(dynamics_speed_range_rpm=[0.72 * natural / RPM, 1.32 * natural / RPM])
    spec, tables = jio.parse_sizing_spec(data)
    settings = jio.sizing_dynamics_settings(tables)
    staged, curves = js.dynamics_stage(spec, table, settings)
    return data, spec, tables, staged, curves, natural


def test_columns_equal_the_sweep_of_the_written_case(staged):
    """Each candidate run, its written case file (``jaxgear size --write``) built by the case
    reader (jio.build_dynamic_model: the case's [scene] defaults) and swept as ``jaxgear
    sweep`` sweeps it (dynamics.settled_sweep with the case's integrator, contact law and kept
    periods) at the stage's speeds: its K_v equals the curve and the columns to 1e-9; its
    whine (dynamics.whine_response, the mesh force's orders 1-3 summed here) the whine
    column, the speed of its largest first order the resonance speed."""
    _, spec, tables, table, curves, _ = staged
    c = table.columns
    assert curves.rows.size == 2 and curves.flanks == ("plain", "plain")
    speed = float(spec.operating.speed)
    at = np.flatnonzero(np.abs(curves.speeds - speed) <= 1e-12 * speed)
    assert at.size == 1 and curves.speeds.size == 14 and np.all(np.diff(curves.speeds) > 0)
    close = lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-9, atol=0)
    for j, k in enumerate(curves.rows):
        row = {n: v[k] for n, v in c.items()}
        case = jio.parse_case(tomllib.loads(jio.candidate_case_text(tables, spec, row, k)))
        model, scene = jio.build_dynamic_model(case)
        run = dynamics.settled_sweep(model, curves.speeds,
                                     integrator=jio.spec_integrator(scene),
                                     contact=case.contact_law(scene.contact),
                                     keep_periods=scene.keep_periods)
        kv = np.asarray(run.sweep.results.dynamic_factor)
        assert np.all(np.asarray(run.sweep.results.result) == 0) and np.all(run.settled)
        close(curves.dynamic_factor[j], kv)
        close(c["dynamic_factor_max"][k], kv.max())
        close(c["dynamic_factor_at_speed"][k], kv[at[0]])
        force = np.abs(np.asarray(dynamics.whine_response(model, curves.speeds).mesh_force))
        rms = np.sqrt(sum(force[:, h, 0] ** 2 / 2 for h in (1, 2, 3)))
        close(curves.whine_force[j], rms)
        close(curves.first_order[j], force[:, 1, 0])
        close(c["whine_force_N"][k], rms.max())
        close(c["resonance_speed_rad_s"][k], curves.speeds[np.argmax(force[:, 1, 0])])
        assert c["dynamics_stage"][k] == "plain" and c["dynamics_unsettled"][k] == 0
        assert 1.0 < kv.max() < 1.5  # a quiet helical pair: a few per cent at resonance
    rest = np.setdiff1d(np.arange(len(table)), curves.rows)
    assert np.all(c["dynamics_stage"][rest] == "none")
    assert np.all(np.isnan(c["dynamic_factor_max"][rest]))


def test_the_resonance_speed_is_the_pairs_natural_frequency(staged):
    """The resonance speed of the first candidate (the one the range was set around: the speed
    of its largest first-order dynamic mesh force) lies within one step of the speed grid
    (5 %) of ω_n/z1, ω_n = sqrt(k̄/m_eq) written here, and so does the speed of its largest
    K_v; the second candidate's (another pair, its resonance inside the range too) within a
    step of its own."""
    _, spec, _, table, curves, natural = staged
    c = table.columns
    step = curves.speeds[-1] - curves.speeds[-2]
    k0, k1 = (int(i) for i in curves.rows)
    assert abs(c["resonance_speed_rad_s"][k0] - natural) <= step
    assert abs(curves.speeds[np.argmax(curves.dynamic_factor[0])] - natural) <= step
    second = _natural_speed(spec, {n: v[k1] for n, v in c.items()})
    assert curves.speeds[1] + step <= second <= curves.speeds[-1] - step
    assert abs(second - natural) > step  # a resonance of its own
    assert abs(c["resonance_speed_rad_s"][k1] - second) <= step


def _dominates(a, b) -> bool:
    return bool(np.all(a <= b) and np.any(a < b))


def test_the_candidates_come_from_the_first_fronts(staged):
    """dynamics_selection: over the spec's objectives less the stage's (here the mass and the
    least margin), written here by brute force: n = 1 the front's knee (pareto_front's
    chosen design), n = 2 the knee and the lightest other of front 1, n = 3 the knee and the
    two ends of the rest of front 1 along the mass, n = |front 1| + 1 front 1 and one of
    front 2 (dominated by front 1 only)."""
    _, spec, _, table, curves, _ = staged
    c = table.columns
    rows = np.flatnonzero(table.feasible)
    v = np.stack([c["mass_kg"][rows], -c["least_margin"][rows]], axis=1)
    first = [r for i, r in enumerate(rows) if not any(_dominates(v[j], v[i])
                                                      for j in range(rows.size))]
    second = [r for i, r in enumerate(rows) if r not in first and not any(
        _dominates(v[j], v[i]) for j in range(rows.size) if rows[j] not in first)]
    assert 4 <= len(first) < rows.size and second
    knee = js.pareto_front(table, (("mass_kg", "min"), ("least_margin", "max"))).chosen
    assert js.dynamics_selection(spec, table, 1).tolist() == [knee]
    ends = sorted((r for r in first if r != knee), key=lambda r: c["mass_kg"][r])
    assert curves.rows.tolist() == [knee, ends[0]]
    assert js.dynamics_selection(spec, table, 3).tolist() == [knee, ends[0], ends[-1]]
    got = js.dynamics_selection(spec, table, len(first) + 1).tolist()
    assert sorted(got[:-1]) == sorted(first) and got[-1] in second
    assert js.dynamics_selection(spec, table, 0).size == 0


def test_the_stage_off_adds_empty_columns(staged):
    """With no candidates the stage runs nothing: its columns NaN, ``dynamics_stage`` "none",
    no curves and no speeds."""
    _, spec, _, table, _, _ = staged
    off, curves = js.dynamics_stage(spec, table, js.DynamicsSettings(candidates=0))
    assert curves.rows.size == 0 and curves.speeds.size == 0
    assert set(off.columns["dynamics_stage"]) == {"none"}
    for name in js.DYNAMICS_COLUMNS:
        assert np.all(np.isnan(off.columns[name]))


BAD = [
    ({"dynamics_candidates": -1}, "[sizing] dynamics_candidates = -1: out of range"),
    ({"dynamics_candidates": 1.5}, "[sizing] dynamics_candidates = 1.5:"),
    ({"dynamics_speeds": 1}, "[sizing] dynamics_speeds = 1: out of range"),
    ({"dynamics_speeds": 401}, "[sizing] dynamics_speeds = 401: out of range"),
    ({"dynamics_speed_range_rpm": [0.0, 100.0]}, "[sizing] dynamics_speed_range_rpm"),
    ({"dynamics_speed_range_rpm": [3000.0, 1000.0]},
     ("[sizing] dynamics_speed_range_rpm = [3000, 1000]: out of range, allowed [lo, hi] with "
      "lo < hi")),
    ({"dynamics_speed_range_rpm": [1000.0, 2000.0, 3000.0]}, "[sizing] dynamics_speed_range_rpm"),
    ({"dynamics_candidates": 0},
     ("[pareto] minimise = ['mass_kg', 'dynamic_factor_max']: 'dynamic_factor_max' is a "
      "column of the dynamics stage, which [sizing] dynamics_candidates = 0 turns off")),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_stage_keys_are_refused_in_one_line(change, message):
    _refused(_spec(**change), message)


def test_an_objective_without_its_stage_is_refused_in_one_line():
    """A front over a stage's column with that stage off would be empty (its column NaN for
    every candidate): refused at load, the transmission-error stage's as the dynamics
    stage's."""
    data = _spec(te_candidates=0)
    data["pareto"] = {"minimise": ["te_ppk_m"], "maximise": ["least_margin"]}
    _refused(data, "[pareto] minimise = ['te_ppk_m']: 'te_ppk_m' is a column of the "
                   "transmission-error stage, which [sizing] te_candidates = 0 turns off")
    data["pareto"] = {"minimise": ["mass_kg"], "maximise": ["whine_force_N"]}
    data["sizing"]["dynamics_candidates"] = 0
    with pytest.raises(ValueError, match=r"^\[pareto\] maximise = \['whine_force_N'\]: "):
        jio.parse_sizing_spec(data)
    data["sizing"]["te_candidates"] = 1  # either stage on: accepted
    data["sizing"]["dynamics_candidates"] = 1
    data["pareto"] = {"minimise": ["te_ppk_m", "whine_force_N"]}
    jio.parse_sizing_spec(data)


@pytest.mark.parametrize("kwargs,message", [
    ({"candidates": -2}, "DynamicsSettings: candidates = -2 is out of range"),
    ({"speed_range": (10.0, 5.0)}, "DynamicsSettings: speed_range = (10.0, 5.0) is out of"),
    ({"speed_range": (0.0, 5.0)}, "DynamicsSettings: speed_range = (0.0, 5.0) is out of"),
    ({"speeds": 1}, "DynamicsSettings: speeds = 1 is out of range"),
])
def test_bad_settings_are_refused_in_one_line(kwargs, message):
    with pytest.raises(ValueError) as err:
        js.DynamicsSettings(**kwargs)
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


def test_the_settings_and_the_default_range(staged):
    """The spec's keys as settings (the range in rad/s); without a range, the default runs
    from half the lower of the spec's speed and the candidates' mesh resonance speeds (the
    speed whose mesh frequency is the mode's natural frequency, the model's own modes) to 1.5
    times the higher, with the spec's speed added."""
    data, spec, tables, table, curves, _ = staged
    s = jio.sizing_dynamics_settings(tables)
    lo, hi = data["sizing"]["dynamics_speed_range_rpm"]
    assert s.candidates == 2 and s.speeds == 13
    np.testing.assert_allclose(s.speed_range, (lo * RPM, hi * RPM), rtol=1e-15)
    assert jio.sizing_dynamics_settings(tables, 0).candidates == 0
    base = copy.deepcopy(data)
    for key in ("dynamics_candidates", "dynamics_speeds", "dynamics_speed_range_rpm"):
        del base["sizing"][key]
    assert jio.sizing_dynamics_settings(jio.parse_sizing_spec(base)[1]) == js.DynamicsSettings()
    models = [js.candidate_dynamic_model(spec, {n: v[k] for n, v in table.columns.items()})
              for k in curves.rows]
    res = [float(m.modes.omega[1]) / int(table.columns["z1"][k])
           for m, k in zip(models, curves.rows, strict=True)]
    speed = float(spec.operating.speed)
    grid = js.dynamics_speeds(spec, js.DynamicsSettings(speeds=5), models)
    want = np.sort(np.append(np.linspace(0.5 * speed, 1.5 * max(res), 5), speed))
    np.testing.assert_allclose(grid, want, rtol=1e-12)


def test_jaxgear_size_runs_the_stage(staged, tmp_path, capsys, monkeypatch):
    """``jaxgear size`` with the fixture's spec (the same compiled programs): the stage's
    columns in sizing.csv and sizing.parquet, its curves in dynamics.csv and its summary in
    sizing.json equal the fixture's; the front over the stage's objective ranks only the
    candidates it ran; ``--dynamics 0`` with that objective, ``--te 0`` with a TE objective
    and ``--dynamics -1`` are refused in one line before any work."""
    import pyarrow.parquet as pq

    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")  # the figure: looked at, not read
    data, _, _, table, curves, _ = staged
    path = tmp_path / "small.toml"
    path.write_text(_toml(data))
    out = tmp_path / "out"
    assert main(["size", str(path), "--out", str(out), "--quiet"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    c = table.columns
    for k in curves.rows:
        for name in js.DYNAMICS_COLUMNS:
            assert float(rows[k][name]) == c[name][k]
    assert [r["dynamics_stage"] for r in rows] == list(c["dynamics_stage"])
    got = pq.read_table(out / "sizing.parquet").to_pydict()
    np.testing.assert_array_equal(got["dynamic_factor_max"], c["dynamic_factor_max"])
    ranked = [i for i, r in enumerate(rows) if int(r["pareto_rank"]) > 0]
    assert sorted(ranked) == sorted(curves.rows.tolist())
    with open(out / "dynamics.csv", encoding="utf-8") as f:
        lines = list(csv.DictReader(f))
    assert len(lines) == curves.rows.size * curves.speeds.size
    kv = np.asarray([float(r["dynamic_factor"]) for r in lines])
    kv = kv.reshape(curves.dynamic_factor.shape)
    np.testing.assert_array_equal(kv, curves.dynamic_factor)
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    assert summary["dynamics_stage"]["candidates"] == curves.rows.tolist()
    assert summary["dynamics_stage"]["speeds_rad_s"] == curves.speeds.tolist()
    for argv, message in (
            (["--dynamics", "0"], ("--dynamics 0: the spec's objective 'dynamic_factor_max' is "
                                   "a column of the dynamics stage, which this turns off")),
            (["--dynamics", "-1"], "--dynamics -1: out of range, allowed an integer >= 0")):
        assert main(["size", str(path), "--out", str(tmp_path / "o2"), *argv]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and message in err[0], err
        assert not (tmp_path / "o2").exists()
    te = copy.deepcopy(data)
    te["sizing"]["te_candidates"] = 1
    te["pareto"] = {"minimise": ["te_ppk_m", "mass_kg"]}
    path.write_text(_toml(te))
    assert main(["size", str(path), "--out", str(tmp_path / "o3"), "--te", "0"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--te 0: the spec's objective 'te_ppk_m' is a column of the " \
        "transmission-error stage" in err[0]
    assert not (tmp_path / "o3").exists()


# default tier: test_columns_equal_the_sweep_of_the_written_case (the written case's model and
# sweep as jaxgear sweep makes them, without the command's other outputs; plain flanks)
@pytest.mark.slow
def test_jaxgear_sweep_on_the_written_modified_case_gives_the_curve(tmp_path, monkeypatch):
    """With the transmission-error stage on (one candidate, a short optimisation) and the front
    over its optimised TE and the mass, the dynamics stage runs that candidate with the
    optimised flanks; ``jaxgear size --write K`` writes ``candidate_K_modified.toml``, and
    ``jaxgear sweep`` on it over the stage's speeds (a range starting at the spec's speed: the
    grid is the START:STOP:N that ``--speeds`` takes) gives sweep.json's dynamic factor equal
    to dynamics.csv's and the row's largest to 1e-9."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
    data = _spec(te_candidates=1, te_torque_min_percent=50.0, te_torques=2,
                 te_max_iterations=20, dynamics_candidates=1, dynamics_speeds=6,
                 dynamics_speed_range_rpm=[1500.0, 30000.0])
    data["pareto"] = {"minimise": ["te_ppk_modified_m", "mass_kg"]}
    spec, _ = jio.parse_sizing_spec(data)
    k = int(js.size(spec).ranked()[0])  # the one the TE stage evaluates
    path = tmp_path / "spec.toml"
    path.write_text(_toml(data))
    out = tmp_path / "size"
    assert main(["size", str(path), "--out", str(out), "--write", str(k), "--quiet"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        row = list(csv.DictReader(f))[k]
    assert row["stage"] == "te" and row["dynamics_stage"] == "modified"
    with open(out / "dynamics.csv", encoding="utf-8") as f:
        lines = list(csv.DictReader(f))
    assert {int(r["candidate"]) for r in lines} == {k}
    speeds = [float(r["speed_rad_s"]) for r in lines]
    lo, hi = 1500.0 * RPM, 30000.0 * RPM
    np.testing.assert_array_equal(speeds, np.linspace(lo, hi, 6))
    sweep = tmp_path / "sweep"
    assert main(["sweep", str(out / f"candidate_{k}_modified.toml"), "--speeds",
                 f"{lo!r}:{hi!r}:6", "--out", str(sweep), "--quiet"]) == 0
    s = json.loads((sweep / "sweep.json").read_text(encoding="utf-8"))
    np.testing.assert_allclose(s["speeds_rad_s"], speeds, rtol=1e-15)
    kv = np.asarray([float(r["dynamic_factor"]) for r in lines])
    np.testing.assert_allclose(s["dynamic_factor"], kv, rtol=1e-9)
    np.testing.assert_allclose(max(s["dynamic_factor"]), float(row["dynamic_factor_max"]),
                               rtol=1e-9)
