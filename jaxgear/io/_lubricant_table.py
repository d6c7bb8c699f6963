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
from typing import ClassVar, Literal, NamedTuple

import pydantic

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
from ._micropitting_table import (
    MICROPITTING_KEYS,
    MicropittingInputs,
    MicropittingKeys,
    check_micropitting,
    parse_micropitting,
)
from ._scuffing_table import ScuffingInputs, ScuffingKeys, parse_scuffing
from ._sections import number, number_list, one_of

__all__ = ["FILM_FORMULAS", "LUBRICANT_KEYS", "LubricantSection", "TribologyInputs",
           "parse_lubricant", "read_lubricant", "tribology_of"]

#: the kinematic viscosities' range (mm²/s): ASTM D341-20's Walther equation is stated from
#: 2 mm²/s (below 0.3 mm²/s its double logarithm has no value) to 2e7 mm²/s
VISCOSITY_RANGE = "[2, 1e+05]"
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


_WALTHER = " (Walther's equation, ASTM D341, holds from 2 mm²/s)"


class LubricantSection(MicropittingKeys, ScuffingKeys):
    """``[lubricant]`` as the file gives it (keys and ranges: the module docstring, the
    scuffing keys :mod:`jaxgear.io._scuffing_table`'s, the micropitting keys
    :mod:`jaxgear.io._micropitting_table`'s), checked whole; :meth:`inputs` its SI inputs with
    the pinion speed of ``[operating]`` (:func:`read_lubricant` reads and checks both)."""

    WHERE: ClassVar[str] = "lubricant"
    viscosity_40C_mm2_s: number(VISCOSITY_RANGE, note=_WALTHER)
    viscosity_100C_mm2_s: number(VISCOSITY_RANGE, note=_WALTHER)
    density_kg_m3: number("(500, 2000)")
    thermal_expansion_per_K: number("[0, 0.01)") = 0.0
    pressure_viscosity_per_GPa: number("(0, 100]")
    oil_temperature_C: number("(-50, 250)")
    roughness_Ra_um: one_of(number=number("(0, 10]"), array=number_list("(0, 10]", length=2))
    lubricant_factor: number("(0, 2]") = 1.0
    friction_coefficient: number("(0, 1]") | None = None
    film: Literal[tuple(FILM_FORMULAS)] = "dowson-higginson"

    @pydantic.model_validator(mode="after")
    def _related(self):
        w = "lubricant"
        nu40, nu100 = self.viscosity_40C_mm2_s, self.viscosity_100C_mm2_s
        if nu100 >= nu40:
            raise sc.fail(w, "viscosity_100C_mm2_s", f"out of range, allowed < "
                          f"viscosity_40C_mm2_s = {nu40:g} (an oil thins as it warms)", nu100)
        if self.friction_coefficient is not None and "lubricant_factor" in self.given:
            raise sc.fail(w, "lubricant_factor", "not read: friction_coefficient is given (X_L "
                          "is Schlenk's); remove one", self.lubricant_factor)
        parse_scuffing(self, bulk_read=bool(MICROPITTING_KEYS & self.given))
        check_micropitting(self)
        return self

    def inputs(self, operating: dict) -> TribologyInputs:
        """The SI inputs (:class:`TribologyInputs`) with the pinion speed of ``operating``
        (the case's ``[operating]``: ``speed_rad_s`` > 0, else ``speed_rpm``).

        Raises:
            SchemaError: no pinion speed > 0, one line.
        """
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
        ra = self.roughness_Ra_um
        ra = ra if isinstance(ra, list) else [ra, ra]
        lub = Lubricant(self.viscosity_40C_mm2_s * 1e-6, self.viscosity_100C_mm2_s * 1e-6,
                        self.density_kg_m3, self.pressure_viscosity_per_GPa * 1e-9,
                        self.oil_temperature_C, self.thermal_expansion_per_K)
        mu = self.friction_coefficient
        friction = GivenFriction(mu) if mu is not None else Schlenk(self.lubricant_factor)
        return TribologyInputs(
            lub, (ra[0] * 1e-6, ra[1] * 1e-6), friction, FILM_FORMULAS[self.film](), speed,
            parse_scuffing(self, bulk_read=bool(MICROPITTING_KEYS & self.given)),
            parse_micropitting(self),
        )


#: the keys of ``[lubricant]``
LUBRICANT_KEYS = set(LubricantSection.model_fields)


def parse_lubricant(table: dict, operating: dict) -> TribologyInputs:
    """Validate ``[lubricant]`` (:class:`LubricantSection`; and the speed of ``[operating]``)
    and build its objects.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and the allowed range.
    """
    return LubricantSection.read(table).inputs(operating)


def read_lubricant(data: dict) -> LubricantSection | None:
    """A case file's ``[lubricant]`` (:class:`LubricantSection`) with its pinion speed of
    ``[operating]`` checked, or None without the table.

    Raises:
        SchemaError: as :func:`parse_lubricant`.
    """
    if "lubricant" not in data:
        return None
    section = LubricantSection.read(data["lubricant"])
    section.inputs(data.get("operating", {}))  # the film and the loss need the pinion speed
    return section


def tribology_of(case) -> TribologyInputs | None:
    """The ``[lubricant]`` inputs of a case (:class:`TribologyInputs`, of its
    :attr:`Case.lubricant <jaxgear.io.Case>`; a train's or a planetary stage's speed its input
    member's), or None without the table."""
    section = getattr(case, "lubricant", None)
    if section is None:
        return None
    return section.inputs((getattr(case, "raw", None) or {}).get("operating", {}))
