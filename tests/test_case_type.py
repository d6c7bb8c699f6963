"""One case type: a pair case file and a train case file both load into :class:`jaxgear.io.Case`,
a pair being a train of two gears and one mesh (its form, :class:`jaxgear.io.PairForm`, names the
mesh by the case); the pair views (``pair``, ``modifications``, ``replace(pair=...)``,
``replace(modifications=...)``) hold on a case of one mesh and are refused in one line on a case
of several; a train of one mesh runs through ``jaxgear sweep`` and ``jaxgear run`` (its sweep
summary holds its one mesh's values as its own, as a pair's); a train's quasi-static scene comes
from the one home of a case's (:func:`jaxgear.io.quasi_static_scene`).

The spur pair is tests/_kinds.py's small pair (m_n 2 mm, α 20°, 20/30 teeth, 60 N·m, tip relief
8 µm), written once as a pair file and once as a train of one mesh."""

from __future__ import annotations

import dataclasses
import json
import math

import pytest
from _kinds import GEAR, INTEGRATION, KINDS, TRAIN_HEAD, TRAIN_TAIL, _pair

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import case_line, main
from jaxgear.cli.run import mesh_dynamics


def _one_mesh_train(name: str, scene: str = "") -> str:
    """The small pair as a train: gears ``input`` (20 teeth, 12 mm) and ``output`` (30, 10 mm),
    one mesh."""
    gears = "".join(
        GEAR.format(name=n, shaft="", teeth=z, shift="", face=b)
        for n, z, b in (("input", 20, 12.0), ("output", 30, 10.0))
    )
    mesh = '\n[[meshes]]\ndriving = "input"\ndriven = "output"\nangle_deg = 0.0\n'
    return (
        TRAIN_HEAD.format(name=name) + gears + mesh + TRAIN_TAIL.format(torque=60.0, ppp=8) + scene
    )


TORSIONAL = '\n[scene]\nmodel = "torsional"\n' + INTEGRATION.format(steps=16, keep=2)


@pytest.fixture(scope="module")
def cases(tmp_path_factory):
    folder = tmp_path_factory.mktemp("case-type")
    (folder / "pair.toml").write_text(_pair("pair"))
    (folder / "train.toml").write_text(_one_mesh_train("train"))
    (folder / "idler.toml").write_text(KINDS["train-rigid"])
    return {k: jio.load_case(folder / f"{k}.toml") for k in ("pair", "train", "idler")}


def test_a_pair_is_a_train_of_one_mesh(cases):
    pair, train = cases["pair"], cases["train"]
    assert type(pair) is type(train) is jio.Case and jio.TrainCase is jio.Case
    assert pair.form == jio.PairForm() and train.form == jio.TrainForm()
    assert pair.gear_names == ("pinion", "gear") and pair.gears == ((0, 1),)
    assert pair.pairs == (pair.pair,) and pair.mesh_case(0) is pair
    assert (pair.mesh_name(0), pair.mesh_label(0)) == ("pair", "")
    assert (train.mesh_name(0), train.mesh_label(0)) == ("input-output", "input-output")
    # the same gears written both ways: one geometry; the train's one mesh as a pair case
    one = train.mesh_case(0)
    assert one.form == jio.PairForm() and one.pair.summary() == pair.pair.summary()
    # the one mesh carries the input torque; F_n = T / (r_b1 cos β_b), r_b1 = m z cos α / 2
    r_b1 = 2e-3 * 20 * math.cos(math.radians(20.0)) / 2
    for case in (pair, one):
        assert case.mesh_torques == pytest.approx((60.0,), rel=1e-15)
        assert case.normal_load == pytest.approx(60.0 / r_b1, rel=1e-12)
    # each gear's tip relief, 8 µm, on both members of the one mesh
    for m in (pair.modifications.pinion, pair.modifications.gear, one.modifications.gear):
        assert float(m.tip_relief_depth) == pytest.approx(8e-6)


def test_pair_views_and_their_refusal_on_several_meshes(cases):
    pair, idler = cases["pair"], cases["idler"]
    wide = dataclasses.replace(pair.pair.pinion, face_width=15e-3)
    moved = pair.replace(pair=dataclasses.replace(pair.pair, pinion=wide), slices=3)
    assert moved.pair.pinion.face_width == 15e-3 and moved.slices == 3
    assert moved.form == jio.PairForm() and moved.name == pair.name
    bare = pair.replace(modifications=jg.Modifications())
    assert float(bare.modifications.pinion.tip_relief_depth) == 0.0
    assert float(pair.modifications.pinion.tip_relief_depth) == pytest.approx(8e-6)
    for view in (
        lambda: idler.pair,
        lambda: idler.modifications,
        lambda: idler.replace(pair=pair.pair),
        lambda: idler.replace(modifications=jg.Modifications()),
    ):
        with pytest.raises(ValueError, match=r"one-mesh case's .* 2 meshes") as err:
            view()
        assert "\n" not in str(err.value)
    assert len(idler.mesh_modifications()) == 2  # what a train of several meshes offers


def test_outputs_follow_the_form_and_the_number_of_meshes(cases):
    """``jaxgear cases`` writes a case's line by its form; ``summary.json``'s per-mesh dynamics
    keys follow what the sweep summary holds (per-mesh lists for several meshes only, as
    ``jaxgear sweep`` writes them): a case of one mesh, a pair or a train, has none (a train of
    one mesh used to look for them, KeyError, after every speed had run)."""
    assert case_line(cases["pair"]) == "z 20/30, m_n 2 mm, β 0°, T 60 N·m, weber stiffness"
    assert case_line(cases["train"]) == "train z 20/30, m_n 2 mm, T 60 N·m (input), weber stiffness"
    one = {"speeds_rad_s": [300.0, 600.0], "dynamic_factor": [1.1, 1.3]}
    assert mesh_dynamics(one) == {}
    two = {
        **one,
        "mesh_names": ["input-idler", "idler-output"],
        "dynamic_factor_mesh": [[1.1, 1.05], [1.2, 1.3]],
    }
    assert mesh_dynamics(two) == {
        "mesh_names": ["input-idler", "idler-output"],
        "dynamic_factor_mesh": [[1.1, 1.05], [1.2, 1.3]],
        "max_dynamic_factor_mesh": [1.2, 1.3],
    }


def test_quasi_static_scene_of_a_lumped_train(tmp_path):
    """``jaxgear.io.quasi_static_scene`` takes a train as a pair (one home for a case's static
    scene, :func:`jaxgear.io.static_scene` by the case's form: the train's is the one
    ``jaxgear run`` solves, the output shaft held): the idler train's bearing forces balance,
    Σ F = 0 in x and y (the mesh forces are internal, the torques pure moments), each bearing
    carrying hundreds of N. About 4.5 s of CPU (tests/_kinds.py's lumped train, 2 slices, 4
    positions per pitch)."""
    path = tmp_path / "train.toml"
    path.write_text(KINDS["train-lumped3d"])
    case = jio.load_case(path).replace(positions_per_pitch=4)
    res, forces = jio.quasi_static_scene(case)
    assert len(res.meshes) == 2
    for axis in ("Fx", "Fy"):
        f = [v for k, v in forces.items() if k.endswith(axis)]
        assert max(abs(v) for v in f) > 100.0
        assert abs(sum(f)) < 1e-9 * max(abs(v) for v in f)


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:.*under-resolved")
def test_a_train_of_one_mesh_runs_and_sweeps(tmp_path, capsys):
    """``jaxgear sweep`` and ``jaxgear run`` on a torsional train of one mesh exit 0 (the sweep
    ended in ``KeyError: 'max_contact_pressure_mesh_Pa'`` after every speed had run). Slow:
    about a minute on 2 loaded cores (run sweeps 30 speeds); the fast tests above check the
    summary keys it failed on."""
    path = tmp_path / "one.toml"
    path.write_text(_one_mesh_train("one", TORSIONAL))
    out = tmp_path / "sweep"
    argv = ["sweep", str(path), "--speeds", "300:600:2", "--out", str(out), "--quiet"]
    assert main(argv) == 0, capsys.readouterr().err
    sw = json.loads((out / "sweep.json").read_text())
    assert len(sw["dynamic_factor"]) == 2 and "mesh_names" not in sw
    assert all(math.isfinite(v) for v in sw["max_contact_pressure_Pa"])
    run = tmp_path / "run"
    assert main(["run", str(path), "--out", str(run), "--quiet"]) == 0, capsys.readouterr().err
    s = json.loads((run / "summary.json").read_text())
    assert s["complete"] is True and s["kind"] == "train" and len(s["meshes"]) == 1
    # a train's first look: every 100 rad/s from 100 to 3000
    assert s["dynamics"]["speeds_rad_s"] == pytest.approx([100.0 * k for k in range(1, 31)])
