"""Robust tooth-modification design against sampled ISO 1328-1 deviations
(docs/robust.md, "Robust optimisation"): the gradient of the sampled objective through the
realisations against central finite differences; the robust optimum beats the nominal optimum
on the sampled objective (and on fresh realisations); one-line errors."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import optimise as op


@pytest.fixture(scope="module")
def setting():
    """The accessory spur pair at 4 slices without modification; tip relief depth and extent
    the variables (TE RMS at 80 N·m), grade-6 pitch and profile deviations of both gears."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=4)
    prob = op.make_problem(
        mesh,
        jg.Modifications(),
        case.torque,
        "tip_relief.depth,tip_relief.extent",
        positions_per_pitch=16,
    )
    sampler = jg.DeviationSampler.for_grade(
        case.pair, 6, kinds=(jg.PitchDeviation(), jg.ProfileDeviation())
    )
    return case, prob, sampler


# a fixed random direction (seeded, unit length) of the directional-derivative checks
DIRECTION = np.random.default_rng(54).standard_normal(2)
DIRECTION /= np.linalg.norm(DIRECTION)


def _robust_gradient_check(setting, statistic, per_variable):
    _, prob, sampler = setting
    rp = op.robust_problem(
        prob, sampler, jax.random.key(1), 4, positions_per_pitch=4, statistic=statistic
    )
    # the gradient and the differences' values from one compiled program (value_and_grad)
    value_and_grad = jax.jit(jax.value_and_grad(lambda x: rp.value(x)))
    x = jnp.asarray([1.1, 0.3])
    g = np.asarray(value_and_grad(x)[1])
    h = 1e-5
    for d in np.eye(2) if per_variable else [DIRECTION]:
        fd = (float(value_and_grad(x + h * d)[0]) - float(value_and_grad(x - h * d)[0])) / (2 * h)
        assert abs(g @ d - fd) < 1e-5 * np.abs(g).max(), (d, g, fd)
    assert np.abs(g).max() > 1e-3  # the gradient is not trivially zero


# default tier for the quantile: the mean here (the same claim, another statistic); the
# quantile's reduction: tests/test_optimise_objects.py::test_statistics_reduce_as_named
@pytest.mark.parametrize(
    "statistic", [op.Mean(), pytest.param(op.Quantile(0.75), marks=pytest.mark.slow)]
)
def test_robust_gradient_matches_central_differences(setting, statistic):
    """4 realisations over one revolution at 4 positions per pitch, smooth contact: jax.grad of
    the objective (mean, or the 75 % quantile) projected on a fixed random direction (seeded)
    equals the central difference along it (h = 1e-5 in the normalised variables) to 1e-5 of
    the gradient's largest component. Each variable along its own: the slow test below."""
    _robust_gradient_check(setting, statistic, per_variable=False)


@pytest.mark.slow  # test_robust_gradient_matches_central_differences keeps the claim
@pytest.mark.parametrize("statistic", [op.Mean(), op.Quantile(0.75)])
def test_robust_gradient_matches_central_differences_per_variable(setting, statistic):
    """As above, each component of the gradient against its own central difference."""
    _robust_gradient_check(setting, statistic, per_variable=True)


def _unoptimised_options() -> dict:
    """XLA compiler options for one program built by the CPU backend at LLVM -O0 with its MLIR
    fusion emitters (XLA's default emitters), whatever this process's ``XLA_FLAGS`` say: the
    suite's conftest builds its programs at -O0 with the element-wise emitter
    (``--xla_cpu_use_fusion_emitters=false``), where the robust gradient below is finite even
    through ``jnp.max``'s derivative. Without the emitter option where the jaxlib no longer
    knows it (the fusion emitters are then the only route)."""
    options = {"xla_backend_optimization_level": 0, "xla_cpu_use_fusion_emitters": True}
    try:
        jax.jit(jnp.sin).lower(1.0).compile(compiler_options=options)
    except Exception:  # noqa: BLE001 - a jaxlib that rejects the option name
        del options["xla_cpu_use_fusion_emitters"]
    return options


def test_safe_max_falls_back_to_the_first_maximum_where_no_element_equals_it(monkeypatch):
    """What keeps the robust gradient finite in the slow test below, at its smallest: where the
    maximum is computed in a kernel that rounds differently from the elements compared with it
    (no element equals it: jnp.max's derivative divides by that count of 0 and is NaN),
    :func:`jaxgear.safe_max`'s derivative is the tangent at the first maximum (jnp.argmax).
    The maximum here: jnp.max raised by 1e-9 (|max| + 1), inside safe_max's module alone."""
    import jaxgear._util as util

    class Rounded:  # jax.numpy, but a maximum that no element compares equal to
        def __getattr__(self, name):
            return getattr(jnp, name)

        @staticmethod
        def max(x, axis=None, keepdims=False):
            m = jnp.max(x, axis=axis, keepdims=keepdims)
            return m + 1e-9 * (jnp.abs(m) + 1.0)

    monkeypatch.setattr(util, "jnp", Rounded())
    x = jnp.asarray([[1.0, 3.0, 2.0], [0.5, -1.0, 4.0]])
    assert not bool(jnp.any(x == Rounded.max(x)))
    np.testing.assert_array_equal(jax.grad(jg.safe_max)(x), [[0, 0, 0], [0, 0, 1]])
    w = jnp.asarray([1.0, 10.0, 100.0])
    g = jax.grad(lambda v: jnp.sum(jg.safe_max(v, 0) * w))(x)
    np.testing.assert_array_equal(g, [[1, 10, 0], [0, 0, 100]])


# default tier: tests/test_optimise_robust.py::test_safe_max_falls_back_to_the_first_maximum_where_no_element_equals_it
# (the mechanism, at its smallest) and ::test_robust_gradient_matches_central_differences (the
# robust gradient against differences)
@pytest.mark.slow
def test_robust_gradient_is_finite_with_unoptimised_xla_code(setting):
    """The robust gradient of a small case (the module's 4 slices, 2 realisations, 2 positions
    per pitch, at x = (1.1, 0.3)) compiled by XLA's CPU backend at LLVM -O0 with its fusion
    emitters (per-program compiler options, :func:`_unoptimised_options`) equals central
    differences of the objective (h = 1e-5) to 1e-5 of its largest component. That program
    computes the masked deviations that feed max_M e (seed (2.8)) in two kernels that round
    differently, so that at some positions no cell equals the maximum: ``jnp.max``'s
    derivative, which divides by the count of cells equal to it, is NaN there (checked on JAX
    0.10.2 with safe_max replaced by ``jnp.max``: [nan nan]; finite with the suite's
    element-wise emitter, which this test once ran and so could not fail);
    :func:`jaxgear.safe_max` falls back to the first maximum. The differences: along the
    module's fixed random direction (each variable along its own: the slow test below)."""
    _unoptimised_gradient_check(setting, [DIRECTION])


# default tier: tests/test_optimise_robust.py::test_safe_max_falls_back_to_the_first_maximum_where_no_element_equals_it
@pytest.mark.slow  # and the directional check beside it (slow too)
def test_robust_gradient_is_finite_with_unoptimised_xla_code_per_variable(setting):
    """As above, each component of the gradient against its own central difference."""
    _unoptimised_gradient_check(setting, np.eye(2))


def _unoptimised_gradient_check(setting, directions):
    _, prob, sampler = setting
    # robust_problem's realisations and span (2 positions per pitch over the pinion's 45 teeth)
    # with scale 1 µm (its exact-contact scale is one more program to compile)
    keys = jax.vmap(lambda i: jax.random.fold_in(jax.random.key(1), i))(jnp.arange(2))
    theta = jg.mesh_positions(prob.mesh, 2, 45)
    rp = op.RobustProblem(prob, jax.jit(jax.vmap(sampler))(keys), theta, 1e-6, op.Mean())
    x = jnp.asarray([1.1, 0.3])
    vg = (
        jax.jit(jax.value_and_grad(lambda x: rp.value(x)))  # one program for both
        .lower(x)
        .compile(compiler_options=_unoptimised_options())
    )
    g = np.asarray(vg(x)[1])
    assert np.all(np.isfinite(g)), g
    h = 1e-5
    for d in directions:
        fd = (float(vg(x + h * d)[0]) - float(vg(x - h * d)[0])) / (2 * h)
        assert abs(g @ d - fd) < 1e-5 * np.abs(g).max(), (d, g, fd)
    assert np.abs(g).max() > 1e-3  # the gradient is not trivially zero


@pytest.mark.slow
def test_robust_optimum_beats_the_nominal_optimum(setting):
    """L-BFGS on the nominal TE RMS (perfect gears) and on the mean TE RMS over 8 realisations
    (one revolution, 8 positions per pitch): on the sampled objective in the exact law the
    robust optimum is lower than the nominal one by more than 1e-4 (relative; the optimisers'
    tolerance is 1e-7), and it is also lower on 16 fresh realisations."""
    _, prob, sampler = setting
    rp = op.robust_problem(prob, sampler, jax.random.key(0), 8, positions_per_pitch=8)
    nominal = op.minimise(prob, np.array([1.0, 0.3]), progress=False)
    robust = op.minimise(rp, nominal.x, progress=False)
    exact = jax.jit(lambda r, x: r.value(x, jg.ExactContact()))
    v_nom, v_rob = (float(exact(rp, jnp.asarray(x))) for x in (nominal.x, robust.x))
    assert v_rob < v_nom * (1 - 1e-4)
    fresh = op.robust_problem(prob, sampler, jax.random.key(99), 16, positions_per_pitch=8)
    assert float(exact(fresh, jnp.asarray(robust.x))) < float(exact(fresh, jnp.asarray(nominal.x)))


def test_robust_problem_errors_are_one_line(setting):
    case, prob, sampler = setting
    mesh = case.mesh_model(slices=4)
    ptp = op.make_problem(mesh, jg.Modifications(), 80.0, "tip_relief.depth", op.TePeakToPeak())
    key = jax.random.key(0)
    for call, text in (
        (lambda: op.robust_problem(prob, sampler, key, 0), "samples = 0"),
        (lambda: op.robust_problem(prob, sampler, key, 2, revolutions=0), "revolutions = 0"),
        (lambda: op.robust_problem(prob, sampler, key, 2, statistic=1.5), "statistic = 1.5"),
        (lambda: op.robust_problem(ptp, sampler, key, 2), "objective = 'te_ptp'"),
    ):
        with pytest.raises(ValueError) as info:
            call()
        assert text in str(info.value) and "\n" not in str(info.value)
