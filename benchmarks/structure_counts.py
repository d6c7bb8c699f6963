"""Structure counts of the source tree: how often the code asks "which kind?".

Run from a source checkout::

    python benchmarks/structure_counts.py            # table per package
    python benchmarks/structure_counts.py --json     # the same as JSON
    python benchmarks/structure_counts.py --write docs/bench/structure_counts_NAME
                                                     # NAME.json and NAME.md (a table)

What is counted (by reading the syntax tree, so comments and strings are never counted):

``kind_branches``
    Branches that choose behaviour by the kind of an object or a name:

    - ``string_switch``: an ``if``/``elif``/conditional expression/``match`` whose test compares a
      value with a string constant (``==``, ``!=``, ``in``/``not in`` a literal of strings), or a
      ``match`` with string patterns;
    - ``isinstance_branch``: an ``if``/``elif``/conditional expression whose test calls
      ``isinstance`` (or ``type(x) is``), unless the branch only raises (an input check);
    - ``getattr_default``: ``getattr(x, "name", default)``, duck typing on an attribute.

    String switches whose body only raises are input checks and are not counted either.

``many_parameters``
    Functions and methods with 10 or more parameters (``self``/``cls`` not counted,
    ``*args``/``**kwargs`` counted once each).

``imports_in_functions``
    ``import`` statements inside a function body, against all ``import`` statements.

``long_modules``
    Modules over 700 lines.

``probes``
    ``hasattr(x, "name")`` calls and ``getattr(x, "name", default)`` (the latter also in
    ``getattr_default``): code that finds out what an object supports by asking it, where a
    kind would declare it. Reported per package; ``model_probes`` sums the model's packages
    (jaxgear without ``cli`` and ``io``).

``type_branches``
    The ``isinstance_branch`` places whose tested type is a class of the project (a model, a
    scene, a case form, a result: a name defined by a ``class`` statement in the packages
    counted), not a built-in or a NumPy type: the code choosing what to do by the kind of a
    project object. Reported per package; the edge's (``jaxgear/cli``, ``jaxgear/io``) apart.

``flag_branches``
    Branches (``if``, conditional expression, comprehension filter) whose test reads the
    extended-contact flag (a name or attribute ``extended_contact``, ``extended`` or a call of
    ``_extended``), input checks that only raise left out.

``lines``, ``modules``
    Lines and modules per package; the edge's share is the lines of ``jaxgear/cli`` and
    ``jaxgear/io`` over the lines of ``jaxgear``.

``public_names``
    Per package (a folder with an ``__init__.py``): the names its ``__init__`` binds that do
    not start with ``_`` (its ``__all__`` where it has one), submodules and the standard
    library's names left out; ``deprecated`` the names a ``_MOVED_TO`` table still serves
    with a warning.

Nothing here is a ceiling: the figures are a report to read before and after a change, and
no test holds them (a ceiling makes code be rewritten to pass a counter).

The edge packages (``jaxgear/io``, ``fem_prep/schema.py`` with its typed sections,
``fem_prep/sections.py``, and the file-text checks it shares with ``jaxgear/io``,
``fem_prep/checks.py``) map names in files to objects by
design; their string switches are listed separately (``edge``) and left out of the total the
targets speak of (model code and CLI together).
"""

from __future__ import annotations

import argparse
import ast
import json
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
PACKAGES = ("jaxgear", "optimise", "fem_prep")
EDGE = ("jaxgear/io/", "fem_prep/schema.py", "fem_prep/checks.py", "fem_prep/sections.py")
LONG_MODULE = 700
MANY_PARAMETERS = 10
#: the edge of the model package (its subpackages): names in files and on the command line,
#: mapped to objects and presented
EDGE_PACKAGES = ("cli", "io")
#: the extended-contact flag, as the code spells it
FLAG_NAMES = ("extended_contact", "extended", "_extended")


def _only_raises(body: list[ast.stmt]) -> bool:
    return len(body) == 1 and isinstance(body[0], ast.Raise)


def _is_string_literal(node: ast.AST) -> bool:
    if isinstance(node, ast.Constant):
        return isinstance(node.value, str)
    if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
        return bool(node.elts) and all(_is_string_literal(e) for e in node.elts)
    return False


def _compares_string(test: ast.AST) -> bool:
    for node in ast.walk(test):
        if isinstance(node, ast.Compare):
            ops_ok = all(isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops)
            sides = [node.left, *node.comparators]
            if isinstance(node.left, ast.Name) and node.left.id == "__name__":
                continue  # the script guard, not a branch on a kind
            if ops_ok and any(_is_string_literal(s) for s in sides):
                return True
    return False


def _checks_type(test: ast.AST) -> bool:
    for node in ast.walk(test):
        if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
            if node.func.id in ("isinstance", "issubclass"):
                return True
        if isinstance(node, ast.Compare) and any(
            isinstance(op, (ast.Is, ast.IsNot)) for op in node.ops
        ):
            left = node.left
            if (
                isinstance(left, ast.Call)
                and isinstance(left.func, ast.Name)
                and left.func.id == "type"
            ):
                return True
    return False


def _identifier(node: ast.AST) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def _tested_types(test: ast.AST) -> set[str]:
    """The class names ``isinstance``/``issubclass``/``type(x) is`` test against in ``test``."""
    out: set[str] = set()

    def names(node):
        if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
            for e in node.elts:
                names(e)
        elif isinstance(node, ast.BinOp):  # A | B
            names(node.left)
            names(node.right)
        elif (n := _identifier(node)) is not None:
            out.add(n)

    for node in ast.walk(test):
        if (
            isinstance(node, ast.Call)
            and isinstance(node.func, ast.Name)
            and node.func.id in ("isinstance", "issubclass")
            and len(node.args) == 2
        ):
            names(node.args[1])
        if isinstance(node, ast.Compare) and any(
            isinstance(op, (ast.Is, ast.IsNot)) for op in node.ops
        ):
            for side in node.comparators:
                names(side)
    return out


def _reads_flag(test: ast.AST) -> bool:
    for node in ast.walk(test):
        if isinstance(node, ast.Call):
            continue  # the call's name is read below as its func
        if _identifier(node) in FLAG_NAMES:
            return True
    return False


class _Counter(ast.NodeVisitor):
    def __init__(self, path: str, project_classes: frozenset[str] = frozenset()):
        self.path = path
        self.project_classes = project_classes
        self.rows: dict[str, list[str]] = {
            "string_switch": [],
            "isinstance_branch": [],
            "getattr_default": [],
            "many_parameters": [],
            "imports_in_functions": [],
            "hasattr": [],
            "type_branches": [],
            "flag_branches": [],
        }
        self.imports = 0
        self._depth = 0

    def _add(self, what: str, node: ast.AST, text: str = "") -> None:
        self.rows[what].append(f"{self.path}:{node.lineno}{': ' + text if text else ''}")

    def _branch(self, node: ast.AST, test: ast.AST, body) -> None:
        raises = isinstance(body, list) and _only_raises(body)
        if raises:
            return
        if _reads_flag(test):
            self._add("flag_branches", node)
        if _compares_string(test):
            self._add("string_switch", node)
        elif _checks_type(test):
            self._add("isinstance_branch", node)
            if _tested_types(test) & self.project_classes:
                self._add("type_branches", node)

    def visit_If(self, node: ast.If) -> None:
        self._branch(node, node.test, node.body)
        self.generic_visit(node)

    def visit_IfExp(self, node: ast.IfExp) -> None:
        self._branch(node, node.test, None)
        self.generic_visit(node)

    def visit_comprehension(self, node: ast.comprehension) -> None:
        for test in node.ifs:
            if _reads_flag(test):
                self._add("flag_branches", test)
        self.generic_visit(node)

    def visit_Match(self, node: ast.Match) -> None:
        for case in node.cases:
            for sub in ast.walk(case.pattern):
                if isinstance(sub, ast.MatchValue) and _is_string_literal(sub.value):
                    self._add("string_switch", case.pattern)
                    break
        self.generic_visit(node)

    def visit_Call(self, node: ast.Call) -> None:
        if isinstance(node.func, ast.Name) and node.func.id == "getattr" and len(node.args) == 3:
            self._add("getattr_default", node)
        if isinstance(node.func, ast.Name) and node.func.id == "hasattr" and len(node.args) == 2:
            self._add("hasattr", node)
        self.generic_visit(node)

    def _function(self, node) -> None:
        a = node.args
        names = [p.arg for p in (*a.posonlyargs, *a.args, *a.kwonlyargs)]
        if names and names[0] in ("self", "cls"):
            names = names[1:]
        n = len(names) + (a.vararg is not None) + (a.kwarg is not None)
        if n >= MANY_PARAMETERS:
            self._add("many_parameters", node, f"{node.name} ({n})")
        self._depth += 1
        self.generic_visit(node)
        self._depth -= 1

    visit_FunctionDef = _function
    visit_AsyncFunctionDef = _function

    def _import(self, node) -> None:
        self.imports += 1
        if self._depth:
            self._add("imports_in_functions", node)

    visit_Import = _import
    visit_ImportFrom = _import


def _project_classes(root: pathlib.Path, packages) -> frozenset[str]:
    names = set()
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            tree = ast.parse(path.read_text(encoding="utf-8"))
            names |= {n.name for n in ast.walk(tree) if isinstance(n, ast.ClassDef)}
    return frozenset(names)


def _moved_names(tree: ast.Module) -> list[str]:
    """The names of a ``_MOVED_TO = {home: "names ..."}`` table (served with a warning)."""
    for node in tree.body:
        if (
            isinstance(node, ast.Assign)
            and any(isinstance(t, ast.Name) and t.id == "_MOVED_TO" for t in node.targets)
            and isinstance(node.value, ast.Dict)
        ):
            return sorted(
                n
                for v in node.value.values
                if isinstance(v, ast.Constant) and isinstance(v.value, str)
                for n in v.value.split()
            )
    return []


def public_names(init: pathlib.Path) -> dict:
    """The public names of the package whose ``__init__.py`` is ``init`` (read, not imported):
    its ``__all__`` where it has one, else the names its top level binds (imports with or
    without ``as``, ``def``, ``class``, assignments) that do not start with ``_``, less its
    submodules and names imported from outside the project (the standard library's, JAX's)."""
    tree = ast.parse(init.read_text(encoding="utf-8"))
    folder = init.parent
    names: list[str] = []
    for node in tree.body:
        if isinstance(node, ast.Assign) and any(
            isinstance(t, ast.Name) and t.id == "__all__" for t in node.targets
        ):
            try:
                return {
                    "names": sorted(ast.literal_eval(node.value)),
                    "deprecated": _moved_names(tree),
                }
            except ValueError:
                pass
    for node in tree.body:
        if isinstance(node, ast.ImportFrom):
            if not node.level and (node.module or "").split(".")[0] not in PACKAGES:
                continue  # from importlib.metadata import version: not the project's
            for a in node.names:
                name = a.asname or a.name
                base = folder.parents[node.level - 2] if node.level > 1 else folder
                sub = base / (node.module or "").replace(".", "/") / a.name
                if node.level and (
                    sub.with_suffix(".py").is_file() or (sub / "__init__.py").is_file()
                ):
                    continue  # from . import submodule, from .cli import run
                names.append(name)
        elif isinstance(node, (ast.FunctionDef, ast.ClassDef)):
            names.append(node.name)
        elif isinstance(node, ast.Assign):
            names += [t.id for t in node.targets if isinstance(t, ast.Name)]
        elif isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            names.append(node.target.id)
    public = sorted({n for n in names if not n.startswith("_")} - {"annotations"})
    return {"names": public, "deprecated": _moved_names(tree)}


def count(root: pathlib.Path = ROOT, packages=PACKAGES) -> dict:
    """Count the structure figures over ``packages`` under ``root``.

    Returns:
        A dict: ``totals`` (the figures the targets speak of: model code and CLI, edge modules
        left out of ``kind_branches``; and the size, probe, type-branch, flag-branch and
        public-name figures), ``by_package`` (the same per top-level package and subpackage,
        with its ``lines`` and ``modules``), ``edge`` (the edge modules' string switches),
        ``public_names`` (per package: ``count``, ``deprecated``, ``names``) and ``where``
        (file:line of each counted place).
    """
    where: dict[str, list[str]] = {}
    by_package: dict[str, dict[str, int]] = {}
    imports = 0
    long_modules = []
    edge_switches = 0
    classes = _project_classes(root, packages)
    public: dict[str, dict] = {}
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            rel = path.relative_to(root).as_posix()
            text = path.read_text(encoding="utf-8")
            lines = len(text.splitlines())
            if lines > LONG_MODULE:
                long_modules.append(f"{rel} ({lines})")
            if path.name == "__init__.py":
                names = public_names(path)
                dotted = ".".join(path.relative_to(root).parent.parts)
                public[dotted] = {
                    "count": len(names["names"]),
                    "deprecated": len(names["deprecated"]),
                    "names": names["names"],
                }
            counter = _Counter(rel, classes)
            counter.visit(ast.parse(text, filename=rel))
            imports += counter.imports
            group = "/".join(rel.split("/")[:2]) if rel.count("/") > 1 else rel.split("/")[0]
            row = by_package.setdefault(group, {"lines": 0, "modules": 0})
            row["lines"] += lines
            row["modules"] += 1
            edge = rel.startswith(EDGE)
            for what, places in counter.rows.items():
                if edge and what == "string_switch":
                    edge_switches += len(places)
                    where.setdefault("edge_string_switch", []).extend(places)
                    continue
                row[what] = row.get(what, 0) + len(places)
                where.setdefault(what, []).extend(places)
    kind = sum(
        len(where.get(w, [])) for w in ("string_switch", "isinstance_branch", "getattr_default")
    )
    inside = len(where.get("imports_in_functions", []))

    def summed(what, groups):
        return sum(r.get(what, 0) for g, r in by_package.items() if g in groups)

    first = packages[0]
    own = [g for g in by_package if g == first or g.startswith(first + "/")]
    edge_groups = [g for g in own if g in {f"{first}/{e}" for e in EDGE_PACKAGES}]
    model_groups = [g for g in own if g not in edge_groups]
    own_lines = summed("lines", own)
    edge_lines = summed("lines", edge_groups)
    totals = {
        "kind_branches": kind,
        "string_switch": len(where.get("string_switch", [])),
        "isinstance_branch": len(where.get("isinstance_branch", [])),
        "getattr_default": len(where.get("getattr_default", [])),
        "many_parameters": len(where.get("many_parameters", [])),
        "imports_in_functions": inside,
        "imports": imports,
        "imports_in_functions_percent": round(100.0 * inside / max(imports, 1), 1),
        "long_modules": len(long_modules),
        "lines": sum(r["lines"] for r in by_package.values()),
        "modules": sum(r["modules"] for r in by_package.values()),
        f"{first}_lines": own_lines,
        f"{first}_modules": summed("modules", own),
        "edge_lines": edge_lines,
        "edge_share_percent": round(100.0 * edge_lines / max(own_lines, 1), 1),
        "edge_share_of_all_percent": round(
            100.0 * edge_lines / max(sum(r["lines"] for r in by_package.values()), 1), 1
        ),
        "model_probes": summed("hasattr", model_groups) + summed("getattr_default", model_groups),
        "model_hasattr": summed("hasattr", model_groups),
        "model_getattr_default": summed("getattr_default", model_groups),
        "type_branches": len(where.get("type_branches", [])),
        "edge_type_branches": summed("type_branches", edge_groups),
        "flag_branches": len(where.get("flag_branches", [])),
        "public_names": sum(v["count"] for v in public.values()),
        f"{first}_top_level_names": public.get(first, {}).get("count", 0),
        "deprecated_names": sum(v["deprecated"] for v in public.values()),
    }
    return {
        "package": first,
        "totals": totals,
        "by_package": by_package,
        "edge": {"string_switch": edge_switches},
        "public_names": public,
        "long_modules": long_modules,
        "where": where,
    }


#: the per-package table's columns
COLUMNS = (
    "lines",
    "modules",
    "public",
    "string_switch",
    "isinstance_branch",
    "type_branches",
    "getattr_default",
    "hasattr",
    "flag_branches",
    "many_parameters",
    "imports_in_functions",
)


def _public_of(group: str, result: dict) -> int | str:
    dotted = group.replace("/", ".")
    entry = result["public_names"].get(dotted)
    return "" if entry is None else entry["count"]


def markdown(result: dict, commit: str = "") -> str:
    """The report as a markdown page: the headline figures, then one row per package."""
    t = result["totals"]
    pkg = result["package"]
    out = [
        f"# Structure counts{f' at {commit}' if commit else ''}",
        "",
        "| figure | value |",
        "|---|---|",
        f"| lines (jaxgear, optimise, fem_prep) / modules | {t['lines']} / {t['modules']} |",
        f"| lines of {pkg} / modules | {t[pkg + '_lines']} / {t[pkg + '_modules']} |",
        (
            f"| the edge (jaxgear/cli + jaxgear/io): lines, share of {pkg} | {t['edge_lines']}, "
            f"{t['edge_share_percent']} % (of all three packages {t['edge_share_of_all_percent']} %) |"
        ),
        (
            f"| public names, all packages (of them at the top level of {pkg}) | "
            f"{t['public_names']} ({t[pkg + '_top_level_names']}) |"
        ),
        f"| moved names still served with a warning | {t['deprecated_names']} |",
        (
            f"| probes in model code: hasattr + getattr(x, name, default) | {t['model_probes']} "
            f"({t['model_hasattr']} + {t['model_getattr_default']}) |"
        ),
        (
            f"| branches on a project type (isinstance), all / in the edge | {t['type_branches']} / "
            f"{t['edge_type_branches']} |"
        ),
        f"| branches on the extended-contact flag | {t['flag_branches']} |",
        (
            f"| kind branches (string switches, isinstance, getattr defaults) | {t['kind_branches']} "
            f"({t['string_switch']}, {t['isinstance_branch']}, {t['getattr_default']}) |"
        ),
        f"| functions with >= {MANY_PARAMETERS} parameters | {t['many_parameters']} |",
        f"| imports inside functions | {t['imports_in_functions']} of {t['imports']} |",
        f"| modules over {LONG_MODULE} lines | {t['long_modules']} |",
        "",
        "| package | " + " | ".join(COLUMNS) + " |",
        "|---|" + "---:|" * len(COLUMNS),
    ]
    for group, row in sorted(result["by_package"].items()):
        cells = [_public_of(group, result) if c == "public" else row.get(c, 0) for c in COLUMNS]
        out.append(f"| {group} | " + " | ".join(str(c) for c in cells) + " |")
    return "\n".join(out) + "\n"


def _commit() -> str:
    import subprocess

    try:
        return subprocess.run(
            ["git", "rev-parse", "--short", "HEAD"],
            cwd=ROOT,
            capture_output=True,
            text=True,
            check=True,
        ).stdout.strip()
    except (OSError, subprocess.CalledProcessError):
        return ""


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the counts as JSON")
    parser.add_argument("--where", action="store_true", help="list file:line of each place")
    parser.add_argument(
        "--write",
        metavar="STEM",
        help="write STEM.json (the counts, the places, the public names) and STEM.md (the table)",
    )
    args = parser.parse_args(argv)
    result = count()
    if args.write:
        stem = pathlib.Path(args.write)
        commit = _commit()
        stem.with_suffix(".json").write_text(
            json.dumps({"commit": commit, **result}, indent=1) + "\n", encoding="utf-8"
        )
        stem.with_suffix(".md").write_text(markdown(result, commit), encoding="utf-8")
    if args.json:
        shown = result if args.where else {k: v for k, v in result.items() if k != "where"}
        print(json.dumps(shown, indent=2))
        return 0
    t = result["totals"]
    print(markdown(result))
    print(
        f"kind branches {t['kind_branches']} (string switches {t['string_switch']}, isinstance "
        f"{t['isinstance_branch']}, getattr defaults {t['getattr_default']}); edge string "
        f"switches {result['edge']['string_switch']} (not counted)"
    )
    print(f"modules over {LONG_MODULE} lines: {', '.join(result['long_modules']) or 'none'}")
    if args.where:
        for what, places in result["where"].items():
            print(f"\n{what}:")
            for p in places:
                print(f"  {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
