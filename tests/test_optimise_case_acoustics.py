"""``jaxgear optimise`` on a housed case: the acoustic objectives "erp" and
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

import jax.numpy as jnp
import numpy as np
import pytest
from _housing import HOUSING_TABLE, WHINE_TABLE, housed_case, housed_train

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


BEM_SOUND_POWER = """
[optimise]
objective = "sound_power"
reduce = "mean"
a_weighted = false
vars = ["tip_relief.depth"]
max_iterations = 1

[acoustics]
method = "bem"
frequencies = 3
"""


@pytest.mark.slow  # a few minutes on the 2-core host (bempp's compile, 3 BEM solves, 2 whines)
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")
def test_sound_power_by_the_bem_in_jaxgear_optimise(tmp_path, capsys):
    """The objective "sound_power" with R of the closed skin by the BEM (Burton-Miller, 3 grid
    frequencies spanning orders 1-2 at 40-160 rad/s) on the small housed case: ``jaxgear
    optimise`` (one L-BFGS step) reports at its start, the case's own design, per speed the
    sound power ``jaxgear run`` radiates from the same case (its acoustics/sound_power.json,
    summed over the orders) to 1e-8; and the derivative of the objective with respect to the
    tip relief depth by jax.grad through the whole chain (quasi-static solve, harmonic balance,
    housing, vertex map, the BEM's low-rank R interpolated log-log) equals the central
    difference to 1e-5."""
    import jax

    from jaxgear.cli.run import whine_outputs

    case = housed_case(tmp_path, whine=WHINE_TABLE, extra=BEM_SOUND_POWER)
    out = tmp_path / "o"
    assert main(["optimise", str(tmp_path / "housed.toml"), "--out", str(out), "--quiet"]) == 0
    assert "sound_power: " in capsys.readouterr().out
    rep = json.loads((out / "optimum.json").read_text())
    assert rep["initial"]["parameters"]["tip_relief.depth"] == pytest.approx(15.0, rel=1e-12)
    grid = rep["acoustics"]["radiation_grid_Hz"]
    z1 = case.pair.pinion.teeth
    np.testing.assert_allclose([grid[0], grid[-1]],
                               [40.0 * z1 / (2 * math.pi), 2 * 160.0 * z1 / (2 * math.pi)],
                               rtol=1e-12)
    whine_outputs(case, str(tmp_path))  # jaxgear run's housed whine and [acoustics]
    ran = json.loads((tmp_path / "acoustics" / "sound_power.json").read_text())
    np.testing.assert_allclose(rep["acoustics"]["initial"]["power_W"],
                               np.sum(ran["power_W"], axis=1), rtol=1e-8)
    problem = jio.case_problem(case, "tip_relief.depth", "sound_power", reduce="mean",
                               a_weighted=False)
    exact = jg.ExactContact()
    x0 = problem.from_physical({"tip_relief.depth": 15.0})

    def value(x):
        return problem.value(x, exact)

    grad = float(jax.grad(value)(jnp.asarray(x0))[0])
    step = 1e-6 * x0
    fd = float(value(x0 + step) - value(x0 - step)) / (2 * step[0])
    assert grad != 0.0
    np.testing.assert_allclose(grad, fd, rtol=1e-5)


TRAIN_ERP = """
[optimise]
objective = "erp"
reduce = "mean"
vars = ["tip_relief.depth"]
max_iterations = 3
"""


@pytest.mark.parametrize(
    ("optimise", "match"),
    [
        (TRAIN_ERP.replace("vars", "# two stages\nvars"),
         (r"\[optimise\] objective = 'erp': runs on a train whose meshes share one mesh "
          r"frequency .*every 2 periods")),
        ('\n[optimise]\nobjective = "te_rms"\n',
         r"\[optimise\] objective = 'te_rms': a train case optimises its housing's noise"),
        ('\n[optimise]\nvars = ["tip_relief.depth"]\n', r"\[optimise\] objective = 'te_rms'"),
        (TRAIN_ERP.replace('"tip_relief.depth"', '"pinion.tip_relief.depth"'),
         r"\[optimise\] vars = 'pinion.tip_relief.depth': .*acts on every gear"),
        (TRAIN_ERP + "[modifications.idler]\ncrowning = { depth_um = 2.0 }\n",
         r"\[modifications\] idler = .*one modification on every gear"),
        (TRAIN_ERP.replace('"erp"', '"sound_power"'),
         r"\[optimise\] objective = 'sound_power': .*needs \[acoustics\]"),
    ],
)
def test_train_optimise_settings_refused_one_line(tmp_path, optimise, match):
    """A train case's [optimise]: an acoustic objective only (given), on meshes of one mesh
    frequency (an idler train, not the two-stage train whose meshes repeat together every 2
    periods of the first), variables without a member prefix, no [modifications.<gear>], sound
    power with [acoustics]: one line naming the key when the case loads (before the housing is
    condensed)."""
    from _kinds import KINDS

    kind = "train-two-stage" if "# two stages" in optimise else "train-lumped3d"
    text = KINDS[kind] + HOUSING_TABLE[: HOUSING_TABLE.index("[housing.points_mm]")]
    with pytest.raises(jio.SchemaError, match=match) as e:
        jio.load_case(str(_write(tmp_path, text + WHINE_TABLE + optimise)))
    assert "\n" not in str(e.value)


def test_cli_train_takes_the_acoustic_objectives_only(tmp_path, capsys):
    """``jaxgear optimise`` on a housed train case: another objective than erp or sound_power,
    or a prefixed variable, stops with one line and exit status 2, nothing written."""
    from _kinds import KINDS

    housing = HOUSING_TABLE[: HOUSING_TABLE.index("[housing.points_mm]")]
    path = _write(tmp_path, KINDS["train-lumped3d"] + housing + WHINE_TABLE)
    out = tmp_path / "o"
    for args, want in ((["--objective", "te_rms"], ("--objective te_rms: 'train-lumped3d' is "
                                                     "a train case")),
                       (["--objective", "erp", "--vars", "gear.crowning.depth"],
                        "acts on every gear")):
        assert main(["optimise", str(path), "--out", str(out), *args]) == 2
        err = capsys.readouterr().err.strip()
        assert "\n" not in err and want in err, err
    assert not out.exists()


@pytest.mark.slow  # a few minutes on the 2-core host (the housed train's whine and gradient)
@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")
def test_jaxgear_optimise_lowers_the_erp_of_a_housed_train(tmp_path, capsys):
    """``jaxgear optimise`` on a housed idler train (the lumped 3D train of tests/_kinds.py in a
    20 mm Tet4 box, loss factor 0.02, gears undamped; objective erp, the energy mean over the
    [whine] speeds, A-weighted; the tip relief depth of every gear, 3 L-BFGS iterations) ends
    below its start in exact contact; the case ``--write`` leaves carries the optimum's depth
    on every gear, and the objective built separately from that written case (its own acoustic
    path, orders and scene) and evaluated at its modifications equals the reported optimum to
    1e-9."""
    housed_train(tmp_path, loss_factor=0.02, extra=TRAIN_ERP)
    out, new = tmp_path / "o", tmp_path / "optimum.toml"
    assert main(["optimise", str(tmp_path / "train.toml"), "--out", str(out), "--quiet",
                 "--write", str(new)]) == 0
    assert "erp: " in capsys.readouterr().out
    rep = json.loads((out / "optimum.json").read_text())
    a, b = rep["initial"]["objective_exact_W"], rep["final"]["objective_exact_W"]
    assert 0 < b < a
    z1 = 20  # the input's teeth: order 2 at 160 rad/s within cut-off / 1.5
    assert 2 * 160.0 * z1 / (2 * math.pi) <= 6000.0 / 1.5
    assert rep["acoustics"]["orders"] == [1, 2]
    designed = jio.load_case(str(new))
    assert isinstance(designed.form, jio.TrainForm)
    depth = rep["final"]["parameters"]["tip_relief.depth"]
    for m in designed.gear_modifications:
        np.testing.assert_allclose(float(m.tip_relief_depth) * 1e6, depth, rtol=1e-9)
    obj = op.EquivalentRadiatedPower(jio.case_acoustic_path(designed), op.Mean())
    value = float(obj.at_torque(None, jio.design_modifications(designed), designed.torque,
                                jg.ExactContact()))
    np.testing.assert_allclose(value, b, rtol=1e-9)


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
