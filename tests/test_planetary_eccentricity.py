"""Eccentricities of the sun, ring and carrier (jaxgear.planetary.Eccentricities) in the load sharing:
K_gamma over a turn against an independent spring model written from the geometry of the mesh
forces (tests/_planetary_stage.py: rigid_path_forces), the floating sun that absorbs a sun
eccentricity, a gradient against a central difference, and the refusals."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _planetary_stage import A_R, A_S, K_MESH, R_R, R_S, rigid_path_forces
from _planetary_stage import lin_parker_stage as stage

import jaxgear as jg
import jaxgear.planetary as jp

TORQUE = 3000.0
E = 30e-6  # m
F_NOM = TORQUE / (4 * R_S)  # N, the mean mesh force of four planets: the forces' scale


def turn(radius, points=24):
    """Mesh travels over one turn of a member of base radius ``radius`` relative to the
    carrier."""
    return np.arange(points) * 2 * np.pi * radius / points


def _solve(model, st, x):
    """The quasi-static solve (unilateral cells, one per mesh) at the mesh travels x (no pin
    error, given as an array: the carrier test's solves take the same program at 6 travels)."""
    return jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), jnp.asarray(TORQUE),
                                     jnp.asarray(x), np.zeros(st.n_planets))


def _sharing(model, st, x):
    """load_sharing at each mesh travel x (every mesh in contact: the same solve as
    :func:`_solve`, tests/test_planetary_mesh.py)."""
    n = st.n_planets
    return jax.vmap(lambda xi: jp.load_sharing(model, st, TORQUE, jnp.zeros(n), travel=xi))(
        jnp.asarray(x))


# the torsional model is the spring model's (rigid centres and pins); the planar one has
# bearings and pins of 1e13 N/m, within 1e-3 of the mean force
MODELS = ((jp.TorsionalPlanetary(), 1e-9), (jp.PlanarPlanetary(), 1e-3))


def test_sun_eccentricity_over_a_turn_against_the_spring_model():
    """The sun's toothed centre turns with the sun, +x / r_bs relative to the carrier: K_gamma
    repeats once per relative turn of the sun."""
    beta, n = 0.7, 4
    st = stage(n, jp.Eccentricities(sun=E, sun_phase=beta))
    x = turn(R_S)
    want = []
    for xi in x:
        angle = beta + xi / R_S
        want.append(rigid_path_forces(TORQUE, R_S, st.planet_angles, A_S, A_R, K_MESH, K_MESH,
                                      sun_centre=E * np.array([np.cos(angle), np.sin(angle)])))
    f_want = np.array([w[0] for w in want])
    k_want = np.array([w[1] for w in want])
    assert k_want.max() > 1.2 and f_want.min() > 0  # a real spread, every mesh in contact
    for model, rtol in MODELS:
        got = _sharing(model, st, x)
        np.testing.assert_allclose(got.sun_mesh_forces, f_want, rtol=0, atol=rtol * F_NOM)
        np.testing.assert_allclose(got.k_gamma, k_want, rtol=min(rtol, 1e-2))
    # the quasi-static solve with unilateral contact (every mesh loaded) is the same
    got = _solve(jp.TorsionalPlanetary(), st, x[::4])
    np.testing.assert_allclose(got.sun_mesh_forces, f_want[::4], rtol=1e-9)


def test_ring_eccentricity_over_a_turn_against_the_spring_model():
    """The ring's toothed centre turns -x / r_br relative to the carrier (with the ring fixed:
    once per carrier turn)."""
    beta = -1.1
    st = stage(4, jp.Eccentricities(ring=E, ring_phase=beta))
    x = turn(R_R)
    for model, rtol in MODELS:
        got = _sharing(model, st, x)
        for i, xi in enumerate(x):
            angle = beta - xi / R_R
            f, k = rigid_path_forces(TORQUE, R_S, st.planet_angles, A_S, A_R, K_MESH, K_MESH,
                                     ring_centre=E * np.array([np.cos(angle), np.sin(angle)]))
            np.testing.assert_allclose(got.ring_mesh_forces[i], f, rtol=0, atol=rtol * F_NOM)
            assert float(got.k_gamma[i]) == pytest.approx(k, rel=min(rtol, 1e-2))


def test_carrier_eccentricity_is_steady_in_the_carrier_frame_and_adds_to_pin_errors():
    """The carrier's pin circle stands off its axis by one vector e: every pin moves by e, the
    same at every carrier position; with a tangential pin error on planet 1 the two add."""
    beta = 2.0
    e_vec = E * np.array([np.cos(beta), np.sin(beta)])
    pin_error = np.array([15e-6, 0.0, 0.0, 0.0])
    st = stage(4, jp.Eccentricities(carrier=E, carrier_phase=beta))
    psi = np.asarray(st.planet_angles)
    t = np.stack([-np.sin(psi), np.cos(psi)], -1)
    r = np.stack([np.cos(psi), np.sin(psi)], -1)
    pins = np.stack([t @ e_vec + pin_error, r @ e_vec], -1)
    f, k = rigid_path_forces(TORQUE, R_S, psi, A_S, A_R, K_MESH, K_MESH, pins=pins)
    x = turn(R_R, 6)
    for model, rtol in MODELS:
        got = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), jnp.asarray(TORQUE),
                                        jnp.asarray(x), pin_error)
        np.testing.assert_allclose(got.sun_mesh_forces, np.broadcast_to(f, (x.size, 4)),
                                   rtol=0, atol=rtol * F_NOM)
        np.testing.assert_allclose(got.k_gamma, k, rtol=min(rtol, 1e-2))
    assert k > 1.1


def test_a_floating_sun_absorbs_a_sun_eccentricity():
    """A sun free to translate follows its own runout (the literature's reason to float the
    sun): K_gamma = 1 at every position, with four planets too; held, it is not."""
    ecc = jp.Eccentricities(sun=E, sun_phase=0.3)
    x = turn(R_S, 6)
    model = jp.PlanarPlanetary()
    for n in (3, 4):
        floating = _solve(model, stage(n, ecc, sun_bearing=0.0, pin=1e8), x)
        np.testing.assert_allclose(floating.k_gamma, 1.0, atol=1e-9)
        np.testing.assert_allclose(floating.sun_mesh_forces, TORQUE / (n * R_S), rtol=1e-9)
    held = _solve(model, stage(4, ecc, pin=1e8), x)
    assert float(held.k_gamma_max) > 1.02  # soft pins (1e8 N/m) take a share


def test_k_gamma_gradient_with_respect_to_the_eccentricity():
    def k_gamma(e):
        st = stage(4, jp.Eccentricities(sun=e, sun_phase=0.4), pin=1e8)
        return jp.load_sharing(jp.PlanarPlanetary(), st, TORQUE, jnp.zeros(4)).k_gamma

    e, h = 20e-6, 1e-8
    g = jax.grad(k_gamma)(e)
    fd = (k_gamma(e + h) - k_gamma(e - h)) / (2 * h)
    assert float(g) == pytest.approx(float(fd), rel=1e-6)


def test_refusals():
    with pytest.raises(ValueError, match=r"Eccentricities: sun = -1e-06 m is out of range"):
        jp.Eccentricities(sun=-1e-6)
    with pytest.raises(ValueError, match="carrier_phase"):
        jp.Eccentricities(carrier_phase=np.inf)
    with pytest.raises(ValueError, match="eccentricities"):
        stage(3, ecc=(1e-6, 0.0))
    with pytest.raises(ValueError, match="travel"):
        jp.load_sharing(jp.PlanarPlanetary(), stage(3), TORQUE, np.zeros(3), travel=np.ones(2))
    assert isinstance(stage(3).eccentricities, eqx.Module)


def test_dynamics_at_a_crawl_follow_the_turning_eccentricity():
    """planetary_dynamics takes the eccentricities at each step: at 1e-7 rad/s over a whole
    turn of the sun relative to the carrier (28 mesh periods of one spring per mesh) the
    recorded mesh forces are the spring model's at the same travels (torsional model)."""
    beta = 0.7
    st = stage(3, jp.Eccentricities(sun=E, sun_phase=beta))
    meshes = jp.ConstantMeshes(2 * np.pi * R_S / 28)
    run = jp.PlanetaryRun(TORQUE, steps_per_period=12, periods=28, keep_periods=28,
                          damping_ratio=0.05)
    got = jp.planetary_dynamics(jp.TorsionalPlanetary(), st, meshes, run, jnp.asarray(1e-7))
    assert int(got.result) == 0
    x = np.asarray(got.travel)
    assert x[-1] - x[0] == pytest.approx(2 * np.pi * R_S, rel=0.01)  # a turn of the sun
    want = np.array([
        rigid_path_forces(TORQUE, R_S, st.planet_angles, A_S, A_R, K_MESH, K_MESH,
                          sun_centre=E * np.array([np.cos(beta + xi / R_S),
                                                   np.sin(beta + xi / R_S)]))[0]
        for xi in x])
    np.testing.assert_allclose(got.sun_mesh_forces, want, rtol=0, atol=1e-8 * F_NOM)
    # the turning eccentricity loads one planet path after the other: at each instant the most
    # loaded path carries well over the mean, but over the whole turn every path reaches the
    # same peak, so the peak-based dynamic K_γ (each path's peak over the mean path's) is 1
    f = np.asarray(got.sun_mesh_forces)
    assert np.max(f.max(axis=1) / f.mean(axis=1)) > 1.2
    assert float(got.k_gamma) == pytest.approx(f.max(axis=0).max() / f.max(axis=0).mean())
    assert float(got.k_gamma) == pytest.approx(1.0, abs=1e-3)
