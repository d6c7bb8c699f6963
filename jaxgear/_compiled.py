"""A quasi-static solve compiled once for one scene: the per-curve call of an optimisation loop.

:func:`quasi_static` checks its inputs, flattens the scene and the modifications and dispatches
a cached program at every call; for one TE curve of a small pair that costs several times the
solve itself. :func:`compile_quasi_static` does that work once: the scene, the angles, the
contact law and the speed are compiled into the program as constants, the modifications become
one flat design vector (the leaves of a template :class:`Modifications`, in its tree order, or
only those a ``free`` selector names: the others are compiled in as constants, and a program
whose design is a few leaves costs about what a fully constant one does), and each call passes
only that vector and the torque.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from typing import Any, NamedTuple

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jax.extend.core.primitives import jit_p
from jax.flatten_util import ravel_pytree
from jaxtyping import Array, Float

from ._baseplane import MeshModel, check_positions
from ._contact import ContactLaw, ExactContact, contact_law
from ._modifications import Modifications
from ._quasi_static import (
    _quasi_static,
    check_operating,
    per_mesh_modifications,
)
from ._results import ContactResult, raise_if_failed
from ._util import check_real, is_traced
from .scenes import Scene

__all__ = ["CompiledQuasiStatic", "compile_quasi_static"]

_WHERE = "compiled quasi_static"


class CompiledQuasiStatic(eqx.Module):
    """:func:`quasi_static` of one scene compiled once (built by :func:`compile_quasi_static`):
    ``compiled(design, torque)`` returns what ``quasi_static(scene, modifications(design),
    torque, ...)`` returns (or its ``output``), to round-off (the same program).

    Call with:
        design: the design vector ``(D,)`` (the template's free leaves flattened, in its tree order:
            :meth:`design_vector` builds it from a :class:`Modifications` of the template's
            structure, :meth:`modifications` maps it back), or such a :class:`Modifications`
            (flattened at each call: slower than passing the vector); ``None`` or a tuple of
            one per mesh when the template was.
        torque: pinion torque (N·m), scalar, > 0 (!= 0 with coast flanks).

    A call with concrete inputs runs the compiled program and reads its result codes as one
    integer (``throw``: ``eqx.EquinoxRuntimeError`` on a failed position, ``quasi_static``'s
    message; ``throw=False``: no wait, the codes not read). The fastest call is
    ``compiled(x, torque)`` with ``x`` a JAX array ``(D,)`` and ``torque`` a Python number:
    it is checked in a few type and range tests; any other form (a NumPy design, a
    :class:`Modifications`, a NumPy or JAX torque) takes the general checks, a few µs more.
    Under ``jax.grad``, ``jax.vmap`` or ``jax.jit`` the same solve is traced into the caller's
    program (errors by ``eqx.error_if``), so the call is differentiable in ``design`` and
    ``torque``.

    Attributes:
        design0: the template's design vector ``(D,)``.
        throw: raise on a failed position (see :func:`quasi_static`).
    """

    design0: Float[Array, " D"]
    throw: bool = eqx.field(static=True)
    _rebuild: Callable = eqx.field(static=True)
    _free: Callable | None = eqx.field(static=True)
    _treedef: Any = eqx.field(static=True)
    _shapes: tuple = eqx.field(static=True)
    _fast: Callable = eqx.field(static=True)
    _traced: Callable = eqx.field(static=True)
    _coast: bool = eqx.field(static=True)
    _recompile: Callable = eqx.field(static=True)
    _lean: Callable = eqx.field(static=True)

    @property
    def size(self) -> int:
        """Length D of the design vector."""
        return int(self.design0.shape[0])

    def design_vector(self, modifications: Modifications) -> Float[Array, " D"]:
        """The design vector ``(D,)`` of ``modifications``, which must have the template's
        structure (the same relief shapes, deviations present or not, the same array shapes).

        Raises:
            ValueError: another structure or leaf shape than the template's (one line).
        """
        leaves, treedef = jax.tree_util.tree_flatten(modifications)
        shapes = tuple(jnp.shape(x) for x in leaves)
        if treedef != self._treedef or shapes != self._shapes:
            raise ValueError(
                f"{_WHERE}: modifications = {type(modifications).__name__} of another structure "
                "than the template's: allowed a Modifications with the same relief shapes, "
                "deviations and array shapes as the one given to compile_quasi_static"
            )
        free = modifications if self._free is None else self._free(modifications)
        if is_traced(leaves):
            return ravel_pytree(free)[0].astype(self.design0.dtype)
        flat = [np.ravel(np.asarray(x)) for x in jax.tree_util.tree_leaves(free)]
        x = jnp.asarray(np.concatenate(flat) if flat else np.zeros(0), self.design0.dtype)
        fixed = jax.tree_util.tree_leaves(self.modifications(x))
        if self._free is not None and not all(
            np.array_equal(a, b, equal_nan=True) for a, b in zip(fixed, leaves, strict=True)
        ):
            raise ValueError(
                f"{_WHERE}: modifications differ from the template in a leaf that is not free: "
                "allowed changes in the free leaves only (compile_quasi_static(free=...))"
            )
        return x

    def with_free(self, free: Callable | None) -> CompiledQuasiStatic:
        """The same solve (scene, angles, contact, output) with the design variables ``free``:
        a function of the template :class:`Modifications` returning the leaves that vary (e.g.
        ``lambda m: (m.pinion.tip_relief_depth, m.pinion.tip_relief_extent)``, or a subtree such
        as ``lambda m: m.pinion``: its array leaves; as ``equinox.tree_at``'s ``where``);
        ``None``: every leaf. The other leaves are compiled in as constants: a smaller, faster
        program (a relief depth enters linearly and folds; a design of the whole template
        evaluates every relief ramp at every cell). A new program, compiled at its first call.

        Raises:
            ValueError: ``free`` not a function returning array leaves of the template (one
                line).
        """
        return self._recompile(free)

    def with_hoisting(self, max_bytes: int) -> CompiledQuasiStatic:
        """The same solve with at most ``max_bytes`` bytes kept between calls for the part of
        the program that depends on neither the design nor the torque (its outputs, computed
        once at the first call; default 256 MiB). A larger part, or ``max_bytes = 0``, is
        computed at every call instead: the same results, slower calls, less memory held. A new
        program, compiled at its first call.

        Raises:
            ValueError: ``max_bytes`` not an integer >= 0 (one line).
        """
        if (
            isinstance(max_bytes, bool)
            or not isinstance(max_bytes, int | np.integer)
            or max_bytes < 0
        ):
            raise ValueError(
                f"{_WHERE}: max_bytes = {max_bytes!r}: allowed an integer >= 0 (bytes)"
            )
        return self._recompile(self._free, int(max_bytes))

    def modifications(self, design: Float[Array, " D"]) -> Modifications:
        """The :class:`Modifications` of a design vector ``(D,)`` (the inverse of
        :meth:`design_vector`)."""
        return self._rebuild(jnp.asarray(design, self.design0.dtype))

    def __call__(self, design, torque):
        # the per-call path is a plain closure (_lean_call): an eqx.Module attribute costs ~2 µs
        # and a bound method ~20 µs, against a ~60 µs solve; anything it does not take (a
        # Modifications, a NumPy design, a traced or bad input) goes through _call
        try:
            return self._lean(design, torque)
        except _NotLean:
            return _call(self, design, torque)


def _call(self: CompiledQuasiStatic, design, torque):
    """The general per-call path: a :class:`Modifications` flattened, the design's shape and the
    torque checked, a traced input traced into the caller's program."""
    as_mods = design is None or isinstance(design, _MODS)
    if as_mods:
        design = self.design_vector(design)
    if jnp.shape(design) != self.design0.shape:
        raise ValueError(
            f"{_WHERE}: design has shape {jnp.shape(design)}: allowed "
            f"({self.design0.shape[0]},), the design vector of the template modifications "
            "(CompiledQuasiStatic.design_vector)"
        )
    if is_traced((design, torque)):
        return self._traced(design, torque)
    _check_torque(torque, self._coast)
    out, failed = self._fast(design, torque)
    if self.throw:
        _raise_if_flagged(failed)
    return out


class _NotLean(Exception):
    """An input the lean per-call path does not take (the general path, :func:`_call`, does)."""


def _lean_call(fast: Callable, shape: tuple, coast: bool, throw: bool) -> Callable:
    """The per-call path of the common call ``compiled(x, torque)``: ``x`` a concrete JAX array
    of the design's shape, ``torque`` a Python number in range (finite, > 0; != 0 with coast
    flanks); :class:`_NotLean` raised for any other input. With ``throw``, it waits for the
    program's one-integer failure flag and raises on a failed position (the flag read after the
    wait: a read of an unfinished array costs several µs more)."""
    array = type(jnp.zeros(()))

    def lean(design, torque):
        if type(design) is not array or design.shape != shape:
            raise _NotLean
        kind = type(torque)
        if not (
            (kind is float or kind is int)
            and (torque != 0 if coast else torque > 0)
            and torque - torque == 0  # finite
        ):
            raise _NotLean
        out, failed = fast(design, torque)
        if throw:
            _raise_if_flagged(failed)
        return out

    return lean


def _failure_flag(codes) -> Array:
    """The result codes ``codes`` (integers >= 0) as one integer: bit k set when code k occurs
    (one scalar read per call instead of the whole code array)."""
    codes = jnp.ravel(codes).astype(jnp.int32)
    return jnp.bitwise_or.reduce(jnp.left_shift(jnp.int32(1), codes))


def _raise_if_flagged(failed) -> None:
    """Raise :func:`~jaxgear._results.raise_if_failed`'s error of the codes in the flag
    ``failed`` (:func:`_failure_flag`; bit 0, success, alone: no error)."""
    failed.block_until_ready()
    bits = int(np.asarray(failed))
    if bits > 1:
        codes = [k for k in range(bits.bit_length()) if bits >> k & 1]
        raise_if_failed(np.asarray(codes), ContactResult, _WHERE)


_MODS = (Modifications, tuple, list)


def _check_torque(torque, coast: bool) -> None:
    """The concrete torque, cheaply (the per-call path): a finite scalar > 0 (!= 0 with coast
    flanks); the one-line message of :func:`~jaxgear._util.check_real` otherwise."""
    try:
        t = float(torque)
    except (TypeError, ValueError):
        t = math.nan
    if math.isfinite(t) and (t != 0.0 if coast else t > 0.0) and np.ndim(torque) == 0:
        return
    check_real(
        "torque", torque, "N·m", lo=None if coast else 0.0, lo_open=True, shape=(), where=_WHERE
    )
    raise ValueError(f"{_WHERE}: torque = 0 N·m is out of range: allowed != 0 (coast flanks)")


def compile_quasi_static(
    scene: Scene | MeshModel,
    modifications: Modifications | None,
    theta: Float[Array, " P"] | None = None,
    *,
    speed=0.0,
    contact: ContactLaw = ExactContact(),
    positions_per_pitch: int = 64,
    periods: int = 1,
    output: Callable | None = None,
    throw: bool = True,
) -> CompiledQuasiStatic:
    """Compile :func:`quasi_static` of ``scene`` once, for repeated TE curves that differ only
    in the modifications and the torque (an optimisation loop, a user's own sweep).

    The scene, ``theta``, ``speed`` and ``contact`` are compiled in as constants (a large
    hybrid scene makes a longer compilation, once); the modifications become the design vector,
    the leaves of ``modifications`` (the template: its relief shapes, deviations present or not
    and array shapes are fixed, its values are the starting design ``design0``). The program is
    compiled at the first call (JAX's persistent compilation cache applies); its part that depends
    on neither the design nor the torque (cell layout, angles, the relief terms compiled in) is
    evaluated then, once, and not at each call (up to 256 MiB of it kept between calls:
    :meth:`CompiledQuasiStatic.with_hoisting`).

    Args:
        scene: a :class:`~jaxgear.scenes.Scene` or a :class:`MeshModel` (its rigid pair).
        modifications: the template :class:`Modifications` (``None``: perfect involutes, an
            empty design vector), one for every mesh of the scene or a tuple of one per mesh.
        theta, speed, contact, positions_per_pitch, periods, throw: as for
            :func:`quasi_static` (fixed for the compiled program).
        output: a function of the :class:`QuasiStaticResult` compiled into the program (e.g.
            ``lambda r: r.te_rms``); ``None``: the whole result. Returning less makes a call
            cheaper (fewer arrays out of the program).

    A concrete call dispatches one program (the design and the torque in; the output and one
    integer of result codes out, the codes read once). On a CPU, JAX runs a program on its
    runtime's threads and the caller waits for them: for a small curve that hand-off costs about
    as much as the curve (0.05 ms of compute, most on an idle machine, whose threads sleep). A
    loop of small calls runs faster with JAX's synchronous CPU dispatch, set in the script before
    its first JAX computation: ``jax.config.update("jax_cpu_enable_async_dispatch", False)``
    (JAX 0.10 reads no environment variable for it; once the backend has started it has no
    effect); the program then runs on the calling thread (measured: the documentation's
    quasi-static benchmark, the free-tip call of the accessory pair 0.069 ms, 1.4x its compute,
    against 0.115 ms by default on a loaded 2-core machine). The results are the same. It is a
    setting for such a loop, not a default: jaxgear never sets it.

    Returns:
        The :class:`CompiledQuasiStatic` callable ``(design, torque)``, every leaf of the
        template a design variable (:meth:`CompiledQuasiStatic.with_free` names fewer).

    Raises:
        ValueError: as :func:`quasi_static`, before any compilation: a ``scene`` that is not a
            scene, ``modifications`` that are not :class:`Modifications`, ``theta`` not finite
            of shape (P,), a negative speed, bad position counts, a contact that is not a
            contact law, ``output`` not callable.
    """
    check_positions(positions_per_pitch, periods)
    check_operating(_WHERE, scene, modifications, 1.0, theta, speed)
    if output is not None and not callable(output):
        raise ValueError(f"{_WHERE}: output = {output!r}: allowed None or a function of the result")
    planes = scene.base_planes
    for plane, mods in zip(planes, per_mesh_modifications(modifications, len(planes)), strict=True):
        if mods.deviations is not None:
            mods.deviations.check(plane)
    dtype = planes[0].base_pitch.dtype
    law = contact_law(contact, dtype)
    speed = jnp.asarray(speed, dtype=dtype)
    if theta is not None:
        theta = jnp.asarray(theta, dtype=dtype)
    positions = (int(positions_per_pitch), int(periods))
    pick = (lambda r: r) if output is None else output
    setup = _Setup(scene, modifications, theta, speed, law, positions, pick, bool(throw), _HOIST)
    return _compile(setup, None)


class _Setup(NamedTuple):
    """What :func:`compile_quasi_static` compiles in, checked: the scene, the template
    modifications, the angles (or None), the speed, the contact law, (positions per pitch,
    periods), the output function, ``throw`` and the hoisting bound (bytes)."""

    scene: Any
    modifications: Any
    theta: Any
    speed: Any
    law: Any
    positions: tuple
    pick: Callable
    throw: bool
    hoist: int


def _compile(setup: _Setup, free: Callable | None) -> CompiledQuasiStatic:
    """The :class:`CompiledQuasiStatic` of ``setup`` with the design leaves ``free`` (a
    function of the template, None: every leaf)."""
    scene, modifications, theta, speed, law, positions, pick, throw, hoist_max = setup
    dtype = scene.base_planes[0].base_pitch.dtype
    where = _free_leaves(free, modifications)
    if where is None:  # every leaf: the template's own flattening
        design0, rebuild = ravel_pytree(modifications)
    else:
        design0, unravel = ravel_pytree(where(modifications))

        def rebuild(x):
            return eqx.tree_at(where, modifications, unravel(x))

    design0 = jnp.asarray(design0, dtype=dtype)
    leaves, treedef = jax.tree_util.tree_flatten(modifications)

    def solve(x, torque, raise_: bool, checks: bool):
        mods = rebuild(jnp.asarray(x, dtype=dtype))
        t = jnp.asarray(torque, dtype=dtype)
        res = _quasi_static(scene, mods, t, speed, theta, law, raise_, positions, checks)
        return pick(res), res.result

    # concrete calls: no eqx.error_if in the program, the result codes read on the host (as one
    # integer flag); what does not depend on the design or the torque is computed once (_hoisted)
    def concrete(x, t):
        out, codes = solve(x, t, False, False)
        return out, _failure_flag(codes)

    fast = _hoisted(concrete, design0, hoist_max)
    # traced calls (grad, vmap, an outer jit): the checks ride in the caller's program
    traced = jax.jit(lambda x, t: solve(x, t, throw, True)[0])
    coast = any(p.coast for p in scene.base_planes)
    return CompiledQuasiStatic(
        design0=design0,
        throw=throw,
        _rebuild=rebuild,
        _free=where,
        _treedef=treedef,
        _shapes=tuple(jnp.shape(x) for x in leaves),
        _fast=fast,
        _traced=traced,
        _coast=coast,
        _recompile=lambda free, hoist=hoist_max: _compile(setup._replace(hoist=hoist), free),
        _lean=_lean_call(fast, design0.shape, coast, throw),
    )


_HOIST = 256 * 2**20  # bytes kept by default for the hoisted part (memory)


def _hoisted(fn: Callable, design0, max_bytes: int) -> Callable:
    """``jax.jit(fn)`` for concrete ``(design, torque)``, with the part of ``fn`` that depends on
    neither computed once, at the first call, and compiled in as constants.

    XLA folds only small constants: the cell layout, the angles and the fixed relief terms of a
    compiled-in scene would be recomputed at every call (a loop over designs hoists them, a
    single call cannot). ``fn``'s jaxpr is split by data dependence (:func:`_walk`, a partial
    evaluation written on ``jax.extend.core``), its design- and torque-free part evaluated once
    and its outputs (the intermediates the rest needs) closed over: the same operations on the
    same values (results to round-off: XLA fuses the rest on its own). Where the split fails
    (an equation it cannot bind) or the intermediates exceed ``max_bytes``: the whole ``fn``."""
    holder: list = []

    def call(x, t):
        if not holder:
            holder.append(_split(fn, design0, max_bytes, (x, t)))
        return holder[0](x, t)

    return call


def _split(fn: Callable, design0, max_bytes: int, first_args: tuple) -> Callable:
    """The jitted ``fn(x, t)`` with its ``(x, t)``-free part evaluated once (see
    :func:`_hoisted`); traced for ``first_args``, the first call's, here (a failed split gives
    the plain program)."""
    dtype = design0.dtype
    args = (jax.ShapeDtypeStruct(design0.shape, dtype), jax.ShapeDtypeStruct((), dtype))
    if max_bytes <= 0:
        return jax.jit(fn)
    try:
        closed, shapes = jax.make_jaxpr(fn, return_shape=True)(*args)
        treedef = jax.tree_util.tree_structure(shapes)

        def known():
            res: list = []
            _walk(closed.jaxpr, closed.consts, [_UNKNOWN, _UNKNOWN], res, True)
            return res

        residuals = jax.jit(known)()
        if sum(r.nbytes for r in residuals) > max_bytes:
            return jax.jit(fn)

        def hot(x, t):
            xt = [jnp.asarray(x, dtype), jnp.asarray(t, dtype)]
            flat = _walk(closed.jaxpr, closed.consts, xt, iter(residuals), False)
            return jax.tree_util.tree_unflatten(treedef, flat)

        program = jax.jit(hot)
        program.trace(*first_args)
    except Exception:  # noqa: BLE001 -- an equation the split cannot handle: the plain program
        return jax.jit(fn)
    return program


_UNKNOWN = object()  # first pass: a value that depends on the design or the torque
_KNOWN = object()  # second pass: a value that does not (read from the residuals where needed)


def _walk(jaxpr, consts, args, res, first: bool, top: bool = True) -> list:
    """One pass over ``jaxpr`` (a ``jax.extend.core.Jaxpr``) split by data dependence on
    ``args``. The first pass (``first``, ``args`` unknown) evaluates every equation whose inputs
    are all known and appends to the list ``res`` each known value an unknown equation reads
    (the residuals, once per jaxpr scope, in walk order); the second (``args`` the traced design
    and torque, ``res`` an iterator over the residuals) binds the unknown equations only,
    reading the residuals in the same order. A ``jit`` equation with inputs of both kinds is
    walked into; any other equation with an unknown input, or with effects, is unknown as a
    whole. Returns the outputs (top level: known ones as residuals)."""
    env: dict = {}  # id of a variable -> its value (a literal is never bound: its .val)
    taken: dict = {}  # id of a known variable -> its residual

    def read(v):
        return env[id(v)] if id(v) in env else v.val

    def unknown(v, x) -> bool:
        return x is _UNKNOWN if first else (id(v) in env and x is not _KNOWN)

    def residual(v):
        if id(v) not in env:  # a literal
            return v.val
        if id(v) not in taken:
            x = env[id(v)] if first else next(res)
            if first:
                res.append(x)
            elif (x.shape, x.dtype) != (v.aval.shape, v.aval.dtype):
                raise ValueError(f"{_WHERE}: residuals out of order")
            taken[id(v)] = x
        return taken[id(v)]

    def bind(vs, xs):
        env.update((id(v), x) for v, x in zip(vs, xs))

    bind(jaxpr.constvars, consts if first else [_KNOWN] * len(consts))
    bind(jaxpr.invars, args)
    for eqn in jaxpr.eqns:
        ins = [read(v) for v in eqn.invars]
        unk = [unknown(v, x) for v, x in zip(eqn.invars, ins)]
        if not any(unk) and not eqn.effects:
            outs = _bind(eqn, ins) if first else [_KNOWN] * len(eqn.outvars)
        elif eqn.primitive is jit_p:
            inner = eqn.params["jaxpr"]
            sub = ins if first else [x if u else _KNOWN for x, u in zip(ins, unk)]
            outs = _walk(inner.jaxpr, inner.consts, sub, res, first, top=False)
        else:
            vals = [x if u else residual(v) for v, x, u in zip(eqn.invars, ins, unk)]
            outs = [_UNKNOWN] * len(eqn.outvars) if first else _bind(eqn, vals)
        bind(eqn.outvars, outs)
    outs = [read(v) for v in jaxpr.outvars]
    if not top:  # known outputs stay known: the caller reads them as residuals where needed
        return [x if first or unknown(v, x) else _KNOWN for v, x in zip(jaxpr.outvars, outs)]
    return [x if unknown(v, x) else residual(v) for v, x in zip(jaxpr.outvars, outs)]


def _bind(eqn, ins) -> list:
    """The outputs of equation ``eqn`` on the values ``ins`` (as ``jax.core.eval_jaxpr``)."""
    outs = eqn.primitive.bind(*ins, **eqn.primitive.get_bind_params(eqn.params))
    return outs if eqn.primitive.multiple_results else [outs]


def _free_leaves(free, template) -> Callable | None:
    """The selector of the design leaves (a function returning a tuple of them; ``None`` for
    ``free = None``, every leaf); a one-line ``ValueError`` when ``free`` is not a function returning array leaves of the
    template."""
    if free is None:
        return None
    msg = (
        f"{_WHERE}: free = {free!r}: allowed None or a function of the template modifications "
        "returning some of its array leaves (e.g. lambda m: (m.pinion.tip_relief_depth,))"
    )

    def where(m):
        return tuple(jax.tree_util.tree_leaves(free(m)))

    picked = ()
    if callable(free):
        try:
            picked = where(template)
            eqx.tree_at(where, template, picked)
        except Exception as err:  # the selector's own error: named in one line
            raise ValueError(msg) from err
    if not picked or not all(isinstance(x, jax.Array | np.ndarray) for x in picked):
        raise ValueError(msg)
    return where
