"""The case-file and body-file references, read from the validators themselves.

The validators of :mod:`jaxgear.io` (case files) declare every key where they check it, through
the helpers of :mod:`fem_prep.checks` (``check_keys``, ``subtable``, ``number``, ``number_list``,
``choice``, ``boolean``, ``string``, ``name``) or a typed section (``jaxgear.io._sections``);
those of :mod:`fem_prep.schema` (body files) are typed sections (``fem_prep.sections``), read
as they are. This module runs the case validators on a set of sample files while recording
those calls (read-only: the helpers are wrapped for the duration of the run and restored), and
writes what they declared:
for each table, the keys it accepts and, for each key, its type, unit (from the key's name),
default and allowed range. Nothing here lists a key by hand, so the reference follows the
validators.

The sample files are the embedded cases and bodies, the example case files, and the case
``SAMPLE_OVERLAYS`` (optional tables that no embedded case uses). A range computed from the case
(a face width in normal modules, a depth up to one module) differs between samples and is shown
with the words "depends on the case", with the samples' values.

``python -m docs._gen.schema_reference docs/reference`` writes ``case-file.md``,
``train-file.md``, ``gearbox-file.md`` and ``body-file.md``, which are committed (the pages link
to them in the repository as on the site); ``tests/test_docs_reference.py`` fails when the
committed pages differ from what the validators declare.
"""

from __future__ import annotations

import contextlib
import copy
import dataclasses
import pathlib
import re
import sys
import tomllib
import types
import typing
import warnings
from collections.abc import Callable, Iterator
from typing import Any

import fem_prep
from fem_prep import checks, schema as body_schema

ROOT = pathlib.Path(__file__).resolve().parents[2]

#: the helpers of fem_prep.checks that declare a key
TRACED = ("check_keys", "subtable", "number", "number_list", "choice", "boolean", "string", "name")

#: the unit words of key names (units are in key names: README, STYLE) and how they print; a
#: key's unit is the longest run of these words (and ``per``) at its end, read by :func:`unit`
UNIT_WORDS = {
    "mm": "mm", "um": "µm", "m": "m", "mm2": "mm²", "m2": "m²", "m3": "m³",
    "N": "N", "kN": "kN", "Nm": "N·m", "kg": "kg", "GPa": "GPa", "MPa": "MPa", "deg": "deg", "rad": "rad",
    "s": "s", "h": "h", "Hz": "Hz", "rpm": "1/min", "SI": "SI", "HB": "HB", "K": "K", "C": "°C",
}
#: the second word of a two-word unit without ``per`` that divides (a rate, a density):
#: ``_rad_s`` rad/s, ``_mm2_s`` mm²/s, ``_kg_m3`` kg/m³; any other pair multiplies (``_kg_m2``)
DIVIDING = {"s", "m3"}

#: optional tables no embedded case holds, added to an embedded pair case to trace them
SAMPLE_OVERLAYS: dict[str, str] = {
    "deviations": """
[deviations]
grade = 6
seed = 1
revolutions = 1
positions_per_pitch = 16
"""
    + "".join(
        f"""
[deviations.{member}]
pitch_um = [{", ".join(["0.0"] * teeth)}]
runout_um = 8.0
runout_phase_deg = 0.0
profile_slope_um = 1.0
profile_form_um = 1.0
helix_slope_um = 1.0
helix_form_um = 1.0
"""
        for member, teeth in (("pinion", 45), ("gear", 86))  # accessory-spur's teeth
    ),
    "robust": """
[robust]
grade = 6
samples = 20
speeds_rad_s = [800.0]
""",
    "optimise": """
[optimise]
objective = "robust_te_rms"
vars = ["tip_relief.depth", "tip_relief.extent"]
torques = [40.0, 80.0, 3]
reduce = "max"
method = "lbfgs"
max_iterations = 10
[optimise.bounds]
"tip_relief.depth" = [0.0, 2.0]
""",
    "optimise lp": """
[optimise]
objective = "line_load_lp"
lp_order = 8
""",
    "optimise least_safety": """
[optimise]
objective = "least_safety"
vars = ["pinion.crowning.depth"]
te_limit_um = 1.0
""",
    "lubricant": """
[operating]
torque_Nm = 80.0
speed_rad_s = 800.0
[lubricant]
viscosity_40C_mm2_s = 220.0
viscosity_100C_mm2_s = 19.0
density_kg_m3 = 890.0
pressure_viscosity_per_GPa = 20.0
oil_temperature_C = 80.0
roughness_Ra_um = [0.4, 0.5]
friction_coefficient = 0.05
film = "pan-hamrock"
fzg_load_stage = 10
scuffing_temperature_C = 320.0
integral_scuffing_temperature_C = 300.0
bulk_temperature_C = 95.0
scuffing_lubricant_factor = 1.0
structural_factor = 1.0
relative_structural_factor = 1.0
micropitting_load_stage = 8
""",
    "housing": """
[housing]
width_mm = 250.0
height_mm = 160.0
wall_thickness_mm = 10.0
length_mm = 110.0
bore_diameter_mm = 50.0
foot_size_mm = 30.0
mesh_size_mm = 40.0
layers = 1
mesher = "structured"
element = "tet10"
youngs_modulus_GPa = 70.0
poisson_ratio = 0.33
density_kg_m3 = 2700.0
cutoff_Hz = 3000.0
loss_factor = 0.02
coupling = "rigid"
[housing.points_mm]
top = [50.0, 80.0, 0.0]
""",
    "housing mesh file": """
[housing]
mesh_file = "housing.msh"
mesh_unit = "mm"
offset_mm = [0.0, 0.0, 0.0]
highest_mesh_frequency_Hz = 2000.0
[[housing.seats]]
centre_mm = [0.0, 80.0, 75.0]
axis = [1.0, 0.0, 0.0]
diameter_mm = 50.0
width_mm = 10.0
name = "input_a"
[[housing.feet]]
x_mm = [0.0, 30.0]
y_mm = [0.0, 30.0]
""",
    "whine": """
[whine]
speed_min_rad_s = 50.0
speed_max_rad_s = 1600.0
speeds = 10
harmonics = 8
method = "harmonic-balance"
positions_per_period = 64
""",
    "acoustics": """
[acoustics]
method = "bem"
band_Hz = [100.0, 4000.0]
frequencies = 24
rank = 64
cache = true
density_kg_m3 = 1.21
sound_speed_m_s = 343.0
[[acoustics.microphones]]
name = "front"
position_mm = [150.0, -1000.0, 80.0]
""",
    "modifications": """
[modifications]
tip_relief = { depth_um = 10.0, extent = 0.2, shape = "parabolic" }
root_relief = { depth_um = 5.0, extent = 0.2 }
crowning = { depth_um = 2.0 }
end_relief = { depth_um = 5.0, extent = 0.1, edge = "both" }
helix_slope = { deviation_um = 1.0 }
profile_deviation = { roll_fraction = [0.0, 0.5, 1.0], deviation_um = [0.0, 1.0, 0.0] }
[modifications.pinion]
crowning = { depth_um = 3.0 }
[modifications.gear]
tip_relief = { depth_um = 8.0 }
""",
    "rating": """
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
sigma_H_lim_MPa = 1500.0
sigma_F_lim_MPa = 430.0
treatment = "case_hardened"
[operating]
torque_Nm = 80.0
speed_rpm = 3000.0
[rating]
application_factor = 1.25
life_h = 20000.0
viscosity_40C_mm2_s = 220.0
roughness_Rz_flank_um = 4.8
roughness_Rz_root_um = 20.0
accuracy_grade = 6
tip_relief_um = 15.0
min_safety_pitting = 1.0
min_safety_bending = 1.4
K_v = 1.1
K_Hbeta = 1.15
K_Fbeta = 1.12
K_Halpha = 1.05
K_Falpha = 1.05
""",
    "torsional scene": """
[scene]
model = "torsional"
pinion_inertia_kg_m2 = 1e-4
gear_inertia_kg_m2 = 5e-4
motor_inertia_kg_m2 = 1e-2
motor_shaft_stiffness_Nm_per_rad = 1e4
load_inertia_kg_m2 = 1e-2
load_shaft_stiffness_Nm_per_rad = 1e4
[scene.damping]
model = "rayleigh"
alpha_per_s = 10.0
beta_s = 1e-7
""",
}

#: a pair's load spectrum, each form with every key (on the rating's overlay)
SAMPLE_OVERLAYS |= {
    f"rating spectrum {form}": SAMPLE_OVERLAYS["rating"] + "[rating.spectrum]\n" + keys
    for form, keys in (
        ("hours", "torque_Nm = [80.0, 40.0]\nspeed_rpm = [3000.0, 3000.0]\nhours = [5e3, 1.5e4]\n"),
        ("cycles", "torque_Nm = [80.0, 40.0]\nspeed_rpm = 3000.0\ncycles = [9e8, 2.7e9]\n"),
        ("share", "torque_Nm = [80.0, 40.0]\nspeed_rpm = 3000.0\ntime_share = [0.25, 0.75]\n"),
        ("series", ("series_torque_Nm = [80.0, 40.0, 60.0]\nseries_speed_rpm = [3000.0, 3000.0, "
                    "2000.0]\nseries_step_s = 0.1\nlevels = 4\n")),
    )
}

#: where paths → the table they belong to (array indices collapsed: ``gears[2]`` → ``gears[]``)
_INDEX = re.compile(r"\[\d+\]")
#: the per-member modification tables of a pair: the same entries as ``[modifications]``
_MEMBER_MODS = re.compile(r"^modifications\.(pinion|gear)\.")
#: tables whose keys are names the file chooses (not schema keys)
NAMED_KEYS = {
    "optimise.bounds": "a design variable of `vars` (E* for depths, Γ for extents, µm for a "
    "bearing's `clearance`)",
    "optimise.choices": "one rolling bearing of the scene, `\"<shaft>.bearings[<k>]\"`: an array "
    "of candidates, the bearing choice's (docs/bearings.md, \"As a design variable\"): "
    "catalogue names or inline tables of a scene bearing's keys without `position_mm` "
    "(`{ catalogue = \"30205\", arrangement = \"O\" }`, `{ kind = ..., bore_mm = ... }`; "
    "`name`: the candidate's name in the ranking)",
    "housing.points_mm": "a point's name: [x, y, z] in the scene frame (mm), read at the "
    "housing's outer skin node nearest it",
}
#: the default ``name`` of a case (its file's name, without the extension)
FILE_NAME = "the-file-name"
#: what stands for a name the file gives a gear or a shaft
NAME = "<name>"
#: what stands for a mesh's name, its driving and driven gears' names (``[rating.<mesh>]``)
MESH = "<driving>-<driven>"


def _is_mesh(part: str, names: frozenset) -> bool:
    """Whether a table name is a mesh's: two of the file's gear names joined by a hyphen."""
    return any(part == f"{a}-{b}" for a in names for b in names if a != b)


def table_path(where: str, names: frozenset = frozenset()) -> str:
    """A validator's ``where`` (``gears[2]``, ``scene.bodies.idler``) → its table's name, the
    file's own ``names`` (of gears and shafts) replaced by ``<name>``."""
    where = _MEMBER_MODS.sub("modifications.", _INDEX.sub("[]", where))
    parts = [NAME if p in names else p for p in where.split(".")] if where else []
    parts = [NAME if p.removesuffix("[]") in names else p for p in parts]
    parts = [MESH if _is_mesh(p, names) else p for p in parts]
    if parts[:2] == ["modifications", NAME] and len(parts) > 2:  # a train gear's own entries
        parts = ["modifications", *parts[2:]]
    return ".".join(parts)


@dataclasses.dataclass
class KeyInfo:
    """What the validators declared about one key (over every sample)."""

    kind: set = dataclasses.field(default_factory=set)
    defaults: set = dataclasses.field(default_factory=set)
    allowed: set = dataclasses.field(default_factory=set)
    required: bool = False
    accepted: bool = False  # listed by check_keys/subtable (a check alone does not accept a key)


@dataclasses.dataclass
class Schema:
    """Tables (``''`` the top level) → {key: KeyInfo}; keys only accepted carry an empty info."""

    tables: dict[str, dict[str, KeyInfo]] = dataclasses.field(default_factory=dict)
    names: frozenset = frozenset()  # the sample file's gear and shaft names

    def table(self, where: str) -> dict[str, KeyInfo]:
        return self.tables.setdefault(table_path(where, self.names), {})

    def key(self, where: str, key: str) -> KeyInfo:
        key = NAME if key in self.names else MESH if _is_mesh(str(key), self.names) else str(key)
        head, dot, leaf = key.rpartition(".")
        if dot and table_path(where, self.names) not in NAMED_KEYS:
            # an inline table's key as its messages write it: [body] holes.count
            where, key = f"{where}.{head}" if where else head, leaf
        return self.table(where).setdefault(key, KeyInfo())

    def merged(self) -> Schema:
        """The tables of an array of tables that the validator names by the element's name
        (``gears.<name>``) merged into the array's (``gears[]``)."""
        out = Schema(names=self.names)
        for t, keys in self.tables.items():
            head, _, tail = t.partition("." + NAME)
            if tail == "" and t.endswith("." + NAME) and head + "[]" in self.tables:
                t = head + "[]"
            elif tail and head + "[]" in self.tables:
                t = head + "[]" + tail
            into = out.tables.setdefault(t, {})
            listed = any(info.accepted for info in keys.values())
            for k, info in keys.items():
                if listed and not info.accepted:  # checked by a shared parser, refused here
                    continue
                have = into.setdefault(k, KeyInfo())
                have.kind |= info.kind
                have.defaults |= info.defaults
                have.allowed |= info.allowed
                have.required |= info.required
                have.accepted |= info.accepted
        for t, keys in out.tables.items():  # a key that is a table of its own
            for k, info in keys.items():
                inner = table_path(f"{t}.{k}.x".lstrip("."))[:-2]  # [modifications.pinion]
                if inner in out.tables or inner + "[]" in out.tables:
                    info.kind.add("table")
        return out

    def accepted(self) -> dict[str, set[str]]:
        """Each table's accepted keys (the user-named ones left out)."""
        return {t: {k for k in keys if t not in NAMED_KEYS} for t, keys in self.tables.items()}


def _fmt(v: Any) -> str:
    return checks.fmt(v)


def _type_kind(t) -> tuple[str, str]:
    """(kind, allowed) of one type of a typed section's field (``jaxgear.io._sections``)."""
    from fem_prep import sections

    base = typing.get_origin(t) is typing.Annotated and t.__origin__ or t
    rng = sections._marker_in(t, sections.Range)
    if typing.get_origin(base) is dict:
        return "table", "a table by gear name (a train's)"
    if rng is not None and rng.array:
        text = str(rng.interval)
        if rng.length:
            text += f", length {rng.length}"
        elif rng.min_length:
            text += f", at least {rng.min_length} values"
        return f"array of {'integers' if rng.integer else 'numbers'}", text + rng.note
    if rng is not None:
        return ("integer" if rng.integer else "number"), str(rng.interval) + rng.note
    names = sections._choices(base)
    if names:
        kind = "array" if typing.get_origin(base) is list else "string"
        return kind, ", ".join(repr(c) for c in names)
    return {bool: "boolean", str: "string"}.get(base, ""), ""


def _by_name(annotation):
    """The ``dict[str, ...]`` type of a section's field that is a table by name (optional or
    not), or None."""
    if typing.get_origin(annotation) is dict:
        return annotation
    args = typing.get_args(annotation)
    if typing.get_origin(annotation) in (typing.Union, types.UnionType) and type(None) in args:
        return next((a for a in args if typing.get_origin(a) is dict), None)
    return None


def _section_kind(field) -> tuple[set, set]:
    """(kinds, allowed ranges) of a typed section's field (``jaxgear.io._sections``): a number
    or an integer in its range, an array of numbers, a name out of a few, a boolean, a string;
    a field of several kinds (``one_of``) each of them, its range once; a field the section
    leaves to another reader (``Any``) none."""
    from fem_prep import sections

    t, args = field.annotation, typing.get_args(field.annotation)
    if typing.get_origin(t) in (typing.Union, types.UnionType) and type(None) in args:
        t = next(a for a in args if a is not type(None))  # optional
    if any(isinstance(m, sections.Range) for m in field.metadata):  # pydantic keeps a field's
        t = typing.Annotated[(t, *field.metadata)]  # own metadata apart from its type
    inner = t.__origin__ if typing.get_origin(t) is typing.Annotated else t
    if typing.get_origin(inner) not in (typing.Union, types.UnionType):
        kind, allowed = _type_kind(t)
        return ({kind} if kind else set()), ({allowed} if allowed else set())
    members = typing.get_args(inner)  # one_of: each kind, the first's range in full
    kinds = [_type_kind(m)[0] for m in members]
    others = []
    for kind, m in zip(kinds[1:], members[1:], strict=True):
        rng = sections._marker_in(m, sections.Range)
        if kind.startswith("array of "):
            size = f" of {rng.length}" if rng.length else (
                f" of at least {rng.min_length}" if rng.min_length else "")
            others.append(f"an array{size} in {rng.interval}")
        else:
            others.append(_type_kind(m)[1])
    return set(kinds), {"; or ".join([_type_kind(members[0])[1], *others])}


class _Recorder:
    """Wraps the helpers of :mod:`fem_prep.checks` while a validator runs."""

    def __init__(self, schema: Schema):
        self.schema = schema
        self.depth_in_body = 0  # a case loading a body file: the body's keys are not the case's

    def record(self, name: str, args: tuple, kw: dict) -> None:
        if self.depth_in_body:
            return
        s = self.schema
        if name == "check_keys":
            table, allowed, where = args[:3]
            for k in allowed:
                s.key(where, k).accepted = True
            return
        if name == "subtable":
            data, key, where = args[:3]
            allowed = args[3] if len(args) > 3 else kw.get("allowed")
            inner = f"{where}.{key}" if where else str(key)
            if "." not in str(key):  # a dotted key names a table further down (a train's gear)
                info = s.key(where, key)
                info.kind.add("table")
                info.required |= bool(kw.get("required"))
            s.table(inner)
            for k in allowed or ():
                s.key(inner, k).accepted = True
            return
        table, key, where = args[:3]
        info = s.key(where, key)
        default = (
            args[3] if len(args) > 3 and name != "choice" else kw.get("default", checks.MISSING)
        )
        if name == "choice":
            default = args[4] if len(args) > 4 else kw.get("default", checks.MISSING)
            info.kind.add("string")
            info.allowed.add(", ".join(repr(c) for c in args[3]))
        elif name == "number":
            info.kind.add("integer" if kw.get("integer") else "number")
            info.allowed.add(str(checks.interval(kw.get("allowed"))) + kw.get("note", ""))
        elif name == "number_list":
            info.kind.add("array of numbers")
            rng = str(checks.interval(kw.get("allowed")))
            if kw.get("length"):
                rng += f", length {kw['length']}"
            elif kw.get("min_length"):
                rng += f", at least {kw['min_length']} values"
            info.allowed.add(rng + kw.get("note", ""))
        elif name == "boolean":
            info.kind.add("boolean")
        else:  # string, name
            info.kind.add("string" if name == "string" else "name")
        if default is checks.MISSING:
            info.required = True
        elif default is not None:
            info.defaults.add("the file's name" if default == FILE_NAME else _fmt(default))

    def record_section(self, cls, table, where: str, context) -> None:
        """A typed section read (``jaxgear.io._sections.Section.read``): every key its model
        declares, with its type, default and range (sub-tables: their own sections)."""
        if self.depth_in_body or not isinstance(table, dict):
            return
        from fem_prep import sections
        from jaxgear.io._sections import Needed

        s = self.schema
        named = [k for k in ("meshes", "members", "planets") if k in cls.model_fields]
        for key in (*cls.file_keys(context), *named):
            field = cls.model_fields[key]
            sub = sections._sections(field.annotation)
            if typing.get_origin(field.annotation) is dict and sub is not None:
                for name in (context or {}).get(key, ()):  # tables by name: the file's
                    s.key(where, name).accepted = True
                    s.key(where, name).kind.add("table")
                    self.record_section(sub, table.get(name, {}), f"{where}.{name}", None)
                if key in named:
                    continue
            by_name = _by_name(field.annotation)
            if by_name is not None:  # a table by name (the train's gears or shafts)
                info = s.key(where, key)
                info.accepted = True
                info.kind.add("table")
                info.required |= field.is_required()
                inner = table.get(key)
                given = inner if isinstance(inner, dict) and inner else {NAME: {}}
                for name, value in given.items():  # the file's names (or <name>)
                    if sub is not None:  # of tables
                        self.record_section(sub, value if isinstance(value, dict) else {},
                                            f"{where}.{key}.{name}", None)
                        continue
                    kind, allowed = _type_kind(typing.get_args(by_name)[1])  # of values
                    entry = s.key(f"{where}.{key}", name)
                    entry.accepted = True
                    entry.kind |= {kind} - {""}
                    entry.allowed |= {allowed} - {""}
                    entry.required |= field.is_required()
                continue
            info = s.key(where, key)
            info.accepted = True
            arms = (field.annotation, *typing.get_args(field.annotation))
            if sub is not None and not any(typing.get_origin(a) is list for a in arms):  # a table
                info.kind.add("table")
                info.required |= sections.range_of(field, Needed) is not None
                inner = table.get(key)
                self.record_section(sub, inner if isinstance(inner, dict) else {},
                                    f"{where}.{key}", None)
                continue
            if sub is not None:  # an array of tables
                info.kind.add("table")
                for k, entry in enumerate(table.get(key) or [{}]):
                    self.record_section(sub, entry if isinstance(entry, dict) else {},
                                        f"{where}.{key}[{k}]", None)
                continue
            if table_path(f"{where}.{key}") in NAMED_KEYS:  # named values: its own section
                info.kind.add("table")
                continue
            kinds, allowed = _section_kind(field)
            info.kind |= kinds
            info.allowed |= allowed
            if field.is_required() or sections.range_of(field, Needed) is not None:
                info.required = True
            elif field.get_default(call_default_factory=True) is not None and kinds:
                info.defaults.add(_fmt(field.get_default(call_default_factory=True)))
            elif isinstance(field.json_schema_extra, dict) and "default" in field.json_schema_extra:
                info.defaults.add(field.json_schema_extra["default"])  # a default in words

    @contextlib.contextmanager
    def active(self) -> Iterator[None]:
        # the helpers are read as ``fem_prep.checks.X`` and as ``fem_prep.schema.X`` (re-exported)
        saved = {n: getattr(checks, n) for n in TRACED}
        saved_load = fem_prep.load_body
        from jaxgear.io._sections import Section

        saved_read = Section.read.__func__  # fem_prep.sections.Section's, inherited

        def read(cls, table, where=None, *, context=None):
            self.record_section(cls, table, cls.WHERE if where is None else where, context)
            return saved_read(cls, table, where, context=context)

        Section.read = classmethod(read)
        saved_of_file = Section.__dict__["of_file"]

        def of_file(cls, data, key=None, *, required=False, context=None):
            if not (self.depth_in_body):  # a file's table, or required
                info = self.schema.key("", cls.WHERE if key is None else key)
                info.kind.add("table")
                info.required |= required
            return saved_of_file.__func__(cls, data, key, required=required, context=context)

        Section.of_file = classmethod(of_file)

        def wrap(name, f):
            def traced(*args, **kw):
                self.record(name, args, kw)
                return f(*args, **kw)

            return traced

        def load_body(*args, **kw):
            self.depth_in_body += 1
            try:
                return saved_load(*args, **kw)
            finally:
                self.depth_in_body -= 1

        for n in TRACED:
            traced = wrap(n, saved[n])
            setattr(checks, n, traced)
            setattr(body_schema, n, traced)
        fem_prep.load_body = load_body
        try:
            yield
        finally:
            for n, f in saved.items():
                setattr(checks, n, f)
                setattr(body_schema, n, f)
            fem_prep.load_body = saved_load
            del Section.read  # the inherited one again
            Section.of_file = saved_of_file


# [acoustics] radiates a housed whine: its sample carries [housing] and [whine] too
SAMPLE_OVERLAYS["acoustics"] = (SAMPLE_OVERLAYS["housing"] + SAMPLE_OVERLAYS["whine"]
                                + SAMPLE_OVERLAYS["acoustics"])
# an acoustic objective runs on a housed whine too ([acoustics]: sound_power's radiation)
SAMPLE_OVERLAYS["optimise acoustic"] = SAMPLE_OVERLAYS["acoustics"] + """
[optimise]
objective = "sound_power"
reduce = "quantile"
quantile = 0.9
a_weighted = false
"""


def case_samples() -> Iterator[tuple[dict, str | None]]:
    """(parsed TOML, base folder) of every sample case file."""
    import jaxgear.io as jio

    for name in jio.list_cases():
        data = tomllib.loads(jio.embedded_case_text(name))
        if "stages" not in data:  # a gearbox's file names its stages' cases (their own keys)
            yield data, None
    for path in sorted((ROOT / "examples").glob("*.toml")):
        yield tomllib.loads(path.read_text(encoding="utf-8")), str(path.parent)
    # the rolling bearings' modified life: the rolling-bearing example at a speed with [bearings]
    data = tomllib.loads((ROOT / "examples" / "accessory-lumped3d-rolling.toml").read_text("utf-8"))
    data["operating"]["speed_rad_s"] = 300.0
    data["bearings"] = {"contamination_factor": 0.5, "reliability_percent": 95.0,
                        "viscosity_mm2_per_s": 20.0}
    yield data, str(ROOT / "examples")
    # and a lumped train's: the rolling-bearing idler train with [bearings]
    data = tomllib.loads((ROOT / "examples" / "idler-train-lumped3d-rolling.toml").read_text(
        "utf-8"))
    data["operating"]["speed_rad_s"] = 300.0
    data["bearings"] = {"contamination_factor": 0.5, "reliability_percent": 95.0,
                        "viscosity_mm2_per_s": 20.0}
    yield data, str(ROOT / "examples")
    base = tomllib.loads(jio.embedded_case_text("accessory-spur"))
    for text in SAMPLE_OVERLAYS.values():
        data = copy.deepcopy(base)
        extra = tomllib.loads(text)
        for k in extra:
            data.pop(k, None)
        data.update(extra)
        yield data, None
    # a planetary ring with its pinion-type cutter (the Weber model of its teeth)
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    data["mesh"]["stiffness"] = "weber"
    ring = next(g for g in data["gears"] if g["name"] == data["planetary"]["ring_gear"])
    ring.update(cutter_teeth=36, cutter_profile_shift=0.0, cutter_tip_radius_coeff=0.3)
    yield data, None
    # a planetary stage's [deviations]: every member's table with every key
    data = tomllib.loads((ROOT / "examples" / "planetary-hunting.toml").read_text("utf-8"))
    for member, teeth in (("sun", 19), ("planet_1", 17), ("planet_2", 17), ("planet_3", 17),
                          ("ring", 53)):
        data["deviations"][member] = {
            "pitch_um": [0.0] * teeth, "profile_slope_um": 1.0, "profile_form_um": 1.0,
            "helix_slope_um": 1.0, "helix_form_um": 1.0,
        }
    yield data, str(ROOT / "examples")
    # each planet's two flanks with their own tables, every key
    data = copy.deepcopy(data)
    for planet in ("planet_1", "planet_2", "planet_3"):
        values = data["deviations"].pop(planet)
        data["deviations"][planet] = {"sun_flank": dict(values), "ring_flank": dict(values)}
    yield data, str(ROOT / "examples")
    # a train gear's own modifications
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    data.setdefault("modifications", {})["idler"] = {"root_relief": {"depth_um": 2.0}}
    yield data, None
    # a train's gear whine in the frequency domain
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    data.update(tomllib.loads(SAMPLE_OVERLAYS["whine"]))
    yield data, None
    # a planetary stage's gear whine (the input member's speeds)
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    data.update(tomllib.loads(SAMPLE_OVERLAYS["whine"]))
    yield data, None
    # a train rated to ISO 6336: the shared [rating] and each mesh's own
    data = tomllib.loads(jio.embedded_case_text("accessory-idler-train"))
    data["material"].update(sigma_H_lim_MPa=1500.0, sigma_F_lim_MPa=430.0)
    data["operating"]["speed_rpm"] = 6000.0
    shared = tomllib.loads(SAMPLE_OVERLAYS["rating"])["rating"]
    data["rating"] = dict(shared)
    for mesh in data["meshes"]:  # each mesh's own [rating.<driving>-<driven>], every key
        data["rating"][f"{mesh['driving']}-{mesh['driven']}"] = dict(shared)
    yield data, None
    # the same train under a load spectrum of its input, each form with every key
    for key in [k for k in SAMPLE_OVERLAYS if k.startswith("rating spectrum ")]:
        spectrum = tomllib.loads(SAMPLE_OVERLAYS[key])["rating"]["spectrum"]
        yield data | {"rating": dict(shared) | {"spectrum": spectrum}}, None
    # a lumped 3D train on a flexible housing (its [housing] as a pair's)
    data = tomllib.loads(jio.embedded_case_text("two-stage"))
    for overlay in ("housing", "housing mesh file"):
        data["housing"] = tomllib.loads(SAMPLE_OVERLAYS[overlay])["housing"]
        yield copy.deepcopy(data), None
    # its radiated sound: [acoustics] beside [housing] and [whine]
    data.update(tomllib.loads(SAMPLE_OVERLAYS["whine"]))
    data.update(tomllib.loads(SAMPLE_OVERLAYS["acoustics"]))
    yield copy.deepcopy(data), None
    # jaxgear optimise on a housed idler train's noise: [optimise] beside [housing], [whine]
    data = tomllib.loads((ROOT / "examples" / "idler-train-lumped3d.toml").read_text("utf-8"))
    for overlay in ("housing", "whine", "acoustics"):
        data[overlay] = tomllib.loads(SAMPLE_OVERLAYS[overlay])[overlay]
    data["optimise"] = tomllib.loads(SAMPLE_OVERLAYS["optimise acoustic"])["optimise"] | {
        "vars": ["tip_relief.depth", "crowning.depth"], "method": "lbfgs",
        "max_iterations": 10, "bounds": {"tip_relief.depth": [0.0, 2.0]}}
    yield data, str(ROOT / "examples")
    # both members condensed: the flexible case with a condensed pinion too
    data = tomllib.loads(jio.embedded_case_text("accessory-spur-flexible"))
    data["scene"]["pinion_body"] = {"body": "accessory-pinion"}
    yield data, None


def is_train(data: dict) -> bool:
    """Whether a parsed case file is a train case (the loader's own test)."""
    from jaxgear.io import _train_file

    return _train_file.is_train(data)


def gear_and_shaft_names(data: dict) -> frozenset:
    """The names a train file gives its gears and shafts."""
    gears = [g for g in data.get("gears", []) if isinstance(g, dict)]
    return frozenset(g.get("name") for g in gears) | {g.get("shaft") for g in gears} - {None}


def trace_cases() -> tuple[Schema, Schema]:
    """The schemas of pair case files and of train case files, as the validator declares them."""
    import jaxgear.io as jio

    pair, train = Schema(), Schema()
    for data, base in case_samples():
        train_case = is_train(data)
        schema = train if train_case else pair
        schema.names = gear_and_shaft_names(data) if train_case else frozenset()
        rec = _Recorder(schema)
        with rec.active(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            (jio.parse_train if train_case else jio.parse_case)(data, FILE_NAME, base)
    pair, train = pair.merged(), train.merged()
    for schema, train_case in ((pair, False), (train, True)):
        samples = [(d, b) for d, b in case_samples() if is_train(d) == train_case]
        for data, base in samples:
            schema.names = gear_and_shaft_names(data) if train_case else frozenset()
            probe_undeclared(
                schema,
                [(data, base)],
                lambda d, b: (
                    lambda x: (jio.parse_train if train_case else jio.parse_case)(x, "p", b)
                ),
            )
    return pair, train


def gearbox_samples() -> Iterator[tuple[dict, str | None]]:
    """(parsed TOML, base folder) of every sample gearbox file (``[[stages]]``)."""
    import jaxgear.io as jio

    for name in jio.list_cases():
        data = tomllib.loads(jio.embedded_case_text(name))
        if "stages" in data:
            yield data, None
    for path in sorted((ROOT / "examples").glob("*.toml")):
        data = tomllib.loads(path.read_text(encoding="utf-8"))
        if "stages" in data:
            yield data, str(path.parent)


def trace_gearbox() -> Schema:
    """The gearbox file's schema (``[[stages]]``), as :func:`jaxgear.io._gearbox_file.
    parse_gearbox` declares it; the stages' own case files are loaded without recording (their
    keys are the pair's and the train's references)."""
    import jaxgear.io as jio
    from jaxgear.io._gearbox_file import parse_gearbox

    schema = Schema()
    rec = _Recorder(schema)

    def load_stage(name):
        rec.depth_in_body += 1  # a stage's own file, as a body file of a case: not recorded
        try:
            return jio.load_case(name)
        finally:
            rec.depth_in_body -= 1

    samples = list(gearbox_samples())
    for data, base in samples:
        with rec.active(), warnings.catch_warnings():
            warnings.simplefilter("ignore")
            parse_gearbox(data, FILE_NAME, base, load_stage)
    schema = schema.merged()
    probe_undeclared(
        schema, samples, lambda d, b: lambda x: parse_gearbox(x, "p", b, jio.load_case)
    )
    return schema


def tables_of(data: dict, path: tuple = ()) -> Iterator[tuple]:
    """The path (keys and array indices) of every table of a parsed file."""
    yield path
    table = data
    for part in path:
        table = table[part]
    for key, value in table.items():
        if isinstance(value, dict):
            yield from tables_of(data, (*path, key))
        elif isinstance(value, list) and value and all(isinstance(v, dict) for v in value):
            yield from tables_of(data, (*path, key, 0))


def where_of(path: tuple) -> str:
    """A table's path as the validators write it (``scene.shafts[0]``)."""
    text = ""
    for part in path:
        text += f"[{part}]" if isinstance(part, int) else (f".{part}" if text else part)
    return text


#: wrong values given to a key whose checks the helpers do not declare: the validator's error
#: then says what the key allows
PROBES = (-1e300, "zz_wrong")
_TOLD = re.compile(r"^\[(?:[^\[\]]|\[\d+\])*\] (?P<key>[\w.-]+)(?: = .*?)?: (?P<what>.*)$")


def _told(parse: Callable[[dict], Any], data: dict, path: tuple, key: str, value) -> str | None:
    """What the validator says about ``key`` = ``value`` in the table at ``path``, or None when
    it accepts the value or speaks of something else."""
    data = copy.deepcopy(data)
    table = data
    for part in path:
        table = table[part]
    table[key] = value
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            parse(data)
    except ValueError as err:
        m = _TOLD.match(str(err))
        if m and m.group("key").rpartition(".")[2] == key:
            return m.group("what").split(", got ")[0]
    return None


def probe_undeclared(schema: Schema, samples, parse_of) -> None:
    """Fill in the ``allowed`` of the keys checked by their table's own code (no helper call
    declared them): the validator's own words for a wrong value, from the first sample file that
    holds the table."""
    for data, base in samples:
        parse = parse_of(data, base)
        for path in tables_of(data):
            table = table_path(where_of(path), schema.names)
            head, _, tail = table.partition("." + NAME)
            if table not in schema.tables and head + "[]" in schema.tables:
                table = head + "[]" + tail
            for key, info in schema.tables.get(table, {}).items():
                if info.kind or info.allowed or key == NAME or table in NAMED_KEYS:
                    continue
                for value in PROBES:
                    what = _told(parse, data, path, key, value)
                    if what and ("allowed" in what or "must" in what):
                        info.allowed.add(
                            what.removeprefix("out of range, ").removeprefix("allowed ")
                        )
                        break


def trace_bodies() -> Schema:
    """The body-file schema, as :func:`fem_prep.schema.parse_body`'s typed sections declare it
    (:class:`fem_prep.schema.BodyFile` and the sections of its tables): each key's type, range,
    default; a range or default that other keys decide in the section's own words."""
    schema = Schema()
    schema.table("")
    _body_section(schema, body_schema.BodyFile, "")
    return schema.merged()


def _body_section(schema: Schema, cls, where: str) -> None:
    """Record the keys of a body file's section ``cls`` (:mod:`fem_prep.sections`) at
    ``where``, its sub-tables in their turn (an array of tables as ``key[0]``)."""
    from fem_prep import sections

    for key, field in cls.model_fields.items():
        info = schema.key(where, key)
        info.accepted = True
        info.required |= field.is_required()
        words = field.json_schema_extra if isinstance(field.json_schema_extra, dict) else {}
        sub = sections._sections(field.annotation)
        if sub is not None:
            info.kind.add("table")
            arms = (field.annotation, *typing.get_args(field.annotation))
            inner = key + ("[0]" if any(typing.get_origin(a) is list for a in arms) else "")
            _body_section(schema, sub, f"{where}.{inner}" if where else inner)
            continue
        rng = sections.range_of(field)
        if rng is not None:
            info.kind.add("integer" if rng.integer else "number")
            info.allowed.add(words.get("allowed") or str(rng.interval) + rng.note)
        elif sections._choices(field.annotation):
            info.kind.add("string")
            info.allowed.add(", ".join(repr(c) for c in sections._choices(field.annotation)))
        else:
            info.kind.add("boolean" if field.annotation is bool else "name")
        default = words.get("default") or field.get_default(call_default_factory=True)
        if default is not None and not info.required:
            info.defaults.add(default if "default" in words else _fmt(default))


def unit(key: str) -> str:
    """The unit a key's name ends in: ``viscosity_40C_mm2_s`` mm²/s, ``stiffness_N_per_um``
    N/µm, ``torsional_stiffness_Nm_per_rad`` N·m/rad, ``c_N_per_mm_per_um`` N/mm/µm,
    ``damping_per_s`` 1/s, ``inertia_kg_m2`` kg·m²; "" when it ends in none (a word of the
    quantity's name is left in front)."""
    words = key.split("_")
    n = len(words)
    while n > 1 and (words[n - 1] in UNIT_WORDS or words[n - 1] == "per"):
        n -= 1
    tail = words[n:]
    while tail and tail[-1] == "per":  # "per" ends no unit
        tail.pop()
    if not tail:
        return ""
    groups, group = [], []
    for w in tail:
        if w == "per":
            groups.append(group)
            group = []
        else:
            group.append(UNIT_WORDS[w])
    groups.append(group)
    if len(groups) == 1 and len(tail) == 2 and tail[1] in DIVIDING:
        groups = [[UNIT_WORDS[tail[0]]], [UNIT_WORDS[tail[1]]]]
    text = ["·".join(g) for g in groups]
    return "/".join([text[0] or "1", *text[1:]])


def _cell(values: set, many: str = "depends on the case") -> str:
    vals = sorted(v for v in values if v)
    if not vals:
        return ""
    if len(vals) == 1:
        return vals[0]
    return f"{many}: " + "; ".join(vals[:3]) + (" …" if len(vals) > 3 else "")


def _escape(text: str) -> str:
    return text.replace("|", "\\|")


def heading(table: str) -> str:
    """``scene.shafts[].bearings[]`` → ``[[scene.shafts.bearings]]`` (an array of tables)."""
    if table == "":
        return "top level"
    bare = table.replace("[]", "")
    return f"[[{bare}]]" if table.endswith("[]") else f"[{bare}]"


def markdown(schema: Schema, title: str, intro: str, notes: dict[str, str] | None = None) -> str:
    """The reference page of one file kind."""
    out = [f"# {title}", "", intro, ""]
    notes = notes or {}
    # the tables in the order the validator checks them, each with its sub-tables
    order = list(schema.tables)
    top = {}
    for i, t in enumerate(order):
        top.setdefault(t.split(".")[0], i)
    for table in sorted(order, key=lambda t: (t != "", top[t.split(".")[0]], order.index(t))):
        keys = schema.tables[table]
        out += [f"## `{heading(table)}`", ""]
        if table in NAMED_KEYS:
            out += [f"Keys: {NAMED_KEYS[table]}.", ""]
            continue
        if table in notes:
            out += [notes[table], ""]
        out += ["| key | type | unit | default | allowed |", "|---|---|---|---|---|"]
        for key in sorted(keys):
            info = keys[key]
            kind = " or ".join(sorted(info.kind)) or ("table" if not info.allowed else "")
            default = "required" if info.required and not info.defaults else _cell(info.defaults)
            # a section's type any finite number, its range the case's (a depth's, a module's)
            loose = {a for a in info.allowed if a.startswith("any finite number")}
            allowed = info.allowed - loose if len(info.allowed) > len(loose) else info.allowed
            row = [f"`{key}`", kind, unit(key), default, _cell(allowed)]
            out.append("| " + " | ".join(_escape(c) for c in row) + " |")
        out.append("")
    return "\n".join(out) + "\n"


CASE_INTRO = """\
Generated from the case-file validator (`jaxgear.io.parse_case`, `jaxgear.io.parse_train`) by
`docs/_gen/schema_reference.py` each time the site is built: every key the validator accepts,
its type, unit, default and allowed range, table by table. Units are in the key names and the
ranges are in those units. Unknown keys are errors. A range that *depends on the case* is
computed from other keys (a face width in normal modules, a depth up to one normal module): the
values shown are the embedded cases'. *Required* keys are asked for when their table (or the
model they belong to, such as the torsional scene's inertias) is used. For a key checked by its
table's own code, *allowed* quotes the validator's message for a wrong value. A file is a
*train* case when it has `[[gears]]`."""

GEARBOX_INTRO = """\
Generated from the gearbox-file validator (`jaxgear.io`'s `parse_gearbox`, which
`jaxgear.io.load_case` calls for a file with `[[stages]]`) by `docs/_gen/schema_reference.py`
each time the site is built. A gearbox file names its stages in order, each an embedded case or a
case file (a planetary stage or a gear pair, whose own keys are in the pair and train
references), the torsional stiffness of the shaft joining each stage to the previous one, and
the operating point once, on the first stage's input; a pair stage also states which gear the
previous stage drives, its gears' polar inertias and its mean mesh stiffness (see *Planetary
stages*, "A gearbox of stages in series"). A stage is rated to ISO 6336 by its own case's
`[rating]`, at the operating point the gearbox carries to it. A `[whine]` table asks for the
whole coupled gearbox's gear whine (docs/whine.md, "A gearbox"): the pair's `[whine]` keys and
units (see the pair reference), its speeds the first stage's input member's, `method`
`"quasi-periodic"` (the default here; another method is refused), `positions_per_period` per
stage's own mesh period, one integer for every stage or a list of one per stage (a slow stage on
a coarser axis), with at most 10⁶ points on the stages' torus grid (their product). A `[housing]`
table (the pair's `[housing]` keys, see the pair reference) is one housing shared by the
`model = "lumped3d"` stages and the planetary stages with `housing_seat` (docs/gearbox.md, "One housing for several stages"). A
`[load_spectrum]` table (the pair's `[rating.spectrum]` keys, see the pair reference: torque in
N·m and speed in rpm per bin with `hours`, `cycles` or `time_share`, or a sampled history) is
the load spectrum of the first stage's input member, carried down the chain to the
`model = "lumped3d"` stages on rolling bearings for their lives by Palmgren–Miner (allowed only
with such a stage; docs/gearbox.md, "Under a load spectrum of the chain"). Unknown keys
are errors."""

#: what the gearbox page says of a table beyond its keys
GEARBOX_NOTES = {
    "stages[]": "One table per stage, in order from the input. *Required* as the stage asks: "
    "`shaft_Nm_per_rad` on every stage but the first (refused there: no shaft before it); "
    "`input`, `pinion_inertia_kg_m2`, `gear_inertia_kg_m2` and `mesh_stiffness_N_per_um` on a "
    "gear-pair stage only (refused on a planetary stage, whose input and output are its "
    "`[planetary]` table's). `model` (a gear-pair stage: `\"torsional\"`, the default, or "
    "`\"lumped3d\"`: the stage case's lumped 3D `[scene]`, shafts, bearings and gear bodies, "
    "as `jaxgear.gearbox.LumpedPairGearboxStage`; the inertia and mesh stiffness keys are "
    "refused with it, and so is a stage case without such a scene; a planetary stage: "
    "`\"torsional\"`, the default, or `\"planar\"`, its kind in the coupled chain, whose "
    "translations read the stage case's radial bearings and pins). `housing_position_mm` "
    "(an array of 3 numbers, mm) and `housing_seats` (an array of integers >= -1, one per "
    "bearing): a `\"lumped3d\"` stage of a gearbox with `[housing]` only (its scene origin in "
    "the gearbox frame, the first stage's scene frame; each bearing's seat, its pinion shaft's "
    "then its gear shaft's, -1 on the ground; docs/gearbox.md, \"One housing for several "
    "stages\"). `housing_seat` (an integer >= 0): a planetary stage whose ring is held, of a "
    "gearbox with `[housing]` only: the seat its ring is bolted to (a bore round its axis in "
    "both end walls of the box), `housing_position_mm` then its centre (its axis the gearbox "
    "frame's z); refused beyond the box's seats or on a seat a lumped stage's bearing takes. "
    "`housing_bore_diameter_mm` (mm, > 0): on a housed stage of a box `[housing]`, the "
    "diameter of the bores round its axes (a lumped stage's two shafts, a planetary stage's "
    "ring seat; default the `[housing]`'s `bore_diameter_mm`), refused where a bore would "
    "leave the end walls' inner faces or meet another bore (the message gives the largest "
    "that fits) and with a mesh file's `[housing]`.",
}

#: what the train page says of a table beyond its keys
TRAIN_NOTES = {
    "rating": "A train's `[rating]` rates every external mesh, a planetary stage's (gear form) "
    "its `sun-planet` and `planet-ring` meshes. `K_gamma` (the load sharing factor K_γ) applies "
    "to planetary stages only: a train without `[planetary]` refuses it (its meshes carry no "
    "load sharing between paths); without it a planetary stage rates with the run's computed "
    "K_γ. The ring's root section comes from its pinion-type cutter "
    "(`jaxgear.rating.ShaperCutterSection`), given on the ring's `[[gears]]` entry (`cutter_teeth`, "
    "`cutter_profile_shift`, `cutter_tip_radius_coeff`); `ring_cutter_teeth` (z0), "
    "`ring_cutter_profile_shift` (x0, default 0) and `ring_cutter_tip_radius_coeff` (the "
    "cutter's tip radius over m_n, default the ring's `fillet_radius_coeff`) are their older "
    "spelling, refused together with them; without a cutter, ISO's substitute rack (the other "
    "two keys are refused without `ring_cutter_teeth`).",
    "rating.spectrum": "A load spectrum (ISO 6336-6) of the input member (a train's input gear, "
    "a planetary stage's `[planetary] input`), the keys a pair's: each mesh's bins are it "
    "carried by the mesh's lossless torque and speed ratios (docs/rating.md, \"Trains and "
    "planetary stages\").",
    "lubricant": "A pair's `[lubricant]` for every mesh (a planetary stage with `[[gears]]` "
    "only): each mesh's film and sliding loss and the train's or stage's efficiency "
    "(docs/tribology.md, \"Trains, planetary stages and gearboxes\").",
    "bearings": "ISO 281's modified rating life L_nm of a `lumped3d` train's `[[scene.shafts]]` "
    "rolling bearings, a pair's keys (each bearing with its ratings; the input's `[operating] "
    "speed_rad_s` > 0, each shaft at its speed ratio); refused without a rolling bearing "
    "(docs/trains.md, \"Rolling bearings\").",
}

BODY_INTRO = """\
Generated from the body-file validator (`fem_prep.schema.parse_body`) by
`docs/_gen/schema_reference.py` each time the site is built: every key, its type, unit, default
and allowed range. Lengths are in mm, the modulus in GPa. A case file names a body file in
`[scene.gear_body] body`, `[scene.pinion_body] body` or `[scene.bodies.<shaft>] body`."""


#: what the pair page says of a table beyond its keys
PAIR_NOTES = {
    "rating.spectrum": "A load spectrum (ISO 6336-6), in one of two forms. Bins: `torque_Nm` "
    "(pinion), `speed_rpm` (one number or one per bin) and exactly one of `hours` (time in each "
    "bin over the life), `cycles` (pinion load cycles) or `time_share` (shares of `[rating] "
    "life_h`); each list as long as `torque_Nm`. Or a sampled history: `series_torque_Nm`, "
    "`series_speed_rpm` (one or one per sample), `series_step_s` and `levels`, counted into "
    "levels (time at level) and scaled to `life_h`. \"Required\" below is within the form "
    "chosen. A train's or a planetary stage's: the same keys for its input member, carried to "
    "each mesh (docs/rating.md, \"Load spectrum and life\").",
    "bearings": "ISO 281's modified rating life L_nm of the `[scene]` shafts' rolling bearings "
    "(`catalogue` or `kind`, each with its ratings `dynamic_rating_kN`, `static_rating_kN` and, "
    "deep groove, `iso281_f0` where the catalogue entry has none) at `[operating] speed_rad_s` "
    "(> 0); the viscosity defaults to `[lubricant]`'s at its oil temperature. Without the table "
    "`jaxgear run` reports L10 and L10r only (docs/bearings.md, \"In the report\").",
}


def pages() -> dict[str, str]:
    """``{file name: markdown}`` of the generated reference pages."""
    pair, train = trace_cases()
    bodies = trace_bodies()
    case_page = markdown(pair, "Case-file reference: a gear pair", CASE_INTRO, PAIR_NOTES)
    train_page = markdown(train, "Case-file reference: a gear train", CASE_INTRO, TRAIN_NOTES)
    body_page = markdown(bodies, "Body-file reference (fem_prep)", BODY_INTRO)
    gearbox_page = markdown(trace_gearbox(), "Case-file reference: a gearbox", GEARBOX_INTRO,
                            GEARBOX_NOTES)
    return {"case-file.md": case_page, "train-file.md": train_page, "body-file.md": body_page,
            "gearbox-file.md": gearbox_page}


def main(argv: list[str] | None = None) -> None:
    out = pathlib.Path((argv or sys.argv[1:] or ["."])[0])
    out.mkdir(parents=True, exist_ok=True)
    for name, text in pages().items():
        (out / name).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()
