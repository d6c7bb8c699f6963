"""The figures of ``jaxgear run``: quasi-static TE and mesh stiffness against position, the load
and pressure maps over a tooth's passage, the Harris map, a train's layout and phasing, and the
TE over a deviation span with its order spectrum."""

from __future__ import annotations

import os

import matplotlib.patches as mpatches
import numpy as np
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from ... import load_map
from ._figure import finish, legend_below_and_save, new_figure, savefig

__all__ = [
    "DYNAMIC_ZERO",
    "LUMPED_STIFFNESS_NOTE",
    "SCENE_STIFFNESS_NOTE",
    "TE_COINCIDE_SHARE",
    "face_map",
    "face_maps",
    "harris_plot",
    "load_map_plot",
    "map_difference_plot",
    "mesh_stiffness_plot",
    "te_coincide",
    "te_spectrum_plot",
    "train_phasing_plot",
    "transmission_error_plot",
]


#: what the rigid mesh's and a scene's "mesh stiffness" curves are (``mesh_stiffness.png``'s note)
SCENE_STIFFNESS_NOTE = (
    "K = Σ k l over the loaded contact cells. Rigid mesh: the cells carry the whole tooth "
    "compliance (tooth, foundation, contact).\nA condensed body's cells leave out its "
    "foundation term (its FE rim carries that compliance): higher K, not the whole mesh's "
    "stiffness (T/TE is)."
)


#: the same for a scene without condensed bodies (its cells are the rigid mesh's)
LUMPED_STIFFNESS_NOTE = (
    "K = Σ k l over the loaded contact cells (tooth, foundation, contact); the scene's shafts "
    "and bearings are not in it"
)


#: what the dynamic pressure map's bands of 0 MPa are (its legend)
DYNAMIC_ZERO = ("0 MPa: no contact there at any kept step (a relief's unloaded zone,\n"
                "or the teeth losing contact in the dynamic response: sweep.json's contact_loss)")

#: exact and smooth TE are drawn as one curve when they differ by less than this share of the
#: plotted TE range (about the width of a line on a FIGSIZE figure)
TE_COINCIDE_SHARE = 0.01


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

    ``curves``: ``{design label: {contact law: TE (m)}}``, the first law solid (``"exact"``,
    then ``"smooth"``; a design may have "exact" only). A law whose curve coincides with the
    first's (:func:`te_coincide`) is drawn with it, its legend entry says so; another is
    dashed. ``note``:
    a line under the plot (what a reader would otherwise take for an error). Returns the
    legend labels.
    """
    fig, ax = new_figure()
    um = {k: {m: np.asarray(a) * 1e6 for m, a in v.items()} for k, v in curves.items()}
    allv = np.concatenate([a for v in um.values() for a in v.values()])
    span = float(np.ptp(allv)) or 1.0
    colors = ("C0", "C3", "C2", "C1", "C4", "C5")
    for (lab, v), color in zip(um.items(), colors, strict=False):
        (law, first), *others = v.items()  # the first law solid, the others against it
        near = {m: te_coincide(first, a, span) for m, a in others}
        same = [m for m, (ok, _) in near.items() if ok]
        label = f"{lab}, {law} contact"
        if same:  # one curve for the laws that coincide with the first
            d = max(near[m][1] for m in same)
            within = f"within {d:.2g} µm" if d >= 1e-3 else "within 0.001 µm"
            label = f"{lab} ({' = '.join((law, *same))} {within})"
        ax.plot(x, first, "-", color=color, label=label)
        for m, a in others:
            if not near[m][0]:
                ax.plot(x, a, "--", color=color, label=f"{lab}, {m} contact")
    ax.set_xlabel(f"{driver} position (mesh periods)")
    ax.set_ylabel("quasi-static TE (µm, along the line of action)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return legend_below_and_save(fig, ax, path, note)


def mesh_stiffness_plot(
    path, x, curves: dict, *, title: str, driver: str = "pinion", note: str | None = None
) -> list[str]:
    """Mesh stiffness (N/µm) against the ``driver``'s position (the pinion's, a train's
    input's); ``curves``: ``{label: K (N/m)}``; ``note``: a line under the plot. Curves that
    coincide (within :data:`TE_COINCIDE_SHARE` of the plotted range, a line's width) are drawn
    once, their legend entry naming them all (``A = B (coincide)``); the others each in their
    own colour and dash, so that one on top of another still shows."""
    fig, ax = new_figure()
    colors = ("C0", "C3", "C2", "C1", "C4", "C5")
    styles = ("-", "--", "-.", ":", "-", "--")  # a curve on top of another one still shows
    n_per_um = {lab: np.asarray(k) / 1e6 for lab, k in curves.items()}
    allv = np.concatenate(list(n_per_um.values())) if n_per_um else np.zeros(1)
    span = float(np.ptp(allv)) or float(np.max(np.abs(allv))) or 1.0
    groups: list[tuple[list[str], np.ndarray]] = []
    for lab, k in n_per_um.items():
        same = next((g for g in groups if g[1].shape == k.shape
                     and np.max(np.abs(g[1] - k)) <= TE_COINCIDE_SHARE * span), None)
        if same is None:
            groups.append(([lab], k))
        else:
            same[0].append(lab)
    for (labs, k), color, ls in zip(groups, colors, styles, strict=False):
        label = labs[0] if len(labs) == 1 else " = ".join(labs) + " (coincide)"
        ax.plot(x, k, ls, color=color, label=label)
    ax.set_xlabel(f"{driver} position (mesh periods)")
    ax.set_ylabel("mesh stiffness K(θ) (N/µm)")
    ax.set_title(title)
    ax.grid(alpha=0.3)
    return legend_below_and_save(fig, ax, path, note)


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
    zero_label: str | None = None,
):
    """Max line load (N/mm) over the line of action (s) and the face width (z); SI inputs
    (``label`` and ``unit``, the SI value of one displayed unit, for another field: the contact
    pressure in MPa, 1e6). ``zero_label``: a legend entry below the axes for the colour of 0
    (what the bands of no load are, a dynamic map's contact loss).

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
    if zero_label:
        zero = mpatches.Patch(facecolor=pc.cmap(0.0), edgecolor="0.5", label=zero_label)
        fig.legend(handles=[zero], loc="outside lower center", fontsize=8, frameon=False)
    finish(
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
    finish(
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
    zero_label: str | None = None,
):
    """One field of one mesh over a tooth's passage (roll position along the line of action ×
    face width), as :func:`~jaxgear.load_map` bins it: the line load (``field`` None, N/m) or a
    cell field of the shape of ``result.line_load`` (the Hertzian pressure of
    :func:`~jaxgear.contact_pressure`, Pa). ``result``: a quasi-static mesh result (P, L, N),
    or a dynamic one recorded with ``cell_loads`` (K, L, N); ``positions_per_pitch``: the
    result's steps per period of that mesh (the step of its contact lines along s).
    ``label``/``unit`` as :func:`load_map_plot`. The one plot of the quasi-static and the
    dynamic pressure maps; ``zero_label`` as :func:`load_map_plot`'s."""
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
        zero_label=zero_label,
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


def loaded_path_plot(path, path_map: dict, *, design_torque: float, title: str) -> None:
    """The loaded path of contact over torque (:func:`jaxgear.loaded_path`), two panels: how
    far contact reaches beyond the theoretical start and end (mm of roll along the line of
    action) and the tip relief that keeps the corners off (µm), each design of ``path_map``
    (``{label: LoadedPath}``), the design torque marked."""
    fig = Figure(figsize=(10.5, 4.2), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 2)
    for (lab, lp), color in zip(path_map.items(), ("C0", "C3"), strict=False):
        t = np.asarray(lp.torque)
        g = float(lp.path_of_contact)
        for ax, y, fmt, what in (
            (axes[0], -np.asarray(lp.start) * 1e3, "o-", "before the start"),
            (axes[0], (np.asarray(lp.end) - g) * 1e3, "s--", "after the end"),
            (axes[1], np.asarray(lp.relief_start) * 1e6, "o-", "gear tip"),
            (axes[1], np.asarray(lp.relief_end) * 1e6, "s--", "pinion tip"),
        ):
            ax.plot(t, y, fmt, color=color, label=f"{lab}: {what}")
    ylabels = (
        "contact beyond the theoretical path (mm of roll)",
        "extra tip relief that clears the corner (µm)",
    )
    for ax, ylabel in zip(axes, ylabels, strict=True):
        ax.axvline(design_torque, color="0.3", lw=0.8, ls="--")
        ax.set_ylim(bottom=0)
        ax.set_xlabel("pinion torque (N·m)")
        ax.set_ylabel(ylabel)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8)
    fig.suptitle(title)
    savefig(fig, path)


def train_phasing_plot(path, layout, pairs, gears, mesh_names, x, stiffness, *, title: str):
    """A gear train's layout and mesh phasing in one figure (two panels).

    Left: the gears in the plane (tip and base circles, centres, each gear's sense of rotation,
    each mesh's line of action between its base-circle tangent points, thick along its path of
    contact, in mm). Right: each
    mesh's stiffness K_k(θ) (N/µm) against the input's position (its mesh periods), each curve
    marked where its mesh angle is a whole number of mesh periods: the marks of mesh k sit at
    −phase_k / (ratio_k · mesh period angle) modulo one period (the layout's phasing).

    Args:
        layout: :class:`jaxgear.scenes.TrainLayout`. pairs: each mesh's
            :class:`~jaxgear.GearPair`. gears: each gear's (name, tip radius (m), base
            radius (m)). mesh_names: the meshes'. x: the input's position (mesh periods), (P,).
        stiffness: ``{mesh label: (K (N/m) (P,), phase marks (mesh periods of the input))}``.
    """
    names = [name for name, _, _ in gears]
    tip_radii = [tip for _, tip, _ in gears]
    base_radii = [base for _, _, base in gears]
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
        label = " +\n".join(together)  # a compound shaft's gears one under the other
        lay.annotate(
            f"{label} {spin}",
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


def te_spectrum_plot(path, theta_rev, te, spectrum, *, title: str, mesh_harmonics: int = 3):
    """The TE over the deviation span (µm against pinion revolutions) above its order spectrum
    (µm against pinion orders up to (``mesh_harmonics`` + ½) z1), the mesh orders and the
    shaft-order sidebands around them marked and labelled (:meth:`jaxgear.TESpectrum.lines`)."""
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


def root_stress_plot(path: str, maps, title: str, names=("pinion", "gear")) -> None:
    """The pinion's and the gear's root-stress maps (:class:`jaxgear.rating.RootStressMap`, MPa) over the
    line of action and the face width, side by side (a surface interpolated linearly between the
    cells), each map's largest stress marked, saved to
    ``path``; ``names`` the two members' (a map ``None``: its panel says why, e.g. "ring: not
    computed (no ring cutter)")."""
    fig = Figure(figsize=(9, 3.8), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplots(1, 2, sharey=True)
    for ax, tag, rmap in zip(axes, names, maps, strict=True):
        if rmap is None:
            ax.text(0.5, 0.5, tag, ha="center", va="center", transform=ax.transAxes)
            ax.set_axis_off()
            continue
        m = np.asarray(rmap.mask)
        s = np.asarray(rmap.cell_s)[m] * 1e3
        z = np.asarray(rmap.cell_z)[m] * 1e3
        stress = np.asarray(rmap.stress)[m] / 1e6
        # a surface over the cells (their s, z lie on the inclined contact lines, not on a
        # grid): Gouraud-shaded triangles between them, so no gaps draw stripes; cells on one
        # line (or fewer than three) span no triangle: drawn as points (a spur stage's map at
        # speed: its dynamics lay one slice per contact line, every cell at mid-face)
        pts = np.column_stack([s, z])
        if len(s) >= 3 and np.linalg.matrix_rank(pts - pts.mean(axis=0)) == 2:
            sc = ax.tripcolor(s, z, stress, shading="gouraud", cmap="viridis")
        else:
            sc = ax.scatter(s, z, c=stress, cmap="viridis")
        k = int(np.argmax(stress))
        ax.plot(s[k], z[k], "r*", ms=10)
        ax.set_title(f"{tag} root stress (MPa), largest {stress[k]:.1f} (★)")
        ax.set_xlabel("s of the load along the line of action (mm)")
        fig.colorbar(sc, ax=ax)
    axes[0].set_ylabel("z across the face (mm)")
    fig.suptitle(title, fontsize=9)
    savefig(fig, path)
