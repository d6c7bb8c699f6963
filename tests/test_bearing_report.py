"""The rolling bearings in what ``jaxgear run`` reports (``summary.json``'s ``bearings``, the
Campbell diagram's and the spectra's tones, the ``[bearings]`` table and the ratings' keys),
against the bearing package called directly with the scene's loads, ISO 281's L10 by hand from
the statics of a shaft on two bearings, and the tones' formulas by hand."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest
from test_bearing_scenes import (  # the hand statics of a shaft on two bearings
    EXAMPLE,
    LINEAR,
    TORQUE,
    A,
    L,
    _refused,
    shaft_point,  # noqa: F401 (the fixture)
)

import jaxgear.io as jio
from jaxgear import bearings as jb
from jaxgear.cli._bearing_report import (
    bearing_outputs,
    bearing_rating_lines,
    bearing_run_lines,
    bearing_tone_lines,
    bearing_tone_orders,
)
from jaxgear.dynamics import operating_lives
from jaxgear.io import case_bearings, operating_point

#: the report's speed (pinion, rad/s) and [bearings] settings for the tests
SPEED = 300.0
SETTINGS = {"contamination_factor": 0.5, "viscosity_mm2_per_s": 20.0, "reliability_percent": 95.0}


#: a [rating] with a two-bin load spectrum (the pinion's torque, speed and hours)
RATING = {"application_factor": 1.0, "life_h": 20000.0, "viscosity_40C_mm2_s": 220.0,
          "roughness_Rz_flank_um": 4.8, "roughness_Rz_root_um": 20.0, "accuracy_grade": 6,
          "spectrum": {"torque_Nm": [80.0, 40.0], "speed_rpm": [3000.0, 1500.0],
                       "hours": [5e3, 1.5e4]}}


def _rated(data):
    data["material"].update(sigma_H_lim_MPa=1500.0, sigma_F_lim_MPa=430.0,
                            treatment="case_hardened")
    data["rating"] = {k: (dict(v) if isinstance(v, dict) else v) for k, v in RATING.items()}
    return data


def _data(speed=SPEED, bearings=SETTINGS):
    data = tomllib.loads(EXAMPLE.read_text())
    if speed is not None:
        data["operating"]["speed_rad_s"] = speed
    if bearings is not None:
        data["bearings"] = dict(bearings)
    return data


@pytest.fixture(scope="module")
def report():
    """The example (6206s and 6207s by geometry with SKF's ratings) at 300 rad/s with a
    ``[bearings]`` table and a ``[rating]`` with a two-bin spectrum: its case and the
    ``bearings`` section ``jaxgear run`` writes (the operating points at 80 and 40 N·m,
    shared)."""
    case = jio.parse_case(_rated(_data()))
    return case, bearing_outputs(case.form, case)


def _normal_force(data):
    """F_n = T / r_b1 of the spur pair (r_b1 = m z1 cos α / 2), by hand."""
    m = data["pair"]["normal_module_mm"] * 1e-3
    alpha = math.radians(data["pair"]["normal_pressure_angle_deg"])
    return data["operating"]["torque_Nm"] / (0.5 * m * data["pinion"]["teeth"] * math.cos(alpha))


def assert_basic_life(row: dict, C: float, P: float, speed: float, *, load_rel: float,
                      life_rel: float) -> None:
    """A report row of a radially loaded ball bearing against ISO 281 by hand: its F_r the
    hand load ``P`` (``load_rel``), its F_a small (P = F_r: far below e), L10 = (C/P)³ 10⁶
    revolutions and L10h at its shaft's ``speed`` (rad/s; ``life_rel``)."""
    assert row["radial_load_N"] == pytest.approx(P, rel=load_rel)
    assert abs(row["axial_load_N"]) < 0.05 * row["radial_load_N"]
    L10 = (C / P) ** 3 * 1e6
    assert row["life"]["L10_revolutions"] == pytest.approx(L10, rel=life_rel)
    assert row["life"]["L10_hours"] == pytest.approx(L10 / (speed / (2 * math.pi)) / 3600,
                                                     rel=life_rel)


def test_reported_life_is_the_bearing_package_with_the_scenes_loads(report):
    """Each bearing's reported loads and lives against jaxgear.bearings called directly (ISO
    281's rating_life and modified_life, ISO/TS 16281's reference_life) with the load and the
    displacement of the scene's operating point, at the shaft's speed (the gear's z1/z2 of the
    pinion's), to 1e-9."""
    case, section = report
    point = case_bearings(case).point
    data = _data()
    ratio = data["pinion"]["teeth"] / data["gear"]["teeth"]
    rows = iter(section["bearings"])
    for k, shaft in enumerate(point.shafts):
        w = SPEED * (1.0, ratio)[k]
        for i, b in enumerate(shaft.bearings):
            row = next(rows)
            f = np.asarray(point.loads[k][i])
            d = np.asarray(point.states[k][i].displacement)
            fr, fa = math.hypot(f[0], f[1]), f[2]
            assert row["shaft_speed_rad_s"] == pytest.approx(w, rel=1e-12)
            assert row["radial_load_N"] == pytest.approx(fr, rel=1e-12)
            assert row["axial_load_N"] == pytest.approx(fa, rel=1e-12)
            basic = jb.rating_life(b.rolling, fr, fa, w)
            mod = jb.modified_life(b.rolling, fr, fa, w, viscosity=20e-6, reliability=0.95,
                                   contamination=0.5)
            ref = jb.reference_life(b.rolling, d)
            life = row["life"]
            for key, want in (
                ("L10_revolutions", basic.revolutions),
                ("L10_hours", basic.duration / 3600),
                ("Lnm_revolutions", mod.revolutions),
                ("Lnm_hours", mod.duration / 3600),
                ("a_ISO", mod.life_factor),
                ("L10r_revolutions", ref.revolutions),
                ("L10r_hours", ref.revolutions * 2 * math.pi / w / 3600),
            ):
                assert life[key] == pytest.approx(float(want), rel=1e-9), key
            assert life["a1"] == pytest.approx(0.64, rel=1e-12)  # ISO 281's table at 95 %


def test_reported_l10_against_the_hand_statics(report):
    """The example's pinion and gear sit at mid-span of their two-bearing shafts: each bearing
    carries F_n / 2 radially (F_n = T / r_b1) and ISO 281's P = F_r (F_a / F_r far below
    e): L10 = (C / P)³ 10⁶ revolutions, L10h = L10 / (ω / 2π) / 3600, with C the catalogue's
    (SKF 6206 20.3 kN, 6207 27 kN), within 0.3 % (three times the loads' 1e-3 from the
    statics: the scene's mean mesh force)."""
    _, section = report
    data = _data()
    half = 0.5 * _normal_force(data)
    ratio = data["pinion"]["teeth"] / data["gear"]["teeth"]
    for row in section["bearings"]:
        C, w = ((20.3e3, SPEED) if row["name"].startswith("pinion")
                else (27.0e3, SPEED * ratio))
        assert_basic_life(row, C, half, w, load_rel=1e-3, life_rel=3e-3)
    lines = bearing_run_lines(section)
    assert len(lines) == 4 and all("L_nm" in t and "L10r" in t for t in lines)


def test_lives_of_an_off_centre_pinion_against_two_support_statics(shaft_point):  # noqa: F811
    """The bwire check's shaft (tests/test_bearing_scenes.py: a 25 mm shaft on two 6205s, the
    pinion 30 mm from the first of 100 mm): operating_lives at its operating point against
    L10 = (C / P)³ with P the beam's reactions F_n (L − a)/L and F_n a/L (C = 14.8 kN, SKF),
    within 0.6 % (three times the reactions' 2e-3)."""
    case, _, _, _, point = shaft_point
    lives = operating_lives(point, (SPEED, SPEED))
    m = case.pair.normal_module
    alpha = case.pair.normal_pressure_angle
    Fn = TORQUE / (0.5 * m * case.pair.pinion.teeth * math.cos(alpha))
    for life, share in zip(lives[0], ((L - A) / L, A / L), strict=True):
        P = Fn * share
        assert life.revolutions == pytest.approx((14.8e3 / P) ** 3 * 1e6, rel=6e-3)
        assert life.duration == pytest.approx(life.revolutions * 2 * math.pi / SPEED, rel=1e-12)
        assert life.modified is None and life.reference is not None
    assert all(b is None for b in lives[1])  # the gear shaft's linear springs: no life
    bare = operating_lives(point, None)[0][0]  # no speed: revolutions only
    assert bare.duration is None and bare.revolutions == pytest.approx(lives[0][0].revolutions)


def test_reported_tones_are_the_hand_formulas(report):
    """Each bearing's tones against the formulas by hand with the example's geometry (α = 0):
    FTF = (1 − D/d_m)/2, BPFO = Z FTF, BPFI = Z (1 + D/d_m)/2, BSF = d_m/(2D) (1 − (D/d_m)²),
    orders of its shaft's speed, in Hz at it, and as orders of the pinion speed (the Campbell
    diagram's and the spectra's lines: the gear shaft's times z1/z2), to 1e-12."""
    _, section = report
    data = _data()
    ratio = data["pinion"]["teeth"] / data["gear"]["teeth"]
    campbell = {(t["bearing"], t["tone"]): t["order"] for t in bearing_tone_orders(report[0])}
    for row in section["bearings"]:
        shaft, i = row["name"].split(".bearings[")
        given = data["scene"][shaft]["bearings"][int(i[:-1])]
        D, dm, Z = given["ball_diameter_mm"], given["pitch_diameter_mm"], given["balls"]
        g = D / dm
        hand = {"ftf": 0.5 * (1 - g), "bpfo": 0.5 * Z * (1 - g), "bpfi": 0.5 * Z * (1 + g),
                "bsf": dm / (2 * D) * (1 - g * g)}
        w = row["shaft_speed_rad_s"]
        r = 1.0 if shaft == "pinion_shaft" else ratio
        for tone, order in hand.items():
            assert row["tones_orders"][tone] == pytest.approx(order, rel=1e-12)
            assert row["tones_Hz"][tone] == pytest.approx(order * w / (2 * math.pi), rel=1e-12)
            assert campbell[row["name"], tone] == pytest.approx(order * r, rel=1e-12)
    lines = bearing_tone_lines(report[0])  # one per shaft and tone: the shafts' pairs alike
    assert len(lines) == 8


def test_no_section_without_rolling_bearings_nor_settings_without_the_table():
    """A case without rolling bearings has no ``bearings`` section; one without ``[bearings]``
    no modified-life settings (parsing only: no operating point is solved)."""
    assert bearing_outputs(jio.load_case(str(LINEAR)).form, jio.load_case(str(LINEAR))) is None
    case = jio.parse_case(_data(speed=None, bearings=None))
    assert case.bearings is None and jio.bearing_life_of(case) is None


def test_viscosity_from_the_lubricant():
    """Without viscosity_mm2_per_s the [lubricant]'s oil at its temperature: Walther's equation
    through ν40 and ν100 written here, log log(ν + 0.7) linear in log T (ASTM D341)."""
    data = _data(bearings={"contamination_factor": 0.3})
    data["lubricant"] = {"viscosity_40C_mm2_s": 220.0, "viscosity_100C_mm2_s": 19.0,
                         "density_kg_m3": 895.0, "pressure_viscosity_per_GPa": 20.0,
                         "oil_temperature_C": 70.0, "roughness_Ra_um": 0.5}
    settings = jio.bearing_life_of(jio.parse_case(data))

    def y(nu):
        return math.log10(math.log10(nu + 0.7))

    x40, x100, x = (math.log10(t + 273.15) for t in (40.0, 100.0, 70.0))
    yy = y(220.0) + (y(19.0) - y(220.0)) * (x - x40) / (x100 - x40)
    nu = 10 ** (10**yy) - 0.7
    assert settings.viscosity * 1e6 == pytest.approx(nu, rel=1e-9)
    assert settings.reliability == 0.9 and settings.contamination == 0.3


def _bearing(data, i=0, shaft="pinion_shaft"):
    return data["scene"][shaft]["bearings"][i]


@pytest.mark.parametrize(
    "edit, start",
    [
        (lambda d: d["bearings"].update(contamination_factor=1.5),
         "[bearings] contamination_factor = 1.5: out of range"),
        (lambda d: d["bearings"].update(reliability_percent=99.99),
         "[bearings] reliability_percent = 99.99: out of range"),
        (lambda d: d["operating"].pop("speed_rad_s"),
         "[operating] speed_rad_s = 0: out of range with [bearings], allowed > 0"),
        (lambda d: d["bearings"].pop("viscosity_mm2_per_s"),
         "[bearings] viscosity_mm2_per_s: missing"),
        (lambda d: [_bearing(d, 1).pop(k) for k in ("dynamic_rating_kN", "static_rating_kN",
                                                     "iso281_f0")],
         "[scene.pinion_shaft.bearings[1]] dynamic_rating_kN: missing: [bearings] rates"),
        (lambda d: _bearing(d).pop("iso281_f0"),
         "[scene.pinion_shaft.bearings[0]] iso281_f0: missing: a rating gives"),
        (lambda d: _bearing(d).update(static_rating_kN=0.0),
         "[scene.pinion_shaft.bearings[0]] static_rating_kN = 0: out of range"),
        (lambda d: d["scene"]["pinion_shaft"]["bearings"].__setitem__(
            0, {"position_mm": 0.0, "catalogue": "6205", "dynamic_rating_kN": 15.0}),
         "[scene.pinion_shaft.bearings[0]] dynamic_rating_kN: not with catalogue = '6205'"),
        (lambda d: d["scene"]["pinion_shaft"]["bearings"].__setitem__(
            0, {"position_mm": 0.0, "catalogue": "NU 205", "dynamic_rating_kN": 29.0,
                "static_rating_kN": 27.0, "iso281_f0": 14.0}),
         "[scene.pinion_shaft.bearings[0]] iso281_f0: not a key of this kind"),
        (lambda d: d["scene"]["pinion_shaft"]["bearings"].__setitem__(
            0, {"position_mm": 0.0, "radial_N_per_um": 200.0, "dynamic_rating_kN": 20.0}),
         "[scene.pinion_shaft.bearings[0]] dynamic_rating_kN: is a rolling bearing's key"),
        (lambda d: _bearing(d).update(fatigue_limit_kN=0.0),
         "[scene.pinion_shaft.bearings[0]] fatigue_limit_kN = 0: out of range"),
        (lambda d: _bearing(d).update(fatigue_limit_kN="high"),
         "[scene.pinion_shaft.bearings[0]] fatigue_limit_kN = 'high': must be a number"),
        (lambda d: _bearing(d).update(fatigue_limit_kN=11.2),
         ("[scene.pinion_shaft.bearings[0]] fatigue_limit_kN = 11.2: out of range, allowed "
          "(0, 11.2) (below static_rating_kN C0")),
        (lambda d: d["scene"]["pinion_shaft"]["bearings"].__setitem__(
            0, {"position_mm": 0.0, "catalogue": "NU 205", "fatigue_limit_kN": 3.35}),
         "[scene.pinion_shaft.bearings[0]] fatigue_limit_kN: not read without a C"),
        (lambda d: d["scene"]["pinion_shaft"]["bearings"].__setitem__(
            0, {"position_mm": 0.0, "radial_N_per_um": 200.0, "fatigue_limit_kN": 0.3}),
         "[scene.pinion_shaft.bearings[0]] fatigue_limit_kN: is a rolling bearing's key"),
    ],
)
def test_bearing_life_keys_refused_in_one_line(edit, start):
    data = _data()
    edit(data)
    _refused(data, start)


def test_bearings_table_refused_without_rolling_bearings():
    data = tomllib.loads(LINEAR.read_text())
    data["operating"]["speed_rad_s"] = SPEED
    data["bearings"] = dict(SETTINGS)
    _refused(data, "[bearings] contamination_factor: not read: the case has no rolling bearing")


def test_catalogue_entry_without_ratings_takes_the_makers():
    """A catalogue entry without C (NU 205) takes dynamic_rating_kN and static_rating_kN,
    which reach the kind in N; the rated L10 = (C/P)^(10/3) of a roller."""
    data = _data()
    data["scene"]["pinion_shaft"]["bearings"][0] = {
        "position_mm": 0.0, "catalogue": "NU 205", "dynamic_rating_kN": 29.0,
        "static_rating_kN": 27.0}
    case = jio.parse_case(data)
    kind = case.scene.pinion_shaft.bearings[0].rolling
    assert (kind.dynamic_rating, kind.static_rating) == (29.0e3, 27.0e3)
    life = jb.rating_life(kind, 1000.0, 0.0, SPEED)
    assert float(life.revolutions) == pytest.approx(29.0**(10 / 3) * 1e6, rel=1e-12)


def _a_iso_ball(kappa, load_ratio):
    """ISO 281's a_ISO of radial ball bearings (its constants written here), κ in 0.1..4."""
    b, c = ((2.2649, 0.054381) if kappa < 0.4 else (1.9987, 0.19087) if kappa < 1
            else (1.9987, 0.071739))
    return 0.1 * (1 - (2.5671 - b / kappa**c) ** 0.83 * load_ratio ** (1 / 3)) ** -9.3


def test_makers_fatigue_limit_from_the_case_in_the_reported_lnm(report):
    """``fatigue_limit_kN`` in a bearing table reaches the kind in N, and the report's L_nm
    takes it: each bearing of the example at its operating point (the module's report), its C_u
    the file's (0.49 kN for the 6206s, 0.655 kN for the 6207s: SKF's P_u as transcribed here),
    against L_nm = a₁ a_ISO (C/P)³ 10⁶ by hand: a₁ = 0.64 (95 %), κ = ν/ν₁ with ν₁ = 4500
    n^−0.5 d_m^−0.5 (n > 1000 r/min), a_ISO with e_C C_u/P (ISO 281's ball set written in the
    test), to 1e-6; the summary's fatigue_limit_N the file's."""
    import dataclasses

    from jaxgear.cli._bearing_report import _life
    case, _ = report
    point = case_bearings(case).point
    data = _data()
    makers = {"pinion_shaft": 0.49, "gear_shaft": 0.655}
    for shaft, cu in makers.items():
        for b in data["scene"][shaft]["bearings"]:
            b["fatigue_limit_kN"] = cu
    given = jio.parse_case(data).scene
    shafts = tuple(
        dataclasses.replace(s, bearings=tuple(
            dataclasses.replace(b, rolling=g.rolling) for b, g in zip(s.bearings, spec.bearings)))
        for s, spec in zip(point.shafts, (given.pinion_shaft, given.gear_shaft)))
    ratio = data["pinion"]["teeth"] / data["gear"]["teeth"]
    speeds = (SPEED, SPEED * ratio)
    lives = operating_lives(point._replace(shafts=shafts), speeds, viscosity=20e-6,
                            reliability=0.95, contamination=0.5)
    for k, shaft in enumerate(makers):
        for i, b in enumerate(shafts[k].bearings):
            assert float(b.rolling.fatigue_limit) == pytest.approx(makers[shaft] * 1e3, rel=1e-12)
            out = _life(lives[k][i])
            P = out["equivalent_load_N"]
            n = speeds[k] * 30 / math.pi
            nu1 = 4500 * n**-0.5 * (float(b.rolling.pitch_diameter) * 1e3) ** -0.5
            a = _a_iso_ball(20.0 / nu1, 0.5 * makers[shaft] * 1e3 / P)
            C = 20.3e3 if k == 0 else 27.0e3
            assert out["fatigue_limit_N"] == pytest.approx(makers[shaft] * 1e3, rel=1e-12)
            assert out["a_ISO"] == pytest.approx(a, rel=1e-6)
            assert out["Lnm_revolutions"] == pytest.approx(0.64 * a * (C / P) ** 3 * 1e6,
                                                           rel=1e-6)


def test_rating_sheet_lines_hold_the_section(report):
    """rating.md's bearing table: one row per bearing with the section's loads and lives (in
    10⁶ revolutions and hours), the settings named."""
    _, section = report
    lines = bearing_rating_lines(section)
    head = lines.index(
        "| bearing | F_r per bin (N) | P_eq (N) | L10h (h) | L10rh (h) | L_nmh (h) |")
    rows = [t for t in lines[:head] if t.startswith(("| pinion_shaft", "| gear_shaft"))]
    assert len(rows) == 4 and "viscosity 20 mm²/s" in "\n".join(lines)
    for row, b in zip(rows, section["bearings"], strict=True):
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert cells[0] == b["name"]
        assert float(cells[2]) == pytest.approx(b["radial_load_N"], rel=1e-3)
        assert float(cells[5]) == pytest.approx(b["life"]["L10_revolutions"] / 1e6, rel=1e-3)
        assert float(cells[9]) == pytest.approx(b["life"]["Lnm_hours"], rel=1e-3)
    spectrum = [t for t in lines[head:] if t.startswith(("| pinion_shaft", "| gear_shaft"))]
    assert len(spectrum) == 4
    for row, b in zip(spectrum, section["bearings"], strict=True):
        cells = [c.strip() for c in row.strip("|").split("|")]
        assert float(cells[3]) == pytest.approx(b["spectrum_life"]["L10_hours"], rel=1e-3)
        assert float(cells[4]) == pytest.approx(b["spectrum_life"]["L10r_hours"], rel=1e-3)
        assert float(cells[5]) == pytest.approx(b["spectrum_life"]["Lnm_hours"], rel=1e-3)


@pytest.mark.slow  # a whole jaxgear run with its dynamic factor sweep
def test_jaxgear_run_reports_the_bearings(report, tmp_path):
    """``jaxgear run`` of the example at 300 rad/s with ``[bearings]`` and the rated spectrum:
    summary.json's ``bearings`` is the section built above (the same operating points found
    again, to 1e-9), rating.md ends with the bearings' table, sweep.json holds the tones as
    orders of the pinion speed and campbell.png is written."""
    import json

    from jaxgear import cli

    path = tmp_path / "rolling.toml"
    data = _rated(_data())
    text = EXAMPLE.read_text().replace("torque_Nm = 80.0\n",
                                       f"torque_Nm = 80.0\nspeed_rad_s = {SPEED}\n")
    text = text.replace("density_kg_m3 = 7800.0\n", "density_kg_m3 = 7800.0\n"
                        "sigma_H_lim_MPa = 1500.0\nsigma_F_lim_MPa = 430.0\n"
                        "treatment = \"case_hardened\"\n")
    text += "\n[bearings]\n" + "".join(f"{k} = {v}\n" for k, v in SETTINGS.items())
    text += "\n[rating]\n" + "".join(f"{k} = {v}\n" for k, v in RATING.items()
                                     if k != "spectrum")
    text += "[rating.spectrum]\n" + "".join(f"{k} = {v}\n"
                                           for k, v in RATING["spectrum"].items())
    assert tomllib.loads(text) == data
    path.write_text(text)
    out = tmp_path / "out"
    assert cli.main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    _, section = report
    for got, want in zip(summary["bearings"]["bearings"], section["bearings"], strict=True):
        assert got["name"] == want["name"]
        for key in ("L10_revolutions", "L10r_revolutions", "Lnm_hours"):
            assert got["life"][key] == pytest.approx(want["life"][key], rel=1e-9)
        assert got["spectrum_life"]["L10_hours"] == pytest.approx(
            want["spectrum_life"]["L10_hours"], rel=1e-9)
    sheet = (out / "rating.md").read_text()
    assert "## Rolling bearings" in sheet  # a row per pinion bearing in each of the two tables
    assert sheet.count("| pinion_shaft.bearings[") == 4 and "F_r per bin" in sheet
    sweep = json.loads((out / "sweep" / "sweep.json").read_text())
    assert sweep["bearing_tones"] == bearing_tone_orders(report[0])
    assert (out / "sweep" / "campbell.png").stat().st_size > 0


def test_spectrum_life_against_the_package_and_palmgren_miner_by_hand(report):
    """Under the rating's spectrum (80 N·m at 3000 r/min for 5000 h, 40 N·m at 1500 r/min for
    15000 h) each bearing's bins are the loads of its operating point at the bin's torque:
    against jaxgear.bearings.spectrum_life and spectrum_modified_life called with those
    loads (1e-9), and by hand: F_r = F_n(T_i)/2 (the mid-span statics), n_i = ω_i t_i / 2π
    revolutions of its shaft, L10 = Σ t_i / Σ (n_i / (C/P_i)³ 10⁶) (Palmgren–Miner), within
    0.3 %; ISO/TS 16281's L10r = Σ t_i / Σ (n_i / L10r,i), each bin's L10r,i the reference life
    of its operating point's ring displacement, to 1e-9."""
    case, section = report
    found = case_bearings(case)
    data = _data()
    ratio = data["pinion"]["teeth"] / data["gear"]["teeth"]
    rows = iter(section["bearings"])
    at40 = operating_point(case, torque=40.0)
    spec = RATING["spectrum"]
    for k, shaft in enumerate(found.point.shafts):
        r = (1.0, ratio)[k]
        w = np.asarray(spec["speed_rpm"]) * 2 * math.pi / 60 * r
        t = np.asarray(spec["hours"]) * 3600
        for i, b in enumerate(shaft.bearings):
            row = next(rows)["spectrum_life"]
            f = np.array([found.point.loads[k][i], at40.loads[k][i]])
            sp = jb.BearingSpectrum(np.hypot(f[:, 0], f[:, 1]), f[:, 2], w, t)
            basic = jb.spectrum_life(b.rolling, sp)
            mod = jb.spectrum_modified_life(b.rolling, sp, viscosity=20e-6, reliability=0.95,
                                            contamination=0.5)
            assert row["L10_hours"] == pytest.approx(float(basic.duration) / 3600, rel=1e-9)
            assert row["Lnm_hours"] == pytest.approx(float(mod.duration) / 3600, rel=1e-9)
            C = 20.3e3 if k == 0 else 27.0e3
            P = np.array([0.5 * _normal_force(data), 0.25 * _normal_force(data)])
            n = w * t / (2 * math.pi)
            hand = t.sum() / np.sum(n / ((C / P) ** 3 * 1e6)) / 3600
            assert row["L10_hours"] == pytest.approx(hand, rel=3e-3)
            assert row["bins_radial_load_N"] == pytest.approx(P.tolist(), rel=1e-3)
            # ISO/TS 16281's L10r of each bin's operating point, Palmgren–Miner by hand
            L10r = [float(jb.reference_life(b.rolling, p.states[k][i].displacement).revolutions)
                    for p in (found.point, at40)]
            D = n[0] / L10r[0] + n[1] / L10r[1]
            assert row["L10r_revolutions"] == pytest.approx(n.sum() / D, rel=1e-9)
            assert row["L10r_hours"] == pytest.approx(t.sum() / D / 3600, rel=1e-9)
            assert row["L10r_hours"] < row["L10_hours"]  # the clearance: fewer balls loaded


def test_bearings_take_the_ratings_speed_rpm():
    """[bearings] with the speed given as the rating's ``speed_rpm`` (no ``speed_rad_s``):
    accepted, the pinion speed converted (parsing only)."""
    from jaxgear.io._bearings_table import pinion_speed

    data = _rated(_data(speed=None))
    data["operating"]["speed_rpm"] = 3000.0
    case = jio.parse_case(data)
    assert case.bearings is not None
    assert pinion_speed(data["operating"]) == pytest.approx(100 * math.pi, rel=1e-12)


def test_operating_life_without_speed_and_its_refusals():
    """jaxgear.bearings.operating_life of a 6205 at the displacement that carries 2 kN radially:
    L10 = (C/F_r)³ 10⁶ (ISO 281's P = F_r without axial load) in revolutions, no hours without
    a speed; L_nm asked without a viscosity or a speed refused in one line."""
    six = jb.catalogue("6205")
    load = np.array([2000.0, 0.0, 0.0, 0.0, 0.0])
    d = np.asarray(jb.solve_displacement(six, load).displacement)
    life = jb.operating_life(six, load, d)
    assert life.radial == pytest.approx(2000.0) and life.duration is None
    assert life.revolutions == pytest.approx((14.8e3 / 2000.0) ** 3 * 1e6, rel=1e-12)
    assert life.modified is None and life.reference is not None
    for kwargs, word in (({"speed": 100.0}, "viscosity = None"),
                         ({"viscosity": 2e-5}, "speed = None")):
        with pytest.raises(ValueError) as err:
            jb.operating_life(six, load, d, contamination=0.5, **kwargs)
        assert str(err.value).startswith(f"operating_life: {word}") and "\n" not in str(err.value)


def _captured(monkeypatch, module):
    """The figure a plot function of ``module`` saves, kept instead of written."""
    kept = {}
    monkeypatch.setattr(module, "savefig", lambda fig, path: kept.setdefault("fig", fig))
    return kept


def test_tones_drawn_on_the_campbell_diagram_and_the_waterfall(report, monkeypatch):
    """The Campbell diagram's and the waterfall's tone lines are f = order Ω / 2π of the pinion
    speed Ω, one per shaft and tone, labelled with the order."""
    from jaxgear.cli._plots import _campbell, _whine

    tones = bearing_tone_orders(report[0])
    summary = {"case": "t", "speeds_rad_s": [100.0, 3000.0], "natural_frequencies_Hz": [0.0, 900.0],
               "mesh_energy_share": [0.0, 0.5], "critical_speeds": [], "bearing_tones": tones}
    kept = _captured(monkeypatch, _campbell)
    _campbell.campbell_plot("unused.png", summary, 45)
    lines = {ln.get_label(): ln for ln in kept["fig"].axes[0].get_lines()}
    lines_w = _captured(monkeypatch, _whine)
    s = np.linspace(100.0, 3000.0, 5)
    _whine.whine_waterfall_plot("unused.png", s, 45 * s / (2 * np.pi), [1.0, 2.0],
                                np.ones((5, 2)), label="bearing force (N)", title="t",
                                tones=bearing_tone_lines(report[0]))
    drawn_w = {ln.get_label(): ln for ln in lines_w["fig"].axes[0].get_lines()}
    for t in tones:
        shaft = t["bearing"].split(".")[0].replace("_", " ")
        for drawn, label in ((lines, f"{shaft} {t['tone'].upper()} ({t['order']:.3g})"),
                             (drawn_w, f"{shaft} {t['tone'].upper()} ({t['order']:.3g}×)")):
            x, y = (np.asarray(v, float) for v in drawn[label].get_data())
            assert np.allclose(y, t["order"] * x / (2 * np.pi), rtol=1e-12)
    assert sum(" FTF " in k or " BPFO " in k for k in lines) == 4
