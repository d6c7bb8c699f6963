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

import fractions
import math
import warnings
from typing import Any

from fem_prep import schema as sc

from .._case import TrainCase
from .._geometry import GearPair
from ..dynamics import SceneSpec
from ..scenes import train_hands
from ._case_file import (
    _MEMBER_KEYS,
    _MOD_KEYS,
    _SCHEMA,
    CENTER_DISTANCE_TOL_MM,
    MODULE_RANGE_MM,
    PRESSURE_ANGLE_RANGE_DEG,
    CaseWarning,
    _member,
    _member_mods,
    check_member_size,
    parse_material,
    parse_mesh_settings,
    parse_torque,
    plausibility,
)
from ._scene_table import _parse_shaft, parse_body, parse_dynamics_settings

__all__ = ["is_train", "parse_train"]

_TOP_KEYS = {"name", "material", "gears", "meshes", "mesh", "modifications", "operating", "scene"}
_GEAR_KEYS = {
    "name",
    "shaft",
    "hand",
    "clocking_deg",
    "normal_module_mm",
    "normal_pressure_angle_deg",
    "helix_angle_deg",
    *_MEMBER_KEYS,
}
_MESH_KEYS = {"driving", "driven", "angle_deg", "center_distance_mm"}
_SCENE_KEYS = {
    "model",
    "inertias_kg_m2",
    "masses_kg",
    "shafts",
    "bodies",
    "damping",
    "integration",
}
_TRAIN_SHAFT_KEYS = {
    "shaft",
    "length_mm",
    "diameter_mm",
    "gear_positions_mm",
    "torque_position_mm",
    "elements",
    "bearings",
}
_WRENCH_KEYS = {"shaft", "position_mm", "force_N", "moment_Nm"}


def table_hand(h: int) -> str:
    """The case-file word of a helix hand (+1 right, −1 left)."""
    return "right" if h > 0 else "left"


def is_train(data: Any) -> bool:
    """Whether a parsed case file is a train (``[[gears]]`` or ``[[meshes]]``)."""
    return isinstance(data, dict) and ("gears" in data or "meshes" in data)


def _array_of_tables(data: dict, key: str, minimum: int) -> list:
    v = data.get(key)
    if v is None:
        raise sc.SchemaError(f"[[{key}]]: missing; a train case needs at least {minimum}")
    if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
        raise sc.fail("", key, f"must be an array of tables ([[{key}]])", v)
    if len(v) < minimum:
        raise sc.SchemaError(f"[[{key}]]: {len(v)} given, allowed at least {minimum}")
    return v


def _gear(table: dict, index: int, names: dict) -> tuple[str, dict]:
    """One ``[[gears]]`` entry: its name and its geometry (member, module, angles) in SI."""
    sc.check_keys(table, _GEAR_KEYS, f"gears[{index}]")
    name = sc.name(table, "name", f"gears[{index}]")
    if name in names:
        raise sc.fail(f"gears[{index}]", "name", f"is taken by gears[{names[name]}]", name)
    where = f"gears.{name}"
    module = sc.number(table, "normal_module_mm", where, allowed=MODULE_RANGE_MM)
    alpha = sc.number(table, "normal_pressure_angle_deg", where, allowed=PRESSURE_ANGLE_RANGE_DEG)
    beta = sc.number(table, "helix_angle_deg", where, 0.0, allowed="[0, 45)")
    member = _member({where: {k: v for k, v in table.items() if k in _MEMBER_KEYS}}, where)
    check_member_size(table, where, member, module, alpha)
    return name, {
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
    geometry = {
        "pinion": a["member"],
        "gear": b["member"],
        "normal_module": a["module_mm"] * 1e-3,
        "normal_pressure_angle": math.radians(a["alpha_deg"]),
        "helix_angle": math.radians(a["beta_deg"]),
    }
    try:
        pair = GearPair(**geometry)
        a0_mm = pair.zero_backlash_center_distance * 1e3
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
    if not isinstance(table, dict):
        raise sc.fail("", "modifications", "must be a table", table)
    sc.check_keys(table, {*_MOD_KEYS, *names}, "modifications")
    common = {k: (v, "modifications") for k, v in table.items() if k in _MOD_KEYS}
    out = []
    for name, module in zip(names, modules, strict=True):
        own = sc.subtable(table, name, "modifications", _MOD_KEYS)
        where = f"modifications.{name}"
        out.append(_member_mods({**common, **{k: (v, where) for k, v in own.items()}}, module))
    return tuple(out)


def _scene(
    table: Any, names: list[str], shafts: list, shaft_names: list, base_dir: str | None = None
) -> tuple:
    """``[scene]`` of a train: the torsional or lumped 3D model, per-gear inertias (and masses),
    the shafts and flexible gears (lumped 3D), damping, integration. Returns (spec, inertias,
    masses)."""
    if not isinstance(table, dict):
        raise sc.fail("", "scene", "must be a table", table)
    sc.check_keys(table, _SCENE_KEYS, "scene")
    model = sc.choice(table, "model", "scene", ("torsional", "lumped3d"), "torsional")
    given = sc.subtable(table, "inertias_kg_m2", "scene", names)
    inertias = tuple(
        sc.number(given, n, "scene.inertias_kg_m2", None, allowed="[1e-09, 1e+15]") for n in names
    )
    given = sc.subtable(table, "masses_kg", "scene", names)
    masses = tuple(
        sc.number(given, n, "scene.masses_kg", None, allowed="[1e-06, 1e+09]") for n in names
    )
    integration = table.get("integration", {})
    rotating = False
    if isinstance(integration, dict) and "rotating_frame" in integration:
        rotating = sc.boolean(integration, "rotating_frame", "scene.integration")
    specs, bodies, rims = None, (), ()
    if model == "lumped3d":
        specs = _train_shafts(table, names, shafts, shaft_names)
        bodies, rims = _bodies(table, names, shafts, shaft_names, base_dir, specs)
    else:
        for key in ("masses_kg", "shafts", "bodies"):
            if key in table:
                raise sc.fail("scene", key, "is for model = 'lumped3d'")
    if rotating and not any(b is not None for b in bodies):
        raise sc.fail(
            "scene.integration",
            "rotating_frame",
            "allowed only with a condensed body ([scene.bodies.<gear>]): the rigid models are "
            "written in the fixed frame",
            True,
        )
    spec = SceneSpec(
        model=model,
        shafts=specs,
        gear_bodies=bodies,
        gear_rims=rims,
        rotating_frame=rotating,
        **parse_dynamics_settings(table),
    )
    return spec, inertias, masses


def _bodies(
    table: dict, names: list, shafts: list, shaft_names: list, base_dir, specs=None
) -> tuple:
    """``[scene.bodies.<gear or shaft>]``: the condensed body that carries a shaft's gears
    (a flexible gear alone on its shaft, named by the gear or the shaft; or the gears of a
    shaft on a body with a ``[pinion_rim]``, named by the shaft, ``gears`` listing the gear on
    each rim). Returns each gear's body reference or ``None`` and each gear's rim (0 the
    webbed wheel's, 1 the pinion rim), () without bodies. A body file (not a condensed .npz)
    is read now: its rim count against the shaft's gears and its pinion rim's position against
    their ``gear_positions_mm`` (``specs``: the shafts), before any work."""
    allowed = [*shaft_names, *(n for n in names if n not in shaft_names)]
    given = sc.subtable(table, "bodies", "scene", allowed)
    if not given:
        return (), ()
    refs: list = [None] * len(names)
    rims = [0] * len(names)
    for key in given:
        where = f"scene.bodies.{key}"
        s_ = shaft_names.index(key) if key in shaft_names else shafts[names.index(key)]
        carried = [names[g] for g in range(len(names)) if shafts[g] == s_]
        t = given[key]
        if not isinstance(t, dict):
            raise sc.fail("scene.bodies", key, "must be a table ([scene.bodies.<name>])", t)
        sc.check_keys(t, {"body", "gears"}, where)
        ref = parse_body(
            {key: {"body": t["body"]} if "body" in t else {}}, key, base_dir, "scene.bodies"
        )
        order = carried
        if "gears" in t:
            order = t["gears"]
            if (
                not isinstance(order, list)
                or not all(isinstance(x, str) for x in order)
                or sorted(order) != sorted(carried)
            ):
                raise sc.fail(
                    where,
                    "gears",
                    "must list the gears of shaft "
                    f"{shaft_names[s_]!r} ({', '.join(carried)}), one per rim of the body: "
                    "the webbed wheel's rim, then the [pinion_rim]",
                    order,
                )
        _check_rims(
            ref, where, order, shaft_names[s_], None if specs is None else specs[s_], carried
        )
        for r, gear in enumerate(order):
            g = names.index(gear)
            if refs[g] is not None:
                raise sc.fail(
                    where,
                    "body",
                    f"gear {gear!r} (shaft {shaft_names[s_]!r}) has a body already",
                    ref,
                )
            refs[g], rims[g] = ref, r
    return tuple(refs), tuple(rims)


def _check_rims(ref: str, where: str, order: list, shaft: str, spec, carried: list) -> None:
    """A fem_prep body file's rims against the gears it carries (one line, mm): as many rims
    as gears, and a pinion rim where ``gear_positions_mm`` puts the second gear (a condensed
    .npz is checked when the scene is built)."""
    import fem_prep

    if ref.endswith(".npz"):
        return
    body = fem_prep.load_body(ref)
    teeth = body.rim_teeth
    if len(teeth) != len(order):
        raise sc.fail(
            where,
            "body",
            f"has {len(teeth)} rim(s) ({', '.join(map(str, teeth))} stations) and shaft "
            f"{shaft!r} {len(order)} gear(s) ({', '.join(order)}) (allowed: one gear per rim; a "
            "second gear needs a fem_prep body with a [pinion_rim])",
            ref,
        )
    if spec is None or body.pinion_rim is None:
        return
    z = dict(zip(carried, spec.gear_positions, strict=True))
    got = (z[order[1]] - z[order[0]]) * 1e3
    want = body.pinion_rim.axial_position * 1e3
    if abs(got - want) > 1e-3:
        raise sc.fail(
            f"scene.shafts.{shaft}",
            "gear_positions_mm",
            f"puts {order[1]!r} {got:.6g} mm from {order[0]!r}, the body {ref!r} its pinion rim "
            f"{want:.6g} mm from its wheel rim (allowed: equal, to 1 µm)",
            {k: round(v * 1e3, 6) for k, v in z.items()},
        )


def _shaft(table: dict, where: str, shaft_names: list) -> tuple[str, int]:
    """A table's ``shaft`` key: (its name, its index), a shaft of the train."""
    name = sc.string(table, "shaft", where)
    if name not in shaft_names:
        raise sc.fail(where, "shaft", f"no such shaft, allowed {', '.join(shaft_names)}", name)
    return name, shaft_names.index(name)


def _train_shafts(table: dict, names: list, shafts: list, shaft_names: list) -> tuple:
    """``[[scene.shafts]]``: one :class:`~jaxgear.scenes.ShaftSpec` per shaft, in shaft order,
    each with the positions of the gears it carries."""
    v = table.get("shafts")
    if v is None:
        raise sc.SchemaError(
            "[scene] model = 'lumped3d' needs [[scene.shafts]], one per shaft: "
            + ", ".join(shaft_names)
        )
    if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
        raise sc.fail("scene", "shafts", "must be an array of tables ([[scene.shafts]])", v)
    out: list = [None] * len(shaft_names)
    for i, t in enumerate(v):
        where = f"scene.shafts[{i}]"
        sc.check_keys(t, _TRAIN_SHAFT_KEYS, where)
        name, s = _shaft(t, where, shaft_names)
        if out[s] is not None:
            raise sc.fail(where, "shaft", "has a [[scene.shafts]] entry already", name)
        carried = [g for g, sh in zip(names, shafts, strict=True) if sh == s]
        out[s] = _parse_shaft(t, f"scene.shafts.{name}", carried)
    missing = [shaft_names[s] for s, spec in enumerate(out) if spec is None]
    if missing:
        raise sc.SchemaError(
            f"[[scene.shafts]]: no entry for shaft {', '.join(missing)} (allowed: one per shaft)"
        )
    return tuple(out)


def _wrenches(op: dict, shaft_names: list, specs) -> tuple:
    """``[[operating.wrenches]]``: ((shaft, z m, force N (3,), moment N·m (3,)), ...) at the
    case's input torque; lumped 3D only, the moment about the shaft axis 0."""
    v = op.get("wrenches", [])
    if not v:
        return ()
    if specs is None:
        raise sc.fail(
            "operating", "wrenches", "needs [scene] model = 'lumped3d' (forces on shaft nodes)"
        )
    if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
        raise sc.fail("operating", "wrenches", "must be an array of tables", v)
    out = []
    for i, t in enumerate(v):
        where = f"operating.wrenches[{i}]"
        sc.check_keys(t, _WRENCH_KEYS, where)
        _, s = _shaft(t, where, shaft_names)
        length_mm = specs[s].length * 1e3
        z = sc.number(t, "position_mm", where, allowed=f"[0, {length_mm:.6g}]") * 1e-3
        vecs = []
        for key in ("force_N", "moment_Nm"):
            x = t.get(key, [0.0, 0.0, 0.0])
            if (
                not isinstance(x, list)
                or len(x) != 3
                or any(isinstance(c, bool) or not isinstance(c, (int, float)) for c in x)
                or not all(math.isfinite(c) and abs(c) <= 1e9 for c in x)
            ):
                raise sc.fail(where, key, "must be 3 numbers (x, y, z; fixed frame), |.| <= 1e9", x)
            vecs.append(tuple(float(c) for c in x))
        if vecs[1][2] != 0.0:
            raise sc.fail(
                where,
                "moment_Nm",
                "z must be 0 (a torque about the shaft axis is a load: [[operating.loads]] or "
                "the balancing output)",
                t["moment_Nm"],
            )
        out.append((s, z, vecs[0], vecs[1]))
    return tuple(out)


def _loads(op: dict, index: dict, shafts: list) -> tuple:
    """``[[operating.loads]]``: ((gear index, torque N·m), ...), each a gear off the input's
    shaft, one per shaft, its torque < 0 (it takes power, in its direction of motion)."""
    v = op.get("loads", [])
    if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
        raise sc.fail("operating", "loads", "must be an array of tables ([[operating.loads]])", v)
    out = {}
    names = list(index)
    for i, t in enumerate(v):
        where = f"operating.loads[{i}]"
        sc.check_keys(t, {"gear", "torque_Nm"}, where)
        gear = sc.string(t, "gear", where)
        if gear not in index:
            raise sc.fail(where, "gear", f"no such gear, allowed {', '.join(names)}", gear)
        if shafts[index[gear]] == 0:
            what = "is the input" if index[gear] == 0 else "is on the input's shaft"
            raise sc.fail(where, "gear", f"{what} (its torque is [operating] torque_Nm)", gear)
        if any(shafts[g] == shafts[index[gear]] for g in out):
            raise sc.fail(
                where, "gear", "turns with a loaded gear (allowed: one load per shaft)", gear
            )
        out[index[gear]] = sc.number(
            t, "torque_Nm", where, allowed="< 0", note=" (a load takes power: negative)"
        )
    return tuple(out.items())


def _check_power(case: TrainCase) -> None:
    """The loads must leave the balancing output some of the input power."""
    taken = sum(case.shares().values())
    if taken >= 1.0:
        raise sc.SchemaError(
            f"[[operating.loads]]: the loads take {100 * taken:.4g} % of the input power "
            f"([operating] torque_Nm = {sc.fmt(case.torque)}); allowed below 100 %, the "
            "balancing output takes the rest"
        )


def _check_overlap(case: TrainCase) -> None:
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
    for i in range(n):
        for j in range(i + 1, n):
            if frozenset((i, j)) in meshing or root(i) != root(j):
                continue
            d = math.dist(layout.centres[i][:2], layout.centres[j][:2])
            if d < radii[i] + radii[j]:
                a, b = case.gear_names[i], case.gear_names[j]
                raise sc.SchemaError(
                    f"[[meshes]] angle_deg: gears {a!r} and {b!r} overlap (centres "
                    f"{d * 1e3:.6g} mm apart, tip radii {radii[i] * 1e3:.6g} + "
                    f"{radii[j] * 1e3:.6g} mm); turn a mesh's angle_deg"
                )


def parse_train(data: dict, default_name: str = "train", base_dir: str | None = None) -> TrainCase:
    """Validate a parsed train case (a dict with ``[[gears]]`` and ``[[meshes]]``) and build a
    :class:`~jaxgear.TrainCase` (SI units); ``base_dir``: the case file's folder (body files of
    ``[scene.bodies]`` are resolved against it).

    Raises:
        SchemaError (a ``ValueError``): unknown keys, missing or wrong values, gears named
            twice or not at all, meshes out of order, a gear driven twice, several or no output
            gears, gears in mesh of different modules or angles, overlapping gears, invalid
            geometry; one line, in the file's units.
    """
    sc.check_keys(data, _TOP_KEYS, "")
    name = sc.name(data, "name", "", default_name)
    for key in ("material", "mesh"):
        sc.subtable(data, key, "", _SCHEMA[key])
    sc.subtable(data, "operating", "", {*_SCHEMA["operating"], "loads", "wrenches"}, required=True)
    gears: dict[str, dict] = {}
    index: dict[str, int] = {}
    shaft_names: dict[str, int] = {}
    shafts, clockings, hands = [], [], []
    for i, table in enumerate(_array_of_tables(data, "gears", 2)):
        gear_name, gear = _gear(table, i, index)
        gears[gear_name], index[gear_name] = gear, i
        where = f"gears.{gear_name}"
        shaft = sc.name(table, "shaft", where, gear_name)
        clocking = sc.number(table, "clocking_deg", where, 0.0, allowed="[-360, 360]")
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
        hand = sc.choice(table, "hand", where, ("right", "left"), None)
        hands.append({"right": 1, "left": -1, None: 0}[hand])
    names = list(gears)
    pairs, links, angles = [], [], []
    driven_by: dict[int, int] = {}  # shaft -> the mesh that drives it
    turning = {0}  # shafts
    meshing: set[int] = set()
    for k, table in enumerate(_array_of_tables(data, "meshes", 1)):
        where = f"meshes[{k}]"
        sc.check_keys(table, _MESH_KEYS, where)
        ends = []
        for key in ("driving", "driven"):
            v = sc.string(table, key, where)
            if v not in gears:
                raise sc.fail(where, key, f"no such gear, allowed {', '.join(names)}", v)
            ends.append(v)
        driving, driven = ends
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
        angle = sc.number(table, "angle_deg", where, allowed="[-360, 360]")
        cd = sc.number(table, "center_distance_mm", where, None, allowed="(0, 1e+06]")
        pairs.append(_mesh_pair(gears, driving, driven, cd, where))
        links.append((g, h))
        angles.append(math.radians(angle))
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
    op = data["operating"]
    torque = parse_torque(op, pairs[0])  # on the input, the first mesh's driving gear
    speed = sc.number(op, "speed_rad_s", "operating", 0.0, allowed="[0, 1e+05]")
    loads = _loads(op, index, shafts)
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
    mods = _modifications(
        data.get("modifications", {}), names, [gears[n]["module_mm"] for n in names]
    )
    shaft_list = list(shaft_names)
    scene, inertias, masses = (
        (None, (), ())
        if "scene" not in data
        else _scene(data["scene"], names, shafts, shaft_list, base_dir)
    )
    wrenches = _wrenches(op, shaft_list, None if scene is None else scene.shafts)
    case = TrainCase(
        name=name,
        gear_names=tuple(names),
        pairs=tuple(pairs),
        gears=tuple(links),
        angles=tuple(angles),
        modifications=mods,
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
        raw=data,
    )
    _check_overlap(case)
    _check_power(case)
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
        _check_table_size(case, scene, mesh["slices"])
    for text in plausibility(case):  # absurd but valid: as a pair case, per mesh
        warnings.warn(text, CaseWarning, stacklevel=2)
    return case


#: the most bytes the dynamics' mesh table may take (1 GB: building it takes several times as
#: much; the 17 780-row table of a 3500-tooth LST pinion at 20 slices ran out of memory)
MAX_TABLE_BYTES = 1e9


def _check_table_size(case: TrainCase, scene: SceneSpec, slices: int) -> None:
    """Refuse, before any work, a dynamics mesh table above :data:`MAX_TABLE_BYTES`: with
    ``steps_per_period`` N_s given, mesh k is tabulated over its own period T_k/T_0 (periods of
    the first mesh) when N_s T_k is whole, else over the whole span of q periods (N_s q rows); a
    row holds each cell's vector on every coordinate (8 bytes each) and a few scalars. The
    message says which multiple of steps makes every mesh's own period whole."""
    spp = scene.steps_per_period
    if spp is None or any(b is not None for b in scene.gear_bodies or ()):
        return  # "auto" steps are multiples of those periods' denominators; bodies: own tables
    q = case.span_periods
    ratio = {case.shaft_of[0]: fractions.Fraction(1)}
    z0 = case.pairs[0].pinion.teeth
    periods, cells = [], 0
    for pair, (g, h) in zip(case.pairs, case.gears, strict=True):
        rg = ratio[case.shaft_of[g]]
        ratio[case.shaft_of[h]] = rg * pair.pinion.teeth / pair.gear.teeth
        periods.append(fractions.Fraction(z0) / (pair.pinion.teeth * rg))
        lead = pair.face_width * math.tan(pair.base_helix_angle)
        lines = math.floor((pair.path_of_contact + lead) / pair.base_pitch * (1 + 1e-12)) + 1
        cells += lines * slices
    rows = max(
        int(spp * t) if (spp * t).denominator == 1 and (spp * q) % (spp * t) == 0 else spp * q
        for t in periods
    )
    if scene.model == "lumped3d" and scene.shafts:
        coords = sum(6 * (s.elements + 1 + len(s.gear_positions)) for s in scene.shafts)
    else:
        coords = case.n_shafts
    need = 8.0 * rows * cells * (coords + 8)
    if need <= MAX_TABLE_BYTES:
        return
    multiple = math.lcm(*(t.denominator for t in periods))
    raise sc.fail(
        "scene.integration",
        "steps_per_period",
        f"out of range: the dynamics' mesh table of the {q}-period span needs {rows} rows × "
        f"{cells} cells × {coords} coordinates, about {need / 1e9:.3g} GB, allowed <= "
        f"{MAX_TABLE_BYTES / 1e9:.3g} GB: a multiple of {multiple} (each mesh tabulated over its "
        "own period), 'auto', or fewer [mesh] slices",
        spp,
    )
