"""Monte Carlo over ISO 1328-1 deviation realisations (docs/robust.md): the JAX
sampler's draws meet the tolerances and have the stated statistics; a runout realisation's TE RMS
equals its closed form; the sampled mean and percentiles converge as 1/√N to the known
distribution; the percentile intervals cover; two processes on the loopback address give what
one process gives (to 1e-12); bad settings are one-line errors."""

from __future__ import annotations

import itertools
import math
import os
import sys
from pathlib import Path

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy import stats

import jaxgear as jg
import jaxgear.io as jio
from benchmarks import free_port, run_processes

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def spur():
    """The rigid accessory spur pair (z1 = 45, z2 = 86), Weber stiffness at 4 slices."""
    case = jio.load_case("accessory-spur")
    return case, case.mesh_model(slices=4)


def _draws(sampler, n, seed=0):
    return _draws_compiled(sampler, n, jnp.asarray(seed))


@eqx.filter_jit
def _draws_compiled(sampler, n, seed):
    """n draws of ``sampler`` in one compiled program (the seed traced: one program for every
    seed; an eager vmap would dispatch and compile the sampler's operations one by one)."""
    keys = jax.vmap(lambda i: jax.random.fold_in(jax.random.key(seed), i))(jnp.arange(n))
    return jax.vmap(sampler)(keys)


# -- the sampler ---------------------------------------------------------------------------------


def test_sampler_meets_every_tolerance_and_the_stated_statistics(spur):
    """1000 realisations of both gears of grade 6: every draw within f_pT, F_pT, F_rT, F_αT,
    F_βT; Σ f_pt = 0; F_r ~ U(0, F_rT) (mean F_rT/2, std F_rT/√12) and φ ~ U(0, 2π) within 4
    standard errors; per-tooth slopes and forms of zero mean."""
    case, _ = spur
    n = 1000
    d = _draws(jg.DeviationSampler.for_grade(case.pair, 6), n)
    for tag, g in (("pinion", d.pinion), ("gear", d.gear)):
        member = getattr(case.pair, tag)
        dia = member.teeth * case.pair.normal_module
        tol = jg.iso1328_tolerances(case.pair.normal_module, dia, member.face_width, 6)
        fpt = np.asarray(g.single_pitch)
        assert fpt.shape == (n, member.teeth)
        assert np.abs(fpt).max() <= tol.single_pitch * (1 + 1e-12)
        assert np.abs(fpt.sum(axis=1)).max() < 1e-12 * tol.single_pitch * member.teeth
        cum = np.cumsum(fpt, axis=1)
        assert (cum.max(axis=1) - cum.min(axis=1)).max() <= tol.cumulative_pitch * (1 + 1e-12)
        fr = np.asarray(g.runout)
        assert 0 <= fr.min() and fr.max() <= tol.runout
        se = tol.runout / math.sqrt(12 * n)
        assert abs(fr.mean() - tol.runout / 2) < 4 * se
        assert abs(fr.std() - tol.runout / math.sqrt(12)) < 4 * tol.runout * 0.129 / math.sqrt(n)
        assert abs(np.asarray(g.runout_phase).mean() - math.pi) < 4 * math.pi / math.sqrt(3 * n)
        x = np.linspace(0, 1, 201)[:, None, None]  # the sampler's 201 points
        for slope, form, total in (
            (g.profile_slope, g.profile_form, tol.profile_total),
            (g.helix_slope, g.helix_form, tol.helix_total),
        ):
            s, f = np.asarray(slope), np.asarray(form)
            trace = s[None] * (x - 0.5) + f[None] * (2 * x - 1) ** 2
            assert (trace.max(axis=0) - trace.min(axis=0)).max() <= total * (1 + 1e-12)
            for v in (s, f):  # zero mean over n × z independent draws
                assert abs(v.mean()) < 4 * v.std() / math.sqrt(v.size)


def test_sampler_has_the_distribution_of_the_numpy_draw():
    """The slow test below with 1000 gears: the same statistics, the same thresholds (the
    two-sample KS test's p > 0.001 holds at any size when the distributions agree; the pooled
    std's standard error is 0.8 % at 8000 draws, well inside 5 %)."""
    _sampler_against_the_numpy_draw(1000)


# default tier: tests/test_robust.py::test_sampler_has_the_distribution_of_the_numpy_draw (the
# same claim with 1000 gears)
@pytest.mark.slow
def test_sampler_has_the_distribution_of_the_numpy_draw_at_3000_gears():
    """The JAX sampler against the NumPy draw written separately (jaxgear.sample_gear_deviations,
    3000 gears of 8 teeth each): per gear, the largest |f_pt|, the range F_p of the cumulative
    pitch, F_r, and tooth 0's profile and helix slopes agree in distribution (two-sample
    Kolmogorov-Smirnov, p > 0.001), and the pooled single pitch std is f_pT/√3 · √(1 − 1/z)
    within 5 % (the scaling seldom acts for 8 teeth)."""
    _sampler_against_the_numpy_draw(3000)


def _sampler_against_the_numpy_draw(n):
    tol = jg.iso1328_tolerances(1.5e-3, 12e-3, 10e-3, 6)
    z = 8
    g = _draws(jg.DeviationSampler(pinion=jg.GearSampler.of(tol, z)), n).pinion
    rng = np.random.default_rng(5)
    ref = [jg.sample_gear_deviations(rng, z, tol) for _ in range(n)]

    def features(fpt, fr, ps, hs):
        cum = np.cumsum(fpt, axis=1)
        return {
            "max|f_pt|": np.abs(fpt).max(axis=1),
            "F_p": cum.max(axis=1) - cum.min(axis=1),
            "F_r": fr,
            "profile_slope": ps[:, 0],
            "helix_slope": hs[:, 0],
        }

    a = features(
        np.asarray(g.single_pitch),
        np.asarray(g.runout),
        np.asarray(g.profile_slope),
        np.asarray(g.helix_slope),
    )
    b = features(
        np.stack([np.asarray(r.single_pitch) for r in ref]),
        np.array([float(r.runout) for r in ref]),
        np.stack([np.asarray(r.profile_slope) for r in ref]),
        np.stack([np.asarray(r.helix_slope) for r in ref]),
    )
    for k in a:
        assert stats.ks_2samp(a[k], b[k]).pvalue > 1e-3, k
    expect = tol.single_pitch / math.sqrt(3) * math.sqrt(1 - 1 / z)
    assert np.asarray(g.single_pitch).std() == pytest.approx(expect, rel=0.05)


# -- one realisation and the Monte Carlo statistics -----------------------------------------------


def _runout_te_rms(r0, runout):
    """TE RMS over one pinion revolution of the perfect TE (RMS r0, mesh-periodic) less a pinion
    runout e_r sin(θ + φ), e_r = F_r/2 (docs/deviations.md, "Runout"): the two are orthogonal over
    a revolution of uniformly spaced positions, so RMS² = r0² + e_r²/2."""
    return np.sqrt(r0**2 + (runout / 2) ** 2 / 2)


def _runout_setup(spur):
    case, mesh = spur
    z1 = case.pair.pinion.teeth
    theta = jg.mesh_positions(mesh, 8, z1)
    sampler = jg.DeviationSampler.for_grade(
        case.pair, 6, members=("pinion",), kinds=(jg.RunoutDeviation(),)
    )
    perfect = jg.quasi_static(mesh, None, case.torque, theta)
    te = np.asarray(perfect.transmission_error)
    r0 = float(np.sqrt(np.mean((te - te.mean()) ** 2)))
    problem = jg.QuasiStaticMetrics(mesh, None, jnp.asarray(case.torque), theta)
    return sampler, problem, r0, sampler.pinion.tolerances[8]


def test_runout_realisations_give_their_closed_form_te_rms(spur):
    """16 realisations through robust_samples: realisation i draws from fold_in(key, i) and its
    TE RMS equals √(r0² + (F_r/2)²/2) with its own F_r, to 1e-9."""
    sampler, problem, r0, _ = _runout_setup(spur)
    key = jax.random.key(7)
    out = jg.robust_samples(problem, sampler, key, 16, batch_size=4)
    fr = np.asarray(_draws(sampler, 16, 7).pinion.runout)
    assert np.all(out.result == 0)
    assert out.te_rms == pytest.approx(_runout_te_rms(r0, fr), rel=1e-9)
    assert out.te_rms.shape == out.te_ptp.shape == out.max_line_load.shape == (16,)


def test_sampled_mean_and_percentiles_converge_as_one_over_root_n(spur):
    """The slow test below at its first two levels, N = 250 and 1000: the same bounds, the
    same halving of the error per 4× N."""
    _sampled_statistics_converge(spur, (250, 1000))


# default tier: tests/test_robust.py::test_sampled_mean_and_percentiles_converge_as_one_over_root_n
# (the same claim, two levels)
@pytest.mark.slow
def test_sampled_mean_and_percentiles_converge_at_three_levels(spur):
    """The TE RMS of a pinion runout F_r ~ U(0, F_rT) (grade 6) has a known distribution: g(F_r)
    with g the closed form above, increasing, so its p-quantile is g(p F_rT) and its mean
    (1/a)∫₀ᵃ √(r0² + x²/8) dx = [x/2 √(r0² + x²/8) + √8 r0²/2 asinh(x/(√8 r0))]₀ᵃ / a.
    Over 40 seeds, the RMS error of sample_statistics' mean, median and 95th percentile at
    N = 250, 1000, 4000: within 1.5 × their asymptotic standard error (σ/√N for the mean,
    √(p(1−p)/N)/f(q_p) for a percentile) and halving (ratio 2 within ±25 %) per 4× N."""
    _sampled_statistics_converge(spur, (250, 1000, 4000))


def _sampled_statistics_converge(spur, ns):
    sampler, _, r0, frt = _runout_setup(spur)
    a = float(frt)
    c = math.sqrt(8.0)
    g = lambda x: _runout_te_rms(r0, x)
    prim = lambda x: x / 2 * math.sqrt(r0**2 + x**2 / 8) + c * r0**2 / 2 * math.asinh(x / (c * r0))
    mean = (prim(a) - prim(0.0)) / a
    second = r0**2 + a**2 / 24  # E[g²] = r0² + E[F_r²]/8
    sigma = math.sqrt(second - mean**2)

    def se_quantile(p, n):  # density of g(F_r) at its p-quantile: 1/(a g'(x)), g' = x/(8 g)
        x = p * a
        return math.sqrt(p * (1 - p) / n) * a * x / (8 * g(x))

    seeds = 40
    errors = {"mean": [], "50": [], "95": []}
    for n in ns:
        e = {k: [] for k in errors}
        for s in range(seeds):
            v = g(np.asarray(_draws(sampler, n, 1000 + s).pinion.runout))
            st = jg.sample_statistics(v)
            e["mean"].append(st["mean"] - mean)
            e["50"].append(st["percentiles"]["50"]["value"] - g(0.5 * a))
            e["95"].append(st["percentiles"]["95"]["value"] - g(0.95 * a))
        for k in errors:
            errors[k].append(math.sqrt(np.mean(np.square(e[k]))))
        assert errors["mean"][-1] < 1.5 * sigma / math.sqrt(n)
        assert errors["50"][-1] < 1.5 * se_quantile(0.5, n)
        assert errors["95"][-1] < 1.5 * se_quantile(0.95, n)
    for k, err in errors.items():
        for e1, e2 in itertools.pairwise(err):
            assert 1.5 < e1 / e2 < 2.5, (k, err)


def test_percentile_intervals_cover_and_binomial_quantile():
    """Order-statistic intervals (distribution-free): over 1000 samples of N = 200 standard
    normal values the 5/50/95 % intervals hold the true percentile in >= 93 % (nominal >= 95 %),
    the mean's in 93-97 %; the interval's ranks are scipy.stats.binom.ppf's quantiles."""
    rng = np.random.default_rng(0)
    hits = {"5": 0, "50": 0, "95": 0, "mean": 0}
    truth = {k: stats.norm.ppf(float(k) / 100) for k in ("5", "50", "95")}
    runs = 1000
    for _ in range(runs):
        st = jg.sample_statistics(rng.standard_normal(200))
        for k, t in truth.items():
            lo, hi = st["percentiles"][k]["ci"]
            hits[k] += lo <= t <= hi
        hits["mean"] += st["mean_ci"][0] <= 0 <= st["mean_ci"][1]
    for k in truth:
        assert hits[k] / runs >= 0.93, hits
    assert 0.93 <= hits["mean"] / runs <= 0.97, hits
    for n in (17, 200, 1000):  # the interval's ranks are scipy's binomial quantiles
        x = np.sort(rng.standard_normal(n))
        st = jg.sample_statistics(x, (5.0, 30.0, 50.0, 95.0))
        for p in (5.0, 30.0, 50.0, 95.0):
            lo = int(stats.binom.ppf(0.025, n, p / 100))
            hi = int(stats.binom.ppf(0.975, n, p / 100)) + 1
            expect = [x[lo - 1] if lo >= 1 else None, x[hi - 1] if hi <= n else None]
            assert st["percentiles"][f"{p:g}"]["ci"] == expect


# -- devices and processes -----------------------------------------------------------------------


def test_process_runner_waits_for_all_and_names_the_one_that_failed(tmp_path):
    """benchmarks.run_processes (the two-process runs' launcher): both processes run at once
    (each waits for the other's file), a failure names the process, its exit status and the
    end of its stderr, and a process past the timeout is stopped with a one-line error."""
    py = [sys.executable, "-c"]
    meet = (
        "import pathlib, sys, time; d = pathlib.Path(sys.argv[1]); i = sys.argv[2]; "
        "(d / i).write_text(i); t = time.time()\n"
        "while len(list(d.iterdir())) < 2 and time.time() - t < 30: time.sleep(0.01)\n"
        "sys.exit(0 if len(list(d.iterdir())) == 2 else 3)"
    )
    run_processes(
        [py + [meet, str(tmp_path), str(i)] for i in range(2)], env=None, cwd=tmp_path, timeout=60
    )
    fail = "import sys; print('first', file=sys.stderr); sys.exit('broken: rank 1')"
    with pytest.raises(
        RuntimeError, match=r"(?s)^process 1 of 2 failed \(exit status 1\): first\nbroken: rank 1$"
    ):
        run_processes([py + ["pass"], py + [fail]], env=None, cwd=tmp_path, timeout=60)
    with pytest.raises(RuntimeError, match=r"^process 0 of 1 ran past 0.5 s: stopped$"):
        run_processes([py + ["import time; time.sleep(30)"]], env=None, cwd=tmp_path, timeout=0.5)


@pytest.mark.slow
def test_two_processes_on_loopback_give_the_one_process_result(spur, tmp_path):
    """13 grade-6 realisations (both gears, every kind, one pinion revolution) by two processes
    joined by jax.distributed on 127.0.0.1, two CPU devices each (4 global devices, the indices
    padded to 16): every process receives all 13, equal to this process's one-device run to
    1e-12."""
    env = dict(
        os.environ,
        XLA_FLAGS="--xla_force_host_platform_device_count=2",
        JAX_PLATFORMS="cpu",
        PYTHONPATH=str(ROOT),
    )
    port = free_port()
    outs = [tmp_path / f"p{i}.npz" for i in range(2)]
    worker = [sys.executable, str(ROOT / "tests" / "_robust_worker.py")]
    run_processes(
        [worker + [str(i), "2", str(port), str(outs[i]), "13"] for i in range(2)],
        env=env,
        cwd=ROOT,
        timeout=300,
    )
    case, mesh = spur
    theta = jg.mesh_positions(mesh, 4, case.pair.pinion.teeth)
    sampler = jg.DeviationSampler.for_grade(case.pair, 6)
    problem = jg.QuasiStaticMetrics(mesh, None, jnp.asarray(case.torque), theta)
    one = jg.robust_samples(problem, sampler, jax.random.key(3), 13, batch_size=4)
    for path in outs:
        two = np.load(path)
        assert int(two["processes"]) == 2 and int(two["devices"]) == 4
        assert np.all(two["result"] == 0)
        for name in ("te_rms", "te_ptp", "max_line_load"):
            a, b = np.asarray(getattr(one, name)), two[name]
            assert a.shape == b.shape == (13,)
            assert np.max(np.abs(b - a) / np.abs(a)) < 1e-12


# -- errors --------------------------------------------------------------------------------------


def test_bad_settings_are_one_line_errors(spur):
    case, mesh = spur
    sampler = jg.DeviationSampler.for_grade(case.pair, 6)
    problem = jg.QuasiStaticMetrics(mesh, None, jnp.asarray(80.0), jg.mesh_positions(mesh, 4))
    cases = [
        (lambda: jg.robust_samples(problem, sampler, jax.random.key(0), 0), "samples = 0"),
        (
            lambda: jg.robust_samples(problem, sampler, jax.random.key(0), 4, batch_size=1.5),
            "batch_size = 1.5",
        ),
        (lambda: jg.robust_samples(problem, None, jax.random.key(0), 4), "sampler"),
        (lambda: jg.DeviationSampler.for_grade(case.pair, 12), "grade = 12"),
        (lambda: jg.DeviationSampler.for_grade(case.pair, 6, kinds=("lead",)), "kinds"),
        (lambda: jg.DeviationSampler.for_grade(case.pair, 6, members=("wheel",)), "members"),
        (lambda: jg.sample_statistics([1.0]), "at least 2"),
        (lambda: jg.sample_statistics([1.0, 2.0], confidence=1.5), "confidence = 1.5"),
        (lambda: jg.sample_statistics([1.0, 2.0], percentiles=(0,)), "percentile = 0"),
    ]
    for call, text in cases:
        with pytest.raises(ValueError, match=".*") as info:
            call()
        msg = str(info.value)
        assert text in msg and "\n" not in msg, msg
