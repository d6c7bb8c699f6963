"""An output folder's manifest (``.jaxgear-outputs``) is input: a run deletes only the files it
lists under one of the command's output names, matched name part by name part, that lie inside
the folder; and a run's files appear when it completes: a failed or refused run leaves the
earlier results as they were (``jaxgear run --keep-partial`` keeps what a failed run wrote)."""

import json
import os

import equinox as eqx
import pytest

import jaxgear.cli.run as run_module  # its steps replaced by quick fakes (tests/test_layout.py)
import jaxgear.io as jio
from fem_prep.schema import atomic_write
from jaxgear.cli import clear_outputs, main
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


def test_links_are_never_followed_out_of_the_folder(tmp_path, capsys, quick_run):
    """A folder whose ``scene`` (a subfolder ``jaxgear run`` writes) is a link out of it is
    refused before anything is touched; without it, a listed file that is a link loses the
    link, never its target."""
    out = tmp_path / "out"
    out.mkdir()
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "load_map.png").write_bytes(b"mine")
    (elsewhere / "target.png").write_bytes(b"mine too")
    (out / "scene").symlink_to(elsewhere, target_is_directory=True)
    (out / "harris_map.png").symlink_to(elsewhere / "target.png")
    (out / ".jaxgear-outputs").write_text("scene/load_map.png\nharris_map.png\n")
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == [
        (
            f"jaxgear: error: --out {out}: {out / 'scene'} is a symbolic link to {elsewhere}, "
            "outside the output folder (jaxgear writes only inside it, never through a link): "
            "remove the link or choose another --out"
        )
    ]
    assert os.path.islink(out / "harris_map.png")
    assert (out / ".jaxgear-outputs").read_text() == "scene/load_map.png\nharris_map.png\n"
    (out / "scene").unlink()
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 0
    assert (elsewhere / "load_map.png").read_bytes() == b"mine"
    assert (elsewhere / "target.png").read_bytes() == b"mine too"
    assert not os.path.lexists(out / "harris_map.png")
    assert sorted(os.listdir(elsewhere)) == ["load_map.png", "target.png"]


def _entries(folder) -> list[str]:
    """The names of everything under ``folder``, links to folders not followed."""
    return sorted(n for _, dirs, files in os.walk(folder) for n in dirs + files)


def _users_folder(tmp_path, sub: str):
    """An output folder whose ``sub`` is a link to a folder of the user's outside it, holding
    files with the names jaxgear writes there; returns (out, the user's folder, its bytes)."""
    out = tmp_path / "out"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    for name in ("sweep.json", "sweep.csv", "body_pinion.vtu", "optimum.json"):
        (elsewhere / name).write_bytes(b"the user's own " + name.encode())
    (out / sub).parent.mkdir(parents=True, exist_ok=True)
    (out / sub).symlink_to(elsewhere, target_is_directory=True)
    return out, elsewhere, {p.name: p.read_bytes() for p in elsewhere.iterdir()}


def _writes_through(sub: str):
    """A ``run_case`` that writes a run's files and files into ``sub/`` of its folder (the
    sweep's, as ``jaxgear run`` on a case with a [scene] does)."""

    def run_case(case, out, **kw):
        _fake_run_case(case, out)
        write_json(os.path.join(out, sub, "sweep.json"), {"this run": True})
        write_json(os.path.join(out, sub, "sweep.csv"), [1.0])
        return {"case": case.name, "complete": True}

    return run_case


@pytest.mark.parametrize("keep_partial", [False, True])
@pytest.mark.parametrize("sub", ["sweep", "optimise", "stage1", "stage2/sweep"])
def test_run_refuses_a_subfolder_linked_out_of_the_folder(
    tmp_path, capsys, quick_run, monkeypatch, sub, keep_partial
):
    """``out/sweep -> ../elsewhere`` (or any subfolder ``jaxgear run`` writes: optimise/, a
    gearbox's stage<k>/ and theirs): refused in one line naming the link before any work, with
    or without --keep-partial; the user's files behind the link untouched, none added."""
    out, elsewhere, before = _users_folder(tmp_path, sub)
    monkeypatch.setattr(run_module, "run_case", _writes_through(sub))
    extra = ["--keep-partial"] if keep_partial else []
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet", *extra]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith(
        f"jaxgear: error: --out {out}: {out / sub} is a symbolic link to {elsewhere}, outside"
    ), err
    assert {p.name: p.read_bytes() for p in elsewhere.iterdir()} == before
    assert _entries(out) == sorted(sub.split("/"))  # the link (and its real parents) only


def test_a_link_made_during_the_run_is_refused_when_the_files_move(
    tmp_path, capsys, quick_run, monkeypatch
):
    """A subfolder turned into a link out of the folder while the run ran: the files are not
    moved through it (none moves), the user's files stay."""
    out = tmp_path / "out"
    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    (elsewhere / "sweep.json").write_bytes(b"the user's")
    write = _writes_through("sweep")

    def run_case(case, work, **kw):
        (out / "sweep").symlink_to(elsewhere, target_is_directory=True)
        return write(case, work)

    monkeypatch.setattr(run_module, "run_case", run_case)
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{out / 'sweep'} leads to {elsewhere}, outside" in err[0], err
    assert sorted(os.listdir(elsewhere)) == ["sweep.json"]
    assert (elsewhere / "sweep.json").read_bytes() == b"the user's"
    assert sorted(os.listdir(out)) == ["sweep"]  # no file moved, no staging folder left


def test_sweep_refuses_a_vtu_folder_linked_out_of_the_folder(tmp_path, capsys):
    """``jaxgear sweep``'s subfolder ``vtu/`` a link out of the folder: refused before work."""
    out, elsewhere, before = _users_folder(tmp_path, "vtu")
    argv = ["sweep", _case(tmp_path), "--speeds", "100:300:3", "--out", str(out), "--quiet"]
    assert main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"{out / 'vtu'} is a symbolic link to {elsewhere}" in err[0], err
    assert {p.name: p.read_bytes() for p in elsewhere.iterdir()} == before
    assert os.listdir(out) == ["vtu"]


def test_a_link_inside_the_folder_is_followed(tmp_path, quick_run, monkeypatch):
    """A subfolder linked to another folder inside the output folder is written through."""
    out = tmp_path / "out"
    (out / "real").mkdir(parents=True)
    (out / "sweep").symlink_to(out / "real", target_is_directory=True)
    monkeypatch.setattr(run_module, "run_case", _writes_through("sweep"))
    assert main(["run", _case(tmp_path), "--out", str(out), "--quiet"]) == 0
    assert json.loads((out / "real" / "sweep.json").read_text()) == {"this run": True}


def test_every_writer_refuses_a_path_through_a_link_out_of_its_output_folder(tmp_path):
    """The atomic writers of both packages, writing in an output folder (``clear_outputs``
    records it: ``jaxgear bench``, ``optimise``, ``run --keep-partial`` write so), refuse a
    file whose folder leads out of it through a link; ``clear_outputs`` itself refuses first."""
    out, elsewhere, before = _users_folder(tmp_path, "sweep")
    with pytest.raises(ValueError, match=r"sweep is a symbolic link to .*elsewhere, outside"):
        clear_outputs(out, "run")
    assert clear_outputs(out, "bench robust") == []  # writes no subfolder: nothing to refuse
    with pytest.raises(ValueError) as err:
        write_json(out / "sweep" / "sweep.json", {"x": 1})
    assert str(err.value) == (
        f"{out / 'sweep' / 'sweep.json'}: {out / 'sweep'} leads to {elsewhere}, outside the "
        f"output folder {out}, through a symbolic link (a command writes only inside its "
        "output folder): remove the link"
    )
    with pytest.raises(ValueError, match="outside the output folder"):
        atomic_write(out / "sweep" / "vtu" / "x.vtu", lambda tmp: tmp.write_bytes(b"x"))
    assert {p.name: p.read_bytes() for p in elsewhere.iterdir()} == before
    write_json(out / "robust.json", {"x": 1})  # inside: written
    assert json.loads((out / "robust.json").read_text()) == {"x": 1}


def test_failed_late_run_leaves_the_earlier_results(tmp_path, capsys, monkeypatch):
    """A real ``jaxgear run`` whose last CSV fails (a late step) leaves the earlier complete run
    as it was and none of its files; with ``--keep-partial`` the same when the failure is a
    refusal of its input (a ValueError), what it wrote, marked incomplete, when the computation
    fails."""
    out = tmp_path / "out"
    case = _case(tmp_path)
    assert main(["run", case, "--out", str(out), "--quiet"]) == 0
    before = {p: p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert json.loads((out / "summary.json").read_text())["complete"] is True
    # 9 files (loaded_path.png with the case files' default extended_contact) and the manifest
    assert len(before) == 10
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

    # --keep-partial and a refusal (a ValueError: the CLI's bad input): the earlier results
    # back, byte for byte, none of this run's
    assert main(["run", case, "--out", str(out), "--quiet", "--keep-partial"]) == 2
    assert {p: p.read_bytes() for p in out.rglob("*") if p.is_file()} == before
    assert sorted(os.listdir(out)) == sorted(p.name for p in before)  # nothing set aside left

    # --keep-partial and a failure of the computation: the earlier files cleared, the partial
    # ones kept, marked incomplete
    def solver_fails(path, header, columns):
        if os.path.basename(path) == "mesh_stiffness.csv":
            raise eqx.EquinoxRuntimeError("the solver failed (injected)")
        real(path, header, columns)

    monkeypatch.setattr(run_module, "write_csv", solver_fails)
    assert main(["run", case, "--out", str(out), "--quiet", "--keep-partial"]) == 2
    assert capsys.readouterr().err.strip().endswith("jaxgear: error: the solver failed (injected)")
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


SPEED_RANGE = "out of range, allowed (0, 100000] (a planetary stage's run sweeps around it)"


@pytest.mark.parametrize(
    "speed, message",
    [
        ("speed_rad_s = 0.0", f"[operating] speed_rad_s = 0: {SPEED_RANGE}"),
        ("speed_rad_s = -5.0", f"[operating] speed_rad_s = -5: {SPEED_RANGE}"),
        ("", "[operating] speed_rad_s: missing required key"),
    ],
)
def test_keep_partial_run_refused_at_load_leaves_the_earlier_results(
    tmp_path, capsys, speed, message
):
    """A lumped planetary stage (lin-parker-1999) at speed 0 (then inside the documented range,
    refused after the sweep as ``speeds must be > 0 rad/s``, the earlier summary.json and
    modes.json gone): refused at load in one line naming the key, its value and the range,
    the earlier results byte-identical even with --keep-partial."""
    text = jio.embedded_case_text("lin-parker-1999")
    assert "speed_rad_s = 100.0" in text
    case = tmp_path / "lp.toml"
    case.write_text(text.replace("speed_rad_s = 100.0", speed))
    out = tmp_path / "out"
    (out / "sweep").mkdir(parents=True)
    earlier = {
        "summary.json": b'{"case": "lin-parker-1999", "complete": true}',
        "modes.json": b'{"planar": []}',
        "campbell.png": b"an earlier png",
        "sweep/sweep.json": b'{"earlier": true}',
        ".jaxgear-outputs": b"summary.json\nmodes.json\ncampbell.png\nsweep/sweep.json\n",
    }
    for name, data in earlier.items():
        (out / name).write_bytes(data)
    assert main(["run", str(case), "--out", str(out), "--quiet", "--keep-partial"]) == 2
    assert capsys.readouterr().err.strip().splitlines() == [f"jaxgear: error: {message}"]
    after = {str(p.relative_to(out)): p.read_bytes() for p in out.rglob("*") if p.is_file()}
    assert after == earlier
