"""Package layout: imports flow one way (model ← optimise ← application), the public API is small.

Two checks: importing the model and ``optimise`` in a fresh interpreter loads none of the
application modules (CLI, plots, benchmarks, file writers) nor matplotlib; and a static scan of
the source shows no import of another package's private module and no argparse/matplotlib in the
model and ``optimise``. The benchmarks live outside the installed packages, in ``benchmarks/``
of the checkout: only the ``jaxgear bench`` command looks for them, and no installed module
reads ``tests/``.
"""

from __future__ import annotations

import ast
import fnmatch
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
APP = ("jaxgear.cli", "jaxgear.io", "benchmarks", "matplotlib")
MODEL_SUBPACKAGES = ("jaxgear.scenes", "jaxgear.dynamics", "jaxgear.io")
FORBIDDEN_IN_MODEL = (
    "argparse",
    "matplotlib",
    "jaxgear.cli",
    "benchmarks",
    "jaxgear.io",
    "tqdm",
)


def _modules_after(statement: str) -> set[str]:
    code = f"import sys\n{statement}\nprint('\\n'.join(sorted(sys.modules)))"
    out = subprocess.run(
        [sys.executable, "-c", code],
        capture_output=True,
        text=True,
        cwd=ROOT,
        timeout=300,
        check=True,
    ).stdout
    return set(out.split())


@pytest.mark.parametrize(
    "statement",
    [
        "import jaxgear",
        "import jaxgear.scenes, jaxgear.dynamics",
        "import optimise",
    ],
)
def test_model_and_optimise_load_no_application_module(statement):
    loaded = _modules_after(statement)
    bad = sorted(m for m in loaded if m.split(".")[0] == "matplotlib" or m.startswith(APP[:3]))
    assert not bad, f"{statement!r} loads application modules: {bad}"


def test_fem_prep_never_imports_jax():
    loaded = _modules_after("import fem_prep")
    assert not any(m == "jax" or m.startswith(("jax.", "jaxgear")) for m in loaded)


def _imports(path: pathlib.Path):
    tree = ast.parse(path.read_text(encoding="utf-8"))
    pkg = ".".join(path.relative_to(ROOT).with_suffix("").parts[:-1])
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                yield a.name
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = pkg.split(".")
                base = base[: len(base) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            yield mod
            for a in node.names:
                yield f"{mod}.{a.name}"


def _package_of(module: str) -> str:
    """The package a dotted name lives in: jaxgear.dynamics, jaxgear, optimise, fem_prep, …"""
    parts = module.split(".")
    keep = [p for p in parts if not p.startswith("_")]
    return ".".join(keep[:2]) if keep[:1] == ["jaxgear"] and len(keep) > 1 else keep[0]


def _sources(*packages):
    for p in packages:
        yield from sorted((ROOT / p).rglob("*.py"))


def test_model_and_optimise_source_import_no_application_module():
    model = [
        p
        for p in _sources("jaxgear", "optimise")
        if p.relative_to(ROOT).parts[1] not in ("cli", "io")
    ]
    bad = []
    for path in model:
        for mod in _imports(path):
            if any(mod == f or mod.startswith(f + ".") for f in FORBIDDEN_IN_MODEL):
                if mod.startswith("tqdm") and "optimise" in path.parts:
                    continue  # progress bars, imported on use (no argparse at import time)
                bad.append(f"{path.relative_to(ROOT)}: {mod}")
    assert not bad, bad


def test_no_import_of_another_packages_private_module():
    """``from jaxgear.dynamics._simulate import x`` inside benchmarks is a private reach-in: a
    module may import private modules of its own package only; the model's subpackages (scenes,
    dynamics, io) may also use the model's private modules; the application (cli, benchmarks)
    uses public names only (tests may reach in)."""
    bad = []
    for path in _sources("jaxgear", "optimise", "fem_prep", "examples", "benchmarks"):
        own = _package_of(".".join(path.relative_to(ROOT).with_suffix("").parts))
        for mod in _imports(path):
            parts = mod.split(".")
            if parts[0] not in ("jaxgear", "optimise", "fem_prep"):
                continue
            private = [i for i, p in enumerate(parts[:-1]) if p.startswith("_")]
            if not private:
                continue
            target = ".".join(parts[: private[0]])
            if target != own and not (target == "jaxgear" and own in MODEL_SUBPACKAGES):
                bad.append(f"{path.relative_to(ROOT)}: {mod}")
    assert not bad, bad


def test_public_api_is_the_model():
    import jaxgear as jg

    names = {n for n in dir(jg) if not n.startswith("_")}
    for app in ("run_case", "atomic_open", "load_case", "main", "bench_quasi_static"):
        assert app not in names, f"jaxgear.{app} belongs to the application, not the model API"
    for model in ("quasi_static", "GearPair", "MeshModel", "Modifications", "ContactResult"):
        assert model in names


INSTALLED = ("jaxgear", "fem_prep", "optimise")
LOCATOR = ROOT / "jaxgear" / "cli" / "_main.py"  # ``jaxgear bench`` finds benchmarks/ of a checkout


def test_benchmarks_live_outside_the_installed_packages():
    import tomllib

    assert (ROOT / "benchmarks" / "__init__.py").is_file()
    assert not list((ROOT / "jaxgear" / "bench").glob("*.py"))  # a stale __pycache__ may stay
    find = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    include = find["tool"]["setuptools"]["packages"]["find"]["include"]
    assert all(any(fnmatch.fnmatch(p, pat) for pat in include) for p in INSTALLED)
    assert not any(fnmatch.fnmatch("benchmarks", pat) for pat in include), include


def test_installed_modules_neither_name_benchmarks_nor_read_tests():
    """The benchmarks and the test data belong to the checkout: no installed module names the
    ``benchmarks`` folder (but the ``jaxgear bench`` locator) or reads a path under ``tests/``."""
    names_benchmarks = re.compile(r"\bbenchmarks\b")
    reads_tests = re.compile(r"""tests/|["']tests["']""")
    bad = []
    for path in _sources(*INSTALLED):
        text = path.read_text(encoding="utf-8")
        if path != LOCATOR and names_benchmarks.search(text):
            bad.append(f"{path.relative_to(ROOT)}: benchmarks")
        if reads_tests.search(text):
            bad.append(f"{path.relative_to(ROOT)}: tests/")
    assert not bad, bad
