"""Small shared helpers (array conversion, atomic file output)."""

from __future__ import annotations

import contextlib
import os
import tempfile

import jax.numpy as jnp

__all__ = ["as_float", "atomic_open"]


def as_float(v):
    """Convert to a JAX array of the default float dtype (float64 with x64 on, else float32)."""
    return jnp.asarray(v, dtype=jnp.result_type(float))


@contextlib.contextmanager
def atomic_open(path, mode: str = "w", **kwargs):
    """Open a temporary file beside ``path``; rename it onto ``path`` only if the block succeeds.

    An interrupted run never leaves a truncated ``path``: either the old file (or nothing) or the
    complete new one is there.
    """
    path = os.fspath(path)
    directory = os.path.dirname(os.path.abspath(path))
    os.makedirs(directory, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=".tmp-" + os.path.basename(path) + "-", dir=directory)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file the usual permissions
    try:
        with os.fdopen(fd, mode, **kwargs) as f:
            yield f
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, path)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise
