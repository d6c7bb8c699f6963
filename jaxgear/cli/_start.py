"""The console script's command line (``jaxgear``, through :mod:`jaxgear_start`, which defers
the model package): parsed and checked first, then, for a command that needs the model, one
line ``jaxgear COMMAND: starting (loading and compiling)...`` on stderr before the model (JAX,
equinox, the optimisers) is loaded and the command compiles, which together take seconds;
:func:`jaxgear.cli._main.main` runs it.

``jaxgear --help``, ``--version``, every subcommand's ``--help`` and ``jaxgear cases`` load
neither the model nor JAX.
"""

from __future__ import annotations

import sys
from collections.abc import Callable

from ._parser import COMMANDS

__all__ = ["entry"]

#: options after which the command prints nothing of its own: help, or no progress output
_SILENT = frozenset({"-h", "--help", "--quiet"})


def entry(load_model: Callable[[], None] | None = None) -> None:  # pragma: no cover
    """``jaxgear [COMMAND] ...``: the command line of ``sys.argv``, its exit status as
    :func:`jaxgear.cli.main`'s. ``load_model``: loads the model package the console script
    deferred (None: it is loaded), called once, when a command needs it; for a command that
    computes with JAX (every one but ``prep`` and ``cases``) the start line comes first,
    unless ``--help`` or ``--quiet`` is given."""
    argv = sys.argv[1:]

    def load(command: str) -> None:
        if COMMANDS[command].jax and not _SILENT & set(argv):
            print(
                f"jaxgear {command}: starting (loading and compiling)...",
                file=sys.stderr,
                flush=True,
            )
        if load_model is not None:
            load_model()

    from ._main import entry as run

    run(load)
