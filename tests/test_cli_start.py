"""The console script answers at once: ``jaxgear --help``, ``--version``, a subcommand's
``--help`` and ``jaxgear cases`` parse the command line before the model is loaded and import
neither JAX, equinox, the optimisers nor fem_prep (checked in ``sys.modules`` of the process the
``jaxgear`` script runs: ``import jaxgear_start; jaxgear_start.entry()``); a command that
computes says it is starting before the model loads (the order of stderr's lines under ``python
-X importtime``: each imported module's line goes to stderr as its import ends). No time is
asserted here (benchmarks/_startup.py measures it). ``jaxgear cases`` lists rating and run
time; every subcommand's help has an example; speeds are taken in rpm too."""

import math
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
ENTRY = "import jaxgear_start; jaxgear_start.entry()"  # what the jaxgear script runs
HEAVY = ("jax", "equinox", "optimise", "fem_prep", "jaxgear.io", "jaxgear.dynamics")
# the script, then the heavy modules it has loaded on stderr's last line
PROBE = (
    "import sys, jaxgear_start\n"
    "try:\n"
    "    jaxgear_start.entry()\n"
    "finally:\n"
    f"    print('LOADED', *[m for m in {HEAVY!r} if m in sys.modules], file=sys.stderr)\n"
)
START = "jaxgear run: starting (loading and compiling)..."


@pytest.mark.parametrize(
    "args",
    [
        ["--help"],
        ["--version"],
        ["cases"],
        ["run", "--help"],
        ["sweep", "--help"],
        ["robust", "--help"],
        ["modes", "--help"],
        ["cases", "--help"],
        ["optimise", "--help"],
        ["master-curve", "--help"],
    ],
)
def test_help_version_and_cases_load_no_model(args):
    proc = subprocess.run(
        [sys.executable, "-c", PROBE, *args], capture_output=True, text=True, cwd=ROOT, timeout=300
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    lines = proc.stderr.strip().splitlines()
    assert lines[-1] == "LOADED", lines[-1]  # none of HEAVY
    assert "starting" not in proc.stderr  # nothing is loaded or compiled


def test_run_says_it_is_starting_before_the_model_loads(tmp_path):
    cmd = [sys.executable, "-X", "importtime", "-c", ENTRY, "run", "--out", str(tmp_path / "o")]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT
    )
    lines, imported = [], {}  # stderr's lines; module -> index of its import's line
    try:
        for line in proc.stderr:  # until the modules of HEAVY are imported, then stop
            lines.append(line.rstrip("\n"))
            if line.startswith("import time:"):
                imported[line.rsplit("|", 1)[1].strip()] = len(lines) - 1
            elif lines[-1] != START:  # another line of the command's own: seen enough
                break
            if all(m in imported for m in ("jax", "equinox", "jaxgear.io")):
                break
    finally:
        proc.kill()
        proc.communicate(timeout=60)
    own = [i for i, s in enumerate(lines) if not s.startswith("import time:")]
    assert own and lines[own[0]] == START, lines[-5:]
    for module in ("jax", "equinox", "jaxgear.io"):
        assert imported[module] > own[0], module


def test_optimise_choices_are_the_model_names():
    """``optimise``'s choices are declared without the model (so that its ``--help`` loads
    none): those its help shows are the names :mod:`jaxgear.io` and :mod:`optimise` map to
    objects."""
    import jaxgear.io as jio
    import optimise

    proc = subprocess.run(
        [sys.executable, "-c", ENTRY, "optimise", "--help"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    text = " ".join(proc.stdout.split())

    def choices(option):
        found = re.search(re.escape(option) + r" \{([^}]*)\}", text)
        assert found, option
        return set(found[1].split(","))

    assert choices("--objective") == set(jio.OBJECTIVES)
    assert choices("--method") == set(jio.OPTIMISERS)
    assert choices("--reduce") == set(jio.STATISTICS)
    listed = re.search(r"\(allowed: ([^)]*), optionally", text)
    assert listed and set(listed[1].split(", ")) == set(optimise.VARIABLES)


def test_optimise_refuses_an_unknown_objective_before_the_model_loads():
    proc = subprocess.run(
        [sys.executable, "-c", PROBE, "optimise", "accessory-spur", "--objective", "nope"],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
    )
    assert proc.returncode == 2
    assert "--objective" in proc.stderr and "te_rms" in proc.stderr
    assert proc.stderr.strip().splitlines()[-1] == "LOADED"  # refused before any import


def test_help_prints_no_start_line():
    proc = subprocess.run(
        [sys.executable, "-c", ENTRY, "--help"], capture_output=True, text=True, cwd=ROOT
    )
    assert proc.returncode == 0 and proc.stdout.startswith("usage: jaxgear")
    assert proc.stderr == ""


def test_cases_lists_rating_and_run_time(capsys):
    from jaxgear.cli import main

    assert main(["cases"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split()[:4] == ["NAME", "RATED", "RUN", "1st/2nd"]
    rows = {line.split()[0]: line.split() for line in out[1:-1]}
    names = sorted(p.stem for p in (ROOT / "jaxgear" / "cases").glob("*.toml"))
    assert sorted(rows) == names  # every embedded case, one row each
    # by hand, from the case files: [rating] present
    assert rows["accessory-spur"][1] == "-"
    assert rows["accessory-idler-train"][1] == "-"
    assert rows["power-helical"][1] == "yes"
    assert rows["nrel-5mw-planetary"][1] == "yes"
    assert rows["nrel-5mw-gearbox"][1:4] == ["3", "of", "3"]
    for line in out[1:-1]:  # a run time for each: seconds, first run >= second
        found = re.search(r"  ~?(\d+)/(\d+) s  ", line)
        assert found, line
        first, second = float(found[1]), float(found[2])
        assert 0 < second <= first < 600, line
    assert "starting" not in capsys.readouterr().err


def test_cases_lines_are_the_loaded_cases():
    """The listing's stored description of each case is what the loaded case gives, and its
    rating what the file holds (a ``[rating]`` table; a gearbox: its stages'); a case file
    changed: update jaxgear/cli/cases.py's CASE_INDEX."""
    import tomllib

    import jaxgear.io as jio
    from jaxgear.cli import case_line
    from jaxgear.cli.cases import CASE_INDEX

    def data(name):
        return tomllib.loads((ROOT / "jaxgear" / "cases" / f"{name}.toml").read_text("utf-8"))

    assert sorted(CASE_INDEX) == sorted(jio.list_cases())
    for name in jio.list_cases():
        assert CASE_INDEX[name][0] == case_line(jio.load_case(name)), name
        stages = [s["case"] for s in data(name).get("stages", [])]
        rated = sum("rating" in data(s) for s in stages)
        expect = "yes" if "rating" in data(name) else f"{rated} of {len(stages)} stages"
        assert CASE_INDEX[name][1] == (expect if expect != "0 of 0 stages" else "-"), name


def test_cases_cold_column_is_the_recorded_builds_of_the_cases_with_fe_parts(capsys):
    """``jaxgear cases``' COLD: a figure for exactly the cases whose files ask for condensed
    FE bodies or a housing (read from the loaded cases), each RUN's first run plus the build
    its benchmark recorded: the bodies' idle wall seconds (bench_run_cases_idle_flexible.json,
    whose first runs are RUN's too), the housings' 1.7 x their CPU seconds under load
    (bench_cold_builds.json); 1.7 lies within the ratios of the bodies measured both ways."""
    import json

    import jaxgear.io as jio
    from jaxgear.cli import main
    from jaxgear.cli.cases import CASE_INDEX, FE_BUILD

    def fe_parts(case):
        gearbox = isinstance(case.form, jio.GearboxForm) and case.form.housing is not None
        return (case.scene is not None and case.scene.hybrid) or case.housing is not None or (
            gearbox)

    assert sorted(FE_BUILD) == sorted(n for n in jio.list_cases() if fe_parts(jio.load_case(n)))
    bench = ROOT / "docs" / "bench"
    idle = {r["case"]: r for r in
            json.loads((bench / "bench_run_cases_idle_flexible.json").read_text())["results"]}
    loaded = {r["case"]: r for r in
              json.loads((bench / "bench_cold_builds.json").read_text())["results"]}
    ratios = [idle[n]["bodies_s"] / loaded[n]["cpu_s"] for n in idle]
    assert min(ratios) <= 1.7 <= max(ratios) and max(ratios) / min(ratios) < 1.05, ratios
    for name, (seconds, measured) in FE_BUILD.items():
        if measured:
            assert seconds == pytest.approx(idle[name]["bodies_s"], abs=0.05), name
            assert CASE_INDEX[name][2] == round(idle[name]["first"]["wall_s"]), name
        else:
            assert seconds == pytest.approx(1.7 * loaded[name]["cpu_s"], abs=0.05), name
    assert main(["cases"]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].split()[:5] == ["NAME", "RATED", "RUN", "1st/2nd", "COLD"]
    for line in out[1:-1]:
        name = line.split()[0]
        found = re.search(r"  ~?(\d+)/\d+ s  +(~?(\d+) s|-)  ", line)
        assert found, line
        if name in FE_BUILD:
            assert int(found[3]) == round(CASE_INDEX[name][2] + FE_BUILD[name][0]), line
        else:
            assert found[2] == "-", line


@pytest.mark.parametrize(
    "command",
    ["run", "cases", "bench", "prep", "sweep", "modes", "robust", "optimise", "master-curve"],
)
def test_every_command_help_has_an_example_and_describes_every_option(command, capsys):
    from jaxgear.cli import main

    assert main([command, "--help"]) == 0
    text = capsys.readouterr().out
    example = text.split("example:\n", 1)[1].split()
    assert example[:2] == ["jaxgear", command]
    # every option has a description: no option line ends bare (argparse puts the help after it)
    lines = text.split("options:\n", 1)[1].split("\n\n", 1)[0].splitlines()
    for k, line in enumerate(lines):
        words = line.split()
        if words and words[0].startswith("--") and len(words) <= 2:
            nxt = lines[k + 1] if k + 1 < len(lines) else ""
            assert nxt.startswith(" " * 10) and not nxt.split()[0].startswith("-"), line


def test_robust_help_shows_defaults(capsys):
    from jaxgear.cli import main

    assert main(["robust", "--help"]) == 0
    text = " ".join(capsys.readouterr().out.split())
    assert "else 200)" in text and "else 0)" in text and "[deviations] grade)" in text


def test_speeds_in_rpm(tmp_path, capsys):
    """``--speeds-rpm`` is read in 1/min and carried on in rad/s (2π/60 per rpm): a VTU speed
    in rad/s outside the band shows the band in rad/s, one in rpm in rpm; the bound on the top
    speed in rpm; the two forms of one option go not together."""
    from jaxgear.cli import main

    out = str(tmp_path / "o")
    assert (
        main(
            [
                "sweep",
                "accessory-spur",
                "--speeds-rpm",
                "1000:3000:3",
                "--vtu-speed",
                "1",
                "--out",
                out,
            ]
        )
        == 2
    )
    err = capsys.readouterr().err
    lo, hi = 1000 * 2 * math.pi / 60, 3000 * 2 * math.pi / 60
    assert f"[{lo:.6g}, {hi:.6g}] rad/s" in err, err
    assert (
        main(
            [
                "sweep",
                "accessory-spur",
                "--speeds-rpm",
                "1000:3000:3",
                "--vtu-speed-rpm",
                "4000",
                "--out",
                out,
            ]
        )
        == 2
    )
    # in the option's own unit
    assert "--vtu-speed-rpm 4000: out of range, allowed a speed of the sweep, [1000, 3000] rpm" in (
        capsys.readouterr().err
    )
    assert main(["sweep", "accessory-spur", "--speeds-rpm", "1000:2000000:3", "--out", out]) == 2
    top = 1e5 * 60 / (2 * math.pi)  # the pinion speed bound, 1e5 rad/s, in rpm
    assert f"STOP = 2e+06 rpm, allowed <= {top:.6g} rpm" in capsys.readouterr().err
    assert main(["sweep", "accessory-spur", "--speeds", "1:2:3", "--speeds-rpm", "1:2:3"]) == 2
    assert "not allowed with argument --speeds" in capsys.readouterr().err
    assert main(["sweep", "accessory-spur", "--speeds-rpm", "0:3000:3", "--out", out]) == 2
    assert "--speeds-rpm '0:3000:3': values must be > 0" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_the_installed_script_is_the_deferring_one():
    """The console script ``jaxgear`` runs :mod:`jaxgear_start` (installed as a module of its
    own beside the packages): ``jaxgear.cli:entry`` would load the model before parsing."""
    import tomllib

    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert project["project"]["scripts"]["jaxgear"] == "jaxgear_start:entry"
    assert "jaxgear_start" in project["tool"]["setuptools"]["py-modules"]
    assert (ROOT / "jaxgear_start.py").is_file()
