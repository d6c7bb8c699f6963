"""How many sizing candidates a second the continuous refinement solves: ``jaxgear.sizing.refine``
(an augmented Lagrangian around ``optimistix.BFGS``, ``jit(vmap)`` over a chunk of candidates)
against SciPy's SLSQP on each candidate in turn, with the same objective, constraints and
bounds and the same JAX functions for their values and gradients (jit-compiled for one
candidate, forward-mode Jacobians), in one process so that the ratio holds under any load.

The spec: examples/sizing/helical.toml with β refined in [8°, 20°] and each profile shift in
[−0.5, 1]; the candidates: ``ROWS`` rows spread over its table. Equal accuracy: both start from
the enumerated design (the refinement with ``starts=1``: one solve a candidate, as SLSQP's),
aim each constraint ``jaxgear.sizing.MARGIN`` inside its limit, and are
judged alike: a result counts where it passes every check when re-rated (the refinement's own
acceptance; for SLSQP the same constraints evaluated at its result, >= 0); the masses of the
rows both solve are compared.

Timed: the refinement's first call (compile) and the best of ``REPEATS`` calls; SLSQP's loop
over the rows after its functions are compiled (the compile reported apart). Writes
docs/bench/sizing_refine.json (or the file given) with the machine, dtype and JAX version
(benchmarks/_timing.py's ``environment()``) and the load average. From the repository root:
``python -m benchmarks.sizing_refine [FILE]``.
"""

from __future__ import annotations

import os
import pathlib
import sys
import time
import tomllib

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp
import numpy as np
import scipy.optimize

import jaxgear.io as jio
import jaxgear.sizing as js
from benchmarks._timing import environment, write_record
from jaxgear.sizing import _refine

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "sizing_refine.json"
SPEC = ROOT / "examples" / "sizing" / "helical.toml"
ROWS = 64
REPEATS = 2


def _spec():
    with open(SPEC, "rb") as f:
        data = tomllib.load(f)
    data["sizing"] |= {"helix_angle_deg": [8.0, 20.0], "profile_shift_min": -0.5,
                       "profile_shift_max": 1.0, "refine": True}
    return jio.parse_sizing_spec(data)[0]


def _slsqp(spec, table, rows):
    """SLSQP on each row in turn: the design (β, x1, x2, b) in its bounds, g >= MARGIN, the
    mass; values and Jacobians by the refinement's own functions, jit-compiled once."""
    cands = js.enumerate_candidates(spec)
    static = js._size._static(spec)
    settings, operating = spec.settings, spec.operating
    fixed = spec.fixed_centre_distance
    lo, hi = _refine._bounds(spec, cands)
    lim = _refine._limits(spec)

    def fg(v, p):
        f, g, _ = _refine._evaluate_design(v, 0.0, p, static, settings, operating, None, fixed,
                                           "mass")
        return f, g

    value = jax.jit(fg)
    jac = jax.jit(jax.jacfwd(fg))
    mass0 = table.columns["mass_kg"]

    def params(k):
        return {"m": jnp.asarray(cands.normal_module[k]), "z1": jnp.asarray(float(cands.z1[k])),
                "z2": jnp.asarray(float(cands.z2[k])), "lim": jnp.asarray(lim),
                "mass0": jnp.asarray(mass0[k] if np.isfinite(mass0[k]) else 1.0)}

    t = time.perf_counter()
    p = params(int(rows[0]))
    v = jnp.asarray([spec.helix_angle, cands.x1[0], cands.x2[0], cands.face_width[0]])
    jax.block_until_ready((value(v, p), jac(v, p)))
    compile_s = time.perf_counter() - t
    results = []
    t = time.perf_counter()
    for k in rows:
        p = params(int(k))
        v0 = np.clip([spec.helix_angle, cands.x1[k], cands.x2[k], cands.face_width[k]],
                     lo[k], hi[k])
        memo = {}

        def ev(v, p=p, memo=memo):
            key = tuple(v)
            if key not in memo:
                f, g = value(jnp.asarray(v), p)
                jf, jg = jac(jnp.asarray(v), p)
                memo.clear()
                memo[key] = (float(f), np.asarray(g), np.asarray(jf), np.asarray(jg))
            return memo[key]

        res = scipy.optimize.minimize(
            lambda v: ev(v)[0], v0, jac=lambda v: ev(v)[2], method="SLSQP",
            bounds=list(zip(lo[k], hi[k], strict=True)),
            constraints=[{"type": "ineq", "fun": lambda v: ev(v)[1] - _refine.MARGIN,
                          "jac": lambda v: ev(v)[3]}],
            options={"maxiter": 200, "ftol": 1e-10})
        f, g = value(jnp.asarray(res.x), p)
        ok = bool(np.all(np.asarray(g) >= 0) and np.isfinite(float(f)))
        results.append((ok, float(f) * float(p["mass0"])))
    loop_s = time.perf_counter() - t
    return compile_s, loop_s, results


def main(path: pathlib.Path = OUT) -> None:
    machine = environment()
    spec = _spec()
    table = js.size(spec)
    n = len(table)
    rows = np.unique(np.linspace(0, n - 1, ROWS).astype(int))
    t = time.perf_counter()
    ref = js.refine(spec, table, rows=rows, starts=1)
    first = time.perf_counter() - t
    runs = []
    for _ in range(REPEATS):
        t = time.perf_counter()
        ref = js.refine(spec, table, rows=rows, starts=1)
        runs.append(time.perf_counter() - t)
    batched = min(runs)
    t = time.perf_counter()
    multi = js.refine(spec, table, rows=rows)  # every start (the default): the same program
    multi_s = time.perf_counter() - t
    compile_s, loop_s, results = _slsqp(spec, table, rows)
    ours = ref.columns["refined"][rows] == 1
    theirs = np.array([ok for ok, _ in results])
    both = ours & theirs
    rel = (ref.columns["mass_kg"][rows][both] - np.array([m for _, m in results])[both]) / \
        ref.columns["mass_kg"][rows][both]
    slsqp_mass = np.array([m for ok, m in results])
    many = (multi.columns["refined"][rows] == 1) & theirs
    rel_many = (multi.columns["mass_kg"][rows][many] - slsqp_mass[many]) / \
        multi.columns["mass_kg"][rows][many]
    record = {
        "what": "refined sizing candidates per second: jaxgear.sizing.refine's batched augmented "
                "Lagrangian (optimistix BFGS, jit(vmap), chunk 64, one start) against scipy.optimize SLSQP "
                "per candidate with the same JAX values and gradients",
        "machine": machine,
        "spec": "examples/sizing/helical.toml, helix_angle_deg = [8, 20], profile shifts "
                "[-0.5, 1], objective mass",
        "candidates": int(rows.size),
        "refine": {"first_call_s": round(first, 2), "best_s": round(batched, 3),
                   "candidates_per_s": round(rows.size / batched, 2),
                   "feasible_refined": int(ours.sum()),
                   "converged": int(ref.columns["refine_converged"][rows].sum())},
        "slsqp": {"compile_s": round(compile_s, 2), "loop_s": round(loop_s, 3),
                  "candidates_per_s": round(rows.size / loop_s, 2),
                  "feasible": int(theirs.sum())},
        "accuracy": {"both_feasible": int(both.sum()),
                     "mass_refine_minus_slsqp_relative": {
                         "median": float(np.median(rel)) if rel.size else None,
                         "min": float(rel.min()) if rel.size else None,
                         "max": float(rel.max()) if rel.size else None},
                     "refine_lighter_by_1e-4": int((rel < -1e-4).sum()),
                     "slsqp_lighter_by_1e-4": int((rel > 1e-4).sum())},
        "speed_ratio": round(loop_s / batched, 2),
        "refine_every_start": {
            "starts": len(js.STARTS) + 1, "s": round(multi_s, 3),
            "candidates_per_s": round(rows.size / multi_s, 2),
            "feasible_refined": int((multi.columns["refined"][rows] == 1).sum()),
            "both_feasible": int(many.sum()),
            "refine_lighter_by_1e-4": int((rel_many < -1e-4).sum()),
            "slsqp_lighter_by_1e-4": int((rel_many > 1e-4).sum()),
            "speed_ratio_to_slsqp_one_start": round(loop_s / multi_s, 2)},
        "load_average_at_end": list(os.getloadavg()),
    }
    write_record(path, record)


if __name__ == "__main__":
    main(pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else OUT)
