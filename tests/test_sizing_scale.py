"""A sizing at scale (jaxgear.sizing.size's devices, processes and results store; jaxgear size's
--chunk, store/ and jax.distributed options): a run interrupted after its first chunk and
resumed from the store gives the uninterrupted run's table bit for bit, with its progress
counting the stored candidates; a store of another spec or chunk size refused in one line
before work (started afresh with restart / --force); the chunks dealt to several devices
equal the one-device run bit for bit. The slow tier runs the same claims where they need
their own processes: two forced CPU devices, two processes joined by jax.distributed on the
loopback address, and a SIGTERM in the middle of a run. Every test here shares one compiled
program (the small spec's static values, 80 candidates a chunk: 145 candidates, 2 chunks)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import jax
import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.sizing as js
from benchmarks import free_port, run_processes
from jaxgear.cli import main
from test_sizing import SPEC, _spec, _toml

ROOT = Path(__file__).resolve().parents[1]
CHUNK = 80  # two chunks of the small spec's 145 candidates


class Interrupted(Exception):
    """Raised by a progress callback: the run stopped between two chunks."""


def _equal(a: js.SizingTable, b: js.SizingTable) -> bool:
    """The same table bit for bit (NaN where NaN)."""
    return (list(a.columns) == list(b.columns) and np.array_equal(a.failed, b.failed)
            and all(np.array_equal(a.columns[k], b.columns[k], equal_nan=True)
                    and a.columns[k].dtype == b.columns[k].dtype for k in a.columns))


@pytest.fixture(scope="module")
def small():
    spec, _ = jio.parse_sizing_spec(_spec())
    return spec, js.size(spec, chunk=CHUNK)  # the uninterrupted run, no store


def test_a_run_stopped_after_its_first_chunk_resumes_to_the_same_table(small, tmp_path):
    spec, whole = small
    n = len(whole)
    assert n == 145  # two chunks: 80 and 65 candidates
    store = tmp_path / "store"
    seen = []

    def stop_after_first(done, total):
        seen.append((done, total))
        raise Interrupted

    with pytest.raises(Interrupted):
        js.size(spec, chunk=CHUNK, store=store, progress=stop_after_first)
    assert seen == [(CHUNK, n)]
    assert sorted(os.listdir(store)) == ["chunk_000000.npz"]  # complete files only
    with np.load(store / "chunk_000000.npz") as z:  # the first 80 rows, as the table's
        assert (int(z["start"]), int(z["stop"])) == (0, CHUNK)
        rated = np.isfinite(whole.columns["S_F1"][:CHUNK])  # the table's NaN: no geometry
        assert 0 < rated.sum() < CHUNK
        np.testing.assert_array_equal(z["outputs"][rated, js.OUTPUTS.index("S_F1")],
                                      whole.columns["S_F1"][:CHUNK][rated])
    seen.clear()
    resumed = js.size(spec, chunk=CHUNK, store=store, progress=lambda d, t: seen.append((d, t)))
    assert seen == [(CHUNK, n), (n, n)]  # the stored chunk counted first, then the other
    assert _equal(resumed, whole)
    assert sorted(os.listdir(store)) == ["chunk_000000.npz", "chunk_000001.npz"]
    # everything stored: nothing rated, the same table again
    seen.clear()
    assert _equal(js.size(spec, chunk=CHUNK, store=store, progress=lambda d, t: seen.append(d)),
                  whole)
    assert seen == [n]


def test_a_store_of_another_sizing_is_refused_in_one_line_or_restarted(small, tmp_path):
    spec, whole = small
    store = tmp_path / "store"
    js.size(spec, chunk=CHUNK, store=store)
    other, _ = jio.parse_sizing_spec(_spec() | {"operating": {"torque_Nm": 130.0,
                                                              "speed_rpm": 1500.0}})
    for s, chunk in ((other, CHUNK), (spec, CHUNK + 1)):  # another load; another chunk size
        rated = []
        with pytest.raises(ValueError) as err:
            js.size(s, chunk=chunk, store=store, progress=lambda d, t: rated.append(d))
        text = str(err.value)
        assert text.startswith(f"store {store}: chunk_000000.npz is another sizing's (its spec, "
                               "chunk size or jaxgear version differ)") and "\n" not in text
        assert rated == []  # refused before any chunk
    fresh = js.size(other, chunk=CHUNK, store=store, restart=True)
    assert _equal(js.size(other, chunk=CHUNK), fresh)  # started afresh: the other spec's table
    assert not np.array_equal(fresh.columns["S_H1"], whole.columns["S_H1"], equal_nan=True)
    # the store's rows are the new spec's: ISO 6336-2's σ_H ∝ √(F_t K_v K_Hβ K_Hα), the load
    # factors falling as the load grows, so S_H(120 N·m)/S_H(130 N·m) lies in (1, √(130/120)]
    ok = np.isfinite(fresh.columns["S_H1"])
    ratio = whole.columns["S_H1"][ok] / fresh.columns["S_H1"][ok]
    assert ok.sum() > 10 and np.all(ratio > 1) and np.all(ratio <= np.sqrt(130 / 120))


def test_chunks_dealt_to_several_devices_equal_the_one_device_run(small):
    """Three devices (this process's one device named three times: the rounds of three chunks,
    the last round's spare device repeating its last chunk) give the one-device table."""
    spec, whole = small
    d = jax.local_devices()[0]
    assert _equal(js.size(spec, chunk=CHUNK, devices=[d, d, d]), whole)
    with pytest.raises(ValueError, match=r"^devices = \[\]: none of this process's"):
        js.size(spec, chunk=CHUNK, devices=[])


def _csv(folder) -> bytes:
    return (Path(folder) / "sizing.csv").read_bytes()


@pytest.mark.usefixtures("no_figures")
def test_jaxgear_size_resumes_from_its_store_and_refuses_another_spec(small, tmp_path, capsys):
    spec, whole = small
    path, other = tmp_path / "small.toml", tmp_path / "other.toml"
    path.write_text(_toml(SPEC))
    data = _spec()
    data["operating"]["torque_Nm"] = 130.0
    other.write_text(_toml(data))
    out = tmp_path / "out"
    # without the TE stage (its own claims: tests/test_sizing_te.py), the store's claims alone
    args = ["--out", str(out), "--chunk", str(CHUNK), "--quiet", "--te", "0"]
    assert main(["size", str(path), *args]) == 0
    first = _csv(out)
    assert sorted(os.listdir(out / "store")) == ["chunk_000000.npz", "chunk_000001.npz"]
    (out / "store" / "chunk_000001.npz").unlink()  # as if stopped after the first chunk
    assert main(["size", str(path), *args]) == 0
    assert _csv(out) == first  # byte for byte: every number at full precision
    s_h1 = [r.split(",")[list(whole.columns).index("S_H1") + 1]
            for r in first.decode().splitlines()[1:]]
    np.testing.assert_array_equal(np.array([float(v) if v else np.nan for v in s_h1]),
                                  whole.columns["S_H1"])
    assert main(["size", str(other), *args]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and f"store {out / 'store'}: chunk_000000.npz is another sizing's" in err[0]
    assert _csv(out) == first  # nothing replaced
    assert main(["size", str(other), *args, "--force"]) == 0
    assert _csv(out) != first
    for bad, message in ((["--chunk", "0"], "--chunk 0: out of range, allowed >= 1"),
                         (["--num-processes", "2"], "--coordinator-address, --num-processes "
                          "and --process-id go together")):
        assert main(["size", str(path), "--out", str(tmp_path / "o3"), *bad]) == 2
        assert message in capsys.readouterr().err
    assert not (tmp_path / "o3").exists()


# -- own processes (slow tier) -------------------------------------------------------------------


def _env(devices: int = 1) -> dict:
    """This test run's environment (its XLA flags: the same compiled code) with ``devices``
    forced CPU devices, importing this source tree."""
    flags = os.environ.get("XLA_FLAGS", "")
    if devices > 1:
        flags += f" --xla_force_host_platform_device_count={devices}"
    return dict(os.environ, XLA_FLAGS=flags.strip(), JAX_PLATFORMS="cpu",
                PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")]))


def _spec_file(tmp_path) -> Path:
    path = tmp_path / "small.toml"
    path.write_text(_toml(SPEC))
    return path


# default tier: test_chunks_dealt_to_several_devices_equal_the_one_device_run (the rounds over
# several devices in this process)
@pytest.mark.slow
def test_two_forced_cpu_devices_give_the_one_device_table(tmp_path):
    path = _spec_file(tmp_path)
    assert main(["size", str(path), "--out", str(tmp_path / "one"), "--chunk", "40",
                 "--quiet"]) == 0
    worker = [sys.executable, str(ROOT / "tests" / "_sizing_worker.py")]
    run_processes([worker + [str(path), str(tmp_path / "two"), "40"]], env=_env(2), cwd=ROOT,
                  timeout=600)
    import json

    summary = json.loads((tmp_path / "two" / "sizing.json").read_text(encoding="utf-8"))
    assert summary["devices"] == 2 and summary["processes"] == 1
    assert _csv(tmp_path / "two") == _csv(tmp_path / "one")


# default tier: test_chunks_dealt_to_several_devices_equal_the_one_device_run (the same rounds
# in one process)
@pytest.mark.slow
def test_two_processes_on_loopback_give_the_one_process_table(tmp_path):
    """Two processes joined by jax.distributed on 127.0.0.1, one CPU device each, four chunks
    of 40: process 0's sizing.csv equals this process's one-process run byte for byte."""
    path = _spec_file(tmp_path)
    assert main(["size", str(path), "--out", str(tmp_path / "one"), "--chunk", "40",
                 "--quiet"]) == 0
    port = free_port()
    worker = [sys.executable, str(ROOT / "tests" / "_sizing_worker.py"), str(path),
              str(tmp_path / "two"), "40"]
    run_processes([worker + [str(i), "2", str(port)] for i in range(2)], env=_env(),
                  cwd=ROOT, timeout=600)
    import json

    summary = json.loads((tmp_path / "two" / "sizing.json").read_text(encoding="utf-8"))
    assert summary["processes"] == 2 and summary["devices"] == 2
    assert _csv(tmp_path / "two") == _csv(tmp_path / "one")
    assert len(os.listdir(tmp_path / "two" / "store")) == 4  # process 0 stored every chunk


# default tier: test_a_run_stopped_after_its_first_chunk_resumes_to_the_same_table (a run
# stopped between chunks, resumed)
@pytest.mark.slow
def test_sigterm_leaves_complete_chunks_that_a_rerun_resumes(tmp_path):
    """jaxgear size of the small spec with modules 1-10 mm (both ISO 54 choices) and z1 12-40,
    chunks of 8 (hundreds of chunk files), sent SIGTERM once its first chunks are stored: exit
    status 143, only complete chunk files of the spec in the store (no temporary file); the
    rerun rates the rest, and its table equals an uninterrupted run's byte for byte."""
    data = _spec(normal_module_min_mm=1.0, normal_module_max_mm=10.0, z1_max=40,
                 outer_diameter_max_mm=2000.0)
    path = tmp_path / "wide.toml"
    path.write_text(_toml(data))
    out = tmp_path / "out"
    worker = [sys.executable, str(ROOT / "tests" / "_sizing_worker.py"), str(path), str(out), "8"]
    proc = subprocess.Popen(worker, cwd=ROOT, env=_env(), stdout=subprocess.DEVNULL,
                            stderr=subprocess.PIPE, text=True)
    try:
        t0 = time.time()
        while time.time() - t0 < 300 and proc.poll() is None:
            if (out / "store").is_dir() and len(os.listdir(out / "store")) >= 3:
                break
            time.sleep(0.02)
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    assert proc.returncode == 143, err
    spec, _ = jio.parse_sizing_spec(data)
    n = len(js.enumerate_candidates(spec))
    names = sorted(os.listdir(out / "store"))
    assert names and all(name.startswith("chunk_") and name.endswith(".npz") for name in names)
    assert len(names) < -(-n // 8)  # stopped before the end
    assert not (out / "sizing.csv").exists()
    for name in names:  # each complete: its rows, of this spec's digest (all the same)
        with np.load(out / "store" / name) as z:
            k = int(name[6:12])
            assert (int(z["start"]), int(z["stop"])) == (8 * k, min(8 * k + 8, n))
            assert z["outputs"].shape == (int(z["stop"]) - int(z["start"]), len(js.OUTPUTS))
    assert main(["size", str(path), "--out", str(out), "--chunk", "8", "--quiet"]) == 0
    assert main(["size", str(path), "--out", str(tmp_path / "whole"), "--chunk", "8",
                 "--quiet"]) == 0
    assert _csv(out) == _csv(tmp_path / "whole")
