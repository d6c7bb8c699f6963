"""fem_prep's disk cache of plane FE tables: one mechanism for the tooth compliance tables of
:func:`fem_prep.tooth_compliance` (``cache_dir()/tooth_fe``) and the fillet influence tables of
:func:`fem_prep.cached_fillet_influence` (``cache_dir()/fillet_influence``).

An entry is one ``.npz`` file ``<kind>/<key>.npz`` under :func:`fem_prep.cache_dir`
(``$FEM_PREP_CACHE`` or ``~/.cache/jaxgear/fem_prep``). ``key`` is the first 32 hex digits of
the sha256 of the JSON text of every input that changes the result (sorted keys; floats written
by ``repr``, so exactly) with the table's format version among them. The file holds the
table's arrays, ``key``, ``format_version`` and ``inputs`` (that JSON text).

Writes are atomic (:func:`fem_prep.files.atomic_open`: a temporary file in the same folder,
flushed to disk, then ``os.replace``): a reader finds the old file, none, or the whole new one;
two processes that write the same key each rename a complete file of the same table, and one of
them stays. A read takes every array (the zip member's CRC-32 is checked as it is read) and
trusts the entry only if its key, format version and inputs are the ones asked for: a
truncated, corrupt or stale file is ignored, recomputed and replaced. A cache that cannot be
written (a read-only folder, a full disk) costs a warning, never the result.

NumPy and the standard library only.
"""

from __future__ import annotations

import hashlib
import json
import warnings
import zipfile
from pathlib import Path

import numpy as np

from .files import atomic_open, fem_prep_cache_dir

__all__ = ["cache_key", "load_entry", "store_entry", "table_dir"]


def table_dir(kind: str) -> Path:
    """The folder of one kind of table: ``fem_prep.cache_dir() / kind``."""
    return fem_prep_cache_dir() / kind


def cache_key(inputs: dict) -> str:
    """32 hex digits of the sha256 of ``json.dumps(inputs, sort_keys=True)``.

    Raises:
        TypeError: a value JSON cannot write (the caller converts its inputs first)."""
    text = json.dumps(inputs, sort_keys=True)
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def load_entry(path: Path, key: str, version: int, inputs: dict | None = None) -> dict | None:
    """The arrays of the entry at ``path`` (a dict of NumPy arrays, every one read), or ``None``
    when there is none or it is not to be trusted: unreadable, truncated, a failed CRC, another
    key, another ``version``, or (given ``inputs``) other inputs."""
    try:
        with open(path, "rb") as fh, np.load(fh, allow_pickle=False) as z:
            data = {k: z[k] for k in z.files}
        if str(data["key"]) != key or int(data["format_version"]) != version:
            return None
        if inputs is not None and str(data["inputs"]) != json.dumps(inputs, sort_keys=True):
            return None
        return data
    except (OSError, ValueError, KeyError, EOFError, TypeError, zipfile.BadZipFile):
        return None


def store_entry(path: Path, data: dict) -> bool:
    """Write ``data`` (name → array) to ``path`` atomically (the folder made if missing).

    Returns:
        Whether it was written; an ``OSError`` (read-only folder, full disk) is a
        ``UserWarning`` naming the path, and the caller goes on with its result."""
    try:
        with atomic_open(path, "wb") as fh:
            np.savez(fh, **data)
    except OSError as e:
        warnings.warn(f"fem_prep cache: {path} not written ({e})", stacklevel=3)
        return False
    return True
