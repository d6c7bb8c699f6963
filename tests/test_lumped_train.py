"""Lumped 3D gear trains: shafts on bearings carrying rigid gear nodes, several meshes
(``[scene] model = "lumped3d"`` with ``[[scene.shafts]]`` in a train case).

References, each written here apart from the model: the torsional train (shafts and bearings
made stiff, the lumped train must reduce to it); the nominal mesh forces of each mesh from the
gear data alone (tangential force T/r_b along the line of action, turned from the centre line by
90° − α_wt towards the driving gear's motion, axial force F_t tan β_b with its sign from the
helix hand and sense of rotation by the screw rule), which each shaft's bearings must balance;
and the second stage of the two-stage case replaced by a wrench (the seed's Tab. III-10 logic):
the nominal one, and the mean of the contact forces of the full model, computed here from its
line loads and the contact points of the base plane.
"""

from __future__ import annotations

import copy
import json
import math
import pathlib
import tomllib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _toml import case_toml
from _trains import contact_forces, line_direction, shaft_sum, spins

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import main
from jaxgear.dynamics import Newmark, SteadyState, bearing_forces, speed_sweep
from jaxgear.io import build_dynamic_model
from jaxgear.scenes import mesh_wrench

jax.config.update("jax_enable_x64", True)


def _two_stage(slices: int = 4) -> dict:
    data = tomllib.loads(jio.embedded_case_text("two-stage"))
    data["mesh"].update(slices=slices, positions_per_pitch=4)
    return data


def _gear(data: dict, name: str) -> dict:
    return next(g for g in data["gears"] if g["name"] == name)


def _solve(case):
    scene = case.static_train()
    res = jg.quasi_static(
        scene,
        case.mesh_modifications(),
        case.torque,
        positions_per_pitch=case.positions_per_pitch,
        periods=case.span_periods,
    )
    return res, bearing_forces(scene, res)


# default tier: tests/test_dynamics_lumped.py::test_stiff_shafts_and_bearings_recover_the_rigid_mesh_te (same claim, stiff shafts and bearings give the rigid scene's TE, on a pair); a lumped train's quasi-static runs in test_each_shaft_bearings_balance_the_nominal_mesh_forces
@pytest.mark.slow
def test_stiff_lumped_idler_train_equals_the_torsional_train():
    """The idler train on shafts and bearings a thousand times stiffer than the meshes: each
    mesh's quasi-static TE equals the torsional train's (mean within 0.5 %, measured 0.1 %)."""
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    data["mesh"].update(slices=4, positions_per_pitch=16)
    torsional = jio.parse_train(copy.deepcopy(data))
    stiff = [
        {"position_mm": 0.0, "radial_N_per_um": 1e6, "axial_N_per_um": 1e6},
        {"position_mm": 40.0, "radial_N_per_um": 1e6},
    ]
    data["scene"]["model"] = "lumped3d"
    data["scene"]["shafts"] = [
        {
            "shaft": g,
            "length_mm": 40.0,
            "diameter_mm": 200.0,
            "gear_positions_mm": {g: 20.0},
            "torque_position_mm": 20.0,
            "bearings": stiff,
        }
        for g in ("input", "idler", "output")
    ]
    lumped = jio.parse_train(data)
    assert lumped.lumped and not torsional.lumped
    res, forces = _solve(lumped)
    ref, _ = _solve(torsional)
    for k in range(2):
        te, te_ref = (np.asarray(r.meshes[k].transmission_error) for r in (res, ref))
        assert te.mean() == pytest.approx(te_ref.mean(), rel=5e-3)
        assert np.abs(te - te_ref).max() < 5e-3 * np.abs(te_ref).max()
    # the idler's bearings carry its two mesh forces: F_n along the first line of action (it
    # is driven) and −F_n along the second (it drives), spur gears
    fn = lumped.torque / lumped.pairs[0].base_radii[0]
    expected = fn * (line_direction(lumped, 0) - line_direction(lumped, 1))
    np.testing.assert_allclose(shaft_sum(forces, "idler")[:2], expected, atol=1e-6 * fn)


def _nominal_force(case, k: int, hands: dict) -> np.ndarray:
    """The force (3,) (N) mesh k's driving gear exerts on its driven gear: T_k / r_b along the
    line's direction, and F_t tan β_b along z with the screw rule's sign (a right-handed driving
    gear turning about +z pushes its mate along −z; each flip of hand or sense flips it)."""
    g, _ = case.gears[k]
    pair = case.pairs[k]
    ft = case.mesh_torques[k] / pair.base_radii[0]
    sign = -hands[case.gear_names[g]] * spins(case)[g]
    return np.array([*(ft * line_direction(case, k)), sign * ft * math.tan(pair.base_helix_angle)])


@pytest.fixture(scope="module")
def two_stage_solved():
    """The default two-stage case (the low-speed pinion right-handed), its quasi-static solve
    over the span and its bearing forces: read by the right-handed bearing balance and the
    wrench test (one solve of the 127-period span, not two)."""
    data = _two_stage()
    case = jio.parse_train(copy.deepcopy(data))
    return data, case, *_solve(case)


@pytest.mark.parametrize("lst_hand", ["right", "left"])
def test_each_shaft_bearings_balance_the_nominal_mesh_forces(lst_hand, request):
    """Two-stage helical case: the bearings of each shaft carry the mesh forces on its gears
    (to 1e-6 of the largest), summed from the cells' contact loads along their normals and
    within 1e-4 of the nominal forces written from the gear data alone; the low-speed pinion
    right-handed as the wheel on its shaft (the default), the two axial forces on the
    intermediate shaft oppose (|F_a1 − F_a2|), left-handed they add."""
    hands = {"input": -1, "hst-wheel": 1, "lst-pinion": 1, "output": -1}
    if lst_hand == "left":
        data = _two_stage()
        _gear(data, "lst-pinion")["hand"] = "left"
        _gear(data, "output")["hand"] = "right"
        hands.update({"lst-pinion": -1, "output": 1})
        case = jio.parse_train(data)
        res, forces = _solve(case)
    else:  # the default hands: the module's solve
        _, case, res, forces = request.getfixturevalue("two_stage_solved")
    assert [int(h) for h in case.layout().hands] == list(hands.values())
    nominal = [_nominal_force(case, k, hands) for k in (0, 1)]
    scale = max(np.abs(nominal).max(), 1.0)
    # the mesh forces the bearings balance: the mean over the positions of the cells' contact
    # forces, along the line of action on the path and along the corner's involute normal
    # beyond it (the case file's default extended contact; tests/_corner.py), whose lever arms
    # break the nominal split slightly: within 1e-4 of the nominal force (measured 1.6e-5)
    f0, f1 = (contact_forces(case, res, k)[1].sum(axis=(1, 2)).mean(axis=0) for k in (0, 1))
    for got, want in zip((f0, f1), nominal, strict=True):
        np.testing.assert_allclose(got, want, atol=1e-4 * scale)
    # a bearing's k u is the force the shaft puts on it: the mesh forces on the shaft's gears
    for shaft, load in (("input", -f0), ("intermediate", f0 - f1), ("output", f1)):
        np.testing.assert_allclose(shaft_sum(forces, shaft), load, atol=1e-6 * scale)
    axial = abs(shaft_sum(forces, "intermediate")[2])
    fa0, fa1 = abs(f0[2]), abs(f1[2])
    expected = abs(fa0 - fa1) if lst_hand == "right" else fa0 + fa1
    assert axial == pytest.approx(expected, rel=1e-6)
    fa0, fa1 = abs(nominal[0][2]), abs(nominal[1][2])
    # docs/trains-evidence.md: 863 and 1509 N, 646 N on the intermediate shaft with the default hands
    assert (round(fa0), round(fa1)) == (863, 1509)
    assert round(axial) == (646 if lst_hand == "right" else 2372)


def test_the_rigid_rotation_strains_nothing_and_closes_no_flank():
    """The two-stage lumped train's rigid rotation (each shaft at its speed ratio, the sense of
    rotation included): no cell of either mesh approaches (V·r = 0 to 1e-12 of |V||r|), the
    shafts and bearings carry no force (K r = 0), and the loads do no work (f·r = 0: the output
    torque balances the input power through both stages). With the case file's default contact
    beyond the path a corner cell's exact gap derivative has a part along r (the rotation moves
    the corner along the path; docs/extended-contact.md, "The free drive rotation"): the law
    holds for the cells on the path and for every cell of the rows the solvers use
    (``cell_row``, that part dropped)."""
    case = jio.parse_train(_two_stage())
    scene = case.lumped_train()
    r = np.asarray(scene.rigid)
    n = scene.structure.size

    # the cells of both meshes at one position, their vectors and the solvers' row, in one
    # compiled program (op by op they were some 150 small programs)
    @eqx.filter_jit
    def cells_and_rows(scene):
        every = tuple(
            m.base_plane.cells(0.3 * m.base_plane.mesh_period_angle) for m in scene.meshes
        )
        vectors = [m.cell_vectors(scene.members, c, n) for m, c in zip(scene.meshes, every)]
        row = scene.cell_row(every, tuple(jnp.zeros_like(c.s) for c in every))
        return every, vectors, row.V

    every, vectors, used = cells_and_rows(scene)
    for mesh, cells, V in zip(scene.meshes, every, vectors, strict=True):
        V = np.asarray(V)
        s = np.asarray(cells.s)
        on = (s >= 0.0) & (s <= float(mesh.base_plane.path_of_contact))
        assert np.any(np.asarray(cells.mask) & ~on)  # corner cells are there
        assert np.abs(V[on] @ r).max() < 1e-12 * np.abs(V).max() * np.abs(r).max() * n
        assert abs(float(mesh.te @ r)) < 1e-12 * np.abs(np.asarray(mesh.te)).max() * np.abs(r).max()
    used = np.asarray(used)
    assert np.abs(used @ r).max() < 1e-12 * np.abs(used).max() * np.abs(r).max() * n
    K = np.asarray(scene.structure.K)
    assert np.abs(K @ r).max() < 1e-9 * np.abs(K).max() * np.abs(r).max()
    assert abs(float(scene.f_torque @ r)) < 1e-12 * np.abs(r).max()


def _hst_with_wrench(data: dict, force, moment) -> dict:
    """The two-stage case with its low-speed train removed: the intermediate shaft carries the
    high-speed wheel, takes the balancing output torque at the low-speed pinion's position and
    the wrench there."""
    hst = copy.deepcopy(data)
    hst["gears"] = [g for g in hst["gears"] if g["name"] in ("input", "hst-wheel")]
    hst["meshes"] = hst["meshes"][:1]
    shaft = next(s for s in hst["scene"]["shafts"] if s["shaft"] == "intermediate")
    position = shaft["gear_positions_mm"].pop("lst-pinion")
    shaft["torque_position_mm"] = position
    hst["scene"]["shafts"] = [s for s in hst["scene"]["shafts"] if s["shaft"] != "output"]
    hst["operating"]["wrenches"] = [
        {
            "shaft": "intermediate",
            "position_mm": position,
            "force_N": [float(v) for v in force],
            "moment_Nm": [float(moment[0]), float(moment[1]), 0.0],
        }
    ]
    return hst


def test_second_stage_as_a_wrench_gives_the_intermediate_bearing_loads(two_stage_solved):
    """The seed's Tab. III-10 logic: the low-speed stage replaced by its wrench on the
    intermediate shaft. The nominal wrench (F_n at the centre of the contact zone) gives the
    input shaft's bearing loads to 1e-4 and the intermediate shaft's to 3 % of its largest
    component (measured 1.6 %: 57 N on the bearing near the high-speed wheel, whose y load is
    142 N; the high-speed TE mean moves by 1.3 %, as docs/trains-evidence.md states). The difference is
    the load centre: the mean contact wrench, summed here from the full model's line loads at
    their base-plane points, gives every bearing load to 1e-6."""
    data, full, res, forces = two_stage_solved
    layout, plane = full.layout(), full.mesh_models()[1]
    pinion = full.gear_names.index("lst-pinion")
    fn = full.mesh_torques[1] / (full.pairs[1].base_radii[0] * math.cos(plane.base_helix_angle))
    nominal = mesh_wrench(layout.lines[1], plane, fn, layout.centres[pinion])
    # its moment about the axis is the pinion's torque, resisting its motion (it turns about −z)
    assert nominal[1][2] == pytest.approx(full.mesh_torques[1], rel=1e-9)

    # the mean contact wrench on the pinion: −f n at M = T1 + (ρ_A + s) t + a (z − b/2) e_z on
    # the path, −f n' at the corner P beyond it (the case file's default extended contact;
    # tests/_trains.contact_forces)
    points, force = contact_forces(full, res, 1)
    moment = np.cross(points - layout.centres[pinion], -force).sum(axis=(1, 2))
    contact = (-force.sum(axis=(1, 2)).mean(axis=0), moment.mean(axis=0))

    scale = {
        shaft: max(abs(v) for k, v in forces.items() if k.startswith(shaft + " "))
        for shaft in ("input", "intermediate")
    }
    # each wrench's solve of the high-speed stage alone: (result, bearing forces)
    by_nominal, by_contact = (
        _solve(jio.parse_train(_hst_with_wrench(data, *w))) for w in (nominal, contact)
    )
    for (_, got), tol in ((by_nominal, {"input": 1e-4, "intermediate": 3e-2}), (by_contact, None)):
        for key, value in got.items():
            shaft = key.split(" ")[0]
            rtol = 1e-6 if tol is None else tol[shaft]
            assert abs(value - forces[key]) <= rtol * scale[shaft], key
    # the nominal wrench misses the intermediate shaft's loads by more than 1 % of the largest
    hst, got = by_nominal
    worst = max(abs(got[k] - forces[k]) for k in got if k.startswith("intermediate"))
    assert worst > 1e-2 * scale["intermediate"]
    assert round(worst) == 57 and round(forces["intermediate z=0mm Fy"]) == 142
    assert round(worst / scale["intermediate"], 3) == 0.016
    shift = np.mean(hst.meshes[0].transmission_error) / np.mean(res.meshes[0].transmission_error)
    assert round(100 * (shift - 1), 1) == 1.3


def test_lumped_train_refusals_are_one_line():
    def clash(d):
        _gear(d, "hst-wheel")["hand"] = "left"

    def torque_moment(d):
        d["operating"]["wrenches"] = [
            {"shaft": "intermediate", "position_mm": 10.0, "moment_Nm": [0.0, 0.0, 5.0]}
        ]

    def torsional_wrench(d):
        d["scene"] = {"model": "torsional"}
        d["operating"]["wrenches"] = [{"shaft": "intermediate", "position_mm": 10.0}]

    def short_force(d):
        d["operating"]["wrenches"] = [{"shaft": "intermediate", "position_mm": 10.0},
                                      {"shaft": "input", "position_mm": 10.0,
                                       "force_N": [1.0, 2.0]}]

    def beyond_the_shaft(d):
        d["operating"]["wrenches"] = [{"shaft": "intermediate", "position_mm": 1e4}]

    def wrench_key(d):
        d["operating"]["wrenches"] = [{"shaft": "intermediate", "position_mm": 1.0,
                                       "torque_Nm": 3.0}]

    def missing_shaft(d):
        d["scene"]["shafts"] = d["scene"]["shafts"][:2]

    def missing_gear(d):
        d["scene"]["shafts"][1]["gear_positions_mm"].pop("lst-pinion")

    def unknown_shaft(d):
        d["scene"]["shafts"][2]["shaft"] = "spindle"

    def outside(d):
        d["scene"]["shafts"][1]["gear_positions_mm"]["hst-wheel"] = 150.0

    for change, message in (
        (clash, r"^\[meshes\[0\]\] input → hst-wheel: both hands are 'left': input \(by "),
        (torque_moment, r"^\[operating\.wrenches\[0\]\] moment_Nm = \[0, 0, 5\]: z must be 0"),
        (torsional_wrench, r"^\[operating\] wrenches: needs \[scene\] model = 'lumped3d'"),
        (short_force, r"^\[operating\.wrenches\[1\]\] force_N = \[1, 2\]: must be an array"),
        (beyond_the_shaft, r"^\[operating\.wrenches\[0\]\] position_mm = 10000: out of range"),
        (wrench_key, r"^\[operating\.wrenches\[0\]\] unknown key 'torque_Nm'"),
        (missing_shaft, r"^\[\[scene\.shafts\]\]: no entry for shaft output"),
        (missing_gear, r"^\[scene\.shafts\.intermediate\.gear_positions_mm\] lst-pinion"),
        (unknown_shaft, r"^\[scene\.shafts\[2\]\] shaft = 'spindle': no such shaft, allowed"),
        (outside, r"^\[scene\.shafts\.intermediate\.gear_positions_mm\] hst-wheel = 150"),
    ):
        data = _two_stage()
        change(data)
        with pytest.raises(jio.SchemaError, match=message):
            jio.parse_train(data)


def test_jaxgear_run_on_the_two_stage_case_writes_bearing_forces(tmp_path, no_figures):
    """``jaxgear run`` on the lumped two-stage case (coarse settings): per-mesh summary over the
    127-period span and the mean bearing forces of every shaft, which balance the mesh forces."""
    data = _two_stage(slices=2)
    # coarse: the balance and the orders asserted hold at any resolution (2 positions per pitch
    # and 4 steps per period: 20 % less CPU than 4 and 8)
    data["mesh"]["positions_per_pitch"] = 2
    data["scene"]["integration"] = {"steps_per_period": 4, "periods": 128, "keep_periods": 127}
    path = tmp_path / "two.toml"
    path.write_text(case_toml(data), "utf-8")
    assert main(["run", str(path), "--out", str(tmp_path / "o"), "--quiet"]) == 0
    summary = json.loads((tmp_path / "o" / "summary.json").read_text())
    assert summary["span_periods"] == 127
    forces = summary["bearing_forces_mean_N"]["exact"]
    case = jio.parse_train(data)
    hands = {n: int(h) for n, h in zip(case.gear_names, case.layout().hands, strict=True)}
    np.testing.assert_allclose(
        shaft_sum(forces, "output"), _nominal_force(case, 1, hands), rtol=1e-6, atol=1e-6
    )
    # the Campbell diagram's orders: 28 teeth per input turn, and 35 × 28/127 for the second
    # stage on the intermediate shaft
    sweep = json.loads((tmp_path / "o" / "sweep" / "sweep.json").read_text())
    np.testing.assert_allclose(sweep["mesh_orders"], [28.0, 35 * 28 / 127], rtol=1e-12)
    assert sweep["model"] == "lumped3d"
    # a dynamic factor per mesh at each of a train's default 30 speeds, the worst the scene's;
    # each mesh's mean stiffness
    per = np.asarray(sweep["dynamic_factor_mesh"])
    assert per.shape == (30, 2) and all(v == 0 for v in sweep["result"])
    np.testing.assert_allclose(sweep["dynamic_factor"], per.max(axis=1))
    assert len(sweep["mesh_stiffness_mean_N_per_m"]) == 2
    # the span in te.csv (127 periods of 2 positions), the compound shaft, the output torque
    # by the tooth ratios, each mesh's frequency and its coincidences ω / (h z_k)
    assert len((tmp_path / "o" / "te.csv").read_text().splitlines()) == 1 + 127 * 2
    shafts = {g["name"]: g["shaft"] for g in summary["gears"]}
    assert shafts["lst-pinion"] == shafts["hst-wheel"] != shafts["output"]
    torque = data["operating"]["torque_Nm"]
    assert summary["operating"]["output_torque_Nm"] == pytest.approx(torque * 127 / 28 * 68 / 35)
    f = np.asarray(sweep["mesh_frequency_mesh_Hz"])
    np.testing.assert_allclose(f[:, 1] / f[:, 0], 35 / 127, rtol=1e-12)
    for z, row in zip((28.0, 35 * 28 / 127), sweep["critical_speeds_mesh"], strict=True):
        assert row
        for c in row:
            w = 2 * math.pi * c["frequency_Hz"]
            assert c["speed_rad_s"] == pytest.approx(w / (c["harmonic"] * z), rel=1e-12)


EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "idler-train-lumped3d.toml"


# default tier: tests/test_dynamics_resolution.py::test_low_speed_limit_and_under_resolved_flag (same claim, the dynamics' low-speed limit is the quasi-static result, on a pair); the lumped idler train's dynamics run in tests/test_mesh_table.py::test_static_rows_are_each_steps_static_solve[idler]
@pytest.mark.slow
def test_lumped_idler_train_dynamics_reach_the_quasi_static_limit():
    """The example lumped idler train (examples/idler-train-lumped3d.toml) in the one dynamics
    stack at 20 rad/s, its mesh frequency (143 Hz) far below its first elastic mode: each mesh's
    dynamic TE has the quasi-static mean (within 1 %) and the dynamic factor is 1 within 3 %;
    the modes include the chain's free rotation once."""
    data = tomllib.loads(EXAMPLE.read_text("utf-8"))
    data["mesh"].update(slices=4, positions_per_pitch=32)
    # the model's time averages on the run's 32 steps per period (not the 64 positions of an
    # "auto" step): the sweep below runs on the rows the build holds (one table, not two)
    data["scene"]["integration"]["steps_per_period"] = 32
    case = jio.parse_train(data)
    model, _ = build_dynamic_model(case, slices=4)
    omega = np.sort(np.asarray(model.modes.omega))
    assert omega[0] == pytest.approx(0.0, abs=1e-6 * omega[-1])
    assert omega[1] > 2 * math.pi * 1000.0
    static, _ = _solve(case)
    sw = speed_sweep(model, [20.0], integrator=Newmark(32), window=SteadyState(20, 2))
    assert np.all(np.asarray(sw.results.result) == 0)
    for k, m in enumerate(sw.results.meshes):
        te = float(np.asarray(m.transmission_error).mean())
        assert te == pytest.approx(float(np.mean(static.meshes[k].transmission_error)), rel=1e-2)
        assert float(m.dynamic_factor[0]) == pytest.approx(1.0, abs=3e-2)
