"""Small shared helpers of the model."""

from __future__ import annotations

import jax.numpy as jnp

__all__ = ["as_float"]


def as_float(v):
    """Convert to a JAX array of the default float dtype (float64 with x64 on, else float32)."""
    return jnp.asarray(v, dtype=jnp.result_type(float))
