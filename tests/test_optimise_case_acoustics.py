"""``jaxgear optimise`` on a housed case (issue 66, item 3): the acoustic objectives "erp" and
"sound_power" from a case file's ``[housing]``, ``[whine]`` and ``[acoustics]``
(docs/acoustics.md, "Optimising for noise").

References, each apart from the code under test: the orders in the housing's band and the
speeds written out from the case's numbers; the design ``jaxgear optimise --write`` leaves in a
case file, evaluated again by an objective built separately from that file; the sound power
``jaxgear run`` radiates from the same case (its vertex velocities recovered from the housing's
coordinates directly, not through the skin facets); the closed skin's vertex normal operator on
the recovery (the vertex map's exactness)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from _housing import HOUSING_TABLE, WHINE_TABLE, housed_case

import jaxgear as jg
import jaxgear.io as jio
import optimise as op
from jaxgear.cli import check_settings, main

ERP_OPTIMISE = """
[optimise]
objective = "erp"
reduce = "mean"
vars = ["tip_relief.depth"]
max_iterations = 3
"""


def _write(tmp_path, text, name="c.toml"):
    path = tmp_path / name
    path.write_text(text)
    return path


@pytest.mark.parametrize(
    ("tables", "match"),
    [
        (ERP_OPTIMISE, r"\[optimise\] objective = 'erp': .*needs \[housing\]"),
        (HOUSING_TABLE + ERP_OPTIMISE, r"\[optimise\] objective = 'erp': .*needs \[whine\]"),
        (HOUSING_TABLE + WHINE_TABLE + ERP_OPTIMISE.replace('"erp"', '"sound_power"'),
         r"\[optimise\] objective = 'sound_power': .*needs \[acoustics\]"),
        (ERP_OPTIMISE.replace('reduce = "mean"', 'reduce = "quantile"'),
         r"\[optimise\] reduce = 'quantile': .*quantile = q in \(0, 1\)"),
        (ERP_OPTIMISE.replace('reduce = "mean"', 'reduce = "quantile"\nquantile = 1.5'),
         r"\[optimise\] quantile = 1\.5"),
        ('\n[optimise]\nobjective = "te_rms"\na_weighted = false\n',
         r"\[optimise\] a_weighted = false: applies to objective = 'erp' or 'sound_power'"),
    ],
)
def test_acoustic_objective_settings_refused_one_line(tmp_path, tables, match):
    """An acoustic objective on a case without the housing's whine (or, sound power, without
    [acoustics]), a quantile without its level or out of (0, 1), an A weighting on a TE
    objective: one line naming the key, when the case loads (before any computation)."""
    text = jio.embedded_case_text("accessory-spur") + tables
    with pytest.raises(jio.SchemaError, match=match) as e:
        jio.load_case(str(_write(tmp_path, text)))
    assert "\n" not in str(e.value)


def test_cli_acoustic_objective_needs_the_housed_tables(tmp_path, capsys):
    """``jaxgear optimise --objective erp`` on a case without [housing] (``--reduce quantile``
    without ``--quantile``, ``--no-a-weighted`` with a TE objective) stops with one line, exit
    status 2, nothing written."""
    case = jio.load_case("accessory-spur")
    with pytest.raises(ValueError, match=r"--objective erp .*has no \[housing\]"):
        check_settings({"objective": "erp", "max_iterations": 5}, case)
    with pytest.raises(ValueError, match="--reduce quantile needs --quantile"):
        check_settings({"objective": "robust_te_rms", "reduce": "quantile", "max_iterations": 5})
    with pytest.raises(ValueError, match="--no-a-weighted applies to the objectives erp and"):
        check_settings({"objective": "te_rms", "a_weighted": False, "max_iterations": 5})
    out = tmp_path / "o"
    assert main(["optimise", "accessory-spur", "--objective", "sound_power", "--out",
                 str(out)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no [housing]" in err
    assert not out.exists()


def test_case_acoustic_path_of_the_small_housed_case(tmp_path):
    """The path of the small housed case: coupled (its lumped 3D scene carries the housing),
    the [whine] speeds (40, 100, 160 rad/s), method (H = 2) and positions (16); the orders h
    whose frequency h Ω z₁ / 2π at the top speed lies within cut-off / 1.5 (6000 / 1.5 Hz),
    counted here; a band_Hz that does not span them and factors beyond the memory limit are
    refused before R is computed, naming their key."""
    case = housed_case(tmp_path, whine=WHINE_TABLE)
    path = jio.case_acoustic_path(case)
    assert path.coupled
    np.testing.assert_allclose(np.asarray(path.speeds), [40.0, 100.0, 160.0])
    assert path.method.harmonics == 2 and path.positions == 16
    z1 = case.pair.pinion.teeth
    want = tuple(h for h in (1, 2) if h * 160.0 * z1 / (2 * math.pi) <= 6000.0 / 1.5)
    assert path.orders == want == (1, 2)
    f_lo = 40.0 * z1 / (2 * math.pi)
    band = f"\n[acoustics]\nmethod = 'erp-only'\nband_Hz = [{2 * f_lo}, 5000.0]\n"
    short = housed_case(tmp_path, whine=WHINE_TABLE, extra=band)
    with pytest.raises(jio.SchemaError, match=r"\[acoustics\] band_Hz = .*must span") as e:
        jio.case_radiation(short, path)
    assert "\n" not in str(e.value)
    wide = housed_case(tmp_path, whine=WHINE_TABLE,
                       extra="\n[acoustics]\nmethod = 'erp-only'\nfrequencies = 2000\n")
    with pytest.raises(jio.SchemaError, match=r"\[acoustics\] rank: .*allowed rank <="):
        jio.case_radiation(wide, path)


@pytest.mark.slow  # about 3 min on the 2-core host (the housed whine, its gradient, 3 L-BFGS steps)
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")
def test_jaxgear_optimise_lowers_the_erp_of_a_housed_case(tmp_path, capsys):
    """``jaxgear optimise`` on the small housed case (objective erp, the energy mean over the
    [whine] speeds, A-weighted; tip relief depth, 3 L-BFGS iterations) ends below its start in
    exact contact; the reported optimum equals the objective built separately from the case
    (its path's damping matrix the start design's, held) evaluated at the modifications of the
    case file ``--write`` leaves (the optimum), and the mean of the report's per-speed powers."""
    case = housed_case(tmp_path, whine=WHINE_TABLE, extra=ERP_OPTIMISE)
    out, new = tmp_path / "o", tmp_path / "optimum.toml"
    assert main(["optimise", str(tmp_path / "housed.toml"), "--out", str(out), "--quiet",
                 "--write", str(new)]) == 0
    assert "erp: " in capsys.readouterr().out
    rep = json.loads((out / "optimum.json").read_text())
    a, b = rep["initial"]["objective_exact_W"], rep["final"]["objective_exact_W"]
    assert 0 < b < a
    assert rep["acoustics"]["orders"] == [1, 2] and rep["acoustics"]["a_weighted"] is True
    designed = jio.load_case(str(new))
    # the path of the start case: its model's damping matrix is held over the designs
    obj = op.EquivalentRadiatedPower(jio.case_acoustic_path(case), op.Mean())
    value = float(obj.at_torque(None, designed.modifications, designed.torque,
                                jg.ExactContact()))
    np.testing.assert_allclose(value, b, rtol=1e-9)
    np.testing.assert_allclose(np.mean(rep["acoustics"]["final"]["power_W"]), b, rtol=1e-12)
    depth = float(designed.modifications.pinion.tip_relief_depth)
    np.testing.assert_allclose(depth * 1e6, rep["final"]["parameters"]["tip_relief.depth"],
                               rtol=1e-9)


@pytest.mark.slow  # about 1 min on the 2-core host (the housed whine twice, R at 4 frequencies)
def test_sound_power_objective_is_the_runs_sound_power(tmp_path):
    """The objective "sound_power" of a housed case with [acoustics] (method 'erp-only', 4 grid
    frequencies), unweighted, at the case's design: per speed, the sound power ``jaxgear run``
    radiates from the same case's whine (its acoustics/sound_power.json, summed over the
    orders) to 1e-8 — the run's vertex velocities come from the housing's coordinates through
    the recovery, the objective's from the skin facets through its vertex map, which reproduces
    the closed skin's normal operator on the recovery to 1e-9."""
    from jaxgear.cli.run import whine_outputs

    case = housed_case(tmp_path, whine=WHINE_TABLE,
                       extra="\n[acoustics]\nmethod = 'erp-only'\nfrequencies = 4\n")
    problem = jio.case_problem(case, "tip_relief.depth", "sound_power", reduce="mean",
                               a_weighted=False)
    obj = problem.objective
    assert isinstance(obj, op.RadiatedSoundPower) and problem.mesh is obj.path.model.scene
    per = np.asarray(obj.per_speed(case.modifications, case.torque, jg.ExactContact()))
    whine_outputs(case, str(tmp_path))
    ran = json.loads((tmp_path / "acoustics" / "sound_power.json").read_text())
    np.testing.assert_allclose(per, np.sum(ran["power_W"], axis=1), rtol=1e-8)
    housed = jio.housed_acoustics(case)
    skin, _ = jio.closed_skin(housed)
    vertices = skin.normal_operator @ housed.body.condensed.recovery
    got = np.asarray(obj.radiation.vertex_map) @ np.asarray(housed.acoustics.normal_map)
    np.testing.assert_allclose(got, vertices, rtol=0, atol=1e-9 * np.abs(vertices).max())


def test_surface_radiation_on_a_grid_checks_its_shapes():
    """``SurfaceRadiation`` with ``grid_hz``: factors (G, n, r) at its G frequencies and the
    vertex map (n, F); another G or n is one line naming both shapes."""
    import jax.numpy as jnp

    vm = jnp.zeros((3, 5))
    rad = op.SurfaceRadiation(vm, jnp.zeros((2, 3, 1), complex), jnp.asarray([100.0, 200.0]))
    assert rad.grid_hz.shape == (2,)
    for L, g in ((jnp.zeros((2, 4, 1), complex), [100.0, 200.0]),
                 (jnp.zeros((2, 3, 1), complex), (100.0, 150.0, 200.0)),
                 (jnp.zeros((1, 2, 3, 1), complex), [100.0, 200.0])):
        with pytest.raises(ValueError, match=r"vertex_map \(3, 5\), factors .*allowed \(n, F\) "
                           r"and \(G, n, r\)") as e:
            op.SurfaceRadiation(vm, L, g)
        assert "\n" not in str(e.value)
