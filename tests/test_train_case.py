"""Gear-train case files (``[[gears]]``, ``[[meshes]]``) and ``jaxgear run`` on a train.

References, each written here apart from the model: the two pairs of the idler train written as
pair case files of their own (each alone at the torque the idler passes on), the torsional chain
of three inertias with each pair's mean mesh stiffness on its base radii (its eigenvalues by
SciPy), and the mesh phase of an idler's two meshes derived by hand from the layout (tangent
points of the lines of action on the idler's base circle, the tooth thickness at the base
circle), read against the engagement jumps of the quasi-static stiffness curves.
"""

from __future__ import annotations

import contextlib
import copy
import io
import json
import math
import pathlib
import tomllib

import jax
import numpy as np
import pytest
import scipy.linalg
from _toml import case_toml

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.scenes as js
from jaxgear.cli import main
from jaxgear.dynamics import Newmark, SteadyState, mesh_energy_shares, speed_sweep
from jaxgear.io import build_dynamic_model

jax.config.update("jax_enable_x64", True)

SLICES = 4
PPP = 48


def _train_data(**mesh_angles) -> dict:
    """The embedded idler train as parsed TOML, small settings; ``mesh_angles``: ``{"m1": deg}``
    replaces meshes[1].angle_deg."""
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    data["mesh"].update(slices=SLICES, positions_per_pitch=PPP)
    if "m1" in mesh_angles:
        data["meshes"][1]["angle_deg"] = mesh_angles["m1"]
    return data


def _gear_table(data: dict, name: str) -> dict:
    return next(g for g in data["gears"] if g["name"] == name)


def _pair_case(data: dict, driving: str, driven: str, torque: float) -> jio.Case:
    """The mesh driving → driven written as a pair case file of its own (``[pair]``,
    ``[pinion]``, ``[gear]``) at ``torque`` on its driving gear."""
    a, b = _gear_table(data, driving), _gear_table(data, driven)
    pair_keys = ("normal_module_mm", "normal_pressure_angle_deg", "helix_angle_deg")
    train_keys = (*pair_keys, "name", "shaft", "clocking_deg")
    member = lambda g: {k: v for k, v in g.items() if k not in train_keys}
    return jio.parse_case(
        {
            "name": f"{driving}-{driven}",
            "pair": {k: a[k] for k in pair_keys if k in a},
            "pinion": member(a),
            "gear": member(b),
            "material": data["material"],
            "operating": {"torque_Nm": torque},
            "mesh": data["mesh"],
            "modifications": data["modifications"],
        }
    )


def _pairs_alone(data: dict):
    """The two pairs as pair cases; the idler's torque T r_b,idler / r_b,input (the same normal
    force on both meshes: the idler carries no load of its own)."""
    torque = data["operating"]["torque_Nm"]
    first = _pair_case(data, "input", "idler", torque)
    rb_in, rb_idler = first.pair.base_radii
    return first, _pair_case(data, "idler", "output", torque * rb_idler / rb_in)


@pytest.fixture(scope="module")
def train():
    data = _train_data()
    return data, jio.parse_train(copy.deepcopy(data), "accessory-idler-train")


# default tier: tests/test_train_case.py::test_two_stage_case_each_mesh_equals_its_pair_alone_over_the_span (same claim, each mesh of a train case equals its pair case alone, on the two-stage case)
@pytest.mark.slow
def test_each_mesh_equals_its_pair_alone(train):
    """Quasi-static contact of both meshes at once on the torsional train against each pair
    solved alone at its own angle (the pair case files written above): TE and mesh stiffness
    over a mesh period to 1e-9 (the issue asks 0.5 % of the means)."""
    data, case = train
    scene = case.static_train()
    res = jg.quasi_static(scene, case.mesh_modifications(), case.torque, positions_per_pitch=PPP)
    theta = np.asarray(res.theta)
    z = [g["teeth"] for g in data["gears"]]
    angles = (theta, z[0] / z[1] * theta + case.layout().phases[1])
    for k, alone in enumerate(_pairs_alone(data)):
        ref = jg.quasi_static(
            js.TorsionalPair(alone.mesh_model(), 1e5),
            alone.modifications,
            alone.torque,
            angles[k],
        )
        got = res.meshes[k]
        np.testing.assert_allclose(got.transmission_error, ref.transmission_error, rtol=1e-9)
        np.testing.assert_allclose(got.mesh_stiffness, ref.mesh_stiffness, rtol=1e-9)
        assert float(got.te_mean) == pytest.approx(float(ref.te_mean), rel=1e-9)


_QS_COMPILES: list[str] = []  # quasi_static's compilations while a test listens (fun names)
_LISTENING = [False]


def _count_solves(name, secs, fun_name="", **kw):
    compiled = name == "/jax/core/compile/backend_compile_duration"
    if _LISTENING[0] and compiled and "_quasi_static" in str(fun_name):
        _QS_COMPILES.append(fun_name)


jax.monitoring.register_event_duration_secs_listener(_count_solves)


def test_one_modifications_for_every_mesh_is_the_per_mesh_solve(train):
    """``quasi_static`` takes one :class:`jaxgear.Modifications` for every mesh, None or one per
    mesh, and makes the per-mesh form before it compiles: a train's unmodified flanks given as
    one ``Modifications()`` after the same flanks given per mesh compile nothing (a CLI run of
    a train solves both designs; they compiled one program each) and give the same TE; None
    likewise."""
    _, case = train
    scene = case.static_train()
    per_mesh = tuple(jg.Modifications() for _ in case.pairs)
    ref = jg.quasi_static(scene, per_mesh, case.torque, positions_per_pitch=PPP)
    _QS_COMPILES.clear()
    _LISTENING[0] = True
    try:
        one = jg.quasi_static(scene, jg.Modifications(), case.torque, positions_per_pitch=PPP)
        none = jg.quasi_static(scene, None, case.torque, positions_per_pitch=PPP)
    finally:
        _LISTENING[0] = False
    assert _QS_COMPILES == []
    for r in (one, none):
        for got, want in zip(r.meshes, ref.meshes, strict=True):
            np.testing.assert_array_equal(got.transmission_error, want.transmission_error)


# default tier: tests/test_dynamics.py::test_disc_inertia_and_torsional_frequency (same claim, the model's modes against the chain written out, on the torsional pair); a train's modes are written by tests/test_every_kind.py's train-torsional run
@pytest.mark.slow
def test_natural_frequencies_equal_a_three_inertia_chain(train):
    """The train's modes (time-averaged mesh stiffness) against the chain written out: three
    solid-disc inertias ½ ρ π b r_a⁴, two mesh springs of each pair's mean stiffness (alone,
    quasi-static over a period) acting on the approaches r_b φ_driving − r_b φ_driven; SciPy's
    generalised eigenvalues. Within 0.5 % (the time averages sample the two meshes at positions
    a phase apart)."""
    data, case = train
    model, _ = build_dynamic_model(case, slices=SLICES)
    first, second = _pairs_alone(data)
    k = [
        float(
            np.mean(
                jg.quasi_static(
                    js.TorsionalPair(c.mesh_model(), 1e5),
                    c.modifications,
                    c.torque,
                    positions_per_pitch=64,
                ).mesh_stiffness
            )
        )
        for c in (first, second)
    ]
    rb = (first.pair.base_radii[0], first.pair.base_radii[1], second.pair.base_radii[1])
    ra = (first.pair.tip_radii[0], first.pair.tip_radii[1], second.pair.tip_radii[1])
    widths = [_gear_table(data, n)["face_width_mm"] * 1e-3 for n in ("input", "idler", "output")]
    rho = data["material"]["density_kg_m3"]
    M = np.diag([0.5 * rho * math.pi * b * r**4 for b, r in zip(widths, ra, strict=True)])
    a = np.array([rb[0], -rb[1], 0.0])
    b = np.array([0.0, rb[1], -rb[2]])
    K = k[0] * np.outer(a, a) + k[1] * np.outer(b, b)
    ref = np.sqrt(np.clip(scipy.linalg.eigh(K, M, eigvals_only=True), 0.0, None))
    got = np.sort(np.asarray(model.modes.omega))
    assert got[0] == pytest.approx(0.0, abs=1e-6 * got[-1])  # the free rotation of the chain
    np.testing.assert_allclose(got[1:], ref[1:], rtol=5e-3)
    # each mesh's share of each elastic mode's strain energy, k_k (u_k·φ)² / ω² in the chain
    w2, phi = scipy.linalg.eigh(K, M)
    chain = np.array(
        [
            [kk * (u @ phi[:, i]) ** 2 / w2[i] for i in (1, 2)]
            for kk, u in zip(k, (a, b), strict=True)
        ]
    )
    shares = np.asarray(mesh_energy_shares(model))[:, 1:]
    np.testing.assert_allclose(shares, chain, atol=5e-3)
    assert 0.2 < shares[0, 0] < 0.3  # the first mode strains the second mesh most


def _idler_delay(case) -> float:
    """Mesh 2's engagement after mesh 1's, in idler pitches (mod 1), derived by hand.

    Angles on the idler (gear 1) are measured in its direction of motion, φ its rotation. The
    idler is driven in mesh 1 on its trailing flank and drives in mesh 2 on its leading flank;
    a tooth with centre line at c has those flanks' involutes starting on the base circle at
    c − ψ_b and c + ψ_b, ψ_b = s/(2r) + inv α_t. A mesh is at its engagement when a contact
    line sits at roll distance ρ_A from its driving gear's tangent point: in mesh 1 the idler's
    contact point is L_1 − ρ_A,1 from its own tangent point T2 (L = T1T2), in mesh 2 it is
    ρ_A,2 from T1. Involute: a flank starting at angle c' meets the line of action at roll
    distance ρ from the tangent point at angle τ when c' = τ ∓ ρ / r_b (− trailing, + leading).
    So a tooth of the idler engages in mesh 1 at c − ψ_b = τ2 − (L_1 − ρ_A,1)/r_b and in mesh 2
    at c + ψ_b = τ1 + ρ_A,2 / r_b: the idler turns φ_2 − φ_1 = τ1 − τ2 + (ρ_A,2 + L_1 − ρ_A,1)
    / r_b − 2 ψ_b between them, modulo a pitch."""
    p1, p2 = case.pairs
    a1, a2 = (p.operating_pressure_angle for p in case.pairs)
    phi1, phi2 = case.angles
    o_in = np.zeros(2)
    o_id = o_in + p1.center_distance * np.array([math.cos(phi1), math.sin(phi1)])
    o_out = o_id + p2.center_distance * np.array([math.cos(phi2), math.sin(phi2)])
    spin_in, spin_id = 1.0, -1.0  # external meshes: the idler turns against the input

    def tangent_points(o_g, o_h, spin_g, rb_g, rb_h, alpha):
        """Where the line of action touches the driving (g) and driven (h) base circles: the
        pair frame's T1 = r_b1 (cos α, −sin α) and T2 = O2 + r_b2 (−cos α, sin α) turned onto
        the centre line e, mirrored for a driving gear turning about −z."""
        e = (o_h - o_g) / np.linalg.norm(o_h - o_g)
        n = np.array([-e[1], e[0]])  # e rotated +90°
        u = math.cos(alpha) * e - spin_g * math.sin(alpha) * n
        return o_g + rb_g * u, o_h - rb_h * u

    _, t2 = tangent_points(o_in, o_id, spin_in, *p1.base_radii, a1)
    t1, _ = tangent_points(o_id, o_out, spin_id, *p2.base_radii, a2)

    def tau(point):  # angle of a point about the idler, in its direction of motion
        d = point - o_id
        return spin_id * math.atan2(d[1], d[0])

    rb = p1.base_radii[1]
    assert rb == pytest.approx(p2.base_radii[0], rel=1e-14)
    at = p2.transverse_pressure_angle
    psi = p2.reference_thickness[0] / (2 * p2.pitch_radii[0]) + math.tan(at) - at
    length1 = p1.center_distance * math.sin(a1)
    turn = tau(t1) - tau(t2) + (p2.start_roll + length1 - p1.start_roll) / rb - 2 * psi
    pitch = 2 * math.pi / p2.pinion.teeth
    return (turn % pitch) / pitch


def _engagements(stiffness) -> float:
    """The position (in positions, mod the period) of the largest upward jump of a stiffness
    curve over one period: a tooth pair entering."""
    k = np.asarray(stiffness)
    jumps = np.diff(np.concatenate([k, k[:1]]))
    return (int(np.argmax(jumps)) + 1) % k.size


@pytest.mark.parametrize("angle_deg", [90.0, 30.0, -60.0])
def test_mesh_phase_read_from_the_stiffness_curves_matches_the_layout(angle_deg):
    """The idler train with its output at three angles about the idler: the second mesh's
    engagement jump in the quasi-static stiffness follows the first's by the delay derived by
    hand from the layout (:func:`_idler_delay`), to one position step; and the delays differ
    between the layouts (the layout matters)."""
    data = _train_data(m1=angle_deg)
    # theoretical path: the hand delay is that of the stiffness jumps at the path's start
    data["mesh"]["extended_contact"] = False
    case = jio.parse_train(data)
    res = jg.quasi_static(case.static_train(), None, case.torque, positions_per_pitch=PPP)
    first, second = (_engagements(m.mesh_stiffness) for m in res.meshes)
    measured = ((second - first) % PPP) / PPP
    expected = _idler_delay(case)
    off = abs((measured - expected + 0.5) % 1.0 - 0.5)
    assert off <= 1.0 / PPP + 1e-12, (angle_deg, measured, expected)
    # the layout's phase (train_phases) against the hand derivation, exactly: mesh 2 reaches a
    # whole period when the input has turned the rest of the idler's pitch beyond its phase
    fraction = case.layout().phases[1] * case.pairs[1].pinion.teeth / (2 * math.pi)
    assert (1.0 - fraction) % 1.0 == pytest.approx(expected, abs=1e-9)


def test_idler_delays_differ_between_layouts():
    """The delays differ by more than two position steps between the three layouts; 0.739 of a
    pitch for the embedded case (docs/trains.md)."""
    delays = [_idler_delay(jio.parse_train(_train_data(m1=a))) for a in (90.0, 30.0, -60.0)]
    assert delays[0] == pytest.approx(0.739, abs=5e-4)
    assert min(abs(a - b) for i, a in enumerate(delays) for b in delays[i + 1 :]) > 2.0 / PPP


def _refused(change, message: str):
    data = _train_data()
    change(data)
    with pytest.raises(jio.SchemaError, match=message) as err:
        jio.parse_train(data)
    assert "\n" not in str(err.value)


def test_train_case_refusals_are_one_line_in_file_units():
    def drive_twice(d):
        d["meshes"].append({"driving": "input", "driven": "output", "angle_deg": 200.0})

    def reverse(d):
        d["meshes"].reverse()

    def two_outputs(d):
        d["gears"].append(dict(_gear_table(d, "output"), name="accessory"))
        d["meshes"].append({"driving": "idler", "driven": "accessory", "angle_deg": -60.0})

    def other_module(d):
        _gear_table(d, "output")["normal_module_mm"] = 2.0

    def overlap(d):
        d["meshes"][1]["angle_deg"] = 150.0

    def unknown_gear(d):
        d["meshes"][1]["driven"] = "outptu"

    def lonely(d):
        d["gears"].append(dict(_gear_table(d, "output"), name="spare"))

    def thin(d):
        _gear_table(d, "idler")["face_width_mm"] = -3.0

    def close(d):
        d["meshes"][0]["center_distance_mm"] = 70.0

    def same_name(d):
        d["gears"][2]["name"] = "idler"

    cases = [
        (drive_twice, r"^\[meshes\[2\]\] driven = 'output': is driven by meshes\[1\] already"),
        (reverse, r"^\[meshes\[0\]\] driving = 'idler': does not turn yet"),
        (two_outputs, r"^\[\[meshes\]\]: the train has output gears output, accessory"),
        (other_module, r"normal_module_mm = 1\.5 and \[gears\.output\] normal_module_mm = 2"),
        (overlap, r"^\[\[meshes\]\] angle_deg: gears 'input' and 'output' overlap"),
        (unknown_gear, r"^\[meshes\[1\]\] driven = 'outptu': no such gear, allowed input"),
        (lonely, r"^\[\[gears\]\] spare: in no mesh"),
        (thin, r"^\[gears\.idler\] face_width_mm = -3: out of range, allowed > 0"),
        (close, r"^\[meshes\[0\]\] center_distance_mm = 70: out of range, allowed >= 80\.5"),
        (same_name, r"^\[gears\[2\]\] name = 'idler': is taken by gears\[1\]"),
    ]
    for change, message in cases:
        _refused(change, message)


@pytest.fixture(scope="module")
def branch_run(tmp_path_factory):
    """``jaxgear run`` on the idler train whose input also drives an accessory (at 180°, loaded
    with −30 N·m), small settings (2 slices, 48 positions per pitch), on rigid shafts (no
    ``[scene]``: the quasi-static run and its files, no sweep; a train's sweep per mesh is
    tests/test_lumped_train.py's default jaxgear run, the torsional train's run
    tests/test_every_kind.py's): the case's data, the output folder and what the run printed.
    One run read by the two tests below (each asserts other outputs of it)."""
    data = _train_data()
    data["mesh"].update(slices=2, positions_per_pitch=PPP)
    del data["scene"]
    acc = dict(_gear_table(data, "output"), name="accessory", teeth=50, profile_shift=0.4)
    data["gears"].append(acc)
    data["meshes"].append({"driving": "input", "driven": "accessory", "angle_deg": 180.0})
    data["operating"]["loads"] = [{"gear": "accessory", "torque_Nm": -30.0}]
    folder = tmp_path_factory.mktemp("branch")
    path = folder / "branch.toml"
    path.write_text(case_toml(data), "utf-8")
    out = folder / "out"
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        code = main(["run", str(path), "--out", str(out), "--quiet"])
    assert code == 0
    return data, out, printed.getvalue()


# default tier: tests/test_every_kind.py::test_run_every_scene_kind[train-rigid] (one jaxgear run of a rigid train: the same per-mesh summary keys, te.csv columns, load maps, phasing figure, output torque)
@pytest.mark.slow
def test_jaxgear_run_on_a_train_writes_per_mesh_files(branch_run):
    """``jaxgear run`` on a small train case file (the branching train of :func:`branch_run`):
    summary.json holds a ``meshes`` entry per mesh with the pair keys of ``quasi_static``, te.csv
    a column per mesh, a load map per mesh and the phasing figure. (A sweep's dynamic factor per
    mesh, whose worst is the scene's: tests/test_lumped_train.py's
    test_jaxgear_run_on_the_two_stage_case_writes_bearing_forces. The balancing output torque without loads,
    T z_out / z_in, is the power balance of test_jaxgear_run_on_an_input_driving_two_meshes
    with no accessory load: one formula, asserted there.)"""
    _, out, printed = branch_run
    summary = json.loads((out / "summary.json").read_text())
    assert summary["complete"] is True
    names = ["input-idler", "idler-output", "input-accessory"]
    assert [m["name"] for m in summary["meshes"]] == names
    for m in summary["meshes"]:
        assert set(m["quasi_static"]["exact"]) >= {
            "te_mean_m",
            "te_rms_m",
            "mesh_stiffness_mean_N_per_m",
            "max_line_load_N_per_m",
        }
        assert (out / f"load_map_{m['name']}.png").stat().st_size > 0
    # the idler passes the normal force on: equal normal loads in its two meshes
    loads = [m["normal_load_N"] for m in summary["meshes"]]
    assert loads[1] == pytest.approx(loads[0], rel=1e-12)
    header = (out / "te.csv").read_text().splitlines()[0].split(",")
    for name in names:
        # the mesh's name in snake case (input-idler -> input_idler)
        assert f"transmission_error_exact_modified_{name.replace('-', '_')}_m" in header
    assert (out / "phasing.png").stat().st_size > 0
    assert not (out / "sweep").exists()  # rigid shafts: no dynamics
    assert "input-idler" in printed


def test_an_implausible_train_warns_per_mesh():
    """Absurd but valid: a tip relief 40 times the mean static deflection warns once per mesh,
    naming the mesh and the key as a pair case does."""
    data = _train_data()
    data["modifications"]["tip_relief"] = {"depth_um": 500.0, "extent": 0.25}
    with pytest.warns(jio.CaseWarning) as caught:
        jio.parse_train(data)
    messages = [str(w.message) for w in caught]
    assert any(m.startswith("meshes[0] input-idler: [modifications] tip_relief") for m in messages)
    assert any(m.startswith("meshes[1] idler-output: [modifications] tip_relief") for m in messages)


def test_a_branching_train_shares_the_power_by_statics():
    """The idler also drives an accessory gear (50 teeth) loaded with −20 N·m; the output takes
    the balance. Each mesh equals its pair alone at the torque the statics written here give
    (the idler passes F_in = T/r_b,in on and splits it, F_in = F_acc + F_out, F_acc =
    20 N·m / r_b,acc): TE to 1e-9 over a period; the train's dynamic model builds and runs."""
    data = _train_data()
    acc = dict(_gear_table(data, "output"), name="accessory", teeth=50, profile_shift=0.4)
    data["gears"].append(acc)
    data["meshes"].append({"driving": "idler", "driven": "accessory", "angle_deg": -90.0})
    data["operating"]["loads"] = [{"gear": "accessory", "torque_Nm": -20.0}]
    # the model's time averages on the run's 32 steps per period (not the 64 positions of an
    # "auto" step): the sweep below runs on the rows the build holds (one table, not two)
    data["scene"]["integration"]["steps_per_period"] = 32
    case = jio.parse_train(copy.deepcopy(data))
    res = jg.quasi_static(
        case.static_train(), case.mesh_modifications(), case.torque, positions_per_pitch=PPP
    )
    first = _pair_case(data, "input", "idler", data["operating"]["torque_Nm"])
    rb_in, rb_id = first.pair.base_radii
    f_in = first.torque / rb_in  # spur: cos β_b = 1
    to_acc = _pair_case(data, "idler", "accessory", 20.0)  # (its geometry only)
    f_acc = 20.0 / to_acc.pair.base_radii[1]
    torques = {"input-idler": first.torque, "idler-accessory": f_acc * rb_id}
    torques["idler-output"] = (f_in - f_acc) * rb_id
    theta = np.asarray(res.theta)
    layout = case.layout()
    for k, (g, h) in enumerate(case.gears):
        name = case.mesh_name(k)
        alone = _pair_case(data, case.gear_names[g], case.gear_names[h], torques[name])
        ref = jg.quasi_static(
            js.TorsionalPair(alone.mesh_model(), 1e5),
            alone.modifications,
            alone.torque,
            layout.ratios[g] * theta + layout.phases[k],
        )
        np.testing.assert_allclose(
            res.meshes[k].transmission_error, ref.transmission_error, rtol=1e-9, err_msg=name
        )
        assert case.mesh_torques[k] == pytest.approx(torques[name], rel=1e-12)
    model, _ = build_dynamic_model(case, slices=2)
    sw = speed_sweep(model, [300.0, 900.0], integrator=Newmark(32), window=SteadyState(4, 2))
    assert len(sw.results.meshes) == 3
    assert np.all(np.asarray(sw.results.result) == 0)
    for k, m in enumerate(sw.results.meshes):  # each mesh's static force: the statics above
        rb = case.pairs[k].base_radii[0]
        assert float(m.static_force[0]) == pytest.approx(case.mesh_torques[k] / rb, rel=1e-6)


def test_loads_are_refused_in_one_line():
    def load(entries):
        def change(d):
            d["operating"]["loads"] = entries

        return change

    _refused(
        load([{"gear": "input", "torque_Nm": -5.0}]),
        r"^\[operating\.loads\[0\]\] gear = 'input': is the input",
    )
    _refused(
        load([{"gear": "idler", "torque_Nm": 5.0}]),
        r"^\[operating\.loads\[0\]\] torque_Nm = 5: out of range",
    )
    _refused(
        load([{"gear": "idler", "torque_Nm": -500.0}]),
        r"^\[\[operating\.loads\]\]: the loads take 461\.1 % of the input power",
    )
    _refused(
        load([{"gear": "output", "torque_Nm": -5.0}]),
        r"^\[\[operating\.loads\]\]: every output gear \(one that drives no other\) has a load",
    )


# default tier: tests/test_train_case.py::test_a_branching_train_shares_the_power_by_statics (the same branching train's power balance, solved) and tests/test_every_kind.py::test_run_every_scene_kind[train-rigid] (a rigid train's jaxgear run and its output torque)
@pytest.mark.slow
def test_jaxgear_run_on_an_input_driving_two_meshes(branch_run):
    """The input drives the idler and an accessory (at 180°, loaded with −30 N·m): ``jaxgear
    run`` completes, and the balancing output's torque is what the power balance written here
    leaves, T_out = −(T ω_0 + T_acc ω_acc)/ω_out."""
    data, out, _ = branch_run
    summary = json.loads((out / "summary.json").read_text())
    z = {g["name"]: g["teeth"] for g in data["gears"]}
    w_acc, w_out = z["input"] / z["accessory"], z["input"] / z["output"]  # per unit ω_0
    expected = (80.0 - 30.0 * w_acc) / w_out
    assert summary["operating"]["output"] == "output"
    assert summary["complete"] is True
    assert summary["operating"]["output_torque_Nm"] == pytest.approx(expected, rel=1e-12)


EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "two-stage-torsional.toml"


def _two_stage_data() -> dict:
    data = tomllib.loads(EXAMPLE.read_text("utf-8"))
    data["mesh"].update(slices=SLICES, positions_per_pitch=16)
    return data


def test_two_stage_case_each_mesh_equals_its_pair_alone_over_the_span():
    """The example two-stage case (20 → 40, a 30-tooth pinion on the 40's shaft → 45): its
    meshes repeat together every 4 periods of the first (20 Ω against 15 Ω); over that span each
    mesh equals its pair written as a pair case of its own, the second at the torque the shaft
    passes on, T r_b,40 / r_b,20 (TE to 1e-9); the clocking of the pinion on its shaft shifts the
    second mesh's phase by the same angle."""
    data = _two_stage_data()
    # on the theoretical path: the shaft passes on T r_b,40 / r_b,20 and each pair is then
    # statically determinate; a corner cell beyond the path (the case file's default) acts with
    # its tip owner's shorter lever arm and changes the torque the shaft passes on
    data.setdefault("mesh", {})["extended_contact"] = False
    case = jio.parse_train(copy.deepcopy(data))
    assert case.span_periods == 4
    # each mesh's order: its driving gear's teeth per input turn (20, then 30 × 20/40)
    assert case.mesh_orders == (20, 15)
    res = jg.quasi_static(
        case.static_train(),
        case.mesh_modifications(),
        case.torque,
        positions_per_pitch=16,
        periods=4,
    )
    theta = np.asarray(res.theta)
    first = _pair_case(data, "input", "wheel-1", 120.0)
    rb_in, rb_wheel = first.pair.base_radii
    second = _pair_case(data, "pinion-2", "output", 120.0 * rb_wheel / rb_in)
    phase = case.layout().phases[1]
    for k, (alone, angles) in enumerate(((first, theta), (second, 0.5 * theta + phase))):
        ref = jg.quasi_static(
            js.TorsionalPair(alone.mesh_model(), 1e5), alone.modifications, alone.torque, angles
        )
        np.testing.assert_allclose(
            res.meshes[k].transmission_error, ref.transmission_error, rtol=1e-9
        )
    clocked = copy.deepcopy(data)
    _gear_table(clocked, "pinion-2")["clocking_deg"] = 3.0
    shifted = jio.parse_train(clocked).layout().phases[1]
    pitch = 2 * math.pi / 30
    assert (shifted - phase) % pitch == pytest.approx(math.radians(3.0), abs=1e-12)


def test_two_stage_refusals():
    def on_shaft(d):
        d["meshes"][1]["driven"] = "wheel-1"

    def first_clocked(d):
        _gear_table(d, "wheel-1")["clocking_deg"] = 5.0

    def short_window(d):
        d["scene"]["integration"]["keep_periods"] = 3

    def driven_twice(d):
        d["gears"].append(dict(_gear_table(d, "output"), name="extra", teeth=25))
        d["meshes"].append({"driving": "extra", "driven": "pinion-2", "angle_deg": 200.0})

    for change, message in (
        (on_shaft, r"^\[meshes\[1\]\] driven = 'wheel-1': is on the driving gear's shaft"),
        (first_clocked, r"^\[gears\.wheel-1\] clocking_deg = 5: the first gear on shaft"),
        (short_window, r"^\[scene\.integration\] keep_periods = 3: out of range, allowed >= 4"),
        (driven_twice, r"^\[meshes\[2\]\] driving = 'extra': does not turn yet"),
    ):
        data = _two_stage_data()
        change(data)
        with pytest.raises(jio.SchemaError, match=message):
            jio.parse_train(data)


# default tier: tests/test_lumped_train.py::test_jaxgear_run_on_the_two_stage_case_writes_bearing_forces (same claims on the embedded two-stage train: span rows, shafts, output torque, mesh frequencies, orders, per-mesh critical speeds)
@pytest.mark.slow
def test_jaxgear_run_on_the_two_stage_example_solves_over_the_span(tmp_path, no_figures):
    data = _two_stage_data()
    data["mesh"].update(slices=2, positions_per_pitch=PPP)
    data["scene"]["integration"] = {"steps_per_period": 16, "periods": 12, "keep_periods": 8}
    path = tmp_path / "two.toml"
    path.write_text(case_toml(data), "utf-8")
    out = tmp_path / "out"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["span_periods"] == 4
    assert len((out / "te.csv").read_text().splitlines()) == 1 + 4 * PPP
    shafts = {g["name"]: g["shaft"] for g in summary["gears"]}
    assert shafts["pinion-2"] == shafts["wheel-1"] == "wheel-1"
    assert summary["operating"]["output_torque_Nm"] == pytest.approx(120.0 * 40 / 20 * 45 / 30)
    sweep = json.loads((out / "sweep" / "sweep.json").read_text())
    f = np.asarray(sweep["mesh_frequency_mesh_Hz"])
    np.testing.assert_allclose(f[:, 1] / f[:, 0], 0.75, rtol=1e-12)
    # the Campbell diagram's orders: 20 and 15 teeth per input turn, each mesh's coincidences
    np.testing.assert_allclose(sweep["mesh_orders"], [20.0, 15.0], rtol=1e-12)
    for z, row in zip((20.0, 15.0), sweep["critical_speeds_mesh"], strict=True):
        for c in row:
            w = 2 * math.pi * c["frequency_Hz"]
            assert c["speed_rad_s"] == pytest.approx(w / (c["harmonic"] * z), rel=1e-12)
