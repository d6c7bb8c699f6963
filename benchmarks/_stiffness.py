"""Speed vs accuracy of the mesh stiffness models (docs/stiffness.md, "Speed vs accuracy").

``bench_stiffness(out_dir)`` builds the k(s) table of a case under ``iso6336`` (a uniform k0 from
ISO 6336-1 c_γα), ``weber`` (Weber's half-plane foundation), ``weber+sainsot`` and ``fe2d`` at
several element sizes, times each build, runs the quasi-static TE (exact contact, the case's
modifications and torque) with each table, and compares TE mean and peak-to-peak with ``fe2d`` at
a refined size (m_n/16). It writes ``bench_stiffness.json`` and ``speed_accuracy_stiffness.png``.

Timing: the table build only (``jaxgear.stiffness_table``), the min of 3 repeats for the analytic
models, the min of 2 cold runs for ``fe2d`` (a fresh FE cache each, scikit-fem imported and
warmed up first); the cached ``fe2d`` table is timed too (min of 2). Benchmarks are not tests:
timings are measured here, never asserted.
"""

from __future__ import annotations

import json
import os
import tempfile
import time

import numpy as np

from ._charts import thin_tick_labels
from ._timing import environment

__all__ = ["bench_stiffness"]


class _fresh_cache:
    """``FEM_PREP_CACHE`` pointed at a new temporary folder inside the block."""

    def __enter__(self):
        self._tmp = tempfile.TemporaryDirectory()
        self._old = os.environ.get("FEM_PREP_CACHE")
        os.environ["FEM_PREP_CACHE"] = self._tmp.name
        return self

    def __exit__(self, *exc):
        if self._old is None:
            os.environ.pop("FEM_PREP_CACHE", None)
        else:
            os.environ["FEM_PREP_CACHE"] = self._old
        self._tmp.cleanup()


def bench_stiffness(
    out_dir,
    quick: bool = False,
    case: str = "accessory-spur",
    progress: bool = True,
    verbose: bool = True,
) -> dict:
    """Run the stiffness-model benchmark and write ``bench_stiffness.json`` and
    ``speed_accuracy_stiffness.png`` into ``out_dir`` (atomically).

    Args:
        out_dir: output folder (created if missing).
        quick: reference m_n/8 and fe2d at m_n/2, m_n/4 only, 16 positions per pitch.
        case: embedded case name or TOML path.
        progress: tqdm progress bar. verbose: print the table.

    Returns:
        The JSON-ready dict that was written.
    """
    import jax

    jax.config.update("jax_enable_x64", True)  # entry point: float64
    from tqdm.auto import tqdm

    from jaxgear import FE2D, MeshModel, quasi_static, stiffness_table
    from jaxgear.io import atomic_open, load_case, stiffness_from_name

    c = load_case(case)
    pair, mn = c.pair, c.pair.normal_module
    ppp = 16 if quick else c.positions_per_pitch
    divisions = (2, 4) if quick else (2, 4, 6, 8)
    ref_div = 8 if quick else 16
    kw = {
        "youngs_modulus": c.youngs_modulus,
        "poisson_ratio": c.poisson_ratio,
        "line_load": c.nominal_line_load(),
    }
    configs = [
        ("iso6336", "iso6336", "weber", None),
        ("weber", "weber", "weber", None),
        ("weber+sainsot", "weber", "sainsot", None),
    ] + [(f"fe2d m_n/{d}", "fe2d", "weber", mn / d) for d in divisions]
    bar = tqdm(total=len(configs) + 3, desc="bench stiffness", disable=not progress, leave=False)

    def te_of(s, k) -> tuple[float, float]:
        mesh = MeshModel.from_pair(pair, s, k, c.slices)
        r = quasi_static(mesh, c.modifications, c.torque, positions_per_pitch=ppp)
        te = np.asarray(r.transmission_error, dtype=float)
        return float(te.mean()), float(np.ptp(te))

    with _fresh_cache():  # warm-up: imports, the first FE solve, the jit of quasi_static
        s0, k0 = stiffness_table(pair, FE2D(mn / 2), **kw)
        te_of(s0, k0)
    bar.update()
    with _fresh_cache():
        t = time.perf_counter()
        s_ref, k_ref = stiffness_table(pair, FE2D(mn / ref_div), **kw)
        ref_s = time.perf_counter() - t
    mean_ref, ptp_ref = te_of(s_ref, k_ref)
    bar.update()
    points = []
    for label, name, foundation, size in configs:
        model = stiffness_from_name(name, foundation=foundation, fe2d_size=size)
        if name == "fe2d":
            build = cached = np.inf
            for _ in range(2):  # min of two cold runs (fresh caches), each then from its cache
                with _fresh_cache():
                    t = time.perf_counter()
                    s, k = stiffness_table(pair, model, **kw)
                    build = min(build, time.perf_counter() - t)
                    t = time.perf_counter()
                    stiffness_table(pair, model, **kw)
                    cached = min(cached, time.perf_counter() - t)
        else:
            best = np.inf
            for _ in range(3):
                t = time.perf_counter()
                s, k = stiffness_table(pair, model, **kw)
                best = min(best, time.perf_counter() - t)
            build, cached = best, None
        mean, ptp = te_of(s, k)
        points.append(
            {
                "model": label,
                "stiffness": name,
                "foundation": foundation,
                "fe2d_size_m": size,
                "table_s": build,
                "table_cached_s": cached,
                "te_mean_m": mean,
                "te_ptp_m": ptp,
                "te_mean_error": abs(mean / mean_ref - 1),
                "te_ptp_error": abs(ptp / ptp_ref - 1),
            }
        )
        bar.update()
    out = {
        "case": c.name,
        "quick": bool(quick),
        "environment": environment(),
        "settings": {
            "slices": c.slices,
            "positions_per_pitch": ppp,
            "torque_Nm": c.torque,
            "contact": "exact",
            "timing": "stiffness_table only: min of 3 (analytic), min of 2 cold runs (fe2d, "
            "fresh caches), then the cached fe2d table (min of 2)",
        },
        "reference": {
            "model": f"fe2d m_n/{ref_div}",
            "table_s": ref_s,
            "te_mean_m": mean_ref,
            "te_ptp_m": ptp_ref,
        },
        "points": points,
    }
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "bench_stiffness.json"), "w") as f:
        json.dump(out, f, indent=2)
    _chart(out, os.path.join(out_dir, "speed_accuracy_stiffness.png"), atomic_open)
    bar.update()
    bar.close()
    if verbose:
        print(_table(out))
    return out


def _chart(out: dict, path: str, atomic_open) -> None:
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    floor = 1e-6
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for i, p in enumerate(out["points"]):
        col = f"C{i}"
        x = p["table_s"]
        ax.plot(x, max(p["te_mean_error"], floor), "o", color=col, label=p["model"])
        ax.plot(x, max(p["te_ptp_error"], floor), "s", color=col, mfc="none")
        if p["table_cached_s"] is not None:
            ax.plot(p["table_cached_s"], max(p["te_mean_error"], floor), "o", color=col, alpha=0.35)
    fe = [p for p in out["points"] if p["stiffness"] == "fe2d"]
    if fe:
        ax.plot(
            [p["table_s"] for p in fe],
            [max(p["te_mean_error"], floor) for p in fe],
            "-",
            color="grey",
            lw=0.7,
        )
        ax.plot(
            [p["table_s"] for p in fe],
            [max(p["te_ptp_error"], floor) for p in fe],
            "--",
            color="grey",
            lw=0.7,
        )
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("time to build the k(s) table (s); faint: fe2d from the cache")
    ax.set_ylabel(f"relative error vs {out['reference']['model']}: ● TE mean, □ TE peak-to-peak")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)
    env = out["environment"]
    ax.set_title(
        f"{out['case']}: stiffness models, speed vs accuracy "
        f"({env.get('cpu_count', '?')} CPU, {out['settings']['slices']} slices × "
        f"{out['settings']['positions_per_pitch']} positions)",
        fontsize=9,
    )
    fig.tight_layout()
    thin_tick_labels(fig)
    with atomic_open(path, "wb") as f:
        fig.savefig(f, format="png", dpi=120)
    plt.close(fig)


def _table(out: dict) -> str:
    r = out["reference"]
    lines = [
        (
            f"stiffness models on {out['case']}: reference {r['model']} (table {r['table_s']:.2f} s), "
            f"TE mean {r['te_mean_m'] * 1e6:.4f} µm, ptp {r['te_ptp_m'] * 1e6:.4f} µm"
        ),
        (
            f"{'model':18s}{'table s':>10s}{'cached s':>10s}{'TE mean µm':>12s}{'err %':>8s}"
            f"{'TE ptp µm':>11s}{'err %':>8s}"
        ),
    ]
    for p in out["points"]:
        cached = "" if p["table_cached_s"] is None else f"{p['table_cached_s']:.3f}"
        lines.append(
            f"{p['model']:18s}{p['table_s']:10.3f}{cached:>10s}{p['te_mean_m'] * 1e6:12.4f}"
            f"{p['te_mean_error'] * 100:8.2f}{p['te_ptp_m'] * 1e6:11.4f}"
            f"{p['te_ptp_error'] * 100:8.2f}"
        )
    return "\n".join(lines)
