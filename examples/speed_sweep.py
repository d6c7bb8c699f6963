"""Speed sweep of the accessory spur pair: dynamic factor vs speed, with and without tip relief.

Torsional pinion-gear model (disc inertias), composite mesh damping (2.36), Newmark with the
exact contact loop; up and down continuation sweeps around the main tooth critical speed, then
the derivative of the dynamic factor with respect to the relief depth (smooth law).
Run: ``python examples/speed_sweep.py [out_dir]``.
"""

import sys

import jax

jax.config.update("jax_enable_x64", True)  # float64 (examples switch it on)

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.scenes as js


def main(out_dir=None, n_speeds: int = 40, periods: int = 40):
    case = jio.load_case("accessory-spur").replace(slices=4)  # spur: few slices suffice
    p = case.pair
    scene = js.TorsionalDynamics(
        case.mesh_model(),
        js.disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        js.disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    )
    kw = dict(integrator=jd.Newmark(32), window=jd.SteadyState(periods))
    models = {
        "tip relief 15 µm": jd.dynamic_model(
            scene, case.modifications, case.torque, positions_per_pitch=32
        ),
        "unmodified": jd.dynamic_model(
            scene, jg.Modifications(), case.torque, positions_per_pitch=32
        ),
    }
    relieved = models["tip relief 15 µm"]
    f_n = float(relieved.modes.frequency[1])
    cs = float(relieved.critical_speeds()[1])
    print(f"torsional mode {f_n:.0f} Hz, main tooth critical speed {cs:.0f} rad/s (pinion)")
    speeds = np.linspace(0.4 * cs, 1.6 * cs, n_speeds)
    curves = {}
    for name, model in models.items():
        s = jd.speed_sweep(model, speeds, direction=jd.Both(), **kw)
        up, down = np.asarray(s.results.dynamic_factor), np.asarray(s.down.dynamic_factor)
        curves[name] = (up, down)
        i = int(np.argmax(np.maximum(up, down)))
        print(
            f"{name:18s} peak dynamic factor {max(up.max(), down.max()):.2f} at "
            f"{speeds[i]:.0f} rad/s; max |up − down| {np.abs(up - down).max():.2f}"
        )

    def df(depth):
        m = eqx.tree_at(lambda m: m.mods.pinion.tip_relief_depth, relieved, depth)
        return jd.simulate(
            m, 0.8 * cs, contact=jg.SmoothContact(case.smooth_width), throw=False, **kw
        ).dynamic_factor

    val, slope = jax.jvp(df, (jnp.asarray(15e-6),), (jnp.asarray(1e-6),))
    print(
        f"dynamic factor at {0.8 * cs:.0f} rad/s (smooth law) {float(val):.3f}, "
        f"d/dE = {float(slope):+.4f} per µm of pinion tip relief"
    )

    if out_dir is not None:
        import os

        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        os.makedirs(out_dir, exist_ok=True)
        fig, ax = plt.subplots(figsize=(8, 5), layout="constrained")
        for k, (name, (up, down)) in enumerate(curves.items()):
            # up: solid with filled dots; down: dashed with open squares, drawn on top, so
            # where the two coincide both still show
            ax.plot(speeds, up, "-o", ms=3.5, color=f"C{k}", label=f"{name}, sweep up")
            ax.plot(
                speeds,
                down,
                "--s",
                ms=5,
                mfc="none",
                color=f"C{k}",
                zorder=3,
                label=f"{name}, sweep down",
            )
        for h in (1, 2):
            ax.axvline(cs / h, color="0.5", ls=":", lw=0.8)
            ax.text(
                cs / h,
                0.98,
                f" critical speed / {h}" if h > 1 else " critical speed",
                transform=ax.get_xaxis_transform(),
                fontsize=7,
                color="0.4",
                va="top",
            )
        ax.set_xlabel("pinion speed (rad/s)")
        ax.set_ylabel("dynamic mesh force / static")
        ax.set_title(
            f"{case.name}: dynamic factor, torsional pair, {n_speeds} speeds "
            f"(marked), Newmark, exact contact",
            fontsize=10,
        )
        fig.legend(loc="outside lower center", ncols=2, fontsize=8, frameon=False)
        ax.grid(alpha=0.3)
        fig.savefig(os.path.join(out_dir, "speed_sweep.png"), dpi=120)
        plt.close(fig)
    return {"critical_speed": cs, "speeds": speeds, "curves": curves, "slope": float(slope)}


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
