"""The housing's evidence (docs/fem_prep.md, "Housing"), measured:

1. Leissa's simply supported plate (0.3 m x 0.2 m x 4 mm steel) meshed by the housing's
   structured mesher, Tet10, 6 x 4, 12 x 8 and 24 x 16 cells: the first five frequencies and
   their errors.
2. The box housing of tests/test_housing.py (0.3 x 0.2 x 0.2 m, 8 mm walls, three bores, four
   feet; 50 mm cells, Tet10): the seats' receptance of the Craig–Bampton housing against the full
   FE model's, relative Frobenius error per frequency from 50 Hz to 3 kHz, undamped and with a
   structural loss factor of 0.03 (every other frequency), for the cut-off of the rule
   with a highest mesh frequency of 2 kHz (3 kHz) and twice it (6 kHz); the free-seat
   frequencies' errors; the wall and CPU time of the condensation.

Writes docs/bench/bench_housing_evidence.json and docs/img/housing_receptance.png. From the
repository root: ``python -m benchmarks.housing_evidence``.
"""

from __future__ import annotations

import json
import math
import pathlib
import time

import numpy as np

import fem_prep
from fem_prep.housing import Bore, Foot, HousingBox, mesh_box, mesh_plate, prepare_housing

ROOT = pathlib.Path(__file__).resolve().parents[1]
STEEL = fem_prep.Material(210e9, 0.3, 7800.0)
ETA = 0.03  # a structural loss factor of the order of a bolted cast housing's


def plate() -> dict:
    a, b, h = 0.3, 0.2, 0.004
    D = STEEL.youngs_modulus * h**3 / (12 * (1 - STEEL.poisson_ratio**2))
    ref = np.sort(
        [
            math.pi / 2 * (m * m / a**2 + k * k / b**2) * math.sqrt(D / (STEEL.density * h))
            for m in range(1, 6)
            for k in range(1, 6)
        ]
    )[:5]
    rows = []
    for nx, ny in ((6, 4), (12, 8), (24, 16)):
        hm = mesh_plate(a, b, h, (nx, ny))
        ops = fem_prep.assemble_operators(hm.basis, STEEL)
        x = hm.nodes
        edge = (
            np.isclose(x[:, 0], 0)
            | np.isclose(x[:, 0], a)
            | np.isclose(x[:, 1], 0)
            | np.isclose(x[:, 1], b)
        )
        keep = np.ones(hm.n_dofs, bool)
        keep[3 * np.nonzero(edge)[0] + 2] = False
        lam, _ = fem_prep.shift_invert_modes(
            ops.K[keep][:, keep], ops.M[keep][:, keep], 8, sigma=-1e4
        )
        f = np.sqrt(lam[lam > 1e2][:5]) / (2 * math.pi)
        rows.append(
            {
                "cells": [nx, ny],
                "dofs": int(hm.n_dofs),
                "f_hz": f.tolist(),
                "error": (f / ref - 1).tolist(),
            }
        )
    return {"leissa_hz": ref.tolist(), "meshes": rows}


def evidence_box():
    """The evidence's steel box (0.3 × 0.2 × 0.2 m, 8 mm walls, three bores, four feet)."""
    return HousingBox(
        0.3,
        0.2,
        0.2,
        0.008,
        bores=(
            Bore("y-", (0.1, 0.12), 0.03),
            Bore("y+", (0.1, 0.12), 0.03),
            Bore("y-", (0.21, 0.12), 0.025),
        ),
        feet=(
            Foot((0.0, 0.05), (0.0, 0.05)),
            Foot((0.25, 0.3), (0.0, 0.05)),
            Foot((0.0, 0.05), (0.15, 0.2)),
            Foot((0.25, 0.3), (0.15, 0.2)),
        ),
    )


def housing() -> dict:
    box = evidence_box()
    hm = mesh_box(box, 0.05)
    out = {"dofs": int(hm.n_dofs), "cutoffs": [], "loss_factor": ETA}
    ref = None
    for fc in (3000.0, 6000.0):
        t0, c0 = time.perf_counter(), time.process_time()
        p = prepare_housing(hm, STEEL, cutoff_hz=fc)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        if ref is None:
            f = np.linspace(50.0, fc, 60)
            ff, _ = p.full_modes(12)
            Hf = p.full_receptance(f)
            Hd = p.full_receptance(f[::2], loss_factor=ETA)
            ref = (f, ff, Hf, Hd)
        f, ff, Hf, Hd = ref
        ch = p.condensed_housing()
        Hc = ch.receptance(f)
        err = np.linalg.norm(Hc - Hf, axis=(1, 2)) / np.linalg.norm(Hf, axis=(1, 2))
        Hcd = ch.receptance(f[::2], loss_factor=ETA)
        err_d = np.linalg.norm(Hcd - Hd, axis=(1, 2)) / np.linalg.norm(Hd, axis=(1, 2))
        fcm = ch.modes(12)[0]
        out["cutoffs"].append(
            {
                "cutoff_hz": fc,
                "interior_modes": int(p.condensed.n_modes),
                "prepare_wall_s": wall,
                "prepare_cpu_s": cpu,
                "f_hz": f.tolist(),
                "receptance_error": err.tolist(),
                "receptance_error_damped": err_d.tolist(),
                "free_seat_full_hz": ff.tolist(),
                "free_seat_condensed_hz": fcm.tolist(),
            }
        )
    return out


def main() -> None:
    res = {"plate": plate(), "housing": housing()}
    (ROOT / "docs" / "bench" / "bench_housing_evidence.json").write_text(
        json.dumps(res, indent=1) + "\n"
    )
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(1, 2, figsize=(10, 3.6))
    for r in res["plate"]["meshes"]:
        ax[0].plot(
            range(1, 6),
            100 * np.array(r["error"]),
            "o-",
            label=f"{r['cells'][0]} x {r['cells'][1]} cells ({r['dofs']} DOFs)",
        )
    ax[0].axhline(1, color="grey", lw=0.5)
    ax[0].set(
        xlabel="mode",
        ylabel="error vs Leissa (%)",
        yscale="symlog",
        title="SS plate, structured Tet10 mesher",
    )
    ax[0].legend(fontsize=7)
    full = res["housing"]["cutoffs"][0]["free_seat_full_hz"]
    for c in res["housing"]["cutoffs"]:
        (line,) = ax[1].semilogy(
            c["f_hz"],
            100 * np.array(c["receptance_error"]),
            label=f"cut-off {c['cutoff_hz']:.0f} Hz ({c['interior_modes']} modes), undamped",
        )
        ax[1].semilogy(
            c["f_hz"][::2],
            100 * np.array(c["receptance_error_damped"]),
            "--",
            color=line.get_color(),
            label=f"same, loss factor {ETA}",
        )
    for f in full:
        if f < 3000:
            ax[1].axvline(f, color="grey", lw=0.4)
    ax[1].axhline(1, color="k", lw=0.5)
    ax[1].set(
        xlabel="frequency (Hz)",
        ylabel="receptance error (%)",
        title="box housing at its seats: CB vs full FE",
    )
    ax[1].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "img" / "housing_receptance.png", dpi=110)
    print(
        json.dumps(
            {
                "plate_finest_error": res["plate"]["meshes"][-1]["error"],
                "cutoffs": [
                    (c["cutoff_hz"], c["interior_modes"], round(c["prepare_wall_s"], 2))
                    for c in res["housing"]["cutoffs"]
                ],
            }
        )
    )


if __name__ == "__main__":
    main()
