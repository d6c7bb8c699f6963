"""``[modifications]`` of a case file: the flank modifications of both members (or one table per
member), depths in µm within one normal module."""

from __future__ import annotations

import functools
import itertools
import re
import tomllib
from typing import Any

import numpy as np

from fem_prep import schema as sc

from .._modifications import (
    BothEdges,
    EdgeZ0,
    EdgeZ1,
    LinearRelief,
    MemberModification,
    Modifications,
    ParabolicRelief,
)

__all__ = [
    "END_RELIEF_EDGES",
    "FILE_KEYS",
    "RELIEF_SHAPES",
    "case_text_with_modifications",
    "modifications_toml",
    "modifications_with",
    "parse_modifications",
]

#: ``tip_relief``/``root_relief`` ``shape`` names
RELIEF_SHAPES = {"linear": LinearRelief(), "parabolic": ParabolicRelief()}
#: ``end_relief`` ``edge`` names
END_RELIEF_EDGES = {"both": BothEdges(), "z0": EdgeZ0(), "z1": EdgeZ1()}

MAX_DEPTH_MODULE = 1.0  # modification and deviation depths: up to one normal module
_MOD_KEYS = {
    "tip_relief": {"depth_um", "extent", "shape"},
    "root_relief": {"depth_um", "extent", "shape"},
    "crowning": {"depth_um"},
    "end_relief": {"depth_um", "extent", "edge"},
    "helix_slope": {"deviation_um"},
    "profile_deviation": {"roll_fraction", "deviation_um"},
}

def _depth_range(module_mm: float | None, signed: bool = False) -> tuple[str, str]:
    """The allowed range (file units, µm) of a modification or deviation depth and its note:
    up to ``MAX_DEPTH_MODULE`` normal modules (deeper, the flank is no longer a tooth's)."""
    if module_mm is None:
        return (">= 0" if not signed else "any"), ""
    hi = MAX_DEPTH_MODULE * module_mm * 1e3
    rng = f"[{-hi:.6g}, {hi:.6g}]" if signed else f"[0, {hi:.6g}]"
    return rng, f" (µm; up to {MAX_DEPTH_MODULE:g} × normal_module_mm)"


def _member_mods(
    entries: dict[str, tuple[Any, str]], module_mm: float | None = None
) -> MemberModification:
    """``{name: (spec, where)}`` → :class:`MemberModification` (depths µm → m), each depth
    within one normal module ``module_mm`` (mm) of the member."""
    kw: dict[str, Any] = {}
    depth_rng, depth_note = _depth_range(module_mm)
    signed_rng, _ = _depth_range(module_mm, signed=True)
    for name, (spec, where) in entries.items():
        if not isinstance(spec, dict):
            raise sc.fail(where, name, "must be a table, e.g. { depth_um = 10.0 }", spec)
        w = f"{where}.{name}"
        sc.check_keys(spec, _MOD_KEYS[name], w)
        if name in ("tip_relief", "root_relief"):
            depth = sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note)
            extent = sc.number(
                spec, "extent", w, 0.25, allowed="(0, 1]", note=" (fraction of the path of contact)"
            )
            shape = RELIEF_SHAPES[sc.choice(spec, "shape", w, tuple(RELIEF_SHAPES), "linear")]
            kw.update(
                {
                    f"{name}_depth": depth * 1e-6,
                    f"{name}_extent": extent,
                    f"{name}_shape": shape,
                }
            )
        elif name == "crowning":
            kw["crowning_depth"] = (
                sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note) * 1e-6
            )
        elif name == "end_relief":
            depth = sc.number(spec, "depth_um", w, 0.0, allowed=depth_rng, note=depth_note)
            extent = sc.number(
                spec,
                "extent",
                w,
                0.1,
                allowed="(0, 0.5]",
                note=" (fraction of the face width at each end)",
            )
            edge = END_RELIEF_EDGES[sc.choice(spec, "edge", w, tuple(END_RELIEF_EDGES), "both")]
            kw.update(end_relief_depth=depth * 1e-6, end_relief_extent=extent, end_relief_edge=edge)
        elif name == "helix_slope":
            kw["helix_slope_deviation"] = (
                sc.number(spec, "deviation_um", w, 0.0, allowed=signed_rng, note=depth_note) * 1e-6
            )
        elif name == "profile_deviation":
            u = sc.number_list(spec, "roll_fraction", w, min_length=2, allowed="[0, 1]")
            d = sc.number_list(spec, "deviation_um", w, min_length=2, allowed=signed_rng)
            if len(u) != len(d):
                raise sc.fail(w, "deviation_um", f"needs one value per roll_fraction ({len(u)})", d)
            if any(b <= a for a, b in itertools.pairwise(u)):
                raise sc.fail(w, "roll_fraction", "must ascend strictly within [0, 1]", u)
            kw.update(profile_deviation_roll=np.asarray(u), profile_deviation=np.asarray(d) * 1e-6)
    return MemberModification(**kw)


def parse_modifications(table: dict, module_mm: float | None = None) -> Modifications:
    """``[modifications]`` → :class:`Modifications`.

    Entries directly under ``[modifications]`` apply to each member; entries under
    ``[modifications.pinion]`` / ``[modifications.gear]`` replace them for that member.

    Raises:
        SchemaError: unknown modification or key, wrong type, value out of range.
    """
    if not isinstance(table, dict):
        raise sc.fail("", "modifications", "must be a table", table)
    allowed = {*_MOD_KEYS, "pinion", "gear"}
    sc.check_keys(table, allowed, "modifications")
    common = {k: (v, "modifications") for k, v in table.items() if k not in ("pinion", "gear")}
    members = []
    for tag in ("pinion", "gear"):
        own = sc.subtable(table, tag, "modifications", _MOD_KEYS)
        where = f"modifications.{tag}"
        members.append(
            _member_mods({**common, **{k: (v, where) for k, v in own.items()}}, module_mm)
        )
    return Modifications(pinion=members[0], gear=members[1])


# ------------------------------------------------------------------------------------------
# writing a design back: a case file's [modifications] with new values

#: the ``[modifications]`` key of each design-variable quantity (``tip_relief.depth`` →
#: ``tip_relief``'s ``depth_um``)
FILE_KEYS = {"depth": "depth_um", "extent": "extent"}
_MEMBERS = ("pinion", "gear")
_HEADER = re.compile(r"^\s*\[\[?\s*\"?([A-Za-z_][A-Za-z0-9_-]*)\"?\s*(?:\.|\])")


def modifications_with(table: dict | None, values: dict) -> dict:
    """The ``[modifications]`` table ``table`` (a case file's, file units; None: none) with
    ``values`` written in: ``{(members, modification, key): value}``, e.g.
    ``{(("pinion", "gear"), "tip_relief", "depth_um"): 12.5}``. Each member's entries are the
    common ones with its own over them (as :func:`parse_modifications` reads them); an entry
    equal for both members is written once, under ``[modifications]``, else under
    ``[modifications.pinion]``/``[modifications.gear]``."""
    table = table or {}
    common = {k: v for k, v in table.items() if k not in _MEMBERS}
    each = {  # each member's own copy of every entry
        m: {k: dict(v) for k, v in {**common, **table.get(m, {})}.items()} for m in _MEMBERS
    }
    for (members, mod, key), value in values.items():
        for m in members:
            each[m].setdefault(mod, {})[key] = float(value)
    out: dict = {}
    for mod in dict.fromkeys([*each["pinion"], *each["gear"]]):
        p, g = each["pinion"].get(mod), each["gear"].get(mod)
        if p == g:
            out[mod] = p
        else:
            for m, entry in (("pinion", p), ("gear", g)):
                if entry is not None:
                    out.setdefault(m, {})[mod] = entry
    return out


@functools.singledispatch
def _toml_value(v) -> str:
    raise TypeError(f"modifications: cannot write {v!r} as TOML")


@_toml_value.register(bool)
def _(v) -> str:
    return "true" if v else "false"


@_toml_value.register(int)
def _(v) -> str:
    return str(v)


@_toml_value.register(float)
def _(v) -> str:
    return repr(v)  # reads back to the same double


@_toml_value.register(str)
def _(v) -> str:
    return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'


@_toml_value.register(list)
@_toml_value.register(tuple)
def _(v) -> str:
    return "[" + ", ".join(_toml_value(x) for x in v) + "]"


@_toml_value.register(dict)
def _(v) -> str:
    return "{ " + ", ".join(f"{k} = {_toml_value(x)}" for k, x in v.items()) + " }"


def modifications_toml(table: dict) -> str:
    """``[modifications]`` (and its member tables) as TOML text, each modification an inline
    table, floats written in full (``repr``: they read back to the same double)."""
    lines = ["[modifications]"]
    lines += [f"{k} = {_toml_value(v)}" for k, v in table.items() if k not in _MEMBERS]
    for m in _MEMBERS:
        if m in table:
            lines += ["", f"[modifications.{m}]"]
            lines += [f"{k} = {_toml_value(v)}" for k, v in table[m].items()]
    return "\n".join(lines) + "\n"


def case_text_with_modifications(text: str, table: dict) -> str:
    """A case file's TOML ``text`` with its ``[modifications]`` tables (and member sub-tables)
    replaced by ``table`` (:func:`modifications_toml`), appended at the end; every other line,
    comments included, kept.

    Raises:
        ValueError: the case writes its modifications in a form this cannot replace (a dotted
            or inline ``modifications`` key outside a ``[modifications]`` header).
    """
    kept, skipping = [], False
    for line in text.splitlines():
        head = _HEADER.match(line)
        if head is not None:
            skipping = head.group(1) == "modifications"
        if not skipping:
            kept.append(line)
    body = "\n".join(kept).rstrip("\n")
    if "modifications" in tomllib.loads(body):
        raise ValueError(
            "the case file gives [modifications] as a dotted or inline key: write it as a "
            "[modifications] table to have the design written back"
        )
    note = "\n\n# the design written by jaxgear optimise --write\n"
    out = body + note + modifications_toml(table)
    tomllib.loads(out)  # a parse error here is a bug of this writer, not the user's
    return out
