"""The CLI's persistent XLA compilation cache (jaxgear/cli/xla_cache.py): a second identical
``jaxgear run`` reads back every program the first one wrote (JAX's monitoring events: no cache
miss, as many hits as the first run's cached compilations) and gives the same results; where
the folder is, how it is switched off, and its size bound."""

import json
import os
import pathlib
import subprocess
import sys

import pytest

from jaxgear.cli import xla_cache as xc

# A CLI run that counts JAX's compilation events (jax.monitoring) and writes them to argv[1].
PROBE = """
import collections, json, sys
from jax import monitoring
events = collections.Counter()
compile_s = []
monitoring.register_event_listener(lambda name, **kw: events.update([name]))
def _duration(name, secs, **kw):
    if name == "/jax/core/compile/backend_compile_duration":
        compile_s.append(secs)
monitoring.register_event_duration_secs_listener(_duration)
from jaxgear.cli import main
status = main(sys.argv[2:])
with open(sys.argv[1], "w") as f:
    json.dump({"status": status, "events": events, "backend_compile_s": compile_s}, f)
"""
HITS = "/jax/compilation_cache/cache_hits"
MISSES = "/jax/compilation_cache/cache_misses"  # a program compiled and written to the cache
USING = "/jax/compilation_cache/tasks_using_cache"
# every program asked of the cache: those not read back were compiled in the run (a program
# JAX does not write, one holding a Python callback such as eqx.error_if's, is one each run)
REQUESTS = "/jax/compilation_cache/compile_requests_use_cache"


def _run(tmp_path, cache, name, case="accessory-spur", command=("run",)):
    env = dict(os.environ)
    env.pop("JAX_COMPILATION_CACHE_DIR", None)  # the CLI switches the cache on, not JAX's env
    env["JAXGEAR_XLA_CACHE"] = str(cache)
    # every program, however short its compilation: with the CLI's 0.2 s a program compiled in
    # about 0.2 s can fall under it in the first run and over it in the second (a miss)
    env["JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"] = "0"
    out = tmp_path / name
    events = tmp_path / f"{name}.json"
    args = [command[0], case, *command[1:], "--out", str(out), "--quiet"]
    proc = subprocess.run(
        [sys.executable, "-c", PROBE, str(events), *args],
        env=env,
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    record = json.loads(events.read_text())
    assert record["status"] == 0
    return out, record["events"]


@pytest.mark.slow
def test_second_run_compiles_nothing_again(tmp_path):
    cache = tmp_path / "xla"
    out1, first = _run(tmp_path, cache, "first")
    assert first.get(USING) == 1
    written = first.get(MISSES, 0)
    assert written > 0  # the case's large programs (its sweep, its scene) went to the cache
    assert len(list(cache.glob("*-cache"))) == written
    out2, second = _run(tmp_path, cache, "second")
    assert second.get(USING) == 1
    assert second.get(MISSES, 0) == 0  # nothing the first run cached was compiled again
    assert second.get(HITS, 0) == written + first.get(HITS, 0)
    # and nothing was compiled at all: every program asked for was read back
    assert second.get(REQUESTS, 0) == second.get(HITS, 0)
    # read-back programs give the same numbers as freshly compiled ones
    assert json.loads((out2 / "summary.json").read_text()) == json.loads(
        (out1 / "summary.json").read_text()
    )
    for name in ("te.csv", "mesh_stiffness.csv"):
        assert (out2 / name).read_bytes() == (out1 / name).read_bytes()


# fast twin: test_second_planetary_sweep_compiles_nothing_again (the same carrier-frame sweep
# engine, Campbell diagram and ring spectrum on a short explicit plan); this one's cost is the
# run's automatic plan (about 49 000 Newmark steps at each of its 9 speeds, twice: ~26 s on the
# idle 2-core CI machine), not its compilations
@pytest.mark.slow
def test_second_planetary_run_compiles_nothing_again(tmp_path):
    """The planetary case lin-parker-1999 (modes, Campbell diagram, load sharing, the carrier-
    frame sweep; about 30 s for both runs): its second run reads back every program the first
    one compiled (its load sharing and Campbell checks are read on the host, not by programs
    holding a Python callback, which JAX never writes to the cache) and gives the same
    numbers."""
    cache = tmp_path / "xla"
    out1, first = _run(tmp_path, cache, "first", "lin-parker-1999")
    written = first.get(MISSES, 0)
    assert written > 0
    assert first.get(REQUESTS, 0) == written  # every program it compiled was written
    out2, second = _run(tmp_path, cache, "second", "lin-parker-1999")
    assert second.get(MISSES, 0) == 0
    assert second.get(REQUESTS, 0) == second.get(HITS, 0) == written
    for name in ("modes.json", "summary.json", "sweep/sweep.csv"):
        assert (out2 / name).read_bytes() == (out1 / name).read_bytes(), name
    sweeps = [json.loads((o / "sweep" / "sweep.json").read_text()) for o in (out1, out2)]
    for s in sweeps:
        s.pop("elapsed_s")  # wall time of the sweep, the one entry that differs
    assert sweeps[0] == sweeps[1]


# default tier: tests/test_xla_cache.py::test_a_program_is_written_and_read_back_in_process (the cache writes a program and reads it back with the same numbers) and ::test_import_compiles_nothing
@pytest.mark.slow
def test_second_planetary_sweep_compiles_nothing_again(tmp_path, no_figures):
    """``jaxgear sweep`` on lin-parker-1999 (2 speeds, an explicit plan of 4 periods of 64
    steps: the cache's behaviour does not depend on the plan's size, and the under-resolution
    warning on stderr does not matter here): the carrier-frame sweep, its Campbell diagram and
    ring spectrum; the second run reads back every program the first one compiled and wrote
    (no program holding a Python callback) and gives the same numbers. The whole ``jaxgear
    run`` (load sharing, modes, rating on top) is the slow twin above; the load sharing's and
    Campbell's host checks under a caller's jit: test_planetary_checks_under_a_callers_jit."""
    cache = tmp_path / "xla"
    sweep = ("sweep", "--speeds", "80:120:2", "--steps-per-period", "64", "--periods", "4",
             "--keep-periods", "2")
    out1, first = _run(tmp_path, cache, "first", "lin-parker-1999", sweep)
    written = first.get(MISSES, 0)
    assert written > 0
    # every program it asked for was compiled and written, or read back (one asked twice)
    assert first.get(REQUESTS, 0) == written + first.get(HITS, 0)
    out2, second = _run(tmp_path, cache, "second", "lin-parker-1999", sweep)
    assert second.get(MISSES, 0) == 0
    assert second.get(REQUESTS, 0) == second.get(HITS, 0) == written + first.get(HITS, 0)
    assert (out2 / "sweep.csv").read_bytes() == (out1 / "sweep.csv").read_bytes()
    sweeps = [json.loads((o / "sweep.json").read_text()) for o in (out1, out2)]
    for s in sweeps:
        s.pop("elapsed_s")  # wall time of the sweep, the one entry that differs
    assert sweeps[0] == sweeps[1]
    assert sweeps[0]["campbell"] and sweeps[0]["ring_spectrum"]


def test_a_program_is_written_and_read_back_in_process(monkeypatch):
    """The persistent cache in this process (the suite's folder, tests/conftest.py; every
    program written, as the CLI's :data:`MIN_COMPILE_SECS`): a program compiled once is written
    (a cache miss), and the same program traced again from a new function object (nothing in
    memory to reuse) is read back (a hit, no miss) and gives the same numbers. The CLI's runs
    twice in subprocesses are the slow tier's."""
    import uuid

    import jax
    import jax.numpy as jnp
    from jax import monitoring

    events = []

    def listen(name, **kw):
        events.append(name)

    salt = 1.0 + uuid.uuid4().int % 10**6 / 10**7  # a program no earlier run wrote

    def make():
        def program(x):
            return jnp.cumsum(jnp.sin(x) * salt) @ x

        return jax.jit(program)

    x = jnp.linspace(0.0, 1.0, 7)
    before = jax.config.values["jax_persistent_cache_min_compile_time_secs"]
    monitoring.register_event_listener(listen)
    try:
        jax.config.update("jax_persistent_cache_min_compile_time_secs", xc.MIN_COMPILE_SECS)
        first = float(make()(x))
        written = events.count(MISSES)
        del events[:]
        second = float(make()(x))
    finally:
        monitoring.unregister_event_listener(listen)
        jax.config.update("jax_persistent_cache_min_compile_time_secs", before)
    assert written == 1
    assert events.count(HITS) == 1 and events.count(MISSES) == 0
    assert second == first


def test_enable_makes_the_default_folder_or_switches_off(monkeypatch, tmp_path):
    """:func:`enable` (what the CLI calls before computing) with no setting makes the default
    folder under the home's cache and gives it to JAX; ``JAXGEAR_XLA_CACHE=off`` makes none and
    switches JAX's cache off. JAX's settings are put back after (the cache JAX opened first in
    this process is the one it keeps)."""
    import jax

    keys = ("jax_compilation_cache_dir", "jax_enable_compilation_cache",
            "jax_persistent_cache_min_compile_time_secs")  # fmt: skip
    saved = {k: jax.config.values[k] for k in keys}
    for name in ("JAXGEAR_XLA_CACHE", "JAX_COMPILATION_CACHE_DIR", "XDG_CACHE_HOME",
                 "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"):  # fmt: skip
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    try:
        jax.config.update("jax_compilation_cache_dir", None)
        folder = tmp_path / "home" / ".cache" / "jaxgear" / "xla"
        assert xc.enable() == folder and folder.is_dir()
        assert jax.config.values["jax_compilation_cache_dir"] == str(folder)
        assert jax.config.values["jax_persistent_cache_min_compile_time_secs"] == 0.0
        monkeypatch.setenv("JAXGEAR_XLA_CACHE", "off")
        monkeypatch.setenv("HOME", str(tmp_path / "home-off"))
        assert xc.enable() is None
        assert jax.config.values["jax_enable_compilation_cache"] is False
        assert not (tmp_path / "home-off").exists()
    finally:
        for k, v in saved.items():
            jax.config.update(k, v)


def test_import_compiles_nothing():
    """``import jaxgear`` (and the CLI, case reader and subpackages) compiles no program: one
    compiled at import precedes the CLI's switching the persistent cache on, so that every run
    compiled it again (a class-level default built with jnp at import did)."""
    code = (
        "import sys\n"
        "from jax import monitoring\n"
        "n = []\n"
        "monitoring.register_event_duration_secs_listener(\n"
        "    lambda name, secs, **kw: n.append(name)\n"
        "    if name == '/jax/core/compile/backend_compile_duration' else None)\n"
        "import jaxgear, jaxgear.cli, jaxgear.io, jaxgear.dynamics, jaxgear.planetary\n"
        "import jaxgear.gearbox, jaxgear.scenes, jaxgear.rating\n"
        "print(len(n))\n"
    )
    env = {k: v for k, v in os.environ.items() if not k.startswith("JAX_")}
    proc = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True,
                          check=False)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.split() == ["0"]


def test_planetary_checks_under_a_callers_jit():
    """load_sharing and campbell read their checks on the host for concrete inputs; under a
    caller's ``eqx.filter_jit`` (traced inputs) the same refusals come from ``eqx.error_if``, and the
    values are those of the concrete call (both balance the sun torque)."""
    import equinox as eqx
    import numpy as np
    from _planetary_stage import lin_parker_stage

    import jaxgear as jg
    import jaxgear.planetary as jp

    held = lin_parker_stage(3)  # ring and carrier held, the sun free to turn
    free = eqx.tree_at(lambda s: s.carrier.torsional_stiffness, held, 0.0)  # a mechanism
    model = jp.PlanarPlanetary()
    zeros = np.zeros(3)
    for f in (
        lambda t: jp.load_sharing(model, free, t, zeros).k_gamma,
        eqx.filter_jit(lambda t: jp.load_sharing(model, free, t, zeros).k_gamma),
    ):
        with pytest.raises(eqx.EquinoxRuntimeError, match="stiffness is singular"):
            f(100.0)
    # the carrier free with the planets' centripetal term: past divergence (at 1000 rad/s
    # beyond the check's 1e-9 of the held members' 1e13 N/m)
    for f in (
        lambda w: jp.campbell(model, free, w),
        eqx.filter_jit(lambda w: jp.campbell(model, free, w)),
    ):
        with pytest.raises(eqx.EquinoxRuntimeError, match="past divergence"):
            f(np.array([50.0, 1000.0]))
    errors = np.array([12e-6, 0.0, -5e-6])
    for r in (
        jp.load_sharing(model, held, 500.0, errors),
        eqx.filter_jit(lambda t, e: jp.load_sharing(model, held, t, e))(500.0, errors),
    ):
        # the sun's moment balance: its meshes' forces along their lines of action, on its
        # base radius, carry the sun torque; the pin errors share it unequally
        total = float(np.sum(r.sun_mesh_forces)) * float(held.sun.base_radius)
        assert total == pytest.approx(500.0, rel=1e-9)
        assert float(r.k_gamma) > 1.01
    # and the host-checked campbell of the held stage runs (its rest frequencies: the modes')
    rest = np.asarray(jp.campbell(model, held, np.array([0.0])))[0]
    np.testing.assert_allclose(
        rest, np.sort(np.asarray(jp.planetary_modes(model, held).frequencies)), rtol=1e-9
    )


def test_folder_option_and_default(monkeypatch, tmp_path):
    monkeypatch.setenv("JAXGEAR_XLA_CACHE", str(tmp_path / "mine"))
    assert xc.cache_folder() == tmp_path / "mine"
    for off in ("off", "OFF", "", "0", "none"):
        monkeypatch.setenv("JAXGEAR_XLA_CACHE", off)
        assert xc.cache_folder() is None
    # unset: JAX's own setting (here the test run's folder, conftest.py) is kept
    monkeypatch.delenv("JAXGEAR_XLA_CACHE")
    assert xc.cache_folder() == pathlib.Path(os.environ["JAX_COMPILATION_CACHE_DIR"])
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    assert xc.default_folder() == tmp_path / "xdg" / "jaxgear" / "xla"
    monkeypatch.delenv("XDG_CACHE_HOME")
    monkeypatch.setenv("HOME", str(tmp_path / "home"))
    assert xc.default_folder() == tmp_path / "home" / ".cache" / "jaxgear" / "xla"


def test_size_bound(monkeypatch, tmp_path):
    monkeypatch.delenv("JAXGEAR_XLA_CACHE_MAX_MB", raising=False)
    assert xc.max_bytes() == xc.DEFAULT_MAX_MB * 2**20
    monkeypatch.setenv("JAXGEAR_XLA_CACHE_MAX_MB", "0.5")
    assert xc.max_bytes() == 2**19
    for bad in ("0", "-1", "lots", "inf", "nan"):
        monkeypatch.setenv("JAXGEAR_XLA_CACHE_MAX_MB", bad)
        with pytest.raises(ValueError, match="JAXGEAR_XLA_CACHE_MAX_MB"):
            xc.max_bytes()
    # least recently used first, down to 3/4 of the bound; other files untouched
    for k in range(8):
        entry = tmp_path / f"k{k}-cache"
        entry.write_bytes(b"x" * 100)
        os.utime(entry, (1000 + k, 1000 + k))
    (tmp_path / ".lockfile").write_bytes(b"")
    assert xc.trim(tmp_path, 800) == 0
    assert xc.trim(tmp_path, 500) == 500  # 800 B over 500: down to 375 B, the 5 oldest go
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        ".lockfile",
        "k5-cache",
        "k6-cache",
        "k7-cache",
    ]


def test_bad_bound_is_an_input_error(monkeypatch, capsys):
    from jaxgear.cli import main

    monkeypatch.setenv("JAXGEAR_XLA_CACHE_MAX_MB", "lots")
    assert main(["modes", "accessory-spur", "--out", "never-made"]) == 2
    assert "JAXGEAR_XLA_CACHE_MAX_MB" in capsys.readouterr().err


def test_bench_cases_option(tmp_path, capsys):
    from jaxgear.cli import main

    out = str(tmp_path / "bench")
    assert main(["bench", "xla-cache", "--cases", "no-such-case", "--out", out]) == 2
    assert "unknown case 'no-such-case'" in capsys.readouterr().err
    assert main(["bench", "stiffness", "--cases", "accessory-spur", "--out", out]) == 2
    assert "--cases is an option of bench xla-cache" in capsys.readouterr().err


# default tier: tests/test_xla_cache.py::test_enable_makes_the_default_folder_or_switches_off (the same folders, in process) and ::test_bad_bound_is_an_input_error (the CLI calls it)
@pytest.mark.slow
def test_cli_default_folder_and_off(tmp_path):
    """With no setting, a CLI command that computes makes the default folder under the home's
    cache (here a temporary home, the case not found after); ``JAXGEAR_XLA_CACHE=off`` makes
    none."""
    env = {k: v for k, v in os.environ.items() if not k.startswith(("JAX_", "JAXGEAR_XLA"))}
    env.pop("XDG_CACHE_HOME", None)
    entry = "from jaxgear.cli import entry; entry()"
    for home, extra in (("home", {}), ("home-off", {"JAXGEAR_XLA_CACHE": "off"})):
        env_k = dict(env, HOME=str(tmp_path / home), **extra)
        proc = subprocess.run(
            [sys.executable, "-c", entry, "modes", str(tmp_path / "no-such.toml")],
            env=env_k,
            capture_output=True,
            text=True,
        )
        assert proc.returncode == 2 and "no-such.toml" in proc.stderr, proc.stderr[-2000:]
        made = (tmp_path / home / ".cache" / "jaxgear" / "xla").is_dir()
        assert made == (not extra)


def test_harris_map_refuses_bad_torques_in_one_line():
    """harris_map checks its torques on the host (its vmapped solve then holds no callback that
    the cache cannot store): a torque <= 0 or not finite is refused before any solve."""
    import jaxgear as jg
    import jaxgear.io as jio

    mesh = jio.load_case("power-helical").replace(slices=2).mesh_model()
    for bad in ([100.0, -5.0], [float("nan")], []):
        with pytest.raises(ValueError, match=r"^torques = .*allowed a non-empty 1-D array"):
            jg.harris_map(mesh, jg.Modifications(), bad, positions_per_pitch=8)


@pytest.mark.slow
def test_second_hybrid_sweep_reads_back_every_program_it_wrote(tmp_path, fem_prep_cache):
    """A hybrid sweep (tests/data/hybrid-test-case.toml: a condensed wheel, the hybrid Newmark
    at three speeds): its sweep program holds no Python callback (the quasi-static solve inside
    it runs without ``eqx.error_if`` once the torque, law and speeds were checked on the host),
    so the first run writes every program it compiles to the cache (77 at 817cc047) and the
    second reads all of them back and compiles none, with the same numbers."""
    case = str(pathlib.Path(__file__).parent / "data" / "hybrid-test-case.toml")
    command = ("sweep", "--speeds", "300:900:3", "--periods", "4", "--keep-periods", "2",
               "--steps-per-period", "16")
    cache = tmp_path / "xla"
    out1, first = _run(tmp_path, cache, "first", case, command)
    written = first.get(MISSES, 0)
    assert written > 0
    assert first.get(REQUESTS, 0) == written  # every program it compiled was written
    out2, second = _run(tmp_path, cache, "second", case, command)
    assert second.get(MISSES, 0) == 0
    assert second.get(REQUESTS, 0) == second.get(HITS, 0) == written
    sweeps = [json.loads((o / "sweep.json").read_text()) for o in (out1, out2)]
    for s in sweeps:
        s.pop("elapsed_s", None)
    assert sweeps[0] == sweeps[1]
