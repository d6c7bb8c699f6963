"""Package layout: imports flow one way (model ← optimise ← application), the public API is small.

Checks: importing the model and ``optimise`` in a fresh interpreter loads none of the
application modules (CLI, plots, benchmarks, file writers) nor matplotlib; and a static scan of
the source shows no import of another package's private module and no argparse/matplotlib in the
model and ``optimise``. The benchmarks live outside the installed packages, in ``benchmarks/``
of the checkout: only the ``jaxgear bench`` command looks for them, and no installed module
reads ``tests/``. The tests use the public API too, but for a short, commented list.
"""

from __future__ import annotations

import ast
import fnmatch
import functools
import pathlib
import re
import subprocess
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
APP = ("jaxgear.cli", "jaxgear.io", "benchmarks", "matplotlib")
MODEL_SUBPACKAGES = (
    "jaxgear.scenes",
    "jaxgear.dynamics",
    "jaxgear.planetary",
    "jaxgear.rating",
    "jaxgear.gearbox",
    "jaxgear.tribology",
    "jaxgear.acoustics",
    "jaxgear.io",
    "jaxgear.sizing",
    "jaxgear.bearings",
)
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


# the modules one import loads are among those its union with others loads: the union (one
# interpreter) in the default tier, each statement alone (an interpreter each) in the slow tier
@pytest.mark.parametrize(
    "statement",
    [
        "import jaxgear, jaxgear.scenes, jaxgear.dynamics, optimise",
        # default tier: tests/test_layout.py::test_model_and_optimise_load_no_application_module[import jaxgear, jaxgear.scenes, jaxgear.dynamics, optimise] (the union of these imports)
        pytest.param("import jaxgear", marks=pytest.mark.slow),
        pytest.param("import jaxgear.scenes, jaxgear.dynamics", marks=pytest.mark.slow),
        pytest.param("import optimise", marks=pytest.mark.slow),
    ],
)
def test_model_and_optimise_load_no_application_module(statement):
    loaded = _modules_after(statement)
    bad = sorted(m for m in loaded if m.split(".")[0] == "matplotlib" or m.startswith(APP[:3]))
    assert not bad, f"{statement!r} loads application modules: {bad}"


def test_fem_prep_never_imports_jax():
    loaded = _modules_after("import fem_prep")
    assert not any(m == "jax" or m.startswith(("jax.", "jaxgear")) for m in loaded)


@functools.cache
def _tree(path: pathlib.Path) -> ast.Module:
    """The parsed source of ``path``, parsed once for the module's tests (they only read it)."""
    return ast.parse(path.read_text(encoding="utf-8"))


def _imports(path: pathlib.Path):
    tree = _tree(path)
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


#: fem_prep's subpackages (one concept spanning several modules); like the model subpackages
#: they may import the private modules of the fem_prep root
FEM_PREP_SUBPACKAGES = ("fem_prep.housing", "fem_prep.acoustics")


def _package_of(module: str) -> str:
    """The package a dotted name lives in: jaxgear.dynamics, jaxgear, optimise, fem_prep,
    fem_prep.housing, …"""
    parts = module.split(".")
    keep = [p for p in parts if not p.startswith("_")]
    if ".".join(keep[:2]) in FEM_PREP_SUBPACKAGES:
        return ".".join(keep[:2])
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
                    continue  # the optimiser's progress bar
                bad.append(f"{path.relative_to(ROOT)}: {mod}")
    assert not bad, bad


def test_no_import_of_another_packages_private_module():
    """``from jaxgear.dynamics._simulate import x`` inside benchmarks is a private reach-in: a
    module may import private modules of its own package only; the model's subpackages (scenes,
    dynamics, io) may also use the model's private modules; the application (cli, benchmarks)
    uses public names only (the tests too: :func:`test_tests_use_public_names_only`)."""
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
            if target != own and not (
                (target == "jaxgear" and own in MODEL_SUBPACKAGES)
                or (target == "fem_prep" and own in FEM_PREP_SUBPACKAGES)
            ):
                bad.append(f"{path.relative_to(ROOT)}: {mod}")
    assert not bad, bad


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """The strongly connected components with more than one module (Tarjan): the import
    cycles of the graph ``edges`` (module → modules it imports)."""
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    out = []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        for w in edges.get(v, ()):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(edges):
        if v not in index:
            visit(v)
    return out


def test_no_import_cycle():
    """No cycle among the modules of the installed packages and the benchmarks, counting every
    import (at module top or inside a function): the model, ``optimise``, ``fem_prep`` and the
    application can each be read from the bottom up."""
    modules = {}
    for path in _sources("jaxgear", "optimise", "fem_prep", "benchmarks"):
        parts = path.relative_to(ROOT).with_suffix("").parts
        modules[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path

    def known(name):
        while name and name not in modules:
            name = name.rpartition(".")[0]
        return name

    edges = {}
    for name, path in modules.items():
        # a package's relative imports start from the package itself
        pkg = (name if path.name == "__init__.py" else name.rpartition(".")[0]).split(".")
        imports = []
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.Import):
                imports += [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = pkg[: len(pkg) - node.level + 1] if node.level else []
                mod = ".".join(base + ([node.module] if node.module else []))
                # ``from pkg import submodule`` imports the submodule, not all of pkg
                imports += [
                    f"{mod}.{a.name}" if f"{mod}.{a.name}" in modules else mod for a in node.names
                ]
        edges[name] = {m for m in map(known, imports) if m and m != name}
    assert _cycles({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]
    assert not _cycles(edges), _cycles(edges)


def test_public_api_is_the_model():
    import jaxgear as jg

    names = {n for n in dir(jg) if not n.startswith("_")}
    for app in ("run_case", "atomic_open", "load_case", "main", "bench_quasi_static"):
        assert app not in names, f"jaxgear.{app} belongs to the application, not the model API"
    for model in ("quasi_static", "GearPair", "MeshModel", "Modifications", "ContactResult"):
        assert model in names


INSTALLED = ("jaxgear", "fem_prep", "optimise")
LOCATOR = ROOT / "jaxgear" / "cli" / "bench.py"  # ``jaxgear bench`` finds benchmarks/ of a checkout


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


# -- tests use the public API ---------------------------------------------------------------------

PROJECT = ("jaxgear", "fem_prep", "optimise", "benchmarks")
# The private names tests still reach, as (test file, dotted name or the private module it is
# reached through): each a white-box check with no public way to the same assertion.
PRIVATE_IN_TESTS: set[tuple[str, str]] = {
    # the bearings' summary section, rating.md lines and tone lines from a case without a whole
    # jaxgear run each (the whole run is the file's slow test); the tone lines as drawn on
    # captured Campbell and waterfall figures; the rating's speed_rpm read as the pinion speed
    ("test_bearing_report.py", "jaxgear.cli._bearing_report"),
    ("test_bearing_report.py", "jaxgear.cli._plots._campbell"),
    ("test_bearing_report.py", "jaxgear.cli._plots._whine"),
    ("test_bearing_report.py", "jaxgear.io._bearings_table.pinion_speed"),
    # a train's bearings' summary section and tone orders from a case without a whole jaxgear
    # run (the whole run is the file's slow test)
    ("test_bearing_train.py", "jaxgear.cli._bearing_report"),
    # a gearbox's bearings' summary section, console lines and tone orders of its input speed
    # from the loaded gearbox and its stage's section without a whole jaxgear run (the whole
    # run is the file's slow test); the tones as drawn on a captured coupled Campbell diagram
    ("test_gearbox_bearings.py", "jaxgear.cli._bearing_report"),
    ("test_gearbox_bearings.py", "jaxgear.cli._plots._gearbox"),
    # the TE stage's own optimiser start, so that the batch is compared where the stage runs it
    ("test_sizing_te.py", "jaxgear.sizing._te._start"),
    # a case's lumped 3D pair built on a synthetic housing (K, M written in the test), which a
    # case file cannot hold: the housed scene's bearing block at the operating point
    ("test_bearing_scenes.py", "jaxgear.io._case_model._lumped3d_pair"),
    # the first operating-point solve's start springs of a shaft on one tapered roller pair: a
    # singular start is factored with a pivot of rounding noise (a CPU-dependent failure, no
    # public result shows it), so the test checks the springs' stiffness is regular
    ("test_bearing_scenes.py", "jaxgear.dynamics._bearings._start_springs"),
    ("test_bearing_scenes.py", "jaxgear.dynamics._bearings.START_SPRING"),
    # the same builder as the independent reference of a bearing's stiffness change: the pair
    # assembled again in NumPy on a changed bearing (on the ground and on a synthetic housing)
    ("test_optimise_bearings.py", "jaxgear.io._case_model._lumped3d_pair"),
    # safe_max's fallback shown at its smallest: the jax.numpy its module computes with patched
    # so that no element equals the maximum (what XLA's -O0 kernels do in the slow test)
    ("test_optimise_robust.py", "jaxgear._util"),
    # jaxgear run's sweep section with the sweep stubbed: the speeds it hands the sweep and the
    # dynamics section it writes on a housed case, without a whole run (minutes a case)
    ("test_housed_first_look.py", "jaxgear.cli.run._sweep_section"),
    # jaxgear optimise's and master-curve's work stubbed: their output checks shown to pass
    # with --force (the work reached) without an optimisation
    ("test_output_paths.py", "jaxgear.cli._optimise"),
    # the housing's estimates before work: the mesher's, the condensation's and the eigen
    # solve's modules patched with functions that fail if reached (the refusal comes first),
    # the mode limit lowered, the FE DOF count and a case's laid-out box read to compare the
    # estimates with what is built
    ("test_housing_estimate.py", "fem_prep.housing._condense"),
    ("test_housing_estimate.py", "fem_prep.housing._estimate"),
    ("test_housing_estimate.py", "fem_prep.housing._mesh"),
    ("test_housing_estimate.py", "jaxgear.io._housing_table._box"),
    ("test_housing_estimate.py", "jaxgear.io._housing_table._mesh_size"),
    # the whine's size check shown to come before its static solves (a function patched that
    # fails if reached)
    ("test_whine_size.py", "jaxgear.dynamics._whine"),
    # the mesh-frequency groups read from a case file's teeth at load against those the
    # quasi-periodic balance finds on the model
    ("test_whine_quasi_periodic.py", "jaxgear.dynamics._whine_qp.mesh_groups"),
    ("test_whine_quasi_periodic.py", "jaxgear.io._case_model.mesh_frequency_periods"),
    # the printed tribology and efficiency lines from summary sections, without a lubricated
    # run of each kind (a train, a planetary stage: minutes each)
    ("test_rating_report_rows.py", "jaxgear.cli._tribology_run"),
    # the ISO stiffness reference and the printed line jaxgear run writes of it, from one
    # quasi-static result (a whole run of the NREL stage: minutes)
    ("test_iso6336.py", "jaxgear.cli._summary"),
    # the planetary sweep's step-resolution refusal on a time plan (the check jaxgear sweep
    # makes before integrating), without a second sweep of the stage
    ("test_planetary_step_resolution.py", "jaxgear.cli._planetary_steps.resolution_checked"),
    # each typed table's section declaration, mutated by the hypothesis tests and its words
    # read against the file reader's
    ("test_typed_sections.py", "jaxgear.io._case_file"),
    ("test_typed_sections.py", "jaxgear.io._micropitting_table"),
    ("test_typed_sections.py", "jaxgear.io._modifications_table"),
    ("test_typed_sections.py", "jaxgear.io._optimise_table"),
    ("test_typed_sections.py", "jaxgear.io._pareto_table"),
    ("test_typed_sections.py", "jaxgear.io._robust_table"),
    ("test_typed_sections.py", "jaxgear.io._scene_table"),
    ("test_typed_sections.py", "jaxgear.io._spectrum_table"),
    ("test_typed_sections.py", "jaxgear.io._train_file"),
    ("test_typed_sections.py", "jaxgear.io._train_scene"),
    ("test_typed_sections.py", "jaxgear.io._gearbox_file"),
    ("test_typed_sections.py", "jaxgear.io._housing_table"),
    ("test_typed_sections.py", "jaxgear.io._planetary_table"),
    ("test_typed_sections.py", "jaxgear.io._planetary_deviations_table"),
    # a mutated file's dict read as load_case reads the file (a gearbox file's dict: no public
    # reader takes one, and the mutants' values need not survive a TOML writer)
    ("test_typed_stage_tables.py", "jaxgear.io._load"),
    # the keys that take a value per gear (a number there is a valid value, not a table)
    ("test_table_types.py", "jaxgear.io._rating_table.PER_GEAR"),
    # the modal basis itself (its statics, without the Newmark program a public run compiles)
    ("test_hybrid_modal_basis.py", "jaxgear.dynamics._modal_basis.modal_space_of"),
}


def _private(dotted: str) -> bool:
    parts = dotted.split(".")
    return parts[0] in PROJECT and any(p.startswith("_") and not p.startswith("__") for p in parts)


def _private_names(tree: ast.AST):
    """Dotted private names of the project a test module reaches: imports (also in code strings
    run by a subprocess or ``-c``), attributes of the modules it imported, ``setattr`` targets."""
    bound: dict[str, str] = {}  # local name -> dotted name of the project
    docstrings = {
        id(n.value)
        for n in ast.walk(tree)
        if isinstance(n, ast.Expr) and isinstance(n.value, ast.Constant)
    }
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] in PROJECT:
                    bound[a.asname or a.name.split(".")[0]] = (
                        a.name if a.asname else a.name.split(".")[0]
                    )
                    yield a.name
        elif isinstance(node, ast.ImportFrom) and not node.level and node.module:
            if node.module.split(".")[0] in PROJECT:
                for a in node.names:
                    bound[a.asname or a.name] = f"{node.module}.{a.name}"
                    yield f"{node.module}.{a.name}"
        elif (
            isinstance(node, ast.Constant)
            and isinstance(node.value, str)
            and id(node) not in docstrings
            and "import" in node.value
        ):
            try:
                code = ast.parse(node.value)
            except SyntaxError:
                continue
            yield from _private_names(code)
        elif isinstance(node, ast.Call) and node.args:
            f, first = node.func, node.args[0]
            name = f.attr if isinstance(f, ast.Attribute) else getattr(f, "id", "")
            if (
                name == "setattr"
                and isinstance(first, ast.Constant)
                and isinstance(first.value, str)
            ):
                yield first.value
    for node in ast.walk(tree):
        if isinstance(node, ast.Attribute) and node.attr.startswith("_"):
            chain, base = [node.attr], node.value
            while isinstance(base, ast.Attribute):
                chain.append(base.attr)
                base = base.value
            if isinstance(base, ast.Name) and base.id in bound:
                yield ".".join([bound[base.id], *reversed(chain)])


def test_tests_use_public_names_only():
    """No test reaches a private module or name of the project (``jaxgear._stiffness``,
    ``from jaxgear.cli.run import x``, ``fem_prep._tooth_fe._compute``) but those listed in
    PRIVATE_IN_TESTS, each with its reason; an entry no test needs any more is an error too."""
    found = set()
    for path in sorted((ROOT / "tests").glob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        found |= {(path.name, d) for d in _private_names(tree) if _private(d)}

    def covers(entry, hit):
        return hit[0] == entry[0] and (hit[1] == entry[1] or hit[1].startswith(entry[1] + "."))

    bad = sorted(h for h in found if not any(covers(e, h) for e in PRIVATE_IN_TESTS))
    assert not bad, f"tests reach private names (use the public API): {bad}"
    unused = sorted(e for e in PRIVATE_IN_TESTS if not any(covers(e, h) for h in found))
    assert not unused, f"PRIVATE_IN_TESTS entries no test needs: {unused}"


def test_source_cites_no_issue_numbers():
    """The repository stands alone: no source, test, benchmark or example file refers to the
    tracker's numbering (the word issue and a number), which means nothing to a reader of the code; it
    says what a check is for instead. (The changelog, development history, may.)"""
    pattern = re.compile(r"\bissues? ?#?\d+", re.IGNORECASE)
    found = []
    for folder in ("jaxgear", "fem_prep", "optimise", "tests", "benchmarks", "examples"):
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix not in {".py", ".toml", ".md", ".ipynb"} or not path.is_file():
                continue
            for i, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if pattern.search(line):
                    found.append(f"{path.relative_to(ROOT)}:{i}")
    assert not found, found
