"""``jaxgear bench hybrid-sweep --quick`` runs on the small hybrid test case and writes its JSON
and chart (a smoke test: no timing asserted; timing lives in the benchmark). The full-coordinate
baselines of the benchmark integrate the same equations as the cell-space Newmark: the same
dynamic factor and the same mesh force step by step.
"""

from __future__ import annotations

import json
import pathlib

import pytest

from benchmarks import bench_hybrid_sweep
from jaxgear.cli import OUTPUT_FILES

CASE = pathlib.Path(__file__).parent / "data" / "hybrid-test-case.toml"


@pytest.mark.slow
def test_bench_hybrid_sweep_quick(tmp_path, fem_prep_cache):
    out_dir = tmp_path / "bench"
    out = bench_hybrid_sweep(
        out_dir, quick=True, case=str(CASE), compare_case=CASE, progress=False, verbose=False
    )
    saved = json.loads((out_dir / "bench_hybrid_sweep.json").read_text())
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(OUTPUT_FILES["bench hybrid-sweep"])
    assert (out_dir / "bench_hybrid_sweep.png").stat().st_size > 0
    assert saved["case"] == out["case"] == "hybrid-test" and saved["quick"] is True
    assert saved["dtype"] == "float64" and saved["jax"] and saved["machine"]["cpu_count"]
    for key in ("setup", "sweep", "convergence", "baseline", "scaling", "wall_s"):
        assert key in saved
    assert saved["setup"]["bodies"][0]["body"] == "hybrid-test-wheel"

    sw = saved["sweep"]
    assert len(sw["dynamic_factor"]) == len(sw["speeds_rad_s"]) == 4
    assert sw["result"] == [0, 0, 0, 0] and all(1.0 < v < 5.0 for v in sw["dynamic_factor"])
    assert sw["total_wall_s"] > 0 and sw["compile_s"] >= 0

    # the modal-basis sweep of the same speeds (ratios against the cell space of this run)
    mb = saved["sweep_modal_basis"]
    assert mb["result"] == [0, 0, 0, 0] and len(mb["dynamic_factor"]) == 4
    assert mb["total_wall_s"] > 0 and mb["ratio_total_wall_vs_cell_space"] > 0
    assert 0 <= mb["max_abs_df_error_vs_cell_space"] < 0.5

    # the baselines integrate the same equations
    bl = saved["baseline"]
    assert bl["result_woodbury"] == [0] * len(bl["speeds_rad_s"])
    assert bl["df_max_abs_diff"] < 1e-9
    agree = bl["per_step"]["first_steps_agreement"]
    assert set(agree) == {"woodbury", "refactor"}
    assert all(a["max_abs_diff_over_static_force"] < 1e-9 for a in agree.values())

    # the convergence run's first periods are the sweep's run: the same DF at the sweep speed
    st = saved["settings"]
    for row in saved["convergence"]["rows"]:
        assert len(row["df_per_period"]) == saved["convergence"]["long_periods"]
        if row["speed_rad_s"] in sw["speeds_rad_s"]:
            i = sw["speeds_rad_s"].index(row["speed_rad_s"])
            assert abs(row["df_at_sweep_periods"] - sw["dynamic_factor"][i]) < 1e-12
    assert st["periods"] == 4 and st["keep_periods"] == 2

    rows = saved["scaling"]["master_dofs"]["rows"]
    assert len(rows) == 1 and rows[0]["structure_dofs"] == saved["setup"]["structure_dofs"]
    for m in ("model", "woodbury", "refactor"):
        assert rows[0][f"{m}_per_step_s"] >= 0
    assert not list(out_dir.glob(".tmp-*"))


@pytest.mark.slow
def test_bench_modal_basis_quick(tmp_path, fem_prep_cache):
    """``jaxgear bench modal-basis --quick`` on the small hybrid test case: its JSON and chart,
    the cell-space and modal-basis sweeps of the same speeds."""
    from benchmarks import bench_modal_basis

    out_dir = tmp_path / "bench"
    out = bench_modal_basis(out_dir, quick=True, case=str(CASE), verbose=False)
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(OUTPUT_FILES["bench modal-basis"])
    saved = json.loads((out_dir / "modal_basis.json").read_text())
    assert saved["case"] == out["case"] == "hybrid-test" and saved["dtype"] == "float64"
    n = len(saved["settings"]["speeds_rad_s"])
    assert saved["cell_space"]["result"] == [0] * n
    assert [r["modes"] for r in saved["modal"]] == [20, 80]
    for r in saved["modal"]:
        assert r["result"] == [0] * n and 0 <= r["max_abs_df_error"] < 0.5
        assert r["basis_s"] > 0 and r["extrapolated_100_speeds_s"] > 0
