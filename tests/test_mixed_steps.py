"""One Newmark program for every automatic step count of a speed sweep (issue 47 §2).

A sweep whose speeds get several automatic N_s (:func:`jaxgear.dynamics.auto_steps_per_period`)
runs them through one compiled program (N_s an argument of it: the mesh table of the largest
N_s's size, a traced step count, masked statistics). The independent reference: each speed run
alone by :func:`jaxgear.dynamics.simulate`, the per-N_s program (its own table, static step
counts, unmasked statistics): the same steps, the same numbers (to 1e-12 relative; the
histories of the sweep are every m-th record of the run alone, m = N_s / min N_s). The
programs are counted with JAX's monitoring events (one trace per compiled function, after
``jax.clear_caches``: the persistent cache does not hide a trace).
"""

import contextlib

import jax
import jax.monitoring
import numpy as np
import pytest

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

_TRACE_EVENT = "/jax/core/compile/jaxpr_trace_duration"
RATIOS = (0.12, 0.3, 0.6, 1.0, 1.3)  # of the first critical speed: N_s 512, 256, 128, 64, 64
WINDOW = SteadyState(4, 2)
SCALARS = ("dynamic_factor", "dynamic_factor_tooth", "te_rms", "te_mean", "contact_loss")
HISTORIES = ("mesh_force", "transmission_error", "time", "theta", "static_te")


@contextlib.contextmanager
def traced():
    """The names of the functions JAX traces inside the block."""
    names = []

    def listen(event, duration, **kwargs):
        if event == _TRACE_EVENT:
            names.append(kwargs.get("fun_name", "?"))

    jax.monitoring.register_event_duration_secs_listener(listen)
    try:
        yield names
    finally:
        jax.monitoring.unregister_event_duration_listener(listen)


@pytest.fixture(scope="module")
def model():
    case = jio.load_case("accessory-spur").replace(slices=2)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2).reduced()
    return dynamic_model(scene, case.modifications, case.torque)


def _speeds(model):
    return np.array(RATIOS) * float(model.critical_speeds(1)[0])


def _same_as_alone(r, model, speeds, n_min):
    """Each speed of the sweep ``r`` (histories at ``n_min`` steps per period) against the
    speed run alone (``simulate``)."""
    ns = np.asarray(r.steps_per_period)
    for i, s in enumerate(speeds):
        one = simulate(model, float(s), window=WINDOW)
        assert int(one.steps_per_period) == ns[i]
        for f in SCALARS:
            np.testing.assert_allclose(float(getattr(r, f)[i]), float(getattr(one, f)), rtol=1e-12)
        # a fraction of F_s: a difference of forces, compared to 1e-12 F_s
        np.testing.assert_allclose(float(r.periodicity[i]), float(one.periodicity), atol=1e-12)
        m = int(ns[i]) // n_min
        np.testing.assert_allclose(float(r.time_step[i]), float(one.time_step) * m, rtol=1e-12)
        for f in HISTORIES:
            a, b = np.asarray(getattr(r, f)[i]), np.asarray(getattr(one, f))[m - 1 :: m]
            assert a.shape == b.shape == (WINDOW.keep_periods * n_min,)
            np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.max(np.abs(b)))
        assert int(r.result[i]) == int(one.result) == 0


def test_one_program_for_every_step_count(model):
    speeds = _speeds(model)
    ns = auto_steps_per_period(model, speeds)
    assert len(set(ns.tolist())) >= 3, ns  # the sweep needs several programs without it
    jax.clear_caches()
    with traced() as names:
        r = speed_sweep(model, speeds, window=WINDOW).results
    # one Newmark program (vmapped over the speeds of each N_s) and one table program
    assert names.count("_vmapped") == 1, names
    assert names.count("_prepare") == 1, names
    assert list(np.asarray(r.steps_per_period)) == list(ns)
    _same_as_alone(r, model, speeds, int(ns.min()))


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
            np.asarray(getattr(chunked, f)), np.asarray(getattr(whole, f)), rtol=1e-12, atol=0
        )


@pytest.mark.slow
def test_continuation_one_program_same_as_alone(model):
    """Continuation up over runs of equal N_s: one scan program; the first speed from the
    static equilibrium is the speed run alone."""
    speeds = _speeds(model)
    jax.clear_caches()
    with traced() as names:
        r = speed_sweep(model, speeds, window=WINDOW, direction=Up()).results
    assert names.count("_scans") == 1, names
    _same_as_alone(jax.tree.map(lambda a: a[:1], r), model, speeds[:1], 64)
