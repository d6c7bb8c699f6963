"""Quasi-static solve on the lumped 3D scene (shafts, bearings) through structure vectors."""

import dataclasses

import equinox as eqx
import numpy as np
import pytest
from _scene_solve import (
    assert_split_equals_whole,
    grounded_solve,
    half_face_meshes,
    solve_grounded,
)

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import Newmark, SteadyState, dynamic_model, simulate
from jaxgear.io import parse_scene


@pytest.fixture(scope="module")
def case():
    return jio.load_case("accessory-spur").replace(slices=6)


@pytest.fixture(scope="module")
def solved(case):
    """The case's model and grounded quasi-static solve (built once for the module)."""
    return grounded_solve(case)


def _solve(case, spec=None):
    model, r = grounded_solve(case, spec)
    return model.scene, r


def test_bearing_loads_balance_the_mesh_force(case, solved):
    sc, r = solved[0].scene, solved[1]
    forces = np.asarray(sc.reaction_matrix()) @ np.asarray(r.x).T  # (n_reactions, P)
    names = sc.reaction_names
    for shaft in ("pinion", "gear"):
        fx = sum(forces[i] for i, n in enumerate(names) if n.startswith(shaft) and n.endswith("Fx"))
        fy = sum(forces[i] for i, n in enumerate(names) if n.startswith(shaft) and n.endswith("Fy"))
        # spur: the bearings of each shaft carry the flank-normal mesh force F_n = T / r_b1
        np.testing.assert_allclose(np.hypot(fx, fy), case.normal_load, rtol=1e-6)


def test_compliant_shafts_add_to_the_rigid_mesh_te_and_stiff_ones_recover_it(case, solved):
    r3 = solved[1]
    rigid = jg.quasi_static(
        case.mesh_model(slices=6), case.modifications, case.torque, positions_per_pitch=16
    )
    assert float(r3.te_mean) > float(rigid.te_mean) * 1.5  # shafts and bearings add compliance
    spec = parse_scene(case.raw["scene"])
    stiff = []
    for sh in (spec.pinion_shaft, spec.gear_shaft):
        bearings = tuple(
            dataclasses.replace(b, radial=b.radial * 1e4, axial=b.axial * 1e4) for b in sh.bearings
        )
        stiff.append(dataclasses.replace(sh, diameter=sh.diameter * 10, bearings=bearings))
    _, r_stiff = _solve(case, dataclasses.replace(spec, pinion_shaft=stiff[0], gear_shaft=stiff[1]))
    np.testing.assert_allclose(
        np.asarray(r_stiff.transmission_error), np.asarray(rigid.transmission_error), rtol=5e-3
    )


def test_structure_nodes_and_a_second_mesh_are_refused_by_one_mesh_entries(case, solved):
    """The structure names its nodes (the torque nodes are the scene's torque DOFs, the gear nodes
    its members'); an unknown node and the one-mesh reads of a scene with two meshes (its
    ``mesh``, its quasi-static result's TE) give one-line errors naming what is allowed; a
    wrong count of per-mesh modifications is refused before any computation."""
    sc = solved[0].scene
    st = sc.structure
    assert sc.torque_dofs == (st.node("input") + 5, st.node("output") + 5)
    pinion, gear = (sc.members[g] for g in sc.meshes[0].gears)  # (driving, driven)
    assert (pinion.dofs[0], gear.dofs[0]) == (st.node("pinion"), st.node("gear"))
    with pytest.raises(
        ValueError,
        match=r"^mesh 0: gears = \(0, 2\) must be two different indices of the scene's 2 gear "
        r"members \(0 to 1\)$",
    ):
        dataclasses.replace(sc, meshes=(dataclasses.replace(sc.meshes[0], gears=(0, 2)),))
    with pytest.raises(
        ValueError,
        match=r"^structure node 'idler' does not exist: allowed pinion, gear, input, output$",
    ):
        st.node("idler")
    two = eqx.tree_at(lambda s: s.meshes, sc, (sc.meshes[0], sc.meshes[0]))
    with pytest.raises(
        ValueError, match=r"^the scene has 2 gear meshes; this entry handles a scene with one mesh$"
    ):
        _ = two.mesh
    res = solve_grounded(two, case, positions_per_pitch=4)
    assert len(res.meshes) == 2
    with pytest.raises(
        ValueError, match=r"^the scene has 2 gear meshes; read their results from meshes\[k\]$"
    ):
        _ = res.transmission_error
    with pytest.raises(ValueError, match=r"^modifications: 3 given for a scene of 2 gear meshes"):
        jg.quasi_static(two, (case.modifications,) * 3, case.torque)


def test_a_pair_cut_into_two_half_face_meshes_gives_the_pair_result(case, solved):
    """A scene of two meshes: the spur pair cut across the face into two half-face meshes on the
    same rigid gear nodes (each at its place along the axes) is the same contact problem, solved
    over both meshes at once. Reference: the one-mesh scene's result (coordinates, TE of each
    half equal to the pair's, mesh stiffness and contact length summing to the pair's, line
    loads side by side), to 1e-9. The tilting moments of the halves' loads on the shafts must
    sit at the right axial places for the coordinates to agree."""
    model, whole = solved
    sc = model.scene
    two = eqx.tree_at(lambda s: s.meshes, sc, half_face_meshes(sc.meshes[0]))
    split = solve_grounded(two, case)
    assert_split_equals_whole(whole, split, 1e-9)


# default tier: tests/test_dynamics.py::test_torsional_pair_cut_into_two_half_face_meshes_gives_the_pair_response (same claim on the torsional scene); a lumped 3D pair's dynamics run in tests/test_dynamics_lumped.py::test_lumped_modes_energy_and_simulation
@pytest.mark.slow
def test_dynamics_of_a_pair_cut_into_two_half_face_meshes_give_the_pair_response(case, solved):
    """The lumped dynamics over every mesh of a scene: the spur pair as two half-face meshes
    on the same gear nodes has the pair's modes, mean mesh stiffness (summed over the meshes)
    and steady-state response at 2000 rad/s. Reference: the one-mesh model's (Newmark, 64
    steps per mesh period, the models' positions per pitch: their table's program; 4 periods,
    2 kept): each half's dynamic factor, tooth dynamic factor and TE
    RMS equal the pair's, its static force is half of T/(r_b1 cos β_b), the bearing forces
    agree, to 1e-9."""
    model = solved[0]
    two = eqx.tree_at(lambda s: s.meshes, model.scene, half_face_meshes(model.scene.meshes[0]))
    split = dynamic_model(two, case.modifications, case.torque)
    np.testing.assert_allclose(
        float(split.mesh_stiffness_mean), float(model.mesh_stiffness_mean), rtol=1e-9
    )
    w1, w2 = np.asarray(model.modes.omega), np.asarray(split.modes.omega)
    np.testing.assert_allclose(w2[1:], w1[1:], rtol=1e-9)
    run = {"integrator": Newmark(64), "window": SteadyState(4, 2)}
    whole = simulate(model, 2000.0, **run)
    parts = simulate(split, 2000.0, **run)
    assert len(parts.meshes) == 2
    for half in parts.meshes:
        for name in ("dynamic_factor", "dynamic_factor_tooth", "te_rms", "te_mean"):
            np.testing.assert_allclose(
                float(getattr(half, name)), float(getattr(whole, name)), rtol=1e-9, err_msg=name
            )
        np.testing.assert_allclose(float(half.static_force), 0.5 * case.normal_load, rtol=1e-9)
    fb = np.asarray(whole.bearing_force)
    np.testing.assert_allclose(
        np.asarray(parts.bearing_force), fb, rtol=0, atol=1e-9 * np.max(np.abs(fb))
    )
    with pytest.raises(ValueError, match=r"^the scene has 2 gear meshes; read their responses"):
        _ = parts.dynamic_factor
