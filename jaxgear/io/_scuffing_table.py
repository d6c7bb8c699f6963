"""The scuffing keys of a pair case's ``[lubricant]`` table: the lubricant's FZG load stage or
its scuffing temperatures, and the bulk-temperature rule of the flash-temperature method
(:func:`jaxgear.tribology.mesh_scuffing`; names → objects here only)::

    [lubricant]
    ...                                 # the film keys (jaxgear.io._lubricant_table)
    fzg_load_stage = 10                 # FZG A/8.3/90 load stage the oil passed, [1, 14]
    scuffing_temperature_C = 320.0      # optional: θ_S instead of the load stage's, (0, 1000)
    integral_scuffing_temperature_C = 300.0  # optional: θ_intS, (0, 1000)
    bulk_temperature_C = 95.0           # optional: a given θ_M (default: ISO/TS 6336-20's rule)
    bulk_lubrication_factor = 1.2       # optional: X_S of that rule (1.0 dip, 1.2 spray), (0, 2]
    scuffing_lubricant_factor = 1.0     # optional: the TS's X_L (1.0 mineral oil), (0, 2]
    structural_factor = 1.0             # optional: X_W, (0, 2]
    relative_structural_factor = 1.0    # optional: X_WrelT, (0, 2]

Without ``fzg_load_stage`` and ``scuffing_temperature_C`` the run computes no scuffing.
"""

from __future__ import annotations

from typing import ClassVar, NamedTuple

from fem_prep import schema as sc

from ..tribology import (
    AbstractBulkTemperature,
    FlashBulkTemperature,
    GivenBulkTemperature,
    ScuffingLimits,
)
from ._sections import Section, number

__all__ = ["SCUFFING_KEYS", "ScuffingInputs", "ScuffingKeys", "parse_scuffing"]

_BULK_KEYS = {"bulk_temperature_C", "bulk_lubrication_factor"}


class ScuffingInputs(NamedTuple):
    """What ``[lubricant]`` gives :func:`jaxgear.tribology.mesh_scuffing`: ``limits`` and the
    ``bulk`` temperature rule."""

    limits: ScuffingLimits
    bulk: AbstractBulkTemperature


class ScuffingKeys(Section):
    """The scuffing keys of ``[lubricant]`` (module docstring): their types and ranges (the
    ``[lubricant]`` section, :class:`jaxgear.io._lubricant_table.LubricantSection`, is these
    and the film keys)."""

    WHERE: ClassVar[str] = "lubricant"
    fzg_load_stage: number("[1, 14]") | None = None
    scuffing_temperature_C: number("(0, 1000)") | None = None
    integral_scuffing_temperature_C: number("(0, 1000)") | None = None
    bulk_temperature_C: number("(-50, 400)") | None = None
    bulk_lubrication_factor: number("(0, 2]") = 1.0
    scuffing_lubricant_factor: number("(0, 2]") = 1.0
    structural_factor: number("(0, 2]") = 1.0
    relative_structural_factor: number("(0, 2]") = 1.0


#: the scuffing keys of ``[lubricant]``
SCUFFING_KEYS = set(ScuffingKeys.model_fields)


def parse_scuffing(section, bulk_read: bool = False) -> ScuffingInputs | None:
    """The scuffing keys of ``[lubricant]`` (a :class:`ScuffingKeys`, such as the
    :class:`~jaxgear.io._lubricant_table.LubricantSection`, or the table: its scuffing keys
    read as one) as :class:`ScuffingInputs`, or None without ``fzg_load_stage`` and
    ``scuffing_temperature_C``. ``bulk_read``: the micropitting keys read the bulk keys
    (``bulk_temperature_C``, ``bulk_lubrication_factor``) when no scuffing is computed.

    Raises:
        SchemaError (a ``ValueError``): a value of the wrong type or out of range, a key not
            read without another, or read beside one that replaces it; one line naming the key
            and its value.
    """
    if isinstance(section, dict):
        section = ScuffingKeys.read({k: v for k, v in section.items() if k in SCUFFING_KEYS})
    w, given = "lubricant", section.given
    stage, theta_s = section.fzg_load_stage, section.scuffing_temperature_C
    theta_int, bulk_c = section.integral_scuffing_temperature_C, section.bulk_temperature_C
    if stage is None and theta_s is None and theta_int is None:
        for key in sorted(SCUFFING_KEYS & given):
            if bulk_read and key in _BULK_KEYS:
                continue
            also = " (or a micropitting key)" if key in _BULK_KEYS else ""
            raise sc.fail(w, key, f"not read: give fzg_load_stage or scuffing_temperature_C{also}",
                          getattr(section, key))
        return None
    if stage is None and (theta_s is None or theta_int is None):
        key = "scuffing_temperature_C" if theta_s is not None else "integral_scuffing_temperature_C"
        raise sc.fail(w, key, "needs fzg_load_stage (or both scuffing_temperature_C and"
                      " integral_scuffing_temperature_C)", getattr(section, key))
    xs = section.bulk_lubrication_factor
    if bulk_c is not None and "bulk_lubrication_factor" in given:
        raise sc.fail(w, "bulk_lubrication_factor",
                      "not read: bulk_temperature_C is given (X_S is the TS rule's); remove one", xs)
    limits = ScuffingLimits(stage, theta_s, theta_int, section.scuffing_lubricant_factor,
                            section.structural_factor, section.relative_structural_factor)
    bulk = GivenBulkTemperature(bulk_c) if bulk_c is not None else FlashBulkTemperature(xs)
    return ScuffingInputs(limits, bulk)
