"""The figures of ``jaxgear optimise`` and ``master-curve``: convergence, the objective map
with the optimiser's path, the Master Curve."""

from __future__ import annotations

import numpy as np
from matplotlib.ticker import MaxNLocator

from ._figure import finish, new_figure, savefig

__all__ = [
    "OBJECTIVE_WORDS",
    "UNSCALED_OBJECTIVE_AXES",
    "convergence_plot",
    "convergence_ylabel",
    "master_curve_plot",
    "optimiser_path_plot",
]


#: the optimisation objectives in words, for plot labels (the code names stay in the JSON files)
OBJECTIVE_WORDS = {
    "te_rms": "TE RMS",
    "te_ptp": "TE peak-to-peak",
    "robust_te_rms": "TE RMS over the torques",
    "max_line_load": "max line load",
    "line_load_lp": "line load Lp norm",
    "erp": "housing ERP",
    "sound_power": "radiated sound power",
}


#: the convergence axis of the objectives that are not scaled by the unmodified design's value
UNSCALED_OBJECTIVE_AXES = {
    "dynamic_factor": "dynamic factor (dynamic mesh force / static)",
    "load_centroid": "load_centroid: ((z̄ − b/2) / 0.1 b)²",
}


def convergence_ylabel(objective: str, unmodified: float, units: str) -> str:
    """The convergence plot's axis label for the optimiser's (scaled) objective history.

    Objectives scaled by the unmodified design's value (``unmodified``, in ``units``: "m",
    "N_per_m") read "<objective> / unmodified design (value unit)"; ``dynamic_factor`` (not
    scaled: a dynamic factor is already relative to the static force) and ``load_centroid``
    (scaled by a fixed 10 % of the face width, the unmodified pair is often centred) read as
    what they are."""
    own = UNSCALED_OBJECTIVE_AXES.get(objective)
    if own is not None:
        return own
    unit, k = {"m": ("µm", 1e6), "N_per_m": ("N/mm", 1e-3)}.get(units, (units, 1.0))
    name = OBJECTIVE_WORDS.get(objective, objective)
    return f"{name} / unmodified design ({unmodified * k:.3g} {unit})"


def convergence_plot(path, history, *, ylabel: str, title: str):
    """Objective per iteration (the start is iteration 0), integer iteration ticks; a log axis
    only where the values span a decade or more (on a narrower range a log axis reads
    "1.14×10⁰"). Returns the axes."""
    fig, ax = new_figure()
    v = np.asarray(history, dtype=float)
    ok = v[np.isfinite(v)]
    ax.plot(np.arange(v.size), v, "o-")
    if ok.size and ok.min() > 0 and ok.max() / ok.min() >= 10:
        ax.set_yscale("log")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    finish(fig, ax, path, xlabel="iteration", ylabel=ylabel, title=title, legend=False)
    return ax


def optimiser_path_plot(
    path, G, E_um, grid_um, path_g, path_e_um, opt, *, label: str, title: str
) -> None:
    """Objective map over relief extent Γ and depth E (µm) with the optimiser's path and the
    optimum ``opt = (Γ, E µm)``; ``grid_um`` has shape (len(G), len(E_um))."""
    fig, ax = new_figure()
    cs = ax.contourf(G, E_um, np.asarray(grid_um).T, levels=30, cmap="viridis")
    fig.colorbar(cs, ax=ax, label=label)
    ax.plot(path_g, path_e_um, "w.-", label="optimiser path")
    ax.plot(path_g[0], path_e_um[0], "wo", mfc="none", ms=9, label="start")
    ax.plot(*opt, "r*", ms=14, label=f"optimum Γ = {opt[0]:.3f}, E = {opt[1]:.2f} µm")
    ax.set_xlabel("relief extent Γ")
    ax.set_ylabel("relief depth E (µm)")
    ax.set_title(title)
    # below the axes: the map stays visible (white markers on a dark ground outside it)
    leg = fig.legend(loc="outside lower center", ncols=3, fontsize=9, frameon=True)
    leg.get_frame().set_facecolor("0.55")
    savefig(fig, path)


def master_curve_plot(
    path,
    G,
    E_um,
    grid_um,
    extent,
    depth_um,
    *,
    on_bound=None,
    family=None,
    title: str,
) -> list[str]:
    """TE RMS map (µm) over (Γ, E µm), the numerical Master Curve, its points on a bound of the
    depth interval (``on_bound``, bool per point) drawn apart, and the zero-fluctuation family
    ``(Γ, E µm)`` where it applies. Returns the legend labels."""
    fig, ax = new_figure()
    cs = ax.contourf(G, E_um, np.asarray(grid_um).T, levels=30, cmap="viridis")
    fig.colorbar(cs, ax=ax, label="TE RMS (µm), exact contact")
    extent = np.asarray(extent, dtype=float)
    depth_um = np.asarray(depth_um, dtype=float)
    ax.plot(extent, depth_um, "r.-", lw=2, label="Master Curve (numerical)")
    if on_bound is not None and np.any(on_bound):
        b = np.asarray(on_bound, dtype=bool)
        ax.plot(
            extent[b],
            depth_um[b],
            "X",
            ms=10,
            mfc="orange",
            mec="k",
            clip_on=False,
            zorder=5,
            label="on a bound of the depth interval (not a true optimum)",
        )
    if family is not None:
        ax.plot(*family, "w--", label="zero-fluctuation family")
    # a margin (grey, outside the map) round the map: points on a depth bound or at the end
    # extents are drawn whole, inside the axes; the legend below the axes covers none of them
    e0, e1 = float(np.min(E_um)), float(np.max(E_um))
    g0, g1 = float(np.min(G)), float(np.max(G))
    me, mg = 0.05 * (e1 - e0 or 1.0), 0.03 * (g1 - g0 or 1.0)
    ax.set_facecolor("0.85")
    ax.fill([], [], color="0.85", label="outside the computed map (margin)")
    ax.set_ylim(e0 - me, e1 + me)
    ax.set_xlim(min(g0, float(np.min(extent))) - mg, max(g1, float(np.max(extent))) + mg)
    ax.set_xlabel("relief extent Γ")
    ax.set_ylabel("relief depth E (µm)")
    ax.set_title(title)
    leg = fig.legend(loc="outside lower center", ncols=3, fontsize=8, frameon=False)
    labels = [t.get_text() for t in leg.get_texts()]
    savefig(fig, path)
    return labels


def bearing_choice_plot(path, names, start, optimum, *, ylabel: str, title: str) -> None:
    """The bearing choice's ranking: per fitting candidate (``names``, best first) its
    objective at its start and at its optimum (``None``: evaluated as given, one bar), in the
    units of ``ylabel``. Points, not bars, on an axis that holds the values only: the
    candidates often differ by a fraction of a percent, which bars from zero would hide."""
    fig, ax = new_figure()
    x = np.arange(len(names))
    if optimum is None:
        ax.plot(x, start, "o", ms=8, label="as given")
    else:
        ax.plot(x, start, "o", ms=8, mfc="none", label="clearance at its start")
        ax.plot(x, optimum, "o", ms=8, label="clearance optimised")
    ax.set_xticks(x, names)
    ax.set_xlim(-0.5, len(names) - 0.5)
    ax.margins(y=0.15)
    ax.ticklabel_format(axis="y", useOffset=False)
    finish(fig, ax, path, xlabel="candidate (best first)", ylabel=ylabel, title=title)
