"""The per-curve public call under JAX's two CPU dispatch modes, paired in interleaved blocks.

Part of ``jaxgear bench quasi-static`` (the ``per_curve_blocks`` key of its JSON). JAX's CPU
client is created once per process, asynchronous (the default: a program runs on the runtime's
own threads, the caller waits for them) or synchronous (``jax_cpu_enable_async_dispatch =
False``, set with ``jax.config.update`` before the backend starts; JAX 0.10 reads no environment
variable for it). One process cannot hold both, so :func:`paired_dispatch_modes` starts one
worker process of each mode (this module's :func:`worker`) and alternates blocks between them
(A B B A A B …). Each block, in each worker, times in turn:

* ``public_free_tip``: ``compile_quasi_static(..., output=TE).with_free(tip relief depth and
  extent)`` called as ``f(x, torque)`` (``x`` a JAX array, ``torque`` a float) and blocked on;
* ``public_whole_result``: every modification leaf a design variable, the whole result;
* ``compute_free_tip``: 16 tip-relief designs in one jitted ``lax.map``, per curve (the
  program's work without the per-call cost);
* ``dispatch_identity``: a jitted identity of the same ``(x, torque)`` (dispatch alone);
* ``public_quasi_static`` and ``batched_256_torques`` (per curve: 256 torques in one jitted
  ``lax.map`` in chunks of 8): what the dispatch mode does to the rest of the work;
* ``baseline``: the NumPy/brentq curve (:mod:`benchmarks._baseline`), with the case's contact
  model (contact beyond the theoretical path where the case has it: like with like);
* ``public_free_tip_theoretical_path`` and ``baseline_theoretical_path`` (a case with contact
  beyond the path only): the same call and baseline, both on the theoretical path;
* ``closure_<option>``: a ``jax.jit`` of the free-tip curve compiled with per-program XLA
  options (``compiler_options``), the per-program alternatives to the dispatch mode.

A block's figure for a candidate is the median of its calls' wall times in that block (a
preempted call does not move it); the record is the median and the inter-quartile range of
those over the blocks, and of the ratios formed within each block (baseline over public call,
public call over compute), so that one record says how reliable a ratio is. Timings are
measured, never asserted.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

__all__ = ["paired_dispatch_modes", "worker"]

MODES = ("async", "sync")
# per-program XLA:CPU options of this jaxlib tried on the free-tip program (name: options); an
# option the compiler refuses is recorded with its error
OPTIONS = {
    "default": {},
    "no_ynn_fusions": {"xla_cpu_experimental_ynn_fusion_type": ""},
    "single_thread_eigen": {"xla_cpu_multi_thread_eigen": False},
    "no_concurrency_scheduler": {"xla_cpu_enable_concurrency_optimized_scheduler": False},
    "small_while_loop_kernels": {
        "xla_backend_extra_options": "xla_cpu_small_while_loop_byte_threshold=1000000000"
    },
}
# designs per compute-only call: short calls (about 0.7 ms), rarely preempted under load; the
# dispatch spread over them is about 1 % of a curve
_DESIGNS = 16
_ROOT = Path(__file__).resolve().parents[1]  # the checkout: benchmarks/ and jaxgear/ in it


def _bootstrap(mode: str) -> str:
    """The ``python -c`` program of a worker: the dispatch mode set before anything starts JAX's
    backend (importing jaxgear may), then :func:`worker`."""
    sync = mode == "sync"
    return (
        "import jax\n"
        'jax.config.update("jax_enable_x64", True)\n'
        f'jax.config.update("jax_cpu_enable_async_dispatch", {not sync})\n'
        "from benchmarks._curve_dispatch import worker\n"
        "worker()\n"
    )


def _reps(quick: bool) -> dict:
    """Calls per block of each candidate (name: calls)."""
    if quick:
        return {
            "public": 60,
            "whole": 30,
            "compute": 2,
            "identity": 60,
            "baseline": 1,
            "opt": 30,
            "plain": 10,
            "many": 5,
        }
    return {
        "public": 300,
        "whole": 100,
        "compute": 5,
        "identity": 300,
        "baseline": 3,
        "opt": 100,
        "plain": 30,
        "many": 20,
    }


def _setup(case: str, quick: bool) -> tuple[dict, dict]:
    """The worker's candidates (name: (call, calls per block, curves per call)) and what it
    records once (options refused, their results' agreement, the call's anatomy)."""
    import jax
    import jax.numpy as jnp

    from jaxgear import TheoreticalPath, compile_quasi_static, quasi_static
    from jaxgear.io import load_case

    from . import _baseline as bl

    c = load_case(case)
    mesh, mods, torque, P = c.mesh_model(), c.modifications, float(c.torque), c.positions_per_pitch
    free = lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)
    tip = compile_quasi_static(
        mesh, mods, positions_per_pitch=P, output=lambda r: r.transmission_error
    ).with_free(free)
    whole = compile_quasi_static(mesh, mods, positions_per_pitch=P)
    x, x0 = tip.design0, whole.design0
    t = jnp.asarray(torque)
    xs = x[None, :] * jnp.linspace(0.9, 1.1, _DESIGNS)[:, None]

    def curve(x, t):
        return quasi_static(mesh, tip.modifications(x), t, positions_per_pitch=P).transmission_error

    many = jax.jit(
        lambda xs: jax.lax.map(
            lambda x: quasi_static(mesh, tip.modifications(x), t, positions_per_pitch=P).te_rms, xs
        )
    )
    ident = jax.jit(lambda x, t: (x, t))
    # what the setting does to other work: the plain quasi_static call and a batched map
    ts = jnp.linspace(0.5, 1.5, 256) * torque
    batched = jax.jit(
        lambda ts: jax.lax.map(
            lambda t: quasi_static(mesh, mods, t, positions_per_pitch=P).te_rms, ts, batch_size=8
        )
    )
    bmesh, bmods = bl.baseline_mesh(c), bl.mods_params(mods)  # the case's contact model
    reps = _reps(quick)
    block = jax.block_until_ready
    calls = {
        "public_free_tip": (lambda: tip(x, torque), reps["public"], 1),
        "public_whole_result": (lambda: whole(x0, torque), reps["whole"], 1),
        "compute_free_tip": (lambda: many(xs), reps["many"], _DESIGNS),
        "dispatch_identity": (lambda: ident(x, torque), reps["identity"], 1),
        "public_quasi_static": (
            lambda: quasi_static(mesh, mods, torque, positions_per_pitch=P),
            reps["plain"],
            1,
        ),
        "batched_256_torques": (lambda: batched(ts), reps["compute"], 256),
        "baseline": (
            lambda: bl.te_curve_numpy(bmesh, bmods, torque, "exact", c.smooth_width, P),
            reps["baseline"],
            1,
        ),
    }
    if mesh.contact_geometry.reaches_beyond_path:  # the other contact model, like with like
        tip_th = compile_quasi_static(
            mesh.with_contact_geometry(TheoreticalPath()),
            mods,
            positions_per_pitch=P,
            output=lambda r: r.transmission_error,
        ).with_free(free)
        bmesh_th = bl.baseline_mesh(c, extended_contact=False)
        calls["public_free_tip_theoretical_path"] = (
            lambda: tip_th(x, torque), reps["public"], 1
        )
        calls["baseline_theoretical_path"] = (
            lambda: bl.te_curve_numpy(bmesh_th, bmods, torque, "exact", c.smooth_width, P),
            reps["baseline"],
            1,
        )
    ref = np.asarray(quasi_static(mesh, mods, torque, positions_per_pitch=P).transmission_error)
    once: dict = {"options": {}}
    for name, options in OPTIONS.items():
        try:
            prog = jax.jit(curve, compiler_options=options)
            te = np.asarray(prog(x, torque))
        except Exception as err:  # noqa: BLE001 -- an option this jaxlib refuses: recorded
            once["options"][name] = {"compiler_options": options, "refused": str(err)[:300]}
            continue
        once["options"][name] = {
            "compiler_options": options,
            "max_rel_diff_te_to_quasi_static": float(
                np.max(np.abs(te - ref)) / np.max(np.abs(ref))
            ),
        }
        calls[f"closure_{name}"] = (lambda prog=prog: prog(x, torque), reps["opt"], 1)
    diff = float(np.max(np.abs(np.asarray(tip(x, torque)) - ref)) / np.max(np.abs(ref)))
    once["public_free_tip_max_rel_diff_te_to_quasi_static"] = diff
    for fn, _, _ in calls.values():
        block(fn())
    once["anatomy"] = _anatomy(lambda: block(tip(x, torque)))
    return calls, once


def _anatomy(call, n: int = 20) -> dict:
    """What one public call does, from a ``jax.profiler`` trace of ``n`` calls: per call, the
    program executions (dispatches), host-to-device puts, buffer awaits and NumPy reads of a
    device array (device-to-host), and the thread the program's thunks ran on (the calling
    thread: synchronous; a runtime thread: a hand-off each way)."""
    import jax

    with tempfile.TemporaryDirectory() as folder:
        try:
            jax.profiler.start_trace(folder)
            for _ in range(n):
                with jax.profiler.TraceAnnotation("curve_call"):
                    call()
            jax.profiler.stop_trace()
            path = next(Path(folder).rglob("*.xplane.pb"))
            data = jax.profiler.ProfileData.from_file(str(path))
        except Exception as err:  # noqa: BLE001 -- no profiler in this jaxlib: say so
            return {"error": str(err)[:300]}
        events = [
            (e.start_ns, e.start_ns + e.duration_ns, line.name, e.name)
            for plane in data.planes
            for line in plane.lines
            for e in line.events
        ]
    windows = [(a, b) for a, b, _, name in events if name == "curve_call"]
    inside = [e for e in events if any(a <= e[0] <= b for a, b in windows)]

    def per_call(pred) -> float:
        return sum(1 for e in inside if pred(e[3])) / max(len(windows), 1)

    main = {line for _, _, line, name in events if name == "curve_call"}
    runs = [line for _, _, line, name in inside if name == "ThunkExecutor::Execute"]
    return {
        "calls_traced": len(windows),
        "program_executions_per_call": per_call(lambda s: "ExecuteHelper" in s),
        "host_to_device_puts_per_call": per_call(lambda s: s == "DevicePut"),
        "buffer_awaits_per_call": per_call(lambda s: s.endswith("Buffer::Await")),
        "numpy_reads_per_call": per_call(lambda s: s == "$numpy asarray"),
        "program_ran_on": "calling thread"
        if runs and all(r in main for r in runs)
        else "runtime threads",
        "how": "jax.profiler trace of 20 calls f(x, torque) + block_until_ready, events counted "
        "inside each call's TraceAnnotation",
    }


def _block(calls: dict) -> dict:
    """One block: each candidate's calls in turn; per candidate the median and the minimum of its
    calls' wall times per curve (s) and its CPU time per curve (``time.process_time``, every
    thread of the process) over the block."""
    import jax

    out: dict = {"median": {}, "min": {}, "cpu": {}}
    for name, (fn, n, curves) in calls.items():
        times = []
        c0 = time.process_time()
        for _ in range(n):
            t0 = time.perf_counter()
            jax.block_until_ready(fn())
            times.append((time.perf_counter() - t0) / curves)
        out["cpu"][name] = (time.process_time() - c0) / (n * curves)
        out["median"][name] = float(np.median(times))
        out["min"][name] = float(np.min(times))
    return out


def worker() -> None:
    """A worker process: reads ``[case, quick]`` (JSON) from its first line of stdin, answers ``ready``
    with what it records once, then one JSON line per ``block`` line, until ``quit``."""
    case, quick = json.loads(sys.stdin.readline())
    calls, once = _setup(case, bool(quick))
    print(json.dumps({"ready": once}), flush=True)
    for line in sys.stdin:
        if line.strip() != "block":
            break
        print(json.dumps(_block(calls)), flush=True)


def _stats(values) -> dict:
    """Median and inter-quartile range of per-block values, and the values."""
    v = np.asarray(values, dtype=float)
    q1, med, q3 = np.percentile(v, [25, 50, 75])
    return {"median": float(med), "q1": float(q1), "q3": float(q3), "per_block": v.tolist()}


class _Worker:
    """A worker process of one dispatch mode (stderr to a file: no pipe to fill)."""

    def __init__(self, mode: str, case: str, quick: bool):
        env = dict(os.environ)
        env["PYTHONPATH"] = os.pathsep.join(filter(None, [str(_ROOT), env.get("PYTHONPATH")]))
        self.mode = mode
        self.err = tempfile.TemporaryFile(mode="w+")  # noqa: SIM115 -- closed in close()
        self.proc = subprocess.Popen(
            [sys.executable, "-c", _bootstrap(mode)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            stderr=self.err,
            text=True,
            cwd=_ROOT,
            env=env,
        )
        if os.path.exists(case):  # a case file: its path from the worker's folder
            case = os.path.abspath(case)
        self.send(json.dumps([case, bool(quick)]))

    def send(self, line: str) -> None:
        self.proc.stdin.write(line + "\n")
        self.proc.stdin.flush()

    def read(self) -> dict:
        line = self.proc.stdout.readline()
        while line and not line.startswith("{"):  # anything else a library printed
            line = self.proc.stdout.readline()
        if not line:
            self.proc.wait()
            self.err.seek(0)
            tail = self.err.read()[-2000:]
            raise RuntimeError(f"bench worker ({self.mode} dispatch) stopped:\n{tail}")
        return json.loads(line)

    def close(self) -> None:
        if self.proc.poll() is None:
            try:
                self.send("quit")
                self.proc.wait(timeout=60)
            except (OSError, subprocess.TimeoutExpired):
                self.proc.kill()
                self.proc.wait()
        for stream in (self.proc.stdin, self.proc.stdout, self.err):
            try:
                stream.close()
            except OSError:  # a broken pipe of a stopped worker: nothing left to flush
                pass


def paired_dispatch_modes(case: str = "accessory-spur", quick: bool = False) -> dict:
    """Blocks of the per-curve candidates in an asynchronous- and a synchronous-dispatch worker,
    alternated (A B B A …), summarised as median and inter-quartile range over the blocks of
    each candidate's time per curve and of the ratios formed within a block (see the module
    docstring). Returns the JSON-ready record."""
    blocks = 5 if quick else 9
    workers = {m: _Worker(m, case, quick) for m in MODES}
    try:
        once = {m: w.read()["ready"] for m, w in workers.items()}
        rows: dict = {m: [] for m in MODES}
        loads = []
        for b in range(blocks):
            order = MODES if b % 2 == 0 else MODES[::-1]
            for m in order:
                workers[m].send("block")
                rows[m].append(workers[m].read())
            loads.append(os.getloadavg()[0] if hasattr(os, "getloadavg") else None)
    finally:
        for w in workers.values():
            w.close()
    out: dict = {
        "how": "two worker processes, JAX's CPU client asynchronous (default) and synchronous "
        "(jax.config.update('jax_cpu_enable_async_dispatch', False) before the backend starts), "
        f"{blocks} blocks alternated between them (A B B A ...); in each block every candidate "
        "runs its calls in turn (public free tip "
        f"{_reps(quick)['public']} calls, compute-only {_reps(quick)['many']} lax.map calls "
        f"of {_DESIGNS} designs, baseline {_reps(quick)['baseline']} curves, ...); a block's figure is "
        "the median wall time per curve of its calls (seconds_per_curve; also their minimum, "
        "seconds_per_curve_block_min, and the CPU time per curve); median and inter-quartile "
        "range (q1, q3) over the blocks, ratios formed within each block (from the block "
        "medians; _from_block_minima: from the block minima; _cpu: of the CPU times, the "
        "least load-sensitive under other jobs' load, where a 5 ms baseline curve is preempted "
        "far more often than a 0.07 ms call)",
        "blocks": blocks,
        "load_average_1min_per_block": loads,
        "modes": {},
    }
    for m in MODES:
        rec: dict = {}
        for stat, key in (
            ("median", "seconds_per_curve"),
            ("min", "seconds_per_curve_block_min"),
            ("cpu", "cpu_seconds_per_curve"),
        ):
            per = {k: np.asarray([r[stat][k] for r in rows[m]]) for k in rows[m][0][stat]}
            rec[key] = {k: _stats(v) for k, v in per.items()}
            if stat == "cpu":
                continue
            tail = "" if stat == "median" else "_from_block_minima"
            public, base = per["public_free_tip"], per["baseline"]
            rec[f"ratio_baseline_over_public_free_tip{tail}"] = _stats(base / public)
            rec[f"public_free_tip_over_compute{tail}"] = _stats(public / per["compute_free_tip"])
            rec[f"ratio_baseline_over_public_whole_result{tail}"] = _stats(
                base / per["public_whole_result"]
            )
            if "baseline_theoretical_path" in per:  # the theoretical path in both codes
                rec[f"ratio_baseline_over_public_free_tip_theoretical_path{tail}"] = _stats(
                    per["baseline_theoretical_path"] / per["public_free_tip_theoretical_path"]
                )
        cpu = {k: np.asarray([r["cpu"][k] for r in rows[m]]) for k in rows[m][0]["cpu"]}
        rec["ratio_baseline_over_public_free_tip_cpu"] = _stats(
            cpu["baseline"] / cpu["public_free_tip"]
        )
        if "baseline_theoretical_path" in cpu:
            rec["ratio_baseline_over_public_free_tip_theoretical_path_cpu"] = _stats(
                cpu["baseline_theoretical_path"] / cpu["public_free_tip_theoretical_path"]
            )
        ratio = np.asarray(rec["ratio_baseline_over_public_free_tip"]["per_block"])
        over = np.asarray(rec["public_free_tip_over_compute"]["per_block"])
        rec["blocks_meeting_50x"] = int(np.sum(ratio >= 50.0))
        rec["blocks_within_2x_compute"] = int(np.sum(over <= 2.0))
        out["modes"][m] = {**rec, **once[m]}
    a, s = (
        np.asarray(out["modes"][m]["seconds_per_curve"]["public_free_tip"]["per_block"])
        for m in MODES
    )
    out["sync_over_async_public_free_tip"] = _stats(s / a)
    return out
