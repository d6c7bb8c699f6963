"""mkdocs hooks: the API pages, one entry per public name (:mod:`docs._gen.api_pages`), and a
page per example (:mod:`docs._gen.example_pages`), listed under Examples in the navigation.

The case-file and body-file references (``docs/reference/case-file.md``, ``train-file.md``,
``gearbox-file.md``, ``body-file.md``) are generated from the validators by
:mod:`docs._gen.schema_reference` and committed, so that the pages' links to them work in the
repository as well as on the site; ``tests/test_docs_reference.py`` fails when they differ from
what the validators declare (``python -m docs._gen.schema_reference docs/reference`` writes them
again)."""

from __future__ import annotations

import pathlib
import sys

from mkdocs.structure.files import File

ROOT = pathlib.Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

from docs._gen import api_pages, example_pages  # noqa: E402


def on_config(config):
    """The Examples section of the navigation: the overview, then a page per example."""
    pages = [{pathlib.Path(path).stem: path} for path in example_pages.pages()]
    for i, item in enumerate(config["nav"]):
        if isinstance(item, dict) and "Examples" in item:
            config["nav"][i] = {"Examples": ["examples.md", *pages]}
    return config


def on_files(files, config):
    for path, text in api_pages.pages().items():
        files.append(File.generated(config, path, content=text))
    for path, (_, text) in example_pages.pages().items():
        files.append(File.generated(config, path, content=text))
    for path, png in example_pages.figures().items():  # the notebooks' stored figures
        files.append(File.generated(config, path, content=png))
    return files
