"""Rolling bearings from their geometry in a gearbox's lumped 3D pair stage
(tests/data/gearbox/two-pair-rolling.toml: stage 2 on four 6205s): their operating point at the
CHAIN's operating point (the stage's pinion torque as the gearbox carries it, not its own case's),
against each shaft on two supports by hand, the bearing package called directly, the same stage
run as its own pair case at the carried torque, and ISO 281's L10 = (C/P)³ by hand in the
gearbox's report; under the gearbox's ``[load_spectrum]`` (two-pair-rolling-spectrum.toml):
each bin carried to the stage by hand, each bearing's lives against Palmgren–Miner by hand from
each bin's hand statics and against the stage run alone as a pair case under the carried
``[rating.spectrum]``, a one-bin spectrum against the single point, and its refusals."""

from __future__ import annotations

import dataclasses
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from test_bearing_report import assert_basic_life  # ISO 281's L10 by hand
from test_bearing_scenes import _working_pressure_angle

import jaxgear.io as jio
from jaxgear import bearings as jb
from jaxgear.cli._bearing_report import (
    bearing_outputs,
    bearing_run_lines,
    bearing_tone_lines,
    bearing_tone_orders,
    gearbox_bearing_outputs,
)
from jaxgear.io import operating_point
from jaxgear.scenes import bearing_dofs

DATA = Path(__file__).resolve().parent / "data" / "gearbox"
GEARBOX = DATA / "two-pair-rolling.toml"
SPECTRUM = DATA / "two-pair-rolling-spectrum.toml"
STAGE1 = DATA / "two-pair-whine-stage1.toml"
STAGE2 = DATA / "two-pair-rolling-stage2.toml"
#: the 6205's basic dynamic rating (SKF's catalogue, as the CWRU bearing data centre lists it)
C_6205 = 14.8e3


def _toml(path: Path) -> dict:
    return tomllib.loads(path.read_text())


def _chain() -> dict:
    """The gearbox's operating point carried by hand: stage 1's pinion at the gearbox's torque
    and speed drives its gear (z1/z2), whose shaft is stage 2's pinion (lossless):
    T₂ = T₁ z₂/z₁, ω₂ = ω₁ z₁/z₂; stage 2's gear shaft at ω₂ z₃/z₄."""
    g, s1, s2 = _toml(GEARBOX), _toml(STAGE1), _toml(STAGE2)
    ratio1 = s1["gear"]["teeth"] / s1["pinion"]["teeth"]
    torque = g["operating"]["torque_Nm"] * ratio1
    speed = g["operating"]["speed_rad_s"] / ratio1
    return {"input_speed": g["operating"]["speed_rad_s"], "torque": torque, "speed": speed,
            "speeds": (speed, speed * s2["pinion"]["teeth"] / s2["gear"]["teeth"]),
            "own_torque": s2["operating"]["torque_Nm"]}


def _hand_radial(torque: float) -> tuple[float, float]:
    """(F_n / 2, tan α_w) of stage 2 at its pinion ``torque``: the normal force
    F_n = T / r_b1 (spur, r_b1 = m z₁ cos α / 2) along the line of action at the working
    pressure angle (the involute function; no profile shift, α_w = α), each gear at mid-span
    of its shaft on two bearings: half of it on each."""
    s2 = _toml(STAGE2)
    m = s2["pair"]["normal_module_mm"] * 1e-3
    alpha = math.radians(s2["pair"]["normal_pressure_angle_deg"])
    z1, z2 = s2["pinion"]["teeth"], s2["gear"]["teeth"]
    aw = _working_pressure_angle(alpha, 0.0, z1 + z2)
    fn = torque / (0.5 * m * z1 * math.cos(alpha))
    for shaft in ("pinion_shaft", "gear_shaft"):
        spec = s2["scene"][shaft]
        assert spec["gear_position_mm"] == pytest.approx(spec["length_mm"] / 2)
    return 0.5 * fn, math.tan(aw)


@pytest.fixture(scope="module")
def staged():
    """The gearbox case, its stage 2 (the stage case carried to the chain's point) and that
    stage's operating point (found once when the gearbox is loaded, cached)."""
    case = jio.load_case(str(GEARBOX))
    stage = case.form.stages[1]
    return case, stage, operating_point(stage.case)


def test_stage_bearings_stand_at_the_chains_torque(staged):
    """Each of stage 2's bearings carries F_n/2 at the torque the chain gives its pinion
    (60 N·m × 40/24 = 100 N·m, not its case's own 40 N·m), along the line of action
    (|F_x|/|F_y| = tan α_w), the axial loads balancing on each shaft: 1e-9 (the theoretical
    path of contact, one slice at mid-span: statics exactly; measured ~1e-14)."""
    _, stage, point = staged
    chain = _chain()
    assert stage.case.torque == pytest.approx(chain["torque"], rel=1e-15)
    assert stage.case.speed == pytest.approx(chain["speed"], rel=1e-15)
    assert chain["torque"] != pytest.approx(chain["own_torque"], rel=0.1)  # they differ
    half, tan_aw = _hand_radial(chain["torque"])
    own, _ = _hand_radial(chain["own_torque"])
    assert point.change <= 1e-6 and 2 <= point.iterations <= 8
    for loads in point.loads:
        for f in loads:
            f = np.asarray(f)
            fr = math.hypot(f[0], f[1])
            assert fr == pytest.approx(half, rel=1e-9)
            assert fr != pytest.approx(own, rel=0.1)  # not the stage case's own torque's
            assert abs(f[0]) / abs(f[1]) == pytest.approx(tan_aw, rel=1e-9)
        assert abs(loads[0][2] + loads[1][2]) <= 1e-9 * half


def test_stage_tangent_stiffness_is_the_packages_at_its_load(staged):
    """Each bearing's stiffness in the gearbox's stage is the package's ``stiffness6`` at the
    displacement that carries its load (:func:`jaxgear.bearings.solve_displacement`, called
    directly with the reported load): 1e-9 of its largest entry; and the gearbox's stage
    scene (the chain's :class:`~jaxgear.gearbox.LumpedPairGearboxStage`) holds that stiffness
    on each bearing node (1e-12); measured identical."""
    _, stage, point = staged
    scene = stage.torsional.scene
    parts = scene.structure.part_names
    kb = np.asarray(scene.structure.parts_K[parts.index("bearings")])
    for dofs, shaft, loads in zip(bearing_dofs(point.shafts), point.shafts, point.loads,
                                  strict=True):
        for n, b, f in zip(dofs, shaft.bearings, loads, strict=True):
            d = np.asarray(jb.solve_displacement(b.rolling, np.asarray(f, float)).displacement)
            k_pkg = np.asarray(b.rolling.stiffness6(d))
            k = b.stiffness_matrix()
            scale = np.max(np.abs(k_pkg))
            assert np.max(np.abs(k - k_pkg)) <= 1e-9 * scale
            np.testing.assert_allclose(kb[n : n + 6, n : n + 6], k, rtol=1e-12,
                                       atol=1e-12 * scale)


def test_stage_as_its_own_pair_case_at_the_carried_torque(staged):
    """The stage case run as its own pair case with ``[operating]`` the carried point (100 N·m
    at 18 rad/s) finds the same operating point: each bearing's load and displacement to 1e-9
    (the same fixed point, one home; measured identical)."""
    _, _, point = staged
    chain = _chain()
    data = _toml(STAGE2)
    data["operating"] = {"torque_Nm": chain["torque"], "speed_rad_s": chain["speed"]}
    alone = operating_point(jio.parse_case(data))
    for got, want in zip(point.loads, alone.loads, strict=True):
        for f, g in zip(got, want, strict=True):
            np.testing.assert_allclose(f, g, rtol=1e-9, atol=1e-9 * np.max(np.abs(g)))
    for a, b in zip(point.states, alone.states, strict=True):
        for s, t in zip(a, b, strict=True):
            scale = np.max(np.abs(np.asarray(t.displacement)))
            np.testing.assert_allclose(s.displacement, t.displacement, rtol=1e-9,
                                       atol=1e-9 * scale)


def _section(case, stage):
    """The gearbox's ``bearings`` section from its stages' rows as ``jaxgear run`` writes them
    (stage 1 torsional, no bearings; stage 2 its own run's ``bearings``)."""
    stages = [{"stage": "stage1", "summary": {}},
              {"stage": "stage2", "summary": {"bearings": bearing_outputs(stage.case.form,
                                                                          stage.case)}}]
    return gearbox_bearing_outputs(case.form, case, stages)


def test_gearbox_report_lives_and_tones_by_hand(staged):
    """The gearbox's report: each bearing named ``stage2.<its table>``, its load F_n/2 at the
    chain's torque, its L10 = (C/P)³ 10⁶ revolutions with P = F_r (a deep groove ball bearing
    with F_a/F_r far below ISO 281's e) and C the 6205's 14.8 kN, L10h at its shaft's speed
    (stage 2's pinion 18 rad/s, its gear 18 × 25/41), within 1e-6 (the loads' 1e-9, P's axial
    part none); its tones as orders of the gearbox's input speed (30 rad/s): its shaft's
    orders × its shaft's speed / 30 (1e-12), the Campbell diagram's and the whine's; the
    console line per bearing."""
    case, stage, _ = staged
    chain = _chain()
    section = _section(case, stage)
    half, _ = _hand_radial(chain["torque"])
    rows = section["bearings"]
    assert [r["name"] for r in rows] == [f"stage2.{s}.bearings[{i}]"
                                         for s in ("pinion_shaft", "gear_shaft") for i in (0, 1)]
    assert section["input_speed_rad_s"] == pytest.approx(chain["input_speed"], rel=1e-15)
    assert [s["stage"] for s in section["stages"]] == ["stage2"]
    tones = {(t["bearing"], t["tone"]): t["order"] for t in bearing_tone_orders(case)}
    assert len(tones) == 4 * 4
    for row in rows:
        w = chain["speeds"][0 if ".pinion_shaft." in row["name"] else 1]
        assert row["stage"] == "stage2"
        assert row["shaft_speed_rad_s"] == pytest.approx(w, rel=1e-12)
        assert_basic_life(row, C_6205, half, w, load_rel=1e-9, life_rel=1e-6)
        for tone, order in row["tones_orders"].items():
            want = order * w / chain["input_speed"]
            assert row["tones_input_orders"][tone] == pytest.approx(want, rel=1e-12)
            assert tones[row["name"], tone] == pytest.approx(want, rel=1e-12)
    # the figures docs/bearings.md states ("In a gearbox")
    assert half == pytest.approx(1419.0, abs=0.5)
    f = np.asarray(rows[0]["load_N_Nm"])
    assert abs(f[1]) == pytest.approx(1333.0, abs=0.5) and abs(f[0]) == pytest.approx(485.0,
                                                                                     abs=0.5)
    assert rows[0]["life"]["L10_revolutions"] == pytest.approx(1.13e9, rel=5e-3)
    assert rows[0]["life"]["L10_hours"] == pytest.approx(110_000.0, rel=5e-3)
    assert rows[2]["life"]["L10_hours"] == pytest.approx(180_000.0, rel=5e-3)
    assert rows[2]["shaft_speed_rad_s"] == pytest.approx(10.98, abs=5e-3)
    lines = bearing_run_lines(section)
    assert len(lines) == 4 and all(t.startswith("bearing stage2.") for t in lines)
    names = [n for n, _ in bearing_tone_lines(case)]
    assert names and all(n.startswith(("stage2 pinion shaft ", "stage2 gear shaft "))
                         for n in names), names


def test_tones_drawn_on_the_gearbox_campbell_diagram(staged, monkeypatch):
    """The coupled Campbell diagram draws each shaft's tones (campbell.json's
    ``bearing_tones``) as f = order Ω / 2π of the gearbox's input speed Ω, labelled with the
    stage's shaft and the order."""
    from jaxgear.cli._plots import _gearbox

    case, _, _ = staged
    kept = {}
    monkeypatch.setattr(_gearbox, "savefig", lambda fig, path: kept.setdefault("fig", fig))
    tones = bearing_tone_orders(case)
    data = {"case": "t", "max_speed_rad_s": 40.0, "operating_speed_rad_s": 30.0,
            "harmonics": [1], "mesh_Hz_per_rad_s": [3.8, 2.3], "crossings": [],
            "modes": [{"frequency_Hz": 0.0, "type": "rigid body", "mesh": "-"},
                      {"frequency_Hz": 900.0, "type": "stage2", "mesh": "m"}],
            "bearing_tones": tones}
    _gearbox.gearbox_campbell_plot("unused.png", data)
    drawn = {ln.get_label(): ln for ln in kept["fig"].axes[0].get_lines()}
    for t in tones:
        shaft = t["bearing"].rsplit(".bearings[", 1)[0].replace("_", " ")
        x, y = (np.asarray(v, float) for v in
                drawn[f"{shaft} {t['tone'].upper()} ({t['order']:.3g})"].get_data())
        assert np.allclose(y, t["order"] * x / (2 * np.pi), rtol=1e-12)
    assert sum(" BPFO " in k for k in drawn) == 2  # one per shaft (its two 6205s alike)


def _copy(tmp_path: Path, stage2: dict | None = None) -> Path:
    """The gearbox's files in ``tmp_path``, stage 2's data replaced by ``stage2``."""
    from _toml import case_toml

    for path in (GEARBOX, STAGE1, STAGE2):
        (tmp_path / path.name).write_text(path.read_text())
    if stage2 is not None:
        (tmp_path / STAGE2.name).write_text(case_toml(stage2), "utf-8")
    return tmp_path / GEARBOX.name


def test_housed_stage_bearings_at_the_chains_point_the_housing_rigid(staged, tmp_path):
    """tests/data/gearbox/two-pair-housed.toml (both stages in one box) with its stage 2 the
    rolling one (the same 120 mm shafts, its bearings on seats 2, 6, 3, 7) at this file's
    60 N·m: the stage's bearings stand at the operating point of the grounded stage (the
    housing rigid there, as a housed pair's: each load F_n/2 at the chain's torque, 1e-9, and
    the unhoused gearbox's loads to 1e-12), and the housed stage's scene holds each bearing's
    tangent stiffness on its node (1e-12), joined to the box's coordinates."""
    _, _, grounded = staged
    text = (DATA / "two-pair-housed.toml").read_text()
    for old, new in (('case = "two-pair-lumped-stage2.toml"', f'case = "{STAGE2.name}"'),
                     ("torque_Nm = 200.0", "torque_Nm = 60.0")):
        assert old in text
        text = text.replace(old, new)
    for path in (DATA / "two-pair-housed-stage1.toml", STAGE2):
        (tmp_path / path.name).write_text(path.read_text())
    (tmp_path / "housed.toml").write_text(text)
    case = jio.load_case(str(tmp_path / "housed.toml"))
    assert case.form.housed() == (0, 1)
    stage = case.form.stages[1]
    point = operating_point(stage.case)
    half, _ = _hand_radial(_chain()["torque"])
    for got, want in zip(point.loads, grounded.loads, strict=True):
        for f, g in zip(got, want, strict=True):
            assert math.hypot(f[0], f[1]) == pytest.approx(half, rel=1e-9)
            np.testing.assert_allclose(f, g, rtol=1e-12, atol=1e-12 * half)
    coupled = case.form.coupled()
    scene = coupled.stages[1].scene
    kb = np.asarray(scene.structure.parts_K[scene.structure.part_names.index("bearings")])
    ground = stage.torsional.scene
    n = np.asarray(ground.structure.parts_K[ground.structure.part_names.index("bearings")]
                   ).shape[0]
    assert kb.shape[0] > n  # the box's coordinates after the stage's own
    for dofs, shaft in zip(bearing_dofs(point.shafts), point.shafts, strict=True):
        for k, b in zip(dofs, shaft.bearings, strict=True):
            kt = b.stiffness_matrix()
            np.testing.assert_allclose(kb[k : k + 6, k : k + 6], kt, rtol=1e-12,
                                       atol=1e-12 * np.max(np.abs(kt)))
            assert np.abs(kb[k : k + 6, n:]).max() > 0  # joined to its seat


def test_a_stage_on_rolling_bearings_under_a_load_spectrum_is_refused(tmp_path):
    """A rolling stage whose case is rated under a load spectrum (``[rating.spectrum]``: its
    bins' torques are the stage's own, not the chain's): one line naming the stage's
    ``model`` and ``[rating.spectrum]``, before any operating point is found."""
    data = _toml(STAGE2)
    data["material"] = {"sigma_H_lim_MPa": 1500.0, "sigma_F_lim_MPa": 430.0,
                        "treatment": "case_hardened"}
    data["rating"] = {"application_factor": 1.0, "life_h": 20000.0,
                      "viscosity_40C_mm2_s": 220.0, "roughness_Rz_flank_um": 4.8,
                      "roughness_Rz_root_um": 20.0, "accuracy_grade": 6,
                      "spectrum": {"torque_Nm": [80.0, 40.0], "speed_rpm": [3000.0, 1500.0],
                                   "hours": [5e3, 1.5e4]}}
    with pytest.raises(ValueError) as err:
        jio.load_case(str(_copy(tmp_path, data)))
    text = str(err.value)
    assert text.startswith("[stages[1]] model = 'lumped3d': not with a stage case on rolling "
                           "bearings from their geometry under a load spectrum") and (
        "[rating.spectrum]" in text and "[load_spectrum]" in text and "\n" not in text), text


# ---------------------------------------------------------- under the gearbox's load spectrum


def _input_bins() -> dict:
    """The ``[load_spectrum]`` of two-pair-rolling-spectrum.toml as written: stage 1's pinion
    torque (N·m), speed (rpm -> rad/s by hand) and time shares."""
    sp = _toml(SPECTRUM)["load_spectrum"]
    return {"torque": np.array(sp["torque_Nm"]), "speed": np.array(sp["speed_rpm"]) * math.pi / 30,
            "share": np.array(sp["time_share"])}


def _stage2_bins() -> dict:
    """Each bin at stage 2's pinion by hand (stage 1 z1 -> z2, lossless: T z2/z1, ω z1/z2) and
    each stage-2 shaft's speed (its gear's ω z3/z4)."""
    s1, s2 = _toml(STAGE1), _toml(STAGE2)
    r1 = s1["gear"]["teeth"] / s1["pinion"]["teeth"]
    b = _input_bins()
    w = b["speed"] / r1
    return {"torque": b["torque"] * r1, "speed": w, "share": b["share"],
            "shafts": (w, w * s2["pinion"]["teeth"] / s2["gear"]["teeth"])}


def _spectrum_section(case, stage_case=None):
    """The gearbox's ``bearings`` section with its ``[load_spectrum]`` (stage 2's own run's
    rows at the carried point; ``stage_case`` another stage-2 case in the form)."""
    form = case.form
    if stage_case is not None:
        stages = list(form.stages)
        stages[1] = dataclasses.replace(stages[1], case=stage_case)
        form = dataclasses.replace(form, stages=tuple(stages))
    s = form.stages[1].case
    rows = [{"stage": "stage1", "summary": {}},
            {"stage": "stage2", "summary": {"bearings": bearing_outputs(s.form, s)}}]
    return gearbox_bearing_outputs(form, case, rows)


@pytest.fixture(scope="module")
def spectrum():
    """The gearbox under its load spectrum and its report's ``bearings`` section."""
    case = jio.load_case(str(SPECTRUM))
    return case, _spectrum_section(case)


def test_spectrum_bins_carried_down_the_chain_by_hand(spectrum):
    """Each bin at each stage: stage 1's pinion the input's bins (rpm -> rad/s), stage 2's
    pinion T z2/z1 and ω z1/z2 of stage 1 (1e-14); the times the shares of the scaled total
    (the lives depend on the shares only); the report's per-stage carried bins alike."""
    case, section = spectrum
    form = case.form
    b, s2 = _input_bins(), _stage2_bins()
    first, second = form.stage_spectrum(0), form.stage_spectrum(1)
    np.testing.assert_allclose(first.torque, b["torque"], rtol=1e-14)
    np.testing.assert_allclose(first.speed, b["speed"], rtol=1e-14)
    np.testing.assert_allclose(second.torque, s2["torque"], rtol=1e-14)
    np.testing.assert_allclose(second.speed, s2["speed"], rtol=1e-14)
    d = np.asarray(second.duration)
    np.testing.assert_allclose(d / d.sum(), b["share"] / b["share"].sum(), rtol=1e-14)
    assert s2["torque"][1] == pytest.approx(100.0, rel=1e-14)  # the file's 60 N·m bin
    row = section["stages"][0]
    np.testing.assert_allclose(row["spectrum_pinion_torque_Nm"], s2["torque"], rtol=1e-14)
    np.testing.assert_allclose(row["spectrum_pinion_speed_rad_s"], s2["speed"], rtol=1e-14)
    np.testing.assert_allclose(section["load_spectrum"]["input_torque_Nm"], b["torque"],
                               rtol=1e-14)


def assert_spectrum_life_by_hand(row: dict, shaft_speeds, *, load_rel: float,
                                 life_rel: float) -> None:
    """A report row's ``spectrum_life`` under the gearbox's spectrum against ISO 281 and
    Palmgren–Miner by hand: each bin's F_r = F_n/2 at stage 2's carried torque
    (:func:`_hand_radial`; the standstill bin none), P_i = F_r,i (F_a/F_r far below e),
    n_i = ω_i t_i / 2π its shaft's turns, damage D = Σ n_i (P_i/C)³ / 10⁶, L10 = Σ n_i / D
    revolutions, L10h = Σ t_i / D, P_eq = (Σ n_i P_i³ / Σ n_i)^(1/3)."""
    bins = _stage2_bins()
    t = bins["share"] / bins["share"].sum()  # the lives: shares only
    half = np.array([_hand_radial(T)[0] for T in bins["torque"]])
    sp = row["spectrum_life"]
    np.testing.assert_allclose(sp["bins_radial_load_N"], half, rtol=load_rel)
    fa = np.abs(np.asarray(sp["bins_axial_load_N"]))
    assert np.all(fa <= 0.06 * half)
    n = shaft_speeds * t / (2 * math.pi)
    damage = np.sum(n * (half / C_6205) ** 3) / 1e6
    assert sp["L10_revolutions"] == pytest.approx(n.sum() / damage, rel=life_rel)
    # L10h = Σt/D: its ratio to L10 = Σn/D is Σt/Σn (the shares' time scale cancels)
    assert sp["L10_hours"] * 3600 / sp["L10_revolutions"] == pytest.approx(
        t.sum() / n.sum(), rel=life_rel)
    peq = (np.sum(n * half**3) / n.sum()) ** (1 / 3)
    assert sp["equivalent_load_N"] == pytest.approx(peq, rel=life_rel)


def test_spectrum_lives_by_palmgren_miner_by_hand(spectrum):
    """Each of stage 2's bearings under the gearbox's spectrum: its bins' loads F_n/2 at each
    bin's carried torque (1e-9, the statics exact), its L10 (revolutions and hours) and P_eq
    by Palmgren–Miner by hand (1e-6, the loads' 1e-9, P's axial part none), its shaft's speed
    per bin the carried pinion speed (its gear z3/z4 of it); L10r reported beside; the console
    line names the gearbox's spectrum."""
    _, section = spectrum
    bins = _stage2_bins()
    rows = section["bearings"]
    assert len(rows) == 4
    for row in rows:
        w = bins["shafts"][0 if ".pinion_shaft." in row["name"] else 1]
        assert_spectrum_life_by_hand(row, w, load_rel=1e-9, life_rel=1e-6)
        assert row["spectrum_life"]["L10r_revolutions"] > 0
    # the figures docs/bearings.md states ("In a gearbox")
    assert rows[0]["spectrum_life"]["L10_hours"] == pytest.approx(1.003e5, rel=5e-3)
    assert rows[2]["spectrum_life"]["L10_hours"] == pytest.approx(1.65e5, rel=5e-3)
    lines = bearing_run_lines(section)
    assert all("under the gearbox's load spectrum L10 " in t for t in lines), lines


def test_spectrum_lives_are_the_stage_run_alone_under_the_carried_spectrum(spectrum):
    """Stage 2 with ``[bearings]`` (ISO 281's modified life) in the gearbox, against its case
    run alone as a pair case whose ``[rating.spectrum]`` is the carried bins written by hand
    (torque T z2/z1 in N·m, speed in rpm, hours; the pair's own spectrum path): each bearing's
    bins' loads, L10, L10r and L_nm (revolutions and hours) to 1e-9 (the same statics per
    bin; measured ~1e-15)."""
    case, _ = spectrum
    settings = {"contamination_factor": 0.5, "viscosity_mm2_per_s": 68.0}
    staged = case.form.stages[1].case
    staged = staged.replace(bearings=jio.BearingsSection.read(settings))
    section = _spectrum_section(case, staged)
    bins = _stage2_bins()
    data = _toml(STAGE2)
    data["operating"] = {"torque_Nm": float(bins["torque"][1]),
                         "speed_rad_s": float(bins["speed"][1])}
    data["bearings"] = settings
    data["material"] = {"sigma_H_lim_MPa": 1500.0, "sigma_F_lim_MPa": 430.0,
                        "treatment": "case_hardened"}
    hours = bins["share"]  # any time scale: the lives are the shares'
    data["rating"] = {"application_factor": 1.0, "life_h": 20000.0,
                      "viscosity_40C_mm2_s": 220.0, "roughness_Rz_flank_um": 4.8,
                      "roughness_Rz_root_um": 20.0, "accuracy_grade": 6,
                      "spectrum": {"torque_Nm": bins["torque"].tolist(),
                                   "speed_rpm": (bins["speed"] * 30 / math.pi).tolist(),
                                   "hours": hours.tolist()}}
    alone = jio.parse_case(data)
    want = bearing_outputs(alone.form, alone)["bearings"]
    got = section["bearings"]
    assert [r["name"] for r in got] == [f"stage2.{r['name']}" for r in want]
    for g, w in zip(got, want, strict=True):
        g, w = g["spectrum_life"], w["spectrum_life"]
        np.testing.assert_allclose(g["bins_radial_load_N"], w["bins_radial_load_N"], rtol=1e-9)
        for key in ("L10", "L10r", "Lnm"):
            assert g[f"{key}_revolutions"] == pytest.approx(w[f"{key}_revolutions"], rel=1e-9)
            assert g[f"{key}_hours"] == pytest.approx(w[f"{key}_hours"], rel=1e-9)
        assert g["Lnm_revolutions"] != pytest.approx(g["L10_revolutions"], rel=1e-3)


def test_one_bin_spectrum_is_the_single_operating_point(spectrum):
    """A spectrum of one bin at the gearbox's ``[operating]`` point: each bearing's L10, L10r
    (revolutions and hours) and P_eq are its lives at the single point (ISO 281's L10 = (C/P)³
    and ISO/TS 16281's L10r at one load: 1e-9)."""
    from jaxgear.rating import LoadSpectrum

    case, _ = spectrum
    op = _toml(SPECTRUM)["operating"]
    form = dataclasses.replace(case.form, spectrum=LoadSpectrum([op["torque_Nm"]],
                                                                [op["speed_rad_s"]], [3600.0]))
    section = _spectrum_section(case.replace(form=form))
    for row in section["bearings"]:
        life, sp = row["life"], row["spectrum_life"]
        for key in ("L10_revolutions", "L10_hours", "L10r_revolutions", "L10r_hours"):
            assert sp[key] == pytest.approx(life[key], rel=1e-9), key
        assert sp["equivalent_load_N"] == pytest.approx(life["equivalent_load_N"], rel=1e-9)


@pytest.mark.parametrize("table, words", [
    ({"torque_Nm": [60.0, -5.0], "speed_rpm": 300.0, "time_share": [0.5, 0.5]},
     "[load_spectrum] torque_Nm"),
    ({"torque_Nm": [60.0, 30.0], "speed_rpm": 300.0, "time_share": [1.0]},
     "[load_spectrum] time_share"),
    ({"torque_Nm": [60.0], "speed_rpm": [300.0, 200.0], "hours": [1.0]},
     "[load_spectrum] speed_rpm"),
    ({"torque_Nm": [0.0], "speed_rpm": 300.0, "hours": [1.0]}, "[load_spectrum]"),
])
def test_bad_bins_refused_in_one_line(tmp_path, table, words):
    """A bad ``[load_spectrum]`` bin (a negative torque, a list of another length, no loaded
    bin): one line naming the gearbox's table and key in the file's units, before any stage
    is built."""
    from _toml import case_toml

    path = _copy(tmp_path)
    data = _toml(SPECTRUM)
    data["load_spectrum"] = table
    path.write_text(case_toml(data), "utf-8")
    with pytest.raises(ValueError) as err:
        jio.load_case(str(path))
    text = str(err.value)
    assert text.startswith(words) and "\n" not in text, text


def test_spectrum_without_a_rolling_stage_refused(tmp_path):
    """``[load_spectrum]`` in a gearbox without a lumped 3D stage on rolling bearings
    (tests/data/gearbox/two-pair-lumped.toml: its stage 2 on linear bearings): one line."""
    from _toml import case_toml

    for name in ("two-pair-lumped.toml", "two-pair-whine-stage1.toml",
                 "two-pair-lumped-stage2.toml"):
        (tmp_path / name).write_text((DATA / name).read_text())
    data = _toml(DATA / "two-pair-lumped.toml")
    data["load_spectrum"] = _toml(SPECTRUM)["load_spectrum"]
    (tmp_path / "g.toml").write_text(case_toml(data), "utf-8")
    with pytest.raises(ValueError) as err:
        jio.load_case(str(tmp_path / "g.toml"))
    text = str(err.value)
    assert "load_spectrum" in text and "rolling bearings" in text and "\n" not in text, text


@pytest.mark.slow  # a whole jaxgear run of the gearbox: each stage's run and sweep, the chain's
# modes, the coupled sweep, Campbell diagram, its bearings' spectrum lives: 170-280 s on the
# shared 2-core host (load 2-5)
def test_jaxgear_run_reports_a_gearbox_stages_bearings(staged, tmp_path):
    """``jaxgear run`` of the gearbox under its load spectrum (two-pair-rolling-spectrum.toml:
    two-pair-rolling.toml with ``[load_spectrum]``): summary.json's ``bearings`` is the
    section built above (the operating point found again in the run's process: loads and lives
    to 1e-9), each bearing's ``spectrum_life`` Palmgren–Miner by hand (1e-6), stage 2's own
    summary.json has its bearings at the carried point, campbell.json holds the tones as
    orders of the gearbox's input speed, and the console names each bearing by its stage and
    its lives under the gearbox's spectrum."""
    import contextlib
    import io
    import json

    from jaxgear import cli

    case, stage, _ = staged
    out = tmp_path / "out"
    text = io.StringIO()
    with contextlib.redirect_stdout(text):
        assert cli.main(["run", str(SPECTRUM), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    want = _section(case, stage)
    got = summary["bearings"]
    assert [r["name"] for r in got["bearings"]] == [r["name"] for r in want["bearings"]]
    for g, w in zip(got["bearings"], want["bearings"], strict=True):
        np.testing.assert_allclose(g["load_N_Nm"], w["load_N_Nm"], rtol=1e-9,
                                   atol=1e-9 * w["radial_load_N"])
        for key in ("L10_revolutions", "L10r_revolutions", "L10_hours"):
            assert g["life"][key] == pytest.approx(w["life"][key], rel=1e-9)
        assert g["tones_input_orders"] == pytest.approx(w["tones_input_orders"], rel=1e-12)
        w = _stage2_bins()["shafts"][0 if ".pinion_shaft." in g["name"] else 1]
        assert_spectrum_life_by_hand(g, w, load_rel=1e-9, life_rel=1e-6)
    np.testing.assert_allclose(got["load_spectrum"]["input_torque_Nm"],
                               _input_bins()["torque"], rtol=1e-14)
    own = json.loads((out / "stage2" / "summary.json").read_text())["bearings"]
    half, _ = _hand_radial(_chain()["torque"])
    assert all(b["radial_load_N"] == pytest.approx(half, rel=1e-9) for b in own["bearings"])
    campbell = json.loads((out / "campbell.json").read_text())
    assert campbell["bearing_tones"] == bearing_tone_orders(case)  # JSON keeps the floats
    printed = text.getvalue()
    assert all(f"bearing {r['name']} (DeepGrooveBall)" in printed for r in got["bearings"])
    assert printed.count("under the gearbox's load spectrum L10 ") == 4, printed
