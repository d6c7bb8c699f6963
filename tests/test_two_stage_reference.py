"""The independent reference of the two-stage coupled example (benchmarks/_two_stage_reference.py,
NumPy/SciPy only) checked against analytic facts: the textbook contact ratios of the gear data,
the kinematics of the mesh deflections, the torque-ratio static forces, the quasi-static limit of
the dynamic factor, the sun-ring phase by a second route, and the integrator against the
frequency response computed by a direct complex solve."""

import math

import numpy as np
import pytest

from benchmarks import (
    TWO_STAGE_SPEEDS,
    TwoStageReference,
    two_stage_dynamic_factors,
    two_stage_harmonic_state,
)

ALPHA = math.radians(20.0)
COS, SIN = math.cos(ALPHA), math.sin(ALPHA)


def test_contact_ratios_against_hand_values():
    """eps = g / p_b, g from the tip rolls (mm, m = 4, alpha = 20 deg, standard gears): sun 20
    (r 40, r_a 44), planet 30 (r 60, r_a 64), ring 80 internal (r 160, r_a 156), a = 100; pair
    32 (r 64, r_a 68) / 24 (r 48, r_a 52), a = 112."""
    pb = math.pi * 4 * COS  # 11.8085 mm
    sun, planet = math.sqrt(44**2 - (40 * COS) ** 2), math.sqrt(64**2 - (60 * COS) ** 2)
    ring = math.sqrt(156**2 - (160 * COS) ** 2)
    eps_sp = (sun + planet - 100 * SIN) / pb
    eps_pr = (planet - ring + 100 * SIN) / pb
    eps_gp = (math.sqrt(68**2 - (64 * COS) ** 2) + math.sqrt(52**2 - (48 * COS) ** 2)
              - 112 * SIN) / pb
    # worked by hand: (22.873 + 30.284 - 34.202) / 11.8085 etc.
    assert eps_sp == pytest.approx(1.6052, abs=2e-4)
    assert eps_pr == pytest.approx(1.9380, abs=2e-4)
    assert eps_gp == pytest.approx(1.6348, abs=2e-4)
    m = TwoStageReference()
    got = [p.contact_ratio for p in (m.sun_planet, m.planet_ring, m.gear_pinion)]
    assert got == pytest.approx([eps_sp, eps_pr, eps_gp], rel=1e-12)
    assert m.planet_ring.tip_radii[1] == pytest.approx(0.156)  # the ring's tip circle inside
    assert m.sun_planet.centre_distance == pytest.approx(0.100)
    assert m.planet_ring.centre_distance == pytest.approx(0.100)


def test_mesh_deflections_vanish_on_the_nominal_motion():
    """Willis with the ring held (omega_c = 1): sun 1 + 80/20 = 5, planets (absolute)
    1 - (20/30)(5 - 1) = -5/3, gear 5, pinion -5 * 32/24; and a rigid turn of stage 1."""
    m = TwoStageReference()
    nominal = np.array([1.0, 0.0, 5.0, *[-5.0 / 3.0] * 4, 5.0, -5.0 * 32 / 24])
    np.testing.assert_allclose(m.mesh_rows @ nominal, 0.0, atol=1e-15)
    rigid = np.array([1.0] * 7 + [0.0, 0.0])
    np.testing.assert_allclose((m.mesh_rows @ rigid)[:8], 0.0, atol=1e-15)


def test_static_forces_are_the_torque_ratio_values():
    """T_sun = 5000 / (1 + 80/20) = 1000 N m; F = T_sun / (4 r_bs) on every stage-1 mesh and
    T_sun / r_bg on the pair, at every pair count (the statics do not depend on stiffness)."""
    m = TwoStageReference()
    f_sun = 1000.0 / (4 * 0.040 * COS)
    f_pair = 1000.0 / (0.064 * COS)
    np.testing.assert_allclose(m.static_forces, [f_sun] * 8 + [f_pair], rtol=1e-12)
    w = 100.0
    for t in m.switch_times(w)[:-1] + 0.3 * np.diff(m.switch_times(w)):
        k = m.mesh_stiffness(t, w)
        theta = np.linalg.solve(m.stiffness_matrix(k), m.load)
        np.testing.assert_allclose(k * (m.mesh_rows @ theta), [f_sun] * 8 + [f_pair],
                                   rtol=1e-9)
    assert sorted(set(np.round(m.mean_mesh_stiffness / m.pair_stiffness, 6))) == pytest.approx(
        [1.6052, 1.6348, 1.9380], abs=1e-4)  # mean pair counts = eps


def test_sun_ring_phase_by_the_reversed_sun_driving_case():
    """Parker & Lin's sun-ring offset for the sun driving (the sun pushes the planet; from the
    engagement points of that direction) is s_bp - pi r_bp + 2 alpha r_bp + rho_s - rho_p
    - a sin alpha, rho the start rolls of the sun on its mesh (a sin alpha - planet tip roll)
    and of the planet on the ring mesh (ring tip roll - a sin alpha); this load direction is its
    mirror run backwards (s -> g - s), so Delta_rs = g_r - g_s - Delta_sun_driving (mod p_b)."""
    m = TwoStageReference()
    sp, pr = m.sun_planet, m.planet_ring
    r_bp, a = 0.060 * COS, 0.100
    s_bp = r_bp * (math.pi / 30 + 2 * (math.tan(ALPHA) - ALPHA))
    rho_s = a * SIN - math.sqrt(0.064**2 - r_bp**2)
    rho_p = math.sqrt(0.156**2 - (0.160 * COS) ** 2) - a * SIN
    sun_driving = s_bp - math.pi * r_bp + 2 * ALPHA * r_bp + rho_s - rho_p - a * SIN
    pb = sp.base_pitch
    expected = (pr.path_length - sp.path_length - sun_driving) % pb
    assert m.derived_sun_ring_offset == pytest.approx(expected, abs=1e-12)
    assert m.derived_sun_ring_offset / pb == pytest.approx(0.5483, abs=1e-4)
    # four planets in phase: z_s psi / 2 pi = 5 n, z_r psi / 2 pi = 20 n
    np.testing.assert_allclose(m.offsets[:4], 0.0, atol=1e-15)
    np.testing.assert_allclose(m.offsets[4:8], m.derived_sun_ring_offset, rtol=1e-12)


def test_slow_speed_limit():
    """Quasi-static limit (stage-1 mesh frequency 10 Hz, 1/45 of the lowest mode; damping ratio
    0.5 so that the ringing after each pair change dies before the next): the force just before
    every pair entry is the static force, the period-mean force is the static force, and the
    maximum force is the one just after an entry, 2 x static (ceil(eps) / floor(eps): the mesh
    deflection is continuous across the stiffness jump), within 1e-3."""
    m = TwoStageReference(damping_ratio=0.5)
    res = two_stage_dynamic_factors([2 * math.pi * 10.0 / 80], m, min_periods=2, tol=1e-6)
    np.testing.assert_allclose(res["pre_entry_ratio"], 1.0, atol=5e-4)
    np.testing.assert_allclose(res["mean_ratio"], 1.0, atol=1e-4)
    dfs = np.concatenate([res["sun"][0], res["ring"][0], res["pair"]])
    np.testing.assert_allclose(dfs, 2.0, atol=1e-3)
    np.testing.assert_allclose(dfs, 2 * res["pre_entry_ratio"][0], rtol=1e-9)


def test_integrator_against_the_frequency_response():
    """Constant mean mesh stiffness and a torque A sin(w t): the steady response is
    theta_0 + Im(H A e^{iwt}), H = (K - w^2 M + i w C)^-1, K = K_s + K_mesh_mean."""
    m = TwoStageReference(damping_ratio=0.2)
    A = np.zeros(9)
    A[0], A[8] = 200.0, -30.0  # on the carrier and the output pinion (N m)
    w = 2 * math.pi * 1000.0
    st = two_stage_harmonic_state(m, A, w, tol=1e-8)
    K = m.stiffness_matrix(m.mean_mesh_stiffness)
    X = np.linalg.solve(K - w**2 * m.mass_matrix + 1j * w * m.damping_matrix, A)
    theta0 = np.linalg.solve(K, m.load)
    t = np.linspace(0.0, st.period, 40, endpoint=False)
    theta, forces = st.sample(t)
    expected = theta0[:, None] + np.imag(X[:, None] * np.exp(1j * w * t)[None, :])
    scale = np.abs(X).max()
    assert np.abs(theta - expected).max() < 1e-5 * scale
    # amplitudes per coordinate
    amp = 0.5 * (theta.max(axis=1) - theta.min(axis=1))
    np.testing.assert_allclose(amp, np.abs(X), atol=2e-3 * scale)
    assert forces.min() > 0  # linear: every mesh in contact


def test_default_speeds_sweep_the_mesh_modes():
    """The default stage-1 mesh frequencies: one slow (below 1/10 of the lowest mode), one
    within 5 % of a mesh-dominated mode, and the range across the lowest three mesh-dominated
    modes (over half the strain energy in the meshes)."""
    m = TwoStageReference()
    f = m.z_ring * np.asarray(TWO_STAGE_SPEEDS) / (2 * np.pi)
    modes = m.modes_hz
    mesh_modes = np.unique(np.round(modes[m.mesh_energy_fractions() > 0.5], 3))[:3]
    assert len(TWO_STAGE_SPEEDS) == 8
    assert f.min() < 0.1 * modes.min()
    assert np.min(np.abs(f[:, None] / mesh_modes[None, :] - 1)) < 0.05
    assert f.max() > mesh_modes.max() and f[f > 0.1 * modes.min()].min() < mesh_modes.min()


def test_bad_speed_is_refused():
    with pytest.raises(ValueError, match="carrier_speeds"):
        two_stage_dynamic_factors([0.0])
