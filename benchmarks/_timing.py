"""One timing helper and one environment record for every ``jaxgear bench`` benchmark.

Timing rule of every benchmark: one warm-up call (compile), then the minimum wall time over
repeats, each call ended by ``jax.block_until_ready`` on its whole result.
"""

from __future__ import annotations

import json
import math
import os
import pathlib
import platform
import time

__all__ = ["cpu_model", "environment", "first_call", "min_time"]


def _block(result):
    import jax

    return jax.block_until_ready(result)


def min_time(fn, repeats: int = 5, block=None, warmup: bool = True) -> float:
    """Min wall time (s) of ``fn()`` over ``repeats`` calls, after one warm-up call (unless
    ``warmup`` is False); ``block`` (default ``jax.block_until_ready``) waits for the result."""
    block = block or _block
    if warmup:
        block(fn())
    best = math.inf
    for _ in range(max(1, int(repeats))):
        t = time.perf_counter()
        block(fn())
        best = min(best, time.perf_counter() - t)
    return best


def first_call(fn, block=None) -> float:
    """Wall time (s) of one call of ``fn()`` (the compiling one when caches are cold)."""
    block = block or _block
    t = time.perf_counter()
    block(fn())
    return time.perf_counter() - t


def cpu_model() -> str:
    """The CPU's model name (``/proc/cpuinfo``), else what ``platform`` knows."""
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def environment() -> dict:
    """Where the figures come from: device, CPU, dtype, versions, load at the start."""
    import jax
    import jax.numpy as jnp
    import numpy as np

    dev = jax.devices()[0]
    return {
        "device": str(dev),
        "platform": dev.platform,
        "device_kind": getattr(dev, "device_kind", ""),
        "cpu_model": cpu_model(),
        "cpu_count": os.cpu_count(),
        "cpu_affinity": len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else None,
        "load_average_at_start": list(os.getloadavg()) if hasattr(os, "getloadavg") else None,
        "dtype": str(jnp.result_type(float)),
        "jax": jax.__version__,
        "numpy": np.__version__,
        "python": platform.python_version(),
        "machine": platform.machine(),
    }


class CompileCounter:
    """XLA backend compilations in this process and their seconds, counted from JAX's monitoring
    events (``/jax/core/compile/backend_compile_duration``) since the counter was made."""

    EVENT = "/jax/core/compile/backend_compile_duration"

    def __init__(self):
        from jax import monitoring

        self.count, self.seconds = 0, 0.0
        monitoring.register_event_duration_secs_listener(self._on_duration)

    def _on_duration(self, name, secs, **_):
        if name == self.EVENT:
            self.count += 1
            self.seconds += secs

    def timed(self, fn):
        """``fn()`` once: (its result, {cpu_s, wall_s, xla_compilations, compile_s} of the call)."""
        n0, s0 = self.count, self.seconds
        t, w = time.process_time(), time.perf_counter()
        out = fn()
        return out, {
            "cpu_s": time.process_time() - t,
            "wall_s": time.perf_counter() - w,
            "xla_compilations": self.count - n0,
            "compile_s": self.seconds - s0,
        }


def write_record(path, record: dict) -> None:
    """Write a benchmark's ``record`` as JSON (indent 2, a final newline) to ``path``, its folder
    made, atomically (a temporary file beside it, then renamed), and print it."""
    path = pathlib.Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    text = json.dumps(record, indent=2) + "\n"
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(text, encoding="utf-8")
    os.replace(tmp, path)
    print(text, end="")
