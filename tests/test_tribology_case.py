"""The ``[lubricant]`` table (jaxgear.io) and ``jaxgear run``'s film and loss files,
on examples/fzg-c14-lubricated.toml: GEARpie's FZG C14 inputs, whose
Schlenk μ (0.0483) and Ohlendorf H_V (0.1950) its report gives (REPORT/C14.txt, commit 039d496)."""

from __future__ import annotations

import csv
import json
import pathlib
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.tribology as tr
from jaxgear.cli.run import run_case, run_lines

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "fzg-c14-lubricated.toml"


def _data():
    return tomllib.loads(EXAMPLE.read_text())


def test_lubricant_table_builds_the_objects():
    case = jio.load_case(EXAMPLE)
    inputs = jio.tribology_of(case)
    assert isinstance(inputs.lubricant, tr.Lubricant)
    assert isinstance(inputs.friction, tr.Schlenk)
    assert isinstance(inputs.film, tr.DowsonHigginson)
    assert inputs.roughness == pytest.approx((0.6e-6, 0.6e-6))
    assert inputs.speed == pytest.approx(157.0796)
    # GEARpie's ν and η at 75 °C (53.10 mm²/s, 46.23 mPa·s)
    assert float(inputs.lubricant.kinematic_viscosity()) * 1e6 == pytest.approx(53.10, abs=0.01)
    assert float(inputs.lubricant.dynamic_viscosity) * 1e3 == pytest.approx(46.23, abs=0.01)
    data = _data()
    data["lubricant"] |= {"friction_coefficient": 0.05, "film": "pan-hamrock"}
    del data["lubricant"]["lubricant_factor"]
    inputs = jio.tribology_of(jio.parse_case(data))
    assert isinstance(inputs.friction, tr.GivenFriction)
    assert float(inputs.friction.value) == 0.05
    assert isinstance(inputs.film, tr.PanHamrock)
    assert jio.tribology_of(jio.load_case("accessory-spur")) is None


@pytest.mark.parametrize(
    "change, match",
    [
        ({"viscosity_100C_mm2_s": 400.0}, r"\[lubricant\] viscosity_100C_mm2_s = 400"),
        ({"oil_temperature_C": 300.0}, r"\[lubricant\] oil_temperature_C = 300"),
        ({"roughness_Ra_um": [0.6]}, r"roughness_Ra_um"),
        ({"film": "reynolds"}, r"film"),
        ({"viscosity_40_mm2s": 1.0}, r"viscosity_40_mm2s"),
        ({"friction_coefficient": 0.05}, r"lubricant_factor .*not read"),
    ],
)
def test_lubricant_table_bad_input_one_line(change, match):
    data = _data()
    data["lubricant"] |= change
    with pytest.raises(ValueError, match=match) as err:
        jio.parse_case(data)
    assert "\n" not in str(err.value)


def test_lubricant_needs_a_speed():
    data = _data()
    del data["operating"]["speed_rad_s"]
    with pytest.raises(ValueError, match=r"\[operating\] speed_rad_s = 0.*\[lubricant\]"):
        jio.parse_case(data)


def test_tribology_outputs_write_film_and_loss_files(tmp_path):
    """The film and loss files ``jaxgear run`` writes, from the tribology outputs of the
    example's quasi-static result at 1 slice and 16 positions per pitch (tests/
    test_flash_case.py's twin: its programs): the checks below (GEARpie's μ and H_V depend on
    the geometry and the oil alone)."""
    import jaxgear as jg
    from jaxgear.cli.run import tribology_outputs, tribology_run_line

    data = _data()
    data["mesh"] |= {"slices": 1, "positions_per_pitch": 16}
    case = jio.parse_case(data)
    res = jg.quasi_static(case.mesh_model(), case.modifications, case.torque,
                          positions_per_pitch=case.positions_per_pitch)
    section = tribology_outputs(case, str(tmp_path), res)
    _film_and_loss_files(case, tmp_path, section, tribology_run_line(section))


# default tier: test_tribology_outputs_write_film_and_loss_files above (the same files and
# lines at 1 slice, 16 positions); tests/test_every_kind.py runs jaxgear run on a pair
@pytest.mark.slow
def test_run_writes_film_and_loss_files(tmp_path):
    """The checks below on ``jaxgear run``'s own files (run_case) at the example's size."""
    case = jio.load_case(EXAMPLE)
    summary = run_case(case, str(tmp_path), show_progress=False)
    _film_and_loss_files(case, tmp_path, summary["tribology"], run_lines(case.form, case, summary))


def _film_and_loss_files(case, tmp_path, section, lines):
    """GEARpie's μ and H_V in tribology.json, the loss μ H_V P_in, the CSV's rows on the loaded
    path and beyond it, the figure, the printed line, Blok's flash temperature at the hottest
    cell from the file's own columns."""
    on_disk = json.loads((tmp_path / "tribology.json").read_text())
    assert on_disk["friction_coefficient"] == pytest.approx(0.0483, abs=5e-5)  # GEARpie
    assert on_disk["loss_factor_ohlendorf"] == pytest.approx(0.1950, abs=5e-5)  # GEARpie
    assert section["mean_power_loss_W"] == pytest.approx(on_disk["mean_power_loss_W"])
    # the loss is μ H_V P_in with the run's own H_V (its load sharing)
    assert section["mean_power_loss_W"] == pytest.approx(
        section["friction_coefficient"]
        * section["loss_factor_integrated"]
        * section["input_power_W"],
        rel=1e-5,
    )
    assert section["input_power_W"] == pytest.approx(200.0 * 157.0796, rel=1e-6)
    with open(tmp_path / "tribology.csv") as f:
        rows = list(csv.DictReader(f))
    lam = np.array([float(r["specific_film"]) for r in rows])
    assert lam.min() == pytest.approx(section["min_specific_film"], rel=1e-5)
    s = np.array([float(r["s_m"]) for r in rows])
    # on the loaded path: the theoretical one and the cells beyond its ends (the case files'
    # default, docs/extended-contact.md), where the corners of this unmodified pair touch
    before, after = (float(x) for x in case.mesh_model().extension_span)
    g = case.pair.path_of_contact
    assert s.min() < 0.0 and s.max() > g  # the loaded corners' rows are there
    assert s.min() >= -before * (1 + 1e-6) and s.max() <= (g + after) * (1 + 1e-6)
    assert (tmp_path / "tribology.png").stat().st_size > 10_000
    assert any("film and loss" in line for line in lines)
    # Blok's flash temperature along the path, written without the scuffing keys: at the
    # hottest cell, Blok's formula again from the file's own columns (spur: speeds normal to
    # the line are the transverse ones; R from p₀ = √(w E*/(π R)), b_H = √(4 w R/(π E*)))
    fl = np.array([float(r["flash_temperature_K"]) for r in rows])
    assert fl.max() == pytest.approx(section["max_flash_temperature_K"], rel=1e-9)
    # the printed line names it (no scuffing keys here: the film line carries it)
    (film_line,) = [ln for ln in lines if "film and loss" in ln]
    assert f"max flash temperature {fl.max():.1f} K" in film_line
    hot = rows[int(np.argmax(fl))]
    w, p0 = float(hot["line_load_N_per_m"]), float(hot["max_pressure_Pa"])
    u, vg = float(hot["entrainment_speed_m_s"]), float(hot["sliding_speed_m_s"])
    e_star = 1.0 / (2 * (1 - 0.3**2) / 206e9)
    r_rel = w * e_star / (np.pi * p0**2)
    b_h = np.sqrt(4 * w * r_rel / (np.pi * e_star))
    v1, v2 = u + vg / 2, u - vg / 2
    b_m = tr.STEEL_THERMAL_CONTACT_COEFFICIENT
    blok = 1.11 * section["friction_coefficient"] * w * vg / (
        b_m * (np.sqrt(v1) + np.sqrt(v2)) * np.sqrt(2 * b_h)
    )
    assert fl.max() == pytest.approx(blok, rel=1e-6)
