"""Small shared helpers of the model."""

from __future__ import annotations

import functools

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

__all__ = [
    "NamedKind",
    "as_float",
    "check_instance",
    "check_integer",
    "check_real",
    "closest_circles",
    "compiled_when_eager",
    "is_traced",
    "of_the_one_mesh",
    "only_one_mesh",
    "only_where_needed",
    "padded_batch",
    "rms_about_mean",
    "safe_max",
    "safe_sqrt",
]


class NamedKind(eqx.Module):
    """A kind of an algorithm or a shape without parameters (a relief shape, a deviation kind),
    named in case files by :attr:`name`. It compares equal to another instance of its class and
    to its name (the string the former API took, so that ``m.tip_relief_shape == "parabolic"``
    still reads) and hashes as its name; the mapping from names to objects is
    :mod:`jaxgear.io`'s."""

    name: eqx.AbstractClassVar[str]

    def __eq__(self, other) -> bool:
        return type(other) is type(self) or (type(other) is str and other == self.name)

    def __hash__(self) -> int:
        return hash(self.name)


#: :func:`padded_batch`'s step: batches padded to a power of two up to it, then to a multiple
BATCH_STEP = 8


def padded_batch(n: int) -> int:
    """The size a group of ``n`` (>= 1) like problems is padded to for one compiled ``vmap``
    program: the next power of two up to :data:`BATCH_STEP`, then the next multiple of it
    (few compiled sizes, little waste)."""
    if n <= BATCH_STEP:
        return 1 << (n - 1).bit_length()
    return -(-n // BATCH_STEP) * BATCH_STEP


def check_integer(name: str, value, lo: int) -> None:
    """Refuse, with one line naming ``name``, its value and the range, a setting that is not an
    integer >= ``lo`` (a bool, a string, ``None`` and 2.5 included)."""
    try:
        ok = not isinstance(value, bool) and int(value) == value and value >= lo
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ValueError(f"{name} = {value!r} is out of range: allowed an integer >= {lo}")


def compiled_when_eager(fn):
    """``fn`` run as one compiled program (``eqx.filter_jit``: array leaves traced, the rest
    static) when it is called on concrete values, and traced inline when an argument is a
    tracer (the caller's ``jit``, ``vmap`` or ``grad`` compiles it with the rest). Called
    eagerly, a function of a few hundred JAX operations otherwise dispatches and compiles
    each on its own (a new small program for each new shape). Same results; the arguments
    are those of ``fn``."""
    compiled = eqx.filter_jit(fn)

    @functools.wraps(fn)
    def call(*args, **kwargs):
        if is_traced((args, kwargs)):
            return fn(*args, **kwargs)
        return compiled(*args, **kwargs)

    return call


def is_traced(value) -> bool:
    """Whether ``value`` (or a leaf of it) is a JAX tracer (under ``jit``, ``vmap``, ``grad``):
    its concrete value cannot be checked, only its shape."""
    return any(isinstance(x, jax.core.Tracer) for x in jax.tree_util.tree_leaves(value))


def checked_on_host(value, failed, message: str):
    """``value``, raising ``eqx.EquinoxRuntimeError(message)`` where the boolean ``failed`` is
    true: on the host when ``failed`` is concrete (an ``eqx.error_if`` on concrete values
    compiles a program holding a Python callback, which the persistent compilation cache does
    not store), else riding on ``value`` through ``eqx.error_if`` (under a caller's trace)."""
    if not is_traced(failed):
        if bool(failed):
            raise eqx.EquinoxRuntimeError(message)
        return value
    return eqx.error_if(value, failed, message)


def each_solve(A, B):
    """``A_i⁻¹ B_i`` for a stack ``A`` (m, k, k), ``B`` (m, k) or (m, k, r): one unbatched
    solve per member in a ``jax.lax.map``, never one batched LAPACK call.

    jaxlib's batched LU (the custom call behind ``jnp.linalg.solve`` on a stack, or a vmapped
    one) hands its members to XLA's CPU intra-op thread pool and waits for them; when the
    runtime runs that call on a thread of the same pool, the members queue behind the waiting
    thread and the program never returns (seen on a 2-core host in the whine balances: the
    pool's thread in ``ParallelBatchMap`` → ``BlockingCounter::Wait``, every other thread
    idle; ``--xla_cpu_multi_thread_eigen=false`` did not prevent it). An unbatched LU runs
    inline. Under an outer ``jax.vmap`` the loop's body is batched again: call it where the
    outer loop is a ``lax.map``. Differentiable (``lax.map`` and ``solve`` are)."""
    return jax.lax.map(lambda ab: jnp.linalg.solve(ab[0], ab[1]), (A, B))


def int_rows(a) -> tuple:
    """The rows of an integer array as a tuple of tuples of Python ints (hashable: a static
    argument of a compiled program)."""
    return tuple(tuple(int(v) for v in row) for row in np.asarray(a))


@functools.singledispatch
def _show(v) -> str:
    """A value for a one-line message: a number as ``%g``, an integer as is, anything else
    (an array by its offending entry) by its ``repr`` on one line, cut at 60 characters."""
    return _one_line(repr(v))


def _one_line(text: str) -> str:
    text = " ".join(text.split())
    return text if len(text) <= 60 else text[:57] + "..."


@_show.register(float)
@_show.register(np.floating)
def _show_float(v) -> str:
    return f"{float(v):g}"


@_show.register(int)
@_show.register(np.integer)
def _show_int(v) -> str:
    return _one_line(str(v))


def _bound(lo, hi, lo_open: bool, hi_open: bool) -> str:
    if lo is not None and hi is not None:
        return f"{'(' if lo_open else '['}{lo:g}, {hi:g}{')' if hi_open else ']'}"
    if lo is not None:
        return f"{'>' if lo_open else '>='} {lo:g}"
    if hi is not None:
        return f"{'<' if hi_open else '<='} {hi:g}"
    return "a finite value"


def check_real(
    name: str,
    value,
    unit: str = "",
    *,
    lo: float | None = None,
    hi: float | None = None,
    lo_open: bool = False,
    hi_open: bool = False,
    shape: tuple | None = None,
    shape_text: str | None = None,
    where: str = "",
) -> None:
    """Refuse, with one ``ValueError`` line, a public input that is not a real number (or array
    of real numbers) that is finite and in the range ``lo``/``hi`` (``lo_open``, ``hi_open``:
    the bound excluded): ``where: name = value unit is out of range: allowed > 0 unit``, the
    entry of an array that fails, and its index. ``shape``: the shape required (``None``: any;
    an entry ``None``: any length on that axis), ``shape_text`` how the message states it
    (``"(n,)"``). A traced value (under ``jit``, ``vmap``, ``grad``) has only its shape
    checked: its value is not known here (the differentiable paths stay open; traced values
    are guarded by ``eqx.error_if`` where they are used). Float32 and float64 alike."""
    head = f"{where}: " if where else ""
    u = f" {unit}" if unit else ""
    if value is None or isinstance(value, bool | str | bytes):
        raise ValueError(
            f"{head}{name} = {value!r} is not a number: allowed {_bound(lo, hi, lo_open, hi_open)}"
            f"{u if (lo, hi) != (None, None) else ''}"
        )
    if is_traced(value):
        got = jnp.shape(value)
        arr = None
    else:
        try:
            arr = np.asarray(value)
        except Exception:  # noqa: BLE001 - any object numpy cannot take
            arr = None
        real = arr is not None and (
            np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)
        )
        if not real:
            raise ValueError(
                f"{head}{name} = {_show(value)} is not a real number: allowed "
                f"{_bound(lo, hi, lo_open, hi_open)}{u if (lo, hi) != (None, None) else ''}"
            )
        got = arr.shape
    if shape is not None and (
        len(got) != len(shape)
        or any(w is not None and g != w for g, w in zip(got, shape, strict=True))
    ):
        want = shape_text or str(tuple(shape))
        units = f" [{unit}]" if unit else ""
        raise ValueError(f"{head}{name} must have shape {want}{units}, got {tuple(got)}")
    if arr is None:
        return
    a = arr.astype(np.float64) if arr.size else arr
    bad = ~np.isfinite(a)
    if lo is not None:
        bad |= (a <= lo) if lo_open else (a < lo)
    if hi is not None:
        bad |= (a >= hi) if hi_open else (a > hi)
    if np.any(bad):
        idx = tuple(int(i) for i in np.argwhere(bad)[0])
        v = a[idx] if a.ndim else a.item()
        at = f"[{', '.join(map(str, idx))}]" if a.ndim else ""
        allowed = _bound(lo, hi, lo_open, hi_open) + (u if (lo, hi) != (None, None) else "")
        raise ValueError(f"{head}{name}{at} = {float(v):g}{u} is out of range: allowed {allowed}")


def check_instance(name: str, value, types, allowed: str, where: str = "") -> None:
    """Refuse, in one ``ValueError`` line, ``value`` that is not an instance of ``types``
    (``allowed`` says what is, e.g. ``"jaxgear.Modifications or None"``)."""
    if not isinstance(value, types):
        raise ValueError(
            f"{where}: " * bool(where)
            + f"{name} = {_show(value)} ({type(value).__name__}) is out of range: allowed "
            f"{allowed}"
        )


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


@functools.partial(jax.custom_jvp, nondiff_argnums=(1,))
def safe_max(x, axis: int | None = None):
    """``jnp.max(x, axis)`` whose derivative never divides by zero, for objectives written on
    results (the maximum line load, the peak-to-peak TE, the largest flank deviation of a
    cell set: :attr:`QuasiStaticResult.max_line_load` and ``te_ptp`` use it).

    The value is ``jnp.max``'s. The tangent is the mean of the tangents at the elements equal
    to the maximum (``jnp.max``'s rule: ties share it evenly), or the tangent at the first
    maximum (``jnp.argmax``) where no element compares equal to it. ``jnp.max``'s rule divides
    by that count, and a compiled program may compute the operand of the comparison and of the
    reduction in two kernels that round differently (XLA's CPU backend at
    ``--xla_backend_optimization_level=0``), making it 0 and the gradient NaN.

    Args:
        x: array of any shape and unit; masked elements as ``-inf`` (they get a zero tangent
            unless every element of the reduction is masked).
        axis: None (all elements: a scalar) or one axis (negative counts from the end): the
            shape of ``x`` without that axis.

    Returns:
        the maximum, in the unit of ``x``; forward and reverse mode differentiable in ``x``.
    """
    return jnp.max(x, axis=axis)


@safe_max.defjvp
def _safe_max_jvp(axis, primals, tangents):
    (x,), (dx,) = primals, tangents
    y = jnp.max(x, axis=axis, keepdims=True)
    hit = x == y
    count = jnp.sum(hit, axis=axis, keepdims=True)
    first = jnp.argmax(x, axis=axis, keepdims=True)
    if axis is None:
        index = jnp.arange(x.size).reshape(x.shape)
    else:
        index = jax.lax.broadcasted_iota(first.dtype, x.shape, axis % x.ndim)
    w = jnp.where(count > 0, hit / jnp.maximum(count, 1), index == first).astype(dx.dtype)
    return jnp.max(x, axis=axis), jnp.sum(w * dx, axis=axis)


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


def static_correction(T, Q, K, correction: bool = True):
    """The static correction of the kept directions T (n, m') for the stiffness K (n, n), Q
    (n, n − m') the other directions (together M-orthonormal: the modal basis's split_modes):
    (D (n, m'), G (n, n)).

    G = Q (Qᵀ K Q)⁻¹ Qᵀ: the structure's flexibility on the M-orthogonal complement of the
    kept directions (the residual flexibility; Craig & Kurdila §14.5), and D = T − G K T. Then
    X = D q + G f solves the static K X = f exactly (block elimination of the complement:
    Dᵀ K D q = Dᵀ f, Dᵀ K G = 0 as G K G = G), and with every mode kept D = T, G = 0: the full
    model in modal coordinates. Tᵀ M D = I and Tᵀ M G = 0 (q = Tᵀ M X recovers the modal
    coordinates). Without ``correction``: D = T, G = 0 (the truncated modal model)."""
    n = T.shape[0]
    if Q.shape[1] == 0 or not correction:
        return T, jnp.zeros((n, n), T.dtype)
    A = Q.T @ K @ Q
    G = Q @ jnp.linalg.solve(0.5 * (A + A.T), Q.T)
    G = 0.5 * (G + G.T)
    return T - G @ (K @ T), G


def closest_circles(centres, radii, pairs=None) -> tuple[int, int, float] | None:
    """Of the circles of ``radii`` r (m, (n,)) at ``centres`` (m, (n, 2), in one plane), the
    pair of the least clearance d − r_i − r_j: (i, j, d), 0-based, i < j, d the centres'
    distance (m); among ``pairs`` ((i, j) with i < j; None: every pair), None where there is
    none. Two gears in one plane that do not mesh must not overlap, d >= r_i + r_j: the one
    rule of a train's layout (its non-meshing gears in one plane, tip radii;
    :mod:`jaxgear.io`'s train case files) and of a planetary stage's planets
    (:func:`jaxgear.planetary.closest_planets`). Clearances equal to 1e-12 of the largest
    distance count as a tie, won by the first pair in (i, j) order (equally spaced planets:
    planets 1 and 2, not a pair chosen by round-off)."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    r = np.asarray(radii, dtype=float).reshape(-1)
    n = c.shape[0]
    if pairs is None:
        pairs = [(i, j) for i in range(n) for j in range(i + 1, n)]
    pairs = sorted((min(p), max(p)) for p in pairs)
    if not pairs:
        return None
    ij = np.asarray(pairs, dtype=int).reshape(-1, 2)
    d = np.hypot(*(c[ij[:, 1]] - c[ij[:, 0]]).T)
    clear = d - r[ij[:, 0]] - r[ij[:, 1]]
    tol = 1e-12 * max(float(np.max(d)), float(np.max(np.abs(r))), 1e-300)
    k = int(np.flatnonzero(clear <= clear.min() + tol)[0])
    return int(ij[k, 0]), int(ij[k, 1]), float(d[k])
