"""The command line's figures (jaxgear.cli._plots) on small synthetic data: valid PNGs, the TE
exact/smooth coincidence rule, the dynamic-factor peak names and the Campbell crossings."""

from __future__ import annotations

import math

import numpy as np
import pytest

from jaxgear.cli import _plots as plots

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
    assert p["name"] == "mode 2 (2\u2009500 Hz) × H1"
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
    # the plot marks every crossing of the plotted modes (≥ 1 % mesh energy) in its speed range
    marked = plots.campbell_plot(tmp_path / "c.png", _sweep_summary(), Z1)
    _png(tmp_path / "c.png")
    s_max = 1200.0 * 1.05
    assert {(c["frequency_Hz"], c["harmonic"]) for c in marked} == {
        (f, h)
        for f in (1000.0, 2500.0)
        for h in (1, 2, 3, 4)
        if 2 * math.pi * f / (h * Z1) <= s_max
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
