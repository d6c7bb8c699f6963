"""The ``[scene]`` table of a case (docs/dynamics.md).

``[scene]`` selects and parameterises the dynamic model (units in key names, SI after parsing):

.. code-block:: toml

    [scene]
    model = "torsional"                  # or "lumped3d" (shafts + bearings, see docs/dynamics.md)
    reduction = "none"                   # or "relative": the 1-DOF relative approach
    pinion_inertia_kg_m2 = 2.4e-4        # default: solid disc, tip radius × face width × density
    gear_inertia_kg_m2 = 2.3e-3
    motor_inertia_kg_m2 = 1e-2           # optional, needs motor_shaft_stiffness_Nm_per_rad
    motor_shaft_stiffness_Nm_per_rad = 2e4
    load_inertia_kg_m2 = 5e-2            # optional, needs load_shaft_stiffness_Nm_per_rad
    load_shaft_stiffness_Nm_per_rad = 5e4
    [scene.damping]
    model = "composite"                  # "composite" (2.36) | "modal" (2.35) | "rayleigh" (2.34) | "none"
    mesh_ratio = 0.07                    # composite: ξ_i = mesh_ratio e_i + structure_ratio (1 − e_i)
    structure_ratio = 0.01
    ratio = 0.05                         # modal: one ξ for every mode
    alpha_per_s = 0.0                    # rayleigh: C = α M + β K̄
    beta_s = 0.0
    [scene.integration]
    solver = "newmark"                   # or a diffrax solver: tsit5, dopri5, kvaerno5, ...
    contact = "exact"                    # or "smooth" (width: [mesh] smooth_width_um)
    steps_per_period = "auto"           # or an integer: time steps per mesh period (see docs)
    periods = "auto"                     # or an integer: mesh periods per speed (see docs)
    keep_periods = 4
    rtol = 1e-6                          # diffrax PID controller (scaled state)
    atol = 1e-6
    rotating_frame = false               # hybrid scenes: the turning bodies' Coriolis, spin
                                         # softening and stress stiffening (docs/hybrid.md)
    modal_basis = false                  # hybrid scenes: an integer m integrates Newmark in the
                                         # modal basis, m modes + static correction (docs/hybrid.md)

A ``lumped3d`` shaft's ``bearings`` are tables ``{ position_mm, radial_N_per_um, axial_N_per_um,
tilt_Nm_per_rad }`` or ``{ position_mm, stiffness_matrix_SI }`` (6×6, not both), each with an
optional ``damping_matrix_SI`` (6×6): SI per DOF pair, DOF order ux, uy, uz, rx, ry, rz
(docs/dynamics.md). A rolling bearing from its geometry (a pair of rigid gears,
docs/bearings.md) is ``{ position_mm, catalogue = "6205" }`` (an embedded bearing, optionally
``clearance_um``) or ``{ position_mm, kind = "deep_groove_ball", bore_mm, outer_diameter_mm,
width_mm, balls, ball_diameter_mm, pitch_diameter_mm, clearance_um, ... }`` (:data:`ROLLING_KINDS`;
rollers: ``rollers``, ``roller_diameter_mm``, ``roller_length_mm``, and optionally ``crown_um``,
the rollers' logarithmic crown (cylindrical and tapered, a pair's rows, their catalogue entries
too; at most the roller diameter/100); angular contact, tapered and spherical:
``contact_angle_deg``; a spherical roller bearing's ``rollers`` are per row, of two;
a pair of tapered roller bearings facing both ways, ``kind = "tapered_roller_pair"``, one row's
geometry, ``arrangement = "O"`` or ``"X"``, ``end_play_um`` in place of ``clearance_um``
(negative: a preload) and ``row_spacing_mm``, at ``position_mm`` the pair's centre; or
``catalogue = "32060 X"``, a tapered roller entry, with ``arrangement`` and optionally
``end_play_um``, ``row_spacing_mm``: the pair of the entry's rows); its
stiffness is the one at the operating point of the case's
quasi-static solve. For its life, ``dynamic_rating_kN`` and ``static_rating_kN`` (the maker's
C and C0, where the catalogue entry has none; a deep groove ball bearing also ``iso281_f0``,
the catalogue's f0 of ISO 281's X and Y table); ``fatigue_limit_kN``, the maker's fatigue load
limit C_u for ISO 281's modified life (default: ISO 281's estimate from C0).
"""

from __future__ import annotations

import math
import os
from typing import Any, ClassVar, Literal

import pydantic

import fem_prep
from fem_prep import schema as sc

from ..bearings import (
    CATALOGUE,
    AngularContactBall,
    CylindricalRoller,
    DeepGrooveBall,
    SphericalRoller,
    TaperedRoller,
    TaperedRollerPair,
    catalogue,
)
from ..dynamics import DIFFRAX_SOLVERS
from ..scenes import Bearing, ShaftSpec, bearing_matrix
from ._scene_spec import SceneSpec
from ._sections import Section, Text, number

__all__ = ["parse_scene"]

#: two radial bearings without tilt stiffness: at least 1 % of the shaft length apart
MIN_BEARING_SPAN = 0.01
#: a bearing's diagonal stiffness keys: (the least stiffness above 0 (free), the most), file units
_DIAGONAL = {"radial_N_per_um": (1e-3, 1e9), "axial_N_per_um": (1e-3, 1e9),
             "tilt_Nm_per_rad": (1.0, 1e15)}
_ON_SHAFT = " (not beyond the shaft length)"


def where_of(info) -> str:
    """The table a validator checks (:meth:`Section.read`'s ``where``)."""
    return (info.context or {}).get("where", "")


def on_shaft(key: str, v: float, length_mm: float | None, where: str) -> float:
    """``v`` (mm), a position along a shaft of ``length_mm`` (None: not known, the length is
    refused itself), or the one line that it lies beyond the shaft (the test against the length
    as given, its words to 6 digits: a position at the end of a length of more digits is on the
    shaft)."""
    if length_mm is not None and not 0 <= v <= length_mm:
        within = sc.interval(f"[0, {length_mm:.6g}]")
        raise sc.fail(where, key, f"out of range, allowed {within}{_ON_SHAFT}", v)
    return v


#: the type of a position along a shaft (mm; within its length: :func:`on_shaft`)
ON_SHAFT_MM = number(note=" (within the shaft: [0, length_mm])")


#: a case file's rolling bearing kinds (``kind = "..."``): the names map to the kinds here only
ROLLING_KINDS = {
    "deep_groove_ball": DeepGrooveBall,
    "angular_contact_ball": AngularContactBall,
    "cylindrical_roller": CylindricalRoller,
    "tapered_roller": TaperedRoller,
    "spherical_roller": SphericalRoller,
    "tapered_roller_pair": TaperedRollerPair,
}
#: the kinds that take ``crown_um`` (their contract's ``crown_field``), in the messages
_CROWNED = ", ".join(n for n, k in ROLLING_KINDS.items() if k.crown_field is not None)
#: each kind's keys beyond the boundary dimensions (bore, outer diameter, width) and clearance
_ELEMENT_KEYS = {
    "deep_groove_ball": ("balls", "ball_diameter_mm", "pitch_diameter_mm"),
    "angular_contact_ball": ("balls", "ball_diameter_mm", "pitch_diameter_mm",
                             "contact_angle_deg"),
    "cylindrical_roller": ("rollers", "roller_diameter_mm", "roller_length_mm",
                           "pitch_diameter_mm"),
    "tapered_roller": ("rollers", "roller_diameter_mm", "roller_length_mm", "pitch_diameter_mm",
                       "contact_angle_deg"),
    # rollers per row (two rows)
    "spherical_roller": ("rollers", "roller_diameter_mm", "roller_length_mm", "pitch_diameter_mm",
                         "contact_angle_deg"),
    # one row's geometry (the two rows alike), and how they face
    "tapered_roller_pair": ("rollers", "roller_diameter_mm", "roller_length_mm",
                            "pitch_diameter_mm", "contact_angle_deg", "arrangement"),
}
_BALL_OPTIONAL = ("inner_conformity", "outer_conformity")
#: a tapered roller pair's optional keys: its axial end play in place of the rows' clearance
_PAIR_OPTIONAL = ("end_play_um", "row_spacing_mm")
#: the keys that make a tapered roller row's ``catalogue`` entry a pair of its rows
_CATALOGUE_PAIR = ("arrangement", *_PAIR_OPTIONAL)
_GEOMETRY = ("bore_mm", "outer_diameter_mm", "width_mm", "balls", "ball_diameter_mm",
             "rollers", "roller_diameter_mm", "roller_length_mm", "pitch_diameter_mm",
             "contact_angle_deg", "inner_conformity", "outer_conformity", "arrangement",
             *_PAIR_OPTIONAL)
_LINEAR = (*_DIAGONAL, "stiffness_matrix_SI")
#: a rolling bearing's load ratings (its life): C and C0 in kN, ISO 281's f0 (deep groove)
_RATINGS = ("dynamic_rating_kN", "static_rating_kN", "iso281_f0")


class BearingSection(Section):
    """A ``lumped3d`` shaft's bearing (module docstring): its position on the shaft (mm, within
    the shaft's length, the context's ``length_mm``) and its stiffness: diagonal (radial and
    axial N/µm, tilt N·m/rad; each 0, free, or at least a floor: :data:`_DIAGONAL`; defaults
    200, 0, 0), a 6×6 ``stiffness_matrix_SI``, or a rolling bearing from its geometry
    (``catalogue``, an embedded designation, or ``kind`` (:data:`ROLLING_KINDS`) with its
    geometry in mm, its rolling elements' count, its contact angle in degrees, its groove
    conformities, a diametral clearance and a roller kind's logarithmic crown in µm; a
    tapered roller entry with
    ``arrangement``, ``end_play_um``, ``row_spacing_mm``: the pair of its rows,
    :meth:`~jaxgear.bearings.TaperedRollerPair.of`); one form only. An optional 6×6
    ``damping_matrix_SI`` (:func:`jaxgear.scenes.bearing_matrix` checks the matrices).
    :meth:`bearing` the :class:`jaxgear.scenes.Bearing` (SI)."""

    WHERE: ClassVar[str] = "scene.pinion_shaft.bearings"
    position_mm: ON_SHAFT_MM
    radial_N_per_um: number("[0, 1e+09]") | None = pydantic.Field(
        None, json_schema_extra={"default": "200"})
    axial_N_per_um: number("[0, 1e+09]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0"})
    tilt_Nm_per_rad: number("[0, 1e+15]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0"})
    stiffness_matrix_SI: Any = None
    damping_matrix_SI: Any = None
    catalogue: Literal[tuple(CATALOGUE)] | None = None
    kind: Literal[tuple(ROLLING_KINDS)] | None = None
    bore_mm: number("[1, 2000]") | None = None
    outer_diameter_mm: number("(1, 3000]") | None = None
    width_mm: number("[0.5, 1000]") | None = None
    balls: number("[3, 1000]", integer=True) | None = None
    rollers: number("[3, 1000]", integer=True) | None = None
    ball_diameter_mm: number("(0, 500]") | None = None
    roller_diameter_mm: number("(0, 500]") | None = None
    roller_length_mm: number("(0, 1000]") | None = None
    pitch_diameter_mm: number("(1, 3000]") | None = None
    contact_angle_deg: number("(0, 90)") | None = None
    inner_conformity: number("(0.5, 0.6]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0.52"})
    outer_conformity: number("(0.5, 0.6]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0.52"})
    clearance_um: number("[-100, 1000]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0 (catalogue: the entry's)"})
    crown_um: number("[0, 5000]") | None = pydantic.Field(
        None, json_schema_extra={"default": "none (straight rollers)"})
    arrangement: Literal["O", "X"] | None = None
    end_play_um: number("[-1000, 10000]") | None = pydantic.Field(
        None, json_schema_extra={"default": "0"})
    row_spacing_mm: number("(0, 2000]") | None = pydantic.Field(
        None, json_schema_extra={"default": "width_mm"})
    dynamic_rating_kN: number("(0, 1e+05]") | None = None
    static_rating_kN: number("(0, 1e+05]") | None = None
    iso281_f0: number("[5, 30]") | None = None
    fatigue_limit_kN: number("(0, 1e+05]") | None = pydantic.Field(
        None, json_schema_extra={"default": "ISO 281's estimate from C0"})

    @pydantic.field_validator("position_mm")
    @classmethod
    def _on_shaft(cls, v, info):
        return on_shaft("position_mm", v, (info.context or {}).get("length_mm"), where_of(info))

    @pydantic.field_validator(*_DIAGONAL)
    @classmethod
    def _free_or_stiff(cls, v, info):
        """0 (free in that direction) or at least the key's floor."""
        lo, hi = _DIAGONAL[info.field_name]
        if 0 < v < lo:
            raise sc.fail(where_of(info), info.field_name,
                          f"out of range, allowed 0 (free) or [{lo:g}, {hi:g}]", v)
        return v

    @pydantic.field_validator("stiffness_matrix_SI", "damping_matrix_SI")
    @classmethod
    def _matrix(cls, v, info):
        try:
            bearing_matrix(v)
        except ValueError as err:
            # a malformed value is shown; the other errors name the offending entries themselves
            shown = v if str(err).startswith("must be") else sc.MISSING
            raise sc.fail(where_of(info), info.field_name, str(err), shown) from None
        return v

    @pydantic.model_validator(mode="after")
    def _one_form(self, info):
        where = where_of(info)
        both = [key for key in _DIAGONAL if key in self.given]
        if "stiffness_matrix_SI" in self.given and both:
            raise sc.fail(
                where,
                "stiffness_matrix_SI",
                f"give either {'/'.join(_DIAGONAL)} or stiffness_matrix_SI, not both "
                f"(the matrix is the whole stiffness; remove {', '.join(both)})",
            )
        rolling = [k for k in ("catalogue", "kind") if k in self.given]
        if not rolling:
            extra = [k for k in (*_GEOMETRY, "clearance_um", "crown_um", *_RATINGS,
                                 "fatigue_limit_kN") if k in self.given]
            if extra:
                raise sc.fail(where, extra[0], "is a rolling bearing's key: allowed with "
                              "catalogue or kind (a bearing from its geometry)")
            return self
        linear = [k for k in _LINEAR if k in self.given]
        if len(rolling) == 2 or linear:
            other = "kind" if len(rolling) == 2 else linear[0]
            raise sc.fail(where, rolling[0], f"give one stiffness form, a linear one "
                          f"({', '.join(_LINEAR)}), catalogue or kind: remove {other}")
        if self.catalogue is not None:
            self._check_catalogue(where)
            rated = [k for k in _RATINGS if k in self.given]
            if rated and CATALOGUE[self.catalogue][1].get("dynamic_rating") is not None:
                raise sc.fail(where, rated[0], f"not with catalogue = {self.catalogue!r} (the "
                              "entry's ratings): allowed where the entry has no C")
        else:
            self._check_geometry(where)
        self._check_ratings(where)
        self.rolling(where)  # whatever the kind still refuses (its own line, in SI)
        return self

    def _check_catalogue(self, where: str) -> None:
        """A ``catalogue`` entry's keys: its geometry is the entry's; a tapered roller row's
        entry may be a pair of its rows (``arrangement``, optionally ``end_play_um`` and
        ``row_spacing_mm``, checked against the entry's roller and width in the file's units);
        one line each."""
        kind, entry, _ = CATALOGUE[self.catalogue]
        own = (*_CATALOGUE_PAIR, "clearance_um") if kind is TaperedRoller else ("clearance_um",)
        self._check_crown(where, kind, entry["element_diameter"] * 1e3,
                          f"catalogue = {self.catalogue!r}")
        for key in _GEOMETRY:
            if key in self.given and key in _CATALOGUE_PAIR and key not in own:
                tapered = [k for k, v in CATALOGUE.items() if v[0] is TaperedRoller]
                raise sc.fail(where, key, f"not with catalogue = {self.catalogue!r} (a "
                              f"{kind.__name__}): allowed with a tapered roller entry "
                              f"({', '.join(map(repr, tapered))}), a pair of its rows",
                              getattr(self, key))
            if key in self.given and key not in own:
                raise sc.fail(where, key, f"not with catalogue = {self.catalogue!r} (the "
                              f"entry's geometry): allowed {', '.join(own)} beside it")
        if self.arrangement is None:
            for key in _PAIR_OPTIONAL:
                if key in self.given:
                    raise sc.fail(where, key, f"not without arrangement: allowed with "
                                  f"catalogue = {self.catalogue!r} and arrangement = 'O' or "
                                  "'X' (a pair of the entry's rows)", getattr(self, key))
            return
        if "clearance_um" in self.given:
            raise sc.fail(where, "clearance_um", "not with arrangement (a pair of the entry's "
                          "rows): allowed end_play_um, which stands in for the rows' clearance",
                          self.clearance_um)
        self._check_pair(where, entry["element_diameter"] * 1e3,
                         math.degrees(entry["contact_angle"]), entry["width"] * 1e3)

    def _check_ratings(self, where: str) -> None:
        """The ratings given together: C and C0 (ISO 281's life and its fatigue load limit
        read both) and a deep groove ball bearing's f0 (its X and Y table); f0 on another kind
        refused."""
        given = [k for k in _RATINGS if k in self.given]
        kind = (ROLLING_KINDS[self.kind] if self.catalogue is None
                else CATALOGUE[self.catalogue][0])
        deep = issubclass(kind, DeepGrooveBall)  # ISO 281's f0 table: radial ball bearings
        if "iso281_f0" in self.given and not deep:
            raise sc.fail(where, "iso281_f0", "not a key of this kind: ISO 281's f0 is a deep "
                          "groove ball bearing's")
        needed = ("dynamic_rating_kN", "static_rating_kN", *(("iso281_f0",) if deep else ()))
        for key in needed:
            if given and key not in self.given:
                raise sc.fail(where, key, f"missing: a rating gives {', '.join(needed)} "
                              "together (ISO 281's life)")
        if self.fatigue_limit_kN is not None:
            self._check_fatigue_limit(where)

    def _check_fatigue_limit(self, where: str) -> None:
        """The maker's C_u: with a C to modify (the entry's or ``dynamic_rating_kN``) and
        below C0 (ISO 281's C_u is the load of its fatigue stress, 1500 MPa, C0's 4000 to
        4200 MPa)."""
        entry = {} if self.catalogue is None else CATALOGUE[self.catalogue][1]
        C0 = (self.static_rating_kN if self.static_rating_kN is not None
              else None if entry.get("static_rating") is None else entry["static_rating"] / 1e3)
        if self.dynamic_rating_kN is None and entry.get("dynamic_rating") is None:
            raise sc.fail(where, "fatigue_limit_kN", "not read without a C: allowed with "
                          "dynamic_rating_kN (or a catalogue entry with its ratings), the life "
                          "it modifies")
        if C0 is not None and not self.fatigue_limit_kN < C0:
            raise sc.fail(where, "fatigue_limit_kN", f"out of range, allowed (0, {C0:.6g}) "
                          "(below static_rating_kN C0: the fatigue load limit is the load of "
                          "ISO 281's 1500 MPa, C0 that of 4000-4200 MPa)", self.fatigue_limit_kN)

    def _check_geometry(self, where: str) -> None:
        """A ``kind``'s keys: its own given, the others refused, the relations between them
        in the file's units (one line each)."""
        own = ("bore_mm", "outer_diameter_mm", "width_mm", *_ELEMENT_KEYS[self.kind])
        pair = self.kind == "tapered_roller_pair"
        optional = (_BALL_OPTIONAL if "balls" in own else
                    _PAIR_OPTIONAL if pair else ()) + (() if pair else ("clearance_um",))
        for key in (*_GEOMETRY, "clearance_um"):
            if key in self.given and key not in own + optional:
                raise sc.fail(where, key, f"not a key of kind = {self.kind!r}: allowed "
                              f"{', '.join(own + optional)}")
        for key in own:
            if key not in self.given:
                raise sc.fail(where, key, f"missing: kind = {self.kind!r} needs "
                              f"{', '.join(own)}")
        if "roller_diameter_mm" in own:
            self._check_crown(where, ROLLING_KINDS[self.kind], self.roller_diameter_mm,
                              f"kind = {self.kind!r}")
        elif "crown_um" in self.given:
            raise sc.fail(where, "crown_um", f"not a key of kind = {self.kind!r}: allowed on "
                          f"a roller kind that takes a crown ({_CROWNED})", self.crown_um)
        d, D = self.bore_mm, self.outer_diameter_mm
        if not D > d:
            raise sc.fail(where, "outer_diameter_mm", f"out of range, allowed > bore_mm = "
                          f"{d:g}", D)
        word = "ball" if "balls" in own else "roller"
        size = getattr(self, f"{word}_diameter_mm")
        section = 0.5 * (D - d)
        if not size < section:
            raise sc.fail(where, f"{word}_diameter_mm", f"out of range, allowed < "
                          f"(outer_diameter_mm - bore_mm)/2 = {section:.6g} (inside the ring "
                          "section)", size)
        dm = self.pitch_diameter_mm
        if not d + size < dm < D - size:
            raise sc.fail(where, "pitch_diameter_mm", f"out of range, allowed ({d + size:.6g}, "
                          f"{D - size:.6g}) (bore_mm + {word}_diameter_mm to outer_diameter_mm "
                          f"- {word}_diameter_mm)", dm)
        count = getattr(self, f"{word}s")
        most = int(math.pi * dm / size)
        if count > most:
            raise sc.fail(where, f"{word}s", f"out of range, allowed <= pi pitch_diameter_mm / "
                          f"{word}_diameter_mm = {most} (they fit on the pitch circle)", count)
        if word == "roller" and not self.roller_length_mm <= self.width_mm:
            raise sc.fail(where, "roller_length_mm", f"out of range, allowed <= width_mm = "
                          f"{self.width_mm:g}", self.roller_length_mm)
        if self.kind == "spherical_roller":
            if not self.contact_angle_deg < 45.0:
                raise sc.fail(where, "contact_angle_deg", "out of range, allowed (0, 45) deg "
                              "(a spherical roller bearing's rows)", self.contact_angle_deg)
            room = self.width_mm / (2.0 * math.cos(math.radians(self.contact_angle_deg)))
            if not self.roller_length_mm <= room:
                raise sc.fail(where, "roller_length_mm", f"out of range, allowed <= width_mm / "
                              f"(2 cos contact_angle_deg) = {room:.6g} (two rows side by side "
                              "within the width)", self.roller_length_mm)
        if pair:
            self._check_pair(where, size, self.contact_angle_deg, self.width_mm)
        if self.clearance_um is not None:
            conformity = sum(getattr(self, k) or 0.52 for k in _BALL_OPTIONAL) - 1.0
            top = size * 1e3
            if self.kind == "deep_groove_ball":
                top = min(top, 2e3 * conformity * size)
            lo = -10.0 * size  # -D/100, in µm
            if not lo <= self.clearance_um < top:
                extra = " and 2 (f_i + f_o - 1) ball_diameter_mm" if top < size * 1e3 else ""
                raise sc.fail(where, "clearance_um", f"out of range, allowed [{lo:.6g}, "
                              f"{top:.6g}) µm (below the {word} diameter{extra}; negative: a "
                              f"preload down to -{word}_diameter_mm/100)", self.clearance_um)

    def _check_crown(self, where: str, kind: type, size: float, what: str) -> None:
        """``crown_um``: on a kind that declares ``crown_field`` only, at most the roller
        diameter ``size`` (mm) / 100 (the kinds' range, in µm); ``what`` the kind's words."""
        if self.crown_um is None:
            return
        if kind.crown_field is None:
            raise sc.fail(where, "crown_um", f"not with {what} (a {kind.__name__}, no crown): "
                          f"allowed on a roller kind that takes a crown ({_CROWNED}, or their "
                          "catalogue entries)", self.crown_um)
        top = 10.0 * size  # D_w / 100, in µm
        if not self.crown_um <= top:
            raise sc.fail(where, "crown_um", f"out of range, allowed [0, {top:.6g}] µm (the "
                          "logarithmic crown's scale, at most the roller diameter/100; ISO/TS "
                          "16281: 0.35 to 0.45 x the roller diameter in mm)", self.crown_um)

    def _check_pair(self, where: str, size: float, angle: float, width: float) -> None:
        """A tapered roller pair's end play (the rows' clearance end_play tan α within the
        roller's range) and row spacing (the rows side by side at least), in the file's
        units: ``size`` the roller diameter (mm), ``angle`` α (deg), ``width`` a row's (mm)."""
        t = math.tan(math.radians(angle))
        if self.end_play_um is not None:
            lo, top = -10.0 * size / t, 1e3 * size / t
            if not lo <= self.end_play_um < top:
                raise sc.fail(where, "end_play_um", f"out of range, allowed [{lo:.6g}, "
                              f"{top:.6g}) µm (the rows' diametral clearance, end play x tan "
                              "contact_angle_deg, from -1 % of the roller diameter to below it; "
                              "negative: a preload)", self.end_play_um)
        if self.row_spacing_mm is not None and not self.row_spacing_mm >= width:
            raise sc.fail(where, "row_spacing_mm", f"out of range, allowed >= width_mm = "
                          f"{width:g} (the rows' mid-planes: side by side at least)",
                          self.row_spacing_mm)

    def rolling(self, where: str = ""):
        """The rolling bearing kind (SI) of ``catalogue`` or ``kind``, or None (a linear
        bearing); ``where`` the table in a refusal (default :attr:`WHERE`)."""
        changes = {}
        if self.clearance_um is not None:
            changes["clearance"] = self.clearance_um * 1e-6
        if self.crown_um is not None:
            changes["crown"] = self.crown_um * 1e-6
        for key, arg, scale in (("dynamic_rating_kN", "dynamic_rating", 1e3),
                                ("static_rating_kN", "static_rating", 1e3),
                                ("iso281_f0", "iso281_f0", 1.0),
                                ("fatigue_limit_kN", "fatigue_limit", 1e3)):
            if getattr(self, key) is not None:
                changes[arg] = getattr(self, key) * scale
        pair = {}
        if self.arrangement is not None:
            pair["arrangement"] = self.arrangement
            if self.end_play_um is not None:
                pair["end_play"] = self.end_play_um * 1e-6
            if self.row_spacing_mm is not None:
                pair["spacing"] = self.row_spacing_mm * 1e-3
        try:
            if self.catalogue is not None:
                row = catalogue(self.catalogue, **changes)
                return TaperedRollerPair.of(row, **pair) if pair else row
            if self.kind is None:
                return None
            mm = 1e-3
            args = {"bore": self.bore_mm * mm, "outer_diameter": self.outer_diameter_mm * mm,
                    "width": self.width_mm * mm, "pitch_diameter": self.pitch_diameter_mm * mm}
            if self.balls is not None:
                args.update(elements=self.balls, element_diameter=self.ball_diameter_mm * mm)
                args.update({k: getattr(self, k) for k in _BALL_OPTIONAL
                             if getattr(self, k) is not None})
            else:
                args.update(elements=self.rollers, element_diameter=self.roller_diameter_mm * mm,
                            effective_length=self.roller_length_mm * mm)
            if self.contact_angle_deg is not None:
                args["contact_angle"] = math.radians(self.contact_angle_deg)
            return ROLLING_KINDS[self.kind](**args, **pair, **changes)
        except ValueError as err:  # a relation the checks above do not state, in SI
            raise sc.SchemaError(f"[{where or self.WHERE}] {err}") from None

    def bearing(self) -> Bearing:
        """The bearing in SI (m, N/m, N·m/rad); a rolling bearing without an operating point
        yet (:func:`jaxgear.dynamics.bearings_at_operating_point` finds it)."""
        C = None if self.damping_matrix_SI is None else bearing_matrix(self.damping_matrix_SI)
        z = self.position_mm * 1e-3
        rolling = self.rolling()
        if rolling is not None:
            return Bearing(z=z, rolling=rolling, damping=C)
        if self.stiffness_matrix_SI is not None:
            return Bearing(z=z, stiffness=bearing_matrix(self.stiffness_matrix_SI), damping=C)

        def given(key, default):
            v = getattr(self, key)
            return default if v is None else v

        return Bearing(z=z, radial=given("radial_N_per_um", 200.0) * 1e6,
                       axial=given("axial_N_per_um", 0.0) * 1e6,
                       tilt=given("tilt_Nm_per_rad", 0.0), damping=C)


def first_rolling(shaft, where: str) -> tuple[str, str] | None:
    """(the table, its key) of a shaft section's first rolling bearing (``catalogue`` or
    ``kind``), or None: where a scene that does not take bearings from geometry refuses it."""
    for i, b in enumerate(shaft.bearings):
        for key in ("catalogue", "kind"):
            if key in b.given:
                return f"{where}.bearings[{i}]", key
    return None


def refuse_rolling(shafts, why: str) -> None:
    """Refuse the first rolling bearing of ``shafts`` ((where, section) pairs; None skipped)
    in one line: bearings from geometry are for ``why``'s scenes only."""
    for where, shaft in shafts:
        found = None if shaft is None else first_rolling(shaft, where)
        if found is not None:
            raise sc.fail(found[0], found[1], "a bearing from its geometry is for a lumped3d "
                          f"pair or train of rigid gears for now ({why}): allowed "
                          "radial_N_per_um/axial_N_per_um/tilt_Nm_per_rad or "
                          "stiffness_matrix_SI here")


class ShaftKeys(Section):
    """What a ``lumped3d`` shaft's table gives (a pair's :class:`ShaftSection`, a train's
    ``[[scene.shafts]]`` entry, each declaring the keys in the file's order): its length and
    diameter (mm, ``length_mm`` in [1, 1e5], ``diameter_mm`` in [1, 1e4]: a denormal size
    passes "> 0" and fails in the solver), its gears' centres, the torque's position on it,
    its finite elements, and its bearings (:class:`BearingSection`, at least one), which must
    hold it (an axial stiffness, and a tilt stiffness, a bearing that carries a moment (a
    tapered roller pair: :meth:`~jaxgear.scenes.Bearing.holds_tilt`) or two radial bearings
    1 % of its length apart). Positions lie on the shaft ([0, length_mm])."""

    @pydantic.field_validator("torque_position_mm", check_fields=False)
    @classmethod
    def _on_shaft(cls, v, info):
        return on_shaft(info.field_name, v, info.data.get("length_mm"), where_of(info))

    @pydantic.field_validator("bearings", mode="before", check_fields=False)
    @classmethod
    def _bearings(cls, v, info):
        """Each bearing read where the file has it (``[scene.pinion_shaft.bearings[1]]``)."""
        where = where_of(info)
        if not isinstance(v, list) or not v:
            raise sc.fail(
                where,
                "bearings",
                "must be a non-empty array of tables, e.g. "
                "[{ position_mm = 0.0, radial_N_per_um = 200.0 }]",
                v,
            )
        context = {"length_mm": info.data.get("length_mm")}
        return [BearingSection.read(b, f"{where}.bearings[{i}]", context=context)
                for i, b in enumerate(v)]

    @pydantic.model_validator(mode="after")
    def _held(self, info):
        """The bearings hold the shaft: axially, and against tilting."""
        where = where_of(info)
        bearings = [b.bearing() for b in self.bearings]
        carried = [b.carried() for b in bearings]
        if not any(c[2] for c in carried):
            rolling = any(b.rolling is not None for b in bearings)
            raise sc.SchemaError(
                f"[{where}] bearings: needs an axial stiffness on at least one bearing "
                "(axial_N_per_um > 0 or stiffness_matrix_SI[2][2] > 0"
                + (", or a rolling bearing that carries an axial load)" if rolling else ")")
            )
        # a single-row rolling bearing is a radial support: its tilt stiffness, which its
        # load gives it, does not hold a shaft alone; a kind that carries a moment does
        if any(b.holds_tilt() for b in bearings):
            return self
        radial = [b.z for b, c in zip(bearings, carried, strict=True) if c[0] and c[1]]
        if len(radial) < 2:
            raise sc.SchemaError(
                f"[{where}] bearings: needs two radial bearings (or a tilt stiffness) to hold "
                "the shaft" + (" (a single-row or self-aligning rolling bearing is a radial "
                               "support only: allowed a second bearing, or a bearing that "
                               "carries a moment, kind = 'tapered_roller_pair')"
                               if any(b.rolling is not None for b in bearings) else "")
            )
        # two radial bearings at one position hold the shaft like one: it tilts freely
        span_mm = (max(radial) - min(radial)) * 1e3
        min_span = MIN_BEARING_SPAN * self.length_mm
        if span_mm < min_span:
            raise sc.fail(
                where,
                "bearings",
                f"radial bearings at position_mm = {min(radial) * 1e3:.6g} to "
                f"{max(radial) * 1e3:.6g}, allowed at least {min_span:.6g} mm apart "
                f"({100 * MIN_BEARING_SPAN:g} % of length_mm; closer, they do not stop the shaft "
                "tilting) or a tilt stiffness (tilt_Nm_per_rad)",
            )
        return self

    def spec(self, gear_z: float | tuple) -> ShaftSpec:
        """The shaft in SI, its gears' centres at ``gear_z`` (m)."""
        return ShaftSpec(
            length=self.length_mm * 1e-3,
            diameter=self.diameter_mm * 1e-3,
            gear_z=gear_z,
            bearings=tuple(b.bearing() for b in self.bearings),
            torque_z=self.torque_position_mm * 1e-3,
            elements=self.elements,
        )


class ShaftSection(ShaftKeys):
    """A pair's ``[scene.pinion_shaft]`` or ``[scene.gear_shaft]`` (:class:`ShaftKeys`), its
    gear's centre at ``gear_position_mm`` on it."""

    WHERE: ClassVar[str] = "scene.pinion_shaft"
    length_mm: number("[1, 1e+05]")
    diameter_mm: number("[1, 1e+04]")
    gear_position_mm: ON_SHAFT_MM
    torque_position_mm: ON_SHAFT_MM = 0.0
    elements: number("[1, 1000]", integer=True) = 4
    bearings: list[BearingSection]

    @pydantic.field_validator("gear_position_mm")
    @classmethod
    def _gear_on_shaft(cls, v, info):
        return on_shaft(info.field_name, v, info.data.get("length_mm"), where_of(info))

    def shaft(self) -> ShaftSpec:
        """The shaft in SI."""
        return self.spec(self.gear_position_mm * 1e-3)


class BodySection(Section):
    """``[scene.<member>_body]`` (a train's ``[scene.bodies.<name>]``): a flexible member's
    ``body``, an embedded fem_prep body's name, a body TOML or a condensed .npz (a path from
    the case file's folder: :meth:`reference`)."""

    WHERE: ClassVar[str] = "scene.gear_body"
    body: Text

    def reference(self, where: str, base_dir: str | None) -> str:
        """The body's reference: an embedded body's name or a body file's path (from the case
        file's folder ``base_dir``), the file read now (its kind checked) before any work."""
        ref = self.body
        if ref.endswith((".toml", ".npz")):
            path = ref if base_dir is None or os.path.isabs(ref) else os.path.join(base_dir, ref)
            if not os.path.isfile(path):
                raise _body_error(where, f"no such file {path!r}", ref)
            _check_body_file(path, ref, where)
            return path
        names = fem_prep.embedded_bodies()
        if ref not in names:
            raise sc.fail(
                where,
                "body",
                f"allowed an embedded body ({', '.join(names)}), a body .toml or a condensed "
                ".npz",
                ref,
            )
        return ref


def _body_error(where: str, why: str, ref: str) -> sc.SchemaError:
    """``[where] body = 'ref': why`` with the whole path (``sc.fail`` shortens long strings to
    40 characters, which cut a path before its file's name)."""
    p = sc.key_path(where, "body")
    return sc.SchemaError(f"{p} = {ref!r}: {why}", p)


def _check_body_file(path: str, ref: str, where: str) -> None:
    """A body file must be what its extension says, read now (before any work): a fem_prep body
    file (``.toml``, checked against its schema) or a condensed body (``.npz``, format checked)."""
    if path.endswith(".toml"):
        try:
            with open(path, "rb") as f:
                data = sc.load_toml(f.read(), f"body file {path!r}")
            if "pair" in data and "body" not in data:
                what = "it" if path == ref else repr(path)
                why = f"{what} is a jaxgear case file ([pair]), not a fem_prep body file"
                raise _body_error(where, why, ref)
            fem_prep.load_body(path)
        except sc.SchemaError as err:
            if err.path == f"[{where}] body":  # already about the reference (_body_error)
                raise
            raise _body_error(where, f"not a fem_prep body file {path!r}: {err}", ref) from None
        except OSError as err:
            raise _body_error(where, f"not a fem_prep body file {path!r}: {err}", ref) from None
        return
    try:
        fem_prep.load_condensed(path)
    except (ValueError, OSError) as err:
        why = str(err).removeprefix(f"{path}: ")
        raise _body_error(where, f"not a condensed body file {path!r}: {why}", ref) from None


#: ``[scene.damping]``'s ratio keys → their :class:`SceneSpec` fields
_DAMPING_FIELDS = {"ratio": "damping_ratio", "mesh_ratio": "mesh_ratio",
                   "structure_ratio": "structure_ratio", "alpha_per_s": "rayleigh_alpha",
                   "beta_s": "rayleigh_beta"}
#: the words of an ``[scene.integration]`` count that may be "auto"
_AUTO_WORDS = {"steps_per_period": "allowed 'auto' or an integer in [4, 1e+06]",
               "periods": "allowed 'auto' or an integer in [2, 1e+06]"}


class DampingSection(Section):
    """``[scene.damping]`` (module docstring): the damping model and its ratios of critical
    damping ([0, 1]) or its Rayleigh coefficients (α 1/s, β s; >= 0)."""

    WHERE: ClassVar[str] = "scene.damping"
    model: Literal["composite", "modal", "rayleigh", "none"] = "composite"
    ratio: number("[0, 1]") | None = None
    mesh_ratio: number("[0, 1]") | None = None
    structure_ratio: number("[0, 1]") | None = None
    alpha_per_s: number(">= 0") | None = None
    beta_s: number(">= 0") | None = None

    def settings(self) -> dict:
        """The :class:`SceneSpec` fields of the keys given (the model always)."""
        return {"damping_model": self.model, **{
            field: getattr(self, key) for key, field in _DAMPING_FIELDS.items()
            if key in self.given}}


class IntegrationSection(Section):
    """``[scene.integration]`` (module docstring): the solver and the contact law, the time
    steps per mesh period and the periods per speed ("auto": the time-plan rule, as
    ``None``), the periods kept, the diffrax tolerances, and the hybrid scenes' rotating frame
    and modal basis (false, or its number of modes; Newmark only)."""

    WHERE: ClassVar[str] = "scene.integration"
    solver: Literal[("newmark", *DIFFRAX_SOLVERS)] = "newmark"
    contact: Literal["exact", "smooth"] = "exact"
    steps_per_period: number("[4, 1e+06]", integer=True) | None = pydantic.Field(
        None, json_schema_extra={"default": "'auto'"})
    periods: number("[2, 1e+06]", integer=True) | None = pydantic.Field(
        None, json_schema_extra={"default": "'auto'"})
    keep_periods: number("[2, 1e+06]", integer=True) | None = pydantic.Field(
        None, json_schema_extra={"default": "4"})
    rtol: number("(0, 1)") | None = None
    atol: number("(0, 1)") | None = None
    rotating_frame: bool = False
    modal_basis: number("[1, 1e+06]", integer=True, note=" (modes), or false") | None = (
        pydantic.Field(None, json_schema_extra={"default": "false"}))

    @pydantic.field_validator("steps_per_period", "periods", "modal_basis", mode="before")
    @classmethod
    def _words(cls, v, info):
        """"auto" (a count) and false (the modal basis) as None; another string in words."""
        if info.field_name == "modal_basis":
            return None if v is False else v
        if isinstance(v, str):
            if v == "auto":
                return None
            raise sc.fail(cls.WHERE, info.field_name, _AUTO_WORDS[info.field_name], v)
        return v

    @pydantic.model_validator(mode="after")
    def _related(self):
        keep = 4 if self.keep_periods is None else self.keep_periods
        if self.periods is not None and keep > self.periods:
            raise sc.fail(self.WHERE, "keep_periods",
                          f"out of range, allowed <= periods = {self.periods}", keep)
        if self.modal_basis is not None and self.solver != "newmark":
            raise sc.fail(self.WHERE, "modal_basis", "allowed only with solver = 'newmark'",
                          self.modal_basis)
        return self

    def settings(self) -> dict:
        """The :class:`SceneSpec` fields (``rotating_frame`` aside: its scene checks it): the
        solver, the contact law and the two counts always, the others where given."""
        kw = {"solver": self.solver, "contact": self.contact,
              "steps_per_period": self.steps_per_period, "periods": self.periods}
        for key in ("keep_periods", "rtol", "atol", "modal_basis"):
            if getattr(self, key) is not None:
                kw[key] = getattr(self, key)
        return kw


def dynamics_settings(scene) -> dict:
    """The :class:`SceneSpec` fields of a scene section's ``[scene.damping]`` and
    ``[scene.integration]`` (a pair's or a train's; ``rotating_frame`` aside)."""
    return scene.damping.settings() | scene.integration.settings()


def needs_a_body(integration: IntegrationSection, hybrid: bool, tables: str,
                 modal: bool = True) -> None:
    """``[scene.integration]``'s hybrid keys refused on a scene without a condensed body
    (``tables``: where the file gives one, in its words): the rotating frame, and with
    ``modal`` the modal basis."""
    if integration.rotating_frame and not hybrid:
        raise sc.fail(
            "scene.integration",
            "rotating_frame",
            f"allowed only with a condensed body ({tables}): the rigid models are written in the "
            "fixed frame",
            True,
        )
    if modal and integration.modal_basis is not None and not hybrid:
        raise sc.fail(
            "scene.integration",
            "modal_basis",
            f"allowed only with a condensed body ({tables}): the modal basis is for the hybrid "
            "models",
            integration.modal_basis,
        )


#: [scene]'s torsional keys → their :class:`SceneSpec` fields
_TORSIONAL = {
    "pinion_inertia_kg_m2": "pinion_inertia",
    "gear_inertia_kg_m2": "gear_inertia",
    "motor_inertia_kg_m2": "motor_inertia",
    "motor_shaft_stiffness_Nm_per_rad": "motor_shaft",
    "load_inertia_kg_m2": "load_inertia",
    "load_shaft_stiffness_Nm_per_rad": "load_shaft",
}
#: the keys of a lumped 3D scene only
_LUMPED = ("pinion_shaft", "gear_shaft", "pinion_mass_kg", "gear_mass_kg", "pinion_body",
           "gear_body")


def _sub(cls):
    """A before-validator reading a sub-table as ``cls`` where the file has it
    (``[scene.pinion_shaft]``): its own checks name it."""
    def read(section, v, info):
        if not isinstance(v, dict):
            return v  # the type's words
        return cls.read(v, f"{where_of(info)}.{info.field_name}")
    return classmethod(read)


class SceneSection(Section):
    """A pair's ``[scene]`` (module docstring): the model (torsional, or lumped 3D on shafts
    and bearings), the 1-DOF reduction (torsional), the members' inertias (kg·m²) and masses
    (kg, lumped 3D), the motor's and the load's inertias with their shafts' stiffnesses
    (N·m/rad, torsional, each pair both or neither), the shafts (:class:`ShaftSection`,
    required by lumped 3D), the flexible members' bodies (:class:`BodySection`, lumped 3D),
    damping and integration. :meth:`spec` the :class:`SceneSpec`."""

    WHERE: ClassVar[str] = "scene"
    model: Literal["torsional", "lumped3d"] = "torsional"
    reduction: Literal["none", "relative"] = "none"
    pinion_shaft: ShaftSection | None = None
    gear_shaft: ShaftSection | None = None
    pinion_body: BodySection | None = None
    gear_body: BodySection | None = None
    pinion_mass_kg: number("[1e-06, 1e+09]") | None = None
    gear_mass_kg: number("[1e-06, 1e+09]") | None = None
    pinion_inertia_kg_m2: number("[1e-09, 1e+15]") | None = None
    gear_inertia_kg_m2: number("[1e-09, 1e+15]") | None = None
    motor_inertia_kg_m2: number("[1e-09, 1e+15]") | None = None
    motor_shaft_stiffness_Nm_per_rad: number("[0.001, 1e+15]") | None = None
    load_inertia_kg_m2: number("[1e-09, 1e+15]") | None = None
    load_shaft_stiffness_Nm_per_rad: number("[0.001, 1e+15]") | None = None
    damping: DampingSection = pydantic.Field(default_factory=DampingSection)
    integration: IntegrationSection = pydantic.Field(default_factory=IntegrationSection)

    _shafts = pydantic.field_validator("pinion_shaft", "gear_shaft", mode="before")(
        _sub(ShaftSection))
    _bodies = pydantic.field_validator("pinion_body", "gear_body", mode="before")(
        _sub(BodySection))

    @pydantic.model_validator(mode="after")
    def _related(self):
        given = self.given
        if self.model == "lumped3d":
            for key in ("pinion_shaft", "gear_shaft"):
                if key not in given:
                    raise sc.SchemaError(
                        f"[scene] model = 'lumped3d' needs a [scene.{key}] table")
            for key in ("motor_inertia_kg_m2", "load_inertia_kg_m2",
                        "motor_shaft_stiffness_Nm_per_rad", "load_shaft_stiffness_Nm_per_rad"):
                if key in given:
                    raise sc.fail("scene", key, "is for model = 'torsional' (lumped3d: the "
                                  "torque acts at the shafts' torque_position_mm)")
            if self.reduction != "none":
                raise sc.fail("scene", "reduction", "applies to model = 'torsional' only",
                              self.reduction)
        else:
            for key in _LUMPED:
                if key in given:
                    raise sc.fail("scene", key, "is for model = 'lumped3d'")
        for side in ("motor", "load"):
            inertia, shaft = f"{side}_inertia_kg_m2", f"{side}_shaft_stiffness_Nm_per_rad"
            if (inertia in given) != (shaft in given):
                raise sc.SchemaError(
                    f"[scene] {inertia} and {shaft} go together: give both or neither")
            if self.reduction == "relative" and inertia in given:
                raise sc.SchemaError(
                    f"[scene] reduction = 'relative' is for a rigid pinion-gear pair: "
                    f"remove {inertia} or set reduction = 'none'"
                )
        needs_a_body(self.integration, bool({"pinion_body", "gear_body"} & given),
                     "[scene] pinion_body or gear_body")
        if {"pinion_body", "gear_body"} & given:
            refuse_rolling([(f"scene.{k}", getattr(self, k)) for k in ("pinion_shaft",
                            "gear_shaft")], "not with pinion_body or gear_body")
        return self

    def spec(self, base_dir: str | None = None) -> SceneSpec:
        """The :class:`SceneSpec` (SI), the bodies' references resolved against the case
        file's folder ``base_dir`` and their files read (:meth:`BodySection.reference`)."""
        kw: dict = {"model": self.model, "reduction": self.reduction}
        for member in ("pinion", "gear"):
            shaft, body = getattr(self, f"{member}_shaft"), getattr(self, f"{member}_body")
            if shaft is not None:
                kw[f"{member}_shaft"] = shaft.shaft()
            if body is not None:
                kw[f"{member}_body"] = body.reference(f"scene.{member}_body", base_dir)
            if getattr(self, f"{member}_mass_kg") is not None:
                kw[f"{member}_mass"] = getattr(self, f"{member}_mass_kg")
        kw.update({field: getattr(self, key) for key, field in _TORSIONAL.items()
                   if key in self.given})
        kw.update(dynamics_settings(self))
        if "rotating_frame" in self.integration.given:
            kw["rotating_frame"] = self.integration.rotating_frame
        return SceneSpec(**kw)


def parse_scene(table: dict | None, base_dir: str | None = None) -> SceneSpec:
    """Validate a ``[scene]`` table (``None`` or ``{}``: the defaults; :class:`SceneSection`).
    Body paths are resolved against ``base_dir`` (the case file's folder).

    Raises:
        SchemaError (a ``ValueError``): unknown keys (named), wrong types, values out of range,
            inconsistent inputs; one line, in the file's units.
    """
    return SceneSection.read({} if table is None else table).spec(base_dir)
