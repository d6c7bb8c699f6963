"""Running an example notebook in a test: the notebook as stored, a probe cell appended that
prints the kernel's values as one ``PROBE{json}`` line, executed in a scratch directory."""

from __future__ import annotations

import json


def execute_with_probe(nb, probe: str, workdir, timeout: int = 900):
    """Append ``probe`` (code printing ``"PROBE" + json.dumps(...)``) to ``nb`` (an nbformat
    notebook, changed in place), execute every cell in a python3 kernel whose working directory is
    ``workdir``, and return (the notebook's code cells before the probe, their stdout joined, the
    probe's dict)."""
    import nbformat
    from nbclient import NotebookClient

    n_cells = len(nb.cells)
    nb.cells.append(nbformat.v4.new_code_cell(probe))
    NotebookClient(
        nb, timeout=timeout, kernel_name="python3", resources={"metadata": {"path": str(workdir)}}
    ).execute()
    code = [c for c in nb.cells[:n_cells] if c.cell_type == "code"]
    text = "".join(o.get("text", "") for c in code for o in c.outputs if o.get("name") == "stdout")
    (got,) = [
        json.loads(line[5:])
        for o in nb.cells[-1].outputs
        for line in o.get("text", "").splitlines()
        if line.startswith("PROBE")
    ]
    return code, text, got
