"""Starting from an embedded case or body, and fem-prep's edges.

``jaxgear cases NAME [--write FILE]`` and ``fem-prep bodies NAME [--write FILE]`` give the file a
user starts from; the written file loads to the same case/body as the embedded one. fem-prep
checks its output folder before the build, exits 130 with one line on Ctrl-C and quietly on a
closed pipe.
"""

import subprocess
import sys

import pytest

import fem_prep
import fem_prep.cli as fem_cli  # only to patch the build it calls (tests/test_layout.py)
from jaxgear.cli import main
from jaxgear.io import list_cases, load_case


def _err_lines(capsys):
    return capsys.readouterr().err.strip().splitlines()


@pytest.mark.parametrize("name", list_cases())
def test_written_case_loads_as_the_embedded_one(tmp_path, capsys, name):
    path = tmp_path / "mine.toml"
    assert main(["cases", name, "--write", str(path)]) == 0
    assert str(path) in capsys.readouterr().out
    written, embedded = load_case(path), load_case(name)
    assert written.raw == embedded.raw
    assert written.name == embedded.name


def test_case_printed_to_stdout(capsys):
    assert main(["cases", "power-helical"]) == 0
    out = capsys.readouterr().out
    assert 'name = "power-helical"' in out and "[pair]" in out


def test_case_write_refuses_to_replace_without_force(tmp_path, capsys):
    path = tmp_path / "mine.toml"
    path.write_text("my own work")
    assert main(["cases", "accessory-spur", "--write", str(path)]) == 2
    assert _err_lines(capsys) == [
        f"jaxgear: error: --write {path}: exists (add --force to replace it)"
    ]
    assert path.read_text() == "my own work"
    assert main(["cases", "accessory-spur", "--write", str(path), "--force"]) == 0
    assert load_case(path).name == "accessory-spur"


@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["cases", "no-such-case"], "no embedded case 'no-such-case'"),
        (["cases", "--write", "x.toml"], "--write needs a case NAME"),
    ],
)
def test_case_errors_are_one_line(tmp_path, capsys, monkeypatch, argv, needle):
    monkeypatch.chdir(tmp_path)
    assert main(argv) == 2
    err = _err_lines(capsys)
    assert len(err) == 1 and needle in err[0]
    assert list(tmp_path.iterdir()) == []


def test_case_write_into_a_folder_or_under_a_file(tmp_path, capsys):
    (tmp_path / "f").write_text("")
    assert main(["cases", "accessory-spur", "--write", str(tmp_path)]) == 2
    assert "is a folder, expected a file name" in _err_lines(capsys)[0]
    assert main(["cases", "accessory-spur", "--write", str(tmp_path / "f" / "x.toml")]) == 2
    assert "is a file, not a folder" in _err_lines(capsys)[0]


def test_written_body_loads_as_the_embedded_one(tmp_path, capsys):
    name = fem_prep.embedded_bodies()[0]
    path = tmp_path / "wheel.toml"
    assert fem_prep.main(["bodies", name, "--write", str(path)]) == 0
    assert fem_prep.load_body(path) == fem_prep.load_body(name)
    assert fem_prep.main(["bodies", name, "--write", str(path)]) == 2
    assert _err_lines(capsys)[-1].endswith("exists (add --force to replace it)")
    assert fem_prep.main(["bodies", "no-such-body"]) == 2
    assert "no embedded body 'no-such-body'" in _err_lines(capsys)[0]


@pytest.mark.parametrize("under", [False, True])
def test_fem_prep_out_is_checked_before_the_build(tmp_path, capsys, monkeypatch, under):
    """``--out`` naming a file (or a folder under a file) fails at once, not after the build."""
    monkeypatch.setattr(fem_cli, "build", lambda *a, **k: pytest.fail("the build started"))
    f = tmp_path / "f"
    f.write_text("")
    out = f / "sub" if under else f
    assert fem_prep.main(["build", "accessory-wheel", "--out", str(out), "--quiet"]) == 2
    (line,) = _err_lines(capsys)
    assert line.startswith(f"fem-prep: error: --out {out}: ") and "is a file" in line
    assert fem_prep.main(["bench", "--out", str(out), "--quick"]) == 2


def test_fem_prep_interrupted(tmp_path, capsys, monkeypatch):
    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(fem_cli, "build", interrupted)
    status = fem_prep.main(["build", "accessory-wheel", "--out", str(tmp_path / "o"), "--quiet"])
    assert status == 130
    assert _err_lines(capsys) == ["fem-prep: interrupted"]


def test_fem_prep_bodies_into_a_closed_pipe():
    """``fem-prep bodies | head -1`` when the reader has gone: no traceback, exit 0."""
    code = "import sys; from fem_prep import main; sys.exit(main(['bodies']))"
    writer = subprocess.Popen(
        [sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE
    )
    writer.stdout.close()  # the reader goes away before the writer has written anything
    err = writer.stderr.read()
    writer.stderr.close()
    assert writer.wait(timeout=120) == 0
    assert b"Traceback" not in err and b"Error" not in err
