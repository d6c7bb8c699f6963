"""Radiated noise's figures (``jaxgear run`` with ``[acoustics]``): the sound power level against
speed per order and overall (linear and A-weighted), the microphone spectra, and the surface map
of the radiated intensity on the housing's skin."""

from __future__ import annotations

import numpy as np
from matplotlib.colors import TwoSlopeNorm
from matplotlib.figure import Figure
from mpl_toolkits.mplot3d.art3d import Poly3DCollection

from ._figure import savefig

__all__ = ["intensity_map_plot", "microphone_plot", "sound_power_plot"]


def _levels(ax, x, levels, orders, total, total_label):
    for j, o in enumerate(orders):
        ax.plot(x, levels[:, j], "-", lw=1.2, marker=".", ms=3, label=f"order {o:g}")
    ax.plot(x, total, "k-", lw=2.0, label=total_label)
    ax.grid(True, alpha=0.3)


def sound_power_plot(path, speeds, orders, level, level_a, total, total_a, *, title) -> None:
    """L_W (dB re 1 pW) against the input speed: each order and the overall, linear (left) and
    A-weighted (right).

    Args:
        speeds: (S,) rad/s. orders: (O,). level, level_a: (S, O) dB and dB(A) (NaN: outside the
            band). total, total_a: (S,) the overall levels.
    """
    fig = Figure(figsize=(11, 4.8), layout="constrained")
    axes = fig.subplots(1, 2, sharey=True)
    _levels(axes[0], speeds, np.asarray(level), orders, total, "overall")
    _levels(axes[1], speeds, np.asarray(level_a), orders, total_a, "overall, A-weighted")
    axes[0].set_ylabel("sound power level L_W (dB re 1 pW)")
    axes[0].set_title("linear")
    axes[1].set_title("A-weighted (IEC 61672-1), dB(A)")
    for ax in axes:
        ax.set_xlabel("input speed (rad/s)")
        ax.legend(fontsize=8, loc="best")
    fig.suptitle(title)
    savefig(fig, path)


def microphone_plot(path, names, speeds, frequencies, orders, level, total_a, *, title) -> None:
    """The sound pressure level (dB re 20 µPa) at each microphone (a row each): against the input
    speed per order with the overall A-weighted level (left), and each order's line against its
    frequency (right: the spectrum the orders sweep).

    Args:
        names: (q,) microphone names. speeds: (S,) rad/s. frequencies: (S, O) Hz.
        level: (S, O, q) L_p (dB). total_a: (S, q) overall L_pA (dB(A)).
    """
    q = len(names)
    fig = Figure(figsize=(11, 2.9 * q + 1.0), layout="constrained")
    axes = np.atleast_2d(fig.subplots(q, 2, squeeze=False))
    level = np.asarray(level)
    for m, name in enumerate(names):
        a, b = axes[m]
        _levels(a, speeds, level[:, :, m], orders, np.asarray(total_a)[:, m],
                "overall, A-weighted (dB(A))")
        a.set_ylabel(f"{name}: L_p (dB re 20 µPa)")
        for j, o in enumerate(orders):
            b.plot(np.asarray(frequencies)[:, j], level[:, j, m], "-", lw=1.2, marker=".", ms=3,
                   label=f"order {o:g}")
        b.grid(True, alpha=0.3)
        if m == 0:
            a.legend(fontsize=8, loc="best")
            a.set_title("against speed")
            b.set_title("against frequency")
        if m == q - 1:
            a.set_xlabel("input speed (rad/s)")
            b.set_xlabel("frequency (Hz)")
    fig.suptitle(title)
    savefig(fig, path)


def intensity_map_plot(path, vertices, triangles, maps, *, title) -> None:
    """The radiated intensity (W/m², a vertex value, drawn per triangle as the mean of its
    vertices) on the surface, from two opposite corners (every face of a box seen once), one row
    per map; a diverging scale centred on zero (negative: power flowing back into the surface).

    Args:
        vertices: (n, 3) m. triangles: (m, 3). maps: {label: (n,) W/m²}.
    """
    rows = len(maps)
    fig = Figure(figsize=(10, 4.2 * rows + 0.6), layout="constrained")
    v = np.asarray(vertices) * 1e3
    tri = np.asarray(triangles)
    lo, hi = v.min(axis=0), v.max(axis=0)
    pad = 0.02 * float(np.max(hi - lo))  # a flat panel: a thin slab, not a singular axis
    lo, hi = lo - pad, hi + pad
    for r, (label, values) in enumerate(maps.items()):
        face = np.asarray(values)[tri].mean(axis=1)
        top = float(np.nanmax(np.abs(face))) or 1.0
        norm = TwoSlopeNorm(0.0, -top, top)
        for c, (elev, azim) in enumerate(((25, -55), (25, 125))):
            ax = fig.add_subplot(rows, 2, 2 * r + c + 1, projection="3d")
            coll = Poly3DCollection(v[tri], cmap="RdBu_r", norm=norm, edgecolor="none")
            coll.set_array(face)
            ax.add_collection3d(coll)
            ax.set_xlim(lo[0], hi[0])
            ax.set_ylim(lo[1], hi[1])
            ax.set_zlim(lo[2], hi[2])
            ax.set_box_aspect(np.maximum(hi - lo, 1e-9))
            ax.view_init(elev, azim)
            ax.set_xlabel("x (mm)", fontsize=8)
            ax.set_ylabel("y (mm)", fontsize=8)
            ax.set_zlabel("z (mm)", fontsize=8)
            ax.tick_params(labelsize=7)
            if c == 0:
                ax.set_title(label, fontsize=9)
        fig.colorbar(coll, ax=fig.axes[-2:], shrink=0.7, label="intensity (W/m²)")
    fig.suptitle(title)
    savefig(fig, path)
