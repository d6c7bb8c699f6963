"""The housing's operating deflection shape as a figure (docs/housing.md, "In `jaxgear run`";
docs/img/housing_ods.png): the outer skin of a housed case's housing, displaced by one operating
deflection shape that ``jaxgear run`` wrote to ``whine/housing_ods.vtu`` (the loudest of them by
ERP, at the phase of its largest displacement), coloured by the displacement amplitude, with the
undisplaced box's edges for reference. The skin is the one the ERP sums over
(``fem_prep.housing.outer_surface``); the housing is the case's (read from fem_prep's cache).

From the repository root, after ``jaxgear run CASE --out RUN``::

    python -m benchmarks.housing_ods_figure CASE RUN docs/img/housing_ods.png
"""

from __future__ import annotations

import argparse
import json
import pathlib

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection

import jaxgear.io as jio
from fem_prep.housing import outer_surface


def draw(case_name: str, run: str, png: str, label: str | None = None) -> dict:
    """Draw the ODS ``label`` (default: the loudest by ERP) of the run folder ``run`` of the
    housed case ``case_name``; returns what was drawn."""
    import meshio

    folder = pathlib.Path(run) / "whine"
    info = json.loads((folder / "housing.json").read_text())
    shapes = info["operating_deflection_shapes"]
    pick = (
        max(shapes, key=lambda s: s["erp_dB"])
        if label is None
        else next(s for s in shapes if s["label"] == label)
    )
    m = meshio.read(folder / "housing_ods.vtu")
    u = m.point_data[f"{pick['label']}_real"] + 1j * m.point_data[f"{pick['label']}_imag"]
    body = jio.load_case(case_name).housing_body()
    mesh = body.mesh.mesh
    skin = outer_surface(body.mesh)
    tri = mesh.facets[:, skin.facets].T  # (F, 3) vertex indices
    # the phase at which the skin's displacement is largest: max over φ of |Re(u e^{iφ})|²
    us = u[np.unique(tri)]
    phase = -0.5 * np.angle(np.sum(us * us))
    real = np.real(u * np.exp(1j * phase))
    x = mesh.p.T  # (N, 3) m, the housing's frame
    span = np.ptp(x, axis=0).max()
    amp = np.linalg.norm(np.abs(u), axis=1)  # |u| per node, each component's amplitude
    scale = 0.08 * span / np.abs(real[np.unique(tri)]).max()
    xd = x + scale * real[: len(x)]
    colour = amp[tri].mean(axis=1) * 1e9  # nm
    fig = Figure(figsize=(8.0, 6.2))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot(projection="3d")
    poly = Poly3DCollection(xd[tri], cmap="viridis", linewidths=0.1, edgecolors="k")
    poly.set_array(colour)
    ax.add_collection3d(poly)
    lo, hi = x.min(axis=0), x.max(axis=0)
    corners = np.array(
        [[a, b, c] for a in (lo[0], hi[0]) for b in (lo[1], hi[1]) for c in (lo[2], hi[2])]
    )
    edges = [
        (i, j)
        for i in range(8)
        for j in range(i + 1, 8)
        if np.count_nonzero(corners[i] != corners[j]) == 1
    ]
    ax.add_collection3d(
        Line3DCollection(
            [corners[[i, j]] for i, j in edges], colors="0.5", linewidths=0.8, linestyles="--"
        )
    )
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(hi - lo)
    ax.view_init(elev=22, azim=-58)
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(MaxNLocator(3))
    ax.set_xlabel("x (m)", labelpad=6)
    ax.set_ylabel("y (m)", labelpad=6)
    ax.set_zlabel("z (m)", labelpad=6)
    fig.colorbar(poly, ax=ax, shrink=0.6, label="displacement amplitude |u| (nm)")
    ax.set_title(
        f"{case_name}: operating deflection shape, order {pick['order']:g} at "
        f"{pick['speed_rad_s']:.0f} rad/s\n({pick['frequency_Hz']:.0f} Hz, ERP "
        f"{pick['erp_dB']:.1f} dB re 1 pW); x along the shafts, z up; displacement × {scale:.3g}, "
        "dashed: the box at rest",
        fontsize=9,
    )
    fig.tight_layout()
    fig.savefig(png, dpi=110)
    return {"png": png, "scale": float(scale), "max_nm": float(colour.max()), **pick}


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("case")
    p.add_argument("run", help="the jaxgear run output folder of the case")
    p.add_argument("png")
    p.add_argument("--label", help="the ODS to draw (default: the loudest)")
    a = p.parse_args(argv)
    print(json.dumps(draw(a.case, a.run, a.png, a.label), indent=1))


if __name__ == "__main__":
    main()
