"""``fem-prep bench``: timings and peak memory of the condensation on three mesh sizes.

Each case runs in a fresh subprocess (so that ``ru_maxrss`` is the peak of that case alone):
the power-helical wheel meshed at three element sizes (the finest >= 150 000 DOFs), condensed by
Craig-Bampton with 50 modes (the block Lanczos, the factor :func:`~fem_prep.factorize` picks:
scikit-sparse's supernodal CHOLMOD, else MKL PARDISO, else cholespy), and the same condensation
with SciPy's SuperLU (the pure-SciPy fallback) as the baseline on the smallest size and with
cholespy's simplicial CHOLMOD on the largest. Each case records the factor library that ran, the
wall and CPU seconds of each phase and the peak RSS.  A second figure plots the error of the first 20 frequencies
against the number of retained modes for Craig-Bampton and Herting (Fig. III-13's question).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import platform
import resource
import signal
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import scipy
import skfem
from tqdm import tqdm

from ._assemble import assemble_operators
from ._condense import (
    CraigBampton,
    Guyan,
    RotatingOperators,
    condense,
    frequency_error_vs_modes,
)
from ._couplings import couple_masters, select_masters
from ._kinds import CondensationMethod
from ._mesh import mesh_body
from ._prepare import prepare
from ._solver import (
    BlockLanczos,
    CholmodFactor,
    Lanczos,
    PardisoFactor,
    SparseFactor,
    _available_factor,
    factorize,
)
from .files import atomic_open
from .schema import load_body

SIZES_MM = ((16.0, 8.0), (8.0, 3.0), (7.0, 2.0))  # (meridian, circumferential) mm
QUICK_SIZES_MM = (
    (40.0, 30.0),
)  # the coarsest mesh of the wheel (22 k DOFs: one station per tooth)


def _peak_mib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0


# the factor of each benchmark case, by its command-line name (--factor): None is factorize's
# own choice (CHOLMOD by scikit-sparse when it imports, else MKL PARDISO, else cholespy)
FACTORS = {
    "default": None,
    "superlu": SparseFactor,
    "cholespy": CholmodFactor,
    "pardiso": PardisoFactor,
}
FACTOR_LABELS = {"superlu": "SuperLU baseline", "cholespy": "cholespy baseline"}
# the eigen-solver of each case, by its command-line name (--eigen)
EIGEN = {"lanczos": Lanczos(), "block": BlockLanczos()}  # block: CraigBampton's default

QUICK_TEETH = 17  # --quick: the wheel with 17 angular stations instead of 68 (a smoke test)


def _body(
    size_mm: float,
    circ_mm: float,
    method: CondensationMethod | None = None,
    modes: int = 50,
    quick: bool = False,
):
    b = load_body("power-helical-wheel")
    s = size_mm * 1e-3
    mesh = dataclasses.replace(
        b.mesh,
        size=s,
        web_size=s,
        hub_size=None,
        rim_size=None,
        circumferential_size=circ_mm * 1e-3,
    )
    cond = dataclasses.replace(
        b.condensation,
        method=method or CraigBampton(),
        modes=modes,
        **({"teeth": QUICK_TEETH} if quick else {}),
    )
    return dataclasses.replace(b, mesh=mesh, condensation=cond)


def _case(
    size_mm: float,
    circ_mm: float,
    factor: str = "default",
    quick: bool = False,
    eigen: str = "block",
) -> dict:
    body = _body(size_mm, circ_mm, quick=quick)
    out: dict = {"size_mm": size_mm, "circumferential_size_mm": circ_mm}
    t0 = time.perf_counter()
    bm = mesh_body(body)
    out["mesh_s"] = time.perf_counter() - t0
    out["n_dofs"] = bm.n_dofs
    out["n_elements"] = int(bm.mesh.nelements)
    t0 = time.perf_counter()
    ops = assemble_operators(bm.basis, body.material)
    out["assembly_s"] = time.perf_counter() - t0
    ms = select_masters(bm, body)
    cp = couple_masters(bm, ops, ms)
    rim = cp.rim_dofs.ravel()
    mdofs = np.concatenate([rim, cp.bearing_dofs.ravel()])
    out["n_master_dofs"] = len(mdofs)
    # the condensation's own peak: what it does not take (the full-model operators, the
    # coupling's other matrices, the mesh) is released first
    K, M, f = cp.K, cp.M, cp.f
    del cp, ops, ms, bm
    t0, c0 = time.perf_counter(), time.process_time()
    interior = np.setdiff1d(np.arange(K.shape[0]), mdofs)
    # the baselines: the same Craig-Bampton with SciPy's SuperLU (the pure-SciPy fallback) or
    # cholespy's simplicial CHOLMOD instead of factorize's choice; everything else identical.
    # factorize's own choice is made inside condense, as the pipeline does: its factor is freed
    # before the projections (one passed in stays alive, and in the peak, until the end)
    cls = FACTORS[factor]
    fac = None if cls is None else factorize(K[interior][:, interior], method=cls)
    solver, library = (cls or _available_factor()).method, (cls or _available_factor()).library
    cond = condense(
        K,
        M,
        mdofs,
        method=CraigBampton(eigen_solver=EIGEN[eigen]),
        n_modes=50,
        rotating=RotatingOperators(f=f),
        interior_factor=fac,
    )
    del fac
    out["condensation_s"] = time.perf_counter() - t0
    # the CPU time of the process (all threads) over the condensation: on a shared machine the
    # wall time counts the other jobs' share too
    out["condensation_cpu_s"] = time.process_time() - c0
    out["factorisation_s"] = cond.timings["factorisation_s"] + (
        out["condensation_s"] - sum(v for k, v in cond.timings.items() if not k.endswith("_cpu_s"))
    )
    for key in ("static_modes", "eigen", "projection"):
        out[f"{key}_s"] = cond.timings[f"{key}_s"]
    for key in ("factorisation", "static_modes", "eigen", "projection"):
        out[f"{key}_cpu_s"] = cond.timings[f"{key}_cpu_s"]
    out["n_condensed_dofs"] = int(cond.K.shape[0])
    out["solver"] = solver
    out["library"] = library
    out["factor"] = factor
    out["eigen_solver"] = repr(EIGEN[eigen])
    out["method"] = f"sparse Craig-Bampton ({FACTOR_LABELS.get(factor, f'{solver} by {library}')})"
    out["baseline"] = factor in FACTOR_LABELS
    out["peak_rss_mib"] = _peak_mib()
    out["load_average_1min"] = os.getloadavg()[0]
    return out


def _error_curve(size_mm: float, circ_mm: float, quick: bool = False) -> dict:
    """Max relative error of the first 20 frequencies (bearings held) vs number of modes."""
    base = prepare(_body(size_mm, circ_mm, Guyan(), 0, quick=quick))
    curves: dict = {
        "modes": [0, 10] if quick else [0, 5, 10, 20, 30, 50, 80],
        "f_full_hz": list(map(float, base.frequencies_full_hz)),
    }
    curves.update(frequency_error_vs_modes(base, curves["modes"]))
    curves["n_dofs"] = base.mesh.n_dofs
    return curves


def _failure(returncode: int, stdout: str, stderr: str) -> str:
    """One line saying why a benchmark subprocess failed: the exception type and message it
    reported, else the signal that killed it, else the last line of its stderr."""
    for line in reversed(stdout.strip().splitlines()):
        try:
            return str(json.loads(line)["error"])
        except (ValueError, TypeError, KeyError, IndexError):  # not an error record
            continue
    if returncode < 0:
        try:
            sig = signal.Signals(-returncode)
        except ValueError:
            return f"killed by signal {-returncode}"
        hint = " (out of memory?)" if sig == signal.SIGKILL else ""
        return f"killed by {sig.name}{hint}"
    tail = [ln for ln in stderr.strip().splitlines() if ln.strip()]
    return f"exit status {returncode}: {tail[-1] if tail else 'no message'}"


def _sub(args: list[str]) -> dict:
    cmd = [sys.executable, "-m", "fem_prep._bench", *args]
    res = subprocess.run(cmd, capture_output=True, text=True, check=False)
    if res.returncode != 0:
        return {
            "error": _failure(res.returncode, res.stdout, res.stderr),
            "stderr_tail": res.stderr[-2000:],
            "args": args,
        }
    return json.loads(res.stdout.strip().splitlines()[-1])


@dataclass(frozen=True)
class _CaseJob:
    """One timing case: the wheel at ``sizes`` (meridian, circumferential mm) with the factor
    named ``factor`` (a key of :data:`FACTORS`); a successful case of an interrupted run
    (``old``) is reused."""

    sizes: tuple[float, float]
    factor: str = "default"

    def run(self, rec: dict, old: list, quick: bool) -> None:
        s, cs = self.sizes
        done = [
            c
            for c in old
            if c["size_mm"] == s
            and c["circumferential_size_mm"] == cs
            and c.get("factor", "superlu" if c.get("baseline") else "default") == self.factor
        ]
        args = ["case", str(s), str(cs), "--factor", self.factor, *(["--quick"] * quick)]
        rec["cases"].append(done[0] if done else _sub(args))


@dataclass(frozen=True)
class _CurveJob:
    """The error curve against the number of retained modes (once: kept on resume)."""

    sizes: tuple[float, float]

    def run(self, rec: dict, old: list, quick: bool) -> None:
        s, cs = self.sizes
        if rec.get("error_curve") is None:
            rec["error_curve"] = _sub(["curve", str(s), str(cs), *(["--quick"] * quick)])


def run_bench(out_dir: str, *, quick: bool = False, resume: bool = False) -> dict:
    """Run the benchmark, write ``bench.json``, ``bench.png`` and ``modes_error.png``.

    Args:
        out_dir: output directory.
        quick: a smoke test: the coarsest mesh of the wheel with 17 angular stations instead of
            68 (about 5 k DOFs), no baseline, a two-point error curve.
        resume: reuse the successful cases of ``partial.json`` from an interrupted run.

    Returns:
        The benchmark record.
    """
    sizes = QUICK_SIZES_MM if quick else SIZES_MM
    rec: dict = {
        "machine": f"{platform.machine()} {platform.processor()}".strip(),
        "cpus": os.cpu_count(),
        "load_average": os.getloadavg(),
        "python": platform.python_version(),
        "numpy": np.__version__,
        "scipy": scipy.__version__,
        "scikit-fem": skfem.__version__,
        "cases": [],
    }
    # the baselines (SuperLU on the smallest size, cholespy on the largest) only in the full
    # benchmark
    baselines = [_CaseJob(sizes[0], "superlu"), _CaseJob(sizes[-1], "cholespy")]
    jobs = [_CaseJob(s) for s in sizes] + [*([] if quick else baselines), _CurveJob(sizes[0])]
    rec["quick"] = bool(quick)
    old: list = []
    part = Path(out_dir) / "partial.json"
    if resume and part.is_file():
        prev = json.loads(part.read_text())
        old = [c for c in prev.get("cases", []) if not _failed(c)]
        if _done(prev.get("error_curve", {})):
            rec["error_curve"] = prev["error_curve"]
    for job in tqdm(jobs, desc="fem-prep bench"):
        job.run(rec, old, quick)
        (Path(out_dir) / "partial.json").parent.mkdir(parents=True, exist_ok=True)
        with atomic_open(Path(out_dir) / "partial.json") as f:
            f.write(json.dumps(rec, indent=2))
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    with atomic_open(out / "bench.json") as f:
        f.write(json.dumps(rec, indent=2))
    _plots(rec, out)
    if _failed(rec.get("error_curve", {})):
        print(f"error curve failed: {rec['error_curve']['error']}")
    for c in rec["cases"]:
        if _failed(c):
            print(f"case {' '.join(c['args'])} failed: {c['error']}")
            continue
        print(
            f"{c['method'][:20]:20s} size {c['size_mm']:5.1f}/{c['circumferential_size_mm']:.1f} mm  DOFs {c['n_dofs']:7d}  "
            f"assembly {c['assembly_s']:6.1f} s  factor {c['factorisation_s']:6.1f} s  "
            f"static {c['static_modes_s']:6.1f} s  eigen {c['eigen_s']:6.1f} s  "
            f"condensation {c['condensation_s']:6.1f} s ({c['condensation_cpu_s']:.1f} s CPU)  "
            f"peak {c['peak_rss_mib']:7.0f} MiB  [{c['library']}]"
        )
    print(f"wrote {out / 'bench.json'}")
    return rec


def _failed(record: dict) -> bool:
    """A benchmark job's record says it failed (``_sub``: it carries the error)."""
    return bool(record.get("error"))


def _done(curve: dict) -> bool:
    """The error-curve record holds a computed curve."""
    return bool(curve.get("modes"))


def _plots(rec: dict, out: Path) -> None:
    # lazy: matplotlib (heavy) only when the benchmark draws its figures, not on `import fem_prep`
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ok = [c for c in rec["cases"] if not _failed(c) and not c.get("baseline")]
    if ok:
        fig, ax = plt.subplots(figsize=(5, 3.5))
        n = [c["n_dofs"] for c in ok]
        for key in ("assembly_s", "factorisation_s", "static_modes_s", "eigen_s", "condensation_s"):
            ax.loglog(n, [c[key] for c in ok], "o-", label=key[:-2])
        ax.set_xlabel("DOFs")
        ax.set_ylabel("time (s)")
        ax.legend(fontsize=7)
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        with atomic_open(out / "bench.png", "wb") as f:
            fig.savefig(f, format="png", dpi=120)
        plt.close(fig)
    cur = rec.get("error_curve", {})
    if _done(cur):
        fig, ax = plt.subplots(figsize=(5, 3.5))
        for method in ("craig-bampton", "herting"):
            ax.semilogy(cur["modes"], np.maximum(cur[method], 1e-12), "o-", label=method)
        ax.set_xlabel("retained modes")
        ax.set_ylabel("max rel. error, first 20 frequencies")
        ax.set_title(f"power-helical wheel, {cur['n_dofs']} DOFs")
        ax.legend()
        ax.grid(True, which="both", alpha=0.3)
        fig.tight_layout()
        with atomic_open(out / "modes_error.png", "wb") as f:
            fig.savefig(f, format="png", dpi=120)
        plt.close(fig)


def _main(argv: list[str]) -> None:
    """``python -m fem_prep._bench case SIZE CIRC [--factor NAME] [--eigen KIND] [--quick]`` or
    ``... curve SIZE CIRC [--quick]``: one benchmark job, its record printed as one JSON line
    (NAME: a key of :data:`FACTORS`; KIND: a key of :data:`EIGEN`)."""
    parser = argparse.ArgumentParser(prog="python -m fem_prep._bench")
    sub = parser.add_subparsers(required=True)
    case = sub.add_parser("case")
    case.set_defaults(run=lambda a: _case(a.size, a.circ, a.factor, a.quick, a.eigen))
    case.add_argument("--factor", choices=sorted(FACTORS), default="default")
    case.add_argument("--eigen", choices=sorted(EIGEN), default="block")
    curve = sub.add_parser("curve")
    curve.set_defaults(run=lambda a: _error_curve(a.size, a.circ, a.quick))
    for p in (case, curve):
        p.add_argument("size", type=float)
        p.add_argument("circ", type=float)
        p.add_argument("--quick", action="store_true")
    args = parser.parse_args(argv)
    print(json.dumps(args.run(args)))


if __name__ == "__main__":
    try:
        _main(sys.argv[1:])
    except Exception as exc:  # noqa: BLE001 - reported to the parent as data: type and message
        print(json.dumps({"error": f"{type(exc).__name__}: {exc}"}), flush=True)
        sys.exit(1)
