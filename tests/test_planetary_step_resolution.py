"""The planetary sweep's time-step check (:func:`jaxgear.cli.planetary_sweep.step_resolution`):
n = S f_mesh / f_max Newmark steps per period of the stage's highest natural frequency f_max
at the lowest swept speed; below 10 one ``CaseWarning`` line names ``--steps-per-period``, its
value, f_max and a value that resolves it; ``sweep.json``'s ``steps_resolution``; the measured
K_v's source says so. f_max is taken here from the public modal API (jaxgear.planetary_modes
on the case's stage), the threshold S = 10 f_max / f_mesh computed here."""

from __future__ import annotations

import math
import re
import tomllib
import warnings

import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import planetary_sweep as ps
from jaxgear.cli.planetary import measured_k_v

RUN = {"periods": 2, "keep_periods": 1}


@pytest.fixture(scope="module")
def lumped():
    """The embedded lin-parker-1999 (lumped form: constant mesh springs, ring fixed, sun in),
    its f_max (Hz) and its mesh frequency per rad/s of the input (Hz): z_s (ω_s − ω_c) / 2π
    with ω_c = ω_s z_s / (z_s + z_r) (Willis, ring fixed), written here."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    case = jio.parse_train(data)
    spec = case.form.spec
    f_max = float(np.max(np.asarray(jg.planetary_modes(jg.PlanarPlanetary(),
                                                       spec.stage(case)).frequencies)))
    z_s, z_r = 28, 92
    per = z_s * (1.0 - z_s / (z_s + z_r)) / (2 * math.pi)
    return case, f_max, per


def _sweep(case, speeds, steps):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s, _ = ps.sweep_summary(case.form, case, speeds, steps_per_period=steps, **RUN)
    return s, [str(x.message) for x in w if issubclass(x.category, jio.CaseWarning)]


def test_the_warning_fires_below_ten_steps_per_top_period_and_names_a_value_that_passes(lumped):
    """Speeds chosen so that 10 f_max / f_mesh(lowest) = 40.5 steps per mesh period: S = 39
    (n = 9.6) warns once (two speeds, one line), naming the option, 39, f_max and 42 (the next
    multiple of the 3 planets); S = 42 (n = 10.4) is silent. The mesh frequency per rad/s of
    the code agrees with Willis written here."""
    case, f_max, per = lumped
    assert case.form.spec.mesh_frequency(1.0) == pytest.approx(per, rel=1e-12)
    lo = 10 * f_max / (40.5 * per)  # rad/s of the sun
    speeds = np.array([lo, 1.5 * lo])
    s, msgs = _sweep(case, speeds, 39)
    assert len(msgs) == 1 and "\n" not in msgs[0]
    text = msgs[0]
    assert text.startswith("--steps-per-period = 39:")
    assert f"{f_max:.4g} Hz" in text
    need = int(re.search(r"--steps-per-period >= (\d+)", text).group(1))
    assert need == 42
    r = s["steps_resolution"]
    assert r["resolved"] is False
    assert r["f_max_Hz"] == pytest.approx(f_max, rel=1e-9)
    assert r["steps_per_top_period_min"] == pytest.approx(39 / 40.5 * 10, rel=1e-9)
    s2, msgs2 = _sweep(case, speeds, need)
    assert msgs2 == []
    assert s2["steps_resolution"]["resolved"] is True
    assert s2["steps_resolution"]["steps_per_top_period_min"] == pytest.approx(
        need / 40.5 * 10, rel=1e-9)


def test_the_measured_k_v_source_says_under_resolved(lumped):
    """The K_v source text carries "(time step under-resolved: n = ...)" exactly where the
    sweep's steps_resolution is not resolved (a stub sweep with equal load sharing)."""
    sweep = {"speeds_rad_s": [1.0, 2.0], "mesh_names": ["s1", "s2", "r1", "r2"],
             "dynamic_factor_mesh": [[1.1, 1.2, 1.3, 1.4], [1.2, 1.3, 1.4, 1.5]],
             "model": "planar", "ring_model": "rigid",
             "steps_resolution": {"f_max_Hz": 1276.0, "steps_per_top_period_min": 0.27,
                                  "resolved": False, "steps_per_period_resolved": 2388}}
    sharing = {"planar": {"sun_mesh_forces_N": [1.0, 1.0],
                                    "ring_mesh_forces_N": [1.0, 1.0]}}
    kv = measured_k_v(sweep, 1.5, sharing)
    assert kv[0]["value"] == pytest.approx(1.25) and kv[1]["value"] == pytest.approx(1.45)
    assert "(time step under-resolved: n = 0.27 " in kv[0]["source"]
    assert "--steps-per-period >= 2388" in kv[0]["source"]
    sweep["steps_resolution"]["resolved"] = True
    assert "under-resolved" not in measured_k_v(sweep, 1.5, sharing)[0]["source"]


@pytest.mark.slow
def test_the_suggested_step_is_on_the_converged_side(tmp_path):
    """The convergence direction behind the rule, on the small contact-cell stage of
    tests/test_planetary_sweep.py (spur 19/17/-53, 3 planets, a 10 um pin error) at one input
    speed where 10 f_max / f_mesh = 264 steps per mesh period (f_max from planetary_modes): the
    default 66 steps (n = 2.5) warns and suggests 264; the largest dynamic factor at 264 and at
    528 differ by less than a quarter of its change from 66 to 264 (measured: 2.134 at 66,
    2.682 at 264, 2.721 at 528, float64 on CPU; about 20 s of CPU, hence slow: the fast twin
    above asserts the threshold itself)."""
    import test_planetary_sweep as small

    path = tmp_path / "small-stage.toml"
    path.write_text(small.CASE)
    case = jio.load_case(str(path))
    spec = case.form.spec
    f_max = float(np.max(np.asarray(jg.planetary_modes(jg.PlanarPlanetary(),
                                                       spec.stage(case)).frequencies)))
    speed = np.array([10 * f_max / (264 * spec.mesh_frequency(1.0))])
    run = {"periods": 20, "keep_periods": 4}
    with pytest.warns(jio.CaseWarning, match=r"--steps-per-period >= 264 resolves it"):
        coarse, _ = ps.sweep_summary(case.form, case, speed, **run)  # the default step
    assert coarse["steps_per_period"] == 66
    df = {66: coarse["max_dynamic_factor"]}
    for steps in (264, 528):
        with warnings.catch_warnings():
            warnings.simplefilter("error", jio.CaseWarning)
            s, _ = ps.sweep_summary(case.form, case, speed, steps_per_period=steps, **run)
        df[steps] = s["max_dynamic_factor"]
    assert df[264] > df[66]  # the coarse step filters the impacts: low
    assert abs(df[528] - df[264]) < 0.25 * abs(df[264] - df[66])
