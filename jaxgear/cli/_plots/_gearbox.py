"""The coupled gearbox's figures beyond its sweep: the coupled Campbell diagram (every stage's
mesh orders against the coupled modes, crossings marked) and the housing-point spectrum (the
ring mount and a parallel stage's bearing), from the data ``jaxgear run`` writes
(``campbell.json``, ``housing_spectrum.json``)."""

from __future__ import annotations

import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ._campbell import _bearing_tone_lines
from ._figure import new_figure, savefig

__all__ = ["coupled_dynamic_factor_plot", "gearbox_campbell_plot", "housing_spectrum_plot"]

#: the stages' colours (stage k: the k-th, cycled)
STAGE_COLOURS = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown")
#: the harmonics' line styles (h = 1, 2, 3, ...)
HARMONIC_STYLES = ("-", "--", ":", "-.")


#: a mesh's marker by its kind (the coupled model's mesh names: "<stage>:<kind> <planet>")
KIND_MARKERS = {"sun-planet": "o", "ring-planet": "s", "pair": "^"}


def mesh_style(name: str) -> dict:
    """The line of mesh ``name`` (``"<k>:<mesh>"``, k the stage from 1) in the coupled
    gearbox's figures: its stage's colour (:data:`STAGE_COLOURS`, so that no two stages share
    one), a marker by its kind (:data:`KIND_MARKERS`: sun ○, ring □, parallel pair △) and, for
    a stage's planets, solid for the sun meshes and dashed for the ring meshes."""
    stage, _, mesh = name.partition(":")
    kind = mesh.rsplit(" ", 1)[0] if mesh[-1:].isdigit() else mesh
    return {"color": STAGE_COLOURS[(int(stage) - 1) % len(STAGE_COLOURS)],
            "marker": KIND_MARKERS.get(kind, "d"), "ls": "--" if kind == "ring-planet" else "-"}


def coupled_dynamic_factor_plot(path, speeds, df, names) -> None:
    """``coupled.png``: every mesh's dynamic factor (max / static, ``df`` (speeds, meshes))
    against the input speed (rad/s), a mesh drawn in its stage's colour (:func:`mesh_style`)."""
    fig, ax = new_figure((9, 4.8))
    for j, name in enumerate(names):
        ax.plot(speeds, df[:, j], ms=3, lw=1.0, label=name, mfc="none", **mesh_style(name))
    ax.set_xlabel("input speed (rad/s)")
    ax.set_ylabel("dynamic factor (max / static)")
    ax.set_title("coupled gearbox: every mesh in one run (colour: stage)")
    ax.legend(fontsize=6, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # beside the curves
    savefig(fig, path)


def _spread(freqs, lo, hi, gap=0.06):
    """The labels' heights: the frequencies, pushed apart to ``gap`` decades at least (log
    axis from ``lo`` to ``hi``), in order."""
    y = np.log10(np.asarray(freqs, dtype=float))
    order = np.argsort(y)
    z = y[order].copy()
    for i in range(1, z.size):
        z[i] = max(z[i], z[i - 1] + gap)
    over = z[-1] - np.log10(hi) + gap if z.size else 0.0
    if over > 0:  # shift the crowded top down, keeping the gaps
        z -= over
        for i in range(z.size - 2, -1, -1):
            z[i] = min(z[i], z[i + 1] - gap)
    out = np.empty_like(z)
    out[order] = z
    return 10.0 ** np.maximum(out, np.log10(lo))


def gearbox_campbell_plot(path, data: dict) -> None:
    """The coupled Campbell diagram: stage k's mesh harmonics f = h f_k(1) Omega (Hz, log
    scale) against the input speed Omega (rad/s), the coupled modes as horizontal lines each
    labelled with its frequency, type and the mesh holding most of its strain energy, the
    crossings marked (black: the exciting stage's meshes hold >= 5 % of the mode's strain
    energy; grey: less), the operating speed dashed, the lumped stages' rolling bearings' tones
    dotted (``bearing_tones``, orders of the input speed). ``data``: ``campbell.json``'s."""
    fig, ax = new_figure((8, 6.5))
    top = float(data["max_speed_rad_s"])
    s = np.linspace(0.0, top, 200)
    modes = [m for m in data["modes"] if m["type"] != "rigid body"]
    f_hi = 1.6 * max(m["frequency_Hz"] for m in modes)
    f_lo = 0.5 * min(min(data["mesh_Hz_per_rad_s"]) * top * 0.2, modes[0]["frequency_Hz"])
    for k, slope in enumerate(data["mesh_Hz_per_rad_s"]):
        for i, h in enumerate(data["harmonics"]):
            ax.plot(s, h * slope * s, HARMONIC_STYLES[i % len(HARMONIC_STYLES)],
                    color=STAGE_COLOURS[k % len(STAGE_COLOURS)], lw=1.1,
                    label=f"stage {k + 1}: {h}× mesh ({h * slope:.4g} Hz per rad/s)")
    for m, y in zip(modes, _spread([m["frequency_Hz"] for m in modes], f_lo, f_hi),
                    strict=True):
        f = m["frequency_Hz"]
        ax.axhline(f, color="0.6", lw=0.6, zorder=0)
        ax.annotate(f"{f:.0f} Hz {m['type']} ({m['mesh']})", (top, f), (top * 1.01, y),
                    fontsize=6, va="center", ha="left", annotation_clip=False,
                    arrowprops={"arrowstyle": "-", "color": "0.6", "lw": 0.5})
    for c in data["crossings"]:
        strong = c["marked"]
        ax.plot(c["speed_rad_s"], c["frequency_Hz"], "o", ms=5 if strong else 3,
                mfc="none" if not strong else "k", mec="k" if strong else "0.6", zorder=3)
    _bearing_tone_lines(ax, data.get("bearing_tones") or (), s)
    ax.axvline(data["operating_speed_rad_s"], color="r", ls="--", lw=0.8,
               label=f"rated input speed {data['operating_speed_rad_s']:.4g} rad/s")
    ax.set_yscale("log")
    ax.set_xlim(0.0, top)
    ax.set_ylim(f_lo, f_hi)
    ax.set_xlabel("input speed Ω (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title(f"{data['case']}: coupled Campbell diagram (modes at rest; ● crossing with "
                 "≥ 5 % of the mode's strain energy in the exciting stage's meshes, ○ less)")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=6, loc="upper left", ncols=2)
    savefig(fig, path)


def _band(ax, f, a, lo, hi, lines, mesh_f, title):
    keep = (f >= lo) & (f <= hi)
    ax.semilogy(f[keep], a[keep], lw=0.6, color="k")
    floor = max(np.max(a[keep]) * 1e-7, np.min(a[keep][a[keep] > 0], initial=1e-12))
    ax.set_ylim(floor, np.max(a[keep]) * 3)
    ax.set_xlim(lo, hi)
    for k, fk in enumerate(mesh_f):
        for h in (1, 2, 3):
            if lo <= h * fk <= hi:
                ax.axvline(h * fk, color=STAGE_COLOURS[k % len(STAGE_COLOURS)], lw=0.7,
                           ls=HARMONIC_STYLES[h - 1], alpha=0.8,
                           label=f"{h}× stage {k + 1} mesh" if h == 1 else None)
    for r in lines:
        if lo <= r["frequency_Hz"] <= hi and r["kind"] == "McFadden-Smith":
            ax.plot(r["frequency_Hz"], r["ring"], "v", color="r", ms=4)
    ax.set_title(title, fontsize=9)
    ax.set_ylabel("amplitude (N, peak)")
    ax.grid(alpha=0.3, which="both")


def housing_spectrum_plot(path, data: dict) -> None:
    """Three panels from ``housing_spectrum.json``'s data: the ring-mount point's force
    spectrum over every stage's orders, the same around stage 1's mesh frequency (its
    planet-pass lines, the McFadden-Smith lines marked ▼), and the parallel stage's bearing's
    spectrum; every stage's mesh harmonics drawn in its colour."""
    fig = Figure(figsize=(8, 9), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(3, 1)
    f = np.asarray(data["spectrum"]["frequency_Hz"], dtype=float)
    ring = np.asarray(data["spectrum"]["ring_point_N"], dtype=float)
    bearing = np.asarray(data["spectrum"]["bearing_N"], dtype=float)
    mesh_f = data["mesh_frequency_Hz"]
    hi = min(3.3 * max(mesh_f), float(f[-1]))
    k = data["ring_stage"] - 1
    fc = abs(data["carrier_frequency_Hz"][k])
    n = data["planets"]
    f1 = mesh_f[k]
    fine = data["spectrum_fine"]
    _band(axes[0], f, ring, 0.0, hi, data["lines"], mesh_f,
          f"ring mount of stage {k + 1} (window ((1 + cos φ)/2)^{data['window_power']}): "
          "every stage's orders")
    _band(axes[1], np.asarray(fine["frequency_Hz"]), np.asarray(fine["ring_point_N"]),
          f1 - 4.5 * n * fc, f1 + 4.5 * n * fc, data["lines"], mesh_f,
          f"ring mount around stage {k + 1}'s mesh frequency {f1:.4g} Hz = "
          f"{f1 / fc:.0f} f_c: lines at multiples of the planet-pass frequency "
          f"{n} f_c = {n * fc:.3g} Hz (▼ McFadden-Smith)")
    for p in np.arange(np.ceil((f1 - 4.5 * n * fc) / (n * fc)),
                       np.floor((f1 + 4.5 * n * fc) / (n * fc)) + 1):
        axes[1].axvline(p * n * fc, color="0.5", lw=0.4, ls=":")
    b = data["bearing_stage"]
    _band(axes[2], f, bearing, 0.0, hi, [], mesh_f,
          f"bearing of stage {b} along its line of action (= its mesh force)")
    axes[2].set_xlabel("frequency (Hz)")
    axes[0].legend(fontsize=7, ncols=3, loc="upper right")
    fig.suptitle(f"{data['case']}: force at housing-fixed points, input "
                 f"{data['input_speed_rad_s']:.4g} rad/s, {data['time_plan']['revolutions']} carrier "
                 f"revolutions (FFT, Hann-windowed)", fontsize=10)
    savefig(fig, path)
