"""The ``jaxgear`` console script (``jaxgear = "jaxgear_start:entry"``): the command line parsed
before the model is loaded.

Importing anything under ``jaxgear`` runs the package's ``__init__`` first, and that imports
the whole model API with JAX and equinox (seconds; tens of seconds on a loaded machine). This
module, outside the package, registers the package ``jaxgear`` found but not yet executed, so
that the command line (:mod:`jaxgear.cli._start`, which imports no model module) can parse and
check the options, answer ``--help``, ``--version`` and ``jaxgear cases`` at once, and execute
the package's ``__init__`` only when a command needs the model. ``from jaxgear.cli import
entry`` (the model loaded as usual) runs the same command line.
"""

from __future__ import annotations

import importlib.util
import sys

__all__ = ["entry"]


def entry() -> None:  # pragma: no cover - console-script wrapper (run in a subprocess)
    """Run ``jaxgear`` on ``sys.argv`` with the model package deferred (see the module)."""
    if "jaxgear" in sys.modules:  # the model is loaded already: nothing to defer
        from jaxgear.cli._start import entry as start

        start()
        return
    spec = importlib.util.find_spec("jaxgear")
    package = importlib.util.module_from_spec(spec)
    sys.modules["jaxgear"] = package  # its submodules import; its own code waits
    loaded = []

    def load_model() -> None:
        if not loaded:
            loaded.append(True)
            spec.loader.exec_module(package)

    from jaxgear.cli._start import entry as start

    start(load_model)


if __name__ == "__main__":  # pragma: no cover
    entry()
