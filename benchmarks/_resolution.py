"""Time step vs accuracy of the dynamic factor (docs/dynamics.md "Time step and accuracy").

The 1-DOF relative-approach model of the accessory spur pair (unmodified and with its tip
relief) at speeds from 0.05× to 3× the critical speed, Newmark with N_s = 16 … 2048 steps per
mesh period, against the continuous-time reference of ``_baseline_dynamics.py``
(solve_ivp DOP853, rtol 1e-10, segmented at every stiffness discontinuity and contact event).

Run from the repository root: ``python -m benchmarks._resolution [--out docs/...png]``.
"""

from __future__ import annotations

import argparse
import json
import math
import time
from pathlib import Path

import jax
import numpy as np

from jaxgear.dynamics import Newmark, SteadyState

from ._charts import thin_tick_labels

RATIOS = (0.05, 0.1, 0.2, 0.5, 1.0, 2.0, 3.0)
STEPS = (16, 32, 64, 128, 256, 512, 1024, 2048)


def _models(slices: int = 4):
    import jaxgear as jg
    import jaxgear.io as jio
    from jaxgear.dynamics import dynamic_model
    from jaxgear.scenes import TorsionalDynamics, disc_inertia

    case = jio.load_case("accessory-spur").replace(slices=slices)
    p = case.pair
    i1 = disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width)
    i2 = disc_inertia(case.density, p.tip_radii[1], p.gear.face_width)
    scene = TorsionalDynamics(case.mesh_model(), i1, i2).reduced()
    return {
        "unmodified": dynamic_model(scene, jg.Modifications(), case.torque),
        "tip relief 15 µm": dynamic_model(scene, case.modifications, case.torque),
    }


def run(periods: int = 60, keep: int = 2) -> dict:
    from jaxgear.dynamics import speed_sweep

    from ._baseline_dynamics import reference_response

    out = {}
    for name, model in _models().items():
        wc = float(model.critical_speeds(1)[0])
        speeds = np.array(RATIOS) * wc
        t0 = time.perf_counter()
        ref = [reference_response(model, s, periods=periods, keep_periods=keep) for s in speeds]
        t_ref = time.perf_counter() - t0
        rows = []
        for n in STEPS:
            t0 = time.perf_counter()
            r = speed_sweep(model, speeds, integrator=Newmark(n), window=SteadyState(periods, keep))
            df = np.asarray(r.results.dynamic_factor)
            rows.append(
                {
                    "steps_per_period": n,
                    "steps_per_mode_period": np.asarray(r.results.steps_per_mode_period).tolist(),
                    "dynamic_factor": df.tolist(),
                    "time_s": time.perf_counter() - t0,
                }
            )
        out[name] = {
            "critical_speed": wc,
            "ratios": list(RATIOS),
            "reference": [x["dynamic_factor"] for x in ref],
            "reference_periodicity": [x["periodicity"] for x in ref],
            "reference_time_s": t_ref,
            "runs": rows,
        }
        print(name, json.dumps(out[name]["reference"]), flush=True)
    return out


def plot(data: dict, path: Path):
    import matplotlib

    from jaxgear.dynamics import STEPS_PER_MODE as rule, UNDER_RESOLVED_STEPS as flag

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    colors = plt.cm.viridis(np.linspace(0, 0.9, len(RATIOS)))
    for ax, (name, d) in zip(axes, data.items(), strict=False):
        ref = np.array(d["reference"])
        for i, (ratio, c) in enumerate(zip(d["ratios"], colors, strict=True)):
            x = [row["steps_per_mode_period"][i] for row in d["runs"]]
            err = [abs(row["dynamic_factor"][i] / ref[i] - 1) * 100 for row in d["runs"]]
            ax.loglog(x, np.maximum(err, 1e-3), "o-", color=c, ms=3.5, label=f"{ratio:g}× Ω_c")
            coarse = [row["steps_per_period"] < 64 for row in d["runs"]]
            xc = [v for v, q in zip(x, coarse, strict=True) if q]
            ec = [max(v, 1e-3) for v, q in zip(err, coarse, strict=True) if q]
            ax.loglog(xc, ec, "o", mfc="white", color=c, ms=5)
        ax.axhline(1.0, color="k", lw=0.8, ls="--")
        ax.axvline(rule, color="tab:red", lw=0.8, ls=":")
        ax.axvline(flag, color="tab:orange", lw=0.8, ls=":")
        ax.set_title(f"accessory spur, 1-DOF, {name}")
        ax.set_xlabel("steps per period of the highest excited mode  N_s·f_mesh/f_max")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_ylabel("|dynamic factor error| vs continuous reference (%)")
    axes[0].text(0.9, 2e-3, "open: N_s < 64 per mesh period", fontsize=8)
    axes[0].legend(fontsize=8, title="speed", title_fontsize=8)
    axes[1].text(rule * 1.05, 2e-3, f"default ≥ {rule}", color="tab:red", fontsize=8)
    axes[1].text(flag * 0.97, 2e-3, f"flag < {flag}", color="tab:orange", fontsize=8, ha="right")
    fig.tight_layout()
    thin_tick_labels(fig)
    fig.savefig(path, dpi=110)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", default="docs/bench/dynamics_resolution.png")
    ap.add_argument("--json", default=None, help="write (or, if it exists, read) the data here")
    ap.add_argument("--periods", type=int, default=60)
    args = ap.parse_args(argv)
    jax.config.update("jax_enable_x64", True)
    if args.json and Path(args.json).exists():
        data = json.loads(Path(args.json).read_text())
    else:
        data = run(args.periods)
        if args.json:
            Path(args.json).write_text(json.dumps(data, indent=1))
    plot(data, Path(args.out))
    for name, d in data.items():
        print(name, "Ω_c =", round(d["critical_speed"], 1), "rad/s")
        for i, ratio in enumerate(d["ratios"]):
            errs = " ".join(
                f"{row['steps_per_mode_period'][i]:7.1f}:{(row['dynamic_factor'][i] / d['reference'][i] - 1) * 100:+6.2f}%"
                for row in d["runs"]
            )
            print(f"  {ratio:5.2f}× ref {d['reference'][i]:.4f}  {errs}")
    return 0 if all(math.isfinite(x) for d in data.values() for x in d["reference"]) else 1


if __name__ == "__main__":
    raise SystemExit(main())
