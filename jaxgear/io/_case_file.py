"""Case files (TOML, units in key names) and the embedded reference cases.

A case is read, checked against the schema as a whole (``[scene]`` and ``[optimise]`` included:
unknown keys are errors, every value is type and range checked in the file's units, one integer
rule), converted to SI and turned into a :class:`Case`; absurd but valid inputs then give a
:class:`CaseWarning`. Errors are :class:`fem_prep.schema.SchemaError` (a ``ValueError``) with a
one-line message such as ``[pinion] face_width_mm = -3: out of range, allowed > 0``. See README.md
for the schema.
"""

from __future__ import annotations

import math
import re
import warnings
from typing import Any, ClassVar, Literal

import pydantic

from fem_prep import schema as sc

from ._case import Case
from .._geometry import JAM, GearPair, Member
from ._deviations_table import parse_deviations
from ._bearings_table import read_bearings
from ._lubricant_table import read_lubricant
from ._modifications_table import parse_modifications
from .._contact_geometry import TheoreticalPath
from ._names import FOUNDATIONS, STIFFNESS_MODELS, contact_geometry_from_key, stiffness_from_name
from ._optimise_table import check_acoustic_tables, check_bearing_variables, parse_optimise
from ._plausibility import MIN_LINE_LOAD_N_PER_MM, CaseWarning, plausibility
from ._rating_material_table import MaterialRatingKeys
from ._rating_table import check_rating
from ._robust_table import parse_robust
from ._housing_table import HOUSING_BAND, check_housing_band, parse_housing
from ._scene_spec import SceneSpec
from ._scene_table import parse_scene
from ._sections import Section, number
from ._acoustics_table import AcousticsSection, check_band, parse_case_acoustics
from ._whine_table import (
    highest_order_frequency,
    lowest_order_frequency,
    WhineSection,
    order_frequency_range,
    parse_whine,
)

__all__ = [
    "check_member_size",
    "parse_case",
    "parse_material",
    "parse_mesh_settings",
    "parse_torque",
]

SchemaError = sc.SchemaError

#: a pair case file's keys (each table checked by its section or its reader)
_SCHEMA: dict[str, Any] = {
    "name": None,
    "pair": None,  # PairSection
    "pinion": None,  # PairMemberSection
    "gear": None,
    "material": None,  # MaterialSection
    "operating": None,  # OperatingSection
    "mesh": None,  # parse_mesh_settings
    "modifications": None,  # checked by parse_modifications
    "deviations": None,  # checked by parse_deviations
    "robust": None,  # checked by parse_robust (jaxgear robust)
    "scene": None,  # checked by parse_scene
    "optimise": None,  # checked by parse_optimise
    "rating": None,  # checked by check_rating (ISO 6336 load capacity)
    "lubricant": None,  # checked by parse_lubricant (film and sliding loss)
    "housing": None,  # checked by parse_housing (a flexible housing, docs/housing.md)
    "whine": None,  # checked by parse_whine (gear whine in the frequency domain)
    "acoustics": None,  # checked by parse_acoustics (the housing's radiated sound)
    "bearings": None,  # checked by read_bearings (the rolling bearings' modified life)
}
#: the case file's table-valued keys (all but its name)
_TABLES = tuple(k for k in _SCHEMA if k != "name")
# [mesh] keys read by some stiffness models only
_MODEL_KEYS = {
    "stiffness_per_length_N_per_mm_per_um": ("uniform",),
    "fe2d_size_um": ("fe2d",),
    "foundation": ("weber", "fe2d"),
}

# physical ranges of the pair (file units), checked before the geometry is computed
MODULE_RANGE_MM = "[0.01, 100]"  # watch gears to mill gears
PRESSURE_ANGLE_RANGE_DEG = "[10, 40]"  # below: undercut (z_min = 66 at 10°); above: pointed tips
MIN_FACE_WIDTH_MODULE = 0.1  # face width >= 0.1 m_n ...
MAX_FACE_WIDTH_MODULE = 100.0  # ... and <= 100 m_n (usual b/m_n: 6 to 40)
MAX_DEPTH_MODULE = 1.0  # modification and deviation depths: up to one normal module
CENTER_DISTANCE_TOL_MM = 1e-3  # a centre distance up to 1 µm below the zero-backlash one is it
MIN_SMOOTH_WIDTH_UM = 1e-4  # smooth contact width w: 0.1 nm ...
MAX_SMOOTH_WIDTH_MODULE = 0.01  # ... to 1 % of the module (the smooth TE is offset by ~ w)


# --------------------------------------------------------------------------------------------
# the typed tables (jaxgear.io._sections): keys, types and ranges in file units


class PairSection(Section):
    """A pair case's ``[pair]``: the normal module (mm), the normal pressure angle and the helix
    angle (deg; below 10° the involute undercuts all but very large gears, z_min = 2/sin²α = 66
    at 10°, above 40° standard teeth are pointed; the module spans watch gears to mill gears),
    the centre distance (mm; default the zero-backlash one)."""

    WHERE: ClassVar[str] = "pair"
    normal_module_mm: number(MODULE_RANGE_MM)
    normal_pressure_angle_deg: number(PRESSURE_ANGLE_RANGE_DEG)
    helix_angle_deg: number("[0, 45)") = 0.0
    center_distance_mm: number("(0, 1e+06]") | None = None


class MemberSection(Section):
    """A gear's own keys (a pair's ``[pinion]`` and ``[gear]``, a train's ``[[gears]]``
    entry): teeth, the tooth form's coefficients (of the normal module), face width and the
    blank (mm); a webbed blank (ISO 6336-1's gear blank factor C_R of the iso6336 stiffness)
    gives both ``web_thickness_mm`` and ``rim_thickness_mm``. :meth:`member` its
    :class:`~jaxgear.Member` (SI)."""

    WHERE: ClassVar[str] = "pinion"
    teeth: number("[5, 10000]", integer=True)
    profile_shift: number() = 0.0  # the geometry checks it
    addendum_coeff: number("(0, 3]") = 1.0
    dedendum_coeff: number("(0, 3]") = 1.25
    face_width_mm: number("> 0")
    fillet_radius_coeff: number(">= 0") = 0.25
    bore_radius_mm: number("> 0") | None = None
    web_thickness_mm: number("> 0") | None = None
    rim_thickness_mm: number("> 0") | None = None

    @pydantic.model_validator(mode="after")
    def _related(self, info):
        where = (info.context or {}).get("where", "")
        dedendum, fillet = self.dedendum_coeff, self.fillet_radius_coeff
        if not fillet < dedendum:
            if "fillet_radius_coeff" not in self.given:  # the default fillet: the dedendum
                raise sc.fail(where, "dedendum_coeff", f"out of range, allowed > {fillet:.6g} "
                              "(above the default fillet_radius_coeff; or give a smaller "
                              "fillet_radius_coeff)", dedendum)
            raise sc.fail(where, "fillet_radius_coeff", f"out of range, allowed [0, "
                          f"{dedendum:.6g}) (below dedendum_coeff)", fillet)
        if (self.web_thickness_mm is None) != (self.rim_thickness_mm is None):
            given, missing = ("web", "rim") if self.rim_thickness_mm is None else ("rim", "web")
            raise sc.fail(where, f"{missing}_thickness_mm", f"required with {given}_thickness_mm "
                          "(the gear blank factor C_R needs both; leave both out for a solid "
                          "blank)")
        return self

    def member(self, teeth: int | None = None, allowance_um: float = 0.0) -> Member:
        """The :class:`~jaxgear.Member` (SI) of these keys, of ``teeth`` where given (an
        internal gear's, negative), with a tooth thickness allowance (µm)."""
        mm = lambda v: None if v is None else v * 1e-3  # noqa: E731
        return Member(
            teeth=self.teeth if teeth is None else teeth,
            profile_shift=self.profile_shift,
            addendum_coeff=self.addendum_coeff,
            dedendum_coeff=self.dedendum_coeff,
            face_width=self.face_width_mm * 1e-3,
            fillet_radius_coeff=self.fillet_radius_coeff,
            bore_radius=mm(self.bore_radius_mm),
            web_thickness=mm(self.web_thickness_mm),
            rim_thickness=mm(self.rim_thickness_mm),
            tooth_thickness_allowance=allowance_um * 1e-6,
        )


class PairMemberSection(MemberSection):
    """A pair case's ``[pinion]`` or ``[gear]``: a gear's keys (:class:`MemberSection`) and its
    tooth thickness allowance (µm; backlash, the coast flanks: a train has none,
    docs/backlash.md)."""

    tooth_thickness_allowance_um: number("[-1e+04, 1e+04]") = 0.0

    def member(self, teeth: int | None = None, allowance_um: float | None = None) -> Member:
        """The :class:`~jaxgear.Member` (SI), with this gear's allowance."""
        allowance = self.tooth_thickness_allowance_um if allowance_um is None else allowance_um
        return super().member(teeth, allowance)


class MaterialSection(MaterialRatingKeys):
    """``[material]``: Young's modulus (GPa), Poisson's ratio, density (kg/m³), and the
    rating's keys (:class:`~jaxgear.io._rating_material_table.MaterialRatingKeys`, per gear: a
    number, a [pinion, gear] list or a train's table by gear name; read where a mesh is rated,
    refused without ``[rating]``)."""

    WHERE: ClassVar[str] = "material"
    youngs_modulus_GPa: number("[0.1, 10000]") = 210.0
    poisson_ratio: number("[0, 0.5)") = 0.3
    density_kg_m3: number("[100, 1e+05]") = 7800.0

    def material(self) -> tuple[float, float, float]:
        """(E Pa, ν, ρ kg/m³)."""
        return self.youngs_modulus_GPa * 1e9, self.poisson_ratio, self.density_kg_m3


class OperatingSection(Section):
    """``[operating]`` of a pair case: the pinion's torque (N·m; its range follows the pair:
    :func:`parse_torque`) and speed (rad/s); the rating's ``speed_rpm`` (1/min; read by
    :func:`~jaxgear.io._rating_table.rating_speed`, refused without ``[rating]``)."""

    WHERE: ClassVar[str] = "operating"
    torque_Nm: Any  # its range follows the pair (parse_torque)
    speed_rad_s: number("[0, 1e+05]") = 0.0
    speed_rpm: number("(0, 1e+06]") | None = None



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
    if name == "total contact ratio":
        return sc.SchemaError(
            f"[pinion]/[gear] addendum_coeff, face_width_mm, [pair] helix_angle_deg: total "
            f"contact ratio ε_γ = {sc.g6(value)}: out of range, allowed {allowed}"
        )
    clearance = re.match(
        r"tip-to-root clearance c\d \((pinion|gear) tip to (pinion|gear) root", name
    )
    if clearance:
        tip, root = clearance.groups()
        return sc.SchemaError(
            f"[{tip}] addendum_coeff = {sc.fmt(file_value(tip, 'addendum_coeff'))}, [{tip}] "
            f"profile_shift = {sc.fmt(file_value(tip, 'profile_shift'))}: the {tip} tip cuts "
            f"into the {root} root (tip-to-root clearance {float(value) * 1e3:.4g} mm), allowed "
            f"a clearance >= 0 (lower [{tip}] addendum_coeff or raise [{root}] dedendum_coeff)"
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


def parse_torque(op: dict, pair: GearPair) -> float:
    """``[operating] torque_Nm`` (N·m; ``op`` the table as the file gives it): positive and at
    least the torque of a line load F_n/b = ``MIN_LINE_LOAD_N_PER_MM`` on ``pair`` (below, the
    deflections are round-off)."""
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
    """``[material]`` (:class:`MaterialSection`): Young's modulus (Pa), Poisson's ratio,
    density (kg/m³)."""
    return MaterialSection.of_file(data).material()


#: ``[mesh] extended_contact`` when a case file does not say (docs/extended-contact.md, "Where it
#: is on"); a pair case with backlash (coast flanks) resolves it to False, an explicit true there
#: is refused
EXTENDED_CONTACT_DEFAULT = True


def _module_range(key: str, v: Any, module: float) -> None:
    """Refuse a ``[mesh]`` width outside its range for the normal module ``module`` (m): the
    smooth contact width up to 1 % of it, fe2d's element size m_n/100 to m_n; a value that is
    not a finite number is left to its type."""
    mn_um = module * 1e6
    if key == "smooth_width_um":
        allowed = f"[{MIN_SMOOTH_WIDTH_UM:g}, {MAX_SMOOTH_WIDTH_MODULE * mn_um:.6g}]"
        note = f" (µm; up to {100 * MAX_SMOOTH_WIDTH_MODULE:g} % of the normal module)"
    else:
        allowed, note = f"[{mn_um / 100:.6g}, {mn_um:.6g}]", _FE2D_NOTE
    if sc.finite(v) and v not in sc.interval(allowed):
        raise sc.fail("mesh", key, f"out of range, allowed {allowed}{note}", v)


_FE2D_NOTE = " (m_n/100 to m_n; default m_n/6)"
_FOUNDATION_WORDS = "allowed 'weber', 'sainsot', 'none' (or true = 'weber', false = 'none')"


class MeshSection(Section):
    """``[mesh]``: the mesh model (``stiffness``: a model's name, default fe2d: Weber's
    half-plane foundation is 16–52 % too stiff against it, docs/stiffness.md) and its settings
    (a key another model would ignore is refused: :data:`_MODEL_KEYS`; ``uniform`` needs its
    stiffness per length), slices, positions per pitch, the smooth contact width and fe2d's
    element size (their ranges follow the normal module, given as the context's
    ``normal_module``, m), the foundation (a name, or the old boolean: true = "weber", false =
    "none") and contact beyond the path. :meth:`settings` the :class:`Case` fields."""

    WHERE: ClassVar[str] = "mesh"
    stiffness: Literal[STIFFNESS_MODELS] = "fe2d"
    stiffness_per_length_N_per_mm_per_um: number("(0, 1e+06]") | None = None
    slices: number("[1, 10000]", integer=True) = 40
    positions_per_pitch: number("[2, 100000]", integer=True) = 64
    smooth_width_um: number(f">= {MIN_SMOOTH_WIDTH_UM:g}", note=(
        f" (µm; up to {100 * MAX_SMOOTH_WIDTH_MODULE:g} % of the normal module)")) = 0.1
    fe2d_size_um: number("> 0", note=_FE2D_NOTE) | None = None
    foundation: Literal[tuple(FOUNDATIONS)] = "weber"  # or the old boolean (_words)
    extended_contact: bool = EXTENDED_CONTACT_DEFAULT

    @pydantic.field_validator("smooth_width_um", "fe2d_size_um", "foundation", mode="before")
    @classmethod
    def _words(cls, v, info):
        """The widths' ranges of the normal module; the foundation's names in their words, the
        old boolean as its name (true "weber", false "none")."""
        if info.field_name == "foundation":
            if isinstance(v, bool):
                return "weber" if v else "none"
            if not isinstance(v, str) or v not in FOUNDATIONS:
                raise sc.fail("mesh", "foundation", _FOUNDATION_WORDS, v)
            return v
        module = (info.context or {}).get("normal_module")
        if module is not None:
            _module_range(info.field_name, v, module)
        return v

    @pydantic.model_validator(mode="after")
    def _related(self):
        for key, models in _MODEL_KEYS.items():  # a key of another model: silently ignored
            if key in self.given and self.stiffness not in models:
                raise sc.fail("mesh", key, f"belongs to stiffness = "
                              f"{' or '.join(repr(x) for x in models)}, not {self.stiffness!r} "
                              "(remove it or change the model)", getattr(self, key))
        if self.stiffness == "uniform" and self.stiffness_per_length_N_per_mm_per_um is None:
            raise sc.fail("mesh", "stiffness_per_length_N_per_mm_per_um", "missing required key")
        return self

    def settings(self) -> dict:
        """The :class:`Case` fields of the mesh model: its stiffness model (SI), slices,
        positions per pitch, smooth width (m) and contact geometry."""
        k0, size = self.stiffness_per_length_N_per_mm_per_um, self.fe2d_size_um
        return {
            "stiffness": stiffness_from_name(
                self.stiffness, uniform_k0=None if k0 is None else k0 * 1e9,
                foundation=self.foundation, fe2d_size=None if size is None else size * 1e-6,
            ),
            "slices": self.slices,
            "positions_per_pitch": self.positions_per_pitch,
            "smooth_width": self.smooth_width_um * 1e-6,
            # contact beyond the theoretical path (docs/extended-contact.md)
            "contact_geometry": contact_geometry_from_key(self.extended_contact),
        }


#: ``[mesh]``'s keys
MESH_TABLE_KEYS = set(MeshSection.model_fields)


def parse_mesh_settings(data: dict, normal_module: float) -> dict:
    """``[mesh]`` (:class:`MeshSection`): the :class:`Case` fields of the mesh model (stiffness
    model and its settings, slices, positions per pitch, smooth width); ``normal_module`` (m)
    scales the ranges of the widths (the smallest module of a train)."""
    return MeshSection.of_file(data, context={"normal_module": normal_module}).settings()


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
    sc.subtables(data, _TABLES, "")  # every table a table before its reader takes it
    name = sc.name(data, "name", "", default_name)
    p = PairSection.of_file(data, required=True)  # ranges before the geometry: errors name
    members = {tag: PairMemberSection.of_file(data, tag, required=True)  # the culprit
               for tag in ("pinion", "gear")}
    material = MaterialSection.of_file(data)
    op = OperatingSection.of_file(data, required=True)
    sc.subtable(data, "mesh", "", MESH_TABLE_KEYS)
    pinion, gear = (members[tag].member() for tag in ("pinion", "gear"))
    module, alpha, cd = p.normal_module_mm, p.normal_pressure_angle_deg, p.center_distance_mm
    beta = p.helix_angle_deg
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
        check_member_size(members[tag].table(), tag, member, module, alpha)
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
                data["pair"]["center_distance_mm"],
            )
        if cd is not None and cd > a0_mm:  # within the tolerance: the zero-backlash distance
            pair = GearPair(**geometry, center_distance=cd * 1e-3)
    except (ValueError, ArithmeticError) as err:
        if isinstance(err, sc.SchemaError):
            raise
        raise _geometry_error(err, data) from None
    E, nu, rho = material.material()
    torque = parse_torque(data["operating"], pair)
    rating = check_rating(data, pair, (E, nu, rho))
    speed = op.speed_rad_s
    lubricant = read_lubricant(data)
    whine = WhineSection.read(data["whine"]) if "whine" in data else None
    acoustics = parse_case_acoustics(data) if "acoustics" in data else None
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
    housing = case_housing(data, scene, base_dir, (E, nu, rho), teeth=(pair.pinion.teeth,))
    bearings = read_bearings(data, scene, lubricant)
    optimise = parse_optimise(data["optimise"]) if "optimise" in data else None
    check_acoustic_tables(data, optimise)
    check_bearing_variables(optimise, {} if scene is None or not scene.lumped else {
        "pinion_shaft": scene.pinion_shaft, "gear_shaft": scene.gear_shaft})
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
        # contact beyond the path is not modelled with the coast flanks: the default resolves
        # to the theoretical path there; an explicit true is refused (docs/extended-contact.md)
        if (
            "extended_contact" in data.get("mesh", {})
            and mesh["contact_geometry"].reaches_beyond_path
        ):
            raise sc.fail(
                "mesh",
                "extended_contact",
                "with backlash (coast flanks; a tooth_thickness_allowance_um) is not modelled: "
                "set it false or drop the allowances",
                data["mesh"]["extended_contact"],
            )
        mesh["contact_geometry"] = TheoreticalPath()
    case = Case.of_pair(
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
        housing=housing,
        optimise=optimise,
        raw=data,
        whine=whine,
        acoustics=acoustics,
        lubricant=lubricant,
        bearings=bearings,
        rating=rating,
    )
    for text in plausibility(case):
        warnings.warn(text, CaseWarning, stacklevel=2)
    return case


def case_housing(data: dict, scene, base_dir, material, *, pair: bool = True, teeth=(),
                 span: int = 1, names=None):
    """``[housing]`` of a case (:func:`parse_housing`), or None; it needs a lumped 3D scene,
    whose bearings it carries, with condensed bodies (a hybrid scene) too
    (:meth:`Case.hybrid_housing`). Also refuses ``[whine]`` with condensed bodies where the
    harmonic balance does not take them (a train's, ``pair`` False, or with a ``[housing]``;
    a pair's runs in the twisted coordinates of its cyclic bodies), before anything is
    built. ``teeth``: each mesh's teeth per input turn and ``span`` the span in first-mesh
    periods (``names`` the meshes'), from which a table without a cut-off takes it from ``[whine]``
    (:func:`~jaxgear.io._whine_table.highest_order_frequency`)."""
    if "whine" in data and scene is not None and scene.hybrid and (not pair or "housing" in data):
        where = "with a [housing]" if pair else "of a train"
        raise sc.fail(
            "whine",
            None,
            f"the gear whine (harmonic balance) of condensed bodies {where} is not there yet: "
            "allowed a pair with condensed bodies and no [housing], or rigid gears (drop "
            "[whine]; the time-domain sweep, jaxgear sweep, takes them)",
        )
    if "housing" not in data:
        return None
    table = sc.subtable(data, "housing", "")  # checked by parse_housing
    kind = (scene or SceneSpec()).kind(pair)  # no [scene]: the torsional default
    if not kind.takes_housing:
        raise sc.fail(
            "housing",
            None,
            f"the scene kind {kind.__name__} takes no housing (a housing carries the bearings "
            "of a lumped 3D scene): allowed with [scene] model = 'lumped3d' (rigid gears or "
            "condensed bodies)",
        )
    if "whine" not in data:
        return parse_housing(table, base_dir, material, None)
    inputs = parse_whine(data["whine"])
    spec = parse_housing(table, base_dir, material,
                         highest_order_frequency(inputs, teeth, span, names))
    check_housing_band(spec, lowest_order_frequency(inputs, teeth, span, names))
    if "acoustics" in data:  # its band meets the orders (before any work)
        lo, hi = order_frequency_range(inputs, teeth, span)
        check_band(AcousticsSection.read(data["acoustics"]),
                   (lo, min(hi, spec.cutoff / HOUSING_BAND)))
    return spec


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
