"""Test configuration: float64 on, strict rank promotion, non-interactive matplotlib; a
module-scoped fresh fem_prep cache for the tests that condense bodies; JAX's compiled
executables released after each test module."""

import gc
import os

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.fixture(scope="module")
def fem_prep_cache(tmp_path_factory):
    """A fresh ``$FEM_PREP_CACHE`` for one test module: its bodies are condensed once there and
    never go to (or come from) the user's cache."""
    with pytest.MonkeyPatch.context() as mp:
        path = tmp_path_factory.mktemp("fem_prep_cache")
        mp.setenv("FEM_PREP_CACHE", str(path))
        yield path


@pytest.fixture(scope="module", autouse=True)
def _release_compiled_code():
    """Drop JAX's compilation caches after each test module.

    One process runs the whole suite: every compiled XLA executable keeps its code mapped, and
    after about 400 tests a compilation on the 2-core CI machine died with a segmentation fault
    inside XLA (vm.max_map_count is 65530 there). Each module recompiles what it needs."""
    yield
    jax.clear_caches()
    gc.collect()
