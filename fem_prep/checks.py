"""Input-file checks shared by jaxgear (case files) and fem_prep (body files).

JAX-free (standard library only), so that ``fem_prep`` can use it and ``jaxgear.io`` can import it
by this public name (``from fem_prep import checks as sc``).  One error type, one message style,
one integer rule:

* :class:`SchemaError` (a ``ValueError``) carries ONE line: the key path, the value as written in
  the file (file units: mm, deg, µm, ...), what is wrong and what is allowed, every number with at
  most 6 significant digits, e.g. ``[pinion] face_width_mm = -3: out of range, allowed > 0``.
* Integer keys accept an integral float (``slices = 4.0`` is 4) and reject anything else
  (``teeth = 45.5``); booleans are never numbers; numbers must be finite.
* Unknown keys are errors that list the allowed keys (and suggest the closest one).

The typed sections of both packages (a table as a pydantic model: ``fem_prep.sections`` for the
body files, ``jaxgear.io._sections`` for the case files) turn pydantic's errors into these
messages; the hand-written checks below (:func:`number`, :func:`choice`, :func:`subtable`, ...)
serve the case tables that are not sections yet. The atomic file writers and the embedded input
files of both packages live beside it, in :mod:`fem_prep.files`; the body file's own schema in
:mod:`fem_prep.schema`.
"""

from __future__ import annotations

import datetime
import decimal
import difflib
import functools
import math
import re
import sys
import tomllib
from collections.abc import Iterable
from dataclasses import dataclass
from typing import Any

__all__ = [
    "MISSING",
    "Interval",
    "SchemaError",
    "boolean",
    "check_keys",
    "choice",
    "fail",
    "finite",
    "fmt",
    "g6",
    "interval",
    "key_path",
    "load_toml",
    "name",
    "number",
    "number_list",
    "string",
    "subtable",
    "subtables",
    "table_array",
    "type_name",
]


class SchemaError(ValueError):
    """An input file does not follow its schema; the message is one line (see module doc).

    Attributes:
        path: the key path, e.g. ``"[pinion] face_width_mm"`` ("" when the whole file is bad).
    """

    def __init__(self, message: str, path: str = ""):
        super().__init__(_one_line(message))
        self.path = path


class _Missing:
    def __repr__(self) -> str:
        return "MISSING"


MISSING: Any = _Missing()
"""Default of a required key."""


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


# --------------------------------------------------------------------------------------------
# formatting


_NUMBER = re.compile(r"(?<![\w.])-?\d+\.\d+(?:[eE][-+]?\d+)?(?![\w.])")


def g6(text: str) -> str:
    """Rewrite every decimal number in ``text`` with at most 6 significant digits."""
    return _NUMBER.sub(lambda m: f"{float(m.group()):.6g}", text)


@functools.singledispatch
def _type_name(v: Any) -> str:
    """What a TOML value is, for messages: ``a number``, ``a table``, ... (by its Python type)."""
    return type(v).__name__


_TYPE_NAMES = (
    (bool, "a boolean"),  # before int: a bool is an int to isinstance, not to singledispatch
    (int, "a number"),
    (float, "a number"),
    (str, "a string"),
    (dict, "a table"),
    (list, "an array"),
    (datetime.date, "a date/time"),
    (datetime.time, "a date/time"),
)
for _cls, _text in _TYPE_NAMES:
    _type_name.register(_cls, lambda v, _text=_text: _text)
#: what a TOML value is, in the messages' words (``a number``, ``a table``, ...)
type_name = _type_name


def _fmt_int(v: int) -> str:
    """An integer, beyond 10^6 with 6 significant digits (also beyond the float range)."""
    if abs(v) < 10**6:
        return str(v)
    if abs(v) < 10**300:
        return f"{v:.6g}"
    mantissa, exponent = f"{decimal.Decimal(v):.5e}".split("e")  # no float, no str(int) limit
    return f"{mantissa.rstrip('0').rstrip('.')}e{exponent}"


@functools.singledispatch
def finite(v: Any) -> bool:
    """``v`` is a finite number (``int`` or ``float``, not a boolean) that a float can hold."""
    return False


@finite.register
def _(v: int) -> bool:
    return abs(v) <= _FLOAT_MAX


@finite.register
def _(v: float) -> bool:
    return math.isfinite(v)


@finite.register
def _(v: bool) -> bool:
    return False


_FLOAT_MAX = int(sys.float_info.max)


@functools.singledispatch
def fmt(v: Any, _depth: int = 0) -> str:
    """A value as it reads in a TOML file, numbers with at most 6 significant digits, short."""
    return _one_line(str(v))[:40]


@fmt.register
def _(v: bool, _depth: int = 0) -> str:
    return "true" if v else "false"


@fmt.register
def _(v: int, _depth: int = 0) -> str:
    return _fmt_int(v)


@fmt.register
def _(v: float, _depth: int = 0) -> str:
    return f"{v:.6g}"


@fmt.register
def _(v: str, _depth: int = 0) -> str:
    s = v if len(v) <= 40 else v[:37] + "..."
    return repr(s)


@fmt.register
def _(v: list, _depth: int = 0) -> str:
    if _depth > 1:
        return "[...]"
    items = [fmt(x, _depth + 1) for x in v[:6]]
    return "[" + ", ".join(items + (["..."] if len(v) > 6 else [])) + "]"


@fmt.register
def _(v: dict, _depth: int = 0) -> str:
    if _depth > 1:
        return "{...}"
    items = [f"{_key(k)} = {fmt(x, _depth + 1)}" for k, x in list(v.items())[:4]]
    return "{ " + ", ".join(items + (["..."] if len(v) > 4 else [])) + " }"


_BARE = re.compile(r"[A-Za-z0-9_-]{1,60}(?:\.[A-Za-z0-9_-]{1,60})*")


def _key(k: Any) -> str:
    k = str(k)
    if _BARE.fullmatch(k):
        return k
    s = k if len(k) <= 40 else k[:37] + "..."
    return repr(s)


def key_path(where: str, key: str | None = None) -> str:
    """``("pinion", "teeth")`` → ``"[pinion] teeth"``; ``("", "name")`` → ``"name"``."""
    if key is None:
        return f"[{where}]" if where else "the file"
    return f"[{where}] {_key(key)}" if where else _key(key)


def fail(where: str, key: str | None, problem: str, value: Any = MISSING) -> SchemaError:
    """The :class:`SchemaError` ``[where] key = value: problem`` (to be raised by the caller)."""
    p = key_path(where, key)
    head = p if value is MISSING else f"{p} = {fmt(value)}"
    return SchemaError(f"{head}: {problem}", p)


# --------------------------------------------------------------------------------------------
# ranges


@dataclass(frozen=True)
class Interval:
    """A range of allowed numbers; ``str`` gives ``> 0``, ``[0, 45)``, ``>= 5`` ...

    Build from text with :meth:`parse`: ``"> 0"``, ``">= 0"``, ``"< 1"``, ``"<= 1"``,
    ``"(0, 1]"``, ``"[3, 1000]"``, ``"any"``.
    """

    lo: float = -math.inf
    hi: float = math.inf
    lo_open: bool = False
    hi_open: bool = False

    def __contains__(self, v: float) -> bool:
        above = v > self.lo if self.lo_open else v >= self.lo
        below = v < self.hi if self.hi_open else v <= self.hi
        return bool(above and below)

    def __str__(self) -> str:
        lo, hi = f"{self.lo:.6g}", f"{self.hi:.6g}"
        if self.lo == -math.inf and self.hi == math.inf:
            return "any finite number"
        if self.hi == math.inf:
            return f"{'>' if self.lo_open else '>='} {lo}"
        if self.lo == -math.inf:
            return f"{'<' if self.hi_open else '<='} {hi}"
        return f"{'(' if self.lo_open else '['}{lo}, {hi}{')' if self.hi_open else ']'}"

    @classmethod
    def parse(cls, text: str | Interval | None) -> Interval:
        """The interval of a range text (see the class doc); an :class:`Interval` is returned as
        is and ``None`` is any finite number (the same as :func:`interval`)."""
        return interval(text)

    @classmethod
    def from_text(cls, text: str) -> Interval:
        """The interval of a range text: ``"> 0"``, ``"[3, 1000]"``, ``"any"`` ...

        Raises:
            ValueError: ``text`` is not one of these forms.
        """
        t = text.strip()
        if t == "any":
            return cls()
        m = re.fullmatch(r"(>=|<=|>|<)\s*(\S+)", t)
        if m:
            op, v = m.group(1), float(m.group(2))
            if op[0] == ">":
                return cls(lo=v, lo_open=op == ">")
            return cls(hi=v, hi_open=op == "<")
        m = re.fullmatch(r"([\[(])\s*(\S+)\s*,\s*(\S+)\s*([\])])", t)
        if not m:
            raise ValueError(f"bad interval {text!r}")
        return cls(float(m.group(2)), float(m.group(3)), m.group(1) == "(", m.group(4) == ")")


@functools.singledispatch
def interval(allowed: Interval) -> Interval:
    """The :class:`Interval` of an ``allowed=`` argument: an interval as is, a range text
    parsed (:meth:`Interval.from_text`), ``None`` any finite number."""
    return allowed


@interval.register
def _(allowed: str) -> Interval:
    return Interval.from_text(allowed)


@interval.register(type(None))
def _(allowed: None) -> Interval:
    return Interval()


# --------------------------------------------------------------------------------------------
# checks


def did_you_mean(name: str, names: Iterable[str]) -> str:
    """`` (did you mean 'x'?)`` naming the one of ``names`` closest to a mistyped ``name``
    (difflib's ratio >= 0.7), or ``""`` where none is close: the hint of an unknown key
    (:func:`check_keys`) or an unknown embedded case or body name."""
    close = difflib.get_close_matches(str(name), list(names), n=1, cutoff=0.7)
    return f" (did you mean {close[0]!r}?)" if close else ""


def check_keys(table: dict, allowed: Iterable[str], where: str) -> None:
    """Unknown keys are errors:
    ``[mesh] unknown key 'slice' (did you mean 'slices'?), allowed: foundation, ...``."""
    allowed = sorted(allowed)
    for key in table:
        if key not in allowed:
            hint = did_you_mean(str(key), allowed)
            shown = str(key) if len(str(key)) <= 40 else str(key)[:37] + "..."
            head = f"[{where}] " if where else ""
            raise SchemaError(
                f"{head}unknown key {shown!r}{hint}, allowed: {', '.join(allowed)}",
                key_path(where, key),
            )


def subtable(
    data: dict,
    key: str,
    where: str,
    allowed: Iterable[str] | None = None,
    *,
    required: bool = False,
) -> dict:
    """``data[key]`` as a table (``{}`` if absent and not required); unknown keys checked."""
    inner = f"{where}.{_key(key)}" if where else _key(key)
    if key not in data:
        if required:
            raise SchemaError(f"[{inner}]: missing required table", f"[{inner}]")
        return {}
    t = data[key]
    if not isinstance(t, dict):
        raise fail(where, key, f"must be a table ([{inner}]), not {_type_name(t)}", t)
    if allowed is not None:
        check_keys(t, allowed, inner)
    return t


def subtables(data: dict, keys: Iterable[str], where: str) -> None:
    """Each of ``keys`` present in ``data`` is a table (:func:`subtable`'s one line otherwise):
    a file's table-valued keys checked at once, before the readers that take the table."""
    for key in keys:
        subtable(data, key, where)


def table_array(
    data: dict,
    key: str,
    where: str,
    allowed: Iterable[str] | None = None,
    *,
    required: bool = False,
) -> list[dict]:
    """``data[key]`` as an array of tables (``[[where.key]]``; ``[]`` if absent and not
    required): a value that is not an array, or an entry that is not a table, is one line naming
    the key (``[housing] seats = 0: must be an array of tables ([[housing.seats]]), not a
    number``); each entry's unknown keys checked against ``allowed``."""
    inner = f"{where}.{_key(key)}" if where else _key(key)
    if key not in data:
        if required:
            raise SchemaError(f"[[{inner}]]: missing required array of tables", f"[[{inner}]]")
        return []
    v = data[key]
    if not isinstance(v, list):
        raise fail(where, key, f"must be an array of tables ([[{inner}]]), not {_type_name(v)}", v)
    for k, t in enumerate(v):
        if not isinstance(t, dict):
            raise fail(
                where, f"{key}[{k}]", f"must be a table ([[{inner}]] entry), not {_type_name(t)}", t
            )
        if allowed is not None:
            check_keys(t, allowed, f"{inner}[{k}]")
    return v


def number(
    table: dict,
    key: str,
    where: str,
    default: Any = MISSING,
    *,
    allowed: str | Interval | None = None,
    integer: bool = False,
    note: str = "",
):
    """A finite number (``int`` when ``integer``), checked against ``allowed`` in file units.

    ``default``: :data:`MISSING` makes the key required; any other value (``None`` included) is
    returned as is when the key is absent.  ``note`` is appended to the range message.
    """
    if key not in table:
        if default is MISSING:
            raise fail(where, key, "missing required key")
        return default
    v = table[key]
    kind = "an integer" if integer else "a number"
    if isinstance(v, bool) or not isinstance(v, (int, float)):
        raise fail(where, key, f"must be {kind}, not {_type_name(v)}", v)
    if isinstance(v, float) and not math.isfinite(v):
        raise fail(where, key, f"must be a finite {kind[2:] if integer else 'number'}", v)
    if integer and isinstance(v, float) and not v.is_integer():
        raise fail(where, key, "must be an integer", v)
    rng = interval(allowed)
    if v not in rng:  # exact for integers of any size (no float conversion yet)
        raise fail(where, key, f"out of range, allowed {rng}{note}", v)
    if not finite(v):  # an integer beyond the float range, in an unbounded range
        raise fail(where, key, f"out of range (beyond ±1.79769e+308), allowed {rng}{note}", v)
    return int(v) if integer else float(v)


def number_list(
    table: dict,
    key: str,
    where: str,
    default: Any = MISSING,
    *,
    min_length: int = 0,
    length: int | None = None,
    allowed: str | Interval | None = None,
    note: str = "",
) -> list[float]:
    """An array of finite numbers (each checked against ``allowed``; ``note`` is appended to the
    range message, as :func:`number`'s)."""
    if key not in table:
        if default is MISSING:
            raise fail(where, key, "missing required key")
        return default
    v = table[key]
    if not isinstance(v, list):
        raise fail(where, key, f"must be an array of numbers, not {_type_name(v)}", v)
    if length is not None and len(v) != length:
        raise fail(where, key, f"must be an array of {length} numbers", v)
    if len(v) < min_length:
        raise fail(where, key, f"must be an array of at least {min_length} numbers", v)
    rng = interval(allowed)
    out = []
    for x in v:
        if not finite(x):
            raise fail(where, key, "must be an array of finite numbers", v)
        if x not in rng:
            raise fail(where, key, f"element {fmt(x)} out of range, allowed {rng}{note}", v)
        out.append(float(x))
    return out


def choice(table: dict, key: str, where: str, choices: Iterable[str], default: Any = MISSING):
    """A string out of ``choices``."""
    if key not in table:
        if default is MISSING:
            raise fail(where, key, "missing required key")
        return default
    v = table[key]
    choices = list(choices)
    if not isinstance(v, str) or v not in choices:
        raise fail(where, key, f"allowed {', '.join(repr(c) for c in choices)}", v)
    return v


def boolean(table: dict, key: str, where: str, default: Any = MISSING):
    """``true`` or ``false``."""
    if key not in table:
        if default is MISSING:
            raise fail(where, key, "missing required key")
        return default
    v = table[key]
    if not isinstance(v, bool):
        raise fail(where, key, "must be true or false", v)
    return v


def string(table: dict, key: str, where: str, default: Any = MISSING) -> str:
    """A non-empty string."""
    if key not in table:
        if default is MISSING:
            raise fail(where, key, "missing required key")
        return default
    v = table[key]
    if not isinstance(v, str) or not v.strip():
        raise fail(where, key, "must be a non-empty string", v)
    return v


_NAME = re.compile(r"[A-Za-z0-9_][A-Za-z0-9_.-]{0,99}")


def name(table: dict, key: str, where: str, default: Any = MISSING) -> str:
    """A name that becomes a file or folder name (``jaxgear-out/<name>/``, ``<name>.npz``): 1 to
    100 letters, digits, ``-``, ``_``, ``.``, not starting with ``.`` or ``-``, so never a path
    (no separator, no ``..``, not absolute)."""
    v = string(table, key, where, default)
    if key not in table:  # the default (a file's stem): a path only in odd cases such as '..'
        if isinstance(v, str) and (v in ("", ".", "..") or re.search(r"[/\\\x00]", v)):
            raise fail(where, key, f"missing; the default {v!r} (from the file name) is not a name")
        return v
    if not _NAME.fullmatch(v):
        raise fail(
            where,
            key,
            "a name, not a path: 1 to 100 letters, digits, '-', '_', '.' allowed (not starting "
            "with '.' or '-')",
            v,
        )
    return v


def load_toml(raw: bytes | str, label: str) -> dict:
    """Decode (UTF-8) and parse TOML text; errors are one-line :class:`SchemaError` naming
    ``label`` (e.g. ``"case file 'x.toml'"``)."""
    raw = _decoded(raw, label)
    try:
        return tomllib.loads(raw)
    except tomllib.TOMLDecodeError as err:
        raise SchemaError(f"{label} is not valid TOML: {_toml_error(str(err), raw)}") from None
    except ValueError as err:  # e.g. an integer of more than 4300 digits
        raise SchemaError(f"{label} is not valid TOML: {err}") from None
    except RecursionError:
        raise SchemaError(f"{label} is not valid TOML: nested too deeply") from None


@functools.singledispatch
def _decoded(raw: str, label: str) -> str:
    """The text of a file's contents: ``str`` as is, ``bytes`` decoded as UTF-8."""
    return raw


@_decoded.register
def _(raw: bytes, label: str) -> str:
    try:
        return raw.decode("utf-8")
    except UnicodeDecodeError as err:
        raise SchemaError(
            f"{label} is not valid UTF-8 text (byte 0x{err.object[err.start]:02x} at offset "
            f"{err.start})"
        ) from None


_AT = re.compile(r"\s*\(at line (\d+), column (\d+)\)$")
_HEADER = re.compile(r"\s*(\[\[?)\s*([^\]#,\[{=]+?)\s*\]\]?\s*(?:#.*)?$")
_PART = r"""(?:[A-Za-z0-9_-]+|"[^"]*"|'[^']*')"""  # a bare or quoted key
_KEY_AT = re.compile(rf"\s*({_PART}(?:\s*\.\s*{_PART})*)\s*=")


def _toml_error(message: str, text: str) -> str:
    """tomllib's message with the key path it stops at, read from the line it names (and the
    table header above it): ``Cannot overwrite a value (at line 14, column 20)`` becomes
    ``duplicate key 'face_width_mm' in [[gears]] #2 (line 14, column 20)``."""
    m = _AT.search(message)
    lines = text.splitlines()
    if m:
        line_no, col = int(m.group(1)), int(m.group(2))
    else:  # "(at end of document)": the last line that holds something
        m = re.search(r"\s*\(at end of document\)$", message)
        filled = [i for i, line in enumerate(lines, 1) if line.strip()]
        if not m or not filled:
            return message
        line_no = filled[-1]
        col = len(lines[line_no - 1]) + 1
    if not 1 <= line_no <= len(lines):
        return message
    table, counts = "", {}
    for line in lines[: line_no - 1]:  # the table the line lies in (its header above it)
        h = _HEADER.match(line)
        if h:
            name = re.sub(r"\s*\.\s*", ".", h.group(2))
            if h.group(1) == "[[":
                counts[name] = counts.get(name, 0) + 1
                table = f"[[{name}]] #{counts[name]}"
            else:
                table = f"[{name}]"
    line = lines[line_no - 1]
    header = _HEADER.match(line)
    key = _KEY_AT.match(line)
    where = f"line {line_no}, column {col}"
    what = message[: m.start()]
    if header:
        name = re.sub(r"\s*\.\s*", ".", header.group(2))
        if what.startswith("Cannot declare"):
            return f"table [{name}] declared twice ({where})"
        return f"{what} in the header [{name}] ({where})"
    if key:
        k = re.sub(r"\s*\.\s*", ".", key.group(1))
        inside = f" in {table}" if table else ""
        if what == "Cannot overwrite a value":
            return f"duplicate key {k!r}{inside} ({where})"
        return f"{what} at key {k!r}{inside} ({where})"
    text = line.strip()
    near = f" near {text if len(text) <= 30 else text[:27] + '...'!r}" if text else ""
    return f"{what}{near}{f' in {table}' if table else ''} ({where})"
