"""A sizing at scale: the candidates' chunks spread over the devices of this process and,
under ``jax.distributed``, over every process's devices, each device rating whole chunks with
the one compiled single-device program, the results gathered on every process; and a resumable
results store, one file per finished chunk, that a rerun of the same sizing skips.

Every chunk is rated by the same compiled program (one device, ``chunk`` candidates) whatever
the number of devices or processes, so a candidate's numbers are the same bits on one device,
on several, on several processes, and read back from the store. (A program partitioned over a
device mesh, ``shard_map``, is compiled otherwise: its numbers differ from the one-device
program's in the last bits, up to about 1e-14 relative in S_F.)"""

from __future__ import annotations

import hashlib
import os
import re
from collections.abc import Callable
from importlib import metadata

import equinox as eqx
import jax
import numpy as np
from jax.experimental import multihost_utils

from fem_prep.files import atomic_open

from .._sharding import gathered

__all__ = ["ChunkStore", "rate_chunks", "sizing_digest"]

#: the layout of a store's chunk files (a change of it makes older stores another sizing's)
STORE_FORMAT = 1
_CHUNK = re.compile(r"chunk_(\d+)\.npz")
_TEMPORARY = ".tmp-chunk_"  # fem_prep.files.atomic_open's temporary files of the chunk files
#: under ``jax.distributed``, the candidates a process rates between two gathers of the results
GATHER = 1 << 16


def _jaxgear_version() -> str:
    try:
        return metadata.version("jaxgear")
    except metadata.PackageNotFoundError:  # pragma: no cover - a source tree not installed
        return "0+unknown"


def sizing_digest(chunk: int, names: tuple, static: tuple, tree, fields: dict) -> str:
    """The SHA-256 (hex) of everything a store's chunk results depend on: the store's format,
    jaxgear's version, the chunk size, the output and check ``names``, the program's ``static``
    values (``repr``), the structure and every array of ``tree`` (the settings and operating
    point) and the candidates' ``fields`` (name → (n,) array), bytes with dtype and shape."""
    h = hashlib.sha256()
    h.update(f"jaxgear sizing store {STORE_FORMAT} {_jaxgear_version()} chunk {chunk}\n"
             f"{names!r}\n{static!r}\n".encode())
    leaves, treedef = jax.tree_util.tree_flatten(tree)
    h.update(str(treedef).encode())
    for a in [*leaves, *(fields[k] for k in sorted(fields))]:
        a = np.asarray(a)
        h.update(f"\n{a.dtype.str}{a.shape}\n".encode())
        h.update(np.ascontiguousarray(a).tobytes())
    return h.hexdigest()


class ChunkStore:
    """The results store of one sizing in a folder: ``chunk_000000.npz``, … one per finished
    chunk (k: the candidates k·chunk … min((k+1)·chunk, n) − 1), each written atomically (a
    temporary file renamed: an interrupted run leaves complete chunk files only) with the
    sizing's digest (:func:`sizing_digest`), its first and last row, its outputs and checks.

    Attributes:
        folder: the store's folder (made when the first chunk is written).
        digest: the sizing's digest. n: its candidates. chunk: candidates per chunk.
    """

    def __init__(self, folder, digest: str, n: int, chunk: int):
        self.folder, self.digest, self.n, self.chunk = os.fspath(folder), digest, n, chunk

    def path(self, k: int) -> str:
        """Chunk ``k``'s file."""
        return os.path.join(self.folder, f"chunk_{k:06d}.npz")

    def _files(self) -> list[tuple[int, str]]:
        if not os.path.isdir(self.folder):
            return []
        out = []
        for name in sorted(os.listdir(self.folder)):
            m = _CHUNK.fullmatch(name)
            if m:
                out.append((int(m[1]), name))
        return out

    def clear(self) -> None:
        """Delete the store's chunk files (and temporary files a killed run left)."""
        for _, name in self._files():
            os.unlink(os.path.join(self.folder, name))
        self._remove_temporary()

    def _remove_temporary(self) -> None:
        if os.path.isdir(self.folder):
            for name in os.listdir(self.folder):
                if name.startswith(_TEMPORARY):
                    os.unlink(os.path.join(self.folder, name))

    def load(self) -> dict[int, tuple[np.ndarray, np.ndarray]]:
        """The finished chunks: k → (outputs, checks) of its rows; a killed run's temporary
        files removed.

        Raises:
            ValueError: one line naming the store and the file: a chunk of another sizing
                (another spec, chunk size or jaxgear version) or a file that is not one of
                this sizing's chunks.
        """
        self._remove_temporary()
        done = {}
        for k, name in self._files():
            path = os.path.join(self.folder, name)
            try:
                with np.load(path, allow_pickle=False) as z:
                    digest, rows = str(z["digest"]), (int(z["start"]), int(z["stop"]))
                    outs, checks = z["outputs"], z["checks"]
            except (OSError, KeyError, ValueError):
                digest = None
            if digest != self.digest:
                raise ValueError(
                    f"store {self.folder}: {name} is another sizing's (its spec, chunk size or "
                    "jaxgear version differ): allowed this sizing's chunks only (start afresh: "
                    "jaxgear size --force, or another --out)")
            want = _rows(k, self.chunk, self.n)
            if rows != want or outs.shape[0] != want[1] - want[0] or checks.shape[0] != outs.shape[0]:
                raise ValueError(
                    f"store {self.folder}: {name} holds rows {rows[0]} … {rows[1] - 1}, allowed "
                    f"chunk {k}'s rows {want[0]} … {want[1] - 1} (start afresh: jaxgear size "
                    "--force, or another --out)")
            done[k] = (outs, checks)
        return done

    def write(self, k: int, outs: np.ndarray, checks: np.ndarray) -> None:
        """Chunk ``k``'s results, atomically."""
        start = k * self.chunk
        with atomic_open(self.path(k), "wb") as f:
            np.savez(f, digest=np.asarray(self.digest), start=np.asarray(start),
                     stop=np.asarray(start + outs.shape[0]), outputs=outs, checks=checks)


#: the compiled per-chunk program: ``local(static, *args, batch)`` on the device of its inputs
_program = eqx.filter_jit(lambda local, static, args, batch: local(static, *args, batch))


def _local_devices(devices) -> list:
    """This process's devices to rate on (``devices``: among them, default all), the same
    count on every process (``jax.distributed``)."""
    mine = jax.local_devices()
    chosen = mine if devices is None else [d for d in devices if d in mine]
    if not chosen:
        raise ValueError(f"devices = {devices!r}: none of this process's ({mine!r}): allowed "
                         "some of jax.local_devices()")
    if jax.process_count() > 1:
        counts = gathered(np.asarray([len(chosen)]))
        if np.any(counts != counts[0]):
            raise ValueError(f"devices: {counts.tolist()} per process, allowed the same count "
                             "on every process")
    return chosen


def _rows(k: int, chunk: int, n: int) -> tuple[int, int]:
    """Chunk ``k``'s first row and the row after its last."""
    return k * chunk, min((k + 1) * chunk, n)


def _agreed_store(store: ChunkStore | None, restart: bool, n: int, chunk: int, widths):
    """The finished chunks (k → (outputs, checks)), read by process 0 and given to every
    process (``jax.distributed``: the other processes need not see the store's folder); a
    refused store refused on every process."""
    done, error = {}, None
    if store is not None and jax.process_index() == 0:
        try:
            done = store.load()
        except ValueError as err:
            if not restart:
                error = str(err)
            else:
                store.clear()
    if jax.process_count() == 1:
        if error:
            raise ValueError(error)
        return done
    bcast = multihost_utils.broadcast_one_to_all
    if int(bcast(np.asarray(int(error is not None), np.int32))):
        raise ValueError(error or "store: refused by process 0 (its message says why)")
    mask = np.zeros(-(-n // chunk), np.int32)
    mask[list(done)] = 1
    ks = np.flatnonzero(np.asarray(bcast(mask)))
    if not ks.size:
        return {}
    spans = [_rows(int(k), chunk, n) for k in ks]
    total = sum(b - a for a, b in spans)
    if jax.process_index() == 0:
        outs = np.concatenate([done[int(k)][0] for k in ks])
        checks = np.concatenate([done[int(k)][1] for k in ks]).astype(np.int8)
    else:
        outs, checks = np.zeros((total, widths[0])), np.zeros((total, widths[1]), np.int8)
    outs, checks = (np.asarray(a) for a in bcast((outs, checks)))
    agreed, at = {}, 0
    for k, (a, b) in zip(ks, spans, strict=True):
        agreed[int(k)] = (outs[at: at + b - a], checks[at: at + b - a].astype(bool))
        at += b - a
    return agreed


def rate_chunks(local: Callable, static, args, fields: dict, n: int, chunk: int, widths: tuple,
                *, devices=None, store: ChunkStore | None = None, restart: bool = False,
                progress: Callable[[int, int], None] | None = None):
    """Every candidate rated by chunks spread over the devices, resumed from ``store``.

    The chunks k = 0 … ⌈n/chunk⌉ − 1 not in the store are rated in rounds of one chunk per
    device of every process (process p's devices take the round's chunks in order after those
    of processes 0 … p−1; the last round's spare devices repeat its last chunk, the last chunk
    is padded with copies of its last candidate: every call has one shape), each device
    running ``local(static, *args, batch)`` on its ``chunk`` candidates, compiled once for one
    device (its calls on the devices of a process dispatched together); the results gathered
    on every process (each round's, or under ``jax.distributed`` those of the rounds of about
    :data:`GATHER` candidates a process), and each finished chunk written to ``store`` by
    process 0.

    Args:
        local: the per-chunk function, ``(static, *args, batch) → (outputs (chunk, w0),
            checks (chunk, w1))``, ``batch`` a dict of (chunk,) arrays. static: its hashable
            static values. args: a tuple of its other arguments (pytrees; their arrays put on
            each device).
        fields: the candidates' inputs, name → (n,) host array (the same on every process).
        n: candidates. chunk: candidates per chunk. widths: (w0, w1), the columns of the
            outputs and checks.
        devices: this process's devices to rate on (default: ``jax.local_devices()``); the same
            count on every process.
        store: the results store (None: none). restart: a store of another sizing emptied
            instead of refused.
        progress: called ``progress(done, n)`` (candidates done, the store's first) once a
            resumed store is read and after each chunk.

    Returns:
        (outputs (n, w0), checks (n, w1)) as NumPy arrays on every process.

    Raises:
        ValueError: a store of another sizing (without ``restart``), devices not this
            process's or of another count than another process's.
    """
    chosen = _local_devices(devices)
    n_chunks = -(-n // chunk)
    done = _agreed_store(store, restart, n, chunk, widths)
    outs = np.zeros((n, widths[0]))
    checks = np.zeros((n, widths[1]), bool)
    finished = 0
    for k, (o, c) in done.items():
        a, b = _rows(k, chunk, n)
        outs[a:b], checks[a:b] = o, c
        finished += b - a
    if finished and progress is not None:
        progress(finished, n)
    todo = [k for k in range(n_chunks) if k not in done]
    if not todo:
        return outs, checks
    per_process, processes, me = len(chosen), jax.process_count(), jax.process_index()
    per_round = per_process * processes
    rounds = [todo[r: r + per_round] for r in range(0, len(todo), per_round)]
    rounds[-1] = rounds[-1] + [rounds[-1][-1]] * (per_round - len(rounds[-1]))
    # one process: each round's results at once; several: gathered every GATHER candidates a
    # process (each gather waits for the slowest process)
    group = 1 if processes == 1 else max(1, GATHER // (chunk * per_process))
    on_device = [jax.device_put(args, d) for d in chosen]
    writer = store is not None and me == 0
    for g in range(0, len(rounds), group):
        block = rounds[g: g + group]
        calls = []
        for ks in block:
            for j, k in enumerate(ks[me * per_process: (me + 1) * per_process]):
                start, stop = _rows(k, chunk, n)
                pad = np.r_[np.arange(start, stop), np.full(chunk - (stop - start), stop - 1)]
                batch = jax.device_put({name: np.asarray(v[pad], dtype=float)
                                        for name, v in fields.items()}, chosen[j])
                calls.append(_program(local, static, on_device[j], batch))
        o, c = gathered((np.concatenate([np.asarray(r[0]) for r in calls]),
                         np.concatenate([np.asarray(r[1]) for r in calls])))
        # process p's results of round r on its device j at ((p·rounds + r)·devices + j)·chunk
        at = {}
        for r, ks in enumerate(block):
            for i, k in enumerate(ks):
                p, j = divmod(i, per_process)
                at.setdefault(k, ((p * len(block) + r) * per_process + j) * chunk)
        for k in sorted(at):
            start, stop = _rows(k, chunk, n)
            outs[start:stop] = o[at[k]: at[k] + stop - start]
            checks[start:stop] = c[at[k]: at[k] + stop - start]
            if writer:
                store.write(k, outs[start:stop], checks[start:stop])
            finished += stop - start
            if progress is not None:
                progress(finished, n)
    return outs, checks
