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

from typing import NamedTuple

from fem_prep import schema as sc

from ..tribology import figure_a1_permissible_film

__all__ = ["MICROPITTING_KEYS", "MicropittingInputs", "parse_micropitting"]

#: the micropitting keys of ``[lubricant]`` (the bulk keys are the scuffing table's)
MICROPITTING_KEYS = {"micropitting_load_stage", "permissible_specific_film"}


class MicropittingInputs(NamedTuple):
    """What ``[lubricant]`` gives :func:`jaxgear.tribology.mesh_micropitting`: ``permissible``
    λ_GFP, its ``source`` (words), a given ``bulk_temperature`` (°C) or None, the
    ``lubrication_factor`` X_S."""

    permissible: float
    source: str
    bulk_temperature: float | None
    lubrication_factor: float


def parse_micropitting(table: dict) -> MicropittingInputs | None:
    """The micropitting keys of ``[lubricant]`` (validated), or None without them.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and the allowed range.
    """
    w = "lubricant"
    stage = sc.number(table, "micropitting_load_stage", w, None, allowed="[5, 10]")
    given = sc.number(table, "permissible_specific_film", w, None, allowed="(0, 10]")
    if stage is None and given is None:
        return None
    if stage is not None and given is not None:
        raise sc.fail(
            w,
            "permissible_specific_film",
            "not read: micropitting_load_stage is given (λ_GFP from the TS's Figure A.1);"
            " remove one",
            given,
        )
    bulk_c = sc.number(table, "bulk_temperature_C", w, None, allowed="(-50, 400)")
    xs = sc.number(table, "bulk_lubrication_factor", w, 1.0, allowed="(0, 2]")
    if bulk_c is not None and "bulk_lubrication_factor" in table:
        raise sc.fail(
            w,
            "bulk_lubrication_factor",
            "not read: bulk_temperature_C is given (X_S is the TS rule's); remove one",
            xs,
        )
    if given is not None:
        return MicropittingInputs(given, "given", bulk_c, xs)
    nu40 = sc.number(table, "viscosity_40C_mm2_s", w, allowed="(0, 1e+05]")
    if not 32.0 <= nu40 <= 460.0:
        raise sc.fail(
            w,
            "viscosity_40C_mm2_s",
            "out of range with micropitting_load_stage, allowed [32, 460] (ISO VG 32 to 460,"
            " the curves of the TS's Figure A.1; or give permissible_specific_film)",
            nu40,
        )
    lam = figure_a1_permissible_film(stage, nu40 * 1e-6)
    return MicropittingInputs(
        lam, f"ISO/TS 6336-22 Figure A.1 at SKS {stage:g}, ν₄₀ {nu40:.0f} mm²/s", bulk_c, xs
    )
