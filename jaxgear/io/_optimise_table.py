"""``[optimise]`` of a case file: the settings of ``jaxgear optimise`` (objective, variables,
torques, bounds), checked and normalised."""

from __future__ import annotations

import functools
import re
from typing import Annotated, Any, ClassVar, Literal

import pydantic
from pydantic import BeforeValidator

from fem_prep import schema as sc
from optimise import (
    OBJECTIVE_DESIGNS_STRUCTURE,
    OBJECTIVE_UNITS,
    OBJECTIVES,
    VARIABLES,
    Variable,
)

from ..bearings import CATALOGUE
from ._scene_table import BearingSection
from ._sections import Section, number, number_list

__all__ = [
    "ACOUSTIC_OBJECTIVES",
    "OPTIMISE_DEFAULTS",
    "TORQUE_RANGE_OBJECTIVES",
    "OptimiseSection",
    "check_acoustic_tables",
    "check_bearing_variables",
    "check_train_design",
    "designs_structure",
    "objective_units",
    "parse_optimise",
]

#: the objectives that take a torque range (``torques``) and its statistic (``reduce``): the TE
#: RMS and the tribology objectives (:mod:`jaxgear.io._problem` maps the names to objects)
TORQUE_RANGE_OBJECTIVES = (
    "robust_te_rms",
    "power_loss",
    "efficiency_loss",
    "min_specific_film",
    "max_flash_temperature",
)

#: what ``jaxgear optimise`` takes for a key that neither the command line nor the case's
#: ``[optimise]`` gives (None: none, or the objective's own: ``lp_order`` 8, no TE limit); the
#: case-file reference shows them
OPTIMISE_DEFAULTS = {
    "objective": "te_rms",
    "vars": "tip_relief.depth,tip_relief.extent",
    "torques": None,
    "reduce": "max",
    "method": "lbfgs",
    "max_iterations": 100,
    "speeds": None,
    "lp_order": 8.0,
    "te_limit_um": None,
    "quantile": None,
    "a_weighted": True,
}

#: the objectives over the speeds of a housed case's [whine] (jaxgear.io's acoustic path)
ACOUSTIC_OBJECTIVES = ("erp", "sound_power")
_MEMBER_PREFIXES = ("pinion", "gear")


def check_acoustic_tables(data: dict, optimise: dict | None) -> None:
    """An acoustic objective in ``[optimise]`` runs on the housed gearbox's whine: the case file
    ``data`` needs ``[housing]`` and ``[whine]`` (and ``[acoustics]`` for "sound_power").

    Raises:
        SchemaError: one line naming ``[optimise] objective`` and the missing table."""
    goal = (optimise or {}).get("objective")
    if goal not in ACOUSTIC_OBJECTIVES:  # the housing's whine, radiated ([acoustics]: its R)
        return
    for needed in ("housing", "whine") + (("acoustics",) if goal == "sound_power" else ()):
        if needed not in data:
            raise sc.fail("optimise", "objective", f"runs on a housed gearbox's whine: "
                          f"needs [{needed}] too (allowed with [housing] and [whine]"
                          f"{' and [acoustics]' if goal == 'sound_power' else ''})", goal)


def check_train_design(objective: str | None, variables, modifications: dict | None,
                       gear_names, span_periods: int = 1) -> None:
    """What a train case's design can be: an acoustic objective (``objective``: "erp" or
    "sound_power"; the housed train's whine), design variables without a member prefix (each
    acts on every gear: ``tip_relief.depth``, not ``pinion.tip_relief.depth``), and a
    ``[modifications]`` table (``modifications``, the case file's) whose entries are common to
    every gear (no ``[modifications.<gear>]``), the design the variables are written into; its
    meshes of one mesh frequency (``span_periods``, the periods of the first mesh after which
    they repeat together, 1: an idler train).

    Raises:
        SchemaError: one line naming the key (``[optimise] objective``, ``[optimise] vars``,
            ``[modifications] <gear>``)."""
    if objective not in ACOUSTIC_OBJECTIVES:
        raise sc.fail("optimise", "objective", "a train case optimises its housing's noise: "
                      "allowed 'erp' or 'sound_power' (with [housing] and [whine])",
                      objective or OPTIMISE_DEFAULTS["objective"])
    if span_periods != 1:
        raise sc.fail("optimise", "objective", "runs on a train whose meshes share one mesh "
                      "frequency (an idler train); this train's meshes repeat together every "
                      f"{span_periods} periods of the first", objective)
    names = variables.split(",") if isinstance(variables, str) else list(variables)
    for name in names:
        if name.strip().split(".")[0] in _MEMBER_PREFIXES:
            raise sc.fail("optimise", "vars", "a train's design variable acts on every gear: "
                          f"allowed without a member prefix ({name.strip().split('.', 1)[1]!r})",
                          name.strip())
    for gear in gear_names:
        if gear in (modifications or {}):
            raise sc.fail("modifications", gear, "a train's design is one modification on "
                          "every gear: allowed the entries common to every gear, directly under "
                          "[modifications], when the train is optimised", "{...}")


def _check_bearing(where: str, key: str, name: str, shaft: str, k: int, shafts: dict) -> None:
    """Bearing ``k`` of ``shaft`` (as ``name`` writes it) is a rolling bearing from its
    geometry of ``shafts`` (``{name: ShaftSpec or None}``); else one line naming
    ``[where] key``."""
    spec = shafts.get(shaft)
    if spec is None:
        given = ", ".join(n for n, v in shafts.items() if v is not None) or "none"
        raise sc.fail(where, key, f"{name!r}: no [scene.{shaft}] of a lumped3d scene, allowed "
                      f"the shafts {given}", name)
    if not k < len(spec.bearings):
        raise sc.fail(where, key, f"{name!r}: [scene.{shaft}] has {len(spec.bearings)} "
                      f"bearings, allowed bearings[0] to bearings[{len(spec.bearings) - 1}]",
                      name)
    rolling = spec.bearings[k].rolling
    if rolling is None or rolling.clearance_field is None:
        raise sc.fail(where, key, f"{name!r} is a linear bearing: a clearance is allowed on a "
                      "rolling bearing from its geometry (kind = ..., or catalogue = ...)", name)


def check_bearing_variables(optimise: dict | None, shafts: dict) -> None:
    """Each bearing variable of ``[optimise] vars`` and each bearing of
    ``[optimise.choices]`` names a rolling bearing from its geometry of the case's ``shafts``
    (``{name: ShaftSpec or None}``, ``pinion_shaft``, ``gear_shaft``; empty where the scene is
    not ``lumped3d``).

    Raises:
        SchemaError: one line naming ``[optimise] vars`` or the ``[optimise.choices]`` key: an
            unknown shaft, a bearing index out of range, a linear bearing (a kind without a
            ``clearance_field``; a tapered roller pair's variable is its ``end_play_um``)."""
    for name in (optimise or {}).get("vars", ()):
        if _variable_kind(name) != "clearance":
            continue
        var = Variable.parse(name)
        _check_bearing(WHERE, "vars", name, var.shaft, var.bearing, shafts)
    for name in (optimise or {}).get("choices") or {}:
        hit = BEARING_NAME.match(name)
        _check_bearing(f"{WHERE}.choices", name, name, hit.group(1), int(hit.group(2)), shafts)


#: a bearing's name, ``<shaft>.bearings[<k>]``: an ``[optimise.choices]`` key, the bearing of
#: :func:`jaxgear.io.bearing_choices`
BEARING_NAME = re.compile(r"^([A-Za-z_][\w-]*)\.bearings\[(\d+)\]$")


def designs_structure(objective: str) -> bool:
    """Whether the objective named ``objective`` (:data:`optimise.OBJECTIVES`) takes a designed
    structure (a bearing's clearance): its class's ``designs_structure``; False for an unknown
    name."""
    return bool(OBJECTIVE_DESIGNS_STRUCTURE.get(objective, False))


def objective_units(objective: str) -> str:
    """The units of the objective named ``objective`` (its class's ``units``: ``m``, ``W``,
    ...; ValueError: an unknown name)."""
    if objective not in OBJECTIVE_UNITS:
        raise ValueError(f"objective = {objective!r} is unknown: allowed {', '.join(OBJECTIVES)}")
    return OBJECTIVE_UNITS[objective]


def _choices(value):
    """``[optimise.choices]``: one bearing ``"<shaft>.bearings[<k>]"`` = a non-empty array of
    candidates, each a catalogue name (:data:`jaxgear.bearings.CATALOGUE`) or an inline table
    (:func:`_candidate`); returns ``{bearing: {candidate name: its bearing table}}`` (the
    tables :func:`jaxgear.io.bearing_choices` takes), the names distinct."""
    where = f"{WHERE}.choices"
    if not isinstance(value, dict) or len(value) != 1:
        raise sc.fail(WHERE, "choices", "allowed one bearing, \"<shaft>.bearings[<k>]\" = "
                      "[candidates] (e.g. \"pinion_shaft.bearings[0]\" = [\"6205\", "
                      "{ catalogue = \"30205\", arrangement = \"O\" }])", value)
    (name, names), = value.items()
    if BEARING_NAME.match(name) is None:
        raise sc.fail(where, name, "unknown bearing, allowed \"<shaft>.bearings[<k>]\" (e.g. "
                      "\"pinion_shaft.bearings[0]\")", names)
    if not isinstance(names, list) or not names:
        raise sc.fail(where, name, "allowed a non-empty array of catalogue names "
                      f"({', '.join(CATALOGUE)}) or inline tables of a rolling bearing's keys",
                      names)
    out: dict[str, dict] = {}
    for i, x in enumerate(names):
        label, table = _candidate(name, i, x, names)
        if label in out:
            raise sc.fail(where, name, f"names the candidate {label!r} twice: allowed distinct "
                          "candidates (a table's own name = \"...\" tells two apart)", names)
        out[label] = table
    return {name: out}


def _candidate(bearing: str, i: int, x, names: list) -> tuple[str, dict]:
    """Candidate ``i`` (from 0) of ``[optimise.choices]``'s ``bearing``: a catalogue name, or
    an inline table of a scene bearing's keys read by the same
    :class:`~jaxgear.io._scene_table.BearingSection` (``catalogue`` with, for a tapered
    roller entry, ``arrangement``, or ``kind`` with its geometry; its clearance key the start;
    no ``position_mm``: the case bearing's) and an optional ``name``. Returns (its name in the
    ranking: ``name``, else the catalogue name with the pair's arrangement, ``"30205 O"``,
    else ``"candidate <i+1> (<kind>)"``; its bearing table without ``name``). SchemaError:
    one line naming ``[optimise.choices."<bearing>"[i]]`` and the key."""
    where = f"{WHERE}.choices.\"{bearing}\"[{i}]"
    if isinstance(x, str):
        if x not in CATALOGUE:
            raise sc.fail(f"{WHERE}.choices", bearing, f"unknown catalogue name {sc.fmt(x)}, "
                          f"allowed {', '.join(CATALOGUE)}", names)
        return x, {"catalogue": x}
    if not isinstance(x, dict):
        raise sc.fail(f"{WHERE}.choices", bearing, f"candidate {sc.fmt(x)}: allowed a "
                      "catalogue name or an inline table of a rolling bearing's keys", names)
    table = dict(x)
    label = table.pop("name", None)
    if label is not None and (not isinstance(label, str) or not label.strip()):
        raise sc.fail(where, "name", "allowed a non-empty text (the candidate's name in the "
                      "ranking)", label)
    if "position_mm" in table:
        raise sc.fail(where, "position_mm", "not a candidate's key: a candidate stands where "
                      "the case's bearing stands", table["position_mm"])
    if "catalogue" not in table and "kind" not in table:
        raise sc.fail(where, "kind", "missing: a candidate is a rolling bearing from its "
                      "geometry, allowed catalogue = <name> or kind = <kind> with its geometry "
                      "(the keys of a scene bearing, docs/bearings.md)")
    section = BearingSection.read({"position_mm": 0.0, **table}, where)
    if label is None:
        label = (f"candidate {i + 1} ({section.kind})" if section.catalogue is None else
                 " ".join(filter(None, (section.catalogue, section.arrangement))))
    return label.strip(), table


_DEFAULT_VARS = tuple(OPTIMISE_DEFAULTS["vars"].split(","))
WHERE = "optimise"
#: what ``vars`` and ``[optimise.bounds]`` allow, in their messages
_ALLOWED_VARS = (f"{', '.join(VARIABLES)}, optionally prefixed 'pinion.' or 'gear.', or a "
                 "rolling bearing's <shaft>.bearings[<k>].clearance (µm; a tapered roller "
                 "pair's end play)")


def _variable_kind(name: str) -> str | None:
    """The kind of a design variable's name (``"depth"``, ``"extent"``, ``"end_extent"``;
    :data:`optimise.VARIABLES`), a member prefix ``pinion.``/``gear.`` allowed, or
    ``"clearance"`` for a bearing's (``pinion_shaft.bearings[0].clearance``); None for a name
    that is none."""
    parts = name.split(".")
    base = ".".join(parts[1:]) if parts[0] in _MEMBER_PREFIXES else name
    if base in VARIABLES:
        return VARIABLES[base][1]
    try:
        var = Variable.parse(name)
    except ValueError:
        return None
    return var.field if var.kind.acts_on == "structure" else None


@functools.singledispatch
def _name_list(value):
    """``vars`` as given (an array of names; checked by the caller)."""
    return value


@_name_list.register
def _(value: str) -> list:
    """``vars = "a, b"``: comma-separated names."""
    return [x.strip() for x in value.split(",") if x.strip()]


def _variable_names(value):
    """``vars`` (an array of names, or one text of comma-separated names) as a list of distinct
    design variable names."""
    v = _name_list(value)
    if not isinstance(v, list) or not v or not all(isinstance(x, str) for x in v):
        raise sc.fail(WHERE, "vars", "must be a non-empty array of variable names", value)
    for x in v:
        if _variable_kind(x) is None:
            raise sc.fail(WHERE, "vars", f"unknown variable {sc.fmt(x)}, allowed {_ALLOWED_VARS}",
                          v)
    if len(set(v)) != len(v):
        raise sc.fail(WHERE, "vars", "names a variable twice", v)
    return list(v)


def _torque_span(v):
    """``torques``: ``[start, stop, n]`` in N·m, 0 < start < stop, an integer n in [2, 10000];
    as ``[float, float, int]``."""
    ok = (
        isinstance(v, list)
        and len(v) == 3
        and all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in v)
        and all(sc.finite(x) for x in v)
        and 0 < v[0] < v[1]
        and float(v[2]).is_integer()
        and 2 <= v[2] <= 10000
    )
    if not ok:
        raise sc.fail(WHERE, "torques", "allowed [start, stop, n] in N·m with 0 < start < stop "
                      "and an integer n in [2, 10000]", v)
    return [float(v[0]), float(v[1]), int(v[2])]


def _speed_span(v):
    """``speeds``: ``[start, stop, n]`` pinion speeds in rad/s, 0 < start <= stop <= 1e5, an
    integer n in [1, 1000], start < stop unless n = 1; as ``[float, float, int]``."""
    ok = (
        isinstance(v, list)
        and len(v) == 3
        and all(sc.finite(x) for x in v)
        and 0 < v[0] <= v[1] <= 1e5
        and float(v[2]).is_integer()
        and 1 <= v[2] <= 1000
        and (v[0] < v[1] or v[2] == 1)
    )
    if not ok:
        raise sc.fail(WHERE, "speeds", "allowed [start, stop, n]: pinion speeds in rad/s with "
                      "0 < start < stop <= 1e+05 and an integer n in [1, 1000] (start = stop "
                      "when n = 1)", v)
    return [float(v[0]), float(v[1]), int(v[2])]


def _not_for(key: str, objectives: str, objective: str, value) -> sc.SchemaError:
    """``[optimise] key = value: applies to objective = ... only, not '...'``."""
    return sc.fail(WHERE, key, f"applies to objective = {objectives} only, not {objective!r}",
                   value)


class OptimiseSection(Section):
    """``[optimise]`` as the file gives it (the keys of the ``jaxgear optimise`` options,
    checked whole): the objective, its statistic over a torque range or speeds, the minimiser,
    the design variables and their bounds. A key the file does not give holds
    :data:`OPTIMISE_DEFAULTS`' value (what the command takes); :meth:`settings` the keys the
    file gave, normalised (:func:`parse_optimise`). The keys that apply to some objectives only
    (``lp_order``, ``te_limit_um``, ``torques``, ``speeds``, ``a_weighted``), ``quantile`` with
    ``reduce = "quantile"`` only, and the bounds of the design variables are checked together
    after each key's own type and range."""

    WHERE: ClassVar[str] = WHERE
    # (in the order a reader meets their errors)
    objective: Literal[OBJECTIVES] = OPTIMISE_DEFAULTS["objective"]
    reduce: Literal["max", "mean", "quantile"] = OPTIMISE_DEFAULTS["reduce"]
    #: the level of reduce = "quantile" (over the torques, or the acoustic objectives' speeds)
    quantile: number("(0, 1)") | None = None
    #: the A weighting of the acoustic objectives' orders (IEC 61672-1)
    a_weighted: bool = OPTIMISE_DEFAULTS["a_weighted"]
    method: Literal["lbfgs", "adam"] = OPTIMISE_DEFAULTS["method"]
    max_iterations: number("[1, 1e+06]", integer=True) = OPTIMISE_DEFAULTS["max_iterations"]
    lp_order: number("[1, 64]") = OPTIMISE_DEFAULTS["lp_order"]
    #: the TE RMS limit of the least_safety objective (µm), as jaxgear optimise --te-limit-um
    te_limit_um: number("(0, 1e+04]") | None = None
    vars: Annotated[list, BeforeValidator(_variable_names)] = pydantic.Field(
        default_factory=lambda: list(_DEFAULT_VARS))
    torques: Annotated[list, BeforeValidator(_torque_span)] | None = None
    #: the speed band of the dynamic_factor objective, as jaxgear optimise --speeds START:STOP:N
    speeds: Annotated[list, BeforeValidator(_speed_span)] | None = None
    bounds: dict[str, number_list(length=2)] = pydantic.Field(default_factory=dict)
    #: bearing choice: one bearing's candidates, ``"<shaft>.bearings[<k>]" = ["6205",
    #: { catalogue = "30205", arrangement = "O" }, { kind = ..., bore_mm = ... }]`` (catalogue
    #: names, inline tables of a bearing's keys), each ranked by the objective (its clearance
    #: optimised where ``vars`` is that bearing's clearance, else evaluated as given); read as
    #: ``{bearing: {candidate name: table}}``
    choices: dict[str, dict[str, dict[str, Any]]] | None = None

    @pydantic.field_validator("choices", mode="before")
    @classmethod
    def _choices(cls, v):
        return _choices(v)

    @pydantic.model_validator(mode="after")
    def _related(self):
        given = self.given
        goal = self.objective if "objective" in given else None
        if "quantile" in given and self.reduce != "quantile":
            raise sc.fail(WHERE, "quantile", "applies to reduce = 'quantile' only, not "
                          f"{self.reduce!r}", self.quantile)
        if "quantile" not in given and self.reduce == "quantile":
            raise sc.fail(WHERE, "reduce", "'quantile' needs its level: quantile = q in (0, 1) "
                          "(e.g. 0.9)", "quantile")
        if "a_weighted" in given and goal not in ACOUSTIC_OBJECTIVES:
            raise _not_for("a_weighted", "'erp' or 'sound_power'", goal or "te_rms",
                           self.a_weighted)
        if "lp_order" in given and goal not in (None, "line_load_lp"):
            raise _not_for("lp_order", "'line_load_lp'", goal, self.lp_order)
        if "te_limit_um" in given and goal != "least_safety":
            raise _not_for("te_limit_um", "'least_safety'", goal or "te_rms", self.te_limit_um)
        if "torques" in given and goal not in (None, *TORQUE_RANGE_OBJECTIVES):
            raise _not_for("torques", "'robust_te_rms' or a tribology objective "
                           f"({', '.join(TORQUE_RANGE_OBJECTIVES[1:])})", goal, self.torques)
        if "speeds" in given and goal != "dynamic_factor":
            raise _not_for("speeds", "'dynamic_factor'", goal or "te_rms", self.speeds)
        if "speeds" not in given and goal == "dynamic_factor":
            raise sc.fail(WHERE, "objective", "'dynamic_factor' needs speeds = [start, stop, n] "
                          "(its pinion speed band in rad/s, e.g. [2800.0, 3200.0, 3])",
                          "dynamic_factor")
        if self.choices is not None:
            self._check_choice(goal or "te_rms")
        for name, (lo, hi) in self.bounds.items():
            kind = _variable_kind(name)
            pair = [lo, hi]
            if kind is None:
                raise sc.fail(f"{WHERE}.bounds", name, f"unknown variable, allowed "
                              f"{_ALLOWED_VARS}", pair)
            if name not in self.vars:
                raise sc.fail(f"{WHERE}.bounds", name, "is not a design variable (vars = "
                              f"{sc.fmt(self.vars)})", pair)
            good = lo < hi and (lo >= 0 if kind == "depth" else
                                kind == "clearance" or 0 < lo and hi < 1)
            if not good:
                lo_ok = {"depth": "0 <= lo < hi", "clearance": "lo < hi"}.get(
                    kind, "0 < lo < hi < 1")
                unit = {"depth": "E* = depth/δ_m", "clearance": "µm, the bearing's range: "
                        "docs/bearings.md"}.get(kind, "Γ")
                raise sc.fail(f"{WHERE}.bounds", name, f"out of range, allowed [lo, hi] with "
                              f"{lo_ok} ({unit})", pair)
        return self

    def _check_choice(self, goal: str) -> None:
        """``choices`` with ``vars`` its bearing's clearance or not given, and an objective
        that takes a designed structure."""
        (name,) = self.choices
        if "vars" in self.given and self.vars != [f"{name}.clearance"]:
            raise sc.fail(WHERE, "vars", f"with [optimise.choices] allowed [\"{name}.clearance\"] "
                          "(each candidate's clearance optimised) or no vars (each evaluated "
                          "as given)", self.vars)
        if not designs_structure(goal):
            raise sc.fail(WHERE, "objective", "a bearing choice needs an objective a bearing's "
                          "stiffness acts on: allowed any but 'dynamic_factor'", goal)

    def settings(self) -> dict:
        """The keys the file gave, normalised (:func:`parse_optimise`)."""
        out: dict[str, Any] = {k: getattr(self, k) for k in type(self).model_fields
                               if k in self.given}
        if "bounds" in out:
            out["bounds"] = {name: (lo, hi) for name, (lo, hi) in self.bounds.items()}
        return out


def parse_optimise(table) -> dict:
    """Validate an ``[optimise]`` table (keys as the ``jaxgear optimise`` options;
    :class:`OptimiseSection`) and return the keys it gives, normalised: ``vars`` a list of
    names, ``torques`` and ``speeds`` ``[start, stop, n]`` (float, float, int), ``bounds``
    ``{name: (lo, hi)}`` (E* for depths, Γ for extents, µm for a clearance),
    ``max_iterations`` an int, ``quantile``, ``lp_order``, ``te_limit_um`` floats, other keys
    as given.

    Raises:
        SchemaError: one line naming the key, its value and what is allowed: the table not a
            table; an unknown key, objective, method or variable; torques not ``[start, stop,
            n]`` with 0 < start < stop and an integer n in [2, 10000]; speeds not ``[start,
            stop, n]`` with 0 < start <= stop <= 1e5 and an integer n in [1, 1000], or without
            objective ``dynamic_factor`` (which needs them); crossed bounds or bounds of a name
            not in ``vars``; ``lp_order`` outside [1, 64] or with an objective other than
            ``line_load_lp``; ``te_limit_um`` (the TE RMS limit of ``least_safety``, µm) not in
            (0, 1e+04] or with another objective; ``quantile`` outside (0, 1) or without
            ``reduce = "quantile"`` (which needs it); ``a_weighted`` not a boolean or with an
            objective other than ``erp`` and ``sound_power``.
    """
    return OptimiseSection.read(table).settings()
