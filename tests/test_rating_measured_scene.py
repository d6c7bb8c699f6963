"""Measured K_Hβ and K_Hα of the model a case runs: ``jaxgear run`` reads them
on its scene's quasi-static load map (a lumped scene: shafts and bearings; a hybrid scene:
condensed bodies) or its coupled train solve, passed through from the run (nothing solved twice),
and keeps the rigid mesh's beside them (``rating.measured.K_Hbeta_rigid_mesh``).

References:
- an off-centre pinion between two bearings: the shaft's slope at the gear from beam theory
  (written here: simply supported Timoshenko beam, a point force and a couple at the gear,
  with the bearings' radial compliance), the mesh's misalignment it gives across the face and
  the linear load distribution it makes on a mesh of uniform stiffness k per unit contact length
  (ISO 6336-1:2019 clause 7's own idea, K_Hβ = 1 + F_βy c_γβ/(2 F_m/b)), with the couple of the
  shifted load fed back on both shafts;
- a crowned pair on the rigid scene (the same model as the rigid mesh, deflection-free): the
  measured factor equals the rigid mesh's to 1e-12 (the plumbing reads the map it is given);
- a torsional train: each mesh's factors from the coupled solve equal those of the mesh solved
  alone at the same mesh angles (1e-9); a flexible idler shaft with the idler off-centre tilts
  both idler meshes, raising their coupled K_Hβ above the mesh-alone one.
"""

import json
import math
import os
import tomllib
from pathlib import Path

import jax
import numpy as np
import pytest
from _rating_cases import rated_accessory_data, stub_table, with_rating

import jaxgear as jg
import jaxgear.scenes as js
import jaxgear.cli.run as run_module
import jaxgear.cli.sweep as sweep_module
import jaxgear.io as jio
from jaxgear import cli

jax.config.update("jax_enable_x64", True)

ROOT = Path(__file__).resolve().parents[1]
K0 = 1.5e10  # N/m²: uniform mesh stiffness per unit contact length
STIFF = 1e5  # N/µm: bearings all but rigid (their compliance is in the reference all the same)
E, NU, KAPPA = 210e9, 0.3, 0.9  # the case's steel; the shaft elements' shear coefficient


def _off_centre_case():
    """The rated accessory pair (8 slices, 16 positions per pitch, no modifications) on its
    lumped scene with the pinion at 25 mm of its 100 mm, 20 mm shaft; both shafts on radial
    bearings of 1e5 N/µm at their ends; uniform mesh stiffness K0."""
    d = rated_accessory_data(8, 16)
    d.pop("modifications", None)
    d["scene"] = tomllib.loads(jio.embedded_case_text("accessory-spur"))["scene"]
    for name in ("pinion_shaft", "gear_shaft"):
        d["scene"][name]["bearings"] = [
            {"position_mm": 0.0, "radial_N_per_um": STIFF, "axial_N_per_um": 100.0},
            {"position_mm": 100.0, "radial_N_per_um": STIFF},
        ]
    d["scene"]["pinion_shaft"].update(diameter_mm=20.0, gear_position_mm=25.0)
    return d


def _slope_compliances(a: float, length: float, diameter: float, k_bearing: float):
    """(θ_F, θ_M) of a simply supported Timoshenko shaft (E, ν, κ above) on two radial springs
    ``k_bearing`` at its ends: the rotation of the section at ``a`` (m from the first bearing)
    per unit force (rad/N) and per unit couple (rad/(N·m)) applied there (unit-load method:
    θ_F = a b (b − a)/(3 L EI) + (a − b)/(k L²), the shear force of a point force integrating
    to zero over the span; θ_M = (a³ + b³)/(3 L² EI) + 1/(L κ G A) + 2/(k L²))."""
    b = length - a
    area = math.pi * diameter**2 / 4
    ei = E * math.pi * diameter**4 / 64
    g = E / (2 * (1 + NU))
    theta_f = a * b * (b - a) / (3 * length * ei) + (a - b) / (k_bearing * length**2)
    theta_m = (
        (a**3 + b**3) / (3 * length**2 * ei)
        + 1 / (length * KAPPA * g * area)
        + 2 / (k_bearing * length**2)
    )
    return theta_f, theta_m


def test_off_centre_pinion_tilts_the_mesh_as_beam_theory_says(tmp_path):
    """The pinion's shaft bends under the mesh force F_n (the gear's, centred, does not tilt
    under it): the mesh's misalignment grows linearly across the face, φ z, with
    φ = θ_F F_n/(1 + θ_M c b³/12) (θ_M of both shafts: the couple c φ b³/12 of the shifted load
    turns them back), c the mesh stiffness per unit face width at the position (k times the
    contact length over b: every cell loaded). The load per unit face width is then
    F_n/b + c φ z, so the slice at z = (b − b/N)/2 gives K_Hβ = 1 + mean(c φ)(b − b/N)/2/(F_n/b)
    (ISO 6336-1's 1 + F_βy c_γβ/(2 F_m/b) with F_βy = φ b, to the slice width). Agreement:
    3e-4 of K_Hβ − 1 (0.16 here); tolerance 1e-3 of it, for what the reference leaves out: the
    bearings' and shafts' rotations under the couple of the other gear's reaction, the discs'
    inertia-free offsets. The rigid mesh alone reads 1: the scene's factor is the one that
    rates (``use_measured``), the rigid mesh's kept beside it."""
    d = _off_centre_case()
    d["rating"]["use_measured"] = ["K_Hbeta"]
    # theoretical path: the beam reference takes every cell of the path loaded
    case = jio.parse_case(d).replace(
        stiffness=jg.Uniform(K0), contact_geometry=jg.TheoreticalPath()
    )
    scene, _ = jio.static_scene(case, slices=case.slices)
    res = jg.quasi_static(scene, None, case.torque, positions_per_pitch=16)
    rigid = jg.quasi_static(case.mesh_model(), None, case.torque, positions_per_pitch=16)
    pair = case.pair
    b, n = float(pair.face_width), case.slices
    f_n = case.torque / float(pair.base_radii[0])
    assert np.all(np.asarray(res.line_load)[np.asarray(res.cell_mask)] > 0)  # full contact
    c = K0 * np.asarray(rigid.contact_length) / b
    theta_f, theta_mp = _slope_compliances(0.025, 0.1, 0.020, STIFF * 1e6)
    _, theta_mg = _slope_compliances(0.050, 0.1, 0.035, STIFF * 1e6)
    phi = theta_f * f_n / (1 + (theta_mp + theta_mg) * c * b**3 / 12)
    want = 1 + np.mean(c * phi) * (b - b / n) / 2 / (f_n / b)
    assert want > 1.1
    curves = {"model": "lumped3d", "results": {"exact": res}, "base_planes": scene.base_planes}
    # compiled, not under jax.disable_jit (whose eager primitives each compile on their own:
    # this test 4.5 -> 3.7 CPU s in a run of its file)
    section = cli.rating_outputs(
        case, str(tmp_path), result=rigid, model=cli.scene_loads(curves, 0.0)
    )
    m = section["measured"]
    assert m["K_Hbeta"]["value"] - 1 == pytest.approx(want - 1, rel=1e-3)
    assert want == pytest.approx(1.1585, abs=5e-5)  # docs/rating.md's figures
    assert m["K_Hbeta"]["value"] == pytest.approx(1.159, abs=5e-4)
    assert "lumped scene: shafts and bearings" in m["K_Hbeta"]["source"]
    assert m["K_Hbeta_rigid_mesh"]["value"] == pytest.approx(1.0, abs=1e-12)
    assert "rigid mesh" in m["K_Hbeta_rigid_mesh"]["source"]
    assert section["factors"]["K_Hbeta"]["value"] == m["K_Hbeta"]["value"]  # rates with it
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert "| K_Hβ measured, rigid mesh | 1.000 |" in table


def test_rigid_scene_reads_the_rigid_mesh_map():
    """A lead crowning of 10 µm on the rigid scene (both bodies rigid: the rigid mesh's model,
    deflection-free): the measured K_Hβ and K_Hα of the scene equal the rigid mesh's to 1e-12,
    and K_Hβ is well above 1 (the crowning is read). A hybrid scene's result goes the same way
    (``scene_loads``), its source naming the model and the speed."""
    d = rated_accessory_data(8, 16)
    d["modifications"]["crowning"] = {"depth_um": 10.0}
    case = jio.parse_case(d)
    mesh = case.mesh_model()
    scene = jg.quasi_static(js.RigidMesh(mesh), case.modifications, case.torque, periods=1)
    rigid = jg.quasi_static(mesh, case.modifications, case.torque, periods=1)
    m = cli.measured_factors(rigid, cli.ModelLoads(scene.meshes, "rigid scene", (mesh,)), 0)
    assert m["K_Hbeta"]["value"] > 1.05
    for key in ("K_Hbeta", "K_Halpha"):
        assert m[key]["value"] == pytest.approx(m[f"{key}_rigid_mesh"]["value"], rel=1e-12)
    assert "rigid scene" in m["K_Hbeta"]["source"]
    # a hybrid scene's result is read the same way, its model and speed named
    hybrid = cli.scene_loads({"model": "hybrid", "results": {"exact": scene},
                                "base_planes": (mesh,)}, 50.0)
    assert hybrid.results == tuple(scene.meshes)
    assert hybrid.model == (
        "hybrid scene: condensed bodies, shafts and bearings, at 50 rad/s (centrifugal loads)"
    )


def _rated_train(d: dict) -> dict:
    d["mesh"].update(slices=8, positions_per_pitch=16)
    return with_rating(d)


def _coupled_and_alone(case):
    """The train's coupled quasi-static solve (as ``jaxgear run``'s: its static train, the
    case's modifications, two periods) and each mesh alone at the same mesh angles."""
    scene = case.static_train()
    res = jg.quasi_static(
        scene, case.mesh_modifications(), case.torque, positions_per_pitch=16, periods=2
    )
    angles = scene.mesh_angles(res.theta)
    alone = []
    for k in range(len(case.pairs)):
        one = case.mesh_case(k)
        alone.append(jg.quasi_static(one.mesh_model(), one.modifications, one.torque, angles[k]))
    return res, alone


def test_rigid_train_measures_each_mesh_as_alone():
    """The embedded idler train (torsional: rigid members) with a 10 µm lead crowning: each
    mesh's measured K_Hβ and K_Hα from the coupled solve (``train_loads``, as ``jaxgear run``
    hands it to ``rating_outputs``) equal those of the mesh solved alone at the same mesh angles
    (its ``*_rigid_mesh`` entries here) to 1e-9."""
    d = _rated_train(tomllib.loads(jio.embedded_case_text("accessory-idler-train")))
    d["modifications"]["crowning"] = {"depth_um": 10.0}
    # on the theoretical path: a rigid train's meshes are then statically determinate, every
    # cell at the line of action's torque ratio; beyond it a corner cell's tip owner acts with
    # a shorter lever arm, shared in the train by its gears' rotations and alone with the gear
    # held (measured 5.7e-5 apart in K_Hβ with the case file's default)
    d["mesh"]["extended_contact"] = False
    case = jio.parse_train(d)
    res, alone = _coupled_and_alone(case)
    loads = cli.train_loads(case, res)
    assert loads.model == "coupled train: torsional"
    for k, one in enumerate(alone):
        m = cli.measured_factors(one, loads, k)
        assert m["K_Hbeta"]["value"] > 1.3  # the crowning
        for key in ("K_Hbeta", "K_Halpha"):
            assert m[key]["value"] == pytest.approx(m[f"{key}_rigid_mesh"]["value"], rel=1e-9)
        assert "coupled train: torsional" in m["K_Hbeta"]["source"]


# default tier: test_off_centre_pinion_tilts_the_mesh_as_beam_theory_says above (a shaft's
# slope raises the measured K_Hbeta, against beam theory), test_rigid_train_measures_each_mesh_as_alone
# (a train's coupled loads read per mesh); a lumped 3D train's jaxgear run stays in default
# (tests/test_every_kind.py's note on which test runs it)
@pytest.mark.slow
def test_flexible_idler_shaft_raises_the_coupled_face_load_factor():
    """The lumped idler train of examples/ without lead modifications (alone, every mesh reads
    K_Hβ = 1), the idler moved to 10 of its 40 mm on a 10 mm shaft: the idler tilts, and both
    its meshes read a coupled K_Hβ above the mesh alone's (sign: the shaft's misalignment adds
    to the aligned mesh's), by more than 0.02. (With the gears centred, as in the example, the
    shafts deflect parallel: 1 to 1e-9, checked when this test was written.)"""
    d = _rated_train(tomllib.loads((ROOT / "examples" / "idler-train-lumped3d.toml").read_text()))
    d["modifications"].pop("crowning", None)
    d["scene"]["shafts"][1].update(diameter_mm=10.0, gear_positions_mm={"idler": 10.0})
    case = jio.parse_train(d)
    res, alone = _coupled_and_alone(case)
    loads = cli.train_loads(case, res)
    assert loads.model == "coupled train: shafts and bearings"
    for k, one in enumerate(alone):
        m = cli.measured_factors(one, loads, k)
        assert m["K_Hbeta_rigid_mesh"]["value"] == pytest.approx(1.0, abs=1e-12)
        assert m["K_Hbeta"]["value"] > m["K_Hbeta_rigid_mesh"]["value"] + 0.02


@pytest.mark.slow
def test_run_writes_the_scene_factors_and_rating_md_once(tmp_path, monkeypatch, capsys):
    """``jaxgear run`` on the rated accessory pair with its lumped scene (2 slices × 8
    positions; the sweep replaced by a given curve through the rating speed, the FE table by a
    stub, the at-speed map by a marker; 14 s CPU, slow): ``rating.measured.K_Hbeta`` is the
    scene's own quasi-static load map's (solved again here, 1e-12), ``K_Hbeta_rigid_mesh`` the
    rigid mesh's, and ``rating.md`` is written once, at the end, from the final section (the
    measured K_v of the sweep in it)."""
    d = rated_accessory_data(2, 8)
    d["scene"] = tomllib.loads(jio.embedded_case_text("accessory-spur"))["scene"]
    d["scene"]["pinion_shaft"]["gear_position_mm"] = 25.0  # a tilt: K_Hβ off 1
    path = tmp_path / "case.toml"
    path.write_text(_toml(d))

    def no_sweep(case, speeds, out_dir, *, slices, **kw):
        return {"speeds_rad_s": [100.0, 3000.0], "dynamic_factor": [1.0, 1.2]}, None

    def marked(case, out, summary, dynamics, run=None, *, write_table):
        assert not write_table
        summary["rating"]["root_stress"]["source"] += " (marked)"

    writes = _count_writes(monkeypatch, "rating.md")
    monkeypatch.setattr(sweep_module, "sweep_case_run", no_sweep)
    monkeypatch.setattr(run_module, "fillet_table", stub_table)
    monkeypatch.setattr(run_module, "root_stress_at_speed", marked)
    out = tmp_path / "o"
    assert cli.main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    capsys.readouterr()
    rating = json.loads((out / "summary.json").read_text())["rating"]
    case = jio.load_case(str(path))
    scene, _ = jio.static_scene(case, slices=case.slices)
    res = jg.quasi_static(scene, case.modifications, case.torque, positions_per_pitch=8)
    rigid = jg.quasi_static(
        case.mesh_model(), case.modifications, case.torque, positions_per_pitch=8
    )
    m = rating["measured"]
    assert m["K_Hbeta"]["value"] == pytest.approx(float(jg.rating.face_load_factor(res)), rel=1e-12)
    assert m["K_Hbeta_rigid_mesh"]["value"] == pytest.approx(
        float(jg.rating.face_load_factor(rigid)), rel=1e-12
    )
    assert m["K_Hbeta"]["value"] > m["K_Hbeta_rigid_mesh"]["value"] + 1e-3
    assert "K_v" in m
    assert len(writes) == 1
    text = (out / "rating.md").read_text(encoding="utf-8")
    assert text == "\n".join(cli.rating_table_lines(case, rating)) + "\n"
    assert "(marked)" in text and "| K_v measured |" in text


def _count_writes(monkeypatch, name: str) -> list:
    """The files named ``name`` the run writes, one entry per write (every output is written
    atomically: a temporary file ``.tmp-<name>-*`` renamed onto it by ``os.replace``; the run's
    move of its finished files from the staging folder is not a write)."""
    writes, real = [], os.replace

    def counted(src, dst, *args, **kwargs):
        if os.path.basename(os.fspath(src)).startswith(f".tmp-{name}-"):
            writes.append(dst)
        return real(src, dst, *args, **kwargs)

    monkeypatch.setattr(os, "replace", counted)
    return writes


def _toml(d: dict) -> str:
    """A parsed case file written back: each top-level table a ``[table]``, nested tables and
    arrays of them inline (numbers, strings, booleans, arrays)."""

    def value(v) -> str:
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, str):
            return json.dumps(v)
        if isinstance(v, list):
            return "[" + ", ".join(value(x) for x in v) + "]"
        if isinstance(v, dict):
            return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
        return repr(v)

    top = [f"{k} = {value(v)}" for k, v in d.items() if not isinstance(v, dict)]
    tables = [
        f"[{k}]\n" + "\n".join(f"{j} = {value(x)}" for j, x in v.items())
        for k, v in d.items()
        if isinstance(v, dict)
    ]
    return "\n".join(top + tables) + "\n"


@pytest.mark.slow
def test_docs_table_of_the_accessory_pair():
    """docs/rating.md's table (3 decimals): the embedded accessory pair (Weber stiffness, its
    tip relief, 40 slices × 64 positions, 80 N·m) on its lumped scene reads the rigid mesh's
    K_Hβ and K_Hα (its gears sit mid-span: the shafts deflect parallel, no misalignment: equal
    to 1e-9), and with the pinion moved to 25 mm of its 100 mm on a 20 mm shaft the scene's
    K_Hβ rises above the rigid mesh's (the shaft's slope misaligns the mesh) and K_Hα falls
    (the misalignment shares the relieved pairs' load differently along the face). 8 s CPU."""
    got = {}
    off_centre = {"diameter_mm": 20.0, "gear_position_mm": 25.0}
    for name, shaft in (("mid-span", {}), ("off-centre", off_centre)):
        d = tomllib.loads(jio.embedded_case_text("accessory-spur"))
        d["scene"]["pinion_shaft"].update(shaft)
        case = jio.parse_case(d)
        scene, _ = jio.static_scene(case, slices=case.slices)
        res = jg.quasi_static(scene, case.modifications, case.torque, positions_per_pitch=64)
        got[name] = (float(jg.rating.face_load_factor(res)), float(jg.rating.transverse_load_factor(res)))
    rigid = jg.quasi_static(case.mesh_model(), case.modifications, case.torque, periods=2)
    got["rigid"] = (float(jg.rating.face_load_factor(rigid)), float(jg.rating.transverse_load_factor(rigid)))
    np.testing.assert_allclose(got["mid-span"], got["rigid"], rtol=1e-9)
    np.testing.assert_allclose(got["rigid"], [1.000, 1.964], atol=5e-4)
    np.testing.assert_allclose(got["off-centre"], [1.203, 1.694], atol=5e-4)


@pytest.mark.slow
def test_train_run_rates_with_the_coupled_solve(tmp_path, monkeypatch):
    """``jaxgear run``'s quasi-static files of the rated lumped idler train (the idler
    off-centre on a 10 mm shaft, no lead modifications; the FE table a stub): each mesh's
    ``rating.measured.K_Hbeta`` is the coupled solve's (solved again here with the run's
    settings, 1e-12), ``K_Hbeta_rigid_mesh`` the mesh alone's (1 to 1e-12), and ``rating.md``
    is written once (the run completes there)."""
    d = _rated_train(tomllib.loads((ROOT / "examples" / "idler-train-lumped3d.toml").read_text()))
    d["modifications"].pop("crowning", None)
    d["scene"]["shafts"][1].update(diameter_mm=10.0, gear_positions_mm={"idler": 10.0})
    case = jio.parse_train(d)
    writes = _count_writes(monkeypatch, "rating.md")
    monkeypatch.setattr(run_module, "fillet_table", stub_table)
    args = type("Args", (), {"quiet": True})()
    summary = run_module.quasi_static_files(case.form, case, str(tmp_path), args, True)
    res = jg.quasi_static(
        case.static_train(),
        case.mesh_modifications(),
        case.torque,
        positions_per_pitch=16,
        periods=2,
    )
    m = summary["rating"]["measured"]
    for k, mesh in enumerate(res.meshes):
        assert m["K_Hbeta"]["value"][k] == pytest.approx(
            float(jg.rating.face_load_factor(mesh)), rel=1e-12
        )
        assert m["K_Hbeta_rigid_mesh"]["value"][k] == pytest.approx(1.0, abs=1e-12)
        assert "coupled train: shafts and bearings" in m["K_Hbeta"]["source"][k]
    assert len(writes) == 1
    assert "K_Hβ measured, rigid mesh" in (tmp_path / "rating.md").read_text(encoding="utf-8")
