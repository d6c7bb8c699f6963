"""Where the time of one BEM frequency goes, and bempp-cl's back ends side by side
(docs/bench/bem_backends.json, docs/acoustics.md "Time per frequency").

On the octahedral sphere of level 4 (1026 vertices, 2048 triangles: the size of a housed pair's
skin) at one frequency, for each back end (:class:`fem_prep.acoustics.Numba`, and
:class:`fem_prep.acoustics.OpenCL` where pyopencl and a CPU OpenCL driver import): the first
use (the kernels' compile or build and one assembly, at 0.8 times the frequency: what the
first frequency of a run costs), then in ``--rounds`` rounds, the back ends
interleaved so that both see the same load, the time of each dense operator (the identity,
V, K, D, and K' which the solve no longer assembles: K' = Kᵀ), the Burton–Miller solve, and
the eigen-decomposition that :func:`fem_prep.acoustics.radiation_resistance` stores, each
assembly in wall and in CPU seconds (all the process's threads: the fairer measure on a
shared machine). The
operators of the two back ends are compared (relative Frobenius difference), and the power of
the pulsating sphere against its analytic value (a check that the figures timed are right).

The exafmm-t fast multipole path of bempp-cl is not measured: exafmm-t is not on the package
index (it builds from source with a C++ toolchain), and a multipole operator gives matrix-vector
products, not the dense Z whose n × n resistance R the cache holds (R would cost n iterative
solves).

Timing on a shared machine is valid only as ratios within one run; the load average is
recorded at the start and the end. From the repository root:
``python -m benchmarks.bem_backends [--rounds N] [--level L]``.
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import time

import numpy as np

import fem_prep.acoustics as fa
from fem_prep.acoustics import _bem

from ._timing import environment

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "bem_backends.json"
RADIUS = 0.1  # m
FREQUENCY = 1000.0  # Hz: ka = 1.83 on the 0.1 m sphere
OPERATORS = ("identity", "single_layer", "double_layer", "hypersingular", "adjoint_double_layer")


def _available():
    bempp = _bem._bempp()
    return [b for b in (fa.Numba(), fa.OpenCL()) if b.available(bempp)]


def _operators(surface, k, backend):
    """Each operator's dense weak form and its time (s), assembled as bem_operators does."""
    bempp, sp, dof = _bem._space(surface)
    b = bempp.operators.boundary
    ix = np.ix_(dof, dof)
    mats, secs, cpu = {}, {}, {}
    with backend.session(bempp), _bem._quiet():
        for name in OPERATORS:
            t, c = time.perf_counter(), time.process_time()
            if name == "identity":
                op = b.sparse.identity(sp, sp, sp)
            else:
                op = getattr(b.helmholtz, name)(
                    sp, sp, sp, k, device_interface=backend.device_interface
                )
            mats[name] = np.asarray(op.weak_form().to_dense())[ix]
            secs[name] = time.perf_counter() - t
            cpu[name] = time.process_time() - c
    return mats, secs, cpu


def _solve(mats, k, frequency):
    """Z by Burton–Miller with K' = Kᵀ (bem_impedance's equations), and its time."""
    t = time.perf_counter()
    alpha = 1j / k
    ident, K = mats["identity"], mats["double_layer"]
    lhs = 0.5 * ident - K + alpha * mats["hypersingular"]
    rhs = -mats["single_layer"] - alpha * (0.5 * ident + K.T)
    Z = 2j * np.pi * frequency * fa.AIR.density * np.linalg.solve(lhs, rhs)
    return Z, time.perf_counter() - t


def _summary(rounds):
    """Per back end: the least (over rounds) assembly wall and CPU seconds of the three
    operators a frequency needs, and the ratio of numba's to each."""
    out = {}
    for be in sorted({r["backend"] for r in rounds}):
        rs = [r for r in rounds if r["backend"] == be]
        out[be] = {
            "assembly_needed_s_min": min(r["assembly_needed_s"] for r in rs),
            "assembly_needed_cpu_s_min": min(r["assembly_needed_cpu_s"] for r in rs),
            "per_frequency_s_min": min(r["per_frequency_s"] for r in rs),
        }
    for be, d in out.items():
        d["numba_over_this_cpu"] = round(
            out["numba"]["assembly_needed_cpu_s_min"] / d["assembly_needed_cpu_s_min"], 2)
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=2)
    ap.add_argument("--level", type=int, default=4)
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    load0 = os.getloadavg()
    surface = fa.sphere_surface(RADIUS, args.level)
    k = fa.AIR.wavenumber(FREQUENCY)
    backends = _available()
    record = {
        "surface": f"sphere_surface({RADIUS}, {args.level})",
        "vertices": surface.n_vertices,
        "triangles": len(surface.triangles),
        "frequency_Hz": FREQUENCY,
        "ka": k * RADIUS,
        "backends": [str(b) for b in backends],
        "load_average_start": load0,
        "first_use_s": {},
        "rounds": [],
    }
    k0 = fa.AIR.wavenumber(0.8 * FREQUENCY)
    for be in backends:  # the kernels' compile (numba) or build (OpenCL) and one assembly
        t, c = time.perf_counter(), time.process_time()
        _operators(surface, k0, be)
        record["first_use_s"][str(be)] = round(time.perf_counter() - t, 2)
        record.setdefault("first_use_cpu_s", {})[str(be)] = round(time.process_time() - c, 2)
        print(f"{be}: first use {record['first_use_s'][str(be)]} s", flush=True)
    mats = {}
    for r in range(args.rounds):
        for be in backends:
            m, secs, cpu = _operators(surface, k, be)
            Z, t_solve = _solve(m, k, FREQUENCY)
            t = time.perf_counter()
            MZ = surface.mass_matrix() @ Z
            np.linalg.eigh(0.25 * (MZ + MZ.conj().T))
            t_eig = time.perf_counter() - t
            needed = sum(v for n, v in secs.items() if n != "adjoint_double_layer")
            needed_cpu = sum(v for n, v in cpu.items() if n != "adjoint_double_layer")
            row = {
                "round": r,
                "backend": str(be),
                "load_average": os.getloadavg()[0],
                "assembly_s": {n: round(v, 2) for n, v in secs.items()},
                "assembly_cpu_s": {n: round(v, 2) for n, v in cpu.items()},
                "assembly_needed_s": round(needed, 2),
                "assembly_needed_cpu_s": round(needed_cpu, 2),
                "solve_s": round(t_solve, 2),
                "eigh_s": round(t_eig, 2),
                "per_frequency_s": round(needed + t_solve + t_eig, 2),
                "per_frequency_with_adjoint_s": round(sum(secs.values()) + t_solve + t_eig, 2),
            }
            record["rounds"].append(row)
            print(json.dumps(row), flush=True)
            mats[str(be)] = (m, Z)
    # checks of what was timed
    m, Z = mats["numba"]
    record["summary"] = _summary(record["rounds"])
    rel = np.linalg.norm(m["adjoint_double_layer"] - m["double_layer"].T)
    record["adjoint_minus_transpose_rel"] = float(rel / np.linalg.norm(m["double_layer"]))
    v = np.full(surface.n_vertices, 1e-3 + 0j)
    M = surface.mass_matrix()
    w = float(np.real(v.conj() @ (0.25 * (M @ Z + (M @ Z).conj().T)) @ v))
    ka = k * RADIUS
    exact = 4 * np.pi * RADIUS**2 * 0.5 * fa.AIR.impedance * 1e-6 * ka**2 / (1 + ka**2)
    record["pulsating_sphere_power_error"] = w / exact - 1
    if "opencl" in mats:
        mo, Zo = mats["opencl"]
        record["opencl_vs_numba_rel"] = {
            n: float(np.linalg.norm(mo[n] - m[n]) / np.linalg.norm(m[n])) for n in OPERATORS
        } | {"Z": float(np.linalg.norm(Zo - Z) / np.linalg.norm(Z))}
    record["load_average_end"] = os.getloadavg()
    record["environment"] = environment()
    print(json.dumps({k: v for k, v in record.items() if k != "rounds"}, indent=1))
    if not args.no_write:
        OUT.write_text(json.dumps(record, indent=1) + "\n")
        print(f"wrote {OUT.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
