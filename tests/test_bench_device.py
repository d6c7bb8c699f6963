"""``benchmarks/_device.py``: every platform's row runs on that platform's device.

The benchmark times each workload once per platform under ``jax.default_device``; a workload that
picks its device itself (``robust_samples(devices=...)``) must be given the platform's device, or
the "CPU" row silently runs on the accelerator (it did, in the first GPU run). On a machine
without an accelerator the CPU rows are checked; timing is not asserted (timing lives in the
benchmarks).
"""

import json

import jax
import numpy as np
import pytest

import jaxgear as jg
from benchmarks import bench_device
from jaxgear.io import load_case


def _rows_run_on_their_platform(out):
    """Each platform's rows ran on that platform's device and agree with the CPU's."""
    platforms = ["cpu"] + (["gpu"] if jax.default_backend() == "gpu" else [])
    for name, rows in out["workloads"].items():
        for plat in platforms:
            row = rows[plat]
            for r in row.get("rows", [row]):
                assert r["ran_on"].startswith(plat if plat == "cpu" else "cuda"), (name, r)
            assert row["max_rel_diff_from_cpu"] < 1e-12, (name, plat)


def test_te_curves_rows_run_on_their_platform_and_are_quasi_static_curves(tmp_path):
    """The batched TE curves workload alone: its rows and file, and the curves those of
    quasi_static called one at a time."""
    out = bench_device(tmp_path, quick=True, only=("te_curves",), verbose=False)
    written = json.loads((tmp_path / "bench_device.json").read_text())
    assert written["workloads"].keys() == {"te_curves"}
    _rows_run_on_their_platform(out)
    _te_curves_are_quasi_static_curves(out)


# default tier: tests/test_bench_device.py::test_te_curves_rows_run_on_their_platform_and_are_quasi_static_curves (the rows' platform and agreement, bench_device's file; on a CPU-only machine every row is a CPU row, so the Monte Carlo rows' platform check fails only where there is an accelerator)
@pytest.mark.slow
def test_every_row_runs_on_its_platform_and_agrees(tmp_path):
    out = bench_device(tmp_path, quick=True, only=("te_curves", "monte_carlo"), verbose=False)
    written = json.loads((tmp_path / "bench_device.json").read_text())
    assert written["workloads"].keys() == {"te_curves", "monte_carlo"}
    _rows_run_on_their_platform(out)
    _te_curves_are_quasi_static_curves(out)


def _te_curves_are_quasi_static_curves(out):
    """The batched TE curves are the curves of quasi_static called one at a time."""
    case = load_case("accessory-spur")
    rng = np.random.default_rng(1)
    gam, dep = rng.uniform(0.05, 0.6, 128), rng.uniform(0.0, 40e-6, 128)
    sample = out["workloads"]["te_curves"]["cpu"]["te_rms_m_every_16"]  # quick: 128 curves
    for k in (0, 5):
        i = 16 * k
        m = jg.MemberModification(
            tip_relief_depth=dep[i], tip_relief_extent=gam[i], tip_relief_shape=jg.LinearRelief()
        )
        one = jg.quasi_static(case.mesh_model(), jg.Modifications.symmetric(m), case.torque)
        np.testing.assert_allclose(sample[k], float(one.te_rms), rtol=1e-12)
