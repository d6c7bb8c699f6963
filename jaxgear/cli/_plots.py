"""Every figure the command line writes, as a gear engineer reads it.

The command modules (``_run``, ``_sweep``, ``_optimise``) compute; the functions here take the
computed data (SI units unless a name says otherwise) and a path, draw one figure and write it
with :func:`savefig` (atomic, PNG, 120 dpi). Figures are built on the Agg canvas directly, so
plotting never changes the process's pyplot backend (a notebook keeps its inline figures).
"""

from __future__ import annotations

import math
import os

import numpy as np

from .. import load_map
from ..dynamics import campbell_coincidences
from ..io import atomic_open

__all__ = [
    "campbell_plot",
    "coincidences",
    "convergence_plot",
    "convergence_ylabel",
    "dynamic_factor_plot",
    "face_map",
    "face_maps",
    "harmonic_crossings",
    "harris_plot",
    "load_map_plot",
    "map_difference_plot",
    "master_curve_plot",
    "mesh_stiffness_plot",
    "name_peaks",
    "new_figure",
    "optimiser_path_plot",
    "pressure_speed_plot",
    "savefig",
    "te_coincide",
    "transmission_error_plot",
]

FIGSIZE = (8, 4.5)
DPI = 120
#: exact and smooth TE are drawn as one curve when they differ by less than this share of the
#: plotted TE range (about the width of a line on a FIGSIZE figure)
TE_COINCIDE_SHARE = 0.01
#: a dynamic-factor maximum is a visible peak above this value
PEAK_MIN = 1.1
#: a sweep of at most this many speeds has its computed points marked (between them the curve
#: is a straight line, and a peak between two samples is not seen)
FEW_SPEEDS = 60


def new_figure(figsize=FIGSIZE):
    """A figure on the Agg canvas (no pyplot state) with one axes, constrained layout."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=figsize, layout="constrained")
    FigureCanvasAgg(fig)
    return fig, fig.add_subplot()


def savefig(fig, path) -> None:
    """Write ``fig`` as PNG (120 dpi, Agg) to ``path`` atomically and close it."""
    import sys

    from matplotlib.backends.backend_agg import FigureCanvasAgg

    try:
        if not isinstance(fig.canvas, FigureCanvasAgg):
            FigureCanvasAgg(fig)
        with atomic_open(path, "wb") as f:
            fig.savefig(f, format="png", dpi=DPI)
    finally:
        plt = sys.modules.get("matplotlib.pyplot")
        if plt is not None:  # a pyplot-managed figure: release it
            plt.close(fig)


def _finish(
    fig, ax, path, *, xlabel: str, ylabel: str, title: str, legend: bool = True, grid: bool = True
):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    if grid:
        ax.grid(alpha=0.3)
    labels = []
    if legend:
        labels = [t.get_text() for t in ax.legend().get_texts()]
    savefig(fig, path)
    return labels


def _hz(f: float) -> str:
    """2345.6 -> '2 346' (a space between thousands, as engineering drawings write it)."""
    return f"{f:,.0f}".replace(",", "\u2009")


# ---------------------------------------------------------------- quasi-static (jaxgear run)


def te_coincide(exact, smooth, span: float, share: float = TE_COINCIDE_SHARE) -> tuple[bool, float]:
    """Whether the exact and smooth TE curves are indistinguishable on a plot whose TE axis spans
    ``span`` (same unit): ``(max |exact - smooth| <= share * span, max |exact - smooth|)``."""
    d = float(np.max(np.abs(np.asarray(exact) - np.asarray(smooth))))
    return d <= share * span, d


def transmission_error_plot(
    path, x, curves: dict, *, title: str, driver: str = "pinion", note: str | None = None
) -> list[str]:
    """Quasi-static TE (µm) against the ``driver``'s position (mesh periods): the pinion's, a
    train's input's.

    ``curves``: ``{design label: {"exact": TE (m), "smooth": TE (m)}}`` (a design may have
    "exact" only). A design whose exact and smooth curves coincide (:func:`te_coincide`) is
    drawn once, its legend entry says so; otherwise exact is solid, smooth dashed. ``note``:
    a line under the plot (what a reader would otherwise take for an error). Returns the
    legend labels.
    """
    fig, ax = new_figure()
    um = {k: {m: np.asarray(a) * 1e6 for m, a in v.items()} for k, v in curves.items()}
    allv = np.concatenate([a for v in um.values() for a in v.values()])
    span = float(np.ptp(allv)) or 1.0
    colors = ("C0", "C3", "C2", "C1", "C4", "C5")
    for (lab, v), color in zip(um.items(), colors, strict=False):
        if "smooth" not in v:
            ax.plot(x, v["exact"], "-", color=color, label=f"{lab}, exact contact")
            continue
        same, d = te_coincide(v["exact"], v["smooth"], span)
        if same:
            within = f"within {d:.2g} µm" if d >= 1e-3 else "within 0.001 µm"
            ax.plot(x, v["exact"], "-", color=color, label=f"{lab} (exact = smooth {within})")
        else:
            ax.plot(x, v["exact"], "-", color=color, label=f"{lab}, exact contact")
            ax.plot(x, v["smooth"], "--", color=color, label=f"{lab}, smooth contact")
    ax.set_xlabel(f"{driver} position (mesh periods)")
    ax.set_ylabel("quasi-static TE (µm, along the line of action)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return _legend_below_and_save(fig, ax, path, note)


def _legend_below_and_save(fig, ax, path, note: str | None) -> list[str]:
    """The legend below the axes (never on the curves; ``note`` as its title), the figure saved
    to ``path``; returns the legend's labels."""
    leg = fig.legend(
        loc="outside lower center",
        ncols=_ncols(ax),
        fontsize=9,
        frameon=False,
        title=note,
        title_fontsize=8,
    )
    savefig(fig, path)
    return [t.get_text() for t in leg.get_texts()]


def _ncols(ax, width: int = 48) -> int:
    """Legend columns below a FIGSIZE figure: two unless a label is too long for half of it."""
    labels = ax.get_legend_handles_labels()[1]
    return 1 if any(len(t) > width for t in labels) else 2


def _fit_ncols(fig, ax, fontsize: float, most: int) -> int:
    """As many legend columns (at most ``most``) as fit the figure's width with its longest
    label: a legend below the axes never runs off either side."""
    labels = ax.get_legend_handles_labels()[1]
    if not labels:
        return 1
    char = 0.6 * fontsize  # points per character, a generous mean for DejaVu Sans
    entry = char * max(len(t) for t in labels) + 3.5 * fontsize  # handle and spacing
    width = fig.get_figwidth() * 72 * 0.97
    return int(max(1, min(most, len(labels), width // entry)))


def mesh_stiffness_plot(
    path, x, curves: dict, *, title: str, driver: str = "pinion", note: str | None = None
) -> list[str]:
    """Mesh stiffness (N/µm) against the ``driver``'s position (the pinion's, a train's
    input's); ``curves``: ``{label: K (N/m)}``; ``note``: a line under the plot."""
    fig, ax = new_figure()
    colors = ("C0", "C3", "C2", "C1", "C4", "C5")
    styles = ("-", "-", "--", ":", "-.", "--")  # a curve on top of another one still shows
    for (lab, k), color, ls in zip(curves.items(), colors, styles, strict=False):
        ax.plot(x, np.asarray(k) / 1e6, ls, color=color, label=lab)
    ax.set_xlabel(f"{driver} position (mesh periods)")
    ax.set_ylabel("mesh stiffness K(θ) (N/µm)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return _legend_below_and_save(fig, ax, path, note)


def load_map_plot(
    path,
    s_edges,
    z_edges,
    lmap,
    *,
    title: str,
    vmax: float | None = None,
    label: str = "max line load (N/mm)",
    unit: float = 1e3,
):
    """Max line load (N/mm) over the line of action (s) and the face width (z); SI inputs
    (``label`` and ``unit``, the SI value of one displayed unit, for another field: the contact
    pressure in MPa, 1e6).

    The colour scale runs from 0 to ``vmax`` (SI; default: the map's maximum): maps that are
    to be compared (a body at rest and at speed) pass the same ``vmax``. Returns the image's
    :class:`~matplotlib.collections.QuadMesh` (its ``norm`` is the colour scale)."""
    fig, ax = new_figure()
    data = np.asarray(lmap, dtype=float)
    if vmax is None:
        vmax = float(np.nanmax(data)) if np.isfinite(data).any() else 1.0
    pc = ax.pcolormesh(
        np.asarray(s_edges) * 1e3,
        np.asarray(z_edges) * 1e3,
        data.T / unit,
        shading="flat",
        cmap="viridis",
        vmin=0.0,
        vmax=max(vmax, 1e-12) / unit,
    )
    fig.colorbar(pc, ax=ax, label=label)
    _finish(
        fig,
        ax,
        path,
        xlabel="s along the line of action (mm): 0 = engagement (gear tip)",
        ylabel="z across the face (mm)",
        title=title,
        legend=False,
        grid=False,
    )
    return pc


def map_difference_plot(path, s_edges, z_edges, dmap, *, title: str, label: str, unit: float):
    """A signed difference of two maps of :func:`load_map_plot`'s kind (SI; ``unit``: the SI
    value of one displayed unit) on a diverging scale symmetric about 0 (red: the first map is
    higher), its largest magnitude in the title (a difference of 0.1 % of a map is invisible
    on the maps' own scale)."""
    fig, ax = new_figure()
    data = np.asarray(dmap, dtype=float) / unit
    big = float(np.nanmax(np.abs(data))) if np.isfinite(data).any() else 0.0
    lim = big or 1.0
    pc = ax.pcolormesh(
        np.asarray(s_edges) * 1e3,
        np.asarray(z_edges) * 1e3,
        data.T,
        shading="flat",
        cmap="RdBu_r",
        vmin=-lim,
        vmax=lim,
    )
    fig.colorbar(pc, ax=ax, label=label)
    unit_name = label[label.rfind("(") + 1 : label.rfind(")")] if "(" in label else ""
    _finish(
        fig,
        ax,
        path,
        xlabel="s along the line of action (mm): 0 = engagement (gear tip)",
        ylabel="z across the face (mm)",
        title=f"{title}\nlargest |Δ| {big:.3g} {unit_name}".rstrip(),
        legend=False,
        grid=False,
    )
    return pc


def face_map(
    path,
    result,
    field,
    pair,
    positions_per_pitch,
    *,
    title: str,
    label: str = "max line load (N/mm)",
    unit: float = 1e3,
):
    """One field of one mesh over a tooth's passage (roll position along the line of action ×
    face width), as :func:`~jaxgear.load_map` bins it: the line load (``field`` None, N/m) or a
    cell field of the shape of ``result.line_load`` (the Hertzian pressure of
    :func:`~jaxgear.contact_pressure`, Pa). ``result``: a quasi-static mesh result (P, L, N),
    or a dynamic one recorded with ``cell_loads`` (K, L, N); ``positions_per_pitch``: the
    result's steps per period of that mesh (the step of its contact lines along s).
    ``label``/``unit`` as :func:`load_map_plot`. The one plot of the quasi-static and the
    dynamic pressure maps."""
    s_edges, z, grid = load_map(
        result, positions_per_pitch, pair.base_pitch, pair.path_of_contact, field=field
    )
    dz = pair.face_width / len(z)
    return load_map_plot(
        path,
        s_edges,
        np.concatenate([[0.0], z + dz / 2]),
        grid,
        title=title,
        label=label,
        unit=unit,
    )


def face_maps(out_dir, names, result, max_pressure, pair, positions_per_pitch, title: str):
    """The load map and the Hertzian pressure map of one mesh's result over a tooth's passage
    (:func:`face_map` of the line load and of ``max_pressure``, (P, L, N) Pa), written
    to ``out_dir`` as ``names`` (load map, pressure map); ``title``: what the maps are of."""
    for name, field, what, label, unit in (
        (names[0], None, "load map", "max line load (N/mm)", 1e3),
        (names[1], max_pressure, "Hertzian contact pressure", "max contact pressure (MPa)", 1e6),
    ):
        face_map(
            os.path.join(out_dir, name),
            result,
            field,
            pair,
            positions_per_pitch,
            title=f"{what} {title}",
            label=label,
            unit=unit,
        )


def pressure_speed_plot(path, summary: dict) -> None:
    """The largest Hertzian contact pressure (MPa) against speed from a sweep summary: per
    speed the largest over the kept steps and the cells (``max_contact_pressure_Pa``; a
    train's per mesh, ``max_contact_pressure_mesh_Pa``), the quasi-static maximum at rest as a
    dashed line of the same colour (``max_contact_pressure_static_Pa``), the down sweep dashed,
    the speed of the dynamic pressure map marked."""
    fig, ax = new_figure()
    sp = _nan(summary["speeds_rad_s"])
    few = sp.size <= FEW_SPEEDS
    mk = {"marker": "o", "ms": 4, "clip_on": False} if few else {}
    if "max_contact_pressure_mesh_Pa" in summary:  # a train: one curve per mesh
        per = np.asarray(summary["max_contact_pressure_mesh_Pa"], dtype=float)  # (S, m)
        curves = [
            (name, per[:, k], summary["max_contact_pressure_static_mesh_Pa"][k])
            for k, name in enumerate(summary["mesh_names"])
        ]
    else:
        curves = [
            (
                "",
                _nan(summary["max_contact_pressure_Pa"]),
                summary["max_contact_pressure_static_Pa"],
            )
        ]
    up = {"independent": "", "up": ", sweep up", "down": ", sweep down", "both": ", sweep up"}[
        summary["direction"]
    ]
    for k, (name, p, p0) in enumerate(curves):
        color = f"C{k % 10}"
        who = f"{name}: " if name else ""
        ax.plot(sp, p / 1e6, "-", color=color, lw=1.8, label=f"{who}dynamic{up}", **mk)
        if p0 is not None:
            ax.axhline(p0 / 1e6, color=color, ls="--", lw=0.9, label=f"{who}quasi-static, at rest")
    if "max_contact_pressure_Pa_down" in summary:
        ax.plot(
            sp,
            _nan(summary["max_contact_pressure_Pa_down"]) / 1e6,
            "--",
            color="C3",
            label=("worst mesh: " if len(curves) > 1 else "") + "dynamic, sweep down",
        )
    m = summary.get("pressure_map_dynamic")
    if m:
        ax.plot(
            [m["speed_rad_s"]],
            [m["max_contact_pressure_Pa"] / 1e6],
            "*",
            ms=11,
            color="k",
            zorder=6,
            label="speed of the dynamic pressure map",
        )
    driver = summary.get("speed_of", "pinion")
    ax.set_xlim(sp.min(), sp.max())
    _finish(
        fig,
        ax,
        path,
        xlabel=f"{driver} speed (rad/s)",
        ylabel="max Hertzian contact pressure (MPa)",
        title=f"{summary['case']}: largest Hertzian pressure p₀ = √(w E*/(π R)) over the kept "
        "steps",
    )


def train_phasing_plot(
    path, layout, pairs, names, mesh_names, tip_radii, base_radii, x, stiffness, *, title: str
):
    """A gear train's layout and mesh phasing in one figure (two panels).

    Left: the gears in the plane (tip and base circles, centres, each gear's sense of rotation,
    each mesh's line of action between its base-circle tangent points, thick along its path of
    contact, in mm). Right: each
    mesh's stiffness K_k(θ) (N/µm) against the input's position (its mesh periods), each curve
    marked where its mesh angle is a whole number of mesh periods: the marks of mesh k sit at
    −phase_k / (ratio_k · mesh period angle) modulo one period (the layout's phasing).

    Args:
        layout: :class:`jaxgear.scenes.TrainLayout`. pairs: each mesh's
            :class:`~jaxgear.GearPair`. names: the gears' names. mesh_names: the meshes'.
            tip_radii,
            base_radii: each gear's (m). x: the input's position (mesh periods), (P,).
        stiffness: ``{mesh label: (K (N/m) (P,), phase marks (mesh periods of the input))}``.
    """
    import matplotlib.patches as mpatches

    fig, ax = new_figure(figsize=(11.0, 4.8))
    fig.delaxes(ax)
    lay, curves = fig.subplots(1, 2, width_ratios=(1.0, 1.4))
    mm = 1e3
    for i, name in enumerate(names):
        c = np.asarray(layout.centres[i]) * mm
        color = f"C{i % 10}"
        lay.add_patch(mpatches.Circle(c[:2], tip_radii[i] * mm, fill=False, color=color, lw=1.5))
        lay.add_patch(
            mpatches.Circle(c[:2], base_radii[i] * mm, fill=False, color=color, lw=0.8, ls=":")
        )
        spin = "↺" if layout.spins[i] > 0 else "↻"
        mates = [j for j in range(i) if np.allclose(layout.centres[j], layout.centres[i])]
        if mates:  # a compound gear: one label for the shaft, under the first gear's
            continue
        together = [
            n for j, n in enumerate(names) if np.allclose(layout.centres[j], layout.centres[i])
        ]
        lay.annotate(
            f"{' + '.join(together)} {spin}",
            c[:2],
            ha="center",
            va="center",
            fontsize=9,
            color=color,
        )
    for k, (line, pair) in enumerate(zip(layout.lines, pairs, strict=True)):
        t1, t = np.asarray(line["tangent_point"]) * mm, np.asarray(line["direction"])
        t2 = t1 + pair.center_distance * np.sin(pair.operating_pressure_angle) * mm * t
        a = t1 + pair.start_roll * mm * t  # the path of contact, engagement to recess
        b = a + pair.path_of_contact * mm * t
        lay.plot([t1[0], t2[0]], [t1[1], t2[1]], "k-", lw=0.6)
        lay.plot([a[0], b[0]], [a[1], b[1]], "k-", lw=2.5)
        lay.annotate(mesh_names[k], b[:2], fontsize=8, xytext=(4, 4), textcoords="offset points")
    lay.set_aspect("equal")
    lay.autoscale_view()
    lay.set_xlabel("x (mm)")
    lay.set_ylabel("y (mm)")
    lay.set_title("layout: tip and base circles, lines of action", fontsize=10)
    lay.grid(alpha=0.3)
    for (lab, (k, marks)), color in zip(
        stiffness.items(), ("C0", "C3", "C2", "C1", "C4"), strict=False
    ):
        curves.plot(x, np.asarray(k) / 1e6, color=color, label=lab)
        for m in np.atleast_1d(marks):
            curves.axvline(m, color=color, ls="--", lw=0.8)
    curves.set_xlabel("input position (mesh periods)")
    curves.set_ylabel("mesh stiffness K(θ) (N/µm)")
    curves.set_title("mesh phasing: dashed, each mesh's angle at a whole period", fontsize=10)
    curves.grid(alpha=0.3)
    # below the panel, never on the curves
    curves.legend(
        fontsize=8, loc="upper center", bbox_to_anchor=(0.5, -0.14), ncols=3, frameon=False
    )
    fig.suptitle(title)
    savefig(fig, path)


def harris_plot(
    path, torques, curves, *, design_torque: float, ylabel: str, title: str
) -> list[str]:
    """Harris map: TE (µm) against torque for several designs, the design torque marked.

    ``curves``: ``[(label, TE (m), matplotlib format), ...]``. Where ``torques`` contains the
    design torque, each curve's value there is ringed. Returns the legend labels.
    """
    fig, ax = new_figure()
    t = np.asarray(torques, dtype=float)
    at = np.flatnonzero(np.isclose(t, design_torque, rtol=1e-9, atol=0.0))
    colors = iter(("C0", "C3", "C2", "C1", "C4"))
    for lab, te, fmt in curves:
        kw = {} if any(ch in fmt for ch in "kbgrcmyw") else {"color": next(colors)}
        line = ax.plot(t, np.asarray(te) * 1e6, fmt, label=lab, **kw)[0]
        if at.size:
            ax.plot(
                t[at],
                np.asarray(te)[at] * 1e6,
                "o",
                ms=11,
                mfc="none",
                mec=line.get_color(),
                mew=1.5,
            )
    ax.axvline(
        design_torque, color="0.3", lw=0.8, ls="--", label=f"design torque {design_torque:g} N·m"
    )
    if at.size:
        ax.plot([], [], "o", ms=9, mfc="none", mec="0.3", label="value at the design torque")
    ax.set_ylim(bottom=0)
    ax.set_xlabel("pinion torque (N·m)")
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(alpha=0.3)
    leg = fig.legend(loc="outside lower center", ncols=3, fontsize=8.5, frameon=False)
    savefig(fig, path)
    return [t.get_text() for t in leg.get_texts()]


# ---------------------------------------------------------------- dynamics (jaxgear sweep)


def _nan(v) -> np.ndarray:
    return np.asarray([np.nan if x is None else x for x in v], dtype=float)


def _at_speed(summary: dict, freqs):
    """The modes' frequencies (Hz) as the sweep's critical speeds take them: at speed, (g, m)
    on the grid ``campbell_speeds_rad_s``, where ``campbell_at_speed``; else ``freqs`` and None."""
    if not summary.get("campbell_at_speed"):
        return np.asarray(freqs, dtype=float), None
    curves = np.array([_nan(row) for row in summary["natural_frequencies_at_speed_Hz"]])
    return curves, _nan(summary["campbell_speeds_rad_s"])


def coincidences(summary: dict, harmonics=(1, 2, 3, 4), min_share: float = 0.05) -> list[dict]:
    """Mode × mesh-harmonic coincidences of a sweep summary, by speed: the ``critical_speeds``
    entries and, for every elastic mode with at least ``min_share`` mesh energy, each harmonic's
    :func:`jaxgear.dynamics.campbell_coincidences` (``z1`` from ``mesh_frequency_Hz`` / speed).
    Each: ``mode``, ``harmonic``, ``speed_rad_s``, ``frequency_Hz``, ``mesh_energy_share``."""
    out = {(c["mode"], c["harmonic"]): dict(c) for c in summary.get("critical_speeds", [])}
    sp = _nan(summary.get("speeds_rad_s", []))
    fm = _nan(summary.get("mesh_frequency_Hz", []))
    ok = np.isfinite(sp) & np.isfinite(fm) & (sp > 0)
    if ok.any():
        z1 = float(np.median(fm[ok] * 2 * math.pi / sp[ok]))
        freqs = _nan(summary.get("natural_frequencies_Hz", []))
        share = _nan(summary.get("mesh_energy_share", [np.nan] * freqs.size))
        m = min(freqs.size, share.size)
        curves, grid = _at_speed(summary, freqs)
        found = campbell_coincidences(
            2 * math.pi * curves[..., :m],
            share[:m],
            z1,
            harmonics=harmonics,
            min_share=min_share,
            speeds=grid,
        )
        for c in found:
            out.setdefault((c["mode"], c["harmonic"]), c)
    # a train's other mesh orders (a second stage), named by their mesh
    names = summary.get("mesh_names", [])
    z0 = (summary.get("mesh_orders") or [None])[0]
    for k, row in enumerate(summary.get("critical_speeds_mesh") or ()):
        if k == 0 or z0 is None or abs(summary["mesh_orders"][k] - z0) < 1e-9 * z0:
            continue  # the first mesh's, or an order the first mesh shares (an idler's)
        for c in row:
            out.setdefault((c["mode"], c["harmonic"], k), {**c, "mesh": names[k]})
    return sorted(out.values(), key=lambda c: c["speed_rad_s"])


def coincidence_name(c: dict) -> str:
    mesh = f" of {c['mesh']}" if "mesh" in c else ""
    return f"mode {c['mode']} ({_hz(c['frequency_Hz'])} Hz) × H{c['harmonic']}{mesh}"


def _distance(c: dict, speed: float) -> float:
    share = max(float(c.get("mesh_energy_share", 1.0)), 1e-12)
    return abs(math.log(c["speed_rad_s"] / speed)) * math.sqrt(c["harmonic"] / share)


def name_peaks(speeds, df, candidates, min_value: float = PEAK_MIN) -> list[dict]:
    """Visible peaks of a dynamic-factor curve (local maxima above ``min_value`` that stand out by
    at least 2 % of the curve's range), each with the nearest coincidence of ``candidates``: the
    smallest |ln(peak speed / coincidence speed)| · sqrt(h / mesh energy share), so a strongly
    excited mode at a low harmonic wins over a faint one that happens to sit a little closer.
    Returns ``[{speed_rad_s, value, coincidence, name}]``."""
    from scipy.signal import find_peaks

    sp = np.asarray(speeds, dtype=float)
    y = np.asarray(df, dtype=float)
    good = np.isfinite(y)
    if good.sum() < 3:
        return []
    yy = np.where(good, y, np.nanmin(y))
    rng = float(np.nanmax(y) - np.nanmin(y))
    idx, _ = find_peaks(yy, height=min_value, prominence=max(0.02 * rng, 1e-6))
    out = []
    for i in idx:
        c = min(candidates, key=lambda c: _distance(c, sp[i])) if candidates else None
        out.append(
            {
                "speed_rad_s": float(sp[i]),
                "value": float(y[i]),
                "coincidence": c,
                "name": coincidence_name(c) if c else "no excited mode nearby",
            }
        )
    return out


def dynamic_factor_plot(path, summary: dict) -> list[dict]:
    """Dynamic factor against pinion speed (rad/s below, rpm on top) from a sweep summary:
    critical speeds as labelled vertical lines above the curve, every visible peak named after
    the nearest mode × harmonic coincidence. A sweep of at most :data:`FEW_SPEEDS` speeds has
    its computed speeds marked on the curves (the lines between them are no data). Returns the
    named peaks (:func:`name_peaks`)."""
    from matplotlib.transforms import blended_transform_factory

    fig, ax = new_figure()
    sp = _nan(summary["speeds_rad_s"])
    df = _nan(summary["dynamic_factor"])
    how = {"independent": "", "up": ", sweep up", "down": ", sweep down", "both": ", sweep up"}[
        summary["direction"]
    ]
    few = sp.size <= FEW_SPEEDS
    mk = {"marker": "o", "ms": 4, "clip_on": False} if few else {}  # end points unclipped
    n_sp = f", {sp.size} speeds (marked)" if few else ""
    ax.plot(sp, df, "-", color="C0", lw=1.8, label=f"dynamic mesh force / static{how}{n_sp}", **mk)
    if "dynamic_factor_down" in summary:
        ax.plot(
            sp,
            _nan(summary["dynamic_factor_down"]),
            "--",
            color="C3",
            label="dynamic mesh force / static, sweep down",
            **({"marker": "s", "ms": 3.5, "mfc": "none", "clip_on": False} if few else {}),
        )
    ax.plot(
        sp,
        _nan(summary["dynamic_factor_tooth"]),
        ":",
        color="C0",
        lw=1,
        label="max tooth force / quasi-static",
        **({"marker": ".", "ms": 4, "clip_on": False} if few else {}),
    )
    loss = _nan(summary["contact_loss"]) > 0
    if loss.any():
        ax.plot(sp[loss], df[loss], "o", ms=5, color="C1", zorder=6, label="teeth lose contact")
    bad = np.asarray(summary["result"]) != 0
    if bad.any():
        ax.plot(sp[bad], np.ones(bad.sum()), "x", color="k", label="diverged (see result)")
    # room above the curves for the labels: the data use the lower 60 % of the axes
    lo, hi = ax.get_ylim()
    ymax = np.nanmax(np.concatenate([df, _nan(summary["dynamic_factor_tooth"])]))
    hi = max(hi, ymax)
    ax.set_ylim(lo, lo + (hi - lo) / 0.6)
    ax.set_xlim(sp.min(), sp.max())
    trans = blended_transform_factory(ax.transData, ax.transAxes)
    cands = coincidences(summary, min_share=0.01)  # small shares still make visible peaks
    shown = [c for c in summary["critical_speeds"] if sp.min() <= c["speed_rad_s"] <= sp.max()]
    peaks = name_peaks(sp, df, cands)
    top = sorted(peaks, key=lambda p: -p["value"])[:PEAKS_NAMED]  # the peaks named
    named = {
        (p["coincidence"]["mode"], p["coincidence"]["harmonic"]) for p in top if p["coincidence"]
    }
    rest = [p for p in peaks if p not in top]
    if rest:
        ax.plot(
            [p["speed_rad_s"] for p in rest],
            [p["value"] for p in rest],
            "v",
            color="C3",
            ms=5,
            mfc="none",
            label=f"smaller peak (the {PEAKS_NAMED} highest are named)",
        )
    crit_texts = []
    for c in shown:
        ax.axvline(c["speed_rad_s"], color="0.55", ls="--", lw=0.8, zorder=0)
        if (c["mode"], c["harmonic"]) in named:  # the peak's label names it
            continue
        crit_texts.append(
            ax.text(
                c["speed_rad_s"],
                0.985,
                f"mode {c['mode']} × H{c['harmonic']}",
                transform=trans,
                rotation=90,
                fontsize=7,
                color="0.35",
                va="top",
                ha="center",
                bbox={"boxstyle": "square,pad=0.15", "fc": "white", "ec": "none"},
            )
        )
    if shown:
        ax.plot([], [], "--", color="0.55", lw=0.8, label="critical speed (mode × mesh harmonic)")

    top = ax.secondary_xaxis(
        "top", functions=(lambda w: w * 30 / math.pi, lambda n: n * math.pi / 30)
    )
    driver = summary.get("speed_of", "pinion")  # a train's: its input gear's
    top.set_xlabel(f"{driver} speed (rpm)")
    ax.set_xlabel(f"{driver} speed (rad/s)")
    ax.set_ylabel("dynamic mesh force / static")
    ax.set_title(
        f"{summary['case']}: dynamic factor ({summary['model']} model, {summary['solver']}, "
        f"{summary['contact']} contact)",
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    note = None
    if few:  # a coarse sweep's straight segments may cross a resonance: say so
        between = [
            c for c in shown if np.min(np.abs(sp - c["speed_rad_s"])) > 0.02 * c["speed_rad_s"]
        ]
        if between:
            n = len(between)
            note = (
                f"straight lines join the {sp.size} computed speeds: {n} critical "
                f"speed{'s lie' if n > 1 else ' lies'} between them, "
                f"{'their peaks' if n > 1 else 'its peak'} not computed"
            )
    fig.legend(
        loc="outside lower center",
        ncols=_fit_ncols(fig, ax, 8, 2 if few else 3),
        fontsize=8,
        frameon=False,
        title=note,
        title_fontsize=8,
    )
    _label_peaks(ax, peaks, sp.min(), sp.max(), avoid=crit_texts)
    savefig(fig, path)
    return peaks


#: the highest peaks of a dynamic factor curve that are named on the plot
PEAKS_NAMED = 3


def _label_peaks(ax, peaks: list[dict], s_lo: float, s_hi: float, avoid=()) -> None:
    """Name the :data:`PEAKS_NAMED` highest ``peaks`` (:func:`name_peaks`) above the curve (the
    others are marked by the caller). Each label takes the first offset, going up, where it lies inside the
    axes and clear of the labels placed before and of ``avoid`` (texts), aligned inward near
    either end of the axis; the figure must be drawn (its layout fixed)."""
    top = sorted(peaks, key=lambda p: -p["value"])[:PEAKS_NAMED]
    if not top:
        return
    from matplotlib.text import Text

    fig = ax.figure
    fig.canvas.draw()  # the layout fixes the axes: labels are placed in pixels
    renderer = fig.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    placed = [t.get_window_extent(renderer).padded(2) for t in avoid]
    for p in top:  # the highest first: it gets the place nearest its peak
        f = (p["speed_rad_s"] - s_lo) / ((s_hi - s_lo) or 1.0)
        has = ["left", "center", "right"] if f < 0.25 else ["right", "center", "left"]
        if 0.25 <= f <= 0.75:
            has = ["center", "left", "right"]

        def label(dy, ha, p=p):
            dx = {"left": -6, "right": 6, "center": 0}[ha]
            ann = ax.annotate(
                f"{p['name']}\nDF {p['value']:.2f}",
                (p["speed_rad_s"], p["value"]),
                xytext=(dx, dy),
                textcoords="offset points",
                ha=ha,
                va="bottom",
                fontsize=7.5,
                color="C3",
                bbox={"boxstyle": "round,pad=0.2", "fc": "white", "ec": "none", "alpha": 0.9},
                arrowprops={"arrowstyle": "->", "color": "C3", "lw": 0.8},
            )
            ann.set_in_layout(False)
            ann.update_positions(renderer)
            return ann, Text.get_window_extent(ann, renderer).padded(3)  # the text, no arrow

        box = None
        for dy, ha in [(dy, ha) for dy in (10, 34, 58, 82, 106) for ha in has]:
            ann, box = label(dy, ha)
            if (
                inside.x0 <= box.x0
                and box.x1 <= inside.x1
                and box.y1 <= inside.y1
                and not any(box.overlaps(b) for b in placed)
            ):
                break
            ann.remove()
            box = None
        if box is None:  # nowhere clear: the nearest place inside the figure
            ann, box = label(10, has[0])
        placed.append(box)


def harmonic_crossings(
    freqs_Hz, z1: int, s_max: float, harmonics=(1, 2, 3, 4), speeds=None
) -> list[dict]:
    """Where mesh harmonic h (f = h z1 Ω / 2π) crosses each mode frequency, for pinion speeds
    0 < Ω <= ``s_max`` (rad/s); with ``speeds`` (a grid), ``freqs_Hz`` has shape (g, m): the
    modes at those speeds. Returns ``[{frequency_Hz, harmonic, speed_rad_s}]``."""
    f = np.asarray(freqs_Hz, dtype=float)
    rows = campbell_coincidences(
        2 * math.pi * f,
        np.ones(f.shape[-1]),
        z1,
        s_max / 1.05,
        harmonics=harmonics,
        min_share=0.0,
        speeds=speeds,
    )
    return [
        {
            "frequency_Hz": c["frequency_Hz"] if speeds is not None else float(f[c["mode"]]),
            "harmonic": c["harmonic"],
            "speed_rad_s": c["speed_rad_s"],
        }
        for c in rows
        if c["speed_rad_s"] <= s_max
    ]


def campbell_plot(
    path, summary: dict, z1: int, harmonics=(1, 2, 3, 4), min_share: float = 0.01
) -> list[dict]:
    """Campbell diagram: mesh harmonics f = h z1 Ω / 2π (and a train's other mesh orders,
    ``mesh_orders``, dash-dotted) against the modes with at least
    ``min_share`` of their strain energy in the mesh (black: ≥ 5 %, grey: weaker), each mode
    labelled with its frequency at the right end, every crossing in the swept speed range
    marked (those of the weaker modes small and grey; below the first speed of the sweep none:
    the low modes' crossings crowd there and no speed was computed).
    Returns the crossings (:func:`harmonic_crossings`)."""
    fig, ax = new_figure()
    sp = _nan(summary["speeds_rad_s"])
    s_max = float(np.nanmax(sp)) * 1.05
    s_line = np.linspace(0, s_max, 50)
    freqs = _nan(summary["natural_frequencies_Hz"])
    # the modes at speed where the run has the rotating-frame terms (else constant)
    at_speed, grid = _at_speed(summary, freqs)
    curves = at_speed if grid is not None else np.vstack([freqs, freqs])
    line_grid = grid if grid is not None else np.array([0.0, s_max])

    def at(i, speed):
        return np.interp(speed, line_grid, curves[:, i])

    modes = [
        (i, f, e)
        for i, (f, e) in enumerate(zip(freqs, _nan(summary["mesh_energy_share"]), strict=True))
        if f > 0 and e >= min_share
    ]
    strong = [float(np.max(curves[:, i])) for i, f, e in modes if e >= 0.05]
    f_top = max([*strong, s_max * z1 / (2 * math.pi)]) * 1.12
    modes = [m for m in modes if m[1] < f_top]
    first = (summary.get("mesh_names") or ["mesh"])[0]
    for h in harmonics:
        ax.plot(s_line, h * s_line * z1 / (2 * math.pi), color=f"C{h - 1}", label=f"{first} H{h}")
    # a train's other mesh orders (a second stage): their first two harmonics, dash-dotted
    others = [
        (name, z)
        for name, z in zip(
            summary.get("mesh_names", []), summary.get("mesh_orders", []), strict=False
        )
        if abs(z - z1) > 1e-9 * z1
    ]
    for j, (name, z) in enumerate(others):
        for h in (1, 2):
            ax.plot(
                s_line,
                h * s_line * z / (2 * math.pi),
                color=f"C{h - 1}",
                ls="-.",
                lw=1.0 + 0.5 * j,
                label=f"{name} H{h}",
            )
    for i, _, e in modes:
        ax.plot(
            s_line,
            at(i, s_line),
            color="k" if e >= 0.05 else "0.6",
            ls="--",
            lw=0.9 if e >= 0.05 else 0.7,
        )
    # one label per group of modes closer than 3 % of the axis (they would print over each
    # other), at the right end, with their frequency there
    # (a label is about 5 % of the axis high: closer groups are moved up, never stacked)
    modes = [(i, float(at(i, s_max * 0.995)), e) for i, _, e in modes]
    groups: list[list] = []
    for m in sorted(modes, key=lambda m: m[1]):
        if groups and m[1] - groups[-1][-1][1] < 0.04 * f_top:
            groups[-1].append(m)
        else:
            groups.append([m])
    mode_labels = []
    y_free = -np.inf  # the lowest place for the next label
    for g in groups:
        ids = ", ".join(str(i) for i, _, _ in g)
        hz = ", ".join(_hz(f) for _, f, _ in g)
        y = max(g[-1][1] + 0.006 * f_top, y_free)
        y_free = y + 0.055 * f_top
        t = ax.text(
            s_max * 0.995,
            y,
            f"mode{'s' if len(g) > 1 else ''} {ids}: {hz} Hz",
            ha="right",
            va="bottom",
            fontsize=7.5,
            color="k" if max(e for _, _, e in g) >= 0.05 else "0.35",
            bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.8},
        )
        mode_labels.append(t)
    s_min = float(np.nanmin(sp)) * (1 - 1e-9)
    cross = []
    for faint in (False, True):
        cols = [i for i, _, e in modes if (e < 0.05) == faint]
        if not cols:
            continue
        drawn = at_speed[..., cols]
        group = harmonic_crossings(drawn, z1, s_max, harmonics, grid)
        for _, z in others:
            group += harmonic_crossings(drawn, z, s_max, (1, 2), grid)
        group = [c for c in group if c["speed_rad_s"] >= s_min]
        if group:
            ax.plot(
                [c["speed_rad_s"] for c in group],
                [c["frequency_Hz"] for c in group],
                "o",
                mfc="none",
                mec="0.55" if faint else "k",
                ms=3.5 if faint else 6,
                label="harmonic crossing, weak mode" if faint else "harmonic crossing",
            )
        cross += group
    crit = [c for c in summary["critical_speeds"] if c["speed_rad_s"] <= s_max]
    if crit:
        ax.plot(
            [c["speed_rad_s"] for c in crit],
            [c["frequency_Hz"] for c in crit],
            "o",
            color="C3",
            ms=4,
            label="critical speed (sweep.json)",
        )
    nd = [r for r in summary.get("nodal_diameter_resonances") or () if r["harmonic"] == 1]
    # one family of markers per condensed gear (a pair's wheel, a train's idler, ...)
    gears = list(dict.fromkeys(r.get("gear", "wheel") for r in nd))
    nd_labels = {}  # (direction, gear tag, colour): [(speed, frequency, n)], placed once laid out
    for j, gear in enumerate(gears):
        tag = f"{gear} " if len(gears) > 1 else ""
        for direction, marker, color in _ND_MARKERS[j % len(_ND_MARKERS)]:
            rows = [
                r
                for r in nd
                if r.get("gear", "wheel") == gear
                and r["direction"] == direction
                and r["frequency_hz"] < f_top
            ]
            if not rows:
                continue
            labelled = set()
            for r in rows:
                # the excitation order h Z ± n of the gear's rotation, in its frame (seed
                # (3.9)), at its speed: its turns per input turn
                ratio = r.get("speed_ratio") or summary.get("pinion_teeth", z1) / summary.get(
                    "wheel_teeth", z1
                )
                ax.plot(
                    s_line,
                    r["order"] * s_line * ratio / (2 * math.pi),
                    color=color,
                    ls=":",
                    lw=0.6,
                )
                if r["nodal_diameter"] in labelled:  # one label per family and direction
                    continue
                labelled.add(r["nodal_diameter"])
                nd_labels.setdefault((direction, tag, color), []).append(
                    (r["pinion_speed_rad_s"], r["frequency_hz"], r["nodal_diameter"])
                )
            ax.plot(
                [r["pinion_speed_rad_s"] for r in rows],
                [r["frequency_hz"] for r in rows],
                marker,
                color=color,
                ms=5,
                ls="none",
                label=f"{tag}{direction} ND resonance, Z{'+' if direction == 'backward' else '−'}n"
                if tag  # several gears: shorter, the legend holds one per gear
                else f"{direction} ND resonance, order Z{'+' if direction == 'backward' else '−'}n "
                "(body frame, (3.9))",
            )
    ax.set_ylim(0, f_top)
    ax.set_xlim(0, s_max)
    top = ax.secondary_xaxis(
        "top", functions=(lambda w: w * 30 / math.pi, lambda n: n * math.pi / 30)
    )
    driver = summary.get("speed_of", "pinion")  # a train's: its input gear's
    top.set_xlabel(f"{driver} speed (rpm)")
    ax.set_xlabel(f"{driver} speed (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(
        f"{summary['case']}: Campbell diagram, modes with ≥ {min_share:.0%} mesh strain energy "
        "(black ≥ 5 %)" + (", modes at speed" if summary.get("campbell_at_speed") else ""),
        fontsize=10,
    )
    ax.grid(alpha=0.3)
    fig.legend(
        loc="outside lower center",
        ncols=_fit_ncols(fig, ax, 8, 3 if nd else 4 if others else 6),
        fontsize=8,
        frameon=False,
    )
    if nd_labels:
        fig.canvas.draw()  # the layout fixes the axes: labels are placed in pixels
        _place_nd_labels(ax, nd_labels, avoid=mode_labels)
    savefig(fig, path)
    return cross


#: ND label offsets (points) from the resonance, tried in turn: backward labels above left of
#: their point, forward ones below right (the two families lie either side of the H1 line)
_ND_OFFSETS = {
    "backward": (
        "right",
        "bottom",
        [(-3, 3), (-3, 14), (-14, 3), (-14, 14), (-3, 26), (-26, 3), (30, 16), (30, 30)]
        + [(-16, -14), (-30, -24)],  # below the point: near the top of the axes
    ),
    "forward": (
        "left",
        "top",
        [(3, -3), (3, -14), (14, -3), (14, -14), (3, -26), (26, -3), (-30, -16), (-30, -30)]
        + [(16, 14), (30, 24)],  # above the point: near the bottom of the axes
    ),
}
_ND_STYLE = {"backward": ("−", "C4"), "forward": ("+", "C2")}
#: the ND resonance markers (direction, marker, colour) of the first and second condensed gear
_ND_MARKERS = (
    (("backward", "v", "C4"), ("forward", "^", "C2")),
    (("backward", "<", "C5"), ("forward", ">", "C8")),
)


def _nd_text(sign: str, ns: list[int]) -> str:
    ns = sorted(set(ns))
    if len(ns) == 1:
        return f"{sign}{ns[0]}ND"
    if ns == list(range(ns[0], ns[-1] + 1)):
        return f"{sign}{ns[0]}…{sign}{ns[-1]}ND"
    return ", ".join(f"{sign}{n}" for n in ns) + "ND"


def _place_nd_labels(ax, labels: dict, avoid=()) -> list:
    """Label the nodal-diameter resonances ``{direction: [(speed, frequency, n)]}`` without
    overlaps: each label takes the first offset of :data:`_ND_OFFSETS` where it lies inside the
    axes and clear of every label placed before (and of ``avoid``); one that fits nowhere joins
    the previous label of its direction ("−1…−4ND" at the first family's point). Needs a drawn
    figure (fixed layout). A key may also be (direction, text prefix, colour): the families of
    one of several condensed gears ("idler −2ND"). Returns the annotations."""
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

    renderer = ax.figure.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    placed = [t.get_window_extent(renderer).padded(1.5) for t in avoid]
    # and the markers (resonances, crossings, critical speeds): a label does not hide one
    for line in ax.get_lines():
        if line.get_marker() in (None, "None", "") or not len(line.get_xdata()):
            continue
        r = line.get_markersize() / 2 * ax.figure.dpi / 72
        xy = ax.transData.transform(np.c_[line.get_xdata(), line.get_ydata()])
        placed += [Bbox([[x - r, y - r], [x + r, y + r]]) for x, y in xy]
    out = []

    def label(anchor, ns, key, k):
        direction, prefix, color = key if isinstance(key, tuple) else (key, "", None)
        ha, va, offsets = _ND_OFFSETS[direction]
        sign, default = _ND_STYLE[direction]
        color = color or default
        ann = ax.annotate(
            prefix + _nd_text(sign, ns),
            anchor,
            textcoords="offset points",
            xytext=offsets[k],
            ha=ha,
            va=va,
            fontsize=7,
            color=color,
            gid="nd-label",
            bbox={"boxstyle": "square,pad=0.05", "fc": "white", "ec": "none", "alpha": 0.7},
            # a label moved off its point has a leader to it
            arrowprops=None
            if k == 0
            else {"arrowstyle": "-", "lw": 0.5, "color": color, "shrinkA": 0, "shrinkB": 3},
        )
        ann.set_in_layout(False)
        ann.update_positions(renderer)
        return ann, Text.get_window_extent(ann, renderer).padded(1.5)  # the text, no leader

    def put(anchor, ns, key, force=False):
        """The label at the first offset that fits, else None (``force``: at the offset with
        the fewest overlaps, inside the axes if any is)."""
        cost = []
        direction = key[0] if isinstance(key, tuple) else key
        for k in range(len(_ND_OFFSETS[direction][2])):
            ann, box = label(anchor, ns, key, k)
            out_ = not (inside.contains(box.x0, box.y0) and inside.contains(box.x1, box.y1))
            hits = sum(box.overlaps(p) for p in placed)
            if not out_ and not hits:
                return ann, box
            ann.remove()
            cost.append((out_, hits, k))
        return label(anchor, ns, key, min(cost)[2]) if force else (None, None)

    for key, families in labels.items():
        last = None  # (annotation, its families, anchor, box)
        for x, y, n in sorted(families):
            ann, box = put((x, y), [n], key)
            if ann is not None:
                last = (ann, [n], (x, y), box)
            elif last is None:
                ann, box = put((x, y), [n], key, force=True)
                last = (ann, [n], (x, y), box)
            else:  # join the previous label of this direction
                prev, ns, anchor, pbox = last
                prev.remove()
                out.remove(prev)
                placed.remove(pbox)
                ns = [*ns, n]
                ann, box = put(anchor, ns, key, force=True)
                last = (ann, ns, anchor, box)
            placed.append(box)
            out.append(ann)
    return out


# ---------------------------------------------------------------- optimisation


#: the optimisation objectives in words, for plot labels (the code names stay in the JSON files)
OBJECTIVE_WORDS = {
    "te_rms": "TE RMS",
    "te_ptp": "TE peak-to-peak",
    "robust_te_rms": "TE RMS over the torques",
    "max_line_load": "max line load",
    "line_load_lp": "line load Lp norm",
}


def convergence_ylabel(objective: str, unmodified: float, units: str) -> str:
    """The convergence plot's axis label for the optimiser's (scaled) objective history.

    Objectives scaled by the unmodified design's value (``unmodified``, in ``units``: "m",
    "N_per_m") read "<objective> / unmodified design (value unit)"; ``dynamic_factor`` (not
    scaled: a dynamic factor is already relative to the static force) and ``load_centroid``
    (scaled by a fixed 10 % of the face width, the unmodified pair is often centred) read as
    what they are."""
    if objective == "dynamic_factor":
        return "dynamic factor (dynamic mesh force / static)"
    if objective == "load_centroid":
        return "load_centroid: ((z̄ − b/2) / 0.1 b)²"
    unit, k = {"m": ("µm", 1e6), "N_per_m": ("N/mm", 1e-3)}.get(units, (units, 1.0))
    name = OBJECTIVE_WORDS.get(objective, objective)
    return f"{name} / unmodified design ({unmodified * k:.3g} {unit})"


def convergence_plot(path, history, *, ylabel: str, title: str):
    """Objective per iteration (the start is iteration 0), integer iteration ticks; a log axis
    only where the values span a decade or more (on a narrower range a log axis reads
    "1.14×10⁰"). Returns the axes."""
    from matplotlib.ticker import MaxNLocator

    fig, ax = new_figure()
    v = np.asarray(history, dtype=float)
    ok = v[np.isfinite(v)]
    ax.plot(np.arange(v.size), v, "o-")
    if ok.size and ok.min() > 0 and ok.max() / ok.min() >= 10:
        ax.set_yscale("log")
    ax.xaxis.set_major_locator(MaxNLocator(integer=True))
    _finish(fig, ax, path, xlabel="iteration", ylabel=ylabel, title=title, legend=False)
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


def te_spectrum_plot(path, theta_rev, te, spectrum, *, title: str, mesh_harmonics: int = 3):
    """The TE over the deviation span (µm against pinion revolutions) above its order spectrum
    (µm against pinion orders up to (``mesh_harmonics`` + ½) z1), the mesh orders and the
    shaft-order sidebands around them marked and labelled (:meth:`jaxgear.TESpectrum.lines`)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(9.0, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    ax0, ax1 = fig.subplots(2, 1)
    ax0.plot(theta_rev, np.asarray(te) * 1e6, lw=0.6)
    ax0.set_xlabel("pinion position (revolutions)")
    ax0.set_ylabel("quasi-static TE (µm)")
    ax0.set_title(title)
    ax0.grid(alpha=0.3)
    z1 = spectrum.teeth[0]
    keep = (spectrum.orders > 0) & (spectrum.orders <= (mesh_harmonics + 0.5) * z1)
    ax1.vlines(spectrum.orders[keep], 0.0, spectrum.amplitude[keep] * 1e6, lw=0.7, color="0.4")
    top = float(spectrum.amplitude[keep].max() * 1e6) if keep.any() else 1.0
    for line in spectrum.lines(mesh_harmonics):
        a = line["amplitude_m"] * 1e6
        sideband = any(c in line["label"] for c in "−+") or "shaft" in line["label"]
        color = "C0" if sideband else "C3"  # mesh orders red, shaft orders and sidebands blue
        ax1.plot(line["bin_order"], a, "o", ms=3.5, color=color)
        if a > 0.02 * top:
            ax1.annotate(
                line["label"],
                (line["bin_order"], a),
                textcoords="offset points",
                xytext=(2, 4),
                rotation=90,
                fontsize=7,
                color=color,
            )
    ax1.set_xlabel(f"pinion order (events per revolution; mesh order = z1 = {z1})")
    ax1.set_ylabel("TE amplitude (µm)")
    ax1.set_ylim(0.0, top * 1.35 or 1.0)
    ax1.grid(alpha=0.3)
    savefig(fig, path)
