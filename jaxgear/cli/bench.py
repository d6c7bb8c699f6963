"""``jaxgear bench WHAT`` (the checkout's benchmarks) and ``jaxgear prep`` (fem_prep's build)."""

from __future__ import annotations

import importlib.util
import sys
from pathlib import Path

from fem_prep import run_build

import jaxgear

from ._parser import BENCHMARKS
from ._paths import check_foreign_files, clear_outputs

__all__ = ["run_bench", "run_prep"]

_NO_BENCHMARKS = (
    "jaxgear bench runs from a source checkout (no benchmarks/ folder next to the jaxgear "
    "package or in the current folder)"
)


def _benchmarks_folder() -> Path | None:
    """The ``benchmarks/`` folder of a source checkout, or None.

    The benchmarks are not installed with jaxgear: they live in the checkout, next to the
    ``jaxgear`` package (an editable install: ``<checkout>/jaxgear/__init__.py``) or in the
    current folder (a checkout's root). A candidate counts only with ``__init__.py`` in it and
    ``jaxgear/`` and ``pyproject.toml`` beside it, so an unrelated ``benchmarks/`` is never taken.
    """
    for root in (Path(jaxgear.__file__).resolve().parents[1], Path.cwd()):
        folder = root / "benchmarks"
        if (
            (folder / "__init__.py").is_file()
            and (root / "jaxgear" / "__init__.py").is_file()
            and (root / "pyproject.toml").is_file()
        ):
            return folder
    return None


def _load_benchmarks():
    """Import the checkout's ``benchmarks`` package (the one already imported when it is the
    same folder, as under pytest); ValueError when no checkout is found."""
    folder = _benchmarks_folder()
    if folder is None:
        raise ValueError(_NO_BENCHMARKS)
    init = (folder / "__init__.py").resolve()
    loaded = sys.modules.get("benchmarks")
    spec = None if loaded is None else loaded.__spec__
    origin = None if spec is None else spec.origin  # a namespace package has none
    if origin is not None and Path(origin).resolve() == init:
        return loaded
    spec = importlib.util.spec_from_file_location(
        "benchmarks", init, submodule_search_locations=[str(folder)]
    )
    module = importlib.util.module_from_spec(spec)
    sys.modules["benchmarks"] = module
    try:
        spec.loader.exec_module(module)
    except BaseException:
        if loaded is None:
            sys.modules.pop("benchmarks", None)
        else:
            sys.modules["benchmarks"] = loaded
        raise
    return module


def run_bench(args) -> int:
    """``jaxgear bench WHAT``: the benchmark's function of :data:`jaxgear.cli._parser.BENCHMARKS`
    (``--cases``: xla-cache's only) into ``--out``, cleared first."""
    if args.cases is not None and args.what != "xla-cache":
        raise ValueError(f"--cases is an option of bench xla-cache, not of bench {args.what}")
    check_foreign_files(args.out, f"bench {args.what}", force=args.force)
    bench = _load_benchmarks()  # before clearing: no checkout, no outputs touched
    clear_outputs(args.out, f"bench {args.what}")
    options = {}
    if args.cases is not None:
        options["cases"] = [c.strip() for c in args.cases.split(",")]
    getattr(bench, BENCHMARKS[args.what])(args.out, quick=args.quick, **options)
    return 0


def run_prep(args) -> int:
    """``jaxgear prep``: fem_prep's ``build`` (the same options, no JAX)."""
    return run_build(args, prog="jaxgear prep")
