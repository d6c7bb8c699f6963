"""The main job (`jaxgear run`), its files, the quickstart example, and atomic output."""

import csv
import json
import os
import pathlib

import pytest
from _examples import load_example
from _toml import small_helical_pair

from jaxgear.cli import main
from jaxgear.io import atomic_open

ROOT = pathlib.Path(__file__).resolve().parents[1]
SMALL = (
    small_helical_pair("small-helical")
    + """[modifications]
tip_relief = { depth_um = 8.0, extent = 0.3, shape = "parabolic" }
[modifications.gear]
crowning = { depth_um = 4.0 }
"""
)
PNGS = ["transmission_error.png", "mesh_stiffness.png", "load_map.png", "harris_map.png"]


# default tier: tests/test_cli_robust.py::test_run_stores_values_that_agree_with_independent_figures (jaxgear run on a rigid pair: --json, the geometry, the quasi-static keys and order, te.csv, no temporary files, the printed TE) and tests/test_readme_claims.py::test_run_case_summary_holds_versions_files_and_two_periods (every file, the four PNGs)
@pytest.mark.slow
def test_run_writes_summary_csv_and_plots(tmp_path, capsys):
    case = tmp_path / "small.toml"
    case.write_text(SMALL)
    out = tmp_path / "out"
    extra = tmp_path / "extra" / "s.json"
    assert main(["run", str(case), "--out", str(out), "--json", str(extra), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "TE rms" in printed and "small-helical" in printed
    summary = json.loads((out / "summary.json").read_text())
    assert json.loads(extra.read_text()) == summary
    g = summary["geometry"]
    for key in (
        "transverse_contact_ratio",
        "overlap_ratio",
        "base_pitch_m",
        "center_distance_m",
        "path_of_contact_m",
    ):
        assert g[key] > 0
    for mode in ("exact", "smooth"):
        q = summary["quasi_static"][mode]
        for key in (
            "te_mean_m",
            "te_rms_m",
            "te_ptp_m",
            "mesh_stiffness_mean_N_per_m",
            "mesh_stiffness_min_N_per_m",
            "mesh_stiffness_max_N_per_m",
            "max_line_load_N_per_m",
        ):
            assert key in q
        assert (
            q["mesh_stiffness_min_N_per_m"]
            <= q["mesh_stiffness_mean_N_per_m"]
            <= q["mesh_stiffness_max_N_per_m"]
        )
        assert 0 < q["te_rms_m"] <= q["te_ptp_m"]
    # ε_β = b sin β / (π m_n) with b = min(20, 22) mm
    import math

    assert g["overlap_ratio"] == pytest.approx(
        20e-3 * math.sin(math.radians(15)) / (math.pi * 2e-3)
    )
    with open(out / "te.csv") as f:
        rows = list(csv.reader(f))
    assert len(rows) == 1 + 2 * 16  # two mesh periods of 16 positions
    assert rows[0][0] == "theta_rad" and len(rows[0]) == 5
    assert (out / "mesh_stiffness.csv").stat().st_size > 0
    for name in PNGS:
        data = (out / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000
    # no temporary files left behind
    assert not [p for p in os.listdir(out) if p.startswith(".tmp-")]


def test_run_bad_input_exits_2_with_a_message(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(SMALL.replace("tip_relief = { depth_um = 8.0", "tip_relief = { depth_um = -8.0"))
    assert main(["run", str(bad), "--out", str(tmp_path / "o"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "depth_um" in err and "-8" in err and "allowed [0, 2000]" in err
    assert main(["run", str(tmp_path / "missing.toml"), "--quiet"]) == 2
    assert "missing.toml': no such file" in capsys.readouterr().err
    assert not (tmp_path / "o" / "summary.json").exists()


def test_cases_lists_embedded_cases(capsys):
    assert main(["cases"]) == 0
    out = capsys.readouterr().out
    assert "accessory-spur" in out and "power-helical" in out
    # a train with two modules lists both (two-stage: 1.5 mm, then 2.5 mm)
    line = next(ln for ln in out.splitlines() if ln.startswith("two-stage"))
    assert "m_n 1.5/2.5 mm" in line
    # its gear names' abbreviations explained
    assert "hst = high-speed train, stage 1, lst = low-speed train, stage 2" in line


def test_atomic_open_keeps_the_old_file_when_interrupted(tmp_path):
    target = tmp_path / "summary.json"
    target.write_text("old")
    with pytest.raises(KeyboardInterrupt):
        with atomic_open(target, "w") as f:
            f.write("half a new fi")
            raise KeyboardInterrupt  # the run is interrupted mid-write
    assert target.read_text() == "old"
    assert os.listdir(tmp_path) == ["summary.json"]
    with atomic_open(target, "w") as f:
        f.write("new")
    assert target.read_text() == "new"


# default tier: tests/test_readme_claims.py::test_run_case_summary_holds_versions_files_and_two_periods (the same run_case on accessory-spur at 2 slices: its files, the relief halving the TE RMS, the pressure column's maximum the summary's)
@pytest.mark.slow
def test_quickstart_example_runs(tmp_path):
    mod = load_example("quickstart")
    res = mod.main(str(tmp_path))
    # tip relief near the seed's optimum (E ≈ 15 µm, Γ ≈ 0.25, IV-3) must cut the TE fluctuation
    assert float(res["relieved"].te_rms) < 0.5 * float(res["plain"].te_rms)
    assert res["summary"]["case"] == "accessory-spur"
    for name in PNGS:
        assert (tmp_path / name).exists()
    # docs/reference/outputs.md: the two CSV files and the six plots, loaded_path.png with the
    # case files' default extended_contact (no sweep, scene or optimisation folder)
    files = sorted(p.name for p in tmp_path.iterdir() if not p.name.startswith("."))
    assert [f for f in files if f.endswith(".png")] == sorted(
        [*PNGS, "pressure_map.png", "loaded_path.png"]
    )
    assert [f for f in files if f.endswith(".csv")] == ["mesh_stiffness.csv", "te.csv"]
    assert not [p for p in tmp_path.iterdir() if p.is_dir()]
    # the contact pressure of this run (jaxgear run on accessory-spur: tests/test_pressure.py's
    # slow test_jaxgear_run_writes_the_pressure, the same run): max_contact_pressure_Pa per
    # contact law and the pressure per position in mesh_stiffness.csv, whose largest column
    # value is the summary's maximum (one field, two outputs)
    q = res["summary"]["quasi_static"]["exact"]
    assert 5e8 < q["max_contact_pressure_Pa"] < 2e9 and q["contact_half_width_at_max_m"] > 0
    header = (tmp_path / "mesh_stiffness.csv").read_text().splitlines()[0].split(",")
    col = header.index("max_contact_pressure_exact_modified_Pa")
    rows = list(csv.reader((tmp_path / "mesh_stiffness.csv").read_text().splitlines()[1:]))
    assert max(float(r[col]) for r in rows) == pytest.approx(q["max_contact_pressure_Pa"], rel=1e-9)
    assert (tmp_path / "pressure_map.png").stat().st_size > 0
