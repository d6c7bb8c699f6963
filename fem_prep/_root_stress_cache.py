"""The fillet influence tables of :func:`fem_prep.fillet_influence` through fem_prep's disk
cache (:func:`cached_fillet_influence`; the mechanism, shared with the tooth compliance tables:
:mod:`fem_prep._fe_cache`).

The key holds every input of the table: the tooth (its class and every field, the cutter of an
internal tooth among them), the load radii (sorted, exact), the element size, the rim radius,
the teeth modelled, Poisson's ratio, the fillet form, the section and the rim support (each its
class and fields; ``None`` as given, so ``size=None`` and the equal explicit size are two
entries), the module defaults these fill in (m_n/18, the 3.5 m_n rim), the format version
:data:`FILLET_FE_VERSION` and the mesher's :data:`TOOTH_FE_VERSION`.

NumPy only (the FE solve is :mod:`fem_prep._root_stress`'s).
"""

from __future__ import annotations

import dataclasses
import functools
import inspect
import json
import numbers
from typing import Any

import numpy as np

from ._fe_cache import cache_key, load_entry, store_entry, table_dir
from ._root_stress import (
    DEFAULT_ELEMENTS_PER_MODULE,
    DEFAULT_RIM_DEPTH,
    FILLET_FE_VERSION,
    FilletInfluence,
    fillet_influence,
)
from ._tooth_fe import TOOTH_FE_VERSION

__all__ = ["cached_fillet_influence", "fillet_cache_dir"]

_SIGNATURE = inspect.signature(fillet_influence)
_NOT_STORED = ("cache_hit", "key")  # the FilletInfluence fields that describe the lookup


def fillet_cache_dir():
    """``fem_prep.cache_dir() / "fillet_influence"``: one ``<key>.npz`` a table."""
    return table_dir("fillet_influence")


@functools.singledispatch
def _plain(value) -> Any:
    """The JSON image of one input of the key: an object as its class name and, for a
    dataclass, every field (recursively); the registered types below as themselves.

    Raises:
        TypeError: an object that is neither a dataclass nor has a ``__dict__``."""
    names = [f.name for f in dataclasses.fields(value)] if dataclasses.is_dataclass(value) else []
    names = names or sorted(vars(value))
    return {"class": type(value).__qualname__, **{n: _plain(getattr(value, n)) for n in names}}


@_plain.register(type(None))
@_plain.register(bool)
@_plain.register(str)
def _(value) -> Any:
    return value


@_plain.register(numbers.Integral)
def _(value) -> Any:
    return int(value)


@_plain.register(numbers.Real)
def _(value) -> Any:
    return float(value)  # written by repr: exact


@_plain.register(np.ndarray)
def _(value) -> Any:
    return _plain(value.tolist())  # Python floats: exact


@_plain.register(list)
@_plain.register(tuple)
def _(value) -> Any:
    return [_plain(v) for v in value]


def _inputs(geometry, load_radii, options: dict) -> dict:
    """Every input of the table (the module docstring), JSON-ready.

    Raises:
        TypeError: an argument :func:`fillet_influence` does not take, or one the key cannot
            hold."""
    bound = _SIGNATURE.bind(geometry, load_radii, **options)
    bound.apply_defaults()
    args = dict(bound.arguments)
    args["load_radii"] = np.sort(np.atleast_1d(np.asarray(load_radii, dtype=float)))
    return {
        "version": FILLET_FE_VERSION,
        "mesh_version": TOOTH_FE_VERSION,
        "defaults": [DEFAULT_ELEMENTS_PER_MODULE, DEFAULT_RIM_DEPTH],
        **{name: _plain(value) for name, value in args.items()},
    }


def _entry(table: FilletInfluence, key: str, inputs: dict) -> dict:
    """The arrays of a table's cache file: its array fields as ``array_<name>``, the others
    (numbers, strings, None) in the JSON text ``fields``."""
    values = {
        f.name: getattr(table, f.name)
        for f in dataclasses.fields(table)
        if f.name not in _NOT_STORED
    }
    arrays = {f"array_{n}": v for n, v in values.items() if np.ndim(v)}
    return {
        "format_version": np.array(FILLET_FE_VERSION),
        "key": np.array(key),
        "inputs": np.array(json.dumps(inputs, sort_keys=True)),
        "fields": np.array(json.dumps({n: _plain(v) for n, v in values.items() if not np.ndim(v)})),
        **arrays,
    }


def _table(data: dict, key: str) -> FilletInfluence:
    """The table of a cache file's arrays (``KeyError``/``TypeError``/``ValueError``: not a
    whole table)."""
    arrays = {n[len("array_") :]: v for n, v in data.items() if n.startswith("array_")}
    return FilletInfluence(**json.loads(str(data["fields"])), **arrays, cache_hit=True, key=key)


def cached_fillet_influence(geometry, load_radii, **options) -> FilletInfluence:
    """:func:`fem_prep.fillet_influence` (the same arguments), read from fem_prep's disk cache
    when the same table was solved before, else solved and written there.

    The cache: ``fillet_cache_dir() / "<key>.npz"`` under ``$FEM_PREP_CACHE`` (default
    ``~/.cache/jaxgear/fem_prep``), keyed by every input (module docstring), written atomically
    (concurrent runs leave one whole file); a truncated, corrupt or stale file is solved again
    and replaced (docs/fem_prep.md, "The FE table cache"). A table read back equals the solved
    one bit for bit; a cache folder that cannot be written is a ``UserWarning``.

    Returns:
        The :class:`FilletInfluence`, with ``cache_hit`` (read from the cache) and ``key``.

    Raises:
        ValueError: as :func:`fem_prep.fillet_influence` (checked when the table is solved: a
            bad input is never in the cache). TypeError: an unknown argument.
    """
    try:
        inputs = _inputs(geometry, load_radii, options)
    except TypeError:  # not a key: fillet_influence names what is wrong with its arguments
        return fillet_influence(geometry, load_radii, **options)
    key = cache_key(inputs)
    path = fillet_cache_dir() / f"{key}.npz"
    data = load_entry(path, key, FILLET_FE_VERSION, inputs)
    if data is not None:
        try:
            return _table(data, key)
        except (KeyError, TypeError, ValueError):  # not a whole table: solved again
            pass
    table = dataclasses.replace(fillet_influence(geometry, load_radii, **options), key=key)
    store_entry(path, _entry(table, key, inputs))
    return table
