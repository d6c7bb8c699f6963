"""Small shared helpers of the model."""

from __future__ import annotations

import jax
import jax.numpy as jnp

__all__ = [
    "as_float",
    "check_integer",
    "of_the_one_mesh",
    "only_one_mesh",
    "rms_about_mean",
    "safe_sqrt",
]


def check_integer(name: str, value, lo: int) -> None:
    """Refuse, with one line naming ``name``, its value and the range, a setting that is not an
    integer >= ``lo`` (a bool, a string, ``None`` and 2.5 included)."""
    try:
        ok = not isinstance(value, bool) and int(value) == value and value >= lo
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} = {value!r} is out of range: allowed an integer >= {lo}")


def as_float(v):
    """Convert to a JAX array of the default float dtype (float64 with x64 on, else float32)."""
    return jnp.asarray(v, dtype=jnp.result_type(float))


@jax.custom_jvp
def safe_sqrt(x):
    """√x with a finite derivative at 0: 1/(2√x) for x > 0, 0 at x = 0 (a subgradient of the
    RMS at zero fluctuation, where the exact derivative does not exist). Differentiable again."""
    return jnp.sqrt(x)


@safe_sqrt.defjvp
def _safe_sqrt_jvp(primals, tangents):
    (x,), (dx,) = primals, tangents
    y = jnp.sqrt(x)
    pos = x > 0
    return y, jnp.where(pos, dx / (2.0 * jnp.where(pos, y, 1.0)), 0.0)


def rms_about_mean(x, axis=-1):
    """Root mean square of ``x`` about its mean along ``axis`` (the standard deviation), with a
    finite gradient when ``x`` is constant (e.g. a perfect relief: zero TE fluctuation)."""
    d = x - jnp.mean(x, axis=axis, keepdims=True)
    return safe_sqrt(jnp.mean(d * d, axis=axis))


def only_one_mesh(meshes: tuple, what: str):
    """The one entry of a result's per-mesh tuple ``meshes``; a one-line error naming
    ``meshes[k]`` when the scene has several meshes (``what``: "results", "responses")."""
    if len(meshes) != 1:
        raise ValueError(
            f"the scene has {len(meshes)} gear meshes; read their {what} from meshes[k]"
        )
    return meshes[0]


def of_the_one_mesh(name: str) -> property:
    """A result's property that reads ``name`` on its ``mesh`` (the scene's one mesh), so that a
    one-mesh scene reads its per-mesh results on the result itself."""
    return property(
        lambda self: getattr(self.mesh, name),
        doc=f"``{name}`` of the scene's one mesh (see ``meshes``).",
    )
