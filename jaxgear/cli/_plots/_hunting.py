"""The planetary stage's quasi-static over the hunting period with per-tooth deviations: K_γ
and each mesh's TE against the sun's turns relative to the carrier."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._figure import savefig

__all__ = ["hunting_plot"]


def hunting_plot(path, turns, k_gamma, sun_te, ring_te, *, title: str, xlabel: str) -> None:
    """K_γ (top), the sun meshes' and the ring meshes' TE (µm, one curve per planet; middle and
    bottom) against ``turns`` (the span's abscissa, named by ``xlabel``)."""
    fig = Figure(figsize=(9.0, 8.0), layout="constrained")
    FigureCanvasAgg(fig)
    ax0, ax1, ax2 = fig.subplots(3, 1, sharex=True)
    ax0.plot(turns, k_gamma, lw=0.6, color="0.2")
    ax0.set_ylabel("K_γ (-)")
    ax0.set_title(title)
    for ax, te, name in ((ax1, sun_te, "sun"), (ax2, ring_te, "ring")):
        te = np.asarray(te) * 1e6
        for n in range(te.shape[1]):  # planet n's colour in both panels, labelled once
            ax.plot(turns, te[:, n], lw=0.5, color=f"C{n}",
                    label=f"planet {n + 1}" if ax is ax1 else None)
        ax.set_ylabel(f"{name}-mesh TE (µm)")
    for ax in (ax0, ax1, ax2):
        ax.grid(alpha=0.3)
    ax2.set_xlabel(xlabel)
    fig.legend(loc="outside lower center", ncols=min(np.shape(sun_te)[1], 6), fontsize=9,
               frameon=False)
    savefig(fig, path)
