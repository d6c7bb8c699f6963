"""The progress output of ``jaxgear run`` and ``jaxgear sweep`` (stderr): every bar has a total,
so that tqdm prints the elapsed and the remaining time (``[00:03<00:05``) once a step is done,
and each long stage says what it is doing (the sweep's compilation, its outputs, the stages of
a planetary run). No timing is asserted, only the fields."""

import re

import pytest
from _kinds import small_pair

import jaxgear.cli.planetary_sweep as cli_planetary
from jaxgear.cli import main
from jaxgear.io import load_case

# tqdm's bar with a total, after at least one step: "k/n [elapsed<remaining"
ESTIMATE = r"\|\s*(\d+)/(\d+) \[\d\d:\d\d<\d\d:\d\d"

TINY_SCENE = (
    small_pair("tiny-scene")
    + """[scene]
model = "torsional"
[scene.integration]
steps_per_period = 16
periods = 6
keep_periods = 2
"""
)


def _states(err: str, desc: str) -> list[str]:
    """The bar ``desc``'s states as printed (tqdm redraws a bar after a carriage return)."""
    return [s for s in re.split(r"[\r\n]", err) if s.startswith(desc + ":")]


def _estimated(states: list[str], total: int) -> set[int]:
    """The step counts k < total at which a state shows the remaining time of a total."""
    seen = set()
    for s in states:
        m = re.search(ESTIMATE, s)
        if m and int(m.group(2)) == total and int(m.group(1)) < total:
            seen.add(int(m.group(1)))
    return seen


def test_run_bar_has_a_total_an_estimate_and_stage_labels(tmp_path, capsys, no_figures):
    """A pair without a scene: the run's bar over its 7 steps shows the remaining time from
    the first step on, and names each stage (quasi-static solves, Harris map, files)."""
    path = tmp_path / "small.toml"
    path.write_text(small_pair("small"))
    assert main(["run", str(path), "--out", str(tmp_path / "out")]) == 0
    states = _states(capsys.readouterr().err, "jaxgear run small")
    assert _estimated(states, 7) >= {1, 2, 3, 4, 5, 6}
    text = "\n".join(states)
    for label in (
        "quasi-static, unmodified, exact contact",
        "quasi-static, modified, smooth contact",
        "Harris map",
        "contact pressure",
        "files and plots",
    ):
        assert label in text, label


@pytest.mark.slow  # ~6 CPU s at -O0: the run's and the planetary run's bars are the default tier's
@pytest.mark.filterwarnings("ignore:.*under-resolved")  # 16 steps per period: a tiny check
def test_sweep_bars_label_the_compilation_and_the_outputs(tmp_path, capsys):
    """A tiny torsional scene at 2 speeds: the speeds' bar says it compiles before the first
    speed and shows the remaining time after it; the outputs that follow (a second run at the
    worst speed, files) have a bar of 3 stages with its estimate and labels."""
    path = tmp_path / "tiny.toml"
    path.write_text(TINY_SCENE)
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--speeds", "100:200:2", "--out", str(out)]) == 0
    err = capsys.readouterr().err
    speeds = _states(err, "jaxgear sweep tiny-scene")
    assert any("compiling the sweep" in s for s in speeds)
    assert any(re.search(r"\|\s*2/2 \[\d\d:\d\d<\d\d:\d\d", s) for s in speeds)
    outputs = _states(err, "jaxgear sweep tiny-scene: outputs")
    assert _estimated(outputs, 3) >= {1, 2}
    text = "\n".join(outputs)
    for label in ("pressure map at the worst speed", "files and plots"):
        assert label in text, label


def test_planetary_run_bar_over_its_stages(tmp_path, capsys, monkeypatch):
    """A planetary ``jaxgear run`` showed nothing for its whole run (50 s on nrel-5mw-stage2):
    now a bar over its two stages (the stage's files, the first-look sweep) with their labels
    and the remaining time after the first. The stages themselves are replaced by stand-ins
    here (their results are tested in test_planetary_case.py)."""
    case = load_case("lin-parker-1999")
    sweep_keys = [
        *("model", "speed_of", "speeds_rad_s", "dynamic_factor", "max_dynamic_factor"),
        *("speed_of_max_rad_s", "mesh_names", "max_dynamic_factor_mesh", "k_gamma"),
        *("max_k_gamma", "k_gamma_mean_load", "max_k_gamma_mean_load", "ring_model", "ring", "steps_per_period", "steps_resolution"),
        "excitation",
    ]
    monkeypatch.setattr(cli_planetary, "planetary_files", lambda *a: {"case": case.name})
    monkeypatch.setattr(cli_planetary, "planetary_sweep",
                        lambda *a, **kw: dict.fromkeys(sweep_keys))

    class Args:
        quiet = False

    cli_planetary.planetary_run_files(case.form, case, str(tmp_path), Args(), True)
    states = _states(capsys.readouterr().err, f"jaxgear run {case.name}")
    assert _estimated(states, 2) == {1}
    text = "\n".join(states)
    assert "load sharing, modes, Campbell" in text and "dynamic sweep, 9 speeds" in text
