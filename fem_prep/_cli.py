"""Command line: ``fem-prep build BODY [--out DIR]``, ``fem-prep bodies``, ``fem-prep bench``."""

from __future__ import annotations

import argparse
import json
import sys
from collections.abc import Sequence

__all__ = ["add_build_arguments", "main", "run_build"]


def add_build_arguments(b: argparse.ArgumentParser) -> None:
    """The options of ``fem-prep build`` (shared with ``jaxgear prep``: one parser, one tree)."""
    b.add_argument("body", help="body file (.toml) or embedded body name (see 'fem-prep bodies')")
    b.add_argument("--out", default=None, help="output directory (default fem-prep-out/<name>)")
    b.add_argument("--no-cache", action="store_true", help="ignore and do not fill the cache")
    b.add_argument("--quiet", action="store_true", help="no progress bars")


def run_build(args, prog: str = "fem-prep") -> int:
    """Run ``build`` for parsed arguments (from :func:`add_build_arguments`); returns the exit
    status (0 ok, 2 bad body file or missing file)."""
    from ._io import build

    try:
        summary = build(args.body, args.out, use_cache=not args.no_cache, progress=not args.quiet)
    except (FileNotFoundError, ValueError) as exc:
        print(f"{prog}: error: {exc}", file=sys.stderr)
        return 2
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
    for f1, f2 in list(zip(summary["frequencies_full_hz"], summary["frequencies_condensed_hz"]))[
        :10
    ]:
        print(f"  {f1:10.1f} {f2:10.1f}")
    for k, v in summary["files"].items():
        print(f"wrote {k}: {v}")
    return 0


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="fem-prep",
        description="Mesh, assemble and condense flexible gear bodies (Craig-Bampton / Herting).",
    )
    sub = p.add_subparsers(dest="command", required=True)
    add_build_arguments(
        sub.add_parser("build", help="build a condensed body (npz + vtu + summary.json)")
    )
    sub.add_parser("bodies", help="list the embedded bodies")
    be = sub.add_parser("bench", help="timing/memory benchmark on three mesh sizes")
    be.add_argument("--out", default="fem-prep-out/bench", help="directory for bench.json/png")
    be.add_argument("--quick", action="store_true", help="small sizes only (smoke test)")
    be.add_argument("--resume", action="store_true", help="reuse cases of an interrupted run")
    return p


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``fem-prep`` console script (also used by ``jaxgear prep``).

    Args:
        argv: arguments without the program name (default ``sys.argv[1:]``).

    Returns:
        Exit status: 0 on success, 2 on a bad body file or a missing file.
    """
    args = _parser().parse_args(None if argv is None else list(argv))
    if args.command == "bodies":
        from ._body import embedded_bodies, load_body

        for name in embedded_bodies():
            b = load_body(name)
            g = b.geometry
            print(
                f"{name:24s} teeth={b.condensation.teeth:<4d} rim r={g.rim_outer_radius * 1e3:.2f}"
                f" mm b={g.rim_width * 1e3:.1f} mm web t={g.web_thickness * 1e3:.1f} mm "
                f"method={b.condensation.method}"
            )
        return 0
    if args.command == "build":
        return run_build(args)
    if args.command == "bench":
        from ._bench import run_bench

        run_bench(args.out, quick=args.quick, resume=args.resume)
        return 0
    return 1  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
