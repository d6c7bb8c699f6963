"""Atomic file output: every file appears complete or not at all (temporary file, then rename).

The JSON and CSV writers are :mod:`fem_prep.files`' (one implementation for both packages): the
one guard against silent NaN and infinity in an output file (:class:`NonFiniteOutput`)."""

from __future__ import annotations

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
