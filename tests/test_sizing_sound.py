"""The sound stage of a sizing (a spec's ``[sound]``, jaxgear size --sound): each candidate's
housed case (its shafts, bearings and box housing) follows the layout rule written here from
ISO 21771's centre distance, tip and root diameters; the stage's ERP peak and its curve equal
``jaxgear run`` of the written housed case (slow tier: the housing is meshed and condensed per
candidate); a spec without ``[sound]`` writes what it wrote before; bad keys and options are
refused in one line."""

from __future__ import annotations

import copy
import csv
import json
import math
import tomllib

import numpy as np
import pytest
from test_sizing import _refused, _spec as _small_spec, _toml

import jaxgear.io as jio
import jaxgear.sizing as js
from jaxgear.cli import main

RPM = math.pi / 30

# the small helical reducer of tests/test_sizing.py narrowed to one module and three pinions (as
# tests/test_sizing_dynamics.py), no transmission-error or dynamics stage; [sound]: one
# candidate, 12 speeds, the coarse default mesh (40 mm), some keys away from their defaults
SPEC = _small_spec(normal_module_min_mm=2.5, normal_module_max_mm=2.5, z1_min=18, z1_max=20,
                   te_candidates=0, dynamics_candidates=0)
SPEC["name"] = "small-sound"
SOUND = {"candidates": 1, "speed_range_rpm": [500.0, 3000.0], "speeds": 12,
         "tip_clearance_mm": 8.0, "wall_thickness_mm": 10.0, "bearing_margin_mm": 15.0,
         "bearing_radial_N_per_um": 400.0, "bearing_axial_N_per_um": 150.0}


def _spec(**sound):
    data = copy.deepcopy(SPEC)
    data["sound"] = copy.deepcopy(SOUND) | sound
    return data


def _involute(a: float) -> float:
    return math.tan(a) - a


def _hand_geometry(data, row) -> dict:
    """ISO 21771 for the row's pair, written here (m): the transverse pressure angle
    tan α_t = tan α_n / cos β, the reference diameters d = z m_n / cos β, the working pressure
    angle inv α_wt = inv α_t + 2 tan α_n (x1 + x2)/(z1 + z2) (bisection), the centre distance
    a = (d1 + d2)/2 cos α_t / cos α_wt, the tip diameters d_a = d + 2 m_n (h_a* + x) and root
    diameters d_f = d − 2 m_n (h_f* − x) (the spec's rack: 1 and 1.25, the defaults)."""
    s = data["sizing"]
    mn, beta = float(row["normal_module_m"]), math.radians(s["helix_angle_deg"])
    an = math.radians(s.get("normal_pressure_angle_deg", 20.0))
    z = (int(row["z1"]), int(row["z2"]))
    x = (float(row["x1"]), float(row["x2"]))
    at = math.atan(math.tan(an) / math.cos(beta))
    d = [zi * mn / math.cos(beta) for zi in z]
    target = _involute(at) + 2 * math.tan(an) * sum(x) / sum(z)
    lo, hi = 1e-6, 1.5
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _involute(mid) < target else (lo, mid)
    awt = 0.5 * (lo + hi)
    return {"a": 0.5 * sum(d) * math.cos(at) / math.cos(awt),
            "da": [di + 2 * mn * (1.0 + xi) for di, xi in zip(d, x, strict=True)],
            "df": [di - 2 * mn * (1.25 - xi) for di, xi in zip(d, x, strict=True)]}


@pytest.fixture(scope="module")
def sized():
    data = _spec()
    spec, tables = jio.parse_sizing_spec(data)
    return data, spec, tables, js.size(spec)


def _row(table, k):
    return {n: v[k] for n, v in table.columns.items()}


def test_the_housed_case_follows_the_layout_rule(sized, tmp_path):
    """The housed case of the first feasible candidate: its own case file first, then a lumped
    3D scene on two equal shafts of length b + 4 margin (gear at the middle, bearings a margin
    in from each end, the pinion's torque at its start, the wheel's at its end), each shaft's
    diameter half the pinion's root diameter (the default) or the given one, the box round the
    tip circles (width a + (d_a1 + d_a2)/2 + 2 (c + t), height max d_a + 2 (c + t)), the cut-off
    key the order-1 mesh frequency z1 Ω_max / 2π at the top speed, the whine over the speeds;
    with the transmission-error stage's flanks (a row of stage "te") its modifications too."""
    data, spec, tables, table = sized
    k = int(np.flatnonzero(table.feasible)[0])
    row = _row(table, k)
    section, n = jio.sizing_sound(tables)
    assert n == 1
    text = jio.housed_case_text(tables, spec, row, k, section)
    assert text.startswith(jio.candidate_case_text(tables, spec, row, k))
    case = tomllib.loads(text)
    g = _hand_geometry(data, row)
    s = data["sound"]
    c, t, m = s["tip_clearance_mm"], s["wall_thickness_mm"], s["bearing_margin_mm"]
    b = case["pinion"]["face_width_mm"]
    h = case["housing"]
    assert h["width_mm"] == pytest.approx(
        g["a"] * 1e3 + (g["da"][0] + g["da"][1]) / 2 * 1e3 + 2 * (c + t), rel=1e-12)
    assert h["height_mm"] == pytest.approx(max(g["da"]) * 1e3 + 2 * (c + t), rel=1e-12)
    assert h["wall_thickness_mm"] == t and h["mesh_size_mm"] == 40.0
    assert (h["youngs_modulus_GPa"], h["poisson_ratio"], h["density_kg_m3"],
            h["loss_factor"]) == (70.0, 0.33, 2700.0, 0.02)
    top = row["z1"] * s["speed_range_rpm"][1] * RPM / (2 * math.pi)
    assert h["highest_mesh_frequency_Hz"] == pytest.approx(top, rel=2e-9)
    assert h["highest_mesh_frequency_Hz"] > top  # kept in the band through round-off
    sc = case["scene"]
    assert sc["model"] == "lumped3d"
    for name, torque in (("pinion_shaft", 0.0), ("gear_shaft", b + 4 * m)):
        shaft = sc[name]
        assert shaft["length_mm"] == pytest.approx(b + 4 * m, rel=1e-12)
        assert shaft["gear_position_mm"] == pytest.approx((b + 4 * m) / 2, rel=1e-12)
        assert shaft["torque_position_mm"] == pytest.approx(torque, rel=1e-12)
        assert shaft["diameter_mm"] == pytest.approx(0.5 * g["df"][0] * 1e3, rel=1e-12)
        first, second = shaft["bearings"]
        assert first["position_mm"] == pytest.approx(m, rel=1e-12)
        assert second["position_mm"] == pytest.approx(b + 3 * m, rel=1e-12)
        assert (first["radial_N_per_um"], first["axial_N_per_um"]) == (400.0, 150.0)
        assert second["radial_N_per_um"] == 400.0 and "axial_N_per_um" not in second
    w = case["whine"]
    assert w["speed_min_rad_s"] == pytest.approx(500 * RPM, rel=1e-15)
    assert w["speed_max_rad_s"] == pytest.approx(3000 * RPM, rel=1e-15)
    assert (w["speeds"], w["harmonics"]) == (12, 8)
    assert "modifications" not in case
    # a given shaft diameter; a row the transmission-error stage optimised: its flanks; a
    # margin of many digits (the wheel's torque at its shaft's end, a length of 12 digits)
    section = jio.SoundSection.read(s | {"shaft_diameter_mm": 30.0,
                                         "bearing_margin_mm": 15.123456789}, "sound")
    te = row | {"stage": "te", "tip_relief_depth_m": 8e-6, "tip_relief_extent": 0.25,
                "crowning_depth_m": 4e-6}
    case = tomllib.loads(jio.housed_case_text(tables, spec, te, k, section))
    assert case["scene"]["gear_shaft"]["diameter_mm"] == 30.0
    shaft = case["scene"]["gear_shaft"]
    assert shaft["torque_position_mm"] == shaft["length_mm"] == pytest.approx(b + 4 * 15.123456789)
    jio.parse_case(case, str(tmp_path))  # the case reader takes it (jaxgear run's)
    # a length whose 6-digit words round below it (100.0000004 → "100"), the torque at its end
    shaft.update(length_mm=100.0000004, torque_position_mm=100.0000004)
    jio.parse_case(case, str(tmp_path))
    shaft["torque_position_mm"] = 100.00001
    with pytest.raises(ValueError, match=r"^\[scene.gear_shaft\] torque_position_mm = 100: out "
                       r"of range, allowed \[0, 100\]"):
        jio.parse_case(case, str(tmp_path))
    assert case["modifications"]["tip_relief"] == {"depth_um": 8.0, "extent": 0.25}
    assert case["modifications"]["crowning"] == {"depth_um": 4.0}


BAD = [
    ({"speeds": 1}, "[sound] speeds = 1: out of range, allowed [2, 400]"),
    ({"speed_range_rpm": [3000.0, 500.0]},
     "[sound] speed_range_rpm = [3000, 500]: out of range, allowed [lo, hi] with lo < hi"),
    ({"speed_range_rpm": [500.0, 2e6]}, "[sound] speed_range_rpm"),
    ({"tip_clearance_mm": 0.0}, "[sound] tip_clearance_mm = 0: out of range, allowed [1, 1000]"),
    ({"wall_thickness_mm": 250.0}, "[sound] wall_thickness_mm = 250: out of range"),
    ({"shaft_diameter_ratio": 0.8},
     "[sound] shaft_diameter_ratio = 0.8: out of range, allowed (0, 0.6]"),
    ({"shaft_diameter_ratio": 0.4, "shaft_diameter_mm": 30.0},
     "[sound] shaft_diameter_mm = 30: give one of shaft_diameter_ratio and shaft_diameter_mm"),
    ({"bearing_margin_mm": 4.0},
     "[sound] bearing_margin_mm = 4: out of range, allowed >= wall_thickness_mm / 2 = 5"),
    ({"bearing_radial_N_per_um": 0.0}, "[sound] bearing_radial_N_per_um = 0: out of range"),
    ({"candidates": 101}, "[sound] candidates = 101: out of range, allowed [0, 100]"),
    ({"poisson_ratio": 0.5}, "[sound] poisson_ratio = 0.5: out of range, allowed [0, 0.5)"),
    ({"loss": 0.1}, "[sound] unknown key 'loss'"),
    # the radiated sound power's keys: [acoustics]'s names and checks under [sound.acoustics]
    ({"sound_power": 1}, "[sound] sound_power = 1: must be true or false"),
    ({"acoustics": {"frequencies": 4}},
     "[sound] sound_power = false: [sound.acoustics] is read only with sound_power = true"),
    ({"sound_power": True, "acoustics": {"frequencies": 0}},
     "[sound.acoustics] frequencies = 0: out of range, allowed [1, 2000]"),
    ({"sound_power": True, "acoustics": {"rank": 0}},
     "[sound.acoustics] rank = 0: out of range, allowed [1, 1e+06]"),
    ({"sound_power": True, "acoustics": {"method": "rayleigh"}},
     "[sound.acoustics] method = 'rayleigh': allowed 'bem', 'erp-only'"),
    ({"sound_power": True, "acoustics": {"sound_speed_m_s": 0.0}},
     "[sound.acoustics] sound_speed_m_s = 0: out of range, allowed (0, 100000]"),
    ({"sound_power": True, "acoustics": {"band_Hz": [100.0, 2000.0]}},
     "[sound.acoustics] band_Hz = [100, 2000]: not in a sizing (the grid spans each "
     "candidate's own orders)"),
    ({"sound_power": True, "acoustics": {"microphones": [{"position_mm": [0.0, 0.0, 900.0]}]}},
     "[sound.acoustics] microphones = ['mic0']: not in a sizing"),
    ({"sound_power": True, "acoustics": {"fluid": "air"}},
     "[sound.acoustics] unknown key 'fluid'"),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_sound_keys_are_refused_in_one_line(change, message):
    _refused(_spec(**change), message)


def test_a_missing_range_and_an_objective_without_the_stage_are_refused():
    data = _spec()
    del data["sound"]["speed_range_rpm"]
    _refused(data, "[sound] speed_range_rpm")
    data = copy.deepcopy(SPEC)
    data["pareto"] = {"minimise": ["mass_kg", "erp_peak_dB"]}
    _refused(data, "[pareto] minimise = ['mass_kg', 'erp_peak_dB']: 'erp_peak_dB' is a column "
                   "of the sound stage, which runs only with a [sound] table")
    data = _spec(candidates=0)
    data["pareto"] = {"minimise": ["mass_kg", "erp_peak_dB"]}
    _refused(data, "[pareto] minimise = ['mass_kg', 'erp_peak_dB']: 'erp_peak_dB' is a column "
                   "of the sound stage, which [sound] candidates = 0 turns off")
    data["sound"]["candidates"] = 1  # the stage on: accepted
    jio.parse_sizing_spec(data)
    data["pareto"] = {"minimise": ["mass_kg", "sound_power_peak_dB"]}
    _refused(data, "[pareto] minimise = ['mass_kg', 'sound_power_peak_dB']: "
                   "'sound_power_peak_dB' is the sound stage's radiated sound power, which "
                   "[sound] sound_power = true turns on")
    data["sound"]["sound_power"] = True  # the sound power on: accepted
    jio.parse_sizing_spec(data)


def test_the_housed_case_holds_the_sound_powers_acoustics(sized, tmp_path):
    """With ``sound_power = true`` the housed case ends in ``[acoustics]``: the given
    ``[sound.acoustics]`` keys, the defaults of the others (6 frequencies, the air of
    docs/acoustics.md, no rank), no band (the orders' range); the case reader takes it and its
    acoustics are the table's; without ``sound_power`` no ``[acoustics]``."""
    _, spec, tables, table = sized
    k = int(np.flatnonzero(table.feasible)[0])
    row = _row(table, k)
    plain = jio.SoundSection.read(SOUND, "sound")
    assert plain.radiation() is None
    assert "acoustics" not in tomllib.loads(jio.housed_case_text(tables, spec, row, k, plain))
    given = {"frequencies": 4, "rank": 30, "cache": False, "sound_speed_m_s": 340.0}
    section = jio.SoundSection.read(SOUND | {"sound_power": True, "acoustics": given}, "sound")
    text = jio.housed_case_text(tables, spec, row, k, section)
    assert text.startswith(jio.housed_case_text(tables, spec, row, k, plain))
    case = tomllib.loads(text)
    assert case["acoustics"] == given | {"method": "bem", "density_kg_m3": 1.21}
    default = jio.SoundSection.read(SOUND | {"sound_power": True}, "sound")
    written = tomllib.loads(jio.housed_case_text(tables, spec, row, k, default))["acoustics"]
    assert written == {"method": "bem", "frequencies": 6, "cache": True, "density_kg_m3": 1.21,
                       "sound_speed_m_s": 343.0}
    parsed = jio.parse_case(case, str(tmp_path))
    inputs = jio.acoustics_of(parsed)
    assert (inputs.frequencies, inputs.rank, inputs.cache, inputs.band) == (4, 30, False, None)
    assert (inputs.fluid.density, inputs.fluid.sound_speed) == (1.21, 340.0)


def test_a_spec_without_sound_writes_what_it_wrote(tmp_path, capsys, monkeypatch):
    """Without ``[sound]``: no stage, no column, no file, no summary entry, ``--sound N``
    refused in one line; with it and ``--sound 0``: the same table and the stage's columns
    empty (``sound_stage`` "none"), ``--write K`` writing the housed case beside the case."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
    assert jio.sizing_sound(jio.parse_sizing_spec(copy.deepcopy(SPEC))[1]) == (None, 0)
    path = tmp_path / "plain.toml"
    path.write_text(_toml(SPEC))
    out = tmp_path / "plain"
    assert main(["size", str(path), "--out", str(out), "--quiet", "--write", "0"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        plain = list(csv.DictReader(f))
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    assert "sound_stage" not in summary and "erp_peak_dB" not in plain[0]
    assert not (out / "sound.csv").exists() and not (out / "candidate_0_housed.toml").exists()
    assert main(["size", str(path), "--out", str(tmp_path / "o2"), "--sound", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].endswith(
        "--sound 1: the spec has no [sound] table (the housing's walls, the shafts' layout, the "
        "whine's speeds; docs/sizing.md): allowed --sound 0, or a spec with [sound]"), err
    assert not (tmp_path / "o2").exists()
    path = tmp_path / "sound.toml"
    path.write_text(_toml(_spec()))
    out = tmp_path / "sound"
    assert main(["size", str(path), "--out", str(out), "--quiet", "--sound", "0",
                 "--write", "0"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    for a, b in zip(plain, rows, strict=True):
        assert {n: b[n] for n in a} == a
        assert [b[n] for n in ("erp_peak_dB", "erp_peak_speed_rad_s", "sound_contact_loss",
                               "sound_stage")] == ["", "", "", "none"]
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    assert summary["sound_stage"]["candidates"] == []
    assert not (out / "sound.csv").exists()
    assert (out / "candidate_0_housed.toml").read_text(encoding="utf-8").startswith(
        (out / "candidate_0.toml").read_text(encoding="utf-8"))
    assert main(["size", str(path), "--out", str(tmp_path / "o3"), "--sound", "-1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sound -1: out of range, allowed an integer >= 0" in err[0]


@pytest.mark.slow
def test_the_stage_equals_jaxgear_run_of_the_written_case(tmp_path, monkeypatch):
    """``jaxgear size --sound 2`` over a front of the mass, the ERP peak and the margin: the
    two candidates of the first fronts (the dynamics stage's rule, the ERP left out) run; the
    first one's housed case (``--write K``) run by ``jaxgear run`` reports the stage's ERP peak
    and its speed, and its overall ERP at every speed (housing.csv) is sound.csv's, to 1e-9
    (the same functions on the same numbers; the stage's result read from the store, the
    run's housing from fem_prep's cache); the front ranks only the candidates run, and among
    them the brute-force domination written here; a rerun reads the store (the same seconds
    recorded)."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
    data = _spec(candidates=2)
    data["pareto"] = {"minimise": ["mass_kg", "erp_peak_dB"], "maximise": ["least_margin"]}
    spec, _ = jio.parse_sizing_spec(data)
    chosen = js.dynamics_selection(spec, js.size(spec), 2, stage="sound")
    k = int(chosen[0])
    path = tmp_path / "sound.toml"
    path.write_text(_toml(data))
    out = tmp_path / "size"
    argv = ["size", str(path), "--out", str(out), "--quiet", "--write", str(k)]
    assert main(argv) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    ran = [i for i, r in enumerate(rows) if r["sound_stage"] != "none"]
    assert ran == sorted(chosen.tolist())
    assert all(rows[i]["sound_stage"] == "plain" for i in ran)
    # the front over the stage's objective: only the candidates run, by domination
    ranked = sorted(i for i, r in enumerate(rows) if int(r["pareto_rank"]) > 0)
    assert ranked == ran
    obj = {i: (float(rows[i]["mass_kg"]), float(rows[i]["erp_peak_dB"]),
               -float(rows[i]["least_margin"])) for i in ran}
    for i in ran:
        dominated = any(all(a <= b for a, b in zip(obj[j], obj[i], strict=True))
                        and obj[j] != obj[i] for j in ran if j != i)
        assert (int(rows[i]["pareto_rank"]) == 1) == (not dominated)
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    seconds = summary["sound_stage"]["candidate_seconds"]
    housed = out / f"candidate_{k}_housed.toml"
    assert housed.read_text(encoding="utf-8") == (
        out / "store" / "sound" / f"candidate_{k}_housed.toml").read_text(encoding="utf-8")
    run = tmp_path / "run"
    assert main(["run", str(housed), "--out", str(run), "--quiet"]) == 0
    got = json.loads((run / "summary.json").read_text(encoding="utf-8"))["whine"]["housing"]
    assert float(rows[k]["erp_peak_dB"]) == pytest.approx(got["max_overall_erp_dB"], rel=1e-9)
    assert float(rows[k]["erp_peak_speed_rad_s"]) == got["speed_of_max_overall_erp_rad_s"]
    with open(run / "whine" / "housing.csv", encoding="utf-8") as f:
        level = {r["speed_rad_s"]: r["overall_erp_dB"] for r in csv.DictReader(f)}  # in order
    with open(out / "sound.csv", encoding="utf-8") as f:
        curve = [r for r in csv.DictReader(f) if int(r["candidate"]) == k]
    assert len(curve) == len(level) == 12
    for r, (speed, want) in zip(curve, level.items(), strict=True):
        assert float(r["speed_rad_s"]) == pytest.approx(float(speed), rel=1e-10)  # 12 digits
        assert (r["overall_erp_dB"] == "") == (want == "")
        if want:
            assert float(r["overall_erp_dB"]) == pytest.approx(float(want), rel=1e-9)
    # a rerun into the same folder: the store's results (the first run's seconds recorded)
    assert main(argv) == 0
    again = json.loads((out / "sizing.json").read_text(encoding="utf-8"))
    assert again["sound_stage"]["candidate_seconds"] == seconds
    with open(out / "sizing.csv", encoding="utf-8") as f:
        assert list(csv.DictReader(f)) == rows


def test_the_documented_table_and_the_example_are_valid():
    """docs/sizing.md's ``[sound]`` block and examples/sizing/helical.toml's (candidates 0:
    the stage on request) are read by the spec reader as they stand."""
    import pathlib
    import re

    root = pathlib.Path(__file__).resolve().parents[1]
    text = (root / "docs" / "sizing.md").read_text(encoding="utf-8")
    block = re.findall(r"^```toml\n(.*?)^```", text[text.index("## The sound stage"):],
                       re.DOTALL | re.MULTILINE)[0]
    data = copy.deepcopy(SPEC) | tomllib.loads(block)
    assert jio.sizing_sound(jio.parse_sizing_spec(data)[1])[1] == 1
    power = re.findall(r"^```toml\n(.*?)^```", text[text.index("**The radiated sound power**"):],
                       re.DOTALL | re.MULTILINE)[0]  # sound_power with [sound.acoustics]
    data = copy.deepcopy(SPEC) | tomllib.loads(power)
    radiation = jio.sizing_sound(jio.parse_sizing_spec(data)[1])[0].radiation()
    assert (radiation.method, radiation.frequencies, radiation.rank) == ("bem", 6, 64)
    _, tables = jio.load_sizing_spec(str(root / "examples" / "sizing" / "helical.toml"))
    section, n = jio.sizing_sound(tables)
    assert n == 0 and section.speed_range_rpm == [300.0, 3000.0]
    assert section.radiation() is None  # sound_power = false
    assert jio.sizing_sound(tables, 1)[1] == 1


def test_a_box_that_does_not_fit_fails_its_candidate(tmp_path, monkeypatch):
    """Shafts too thick for the box (bores of 1.5 x 200 mm round axes under 100 mm apart): the
    candidate's housed case is refused by the case reader in one line, which the stage records
    (``sound_stage`` "failed", the reason in sizing.json, its columns empty) instead of
    stopping the sizing."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
    path = tmp_path / "thick.toml"
    path.write_text(_toml(_spec(shaft_diameter_mm=200.0)))
    out = tmp_path / "out"
    assert main(["size", str(path), "--out", str(out), "--quiet"]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    failed = [i for i, r in enumerate(rows) if r["sound_stage"] == "failed"]
    assert len(failed) == 1 and rows[failed[0]]["erp_peak_dB"] == ""
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))["sound_stage"]
    why = summary["failed"][str(failed[0])]
    assert why.startswith("[housing] bore_diameter_mm = 300: no diameter fits") and "\n" not in why
    with open(out / "sound.csv", encoding="utf-8") as f:
        assert list(csv.DictReader(f)) == []  # no curve of a failed candidate


def _spec_text(data) -> str:
    """A spec's tables as TOML (its tables and one level of sub-tables, JSON's numbers, strings,
    lists and booleans, which TOML reads the same)."""
    lines = [f"name = {json.dumps(data['name'])}"]
    for table, values in data.items():
        if not isinstance(values, dict):
            continue
        lines.append(f"[{table}]")
        lines += [f"{k} = {json.dumps(v)}" for k, v in values.items() if not isinstance(v, dict)]
        for k, v in values.items():
            if isinstance(v, dict):
                lines.append(f"[{table}.{k}]")
                lines += [f"{kk} = {json.dumps(vv)}" for kk, vv in v.items()]
    return "\n".join(lines) + "\n"


@pytest.mark.slow
def test_the_sound_power_equals_jaxgear_run_and_stays_below_the_erp(tmp_path, monkeypatch,
                                                                  fem_prep_cache):
    """``[sound] sound_power = true`` (the default 6 BEM frequencies over the orders' range), a
    front of the mass and the sound power peak: the stage's candidate's ``sound_power_peak_dB``
    and its speed equal ``jaxgear run`` of the written housed case (``--write K``, its
    ``[acoustics]``): acoustics/sound_power.json's largest overall L_W, and sound.csv's curve
    that file's overall L_W at every speed, to 1e-9 (the same functions on the same numbers,
    the radiation operators solved by the stage into the test run's fresh fem_prep cache and
    read back from it by the run). Physics: at every speed and order
    the radiated power is at most the housing's ERP (housing.csv's, σ = W / ERP <= 1) within
    2.5 %, the BEM's own accuracy on the pulsating sphere (docs/acoustics.md), and above zero;
    the overall L_W at most the overall ERP."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")
    data = _spec(sound_power=True, speeds=6)
    data["pareto"] = {"minimise": ["mass_kg", "sound_power_peak_dB"]}
    spec, _ = jio.parse_sizing_spec(data)
    k = int(js.dynamics_selection(spec, js.size(spec), 1, stage="sound")[0])
    path = tmp_path / "power.toml"
    path.write_text(_spec_text(data))
    out = tmp_path / "size"
    assert main(["size", str(path), "--out", str(out), "--quiet", "--write", str(k)]) == 0
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert [i for i, r in enumerate(rows) if r["sound_stage"] != "none"] == [k]
    assert [i for i, r in enumerate(rows) if int(r["pareto_rank"]) > 0] == [k]
    summary = json.loads((out / "sizing.json").read_text(encoding="utf-8"))["sound_stage"]
    assert summary["sound_power"]["frequencies"] == 6
    housed = out / f"candidate_{k}_housed.toml"
    assert tomllib.loads(housed.read_text(encoding="utf-8"))["acoustics"]["frequencies"] == 6
    run = tmp_path / "run"
    assert main(["run", str(housed), "--out", str(run), "--quiet"]) == 0
    got = json.loads((run / "acoustics" / "sound_power.json").read_text(encoding="utf-8"))
    overall = np.asarray([math.nan if v is None else v for v in got["overall_LW_dB"]])
    top = int(np.nanargmax(overall))
    assert float(rows[k]["sound_power_peak_dB"]) == pytest.approx(overall[top], rel=1e-9)
    assert float(rows[k]["sound_power_peak_speed_rad_s"]) == got["speeds_rad_s"][top]
    with open(out / "sound.csv", encoding="utf-8") as f:
        curve = [float(r["overall_sound_power_dB"]) for r in csv.DictReader(f)]
    np.testing.assert_allclose(curve, overall, rtol=1e-9)
    # σ <= 1: each order's power against the housing's ERP of the same run
    with open(run / "whine" / "housing.csv", encoding="utf-8") as f:
        erp = list(csv.DictReader(f))  # one row per speed and order, speed by speed
    power = np.asarray(got["power_W"], dtype=float)  # (S, O)
    assert power.size and np.all(power > 0)
    per_speed = len(erp) // len(got["speeds_rad_s"])
    for s, speed in enumerate(got["speeds_rad_s"]):
        here = erp[s * per_speed : (s + 1) * per_speed]
        for o, order in enumerate(got["orders"]):
            e = next(r for r in here if float(r["order"]) == order)
            assert float(e["speed_rad_s"]) == pytest.approx(speed, rel=1e-10)  # 12 digits
            assert float(e["in_band"]) == 1.0
            assert power[s, o] <= 1.025 * float(e["erp_W"]), (speed, order)
        assert overall[s] <= float(e["overall_erp_dB"]) + 10 * math.log10(1.025)
