"""How many sizing candidates a second: the batched program of ``jaxgear.sizing.size``
(``jit(vmap)`` over chunks of candidates: geometry, validity, ISO 1328-1 tolerances and the ISO
6336 rating) against a loop over the candidates of the same formulas in NumPy, one candidate at
a time, in one process so that the ratio holds under any load.

The NumPy loop is the library's own code evaluated by NumPy (``jaxgear.sizing.candidate_outputs``,
one candidate): the modules the candidate's evaluation runs through (the rating, its geometry and tooth form, the ISO 1328-1 tolerances,
the sizing's candidate function) have their ``jax.numpy`` name pointed at NumPy for the loop,
so it computes the very formulas the batched program compiles, on NumPy scalars, with no JAX
dispatch (a careful hand port would do the same operations; it would not be faster by more
than NumPy's per-call overhead allows). Its results are checked equal to the batched ones
(rtol 1e-12) on the candidates it evaluates.

Timed: the batched program's first call (compile) and the best of ``REPEATS`` calls on every
candidate of the spec (``block_until_ready``), candidates/s; the NumPy loop over its first
``LOOP`` candidates (best of 2), candidates/s. Writes docs/bench/sizing_throughput.json (or
the file given) with the machine, dtype and JAX version (benchmarks/_timing.py's
``environment()``) and the load average. From the repository root:
``python -m benchmarks.sizing_throughput [FILE]``.
"""

from __future__ import annotations

import contextlib
import importlib
import json
import os
import pathlib
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import numpy as np

import jaxgear.io as jio
import jaxgear.sizing as js
from benchmarks._timing import environment

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_throughput.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
REPEATS = 3
LOOP = 200
#: the modules whose ``jnp`` the NumPy loop points at NumPy (every one the candidate's
#: evaluation reaches)
MODULES = ("jaxgear._util", "jaxgear._deviations", "jaxgear.rating._geometry",
           "jaxgear.rating._bending", "jaxgear.rating._factors", "jaxgear.rating._iso6336",
           "jaxgear.rating._material", "jaxgear.rating._settings", "jaxgear.rating._standard",
           "jaxgear.sizing._size")


@contextlib.contextmanager
def numpy_formulas():
    """The modules of :data:`MODULES` compute with NumPy while the block runs."""
    mods = [importlib.import_module(m) for m in MODULES]
    saved = [m.__dict__.get("jnp") for m in mods]
    for m in mods:
        if "jnp" in m.__dict__:
            m.jnp = np
    try:
        yield
    finally:
        for m, old in zip(mods, saved, strict=True):
            if old is not None:
                m.jnp = old


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    spec, _ = jio.load_sizing_spec(str(SPEC))
    # the spec's ranges widened to many candidates: every module of both ISO 54 choices 1-10
    import dataclasses

    spec = dataclasses.replace(spec, normal_modules=js.module_series(1e-3, 10e-3, "both"),
                               pinion_teeth=(14, 60), centre_distance=None,
                               outer_diameter_max=None)
    n = len(js.enumerate_candidates(spec))
    t = time.perf_counter()
    table = js.size(spec)
    first = time.perf_counter() - t
    runs = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        table = js.size(spec)
        runs.append(time.perf_counter() - t)
    batched = min(runs)
    # the NumPy loop: the same candidate function, one candidate at a time, NumPy inside
    cands = js.enumerate_candidates(spec)
    settings, operating = jax.tree_util.tree_map(np.asarray, (spec.settings, spec.operating))
    spec_np = dataclasses.replace(spec, settings=settings, operating=operating)
    k = min(LOOP, n)
    loop_runs, outs = [], None
    with numpy_formulas():
        for _ in range(2):
            t = time.perf_counter()
            rows = []
            for i in range(k):
                rows.append(js.candidate_outputs(
                    spec_np, cands.normal_module[i], float(cands.z1[i]), float(cands.z2[i]),
                    cands.x1[i], cands.x2[i], cands.face_width[i])[0])
            loop_runs.append(time.perf_counter() - t)
            outs = np.array(rows)
    ref = np.stack([table.columns[name][:k] for name in js.OUTPUTS], axis=1)
    valid = table.feasible[:k] | ~np.isnan(ref).any(axis=1)
    agree = bool(np.allclose(outs[valid], ref[valid], rtol=1e-12, atol=0))
    loop = min(loop_runs)
    record = {
        "what": "sizing candidates per second: jaxgear.sizing.size's jit(vmap) program against "
                "the same formulas in NumPy, one candidate at a time",
        "machine": machine,
        "spec": "examples/sizing/helical.toml with modules 1-10 mm (both ISO 54 choices), "
                "z1 14-60, no centre-distance window or outer-diameter limit",
        "candidates": n,
        "batched": {"first_call_s": round(first, 3), "best_s": round(batched, 4),
                    "candidates_per_s": round(n / batched, 1), "chunk": 2048},
        "numpy_loop": {"candidates": k, "best_s": round(loop, 4),
                       "candidates_per_s": round(k / loop, 1),
                       "equal_to_batched_rtol_1e-12": agree},
        "numpy_loop_note": "the library's own candidate function on NumPy scalars: it keeps the "
                           "library's per-candidate overheads (equinox modules built, tree_at, "
                           "the rating's detail dictionaries), which a hand port would drop; the "
                           "ratio is the batching's gain over that loop, not over the best "
                           "possible scalar code",
        "speed_ratio": round((n / batched) / (k / loop), 1),
        "load_average_at_end": list(os.getloadavg()),
    }
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(record, indent=2) + "\n", encoding="utf-8")
    print(json.dumps(record, indent=2))


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
