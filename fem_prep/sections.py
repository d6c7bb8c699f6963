"""A file's table as a typed section: pydantic checks it, one line tells what is wrong.

The one home of the typed tables of both packages: fem_prep's body and ring files
(:mod:`fem_prep.schema`) and jaxgear's case files (``jaxgear.io._sections`` builds on this
module, adding only what is its own).

A table is a :class:`Section`, a frozen pydantic model whose field names are the file's keys
(units in the key names: ``bore_radius_mm``); each field's type and range are declared once with
:func:`number` (an integer with ``integer=True``), :func:`number_list`, :func:`one_of` (a number,
an array or a table), :func:`by_sign` (a range by the sign), ``Literal[...]`` (a name out of a
few), ``bool`` and :data:`Text`, a sub-table as a section, an array of tables as a list of
sections. Keys the model does not declare are refused, and a table given as anything but a table
too. Pydantic checks; :func:`schema_error` turns the first of its errors into the one line of
:mod:`fem_prep.checks` (a :class:`~fem_prep.checks.SchemaError`), in the file's words and units:

* ``[mesh] size_mm = 0: out of range, allowed [0.001, 1e+06]``
* ``[mesh] unknown key 'sise_mm' (did you mean 'size_mm'?), allowed: circumferential_size_mm, ...``
* ``material = 3: must be a table ([material]), not a number``
* ``[bearings[1]] coupling = 'glue': allowed 'rigid', 'averaging'``

so a reader never raises a ``TypeError``, a ``KeyError`` or pydantic's own many-line report.
What relates two keys of a table (a radius below another) is a ``model_validator`` raising
:func:`fem_prep.checks.fail`'s one line, which passes through as it is. Integer keys take an
integral float (``modes = 50.0`` is 50) and refuse others; booleans are never numbers; numbers
are finite (the rules of :mod:`fem_prep.checks`). Standard library, pydantic and
:mod:`fem_prep.checks` only (no JAX).
"""

from __future__ import annotations

import dataclasses
import math
import sys
import typing
from typing import Annotated, Any, ClassVar, Literal

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict, Discriminator, Field, Tag

from . import checks as sc

__all__ = ["Range", "Section", "Text", "by_sign", "named_keys", "number", "number_list", "one_of",
           "range_of", "schema_error"]

#: the prefix of a union member's tag (:func:`one_of`), which the error's location skips
_TAG = "§"


@dataclasses.dataclass(frozen=True)
class Range:
    """A number field's allowed range in file units (:class:`~fem_prep.checks.Interval`), the
    words its range message adds (``note``), whether it is an integer, and for an array of
    numbers its length (``length``, or at least ``min_length``)."""

    interval: sc.Interval
    note: str = ""
    integer: bool = False
    array: bool = False
    length: int | None = None
    min_length: int = 0


def _integral(v: Any) -> Any:
    """An integral float as the integer it is (``50.0`` → 50); anything else as it is."""
    if type(v) is float and math.isfinite(v) and v.is_integer():
        return int(v)
    return v


#: the largest integer a float holds: an integer key's bounds where its range has none
_FLOAT_MAX = int(sys.float_info.max)


def _bounds(rng: sc.Interval, integer: bool, any_size: bool = False) -> dict:
    """pydantic's constraints of an interval (integral bounds as integers for an integer; an
    integer's open ends at what a float holds, as :func:`fem_prep.checks.number`, unless
    ``any_size``)."""
    def bound(x):
        return int(x) if integer and float(x).is_integer() else x

    wide = integer and not any_size
    out = {}
    if rng.lo == 0.0 and rng.lo_open and not integer:
        # a positive quantity: at least the smallest normal float, so that a subnormal value
        # (5e-324) cannot pass the range and underflow to 0 in the unit conversion (µm → m)
        out["ge"] = sys.float_info.min
    elif rng.lo > -math.inf:
        out["gt" if rng.lo_open else "ge"] = bound(rng.lo)
    elif wide:
        out["ge"] = -_FLOAT_MAX
    if rng.hi < math.inf:
        out["lt" if rng.hi_open else "le"] = bound(rng.hi)
    elif wide:
        out["le"] = _FLOAT_MAX
    return out


def number(allowed: str | sc.Interval | None = None, *, integer: bool = False, note: str = "",
           any_size: bool = False):
    """The type of a number key in ``allowed`` (a range text, ``"[0.001, 1e+06]"``, file units;
    None: any finite number), an integer with ``integer`` (a Python integer; where the range is
    open, within what a float holds, or of any size with ``any_size``: a key whose range a
    ``model_validator`` checks); ``note``: what its range message adds (a source, a reason)."""
    rng = sc.interval(allowed)
    if integer:
        return Annotated[int, BeforeValidator(_integral), Field(**_bounds(rng, True, any_size)),
                         Range(rng, note, True)]
    return Annotated[float, Field(allow_inf_nan=False, **_bounds(rng, False)), Range(rng, note)]


def number_list(allowed: str | sc.Interval | None = None, *, length: int | None = None,
                min_length: int = 0, integer: bool = False, note: str = ""):
    """The type of an array of numbers, each in ``allowed`` (as :func:`number`), of ``length``
    numbers (or at least ``min_length``)."""
    rng = sc.interval(allowed)
    sizes = {"min_length": length, "max_length": length} if length is not None else (
        {"min_length": min_length} if min_length else {})
    return Annotated[list[number(rng, integer=integer)], Field(**sizes),
                     Range(rng, note, integer, True, length, min_length)]


def one_of(**kinds):
    """The type of a key that is one of several kinds, picked by the value's type: keywords
    ``number``, ``array``, ``table`` (each a type, e.g. ``number=number("[1, 10]")``): a number,
    an array or a table. The kind of another value is the first's (its error names the key)."""
    order = tuple(kinds)

    def pick(v):
        kind = "array" if isinstance(v, list) else "table" if isinstance(v, dict) else "number"
        return _TAG + (kind if kind in kinds else order[0])

    members = tuple(Annotated[t, Tag(_TAG + k)] for k, t in kinds.items())
    return Annotated[typing.Union[members], Discriminator(pick)]  # noqa: UP007


def by_sign(positive, negative):
    """The type of a number key whose range follows its sign (an internal gear's negative
    teeth): ``positive`` (a :func:`number`) for a value >= 0 or not a number (its error names
    the key), ``negative`` for a number below 0."""
    def pick(v):
        below = isinstance(v, (int, float)) and not isinstance(v, bool) and v < 0
        return _TAG + ("negative" if below else "positive")

    members = (Annotated[positive, Tag(_TAG + "positive")],
               Annotated[negative, Tag(_TAG + "negative")])
    return Annotated[typing.Union[members], Discriminator(pick)]  # noqa: UP007


#: the type of a non-empty text key (a name, a designation)
Text = Annotated[str, Field(pattern=r"\S")]


def named_keys(data: Any, names, where: str, keys=(), *, tables=(),
               into: str | None = None) -> Any:
    """A table whose keys are the section's own ``keys`` and the case's ``names`` (its members,
    planets, meshes, gears: what the validation context names), as a section's validator
    takes it before pydantic reads it: every key checked to be one of them
    (:func:`~fem_prep.checks.check_keys`: an unknown key in one line naming the table
    ``where``), then each of ``tables`` (own keys whose values are tables) and, with ``into``,
    each named entry checked to be a table (:func:`~fem_prep.checks.subtable`), the named
    entries moved to the field ``into`` (``{name: table}``, in the file's order).

    ``data`` not a dict, or ``names`` None (the case not known): ``data`` as given (the
    field's type, or no check of the names).

    Returns:
        ``data`` (checked), or with ``into`` a new dict: ``data`` without the named entries,
        and ``into`` holding them.

    Raises:
        SchemaError: an unknown key, or a ``tables`` or named entry that is not a table (one
            line).
    """
    if not isinstance(data, dict) or names is None:
        return data
    sc.check_keys(data, {*keys, *names}, where)
    for k in tables:
        sc.subtable(data, k, where)
    if into is None:
        return data
    own = {k: v for k, v in data.items() if k in names}
    for k in own:
        sc.subtable(own, k, where)
    return {k: v for k, v in data.items() if k not in names} | {into: own}


class Section(BaseModel):
    """A file's table (module docstring): a frozen pydantic model, its fields the table's keys.
    ``WHERE``: the table's name in the file (``"body"``, ``"acoustics.microphones"``; ``""`` the
    top level). ``UNKNOWN_KEYS_FIRST``: which error a reader meets first where a file has
    several (:func:`schema_error`): False, an unknown key before the other errors of its own
    table (a reader that checks each table's keys as it reads it); True, the unknown keys of
    the whole file, in its order, before any other error."""

    # defer_build: a model's validator is built when a file is first read, not at import
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True, defer_build=True,
                              protected_namespaces=(), hide_input_in_errors=True)
    WHERE: ClassVar[str] = ""
    UNKNOWN_KEYS_FIRST: ClassVar[bool] = False

    @classmethod
    def read(cls, table: Any, where: str | None = None, *, context: dict | None = None):
        """The section of ``table`` (the file's table, a dict) at ``where`` (default
        :attr:`WHERE`); ``context``: what its validators need beyond the table (``where``
        added).

        Raises:
            SchemaError: one line naming the key, its value as written and what is allowed
                (:func:`schema_error`): a table given as something else, an unknown key, a value
                of the wrong type or out of range, what the section's own checks refuse.
        """
        where = cls.WHERE if where is None else where
        context = {"where": where, **(context or {})}
        if not isinstance(table, dict):
            head, _, last = where.rpartition(".")
            raise sc.fail(head, last, f"must be a table ([{where}]), not {sc.type_name(table)}",
                          table)
        try:
            return cls.model_validate(table, context=context)
        except pydantic.ValidationError as err:
            raise schema_error(cls, where, table, err) from None


# --------------------------------------------------------------------------------------------
# pydantic's errors in the file's words


def _field(model, key):
    """The field ``key`` of ``model`` (a :class:`Section` class) or None."""
    if isinstance(model, type) and issubclass(model, BaseModel):
        return model.model_fields.get(key)
    return None


def _sections(annotation) -> type[Section] | None:
    """The :class:`Section` class a field holds (itself, in a list or a dict, or optional), or
    None."""
    if isinstance(annotation, type) and issubclass(annotation, Section):
        return annotation
    for arg in typing.get_args(annotation):
        found = _sections(arg)
        if found is not None:
            return found
    return None


def range_of(info, cls=Range):
    """The :class:`Range` (or another marker ``cls``) of a section's field, or None: ``info`` a
    pydantic ``FieldInfo`` (``Section.model_fields[key]``; an optional field's in its type)."""
    if info is None:
        return None
    for m in info.metadata:
        if isinstance(m, cls):
            return m
    return _marker_in(info.annotation, cls)


def _marker_in(annotation, cls):
    """The marker ``cls`` in a type (``Annotated[...]``, in an optional one: its member's)."""
    for arg in getattr(annotation, "__metadata__", ()):
        if isinstance(arg, cls):
            return arg
    for arg in typing.get_args(annotation):
        if arg is not type(None) and not isinstance(arg, (str, int)):
            found = _marker_in(arg, cls)
            if found is not None:
                return found
    return None


def _tagged(annotation, tag: str):
    """The :class:`Range` of the member tagged ``tag`` of a :func:`one_of` field."""
    for arg in typing.get_args(annotation):
        meta = getattr(arg, "__metadata__", ())
        if any(isinstance(m, Tag) and m.tag == tag for m in meta):
            return _marker_in(arg, Range)
        found = _tagged(arg, tag) if not isinstance(arg, (str, int)) else None
        if found is not None:
            return found
    return None


def _choices(annotation) -> tuple:
    """The names a ``Literal[...]`` field (optional or not) allows, in their order."""
    if typing.get_origin(annotation) is Literal:
        return typing.get_args(annotation)
    for arg in typing.get_args(annotation):
        found = _choices(arg)
        if found:
            return found
    return ()


def _value(table, loc):
    """The value at ``loc`` in ``table`` (union tags skipped), or MISSING."""
    v = table
    for part in loc:
        if isinstance(part, str) and part.startswith(_TAG):
            continue
        try:
            v = v[part]
        except (KeyError, IndexError, TypeError):
            return sc.MISSING
    return v


def _join(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def _first(errors: list[dict], table: dict, file_order: bool) -> dict:
    """The error a reader meets first (:attr:`Section.UNKNOWN_KEYS_FIRST`): with
    ``file_order`` the unknown keys first, in the table's order (as
    :func:`fem_prep.checks.check_keys` reports them); else an unknown key before the other
    errors of its table; then pydantic's order (the fields')."""
    if file_order:
        keys = list(table) if isinstance(table, dict) else []

        def order(e):
            if e["type"] != "extra_forbidden":
                return (1, 0, 0)
            first = e["loc"][0]
            return (0, len(e["loc"]), keys.index(first) if first in keys else 0)

        return min(errors, key=order)

    def rank(i):
        e = errors[i]
        if e["type"] != "extra_forbidden":
            return i
        parent = e["loc"][:-1]
        return min(j for j, f in enumerate(errors) if f["loc"][: len(parent)] == parent) - 0.5

    return errors[min(range(len(errors)), key=rank)]


def schema_error(cls, where: str, table: dict, error: pydantic.ValidationError) -> sc.SchemaError:
    """The one-line :class:`~fem_prep.checks.SchemaError` of the first of pydantic's errors of
    section ``cls`` read from ``table`` at ``where`` (module docstring's words)."""
    err = _first(error.errors(include_url=False), table, cls.UNKNOWN_KEYS_FIRST)
    ctx = err.get("ctx") or {}
    if isinstance(ctx.get("error"), sc.SchemaError):  # the section's own check: its one line
        return ctx["error"]
    loc = tuple(p for p in err["loc"] if not (isinstance(p, str) and p.startswith(_TAG)))
    # walk the location: the table the key lies in, the key, an index into its array
    model, key, index, info = cls, None, None, None
    tag = next((p for p in err["loc"] if isinstance(p, str) and p.startswith(_TAG)), None)
    named = False  # the next part names a sub-table (a field of tables by name)
    for part in loc:
        if isinstance(part, int):
            index = part
            continue
        if named:  # [where.<name>]: a table of a field of tables by name
            where, key, info, named = _join(where, part), None, None, False
            continue
        if key is not None and tag == _TAG + "table":  # a key of a table of numbers
            index = part
            break
        if key is not None:  # into a sub-table (or an entry of an array of tables)
            model = _sections(info.annotation) if info is not None else None
            where = _join(where, key if index is None else f"{key}[{index}]")
            index = None
        held, key = info, part
        info = _field(model, key)
        if info is None and model is None and held is not None and typing.get_origin(
                held.annotation) is dict:  # a value of a table of values by name: their type
            info = held
        if info is not None and typing.get_origin(info.annotation) is dict and _sections(
                info.annotation) is not None:
            model, named = _sections(info.annotation), True
    if err["type"] == "extra_forbidden":
        allowed = sorted(model.model_fields) if model is not None else []
        hint = sc.did_you_mean(str(key), allowed)
        shown = str(key) if len(str(key)) <= 40 else str(key)[:37] + "..."
        head = f"[{where}] " if where else ""
        return sc.SchemaError(f"{head}unknown key {shown!r}{hint}, allowed: {', '.join(allowed)}",
                              sc.key_path(where, key))
    if err["type"] == "missing" and info is not None and isinstance(
            info.annotation, type) and issubclass(info.annotation, Section):  # a table
        inner = _join(where, key)
        return sc.SchemaError(f"[{inner}]: missing required table", f"[{inner}]")
    sub = _sections(info.annotation) if info is not None else None
    element = index is not None and sub is None and loc[-1] == index  # in an array of numbers
    v = sc.MISSING if err["type"] == "missing" else err.get("input", sc.MISSING)
    rng = range_of(info) if tag is None else _tagged(info.annotation, tag)
    problem = _problem(err["type"], ctx, v, rng, info, element, where, key, index)
    if element:  # the array (or the table of numbers) as written
        whole = _value(table, err["loc"][:-1])
        return sc.fail(where, key, problem, v if whole is sc.MISSING else whole)
    if index is not None and isinstance(loc[-1], int):  # an entry of an array of tables
        return sc.fail(where, f"{key}[{index}]", problem, v)
    return sc.fail(where, key, problem, v)


def _problem(kind, ctx, v, rng, info, element, where, key, index):
    """What is wrong with value ``v`` (pydantic's error ``kind``), in the file's words."""
    note = rng.note if rng is not None else ""
    allowed = f"{rng.interval}{note}" if rng is not None else ""
    if kind == "missing":
        return "missing required key"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        if not sc.finite(v) and rng is not None and v in rng.interval:  # beyond a float
            return f"out of range (beyond ±1.79769e+308), allowed {allowed}"
        # a subnormal value inside a range open at 0 (refused by :func:`_bounds`' floor)
        subnormal = (isinstance(v, float) and 0.0 < abs(v) < sys.float_info.min
                     and rng is not None and v in rng.interval)
        why = " (subnormal: below 2.22507e-308)" if subnormal else ""
        if element:
            return f"element {sc.fmt(v)} out of range{why}, allowed {allowed}"
        return f"out of range{why}, allowed {allowed}"
    if kind in ("float_type", "int_type", "finite_number", "int_from_float", "float_parsing",
                "int_parsing"):
        if element:
            return f"must be an array of finite {'integers' if rng.integer else 'numbers'}"
        integer = rng is not None and rng.integer
        what = "an integer" if integer else "a number"
        if isinstance(v, int) and not isinstance(v, bool):  # beyond a float
            inside = rng is None or v in rng.interval
            return (f"out of range (beyond ±1.79769e+308), allowed {allowed or 'any number'}"
                    if inside else f"out of range, allowed {allowed}")
        if isinstance(v, float):
            if not math.isfinite(v):
                return f"must be a finite {'integer' if integer else 'number'}"
            return "must be an integer"
        return f"must be {what}, not {sc.type_name(v)}"
    if kind == "literal_error":
        names = ", ".join(repr(c) for c in _choices(info.annotation))
        return f"unknown {sc.fmt(v)}, allowed {names}" if element else f"allowed {names}"
    if kind == "bool_type":
        return "must be true or false"
    if kind in ("string_type", "string_pattern_mismatch", "string_too_short"):
        return "must be a non-empty string"
    if kind in ("list_type", "too_short", "too_long"):
        sub = _sections(info.annotation) if info is not None else None
        if sub is not None:  # an array of tables
            return f"must be an array of tables ([[{_join(where, key)}]]), not {sc.type_name(v)}"
        if kind == "list_type" and rng is None:  # an array of names
            names = ", ".join(repr(c) for c in _choices(info.annotation))
            return f"must be an array{f' of {names}' if names else ''}, not {sc.type_name(v)}"
        if kind == "list_type":
            return f"must be an array of numbers, not {sc.type_name(v)}"
        if rng is not None and rng.length is not None:
            return f"must be an array of {rng.length} numbers"
        return f"must be an array of at least {ctx.get('min_length', 0)} numbers"
    if kind in ("model_type", "model_attributes_type", "dict_type"):
        inner = _join(where, key)
        if index is not None:
            return f"must be a table ([[{inner}]] entry), not {sc.type_name(v)}"
        return f"must be a table ([{inner}]), not {sc.type_name(v)}"
    return " ".join(str(ctx.get("error", kind)).split())  # any other: pydantic's words, one line
