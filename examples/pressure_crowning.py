"""Contact pressure across the face against lead crowning at speed, in the form of the seed's
Fig. IV-47: the power pair with its thin-webbed wheel condensed (hybrid scene, centrifugal load
at 3000 rad/s on the pinion), quasi-static, exact contact; for each crowning depth per member the
largest Hertzian pressure over a mesh period at each slice across the face
(:func:`jaxgear.contact_pressure`). The seed's IV-47 is drawn from its dynamic run at 3000 rad/s;
this one is quasi-static at that speed (the centrifugal load and the rim's growth included).

Writes docs/pressure_crowning.png and docs/pressure_crowning.json. Run from the repository root:
``python examples/pressure_crowning.py`` (about a minute on 2 cores once fem_prep has built the
wheel body).
"""

from __future__ import annotations

import dataclasses
import json
import pathlib

import jax

jax.config.update("jax_enable_x64", True)

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.dynamics import static_scene  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs"
SPEED = 3000.0  # pinion, rad/s
DEPTHS_UM = (0.0, 5.0, 10.0, 15.0, 20.0)


def pressure_across_face(case, scene, depth_um: float) -> tuple[np.ndarray, np.ndarray]:
    """(slice centres z (m), the largest pressure at each slice over a mesh period (Pa)) with
    lead crowning ``depth_um`` on both members."""
    m = case.modifications
    crowned = jg.Modifications(
        dataclasses.replace(m.pinion, crowning_depth=depth_um * 1e-6),
        dataclasses.replace(m.gear, crowning_depth=depth_um * 1e-6),
    )
    res = jg.quasi_static(
        scene, crowned, case.torque, speed=SPEED, positions_per_pitch=case.positions_per_pitch
    )
    p = jg.contact_pressure(case.pair, res, case.youngs_modulus, case.poisson_ratio)
    z = np.asarray(res.cell_z)[0, 0]
    return z, np.asarray(p.max_pressure).max(axis=(0, 1))


def main() -> dict:
    case = jio.load_case("power-helical-flexible")
    scene, _ = static_scene(case)
    out = {
        "case": case.name,
        "speed_rad_s": SPEED,
        "crowning_um": list(DEPTHS_UM),
        "pressure_Pa": [],
    }
    fig, ax = plt.subplots(figsize=(8, 4.6))
    for d in DEPTHS_UM:
        z, p = pressure_across_face(case, scene, d)
        out["z_m"] = z.tolist()
        out["pressure_Pa"].append(p.tolist())
        ax.plot(z * 1e3, p / 1e6, "o-", ms=3, label=f"crowning {d:g} µm")
    ax.set_xlabel("z across the face (mm); the wheel's cantilevered edge at the right")
    ax.set_ylabel("max Hertzian contact pressure (MPa)")
    ax.set_title(f"{case.name}: contact pressure across the face at {SPEED:g} rad/s (quasi-static)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(DOCS / "pressure_crowning.png", dpi=110)
    (DOCS / "pressure_crowning.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    res = main()
    for d, p in zip(res["crowning_um"], res["pressure_Pa"], strict=True):
        print(
            f"crowning {d:4.1f} µm: max {max(p) / 1e6:7.1f} MPa, edges {p[0] / 1e6:7.1f} / {p[-1] / 1e6:7.1f} MPa"
        )
