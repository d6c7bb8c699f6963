"""``jaxgear bench trains --quick`` runs and writes its JSON and chart (a smoke test: no timing
asserted; timing lives in the benchmark): a row per model (torsional, lumped 3D) and chain of 1,
2, 3 meshes with the cells of each (8 per mesh at 4 slices: two contact lines of 4 slices each)
and the ratios to the model's first; the long span of the ``two-stage`` case at 35 steps per
period on its own-period table (rows 35 and 127: the LST period is 127/35 HST periods) and on
the long table of the span (4445 rows), with the same dynamic factors, and with the static rows
solved on every coordinate (as before the condensed structure), with the same dynamic factors."""

from __future__ import annotations

import json
import math

import jax
import pytest

from benchmarks import bench_trains
from jaxgear.cli import OUTPUT_FILES

jax.config.update("jax_enable_x64", True)


@pytest.mark.slow
def test_bench_trains_quick(tmp_path):
    out_dir = tmp_path / "bench"
    bench_trains(str(out_dir), quick=True)
    assert sorted(p.name for p in out_dir.iterdir()) == sorted(OUTPUT_FILES["bench trains"])
    saved = json.loads((out_dir / "bench_trains.json").read_text())
    assert saved["quick"] is True and saved["environment"]["dtype"] == "float64"
    rows = saved["rows"]
    assert [(r["model"], r["meshes"]) for r in rows] == [
        (m, n) for m in ("torsional", "lumped3d") for n in (1, 2, 3)
    ]
    assert [r["cells"] for r in rows] == [8, 16, 24] * 2
    assert [r["dofs"] for r in rows[:3]] == [2, 3, 4]
    assert all(r["dofs"] > 6 * r["gears"] for r in rows[3:])  # shaft nodes, 6 DOFs each
    assert rows[0]["quasi_static_ratio"] == rows[0]["newmark_ratio"] == 1.0
    assert rows[3]["quasi_static_ratio"] == rows[3]["newmark_ratio"] == 1.0
    # timings are recorded, not tested: a per-step cost is the difference of two short runs and
    # may come out negative on a loaded machine in the quick form
    assert all(
        math.isfinite(r["quasi_static_per_position_s"]) and math.isfinite(r["newmark_per_step_s"])
        for r in rows
    )
    span = saved["span"]
    assert span["own"]["rows"] == [35, 127] and span["long"]["table_rows"] == 127 * 35
    assert span["ratios_long_over_own"]["table_rows"] == 35.0
    assert span["dynamic_factor_rel_diff"] < 1e-10
    # the static rows on every coordinate (as before) against the condensed structure's
    assert (
        span["own_full"]["rows"] == [35, 127]
        and span["own_full"]["static_rows"] != (span["own"]["static_rows"])
    )
    assert span["dynamic_factor_rel_diff_condensed"] < 1e-10
