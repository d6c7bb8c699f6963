"""Gear sizing (jaxgear.sizing, jaxgear size): the enumeration against a brute-force loop
written here; the bad specs refused in one line naming the key; the traced ISO 1328-1
tolerances against the standard's decimal arithmetic; every candidate's validity against
jaxgear.GearPair's own checks; a candidate written as a case file rated by the case reader's
path (what jaxgear run rates) to the table's S_H, S_F, contact ratios and mass to 1e-9. One
compiled sizing program (one small spec's static values) serves every test here."""

from __future__ import annotations

import copy
import csv
import dataclasses
import math
import tomllib
from fractions import Fraction

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
import jaxgear.sizing as js
from jaxgear.cli import main

# a small helical reducer: 5 modules (2-3 mm, both ISO 54 choices) x z1 12-20, ratio 2 ± 5 %:
# small pinions undercut (x1 = 0), a tight outer diameter and the safety factors reject others
SPEC = {
    "name": "small",
    "operating": {"torque_Nm": 120.0, "speed_rpm": 1500.0},
    "material": {"sigma_H_lim_MPa": 1500.0, "sigma_F_lim_MPa": 430.0,
                 "treatment": "case_hardened", "density_kg_m3": 7830.0},
    "rating": {"life_h": 20000.0, "application_factor": 1.25, "min_safety_pitting": 1.1,
               "min_safety_bending": 1.4, "viscosity_40C_mm2_s": 220.0,
               "roughness_Rz_flank_um": 4.0, "roughness_Rz_root_um": 16.0, "accuracy_grade": 6},
    "sizing": {"ratio": 2.0, "ratio_tolerance_percent": 5.0, "normal_module_min_mm": 2.0,
               "normal_module_max_mm": 3.0, "module_series": "both", "z1_min": 12,
               "z1_max": 20, "helix_angle_deg": 15.0, "profile_shift": [0.0, 0.1],
               "face_width_min_mm": 12.0, "face_width_max_mm": 30.0,
               "face_width_ratio_max": 0.6, "outer_diameter_max_mm": 118.0,
               "tip_thickness_min": 0.0,
               "dynamics_candidates": 0},  # the dynamics stage: tests/test_sizing_dynamics.py
}


def _spec(**sizing):
    data = copy.deepcopy(SPEC)
    data["sizing"].update(sizing)
    return data


def _refused(data, message):
    """``data`` (a spec's tables) refused at load in one line starting with ``message``."""
    with pytest.raises(ValueError) as err:
        jio.parse_sizing_spec(data)
    text = str(err.value)
    assert text.startswith(message) and "\n" not in text, text


def _brute_force(data):
    """Every (m_n mm, z1, z2) of the spec by loops, exact ratios (fractions of the decimal
    values), ISO 54's modules typed here, the zero-backlash centre distance of the shifts."""
    s = data["sizing"]
    first = [1, 1.25, 1.5, 2, 2.5, 3, 4, 5, 6, 8, 10, 12, 16, 20, 25, 32, 40, 50]
    second = [1.125, 1.375, 1.75, 2.25, 2.75, 3.5, 4.5, 5.5, 7, 9, 11, 14, 18, 22, 28, 36, 45]
    series = {"first": first, "second": second, "both": first + second}[s["module_series"]]
    u, tol = Fraction(str(s["ratio"])), Fraction(str(s["ratio_tolerance_percent"])) / 100
    out = []
    for m in sorted(series):
        if not s["normal_module_min_mm"] <= m <= s["normal_module_max_mm"]:
            continue
        for z1 in range(s["z1_min"], s["z1_max"] + 1):
            for z2 in range(1, 20 * z1 + 1):
                if abs(Fraction(z2, z1) - u) > tol * u:
                    continue
                if "centre_distance_min_mm" in s:
                    an = math.radians(s.get("normal_pressure_angle_deg", 20.0))
                    beta = math.radians(s["helix_angle_deg"])
                    at = math.atan(math.tan(an) / math.cos(beta))
                    inv = math.tan(at) - at + 2 * math.tan(an) * sum(s["profile_shift"]) / (z1 + z2)
                    a_ = 0.3
                    for _ in range(60):  # inv α = tan α − α, Newton
                        a_ -= (math.tan(a_) - a_ - inv) / math.tan(a_) ** 2
                    a = (z1 + z2) * m / math.cos(beta) / 2 * math.cos(at) / math.cos(a_)
                    if not s["centre_distance_min_mm"] <= a <= s["centre_distance_max_mm"]:
                        continue
                out.append((m, z1, z2))
    return out


@pytest.mark.parametrize("window", [None, (70.0, 78.0)])
def test_enumeration_equals_a_brute_force_loop(window):
    data = _spec() if window is None else _spec(centre_distance_min_mm=window[0],
                                               centre_distance_max_mm=window[1])
    spec, _ = jio.parse_sizing_spec(data)
    c = js.enumerate_candidates(spec)
    got = [(round(m * 1e3, 9), int(a), int(b)) for m, a, b in zip(c.normal_module, c.z1, c.z2)]
    want = _brute_force(data)
    assert got == want and len(want) > 10


def test_fixed_centre_distance_gives_shift_sums_that_reach_it():
    spec, _ = jio.parse_sizing_spec(_spec(centre_distance_mm=75.0, profile_shift_sum_min=-0.5,
                                          profile_shift_sum_max=1.0))
    c = js.enumerate_candidates(spec)
    assert len(c) > 0 and np.all(c.x1 == 0.0)
    for k in range(len(c)):  # GearPair's zero-backlash distance of those shifts: 75 mm
        pair = jg.GearPair(jg.Member(int(c.z1[k]), float(c.x1[k]), 1.0, 1.25, 0.02, 0.38),
                           jg.Member(int(c.z2[k]), float(c.x2[k]), 1.0, 1.25, 0.02, 0.38),
                           normal_module=float(c.normal_module[k]),
                           normal_pressure_angle=math.radians(20), helix_angle=math.radians(15))
        assert pair.center_distance == pytest.approx(0.075, rel=1e-12)
        assert -0.5 <= c.x1[k] + c.x2[k] <= 1.0


BAD = [
    ({"z1_max": 10}, "[sizing] z1_max = 10: below z1_min = 12: an empty range"),
    ({"ratio_tolerance_percent": 0.0, "ratio": 2.03, "z1_max": 14},
     "[sizing] ratio_tolerance_percent = 0: no tooth counts z1 in [12, 14]"),
    ({"normal_module_min_mm": 3.1, "normal_module_max_mm": 3.4, "module_series": "first"},
     "[sizing] normal_module_max_mm = 3.4: no module of ISO 54's first choice"),
    ({"centre_distance_min_mm": 10.0, "centre_distance_max_mm": 20.0},
     "[sizing] centre_distance_min_mm = 10: no candidate's centre distance lies in [10, 20] mm"),
    ({"centre_distance_mm": 75.0, "centre_distance_min_mm": 70.0},
     "[sizing] centre_distance_mm = 75: give a fixed centre distance or a window"),
    ({"outer_diameter_max_mm": 40.0},
     "[sizing] outer_diameter_max_mm = 40: at or below the smallest gear's"),
    ({"face_width_ratio_max": 0.05}, "[sizing] face_width_ratio_max = 0.05: below"),
    ({"ratio": 0.5}, "[sizing] ratio = 0.5: out of range"),
    ({"fillet_radius_coeff": 1.3}, "[sizing] fillet_radius_coeff = 1.3: out of range"),
    ({"speed": 1}, "[sizing] unknown key 'speed'"),
]


@pytest.mark.parametrize("change,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_specs_are_refused_in_one_line_naming_the_key(change, message):
    _refused(_spec(**change), message)


def test_operating_needs_one_of_torque_or_power():
    data = _spec()
    data["operating"]["power_kW"] = 10.0
    with pytest.raises(ValueError, match=r"^\[operating\] torque_Nm = 120: give one of"):
        jio.parse_sizing_spec(data)
    del data["operating"]["torque_Nm"]
    spec, _ = jio.parse_sizing_spec(data)
    assert float(spec.operating.torque) == pytest.approx(10e3 / (1500 * math.pi / 30), 1e-14)


def test_traced_iso1328_tolerances_equal_the_standards_decimal_arithmetic():
    """Every module of ISO 54 (1-10 mm), diameters of 10-200 teeth spur and helical, face
    widths of whole and odd millimetres, the classes 1-6, 9, 11 (the odd and even steps): the jnp path rounds as the
    standard's decimal arithmetic (ties included) does: the same values to the last bit but
    one (the µm-to-m product of a rounded value may land one ulp apart; a rounding step apart
    would be 1e-3 relative or more)."""
    mods = [m * 1e-3 for m in js.ISO54_FIRST + js.ISO54_SECOND if m <= 10]
    rows = []
    for m in mods:
        for z in (10, 23, 81, 200):
            for beta in (0.0, math.radians(15.0)):
                for b in (0.004, 0.0125, 0.0577):
                    rows.append((m, z * m / math.cos(beta), b))
    mn, d, b = (np.array(c) for c in zip(*rows))
    for grade in (1, 2, 3, 4, 5, 6, 9, 11):
        got = np.stack([np.asarray(v) for v in jg.iso1328_tolerances_array(mn, d, b, grade)])
        ref = np.array([[t.single_pitch, t.profile_form, t.helix_slope] for t in
                        (jg.iso1328_tolerances(*r, grade) for r in rows)]).T
        np.testing.assert_allclose(got, ref, rtol=3e-16, atol=0, err_msg=f"grade {grade}")


@pytest.fixture(scope="module")
def sized():
    spec, tables = jio.parse_sizing_spec(_spec())
    return spec, tables, js.size(spec)  # the default chunk: jaxgear size's program


def _pair(row, spec):
    members = [jg.Member(int(row[z]), float(row[x]), spec.addendum_coeff, spec.dedendum_coeff,
                         float(row["face_width_m"]), spec.fillet_radius_coeff)
               for z, x in (("z1", "x1"), ("z2", "x2"))]
    return jg.GearPair(*members, normal_module=float(row["normal_module_m"]),
                       normal_pressure_angle=spec.normal_pressure_angle,
                       helix_angle=spec.helix_angle)


def test_rejections_agree_with_the_pairs_own_checks(sized):
    """A candidate fails a check of the geometry exactly when jaxgear.GearPair refuses it; the
    space limits and safety factors read back from the columns."""
    spec, _, table = sized
    names = list(js.CHECKS)
    geometric = table.failed[:, [names.index(k) for k in js.GEOMETRIC]].any(axis=1)
    refused = []
    for k in range(len(table)):
        row = {n: v[k] for n, v in table.columns.items()}
        try:
            _pair(row, spec)
            refused.append(False)
        except ValueError:
            refused.append(True)
    assert np.array_equal(np.array(refused), geometric)
    assert 0 < geometric.sum() < len(table) and 0 < table.feasible.sum()
    c, f = table.columns, table.failed
    ok = ~geometric
    assert np.array_equal(f[:, names.index("outer_diameter")],
                          np.maximum(c["tip_diameter_1_m"], c["tip_diameter_2_m"]) > 0.118)
    s_h = np.minimum(c["S_H1"], c["S_H2"])
    assert np.array_equal(f[ok, names.index("pitting")], s_h[ok] < 1.1)
    assert f[:, names.index("pitting")].any() and f[:, names.index("outer_diameter")].any()
    assert np.all(np.isnan(c["S_H1"][geometric])) and np.all(np.isfinite(c["S_H1"][ok]))


def _rated_case(text):
    """The rating jaxgear run makes of a case file's text: the case reader's rating, rated
    (compiled, as one program: half the cost of the run's op-by-op call here, the same
    numbers; the slow tier runs the whole jaxgear run)."""
    case = jio.parse_case(tomllib.loads(text))
    rc = jio.rating_of(case)
    return case, eqx.filter_jit(jr.rate)(rc.geometry, rc.operating, rc.settings)


def _rates_as_row(case, rating, row) -> None:
    """The written case's rating (safety factors), contact ratios, centre distance and blank
    mass equal the table row's to 1e-9 (the refine tests use it too)."""
    close = lambda a, b: np.testing.assert_allclose(a, b, rtol=1e-9, atol=0)
    close(rating.pitting.S_H, [row["S_H1"], row["S_H2"]])
    close(rating.bending.S_F, [row["S_F1"], row["S_F2"]])
    p = case.pair
    close(p.transverse_contact_ratio, row["eps_alpha"])
    close(p.overlap_ratio, row["eps_beta"])
    close(p.center_distance, row["centre_distance_m"])
    # the blank: the root cylinder and half the annulus to the tip, written from the radii
    mass = sum(case.density * p.face_width * math.pi * (ra**2 + rf**2) / 2
               for ra, rf in zip(p.tip_radii, p.root_radii, strict=True))
    close(mass, row["mass_kg"])


def test_a_written_candidate_rates_to_the_tables_numbers(sized):
    spec, tables, table = sized
    k = int(table.ranked()[0])
    row = {n: v[k] for n, v in table.columns.items()}
    case, rating = _rated_case(jio.candidate_case_text(tables, spec, row, k))
    _rates_as_row(case, rating, row)
    np.testing.assert_allclose(rating.factors.K_v, row["K_v"], rtol=1e-9, atol=0)
    # ranked lightest first among the feasible
    feasible_mass = table.columns["mass_kg"][table.feasible]
    assert row["mass_kg"] == feasible_mass.min()


@pytest.mark.usefixtures("no_figures")
def test_jaxgear_size_writes_the_table_and_a_candidate(sized, tmp_path, capsys):
    spec, tables, table = sized
    path = tmp_path / "small.toml"
    path.write_text(_toml(SPEC))
    out = tmp_path / "out"
    k = int(table.ranked()[1])
    assert main(["size", str(path), "--out", str(out), "--write", str(k), "--quiet",
                 "--te", "0"]) == 0  # the TE stage: tests/test_sizing_te.py
    with open(out / "sizing.csv", encoding="utf-8") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(table)
    reasons = table.reasons()
    for i, r in enumerate(rows):
        assert int(r["z2"]) == table.columns["z2"][i] and r["rejected"] == reasons[i]
        assert r["feasible"] == str(int(reasons[i] == ""))
        assert (r["S_H1"] == "") == bool(np.isnan(table.columns["S_H1"][i]))
    # the case file of row k (rated to the row's numbers: the test above)
    row = {n: v[k] for n, v in table.columns.items()}
    written = (out / f"candidate_{k}.toml").read_text(encoding="utf-8")
    assert written == jio.candidate_case_text(tables, spec, row, k)
    assert [float(rows[k][n]) for n in ("S_H1", "S_F2", "mass_kg")] == [
        row["S_H1"], row["S_F2"], row["mass_kg"]]  # full precision in the CSV
    assert main(["size", str(path), "--out", str(out), "--write", "100000"]) == 2
    assert "--write 100000: out of range, allowed a candidate row 0" in capsys.readouterr().err
    bad = int(np.flatnonzero(np.isnan(table.columns["S_H1"]))[0])  # an undercut pinion
    assert main(["size", str(path), "--out", str(tmp_path / "o2"), "--write", str(bad),
                 "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"--write {bad}: candidate {bad} has no valid geometry (" in err[0]
    assert not (tmp_path / "o2").exists()


def _toml(data) -> str:
    lines = [f'name = "{data["name"]}"']
    for table, values in data.items():
        if isinstance(values, dict):
            lines.append(f"[{table}]")
            for k, v in values.items():
                lines.append(f"{k} = " + (f'"{v}"' if isinstance(v, str) else repr(v)))
    return "\n".join(lines) + "\n"


# default tier: test_a_written_candidate_rates_to_the_tables_numbers (the same claim through
# the case reader's rating, without the rest of jaxgear run)
@pytest.mark.slow
def test_jaxgear_run_rates_a_written_candidate_to_the_tables_numbers(sized, tmp_path):
    """The whole ``jaxgear run`` on a written candidate (its quasi-static analysis too):
    summary.json's rating and geometry equal the table's row to 1e-9."""
    import json

    spec, tables, table = sized
    k = int(table.ranked()[0])
    row = {n: v[k] for n, v in table.columns.items()}
    path = tmp_path / "candidate.toml"
    path.write_text(jio.candidate_case_text(tables, spec, row, k), encoding="utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "run"), "--quiet"]) == 0
    summary = json.loads((tmp_path / "run" / "summary.json").read_text(encoding="utf-8"))
    r, g = summary["rating"], summary["geometry"]
    np.testing.assert_allclose(r["pitting"]["S_H"], [row["S_H1"], row["S_H2"]], rtol=1e-9)
    np.testing.assert_allclose(r["bending"]["S_F"], [row["S_F1"], row["S_F2"]], rtol=1e-9)
    np.testing.assert_allclose(g["transverse_contact_ratio"], row["eps_alpha"], rtol=1e-9)
    np.testing.assert_allclose(g["overlap_ratio"], row["eps_beta"], rtol=1e-9)


# default tier: tests/test_sizing.py::test_jaxgear_size_writes_the_table_and_a_candidate (the
# command on a small spec)
@pytest.mark.slow
def test_example_spec_sizes_and_ranks(tmp_path, capsys):
    """The example spec (examples/sizing/helical.toml): every candidate rated, some feasible,
    the printed ranking lightest first."""
    import pathlib

    spec_path = pathlib.Path(__file__).resolve().parents[1] / "examples" / "sizing" / "helical.toml"
    assert main(["size", str(spec_path), "--out", str(tmp_path / "o"), "--top", "3"]) == 0
    text = capsys.readouterr().out
    masses = [float(line.split()[5]) for line in text.splitlines()[3:6]]
    assert masses == sorted(masses) and len(masses) == 3, text


def test_traced_teeth_geometry_and_accuracy_from_dimensions_refuse_and_agree():
    """The batch kinds' own refusals (one line naming the argument), and the accuracy of a
    pair's dimensions equal to the pair's (the decimal path) for a helical pair."""
    pair = jg.GearPair(jg.Member(23, 0.2, face_width=0.03), jg.Member(79, 0.0, face_width=0.028),
                       normal_module=2.75e-3, normal_pressure_angle=math.radians(20),
                       helix_angle=math.radians(15))
    g = jr.TracedTeethRatingGeometry.of(pair)
    assert g.teeth.shape == (2,) and list(np.asarray(g.teeth)) == [23.0, 79.0]
    fields = {f.name: getattr(g, f.name) for f in dataclasses.fields(g)}
    with pytest.raises(ValueError, match=r"^TracedTeethRatingGeometry: teeth of shape \(3,\)"):
        jr.TracedTeethRatingGeometry(**(fields | {"teeth": np.array([23.0, 79.0, 5.0])}))
    with pytest.raises(ValueError, match=r"^TracedTeethRatingGeometry.of_geometry: geometry = "
                       r".*\(GearPair\) is out of range: allowed a jaxgear.rating.RatingGeometry"):
        jr.TracedTeethRatingGeometry.of_geometry(pair)
    d = np.array(pair.pitch_radii) * 2
    got = jr.GearAccuracy.from_dimensions(2.75e-3, d, [0.03, 0.028], 7)
    ref = jr.GearAccuracy.from_grade(pair, 7)
    for name in ("base_pitch", "profile_form", "helix_slope"):
        np.testing.assert_allclose(getattr(got, name), getattr(ref, name), rtol=3e-16)
    assert got.grade == 7
    with pytest.raises(ValueError, match=r"^ISO 1328-1 grade = 12 is out of range"):
        jr.GearAccuracy.from_dimensions(2.75e-3, d, [0.03, 0.028], 12)


def test_jaxgear_size_refuses_a_bad_spec_in_one_line_before_work(tmp_path, capsys):
    bad = copy.deepcopy(SPEC)
    bad["sizing"]["z1_max"] = 10
    path = tmp_path / "bad.toml"
    path.write_text(_toml(bad))
    out = tmp_path / "out"
    assert main(["size", str(path), "--out", str(out)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "[sizing] z1_max = 10: below z1_min = 12: an empty range" in err[0]
    assert not out.exists()
    assert main(["size", str(tmp_path / "none.toml")]) == 2
    assert "none.toml: no such sizing spec file" in capsys.readouterr().err


@pytest.mark.usefixtures("no_figures")
def test_the_table_as_parquet_equals_the_csv(request, tmp_path):
    """sizing.parquet holds the table (read back column by column)."""
    import pyarrow.parquet as pq

    table = request.getfixturevalue("sized")[2]
    path = tmp_path / "small.toml"
    path.write_text(_toml(SPEC))
    assert main(["size", str(path), "--out", str(tmp_path / "o"), "--quiet", "--te", "0"]) == 0
    got = pq.read_table(tmp_path / "o" / "sizing.parquet").to_pydict()
    for name, col in table.columns.items():
        np.testing.assert_array_equal(np.asarray(got[name], dtype=float), col.astype(float))
    assert got["rejected"] == table.reasons()


@pytest.mark.parametrize("table,key,value,message", [
    ("rating", "use_measured", ["K_Hbeta"], "[rating] use_measured: not read by a sizing"),
    ("rating", "life_h", None, "[rating] life_h: missing required key"),
    ("material", "sigma_H_lim_MPa", 5.0, "[material] sigma_H_lim_MPa = 5: out of range"),
    ("operating", "speed_rpm", None, "[operating]"),
    ("sizing", None, None, "[sizing]: missing required table"),
])
def test_the_case_tables_of_a_spec_are_the_case_readers(table, key, value, message):
    """``[material]`` and ``[rating]`` refused as a case's are (their readers), the sizing's
    own tables required."""
    data = _spec()
    if key is None:
        del data[table]
    elif value is None:
        del data[table][key]
    else:
        data[table][key] = value
    with pytest.raises(ValueError) as err:
        jio.parse_sizing_spec(data)
    assert str(err.value).startswith(message) and "\n" not in str(err.value), str(err.value)
