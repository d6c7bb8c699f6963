"""A case file's table as a typed section: the house's one way to declare what a table holds.

The machinery is :mod:`fem_prep.sections` (JAX-free, shared with fem_prep's body files): a table
is a :class:`Section`, a pydantic model whose field names are the file's keys (units in the key
names, as the file spells them), each field's type and range declared once with :func:`number`,
:func:`number_list`, :func:`one_of` (a number, an array or a table), :func:`by_sign` (a range by
the sign), ``Literal[...]`` (a name out of a few), ``bool`` and :data:`Text`; keys the model does
not declare are refused, and a table given as anything but a table is refused before pydantic
sees it. Pydantic checks; :func:`schema_error` turns the first of its errors into the project's
one line in the file's words (:mod:`fem_prep.checks`):

* ``[whine] speeds = 1: out of range, allowed [2, 2000]``
* ``[whine] unknown key 'speed' (did you mean 'speeds'?), allowed: harmonics, method, ...``
* ``whine = 0: must be a table ([whine]), not a number``
* ``[lubricant] film = 'x': allowed 'dowson-higginson', 'pan-hamrock', ...``

What relates two keys of a table (a maximum above its minimum, a key read only with another) is
a ``model_validator`` of the section raising :func:`fem_prep.checks.fail`'s one line, which
passes through as it is. A section is frozen; :attr:`Section.given` holds the keys the file gave.

A case file's own: a section reads the file's tables (:meth:`Section.of_file`), reports the
unknown keys of the whole file first, marks a key a table needs where it is used
(:data:`NEEDED`), and checks a range that follows the case (:func:`in_range`).
"""

from __future__ import annotations

import dataclasses
from typing import ClassVar

from pydantic import ConfigDict

from fem_prep import checks as sc, sections as base
from fem_prep.sections import (
    Range,
    Text,
    by_sign,
    named_keys,
    number,
    number_list,
    one_of,
    range_of,
    schema_error,
)

__all__ = ["NEEDED", "Needed", "Range", "Section", "Text", "by_sign", "named_keys", "number",
           "number_list", "one_of", "range_of", "schema_error"]


@dataclasses.dataclass(frozen=True)
class Needed:
    """A key the section leaves optional that is required where its table is used (a rating's
    life, which a train's mesh table may give instead of the shared one): the reference lists
    it as required."""


#: the marker of a :class:`Needed` key (``Annotated[number(...) | None, NEEDED]``)
NEEDED = Needed()


class Section(base.Section):
    """A case file's table (module docstring; :class:`fem_prep.sections.Section`): a frozen
    pydantic model, its fields the table's keys. ``WHERE``: the table's name in the file
    (``"whine"``, ``"acoustics.microphones"``). The unknown keys of the whole file are reported
    before any other error, in its order (as :func:`fem_prep.checks.check_keys` reports them)."""

    model_config = ConfigDict(defer_build=False)
    UNKNOWN_KEYS_FIRST: ClassVar[bool] = True

    @classmethod
    def of_file(cls, data: dict, key: str | None = None, *, required: bool = False,
                context: dict | None = None):
        """The section of the file's table ``data[key]`` (default :attr:`WHERE`; :meth:`read`),
        of an empty table where the file has none (``required``: refused in one line,
        ``[key]: missing required table``)."""
        key = cls.WHERE if key is None else key
        if key not in data and required:
            raise sc.SchemaError(f"[{key}]: missing required table", f"[{key}]")
        return cls.read(data.get(key, {}), key, context=context)

    @classmethod
    def file_keys(cls, context: dict | None = None) -> tuple[str, ...]:
        """The keys a file may give this table (its fields; ``context`` as :meth:`read`'s)."""
        return tuple(cls.model_fields)

    @property
    def given(self) -> frozenset:
        """The keys the file gave (the others hold their defaults)."""
        return frozenset(self.model_fields_set)

    def table(self) -> dict:
        """The keys the file gave and their values, as a table (sub-tables as tables)."""
        return self.model_dump(exclude_unset=True)


# --------------------------------------------------------------------------------------------
# a range that follows the case


def in_range(where: str, key: str, value, allowed: str | sc.Interval, note: str = ""):
    """``value`` (a section's number, already typed) in ``allowed``, a range the section cannot
    declare because it follows the case (another table, the gears, a body file): the value,
    or :func:`fem_prep.checks.number`'s one line for it (``[where] key = value: out of range,
    allowed ...``; an integer's range as an integer's)."""
    integer = isinstance(value, int) and not isinstance(value, bool)
    return sc.number({key: value}, key, where, allowed=allowed, integer=integer, note=note)
