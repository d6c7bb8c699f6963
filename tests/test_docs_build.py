"""The documentation site builds with warnings as errors (``mkdocs build --strict``: broken
links, missing pages, unresolved API names and docstrings griffe cannot parse fail), and the
generated pages hold what they are generated from: the case-file reference the validator's keys,
the API pages the public names with their signatures. The build (about 15 s of CPU) is the slow
tier's; the default tier checks the same pages and pictures on the Markdown the build reads
(the configuration loaded by mkdocs with its plugins and hooks, in process)."""

import os
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    for module in ("mkdocs", "mkdocstrings", "material"):  # the [docs] extra (also in [test])
        pytest.importorskip(module, reason=f'{module} is not installed (pip install -e ".[docs]")')
    out = tmp_path_factory.mktemp("site")
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1", "PYTHONPATH": str(ROOT)}
    run = subprocess.run(
        [
            sys.executable,
            "-m",
            "mkdocs",
            "build",
            "--strict",
            "-f",
            str(ROOT / "mkdocs.yml"),
            "-d",
            str(out),
        ],
        cwd=ROOT,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-3000:]
    return out


# default tier: tests/test_docs_build.py::test_navigation_pages_exist_and_the_configuration_loads (every page of the navigation, the configuration as mkdocs loads it)
@pytest.mark.slow
def test_strict_build_and_navigation(site):
    """Every section of the navigation is a page of the site."""
    for page in (
        "getting-started",
        "guide/pair",
        "guide/modifications",
        "guide/dynamics",
        "guide/trains",
        "guide/flexible",
        "guide/deviations",
        "guide/rating",
        "guide/planetary",
        "reference/case-file",
        "reference/train-file",
        "reference/body-file",
        "reference/outputs",
        "api/jaxgear",
        "api/jaxgear.scenes",
        "api/jaxgear.dynamics",
        "api/jaxgear.io",
        "api/optimise",
        "api/fem_prep",
        "examples",
        "design",
        "benchmarks",
        "changelog",
        "developers",
    ):
        assert (site / page / "index.html").is_file(), page


IMG = re.compile(r'<img[^>]*\bsrc="([^"]+)"')
#: examples that draw no figure, and where their result is shown instead
NO_FIGURE = {"stiffness_table": "stiffness/"}  # a table of mean mesh stiffnesses


# default tier: tests/test_docs_build.py::test_example_pages_show_their_figures (the generated Markdown of each example's page)
@pytest.mark.slow
def test_every_example_has_a_page_with_its_figure(site):
    """Each script and notebook of examples/ has a page (generated, listed under Examples) that
    shows the figures it draws: a script's PNG files (docs/bench/, docs/img/), a notebook's
    stored outputs; the one example that writes a table links the page that holds it."""
    missing = []
    for path in [*(ROOT / "examples").glob("*.py"), *(ROOT / "examples").glob("*.ipynb")]:
        page = site / "examples" / path.stem / "index.html"
        assert page.is_file(), path.name
        html = page.read_text(encoding="utf-8")
        if path.stem in NO_FIGURE:
            assert f'href="../../{NO_FIGURE[path.stem]}"' in html, path.name
        elif not IMG.search(html):
            missing.append(path.name)
    assert not missing, f"example pages without a figure: {missing}"
    html = (site / "examples" / "pressure_crowning" / "index.html").read_text(encoding="utf-8")
    assert 'src="../../bench/pressure_crowning.png"' in html
    # the notebooks' pages show every figure stored in them (three plots, four plots)
    for stem, n in (("master_curve", 3), ("thin_webbed_gear", 4)):
        html = (site / "examples" / stem / "index.html").read_text(encoding="utf-8")
        assert len(IMG.findall(html)) >= n, stem


# default tier: tests/test_docs_build.py::test_every_picture_a_page_shows_is_a_file (the pictures of the Markdown pages)
@pytest.mark.slow
def test_every_image_of_the_site_exists(site):
    """Every picture a page shows is a file of the site (generated figures included)."""
    broken = []
    for page in site.rglob("*.html"):
        for src in IMG.findall(page.read_text(encoding="utf-8")):
            if src.startswith(("http:", "https:", "data:")):
                continue
            if not (page.parent / src.split("#")[0]).resolve().is_file():
                broken.append(f"{page.relative_to(site)}: {src}")
    assert not broken, broken


# default tier: tests/test_docs_build.py::test_every_picture_a_page_shows_is_a_file (the guide's Markdown shows bench/planetary_campbell.png)
@pytest.mark.slow
def test_planetary_guide_shows_its_campbell_diagram(site):
    """The planetary guide page shows the Campbell diagram that examples/planetary_campbell.py
    draws."""
    html = (site / "guide" / "planetary" / "index.html").read_text(encoding="utf-8")
    assert 'src="../../bench/planetary_campbell.png"' in html
    assert (site / "bench" / "planetary_campbell.png").is_file()


def test_outputs_reference_names_every_file_jaxgear_run_writes():
    """docs/reference/outputs.md explains every file that `jaxgear run` writes (the command's
    own list of its outputs, jaxgear.cli.OUTPUT_FILES, which also decides what a new run
    may delete), in its folder and in sweep/, scene/, optimise/ and deviations/."""
    from jaxgear.cli import OUTPUT_FILES

    text = (ROOT / "docs" / "reference" / "outputs.md").read_text(encoding="utf-8")
    folders = ("sweep", "scene", "optimise", "deviations")
    names = {n.split("/", 1)[1] if n.split("/")[0] in folders else n for n in OUTPUT_FILES["run"]}
    missing = sorted(n for n in names if f"`{n}`" not in text)
    assert not missing, missing
    for folder in folders:
        assert f"`{folder}/`" in text, folder


# default tier: tests/test_docs_build.py::test_generated_markdown_holds_keys_and_names (the Markdown the build renders)
@pytest.mark.slow
def test_generated_pages_hold_keys_and_signatures(site):
    """The case-file reference lists a key with its unit and range (``[pinion] face_width_mm``,
    required, > 0); the API page of jaxgear documents ``quasi_static`` with its signature and
    units from its docstring."""
    ref = (site / "reference/case-file/index.html").read_text(encoding="utf-8")
    assert "face_width_mm" in ref and "youngs_modulus_GPa" in ref and "[0.1, 10000]" in ref
    api = (site / "api/jaxgear/index.html").read_text(encoding="utf-8")
    assert 'id="jaxgear.quasi_static"' in api and "positions_per_pitch" in api
    assert 'id="jaxgear.GearPair"' in api and "N·m" in api
    # the docstrings' Sphinx roles are shown as code, the packages' introductions included
    for page in (site / "api").glob("*/index.html"):
        text = page.read_text(encoding="utf-8")
        assert not re.search(r":(?:class|func|meth|attr|mod|data|exc|obj):", text), page


HISTORY = re.compile(
    r"\bsession \d+\b|\b(?:this|previous|until|one|each|other) sessions?\b|before the move"
    r"|before the fix|\bwe (?:changed|fixed|moved|removed)\b|\bissue \d+|\bthis task\b"
    r"|\ban earlier version\b|\bcommit [0-9a-f]{7}\b|\([0-9a-f]{7,40}\)",
    re.IGNORECASE,
)


def test_user_pages_do_not_tell_development_history():
    """No page of the site speaks of the development sessions or names a commit, but the
    changelog (user-facing changes by version) and the developers' architecture page."""
    found = []
    for page in sorted((ROOT / "docs").rglob("*.md")):
        if page.name in ("changelog.md", "architecture.md") or "_gen" in page.parts:
            continue
        for n, line in enumerate(page.read_text(encoding="utf-8").splitlines(), 1):
            if HISTORY.search(line):
                found.append(f"{page.relative_to(ROOT)}:{n}: {line.strip()}")
    assert not found, "\n".join(found)


def test_validation_page_names_existing_tests():
    """Every test file the validation page cites exists (the page cannot point at a check that
    is gone)."""
    text = (ROOT / "docs" / "validation.md").read_text(encoding="utf-8")
    named = set(re.findall(r"`(tests/test_\w+\.py)`", text))
    assert len(named) >= 15
    missing = sorted(n for n in named if not (ROOT / n).is_file())
    assert not missing, missing


def test_notebook_pages_show_their_stored_outputs(tmp_path):
    """An example notebook's page shows the outputs stored with it, without running it: a
    printed line as a text block, a figure as an image whose PNG bytes the site serves beside
    the page (the bytes written into the notebook, decoded back)."""
    import base64
    import json

    from docs._gen import example_pages

    png = b"\x89PNG\r\n\x1a\n" + bytes(range(40))  # any bytes: the page passes them through
    cells = [
        {"cell_type": "markdown", "metadata": {}, "source": ["# A demo\n", "Text."]},
        {
            "cell_type": "code",
            "metadata": {},
            "execution_count": 1,
            "source": ["print('TE rms 0.42 µm')\n", "plot()"],
            "outputs": [
                {"output_type": "stream", "name": "stdout", "text": ["TE rms 0.42 µm\n"]},
                {
                    "output_type": "display_data",
                    "metadata": {},
                    "data": {"image/png": base64.b64encode(png).decode(), "text/plain": ["<Fig>"]},
                },
            ],
        },
        {"cell_type": "code", "metadata": {}, "execution_count": None, "source": ["x = 1"]},
    ]
    path = tmp_path / "demo.ipynb"
    nb = {"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}
    path.write_text(json.dumps(nb), encoding="utf-8")
    title, text, figures = example_pages.notebook(path)
    assert title == "A demo"
    assert "```text\nTE rms 0.42 µm\n```" in text
    assert "![output 1](demo-1.png)" in text and "<Fig>" not in text
    assert figures == {"examples/demo-1.png": png}
    assert example_pages.notebook_page(path) == (title, text)


def _nav_paths(nav) -> list[str]:
    """The Markdown paths of a navigation (nested sections flattened)."""
    if isinstance(nav, str):
        return [nav]
    if isinstance(nav, dict):
        return [p for v in nav.values() for p in _nav_paths(v)]
    return [p for item in nav for p in _nav_paths(item)]


@pytest.fixture(scope="module")
def markdown():
    """The site's pages as the build reads them, without building it: the configuration
    loaded and validated by mkdocs (its theme, plugins and hooks imported; the hooks' Examples
    section in the navigation), the Markdown files of docs/ and the generated pages (the API
    pages, a page per example) with the notebooks' stored figures."""
    for module in ("mkdocs", "mkdocstrings", "material"):  # the [docs] extra (also in [test])
        pytest.importorskip(module, reason=f'{module} is not installed (pip install -e ".[docs]")')
    from mkdocs.config import load_config

    from docs._gen import api_pages, example_pages

    config = load_config(str(ROOT / "mkdocs.yml"))
    config = config.plugins.on_config(config)
    pages = {
        str(p.relative_to(ROOT / "docs")): p.read_text(encoding="utf-8")
        for p in (ROOT / "docs").rglob("*.md")
        if "_gen" not in p.parts and p.parent.name != "bench"  # exclude_docs
    }
    pages.update(api_pages.pages())
    pages.update({path: text for path, (_, text) in example_pages.pages().items()})
    return config, pages, set(example_pages.figures())


def test_navigation_pages_exist_and_the_configuration_loads(markdown):
    """Every page of the navigation is a page of the site (a file of docs/ or a generated
    page), the sections the strict build's test checks included."""
    config, pages, _ = markdown
    assert config["strict"] and config["docs_dir"] == str(ROOT / "docs")
    nav = _nav_paths(config["nav"])
    missing = [p for p in nav if p not in pages]
    assert not missing, missing
    for page in (
        "getting-started", "guide/pair", "guide/modifications", "guide/dynamics",
        "guide/trains", "guide/flexible", "guide/deviations", "guide/rating", "guide/planetary",
        "reference/case-file", "reference/train-file", "reference/body-file",
        "reference/outputs", "api/jaxgear", "api/jaxgear.scenes", "api/jaxgear.dynamics",
        "api/jaxgear.io", "api/optimise", "api/fem_prep", "examples", "design", "benchmarks",
        "changelog", "developers",
    ):  # fmt: skip
        assert f"{page}.md" in nav, page
    # the hooks listed a page per example under Examples
    for path in [*(ROOT / "examples").glob("*.py"), *(ROOT / "examples").glob("*.ipynb")]:
        assert f"examples/{path.stem}.md" in nav, path.name


MD_IMG = re.compile(r"!\[[^\]]*\]\(([^)\s]+)[^)]*\)|<img[^>]*\bsrc=\"([^\"]+)\"")


def test_example_pages_show_their_figures(markdown):
    """Each script and notebook of examples/ has a generated page that shows a figure (the
    one example that writes a table links the page that holds it); the notebooks' pages show
    every figure stored in them."""
    _, pages, _ = markdown
    missing = []
    for path in [*(ROOT / "examples").glob("*.py"), *(ROOT / "examples").glob("*.ipynb")]:
        text = pages[f"examples/{path.stem}.md"]
        if path.stem in NO_FIGURE:
            assert f"../{NO_FIGURE[path.stem].rstrip('/')}.md" in text, path.name
        elif not MD_IMG.search(text):
            missing.append(path.name)
    assert not missing, f"example pages without a figure: {missing}"
    assert "../bench/pressure_crowning.png" in pages["examples/pressure_crowning.md"]
    for stem, n in (("master_curve", 3), ("thin_webbed_gear", 4)):
        assert len(MD_IMG.findall(pages[f"examples/{stem}.md"])) >= n, stem


def test_every_picture_a_page_shows_is_a_file(markdown):
    """Every picture a Markdown page shows is a file of docs/ or a figure the hooks generate;
    the planetary guide shows the Campbell diagram examples/planetary_campbell.py draws."""
    _, pages, figures = markdown
    broken = []
    for path, text in pages.items():
        for groups in MD_IMG.findall(text):
            src = (groups[0] or groups[1]).split("#")[0]
            if src.startswith(("http:", "https:", "data:")):
                continue
            target = (pathlib.PurePosixPath(path).parent / src).as_posix()
            parts = []
            for part in target.split("/"):
                if part == "..":
                    parts.pop() if parts else broken.append(f"{path}: {src}")
                elif part not in ("", "."):
                    parts.append(part)
            target = "/".join(parts)
            if not ((ROOT / "docs" / target).is_file() or target in figures):
                broken.append(f"{path}: {src}")
    assert not broken, broken
    assert "../bench/planetary_campbell.png" in pages["guide/planetary.md"]


def test_generated_markdown_holds_keys_and_names(markdown):
    """The case-file reference lists a key with its unit and range; the API page of jaxgear
    documents ``quasi_static`` and ``GearPair``; the griffe extension the configuration names
    shows the docstrings' Sphinx roles as code."""
    config, pages, _ = markdown
    ref = pages["reference/case-file.md"]
    assert "face_width_mm" in ref and "youngs_modulus_GPa" in ref and "[0.1, 10000]" in ref
    api = pages["api/jaxgear.md"]
    assert "::: jaxgear.quasi_static\n" in api and "::: jaxgear.GearPair\n" in api
    handler = config["plugins"]["mkdocstrings"].config["handlers"]["python"]
    assert "docs/_gen/griffe_roles.py:SphinxRoles" in handler["options"]["extensions"]
    from docs._gen.griffe_roles import plain

    text = "see :class:`~jaxgear.Weber`, :func:`jaxgear.quasi_static` and :attr:`x`"
    assert plain(text) == "see `Weber`, `jaxgear.quasi_static` and `x`"
