"""The Python API's own inputs: the public constructors and entry points refuse a
wrong shape, a wrong type, NaN/inf or a value outside its documented range in one
``ValueError`` line naming the argument, its value (or shape) and the allowed range, raised
before any tracing (no JAX frame in the traceback), never an error deep inside JAX; and the
checks leave ``jax.jit``, ``jax.vmap`` and ``jax.grad`` through those constructors working
(traced values are not checked eagerly).
"""

from __future__ import annotations

import functools
import math
import traceback

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
import jaxgear.scenes as js

NAN, INF = math.nan, math.inf


@functools.cache
def _mesh():
    """The accessory pair's mesh, small (4 slices, 8 positions per pitch)."""
    case = jio.load_case("accessory-spur")
    return case, case.replace(slices=4, positions_per_pitch=8).mesh_model()


def _refused(fn, *words: str) -> str:
    """``fn()`` raises one ``ValueError`` line that contains each of ``words``, before any
    tracing: no frame of JAX (nor of an ``eqx.error_if``) in its traceback."""
    with pytest.raises(ValueError) as info:
        fn()
    msg = str(info.value)
    assert "\n" not in msg.strip(), msg
    for w in words:
        assert w in msg, (w, msg)
    frames = [f.filename for f in traceback.extract_tb(info.value.__traceback__)]
    assert not any("jax/_src" in f or "equinox/_errors" in f for f in frames), frames[-3:]
    return msg


def _qs(**kw):
    case, mesh = _mesh()
    args = dict(modifications=case.modifications, torque=case.torque)
    args.update(kw)
    return lambda: jg.quasi_static(mesh, args.pop("modifications"), args.pop("torque"), **args)


@pytest.mark.parametrize(
    "kw,words",
    [
        (dict(torque=jnp.array([80.0, 90.0])), ("torque must have shape ()", "got (2,)")),
        (dict(torque=np.ones((1, 1))), ("torque must have shape ()",)),
        (dict(theta=jnp.zeros((2, 3))), ("theta must have shape (n,) [rad], got (2, 3)",)),
        (dict(theta=np.zeros(0)), ("theta must have shape (n,)",)),
        (dict(theta=[0.1, NAN]), ("theta[1] = nan rad", "finite")),
        (dict(modifications="tip"), ("modifications = 'tip'", "jaxgear.Modifications")),
        (dict(modifications=(jg.Modifications(), 3)), ("modifications[1] = 3",)),
        (dict(torque=-5.0), ("quasi_static: torque = -5 N·m is out of range", "allowed > 0")),
        (dict(torque=0.0), ("torque = 0 N·m", "allowed > 0")),
        (dict(torque=NAN), ("torque = nan N·m",)),
        (dict(torque=INF), ("torque = inf N·m",)),
        (dict(torque="80"), ("torque = '80' is not a number",)),
        (dict(torque=None), ("torque = None is not a number",)),
        (dict(speed=-1.0), ("speed = -1 rad/s", "allowed >= 0")),
        (dict(speed=NAN), ("speed = nan rad/s",)),
    ],
)
def test_quasi_static_inputs(kw, words):
    _refused(_qs(**kw), "quasi_static", *words)


def test_quasi_static_scene():
    case, _ = _mesh()
    _refused(lambda: jg.quasi_static(case.pair, None, 80.0), "scene = ", "MeshModel")


def test_scene_constructors():
    _, mesh = _mesh()
    _refused(lambda: js.RigidMesh("mesh"), "RigidMesh: mesh = 'mesh'", "MeshModel")
    _refused(lambda: js.TorsionalPair(None), "TorsionalPair: mesh = None", "MeshModel")
    _refused(
        lambda: js.TorsionalPair(mesh, -1.0),
        "TorsionalPair: output_stiffness = -1 N·m/rad is out of range",
        "allowed > 0",
    )
    _refused(lambda: js.TorsionalPair(mesh, NAN), "output_stiffness = nan")
    dyn = jg.scenes.TorsionalDynamics
    _refused(lambda: dyn(mesh, -1e-3, 4e-3), "TorsionalDynamics: inertia_pinion = -0.001 kg·m²")
    _refused(lambda: dyn(mesh, 1e-3, INF), "TorsionalDynamics: inertia_gear = inf kg·m²")
    _refused(lambda: dyn(mesh, 1e-3, 1e-3, shaft_load=0.0), "shaft_load = 0 N·m/rad")
    _refused(lambda: dyn("mesh", 1e-3, 1e-3), "TorsionalDynamics: mesh = 'mesh'")


def _pair(p1=None, p2=None, **kw):
    args = dict(normal_module=2e-3, normal_pressure_angle=math.radians(20))
    args.update(kw)
    return jg.GearPair(p1 or jg.Member(20), p2 or jg.Member(40), **args)


@pytest.mark.parametrize(
    "fn,words",
    [
        (lambda: _pair(jg.Member(teeth=NAN)), ("pinion.teeth = nan", "integer >= 5")),
        (lambda: _pair(p2=jg.Member(teeth="40")), ("gear.teeth = '40'",)),
        (lambda: _pair(jg.Member(20, face_width=INF)), ("pinion.face_width = inf m",)),
        (lambda: _pair(jg.Member(20, profile_shift=NAN)), ("pinion.profile_shift = nan",)),
        (lambda: _pair(jg.Member(20, addendum_coeff=INF)), ("pinion.addendum_coeff = inf",)),
        (lambda: _pair(jg.Member(20, bore_radius=NAN)), ("pinion.bore_radius = nan m",)),
        (
            lambda: _pair(jg.Member(20, tooth_thickness_allowance=-INF)),
            ("pinion.tooth_thickness_allowance = -inf m",),
        ),
        (lambda: _pair(normal_module=INF), ("normal_module = inf m",)),
        (lambda: _pair(normal_module="2"), ("normal_module = '2' is not a number",)),
        (lambda: _pair(helix_angle=NAN), ("helix_angle = nan rad",)),
        (lambda: _pair(center_distance=INF), ("center_distance = inf m",)),
        (lambda: _pair("pinion"), ("GearPair: pinion = 'pinion'", "jaxgear.Member")),
    ],
)
def test_gear_pair_inputs(fn, words):
    _refused(fn, *words)


@pytest.mark.parametrize(
    "kw,words",
    [
        (dict(tip_relief_depth=-1e-5), ("tip_relief_depth = -1e-05 m", "allowed >= 0 m")),
        (dict(tip_relief_depth=NAN), ("tip_relief_depth = nan m",)),
        (dict(tip_relief_depth=np.float32(-1e-5)), ("tip_relief_depth = -1e-05 m",)),
        (dict(tip_relief_extent=0.0), ("tip_relief_extent = 0", "allowed (0, 1]")),
        (dict(tip_relief_extent=1.5), ("tip_relief_extent = 1.5",)),
        (dict(root_relief_depth=-1e-6), ("root_relief_depth = -1e-06 m",)),
        (dict(root_relief_extent=INF), ("root_relief_extent = inf",)),
        (dict(crowning_depth=-1e-6), ("crowning_depth = -1e-06 m",)),
        (dict(end_relief_depth=INF), ("end_relief_depth = inf m",)),
        (dict(end_relief_extent=0.6), ("end_relief_extent = 0.6", "allowed (0, 0.5]")),
        (dict(helix_slope_deviation=NAN), ("helix_slope_deviation = nan m",)),
        (dict(relief_blend=-0.1), ("relief_blend = -0.1", "allowed >= 0")),
        (dict(end_relief_blend=INF), ("end_relief_blend = inf",)),
        (
            dict(profile_deviation_roll=[0.0, 0.5, 0.5], profile_deviation=[0.0, 1e-6, 0.0]),
            ("profile_deviation_roll = [0.0, 0.5, 0.5]", "ascending"),
        ),
        (
            dict(profile_deviation_roll=[0.0, 1.0], profile_deviation=[0.0, NAN]),
            ("profile_deviation[1] = nan m",),
        ),
    ],
)
def test_member_modification_inputs(kw, words):
    _refused(lambda: jg.MemberModification(**kw), "MemberModification", *words)


def test_modifications_member_types():
    _refused(lambda: jg.Modifications(pinion="tip"), "Modifications: pinion = 'tip'")
    _refused(
        lambda: jg.Modifications(deviations=np.zeros(3)), "Modifications: deviations = "
    )


@pytest.mark.parametrize(
    "kw,words",
    [
        (dict(single_pitch=[NAN] * 45), ("single_pitch[0] = nan m",)),
        (dict(single_pitch=[0.0] * 44 + [INF]), ("single_pitch[44] = inf m",)),
        (dict(single_pitch=[0.0] * 45, runout=-1e-6), ("runout = -1e-06 m", "allowed >= 0")),
        (dict(single_pitch=[0.0] * 45, runout=NAN), ("runout = nan m",)),
        (dict(single_pitch=[0.0] * 45, runout_phase=INF), ("runout_phase = inf rad",)),
        (dict(single_pitch=[0.0] * 45, profile_slope=NAN), ("profile_slope[0] = nan m",)),
        (dict(single_pitch=[0.0] * 45, helix_form=[0.0] * 44 + [NAN]), ("helix_form[44]",)),
    ],
)
def test_gear_deviations_inputs(kw, words):
    _refused(lambda: jg.GearDeviations(**kw), "GearDeviations", *words)


def test_deviations_member_types():
    _refused(lambda: jg.Deviations(pinion=np.zeros(45)), "Deviations: pinion = ", "GearDeviations")


def test_stiffness_table_inputs():
    case, _ = _mesh()
    _refused(
        lambda: jg.stiffness_table(case.pair, jg.Weber(), youngs_modulus=NAN),
        "stiffness_table: youngs_modulus = nan Pa",
    )
    _refused(
        lambda: jg.stiffness_table(case.pair, jg.Weber(), poisson_ratio=0.5),
        "poisson_ratio = 0.5",
        "[0, 0.5)",
    )
    _refused(lambda: jg.stiffness_table(case.pair, jg.Weber(), n_points=1.5), "n_points = 1.5")
    _refused(lambda: jg.stiffness_table("pair", jg.Weber()), "pair = 'pair'", "GearPair")
    _refused(
        lambda: jg.stiffness_table(case.pair, jg.Uniform(INF)),
        "stiffness_per_length",
    )


@pytest.mark.parametrize(
    "fn,words",
    [
        (lambda: jd.ModalBasis(4, speed=INF), ("speed = inf",)),
        (lambda: jd.DiffraxIntegrator(rtol=INF), ("rtol = inf",)),
        (lambda: jd.DiffraxIntegrator(atol=True), ("atol = True",)),
    ],
)
def test_dynamics_settings_inputs(fn, words):
    _refused(fn, *words)


def test_hertz_pressure_inputs():
    case, _ = _mesh()
    _refused(lambda: jd.HertzPressure(case.pair, INF, 0.3), "youngs_modulus = inf Pa")
    _refused(lambda: jd.HertzPressure(case.pair, 210e9, NAN), "poisson_ratio = nan")


@functools.cache
def _dynamic():
    """A small lumped model of the accessory pair (torsional, 2 slices, 8 positions)."""
    case = jio.load_case("accessory-spur").replace(slices=2)
    scene = jg.scenes.TorsionalDynamics(case.mesh_model(), 1e-3, 4e-3)
    model = jd.dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=8)
    return case, scene, model


def test_dynamics_entries():
    case, scene, model = _dynamic()
    kw = dict(integrator=jd.Newmark(16), window=jd.SteadyState(4, 2))
    _refused(lambda: jd.simulate(model, -1.0, **kw), "simulate: speed = -1 rad/s", "> 0")
    _refused(lambda: jd.simulate(model, NAN, **kw), "simulate: speed = nan rad/s")
    _refused(
        lambda: jd.simulate(model, jnp.array([1.0, 2.0]), **kw),
        "simulate: speed must have shape () [rad/s], got (2,)",
    )
    _refused(lambda: jd.speed_sweep(model, [100.0, INF], **kw), "speeds[1] = inf rad/s")
    # the automatic span is a planetary stage's (automatic_span): refused here before any run
    auto = dict(integrator=jd.Newmark(16), window=jd.SteadyState(None, 2))
    _refused(lambda: jd.simulate(model, 100.0, **auto), "window periods = None", ">= 2")
    _refused(lambda: jd.speed_sweep(model, [100.0], **auto), "window periods = None")
    mods = case.modifications
    _refused(lambda: jd.dynamic_model(scene, mods, -5.0), "dynamic_model: torque = -5 N·m")
    _refused(lambda: jd.dynamic_model(scene, "tip", 80.0), "dynamic_model: mods = 'tip'")
    _refused(lambda: jd.dynamic_model(scene.mesh, mods, 80.0), "dynamic_model: scene = ")


# ---------------------------------------------------------------------------------------------
# the checks leave the differentiable paths open


def test_grad_jit_vmap_through_checked_constructors():
    """value_and_grad of a TE objective wrt the tip relief depth (the MemberModification built
    from a tracer), under jit; vmap over torques; the same numbers as eager calls."""
    case, mesh = _mesh()
    law = jg.SmoothContact(1e-7)

    def te_rms(depth, torque):
        tip = jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.25)
        return jg.quasi_static(mesh, jg.Modifications.symmetric(tip), torque, contact=law).te_rms

    value, grad = jax.jit(jax.value_and_grad(te_rms))(15e-6, case.torque)
    assert np.isfinite(value) and np.isfinite(grad) and grad != 0
    h = 1e-8
    fd = (te_rms(15e-6 + h, case.torque) - te_rms(15e-6 - h, case.torque)) / (2 * h)
    assert abs(grad - fd) <= 1e-4 * abs(fd) + 1e-12
    torques = jnp.array([40.0, 80.0, 120.0])
    batched = jax.vmap(lambda t: te_rms(15e-6, t))(torques)
    eager = [te_rms(15e-6, float(t)) for t in torques]
    np.testing.assert_allclose(batched, eager, rtol=1e-9, atol=1e-15)
    # a batch of modifications built inside vmap, and a traced deviation array
    depths = jnp.array([5e-6, 10e-6])
    assert jax.vmap(lambda d: te_rms(d, case.torque))(depths).shape == (2,)
    dev = jax.jit(lambda f: jg.GearDeviations(single_pitch=f).runout)(jnp.zeros(45))
    assert float(dev) == 0.0


def test_float32_inputs_pass():
    """Float32 values in range pass the checks (and float32 negatives are refused above)."""
    f32 = np.float32
    tip = jg.MemberModification(tip_relief_depth=f32(1e-5), tip_relief_extent=f32(0.25))
    assert float(tip.tip_relief_depth) == pytest.approx(1e-5)
    jg.GearDeviations(single_pitch=np.zeros(45, np.float32), runout=np.float32(1e-6))
    case, mesh = _mesh()
    res = jg.quasi_static(mesh, None, np.float32(80.0), np.asarray([0.01, 0.02], np.float32))
    assert res.transmission_error.shape == (2,)


# -- the tribology, housing-skin and planetary entries -----------------------------------------

_FILM = dict(
    radius=0.0075,
    entrainment_speed=2.5,
    line_load=4e5,
    viscosity=0.046,
    pressure_viscosity=20e-9,
    contact_modulus=115e9,
)


@pytest.mark.parametrize(
    "kw,words",
    [
        (
            dict(formula="grubin"),
            ("formula = 'grubin' (str)", "jaxgear.tribology.DowsonHigginson()"),
        ),
        (dict(viscosity=0.0), ("viscosity = 0 Pa·s is out of range", "allowed > 0 Pa·s")),
        (dict(radius=-0.01), ("radius = -0.01 m is out of range", "allowed > 0 m")),
        (dict(line_load=NAN), ("line_load = nan N/m", "allowed >= 0 N/m")),
        (dict(line_load=np.array([1e5, -1.0])), ("line_load[1] = -1 N/m",)),
        (dict(entrainment_speed=0.0), ("entrainment_speed = 0 m/s",)),
        (dict(pressure_viscosity=INF), ("pressure_viscosity = inf 1/Pa",)),
        (dict(contact_modulus="115e9"), ("contact_modulus = '115e9' is not a number",)),
    ],
)
def test_film_thickness_inputs(kw, words):
    """``film_thickness('grubin', ...)`` was an ``AttributeError``; viscosity 0, a negative
    radius or a NaN load gave a film of 0 or NaN."""
    import jaxgear.tribology as tr

    args = dict(_FILM, formula=tr.Grubin()) | kw
    _refused(lambda: tr.film_thickness(**args), "film_thickness: ", *words)


def test_film_thickness_zero_load_and_traced_inputs_pass():
    """A zero line load stays the documented floor (W = 1e-12), and traced inputs (a gradient
    in the load, a vmap over radii) are not checked eagerly."""
    import jaxgear.tribology as tr

    f = lambda **kw: tr.film_thickness(tr.DowsonHigginson(), **(_FILM | kw)).minimum  # noqa: E731
    assert float(f(line_load=0.0)) > 0.0
    assert math.isfinite(float(jax.grad(lambda w: f(line_load=w))(4e5)))
    assert jax.vmap(lambda r: f(radius=r))(jnp.array([0.005, 0.01])).shape == (2,)


def test_outer_surface_points_inputs():
    from fem_prep.housing import HousingBox, mesh_box, outer_surface

    hm = mesh_box(HousingBox(0.3, 0.2, 0.2, 0.01), 0.1)
    for points, words in (
        ("top", ("outer_surface: points = 'top' (str)", "allowed a dict {name: (x, y, z)}")),
        ([(0.1, 0.1, 0.2)], ("points = [(0.1, 0.1, 0.2)] (list)",)),
        ({"top": ("a", "b", "c")}, ("points['top'] = ('a', 'b', 'c')", "3 finite numbers")),
        ({"top": (0.1, NAN, 0.2)}, ("points['top']", "3 finite numbers")),
    ):
        _refused(lambda p=points: outer_surface(hm, p), *words)
    assert outer_surface(hm, {"top": (0.15, 0.1, 0.2)}).point_names == ("top",)


@functools.cache
def _planetary():
    case = jio.load_case("lin-parker-1999")
    spec = case.form.spec
    return spec.sharing_stage(spec.stage(case))


@pytest.mark.parametrize(
    "torque,positions,words",
    [
        (-100.0, [0.0, 1e-3], ("sun_torque = -100 N·m is out of range", "allowed > 0 N·m")),
        (0.0, [0.0, 1e-3], ("sun_torque = 0 N·m",)),
        (NAN, [0.0, 1e-3], ("sun_torque = nan N·m",)),
        (100.0, [0.0, NAN], ("positions[1] = nan m is out of range", "a finite value")),
        (100.0, np.zeros((2, 2)), ("positions must have shape (p,) [m], got (2, 2)",)),
        (np.array([1.0, 2.0]), [0.0], ("sun_torque must have shape ()",)),
    ],
)
def test_planetary_quasi_static_inputs(torque, positions, words):
    """A NaN position or a negative sun torque gave NaN forces."""
    st = _planetary()
    fn = lambda: jp.planetary_quasi_static(  # noqa: E731
        jp.TorsionalPlanetary(), st, jp.ConstantMeshes(), torque, positions
    )
    _refused(fn, "planetary_quasi_static: ", *words)
