"""The gearbox case form (``[[stages]]``, :class:`jaxgear.io.GearboxForm`): the embedded
``nrel-5mw-gearbox`` (Nejad et al. 2016's three stages) parses to its stages in order, the
operating point carried by the Willis and pair ratios worked out here from the teeth (and equal
to the stage cases' own operating points, which their files state by hand), the overall ratio
Table V's 1:96.354; one-line errors. Parsing only (fast)."""

from __future__ import annotations

import copy
import json
import re
import tomllib

import numpy as np
import pytest
from _toml import case_toml
from test_gearbox import reference_frequencies

import jaxgear.io as jio
from docs._gen import schema_reference as sr
from fem_prep.schema import SchemaError
from jaxgear.cli import main


def test_nrel_gearbox_stages_ratios_and_operating_points():
    case = jio.load_case("nrel-5mw-gearbox")
    form = case.form
    assert isinstance(form, jio.GearboxForm) and case.name == "nrel-5mw-gearbox"
    names = [s.case.name for s in form.stages]
    assert names == ["nrel-5mw-planetary", "nrel-5mw-stage2", "nrel-5mw-stage3"]
    # step-up ratios from the teeth: ring fixed, carrier in, sun out: 1 + z_r / z_s; the pair
    # wheel in, pinion out: z_wheel / z_pinion
    up = [1 + 56 / 19, 1 + 93 / 18, 95 / 24]
    assert [1 / s.ratio for s in form.stages] == pytest.approx(up, rel=1e-14)
    assert 1 / form.ratio() == pytest.approx(96.354, abs=5e-4)  # Table V's 1:96.354
    assert [round(u, 3) for u in up] == [3.947, 6.167, 3.958]  # Table V's stage ratios
    speed, torque = 1.2671, 3.946e6
    for s, u in zip(form.stages, up, strict=True):
        assert (s.input_speed, s.input_torque) == pytest.approx((speed, torque), rel=1e-14)
        speed, torque = speed * u, torque / u
    # a pair's case holds its pinion's point: the output here (the wheel is driven)
    s3 = form.stages[2]
    assert (s3.case.speed, s3.case.torque) == pytest.approx((speed, torque), rel=1e-14)
    # the carried points are the stage files' own (their headers' arithmetic, 5 digits)
    for s in form.stages:
        own = jio.load_case(s.case.name)
        assert (s.case.speed, s.case.torque) == pytest.approx((own.speed, own.torque), rel=1e-4)
    assert form.stages[0].shaft_stiffness == 0.0
    assert [s.shaft_stiffness for s in form.stages[1:]] == [1.26e9, 1.435e8]
    assert form.torsional().shaft_stiffnesses.shape == (2,)


def _write(tmp_path, text):
    path = tmp_path / "box.toml"
    path.write_text(text)
    return path


GOOD = """
[operating]
torque_Nm = 1000.0
speed_rad_s = 10.0
[[stages]]
case = "nrel-5mw-stage2"
[[stages]]
case = "nrel-5mw-stage3"
input = "gear"
shaft_Nm_per_rad = 1e8
pinion_inertia_kg_m2 = 1.0
gear_inertia_kg_m2 = 10.0
mesh_stiffness_N_per_um = 1000.0
"""


def test_a_gearbox_file_and_its_errors(tmp_path):
    case = jio.load_case(_write(tmp_path, GOOD))
    assert case.name == "box" and len(case.form.stages) == 2
    assert 1 / case.form.ratio() == pytest.approx((1 + 93 / 18) * 95 / 24, rel=1e-14)
    bad = {
        GOOD.replace("shaft_Nm_per_rad = 1e8", "shaft_Nm_per_rad = -1.0"): "shaft_Nm_per_rad",
        GOOD.replace('input = "gear"', 'input = "wheel"'): "input",
        GOOD.replace('case = "nrel-5mw-stage2"', 'case = "nrel-5mw-stage2"\ninput = "gear"'): (
            "only for a pair stage"
        ),
        GOOD.replace("mesh_stiffness_N_per_um", "mesh_stiffnes_N_per_um"): "mesh_stiffnes",
        GOOD.replace(
            '[[stages]]\ncase = "nrel-5mw-stage2"\n',
            '[[stages]]\ncase = "nrel-5mw-stage2"\nshaft_Nm_per_rad = 1.0\n',
        ): "first stage",
        # a stage case that is neither a file nor an embedded case: the gearbox file's error
        GOOD.replace('case = "nrel-5mw-stage2"', 'case = "no-such-stage"'): (
            r"\[stages\[0\]\] case: case 'no-such-stage' is neither a file"
        ),
    }
    for text, needle in bad.items():
        with pytest.raises(SchemaError, match=needle) as err:
            jio.load_case(_write(tmp_path, text))
        assert "\n" not in str(err.value)


@pytest.mark.slow  # each stage's whole run (two planetary sweeps): minutes on the loaded CPU;
# fast twins: the parsing above, the chain's modes in tests/test_gearbox.py
def test_nrel_gearbox_through_jaxgear_run(tmp_path, capsys):
    out = tmp_path / "gearbox"
    assert main(["run", "nrel-5mw-gearbox", "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "gearbox nrel-5mw-gearbox: 3 stages" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is True
    assert summary["gearbox"]["step_up"] == pytest.approx(96.354, abs=5e-4)
    st = summary["stages"]
    assert [s["case"] for s in st] == ["nrel-5mw-planetary", "nrel-5mw-stage2", "nrel-5mw-stage3"]
    for s in st[:2]:  # a sweep per planetary stage
        assert s["summary"]["dynamics"]["max_dynamic_factor"] >= 1.0
    # stage 1's file has a 20 um pin error (its torsional K_gamma > 1), stage 2 none: equal shares
    assert st[0]["summary"]["load_sharing"]["torsional"]["k_gamma"] > 1.01
    assert st[1]["summary"]["load_sharing"]["planar"]["k_gamma"] == pytest.approx(1.0, abs=1e-9)
    assert st[2]["summary"]["quasi_static"]["exact"]["te_ptp_m"] > 0
    assert {p.name for p in out.iterdir()} >= {"stage1", "stage2", "stage3", "modes.json"}
    modes = summary["torsional_modes"]
    assert [m["type"] for m in modes].count("rigid body") == 1
    f = [m["frequency_Hz"] for m in modes]
    np.testing.assert_allclose(f[1:], reference_frequencies()[1:], rtol=1e-9)


def test_jaxgear_modes_on_the_gearbox_lists_the_chain(tmp_path, capsys):
    out = tmp_path / "modes"
    assert main(["modes", "nrel-5mw-gearbox", "--out", str(out)]) == 0
    assert "nrel-5mw-gearbox: natural frequencies" in capsys.readouterr().out
    rows = json.loads((out / "modes.json").read_text())["torsional_chain"]
    assert [r["type"] for r in rows].count("rigid body") == 1
    assert {r["type"] for r in rows[1:]} <= {"stage1", "stage2", "stage3"}
    f = [r["frequency_Hz"] for r in rows]
    np.testing.assert_allclose(f[1:], reference_frequencies()[1:], rtol=1e-9)


def test_the_gearbox_reference_holds_the_validators_keys(tmp_path):
    """docs/_gen/schema_reference.py's gearbox page: each table of the embedded
    nrel-5mw-gearbox holds exactly the keys the validator allows there, read from its one-line
    error for an unknown key (as a user would find them), and the page lists them."""
    schema = sr.trace_gearbox()
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-gearbox"))
    allowed_re = re.compile(r"unknown key 'zz_not_a_key'(?: \(did you mean .*?\))?, allowed: (.*)$")
    for path, table in (((), ""), (("operating",), "operating"), (("stages", 2), "stages[]")):
        probe = copy.deepcopy(data)
        t = probe
        for part in path:
            t = t[part]
        t["zz_not_a_key"] = 1.0
        path = tmp_path / "probe.toml"
        path.write_text(case_toml(probe))
        with pytest.raises(SchemaError) as err:
            jio.load_case(str(path))
        m = allowed_re.search(str(err.value))
        assert m, str(err.value)
        assert set(m.group(1).split(", ")) == set(schema.tables[table]), table
    page = sr.pages()["gearbox-file.md"]
    assert "## `[[stages]]`" in page and "| `shaft_Nm_per_rad` |" in page
    assert "| `mesh_stiffness_N_per_um` | number | N/µm |" in page
