"""The seed's Fig. IV-8 as percentile bands: the dynamic factor against speed of the accessory spur
pair for an aeronautical accuracy grade (ISO 1328-1 class 4) and a lower one (class 8), with and
without the case's tip relief (15 µm, Γ = 0.25, linear), over sampled deviations
(docs/robust.md, "Fig. IV-8 as percentile bands").

Model: the torsional pair on solid-disc inertias (Weber stiffness, 8 slices), composite damping;
the pinion's deviations drawn for the class (pitch, runout, profile, helix; the gear perfect, so
that one pinion revolution, the span of each run, is their exact period), Newmark 32 steps per
mesh period, 10 transient periods then one revolution kept, exact contact; realisation i from
``jax.random.fold_in(jax.random.key(SEED), i)`` (common to every speed, class and design). Writes
docs/bench/robust_iv8.png and docs/bench/robust_iv8.json. Run from the repository root:
``python examples/robust_iv8.py`` (a few minutes on 2 cores)."""

from __future__ import annotations

import dataclasses
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
import jaxgear.dynamics as jd  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.scenes import TorsionalDynamics  # noqa: E402
from jaxgear.scenes import disc_inertia  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
GRADES = (4, 8)
SAMPLES = 48
SEED = 0
SPEED_RANGE = (0.4, 1.6, 25)  # × the critical speed of the unmodified pair (first mesh order)
STEPS, TRANSIENT = 32, 10
SLICES = 8


def setup():
    """The case, the torsional scene and the critical speed (rad/s) of the unmodified pair."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=SLICES)
    p = case.pair
    inertia = [
        disc_inertia(case.density, r, m.face_width)
        for r, m in zip(p.tip_radii, (p.pinion, p.gear), strict=True)
    ]
    scene = TorsionalDynamics(mesh, *inertia)
    crit = float(jd.dynamic_model(scene, None, case.torque).critical_speeds()[-1])
    return case, scene, crit


def problem(case, scene, relief: bool, speeds):
    """The DynamicMetrics of the pair with (or without) the case's tip relief at ``speeds``."""
    mods = case.modifications if relief else jg.Modifications()
    model = jd.dynamic_model(scene, mods, case.torque)
    z1 = case.pair.pinion.teeth
    model = dataclasses.replace(model, deviation_span=z1)
    window = jd.SteadyState(TRANSIENT + z1, z1)
    return jd.DynamicMetrics(model, jnp.asarray(speeds), jd.Newmark(STEPS), window)


def sampler(case, grade):
    return jg.DeviationSampler.for_grade(case.pair, grade, members=("pinion",))


def run(case, scene, grade, relief, speeds, samples=SAMPLES):
    """Dynamic factors (samples, speeds) and result codes."""
    out = jg.robust_samples(
        problem(case, scene, relief, speeds),
        sampler(case, grade),
        jax.random.key(SEED),
        samples,
        batch_size=4,
    )
    return out.dynamic_factor, out.result


def perfect(case, scene, relief, speeds):
    """The dynamic factor of the perfect gears (mesh-periodic: 30 periods, 4 kept)."""
    mods = case.modifications if relief else jg.Modifications()
    model = jd.dynamic_model(scene, mods, case.torque)
    r = jd.speed_sweep(
        model, jnp.asarray(speeds), integrator=jd.Newmark(STEPS), window=jd.SteadyState(30, 4)
    )
    return np.asarray(r.results.dynamic_factor)


def main():
    case, scene, crit = setup()
    speeds = crit * np.linspace(*SPEED_RANGE)
    data = {
        "what": "dynamic factor against pinion speed over sampled ISO 1328-1 deviations of the "
        "pinion, accessory spur pair (torsional, Weber 8 slices), docs/robust.md",
        "samples": SAMPLES,
        "seed": SEED,
        "steps_per_period": STEPS,
        "transient_periods": TRANSIENT,
        "critical_speed_rad_s": crit,
        "speeds_rad_s": speeds.tolist(),
        "runs": {},
    }
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2), sharey=True, layout="constrained")
    colours = {4: "C0", 8: "C3"}
    for ax, relief in zip(axes, (False, True), strict=True):
        for grade in GRADES:
            df, res = run(case, scene, grade, relief, speeds)
            df = np.asarray(df)
            key = f"grade{grade}_{'relief' if relief else 'none'}"
            ok = np.asarray(res) == 0
            stats = [
                jg.sample_statistics(df[ok[:, j], j], (5.0, 50.0, 95.0)) for j in range(speeds.size)
            ]
            data["runs"][key] = {
                "grade": grade,
                "tip_relief": relief,
                "failed": int((~ok).sum()),
                "p5": [s["percentiles"]["5"]["value"] for s in stats],
                "p50": [s["percentiles"]["50"]["value"] for s in stats],
                "p95": [s["percentiles"]["95"]["value"] for s in stats],
                "mean": [s["mean"] for s in stats],
                "dynamic_factor": df.tolist(),
            }
            r = data["runs"][key]
            x = speeds / crit
            ax.fill_between(x, r["p5"], r["p95"], color=colours[grade], alpha=0.25)
            ax.plot(x, r["p50"], color=colours[grade], label=f"class {grade}: P50, P5–P95")
        nominal = perfect(case, scene, relief, speeds)
        data["perfect_" + ("relief" if relief else "none")] = nominal.tolist()
        ax.plot(speeds / crit, nominal, "k--", lw=1, label="perfect gears")
        ax.set_title("with tip relief (15 µm, Γ = 0.25)" if relief else "without tip relief")
        ax.set_xlabel("pinion speed / critical speed")
        ax.grid(alpha=0.3)
    axes[0].set_ylabel("dynamic factor")
    axes[0].legend()
    fig.suptitle(
        f"Accessory spur pair, {SAMPLES} realisations of the pinion's ISO 1328-1 deviations "
        f"per class (critical speed {crit:.0f} rad/s)"
    )
    fig.savefig(DOCS / "robust_iv8.png", dpi=120)
    (DOCS / "robust_iv8.json").write_text(json.dumps(data, indent=1))
    return data


if __name__ == "__main__":
    main()
