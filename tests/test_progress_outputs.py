"""Progress and outputs: fem-prep's bar reaches its total and names the long
calls; the eigen-solve's progress hook changes nothing; the hybrid sweep in chunks gives the
one-shot results; ``jaxgear sweep`` keeps clear of ``jaxgear run``'s ``sweep/``; an interrupted
optimisation leaves a marker, removed when it finishes."""

from __future__ import annotations

import json
import pathlib
import re

import jax
import numpy as np
import pytest
import scipy.sparse as sp

import fem_prep
import jaxgear as jg
import jaxgear.cli.sweep as cli_sweep  # to replace the sweep computation (tests/test_layout.py)
import optimise as op
from fem_prep import load_body, prepare, shift_invert_modes
from jaxgear import io as jio
from jaxgear.cli import (
    check_settings,
    main,
    optimise_case,
    plots,
    scene_outputs,
    settings_from_case,
)
from jaxgear.dynamics import Batching, Newmark, SteadyState, dynamic_model, speed_sweep
from jaxgear.io import static_scene

PARTIAL = "optimum.partial.json"  # the marker of an unfinished jaxgear optimise

DATA = pathlib.Path(__file__).parent / "data"


def _sweep(scene, mods, torque, speeds, **settings):
    """:func:`jaxgear.dynamics.speed_sweep` on the hybrid model of ``scene``: its results."""
    return speed_sweep(dynamic_model(scene, mods, torque), speeds, **settings).results


def test_fem_prep_bar_reaches_its_total_and_names_the_long_calls(capsys, fem_prep_cache):
    body = load_body(DATA / "hybrid-test-wheel.toml")
    shown = prepare(body, progress=True)
    err = capsys.readouterr().err
    states = re.findall(r"fem-prep hybrid-test-wheel:\s+\d+%\|[^|]*\|\s*(\d+)/(\d+)", err)
    assert states and states[-1] == ("6", "6")  # it stopped at 5/6 before
    for inner in (
        "factorisation of the full model",
        "modes of the full model (20)",
        "factorisation of K_ii",
        "constraint modes",
        "fixed-interface modes (10)",
        "projection H^T A H (5 matrices",
    ):
        assert inner in err, inner
    # the bars change nothing: the same condensed model as the one prepared without them
    # (fem_prep.condensed, progress=False: the suite's fem_prep cache, where the hybrid tests
    # condense this wheel; its modal coordinates are defined up to sign and, for the degenerate
    # nodal-diameter pairs, a rotation: ARPACK's start vector is random; compare what does not
    # depend on them)
    quiet = fem_prep.condensed(body)
    assert capsys.readouterr().err == ""
    nb = len(shown.master_dofs)
    for a, b in ((shown.condensed.K, quiet.K), (shown.condensed.M, quiet.M)):
        np.testing.assert_allclose(a[:nb, :nb], b[:nb, :nb], rtol=0, atol=1e-9 * np.abs(b).max())
    for key in ("frequencies_full_hz", "frequencies_condensed_hz"):
        np.testing.assert_allclose(getattr(shown, key), quiet.metadata[key], rtol=1e-9)
    np.testing.assert_allclose(shown.condensed.modes_hz, quiet.modes_hz, rtol=1e-9)


def test_eigen_solve_hook_counts_solves_and_leaves_the_modes():
    # fixed-fixed chain of n unit masses and springs: λ_j = 4 sin²(jπ / (2 (n + 1)))
    n, k = 600, 8
    K = sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1]).tocsr()
    M = sp.identity(n, format="csr")
    calls = []
    lam, phi = shift_invert_modes(K, M, k, on_solve=lambda: calls.append(1))
    exact = 4 * np.sin(np.arange(1, k + 1) * np.pi / (2 * (n + 1))) ** 2
    np.testing.assert_allclose(lam, exact, rtol=1e-9)
    assert len(calls) >= k  # one call per Lanczos solve
    lam0, phi0 = shift_invert_modes(K, M, k)  # without the hook (ARPACK's start is random)
    np.testing.assert_allclose(lam, lam0, rtol=1e-12)
    np.testing.assert_allclose(np.abs(np.sum(phi * phi0, axis=0)), 1.0, atol=1e-8)


@pytest.fixture(scope="module")
def hybrid_setup(fem_prep_cache):
    case = jio.load_case(DATA / "hybrid-test-case.toml")
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    return case, static_scene(case, bodies=(None, body))[0]


@pytest.mark.slow
def test_hybrid_sweep_in_chunks_equals_one_call(hybrid_setup):
    case, scene = hybrid_setup
    kw = {"integrator": Newmark(16), "window": SteadyState(3, 1)}
    speeds = [300.0, 600.0, 900.0]
    one = _sweep(scene, case.modifications, case.torque, speeds, **kw)
    done = []
    # chunks of 2: the last one padded (same compiled program), the padding dropped
    parts = _sweep(
        scene, case.modifications, case.torque, speeds, batching=Batching(2, done.append), **kw
    )
    assert done == [2, 3]
    flat_one, tree_one = jax.tree.flatten(one)
    flat_parts, tree_parts = jax.tree.flatten(parts)
    assert tree_one == tree_parts
    for a, b in zip(flat_one, flat_parts, strict=True):
        a, b = np.asarray(a), np.asarray(b)
        assert a.shape == b.shape and a.shape[0] == 3
        np.testing.assert_allclose(
            b, a, rtol=1e-12, atol=1e-12 * max(np.abs(a).max(initial=0.0), 1e-300)
        )
    with pytest.raises(ValueError, match="chunk_size"):
        _sweep(
            scene, case.modifications, case.torque, speeds, batching=Batching(chunk_size=0), **kw
        )


def test_sweep_default_folder_leaves_the_run_sweep_alone(tmp_path, monkeypatch, capsys):
    """``jaxgear sweep`` writes to ``jaxgear-out/<case>/sweep-START-STOP-N/``: the ``sweep/``
    of an earlier ``jaxgear run``, which its ``summary.json`` describes, stays as it was."""
    monkeypatch.chdir(tmp_path)
    run_dir = tmp_path / "jaxgear-out" / "accessory-spur"
    (run_dir / "sweep").mkdir(parents=True)
    run_sweep = {"speeds_rad_s": [100.0, 3000.0], "dynamic_factor": [1.1, 1.2]}
    (run_dir / "sweep" / "sweep.json").write_text(json.dumps(run_sweep))
    (run_dir / "summary.json").write_text(json.dumps({"dynamics": run_sweep}))
    seen = {}

    def fake_sweep_case(case, speeds, out_dir, **kw):  # the folder is what is under test
        seen["out"], seen["speeds"] = out_dir, np.asarray(speeds)
        s = {
            "speeds_rad_s": list(map(float, speeds)),
            "dynamic_factor": [1.0] * len(speeds),
            "natural_frequencies_Hz": [1000.0],
            "result": [0] * len(speeds),
            "elapsed_s": 0.0,
        }
        jio.write_json(pathlib.Path(out_dir) / "sweep.json", s)
        return s

    monkeypatch.setattr(cli_sweep, "sweep_case", fake_sweep_case)
    assert main(["sweep", "accessory-spur", "--speeds", "250:1250.5:3", "--quiet"]) == 0
    # written into a staging folder inside it, moved in place at the end
    assert pathlib.Path(seen["out"]).parent == pathlib.Path(
        "jaxgear-out/accessory-spur/sweep-250-1250.5-3"
    )
    np.testing.assert_allclose(seen["speeds"], [250.0, 750.25, 1250.5])
    assert json.loads((run_dir / "sweep" / "sweep.json").read_text()) == run_sweep
    assert json.loads((run_dir / "summary.json").read_text())["dynamics"] == run_sweep
    new = json.loads((run_dir / "sweep-250-1250.5-3" / "sweep.json").read_text())
    assert new["speeds_rad_s"] == [250.0, 750.25, 1250.5]
    assert "sweep-250-1250.5-3" in capsys.readouterr().out


def _settings(small=False, **kw):
    """The accessory-spur case and its optimise settings; ``small``: a coarser mesh (8 slices,
    16 positions per pitch), where the property is the outputs' bookkeeping, not a value."""
    case = jio.load_case("accessory-spur")
    if small:
        case = case.replace(slices=8, positions_per_pitch=16)
    s = check_settings(settings_from_case(case), case)
    s.update(kw)
    return case, s


def test_interrupted_optimiser_leaves_the_marker(tmp_path, monkeypatch):
    def interrupted(*args, **kw):
        raise KeyboardInterrupt

    # Ctrl-C as the optimiser starts (optimise.minimise maps the start to the unbounded space)
    monkeypatch.setattr(op.Problem, "unbounded", interrupted)
    case, settings = _settings()
    with pytest.raises(KeyboardInterrupt):
        optimise_case(case, settings, str(tmp_path), progress=False)
    assert not (tmp_path / "optimum.json").exists()
    marker = json.loads((tmp_path / PARTIAL).read_text())
    assert marker["complete"] is False and marker["stage"] == "optimiser running"
    assert marker["variables"] == ["tip_relief.depth", "tip_relief.extent"]
    assert "iterations" not in marker


@pytest.mark.filterwarnings("ignore:optimiser stopped at the iteration cap")
def test_interrupted_plots_leave_the_marker_until_a_run_finishes(tmp_path, monkeypatch):
    def interrupted(*args, **kw):
        raise KeyboardInterrupt

    # the guide's robust example (slow tier: test_readme_robust_example_converges_to_the_stated_
    # optimum) on the coarser mesh, three torques
    case, settings = _settings(
        small=True,
        max_iterations=2,
        objective="robust_te_rms",
        torques="40:120:3",
        reduce="mean",
        vars="tip_relief.depth,tip_relief.extent",
    )
    with monkeypatch.context() as mp:  # after the convergence plot, before optimum.json
        mp.setattr(plots, "harris_plot", interrupted)
        with pytest.raises(KeyboardInterrupt):
            optimise_case(case, settings, str(tmp_path), progress=False)
    assert (tmp_path / "convergence.png").is_file()
    assert not (tmp_path / "optimum.json").exists()
    marker = json.loads((tmp_path / PARTIAL).read_text())
    assert marker["complete"] is False and marker["stage"].startswith("post-processing")
    assert 1 <= marker["iterations"] <= 2 and marker["converged"] is False
    assert set(marker["parameters"]) == {"tip_relief.depth", "tip_relief.extent"}
    # the same run finished: optimum.json, no marker; the robust objective (the mean of the
    # TE RMS over the torques) lower in exact contact at the optimum than at the start, and
    # the torques those given
    rep = optimise_case(case, settings, str(tmp_path), progress=False)
    assert json.loads((tmp_path / "optimum.json").read_text())["iterations"] == rep["iterations"]
    assert not (tmp_path / PARTIAL).exists()
    assert rep["objective"] == "robust_te_rms" and rep["reduce"] == "mean"
    assert rep["torques_Nm"] == pytest.approx([40.0, 80.0, 120.0])
    assert rep["final"]["objective_exact_m"] < rep["initial"]["objective_exact_m"]


# default tier: tests/test_cli_scene_curves.py::test_run_writes_the_scene_te_and_stiffness_beside_the_rigid_mesh (the scene's bar over its steps ends full and names its solves, on a lumped 3D pair; te.csv's scene curves its quasi-static solution) and tests/test_every_kind.py::test_run_every_scene_kind[pair-hybrid] (jaxgear run's hybrid scene outputs)
@pytest.mark.slow
def test_run_scene_bar_covers_the_steps_after_the_quasi_static_bar(hybrid_setup, tmp_path, capsys):
    """``jaxgear run`` on a hybrid case: after its 7-step bar, a bar over the scene's steps
    (the condensed bodies, the scene, exact and smooth solves, maps and VTU files) ends full."""
    case, _ = hybrid_setup
    curves = {}
    out = scene_outputs(case, str(tmp_path / "scene"), progress=True, curves=curves)
    err = capsys.readouterr().err
    states = re.findall(r"jaxgear run hybrid-test: scene:\s+\d+%\|[^|]*\|\s*(\d+)/(\d+)", err)
    assert states and states[-1] == ("5", "5")  # speed 0: no solve at rest
    assert "quasi-static, exact contact" in err and "quasi-static, smooth contact" in err
    assert sorted(out["files"]) == sorted(
        f"scene/{f}"
        for f in (
            "load_map.png",
            "pressure_map.png",
            "body_gear.vtu",
            "contact.vtu",
            "body_gear_stress.vtu",
        )
    )
    # the hybrid curves for te.csv (jaxgear run): one period at the rigid mesh's first
    # positions, repeated over the second: equal to a two-period solve (the scene is periodic)
    assert curves["model"] == "hybrid" and set(curves["results"]) == {"exact", "smooth"}
    ex = curves["results"]["exact"]
    rigid = jg.quasi_static(
        case.mesh_model(),
        case.modifications,
        case.torque,
        positions_per_pitch=case.positions_per_pitch,
        periods=2,
    )
    n = ex.theta.shape[0]
    assert rigid.theta.shape[0] == 2 * n
    np.testing.assert_allclose(np.asarray(ex.theta), np.asarray(rigid.theta)[:n], atol=1e-15)
    two = jg.quasi_static(
        hybrid_setup[1],
        case.modifications,
        case.torque,
        speed=case.speed,
        contact=case.contact_law("exact"),
        positions_per_pitch=case.positions_per_pitch,
        periods=2,
    )
    np.testing.assert_allclose(
        np.tile(np.asarray(ex.transmission_error), 2), two.transmission_error, rtol=0, atol=1e-12
    )
    np.testing.assert_allclose(
        np.tile(np.asarray(ex.mesh_stiffness), 2), two.mesh_stiffness, rtol=1e-9
    )
    assert float(ex.te_mean) == pytest.approx(out["exact"]["te_mean_m"], rel=1e-12)
    assert float(ex.te_mean) > float(rigid.te_mean)  # the condensed wheel's compliance
    # contact.vtu in SI as the body VTUs: at the position of the largest line load
    import meshio

    data = meshio.read(tmp_path / "scene" / "contact.vtu").point_data
    assert set(data) == {"line_load_N_per_m", "contact_pressure_Pa", "contact_half_width_m"}
    e = out["exact"]
    assert data["line_load_N_per_m"].max() == pytest.approx(e["max_line_load_N_per_m"], rel=1e-9)
    assert 1e8 < data["contact_pressure_Pa"].max() <= e["max_contact_pressure_Pa"] * (1 + 1e-9)
    assert 0 < data["contact_half_width_m"].max() < 1e-3


# default tier: tests/test_optimise.py::test_robust_design_beats_single_load_optimum_in_the_worst_case (robust_te_rms over 5 torques, converged against the single-load optimum) and tests/test_progress_outputs.py::test_interrupted_plots_leave_the_marker_until_a_run_finishes (optimise_case with robust_te_rms, reduce mean, smaller mesh)
@pytest.mark.slow
def test_readme_robust_example_converges_to_the_stated_optimum(tmp_path):
    """docs/guide/modifications.md: ``jaxgear optimise accessory-spur --objective robust_te_rms
    --torques 40:120:5 --reduce mean --vars tip_relief.depth,tip_relief.extent`` converges in under 20 iterations
    to E = 12.8 µm, Γ = 0.235, mean TE RMS 0.627 µm from 0.748 µm (exact contact, contact beyond
    the path: the case files' default, its corner cells along the corner's normal; measured 14
    iterations, 12.797 µm, 0.2354, 0.6273 µm from 0.7480 µm)."""
    case, settings = _settings(
        objective="robust_te_rms",
        torques="40:120:5",
        reduce="mean",
        vars="tip_relief.depth,tip_relief.extent",
    )
    rep = optimise_case(case, settings, str(tmp_path), progress=False)
    assert rep["converged"] and rep["iterations"] < 20
    p = rep["final"]["parameters"]
    assert p["tip_relief.depth"] == pytest.approx(12.8, abs=0.05)
    assert p["tip_relief.extent"] == pytest.approx(0.235, abs=0.0005)
    assert rep["final"]["objective_exact_m"] == pytest.approx(0.627e-6, abs=0.0005e-6)
    assert rep["initial"]["objective_exact_m"] == pytest.approx(0.748e-6, abs=0.0005e-6)
    assert rep["torques_Nm"] == pytest.approx([40.0, 60.0, 80.0, 100.0, 120.0])
