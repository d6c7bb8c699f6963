"""The scuffing keys of ``[lubricant]`` (jaxgear.io) and ``jaxgear run``'s flash temperature in
the tribology files, on examples/fzg-c14-lubricated.toml with an FZG load
stage added. The references: the scuffing temperature of ISO/TS 6336-20 written here from the
load stage (θ_S = 80 + 2.25 S_FZG² for X_W = X_L = 1), S_B from the files' own temperatures,
and the CSV's cells against the summary."""

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


def _data(**scuffing):
    data = tomllib.loads(EXAMPLE.read_text())
    data["lubricant"] |= scuffing
    return data


def test_scuffing_keys_build_the_objects():
    inputs = jio.tribology_of(jio.parse_case(_data(fzg_load_stage=9)))
    assert isinstance(inputs.scuffing.limits, tr.ScuffingLimits)
    assert inputs.scuffing.limits.flash() == pytest.approx(80.0 + 2.25 * 81.0)
    assert isinstance(inputs.scuffing.bulk, tr.FlashBulkTemperature)
    given = jio.tribology_of(
        jio.parse_case(
            _data(
                scuffing_temperature_C=300.0,
                integral_scuffing_temperature_C=280.0,
                bulk_temperature_C=95.0,
            )
        )
    )
    assert isinstance(given.scuffing.bulk, tr.GivenBulkTemperature)
    assert given.scuffing.limits.flash() == 300.0
    assert given.scuffing.limits.integral(100e-6) == 280.0
    assert jio.tribology_of(jio.load_case(EXAMPLE)).scuffing is None


@pytest.mark.parametrize(
    "change, match",
    [
        ({"fzg_load_stage": 15}, r"\[lubricant\] fzg_load_stage = 15"),
        ({"scuffing_temperature_C": 300.0}, r"scuffing_temperature_C = 300.*needs fzg_load_stage"),
        ({"structural_factor": 1.2}, r"structural_factor = 1.2.*not read"),
        (
            {"fzg_load_stage": 9, "bulk_temperature_C": 90.0, "bulk_lubrication_factor": 1.2},
            r"bulk_lubrication_factor .*not read",
        ),
    ],
)
def test_scuffing_keys_bad_input_one_line(change, match):
    with pytest.raises(ValueError, match=match) as err:
        jio.parse_case(_data(**change))
    assert "\n" not in str(err.value)


def _scuffing_files(folder, sc: dict, case) -> list:
    """The scuffing section ``sc`` and the files in ``folder`` agree: tribology.json's safety
    factor, the scuffing temperature of the example's oil (80 + 2.25 × 100 °C), S_S = (θ_S −
    θ_oil)/(θ_B,max − θ_oil), tribology.csv's largest flash temperature and its bulk
    temperature, and zero flash temperature where the sliding vanishes (the pitch point).
    Returns the CSV's rows."""
    on_disk = json.loads((folder / "tribology.json").read_text())["scuffing"]
    assert on_disk["scuffing_safety_factor"] == pytest.approx(sc["scuffing_safety_factor"])
    oil = 75.0  # the example's oil temperature
    assert sc["scuffing_temperature_C"] == pytest.approx(80.0 + 2.25 * 100.0)
    assert sc["scuffing_safety_factor"] == pytest.approx(
        (sc["scuffing_temperature_C"] - oil) / (sc["max_contact_temperature_C"] - oil)
    )
    with open(folder / "tribology.csv") as f:
        rows = list(csv.DictReader(f))
    fl = np.array([float(r["flash_temperature_K"]) for r in rows])
    tb = np.array([float(r["contact_temperature_C"]) for r in rows])
    assert fl.max() == pytest.approx(sc["max_flash_temperature_K"], rel=1e-5)
    np.testing.assert_allclose(tb - fl, sc["bulk_temperature_C"], rtol=1e-6)
    s = np.array([float(r["s_m"]) for r in rows])
    s_c = tr.pitch_point_roll(case.pair)
    assert fl[np.argmin(np.abs(s - s_c))] < 0.05 * fl.max()
    return rows


def test_tribology_outputs_write_the_flash_temperature(tmp_path):
    """The files ``jaxgear run`` writes of the scuffing and micropitting keys, from the
    tribology outputs of the quasi-static result at the small size of
    tests/test_micropitting_case.py (1 slice, 16 positions per pitch: its programs): θ_S from
    the load stage, S_B from the files' own temperatures, the CSV's flash temperature its
    maximum and the bulk temperature, near zero at the pitch point; S_λ the CSV's least λ over
    Figure A.1's; the run lines name both."""
    import jaxgear as jg
    from jaxgear.cli.run import tribology_outputs, tribology_run_line

    data = _data(fzg_load_stage=10, micropitting_load_stage=8)
    data["mesh"] |= {"slices": 1, "positions_per_pitch": 16}
    case = jio.parse_case(data)
    res = jg.quasi_static(case.mesh_model(), case.modifications, case.torque,
                          positions_per_pitch=case.positions_per_pitch)
    section = tribology_outputs(case, str(tmp_path), res)
    sc = section["scuffing"]
    rows = _scuffing_files(tmp_path, sc, case)
    mp = section["micropitting"]
    on_disk = json.loads((tmp_path / "tribology.json").read_text())["micropitting"]
    for key in ("min_specific_film", "safety_factor", "bulk_temperature_C"):
        assert on_disk[key] == pytest.approx(mp[key])
    lam = np.array([float(r["micropitting_specific_film"]) for r in rows])
    assert mp["min_specific_film"] == pytest.approx(lam.min(), rel=1e-5)
    lam_p = tr.figure_a1_permissible_film(8, 315.997e-6)  # the example's ν₄₀
    assert mp["permissible_specific_film"] == pytest.approx(lam_p)
    assert mp["safety_factor"] == pytest.approx(lam.min() / lam_p, rel=1e-5)
    lines = tribology_run_line(section)
    assert any("scuffing: max flash" in line for line in lines)
    assert any(line.startswith("micropitting (ISO/TS 6336-22)") for line in lines)


# default tier: tests/test_flash_case.py::test_tribology_outputs_write_the_flash_temperature
# (the same files and lines at 1 slice, 16 positions), tests/test_tribology_case.py::
# test_run_writes_film_and_loss_files (jaxgear run's tribology files on this example)
@pytest.mark.slow
def test_run_writes_the_flash_temperature(tmp_path):
    # the micropitting keys ride along (tests/test_micropitting_case.py reads their outputs)
    case = jio.parse_case(_data(fzg_load_stage=10, micropitting_load_stage=8))
    summary = run_case(case, str(tmp_path), show_progress=False)
    sc = summary["tribology"]["scuffing"]
    rows = _scuffing_files(tmp_path, sc, case)
    assert (tmp_path / "tribology.png").stat().st_size > 10_000
    lines = run_lines(case.form, case, summary)
    assert any("scuffing: max flash" in line for line in lines)
    # micropitting: S_λ and λ_GF,min in tribology.json and summary.json, λ_GF,min the CSV's least
    mp = summary["tribology"]["micropitting"]
    on_disk = json.loads((tmp_path / "tribology.json").read_text())["micropitting"]
    in_summary = json.loads((tmp_path / "summary.json").read_text())["tribology"]["micropitting"]
    for key in ("min_specific_film", "safety_factor", "bulk_temperature_C"):
        assert on_disk[key] == pytest.approx(mp[key]) and in_summary[key] == pytest.approx(mp[key])
    lam = np.array([float(r["micropitting_specific_film"]) for r in rows])
    assert mp["min_specific_film"] == pytest.approx(lam.min(), rel=1e-5)
    lam_p = tr.figure_a1_permissible_film(8, 315.997e-6)  # the example's ν₄₀
    assert mp["permissible_specific_film"] == pytest.approx(lam_p)
    assert mp["safety_factor"] == pytest.approx(lam.min() / lam_p, rel=1e-5)
    assert any(line.startswith("micropitting (ISO/TS 6336-22)") for line in lines)
