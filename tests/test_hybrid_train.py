"""A gear train with a flexible idler: a condensed FE body meshing twice, its two
contact zones on one rim through the mortar interface (docs/trains.md, "Flexible gears in a
train").

References: the rigid-node lumped train (the idler made a thousand times stiffer must reduce to
it); the tooth geometry (each tooth in contact sits on a rim station, read from the contact
points by the involute, independent of the layout's phasing); the mesh forces written from the
gear data alone (the idler's bearings carry them, seen through the turning body frame);
Maxwell–Betti reciprocity of the body's cross-compliance.
"""

from __future__ import annotations

import dataclasses
import pathlib

import equinox as eqx
import meshio
import numpy as np
import pytest
from _examples import load_example
from _hybrid_util import (
    rigid_mass_matrix,
    stiffened_body,
    tooth_offsets,
    train_fixtures,
    zone_compliance,
)
from _trains import contact_forces, line_direction, shaft_sum

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.cli import main
from jaxgear.dynamics import Newmark, SteadyState, bearing_forces, dynamic_model, speed_sweep
from jaxgear.io import Damping
from jaxgear.scenes import FlexibleMember

DATA = pathlib.Path(__file__).parent / "data"
CASE = DATA / "hybrid-test-train.toml"


case, bodies, scene = train_fixtures(CASE)


def test_each_tooth_in_contact_sits_on_a_rim_station_in_both_meshes(scene):
    """The idler's body frame is set from the first mesh; in the second mesh (the other flank,
    another line of action, the layout's phase) its teeth in contact must land on stations too:
    the layout's phasing and the turning frame agree (to 1e-9 of a pitch, 7 positions)."""
    idler = scene.members[1]
    assert isinstance(idler, FlexibleMember)
    assert scene.N.shape[1] == 2  # the input and the idler turn freely; the output is held
    for k, side in ((0, -1.0), (1, 1.0)):  # driven in the first mesh, driving in the second
        mesh = scene.meshes[k]
        for theta in np.linspace(0.0, 0.5, 7):
            off = tooth_offsets(idler, mesh, side, theta)
            assert off.size and np.abs(off).max() < 1e-9, (k, theta, off)


def test_rigidified_idler_reproduces_the_rigid_node_train(case):
    """The idler's body a thousand times stiffer (E × 1000) on the same shafts gives each mesh's
    TE of the rigid-node lumped train (uniform mesh stiffness: no foundation term): mean within
    0.5 % (measured 0.012 % and 0.013 %), RMS within 3 % (0.007 %); the steel body adds more
    than 5 % to each mesh's TE (measured 12 % and 13 %)."""
    stiff = stiffened_body(DATA / "hybrid-test-wheel.toml", 1000.0)
    steel = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    uni = case.replace(stiffness=jg.Uniform(1.4e10))
    mods = uni.mesh_modifications()
    rigid_case = uni.replace(scene=dataclasses.replace(uni.scene, gear_bodies=()))
    assert not rigid_case.flexible and uni.flexible
    ref = jg.quasi_static(rigid_case.static_train(), mods, uni.torque)
    hyb = jg.quasi_static(uni.static_train(bodies=(None, stiff, None)), mods, uni.torque)
    soft = jg.quasi_static(uni.static_train(bodies=(None, steel, None)), mods, uni.torque)
    for k in range(2):
        te_ref = float(ref.meshes[k].te_mean)
        assert float(hyb.meshes[k].te_mean) == pytest.approx(te_ref, rel=5e-3)
        assert float(hyb.meshes[k].te_rms) == pytest.approx(float(ref.meshes[k].te_rms), rel=3e-2)
        assert float(soft.meshes[k].te_mean) > 1.05 * te_ref


def test_idler_bearings_carry_its_two_mesh_forces(case, scene):
    """The idler's bearings (on a shaft that turns with its body frame) carry the force of the
    first mesh on it, F_n along the first line, less the force it puts on the output, F_n along
    the second (spur gears; an idler passes F_n on), to 1e-6 of F_n; the input's and the
    output's bearings theirs. With the case file's default contact beyond the path each mesh's
    force is the mean of its cells' contact forces, along the corner's involute normal beyond
    the path (tests/_trains.contact_forces): to 1e-5 of F_n (the code interpolates the corner's
    normal on its table's grid, the reference takes it exact), and within 5e-3 of the nominal
    F_n along the line (measured 1.9e-3: the corners' lever arms)."""
    res = jg.quasi_static(scene, case.mesh_modifications(), case.torque)
    forces = bearing_forces(scene, res)
    fn = case.torque / case.pairs[0].base_radii[0]
    d0, d1 = line_direction(case, 0), line_direction(case, 1)
    f0, f1 = (contact_forces(case, res, k)[1].sum(axis=(1, 2)).mean(axis=0)[:2] for k in (0, 1))
    np.testing.assert_allclose(f0, fn * d0, atol=5e-3 * fn)
    np.testing.assert_allclose(f1, fn * d1, atol=5e-3 * fn)
    np.testing.assert_allclose(shaft_sum(forces, "idler")[:2], f0 - f1, atol=1e-5 * fn)
    np.testing.assert_allclose(shaft_sum(forces, "input")[:2], -f0, atol=1e-5 * fn)
    np.testing.assert_allclose(shaft_sum(forces, "output")[:2], f1, atol=1e-5 * fn)


def test_the_two_contact_zones_share_the_idler_body(scene):
    """Cross-compliance between the meshes through the idler body (its hub held): a unit force
    over one contact zone moves the other zone by 65 % of what it moves its own (asserted:
    more than 10 %), reciprocally (Maxwell–Betti, 1e-9) and with a positive definite 2 × 2
    zone compliance. docs/trains-evidence.md states 4.2 nm/N own and −2.8 nm/N across: the web twists
    under either zone's torque alone (an idler's two mesh torques cancel on the rim)."""
    for theta in (0.0, 0.05, 0.1):
        C = zone_compliance(scene, theta)
        assert C[0, 1] == pytest.approx(C[1, 0], rel=1e-9)
        assert np.all(np.linalg.eigvalsh(0.5 * (C + C.T)) > 0)
        cross = abs(C[0, 1]) / np.sqrt(C[0, 0] * C[1, 1])
        assert cross > 0.1, C
        assert 3.5e-9 < C[0, 0] < 5e-9 and -3.5e-9 < C[0, 1] < -2e-9  # the docs' figures


def test_flexible_train_refusals_are_one_line(case, tmp_path):
    """Bodies in a torsional scene, the rigid-gear scene of a flexible train and a static scene
    without its bodies: one line each, before any work."""
    text = CASE.read_text()
    bad = text.split("[[scene.shafts]]")[0].replace('model = "lumped3d"', 'model = "torsional"')
    bad += '[scene.bodies.idler]\nbody = "hybrid-test-wheel.toml"\n'
    path = tmp_path / "torsional.toml"
    path.write_text(bad)
    with pytest.raises(ValueError, match=r"^\[scene\] bodies: .*lumped3d") as err:
        jio.load_case(path)
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="a train with flexible gears is a hybrid scene") as err:
        case.dynamic_train()
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="pass their condensed bodies"):
        case.static_train()


@pytest.mark.slow
def test_jaxgear_run_on_a_flexible_idler_train(case, tmp_path):
    """``jaxgear run`` on the test train: per-mesh quasi-static figures, bearing forces, the
    flexible gear named, its body's VTU, no sweep (the ``jaxgear sweep`` command printed
    instead); then
    ``jaxgear sweep`` on it: a hybrid sweep per mesh with the idler's nodal-diameter
    resonances (seed (3.9) at its 30 teeth) and rim waves."""
    import json

    out = tmp_path / "out"
    assert main(["run", str(CASE), "--out", str(out), "--quiet"]) == 0
    s = json.loads((out / "summary.json").read_text())
    assert s["flexible_gears"] == ["idler"] and s["complete"] and "dynamics" not in s
    assert len(s["meshes"]) == 2
    for m in s["meshes"]:
        assert m["quasi_static"]["exact"]["te_mean_m"] > 0
    assert any(k.startswith("idler ") for k in s["bearing_forces_mean_N"]["exact"])
    # the idler body deformed at the largest line load, named by its gear, on its own axis
    assert s["body_vtu"] == ["body_idler.vtu"]
    body = meshio.read(out / "body_idler.vtu")
    assert np.abs(body.point_data["displacement_m"]).max() > 0
    centre = s["gears"][1]["centre_m"]
    np.testing.assert_allclose(body.points.mean(axis=0)[:2], centre, atol=1e-6)
    sweep = tmp_path / "sweep"
    argv = ["sweep", str(CASE), "--speeds", "500:1000:2", "--out", str(sweep), "--quiet"]
    assert main([*argv, "--steps-per-period", "64", "--periods", "20"]) == 0
    w = json.loads((sweep / "sweep.json").read_text())
    assert w["model"] == "hybrid" and w["flexible_gears"] == ["idler"]
    assert np.asarray(w["dynamic_factor_mesh"]).shape == (2, 2) and w["result"] == [0, 0]
    for r in w["nodal_diameter_resonances"]:  # seed (3.9) at the idler's 30 teeth
        sign = 1 if r["direction"] == "backward" else -1
        assert r["order"] == 30 * r["harmonic"] + sign * r["nodal_diameter"]
        # the idler turns at 20/30 of the input: input speed = idler speed × 30/20
        assert r["pinion_speed_rad_s"] == pytest.approx(r["wheel_speed_rad_s"] * 1.5)
    assert all(r["gear"] == "idler" and r["teeth"] == 30 for r in w["nodal_diameter_resonances"])
    assert list(w["rim_waves"]) == ["idler"] and len(w["rim_waves"]["idler"]) == 2


@pytest.mark.slow
def test_flexible_idler_case_gives_the_documented_figures(tmp_path):
    """The embedded ``flexible-idler`` case (fem_prep builds its idler body once, about a minute
    on 2 cores): examples/flexible_idler.py recomputed against docs/bench/flexible_idler.json (rtol
    1e-6) and docs/trains-evidence.md's table (TE mean 31.39 / 28.81 and 25.47 / 22.88 µm, flexible /
    rigid idler; the cross term −0.55 of the own)."""
    import json

    root = pathlib.Path(__file__).parents[1]
    ex = load_example("flexible_idler")
    stored = json.loads((root / "docs" / "bench" / "flexible_idler.json").read_text())
    got = ex.main(tmp_path)
    for a, b in zip(got["meshes"], stored["meshes"], strict=True):
        for key, value in b.items():
            assert a[key] == (value if key == "name" else pytest.approx(value, rel=1e-6))
    np.testing.assert_allclose(
        got["zone_compliance_nm_per_N"], stored["zone_compliance_nm_per_N"], rtol=1e-6
    )
    te = [(round(m["flexible_te_mean"], 2), round(m["rigid_te_mean"], 2)) for m in got["meshes"]]
    assert te == [(31.39, 28.81), (25.47, 22.88)]
    assert round(got["cross_over_own"], 2) == -0.55


def test_rigidified_idler_train_dynamics_equal_the_rigid_node_train(case):
    """The idler body a thousand times stiffer (teeth not lumped on its rim) in the hybrid
    Newmark against the lumped train's Newmark with a rigid idler disc of the body's mass and
    polar inertia (its diametral inertia the disc formula's), Rayleigh damping (25 1/s,
    2.5e-6 s) in both, uniform mesh stiffness, 64 steps per period, 12 periods (the last 4
    recorded): each mesh's dynamic factor within 2 % at 1000 rad/s (near a coincidence, DF
    1.89 and 1.70; measured 0.03 to 0.7 % with 2000 rad/s, after 30 periods 0.05 to 0.7 %).
    The same at 2000 rad/s: test_rigidified_idler_train_dynamics_at_2000_rad_s (slow)."""
    _rigidified_idler_dynamics(case, [1000.0])


# default tier: test_rigidified_idler_train_dynamics_equal_the_rigid_node_train (the same claim at 1000 rad/s)
@pytest.mark.slow
def test_rigidified_idler_train_dynamics_at_2000_rad_s(case):
    """test_rigidified_idler_train_dynamics_equal_the_rigid_node_train at 2000 rad/s."""
    _rigidified_idler_dynamics(case, [2000.0])


def _rigidified_idler_dynamics(case, speeds):
    stiff = stiffened_body(DATA / "hybrid-test-wheel.toml", 1000.0)
    # on the theoretical path (an open question): beyond it the two scenes' corner rows differ by
    # the drive-rotation step, which takes a corner cell's part along the free rotation off
    # along M r on the mesh's window coordinates: a rigid node's whole gear, a condensed body's
    # rim masters under the contact; with the case file's default the dynamic factors at
    # 1000 rad/s were 1.527 (hybrid) and 1.569 (rigid node), at 2000 rad/s 0.5 % apart
    uni = case.replace(stiffness=jg.Uniform(1.4e10), contact_geometry=jg.TheoreticalPath())
    mods = uni.mesh_modifications()
    damping = Damping("rayleigh", alpha=25.0, beta=2.5e-6)
    Mr = rigid_mass_matrix(stiff)
    mass, polar = Mr[0, 0], Mr[5, 5]
    rigid = uni.replace(
        scene=dataclasses.replace(uni.scene, gear_bodies=()),
        masses=(None, mass, None),
        inertias=(None, polar, None),
    )
    hybrid = dynamic_model(
        uni.hybrid_train((None, stiff, None), tooth_mass=False), mods, uni.torque, damping
    )
    lumped = dynamic_model(rigid.lumped_train(), mods, uni.torque, damping)
    kw = dict(integrator=Newmark(64), window=SteadyState(12, 4))
    got = speed_sweep(hybrid, speeds, **kw).results
    ref = speed_sweep(lumped, speeds, **kw).results
    assert np.all(np.asarray(got.result) == 0) and np.all(np.asarray(ref.result) == 0)
    for k in range(2):
        df, df_ref = (np.asarray(r.meshes[k].dynamic_factor) for r in (got, ref))
        np.testing.assert_allclose(df, df_ref, rtol=2e-2)
    if speeds[0] == 1000.0:
        assert float(np.asarray(ref.meshes[0].dynamic_factor)[0]) > 1.5  # near a resonance


# default tier: tests/test_hybrid.py::test_cached_window_compliance_gives_the_same_solve (the same claim on the flexible pair: two torques, the smooth law, an uncached position raises) and test_idler_bearings_carry_its_two_mesh_forces (this train's quasi-static solve)
@pytest.mark.slow
def test_cached_train_equals_the_uncached_solve(case, scene):
    """The flexible idler train (two meshes on one body, two rigid-body amplitudes) with its
    window compliance cached (the exact law on the factored full contact set) against the
    uncached cell-space solve: both meshes' TE, the line loads and the coordinates to 1e-10,
    with a tip relief and a crowning that lift cells off the flanks, at two torques; the smooth
    law (which reads the cached compliance C, not the factor) to 1e-10 of the TE; a position
    that is not cached raises. Both at quasi_static's default positions (64 per pitch, the
    cache's default too): the uncached exact solve is then the program of the module's other
    solves on the scene."""
    from jaxgear.scenes import cache_window_compliance

    cached = cache_window_compliance(scene)
    relief = jg.Modifications.symmetric(
        jg.MemberModification(tip_relief_depth=20e-6, tip_relief_extent=0.4, crowning_depth=30e-6)
    )
    for torque in (0.3 * case.torque, case.torque):
        a = jg.quasi_static(scene, relief, torque)
        b = jg.quasi_static(cached, relief, torque)
        # cells leave the flanks: active-set passes after the first, on the factored set
        assert np.array_equal(np.asarray(b.iterations), np.asarray(a.iterations))
        assert np.any(np.asarray(b.iterations) > 2)
        for ma, mb in zip(a.meshes, b.meshes, strict=True):
            for f in ("transmission_error", "line_load"):
                x, y = np.asarray(getattr(ma, f)), np.asarray(getattr(mb, f))
                np.testing.assert_allclose(y, x, rtol=0, atol=1e-10 * np.abs(x).max())
        np.testing.assert_allclose(b.x, a.x, rtol=0, atol=1e-10 * np.abs(np.asarray(a.x)).max())
    smooth = jg.SmoothContact(1e-7)
    a = jg.quasi_static(scene, relief, case.torque, contact=smooth)
    b = jg.quasi_static(cached, relief, case.torque, contact=smooth)
    for ma, mb in zip(a.meshes, b.meshes, strict=True):
        x, y = np.asarray(ma.transmission_error), np.asarray(mb.transmission_error)
        np.testing.assert_allclose(y, x, rtol=0, atol=1e-10 * np.abs(x).max())
    theta = jg.mesh_positions(scene.base_planes[0], 64, 1)  # the cached positions, moved
    with pytest.raises(eqx.EquinoxRuntimeError, match="not one of the cached positions"):
        jg.quasi_static(cached, relief, case.torque, theta + 1e-4)
