"""The ``[scene]`` of a gear-train case file: torsional or lumped 3D, the shafts on their bearings
(``[[scene.shafts]]``), the flexible gears' condensed bodies (``[scene.bodies]``) and the size
check of the dynamics' mesh tables (docs/trains.md)."""

from __future__ import annotations

import fractions
import math
from typing import Any

import fem_prep
from fem_prep import schema as sc

from ._case import Case
from ._scene_spec import SceneSpec
from ._scene_table import _parse_shaft, integration_of, parse_body, parse_dynamics_settings

__all__ = ["MAX_TABLE_BYTES", "check_table_size", "shaft_of_table", "train_scene"]

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


def train_scene(
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
    rotating = integration_of(table).rotating_frame
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


def shaft_of_table(table: dict, where: str, shaft_names: list) -> tuple[str, int]:
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
        name, s = shaft_of_table(t, where, shaft_names)
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


#: the most bytes the dynamics' mesh table may take (1 GB: building it takes several times as
#: much; the 17 780-row table of a 3500-tooth LST pinion at 20 slices ran out of memory)
MAX_TABLE_BYTES = 1e9


def check_table_size(case: Case, scene: SceneSpec, slices: int) -> None:
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
    if scene.lumped and scene.shafts:
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
