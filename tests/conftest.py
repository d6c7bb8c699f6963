"""Test configuration: float64 on, strict rank promotion, non-interactive matplotlib, one BLAS
thread per process; one JAX persistent compilation cache for the test run; one fresh fem_prep
cache for the run's condensed test bodies (shared by the xdist workers too); JAX's compiled
executables released between families of test modules above a bound of memory maps."""

import collections
import gc
import json
import os
import pathlib
import re
import resource
import subprocess
import sys
import time

import pytest

os.environ.setdefault("MPLBACKEND", "Agg")

# XLA's CPU backend builds the test programs with LLVM at -O0 (set before JAX starts its backend;
# the subprocesses the tests start inherit it): most of the suite's time is compiling programs
# that then run a few steps. The unoptimised code keeps IEEE arithmetic, so its results are the
# optimised code's to round-off, but it may compute one value in two kernels that round
# differently (jaxgear.safe_max is the derivative of a maximum that survives it;
# test_optimise_robust checks the robust gradient at this level). An XLA_FLAGS that names the
# level is kept (--xla_backend_optimization_level=3: XLA's default pipeline).
if "xla_backend_optimization_level" not in os.environ.get("XLA_FLAGS", ""):
    os.environ["XLA_FLAGS"] = (
        os.environ.get("XLA_FLAGS", "") + " --xla_backend_optimization_level=0"
    ).strip()


def _xla_accepts(flag: str) -> bool:
    """Whether the installed jaxlib's XLA accepts ``flag`` in ``XLA_FLAGS``: a process with an
    unknown flag stops as its backend starts, so a child process tries it (about a second, once
    per run: the xdist workers and the CLI subprocesses inherit the environment set here)."""
    env = dict(os.environ, XLA_FLAGS=f"{os.environ.get('XLA_FLAGS', '')} {flag}".strip())
    env["JAX_PLATFORMS"] = "cpu"
    probe = [sys.executable, "-c", "import jax; jax.devices()"]
    try:
        r = subprocess.run(probe, env=env, capture_output=True, timeout=300, check=False)
    except subprocess.TimeoutExpired:  # pragma: no cover - a stalled machine: leave it out
        return False
    return r.returncode == 0


# Settings of XLA's CPU compiler that cut the CPU it spends compiling the test programs without
# changing their IEEE arithmetic (the same HLO, the same operations): each is added only where
# this jaxlib knows the flag (a child process tries them, once per run), and an XLA_FLAGS that
# names a flag is kept (its value there wins).
# - the element-wise IR emitter for the fusions instead of the newer MLIR fusion emitters: about
#   40 % less CPU compiling (on the 2-core CI machine, jaxlib 0.10.2: the first 174 tests of the
#   suite's "other" files 352 → 205 CPU s, tests/test_optimise_dynamic.py and
#   tests/test_gradients.py in paired runs 82 → 47 CPU s; =true: XLA's default, XLA is retiring
#   the element-wise route);
# - one LLVM module per program (XLA splits it into parts compiled in parallel threads, which
#   costs CPU to clone and link, and gains nothing on a machine whose cores the xdist workers
#   already fill) and LLVM's expensive passes left out (the programs run at -O0 anyway): 3-9 %
#   less CPU on the test files measured, the same compilations (docs/bench/suite_profile.json,
#   "xla_flags"), and a third fewer memory maps (the release below comes later).
_XLA_TEST_FLAGS = (
    "--xla_cpu_use_fusion_emitters=false",
    "--xla_cpu_parallel_codegen_split_count=1",
    "--xla_llvm_disable_expensive_passes=true",
)
_new_flags = [
    f for f in _XLA_TEST_FLAGS if f[2:].split("=")[0] not in os.environ.get("XLA_FLAGS", "")
]
if _new_flags:
    _accepted = _new_flags if _xla_accepts(" ".join(_new_flags)) else []
    _accepted = _accepted or [f for f in _new_flags if _xla_accepts(f)]
    if _accepted:
        os.environ["XLA_FLAGS"] = " ".join([os.environ.get("XLA_FLAGS", ""), *_accepted]).strip()

# pypardiso looks for MKL's runtime library as it is imported (a recursive search of the
# environment's library folders where the linker does not find it, as in a venv: 0.2-0.4 CPU s
# and a few subprocesses); named here once, the xdist workers and the subprocesses the tests
# start (CLI runs, the docs build) inherit it (fem_prep's later PARDISO handles reuse their
# process's first library anyway: fem_prep._solver._pardiso_solver)
if "PYPARDISO_MKL_RT" not in os.environ:
    try:
        import pypardiso
    except ImportError:  # pragma: no cover - no MKL wheel (not x86-64)
        pypardiso = None
    _mkl = getattr(getattr(getattr(pypardiso, "ps", None), "libmkl", None), "_name", None)
    if isinstance(_mkl, str):
        os.environ["PYPARDISO_MKL_RT"] = _mkl

# One BLAS and OpenMP thread per test process (OpenBLAS under NumPy and SciPy, MKL under
# PARDISO): the suite runs in two xdist workers on the 2-core CI machine, where a second BLAS
# thread finds no free core (the other worker, XLA's compiler) and spin-waits. The results are
# the same to round-off. Paired on the 2-core machine (docs/bench/suite_profile.json,
# "blas_threads_2026_11_27"): tests/test_hybrid_composite.py 30.4 → 13.9 CPU s (its NumPy
# reference's dense solves), the fem_prep and hybrid train files not otherwise changed 8 %
# less. The workers and the subprocesses the tests start inherit the variables; this process
# loaded NumPy already (jaxtyping's pytest plugin imports it), so its libraries are limited at
# run time too (threadpoolctl, as fem_prep's ``blas_threads`` does; that one leaves a set
# OPENBLAS_NUM_THREADS or OMP_NUM_THREADS alone). A thread count set in the environment is kept.
_THREAD_VARS = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "OMP_NUM_THREADS")
if not any(os.environ.get(v) for v in _THREAD_VARS):
    from threadpoolctl import threadpool_limits

    for _var in _THREAD_VARS:
        os.environ[_var] = "1"
    threadpool_limits(limits=1)

import jax  # noqa: E402
from jax import monitoring

jax.config.update("jax_enable_x64", True)
jax.config.update("jax_numpy_rank_promotion", "raise")


# the run's base temporary folder (the xdist controller's, shared by its workers)
_RUN_BASE: list = [None]


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
    _RUN_BASE[0] = base
    path = str(base / "xla-cache")
    os.environ["JAX_COMPILATION_CACHE_DIR"] = path
    os.environ["JAXGEAR_XLA_CACHE"] = path
    os.environ.pop("JAXGEAR_XLA_CACHE_MAX_MB", None)
    os.environ["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0.2"
    jax.config.update("jax_enable_compilation_cache", True)
    jax.config.update("jax_compilation_cache_dir", path)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", 0.2)
    if os.environ.get("JAXGEAR_TEST_COMPILE_LOG"):
        _count_compilations()


# JAX's monitoring events counted per test when $JAXGEAR_TEST_COMPILE_LOG names a file (a
# profile of the suite: which tests compile, for how long, and what the persistent cache saved)
_EVENTS = {
    "/jax/core/compile/backend_compile_duration": "compile_s",
    "/jax/core/compile/jaxpr_trace_duration": "trace_s",
    "/jax/core/compile/jaxpr_to_mlir_module_duration": "lower_s",
    "/jax/compilation_cache/cache_retrieval_time_sec": "cache_read_s",
    "/jax/compilation_cache/compile_time_saved_sec": "saved_s",
}
_COUNTS = {
    "/jax/compilation_cache/cache_hits": "hits",
    "/jax/compilation_cache/cache_misses": "written",
}
_tally = collections.Counter()
_programs = collections.Counter()  # backend compile seconds by function name, in the test


def _count_compilations():
    def duration(name, secs, **kw):
        if name in _EVENTS:
            _tally[_EVENTS[name]] += secs
            if name.endswith("backend_compile_duration"):
                _tally["compiles"] += 1
                _programs[kw.get("fun_name", "?")] += secs
                _programs[kw.get("fun_name", "?") + " #"] += 1

    def event(name, **kw):
        if name in _COUNTS:
            _tally[_COUNTS[name]] += 1

    monitoring.register_event_duration_secs_listener(duration)
    monitoring.register_event_listener(event)


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    """With ``$JAXGEAR_TEST_COMPILE_LOG``: one JSON line per test (wall and CPU seconds, the
    CPU seconds of the subprocesses it waited for (``child_cpu_s``: a CLI run or a pytest in
    a subprocess, whose compilations this process does not see), compilations and their
    seconds, persistent-cache reads), appended to that file."""
    path = os.environ.get("JAXGEAR_TEST_COMPILE_LOG")
    if not path:
        yield
        return
    before, t0, c0 = dict(_tally), time.perf_counter(), time.process_time()
    k0 = _children_cpu()
    _programs.clear()
    yield
    row = {k: round(v - before.get(k, 0), 3) for k, v in _tally.items()}
    top = [k for k, _ in _programs.most_common() if not k.endswith(" #")][:10]
    row["programs"] = {k: [int(_programs[k + " #"]), round(_programs[k], 2)] for k in top}
    row.update(
        test=item.nodeid,
        wall_s=round(time.perf_counter() - t0, 3),
        cpu_s=round(time.process_time() - c0, 3),
        child_cpu_s=round(_children_cpu() - k0, 3),
        worker=os.environ.get("PYTEST_XDIST_WORKER", "-"),
        maps=_memory_maps(),
    )
    with open(path, "a") as f:
        f.write(json.dumps(row) + "\n")


def _children_cpu() -> float:
    """User + system CPU seconds of this process's finished (waited-for) subprocesses."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


@pytest.fixture(scope="session")
def fem_prep_cache(tmp_path_factory):
    """A fresh ``$FEM_PREP_CACHE`` for the test run: the test bodies are condensed once there
    (the first module that asks, in either xdist worker: the folder lies in the run's base
    folder, and fem_prep writes an entry by renaming a finished temporary file, so a worker
    reads only whole bodies) and never go to (or come from) the user's cache. Tests of the
    cache itself (a miss, a hit, a stale entry) set their own."""
    with pytest.MonkeyPatch.context() as mp:
        if _RUN_BASE[0] is None:  # pragma: no cover - pytest without its tmp_path plugin
            path = tmp_path_factory.mktemp("fem_prep_cache")
        else:
            path = _RUN_BASE[0] / "fem_prep_cache"
            path.mkdir(exist_ok=True)
        mp.setenv("FEM_PREP_CACHE", str(path))
        yield path


@pytest.fixture
def no_figures(monkeypatch):
    """The CLI runs of a test that never reads a figure write none
    (``$JAXGEAR_TEST_NO_FIGURES``, :func:`jaxgear.cli._plots._figure.figures_off`): drawing and
    encoding a PNG costs about 0.14 CPU s, 10-25 % of the small runs of the tests. Its runs in this process and in
    the subprocesses it starts (the environment carries it); a run's other files, its printed
    lines and its ``summary.json`` numbers are unchanged (its lists of files lack the PNGs). A
    module whose tests never look at figures or at lists of output files takes it for all of
    them: ``pytestmark = pytest.mark.usefixtures("no_figures")``."""
    monkeypatch.setenv("JAXGEAR_TEST_NO_FIGURES", "1")


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


def _say_collected(config, n: int) -> None:
    """Print ``collected N tests`` (the tests that will run, after ``-m``'s deselection) on a
    line of its own before the first result, also under ``-q`` and xdist (the README's test
    command: its count up front)."""
    reporter = config.pluginmanager.get_plugin("terminalreporter")
    if reporter is not None and not getattr(config, "_said_collected", False):
        config._said_collected = True
        reporter.ensure_newline()
        reporter.write_line(f"collected {n} tests")


def pytest_collection_finish(session):
    """Without xdist (or in its workers, which print nothing): :func:`_say_collected`."""
    if not getattr(session.config, "workerinput", None):
        _say_collected(session.config, len(session.items))


@pytest.hookimpl(optionalhook=True)
def pytest_xdist_node_collection_finished(node, ids):
    """xdist's controller, when the first worker has collected (every worker collects the same
    tests): :func:`_say_collected`."""
    _say_collected(node.config, len(ids))


_last_family = [None]

# The process's memory maps above which a new family releases the compiled programs (the
# kernel's vm.max_map_count is 65530 on the CI machine); $JAXGEAR_TEST_RELEASE_MAPS changes it
# (0: release at every new family). 20 000 was reached after ~90 tests, so that most of a run
# traced and compiled again after each family change; at 30 000 a clean CI run took 9:36
# against 10:46 at 20 000 (the same tree, the idle machine, session 60), with no crash.
RELEASE_MAPS = int(os.environ.get("JAXGEAR_TEST_RELEASE_MAPS", "30000"))


def _memory_maps() -> int:
    """The process's memory maps (lines of /proc/self/maps); 0 where there is no /proc."""
    try:
        with open("/proc/self/maps", "rb") as f:
            return sum(1 for _ in f)
    except OSError:  # pragma: no cover - not Linux
        return 0


@pytest.fixture(scope="module", autouse=True)
def _release_compiled_code(request):
    """Drop JAX's compilation caches when a new family of test modules starts and the process
    holds more than :data:`RELEASE_MAPS` memory maps.

    One process runs the whole suite: every compiled XLA executable keeps its code mapped, and
    after about 400 tests a compilation on the 2-core CI machine died with a segmentation fault
    inside XLA (vm.max_map_count is 65530 there). The modules of one family (pytest runs them
    one after the other: ``test_hybrid``, ``test_hybrid_composite``, ``test_hybrid_dynamics``,
    …) share their compiled programs; below the bound the next families share them too (the
    quasi-static solve of a case, the small programs of eager operations) instead of compiling
    them again."""
    family = _family(request.module)
    new_family = _last_family[0] is not None and family != _last_family[0]
    if new_family and _memory_maps() > RELEASE_MAPS:
        jax.clear_caches()
        gc.collect()
    _last_family[0] = family
    yield
