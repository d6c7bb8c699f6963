"""The lumped dynamics' mesh table: each mesh tabulated over its own period (docs/trains.md,
"Long spans").

A two-stage train's meshes pass teeth at different rates and repeat together only after a span
of first-mesh periods; the table holds each mesh over its own period instead and each mesh takes
its row at step j mod its own period's steps. References: the long table of the span (every
mesh at every step of the span, ``own_periods=False``), whose runs must be reproduced to
rounding (the same cells at every step), and the tooth counts (the rows each mesh needs).
"""

import dataclasses
import functools
import math
import pathlib
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
from jaxgear.scenes import disc_inertia, torsional_train

jax.config.update("jax_enable_x64", True)

MODULE, ALPHA, FACE, SLICES, TORQUE = 2e-3, math.radians(20.0), 15e-3, 4, 120.0
IDLER = pathlib.Path(__file__).resolve().parents[1] / "examples" / "idler-train-lumped3d.toml"


def _pair(z1: int, z2: int) -> jg.GearPair:
    return jg.GearPair(
        jg.Member(z1, face_width=FACE), jg.Member(z2, face_width=FACE), MODULE, ALPHA
    )


def _plane(z1: int, z2: int, slices: int = SLICES) -> jg.MeshModel:
    pair = _pair(z1, z2)
    return jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Weber()), slices)


@functools.cache
def _two_stage():
    """20 → 40, then a 30-tooth pinion on the 40's shaft → 45: the second mesh's period is
    40/30 = 4/3 periods of the first, so the meshes repeat together every 4 periods and each
    mesh's own period is a whole number of steps when N_s is a multiple of 3."""
    pairs = (_pair(20, 40), _pair(30, 45))
    planes = (_plane(20, 40), _plane(30, 45))
    disc = lambda r: disc_inertia(7800.0, r, FACE)
    inertias = [
        disc(pairs[0].tip_radii[0]),
        disc(pairs[0].tip_radii[1]) + disc(pairs[1].tip_radii[0]),
        disc(pairs[1].tip_radii[1]),
    ]
    phases = (0.0, 0.3 * float(planes[1].mesh_period_angle))
    train = torsional_train(((planes[0], (0, 1)), (planes[1], (1, 2))), inertias, phases)
    tip = jg.MemberModification(tip_relief_depth=10e-6, tip_relief_extent=0.25)
    mods = jg.Modifications.symmetric(tip)
    return train, mods


def test_each_mesh_takes_its_own_period_in_rows():
    """The rows follow from the tooth counts: N_s and N_s × 4/3 for the two-stage train at
    N_s = 24 (span 96), the span for the second when N_s is no multiple of 3, and N_s for both meshes
    of an idler train (23 → 37 → 29: one period for both). Each mesh's cells at every step of
    the span equal the long table's at that step (the same positions, whole periods apart)."""
    train, mods = _two_stage()
    assert train.mesh_periods() == (1, jg.scenes.mesh_period_ratios([3.0, 4.0])[1])
    table = jd.mesh_table(train, mods, 24)
    assert table.rows == (24, 32) and table.span == 96 and table.theta.shape == (32,)
    assert jd.mesh_table(train, mods, 16).rows == (16, 64)
    long = jd.mesh_table(train, mods, 24, own_periods=False)
    assert long.rows == (96, 96)
    steps = jnp.arange(96)
    for field in ("V", "k", "length", "delta0", "mask"):
        np.testing.assert_allclose(
            np.asarray(table.take(getattr(table, field), steps), float),
            np.asarray(getattr(long, field), float),
            rtol=0,
            atol=1e-12 * float(np.max(np.abs(np.asarray(getattr(long, field), float)))),
            err_msg=field,
        )
    np.testing.assert_allclose(np.asarray(table.e_max), np.asarray(long.e_max[:32]), rtol=1e-14)
    idler = torsional_train(
        tuple((_plane(a, b, 2), (i, i + 1)) for i, (a, b) in enumerate(((23, 37), (37, 29)))),
        (1e-3, 1e-3, 1e-3),
    )
    assert jd.mesh_table(idler, None, 16).rows == (16, 16)


@functools.cache
def _two_stage_model():
    """The two-stage train's dynamic model (24 positions per pitch) and its speed, 0.6 of its
    first elastic mode's first-mesh coincidence (shared by the tests of this module)."""
    train, mods = _two_stage()
    model = jd.dynamic_model(train, mods, TORQUE, positions_per_pitch=24)
    return model, 0.6 * float(model.modes.omega[1]) / 20


@functools.cache
def _two_stage_own_run():
    """The two-stage train's run on its own-period table, 24 steps per period, two spans kept
    (SteadyState(16, 8)): (result, prepared)."""
    model, speed = _two_stage_model()
    return jd.simulate_on_table(model, speed, 24, jd.SteadyState(16, 8))


def test_own_period_tables_run_the_long_table_dynamics():
    """The two-stage train (tip relief, exact contact) at 0.6 of its first elastic mode's
    first-mesh coincidence, 24 steps per period, two spans kept: every mesh's dynamic factors,
    mesh forces, TE and static force on the own-period table equal the long table's to 1e-10."""
    model, speed = _two_stage_model()
    window = jd.SteadyState(16, 8)
    own, p_own = _two_stage_own_run()
    long, p_long = jd.simulate_on_table(model, speed, 24, window, own_periods=False)
    assert p_own.table.theta.shape == (32,) and p_long.table.theta.shape == (96,)
    assert int(own.result) == 0 and int(long.result) == 0
    _assert_same_run(own, long)


def _assert_same_run(own, long):
    """Two runs of the same steps agree to rounding: every mesh's factors, forces, TE, static
    force; the bearing forces and the records' angles."""
    for a, b in zip(own.meshes, long.meshes, strict=True):
        for f in ("dynamic_factor", "dynamic_factor_tooth", "te_rms", "static_force"):
            assert float(getattr(a, f)) == pytest.approx(float(getattr(b, f)), rel=1e-10), f
        for f in ("mesh_force", "transmission_error", "static_te"):
            x, y = np.asarray(getattr(a, f)), np.asarray(getattr(b, f))
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-10 * np.max(np.abs(y)), err_msg=f)
    for f in ("bearing_force", "bearing_force_max", "bearing_force_static"):
        x, y = np.asarray(getattr(own, f)), np.asarray(getattr(long, f))
        assert x.shape == y.shape
        if y.size:  # a lumped 3D scene's bearings (none in a torsional one)
            np.testing.assert_allclose(x, y, rtol=0, atol=1e-10 * np.max(np.abs(y)), err_msg=f)
    np.testing.assert_allclose(np.asarray(own.theta), np.asarray(long.theta), rtol=1e-14)


# default tier: tests/test_mesh_table.py::test_own_period_tables_run_the_long_table_dynamics (same claim on the torsional two-stage train, whose own-period rows differ from the span's; the idler's are the same rows) and test_static_rows_are_each_steps_static_solve[idler] (the lumped idler's own-period run)
@pytest.mark.slow
@pytest.mark.parametrize("case", ["two-stage", "idler"])
def test_lumped_trains_on_own_period_tables_run_the_long_table_dynamics(case):
    """The embedded lumped 3D ``two-stage`` case (2 slices, 35 steps per HST period: its LST
    mesh's 127/35 periods are 127 steps; the table has 127 rows against the span's 4445; slow:
    50 s) and the lumped idler train of examples/ (one period for both meshes: the tables are the same) at
    half their first elastic mode's coincidence, the span kept: dynamic factors, mesh forces,
    TE and bearing forces equal the long table's to 1e-10."""
    steps, rows = (35, (35, 127)) if case == "two-stage" else (16, (16, 16))
    model, speed, steps_, window = _lumped_case(case)
    assert steps_ == steps
    q = window.periods - 2
    own, p_own = _lumped_own_run(case)
    long, p_long = jd.simulate_on_table(model, speed, steps, window, own_periods=False)
    assert p_own.table.rows == rows and p_long.table.theta.shape == (q * steps,)
    if case == "two-stage":  # the case's own 140 steps (docs/trains.md): 140 and 508 rows
        assert jd.steps_multiple(model) == 35
        assert jd.mesh_rows(model.scene, model.mods, 140, q) == (140, 508)
    assert int(own.result) == 0 and int(long.result) == 0
    _assert_same_run(own, long)


def test_diffrax_records_take_each_mesh_at_its_own_row():
    """A diffrax solver evaluates the cells at θ(t) and records the cell forces from the table
    at the kept samples: over a transient of 5 periods (not a whole span of 4) each mesh's
    recorded force follows its own row. Tsit5 (adaptive, rtol 1e-8, 24 samples per period) and
    Newmark at 384 steps per period, both with the smooth law, agree at the samples on every
    mesh's dynamic factor within 0.5 % (measured 0.06 %, 0.19 %) and on its mesh force within 1 %
    of the static force at 95 % of the samples (before the rows were fixed, the second mesh's
    cells were read a first-mesh period, 3/4 of its own, away)."""
    model, speed = _two_stage_model()
    window = jd.SteadyState(13, 8)
    law = jg.SmoothContact(1e-7)
    steps = 24
    ode = jd.simulate(
        model,
        speed,
        integrator=jd.DiffraxIntegrator("tsit5", rtol=1e-8, atol=1e-8, steps_per_period=steps),
        contact=law,
        window=window,
    )
    ref = jd.simulate(model, speed, integrator=jd.Newmark(16 * steps), contact=law, window=window)
    for a, b in zip(ode.meshes, ref.meshes, strict=True):
        fs = float(b.static_force)
        # the Newmark records at the ODE's samples (both stamped on θ = Ω t)
        fb = np.interp(np.asarray(ode.time), np.asarray(ref.time), np.asarray(b.mesh_force))
        assert float(a.dynamic_factor) == pytest.approx(fb.max() / fs, rel=5e-3)
        # a sample next to a tooth pair's entry may differ more (the interpolated Newmark force)
        diff = np.abs(np.asarray(a.mesh_force) - fb) / fs
        assert np.percentile(diff, 95) < 1e-2, np.percentile(diff, 95)


def _two_stage_scene(model):
    """The embedded ``two-stage`` case and its torsional train or lumped static train (2
    slices), built in the current precision."""
    case = jio.load_case("two-stage")
    if model == "torsional":
        return case, case.torsional_train(slices=2)
    return case, case.static_train(slices=2)


def test_two_stage_train_builds_in_float32():
    """float32 must build: the span and the period ratios of ``two-stage``'s torsional train come
    from the tooth counts, not from float32 base radii (127/35 there was refused as 'not a
    ratio of tooth counts')."""
    import fractions

    with jax.enable_x64(False):
        _, scene32 = _two_stage_scene("torsional")
        assert np.asarray(scene32.meshes[0].base_plane.mesh_period_angle).dtype == np.float32
    # the second stage's 35-tooth pinion on the 127-tooth wheel's shaft (docs/trains.md)
    assert scene32.period_ratios == (1, fractions.Fraction(127, 35))
    assert scene32.periods == 127


# default tier: tests/test_mesh_table.py::test_two_stage_train_builds_in_float32 (the float32 build of this train) and tests/test_quasi_static.py::test_float32_runs_and_matches_float64 (same claim, a float32 quasi-static TE within 1e-3 of float64's, on a pair)
@pytest.mark.slow
@pytest.mark.parametrize("model", ["torsional", "lumped3d"])
def test_two_stage_train_quasi_static_in_float32_is_float64s(model):
    """float32 must run: the quasi-static TE per mesh of ``two-stage`` stays within 1e-3 of
    float64's, the span from the tooth counts in both."""
    import fractions

    def te(case, scene):
        res = jg.quasi_static(scene, case.mesh_modifications(), case.torque, positions_per_pitch=8)
        return [np.asarray(m.transmission_error) for m in res.meshes]

    case64, scene64 = _two_stage_scene(model)
    with jax.enable_x64(False):
        case32, scene32 = _two_stage_scene(model)
        te32 = te(case32, scene32)
        assert te32[0].dtype == np.float32
    train32, train64 = (getattr(s, "base", s) for s in (scene32, scene64))  # lumped: Grounded
    assert train32.period_ratios == (1, fractions.Fraction(127, 35))
    assert train32.periods == train64.periods == 127
    for a, b in zip(te32, te(case64, scene64), strict=True):
        np.testing.assert_allclose(a, b, rtol=1e-3)


@functools.cache
def _lumped_case(case: str):
    """The lumped 3D ``two-stage`` case (2 slices, 35 steps per HST period: a span of 4445
    steps) or the lumped idler train of examples/ (16 steps), at half their first elastic
    mode's coincidence, the span kept: (model, speed, steps, window)."""
    if case == "two-stage":
        data = tomllib.loads(jio.embedded_case_text("two-stage"))
        steps = 35
    else:
        data = tomllib.loads(IDLER.read_text("utf-8"))
        steps = 16
    data["mesh"].update(slices=2, positions_per_pitch=4)
    train = jio.parse_train(data)
    spec = dataclasses.replace(train.scene, steps_per_period=steps)
    model, _ = jio.build_dynamic_model(train, spec, slices=2)
    q = train.span_periods
    speed = 0.5 * float(model.modes.omega[1]) / train.pairs[0].pinion.teeth
    return model, speed, steps, jd.SteadyState(q + 2, max(q, 2))


@functools.cache
def _lumped_own_run(case: str):
    """The lumped case's run on its own-period table (:func:`_lumped_case`): (result,
    prepared), shared by the tests of this module."""
    model, speed, steps, window = _lumped_case(case)
    return jd.simulate_on_table(model, speed, steps, window)


def _static_reference(model, steps: int, periods: int):
    """The static contact at every step of the span, solved here on every coordinate with the
    public ``jaxgear.solve_contact``, each step's cells read from the long table (every mesh at
    that step): K_s X + Σ P V = F with the rigid-body modes r pinned by a penalty
    (M r)(M r)ᵀ k_ref / (rᵀ M r) of this test's own (any weight gives the X with rᵀ M X = 0).
    Returns (X, cell force densities), (S, n) and (S, c)."""
    scene = model.scene
    long = jd.mesh_table(scene, model.mods, steps, periods, own_periods=False)
    K, M, R = scene.stiffness(), scene.mass(), scene.rigid_modes()
    if R.shape[1]:
        MR = M @ R
        scale = jnp.max(jnp.abs(jnp.diag(K))) + jnp.max(long.k * long.length) * 1e-3
        K = K + scale * MR @ jnp.diag(1.0 / jnp.einsum("ir,ij,jr->r", R, M, R)) @ MR.T
    F = scene.external_load(model.torque)

    def one(j):
        r = long.at(j)
        return jg.solve_contact(K, F, r.V, r.k, r.length, r.delta0, r.mask)

    # one compiled program (an eager vmap dispatches and compiles the solve's operations one
    # by one)
    sol = jax.jit(jax.vmap(one))(jnp.arange(long.span))
    assert np.all(np.asarray(sol.result) == 0)
    return np.asarray(sol.x), np.asarray(sol.force_density)


@pytest.mark.parametrize(
    "case", ["torsional", "idler", pytest.param("two-stage", marks=pytest.mark.slow)]
)
def test_static_rows_are_each_steps_static_solve(case):
    """The static rows (the quasi-static reference at every step of the span: static forces,
    static TE, bearing loads, the start state) and the Newmark steps are solved on the
    structure condensed onto the coordinates the cells reach (the gear nodes' 6 DOFs: 18 of 90
    for the idler train, 24 of 102 for ``two-stage``; a torsional train's cells reach all 3).
    At every step of the span the static rows equal this test's own solve of that step on every
    coordinate (1e-10 of the largest; a row taken one step off differs by far more), and
    (lumped) the dynamic factors, static forces, static TE, TE and bearing loads equal those of
    the run on every coordinate (``condensed=False``: the static rows and each Newmark step's
    contact solved as before; to 1e-10, measured 1.7e-12). The lumped ``two-stage`` at 35
    steps (a span of 4445 steps) is slow (about a minute)."""
    if case == "torsional":  # the static rows do not depend on the window: the module's run
        model, _ = _two_stage_model()
        steps = 24
        assert model.scene.contact_dofs() == (0, 1, 2)
    else:
        model, speed, steps, window = _lumped_case(case)
        # the 6 DOFs of each gear node: 18 of 90 (idler), 24 of 102 (two-stage)
        nodes = model.scene.structure.nodes
        gears = [first + k for name, first in nodes if name.startswith("gear") for k in range(6)]
        assert model.scene.contact_dofs() == tuple(sorted(gears))
        sizes = {"idler": (18, 90), "two-stage": (24, 102)}[case]
        assert (len(gears), model.scene.structure.size) == sizes
    res, prep = _two_stage_own_run() if case == "torsional" else _lumped_own_run(case)
    span = prep.table.span
    x_ref, p_ref = _static_reference(model, steps, span // steps)
    x, p = np.asarray(prep.static_x), np.asarray(prep.static_force_density)
    assert x.shape == x_ref.shape and p.shape == p_ref.shape
    for got, ref in ((x, x_ref), (p, p_ref)):
        scale = np.max(np.abs(ref))
        np.testing.assert_allclose(got, ref, rtol=0, atol=1e-10 * scale)
        # the rows differ from step to step: a shifted row would fail
        assert np.max(np.abs(np.roll(got, 1, axis=0) - ref)) > 1e-6 * scale
    if case == "torsional":  # every coordinate is a contact coordinate: nothing condensed
        return
    full, _ = jd.simulate_on_table(model, speed, steps, window, condensed=False)
    assert int(res.result) == 0 and int(full.result) == 0
    _assert_same_run(res, full)
