"""The example pages: one page per script and notebook of ``examples/`` (its docstring or
Markdown cells, the figures it writes into ``docs/bench/`` or ``docs/img/``, the outputs stored
with a notebook, the documentation pages that discuss it, and its source), so that a new example
gets its page without editing one."""

from __future__ import annotations

import ast
import base64
import json
import pathlib
import re

from docs._gen.griffe_roles import plain

ROOT = pathlib.Path(__file__).resolve().parents[2]
EXAMPLES = ROOT / "examples"
DOCS = ROOT / "docs"
#: the folders of docs/ holding the figures and records the examples and benchmarks write
FIGURE_DIRS = ("bench", "img")
#: a figure the source names: "name.png"
FIGURE = re.compile(r"([A-Za-z0-9_-]+\.png)")
#: figures an example makes without naming them: quickstart.py runs `jaxgear run`'s quasi-static
#: files on the accessory pair, those that Getting started shows
MADE_ELSEWHERE = {
    "quickstart.py": (
        "img/getting-started-transmission_error.png",
        "img/getting-started-mesh_stiffness.png",
        "img/getting-started-load_map.png",
        "img/getting-started-pressure_map.png",
        "img/getting-started-harris_map.png",
    ),
}


def _figures(path: pathlib.Path, source: str) -> list[str]:
    """The PNG files (paths under docs/) that the example writes: those of docs/bench/ and
    docs/img/ its source names, and those of :data:`MADE_ELSEWHERE`."""
    names = dict.fromkeys(FIGURE.findall(source))
    found = [f"{d}/{n}" for n in names for d in FIGURE_DIRS if (DOCS / d / n).is_file()]
    return found + list(MADE_ELSEWHERE.get(path.name, ()))


def _title(page: pathlib.Path) -> str:
    """The first heading of a documentation page."""
    for line in page.read_text(encoding="utf-8").splitlines():
        if line.startswith("# "):
            return line[2:].strip()
    return page.stem


def discussed_on(path: pathlib.Path) -> list[str]:
    """Markdown links (from the example's page) to the documentation pages that name the
    example (``examples/<name>``), the Examples overview aside."""
    out = []
    for page in sorted(DOCS.rglob("*.md")):
        rel = page.relative_to(DOCS)
        if rel.parts[0] == "_gen" or rel.as_posix() == "examples.md":
            continue
        if f"examples/{path.name}" in page.read_text(encoding="utf-8"):
            out.append(f"[{_title(page)}](../{rel.as_posix()})")
    return out


def script_page(path: pathlib.Path) -> tuple[str, str]:
    """(title, markdown) of an example script."""
    source = path.read_text(encoding="utf-8")
    doc = plain(ast.get_docstring(ast.parse(source)) or "")
    title, _, body = doc.partition("\n\n")  # the first paragraph, then the rest
    title = " ".join(title.split())
    out = [f"# `{path.name}`", "", title, "", body.strip(), ""]
    out += [f"![{pathlib.Path(n).stem}](../{n})" for n in _figures(path, source)] + [""]
    pages = discussed_on(path)
    if pages:
        out += ["Discussed on: " + ", ".join(pages) + ".", ""]
    out += [
        f"Run from the repository root: `python examples/{path.name}`.",
        "",
        '??? example "Source"',
        "",
        "    ```python",
        *("    " + line if line else "" for line in source.splitlines()),
        "    ```",
        "",
    ]
    return title.rstrip("."), "\n".join(out)


def _outputs(cell: dict, stem: str, figures: dict[str, bytes]) -> list[str]:
    """The Markdown of a code cell's stored outputs: text as a text block, a PNG as an image
    (its bytes put in ``figures`` under the site path ``examples/<stem>-<n>.png``). Nothing is
    executed here: a notebook saved without outputs would show its code only."""
    out = []
    for o in cell.get("outputs", []):
        data = o.get("data", {})
        if "image/png" in data:
            name = f"{stem}-{len(figures) + 1}.png"
            png = data["image/png"]
            figures[f"examples/{name}"] = base64.b64decode(
                "".join(png) if isinstance(png, list) else png
            )
            out += [f"![output {len(figures)}]({name})", ""]
            continue
        text = o.get("text") if o.get("output_type") == "stream" else data.get("text/plain")
        if text:
            out += ["```text", "".join(text).rstrip("\n"), "```", ""]
    return out


def notebook(path: pathlib.Path) -> tuple[str, str, dict[str, bytes]]:
    """(title, markdown, figures) of an example notebook: its Markdown cells, its code and the
    outputs stored with it (``figures``: site path → PNG bytes; the notebooks are stored executed,
    :mod:`docs._gen.notebooks`)."""
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    out = [f"# `{path.name}`", ""]
    title = ""
    figures: dict[str, bytes] = {}
    for cell in cells:
        text = "".join(cell["source"])
        if cell["cell_type"] == "markdown":
            text = re.sub(r"^(#+) ", lambda m: "#" + m.group(1) + " ", text, flags=re.M)
            title = title or text.strip().splitlines()[0].lstrip("# ")
            out += [plain(text), ""]
        elif cell["cell_type"] == "code" and text.strip():
            out += ["```python", text, "```", ""]
            out += _outputs(cell, path.stem, figures)
    pages = discussed_on(path)
    if pages:
        out += ["Discussed on: " + ", ".join(pages) + ".", ""]
    out += [f"Open it with Jupyter: `jupyter lab examples/{path.name}`.", ""]
    return title, "\n".join(out), figures


def notebook_page(path: pathlib.Path) -> tuple[str, str]:
    """(title, markdown) of an example notebook (:func:`notebook`)."""
    title, text, _ = notebook(path)
    return title, text


def figures() -> dict[str, bytes]:
    """``{site path: PNG bytes}`` of the figures stored in the example notebooks' outputs."""
    out: dict[str, bytes] = {}
    for path in sorted(EXAMPLES.glob("*.ipynb")):
        out.update(notebook(path)[2])
    return out


def pages() -> dict[str, tuple[str, str]]:
    """``{page path: (title, markdown)}`` of every example."""
    out = {}
    for path in sorted(EXAMPLES.glob("*.py")):
        out[f"examples/{path.stem}.md"] = script_page(path)
    for path in sorted(EXAMPLES.glob("*.ipynb")):
        out[f"examples/{path.stem}.md"] = notebook_page(path)
    return out
