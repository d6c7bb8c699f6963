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
(docs/dynamics.md).
"""

from __future__ import annotations

import os
from typing import ClassVar, Literal

import numpy as np
import pydantic

import fem_prep
from fem_prep import schema as sc

from ..dynamics import DIFFRAX_SOLVERS
from ..scenes import Bearing, ShaftSpec, bearing_matrix
from ._scene_spec import SceneSpec
from ._sections import Section, number

__all__ = ["parse_scene"]

_SCENE_KEYS = {
    "model",
    "reduction",
    "pinion_inertia_kg_m2",
    "gear_inertia_kg_m2",
    "motor_inertia_kg_m2",
    "motor_shaft_stiffness_Nm_per_rad",
    "load_inertia_kg_m2",
    "load_shaft_stiffness_Nm_per_rad",
    "damping",
    "integration",
    "pinion_mass_kg",
    "gear_mass_kg",
    "pinion_shaft",
    "gear_shaft",
    "pinion_body",
    "gear_body",
}
_BODY_KEYS = {"body"}
_SHAFT_KEYS = {
    "length_mm",
    "diameter_mm",
    "gear_position_mm",
    "torque_position_mm",
    "elements",
    "bearings",
}
#: two radial bearings without tilt stiffness: at least 1 % of the shaft length apart
MIN_BEARING_SPAN = 0.01
_DIAGONAL_BEARING_KEYS = ("radial_N_per_um", "axial_N_per_um", "tilt_Nm_per_rad")
_BEARING_KEYS = {"position_mm", *_DIAGONAL_BEARING_KEYS, "stiffness_matrix_SI", "damping_matrix_SI"}


def _parse_shaft(t: dict, where: str, gears: list | None = None) -> ShaftSpec:
    """A shaft table (its keys checked by the caller) at ``[where]``: a pair's shaft
    (``gear_position_mm``) or, with ``gears`` (the names of the gears it carries, in gear
    order), a train's (``gear_positions_mm = { <gear> = mm, ... }``, one per gear)."""
    # physical lower bounds: a denormal size or stiffness passes "> 0" and fails in the solver
    length_mm = sc.number(t, "length_mm", where, allowed="[1, 1e+05]")
    length = length_mm * 1e-3
    diameter = sc.number(t, "diameter_mm", where, allowed="[1, 1e+04]") * 1e-3
    within = f"[0, {length_mm:.6g}]"
    note = " (not beyond the shaft length)"
    if gears is None:
        gear_z = sc.number(t, "gear_position_mm", where, allowed=within, note=note) * 1e-3
    else:
        given = sc.subtable(t, "gear_positions_mm", where, gears, required=True)
        w = f"{where}.gear_positions_mm"
        gear_z = tuple(sc.number(given, g, w, allowed=within, note=note) * 1e-3 for g in gears)
    torque_z = sc.number(t, "torque_position_mm", where, 0.0, allowed=within, note=note) * 1e-3
    elements = sc.number(t, "elements", where, 4, allowed="[1, 1000]", integer=True)
    if "bearings" not in t:
        raise sc.fail(where, "bearings", "missing required key")
    bearings = t["bearings"]
    if not isinstance(bearings, list) or not bearings:
        raise sc.fail(
            where,
            "bearings",
            "must be a non-empty array of tables, e.g. "
            "[{ position_mm = 0.0, radial_N_per_um = 200.0 }]",
            bearings,
        )
    out = []
    for i, b in enumerate(bearings):
        w = f"{where}.bearings[{i}]"
        if not isinstance(b, dict):
            raise sc.fail(where, f"bearings[{i}]", "must be a table", b)
        sc.check_keys(b, _BEARING_KEYS, w)
        z = sc.number(b, "position_mm", w, allowed=within, note=note) * 1e-3
        K, C = (_bearing_matrix(b, key, w) for key in ("stiffness_matrix_SI", "damping_matrix_SI"))
        if K is None:
            out.append(
                Bearing(
                    z=z,
                    radial=_stiffness(b, "radial_N_per_um", w, 200.0, 1e-3, 1e9) * 1e6,
                    axial=_stiffness(b, "axial_N_per_um", w, 0.0, 1e-3, 1e9) * 1e6,
                    tilt=_stiffness(b, "tilt_Nm_per_rad", w, 0.0, 1.0, 1e15),
                    damping=C,
                )
            )
            continue
        both = [key for key in _DIAGONAL_BEARING_KEYS if key in b]
        if both:
            raise sc.fail(
                w,
                "stiffness_matrix_SI",
                f"give either {'/'.join(_DIAGONAL_BEARING_KEYS)} or stiffness_matrix_SI, not both "
                f"(the matrix is the whole stiffness; remove {', '.join(both)})",
            )
        out.append(Bearing(z=z, stiffness=K, damping=C))
    diag = [np.diag(b.stiffness_matrix()) for b in out]
    if not any(d[2] > 0 for d in diag):
        raise sc.SchemaError(
            f"[{where}] bearings: needs an axial stiffness on at least one bearing "
            "(axial_N_per_um > 0 or stiffness_matrix_SI[2][2] > 0)"
        )
    radial = [b.z for b, d in zip(out, diag, strict=True) if d[0] > 0 and d[1] > 0]
    if not any(d[3] > 0 and d[4] > 0 for d in diag):
        if len(radial) < 2:
            raise sc.SchemaError(
                f"[{where}] bearings: needs two radial bearings (or a tilt stiffness) to hold "
                "the shaft"
            )
        # two radial bearings at one position hold the shaft like one: it tilts freely
        span_mm = (max(radial) - min(radial)) * 1e3
        min_span = MIN_BEARING_SPAN * length_mm
        if span_mm < min_span:
            raise sc.fail(
                where,
                "bearings",
                f"radial bearings at position_mm = {min(radial) * 1e3:.6g} to "
                f"{max(radial) * 1e3:.6g}, allowed at least {min_span:.6g} mm apart "
                f"({100 * MIN_BEARING_SPAN:g} % of length_mm; closer, they do not stop the shaft "
                "tilting) or a tilt stiffness (tilt_Nm_per_rad)",
            )
    return ShaftSpec(
        length=length,
        diameter=diameter,
        gear_z=gear_z,
        bearings=tuple(out),
        torque_z=torque_z,
        elements=elements,
    )


def _stiffness(b: dict, key: str, where: str, default: float, lo: float, hi: float) -> float:
    """A bearing stiffness: 0 (free in that direction) or within [lo, hi] (file units)."""
    v = sc.number(b, key, where, default, allowed=f"[0, {hi:g}]")
    if 0 < v < lo:
        raise sc.fail(
            where, key, f"out of range, allowed 0 (free) or [{lo:g}, {hi:g}]", b.get(key, v)
        )
    return v


def _bearing_matrix(b: dict, key: str, where: str):
    """``stiffness_matrix_SI`` / ``damping_matrix_SI`` of a bearing table: 6 rows of 6 numbers,
    SI per DOF pair (DOF order ux, uy, uz, rx, ry, rz), symmetric, positive semi-definite, row
    and column rz zero (:func:`jaxgear.scenes.bearing_matrix`); ``None`` when absent."""
    if key not in b:
        return None
    v = b[key]
    try:
        return bearing_matrix(v)
    except ValueError as err:
        # a malformed value is shown; the other errors name the offending entries themselves
        shown = v if str(err).startswith("must be") else sc.MISSING
        raise sc.fail(where, key, str(err), shown) from None


def parse_body(table: dict, key: str, base_dir: str | None, parent: str = "scene") -> str:
    """``[scene.<member>_body] body = ...`` (a train's ``[scene.bodies.<gear>]``, ``parent``
    ``scene.bodies``): an embedded fem_prep body, a body TOML or a .npz, resolved against the
    case file's folder ``base_dir``."""
    t = sc.subtable(table, key, parent, _BODY_KEYS, required=True)
    where = f"{parent}.{key}"
    ref = sc.string(t, "body", where, sc.MISSING)
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
            f"allowed an embedded body ({', '.join(names)}), a body .toml or a condensed .npz",
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


def integration_of(table: dict) -> IntegrationSection:
    """The ``[scene.integration]`` of a ``[scene]`` table (its defaults where it has none)."""
    return IntegrationSection.read(table.get("integration", {}))


def parse_dynamics_settings(table: dict) -> dict:
    """The ``[scene.damping]`` and ``[scene.integration]`` tables of a pair's or a train's
    ``[scene]`` (``rotating_frame`` aside): :class:`SceneSpec` fields."""
    return (DampingSection.read(table.get("damping", {})).settings()
            | integration_of(table).settings())


def parse_scene(table: dict | None, base_dir: str | None = None) -> SceneSpec:
    """Validate a ``[scene]`` table (``None`` or ``{}``: the defaults). Body paths are resolved
    against ``base_dir`` (the case file's folder).

    Raises:
        SchemaError (a ``ValueError``): unknown keys (named), wrong types, values out of range,
            inconsistent inputs; one line, in the file's units.
    """
    table = {} if table is None else table
    if not isinstance(table, dict):
        raise sc.fail("", "scene", "must be a table", table)
    sc.check_keys(table, _SCENE_KEYS, "scene")
    kw: dict = {}
    model = sc.choice(table, "model", "scene", ("torsional", "lumped3d"), "torsional")
    reduction = sc.choice(table, "reduction", "scene", ("none", "relative"), "none")
    if model == "lumped3d":
        for key in ("pinion_shaft", "gear_shaft"):
            if key not in table:
                raise sc.SchemaError(f"[scene] model = 'lumped3d' needs a [scene.{key}] table")
            t = sc.subtable(table, key, "scene", _SHAFT_KEYS, required=True)
            kw[key] = _parse_shaft(t, f"scene.{key}")
        for key in (
            "motor_inertia_kg_m2",
            "load_inertia_kg_m2",
            "motor_shaft_stiffness_Nm_per_rad",
            "load_shaft_stiffness_Nm_per_rad",
        ):
            if key in table:
                raise sc.fail(
                    "scene",
                    key,
                    "is for model = 'torsional' (lumped3d: the torque acts at the shafts' "
                    "torque_position_mm)",
                )
        if reduction != "none":
            raise sc.fail("scene", "reduction", "applies to model = 'torsional' only", reduction)
        for key in ("pinion_body", "gear_body"):
            if key in table:
                kw[key] = parse_body(table, key, base_dir)
    else:
        for key in (
            "pinion_shaft",
            "gear_shaft",
            "pinion_mass_kg",
            "gear_mass_kg",
            "pinion_body",
            "gear_body",
        ):
            if key in table:
                raise sc.fail("scene", key, "is for model = 'lumped3d'")
    for key, field in (("pinion_mass_kg", "pinion_mass"), ("gear_mass_kg", "gear_mass")):
        if key in table:
            kw[field] = sc.number(table, key, "scene", allowed="[1e-06, 1e+09]")
    kw.update(model=model, reduction=reduction)
    names = {
        "pinion_inertia_kg_m2": "pinion_inertia",
        "gear_inertia_kg_m2": "gear_inertia",
        "motor_inertia_kg_m2": "motor_inertia",
        "motor_shaft_stiffness_Nm_per_rad": "motor_shaft",
        "load_inertia_kg_m2": "load_inertia",
        "load_shaft_stiffness_Nm_per_rad": "load_shaft",
    }
    for key, field in names.items():
        if key in table:
            lo = "1e-09" if key.endswith("inertia_kg_m2") else "0.001"
            kw[field] = sc.number(table, key, "scene", allowed=f"[{lo}, 1e+15]")
    for side in ("motor", "load"):
        if (f"{side}_inertia" in kw) != (f"{side}_shaft" in kw):
            raise sc.SchemaError(
                f"[scene] {side}_inertia_kg_m2 and {side}_shaft_stiffness_Nm_per_rad "
                "go together: give both or neither"
            )
        if reduction == "relative" and f"{side}_inertia" in kw:
            raise sc.SchemaError(
                f"[scene] reduction = 'relative' is for a rigid pinion-gear pair: "
                f"remove {side}_inertia_kg_m2 or set reduction = 'none'"
            )
    kw.update(parse_dynamics_settings(table))
    w = "scene.integration"
    integration = integration_of(table)
    if "rotating_frame" in integration.given:
        kw["rotating_frame"] = integration.rotating_frame
        if kw["rotating_frame"] and not any(f"{m}_body" in kw for m in ("pinion", "gear")):
            raise sc.fail(
                w,
                "rotating_frame",
                "allowed only with a condensed body ([scene] pinion_body or gear_body): the "
                "rigid models are written in the fixed frame",
                True,
            )
    if "modal_basis" in kw and not any(f"{m}_body" in kw for m in ("pinion", "gear")):
        raise sc.fail(
            w,
            "modal_basis",
            "allowed only with a condensed body ([scene] pinion_body or gear_body): the "
            "modal basis is for the hybrid models",
            kw["modal_basis"],
        )
    return SceneSpec(**kw)
