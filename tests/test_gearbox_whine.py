"""Gear whine of the coupled gearbox (:func:`jaxgear.gearbox.gearbox_whine`; docs/whine.md,
"A gearbox"): each stage's mesh orders from the quasi-periodic balance on the torus of the
stages' mesh phases.

References, each apart from the code under test:

* the coupled gearbox's own time integration (:func:`jaxgear.gearbox.gearbox_dynamics`,
  Newmark with unilateral contact) where it keeps contact, its mesh forces Fourier analysed
  here at each stage's own mesh frequency over a window of whole periods of both stages;
* the limit of a gearbox whose shaft and output hold go to zero stiffness: each stage is then a
  pair under constant torques, whose whine the single-pair path gives
  (:func:`jaxgear.dynamics.whine_response` on a :class:`jaxgear.scenes.TorsionalDynamics`
  scene: its own mesh table, structure vectors and harmonic balance).
"""

import math

import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.planetary as jp
from jaxgear import gearbox as gb
from jaxgear.dynamics import (
    HarmonicBalance,
    ModalDamping,
    QuasiPeriodicBalance,
    dynamic_model,
    whine_response,
)
from jaxgear.scenes import TorsionalDynamics

K_U = 1.4e10  # N/m per m of contact line
MODULE, ALPHA, B = 3e-3, math.radians(20.0), 0.03
# two spur pairs, 24/40 then 25/41 (pinions driven): the second stage meshes at
# 25 x 24/40 = 15 input-speed units against the first's 24, a ratio of 5/8
TEETH = ((24, 40), (25, 41))


def _disc(z):
    r = 0.5 * MODULE * z
    return 0.5 * 7850.0 * math.pi * B * r**4


def _stage(z1, z2, relief=0.0):
    pair = jg.GearPair(jg.Member(z1, face_width=B), jg.Member(z2, face_width=B), MODULE, ALPHA)
    mesh = jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(K_U)), 1)
    mods = jg.Modifications()
    if relief:
        mods = jg.Modifications.symmetric(
            jg.MemberModification(tip_relief_depth=relief, tip_relief_extent=0.3))
    stage = gb.TorsionalPairGearboxStage((_disc(z1), _disc(z2)), pair.base_radii, K_U * B * 1.6,
                                         input=0, mesh=mesh, modifications=mods)
    return stage, mesh


def _two_pairs(shaft=2e5, output=2e5, relief=10e-6, **run):
    stages = [_stage(*t, relief)[0] for t in TEETH]
    return gb.GearboxTorsional(tuple(stages), [shaft]), gb.GearboxRun(200.0, output, **run)


def _pick(w, mesh, order):
    g = np.asarray(w.order_group)
    o = np.asarray(w.group_order)
    return int(np.flatnonzero((g == w.mesh_group[mesh]) & (o == order))[0])


@pytest.mark.slow
def test_two_pairs_against_newmark():
    """Two relieved spur pairs (tip relief 10 µm over 0.3 of the path) joined by a shaft, at
    30 and 80 rad/s (first mesh 115 and 306 Hz; coupled modes 403, 1710 Hz and up), no contact
    loss, ``nonlinearity`` ~ 1e-16: each mesh's order 1 within 0.5 % and 0.5°, order 2 within
    2.5 % and 2° of Newmark's (640 steps per first-mesh period, converged: 2560 steps move no
    line by more than 0.01 %; 40 blocks of the second mesh's period, the last 5 kept: 8 periods
    of the first mesh and 5 of the second, so that every line of both is a whole number of
    cycles). Measured: orders 1 within 0.1 % and 0.17°, orders 2 within 1.8 % and 1.7° (the
    first mesh's order 2 is 1e-4 of the static force; the sampled engagement of the relieved
    cells moves it by a few per cent between 144 and 288 positions). The same on
    ``positions=(144, 72)``: the second pair's axis halved (its lines move by 0.25 % at most,
    the first pair's by 0.001 %)."""
    chain, run = _two_pairs(steps_per_period=640, periods=40, keep_periods=5)
    speeds = [30.0, 80.0]
    ws = [gb.gearbox_whine(chain, run, speeds, QuasiPeriodicBalance(16, 1), positions=p)
          for p in (144, (144, 72))]  # (144, 72): the slower second pair on half the points
    for w in ws:
        assert not np.any(np.asarray(w.contact_loss))
        assert float(np.max(np.asarray(w.nonlinearity))) < 1e-6
        np.testing.assert_allclose(np.asarray(w.orders)[_pick(w, 1, 1)], 15 / 24, rtol=1e-12)
    for i, speed in enumerate(speeds):
        r = gb.gearbox_dynamics(chain, run, speed)
        assert int(r.result) == 0 and float(np.min(np.asarray(r.mesh_forces))) > 0.0
        t, f = np.asarray(r.time), np.asarray(r.mesh_forces)
        for w in ws:
            w1 = 2 * math.pi * float(w.frequency[i])
            np.testing.assert_allclose(float(w.frequency[i]), 24 * speed / (2 * math.pi),
                                       rtol=1e-12)
            for mesh in (0, 1):
                for order, amp, deg in ((1, 0.005, 0.5), (2, 0.025, 2.0)):
                    j = _pick(w, mesh, order)
                    nu = float(w.orders[j]) * w1
                    ref = 2 * np.mean(f[:, mesh] * np.exp(-1j * nu * t))
                    got = complex(w.mesh_force[i, j, mesh])
                    assert abs(abs(got) / abs(ref) - 1) < amp, (speed, mesh, order, got, ref)
                    assert abs(math.degrees(np.angle(got / ref))) < deg, (speed, mesh, order)


@pytest.mark.slow
def test_uncoupled_limit_is_each_pairs_own_whine():
    """Shaft and output hold at 1e-3 N m/rad (the pairs' torsional mesh stiffness r_b² k is
    about 4e5 N m/rad): each stage runs under constant torques, a pair of its own. Its whine
    (unrelieved: every cell on the path loaded, so that both models average the same mean
    stiffness for the modal damping) equals the single-pair whine of its TorsionalDynamics
    scene at its own pinion speed and torque, ModalDamping(0.05), HarmonicBalance(8) on the same
    48 positions: TE orders 1-8 within 1e-5 of order 1 and mesh force within 1e-5 of the static
    force (measured 1.4e-6 and 1.5e-6)."""
    soft, H, P = 1e-3, 8, 48
    stages = [_stage(*t) for t in TEETH]
    chain = gb.GearboxTorsional(tuple(s for s, _ in stages), [soft])
    run = gb.GearboxRun(200.0, soft, mean_positions=P, damping_ratio=0.05)
    speed, torque = 50.0, 200.0
    w = gb.gearbox_whine(chain, run, speed, QuasiPeriodicBalance(H, 1), positions=P)
    assert w.mesh_group == (0, 1)
    for k, (stage, mesh) in enumerate(stages):
        scene = TorsionalDynamics(mesh, float(stage.inertias[0]), float(stage.inertias[1]))
        model = dynamic_model(scene, None, torque, ModalDamping(0.05), positions_per_pitch=P)
        ref = whine_response(model, speed, HarmonicBalance(H), positions=P)
        pick = [0] + [_pick(w, k, o) for o in range(1, H + 1)]
        te, te_ref = np.asarray(w.transmission_error[0, pick, k]), np.asarray(
            ref.transmission_error[0, :, 0])
        f, f_ref = np.asarray(w.mesh_force[0, pick, k]), np.asarray(ref.mesh_force[0, :, 0])
        # orders 1-8 (the mean differs by the single pair's TE reference e_ref)
        assert np.max(np.abs(te[1:] - te_ref[1:])) < 1e-5 * abs(te_ref[1])
        assert np.max(np.abs(f - f_ref)) < 1e-5 * abs(f_ref[0])
        # the next stage: pinion speed and torque through this stage's ratio
        speed, torque = speed * TEETH[k][0] / TEETH[k][1], torque * TEETH[k][1] / TEETH[k][0]


def test_bad_inputs_one_line():
    chain, run = _two_pairs(relief=0.0)
    method = QuasiPeriodicBalance(2, 0)
    cases = [
        (lambda: gb.gearbox_whine(chain, run, 10.0, jg.dynamics.HarmonicBalance(2)),
         TypeError, "method"),
        (lambda: gb.gearbox_whine(chain, run, 10.0, method, positions=8),
         ValueError, "positions = 8.*>= 4 harmonics \\+ 1 = 9"),
        (lambda: gb.gearbox_whine(chain, run, 10.0, method, positions=(12,)),
         ValueError, "positions = \\(12,\\).*2 positive ints"),
        (lambda: gb.gearbox_whine(chain, run, 10.0, method, positions=(12, 8)),
         ValueError, "positions = \\(12, 8\\).*>= 4 harmonics \\+ 1 = 9"),
        (lambda: gb.gearbox_whine(chain, run, [10.0, 0.0], method, positions=12),
         ValueError, "input_speeds"),
        (lambda: gb.gearbox_whine("box", run, 10.0, method), ValueError, "chain"),
    ]
    springs = gb.GearboxTorsional((gb.PairGearboxStage((1e-3, 2e-3), (0.03, 0.05), 1e9),), [])
    cases.append((lambda: gb.gearbox_whine(springs, run, 10.0, method, positions=12),
                  ValueError, "no stage with contact cells"))
    # stepped planets of two tooth counts (30 and 22): the stage's cells repeat only after a
    # pattern of several mesh periods
    sun = jg.GearPair(jg.Member(20, face_width=0.05), jg.Member(30, face_width=0.05), 4e-3,
                      ALPHA, center_distance=0.1)
    ring = jg.InternalGearPair(jg.Member(22, face_width=0.05, dedendum_coeff=1.4),
                               jg.Member(-72, face_width=0.05), 4e-3, ALPHA,
                               center_distance=0.1)
    meshes = tuple(jg.MeshModel.from_pair(p, *jg.stiffness_table(p, jg.Uniform(K_U)), 1)
                   for p in (sun, ring))
    stepped = gb.CompoundPlanetaryStage.from_pairs(
        sun, ring, 2 * np.pi * np.arange(4) / 4, (0.5, 2.0, 1.6e-3, 9e-3), 5.0, (1.1e9, 1.3e9),
        1e9, jp.Central.SUN, jp.Central.CARRIER, meshes)
    box = gb.GearboxTorsional((stepped, chain.stages[0]), [1e6])
    cases.append((lambda: gb.gearbox_whine(box, run, 10.0, method, positions=12),
                  ValueError, "stage 1 \\(CompoundPlanetaryStage\\).*do not repeat"))
    for call, kind, match in cases:
        with pytest.raises(kind, match=match) as e:
            call()
        assert "\n" not in str(e.value)
    assert np.all(np.isfinite(np.asarray(
        gb.gearbox_whine(chain, run, jnp.array([10.0]), method, positions=12).mesh_force)))


@pytest.mark.slow
def test_planetary_stage_driving_a_pair_against_newmark():
    """The planetary stage of examples/gearbox_two_stage.py (four planets, ring held, carrier
    in, sun out; unrelieved spur meshes) whose sun drives a 25/41 spur pair (mesh frequencies
    80 and 125 carrier-speed units: 16 planetary periods hold 25 of the pair's), carrier at
    10 rad/s, no contact loss: every mesh's orders 1-2 within 1 % and 2.5° of Newmark's (256
    steps per pair period, the last 16 planetary periods). Measured: 0.8 % and 1.5°. On the same
    gearbox with a 50 mm wide pair the balance moved by less than 0.05 % from 144 to 288
    positions and Newmark by up to 0.5° from 256 to 1024 steps (the unrelieved meshes'
    stiffness jumps): the remaining difference is mostly Newmark's."""
    from _examples import load_example

    chain, run = load_example("gearbox_two_stage").two_stage(steps_per_period=256, periods=80,
                                                             keep_periods=16)
    pair, _ = _stage(25, 41)
    chain = gb.GearboxTorsional((chain.stages[0], pair), chain.shaft_stiffnesses)
    speed = 10.0
    w = gb.gearbox_whine(chain, run, speed, QuasiPeriodicBalance(16, 1), positions=144)
    assert w.mesh_group == (0,) * 8 + (1,)
    assert not np.any(np.asarray(w.contact_loss))
    np.testing.assert_allclose(np.asarray(w.orders)[_pick(w, 8, 1)], 125 / 80, rtol=1e-12)
    r = gb.gearbox_dynamics(chain, run, speed)
    assert int(r.result) == 0 and float(np.min(np.asarray(r.mesh_forces))) > 0.0
    t, f = np.asarray(r.time), np.asarray(r.mesh_forces)
    w1 = 2 * math.pi * float(w.frequency[0])
    for mesh in range(9):
        for order in (1, 2):
            j = _pick(w, mesh, order)
            ref = 2 * np.mean(f[:, mesh] * np.exp(-1j * float(w.orders[j]) * w1 * t))
            got = complex(w.mesh_force[0, j, mesh])
            assert abs(abs(got) / abs(ref) - 1) < 0.01, (mesh, order, got, ref)
            assert abs(math.degrees(np.angle(got / ref))) < 2.5, (mesh, order, got, ref)
