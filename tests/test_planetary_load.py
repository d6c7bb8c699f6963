"""Quasi-static load sharing among the planets with a planet-pin tangential error: the lumped
models' K_gamma against a spring model derived here by hand, the floating sun of a 3-planet
stage (equal shares whatever the error), a gradient, and the singular-stiffness refusal."""

import equinox as eqx
import jax
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.planetary as jp

ALPHA = np.radians(24.6)
R_SUN = 77.4e-3 / 2
K_MESH = 5e8
HELD = 1e13  # N/m on u = r theta, or N/m on a translation: "rigid"


def stage(n, sun_bearing=HELD, pin=HELD, carrier_u=HELD, ring_angle=ALPHA):
    """Lin & Parker's example masses and radii (their Table 1); bearings as asked, the ring and
    (unless told) the carrier held in rotation."""
    member = jp.PlanetaryMember.lumped
    return jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(0.4, 0.39, R_SUN, sun_bearing, 0.0),
        ring=member(2.35, 3.0, 275.0e-3 / 2, HELD, HELD),
        carrier=member(5.43, 6.29, 176.8e-3 / 2, HELD, carrier_u),
        planet=member(0.66, 0.61, 100.3e-3 / 2, pin, 0.0),
        sun_pressure_angle=ALPHA,
        ring_pressure_angle=ring_angle,
        sun_mesh_stiffness=K_MESH,
        ring_mesh_stiffness=K_MESH,
    )


def hand_spring_model(n, torque, errors, radial=0.0, a_r=ALPHA):
    """Rigid centres, rigid pins, ring and carrier held; the sun turns. Planet path j: the sun
    mesh k_s = k (u_s + u_j - e_j cos a) and the ring mesh k (-u_j - e_j cos a) in series
    (the planet's moment balance k_s delta_s = k_r delta_r), so
    F_j = k_eq (u_s - e_j (cos a_s + cos a_r)) with k_eq = k k / (k + k); the sun's balance
    sum F_j = T / r_s gives u_s, and F_j = T / (N r_s) + k_eq c (mean e - e_j). A radial
    error eps_j (outward) adds the offsets -eps sin a_s and +eps sin a_r: e_j c becomes
    e_j (cos a_s + cos a_r) + eps_j (sin a_s - sin a_r)."""
    k_eq = K_MESH * K_MESH / (2 * K_MESH)
    shift = errors * (np.cos(ALPHA) + np.cos(a_r)) + radial * (np.sin(ALPHA) - np.sin(a_r))
    forces = torque / (n * R_SUN) + k_eq * (np.mean(shift) - shift)
    return forces, forces.max() / forces.mean()


@pytest.mark.parametrize("n", [
    3,
    # default tier: tests/test_planetary_load.py::test_k_gamma_with_one_pin_error_against_a_hand_spring_model[3] (same claim)
    pytest.param(4, marks=pytest.mark.slow), pytest.param(5, marks=pytest.mark.slow)])
def test_k_gamma_with_one_pin_error_against_a_hand_spring_model(n):
    torque, errors = 3000.0, np.zeros(n)
    errors[0] = 20e-6  # planet 1's pin 20 um ahead (it unloads)
    forces, k_gamma = hand_spring_model(n, torque, errors)
    assert k_gamma > 1.05 and forces.min() > 0  # a real spread, every mesh in contact
    for model, rtol in ((jp.PlanarPlanetary(), 1e-3), (jp.TorsionalPlanetary(), 1e-9)):
        got = jp.load_sharing(model, stage(n), torque, errors)
        np.testing.assert_allclose(got.sun_mesh_forces, forces, rtol=rtol)
        np.testing.assert_allclose(got.ring_mesh_forces, forces, rtol=rtol)
        assert float(got.k_gamma) == pytest.approx(k_gamma, rel=rtol)


def test_radial_pin_errors_against_the_hand_spring_model():
    """Equal pressure angles: a radial error leaves the shares equal; unequal (24.6 and 20 deg):
    it acts through sin a_s - sin a_r."""
    radial = np.array([0.0, 100e-6, 0.0, 0.0])
    same = jp.load_sharing(jp.TorsionalPlanetary(), stage(4), 3000.0, np.zeros(4), radial)
    assert float(same.k_gamma) == pytest.approx(1.0, abs=1e-9)
    a_r = np.radians(20.0)
    errors = np.array([10e-6, 0.0, 0.0, 0.0])
    forces, k_gamma = hand_spring_model(4, 3000.0, errors, radial, a_r)
    for model, rtol in ((jp.PlanarPlanetary(), 1e-3), (jp.TorsionalPlanetary(), 1e-9)):
        got = jp.load_sharing(model, stage(4, ring_angle=a_r), 3000.0, errors, radial)
        np.testing.assert_allclose(got.sun_mesh_forces, forces, rtol=rtol)
        assert float(got.k_gamma) == pytest.approx(k_gamma, rel=rtol)


def test_a_floating_sun_shares_three_planets_equally():
    """Three forces on a sun free to translate, along lines 120 deg apart, balance only when
    equal: K_gamma = 1 whatever the pin errors."""
    errors = np.array([30e-6, 0.0, -10e-6])
    floating = jp.load_sharing(
        jp.PlanarPlanetary(), stage(3, sun_bearing=0.0, pin=1e8), 2000.0, errors
    )
    assert float(floating.k_gamma) == pytest.approx(1.0, abs=1e-9)
    assert float(floating.sun_mesh_forces.mean()) == pytest.approx(2000.0 / (3 * R_SUN), rel=1e-9)
    # four planets: the lines of action of planets 1 and 3 (2 and 4) are opposite, so the sun's
    # balance equalises them pairwise; it does not reach the most loaded pair, K_gamma stays
    e4 = np.array([30e-6, 0.0, 0.0, 0.0])
    rigid = jp.load_sharing(jp.PlanarPlanetary(), stage(4, pin=1e8), 3000.0, e4)
    float4 = jp.load_sharing(jp.PlanarPlanetary(), stage(4, sun_bearing=0.0, pin=1e8), 3000.0, e4)
    f = np.asarray(float4.sun_mesh_forces)
    assert f[0] == pytest.approx(f[2], rel=1e-9) and f[1] == pytest.approx(f[3], rel=1e-9)
    assert f[0] > float(rigid.sun_mesh_forces[0]) * 1.01  # planet 1 picks up load
    assert float(float4.k_gamma) == pytest.approx(float(rigid.k_gamma), rel=1e-6)


def test_k_gamma_gradient_against_finite_difference():
    model = jp.PlanarPlanetary()

    def k_gamma(e1):
        return jp.load_sharing(
            model, stage(4, pin=1e8), 3000.0, jax.numpy.array([e1, 0, 0, 0.0])
        ).k_gamma

    e1, h = 20e-6, 1e-8
    g = jax.grad(k_gamma)(e1)
    fd = (k_gamma(e1 + h) - k_gamma(e1 - h)) / (2 * h)
    assert float(g) == pytest.approx(float(fd), rel=1e-6)


def test_load_sharing_refuses_a_free_stage_and_a_wrong_error_shape():
    free = stage(3, carrier_u=0.0)  # the carrier free to turn: a mechanism
    with pytest.raises(eqx.EquinoxRuntimeError, match="stiffness is singular") as e:
        jp.load_sharing(jp.TorsionalPlanetary(), free, 100.0, np.zeros(3))
    # the message names the mechanism's coordinates: the free carrier's rotation
    coords = jp.TorsionalPlanetary().dof_names(free)
    carrier = [n for n in coords if n.endswith("_c")]
    assert carrier and all(n in str(e.value) for n in carrier)
    assert "\n" not in str(e.value).strip()
    with pytest.raises(ValueError, match=r"tangential_pin_errors must have shape \(3,\)"):
        jp.load_sharing(jp.PlanarPlanetary(), stage(3), 100.0, np.zeros(4))
