"""The case file's ``[rating]`` table (ISO 6336 load capacity): keys validated whole before any
work, one-line errors naming the key, its value and the allowed range; the rating built from a
case equals the one built through the API; ``rating.md`` and the ``summary.json`` section.

The case is ISO/TR 6336-30:2017 Annex A example 1 (tests/test_rating.py gives its provenance);
the API-built rating there is checked against the TR's printed values."""

import copy
import json
import math
import pathlib
import re
from typing import NamedTuple

import numpy as np
import pytest
from _toml import case_toml

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli
from jaxgear.cli import main

CASE = {
    "name": "tr-6336-30-example-1",
    "pair": {
        "normal_module_mm": 8.0,
        "normal_pressure_angle_deg": 20.0,
        "helix_angle_deg": 15.8,
        "center_distance_mm": 500.0,
    },
    "pinion": {"teeth": 17, "profile_shift": 0.145},
    "gear": {"teeth": 103, "profile_shift": 0.0},
    "material": {
        "youngs_modulus_GPa": 206.0,
        "density_kg_m3": 7830.0,
        "sigma_H_lim_MPa": 1500.0,
        "sigma_F_lim_MPa": 500.0,
    },
    "operating": {"torque_Nm": 9000.0, "speed_rpm": 360.0},
    "mesh": {"stiffness": "iso6336", "slices": 8, "positions_per_pitch": 8},
    "rating": {
        "life_h": 50000.0,
        "viscosity_40C_mm2_s": 320.0,
        "roughness_Rz_flank_um": 6.0,
        "roughness_Rz_root_um": 10.0,
        "accuracy_grade": 5,
        "tip_relief_um": 70.0,
        "K_Hbeta": 1.16,
    },
}
for _tag in ("pinion", "gear"):
    CASE[_tag].update(
        {
            "addendum_coeff": 1.0,
            "dedendum_coeff": 1.4,
            "fillet_radius_coeff": 0.39,
            "face_width_mm": 100.0,
        }
    )


def _case(**changes):
    d = copy.deepcopy(CASE)
    for path, value in changes.items():
        table, key = path.split("/")
        if value is None:
            del d[table][key]
        else:
            d[table][key] = value
    return d


def test_case_rating_is_the_api_rating():
    rc = jio.rating_of(jio.parse_case(_case()))
    assert rc.operating.speed == pytest.approx(360.0 * 2 * math.pi / 60)
    assert rc.settings.given.K_Hbeta == 1.16 and rc.settings.given.K_v is None
    assert rc.settings.accuracy.grade == 5
    assert rc.settings.tip_relief == pytest.approx(70e-6)
    assert list(rc.settings.material.sigma_h_lim) == [1500e6, 1500e6]
    assert isinstance(rc.settings.material.treatment, jr.CaseHardened)
    assert list(rc.settings.lubrication.roughness_flank) == pytest.approx([6e-6, 6e-6])
    assert float(rc.geometry.center_distance) == pytest.approx(0.5)
    assert isinstance(rc.settings.standard, jg.rating.Edition2019)  # the default
    old = jio.rating_of(jio.parse_case(_case(**{"rating/edition": 2006})))
    assert isinstance(old.settings.standard, jg.rating.Edition2006)


def test_case_without_rating_has_none():
    d = _case()
    del d["rating"]
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa"):
        del d["material"][key]
    del d["operating"]["speed_rpm"]
    assert jio.rating_of(jio.parse_case(d)) is None


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"rating/life_h": None}, "[rating] life_h: missing required key"),
        ({"material/sigma_F_lim_MPa": None}, "[material] sigma_F_lim_MPa: missing required key"),
        (
            {"rating/viscosity_40C_mm2_s": 0.5},
            "[rating] viscosity_40C_mm2_s = 0.5: out of range, allowed [1, 10000]",
        ),
        ({"rating/K_v": 0.9}, "[rating] K_v = 0.9: out of range, allowed [1, 10]"),
        (
            {"rating/accuracy_grade": 12},
            "[rating] accuracy_grade = 12: out of range, allowed [1, 11]",
        ),
        ({"rating/roughness_Rz_root_um": [10.0]}, "[rating] roughness_Rz_root_um"),
        (
            {"material/sigma_H_lim_MPa": -1.0},
            "[material] sigma_H_lim_MPa = -1: out of range, allowed [200, 2000]",
        ),
        ({"material/treatment": "carburised"}, "[material] treatment = 'carburised': allowed"),
        ({"operating/speed_rpm": None}, "[operating] speed_rpm: missing required key"),
        ({"operating/speed_rad_s": 10.0}, "[operating] speed_rpm = 360: give the speed once"),
        ({"rating/K_Hbta": 1.2}, "[rating] unknown key 'K_Hbta' (did you mean 'K_Hbeta'?)"),
        (
            {"rating/edition": 2010},
            "[rating] edition = 2010: out of range, allowed [2006, 2019], the years 2006 or 2019",
        ),
        ({"rating/edition": 1990}, "[rating] edition = 1990: out of range, allowed [2006, 2019]"),
    ],
)
def test_bad_rating_input_is_one_line_naming_the_key(changes, message):
    with pytest.raises(jio.SchemaError) as err:
        jio.parse_case(_case(**changes))
    text = str(err.value)
    assert message in text and "\n" not in text, text


@pytest.mark.parametrize(
    "changes, message",
    [
        ({"rating/life_h": None}, r"^jaxgear: error: \[rating\] life_h: missing required key"),
        ({"rating/K_v": 0.9}, r"^jaxgear: error: \[rating\] K_v = 0.9: out of range"),
    ],
)
def test_jaxgear_run_refuses_a_bad_rating_in_one_line_before_any_work(
    tmp_path, capsys, changes, message
):
    """``jaxgear run`` on a case whose ``[rating]`` lacks a key or has one out of range: exit
    status 2, one line on stderr naming the key, no output folder."""
    path = tmp_path / "bad.toml"
    path.write_text(case_toml(_case(**changes)))
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and re.search(message, err), err
    assert not out.exists()


def test_rating_keys_without_a_rating_table_are_refused():
    d = _case()
    del d["rating"]
    with pytest.raises(jio.SchemaError, match=r"\[material\] sigma_F_lim_MPa = 500: read by the"):
        jio.parse_case(d)


def test_rating_outputs_write_the_table_and_the_summary_section(tmp_path):
    case = jio.parse_case(_case())
    section = cli.rating_outputs(case, str(tmp_path))
    assert section["method"] == "ISO 6336:2019 method B"
    assert section["factors"]["K_Hbeta"] == {"value": 1.16, "source": "given"}
    assert section["factors"]["K_v"]["source"] == "ISO 6336-1 method B"
    for key in ("Z_H", "Z_E_sqrt_Pa", "Z_epsilon", "Z_beta", "sigma_H0_Pa"):
        assert isinstance(section["pitting"][key], float)
    for key in ("sigma_H_Pa", "sigma_HP_Pa", "S_H"):
        assert len(section["pitting"][key]) == 2
    for key in ("Y_F", "Y_S", "sigma_F0_Pa", "sigma_F_Pa", "sigma_FP_Pa", "S_F"):
        assert len(section["bending"][key]) == 2
    json.dumps(section)  # JSON-ready
    # S_H of the TR (printed 1.02853 / 1.08696), through the case file
    assert section["pitting"]["S_H"] == pytest.approx([1.02853, 1.08696], rel=5e-3)
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "| face load factor (contact) | K_Hβ | 1.160 (given) |" in table
    # each row names where the edition defines the factor (2019: the part, its clause where
    # checked, else the 2006 edition's labelled so; 2006's parts 2 and 3: the clauses their
    # tables of contents number, BS ISO 6336-3:2006 5.1 for S_F)
    assert "| S_F | " in table and "|  | ISO 6336-3:2019 (2006 ed. 5.1) |" in table
    assert "| dynamic factor | K_v | " in table and "|  | ISO 6336-1:2019 6 |" in table
    cli.rating_outputs(jio.parse_case(_case(**{"rating/edition": 2006})), str(tmp_path))
    old = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "|  | ISO 6336-3:2006 5.1 |" in old and "| ISO 6336-3:2006 6.2 |" in old
    no_rating = _case()
    del no_rating["rating"], no_rating["operating"]["speed_rpm"]
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa"):
        del no_rating["material"][key]
    other = tmp_path / "none"
    other.mkdir()
    assert cli.rating_outputs(jio.parse_case(no_rating), str(other)) is None
    assert not list(other.iterdir())


def test_a_rating_out_of_scope_warns_naming_the_clause(tmp_path):
    # 9000 1/min: K_v's resonance ratio N = 0.99 (0.0396 at 360 1/min), in the main resonance
    case = jio.parse_case(_case(**{"operating/speed_rpm": 9000.0}))
    with pytest.warns(
        jio.CaseWarning, match=r"\[rating\] ISO 6336-1:2019 6 dynamic factor K_v: reso"
    ):
        cli.rating_outputs(case, str(tmp_path))


def test_case_file_rim_thickness_rates_y_b_and_warns_below_its_scope(tmp_path):
    """``[gear] rim_thickness_mm`` (with ``web_thickness_mm``, the blank keys) reaches the
    rating: a rim of 0.8 tooth depths (h_t = (1 + 1.4) m_n = 19.2 mm) gives the gear Y_B =
    1.6 ln(2.242/0.8) (ISO 6336-3, rim thickness factor) in ``rating.bending.Y_B`` and its σ_F0
    that factor above the solid blank's (1e-12), the pinion's unchanged; a rim of 0.4 tooth
    depths warns with a CaseWarning naming the factor and its scope 0.5 < s_R/h_t."""
    blank = {"gear/web_thickness_mm": 30.0}

    def section(rim_mm=None, **more):
        changes = blank | {"gear/rim_thickness_mm": rim_mm} if rim_mm else {}
        # compiled, not under jax.disable_jit (whose eager primitives each compile on their
        # own: this test 2.4 -> 0.9 CPU s in a run of its file)
        return cli.rating_outputs(jio.parse_case(_case(**changes, **more)), str(tmp_path))

    solid, thin = section()["bending"], section(0.8 * 19.2)["bending"]
    y_b = 1.6 * math.log(2.242 / 0.8)
    assert thin["Y_B"] == pytest.approx([1.0, y_b], rel=1e-12)
    ratio = np.asarray(thin["sigma_F0_Pa"]) / np.asarray(solid["sigma_F0_Pa"])
    np.testing.assert_allclose(ratio, [1.0, y_b], rtol=1e-12)
    with pytest.warns(
        jio.CaseWarning, match=r"\[rating\] ISO 6336-3:2019 rim thickness factor Y_B"
    ):
        section(0.4 * 19.2)


def test_a_given_k_fbeta_replaces_iso_and_scales_the_root_stress_alone(tmp_path):
    """``[rating] K_Fbeta = 1.3``: the factor reads 1.3 with source "given" in place of ISO's
    K_Hβ^N_F, σ_F of both gears scales by 1.3/K_Fβ,ISO (σ_F = σ_F0 K_A K_v K_Fβ K_Fα, ISO 6336-3
    (2); 1e-12) and the pitting side is unchanged (σ_H does not read K_Fβ)."""
    # compiled, not under jax.disable_jit (as the rim test above; this test and that one
    # 2.2 -> 1.1 CPU s in a run of their file)
    iso = cli.rating_outputs(jio.parse_case(_case()), str(tmp_path))
    given = cli.rating_outputs(jio.parse_case(_case(**{"rating/K_Fbeta": 1.3})), str(tmp_path))
    assert iso["factors"]["K_Fbeta"]["source"] == "ISO 6336-1 method B"
    assert given["factors"]["K_Fbeta"] == {"value": 1.3, "source": "given"}
    r = 1.3 / iso["factors"]["K_Fbeta"]["value"]
    ratio = np.asarray(given["bending"]["sigma_F_Pa"]) / np.asarray(iso["bending"]["sigma_F_Pa"])
    np.testing.assert_allclose(ratio, [r, r], rtol=1e-12)
    assert given["pitting"]["sigma_H_Pa"] == pytest.approx(iso["pitting"]["sigma_H_Pa"], rel=1e-12)
    assert "| K_Fβ | 1.300 (given) |" in (tmp_path / "rating.md").read_text(encoding="utf-8")


@pytest.mark.slow  # ~5 s idle (two compilations); the fast test below checks the arithmetic
def test_measured_face_load_factor_of_a_crowned_spur_pair(tmp_path):
    """K_Hβ measured on the load map against the closed form of a crowned spur pair: with a
    uniform stiffness k per unit contact length and the pinion's parabolic lead crowning
    c(z) = C (2z/b − 1)², every line in contact at position p closes by one δ_p, so the load per
    unit face width of slice n is Σ_l w = k (n_p δ_p − n_p c_n) and the force balance gives
    Σ_l w = F_n/b + k n_p (c̄ − c_n) (c̄ the mean of c over the slices); averaged over the
    positions, K_Hβ = 1 + k n̄ b (c̄ − min c)/F_n with n̄ the mean number of lines in contact."""
    d = {
        "name": "crowned-spur",
        "pair": {"normal_module_mm": 2.0, "normal_pressure_angle_deg": 20.0},
        "pinion": {"teeth": 24, "face_width_mm": 20.0},
        "gear": {"teeth": 48, "face_width_mm": 20.0},
        "material": {"sigma_H_lim_MPa": 1500.0, "sigma_F_lim_MPa": 430.0},
        "operating": {"torque_Nm": 100.0, "speed_rpm": 1000.0},
        "mesh": {
            "stiffness": "uniform",
            "stiffness_per_length_N_per_mm_per_um": 10.0,
            "slices": 10,
            "positions_per_pitch": 16,
            # the closed form's premise: every cell on the theoretical path, in contact (the
            # cells beyond it, a tip corner's, load only where the teeth deflect enough)
            "extended_contact": False,
        },
        "modifications": {"pinion": {"crowning": {"depth_um": 4.0}}},
        "rating": copy.deepcopy(CASE["rating"]),
    }
    case = jio.parse_case(d)
    mesh = case.mesh_model()
    res = jg.quasi_static(
        mesh, case.modifications, case.torque, jg.mesh_positions(mesh, 16, periods=1)
    )
    mask = np.asarray(res.cell_mask)
    assert np.all(np.asarray(res.line_load)[mask] > 0)  # every cell in contact: the closed form
    k, b, n_slices, crown = 10e9, 0.02, 10, 4e-6
    c = crown * (2 * (np.arange(n_slices) + 0.5) / n_slices - 1) ** 2
    lines = mask.any(axis=-1).sum(axis=-1).mean()
    f_n = case.torque / case.pair.base_radii[0]
    want = 1 + k * lines * b * (c.mean() - c.min()) / f_n
    assert float(jg.rating.face_load_factor(res)) == pytest.approx(want, rel=1e-6)
    section = cli.rating_outputs(case, str(tmp_path), result=res)
    assert section["measured"]["K_Hbeta"]["value"] == pytest.approx(want, rel=1e-6)
    assert "| K_Hβ measured |" in (tmp_path / "rating.md").read_text(encoding="utf-8")


class _Loads(NamedTuple):
    line_load: np.ndarray
    cell_mask: np.ndarray


def test_measured_face_load_factor_by_hand(tmp_path):
    """Two positions, two lines, three slices: the load per unit face width of a slice is the
    sum over the lines (masked cells and negative loads count 0), averaged over positions."""
    w = np.array(
        [[[1.0, 2.0, 3.0], [1.0, 1.0, -5.0]], [[2.0, 2.0, 2.0], [9.0, 9.0, 9.0]]]
    )  # (P, L, N)
    mask = np.array([[[1, 1, 1], [1, 1, 1]], [[1, 1, 1], [0, 0, 0]]], dtype=bool)
    # slices: position 0 -> (2, 3, 3), position 1 -> (2, 2, 2); mean (2, 2.5, 2.5): 2.5/(7/3)
    loads = _Loads(w, mask)
    assert float(jg.rating.face_load_factor(loads)) == pytest.approx(2.5 / (7 / 3), rel=1e-12)
    section = cli.rating_outputs(jio.parse_case(_case()), str(tmp_path), result=loads)
    assert section["measured"]["K_Hbeta"]["value"] == pytest.approx(2.5 / (7 / 3), rel=1e-12)
    assert section["factors"]["K_Hbeta"]["value"] == 1.16  # the given one rates; measured beside


def test_measured_dynamic_factor_is_the_sweep_at_the_rating_speed(tmp_path):
    """jaxgear run's K_v measured (cli.measured_dynamic_factor): the sweep's dynamic factor at
    the rating's pinion speed, linear between the two swept speeds around it, beside ISO's
    (which still rates); a speed outside the sweep adds nothing."""
    case = jio.parse_case(_case())  # 360 1/min = 37.70 rad/s
    section = cli.rating_outputs(case, str(tmp_path))
    w = 360.0 * 2 * math.pi / 60
    dynamics = {"model": "torsional", "slices": 8, "speeds_rad_s": [30.0, 40.0, 50.0]}
    dynamics["dynamic_factor"] = [1.10, 1.30, 1.20]
    cli.measured_dynamic_factor(case, str(tmp_path), {"rating": section}, dynamics)
    want = 1.10 + (w - 30.0) / 10.0 * 0.20  # by hand: 1.2540
    assert section["measured"]["K_v"]["value"] == pytest.approx(want, rel=1e-12)
    assert "torsional scene, 8 slices" in section["measured"]["K_v"]["source"]
    assert section["factors"]["K_v"]["source"] == "ISO 6336-1 method B"
    assert "| K_v measured | 1.254 |" in (tmp_path / "rating.md").read_text(encoding="utf-8")
    outside = {**dynamics, "speeds_rad_s": [100.0, 200.0, 300.0]}
    other = cli.rating_outputs(case, str(tmp_path))
    cli.measured_dynamic_factor(case, str(tmp_path), {"rating": other}, outside)
    assert "measured" not in other
    d = _case()  # a case without [rating]: nothing added, nothing read
    del d["rating"], d["operating"]["speed_rpm"]
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa"):
        del d["material"][key]
    no_rating = jio.parse_case(d)
    summary = {}
    cli.measured_dynamic_factor(no_rating, str(tmp_path), summary, dynamics)
    assert summary == {}


def test_the_wind_turbine_stage_case_file_reproduces_the_published_report(tmp_path):
    """tests/data/rating/wind-helical-stage.toml: the KISSsoft-rated helical stage of
    tests/test_rating_kisssoft.py (provenance there) as a case file, 2006 edition and the
    report's load factors given: S_F, S_H, σ_F0 and σ_HP as printed, within 0.5 %."""
    path = pathlib.Path(__file__).resolve().parent / "data" / "rating" / "wind-helical-stage.toml"
    section = cli.rating_outputs(jio.load_case(str(path)), str(tmp_path))
    assert section["method"] == "ISO 6336:2006 method B"
    got = {k: section[p][k] for p, k in (("bending", "S_F"), ("pitting", "S_H"))}
    got["sigma_F0"] = [v / 1e6 for v in section["bending"]["sigma_F0_Pa"]]
    got["sigma_HP"] = [v / 1e6 for v in section["pitting"]["sigma_HP_Pa"]]
    printed = {
        "S_F": [3.26, 3.09],
        "S_H": [1.81, 1.88],
        "sigma_F0": [117.92, 127.69],
        "sigma_HP": [1070.64, 1109.85],
    }
    for key, want in printed.items():
        assert got[key] == pytest.approx(want, rel=5e-3), key
