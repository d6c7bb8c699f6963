"""``jaxgear size``'s figures: the Pareto front of each pair of objectives, and the objectives
over the contact ratios ε_α, ε_β (where the design rules show: contact ratios near whole numbers
for a quiet mesh, a larger ε_α for a smaller sliding loss), and the dynamics stage's dynamic
factor and whine against speed."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._figure import new_figure, savefig

__all__ = ["contact_ratio_plot", "pareto_pair_plot", "sizing_dynamics_plot"]

#: the chosen design's marker
CHOSEN = {"marker": "*", "s": 220, "color": "gold", "edgecolor": "k", "linewidths": 0.8,
          "zorder": 5}


def _axis(name: str, words: dict) -> tuple[str, float]:
    """(axis label, factor from the column's SI unit) of an objective column."""
    label, factor = words.get(name, (name, 1.0))
    return label, factor


def pareto_pair_plot(path, columns: dict, feasible, rank, chosen, x: str, y: str, *,
                     words: dict, senses: dict, title: str) -> None:
    """One pair of objectives: every feasible candidate grey, the Pareto front (rank 1 over all
    the objectives) highlighted and joined along ``x``, the chosen design a star; arrows name
    each axis's better direction. ``words``: column → (axis label, factor); ``senses``: column
    → "min" | "max"; ``chosen``: its row or None."""
    fig, ax = new_figure()
    (xl, xf), (yl, yf) = _axis(x, words), _axis(y, words)
    cx, cy = np.asarray(columns[x], float) * xf, np.asarray(columns[y], float) * yf
    ok = np.asarray(feasible) & np.isfinite(cx) & np.isfinite(cy)
    ax.scatter(cx[ok], cy[ok], s=9, color="0.7", label=f"feasible ({int(ok.sum())})",
               linewidths=0)
    front = np.flatnonzero(np.asarray(rank) == 1)
    front = front[np.argsort(cx[front], kind="stable")]
    ax.scatter(cx[front], cy[front], s=16, color="C3", zorder=3,
               label=f"Pareto front over all objectives ({front.size})")
    # the front of this pair alone: the staircase a designer reads the trade-off from
    pair = _pair_front(cx[ok], cy[ok], senses[x], senses[y])
    if pair.size:
        # the boundary of what the pair's front dominates: along the sweep, across then over
        ax.plot(cx[ok][pair], cy[ok][pair], color="C3", lw=1.0, drawstyle="steps-post",
                label="front of these two")
    if chosen is not None:
        ax.scatter([cx[chosen]], [cy[chosen]], label=f"chosen design (row {chosen})", **CHOSEN)
    ax.set_xlabel(f"{xl}  ({'lower' if senses[x] == 'min' else 'higher'} is better)")
    ax.set_ylabel(f"{yl}  ({'lower' if senses[y] == 'min' else 'higher'} is better)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="best", framealpha=0.9)
    savefig(fig, path)


def _pair_front(x, y, sx: str, sy: str) -> np.ndarray:
    """The indices of the non-dominated points of two objectives (ordered along x): a sweep in
    x, keeping each point better in y than every point before it."""
    ox = x if sx == "min" else -x
    oy = y if sy == "min" else -y
    order = np.lexsort((oy, ox))
    keep, best = [], np.inf
    for i in order:
        if oy[i] < best:
            keep.append(i)
            best = oy[i]
    return np.asarray(keep, dtype=int)


def _whole_numbers(ax, values, axis: str) -> None:
    """The axis from the whole number below ``values`` to the one above, each dashed."""
    if values.size == 0:
        return
    lo, hi = int(np.floor(values.min())), int(np.ceil(values.max()))
    hi = max(hi, lo + 1)
    line = ax.axvline if axis == "x" else ax.axhline
    for k in range(lo, hi + 1):
        line(k, color="0.4", lw=0.8, ls="--")
    pad = 0.03 * (hi - lo)
    (ax.set_xlim if axis == "x" else ax.set_ylim)(lo - pad, hi + pad)


def contact_ratio_plot(path, columns: dict, feasible, rank, chosen, objectives, *,
                       words: dict, title: str) -> None:
    """One column of panels per objective, over the contact ratios of the feasible candidates:
    above, the objective against the transverse contact ratio ε_α, coloured by the overlap
    ratio ε_β; below, the (ε_α, ε_β) plane coloured by the objective. The front ringed, the
    chosen design a star, whole numbers of ε_α and ε_β dashed (TE is least near them), the
    contact ratios' axes from the whole number below the candidates to the one above."""
    k = len(objectives)
    fig = Figure(figsize=(4.2 * k, 8.4), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(2, k, sharex=True, squeeze=False)
    ea, eb = np.asarray(columns["eps_alpha"], float), np.asarray(columns["eps_beta"], float)
    ok = np.asarray(feasible) & np.isfinite(ea) & np.isfinite(eb)
    front = np.flatnonzero(np.asarray(rank) == 1)
    ring = {"s": 34, "facecolors": "none", "edgecolors": "C3", "linewidths": 0.8}
    for j, (name, sense) in enumerate(objectives):
        top, ax = axes[0, j], axes[1, j]
        label, factor = _axis(name, words)
        better = "lower" if sense == "min" else "higher"
        v = np.asarray(columns[name], float) * factor
        by_beta = top.scatter(ea[ok], v[ok], c=eb[ok], s=14, cmap="viridis", linewidths=0)
        top.scatter(ea[front], v[front], label="Pareto front", **ring)
        top.set_ylabel(f"{label}\n({better} is better)", fontsize=9)
        cmap = "viridis_r" if sense == "min" else "viridis"  # yellow is better either way
        sc = ax.scatter(ea[ok], eb[ok], c=v[ok], s=14, cmap=cmap, linewidths=0)
        ax.scatter(ea[front], eb[front], **ring)
        if chosen is not None:
            top.scatter([ea[chosen]], [v[chosen]], label="chosen", **CHOSEN)
            ax.scatter([ea[chosen]], [eb[chosen]], **CHOSEN)
        fig.colorbar(sc, ax=ax, location="bottom", shrink=0.9, pad=0.02).set_label(
            f"{label} ({better} is better)", fontsize=8)
        _whole_numbers(ax, ea[ok], "x")
        _whole_numbers(ax, eb[ok], "y")
        _whole_numbers(top, ea[ok], "x")
        ax.set_xlabel("transverse contact ratio ε_α")
        ax.set_ylabel("overlap ratio ε_β")
        for a in (top, ax):
            a.grid(alpha=0.3)
    fig.colorbar(by_beta, ax=axes[0, -1], location="right", shrink=0.9).set_label(
        "overlap ratio ε_β (colour, above)", fontsize=8)
    axes[0, 0].legend(fontsize=8, loc="best", framealpha=0.9)
    fig.suptitle(title)
    savefig(fig, path)


def sizing_dynamics_plot(path, curves, columns: dict, speed: float, *, title: str) -> None:
    """The dynamics stage's candidates (``curves``, :class:`jaxgear.sizing.DynamicsCurves`):
    above, the dynamic factor K_v against the pinion speed (1/min), each candidate's largest
    marked; below, the whine (the dynamic mesh force's RMS over the first mesh orders, N); the
    spec's ``speed`` (rad/s) dashed. Each candidate named by its row, module, teeth, contact
    ratios and flanks (``columns``: the table's)."""
    fig = Figure(figsize=(8.0, 7.2), layout="constrained")
    FigureCanvasAgg(fig)
    top, low = fig.subplots(2, 1, sharex=True)
    rpm = 30 / np.pi
    x = np.asarray(curves.speeds, float) * rpm
    for j, i in enumerate(curves.rows):
        label = (f"row {i}: {columns['normal_module_m'][i] * 1e3:g} mm {columns['z1'][i]}/"
                 f"{columns['z2'][i]}, ε_α {columns['eps_alpha'][i]:.2f}, ε_β "
                 f"{columns['eps_beta'][i]:.2f}, {curves.flanks[j]} flanks")
        kv = np.asarray(curves.dynamic_factor[j], float)
        line = top.plot(x, kv, marker=".", ms=4, lw=1.2, label=label)[0]
        if np.isfinite(kv).any():
            k = int(np.nanargmax(kv))
            top.scatter([x[k]], [kv[k]], s=40, color=line.get_color(), zorder=4)
        low.plot(x, curves.whine_force[j], marker=".", ms=4, lw=1.2, color=line.get_color())
    for ax in (top, low):
        ax.axvline(speed * rpm, color="0.4", ls="--", lw=0.9)
        ax.grid(alpha=0.3)
    top.text(speed * rpm, 1.0, " the spec's speed", transform=top.get_xaxis_transform(),
             va="top", ha="left", fontsize=8, color="0.3")
    top.set_ylabel("dynamic factor K_v (largest mesh force / static)")
    low.set_ylabel("whine: dynamic mesh force,\nmesh orders 1-3, RMS (N)")
    low.set_xlabel("pinion speed (1/min)")
    top.set_title(title)
    top.legend(fontsize=8, loc="best", framealpha=0.9)
    savefig(fig, path)
