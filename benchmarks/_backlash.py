"""The backlash evidence (docs/backlash.md): the gear pair shared by the tests and the figure,
and docs/bench/backlash.{png,json}: RMS DTE against speed, up and down sweeps, jaxgear (Newmark with the
coast flanks) against the independent reference (benchmarks/_backlash_reference.py), regimes
marked. Run: ``python -m benchmarks._backlash`` (float64; about a minute on a CPU)."""

from __future__ import annotations

import math
from pathlib import Path

import jax
import numpy as np

import jaxgear as jg
from jaxgear.dynamics import Both, Newmark, SteadyState, dynamic_model, speed_sweep
from jaxgear.io import Damping, write_json
from jaxgear.scenes import TorsionalDynamics

from ._backlash_reference import dead_zone_pair, sweep

# a spur pair, a flat stiffness per unit length (k(s) constant: the mesh stiffness steps
# between one and two pairs), thin teeth (A_sn = −1.5 µm each: j_bn = 2.82 µm), light load
Z1, Z2, MODULE, ALPHA, WIDTH = 30, 45, 3e-3, math.radians(20.0), 0.02
ALLOWANCE, TORQUE, ZETA, K_LENGTH = -1.5e-6, 60.0, 0.1, 1.2e10
INERTIAS = tuple(
    7800 * math.pi * WIDTH * r**4 / 2 for r in (Z1 * MODULE / 2 + MODULE, Z2 * MODULE / 2 + MODULE)
)
WINDOW = SteadyState(100, 8)
STEPS = Newmark(256)  # one speed: within 1 % of the reference in every regime
# the sweeps: the down sweep's jump off the double-sided branch sits within one speed step of
# the reference only from ~1024 steps per period (at 256 it falls one step, 2.5 %, early)
SWEEP_STEPS = Newmark(1024)
# the three regimes at fractions of the linear resonance Ω_n = ω_n / z1 (ω_n² = ε_α k_1 / m)
REGIMES = {"no impact": 0.7, "single-sided": 1.0, "double-sided": 0.85}


def reference():
    p0 = dead_zone_pair(
        Z1, Z2, MODULE, ALPHA, (ALLOWANCE,) * 2, WIDTH, K_LENGTH, TORQUE, INERTIAS, 0.0
    )
    wn = math.sqrt(p0.pair_stiffness * p0.contact_ratio / p0.mass)
    alpha = 2 * ZETA * wn
    return (
        dead_zone_pair(
            Z1, Z2, MODULE, ALPHA, (ALLOWANCE,) * 2, WIDTH, K_LENGTH, TORQUE, INERTIAS, alpha
        ),
        wn / Z1,
        alpha,
    )


def jaxgear_model(alpha, torsional=False):
    pair = jg.GearPair(
        jg.Member(Z1, face_width=WIDTH, tooth_thickness_allowance=ALLOWANCE),
        jg.Member(Z2, face_width=WIDTH, tooth_thickness_allowance=ALLOWANCE),
        MODULE,
        ALPHA,
    )
    s = np.linspace(0.0, pair.path_of_contact, 3)
    mesh = jg.MeshModel.from_pair(pair, s, np.full(3, K_LENGTH), 1, coast=True)
    torsion = TorsionalDynamics(mesh, *INERTIAS)
    scene = torsion if torsional else torsion.reduced()
    return dynamic_model(scene, None, TORQUE, Damping("rayleigh", alpha=alpha, beta=0.0))


SWEEP = np.linspace(0.6, 1.3, 29)


def regime(coast_share, loss):
    return "double-sided" if coast_share > 0 else ("single-sided" if loss > 0 else "no impact")


def main(out: Path = Path("docs/bench")) -> dict:
    p, speed_n, alpha = reference()
    model = jaxgear_model(alpha)
    speeds = SWEEP * speed_n
    res = speed_sweep(model, speeds, integrator=SWEEP_STEPS, window=WINDOW, direction=Both())
    x0 = [p.force / (p.pair_stiffness * p.contact_ratio), 0.0]
    ref = {"up": sweep(p, speeds, x0, 100, 8), "down": sweep(p, speeds[::-1], x0, 100, 8)[::-1]}
    data = {
        "speed_ratio": SWEEP.tolist(),
        "speed_rad_s": speeds.tolist(),
        "backlash_normal_m": p.backlash,
        "static_te_m": p.force / (p.pair_stiffness * p.contact_ratio),
    }
    for name, got in (("up", res.results), ("down", res.down)):
        r = ref[name]
        data[name] = {
            "jaxgear_te_rms_m": np.asarray(got.te_rms).tolist(),
            "reference_te_rms_m": [x["te_rms"] for x in r],
            "jaxgear_coast_share": np.asarray(got.coast_share).tolist(),
            "jaxgear_contact_loss": np.asarray(got.contact_loss).tolist(),
            "jaxgear_impacts": [
                np.asarray(got.impacts_drive).tolist(),
                np.asarray(got.impacts_coast).tolist(),
            ],
            "reference_impacts": [x["impacts"] for x in r],
            "regime": [
                regime(c, l)
                for c, l in zip(
                    np.asarray(got.coast_share), np.asarray(got.contact_loss), strict=True
                )
            ],
        }
        rel = np.abs(
            np.array(data[name]["jaxgear_te_rms_m"]) / np.array(data[name]["reference_te_rms_m"])
            - 1
        )
        data[name]["max_relative_difference"] = float(rel.max())
    write_json(out / "backlash.json", data)
    _plot(data, out / "backlash.png")
    return data


def _plot(data, path):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {"no impact": "#dddddd", "single-sided": "#ffe0a0", "double-sided": "#f4a0a0"}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True)
    x = np.array(data["speed_ratio"])
    for ax, name in zip(axes, ("up", "down"), strict=True):
        d = data[name]
        for i, reg in enumerate(d["regime"]):
            lo = x[i] - 0.5 * (x[1] - x[0])
            ax.axvspan(lo, lo + (x[1] - x[0]), color=colours[reg], lw=0)
        ax.plot(
            x, np.array(d["reference_te_rms_m"]) * 1e6, "k-", lw=2, label="reference (solve_ivp)"
        )
        ax.plot(
            x,
            np.array(d["jaxgear_te_rms_m"]) * 1e6,
            "o",
            ms=4,
            color="C0",
            label="jaxgear (Newmark, 1024 steps/period)",
        )
        ax.set_title(f"{name} sweep (max difference {100 * d['max_relative_difference']:.2f} %)")
        ax.set_xlabel("mesh frequency / linear natural frequency")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("RMS DTE (µm)")
    handles = [plt.Rectangle((0, 0), 1, 1, color=c) for c in colours.values()]
    h, l = axes[0].get_legend_handles_labels()
    axes[1].legend(h + handles, l + list(colours), fontsize=8, loc="upper right")
    fig.suptitle(
        f"1-DOF spur pair with backlash j_bn = {data['backlash_normal_m'] * 1e6:.2f} µm: "
        "no-impact, single- and double-sided regimes"
    )
    fig.tight_layout()
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=120)
    plt.close(fig)
    tmp.replace(path)


if __name__ == "__main__":
    jax.config.update("jax_enable_x64", True)
    main()
