"""``jaxgear run`` on a case with a scene: ``te.csv``, ``mesh_stiffness.csv`` and their plots
hold the scene model's own curves beside the rigid mesh's (a flexible case's files
were the rigid case's under its name), each column and legend named by its model; the scene's
steps have their own progress bar."""

import csv
import json
import re

import numpy as np
import pytest

import jaxgear.cli.sweep as sweep_module  # only to leave the 60-speed sweep out (test_layout)
from jaxgear.cli import main


@pytest.fixture
def small_lumped3d(tmp_path, capsys):
    """The default case (lumped 3D scene: shafts on bearings) at 2 slices × 8 positions."""
    path = tmp_path / "small.toml"
    assert main(["cases", "accessory-spur", "--write", str(path)]) == 0
    capsys.readouterr()
    text = path.read_text()
    text = text.replace("slices = 40", "slices = 2").replace(
        "positions_per_pitch = 64", "positions_per_pitch = 8"
    )
    path.write_text(text)
    return path


def test_run_writes_the_scene_te_and_stiffness_beside_the_rigid_mesh(
    small_lumped3d, tmp_path, monkeypatch, capsys, no_figures
):
    def no_sweep(case, speeds, out_dir, *, slices, **kw):
        return {"speeds_rad_s": [100.0, 200.0], "dynamic_factor": [1.0, 1.1]}, None

    monkeypatch.setattr(sweep_module, "sweep_case_run", no_sweep)  # (summary, worst run)
    out = tmp_path / "o"
    assert main(["run", str(small_lumped3d), "--out", str(out)]) == 0
    # after the run's bar, a bar over the scene's steps (the scene, its quasi-static solves,
    # maps and files) ends full and names its solves
    err = capsys.readouterr().err
    states = re.findall(r"jaxgear run accessory-spur: scene:\s+\d+%\|[^|]*\|\s*(\d+)/(\d+)", err)
    assert states and states[-1] == ("3", "3"), err[-2000:]
    assert "quasi-static, exact contact" in err and "quasi-static, smooth contact" in err
    with open(out / "te.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 * 8
    head = list(rows[0])
    # the rigid mesh's columns first, as before; the scene's added
    assert head[:5] == [
        "theta_rad",
        "te_exact_unmodified_m",
        "te_smooth_unmodified_m",
        "te_exact_modified_m",
        "te_smooth_modified_m",
    ]
    assert head[5:] == ["te_lumped3d_exact_modified_m", "te_lumped3d_smooth_modified_m"]
    rigid = np.array([float(r["te_exact_modified_m"]) for r in rows])
    scene = np.array([float(r["te_lumped3d_exact_modified_m"]) for r in rows])
    # shaft and bearing compliance: a larger mean TE (35 against 12 µm at 40 slices)
    assert scene.mean() > rigid.mean() + 10e-6
    s = json.loads((out / "summary.json").read_text())
    q = s["quasi_static_scene"]["exact"]
    assert scene.mean() == pytest.approx(q["te_mean_m"], rel=1e-9)
    assert np.ptp(scene) == pytest.approx(q["te_ptp_m"], rel=1e-9)
    with open(out / "mesh_stiffness.csv", newline="") as f:
        krows = list(csv.DictReader(f))
    assert "mesh_stiffness_lumped3d_exact_modified_N_per_m" in krows[0]
    assert "mesh_stiffness_exact_modified_N_per_m" in krows[0]
    k = np.array([float(r["mesh_stiffness_lumped3d_exact_modified_N_per_m"]) for r in krows])
    assert k.mean() == pytest.approx(q["mesh_stiffness_mean_N_per_m"], rel=1e-9)


def test_te_plot_labels_each_model(tmp_path):
    from jaxgear.cli import plots

    x = np.linspace(0, 2, 16)
    labels = plots.transmission_error_plot(
        tmp_path / "te.png",
        x,
        {
            "rigid mesh modified": {"exact": 1e-6 * np.sin(x), "smooth": 1e-6 * np.sin(x)},
            "hybrid scene, modified": {
                "exact": 3e-6 + 1e-6 * np.cos(x),
                "smooth": 3e-6 + np.cos(x) * 1e-6,
            },
            "hybrid scene at rest, modified": {"exact": 2e-6 + 1e-6 * np.cos(x)},
        },
        title="t",
    )
    assert labels[0].startswith("rigid mesh modified (exact = smooth")
    assert labels[1].startswith("hybrid scene, modified (exact = smooth")
    assert labels[2] == "hybrid scene at rest, modified, exact contact"


def test_two_stage_plots_show_two_periods_of_its_slow_mesh_not_the_span():
    """docs/trains.md: the two-stage span (127 input mesh periods) is drawn over two periods of
    its slowest mesh (the second stage's: 127/35 input periods each), a pair's two periods whole;
    the CSV files keep the span."""
    from jaxgear.cli.train import plotted_periods
    from jaxgear.io import load_case

    case = load_case("two-stage")
    assert case.span_periods == 127
    assert plotted_periods(case, case.layout(), 127.0) == pytest.approx(2 * 127 / 35, rel=1e-12)
    idler = load_case("accessory-idler-train")
    assert plotted_periods(idler, idler.layout(), 2.0) == 2.0


def test_train_table_names_the_balancing_gear_once():
    """The idler train's table said "balancing output output -171.2 N·m" (its output gear is
    named "output"): the gear's name is quoted after what it is."""
    from jaxgear.cli.train import format_train_table

    summary = {
        "case": "t",
        "gears": [{}, {}, {}],
        "meshes": [],
        "operating": {"torque_Nm": 80.0, "output": "output", "output_torque_Nm": -171.2},
    }
    head = format_train_table(summary).splitlines()[0]
    assert "balancing torque on gear 'output' -171.2 N·m" in head
    assert "output output" not in head
