"""The housing mount (jaxgear.scenes.HousingMount): its seat coupling against a seat spring
assembled here from the rigid-body motion of the seat (cross products, not the module's lever
matrix), its one-line refusals, and a case's ``[housing]`` refused at load for a kind that
does not declare ``takes_housing``."""

import math

import jax.numpy as jnp
import numpy as np
import pytest
from _housing import HOUSING_BOX

import jaxgear.io as jio
from jaxgear.dynamics import AbstractDynamicModel, AbstractStage, DynamicModel, HybridModel
from jaxgear.gearbox import GearboxModel
from jaxgear.planetary import PlanetaryModel
from jaxgear.scenes import (
    Housing,
    HousingMount,
    HybridScene,
    LumpedPair,
    LumpedTrain,
    MountJoint,
    RelativeApproach,
    TorsionalDynamics,
    TorsionalTrain,
)


def _rotation(axis, angle):
    """Rodrigues' rotation matrix about the unit ``axis`` by ``angle`` (rad)."""
    k = np.asarray(axis, float) / np.linalg.norm(axis)
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def _housing(rng, seats=2, modes=3, rotation=None):
    h = 6 * seats + modes
    a = rng.standard_normal((h, h))
    K = a @ a.T + h * np.eye(h)
    M = np.eye(h) * 2.0
    R = np.eye(3) if rotation is None else rotation
    return Housing(K=K, M=M, C=0.01 * K, seat_positions=tuple(
        tuple(float(x) for x in rng.standard_normal(3)) for _ in range(seats)),
        rotation=tuple(tuple(float(x) for x in r) for r in R),
        seat_names=tuple(f"s{k}" for k in range(seats)))


def _seat_motion(R, c, p):
    """G (6, 6): column j the scene-frame motion (translation, rotation vector) of the point p
    rigidly attached to a seat of centre c for a unit j-th seat coordinate (housing frame):
    a unit translation e_j moves p by R e_j; a unit rotation e_j turns it by R e_j and moves p
    by (R e_j) × (p − c)."""
    G = np.zeros((6, 6))
    for j in range(3):
        e = R[:, j]
        G[:3, j] = e
        G[3:, 3 + j] = e
        G[:3, 3 + j] = np.cross(e, np.asarray(p) - np.asarray(c))
    return G


def _turn(phi):
    """Q(φ) (6, 6): the rotation by φ about +z on a translation and a rotation vector."""
    c, s = math.cos(phi), math.sin(phi)
    r = np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])
    out = np.zeros((6, 6))
    out[:3, :3] = r
    out[3:, 3:] = r
    return out


@pytest.mark.parametrize("rows,frame", [((0, 1, 2, 3, 4, 5), 0.0), ((0, 1, 2, 3, 4, 5), 0.7),
                                        ((2, 5), 0.3)])
def test_coupling_is_the_seat_spring_of_the_relative_motion(rows, frame):
    """One joint on seat 1 of a turned housing: the mount's coupling is the Hessian of
    ½ dᵀ P K_b P d, d = T x − Q(φ)ᵀ G q (q seat 1's six coordinates, the rest of the housing's
    free), assembled here as Jᵀ P K_b P J with J = [T, −Q(φ)ᵀ G S]; to 1e-12 of its largest
    entry. Without the member's block (member=False) only T's block is left out."""
    rng = np.random.default_rng(3)
    R = _rotation((1.0, -2.0, 0.5), 0.9)
    housing = _housing(rng, rotation=R)
    n, h = 7, housing.size
    point = (0.12, -0.05, 0.31)
    mount = HousingMount(housing, (MountJoint("node", 1, point, rows, frame),))
    T = rng.standard_normal((6, n))
    a = rng.standard_normal((6, 6))
    kb = a @ a.T + np.eye(6)
    got = mount.coupling([T], [kb])

    G = _turn(frame).T @ _seat_motion(R, housing.seat_positions[1], point)
    S = np.zeros((6, h))
    S[:, 6:12] = np.eye(6)
    J = np.hstack([T, -G @ S])
    P = np.diag([1.0 if r in rows else 0.0 for r in range(6)])
    want = J.T @ P @ kb @ P @ J
    scale = np.abs(want).max()
    assert isinstance(got, np.ndarray) and got.shape == (n + h, n + h)
    np.testing.assert_allclose(got, want, rtol=0, atol=1e-12 * scale)
    bare = mount.coupling([T], [kb], member=False)
    want[:n, :n] = 0.0
    np.testing.assert_allclose(bare, want, rtol=0, atol=1e-12 * scale)


def test_two_joints_on_one_seat_add_and_jax_springs_give_the_same():
    """Two joints on one seat (a seat name and an index): the coupling is the sum of each
    alone; a JAX spring gives the NumPy result (to 1e-12)."""
    rng = np.random.default_rng(5)
    housing = _housing(rng, seats=1, modes=0)
    n = 4
    T1, T2 = rng.standard_normal((6, n)), rng.standard_normal((6, n))
    k1, k2 = np.diag(rng.uniform(1, 2, 6)), np.diag(rng.uniform(1, 2, 6))
    j1 = MountJoint("a", "s0", (0.1, 0.0, 0.0))
    j2 = MountJoint("b", 0, (0.0, 0.2, 0.0), frame=0.4)
    both = HousingMount(housing, (j1, j2)).coupling([T1, T2], [k1, k2])
    one = HousingMount(housing, (j1,)).coupling([T1], [k1])
    two = HousingMount(housing, (j2,)).coupling([T2], [k2])
    np.testing.assert_allclose(both, one + two, rtol=0, atol=1e-12 * np.abs(both).max())
    traced = HousingMount(housing, (j1, j2)).coupling([jnp.asarray(T1), T2],
                                                      [jnp.asarray(k1), k2])
    np.testing.assert_allclose(np.asarray(traced), both, rtol=0,
                               atol=1e-12 * np.abs(both).max())
    assert HousingMount(housing, (j1, j2)).seats() == (0,)
    assert HousingMount(housing, (j1, j2)).fixed_frame
    assert not HousingMount.on_axis(housing, (("ring", 0),)).fixed_frame
    assert HousingMount.on_axis(housing, (("ring", 0),)).joints[0].rows == (2, 5)
    # the seats a member holds alone: declared by on_axis's members, not by a bearing's joint
    assert HousingMount(housing, (j1, j2)).own_seats() == ()
    assert HousingMount.on_axis(housing, (("ring", "s0"),)).own_seats() == (("ring", 0),)


@pytest.mark.parametrize("make,match", [
    (lambda h: HousingMount(h, (MountJoint("a", 2),)), r"seat of a = 2, allowed a seat index 0 to 1"),
    (lambda h: HousingMount(h, (MountJoint("a", "nope"),)), r"seat of a = 'nope', allowed a seat"),
    (lambda h: HousingMount(h, (MountJoint("a", 0), MountJoint("a", 1))), r"joined twice"),
    (lambda h: HousingMount(h, ("a",)), r"joints\[0\] = .*allowed a jaxgear.scenes.MountJoint"),
    (lambda h: MountJoint("a", 0, rows=(5, 2)), r"rows = \(5, 2\), allowed distinct ascending"),
    (lambda h: MountJoint("a", 0, point=(0.0, math.nan, 0.0)), r"point = .*allowed 3 finite"),
])
def test_bad_mounts_one_line(make, match):
    housing = _housing(np.random.default_rng(0), seats=2, modes=0)
    with pytest.raises(ValueError, match=match) as e:
        make(housing)
    assert "\n" not in str(e.value)


def test_own_seat_not_a_bool_one_line():
    with pytest.raises(TypeError, match=r"own_seat = 1, allowed True or False") as e:
        MountJoint("a", 0, own_seat=1)
    assert "\n" not in str(e.value)


@pytest.mark.parametrize("scene,kind", [("", "TorsionalDynamics"),
                                        ('[scene]\nmodel = "torsional"\n', "TorsionalDynamics"),
                                        ('[scene]\nreduction = "relative"\n', "RelativeApproach")])
def test_a_housing_for_a_kind_that_takes_none_is_refused_at_load(tmp_path, scene, kind):
    """A case's ``[housing]`` on a pair whose scene kind does not declare ``takes_housing``
    (no [scene]: the torsional default; a torsional scene; its relative approach) is refused
    at load, in one line naming the kind; the kinds' declarations are the ones the reader
    reads (the lumped and hybrid scenes, the dynamic models that carry them, the planetary
    model and the gearbox declare it; the torsional scenes and the stage contract's default
    do not)."""
    text = jio.embedded_case_text("accessory-spur")
    path = tmp_path / "case.toml"
    path.write_text(text[: text.index("[scene]")] + scene + HOUSING_BOX + "cutoff_Hz = 2000.0\n")
    with pytest.raises(ValueError, match=rf"^\[housing\]: the scene kind {kind} takes no "
                                         r"housing .*allowed with \[scene\] model = "
                                         r"'lumped3d'") as e:
        jio.load_case(path)
    assert "\n" not in str(e.value)
    assert [k.takes_housing for k in (LumpedPair, LumpedTrain, HybridScene, TorsionalDynamics,
                                      TorsionalTrain, RelativeApproach)] == [True] * 3 + [False] * 3
    assert [k.takes_housing for k in (DynamicModel, HybridModel, PlanetaryModel, GearboxModel,
                                      AbstractStage, AbstractDynamicModel)] == [True] * 4 + [False] * 2
