"""No output file holds NaN or infinity without a warning that names its cause: the one guard in
the JSON and CSV writers (jaxgear.io.write_json, write_csv) names the file and the fields; the
inputs that make a result meaningless are refused at load in one line naming the key
([acoustics] band_Hz with no order in it, a viscosity outside Walther's equation), and a load
spectrum bin beyond the flanks' static strength is a warning naming [rating.spectrum]."""

from __future__ import annotations

import copy
import csv
import json
import math
import pathlib
import tomllib
import warnings

import pytest

import jaxgear.io as jio
from fem_prep import schema as sc

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"


def test_json_non_finite_written_as_null_with_a_warning_naming_the_fields(tmp_path):
    path = tmp_path / "summary.json"
    data = {
        "te": {"rms_m": 1e-6, "ptp_m": math.nan},
        "levels_dB": [1.0, math.inf, -math.inf],
        "absent": None,
        "ok": [1, 2.5, "x", True],
    }
    with pytest.warns(jio.NonFiniteOutput) as rec:
        jio.write_json(path, data, cause="[lubricant] viscosity_40C_mm2_s = 1e-300")
    assert len(rec) == 1
    msg = str(rec[0].message)
    assert msg.startswith(
        "summary.json: NaN or infinite values in te.ptp_m, levels_dB[] (2 "
        "entries): [lubricant] viscosity_40C_mm2_s = 1e-300"
    ), msg
    assert "absent" not in msg and "ok" not in msg
    text = path.read_text()
    assert "NaN" not in text and "Infinity" not in text  # strict JSON
    got = json.loads(text)
    assert got["te"]["ptp_m"] is None and got["levels_dB"] == [1.0, None, None]
    assert got["absent"] is None and got["ok"] == [1, 2.5, "x", True]


def test_json_without_non_finite_values_does_not_warn(tmp_path):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        jio.write_json(tmp_path / "a.json", {"a": [1.0, None], "b": {"c": 0.0}})
    assert json.loads((tmp_path / "a.json").read_text()) == {"a": [1.0, None], "b": {"c": 0.0}}


def test_csv_non_finite_warns_naming_the_columns_and_none_is_an_empty_cell(tmp_path):
    path = tmp_path / "sweep.csv"
    with pytest.warns(
        jio.NonFiniteOutput,
        match=r"^sweep.csv: NaN or infinite values in "
        r"dynamic_factor \(2 entries\)$",
    ):
        jio.write_csv(
            path, ["speed_rad_s", "dynamic_factor"], [[1.0, 2.0, 3.0], [math.nan, 1.1, math.inf]]
        )
    rows = list(csv.reader(path.read_text().splitlines()))
    assert rows[1:] == [["1", "nan"], ["2", "1.1"], ["3", "inf"]]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        jio.write_csv(path, ["speed_rad_s", "te_m"], [[1.0, 2.0], [None, 2.5e-6]])
    assert path.read_text().splitlines()[1:] == ["1,", "2,2.5e-06"]


def _housed(band):
    data = tomllib.loads(jio.embedded_case_text("power-helical-housed"))
    data["acoustics"] = {"band_Hz": band}
    return data


def test_acoustics_band_without_an_order_refused_at_load():
    """power-helical-housed's [whine]: 100-800 rad/s, orders 1-8 of z_1 = 35 teeth: order 1 at
    the lowest speed sounds at 35 x 100 / 2 pi = 557.04 Hz; its housing keeps orders up to the
    cut-off / 1.5 (its highest_mesh_frequency_Hz = 4500 Hz: the cut-off 6750 Hz)."""
    lowest = 35 * 100.0 / (2 * math.pi)
    top = 4500.0  # its [housing] highest_mesh_frequency_Hz: the cut-off 1.5 x it
    for band in ([10.0, 20.0], [10.0, 0.999 * lowest], [1.001 * top, 3e4]):
        with pytest.raises(sc.SchemaError) as err:
            jio.parse_case(_housed(band))
        msg = str(err.value)
        assert msg.startswith("[acoustics] band_Hz = [") and "no order of [whine] in it" in msg
        assert f"{lowest:.6g} to {top:.6g} Hz" in msg and "\n" not in msg
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", jio.CaseWarning)
        for band in ([10.0, 1.001 * lowest], [0.999 * top, 3e4]):  # an order in the band
            jio.parse_case(_housed(band))


@pytest.mark.parametrize("key", ["viscosity_40C_mm2_s", "viscosity_100C_mm2_s"])
@pytest.mark.parametrize("value", [1e-300, 1.99])
def test_viscosity_outside_walthers_equation_refused(key, value):
    data = tomllib.loads((EXAMPLES / "fzg-c14-lubricated.toml").read_text(encoding="utf-8"))
    data["lubricant"][key] = value
    with pytest.raises(
        sc.SchemaError,
        match=rf"^\[lubricant\] {key} = {value:g}: out of range, "
        r"allowed \[2, 100000\] \(Walther's equation, ASTM D341, holds from 2",
    ):
        jio.parse_case(data, "c", str(EXAMPLES))


def test_spectrum_bin_beyond_static_strength_warns_naming_the_key(tmp_path):
    from test_rating_case import CASE

    from jaxgear import cli

    data = copy.deepcopy(CASE)
    rated = data["operating"]["torque_Nm"]
    data["rating"]["spectrum"] = {
        "torque_Nm": [rated, 12000 * rated],
        "speed_rpm": 360.0,
        "hours": [20000.0, 10.0],
    }
    case = jio.parse_case(data)
    with pytest.warns(
        jio.CaseWarning,
        match=r"^\[rating.spectrum\] torque_Nm: bin 2 at "
        r"1.08e\+08 N·m load the flanks beyond their static strength",
    ):
        section = cli.rating_outputs(case, str(tmp_path))
    assert section["spectrum"]["pitting"]["damage"][1] == [None, None]
