"""Dynamics with backlash against an independent continuous-time reference
(benchmarks/_backlash_reference.py: a 1-DOF dead-zone model integrated by solve_ivp, segmented
at every stiffness and contact change; docs/backlash.md, "Evidence")."""

import math

import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
from benchmarks._backlash_reference import dead_zone_pair, response, sweep
from jaxgear.dynamics import Damping, DiffraxIntegrator, Newmark, SteadyState, dynamic_model
from jaxgear.dynamics import simulate, speed_sweep
from jaxgear.scenes import RelativeApproach, TorsionalDynamics

# a spur pair, a flat stiffness per unit length (k(s) constant: the mesh stiffness steps
# between one and two pairs), thin teeth (A_sn = −1.5 µm each: j_bn = 2.82 µm), light load
Z1, Z2, MODULE, ALPHA, WIDTH = 30, 45, 3e-3, math.radians(20.0), 0.02
ALLOWANCE, TORQUE, ZETA, K_LENGTH = -1.5e-6, 60.0, 0.1, 1.2e10
INERTIAS = tuple(
    7800 * math.pi * WIDTH * r**4 / 2 for r in (Z1 * MODULE / 2 + MODULE, Z2 * MODULE / 2 + MODULE)
)
WINDOW = SteadyState(100, 8)
STEPS = Newmark(256)
# the three regimes at fractions of the linear resonance Ω_n = ω_n / z1 (ω_n² = ε_α k_1 / m)
REGIMES = {"no impact": 0.7, "single-sided": 1.0, "double-sided": 0.85}


def reference():
    p0 = dead_zone_pair(
        Z1, Z2, MODULE, ALPHA, (ALLOWANCE,) * 2, WIDTH, K_LENGTH, TORQUE, INERTIAS, 0.0
    )
    wn = math.sqrt(p0.pair_stiffness * p0.contact_ratio / p0.mass)
    alpha = 2 * ZETA * wn
    return (
        dead_zone_pair(
            Z1, Z2, MODULE, ALPHA, (ALLOWANCE,) * 2, WIDTH, K_LENGTH, TORQUE, INERTIAS, alpha
        ),
        wn / Z1,
        alpha,
    )


def jaxgear_model(alpha, torsional=False):
    pair = jg.GearPair(
        jg.Member(Z1, face_width=WIDTH, tooth_thickness_allowance=ALLOWANCE),
        jg.Member(Z2, face_width=WIDTH, tooth_thickness_allowance=ALLOWANCE),
        MODULE,
        ALPHA,
    )
    s = np.linspace(0.0, pair.path_of_contact, 3)
    mesh = jg.MeshModel.from_pair(pair, s, np.full(3, K_LENGTH), 1, coast=True)
    torsion = TorsionalDynamics(mesh, *INERTIAS)
    scene = torsion if torsional else torsion.reduced()
    return dynamic_model(scene, None, TORQUE, Damping("rayleigh", alpha=alpha, beta=0.0))


@pytest.fixture(scope="module")
def setup():
    p, speed_n, alpha = reference()
    return p, speed_n, jaxgear_model(alpha)


def test_reference_and_jaxgear_share_the_gear_data(setup):
    p, _, model = setup
    mesh = model.scene.mesh
    assert float(mesh.backlash) == pytest.approx(p.backlash, rel=1e-12)
    assert float(mesh.contact_ratio) == pytest.approx(p.contact_ratio, rel=1e-12)
    phase = float(mesh.coast_angle / mesh.mesh_period_angle) % 1.0
    assert phase == pytest.approx(p.coast_phase, rel=1e-10)


@pytest.mark.parametrize("regime", list(REGIMES))
def test_dte_rms_matches_the_reference_in_each_regime(setup, regime):
    p, speed_n, model = setup
    speed = REGIMES[regime] * speed_n
    r = simulate(model, speed, integrator=STEPS, window=WINDOW)
    ref = response(p, speed, [p.force / (p.pair_stiffness * p.contact_ratio), 0.0], 100, 8)
    assert float(r.te_rms) == pytest.approx(ref["te_rms"], rel=0.02)
    assert float(r.te_mean) == pytest.approx(ref["te_mean"], rel=0.02)
    drive, coast = int(r.impacts_drive), int(r.impacts_coast)
    if regime == "no impact":
        assert drive == coast == 0 and float(r.contact_loss) == 0.0
        assert ref["impacts"] == [0, 0]
    elif regime == "single-sided":
        assert drive > 0 and coast == 0 and float(r.coast_share) == 0.0
        assert ref["impacts"][0] > 0 and ref["impacts"][1] == 0
    else:
        assert drive > 0 and coast > 0 and float(r.coast_share) > 0.0
        assert ref["impacts"][0] > 0 and ref["impacts"][1] > 0
        assert float(r.coast_share) == pytest.approx(ref["coast_share"], abs=0.03)
        assert float(jnp.min(r.mesh_force)) < 0  # the coast flank's force counts negative


def test_torsional_scene_gives_the_relative_approach_response(setup):
    """Two rotations with the coast flanks (V = −cos β_b (r_b1, −r_b2)) move as the 1-DOF
    relative approach they reduce to (double-sided impacts)."""
    p, speed_n, model = setup
    torsional = jaxgear_model(float(model.damping[0, 0] / model.scene.mass()[0, 0]), True)
    speed = REGIMES["double-sided"] * speed_n
    a = simulate(model, speed, integrator=STEPS, window=WINDOW)
    b = simulate(torsional, speed, integrator=STEPS, window=WINDOW)
    assert int(b.impacts_coast) > 0
    np.testing.assert_allclose(b.te_rms, a.te_rms, rtol=2e-2)


def test_diffrax_with_backlash_is_refused(setup):
    with pytest.raises(ValueError, match="diffrax solver with backlash"):
        simulate(setup[2], 1000.0, integrator=DiffraxIntegrator("tsit5"))


SWEEP = np.linspace(0.6, 1.3, 29)


def jump(rms, rel=0.3):
    """The first speed index where the RMS changes by more than ``rel`` between neighbours."""
    r = np.asarray(rms)
    steps = np.abs(np.diff(r)) / np.minimum(r[1:], r[:-1])
    return int(np.argmax(steps > rel))


@pytest.mark.slow
def test_sweeps_up_and_down_match_the_reference_with_their_jumps(setup):
    p, speed_n, model = setup
    speeds = SWEEP * speed_n
    res = speed_sweep(model, speeds, integrator=STEPS, window=WINDOW, direction="both")
    x0 = [p.force / (p.pair_stiffness * p.contact_ratio), 0.0]
    up = sweep(p, speeds, x0, 100, 8)
    down = sweep(p, speeds[::-1], x0, 100, 8)[::-1]
    for got, ref in ((res.results, up), (res.down, down)):
        ref_rms = np.array([r["te_rms"] for r in ref])
        np.testing.assert_allclose(np.asarray(got.te_rms), ref_rms, rtol=0.02)
        assert jump(got.te_rms) == jump(ref_rms)
