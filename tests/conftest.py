"""Test configuration: float64 on, strict rank promotion, non-interactive matplotlib; a
module-scoped fresh fem_prep cache for the tests that condense bodies."""

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
