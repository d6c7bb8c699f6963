"""The embedded ``two-stage-housed``: the embedded ``two-stage`` train in a
cast aluminium box round its three shafts, with the quasi-periodic whine to the housing's
surface (docs/housing.md, "In jaxgear run"; docs/whine.md, "Trains of several mesh
frequencies").

References written here: the ``two-stage`` file's own tables (the train is that case, unchanged);
the gears' tip circles and the shafts' axes from the involute geometry alone (the operating
centre distance of a profile-shifted helical pair, a_w = a cos α_t / cos α_wt with
inv α_wt = inv α_t + 2 tan α_n (x_1 + x_2) / (z_1 + z_2); the tip radius z m_n / (2 cos β) +
m_n (h_a* + x)) for the box's clearance; the mesh frequency z Ω / 2π for the band. Its run's
numbers are held by the regression record ``run-two-stage-housed`` (tests/test_regression.py)."""

from __future__ import annotations

import math
import tomllib

import pytest

import jaxgear.io as jio

NAME = "two-stage-housed"


def _tables(name):
    return tomllib.loads(jio.embedded_case_text(name))


def test_the_train_is_two_stage_unchanged():
    """Every table but the name, ``[housing]`` and ``[whine]`` is the ``two-stage`` file's, but
    for the quasi-static files' positions per pitch (4 instead of 16: the file's header)."""
    housed, train = _tables(NAME), _tables("two-stage")
    assert set(housed) - set(train) == {"housing", "whine"}
    assert (housed["mesh"].pop("positions_per_pitch"),
            train["mesh"].pop("positions_per_pitch")) == (4, 16)
    for key in train:
        if key != "name":
            assert housed[key] == train[key], key


def _inv(a):
    return math.tan(a) - a


def _operating_centre_distance(g1, g2):
    """a_w (mm) of two meshing helical gears (the case's [[gears]] tables), by the involute
    function inverted by Newton's method."""
    m, an, b = g1["normal_module_mm"], math.radians(g1["normal_pressure_angle_deg"]), math.radians(
        g1["helix_angle_deg"])
    z = g1["teeth"] + g2["teeth"]
    at = math.atan(math.tan(an) / math.cos(b))
    target = _inv(at) + 2 * math.tan(an) * (g1["profile_shift"] + g2["profile_shift"]) / z
    aw = at
    for _ in range(50):
        aw -= (_inv(aw) - target) / math.tan(aw) ** 2
    return z * m / (2 * math.cos(b)) * math.cos(at) / math.cos(aw)


def _tip_radius(g):
    m, b = g["normal_module_mm"], math.radians(g["helix_angle_deg"])
    return g["teeth"] * m / (2 * math.cos(b)) + m * (g["addendum_coeff"] + g["profile_shift"])


def test_housing_box_clears_every_gear_and_holds_the_band():
    """The box (centred across the shafts' axes, as docs/housing.md lays it) holds every gear's
    tip circle inside its walls with at least 5 mm to spare (the 127-tooth wheel 8 mm from the
    x+ wall); its named points lie on its outer faces; its cut-off is 1.5 x a frequency at or
    above the first mesh's order 5 at the top of the [whine] range, which is the benchmark's
    20-100 rad/s with the quasi-periodic balance."""
    t = _tables(NAME)
    gears = {g["name"]: g for g in t["gears"]}
    a1 = _operating_centre_distance(gears["input"], gears["hst-wheel"])
    a2 = _operating_centre_distance(gears["lst-pinion"], gears["output"])
    angle = math.radians(t["meshes"][1]["angle_deg"])
    centres = {"input": (0.0, 0.0), "hst-wheel": (a1, 0.0), "lst-pinion": (a1, 0.0),
               "output": (a1 + a2 * math.cos(angle), a2 * math.sin(angle))}
    xs, ys = [c[0] for c in centres.values()], [c[1] for c in centres.values()]
    mid = (0.5 * (min(xs) + max(xs)), 0.5 * (min(ys) + max(ys)))
    h = t["housing"]
    inner = h["wall_thickness_mm"]
    half = (h["width_mm"] / 2 - inner, h["height_mm"] / 2 - inner)
    spare = min(
        half[k] - abs(centres[name][k] - mid[k]) - _tip_radius(g)
        for name, g in gears.items() for k in (0, 1)
    )
    assert 5.0 < spare < 10.0
    faces = (mid[0] + h["width_mm"] / 2, mid[1] + h["height_mm"] / 2)
    assert t["housing"]["points_mm"]["lid"][1] == pytest.approx(faces[1], abs=0.1)
    assert t["housing"]["points_mm"]["side wall"][0] == pytest.approx(faces[0], abs=0.1)
    w = t["whine"]
    assert (w["speed_min_rad_s"], w["speed_max_rad_s"], w["method"]) == (20.0, 100.0,
                                                                         "quasi-periodic")
    order5 = 5 * gears["input"]["teeth"] * w["speed_max_rad_s"] / (2 * math.pi)
    assert order5 <= h["highest_mesh_frequency_Hz"] < 1.05 * order5
