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
    steps_per_period = 64
    periods = 60
    keep_periods = 4
    rtol = 1e-6                          # diffrax PID controller (scaled state)
    atol = 1e-6
"""

from __future__ import annotations

import math

from ..dynamics import DIFFRAX_SOLVERS, SceneSpec
from ..scenes import Bearing, ShaftSpec

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
}
_SHAFT_KEYS = {
    "length_mm",
    "diameter_mm",
    "gear_position_mm",
    "torque_position_mm",
    "elements",
    "bearings",
}
_BEARING_KEYS = {"position_mm", "radial_N_per_um", "axial_N_per_um", "tilt_Nm_per_rad"}
_DAMPING_KEYS = {"model", "ratio", "alpha_per_s", "beta_s", "mesh_ratio", "structure_ratio"}
_INTEGRATION_KEYS = {
    "solver",
    "contact",
    "steps_per_period",
    "periods",
    "keep_periods",
    "rtol",
    "atol",
}


def _parse_shaft(table, where: str):
    if not isinstance(table, dict):
        raise ValueError(f"[{where}] must be a table")
    _unknown(table, _SHAFT_KEYS, f"[{where}] ")
    for key in ("length_mm", "diameter_mm", "gear_position_mm", "bearings"):
        if key not in table:
            raise ValueError(f"missing required key [{where}] {key}")
    length = _number(table, "length_mm", where) * 1e-3
    diameter = _number(table, "diameter_mm", where) * 1e-3
    gear_z = _number(table, "gear_position_mm", where, nonneg=True) * 1e-3
    torque_z = (
        _number(table, "torque_position_mm", where, nonneg=True) * 1e-3
        if "torque_position_mm" in table
        else 0.0
    )
    elements = _number(table, "elements", where, integer=True) if "elements" in table else 4
    bearings = table["bearings"]
    if not isinstance(bearings, list) or not bearings:
        raise ValueError(
            f"[{where}] bearings must be a non-empty list of tables, e.g. "
            "[{ position_mm = 0.0, radial_N_per_um = 200.0 }]"
        )
    out = []
    for i, b in enumerate(bearings):
        w = f"{where}.bearings[{i}]"
        if not isinstance(b, dict):
            raise ValueError(f"[{w}] must be a table")
        _unknown(b, _BEARING_KEYS, f"[{w}] ")
        if "position_mm" not in b:
            raise ValueError(f"missing required key [{w}] position_mm")
        out.append(
            Bearing(
                z=_number(b, "position_mm", w, nonneg=True) * 1e-3,
                radial=_number(b, "radial_N_per_um", w, nonneg=True) * 1e6
                if "radial_N_per_um" in b
                else 2e8,
                axial=_number(b, "axial_N_per_um", w, nonneg=True) * 1e6
                if "axial_N_per_um" in b
                else 0.0,
                tilt=_number(b, "tilt_Nm_per_rad", w, nonneg=True)
                if "tilt_Nm_per_rad" in b
                else 0.0,
            )
        )
    for name, z in (
        ("gear_position_mm", gear_z),
        ("torque_position_mm", torque_z),
        *((f"bearings[{i}].position_mm", b.z) for i, b in enumerate(out)),
    ):
        if z > length * (1 + 1e-12):
            raise ValueError(
                f"[{where}] {name} = {z * 1e3:g} is beyond the shaft length {length * 1e3:g} mm"
            )
    if not any(b.axial > 0 for b in out):
        raise ValueError(
            f"[{where}] needs an axial stiffness on at least one bearing (axial_N_per_um > 0)"
        )
    if sum(b.radial > 0 for b in out) < 2 and not any(b.tilt > 0 for b in out):
        raise ValueError(
            f"[{where}] needs two radial bearings (or a tilt stiffness) to hold the shaft"
        )
    return ShaftSpec(
        length=length,
        diameter=diameter,
        gear_z=gear_z,
        bearings=tuple(out),
        torque_z=torque_z,
        elements=elements,
    )


def _unknown(table: dict, allowed: set, where: str) -> None:
    for key in table:
        if key not in allowed:
            raise ValueError(f"unknown key {where}{key!r} in case file: allowed {sorted(allowed)}")


def _number(table, key, where, *, positive=True, nonneg=False, integer=False, upper=None):
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError(f"[{where}] {key} = {v!r} must be a finite number")
    if integer and int(v) != v:
        raise ValueError(f"[{where}] {key} = {v!r} must be an integer")
    if positive and not nonneg and not v > 0:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed > 0")
    if nonneg and not v >= 0:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed >= 0")
    if upper is not None and not v <= upper:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed <= {upper}")
    return int(v) if integer else float(v)


def parse_scene(table: dict | None) -> SceneSpec:
    """Validate a ``[scene]`` table (``None`` or ``{}``: the defaults).

    Raises:
        ValueError: unknown keys (named), wrong types, values out of range, inconsistent inputs.
    """
    table = {} if table is None else table
    if not isinstance(table, dict):
        raise ValueError("[scene] must be a table")
    _unknown(table, _SCENE_KEYS, "[scene] ")
    kw: dict = {}
    model = table.get("model", "torsional")
    if model not in ("torsional", "lumped3d"):
        raise ValueError(f"[scene] model = {model!r}: allowed 'torsional', 'lumped3d'")
    if model == "lumped3d":
        for key in ("pinion_shaft", "gear_shaft"):
            if key not in table:
                raise ValueError(f"[scene] model = 'lumped3d' needs a [scene.{key}] table")
            kw[key] = _parse_shaft(table[key], f"scene.{key}")
        for key in (
            "motor_inertia_kg_m2",
            "load_inertia_kg_m2",
            "motor_shaft_stiffness_Nm_per_rad",
            "load_shaft_stiffness_Nm_per_rad",
        ):
            if key in table:
                raise ValueError(
                    f"[scene] {key} is for model = 'torsional' (lumped3d: the torque "
                    "acts at the shafts' torque_position_mm)"
                )
        if table.get("reduction", "none") != "none":
            raise ValueError("[scene] reduction applies to model = 'torsional' only")
    else:
        for key in ("pinion_shaft", "gear_shaft", "pinion_mass_kg", "gear_mass_kg"):
            if key in table:
                raise ValueError(f"[scene] {key} is for model = 'lumped3d'")
    for key, field in (("pinion_mass_kg", "pinion_mass"), ("gear_mass_kg", "gear_mass")):
        if key in table:
            kw[field] = _number(table, key, "scene")
    reduction = table.get("reduction", "none")
    if reduction not in ("none", "relative"):
        raise ValueError(f"[scene] reduction = {reduction!r}: allowed 'none', 'relative'")
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
            kw[field] = _number(table, key, "scene")
    for side in ("motor", "load"):
        if (f"{side}_inertia" in kw) != (f"{side}_shaft" in kw):
            raise ValueError(
                f"[scene] {side}_inertia_kg_m2 and {side}_shaft_stiffness_Nm_per_rad "
                "go together: give both or neither"
            )
        if reduction == "relative" and f"{side}_inertia" in kw:
            raise ValueError(
                f"[scene] reduction = 'relative' is for a rigid pinion-gear pair: "
                f"remove {side}_inertia_kg_m2 or set reduction = 'none'"
            )
    d = table.get("damping", {})
    if not isinstance(d, dict):
        raise ValueError("[scene.damping] must be a table")
    _unknown(d, _DAMPING_KEYS, "[scene.damping] ")
    dm = d.get("model", "composite")
    if dm not in ("composite", "modal", "rayleigh", "none"):
        raise ValueError(
            f"[scene.damping] model = {dm!r}: allowed 'composite', 'modal', 'rayleigh', 'none'"
        )
    kw["damping_model"] = dm
    for key, field in (
        ("ratio", "damping_ratio"),
        ("mesh_ratio", "mesh_ratio"),
        ("structure_ratio", "structure_ratio"),
    ):
        if key in d:
            kw[field] = _number(d, key, "scene.damping", nonneg=True, upper=1.0)
    for key, field in (("alpha_per_s", "rayleigh_alpha"), ("beta_s", "rayleigh_beta")):
        if key in d:
            kw[field] = _number(d, key, "scene.damping", nonneg=True)
    g = table.get("integration", {})
    if not isinstance(g, dict):
        raise ValueError("[scene.integration] must be a table")
    _unknown(g, _INTEGRATION_KEYS, "[scene.integration] ")
    solver = g.get("solver", "newmark")
    if solver != "newmark" and solver not in DIFFRAX_SOLVERS:
        raise ValueError(
            f"[scene.integration] solver = {solver!r}: allowed 'newmark', "
            f"{', '.join(repr(s) for s in DIFFRAX_SOLVERS)}"
        )
    contact = g.get("contact", "exact")
    if contact not in ("exact", "smooth"):
        raise ValueError(f"[scene.integration] contact = {contact!r}: allowed 'exact', 'smooth'")
    kw.update(solver=solver, contact=contact)
    for key, lo in (("steps_per_period", 4), ("periods", 2), ("keep_periods", 2)):
        if key in g:
            v = _number(g, key, "scene.integration", integer=True)
            if v < lo:
                raise ValueError(
                    f"[scene.integration] {key} = {v} is out of range: allowed >= {lo}"
                )
            kw[key] = v
    if kw.get("keep_periods", 4) > kw.get("periods", 60):
        raise ValueError("[scene.integration] keep_periods must be <= periods")
    for key in ("rtol", "atol"):
        if key in g:
            kw[key] = _number(g, key, "scene.integration")
    return SceneSpec(**kw)
