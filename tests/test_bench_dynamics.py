"""``jaxgear bench dynamics --quick`` runs and writes its JSON (a smoke test: no timing asserted).

The baselines' accuracy is what the benchmark reports; here only that every row is there and that
the Numba Newmark (same algorithm, same cell table) reproduces jaxgear's dynamic factors.
"""

import json

import pytest

from benchmarks import bench_dynamics, numba_available


def _check(saved, numba):
    names = [r["method"] for r in saved["rows"]]
    assert names[0] == "jaxgear Newmark (vmap)"
    assert any(n.startswith("solve_ivp LSODA") for n in names)
    rows = {r["method"]: r for r in saved["rows"]}
    assert rows["jaxgear Newmark (vmap)"]["run_s"] > 0
    assert saved["platform"]["dtype"] == "float64" and saved["platform"]["jax"]
    nb = [r for r in saved["rows"] if r["method"].startswith("Numba")]
    if numba:
        assert len(nb) == 2 and all(r["max_abs_diff_vs_jaxgear"] < 1e-9 for r in nb)
    else:
        assert nb == [{"method": "Numba Newmark", "skipped": "numba not installed"}]


@pytest.mark.slow
def test_bench_dynamics_quick_without_numba(tmp_path):
    out = bench_dynamics(
        tmp_path, quick=True, progress=False, verbose=False, stability=False, numba=False
    )
    saved = json.loads((tmp_path / "bench_dynamics.json").read_text())
    assert saved["speeds"] == out["speeds"] == 16
    _check(saved, numba=False)
    assert not list(tmp_path.glob(".tmp-*"))


@pytest.mark.slow
@pytest.mark.skipif(
    not numba_available(), reason="numba not installed (pip install jaxgear[bench])"
)
def test_bench_dynamics_quick_numba(tmp_path):
    bench_dynamics(tmp_path, quick=True, progress=False, verbose=False, stability=False)
    _check(json.loads((tmp_path / "bench_dynamics.json").read_text()), numba=True)
