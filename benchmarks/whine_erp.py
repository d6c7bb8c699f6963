"""Gear whine to radiated power (docs/whine.md, "Outputs" and "Housing and ERP"): the relieved
``accessory-spur`` pair in its case's lumped 3D scene (4 slices) with a ``[whine]`` table (60
speeds, 50-1600 rad/s, harmonic balance H = 16 on 128 positions) through ``jaxgear run``'s whine
outputs (the order plot of the TE and the waterfall of the bearing forces, copied to docs/img),
then its four bearings' forces on the four seats of an aluminium box housing (360 x 200 x 220
mm, 8 mm walls, two feet; structured Tet10 mesh of 50 mm, Craig–Bampton with the
fixed-interface modes to 1.5 x 12 kHz, the orders drawn up to 12 kHz) and the ERP of orders 1-4 and
overall against speed (docs/img/whine_erp.png), an operating deflection shape at the loudest
speed and order to VTU (a temporary file), the costs in docs/bench/whine_erp.json. From the
repository root: ``python -m benchmarks.whine_erp``.
"""

from __future__ import annotations

import json
import pathlib
import shutil
import tempfile
import time

import jax

jax.config.update("jax_enable_x64", True)

import jax.numpy as jnp
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

import fem_prep
import jaxgear.io as jio
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    condensed_housing,
    housing_cutoff_hz,
    mesh_box,
    outer_surface,
    write_housing_ods_vtu,
)
from jaxgear.acoustics import housing_acoustics, housing_response, seat_forces, total_level
from jaxgear.cli.run import whine_outputs  # (jaxgear run's whine files)
from jaxgear.dynamics import whine_response

from ._timing import environment

ROOT = pathlib.Path(__file__).resolve().parents[1]
ALUMINIUM = fem_prep.Material(70e9, 0.33, 2700.0)
WHINE = (
    "\n[whine]\nspeed_min_rad_s = 50.0\nspeed_max_rad_s = 1600.0\nspeeds = 60\nharmonics = 16\n"
    "positions_per_period = 128\n"
)
ORDERS = 4
#: the highest order frequency drawn (Hz): the housing's modes to 1.5 x it are kept (a 50 mm
#: mesh of 8 mm walls resolves its bending waves up to about that); above it, not drawn
F_MAX = 12000.0


def housing_box():
    """The pinion shaft's bearings at (x, z) = (0.1, 0.12) m in the walls y = 0 and y = 0.2 m,
    the gear's at (0.1 + a, 0.12) m (a = the centre distance, 100.3 mm here)."""
    return HousingBox(
        0.36, 0.2, 0.22, 0.008,
        bores=(Bore("y-", (0.1, 0.12), 0.03), Bore("y+", (0.1, 0.12), 0.03),
               Bore("y-", (0.2003, 0.12), 0.035), Bore("y+", (0.2003, 0.12), 0.035)),
        feet=(Foot((0.0, 0.06), (0.0, 0.2)), Foot((0.3, 0.36), (0.0, 0.2))),
    )


def main() -> None:
    text = (ROOT / "jaxgear" / "cases" / "accessory-spur.toml").read_text()
    text = text.replace("slices = 40", "slices = 4") + WHINE
    with tempfile.TemporaryDirectory() as tmp:
        path = pathlib.Path(tmp) / "accessory-spur.toml"
        path.write_text(text)
        case = jio.load_case(str(path))
        t = time.perf_counter()
        section = whine_outputs(case, tmp)
        t_outputs = time.perf_counter() - t
        for src, dst in (("te_orders.png", "whine_te_orders.png"),
                         ("bearing_waterfall.png", "whine_bearing_waterfall.png")):
            shutil.copy(pathlib.Path(tmp) / "whine" / src, ROOT / "docs" / "img" / dst)
    model, _ = jio.build_dynamic_model(case)
    inputs = jio.whine_of(case)
    w = whine_response(model, np.asarray(inputs.speeds), inputs.method,
                       positions=inputs.positions)
    names = model.scene.reaction_names
    # the scene's axes: z along the shafts (the housing's y), x between the centres (its x)
    rotation = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, 1.0, 0.0]])
    seats = [(0 if "z=0mm" in n else 1) + (2 if n.startswith("gear") else 0) for n in names]
    t = time.perf_counter()
    mesh = mesh_box(housing_box(), 0.05)
    ch = condensed_housing(mesh, ALUMINIUM, housing_cutoff_hz(F_MAX), cache=False)
    surface = outer_surface(mesh, {"top centre": (0.18, 0.1, 0.22), "side": (0.18, 0.0, 0.12)})
    t_housing = time.perf_counter() - t
    ac = housing_acoustics(ch, surface, loss_factor=0.02)
    orders = slice(1, ORDERS + 1)
    freq = w.frequency[:, None] * w.orders[None, orders]
    loads = seat_forces(w.bearing_force[:, orders], seats, names, len(ch.seat_names), rotation)
    respond = jax.jit(housing_response)
    r = jax.block_until_ready(respond(ac, loads, freq))
    t = time.perf_counter()
    r = jax.block_until_ready(respond(ac, loads, freq))
    t_erp = time.perf_counter() - t
    speeds = np.asarray(w.speed)
    level = np.where(np.asarray(freq) <= F_MAX, np.asarray(r.level), np.nan)
    overall = np.asarray(total_level(jnp.where(freq <= F_MAX, r.power, 0.0)))
    loss = np.asarray(w.contact_loss).any(axis=1)
    fig = Figure(figsize=(8, 4.8), layout="constrained")
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    for j in range(ORDERS):
        ax.plot(speeds, level[:, j], ".-", ms=3, lw=1.1, label=f"order {j + 1}")
    ax.plot(speeds, overall, "k-", lw=1.8, label="overall (orders 1-4)")
    for k in np.nonzero(loss)[0]:
        ax.axvspan(speeds[k] - 13, speeds[k] + 13, color="tab:red", alpha=0.15, lw=0)
    ax.set_xlabel("pinion speed (rad/s)")
    ax.set_ylabel("ERP level (dB re 1 pW)")
    top = float(np.nanmax(overall))
    ax.set_ylim(top - 70, top + 5)
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right", fontsize=8, ncol=2)
    ax.set_title("accessory-spur on an aluminium box housing: equivalent radiated power\n"
                 f"({len(ch.modes_hz)} housing modes to {ch.cutoff_hz / 1e3:.0f} kHz, orders "
                 f"drawn to {F_MAX / 1e3:g} kHz)", fontsize=10)
    ax.text(0.0, -0.16, "one-way: bearing forces of the gears on rigid supports, loss factor "
            "0.02, ρc of air; shaded: contact loss (the linear result does not hold)",
            transform=ax.transAxes, fontsize=8, va="top")
    fig.savefig(ROOT / "docs" / "img" / "whine_erp.png", dpi=120)
    s, j = np.unravel_index(int(np.nanargmax(level)), level.shape)
    label = f"order{j + 1}_{speeds[s]:.0f}rad_s"
    with tempfile.TemporaryDirectory() as tmp:  # (ParaView's file: not kept in the docs)
        ods = write_housing_ods_vtu(mesh, ch, {label: np.asarray(r.coordinates[s, j])},
                                    pathlib.Path(tmp) / "ods.vtu")
        ods_bytes = ods.stat().st_size
    out = {
        "environment": environment(),
        "case": "accessory-spur (lumped 3D, 4 slices), [whine] 60 speeds 50-1600 rad/s, H = 16",
        "housing_dofs": int(mesh.n_dofs),
        "housing_modes_kept": int(len(ch.modes_hz)),
        "housing_cutoff_Hz": float(ch.cutoff_hz),
        "skin_facets": int(surface.facets.size),
        "seconds": {"whine_outputs_with_plots": t_outputs,
                    "housing_mesh_and_condensation": t_housing,
                    "housing_response_and_erp_60x4": t_erp},
        "ods_vtu_bytes": int(ods_bytes),
        "loudest": {"speed_rad_s": float(speeds[s]), "order": int(j + 1),
                    "frequency_Hz": float(freq[s, j]), "level_dB": float(level[s, j])},
        "overall_dB_max": top,
        "contact_loss_speeds_rad_s": speeds[loss].tolist(),
        "whine_section": section,
    }
    (ROOT / "docs" / "bench" / "whine_erp.json").write_text(json.dumps(out, indent=2) + "\n")
    print(json.dumps(out["seconds"]), out["loudest"], f"overall max {top:.1f} dB")


if __name__ == "__main__":
    main()
