"""Case files: schema, units, embedded cases and the documented errors for bad input."""

import math
import tomllib

import numpy as np
import pytest

import jaxgear.io as jio

SCHEMA_EXAMPLE = """
name = "my-pair"
[pair]
normal_module_mm = 1.5
normal_pressure_angle_deg = 25.0
helix_angle_deg = 0.0
[pinion]
teeth = 45
profile_shift = 0.341
addendum_coeff = 0.9447
dedendum_coeff = 1.1933
face_width_mm = 11.5
[gear]
teeth = 86
profile_shift = 0.481
addendum_coeff = 0.9447
dedendum_coeff = 1.1933
face_width_mm = 9.5
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
[operating]
torque_Nm = 80.0
[mesh]
stiffness = "weber"
slices = 40
positions_per_pitch = 64
[modifications]
tip_relief = { depth_um = 15.0, extent = 0.25, shape = "linear" }
crowning = { depth_um = 0.0 }
"""


def _data():
    return tomllib.loads(SCHEMA_EXAMPLE)


def test_issue_schema_example_parses_in_si_units():
    c = jio.parse_case(_data())
    assert c.name == "my-pair"
    assert c.pair.normal_module == pytest.approx(1.5e-3)
    assert c.pair.normal_pressure_angle == pytest.approx(math.radians(25))
    assert c.pair.pinion.face_width == pytest.approx(11.5e-3)
    assert c.pair.face_width == pytest.approx(9.5e-3)  # overlap of the two face widths
    assert c.torque == 80.0
    # symmetric tip relief: depth on both members, in metres
    assert float(c.modifications.pinion.tip_relief_depth) == pytest.approx(15e-6)
    assert float(c.modifications.gear.tip_relief_depth) == pytest.approx(15e-6)
    assert float(c.modifications.gear.tip_relief_extent) == 0.25
    # default centre distance = zero-backlash distance; 99.45 mm is the value in the issue's comment
    assert c.pair.center_distance * 1e3 == pytest.approx(99.45, abs=5e-3)


def test_per_member_modifications_override_the_common_table():
    d = _data()
    d["modifications"]["pinion"] = {
        "tip_relief": {"depth_um": 5.0, "extent": 0.4, "shape": "parabolic"}
    }
    c = jio.parse_case(d)
    assert float(c.modifications.pinion.tip_relief_depth) == pytest.approx(5e-6)
    assert c.modifications.pinion.tip_relief_shape == "parabolic"
    assert float(c.modifications.gear.tip_relief_depth) == pytest.approx(15e-6)


def test_uniform_stiffness_unit_conversion():
    d = _data()
    d["mesh"].update(stiffness="uniform", stiffness_per_length_N_per_mm_per_um=13.0)
    c = jio.parse_case(d)
    # 13 N/(mm·µm) = 13e3 N/m / 1e-6 m = 1.3e10 N/m²
    assert c.stiffness.k0 == pytest.approx(1.3e10)
    m = c.mesh_model()
    assert np.allclose(np.asarray(m.stiffness_k), 1.3e10)


@pytest.mark.parametrize("name", ["accessory-spur", "power-helical"])
def test_embedded_cases_load(name):
    assert name in jio.list_cases()
    c = jio.load_case(name)
    assert c.name == name
    assert c.pair.transverse_contact_ratio > 1


def test_power_helical_is_table_III5():
    c = jio.load_case("power-helical")
    assert (c.pair.pinion.teeth, c.pair.gear.teeth) == (35, 68)
    assert c.pair.helix_angle == pytest.approx(math.radians(12))
    assert c.torque == 310.0


def _expect(mutate, *needles):
    d = _data()
    mutate(d)
    with pytest.raises(ValueError) as info:
        jio.parse_case(d)
    msg = str(info.value)
    for n in needles:
        assert n in msg, msg


def test_unknown_keys_are_named():
    _expect(lambda d: d["pinion"].update(face_widht_mm=3.0), "face_widht_mm")
    _expect(lambda d: d.update(extra={}), "extra")
    _expect(lambda d: d["modifications"].update(tip_releif={"depth_um": 1.0}), "tip_releif")
    _expect(lambda d: d["modifications"]["tip_relief"].update(depht_um=1.0), "depht_um")


def test_range_errors_name_parameter_value_and_range():
    _expect(
        lambda d: d["modifications"]["tip_relief"].update(depth_um=-2.0),
        "depth_um",
        "-2",
        "[0, 1500]",
    )
    _expect(
        lambda d: d["modifications"]["tip_relief"].update(extent=1.5), "extent", "1.5", "(0, 1]"
    )
    _expect(lambda d: d["modifications"]["tip_relief"].update(extent=0.0), "extent", "(0, 1]")
    _expect(lambda d: d["modifications"]["crowning"].update(depth_um=-1.0), "crowning", "depth_um")
    _expect(lambda d: d["pinion"].update(face_width_mm=0.0), "face_width_mm", "> 0")
    _expect(lambda d: d["pair"].update(normal_module_mm=-1.5), "normal_module_mm", "[0.01, 100]")
    _expect(lambda d: d["operating"].update(torque_Nm=-5.0), "torque_Nm", ">= 2.91e-07")
    _expect(lambda d: d["mesh"].update(stiffness="fem"), "stiffness", "fem")
    _expect(lambda d: d["mesh"].update(slices=0), "slices")
    _expect(lambda d: d["modifications"]["tip_relief"].update(shape="cubic"), "shape", "cubic")


def test_geometry_errors_reach_the_case_loader():
    # pointed teeth: a large addendum on a small pinion
    _expect(
        lambda d: d["pinion"].update(teeth=12, addendum_coeff=1.6, profile_shift=0.6), "pointed"
    )
    # contact ratio below 1: tiny addenda
    _expect(
        lambda d: (d["pinion"].update(addendum_coeff=0.3), d["gear"].update(addendum_coeff=0.3)),
        "contact ratio",
        ">= 1",
    )
    # centre distance below the zero-backlash distance
    _expect(lambda d: d["pair"].update(center_distance_mm=99.0), "center_distance", "zero-backlash")


def test_missing_file_and_corrupt_toml(tmp_path):
    with pytest.raises(FileNotFoundError, match=r"case file '.*nope.toml': no such file"):
        jio.load_case(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[pair\nnormal_module_mm = 1")
    with pytest.raises(ValueError, match="not valid TOML"):
        jio.load_case(bad)


def test_missing_required_key():
    _expect(lambda d: d["pinion"].pop("teeth"), "teeth")
    _expect(lambda d: d.pop("operating"), "operating")
