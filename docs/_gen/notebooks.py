"""The example notebooks are stored executed, with their outputs (figures and printed tables), so
that their documentation pages show them without the site running them. This module executes a
notebook in a fresh kernel (working directory ``examples/``, as Jupyter opened there runs it) and
records the hash of the code it ran in the notebook's metadata; ``tests/test_notebook_outputs.py``
fails when a code cell was edited afterwards (stored outputs no longer those of the code).

Run from the repository root after editing a notebook::

    python -m docs._gen.notebooks examples/master_curve.ipynb [more.ipynb ...]
"""

from __future__ import annotations

import hashlib
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[2]
#: the notebook metadata key holding :func:`source_hash` of the executed code
KEY = "jaxgear"


def source_hash(cells) -> str:
    """SHA-256 (hex) of the code cells' sources, in order, each followed by a NUL byte."""
    digest = hashlib.sha256()
    for cell in cells:
        if cell["cell_type"] == "code":
            source = cell["source"]
            digest.update(("".join(source) if isinstance(source, list) else source).encode())
            digest.update(b"\0")
    return digest.hexdigest()


def execute(path: pathlib.Path, timeout: int = 1800) -> None:
    """Execute the notebook at ``path`` in place (every cell, a fresh ``python3`` kernel, in
    ``examples/``) and store its outputs (but what it wrote to stderr: library warnings) and the
    hash of its code. Raises the kernel's error
    when a cell fails (the notebook file is then left unchanged)."""
    import nbformat
    from nbclient import NotebookClient

    nb = nbformat.read(path, as_version=4)
    NotebookClient(
        nb,
        timeout=timeout,
        kernel_name="python3",
        record_timing=False,  # no timestamps in the stored file
        resources={"metadata": {"path": str(path.parent)}},
    ).execute()
    for cell in nb.cells:  # library warnings on stderr are not part of the example
        if cell.cell_type == "code":
            cell.outputs = [o for o in cell.outputs if o.get("name") != "stderr"]
    nb.metadata[KEY] = {"executed_source_sha256": source_hash(nb.cells)}
    nbformat.write(nb, path)


if __name__ == "__main__":
    for name in sys.argv[1:]:
        execute(pathlib.Path(name).resolve())
        print(f"executed {name}")
