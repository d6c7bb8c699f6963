"""One housing shared by several stages of the coupled gearbox (jaxgear.gearbox.GearboxTorsional's
``housing``; docs/gearbox.md, "One housing for several stages"): two lumped 3D parallel stages
in one box, their bearings on their own seats; then a planetary stage whose held ring is bolted
to a seat of the same box as a lumped pair's bearings (a PlanetaryGearboxStage with a
planetary model on a HousingMount; docs/gearbox.md, "A planetary stage in the shared housing"). Evidence
against a hand assembly written here (the grounded stages' matrices, the condensed housing's K
and M and the seats' rigid levers), the stiff-housing limit (the grounded gearbox), the balance
of the bearing forces, the ring seat's reaction against the ring torque of the stage's torque
balance, the whine against Newmark, the one name of the housing's coordinates, and bad input."""

import dataclasses
import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sla
from _examples import load_example

import fem_prep
import jaxgear as jg
import jaxgear.planetary as jp
from fem_prep.housing import Bore, Foot, HousingBox, Tet4, mesh_box, prepare_housing
from jaxgear import gearbox as gb
from jaxgear.dynamics import QuasiPeriodicBalance
from jaxgear.scenes import Bearing, Housing, HousingMount, ShaftSpec, lumped_pair

EX = load_example("gearbox_two_stage")
L, D = 0.12, 0.06  # each shaft: length, diameter (m); bearings at both ends, the gear mid-way
T_WALL, Y0, Z1, Z2 = 0.01, 0.07, 0.08, 0.21  # wall; first axis (housing y); stages' heights
# housing frame -> each stage's scene frame: scene z (the shafts) along the box's length
# (housing x), scene x (between the centres) its width (housing y), scene y its height (z)
R = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
MASSES, INERTIAS = (1.5, 2.5), ((2e-3, 4e-3), (7.7e-3, 1.53e-2))
SHAFT, HOLD, TORQUE = 2e5, 1e4, 500.0  # inter-stage shaft, output hold (N m/rad), input (N m)


def _pair(z1, z2):
    pair = jg.GearPair(jg.Member(z1, face_width=0.06), jg.Member(z2, face_width=0.06),
                       EX.MODULE, EX.ALPHA)
    return pair, jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(EX.K_U)), 1)


PAIRS = (_pair(24, 32), _pair(20, 36))  # stage 1, stage 2 (centre distances 112, 112 mm)
A = PAIRS[0][0].center_distance
HEIGHTS = (Z1, Z2)


def _shaft():
    return ShaftSpec(length=L, diameter=D, gear_z=0.5 * L, torque_z=0.5 * L, elements=2,
                     bearings=(Bearing(0.0, 2e8, 1e8, 0.0), Bearing(L, 2e8, 0.0, 0.0)))


def _condensed(E, density, cutoff_hz=5000.0):
    """The box (length L + wall along the shafts, the end walls' mid-planes at the bearings),
    a bore round each of the four axes in both end walls: seat 2 j + w, j = stage 1's pinion,
    gear, stage 2's pinion, gear, w = 0 the wall x = 0 (the bearing at z = 0), 1 the other."""
    W, H, Lb = A + 2 * Y0, Z2 + 0.07, L + T_WALL
    bores = tuple(Bore(w, (Y0 + dy, z), 0.025) for z in HEIGHTS for dy in (0.0, A)
                  for w in ("x-", "x+"))
    f = 0.03
    feet = tuple(Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, Lb - f) for y0 in (0.0, W - f))
    box = HousingBox(Lb, W, H, T_WALL, bores=bores, feet=feet)
    ph = prepare_housing(mesh_box(box, 0.05, element=Tet4()), fem_prep.Material(E, 0.3, density),
                         cutoff_hz)
    return ph.condensed_housing()


def _offset(k):
    """t: stage k's scene frame from the housing frame, x_scene = R x_housing + t (its pinion's
    axis the scene z axis, its gear's centre at z = 0)."""
    return -R @ np.array([0.5 * (L + T_WALL), Y0, HEIGHTS[k]])


def _place(k):
    """Stage k's scene origin in the gearbox frame (stage 1's scene frame), the axes parallel:
    x_gearbox = x_stage + t_k."""
    return _offset(0) - _offset(k)


def _scene(k, housing=None, seats=None, position=None):
    pair, mesh = PAIRS[k]
    return lumped_pair(pair, mesh, _shaft(), _shaft(), masses=MASSES, inertias=INERTIAS,
                       housing=housing, seats=seats, housing_position=position)


def _seats(k):
    return tuple(range(4 * k, 4 * k + 4))


def _chains(ch, loss_factor=0.0):
    """(the gearbox with both stages in the one housing, placed once in the gearbox frame
    (stage 1's scene frame) and each stage's scene on that object at its place
    :func:`_place`, the grounded gearbox, the housings placed in each stage's frame: the
    first the shared one, the second for the hand checks)."""
    housings = [Housing.of(ch, loss_factor=loss_factor, rotation=R, offset=_offset(k))
                for k in range(2)]
    housed = tuple(gb.LumpedPairGearboxStage(_scene(k, housings[0], _seats(k), _place(k)))
                   for k in range(2))
    grounded = tuple(gb.LumpedPairGearboxStage(_scene(k)) for k in range(2))
    return (gb.GearboxTorsional(housed, [SHAFT], housing=housings[0]),
            gb.GearboxTorsional(grounded, [SHAFT]), housings)


RUN = gb.GearboxRun(TORQUE, HOLD, steps_per_period=16, periods=6, keep_periods=2)


@pytest.fixture(scope="module")
def steel():
    return _condensed(210e9, 7800.0, 8000.0)  # 6 interior modes kept (5.1 to 8 kHz)


# a stage's parts (M, K_s, K̄_m, F) by one compiled program per kind of stage (evaluated op by
# op: several hundred small ones); the same function of the stage's leaves
_parts = eqx.filter_jit(lambda stage, positions: stage.dynamic_parts(positions))


def _skew(a):
    return np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])


def _bearings(scene):
    """Each bearing of a grounded scene: (its shaft node's first DOF, K_b (6, 6)), the pinion
    shaft's first, each shaft's in its bearings' order (z ascending): read off the scene's
    ``bearings`` stiffness part (one bearing per node)."""
    part = np.asarray(scene.structure.stiffness_parts()["bearings"])
    out = []
    for u in range(0, part.shape[0], 6):
        block = part[u:u + 6, u:u + 6]
        if np.any(block != 0):
            out.append((u, block))
    return out


def _hand_assembly(ch, grounded):
    """The coupled gearbox's (M, K + K̄_m) written out here: the grounded stages' structure and
    mean mesh stiffness, the housing once, each bearing's energy ½ dᵀ K_b d with
    d = u − G q, G = [[R, −S(p − c) R], [0, R]] (p the bearing, c its seat's centre, both in
    its stage's frame), the inter-stage shaft and the output hold."""
    scenes = [s.scene for s in grounded.stages]
    sizes = [s.structure.size for s in scenes]
    h = ch.K.shape[0]
    n = sum(sizes) + h
    K, M = np.zeros((n, n)), np.zeros((n, n))
    offs = [0, sizes[0]]
    q0 = sum(sizes)
    K[q0:, q0:] = ch.K
    M[q0:, q0:] = ch.M
    for k, (stage, scene) in enumerate(zip(grounded.stages, scenes, strict=True)):
        o, w = offs[k], sizes[k]
        K[o:o + w, o:o + w] += np.asarray(scene.structure.K)
        K[o:o + w, o:o + w] += np.asarray(_parts(stage, RUN.mean_positions)[2])
        M[o:o + w, o:o + w] += np.asarray(scene.structure.M)
        positions = [np.array([x, 0.0, z]) for x in (0.0, A) for z in (-0.5 * L, 0.5 * L)]
        for (u, kb), p, s in zip(_bearings(scene), positions, _seats(k), strict=True):
            c = R @ np.asarray(ch.seat_positions[s]) + _offset(k)
            G = np.zeros((6, 6))
            G[:3, :3] = G[3:, 3:] = R
            G[:3, 3:] = -_skew(p - c) @ R
            iu = slice(o + u, o + u + 6)
            iq = slice(q0 + 6 * s, q0 + 6 * s + 6)
            K[iu, iq] -= kb @ G
            K[iq, iu] -= G.T @ kb
            K[iq, iq] += G.T @ kb @ G
    out1 = offs[0] + scenes[0].torque_dofs[1]
    in2, out2 = (offs[1] + t for t in scenes[1].torque_dofs)
    for i, j, kt in ((out1, in2, SHAFT), (out2, None, HOLD)):
        K[i, i] += kt
        if j is not None:
            K[j, j] += kt
            K[i, j] -= kt
            K[j, i] -= kt
    return M, K


def _elastic(modes):
    f = np.asarray(modes.analysis.frequency)
    return f[~np.asarray(modes.analysis.rigid)]


def test_two_stages_in_one_housing_match_a_hand_assembly(steel):
    """Both stages' bearings on their seats of one steel box: the housing's coordinates appear
    once (after both stages' own), and the coupled natural frequencies are those of the system
    assembled in this test (1e-8)."""
    housed, grounded, _ = _chains(steel)
    h = steel.K.shape[0]
    names = gb.coordinate_names(housed)
    n1, n2 = (s.scene.structure.size for s in grounded.stages)
    assert len(names) == n1 + n2 + h
    assert names[n1 + n2] == "housing seat0 u_x" and names[-1].startswith("housing mode")
    M, K = _hand_assembly(steel, grounded)
    w2 = sla.eigh(K, M, eigvals_only=True)
    f_ref = np.sqrt(np.maximum(w2, 0.0)) / (2 * math.pi)
    modes = gb.gearbox_coupled_modes(housed, RUN)
    f = np.asarray(modes.analysis.frequency)
    assert f.size == f_ref.size
    keep = f_ref > 1.0
    print("shared housing vs hand assembly: max relative difference",
          np.abs(f[keep] / f_ref[keep] - 1).max(), "; modes", f.size)
    np.testing.assert_allclose(f[keep], f_ref[keep], rtol=1e-8)
    # the kinetic energy: the stages' and the housing's shares make up each mode
    total = np.asarray(modes.stage_energy).sum(axis=0) + np.asarray(modes.housing_energy)
    np.testing.assert_allclose(total[~np.asarray(modes.analysis.rigid)], 1.0, atol=1e-9)
    table = gb.coupled_mode_table(housed, modes)
    assert any(r["type"] == "housing" for r in table)  # the box's own modes are in the band


# default tier: tests/test_gearbox_case_housing.py::test_planar_ring_on_a_stiff_box_is_the_grounded_gearbox (same claim, a planar planetary and a pair in the box)
@pytest.mark.slow
def test_stiff_shared_housing_is_the_grounded_gearbox():
    """The box 100 and 1000 x stiffer than steel (steel's density): the coupled modes below
    5 kHz tend to the grounded gearbox's as the box's compliance (the difference falls about
    tenfold), within 3e-4 at x 1000 (measured 1.7e-4)."""
    grounded = _chains(_condensed(210e9, 7800.0))[1]
    f0 = _elastic(gb.gearbox_coupled_modes(grounded, RUN))
    f0 = f0[f0 < 5000.0]
    errs = []
    for scale in (1e2, 1e3):
        housed = _chains(_condensed(210e9 * scale, 7800.0))[0]
        f = _elastic(gb.gearbox_coupled_modes(housed, RUN))[: f0.size]
        errs.append(np.abs(f / f0 - 1).max())
    print("stiff shared housing: modes below 5 kHz", f0.size, ", max relative difference at "
          "E x 100, x 1000", errs)
    assert errs[0] / errs[1] > 8.0 and errs[1] < 3e-4


# default tier: tests/test_gearbox_case_housing.py::test_file_planetary_ring_seat_carries_the_ring_torque (a housed chain's quasi-static run: mean mesh forces the static ones, the seat's load the torque balance's) and ::test_housing_signals_read_the_housed_file (the pair's bearing forces by hand, their mean the mesh force)
@pytest.mark.slow
def test_shared_housing_run_balances_the_bearing_forces(steel):
    """A Newmark run of the housed gearbox at a low speed (quasi-static: the mesh frequencies
    far below the modes) completes with finite values, each shaft's two bearings carry its
    mesh's force, and the housing feels no net force: the eight bearings' forces (K_b d,
    d = u − G q as in the hand assembly) sum to zero against the mesh forces."""
    housed, grounded, housings = _chains(steel, loss_factor=0.02)
    out = gb.gearbox_dynamics(housed, RUN, 2.0)
    assert int(out.result) == 0
    X = np.asarray(out.displacement)
    assert np.all(np.isfinite(X))
    x = X.mean(axis=0)
    F = np.asarray(out.mesh_forces).mean(axis=0)  # each stage's mesh force (N)
    np.testing.assert_allclose(F, np.asarray(out.static_forces), rtol=1e-3)
    n1, n2 = (s.scene.structure.size for s in grounded.stages)
    q0 = n1 + n2
    total = np.zeros(3)
    for k, stage in enumerate(grounded.stages):
        o = (0, n1)[k]
        positions = [np.array([xx, 0.0, z]) for xx in (0.0, A) for z in (-0.5 * L, 0.5 * L)]
        shafts = [np.zeros(3), np.zeros(3)]
        for b, ((u, kb), p, s) in enumerate(zip(_bearings(stage.scene), positions, _seats(k),
                                                strict=True)):
            G = housings[k].seat_transform(s, p)
            d = x[o + u:o + u + 6] - G @ x[q0 + 6 * s:q0 + 6 * s + 6]
            force = (kb @ d)[:3]
            shafts[b // 2] += force
            total += force
        for f_shaft in shafts:  # each shaft's bearings hold its gear's mesh force
            np.testing.assert_allclose(np.linalg.norm(f_shaft), F[k], rtol=1e-3)
    print("shared housing: net bearing force / mesh force", np.linalg.norm(total) / F.max())
    assert np.linalg.norm(total) < 1e-4 * F.max()


def test_housing_coordinates_have_one_name_on_every_path(steel):
    """The housing's coordinates are named alike by the housing itself
    (``Housing.coordinate_names``), a lumped scene's structure nodes (``"housing <seat>"`` at
    each seat's first coordinate), a housed planetary stage's ``dof_names`` and the coupled
    gearbox's ``coordinate_names``; the spelling checked here word by word."""
    housed, grounded, housings = _chains(steel)
    h = housings[0]
    names = h.coordinate_names()
    n_seats = len(steel.seat_names)
    expected = tuple(f"housing {s} {d}" for s in steel.seat_names
                     for d in ("u_x", "u_y", "u_z", "phi_x", "phi_y", "phi_z"))
    expected += tuple(f"housing mode {k}" for k in range(1, steel.K.shape[0] - 6 * n_seats + 1))
    assert names == expected
    n_own = sum(s.scene.structure.size for s in grounded.stages)
    assert gb.coordinate_names(housed)[n_own:] == names
    st = housed.stages[0].scene.structure
    nodes = {key: first for key, first in st.nodes if key.startswith("housing ")}
    first = st.size - h.size
    assert nodes == {names[6 * k].rsplit(" ", 1)[0]: first + 6 * k for k in range(n_seats)}
    planetary = EX.two_stage()[0].stages[0].stage
    model = jp.TorsionalPlanetary().on(HousingMount.on_axis(h, (("ring", 0),)))
    own = jp.TorsionalPlanetary().dof_names(planetary)
    assert model.dof_names(planetary) == tuple(own) + names


def test_shared_housing_bad_input_one_line(steel):
    housed, grounded, housings = _chains(steel)
    for scene, match in (
        (lambda: _scene(0, housings[0], (8, 1, 2, 3)), r"seats\[0\] = 8"),  # 8 seats: 0..7
        (lambda: _scene(1, housings[0], _seats(1), (0.0, math.nan, 0.0)),
         r"housing_position = \(0.0, nan, 0.0\), allowed 3 finite numbers"),
        (lambda: _scene(1, None, None, _place(1)), r"housing_position = .* without a housing"),
    ):
        with pytest.raises(ValueError, match=match) as err:
            scene()
        assert "\n" not in str(err.value)
    stiffer = dataclasses.replace(steel, K=2.0 * steel.K)
    other = Housing.of(stiffer, rotation=R, offset=_offset(0))
    for chain, match in (
        (lambda: gb.GearboxTorsional(grounded.stages, [SHAFT], housing=housings[0]),
         "no stage sits in it"),
        (lambda: gb.GearboxTorsional(housed.stages, [SHAFT], housing=other),
         "stage 1's mount holds another housing"),
        # stage 2 placed with another housing object (a stiffer box) than the chain's
        (lambda: gb.GearboxTorsional(
            (housed.stages[0], gb.LumpedPairGearboxStage(_scene(1, other, _seats(1),
                                                                _place(1)))),
            [SHAFT], housing=housings[0]), "stage 2's mount holds another housing"),
        (lambda: gb.GearboxTorsional((EX.two_stage()[0].stages[1], housed.stages[1]), [SHAFT],
                                     housing=steel), "housing ="),
    ):
        with pytest.raises(ValueError, match=match) as err:
            chain()
        assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="gearbox_modes: chain.housing"):
        gb.gearbox_modes(housed)


def _same_coupled_matrices(new, old):
    """The coupled structure (M, K_s: the housing once, the seats' couplings, the shafts and
    the hold) and each stage's bearing damping of two chains equal to 1e-12 of their largest
    entry; returns the largest relative difference."""
    worst = 0.0
    pairs = list(zip(gb.GearboxModel(new, RUN).structure_matrices(),
                     gb.GearboxModel(old, RUN).structure_matrices(), strict=True))
    pairs += [(a.speed_terms(0.0)[0], b.speed_terms(0.0)[0])
              for a, b in zip(new.stages, old.stages, strict=True)]
    for a, b in pairs:
        a, b = np.asarray(a), np.asarray(b)
        scale = np.abs(b).max()
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * scale)
        worst = max(worst, float(np.abs(a - b).max() / scale))
    return worst


def test_one_housing_object_is_the_stages_own_copies(steel):
    """The housing placed once in the gearbox frame and both stages' scenes on that one object
    at their places t (``lumped_pair(..., housing_position=t)``): the chain finds it as its
    stages' mounts' one object, and its coupled M and K_s and the stages' bearing damping are
    those of the form before it (each stage on its own copy of the box placed in its own
    frame, accepted with a DeprecationWarning) to 1e-12 of their largest entry: a seat's lever
    depends on p − c alone. The same scene on the shared box without its place differs (the
    comparison can fail)."""
    housed, _, housings = _chains(steel, loss_factor=0.02)
    assert all(s.mount().housing is housed.housing for s in housed.stages)
    copies = tuple(gb.LumpedPairGearboxStage(_scene(k, housings[k], _seats(k)))
                   for k in range(2))
    with pytest.warns(DeprecationWarning, match=r"stage\(s\) 2 mounted on a copy") as rec:
        old = gb.GearboxTorsional(copies, [SHAFT], housing=housings[0])
    assert len(rec) == 1 and "\n" not in str(rec[0].message)
    worst = _same_coupled_matrices(housed, old)
    print("one housing object vs per-stage copies: largest relative difference", worst)
    unplaced = gb.GearboxTorsional(
        (housed.stages[0], gb.LumpedPairGearboxStage(_scene(1, housings[0], _seats(1)))),
        [SHAFT], housing=housings[0])
    k_new, k_off = (np.asarray(gb.GearboxModel(c, RUN).structure_matrices()[1])
                    for c in (housed, unplaced))
    assert np.abs(k_off - k_new).max() > 1e-6 * np.abs(k_new).max()


def test_one_housing_object_with_a_planetary_stage_on_its_axis(planetary_box):
    """The planetary chain in the box placed once in the pair's frame (the gearbox frame here),
    the planetary stage's ring on ``HousingMount.on_axis(housing, seats, centre=t)``, t its
    centre there: the coupled M, K_s and bearing damping are those of each stage on its own
    copy of the box (the planetary's placed in its own frame, deprecated) to 1e-12."""
    _, _, (hp, hl), _ = _planetary_chains(planetary_box, loss_factor=0.02)
    planetary = EX.two_stage()[0].stages[0]
    pair, mesh = PAIRS[1]
    scene = lumped_pair(pair, mesh, _shaft(), _shaft(), masses=MASSES, inertias=INERTIAS,
                        housing=hl, seats=(0, 1, 2, 3))
    lumped = gb.LumpedPairGearboxStage(scene, input=1)

    def chain(housing, centre):
        mount = HousingMount.on_axis(housing, (("ring", RING_SEAT),), centre=centre)
        stage = gb.PlanetaryGearboxStage(planetary.stage, planetary.input, planetary.output,
                                         planetary.meshes, model=jp.TorsionalPlanetary(),
                                         mount=mount)
        return gb.GearboxTorsional((stage, lumped), [SHAFT], housing=hl)

    new = chain(hl, _pair_offset() - _planet_offset())
    assert new.stages[0].mount().housing is new.housing is new.stages[1].mount().housing
    with pytest.warns(DeprecationWarning, match=r"stage\(s\) 1 mounted on a copy"):
        old = chain(hp, (0.0, 0.0, 0.0))
    worst = _same_coupled_matrices(new, old)
    print("planetary on the one housing object vs its own copy: largest relative difference",
          worst)


@pytest.mark.slow
def test_stiff_shared_housing_whine_is_the_grounded_gearbox_whine():
    """The gearbox's whine (:func:`jaxgear.gearbox.gearbox_whine`) with both stages in one box
    1000 x stiffer than steel: each mesh's force orders 1 and 2 at 60 and 150 rad/s are the
    grounded gearbox's within 1e-3 in amplitude and 0.1° in phase (measured 3e-4 and 0.005°:
    the box's compliance, as the modes' 1.7e-4), and the balance stays in its linear regime."""
    grounded = _chains(_condensed(210e9, 7800.0))[1]
    stiff = _chains(_condensed(210e12, 7800.0))[0]
    method = QuasiPeriodicBalance(6, 1)
    out = [gb.gearbox_whine(ch, RUN, [60.0, 150.0], method=method, positions=32)
           for ch in (grounded, stiff)]
    for w in out:
        assert not np.any(np.asarray(w.contact_loss))
        assert np.all(np.asarray(w.nonlinearity) < 1e-6)
    g = np.asarray(out[0].order_group)
    o = np.asarray(out[0].group_order)
    for mesh in range(2):
        cols = [int(np.flatnonzero((g == out[0].mesh_group[mesh]) & (o == h))[0]) for h in (1, 2)]
        a, b = (np.asarray(w.mesh_force)[:, cols, mesh] for w in out)
        np.testing.assert_allclose(np.abs(b), np.abs(a), rtol=1e-3)
        assert np.abs(np.angle(b / a, deg=True)).max() < 0.1


# -- a planetary stage in the shared housing -------------------------------------------------
# The NREL-like chain: the planetary stage of examples/gearbox_two_stage.py (ring held, carrier
# in, sun out; 4 planets on contact cells) whose sun drives the 36-tooth wheel of the lumped
# 20/36 pair through a shaft. One box: the pair's four bearings on seats 0..3 (bores round its
# two axes in both end walls, at height Z2) and the ring's flange bolted round a bore of its own
# in the x- wall (seat 4, "seat4", at height Z_RING), the planetary stage ahead of that wall.
X_PLANET = -0.06  # the planetary stage's plane along the box's x (housing frame, m)
Z_RING, R_RING = 0.08, 0.05  # the ring's bore: its height and radius (m)
RING_SEAT = 4
P_TORQUE = 2000.0  # on the carrier (N m)


def _planetary_box(E, cutoff_hz=8000.0):
    W, H, Lb = A + 2 * Y0, Z2 + 0.07, L + T_WALL
    bores = tuple(Bore(w, (Y0 + dy, Z2), 0.025) for dy in (0.0, A) for w in ("x-", "x+"))
    bores += (Bore("x-", (0.5 * W, Z_RING), R_RING),)
    f = 0.03
    feet = tuple(Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, Lb - f) for y0 in (0.0, W - f))
    box = HousingBox(Lb, W, H, T_WALL, bores=bores, feet=feet)
    ph = prepare_housing(mesh_box(box, 0.05, element=Tet4()), fem_prep.Material(E, 0.3, 7800.0),
                         cutoff_hz)
    return ph.condensed_housing()


def _planet_offset():
    """The planetary stage's frame (its axis scene z, its centre the origin) from the box's."""
    return -R @ np.array([X_PLANET, 0.5 * (A + 2 * Y0), Z_RING])


def _pair_offset():
    return -R @ np.array([0.5 * (L + T_WALL), Y0, Z2])


def _planetary_chains(ch, loss_factor=0.0, ring_seat="seat4", **run):
    """(the chain in one box, placed once in the gearbox frame (the planetary's: its centre the
    origin) with the pair's scene on that object at its place there, the grounded chain, the
    housings placed in the planetary's (the shared one) and the pair's frames, the run)."""
    hp = Housing.of(ch, loss_factor=loss_factor, rotation=R, offset=_planet_offset())
    hl = Housing.of(ch, loss_factor=loss_factor, rotation=R, offset=_pair_offset())
    planetary = EX.two_stage()[0].stages[0]
    mount = HousingMount.on_axis(hp, (("ring", ring_seat),))
    housed_p = gb.PlanetaryGearboxStage(planetary.stage, planetary.input, planetary.output,
                                        planetary.meshes, model=jp.TorsionalPlanetary(),
                                        mount=mount)
    pair, mesh = PAIRS[1]
    place = _planet_offset() - _pair_offset()  # the pair's scene origin in the gearbox frame
    scenes = [lumped_pair(pair, mesh, _shaft(), _shaft(), masses=MASSES, inertias=INERTIAS,
                          housing=h, seats=s, housing_position=t)
              for h, s, t in ((hp, (0, 1, 2, 3), place), (None, None, None))]
    housed = gb.GearboxTorsional((housed_p, gb.LumpedPairGearboxStage(scenes[0], input=1)),
                                 [SHAFT], housing=hp)
    grounded = gb.GearboxTorsional((planetary, gb.LumpedPairGearboxStage(scenes[1], input=1)),
                                   [SHAFT])
    opts = {"steps_per_period": 16, "periods": 6, "keep_periods": 2} | run
    return housed, grounded, (hp, hl), gb.GearboxRun(P_TORQUE, HOLD, **opts)


@pytest.fixture(scope="module")
def planetary_box():
    return _planetary_box(210e9)  # steel; 10 interior modes kept (to 8 kHz)


def _planetary_hand_assembly(ch, grounded, run):
    """(M, K + K̄_m) of the planetary chain in the box, written out here: the planetary stage's
    matrices with its ring's torsional spring taken off (the grounded stage's parts, ring free),
    that spring k_t put on θ_r − θ_seat, θ_seat the ring seat's rotation about the stage axis
    (scene z: R's last row on the seat's rotations); the grounded pair's structure and mean mesh
    stiffness with each bearing's ½ dᵀ K_b d, d = u − G q (as :func:`_hand_assembly`); the box's
    K and M once; the shaft sun–wheel and the hold on the pinion."""
    planetary, pair = grounded.stages
    free = eqx.tree_at(lambda s: s.stage.ring.torsional_stiffness, planetary, jnp.asarray(0.0))
    mp, kp, kmp, _ = (np.asarray(a) for a in _parts(free, run.mean_positions))
    scene = pair.scene
    n1, n2, h = mp.shape[0], scene.structure.size, ch.K.shape[0]
    n = n1 + n2 + h
    q0 = n1 + n2
    K, M = np.zeros((n, n)), np.zeros((n, n))
    K[:n1, :n1] = kp + kmp
    M[:n1, :n1] = mp
    o = slice(n1, n1 + n2)
    K[o, o] = np.asarray(scene.structure.K) + np.asarray(_parts(pair, run.mean_positions)[2])
    M[o, o] = np.asarray(scene.structure.M)
    K[q0:, q0:] = ch.K
    M[q0:, q0:] = ch.M
    names = planetary.coordinates()
    a = np.zeros(n)
    a[names.index("theta_r")] = 1.0
    a[q0 + 6 * RING_SEAT + 3:q0 + 6 * RING_SEAT + 6] = -R[2]
    K += float(planetary.stage.ring.torsional_stiffness) * np.outer(a, a)
    positions = [np.array([x, 0.0, z]) for x in (0.0, A) for z in (-0.5 * L, 0.5 * L)]
    for (u, kb), p, s in zip(_bearings(scene), positions, range(4), strict=True):
        c = R @ np.asarray(ch.seat_positions[s]) + _pair_offset()
        G = np.zeros((6, 6))
        G[:3, :3] = G[3:, 3:] = R
        G[:3, 3:] = -_skew(p - c) @ R
        iu = slice(n1 + u, n1 + u + 6)
        iq = slice(q0 + 6 * s, q0 + 6 * s + 6)
        K[iu, iq] -= kb @ G
        K[iq, iu] -= G.T @ kb
        K[iq, iq] += G.T @ kb @ G
    sun = names.index("theta_s")
    wheel, pinion = n1 + scene.torque_dofs[1], n1 + scene.torque_dofs[0]
    b = np.zeros((2, n))
    b[0, sun], b[0, wheel] = 1.0, -1.0
    b[1, pinion] = 1.0
    K += b.T @ np.diag([SHAFT, HOLD]) @ b
    return M, K


# default tier: tests/test_gearbox_housing.py::test_two_stages_in_one_housing_match_a_hand_assembly (the shared box against a hand assembly, the pairs' seats); the ring's mount in a run: tests/test_gearbox_case_housing.py::test_file_planetary_ring_seat_carries_the_ring_torque
@pytest.mark.slow
def test_planetary_ring_in_the_shared_housing_matches_a_hand_assembly(planetary_box):
    """The planetary stage's ring on its own seat of the box the lumped pair's bearings sit in
    (seat given by name): the housing's coordinates once, after both stages' own, and the
    coupled natural frequencies those of the system assembled in this test within 1e-9
    (measured 2.3e-12); the kinetic shares (stages + housing) sum to 1."""
    housed, grounded, _, run = _planetary_chains(planetary_box)
    h = planetary_box.K.shape[0]
    n1 = len(grounded.stages[0].coordinates())
    n2 = grounded.stages[1].scene.structure.size
    names = gb.coordinate_names(housed)
    assert len(names) == n1 + n2 + h
    assert names[n1 + n2 + 6 * RING_SEAT + 5] == "housing seat4 phi_z"
    assert housed.stages[0].housing_seats() == (RING_SEAT,)
    assert housed.stages[1].housing_seats() == (0, 1, 2, 3)
    M, K = _planetary_hand_assembly(planetary_box, grounded, run)
    f_ref = np.sqrt(np.maximum(sla.eigh(K, M, eigvals_only=True), 0.0)) / (2 * math.pi)
    modes = gb.gearbox_coupled_modes(housed, run)
    f = np.asarray(modes.analysis.frequency)
    assert f.size == f_ref.size
    print("planetary in the shared housing vs hand assembly: max relative difference",
          np.abs(f / f_ref - 1).max(), "; modes", f.size, "; lowest", f[:3])
    np.testing.assert_allclose(f, f_ref, rtol=1e-9)
    total = np.asarray(modes.stage_energy).sum(axis=0) + np.asarray(modes.housing_energy)
    np.testing.assert_allclose(total, 1.0, atol=1e-9)


# default tier: tests/test_gearbox_case_housing.py::test_planar_ring_on_a_stiff_box_is_the_grounded_gearbox (same claim, planar kind)
@pytest.mark.slow
def test_stiff_box_with_a_planetary_ring_is_the_grounded_gearbox(planetary_box):
    """The box 1000 and 10 000 x stiffer than steel (steel's density): the coupled modes below
    5 kHz tend to those of the gearbox whose ring is held by its torsional spring to the ground
    and whose pair's bearings are grounded, as the box's compliance (the difference falls about
    tenfold), within 2e-3 at x 10 000 (measured 1.0e-2 and 1.0e-3). The ring's spring
    (1e9 N m/rad, a held ring) is far stiffer than the 100 mm bore's twist in a 10 mm steel wall
    (about 4π G t r² = 2.5e7 N m/rad), so that the modes in which the ring turns on its seat
    are the last to come to the grounded ones."""
    _, grounded, _, run = _planetary_chains(planetary_box)
    f0 = _elastic(gb.gearbox_coupled_modes(grounded, run))
    f0 = f0[f0 < 5000.0]
    errs = []
    for scale in (1e3, 1e4):
        housed = _planetary_chains(_planetary_box(210e9 * scale, 8000.0 * math.sqrt(scale)))[0]
        f = _elastic(gb.gearbox_coupled_modes(housed, run))[: f0.size]
        errs.append(np.abs(f / f0 - 1).max())
    print("stiff box with the planetary ring: modes below 5 kHz", f0.size,
          ", max relative difference at E x 1000, x 10 000", errs)
    assert errs[0] / errs[1] > 8.0 and errs[1] < 2e-3


# default tier: tests/test_gearbox_case_housing.py::test_file_planetary_ring_seat_carries_the_ring_torque (same claim, file-built, 1e-3)
@pytest.mark.slow
def test_planetary_ring_seat_carries_the_ring_torque(planetary_box):
    """A Newmark run (``gearbox_dynamics``) of the chain in the box (2 % loss factor) at a
    carrier speed of 2 rad/s (quasi-static: the mesh frequencies far below the modes): it
    completes, each mesh's mean force is its static force (1e-3), and over the recorded window
    the box's own elastic moment at the ring's seat, about the stage axis ((K_h q) at the seat's
    rotations, R's last row), is the ring's torque from the torque balance of the stage,
    T_c r_br / (r_bs + r_br) (Willis), within 1e-4, equal to the ring spring's
    k_t (θ_r − θ_seat); the seat's other force and moment components stay below 1e-4 of it
    (measured 2.8e-5, 4.4e-8 and 2.8e-5: the window's dynamic residue)."""
    housed, _, _, run = _planetary_chains(planetary_box, loss_factor=0.02)
    out = gb.gearbox_dynamics(housed, run, 2.0)
    assert int(out.result) == 0
    X = np.asarray(out.displacement)
    assert np.all(np.isfinite(X))
    np.testing.assert_allclose(np.asarray(out.mesh_forces).mean(axis=0),
                               np.asarray(out.static_forces), rtol=1e-3)
    _ring_torque_check(housed, planetary_box, X.mean(axis=0), 1e-4)


def _ring_torque_check(housed, ch, x, rtol):
    names = gb.coordinate_names(housed)
    q0 = len(names) - ch.K.shape[0]
    q = x[q0:]
    seat = (np.asarray(ch.K) @ q)[6 * RING_SEAT:6 * RING_SEAT + 6]
    moment = float(R[2] @ seat[3:])
    st = housed.stages[0].stage
    r_s, r_r = float(st.sun.base_radius), float(st.ring.base_radius)
    expected = P_TORQUE * r_r / (r_s + r_r)
    theta_seat = float(R[2] @ q[6 * RING_SEAT + 3:6 * RING_SEAT + 6])
    spring = float(st.ring.torsional_stiffness) * (x[names.index("1:theta_r")] - theta_seat)
    print("ring seat moment", moment, "ring spring", spring, "ring torque", expected)
    np.testing.assert_allclose(abs(moment), expected, rtol=rtol)
    np.testing.assert_allclose(moment, spring, rtol=rtol)
    rest = np.concatenate([seat[:3], seat[3:] - moment * R[2]])
    assert np.abs(rest).max() < rtol * expected


@pytest.mark.slow
def test_planetary_ring_in_the_shared_housing_whine_against_newmark(planetary_box):
    """``gearbox_whine`` on the chain in the box (QuasiPeriodicBalance(8, 1), 144 positions per
    mesh period of each stage) at a carrier speed of 2.5 rad/s (planetary mesh 31.8 Hz, pair
    71.6 Hz: 80 and 180 carrier-speed units, 4 planetary periods hold 9 of the pair's; the
    lowest coupled mode, the output hold's, at 108 Hz): no contact loss; its quasi-static mean
    puts the ring's torque on the ring seat to 1e-9; each mesh's order 1 is Newmark's
    (``gearbox_dynamics``, 256 steps per pair period, the last 8 planetary periods of 16)
    within 1.5 % and 1° (measured: the planetary meshes' 0.7 % and 0.35°, their order 1 only
    2e-4 of their static force; the pair's 0.05 % and 0.01°; at 72 positions the planetary
    meshes' were 5.5 % and 3.4° off, the sampled engagement of their unrelieved cells). (At
    10 rad/s the ring meshes lose contact in Newmark: the planetary mesh's order 4, 509 Hz,
    meets the 495 Hz mode in which the ring turns on its seat.)"""
    housed, _, _, run = _planetary_chains(planetary_box, steps_per_period=256, periods=16,
                                          keep_periods=8)
    speed = 2.5
    w = gb.gearbox_whine(housed, run, speed, QuasiPeriodicBalance(8, 1), positions=144)
    assert not np.any(np.asarray(w.contact_loss))
    _ring_torque_check(housed, planetary_box, np.real(np.asarray(w.quasi_static)[0]), 1e-9)
    r = gb.gearbox_dynamics(housed, run, speed)
    assert int(r.result) == 0 and float(np.min(np.asarray(r.mesh_forces))) > 0.0
    t, f = np.asarray(r.time), np.asarray(r.mesh_forces)
    w1 = 2 * math.pi * float(w.frequency[0])
    g, o = np.asarray(w.order_group), np.asarray(w.group_order)
    worst = [0.0, 0.0]
    for mesh in range(9):
        j = int(np.flatnonzero((g == w.mesh_group[mesh]) & (o == 1))[0])
        ref = 2 * np.mean(f[:, mesh] * np.exp(-1j * float(w.orders[j]) * w1 * t))
        got = complex(w.mesh_force[0, j, mesh])
        worst = [max(worst[0], abs(abs(got) / abs(ref) - 1)),
                 max(worst[1], abs(math.degrees(np.angle(got / ref))))]
    print("planetary in the shared housing, whine vs Newmark order 1: amplitude, phase", worst)
    assert worst[0] < 0.015 and worst[1] < 1.0


def test_planetary_ring_in_the_shared_housing_bad_input_one_line(planetary_box):
    hp = Housing.of(planetary_box, rotation=R, offset=_planet_offset())
    with pytest.raises(ValueError, match="seat of ring = 'bore9'") as err:
        HousingMount.on_axis(hp, (("ring", "bore9"),))
    assert "\n" not in str(err.value)
    # the ring on seat 0, which the pair's pinion bearing holds already
    with pytest.raises(ValueError, match="seat 'seat0' .* used twice") as err:
        _planetary_chains(planetary_box, ring_seat="seat0")
    assert "\n" not in str(err.value)
    planetary = EX.two_stage()[0].stages[0]
    star = HousingMount.on_axis(hp, (("ring", 4),), fixed_frame=True)
    with pytest.raises(ValueError, match="joins every support") as err:
        gb.PlanetaryGearboxStage(planetary.stage, planetary.input, planetary.output,
                                 planetary.meshes, model=jp.TorsionalPlanetary(), mount=star)
    assert "\n" not in str(err.value)
