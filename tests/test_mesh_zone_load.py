"""jaxgear.scenes.mesh_zone_load: a unit normal force spread over a mesh's contact zone, as a load
on the structure (seed (2.9)).

References, each written here from the gear data alone: on a rigid 6-DOF gear node the load is
a unit force along the line of action (in-plane direction turned from the centre line by
90° − α_wt towards the driving gear's motion, axial part sin β_b, tan β_b = tan β cos α_t) whose
moment about the gear axis is the base radius r_b = m_n z cos α_t / (2 cos β) times cos β_b, in
the driving gear's sense of rotation and against the driven gear's; on a torsional member the
load is ±r_b cos β_b; nothing on the other coordinates.
"""

from __future__ import annotations

import math
import pathlib
import tomllib

import jax
import numpy as np
import pytest
from _trains import line_direction, spins

import jaxgear.io as jio
from jaxgear.io import static_scene
from jaxgear.scenes import mesh_zone_load

jax.config.update("jax_enable_x64", True)

EXAMPLES = pathlib.Path(__file__).parents[1] / "examples"
THETAS = (0.0, 0.013, 0.031)


def _base_radius(teeth: int, normal_module: float, alpha_n: float, beta: float) -> tuple:
    """(r_b, β_b) of an involute gear: r_b = m_n z cos α_t / (2 cos β), tan α_t = tan α_n / cos β,
    tan β_b = tan β cos α_t."""
    alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
    rb = normal_module * teeth * math.cos(alpha_t) / (2 * math.cos(beta))
    return rb, math.atan(math.tan(beta) * math.cos(alpha_t))


@pytest.mark.parametrize("helix_deg", [0.0, 15.0])
def test_on_rigid_gear_nodes_the_zone_load_is_the_unit_mesh_force(helix_deg, tmp_path):
    """The accessory pair on shafts (examples/accessory-lumped3d.toml; spur and 15° helical): the
    zone load puts on the pinion node a unit force along the line of action, (sin α_wt,
    cos α_wt) cos β_b in the plane (the pinion on the origin, the gear on +x) and ±sin β_b
    axially, and the moment r_b1 cos β_b about its axis (+z, its motion); on the gear node the
    opposite force and the moment r_b2 cos β_b about +z (against its motion, about −z); nothing
    elsewhere (1e-12)."""
    text = (EXAMPLES / "accessory-lumped3d.toml").read_text()
    path = tmp_path / "pair.toml"
    path.write_text(text.replace("helix_angle_deg = 0.0", f"helix_angle_deg = {helix_deg}"))
    case = jio.load_case(path)
    scene = static_scene(case)[0].base  # the lumped pair (not its grounded copy)
    alpha_n, beta = math.radians(25.0), math.radians(helix_deg)
    rb1, beta_b = _base_radius(45, 1.5e-3, alpha_n, beta)
    rb2, _ = _base_radius(86, 1.5e-3, alpha_n, beta)
    awt = case.pair.operating_pressure_angle
    t = np.array([math.sin(awt), math.cos(awt)]) * math.cos(beta_b)
    pin, gear = (np.asarray(m.dofs) for m in scene.members)
    for theta in THETAS:
        f = np.asarray(mesh_zone_load(scene, 0, theta))
        assert f.shape == (scene.structure.size,)
        fp, fg = f[pin], f[gear]
        np.testing.assert_allclose(fp[:2], t, atol=1e-12)
        np.testing.assert_allclose(fg[:2], -t, atol=1e-12)
        assert abs(fp[2]) == pytest.approx(math.sin(beta_b), abs=1e-12)
        assert fg[2] == pytest.approx(-fp[2], abs=1e-12)
        assert np.linalg.norm(fp[:3]) == pytest.approx(1.0, abs=1e-12)
        assert fp[5] == pytest.approx(rb1 * math.cos(beta_b), rel=1e-12)
        assert fg[5] == pytest.approx(rb2 * math.cos(beta_b), rel=1e-12)
        rest = np.delete(f, np.concatenate([pin, gear]))
        assert rest.size and np.abs(rest).max() == 0.0


def _train_gears(path: pathlib.Path) -> dict:
    """Each gear's base radius r_b = m z cos α / 2 (spur) from the case file's gear data."""
    data = tomllib.loads(path.read_text())
    return {
        g["name"]: g["normal_module_mm"]
        * 1e-3
        * g["teeth"]
        * math.cos(math.radians(g["normal_pressure_angle_deg"]))
        / 2
        for g in data["gears"]
    }


def test_in_a_lumped_train_each_mesh_loads_its_own_two_gears():
    """The lumped idler train (examples/idler-train-lumped3d.toml, spur): mesh k's zone load is
    the unit force along the mesh's line (tests/_trains.line_direction, from the gear data) on
    its driving gear and the opposite one on its driven gear, with the moments r_b about the
    axes (+ in the driving gear's sense of rotation, − in the driven gear's), nothing on the
    third gear; ``first`` keeps the coordinates from it on."""
    path = EXAMPLES / "idler-train-lumped3d.toml"
    case = jio.load_case(path)
    scene = case.static_train().base
    rb = _train_gears(path)
    spin = spins(case)
    for k, (g, h) in enumerate(case.gears):
        d = line_direction(case, k)
        (other,) = set(range(3)) - {g, h}
        for theta in THETAS:
            f = np.asarray(mesh_zone_load(scene, k, theta))
            fd, fn = (f[np.asarray(scene.members[i].dofs)] for i in (g, h))
            np.testing.assert_allclose(fd[:3], [*d, 0.0], atol=1e-12)
            np.testing.assert_allclose(fn[:3], [*-d, 0.0], atol=1e-12)
            assert fd[5] == pytest.approx(spin[g] * rb[case.gear_names[g]], rel=1e-12)
            assert fn[5] == pytest.approx(-spin[h] * rb[case.gear_names[h]], rel=1e-12)
            assert np.all(f[np.asarray(scene.members[other].dofs)] == 0.0)
        first = 7
        whole = np.asarray(mesh_zone_load(scene, k, 0.0))
        np.testing.assert_array_equal(
            np.asarray(mesh_zone_load(scene, k, 0.0, first)), whole[first:]
        )


def test_on_torsional_members_the_zone_load_is_the_base_radius():
    """The torsional idler train (embedded ``accessory-idler-train``): mesh k's zone load is
    r_b cos β_b on its driving gear's rotation and −r_b cos β_b on its driven gear's (the driving
    gear advancing closes the flanks), spur: cos β_b = 1; zero on the third gear; the same
    through the grounded scene that ``static_train`` returns."""
    case = jio.load_case("accessory-idler-train")
    grounded = case.static_train()
    scene = grounded.base
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    rb = {
        g["name"]: g["normal_module_mm"]
        * 1e-3
        * g["teeth"]
        * math.cos(math.radians(g["normal_pressure_angle_deg"]))
        / 2
        for g in data["gears"]
    }
    for k, (g, h) in enumerate(case.gears):
        f = np.asarray(mesh_zone_load(scene, k, 0.02))
        want = np.zeros_like(f)
        want[scene.members[g].dof] = rb[case.gear_names[g]]
        want[scene.members[h].dof] = -rb[case.gear_names[h]]
        np.testing.assert_allclose(f, want, rtol=1e-12, atol=0)
        # a grounded scene loads its base's coordinates
        np.testing.assert_array_equal(np.asarray(mesh_zone_load(grounded, k, 0.02)), f)


def test_a_mesh_or_a_first_coordinate_out_of_range_is_a_one_line_error():
    """``k`` not a mesh of the scene, ``first`` beyond the coordinates: one line naming the
    argument, its value and the allowed range."""
    scene = jio.load_case("accessory-idler-train").static_train().base
    n = scene.structure.size
    for kw, match in (
        ({"k": 2}, r"^mesh_zone_load: k = 2: not a mesh of the scene, allowed 0 to 1$"),
        ({"k": -1}, r"^mesh_zone_load: k = -1: not a mesh of the scene, allowed 0 to 1$"),
        (
            {"k": 0, "first": n + 1},
            rf"^mesh_zone_load: first = {n + 1}: out of range, allowed \[0, {n}\]$",
        ),
    ):
        with pytest.raises(ValueError, match=match):
            mesh_zone_load(scene, theta=0.0, **kw)
