"""Atomic file output: every file appears complete or not at all (temporary file, then rename)."""

from __future__ import annotations

import contextlib
import csv
import io
import json
import os
import tempfile

__all__ = ["atomic_open", "write_csv", "write_json"]


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


def write_json(path, data) -> None:
    """Write ``data`` as indented JSON to ``path`` atomically (NaN is written as null)."""
    text = json.dumps(_nan_to_none(data), indent=2)
    with atomic_open(path, "w") as f:
        f.write(text)


def _nan_to_none(v):
    if isinstance(v, float) and v != v:
        return None
    if isinstance(v, dict):
        return {k: _nan_to_none(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_nan_to_none(x) for x in v]
    return v


def write_csv(path, header, columns) -> None:
    """Write columns (equal-length sequences of numbers) under ``header`` to ``path`` atomically,
    12 significant digits."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    for row in zip(*columns):
        w.writerow([f"{v:.12g}" for v in row])
    with atomic_open(path, "w", newline="") as f:
        f.write(buf.getvalue())
