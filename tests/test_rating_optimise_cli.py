"""``jaxgear optimise --objective least_safety`` (and ``[optimise] objective = "least_safety"``,
``te_limit_um``): the name maps to optimise.LeastSafetyFactor on the case's ``[rating]``; the
problem's value is 1/soft-min of the safety factors rated by jaxgear.rating.rate with the K_Hβ
measured on the load map and the design's tip relief and crowning as ISO's C_a and C_β
(computed here from the load map and the depths, not by the objective); a case
without ``[rating]`` and a TE limit on another objective are refused in one line before any
work; and (slow) the CLI's optimum raises the least safety factor of a misaligned spur pair,
re-rated here by jaxgear.rating.rate at the start and at the optimum, with the TE RMS under its
limit.

References: jaxgear.rating.rate (checked against ISO/TR 6336-30 and KISSsoft in
tests/test_rating*.py) with the measured K_Hβ given; the soft minimum
−log Σ exp(−κ S)/κ written with numpy."""

import json
import math
import re

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _rating_cases import rated_accessory_data
from _toml import case_toml

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
import optimise as op
from jaxgear.cli import main

jax.config.update("jax_enable_x64", True)

DEVIATION_UM = 12.0  # helix slope deviation on the pinion: a misalignment, K_Hβ about 1.4


def _data(slices, ppp, optimise=None):
    d = rated_accessory_data(slices, ppp)
    d["modifications"] = {
        "tip_relief": {"depth_um": 15.0, "extent": 0.25},
        "pinion": {"helix_slope": {"deviation_um": DEVIATION_UM}},
    }
    if optimise is not None:
        d["optimise"] = optimise
    return d


def _by_hand(case, mods, contact=None):
    """(S_H pinion, S_H gear, S_F pinion, S_F gear) and the TE RMS of ``mods``: jg.rating.rate with
    the K_Hβ of the quasi-static load map given, K_Hα ISO's, and the design's tip relief and
    crowning (the larger member's depths) as ISO's C_a and C_β."""
    res = jg.quasi_static(
        case.mesh_model(),
        mods,
        case.torque,
        positions_per_pitch=case.positions_per_pitch,
        contact=contact or jg.ExactContact(),
    )
    rc = jio.rating_of(case)
    relief = max(float(mods.pinion.tip_relief_depth), float(mods.gear.tip_relief_depth))
    crowning = max(float(mods.pinion.crowning_depth), float(mods.gear.crowning_depth))
    settings = eqx.tree_at(
        lambda s: (s.given, s.tip_relief, s.crowning),
        rc.settings,
        (jr.GivenFactors(K_Hbeta=float(jg.rating.face_load_factor(res))), relief, crowning),
        is_leaf=lambda x: x is None,
    )
    r = jr.rate(rc.geometry, rc.operating, settings)
    s = np.concatenate([np.asarray(r.pitting.S_H), np.asarray(r.bending.S_F)])
    return s, float(res.te_rms)


def _soft_inverse(s, kappa=50.0):
    m = np.min(s)
    return 1.0 / (m - math.log(np.sum(np.exp(-kappa * (s - m)))) / kappa)


@pytest.mark.slow
def test_case_problem_least_safety_against_rate_by_hand():
    """case_problem(case, ..., "least_safety", te_limit) on a coarse rated case: the objective
    is a LeastSafetyFactor of the case's rating and the limit; with sharp relief starts, its
    unscaled value at a crowned design is 1/soft-min of the four safety factors jg.rating.rate gives
    with the measured factors (1e-9), the TE below the limit (no penalty), and 1/soft-min plus
    100 (TE/limit − 1)² with the limit at half the TE. About 35 s on a loaded 2-core machine
    (the fast tests: the name → object in tests/test_optimise_objects.py, the objective's
    rating against jg.rating.rate in tests/test_rating_optimise.py)."""
    case = jio.parse_case(_data(3, 8))
    prob = jio.case_problem(
        case, ["pinion.crowning.depth"], "least_safety", te_limit=1e-5, relief_blend=0.0
    )
    assert isinstance(prob.objective, op.LeastSafetyFactor)
    assert prob.objective.te_limit == 1e-5
    x = jnp.asarray(prob.from_physical({"pinion.crowning.depth": 6.0}))
    mods = prob.modifications(x)
    assert float(mods.pinion.crowning_depth) == pytest.approx(6e-6, rel=1e-12)
    assert float(mods.pinion.helix_slope_deviation) == pytest.approx(DEVIATION_UM * 1e-6)
    s, te = _by_hand(case, mods, prob.contact)
    got = float(prob.per_torque(x, None)[0])
    assert got == pytest.approx(_soft_inverse(s), rel=1e-9)
    o = prob.objective
    half = op.LeastSafetyFactor(o.geometry, o.operating, o.settings, te_limit=te / 2)
    tight = eqx.tree_at(lambda p: p.objective, prob, half)
    got = float(tight.per_torque(x, None)[0])
    assert got == pytest.approx(_soft_inverse(s) + 100.0 * (2.0 - 1.0) ** 2, rel=1e-9)


def test_cli_least_safety_refusals(tmp_path, capsys):
    """One line naming what is missing or misplaced, exit status 2, nothing written: a case
    without [rating]; --te-limit-um with another objective; a limit out of range; the
    [optimise] table's te_limit_um with another objective."""
    d = _data(3, 8)
    del d["rating"]
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa"):
        del d["material"][key]
    del d["operating"]["speed_rpm"]
    bare = tmp_path / "bare.toml"
    bare.write_text(case_toml(d))
    rated = tmp_path / "rated.toml"
    rated.write_text(case_toml(_data(3, 8)))
    out = tmp_path / "out"
    runs = (
        (["optimise", str(bare), "--objective", "least_safety"], r"no \[rating\] table"),
        (["optimise", str(rated), "--te-limit-um", "1.0"], "applies to the objective least_safety"),
        (
            ["optimise", str(rated), "--objective", "least_safety", "--te-limit-um", "-1"],
            r"--te-limit-um -1: out of range, allowed \(0, 1e\+04\] µm",
        ),
    )
    for argv, message in runs:
        assert main([*argv, "--out", str(out), "--quiet"]) == 2
        err = capsys.readouterr().err.strip()
        assert len(err.splitlines()) == 1 and re.search(message, err), err
    assert not out.exists()
    with pytest.raises(ValueError, match="te_limit_um.*applies to objective = 'least_safety'"):
        jio.parse_case(_data(3, 8, {"objective": "te_rms", "te_limit_um": 1.0}))
    with pytest.raises(ValueError, match=r"te_limit_um.*out of range, allowed \(0, 10000\]"):
        jio.parse_case(_data(3, 8, {"objective": "least_safety", "te_limit_um": 0.0}))


@pytest.mark.slow
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")  # gain asserted
def test_cli_least_safety_raises_the_least_safety_factor(tmp_path):
    """jaxgear optimise on a rated accessory pair with a 12 µm helix slope deviation on the
    pinion and 15 µm tip relief ([optimise] objective = "least_safety", the pinion crowning as
    the variable (its default bounds), te_limit_um = 1.0; 6 slices, 8 positions): the optimum's
    least safety factor, re-rated by jaxgear.rating.rate with the factors measured on its
    exact-contact load map, is above the start's and above the case's own design (no crowning), the
    exact TE RMS at the optimum is under the limit, and the report's rating is the same re-rating.
    About 60 s on a loaded 2-core machine (the fast tests above check the objective's parts)."""
    table = {
        "objective": "least_safety",
        "vars": ["pinion.crowning.depth"],
        "te_limit_um": 1.0,
        "max_iterations": 30,
    }
    path = tmp_path / "misaligned.toml"
    path.write_text(case_toml(_data(6, 8, table)))
    out = tmp_path / "out"
    assert main(["optimise", str(path), "--out", str(out), "--quiet"]) == 0
    rep = json.loads((out / "optimum.json").read_text())
    assert rep["objective"] == "least_safety"
    assert {p.name for p in out.iterdir()} >= {"optimum.json", "convergence.png", "harris.png"}
    case = jio.parse_case(_data(6, 8))

    def rated(crowning_um):
        mods = eqx.tree_at(
            lambda m: m.pinion.crowning_depth, case.modifications, jnp.asarray(crowning_um * 1e-6)
        )
        return _by_hand(case, mods)

    own, _ = rated(0.0)
    start, _ = rated(rep["initial"]["parameters"]["pinion.crowning.depth"])
    s, te = rated(rep["final"]["parameters"]["pinion.crowning.depth"])
    print(f"least S: case {own.min():.4f}, start {start.min():.4f}, optimum {s.min():.4f}; "
          f"TE {te * 1e6:.3f} µm")
    assert s.min() > start.min() + 1e-3 and s.min() > own.min() + 1e-3
    assert te < 1.0e-6
    np.testing.assert_allclose(rep["rating"]["final"]["S_H"] + rep["rating"]["final"]["S_F"], s,
                               rtol=1e-9)
    assert rep["rating"]["final"]["least_S"] == pytest.approx(s.min(), rel=1e-9)
