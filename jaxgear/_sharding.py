"""Work spread over processes joined by ``jax.distributed``: joining them, and results gathered
whole on every process. ``jaxgear robust``'s realisations and ``jaxgear size``'s chunks of
candidates both run through it."""

from __future__ import annotations

import jax
import numpy as np
from jax.experimental import multihost_utils

__all__ = ["gathered", "join_processes"]


def join_processes(coordinator_address: str | None, num_processes: int | None,
                   process_id: int | None) -> None:
    """Join ``jax.distributed`` as process ``process_id`` of ``num_processes`` (the coordinator
    at ``coordinator_address``, HOST:PORT, process 0's host); nothing for one process (None or
    1). Called before any other JAX work of the process."""
    if num_processes is not None and num_processes > 1:
        jax.distributed.initialize(coordinator_address=coordinator_address,
                                   num_processes=num_processes, process_id=process_id)


def gathered(tree):
    """Every leaf of ``tree`` whole, as NumPy arrays, on every process: a global array's
    shards, or each process's own host array of one shape (joined along the leading axis in
    process order), gathered under ``jax.distributed`` (``process_allgather``)."""
    if jax.process_count() > 1:
        tree = multihost_utils.process_allgather(tree, tiled=True)
    return jax.tree.map(np.asarray, tree)
