"""Docs that run: every ```python block of the getting-started and user-guide pages is executed,
the blocks of a page one after another in one namespace (as a reader runs them), so that a
renamed function or a changed signature fails here and not for a user. The pages use small
settings (4 slices, 16 positions per mesh period) so that each page runs in a few seconds."""

import copy
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


@pytest.mark.parametrize("page", PAGES, ids=lambda p: p.relative_to(ROOT / "docs").as_posix())
def test_page_code_runs(page, capsys):
    namespace: dict = {"__name__": "__docs__"}
    for i, code in enumerate(blocks(page)):
        exec(compile(code, f"{page.name}[block {i}]", "exec"), namespace)  # noqa: S102
    out = capsys.readouterr().out
    assert "nan" not in out.lower().split(), out  # printed figures are numbers


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
