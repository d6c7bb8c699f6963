"""Contact pressure across the face against lead crowning at speed, in the form of the seed's
Fig. IV-47: the power pair with its thin-webbed wheel condensed (hybrid scene, centrifugal load
at 3000 rad/s on the pinion), quasi-static, exact contact; for each crowning depth per member the
largest Hertzian pressure over a mesh period at each slice across the face
(:func:`jaxgear.contact_pressure`), quasi-static at that speed (the centrifugal load and the
rim's growth included) and, as the seed draws IV-47, dynamic: the hybrid model integrated at
3000 rad/s (the case's ``[scene]``: Newmark, its damping and window), the pressure the largest
over the kept steps (cell loads recorded, :func:`jaxgear.dynamics.simulate`).

Writes docs/bench/pressure_crowning.png and docs/bench/pressure_crowning.json. Run from the repository root:
``python examples/pressure_crowning.py`` (a few minutes on 2 cores once fem_prep has built the
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
from jaxgear.dynamics import Outputs, simulate  # noqa: E402
from jaxgear.io import (  # noqa: E402
    build_dynamic_model,
    load_bodies,
    spec_integrator,
    spec_window,
    static_scene,
)

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
SPEED = 3000.0  # pinion, rad/s
DEPTHS_UM = (0.0, 5.0, 10.0, 15.0, 20.0)


def crowned(case, depth_um: float) -> jg.Modifications:
    """The case's modifications with lead crowning ``depth_um`` on both members."""
    m = case.modifications
    return jg.Modifications(
        dataclasses.replace(m.pinion, crowning_depth=depth_um * 1e-6),
        dataclasses.replace(m.gear, crowning_depth=depth_um * 1e-6),
    )


def pressure_across_face(case, scene, depth_um: float) -> tuple[np.ndarray, np.ndarray]:
    """(slice centres z (m), the largest pressure at each slice over a mesh period (Pa)) with
    lead crowning ``depth_um`` on both members, quasi-static at ``SPEED``."""
    res = jg.quasi_static(
        scene,
        crowned(case, depth_um),
        case.torque,
        speed=SPEED,
        positions_per_pitch=case.positions_per_pitch,
    )
    p = jg.contact_pressure(case.pair, res, case.youngs_modulus, case.poisson_ratio)
    z = np.asarray(res.cell_z)[0, 0]
    return z, np.asarray(p.max_pressure).max(axis=(0, 1))


def dynamic_pressure_across_face(case, bodies, depth_um: float) -> tuple[np.ndarray, float]:
    """(the largest pressure at each slice over the kept steps of the dynamic run at ``SPEED``
    (Pa), the run's dynamic factor) with lead crowning ``depth_um`` on both members."""
    spec = case.scene
    model, spec = build_dynamic_model(
        case.replace(modifications=crowned(case, depth_um)), spec, bodies=bodies
    )
    one = simulate(
        model,
        SPEED,
        integrator=spec_integrator(spec),
        contact=case.contact_law(spec.contact),
        window=spec_window(spec),
        outputs=Outputs(cell_loads=True),
    )
    m = one.meshes[0]
    p = jg.contact_pressure(case.pair, m, case.youngs_modulus, case.poisson_ratio)
    return np.asarray(p.max_pressure).max(axis=(0, 1)), float(np.max(m.dynamic_factor))


def main() -> dict:
    case = jio.load_case("power-helical-flexible")
    scene, _ = static_scene(case)
    out = {
        "case": case.name,
        "speed_rad_s": SPEED,
        "crowning_um": list(DEPTHS_UM),
        "pressure_Pa": [],
        "pressure_dynamic_Pa": [],
        "dynamic_factor": [],
    }
    bodies = load_bodies(case.scene)
    fig, axes = plt.subplots(1, 2, figsize=(13, 4.6), sharey=True)
    for k, d in enumerate(DEPTHS_UM):
        z, p = pressure_across_face(case, scene, d)
        pd, df = dynamic_pressure_across_face(case, bodies, d)
        print(
            f"crowning {d:g} um: quasi-static {p.max() / 1e6:.0f} MPa, dynamic "
            f"{pd.max() / 1e6:.0f} MPa (K_v {df:.3f})",
            flush=True,
        )
        out["z_m"] = z.tolist()
        out["pressure_Pa"].append(p.tolist())
        out["pressure_dynamic_Pa"].append(pd.tolist())
        out["dynamic_factor"].append(df)
        axes[0].plot(z * 1e3, p / 1e6, "o-", ms=3, color=f"C{k}", label=f"crowning {d:g} µm")
        axes[1].plot(
            z * 1e3, pd / 1e6, "o-", ms=3, color=f"C{k}", label=f"crowning {d:g} µm (K_v {df:.2f})"
        )
    axes[0].set_title(f"quasi-static at {SPEED:g} rad/s")
    axes[1].set_title(f"dynamic at {SPEED:g} rad/s (max over the kept steps)")
    axes[0].set_ylabel("max Hertzian contact pressure (MPa)")
    for ax in axes:
        ax.set_xlabel("z across the face (mm); the wheel's cantilevered edge at the right")
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(f"{case.name}: contact pressure across the face against lead crowning")
    fig.tight_layout()
    fig.savefig(DOCS / "pressure_crowning.png", dpi=110)
    (DOCS / "pressure_crowning.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    res = main()
    for d, p, pd in zip(
        res["crowning_um"], res["pressure_Pa"], res["pressure_dynamic_Pa"], strict=True
    ):
        print(
            f"crowning {d:4.1f} µm: quasi-static max {max(p) / 1e6:7.1f} MPa, edges "
            f"{p[0] / 1e6:7.1f} / {p[-1] / 1e6:7.1f} MPa; dynamic max {max(pd) / 1e6:7.1f} MPa, "
            f"edges {pd[0] / 1e6:7.1f} / {pd[-1] / 1e6:7.1f} MPa"
        )
