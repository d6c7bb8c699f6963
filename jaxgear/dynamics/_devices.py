"""Speeds placed across the local devices (``jax.sharding``): what a sweep's engines share to
split independent speeds over several accelerators."""

from __future__ import annotations

import jax
import jax.numpy as jnp
import numpy as np

__all__ = ["shard_speeds"]


def shard_speeds(speeds, rows: bool = False):
    """``speeds`` (S,) padded with its last speed to a multiple of the local devices and placed
    across them (``jax.sharding``): (S',) split along its axis, or with ``rows`` (devices,
    S'/devices), one row per device. Returns (the placed array, the padding)."""
    devices = jax.local_devices()
    n = len(devices)
    pad = (-speeds.shape[0]) % n
    padded = jnp.concatenate([speeds, jnp.full((pad,), speeds[-1], speeds.dtype)])
    if rows:
        padded = padded.reshape(n, -1)
    mesh = jax.sharding.Mesh(np.array(devices), ("speed",))
    sharding = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("speed"))
    return jax.device_put(padded, sharding), pad


def several_devices(shard: bool, speeds) -> bool:
    """Whether ``speeds`` are to be spread over the local devices: ``shard`` asked, more than
    one device, and concrete speeds (a traced sweep runs where it is traced)."""
    return bool(shard) and len(jax.local_devices()) > 1 and not isinstance(speeds, jax.core.Tracer)
