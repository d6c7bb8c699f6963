"""``jaxgear bench hybrid --quick`` runs and writes its JSON and chart (a smoke test: no timing
asserted; timing lives in the benchmark), on the small hybrid test case with a fresh fem_prep
cache. The relief map is vmapped with the flexible wheel: its TE at one grid point equals a
single :func:`jaxgear.quasi_static` call.
"""

from __future__ import annotations

import json
import pathlib

import pytest

from benchmarks import bench_hybrid
from jaxgear.cli import OUTPUT_FILES

CASE = pathlib.Path(__file__).parent / "data" / "hybrid-test-case.toml"


@pytest.mark.slow
def test_bench_hybrid_quick(tmp_path, monkeypatch):
    monkeypatch.setenv("FEM_PREP_CACHE", str(tmp_path / "fem_prep_cache"))
    out_dir = tmp_path / "bench"
    out = bench_hybrid(out_dir, quick=True, case=str(CASE), progress=False, verbose=False)
    saved = json.loads((out_dir / "bench_hybrid.json").read_text())
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(OUTPUT_FILES["bench hybrid"])
    assert (out_dir / "bench_hybrid.png").stat().st_size > 0
    assert saved["case"] == out["case"] == "hybrid-test" and saved["quick"] is True
    assert saved["dtype"] == "float64" and saved["jax"] and saved["machine"]["cpu_count"]
    for key in ("setup", "te_curve", "cost_split", "relief_map", "scaling", "wall_s"):
        assert key in saved

    body = saved["setup"]["bodies"][0]
    assert body["body"] == "hybrid-test-wheel" and body["cache_hit"] is False
    assert body["rim_master_dofs"] == 30 * 3 * 3 and body["modes"] >= 10  # pairs kept whole
    assert body["fem_prep_timings_s"]["condensation_s"] > 0

    tc = saved["te_curve"]
    for model in ("hybrid", "rigid"):
        for mode in ("exact", "smooth"):
            for how in ("jit", "public"):
                row = tc[model][mode][how]
                assert row["per_curve_s"] > 0 and row["compile_s"] >= 0
    for mode in ("exact", "smooth"):
        assert tc["ratio_hybrid_over_rigid"][mode]["jit"] > 0
    assert tc["hybrid_te_rms_m"] > 0 and tc["rigid_te_rms_m"] > 0
    cached = tc["hybrid_cached_compliance"]  # the same curve from the cached compliance
    assert cached["te_max_rel_diff"] <= 1e-12 and cached["per_curve_s"] > 0
    assert cached["smooth"]["te_max_rel_diff"] <= 1e-12 and cached["uncached_per_curve_s"] > 0
    for mode in ("exact", "smooth"):  # an optimisation iteration: the same value and gradient
        g = saved["gradient"][mode]
        assert g["grad_rel_diff"] <= 1e-9 and g["value_rel_diff"] <= 1e-12
        assert g["rigid_s"] > 0 and g["hybrid_cached_s"] > 0 and g["hybrid_uncached_s"] > 0

    rm = saved["relief_map"]
    assert rm["shape"] == [5, 5] and rm["slices"] == 8 and rm["positions_per_pitch"] == 16
    assert rm["tip_relief_depth_m"][0] == 0.0 and abs(rm["tip_relief_depth_m"][-1] - 30e-6) < 1e-15
    assert rm["speedup_cached_over_uncached"] > 0  # before (uncached) and after, one run
    assert rm["te_rms_max_rel_diff_cached_uncached"] <= 1e-12
    for model in ("hybrid", "hybrid_uncached", "rigid"):
        m = rm[model]
        assert m["curves"] == 25 and m["curves_per_s"] > 0
        assert m["memory"]["ru_maxrss_process_mib"] > 0
        assert len(m["te_rms_m"]) == 5 and all(len(r) == 5 for r in m["te_rms_m"])
    # vmappability: the vmapped (lax.map) map = single calls at one grid point
    vc = rm["hybrid"]["vmap_check"]
    assert vc["te_rms_rel_diff"] <= 1e-9 and vc["te_curve_max_rel_diff"] <= 1e-9
    i, j = vc["grid_index"]
    assert rm["hybrid"]["te_rms_m"][i][j] == vc["te_rms_map_m"]

    sc = saved["scaling"]
    assert (
        len(sc["window"]) == 2 and sc["window"][1]["window_dofs"] > sc["window"][0]["window_dofs"]
    )
    # a wider window than needed changes nothing but the cost on the theoretical path; beyond
    # it (the case's default) the corner cells' free-drive part comes off along the window's
    # inertias (docs/extended-contact.md, "Open"): 4 more rim stations move the TE by 8.9e-4
    # of its peak (measured, session 60), 8 more by 1.9e-3; with extended_contact = false
    # both 2e-16
    assert sc["window"][0]["te_rel_diff_to_default_window"] == 0.0
    assert all(r["te_rel_diff_to_default_window"] <= 3e-3 for r in sc["window"])
    assert [r["slices"] for r in sc["cells"]] == [8, 16]
    assert "skipped" in sc["body_size"]  # the comparison case is the case itself
    assert not list(out_dir.glob(".tmp-*"))
