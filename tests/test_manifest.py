"""An output folder's manifest (``.jaxgear-outputs``) is input: a run deletes only the files it
lists under one of the command's output names, matched name part by name part, that lie inside
the folder; and a run's files appear when it completes: a failed or refused run leaves the
earlier results as they were (``jaxgear run --keep-partial`` keeps what a failed run wrote)."""

import json
import os

import pytest

import jaxgear.cli.run as run_module  # its steps replaced by quick fakes (tests/test_layout.py)
from jaxgear.cli import main
from jaxgear.io import write_json

from _kinds import small_pair


def _case(tmp_path, face: float = 10.0, extra: str = "") -> str:
    path = tmp_path / "tiny.toml"
    path.write_text(small_pair("tiny", pinion_face_mm=face) + extra)
    return str(path)


def _fake_run_case(case, out, **kw):
    """``run_case`` reduced to two files (the files are what is under test)."""
    summary = {"case": case.name, "complete": True}
    write_json(os.path.join(out, "summary.json"), summary)
    write_json(os.path.join(out, "te.csv"), [1.0])
    return summary


@pytest.fixture
def quick_run(monkeypatch):
    monkeypatch.setattr(run_module, "run_case", _fake_run_case)
    monkeypatch.setattr(run_module, "format_table", lambda summary, stiffness, *modified: "")


def _listed(folder):
    text = (folder / ".jaxgear-outputs").read_text()
    return [line for line in text.splitlines() if line and not line.startswith("#")]


@pytest.mark.parametrize(
    "name",
    [
        "load_map_/../../victim.png",  # load_map_*.png of a train, fnmatch's * crossing "/"
        "pressure_map_x/../../../victim.png",
        "sweep/pressure_map_dynamic_/../../../victim.png",
        "load_map_/../load_map_/../../victim.png",
        "./../victim.png",
        "ABSOLUTE",  # the victim's absolute path
        "load_map_//../../victim.png",
    ],
)
def test_crafted_manifest_names_never_delete_outside(tmp_path, capsys, quick_run, name):
    out = tmp_path / "a" / "out"
    out.mkdir(parents=True)
    if name == "ABSOLUTE":
        name = str(tmp_path / "victim.png")
    victim = tmp_path / "a" / "out" / name
    victim = type(victim)(os.path.normpath(victim))
    assert not str(victim).startswith(str(out) + os.sep)
    victim.parent.mkdir(parents=True, exist_ok=True)
    victim.write_bytes(b"not jaxgear's")
    (out / "load_map_").mkdir()  # so that the crafted path resolves
    (out / "pressure_map_x").mkdir()
    (out / "sweep" / "pressure_map_dynamic_").mkdir(parents=True)
    (out / "harris_map.png").write_bytes(b"earlier run")  # listed and inside: deleted
    (out / ".jaxgear-outputs").write_text(f"harris_map.png\n{name}\n")
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 0
    assert victim.read_bytes() == b"not jaxgear's"
    assert not (out / "harris_map.png").exists()
    assert _listed(out) == ["summary.json", "te.csv"]


def test_links_are_never_followed_out_of_the_folder(tmp_path, quick_run):
    """A listed name under a linked folder (``scene`` → elsewhere) is not deleted; a listed
    file that is a link loses the link, never its target."""
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "load_map.png").write_bytes(b"mine")
    (elsewhere / "target.png").write_bytes(b"mine too")
    (out / "scene").symlink_to(elsewhere, target_is_directory=True)
    (out / "harris_map.png").symlink_to(elsewhere / "target.png")
    (out / ".jaxgear-outputs").write_text("scene/load_map.png\nharris_map.png\n")
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 0
    assert (elsewhere / "load_map.png").read_bytes() == b"mine"
    assert (elsewhere / "target.png").read_bytes() == b"mine too"
    assert not os.path.lexists(out / "harris_map.png")
    assert sorted(os.listdir(elsewhere)) == ["load_map.png", "target.png"]


def test_failed_late_run_leaves_the_earlier_results(tmp_path, capsys, monkeypatch):
    """A real ``jaxgear run`` whose last CSV fails (a late step) leaves the earlier complete run
    as it was and none of its files; with ``--keep-partial`` what it wrote, marked incomplete."""
    out = tmp_path / "out"
    case = _case(tmp_path)
    assert main(["run", case, "--out", str(out), "--quiet"]) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert json.loads((out / "summary.json").read_text())["complete"] is True
    assert len(before) == 9  # 8 files and the manifest
    real = run_module.write_csv

    def fail_second(path, header, columns):
        if os.path.basename(path) == "mesh_stiffness.csv":
            raise ValueError("the disk is full (injected)")
        real(path, header, columns)

    monkeypatch.setattr(run_module, "write_csv", fail_second)
    capsys.readouterr()
    assert main(["run", case, "--out", str(out), "--quiet"]) == 2
    assert capsys.readouterr().err.strip() == "jaxgear: error: the disk is full (injected)"
    after = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == before
    assert sorted(os.listdir(out)) == sorted(p.name for p in before)  # no staging folder left

    # a failed first run into a new folder leaves no folder
    fresh = tmp_path / "fresh"
    assert main(["run", case, "--out", str(fresh), "--quiet"]) == 2
    assert not fresh.exists()

    # --keep-partial: the earlier files cleared, the partial ones kept, marked incomplete
    assert main(["run", case, "--out", str(out), "--quiet", "--keep-partial"]) == 2
    assert json.loads((out / "summary.json").read_text()) == {"case": "tiny", "complete": False}
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "summary.json", "te.csv"]
    assert sorted(_listed(out)) == ["summary.json", "te.csv"]


def test_refused_sweep_leaves_the_earlier_files(tmp_path, capsys):
    """``jaxgear sweep --vtu-speed`` on a rigid scene is refused before the earlier sweep's
    files and its manifest are touched."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "sweep.json").write_text('{"earlier": true}')
    (out / ".jaxgear-outputs").write_text("sweep.json\n")
    argv = ["sweep", _case(tmp_path), "--speeds", "100:300:3", "--out", str(out), "--quiet"]
    assert main([*argv, "--vtu-speed", "200"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("jaxgear: error: --vtu-speed 200")
    assert (out / "sweep.json").read_text() == '{"earlier": true}'
    assert (out / ".jaxgear-outputs").read_text() == "sweep.json\n"
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "sweep.json"]


def test_refused_robust_leaves_the_earlier_files(tmp_path, capsys):
    """``jaxgear robust`` on a pair outside ISO 1328-1's scope (a 3 mm face) is refused before
    the earlier robust.json and the manifest are touched."""
    out = tmp_path / "out"
    out.mkdir()
    (out / "robust.json").write_text('{"earlier": true}')
    (out / ".jaxgear-outputs").write_text("robust.json\n")
    status = main(["robust", _case(tmp_path, face=3.0), "--grade", "6", "--out", str(out)])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and "face_width_mm" in err[0], err
    assert (out / "robust.json").read_text() == '{"earlier": true}'
    assert sorted(os.listdir(out)) == [".jaxgear-outputs", "robust.json"]
