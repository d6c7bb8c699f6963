"""Speed sweeps: vmapped (and device-sharded) independent speeds, continuation up and down."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np

from .._contact import ContactLaw, ExactContact, contact_law
from .._util import check_integer
from ._model import DynamicModel
from ._settings import (
    DiffraxIntegrator,
    Newmark,
    SteadyState,
    _Config,
    _config,
    check_integrator,
    check_window,
)
from ._simulate import SweepResult, _prep, _run, _static_start, auto_steps_per_period

__all__ = ["speed_sweep"]


def _shard(speeds):
    devices = jax.local_devices()
    n = len(devices)
    pad = (-speeds.shape[0]) % n
    padded = jnp.concatenate([speeds, jnp.full((pad,), speeds[-1], speeds.dtype)])
    mesh = jax.sharding.Mesh(np.array(devices), ("speed",))
    sharding = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("speed"))
    return jax.device_put(padded, sharding), pad


def in_chunks(run, speeds, chunk_size: int, progress=None):
    """``run`` over ``speeds`` (S,) in chunks of ``chunk_size``, one call per chunk from a Python
    loop: the last chunk is padded with its last speed (every chunk runs the same compiled
    program) and the padding dropped; ``progress(n_done)`` after each chunk, and Ctrl-C is
    honoured between chunks. Returns the results concatenated along the speed axis (S, ...)."""
    n = speeds.shape[0]
    parts = []
    for k in range(0, n, chunk_size):
        part = speeds[k : k + chunk_size]
        padded = jnp.concatenate([part, jnp.full(chunk_size - part.shape[0], part[-1], part.dtype)])
        parts.append(jax.tree.map(lambda x, m=part.shape[0]: x[:m], run(padded)))
        jax.block_until_ready(parts[-1])
        if progress is not None:
            progress(k + part.shape[0])
    return jax.tree.map(lambda *xs: jnp.concatenate(xs), *parts)


def _flip(r):
    return jax.tree_util.tree_map(lambda a: a[::-1], r)


def speed_sweep(
    model: DynamicModel,
    speeds,
    *,
    integrator: Newmark | DiffraxIntegrator = Newmark(),
    contact: ContactLaw = ExactContact(),
    window: SteadyState = SteadyState(),
    direction: str = "independent",
    shard: bool = True,
    chunk_size: int | None = None,
    progress=None,
    blowup: float = 100.0,
) -> SweepResult:
    """Dynamic response over pinion speeds.

    Args:
        model: :class:`DynamicModel`.
        speeds: pinion speeds (rad/s), shape (S,), ascending for continuation sweeps.
        integrator, contact, window, blowup: as :func:`simulate`. With automatic steps
            (``integrator.steps_per_period=None``, the default) each speed gets its own N_s
            (:func:`~jaxgear.dynamics.auto_steps_per_period`, a power of two); speeds sharing an
            N_s are run together (one compilation per distinct N_s); the kept histories of a
            sweep with several N_s are subsampled to the smallest one (every speed's scalar
            outputs use its own full resolution); continuation carries the state across them.
        direction: "independent" (every speed from the static equilibrium, ``jax.vmap``, sharded
            over the local devices with ``jax.sharding`` when there are several and ``shard``),
            "up" or "down" (continuation: each speed starts from the previous steady state,
            ``lax.scan``), or "both" (up and down; ``SweepResult.down`` in the order of
            ``speeds``; one vmap over the two scans when not chunked).
        chunk_size: split the sweep into chunks of this many speeds (one compilation; the last
            chunk is padded), calling ``progress(n_done)`` after each (for a progress bar).
            Continuation carries the state across chunks.

    Returns:
        :class:`SweepResult` (never raises on divergence: read ``result`` per speed).

    Raises:
        ValueError: bad settings or speeds (before any work).
    """
    if direction not in ("independent", "up", "down", "both"):
        raise ValueError(f"direction = {direction!r}: allowed 'independent', 'up', 'down', 'both'")
    dtype = model.mesh.base_pitch.dtype
    speeds = jnp.asarray(speeds, dtype)
    if speeds.ndim != 1 or speeds.shape[0] < 1:
        raise ValueError("speeds must be a 1-D array of pinion speeds (rad/s)")
    integrator = check_integrator(integrator)
    window = check_window(window)
    law = contact_law(contact, dtype)
    if chunk_size is not None:
        check_integer("chunk_size", chunk_size, 1)
    common = {"shard": shard, "chunk_size": chunk_size}

    def cfg_of(n):
        return _config(integrator, window, int(n), blowup)

    if integrator.steps_per_period is not None:
        cfg = cfg_of(integrator.steps_per_period)
        return _fixed_sweep(
            model, speeds, law, cfg, direction=direction, progress=progress, **common
        )
    ns = auto_steps_per_period(model, np.asarray(speeds))
    if np.all(ns == ns[0]):
        cfg = cfg_of(ns[0])
        return _fixed_sweep(
            model, speeds, law, cfg, direction=direction, progress=progress, **common
        )
    n_min = int(ns.min())
    done = [0]

    def run(sp, n, d, start=None):
        base = done[0]

        def tick(k):
            if progress is not None:
                progress(base + k)

        r = _fixed_sweep(
            model, sp, law, cfg_of(n), direction=d, progress=tick, start=start, **common
        ).results
        done[0] += int(sp.shape[0])
        return _subsample(r, int(n) // n_min)

    if direction == "independent":
        parts, order = [], []
        for n in np.unique(ns):
            idx = np.nonzero(ns == n)[0]
            parts.append(run(speeds[idx], n, "independent"))
            order.append(idx)
        inv = np.argsort(np.concatenate(order))
        return SweepResult(
            speeds, jax.tree_util.tree_map(lambda *a: jnp.concatenate(a)[inv], *parts)
        )

    def continuation(sp, n_s):
        # runs of equal N_s in sweep order, each continuing from the previous run's last state
        cuts = np.nonzero(np.diff(n_s))[0] + 1
        parts, start = [], None
        for idx in np.split(np.arange(sp.shape[0]), cuts):
            r = run(sp[idx], n_s[idx[0]], "up", start)
            ok = bool(r.result[-1] == 0)
            start = (r.final_state[0][-1], r.final_state[1][-1]) if ok else None
            parts.append(r)
        return jax.tree_util.tree_map(lambda *a: jnp.concatenate(a), *parts)

    if direction == "up":
        return SweepResult(speeds, continuation(speeds, ns))
    down = _flip(continuation(speeds[::-1], ns[::-1]))
    if direction == "down":
        return SweepResult(speeds, down)
    return SweepResult(speeds, continuation(speeds, ns), down)


def _subsample(r, m: int):
    """Keep every m-th recorded step (ending on each period's last step) of a batched result."""
    if m == 1:
        return r
    hist = ("time", "theta", "mesh_force", "transmission_error", "line_force", "static_te")
    hist += ("bearing_force",)
    return eqx.tree_at(
        lambda x: [getattr(x, h) for h in hist],
        r,
        [getattr(r, h)[:, m - 1 :: m] for h in hist],
    )


def _fixed_sweep(
    model: DynamicModel,
    speeds,
    law: ContactLaw,
    cfg: _Config,
    *,
    direction: str,
    shard: bool,
    chunk_size: int | None,
    progress,
    start=None,
) -> SweepResult:
    """The sweep at one resolved step count (``cfg``), from ``start`` (default: the static
    equilibrium)."""
    dtype = model.mesh.base_pitch.dtype
    speeds = jnp.asarray(speeds, dtype)
    if speeds.ndim != 1 or speeds.shape[0] < 1:
        raise ValueError("speeds must be a 1-D array of pinion speeds (rad/s)")
    S = speeds.shape[0]
    n_dev = len(jax.local_devices()) if shard else 1
    prep = _prep(model, law, cfg.steps_per_period)
    if start is None:
        start = _static_start(prep)

    def independent(sp):
        if n_dev > 1:
            padded, _ = _shard(sp)
            r = _run(model, prep, padded, start, law, cfg, "vmap")
            return jax.tree_util.tree_map(lambda a: a[: sp.shape[0]], r)
        return _run(model, prep, sp, start, law, cfg, "vmap")

    if chunk_size is None:
        if direction == "independent":
            return SweepResult(speeds, independent(speeds))
        if direction == "up":
            return SweepResult(speeds, _run(model, prep, speeds, start, law, cfg, "continuation"))
        if direction == "down":
            return SweepResult(
                speeds, _flip(_run(model, prep, speeds[::-1], start, law, cfg, "continuation"))
            )
        up, down = _run(model, prep, speeds, start, law, cfg, "both")
        return SweepResult(speeds, up, down)

    size = int(chunk_size)
    if direction == "independent":
        size = -(-size // n_dev) * n_dev

    def continuation(sp, base=0):
        state = start

        def run(ch):
            nonlocal state
            r = _run(model, prep, ch, state, law, cfg, "continuation")
            ok = bool(r.result[-1] == 0)
            state = (r.final_state[0][-1], r.final_state[1][-1]) if ok else start
            return r

        tick = None if progress is None else (lambda k: progress(base + k))
        return in_chunks(run, sp, size, tick)

    if direction == "independent":
        return SweepResult(speeds, in_chunks(independent, speeds, size, progress))
    if direction == "up":
        return SweepResult(speeds, continuation(speeds))
    if direction == "down":
        return SweepResult(speeds, _flip(continuation(speeds[::-1])))
    # progress counts both passes: S + S
    return SweepResult(speeds, continuation(speeds), _flip(continuation(speeds[::-1], S)))
