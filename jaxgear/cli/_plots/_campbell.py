"""The Campbell diagram of ``jaxgear sweep``: mesh harmonics against the modes (at speed where
the run follows them), their crossings and critical speeds, and the nodal-diameter resonances
of condensed gears, labelled without overlaps."""

from __future__ import annotations

import math

import numpy as np
from matplotlib.text import Text
from matplotlib.transforms import Bbox

from ...dynamics import campbell_coincidences
from ._figure import fit_legend_columns, floats, hz_text, new_figure, savefig

__all__ = [
    "campbell_plot",
    "harmonic_crossings",
    "modes_on_grid",
]


def modes_on_grid(summary: dict, freqs):
    """The modes' frequencies (Hz) as the sweep's critical speeds take them: at speed, (g, m)
    on the grid ``campbell_speeds_rad_s``, where ``campbell_at_speed``; else ``freqs`` and None."""
    if not summary.get("campbell_at_speed"):
        return np.asarray(freqs, dtype=float), None
    curves = np.array([floats(row) for row in summary["natural_frequencies_at_speed_Hz"]])
    return curves, floats(summary["campbell_speeds_rad_s"])


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
    the low modes' crossings crowd there and no speed was computed), and the rolling bearings'
    tones (``bearing_tones``, orders of the pinion speed; dotted).
    Returns the crossings (:func:`harmonic_crossings`)."""
    fig, ax = new_figure()
    sp = floats(summary["speeds_rad_s"])
    s_max = float(np.nanmax(sp)) * 1.05
    s_line = np.linspace(0, s_max, 50)
    freqs = floats(summary["natural_frequencies_Hz"])
    # the modes at speed where the run has the rotating-frame terms (else constant)
    at_speed, grid = modes_on_grid(summary, freqs)
    curves = at_speed if grid is not None else np.vstack([freqs, freqs])
    line_grid = grid if grid is not None else np.array([0.0, s_max])

    def at(i, speed):
        return np.interp(speed, line_grid, curves[:, i])

    modes = [
        (i, f, e)
        for i, (f, e) in enumerate(zip(freqs, floats(summary["mesh_energy_share"]), strict=True))
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
        ids = ", ".join(str(i + 1) for i, _, _ in g)  # 1-based, as `jaxgear modes`
        hz = ", ".join(hz_text(f) for _, f, _ in g)
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
                label=f"{tag}{direction} ND resonance, Z{_ND_ORDER_SIGN[direction]}n"
                if tag  # several gears: shorter, the legend holds one per gear
                else f"{direction} ND resonance, order Z{_ND_ORDER_SIGN[direction]}n "
                "(body frame, (3.9))",
            )
    _bearing_tone_lines(ax, summary.get("bearing_tones") or (), s_line)
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
        ncols=fit_legend_columns(fig, ax, 8, 3 if nd else 4 if others else 6),
        fontsize=8,
        frameon=False,
    )
    if nd_labels:
        fig.canvas.draw()  # the layout fixes the axes: labels are placed in pixels
        _place_nd_labels(ax, nd_labels, avoid=mode_labels)
    savefig(fig, path)
    return cross


#: the colours of the bearing tones on the Campbell diagram (after the mesh harmonics' C0-C3)
_TONE_COLORS = {"ftf": "C4", "bpfo": "C5", "bpfi": "C6", "bsf": "C8"}


def _bearing_tone_lines(ax, tones, s_line) -> None:
    """The rolling bearings' tones (``sweep.json``'s ``bearing_tones``: each a bearing's
    cage, ball-pass and ball-spin frequency as an order of the pinion speed), dotted, one line
    and legend entry per shaft and tone (the bearings of a shaft that share an order drawn
    once)."""
    drawn = {}
    for t in tones:
        shaft = t["bearing"].rsplit(".bearings[", 1)[0]
        key = (shaft, t["tone"], round(float(t["order"]), 6))
        if key in drawn:
            continue
        drawn[key] = True
        ax.plot(s_line, t["order"] * s_line / (2 * math.pi), color=_TONE_COLORS[t["tone"]],
                ls=":" if shaft.endswith("pinion_shaft") else (0, (3, 1, 1, 1, 1, 1)), lw=1.0,
                label=f"{shaft.replace('_', ' ')} {t['tone'].upper()} ({t['order']:.3g})")


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
#: the sign of n in a family's excitation order Z ± n (body frame, seed (3.9)), in its legend
_ND_ORDER_SIGN = {"backward": "+", "forward": "−"}


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
    """Label the nodal-diameter resonances ``{(direction, text prefix, colour): [(speed,
    frequency, n)]}`` without overlaps (the prefix names one of several condensed gears,
    "idler −2ND", else ""; the colour None: the direction's own): each label takes the first
    offset of :data:`_ND_OFFSETS` where it lies inside the axes and clear of every label placed
    before (and of ``avoid``); one that fits nowhere joins the previous label of its direction
    ("−1…−4ND" at the first family's point). Needs a drawn figure (fixed layout). Returns the
    annotations."""
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
        direction, prefix, color = key
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
        direction = key[0]
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
