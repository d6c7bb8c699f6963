"""A sizing spec file (``jaxgear size SPEC.toml``): what a designer knows before the gears,
checked whole before any work and mapped to :class:`jaxgear.sizing.SizingSpec`; and a
candidate of the result written as a case file that ``jaxgear run`` rates
(:func:`candidate_case_text`).

Tables (file units in the key names)::

    name = "helical-reducer"
    [operating]
    torque_Nm = 500.0               # the pinion's torque, (0, 1e7]; or
    power_kW = 78.5                 # the power, (0, 1e5] kW (T₁ = P/ω₁); one of the two
    speed_rpm = 1500.0              # the pinion's speed, (0, 1e6] 1/min
    [material]                      # a case file's [material] (σ_Hlim, σ_Flim, treatment, E,
                                    # ν, ρ; jaxgear.io._rating_table)
    [rating]                        # a case file's [rating]: life_h, application_factor,
                                    # min_safety_pitting, min_safety_bending (the feasibility
                                    # limits), lubricant, roughness, accuracy_grade, edition
    min_safety_scuffing = 1.5       # S_Bmin of the scuffing check, [0.5, 10], default 1 (with
                                    # [lubricant] fzg_load_stage; the sizing's key only)
    [sizing]
    ratio = 3.5                     # target u = z2/z1, [1, 20]
    ratio_tolerance_percent = 2.0   # |z2/z1 − u| <= tolerance · u, [0, 20], default 2
    normal_module_min_mm = 2.0      # the modules searched: ISO 54's series between these,
    normal_module_max_mm = 6.0      # [1, 50] mm
    module_series = "first"         # "first" | "second" | "both" (ISO 54's choices)
    z1_min = 17                     # the pinion teeth searched, [5, 300]
    z1_max = 35
    normal_pressure_angle_deg = 20.0    # (10, 35), default 20
    helix_angle_deg = 15.0          # [0, 40), default 0
    profile_shift = [0.2, 0.0]      # x1, x2, each [-1, 2], default [0, 0]; with a fixed
                                    # centre distance x2 follows from it (x1 given)
    addendum_coeff = 1.0            # the basic rack: h_aP/m_n (0, 2], h_fP/m_n (0, 2],
    dedendum_coeff = 1.25           # ρ_fP/m_n [0, dedendum_coeff); defaults 1, 1.25, 0.38
    fillet_radius_coeff = 0.38
    centre_distance_mm = 150.0      # fixed, (0, 1e5]; or a window:
    centre_distance_min_mm = 120.0  # centre_distance_min_mm, centre_distance_max_mm
    profile_shift_sum_min = -1.0    # with a fixed centre distance: the sums x1 + x2 allowed,
    profile_shift_sum_max = 2.0     # [-3, 5], defaults -1 and 2
    face_width_min_mm = 10.0        # [4, 1200], default 4 (ISO 1328-1's scope)
    face_width_max_mm = 80.0        # [4, 1200], required
    face_width_ratio_max = 0.8      # the largest b/d1, (0, 3]; optional
    outer_diameter_max_mm = 400.0   # the largest tip diameter, (0, 1e5]; optional
    tip_thickness_min = 0.2         # the least normal tip thickness / m_n, [0, 1], default 0.2
    te_candidates = 3               # the transmission-error stage: the best feasible
                                    # candidates evaluated, [0, 1000], default 3 (0: none)
    te_torque_min_percent = 25.0    # its torque range: from this % of the rated torque,
                                    # (0, 100], default 25
    te_torques = 4                  # to the rated one in this many equal steps, [1, 16],
                                    # default 4 (1: the rated torque alone)
    te_max_iterations = 50          # the modification optimiser's cap, [1, 1000], default 50
    dynamics_candidates = 3         # the dynamics stage: candidates of the first Pareto
                                    # fronts run, [0, 100], default 3 (0: none)
    dynamics_speed_range_rpm = [750.0, 30000.0]  # its pinion speeds, each (0, 1e6], lo < hi;
                                    # default through every candidate's mesh resonance
    dynamics_speeds = 40            # equally spaced over the range, [2, 400], default 40
                                    # (the [operating] speed added to them)
    refine = true                   # refine the continuous variables by gradients, default
                                    # false (jaxgear size --refine too)
    refine_objective = "mass"       # "mass" (default) | "margin"
    # helix_angle_deg = [8.0, 20.0] # a range: β refined within it (enumerated at its middle)
    profile_shift_min = -0.5        # each shift refined within these, [-1, 2]; both or
    profile_shift_max = 1.0         # neither (neither: the shifts stay as enumerated)
    [lubricant]                     # optional: the oil of the mesh loss columns and, with
                                    # fzg_load_stage, of the scuffing check (ISO/TS 6336-20's
                                    # closed form; its S_B, θ_B,max, μ_mC columns), and
    [pareto]                        # the objectives of the front (jaxgear.io._pareto_table)
    [sound]                         # optional: the sound stage's housing, shafts and speeds
                                    # (jaxgear.io._sizing_sound)

Each candidate's face width is the widest allowed, min(face_width_max_mm, face_width_ratio_max
d1). A spec that can give no candidate (no tooth counts within the ratio tolerance, none in the
centre-distance window, no module of the series between the bounds) is refused in one line
naming the key, before any work.
"""

from __future__ import annotations

import math
import os
import tomllib
from typing import ClassVar, Literal

import pydantic

from fem_prep import schema as sc

from .._util import as_float
from ..sizing import (
    CANDIDATE_MESH,
    STAGE_OBJECTIVES,
    DynamicsSettings,
    SizingSpec,
    TeSettings,
    candidate_pair,
    enumerate_candidates,
    module_series,
    ratio_pairs,
)
from ._case_file import MaterialSection
from ._housing_table import EDGE
from ._modifications_table import modifications_toml, modifications_with
from ._pareto_table import (
    SIZING_RATING_KEYS,
    parse_pareto,
    parse_sizing_lubricant,
    parse_sizing_scuffing,
)
from ._rating_inputs import modification_inputs
from ._rating_material_table import MaterialRatingKeys, refuse_unread_material
from ._rating_table import RatingSection, rating_settings
from ._sections import Section, number, number_list, one_of
from ._sizing_sound import POSITIONS as SOUND_POSITIONS, SOUND_ELEMENTS, SoundSection, sound_layout
from ._writers import toml_value

__all__ = ["SIZING_STAGES", "SizingSection", "SpecOperating", "candidate_case_text",
           "housed_case_text",
           "load_sizing_spec", "parse_sizing_spec", "sizing_dynamics_settings",
           "sizing_te_settings", "unstaged_objective"]

RPM = math.pi / 30


class SpecOperating(Section):
    """A sizing spec's ``[operating]``: the pinion's torque or the power, and its speed."""

    WHERE: ClassVar[str] = "operating"
    torque_Nm: number("(0, 1e+07]") | None = None
    power_kW: number("(0, 1e+05]") | None = None
    speed_rpm: number("(0, 1e+06]")

    @pydantic.model_validator(mode="after")
    def _one_load(self):
        if (self.torque_Nm is None) == (self.power_kW is None):
            raise sc.fail("operating", "torque_Nm", "give one of torque_Nm or power_kW",
                          self.torque_Nm if self.torque_Nm is not None else sc.MISSING)
        return self

    def torque(self) -> float:
        """T₁ (N·m): the given torque, or P/ω₁."""
        if self.torque_Nm is not None:
            return self.torque_Nm
        return self.power_kW * 1e3 / (self.speed_rpm * RPM)


class SizingSection(Section):
    """A sizing spec's ``[sizing]`` (module docstring): the ratio, the ranges searched, the
    basic rack, the limits; each key's range declared here, the relations between keys in
    :meth:`_related`."""

    WHERE: ClassVar[str] = "sizing"
    ratio: number("[1, 20]")
    ratio_tolerance_percent: number("[0, 20]") = 2.0
    normal_module_min_mm: number("[1, 50]")
    normal_module_max_mm: number("[1, 50]")
    module_series: Literal["first", "second", "both"] = "first"
    z1_min: number("[5, 300]", integer=True)
    z1_max: number("[5, 300]", integer=True)
    normal_pressure_angle_deg: number("(10, 35)") = 20.0
    helix_angle_deg: one_of(number=number("[0, 40)"),
                            array=number_list("[0, 40)", length=2)) = 0.0
    profile_shift: number_list("[-1, 2]", length=2) = pydantic.Field(
        default_factory=lambda: [0.0, 0.0])
    addendum_coeff: number("(0, 2]") = 1.0
    dedendum_coeff: number("(0, 2]") = 1.25
    fillet_radius_coeff: number("[0, 2)") = 0.38
    centre_distance_mm: number("(0, 1e+05]") | None = None
    centre_distance_min_mm: number("(0, 1e+05]") | None = None
    centre_distance_max_mm: number("(0, 1e+05]") | None = None
    profile_shift_sum_min: number("[-3, 5]") = -1.0
    profile_shift_sum_max: number("[-3, 5]") = 2.0
    face_width_min_mm: number("[4, 1200]") = 4.0
    face_width_max_mm: number("[4, 1200]")
    face_width_ratio_max: number("(0, 3]") | None = None
    outer_diameter_max_mm: number("(0, 1e+05]") | None = None
    tip_thickness_min: number("[0, 1]") = 0.2
    te_candidates: number("[0, 1000]", integer=True) = 3
    te_torque_min_percent: number("(0, 100]") = 25.0
    te_torques: number("[1, 16]", integer=True) = 4
    te_max_iterations: number("[1, 1000]", integer=True) = 50
    dynamics_candidates: number("[0, 100]", integer=True) = 3
    dynamics_speed_range_rpm: number_list("(0, 1e+06]", length=2) | None = None
    dynamics_speeds: number("[2, 400]", integer=True) = 40
    refine: bool = False
    refine_objective: Literal["mass", "margin"] = "mass"
    profile_shift_min: number("[-1, 2]") | None = None
    profile_shift_max: number("[-1, 2]") | None = None

    def helix_angles_deg(self) -> tuple[float, float]:
        """(β_min, β_max) in degrees: the range given, or the one angle twice."""
        v = self.helix_angle_deg
        return (v[0], v[1]) if isinstance(v, list) else (v, v)

    @pydantic.model_validator(mode="after")
    def _related(self):
        w = self.WHERE
        for lo, hi in (("normal_module_min_mm", "normal_module_max_mm"), ("z1_min", "z1_max"),
                       ("face_width_min_mm", "face_width_max_mm"),
                       ("centre_distance_min_mm", "centre_distance_max_mm"),
                       ("profile_shift_sum_min", "profile_shift_sum_max"),
                       ("profile_shift_min", "profile_shift_max")):
            a, b = getattr(self, lo), getattr(self, hi)
            if a is not None and b is not None and b < a:
                raise sc.fail(w, hi, f"below {lo} = {sc.fmt(a)}: an empty range", b)
        window = (self.centre_distance_min_mm, self.centre_distance_max_mm)
        if self.centre_distance_mm is not None and any(v is not None for v in window):
            raise sc.fail(w, "centre_distance_mm", "give a fixed centre distance or a window "
                          "(centre_distance_min_mm, centre_distance_max_mm), not both",
                          self.centre_distance_mm)
        if isinstance(self.helix_angle_deg, list) and not (
                self.helix_angle_deg[0] <= self.helix_angle_deg[1]):
            raise sc.fail(w, "helix_angle_deg", "out of range, allowed one angle or [lo, hi] "
                          "with lo <= hi", self.helix_angle_deg)
        r = self.dynamics_speed_range_rpm
        if r is not None and not r[0] < r[1]:
            raise sc.fail(w, "dynamics_speed_range_rpm", "out of range, allowed [lo, hi] with "
                          "lo < hi", r)
        shifts = (self.profile_shift_min, self.profile_shift_max)
        if (shifts[0] is None) != (shifts[1] is None):
            given = "profile_shift_min" if shifts[0] is not None else "profile_shift_max"
            raise sc.fail(w, given, "a range needs both profile_shift_min and "
                          "profile_shift_max", shifts[0] if shifts[0] is not None else shifts[1])
        if (window[0] is None) != (window[1] is None):
            given = "centre_distance_min_mm" if window[0] is not None else "centre_distance_max_mm"
            raise sc.fail(w, given, "a window needs both centre_distance_min_mm and "
                          "centre_distance_max_mm", window[0] if window[0] is not None
                          else window[1])
        if not self.fillet_radius_coeff < self.dedendum_coeff:
            raise sc.fail(w, "fillet_radius_coeff", "out of range, allowed [0, dedendum_coeff = "
                          f"{sc.fmt(self.dedendum_coeff)})", self.fillet_radius_coeff)
        if self.face_width_ratio_max is not None:
            d_most = self.z1_max * self.normal_module_max_mm / math.cos(
                math.radians(self.helix_angles_deg()[1]))
            if self.face_width_ratio_max * d_most < self.face_width_min_mm:
                raise sc.fail(w, "face_width_ratio_max", "below face_width_min_mm = "
                              f"{sc.fmt(self.face_width_min_mm)} / the largest pinion diameter "
                              f"{sc.fmt(d_most)} mm: every face width too narrow",
                              self.face_width_ratio_max)
        if self.outer_diameter_max_mm is not None:
            d_least = (self.z1_min * self.ratio * (1 - self.ratio_tolerance_percent / 100)
                       * self.normal_module_min_mm / math.cos(
                           math.radians(self.helix_angles_deg()[0])))
            if d_least >= self.outer_diameter_max_mm:
                raise sc.fail(w, "outer_diameter_max_mm", "at or below the smallest gear's "
                              f"reference diameter {sc.fmt(d_least)} mm the ranges allow",
                              self.outer_diameter_max_mm)
        return self


#: the tables of a sizing spec
SPEC_TABLES = ("operating", "material", "rating", "sizing", "lubricant", "pareto", "sound")


def parse_sizing_spec(data: dict) -> tuple[SizingSpec, dict]:
    """Check a parsed spec (a dict, module docstring) whole and build the
    :class:`jaxgear.sizing.SizingSpec`; returns it and the spec's tables (for
    :func:`candidate_case_text`). Every refusal is one line naming the key, before any work;
    a spec that can give no candidate is refused too (naming the key that empties it).

    Raises:
        SchemaError (a ``ValueError``): as above.
    """
    if not isinstance(data, dict):
        raise sc.SchemaError(f"a sizing spec must be a table of tables, not {type(data).__name__}")
    sc.check_keys(data, {"name", *SPEC_TABLES}, "")
    sc.subtables(data, SPEC_TABLES, "")
    for table in ("operating", "material", "rating", "sizing"):
        if table not in data:
            raise sc.SchemaError(f"[{table}]: missing required table", f"[{table}]")
    sz = SizingSection.of_file(data, required=True)
    op = SpecOperating.of_file(data, required=True)
    mat = MaterialSection.of_file(data)
    rating = RatingSection.of({k: v for k, v in data["rating"].items()
                               if k not in SIZING_RATING_KEYS})
    if rating.spectrum is not None or rating.use_measured:
        key = "spectrum" if rating.spectrum is not None else "use_measured"
        raise sc.fail("rating", key, "not read by a sizing (one operating point, ISO's factors)")
    refuse_unread_material(data["material"], [MaterialRatingKeys.of_mesh(
        data["material"]).treatment_names()])
    rt = rating.keys()
    settings, operating, _, _ = rating_settings(
        rt, data["material"], {"torque_Nm": op.torque(), "speed_rpm": op.speed_rpm},
        mat.material(), lambda g: _grade_only(g), modification_inputs(
            None if rt.tip_relief_um is None else rt.tip_relief_um * 1e-6, None),
    )
    modules = module_series(sz.normal_module_min_mm * 1e-3, sz.normal_module_max_mm * 1e-3,
                            sz.module_series)
    if not modules:
        raise sc.fail("sizing", "normal_module_max_mm", f"no module of ISO 54's "
                      f"{sz.module_series} choice between normal_module_min_mm = "
                      f"{sc.fmt(sz.normal_module_min_mm)} and this", sz.normal_module_max_mm)
    if sz.centre_distance_mm is not None:
        window = (sz.centre_distance_mm * 1e-3,) * 2
    elif sz.centre_distance_min_mm is not None:
        window = (sz.centre_distance_min_mm * 1e-3, sz.centre_distance_max_mm * 1e-3)
    else:
        window = None
    spec = SizingSpec(
        operating=operating,
        settings=settings,
        ratio=sz.ratio,
        ratio_tolerance=sz.ratio_tolerance_percent / 100,
        normal_modules=modules,
        pinion_teeth=(sz.z1_min, sz.z1_max),
        normal_pressure_angle=math.radians(sz.normal_pressure_angle_deg),
        helix_angle=math.radians(sum(sz.helix_angles_deg()) / 2),
        addendum_coeff=sz.addendum_coeff,
        dedendum_coeff=sz.dedendum_coeff,
        fillet_radius_coeff=sz.fillet_radius_coeff,
        profile_shift=tuple(sz.profile_shift),
        centre_distance=window,
        profile_shift_sum=(sz.profile_shift_sum_min, sz.profile_shift_sum_max),
        face_width=(sz.face_width_min_mm * 1e-3, sz.face_width_max_mm * 1e-3),
        face_width_ratio=sz.face_width_ratio_max,
        outer_diameter_max=None if sz.outer_diameter_max_mm is None
        else sz.outer_diameter_max_mm * 1e-3,
        tip_thickness_min=sz.tip_thickness_min,
        **_objectives(data),
        helix_angle_range=tuple(map(math.radians, sz.helix_angles_deg()))
        if isinstance(sz.helix_angle_deg, list) else None,
        profile_shift_range=None if sz.profile_shift_min is None
        else (sz.profile_shift_min, sz.profile_shift_max),
        refine=sz.refine,
        refine_objective=sz.refine_objective,
    )
    sound = SoundSection.of_file(data) if "sound" in data else None
    _refuse_unstaged(spec.objectives, {"te": sz.te_candidates, "dynamics": sz.dynamics_candidates,
                                       "sound": 0 if sound is None else sound.candidates},
                     data)
    _refuse_unradiated(spec.objectives, sound, data)
    _refuse_empty(spec, sz)
    return spec, data


#: each stage that adds objectives (:data:`jaxgear.sizing.STAGE_OBJECTIVES`): its words, its
#: spec table and key, and ``jaxgear size``'s option for its candidates
SIZING_STAGES = {"te": ("the transmission-error stage", ("sizing", "te_candidates"), "--te"),
                 "dynamics": ("the dynamics stage", ("sizing", "dynamics_candidates"),
                              "--dynamics"),
                 "sound": ("the sound stage", ("sound", "candidates"), "--sound")}


def unstaged_objective(objectives, candidates: dict) -> tuple[str, str] | None:
    """(the first objective of ``objectives`` a stage adds, that stage) where ``candidates``
    (stage → its candidates) turns the stage off (0), else None: a front over it would be
    empty (its column NaN for every candidate)."""
    for name, _ in objectives:
        for stage, names in STAGE_OBJECTIVES.items():
            if name in names and candidates.get(stage, 1) == 0:
                return name, stage
    return None


def _refuse_unstaged(objectives, candidates: dict, data: dict) -> None:
    """One line naming ``[pareto]``'s key that names an objective whose stage the spec
    (``data``, its tables) turns off (:func:`unstaged_objective`)."""
    bad = unstaged_objective(objectives, candidates)
    if bad is None:
        return
    name, stage = bad
    words, (table, key), _ = SIZING_STAGES[stage]
    pareto = data.get("pareto")
    where = next(k for k in ("minimise", "maximise") if name in (pareto or {}).get(k, []))
    off = (f"which [{table}] {key} = 0 turns off" if table in data
           else f"which runs only with a [{table}] table")
    raise sc.fail("pareto", where, f"{name!r} is a column of {words}, {off}: allowed "
                  f"[{table}] {key} >= 1 with it, or objectives without it", pareto[where])


def _refuse_unradiated(objectives, sound, data: dict) -> None:
    """One line naming ``[pareto]``'s key that ranks by ``sound_power_peak_dB`` where ``[sound]``
    runs without ``sound_power = true`` (the column NaN for every candidate); without
    ``[sound]`` :func:`_refuse_unstaged` has refused it."""
    name = "sound_power_peak_dB"
    if sound is None or sound.sound_power or name not in [n for n, _ in objectives]:
        return
    pareto = data["pareto"]
    where = next(k for k in ("minimise", "maximise") if name in pareto.get(k, []))
    raise sc.fail("pareto", where, f"{name!r} is the sound stage's radiated sound power, which "
                  "[sound] sound_power = true turns on: allowed sound_power = true with it, or "
                  "objectives without it", pareto[where])


def _objectives(data: dict) -> dict:
    """The mesh loss's and the scuffing check's inputs of ``[lubricant]`` (and ``[rating]
    min_safety_scuffing``) and the front's of ``[pareto]``
    (:mod:`jaxgear.io._pareto_table`), as :class:`jaxgear.sizing.SizingSpec`'s keywords."""
    lub = data.get("lubricant")
    mesh_loss = None if lub is None else parse_sizing_lubricant(lub, data["operating"])
    scuffing = parse_sizing_scuffing(lub, data["rating"], mesh_loss)
    objectives, chosen = parse_pareto(data.get("pareto"), lub is not None, scuffing is not None)
    return {"mesh_loss": mesh_loss, "scuffing": scuffing, "objectives": objectives,
            "chosen": chosen}


def _grade_only(grade: int):
    """The accuracy the spec's settings hold: the grade, the tolerances of no candidate (each
    candidate is rated with its own, :meth:`jaxgear.rating.GearAccuracy.from_dimensions`)."""
    from ..rating import GearAccuracy

    return GearAccuracy(*(as_float(float("nan")),) * 3, int(grade))


def _refuse_empty(spec: SizingSpec, sz: SizingSection) -> None:
    """One line naming the key that leaves the spec no candidate."""
    z1, _ = ratio_pairs(spec)
    if z1.size == 0:
        raise sc.fail("sizing", "ratio_tolerance_percent", "no tooth counts z1 in "
                      f"[{sz.z1_min}, {sz.z1_max}] give a ratio z2/z1 within it of ratio = "
                      f"{sc.fmt(sz.ratio)}: widen it or the z1 range", sz.ratio_tolerance_percent)
    if len(enumerate_candidates(spec)) == 0:
        if sz.centre_distance_mm is not None:
            raise sc.fail("sizing", "centre_distance_mm", "no candidate reaches it with a "
                          f"profile shift sum in [{sc.fmt(sz.profile_shift_sum_min)}, "
                          f"{sc.fmt(sz.profile_shift_sum_max)}]", sz.centre_distance_mm)
        raise sc.fail("sizing", "centre_distance_min_mm", "no candidate's centre distance lies "
                      f"in [{sc.fmt(sz.centre_distance_min_mm)}, "
                      f"{sc.fmt(sz.centre_distance_max_mm)}] mm", sz.centre_distance_min_mm)


def load_sizing_spec(path: str) -> tuple[SizingSpec, dict]:
    """Read and check the sizing spec file ``path`` (:func:`parse_sizing_spec`); returns the
    spec and its tables (with ``name``: the file's, else the file name's stem).

    Raises:
        SchemaError (a ``ValueError``): a file that is not TOML, or as
            :func:`parse_sizing_spec`. FileNotFoundError: no such file.
    """
    with open(path, "rb") as f:
        try:
            data = tomllib.load(f)
        except tomllib.TOMLDecodeError as err:
            raise sc.SchemaError(f"{path}: not a TOML file ({err})") from None
    spec, tables = parse_sizing_spec(data)
    name = tables.get("name") or os.path.splitext(os.path.basename(path))[0]
    return spec, tables | {"name": str(name)}


def sizing_te_settings(tables: dict, candidates: int | None = None) -> TeSettings:
    """The transmission-error stage's settings (:class:`jaxgear.sizing.TeSettings`) of a
    spec's checked tables (:func:`load_sizing_spec`): ``[sizing]``'s ``te_candidates`` (or
    ``candidates``, ``jaxgear size --te N``, where given), ``te_max_iterations`` and the torque
    range, ``te_torques`` fractions of the rated torque equally spaced from
    ``te_torque_min_percent`` % to 1 (one: the rated torque alone)."""
    sz = SizingSection.of_file(tables, required=True)
    n = sz.te_torques
    lo = sz.te_torque_min_percent / 100
    fractions = (1.0,) if n == 1 else tuple(lo + (1.0 - lo) * k / (n - 1) for k in range(n))
    return TeSettings(candidates=sz.te_candidates if candidates is None else int(candidates),
                      torque_fractions=fractions[:-1] + (1.0,),
                      max_iterations=sz.te_max_iterations)


def sizing_dynamics_settings(tables: dict, candidates: int | None = None) -> DynamicsSettings:
    """The dynamics stage's settings (:class:`jaxgear.sizing.DynamicsSettings`) of a spec's
    checked tables (:func:`load_sizing_spec`): ``[sizing]``'s ``dynamics_candidates`` (or
    ``candidates``, ``jaxgear size --dynamics N``, where given), ``dynamics_speed_range_rpm``
    (in rad/s; none: the stage's default range) and ``dynamics_speeds``."""
    sz = SizingSection.of_file(tables, required=True)
    r = sz.dynamics_speed_range_rpm
    return DynamicsSettings(
        candidates=sz.dynamics_candidates if candidates is None else int(candidates),
        speed_range=None if r is None else (r[0] * RPM, r[1] * RPM),
        speeds=sz.dynamics_speeds)


def candidate_case_text(tables: dict, spec: SizingSpec, row: dict, index: int,
                        modified: bool = False) -> str:
    """The case file (TOML text) of one candidate of a sizing: ``[pair]``, ``[pinion]`` and
    ``[gear]`` of the candidate (values written to full precision, so that ``jaxgear run``
    rates the same numbers), the spec's ``[material]``, ``[rating]`` and ``[lubricant]`` (where
    it gives one), ``[operating]`` the
    pinion's torque and speed, and a light ``[mesh]`` (Weber stiffness) for the rest of the
    run.

    Args:
        tables: the spec's tables (:func:`load_sizing_spec`). spec: its
            :class:`jaxgear.sizing.SizingSpec`. row: the candidate's columns
            (:class:`jaxgear.sizing.SizingTable`, one value each). index: its row number.
        modified: also ``[modifications]``, the tip relief and crowning the transmission-error
            stage found (the row's ``tip_relief_depth_m``, ``tip_relief_extent``,
            ``crowning_depth_m``; a row of that stage, ``stage`` "te"). Its rating then takes
            ISO's C_a and C_β from them (K_v, K_Hβ): the table's rating is the plain flanks'.

    Raises:
        ValueError: ``modified`` for a row the stage did not evaluate.
    """
    if modified and row.get("stage") != "te":
        raise ValueError(f"candidate_case_text: modified = True for candidate {index}, which "
                         "the transmission-error stage did not evaluate: allowed a row of "
                         "stage 'te'")
    name = f"{tables.get('name', 'sizing')}-candidate-{index}" + ("-modified" if modified else "")
    sz, op = tables.get("sizing", {}), tables.get("operating", {})
    pair = candidate_pair(spec, row)  # the numbers the sizing's stages analyse

    def deg(key, radians):  # the spec's own value where it gave one (no round trip)
        if key == "helix_angle_deg" and row.get("refined", 0):  # the row's own (refined)
            return math.degrees(float(row["helix_angle_rad"]))
        v = sz.get(key, math.degrees(radians))
        return math.degrees(radians) if isinstance(v, list) else v
    lines = [
        f"# Candidate {index} of the sizing spec {tables.get('name', '')!r} (jaxgear size):",
        "# the spec's material, rating and operating point; the geometry it "
        + ("refined." if row.get("refined", 0) else "enumerated."),
        f"name = {toml_value(name)}",
        "[pair]",
        f"normal_module_mm = {toml_value(pair.normal_module * 1e3)}",
        ("normal_pressure_angle_deg = "
         f"{toml_value(float(deg('normal_pressure_angle_deg', spec.normal_pressure_angle)))}"),
        f"helix_angle_deg = {toml_value(float(deg('helix_angle_deg', spec.helix_angle)))}",
    ]
    for tag, m in (("pinion", pair.pinion), ("gear", pair.gear)):
        lines += [
            f"[{tag}]",
            f"teeth = {int(m.teeth)}",
            f"profile_shift = {toml_value(float(m.profile_shift))}",
            f"addendum_coeff = {toml_value(float(m.addendum_coeff))}",
            f"dedendum_coeff = {toml_value(float(m.dedendum_coeff))}",
            f"fillet_radius_coeff = {toml_value(float(m.fillet_radius_coeff))}",
            f"face_width_mm = {toml_value(float(m.face_width) * 1e3)}",
        ]
    lines += ["[operating]", f"torque_Nm = {toml_value(float(spec.operating.torque))}",
              f"speed_rpm = {toml_value(float(op.get('speed_rpm', spec.operating.speed / RPM)))}"]
    for table in ("material", "rating", *(("lubricant",) if "lubricant" in tables else ())):
        lines.append(f"[{table}]")
        lines += [f"{k} = {toml_value(v)}" for k, v in tables[table].items()
                  if not (table == "rating" and k in SIZING_RATING_KEYS)]
        lines += [f"# the sizing's {k} = {toml_value(v)} (a case run reports S_B, no limit)"
                  for k, v in tables[table].items() if table == "rating" and k in SIZING_RATING_KEYS]
    lines += ["[mesh]"] + [f"{k} = {toml_value(v)}" for k, v in CANDIDATE_MESH.items()]
    text = "\n".join(lines) + "\n"
    if modified:  # the transmission-error stage's optimised flanks
        depth, extent, crown = (float(row[k]) for k in (
            "tip_relief_depth_m", "tip_relief_extent", "crowning_depth_m"))
        both = ("pinion", "gear")
        text += "# the tip relief and crowning of the sizing's transmission-error stage\n"
        text += modifications_toml(modifications_with(None, {
            (both, "tip_relief", "depth_um"): depth * 1e6,
            (both, "tip_relief", "extent"): extent,
            (both, "crowning", "depth_um"): crown * 1e6}))
    return text


def housed_case_text(tables: dict, spec: SizingSpec, row: dict, index: int,
                     section: SoundSection) -> str:
    """The housed case file (TOML text) of one candidate: its case file
    (:func:`jaxgear.io.candidate_case_text`; with the transmission-error stage's tip relief and
    crowning where that stage evaluated it, ``stage`` "te") and a lumped 3D scene on the shafts
    and bearings of :func:`jaxgear.io.sound_layout` with composite damping, the box
    ``[housing]`` round them (tet10, ``highest_mesh_frequency_Hz`` the mesh order ``band_orders`` at the top speed,
    raised by 1e-9 so that round-off keeps it in the band) and ``[whine]`` over ``[sound]``'s
    speeds (harmonic balance, 64 positions per period); with ``[sound] sound_power = true`` its
    ``[acoustics]`` (:meth:`jaxgear.io.SoundSection.radiation`: method, frequencies, rank,
    cache and the air; the band the orders' range). ``jaxgear run`` of it runs the housed
    whine, the ERP and the radiated sound power the sound stage reports.

    Args:
        tables, spec, row, index: as :func:`jaxgear.io.candidate_case_text`'s.
        section: the spec's ``[sound]``.

    Raises:
        ValueError: an invalid geometry (:func:`jaxgear.sizing.candidate_pair`'s).
    """
    pair = candidate_pair(spec, row)
    lay = sound_layout(section, pair)
    s = section
    lo, hi = (v * RPM for v in s.speed_range_rpm)
    top = s.band_orders * int(row["z1"]) * hi / (2 * math.pi) * (1 + EDGE)
    text = candidate_case_text(tables, spec, row, index, modified=row.get("stage") == "te")
    mm = 1e3

    def bearings(first: float, second: float) -> str:
        k, ax = toml_value(s.bearing_radial_N_per_um), toml_value(s.bearing_axial_N_per_um)
        return (f"[{{ position_mm = {toml_value(first * mm)}, radial_N_per_um = {k}, "
                f"axial_N_per_um = {ax} }}, {{ position_mm = {toml_value(second * mm)}, "
                f"radial_N_per_um = {k} }}]")

    lines = [("# the sound stage's housed model ([sound] of the spec: shafts, bearings, a box "
              "round the tip circles)"), "[scene]", 'model = "lumped3d"', "[scene.damping]",
             'model = "composite"']
    for name, torque in (("pinion_shaft", 0.0), ("gear_shaft", lay.shaft_length)):
        lines += [f"[scene.{name}]",
                  f"length_mm = {toml_value(lay.shaft_length * mm)}",
                  f"diameter_mm = {toml_value(lay.shaft_diameter * mm)}",
                  f"gear_position_mm = {toml_value(lay.gear_position * mm)}",
                  f"torque_position_mm = {toml_value(torque * mm)}",
                  f"elements = {SOUND_ELEMENTS}",
                  f"bearings = {bearings(*lay.bearing_positions)}"]
    lines += ["[housing]",
              f"width_mm = {toml_value(lay.width * mm)}",
              f"height_mm = {toml_value(lay.height * mm)}",
              f"wall_thickness_mm = {toml_value(s.wall_thickness_mm)}",
              f"mesh_size_mm = {toml_value(s.mesh_size_mm)}",
              'element = "tet10"',
              f"youngs_modulus_GPa = {toml_value(s.youngs_modulus_GPa)}",
              f"poisson_ratio = {toml_value(s.poisson_ratio)}",
              f"density_kg_m3 = {toml_value(s.density_kg_m3)}",
              f"highest_mesh_frequency_Hz = {toml_value(top)}",
              f"loss_factor = {toml_value(s.loss_factor)}",
              "[whine]",
              f"speed_min_rad_s = {toml_value(lo)}",
              f"speed_max_rad_s = {toml_value(hi)}",
              f"speeds = {s.speeds}",
              f"harmonics = {s.harmonics}",
              f"positions_per_period = {SOUND_POSITIONS}"]
    radiation = s.radiation()
    if radiation is not None:  # [sound] sound_power: the radiated sound power, jaxgear run's
        lines += ["[acoustics]", f"method = {toml_value(radiation.method)}",
                  f"frequencies = {radiation.frequencies}"]
        lines += [] if radiation.rank is None else [f"rank = {radiation.rank}"]
        lines += [f"cache = {toml_value(radiation.cache)}",
                  f"density_kg_m3 = {toml_value(radiation.density_kg_m3)}",
                  f"sound_speed_m_s = {toml_value(radiation.sound_speed_m_s)}"]
    return text + "\n".join(lines) + "\n"
