"""``[deviations]`` of a planetary stage's case file (the gear form): ISO 1328-1 deviations per
tooth of the sun, each planet and the ring, drawn from a grade or given, and the span of the
quasi-static over the stage's hunting period (docs/planetary.md, "Per-tooth deviations and the
hunting period"). The keys are the pair's ``[deviations]`` keys (jaxgear/io/_deviations_table.py)
with the members ``[deviations.sun]``, ``[deviations.planet_1]`` … ``[deviations.planet_N]`` and
``[deviations.ring]``; a planet's two flanks either share its table or each has its own,
``[deviations.planet_N.sun_flank]`` and ``[deviations.planet_N.ring_flank]``; runout is the
stage's (``[planetary]`` eccentricities and planet runout)."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import pydantic

from fem_prep import schema as sc

from .._deviations import ISO1328_SCOPE, GearDeviations, iso1328_tolerances, sample_gear_deviations
from ..planetary import PlanetaryDeviations, PlanetFlanks, planetary_hunting_periods
from ._deviations_table import DeviationSpan, GearDeviationsSection, member_values
from ._modifications_table import _depth_range
from ._sections import named_keys, number

__all__ = ["MAX_STAGE_POSITIONS", "StageDeviationsSection", "parse_planetary_deviations"]

#: the most positions a stage's deviation span may ask for (sun turns × z_s × positions per
#: pitch): each position is a contact solve of all 2N meshes
MAX_STAGE_POSITIONS = 400_000
#: where a member's runout goes instead ([planetary]; a planet's: planet_runout_um)
RUNOUT_KEYS = {"sun": "sun_eccentricity_um", "ring": "ring_eccentricity_um"}
#: a planet's flank tables: the flanks the sun loads, those the ring loads
FLANKS = ("sun_flank", "ring_flank")
class MemberDeviations(GearDeviationsSection):
    """``[deviations.sun]``, ``[deviations.ring]`` or a planet flank's table (µm): the pair's
    gear keys (:class:`jaxgear.io._deviations_table.GearDeviationsSection`;
    :func:`jaxgear.io._deviations_table.member_values` checks the ranges that follow the
    module and the lengths that follow the member's teeth), the runout keys declared to be
    refused in their words (the stage's eccentricities carry the runout)."""

    WHERE: ClassVar[str] = "deviations.sun"
    runout_um: Any = None  # refused: _refuse_runout
    runout_phase_deg: Any = None

    def values(self) -> dict:
        """The deviation keys given (the runout's refused first), as a table."""
        return {k: v for k, v in self.table().items() if k not in FLANKS}


class PlanetDeviations(MemberDeviations):
    """``[deviations.planet_<n>]``: both flanks' values, or each flank's table
    (``sun_flank``, ``ring_flank``; not both forms: :func:`parse_planetary_deviations`)."""

    WHERE: ClassVar[str] = "deviations.planet_1"
    sun_flank: MemberDeviations | None = None
    ring_flank: MemberDeviations | None = None


class StageDeviationsSection(DeviationSpan):
    """``[deviations]`` of a planetary stage (module docstring): the span's keys
    (:class:`jaxgear.io._deviations_table.DeviationSpan`; ``revolutions`` in sun turns) and
    its positions per pitch, the members' tables (the planets' named ``planet_1`` …
    ``planet_N``, the context's ``planets``: :attr:`planets`). The span's size and the
    grade's scope follow the stage's teeth (:func:`parse_planetary_deviations`)."""

    positions_per_pitch: number(">= 2", integer=True) = 4
    sun: MemberDeviations | None = None
    ring: MemberDeviations | None = None
    planets: dict[str, PlanetDeviations] = pydantic.Field(default_factory=dict)

    @pydantic.model_validator(mode="before")
    @classmethod
    def _tables(cls, data, info):
        """The planets' tables (``planet_1`` … ``planet_N``) moved to :attr:`planets` (the
        span's "hunting": :class:`~jaxgear.io._deviations_table.DeviationSpan`)."""
        planets = (info.context or {}).get("planets", ())
        if not isinstance(data, dict):
            return data
        return named_keys(data, planets, "deviations", cls.file_keys(), into="planets")

    @classmethod
    def file_keys(cls, context: dict | None = None) -> tuple[str, ...]:
        """The table's keys but the planets' (named by the stage: :attr:`planets`)."""
        return tuple(k for k in cls.model_fields if k != "planets")


def parse_planetary_deviations(table, pairs: tuple, n_planets: int) -> tuple[PlanetaryDeviations,
                                                                             dict]:
    """``[deviations]`` of a planetary case → (:class:`~jaxgear.planetary.PlanetaryDeviations`, the run
    settings).

    ``grade`` (ISO 1328-1 flank tolerance class, 1 to 11) draws every member's pitch, profile
    and helix deviations (:func:`~jaxgear.sample_gear_deviations`, NumPy ``default_rng(seed)``:
    the sun, the sun-side flanks of planet 1 … planet N, the ring, then the ring-side flanks of
    planet 1 … planet N: ISO 1328-1 tolerances each flank, so a planet's two flanks are drawn
    independently; the drawn runout set to 0); the member tables give values (µm) that replace
    the drawn ones key by key, or, without a grade, are the only deviations (the other members
    perfect). A planet's table gives values for both flanks, or its ``sun_flank`` and
    ``ring_flank`` tables each flank's (:class:`~jaxgear.planetary.PlanetFlanks`; not both forms in one
    planet). Without a grade and without flank tables a planet is one
    :class:`~jaxgear.GearDeviations` (both flanks the same).

    Args:
        table: the ``[deviations]`` table. pairs: (sun–planet pair, planet–ring pair).
        n_planets: N.

    Settings returned (case-file units): ``grade`` (or None), ``seed``, ``revolutions`` (turns
    of the sun relative to the carrier, an integer or ``"hunting"``: H / z_s, H =
    lcm(z_s, z_p, z_r) mesh periods), ``revolutions_count``, ``mesh_periods`` (the span),
    ``hunting_periods`` (H), ``positions_per_pitch`` (default 4), ``tolerances_um`` per member
    (with a grade).

    Raises:
        SchemaError: one line (unknown keys, wrong types, values out of range, arrays of another
            length than the member's teeth, pitch deviations that do not close, a planet's values
            given both in its table and in its flank tables, a span of more than
            :data:`MAX_STAGE_POSITIONS` positions).
    """
    planets = [f"planet_{i + 1}" for i in range(n_planets)]
    t = StageDeviationsSection.read(table, context={"planets": tuple(planets)})
    sp, pr = pairs
    z_s, z_p, z_r = int(sp.pinion.teeth), int(sp.gear.teeth), -int(pr.gear.teeth)
    grade, seed, ppp = t.grade, t.seed, t.positions_per_pitch
    hunting = planetary_hunting_periods(z_s, z_p, z_r)
    count = hunting // z_s if t.revolutions is None else t.revolutions
    rev = "hunting" if t.revolutions is None else count
    if count * z_s * ppp > MAX_STAGE_POSITIONS:
        raise sc.fail(
            "deviations",
            "revolutions",
            f"out of range: {count} sun turns × {z_s} teeth × {ppp} positions per pitch is "
            f"{count * z_s * ppp} positions, allowed <= {MAX_STAGE_POSITIONS} (lower "
            "positions_per_pitch or give a number of revolutions)",
            rev,
        )
    signed, note = _depth_range(sp.normal_module * 1e3, signed=True)
    positive, _ = _depth_range(sp.normal_module * 1e3)
    members = [("sun", sp.pinion, z_s), *((p, sp.gear, z_p) for p in planets),
               ("ring", pr.gear, z_r)]
    if grade is not None:
        lo, hi = ISO1328_SCOPE["teeth"]
        for tag, z in (("sun", z_s), ("planet", z_p), ("ring", z_r)):
            if not lo <= z <= hi:
                raise sc.fail(tag, "teeth", f"out of range with [deviations] grade = {grade}, "
                              f"allowed [{lo}, {hi}] (the scope of ISO 1328-1; give the "
                              "deviations per member without a grade instead)", z)
    rng = np.random.default_rng(seed)
    alpha = float(sp.transverse_pressure_angle)
    tolerances = {}
    drawn: dict[tuple[str, str | None], dict] = {}
    # the draw order: sun, the planets' sun-side flanks, ring, the planets' ring-side flanks
    order = [(tag, member, z, None if tag in ("sun", "ring") else "sun_flank")
             for tag, member, z in members]
    order += [(p, sp.gear, z_p, "ring_flank") for p in planets]
    for tag, member, z, flank in order if grade is not None else ():
        d = z * sp.normal_module / math.cos(sp.helix_angle)
        try:
            tol = iso1328_tolerances(sp.normal_module, d, member.face_width, grade)
        except ValueError as err:
            raise sc.fail("deviations", "grade", f"{tag}: {err}", grade) from None
        tolerances[tag] = tol.as_um()
        g = sample_gear_deviations(rng, z, tol, alpha)
        drawn[tag, flank] = {f: np.asarray(getattr(g, f)) for f in (
            "single_pitch", "profile_slope", "profile_form", "helix_slope", "helix_form")}
    out: dict[str, Any] = {}
    for tag, _, z in members:
        planet = tag in planets
        spec = (t.planets.get(tag) if planet else getattr(t, tag)) or (
            PlanetDeviations() if planet else MemberDeviations())
        _refuse_runout(spec, f"deviations.{tag}", tag)
        values = spec.values()
        given = member_values(values, f"deviations.{tag}", z, signed, positive, note)
        flanks = {}
        for flank in FLANKS if planet else ():
            sub = getattr(spec, flank)
            if sub is not None:
                _refuse_runout(sub, f"deviations.{tag}.{flank}", tag)
            flanks[flank] = None if sub is None else member_values(
                sub.values(), f"deviations.{tag}.{flank}", z, signed, positive, note)
        per_flank = any(v is not None for v in flanks.values())
        flat = sorted(values)
        if per_flank and flat:
            raise sc.fail(f"deviations.{tag}", flat[0], "not beside its flank tables (allowed: "
                          f"the values of both flanks in [deviations.{tag}], or each flank's "
                          f"in [deviations.{tag}.sun_flank] / [deviations.{tag}.ring_flank], "
                          "not both)", values[flat[0]])
        if not planet or (grade is None and not per_flank):
            out[tag] = _gear({**drawn.get((tag, None), {}), **given}, z, alpha)
            continue
        out[tag] = PlanetFlanks(*(
            _gear({**drawn.get((tag, f), {}), **given, **(flanks[f] or {})}, z, alpha)
            for f in FLANKS))
    planet_devs = tuple(out[p] for p in planets)
    deviations = PlanetaryDeviations(
        sun=out["sun"], planets=planet_devs if any(g is not None for g in planet_devs) else (),
        ring=out["ring"])
    settings = {
        "grade": grade,
        "seed": seed,
        "revolutions": rev,
        "revolutions_count": int(count),
        "mesh_periods": int(count * z_s),
        "hunting_periods": int(hunting),
        "positions_per_pitch": ppp,
    }
    if tolerances:
        settings["tolerances_um"] = tolerances
    return deviations, settings


def _refuse_runout(spec: MemberDeviations, where: str, tag: str) -> None:
    """Refuse a member's (or a planet flank's) runout keys: the stage's eccentricities carry
    it (one line naming the key to use)."""
    for key in ("runout_um", "runout_phase_deg"):
        if key in spec.given:
            raise sc.fail(where, key, "not here in a planetary stage (allowed: the stage's "
                          f"runout, [planetary] {RUNOUT_KEYS.get(tag, 'planet_runout_um')})",
                          getattr(spec, key))


def _gear(kw: dict, z: int, alpha: float) -> GearDeviations | None:
    """A member's (or flank's) :class:`~jaxgear.GearDeviations` from its keywords, None for
    none (a perfect member)."""
    if not kw:
        return None
    kw.setdefault("single_pitch", np.zeros(z))
    return GearDeviations(**kw, reference_pressure_angle=alpha)
