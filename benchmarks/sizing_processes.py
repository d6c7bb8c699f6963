"""Sizing candidates per second on one process and on two processes joined by
``jax.distributed`` on the loopback address (``jaxgear.sizing.size``: the chunks dealt to every
process's device, the results gathered on every process), one CPU device each, in one run.

Each measurement starts its own processes with the same environment (XLA's default flags, one
CPU device each): the first call of ``size`` (compile) and the best of ``REPEATS`` calls on
every candidate, timed on process 0; one and two processes are started alternately ``PAIRS``
times (the machine's load drifts), the best of each kept; the tables of the two are compared
bit for bit (the two-process table saved by process 0). Writes docs/bench/sizing_processes.json (or the file
given) with the machine (benchmarks/_timing.py's ``environment()``) and the load average. On
the 2-core machine the two processes share its two cores with each other (and any other load),
so the ratio is the gain of a second process there, not a cluster's scaling. From the
repository root: ``python -m benchmarks.sizing_processes [FILE]``.
"""

from __future__ import annotations

import dataclasses
import json
import os
import pathlib
import sys
import tempfile
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_processes.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
REPEATS = 3
PAIRS = 2
CHUNK = 2048


def _spec():
    import jaxgear.io as jio
    import jaxgear.sizing as js

    spec, _ = jio.load_sizing_spec(str(SPEC))
    # the spec's ranges widened to many candidates: modules 1-10 mm (both ISO 54 choices)
    return dataclasses.replace(spec, normal_modules=js.module_series(1e-3, 10e-3, "both"),
                               pinion_teeth=(14, 200), centre_distance=None,
                               outer_diameter_max=None)


def _worker(argv) -> None:
    """One process: joins jax.distributed (two processes), times ``size``; process 0 writes
    the times and the table."""
    pid, n, port, out = int(argv[0]), int(argv[1]), argv[2], pathlib.Path(argv[3])
    import jax

    jax.config.update("jax_enable_x64", True)
    if n > 1:
        jax.distributed.initialize(coordinator_address=f"127.0.0.1:{port}", num_processes=n,
                                   process_id=pid)
    import numpy as np

    import jaxgear.sizing as js

    spec = _spec()
    t = time.perf_counter()
    table = js.size(spec, chunk=CHUNK)
    first = time.perf_counter() - t
    runs = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        table = js.size(spec, chunk=CHUNK)
        runs.append(time.perf_counter() - t)
    if pid == 0:
        np.savez(out.with_suffix(".npz"), failed=table.failed, **table.columns)
        out.write_text(json.dumps({"first_call_s": first, "best_s": min(runs),
                                   "candidates": len(table), "processes": jax.process_count(),
                                   "devices": jax.device_count()}))


def _measure(processes: int, folder: pathlib.Path) -> dict:
    from benchmarks import free_port, run_processes

    port = free_port()
    out = folder / f"p{processes}.json"
    env = dict(os.environ, JAX_PLATFORMS="cpu", PYTHONPATH=str(ROOT))
    env.pop("XLA_FLAGS", None)
    argv = [sys.executable, "-m", "benchmarks.sizing_processes", "--worker"]
    run_processes([argv + [str(i), str(processes), str(port), str(out)]
                   for i in range(processes)], env=env, cwd=ROOT, timeout=3600)
    return json.loads(out.read_text())


def main(path: pathlib.Path = OUT) -> None:
    import jax
    import numpy as np

    from benchmarks._timing import environment

    jax.config.update("jax_enable_x64", True)  # the workers' dtype, recorded in the machine
    machine = environment()
    with tempfile.TemporaryDirectory() as tmp:
        folder = pathlib.Path(tmp)
        runs = {1: [], 2: []}
        for _ in range(PAIRS):  # one and two processes alternately: the load drifts
            for processes in (1, 2):
                runs[processes].append(_measure(processes, folder))
        a, b = np.load(folder / "p1.npz"), np.load(folder / "p2.npz")
        same = all(np.array_equal(a[k], b[k], equal_nan=True) for k in a.files)
    one, two = (dict(min(runs[p], key=lambda r: r["best_s"]),
                     best_s_of_each_start=[round(r["best_s"], 4) for r in runs[p]])
                for p in (1, 2))
    rate = {k: r["candidates"] / r["best_s"] for k, r in (("one", one), ("two", two))}
    record = {
        "what": "sizing candidates per second, jaxgear.sizing.size on one process and on two "
                "processes joined by jax.distributed on 127.0.0.1 (one CPU device each), one run",
        "machine": machine,
        "spec": "examples/sizing/helical.toml with modules 1-10 mm (both ISO 54 choices), "
                "z1 14-200, no centre-distance window or outer-diameter limit",
        "chunk": CHUNK,
        "one_process": {**one, "candidates_per_s": round(rate["one"], 1)},
        "two_processes": {**two, "candidates_per_s": round(rate["two"], 1)},
        "speed_ratio_two_over_one": round(rate["two"] / rate["one"], 3),
        "tables_bitwise_equal": bool(same),
        "note": "the two processes share this machine's cores with each other and with any "
                "other load: the ratio is a second process's gain on this machine, not a "
                "cluster's scaling",
        "load_average_at_end": list(os.getloadavg()),
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    print(json.dumps(record, indent=2))


if __name__ == "__main__":
    if sys.argv[1:2] == ["--worker"]:
        _worker(sys.argv[2:])
    else:
        main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
