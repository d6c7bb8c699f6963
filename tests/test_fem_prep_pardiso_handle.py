"""PARDISO factors find MKL through the library pypardiso loaded as it was imported: pypardiso's
search of the environment's library folders (a recursive glob) runs for none of them, the
caller's environment is left as it was, and a PYPARDISO_MKL_RT of the caller's is the one used.
The solves are checked against a dense solve (1e-12 relative)."""

import glob
import importlib.util
import os

import numpy as np
import pytest
import scipy.sparse as sp

from fem_prep import PardisoFactor

pytestmark = pytest.mark.skipif(
    importlib.util.find_spec("pypardiso") is None, reason="pypardiso is not installed"
)


def _spd(n=40, seed=0):
    A = sp.random(n, n, density=0.1, random_state=seed)
    return (A @ A.T + 10.0 * sp.eye(n)).tocsr()


def test_factors_skip_the_library_search(monkeypatch):
    import pypardiso

    assert os.path.exists(pypardiso.ps.libmkl._name)  # the import-time handle's library
    monkeypatch.delenv("PYPARDISO_MKL_RT", raising=False)
    searches = []
    real_glob = glob.glob

    def counted(*args, **kw):
        searches.append(args)
        return real_glob(*args, **kw)

    monkeypatch.setattr(glob, "glob", counted)
    A = _spd()
    b = np.random.default_rng(1).standard_normal((A.shape[0], 3))
    want = np.linalg.solve(A.toarray(), b)
    for _ in range(3):
        f = PardisoFactor(A)
        np.testing.assert_allclose(f.solve(b), want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    assert searches == []
    assert "PYPARDISO_MKL_RT" not in os.environ


def test_the_callers_library_setting_wins(monkeypatch):
    monkeypatch.setenv("PYPARDISO_MKL_RT", "/nonexistent/callers_mkl_rt.so")
    with pytest.raises(OSError, match="callers_mkl_rt"):
        PardisoFactor(_spd())
    assert os.environ["PYPARDISO_MKL_RT"] == "/nonexistent/callers_mkl_rt.so"
