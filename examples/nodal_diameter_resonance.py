"""Nodal-diameter resonances of a thin web in a speed sweep of the hybrid model (seed (3.9),
Tab. III-11): the wheel's 2-nodal-diameter modes predicted from the modal analysis of the
assembled structure, and found again in the rim response of the time integration.

The small helical test pair (tests/data/hybrid-test-helical.toml: 20/30 teeth, β = 10°, the wheel
a 3 mm web; its axial mesh force excites the out-of-plane modes). In the wheel's frame the mesh
runs round the rim against the rotation: its first harmonic drives diameter n at the orders
Z + n (a backward wave) and Z − n (forward) of the wheel's rotation frequency. Light Rayleigh
damping (α = 0, β = 5e-7 s: ξ ≈ 1 % at 7 kHz) separates the two peaks.

Writes docs/bench/nd_resonance.png and docs/bench/nd_resonance.json. Run from the repository root:
``python examples/nodal_diameter_resonance.py`` (about a minute)."""

from __future__ import annotations

import json
import pathlib

import jax

jax.config.update("jax_enable_x64", True)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import fem_prep  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.dynamics import (
    Newmark,
    SteadyState,
    dynamic_model,
    mesh_averaged_modes,
    nodal_diameter_modes,
    nodal_diameter_resonances,
    rim_waves,
    speed_sweep,
)
from jaxgear.io import Damping, static_scene

ROOT = pathlib.Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"
SPEEDS = np.arange(1850.0, 2450.1, 25.0)  # pinion, rad/s
SPP, PERIODS, KEEP = 32, 60, 30  # KEEP = one wheel turn: orders fall on integer bins
RAYLEIGH = (0.0, 5e-7)


def compute(speeds=SPEEDS, n=2) -> dict:
    case = jio.load_case(DATA / "hybrid-test-helical.toml")
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    scene = static_scene(case, bodies=(None, body))[0]
    z1, z2 = case.pair.pinion.teeth, case.pair.gear.teeth
    damping = Damping("rayleigh", alpha=RAYLEIGH[0], beta=RAYLEIGH[1])
    model = dynamic_model(scene, case.modifications, case.torque, damping)
    modes = nodal_diameter_modes(
        scene, mesh_averaged_modes(model, positions_per_pitch=SPP), n_modes=30
    )
    web = (modes["rim_share"] > 0.5) & (modes["nodal_diameter"] == n)
    predicted = nodal_diameter_resonances(
        modes["frequency_hz"][web], modes["nodal_diameter"][web], z2, z1
    )
    sw = speed_sweep(
        model, speeds, integrator=Newmark(SPP), window=SteadyState(PERIODS, KEEP)
    ).results
    out = {"backward": [], "forward": []}
    for i, s in enumerate(speeds):
        f_wheel = s * z1 / z2 / (2 * np.pi)
        for name, order in (("backward", z2 + n), ("forward", z2 - n)):
            band = ((order - 0.5) * f_wheel, (order + 0.5) * f_wheel)
            w = rim_waves(np.asarray(sw.rim_axial[i]), float(sw.time_step[i]), -1.0, band)
            out[name].append(
                {
                    "amplitude_m": float(w["amplitude"][n]),
                    "frequency_hz": float(w["frequency_hz"][n]),
                    "direction": int(w["direction"][n]),
                }
            )
    return {
        "case": case.name,
        "nodal_diameter": n,
        "wheel_teeth": z2,
        "pinion_teeth": z1,
        "rayleigh": list(RAYLEIGH),
        "steps_per_period": SPP,
        "periods": PERIODS,
        "keep_periods": KEEP,
        "speeds_rad_s": [float(s) for s in speeds],
        "dynamic_factor": np.asarray(sw.dynamic_factor).tolist(),
        "result": np.asarray(sw.result).tolist(),
        "modes_hz": modes["frequency_hz"][web].tolist(),
        "predicted": predicted,
        "response": out,
    }


def plot(res: dict, path) -> None:
    sp = np.asarray(res["speeds_rad_s"])
    fig, (ax, bx) = plt.subplots(2, 1, figsize=(7.5, 6.5), sharex=True)
    n = res["nodal_diameter"]
    z2 = res["wheel_teeth"]
    for name, color, order in (("backward", "C0", z2 + n), ("forward", "C3", z2 - n)):
        a = np.array([r["amplitude_m"] for r in res["response"][name]]) * 1e6
        ax.plot(
            sp,
            a,
            "o-",
            color=color,
            ms=3.5,
            label=f"{name} wave, order Z{'+' if name == 'backward' else '−'}{n} = {order}",
        )
        pred = [p["pinion_speed_rad_s"] for p in res["predicted"] if p["direction"] == name]
        for k, x in enumerate(pred):
            ax.axvline(
                x,
                color=color,
                ls="--",
                lw=0.9,
                label=f"(3.9) {name}, modes {', '.join(f'{f:.0f}' for f in res['modes_hz'])} Hz"
                if k == 0
                else None,
            )
    ax.set_ylabel(f"{n}-nodal-diameter axial rim amplitude (µm)")
    ax.set_title(
        f"{res['case']}: web ND resonances in a hybrid speed sweep (seed (3.9), Tab. III-11)",
        fontsize=9.5,
    )
    ax.legend(fontsize=7.5)
    ax.grid(alpha=0.3)
    bx.plot(sp, res["dynamic_factor"], "k.-")
    bx.set_xlabel("pinion speed (rad/s)")
    bx.set_ylabel("dynamic factor")
    bx.grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(path, dpi=130)
    plt.close(fig)


def main() -> dict:
    res = compute()
    docs = ROOT / "docs" / "bench"
    (docs / "nd_resonance.json").write_text(json.dumps(res, indent=1) + "\n")
    plot(res, docs / "nd_resonance.png")
    return res


if __name__ == "__main__":
    r = main()
    for name in ("backward", "forward"):
        a = [x["amplitude_m"] for x in r["response"][name]]
        k = int(np.argmax(a))
        print(
            name,
            "peak at",
            r["speeds_rad_s"][k],
            "rad/s,",
            f"{a[k] * 1e6:.2f} µm,",
            r["response"][name][k]["frequency_hz"],
            "Hz, direction",
            r["response"][name][k]["direction"],
        )
    print("predicted", [(p["direction"], round(p["pinion_speed_rad_s"])) for p in r["predicted"]])
