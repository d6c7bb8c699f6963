"""A body file's table as a typed section: pydantic checks it, one line tells what is wrong.

A table of a body file is a :class:`Section`, a frozen pydantic model whose field names are the
file's keys (units in the key names: ``bore_radius_mm``); each number field's type and range are
declared once with :func:`number` (an integer with ``integer=True``), a name out of a few with
``Literal[...]``, a sub-table as a section, an array of tables as a list of sections. Keys the
model does not declare are refused, and a table given as anything but a table too. Pydantic
checks; :func:`schema_error` turns the first of its errors into the one line of
:mod:`fem_prep.checks` (a :class:`~fem_prep.checks.SchemaError`), in the file's words and units:

* ``[mesh] size_mm = 0: out of range, allowed [0.001, 1e+06]``
* ``[mesh] unknown key 'sise_mm' (did you mean 'size_mm'?), allowed: circumferential_size_mm, ...``
* ``material = 3: must be a table ([material]), not a number``
* ``[bearings[1]] coupling = 'glue': allowed 'rigid', 'averaging'``

What relates two keys of a table (a radius below another) is a ``model_validator`` raising
:func:`fem_prep.checks.fail`'s one line, which passes through as it is. Integer keys take an
integral float (``modes = 50.0`` is 50) and refuse others; booleans are never numbers; numbers
are finite (the rules of :mod:`fem_prep.checks`). Standard library, pydantic and
:mod:`fem_prep.checks` only (no JAX): jaxgear's case tables follow the same rules
(``jaxgear.io._sections``).
"""

from __future__ import annotations

import dataclasses
import math
import typing
from typing import Annotated, Any, ClassVar, Literal

import pydantic
from pydantic import BaseModel, BeforeValidator, ConfigDict, Field

from . import checks as sc

__all__ = ["Range", "Section", "number", "schema_error"]


@dataclasses.dataclass(frozen=True)
class Range:
    """A number field's allowed range in file units (:class:`~fem_prep.checks.Interval`), the
    words its range message adds (``note``) and whether it is an integer."""

    interval: sc.Interval
    note: str = ""
    integer: bool = False


def _integral(v: Any) -> Any:
    """An integral float as the integer it is (``50.0`` → 50); anything else as it is."""
    if type(v) is float and math.isfinite(v) and v.is_integer():
        return int(v)
    return v


def number(allowed: str | sc.Interval | None = None, *, integer: bool = False, note: str = ""):
    """The type of a number key in ``allowed`` (a range text, ``"[0.001, 1e+06]"``, file units;
    None: any finite number), an integer with ``integer`` (a Python integer: exact, of any
    size where the range is open); ``note``: what its range message adds."""
    rng = sc.interval(allowed)
    bounds = {}
    if rng.lo > -math.inf:
        lo = int(rng.lo) if integer and rng.lo.is_integer() else rng.lo
        bounds["gt" if rng.lo_open else "ge"] = lo
    if rng.hi < math.inf:
        hi = int(rng.hi) if integer and rng.hi.is_integer() else rng.hi
        bounds["lt" if rng.hi_open else "le"] = hi
    if integer:
        return Annotated[int, BeforeValidator(_integral), Field(**bounds), Range(rng, note, True)]
    return Annotated[float, Field(allow_inf_nan=False, **bounds), Range(rng, note)]


class Section(BaseModel):
    """A body file's table (module docstring): a frozen pydantic model, its fields the table's
    keys; ``WHERE``: the table's name in the file (``"body"``, ``""`` the top level)."""

    # defer_build: a model's validator is built when a file is first read, not at import
    model_config = ConfigDict(extra="forbid", strict=True, frozen=True, defer_build=True,
                              protected_namespaces=(), hide_input_in_errors=True)
    WHERE: ClassVar[str] = ""

    @classmethod
    def read(cls, table: Any, where: str | None = None, *, context: dict | None = None):
        """The section of ``table`` (the file's table, a dict) at ``where`` (default
        :attr:`WHERE`); ``context``: what its validators need beyond the table.

        Raises:
            SchemaError: one line naming the key, its value as written and what is allowed
                (:func:`schema_error`).
        """
        where = cls.WHERE if where is None else where
        if not isinstance(table, dict):
            head, _, last = where.rpartition(".")
            raise sc.fail(head, last, f"must be a table ([{where}]), not {sc.type_name(table)}",
                          table)
        try:
            return cls.model_validate(table, context=context)
        except pydantic.ValidationError as err:
            raise schema_error(cls, where, err) from None


# --------------------------------------------------------------------------------------------
# pydantic's errors in the file's words


def _section(annotation) -> type[Section] | None:
    """The :class:`Section` a field holds (itself or in a list), or None."""
    if isinstance(annotation, type) and issubclass(annotation, Section):
        return annotation
    for arg in typing.get_args(annotation):
        found = _section(arg)
        if found is not None:
            return found
    return None


def _range(info) -> Range | None:
    """The :class:`Range` of a field (a ``FieldInfo``; an optional field's in its type), or
    None."""
    if info is None:
        return None
    return next((m for m in info.metadata if isinstance(m, Range)), None) or _marker(
        info.annotation)


def _marker(annotation) -> Range | None:
    """The :class:`Range` in a type (``Annotated[...]``, in an optional one: its member's)."""
    args = typing.get_args(annotation)
    if typing.get_origin(annotation) is Annotated:
        found = [m for m in args[1:] if isinstance(m, Range)]
        if found:
            return found[0]
    return next((r for a in args if (r := _marker(a)) is not None), None)


def _choices(annotation) -> tuple:
    """The names a ``Literal[...]`` field allows, in their order."""
    if typing.get_origin(annotation) is Literal:
        return typing.get_args(annotation)
    return next((c for a in typing.get_args(annotation) if (c := _choices(a))), ())


def _join(where: str, key: str) -> str:
    return f"{where}.{key}" if where else key


def _first(errors: list[dict]) -> dict:
    """The error a reader meets first: an unknown key before the other errors of its table
    (:func:`fem_prep.checks.check_keys` runs first), else pydantic's order (the fields')."""
    def rank(i):
        e = errors[i]
        if e["type"] != "extra_forbidden":
            return i
        parent = e["loc"][:-1]
        return min(j for j, f in enumerate(errors) if f["loc"][: len(parent)] == parent) - 0.5

    return errors[min(range(len(errors)), key=rank)]


def schema_error(cls, where: str, error: pydantic.ValidationError) -> sc.SchemaError:
    """The one-line :class:`~fem_prep.checks.SchemaError` of the first of pydantic's errors of
    section ``cls`` read at ``where`` (module docstring's words)."""
    err = _first(error.errors(include_url=False))
    ctx = err.get("ctx") or {}
    if isinstance(ctx.get("error"), sc.SchemaError):  # the section's own check: its one line
        return ctx["error"]
    model, key, index = cls, None, None  # walk the location: the table, the key, an entry
    for part in err["loc"]:
        if isinstance(part, int):
            index = part
            continue
        if key is not None:  # into a sub-table (an entry of an array of tables)
            model = _section(model.model_fields[key].annotation)
            where, index = _join(where, key if index is None else f"{key}[{index}]"), None
        key = part
    info = model.model_fields.get(key) if key is not None else None
    kind, v = err["type"], err.get("input", sc.MISSING)
    if kind == "extra_forbidden":
        allowed = sorted(model.model_fields)
        shown = str(key) if len(str(key)) <= 40 else str(key)[:37] + "..."
        head = f"[{where}] " if where else ""
        return sc.SchemaError(
            f"{head}unknown key {shown!r}{sc.did_you_mean(str(key), allowed)}, allowed: "
            f"{', '.join(allowed)}", sc.key_path(where, key))
    inner = _join(where, key)
    if kind == "missing" and info is not None and _section(info.annotation) is not None:
        return sc.SchemaError(f"[{inner}]: missing required table", f"[{inner}]")
    if kind in ("model_type", "model_attributes_type", "dict_type"):
        if index is not None:
            return sc.fail(where, f"{key}[{index}]",
                           f"must be a table ([[{inner}]] entry), not {sc.type_name(v)}", v)
        return sc.fail(where, key, f"must be a table ([{inner}]), not {sc.type_name(v)}", v)
    problem = _problem(kind, v, _range(info), info) or " ".join(err["msg"].split())
    return sc.fail(where, key, problem, sc.MISSING if kind == "missing" else v)


def _problem(kind: str, v: Any, rng: Range | None, info) -> str:
    """What is wrong with value ``v`` (pydantic's error ``kind``), in the file's words."""
    allowed = f"{rng.interval}{rng.note}" if rng is not None else ""
    integer = rng is not None and rng.integer
    if kind == "missing":
        return "missing required key"
    if kind in ("greater_than", "greater_than_equal", "less_than", "less_than_equal"):
        return f"out of range, allowed {allowed}"
    if kind in ("float_type", "int_type", "finite_number", "int_from_float"):
        if isinstance(v, int) and not isinstance(v, bool):  # an integer beyond a float
            if rng is None or v in rng.interval:
                return f"out of range (beyond ±1.79769e+308), allowed {allowed or 'any number'}"
            return f"out of range, allowed {allowed}"
        if isinstance(v, float):
            if not math.isfinite(v):
                return f"must be a finite {'integer' if integer else 'number'}"
            return "must be an integer"
        return f"must be {'an integer' if integer else 'a number'}, not {sc.type_name(v)}"
    if kind == "literal_error":
        return f"allowed {', '.join(repr(c) for c in _choices(info.annotation))}"
    if kind == "bool_type":
        return "must be true or false"
    return ""
