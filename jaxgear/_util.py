"""Small shared helpers of the model."""

from __future__ import annotations

import jax
import jax.numpy as jnp

__all__ = [
    "as_float",
    "check_integer",
    "of_the_one_mesh",
    "only_one_mesh",
    "only_where_needed",
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


_CHUNK = 8  # positions computed together when only some positions of a batch need it


def only_where_needed(fn):
    """``g(need, default, *args)``: ``fn(*args)`` where ``need``, else ``default`` (a pytree of
    the output's shapes). Unbatched it is a ``lax.cond``. Under ``jax.vmap`` the positions that
    need it are gathered and ``fn`` runs on them only, :data:`_CHUNK` at a time (a while loop
    over the chunks): a vmapped ``cond`` or while loop would run ``fn`` on the whole batch
    whenever one position needs it (a relief map's later passes factor a few positions of 64).
    ``fn``'s inputs are stopped values: no tangent reaches it."""

    @jax.custom_batching.custom_vmap
    def g(need, default, *args):
        return jax.lax.cond(need, lambda: fn(*args), lambda: default)

    @g.def_vmap
    def rule(axis_size, in_batched, need, default, *args):
        def full(x, batched):
            return x if batched else jnp.broadcast_to(x, (axis_size, *jnp.shape(x)))

        need = full(need, in_batched[0])
        default = jax.tree_util.tree_map(full, default, in_batched[1])
        args = jax.tree_util.tree_map(full, args, tuple(in_batched[2:]))
        m = min(_CHUNK, axis_size)
        count = jnp.sum(need)
        # the needing positions first, in order (padded for the last chunk's slice)
        order = jnp.argsort(~need, stable=True).astype(jnp.int32)
        order = jnp.concatenate([order, jnp.full((m,), axis_size, jnp.int32)])

        def body(state):
            q, out = state
            idx = jax.lax.dynamic_slice(order, (q * m,), (m,))
            idx = jnp.where(q * m + jnp.arange(m) < count, idx, axis_size)
            take = jnp.minimum(idx, axis_size - 1)
            part = jax.vmap(fn)(*jax.tree_util.tree_map(lambda x: x[take], args))
            # positions past the count carry the index axis_size: dropped by the scatter
            out = jax.tree_util.tree_map(lambda o, p: o.at[idx].set(p, mode="drop"), out, part)
            return q + 1, out

        _, out = jax.lax.while_loop(
            lambda st: st[0] * m < count, body, (jnp.array(0, jnp.int32), default)
        )
        return out, jax.tree_util.tree_map(lambda _: True, out)

    return g
