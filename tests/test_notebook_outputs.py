"""The example notebooks are stored executed, so that their documentation pages show their
figures and printed tables without the site running them: every code cell ran, in order, in one
fresh kernel, the plots are in the stored outputs, and the outputs are those of the code as it
stands (the hash of the code cells recorded when the notebook was executed, by
``python -m docs._gen.notebooks``, is that of the cells now: editing a cell without executing the
notebook again fails here). The notebooks' values are checked against references by the slow
tests that execute them (tests/test_notebook_thin_webbed.py, tests/test_optimise.py). < 1 s."""

from __future__ import annotations

import hashlib
import json
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
# the examples' notebooks and those of their folders (examples/sizing/explore.ipynb)
NOTEBOOKS = sorted([*(ROOT / "examples").glob("*.ipynb"), *(ROOT / "examples").glob("*/*.ipynb")])


def code_hash(cells: list[dict]) -> str:
    """SHA-256 of the code cells' sources, in order, each followed by a NUL byte (written here
    from the rule that docs/_gen/notebooks.py states, not imported from it)."""
    h = hashlib.sha256()
    for cell in cells:
        if cell["cell_type"] == "code":
            source = cell["source"]
            h.update(("".join(source) if isinstance(source, list) else source).encode("utf-8"))
            h.update(b"\0")
    return h.hexdigest()


def test_there_are_notebooks():
    assert {p.name for p in NOTEBOOKS} >= {"master_curve.ipynb", "thin_webbed_gear.ipynb"}


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.name)
def test_stored_outputs_are_those_of_the_code(path):
    nb = json.loads(path.read_text(encoding="utf-8"))
    recorded = nb["metadata"].get("jaxgear", {}).get("executed_source_sha256")
    assert recorded, f"{path.name} is stored unexecuted: python -m docs._gen.notebooks {path}"
    assert recorded == code_hash(nb["cells"]), (
        f"{path.name}: a code cell changed since the notebook was executed; run "
        f"python -m docs._gen.notebooks examples/{path.name}"
    )
    code = [c for c in nb["cells"] if c["cell_type"] == "code" and "".join(c["source"]).strip()]
    # one run of every cell, in order, in a fresh kernel
    assert [c["execution_count"] for c in code] == list(range(1, len(code) + 1))
    for c in code:
        kinds = {o["output_type"] for o in c["outputs"]}
        assert "error" not in kinds, "".join(c["source"])[:200]
        assert not any(o.get("name") == "stderr" for o in c["outputs"])
        if "plt.show()" in "".join(c["source"]):  # each plot is stored as a PNG
            assert any("image/png" in o.get("data", {}) for o in c["outputs"]), c["source"][:3]
    # kept small: a few figures at the inline resolution
    assert path.stat().st_size < 600_000, path.stat().st_size


def test_code_hash_is_the_executors(tmp_path):
    """The executor's hash (docs/_gen/notebooks.py) is the rule above, and it changes with any
    edit of a code cell, not with outputs or Markdown."""
    from docs._gen import notebooks

    nb = json.loads(NOTEBOOKS[0].read_text(encoding="utf-8"))
    assert notebooks.source_hash(nb["cells"]) == code_hash(nb["cells"])
    before = code_hash(nb["cells"])
    for cell in nb["cells"]:
        if cell["cell_type"] == "markdown":
            cell["source"] = ["# another title\n"]
        else:
            cell["outputs"] = []
    assert code_hash(nb["cells"]) == before
    code = next(c for c in nb["cells"] if c["cell_type"] == "code")
    code["source"] = [*code["source"], "\nx = 1"]
    assert code_hash(nb["cells"]) != before
