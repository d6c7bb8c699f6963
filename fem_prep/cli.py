"""Command line: ``fem-prep build BODY [--out DIR]``, ``fem-prep bodies [NAME [--write FILE]]``,
``fem-prep bench``.

As ``jaxgear``'s: the body file and the output folder are checked before any work; bad input
gives one line ``fem-prep: error: …`` and exit status 2, Ctrl-C one line ``fem-prep:
interrupted`` and exit status 130, a closed pipe (``fem-prep bodies | head -1``) a quiet exit.
"""

from __future__ import annotations

import argparse
import functools
import json
import os
import sys
from collections.abc import Sequence
from pathlib import Path

from ._bench import run_bench
from ._io import build, output_names
from .files import check_not_input, check_output_dir, print_or_write
from .schema import embedded_bodies, embedded_body_text, load_body

__all__ = ["add_build_arguments", "main", "run_build"]


def add_build_arguments(b: argparse.ArgumentParser) -> None:
    """The options of ``fem-prep build`` (shared with ``jaxgear prep``: one parser, one tree)."""
    b.add_argument("body", help="body file (.toml) or embedded body name (see 'fem-prep bodies')")
    b.add_argument("--out", default=None, help="output directory (default fem-prep-out/<name>)")
    b.add_argument("--no-cache", action="store_true", help="ignore and do not fill the cache")
    b.add_argument("--quiet", action="store_true", help="no progress bars")


def _fail(prog: str, exc: BaseException) -> int:
    print(f"{prog}: error: {exc}", file=sys.stderr)
    return 2


def run_build(args, prog: str = "fem-prep") -> int:
    """Run ``build`` for parsed arguments (from :func:`add_build_arguments`); returns the exit
    status (0 ok, 2 bad body file, missing file or an output folder that cannot be written:
    checked before the build starts)."""
    try:
        body = load_body(args.body)
        out = Path(check_output_dir(args.out or Path("fem-prep-out") / body.name))
        if os.path.isfile(args.body):  # the build writes over none of its inputs
            for name in output_names(body).values():
                check_not_input(out / name, "--out", {args.body: "the body file"})
    except (FileNotFoundError, ValueError) as exc:
        return _fail(prog, exc)
    summary = build(body, out, use_cache=not args.no_cache, progress=not args.quiet)
    keys = (
        "name",
        "n_nodes",
        "n_dofs",
        "mass_kg",
        "n_master_dofs",
        "n_modes",
        "centrifugal_rim_radial_displacement_m",
        "cache_hit",
    )
    print(json.dumps({k: summary[k] for k in keys}, indent=1))
    print("first frequencies (Hz), full / condensed:")
    pairs = zip(summary["frequencies_full_hz"], summary["frequencies_condensed_hz"])
    for f1, f2 in list(pairs)[:10]:
        print(f"  {f1:10.1f} {f2:10.1f}")
    for k, v in summary["files"].items():
        print(f"wrote {k}: {v}")
    return 0


def _bodies(args) -> int:
    """``fem-prep bodies``: one line per embedded body; with NAME its body file (to stdout or,
    with ``--write FILE``, to a new file to start from)."""
    if args.name is None:
        if args.write is not None:
            raise ValueError("--write needs a body NAME (fem-prep bodies NAME --write FILE)")
        for name in embedded_bodies():
            b = load_body(name)
            g = b.geometry
            print(
                f"{name:24s} teeth={b.condensation.teeth:<4d} rim r={g.rim_outer_radius * 1e3:.2f}"
                f" mm b={g.rim_width * 1e3:.1f} mm web t={g.web_thickness * 1e3:.1f} mm "
                f"method={b.condensation.method}"
            )
        return 0
    text = embedded_body_text(args.name)
    what = f"embedded body {args.name!r}"
    print_or_write(text, args.write, force=args.force, what=what, next_command="fem-prep build")
    return 0


def _bench(args) -> int:
    """``fem-prep bench``: the timing and memory benchmark (``fem_prep._bench``)."""
    run_bench(check_output_dir(args.out), quick=args.quick, resume=args.resume)
    return 0


@functools.singledispatch
def _exit_status(code) -> int:
    """The exit status of argparse's ``SystemExit`` code: an int as is, ``None`` 0 (``--help``),
    a message 2."""
    return 2


@_exit_status.register
def _(code: int) -> int:
    return code


@_exit_status.register(type(None))
def _(code: None) -> int:
    return 0


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="fem-prep",
        description="Mesh, assemble and condense flexible gear bodies (Craig-Bampton / Herting).",
    )
    sub = p.add_subparsers(dest="command", required=True)
    bu = sub.add_parser("build", help="build a condensed body (npz + vtu + summary.json)")
    add_build_arguments(bu)
    bu.set_defaults(run=run_build)
    bo = sub.add_parser("bodies", help="list the embedded bodies, or print / write one")
    bo.set_defaults(run=_bodies)
    bo.add_argument("name", nargs="?", help="an embedded body: print its body file")
    bo.add_argument("--write", metavar="FILE", help="write the body file to FILE instead")
    bo.add_argument("--force", action="store_true", help="replace FILE if it exists")
    be = sub.add_parser("bench", help="timing/memory benchmark on three mesh sizes")
    be.set_defaults(run=_bench)
    be.add_argument("--out", default="fem-prep-out/bench", help="directory for bench.json/png")
    be.add_argument("--quick", action="store_true", help="small sizes only (smoke test)")
    be.add_argument("--resume", action="store_true", help="reuse cases of an interrupted run")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``fem-prep`` console script (also used by ``jaxgear prep``).

    Args:
        argv: arguments without the program name (default ``sys.argv[1:]``).

    Returns:
        Exit status: 0 on success, 2 on a bad body file, a missing file or an output path that
        cannot be written, 130 when interrupted (Ctrl-C).
    """
    try:
        args = _parser().parse_args(None if argv is None else list(argv))
    except SystemExit as err:  # --help or argparse's usage error (status 2)
        return _exit_status(err.code)
    try:
        status = args.run(args)
        sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
        return status
    except (FileNotFoundError, ValueError) as exc:
        return _fail("fem-prep", exc)
    except KeyboardInterrupt:
        print("\nfem-prep: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader went away (``fem-prep bodies | head -1``): exit quietly, no traceback
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
