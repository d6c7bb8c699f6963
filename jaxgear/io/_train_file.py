"""Gear-train case files: ``[[gears]]`` and ``[[meshes]]`` instead of a pair's ``[pair]``,
``[pinion]`` and ``[gear]`` (docs/trains.md).

.. code-block:: toml

    name = "idler-train"
    [material]                       # as a pair case
    [[gears]]
    name = "input"                   # unique; meshes and [scene.inertias_kg_m2] refer to it
    # shaft = "intermediate"         # gears naming one shaft turn together (a compound gear)
    # clocking_deg = 0.0             # on a later gear of a shaft: its teeth's angle from the
                                     # first gear's (in the direction of motion)
    teeth = 45
    normal_module_mm = 1.5
    normal_pressure_angle_deg = 25.0
    helix_angle_deg = 0.0            # magnitude; external mates have opposite hands
    profile_shift = 0.341            # and the other member keys of a pair case
    face_width_mm = 11.5
    [[meshes]]
    driving = "input"                # the gear that drives in this mesh
    driven = "idler"
    angle_deg = 0.0                  # direction of the driven gear's centre seen from the
                                     # driving one (fixed frame, degrees counter-clockwise)
    center_distance_mm = 98.5        # optional: default the zero-backlash distance
    [mesh]                           # as a pair case, for every mesh
    [modifications]                  # as a pair case, on every gear; [modifications.<gear>]
                                     # replaces entries for that gear
    [operating]
    torque_Nm = 80.0                 # on the input: the first mesh's driving gear
    speed_rad_s = 0.0
    [[operating.loads]]              # a loaded gear other than the balancing output
    gear = "accessory"
    torque_Nm = -5.0                 # in its direction of motion: < 0, it takes power
    [scene]
    model = "torsional"              # or "lumped3d": shafts on bearings, [[scene.shafts]]
    [scene.inertias_kg_m2]           # per gear name (default: solid disc)
    input = 2.4e-4
    [scene.masses_kg]                # lumped3d, per gear name (default: solid disc)
    [[scene.shafts]]                 # lumped3d: one per shaft
    shaft = "input"                  # a shaft name (a gear's `shaft`, by default its own name)
    length_mm = 60.0
    diameter_mm = 30.0
    gear_positions_mm = { input = 30.0 }   # each gear the shaft carries
    torque_position_mm = 0.0         # input, loaded and balancing output shafts' torque
    bearings = [{ position_mm = 0.0, radial_N_per_um = 200.0, axial_N_per_um = 100.0 },
                { position_mm = 60.0, radial_N_per_um = 200.0 }]
    [scene.bodies.idler]             # lumped3d: a flexible gear alone on its shaft, or a shaft
    body = "accessory-idler"         # a fem_prep body: embedded name, body .toml or .npz
    # gears = ["wheel", "pinion"]    # a body with a [pinion_rim]: the gear on each rim
    [[operating.wrenches]]           # lumped3d: a force and tilting moment on a shaft node
    shaft = "intermediate"
    position_mm = 80.0
    force_N = [0.0, -1200.0, 300.0]  # fixed frame, at [operating] torque_Nm (they scale with it)
    moment_Nm = [10.0, 0.0, 0.0]     # z must be 0: a torque about the axis is a load
    [scene.damping]                  # as a pair case
    [scene.integration]              # as a pair case
    [optimise]                       # a housed train ([housing], [whine]): its noise only,
    objective = "erp"                # "erp" or "sound_power"; variables on every gear (no
    vars = ["tip_relief.depth"]      # pinion./gear. prefix), [modifications] common to all

An internal gear (a ring) has a negative ``teeth`` (ISO 21771, e.g. ``teeth = -56``; its
``profile_shift`` in ISO 21771's sign, its tip and root keys as an external gear's): it may be
a mesh's ``driven`` gear only, its ``driving`` mate an external gear inside it, and the mesh an
:class:`~jaxgear.InternalGearPair`. A train with an internal mesh has that one mesh and no
``[scene]`` (``jaxgear run`` writes the rigid mesh's quasi-static files, as a pair's), and its
``[mesh] stiffness`` must have an internal-gear form (``uniform``, ``iso6336``, the default
there, ``fe2d``, or ``weber`` with the internal gear's cutter: its ``cutter_teeth``,
``cutter_profile_shift`` and ``cutter_tip_radius_coeff``). A planetary stage
names its sun, planet and ring gears in ``[planetary]`` (jaxgear/io/_planetary_table.py) instead
of ``[[meshes]]``; its ring's cutter keys serve the rating too (``[rating] ring_cutter_*``, the
older spelling, serve the stiffness model too; both refused).

A helical gear may state its ``hand = "right"`` or ``"left"``; by default the input is
left-handed (a pair case's pinion), a driven gear takes its mate's other hand and a later gear on
a shaft its shaft's first gear's hand (the axial forces of a compound gear then oppose).

A train is checked as a whole before any computation, in the file's units: every gear and mesh
key, gears referred to by name, meshes listed from the input outwards (a mesh's driving gear is
the input or a gear an earlier mesh drives), each gear driven once, one output gear without a
load (the balancing output), the loads leaving it some power, the module,
pressure angle and helix angle of the two gears of a mesh equal, and no two gears that do not
mesh with each other overlapping (tip circles apart).
"""

from __future__ import annotations

import dataclasses
import math
import warnings
from typing import Any, ClassVar, Literal

import pydantic

from fem_prep import schema as sc

from .._geometry import GearPair
from .._internal import InternalGearPair
from .._util import closest_circles
from ..scenes import train_hands
from ._acoustics_table import parse_case_acoustics
from ._bearings_table import read_bearings
from ._case import Case, TrainForm, mesh_teeth_per_turn, teeth_span
from ._case_file import (
    CENTER_DISTANCE_TOL_MM,
    MESH_TABLE_KEYS,
    MODULE_RANGE_MM,
    PRESSURE_ANGLE_RANGE_DEG,
    MaterialSection,
    MemberSection,
    OperatingSection,
    case_housing,
    check_member_size,
    parse_material,
    parse_mesh_settings,
    parse_torque,
)
from ._housing_table import check_housing_band, stage_housing_spec
from ._lubricant_table import read_lubricant
from ._modifications_table import ModificationsSection
from ._optimise_table import (
    OPTIMISE_DEFAULTS,
    check_acoustic_tables,
    check_train_design,
    parse_optimise,
)
from ._planetary_deviations_table import parse_planetary_deviations
from ._planetary_spec import InternalMeshForm
from ._planetary_table import (
    check_internal_stiffness,
    check_ring_teeth,
    gear_cutter,
    is_planetary,
    parse_planetary,
    planetary_mesh_settings,
)
from ._plausibility import CaseWarning, plausibility
from ._rating_table import (
    check_planetary_rating,
    check_train_rating,
    older_ring_cutter,
)
from ._sections import Section, Text, by_sign, in_range, number, number_list
from ._train_scene import check_table_size, shaft_of_table, train_scene
from ._whine_table import (
    WhineSection,
    highest_order_frequency,
    lowest_order_frequency,
    parse_whine,
)

__all__ = ["is_train", "parse_train"]

_TOP_KEYS = {
    "name",
    "material",
    "gears",
    "meshes",
    "mesh",
    "modifications",
    "operating",
    "scene",
    "housing",
    "planetary",
    "rating",
    "deviations",  # a planetary stage's only (jaxgear/io/_planetary_deviations_table.py)
    "lubricant",  # every mesh's film, loss and the efficiency (jaxgear/io/_lubricant_table.py)
    "bearings",  # the rolling bearings' modified life (jaxgear/io/_bearings_table.py)
    "whine",  # a train's gear whine (jaxgear/io/_whine_table.py)
    "acoustics",  # the housing's radiated sound (jaxgear/io/_acoustics_table.py)
    "optimise",  # jaxgear optimise on the housed train's noise (jaxgear/io/_optimise_table.py)
}
#: a wrench's force or moment: (x, y, z) in the fixed frame
_WRENCH_VECTOR = number_list("[-1e+09, 1e+09]", length=3)


class WrenchEntry(Section):
    """An ``[[operating.wrenches]]`` entry (lumped 3D): a force (N) and a tilting moment (N·m)
    on a shaft's node at ``position_mm`` along it, each (x, y, z) in the fixed frame, the
    moment's z 0 (a torque about the shaft axis is a load). The shaft's name, the position's
    range and the moment's z are checked with the entry's index (:func:`_wrenches`)."""

    WHERE: ClassVar[str] = "operating.wrenches[]"
    shaft: Text
    position_mm: number(">= 0")
    force_N: _WRENCH_VECTOR = pydantic.Field(default_factory=lambda: [0.0, 0.0, 0.0])
    moment_Nm: _WRENCH_VECTOR = pydantic.Field(default_factory=lambda: [0.0, 0.0, 0.0])


class LoadEntry(Section):
    """An ``[[operating.loads]]`` entry: a loaded gear (its name) and its torque (N·m, in its
    direction of motion: < 0, it takes power)."""

    gear: Text
    torque_Nm: number("< 0", note=" (a load takes power: negative)")


class TrainOperating(OperatingSection):
    """A train's ``[operating]``: a pair's (:class:`OperatingSection`, on the input) with the
    loaded gears (:class:`LoadEntry`) and the wrenches on shaft nodes (checked with the scene's
    shafts: :func:`_wrenches`)."""

    loads: list[LoadEntry] = pydantic.Field(default_factory=list)
    wrenches: list[WrenchEntry] = pydantic.Field(default_factory=list)


class PlanetaryOperating(TrainOperating):
    """A planetary stage's ``[operating]``: the input member's torque (N·m; its floor follows
    the stage, :func:`jaxgear.io._planetary_table.torque_floor`) and speed (rad/s, required:
    its run sweeps the speeds around it, the mesh frequency and the rating are at it); the
    other keys refused by the stage's reader in its words."""

    torque_Nm: number("(0, 1e+12]")
    speed_rad_s: number("(0, 1e+05]", note=" (a planetary stage's run sweeps around it)")
    speed_rpm: Any = None
    loads: Any = None


def table_hand(h: int) -> str:
    """The case-file word of a helix hand (+1 right, −1 left)."""
    return "right" if h > 0 else "left"


def is_train(data: Any) -> bool:
    """Whether a parsed case file is a train (``[[gears]]`` or ``[[meshes]]``) or a planetary
    stage (``[planetary]``, :func:`parse_train` reads both)."""
    return isinstance(data, dict) and ("gears" in data or "meshes" in data or is_planetary(data))


def _array_of_tables(data: dict, key: str, minimum: int) -> list:
    v = data.get(key)
    if v is None:
        raise sc.SchemaError(f"[[{key}]]: missing; a train case needs at least {minimum}")
    if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
        raise sc.fail("", key, f"must be an array of tables ([[{key}]])", v)
    if len(v) < minimum:
        raise sc.SchemaError(f"[[{key}]]: {len(v)} given, allowed at least {minimum}")
    return v


class GearSection(MemberSection):
    """A ``[[gears]]`` entry of a train or a planetary stage (module docstring): a gear's keys
    (:class:`MemberSection`; an internal gear's ``teeth`` negative, ISO 21771), its name and
    shaft (names: :func:`fem_prep.checks.name`), hand, clocking on its shaft, the mesh's module
    and angles (mm, deg), an internal gear's pinion-type cutter (its ranges follow the gear's
    teeth: :func:`jaxgear.io._planetary_table.gear_cutter`)."""

    WHERE: ClassVar[str] = "gears"
    name: Any
    shaft: Any = None
    hand: Literal["right", "left"] | None = None
    clocking_deg: number("[-360, 360]") = 0.0
    normal_module_mm: number(MODULE_RANGE_MM)
    normal_pressure_angle_deg: number(PRESSURE_ANGLE_RANGE_DEG)
    helix_angle_deg: number("[0, 45)") = 0.0
    teeth: by_sign(number("[5, 10000]", integer=True), number(
        "[-10000, -5]", integer=True, note=" (an internal gear, ISO 21771; external: [5, 10000])"))
    cutter_teeth: Any = None
    cutter_profile_shift: Any = None
    cutter_tip_radius_coeff: Any = None


class MeshEntry(Section):
    """A ``[[meshes]]`` entry (module docstring): its driving and driven gears (names), the
    direction of the driven gear's centre seen from the driving one (deg) and the centre
    distance (mm; default the zero-backlash one)."""

    WHERE: ClassVar[str] = "meshes"
    driving: Text
    driven: Text
    angle_deg: number("[-360, 360]")
    center_distance_mm: number("(0, 1e+06]") | None = None


def _gear(table: dict, index: int, names: dict) -> tuple[str, dict]:
    """One ``[[gears]]`` entry: its name and its geometry (member, module, angles) in SI, its
    :class:`GearSection` (``"table"``)."""
    name = sc.name(table, "name", f"gears[{index}]")
    if name in names:
        raise sc.fail(f"gears[{index}]", "name", f"is taken by gears[{names[name]}]", name)
    where = f"gears.{name}"
    g = GearSection.read(table, where)
    module, alpha, beta = g.normal_module_mm, g.normal_pressure_angle_deg, g.helix_angle_deg
    member = g.member(abs(g.teeth))
    check_member_size(table, where, member, module, alpha)
    member = g.member()  # an internal gear (a ring): negative teeth
    return name, {
        "table": g,
        "cutter": gear_cutter(table, where, member, module, alpha, beta),
        "member": member,
        "module_mm": module,
        "alpha_deg": alpha,
        "beta_deg": beta,
        "where": where,
    }


def _mesh_pair(gears: dict, driving: str, driven: str, cd, where: str) -> GearPair:
    """The pair of a mesh (driving gear as pinion), its geometry checked in file units."""
    a, b = gears[driving], gears[driven]
    for key, label in (
        ("module_mm", "normal_module_mm"),
        ("alpha_deg", "normal_pressure_angle_deg"),
        ("beta_deg", "helix_angle_deg"),
    ):
        if a[key] != b[key]:
            raise sc.SchemaError(
                f"[{where}] {driving} → {driven}: [{a['where']}] {label} = {sc.fmt(a[key])} and "
                f"[{b['where']}] {label} = {sc.fmt(b[key])} differ (gears in mesh share them)"
            )
    if a["member"].teeth < 0:
        raise sc.fail(
            where,
            "driving",
            "is an internal gear (teeth < 0): allowed as a mesh's driven gear only, its mate "
            "an external gear inside it",
            driving,
        )
    kind = InternalGearPair if b["member"].teeth < 0 else GearPair
    geometry = {
        "pinion": a["member"],
        "gear": b["member"],
        "normal_module": a["module_mm"] * 1e-3,
        "normal_pressure_angle": math.radians(a["alpha_deg"]),
        "helix_angle": math.radians(a["beta_deg"]),
    }
    try:
        pair = kind(**geometry)
        a0_mm = pair.zero_backlash_center_distance * 1e3
        if cd is not None and kind is InternalGearPair:  # backlash closer, jams farther
            if cd > a0_mm + CENTER_DISTANCE_TOL_MM:
                raise sc.fail(
                    where,
                    "center_distance_mm",
                    f"out of range, allowed <= {a0_mm:.3f} mm (the zero-backlash distance of "
                    f"the internal pair {driving} → {driven}; farther, the teeth jam)",
                    cd,
                )
            return kind(**geometry, center_distance=min(cd, a0_mm) * 1e-3)
        if cd is not None and cd < a0_mm - CENTER_DISTANCE_TOL_MM:
            raise sc.fail(
                where,
                "center_distance_mm",
                f"out of range, allowed >= {a0_mm:.3f} mm (the zero-backlash distance of "
                f"{driving} → {driven}, to {CENTER_DISTANCE_TOL_MM * 1e3:g} µm; closer, the "
                "teeth jam)",
                cd,
            )
        if cd is not None and cd > a0_mm:
            pair = GearPair(**geometry, center_distance=cd * 1e-3)
    except (ValueError, ArithmeticError) as err:
        if isinstance(err, sc.SchemaError):
            raise
        raise sc.SchemaError(f"[{where}] {driving} → {driven}: {sc.g6(str(err))}") from None
    return pair


def _modifications(table: Any, names: list[str], modules: list[float]) -> tuple:
    """``[modifications]``: the common entries on every gear, ``[modifications.<gear>]``
    replacing them for that gear; one :class:`MemberModification` per gear."""
    section = ModificationsSection.of(table, names)
    return tuple(section.member(n, module) for n, module in zip(names, modules, strict=True))


def _wrenches(wrenches: list[WrenchEntry], shaft_names: list, specs) -> tuple:
    """``[[operating.wrenches]]`` (:class:`WrenchEntry`): ((shaft, z m, force N (3,), moment
    N·m (3,)), ...) at the case's input torque; lumped 3D only, each on a shaft of the train
    and within its length."""
    if not wrenches:
        return ()
    if specs is None:
        raise sc.fail(
            "operating", "wrenches", "needs [scene] model = 'lumped3d' (forces on shaft nodes)"
        )
    out = []
    for i, t in enumerate(wrenches):
        where = f"operating.wrenches[{i}]"
        _, s = shaft_of_table({"shaft": t.shaft}, where, shaft_names)
        length_mm = specs[s].length * 1e3
        z = in_range(where, "position_mm", t.position_mm, f"[0, {length_mm:.6g}]") * 1e-3
        if t.moment_Nm[2] != 0.0:
            raise sc.fail(where, "moment_Nm", "z must be 0 (a torque about the shaft axis is a "
                          "load: [[operating.loads]] or the balancing output)", t.moment_Nm)
        out.append((s, z, tuple(t.force_N), tuple(t.moment_Nm)))
    return tuple(out)


def _loads(loads: list[LoadEntry], index: dict, shafts: list) -> tuple:
    """``[[operating.loads]]``: ((gear index, torque N·m), ...), each a gear off the input's
    shaft, one per shaft, its torque < 0 (it takes power, in its direction of motion)."""
    out = {}
    names = list(index)
    for i, t in enumerate(loads):
        where = f"operating.loads[{i}]"
        gear = t.gear
        if gear not in index:
            raise sc.fail(where, "gear", f"no such gear, allowed {', '.join(names)}", gear)
        if shafts[index[gear]] == 0:
            what = "is the input" if index[gear] == 0 else "is on the input's shaft"
            raise sc.fail(where, "gear", f"{what} (its torque is [operating] torque_Nm)", gear)
        if any(shafts[g] == shafts[index[gear]] for g in out):
            raise sc.fail(
                where, "gear", "turns with a loaded gear (allowed: one load per shaft)", gear
            )
        out[index[gear]] = t.torque_Nm
    return tuple(out.items())


def _check_power(case: Case) -> None:
    """The loads must leave the balancing output some of the input power."""
    taken = sum(case.shares().values())
    if taken >= 1.0:
        raise sc.SchemaError(
            f"[[operating.loads]]: the loads take {100 * taken:.4g} % of the input power "
            f"([operating] torque_Nm = {sc.fmt(case.torque)}); allowed below 100 %, the "
            "balancing output takes the rest"
        )


def _check_overlap(case: Case) -> None:
    """Two gears in one plane (joined by meshes) that do not mesh with each other must not
    overlap: their centres at least the sum of their tip radii apart (mm in the message)."""
    layout = case.layout()
    radii = case.tip_radii()
    meshing = {frozenset(g) for g in case.gears}
    n = case.n_gears
    # gears in one plane: those joined by meshes (a compound gear's two gears sit in two planes,
    # so a second stage may pass over the first's wheel)
    plane = list(range(n))

    def root(i):
        while plane[i] != i:
            i = plane[i]
        return i

    for g, h in case.gears:
        plane[root(h)] = root(g)
    apart = [(i, j) for i in range(n) for j in range(i + 1, n)
             if frozenset((i, j)) not in meshing and root(i) == root(j)]
    worst = closest_circles([c[:2] for c in layout.centres], radii, apart)
    if worst is None:
        return
    i, j, d = worst
    if d < radii[i] + radii[j]:
        a, b = case.gear_names[i], case.gear_names[j]
        raise sc.SchemaError(
            f"[[meshes]] angle_deg: gears {a!r} and {b!r} overlap (centres "
            f"{d * 1e3:.6g} mm apart, tip radii {radii[i] * 1e3:.6g} + "
            f"{radii[j] * 1e3:.6g} mm); turn a mesh's angle_deg"
        )


def _planetary_case(data: dict, name: str, base_dir: str | None, op: PlanetaryOperating) -> Case:
    """A planetary stage's case (``[planetary]``, :func:`jaxgear.io._planetary_table.
    parse_planetary`): its ``[[gears]]`` (none in the lumped form), material, mesh settings,
    modifications and input torque and speed (``op``) read as a train's."""
    gears: dict[str, dict] = {}
    index: dict[str, int] = {}
    check_ring_teeth(data)  # before the ring's cutter keys, whose range follows its teeth
    if "gears" in data:
        for i, table in enumerate(_array_of_tables(data, "gears", 3)):
            gear_name, gear = _gear(table, i, index)
            gears[gear_name], index[gear_name] = gear, i
    names = list(gears)
    modules = [gears[n]["module_mm"] for n in names]
    E, nu, rho = parse_material(data)
    base = {
        "name": name,
        "youngs_modulus": E,
        "poisson_ratio": nu,
        "density": rho,
        "torque": op.torque_Nm,
        "speed": op.speed_rad_s,
        "raw": data,
        "gear_modifications": (
            _modifications(data.get("modifications", {}), names, modules) if names else ()
        ),
        **planetary_mesh_settings(
            data, parse_mesh_settings(data, min(modules or [1.0]) * 1e-3), gears
        ),
    }
    case = parse_planetary(data, base, gears, index)
    if "deviations" in data:  # per tooth, over the hunting period: the gear form only
        if not case.pairs:
            raise sc.fail("", "deviations", "allowed only with [[gears]] (the gear form: the "
                          "deviations are the gears' teeth)", "[deviations]")
        devs, settings = parse_planetary_deviations(data["deviations"], case.pairs,
                                                    case.form.spec.n_planets)
        case = dataclasses.replace(case, deviations=devs, deviation_settings=settings)
    # [rating]: both meshes (ISO 6336, the ring internal), the ring's cutter given once
    case = case.replace(rating=check_planetary_rating(data, case))
    older = older_ring_cutter(data, case)  # [rating] ring_cutter_*: the stiffness model's too
    if older is not None:
        case = case.replace(stiffness=case.stiffness.with_ring_cutter(older))
    check_internal_stiffness(case, "[planetary]")
    case = _check_lubricant(data, case)
    if "housing" in data:  # the held member bolted to it (docs/planetary.md, "On a housing")
        # a stage's whine: orders of its mesh frequency (carrier frame) z_s |ω_s − ω_c| / 2π
        teeth = (2 * math.pi * case.form.spec.mesh_frequency(1.0),)
        inputs = parse_whine(data["whine"]) if "whine" in data else None
        whine = None if inputs is None else highest_order_frequency(inputs, teeth)
        case = dataclasses.replace(case, housing=stage_housing_spec(data, base_dir, (E, nu, rho),
                                                                    whine))
        if inputs is not None:
            check_housing_band(case.housing, lowest_order_frequency(inputs, teeth))
    return case


def _check_lubricant(data: dict, case):
    """``[lubricant]`` of a train or a planetary stage checked whole (:func:`read_lubricant`):
    every mesh's film and sliding loss and the efficiency; a lumped stage (no gears) refused.
    Returns the case with its :attr:`~jaxgear.io.Case.lubricant`."""
    if "lubricant" not in data:
        return case
    if not case.pairs:
        raise sc.fail("", "lubricant", "allowed only with [[gears]] (a lumped planetary stage "
                      "has no flanks to lubricate)", "[lubricant]")
    return case.replace(lubricant=read_lubricant(data))


def parse_train(data: dict, default_name: str = "train", base_dir: str | None = None) -> Case:
    """Validate a parsed train case (a dict with ``[[gears]]`` and ``[[meshes]]``) and build a
    :class:`Case` (SI units); ``base_dir``: the case file's folder (body files of
    ``[scene.bodies]`` are resolved against it).

    Raises:
        SchemaError (a ``ValueError``): unknown keys, missing or wrong values, gears named
            twice or not at all, meshes out of order, a gear driven twice, several or no output
            gears, gears in mesh of different modules or angles, overlapping gears, invalid
            geometry; one line, in the file's units.
    """
    sc.check_keys(data, _TOP_KEYS, "")
    sc.subtables(data, sorted(_TOP_KEYS - {"name", "gears", "meshes"}), "")  # before their readers
    name = sc.name(data, "name", "", default_name)
    MaterialSection.of_file(data)
    sc.subtable(data, "mesh", "", MESH_TABLE_KEYS)
    op = (PlanetaryOperating if is_planetary(data) else TrainOperating).of_file(data,
                                                                              required=True)
    # a train's or a planetary stage's gear whine
    whine = WhineSection.read(data["whine"]) if "whine" in data else None
    if "optimise" in data and is_planetary(data):
        raise sc.fail("", "optimise", "not in a planetary stage's case (allowed: a pair's case, "
                      "or a housed train's)", "[optimise]")
    # a housed train's or planetary stage's radiated sound
    acoustics = parse_case_acoustics(data) if "acoustics" in data else None
    if "bearings" in data and (is_planetary(data) or "scene" not in data):
        read_bearings(data, None, None)  # refused: no rolling bearing to rate
    if is_planetary(data):
        return _planetary_case(data, name, base_dir, op).replace(whine=whine,
                                                                 acoustics=acoustics)
    if "deviations" in data:
        raise sc.fail("", "deviations", "not in a gear train's case (allowed: a pair's case, or "
                      "a planetary stage's with [[gears]])", "[deviations]")
    gears: dict[str, dict] = {}
    index: dict[str, int] = {}
    shaft_names: dict[str, int] = {}
    shafts, clockings, hands = [], [], []
    for i, table in enumerate(_array_of_tables(data, "gears", 2)):
        gear_name, gear = _gear(table, i, index)
        gears[gear_name], index[gear_name] = gear, i
        where = f"gears.{gear_name}"
        shaft = sc.name(table, "shaft", where, gear_name)
        clocking = gear["table"].clocking_deg
        if shaft not in shaft_names:
            if "clocking_deg" in table:
                raise sc.fail(
                    where,
                    "clocking_deg",
                    f"the first gear on shaft {shaft!r} sets its reference (allowed: on a later "
                    "gear of the shaft, the angle of its teeth from this gear's)",
                    table["clocking_deg"],
                )
            shaft_names[shaft] = len(shaft_names)
        shafts.append(shaft_names[shaft])
        clockings.append(math.radians(clocking))
        hand = gear["table"].hand
        hands.append({"right": 1, "left": -1, None: 0}[hand])
    names = list(gears)
    pairs, links, angles = [], [], []
    driven_by: dict[int, int] = {}  # shaft -> the mesh that drives it
    turning = {0}  # shafts
    meshing: set[int] = set()
    for k, table in enumerate(_array_of_tables(data, "meshes", 1)):
        where = f"meshes[{k}]"
        mesh = MeshEntry.read(table, where)
        driving, driven = mesh.driving, mesh.driven
        for key, v in (("driving", driving), ("driven", driven)):
            if v not in gears:
                raise sc.fail(where, key, f"no such gear, allowed {', '.join(names)}", v)
        g, h = index[driving], index[driven]
        if shafts[g] == shafts[h]:
            raise sc.fail(
                where, "driven", "is on the driving gear's shaft (allowed: another shaft)", driven
            )
        if shafts[g] not in turning:
            raise sc.fail(
                where,
                "driving",
                f"does not turn yet: list the meshes from the input ({names[0]!r}, the first "
                "gear) outwards",
                driving,
            )
        if shafts[h] == 0 or shafts[h] in driven_by:
            if h == 0:
                by = "is the input"
            elif shafts[h] == 0:
                by = "is on the input's shaft"
            elif links[driven_by[shafts[h]]][1] == h:
                by = f"is driven by meshes[{driven_by[shafts[h]]}] already"
            else:
                by = f"turns with a gear driven by meshes[{driven_by[shafts[h]]}] already"
            raise sc.fail(where, "driven", f"{by} (allowed: a shaft driven once)", driven)
        driven_by[shafts[h]] = k
        turning.add(shafts[h])
        meshing.update((g, h))
        pairs.append(_mesh_pair(gears, driving, driven, mesh.center_distance_mm, where))
        links.append((g, h))
        angles.append(math.radians(mesh.angle_deg))
    internal = [k for k, p in enumerate(pairs) if isinstance(p, InternalGearPair)]
    if internal:  # the rigid path of one internal mesh (its scenes are not written yet)
        if len(pairs) > 1:
            raise sc.SchemaError(
                f"[meshes[{internal[0]}]] {names[links[internal[0]][0]]} → "
                f"{names[links[internal[0]][1]]}: an internal gear is allowed in a train of one "
                f"mesh only (this train has {len(pairs)}; a planetary stage: [planetary])"
            )
        if "scene" in data:
            raise sc.fail(
                "scene",
                "model",
                "no scene kind takes an internal mesh yet (allowed: no [scene], the rigid "
                "mesh's quasi-static run; a planetary stage: [planetary])",
            )
    effective, clash = train_hands(links, shafts, hands)
    if clash is not None:
        g, h = links[clash]
        how = {i: "" if hands[i] else " (by default)" for i in (g, h)}
        raise sc.SchemaError(
            f"[meshes[{clash}]] {names[g]} → {names[h]}: both hands are "
            f"{table_hand(effective[g])!r}: {names[g]}{how[g]}, {names[h]}{how[h]} (external "
            "gears in mesh have opposite hands; set [[gears]] hand)"
        )
    idle = [n for i, n in enumerate(names) if i not in meshing]
    if idle:
        raise sc.SchemaError(
            f"[[gears]] {', '.join(idle)}: in no mesh (allowed: every gear meshes)"
        )
    E, nu, rho = parse_material(data)
    torque = parse_torque(data["operating"], pairs[0])  # on the input: the first mesh's driving
    speed = op.speed_rad_s  # gear
    loads = _loads(op.loads, index, shafts)
    drivers = {shafts[g] for g, _ in links}
    loaded = {shafts[g] for g, _ in loads}
    first_on = {}
    for i, s_ in enumerate(shafts):
        first_on.setdefault(s_, names[i])
    free = [first_on[s_] for s_ in sorted(first_on) if s_ not in drivers and s_ not in loaded]
    if not free:
        raise sc.SchemaError(
            "[[operating.loads]]: every output gear (one that drives no other) has a load; "
            "leave one without, the balancing output"
        )
    if len(free) > 1:
        raise sc.SchemaError(
            f"[[meshes]]: the train has output gears {', '.join(free)} without a "
            "[[operating.loads]] entry (gears that drive no other); allowed exactly one, the "
            "balancing output"
        )
    mesh = parse_mesh_settings(data, min(p.normal_module for p in pairs))
    if internal:  # the default FE model has no internal-gear form
        mesh = planetary_mesh_settings(data, mesh, gears)
    mods = _modifications(
        data.get("modifications", {}), names, [gears[n]["module_mm"] for n in names]
    )
    shaft_list = list(shaft_names)
    scene, inertias, masses = (
        (None, (), ())
        if "scene" not in data
        else train_scene(data["scene"], names, shafts, shaft_list, base_dir)
    )
    wrenches = _wrenches(op.wrenches, shaft_list, None if scene is None else scene.shafts)
    teeth = mesh_teeth_per_turn(pairs, links, shafts)
    housing = case_housing(data, scene, base_dir, (E, nu, rho), pair=False, teeth=teeth,
                           span=teeth_span(teeth),
                           names=[f"{names[g]}-{names[h]}" for g, h in links])
    optimise = None
    if "optimise" in data:  # the housed train's noise (an acoustic objective only)
        if internal:
            raise sc.fail("", "optimise", "not in a train with an internal mesh (allowed: a "
                          "pair's case, or a housed train of external meshes)", "[optimise]")
        optimise = parse_optimise(data["optimise"])
        if "choices" in optimise:
            raise sc.fail("optimise", "choices", "a bearing choice is a pair case's (its "
                          "lumped3d scene): allowed in a pair's case file", "{...}")
    case = Case(
        name=name,
        gear_names=tuple(names),
        pairs=tuple(pairs),
        gears=tuple(links),
        angles=tuple(angles),
        gear_modifications=mods,
        youngs_modulus=E,
        poisson_ratio=nu,
        density=rho,
        torque=torque,
        loads=loads,
        speed=speed,
        **mesh,
        inertias=inertias,
        shafts=tuple(shafts),
        clockings=tuple(clockings),
        hands=tuple(hands),
        masses=masses,
        wrenches=wrenches,
        shaft_names=tuple(shaft_list),
        scene=scene,
        housing=housing,
        optimise=optimise,
        raw=data,
        form=InternalMeshForm() if internal else TrainForm(),
        whine=whine,
        acoustics=acoustics,
    )
    if internal:
        check_internal_stiffness(case, f"meshes[{internal[0]}]")
        check_train_rating(data, case)  # [rating]: refused (external pairs only)
        case = _check_lubricant(data, case)
        if "bearings" in data:  # refused: its scene takes no rolling bearings
            read_bearings(data, None, None)
        return case
    _check_overlap(case)
    _check_power(case)
    if optimise is not None:
        check_train_design(optimise.get("objective"),
                           optimise.get("vars", OPTIMISE_DEFAULTS["vars"]),
                           data.get("modifications"), names, case.span_periods)
        check_acoustic_tables(data, optimise)
    case = case.replace(rating=check_train_rating(data, case))  # every mesh (ISO 6336)
    case = _check_lubricant(data, case)
    if "bearings" in data:  # the rolling bearings' modified life (docs/bearings.md)
        named = () if scene is None or scene.shafts is None else tuple(
            (f"scene.shafts.{n}", s) for n, s in zip(shaft_list, scene.shafts, strict=True))
        case = case.replace(bearings=read_bearings(data, scene, case.lubricant, named))
    q = case.span_periods
    if scene is not None and scene.keep_periods < q:
        raise sc.fail(
            "scene.integration",
            "keep_periods",
            f"out of range, allowed >= {q} (the meshes repeat together every {q} periods of "
            "the first mesh: the kept periods must hold them all)",
            scene.keep_periods,
        )
    if scene is not None:
        check_table_size(case, scene, mesh["slices"])
    for text in plausibility(case):  # absurd but valid: as a pair case, per mesh
        warnings.warn(text, CaseWarning, stacklevel=2)
    return case
