"""``[whine]`` in ``jaxgear run``: the table's one-line errors, and the files
of a run, whose low-speed orders are the quasi-static TE's Fourier coefficients."""

import csv
import json

import numpy as np
import pytest
from _toml import small_helical_pair

import jaxgear.io as jio
from jaxgear.cli import main
from jaxgear.dynamics import HarmonicBalance, TransmissionErrorSource

GOOD = {"speed_min_rad_s": 10.0, "speed_max_rad_s": 100.0}


def test_whine_table_maps_names_to_methods():
    w = jio.parse_whine(GOOD | {"speeds": 4, "harmonics": 3, "method": "te-source",
                                "positions_per_period": 13})
    assert w.speeds == [10.0, 40.0, 70.0, 100.0]
    assert isinstance(w.method, TransmissionErrorSource) and w.method.harmonics == 3
    assert w.positions == 13
    d = jio.parse_whine(GOOD)
    assert isinstance(d.method, HarmonicBalance) and d.method.harmonics == 16
    assert d.positions == 256 and len(d.speeds) == 48


@pytest.mark.parametrize(
    ("extra", "match"),
    [
        ({"speed_max_rad_s": 5.0}, r"speed_max_rad_s.*> speed_min_rad_s"),
        ({"speeds": 1}, "speeds"),
        ({"harmonics": 0}, "harmonics"),
        ({"method": "newmark"}, "method.*harmonic-balance"),
        ({"harmonics": 16, "positions_per_period": 32}, "positions_per_period.*65"),
        ({"speed_rpm": 3}, "speed_rpm"),
        ({"speed_min_rad_s": -1.0}, "speed_min_rad_s"),
    ],
)
def test_whine_table_bad_input_one_line(extra, match):
    with pytest.raises(ValueError, match=match) as e:
        jio.parse_whine(GOOD | extra)
    assert "\n" not in str(e.value)


def test_whine_table_is_checked_when_a_case_loads(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text(small_helical_pair("c", slices=2) + "[whine]\nspeed_min_rad_s = 10.0\n")
    with pytest.raises(ValueError, match="speed_max_rad_s") as e:
        jio.load_case(str(path))
    assert "\n" not in str(e.value)


@pytest.mark.slow  # about 70 s on the 2-core host (the pair's quasi-static files first)
def test_run_writes_whine_files_and_the_low_speed_limit_is_the_static_te(tmp_path, capsys):
    """``jaxgear run`` on a pair case (its torsional model) with ``[whine]``: whine.json,
    whine.csv, the order plots and waterfalls; at 1 rad/s the dynamic TE's orders 1-3 are the
    Fourier coefficients of te.csv's rigid-mesh quasi-static TE (the same mesh, positions at
    the same mid-points) to 1e-4, and its mean the TE mean."""
    case = tmp_path / "w.toml"
    # on the theoretical path: the reference, te.csv's quasi-static TE of the MeshModel, is the
    # pinion's advance with the gear held, while the torsional scene puts the corner's lever
    # ratio λ on the tip owner's rotation, so beyond the path its TE depends on the output
    # shaft (docs/extended-contact.md, "Tests whose reference is the line of action"; with
    # contact beyond the path the two differ by 0.1 / 0.4 / 2 % on orders 1-3 here)
    text = small_helical_pair("w", slices=4, positions_per_pitch=32).replace(
        "[mesh]\n", "[mesh]\nextended_contact = false\n", 1)
    case.write_text(text + (
        "[whine]\nspeed_min_rad_s = 1.0\nspeed_max_rad_s = 3000.0\nspeeds = 3\nharmonics = 4\n"
        "positions_per_period = 32\n"
    ))
    out = tmp_path / "o"
    assert main(["run", str(case), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "whine (HarmonicBalance, H = 4, 3 speeds" in printed
    for name in ("whine.json", "whine.csv", "te_orders.png", "te_waterfall.png"):
        assert (out / "whine" / name).stat().st_size > 0
    d = json.loads((out / "whine" / "whine.json").read_text())
    assert d["speeds_rad_s"] == [1.0, 1500.5, 3000.0] and d["orders"] == [0, 1, 2, 3, 4]
    assert d["linear_result_invalid_at_rad_s"] == [] and "no contact loss" in d["validity"]
    with open(out / "te.csv") as f:
        te = np.array([float(r["te_exact_unmodified_m"]) for r in csv.DictReader(f)])[:32]
    s = (np.arange(32) + 0.5) / 32
    ref = [abs(2 * np.mean(te * np.exp(-2j * np.pi * h * s))) for h in (1, 2, 3)]
    got = np.array(d["transmission_error_m"]["amplitude"])[0, 1:4, 0]
    np.testing.assert_allclose(got, ref, rtol=1e-4)
    np.testing.assert_allclose(d["transmission_error_m"]["amplitude"][0][0][0], te.mean(),
                               rtol=1e-5)
    with open(out / "whine" / "whine.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 3 * 5 and {"te_mesh_um", "contact_loss"} <= set(rows[0])
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] and summary["whine"]["speeds"] == 3
