"""benchmarks/structure_counts.py counts what it says on a small package written here (each
kind of place once, and the input checks and the script guard it must leave out)."""

import importlib.util
import pathlib

ROOT = pathlib.Path(__file__).resolve().parent.parent

SOURCE = '''
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
'''


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
