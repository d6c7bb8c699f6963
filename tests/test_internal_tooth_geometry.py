"""fem_prep's internal tooth geometry (the ring's tooth for the tooth-form, FE and Weber models)
against jaxgear's InternalGearPair radii (ISO 21771, written separately in JAX's package) and
its one-line refusals."""

import math

import pytest

import fem_prep
import jaxgear as jg


@pytest.mark.parametrize("x2, beta", [(0.0, 0.0), (0.4, 0.0), (-0.2, math.radians(12.0))])
def test_radii_match_the_internal_pair(x2, beta):
    mn, an = 3e-3, math.radians(20.0)
    ring = jg.Member(-90, profile_shift=x2, face_width=0.02)
    pair = jg.InternalGearPair(jg.Member(25, 0.4, face_width=0.02), ring, mn, an, beta)
    g = jg.internal_tooth_geometry(pair, fem_prep.ShaperCutter(30))
    assert (g.teeth, g.profile_shift, g.helix_angle) == (-90, x2, beta)
    assert g.tip_radius == pytest.approx(pair.tip_radii[1], rel=1e-12)
    assert g.root_radius == pytest.approx(pair.root_radii[1], rel=1e-12)
    assert g.base_radius == pytest.approx(pair.base_radii[1], rel=1e-12)
    assert g.reference_radius == pytest.approx(pair.pitch_radii[1], rel=1e-12)


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"teeth": 90}, "teeth = 90 is out of range: allowed an integer <= -16"),
        ({"profile_shift": float("nan")}, "profile_shift = nan is out of range: allowed a finite number"),
        ({"cutter": fem_prep.ShaperCutter(85)}, "cutter.teeth = 85 is out of range"),
        ({"cutter": 30}, "cutter = 30 is out of range"),
    ],
)
def test_refusals_name_the_parameter(kwargs, message):
    args = {"teeth": -90, "normal_module": 3e-3, "normal_pressure_angle": 0.35, **kwargs}
    with pytest.raises(ValueError, match=message):
        fem_prep.InternalToothGeometry(**args)


def test_cutter_refusals():
    with pytest.raises(ValueError, match=r"teeth = 10 is out of range: allowed an integer >= 11"):
        fem_prep.ShaperCutter(10)
    with pytest.raises(ValueError, match=r"tip_radius_coeff = 0.7 is out of range"):
        fem_prep.ShaperCutter(30, tip_radius_coeff=0.7)


def test_pair_refusal_names_the_gear():
    pair = jg.InternalGearPair(
        jg.Member(25, 0.4, face_width=0.02), jg.Member(-90, face_width=0.02), 3e-3, 0.35
    )
    with pytest.raises(ValueError, match=r"^gear.cutter.teeth = 85 is out of range"):
        jg.internal_tooth_geometry(pair, fem_prep.ShaperCutter(85))
