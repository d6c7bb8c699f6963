"""Rolling bearings from their geometry in a lumped 3D train (``[[scene.shafts]]`` bearings with
``kind`` or ``catalogue``): the operating point (:func:`jaxgear.io.operating_point`, the pair's
fixed point on the train's scene), against the statics of each shaft on two supports by hand,
the bearing package called directly, the pair case with the same bearings, and ISO 281's
L10 = (C/P)³ by hand in the report."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_bearing_scenes import _working_pressure_angle

import jaxgear.io as jio
from jaxgear import bearings as jb
from jaxgear.cli._bearing_report import bearing_outputs, bearing_run_lines, bearing_tone_orders
from jaxgear.io import operating_point

ROOT = Path(__file__).resolve().parents[1]
TRAIN = ROOT / "examples" / "idler-train-lumped3d-rolling.toml"
PAIR = ROOT / "examples" / "accessory-lumped3d-rolling.toml"
#: the report's input speed (rad/s) and [bearings] settings
SPEED = 300.0
SETTINGS = {"contamination_factor": 0.5, "viscosity_mm2_per_s": 20.0, "reliability_percent": 95.0}


def _cheap(data: dict) -> dict:
    """A case's data at the cost of a default test: 2 slices, 8 positions per pitch."""
    data["mesh"].update(slices=2, positions_per_pitch=8)
    return data


def _hand_shaft_forces(data: dict) -> dict:
    """The force (F_x, F_y) (N) each shaft's gear puts on its shaft, from the gear data alone:
    each spur mesh's normal force F_n = T_k / r_b (r_b = m z cos α / 2 of its driving gear, T_k
    its driving gear's torque: the input's, then the idler's T z_idler / z_input, so that both
    meshes carry T / r_b,input) on the driven gear along the centre line (the mesh's angle_deg)
    turned by 90° − α_w towards the driving gear's motion (the input turns counter-clockwise,
    the idler clockwise), −F_n on the driving gear."""
    gears = {g["name"]: g for g in data["gears"]}
    T = data["operating"]["torque_Nm"]
    spin = {"input": 1.0, "idler": -1.0}
    out = {name: np.zeros(2) for name in gears}
    for mesh in data["meshes"]:
        a, b = gears[mesh["driving"]], gears[mesh["driven"]]
        m = a["normal_module_mm"] * 1e-3
        alpha = math.radians(a["normal_pressure_angle_deg"])
        aw = _working_pressure_angle(alpha, a["profile_shift"] + b["profile_shift"],
                                     a["teeth"] + b["teeth"])
        torque = T * a["teeth"] / gears["input"]["teeth"]
        fn = torque / (0.5 * m * a["teeth"] * math.cos(alpha))
        phi = math.radians(mesh["angle_deg"]) + spin[mesh["driving"]] * (math.pi / 2 - aw)
        f = fn * np.array([math.cos(phi), math.sin(phi)])
        out[mesh["driven"]] += f
        out[mesh["driving"]] -= f
    return out


@pytest.fixture(scope="module")
def train_point():
    """The example train (examples/idler-train-lumped3d-rolling.toml: 6206s on the input and
    idler shafts, 6207s on the output shaft, 10 µm clearance) at 300 rad/s with a
    ``[bearings]`` table, cheap: its data, case, operating point and ``jaxgear run``'s
    ``bearings`` section."""
    data = _cheap(tomllib.loads(TRAIN.read_text()))
    data["operating"]["speed_rad_s"] = SPEED
    data["bearings"] = dict(SETTINGS)
    case = jio.parse_train(data)
    return data, case, operating_point(case), bearing_outputs(case.form, case)


def test_train_bearing_reactions_equal_two_support_statics(train_point):
    """Each bearing's load against each shaft on two supports by hand: every gear sits at
    mid-span, so each bearing carries half its shaft's gear force (:func:`_hand_shaft_forces`,
    the idler's the sum of its two meshes' forces): 1e-3 of it, the pair's tolerance
    (measured 3e-5 in magnitude, 1e-5 in direction), the axial loads balancing on each
    shaft (spur meshes)."""
    data, case, point, _ = train_point
    hand = _hand_shaft_forces(data)
    assert point.change <= 1e-6 and 2 <= point.iterations <= 6
    worst = 0.0
    for name, loads in zip(case.shaft_names, point.loads, strict=True):
        want = 0.5 * hand[name]
        for f in loads:
            f = np.asarray(f)
            worst = max(worst, float(np.max(np.abs(f[:2] - want))) / np.linalg.norm(want))
        assert abs(loads[0][2] + loads[1][2]) <= 1e-6 * np.linalg.norm(hand[name])
    assert worst <= 1e-3, worst


def test_train_bearing_stiffness_is_the_package_stiffness_at_the_hand_load(train_point):
    """Each bearing's radial stiffness in the train against the bearing package called
    directly with the hand load (half its shaft's gear force, no axial load or moment): 5e-3
    of its largest entry, the pair's (the scene's small axial loads and moments, which the
    hand load leaves out); and exactly the package's tangent stiffness at the train's own
    operating point (1e-9)."""
    data, case, point, _ = train_point
    hand = _hand_shaft_forces(data)
    for name, shaft, states in zip(case.shaft_names, point.shafts, point.states, strict=True):
        for b, state in zip(shaft.bearings, states, strict=True):
            f = np.array([*(0.5 * hand[name]), 0.0, 0.0, 0.0])
            k_hand = np.asarray(jb.solve_displacement(b.rolling, f).stiffness)[:2, :2]
            k = b.stiffness_matrix()
            scale = np.max(np.abs(k_hand))
            assert np.max(np.abs(k[:2, :2] - k_hand)) <= 5e-3 * scale
            d = np.asarray(b.operating)
            assert np.allclose(k, np.asarray(b.rolling.stiffness6(d)), rtol=1e-9,
                               atol=1e-9 * scale)
            assert np.allclose(d, np.asarray(state.displacement), rtol=0, atol=1e-15)


def _pair_as_train(pair: dict) -> dict:
    """The pair case's data written as a two-gear train (gears ``pinion`` and ``gear``, one
    mesh at angle 0, each on its own shaft with the pair's shaft and bearings)."""
    gears = []
    for name in ("pinion", "gear"):
        g = dict(pair[name], name=name)
        g.update(normal_module_mm=pair["pair"]["normal_module_mm"],
                 normal_pressure_angle_deg=pair["pair"]["normal_pressure_angle_deg"])
        gears.append(g)
    shafts = []
    for name in ("pinion", "gear"):
        s = dict(pair["scene"][f"{name}_shaft"])
        s["gear_positions_mm"] = {name: s.pop("gear_position_mm")}
        shafts.append(dict(s, shaft=name))
    scene = {k: v for k, v in pair["scene"].items() if not k.endswith("_shaft")}
    return {"name": "pair-as-train", "material": pair["material"],
            "operating": pair["operating"], "mesh": pair["mesh"],
            "modifications": pair["modifications"], "gears": gears,
            "meshes": [{"driving": "pinion", "driven": "gear", "angle_deg": 0.0}],
            "scene": dict(scene, shafts=shafts)}


def test_a_two_gear_train_has_the_pairs_operating_point():
    """The pair example (6206s and 6207s) and the same pair written as a two-gear train: each
    bearing's load, its displacement and its stiffness at the operating point equal, to 1e-9
    of their largest entries (the same fixed point on two builds of one scene)."""
    pair = _cheap(tomllib.loads(PAIR.read_text()))
    one = operating_point(jio.parse_case(pair))
    two = operating_point(jio.parse_train(_pair_as_train(pair)))
    assert one.iterations == two.iterations
    for a, b, sa, sb, la, lb in zip(one.shafts, two.shafts, one.states, two.states, one.loads,
                                    two.loads, strict=True):
        for ba, bb, xa, xb, fa, fb in zip(a.bearings, b.bearings, sa, sb, la, lb, strict=True):
            assert np.max(np.abs(np.asarray(fa) - fb)) <= 1e-9 * np.max(np.abs(fa))
            da, db = np.asarray(xa.displacement), np.asarray(xb.displacement)
            assert np.max(np.abs(da - db)) <= 1e-9 * np.max(np.abs(da))
            ka, kb = ba.stiffness_matrix(), bb.stiffness_matrix()
            assert np.max(np.abs(ka - kb)) <= 1e-9 * np.max(np.abs(ka))


def test_train_report_lives_against_iso281_by_hand(train_point):
    """The report's lives: each bearing's L10 = (C/P)³ 10⁶ revolutions with P = F_r (ISO 281's
    deep groove ball: F_a / F_r far below e) from the hand statics and C the catalogue's (SKF
    6206 20.3 kN, 6207 27 kN), L10h at its shaft's speed (the input's 300 rad/s times
    z_input/z_idler, z_input/z_output), within 0.3 % (the pair's: three times the loads'
    1e-3); ISO 281's modified life with the ``[bearings]`` settings the package's
    ``modified_life`` at the reported loads (1e-9); each bearing named by its table, its tones
    orders of the input speed."""
    data, case, point, section = train_point
    hand = _hand_shaft_forces(data)
    teeth = {g["name"]: g["teeth"] for g in data["gears"]}
    C = {"input": 20.3e3, "idler": 20.3e3, "output": 27.0e3}
    rows = section["bearings"]
    assert [r["name"] for r in rows] == [f"shafts.{s}.bearings[{i}]"
                                         for s in ("input", "idler", "output") for i in (0, 1)]
    for row in rows:
        shaft = row["name"].split(".")[1]
        w = SPEED * teeth["input"] / teeth[shaft]
        fr = 0.5 * np.linalg.norm(hand[shaft])
        assert row["shaft_speed_rad_s"] == pytest.approx(w, rel=1e-12)
        assert row["radial_load_N"] == pytest.approx(fr, rel=1e-3)
        assert abs(row["axial_load_N"]) < 0.05 * row["radial_load_N"]
        L10 = (C[shaft] / fr) ** 3 * 1e6
        assert row["life"]["L10_revolutions"] == pytest.approx(L10, rel=3e-3)
        assert row["life"]["L10_hours"] == pytest.approx(L10 / (w / (2 * math.pi)) / 3600,
                                                         rel=3e-3)
        k, i = case.shaft_names.index(shaft), int(row["name"][-2])
        mod = jb.modified_life(point.shafts[k].bearings[i].rolling, row["radial_load_N"],
                               row["axial_load_N"], w, viscosity=20e-6, reliability=0.95,
                               contamination=0.5)
        assert row["life"]["Lnm_hours"] == pytest.approx(float(mod.duration) / 3600, rel=1e-9)
    assert section["life_settings"]["reliability"] == pytest.approx(0.95)
    assert all("L_nm" in t for t in bearing_run_lines(section))
    tones = bearing_tone_orders(case)
    for t in tones:
        shaft = t["bearing"].split(".")[1]
        row = next(r for r in rows if r["name"] == t["bearing"])
        ratio = teeth["input"] / teeth[shaft]
        assert t["order"] == pytest.approx(row["tones_orders"][t["tone"]] * ratio, rel=1e-12)
    assert len(tones) == 6 * 4


def test_train_dynamics_take_the_bearings_at_their_operating_point(train_point):
    """The train's lumped scene (its dynamics and modes) holds each rolling bearing's tangent
    stiffness at the operating point on its shaft node (1e-12), on the ground and in a housing
    (a small synthetic one: two seats, three modes; the operating point the grounded scene's,
    each bearing joined to a seat)."""
    from _housing import two_seat_housing

    from jaxgear.scenes import bearing_dofs

    _, case, point, _ = train_point
    housing, h = two_seat_housing()
    extra = case.train_spec().wrench_z
    for scene, seats in ((case.lumped_train(), 0), (case.lumped_train(housing=housing), h)):
        parts = scene.structure.part_names
        kb = np.asarray(scene.structure.parts_K[parts.index("bearings")])
        n = kb.shape[0] - seats
        for s, shaft in zip(bearing_dofs(point.shafts, extra), point.shafts, strict=True):
            for k, b in zip(s, shaft.bearings, strict=True):
                np.testing.assert_allclose(kb[k : k + 6, k : k + 6], b.stiffness_matrix(),
                                           rtol=1e-12, atol=1e-6)
                assert seats == 0 or np.abs(kb[k : k + 6, n:]).max() > 0  # joined to a seat


def test_a_hybrid_trains_shafts_refuse_bearings_from_geometry(tmp_path):
    """A train with a condensed body (examples/two-gear-body.toml) on a catalogue bearing: one
    line naming the bearing and the key, before the body is read."""
    text = (ROOT / "examples" / "two-gear-body.toml").read_text()
    linear = "{ position_mm = 0.0, radial_N_per_um = 300.0, axial_N_per_um = 150.0 }"
    assert linear in text
    path = tmp_path / "train.toml"
    path.write_text(text.replace(linear, '{ position_mm = 0.0, catalogue = "6205" }', 1))
    with pytest.raises(ValueError) as err:
        jio.load_case(str(path))
    text = str(err.value)
    assert text.startswith("[scene.shafts.input.bearings[0]] catalogue: a bearing from its "
                           "geometry is for a lumped3d pair or train of rigid gears for now "
                           "(not with [scene.bodies])") and "\n" not in text, text


def test_bearings_table_of_a_train_refused_in_one_line():
    """A train's ``[bearings]`` without a rolling bearing, and with one lacking its rating:
    one line each, naming the key (the pair's words, the train's table)."""
    data = tomllib.loads((ROOT / "examples" / "idler-train-lumped3d.toml").read_text())
    data["operating"]["speed_rad_s"] = SPEED
    data["bearings"] = dict(SETTINGS)
    with pytest.raises(ValueError, match=r"^\[bearings\] contamination_factor: not read: the "
                       "case has no rolling bearing"):
        jio.parse_train(data)
    data = tomllib.loads(TRAIN.read_text())
    data["operating"]["speed_rad_s"] = SPEED
    data["bearings"] = dict(SETTINGS)
    del data["scene"]["shafts"][1]["bearings"][1]["dynamic_rating_kN"]
    del data["scene"]["shafts"][1]["bearings"][1]["static_rating_kN"]
    del data["scene"]["shafts"][1]["bearings"][1]["iso281_f0"]
    with pytest.raises(ValueError, match=r"^\[scene\.shafts\.idler\.bearings\[1\]\] "
                       "dynamic_rating_kN: missing"):
        jio.parse_train(data)


@pytest.mark.slow  # a whole jaxgear run of the train with its dynamic factor sweep
def test_jaxgear_run_reports_a_trains_bearings(train_point, tmp_path):
    """``jaxgear run`` of the cheap example train at 300 rad/s with ``[bearings]``:
    summary.json's ``bearings`` is the section built above (the operating point found again,
    to 1e-9), sweep.json holds the tones as orders of the input speed."""
    import json

    from _toml import case_toml

    from jaxgear import cli

    data, case, _, section = train_point
    data = dict(data, scene=dict(data["scene"], integration={
        "steps_per_period": 16, "periods": 8, "keep_periods": 4}))
    path = tmp_path / "train.toml"
    path.write_text(case_toml(data), "utf-8")
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    for got, want in zip(summary["bearings"]["bearings"], section["bearings"], strict=True):
        assert got["name"] == want["name"]
        for key in ("L10_revolutions", "L10r_revolutions", "Lnm_hours"):
            assert got["life"][key] == pytest.approx(want["life"][key], rel=1e-9)
    sweep = json.loads((out / "sweep" / "sweep.json").read_text())
    assert sweep["bearing_tones"] == bearing_tone_orders(case)


def test_train_spectrum_life_by_palmgren_miner(train_point):
    """Under a ``[rating.spectrum]`` of the input (80 N·m at 3000 r/min for 5000 h, 40 N·m at
    1500 r/min for 15 000 h) each bearing's bins are its operating points' loads at the bins'
    input torques: by hand F_r(T_i) = F_r(T) T_i / T (the statics scale with the torque),
    n_i = ω_i t_i / 2π revolutions of its shaft (the input's speed times z_input/z_shaft),
    L10 = Σ t_i / Σ (n_i / (C/P_i)³ 10⁶) (Palmgren–Miner), within 0.3 % (the pair's)."""
    data, _, _, _ = train_point
    data = dict(data, material=dict(data["material"], sigma_H_lim_MPa=1500.0,
                                    sigma_F_lim_MPa=430.0))
    spectrum = {"torque_Nm": [80.0, 40.0], "speed_rpm": [3000.0, 1500.0],
                "hours": [5e3, 1.5e4]}
    data["rating"] = {"life_h": 20000.0, "viscosity_40C_mm2_s": 46.0,
                      "roughness_Rz_flank_um": 3.0, "roughness_Rz_root_um": 10.0,
                      "spectrum": spectrum}
    case = jio.parse_train(data)
    section = bearing_outputs(case.form, case)
    hand = _hand_shaft_forces(data)
    teeth = {g["name"]: g["teeth"] for g in data["gears"]}
    C = {"input": 20.3e3, "idler": 20.3e3, "output": 27.0e3}
    t = np.asarray(spectrum["hours"]) * 3600
    for row in section["bearings"]:
        shaft = row["name"].split(".")[1]
        w = np.asarray(spectrum["speed_rpm"]) * 2 * math.pi / 60 * teeth["input"] / teeth[shaft]
        P = 0.5 * np.linalg.norm(hand[shaft]) * np.asarray(spectrum["torque_Nm"]) / 80.0
        n = w * t / (2 * math.pi)
        life = t.sum() / np.sum(n / ((C[shaft] / P) ** 3 * 1e6)) / 3600
        sp = row["spectrum_life"]
        assert sp["bins_radial_load_N"] == pytest.approx(P.tolist(), rel=1e-3)
        assert sp["L10_hours"] == pytest.approx(life, rel=3e-3)
        assert "Lnm_hours" in sp  # the [bearings] settings apply to each bin
