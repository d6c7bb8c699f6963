"""No recompilation: the jitted entry points trace once per structure, not per value.

A Python float passed to ``eqx.filter_jit`` is static and would recompile for each value; the
entry points convert operating values (torque, speed, relief depths) to arrays first. The inner
jitted functions are decorated with ``eqx.debug.assert_max_traces(max_traces=None)`` so the tests
can count their traces.
"""

import equinox as eqx
import jax.numpy as jnp

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.scenes as js
from jaxgear._quasi_static import _quasi_static  # traces counted (tests/test_layout.py)
from jaxgear.dynamics._lumped import _run


def _traces(fn):
    return eqx.debug.get_num_traces(fn)


def test_quasi_static_traces_once_for_new_values():
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=3)
    kw = dict(positions_per_pitch=8)
    jg.quasi_static(mesh, case.modifications, 80.0, contact=jg.SmoothContact(), **kw)
    n = _traces(_quasi_static)
    for torque, depth in ((60.0, 5e-6), (95.5, 12e-6), (jnp.asarray(70.0), 20e-6)):
        mm = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.3)
        law = jg.SmoothContact(2e-7)
        jg.quasi_static(mesh, jg.Modifications.symmetric(mm), torque, contact=law, **kw)
    assert _traces(_quasi_static) == n


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
    jd.simulate(model, 500.0, **kw)
    n = _traces(_run)
    for speed in (650.0, 900.25, jnp.asarray(1200.0)):
        jd.simulate(model, speed, **kw)
    assert _traces(_run) == n


def _tip_relief_problem(variables):

    case = jio.load_case("accessory-spur").replace(slices=3, positions_per_pitch=16)
    return jio.case_problem(case, variables, "te_rms", relief_blend=0.0)


def test_minimise_traces_once_for_new_starts_tolerances_and_caps():
    """One optimistix solve per call, traced once: x0, tol, max_iterations and the learning
    rate are traced values (the old chunked loop traced twice per call and again per tol)."""
    import optimise as op
    from optimise._minimise import _solve

    problem = _tip_relief_problem("tip_relief.depth")
    n0 = _traces(_solve)
    op.minimise(problem, [0.4], progress=False, max_iterations=30)
    assert _traces(_solve) <= n0 + 1
    n = _traces(_solve)
    for x0, tol, cap in (([1.3], 1e-8, 40), ([2.0], 3e-6, 25)):
        r = op.minimise(problem, x0, tol=tol, max_iterations=cap, progress=False)
        assert r.history_x.shape == (r.iterations + 1, 1)
    assert _traces(_solve) == n


def test_master_curve_traces_once_for_new_extents():
    import numpy as np

    import optimise as op
    from optimise._master_curve import _grid, _refine

    problem = _tip_relief_problem("tip_relief.depth,tip_relief.extent")
    kw = {"coarse_depths": np.linspace(0.0, 3.0, 9), "iterations": 8}
    n0 = _traces(_refine), _traces(_grid)
    op.master_curve(problem, [0.2, 0.3], **kw)
    assert _traces(_refine) <= n0[0] + 1 and _traces(_grid) <= n0[1] + 1
    n = _traces(_refine), _traces(_grid)
    op.master_curve(problem, [0.25, 0.35], **kw)
    assert (_traces(_refine), _traces(_grid)) == n
