"""The case file's load-capacity rating: ``[rating]`` with the ``[material]`` strength keys and
the ``[operating]`` rating speed, checked whole before any work and mapped to the model's
objects (:class:`jaxgear.RatingGeometry`, :class:`jaxgear.OperatingPoint`,
:class:`jaxgear.RatingSettings`).

Keys (file units; ranges as checked)::

    [material]
    sigma_H_lim_MPa = 1500.0        # σ_Hlim (ISO 6336-5), (0, 3000]; or [pinion, gear]
    sigma_F_lim_MPa = 430.0         # σ_Flim (ISO 6336-5), (0, 1500]; or [pinion, gear]
    treatment = "case_hardened"     # | "through_hardened" | "nitrided" (life curves, ρ', Y_X);
                                    # or [pinion, gear]: each gear its own (jaxgear.PairTreatment)
    brinell_hardness_HB = 240.0     # surface hardness HB, [100, 700]; or [pinion, gear]; read
                                    # for a through-hardened gear's Z_W against a surface-
                                    # hardened mate (ignored for surface-hardened gears)
    proof_stress_MPa = 1000.0       # 0.2 % proof stress σ_0.2, [500, 1000] N/mm²; or [pinion,
                                    # gear]; read for a through-hardened gear's slip-layer
                                    # thickness ρ' (ISO 6336-3's table; default its 500 N/mm²
                                    # row; surface-hardened gears have one ρ' for all)
    [operating]
    speed_rpm = 1165.9              # pinion speed of the rating, (0, 1e6] 1/min
                                    # (without it: speed_rad_s, which must then be > 0)
    [rating]                        # ISO 6336:2019 method B
    application_factor = 1.25       # K_A, [1, 10], default 1
    life_h = 175200.0               # required life, (0, 1e7] h
    viscosity_40C_mm2_s = 220.0     # ν_40, [1, 1e4] mm²/s
    roughness_Rz_flank_um = 4.8     # R_z of the flanks, (0, 100] µm; or [pinion, gear]
    roughness_Rz_root_um = 20.0     # R_z of the root fillets, (0, 200] µm; or [pinion, gear]
    accuracy_grade = 6              # ISO 1328-1 flank tolerance class, 1..11, default 6
    tip_relief_um = 20.0            # C_a of K_v, [0, 1000] µm; default: the running-in C_ay
    min_safety_pitting = 1.0        # S_Hmin, [0.5, 10], default 1
    min_safety_bending = 1.0        # S_Fmin, [0.5, 10], default 1
    edition = 2019                  # ISO 6336 edition, 2019 | 2006 (Y_β), default 2019
    # K_v, K_Hbeta, K_Fbeta, K_Halpha, K_Falpha = ...  [1, 10]: given factors replace ISO's
    use_measured = ["K_Hbeta"]      # measured factors that replace ISO's (jaxgear run): K_Hbeta
                                    # (load map), K_Halpha (load sharing; K_Falpha too), K_v
                                    # (the speed sweep at the rating speed); default none

A train file's ``[rating]`` is a pair's for every mesh (:func:`parse_train_rating`): per-gear
values a number or a table by gear name, ``[rating.<driving>-<driven>]`` replacing entries for
one mesh; ``[operating] speed_rpm`` the input's speed. A planetary stage's (gear form,
:func:`parse_planetary_rating`) is a train's for its ``sun-planet`` and ``planet-ring`` meshes
(the ring an internal gear: :class:`jaxgear.InternalRatingGeometry`, :data:`GEOMETRIES`) with
``K_gamma`` (the load sharing factor, [1, 10]; default the run's computed one) and
``ring_cutter_teeth`` (the ring's pinion-type cutter, [11, |z_ring| − 10]: its root section
from the cutter, :class:`jaxgear.ShaperCutterSection`; default ISO's substitute rack), each mesh
at one planet path's mean load and its speed relative to the carrier.
"""

from __future__ import annotations

import dataclasses
import functools
import math

import equinox as eqx

from fem_prep import schema as sc

from .. import (
    CaseHardened,
    Edition2006,
    Edition2019,
    GearAccuracy,
    GearPair,
    GivenFactors,
    InternalGearPair,
    InternalRatingGeometry,
    Lubrication,
    Nitrided,
    OperatingPoint,
    PairTreatment,
    RatingGeometry,
    RatingMaterial,
    RatingSettings,
    ShaperCutterSection,
    ThroughHardened,
    ToothLoading,
)
from ._case import PairForm, TrainForm
from ._planetary_spec import PlanetaryForm

__all__ = [
    "EDITIONS",
    "MATERIAL_RATING_KEYS",
    "MEASURABLE",
    "OPERATING_RATING_KEYS",
    "RATING_KEYS",
    "TREATMENTS",
    "RatingCase",
    "check_rating",
    "check_planetary_rating",
    "check_train_rating",
    "mesh_roles",
    "parse_planetary_rating",
    "parse_rating",
    "parse_train_rating",
    "rating_of",
    "rating_speed",
    "ratings_of",
]

#: ``[material] treatment`` names → the model's treatment objects
TREATMENTS = {
    "case_hardened": CaseHardened,
    "through_hardened": ThroughHardened,
    "nitrided": Nitrided,
}
#: a mesh's pair type → its rating geometry (an internal pair: ISO's internal-gear rules, the
#: ring's root section ISO's substitute rack)
GEOMETRIES = {GearPair: RatingGeometry.of, InternalGearPair: InternalRatingGeometry.of}
#: a planetary mesh's pair type → its rating geometry with the ring's root section (``None``:
#: the substitute rack; an external mesh has none)
SECTIONED = {
    GearPair: lambda pair, section: RatingGeometry.of(pair),
    InternalGearPair: lambda pair, section: InternalRatingGeometry.of(pair, section),
}
#: the keys a planetary stage's ``[rating]`` adds to a train's
PLANETARY_KEYS = {"K_gamma", "ring_cutter_teeth"}
#: ``[rating] edition`` years → the model's edition objects
EDITIONS = {2006: Edition2006, 2019: Edition2019}
#: the keys a rating adds to ``[material]`` and ``[operating]``
MATERIAL_RATING_KEYS = {
    "sigma_H_lim_MPa",
    "sigma_F_lim_MPa",
    "treatment",
    "brinell_hardness_HB",
    "proof_stress_MPa",
}
OPERATING_RATING_KEYS = {"speed_rpm"}
GIVEN = ("K_v", "K_Hbeta", "K_Fbeta", "K_Halpha", "K_Falpha")
#: the factors jaxgear measures that ``[rating] use_measured`` may put in place of ISO's
#: (K_Hβ: the load map's face load distribution; K_Hα: its load sharing between pairs, also
#: taken for K_Fα; K_v: the speed sweep at the rating speed)
MEASURABLE = ("K_Hbeta", "K_Halpha", "K_v")
RATING_KEYS = {
    "use_measured",
    "application_factor",
    "life_h",
    "viscosity_40C_mm2_s",
    "roughness_Rz_flank_um",
    "roughness_Rz_root_um",
    "accuracy_grade",
    "tip_relief_um",
    "min_safety_pitting",
    "min_safety_bending",
    "edition",
    *GIVEN,
}
RPM = 2 * math.pi / 60


@dataclasses.dataclass(frozen=True)
class RatingCase:
    """A case's rating, ready for :func:`jaxgear.rate` (``rate(geometry, operating,
    settings)``)."""

    geometry: RatingGeometry
    operating: OperatingPoint
    settings: RatingSettings
    #: the measured factors to rate with instead of ISO's (``[rating] use_measured``)
    use_measured: tuple[str, ...] = ()
    #: a planetary mesh's given load sharing factor K_γ (``[rating] K_gamma``), or ``None``:
    #: ``jaxgear run`` then takes the stage's computed one (planar model, pin errors)
    k_gamma: float | None = None


@functools.singledispatch
def _per_gear(value, table: dict, key: str, where: str, allowed: str) -> list[float]:
    """A number for both gears (any other type: :func:`fem_prep.schema.number` names it)."""
    v = sc.number(table, key, where, allowed=allowed)
    return [v, v]


@_per_gear.register(list)
def _(value, table: dict, key: str, where: str, allowed: str) -> list[float]:
    """[pinion, gear]."""
    return sc.number_list(table, key, where, length=2, allowed=allowed)


def _pair_of(table: dict, key: str, where: str, allowed: str) -> list[float]:
    """A number or a [pinion, gear] list of two numbers (file units); the key required."""
    return _per_gear(table.get(key), table, key, where, allowed)


def _need(table: dict, key: str, where: str) -> None:
    if key not in table:
        raise sc.fail(where, key, "missing required key (the [rating] table needs it)")


def rating_speed(op: dict) -> float:
    """The rating's speed (rad/s) of ``[operating]``: ``speed_rpm``, or ``speed_rad_s`` (> 0);
    a pair's pinion speed, a train's input speed."""
    rpm = sc.number(op, "speed_rpm", "operating", None, allowed="(0, 1e+06]")
    if rpm is not None and op.get("speed_rad_s", 0.0):
        raise sc.fail(
            "operating", "speed_rpm", "give the speed once: speed_rpm or speed_rad_s", rpm
        )
    speed = rpm * RPM if rpm is not None else float(op.get("speed_rad_s", 0.0))
    if not speed > 0:
        raise sc.fail(
            "operating",
            "speed_rpm",
            "missing required key (the [rating] table needs a pinion speed > 0: speed_rpm, "
            "or speed_rad_s)",
        )
    return speed


def parse_rating(data: dict, pair: GearPair, material: tuple[float, float, float]) -> RatingCase:
    """Check a case's ``[rating]`` with its ``[material]`` and ``[operating]`` rating keys (module
    docstring) and build the :class:`RatingCase`.

    Args:
        data: the parsed case TOML (a dict) with a ``rating`` table.
        pair: the case's gear pair. material: (E Pa, ν, ρ kg/m³) of ``[material]``.

    Raises:
        SchemaError: a missing key (named), a value out of range (key, value, allowed range in
            the file's units), unknown keys; one line.
    """
    rt = sc.subtable(data, "rating", "", RATING_KEYS)
    mat = data.get("material", {})
    op = data.get("operating", {})
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa"):
        _need(mat, key, "material")
    for key in ("life_h", "viscosity_40C_mm2_s", "roughness_Rz_flank_um", "roughness_Rz_root_um"):
        _need(rt, key, "rating")
    s_h = _pair_of(mat, "sigma_H_lim_MPa", "material", "(0, 3000]")
    s_f = _pair_of(mat, "sigma_F_lim_MPa", "material", "(0, 1500]")
    treatment = _treatment(mat)
    speed = rating_speed(op)
    ka = sc.number(rt, "application_factor", "rating", 1.0, allowed="[1, 10]")
    life = sc.number(rt, "life_h", "rating", allowed="(0, 1e+07]") * 3600.0
    nu40 = sc.number(rt, "viscosity_40C_mm2_s", "rating", allowed="[1, 10000]") * 1e-6
    rz_flank = _pair_of(rt, "roughness_Rz_flank_um", "rating", "(0, 100]")
    rz_root = _pair_of(rt, "roughness_Rz_root_um", "rating", "(0, 200]")
    grade = sc.number(rt, "accuracy_grade", "rating", 6, allowed="[1, 11]", integer=True)
    ca = sc.number(rt, "tip_relief_um", "rating", None, allowed="[0, 1000]")
    s_hmin = sc.number(rt, "min_safety_pitting", "rating", 1.0, allowed="[0.5, 10]")
    s_fmin = sc.number(rt, "min_safety_bending", "rating", 1.0, allowed="[0.5, 10]")
    given = {k: sc.number(rt, k, "rating", None, allowed="[1, 10]") for k in GIVEN}
    years = ", the years 2006 or 2019"
    year = sc.number(
        rt, "edition", "rating", 2019, allowed="[2006, 2019]", integer=True, note=years
    )
    if year not in EDITIONS:
        raise sc.fail("rating", "edition", f"out of range, allowed [2006, 2019]{years}", year)
    E, nu, rho = material
    try:
        accuracy = GearAccuracy.from_grade(pair, grade)
    except ValueError as err:  # outside ISO 1328-1's scope (module, diameter, face width)
        raise sc.fail("rating", "accuracy_grade", f"{err}", grade) from None
    settings = RatingSettings(
        material=RatingMaterial(
            [v * 1e6 for v in s_h], [v * 1e6 for v in s_f], E, nu, rho, treatment
        ),
        lubrication=Lubrication(nu40, [v * 1e-6 for v in rz_flank], [v * 1e-6 for v in rz_root]),
        accuracy=accuracy,
        life=life,
        application_factor=ka,
        given=GivenFactors(**given),
        tip_relief=None if ca is None else ca * 1e-6,
        min_safety_pitting=s_hmin,
        min_safety_bending=s_fmin,
        edition=EDITIONS[year](),
    )
    torque = sc.number(op, "torque_Nm", "operating")
    use = _use_measured(rt, given)
    return RatingCase(GEOMETRIES[type(pair)](pair), OperatingPoint(torque, speed), settings, use)


@functools.singledispatch
def _treatment_names(value, mat: dict) -> list[str]:
    """``[material] treatment``: one name for both gears (default case-hardened)."""
    return [sc.choice(mat, "treatment", "material", TREATMENTS, "case_hardened")] * 2


@_treatment_names.register(list)
def _(value, mat: dict) -> list[str]:
    """[pinion, gear] names."""
    if len(value) != 2:
        raise sc.fail(
            "material", "treatment", f"a name or a [pinion, gear] list of two names of "
            f"{', '.join(repr(c) for c in TREATMENTS)}", value,
        )
    return [sc.choice({"treatment": v}, "treatment", "material", TREATMENTS) for v in value]


@functools.singledispatch
def _optional_pair(value, mat: dict, key: str, allowed: str) -> list:
    """An optional ``[material]`` number for both gears; absent: ``[None, None]``."""
    v = sc.number(mat, key, "material", None, allowed=allowed)
    return [v, v]


@_optional_pair.register(list)
def _(value, mat: dict, key: str, allowed: str) -> list:
    """[pinion, gear]."""
    return sc.number_list(mat, key, "material", None, length=2, allowed=allowed)


def _treatment(mat: dict):
    """The pair's treatment object of ``[material] treatment``, ``brinell_hardness_HB`` and
    ``proof_stress_MPa`` (the last two read for a through-hardened gear only: its Z_W and its
    slip-layer thickness ρ'): one treatment for both gears, or :class:`jaxgear.PairTreatment`
    when the gears differ."""
    names = _treatment_names(mat.get("treatment"), mat)
    hb = _optional_pair(mat.get("brinell_hardness_HB"), mat, "brinell_hardness_HB", "[100, 700]")
    ps = _optional_pair(mat.get("proof_stress_MPa"), mat, "proof_stress_MPa", "[500, 1000]")
    each = []
    for name, h, p in zip(names, hb, ps, strict=True):
        each.append(TREATMENTS[name].of_material(h, None if p is None else p * 1e6))
    return each[0] if each[0] == each[1] else PairTreatment(*each)


def _use_measured(rt: dict, given: dict) -> tuple[str, ...]:
    """``[rating] use_measured``: a list of distinct names of :data:`MEASURABLE`, none also
    given as a value."""
    v = rt.get("use_measured", [])
    allowed = f"a list of {', '.join(MEASURABLE)}"
    if not isinstance(v, list) or not all(isinstance(n, str) for n in v):
        raise sc.fail("rating", "use_measured", f"allowed {allowed}", v)
    for n in v:
        if n not in MEASURABLE:
            raise sc.fail("rating", "use_measured", f"unknown factor {n!r}, allowed {allowed}", v)
        if given.get(n) is not None:
            raise sc.fail("rating", "use_measured", f"{n} is given as a value too: give it once", v)
    if len(set(v)) != len(v):
        raise sc.fail("rating", "use_measured", "a factor named twice", v)
    return tuple(v)


def check_rating(data: dict, pair: GearPair, material: tuple[float, float, float]) -> None:
    """The case reader's hook: a ``[rating]`` table checked whole (:func:`parse_rating`), and
    the rating's ``[material]``/``[operating]`` keys refused without one (they would be
    silently unused)."""
    if "rating" in data:
        parse_rating(data, pair, material)
        return
    _refuse_unread(data)


def rating_of(case) -> RatingCase | None:
    """A pair case's :class:`RatingCase`, ``None`` when it has no ``[rating]`` table."""
    if "rating" not in case.raw:
        return None
    material = (case.youngs_modulus, case.poisson_ratio, case.density)
    return parse_rating(case.raw, case.pair, material)


# ------------------------------------------------------------------------------------------
# trains: every mesh rated


@functools.singledispatch
def _mesh_value(value, key: str, where: str, names: tuple, ends: tuple[int, int]):
    """A shared ``[rating]``/``[material]`` value for one train mesh: a number as it is (the
    pair reader checks it)."""
    return value


@_mesh_value.register(dict)
def _(value, key: str, where: str, names: tuple, ends: tuple[int, int]):
    """``{gear name = value}``: every gear of the train named, once → [driving, driven]."""
    missing = [n for n in names if n not in value]
    unknown = [n for n in value if n not in names]
    if missing or unknown:
        what = f"no gear {unknown[0]!r}" if unknown else f"gear {missing[0]!r} missing"
        raise sc.fail(
            where, key, f"{what}: a number, or a table of one per gear ({', '.join(names)})", value
        )
    return [value[names[ends[0]]], value[names[ends[1]]]]


@_mesh_value.register(list)
def _(value, key: str, where: str, names: tuple, ends: tuple[int, int]):
    raise sc.fail(
        where,
        key,
        "a number, or a table of one per gear ({}); a [driving, driven] list only in a "
        "[rating.<driving>-<driven>] table".format(", ".join(names)),
        value,
    )


#: the per-gear keys of a train's [rating] and [material]: a number or a table by gear name
PER_GEAR = {
    "roughness_Rz_flank_um",
    "roughness_Rz_root_um",
    "sigma_H_lim_MPa",
    "sigma_F_lim_MPa",
    "treatment",
    "brinell_hardness_HB",
    "proof_stress_MPa",
}


def _mesh_table(table: dict, keys: set, where: str, names: tuple, ends) -> dict:
    """The entries of ``keys`` for one mesh: per-gear values (:data:`PER_GEAR`) resolved."""
    out = {k: v for k, v in table.items() if k in keys}
    for k in PER_GEAR & set(out):
        out[k] = _mesh_value(out[k], k, where, names, ends)
    return out


def mesh_roles(case) -> tuple[list[int], list[int]]:
    """How many meshes each gear of a train drives in and is driven in, (n,) each."""
    driving, driven = [0] * case.n_gears, [0] * case.n_gears
    for g, h in case.gears:
        driving[g] += 1
        driven[h] += 1
    return driving, driven


def parse_train_rating(data: dict, case) -> tuple[RatingCase, ...]:
    """Check a train's ``[rating]`` with its ``[material]`` and ``[operating]`` rating keys and
    build one :class:`RatingCase` per mesh (the driving gear as the rating's pinion).

    The train's keys are a pair's, for every mesh, with per-gear values (``sigma_H_lim_MPa``,
    ``sigma_F_lim_MPa``, ``roughness_Rz_flank_um``, ``roughness_Rz_root_um``) a number or a
    table of one per gear name (``{ input = 4.8, idler = 4.8, output = 6.0 }``); a
    ``[rating.<driving>-<driven>]`` table (a mesh's name) replaces entries for that mesh (its
    given load factors, accuracy grade, tip relief, or a per-gear key as a pair's
    ``[driving, driven]``). ``[operating] speed_rpm`` (or ``speed_rad_s``) is the input's
    speed; each mesh is rated at its driving gear's speed and torque
    (:attr:`jaxgear.io.Case.mesh_torques`). A gear of two meshes rates each flank it is loaded
    on with its load cycles per turn and Y_M (:meth:`jaxgear.ToothLoading.of_roles`: an
    idler, loaded on alternate flanks, Y_M = 0.7).

    Raises:
        SchemaError: as :func:`parse_rating`, and a mesh table that names no mesh, a per-gear
            table that misses a gear, an internal mesh (external pairs only); one line.
    """
    meshes = [case.mesh_name(k) for k in range(len(case.pairs))]
    for k, (g, h) in enumerate(case.gears):
        if not isinstance(case.pairs[k], GearPair):  # an internal mesh (InternalGearPair)
            raise sc.fail(
                "rating",
                None,
                f"mesh {meshes[k]} is internal ({case.gear_names[h]}: teeth "
                f"{case.pairs[k].gear.teeth}): the rating covers external pairs only",
            )
    rt = sc.subtable(data, "rating", "", RATING_KEYS | set(meshes))
    own = {m: sc.subtable(rt, m, "rating", RATING_KEYS) for m in meshes}
    mat, op = data.get("material", {}), data.get("operating", {})
    names = case.gear_names
    speed = rating_speed(op)
    ratios = case.layout().ratios
    torques = case.mesh_torques
    driving, driven = mesh_roles(case)
    material = (case.youngs_modulus, case.poisson_ratio, case.density)
    out = []
    for k, (g, h) in enumerate(case.gears):
        ends = (g, h)
        shared = _mesh_table(rt, RATING_KEYS, "rating", names, ends)
        mesh_data = {
            "rating": shared | own[meshes[k]],
            "material": _mesh_table(mat, MATERIAL_RATING_KEYS, "material", names, ends),
            "operating": {"torque_Nm": torques[k], "speed_rad_s": speed * abs(ratios[g])},
        }
        rc = parse_rating(mesh_data, case.pairs[k], material)
        loading = ToothLoading.of_roles((driving[g], driving[h]), (driven[g], driven[h]))
        settings = eqx.tree_at(lambda s: s.loading, rc.settings, loading)
        out.append(dataclasses.replace(rc, settings=settings))
    return tuple(out)


def check_train_rating(data: dict, case) -> None:
    """The train reader's hook: a ``[rating]`` table checked whole (:func:`parse_train_rating`),
    the rating's ``[material]``/``[operating]`` keys refused without one."""
    if "rating" in data:
        parse_train_rating(data, case)
        return
    _refuse_unread(data)


def _refuse_unread(data: dict) -> None:
    for table, keys in (("material", MATERIAL_RATING_KEYS), ("operating", OPERATING_RATING_KEYS)):
        for key in sorted(keys & set(data.get(table, {}))):
            raise sc.fail(table, key, "read by the [rating] table only: add one", data[table][key])


def parse_planetary_rating(data: dict, case) -> tuple[RatingCase, ...]:
    """Check a planetary stage's ``[rating]`` (the gear form) and build one :class:`RatingCase`
    per mesh, ``sun-planet`` (the sun the pinion) and ``planet-ring`` (the planet the pinion, the
    ring rated as an internal gear: :class:`jaxgear.InternalRatingGeometry`), each at one planet
    path's mean load and its driving member's speed relative to the carrier
    (:meth:`jaxgear.io.PlanetaryForm.mesh_case`). The keys are a train's (per-gear values a
    number or a table by gear name, ``[rating.<mesh>]`` tables for one mesh) and
    ``K_gamma`` (the load sharing factor, [1, 10]: the most loaded planet path over the mean,
    which multiplies the rating's load; default: ``jaxgear run``'s planar load sharing with the
    pin errors). Load cycles per relative turn: the sun's and the ring's teeth meet every
    planet (p per turn), the planet's once; the planet's teeth are loaded on alternate flanks by
    the sun and the ring, Y_M = 0.7 (ISO 6336-3, mean stress influence factor).

    Raises:
        SchemaError: as :func:`parse_train_rating`; a lumped stage (no gears to rate); one line.
    """
    if not case.pairs:
        raise sc.fail(
            "rating", None, "a lumped planetary stage ([planetary] without [[gears]]) has no "
            "gears to rate: give the stage by its [[gears]]",
        )
    meshes = [case.mesh_name(k) for k in range(len(case.pairs))]
    rt = sc.subtable(data, "rating", "", RATING_KEYS | set(meshes) | PLANETARY_KEYS)
    k_gamma = sc.number(rt, "K_gamma", "rating", None, allowed="[1, 10]")
    z_ring = abs(case.pairs[-1].gear.teeth)
    z0 = sc.number(
        rt, "ring_cutter_teeth", "rating", None, allowed=f"[11, {z_ring - 10}]", integer=True,
        note=" (the ring's pinion-type cutter: 11 to the ring's teeth less 10)",
    )
    section = None if z0 is None else ShaperCutterSection(z0)
    rt = {k: v for k, v in rt.items() if k not in PLANETARY_KEYS}
    own = {m: sc.subtable(rt, m, "rating", RATING_KEYS) for m in meshes}
    mat = data.get("material", {})
    names = case.gear_names
    n = float(case.form.spec.n_planets)
    loading = (ToothLoading((n, 1.0), (1.0, 0.7)), ToothLoading((1.0, n), (0.7, 1.0)))
    material = (case.youngs_modulus, case.poisson_ratio, case.density)
    out = []
    for k, ends in enumerate(case.gears):
        one = case.mesh_case(k)
        mesh_data = {
            "rating": _mesh_table(rt, RATING_KEYS, "rating", names, ends) | own[meshes[k]],
            "material": _mesh_table(mat, MATERIAL_RATING_KEYS, "material", names, ends),
            "operating": {"torque_Nm": one.torque, "speed_rad_s": one.speed},
        }
        rc = parse_rating(mesh_data, case.pairs[k], material)
        settings = eqx.tree_at(lambda s: s.loading, rc.settings, loading[k])
        geometry = SECTIONED[type(case.pairs[k])](case.pairs[k], section)
        out.append(
            dataclasses.replace(rc, geometry=geometry, settings=settings, k_gamma=k_gamma)
        )
    return tuple(out)


def check_planetary_rating(data: dict, case) -> None:
    """The planetary reader's hook: a ``[rating]`` table checked whole
    (:func:`parse_planetary_rating`), the rating's ``[material]``/``[operating]`` keys refused
    without one."""
    if "rating" in data:
        parse_planetary_rating(data, case)
        return
    _refuse_unread(data)


@functools.singledispatch
def _ratings(form, case) -> tuple:
    raise TypeError(f"ratings_of: no rating for a case of form {type(form).__name__}")


@_ratings.register
def _(form: PairForm, case) -> tuple:
    return (rating_of(case),)


@_ratings.register
def _(form: TrainForm, case) -> tuple:
    return parse_train_rating(case.raw, case)


@_ratings.register
def _(form: PlanetaryForm, case) -> tuple:
    return parse_planetary_rating(case.raw, case)


def ratings_of(case) -> tuple[RatingCase, ...] | None:
    """Each mesh's :class:`RatingCase` of a case with ``[rating]`` (a pair: one; a train: one
    per mesh, in the order of its meshes), ``None`` without one."""
    if "rating" not in case.raw:
        return None
    return _ratings(case.form, case)
