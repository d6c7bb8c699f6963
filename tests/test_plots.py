"""The command line's figures (jaxgear.cli.plots) on small synthetic data: valid PNGs, the TE
exact/smooth coincidence rule, the dynamic-factor peak names and the Campbell crossings."""

from __future__ import annotations

import itertools
import json
import math
import pathlib
import re
import shutil
import types

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.text import Text
from matplotlib.ticker import LogFormatter, MaxNLocator

from benchmarks import hybrid_chart, hybrid_sweep_chart, thin_tick_labels
from jaxgear import load_map
from jaxgear.cli import plots, scene_outputs
from jaxgear.dynamics import nodal_diameter_resonances
from jaxgear.io import load_case

DATA = pathlib.Path(__file__).parent / "data"
DOCS = pathlib.Path(__file__).parent.parent / "docs" / "bench"

Z1 = 20


def _png(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 2000
    return data


def _sweep_summary(df_peak_speed: float | None = None) -> dict:
    """A sweep.json-like dict: modes 1 (1000 Hz, 60 % mesh energy) and 2 (2500 Hz, 30 %)."""
    sp = np.linspace(100.0, 1200.0, 221)
    df = 1.0 + 0.02 * sp / sp.max()
    if df_peak_speed is not None:
        df = df + 0.8 / (1 + ((sp - df_peak_speed) / 15.0) ** 2)
    freqs = [0.0, 1000.0, 2500.0, 40000.0]
    share = [0.0, 0.6, 0.3, 0.001]
    crit = [
        {
            "mode": i,
            "harmonic": h,
            "speed_rad_s": 2 * math.pi * freqs[i] / (h * Z1),
            "frequency_Hz": freqs[i],
            "mesh_energy_share": share[i],
        }
        for i in (1, 2)
        for h in (1, 2, 3)
    ]
    return {
        "case": "synthetic",
        "model": "torsional",
        "solver": "newmark",
        "contact": "exact",
        "direction": "independent",
        "speeds_rad_s": sp.tolist(),
        "mesh_frequency_Hz": (sp * Z1 / (2 * math.pi)).tolist(),
        "dynamic_factor": df.tolist(),
        "dynamic_factor_tooth": (df * 0.98).tolist(),
        "contact_loss": [0.0] * sp.size,
        "result": [0] * sp.size,
        "natural_frequencies_Hz": freqs,
        "mesh_energy_share": share,
        "critical_speeds": crit,
    }


def test_savefig_writes_png_atomically_and_closes(tmp_path):
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots()
    ax.plot([0, 1], [0, 1])
    plots.savefig(fig, tmp_path / "a.png")
    _png(tmp_path / "a.png")
    assert not plt.fignum_exists(fig.number)
    assert [p.name for p in tmp_path.iterdir()] == ["a.png"]  # no temporary file left


@pytest.mark.parametrize("offset_um, n_labels", [(0.0, 2), (0.004, 2), (0.5, 4)])
def test_te_one_legend_entry_per_design_when_exact_equals_smooth(tmp_path, offset_um, n_labels):
    x = np.linspace(0, 2, 97)
    te = 1e-6 * (10 + 2 * np.sin(2 * np.pi * x))  # 4 µm range
    curves = {
        "unmodified": {"exact": te, "smooth": te + offset_um * 1e-6},
        "modified": {"exact": te * 0.5, "smooth": te * 0.5 + offset_um * 1e-6},
    }
    labels = plots.transmission_error_plot(tmp_path / "te.png", x, curves, title="t")
    _png(tmp_path / "te.png")
    assert len(labels) == n_labels
    if n_labels == 2:
        assert all("exact = smooth" in lab for lab in labels)
    else:
        assert labels == [
            "unmodified, exact contact",
            "unmodified, smooth contact",
            "modified, exact contact",
            "modified, smooth contact",
        ]


def test_te_coincide_threshold():
    a = np.zeros(5)
    assert plots.te_coincide(a, a + 0.009, span=1.0)[0]
    assert not plots.te_coincide(a, a + 0.011, span=1.0)[0]


def test_dynamic_factor_peak_named_after_the_coinciding_mode(tmp_path):
    speed = 2 * math.pi * 2500.0 / (1 * Z1)  # mode 2 × H1 (785 rad/s)
    summary = _sweep_summary(df_peak_speed=speed + 3.0)
    peaks = plots.dynamic_factor_plot(tmp_path / "df.png", summary)
    _png(tmp_path / "df.png")
    assert len(peaks) == 1
    (p,) = peaks
    assert p["speed_rad_s"] == pytest.approx(speed, abs=6.0)
    assert (p["coincidence"]["mode"], p["coincidence"]["harmonic"]) == (2, 1)
    # named 1-based, as `jaxgear modes` numbers it (index 2: mode 3)
    assert p["name"] == "mode 3 (2\u2009500 Hz) × H1"
    # a peak at mode 1 × H2 (157 rad/s) is named so, not after mode 2 × H3 nearby (262 rad/s)
    speed = 2 * math.pi * 1000.0 / (2 * Z1)
    (p,) = plots.name_peaks(
        summary["speeds_rad_s"],
        _sweep_summary(df_peak_speed=speed)["dynamic_factor"],
        plots.coincidences(summary),
    )
    assert (p["coincidence"]["mode"], p["coincidence"]["harmonic"]) == (1, 2)


def test_flat_dynamic_factor_has_no_named_peak(tmp_path):
    assert plots.dynamic_factor_plot(tmp_path / "df.png", _sweep_summary()) == []
    _png(tmp_path / "df.png")


def test_campbell_crossings_at_f_equals_h_z1_omega_over_2pi(tmp_path):
    cross = plots.harmonic_crossings([1000.0, 2500.0], Z1, s_max=1000.0, harmonics=(1, 2, 3, 4))
    got = {(c["frequency_Hz"], c["harmonic"]): c["speed_rad_s"] for c in cross}
    for (f, h), s in got.items():
        assert h * Z1 * s / (2 * math.pi) == pytest.approx(f)
    # 2500 Hz × H1 is at 785 rad/s (inside), 1000 Hz × H1 at 314 rad/s: all 8 inside 1000 rad/s
    assert len(got) == 8
    assert got[2500.0, 1] == pytest.approx(2 * math.pi * 2500 / Z1)
    assert plots.harmonic_crossings([2500.0], Z1, s_max=700.0, harmonics=(1,)) == []
    # the plot marks every crossing of the plotted modes (≥ 1 % mesh energy) in its speed
    # range from the sweep's first speed (below it the low modes' crossings crowd unswept)
    marked = plots.campbell_plot(tmp_path / "c.png", _sweep_summary(), Z1)
    _png(tmp_path / "c.png")
    s_max = 1200.0 * 1.05
    assert {(c["frequency_Hz"], c["harmonic"]) for c in marked} == {
        (f, h)
        for f in (1000.0, 2500.0)
        for h in (1, 2, 3, 4)
        if 100.0 <= 2 * math.pi * f / (h * Z1) <= s_max
    }


def test_harris_marks_the_design_torque(tmp_path):
    t = np.union1d(np.linspace(10.0, 160.0, 7), [80.0])
    labels = plots.harris_plot(
        tmp_path / "h.png",
        t,
        [("a", 1e-6 * t / 80, "o-"), ("unmodified (lower bounds)", 2e-6 * np.ones_like(t), "k:")],
        design_torque=80.0,
        ylabel="TE RMS (µm)",
        title="t",
    )
    _png(tmp_path / "h.png")
    assert "unmodified (lower bounds)" in labels
    assert "design torque 80 N·m" in labels and "value at the design torque" in labels


def test_run_plots_write_pngs(tmp_path):
    x = np.linspace(0, 2, 50)
    plots.mesh_stiffness_plot(tmp_path / "k.png", x, {"a": 3e8 + 1e7 * x}, title="t")
    s_edges, z_edges = np.linspace(0, 5e-3, 11), np.linspace(0, 1e-2, 5)
    plots.load_map_plot(tmp_path / "l.png", s_edges, z_edges, np.ones((10, 4)) * 1e5, title="t")
    plots.convergence_plot(tmp_path / "c.png", [1.0, 0.5, 0.1], ylabel="te_rms", title="t")
    for name in ("k", "l", "c"):
        _png(tmp_path / f"{name}.png")


def test_optimisation_maps_write_pngs(tmp_path):
    G, E = np.linspace(0.1, 0.6, 6), np.linspace(0, 30, 7)
    grid = np.add.outer(G, E / 30)
    plots.optimiser_path_plot(
        tmp_path / "p.png",
        G,
        E,
        grid,
        np.array([0.2, 0.3]),
        np.array([5.0, 10.0]),
        (0.3, 10.0),
        label="te_rms (µm)",
        title="path",
    )
    labels = plots.master_curve_plot(
        tmp_path / "m.png",
        G,
        E,
        grid,
        [0.2, 0.3, 0.4],
        [0.0, 10.0, 12.0],
        on_bound=[True, False, False],
        family=(G, E[: G.size]),
        title="t",
    )
    assert any("on a bound" in lab for lab in labels)
    for name in ("p", "m"):
        _png(tmp_path / f"{name}.png")


@pytest.fixture
def figures(monkeypatch):
    """The figures the plot functions write, in order (matplotlib's Figure.savefig, which
    plots.savefig calls for every figure, still writes them)."""
    out = []
    save = Figure.savefig

    def keep(fig, *args, **kw):
        out.append(fig)
        save(fig, *args, **kw)

    monkeypatch.setattr(Figure, "savefig", keep)
    return out


def _few_speeds(summary: dict, n: int) -> dict:
    idx = np.linspace(0, len(summary["speeds_rad_s"]) - 1, n).astype(int)
    per_speed = ("speeds_rad_s", "mesh_frequency_Hz", "dynamic_factor", "dynamic_factor_tooth")
    for k in (*per_speed, "contact_loss", "result"):
        summary[k] = [summary[k][i] for i in idx]
    return summary


def test_load_map_has_no_empty_bin_inside_the_path_of_contact():
    """Contact lines step by ds = base pitch / positions per pitch along s, each face slice at its
    own offset (a helical pair); the path of contact is 10.3 ds. Bins of one ds with a partial
    11th bin left that bin empty on the slices whose samples missed it (the column of unfilled
    cells at the right edge of the power-helical map)."""
    ds, path = 1e-4, 10.3e-4
    offsets = np.linspace(0.05, 0.95, 8) * ds  # one per slice
    s = offsets[None, :] + ds * np.arange(-2, 14)[:, None]  # (positions, slices)
    mask = (s >= 0) & (s <= path)
    r = types.SimpleNamespace(
        cell_s=s[:, None, :],
        line_load=np.where(mask, 1e5, 0.0)[:, None, :],
        cell_mask=mask[:, None, :],
        cell_z=np.broadcast_to(np.linspace(0.5e-3, 7.5e-3, 8), s.shape)[:, None, :],
    )
    s_edges, z, lmap = load_map(r, 64, 64 * ds, path)
    assert s_edges[0] == 0.0 and s_edges[-1] == pytest.approx(path)
    assert np.all(np.diff(s_edges) >= ds * (1 - 1e-12))  # every bin at least one step wide
    assert lmap.shape == (s_edges.size - 1, 8)
    assert not np.isnan(lmap).any()


def test_load_maps_share_one_colour_scale(tmp_path):
    s_edges, z_edges = np.linspace(0, 5e-3, 11), np.linspace(0, 1e-2, 5)
    rest, speed = np.full((10, 4), 3.2e5), np.full((10, 4), 2.9e5)
    own = plots.load_map_plot(tmp_path / "a.png", s_edges, z_edges, speed, title="t")
    assert (own.norm.vmin, own.norm.vmax) == (0.0, pytest.approx(290.0))  # N/mm, from 0
    a = plots.load_map_plot(tmp_path / "a.png", s_edges, z_edges, rest, title="t", vmax=3.2e5)
    b = plots.load_map_plot(tmp_path / "b.png", s_edges, z_edges, speed, title="t", vmax=3.2e5)
    assert (a.norm.vmin, a.norm.vmax) == (b.norm.vmin, b.norm.vmax) == (0.0, pytest.approx(320.0))


@pytest.mark.slow
def test_hybrid_load_maps_at_rest_and_at_speed_share_one_scale(
    tmp_path, fem_prep_cache, monkeypatch
):
    """``jaxgear run`` of a hybrid case at speed: load_map.png (at rest) and load_map_speed.png
    are drawn on one colour scale, 0 to the larger maximum of the two; so are the pressure
    maps (MPa)."""
    for f in DATA.glob("hybrid-test-*.toml"):
        shutil.copy(f, tmp_path)
    toml = tmp_path / "hybrid-test-case.toml"
    toml.write_text(toml.read_text().replace("speed_rad_s = 0.0", "speed_rad_s = 1500.0"))
    drawn = {}
    draw = plots.load_map_plot

    def spy(path, s_edges, z_edges, lmap, **kw):
        norm = draw(path, s_edges, z_edges, lmap, **kw).norm
        drawn[pathlib.Path(path).name] = (np.nanmax(lmap) / kw.get("unit", 1e3), norm)

    monkeypatch.setattr(plots, "load_map_plot", spy)
    scene_outputs(load_case(toml), str(tmp_path / "out"))
    assert set(drawn) == {
        "load_map.png",
        "load_map_speed.png",
        "pressure_map.png",
        "pressure_map_speed.png",
    }
    for kind in ("load", "pressure"):
        (m1, n1), (m2, n2) = drawn[f"{kind}_map.png"], drawn[f"{kind}_map_speed.png"]
        assert (n1.vmin, n1.vmax) == (n2.vmin, n2.vmax) == (0.0, pytest.approx(max(m1, m2)))


def test_sweep_of_few_speeds_marks_the_computed_points(tmp_path, figures):
    """9 speeds around a resonance that peaks between two of them: every curve over the speeds
    has a marker on each computed speed; a dense sweep (221 speeds) is drawn as plain lines."""
    speed = 2 * math.pi * 2500.0 / Z1
    plots.dynamic_factor_plot(
        tmp_path / "df.png", _few_speeds(_sweep_summary(df_peak_speed=speed + 40.0), 9)
    )
    plots.dynamic_factor_plot(tmp_path / "dense.png", _sweep_summary(df_peak_speed=speed))
    _png(tmp_path / "df.png")
    few, dense = (fig.axes[0].get_lines() for fig in figures)
    curves = [ln for ln in few if len(ln.get_xdata()) == 9]
    assert len(curves) == 2  # dynamic factor and tooth factor
    assert all(ln.get_marker() not in (None, "None", "") for ln in curves)
    curves = [ln for ln in dense if len(ln.get_xdata()) == 221]
    assert len(curves) == 2 and all(ln.get_marker() in (None, "None", "") for ln in curves)


@pytest.mark.parametrize(
    "objective, history, log",
    [("dynamic_factor", [1.144, 1.12, 1.092], False), ("te_rms", [1.0, 0.3, 0.04], True)],
)
def test_convergence_axis(tmp_path, objective, history, log):
    """dynamic_factor is plotted as itself (no "/ unmodified": its scale is a placeholder 1.0)
    on a linear axis (its range is not a decade); a scaled objective spanning a decade reads on
    a log axis. Iterations are integers: 3 points would otherwise get ticks 0, 0.25, ..."""
    units = {"dynamic_factor": "dimensionless", "te_rms": "m"}[objective]
    ylabel = plots.convergence_ylabel(objective, 1.0 if log is False else 5.2e-7, units)
    ax = plots.convergence_plot(tmp_path / "c.png", history, ylabel=ylabel, title="t")
    _png(tmp_path / "c.png")
    assert ax.get_yscale() == ("log" if log else "linear")
    if objective == "dynamic_factor":
        assert "unmodified" not in ax.get_ylabel() and "dynamic factor" in ax.get_ylabel()
    else:
        assert ax.get_ylabel() == "TE RMS / unmodified design (0.52 µm)"  # words, not code
    loc = ax.xaxis.get_major_locator()
    assert isinstance(loc, MaxNLocator) and loc._integer
    ticks = [x for x in ax.get_xticks() if 0 <= x <= len(history) - 1]
    assert ticks == [0, 1, 2]


def test_master_curve_points_on_the_bound_are_inside_the_axes(tmp_path, figures):
    """Points on the upper depth bound and at the end extents are drawn whole: the axes reach a
    margin beyond the map on every side, and the legend is outside the axes."""
    G, E = np.linspace(0.05, 0.6, 12), np.linspace(0, 30, 31)
    grid = 0.2 + 10 * (G[:, None] - 0.3) ** 2 + (E[None, :] / 30 - 0.5) ** 2
    depth = np.minimum(8 + 50 * G, 30.0)
    plots.master_curve_plot(
        tmp_path / "m.png", G, E, grid, G, depth, on_bound=depth >= 30, title="t"
    )
    (fig,) = figures
    ax = fig.axes[0]
    y0, y1 = ax.get_ylim()
    x0, x1 = ax.get_xlim()
    assert y0 < 0 and y1 > 30 and x0 < G[0] and x1 > G[-1]
    fig.canvas.draw()
    box = ax.get_window_extent()
    for ln in ax.get_lines():
        if ln.get_marker() == "X":  # the points on the bound, whole inside the axes
            xy = ax.transData.transform(np.c_[ln.get_xdata(), ln.get_ydata()])
            r = ln.get_markersize() / 2 * fig.dpi / 72
            assert np.all(xy[:, 1] + r <= box.y1) and np.all(xy[:, 0] + r <= box.x1)
    assert not ax.get_legend()  # the legend is the figure's, below the axes


def test_campbell_nodal_diameter_labels_do_not_overlap(tmp_path, figures):
    """A wheel with ND 1-8 web modes (two of each, 640-5 900 Hz) on the power pair (35/68
    teeth): the resonances of the low families crowd below 250 rad/s. Every ND label lies inside
    the axes, clear of the others and of the mode labels."""
    n = np.repeat(np.arange(1, 9), 2)
    f = np.repeat([700.0, 640.0, 1250.0, 1900.0, 2700.0, 3600.0, 4700.0, 5900.0], 2)
    f[1::2] += 3.0
    summary = _sweep_summary()
    summary.update(
        speeds_rad_s=np.linspace(150.0, 3000.0, 20).tolist(),
        pinion_teeth=35,
        wheel_teeth=68,
        nodal_diameter_resonances=nodal_diameter_resonances(f, n, 68, 35, harmonics=(1, 2)),
        critical_speeds=[],
    )
    plots.campbell_plot(tmp_path / "c.png", summary, 35)
    _png(tmp_path / "c.png")
    (fig,) = figures
    ax = fig.axes[0]
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    nd = [t for t in ax.texts if t.get_text().endswith("ND")]
    named = {int(k) for t in nd for k in re.findall(r"\d+", t.get_text())}
    assert named <= set(range(1, 9)) and {1, 8} <= named
    boxes = [Text.get_window_extent(t, renderer) for t in nd]
    others = [t.get_window_extent(renderer) for t in ax.texts if t not in nd]
    inside = ax.get_window_extent(renderer)
    for i, b in enumerate(boxes):
        assert inside.x0 <= b.x0 and b.x1 <= inside.x1 and inside.y0 <= b.y0 and b.y1 <= inside.y1
        assert not any(b.overlaps(o) for o in boxes[i + 1 :] + others), nd[i].get_text()


def _tick_label_overlaps(fig) -> list[tuple[str, str]]:
    """Pairs of drawn tick labels (major and minor, in the view) that overlap on an axis."""
    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    fig.canvas.draw()
    renderer = fig.canvas.get_renderer()
    bad = []
    for ax in fig.axes:
        for axis in (ax.xaxis, ax.yaxis):
            lo, hi = sorted(axis.get_view_interval())
            labels = []
            for minor in (False, True):
                locs = axis.get_minorticklocs() if minor else axis.get_majorticklocs()
                n = len(locs)
                ticks = axis.get_minor_ticks(n) if minor else axis.get_major_ticks(n)
                labels += [
                    t.label1
                    for t, loc in zip(ticks, locs, strict=True)
                    if lo - 1e-9 * abs(lo) <= loc <= hi + 1e-9 * abs(hi)
                    and t.label1.get_visible()
                    and t.label1.get_text()
                ]
            for a, b in itertools.combinations(labels, 2):
                if a.get_window_extent(renderer).overlaps(b.get_window_extent(renderer)):
                    bad.append((a.get_text(), b.get_text()))
    return bad


def test_thin_tick_labels_hides_overlapping_ones():
    """Log axes over about a decade with every minor tick labelled (the hybrid benchmark's
    formatter) on a small axes: 300 and 400 print over each other; thinned, none do, and the
    decades keep their labels."""

    def figure():
        fig = Figure(figsize=(3.2, 2.4), layout="constrained")
        FigureCanvasAgg(fig)
        ax = fig.add_subplot()
        ax.loglog([110, 1900], [35, 3000], "o-")
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 1)))
            axis.set_minor_formatter(LogFormatter(labelOnlyBase=False, minor_thresholds=(2, 1)))
        return fig

    assert _tick_label_overlaps(figure())
    fig = figure()
    assert thin_tick_labels(fig) > 0
    assert _tick_label_overlaps(fig) == []
    ax = fig.axes[0]
    shown = {t.get_text() for t in ax.xaxis.get_ticklabels() if t.get_visible()}
    assert {"100", "1000"} <= shown


@pytest.mark.parametrize(
    "chart, name", [(hybrid_chart, "bench_hybrid"), (hybrid_sweep_chart, "bench_hybrid_sweep")]
)
def test_benchmark_charts_have_no_overlapping_tick_labels(tmp_path, chart, name, monkeypatch):
    """The benchmark charts of docs/ redrawn from their JSON: no tick label over another."""
    figs = []
    save = Figure.savefig

    def keep(self, *args, **kw):
        figs.append(self)
        return save(self, *args, **kw)

    monkeypatch.setattr(Figure, "savefig", keep)
    chart(json.loads((DOCS / f"{name}.json").read_text()), str(tmp_path / f"{name}.png"))
    _png(tmp_path / f"{name}.png")
    (fig,) = figs
    assert _tick_label_overlaps(fig) == []


def test_sweep_of_three_speeds_says_its_lines_cross_critical_speeds(tmp_path, figures):
    """A 3-speed sweep joins its points straight across the critical speeds between them: the
    legend says so; a dense sweep, whose samples sit on every critical speed, says nothing."""
    plots.dynamic_factor_plot(tmp_path / "df.png", _few_speeds(_sweep_summary(), 3))
    plots.dynamic_factor_plot(tmp_path / "dense.png", _sweep_summary())
    few, dense = (fig.legends[0].get_title().get_text() for fig in figures)
    assert few.startswith("straight lines join the 3 computed speeds: ")
    assert "critical speeds lie between them" in few
    assert dense == ""


def test_dynamic_factor_names_at_most_three_peaks_without_overlap(tmp_path, figures):
    """Five resonance peaks: the three highest are named, each label inside the axes and clear
    of the others; the two others are marked only."""
    summary = _sweep_summary()
    sp = np.asarray(summary["speeds_rad_s"])
    df = np.asarray(summary["dynamic_factor"])
    for c, h in zip((200.0, 380.0, 560.0, 800.0, 1050.0), (0.9, 0.5, 0.7, 0.3, 0.6), strict=True):
        df = df + h / (1 + ((sp - c) / 12.0) ** 2)
    summary["dynamic_factor"] = df.tolist()
    peaks = plots.dynamic_factor_plot(tmp_path / "df.png", summary)
    _png(tmp_path / "df.png")
    assert len(peaks) == 5
    (fig,) = figures
    ax = fig.axes[0]
    labels = [t for t in ax.texts if "\nDF " in t.get_text()]
    assert sorted(float(t.get_text().rsplit(" ", 1)[1]) for t in labels) == pytest.approx(
        sorted(p["value"] for p in peaks)[-3:], abs=0.006
    )
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(r) for t in labels]
    inside = ax.get_window_extent(r)
    for i, b in enumerate(boxes):
        assert inside.x0 <= b.x0 and b.x1 <= inside.x1 and b.y1 <= inside.y1
        assert not any(b.overlaps(o) for o in boxes[i + 1 :])
    _assert_labels_hide_no_curve(ax, boxes)
    marked = [ln for ln in ax.get_lines() if ln.get_marker() == "v"]
    assert len(marked) == 1 and len(marked[0].get_xdata()) == 2


def _assert_labels_hide_no_curve(ax, boxes):
    """The peak labels' opaque boxes hide no part of the curves (each sampled every pixel)."""
    for line in ax.get_lines():
        x, y = np.asarray(line.get_xdata(), float), np.asarray(line.get_ydata(), float)
        if len(x) < 3:
            continue
        t = np.linspace(x.min(), x.max(), 4000)
        px = ax.transData.transform(np.column_stack([t, np.interp(t, x, y)]))
        for b in boxes:
            assert not b.count_contains(px), line.get_label()


def test_peak_labels_of_clustered_resonances_hide_no_curve(tmp_path, figures):
    """Three resonances 30 rad/s apart: each lower peak's label, first tried just above it,
    would sit on the higher neighbour's flank (its white box hid 173 pixels of the curve):
    every label is placed clear of the curves."""
    summary = _sweep_summary()
    sp = np.asarray(summary["speeds_rad_s"])
    df = np.asarray(summary["dynamic_factor"])
    for c, h in zip((500.0, 530.0, 560.0), (0.9, 0.6, 0.4), strict=True):
        df = df + h / (1 + ((sp - c) / 12.0) ** 2)
    summary["dynamic_factor"] = df.tolist()
    plots.dynamic_factor_plot(tmp_path / "df.png", summary)
    (fig,) = figures
    ax = fig.axes[0]
    fig.canvas.draw()
    r = fig.canvas.get_renderer()
    boxes = [t.get_window_extent(r) for t in ax.texts if "\nDF " in t.get_text()]
    assert len(boxes) == 3
    _assert_labels_hide_no_curve(ax, boxes)


def test_every_critical_speed_line_is_labelled(tmp_path, monkeypatch):
    """Each critical-speed line in range carries a label at its top, also the lines whose
    coincidence a peak's label names (those: their harmonic, "H1", above it; today they had
    none: one of three lines labelled on the default case's plot). Modes numbered from 1."""
    import matplotlib.figure

    figs = []
    real = matplotlib.figure.Figure.savefig

    def keep(fig, *args, **kw):
        figs.append(fig)
        return real(fig, *args, **kw)

    monkeypatch.setattr(matplotlib.figure.Figure, "savefig", keep)
    speed = 2 * math.pi * 2500.0 / (1 * Z1)  # mode index 2 × H1, a named peak
    summary = _sweep_summary(df_peak_speed=speed + 3.0)
    plots.dynamic_factor_plot(tmp_path / "df.png", summary)
    (fig,) = figs
    ax = fig.axes[0]
    sp = summary["speeds_rad_s"]
    shown = [c for c in summary["critical_speeds"] if sp[0] <= c["speed_rad_s"] <= sp[-1]]
    lines = [t.get_text() for t in ax.texts if t.get_rotation() == 90.0]
    assert len(lines) == len(shown) >= 3
    assert "H1" in lines  # the named peak's line
    assert all(re.fullmatch(r"(mode [1-4] × )?H[1-3]", t) for t in lines), lines
    assert "mode 2 × H2" in lines  # index 1: mode 2, as jaxgear modes numbers it


def test_root_stress_plot_draws_cells_on_one_line_as_points(tmp_path):
    """A root-stress map whose loaded cells lie on one line (or are fewer than three) spans no
    triangle: the panel draws them as points instead of failing in the triangulation (it
    raised qhull's "singular input data" in ``jaxgear run`` of a planetary stage at speed)."""
    from jaxgear.rating import RootStressMap

    line = np.zeros((1, 1, 4))
    s = np.linspace(0.0, 3e-3, 4).reshape(1, 1, 4)
    on_a_line = RootStressMap(stress=s * 1e11, roll=line, cell_s=s, cell_z=line,
                              mask=np.ones((1, 1, 4), bool))
    grid = RootStressMap(stress=np.arange(4.0).reshape(1, 2, 2) * 1e8, roll=np.zeros((1, 2, 2)),
                         cell_s=np.array([[[0.0, 1e-3], [0.0, 1e-3]]]),
                         cell_z=np.array([[[0.0, 0.0], [1e-3, 1e-3]]]),
                         mask=np.ones((1, 2, 2), bool))
    path = tmp_path / "root.png"
    plots.root_stress_plot(str(path), (on_a_line, grid), "t")
    assert path.stat().st_size > 0
