"""Rolling bearings from their geometry in the lumped 3D scenes: ``scenes.Bearing(rolling=)`` at
an operating point, the fixed point of the bearings' loads
(:func:`jaxgear.dynamics.bearings_at_operating_point`) and the case files' bearing keys
(``catalogue``, ``kind``), against statics by hand and the bearing package called directly."""

from __future__ import annotations

import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear import bearings as jb
from jaxgear.dynamics import bearings_at_operating_point
from jaxgear.io import build_dynamic_model, operating_point
from jaxgear.scenes import Bearing, ShaftSpec, lumped_pair

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "accessory-lumped3d-rolling.toml"
LINEAR = ROOT / "examples" / "accessory-lumped3d.toml"

#: the shaft of the statics check: 100 mm long, 25 mm (a 6205's bore), the pinion at 30 mm
L, A, TORQUE = 0.100, 0.030, 80.0
CLEARANCE = 10e-6


def _involute(a):
    return math.tan(a) - a


def _working_pressure_angle(alpha, x_sum, z_sum):
    """α_w of a spur pair without backlash: inv α_w = inv α + 2 tan α (x1 + x2)/(z1 + z2), by
    bisection (written here, not the package's)."""
    target = _involute(alpha) + 2.0 * math.tan(alpha) * x_sum / z_sum
    lo, hi = 0.0, 1.2
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if _involute(mid) < target else (lo, mid)
    return 0.5 * (lo + hi)


@pytest.fixture(scope="module")
def shaft_point():
    """The accessory pair (examples/accessory-lumped3d.toml, perfect involutes, 2 slices, 8
    positions per pitch) with its pinion on a 25 mm shaft on two 6205s (10 µm clearance) at its
    ends, the pinion 30 mm from the first; the gear shaft on the example's linear springs."""
    case = jio.load_case(str(LINEAR))
    six = jb.catalogue("6205", clearance=CLEARANCE)
    pinion = ShaftSpec(length=L, diameter=0.025, gear_z=A, torque_z=0.0, elements=4,
                       bearings=(Bearing(0.0, rolling=six), Bearing(L, rolling=six)))
    gear = case.scene.gear_shaft
    mesh = case.mesh_model(slices=2)

    def build(shafts):
        return lumped_pair(case.pair, mesh, *shafts, masses=(0.5, 2.0),
                           inertias=((2e-4, 3e-4), (2e-3, 3e-3)))

    point = bearings_at_operating_point(build, (pinion, gear), None, TORQUE,
                                        hold=lambda s: (s.torque_dofs[1],),
                                        positions_per_pitch=8)
    return case, six, build, (pinion, gear), point


def test_bearing_reactions_equal_two_support_statics(shaft_point):
    """The pinion shaft's bearing loads against a beam on two supports by hand: the normal
    force F_n = T / r_b1 (spur, r_b1 = m z1 cos α / 2) split F_n (L − a)/L and F_n a/L, along
    the line of action at the working pressure angle from the involute function
    (|F_x| / |F_y| = tan α_w, the centres along x). Measured: the two loads' sum 5e-4 above
    F_n and 2.3e-3 off tan α_w in direction, the split 2e-3 off a/L (the scene's mean mesh
    force, the same on linear springs of 100 N/µm: the pinion 30 mm along a 25 mm shaft tilts
    and moves its contact; the example's pinion at mid-span meets tan α_w to 1e-5); the
    bearings' own stiffness does not move them (statically determinate to 1e-4: their tilt
    stiffness is small)."""
    _, _, _, _, point = shaft_point
    g = tomllib.loads(LINEAR.read_text())
    m, alpha = g["pair"]["normal_module_mm"] * 1e-3, math.radians(
        g["pair"]["normal_pressure_angle_deg"])
    z1, z2 = g["pinion"]["teeth"], g["gear"]["teeth"]
    rb1 = 0.5 * m * z1 * math.cos(alpha)
    Fn = TORQUE / rb1
    aw = _working_pressure_angle(alpha, g["pinion"]["profile_shift"] + g["gear"]["profile_shift"],
                                 z1 + z2)
    f0, f1 = (np.asarray(f) for f in point.loads[0])
    total = f0[:2] + f1[:2]
    assert math.hypot(*total) == pytest.approx(Fn, rel=1e-3)
    assert abs(total[0]) / abs(total[1]) == pytest.approx(math.tan(aw), rel=5e-3)
    for f, share in ((f0, (L - A) / L), (f1, A / L)):
        assert math.hypot(f[0], f[1]) == pytest.approx(Fn * share, rel=3e-3)
    # both along one line, the same way (the pinion's force on both supports)
    assert abs(f0[0] * f1[1] - f0[1] * f1[0]) <= 1e-3 * math.hypot(*f0[:2]) * math.hypot(*f1[:2])
    assert f0[0] * f1[0] > 0 and f0[1] * f1[1] > 0
    # the axial loads balance (a spur pair): what one bearing takes the other gives back
    assert abs(f0[2] + f1[2]) <= 1e-6 * Fn


def test_bearing_stiffness_is_the_package_stiffness_at_the_hand_load(shaft_point):
    """Each rolling bearing's radial stiffness in the scene against the bearing package called
    directly with the hand reactions (F_x, F_y of the two-support statics, no axial load or
    moment): 5e-3 (the scene's small axial load and moments, which the hand load leaves
    out)."""
    _, six, _, _, point = shaft_point
    for j, share in ((0, (L - A) / L), (1, A / L)):
        f = np.asarray(point.loads[0][j])
        direction = f[:2] / math.hypot(f[0], f[1])
        g = tomllib.loads(LINEAR.read_text())
        rb1 = 0.5 * g["pair"]["normal_module_mm"] * 1e-3 * g["pinion"]["teeth"] * math.cos(
            math.radians(g["pair"]["normal_pressure_angle_deg"]))
        hand = np.array([*(TORQUE / rb1 * share * direction), 0.0, 0.0, 0.0])
        state = jb.solve_displacement(six, hand)
        k_hand = np.asarray(state.stiffness)[:2, :2]
        k_scene = point.shafts[0].bearings[j].stiffness_matrix()[:2, :2]
        scale = np.max(np.abs(k_hand))
        assert np.max(np.abs(k_scene - k_hand)) <= 5e-3 * scale
        # and exactly the package's tangent stiffness at the scene's own operating point
        d = point.shafts[0].bearings[j].operating
        assert np.allclose(point.shafts[0].bearings[j].stiffness_matrix(),
                           np.asarray(six.stiffness6(np.asarray(d))), rtol=1e-9, atol=1e-9 * scale)


def test_fixed_point_converges_and_is_the_nonlinear_equilibrium(shaft_point):
    """The fixed point stops within a few quasi-static solves (measured 3) below its
    tolerance; each bearing carries its load at its operating point (f(d) = load, the package's
    load function, 1e-9), and the gear shaft's linear bearings are left as given."""
    _, six, _, (_, gear), point = shaft_point
    assert 2 <= point.iterations <= 6
    assert point.change <= 1e-6
    for j in range(2):
        f = np.asarray(point.loads[0][j])
        d = np.asarray(point.shafts[0].bearings[j].operating)
        assert np.max(np.abs(np.asarray(six.load(d)) - f)) <= 1e-6 * np.max(np.abs(f))
        assert float(point.states[0][j].residual) < 1e-9
    assert point.shafts[1] == gear and point.loads[1] == (None, None)


def test_fixed_point_refuses_what_does_not_settle(shaft_point):
    """Too few solves for the tolerance: refused in one line naming the change."""
    _, _, build, shafts, _ = shaft_point
    with pytest.raises(ValueError) as err:
        bearings_at_operating_point(build, shafts, None, TORQUE, hold=lambda s: (s.torque_dofs[1],),
                                    positions_per_pitch=8, tolerance=1e-12, max_iterations=2)
    text = str(err.value)
    assert "did not settle in 2 quasi-static solves" in text and "\n" not in text


def test_scene_bearing_contract():
    """A rolling scene bearing has no stiffness before its operating point; ``at`` gives it the
    kind's, its DOFs are the kind's declaration, two stiffness forms are refused."""
    six = jb.catalogue("6205")
    b = Bearing(0.01, rolling=six)
    with pytest.raises(ValueError, match="only at an operating point"):
        b.stiffness_matrix()
    assert b.carried() == six.carried()
    nu = Bearing(0.01, rolling=jb.catalogue("NU 205"))
    assert nu.carried() == (True, True, False, True, True)
    with pytest.raises(ValueError, match="not both"):
        Bearing(0.01, radial=1e8, rolling=six)
    with pytest.raises(ValueError, match="without a rolling bearing"):
        Bearing(0.01, operating=(0, 0, 0, 0, 0))
    d = np.asarray(jb.solve_displacement(six, [800.0, 300.0, 0, 0, 0]).displacement)
    assert np.allclose(b.at(d).stiffness_matrix(), np.asarray(six.stiffness6(d)))


def _example():
    return tomllib.loads(EXAMPLE.read_text())


def _refused(data, start):
    with pytest.raises(ValueError) as err:
        jio.parse_case(data)
    text = str(err.value)
    assert text.startswith(start) and "\n" not in text, text


@pytest.mark.parametrize(
    "change, start",
    [
        ({"catalogue": "6209"}, "[scene.pinion_shaft.bearings[0]] catalogue = '6209': allowed '6205'"),
        ({"ball_diameter_mm": 17.0}, ("[scene.pinion_shaft.bearings[0]] ball_diameter_mm = 17: out "
                                      "of range, allowed < (outer_diameter_mm - bore_mm)/2 = 16")),
        ({"kind": "angular_contact_ball", "contact_angle_deg": 90.0},
         "[scene.pinion_shaft.bearings[0]] contact_angle_deg = 90: out of range"),
        ({"clearance_um": 900.0}, "[scene.pinion_shaft.bearings[0]] clearance_um = 900: out of range"),
        ({"balls": 20}, "[scene.pinion_shaft.bearings[0]] balls = 20: out of range, allowed <= pi"),
        ({"pitch_diameter_mm": 60.0}, ("[scene.pinion_shaft.bearings[0]] pitch_diameter_mm = 60: "
                                       "out of range")),
        ({"radial_N_per_um": 100.0}, "[scene.pinion_shaft.bearings[0]] kind: give one stiffness form"),
        ({"rollers": 12}, "[scene.pinion_shaft.bearings[0]] rollers: not a key of kind"),
    ],
)
def test_case_file_bearing_keys_refused_in_one_line(change, start):
    data = _example()
    data["scene"]["pinion_shaft"]["bearings"][0].update(change)
    _refused(data, start)


def test_case_file_catalogue_and_where_geometry_bearings_are_not_taken():
    """``catalogue`` with geometry keys, a linear bearing with a rolling key, and bearings from
    geometry beside a condensed body: one line each."""
    data = _example()
    data["scene"]["pinion_shaft"]["bearings"][0] = {"position_mm": 0.0, "catalogue": "6205",
                                                     "bore_mm": 25.0}
    _refused(data, "[scene.pinion_shaft.bearings[0]] bore_mm: not with catalogue = '6205'")
    data = _example()
    data["scene"]["pinion_shaft"]["bearings"][0] = {"position_mm": 0.0, "clearance_um": 5.0}
    _refused(data, "[scene.pinion_shaft.bearings[0]] clearance_um: is a rolling bearing's key")
    data = _example()
    data["scene"]["gear_body"] = {"body": "any"}
    _refused(data, "[scene.pinion_shaft.bearings[0]] kind: a bearing from its geometry is for a "
             "lumped3d pair or train of rigid gears for now (not with pinion_body")


def test_a_housing_holds_the_bearings_at_their_operating_point():
    """The example's shafts in a housing (a small synthetic one: two seats, three modes): the
    operating point is the grounded scene's (the housing rigid there), and the housed scene's
    bearing part holds each bearing's stiffness at that point on its shaft node, coupled to its
    seat."""
    from jaxgear.io._case_model import _lumped3d_pair
    from jaxgear.scenes import Housing, bearing_dofs

    case = jio.parse_case(_example())
    rng = np.random.default_rng(3)
    h = 6 * 2 + 3
    a = rng.standard_normal((h, h))
    K = 1e9 * (a @ a.T + h * np.eye(h))
    housing = Housing(K=K, M=np.eye(h), C=1e-3 * K, seat_positions=(
        (0.0, 0.0, -0.05), (0.0, 0.0, 0.05)), seat_names=("front", "back"),
        rotation=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))
    scene = _lumped3d_pair(case, case.scene, case.mesh_model(slices=2), housing=housing)
    point = operating_point(case)
    parts = scene.structure.part_names
    kb = np.asarray(scene.structure.parts_K[parts.index("bearings")])
    n = kb.shape[0] - h
    for s, row in zip(bearing_dofs(point.shafts), point.shafts, strict=True):
        for k, b in zip(s, row.bearings, strict=True):
            np.testing.assert_allclose(kb[k : k + 6, k : k + 6], b.stiffness_matrix(),
                                       rtol=1e-12, atol=1e-6)
            assert np.abs(kb[k : k + 6, n:]).max() > 0  # joined to a seat


def test_case_file_bearings_from_geometry_move_the_mesh_mode(tmp_path):
    """The example case (6206/6207 by geometry) and the same case on catalogue bearings load
    and find their operating point; the mesh mode (the mode of the largest mesh energy, the
    sweep's) of the mesh-averaged system moves with the bearings' radial stiffness against
    the linear-spring case (200 and 300 N/µm): the rolling bearings at 67-120 N/µm lower it,
    and a preload (clearance -5 µm), stiffer, raises it again."""
    from jaxgear.dynamics import mesh_averaged_modes

    def mesh_mode(case):
        model, _ = build_dynamic_model(case)
        modes = mesh_averaged_modes(model, speed=case.speed, positions_per_pitch=16)
        i = int(np.argmax(np.asarray(modes.mesh_energy)))
        return float(np.asarray(modes.omega)[i]) / (2 * math.pi)

    def radial(case):
        p = operating_point(case)
        return min(b.stiffness_matrix()[0, 0] + b.stiffness_matrix()[1, 1]
                   for s in p.shafts for b in s.bearings) / 2

    rolling = jio.parse_case(_example())
    data = _example()
    for shaft in ("pinion_shaft", "gear_shaft"):
        for b in data["scene"][shaft]["bearings"]:
            b["clearance_um"] = -5.0
    preloaded = jio.parse_case(data)
    linear = jio.load_case(str(LINEAR))
    assert operating_point(rolling).iterations <= 6
    assert radial(preloaded) > radial(rolling)
    f_lin, f_roll, f_pre = mesh_mode(linear), mesh_mode(rolling), mesh_mode(preloaded)
    assert f_roll < f_lin
    assert f_roll < f_pre


@pytest.mark.slow  # five operating points and modal analyses, and a derivative through the solve
def test_clearance_derivative_of_the_mesh_mode():
    """The clearance derivative of the example's mesh mode, from JAX: each bearing's stiffness
    at its operating load differentiated through the displacement solve (the implicit
    derivative) and put into the modal sensitivity dω/dc = Σ_b φ_bᵀ (∂K_b/∂c) φ_b / (2ω)
    (φ mass-normalised, the bearings' loads and the averaged mesh stiffness held), against a
    central difference (±0.5 µm) of the whole model's mesh mode, each clearance its own fixed
    point: measured −2.19 against −2.23 rad/s per µm, 2.0 % (what the held loads and mesh
    stiffness leave out)."""
    import equinox as eqx
    import jax
    import jax.numpy as jnp

    from jaxgear.dynamics import mesh_averaged_modes
    from jaxgear.scenes import bearing_dofs

    def case_at(clearance_um):
        data = _example()
        for shaft in ("pinion_shaft", "gear_shaft"):
            for b in data["scene"][shaft]["bearings"]:
                b["clearance_um"] = clearance_um
        return jio.parse_case(data)

    def mesh_mode(case):
        model, _ = build_dynamic_model(case)
        modes = mesh_averaged_modes(model, speed=case.speed, positions_per_pitch=16)
        i = int(np.argmax(np.asarray(modes.mesh_energy)))
        return modes, i

    c0, h = 10.0, 0.5
    case = case_at(c0)
    point = operating_point(case)
    modes, i = mesh_mode(case)
    phi, omega = np.asarray(modes.shapes)[:, i], float(np.asarray(modes.omega)[i])
    dofs = bearing_dofs(point.shafts)
    slope = 0.0
    for s, row in enumerate(point.shafts):
        for j, b in enumerate(row.bearings):
            load = jnp.asarray(point.loads[s][j])

            def k6(c, b=b, load=load):
                kind = eqx.tree_at(lambda x: x.clearance, b.rolling, c)
                return kind.stiffness6(jb.solve_displacement(kind, load).displacement)

            dk = np.asarray(jax.jacfwd(k6)(jnp.asarray(c0 * 1e-6)))
            p = phi[dofs[s][j]: dofs[s][j] + 6]
            slope += float(p @ dk @ p) / (2 * omega) * 1e-6  # per µm
    up, down = (mesh_mode(case_at(c0 + sign * h)) for sign in (1, -1))
    fd = (float(np.asarray(up[0].omega)[up[1]]) - float(np.asarray(down[0].omega)[down[1]])) / (
        2 * h)
    assert slope < 0  # more clearance, softer bearings, a lower mesh mode
    assert slope == pytest.approx(fd, rel=3e-2)
