"""Dynamics with backlash against an independent continuous-time reference
(benchmarks/_backlash_reference.py: a 1-DOF dead-zone model integrated by solve_ivp, segmented
at every stiffness and contact change; docs/backlash.md, "Evidence")."""

import jax.numpy as jnp
import numpy as np
import pytest

from benchmarks import (
    BACKLASH_REGIMES as REGIMES,
    BACKLASH_STEPS as STEPS,
    BACKLASH_SWEEP as SWEEP,
    BACKLASH_SWEEP_STEPS as SWEEP_STEPS,
    BACKLASH_WINDOW as WINDOW,
    backlash_model as jaxgear_model,
    backlash_reference as reference,
    dead_zone_response as response,
    dead_zone_sweep as sweep,
)
from jaxgear.dynamics import Both, DiffraxIntegrator, simulate, speed_sweep


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
    _p, speed_n, model = setup
    torsional = jaxgear_model(float(model.damping[0, 0] / model.scene.mass()[0, 0]), True)
    speed = REGIMES["double-sided"] * speed_n
    a = simulate(model, speed, integrator=STEPS, window=WINDOW)
    b = simulate(torsional, speed, integrator=STEPS, window=WINDOW)
    assert int(b.impacts_coast) > 0
    np.testing.assert_allclose(b.te_rms, a.te_rms, rtol=2e-2)


def test_diffrax_with_backlash_is_refused(setup):
    with pytest.raises(ValueError, match="diffrax solver with backlash"):
        simulate(setup[2], 1000.0, integrator=DiffraxIntegrator("tsit5"))


def jump(rms, rel=0.3):
    """The first speed index where the RMS changes by more than ``rel`` between neighbours."""
    r = np.asarray(rms)
    steps = np.abs(np.diff(r)) / np.minimum(r[1:], r[:-1])
    return int(np.argmax(steps > rel))


@pytest.mark.slow
def test_sweeps_up_and_down_match_the_reference_with_their_jumps(setup):
    p, speed_n, model = setup
    speeds = SWEEP * speed_n
    res = speed_sweep(model, speeds, integrator=SWEEP_STEPS, window=WINDOW, direction=Both())
    x0 = [p.force / (p.pair_stiffness * p.contact_ratio), 0.0]
    up = sweep(p, speeds, x0, 100, 8)
    down = sweep(p, speeds[::-1], x0, 100, 8)[::-1]
    for got, ref in ((res.results, up), (res.down, down)):
        ref_rms = np.array([r["te_rms"] for r in ref])
        np.testing.assert_allclose(np.asarray(got.te_rms), ref_rms, rtol=0.02)
        assert jump(got.te_rms) == jump(ref_rms)
