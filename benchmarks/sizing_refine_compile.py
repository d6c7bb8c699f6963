"""Where the continuous refinement's compile time goes (``jaxgear.sizing.refine``): the sizes
of the traced programs (jaxpr equations, counted into every sub-program) and the XLA compile
seconds of the rating's forward program, its reverse-mode gradient and forward-mode Jacobian
(each ``vmap``ped over a chunk), and of the whole solve (the augmented-Lagrangian ``scan``
around ``optimistix.BFGS``, ``vmap``ped over the chunk) with the gradient in reverse mode (as
shipped) and in forward mode; how often the solve's trace evaluates the rating (once each: its
shape, BFGS's linearisation, the outer step's re-evaluation: no retrace per start, outer
iteration or chunk); the solve's compile at a chunk of one, and with the XLA CPU options the
test suite sets (``SUITE_OPTIONS``). In one process, one compile each (compile times move with
the load: compare them within a run).

The spec: examples/sizing/helical.toml with β refined in [8°, 20°] and each profile shift in
[−0.5, 1] (benchmarks/sizing_refine.py's). Writes docs/bench/sizing_refine_compile.json (or
the file given) with the machine, dtype and JAX version (benchmarks/_timing.py's
``environment()``) and the load average. From the repository root:
``python -m benchmarks.sizing_refine_compile [FILE]``.
"""

from __future__ import annotations

import os
import pathlib
import sys
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.extend
import jax.numpy as jnp
import numpy as np

import jaxgear.sizing as js
from benchmarks._timing import environment, write_record
from benchmarks.sizing_refine import _spec
from jaxgear.sizing import _refine

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_refine_compile.json"
CHUNK = 64


def _equations(closed) -> int:
    """The equations of a traced program, those of its sub-programs (jit, scan, while, cond,
    custom rules) counted in."""
    kinds = (jax.extend.core.ClosedJaxpr, jax.extend.core.Jaxpr)

    def walk(jaxpr):
        n = 0
        for e in jaxpr.eqns:
            n += 1
            for v in e.params.values():
                for x in v if isinstance(v, list | tuple) else [v]:
                    if isinstance(x, kinds):
                        n += walk(x.jaxpr if hasattr(x, "jaxpr") else x)
        return n

    return walk(closed.jaxpr)


#: the XLA CPU options the test suite compiles with (tests/conftest.py: the element-wise fusion
#: emitter, one LLVM module a program, LLVM's expensive passes left out)
SUITE_OPTIONS = {"xla_cpu_use_fusion_emitters": False,
                 "xla_cpu_parallel_codegen_split_count": 1,
                 "xla_llvm_disable_expensive_passes": True}


def _compile_s(fn, *args, options=None) -> tuple[float, float]:
    """(trace and lower, XLA compile) seconds of ``fn`` (jitted) at ``args``, compiled with the
    XLA ``options`` (None: XLA's defaults)."""
    t = time.perf_counter()
    lowered = fn.lower(*args)
    t1 = time.perf_counter()
    lowered.compile(options)
    return t1 - t, time.perf_counter() - t1


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    spec = _spec()
    cands = js.enumerate_candidates(spec)
    static = js._size._static(spec)
    settings, operating = jax.tree_util.tree_map(
        lambda v: jnp.asarray(v, dtype=float) if isinstance(v, float) else v,
        (spec.settings, spec.operating))
    lo, hi = _refine._bounds(spec, cands)
    k = 0
    one = {"m": cands.normal_module[k], "z1": float(cands.z1[k]), "z2": float(cands.z2[k]),
           "lo": lo[k], "hi": hi[k], "mass0": 1.0, "lim": _refine._limits(spec),
           "y0": np.zeros(5)}
    one = {n: jnp.asarray(v, dtype=float) for n, v in one.items()}
    batch = {n: jnp.broadcast_to(v, (CHUNK, *v.shape)) for n, v in one.items()}
    fixed = spec.fixed_centre_distance

    def fg(y, p):
        f, g, _ = _refine._evaluate(y, p, static, settings, operating, None, fixed, "mass")
        return f, g

    def penalty(y, p):  # a scalar of f and g as the Lagrangian's (its gradient's program)
        f, g = fg(y, p)
        return f + jnp.sum(jnp.maximum(0.0, -g) ** 2)

    y = jnp.zeros((CHUNK, 5))
    programs = {
        "rating_forward": jax.vmap(fg),
        "rating_gradient_reverse": jax.vmap(jax.grad(penalty)),
        "rating_jacobian_forward": jax.vmap(jax.jacfwd(fg)),
    }
    record_programs = {}
    for name, fn in programs.items():
        equations = _equations(jax.make_jaxpr(fn)(y, batch))
        lower_s, compile_s = _compile_s(jax.jit(fn), y, batch)
        record_programs[name] = {"equations": equations, "trace_lower_s": round(lower_s, 2),
                                 "compile_s": round(compile_s, 2)}
        print(name, record_programs[name], flush=True)

    # the whole solve: how often its trace evaluates the rating, and its compile
    calls = []
    rating = _refine._one

    def counted(*args, **kwargs):
        calls.append(1)
        return rating(*args, **kwargs)

    args = (static, settings, operating, None, fixed, "mass", 12, 40)
    _refine._one = counted
    try:
        solve_eqs = _equations(jax.make_jaxpr(
            lambda b: _refine._solve_one(jax.tree.map(lambda v: v[0], b), *args))(batch))
    finally:
        _refine._one = rating
    solves = {}
    for mode, n, options in (("bwd", CHUNK, None), ("fwd", CHUNK, None), ("bwd", 1, None),
                             ("bwd", CHUNK, SUITE_OPTIONS)):
        _refine._AUTODIFF_MODE = mode
        try:
            b = {name: v[:n] for name, v in batch.items()}
            # a fresh jit of the solve (refine's own is cached whatever the mode)
            fn = jax.jit(lambda b: jax.vmap(lambda p: _refine._solve_one(p, *args))(b))
            lower_s, compile_s = _compile_s(fn, b, options=options)
        finally:
            _refine._AUTODIFF_MODE = "bwd"
        key = f"{mode}_chunk_{n}" + ("" if options is None else "_suite_xla_options")
        solves[key] = {"trace_lower_s": round(lower_s, 2), "compile_s": round(compile_s, 2)}
        print(key, solves[key], flush=True)
    record = {
        "what": "the refinement's compile: traced program sizes and XLA compile seconds of the "
                "rating's forward program, reverse-mode gradient, forward-mode Jacobian and the "
                "whole solve (reverse and forward mode, chunk 64 and 1, and with the test "
                "suite's XLA CPU options), one compile each",
        "machine": machine,
        "spec": "examples/sizing/helical.toml, helix_angle_deg = [8, 20], profile shifts "
                "[-0.5, 1], objective mass",
        "chunk": CHUNK,
        "programs": record_programs,
        "solve": {"equations_one_candidate": solve_eqs,
                  "rating_evaluations_in_its_trace": len(calls), **solves},
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
