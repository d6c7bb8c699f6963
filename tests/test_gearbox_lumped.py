"""A parallel pair in lumped 3D form as a gearbox stage (jaxgear.gearbox.LumpedPairGearboxStage;
docs/gearbox.md, "A parallel stage in lumped 3D form"): a gearbox of that one stage against the
scene's own dynamics (jaxgear.dynamics), the stiff-support limit against the torsional pair, and
the two-stage example with its parallel stage in 3D form."""

import math

import equinox as eqx
import numpy as np
import pytest
import scipy.linalg
from _examples import load_example

import jaxgear as jg
from jaxgear import dynamics as jd, gearbox as gb
from jaxgear.dynamics import ModalDamping, Newmark, SteadyState
from jaxgear.scenes import Bearing, ShaftSpec, lumped_pair

EX = load_example("gearbox_two_stage")
MODULE, ALPHA, K_U = EX.MODULE, EX.ALPHA, EX.K_U
B2 = 0.08  # the example's pair: 24 (pinion) / 32 (wheel), b 80 mm
L, D, RHO = 0.12, 0.06, 7800.0  # each shaft: length, diameter (m), density
J_SHAFT = RHO * math.pi * D**4 / 32 * L  # a shaft's polar inertia (kg m^2)
# the gear bodies' polar inertias: with the shaft's, the example's pair (5.2e-3, 0.0165)
J_TOTAL = (5.2e-3, 0.0165)


# a stage's parts (M, K_s, K̄_m, F) by one compiled program per kind of stage (evaluated op by
# op: several hundred small ones); the same function of the stage's leaves
_parts = eqx.filter_jit(lambda stage, positions: stage.dynamic_parts(positions))
# its chain view (M, K) on the torque nodes likewise
_matrices = eqx.filter_jit(lambda stage: stage.matrices())


def _pair():
    pair = jg.GearPair(jg.Member(24, face_width=B2), jg.Member(32, face_width=B2), MODULE, ALPHA)
    mesh = jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(K_U)), 1)
    return pair, mesh


def _scene(support=1.0, torque_z=0.5 * L, elements=4):
    """The example's pair on two shafts (bearings at both ends, the gear mid-way, the torque node
    at ``torque_z``, by default the gear's); ``support`` scales the bearings' stiffness and the shafts' modulus."""
    pair, mesh = _pair()
    radial = 1e10 * support

    def shaft():
        return ShaftSpec(length=L, diameter=D, gear_z=0.5 * L, torque_z=torque_z,
                         elements=elements,
                         bearings=(Bearing(0.0, radial, radial, 0.0), Bearing(L, radial, 0.0, 0.0)))

    inertias = tuple((0.5 * (j - J_SHAFT), j - J_SHAFT) for j in J_TOTAL)
    return lumped_pair(pair, mesh, shaft(), shaft(), masses=(1.5, 2.5), inertias=inertias,
                       youngs_modulus=210e9 * support)


def _elastic(modes):
    f = np.asarray(modes.analysis.frequency)
    return f[~np.asarray(modes.analysis.rigid)]


def test_coordinates_and_ends_are_the_scenes():
    scene = _scene(torque_z=0.0)
    stage = gb.LumpedPairGearboxStage(scene)
    names = stage.coordinates()
    assert len(names) == scene.structure.size == 60  # 2 shafts x 5 nodes x 6
    t_in, t_out = scene.torque_dofs
    assert stage.coordinate_ends() == (t_in, t_out)
    assert names[t_in] == "input phi_z" and names[t_out] == "output phi_z"
    assert gb.LumpedPairGearboxStage(scene, input=1).coordinate_ends() == (t_out, t_in)
    # the cells' structure vectors on the gear nodes' phi_z: cos(beta_b) r_b, both positive (the
    # torsional pair's sense), and none on the torque nodes away from the gears
    row = stage.cell_row(np.asarray(0.3 * float(scene.mesh.base_pitch)))
    on = np.asarray(row.mask)
    V = np.asarray(row.V)[on]
    pair, _ = _pair()
    g1, g2 = (m.dofs[5] for m in scene.members)
    np.testing.assert_allclose(V[:, g1], pair.base_radii[0], rtol=1e-12)
    np.testing.assert_allclose(V[:, g2], pair.base_radii[1], rtol=1e-12)
    assert np.all(V[:, [t_in, t_out]] == 0.0)


def test_bad_inputs_one_line():
    scene = _scene()
    with pytest.raises(ValueError, match="input = 2"):
        gb.LumpedPairGearboxStage(scene, input=2)
    with pytest.raises((TypeError, ValueError), match="LumpedPair"):
        gb.LumpedPairGearboxStage(EX.two_stage()[0].stages[1])


def test_chain_view_is_the_torsional_pair_when_shafts_and_bearings_are_stiff():
    """The torsional chain's 2-DOF view (Guyan onto the torque nodes) tends to the torsional
    pair of the rigid shafts' inertias (body + rho pi d^4 L / 32) and the mean mesh spring."""
    pair, mesh = _pair()
    ref = gb.TorsionalPairGearboxStage(J_TOTAL, pair.base_radii, 1.0, input=0, mesh=mesh)
    m_ref, _, k_ref, _ = _parts(ref, 64)
    errs = []
    for s in (1.0, 1e2, 1e4):
        m, k = _matrices(gb.LumpedPairGearboxStage(_scene(s)))
        errs.append(abs(float(np.asarray(k)[0, 0] / np.asarray(k_ref)[0, 0]) - 1.0))
        if s == 1e4:
            np.testing.assert_allclose(np.asarray(m), np.asarray(m_ref), atol=5e-3 * J_TOTAL[1])
    print("chain view, support x1, x1e2, x1e4: K relative error", errs)
    assert errs[0] > 0.01 and np.all(np.diff(errs) < 0) and errs[2] / errs[1] < 0.03


def _one_stage(torque=500.0):
    scene = _scene(torque_z=0.0, elements=2)
    chain = gb.GearboxTorsional((gb.LumpedPairGearboxStage(scene),), [])
    run = gb.GearboxRun(torque, 1e-2, steps_per_period=32, periods=60, keep_periods=2,
                        damping_ratio=0.05, mean_positions=64)
    model = jd.dynamic_model(scene, None, torque, ModalDamping(0.05), positions_per_pitch=64)
    return chain, run, model


def test_one_stage_gearbox_modes_are_the_scenes():
    """One 3D stage driven by T at the pinion's torque node, its wheel held by a soft output
    spring (in the limit the scene's load, a constant torque on a free drive rotation): its
    coupled modes are the scene's DynamicModel's (1e-6; K̄_m over the same mid-points)."""
    chain, run, model = _one_stage()
    f_ref = np.asarray(model.modes.frequency)[~np.asarray(model.modes.rigid)]
    f = _elastic(gb.gearbox_coupled_modes(chain, run))
    assert f.size == f_ref.size == 35  # 2 shafts x 3 nodes x 6, less the drive rotation
    np.testing.assert_allclose(f, f_ref, rtol=1e-6)


@pytest.mark.slow
def test_one_stage_gearbox_run_is_the_scenes_own_run():
    """The same set-up run at one speed: its mesh force over the recorded window is the
    scene's own run's (jaxgear.dynamics.simulate; the same damping ratio on every mode, the
    same steps and window) within 1e-4 of the static force."""
    chain, run, model = _one_stage()
    speed = 300.0
    r = jd.simulate(model, speed, integrator=Newmark(32), window=SteadyState(60, 2))
    out = gb.gearbox_dynamics(chain, run, speed)
    assert int(out.result) == 0 and int(r.result) == 0
    f_s = float(model.static_force)
    np.testing.assert_allclose(float(out.static_forces[0]), f_s, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(out.mesh_forces)[:, 0], np.asarray(r.mesh_force),
                               atol=1e-4 * f_s)
    np.testing.assert_allclose(float(out.dynamic_factors[0]), float(r.dynamic_factor), rtol=1e-4)


def test_stiff_supports_tend_to_the_torsional_pair():
    """Bearings and shafts stiffer by 10 and 100: the one-stage gearbox's two lowest coupled
    modes (the hold and the mesh mode) tend to the torsional pair's (same inertias, cells and
    hold), the error falling with the support's compliance."""
    pair, mesh = _pair()
    run = gb.GearboxRun(500.0, 1e5)
    ref = gb.TorsionalPairGearboxStage(J_TOTAL, pair.base_radii, 1.0, input=0, mesh=mesh)
    f_ref = np.asarray(gb.gearbox_coupled_modes(gb.GearboxTorsional((ref,), []), run)
                       .analysis.frequency)
    errs = []
    for s in (1.0, 10.0, 100.0):
        chain = gb.GearboxTorsional((gb.LumpedPairGearboxStage(_scene(s)),), [])
        f = np.asarray(gb.gearbox_coupled_modes(chain, run).analysis.frequency)[:2]
        errs.append(np.abs(f / f_ref - 1.0).max())
    errs = np.asarray(errs)
    print("one stage, support x1, x10, x100: max relative error", errs)
    assert errs[0] > 1e-2  # the supports' compliance matters at s = 1
    assert np.all(np.diff(errs) < 0) and errs[2] / errs[1] < 0.15  # ~ 1 / s


def _two_stage(support):
    chain, run = EX.two_stage()
    stage = gb.LumpedPairGearboxStage(_scene(support), input=1)  # the wheel is driven
    return gb.GearboxTorsional((chain.stages[0], stage), chain.shaft_stiffnesses), chain, run


# default tier: tests/test_gearbox_lumped.py::test_stiff_supports_tend_to_the_torsional_pair (the 3D pair's modes tend to the torsional pair's as the supports stiffen, one stage); a 3D pair beside a planetary stage: tests/test_gearbox_case_housing.py::test_file_planetary_ring_seat_carries_the_ring_torque
@pytest.mark.slow
def test_two_stage_example_with_its_pair_in_3d_form():
    """The example's two-stage gearbox with its spur pair in lumped 3D form: the 9 coupled modes
    of the torsional example move by an amount that shrinks as 1 / the supports' stiffness."""
    _, chain, run = _two_stage(1.0)
    f_ref = _elastic(gb.gearbox_coupled_modes(chain, run))
    errs = []
    for s in (1.0, 10.0, 100.0):
        f = _elastic(gb.gearbox_coupled_modes(_two_stage(s)[0], run))[: f_ref.size]
        errs.append(np.abs(f / f_ref - 1.0).max())
    errs = np.asarray(errs)
    print("two stages, support x1, x10, x100: max relative error", errs)
    assert errs[0] > 0.1 and errs[1] < 0.1  # the supports of x1 are as stiff as the mesh
    assert np.all(np.diff(errs) < 0) and errs[2] / errs[1] < 0.15


@pytest.mark.slow
def test_two_stage_run_with_its_pair_in_3d_form():
    """One coupled run of the two-stage example with stiff supports: every mesh's dynamic
    factor is the torsional example's (1e-3), and its static forces the torque ratios'."""
    chain3, chain, run = _two_stage(1e4)
    a = gb.gearbox_dynamics(chain, run, 60.0)
    b = gb.gearbox_dynamics(chain3, run, 60.0)
    assert int(a.result) == 0 and int(b.result) == 0
    np.testing.assert_allclose(np.asarray(b.static_forces), np.asarray(a.static_forces),
                               rtol=1e-12)
    np.testing.assert_allclose(np.asarray(b.dynamic_factors), np.asarray(a.dynamic_factors),
                               rtol=1e-3)


def test_guyan_view_against_a_dense_reduction():
    """The chain's view equals a separately written static condensation (scipy) of the
    scene's K + mean mesh stiffness onto the torque nodes."""
    scene = _scene(torque_z=0.0, elements=2)
    stage = gb.LumpedPairGearboxStage(scene)
    m, k = (np.asarray(a) for a in _matrices(stage))
    mm, ks, km, _ = (np.asarray(a) for a in _parts(stage, 64))
    kk = ks + km
    e = list(scene.torque_dofs)
    i = [j for j in range(kk.shape[0]) if j not in e]
    # condensed stiffness K_ee - K_ei K_ii^-1 K_ie; the mass through the static shapes
    # (the internal coordinates' response to a unit end rotation, the other end held)
    k_ref = kk[np.ix_(e, e)] - kk[np.ix_(e, i)] @ scipy.linalg.solve(kk[np.ix_(i, i)],
                                                                     kk[np.ix_(i, e)])
    np.testing.assert_allclose(k, k_ref, rtol=1e-9, atol=1e-9 * np.abs(k_ref).max())
    shapes = np.zeros((kk.shape[0], 2))
    for c, end in enumerate(e):
        u = np.zeros(kk.shape[0])
        u[end] = 1.0
        f = -kk @ u  # the internal coordinates in equilibrium with the end rotation
        u[i] = scipy.linalg.solve(kk[np.ix_(i, i)], f[i])
        shapes[:, c] = u
    np.testing.assert_allclose(m, shapes.T @ mm @ shapes, rtol=1e-9,
                               atol=1e-12 * np.abs(m).max())
    pair, _ = _pair()
    rigid = np.array([pair.base_radii[1], -pair.base_radii[0]])
    assert np.abs(k @ rigid).max() < 1e-6 * np.abs(k).max() * pair.base_radii[1]
    assert m.shape == (2, 2) and np.all(np.linalg.eigvalsh(m) > 0)


def _housed_one_stage(tmp_path):
    """The accessory-spur pair's lumped scene as a one-stage gearbox, grounded and in a box
    housing of 1000 x steel's modulus (steel's density; Tet4, 40 mm, condensed to 5 kHz)."""
    from _housing import HOUSING_BOX, housed_case

    table = (HOUSING_BOX.replace("youngs_modulus_GPa = 7.0", "youngs_modulus_GPa = 210000.0")
             .replace("density_kg_m3 = 2700.0", "density_kg_m3 = 7800.0")
             + "cutoff_Hz = 5000.0\n")
    case = housed_case(tmp_path, table=table)
    housing = case.housing_body(cache=False).housing
    s = case.scene
    chains = []
    for h in (None, housing):
        scene = lumped_pair(case.pair, case.mesh_model(), s.pinion_shaft, s.gear_shaft,
                            masses=(1.0, 2.5), inertias=((1e-3, 2e-3), (4e-3, 8e-3)), housing=h)
        chains.append(gb.GearboxTorsional((gb.LumpedPairGearboxStage(scene),), []))
    run = gb.GearboxRun(case.torque, 1e4, steps_per_period=32, periods=40, keep_periods=2)
    return chains, run


# default tier: tests/test_gearbox_case_housing.py::test_planar_ring_on_a_stiff_box_is_the_grounded_gearbox (same claim, a planar planetary and a 3D pair in the box)
@pytest.mark.slow
def test_stage_in_a_stiff_housing_is_the_grounded_stage(tmp_path):
    """The stage's scene built with a housing (its bearings on the seats, the housing's
    coordinates in the stage): in a box 1000 x stiffer than steel the one-stage gearbox's
    coupled modes below 5 kHz are the grounded stage's (1e-3)."""
    (grounded, housed), run = _housed_one_stage(tmp_path)
    stage = housed.stages[0]
    assert len(stage.coordinates()) > len(grounded.stages[0].coordinates())
    assert stage.coordinate_ends() == grounded.stages[0].coordinate_ends()
    f0 = _elastic(gb.gearbox_coupled_modes(grounded, run))
    f0 = f0[f0 < 5000.0]
    f = _elastic(gb.gearbox_coupled_modes(housed, run))[: f0.size]
    print("stiff housing: modes below 5 kHz, max relative difference", np.abs(f / f0 - 1).max())
    np.testing.assert_allclose(f, f0, rtol=1e-3)


@pytest.mark.slow
def test_stage_in_a_stiff_housing_runs_as_the_grounded_stage(tmp_path):
    """The same pair of gearboxes at 300 rad/s: the housed stage's mesh force over the recorded
    window is the grounded stage's within 1e-3 of the static force."""
    (grounded, housed), run = _housed_one_stage(tmp_path)
    a = gb.gearbox_dynamics(grounded, run, 300.0)
    b = gb.gearbox_dynamics(housed, run, 300.0)
    assert int(a.result) == 0 and int(b.result) == 0
    f_s = float(a.static_forces[0])
    print("stiff housing: mesh force, max difference / static",
          np.abs(np.asarray(b.mesh_forces) - np.asarray(a.mesh_forces)).max() / f_s)
    np.testing.assert_allclose(np.asarray(b.mesh_forces), np.asarray(a.mesh_forces),
                               atol=1e-3 * f_s)
