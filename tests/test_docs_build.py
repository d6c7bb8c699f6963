"""The documentation site builds with warnings as errors (``mkdocs build --strict``: broken
links, missing pages, unresolved API names and docstrings griffe cannot parse fail), and the
generated pages hold what they are generated from: the case-file reference the validator's keys,
the API pages the public names with their signatures. About 6 s."""

import os
import pathlib
import subprocess
import sys

import pytest

pytest.importorskip(
    "mkdocs", reason='the docs packages are not installed (pip install -e ".[docs]")'
)
pytest.importorskip(
    "mkdocstrings", reason='mkdocstrings is not installed (pip install -e ".[docs]")'
)
pytest.importorskip(
    "material", reason='mkdocs-material is not installed (pip install -e ".[docs]")'
)

ROOT = pathlib.Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
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
        "reference/case-file",
        "reference/train-file",
        "reference/body-file",
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


def test_generated_pages_hold_keys_and_signatures(site):
    """The case-file reference lists a key with its unit and range (``[pinion] face_width_mm``,
    required, > 0); the API page of jaxgear documents ``quasi_static`` with its signature and
    units from its docstring."""
    ref = (site / "reference/case-file/index.html").read_text(encoding="utf-8")
    assert "face_width_mm" in ref and "youngs_modulus_GPa" in ref and "[0.1, 10000]" in ref
    api = (site / "api/jaxgear/index.html").read_text(encoding="utf-8")
    assert 'id="jaxgear.quasi_static"' in api and "positions_per_pitch" in api
    assert 'id="jaxgear.GearPair"' in api and "N·m" in api
