"""The ``[lubricant]`` table of a case (a pair's; a train's or a planetary stage's with
``[[gears]]``, for every mesh): the oil, the flanks' roughness, the friction law and
the film formula of the mesh's film and sliding loss (:mod:`jaxgear.tribology`; names → objects
here only)::

    [lubricant]
    viscosity_40C_mm2_s = 316.0          # ν₄₀, [2, 1e5] (Walther's equation from 2 mm²/s)
    viscosity_100C_mm2_s = 22.2          # ν₁₀₀, [2, ν₄₀)
    density_kg_m3 = 902.0               # at 15 °C, (500, 2000)
    thermal_expansion_per_K = 5.8e-4      # optional (default 0), [0, 0.01)
    pressure_viscosity_per_GPa = 71.05    # Barus' α at the oil temperature, (0, 100]
    oil_temperature_C = 75.0            # (−50, 250)
    roughness_Ra_um = [0.6, 0.6]        # R_a of pinion and gear flanks (or one number), (0, 10]
    lubricant_factor = 0.85             # Schlenk's X_L, optional (default 1.0, mineral oil)
    friction_coefficient = 0.05         # optional: a given μ instead of Schlenk's
    film = "dowson-higginson"           # optional: "dowson-higginson", "pan-hamrock", "grubin",
                                        # "iso-ts-6336-22"

The scuffing keys: :mod:`jaxgear.io._scuffing_table`; the micropitting keys (ISO/TS 6336-22):
:mod:`jaxgear.io._micropitting_table`.

The pinion speed (a train's or a stage's: its input member's) comes from ``[operating]
speed_rad_s`` (> 0) or, without it, ``[operating] speed_rpm`` (the rating's).
"""

from __future__ import annotations

import math
from typing import NamedTuple

from fem_prep import schema as sc

from ..tribology import (
    AbstractFilmFormula,
    AbstractFriction,
    DowsonHigginson,
    GivenFriction,
    Grubin,
    Lubricant,
    PanHamrock,
    Schlenk,
    TSMicropittingFilm,
)
from ._micropitting_table import MICROPITTING_KEYS, MicropittingInputs, parse_micropitting
from ._scuffing_table import SCUFFING_KEYS, ScuffingInputs, parse_scuffing

__all__ = ["FILM_FORMULAS", "LUBRICANT_KEYS", "TribologyInputs", "parse_lubricant", "tribology_of"]

#: the kinematic viscosities' range (mm²/s): ASTM D341-20's Walther equation is stated from
#: 2 mm²/s (below 0.3 mm²/s its double logarithm has no value) to 2e7 mm²/s
VISCOSITY_RANGE = "[2, 1e+05]"
#: the keys of ``[lubricant]``
LUBRICANT_KEYS = {
    "viscosity_40C_mm2_s",
    "viscosity_100C_mm2_s",
    "density_kg_m3",
    "thermal_expansion_per_K",
    "pressure_viscosity_per_GPa",
    "oil_temperature_C",
    "roughness_Ra_um",
    "lubricant_factor",
    "friction_coefficient",
    "film",
} | SCUFFING_KEYS | MICROPITTING_KEYS  # jaxgear.io._scuffing_table, ._micropitting_table

#: film formula names → kinds
FILM_FORMULAS = {
    "dowson-higginson": DowsonHigginson,
    "pan-hamrock": PanHamrock,
    "grubin": Grubin,
    "iso-ts-6336-22": TSMicropittingFilm,
}


class TribologyInputs(NamedTuple):
    """What ``[lubricant]`` gives :func:`jaxgear.tribology.mesh_tribology` (SI units):
    ``lubricant``, ``roughness`` (R_a1, R_a2) (m), ``friction`` and ``film`` kinds, ``speed``
    (pinion, rad/s), ``scuffing`` (:class:`~jaxgear.io._scuffing_table.ScuffingInputs` or
    None), ``micropitting`` (:class:`~jaxgear.io._micropitting_table.MicropittingInputs` or
    None)."""

    lubricant: Lubricant
    roughness: tuple[float, float]
    friction: AbstractFriction
    film: AbstractFilmFormula
    speed: float
    scuffing: ScuffingInputs | None = None
    micropitting: MicropittingInputs | None = None


def parse_lubricant(table: dict, operating: dict) -> TribologyInputs:
    """Validate ``[lubricant]`` (and the speed of ``[operating]``) and build its objects.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and the allowed range.
    """
    w = "lubricant"
    sc.check_keys(table, LUBRICANT_KEYS, w)
    walther = " (Walther's equation, ASTM D341, holds from 2 mm²/s)"
    nu40 = sc.number(table, "viscosity_40C_mm2_s", w, allowed=VISCOSITY_RANGE, note=walther)
    nu100 = sc.number(table, "viscosity_100C_mm2_s", w, allowed=VISCOSITY_RANGE, note=walther)
    if nu100 >= nu40:
        raise sc.fail(
            w,
            "viscosity_100C_mm2_s",
            f"out of range, allowed < viscosity_40C_mm2_s = {nu40:g} (an oil thins as it warms)",
            nu100,
        )
    rho = sc.number(table, "density_kg_m3", w, allowed="(500, 2000)")
    gamma = sc.number(table, "thermal_expansion_per_K", w, 0.0, allowed="[0, 0.01)")
    alpha = sc.number(table, "pressure_viscosity_per_GPa", w, allowed="(0, 100]")
    temp = sc.number(table, "oil_temperature_C", w, allowed="(-50, 250)")
    ra = table.get("roughness_Ra_um")
    if isinstance(ra, list):
        ra = sc.number_list(table, "roughness_Ra_um", w, length=2, allowed="(0, 10]")
    else:
        ra = [sc.number(table, "roughness_Ra_um", w, allowed="(0, 10]")] * 2
    xl = sc.number(table, "lubricant_factor", w, 1.0, allowed="(0, 2]")
    mu = sc.number(table, "friction_coefficient", w, None, allowed="(0, 1]")
    if mu is not None and "lubricant_factor" in table:
        raise sc.fail(
            w,
            "lubricant_factor",
            "not read: friction_coefficient is given (X_L is Schlenk's); remove one",
            table["lubricant_factor"],
        )
    film = sc.choice(table, "film", w, tuple(FILM_FORMULAS), "dowson-higginson")
    speed = sc.number(operating, "speed_rad_s", "operating", 0.0, allowed="[0, 1e+05]")
    if speed <= 0.0:
        rpm = operating.get("speed_rpm")
        if rpm is None:
            raise sc.fail(
                "operating",
                "speed_rad_s",
                "out of range with [lubricant], allowed > 0 "
                "(the film and the sliding loss need the pinion speed; or give "
                "speed_rpm)",
                speed,
            )
        speed = float(rpm) * 2.0 * math.pi / 60.0
    lub = Lubricant(nu40 * 1e-6, nu100 * 1e-6, rho, alpha * 1e-9, temp, gamma)
    friction = GivenFriction(mu) if mu is not None else Schlenk(xl)
    return TribologyInputs(
        lub, (ra[0] * 1e-6, ra[1] * 1e-6), friction, FILM_FORMULAS[film](), speed,
        parse_scuffing(table, bulk_read=bool(MICROPITTING_KEYS & set(table))),
        parse_micropitting(table),
    )


def tribology_of(case) -> TribologyInputs | None:
    """The ``[lubricant]`` inputs of a case (:class:`TribologyInputs`; a train's or a planetary
    stage's speed its input member's), or None without the table."""
    raw = getattr(case, "raw", None) or {}
    if "lubricant" not in raw:
        return None
    return parse_lubricant(raw["lubricant"], raw.get("operating", {}))
