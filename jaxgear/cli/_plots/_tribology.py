"""``jaxgear run``'s figure of the film and the sliding loss along the path of contact."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._figure import savefig

__all__ = ["path_of_contact_plot"]


def path_of_contact_plot(
    path, s, line_load, central, minimum, lam, loss, *, pitch, title, flash=None
):
    """Four panels against the base-plane coordinate s (mm) of every loaded cell: the line load
    (N/mm), the central and minimum film (µm), λ and the local sliding loss (W/mm); with
    ``flash`` (Blok's flash temperature θ_fl, K) a fifth; the pitch point ``pitch`` (m) marked.
    Arrays in SI units, one entry per loaded cell."""
    rows = 4 if flash is None else 5
    fig = Figure(figsize=(8, 2 * rows), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(rows, 1, sharex=True)
    x = np.asarray(s) * 1e3
    kw = {"ls": "none", "marker": ".", "ms": 2.5}
    axes[0].plot(x, np.asarray(line_load) * 1e-3, color="C0", **kw)
    axes[0].set_ylabel("line load (N/mm)")
    axes[1].plot(x, np.asarray(central) * 1e6, color="C0", label="central h_c", **kw)
    axes[1].plot(x, np.asarray(minimum) * 1e6, color="C3", label="minimum h_min", **kw)
    axes[1].set_ylabel("film (µm)")
    axes[1].legend(fontsize=8, frameon=False)
    axes[2].plot(x, np.asarray(lam), color="C2", **kw)
    axes[2].set_ylabel("λ = h_min / R_a")
    axes[3].plot(x, np.asarray(loss) * 1e-3, color="C1", **kw)
    axes[3].set_ylabel("sliding loss μ w v_g (W/mm)")
    if flash is not None:
        axes[4].plot(x, np.asarray(flash), color="C4", **kw)
        axes[4].set_ylabel("flash temp. θ_fl (K)")
    axes[-1].set_xlabel("path of contact s (mm, from its start at the gear's tip)")
    for ax in axes:
        ax.axvline(pitch * 1e3, color="0.3", lw=0.8, ls="--")
        ax.grid(alpha=0.3)
        ax.set_ylim(bottom=0)
    axes[0].set_title(title)
    savefig(fig, path)
