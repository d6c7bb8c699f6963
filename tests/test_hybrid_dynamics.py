"""Hybrid dynamics, first part (issue 12 §1–2): Newmark with the contact loop in the cell space
on the small test body. References: the same Newmark scheme on all coordinates (each step the
contact problem K_eff X = F_eff − Σ P V solved with jaxgear.solve_contact), and the quasi-static
limit at low speed."""

from __future__ import annotations

import pathlib

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.dynamics import hybrid_speed_sweep, simulate_hybrid, static_scene

DATA = pathlib.Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("FEM_PREP_CACHE", str(tmp_path_factory.mktemp("fem_prep_cache")))
        case = jio.load_case(DATA / "hybrid-test-case.toml")
        body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
        yield case, static_scene(case, bodies=(None, body))[0]


def _reference_newmark(scene, mods, torque, speed, spp, n_steps, alpha, beta):
    """Newmark average acceleration on all coordinates, written out here: mesh force per step."""
    mesh = scene.mesh
    M, K = np.asarray(scene.M), np.asarray(scene.K)
    C = alpha * M + beta * K
    dt = float(mesh.mesh_period_angle) / speed / spp
    a0, a1 = 4.0 / dt**2, 2.0 / dt
    Keff = jnp.asarray(K + a0 * M + a1 * C)
    F = torque * np.asarray(scene.f_torque) + speed**2 * np.asarray(scene.f_centrifugal)
    th0 = 0.5 * float(mesh.mesh_period_angle) / spp
    qs = jg.quasi_static(
        eqx.tree_at(lambda s: s.speed, scene, jnp.asarray(speed)), mods, torque, jnp.array([th0])
    )
    X, Xd, Xdd = np.asarray(qs.x[0]), np.zeros(M.shape[0]), np.zeros(M.shape[0])

    @jax.jit
    def step(th, Feff):
        cells, _, d0 = jg.separation(mesh, mods, th)
        n = scene.K.shape[0]
        V = scene.cell_vectors(cells).reshape(-1, n)
        sol = jg.solve_contact(
            Keff,
            Feff,
            V,
            cells.stiffness.reshape(-1),
            cells.length.reshape(-1),
            d0.reshape(-1),
            cells.mask.reshape(-1),
        )
        return sol.x, jnp.sum(sol.force_density * cells.length.reshape(-1))

    forces = []
    for i in range(n_steps):
        Feff = F + M @ (a0 * X + 4.0 / dt * Xd + Xdd) + C @ (a1 * X + Xd)
        Xn, fm = step(
            jnp.asarray(th0 + (i + 1) * float(mesh.mesh_period_angle) / spp), jnp.asarray(Feff)
        )
        Xn = np.asarray(Xn)
        Xddn = a0 * (Xn - X - dt * Xd - dt * dt * 0.25 * Xdd)
        Xd = Xd + dt * 0.5 * (Xdd + Xddn)
        X, Xdd = Xn, Xddn
        forces.append(float(fm))
    return np.array(forces)


def test_cell_space_newmark_equals_newmark_on_all_coordinates(setup):
    case, scene = setup
    spp, periods, speed, ray = 16, 3, 800.0, (25.0, 2.5e-6)
    r = simulate_hybrid(
        scene,
        case.modifications,
        case.torque,
        speed,
        steps_per_period=spp,
        periods=periods,
        keep_periods=periods,
        rayleigh=ray,
    )
    assert int(r.result) == 0
    ref = _reference_newmark(
        scene, case.modifications, case.torque, speed, spp, spp * periods, *ray
    )
    np.testing.assert_allclose(np.asarray(r.mesh_force), ref, rtol=1e-8, atol=1e-8 * ref.max())


def test_low_speed_is_the_quasi_static_response(setup):
    """At 5 rad/s (mesh frequency 16 Hz, far below the modes) the dynamic mesh force follows the
    quasi-static one at speed (centrifugal load included) within 0.5 % of the static force."""
    case, scene = setup
    spp, speed = 16, 5.0
    r = simulate_hybrid(
        scene,
        case.modifications,
        case.torque,
        speed,
        steps_per_period=spp,
        periods=3,
        keep_periods=1,
    )
    qs = jg.quasi_static(
        eqx.tree_at(lambda s: s.speed, scene, jnp.asarray(speed)),
        case.modifications,
        case.torque,
        r.theta,
    )
    f_qs = np.sum(
        np.asarray(qs.line_load) * np.asarray(scene.mesh.cells(0.0).length)[None], axis=(1, 2)
    )
    np.testing.assert_allclose(np.asarray(r.mesh_force), f_qs, atol=5e-3 * float(r.static_force))


def test_speed_sweep_maps_single_speeds(setup):
    case, scene = setup
    kw = dict(steps_per_period=16, periods=3, keep_periods=1)
    sw = hybrid_speed_sweep(scene, case.modifications, case.torque, [300.0, 900.0], **kw)
    one = simulate_hybrid(scene, case.modifications, case.torque, 900.0, **kw)
    np.testing.assert_allclose(sw.mesh_force[1], one.mesh_force, rtol=1e-10)
    with pytest.raises(ValueError, match="steps_per_period"):
        simulate_hybrid(scene, None, case.torque, 900.0, steps_per_period=2)

