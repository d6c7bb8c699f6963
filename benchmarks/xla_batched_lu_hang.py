"""Standalone reproducer: an XLA CPU program holding a BATCHED LAPACK LU (``jnp.linalg.solve`` on
a stack) sometimes never returns on a small (2-core) host.

The program: an einsum of a few stacks (XLA's parallel CPU kernels) feeding TWO independent
batched complex solves (``jnp.linalg.solve`` on (m, k, k) stacks), the two results combined.
jaxlib's batched LU custom call (``lapack_zgetrf_ffi``) hands its members to XLA's CPU intra-op
thread pool and waits on a counter (``jax::ParallelBatchMap`` → ``BlockingCounter::Wait``); the
thunk executor may run that call itself on a thread of the same pool, and two such calls in
flight on a two-thread pool leave no thread for the members they wait for.

Each variant runs in a fresh subprocess that calls the compiled program ``--calls`` times on new
random inputs; the parent watches the child's CPU time (``/proc/<pid>/stat``) and its progress:
when no call completes and the CPU time gains under half a second for ``--stall`` seconds (60
by default) the child is counted hung (its threads' stacks written with gdb under ``--gdb``),
killed, and a new child continues with the calls left. Variants:

* ``batched``: ``jnp.linalg.solve`` on the stacks (one batched LAPACK call each);
* ``each``: one unbatched solve per member in a ``jax.lax.map`` (``jaxgear._util.each_solve``'s
  form, written out here so the script needs only jax);
* ``flag``: ``batched`` with ``XLA_FLAGS=--xla_cpu_multi_thread_eigen=false``.

From the repository root: ``python -m benchmarks.xla_batched_lu_hang [--calls 2000] [--m 32]
[--k 100] [--variants batched,each,flag] [--gdb /tmp/hang]``. Prints one line per variant
(calls, hangs, seconds) and the jax/jaxlib versions, and the same as JSON at the end.

Measured (jax and jaxlib 0.10.2, the 2-core host under load, default sizes): ``batched`` 7 hangs
in 450 calls, ``flag`` 4 in 287, ``each`` none in 450; each hung child's stacks (gdb): both
``tf_XLAEigen`` threads in ``lapack_zgetrf_ffi`` → ``ParallelBatchMap`` →
``BlockingCounter::Wait``, every other thread idle.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time

_CHILD = r"""
import sys, os
import jax
jax.config.update("jax_enable_x64", True)
import jax.numpy as jnp
import numpy as np

variant, progress = sys.argv[1], sys.argv[5]
calls, m, k = (int(a) for a in sys.argv[2:5])

def solve(A, b):
    if variant == "each":
        return jax.lax.map(lambda ab: jnp.linalg.solve(ab[0], ab[1]), (A, b))
    return jnp.linalg.solve(A, b)

@jax.jit
def program(P, Q, R, b):
    A1 = jnp.einsum("mij,mjk->mik", P, Q) + 1j * R + k * jnp.eye(k)
    A2 = jnp.einsum("mij,mkj->mik", Q, R) - 1j * P + k * jnp.eye(k)
    x1 = solve(A1, b)
    x2 = solve(A2, jnp.conj(b))
    return jnp.sum(jnp.abs(x1)) + jnp.sum(jnp.abs(x2))

rng = np.random.default_rng(os.getpid())
shape = (m, k, k)
for i in range(calls):
    P, Q, R = (rng.standard_normal(shape) for _ in range(3))
    b = rng.standard_normal((m, k, 1)) + 1j * rng.standard_normal((m, k, 1))
    float(program(P, Q, R, b))
    with open(progress, "w") as f:
        f.write(str(i + 1))
"""


def _cpu_ticks(pid: int) -> int:
    """utime + stime of every thread of ``pid`` (clock ticks), -1 once it is gone."""
    try:
        with open(f"/proc/{pid}/stat") as f:
            fields = f.read().rsplit(")", 1)[1].split()
        return int(fields[11]) + int(fields[12])
    except (OSError, IndexError, ValueError):
        return -1


def _backtrace(pid: int, path: str) -> None:
    """Every thread's stack of ``pid`` into ``path`` (gdb, where installed)."""
    try:
        with open(path, "w") as f:
            subprocess.run(["gdb", "-p", str(pid), "-batch", "-ex", "thread apply all bt"],
                           check=False, stdout=f, stderr=subprocess.STDOUT, timeout=120)
    except (OSError, subprocess.TimeoutExpired):
        pass


def run_variant(variant: str, calls: int, m: int, k: int, stall: float, gdb: str = "") -> dict:
    """``calls`` calls of the program in as many children as hangs need; returns the counts."""
    env = dict(os.environ)
    if variant == "flag":
        flags = env.get("XLA_FLAGS", "") + " --xla_cpu_multi_thread_eigen=false"
        env["XLA_FLAGS"] = flags.strip()
    progress = f"/tmp/xla_batched_lu_hang_{os.getpid()}_{variant}"
    done, hangs, children, failures = 0, 0, 0, 0
    t0 = time.time()
    while done < calls:
        with open(progress, "w") as f:
            f.write("0")
        child = subprocess.Popen(
            [sys.executable, "-c", _CHILD, "batched" if variant == "flag" else variant,
             str(calls - done), str(m), str(k), progress],
            env=env,
        )
        children += 1
        ref_ticks, ref_text, ref_time = -1, "", time.time()
        while child.poll() is None:
            time.sleep(1.0)
            ticks = _cpu_ticks(child.pid)
            with open(progress) as f:
                text = f.read()
            # a wedged child still gains a tick now and then (idle threads): progress is a new
            # call done or half a second of CPU since the last progress
            if text != ref_text or ticks - ref_ticks > 50 or ticks < 0:
                ref_ticks, ref_text, ref_time = ticks, text, time.time()
            elif time.time() - ref_time > stall:
                if gdb:
                    _backtrace(child.pid, f"{gdb}_{variant}_{hangs}.txt")
                child.kill()
                child.wait()
                hangs += 1
                break
        with open(progress) as f:
            text = f.read()
        done += int(text or 0)
        if child.returncode not in (0, -9):
            failures += 1
            if failures > 2:
                raise RuntimeError(f"variant {variant}: child failed with {child.returncode}")
    os.remove(progress)
    return {"variant": variant, "calls": done, "hangs": hangs, "children": children,
            "wall_s": round(time.time() - t0, 1)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--calls", type=int, default=2000)
    ap.add_argument("--m", type=int, default=32, help="members of each stack")
    ap.add_argument("--k", type=int, default=100, help="unknowns of each member")
    ap.add_argument("--stall", type=float, default=60.0, help="seconds without progress = hung")
    ap.add_argument("--variants", default="batched,each,flag")
    ap.add_argument("--gdb", default="", help="path prefix: each hung child's stacks (gdb)")
    args = ap.parse_args()
    import jax
    import jaxlib

    versions = {"jax": jax.__version__, "jaxlib": jaxlib.__version__, "cpus": os.cpu_count()}
    print(f"jax {versions['jax']}, jaxlib {versions['jaxlib']}, {versions['cpus']} CPUs; "
          f"{args.calls} calls of 2 solves of stacks ({args.m}, {args.k}, {args.k}) complex",
          flush=True)
    out = []
    for variant in args.variants.split(","):
        r = run_variant(variant, args.calls, args.m, args.k, args.stall, args.gdb)
        out.append(r)
        print(f"{variant:8s} calls {r['calls']:6d}  hangs {r['hangs']:3d}  "
              f"wall {r['wall_s']:8.1f} s", flush=True)
    print(json.dumps({"versions": versions, "m": args.m, "k": args.k, "results": out}))


if __name__ == "__main__":
    main()
