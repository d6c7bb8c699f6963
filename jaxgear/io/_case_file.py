"""Case files (TOML, units in key names) and the embedded reference cases.

A case is read, checked against the schema (unknown keys are errors, every value is range
checked), converted to SI and turned into a :class:`Case`. See README.md for the schema.
"""

from __future__ import annotations

import importlib.resources
import math
import os
import tomllib
from typing import Any

import numpy as np

from .._case import Case
from .._geometry import GearPair, Member
from .._modifications import MemberModification, Modifications
from ._scene_table import parse_scene

__all__ = ["list_cases", "load_case", "parse_case", "parse_modifications"]

_SCHEMA: dict[str, Any] = {
    "name": str,
    "pair": {
        "normal_module_mm",
        "normal_pressure_angle_deg",
        "helix_angle_deg",
        "center_distance_mm",
    },
    "pinion": {
        "teeth",
        "profile_shift",
        "addendum_coeff",
        "dedendum_coeff",
        "face_width_mm",
        "fillet_radius_coeff",
    },
    "gear": {
        "teeth",
        "profile_shift",
        "addendum_coeff",
        "dedendum_coeff",
        "face_width_mm",
        "fillet_radius_coeff",
    },
    "material": {"youngs_modulus_GPa", "poisson_ratio", "density_kg_m3"},
    "operating": {"torque_Nm"},
    "mesh": {
        "stiffness",
        "stiffness_per_length_N_per_mm_per_um",
        "slices",
        "positions_per_pitch",
        "smooth_width_um",
        "foundation",
    },
    "modifications": None,  # checked by _member_mods
    "scene": None,  # reserved for the structure scenes (torsional, lumped 3D); kept raw
    "optimise": None,  # reserved for the optimisation settings; kept raw
}
_MOD_KEYS = {
    "tip_relief": {"depth_um", "extent", "shape"},
    "root_relief": {"depth_um", "extent", "shape"},
    "crowning": {"depth_um"},
    "end_relief": {"depth_um", "extent"},
    "helix_slope": {"deviation_um"},
    "profile_deviation": {"roll_fraction", "deviation_um"},
}
_REQUIRED = {
    "pair": ("normal_module_mm", "normal_pressure_angle_deg"),
    "pinion": ("teeth", "face_width_mm"),
    "gear": ("teeth", "face_width_mm"),
    "operating": ("torque_Nm",),
}


def _check_keys(table: dict, allowed, where: str) -> None:
    for key in table:
        if key not in allowed:
            raise ValueError(f"unknown key {where}{key!r} in case file: allowed {sorted(allowed)}")


def _num(table: dict, key: str, where: str, default=None, *, positive=False, integer=False):
    if key not in table:
        if default is None:
            raise ValueError(f"missing required key [{where}] {key}")
        return default
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise ValueError(f"[{where}] {key} = {v!r} must be a number")
    if integer and int(v) != v:
        raise ValueError(f"[{where}] {key} = {v!r} must be an integer")
    if not math.isfinite(v):
        raise ValueError(f"[{where}] {key} = {v!r} must be finite")
    if positive and not v > 0:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed > 0")
    return int(v) if integer else float(v)


def _member_mods(entries: dict, where: str) -> MemberModification:
    kw: dict[str, Any] = {}
    for name, spec in entries.items():
        if name not in _MOD_KEYS:
            raise ValueError(f"unknown modification {where}.{name!r}: allowed {sorted(_MOD_KEYS)}")
        if not isinstance(spec, dict):
            raise ValueError(f"{where}.{name} must be a table, e.g. {{ depth_um = 10.0 }}")
        _check_keys(spec, _MOD_KEYS[name], f"{where}.{name}.")
        w = f"{where}.{name}"
        if name in ("tip_relief", "root_relief"):
            prefix = name
            depth = _num(spec, "depth_um", w, 0.0)
            extent = _num(spec, "extent", w, 0.25)
            if depth < 0:
                raise ValueError(f"{w}.depth_um = {depth} is out of range: allowed >= 0")
            if not 0 < extent <= 1:
                raise ValueError(
                    f"{w}.extent = {extent} is out of range: allowed (0, 1] "
                    "(fraction of the path of contact)"
                )
            shape = spec.get("shape", "linear")
            if shape not in ("linear", "parabolic"):
                raise ValueError(f"{w}.shape = {shape!r}: allowed 'linear', 'parabolic'")
            kw.update(
                {
                    f"{prefix}_depth": depth * 1e-6,
                    f"{prefix}_extent": extent,
                    f"{prefix}_shape": shape,
                }
            )
        elif name == "crowning":
            depth = _num(spec, "depth_um", w, 0.0)
            if depth < 0:
                raise ValueError(f"{w}.depth_um = {depth} is out of range: allowed >= 0")
            kw["crowning_depth"] = depth * 1e-6
        elif name == "end_relief":
            depth = _num(spec, "depth_um", w, 0.0)
            extent = _num(spec, "extent", w, 0.1)
            if depth < 0:
                raise ValueError(f"{w}.depth_um = {depth} is out of range: allowed >= 0")
            if not 0 < extent <= 0.5:
                raise ValueError(
                    f"{w}.extent = {extent} is out of range: allowed (0, 0.5] "
                    "(fraction of the face width at each end)"
                )
            kw.update(end_relief_depth=depth * 1e-6, end_relief_extent=extent)
        elif name == "helix_slope":
            kw["helix_slope_deviation"] = _num(spec, "deviation_um", w, 0.0) * 1e-6
        elif name == "profile_deviation":
            u = np.asarray(spec.get("roll_fraction", []), dtype=float)
            d = np.asarray(spec.get("deviation_um", []), dtype=float)
            if u.ndim != 1 or u.shape != d.shape or u.size < 2:
                raise ValueError(
                    f"{w}: roll_fraction and deviation_um must be lists of equal length >= 2"
                )
            if np.any(np.diff(u) <= 0) or u[0] < 0 or u[-1] > 1:
                raise ValueError(
                    f"{w}.roll_fraction = {u.tolist()} must ascend strictly within [0, 1]"
                )
            kw.update(profile_deviation_roll=u, profile_deviation=d * 1e-6)
    return MemberModification(**kw)


def parse_modifications(table: dict) -> Modifications:
    """``[modifications]`` → :class:`Modifications`.

    Entries directly under ``[modifications]`` apply to each member; entries under
    ``[modifications.pinion]`` / ``[modifications.gear]`` replace them for that member.
    """
    common = {k: v for k, v in table.items() if k not in ("pinion", "gear")}
    members = []
    for tag in ("pinion", "gear"):
        own = table.get(tag, {})
        if not isinstance(own, dict):
            raise ValueError(f"modifications.{tag} must be a table")
        members.append(
            _member_mods({**common, **own}, f"modifications{'' if not own else '.' + tag}")
        )
    return Modifications(pinion=members[0], gear=members[1])


def parse_case(data: dict, default_name: str = "case") -> Case:
    """Validate a parsed case TOML (a dict) and build a :class:`Case`.

    Raises:
        ValueError: unknown keys, missing required keys, values out of range, invalid geometry.
    """
    _check_keys(data, _SCHEMA.keys(), "")
    for section, allowed in _SCHEMA.items():
        if isinstance(allowed, set):
            table = data.get(section, {})
            if not isinstance(table, dict):
                raise ValueError(f"[{section}] must be a table")
            _check_keys(table, allowed, f"[{section}] ")
    for section, keys in _REQUIRED.items():
        if section not in data:
            raise ValueError(f"missing required table [{section}]")
        for key in keys:
            if key not in data[section]:
                raise ValueError(f"missing required key [{section}] {key}")
    p = data["pair"]
    members = []
    for tag in ("pinion", "gear"):
        t = data[tag]
        members.append(
            Member(
                teeth=_num(t, "teeth", tag, integer=True),
                profile_shift=_num(t, "profile_shift", tag, 0.0),
                addendum_coeff=_num(t, "addendum_coeff", tag, 1.0),
                dedendum_coeff=_num(t, "dedendum_coeff", tag, 1.25),
                face_width=_num(t, "face_width_mm", tag, positive=True) * 1e-3,
                fillet_radius_coeff=_num(t, "fillet_radius_coeff", tag, 0.25),
            )
        )
    cd = p.get("center_distance_mm")
    pair = GearPair(
        pinion=members[0],
        gear=members[1],
        normal_module=_num(p, "normal_module_mm", "pair", positive=True) * 1e-3,
        normal_pressure_angle=math.radians(
            _num(p, "normal_pressure_angle_deg", "pair", positive=True)
        ),
        helix_angle=math.radians(_num(p, "helix_angle_deg", "pair", 0.0)),
        center_distance=None
        if cd is None
        else _num(p, "center_distance_mm", "pair", positive=True) * 1e-3,
    )
    mat = data.get("material", {})
    E = _num(mat, "youngs_modulus_GPa", "material", 210.0, positive=True) * 1e9
    nu = _num(mat, "poisson_ratio", "material", 0.3)
    if not 0 <= nu < 0.5:
        raise ValueError(f"[material] poisson_ratio = {nu} is out of range: allowed [0, 0.5)")
    rho = _num(mat, "density_kg_m3", "material", 7800.0, positive=True)
    torque = _num(data["operating"], "torque_Nm", "operating", positive=True)
    m = data.get("mesh", {})
    model = m.get("stiffness", "weber")
    if model not in ("weber", "uniform", "iso6336"):
        raise ValueError(f"[mesh] stiffness = {model!r}: allowed 'weber', 'uniform', 'iso6336'")
    k0 = m.get("stiffness_per_length_N_per_mm_per_um")
    if model == "uniform":
        k0 = _num(m, "stiffness_per_length_N_per_mm_per_um", "mesh", positive=True) * 1e9
    elif k0 is not None:
        k0 = _num(m, "stiffness_per_length_N_per_mm_per_um", "mesh", positive=True) * 1e9
    slices = _num(m, "slices", "mesh", 40, integer=True)
    if slices < 1:
        raise ValueError(f"[mesh] slices = {slices} is out of range: allowed >= 1")
    ppp = _num(m, "positions_per_pitch", "mesh", 64, integer=True)
    if ppp < 2:
        raise ValueError(f"[mesh] positions_per_pitch = {ppp} is out of range: allowed >= 2")
    width = _num(m, "smooth_width_um", "mesh", 0.1, positive=True) * 1e-6
    foundation = m.get("foundation", True)
    if not isinstance(foundation, bool):
        raise ValueError(f"[mesh] foundation = {foundation!r} must be true or false")
    mods_table = data.get("modifications", {})
    if not isinstance(mods_table, dict):
        raise ValueError("[modifications] must be a table")
    mods = parse_modifications(mods_table)
    name = data.get("name", default_name)
    if not isinstance(name, str) or not name:
        raise ValueError(f"name = {name!r} must be a non-empty string")
    scene = parse_scene(data["scene"]) if "scene" in data else None
    optimise = parse_optimise(data["optimise"]) if "optimise" in data else None
    return Case(
        name=name,
        pair=pair,
        modifications=mods,
        youngs_modulus=E,
        poisson_ratio=nu,
        density=rho,
        torque=torque,
        stiffness_model=model,
        uniform_k0=k0,
        slices=slices,
        positions_per_pitch=ppp,
        smooth_width=width,
        foundation=foundation,
        scene=scene,
        optimise=optimise,
        raw=data,
    )


_OPTIMISE_KEYS = {"objective", "vars", "torques", "reduce", "method", "max_iterations", "bounds"}


def parse_optimise(table) -> dict:
    """Validate an ``[optimise]`` table (keys as the ``jaxgear optimise`` options)."""
    if not isinstance(table, dict):
        raise ValueError("[optimise] must be a table")
    _check_keys(table, _OPTIMISE_KEYS, "[optimise] ")
    return dict(table)


def _embedded():
    return importlib.resources.files("jaxgear") / "cases"


def list_cases() -> list[str]:
    """Names of the embedded cases (``jaxgear cases``)."""
    return sorted(p.name[:-5] for p in _embedded().iterdir() if p.name.endswith(".toml"))


def load_case(name_or_path: str | os.PathLike) -> Case:
    """Load a case from a TOML path or an embedded case name.

    Raises:
        FileNotFoundError: neither a file nor an embedded case name.
        ValueError: TOML syntax errors (with the file name) and schema/range errors.
    """
    text, label = None, str(name_or_path)
    if os.path.isfile(name_or_path):
        with open(name_or_path, "rb") as f:
            raw = f.read()
        default = os.path.splitext(os.path.basename(label))[0]
    elif str(name_or_path) in list_cases():
        raw = (_embedded() / f"{name_or_path}.toml").read_bytes()
        default = str(name_or_path)
    else:
        raise FileNotFoundError(
            f"case {label!r} is neither a file nor an embedded case "
            f"(embedded: {', '.join(list_cases())})"
        )
    try:
        text = raw.decode("utf-8")
        data = tomllib.loads(text)
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as err:
        raise ValueError(f"case file {label!r} is not valid TOML: {err}") from None
    return parse_case(data, default)
