"""No recompilation: the jitted entry points trace once per structure, not per value.

A Python float passed to ``eqx.filter_jit`` is static and would recompile for each value; the
entry points convert operating values (torque, speed, relief depths) to arrays first. The tests
count what JAX traces through its public monitoring events (one ``jaxpr_trace_duration`` event
per traced function): after a first call with each kind of value (a Python float, an array),
calls with new values must trace nothing at all.
"""


import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx
import pytest

from _tracing import traced

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.scenes as js
import optimise as op



def _first_then_none(call, first_args, new_args):
    """Run ``call`` on each of ``first_args`` (it must trace something, or the listener is
    deaf), then on each of ``new_args``: returns the names traced by the second group. JAX's
    in-memory caches are cleared first, so that programs an earlier test of this worker traced
    for the same shapes do not answer the first calls."""
    jax.clear_caches()
    with traced() as first:
        for a in first_args:
            call(*a)
    assert first, "no trace recorded for the first calls: the monitoring event changed"
    with traced() as again:
        for a in new_args:
            call(*a)
    return again


def test_quasi_static_traces_once_for_new_values():
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=3)

    def solve(torque, depth):
        mm = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.3)
        law = jg.SmoothContact(2e-7)
        jg.quasi_static(
            mesh, jg.Modifications.symmetric(mm), torque, contact=law, positions_per_pitch=8
        )

    first = ((80.0, 3e-6), (jnp.asarray(75.0), 4e-6))
    new = ((60.0, 5e-6), (95.5, 12e-6), (jnp.asarray(70.0), 20e-6))
    assert _first_then_none(solve, first, new) == []


def test_simulate_traces_once_for_new_speeds():
    case = jio.load_case("accessory-spur").replace(slices=2)
    p = case.pair
    scene = js.TorsionalDynamics(
        case.mesh_model(),
        js.disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        js.disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    ).reduced()
    model = jd.dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    kw = dict(integrator=jd.Newmark(16), window=jd.SteadyState(3, 2))

    def run(speed):
        jd.simulate(model, speed, **kw)

    first = ((500.0,), (jnp.asarray(550.0),))
    new = ((650.0,), (900.25,), (jnp.asarray(1200.0),))
    assert _first_then_none(run, first, new) == []


def _tip_relief_problem(variables):
    case = jio.load_case("accessory-spur").replace(slices=3, positions_per_pitch=16)
    return jio.case_problem(case, variables, "te_rms", relief_blend=0.0)


# default tier: tests/test_traces.py::test_quasi_static_traces_once_for_new_values and test_simulate_traces_once_for_new_speeds (same claim, an entry point's new values trace nothing); minimise's path runs in tests/test_optimise.py
@pytest.mark.slow
def test_minimise_traces_once_for_new_starts_tolerances_and_caps():
    """One optimistix solve per call, traced once: x0, tol, max_iterations and the learning
    rate are traced values (the old chunked loop traced twice per call and again per tol)."""
    problem = _tip_relief_problem("tip_relief.depth")

    def minimise(x0, tol, cap):
        r = op.minimise(problem, x0, optx.LBFGS(tol, tol), max_iterations=cap, progress=False)
        assert r.history_x.shape == (r.iterations + 1, 1)

    first = (([0.4], 1e-6, 30),)
    new = (([1.3], 1e-8, 40), ([2.0], 3e-6, 25))
    assert _first_then_none(minimise, first, new) == []


# default tier: tests/test_traces.py::test_quasi_static_traces_once_for_new_values (same claim, an entry point's new values trace nothing; master_curve's path runs in tests/test_cli_robust.py::test_master_curve_flags_points_on_a_bound)
@pytest.mark.slow
def test_master_curve_traces_once_for_new_extents():
    problem = _tip_relief_problem("tip_relief.depth,tip_relief.extent")
    kw = {"coarse_depths": np.linspace(0.0, 3.0, 9), "iterations": 8}

    def curve(x0):
        op.master_curve(problem, x0, **kw)

    assert _first_then_none(curve, (([0.2, 0.3],),), (([0.25, 0.35],),)) == []
