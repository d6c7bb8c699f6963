"""The ``[robust]`` table of a case file (``jaxgear robust``; docs/robust.md, "Case file")."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import pydantic

from fem_prep import schema as sc

from .._deviations import ISO1328_SCOPE
from ._sections import Section, number, number_list

__all__ = ["ROBUST_DEFAULTS", "RobustSection", "parse_robust"]

#: the names ``[robust] members`` and ``kinds`` take
NAMES = {"members": ("pinion", "gear"), "kinds": ("pitch", "runout", "profile", "helix")}
#: the most positions one realisation's quasi-static span may ask for
MAX_ROBUST_POSITIONS = 200_000


class RobustSection(Section):
    """``[robust]``, the settings of ``jaxgear robust`` (:func:`parse_robust`; docs/robust.md):
    ``grade`` (ISO 1328-1 flank tolerance class; default ``[deviations] grade``), ``samples``,
    ``seed``, the ``members`` and deviation ``kinds`` sampled (:data:`NAMES`), ``revolutions``
    of the pinion in the span (or "hunting": z2/gcd(z1, z2), the pair's teeth in the context),
    quasi-static ``positions_per_pitch``, the pinion ``speeds_rad_s`` of the dynamic-factor
    distributions (as ``[operating] speed_rad_s``: up to 1e5 rad/s; empty: quasi-static
    only), Newmark ``steps_per_period``, ``transient_periods`` before the kept span,
    ``batch_size``, the ``percentiles`` reported and the ``confidence`` of their bands."""

    WHERE: ClassVar[str] = "robust"
    grade: number("[1, 11]", integer=True) | None = None
    samples: number(">= 2", integer=True) = 200
    seed: number(">= 0", integer=True) = 0
    members: list[str] = pydantic.Field(default_factory=lambda: list(NAMES["members"]))
    kinds: list[str] = pydantic.Field(default_factory=lambda: list(NAMES["kinds"]))
    revolutions: number(">= 1", integer=True) = 1
    positions_per_pitch: number(">= 2", integer=True) = 8
    speeds_rad_s: number_list("(0, 1e+05]") = pydantic.Field(default_factory=list)
    steps_per_period: number(">= 8", integer=True) = 32
    transient_periods: number(">= 1", integer=True) = 10
    batch_size: number(">= 1", integer=True) = 16
    percentiles: number_list("(0, 100)", min_length=1) = pydantic.Field(
        default_factory=lambda: [5.0, 50.0, 95.0])
    confidence: number("(0, 1)") = 0.95

    @pydantic.field_validator("members", "kinds", "revolutions", mode="before")
    @classmethod
    def _words(cls, v, info):
        """Names in the table's words; "hunting" revolutions as their count."""
        where, key = (info.context or {}).get("where", cls.WHERE), info.field_name
        if key == "revolutions":
            if isinstance(v, str) and v != "hunting":
                raise sc.fail(where, key, 'allowed an integer >= 1 or "hunting"', v)
            z1, z2 = (info.context or {}).get("teeth", (1, 1))
            return z2 // math.gcd(z1, z2) if v == "hunting" else v
        allowed = NAMES[key]
        if (not isinstance(v, list) or not v or any(x not in allowed for x in v)
                or len(set(v)) != len(v)):
            raise sc.fail(where, key, f"out of range, allowed distinct names among "
                          f"{list(allowed)}", v)
        return v


#: the settings of ``jaxgear robust`` when neither ``[robust]`` nor an option gives them
ROBUST_DEFAULTS: dict[str, Any] = {
    k: f.get_default(call_default_factory=True) for k, f in RobustSection.model_fields.items()}


def parse_robust(table, teeth: tuple[int, int], *, grade_from_deviations=None) -> dict:
    """``[robust]`` (a dict from the case file, possibly empty; :class:`RobustSection`) → the
    settings of ``jaxgear robust`` (case-file units), the defaults of :data:`ROBUST_DEFAULTS`
    filled in; ``grade`` by default ``grade_from_deviations``.

    Raises:
        SchemaError: one line naming the key, its value and the allowed range (a grade with
            teeth beyond ISO 1328-1's scope, a span of more than :data:`MAX_ROBUST_POSITIONS`
            positions).
    """
    section = RobustSection.read(table, context={"teeth": tuple(teeth)})
    out = section.model_dump()
    out["grade"] = grade_from_deviations if section.grade is None else section.grade
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
    n = out["revolutions"] * teeth[0] * out["positions_per_pitch"]
    if n > MAX_ROBUST_POSITIONS:
        raise sc.fail(
            "robust",
            "revolutions",
            f"out of range: {out['revolutions']} revolutions × {teeth[0]} teeth × "
            f"{out['positions_per_pitch']} positions per pitch is {n} positions per realisation, "
            f"allowed <= {MAX_ROBUST_POSITIONS}",
            table.get("revolutions", 1),
        )
    return out
