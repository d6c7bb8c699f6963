"""Structure counts of the source tree: how often the code asks "which kind?".

Run from a source checkout::

    python benchmarks/structure_counts.py            # table per package
    python benchmarks/structure_counts.py --json     # the same as JSON

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

The edge packages (``jaxgear/io``, ``fem_prep/schema.py`` and the file-text checks it shares with
``jaxgear/io``, ``fem_prep/checks.py``) map names in files to objects by
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
EDGE = ("jaxgear/io/", "fem_prep/schema.py", "fem_prep/checks.py")
LONG_MODULE = 700
MANY_PARAMETERS = 10


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
            ops_ok = all(
                isinstance(op, (ast.Eq, ast.NotEq, ast.In, ast.NotIn)) for op in node.ops
            )
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


class _Counter(ast.NodeVisitor):
    def __init__(self, path: str):
        self.path = path
        self.rows: dict[str, list[str]] = {
            "string_switch": [],
            "isinstance_branch": [],
            "getattr_default": [],
            "many_parameters": [],
            "imports_in_functions": [],
        }
        self.imports = 0
        self._depth = 0

    def _add(self, what: str, node: ast.AST, text: str = "") -> None:
        self.rows[what].append(f"{self.path}:{node.lineno}{': ' + text if text else ''}")

    def _branch(self, node: ast.AST, test: ast.AST, body) -> None:
        raises = isinstance(body, list) and _only_raises(body)
        if raises:
            return
        if _compares_string(test):
            self._add("string_switch", node)
        elif _checks_type(test):
            self._add("isinstance_branch", node)

    def visit_If(self, node: ast.If) -> None:
        self._branch(node, node.test, node.body)
        self.generic_visit(node)

    def visit_IfExp(self, node: ast.IfExp) -> None:
        self._branch(node, node.test, None)
        self.generic_visit(node)

    def visit_Match(self, node: ast.Match) -> None:
        for case in node.cases:
            for sub in ast.walk(case.pattern):
                if isinstance(sub, ast.MatchValue) and _is_string_literal(sub.value):
                    self._add("string_switch", case.pattern)
                    break
        self.generic_visit(node)

    def visit_Call(self, node: ast.Call) -> None:
        if (
            isinstance(node.func, ast.Name)
            and node.func.id == "getattr"
            and len(node.args) == 3
        ):
            self._add("getattr_default", node)
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


def count(root: pathlib.Path = ROOT, packages=PACKAGES) -> dict:
    """Count the structure figures over ``packages`` under ``root``.

    Returns:
        A dict: ``totals`` (the figures the targets speak of: model code and CLI, edge modules
        left out of ``kind_branches``), ``by_package`` (the same per top-level package and
        subpackage), ``edge`` (the edge modules' string switches) and ``where`` (file:line of
        each counted place).
    """
    where: dict[str, list[str]] = {}
    by_package: dict[str, dict[str, int]] = {}
    imports = 0
    long_modules = []
    edge_switches = 0
    for package in packages:
        for path in sorted((root / package).rglob("*.py")):
            rel = path.relative_to(root).as_posix()
            text = path.read_text(encoding="utf-8")
            lines = text.count("\n") + (not text.endswith("\n"))
            if lines > LONG_MODULE:
                long_modules.append(f"{rel} ({lines})")
            counter = _Counter(rel)
            counter.visit(ast.parse(text, filename=rel))
            imports += counter.imports
            group = "/".join(rel.split("/")[:2]) if rel.count("/") > 1 else rel.split("/")[0]
            row = by_package.setdefault(group, {})
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
    }
    return {
        "totals": totals,
        "by_package": by_package,
        "edge": {"string_switch": edge_switches},
        "long_modules": long_modules,
        "where": where,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print the counts as JSON")
    parser.add_argument("--where", action="store_true", help="list file:line of each place")
    args = parser.parse_args(argv)
    result = count()
    if args.json:
        shown = result if args.where else {k: v for k, v in result.items() if k != "where"}
        print(json.dumps(shown, indent=2))
        return 0
    t = result["totals"]
    print(
        f"kind branches {t['kind_branches']} (string switches {t['string_switch']}, isinstance "
        f"{t['isinstance_branch']}, getattr defaults {t['getattr_default']}); edge string "
        f"switches {result['edge']['string_switch']} (not counted)"
    )
    print(f"functions with >= {MANY_PARAMETERS} parameters: {t['many_parameters']}")
    print(
        f"imports inside functions: {t['imports_in_functions']} of {t['imports']} "
        f"({t['imports_in_functions_percent']} %)"
    )
    print(f"modules over {LONG_MODULE} lines: {', '.join(result['long_modules']) or 'none'}")
    print()
    cols = ("string_switch", "isinstance_branch", "getattr_default", "many_parameters",
            "imports_in_functions")
    print(f"{'package':24s} " + " ".join(f"{c[:14]:>14s}" for c in cols))
    for group, row in sorted(result["by_package"].items()):
        print(f"{group:24s} " + " ".join(f"{row.get(c, 0):14d}" for c in cols))
    if args.where:
        for what, places in result["where"].items():
            print(f"\n{what}:")
            for p in places:
                print(f"  {p}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
