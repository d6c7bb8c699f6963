"""The ``[robust]`` table of a case file (``jaxgear robust``; docs/robust.md, "Case file")."""

from __future__ import annotations

import math
from typing import Any

from fem_prep import schema as sc

from .._deviations import ISO1328_SCOPE

__all__ = ["ROBUST_DEFAULTS", "parse_robust"]

#: the settings of ``jaxgear robust`` when neither ``[robust]`` nor an option gives them
ROBUST_DEFAULTS: dict[str, Any] = {
    "grade": None,
    "samples": 200,
    "seed": 0,
    "members": ["pinion", "gear"],
    "kinds": ["pitch", "runout", "profile", "helix"],
    "revolutions": 1,
    "positions_per_pitch": 8,
    "speeds_rad_s": [],
    "steps_per_period": 32,
    "transient_periods": 10,
    "batch_size": 16,
    "percentiles": [5.0, 50.0, 95.0],
    "confidence": 0.95,
}
#: the most positions one realisation's quasi-static span may ask for
MAX_ROBUST_POSITIONS = 200_000


def _names(table, key, allowed, where):
    v = table.get(key, ROBUST_DEFAULTS[key])
    if (
        not isinstance(v, list)
        or not v
        or any(x not in allowed for x in v)
        or len(set(v)) != len(v)
    ):
        raise sc.fail(where, key, f"out of range, allowed distinct names among {list(allowed)}", v)
    return list(v)


def parse_robust(table, teeth: tuple[int, int], *, grade_from_deviations=None) -> dict:
    """``[robust]`` (a dict from the case file, possibly empty) → the settings of
    ``jaxgear robust`` (case-file units), the defaults of :data:`ROBUST_DEFAULTS` filled in.

    Keys: ``grade`` (ISO 1328-1 flank tolerance class 1-11; default ``[deviations] grade``),
    ``samples`` (>= 2), ``seed`` (>= 0), ``members`` (["pinion", "gear"]), ``kinds`` (among
    pitch, runout, profile, helix), ``revolutions`` (pinion revolutions of the span, >= 1, or
    "hunting": z2/gcd(z1, z2)), ``positions_per_pitch`` (quasi-static, >= 2), ``speeds_rad_s``
    (pinion speeds > 0 of the dynamic-factor distributions; empty: quasi-static only),
    ``steps_per_period`` (Newmark, >= 8), ``transient_periods`` (mesh periods integrated before
    the kept span, >= 1), ``batch_size`` (>= 1), ``percentiles`` (in (0, 100)), ``confidence``
    (in (0, 1)).

    Raises:
        SchemaError: one line naming the key, its value and the allowed range.
    """
    where = "robust"
    if not isinstance(table, dict):
        raise sc.fail("", where, "must be a table", table)
    sc.check_keys(table, ROBUST_DEFAULTS, where)
    out = dict(ROBUST_DEFAULTS)
    out["grade"] = sc.number(
        table, "grade", where, grade_from_deviations, allowed="[1, 11]", integer=True
    )
    if out["grade"] is not None:  # the tolerances of ISO 1328-1 hold within its scope only
        lo, hi = ISO1328_SCOPE["teeth"]
        for tag, z in zip(("pinion", "gear"), teeth, strict=True):
            if not lo <= z <= hi:
                raise sc.fail(
                    tag,
                    "teeth",
                    f"out of range with [robust] grade = {out['grade']}, allowed [{lo}, {hi}] "
                    "(the scope of ISO 1328-1, which the grade's tolerances come from)",
                    z,
                )
    out["samples"] = sc.number(table, "samples", where, 200, allowed=">= 2", integer=True)
    out["seed"] = sc.number(table, "seed", where, 0, allowed=">= 0", integer=True)
    out["members"] = _names(table, "members", ("pinion", "gear"), where)
    out["kinds"] = _names(table, "kinds", ("pitch", "runout", "profile", "helix"), where)
    z1, z2 = teeth
    rev = table.get("revolutions", 1)
    if rev == "hunting":
        out["revolutions"] = z2 // math.gcd(z1, z2)
    elif isinstance(rev, str):
        raise sc.fail(where, "revolutions", 'allowed an integer >= 1 or "hunting"', rev)
    else:
        out["revolutions"] = sc.number(table, "revolutions", where, 1, allowed=">= 1", integer=True)
    out["positions_per_pitch"] = sc.number(
        table, "positions_per_pitch", where, 8, allowed=">= 2", integer=True
    )
    n = out["revolutions"] * z1 * out["positions_per_pitch"]
    if n > MAX_ROBUST_POSITIONS:
        raise sc.fail(
            where,
            "revolutions",
            f"out of range: {out['revolutions']} revolutions × {z1} teeth × "
            f"{out['positions_per_pitch']} positions per pitch is {n} positions per realisation, "
            f"allowed <= {MAX_ROBUST_POSITIONS}",
            rev,
        )
    # as [operating] speed_rad_s: up to 1e5 rad/s (a mesh frequency beyond any gear's)
    out["speeds_rad_s"] = sc.number_list(table, "speeds_rad_s", where, [], allowed="(0, 1e+05]")
    out["steps_per_period"] = sc.number(
        table, "steps_per_period", where, 32, allowed=">= 8", integer=True
    )
    out["transient_periods"] = sc.number(
        table, "transient_periods", where, 10, allowed=">= 1", integer=True
    )
    out["batch_size"] = sc.number(table, "batch_size", where, 16, allowed=">= 1", integer=True)
    out["percentiles"] = sc.number_list(
        table, "percentiles", where, [5.0, 50.0, 95.0], min_length=1, allowed="(0, 100)"
    )
    out["confidence"] = sc.number(table, "confidence", where, 0.95, allowed="(0, 1)")
    return out
