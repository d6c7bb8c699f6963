"""Atomic file writers, output-path checks and embedded input files shared by jaxgear and fem_prep.

JAX-free (standard library only), so that ``jaxgear`` can import it by this public name.  A file
written by :func:`atomic_open` / :func:`atomic_write` appears complete or not at all; the
output-path checks raise one-line ``ValueError``s naming the option (``--out PATH: ...``).

:func:`write_json` and :func:`write_csv` are the one guard of every JSON and CSV output of both
packages' commands: a value that is NaN or infinite is written as ``null`` (JSON) or
``nan``/``inf`` (CSV) and warned about (:class:`NonFiniteOutput`, one line naming the file and
its fields, and the cause where the caller knows it). A value absent on purpose (a diverged
speed, an order outside a band) is given as ``None`` by its caller: ``null`` or an empty CSV
cell, with no warning.
"""

from __future__ import annotations

import contextlib
import csv
import functools
import io
import json
import math
import numbers
import os
import sys
import tempfile
import warnings
from collections.abc import Callable, Iterator
from pathlib import Path

from .checks import did_you_mean

__all__ = [
    "OUTPUT_MANIFEST",
    "NonFiniteOutput",
    "atomic_open",
    "atomic_write",
    "check_not_input",
    "check_output_dir",
    "check_output_file",
    "embedded_names",
    "embedded_text",
    "fem_prep_cache_dir",
    "print_or_write",
    "record_outputs",
    "recorded_outputs",
    "write_csv",
    "write_json",
    "write_new_file",
]


def fem_prep_cache_dir() -> Path:
    """fem_prep's cache directory: ``$FEM_PREP_CACHE`` or ``~/.cache/jaxgear/fem_prep``
    (``fem_prep.cache_dir``)."""
    env = os.environ.get("FEM_PREP_CACHE")
    return Path(env) if env else Path.home() / ".cache" / "jaxgear" / "fem_prep"


OUTPUT_MANIFEST = ".jaxgear-outputs"
"""The file, in an output folder, that lists what a command wrote there (one relative path a
line): its next run deletes only those files (see ``jaxgear.cli._paths.clear_outputs``)."""
_RECORDING: set[str] = set()  # absolute folders whose written files go to their manifest


def record_outputs(folder) -> None:
    """From now on, every file written under ``folder`` by :func:`atomic_open` /
    :func:`atomic_write` is listed in ``folder/.jaxgear-outputs`` (created with the first file,
    so that a run that writes nothing leaves no folder behind)."""
    _RECORDING.add(os.path.abspath(os.fspath(folder)))


def recorded_outputs(folder) -> list[str]:
    """The relative paths listed in ``folder``'s manifest (none without one)."""
    try:
        text = (Path(os.fspath(folder)) / OUTPUT_MANIFEST).read_text("utf-8")
    except (OSError, UnicodeDecodeError):
        return []
    return [line for line in text.splitlines() if line and not line.startswith("#")]


def _recording_folder(path) -> str | None:
    """The innermost recording folder (:func:`record_outputs`) that holds ``path``, if any."""
    target = os.path.abspath(path)
    holders = [f for f in _RECORDING if target.startswith(f.rstrip(os.sep) + os.sep)]
    return max(holders, key=len) if holders else None


def _check_inside(path) -> None:
    """Refuse to write ``path`` when it lies in a recording folder (an output folder,
    :func:`record_outputs`) but its own folder leads out of it through a symbolic link
    (``out/sweep -> ../elsewhere``): a command writes only inside its output folder.

    Raises:
        ValueError: one line naming the path, the link's target and the output folder.
    """
    folder = _recording_folder(path)
    if folder is None:
        return
    root = os.path.realpath(folder)
    where = os.path.dirname(os.path.abspath(path))
    real = os.path.realpath(where)
    if real != root and not real.startswith(root.rstrip(os.sep) + os.sep):
        raise ValueError(
            f"{path}: {where} leads to {real}, outside the output folder {folder}, through a "
            "symbolic link (a command writes only inside its output folder): remove the link"
        )


def _record(path: Path) -> None:
    """List a written file in the manifest of the innermost recording folder that holds it."""
    target = os.path.abspath(path)
    folder = _recording_folder(target)
    if folder is None:
        return
    rel = os.path.relpath(target, folder)
    if rel in recorded_outputs(folder):
        return
    manifest = os.path.join(folder, OUTPUT_MANIFEST)
    with contextlib.suppress(OSError):
        new = not os.path.exists(manifest)
        with open(manifest, "a", encoding="utf-8") as f:
            if new:
                f.write("# files written here by jaxgear (its next run deletes them)\n")
            f.write(rel + "\n")


@contextlib.contextmanager
def _atomic_path(path) -> Iterator[Path]:
    path = Path(os.fspath(path))
    _check_inside(path)  # before anything is made through a link out of an output folder
    directory = path.absolute().parent
    directory.mkdir(parents=True, exist_ok=True)
    fd, tmp = tempfile.mkstemp(prefix=f".tmp-{path.name}-", suffix=".tmp", dir=directory)
    os.close(fd)
    umask = os.umask(0)
    os.umask(umask)
    os.chmod(tmp, 0o666 & ~umask)  # mkstemp makes 0600; give the file the usual permissions
    try:
        yield Path(tmp)
        fd = os.open(tmp, os.O_RDONLY)
        try:
            os.fsync(fd)
        finally:
            os.close(fd)
        os.replace(tmp, path)
        _record(path)
    finally:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)


@contextlib.contextmanager
def atomic_open(path, mode: str = "w", **kwargs):
    """Open a temporary file beside ``path``; rename it onto ``path`` only if the block succeeds.

    An interrupted run never leaves a truncated ``path``: either the old file (or nothing) or the
    complete new one is there.
    """
    with _atomic_path(path) as tmp, open(tmp, mode, **kwargs) as f:
        yield f


def atomic_write(path, write: Callable[[Path], None]) -> Path:
    """Call ``write(tmp)`` on a temporary path beside ``path``, then rename it onto ``path``."""
    with _atomic_path(path) as tmp:
        write(tmp)
    return Path(path)


def check_output_dir(path, option: str = "--out") -> str:
    """Check that ``path`` can be the output folder of a command, without creating anything
    (the writers create it when the first file is written: bad input leaves no folder behind).

    Returns the path, normalised (``results/`` → ``results``: the commands print ``written to
    PATH/``).

    Raises:
        ValueError: one-line message ``{option} PATH: why`` when ``path`` is a file, lies under
            a file, or its nearest existing folder is not writable.
    """
    path = os.fspath(path)
    if os.path.exists(path) and not os.path.isdir(path):
        raise ValueError(f"{option} {path}: is a file, not a folder")
    existing = os.path.abspath(path)
    while not os.path.exists(existing):
        existing = os.path.dirname(existing)
    if not os.path.isdir(existing):
        raise ValueError(f"{option} {path}: {existing} is a file, not a folder")
    try:  # os.access alone misses read-only mounts (and root passes it everywhere)
        fd, probe = tempfile.mkstemp(prefix=".tmp-probe-", dir=existing)
        os.close(fd)
        os.unlink(probe)
    except OSError:
        where = "folder" if existing == os.path.abspath(path) else f"parent folder {existing}"
        raise ValueError(f"{option} {path}: {where} is not writable") from None
    return os.path.normpath(path)


def check_output_file(path, option: str = "--json", *, inputs=None, force: bool = False) -> str:
    """Check, before any work, that a command may write the file ``path`` (a missing folder is
    created on writing): the rule of every option that names an output file (``jaxgear run
    --json``, ``jaxgear optimise --write``, ``jaxgear cases --write``, ``fem-prep bodies
    --write``): never over an input of the run, never over an existing file unless ``force``
    (the option's ``--force``).

    Args:
        path: the file the option names.
        option: the option, as the message names it.
        inputs: {path: what it is (``"the case file"``)} of the files the run reads
            (:func:`check_not_input`); None: none.
        force: replace an existing file (never an input).

    Returns:
        ``path``.

    Raises:
        ValueError: one line ``{option} PATH: why``: a folder, an input of the run, an existing
            file without ``force``, a folder that cannot be created or written, a file that
            cannot be written.
    """
    path = os.fspath(path)
    if path.endswith(os.sep) or os.path.isdir(path):
        raise ValueError(f"{option} {path}: is a folder, expected a file name")
    check_not_input(path, option, inputs)
    if os.path.lexists(path) and not force:
        raise ValueError(f"{option} {path}: exists (add --force to replace it)")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        check_output_dir(folder, option)
    except ValueError as err:
        why = str(err).split(": ", 1)[1]
        if why.startswith("is a file"):  # the folder itself: name it (the path is a file name)
            why = f"{folder} {why}"
        raise ValueError(f"{option} {path}: {why}") from None
    if os.path.exists(path) and not os.access(path, os.W_OK):
        raise ValueError(f"{option} {path}: file is not writable")
    return path


def check_not_input(path, option: str, inputs) -> None:
    """Refuse an output ``path`` that is one of the run's ``inputs`` ({path: what it is}): the
    same file (links and other spellings of it followed), with or without ``--force``.

    Raises:
        ValueError: one line ``{option} PATH: is WHAT of this run (INPUT), which it reads:
            choose another file``.
    """
    if not inputs or not os.path.exists(path):
        return
    for source, what in inputs.items():
        with contextlib.suppress(OSError):
            if os.path.samefile(path, source):
                raise ValueError(
                    f"{option} {path}: is {what} of this run ({source}), which it reads: "
                    "choose another file"
                )


def write_new_file(path, text: str, *, force: bool = False, option: str = "--write") -> Path:
    """Write ``text`` to ``path`` atomically, refusing to replace a file unless ``force``
    (``jaxgear cases NAME --write FILE``, ``fem-prep bodies NAME --write FILE``).

    Raises:
        ValueError: one line ``{option} PATH: why``: a folder, an existing file without
            ``force``, or a folder that cannot be written.
    """
    path = os.fspath(path)
    check_output_file(path, option, force=force)
    with atomic_open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return Path(path)


# --------------------------------------------------------------------------------------------
# embedded input files (jaxgear's cases, fem_prep's bodies)


def embedded_names(folder) -> list[str]:
    """Names of the ``*.toml`` files in a package folder (``importlib.resources`` traversable)."""
    return sorted(p.name[:-5] for p in folder.iterdir() if p.name.endswith(".toml"))


def embedded_text(folder, name: str, kind: str) -> str:
    """The text of the embedded ``kind`` file ``name`` (``folder/name.toml``).

    Raises:
        FileNotFoundError: ``name`` is not one of them (the message lists them).
    """
    names = embedded_names(folder)
    if name not in names:
        kinds = kind[:-1] + "ies" if kind.endswith("y") else kind + "s"
        raise FileNotFoundError(
            f"no embedded {kind} {name!r}{did_you_mean(name, names)} (embedded {kinds}: "
            f"{', '.join(names)})"
        )
    return (folder / f"{name}.toml").read_text("utf-8")


def print_or_write(text: str, write, *, force: bool, what: str, next_command: str) -> None:
    """``text`` to stdout, or with ``write`` (a path) to a new file (:func:`write_new_file`),
    saying ``wrote PATH (what; next_command PATH)``."""
    if write is None:
        sys.stdout.write(text)
        return
    path = write_new_file(write, text, force=force)
    print(f"wrote {path} ({what}; {next_command} {path})")


# --------------------------------------------------------------------------------------------
# JSON and CSV: the guard against silent NaN and infinity

#: the fields a warning names before it counts the rest
_SHOWN = 4


class NonFiniteOutput(UserWarning):
    """An output file holds NaN or infinite values: the message names the file, its fields
    (JSON: ``rating.S_H``, an array's entries as ``levels_dB[]`` with their count; CSV: the
    columns) and, where the writer's caller knows it, the input that caused them."""


def _warn_non_finite(path, fields: dict[str, int], cause: str | None) -> None:
    if not fields:
        return
    shown = [f"{k} ({n} entries)" if n > 1 else k for k, n in list(fields.items())[:_SHOWN]]
    more = f" and {len(fields) - _SHOWN} more fields" if len(fields) > _SHOWN else ""
    why = f": {cause}" if cause else ""
    warnings.warn(
        f"{os.path.basename(os.fspath(path))}: NaN or infinite values in {', '.join(shown)}"
        f"{more}{why}",
        NonFiniteOutput,
        stacklevel=3,
    )


def write_json(path, data, *, cause: str | None = None) -> None:
    """Write ``data`` as indented JSON to ``path`` atomically (NumPy scalars as Python numbers).
    NaN and ±inf are written as null with a :class:`NonFiniteOutput` warning naming their
    fields (``cause``: the input that made them, when the caller knows it); ``None`` is null
    without one."""
    fields: dict[str, int] = {}
    text = json.dumps(_finite_or_none(data, "", fields), indent=2, allow_nan=False)
    with atomic_open(path, "w") as f:
        f.write(text)
    _warn_non_finite(path, fields, cause)


@functools.singledispatch
def _finite_or_none(v, where: str, fields: dict):
    """``v`` with every non-finite number, at any depth of its dicts, lists and tuples, as None,
    each one's field (array entries as ``name[]``) counted in ``fields``; NumPy scalars (real
    numbers by ``numbers.Real``) as Python numbers."""
    return v


@_finite_or_none.register(bool)
@_finite_or_none.register(int)
def _int_as_is(v, where: str, fields: dict):
    return v


@_finite_or_none.register(numbers.Integral)
def _integral(v, where: str, fields: dict):
    return int(v)


@_finite_or_none.register(numbers.Real)
def _real(v, where: str, fields: dict):
    v = float(v)
    if math.isfinite(v):
        return v
    key = where or "the value"
    fields[key] = fields.get(key, 0) + 1
    return None


@_finite_or_none.register(dict)
def _dict(v, where: str, fields: dict):
    return {
        k: _finite_or_none(x, f"{where}.{k}" if where else str(k), fields) for k, x in v.items()
    }


@_finite_or_none.register(list)
@_finite_or_none.register(tuple)
def _list(v, where: str, fields: dict):
    return [_finite_or_none(x, f"{where}[]", fields) for x in v]


def write_csv(path, header, columns, *, cause: str | None = None) -> None:
    """Write columns (equal-length sequences of numbers) under ``header`` to ``path`` atomically,
    12 significant digits; ``None`` (no value) as an empty cell, a text (a name) as itself.
    NaN and ±inf are written as ``nan``/``inf`` with a :class:`NonFiniteOutput` warning naming
    their columns (``cause`` as :func:`write_json`)."""
    buf = io.StringIO()
    w = csv.writer(buf)
    w.writerow(header)
    fields: dict[str, int] = {}
    for row in zip(*columns):
        for name, v in zip(header, row):
            if v is not None and not isinstance(v, str) and not math.isfinite(v):
                fields[name] = fields.get(name, 0) + 1
        w.writerow(["" if v is None else v if isinstance(v, str) else f"{v:.12g}"
                    for v in row])
    with atomic_open(path, "w", newline="") as f:
        f.write(buf.getvalue())
    _warn_non_finite(path, fields, cause)
