"""One Newmark program for every automatic step count of a speed sweep.

A sweep whose speeds get several automatic N_s (:func:`jaxgear.dynamics.auto_steps_per_period`)
runs them through one compiled program (N_s an argument of it: the mesh table of the largest
N_s's size, a traced step count, masked statistics). The independent reference: each speed run
alone by :func:`jaxgear.dynamics.simulate`, the per-N_s program (its own table, static step
counts, unmasked statistics): the same steps, the same numbers (to 1e-10 relative: the programs
and the calls' batch sizes differ, so XLA's rounding differs, measured up to 1.3e-12; the
histories of the sweep are every m-th record of the run alone, m = N_s / min N_s). The
programs are counted with JAX's monitoring events (one trace per compiled function, after
``jax.clear_caches``: the persistent cache does not hide a trace).
"""

import pathlib
import sys

import jax
import numpy as np
import pytest

from _tracing import traced

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import (
    Batching,
    SteadyState,
    Up,
    auto_steps_per_period,
    dynamic_model,
    simulate,
    speed_sweep,
)
from jaxgear.scenes import TorsionalDynamics, disc_inertia

RATIOS = (0.3, 0.6, 1.0, 1.3)  # of the first critical speed: N_s 256, 128, 64, 64
WINDOW = SteadyState(4, 2)
SCALARS = ("dynamic_factor", "dynamic_factor_tooth", "te_rms", "te_mean", "contact_loss")
HISTORIES = ("mesh_force", "transmission_error", "time", "theta", "static_te")


@pytest.fixture(scope="module")
def model():
    case = jio.load_case("accessory-spur").replace(slices=2)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2).reduced()
    return dynamic_model(scene, case.modifications, case.torque)


#: same steps, other programs and batch sizes: roundoff (measured up to 1.3e-12 relative)
RTOL = 1e-10


def _speeds(model):
    return np.array(RATIOS) * float(model.critical_speeds(1)[0])


def _same_as_alone(r, model, speeds, which, n_min):
    """The speeds ``which`` (indices) of the sweep ``r`` (histories at ``n_min`` steps per
    period) against each speed run alone (``simulate``: its own N_s's program)."""
    ns = np.asarray(r.steps_per_period)
    for i in which:
        one = simulate(model, float(speeds[i]), window=WINDOW)
        assert int(one.steps_per_period) == ns[i]
        for f in SCALARS:
            np.testing.assert_allclose(float(getattr(r, f)[i]), float(getattr(one, f)), rtol=RTOL)
        # a fraction of F_s: a difference of forces, compared to RTOL F_s
        np.testing.assert_allclose(float(r.periodicity[i]), float(one.periodicity), atol=RTOL)
        m = int(ns[i]) // n_min
        np.testing.assert_allclose(float(r.time_step[i]), float(one.time_step) * m, rtol=RTOL)
        for f in HISTORIES:
            a, b = np.asarray(getattr(r, f)[i]), np.asarray(getattr(one, f))[m - 1 :: m]
            assert a.shape == b.shape == (WINDOW.keep_periods * n_min,)
            np.testing.assert_allclose(a, b, rtol=0, atol=RTOL * np.max(np.abs(b)))
        assert int(r.result[i]) == int(one.result) == 0


@pytest.fixture(scope="module")
def sweep(model):
    """The sweep of :data:`RATIOS` from fresh in-memory caches, with the names JAX traced."""
    speeds = _speeds(model)
    jax.clear_caches()
    with traced() as names:
        r = speed_sweep(model, speeds, window=WINDOW).results
    return speeds, r, names


def test_one_program_for_every_step_count(model, sweep):
    """Three N_s, one Newmark program (vmapped over each N_s's speeds) and one table program;
    the speed of N_s 128 (records thinned by 2, padded to the 256 table) as run alone (those of
    256 and 64, the most padding, with the slow tier: one more pair of programs each)."""
    speeds, r, names = sweep
    ns = auto_steps_per_period(model, speeds)
    assert list(ns) == [256, 128, 64, 64]  # without it: three Newmark programs
    assert names.count("_vmapped") == 1, names
    assert names.count("_prepare") == 1, names
    assert list(np.asarray(r.steps_per_period)) == list(ns)
    _same_as_alone(r, model, speeds, [1], 64)


# default tier: tests/test_mixed_steps.py::test_one_program_for_every_step_count (same claim, a sweep's speed equals its run alone, at N_s 128)
@pytest.mark.slow
def test_largest_step_count_same_as_alone(model, sweep):
    speeds, r, _ = sweep
    _same_as_alone(r, model, speeds, [0, 2, 3], 64)


def test_chunked_sweep_same_as_whole(model):
    """Chunks of 2 speeds (the groups padded to whole chunks) give the same records."""
    speeds = _speeds(model)
    whole = speed_sweep(model, speeds, window=WINDOW).results
    done = []
    chunked = speed_sweep(
        model, speeds, window=WINDOW, batching=Batching(chunk_size=2, progress=done.append)
    ).results
    assert done[-1] == len(speeds)
    for f in SCALARS + HISTORIES:
        np.testing.assert_allclose(
            np.asarray(getattr(chunked, f)), np.asarray(getattr(whole, f)), rtol=RTOL, atol=0
        )


@pytest.mark.slow
def test_continuation_one_program_same_as_alone(model):
    """Continuation up over runs of equal N_s: one scan program; the first speed, from the
    static equilibrium, as run alone."""
    speeds = _speeds(model)
    jax.clear_caches()
    with traced() as names:
        r = speed_sweep(model, speeds, window=WINDOW, direction=Up()).results
    assert names.count("_scans") == 1, names
    assert list(np.asarray(r.steps_per_period)) == [256, 128, 64, 64]
    assert np.all(np.asarray(r.result) == 0)
    _same_as_alone(jax.tree.map(lambda a: a[:1], r), model, speeds[:1], [0], 64)


@pytest.mark.slow
def test_two_stage_train_traced_span(tmp_path):
    """A two-stage train (20 → 40, then 30 → 45: mesh periods 3 : 4, D = 3, a span of 4 N_s
    steps): N_s 768, 384, 192, static rows over spans of 3072, 1536 and 768 steps (batches of a
    traced count past 1024), one program; every speed and mesh as run alone."""
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
    from test_train import TORQUE, two_stage_train

    train = two_stage_train()[2]
    model = dynamic_model(train, jg.Modifications(), TORQUE)
    speeds = np.array([0.1, 0.25, 0.6]) * float(model.modes.omega[1]) / 20
    window = SteadyState(8, 4)
    jax.clear_caches()
    with traced() as names:
        r = speed_sweep(model, speeds, window=window).results
    ns = np.asarray(r.steps_per_period)
    assert list(ns) == [768, 384, 192]
    assert names.count("_vmapped") == 1 and names.count("_prepare") == 1, names
    for i, s in enumerate(speeds):
        one = simulate(model, float(s), window=window)
        m = int(ns[i]) // 192
        for a, b in zip(r.meshes, one.meshes, strict=True):
            for f in SCALARS + ("static_force",):
                np.testing.assert_allclose(float(getattr(a, f)[i]), float(getattr(b, f)), rtol=RTOL)
            for f in ("mesh_force", "transmission_error", "static_te"):
                x, y = np.asarray(getattr(a, f)[i]), np.asarray(getattr(b, f))[m - 1 :: m]
                np.testing.assert_allclose(x, y, rtol=0, atol=RTOL * np.max(np.abs(y)))
