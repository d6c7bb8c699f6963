"""Shared pieces of the rating tests: the accessory pair rated to ISO 6336 (a `[rating]` added
to the embedded case, no scene) and a stub FE fillet table for the root-stress plumbing."""

from __future__ import annotations

import math
import tomllib
from typing import NamedTuple

import numpy as np

import jaxgear.io as jio


def rated_accessory_case(slices: int, positions_per_pitch: int) -> jio.Case:
    """The embedded accessory pair with a ``[rating]`` (σ_Hlim 1500, σ_Flim 430 N/mm², 6000
    1/min, 20 000 h) and no scene: the quasi-static model at the given resolution."""
    return jio.parse_case(rated_accessory_data(slices, positions_per_pitch))


def rated_accessory_data(slices: int, positions_per_pitch: int) -> dict:
    """:func:`rated_accessory_case` as the parsed TOML (a dict, to write or change)."""
    d = tomllib.loads(jio.embedded_case_text("accessory-spur"))
    d.pop("scene", None)
    d["mesh"].update(slices=slices, positions_per_pitch=positions_per_pitch)
    return with_rating(d)


def with_rating(d: dict) -> dict:
    """The parsed case file ``d`` given the rating's keys (a case-hardened steel's σ_Hlim 1500 and
    σ_Flim 430 MPa, 6000 1/min, 20 000 h, ISO VG 46, Rz 3/10 µm), changed in place and returned."""
    d["material"].update(sigma_H_lim_MPa=1500.0, sigma_F_lim_MPa=430.0)
    d["operating"]["speed_rpm"] = 6000.0
    d["rating"] = {
        "life_h": 20000.0,
        "viscosity_40C_mm2_s": 46.0,
        "roughness_Rz_flank_um": 3.0,
        "roughness_Rz_root_um": 10.0,
    }
    return d


class Cells(NamedTuple):
    """A hand-made load map: what the root-stress map reads of a quasi-static result."""

    line_load: np.ndarray
    cell_s: np.ndarray
    cell_z: np.ndarray
    cell_mask: np.ndarray


class Table(NamedTuple):
    """A fillet table: roll distance on the member's flank (m) → peak root stress (Pa per N/m)."""

    roll: np.ndarray
    peak: np.ndarray


def stub_table(tooth, radii) -> Table:
    """A stub FE table, g(ρ) = 1e3 ρ (Pa per N/m): linear, so exact under interpolation."""
    rb = tooth.teeth * tooth.normal_module / 2 * math.cos(tooth.normal_pressure_angle)
    roll = np.sqrt(np.asarray(radii) ** 2 - rb**2)
    return Table(roll, 1e3 * roll)
