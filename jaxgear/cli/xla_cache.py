"""JAX's persistent compilation cache, switched on by the CLI: a second run reads back the XLA
programs the first one compiled instead of compiling them again.

Where (first that applies):

* ``$JAXGEAR_XLA_CACHE``: a folder; ``off`` (or ``0``, ``no``, ``false``, ``none``, empty)
  switches the cache off;
* ``$JAX_COMPILATION_CACHE_DIR`` (or a ``jax_compilation_cache_dir`` set in this process before
  :func:`enable` is called): JAX's own setting, kept;
* ``$XDG_CACHE_HOME/jaxgear/xla``, else ``~/.cache/jaxgear/xla`` (next to fem_prep's
  ``~/.cache/jaxgear/fem_prep``).

Every program is written (:data:`MIN_COMPILE_SECS` = 0: JAX's default, 1 s, and the 0.2 s used
before, left most of a run's programs out, about 100 of the default case's 108, compiled again
by every run); ``$JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS`` changes it.
The folder is kept under ``$JAXGEAR_XLA_CACHE_MAX_MB`` megabytes (default
:data:`DEFAULT_MAX_MB`): when a run starts over the bound, the least recently used entries are
removed until it is under 3/4 of it. (JAX's own bound, ``jax_compilation_cache_max_size``,
needs the ``filelock`` package, not a dependency of jaxgear; when a user sets it, JAX bounds the
folder as well.)

JAX's cache key holds the program, its argument shapes and dtypes, the compile options, the
backend and the jax/jaxlib versions: a float32 program never reads a float64 entry, and an
upgrade of JAX starts afresh (old entries age out by the bound).
"""

from __future__ import annotations

import os
from pathlib import Path

__all__ = [
    "DEFAULT_MAX_MB",
    "MIN_COMPILE_SECS",
    "cache_folder",
    "default_folder",
    "enable",
    "max_bytes",
    "trim",
]

DEFAULT_MAX_MB = 2048
"""The cache folder's default bound, MB (``$JAXGEAR_XLA_CACHE_MAX_MB``)."""

MIN_COMPILE_SECS = 0.0
"""The compile time (s) from which a program is written to the cache: 0, every program (JAX's
default: 1 s). The folder stays bounded by :func:`trim`."""

_OFF = ("", "off", "0", "no", "false", "none")
_ENTRY_SUFFIX = "-cache"  # JAX's file cache: <key>-cache (and <key>-atime when JAX bounds it)


def default_folder() -> Path:
    """``$XDG_CACHE_HOME/jaxgear/xla`` (an absolute ``XDG_CACHE_HOME``), else
    ``~/.cache/jaxgear/xla``."""
    xdg = os.environ.get("XDG_CACHE_HOME")
    base = Path(xdg) if xdg and Path(xdg).is_absolute() else Path.home() / ".cache"
    return base / "jaxgear" / "xla"


def cache_folder() -> Path | None:
    """The folder the CLI caches compiled programs in, or None when the cache is off
    (``JAXGEAR_XLA_CACHE=off``)."""
    import jax  # here, not at the top: the command line imports this module before JAX

    own = os.environ.get("JAXGEAR_XLA_CACHE")
    if own is not None:
        if own.strip().lower() in _OFF:
            return None
        return Path(own).expanduser()
    theirs = jax.config.values.get("jax_compilation_cache_dir") or os.environ.get(
        "JAX_COMPILATION_CACHE_DIR"
    )
    if theirs:
        return Path(theirs).expanduser()
    return default_folder()


def max_bytes() -> int:
    """The folder's bound in bytes: ``$JAXGEAR_XLA_CACHE_MAX_MB`` (a positive number) or
    :data:`DEFAULT_MAX_MB`; ValueError on anything else."""
    text = os.environ.get("JAXGEAR_XLA_CACHE_MAX_MB")
    if text is None or not text.strip():
        return DEFAULT_MAX_MB * 2**20
    try:
        mb = float(text)
    except ValueError:
        mb = float("nan")
    if not mb > 0 or mb == float("inf"):
        raise ValueError(
            f"JAXGEAR_XLA_CACHE_MAX_MB = {text!r}: expected a positive number of megabytes"
        )
    return int(mb * 2**20)


def trim(folder: Path, limit: int) -> int:
    """Remove the least recently used cache entries of ``folder`` (by access, else modification
    time) while it holds more than ``limit`` bytes, down to 3/4 of it; return the bytes
    removed. Entries another process removes meanwhile are skipped."""
    entries = []
    total = 0
    try:
        listing = list(folder.iterdir())
    except OSError:
        return 0
    for path in listing:
        if not path.name.endswith(_ENTRY_SUFFIX):
            continue
        try:
            st = path.stat()
        except OSError:
            continue
        entries.append((max(st.st_atime, st.st_mtime), st.st_size, path))
        total += st.st_size
    if total <= limit:
        return 0
    entries.sort()
    target = limit * 3 // 4
    removed = 0
    for _, size, path in entries:
        if total - removed <= target:
            break
        try:
            path.unlink()
            path.with_name(path.name[: -len(_ENTRY_SUFFIX)] + "-atime").unlink(missing_ok=True)
        except OSError:
            continue
        removed += size
    return removed


def enable() -> Path | None:
    """Switch JAX's persistent compilation cache on for this process (before its first
    compilation: JAX looks at the setting once): the folder of :func:`cache_folder`, trimmed to
    :func:`max_bytes`, and the :data:`MIN_COMPILE_SECS` threshold unless
    ``$JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS`` is set. ``JAXGEAR_XLA_CACHE=off`` switches
    it off. Returns the folder (None when off); a setting already in force is left as it is."""
    import jax  # here, not at the top: the command line imports this module before JAX

    limit = max_bytes()  # a bad bound is an input error, before anything else
    folder = cache_folder()
    if folder is None:
        if jax.config.values.get("jax_enable_compilation_cache", True):
            jax.config.update("jax_enable_compilation_cache", False)
        return None
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as err:
        raise ValueError(
            f"XLA compilation cache folder {str(folder)!r} cannot be created ({err.strerror}); "
            "set JAXGEAR_XLA_CACHE to another folder, or to 'off'"
        ) from None
    trim(folder, limit)
    if jax.config.values.get("jax_compilation_cache_dir") != str(folder):
        jax.config.update("jax_compilation_cache_dir", str(folder))
    if "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS" not in os.environ:
        jax.config.update("jax_persistent_cache_min_compile_time_secs", MIN_COMPILE_SECS)
    return folder
