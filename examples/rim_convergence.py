"""Does a hybrid result depend on the body's mesh? The accessory wheel (embedded body
``accessory-wheel``) refined twice (the rim section halved, then the circumference as well),
with each rim master coupling of fem_prep (``[condensation] rim_coupling``, docs/fem_prep.md,
"Rim masters"):

* ``nodal``: the tooth loads sit on the corner nodes of the rim faces;
* ``distributing``: they spread over the rim face as a traction (a least-squares fit of the face).

For each body: the compliance of one rim station (a unit tangential and radial force over its
axial masters, the bearings held) and the quasi-static TE of the case
``accessory-spur-flexible`` (80 N·m, 3000 rad/s).

Writes docs/bench/rim_convergence.png and docs/bench/rim_convergence.json. Run from the repository root:
``python examples/rim_convergence.py`` (about 25 minutes on 2 cores: six fem_prep builds, the
finest about 5 minutes each).

``python examples/rim_convergence.py power``: the same for the helical power pair's wheel
(embedded body ``power-helical-wheel``, case ``power-helical-flexible``, 310 N·m at 3000 rad/s)
with distributing masters only, refined as ``POWER_REFINEMENTS`` (the rim section halved, then
the circumference: 2 → 4 elements per pitch); writes docs/bench/rim_convergence_power.json (about
30 minutes on 2 cores: the finest body has about 333 000 DOFs).
"""

from __future__ import annotations

import dataclasses
import json
import pathlib
import tempfile

import jax

jax.config.update("jax_enable_x64", True)

import fem_prep  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import jaxgear as jg  # noqa: E402
from jaxgear import io as jio  # noqa: E402
from jaxgear.io import static_scene  # noqa: E402

DOCS = pathlib.Path(__file__).resolve().parents[1] / "docs" / "bench"
COUPLINGS = ("nodal", "distributing")
# (label, rim section element size (mm, None: the body's 3.5), circumferential size (mm))
REFINEMENTS = (
    ("as embedded", None, 4.6),
    ("rim section / 2", 1.75, 4.6),
    ("and circumference / 2", 1.75, 2.3),
)


# (label, rim section size (mm, None: the body's 6), circumferential size (mm, None: the body's
# 6, two elements per 7.8 mm pitch))
POWER_REFINEMENTS = (
    ("as embedded", None, None),
    ("rim section / 2", 3.0, None),
    ("and circumference / 2", 3.0, 1.95),
)


def power_body_text(rim_mm: float | None, circ_mm: float | None) -> str:
    """The power wheel with distributing rim masters and the given rim and circumferential
    element sizes."""
    text = fem_prep.embedded_body_text("power-helical-wheel")
    text = text.replace("[condensation]", '[condensation]\nrim_coupling = "distributing"')
    extra = "" if rim_mm is None else f"\nrim_size_mm = {rim_mm}"
    extra += "" if circ_mm is None else f"\ncircumferential_size_mm = {circ_mm}"
    return text.replace("[mesh]", "[mesh]" + extra)


def body_text(coupling: str, rim_mm: float | None, circ_mm: float) -> str:
    text = fem_prep.embedded_body_text("accessory-wheel")
    text = text.replace("[condensation]", f'[condensation]\nrim_coupling = "{coupling}"')
    extra = "" if rim_mm is None else f"\nrim_size_mm = {rim_mm}"
    sizes = f"circumferential_size_mm = {circ_mm}{extra}"
    return text.replace("circumferential_size_mm = 4.6", sizes)


def station_compliance(body) -> dict:
    """Compliance (nm/N) of station 0 under a unit tangential and a unit radial force spread
    over its axial masters by their face shares, the bearing nodes held (the condensed model's
    statics are exact for master loads)."""
    K = np.asarray(body.K)
    grid = np.asarray(body.rim_grid)
    coords = np.asarray(body.master_coords)
    dof = {(int(m), int(c)): i for i, (m, c) in enumerate(np.asarray(body.dof_map)) if m >= 0}
    z = coords[grid[0], 2]
    share = np.zeros(len(z))
    share[:-1] += np.diff(z) / 2
    share[1:] += np.diff(z) / 2
    share /= share.sum()
    kind = np.asarray(body.master_kind)
    held = [dof[(m, c)] for m in np.nonzero(kind == 1)[0] for c in range(6)]
    free = np.setdiff1d(np.arange(K.shape[0]), held)
    x0 = coords[grid[0, 0]]
    er = np.array([x0[0], x0[1], 0.0]) / np.hypot(x0[0], x0[1])
    et = np.array([-er[1], er[0], 0.0])
    out = {}
    for name, e in (("tangential", et), ("radial", er)):
        F = np.zeros(K.shape[0])
        for j, m in enumerate(grid[0]):
            for c in range(3):
                F[dof[(int(m), c)]] = share[j] * e[c]
        q = np.zeros(K.shape[0])
        q[free] = np.linalg.solve(K[np.ix_(free, free)], F[free])
        out[name] = float(F @ q) * 1e9
    return out


def te_of(case, body_path: str) -> dict:
    case = case.replace(scene=dataclasses.replace(case.scene, gear_body=body_path))
    scene, _ = static_scene(case)
    r = jg.quasi_static(
        scene,
        case.modifications,
        case.torque,
        speed=case.speed,
        positions_per_pitch=case.positions_per_pitch,
    )
    te = np.asarray(r.meshes[0].transmission_error)
    return {"te_mean_um": float(te.mean()) * 1e6, "te_rms_um": float(te.std()) * 1e6}


def main() -> dict:
    case = jio.load_case("accessory-spur-flexible")
    out: dict = {"case": case.name, "refinements": [r[0] for r in REFINEMENTS], "couplings": {}}
    with tempfile.TemporaryDirectory() as tmp:
        for coupling in COUPLINGS:
            rows = []
            for label, rim, circ in REFINEMENTS:
                path = pathlib.Path(tmp) / f"wheel-{coupling}-{len(rows)}.toml"
                path.write_text(body_text(coupling, rim, circ))
                body = fem_prep.condensed(path, progress=True)
                row = {"label": label, "rim_size_mm": rim or 3.5, "circumferential_size_mm": circ}
                row["n_dofs"] = int(body.metadata["n_dofs"])
                row["compliance_nm_per_N"] = station_compliance(body)
                row.update(te_of(case, str(path)))
                print(coupling, row, flush=True)
                rows.append(row)
            out["couplings"][coupling] = rows
    DOCS.mkdir(exist_ok=True)
    (DOCS / "rim_convergence.json").write_text(json.dumps(out, indent=1) + "\n")
    plot(out)
    return out


def plot(out: dict) -> None:
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.2))
    x = np.arange(len(out["refinements"]))
    for coupling, style in zip(COUPLINGS, ("s--", "o-")):
        rows = out["couplings"][coupling]
        for key, color in (("tangential", "C0"), ("radial", "C1")):
            axes[0].plot(
                x,
                [r["compliance_nm_per_N"][key] for r in rows],
                style,
                color=color,
                label=f"{coupling}, {key}",
            )
        axes[1].plot(x, [r["te_mean_um"] for r in rows], style, color="C2", label=coupling)
        axes[2].plot(x, [r["te_rms_um"] for r in rows], style, color="C3", label=coupling)
    titles = ("rim station compliance (nm/N)", "TE mean (µm)", "TE RMS (µm)")
    for ax, title in zip(axes, titles):
        ax.set_xticks(x, out["refinements"], fontsize=8)
        ax.set_title(title)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(
        "accessory wheel refined: nodal rim masters (dashed) vs distributing (solid); "
        f"TE of {out['case']}"
    )
    fig.tight_layout()
    fig.savefig(DOCS / "rim_convergence.png", dpi=110)
    plt.close(fig)


def power_study() -> dict:
    """TE mean and RMS of ``power-helical-flexible`` on its wheel refined twice (distributing
    rim masters): docs/bench/rim_convergence_power.json."""
    case = jio.load_case("power-helical-flexible")
    out: dict = {"case": case.name, "coupling": "distributing", "rows": []}
    with tempfile.TemporaryDirectory() as tmp:
        for k, (label, rim, circ) in enumerate(POWER_REFINEMENTS):
            path = pathlib.Path(tmp) / f"power-wheel-{k}.toml"
            path.write_text(power_body_text(rim, circ))
            body = fem_prep.condensed(path, progress=True)
            row = {"label": label, "rim_size_mm": rim or 6.0, "circumferential_size_mm": circ}
            row["n_dofs"] = int(body.metadata["n_dofs"])
            row["compliance_nm_per_N"] = station_compliance(body)
            row.update(te_of(case, str(path)))
            print(row, flush=True)
            out["rows"].append(row)
    (DOCS / "rim_convergence_power.json").write_text(json.dumps(out, indent=1) + "\n")
    return out


if __name__ == "__main__":
    import sys

    power_study() if sys.argv[1:] == ["power"] else main()
