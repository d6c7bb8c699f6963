"""The micropitting keys of a pair case's ``[lubricant]`` table: the permissible specific film
thickness λ_GFP of ISO/TS 6336-22, given or from the oil's micropitting test
(:func:`jaxgear.tribology.mesh_micropitting`; names → objects here only)::

    [lubricant]
    ...                                 # the film keys (jaxgear.io._lubricant_table)
    micropitting_load_stage = 8         # SKS, the FVA-FZG GF-C/8.3/90 failure load stage, [5, 10]
    permissible_specific_film = 0.25    # or: λ_GFP given, (0, 10]
    bulk_temperature_C = 95.0           # optional: a given θ_M (default: the TS-22 rule)
    bulk_lubrication_factor = 1.2       # optional: X_S of that rule (1.0 dip, 1.2 spray), (0, 2]

With a load stage, λ_GFP is read from the TS's Figure A.1 at the oil's ν₄₀
(:func:`jaxgear.tribology.figure_a1_permissible_film`, 32 to 460 mm²/s). ``bulk_temperature_C``
and ``bulk_lubrication_factor`` are the flanks' bulk temperature and its lubrication factor, the
same keys the scuffing methods read. Without ``micropitting_load_stage`` and
``permissible_specific_film`` the run computes no micropitting.
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

import pydantic

from fem_prep import schema as sc

from ..tribology import figure_a1_permissible_film
from ._sections import Section, number

__all__ = ["MICROPITTING_KEYS", "MicropittingInputs", "MicropittingKeys", "check_micropitting",
           "parse_micropitting"]

WHERE = "lubricant"
#: the oils the TS's Figure A.1 has curves for (ISO VG 32 to 460), ν₄₀ in mm²/s
FIGURE_A1_VISCOSITY = (32.0, 460.0)


class MicropittingInputs(NamedTuple):
    """What ``[lubricant]`` gives :func:`jaxgear.tribology.mesh_micropitting`: ``permissible``
    λ_GFP, its ``source`` (words), a given ``bulk_temperature`` (°C) or None, the
    ``lubrication_factor`` X_S."""

    permissible: float
    source: str
    bulk_temperature: float | None
    lubrication_factor: float


class MicropittingKeys(Section):
    """The micropitting keys of ``[lubricant]`` (module docstring): their types and ranges, and
    one source of λ_GFP (the ``[lubricant]`` section,
    :class:`jaxgear.io._lubricant_table.LubricantSection`, is these, the scuffing keys and the
    film keys; :func:`check_micropitting` what relates them to the oil's and the bulk keys)."""

    WHERE: ClassVar[str] = WHERE
    micropitting_load_stage: number("[5, 10]") | None = None
    permissible_specific_film: number("(0, 10]") | None = None

    @pydantic.model_validator(mode="after")
    def _one_source(self):
        if self.micropitting_load_stage is not None and (
                self.permissible_specific_film is not None):
            raise sc.fail(WHERE, "permissible_specific_film", "not read: micropitting_load_stage "
                          "is given (λ_GFP from the TS's Figure A.1); remove one",
                          self.permissible_specific_film)
        return self


#: the micropitting keys of ``[lubricant]`` (the bulk keys are the scuffing table's)
MICROPITTING_KEYS = set(MicropittingKeys.model_fields)


class _MicropittingTable(MicropittingKeys):
    """The keys of ``[lubricant]`` the micropitting reads, of a table given as a dict
    (:func:`parse_micropitting`): its own, the bulk keys and the oil's ν₄₀."""

    bulk_temperature_C: number("(-50, 400)") | None = None
    bulk_lubrication_factor: number("(0, 2]") = 1.0
    viscosity_40C_mm2_s: number("(0, 1e+05]") | None = None


def check_micropitting(section) -> None:
    """What relates the micropitting keys of ``[lubricant]`` (a section with them, the bulk keys
    and ``viscosity_40C_mm2_s``: :class:`jaxgear.io._lubricant_table.LubricantSection`) to its
    other keys: X_S not given beside a given bulk temperature, and with a load stage an oil of
    Figure A.1 (ν₄₀ in [32, 460] mm²/s, ISO VG 32 to 460). Nothing without the micropitting
    keys.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and what is allowed.
    """
    if section.micropitting_load_stage is None and section.permissible_specific_film is None:
        return
    if section.bulk_temperature_C is not None and "bulk_lubrication_factor" in section.given:
        raise sc.fail(WHERE, "bulk_lubrication_factor", "not read: bulk_temperature_C is given "
                      "(X_S is the TS rule's); remove one", section.bulk_lubrication_factor)
    if section.permissible_specific_film is not None:
        return
    nu40 = section.viscosity_40C_mm2_s
    if nu40 is None:
        raise sc.fail(WHERE, "viscosity_40C_mm2_s", "missing required key")
    lo, hi = FIGURE_A1_VISCOSITY
    if not lo <= nu40 <= hi:
        raise sc.fail(WHERE, "viscosity_40C_mm2_s", "out of range with micropitting_load_stage, "
                      "allowed [32, 460] (ISO VG 32 to 460, the curves of the TS's Figure A.1; "
                      "or give permissible_specific_film)", nu40)


def parse_micropitting(table) -> MicropittingInputs | None:
    """The micropitting keys of ``[lubricant]`` (a table, or a section with them:
    :class:`jaxgear.io._lubricant_table.LubricantSection`), validated, as
    :class:`MicropittingInputs`, or None without them: λ_GFP given, or read from the TS's
    Figure A.1 at the load stage and the oil's ν₄₀.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and the allowed range.
    """
    section = table
    if isinstance(table, dict):  # the keys the micropitting reads, others left to their readers
        fields = _MicropittingTable.model_fields
        section = _MicropittingTable.read({k: v for k, v in table.items() if k in fields})
    check_micropitting(section)
    stage, given = section.micropitting_load_stage, section.permissible_specific_film
    if stage is None and given is None:
        return None
    bulk_c, xs = section.bulk_temperature_C, section.bulk_lubrication_factor
    if given is not None:
        return MicropittingInputs(given, "given", bulk_c, xs)
    nu40 = section.viscosity_40C_mm2_s
    lam = figure_a1_permissible_film(stage, nu40 * 1e-6)
    return MicropittingInputs(
        lam, f"ISO/TS 6336-22 Figure A.1 at SKS {stage:g}, ν₄₀ {nu40:.0f} mm²/s", bulk_c, xs
    )
