"""A scene placed in a housing (docs/housing.md, "A scene placed in a housing"): every scene kind
that declares ``takes_housing`` takes the housing alike, ``housing=``, ``seats=`` and
``housing_position=t`` (m, the scene origin in the frame the housing is placed in), with the
same refusals: the lumped 3D pair, the lumped 3D train, the hybrid pair and the hybrid train.

Reference (written here): a seat's lever depends on p + t − c alone (p a bearing in the scene
frame, c its seat's centre), so the scene at t in a housing whose seat centres are moved by t by
hand couples as the scene at 0 in the housing as it is: the assembled M, K, bearing damping and
bearing-force rows equal to 1e-12 of their largest entry, and the bearings on the same seats.
The scene at 0 in the moved housing differs (the placement is not ignored). A t that carries
the bearings elsewhere seats them on the seats nearest p + t (found here from the seat centres):
no refusal, as a housing built round other bearings would seat them. A bad t is one line, before
any work.

The housing is written here: random symmetric positive K and M (one seat per bearing, a few
modal coordinates), its seats 2-8 mm off the bearings and turned from the scene frame, so every
lever and the rotation count."""

import dataclasses
import math
import pathlib

import numpy as np
import pytest

import fem_prep
import jaxgear.io as jio
from jaxgear.scenes import Housing, hybrid_pair, lumped_pair

DATA = pathlib.Path(__file__).parent / "data"
T = np.array([0.031, -0.047, 0.012])  # the scene origin's place (m)
MASSES, INERTIAS = (0.3, 1.0), ((1e-4, 2e-4), (1e-3, 1e-3))


def _rotation(axis, angle):
    """Rodrigues' rotation matrix about ``axis`` by ``angle`` (rad)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _housing(points, seed=0, modes=4):
    """A housing with a seat 2-8 mm off each of ``points`` (m, scene frame), random K and M."""
    rng = np.random.default_rng(seed)
    h = 6 * len(points) + modes
    a = rng.standard_normal((h, h))
    K = 1e8 * (a @ a.T / h + np.eye(h))
    b = rng.standard_normal((h, h))
    M = b @ b.T / h + np.eye(h)
    seats = [np.asarray(p) + rng.uniform(0.002, 0.008, 3) * rng.choice((-1, 1), 3)
             for p in points]
    R = _rotation((1.0, 2.0, 0.5), 0.8)
    return Housing(K=K, M=M, C=1e-5 * K,
                   seat_positions=tuple(tuple(float(x) for x in c) for c in seats),
                   rotation=tuple(tuple(float(x) for x in r) for r in R),
                   seat_names=tuple(f"s{k}" for k in range(len(points))))


def _moved(housing, t):
    """``housing`` with every seat centre moved by ``t`` by hand (nothing else changed)."""
    return dataclasses.replace(housing, seat_positions=tuple(
        tuple(float(x) for x in np.asarray(c) + t) for c in housing.seat_positions))


def _points(case, shafts, centres, gear_z):
    """Each bearing's scene position (m), shaft after shaft: shaft i's axis along +z through
    ``centres[i]``, its gear at z = 0 (a bearing at s along the shaft at z = s − gear_z[i])."""
    return [np.array([c[0], c[1], b.z - g]) for sh, c, g in zip(shafts, centres, gear_z,
                                                                   strict=True)
            for b in sh.bearings]


@pytest.fixture(scope="module")
def pair_case(fem_prep_cache):
    return jio.load_case(DATA / "hybrid-test-case.toml")


@pytest.fixture(scope="module")
def train_case(fem_prep_cache):
    return jio.load_case(DATA / "hybrid-test-train.toml")


@pytest.fixture(scope="module")
def body(fem_prep_cache):
    return fem_prep.condensed(DATA / "hybrid-test-wheel.toml")


def _pair_points(case):
    s = case.scene
    shafts = (s.pinion_shaft, s.gear_shaft)
    a = case.pair.center_distance
    return _points(case, shafts, ((0.0, 0.0), (a, 0.0)), [sh.gear_positions[0] for sh in shafts])


def _train_points(case):
    shafts = case.scene.shafts
    centres = np.asarray(case.layout().centres)[[case.shaft_of.index(i)
                                                 for i in range(len(shafts))]]
    return _points(case, shafts, centres, [sh.gear_positions[0] for sh in shafts])


@pytest.fixture(scope="module")
def builders(pair_case, train_case, body):
    """Each builder as (name, the bearings' scene positions, build(housing, seats, t)): the
    lumped pair, the hybrid pair, the lumped train, the hybrid train."""
    s = pair_case.scene
    rigid_train = train_case.replace(scene=dataclasses.replace(train_case.scene,
                                                               gear_bodies=()))
    meshes = (pair_case.mesh_model(), pair_case.mesh_model(flexible=(False, True)))

    def pair(bodies):
        def build(housing, seats, t):
            if bodies is None:
                return lumped_pair(pair_case.pair, meshes[0], s.pinion_shaft, s.gear_shaft,
                                   masses=MASSES, inertias=INERTIAS, housing=housing,
                                   seats=seats, housing_position=t)
            return hybrid_pair(pair_case.pair, meshes[1], s.pinion_shaft, s.gear_shaft,
                               bodies=bodies, masses=MASSES, inertias=INERTIAS,
                               housing=housing, seats=seats, housing_position=t)
        return build

    return (
        ("lumped pair", _pair_points(pair_case), pair(None)),
        ("hybrid pair", _pair_points(pair_case), pair((None, body))),
        ("lumped train", _train_points(train_case),
         lambda h, s_, t: rigid_train.lumped_train(housing=h, seats=s_, housing_position=t)),
        ("hybrid train", _train_points(train_case),
         lambda h, s_, t: train_case.hybrid_train((None, body, None), housing=h, seats=s_,
                                                  housing_position=t)),
    )


def _arrays(scene):
    st = scene.structure
    return {"M": st.M, "K": st.K, "C_bearing": st.C_bearing, "reaction": st.reaction}


def _seats(scene):
    return [j.seat for j in scene.structure.mount.joints]


def test_a_scene_at_t_in_the_moved_housing_couples_as_at_0(builders):
    """Each builder: the scene at t in the housing whose seats are moved by t (by hand) equals
    the scene at 0 in the housing as it is (M, K, C_bearing and the bearing-force rows to 1e-12
    of their largest entry; the nearest seats, a lumped scene's given seats with one bearing
    on the ground too), each joint at its bearing plus t. The lumped scenes at 0 in the moved
    housing differ by more than 1e-6 (the seats' move is seen: with the joints at p + t, a
    placement dropped would fail the comparison)."""
    for name, points, build in builders:
        housing = _housing(points)
        moved = _moved(housing, T)
        given = [None] + list(range(len(points) - 1))[::-1]  # the first bearing grounded
        lumped = name.startswith("lumped")
        for seats in (None, given) if lumped else (None,):
            ref, placed = build(housing, seats, None), build(moved, seats, T)
            assert _seats(placed) == _seats(ref) == (
                list(range(len(points))) if seats is None else given[1:]), name
            joints = placed.structure.mount.joints
            grounded = 0 if seats is None else 1
            np.testing.assert_allclose([j.point for j in joints],
                                       np.array(points[grounded:]) + T, rtol=0, atol=1e-15)
            for key, a in _arrays(ref).items():
                a, b = np.asarray(a), np.asarray(_arrays(placed)[key])
                np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.abs(a).max(),
                                           err_msg=f"{name} {key}")
        if lumped:
            unplaced = np.asarray(build(moved, None, None).structure.K)
            K = np.asarray(build(housing, None, None).structure.K)
            assert np.abs(unplaced - K).max() > 1e-6 * np.abs(K).max(), name


def test_a_place_far_from_the_seats_takes_the_nearest_ones(builders, pair_case):
    """t of one centre distance along x carries the pinion's (the input's) bearings onto the
    gear's (the idler's) seats: each bearing joins the seat nearest p + t (found here from the
    seat centres), as couple_housing seats every bearing; the structure is the one at 0 on those
    seats given by hand, in the housing moved by −t."""
    for name, points, build in builders[::2]:  # the lumped ones
        housing = _housing(points)
        a = pair_case.pair.center_distance
        t = np.array([a, 0.0, 0.0])
        centres = np.asarray(housing.seat_positions)
        nearest = [int(np.argmin(np.linalg.norm(centres - (p + t), axis=1))) for p in points]
        far = build(housing, None, t)
        assert _seats(far) == nearest != list(range(len(points))), name
        ref = build(_moved(housing, -t), nearest, None)
        for key, x in _arrays(ref).items():
            x = np.asarray(x)
            np.testing.assert_allclose(np.asarray(_arrays(far)[key]), x, rtol=0,
                                       atol=1e-12 * np.abs(x).max(), err_msg=f"{name} {key}")


@pytest.mark.parametrize("t,match", [
    ((0.0, math.nan, 0.0), r"housing_position = \(0.0, nan, 0.0\), allowed 3 finite numbers"),
    ((0.0, math.inf, 0.0), r"housing_position = \(0.0, inf, 0.0\), allowed 3 finite numbers"),
    ((0.1, 0.2), r"housing_position = \(0.1, 0.2\), allowed 3 finite numbers"),
    ("far", r"housing_position = 'far', allowed 3 finite numbers"),
])
def test_bad_places_one_line_from_every_builder(builders, t, match):
    """A t that is not 3 finite numbers, and a t without a housing: one line naming the
    builder and the value, raised before the scene is assembled (the check is the builders'
    one, :func:`jaxgear.scenes.lumped_pair`'s)."""
    for name, points, build in builders:
        housing = _housing(points)
        for h, pattern in ((housing, match), (None, r"housing_position = .* without a housing")):
            with pytest.raises(ValueError, match=pattern) as err:
                build(h, None, t)
            assert "\n" not in str(err.value), name
