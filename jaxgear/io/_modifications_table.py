"""``[modifications]`` of a case file: the flank modifications of both members (or one table per
member), depths in µm within one normal module."""

from __future__ import annotations

import itertools
import re
import tomllib
from typing import Any, ClassVar, Literal

import numpy as np
import pydantic

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
from ._sections import Section, named_keys, number, number_list
from ._writers import toml_value

__all__ = [
    "END_RELIEF_EDGES",
    "FILE_KEYS",
    "RELIEF_SHAPES",
    "ModificationSet",
    "ModificationsSection",
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
#: a modification that is not a table: what it says
_NOT_A_TABLE = "must be a table, e.g. { depth_um = 10.0 }"


def _depth_range(module_mm: float | None, signed: bool = False) -> tuple[str, str]:
    """The allowed range (file units, µm) of a modification or deviation depth and its note:
    up to ``MAX_DEPTH_MODULE`` normal modules (deeper, the flank is no longer a tooth's)."""
    if module_mm is None:
        return (">= 0" if not signed else "any"), ""
    hi = MAX_DEPTH_MODULE * module_mm * 1e3
    rng = f"[{-hi:.6g}, {hi:.6g}]" if signed else f"[0, {hi:.6g}]"
    return rng, f" (µm; up to {MAX_DEPTH_MODULE:g} × normal_module_mm)"


class ReliefSection(Section):
    """A ``tip_relief`` or ``root_relief``: its depth (µm; up to one normal module of its
    member: :func:`member_modification`), its extent (a fraction of the path of contact) and
    shape (:data:`RELIEF_SHAPES`)."""

    depth_um: number() = 0.0
    extent: number("(0, 1]", note=" (fraction of the path of contact)") = 0.25
    shape: Literal[tuple(RELIEF_SHAPES)] = "linear"


class CrowningSection(Section):
    """A ``crowning``: its depth (µm; up to one normal module)."""

    depth_um: number() = 0.0


class EndReliefSection(Section):
    """An ``end_relief``: its depth (µm; up to one normal module), its extent at each end (a
    fraction of the face width) and the ends it relieves (:data:`END_RELIEF_EDGES`)."""

    depth_um: number() = 0.0
    extent: number("(0, 0.5]", note=" (fraction of the face width at each end)") = 0.1
    edge: Literal[tuple(END_RELIEF_EDGES)] = "both"


class HelixSlopeSection(Section):
    """A ``helix_slope``: its deviation across the face (µm, signed; up to one normal module)."""

    deviation_um: number() = 0.0


class ProfileDeviationSection(Section):
    """A ``profile_deviation``: deviations (µm, signed; up to one normal module) at strictly
    ascending roll fractions in [0, 1], one each (:func:`member_modification`)."""

    roll_fraction: number_list("[0, 1]", min_length=2)
    deviation_um: number_list(min_length=2)


class ModificationSet(Section):
    """The modifications of one member (or those common to every member): each a table
    (module docstring)."""

    tip_relief: ReliefSection | None = None
    root_relief: ReliefSection | None = None
    crowning: CrowningSection | None = None
    end_relief: EndReliefSection | None = None
    helix_slope: HelixSlopeSection | None = None
    profile_deviation: ProfileDeviationSection | None = None


#: the modification names
_MOD_KEYS = tuple(ModificationSet.model_fields)


class ModificationsSection(ModificationSet):
    """``[modifications]``: the modifications of every member (:class:`ModificationSet`) and
    the member tables that replace entries for one member (:attr:`members`: a pair's
    ``[modifications.pinion]`` and ``[modifications.gear]``, a train's by gear name). Read it
    with :meth:`of`, which names the members."""

    WHERE: ClassVar[str] = "modifications"
    members: dict[str, ModificationSet] = pydantic.Field(default_factory=dict)

    @pydantic.model_validator(mode="before")
    @classmethod
    def _tables(cls, data, info):
        """The keys of a modification or a member's table, each a table (in its words), the
        member tables moved to :attr:`members`."""
        names = (info.context or {}).get("members", ("pinion", "gear"))
        if not isinstance(data, dict):
            return data
        data = named_keys(data, names, cls.WHERE, _MOD_KEYS, into="members")
        for where, table in ((cls.WHERE, data), *((f"{cls.WHERE}.{k}", v) for k, v in
                                                  data["members"].items())):
            for k in _MOD_KEYS:
                if k in table and not isinstance(table[k], dict):
                    raise sc.fail(where, k, _NOT_A_TABLE, table[k])
        return data

    @classmethod
    def file_keys(cls, context: dict | None = None) -> tuple[str, ...]:
        """The modifications; the member tables are named by the case (:attr:`members`)."""
        return _MOD_KEYS

    @classmethod
    def of(cls, table, members=("pinion", "gear")) -> ModificationsSection:
        """The ``[modifications]`` of a case whose members are named ``members``."""
        return cls.read(table, context={"members": tuple(members)})

    def member(self, name: str, module_mm: float | None = None) -> MemberModification:
        """Member ``name``'s :class:`MemberModification`: the common entries, its own table's
        over them (:func:`member_modification`)."""
        own = self.members.get(name)
        entries = {k: (getattr(self, k), self.WHERE) for k in _MOD_KEYS
                   if getattr(self, k) is not None}
        entries |= {k: (getattr(own, k), f"{self.WHERE}.{name}") for k in _MOD_KEYS
                    if own is not None and getattr(own, k) is not None}
        return member_modification(entries, module_mm)


def _within(value, where: str, key: str, allowed: str, note: str = ""):
    """``value`` (a number or a list of a section, file units) in ``allowed`` (a depth's range
    follows its member's module), else :func:`fem_prep.checks.number`'s one line (an array's:
    :func:`fem_prep.checks.number_list`'s)."""
    check = sc.number_list if isinstance(value, list) else sc.number
    return check({key: value}, key, where, allowed=allowed, note=note)


def member_modification(entries: dict, module_mm: float | None = None) -> MemberModification:
    """``{name: (section, where)}`` (each modification's typed table and where the file gives
    it) → :class:`MemberModification` (depths µm → m), each depth within one normal module
    ``module_mm`` (mm) of the member."""
    kw: dict[str, Any] = {}
    depth, note = _depth_range(module_mm)
    signed, _ = _depth_range(module_mm, signed=True)
    for name, (spec, where) in entries.items():
        w = f"{where}.{name}"
        if name in ("tip_relief", "root_relief"):
            kw |= {f"{name}_depth": _within(spec.depth_um, w, "depth_um", depth, note) * 1e-6,
                   f"{name}_extent": spec.extent, f"{name}_shape": RELIEF_SHAPES[spec.shape]}
        elif name == "crowning":
            kw["crowning_depth"] = _within(spec.depth_um, w, "depth_um", depth, note) * 1e-6
        elif name == "end_relief":
            kw.update(end_relief_depth=_within(spec.depth_um, w, "depth_um", depth, note) * 1e-6,
                      end_relief_extent=spec.extent, end_relief_edge=END_RELIEF_EDGES[spec.edge])
        elif name == "helix_slope":
            kw["helix_slope_deviation"] = _within(spec.deviation_um, w, "deviation_um", signed,
                                                  note) * 1e-6
        elif name == "profile_deviation":
            u, d = spec.roll_fraction, _within(spec.deviation_um, w, "deviation_um", signed)
            if len(u) != len(d):
                raise sc.fail(w, "deviation_um", f"needs one value per roll_fraction ({len(u)})", d)
            if any(b <= a for a, b in itertools.pairwise(u)):
                raise sc.fail(w, "roll_fraction", "must ascend strictly within [0, 1]", u)
            kw.update(profile_deviation_roll=np.asarray(spec.roll_fraction),
                      profile_deviation=np.asarray(d) * 1e-6)
    return MemberModification(**kw)


def parse_modifications(table: dict, module_mm: float | None = None) -> Modifications:
    """``[modifications]`` → :class:`Modifications`.

    Entries directly under ``[modifications]`` apply to each member; entries under
    ``[modifications.pinion]`` / ``[modifications.gear]`` replace them for that member.

    Raises:
        SchemaError: unknown modification or key, wrong type, value out of range.
    """
    section = ModificationsSection.of(table)
    return Modifications(pinion=section.member("pinion", module_mm),
                         gear=section.member("gear", module_mm))


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


def modifications_toml(table: dict) -> str:
    """``[modifications]`` (and its member tables) as TOML text, each modification an inline
    table, floats written in full (``repr``: they read back to the same double)."""
    lines = ["[modifications]"]
    lines += [f"{k} = {toml_value(v)}" for k, v in table.items() if k not in _MEMBERS]
    for m in _MEMBERS:
        if m in table:
            lines += ["", f"[modifications.{m}]"]
            lines += [f"{k} = {toml_value(v)}" for k, v in table[m].items()]
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
