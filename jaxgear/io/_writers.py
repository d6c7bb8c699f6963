"""Atomic file output: every file appears complete or not at all (temporary file, then rename).

One guard for every JSON and CSV output: a value that is NaN or infinite is written as ``null``
(JSON) or ``nan``/``inf`` (CSV) and warned about (:class:`NonFiniteOutput`, one line naming the
file and its fields, and the cause where the caller knows it). A value that is absent on purpose
(a diverged speed, an order outside the housing's band) is written as ``None`` by its caller:
``null`` with no warning."""

from __future__ import annotations

import csv
import functools
import io
import json
import math
import os
import warnings

from fem_prep.schema import atomic_open, atomic_write  # one implementation for both packages

__all__ = ["NonFiniteOutput", "atomic_open", "write_csv", "write_json", "write_vtu"]

#: the fields a warning names before it counts the rest
_SHOWN = 4


class NonFiniteOutput(UserWarning):
    """An output file holds NaN or infinite values: the message names the file, its fields
    (JSON: ``rating.S_H[1]``, an array's entries as ``levels_dB[]`` with their count; CSV: the
    columns) and, where the writer's caller knows it, the input that caused them."""


def _warn_non_finite(path, fields: dict[str, int], cause: str | None) -> None:
    if not fields:
        return
    shown = [f"{k} ({n} entries)" if n > 1 else k for k, n in list(fields.items())[:_SHOWN]]
    more = f" and {len(fields) - _SHOWN} more fields" if len(fields) > _SHOWN else ""
    why = f": {cause}" if cause else ""
    warnings.warn(
        f"{os.path.basename(path)}: NaN or infinite values in {', '.join(shown)}{more}{why}",
        NonFiniteOutput,
        stacklevel=3,
    )


def write_json(path, data, *, cause: str | None = None) -> None:
    """Write ``data`` as indented JSON to ``path`` atomically. NaN and ±inf are written as
    null with a :class:`NonFiniteOutput` warning naming their fields (``cause``: the input
    that made them, when the caller knows it); ``None`` is null without one."""
    fields: dict[str, int] = {}
    text = json.dumps(_finite_or_none(data, "", fields), indent=2, allow_nan=False)
    with atomic_open(path, "w") as f:
        f.write(text)
    _warn_non_finite(path, fields, cause)


@functools.singledispatch
def _finite_or_none(v, where: str, fields: dict):
    """``v`` with every non-finite float, at any depth of its dicts, lists and tuples, as None;
    each one's field (array entries as ``name[]``) counted in ``fields``."""
    return v


@_finite_or_none.register(float)
def _float_finite_or_none(v, where: str, fields: dict):
    if math.isfinite(v):
        return v
    fields[where or "the value"] = fields.get(where or "the value", 0) + 1
    return None


@_finite_or_none.register(dict)
def _dict_finite_or_none(v, where: str, fields: dict):
    return {
        k: _finite_or_none(x, f"{where}.{k}" if where else str(k), fields) for k, x in v.items()
    }


@_finite_or_none.register(list)
@_finite_or_none.register(tuple)
def _list_finite_or_none(v, where: str, fields: dict):
    return [_finite_or_none(x, f"{where}[]", fields) for x in v]


def write_csv(path, header, columns, *, cause: str | None = None) -> None:
    """Write columns (equal-length sequences of numbers) under ``header`` to ``path`` atomically,
    12 significant digits; ``None`` (no value) as an empty cell. NaN and ±inf are written as
    ``nan``/``inf`` with a :class:`NonFiniteOutput` warning naming their columns (``cause`` as
    :func:`write_json`)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    fields: dict[str, int] = {}
    for row in zip(*columns):
        for name, v in zip(header, row):
            if v is not None and not math.isfinite(v):
                fields[name] = fields.get(name, 0) + 1
        w.writerow(["" if v is None else f"{v:.12g}" for v in row])
    with atomic_open(path, "w", newline="") as f:
        f.write(buf.getvalue())
    _warn_non_finite(path, fields, cause)


def write_vtu(path, points, cells, point_data) -> None:
    """Write an unstructured grid (ParaView ``.vtu``, meshio) atomically.

    Args:
        points: (n, 3) coordinates (m). cells: meshio cell blocks, e.g.
            ``[("hexahedron", (n_cells, 8) indices)]``. point_data: name → (n, ...) arrays.
    """
    import meshio  # only where a VTU is written (0.1 s of import otherwise not paid)

    mesh = meshio.Mesh(points, cells, point_data=point_data)
    atomic_write(path, lambda tmp: meshio.write(tmp, mesh, file_format="vtu"))
