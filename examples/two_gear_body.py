"""A condensed FE body carrying two gears (examples/two-gear-body.toml): the intermediate shaft of
a small two-stage train as one body (fem_prep's ``intermediate-shaft``: a thin-webbed 48-tooth
wheel and a 16-tooth pinion cut on the shaft), each mesh's quasi-static TE against the same
body made a thousand times stiffer and against rigid gear discs on the case's beam shaft, and
the two rims' contact zones sharing the body's compliance (docs/trains.md, "A body carrying
two gears").

Writes docs/bench/two_gear_body.png and docs/bench/two_gear_body.json. Run from the repository root:
``python examples/two_gear_body.py`` (about a minute on 2 cores, plus one to two minutes for
each of the two bodies the first time fem_prep builds them).
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

import fem_prep  # noqa: E402
import jaxgear as jg  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.io import load_bodies  # noqa: E402
from jaxgear.scenes import mesh_zone_load  # noqa: E402

ROOT = pathlib.Path(__file__).parents[1]
DOCS = ROOT / "docs" / "bench"
CASE = ROOT / "examples" / "two-gear-body.toml"


def main(out_dir: pathlib.Path = DOCS) -> dict:
    """Compute, draw and write two_gear_body.{png,json} into ``out_dir`` (default docs/)."""
    case = jio.load_case(CASE)
    bodies = load_bodies(case.scene, progress=True)
    text = fem_prep.embedded_body_text("intermediate-shaft")
    stiff_text = text.replace("youngs_modulus_GPa = 210.0", "youngs_modulus_GPa = 210000.0")
    assert stiff_text != text
    stiff = fem_prep.condensed(
        fem_prep.parse_body(stiff_text, default_name="intermediate-shaft-stiff"), progress=True
    )
    rigid = case.replace(scene=dataclasses.replace(case.scene, gear_bodies=(), gear_rims=()))
    mods = case.mesh_modifications()
    kw = dict(positions_per_pitch=case.positions_per_pitch, periods=case.span_periods)
    scene = case.static_train(bodies=bodies)
    flex = jg.quasi_static(scene, mods, case.torque, **kw)
    hard = jg.quasi_static(
        case.static_train(bodies=(None, stiff, stiff, None)), mods, case.torque, **kw
    )
    ref = jg.quasi_static(rigid.static_train(), mods, case.torque, **kw)
    names = [case.mesh_name(k) for k in range(2)]
    out = {"case": case.name, "torque_Nm": case.torque, "meshes": []}
    for k in range(2):
        out["meshes"].append(
            {
                "name": names[k],
                **{
                    f"{label}_{key}": float(getattr(r.meshes[k], key)) * scale
                    for label, r in (("flexible", flex), ("stiff_body", hard), ("rigid", ref))
                    for key, scale in (
                        ("te_mean", 1e6),
                        ("te_rms", 1e6),
                        ("te_ptp", 1e6),
                        ("max_line_load", 1e-3),
                    )
                },
            }
        )
    # the body alone, its bearing nodes held: a unit load on each rim's contact zone, over a
    # period of the second (slower) mesh
    first = scene.structure.C_bearing.shape[0]
    K = np.asarray(scene.structure.K)[first:, first:]
    period = float(scene.meshes[0].base_plane.mesh_period_angle)
    span = case.span_periods * period
    Cs = []
    for th in np.linspace(0.0, span, 12, endpoint=False):
        F = np.stack([mesh_zone_load(scene, k, th, first) for k in range(2)], 1)
        Cs.append(F.T @ np.linalg.solve(K, F))
    Cs = np.array(Cs)
    C = Cs.mean(axis=0)
    out["zone_compliance_nm_per_N"] = (C * 1e9).tolist()
    out["zone_compliance_range_nm_per_N"] = [
        (Cs.min(axis=0) * 1e9).tolist(),
        (Cs.max(axis=0) * 1e9).tolist(),
    ]
    out["cross_over_own"] = float(C[0, 1] / np.sqrt(C[0, 0] * C[1, 1]))
    out["reciprocity_error"] = float(
        np.max(np.abs(Cs[:, 0, 1] - Cs[:, 1, 0]) / np.abs(Cs[:, 0, 1]))
    )

    fig, ax = plt.subplots(1, 2, figsize=(12.5, 4.8), gridspec_kw={"width_ratios": [1.6, 1]})
    variants = (
        (flex, "-", "flexible body"),
        (hard, "-.", "body 10³ stiffer"),
        (ref, "--", "rigid gear discs on the beam shaft"),
    )
    for k, colour in ((0, "C0"), (1, "C3")):
        for r, style, label in variants:
            te = np.asarray(r.meshes[k].transmission_error) * 1e6
            ax[0].plot(
                np.asarray(r.theta) / period, te, style, color=colour, label=f"{names[k]}, {label}"
            )
    ax[0].set_xlabel("input angle / first mesh period")
    ax[0].set_ylabel("quasi-static TE (µm)")
    ax[0].set_title(f"{case.name}: each mesh's TE at {case.torque:g} N·m")
    lo, hi = ax[0].get_ylim()
    ax[0].set_ylim(lo, hi + 0.45 * (hi - lo))
    ax[0].legend(fontsize=7.5, ncol=2, loc="upper center")
    im = ax[1].imshow(C * 1e9, cmap="viridis")
    for i in range(2):
        for j in range(2):
            dark = C[i, j] < 0.6 * C.max()
            ax[1].text(
                j,
                i,
                f"{C[i, j] * 1e9:.3f}",
                ha="center",
                va="center",
                color="w" if dark else "k",
                fontsize=11,
            )
    labels = ["wheel zone\n(" + names[0] + ")", "pinion zone\n(" + names[1] + ")"]
    ax[1].set_xticks([0, 1], labels, fontsize=8)
    ax[1].set_yticks([0, 1], labels, fontsize=8)
    ax[1].set_title(
        f"body zone compliance (nm/N), bearings held\ncross / own = {out['cross_over_own']:.3f}",
        fontsize=10,
    )
    fig.colorbar(im, ax=ax[1], fraction=0.046)
    fig.tight_layout()
    fig.savefig(out_dir / "two_gear_body.png", dpi=110)
    (out_dir / "two_gear_body.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    print(json.dumps(main(), indent=1))
