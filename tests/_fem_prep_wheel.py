"""The small wheel of the fem_prep tests (a 12-tooth Craig-Bampton body of a few thousand DOFs):
its body file text, and the wheel prepared once per test process for the modules that read it
(tests/test_fem_prep_condense.py, tests/test_fem_prep_rotating.py): :func:`fem_prep.prepare` is
a pure function of the body, and its result is only read by the tests."""

from __future__ import annotations

import functools

from fem_prep import Prepared, parse_body, prepare

__all__ = ["prepared_wheel", "wheel_text"]


def wheel_text(
    holes=0,
    method="craig-bampton",
    modes=50,
    coupling="rigid",
    plain=False,
    teeth=12,
    rim_coupling="nodal",
):
    web = 10.0 if plain else 1.5
    hub_r = 26.0 if plain else 12.0
    return f"""
name = "tiny"
[body]
bore_radius_mm = 8.0
hub_outer_radius_mm = {hub_r}
hub_width_mm = {10.0 if plain else 12.0}
web_thickness_mm = {web}
rim_inner_radius_mm = 26.0
rim_outer_radius_mm = 30.0
rim_width_mm = {10.0 if plain else 8.0}
holes = {{ count = {holes}, center_radius_mm = 19.0, radius_mm = 4.0 }}
[[bearings]]
axial_position_mm = -5.0
coupling = "{coupling}"
[[bearings]]
axial_position_mm = 5.0
coupling = "{coupling}"
[mesh]
size_mm = 4.0
circumferential_size_mm = 8.0
[condensation]
method = "{method}"
modes = {modes}
teeth = {teeth}
axial_master_nodes = 3
rim_coupling = "{rim_coupling}"
[centrifugal]
speed_rad_s = 2000.0
"""


def prepared_wheel(**kwargs) -> Prepared:
    """``prepare(parse_body(wheel_text(**kwargs)))``, once per test process and body text."""
    return _prepared(wheel_text(**kwargs))


@functools.cache
def _prepared(text: str) -> Prepared:
    return prepare(parse_body(text))
