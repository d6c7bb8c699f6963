"""Command line: ``jaxgear run | cases | optimise | master-curve | sweep | robust | bench | prep``.

The CLI is an entry point, so it switches float64 on (library modules never do) and JAX's
persistent compilation cache (:mod:`.xla_cache`: ``~/.cache/jaxgear/xla``, ``$JAXGEAR_XLA_CACHE``
to move it or ``off``). Every command
validates its whole input (case file, options, output folder) before it computes; bad input gives
one line ``jaxgear: error: …`` and exit status 2, Ctrl-C one line ``jaxgear: interrupted`` and
exit status 130, a closed pipe (``jaxgear run | head``) a quiet exit.
"""

from __future__ import annotations

import argparse
import os
import re
import sys

__all__ = ["main", "runtime_message"]


def _version() -> str:
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("jaxgear")
    except PackageNotFoundError:  # pragma: no cover - source tree not installed
        return "unknown"


def _parser() -> argparse.ArgumentParser:
    from ._optimise import add_parsers as add_optimise_parsers
    from .robust import add_robust_parser
    from .sweep import add_sweep_parser

    p = argparse.ArgumentParser(prog="jaxgear", description="Differentiable gear dynamics in JAX.")
    p.add_argument("--version", action="version", version=f"jaxgear {_version()}")
    sub = p.add_subparsers(dest="command", required=True)
    r = sub.add_parser(
        "run",
        help="the main job: quasi-static analysis of a case, and the speed sweep and "
        "optimisation its [scene] and [optimise] ask for",
    )
    r.add_argument(
        "case",
        nargs="?",
        default="accessory-spur",
        help="TOML case file or embedded case name (default: accessory-spur)",
    )
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/)")
    r.add_argument(
        "--json", help="also write the summary to this file (its folder is created if missing)"
    )
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument(
        "--keep-partial",
        action="store_true",
        help="write into the output folder as the run goes and keep what a failed or "
        "interrupted run wrote, summary.json saying \"complete\": false (default: the files "
        "appear when the run completes; a failed run leaves the earlier results)",
    )
    c = sub.add_parser("cases", help="list the embedded cases, or print / write one")
    c.add_argument("name", nargs="?", help="an embedded case: print its case file")
    c.add_argument("--write", metavar="FILE", help="write the case file to FILE instead")
    c.add_argument("--force", action="store_true", help="replace FILE if it exists")
    b = sub.add_parser(
        "bench",
        help="benchmarks (speed vs a baseline, speed-vs-accuracy charts; from a source checkout)",
    )
    b.add_argument(
        "what",
        choices=[
            "quasi-static",
            "optimise",
            "dynamics",
            "hybrid",
            "hybrid-sweep",
            "modal-basis",
            "stiffness",
            "trains",
            "robust",
            "xla-cache",
        ],
        help="which benchmark",
    )
    b.add_argument("--out", default="jaxgear-out/bench", help="output folder")
    b.add_argument("--quick", action="store_true", help="a small, fast version (smoke test)")
    b.add_argument(
        "--cases",
        metavar="NAME[,NAME…]",
        help="xla-cache: the embedded cases to run twice (default: all; --quick: accessory-spur)",
    )
    from fem_prep import add_build_arguments

    pr = sub.add_parser("prep", help="fem_prep: mesh and condense a gear body (= fem-prep build)")
    add_build_arguments(pr)
    add_sweep_parser(sub)
    add_robust_parser(sub)
    add_optimise_parsers(sub)
    return p


def _cases(args) -> int:
    """``jaxgear cases``: one line per embedded case; with NAME its case file (to stdout or,
    with ``--write FILE``, to a new file to start from: ``jaxgear run FILE`` runs it)."""
    from fem_prep.schema import print_or_write

    from ..io import embedded_case_text, list_cases, load_case
    from .train import gear_glossary

    if args.name is None:
        if args.write is not None:
            raise ValueError("--write needs a case NAME (jaxgear cases NAME --write FILE)")
        for name in list_cases():
            c = load_case(name)
            if hasattr(c, "gear_names"):  # a train: its gears' teeth, input first
                teeth = "/".join(str(m.teeth) for m in c.members())
                modules = dict.fromkeys(f"{p.normal_module * 1e3:g}" for p in c.pairs)
                glossary = gear_glossary(c.gear_names)
                print(
                    f"{name:24s} train z {teeth}, m_n {'/'.join(modules)} mm, "
                    f"T {c.torque:g} N·m (input), {c.stiffness_model} stiffness"
                    + (f", {c.scene.model} scene" if c.scene is not None else "")
                    + (f" ({glossary})" if glossary else "")
                )
                continue
            print(
                f"{name:24s} z {c.pair.pinion.teeth}/{c.pair.gear.teeth}, "
                f"m_n {c.pair.normal_module * 1e3:g} mm, "
                f"β {c.raw['pair'].get('helix_angle_deg', 0)}°, "
                f"T {c.torque:g} N·m, {c.stiffness_model} stiffness"
                + (f", {c.scene.model} scene" if c.scene is not None else "")
                + (" with condensed bodies" if c.scene is not None and c.scene.hybrid else "")
            )
        return 0
    text = embedded_case_text(args.name)
    what = f"embedded case {args.name!r}"
    print_or_write(text, args.write, force=args.force, what=what, next_command="jaxgear run")
    return 0


_NO_BENCHMARKS = (
    "jaxgear bench runs from a source checkout (no benchmarks/ folder next to the jaxgear "
    "package or in the current folder)"
)


def _benchmarks_folder():
    """The ``benchmarks/`` folder of a source checkout, or None.

    The benchmarks are not installed with jaxgear: they live in the checkout, next to the
    ``jaxgear`` package (an editable install: ``<checkout>/jaxgear/__init__.py``) or in the
    current folder (a checkout's root). A candidate counts only with ``__init__.py`` in it and
    ``jaxgear/`` and ``pyproject.toml`` beside it, so an unrelated ``benchmarks/`` is never taken.
    """
    from pathlib import Path

    import jaxgear

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
    import importlib.util
    from pathlib import Path

    folder = _benchmarks_folder()
    if folder is None:
        raise ValueError(_NO_BENCHMARKS)
    init = (folder / "__init__.py").resolve()
    loaded = sys.modules.get("benchmarks")
    here = getattr(loaded, "__file__", None)
    if here is not None and Path(here).resolve() == init:
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


def _bench(args) -> int:
    from ._paths import clear_outputs

    if args.cases is not None and args.what != "xla-cache":
        raise ValueError(f"--cases is an option of bench xla-cache, not of bench {args.what}")
    bench = _load_benchmarks()  # before clearing: no checkout, no outputs touched
    clear_outputs(args.out, f"bench {args.what}")
    if args.what == "dynamics":
        bench.bench_dynamics(args.out, quick=args.quick)
    elif args.what == "optimise":
        bench.bench_optimise(args.out, quick=args.quick)
    elif args.what == "hybrid":
        bench.bench_hybrid(args.out, quick=args.quick)
    elif args.what == "hybrid-sweep":
        bench.bench_hybrid_sweep(args.out, quick=args.quick)
    elif args.what == "modal-basis":
        bench.bench_modal_basis(args.out, quick=args.quick)
    elif args.what == "stiffness":
        bench.bench_stiffness(args.out, quick=args.quick)
    elif args.what == "trains":
        bench.bench_trains(args.out, quick=args.quick)
    elif args.what == "robust":
        bench.bench_robust(args.out, quick=args.quick)
    elif args.what == "xla-cache":
        cases = None if args.cases is None else [c.strip() for c in args.cases.split(",")]
        bench.bench_xla_cache(args.out, quick=args.quick, cases=cases)
    else:
        bench.bench_quasi_static(args.out, quick=args.quick)
    return 0


def _dispatch(args) -> int:
    if args.command == "prep":
        from fem_prep import run_build

        return run_build(args, prog="jaxgear prep")

    import jax

    from .xla_cache import enable as enable_xla_cache

    jax.config.update("jax_enable_x64", True)
    enable_xla_cache()  # before the first compilation: a second run compiles nothing again
    if args.command == "cases":
        return _cases(args)
    if args.command == "run":
        from .run import run_command

        return run_command(args)
    if args.command == "optimise":
        from ._optimise import run_optimise

        return run_optimise(args)
    if args.command == "master-curve":
        from ._optimise import run_master_curve

        return run_master_curve(args)
    if args.command == "sweep":
        from .sweep import run_sweep

        return run_sweep(args)
    if args.command == "robust":
        from .robust import run_robust

        return run_robust(args)
    if args.command == "bench":
        return _bench(args)
    raise ValueError(f"unknown command {args.command!r}")  # pragma: no cover


def runtime_message(err: BaseException) -> str:
    """The message of a failure raised inside compiled code, as one line.

    ``eqx.EquinoxRuntimeError`` wraps the message of ``eqx.error_if`` (or of a result code with
    ``throw=True``) between a banner, the stack inside JIT and debugging advice; the line that
    carries it reads ``equinox.EquinoxRuntimeError: <message>``. Without it (code compiled with
    ``jax.jit`` instead of ``eqx.filter_jit``) the message is not available and this says so.
    """
    text = str(err)
    found = re.findall(r"EquinoxRuntimeError:\s*(.+)", text)
    if found:
        return found[-1].strip()
    first = text.strip().splitlines()[0] if text.strip() else ""
    if first and not first.startswith(("Above is the stack", "An error occurred")):
        return first
    return "a compiled solver failed and gave no message (set EQX_ON_ERROR=breakpoint to debug)"


def fail(msg: str) -> int:
    """Print ``jaxgear: error: msg`` (first line only) on stderr, on a line of its own (the
    progress bars a failed command left open closed first); return exit status 2."""
    first = str(msg).strip().splitlines()[0] if str(msg).strip() else "failed"
    _close_bars()
    print(f"jaxgear: error: {first}", file=sys.stderr)
    return 2


def _close_bars() -> None:
    """Close every progress bar still open (a command that failed inside a bar's loop leaves
    it open, its line unfinished): each ends its line, so that what follows starts on a fresh
    line instead of being glued to the bar's (and overwritten by its last refresh)."""
    module = sys.modules.get("tqdm")
    if module is None:
        return
    for bar in list(getattr(module.tqdm, "_instances", ())):
        try:
            bar.close()
        except Exception:  # noqa: BLE001 - a broken bar must not hide the message
            pass


def _show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """``warnings.showwarning`` of the CLI: one line ``jaxgear: warning: …`` on stderr."""
    text = " ".join(str(message).split())
    try:
        print(f"jaxgear: warning: {text}", file=file or sys.stderr, flush=True)
    except (OSError, ValueError):  # stderr gone: nothing to tell
        pass


def main(argv: list[str] | None = None) -> int:
    """Run the CLI; returns the exit status (0 ok, 2 bad input, 130 interrupted).

    Library warnings reach the user as one line ``jaxgear: warning: …`` on stderr.
    """
    import warnings

    saved = warnings.showwarning
    warnings.showwarning = _show_warning
    try:
        try:
            args = _parser().parse_args(argv)
        except SystemExit as err:  # --help, --version, or argparse's usage error (status 2)
            return err.code if isinstance(err.code, int) else (0 if err.code is None else 2)
        try:
            from ._options import check_options

            check_options(args)  # before JAX, the model or the case file is touched
        except ValueError as err:
            return fail(str(err))
        import equinox as eqx

        try:
            status = _dispatch(args)
            sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
            return status
        except (ValueError, FileNotFoundError, NotADirectoryError, PermissionError) as err:
            return fail(str(err))
        except eqx.EquinoxRuntimeError as err:
            return fail(runtime_message(err))
    except KeyboardInterrupt:
        _close_bars()
        print("\njaxgear: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader went away (``jaxgear run | head``): exit quietly, no traceback
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0
    finally:
        warnings.showwarning = saved


def entry() -> None:  # pragma: no cover - console-script wrapper
    status = main()
    if status == 130:
        # interrupted: XLA may still run threads of the abandoned computation, and tearing the
        # interpreter down under them can crash; the files are closed and complete, so leave now
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(130)
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    entry()
