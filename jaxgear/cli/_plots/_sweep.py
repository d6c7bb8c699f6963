"""The speed-sweep figures of ``jaxgear sweep``: the dynamic factor with its peaks named after
the nearest mode × mesh-harmonic coincidence, and the largest Hertzian pressure per speed."""

from __future__ import annotations

import dataclasses
import itertools
import math

import numpy as np
from matplotlib.text import Text
from matplotlib.transforms import blended_transform_factory

from ...dynamics import campbell_coincidences
from ._campbell import modes_on_grid
from ._figure import finish, fit_legend_columns, floats, hz_text, new_figure, savefig

__all__ = [
    "DIRECTIONS",
    "FEW_SPEEDS",
    "PEAKS_NAMED",
    "PEAK_MIN",
    "coincidence_name",
    "coincidences",
    "dynamic_factor_plot",
    "mode_number",
    "name_peaks",
    "pressure_speed_plot",
]


#: a dynamic-factor maximum is a visible peak above this value
PEAK_MIN = 1.1


#: a sweep of at most this many speeds has its computed points marked (between them the curve
#: is a straight line, and a peak between two samples is not seen)
FEW_SPEEDS = 60


@dataclasses.dataclass(frozen=True)
class Direction:
    """How a sweep went over its speeds (``jaxgear sweep --direction``), as its figures draw it:
    ``label``, what the legend adds to the first sweep's curves; ``down``, whether a second
    sweep went down the speeds (the summary's ``*_down`` curves, drawn dashed)."""

    label: str
    down: bool = False


#: each ``--direction`` (a sweep summary's ``direction``) as its figures draw it
DIRECTIONS = {
    "independent": Direction(""),
    "up": Direction(", sweep up"),
    "down": Direction(", sweep down"),
    "both": Direction(", sweep up", down=True),
}


def pressure_speed_plot(path, summary: dict, curves: list[tuple]) -> None:
    """The largest Hertzian contact pressure (MPa) against speed from a sweep summary:
    ``curves``, ``(mesh name, per speed the largest over the kept steps and the cells (Pa),
    the quasi-static maximum at rest (Pa) or None)`` of each mesh (a pair's one unnamed:
    :func:`jaxgear.cli._case_kinds.pressure_curves`), the one at rest as a dashed line of the
    same colour, the down sweep dashed, the speed of the dynamic pressure map marked."""
    fig, ax = new_figure()
    sp = floats(summary["speeds_rad_s"])
    few = sp.size <= FEW_SPEEDS
    mk = {"marker": "o", "ms": 4, "clip_on": False} if few else {}
    direction = DIRECTIONS[summary["direction"]]
    up = direction.label
    for k, (name, p, p0) in enumerate(curves):
        color = f"C{k % 10}"
        who = f"{name}: " if name else ""
        p = floats(p)
        ax.plot(sp, p / 1e6, "-", color=color, lw=1.8, label=f"{who}dynamic{up}", **mk)
        if p0 is not None:
            ax.axhline(p0 / 1e6, color=color, ls="--", lw=0.9, label=f"{who}quasi-static, at rest")
    if direction.down:
        ax.plot(
            sp,
            floats(summary["max_contact_pressure_Pa_down"]) / 1e6,
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
    finish(
        fig,
        ax,
        path,
        xlabel=f"{driver} speed (rad/s)",
        ylabel="max Hertzian contact pressure (MPa)",
        title=f"{summary['case']}: largest Hertzian pressure p₀ = √(w E*/(π R)) over the kept "
        "steps",
    )


def coincidences(summary: dict, harmonics=(1, 2, 3, 4), min_share: float = 0.05) -> list[dict]:
    """Mode × mesh-harmonic coincidences of a sweep summary, by speed: the ``critical_speeds``
    entries and, for every elastic mode with at least ``min_share`` mesh energy, each harmonic's
    :func:`jaxgear.dynamics.campbell_coincidences` (``z1`` from ``mesh_frequency_Hz`` / speed).
    Each: ``mode``, ``harmonic``, ``speed_rad_s``, ``frequency_Hz``, ``mesh_energy_share``."""
    out = {(c["mode"], c["harmonic"]): dict(c) for c in summary.get("critical_speeds", [])}
    sp = floats(summary.get("speeds_rad_s", []))
    fm = floats(summary.get("mesh_frequency_Hz", []))
    ok = np.isfinite(sp) & np.isfinite(fm) & (sp > 0)
    if ok.any():
        z1 = float(np.median(fm[ok] * 2 * math.pi / sp[ok]))
        freqs = floats(summary.get("natural_frequencies_Hz", []))
        share = floats(summary.get("mesh_energy_share", [np.nan] * freqs.size))
        m = min(freqs.size, share.size)
        curves, grid = modes_on_grid(summary, freqs)
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


def mode_number(c: dict) -> int:
    """A coincidence's mode as the figures and ``jaxgear modes`` number it: 1-based (the
    ``mode`` of ``sweep.json``'s ``critical_speeds`` is the 0-based index into the modal
    analysis' frequencies, rigid modes included, as ``modes.json``'s list)."""
    return int(c["mode"]) + 1


def coincidence_name(c: dict) -> str:
    mesh = f" of {c['mesh']}" if "mesh" in c else ""
    return (f"mode {mode_number(c)} ({hz_text(c['frequency_Hz'])} Hz) × "
            f"H{c['harmonic']}{mesh}")


def _distance(c: dict, speed: float) -> float:
    share = max(float(c.get("mesh_energy_share", 1.0)), 1e-12)
    return abs(math.log(c["speed_rad_s"] / speed)) * math.sqrt(c["harmonic"] / share)


def name_peaks(speeds, df, candidates, min_value: float = PEAK_MIN) -> list[dict]:
    """Visible peaks of a dynamic-factor curve (local maxima above ``min_value`` that stand out by
    at least 2 % of the curve's range), each with the nearest coincidence of ``candidates``: the
    smallest |ln(peak speed / coincidence speed)| · sqrt(h / mesh energy share), so a strongly
    excited mode at a low harmonic wins over a faint one that happens to sit a little closer.
    Returns ``[{speed_rad_s, value, coincidence, name}]``."""
    sp = np.asarray(speeds, dtype=float)
    y = np.asarray(df, dtype=float)
    good = np.isfinite(y)
    if good.sum() < 3:
        return []
    yy = np.where(good, y, np.nanmin(y))
    rng = float(np.nanmax(y) - np.nanmin(y))
    # lazy: scipy.signal costs 0.4 s at import and only the sweep's plot needs it
    from scipy.signal import find_peaks

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
    fig, ax = new_figure()
    sp = floats(summary["speeds_rad_s"])
    df = floats(summary["dynamic_factor"])
    direction = DIRECTIONS[summary["direction"]]
    how = direction.label
    few = sp.size <= FEW_SPEEDS
    mk = {"marker": "o", "ms": 4, "clip_on": False} if few else {}  # end points unclipped
    n_sp = f", {sp.size} speeds (marked)" if few else ""
    ax.plot(sp, df, "-", color="C0", lw=1.8, label=f"dynamic mesh force / static{how}{n_sp}", **mk)
    if direction.down:
        ax.plot(
            sp,
            floats(summary["dynamic_factor_down"]),
            "--",
            color="C3",
            label="dynamic mesh force / static, sweep down",
            **({"marker": "s", "ms": 3.5, "mfc": "none", "clip_on": False} if few else {}),
        )
    ax.plot(
        sp,
        floats(summary["dynamic_factor_tooth"]),
        ":",
        color="C0",
        lw=1,
        label="max tooth force / quasi-static",
        **({"marker": ".", "ms": 4, "clip_on": False} if few else {}),
    )
    loss = floats(summary["contact_loss"]) > 0
    if loss.any():
        ax.plot(sp[loss], df[loss], "o", ms=5, color="C1", zorder=6, label="teeth lose contact")
    bad = np.asarray(summary["result"]) != 0
    if bad.any():
        ax.plot(sp[bad], np.ones(bad.sum()), "x", color="k", label="diverged (see result)")
    # room above the curves for the labels: the data use the lower 60 % of the axes
    lo, hi = ax.get_ylim()
    ymax = np.nanmax(np.concatenate([df, floats(summary["dynamic_factor_tooth"])]))
    hi = max(hi, ymax)
    ax.set_ylim(lo, lo + (hi - lo) / 0.6)
    ax.set_xlim(sp.min(), sp.max())
    trans = blended_transform_factory(ax.transData, ax.transAxes)
    cands = coincidences(summary, min_share=0.01)  # small shares still make visible peaks
    shown = [c for c in summary["critical_speeds"] if sp.min() <= c["speed_rad_s"] <= sp.max()]
    peaks = name_peaks(sp, df, cands)
    top = sorted(peaks, key=lambda p: -p["value"])[:PEAKS_NAMED]  # the peaks named
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
    named = {  # the coincidences the peak labels name: their lines labelled short
        (p["coincidence"]["mode"], p["coincidence"]["harmonic"]) for p in top if p["coincidence"]
    }
    crit_texts = []
    for c in shown:
        # every line labelled at its top (also where a named peak's label names it, which may
        # stand away from its line: then its harmonic only, above that label)
        ax.axvline(c["speed_rad_s"], color="0.55", ls="--", lw=0.8, zorder=0)
        short = (c["mode"], c["harmonic"]) in named  # a peak's label names it below
        crit_texts.append(
            ax.text(
                c["speed_rad_s"],
                0.985,
                # a line a peak's label names: its short name, above that label
                f"H{c['harmonic']}" if short else f"mode {mode_number(c)} × H{c['harmonic']}",
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
        ncols=fit_legend_columns(fig, ax, 8, 2 if few else 3),
        fontsize=8,
        frameon=False,
        title=note,
        title_fontsize=8,
    )
    _label_peaks(ax, peaks, sp.min(), sp.max(), avoid=crit_texts)
    savefig(fig, path)
    return peaks


def _curve_points(ax, step_px: float = 2.0) -> np.ndarray:
    """Points (display pixels, (n, 2)) along every data curve of ``ax`` (its lines of more
    than two points), at most ``step_px`` apart along each straight segment."""
    out = [np.zeros((0, 2))]
    for line in ax.get_lines():
        xy = np.column_stack([np.asarray(line.get_xdata(), float),
                              np.asarray(line.get_ydata(), float)])
        xy = xy[np.all(np.isfinite(xy), axis=1)]
        if len(xy) < 3:
            continue
        px = ax.transData.transform(xy)
        for a, b in itertools.pairwise(px):
            n = max(2, int(np.hypot(*(b - a)) / step_px) + 1)
            out.append(a + np.linspace(0.0, 1.0, n)[:, None] * (b - a))
    return np.concatenate(out)


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
    fig = ax.figure
    fig.canvas.draw()  # the layout fixes the axes: labels are placed in pixels
    renderer = fig.canvas.get_renderer()
    inside = ax.get_window_extent(renderer)
    placed = [t.get_window_extent(renderer).padded(2) for t in avoid]
    curves = _curve_points(ax)  # a label's box must not hide the curves (it is opaque)
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
                and not box.count_contains(curves)
            ):
                break
            ann.remove()
            box = None
        if box is None:  # nowhere clear: the nearest place inside the figure
            ann, box = label(10, has[0])
        placed.append(box)
