"""The CLI as a user expects it: bad output paths and options are one-line errors
(exit 2, no traceback, no files), Ctrl-C and closed pipes are quiet, runs leave no stale files,
library warnings are one line, and the stored values agree with independent figures."""

import csv
import json
import math
import os
import pathlib
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

import fem_prep.schema  # noqa: F401 - the CLI imports the path checks on first use: not timed
from jaxgear.cli import main

ROOT = pathlib.Path(__file__).resolve().parents[1]
ENTRY = "from jaxgear.cli import entry; entry()"  # what the jaxgear script runs
M = 3.0  # KHK "profile shifted spur gears" (tests/test_geometry.py): m 3, z 12/24, x 0.6/0.36
KHK = f"""
name = "khk-spur"
[pair]
normal_module_mm = {M}
normal_pressure_angle_deg = 20.0
[pinion]
teeth = 12
profile_shift = 0.6
addendum_coeff = {(44.840 / 2 - 12 * M / 2) / M - 0.6!r}
dedendum_coeff = 1.25
face_width_mm = 20.0
[gear]
teeth = 24
profile_shift = 0.36
addendum_coeff = {(79.400 / 2 - 24 * M / 2) / M - 0.36!r}
dedendum_coeff = 1.25
face_width_mm = 20.0
[operating]
torque_Nm = 100.0
[mesh]
slices = 4
positions_per_pitch = 16
[modifications]
tip_relief = {{ depth_um = 10.0, extent = 0.25 }}
"""


@pytest.fixture
def khk(tmp_path):
    p = tmp_path / "khk.toml"
    p.write_text(KHK)
    return p


def _one_line_error(capsys, *needles):
    err = capsys.readouterr().err
    lines = [ln for ln in err.splitlines() if ln.strip()]
    assert len(lines) == 1 and lines[0].startswith("jaxgear: error: "), err
    assert "Traceback" not in err
    for n in needles:
        assert n in lines[0], err
    return lines[0]


# -- output paths: checked before anything is computed -------------------------------------------


def _bad_paths(tmp_path):
    f = tmp_path / "a-file"
    f.write_text("user data")
    folder = tmp_path / "a-folder"
    folder.mkdir()
    return {
        "out is a file": ["--out", str(f)],
        "out under a file": ["--out", str(f / "sub" / "dir")],
        "out not creatable": ["--out", "/proc/jaxgear-test/out"],
        "json is a folder": ["--json", str(folder)],
        "json under a file": ["--json", str(f / "s.json")],
    }


COMMANDS = {
    "run": ["run", "accessory-spur", "--quiet"],
    "optimise": ["optimise", "accessory-spur", "--quiet"],
    "sweep": ["sweep", "accessory-spur", "--speeds", "100:200:3", "--quiet"],
    "master-curve": ["master-curve", "accessory-spur"],
    "bench": ["bench", "dynamics", "--quick"],
    "prep": ["prep", "power-helical-wheel", "--quiet"],
}


@pytest.mark.parametrize("command", sorted(COMMANDS))
def test_bad_output_paths_exit_2_with_one_line_and_no_files(command, tmp_path, capsys):
    for why, opts in _bad_paths(tmp_path).items():
        if opts[0] == "--json" and command != "run":
            continue
        before = sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*"))
        t0 = time.perf_counter()
        assert main([*COMMANDS[command], *opts]) == 2, why
        assert time.perf_counter() - t0 < 5, f"{why}: the check must come before computing"
        _one_line_error(capsys, opts[0])
        assert sorted(p.relative_to(tmp_path) for p in tmp_path.rglob("*")) == before, why
    assert (tmp_path / "a-file").read_text() == "user data"


def test_read_only_output_folder_is_an_error(tmp_path, capsys, monkeypatch):
    ro = tmp_path / "ro"
    ro.mkdir()
    import tempfile

    real = tempfile.mkstemp

    def refuse(*a, dir=None, **k):  # a read-only mount (chmod does not stop root)
        if dir is not None and os.path.samefile(dir, ro):
            raise PermissionError(13, "Read-only file system")
        return real(*a, dir=dir, **k)

    monkeypatch.setattr(tempfile, "mkstemp", refuse)
    assert main(["run", "accessory-spur", "--out", str(ro), "--quiet"]) == 2
    _one_line_error(capsys, "--out", "not writable")
    assert os.listdir(ro) == []


def test_json_into_a_missing_folder_is_created():
    import tempfile

    from fem_prep.schema import check_output_file
    from jaxgear.io import write_json

    with tempfile.TemporaryDirectory() as d:
        p = os.path.join(d, "new", "deeper", "s.json")
        assert check_output_file(p) == p
        assert not os.path.exists(os.path.join(d, "new"))  # the check creates nothing
        write_json(p, {"a": 1})  # the writer creates the folder
        assert os.path.isfile(p)


# -- options: reversed or meaningless ranges are errors, before any computation ------------------


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (
            ["optimise", "accessory-spur", "--objective", "robust_te_rms", "--torques", "120:40:5"],
            "--torques",
        ),
        (
            ["optimise", "accessory-spur", "--torques", "40:120:5", "--objective", "te_rms"],
            "robust_te_rms",
        ),
        (
            ["optimise", "accessory-spur", "--torques", "0:120:5", "--objective", "robust_te_rms"],
            "> 0",
        ),
        (["optimise", "accessory-spur", "--max-iterations", "-5"], "--max-iterations"),
        (["optimise", "accessory-spur", "--max-iterations", "0"], "--max-iterations"),
        (["master-curve", "accessory-spur", "--extents", "0.6:0.05:5"], "--extents"),
        (["master-curve", "accessory-spur", "--extents", "0.0:1.2:5"], "--extents"),
        (["master-curve", "accessory-spur", "--extents", "0.1:0.5"], "--extents"),
        (["sweep", "accessory-spur", "--speeds", "3000:100:10"], "--speeds"),
        (["sweep", "accessory-spur", "--speeds=-100:100:10"], "--speeds"),
        (["sweep", "accessory-spur", "--speeds", "100:200:0"], "--speeds"),
        (["sweep", "accessory-spur", "--speeds", "100:200:5", "--periods", "0"], "--periods"),
    ],
)
def test_meaningless_options_are_one_line_errors(argv, needle, tmp_path, capsys):
    t0 = time.perf_counter()
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    assert time.perf_counter() - t0 < 5
    _one_line_error(capsys, needle)
    assert not (tmp_path / "o").exists()


def test_torques_from_the_case_file_with_another_objective_is_an_error():
    from jaxgear.cli import check_settings

    ok = {"objective": "robust_te_rms", "torques": "40:120:5", "max_iterations": 10}
    assert check_settings(ok) is ok
    with pytest.raises(ValueError, match="robust_te_rms only"):
        check_settings({**ok, "objective": "te_rms"})
    with pytest.raises(ValueError, match="reversed"):
        check_settings({**ok, "torques": "120:40:5"})
    with pytest.raises(ValueError, match="max_iterations"):
        check_settings({**ok, "max_iterations": 0})


# -- --version, warnings, broken pipe -------------------------------------------------------------


def test_version(capsys):
    from importlib.metadata import version

    assert main(["--version"]) == 0
    assert capsys.readouterr().out.strip() == f"jaxgear {version('jaxgear')}"


@pytest.mark.filterwarnings("default")
def test_library_warnings_reach_the_user_as_one_line(monkeypatch, capsys):
    import warnings

    import jaxgear.io

    def warns(*args):  # ``jaxgear modes`` loads its case with jaxgear.io.load_case: a warning
        warnings.warn("something odd\n  happened", UserWarning, stacklevel=1)
        raise ValueError("stopped here")

    monkeypatch.setattr(jaxgear.io, "load_case", warns)
    saved = warnings.showwarning
    assert main(["modes", "accessory-spur", "--quiet"]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines() == [
        "jaxgear: warning: something odd happened",
        "jaxgear: error: stopped here",
    ]
    assert warnings.showwarning is saved  # restored after the command


def test_broken_pipe_in_process_exits_0_quietly(tmp_path, monkeypatch, capsys):
    """The reader of stdout went away (``jaxgear cases | head``): main returns 0, writes
    nothing to stderr, and points stdout at the null device so that the interpreter's flush at
    exit cannot raise again (the subprocess form is the slow tier's)."""

    class ClosedPipe:
        def __init__(self, fd):
            self.fd = fd

        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            raise BrokenPipeError(32, "Broken pipe")

        def fileno(self):
            return self.fd

    with open(tmp_path / "stdout", "w") as f:
        monkeypatch.setattr(sys, "stdout", ClosedPipe(f.fileno()))
        assert main(["cases"]) == 0
        os.write(f.fileno(), b"after")  # the descriptor now writes to the null device
    assert capsys.readouterr().err == ""
    assert (tmp_path / "stdout").read_bytes() == b""


# default tier: tests/test_cli_robust.py::test_broken_pipe_in_process_exits_0_quietly (main on a closed stdout)
@pytest.mark.slow
def test_broken_pipe_exits_quietly():
    res = subprocess.run(
        f"{sys.executable} -c '{ENTRY}' cases | head -c 10",
        shell=True,
        capture_output=True,
        text=True,
        timeout=300,
        cwd=ROOT,
        check=False,
    )
    assert len(res.stdout) == 10
    assert "Traceback" not in res.stderr and "BrokenPipeError" not in res.stderr, res.stderr


# -- interrupt ------------------------------------------------------------------------------------


@pytest.mark.parametrize("keep_partial", [False, True])
def test_interrupt_leaves_the_earlier_files_or_with_keep_partial_an_incomplete_summary(
    khk, tmp_path, monkeypatch, capsys, keep_partial
):
    import jaxgear.cli.run as _run  # to interrupt run_case between two files

    out = tmp_path / "out"
    out.mkdir()
    (out / "harris_map.png").write_bytes(b"earlier")  # from an earlier run
    (out / ".jaxgear-outputs").write_text("harris_map.png\n")  # (the earlier run's list)
    real = _run.write_csv
    calls = []

    def write_then_interrupt(path, header, columns):
        calls.append(path)
        if len(calls) == 2:  # te.csv is written, Ctrl-C before mesh_stiffness.csv
            raise KeyboardInterrupt
        real(path, header, columns)

    monkeypatch.setattr(_run, "write_csv", write_then_interrupt)
    extra = ["--keep-partial"] if keep_partial else []
    assert main(["run", str(khk), "--out", str(out), "--quiet", *extra]) == 130
    captured = capsys.readouterr()
    assert captured.err.strip() == "jaxgear: interrupted" and "Traceback" not in captured.err
    if not keep_partial:  # the earlier run's files as they were, none of this run's
        assert sorted(os.listdir(out)) == [".jaxgear-outputs", "harris_map.png"]
        assert (out / "harris_map.png").read_bytes() == b"earlier"
        assert (out / ".jaxgear-outputs").read_text() == "harris_map.png\n"
        return
    assert json.loads((out / "summary.json").read_text()) == {"case": "khk-spur", "complete": False}
    rows = list(csv.reader((out / "te.csv").read_text().splitlines()))
    assert len(rows) == 1 + 2 * 16 and all(len(r) == len(rows[0]) for r in rows)
    # no earlier, no temporary files; the list of this run's files
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "summary.json", "te.csv"]


@pytest.mark.slow
@pytest.mark.parametrize("keep_partial", [False, True])
def test_sigint_gives_one_line_and_exit_130(khk, tmp_path, keep_partial):
    out = tmp_path / "out"
    extra = ["--keep-partial"] if keep_partial else []
    p = subprocess.Popen(
        [sys.executable, "-c", ENTRY, "run", str(khk), "--out", str(out), "--quiet", *extra],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=ROOT,
    )

    def started():  # the first file written (a staging folder's without --keep-partial)
        return any(p.name == "summary.json" for p in out.rglob("*")) if out.exists() else False

    deadline = time.time() + 120
    while not started() and time.time() < deadline and p.poll() is None:
        time.sleep(0.2)
    time.sleep(1.0)  # inside the computation
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    assert p.returncode == 130, err
    assert "Traceback" not in err and "jaxgear: interrupted" in err
    if keep_partial:
        assert json.loads((out / "summary.json").read_text())["complete"] is False
    else:  # no earlier run: no file, no folder
        assert not out.exists()


# -- a complete run: stored values against independent figures -----------------------------------


def test_run_stores_values_that_agree_with_independent_figures(khk, tmp_path, capsys, no_figures):
    out = tmp_path / "out"
    out.mkdir()
    (out / "notes.txt").write_text("mine")  # a user's file is never touched
    assert (
        main(
            [
                "run",
                str(khk),
                "--out",
                str(out),
                "--json",
                str(tmp_path / "j" / "s.json"),
                "--quiet",
            ]
        )
        == 0
    )
    s = json.loads((out / "summary.json").read_text())
    assert json.loads((tmp_path / "j" / "s.json").read_text()) == s
    assert s["complete"] is True
    assert (out / "notes.txt").read_text() == "mine"
    g = s["geometry"]  # KHK Table 4.6
    assert g["center_distance_m"] * 1e3 == pytest.approx(56.4999, abs=1e-4)
    assert g["operating_pressure_angle_deg"] == pytest.approx(26.0888, abs=3e-4)
    assert g["transverse_contact_ratio"] == pytest.approx(1.202, abs=5e-4)
    assert [2e3 * r for r in g["base_radii_m"]] == pytest.approx([33.8289, 67.6579], abs=1e-4)
    assert [2e3 * r for r in g["tip_radii_m"]] == pytest.approx([44.840, 79.400], abs=1e-9)
    assert g["base_pitch_m"] == pytest.approx(math.pi * 3e-3 * math.cos(math.radians(20)))
    # each quasi-static table holds the TE and stiffness keys, ordered min <= mean <= max
    for key in ("quasi_static", "quasi_static_unmodified"):
        for mode in ("exact", "smooth"):
            q = s[key][mode]
            assert {"te_mean_m", "te_rms_m", "te_ptp_m", "max_line_load_N_per_m"} <= set(q)
            assert (
                q["mesh_stiffness_min_N_per_m"]
                <= q["mesh_stiffness_mean_N_per_m"]
                <= q["mesh_stiffness_max_N_per_m"]
            )
            assert 0 < q["te_rms_m"] <= q["te_ptp_m"]
    assert not [p for p in os.listdir(out) if p.startswith(".tmp-")]  # no temporary files
    # a rigid pair (no [scene]): no sweep, no staging folder left, finite stiffness curves
    assert not (out / "sweep").exists()
    assert not [p for p in os.listdir(out) if p.startswith(".jaxgear-staging-")]
    with open(out / "mesh_stiffness.csv") as f:
        k_rows = list(csv.reader(f))
    assert len(k_rows) > 2 and all(math.isfinite(float(v)) for r in k_rows[1:] for v in r)
    # TE in te.csv is the TE the summary describes: two mesh periods, theta and 4 curves
    with open(out / "te.csv") as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 2 * 16 and next(iter(rows[0])) == "theta_rad" and len(rows[0]) == 5
    for lab, key in (("modified", "quasi_static"), ("unmodified", "quasi_static_unmodified")):
        for mode in ("exact", "smooth"):
            te = np.array([float(r[f"te_{mode}_{lab}_m"]) for r in rows])
            q = s[key][mode]
            assert np.sqrt(np.mean((te - te.mean()) ** 2)) == pytest.approx(q["te_rms_m"], rel=1e-9)
            assert te.mean() == pytest.approx(q["te_mean_m"], rel=1e-9)
            assert np.ptp(te) == pytest.approx(q["te_ptp_m"], rel=1e-9)
    # the Harris map at the case torque is the TE ptp of the quasi-static run (exact contact)
    h = s["harris_map"]
    i = int(np.argmin(np.abs(np.asarray(h["torque_Nm"]) - 100.0)))
    assert h["torque_Nm"][i] == pytest.approx(100.0)
    assert h["te_ptp_modified_m"][i] == pytest.approx(
        s["quasi_static"]["exact"]["te_ptp_m"], rel=1e-6
    )
    assert h["te_ptp_unmodified_m"][i] == pytest.approx(
        s["quasi_static_unmodified"]["exact"]["te_ptp_m"], rel=1e-6
    )
    # static equilibrium: mean mesh force = normal load, so K̄ · mean TE ≈ F for the unmodified pair
    qs = s["quasi_static_unmodified"]["exact"]
    F = s["operating"]["normal_load_N"]
    assert F == pytest.approx(100.0 / g["base_radii_m"][0])
    assert qs["te_mean_m"] > 0 and qs["mesh_stiffness_mean_N_per_m"] * qs[
        "te_mean_m"
    ] == pytest.approx(F, rel=0.1)
    printed = capsys.readouterr().out
    assert f"{s['quasi_static']['exact']['te_rms_m'] * 1e6:.4f}" in printed


@pytest.mark.filterwarnings("default")
def test_optimise_clears_stale_files_warns_at_the_cap_and_stores_values(khk, tmp_path, capsys):
    out = tmp_path / "opt"
    out.mkdir()
    (out / "path.png").write_bytes(b"from a 2-variable run")
    (out / ".jaxgear-outputs").write_text("path.png\noptimum.json\n")  # that run's list
    (out / "notes.txt").write_text("mine")
    argv = ["optimise", str(khk), "--vars", "crowning.depth", "--max-iterations", "1"]
    assert main([*argv, "--out", str(out), "--quiet"]) == 0
    assert not (out / "path.png").exists()  # not a file of this run
    assert (out / "notes.txt").read_text() == "mine"
    assert sorted(os.listdir(out)) == [
        ".jaxgear-outputs",
        "convergence.png",
        "harris.png",
        "notes.txt",
        "optimum.json",
    ]
    rep = json.loads((out / "optimum.json").read_text())
    err = capsys.readouterr().err
    if not rep["converged"]:
        assert (
            "jaxgear: warning: optimiser stopped at the iteration cap (1) before convergence" in err
        )
        assert "UserWarning" not in err
    assert rep["iterations"] <= 1
    assert rep["final"]["objective_smooth_m"] <= rep["initial"]["objective_smooth_m"]
    # the Harris curve of the optimum at the design torque is the final exact objective
    h = rep["harris"]
    i = int(np.argmin(np.abs(np.asarray(h["torque_Nm"]) - 100.0)))
    assert h["te_rms_optimum_m"][i] == pytest.approx(rep["final"]["objective_exact_m"], rel=1e-6)


def test_iteration_cap_warns_in_the_library():
    import jaxgear as jg
    import optimise as op
    from jaxgear.io import case_problem, load_case

    del jg
    case = load_case("accessory-spur").replace(slices=4, positions_per_pitch=16)
    problem = case_problem(case, "tip_relief.depth", "te_rms")
    with pytest.warns(UserWarning, match=r"iteration cap \(1\) before convergence"):
        r = op.minimise(problem, [0.2], max_iterations=1, progress=False)
    assert r.converged is False and r.iterations == 1


def test_master_curve_flags_points_on_a_bound():
    import optimise as op
    from jaxgear.io import case_problem, load_case

    case = load_case("accessory-spur").replace(slices=4, positions_per_pitch=16)
    # the depth interval stops well below the optimum depth (about one mean deflection)
    problem = case_problem(
        case,
        "tip_relief.depth,tip_relief.extent",
        "te_rms",
        relief_blend=0.0,
        bounds={"tip_relief.depth": (0.0, 0.2), "tip_relief.extent": (0.02, 0.98)},
    )
    mc = op.master_curve(problem, [0.2, 0.3], coarse_depths=np.linspace(0.0, 0.2, 5), iterations=5)
    assert mc["on_bound"].tolist() == [True, True]
    assert mc["depth_star"] == pytest.approx([0.2, 0.2])
