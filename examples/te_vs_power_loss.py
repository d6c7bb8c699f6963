"""Transmission error against mesh power loss over the tip relief: the trade-off front on the FZG
C14 gears (examples/fzg-c14-lubricated.toml: m 4.5 mm, z 16/24, 200 N·m, 1500 rpm, ISO VG 320
at 75 °C).

1. Map the design space: the same tip relief on both gears, depth E* = E/δ_m in [0, 3] and
   extent Γ in [0.05, 0.95] of the path of contact, each design solved in exact contact (sharp
   relief starts, as a case file writes it), its peak-to-peak TE (``result.te_ptp``) and its
   sliding power loss P_VZP (``optimise.MeshPowerLoss``: μ w v_g over the path of contact from
   the design's own line loads, Schlenk's μ) read from one solve. The designs that no other
   beats on both are the front.
2. Walk the front with the optimiser: a weighted sum w TE_ptp/TE_ptp,0 + (1 − w) P/P_0 (one
   subclass of ``optimise.AbstractTribologyObjective``: a new objective is one class) minimised
   by L-BFGS in the smooth law for w from 1 (TE only) to 0 (loss only), each from the map's best
   design for its weight (the peak-to-peak TE has several valleys over the map), and its optimum
   evaluated in exact contact.

Prints the TE-optimal and the loss-optimal reliefs; writes ``te_vs_power_loss.json`` and
``te_vs_power_loss.png`` (the two maps with both optima, and the front) into the output folder,
by default ``jaxgear-out/te_vs_power_loss``. Run from anywhere:
``python examples/te_vs_power_loss.py [out_dir]`` (a few minutes on 2 loaded cores).
"""

import json
import pathlib
import sys
import warnings
from typing import ClassVar

import jax

jax.config.update("jax_enable_x64", True)

import equinox as eqx
import jax.numpy as jnp
import matplotlib
import numpy as np

import jaxgear as jg
import jaxgear.io as jio
import optimise as op

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

HERE = pathlib.Path(__file__).resolve().parent
OUT = pathlib.Path("jaxgear-out") / "te_vs_power_loss"
VARS = "tip_relief.depth,tip_relief.extent"
WEIGHTS = (1.0, 0.8, 0.6, 0.4, 0.2, 0.0)


class TeAndLoss(op.AbstractTribologyObjective):
    """w TE_ptp/te_scale + (1 − w) P_VZP/loss_scale (-): the weighted sum of the front."""

    weight: float = eqx.field(default=0.5, static=True)
    te_scale: float = eqx.field(default=1.0, static=True)
    loss_scale: float = eqx.field(default=1.0, static=True)

    name: ClassVar[str] = "te_ptp_and_power_loss"
    units: ClassVar[str] = "dimensionless"

    def of_tribology(self, result, torque):
        loss = self.lubrication.tribology(result, torque).mean_power_loss
        w = self.weight
        return w * result.te_ptp / self.te_scale + (1.0 - w) * loss / self.loss_scale


def _front(te, loss) -> np.ndarray:
    """Indices of the designs no other beats on both TE and loss, by increasing TE."""
    order = np.lexsort((loss, te))
    keep, best = [], np.inf
    for i in order:
        if loss[i] < best:
            keep.append(i)
            best = loss[i]
    return np.asarray(keep)


def main(
    out_dir=OUT,
    n_grid: int = 25,
    positions: int = 32,
    max_iterations: int = 30,
    weights=WEIGHTS,
) -> dict:
    """Run the example at ``n_grid``² designs, ``positions`` per pitch and the weighted sums of
    ``weights``; write the record and the figure into ``out_dir`` (created if missing);
    returns the record."""
    out_dir = pathlib.Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    # on the theoretical path of contact, as GEARpie's C14 reference (docs/tribology.md)
    case = jio.load_case(HERE / "fzg-c14-lubricated.toml")
    case = case.replace(contact_geometry=jg.TheoreticalPath())
    loss_problem = jio.case_problem(case, VARS, "power_loss", positions_per_pitch=positions)
    lub = loss_problem.objective.lubrication
    sharp = loss_problem.sharp()
    torque = float(case.torque)

    def te_and_loss(x):
        res = jg.quasi_static(
            sharp.mesh, sharp.modifications(x), torque, positions_per_pitch=positions
        )
        return res.te_ptp, lub.tribology(res, torque).mean_power_loss

    depths = np.linspace(0.0, 3.0, n_grid)
    extents = np.linspace(0.05, 0.95, n_grid)
    grid = jnp.asarray([[e, g] for g in extents for e in depths])
    te, loss = (np.asarray(a) for a in jax.jit(jax.vmap(te_and_loss))(grid))
    # the unmodified design: depth 0 (at an extent inside its range (0, 1]; Γ = 0 would divide
    # 0/0 at the path's ends, which contact beyond the path reaches)
    te0, loss0 = (float(a) for a in jax.jit(te_and_loss)(jnp.asarray([0.0, 0.5])))
    front = _front(te, loss)

    # the weighted sums, each started from the map's best design for its weight (TE_ptp has
    # several valleys over the map: a start from the previous optimum stays in its valley)
    walked = []
    for w in weights:
        x = jnp.clip(grid[int(np.argmin(w * te / te0 + (1.0 - w) * loss / loss0))],
                     jnp.asarray([0.15, 0.07]), jnp.asarray([2.85, 0.93]))
        obj = TeAndLoss(lub, weight=w, te_scale=te0, loss_scale=loss0)
        prob = op.make_problem(
            case.mesh_model(),
            case.modifications,
            torque,
            VARS,
            obj,
            positions_per_pitch=positions,
            smoothing=op.Smoothing(jg.SmoothContact(case.smooth_width)),
        )
        with warnings.catch_warnings():  # a kinked TE_ptp may stop L-BFGS at the cap
            warnings.filterwarnings("ignore", "optimiser stopped at the iteration cap")
            r = op.minimise(prob, x, max_iterations=max_iterations, progress=False)
        x = jnp.asarray(r.x)
        t_x, l_x = (float(a) for a in jax.jit(te_and_loss)(x))
        walked.append(
            {
                "weight": w,
                "depth_E_star": float(x[0]),
                "extent": float(x[1]),
                "depth_um": float(x[0]) * float(prob.delta_m) * 1e6,
                "te_ptp_um": t_x * 1e6,
                "power_loss_W": l_x,
                "iterations": int(r.iterations),
            }
        )
        print(
            f"w {w:.1f}: E* {float(x[0]):.3f}, Γ {float(x[1]):.3f} → TE_ptp {t_x * 1e6:.3f} µm, "
            f"P_VZP {l_x:.2f} W ({r.iterations} iterations)"
        )

    i_te, i_loss = int(np.argmin(te)), int(np.argmin(loss))
    delta_m = float(loss_problem.delta_m)

    def design(i):
        e, g = (float(v) for v in grid[i])
        return {
            "depth_E_star": e,
            "depth_um": e * delta_m * 1e6,
            "extent": g,
            "te_ptp_um": float(te[i]) * 1e6,
            "power_loss_W": float(loss[i]),
            "efficiency": 1.0 - float(loss[i]) / (torque * lub.speed.item()),
        }

    record = {
        "case": case.name,
        "dtype": "float64",
        "jax": jax.__version__,
        "torque_Nm": torque,
        "speed_rad_s": float(lub.speed),
        "positions_per_pitch": positions,
        "delta_m_um": delta_m * 1e6,
        "unmodified": {"te_ptp_um": te0 * 1e6, "power_loss_W": loss0},
        "grid": {"n": n_grid, "depth_E_star": [0.0, 3.0], "extent": [0.05, 0.95]},
        "te_optimal": design(i_te),
        "loss_optimal": design(i_loss),
        "front": [design(int(i)) for i in front],
        "weighted_sums": walked,
        "notes": "exact contact, sharp relief starts, the same tip relief on both gears; "
        "the weighted sums minimised in the smooth law (case width) by L-BFGS",
    }
    (out_dir / "te_vs_power_loss.json").write_text(json.dumps(record, indent=1) + "\n")
    np.savez(out_dir / "te_vs_power_loss_map.npz", depths=depths, extents=extents, te=te, loss=loss)
    plot(record, depths, extents, te, loss, out_dir / "te_vs_power_loss.png")
    a, b = record["te_optimal"], record["loss_optimal"]
    print(
        f"TE-optimal: E {a['depth_um']:.1f} µm over Γ {a['extent']:.2f}: TE_ptp "
        f"{a['te_ptp_um']:.3f} µm, P_VZP {a['power_loss_W']:.1f} W; loss-optimal: E "
        f"{b['depth_um']:.1f} µm over Γ {b['extent']:.2f}: TE_ptp {b['te_ptp_um']:.3f} µm, "
        f"P_VZP {b['power_loss_W']:.1f} W (unmodified {te0 * 1e6:.3f} µm, {loss0:.1f} W)"
    )
    return record


def _weight_labels(ws, key=None, tol=0.02) -> dict:
    """One label per distinct point of the weighted sums ("w 0.8, 0.6" where two weights give
    the same design), by the point's (Γ, E*) or by ``d[key]``."""
    out: dict = {}
    for d in ws:
        at = d[key] if key else (d["extent"], d["depth_E_star"])
        near = next((p for p in out if abs(p[0] - at[0]) + abs(p[1] - at[1]) < tol), None)
        if near is None:
            out[at] = f"w {d['weight']:.1f}"
        else:
            out[near] += f", {d['weight']:.1f}"
    return out


def plot(record, depths, extents, te, loss, path) -> None:
    """Left: TE_ptp over (Γ, E*); middle: P_VZP over the same; right: the front."""
    n = len(depths)
    te_map = te.reshape(n, n) * 1e6  # rows: extents, columns: depths
    loss_map = loss.reshape(n, n)
    fig, axes = plt.subplots(1, 3, figsize=(14, 4.6), layout="constrained")
    a, b, ws = record["te_optimal"], record["loss_optimal"], record["weighted_sums"]
    marks = {"clip_on": False, "zorder": 5, "ms": 9, "mec": "k"}
    for ax, z, label, cmap in (
        (axes[0], te_map, "TE peak-to-peak (µm)", "viridis"),
        (axes[1], loss_map, "mesh power loss P_VZP (W)", "magma"),
    ):
        c = ax.contourf(extents, depths, z.T, levels=20, cmap=cmap)
        fig.colorbar(c, ax=ax, label=label)
        ax.plot(a["extent"], a["depth_E_star"], "o", mfc="w", label="TE-optimal (map)", **marks)
        ax.plot(b["extent"], b["depth_E_star"], "s", mfc="w", label="loss-optimal (map)", **marks)
        ax.plot([d["extent"] for d in ws], [d["depth_E_star"] for d in ws], "^", mfc="C3",
                label="weighted sums (L-BFGS)", **{**marks, "ms": 7})
        for (g, e), text in _weight_labels(ws).items():
            ax.annotate(text, (g, e), xytext=(6, -10), textcoords="offset points", color="w",
                        fontsize=7)
        ax.set_xlabel("tip relief extent Γ (fraction of the path of contact)")
        ax.set_ylabel("tip relief depth E* = E/δ_m")
        ax.set_title(label.split(" (")[0] + " over the tip relief")
        ax.legend(loc="lower right", fontsize=7)
    ax = axes[2]
    ax.plot(te * 1e6, loss, ".", color="0.75", ms=3, label="designs of the map")
    fr = record["front"]
    ax.plot([d["te_ptp_um"] for d in fr], [d["power_loss_W"] for d in fr], "k-", lw=2,
            label="front (map)")
    ax.plot(a["te_ptp_um"], a["power_loss_W"], "o", mfc="w", label="TE-optimal (map)", **marks)
    ax.plot(b["te_ptp_um"], b["power_loss_W"], "s", mfc="w", label="loss-optimal (map)", **marks)
    ax.plot([d["te_ptp_um"] for d in ws], [d["power_loss_W"] for d in ws], "^", color="C3",
            ms=7, label="weighted sums (L-BFGS)")
    for d in ws:
        d["_at"] = (d["te_ptp_um"], d["power_loss_W"])
    for at, text in _weight_labels(ws, "_at", 0.2).items():
        ax.annotate(text, at, xytext=(5, 2), textcoords="offset points", color="C3", fontsize=7)
    for d in ws:
        del d["_at"]
    u = record["unmodified"]
    ax.plot(u["te_ptp_um"], u["power_loss_W"], "x", color="k", ms=9, label="unmodified")
    ax.set_xlim(0.0, 1.15 * u["te_ptp_um"])
    ax.set_xlabel("TE peak-to-peak (µm)")
    ax.set_ylabel("mesh power loss P_VZP (W)")
    ax.set_title("the trade-off: TE against power loss")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="lower right", framealpha=0.95)
    fig.suptitle(
        f"{record['case']}: the same tip relief on both gears, {record['torque_Nm']:.0f} N·m, "
        f"{record['speed_rad_s']:.0f} rad/s, δ_m {record['delta_m_um']:.1f} µm (exact contact)"
    )
    fig.savefig(path, dpi=110)
    plt.close(fig)


def replot(out_dir=OUT) -> None:
    """Redraw the figure from the record and the map in ``out_dir`` (no solve)."""
    out_dir = pathlib.Path(out_dir)
    record = json.loads((out_dir / "te_vs_power_loss.json").read_text())
    m = np.load(out_dir / "te_vs_power_loss_map.npz")
    plot(record, m["depths"], m["extents"], m["te"], m["loss"], out_dir / "te_vs_power_loss.png")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else OUT)
