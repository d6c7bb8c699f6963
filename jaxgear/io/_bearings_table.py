"""The ``[bearings]`` table of a case: what ISO 281's modified rating life of its rolling
bearings needs beyond their loads and ratings (docs/bearings.md, "In the report")::

    [bearings]
    contamination_factor = 0.5      # ISO 281's e_C, [0, 1] (its guideline table by cleanliness)
    reliability_percent = 90.0      # optional (default 90), [90, 99.95] (ISO 281's a1)
    viscosity_mm2_per_s = 20.0      # optional: the oil's operating kinematic viscosity,
                                    # [2, 1e5]; default [lubricant]'s at its oil_temperature_C

The bearings themselves are the ``[scene]`` shafts' rolling bearings (``catalogue`` or
``kind``, with ``dynamic_rating_kN`` where the catalogue has no C); the speed is
``[operating] speed_rad_s`` (the pinion's), else the rating's ``speed_rpm``. Each key is checked at load, in one line in the
file's units; :func:`bearing_life_of` gives the SI settings.
"""

from __future__ import annotations

import math
from typing import ClassVar, NamedTuple

import pydantic

from fem_prep import schema as sc

from ._lubricant_table import VISCOSITY_RANGE, tribology_of
from ._sections import Section, number

__all__ = ["BearingLifeSettings", "BearingsSection", "bearing_life_of", "pinion_speed",
           "read_bearings"]


class BearingLifeSettings(NamedTuple):
    """The SI settings of ISO 281's modified rating life (:func:`bearing_life_of`):
    ``reliability`` R (a fraction), ``viscosity`` ν (m²/s), ``contamination`` e_C."""

    reliability: float
    viscosity: float
    contamination: float


def pinion_speed(operating: dict) -> float:
    """The pinion speed (rad/s) of a case file's ``[operating]`` table: ``speed_rad_s`` where
    > 0, else the rating's ``speed_rpm`` (converted), else 0."""
    speed = float(operating.get("speed_rad_s", 0.0))
    if speed <= 0 and operating.get("speed_rpm") is not None:
        speed = float(operating["speed_rpm"]) * 2.0 * math.pi / 60.0
    return speed


class BearingsSection(Section):
    """``[bearings]`` as the file gives it (keys and ranges: the module docstring)."""

    WHERE: ClassVar[str] = "bearings"
    contamination_factor: number("[0, 1]")
    reliability_percent: number("[90, 99.95]") = 90.0
    viscosity_mm2_per_s: number(VISCOSITY_RANGE) | None = pydantic.Field(
        None, json_schema_extra={"default": "[lubricant]'s at oil_temperature_C"})


def read_bearings(data: dict, scene, lubricant, shafts=None) -> BearingsSection | None:
    """A case file's ``[bearings]`` (:class:`BearingsSection`), or None without the table;
    ``scene``: the case's :class:`~jaxgear.io.SceneSpec` (or None), ``lubricant`` its
    ``[lubricant]`` section (or None), ``shafts`` its shafts as (table, ShaftSpec) pairs
    (default a pair's ``scene.pinion_shaft`` and ``scene.gear_shaft``; a train's
    ``scene.shafts.<name>``).

    Raises:
        SchemaError: a key out of range; no rolling bearing on the scene's shafts; no
            viscosity (neither ``viscosity_mm2_per_s`` nor ``[lubricant]``); no pinion speed;
            a rolling bearing without ``dynamic_rating_kN`` (one line each).
    """
    if "bearings" not in data:
        return None
    section = BearingsSection.read(data["bearings"])
    if scene is None or not scene.rolling:
        raise sc.fail("bearings", "contamination_factor", "not read: the case has no rolling "
                      "bearing (a [scene] shaft's bearing with catalogue or kind)")
    if section.viscosity_mm2_per_s is None and lubricant is None:
        raise sc.fail("bearings", "viscosity_mm2_per_s", "missing: ISO 281's modified life "
                      "needs the oil's viscosity (give it, or a [lubricant] table)")
    if not pinion_speed(data.get("operating", {})) > 0:
        raise sc.fail("operating", "speed_rad_s", "out of range with [bearings], allowed > 0 "
                      "(the bearings' lives in hours and ISO 281's rated viscosity need the "
                      "pinion speed; or the rating's speed_rpm)",
                      data.get("operating", {}).get("speed_rad_s", 0.0))
    if shafts is None:
        shafts = (("scene.pinion_shaft", scene.pinion_shaft),
                  ("scene.gear_shaft", scene.gear_shaft))
    for where, shaft in shafts:
        for i, b in enumerate(() if shaft is None else shaft.bearings):
            if b.rolling is not None and b.rolling.dynamic_rating is None:
                raise sc.fail(f"{where}.bearings[{i}]", "dynamic_rating_kN", "missing: "
                              "[bearings] rates every rolling bearing's life (the catalogue "
                              "entry has no C: give the maker's)")
    return section


def bearing_life_of(case) -> BearingLifeSettings | None:
    """The SI settings of a case's ``[bearings]`` (:class:`BearingLifeSettings`; the viscosity
    ``viscosity_mm2_per_s`` or its ``[lubricant]``'s at the oil temperature), or None
    without the table."""
    section = getattr(case, "bearings", None)
    if section is None:
        return None
    nu = section.viscosity_mm2_per_s
    if nu is None:
        nu = float(tribology_of(case).lubricant.kinematic_viscosity()) * 1e6
    return BearingLifeSettings(section.reliability_percent / 100.0, nu * 1e-6,
                               section.contamination_factor)
