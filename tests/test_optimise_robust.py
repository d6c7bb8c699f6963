"""Robust tooth-modification design against sampled ISO 1328-1 deviations (issue 22 §3,
docs/robust.md, "Robust optimisation"): the gradient of the sampled objective through the
realisations against central finite differences; the robust optimum beats the nominal optimum
on the sampled objective (and on fresh realisations); one-line errors."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import optimise as op

ROOT = Path(__file__).resolve().parents[1]


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


@pytest.mark.parametrize("statistic", [op.Mean(), op.Quantile(0.75)])
def test_robust_gradient_matches_central_differences(setting, statistic):
    """4 realisations over one revolution at 4 positions per pitch, smooth contact: jax.grad of
    the objective (mean, or the 75 % quantile) equals central differences (h = 1e-5 in the
    normalised variables) to 1e-5 of the gradient's largest component."""
    _, prob, sampler = setting
    rp = op.robust_problem(
        prob, sampler, jax.random.key(1), 4, positions_per_pitch=4, statistic=statistic
    )
    f = jax.jit(lambda x: rp.value(x))
    x = jnp.asarray([1.1, 0.3])
    g = np.asarray(jax.grad(rp.value)(x))
    h = 1e-5
    fd = [(float(f(x.at[i].add(h))) - float(f(x.at[i].add(-h)))) / (2 * h) for i in range(x.size)]
    assert np.abs(g - np.asarray(fd)).max() < 1e-5 * np.abs(g).max()
    assert np.abs(g).max() > 1e-3  # the gradient is not trivially zero


def _small_gradient() -> dict:
    """The robust gradient of a small case (1 slice, 2 realisations, 2 positions per pitch) at
    x = (1.1, 0.3) and its central differences (h = 1e-5): {"grad": [..], "fd": [..]}."""
    jax.config.update("jax_enable_x64", True)
    case = jio.load_case("accessory-spur")
    prob = op.make_problem(
        case.mesh_model(slices=1),
        jg.Modifications(),
        case.torque,
        "tip_relief.depth,tip_relief.extent",
    )
    kinds = (jg.PitchDeviation(), jg.ProfileDeviation())
    sampler = jg.DeviationSampler.for_grade(case.pair, 6, kinds=kinds)
    # robust_problem's realisations and span (2 positions per pitch over the pinion's 45 teeth)
    # with scale 1 µm (its exact-contact scale is one more program to compile)
    keys = jax.vmap(lambda i: jax.random.fold_in(jax.random.key(1), i))(jnp.arange(2))
    theta = jg.mesh_positions(prob.mesh, 2, 45)
    rp = op.RobustProblem(prob, jax.vmap(sampler)(keys), theta, 1e-6, op.Mean())
    vg = jax.jit(jax.value_and_grad(lambda x: rp.value(x)))  # one program for both
    f = lambda x: float(vg(x)[0])
    x = jnp.asarray([1.1, 0.3])
    g = vg(x)[1]
    h = 1e-5
    fd = [(f(x.at[i].add(h)) - f(x.at[i].add(-h))) / (2 * h) for i in range(2)]
    return {"grad": [float(v) for v in g], "fd": fd}


_O0 = "--xla_backend_optimization_level=0"


def test_robust_gradient_is_finite_with_unoptimised_xla_code():
    """The robust gradient of a small case (1 slice, 2 realisations, 2 positions per pitch)
    compiled by XLA's CPU backend at LLVM -O0 (``--xla_backend_optimization_level=0``: this
    process's level where the suite runs there, else a separate process, since the level is
    fixed when JAX starts) equals central differences to 1e-5 of its largest component. There
    the program computes the masked deviations that feed max_M e (seed (2.8)) in two kernels
    that round differently, so that no cell equals the maximum: ``jnp.max``'s derivative, which
    divides by the count of cells equal to it, was NaN (:func:`jaxgear._util.safe_max` falls
    back to the first maximum)."""
    if _O0 in os.environ.get("XLA_FLAGS", "").split():
        out = _small_gradient()
    else:
        flags = [
            f for f in os.environ.get("XLA_FLAGS", "").split() if "optimization_level" not in f
        ]
        script = (
            "import json, sys; sys.path.insert(0, 'tests'); "
            "from test_optimise_robust import _small_gradient; "
            "print(json.dumps(_small_gradient()))"
        )
        r = subprocess.run(
            [sys.executable, "-c", script],
            cwd=ROOT,
            env=dict(os.environ, XLA_FLAGS=" ".join([*flags, _O0])),
            capture_output=True,
            text=True,
            timeout=600,
            check=False,
        )
        assert r.returncode == 0, r.stderr[-3000:]
        out = json.loads(r.stdout.splitlines()[-1])
    g, fd = np.asarray(out["grad"]), np.asarray(out["fd"])
    assert np.all(np.isfinite(g)), g
    assert np.abs(g - fd).max() < 1e-5 * np.abs(g).max()
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
