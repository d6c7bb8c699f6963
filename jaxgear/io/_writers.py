"""Atomic file output: every file appears complete or not at all (temporary file, then rename).

The JSON and CSV writers are :mod:`fem_prep.files`' (one implementation for both packages): the
one guard against silent NaN and infinity in an output file (:class:`NonFiniteOutput`)."""

from __future__ import annotations

import functools

from fem_prep.files import NonFiniteOutput, write_csv, write_json
from fem_prep.schema import atomic_open, atomic_write  # one implementation for both packages

__all__ = ["NonFiniteOutput", "atomic_open", "write_csv", "write_json", "write_vtu"]


def write_vtu(path, points, cells, point_data) -> None:
    """Write an unstructured grid (ParaView ``.vtu``, meshio) atomically.

    Args:
        points: (n, 3) coordinates (m). cells: meshio cell blocks, e.g.
            ``[("hexahedron", (n_cells, 8) indices)]``. point_data: name → (n, ...) arrays.
    """
    import meshio  # only where a VTU is written (0.1 s of import otherwise not paid)

    mesh = meshio.Mesh(points, cells, point_data=point_data)
    atomic_write(path, lambda tmp: meshio.write(tmp, mesh, file_format="vtu"))


@functools.singledispatch
def toml_value(v) -> str:
    """``v`` as a TOML value (the case files the commands write: ``--write``): booleans,
    integers, floats in full (``repr``: they read back to the same double), strings, lists and
    tuples as arrays, dicts as inline tables.

    Raises:
        TypeError: a value of any other type.
    """
    raise TypeError(f"cannot write {v!r} as TOML")


@toml_value.register(bool)
def _(v) -> str:
    return "true" if v else "false"


@toml_value.register(int)
def _(v) -> str:
    return str(v)


@toml_value.register(float)
def _(v) -> str:
    return repr(v)


@toml_value.register(str)
def _(v) -> str:
    return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'


@toml_value.register(list)
@toml_value.register(tuple)
def _(v) -> str:
    return "[" + ", ".join(toml_value(x) for x in v) + "]"


@toml_value.register(dict)
def _(v) -> str:
    return "{ " + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + " }"
