"""The housing's condensation at growing sizes (the aim: "a 300 k-DOF housing under 2 min and
6 GiB").

The box of benchmarks/housing_evidence.py (0.3 x 0.2 x 0.2 m steel, 8 mm walls, three bores,
four feet) meshed by the structured mesher (Tet10, two cells through each wall) at cell sizes
from 50 mm down to 8.5 mm (39 k to 296 k DOFs), condensed at its three seats by
``fem_prep.housing.prepare_housing`` with every fixed-interface mode up to 6 kHz (the rule
for a highest mesh frequency of 4 kHz). Each size runs in its own process (its peak resident
memory is its own): the wall and CPU seconds of the meshing and of each step of
``PreparedHousing.timings`` (assembly, coupling, mode count, factorisation, eigen-solve,
constraint modes, projection), the peak resident set (``ru_maxrss``), the modes found, the
machine and the library versions. The machine is shared: the CPU seconds are the comparable
figure; the load average before and after each size is recorded.

Writes docs/bench/housing_condensation.json and docs/img/housing_condensation.png. From the
repository root: ``python -m benchmarks.housing_condensation`` (all sizes, about 3 min of CPU),
``--sizes 0.05 0.025`` (some), ``--one SIZE`` (one size, JSON on stdout: what each process runs).
"""

from __future__ import annotations

import argparse
import json
import os
import pathlib
import platform
import resource
import subprocess
import sys
import time

ROOT = pathlib.Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "bench" / "housing_condensation.json"
PNG = ROOT / "docs" / "img" / "housing_condensation.png"
SIZES = (0.05, 0.025, 0.015, 0.011, 0.0085)  # m; 39 k .. 296 k DOFs
LAYERS = 2
CUTOFF_HZ = 6000.0
TARGET_S, TARGET_GIB = 120.0, 6.0


def _box():
    from benchmarks.housing_evidence import evidence_box

    return evidence_box()


def one(size: float, progress: bool = False) -> dict:
    """Mesh and condense the box at ``size`` in this process; its figures."""
    import fem_prep
    from fem_prep.housing import mesh_box, prepare_housing

    load0 = os.getloadavg()[0]
    t0, c0 = time.perf_counter(), time.process_time()
    hm = mesh_box(_box(), size, layers=LAYERS)
    mesh_s, mesh_cpu_s = time.perf_counter() - t0, time.process_time() - c0
    t0, c0 = time.perf_counter(), time.process_time()
    p = prepare_housing(hm, fem_prep.Material(210e9, 0.3, 7800.0), CUTOFF_HZ, progress=progress)
    wall, cpu = time.perf_counter() - t0, time.process_time() - c0
    c = p.condensed
    return {
        "size_m": size,
        "layers": LAYERS,
        "tetrahedra": int(hm.mesh.t.shape[1]),
        "dofs": int(hm.n_dofs),
        "interior_dofs": int(p.K.shape[0] - p.seat_dofs.size),
        "seat_dofs": int(p.seat_dofs.size),
        "modes_found": int(c.n_modes),
        "modes_hz": [round(float(f), 3) for f in c.modes_hz],
        "mesh_s": mesh_s,
        "mesh_cpu_s": mesh_cpu_s,
        "steps": dict(p.timings),
        "prepare_wall_s": wall,
        "prepare_cpu_s": cpu,
        "total_wall_s": wall + mesh_s,
        "total_cpu_s": cpu + mesh_cpu_s,
        "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
        "factor": _factor_library(),
        "load_average_before": load0,
        "load_average_after": os.getloadavg()[0],
    }


def _factor_library() -> str:
    """The library ``fem_prep.factorize`` picks here (of a 2 x 2 identity)."""
    import scipy.sparse as sp

    import fem_prep

    return fem_prep.factorize(sp.identity(2, format="csr")).library


def _machine() -> dict:
    import numpy
    import scipy
    import skfem

    cpu = ""
    try:
        for line in pathlib.Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    mem = 0.0
    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):
        pass
    versions = {
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "scikit-fem": skfem.__version__,
    }
    from importlib.metadata import PackageNotFoundError, version

    for name in ("pypardiso", "mkl", "cholespy"):
        try:
            versions[name] = version(name)
        except PackageNotFoundError:
            versions[name] = None
    return {
        "cpu": cpu,
        "cpus": os.cpu_count(),
        "memory_gib": round(mem, 1),
        "shared": "2 cores shared with other processes (load average per size)",
        "versions": versions,
    }


def chart(res: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = res["sizes"]
    before = res.get("before", [])
    n = [r["dofs"] / 1e3 for r in rows]
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.2))
    steps = (
        "assembly",
        "coupling",
        "mode_count",
        "factorisation",
        "eigen",
        "constraint_modes",
        "projection",
    )
    bottom = [r["mesh_cpu_s"] for r in rows]
    ax[0].bar(n, bottom, width=16, label="meshing", color="0.8")
    for s in steps:
        v = [r["steps"].get(f"{s}_cpu_s", 0.0) for r in rows]
        ax[0].bar(n, v, width=16, bottom=bottom, label=s.replace("_", " "))
        bottom = [b + x for b, x in zip(bottom, v)]
    for r in before:
        ax[0].plot(
            r["dofs"] / 1e3,
            r["total_cpu_s"],
            "x",
            color="k",
            ms=9,
            label="before (16, 32, 64 modes)",
        )
    ax[0].axhline(TARGET_S, color="r", lw=0.8, ls=":", label=f"target {TARGET_S:.0f} s")
    ax[0].set(
        xlabel="housing DOFs (thousands)",
        ylabel="CPU seconds",
        title=f"condensation to {CUTOFF_HZ:.0f} Hz: CPU s by step",
    )
    ax[0].legend(fontsize=7)
    ax[1].plot(n, [r["total_wall_s"] for r in rows], "^-", label="wall, meshing included")
    for x, r in zip(n, rows):
        ax[1].annotate(
            f"load {r['load_average_before']:.0f}",
            (x, r["total_wall_s"]),
            fontsize=7,
            xytext=(-12, 6),
            textcoords="offset points",
        )
    for r in before:
        ax[1].plot(r["dofs"] / 1e3, r["prepare_wall_s"], "x", color="k", ms=9, label="before")
    ax[1].axhline(TARGET_S, color="r", lw=0.8, ls=":", label=f"target {TARGET_S:.0f} s")
    ax[1].set(
        xlabel="housing DOFs (thousands)",
        ylabel="wall seconds",
        title="wall time on the shared 2-core machine",
    )
    ax[1].legend(fontsize=7)
    ax[2].plot(n, [r["peak_rss_gib"] for r in rows], "o-", label="peak resident set")
    for r in before:
        ax[2].plot(r["dofs"] / 1e3, r["peak_rss_gib"], "x", color="k", ms=9, label="before")
    ax[2].axhline(TARGET_GIB, color="r", lw=0.8, ls=":", label=f"target {TARGET_GIB:.0f} GiB")
    ax[2].set(xlabel="housing DOFs (thousands)", ylabel="GiB", ylim=(0, None), title="peak memory")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(PNG, dpi=110)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--sizes", type=float, nargs="*", default=list(SIZES))
    ap.add_argument("--one", type=float, default=None)
    ap.add_argument("--progress", action="store_true")
    ap.add_argument("--chart-only", action="store_true")
    a = ap.parse_args()
    if a.one is not None:
        print(json.dumps(one(a.one, a.progress)))
        return
    res = json.loads(OUT.read_text()) if OUT.exists() else {}
    if not a.chart_only:
        rows = {r["size_m"]: r for r in res.get("sizes", [])}
        env = dict(os.environ, PYTHONPATH=str(ROOT))
        for s in a.sizes:
            out = subprocess.run(
                [sys.executable, "-m", "benchmarks.housing_condensation", "--one", str(s)]
                + (["--progress"] if a.progress else []),
                cwd=ROOT,
                env=env,
                check=True,
                stdout=subprocess.PIPE,
                text=True,
            ).stdout
            rows[s] = json.loads(out.strip().splitlines()[-1])
            print(
                json.dumps(
                    {
                        k: rows[s][k]
                        for k in (
                            "dofs",
                            "modes_found",
                            "total_wall_s",
                            "total_cpu_s",
                            "peak_rss_gib",
                        )
                    }
                )
            )
        res["cutoff_hz"] = CUTOFF_HZ
        res["target"] = {"dofs": 300000, "wall_s": TARGET_S, "memory_gib": TARGET_GIB}
        res["sizes"] = sorted(rows.values(), key=lambda r: r["dofs"])
        res["machine"] = _machine()
        res["date"] = time.strftime("%Y-%m-%d", time.gmtime())
        OUT.write_text(json.dumps(res, indent=1) + "\n")
    chart(res)


if __name__ == "__main__":
    main()
