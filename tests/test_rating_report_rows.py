"""rating.md's rows of the geometry, the tool, the oil and the scuffing verdicts, and the
printed line of a lubricated run: each value against the case file's inputs evaluated here
(ISO 21771's d_a = d + 2 m_n (h_a* + x), d_f = d − 2 m_n (h_f* − x), d = z m_n/cos β)."""

from __future__ import annotations

import math
import re
import tomllib

import pytest

import jaxgear.io as jio
from jaxgear import cli
from jaxgear.cli._tribology_run import (
    efficiency_run_line,
    tribology_rating_lines,
    tribology_run_line,
)


def _cells(md: str, quantity_start: str) -> list[str]:
    for line in md.splitlines():
        if line.startswith(f"| {quantity_start}"):
            return [c.strip() for c in line.strip("|").split("|")]
    raise AssertionError(f"no row {quantity_start!r}")


def _nums(cell: str) -> list[float]:
    return [float(x) for x in re.findall(r"-?\d+(?:\.\d+)?(?:e[+-]\d+)?", cell)]


def _data(**changes):
    data = tomllib.loads(jio.embedded_case_text("fzg-h951"))
    for path, value in changes.items():
        table, key = path.split("/")
        data[table][key] = value
    return data


def _report(tmp_path, data) -> str:
    cli.rating_outputs(jio.parse_case(data), str(tmp_path))
    return (tmp_path / "rating.md").read_text(encoding="utf-8")


def test_rating_md_has_the_tool_diameters_oil_and_minimum_safety_source(tmp_path):
    data = _data()
    md = _report(tmp_path, data)
    mn, beta = data["pair"]["normal_module_mm"], math.radians(data["pair"]["helix_angle_deg"])
    for k, tag in enumerate(("pinion", "gear")):
        m = data[tag]
        d = m["teeth"] * mn / math.cos(beta)
        d_a = d + 2 * mn * (m["addendum_coeff"] + m["profile_shift"])
        d_f = d - 2 * mn * (m["dedendum_coeff"] - m["profile_shift"])
        assert _nums(_cells(md, "tip diameter")[2])[k] == pytest.approx(d_a, rel=5e-4)
        assert _nums(_cells(md, "root diameter")[2])[k] == pytest.approx(d_f, rel=5e-4)
        rack = {"h_fP*": m["dedendum_coeff"], "ρ_fP*": m["fillet_radius_coeff"],
                "h_a*": m["addendum_coeff"]}
        for symbol, want in rack.items():
            row = next(c for c in (
                [x.strip() for x in ln.strip("|").split("|")] for ln in md.splitlines()
                if ln.startswith("| ")) if len(c) > 2 and c[1] == symbol)
            assert _nums(row[2])[k] == pytest.approx(want, rel=5e-4), symbol
    assert _nums(_cells(md, "basic rack (tool): pressure angle")[2]) == [
        pytest.approx(data["pair"]["normal_pressure_angle_deg"])]
    # GEARpie's printed radii (REPORT/H951.txt), diameters here
    assert _nums(_cells(md, "tip diameter")[2]) == pytest.approx([76.23, 111.7], abs=0.01)
    lub = data["lubricant"]
    assert _nums(_cells(md, "oil ([lubricant]): kinematic viscosity at 40 °C")[2])[-1] == (
        pytest.approx(lub["viscosity_40C_mm2_s"], rel=5e-4))
    assert _nums(_cells(md, "oil temperature")[2]) == [pytest.approx(lub["oil_temperature_C"])]
    assert "Warning: two oils" not in md
    # without the report-only keys: a dash, not a made-up value
    bare = _data()
    del bare["material"]["designation"], bare["material"]["surface_hardness_HV"]
    md_bare = _report(tmp_path, bare)
    assert _cells(md_bare, "material designation")[2] == "— (not given)"
    assert _cells(md_bare, "surface hardness")[2] == "— (not given)"
    md = _report(tmp_path, data)
    # the material as the file names it
    assert _cells(md, "material designation")[2] == f"{data['material']['designation']} / " \
        f"{data['material']['designation']}"
    assert _nums(_cells(md, "surface hardness")[2]) == [data["material"]["surface_hardness_HV"]] * 2
    # the minimum safety factors: the default named with its source and practice's values
    s_h = [c.strip() for c in next(ln for ln in md.splitlines()
                                   if ln.startswith("| S_H |")).strip("|").split("|")]
    assert s_h[2] == "S_Hmin = 1.000" and s_h[3] == "pass / pass"
    assert "without them jaxgear takes 1.0" in md and "S_Hmin = 1.25 and S_Fmin = 1.56" in md


def test_rating_md_warns_when_the_rating_and_the_lubricant_differ_in_oil(tmp_path):
    md = _report(tmp_path, _data(**{"rating/viscosity_40C_mm2_s": 220.0}))
    (line,) = [ln for ln in md.splitlines() if "Warning: two oils" in ln]
    assert "ν₄₀ = 220.0 mm²/s" in line and "ν₄₀ = 316.0 mm²/s" in line


def _scuffing_section(s_b, s_int):
    return {
        "film_formula": "dowson-higginson", "friction": "schlenk", "friction_coefficient": 0.04,
        "min_specific_film": 1.2, "mean_power_loss_W": 50.0, "efficiency": 0.995,
        "loss_factor_integrated": 0.1, "loss_factor_ohlendorf": 0.1,
        "max_flash_temperature_K": 42.25,
        "scuffing": {"max_flash_temperature_K": 42.25, "max_contact_temperature_C": 150.0,
                     "scuffing_temperature_C": 300.0, "scuffing_safety_factor": s_b,
                     "integral_temperature_C": 140.0, "integral_scuffing_temperature_C": 250.0,
                     "integral_scuffing_safety_factor": s_int},
    }


def test_scuffing_rows_have_minimum_verdict_and_the_oil():
    case = jio.parse_case(_data(**{"rating/viscosity_40C_mm2_s": 220.0}))
    lines = tribology_rating_lines(_scuffing_section(0.8, 1.6), case)
    s_b = next(ln for ln in lines if ln.startswith("| S_B |"))
    s_int = next(ln for ln in lines if ln.startswith("| S_intS |"))
    assert "| 0.80 | S_Bmin = 1 | FAIL |" in s_b and "max θ_fl 42.2 K" in s_b
    assert "| 1.60 | S_intSmin = 1 | pass |" in s_int
    assert any(ln.startswith("Oil ([lubricant]): ν₄₀ 315.997 mm²/s") and "θ_oil 75 °C" in ln
               for ln in lines)
    assert any("Warning: two oils" in ln for ln in lines)
    same = tribology_rating_lines(_scuffing_section(2.0, 2.0), jio.parse_case(_data()))
    assert any("uses the same oil" in ln for ln in same)


def test_printed_line_names_the_max_flash_temperature():
    section = _scuffing_section(2.0, 2.0)
    del section["scuffing"]  # a lubricated run without scuffing keys
    (film,) = tribology_run_line(section)
    assert "max flash temperature 42.2 K" in film
    # with scuffing keys the scuffing line names it, once
    lines = tribology_run_line(_scuffing_section(2.0, 2.0))
    assert sum("max flash temperature 42.2 K" in ln for ln in lines) == 1


@pytest.mark.parametrize(
    "change, match",
    [
        ({"designation": ""}, r"^\[material\] designation = '': must be a material name"),
        ({"designation": ["16MnCr5"]}, r"^\[material\] designation = \['16MnCr5'\]: must be a material"),
        ({"surface_hardness_HV": 50.0},
         r"^\[material\] surface_hardness_HV = 50: out of range, allowed \[100, 1000\]"),
    ],
)
def test_material_identity_keys_refused_in_one_line(change, match):
    data = _data()
    data["material"].update(change)
    with pytest.raises(ValueError, match=match) as err:
        jio.parse_case(data)
    assert "\n" not in str(err.value)


def test_train_efficiency_line_names_the_hottest_mesh():
    flow = {"efficiency": 0.99, "total_loss_W": 10.0, "input_power_W": 1000.0,
            "names": ["a-b", "b-c"], "efficiency_each": [0.995, 0.995]}
    meshes = {"a-b": {"max_flash_temperature_K": 12.25},
              "b-c": {"scuffing": {"max_flash_temperature_K": 30.5}}}
    (line,) = efficiency_run_line({"overall": flow, "meshes": meshes})
    assert ", max flash temperature 30.5 K (b-c) (tribology.json)" in line
    (bare,) = efficiency_run_line(flow)
    assert "flash" not in bare
