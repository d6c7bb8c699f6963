"""No command writes over an input of its run or, without ``--force``, over an existing file.

Every option that names an output file (``run --json``, ``optimise --write``, ``cases --write``,
``fem-prep bodies --write``) refuses the case file and the files it names (a body file, a
housing mesh file, a gearbox's stage files: ``Case.input_files``) even with ``--force``, and an
existing file without it, in one line naming the option and the path, before any work; an
output folder refuses an input where the command writes. The inputs' list is checked against
the files written into the case by hand (an independent list), the refusals by the files'
bytes left as they were.
"""

import os
import pathlib
import time

import pytest

import fem_prep
import fem_prep.cli as fem_cli  # only to patch the build it calls (tests/test_layout.py)
import jaxgear.cli._optimise as optimise_module  # its work replaced: the paths are under test
import jaxgear.cli.run as run_module  # its steps replaced by quick fakes (tests/test_manifest.py)
import jaxgear.io as jio
from jaxgear.cli import main
from jaxgear.io import embedded_case_text, write_json

CASES = pathlib.Path(jio.__file__).resolve().parents[1] / "cases"


class Reached(Exception):
    """Raised where a command's work starts: its output checks have passed."""


def _reached(*args, **kw):
    raise Reached


def _fake_run_case(case, out, **kw):
    summary = {"case": case.name, "complete": True}
    write_json(os.path.join(out, "summary.json"), summary)
    return summary


@pytest.fixture
def quick_run(monkeypatch):
    monkeypatch.setattr(run_module, "run_case", _fake_run_case)
    monkeypatch.setattr(run_module, "format_table", lambda summary, stiffness, *modified: "")


def _case_file(tmp_path, name="power-helical") -> pathlib.Path:
    p = tmp_path / "c.toml"
    p.write_text(embedded_case_text(name))
    return p


def _one_line(capsys, *needles) -> str:
    err = [ln for ln in capsys.readouterr().err.splitlines() if ln.strip()]
    assert len(err) == 1 and err[0].startswith(("jaxgear: error: ", "fem-prep: error: ")), err
    for n in needles:
        assert n in err[0], err
    return err[0]


# -- the files a case reads ----------------------------------------------------------------------


def test_input_files_are_the_case_file_and_the_files_it_names(tmp_path):
    """A pair with a body file, a housed pair with a mesh file, a gearbox with a stage file:
    ``input_files`` lists exactly the files written here (absolute), and an embedded case
    none (its bodies are embedded names, not files)."""
    (tmp_path / "wheel.toml").write_text(fem_prep.embedded_body_text("accessory-wheel"))
    flexible = tmp_path / "flexible.toml"
    flexible.write_text(
        embedded_case_text("accessory-spur-flexible").replace(
            'body = "accessory-wheel"', 'body = "wheel.toml"'
        )
    )
    assert jio.load_case(flexible).input_files == (str(flexible), str(tmp_path / "wheel.toml"))

    (tmp_path / "box.msh").write_text("read when the housing is built, not at load")
    text = embedded_case_text("power-helical-housed")
    head, rest = text.split("\n[housing]", 1)
    housed = tmp_path / "housed.toml"
    housed.write_text(
        head + '\n[housing]\nmesh_file = "box.msh"\ncutoff_Hz = 6000.0\n[[housing.seats]]\n'
        "centre_mm = [0.0, 0.0, 20.0]\ndiameter_mm = 60.0\nwidth_mm = 12.0\n"
        "[whine]" + rest.split("[whine]", 1)[1]
    )
    assert jio.load_case(housed).input_files == (str(housed), str(tmp_path / "box.msh"))

    (tmp_path / "sub").mkdir()
    stage = tmp_path / "sub" / "stage3.toml"
    stage.write_text(embedded_case_text("nrel-5mw-stage3"))
    gearbox = tmp_path / "sub" / "gearbox.toml"
    gearbox.write_text(
        embedded_case_text("nrel-5mw-gearbox").replace(
            'case = "nrel-5mw-stage3"', 'case = "stage3.toml"'
        )
    )
    assert jio.load_case(gearbox).input_files == (str(gearbox), str(stage))
    assert jio.load_case("accessory-spur-flexible").input_files == ()


# -- file options ----------------------------------------------------------------------------


def test_run_json_refuses_the_case_file_and_an_existing_file(tmp_path, capsys, quick_run):
    case = _case_file(tmp_path)
    before = case.read_bytes()
    mine = tmp_path / "notes.json"
    mine.write_text("my own notes")
    out = str(tmp_path / "out")
    for path, force, why in (
        (case, False, "is the case file of this run"),
        (case, True, "is the case file of this run"),  # --force never replaces an input
        (mine, False, "exists (add --force to replace it)"),
    ):
        t0 = time.perf_counter()
        argv = ["run", str(case), "--out", out, "--json", str(path), "--quiet"]
        assert main(argv + ["--force"] * force) == 2
        assert time.perf_counter() - t0 < 5  # before the model is loaded
        _one_line(capsys, f"--json {path}: {why}")
    assert case.read_bytes() == before and mine.read_text() == "my own notes"
    assert not os.path.exists(out)
    # another spelling of the case file (a link to it) is the case file
    link = tmp_path / "link.json"
    link.symlink_to(case)
    assert main(["run", str(case), "--out", out, "--json", str(link), "--force", "--quiet"]) == 2
    _one_line(capsys, f"--json {link}: is the case file of this run")
    # with --force an existing file of the user's is replaced by the summary
    assert main(["run", str(case), "--out", out, "--json", str(mine), "--force", "--quiet"]) == 0
    assert '"complete": true' in mine.read_text()


def test_run_json_never_lands_on_another_output(tmp_path, capsys, quick_run):
    """``--json out/te.csv``: the summary would replace the run's own te.csv."""
    case = _case_file(tmp_path)
    out = tmp_path / "out"
    assert main(["run", str(case), "--out", str(out), "--json", str(out / "te.csv")]) == 2
    _one_line(capsys, f"--out {out}: {out / 'te.csv'} is the --json file of this run",
              "writes te.csv there")
    assert not out.exists()


def test_run_json_refuses_a_file_the_case_names(tmp_path, capsys, quick_run):
    (tmp_path / "wheel.toml").write_text(fem_prep.embedded_body_text("accessory-wheel"))
    before = (tmp_path / "wheel.toml").read_bytes()
    case = tmp_path / "c.toml"
    case.write_text(
        embedded_case_text("accessory-spur-flexible").replace(
            'body = "accessory-wheel"', 'body = "wheel.toml"'
        )
    )
    wheel = tmp_path / "wheel.toml"
    argv = ["run", str(case), "--out", str(tmp_path / "o"), "--json", str(wheel), "--force"]
    assert main(argv) == 2
    _one_line(capsys, f"--json {wheel}: is a file the case names of this run ({wheel})")
    assert wheel.read_bytes() == before


def test_optimise_write_refuses_its_case_and_an_existing_file(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(optimise_module, "_optimise", _reached)
    case = _case_file(tmp_path)
    before = case.read_bytes()
    mine = tmp_path / "notes.toml"
    mine.write_text("my own notes")
    out = str(tmp_path / "out")
    for path, force, why in (
        (case, False, "is the case file of this run"),
        (case, True, "is the case file of this run"),
        (mine, False, "exists (add --force to replace it)"),
    ):
        argv = ["optimise", str(case), "--out", out, "--write", str(path), "--quiet"]
        assert main(argv + ["--force"] * force) == 2  # refused before the optimiser starts
        _one_line(capsys, f"--write {path}: {why}")
    assert case.read_bytes() == before and mine.read_text() == "my own notes"
    with pytest.raises(Reached):  # with --force the checks pass and the work starts
        main(["optimise", str(case), "--out", out, "--write", str(mine), "--force", "--quiet"])


@pytest.mark.parametrize("command", ["cases", "bodies"])
def test_write_of_a_starting_file_needs_force(tmp_path, capsys, command):
    """``jaxgear cases NAME --write`` and ``fem-prep bodies NAME --write`` (their inputs are
    embedded: only an existing file to refuse)."""
    mine = tmp_path / "mine.toml"
    mine.write_text("my own work")
    if command == "cases":
        run, argv = main, ["cases", "power-helical", "--write", str(mine)]
    else:
        run, argv = fem_prep.main, ["bodies", "accessory-wheel", "--write", str(mine)]
    assert run(argv) == 2
    _one_line(capsys, f"--write {mine}: exists (add --force to replace it)")
    assert mine.read_text() == "my own work"
    assert run([*argv, "--force"]) == 0
    assert mine.read_text() != "my own work"


# -- output folders ----------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("command", "extra", "name"),
    [
        ("run", [], "summary.json"),
        ("modes", [], "modes.json"),
        ("sweep", ["--speeds", "100:200:3"], "sweep.json"),
        ("optimise", [], "optimum.json"),
        ("master-curve", [], "master_curve.json"),
        ("robust", ["--grade", "6"], "robust.json"),
    ],
)
def test_out_folder_refuses_an_input_where_the_command_writes(
    tmp_path, capsys, monkeypatch, command, extra, name
):
    """The case file lying in the output folder under a name the command writes there: refused
    naming ``--out``, the file and the name, before any work; the case file as it was."""
    for module, fn in ((run_module, "run_kind"), (optimise_module, "_optimise"),
                       (optimise_module, "master_curve_case")):
        monkeypatch.setattr(module, fn, _reached)
    out = tmp_path / "out"
    out.mkdir()
    case = out / name
    case.write_text(embedded_case_text("accessory-spur"))
    before = case.read_bytes()
    assert main([command, str(case), "--out", str(out), "--quiet", *extra]) == 2
    _one_line(capsys, f"--out {out}: {case} is the case file of this run", f"writes {name} there")
    assert case.read_bytes() == before and os.listdir(out) == [name]


@pytest.mark.parametrize(
    ("command", "extra", "name"),
    [
        ("run", [], "te.csv"),
        ("modes", [], "modes.json"),
        ("sweep", ["--speeds", "100:200:3"], "sweep.csv"),
        ("optimise", [], "convergence.png"),
        ("master-curve", [], "master_curve.png"),
        ("robust", ["--grade", "6"], "samples.csv"),
        ("bench", [], "bench_dynamics.json"),
    ],
)
def test_out_folder_refuses_a_users_file_with_an_output_name_without_force(
    tmp_path, capsys, monkeypatch, command, extra, name
):
    """A file of the user's (not in the folder's list of what jaxgear wrote) under a name the
    command writes: refused naming ``--out`` and the file, before any work; with ``--force``
    the work starts. A file jaxgear wrote there (listed) is replaced without ``--force``."""
    import jaxgear.cli.bench as bench_module
    import jaxgear.cli.modes as modes_module
    import jaxgear.cli.robust as robust_module
    import jaxgear.cli.sweep as sweep_module

    for module, fn in ((run_module, "run_kind"), (optimise_module, "_optimise"),
                       (optimise_module, "master_curve_case"), (modes_module, "case_modes"),
                       (sweep_module, "sweep_case"), (bench_module, "_load_benchmarks")):
        monkeypatch.setattr(module, fn, _reached)
    monkeypatch.setattr(robust_module.DeviationSampler, "for_grade", _reached)
    out = tmp_path / "out"
    out.mkdir()
    (out / name).write_text("the user's own")
    if command == "bench":
        argv = ["bench", "dynamics", "--quick", "--out", str(out)]
    else:
        argv = [command, "accessory-spur", "--out", str(out), "--quiet", *extra]
    assert main(argv) == 2
    _one_line(capsys, f"--out {out}: {out / name} exists and jaxgear did not write it",
              "add --force")
    assert (out / name).read_text() == "the user's own"
    with pytest.raises(Reached):
        main([*argv, "--force"])
    (out / ".jaxgear-outputs").write_text(f"{name}\n")  # an earlier run's: no --force needed
    with pytest.raises(Reached):
        main(argv)


def test_out_folder_keeps_an_input_that_is_not_an_output_name(tmp_path, quick_run):
    out = tmp_path / "out"
    out.mkdir()
    case = out / "c.toml"
    case.write_text(embedded_case_text("power-helical"))
    before = case.read_bytes()
    assert main(["run", str(case), "--out", str(out), "--quiet"]) == 0
    assert case.read_bytes() == before and (out / "summary.json").is_file()


def test_fem_prep_build_refuses_its_body_file_in_its_folder(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(fem_cli, "build", lambda *a, **k: pytest.fail("the build started"))
    body = tmp_path / "summary.json"  # where the build writes its summary
    body.write_text(fem_prep.embedded_body_text("accessory-wheel"))
    before = body.read_bytes()
    assert fem_prep.main(["build", str(body), "--out", str(tmp_path), "--quiet"]) == 2
    _one_line(capsys, f"--out {body}: is the body file of this run")
    assert body.read_bytes() == before


# -- SIGTERM: an interruption, as Ctrl-C -----------------------------------------------------------

#: a ``jaxgear run`` whose work writes one file, says so and then waits (the SIGTERM comes while
#: it waits): the signal's path through the real console entry, without the cost of a real run
_WAITING_RUN = """
import os, sys, time
import jaxgear.cli.run as run_module
from jaxgear.io import write_json

def run_case(case, out, **kw):
    write_json(os.path.join(out, "te.csv"), [1.0])  # a finished part
    print("finished a part", flush=True)
    time.sleep(600)

run_module.run_case = run_case
from jaxgear.cli import entry
sys.argv = ["jaxgear", *sys.argv[1:]]
entry()
"""


# default tier: tests/test_output_paths.py::test_sigterm_keeps_the_finished_parts_of_a_keep_partial_run (SIGTERM while main runs: one line, exit 143, the handler restored) and tests/test_cli_robust.py::test_interrupt_leaves_the_earlier_files_or_with_keep_partial_an_incomplete_summary (the clean-up SIGTERM's Terminated shares with Ctrl-C: the earlier results as they were, no staging folder); this one the same in a real process through its console entry
@pytest.mark.slow
def test_sigterm_mid_run_is_an_interruption_with_exit_143(tmp_path):
    """``timeout``/a job scheduler's SIGTERM while ``jaxgear run`` works (a real process, its
    console entry): one line, exit status 143 (128 + 15), the earlier results as they were and
    no hidden staging folder left (what Ctrl-C gives: tests/test_cli_robust.py)."""
    import signal
    import subprocess
    import sys

    case = _case_file(tmp_path)
    out = tmp_path / "out"
    out.mkdir()
    (out / "harris_map.png").write_bytes(b"earlier")  # an earlier run's file, listed as such
    (out / ".jaxgear-outputs").write_text("harris_map.png\n")
    p = subprocess.Popen(
        [sys.executable, "-c", _WAITING_RUN, "run", str(case), "--out", str(out), "--quiet"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )
    try:
        assert p.stdout.readline().strip() == "finished a part", p.stderr.read()
        assert [n for n in os.listdir(out) if n.startswith(".jaxgear-staging-")]  # mid-run
        p.send_signal(signal.SIGTERM)
        _, err = p.communicate(timeout=120)
    finally:
        p.kill()
    assert p.returncode == 143, err
    assert err.strip().splitlines() == ["jaxgear: terminated (SIGTERM)"], err
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "harris_map.png"]
    assert (out / "harris_map.png").read_bytes() == b"earlier"


def test_sigterm_keeps_the_finished_parts_of_a_keep_partial_run(tmp_path, capsys, monkeypatch):
    """The same SIGTERM (sent to this process while ``main`` runs) on ``--keep-partial``: the
    finished file kept where the user sees it, ``summary.json`` saying the run is incomplete,
    exit status 143; SIGTERM's own handler back after. Without it: the earlier run's files as
    they were, no staging folder left, 143 (in a real process: the slow test above)."""
    import json
    import signal

    def run_case(case, out, **kw):
        write_json(os.path.join(out, "te.csv"), [1.0])  # a finished part
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(60)  # (the handler raises at once)
        pytest.fail("SIGTERM did not stop the run")

    monkeypatch.setattr(run_module, "run_case", run_case)
    before = signal.getsignal(signal.SIGTERM)
    case = _case_file(tmp_path)
    earlier = tmp_path / "earlier"
    earlier.mkdir()
    (earlier / "harris_map.png").write_bytes(b"earlier")  # an earlier run's file, listed
    (earlier / ".jaxgear-outputs").write_text("harris_map.png\n")
    assert main(["run", str(case), "--out", str(earlier), "--quiet"]) == 143
    assert capsys.readouterr().err.strip() == "jaxgear: terminated (SIGTERM)"
    assert sorted(os.listdir(earlier)) == [".jaxgear-outputs", "harris_map.png"]
    assert (earlier / "harris_map.png").read_bytes() == b"earlier"
    assert signal.getsignal(signal.SIGTERM) == before
    out = tmp_path / "out"
    assert main(["run", str(case), "--out", str(out), "--quiet", "--keep-partial"]) == 143
    assert capsys.readouterr().err.strip() == "jaxgear: terminated (SIGTERM)"
    assert signal.getsignal(signal.SIGTERM) == before
    assert json.loads((out / "summary.json").read_text()) == {"case": "power-helical",
                                                              "complete": False}
    assert json.loads((out / "te.csv").read_text()) == [1.0]
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "summary.json", "te.csv"]
