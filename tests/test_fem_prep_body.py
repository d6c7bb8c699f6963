"""Body-file schema: the issue's example is accepted as written; bad inputs raise clear errors."""

import pytest

from fem_prep import embedded_bodies, embedded_body_text, load_body, parse_body

ISSUE_EXAMPLE = """
name = "my-wheel"
[body]                                  # meridian section, axisymmetric; z = 0 at mid-rim
bore_radius_mm = 20.0
hub_outer_radius_mm = 35.0
hub_width_mm = 30.0
web_thickness_mm = 4.0
web_offset_mm = 0.0                     # axial offset of the web mid-plane from mid-rim
web_inclination_deg = 0.0
rim_inner_radius_mm = 55.0
rim_outer_radius_mm = 62.0              # root circle
rim_width_mm = 10.0
holes = { count = 0, center_radius_mm = 45.0, radius_mm = 5.0 }
[[bearings]]                            # 6-DOF nodes coupled to the bore at these axial positions
axial_position_mm = 0.0
coupling = "rigid"                      # or "averaging"
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
[mesh]
element = "hex20"                       # or "hex27"
size_mm = 2.0                           # target edge length; per-region overrides allowed
[condensation]
method = "craig-bampton"                # "guyan" | "craig-bampton" | "herting"
modes = 50
teeth = 86                              # master-node angular grid = one station per tooth
axial_master_nodes = 5
[centrifugal]
speed_rad_s = 1000.0
"""


def test_issue_example_accepted_in_si():
    b = parse_body(ISSUE_EXAMPLE)
    assert b.name == "my-wheel"
    assert b.geometry.bore_radius == pytest.approx(0.020)
    assert b.geometry.rim_outer_radius == pytest.approx(0.062)
    assert b.material.youngs_modulus == pytest.approx(210e9)
    assert b.condensation.teeth == 86 and b.condensation.modes == 50
    assert b.bearings[0].coupling == "rigid"
    assert b.speed == 1000.0
    assert len(b.sha256) == 64


def test_embedded_bodies_load():
    names = embedded_bodies()
    assert {"accessory-wheel", "power-helical-wheel"} <= set(names)
    acc = load_body("accessory-wheel")
    # root radius r_f = m (z/2 + x - h_f*) from Tab. III-1 (independent arithmetic)
    assert acc.geometry.rim_outer_radius == pytest.approx(
        1.5e-3 * (86 / 2 + 0.481 - 1.1933), rel=1e-4
    )
    assert acc.condensation.teeth == 86
    assert acc.geometry.rim_width == pytest.approx(9.5e-3)
    idler = load_body("accessory-idler")  # the flexible-idler case's 61-tooth idler
    assert idler.geometry.rim_outer_radius == pytest.approx(
        1.5e-3 * (61 / 2 + 0.4 - 1.1933), rel=1e-4
    )
    assert idler.condensation.teeth == 61


def _replace(old: str, new: str) -> str:
    assert old in ISSUE_EXAMPLE
    return ISSUE_EXAMPLE.replace(old, new)


@pytest.mark.parametrize(
    "old,new,match",
    [
        ("bore_radius_mm = 20.0", "bore_radius_mm = 40.0", "bore_radius_mm = 40"),
        ("rim_inner_radius_mm = 55.0", "rim_inner_radius_mm = 65.0", "rim_inner_radius_mm = 65"),
        ("web_thickness_mm = 4.0", "web_thickness_mm = 12.0", "web_thickness_mm = 12"),
        ("hub_width_mm = 30.0", "hub_width_mm = -3.0", "hub_width_mm = -3"),
        (
            "rim_width_mm = 10.0",
            "rim_width_mm = 0.0",
            r"rim_width_mm = 0: out of range, allowed \[0.001, 1e\+06\]",
        ),
        ("modes = 50", "modes = -1", r"modes = -1: out of range, allowed \[0, 2000\]"),
        ('method = "craig-bampton"', 'method = "mcneal"', "method = 'mcneal'"),
        ('element = "hex20"', 'element = "tet10"', "element = 'tet10'"),
        ('coupling = "rigid"', 'coupling = "glue"', "coupling = 'glue'"),
        (
            "holes = { count = 0, center_radius_mm = 45.0,",
            "holes = { count = 6, center_radius_mm = 38.0,",
            r"\[body\.holes\] center_radius_mm = 38: .*allowed \(40, 50\)",
        ),
        (
            "holes = { count = 0, center_radius_mm = 45.0, radius_mm = 5.0 }",
            "holes = { count = 40, center_radius_mm = 45.0, radius_mm = 4.0 }",
            "overlap",
        ),
        (
            "web_offset_mm = 0.0",
            "web_offset_mm = 4.0",
            r"\[body\] web_offset_mm = 4: .*allowed \[-3, 3\]",
        ),
        ("poisson_ratio = 0.3", "poisson_ratio = 0.5", "poisson_ratio = 0.5"),
        (
            "teeth = 86",
            "teeth = 2",
            r"\[condensation\] teeth = 2: out of range, allowed \[3, 1000\]",
        ),
        ("size_mm = 2.0", "size_mm = 0.0", r"size_mm = 0: out of range, allowed \[0.001, 1e\+06\]"),
        ("modes = 50", "modes = 50.5", "modes = 50.5: must be an integer"),
        ("speed_rad_s = 1000.0", "speed_rad_s = 1000.0\nrpm = 3", "unknown key.*'rpm'"),
        ("[material]", "[material]\nyoung = 1", "unknown key.*'young'"),
        ('name = "my-wheel"', "name = \"my-wheel\"\ncolour = 'red'", "unknown key 'colour'"),
    ],
)
def test_bad_inputs_raise_named_errors(old, new, match):
    with pytest.raises(ValueError, match=match):
        parse_body(_replace(old, new))


def test_missing_key_and_bad_toml():
    with pytest.raises(ValueError, match=r"\[body\] bore_radius_mm: missing required key"):
        parse_body(_replace("bore_radius_mm = 20.0\n", ""))
    with pytest.raises(ValueError, match="not valid TOML"):
        parse_body("[body\n")
    with pytest.raises(ValueError, match="bearings"):
        parse_body(
            _replace(
                '[[bearings]]                            # 6-DOF nodes coupled to the bore at these axial positions\naxial_position_mm = 0.0\ncoupling = "rigid"                      # or "averaging"\n',
                "",
            )
        )


def test_missing_file_is_clear(tmp_path):
    with pytest.raises(FileNotFoundError, match="not found.*embedded bodies"):
        load_body(tmp_path / "nope.toml")


def _two_bearings(w0="", w1="", p0=-10.0, p1=5.0):
    bearings = f"[[bearings]]\naxial_position_mm = {p0}\n{w0}\n[[bearings]]\naxial_position_mm = {p1}\n{w1}\n"
    return ISSUE_EXAMPLE.replace(
        '[[bearings]]                            # 6-DOF nodes coupled to the bore at these axial positions\naxial_position_mm = 0.0\ncoupling = "rigid"                      # or "averaging"\n',
        bearings,
    )


def test_bearing_width_default_covers_the_hub_share_and_is_clipped():
    # one bearing: the whole hub width (30 mm), centred on the hub
    (b,) = parse_body(ISSUE_EXAMPLE).bearings
    assert b.width == pytest.approx(0.030)
    assert b.z_band == pytest.approx((-0.015, 0.015))
    # two bearings 15 mm apart on a 30 mm hub [-15, 15]: hub / 2 = 15 mm each, the first
    # clipped at the hub face, the bands touch at -2.5 mm without overlapping
    b0, b1 = parse_body(_two_bearings()).bearings
    assert (b0.width, b1.width) == pytest.approx((0.015, 0.015))
    assert b0.z_band == pytest.approx((-0.015, -0.0025))
    assert b1.z_band == pytest.approx((-0.0025, 0.0125))
    # closer bearings: the default shrinks to their distance
    b0, b1 = parse_body(_two_bearings(p0=0.0, p1=6.0)).bearings
    assert b0.width == pytest.approx(0.006) and b0.z_band == pytest.approx((-0.003, 0.003))


def test_bearing_width_explicit_and_errors():
    b0, b1 = parse_body(_two_bearings("width_mm = 4.0", "width_mm = 8.0")).bearings
    assert b0.z_band == pytest.approx((-0.012, -0.008))
    assert b1.z_band == pytest.approx((0.001, 0.009))
    with pytest.raises(ValueError, match=r"^\[bearings\[0\]\] width_mm = 0: out of range, allowed"):
        parse_body(_two_bearings("width_mm = 0.0"))
    with pytest.raises(ValueError, match=r"^\[bearings\[1\]\] width_mm = 'wide': must be a number"):
        parse_body(_two_bearings("", 'width_mm = "wide"'))
    msg = (
        r"^\[bearings\[1\]\] width_mm = 28: its band \[-9, 15\] mm overlaps the band \[-12, -8\] "
        r"mm of bearings\[0\] \(bands are axial_position_mm -/\+ width_mm/2 and must not overlap; "
        r"bearings 15 mm apart\)$"
    )
    with pytest.raises(ValueError, match=msg):
        parse_body(_two_bearings("width_mm = 4.0", "width_mm = 28.0"))
    # an explicit width next to a default one: the explicit one is named
    with pytest.raises(ValueError, match=r"^\[bearings\[0\]\] width_mm = 30: its band"):
        parse_body(_two_bearings("width_mm = 30.0", ""))


def test_unknown_embedded_body_lists_the_embedded_bodies():
    with pytest.raises(FileNotFoundError, match=r"no embedded body 'nope' \(embedded bodies: "):
        embedded_body_text("nope")
