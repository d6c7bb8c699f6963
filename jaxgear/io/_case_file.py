"""Case files (TOML, units in key names) and the embedded reference cases.

A case is read, checked against the schema as a whole (``[scene]`` and ``[optimise]`` included:
unknown keys are errors, every value is type and range checked in the file's units, one integer
rule), converted to SI and turned into a :class:`Case`; absurd but valid inputs then give a
:class:`CaseWarning`. Errors are :class:`fem_prep.schema.SchemaError` (a ``ValueError``) with a
one-line message such as ``[pinion] face_width_mm = -3: out of range, allowed > 0``. See README.md
for the schema.
"""

from __future__ import annotations

import itertools
import math
import re
import warnings
from typing import Any

import numpy as np

from fem_prep import schema as sc
from optimise import OBJECTIVES, VARIABLES

from .._case import Case, TrainCase
from .._deviations import (
    ISO1328_SCOPE,
    Deviations,
    GearDeviations,
    iso1328_tolerances,
    sample_gear_deviations,
)
from .._geometry import JAM, GearPair, Member
from .._modifications import MemberModification, Modifications
from .._stiffness import FOUNDATIONS, iso6336_mesh_stiffness, sainsot_fit_check, stiffness_table
from ..scenes import disc_inertia
from ._robust_table import parse_robust
from ._scene_table import parse_scene

__all__ = [
    "CaseWarning",
    "mean_static_deflection",
    "parse_case",
    "parse_deviations",
    "parse_modifications",
    "parse_optimise",
    "plausibility",
]

SchemaError = sc.SchemaError


class CaseWarning(UserWarning):
    """A valid but implausible case (one-line message naming the key): relief far deeper than the
    mean static deflection, a torque too small to deflect the teeth measurably, or a load beyond
    what steel teeth carry, or a gear body outside the range of the Sainsot foundation fit."""


_MEMBER_KEYS = {
    "teeth",
    "profile_shift",
    "addendum_coeff",
    "dedendum_coeff",
    "face_width_mm",
    "fillet_radius_coeff",
    "bore_radius_mm",
    "web_thickness_mm",
    "rim_thickness_mm",
}
#: a pair case's member keys: the train's and the tooth thickness allowance (backlash; a train
#: has no coast flanks: docs/backlash.md)
_PAIR_MEMBER_KEYS = _MEMBER_KEYS | {"tooth_thickness_allowance_um"}
_SCHEMA: dict[str, Any] = {
    "name": None,
    "pair": {
        "normal_module_mm",
        "normal_pressure_angle_deg",
        "helix_angle_deg",
        "center_distance_mm",
    },
    "pinion": _PAIR_MEMBER_KEYS,
    "gear": _PAIR_MEMBER_KEYS,
    "material": {"youngs_modulus_GPa", "poisson_ratio", "density_kg_m3"},
    "operating": {"torque_Nm", "speed_rad_s"},
    "mesh": {
        "stiffness",
        "stiffness_per_length_N_per_mm_per_um",
        "slices",
        "positions_per_pitch",
        "smooth_width_um",
        "foundation",
        "fe2d_size_um",
    },
    "modifications": None,  # checked by parse_modifications
    "deviations": None,  # checked by parse_deviations
    "robust": None,  # checked by parse_robust (jaxgear robust)
    "scene": None,  # checked by parse_scene
    "optimise": None,  # checked by parse_optimise
}
# [mesh] keys read by some stiffness models only
_MODEL_KEYS = {
    "stiffness_per_length_N_per_mm_per_um": ("uniform",),
    "fe2d_size_um": ("fe2d",),
    "foundation": ("weber", "fe2d"),
}
_MOD_KEYS = {
    "tip_relief": {"depth_um", "extent", "shape"},
    "root_relief": {"depth_um", "extent", "shape"},
    "crowning": {"depth_um"},
    "end_relief": {"depth_um", "extent", "edge"},
    "helix_slope": {"deviation_um"},
    "profile_deviation": {"roll_fraction", "deviation_um"},
}

# plausibility thresholds (CaseWarning), documented in README.md
RELIEF_RATIO_WARN = 10.0  # a relief/crowning depth above 10 δ_m
MIN_DEFLECTION_UM = 0.01  # δ_m below 0.01 µm: torque too small
MAX_LINE_LOAD_N_PER_MM = 2000.0  # F_n / b above what case-hardened steel teeth carry
MAX_DEFLECTION_MODULE = 0.05  # δ_m above 5 % of the normal module

# physical ranges of the pair (file units), checked before the geometry is computed
MODULE_RANGE_MM = "[0.01, 100]"  # watch gears to mill gears
PRESSURE_ANGLE_RANGE_DEG = "[10, 40]"  # below: undercut (z_min = 66 at 10°); above: pointed tips
MIN_FACE_WIDTH_MODULE = 0.1  # face width >= 0.1 m_n ...
MAX_FACE_WIDTH_MODULE = 100.0  # ... and <= 100 m_n (usual b/m_n: 6 to 40)
MAX_DEPTH_MODULE = 1.0  # modification and deviation depths: up to one normal module
MIN_LINE_LOAD_N_PER_MM = 1e-6  # torque: F_n/b >= 1e-6 N/mm (δ_m ~ 1e-7 µm; below, round-off)
CENTER_DISTANCE_TOL_MM = 1e-3  # a centre distance up to 1 µm below the zero-backlash one is it
MIN_SMOOTH_WIDTH_UM = 1e-4  # smooth contact width w: 0.1 nm ...
MAX_SMOOTH_WIDTH_MODULE = 0.01  # ... to 1 % of the module (the smooth TE is offset by ~ w)
SMOOTH_WIDTH_WARN = 1.0  # CaseWarning: w above δ_m
MAX_DAMPING_RATIO = 1.0  # CaseWarning: Rayleigh ξ above critical at a mesh mode's frequency


# --------------------------------------------------------------------------------------------
# modifications


def _depth_range(module_mm: float | None, signed: bool = False) -> tuple[str, str]:
    """The allowed range (file units, µm) of a modification or deviation depth and its note:
    up to ``MAX_DEPTH_MODULE`` normal modules (deeper, the flank is no longer a tooth's)."""
    if module_mm is None:
        return (">= 0" if not signed else "any"), ""
    hi = MAX_DEPTH_MODULE * module_mm * 1e3
    rng = f"[{-hi:.6g}, {hi:.6g}]" if signed else f"[0, {hi:.6g}]"
    return rng, f" (µm; up to {MAX_DEPTH_MODULE:g} × normal_module_mm)"


def _member_mods(
    entries: dict[str, tuple[Any, str]], module_mm: float | None = None
) -> MemberModification:
    """``{name: (spec, where)}`` → :class:`MemberModification` (depths µm → m), each depth
    within one normal module ``module_mm`` (mm) of the member."""
    kw: dict[str, Any] = {}
    depth_rng, depth_note = _depth_range(module_mm)
    signed_rng, _ = _depth_range(module_mm, signed=True)
    for name, (spec, where) in entries.items():
        if not isinstance(spec, dict):
            raise sc.fail(where, name, "must be a table, e.g. { depth_um = 10.0 }", spec)
        w = f"{where}.{name}"
        sc.check_keys(spec, _MOD_KEYS[name], w)
        if name in ("tip_relief", "root_relief"):
            depth = sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note)
            extent = sc.number(
                spec, "extent", w, 0.25, allowed="(0, 1]", note=" (fraction of the path of contact)"
            )
            shape = sc.choice(spec, "shape", w, ("linear", "parabolic"), "linear")
            kw.update(
                {
                    f"{name}_depth": depth * 1e-6,
                    f"{name}_extent": extent,
                    f"{name}_shape": shape,
                }
            )
        elif name == "crowning":
            kw["crowning_depth"] = (
                sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note) * 1e-6
            )
        elif name == "end_relief":
            depth = sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note)
            extent = sc.number(
                spec,
                "extent",
                w,
                0.1,
                allowed="(0, 0.5]",
                note=" (fraction of the face width at each end)",
            )
            edge = sc.choice(spec, "edge", w, ("both", "z0", "z1"), "both")
            kw.update(end_relief_depth=depth * 1e-6, end_relief_extent=extent, end_relief_edge=edge)
        elif name == "helix_slope":
            kw["helix_slope_deviation"] = (
                sc.number(spec, "deviation_um", w, 0.0, allowed=signed_rng, note=depth_note) * 1e-6
            )
        elif name == "profile_deviation":
            u = sc.number_list(spec, "roll_fraction", w, min_length=2, allowed="[0, 1]")
            d = sc.number_list(spec, "deviation_um", w, min_length=2, allowed=signed_rng)
            if len(u) != len(d):
                raise sc.fail(w, "deviation_um", f"needs one value per roll_fraction ({len(u)})", d)
            if any(b <= a for a, b in itertools.pairwise(u)):
                raise sc.fail(w, "roll_fraction", "must ascend strictly within [0, 1]", u)
            kw.update(profile_deviation_roll=np.asarray(u), profile_deviation=np.asarray(d) * 1e-6)
    return MemberModification(**kw)


def parse_modifications(table: dict, module_mm: float | None = None) -> Modifications:
    """``[modifications]`` → :class:`Modifications`.

    Entries directly under ``[modifications]`` apply to each member; entries under
    ``[modifications.pinion]`` / ``[modifications.gear]`` replace them for that member.

    Raises:
        SchemaError: unknown modification or key, wrong type, value out of range.
    """
    if not isinstance(table, dict):
        raise sc.fail("", "modifications", "must be a table", table)
    allowed = {*_MOD_KEYS, "pinion", "gear"}
    sc.check_keys(table, allowed, "modifications")
    common = {k: (v, "modifications") for k, v in table.items() if k not in ("pinion", "gear")}
    members = []
    for tag in ("pinion", "gear"):
        own = sc.subtable(table, tag, "modifications", _MOD_KEYS)
        where = f"modifications.{tag}"
        members.append(
            _member_mods({**common, **{k: (v, where) for k, v in own.items()}}, module_mm)
        )
    return Modifications(pinion=members[0], gear=members[1])


# --------------------------------------------------------------------------------------------
# manufacturing deviations (ISO 1328-1)

_DEV_KEYS = {"grade", "seed", "revolutions", "positions_per_pitch", "pinion", "gear"}
_DEV_MEMBER_KEYS = {
    "pitch_um",
    "runout_um",
    "runout_phase_deg",
    "profile_slope_um",
    "profile_form_um",
    "helix_slope_um",
    "helix_form_um",
}
_PER_TOOTH = ("profile_slope", "profile_form", "helix_slope", "helix_form")
#: tolerance on the closure Σ f_pt = 0 of given single pitch deviations (µm)
PITCH_CLOSURE_UM = 1e-6
#: the most positions a deviation span may ask for (revolutions × z1 × positions_per_pitch)
MAX_SPAN_POSITIONS = 2_000_000


def _per_tooth(spec: dict, key: str, where: str, z: int, allowed: str = "any", note: str = ""):
    """A number (every tooth) or an array of one number per tooth, µm → m (None: absent)."""
    if key not in spec:
        return None
    v = spec[key]
    if isinstance(v, list):
        return np.asarray(sc.number_list(spec, key, where, length=z, allowed=allowed)) * 1e-6
    return sc.number(spec, key, where, allowed=allowed, note=note) * 1e-6


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
    if not isinstance(table, dict):
        raise sc.fail("", "deviations", "must be a table", table)
    sc.check_keys(table, _DEV_KEYS, "deviations")
    grade = sc.number(table, "grade", "deviations", None, allowed="[1, 11]", integer=True)
    seed = sc.number(table, "seed", "deviations", 0, allowed=">= 0", integer=True)
    rev = table.get("revolutions", "hunting")
    z1, z2 = pair.pinion.teeth, pair.gear.teeth
    if rev == "hunting":
        count = z2 // math.gcd(z1, z2)
    else:
        if isinstance(rev, str):
            raise sc.fail("deviations", "revolutions", 'allowed an integer >= 1 or "hunting"', rev)
        count = sc.number(table, "revolutions", "deviations", allowed=">= 1", integer=True)
        rev = count
    ppp = sc.number(table, "positions_per_pitch", "deviations", 16, allowed=">= 2", integer=True)
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
        spec = sc.subtable(table, tag, "deviations", _DEV_MEMBER_KEYS)
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


# --------------------------------------------------------------------------------------------
# the case


def _geometry_error(err: Exception, data: dict) -> sc.SchemaError:
    """A :class:`GearPair` ``ValueError`` (SI names and units) → a case-file message (mm, deg)."""
    msg = str(err)
    m = re.match(r"(?P<name>.+?) = (?P<value>.+?) is out of range: allowed (?P<allowed>.*)$", msg)
    if not m:
        return sc.SchemaError(f"[pair] geometry: {sc.g6(msg)}")
    name, value, allowed = m.group("name"), m.group("value"), sc.g6(m.group("allowed"))
    file_value = lambda where, key: data.get(where, {}).get(key, "default")
    member = re.match(r"(pinion|gear)\.(\w+)(?: \((.*)\))?$", name)
    if name == "center_distance":
        v = sc.fmt(file_value("pair", "center_distance_mm"))
        return sc.SchemaError(f"[pair] center_distance_mm = {v}: out of range, allowed {allowed}")
    if name == JAM:
        a = re.search(r"center_distance >= (\S+) mm", allowed)
        total = sum(
            data.get(t, {}).get("tooth_thickness_allowance_um", 0.0) for t in ("pinion", "gear")
        )
        return sc.SchemaError(
            f"[pinion] tooth_thickness_allowance_um + [gear] tooth_thickness_allowance_um = "
            f"{sc.fmt(total)}: out of range without [pair] center_distance_mm, allowed <= 0 (the "
            "thickened teeth jam at the zero-backlash distance of the nominal teeth); or give "
            f"[pair] center_distance_mm >= {a.group(1) if a else '?'}"
        )
    if name.startswith("profile_shift (x1 + x2)"):
        return sc.SchemaError(
            f"[pinion] profile_shift + [gear] profile_shift = {sc.g6(value)}: out of range, "
            f"allowed {allowed}"
        )
    if name == "transverse contact ratio":
        return sc.SchemaError(
            f"[pinion]/[gear] addendum_coeff: transverse contact ratio = {sc.g6(value)}: out of "
            f"range, allowed {allowed}"
        )
    radius = re.match(r"(pinion|gear)\.(root|tip) radius \(from (\w+) and profile_shift\)$", name)
    if radius:
        tag, which, key = radius.groups()
        try:
            mm = f"{float(value) * 1e3:.6g} mm"
        except ValueError:
            mm = value
        return sc.SchemaError(
            f"[{tag}] {key} = {sc.fmt(file_value(tag, key))}: {which} radius {mm} (from {key} "
            f"and profile_shift), allowed {allowed}"
        )
    if member:
        tag, key, why = member.groups()
        unit_key = {"face_width": "face_width_mm", "bore_radius": "bore_radius_mm"}.get(key, key)
        rf = re.match(r"\(0, (\S+)\) m", m.group("allowed"))
        if key == "bore_radius" and rf:
            return sc.SchemaError(
                f"[{tag}] bore_radius_mm = {sc.fmt(file_value(tag, unit_key))}: out of range, "
                f"allowed (0, {float(rf.group(1)) * 1e3:.6g}) (below the root radius)"
            )
        why = f" ({sc.g6(why)})" if why else ""
        return sc.SchemaError(
            f"[{tag}] {unit_key} = {sc.fmt(file_value(tag, unit_key))}: out of range{why}, "
            f"allowed {allowed}"
        )
    keys = {
        "normal_module": "normal_module_mm",
        "normal_pressure_angle": "normal_pressure_angle_deg",
        "helix_angle": "helix_angle_deg",
    }
    if name in keys:
        v = sc.fmt(file_value("pair", keys[name]))
        return sc.SchemaError(f"[pair] {keys[name]} = {v}: out of range, allowed {allowed}")
    return sc.SchemaError(f"[pair] geometry: {sc.g6(msg)}")


def check_member_size(t: dict, where: str, member: Member, module_mm: float, alpha_deg: float):
    """A member's face width within [0.1, 100] normal modules and its generating rack a tooth:
    the two tip roundings (ρ_fP = fillet_radius_coeff m_n) fit on the rack tooth's tip, whose
    half-width is π/4 − h_fP tan α_n modules (ISO 53; fem_prep.tooth_form), i.e.
    ρ_fP* <= (π/4 − h_fP* tan α_n) cos α_n / (1 − sin α_n). ``t``: the member's table as
    written, ``where`` its key path."""
    b_min, b_max = MIN_FACE_WIDTH_MODULE * module_mm, MAX_FACE_WIDTH_MODULE * module_mm
    if not b_min <= member.face_width * 1e3 <= b_max:
        raise sc.fail(
            where,
            "face_width_mm",
            f"out of range, allowed [{b_min:.6g}, {b_max:.6g}] ({MIN_FACE_WIDTH_MODULE:g} to "
            f"{MAX_FACE_WIDTH_MODULE:g} × normal_module_mm)",
            t["face_width_mm"],
        )
    an = math.radians(alpha_deg)
    hf, rho = member.dedendum_coeff, member.fillet_radius_coeff
    shape = (1 - math.sin(an)) / math.cos(an)
    rho_max = (math.pi / 4 - hf * math.tan(an)) / shape
    if rho <= rho_max * (1 + 1e-12):
        return
    why = (
        f"at normal_pressure_angle_deg = {alpha_deg:.6g} (the generating rack's tooth tip must "
        "hold its two tip roundings of radius fillet_radius_coeff × m_n)"
    )
    if "fillet_radius_coeff" in t and rho_max > 0:
        raise sc.fail(
            where,
            "fillet_radius_coeff",
            f"out of range, allowed [0, {rho_max:.6g}] with dedendum_coeff = {hf:.6g} {why}",
            t["fillet_radius_coeff"],
        )
    hf_max = (math.pi / 4 - rho * shape) / math.tan(an)
    given = "" if "fillet_radius_coeff" in t else " (the default)"
    raise sc.fail(
        where,
        "dedendum_coeff",
        f"out of range, allowed <= {hf_max:.6g} with fillet_radius_coeff = {rho:.6g}{given} {why}",
        t.get("dedendum_coeff", member.dedendum_coeff),
    )


def _member(data: dict, tag: str, keys=_MEMBER_KEYS) -> Member:
    t = sc.subtable(data, tag, "", keys, required=True)
    dedendum = sc.number(t, "dedendum_coeff", tag, 1.25, allowed="(0, 3]")
    fillet = sc.number(t, "fillet_radius_coeff", tag, 0.25, allowed=">= 0")
    if not fillet < dedendum:
        if "fillet_radius_coeff" not in t:  # the default fillet: the dedendum is the culprit
            raise sc.fail(
                tag,
                "dedendum_coeff",
                f"out of range, allowed > {fillet:.6g} (above the default fillet_radius_coeff; "
                "or give a smaller fillet_radius_coeff)",
                t["dedendum_coeff"],
            )
        raise sc.fail(
            tag,
            "fillet_radius_coeff",
            f"out of range, allowed [0, {dedendum:.6g}) (below dedendum_coeff)",
            t["fillet_radius_coeff"],
        )
    bore = sc.number(t, "bore_radius_mm", tag, None, allowed="> 0")
    # webbed blank (ISO 6336-1 gear blank factor C_R of the iso6336 stiffness): both or neither
    web = sc.number(t, "web_thickness_mm", tag, None, allowed="> 0")
    rim = sc.number(t, "rim_thickness_mm", tag, None, allowed="> 0")
    if (web is None) != (rim is None):
        given, missing = ("web", "rim") if rim is None else ("rim", "web")
        raise sc.fail(
            tag,
            f"{missing}_thickness_mm",
            f"required with {given}_thickness_mm (the gear blank factor C_R needs both; "
            "leave both out for a solid blank)",
        )
    return Member(
        teeth=sc.number(t, "teeth", tag, allowed="[5, 10000]", integer=True),
        profile_shift=sc.number(t, "profile_shift", tag, 0.0, allowed="(-1.5, 1.5)"),
        addendum_coeff=sc.number(t, "addendum_coeff", tag, 1.0, allowed="(0, 3]"),
        dedendum_coeff=dedendum,
        face_width=sc.number(t, "face_width_mm", tag, allowed="> 0") * 1e-3,
        fillet_radius_coeff=fillet,
        bore_radius=None if bore is None else bore * 1e-3,
        web_thickness=None if web is None else web * 1e-3,
        rim_thickness=None if rim is None else rim * 1e-3,
        tooth_thickness_allowance=sc.number(
            t, "tooth_thickness_allowance_um", tag, 0.0, allowed="[-1e+04, 1e+04]"
        )
        * 1e-6,
    )


def parse_torque(op: dict, pair: GearPair) -> float:
    """``[operating] torque_Nm`` (N·m): positive and at least the torque of a line load
    F_n/b = ``MIN_LINE_LOAD_N_PER_MM`` on ``pair`` (below, the deflections are round-off)."""
    t_min = (
        MIN_LINE_LOAD_N_PER_MM
        * 1e3
        * pair.face_width
        * pair.base_radii[0]
        * math.cos(pair.base_helix_angle)
    )
    return sc.number(
        op,
        "torque_Nm",
        "operating",
        allowed=f">= {float(f'{t_min:.3g}'):.3g}",
        note=f" (a line load F_n/b of {MIN_LINE_LOAD_N_PER_MM:g} N/mm on this pair)",
    )


def parse_material(data: dict) -> tuple[float, float, float]:
    """``[material]``: Young's modulus (Pa), Poisson's ratio, density (kg/m³)."""
    mat = sc.subtable(data, "material", "")
    E = sc.number(mat, "youngs_modulus_GPa", "material", 210.0, allowed="[0.1, 10000]") * 1e9
    nu = sc.number(mat, "poisson_ratio", "material", 0.3, allowed="[0, 0.5)")
    rho = sc.number(mat, "density_kg_m3", "material", 7800.0, allowed="[100, 1e+05]")
    return E, nu, rho


def parse_mesh_settings(data: dict, normal_module: float) -> dict:
    """``[mesh]``: the :class:`Case` fields of the mesh model (stiffness model and its
    settings, slices, positions per pitch, smooth width); ``normal_module`` (m) scales the
    ranges of the widths (the smallest module of a train)."""
    m = sc.subtable(data, "mesh", "")
    # default fe2d: Weber's half-plane foundation is 16–52 % too stiff against it (README,
    # docs/stiffness.md); the embedded seed cases say "weber", the seed's model
    model = sc.choice(m, "stiffness", "mesh", ("weber", "uniform", "iso6336", "fe2d"), "fe2d")
    for key, models in _MODEL_KEYS.items():  # a key of another model would be silently ignored
        if key in m and model not in models:
            raise sc.fail(
                "mesh",
                key,
                f"belongs to stiffness = {' or '.join(repr(x) for x in models)}, not {model!r} "
                "(remove it or change the model)",
                m[key],
            )
    k0 = sc.number(
        m,
        "stiffness_per_length_N_per_mm_per_um",
        "mesh",
        sc.MISSING if model == "uniform" else None,
        allowed="(0, 1e+06]",
    )
    k0 = None if k0 is None else k0 * 1e9
    slices = sc.number(m, "slices", "mesh", 40, allowed="[1, 10000]", integer=True)
    ppp = sc.number(m, "positions_per_pitch", "mesh", 64, allowed="[2, 100000]", integer=True)
    mn_um = normal_module * 1e6  # fe2d element size: 1 to 100 elements per module
    width = (
        sc.number(
            m,
            "smooth_width_um",
            "mesh",
            0.1,
            allowed=f"[{MIN_SMOOTH_WIDTH_UM:g}, {MAX_SMOOTH_WIDTH_MODULE * mn_um:.6g}]",
            note=f" (µm; up to {100 * MAX_SMOOTH_WIDTH_MODULE:g} % of the normal module)",
        )
        * 1e-6
    )
    fe2d_size = sc.number(
        m,
        "fe2d_size_um",
        "mesh",
        None,
        allowed=f"[{mn_um / 100:.6g}, {mn_um:.6g}]",
        note=" (m_n/100 to m_n; default m_n/6)",
    )
    fe2d_size = None if fe2d_size is None else fe2d_size * 1e-6
    foundation = m.get("foundation", "weber")
    if isinstance(foundation, bool):  # the old boolean: true = "weber", false = "none"
        foundation = "weber" if foundation else "none"
    elif foundation not in FOUNDATIONS:
        raise sc.fail(
            "mesh",
            "foundation",
            "allowed 'weber', 'sainsot', 'none' (or true = 'weber', false = 'none')",
            foundation,
        )
    return {
        "stiffness_model": model,
        "uniform_k0": k0,
        "slices": slices,
        "positions_per_pitch": ppp,
        "smooth_width": width,
        "foundation": foundation,
        "fe2d_size": fe2d_size,
    }


def parse_case(data: dict, default_name: str = "case", base_dir: str | None = None) -> Case:
    """Validate a parsed case TOML (a dict), ``[scene]`` and ``[optimise]`` included, and build a
    :class:`Case`; then warn (:class:`CaseWarning`) about absurd but valid inputs.

    Raises:
        SchemaError (a ``ValueError``): unknown keys, missing required keys, wrong types, values
            out of range, invalid geometry; one line, in the file's units.
    """
    if not isinstance(data, dict):
        raise sc.SchemaError(f"a case must be a table of tables, not {type(data).__name__}")
    sc.check_keys(data, _SCHEMA, "")
    name = sc.name(data, "name", "", default_name)
    for section, allowed in _SCHEMA.items():
        if isinstance(allowed, set):
            sc.subtable(data, section, "", allowed, required=section in ("pair", "operating"))
    p = data["pair"]
    pinion = _member(data, "pinion", _PAIR_MEMBER_KEYS)
    gear = _member(data, "gear", _PAIR_MEMBER_KEYS)
    # physical ranges checked before the geometry, so that its errors name the culprit: below
    # 10° the involute undercuts all but very large gears (z_min = 2/sin²α = 66 at 10°), above
    # 40° standard teeth are pointed; the module spans watch gears to mill gears
    module = sc.number(p, "normal_module_mm", "pair", allowed=MODULE_RANGE_MM)
    alpha = sc.number(p, "normal_pressure_angle_deg", "pair", allowed=PRESSURE_ANGLE_RANGE_DEG)
    beta = sc.number(p, "helix_angle_deg", "pair", 0.0, allowed="[0, 45)")
    cd = sc.number(p, "center_distance_mm", "pair", None, allowed="(0, 1e+06]")
    for tag, member in (("pinion", pinion), ("gear", gear)):
        limit = 0.25 * module * 1e3  # µm: a quarter of the module (GearPair's range)
        if abs(member.tooth_thickness_allowance) * 1e6 > limit:
            raise sc.fail(
                tag,
                "tooth_thickness_allowance_um",
                f"out of range, allowed [{-limit:.6g}, {limit:.6g}] (a quarter of "
                "normal_module_mm; negative thins the tooth)",
                data[tag]["tooth_thickness_allowance_um"],
            )
        check_member_size(data[tag], tag, member, module, alpha)
    geometry = {
        "pinion": pinion,
        "gear": gear,
        "normal_module": module * 1e-3,
        "normal_pressure_angle": math.radians(alpha),
        "helix_angle": math.radians(beta),
    }
    try:
        try:
            pair = GearPair(**geometry)
        except ValueError as err:  # thickened teeth jam at the nominal zero-backlash distance
            if cd is None or not str(err).startswith(JAM):
                raise
            pair = GearPair(**geometry, center_distance=cd * 1e-3)
        a0_mm = pair.zero_backlash_center_distance * 1e3
        if cd is not None and cd < a0_mm - CENTER_DISTANCE_TOL_MM:
            raise sc.fail(
                "pair",
                "center_distance_mm",
                f"out of range, allowed >= {a0_mm:.3f} mm (the zero-backlash distance, to "
                f"{CENTER_DISTANCE_TOL_MM * 1e3:g} µm; closer, the teeth jam)",
                p["center_distance_mm"],
            )
        if cd is not None and cd > a0_mm:  # within the tolerance: the zero-backlash distance
            pair = GearPair(**geometry, center_distance=cd * 1e-3)
    except (ValueError, ArithmeticError) as err:
        if isinstance(err, sc.SchemaError):
            raise
        raise _geometry_error(err, data) from None
    E, nu, rho = parse_material(data)
    torque = parse_torque(data["operating"], pair)
    speed = sc.number(data["operating"], "speed_rad_s", "operating", 0.0, allowed="[0, 1e+05]")
    mesh = parse_mesh_settings(data, pair.normal_module)
    mods = parse_modifications(data.get("modifications", {}), module)
    deviations, deviation_settings = (
        parse_deviations(data["deviations"], pair) if "deviations" in data else (None, None)
    )
    if "robust" in data:  # jaxgear robust's table, checked by every command (run, sweep)
        parse_robust(
            data["robust"],
            (pair.pinion.teeth, pair.gear.teeth),
            grade_from_deviations=(deviation_settings or {}).get("grade"),
        )
    scene = parse_scene(data["scene"], base_dir) if "scene" in data else None
    optimise = parse_optimise(data["optimise"]) if "optimise" in data else None
    if optimise is not None and "speeds" in optimise and (scene is None or not scene.hybrid):
        raise sc.fail(
            "optimise",
            "speeds",
            "the dynamic_factor objective needs a case with condensed bodies ([scene.gear_body] "
            "or [scene.pinion_body])",
            data["optimise"]["speeds"],
        )
    coast = any("tooth_thickness_allowance_um" in data[tag] for tag in ("pinion", "gear"))
    if coast:
        _refuse_with_backlash(data, deviations is not None, scene)
    case = Case(
        coast=coast,
        name=name,
        pair=pair,
        modifications=mods,
        deviations=deviations,
        deviation_settings=deviation_settings,
        youngs_modulus=E,
        poisson_ratio=nu,
        density=rho,
        torque=torque,
        speed=speed,
        **mesh,
        scene=scene,
        optimise=optimise,
        raw=data,
    )
    for text in plausibility(case):
        warnings.warn(text, CaseWarning, stacklevel=2)
    return case


def _refuse_with_backlash(data: dict, deviations: bool, scene) -> None:
    """One-line errors for what is not modelled with the coast flanks (docs/backlash.md)."""
    tag = "pinion" if "tooth_thickness_allowance_um" in data["pinion"] else "gear"
    value = data[tag]["tooth_thickness_allowance_um"]
    what = None
    if deviations:
        what = "[deviations]"
    elif scene is not None and scene.hybrid:
        what = "condensed bodies ([scene.pinion_body]/[scene.gear_body])"
    elif scene is not None and scene.solver != "newmark":
        what = f"[scene.integration] solver = {scene.solver!r} (use 'newmark')"
    if what is not None:
        raise sc.fail(
            tag,
            "tooth_thickness_allowance_um",
            f"backlash (coast flanks) with {what} is not modelled: drop one of them",
            value,
        )


# --------------------------------------------------------------------------------------------
# plausibility (absurd but valid)


def mean_static_deflection(case: Case) -> float:
    """A cheap estimate of the mean static deflection δ_m = F_n / K̄ (m), without a contact solve.

    K̄ is the mean mesh stiffness: k0 ε_α b / cos β_b for ``uniform``, the ISO 6336-1 c_γα b for
    ``iso6336`` and, for ``weber``, c_γα b scaled by E / 210 GPa (the Weber profile of the
    embedded cases agrees with it within about 25 %).

    Raises:
        SchemaError: for ``weber``, when the line load is beyond ``MAX_LINE_LOAD_N_PER_MM`` and the
            stiffness model cannot be evaluated (Hertzian contact wider than the teeth): the
            message names ``[operating] torque_Nm``.
    """
    pair = case.pair
    b, eps = pair.face_width, pair.transverse_contact_ratio
    if case.stiffness_model == "uniform" and case.uniform_k0 is not None:
        k_mean = case.uniform_k0 * eps * b / math.cos(pair.base_helix_angle)
    else:
        k_mean = iso6336_mesh_stiffness(pair) * b
        if case.stiffness_model in ("weber", "fe2d"):
            k_mean *= case.youngs_modulus / 210e9
    w = case.normal_load / b * 1e-3
    if case.stiffness_model in ("weber", "fe2d") and w > MAX_LINE_LOAD_N_PER_MM:
        try:
            with np.errstate(all="ignore"):
                stiffness_table(
                    pair,
                    "weber",
                    youngs_modulus=case.youngs_modulus,
                    poisson_ratio=case.poisson_ratio,
                    line_load=case.nominal_line_load(),
                    foundation=case.foundation,
                )
        except (ValueError, ArithmeticError):
            raise sc.SchemaError(
                f"[operating] torque_Nm = {case.torque:.6g}: the line load F_n/b = {w:.6g} N/mm "
                "is far beyond what steel teeth carry (the Hertzian contact would be wider than "
                f"the teeth), allowed up to about {MAX_LINE_LOAD_N_PER_MM:.6g} N/mm"
            ) from None
    return case.normal_load / k_mean


def _mesh_mode_frequencies(case: Case, k_mean: float) -> list[float]:
    """The natural frequencies ω (rad/s) of the torsional modes the mesh excites (a mesh strain
    energy share >= 5 %, as the sweep's critical speeds count them), a cheap estimate without the
    dynamic model: the pinion and gear rotations (the scene's inertias, solid discs by default)
    coupled by the mean mesh stiffness ``k_mean`` (N/m) along V = cos β_b (r_b1, −r_b2), with the
    motor and load rotations on their shafts where a torsional scene has them. For a lumped 3D
    scene, the bearings lower the mesh mode somewhat below this torsional one."""
    spec, pair = case.scene, case.pair
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    motor = spec.model != "lumped3d" and spec.motor_inertia is not None
    load = spec.model != "lumped3d" and spec.load_inertia is not None
    inertias = [spec.motor_inertia] * motor + [i1, i2] + [spec.load_inertia] * load
    n, p = len(inertias), int(motor)
    cb = math.cos(pair.base_helix_angle)
    v = np.zeros(n)
    v[p], v[p + 1] = cb * pair.base_radii[0], -cb * pair.base_radii[1]
    K = k_mean * np.outer(v, v)
    # the shafts motor-pinion and gear-load (stiffness 1 N·m/rad unless given, as the model's)
    for i, k, has in ((0, spec.motor_shaft, motor), (p + 1, spec.load_shaft, load)):
        if has:
            e = np.zeros(n)
            e[i], e[i + 1] = 1.0, -1.0
            K += (k or 1.0) * np.outer(e, e)
    s = 1.0 / np.sqrt(np.asarray(inertias, float))
    w2, U = np.linalg.eigh(s[:, None] * K * s[None, :])
    phi = s[:, None] * U
    elastic = w2 > 1e-9 * w2.max()
    share = k_mean * (v @ phi) ** 2 / np.maximum(np.einsum("ij,ik,kj->j", phi, K, phi), 1e-300)
    keep = elastic & (share >= 0.05)
    return [math.sqrt(w) for w in w2[keep]] or [math.sqrt(w2.max())]


def plausibility(case: Case | TrainCase) -> list[str]:
    """One-line warnings about absurd but valid inputs (thresholds in README.md); a train's,
    those of each mesh as a pair case, named by mesh (``meshes[k] driving-driven: ...``):

    * a relief or crowning depth above ``RELIEF_RATIO_WARN`` (10) × δ_m;
    * δ_m below ``MIN_DEFLECTION_UM`` (0.01 µm): the torque is too small to deflect the teeth;
    * the line load F_n/b above ``MAX_LINE_LOAD_N_PER_MM`` (2000 N/mm) or δ_m above
      ``MAX_DEFLECTION_MODULE`` (5 %) of the normal module: beyond what steel teeth carry;
    * ``foundation = "sainsot"`` on a member whose h_f = r_f/r_int, θ_f give Sainsot coefficients
      outside the span of the published fit (extrapolation);
    * a Rayleigh damping whose ratio ξ = α/(2ω) + β ω/2 exceeds ``MAX_DAMPING_RATIO`` (1) at the
      natural frequency ω of a mode the mesh excites (:func:`_mesh_mode_frequencies`).

    Raises:
        SchemaError: see :func:`mean_static_deflection`.
    """
    if isinstance(case, TrainCase):
        return [
            f"meshes[{k}] {case.mesh_name(k)}: {text}"
            for k in range(len(case.pairs))
            for text in plausibility(case.mesh_case(k))
        ]
    out = []
    delta = mean_static_deflection(case)
    d_um = delta * 1e6
    w = case.normal_load / case.pair.face_width * 1e-3
    t = f"[operating] torque_Nm = {case.torque:.6g}"
    if not math.isfinite(delta):
        return [f"{t}: the mean static deflection is not finite; check the material and torque"]
    if d_um < MIN_DEFLECTION_UM:
        out.append(
            f"{t}: mean static deflection {d_um:.6g} µm is below {MIN_DEFLECTION_UM:g} µm; the "
            "torque is too small for a meaningful transmission error"
        )
    ratio_m = delta / case.pair.normal_module
    if w > MAX_LINE_LOAD_N_PER_MM or ratio_m > MAX_DEFLECTION_MODULE:
        out.append(
            f"{t}: line load F_n/b = {w:.6g} N/mm and mean static deflection {d_um:.6g} µm "
            f"({100 * ratio_m:.3g} % of the module) are beyond what steel teeth carry "
            f"(limits {MAX_LINE_LOAD_N_PER_MM:g} N/mm, {100 * MAX_DEFLECTION_MODULE:g} %)"
        )
    if d_um >= MIN_DEFLECTION_UM and case.smooth_width > SMOOTH_WIDTH_WARN * delta:
        out.append(
            f"[mesh] smooth_width_um = {case.smooth_width * 1e6:.6g}: above the mean static "
            f"deflection {d_um:.6g} µm; the smooth contact law blurs the contact (its TE is offset "
            "by several widths)"
        )
    scene = case.scene
    if scene is not None and scene.damping_model == "rayleigh":
        # the modal damping ratio of C = α M + β K, ξ = α/(2ω) + β ω/2, of each mode the mesh
        # excites, at its natural frequency ω (not at an excitation frequency)
        a, b = scene.rayleigh_alpha, scene.rayleigh_beta
        omegas = _mesh_mode_frequencies(case, case.normal_load / delta)
        xi, w_n = max((a / (2 * w) + b * w / 2, w) for w in omegas)
        if xi > MAX_DAMPING_RATIO:
            key = "beta_s" if b * w_n > a / w_n else "alpha_per_s"
            value = b if key == "beta_s" else a
            out.append(
                f"[scene.damping] {key} = {value:.6g}: the Rayleigh damping ratio at the mesh "
                f"mode's natural frequency ({w_n:.4g} rad/s) is ξ = {xi:.3g} (above critical, "
                f"{MAX_DAMPING_RATIO:g}); usual ξ are 0.01 to 0.1"
            )
    if d_um >= MIN_DEFLECTION_UM:
        raw = case.raw.get("modifications", {}) if isinstance(case.raw, dict) else {}
        for tag in ("pinion", "gear"):
            mm = getattr(case.modifications, tag)
            own = raw.get(tag, {}) if isinstance(raw, dict) else {}
            for key in ("tip_relief", "root_relief", "crowning", "end_relief"):
                depth = float(getattr(mm, f"{key}_depth"))
                if depth > RELIEF_RATIO_WARN * delta:
                    where = f"modifications.{tag}" if key in own else "modifications"
                    out.append(
                        f"[{where}] {key}.depth_um = {depth * 1e6:.6g}: {depth / delta:.3g} × the "
                        f"mean static deflection {d_um:.6g} µm (more than {RELIEF_RATIO_WARN:g} ×); "
                        "the relief removes most of the contact"
                    )
    if case.stiffness_model == "weber" and case.foundation == "sainsot":
        for tag, fit in zip(("pinion", "gear"), sainsot_fit_check(case.pair)):
            if fit["outside"]:
                bore = (case.pair.pinion, case.pair.gear)[tag == "gear"].bore_radius
                given = "default 0.5 × root radius" if bore is None else "given"
                coeffs = ", ".join(f"{k}* = {fit['coefficients'][k]:.4g}" for k in fit["outside"])
                out.append(
                    f"[{tag}] bore_radius_mm ({given}): h_f = r_f/r_int = {fit['h_f']:.4g}, "
                    f"θ_f = {fit['theta_f']:.4g} rad lie outside the range of the Sainsot fit "
                    f"({coeffs} beyond the fitted span); [mesh] foundation = 'sainsot' extrapolates"
                )
    return list(dict.fromkeys(out))


# --------------------------------------------------------------------------------------------
# [optimise]

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
}
_DEFAULT_VARS = ("tip_relief.depth", "tip_relief.extent")


def parse_optimise(table) -> dict:
    """Validate an ``[optimise]`` table (keys as the ``jaxgear optimise`` options) and return it
    normalised: ``vars`` a list of names, ``torques`` ``[start, stop, n]`` (float, float, int),
    ``bounds`` ``{name: (lo, hi)}`` (E* for depths, Γ for extents), other keys as given.

    Raises:
        SchemaError: unknown key, objective, method or variable; torques not ``[start, stop, n]``
            with 0 < start < stop and an integer n >= 2; crossed bounds; ``lp_order`` outside
            [1, 64] or with an objective other than ``line_load_lp``.
    """
    w = "optimise"
    if not isinstance(table, dict):
        raise sc.fail("", "optimise", "must be a table", table)
    sc.check_keys(table, _OPTIMISE_KEYS, w)
    out: dict[str, Any] = {}
    if "objective" in table:
        out["objective"] = sc.choice(table, "objective", w, OBJECTIVES)
    if "reduce" in table:
        out["reduce"] = sc.choice(table, "reduce", w, ("max", "mean"))
    if "method" in table:
        out["method"] = sc.choice(table, "method", w, ("lbfgs", "adam"))
    if "max_iterations" in table:
        out["max_iterations"] = sc.number(
            table, "max_iterations", w, allowed="[1, 1e+06]", integer=True
        )

    if "lp_order" in table:
        out["lp_order"] = float(sc.number(table, "lp_order", w, allowed="[1, 64]"))
        if out.get("objective", "line_load_lp") != "line_load_lp":
            raise sc.fail(
                w,
                "lp_order",
                f"applies to objective = 'line_load_lp' only, not {out['objective']!r}",
                table["lp_order"],
            )

    def kind(name: str):
        parts = name.split(".")
        base = ".".join(parts[1:]) if parts[0] in ("pinion", "gear") else name
        return VARIABLES[base][1] if base in VARIABLES else None

    allowed_vars = f"{', '.join(VARIABLES)}, optionally prefixed 'pinion.' or 'gear.'"
    names = list(_DEFAULT_VARS)
    if "vars" in table:
        v = table["vars"]
        if isinstance(v, str):
            v = [x.strip() for x in v.split(",") if x.strip()]
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
        if out.get("objective", "robust_te_rms") != "robust_te_rms":
            raise sc.fail(
                w,
                "torques",
                f"applies to objective = 'robust_te_rms' only, not {out['objective']!r}",
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
