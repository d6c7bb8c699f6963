"""The ``jaxgear`` console script (``jaxgear = "jaxgear_start:entry"``): the command line parsed
before the model is loaded.

Importing anything under ``jaxgear`` runs the package's ``__init__`` first, and that imports
the whole model API with JAX and equinox (seconds; tens of seconds on a loaded machine). This
module, outside the package, registers the package ``jaxgear`` found but not yet executed, so
that the command line (:mod:`jaxgear.cli._start`, which imports no model module) can parse and
check the options, answer ``--help``, ``--version`` and ``jaxgear cases`` at once, and execute
the package's ``__init__`` only when a command needs the model. ``from jaxgear.cli import
entry`` (the model loaded as usual) runs the same command line.

OpenBLAS runs single-threaded in the command (``OPENBLAS_NUM_THREADS=1``, set before numpy or
SciPy load it, unless ``OPENBLAS_NUM_THREADS``, ``GOTO_NUM_THREADS`` or ``OMP_NUM_THREADS`` is
set): JAX's dense solves on the CPU go through SciPy's OpenBLAS, which splits an LU of more
than about 128 unknowns over threads that wait for each other busily; on a loaded machine one
152 x 152 solve took 200 ms so, 0.4 ms single-threaded (a housed scene's static contact solves
and the whine balance's systems; docs/housing.md, "Run time").
"""

from __future__ import annotations

import importlib.util
import os
import sys

__all__ = ["entry"]

#: the variables OpenBLAS reads its thread count from, in its order
BLAS_THREADS = ("OPENBLAS_NUM_THREADS", "GOTO_NUM_THREADS", "OMP_NUM_THREADS")


def single_threaded_blas() -> None:
    """``OPENBLAS_NUM_THREADS=1`` unless one of :data:`BLAS_THREADS` is set (see the module);
    takes effect where OpenBLAS is not loaded yet."""
    if not any(os.environ.get(name) for name in BLAS_THREADS):
        os.environ["OPENBLAS_NUM_THREADS"] = "1"


def entry() -> None:  # pragma: no cover - console-script wrapper (run in a subprocess)
    """Run ``jaxgear`` on ``sys.argv`` with the model package deferred (see the module)."""
    single_threaded_blas()  # before numpy and SciPy load OpenBLAS (see the module)
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
