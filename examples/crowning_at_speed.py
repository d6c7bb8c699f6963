"""Maximum line load against lead crowning on the power pair with its flexible wheel, at rest and
at 3000 rad/s (pinion), with the gradient-based optimum at speed (seed IV-47/48).

Writes docs/bench/crowning_at_speed.png and docs/bench/crowning_at_speed.json. Run from the repository root:
``python examples/crowning_at_speed.py`` (the wheel is condensed once, about a minute, then read
from the fem_prep cache)."""

from __future__ import annotations

import json
import pathlib

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
import optimise  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.io import static_scene  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"


def main() -> dict:
    case = jio.load_case("power-helical-flexible")
    depths = np.arange(0.0, 20.01, 1.0)
    out = {"case": case.name, "crowning_depth_um": depths.tolist(), "speeds": {}}
    scene, _ = static_scene(case)
    for speed in (0.0, 3000.0):
        problem = jio.case_problem(
            case, "crowning.depth", "max_line_load", scene=scene, speed=speed, relief_blend=0.0
        )
        value = jax.jit(lambda x, p=problem: p.value(x, jg.ExactContact()) * p.scale)
        edge = jax.jit(
            lambda x, p=problem: jnp.max(
                jg.quasi_static(p.mesh, p.modifications(x), case.torque, speed=p.speed).line_load,
                axis=(0, 1),
            )
        )
        loads, edges = [], []
        for d in depths:
            x = jnp.asarray(problem.from_physical({"crowning.depth": d}))
            loads.append(float(value(x)))
            e = np.asarray(edge(x))
            edges.append([float(e[0]), float(e[-1])])
        res = optimise.minimise(problem, np.array([0.3]), progress=False)
        best = problem.to_physical(res.x)["crowning.depth"]
        out["speeds"][f"{speed:g}"] = {
            "max_line_load_N_per_m": loads,
            "edge_line_load_N_per_m": edges,
            "optimum_crowning_um": best,
            "optimum_max_line_load_N_per_m": float(value(jnp.asarray(res.x))),
        }
    (DOCS / "crowning_at_speed.json").write_text(json.dumps(out, indent=2))
    fig, ax = plt.subplots(figsize=(8, 4.8))
    for (label, d), col in zip(out["speeds"].items(), ("C0", "C3"), strict=True):
        name = "at rest" if label == "0" else f"{label} rad/s (pinion)"
        ax.plot(
            depths,
            np.asarray(d["max_line_load_N_per_m"]) / 1e3,
            "o-",
            color=col,
            label=f"max line load, {name}",
        )
        e = np.asarray(d["edge_line_load_N_per_m"]) / 1e3
        ax.plot(depths, e[:, 0], ":", color=col, label=f"load at the web-side edge, {name}")
        ax.plot(depths, e[:, 1], "--", color=col, label=f"load at the cantilevered edge, {name}")
        ax.plot(
            d["optimum_crowning_um"],
            d["optimum_max_line_load_N_per_m"] / 1e3,
            "*",
            ms=16,
            color=col,
            mec="k",
            label=f"gradient optimum {d['optimum_crowning_um']:.1f} µm, {name}",
        )
    ax.set_xlabel("lead crowning depth per member (µm)")
    ax.set_ylabel("line load (N/mm), exact contact")
    ax.set_title("power-helical-flexible: crowning against the centrifugal web deflection")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="upper center", ncol=2)
    ax.set_ylim(0, None)
    fig.tight_layout()
    fig.savefig(DOCS / "crowning_at_speed.png", dpi=120)
    return out


if __name__ == "__main__":
    o = main()
    for k, v in o["speeds"].items():
        print(k, "rad/s: optimum", round(v["optimum_crowning_um"], 2), "µm")
