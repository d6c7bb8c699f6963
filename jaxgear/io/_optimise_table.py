"""``[optimise]`` of a case file: the settings of ``jaxgear optimise`` (objective, variables,
torques, bounds), checked and normalised."""

from __future__ import annotations

import functools
from typing import Any

from fem_prep import schema as sc
from optimise import OBJECTIVES, VARIABLES

__all__ = [
    "ACOUSTIC_OBJECTIVES",
    "OPTIMISE_DEFAULTS",
    "TORQUE_RANGE_OBJECTIVES",
    "check_acoustic_tables",
    "check_train_design",
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

_OPTIMISE_KEYS = {
    "objective",
    "vars",
    "torques",
    "reduce",
    "method",
    "max_iterations",
    "bounds",
    "lp_order",
    "speeds",
    "te_limit_um",
    "quantile",
    "a_weighted",
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
_DEFAULT_VARS = tuple(OPTIMISE_DEFAULTS["vars"].split(","))


@functools.singledispatch
def _name_list(value):
    """``vars`` as given (an array of names; checked by the caller)."""
    return value


@_name_list.register
def _(value: str) -> list:
    """``vars = "a, b"``: comma-separated names."""
    return [x.strip() for x in value.split(",") if x.strip()]


def parse_optimise(table) -> dict:
    """Validate an ``[optimise]`` table (keys as the ``jaxgear optimise`` options) and return it
    normalised: ``vars`` a list of names, ``torques`` ``[start, stop, n]`` (float, float, int),
    ``bounds`` ``{name: (lo, hi)}`` (E* for depths, Γ for extents), other keys as given.

    Raises:
        SchemaError: unknown key, objective, method or variable; torques not ``[start, stop, n]``
            with 0 < start < stop and an integer n >= 2; crossed bounds; ``lp_order`` outside
            [1, 64] or with an objective other than ``line_load_lp``; ``te_limit_um`` (the TE
            RMS limit of ``least_safety``, µm) not in (0, 1e+04] or with another objective;
            ``quantile`` outside (0, 1) or without ``reduce = "quantile"`` (which needs it);
            ``a_weighted`` not a boolean or with an objective other than ``erp`` and
            ``sound_power``.
    """
    w = "optimise"
    if not isinstance(table, dict):
        raise sc.fail("", "optimise", "must be a table", table)
    sc.check_keys(table, _OPTIMISE_KEYS, w)
    out: dict[str, Any] = {}
    if "objective" in table:
        out["objective"] = sc.choice(table, "objective", w, OBJECTIVES, OPTIMISE_DEFAULTS["objective"])
    if "reduce" in table:
        out["reduce"] = sc.choice(table, "reduce", w, ("max", "mean", "quantile"),
                                  OPTIMISE_DEFAULTS["reduce"])
    # the level of reduce = "quantile" (over the torques, or the acoustic objectives' speeds)
    if "quantile" in table:
        out["quantile"] = float(sc.number(table, "quantile", w, None, allowed="(0, 1)"))
        if out.get("reduce") != "quantile":
            raise sc.fail(w, "quantile", "applies to reduce = 'quantile' only, not "
                          f"{out.get('reduce', 'max')!r}", table["quantile"])
    elif out.get("reduce") == "quantile":
        raise sc.fail(w, "reduce", "'quantile' needs its level: quantile = q in (0, 1) "
                      "(e.g. 0.9)", "quantile")
    # the A weighting of the acoustic objectives' orders (IEC 61672-1)
    if "a_weighted" in table:
        out["a_weighted"] = sc.boolean(table, "a_weighted", w, True)
        if out.get("objective") not in ACOUSTIC_OBJECTIVES:
            raise sc.fail(w, "a_weighted", "applies to objective = 'erp' or 'sound_power' only, "
                          f"not {out.get('objective', 'te_rms')!r}", table["a_weighted"])
    if "method" in table:
        out["method"] = sc.choice(table, "method", w, ("lbfgs", "adam"), OPTIMISE_DEFAULTS["method"])
    if "max_iterations" in table:
        out["max_iterations"] = sc.number(
            table, "max_iterations", w, OPTIMISE_DEFAULTS["max_iterations"], allowed="[1, 1e+06]",
            integer=True,
        )

    if "lp_order" in table:
        out["lp_order"] = float(sc.number(table, "lp_order", w, OPTIMISE_DEFAULTS["lp_order"],
                                             allowed="[1, 64]"))
        if out.get("objective", "line_load_lp") != "line_load_lp":
            raise sc.fail(
                w,
                "lp_order",
                f"applies to objective = 'line_load_lp' only, not {out['objective']!r}",
                table["lp_order"],
            )

    # the TE RMS limit of the least_safety objective, as jaxgear optimise --te-limit-um
    if "te_limit_um" in table:
        out["te_limit_um"] = float(sc.number(table, "te_limit_um", w, None,
                                                allowed="(0, 1e+04]"))
        if out.get("objective") != "least_safety":
            raise sc.fail(
                w,
                "te_limit_um",
                "applies to objective = 'least_safety' only, not "
                f"{out.get('objective', 'te_rms')!r}",
                table["te_limit_um"],
            )

    def kind(name: str):
        parts = name.split(".")
        base = ".".join(parts[1:]) if parts[0] in ("pinion", "gear") else name
        return VARIABLES[base][1] if base in VARIABLES else None

    allowed_vars = f"{', '.join(VARIABLES)}, optionally prefixed 'pinion.' or 'gear.'"
    names = list(_DEFAULT_VARS)
    if "vars" in table:
        v = table["vars"]
        v = _name_list(v)
        if not isinstance(v, list) or not v or not all(isinstance(x, str) for x in v):
            raise sc.fail(w, "vars", "must be a non-empty array of variable names", table["vars"])
        for x in v:
            if kind(x) is None:
                raise sc.fail(w, "vars", f"unknown variable {sc.fmt(x)}, allowed {allowed_vars}", v)
        if len(set(v)) != len(v):
            raise sc.fail(w, "vars", "names a variable twice", v)
        out["vars"] = names = list(v)
    if "torques" in table:
        v = table["torques"]
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
            raise sc.fail(
                w,
                "torques",
                "allowed [start, stop, n] in N·m with 0 < start < stop and an integer n in "
                "[2, 10000]",
                v,
            )
        if out.get("objective", "robust_te_rms") not in TORQUE_RANGE_OBJECTIVES:
            raise sc.fail(
                w,
                "torques",
                "applies to objective = 'robust_te_rms' or a tribology objective "
                f"({', '.join(TORQUE_RANGE_OBJECTIVES[1:])}) only, not {out['objective']!r}",
                v,
            )
        out["torques"] = [float(v[0]), float(v[1]), int(v[2])]
    # the speed band of the dynamic_factor objective, as jaxgear optimise --speeds START:STOP:N
    if "speeds" in table:
        v = table["speeds"]
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
            raise sc.fail(
                w,
                "speeds",
                "allowed [start, stop, n]: pinion speeds in rad/s with 0 < start < stop <= 1e+05 "
                "and an integer n in [1, 1000] (start = stop when n = 1)",
                v,
            )
        if out.get("objective") != "dynamic_factor":
            raise sc.fail(
                w,
                "speeds",
                "applies to objective = 'dynamic_factor' only, not "
                f"{out.get('objective', 'te_rms')!r}",
                v,
            )
        out["speeds"] = [float(v[0]), float(v[1]), int(v[2])]
    elif out.get("objective") == "dynamic_factor":
        raise sc.fail(
            w,
            "objective",
            "'dynamic_factor' needs speeds = [start, stop, n] (its pinion speed band in rad/s, "
            "e.g. [2800.0, 3200.0, 3])",
            "dynamic_factor",
        )
    if "bounds" in table:
        b = sc.subtable(table, "bounds", w)
        bounds = {}
        for name, pair in b.items():
            k = kind(name)
            if k is None:
                raise sc.fail(
                    f"{w}.bounds", name, f"unknown variable, allowed {allowed_vars}", pair
                )
            if name not in names:
                raise sc.fail(
                    f"{w}.bounds", name, f"is not a design variable (vars = {sc.fmt(names)})", pair
                )
            lo_ok = "0 < lo < hi < 1" if k != "depth" else "0 <= lo < hi"
            lohi = sc.number_list(b, name, f"{w}.bounds", length=2)
            lo, hi = lohi
            good = lo < hi and (lo >= 0 if k == "depth" else 0 < lo and hi < 1)
            if not good:
                unit = "E* = depth/δ_m" if k == "depth" else "Γ"
                raise sc.fail(
                    f"{w}.bounds",
                    name,
                    f"out of range, allowed [lo, hi] with {lo_ok} ({unit})",
                    pair,
                )
            bounds[name] = (lo, hi)
        out["bounds"] = bounds
    return out
