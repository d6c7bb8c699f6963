"""Atomic file output: every file appears complete or not at all (temporary file, then rename)."""

from __future__ import annotations

import csv
import functools
import io
import json

from fem_prep.schema import atomic_open, atomic_write  # one implementation for both packages

__all__ = ["atomic_open", "write_csv", "write_json", "write_vtu"]


def write_json(path, data) -> None:
    """Write ``data`` as indented JSON to ``path`` atomically (NaN is written as null)."""
    text = json.dumps(_nan_to_none(data), indent=2)
    with atomic_open(path, "w") as f:
        f.write(text)


@functools.singledispatch
def _nan_to_none(v):
    """``v`` with every float NaN, at any depth of its dicts, lists and tuples, as None."""
    return v


@_nan_to_none.register(float)
def _float_nan_to_none(v):
    return None if v != v else v


@_nan_to_none.register(dict)
def _dict_nan_to_none(v):
    return {k: _nan_to_none(x) for k, x in v.items()}


@_nan_to_none.register(list)
@_nan_to_none.register(tuple)
def _list_nan_to_none(v):
    return [_nan_to_none(x) for x in v]


def write_csv(path, header, columns) -> None:
    """Write columns (equal-length sequences of numbers) under ``header`` to ``path`` atomically,
    12 significant digits."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    for row in zip(*columns):
        w.writerow([f"{v:.12g}" for v in row])
    with atomic_open(path, "w", newline="") as f:
        f.write(buf.getvalue())


def write_vtu(path, points, cells, point_data) -> None:
    """Write an unstructured grid (ParaView ``.vtu``, meshio) atomically.

    Args:
        points: (n, 3) coordinates (m). cells: meshio cell blocks, e.g.
            ``[("hexahedron", (n_cells, 8) indices)]``. point_data: name → (n, ...) arrays.
    """
    import meshio  # only where a VTU is written (0.1 s of import otherwise not paid)

    mesh = meshio.Mesh(points, cells, point_data=point_data)
    atomic_write(path, lambda tmp: meshio.write(tmp, mesh, file_format="vtu"))
