"""The console script ``jaxgear`` (``jaxgear = "jaxgear.cli:entry"``): a command that computes
says so on stderr before the command line's own imports (the option checks' ``fem_prep``, the
optimisers and :mod:`jaxgear.io` behind the parser's optimise options, the command's module and
matplotlib) and its first compilation, which together take seconds; then
:func:`jaxgear.cli._main.entry` runs it.

Only the model itself (``import jaxgear``: JAX and equinox) is loaded before this line: the
console script imports this package, and Python imports the parent package first.
"""

from __future__ import annotations

import sys

from ._parser import COMMANDS

__all__ = ["entry"]

#: options after which the command prints nothing of its own: help, or no progress output
_SILENT = frozenset({"-h", "--help", "--quiet"})


def entry() -> None:  # pragma: no cover - console-script wrapper (run in a subprocess)
    """``jaxgear [COMMAND] ...``: for a command that computes with JAX (every one but ``prep``)
    one line ``jaxgear COMMAND: starting...`` on stderr, unless ``--help`` or ``--quiet`` is
    given; then the command (exit status as :func:`jaxgear.cli.main`)."""
    argv = sys.argv[1:]
    command = COMMANDS.get(argv[0]) if argv else None
    if command is not None and command.jax and not _SILENT & set(argv):
        print(f"jaxgear {argv[0]}: starting (loading and compiling)...", file=sys.stderr,
              flush=True)
    from ._main import entry as run

    run()
