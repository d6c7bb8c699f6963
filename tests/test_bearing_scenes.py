"""Rolling bearings from their geometry in the lumped 3D scenes: ``scenes.Bearing(rolling=)`` at
an operating point, the fixed point of the bearings' loads
(:func:`jaxgear.dynamics.bearings_at_operating_point`) and the case files' bearing keys
(``catalogue``, ``kind``), against statics by hand and the bearing package called directly."""

from __future__ import annotations

import dataclasses
import json
import math
import tomllib
from pathlib import Path

import equinox as eqx
import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear import BeyondPath, TheoreticalPath, bearings as jb, cli, quasi_static
from jaxgear.dynamics import bearings_at_operating_point
from jaxgear.io import build_dynamic_model, operating_point
from jaxgear.scenes import Bearing, ShaftSpec, bearing_dofs, grounded, lumped_pair

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
    build, point = _accessory_point(case, case.mesh_model(slices=2), pinion)
    return case, six, build, (pinion, gear), point


def _accessory_point(case, mesh, pinion):
    """(build, the operating point at :data:`TORQUE`) of the accessory pair ``case`` on
    ``mesh`` with ``pinion`` its pinion shaft, its gear shaft the case's, 8 positions per
    pitch, the load's rotation held."""

    def build(shafts):
        return lumped_pair(case.pair, mesh, *shafts, masses=(0.5, 2.0),
                           inertias=((2e-4, 3e-4), (2e-3, 3e-3)))

    point = bearings_at_operating_point(build, (pinion, case.scene.gear_shaft), None, TORQUE,
                                        hold=lambda s: (s.torque_dofs[1],),
                                        positions_per_pitch=8)
    return build, point


def test_bearing_reactions_equal_two_support_statics(shaft_point):
    """The pinion shaft's bearing loads against a beam on two supports by hand: the normal
    force F_n = T / r_b1 (spur, r_b1 = m z1 cos α / 2) split F_n (L − a)/L and F_n a/L, along
    the line of action at the working pressure angle from the involute function
    (|F_x| / |F_y| = tan α_w, the centres along x). Measured: the two loads' sum 5.05e-4 above
    F_n and 2.28e-3 off tan α_w in direction: the mesh's contact beyond the path of contact
    (the case's default), whose tip-corner cells push off the line of action, as the next test
    reproduces by hand (5.14e-4 and 2.31e-3 there on linear springs; on the theoretical path
    the statics hold to 1e-9); so the sum lies above F_n by less than 6e-4 and its direction
    off by less than 2.5e-3. The split: 1.4e-3 and −1.7e-3 off a/L (the face load's centroid
    off mid-face, the next test's z̄; the bearings' small tilt stiffness); the axial loads
    balance."""
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
    assert 0.0 < math.hypot(*total) / Fn - 1.0 < 6e-4
    assert 0.0 < abs(total[0]) / abs(total[1]) / math.tan(aw) - 1.0 < 2.5e-3
    for f, share in ((f0, (L - A) / L), (f1, A / L)):
        assert math.hypot(f[0], f[1]) == pytest.approx(Fn * share, rel=2e-3)
    # both along one line, the same way (the pinion's force on both supports)
    assert abs(f0[0] * f1[1] - f0[1] * f1[0]) <= 1e-3 * math.hypot(*f0[:2]) * math.hypot(*f1[:2])
    assert f0[0] * f1[0] > 0 and f0[1] * f1[1] > 0
    # the axial loads balance (a spur pair): what one bearing takes the other gives back
    assert abs(f0[2] + f1[2]) <= 1e-6 * Fn


def _rotated(v, angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] - s * v[1], s * v[0] + c * v[1]])


def _tangent_to(point, centre, radius, towards):
    """The unit direction of the line through ``point`` tangent to the circle (``centre``,
    ``radius``) (an involute's normal there), of the two tangents and two senses the one
    nearest ``towards``."""
    d = point - centre
    rho, phi = math.hypot(*d), math.atan2(d[1], d[0])
    best = None
    for sign in (1.0, -1.0):
        q = phi + sign * math.acos(radius / rho)
        u = point - centre - radius * np.array([math.cos(q), math.sin(q)])
        for v in (u, -u):
            v = v / math.hypot(*v)
            if best is None or v @ towards > best @ towards:
                best = v
    return best


def test_mesh_force_off_the_line_of_action_is_the_corner_contacts():
    """Where the mesh force on the pinion shaft leaves T / r_b1 along the line of action: the
    pinion 30 mm along a 100 mm, 25 mm shaft on two linear springs (100 N/µm radially, no tilt
    stiffness: the reactions are statics'), 8 positions per mesh period.

    - On the theoretical path of contact only (``TheoreticalPath``) every cell pushes along the
      line of action t with the arm r_b1: at every position the two reactions sum to F_n =
      T/r_b1 along t (tan α_w from the involute function by hand), and each carries the statics'
      share of the resultant at the face load's centroid z̄ = Σ w z / Σ w (the shaft's tilt
      moves it 0.04–0.06 mm off mid-face: the "2e-3 off a/L"), to 1e-9.
    - With contact beyond the path (``BeyondPath``, the case files' default) a cell at s < 0
      is the gear's tip corner, turned back from the path's start A by −s / r_b2 about the gear
      centre, pressing on the pinion's involute (its normal the tangent to the pinion's base
      circle), and a cell at s > g_α the pinion's tip corner, turned on from the path's end E by
      (s − g_α)/r_b1, pressing on the gear's involute (the tangent to the gear's base circle).
      Their normals turn 2e-3 to 1.4e-2 rad off t. With each cell's load w (the solve's line
      load times its length) the pinion's force Σ w n by this geometry, written here, is the
      reactions' sum at every position to 1e-6 of F_n (measured 1.8e-7: the package
      interpolates its corner table), the positions without a loaded corner to 1e-9: at the 3
      of 8 positions with a loaded
      corner it is 7.0e-4, 2.5e-3 and 8.8e-4 above F_n, their mean 5.14e-4 above F_n and
      2.3e-3 off tan α_w in direction, the offset the rolling bearings of the test above show
      (the same at mid-span: it is the mesh's, not the shaft's). The solve balances T with each
      corner cell's pinion arm less its part along the free drive rotation
      (docs/extended-contact.md, "The free drive rotation"), so Σ w r_b1 is not T there; the
      force's direction and point are the exact corner's."""
    case = jio.load_case(str(LINEAR))
    g = tomllib.loads(LINEAR.read_text())
    m, alpha = g["pair"]["normal_module_mm"] * 1e-3, math.radians(
        g["pair"]["normal_pressure_angle_deg"])
    (z1, x1), (z2, x2) = ((g[k]["teeth"], g[k]["profile_shift"]) for k in ("pinion", "gear"))
    rb1, rb2 = 0.5 * m * z1 * math.cos(alpha), 0.5 * m * z2 * math.cos(alpha)
    ra1 = m * (0.5 * z1 + x1 + g["pinion"]["addendum_coeff"])
    ra2 = m * (0.5 * z2 + x2 + g["gear"]["addendum_coeff"])
    aw = _working_pressure_angle(alpha, x1 + x2, z1 + z2)
    centre2 = np.array([(rb1 + rb2) / math.cos(aw), 0.0])
    t = np.array([math.sin(aw), math.cos(aw)])
    T1 = rb1 * np.array([math.cos(aw), -math.sin(aw)])

    def along(centre, radius, root):  # T1 + λ t at ``radius`` from ``centre``: a root of two
        b, c = (T1 - centre) @ t, (T1 - centre) @ (T1 - centre) - radius**2
        return -b + root * math.sqrt(b * b - c)

    lam_A, lam_E = along(centre2, ra2, -1.0), along(np.zeros(2), ra1, 1.0)
    A_pt, E_pt, g_alpha = T1 + lam_A * t, T1 + lam_E * t, lam_E - lam_A
    Fn = TORQUE / rb1
    pinion = ShaftSpec(length=L, diameter=0.025, gear_z=A, torque_z=0.0, elements=4,
                       bearings=(Bearing(0.0, radial=1e8, axial=1e8, tilt=0.0),
                                 Bearing(L, radial=1e8, axial=0.0, tilt=0.0)))
    offsets = {}
    for geometry in (TheoreticalPath(), BeyondPath()):
        mesh = case.replace(contact_geometry=geometry).mesh_model(slices=2)
        scene = lumped_pair(case.pair, mesh, pinion, case.scene.gear_shaft, masses=(0.5, 2.0),
                            inertias=((2e-4, 3e-4), (2e-3, 3e-3)))
        res = quasi_static(grounded(scene, (scene.torque_dofs[1],)), None, TORQUE,
                           positions_per_pitch=8)
        x = np.asarray(res.x)
        first = bearing_dofs((pinion, case.scene.gear_shaft))[0]
        f = [x[:, k:k + 6] @ np.asarray(b.stiffness_matrix()).T
             for k, b in zip(first, pinion.bearings, strict=True)]
        # the shaft's push on its bearings, the mesh's push −Σ w n on the pinion (n the
        # pinion's outward normal: t on the path)
        total = -(f[0] + f[1])[:, :2]
        w = np.asarray(res.line_load) * float(mesh.face_width) / 2  # N per cell
        s_cell, z_cell = np.asarray(res.cell_s), np.asarray(res.cell_z)
        if isinstance(geometry, TheoreticalPath):
            assert np.allclose(total, Fn * t, rtol=0, atol=1e-9 * Fn)
            zbar = (w * (z_cell - 0.5 * float(mesh.face_width))).sum(axis=(1, 2)) / w.sum(
                axis=(1, 2))
            assert np.allclose(-f[1][:, :2], Fn * t * ((A + zbar) / L)[:, None], rtol=0,
                               atol=1e-9 * Fn)
            continue
        hand = np.zeros_like(total)
        for p, c in np.ndindex(*s_cell.shape[:2]):
            for k in range(s_cell.shape[2]):
                s = s_cell[p, c, k]
                if w[p, c, k] == 0.0:
                    continue
                if s < 0.0:
                    n = _tangent_to(centre2 + _rotated(A_pt - centre2, -s / rb2), np.zeros(2),
                                    rb1, t)
                elif s > g_alpha:
                    n = _tangent_to(_rotated(E_pt, (s - g_alpha) / rb1), centre2, rb2, t)
                else:
                    n = t
                hand[p] += w[p, c, k] * n
        assert np.allclose(total, hand, rtol=0, atol=1e-6 * Fn)
        corner = (s_cell < 0) | (s_cell > g_alpha)
        touched = np.any(corner & (w > 0), axis=(1, 2))
        assert 1 <= touched.sum() < len(touched)
        assert np.allclose(total[~touched], Fn * t, rtol=0, atol=1e-9 * Fn)
        mean = total.mean(axis=0)
        offsets = (math.hypot(*mean) / Fn - 1, mean[0] / mean[1] / math.tan(aw) - 1)
    assert offsets[0] == pytest.approx(5.14e-4, rel=0.01)
    assert offsets[1] == pytest.approx(2.31e-3, rel=0.01)


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


def test_scene_bearing_equality_compares_the_rolling_kind_by_value():
    """Two rolling bearings without an operating point are equal (and hash alike) only when
    their kinds are: the same catalogue entry built twice is equal, another clearance, another
    entry, another rating (None against a value), another class or a linear spring is not; at
    an operating point the point counts too. A program compiled with a bearing as a static
    argument is reused for an equal bearing and traced anew for another one. A pickled or
    deep-copied bearing equals its original."""
    import copy
    import pickle

    import jax

    def b(**kw):
        return Bearing(0.01, rolling=jb.catalogue("6205", **kw))

    assert b() == b() and hash(b()) == hash(b())
    assert b() != b(clearance=10e-6)
    assert b() != Bearing(0.01, rolling=jb.catalogue("6203"))
    assert b() != b(fatigue_limit=335.0)
    nu = Bearing(0.01, rolling=jb.catalogue("NU 205"))
    assert nu != Bearing(0.01, rolling=jb.catalogue("NU 205", slices=12))
    assert b() != Bearing(0.01, radial=1e8) and b() != Bearing(0.02, rolling=b().rolling)
    d = np.asarray(jb.solve_displacement(b().rolling, [800.0, 300.0, 0, 0, 0]).displacement)
    assert b().at(d) == b().at(d) and b().at(d) != b().at(d * 1.01) and b().at(d) != b()
    assert len({b(), b(), b(clearance=10e-6)}) == 2
    again = pickle.loads(pickle.dumps(b(clearance=10e-6)))
    assert again == b(clearance=10e-6) and hash(again) == hash(b(clearance=10e-6))
    assert copy.deepcopy(b().at(d)) == b().at(d)
    traced = []

    def radial(bearing, x):
        traced.append(bearing)
        return x * bearing.rolling.clearance

    run = jax.jit(radial, static_argnums=0)
    for bearing in (b(clearance=5e-6), b(clearance=5e-6), b(clearance=6e-6)):
        run(bearing, 1.0)
    assert len(traced) == 2


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
    from _housing import two_seat_housing

    from jaxgear.io._case_model import _lumped3d_pair
    from jaxgear.scenes import bearing_dofs

    case = jio.parse_case(_example())
    housing, h = two_seat_housing()
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


#: the overhung pinion: its shaft 60 mm long on ONE tapered roller pair (30205's rows, O) at
#: z = 0, the pinion 45 mm out
OVERHANG = 0.045


@pytest.fixture(scope="module")
def overhung_point():
    """The accessory pair (examples/accessory-lumped3d.toml) on the theoretical path of
    contact (every cell's normal along the line of action, arm r_b1), ONE slice over the face
    (the mesh force at mid-face whatever the shaft's tilt), 8 positions per pitch; its pinion
    on a 25 mm shaft held by a tapered roller pair alone at z = 0, overhung by 45 mm; the gear
    shaft on the example's linear springs."""
    case = jio.load_case(str(LINEAR))
    pair = jb.TaperedRollerPair.of(jb.catalogue("30205"), "O", end_play=-5e-6)
    pinion = ShaftSpec(length=0.060, diameter=0.025, gear_z=OVERHANG, torque_z=0.060,
                       elements=4, bearings=(Bearing(0.0, rolling=pair),))
    mesh = case.replace(contact_geometry=TheoreticalPath()).mesh_model(slices=1)
    return pair, _accessory_point(case, mesh, pinion)[1]


def test_overhung_pinion_on_one_pair_is_the_cantilever_statics(overhung_point):
    """A shaft held by one bearing that carries a moment (``carries_moment``): the pair's
    load against the shaft's force and moment balance by hand. On the theoretical path every
    contact pushes along the line of action t with the arm r_b1, so the mesh force on the
    pinion is F_n = T / r_b1 along t (spur: no axial part; the torque about z the only other
    load); with one slice it acts at mid-face, 45 mm from the pair. The pair carries it:
    (F_x, F_y) of magnitude F_n, F_z = 0, and the moment of the force about its node,
    M = Δz e_z × F: M_x = −Δz F_y, M_y = Δz F_x (Δz = 45 mm), each to 1e-8 of F_n (of
    F_n Δz): the shaft is statically determinate, so every iteration's loads are statics'."""
    _, point = overhung_point
    g = tomllib.loads(LINEAR.read_text())
    m, alpha = g["pair"]["normal_module_mm"] * 1e-3, math.radians(
        g["pair"]["normal_pressure_angle_deg"])
    z1, z2 = g["pinion"]["teeth"], g["gear"]["teeth"]
    Fn = TORQUE / (0.5 * m * z1 * math.cos(alpha))
    aw = _working_pressure_angle(alpha, g["pinion"]["profile_shift"] + g["gear"]["profile_shift"],
                                 z1 + z2)
    (f,) = (np.asarray(x) for x in point.loads[0])
    assert math.hypot(f[0], f[1]) == pytest.approx(Fn, rel=1e-8)
    assert abs(f[0]) / abs(f[1]) == pytest.approx(math.tan(aw), rel=1e-8)
    assert abs(f[2]) <= 1e-8 * Fn
    np.testing.assert_allclose(f[3:], [-OVERHANG * f[1], OVERHANG * f[0]], rtol=0,
                               atol=1e-8 * Fn * OVERHANG)
    assert 2 <= point.iterations <= 8 and point.change <= 1e-6


def test_overhung_pair_stiffness_is_the_central_differences(overhung_point):
    """The pair's stiffness in the scene at its operating point (all five DOFs, the tilt
    included: what holds the overhung shaft) against central differences of its load
    function there (h = 1e-6 of the displacement's scale per DOF, translations and tilts), to
    1e-8 of each column's largest entry (measured 4e-10; the differences converge as h², 5e-6
    at h = 1e-4); the pair carries its load there (f(d) = load, 1e-9)."""
    pair, point = overhung_point
    b = point.shafts[0].bearings[0]
    d = np.asarray(b.operating)
    f = np.asarray(point.loads[0][0])
    load = eqx.filter_jit(pair.load)
    assert np.max(np.abs(np.asarray(load(d)) - f)) <= 1e-9 * np.max(np.abs(f))
    K = np.asarray(b.stiffness_matrix())[:5, :5]
    scale = np.array([*[np.max(np.abs(d[:3]))] * 3, *[np.max(np.abs(d[3:]))] * 2])
    for j in range(5):
        h = 1e-6 * scale[j]
        e = np.zeros(5)
        e[j] = h
        fd = (np.asarray(load(d + e)) - np.asarray(load(d - e))) / (2 * h)
        assert np.max(np.abs(K[:, j] - fd)) <= 1e-8 * np.max(np.abs(fd)), j
    assert K[3, 3] > 0 and K[4, 4] > 0  # the tilt stiffness that holds the shaft


@pytest.mark.parametrize("bearing, held", [
    ({"catalogue": "30205", "arrangement": "O"}, True),
    ({"catalogue": "30205", "arrangement": "X", "end_play_um": -5.0}, True),
    ({"catalogue": "6205"}, False),
    ({"catalogue": "7205 B"}, False),
    ({"catalogue": "30205"}, False),
    ({"catalogue": "231/750 CA"}, False),
])
def test_case_file_shaft_on_one_bearing_carries_a_moment_or_is_refused(bearing, held):
    """A shaft on one bearing (the example's pinion shaft, its second bearing removed): held
    by a kind that declares ``carries_moment`` (a tapered roller pair, O or X), refused in one
    line by a single-row ball, angular contact or tapered bearing and a self-aligning
    spherical one (radial supports only)."""
    data = _example()
    data["scene"]["pinion_shaft"]["bearings"] = [{"position_mm": 0.0, **bearing}]
    if held:
        b = jio.parse_case(data).scene.pinion_shaft.bearings[0]
        assert b.rolling.carries_moment and b.holds_tilt()
        return
    _refused(data, "[scene.pinion_shaft] bearings: needs two radial bearings (or a tilt "
             "stiffness) to hold the shaft (a single-row or self-aligning rolling bearing is a "
             "radial support only: allowed a second bearing, or a bearing that carries a "
             "moment, kind = 'tapered_roller_pair')")


def test_contract_declares_which_kinds_carry_a_moment():
    """``carries_moment`` on the contract: the pair and a linear spring (its tilt spring) yes;
    every single-row kind and the self-aligning spherical roller bearing no."""
    assert jb.TaperedRollerPair.carries_moment and jb.LinearSpring.carries_moment
    for kind in (jb.DeepGrooveBall, jb.AngularContactBall, jb.CylindricalRoller,
                 jb.TaperedRoller, jb.SphericalRoller):
        assert not kind.carries_moment, kind


def test_start_springs_hold_a_shaft_on_one_pair():
    """The first solve's springs (white box: a singular start is factored with a pivot of
    rounding noise, which some CPUs turn into a failed solve): a shaft on one pair stands on
    its tilt spring too, k_t = k_r (d_m/2)² by hand (30205: d_m = 39 mm), so that the shaft's
    stiffness (its elements and start springs) is singular only in the free rotation about
    its axis (1 zero eigenvalue; 3 without the tilt spring: the shaft tilts about the node);
    a shaft on two radial bearings keeps no tilt spring (statically determinate as before)."""
    from jaxgear.dynamics._bearings import START_SPRING, _start_springs
    from jaxgear.scenes import shaft_matrices

    pair = jb.TaperedRollerPair.of(jb.catalogue("30205"), "O")
    one = ShaftSpec(length=0.06, diameter=0.025, gear_z=0.045, torque_z=0.06, elements=4,
                    bearings=(Bearing(0.0, rolling=pair),))
    (start,) = _start_springs(one)
    assert start.tilt == pytest.approx(START_SPRING[0] * 0.0195**2, rel=1e-12)
    assert start.radial == START_SPRING[0] and start.axial == START_SPRING[1]
    two = ShaftSpec(length=0.06, diameter=0.025, gear_z=0.045, torque_z=0.06, elements=4,
                    bearings=(Bearing(0.0, rolling=pair),
                              Bearing(0.06, rolling=jb.catalogue("6205"))))
    assert [b.tilt for b in _start_springs(two)] == [0.0, 0.0]
    free = Bearing(0.0, radial=START_SPRING[0], axial=START_SPRING[1], tilt=0.0)
    for bearings, zeros in (((start,), 1), ((free,), 3)):
        m = shaft_matrices(dataclasses.replace(one, bearings=bearings), 2.1e11, 8.1e10, 7850.0)
        w = np.linalg.eigvalsh(m.K + m.K_bearing)
        assert int(np.sum(np.abs(w) < 1e-9 * w.max())) == zeros


OVERHUNG_CASE = ROOT / "tests" / "data" / "overhung-pinion-pair.toml"


@pytest.mark.slow  # a whole jaxgear run: quasi-static files and the lumped scene's sweep
def test_jaxgear_run_of_an_overhung_pinion_on_one_pair(tmp_path):
    """``jaxgear run`` on a case file whose pinion shaft stands on ONE tapered roller pair
    (``catalogue = "30205"``, ``arrangement = "O"``) 40 mm from the pinion: the run's
    summary against statics by hand. The pair carries the whole mesh force, F_n = T / r_b1
    in the transverse plane (the case's default contact beyond the path moves it by the
    corner cells' offset, a few 1e-4), along tan α_w, no axial load (spur); its moment is
    the force's about the pair's node, M ⟂ F, with the lever |M| / |F| the distance to the
    mesh force's centre, which lies on the pinion's face (40 mm ± half the 11.5 mm face);
    the gear shaft's two bearings 50 mm either side of its gear share the opposite force
    equally (to the moment of its own face's load centre)."""
    out = tmp_path / "out"
    assert cli.main(["run", str(OVERHUNG_CASE), "--out", str(out), "--quiet"]) == 0
    rows = {b["name"]: b for b in json.loads((out / "summary.json").read_text())["bearings"]
            ["bearings"]}
    g = tomllib.loads(OVERHUNG_CASE.read_text())
    m, alpha = g["pair"]["normal_module_mm"] * 1e-3, math.radians(
        g["pair"]["normal_pressure_angle_deg"])
    z1, z2 = g["pinion"]["teeth"], g["gear"]["teeth"]
    Fn = g["operating"]["torque_Nm"] / (0.5 * m * z1 * math.cos(alpha))
    aw = _working_pressure_angle(alpha, g["pinion"]["profile_shift"] + g["gear"]["profile_shift"],
                                 z1 + z2)
    pair = rows["pinion_shaft.bearings[0]"]
    assert pair["kind"] == "TaperedRollerPair"
    f = np.asarray(pair["load_N_Nm"])
    assert math.hypot(f[0], f[1]) == pytest.approx(Fn, rel=2e-3)
    assert abs(f[0]) / abs(f[1]) == pytest.approx(math.tan(aw), rel=5e-3)
    assert abs(f[2]) <= 1e-6 * Fn
    # M ⟂ F (the mesh's contact forces nearly parallel: measured 6e-8 of |F| |M|)
    assert abs(f[:2] @ f[3:]) <= 1e-6 * np.linalg.norm(f[:2]) * np.linalg.norm(f[3:])
    lever = math.hypot(f[3], f[4]) / math.hypot(f[0], f[1])
    shaft = g["scene"]["pinion_shaft"]
    dz = (shaft["gear_position_mm"] - shaft["bearings"][0]["position_mm"]) * 1e-3
    half = 0.5 * g["pinion"]["face_width_mm"] * 1e-3
    assert dz - half < lever < dz + half
    # the moment's sense: the force at +Δz from the node, M = Δz e_z × F
    assert np.sign(f[3]) == -np.sign(f[1]) and np.sign(f[4]) == np.sign(f[0])
    a, b = (np.asarray(rows[f"gear_shaft.bearings[{k}]"]["load_N_Nm"])[:2] for k in (0, 1))
    np.testing.assert_allclose(a + b, -f[:2], rtol=0, atol=1e-6 * Fn)
    assert math.hypot(*a) == pytest.approx(0.5 * Fn, rel=0.05)
    assert math.hypot(*b) == pytest.approx(0.5 * Fn, rel=0.05)
    assert set(pair["tones_orders"]) == {"ftf", "bpfo", "bpfi", "bsf"}
