"""``jaxgear robust`` (docs/robust.md, "Command line"): the files, the statistics of the
realisations it reports against the realisations recomputed here, and one-line errors for bad
options and [robust] keys (exit 2, no traceback)."""

from __future__ import annotations

import csv
import json
import math

import jax
import numpy as np
import pytest
from _toml import ACCESSORY_PAIR

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import main

CASE = (
    'name = "robust-spur"\n'
    + ACCESSORY_PAIR
    + """
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
[mesh]
stiffness = "weber"
slices = 4
[modifications]
tip_relief = { depth_um = 15.0, extent = 0.25, shape = "linear" }
"""
)


def test_robust_command_writes_the_statistics_of_its_realisations(tmp_path):
    """8 realisations of grade 7 (pinion and gear, every deviation), 1 revolution at 4
    positions per pitch: robust.json's mean, std and median of the TE RMS equal those of the
    realisations recomputed here with jaxgear.quasi_static on the drawn deviations (realisation
    i from fold_in(key(seed), i)), to 1e-9; samples.csv holds them; both plots are written."""
    path = tmp_path / "case.toml"
    path.write_text(CASE + "[robust]\nsamples = 8\npositions_per_pitch = 4\nseed = 3\n")
    out = tmp_path / "out"
    assert main(["robust", str(path), "--grade", "7", "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "robust.json").read_text())
    assert (out / "robust_distributions.png").stat().st_size > 0
    assert not (out / "robust_speed_bands.png").exists()  # no speeds: no bands
    case = jio.load_case(str(path))
    mesh = case.mesh_model()
    theta = jg.mesh_positions(mesh, 4, 45)
    sampler = jg.DeviationSampler.for_grade(case.pair, 7)
    rms = []
    for i in range(8):
        dev = sampler(jax.random.fold_in(jax.random.key(3), i))
        mods = jg.Modifications(case.modifications.pinion, case.modifications.gear, deviations=dev)
        te = np.asarray(jg.quasi_static(mesh, mods, case.torque, theta).transmission_error)
        rms.append(math.sqrt(np.mean((te - te.mean()) ** 2)) * 1e6)
    st = summary["quasi_static"]["te_rms_um"]
    assert st["n"] == 8 and summary["quasi_static"]["failed"] == 0
    assert st["mean"] == pytest.approx(np.mean(rms), rel=1e-9)
    assert st["std"] == pytest.approx(np.std(rms, ddof=1), rel=1e-9)
    assert st["percentiles"]["50"]["value"] == pytest.approx(np.median(rms), rel=1e-9)
    with open(out / "samples.csv") as f:
        rows = list(csv.DictReader(f))
    assert [float(r["te_rms_m"]) * 1e6 for r in rows] == pytest.approx(rms, rel=1e-9)
    assert summary["settings"]["grade"] == 7 and summary["devices"] == jax.device_count()
    # the nominal gears (no deviation) over the same positions: the histograms' dashed line
    nom = jg.quasi_static(mesh, case.modifications, case.torque, theta)
    te = np.asarray(nom.transmission_error)
    nominal = summary["quasi_static"]["nominal"]
    assert nominal["te_rms_um"] == pytest.approx(np.std(te) * 1e6, rel=1e-9)


@pytest.mark.parametrize(
    ("extra", "options", "message"),
    [
        ("", ["--grade", "12"], "--grade = 12: out of range, allowed [1, 11]"),
        ("", ["--samples", "1", "--grade", "6"], "--samples = 1: out of range, allowed >= 2"),
        ("", [], "grade: missing"),
        ("", ["--grade", "6", "--process-id", "0"], "go together"),
        (
            "",
            ["--grade", "6", "--coordinator-address", "x", "--num-processes", "2"]
            + ["--process-id", "0"],
            "allowed HOST:PORT",
        ),
        (
            "",
            ["--grade", "6", "--coordinator-address", "127.0.0.1:1234", "--num-processes", "2"]
            + ["--process-id", "2"],
            "--process-id = 2: out of range, allowed [0, 1]",
        ),
        ("[robust]\nsample = 3\n", ["--grade", "6"], "unknown key 'sample'"),
        ("[robust]\nmembers = ['wheel']\n", ["--grade", "6"], "members"),
        ("[robust]\nspeeds_rad_s = [-1.0]\n", ["--grade", "6"], "speeds_rad_s"),
        ("[robust]\nrevolutions = 'all'\n", ["--grade", "6"], "revolutions"),
    ],
)
def test_robust_command_errors_are_one_line(tmp_path, capsys, extra, options, message):
    path = tmp_path / "case.toml"
    path.write_text(CASE + extra)
    status = main(["robust", str(path), "--out", str(tmp_path / "o"), *options])
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert err.startswith("jaxgear: error:") and "\n" not in err
    assert message in err, err
    assert not (tmp_path / "o" / "robust.json").exists()
