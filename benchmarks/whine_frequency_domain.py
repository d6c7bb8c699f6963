"""Gear whine: the frequency-domain sweep against the time-domain sweep (docs/whine.md).

The relieved ``accessory-spur`` pair in its case's own lumped 3D scene (60 coordinates,
4 slices), over S speeds from 0.1 to 1.6 of the speed where order 1 meets its most excited
mode: :func:`jaxgear.dynamics.whine_response` (harmonic balance, H = 32 on 256 positions, and
the mean-stiffness model) against :func:`jaxgear.dynamics.speed_sweep` (Newmark, 256 steps per
mesh period, 60 periods with 4 kept, every speed from the static equilibrium, vmapped). Each
timed five times (the first call compiles; the best of the other four is reported: the host is shared, its timings vary several-fold); the orders
1-3 of the mesh force compared where Newmark keeps contact, by the frequency domain's
``nonlinearity`` indicator. Writes docs/bench/whine_frequency_domain.json and
docs/img/whine_orders.png. From the repository root: ``python -m benchmarks.whine_frequency_domain``.
"""

from __future__ import annotations

import os

# one BLAS thread: LAPACK's threads spin against the other processes of a shared 2-core host
# (the 130 × 130 complex solves of H = 32 ran 4-20 times slower with them, varying run to run)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
os.environ.setdefault("OMP_NUM_THREADS", "1")

import json
import math
import pathlib
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp
import numpy as np

import jaxgear.io as jio
from jaxgear.dynamics import (
    HarmonicBalance,
    Newmark,
    SteadyState,
    TransmissionErrorSource,
    excited_omega,
    speed_sweep,
    whine_response,
)

from ._timing import environment

ROOT = pathlib.Path(__file__).resolve().parents[1]
SPEEDS, ORDERS, STEPS, H, POSITIONS = 48, 3, 256, 32, 256


def model():
    return jio.build_dynamic_model(jio.load_case("accessory-spur"), slices=4)[0]


def timed(fn):
    out = []
    for _ in range(5):
        t = time.perf_counter()
        r = jax.block_until_ready(fn())
        out.append(time.perf_counter() - t)
    return r, out


def main():
    m = model()
    crit = float(excited_omega(m.modes)) * float(m.mesh.mesh_period_angle) / (2 * math.pi)
    speeds = np.linspace(0.1, 1.6, SPEEDS) * crit
    hb, t_hb = timed(lambda: whine_response(m, speeds, HarmonicBalance(H), positions=POSITIONS))
    ts, t_ts = timed(
        lambda: whine_response(m, speeds, TransmissionErrorSource(H), positions=POSITIONS)
    )
    td, t_td = timed(
        lambda: speed_sweep(
            m, jnp.asarray(speeds), integrator=Newmark(STEPS), window=SteadyState(60, 4)
        )
    )
    td = td.results
    t = np.asarray(td.time)  # (S, K)
    w = 2 * math.pi * speeds / float(m.mesh.mesh_period_angle)
    fm = np.asarray(td.mesh_force)
    orders = np.stack(
        [2 * np.mean(fm * np.exp(-1j * h * w[:, None] * t), axis=1) for h in range(ORDERS + 1)],
        axis=1,
    )  # (S, orders)
    in_contact = np.asarray(td.contact_loss) == 0.0
    f_hb = np.asarray(hb.mesh_force[:, : ORDERS + 1, 0])
    f_ts = np.asarray(ts.mesh_force[:, : ORDERS + 1, 0])
    amp = np.abs(np.abs(f_hb[:, 1:]) / np.abs(orders[:, 1:]) - 1)
    phase = np.abs(np.degrees(np.angle(f_hb[:, 1:] / orders[:, 1:])))
    amp_ts = np.abs(np.abs(f_ts[:, 1:]) / np.abs(orders[:, 1:]) - 1)
    nonlin = np.asarray(hb.nonlinearity[:, 0])
    ok = in_contact
    for i in range(SPEEDS):
        print(
            f"{speeds[i] / crit:.3f} nonlinearity {nonlin[i]:.2e} amp {amp[i].round(4)} "
            f"phase {phase[i].round(3)} loss td {not in_contact[i]} fd {bool(hb.contact_loss[i, 0])}"
        )
    classes = {}
    for lo, hi in ((0.0, 0.005), (0.005, 0.02), (0.02, 0.1), (0.1, np.inf)):
        sel = ok & (nonlin >= lo) & (nonlin < hi)
        if sel.any():
            classes[f"nonlinearity {lo}-{hi}"] = {
                "speeds": int(sel.sum()),
                "amplitude_rel_max": amp[sel].max(axis=0).tolist(),
                "phase_deg_max": phase[sel].max(axis=0).tolist(),
                "te_source_amplitude_rel_max": amp_ts[sel].max(axis=0).tolist(),
            }
    res = {
        "case": "accessory-spur, its lumped 3D scene (60 coordinates), 4 slices, its tip relief",
        "coordinates": int(m.scene.mass().shape[0]),
        "speeds": SPEEDS,
        "speed_range_rad_s": [float(speeds[0]), float(speeds[-1])],
        "critical_speed_rad_s": crit,
        "harmonic_balance": {"harmonics": H, "positions": POSITIONS, "seconds": t_hb},
        "te_source": {"harmonics": H, "positions": POSITIONS, "seconds": t_ts},
        "newmark_sweep": {"steps_per_period": STEPS, "periods": 60, "kept": 4, "seconds": t_td},
        "speedup_warm": min(t_td[1:]) / min(t_hb[1:]),
        "speeds_in_contact": int(ok.sum()),
        "flagged_contact_loss_frequency_domain": int(np.asarray(hb.contact_loss[:, 0]).sum()),
        "contact_loss_time_domain": int((~in_contact).sum()),
        "mesh_force_orders_1_3_vs_newmark_in_contact": {
            "harmonic_balance_amplitude_rel_max": amp[ok].max(axis=0).tolist(),
            "harmonic_balance_amplitude_rel_median": np.median(amp[ok], axis=0).tolist(),
            "harmonic_balance_phase_deg_max": phase[ok].max(axis=0).tolist(),
            "te_source_amplitude_rel_max": amp_ts[ok].max(axis=0).tolist(),
            "te_source_amplitude_rel_median": np.median(amp_ts[ok], axis=0).tolist(),
        },
        "by_nonlinearity": classes,
        "blas_threads": os.environ.get("OPENBLAS_NUM_THREADS"),
        "environment": environment(),
    }
    out = ROOT / "docs" / "bench" / "whine_frequency_domain.json"
    out.write_text(json.dumps(res, indent=2) + "\n")
    print(json.dumps({k: v for k, v in res.items() if k != "environment"}, indent=2))

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(8, 4.8))
    r = speeds / crit
    for h, c in zip(range(1, ORDERS + 1), ("C0", "C1", "C2"), strict=False):
        ax.semilogy(r, np.abs(f_hb[:, h]), "-", color=c, label=f"order {h}: harmonic balance")
        ax.semilogy(r, np.abs(f_ts[:, h]), ":", color=c, label=f"order {h}: TE source")
        ax.semilogy(r[ok], np.abs(orders[ok, h]), "o", ms=3, color=c, label=f"order {h}: Newmark")
        if (~ok).any():
            ax.semilogy(r[~ok], np.abs(orders[~ok, h]), "x", ms=4, color=c)
    ax.set_xlabel("pinion speed / speed where order 1 meets the most excited mode")
    ax.set_ylabel("dynamic mesh force amplitude (N)")
    ax.set_title("accessory-spur (lumped 3D): mesh-force orders, frequency vs time domain")
    ax.legend(fontsize=7, ncol=3)
    ax.grid(True, which="both", alpha=0.3)
    fig.tight_layout()
    fig.savefig(ROOT / "docs" / "img" / "whine_orders.png", dpi=120)


if __name__ == "__main__":
    main()
