"""``jaxgear run`` and ``jaxgear sweep`` end to end on one small case of every scene kind a case
file accepts: a pair rigid (no ``[scene]``), torsional, 1-DOF relative (modal damping), lumped
3D and hybrid (a condensed wheel); a train rigid, torsional, lumped 3D, a lumped two-stage train
(its meshes repeat every 2 periods of the first) and a hybrid train (a condensed idler). Each
command exits 0 and writes its files with finite numbers, so that no kind breaks unseen
(``jaxgear sweep`` on a relative scene ended in ``AttributeError: 'RelativeApproach' object has
no attribute 'meshes'`` after every speed had run).

Smallest settings: 2 slices, 8 positions per pitch (16 for the hybrid bodies, whose test data
asks it), 16 or 32 steps per mesh period, 6 periods, 2 speeds; the hybrid bodies are the small
test bodies of tests/data, condensed once per session (``fem_prep_cache``). The case texts are
tests/_kinds.py's (tests/test_regression.py compares their numbers with records)."""

from __future__ import annotations

import csv
import json
import math
from pathlib import Path

import numpy as np
import pytest
from _kinds import KINDS
from test_regression import _compare, _files, _recorded_files

import jaxgear.io as jio
from jaxgear.cli import main


def _finite(value) -> int:
    """The numbers in a JSON value, all asserted finite; returns how many (None, the CLI's
    NaN, is not counted: compare the count where every entry must be a number)."""
    if isinstance(value, bool) or isinstance(value, str):
        return 0
    if isinstance(value, (int, float)):
        assert math.isfinite(value), value
        return 1
    if isinstance(value, dict):
        return sum(_finite(v) for v in value.values())
    if isinstance(value, list):
        return sum(_finite(v) for v in value)
    return 0


def _csv_finite(path: Path) -> None:
    rows = list(csv.reader(path.read_text().splitlines()))
    assert len(rows) > 2
    assert all(math.isfinite(float(v)) for row in rows[1:] for v in row)


# Which kinds run in the default suite. jaxgear run sweeps a lumped scene with the same sweep_case
# as jaxgear sweep, so the sweep command of a lumped kind is slow-only (its run covers the sweep of
# that scene; pair-rigid's and pair-relative's sweeps cover the command itself); a rigid train's
# sweep is a torsional train's (train-torsional's run); the hybrid sweeps are covered by
# tests/test_hybrid_dynamics.py's default jaxgear sweep on a hybrid pair and by a lumped 3D train's
# run (below) for a train's keys. Runs: a rigid pair's run (a case without [scene]) is
# tests/test_cli_robust.py::test_run_stores_values_that_agree_with_independent_figures (jaxgear
# run on the KHK rigid pair: its files, summary and te.csv against the KHK tables; no sweep, no
# staging folder left) with tests/test_readme_claims.py::test_run_case_summary_holds_versions_files_and_two_periods
# (every file of a pair's run, its figures); a torsional pair's run is that rigid run_case and
# pair-rigid's sweep (the default scene of a case without one is that torsional pair); a lumped 3D
# train's whole run (its 60-speed sweep included, the two-stage train's path) is
# tests/test_lumped_train.py's default jaxgear run on the two-stage lumped 3D train
# (test_jaxgear_run_on_the_two_stage_case_writes_bearing_forces: measured as costly as
# train-lumped3d's run here, and it asserts more); a lumped 3D pair's run is
# tests/test_cli_scene_curves.py's default run of a small lumped 3D pair (its scene's curves and
# files) with tests/test_regression.py's default sweep-accessory-spur (the sweep_case of a lumped
# 3D pair, against its record).
SLOW_RUN = {"train-two-stage", "pair-rigid", "pair-torsional", "train-lumped3d", "pair-lumped3d"}
# The commands here that are also tests/test_regression.py's records (the same case text, the
# same options): their outputs are compared with the record here, and the regression test runs
# them only in the slow suite (one run of each in the default suite, not two).
RECORDED = {
    ("run", "pair-relative"): "run-pair-relative",
    ("sweep", "pair-relative"): "sweep-pair-relative",
    ("run", "train-torsional"): "run-train-torsional",  # its sweep: sweep-train-torsional's path
}


def _same_as_recorded(command: str, kind: str, out: Path) -> None:
    """The outputs in ``out`` equal the regression record of the same command, if it has one
    (:data:`RECORDED`; tests/test_regression.py's comparison)."""
    name = RECORDED.get((command, kind))
    if name is not None:
        got = {f: json.loads((out / f).read_text(encoding="utf-8")) for f in _files(name)}
        diff = _compare(got, _recorded_files(name))
        assert not diff, f"{name}: {len(diff)} differences, first: " + "; ".join(diff[:5])


SLOW_SWEEP = set(KINDS) - {"pair-rigid", "pair-relative"}


def _params(slow):
    return [pytest.param(k, marks=pytest.mark.slow) if k in slow else k for k in KINDS]


def _case(kind, tmp_path, request) -> Path:
    if "hybrid" in kind:
        request.getfixturevalue("fem_prep_cache")  # the test bodies condensed once per session
    path = tmp_path / f"{kind}.toml"
    path.write_text(KINDS[kind])
    return path


@pytest.mark.filterwarnings("ignore:.*under-resolved")
@pytest.mark.parametrize("kind", _params(SLOW_RUN))
def test_run_every_scene_kind(kind, tmp_path, capsys, request):
    path = _case(kind, tmp_path, request)
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0, capsys.readouterr().err
    s = json.loads((out / "summary.json").read_text())
    assert s["complete"] is True and s["case"] == kind
    assert _finite(s) > 20
    for name in ("te.csv", "mesh_stiffness.csv"):
        _csv_finite(out / name)
    for png in ("transmission_error.png", "mesh_stiffness.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG"
    if "rigid" not in kind and "hybrid" not in kind:  # jaxgear run sweeps a lumped scene
        sw = json.loads((out / "sweep" / "sweep.json").read_text())
        n = 30 if kind.startswith("train-") else 60  # a train's first look: every 100 rad/s
        assert len(sw["dynamic_factor"]) == n and _finite(sw["dynamic_factor"]) == n
        assert _finite(s["dynamics"]["dynamic_factor"]) == n
    else:
        assert not (out / "sweep").exists()
    if kind == "pair-hybrid":
        assert (out / "scene" / "body_gear.vtu").is_file()
    if kind == "train-hybrid":
        assert (out / "body_idler.vtu").is_file()
    assert not [p for p in out.iterdir() if p.name.startswith(".jaxgear-staging-")]
    _same_as_recorded("run", kind, out)
    if kind.startswith("train-") and "hybrid" not in kind:
        _train_outputs(path, out, s)


def _train_outputs(path: Path, out: Path, s: dict) -> None:
    """A train's run, per mesh: summary.json a ``meshes`` entry per mesh with the pair keys of
    ``quasi_static``, te.csv a column per mesh, a load map per mesh, the phasing figure; the
    balancing output's torque T z_out / z_in (the tooth ratios: no loads, the power balance).
    With a sweep (a dynamic scene): each mesh's dynamic factor at every speed, the worst the
    scene's, each mesh's mean stiffness, and each mesh's order, its driving gear's teeth per
    input turn (the case's exact tooth-count orders), with its Campbell coincidences ω / (h z_k)."""
    case = jio.load_case(str(path))
    names = [case.mesh_name(k) for k in range(len(case.pairs))]
    assert [m["name"] for m in s["meshes"]] == names
    header = (out / "te.csv").read_text().splitlines()[0].split(",")
    for m in s["meshes"]:
        assert set(m["quasi_static"]["exact"]) >= {
            "te_mean_m",
            "te_rms_m",
            "mesh_stiffness_mean_N_per_m",
            "max_line_load_N_per_m",
        }
        assert (out / f"load_map_{m['name']}.png").read_bytes()[:4] == b"\x89PNG"
        # the mesh's name in snake case (input-idler -> input_idler)
        assert f"transmission_error_exact_modified_{m['name'].replace('-', '_')}_m" in header
    assert (out / "phasing.png").read_bytes()[:4] == b"\x89PNG"
    if "idler" in case.gear_names:  # the idler passes the normal force on: equal in its meshes
        loads = [m["normal_load_N"] for m in s["meshes"]]
        assert loads[1] == pytest.approx(loads[0], rel=1e-12)
    # the output turns at o_last / z_out of the input (o_last: the last mesh's order)
    z_out = int(case.pairs[-1].gear.teeth)
    expected = case.torque * z_out / float(case.mesh_orders[-1])
    assert s["operating"]["output_torque_Nm"] == pytest.approx(expected, rel=1e-12)
    sweep = out / "sweep" / "sweep.json"
    if not sweep.exists():
        return
    sw = json.loads(sweep.read_text())
    per = np.asarray(sw["dynamic_factor_mesh"])
    assert per.shape == (len(sw["speeds_rad_s"]), len(names))
    np.testing.assert_allclose(sw["dynamic_factor"], per.max(axis=1))
    assert len(sw["mesh_stiffness_mean_N_per_m"]) == len(names)
    orders = [float(o) for o in case.mesh_orders]
    np.testing.assert_allclose(sw["mesh_orders"], orders, rtol=1e-12)
    for z, row in zip(orders, sw["critical_speeds_mesh"], strict=True):
        assert row
        for c in row:
            w = 2 * math.pi * c["frequency_Hz"]
            assert c["speed_rad_s"] == pytest.approx(w / (c["harmonic"] * z), rel=1e-12)


@pytest.mark.filterwarnings("ignore:.*under-resolved")
@pytest.mark.filterwarnings("ignore:the structure's modes move")
@pytest.mark.parametrize("kind", _params(SLOW_SWEEP))
def test_sweep_every_scene_kind(kind, tmp_path, capsys, request):
    path = _case(kind, tmp_path, request)
    out = tmp_path / "sweep"
    argv = ["sweep", str(path), "--speeds", "300:600:2", "--out", str(out), "--quiet"]
    argv += ["--periods", "6", "--keep-periods", "2", "--steps-per-period", "16"]
    assert main(argv) == 0, capsys.readouterr().err
    sw = json.loads((out / "sweep.json").read_text())
    assert _finite(sw["dynamic_factor"]) == 2 and _finite(sw["speeds_rad_s"]) == 2
    assert sw["result"] == [0, 0]
    assert _finite(sw["natural_frequencies_Hz"]) > 0
    for png in ("dynamic_factor.png", "campbell.png", "contact_pressure.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG"
    assert "sweep.json" in (out / ".jaxgear-outputs").read_text()
    assert not [p for p in out.iterdir() if p.name.startswith(".jaxgear-staging-")]
    _same_as_recorded("sweep", kind, out)
