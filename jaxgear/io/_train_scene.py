"""The ``[scene]`` of a gear-train case file: torsional or lumped 3D, the shafts on their bearings
(``[[scene.shafts]]``), the flexible gears' condensed bodies (``[scene.bodies]``) and the size
check of the dynamics' mesh tables (docs/trains.md)."""

from __future__ import annotations

import fractions
import math
from typing import Any, ClassVar, Literal

import pydantic

import fem_prep
from fem_prep import schema as sc

from ._case import Case
from ._scene_spec import SceneSpec
from ._scene_table import (
    ON_SHAFT_MM,
    BearingSection,
    BodySection,
    DampingSection,
    IntegrationSection,
    ShaftKeys,
    dynamics_settings,
    needs_a_body,
    on_shaft,
    refuse_rolling,
    where_of,
)
from ._sections import Section, Text, named_keys, number

__all__ = ["MAX_TABLE_BYTES", "check_table_size", "shaft_of_table", "train_scene"]


class TrainShaftSection(ShaftKeys):
    """A ``[[scene.shafts]]`` entry: a train's shaft (:class:`ShaftKeys`) named by ``shaft``
    (one of the train's), the centres of the gears it carries by gear name
    (``gear_positions_mm``, one per gear: the context's ``carried``, in gear order)."""

    WHERE: ClassVar[str] = "scene.shafts"
    shaft: Text
    length_mm: number("[1, 1e+05]")
    diameter_mm: number("[1, 1e+04]")
    gear_positions_mm: dict[str, ON_SHAFT_MM]
    torque_position_mm: ON_SHAFT_MM = 0.0
    elements: number("[1, 1000]", integer=True) = 4
    bearings: list[BearingSection]

    @pydantic.field_validator("gear_positions_mm", mode="before")
    @classmethod
    def _gears(cls, v, info):
        carried = (info.context or {}).get("carried")
        return named_keys(v, carried, f"{where_of(info)}.gear_positions_mm")

    @pydantic.field_validator("gear_positions_mm")
    @classmethod
    def _on_shaft(cls, v, info):
        """Every gear the shaft carries on it, in gear order."""
        where = f"{where_of(info)}.gear_positions_mm"
        carried = (info.context or {}).get("carried") or list(v)
        for g in carried:
            if g not in v:
                raise sc.fail(where, g, "missing required key")
            on_shaft(g, v[g], info.data.get("length_mm"), where)
        return {g: v[g] for g in carried}

    def shaft_spec(self):
        """The shaft in SI, its gears' centres in gear order."""
        return self.spec(tuple(z * 1e-3 for z in self.gear_positions_mm.values()))


class TrainBodySection(BodySection):
    """A train's ``[scene.bodies.<gear or shaft>]``: a body (:class:`BodySection`) and, for a
    body with two rims, the gears on its rims (``gears``: the webbed wheel's, then the
    ``[pinion_rim]``'s; checked against the shaft's gears by :func:`_bodies`)."""

    WHERE: ClassVar[str] = "scene.bodies.idler"
    gears: list[Text] | None = None

    @pydantic.field_validator("gears", mode="before")
    @classmethod
    def _rims(cls, v, info):
        """The gears of the body's shaft (the context's ``carried``, on shaft ``shaft``), one
        per rim."""
        ctx = info.context or {}
        carried = ctx.get("carried")
        if carried is not None and (not isinstance(v, list) or not all(
                isinstance(x, str) for x in v) or sorted(v) != sorted(carried)):
            raise sc.fail(
                where_of(info),
                "gears",
                f"must list the gears of shaft {ctx['shaft']!r} ({', '.join(carried)}), one per "
                "rim of the body: the webbed wheel's rim, then the [pinion_rim]",
                v,
            )
        return v


def shaft_of_table(table: dict, where: str, shaft_names: list) -> tuple[str, int]:
    """A table's ``shaft`` key: (its name, its index), a shaft of the train."""
    name = sc.string(table, "shaft", where)
    if name not in shaft_names:
        raise sc.fail(where, "shaft", f"no such shaft, allowed {', '.join(shaft_names)}", name)
    return name, shaft_names.index(name)


class TrainSceneSection(Section):
    """A train's ``[scene]`` (module docstring): torsional or lumped 3D, per-gear inertias
    (kg·m²) and masses (kg, lumped 3D), the shafts on their bearings (:class:`TrainShaftSection`,
    one per shaft, lumped 3D), the flexible gears' bodies (:class:`TrainBodySection`, by gear
    or shaft name, lumped 3D), damping and integration. The context names the train's gears
    (``names``), each gear's shaft (``shafts``, indices) and the shafts (``shaft_names``)."""

    WHERE: ClassVar[str] = "scene"
    model: Literal["torsional", "lumped3d"] = "torsional"
    inertias_kg_m2: dict[str, number("[1e-09, 1e+15]")] = pydantic.Field(default_factory=dict)
    masses_kg: dict[str, number("[1e-06, 1e+09]")] = pydantic.Field(default_factory=dict)
    shafts: list[TrainShaftSection] | None = None
    bodies: dict[str, TrainBodySection] = pydantic.Field(default_factory=dict)
    damping: DampingSection = pydantic.Field(default_factory=DampingSection)
    integration: IntegrationSection = pydantic.Field(default_factory=IntegrationSection)

    @pydantic.field_validator("inertias_kg_m2", "masses_kg", mode="before")
    @classmethod
    def _by_gear(cls, v, info):
        return named_keys(v, (info.context or {}).get("names"), f"scene.{info.field_name}")

    @pydantic.field_validator("shafts", mode="before")
    @classmethod
    def _named_shafts(cls, v, info):
        """Each entry read where its shaft's name puts it (``[scene.shafts.<shaft>]``), in
        shaft order, once per shaft."""
        ctx = info.context or {}
        shaft_names = ctx.get("shaft_names")
        if not isinstance(v, list) or not all(isinstance(t, dict) for t in v):
            return v  # the type's words
        if shaft_names is None:  # the train not known: each entry where the file has it
            return [TrainShaftSection.read(t, f"scene.shafts[{i}]") for i, t in enumerate(v)]
        out: dict = {}
        for i, t in enumerate(v):
            where = f"scene.shafts[{i}]"
            name, s = shaft_of_table(t, where, shaft_names)
            if s in out:
                raise sc.fail(where, "shaft", "has a [[scene.shafts]] entry already", name)
            carried = [g for g, sh in zip(ctx["names"], ctx["shafts"], strict=True) if sh == s]
            out[s] = TrainShaftSection.read(t, f"scene.shafts.{name}",
                                            context={"carried": carried})
        return [out[s] for s in sorted(out)]

    @pydantic.field_validator("bodies", mode="before")
    @classmethod
    def _named_bodies(cls, v, info):
        """Each body read where the file has it (``[scene.bodies.<name>]``), named by a shaft
        or a gear of the train."""
        ctx = info.context or {}
        if not isinstance(v, dict):
            return v  # the type's words
        if "names" not in ctx:  # the train not known
            return {k: TrainBodySection.read(t, f"scene.bodies.{k}") for k, t in v.items()}
        names, shafts, shaft_names = ctx["names"], ctx["shafts"], ctx["shaft_names"]
        named_keys(v, [*shaft_names, *names], "scene.bodies")
        out = {}
        for k, t in v.items():
            s = shaft_names.index(k) if k in shaft_names else shafts[names.index(k)]
            carried = [g for g, sh in zip(names, shafts, strict=True) if sh == s]
            out[k] = TrainBodySection.read(t, f"scene.bodies.{k}", context={
                "carried": carried, "shaft": shaft_names[s]})
        return out

    @pydantic.model_validator(mode="after")
    def _related(self, info):
        if self.model != "lumped3d":
            for key in ("masses_kg", "shafts", "bodies"):
                if key in self.given:
                    raise sc.fail("scene", key, "is for model = 'lumped3d'")
        shaft_names = (info.context or {}).get("shaft_names")
        if self.model == "lumped3d" and shaft_names is not None:
            if self.shafts is None:
                raise sc.SchemaError(
                    "[scene] model = 'lumped3d' needs [[scene.shafts]], one per shaft: "
                    + ", ".join(shaft_names)
                )
            given = {sh.shaft for sh in self.shafts}
            missing = [n for n in shaft_names if n not in given]
            if missing:
                raise sc.SchemaError(f"[[scene.shafts]]: no entry for shaft "
                                     f"{', '.join(missing)} (allowed: one per shaft)")
        if self.bodies and self.shafts:  # a hybrid train: its bearings linear
            refuse_rolling([(f"scene.shafts.{sh.shaft}", sh) for sh in self.shafts],
                           "not with [scene.bodies]")
        needs_a_body(self.integration, self.model == "lumped3d" and bool(self.bodies),
                     "[scene.bodies.<gear>]", modal=False)
        return self


def train_scene(
    table: Any, names: list[str], shafts: list, shaft_names: list, base_dir: str | None = None
) -> tuple:
    """``[scene]`` of a train (:class:`TrainSceneSection`): the torsional or lumped 3D model,
    per-gear inertias (and masses), the shafts and flexible gears (lumped 3D), damping,
    integration. Returns (spec, inertias, masses)."""
    s = TrainSceneSection.read(table, context={"names": list(names), "shafts": list(shafts),
                                               "shaft_names": list(shaft_names)})
    specs, bodies, rims = None, (), ()
    if s.model == "lumped3d":
        specs = tuple(sh.shaft_spec() for sh in s.shafts)
        bodies, rims = _bodies(s.bodies, names, shafts, shaft_names, base_dir, specs)
    spec = SceneSpec(
        model=s.model,
        shafts=specs,
        gear_bodies=bodies,
        gear_rims=rims,
        rotating_frame=s.integration.rotating_frame,
        **dynamics_settings(s),
    )
    inertias = tuple(s.inertias_kg_m2.get(n) for n in names)
    masses = tuple(s.masses_kg.get(n) for n in names)
    return spec, inertias, masses


def _bodies(given: dict, names: list, shafts: list, shaft_names: list, base_dir,
            specs=None) -> tuple:
    """``[scene.bodies.<gear or shaft>]`` (:class:`TrainBodySection` by name): the condensed
    body that carries a shaft's gears (a flexible gear alone on its shaft, named by the gear or
    the shaft; or the gears of a shaft on a body with a ``[pinion_rim]``, named by the shaft,
    ``gears`` listing the gear on each rim). Returns each gear's body reference or ``None`` and
    each gear's rim (0 the webbed wheel's, 1 the pinion rim), () without bodies. A body file
    (not a condensed .npz) is read now: its rim count against the shaft's gears and its pinion
    rim's position against their ``gear_positions_mm`` (``specs``: the shafts), before any
    work."""
    if not given:
        return (), ()
    refs: list = [None] * len(names)
    rims = [0] * len(names)
    for key, t in given.items():
        where = f"scene.bodies.{key}"
        s_ = shaft_names.index(key) if key in shaft_names else shafts[names.index(key)]
        carried = [names[g] for g in range(len(names)) if shafts[g] == s_]
        ref = t.reference(where, base_dir)
        order = carried if t.gears is None else list(t.gears)  # the section's: one per rim
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
