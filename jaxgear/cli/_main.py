"""Command line: ``jaxgear run | cases | optimise | master-curve | sweep | modes | robust | size | bench | prep``.

The command line is parsed and its options checked before the model is imported: this module
imports neither JAX nor equinox, so that ``jaxgear --help``, ``--version``, a subcommand's
``--help`` and ``jaxgear cases`` answer at once (the console script, :mod:`jaxgear_start`, defers
the model package itself, and :func:`main` loads it for a command that needs it).

The CLI is an entry point, so it switches float64 on (library modules never do) and JAX's
persistent compilation cache (:mod:`.xla_cache`: ``~/.cache/jaxgear/xla``, ``$JAXGEAR_XLA_CACHE``
to move it or ``off``). Every command
validates its whole input (case file, options, output folder) before it computes; bad input gives
one line ``jaxgear: error: …`` and exit status 2, Ctrl-C one line ``jaxgear: interrupted`` and
exit status 130, SIGTERM (``timeout``, a job scheduler, ``kill``) the same clean-up as Ctrl-C
(:class:`Terminated`), one line ``jaxgear: terminated (SIGTERM)`` and exit status 143 (128 + 15),
a closed pipe (``jaxgear run | head``) a quiet exit.
"""

from __future__ import annotations

import contextlib
import importlib
import os
import re
import signal
import sys
import warnings
from collections.abc import Callable

from ._options import check_options
from ._parser import COMMANDS, build_parser, command_of

__all__ = ["Terminated", "main", "runtime_message"]

#: the exit statuses of a run stopped by Ctrl-C (SIGINT) and by SIGTERM: 128 + the signal's number
INTERRUPTED, TERMINATED = 130, 143


class Terminated(KeyboardInterrupt):
    """SIGTERM received by the command line's main thread (:func:`_sigterm_interrupts`): an
    interruption like Ctrl-C's ``KeyboardInterrupt`` (of which it is one), so that whatever
    cleans up after Ctrl-C cleans up after it alike: a staged run's hidden staging folder is
    removed and the earlier results stay (:func:`jaxgear.cli._paths.staged_outputs`), a
    ``--keep-partial`` run keeps its finished files with ``summary.json`` saying ``"complete":
    false``, temporary files are deleted. Like Ctrl-C it takes effect when the main thread is
    back in Python (between compiled calls)."""


@contextlib.contextmanager
def _sigterm_interrupts():
    """While the block runs, SIGTERM raises :class:`Terminated` in the main thread (once: a
    second SIGTERM during the clean-up is ignored, so that the clean-up completes); the
    previous handler is restored after. Called from another thread (where no handler can be
    set), the block runs with SIGTERM as it was."""

    def handler(signum, frame):
        signal.signal(signal.SIGTERM, signal.SIG_IGN)
        raise Terminated

    try:
        previous = signal.signal(signal.SIGTERM, handler)
    except ValueError:  # not the main thread
        yield
        return
    try:
        yield
    finally:
        signal.signal(signal.SIGTERM, previous)


def _command(name: str):
    """The function that runs the subcommand ``name`` (:data:`jaxgear.cli._parser.COMMANDS`):
    its module imported here, the one place the CLI imports a command's implementation (the
    parser and the option checks need none of them)."""
    module, _, function = COMMANDS[name].target.partition(":")
    return getattr(importlib.import_module(module), function)


def _dispatch(args) -> int:
    """Run the parsed command: float64 and the persistent compilation cache first for a
    command that computes with JAX (before its first compilation: a second run compiles
    nothing again)."""
    if COMMANDS[args.command].jax:
        import jax

        from .xla_cache import enable as enable_xla_cache

        jax.config.update("jax_enable_x64", True)
        enable_xla_cache()
        with _one_blas_thread():
            return _command(args.command)(args)
    return _command(args.command)(args)


#: the variables OpenBLAS reads its thread count from: a count the user set is left alone
BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def _one_blas_thread():
    """A command computing with JAX runs the BLAS libraries on one thread (``threadpoolctl``;
    fem_prep's builds set their own count inside, :mod:`fem_prep`'s ``blas_threads``), unless
    the user set one of :data:`BLAS_THREAD_VARIABLES`. JAX's dense solves on the CPU go through
    SciPy's OpenBLAS, which splits an LU of more than about 128 unknowns over threads that wait
    for each other busily: on the loaded 2-core host one 152 x 152 solve (a housed train's
    static contact) took 200 ms on OpenBLAS's two threads, 0.4 ms on one (docs/housing.md,
    "A two-stage train")."""
    if any(os.environ.get(name) for name in BLAS_THREAD_VARIABLES):
        return contextlib.nullcontext()
    import scipy.linalg  # noqa: F401  (loads SciPy's OpenBLAS, the one JAX's LAPACK calls use)
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1, user_api="blas")


def _equinox_runtime_error(err: BaseException) -> bool:
    """Whether ``err`` is equinox's runtime error (a failure inside compiled code); equinox is
    not imported for it (a command that never loaded it raised none)."""
    eqx = sys.modules.get("equinox")
    return eqx is not None and isinstance(err, eqx.EquinoxRuntimeError)


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
    for bar in list(module.tqdm._instances):
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


#: a value that argparse would take for an option: a range starting below zero (``-100:3000:5``)
_NEGATIVE_RANGE = re.compile(r"^-[0-9.][^:]*:")


def _glued_ranges(argv: list[str]) -> list[str]:
    """``--speeds -100:3000:5`` as ``--speeds=-100:3000:5``: argparse reads a value that begins
    with ``-`` and is not a plain number as an option (its message: "expected one argument"),
    so a range starting below zero reaches the range's own check, which names it."""
    out: list[str] = []
    for a in argv:
        if out and _NEGATIVE_RANGE.match(a) and out[-1].startswith("--") and "=" not in out[-1]:
            out[-1] = f"{out[-1]}={a}"
        else:
            out.append(a)
    return out


def main(
    argv: list[str] | None = None, load_model: Callable[[str], None] | None = None
) -> int:
    """Run the CLI; returns the exit status (0 ok, 2 bad input, 130 interrupted by Ctrl-C, 143
    by SIGTERM).

    ``load_model(command)``: called once a command that needs the model
    (:attr:`~jaxgear.cli._parser.Command.model`) has its options checked; the console script
    passes the function that loads the model package it deferred. None: the model is
    loaded already (``from jaxgear.cli import main``).

    Library warnings reach the user as one line ``jaxgear: warning: …`` on stderr.
    """
    saved = warnings.showwarning
    warnings.showwarning = _show_warning
    argv = _glued_ranges(sys.argv[1:] if argv is None else list(argv))
    try:
        with _sigterm_interrupts():
            return _main(argv, load_model)
    except KeyboardInterrupt as err:  # Ctrl-C, or SIGTERM (Terminated)
        return _interrupted(err)
    finally:
        warnings.showwarning = saved


def _interrupted(err: KeyboardInterrupt) -> int:
    """The line and exit status of a command stopped by Ctrl-C or SIGTERM (:class:`Terminated`)."""
    _close_bars()
    if isinstance(err, Terminated):
        print("\njaxgear: terminated (SIGTERM)", file=sys.stderr)
        return TERMINATED
    print("\njaxgear: interrupted", file=sys.stderr)
    return INTERRUPTED


def _main(argv: list[str], load_model) -> int:
    """:func:`main`'s body, SIGTERM an interruption (:func:`_sigterm_interrupts`)."""
    try:
        try:
            args = build_parser(command_of(argv)).parse_args(argv)
        except SystemExit as err:  # --help, --version (0), or argparse's usage error (2)
            return int(err.code or 0)
        try:
            check_options(args)  # before JAX, the model or the case file is touched
        except ValueError as err:
            return fail(str(err))
        try:
            if COMMANDS[args.command].model and load_model is not None:
                load_model(args.command)
            status = _dispatch(args)
            sys.stdout.flush()  # a closed pipe shows here, not at interpreter exit
            return status
        except (ValueError, FileNotFoundError, NotADirectoryError, PermissionError) as err:
            return fail(str(err))
        except Exception as err:
            if _equinox_runtime_error(err):
                return fail(runtime_message(err))
            raise
    except BrokenPipeError:
        # the reader went away (``jaxgear run | head``): exit quietly, no traceback
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return 0


def entry(load_model: Callable[[str], None] | None = None) -> None:  # pragma: no cover
    """The console script's body: :func:`main` on ``sys.argv``, then exit with its status."""
    status = main(None, load_model)
    if status in (INTERRUPTED, TERMINATED):
        # interrupted: XLA may still run threads of the abandoned computation, and tearing the
        # interpreter down under them can crash; the files are closed and complete, so leave now
        for stream in (sys.stdout, sys.stderr):
            try:
                stream.flush()
            except (OSError, ValueError):
                pass
        os._exit(status)
    sys.exit(status)


if __name__ == "__main__":  # pragma: no cover
    entry()
