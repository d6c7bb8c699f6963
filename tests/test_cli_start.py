"""The console script's first line: ``jaxgear run`` says it is starting before the command line's
own imports (fem_prep, the optimisers, jaxgear.io, the command's module, matplotlib), which with
the first compilation keep it silent for seconds; ``--help`` prints no such line. Run as the
``jaxgear`` script runs (``from jaxgear.cli import entry; entry()``) in a subprocess; no time is
asserted, the order of the lines is: under ``python -X importtime`` each imported module's line
goes to stderr as its import ends, so the start line stands before those of the modules imported
after it."""

import pathlib
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]
ENTRY = "from jaxgear.cli import entry; entry()"  # what the jaxgear script runs
START = "jaxgear run: starting (loading and compiling)..."
LATER = ("fem_prep", "jaxgear.cli._main", "optimise", "jaxgear.io")  # after the line


def test_run_says_it_is_starting_before_the_command_lines_imports(tmp_path):
    cmd = [sys.executable, "-X", "importtime", "-c", ENTRY, "run", "--out", str(tmp_path / "o")]
    proc = subprocess.Popen(
        cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT
    )
    lines, imported = [], {}  # stderr's lines; module -> index of its import's line
    try:
        for line in proc.stderr:  # until the modules of LATER are imported, then stop
            lines.append(line.rstrip("\n"))
            if line.startswith("import time:"):
                imported[line.rsplit("|", 1)[1].strip()] = len(lines) - 1
            elif lines[-1] != START:  # another line of the command's own: seen enough
                break
            if all(m in imported for m in LATER):
                break
    finally:
        proc.kill()
        proc.communicate(timeout=60)
    own = [i for i, s in enumerate(lines) if not s.startswith("import time:")]
    assert own and lines[own[0]] == START, lines[-5:]
    assert imported["jaxgear"] < own[0]  # the model (JAX, equinox): before, as a package
    for module in LATER:
        assert imported[module] > own[0], module


def test_help_prints_no_start_line():
    proc = subprocess.run(
        [sys.executable, "-c", ENTRY, "--help"], capture_output=True, text=True, cwd=ROOT
    )
    assert proc.returncode == 0 and proc.stdout.startswith("usage: jaxgear")
    assert proc.stderr == ""
