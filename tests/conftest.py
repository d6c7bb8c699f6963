"""Test configuration: float64 on, strict rank promotion, non-interactive matplotlib; one JAX
persistent compilation cache for the test run; one fresh fem_prep cache for the session's
condensed test bodies; JAX's compiled executables released between families of test modules."""

import gc
import os
import pathlib
import re

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

import jax  # noqa: E402

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")


@pytest.hookimpl(trylast=True)  # after pytest's tmp_path plugin made its factory
def pytest_configure(config):
    """One JAX persistent compilation cache for the whole test run, in the run's temporary
    folder (pytest removes old ones), shared by the xdist workers (their base folders lie in
    the run's), a run without xdist, and the ``jaxgear`` subprocesses the CLI tests start (the
    environment carries it): a program compiled once in the run (a case's quasi-static solve, a
    sweep) is read back instead of compiled again by the other worker, by a later family after
    :func:`_release_compiled_code`, or by a CLI run. ``JAXGEAR_XLA_CACHE`` names the same
    folder, so that the CLI's own default (``~/.cache/jaxgear/xla``) or a user's setting is
    never used by the tests. Set before the first compilation (JAX checks the cache once per
    process)."""
    if getattr(config, "workerinput", None) and config.option.basetemp:
        base = pathlib.Path(config.option.basetemp).parent  # the controller's base folder
    else:
        factory = getattr(config, "_tmp_path_factory", None)
        if factory is None:  # pragma: no cover - pytest without its tmp_path plugin
            return
        base = factory.getbasetemp()
    path = str(base / "xla-cache")
    os.environ["JAX_COMPILATION_CACHE_DIR"] = path
    os.environ["JAXGEAR_XLA_CACHE"] = path
    os.environ.pop("JAXGEAR_XLA_CACHE_MAX_MB", None)
    os.environ["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0.2"
    jax.config.update("jax_enable_compilation_cache", True)
    jax.config.update("jax_compilation_cache_dir", path)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.2)


@pytest.fixture(scope="session")
def fem_prep_cache(tmp_path_factory):
    """A fresh ``$FEM_PREP_CACHE`` for the test session: the test bodies are condensed once
    there (the first module that asks) and never go to (or come from) the user's cache. Tests
    of the cache itself (a miss, a hit, a stale entry) set their own."""
    with pytest.MonkeyPatch.context() as mp:
        path = tmp_path_factory.mktemp("fem_prep_cache")
        mp.setenv("FEM_PREP_CACHE", str(path))
        yield path


def _family(module) -> str:
    """A module's family: ``test_hybrid_dynamics`` → ``hybrid`` (modules of one family compile
    the same programs: the same cases, scenes and settings)."""
    name = module.__name__.rsplit(".", 1)[-1]
    return re.sub(r"^test_", "", name).split("_")[0]


# Families by their cost on the 2-core CI machine (``pytest --durations``, heaviest first): the
# suite runs them first, so that the xdist workers (``-n 2 --dist worksteal``) share out the long
# tests early and end together on short ones; the families not named follow in name order.
HEAVY_FIRST = ("hybrid", "fem", "optimise", "dynamics", "progress", "regression", "readme")


def pytest_collection_modifyitems(config, items):
    """Run the heavy families first (:data:`HEAVY_FIRST`); a stable sort keeps each module's
    tests together and in their order (module fixtures are built once per module)."""
    rank = {f: k for k, f in enumerate(HEAVY_FIRST)}

    def key(item):
        module = getattr(item, "module", None)
        return len(rank) if module is None else rank.get(_family(module), len(rank))

    items.sort(key=key)


_last_family = [None]


@pytest.fixture(scope="module", autouse=True)
def _release_compiled_code(request):
    """Drop JAX's compilation caches when a new family of test modules starts.

    One process runs the whole suite: every compiled XLA executable keeps its code mapped, and
    after about 400 tests a compilation on the 2-core CI machine died with a segmentation fault
    inside XLA (vm.max_map_count is 65530 there). The modules of one family (pytest runs them
    one after the other: ``test_hybrid``, ``test_hybrid_composite``, ``test_hybrid_dynamics``,
    …) share their compiled programs; each family recompiles what it needs."""
    family = _family(request.module)
    if _last_family[0] is not None and family != _last_family[0]:
        jax.clear_caches()
        gc.collect()
    _last_family[0] = family
    yield
