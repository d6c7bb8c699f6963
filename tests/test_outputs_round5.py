"""What the outputs say (issue 69 §6): a sweep with nothing to excite says so (lin-parker-1999:
constant mesh springs, no pin errors, DF = 1, not round-off); sweep.csv's column names in snake
case; titles that keep a unit with its number when wrapped; the planetary Campbell title; every
critical-speed line labelled; no "modified" rows when a case has none; which stiffness each
curve of a flexible case is. Titles and labels are read back from the matplotlib figures."""

from __future__ import annotations

import csv
import re
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear.cli import planetary_sweep as ps
from jaxgear.cli._plots import _figure

pytestmark = [pytest.mark.filterwarnings("ignore:.*time step under-resolved"),
              pytest.mark.filterwarnings("ignore:.*not settled")]

LP_SPEEDS = np.array([40.0, 100.0])  # rad/s of the sun; the case's operating speed is 100
LP_RUN = {"steps_per_period": 16, "periods": 4, "keep_periods": 2}


def _capture(monkeypatch, module):
    """Replace ``module.legend_below_and_save`` by one that keeps (fig, ax) and the legend's
    labels, and still writes the file."""
    figs = []
    real = module.legend_below_and_save

    def keep(fig, ax, path, note):
        labels = real(fig, ax, path, note)
        figs.append((fig, ax, labels, note))
        return labels

    monkeypatch.setattr(module, "legend_below_and_save", keep)
    return figs


@pytest.fixture(scope="module")
def lin_parker():
    return jio.load_case("lin-parker-1999")


def test_lin_parker_has_nothing_to_excite(lin_parker):
    """The lumped form's constant springs: the meshes' stiffness over a mesh period varies by
    0 relative to its mean (round-off at most), no pin error, no eccentricity: not excited."""
    spec, stage, meshes, model = ps._dynamic_setup(lin_parker.form, lin_parker)
    e = ps.excitation(model, stage, meshes, spec)
    assert e["mesh_stiffness_variation"] < 1e-12
    assert e["excited"] is False and "no excitation" in e["words"]


def test_a_pin_error_or_an_eccentricity_is_an_excitation(lin_parker):
    """The same stage with a 10 µm pin error, or a 20 µm sun eccentricity, is excited."""
    for extra in ({"tangential_pin_errors_um": [10.0, 0.0, 0.0]},
                  {"sun_eccentricity_um": 20.0}):
        data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
        data["planetary"].update(extra)
        case = jio.parse_train(data)
        spec, stage, meshes, model = ps._dynamic_setup(case.form, case)
        assert ps.excitation(model, stage, meshes, spec)["excited"] is True, extra


def test_the_unexcited_sweep_says_df_1(lin_parker, tmp_path, monkeypatch):
    """lin-parker-1999's sweep: dynamic factor and K_γ exactly 1 (the round-off kept in
    ``excitation``), the ring spectrum at the operating speed (not one chosen by round-off),
    the figure's title and legend saying "no excitation" and its y axis without an offset
    (today: "1e-11+1", ticks −3…1); the printed line says so."""
    figs = _capture(monkeypatch, ps)
    s = ps.planetary_sweep(lin_parker.form, lin_parker, LP_SPEEDS, str(tmp_path), **LP_RUN)
    assert s["dynamic_factor"] == [1.0, 1.0] and s["k_gamma"] == [1.0, 1.0]
    assert np.all(np.asarray(s["dynamic_factor_mesh"]) == 1.0)
    assert s["excitation"]["round_off_deviation"] < 1e-8
    assert s["ring_spectrum"]["speed_rad_s"] == 100.0
    by_title = {ax.get_title(): (ax, labels) for _, ax, labels, _ in figs}
    (title, (ax, labels)), = ((t, v) for t, v in by_title.items() if "dynamic factor" in t)
    assert "no excitation, dynamic factor = 1" in title.replace("\n", " ")
    assert labels == ["every mesh's dynamic factor and K_γ: 1"] + [
        lab for lab in labels[1:] if lab.startswith("mesh order")]
    offset = ax.yaxis.get_major_formatter().get_offset()
    assert offset == "" and ax.get_ylim() == (0.9, 1.1)
    spectrum = next(t for t in by_title if "ring transducer" in t)
    assert "no excitation" in spectrum.replace("\n", " ")
    line = ps.sweep_lines(lin_parker, s)[0]
    assert "no excitation" in line and "dynamic factor = 1" in line
    # the CSV's columns: snake case, the mesh names' spaces and hyphens gone
    with open(tmp_path / "sweep.csv", newline="") as f:
        header = next(csv.reader(f))
    assert all(re.fullmatch(r"[a-z0-9_]+(Hz)?", h) for h in header), header
    assert "dynamic_factor_mesh_sun_planet_1" in header
    assert "dynamic_factor_mesh_ring_planet_3" in header


def test_every_crossing_line_is_labelled(tmp_path, monkeypatch):
    """The planetary dynamic-factor plot: one text label per crossing line (frequency and
    order), not one legend entry per order only."""
    figs = _capture(monkeypatch, ps)
    crossings = [{"order": 3, "frequency_Hz": 743.2, "speed_rad_s": 72.5},
                 {"order": 3, "frequency_Hz": 1102.0, "speed_rad_s": 107.6},
                 {"order": 2, "frequency_Hz": 743.2, "speed_rad_s": 108.8}]
    summary = {"speeds_rad_s": [20.0, 120.0], "dynamic_factor_mesh": [[1.1, 1.2], [1.3, 1.0]],
               "mesh_names": ["sun-planet 1", "ring-planet 1"], "k_gamma": [1.0, 1.0],
               "crossings": crossings, "speed_of": "input (sun)", "model": "planar",
               "ring_model": "rigid ring"}

    class Case:
        name = "x"

    ps.dynamic_factor_plot(Case, summary, str(tmp_path / "df.png"))
    (_, ax, _, _), = figs
    texts = sorted(t.get_text() for t in ax.texts)
    assert texts == ["1102 Hz / 3", "743 Hz / 2", "743 Hz / 3"]


def test_a_wrapped_title_keeps_units_with_their_numbers():
    """A title wider than its axes is wrapped at spaces, but never between a number and its
    unit or after a ≥ sign (today "5 %" ends a line with "5" and starts the next with "%")."""
    fig, ax = _figure.new_figure()
    words = "power-helical: Campbell diagram, modes with ≥ 1% mesh strain energy (black ≥ 5 %)"
    for pad in range(0, 40):  # wherever the break falls, "%" never starts a line
        ax.set_title("x" * pad + " " + words)
        _figure.wrap_titles(fig)
        lines = ax.get_title().splitlines()
        assert len(lines) >= 1
        assert not any(line.lstrip().startswith(("%", "µm")) for line in lines)
        assert not any(line.rstrip().endswith("≥") for line in lines)
