"""Docs that run: every ```python block of the getting-started and user-guide pages is executed,
the blocks of a page one after another in one namespace (as a reader runs them), so that a
renamed function or a changed signature fails here and not for a user. The pages use small
settings (4 slices, 16 positions per mesh period) so that each page runs in a few seconds."""

import ast
import copy
import inspect
import pathlib
import re
import tomllib
import warnings

import pytest

import jaxgear.io as jio

ROOT = pathlib.Path(__file__).resolve().parents[1]
PAGES = [ROOT / "docs" / "getting-started.md", *sorted((ROOT / "docs" / "guide").glob("*.md"))]
BLOCK = re.compile(r"^```python\n(.*?)^```", re.DOTALL | re.MULTILINE)


def blocks(page: pathlib.Path) -> list[str]:
    return BLOCK.findall(page.read_text(encoding="utf-8"))


def test_every_guide_page_is_collected():
    """The collector finds the pages and their blocks (a page of the guide without a Python
    block is allowed; the getting-started page and at least five guide pages have some)."""
    names = {p.name for p in PAGES}
    assert "getting-started.md" in names and len(PAGES) >= 7
    assert sum(1 for p in PAGES if blocks(p)) >= 6
    assert blocks(ROOT / "docs" / "getting-started.md")


def _run_tier(page: pathlib.Path):
    """The getting-started page runs in the default tier; the user guide's pages in the slow
    tier (their names and keywords are checked by default: test_page_code_names_and_keywords_
    exist)."""
    if page.name == "getting-started.md":
        return page
    return pytest.param(page, marks=pytest.mark.slow)


# default tier: tests/test_docs_code.py::test_page_code_names_and_keywords_exist (every page's names and call keywords, the renamed function or changed signature this test is for) and test_page_code_runs[getting-started.md]
@pytest.mark.parametrize(
    "page", [_run_tier(p) for p in PAGES], ids=lambda p: p.relative_to(ROOT / "docs").as_posix()
)
def test_page_code_runs(page, capsys):
    namespace: dict = {"__name__": "__docs__"}
    for i, code in enumerate(blocks(page)):
        exec(compile(code, f"{page.name}[block {i}]", "exec"), namespace)  # noqa: S102
    out = capsys.readouterr().out
    assert "nan" not in out.lower().split(), out  # printed figures are numbers


OURS = ("jaxgear", "optimise", "fem_prep")


def _chain(node) -> list[str] | None:
    """``a.b.c`` as ``["a", "b", "c"]``; None for anything else (a call's result, a
    subscript)."""
    names = []
    while isinstance(node, ast.Attribute):
        names.append(node.attr)
        node = node.value
    if not isinstance(node, ast.Name):
        return None
    return [node.id, *reversed(names)]


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT / "docs").as_posix())
def test_page_code_names_and_keywords_exist(page):
    """Without running a page (test_page_code_runs does, the guide's pages in the slow tier):
    every name its code reaches through jaxgear, optimise or fem_prep (``jg.quasi_static``,
    ``jio.load_case``, ``from jaxgear.dynamics import Newmark``) exists, and every call of
    such a name gives arguments its signature accepts (the number of positional arguments,
    the keywords' names): a renamed function or a changed signature fails here."""
    tree = ast.parse("\n".join(blocks(page)), page.name)
    namespace: dict = {}
    for node in ast.walk(tree):  # the page's imports, executed (already imported modules)
        if isinstance(node, (ast.Import, ast.ImportFrom)):
            exec(compile(ast.Module([node], []), page.name, "exec"), namespace)  # noqa: S102

    def ours(obj) -> bool:
        module = obj.__name__ if inspect.ismodule(obj) else getattr(obj, "__module__", "")
        return (module or "").split(".")[0] in OURS

    problems = []

    def resolve(chain):
        obj = namespace[chain[0]]
        for i, name in enumerate(chain[1:], 1):
            if not hasattr(obj, name):
                problems.append(f"{'.'.join(chain[: i + 1])}: no such name")
                return None
            obj = getattr(obj, name)
        return obj

    for node in ast.walk(tree):
        chain = _chain(node) if isinstance(node, (ast.Attribute, ast.Name)) else None
        if chain is not None and chain[0] in namespace and ours(namespace[chain[0]]):
            resolve(chain)
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        chain = _chain(node.func)
        if chain is None or chain[0] not in namespace or not ours(namespace[chain[0]]):
            continue
        obj = resolve(chain)
        if obj is None or not callable(obj) or not ours(obj):
            continue
        if any(isinstance(a, ast.Starred) for a in node.args) or any(
            k.arg is None for k in node.keywords
        ):
            continue  # *args or **kwargs: not checked
        try:
            signature = inspect.signature(obj)
        except (TypeError, ValueError):  # pragma: no cover - a callable without a signature
            continue
        try:
            signature.bind(*node.args, **{k.arg: k.value for k in node.keywords})
        except TypeError as err:
            problems.append(f"{'.'.join(chain)} (line {node.lineno}): {err}")
    assert any(ours(v) for v in namespace.values() if inspect.ismodule(v)), page.name
    assert not problems, "\n".join(problems)


TOML = re.compile(r"^```toml\n(.*?)^```", re.DOTALL | re.MULTILINE)


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT / "docs").as_posix())
def test_page_case_files_are_valid(page):
    """Every ```toml block of the getting-started and user-guide pages is a valid case file: a
    whole file (a pair with [pair], a train with [[gears]], a planetary stage with [planetary])
    as it stands, a table alone put
    into the default case in place of its own. The validator checks them before any work, as
    for a user's file."""
    base = tomllib.loads(jio.embedded_case_text("accessory-spur"))
    for block in TOML.findall(page.read_text(encoding="utf-8")):
        data = tomllib.loads(block)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", jio.CaseWarning)
            if "gears" in data or "planetary" in data:
                jio.parse_train(data, "docs")
            elif "pair" in data:
                jio.parse_case(data, "docs")
            else:
                case = copy.deepcopy(base)
                case.update(data)
                jio.parse_case(case, "docs")


def test_annotated_case_file_is_valid():
    """The annotated case file of docs/guide/pair.md ("The case file in detail": every table of a
    pair case, the optional keys commented) is a valid pair case with the default stiffness
    model."""
    text = (ROOT / "docs" / "guide" / "pair.md").read_text(encoding="utf-8")
    block = TOML.findall(text[text.index("## The case file in detail") :])[0]
    case = jio.parse_case(tomllib.loads(block), "docs")
    assert case.stiffness_model == "fe2d"


TEXT = re.compile(r"^```text\n(.*?)^```", re.DOTALL | re.MULTILINE)


def test_rating_page_shows_what_jaxgear_run_writes(tmp_path):
    """The rows of ``rating.md`` quoted on docs/guide/rating.md are those `jaxgear run` writes
    for the page's case (the embedded power-helical pair with the page's ```toml tables), so
    that the quoted figures cannot drift from the program. About 3 s (one rating)."""
    from jaxgear.cli import rating_outputs

    text = (ROOT / "docs" / "guide" / "rating.md").read_text(encoding="utf-8")
    data = tomllib.loads(jio.embedded_case_text("power-helical"))
    data.update(tomllib.loads(TOML.findall(text)[0]))
    section = rating_outputs(jio.parse_case(data, "docs"), str(tmp_path))
    assert section is not None
    written = (tmp_path / "rating.md").read_text(encoding="utf-8").splitlines()
    quoted = [row for row in TEXT.findall(text)[0].splitlines() if row.startswith("| ")]
    assert len(quoted) >= 6
    missing = [row for row in quoted if row not in written]
    assert not missing, missing
