"""docs/robust.md, "Fig. IV-8 as percentile bands" (examples/robust_iv8.py,
docs/bench/robust_iv8.json): the statements the page makes about the committed figure, and the figure
recomputed for a few realisations and speeds."""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
from _examples import load_example

ROOT = pathlib.Path(__file__).resolve().parents[1]
STORED = json.loads((ROOT / "docs" / "bench" / "robust_iv8.json").read_text())


def _p(key, what):
    return np.asarray(STORED["runs"][key][what])


def test_the_documented_statements_hold_on_the_committed_figure():
    """Every realisation converged; with tip relief the class-4 band (P95) lies below the
    class-8 band (P5) at every speed; tip relief lowers the class-4 median peak from 4.09 to
    2.02 (±0.01); the class-8 median with tip relief is above the class-4 median without it at
    23 of the 25 speeds (all but the class-4 resonance at 0.85-0.9 of the critical speed); the
    perfect gears with tip relief stay below the class-4 median."""
    for run in STORED["runs"].values():
        assert run["failed"] == 0
        assert len(run["p50"]) == len(STORED["speeds_rad_s"]) == 25
    assert np.all(_p("grade4_relief", "p95") < _p("grade8_relief", "p5"))
    assert _p("grade4_none", "p50").max() == pytest.approx(4.09, abs=0.01)
    assert _p("grade4_relief", "p50").max() == pytest.approx(2.02, abs=0.01)
    worse = _p("grade8_relief", "p50") > _p("grade4_none", "p50")
    x = np.asarray(STORED["speeds_rad_s"]) / STORED["critical_speed_rad_s"]
    assert worse.sum() == 23
    assert np.allclose(x[~worse], [0.85, 0.9])
    assert np.all(np.asarray(STORED["perfect_relief"]) < _p("grade4_relief", "p50"))


@pytest.mark.slow
def test_the_figure_is_reproduced():
    """Realisations 0-3 of class 8 with tip relief at the first, the 12th and the last speed,
    recomputed with examples/robust_iv8.py's setup, equal the stored dynamic factors (1e-6)."""
    ex = load_example("robust_iv8")
    case, scene, crit = ex.setup()
    assert crit == pytest.approx(STORED["critical_speed_rad_s"], rel=1e-9)
    pick = [0, 11, 24]
    speeds = np.asarray(STORED["speeds_rad_s"])[pick]
    df, res = ex.run(case, scene, 8, True, speeds, samples=4)
    assert np.all(np.asarray(res) == 0)
    stored = np.asarray(STORED["runs"]["grade8_relief"]["dynamic_factor"])[:4][:, pick]
    np.testing.assert_allclose(np.asarray(df), stored, rtol=1e-6)


@pytest.mark.slow
def test_profile_slopes_drive_the_class_4_peak():
    """The page's attribution: one class-4 realisation of the pinion (key 0) without tip relief at
    0.85 of the critical speed, each kind of deviation alone: the profile deviations give
    3.96 (±0.01), the pitch, runout and helix deviations 1.76-1.80 (within [1.75, 1.81]), the
    perfect gears 1.76 (±0.01)."""
    import dataclasses

    import jax
    import jax.numpy as jnp

    import jaxgear as jg
    import jaxgear.dynamics as jd

    ex = load_example("robust_iv8")
    case, scene, crit = ex.setup()
    speed = jnp.asarray([0.85 * crit])
    z1 = case.pair.pinion.teeth
    perfect = jd.dynamic_model(scene, None, case.torque)
    r = jd.speed_sweep(perfect, speed, integrator=jd.Newmark(32), window=jd.SteadyState(30, 4))
    assert float(r.results.dynamic_factor[0]) == pytest.approx(1.76, abs=0.01)
    out = {}
    kinds = {
        "pitch": jg.PitchDeviation(),
        "runout": jg.RunoutDeviation(),
        "profile": jg.ProfileDeviation(),
        "helix": jg.HelixDeviation(),
    }
    for kind in ("pitch", "runout", "profile", "helix"):
        sampler = jg.DeviationSampler.for_grade(
            case.pair, 4, members=("pinion",), kinds=(kinds[kind],)
        )
        mods = jg.Modifications(deviations=sampler(jax.random.key(0)))
        model = dataclasses.replace(jd.dynamic_model(scene, mods, case.torque), deviation_span=z1)
        r = jd.speed_sweep(
            model, speed, integrator=jd.Newmark(32), window=jd.SteadyState(z1 + 10, z1)
        )
        out[kind] = float(r.results.dynamic_factor[0])
    assert out["profile"] == pytest.approx(3.96, abs=0.01), out
    for kind in ("pitch", "runout", "helix"):
        assert 1.75 <= out[kind] <= 1.81, out
