"""The CLI's edges: sweep settings that cannot run are refused before any work with
one line naming the option, and a failure inside compiled code shows its own message."""

import re
from pathlib import Path

import equinox as eqx
import jax.numpy as jnp
import pytest

import jaxgear.io
from jaxgear.cli import main, runtime_message
from jaxgear.io import list_cases

from _kinds import small_pair


def _run(argv, capsys):
    status = main(argv)
    err = capsys.readouterr().err.strip().splitlines()
    return status, err


@pytest.mark.parametrize(
    ("speeds", "extra", "names"),
    [
        ("100:3000:100000000", [], "--speeds"),  # 1e8 speeds
        ("1e9:2e9:2", [], "--speeds"),  # beyond any pinion
        ("100:3000:3", ["--vtu-speed", "5000"], "--vtu-speed"),  # outside the swept band
        ("100:3000:3", ["--vtu-speed", "nan"], "--vtu-speed"),
        ("100:3000:3", ["--steps-per-period", "1"], "--steps-per-period"),
        ("100:3000:3", ["--periods", "1"], "--periods"),
        ("100:3000:3", ["--periods", "4", "--keep-periods", "8"], "--keep-periods"),
        ("100:3000:3", ["--periods", "10000000"], "--periods"),
    ],
)
def test_sweep_options_that_cannot_run(tmp_path, capsys, speeds, extra, names):
    out = tmp_path / "out"
    status, err = _run(
        ["sweep", "accessory-spur", "--speeds", speeds, "--out", str(out), *extra], capsys
    )
    assert status == 2
    assert len(err) == 1 and err[0].startswith("jaxgear: error: ")
    assert names in err[0]
    assert not out.exists()


def test_case_periods_that_cannot_run(tmp_path, capsys):
    """``[scene.integration] periods = 1e6`` is inside the key's range but 6.4e7 time steps per
    speed: refused with one line naming periods, nothing written (it ran out of memory)."""
    text = (Path(__file__).parent.parent / "jaxgear" / "cases" / "accessory-spur.toml").read_text()
    text, n = re.subn(r"(?m)^periods = .*$", "periods = 1000000", text)
    assert n == 1
    path = tmp_path / "long.toml"
    path.write_text(text)
    out = tmp_path / "out"
    status, err = _run(
        ["sweep", str(path), "--speeds", "500:1000:2", "--out", str(out), "--quiet"], capsys
    )
    assert status == 2 and len(err) == 1
    assert "periods = 1000000" in err[0] and "allowed <=" in err[0]
    assert not any(p.is_file() for p in out.rglob("*")) if out.exists() else True


def test_near_zero_speed_names_the_speeds(tmp_path, capsys):
    """A pinion speed so low that resolving the excited modes needs more than the allowed steps
    per speed: one line naming the speeds and the lowest allowed speed (it printed
    ``steps_per_period = -9223372036854775808``)."""
    out = tmp_path / "out"
    status, err = _run(
        ["sweep", "accessory-spur", "--speeds", "1e-9:1e-8:2", "--out", str(out), "--quiet"], capsys
    )
    assert status == 2 and len(err) == 1
    assert "speeds: 1e-09 rad/s" in err[0] and "allowed >=" in err[0]
    assert "-9223372036854775808" not in err[0]


def test_runtime_message_of_compiled_failure():
    """The message of ``eqx.error_if`` inside ``eqx.filter_jit`` is what the user reads, not the
    banner line ``Above is the stack outside of JIT…``."""

    @eqx.filter_jit
    def solve(x):
        return eqx.error_if(x, x > 0, "the static contact solve failed")

    with pytest.raises(eqx.EquinoxRuntimeError) as info:
        solve(jnp.asarray(1.0))
    assert str(info.value).startswith("Above is the stack")
    assert runtime_message(info.value) == "the static contact solve failed"

    # without the message line (code compiled with jax.jit): one line that says so
    banner = RuntimeError("Above is the stack outside of JIT. Below is the stack inside:\n  x")
    msg = runtime_message(banner)
    assert "\n" not in msg and "no message" in msg
    assert runtime_message(ValueError("one line")) == "one line"


def test_main_prints_the_compiled_failure(monkeypatch, tmp_path, capsys):
    """``jaxgear run`` whose compiled solve fails prints that solve's message in one line (the
    failure injected where the command loads its case, ``jaxgear.io.load_case``)."""

    @eqx.filter_jit
    def failing(x):
        return eqx.error_if(x, x > 0, "the static contact solve failed")

    def boom(name):
        failing(jnp.asarray(1.0))

    monkeypatch.setattr(jaxgear.io, "load_case", boom)
    status, err = _run(["run", list_cases()[0], "--out", str(tmp_path / "o")], capsys)
    assert status == 2
    assert err == ["jaxgear: error: the static contact solve failed"]


def test_run_sweep_slices_are_recorded(monkeypatch, tmp_path, capsys):
    """``jaxgear run`` sweeps a lumped scene at no more than 8 slices per contact line (the
    case asks 40): ``summary.json`` says so in ``dynamics.slices``."""
    import json

    # the steps before and after the sweep replaced (tests/test_layout.py)
    import jaxgear.cli.run as run_module
    import jaxgear.cli.scene as scene_module
    import jaxgear.cli.sweep as sweep_module

    seen = {}

    def fake_sweep(case, speeds, out_dir, *, slices, **kw):
        seen["slices"], seen["case_slices"] = slices, case.slices
        return {"speeds_rad_s": [100.0, 200.0], "dynamic_factor": [1.0, 1.1]}, None

    monkeypatch.setattr(run_module, "run_case", lambda case, out, **kw: {"case": case.name})
    monkeypatch.setattr(scene_module, "scene_outputs", lambda *a, **kw: {})
    monkeypatch.setattr(run_module, "format_table", lambda summary, stiffness, *modified: "")
    monkeypatch.setattr(scene_module, "scene_lines", lambda s: [])
    monkeypatch.setattr(sweep_module, "sweep_case_run", fake_sweep)  # (summary, worst run)
    out = tmp_path / "o"
    assert main(["run", "accessory-spur", "--out", str(out), "--quiet"]) == 0
    assert seen == {"slices": 8, "case_slices": 40}
    assert json.loads((out / "summary.json").read_text())["dynamics"]["slices"] == 8


TINY_SCENE = small_pair("tiny-scene") + """[scene]
model = "torsional"
[scene.integration]
steps_per_period = 16
periods = {periods}
keep_periods = 2
"""


def test_run_refuses_case_periods_before_any_file(tmp_path, capsys):
    """``jaxgear run`` on ``[scene.integration] periods = 900000``: one line naming the key, its
    value and the allowed range before the quasi-static part (it ran it, then ended with exit 2,
    the message glued to the sweep's bar, and 9 files)."""
    path = tmp_path / "long.toml"
    path.write_text(TINY_SCENE.format(periods=900000))
    out = tmp_path / "out"
    status, err = _run(["run", str(path), "--out", str(out)], capsys)
    assert status == 2 and len(err) == 1, err
    assert err[0].startswith("jaxgear: error: [scene.integration] periods = 900000: out of range")
    assert "allowed <= 262144" in err[0]
    assert not out.exists()


@pytest.mark.parametrize(
    ("argv", "needles"),
    [
        # a two-stage train repeats every 127 periods of its first mesh (it failed after 8 s)
        (
            ["sweep", "two-stage", "--speeds", "100:200:2", "--keep-periods", "2"],
            ["--keep-periods = 2: out of range, allowed >= 127"],
        ),
        (
            ["sweep", "two-stage", "--speeds", "100:200:2", "--periods", "200000"],
            ["--periods = 200000: out of range, allowed <= 29959", "steps_per_period"],
        ),
        # a train (AttributeError: 'TrainCase' object has no attribute 'deviation_settings')
        (["robust", "accessory-idler-train", "--grade", "6"], ["a gear train", "pair case"]),
        # 1e9 realisations (RESOURCE_EXHAUSTED after 12 s)
        (
            ["robust", "accessory-spur", "--grade", "6", "--samples", "1000000000"],
            ["--samples = 1000000000: out of range, allowed <=", "fewer samples"],
        ),
    ],
)
def test_late_refusals_come_first_in_one_line(tmp_path, capsys, argv, needles):
    out = tmp_path / "out"
    status, err = _run([*argv, "--out", str(out)], capsys)
    assert status == 2 and len(err) == 1, err
    assert err[0].startswith("jaxgear: error: ")
    for needle in needles:
        assert needle in err[0], err[0]
    assert not out.exists()


def test_a_failure_inside_the_bar_starts_a_fresh_line(tmp_path, capsys, monkeypatch):
    """A sweep failing while its bar is drawn: the message is a line of its own on stderr (it
    was glued to the bar's line, after its carriage return), and the folder stays empty."""
    import jaxgear.dynamics

    def late(*args, **kw):
        raise ValueError("a late failure (injected)")

    monkeypatch.setattr(jaxgear.dynamics, "speed_sweep", late)
    path = tmp_path / "tiny.toml"
    path.write_text(TINY_SCENE.format(periods=6))
    out = tmp_path / "out"
    status = main(["sweep", str(path), "--speeds", "100:200:2", "--out", str(out)])
    err = capsys.readouterr().err
    assert status == 2
    assert "jaxgear sweep tiny-scene" in err  # the bar was drawn
    assert "\njaxgear: error: a late failure (injected)\n" in err
    assert err.count("jaxgear: error:") == 1
    assert not out.exists()


# a new user's first mistakes on the default case: each refused before any work with one line
# naming what was wrong (the option or key, the value, what is allowed), nothing written
@pytest.mark.parametrize(
    ("argv", "needles"),
    [
        # a typo in a case name: the closest embedded case offered
        (["run", "accesory-spur"], ["'accesory-spur'", "did you mean 'accessory-spur'?"]),
        (["cases", "accesory-spur"], ["'accesory-spur'", "did you mean 'accessory-spur'?"]),
        # a case file that is not there: said as a file, not as an unknown embedded case
        (["run", "my-case.toml"], ["case file 'my-case.toml': no such file"]),
        # argparse's own errors: one line with the option, not the whole usage
        (["sweep", "accessory-spur", "--speeds", "100:3000:3", "--periods", "forty"],
         ["--periods", "'forty'", "allowed an integer in [2, 1e+06] or auto"]),
        (["sweep", "accessory-spur"], ["--speeds", "required"]),
        # the top parser reports a subcommand's unknown option: the hint names that command
        (["run", "--bogus"], ["unrecognized arguments: --bogus", "(jaxgear run --help"]),
        # a range below zero reaches the range check (argparse read it as an option before)
        (["sweep", "accessory-spur", "--speeds", "-100:3000:5"],
         ["--speeds '-100:3000:5'", "must be > 0"]),
        (["sweep", "accessory-spur", "--speeds", "100-3000-60"], ["--speeds", "START:STOP:N"]),
        (["sweep", "accessory-spur", "--speeds", "3000:100:5"], ["--speeds", "START must be"]),
    ],
)
def test_first_mistakes_are_one_line(tmp_path, capsys, monkeypatch, argv, needles):
    monkeypatch.chdir(tmp_path)
    status, err = _run([*argv, "--quiet"] if argv[0] != "cases" else argv, capsys)
    assert status == 2 and len(err) == 1, err
    assert all(n in err[0] for n in needles), err[0]
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        ("torque_Nm = 80.0", "torque_Nm = -80.0", ["[operating] torque_Nm = -80", "allowed >="]),
        ("teeth = 45\n", "teeth = 45\ntooth_count = 3\n", ["[pinion] unknown key 'tooth_count'"]),
        ("[scene.damping]", "[scene.dampin]", ["did you mean 'damping'?"]),
        ("slices = 40", 'slices = "forty"', ["[mesh] slices = 'forty'", "integer"]),
        ('periods = "auto"', "periods = 0", ["[scene.integration] periods = 0", "[2, 1e+06]"]),
    ],
)
def test_a_copied_case_file_with_a_mistake_is_one_line(tmp_path, capsys, old, new, needles):
    text = jaxgear.io.embedded_case_text("accessory-spur")
    assert old in text
    path = tmp_path / "my-case.toml"
    path.write_text(text.replace(old, new, 1))
    out = tmp_path / "out"
    status, err = _run(["run", str(path), "--out", str(out), "--quiet"], capsys)
    assert status == 2 and len(err) == 1, err
    assert all(n in err[0] for n in needles), err[0]
    assert not out.exists()


def test_an_output_folder_that_is_a_file(tmp_path, capsys):
    (tmp_path / "afile").write_text("mine")
    status, err = _run(["run", "--out", str(tmp_path / "afile"), "--quiet"], capsys)
    assert status == 2 and err == [f"jaxgear: error: --out {tmp_path / 'afile'}: is a file, not a folder"]
    assert (tmp_path / "afile").read_text() == "mine"
    # a --json file under it: the file that is in the way named, not the path given
    status, err = _run(["run", "--json", str(tmp_path / "afile" / "s.json"), "--quiet"], capsys)
    assert status == 2 and len(err) == 1
    assert err[0].endswith(f"s.json: {tmp_path / 'afile'} is a file, not a folder"), err[0]


def test_output_folder_is_said_without_a_doubled_slash(tmp_path):
    # jaxgear run --out results/ said "written to results//"
    from fem_prep.schema import check_output_dir  # jaxgear's output folders' one check

    assert check_output_dir(f"{tmp_path}/results/") == f"{tmp_path}/results"


def test_periods_auto_on_the_command_line_replaces_a_case_files_fixed_periods():
    # --periods auto: the settled sweep (spec periods None), whatever the case file fixes
    from jaxgear.cli.sweep import sweep_spec

    case = jaxgear.io.load_case("accessory-spur")
    fixed = sweep_spec(case, periods=40)
    assert fixed.periods == 40
    assert sweep_spec(case.replace(scene=fixed), periods="auto").periods is None
    assert sweep_spec(case.replace(scene=fixed)).periods == 40  # None keeps the case's
