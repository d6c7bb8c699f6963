"""Results of work spread over processes joined by ``jax.distributed``, gathered whole on every
process: ``jaxgear robust``'s realisations and ``jaxgear size``'s chunks of candidates."""

from __future__ import annotations

import jax
import numpy as np
from jax.experimental import multihost_utils

__all__ = ["gathered"]


def gathered(tree):
    """Every leaf of ``tree`` whole, as NumPy arrays, on every process: a global array's
    shards, or each process's own host array of one shape (joined along the leading axis in
    process order), gathered under ``jax.distributed`` (``process_allgather``)."""
    if jax.process_count() > 1:
        tree = multihost_utils.process_allgather(tree, tiled=True)
    return jax.tree.map(np.asarray, tree)
