"""A sizing spec's objectives (``[pareto]``) and the oil of its mesh loss (``[lubricant]``),
checked at load and mapped to :class:`jaxgear.sizing.SizingSpec`'s ``objectives``, ``chosen``
and ``mesh_loss``::

    [pareto]
    minimise = ["mass_kg", "mesh_loss_W"]   # columns of the table, each with its sense;
    maximise = ["least_margin"]             # 2 to 6 in all (jaxgear.sizing.OBJECTIVES)
    choose = "knee"                         # the chosen design: "knee" or an objective's column

    [lubricant]                             # a case file's [lubricant]: the oil, the flanks'
                                            # R_a and the friction law of the mesh loss, and
    fzg_load_stage = 10                     # its scuffing keys: the scuffing check (below)

Without ``[pareto]`` the front is the mass (minimised) and the least margin (maximised) with the
knee chosen; ``mesh_loss_W`` and ``efficiency`` need ``[lubricant]``, ``S_B`` the scuffing
rating (below). Of ``[lubricant]`` a sizing
reads the oil, the roughness and the friction (Schlenk's X_L or a given μ) and the scuffing keys
(:mod:`jaxgear.io._scuffing_table`: ``fzg_load_stage`` or the scuffing temperatures, the bulk
rule, X_L, X_W): with ``fzg_load_stage`` (or ``scuffing_temperature_C``) every candidate is rated
for scuffing by ISO/TS 6336-20's closed form (:class:`jaxgear.sizing.ScuffingRequirement`, S_Bmin
from ``[rating] min_safety_scuffing``, default 1); its film and micropitting keys are refused
(no film or micropitting stage here).
"""

from __future__ import annotations

from typing import Any, ClassVar

import pydantic

from fem_prep import schema as sc

from ..sizing import (
    CHOICES,
    DEFAULT_OBJECTIVES,
    MOST_OBJECTIVES,
    OBJECTIVES,
    MeshLossInputs,
    ScuffingRequirement,
)
from ._lubricant_table import LubricantSection
from ._scuffing_table import SCUFFING_KEYS, parse_scuffing
from ._sections import Section, number

__all__ = ["PARETO_KEYS", "SIZING_LUBRICANT_KEYS", "SIZING_RATING_KEYS", "ParetoSection",
           "SizingRatingKeys", "parse_pareto", "parse_sizing_lubricant", "parse_sizing_scuffing"]

#: the keys of ``[lubricant]`` a sizing reads (the mesh loss's and the scuffing check's)
SIZING_LUBRICANT_KEYS = frozenset({
    "viscosity_40C_mm2_s", "viscosity_100C_mm2_s", "density_kg_m3", "thermal_expansion_per_K",
    "pressure_viscosity_per_GPa", "oil_temperature_C", "roughness_Ra_um", "lubricant_factor",
    "friction_coefficient", *SCUFFING_KEYS})


class SizingRatingKeys(Section):
    """The keys of a sizing spec's ``[rating]`` beyond a case file's (its feasibility limits
    that a case run does not read): ``min_safety_scuffing``, S_Bmin of the scuffing check,
    [0.5, 10], default 1 (with ``[lubricant] fzg_load_stage`` only)."""

    WHERE: ClassVar[str] = "rating"
    min_safety_scuffing: number("[0.5, 10]") | None = None


#: the keys of ``[rating]`` a sizing reads and a case file does not
SIZING_RATING_KEYS = frozenset(SizingRatingKeys.model_fields)
#: the objectives of the mesh loss, which need ``[lubricant]``
_LUBRICATED = ("mesh_loss_W", "efficiency")
#: the objectives of the scuffing rating, which need its keys (``[lubricant] fzg_load_stage`` or
#: ``scuffing_temperature_C``)
_SCUFFED = ("S_B",)


def _column_names(value, info: pydantic.ValidationInfo):
    """``minimise`` or ``maximise``: a list of the objectives' column names."""
    allowed = ", ".join(OBJECTIVES)
    if not isinstance(value, list) or not all(isinstance(n, str) for n in value):
        raise sc.fail("pareto", info.field_name, "allowed a list of column names: " + allowed,
                      value)
    for name in value:
        if name not in OBJECTIVES:
            raise sc.fail("pareto", info.field_name, f"{name!r} is not an objective: allowed "
                          f"{allowed}", value)
    return value


class ParetoSection(Section):
    """A sizing spec's ``[pareto]`` (module docstring), checked whole: the objectives' columns
    to minimise and to maximise (:data:`jaxgear.sizing.OBJECTIVES`, each named once, 2 to
    :data:`~jaxgear.sizing.MOST_OBJECTIVES` in all; the mesh loss's only with ``[lubricant]``,
    the context's ``has_lubricant``, ``S_B`` only with the scuffing rating, ``has_scuffing``) and the design chosen (``"knee"`` or one of them).
    Without ``minimise`` and ``maximise`` the front is :data:`~jaxgear.sizing.
    DEFAULT_OBJECTIVES`'."""

    WHERE: ClassVar[str] = "pareto"
    minimise: list = pydantic.Field(default_factory=list)
    maximise: list = pydantic.Field(default_factory=list)
    choose: Any = "knee"  # a name out of CHOICES and the objectives chosen (checked below)

    _names = pydantic.field_validator("minimise", "maximise", mode="before")(_column_names)

    @pydantic.model_validator(mode="after")
    def _related(self, info: pydantic.ValidationInfo):
        has_lubricant = (info.context or {}).get("has_lubricant", False)
        has_scuffing = (info.context or {}).get("has_scuffing", False)
        seen = []
        for key in ("minimise", "maximise"):
            names = getattr(self, key)
            for name in names:
                if name in seen:
                    raise sc.fail("pareto", key, f"{name!r} is named twice", names)
                if name in _LUBRICATED and not has_lubricant:
                    raise sc.fail("pareto", key, f"{name!r} needs a [lubricant] table (the oil, "
                                  "roughness and friction of the mesh loss)", names)
                if name in _SCUFFED and not has_scuffing:
                    raise sc.fail("pareto", key, f"{name!r} needs the scuffing rating: [lubricant]"
                                  " with fzg_load_stage (the oil's FZG A/8.3/90 load stage) or "
                                  "scuffing_temperature_C", names)
                seen.append(name)
        objectives = self.objectives()
        if not 2 <= len(objectives) <= MOST_OBJECTIVES:
            raise sc.fail("pareto", "minimise", f"{len(objectives)} objectives with maximise: "
                          f"allowed 2 to {MOST_OBJECTIVES}", self.minimise)
        names = [o[0] for o in objectives]
        if self.choose not in (*CHOICES, *names):
            raise sc.fail("pareto", "choose", "allowed " + ", ".join(
                map(repr, (*CHOICES, *names))), self.choose)
        return self

    def objectives(self) -> tuple:
        """The front's objectives, ``(column, "min" | "max")`` each, the minimised first."""
        if not self.given & {"minimise", "maximise"}:
            return tuple(DEFAULT_OBJECTIVES)
        return tuple([(n, "min") for n in self.minimise] + [(n, "max") for n in self.maximise])


#: the keys of a sizing spec's ``[pareto]``
PARETO_KEYS = tuple(ParetoSection.model_fields)


def parse_sizing_lubricant(table: dict, operating: dict) -> MeshLossInputs:
    """``[lubricant]`` of a sizing spec (the case file's reader, :class:`LubricantSection`, and
    only the keys of :data:`SIZING_LUBRICANT_KEYS`) as the mesh loss's inputs.

    Raises:
        SchemaError (a ``ValueError``): one line naming the key.
    """
    section = LubricantSection.read(table)
    unread = sorted(section.given - SIZING_LUBRICANT_KEYS)
    if unread:
        raise sc.fail("lubricant", unread[0], "not read by a sizing (its mesh loss reads the "
                      "oil, roughness_Ra_um and the friction, its scuffing check the scuffing "
                      "keys: " + ", ".join(sorted(SIZING_LUBRICANT_KEYS)) + ")")
    inputs = section.inputs(operating)
    return MeshLossInputs(inputs.lubricant, inputs.roughness, inputs.friction)


def parse_sizing_scuffing(lubricant: dict | None, rating: dict,
                          mesh_loss: MeshLossInputs | None) -> ScuffingRequirement | None:
    """The scuffing check's inputs of a sizing spec (module docstring): the scuffing keys of
    ``[lubricant]`` (:func:`jaxgear.io._scuffing_table.parse_scuffing`, already checked with
    the table by :func:`parse_sizing_lubricant`, whose oil and roughness ``mesh_loss`` holds)
    and ``[rating] min_safety_scuffing``; None without ``fzg_load_stage`` and
    ``scuffing_temperature_C``.

    Raises:
        SchemaError (a ``ValueError``): ``min_safety_scuffing`` out of range, or given without
            the scuffing keys; one line naming the key.
    """
    keys = SizingRatingKeys.read({k: v for k, v in rating.items() if k in SIZING_RATING_KEYS})
    s_min = keys.min_safety_scuffing
    inputs = None if lubricant is None else parse_scuffing(lubricant)
    if inputs is None:
        if s_min is not None:
            raise sc.fail("rating", "min_safety_scuffing", "not read: the scuffing check needs "
                          "[lubricant] with fzg_load_stage (the oil's FZG A/8.3/90 load stage, "
                          "[1, 14]) or scuffing_temperature_C", s_min)
        return None
    return ScuffingRequirement(mesh_loss.lubricant, mesh_loss.roughness, inputs.limits,
                               inputs.bulk, 1.0 if s_min is None else s_min)


def parse_pareto(table: dict | None, has_lubricant: bool,
                 has_scuffing: bool = False) -> tuple[tuple, str]:
    """``[pareto]`` (or None: the defaults) as (objectives, chosen) for
    :class:`jaxgear.sizing.SizingSpec` (the module docstring; :class:`ParetoSection`), with
    ``has_lubricant`` whether the spec has a ``[lubricant]`` table (the mesh loss's objectives
    need it) and ``has_scuffing`` whether it rates scuffing (``S_B`` needs it).

    Raises:
        SchemaError (a ``ValueError``): one line naming the key, its value and what is allowed.
    """
    if table is None:
        return DEFAULT_OBJECTIVES, "knee"
    section = ParetoSection.read(table, context={"has_lubricant": has_lubricant,
                                                 "has_scuffing": has_scuffing})
    return section.objectives(), section.choose
