"""benchmarks/structure_counts.py counts what it says on a small package written here (each
kind of place once, and the input checks and the script guard it must leave out)."""

import importlib.util
import pathlib

ROOT = pathlib.Path(__file__).resolve().parent.parent

SOURCE = """
import os


def dispatch(kind, x, a, b, c, d, e, f, g, *args, **kw):
    import math
    if kind == "weber":
        return 1
    elif kind in ("iso", "fe2d"):
        return 2
    if isinstance(x, float):
        return 3
    if isinstance(x, str):
        raise ValueError("x must not be a string")
    if kind not in ("a", "b"):
        raise ValueError("kind")
    y = 1 if type(x) is int else 2
    return getattr(x, "name", None), y, math.pi


def small(self, a, b):
    return a


if __name__ == "__main__":
    dispatch("weber", 1, 2, 3, 4, 5, 6, 7, 8)
"""


def _load():
    spec = importlib.util.spec_from_file_location(
        "structure_counts", ROOT / "benchmarks" / "structure_counts.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_counts_each_kind_of_place_and_leaves_out_checks(tmp_path):
    sc = _load()
    (tmp_path / "pkg").mkdir()
    (tmp_path / "pkg" / "mod.py").write_text(SOURCE + "\n" * 700)
    result = sc.count(tmp_path, packages=("pkg",))
    t = result["totals"]
    assert t["string_switch"] == 2  # == and `in` a literal; the raising check and guard left out
    assert t["isinstance_branch"] == 2  # isinstance and type(x) is; the raising check left out
    assert t["getattr_default"] == 1
    assert t["kind_branches"] == 5
    assert t["many_parameters"] == 1  # dispatch: 9 named + *args + **kw = 11; small: 2
    assert (t["imports_in_functions"], t["imports"]) == (1, 2)
    assert result["long_modules"] == [f"pkg/mod.py ({SOURCE.count(chr(10)) + 700})"]


INIT = '''
from importlib.metadata import version
from . import cli
from ._geometry import GearPair as GearPair, involute
from .cli import run

LIMIT = 3


def helper():
    return 1


class Result:
    pass


_MOVED_TO = {"cli": """Old Older"""}
'''

MODEL = """
class Pair:
    extended_contact = False


def probe(x, mesh, items):
    if hasattr(x, "whine"):
        return 1
    if isinstance(x, Pair):
        return 2
    if isinstance(x, (int, float)):
        return 3
    if mesh.extended_contact:
        return 4
    if not mesh.extended_contact:
        raise ValueError("only with the flag")
    return [m for m in items if m.extended_contact], getattr(x, "k", 0)
"""

EDGE = """
from pkg._geometry import Pair


def present(model):
    if isinstance(model, Pair):
        return "pair"
    return ""
"""


def test_counts_size_probes_type_and_flag_branches_and_public_names(tmp_path):
    sc = _load()
    pkg = tmp_path / "pkg"
    (pkg / "cli").mkdir(parents=True)
    (pkg / "__init__.py").write_text(INIT)
    (pkg / "_geometry.py").write_text(MODEL)
    (pkg / "cli" / "__init__.py").write_text("")
    (pkg / "cli" / "run.py").write_text(EDGE)
    result = sc.count(tmp_path, packages=("pkg",))
    t = result["totals"]
    lines = {
        name: text.count("\n") for name, text in (("init", INIT), ("model", MODEL), ("edge", EDGE))
    }
    assert t["pkg_lines"] == lines["init"] + lines["model"] + lines["edge"]
    assert t["pkg_modules"] == 4
    assert t["edge_lines"] == lines["edge"]
    assert t["edge_share_percent"] == round(100 * lines["edge"] / t["pkg_lines"], 1)
    # hasattr once, getattr with a default once; the edge has none
    assert (t["model_hasattr"], t["model_getattr_default"], t["model_probes"]) == (1, 1, 2)
    # isinstance on Pair in the model and in the edge; on (int, float) not a project type
    assert (t["isinstance_branch"], t["type_branches"], t["edge_type_branches"]) == (3, 2, 1)
    # the flag read by an if and a comprehension filter; the check that only raises left out
    assert t["flag_branches"] == 2
    # GearPair, involute, LIMIT, helper, Result: not the submodules (cli, run) nor version
    public = result["public_names"]
    assert public["pkg"]["names"] == ["GearPair", "LIMIT", "Result", "helper", "involute"]
    assert (public["pkg"]["deprecated"], public["pkg.cli"]["count"]) == (2, 0)
    assert (t["public_names"], t["pkg_top_level_names"], t["deprecated_names"]) == (5, 5, 2)
    page = sc.markdown(result)
    assert "| pkg/cli | " + str(lines["edge"]) + " | 2 | 0 |" in page
