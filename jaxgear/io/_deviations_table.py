"""``[deviations]`` of a case file: manufacturing deviations per tooth (ISO 1328-1), drawn from a
grade or given, and their run settings."""

from __future__ import annotations

import math
from typing import Any, ClassVar

import numpy as np
import pydantic

from fem_prep import schema as sc

from .._deviations import (
    ISO1328_SCOPE,
    Deviations,
    GearDeviations,
    iso1328_tolerances,
    sample_gear_deviations,
)
from .._geometry import GearPair
from .._robust import (
    AbstractDeviationKind,
    HelixDeviation,
    PitchDeviation,
    ProfileDeviation,
    RunoutDeviation,
)
from ._modifications_table import _depth_range
from ._sections import Section, number, number_list, one_of

__all__ = [
    "DEVIATION_KINDS",
    "DeviationSpan",
    "DeviationsSection",
    "GearDeviationsSection",
    "deviation_kinds_from_names",
    "member_values",
    "parse_deviations",
]

#: ``[robust] kinds`` names: the deviations a sampler draws
DEVIATION_KINDS = {
    "pitch": PitchDeviation(),
    "runout": RunoutDeviation(),
    "profile": ProfileDeviation(),
    "helix": HelixDeviation(),
}


def deviation_kinds_from_names(names) -> tuple[AbstractDeviationKind, ...]:
    """The deviation kinds a ``[robust] kinds`` list names ("pitch", "runout", "profile",
    "helix"), for :meth:`jaxgear.DeviationSampler.for_grade`.

    Raises:
        ValueError: an unknown name (one line).
    """
    names = tuple(names)
    bad = [n for n in names if n not in DEVIATION_KINDS]
    if bad:
        raise ValueError(
            f"kinds = {names!r} is out of range: allowed names among {tuple(DEVIATION_KINDS)}"
        )
    return tuple(DEVIATION_KINDS[n] for n in names)

_PER_TOOTH = ("profile_slope", "profile_form", "helix_slope", "helix_form")
#: tolerance on the closure Σ f_pt = 0 of given single pitch deviations (µm)
PITCH_CLOSURE_UM = 1e-6
#: the most positions a deviation span may ask for (revolutions × z1 × positions_per_pitch)
MAX_SPAN_POSITIONS = 2_000_000
#: a per-tooth deviation (µm): one for every tooth, or an array of one per tooth
_PER_TOOTH_VALUE = one_of(number=number(), array=number_list())


class GearDeviationsSection(Section):
    """``[deviations.pinion]`` or ``[deviations.gear]`` (µm, deg): a gear's single pitch
    deviations (one per tooth, closing), its runout and the runout's phase, its profile and
    helix slopes and forms (a number for every tooth or one per tooth). The ranges that follow
    the module and the lengths that follow the gear's teeth are checked where the gear is known
    (:func:`member_values`). A planetary member's table is this one with the runout refused
    (:class:`jaxgear.io._planetary_deviations_table.MemberDeviations`)."""

    WHERE: ClassVar[str] = "deviations.pinion"
    pitch_um: number_list() | None = None
    profile_slope_um: _PER_TOOTH_VALUE | None = None
    profile_form_um: _PER_TOOTH_VALUE | None = None
    helix_slope_um: _PER_TOOTH_VALUE | None = None
    helix_form_um: _PER_TOOTH_VALUE | None = None
    runout_um: number() | None = None
    runout_phase_deg: number("[-360, 360]") | None = None

    def values(self) -> dict:
        """The deviation keys given, as a table (:func:`member_values`' input)."""
        return self.table()


class DeviationSpan(Section):
    """The keys every ``[deviations]`` table shares (a pair's, :class:`DeviationsSection`; a
    planetary stage's): the ISO 1328-1 grade, the draw's seed and the quasi-static span
    (``revolutions``: an integer, or "hunting", held as ``None``)."""

    WHERE: ClassVar[str] = "deviations"
    grade: number("[1, 11]", integer=True) | None = None
    seed: number(">= 0", integer=True) = 0
    revolutions: number(">= 1", integer=True) | None = pydantic.Field(
        None, json_schema_extra={"default": "'hunting'"})

    @pydantic.model_validator(mode="before")
    @classmethod
    def _hunting(cls, data):
        """"hunting" revolutions as None; another string refused in the table's words."""
        return hunting_revolutions(data)


class DeviationsSection(DeviationSpan):
    """``[deviations]`` of a pair (:func:`parse_deviations`): the span's keys
    (:class:`DeviationSpan`; ``revolutions`` in pinion revolutions), its positions per pitch
    and the gears' tables. The span's size and the grade's scope follow the pair's teeth
    (:func:`parse_deviations`)."""

    positions_per_pitch: number(">= 2", integer=True) = 16
    pinion: GearDeviationsSection | None = None
    gear: GearDeviationsSection | None = None


def hunting_revolutions(data):
    """A ``[deviations]`` table with ``revolutions = "hunting"`` dropped (the span's default);
    another string refused in one line (``allowed an integer >= 1 or "hunting"``)."""
    if not isinstance(data, dict):
        return data
    rev = data.get("revolutions")
    if isinstance(rev, str):
        if rev != "hunting":
            raise sc.fail("deviations", "revolutions", 'allowed an integer >= 1 or "hunting"', rev)
        data = {k: v for k, v in data.items() if k != "revolutions"}
    return data


def _per_tooth(spec: dict, key: str, where: str, z: int, allowed: str = "any", note: str = ""):
    """A number (every tooth) or an array of one number per tooth, µm → m (None: absent)."""
    if key not in spec:
        return None
    if np.ndim(spec[key]):  # an array: one value per tooth
        return np.asarray(sc.number_list(spec, key, where, length=z, allowed=allowed)) * 1e-6
    return sc.number(spec, key, where, allowed=allowed, note=note) * 1e-6


def member_values(spec: dict, where: str, z: int, signed: str, positive: str,
                  note: str) -> dict[str, Any]:
    """The values a member's table ``[deviations.<member>]`` gives (µm, deg → m, rad), as
    :class:`~jaxgear.GearDeviations` keywords: ``pitch_um`` (single pitch deviations, one per
    tooth, closing: Σ = 0), ``runout_um``, ``runout_phase_deg`` and the per-tooth (or every
    tooth's) profile and helix slopes and forms; ``signed`` / ``positive``: the allowed ranges
    of signed and positive depths (``note``: why).

    Raises:
        SchemaError: wrong types, values out of range, arrays of another length than ``z``,
            pitch deviations that do not close."""
    kw: dict[str, Any] = {}
    if "pitch_um" in spec:
        fpt = np.asarray(sc.number_list(spec, "pitch_um", where, length=z, allowed=signed))
        fpt = fpt * 1e-6
        if abs(fpt.sum()) * 1e6 > PITCH_CLOSURE_UM:
            raise sc.fail(
                where,
                "pitch_um",
                f"out of range: the single pitch deviations sum to {fpt.sum() * 1e6:.6g} µm, "
                "allowed a sum of 0 (they close around the gear)",
                spec["pitch_um"],
            )
        kw["single_pitch"] = fpt
    if "runout_um" in spec:
        kw["runout"] = sc.number(spec, "runout_um", where, allowed=positive, note=note) * 1e-6
    if "runout_phase_deg" in spec:
        kw["runout_phase"] = math.radians(
            sc.number(spec, "runout_phase_deg", where, allowed="[-360, 360]")
        )
    for f in _PER_TOOTH:
        v = _per_tooth(spec, f"{f}_um", where, z, signed, note)
        if v is not None:
            kw[f] = v
    return kw


def parse_deviations(table, pair: GearPair) -> tuple[Deviations, dict]:
    """``[deviations]`` → (:class:`Deviations`, the run settings).

    ``grade`` (ISO 1328-1 flank tolerance class, 1 to 11) draws every deviation of both gears
    (:func:`~jaxgear.sample_gear_deviations`, NumPy ``default_rng(seed)``: pinion first, then
    gear); ``[deviations.pinion]`` / ``[deviations.gear]`` give values (µm) that replace the drawn
    ones key by key, or, without a grade, are the only deviations (the others 0).

    Settings returned (case-file units): ``grade`` (or None), ``seed``, ``revolutions`` (pinion
    revolutions of the quasi-static span, an integer or ``"hunting"``), ``revolutions_count`` (the
    integer), ``positions_per_pitch``, ``tolerances_um`` per gear (with a grade).

    Raises:
        SchemaError: unknown keys, wrong types, values out of range, arrays of another length
            than the gear's teeth, given single pitch deviations that do not close (Σ ≠ 0).
    """
    t = DeviationsSection.read(table)
    grade, seed, ppp = t.grade, t.seed, t.positions_per_pitch
    z1, z2 = pair.pinion.teeth, pair.gear.teeth
    count = z2 // math.gcd(z1, z2) if t.revolutions is None else t.revolutions
    rev = "hunting" if t.revolutions is None else count
    if count * z1 * ppp > MAX_SPAN_POSITIONS:
        raise sc.fail(
            "deviations",
            "revolutions",
            f"out of range: {count} pinion revolutions × {z1} teeth × {ppp} positions per pitch "
            f"is {count * z1 * ppp} positions, allowed <= {MAX_SPAN_POSITIONS} (lower "
            "positions_per_pitch or give a number of revolutions)",
            rev,
        )
    rng = np.random.default_rng(seed)
    members, tolerances = [], {}
    # deviations up to one normal module (µm): beyond, the flank is no longer a tooth's
    signed, note = _depth_range(pair.normal_module * 1e3, signed=True)
    positive, _ = _depth_range(pair.normal_module * 1e3)
    lo_z, hi_z = ISO1328_SCOPE["teeth"]
    for tag, z in (("pinion", z1), ("gear", z2)):
        if grade is not None and not lo_z <= z <= hi_z:
            raise sc.fail(
                tag,
                "teeth",
                f"out of range with [deviations] grade = {grade}, allowed [{lo_z}, {hi_z}] (the "
                "scope of ISO 1328-1, which the grade's tolerances come from; give the "
                f"deviations in [deviations.{tag}] without a grade instead)",
                z,
            )
    for tag, member, z in (("pinion", pair.pinion, z1), ("gear", pair.gear, z2)):
        spec = getattr(t, tag) or GearDeviationsSection()
        where = f"deviations.{tag}"
        kw: dict[str, Any] = {}
        if grade is not None:
            d = z * pair.normal_module / math.cos(pair.helix_angle)
            try:  # the gear's own reference diameter and face width (tolerances are per gear)
                tol = iso1328_tolerances(pair.normal_module, d, member.face_width, grade)
            except ValueError as err:
                raise sc.fail("deviations", "grade", f"{tag}: {err}", grade) from None
            tolerances[tag] = tol.as_um()
            drawn = sample_gear_deviations(rng, z, tol, pair.transverse_pressure_angle)
            kw = {
                f: np.asarray(getattr(drawn, f))
                for f in ("single_pitch", "runout", "runout_phase", *_PER_TOOTH)
            }
        kw.update(member_values(spec.values(), where, z, signed, positive, note))
        if not kw and grade is None:
            members.append(None)
            continue
        kw.setdefault("single_pitch", np.zeros(z))
        members.append(
            GearDeviations(**kw, reference_pressure_angle=pair.transverse_pressure_angle)
        )
    settings = {
        "grade": grade,
        "seed": seed,
        "revolutions": rev,
        "revolutions_count": int(count),
        "positions_per_pitch": ppp,
    }
    if tolerances:
        settings["tolerances_um"] = tolerances
    return Deviations(pinion=members[0], gear=members[1]), settings
