"""The planetary sweep's time-step check (:func:`jaxgear.planetary.step_resolution`, its warning in ``jaxgear sweep``):
n = S f_mesh / f_max Newmark steps per period of the highest natural frequency the meshes excite
f_max, at the lowest swept speed; below 20 (the pairs' ``under_resolved`` bound) one
``CaseWarning`` line names ``--steps-per-period``, its value, f_max and the default step there
(which resolves it); ``sweep.json``'s ``steps_resolution``; the measured K_v's source says so.
f_max is computed here from the public modal API (jaxgear.planetary.planetary_modes on the stage the
sweep integrates, the meshes' strain-energy share from the stage with and without its mesh springs:
tests/test_planetary_step_plan.py), the threshold S = 20 f_max / f_mesh here."""

from __future__ import annotations

import math
import re
import tomllib
import warnings

import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import planetary_sweep as ps
from jaxgear.cli.planetary import measured_k_v
from test_planetary_step_plan import reference_plan

# the contact model a stub measured row states (jaxgear.rating.contact_model's words)
CONTACT = "stub contact model"

RUN = {"periods": 2, "keep_periods": 1}


@pytest.fixture(scope="module")
def lumped():
    """The embedded lin-parker-1999 (lumped form: constant mesh springs, ring fixed, sun in),
    its f_max (Hz, the highest mode storing >= 5 % of its strain energy in the meshes) and its
    mesh frequency per rad/s of the input (Hz): z_s (ω_s − ω_c) / 2π with ω_c = ω_s z_s /
    (z_s + z_r) (Willis, ring fixed), written here."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    case = jio.parse_train(data)
    f_max = reference_plan(case, [1.0])[2]
    z_s, z_r = 28, 92
    per = z_s * (1.0 - z_s / (z_s + z_r)) / (2 * math.pi)
    return case, f_max, per


def _sweep(case, speeds, steps):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        s, _ = ps.sweep_summary(case.form, case, speeds, steps_per_period=steps, **RUN)
    return s, [str(x.message) for x in w if issubclass(x.category, jio.CaseWarning)]


def test_the_warning_fires_below_twenty_steps_per_top_period_and_names_the_default(lumped):
    """Speeds chosen so that 20 f_max / f_mesh(lowest) = 40.5 steps per mesh period: S = 39
    (n = 19.3) warns once (two speeds, one line), naming the option, 39, f_max and the default
    step at the lowest speed, 96 (the smallest 3 × 2^j >= 40 f_max / f_mesh = 81); S = 42
    (n = 20.7) is silent, and so is the default. The mesh frequency per rad/s of the code
    agrees with Willis written here."""
    case, f_max, per = lumped
    assert case.form.spec.mesh_frequency(1.0) == pytest.approx(per, rel=1e-12)
    lo = 20 * f_max / (40.5 * per)  # rad/s of the sun
    speeds = np.array([lo, 1.5 * lo])
    s, msgs = _sweep(case, speeds, 39)
    assert len(msgs) == 1 and "\n" not in msgs[0]
    text = msgs[0]
    assert text.startswith("--steps-per-period = 39:")
    assert f"{f_max:.4g} Hz" in text
    need = int(re.search(r"--steps-per-period >= (\d+)", text).group(1))
    assert need == 96
    r = s["steps_resolution"]
    assert r["resolved"] is False and r["automatic"] is False
    assert r["f_max_Hz"] == pytest.approx(f_max, rel=1e-9)
    assert r["steps_per_top_period_min"] == pytest.approx(39 / 40.5 * 20, rel=1e-9)
    # S = 42: the check sweep_summary makes before the work (resolution_checked, whose
    # CaseWarning and steps_resolution the S = 39 sweep above carried), on the plan it runs
    # (sweep_time_plan), without integrating (the sweep's records are the S = 39 run's concern)
    from jaxgear.cli._planetary_steps import resolution_checked

    plan42 = ps.sweep_time_plan(case.form, case, speeds, steps_per_period=42, **RUN)
    assert plan42.steps.tolist() == [42, 42]
    with warnings.catch_warnings():
        warnings.simplefilter("error", jio.CaseWarning)
        r2 = resolution_checked(plan42, speeds * case.form.spec.mesh_frequency(1.0), 3)
    assert r2["resolved"] is True
    assert r2["steps_per_top_period_min"] == pytest.approx(42 / 40.5 * 20, rel=1e-9)
    plan = ps.sweep_time_plan(case.form, case, speeds)  # the default (not integrated here)
    assert plan.steps.tolist() == [96, 96]
    with warnings.catch_warnings():
        warnings.simplefilter("error", jio.CaseWarning)
        r3 = jp.step_resolution(plan, speeds * per, 3)
    assert r3["resolved"] and r3["automatic"] and r3["steps_per_top_period_min"] >= 40


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
    kv = measured_k_v(sweep, 1.5, sharing, CONTACT)
    assert kv[0]["value"] == pytest.approx(1.25) and kv[1]["value"] == pytest.approx(1.45)
    assert "(time step under-resolved: n = 0.27 " in kv[0]["source"]
    assert "--steps-per-period >= 2388" in kv[0]["source"]
    sweep["steps_resolution"]["resolved"] = True
    assert "under-resolved" not in measured_k_v(sweep, 1.5, sharing, CONTACT)[0]["source"]
