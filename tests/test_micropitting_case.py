"""The micropitting keys of ``[lubricant]`` (jaxgear.io) and what ``jaxgear run`` writes of
ISO/TS 6336-22, on examples/fzg-c14-lubricated.toml with the keys added.
The references: λ_GFP read from the TS's Figure A.1 (jaxgear.tribology.figure_a1_permissible_film,
tests/test_micropitting.py) or given, S_λ from the CSV's per-cell λ. The full ``jaxgear run``
(tribology.json, summary.json, the run line) rides on tests/test_flash_case.py's run
(slow; its default twin there writes the same files from the tribology outputs)."""

from __future__ import annotations

import csv
import json
import pathlib
import tomllib

import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.tribology as tr
from jaxgear import cli

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "fzg-c14-lubricated.toml"


def _data(**keys):
    data = tomllib.loads(EXAMPLE.read_text())
    data["lubricant"] |= keys
    data["mesh"] |= {"slices": 1, "positions_per_pitch": 16}
    return data


def test_micropitting_keys_build_the_inputs():
    mp = jio.tribology_of(jio.parse_case(_data(micropitting_load_stage=7))).micropitting
    assert mp.permissible == pytest.approx(tr.figure_a1_permissible_film(7, 315.997e-6))
    assert "Figure A.1" in mp.source and mp.bulk_temperature is None
    given = jio.tribology_of(
        jio.parse_case(_data(permissible_specific_film=0.3, bulk_temperature_C=95.0))
    )
    assert given.micropitting.permissible == 0.3 and given.micropitting.source == "given"
    assert given.micropitting.bulk_temperature == 95.0
    assert given.scuffing is None  # the bulk keys are read by the micropitting method here
    assert jio.tribology_of(jio.load_case(EXAMPLE)).micropitting is None


@pytest.mark.parametrize(
    "change, match",
    [
        ({"micropitting_load_stage": 11}, r"\[lubricant\] micropitting_load_stage = 11"),
        ({"permissible_specific_film": -0.1}, r"permissible_specific_film = -0.1"),
        (
            {"micropitting_load_stage": 8, "permissible_specific_film": 0.2},
            r"permissible_specific_film = 0.2.*not read",
        ),
        (
            {"micropitting_load_stage": 8, "viscosity_40C_mm2_s": 680.0},
            r"viscosity_40C_mm2_s = 680.*allowed \[32, 460\]",
        ),
        (
            {
                "permissible_specific_film": 0.2,
                "bulk_temperature_C": 90.0,
                "bulk_lubrication_factor": 1.2,
            },
            r"bulk_lubrication_factor .*not read",
        ),
        ({"bulk_temperature_C": 90.0}, r"bulk_temperature_C = 90.*not read"),
    ],
)
def test_micropitting_keys_bad_input_one_line(change, match):
    with pytest.raises(ValueError, match=match) as err:
        jio.parse_case(_data(**change))
    assert "\n" not in str(err.value)


def test_tribology_outputs_write_the_micropitting(tmp_path):
    case = jio.parse_case(_data(permissible_specific_film=0.3))
    res = jg.quasi_static(
        case.mesh_model(),
        case.modifications,
        case.torque,
        positions_per_pitch=case.positions_per_pitch,
    )
    section = cli.tribology_outputs(case, str(tmp_path), res)
    mp = section["micropitting"]
    assert json.loads((tmp_path / "tribology.json").read_text())["micropitting"][
        "safety_factor"
    ] == pytest.approx(mp["safety_factor"])
    with open(tmp_path / "tribology.csv") as f:
        lam = np.array([float(r["micropitting_specific_film"]) for r in csv.DictReader(f)])
    assert mp["min_specific_film"] == pytest.approx(lam.min(), rel=1e-5)
    assert mp["safety_factor"] == pytest.approx(lam.min() / 0.3, rel=1e-5)
    assert mp["permissible_source"] == "given"
    report = cli.tribology_rating_lines(section)
    assert any(f"S_λ {mp['safety_factor']:.2f}" in line for line in report)
    assert cli.tribology_rating_lines({"min_specific_film": 1.0}) == []
