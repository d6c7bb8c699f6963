"""``jaxgear run``'s first-look dynamic factor sweep on a housed case keeps to the speeds where
the model holds (docs/housing.md, "The first-look sweep"): every mesh's order-1 frequency within
the housing's band, cut-off / 1.5 (the band the condensed housing's response holds; the whine's
``in_band``), and says what it left out.

References written here: the housing's cut-off and the tooth counts read from the embedded case
files as text (TOML), each mesh's frequency z_g Ω_g / 2π with Ω_g the driving gear's shaft
speed from the tooth counts along the train; the unhoused first look's speeds as documented
(a pair 60 from 100 to 3000 rad/s, a train 30). No run: the sweep is replaced by a stub that
records the speeds it is given (the runs' numbers are the regression records'
``run-*-housed``)."""

from __future__ import annotations

import math
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear.cli import run as cli_run, sweep as cli_sweep

BAND = 1.5  # docs/housing.md, "What the condensation keeps": the response below cut-off / 1.5
MIN_SPEEDS = 5  # docs/housing.md, "The first-look sweep"


def _file(name):
    return tomllib.loads(jio.embedded_case_text(name))


def _cutoff_hz(t):
    h = t["housing"]
    return h["cutoff_Hz"] if "cutoff_Hz" in h else BAND * h["highest_mesh_frequency_Hz"]


def _mesh_orders(t):
    """Each mesh's frequency over the input speed times 2π (teeth per input turn), from the
    file's tooth counts: a pair's pinion teeth; a train's driving gear's teeth times its shaft's
    speed over the input's (each mesh turns its driven shaft at z_driving / z_driven)."""
    if "pinion" in t:
        return [t["pinion"]["teeth"]]
    gears = {g["name"]: g for g in t["gears"]}
    shaft = {n: g.get("shaft", n) for n, g in gears.items()}
    speed = {shaft[t["meshes"][0]["driving"]]: 1.0}
    out = []
    for m in t["meshes"]:
        g, h = gears[m["driving"]], gears[m["driven"]]
        w = speed[shaft[g["name"]]]
        speed[shaft[h["name"]]] = w * g["teeth"] / h["teeth"]
        out.append(g["teeth"] * w)
    return out


def _first_look(t):
    """The unhoused first look's speeds (rad/s): a pair's 60, a train's 30, 100 to 3000."""
    return np.linspace(100.0, 3000.0, 60 if "pinion" in t else 30)


def _speeds_run(case, monkeypatch, tmp_path):
    """(the speeds jaxgear run's sweep section passes to the sweep, the dynamics section)."""
    seen = {}

    def stub(case, speeds, out, **kw):
        seen["speeds"] = np.asarray(speeds, dtype=float)
        n = len(speeds)
        return {"speeds_rad_s": [float(v) for v in speeds], "dynamic_factor": [1.0] * n}, None

    monkeypatch.setattr(cli_sweep, "sweep_case_run", stub)
    section, _ = cli_run._sweep_section(case, str(tmp_path), True)
    return seen["speeds"], section


@pytest.mark.parametrize(
    "name", ["two-stage-housed", "power-helical-housed", "nrel-5mw-stage3-housed"]
)
def test_housed_first_look_stays_in_the_band(name, monkeypatch, tmp_path):
    """Every speed's highest order-1 mesh frequency lies within cut-off / 1.5; the speeds are
    the unhoused first look's within the band (at least five of them), else five evenly up to
    the band's edge; the dynamics section and the printed line name the band and the speeds
    left out."""
    t = _file(name)
    band = _cutoff_hz(t) / BAND
    top = max(abs(o) for o in _mesh_orders(t))  # teeth per input turn of the fastest mesh
    limit = 2 * math.pi * band / top  # rad/s
    grid = _first_look(t)
    inside = grid[grid * top / (2 * math.pi) <= band]
    want = inside if inside.size >= MIN_SPEEDS else np.linspace(limit / 5, limit, MIN_SPEEDS)
    speeds, section = _speeds_run(jio.load_case(name), monkeypatch, tmp_path)
    np.testing.assert_allclose(speeds, want, rtol=1e-12)
    assert np.all(speeds * top / (2 * math.pi) <= band * (1 + 1e-12))
    assert grid[-1] * top / (2 * math.pi) > band  # the full first look would leave the band
    b = section["housing_band"]
    np.testing.assert_allclose(
        [b["cutoff_Hz"], b["band_limit_Hz"], b["mesh_order"], b["speed_limit_rad_s"]],
        [_cutoff_hz(t), band, top, limit],
        rtol=1e-12,
    )
    assert b["first_look_rad_s"] == [100.0, 3000.0]
    assert cli_run.housing_band_lines(section) == [b["note"]]
    assert f"{limit:.4g} rad/s" in b["note"] and f"{band:.4g} Hz" in b["note"]
    assert "--speeds" in b["note"]


def test_the_expected_speeds_of_the_two_stage_train():
    """The train's numbers by hand: its fastest mesh is the first (28 teeth on the input,
    the second 35 x 28/127 = 7.7 per input turn), the band 3450 / 1.5 = 2300 Hz, so Ω_b =
    2π 2300 / 28 = 516.1 rad/s: the first look's 100-500 rad/s (600 rad/s puts the first mesh
    at 2674 Hz)."""
    t = _file("two-stage-housed")
    assert _mesh_orders(t) == pytest.approx([28.0, 35 * 28 / 127])
    assert _cutoff_hz(t) == pytest.approx(3450.0)
    assert 2 * math.pi * 2300 / 28 == pytest.approx(516.1, abs=0.05)


@pytest.mark.parametrize("name", ["two-stage", "accessory-spur"])
def test_an_unhoused_first_look_is_unchanged(name, monkeypatch, tmp_path):
    """Without [housing] the sweep runs the whole first look and says nothing of a band."""
    case = jio.load_case(name)
    assert cli_run.sweeps(case) and case.housing is None
    speeds, section = _speeds_run(case, monkeypatch, tmp_path)
    np.testing.assert_array_equal(speeds, _first_look(_file(name)))
    assert "housing_band" not in section and cli_run.housing_band_lines(section) == []


def test_jaxgear_sweep_says_which_speeds_lie_above_the_band():
    """``jaxgear sweep`` runs the speeds it is given and names those above the band's speed
    limit (two of these three on two-stage-housed: 600 and 3000 rad/s above 516.1)."""
    case = jio.load_case("two-stage-housed")
    (line,) = cli_sweep.housing_band_lines(case, [100.0, 600.0, 3000.0])
    assert line.startswith("2 of 3 speeds above 516.1 rad/s") and "2300 Hz" in line
    assert cli_sweep.housing_band_lines(case, [100.0, 500.0]) == []
    assert cli_sweep.housing_band_lines(jio.load_case("two-stage"), [3000.0]) == []
