"""A flexible idler meshing twice (embedded case ``flexible-idler``): each mesh's quasi-static TE
with the idler as a thin-webbed condensed FE body against the same train with a rigid idler node,
and the two contact zones sharing the body's compliance (docs/trains.md, "Flexible gears in a
train").

Writes docs/bench/flexible_idler.png and docs/bench/flexible_idler.json. Run from the repository root:
``python examples/flexible_idler.py`` (about 1 minute on 2 cores, plus 1-2 minutes the first
time fem_prep builds the idler body).
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
from jaxgear.io import load_bodies  # noqa: E402
from jaxgear.scenes import mesh_zone_load  # noqa: E402

DOCS = pathlib.Path(__file__).parents[1] / "docs" / "bench"


def main(out_dir: pathlib.Path = DOCS) -> dict:
    """Compute, draw and write flexible_idler.{png,json} into ``out_dir`` (default docs/)."""
    case = jio.load_case("flexible-idler")
    bodies = load_bodies(case.scene, progress=True)
    rigid = case.replace(scene=dataclasses.replace(case.scene, gear_bodies=()))
    mods = case.mesh_modifications()
    kw = dict(positions_per_pitch=case.positions_per_pitch, periods=2)
    scene = case.static_train(bodies=bodies)
    flex = jg.quasi_static(scene, mods, case.torque, **kw)
    ref = jg.quasi_static(rigid.static_train(), mods, case.torque, **kw)
    names = [case.mesh_name(k) for k in range(2)]
    out = {"case": case.name, "meshes": []}
    for k in range(2):
        out["meshes"].append(
            {
                "name": names[k],
                **{
                    f"{label}_{key}": float(getattr(r.meshes[k], key)) * scale
                    for label, r in (("flexible", flex), ("rigid", ref))
                    for key, scale in (("te_mean", 1e6), ("te_ptp", 1e6), ("max_line_load", 1e-3))
                },
            }
        )
    # the idler body with its hub held: each zone's unit load, the other zone's approach
    first = scene.structure.C_bearing.shape[0]
    K = np.asarray(scene.structure.K)[first:, first:]
    idler = scene.members[1]
    period = float(scene.meshes[0].base_plane.mesh_period_angle)
    Cs = []
    for th in np.linspace(0.0, period, 8, endpoint=False):
        F = np.stack([mesh_zone_load(scene, k, th, first) for k in range(2)], 1)
        Cs.append(F.T @ np.linalg.solve(K, F))
    C = np.mean(Cs, axis=0)
    out["zone_compliance_nm_per_N"] = (C * 1e9).tolist()
    out["cross_over_own"] = float(C[0, 1] / np.sqrt(C[0, 0] * C[1, 1]))
    # rim radial and tangential displacement (mid-face) under each zone's load at θ = 0
    X = np.linalg.solve(K, np.stack([mesh_zone_load(scene, k, 0.0, first) for k in range(2)], 1))
    j = int(np.argmin(np.abs(np.asarray(idler.z_nodes))))
    rim = np.asarray(idler.rim_dofs)[:, j, :] - first
    Z = rim.shape[0]
    ang = float(idler.station0) + float(idler.pitch_angle) * np.arange(Z)
    fixed = ang + float(idler.frame_angle(0.0))  # station angles in the fixed frame
    centre = np.asarray(idler.centre)
    zones = [
        np.degrees(np.arctan2(*(np.asarray(m.line()["zone"]) - centre)[1::-1]))
        for m in scene.meshes
    ]

    fig, ax = plt.subplots(1, 2, figsize=(12, 4.4))
    for k, colour in ((0, "C0"), (1, "C3")):
        for r, style, label in ((flex, "-", "flexible idler"), (ref, "--", "rigid idler node")):
            te = np.asarray(r.meshes[k].transmission_error) * 1e6
            ax[0].plot(
                np.asarray(r.theta) / period, te, style, color=colour, label=f"{names[k]}, {label}"
            )
    ax[0].set_xlabel("input angle / first mesh period")
    ax[0].set_ylabel("quasi-static TE (µm)")
    ax[0].set_title(f"{case.name}: each mesh's TE, {case.torque:g} N·m")
    ax[0].legend(fontsize=8)
    order = np.argsort(np.degrees(fixed) % 360)
    for k, colour in ((0, "C0"), (1, "C3")):
        u = X[rim, k]
        ur = u[:, 0] * np.cos(ang) + u[:, 1] * np.sin(ang)
        ut = -u[:, 0] * np.sin(ang) + u[:, 1] * np.cos(ang)
        deg = (np.degrees(fixed) % 360)[order]
        ax[1].plot(deg, ur[order] * 1e9, "-", color=colour, label=f"radial, 1 N on {names[k]}")
        ax[1].plot(deg, ut[order] * 1e9, ":", color=colour, label=f"tangential, 1 N on {names[k]}")
        ax[1].axvline(zones[k] % 360, color=colour, lw=0.8, alpha=0.6)
    ax[1].set_xlabel("rim station angle, fixed frame (deg); lines: the contact zones")
    ax[1].set_ylabel("rim displacement, hub held (nm per N)")
    ax[1].set_title(
        f"the idler body: zone compliance {C[0, 0] * 1e9:.2f} nm/N own, "
        f"{C[0, 1] * 1e9:.2f} nm/N across"
    )
    ax[1].legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out_dir / "flexible_idler.png", dpi=110)
    (out_dir / "flexible_idler.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
