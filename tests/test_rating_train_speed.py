"""A train's rating at speed, per mesh: K_v measured from the train's speed sweep (each mesh's
largest dynamic mesh force over its static one, interpolated at the rating's input speed) and
the root-stress map at speed of every mesh (``rating.root_stress.at_speed`` per mesh), by the
same functions as a pair's (``measured_dynamic_factor``, ``at_speed_sections``).

References: the dynamic factor's definition computed by hand from the train's own dynamic mesh
forces and the static mesh force T_k/r_b (slow: a real sweep), linear interpolation by hand
on given curves, σ_H ∝ √K_v and σ_F ∝ K_v with K_Hβ and K_Hα given (ISO 6336-2 (4), -3 (2)),
and the root-stress map's linearity in the loads with a stub FE table g(ρ) = 1e3 ρ (hand count
over the cells)."""

import copy
import math
from typing import NamedTuple

import jax
import numpy as np
import pytest
from _rating_cases import stub_table
from test_rating_train import TRAIN

import jaxgear.io as jio
from jaxgear import cli, dynamics as dyn, quasi_static
from jaxgear.cli.run import mesh_dynamics
from jaxgear.cli.sweep import sweep_case

jax.config.update("jax_enable_x64", True)

INPUT_SPEED = 6000.0 * 2 * math.pi / 60  # [operating] speed_rpm of TRAIN, rad/s


def _case(slices=2, ppp=8, **rating):
    d = copy.deepcopy(TRAIN)
    d["rating"].update(rating)
    d["mesh"].update(slices=slices, positions_per_pitch=ppp)
    return jio.parse_train(d)


def test_train_measured_k_v_per_mesh_from_given_curves(tmp_path):
    """Each mesh's dynamic factor curve (``dynamic_factor_mesh``: speeds × meshes) interpolated
    by hand at the input's rating speed; ``use_measured = ["K_v"]`` rates each mesh with its
    own: with K_Hβ, K_Hα, K_Fα given, σ_H scales by √(K_v/K_v,ISO) and σ_F by K_v/K_v,ISO."""
    fixed = {"K_Hbeta": 1.1, "K_Halpha": 1.05, "K_Falpha": 1.05}
    speeds = [100.0, 600.0, 700.0, 1000.0]
    per_mesh = [[1.0, 1.0], [1.2, 1.6], [1.5, 1.1], [2.0, 2.0]]
    dynamics = {
        "model": "torsional",
        "slices": 2,
        "speeds_rad_s": speeds,
        "dynamic_factor": [max(r) for r in per_mesh],
        "dynamic_factor_mesh": per_mesh,
    }
    t = (INPUT_SPEED - 600.0) / 100.0  # 628.3 rad/s between the 2nd and 3rd speeds
    want = [1.2 + t * (1.5 - 1.2), 1.6 + t * (1.1 - 1.6)]
    case = _case(use_measured=["K_v"], **fixed)
    # eagerly: jit would compile the rating four times (each mesh's static structure, with and
    # without a given K_v), ~1.4 s CPU each; the values are the same
    with jax.disable_jit():
        iso = cli.rating_outputs(case, str(tmp_path))
        summary = {"rating": copy.deepcopy(iso)}
        cli.measured_dynamic_factor(case, str(tmp_path), summary, dynamics)
    used = summary["rating"]
    assert used["meshes"] == ["input-idler", "idler-output"]
    assert used["measured"]["K_v"]["value"] == pytest.approx(want, rel=1e-12)
    assert "mesh idler-output's dynamic factor" in used["measured"]["K_v"]["source"][1]
    k_iso = iso["factors"]["K_v"]["value"]
    assert iso["factors"]["K_v"]["source"] == ["ISO 6336-1 method B"] * 2
    assert used["factors"]["K_v"]["value"] == pytest.approx(want, rel=1e-12)
    assert all(src.startswith("measured") for src in used["factors"]["K_v"]["source"])
    for k in (0, 1):
        r = want[k] / k_iso[k]
        assert used["pitting"]["sigma_H_Pa"][k] == pytest.approx(
            [math.sqrt(r) * v for v in iso["pitting"]["sigma_H_Pa"][k]], rel=1e-12
        )
        assert used["bending"]["sigma_F_Pa"][k] == pytest.approx(
            [r * v for v in iso["bending"]["sigma_F_Pa"][k]], rel=1e-12
        )
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert table.count("| K_v measured |") == 2
    # a rating speed outside the swept range adds nothing
    summary = {"rating": copy.deepcopy(iso)}
    outside = dynamics | {"speeds_rad_s": [1.0, 2.0, 3.0, 4.0]}
    cli.measured_dynamic_factor(case, str(tmp_path), summary, outside)
    assert "K_v" not in summary["rating"].get("measured", {})


class _Mesh(NamedTuple):
    """A stub dynamic mesh: the fields the root-stress map and the at-speed section read."""

    line_load: np.ndarray
    cell_s: np.ndarray
    cell_z: np.ndarray
    cell_mask: np.ndarray
    dynamic_factor: float
    dynamic_factor_tooth: float


class _Run(NamedTuple):
    speed: float
    result: int
    meshes: tuple


def _hand_max(pair, member, line_load, cell_s, mask) -> float:
    """max over the cells of w · g(ρ), g = 1e3 ρ (the stub table), ρ the member's roll."""
    roll = np.asarray(pair.roll_distance(np.asarray(cell_s), member))
    return float(np.max(np.where(mask, np.maximum(line_load, 0.0) * 1e3 * roll, 0.0)))


def test_train_root_stress_at_speed_per_mesh(tmp_path):
    """``at_speed_sections`` on a train: each mesh's map at speed from its own dynamic cell loads
    (stub loads, hand count), its static map from its own rigid mesh at the run's slices (hand
    count over the quasi-static result's cells), the ratio, and the mesh's dynamic factors;
    per-mesh lists in ``rating.root_stress.at_speed`` and two rows per mesh in rating.md."""
    case = _case()
    results = cli.train_mesh_results(case)
    # compiled (not under jax.disable_jit, whose eager primitives compiled one by one cost more
    # than the rating's programs: 9.1 -> 6.7 CPU s for this test)
    section = cli.rating_outputs(case, str(tmp_path), results, root_stress=stub_table)
    meshes = []
    for k, pair in enumerate(case.pairs):
        g = float(pair.path_of_contact)
        s = np.array([[[0.2 * g] * 2, [0.7 * g] * 2], [[0.4 * g] * 2, [0.9 * g] * 2]])
        w = np.array([[[1.0, 2.0], [0.5, 0.5]], [[3.0, -1.0], [2.0, 1.0]]]) * 1e5 * (k + 1)
        mask = np.ones((2, 2, 2), dtype=bool)
        mask[1, 0, 0] = k == 1  # mesh 0: its largest load off the flanks
        meshes.append(_Mesh(w, s, np.zeros_like(s), mask, 1.3 + k, 1.4 + k))
    run = _Run(speed=700.0, result=0, meshes=tuple(meshes))
    out = cli.at_speed_sections(case, str(tmp_path), section, run, 2, stub_table)
    fast = out["root_stress"]["at_speed"]
    assert fast["speed_rad_s"] == [700.0, 700.0] and fast["slices"] == [2, 2]
    assert fast["dynamic_factor"] == [1.3, 2.3] and fast["dynamic_factor_tooth"] == [1.4, 2.4]
    for k, pair in enumerate(case.pairs):
        m = meshes[k]
        one = case.mesh_case(k)
        static = quasi_static(one.mesh_model(slices=2), one.modifications, one.torque)
        for i in (0, 1):
            at = _hand_max(pair, i, m.line_load, m.cell_s, m.cell_mask)
            rest = _hand_max(
                pair, i, np.asarray(static.line_load), static.cell_s, np.asarray(static.cell_mask)
            )
            assert fast["max_Pa"][k][i] == pytest.approx(at, rel=1e-12)
            assert fast["static_max_Pa"][k][i] == pytest.approx(rest, rel=1e-9)
            assert fast["ratio"][k][i] == pytest.approx(at / rest, rel=1e-9)
    table = (tmp_path / "rating.md").read_text(encoding="utf-8")
    assert table.count("| σ_F,FE max at speed |") == 2
    assert table.count("| σ_F,FE at speed / static |") == 2


@pytest.mark.slow
def test_train_k_v_and_root_stress_at_speed_from_a_real_sweep(tmp_path):
    """A two-speed sweep of the small torsional idler train (2 slices, 16 steps per mesh
    period), as ``jaxgear run`` reads it: each mesh's measured K_v against its dynamic factor
    by hand from the train's own dynamic mesh forces at the two speeds (max F_m / F_s, F_s =
    T_k/r_b,k of the mesh's driving gear, spur), interpolated at the input's rating speed; and
    the root-stress map at speed of every mesh (stub FE table) against a hand count over the
    same run's cell loads at the sweep's speed of the largest dynamic factor."""
    d = copy.deepcopy(TRAIN)
    d["mesh"].update(slices=2, positions_per_pitch=8)
    d["scene"]["integration"].update(periods=6, keep_periods=2, steps_per_period=16)
    case = jio.parse_train(d)
    speeds = [550.0, 700.0]
    sw = sweep_case(case, speeds, str(tmp_path / "sweep"), slices=2, show_progress=False)
    df = np.asarray(sw["dynamic_factor"], dtype=float)
    dynamics = {
        "model": "torsional",
        "slices": 2,
        "speeds_rad_s": sw["speeds_rad_s"],
        "dynamic_factor": sw["dynamic_factor"],
        "speed_of_max_rad_s": float(speeds[int(np.argmax(df))]),
        **mesh_dynamics(sw),
    }
    results = cli.train_mesh_results(case)
    summary = {"rating": cli.rating_outputs(case, str(tmp_path), results, root_stress=stub_table)}
    cli.measured_dynamic_factor(case, str(tmp_path), summary, dynamics)
    cli.root_stress_at_speed(case, str(tmp_path), summary, dynamics, table=stub_table)
    # by hand: the train's dynamic mesh forces at each speed
    model, spec = jio.build_dynamic_model(case, case.scene, slices=2)
    hand = []  # (speed, per mesh DF, run)
    for v in speeds:
        run = dyn.simulate(
            model,
            v,
            integrator=jio.spec_integrator(spec),
            window=jio.spec_window(spec),
            outputs=dyn.Outputs(cell_loads=True),
        )
        f_s = []
        for k, pair in enumerate(case.pairs):
            z, m, alpha = pair.pinion.teeth, 1.5e-3, math.radians(25.0)
            f_s.append(case.mesh_torques[k] / (z * m / 2 * math.cos(alpha)))
        hand.append((v, [float(np.max(run.meshes[k].mesh_force)) / f_s[k] for k in (0, 1)], run))
    t = (INPUT_SPEED - speeds[0]) / (speeds[1] - speeds[0])
    want = [hand[0][1][k] + t * (hand[1][1][k] - hand[0][1][k]) for k in (0, 1)]
    rating = summary["rating"]
    assert rating["measured"]["K_v"]["value"] == pytest.approx(want, rel=1e-6)
    _, df_hand, run = max(hand, key=lambda h: max(h[1]))
    fast = rating["root_stress"]["at_speed"]
    assert fast["speed_rad_s"] == pytest.approx([dynamics["speed_of_max_rad_s"]] * 2)
    assert fast["dynamic_factor"] == pytest.approx(df_hand, rel=1e-6)
    for k, pair in enumerate(case.pairs):
        m = run.meshes[k]
        for i in (0, 1):
            at = _hand_max(pair, i, np.asarray(m.line_load), m.cell_s, np.asarray(m.cell_mask))
            assert fast["max_Pa"][k][i] == pytest.approx(at, rel=1e-6)
