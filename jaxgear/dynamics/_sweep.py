"""The entries of every dynamic model (:class:`~jaxgear.dynamics.DynamicModel` and
:class:`~jaxgear.dynamics.HybridModel`): speed sweeps (:func:`speed_sweep`: vmapped and
device-sharded independent speeds, continuation up and down), the smooth dynamic factor of a
speed band (:func:`band_dynamic_factor`), the automatic time step (:func:`auto_steps_per_period`)
and the modes it resolves (:func:`mesh_averaged_modes`). One speed: :func:`simulate`."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact, SmoothContact, contact_law
from .._util import check_integer, check_real
from ._modal import ModalAnalysis, excited_omega, steps_for_mode
from ._model import AbstractDynamicModel
from ._result import SweepResult, checked
from ._settings import (
    DiffraxIntegrator,
    HertzPressure,
    Newmark,
    Outputs,
    SteadyState,
    check_integrator,
    check_pressure,
    check_window,
)

__all__ = [
    "auto_steps_per_period",
    "band_dynamic_factor",
    "mesh_averaged_modes",
    "speed_sweep",
    "steps_multiple",
]

Model = AbstractDynamicModel


def resolve_settings(model, integrator, contact, window, states: bool = False):
    """The settings of a run on ``model``, checked, with the model kind's defaults for ``None``
    (:meth:`~jaxgear.dynamics.AbstractDynamicModel.default_settings`: a lumped model Newmark
    with automatic steps, the exact law (100 passes) and 60 periods with 4 kept; a hybrid
    model Newmark with the seed's 64 steps per mesh period (IV-27), the exact law (50 passes)
    and 20 periods with 4 kept). ``states``: the states are to be recorded (Newmark only).
    Returns (integrator, contact law in the model's dtype, window)."""
    if not isinstance(model, AbstractDynamicModel):
        raise ValueError(
            f"model = {type(model).__name__}: allowed a jaxgear.dynamics.DynamicModel or "
            "HybridModel (jaxgear.dynamics.dynamic_model)"
        )
    default_integrator, default_contact, default_window = model.default_settings()
    integrator = check_integrator(default_integrator if integrator is None else integrator)
    window = check_window(default_window if window is None else window)
    contact = default_contact if contact is None else contact
    model.check_integrator(integrator)
    q = model.span_periods()
    if window.keep_periods < q:
        why = (
            f"the meshes repeat together every {q} periods of the first mesh (a two-stage train)"
            if q == model.scene.scene_periods()
            else f"the manufacturing deviations span {q} mesh periods (dynamic_model's "
            "revolutions, or the hunting period of the deviating gears)"
        )
        raise ValueError(
            f"window keep_periods = {window.keep_periods}: {why}; allowed keep_periods >= {q}, "
            "so that the kept steps hold every mesh position"
        )
    if isinstance(integrator, DiffraxIntegrator) and any(p.coast for p in model.scene.base_planes):
        raise ValueError(
            "integrator: a diffrax solver with backlash (coast flanks) is not modelled: use "
            "jaxgear.dynamics.Newmark"
        )
    if states and isinstance(integrator, DiffraxIntegrator):
        raise ValueError("states = True: only Newmark records the states (integrator)")
    return integrator, contact_law(contact, model.dtype), window


def mesh_averaged_modes(
    model: Model,
    *,
    speed=0.0,
    positions_per_pitch: int = 64,
    contact: ContactLaw = ExactContact(),
) -> ModalAnalysis:
    """The modes of (M, K + K̄_m), K̄_m the loaded mesh stiffness averaged over one mesh period
    at the model's torque: the critical speeds, the Campbell diagram and the automatic time step
    read them.

    A lumped model's are its own (:attr:`DynamicModel.modes`, built by
    :func:`~jaxgear.dynamics.dynamic_model`; the arguments are not used). A hybrid model's are
    computed here (a dense eigen-analysis of the n structure coordinates): K̄_m over
    ``positions_per_pitch`` quasi-static positions at pinion ``speed`` (rad/s, the centrifugal
    load) with the ``contact`` law (:func:`~jaxgear.dynamics.mean_mesh_stiffness`).
    """
    return model.averaged_modes(
        speed=speed, positions_per_pitch=positions_per_pitch, contact=contact
    )


def auto_steps_per_period(model: Model, speeds, modes: ModalAnalysis | None = None) -> np.ndarray:
    """Automatic time steps per mesh period at each pinion speed (the default of
    :func:`~jaxgear.dynamics.simulate` and :func:`speed_sweep` for a lumped model, and with
    ``Newmark(None)`` for a hybrid one).

    N_s = the smallest D × 2^j >= max(64 r, 40 · f_max / f_mesh): at least 40 steps per
    period of the highest mode the mesh excites (f_max, mesh-energy share >= 5 %,
    :func:`~jaxgear.dynamics.excited_omega`) and 64 per period of the fastest mesh (f_mesh = Ω
    z1 / 2π, the first mesh's; r its periods per period of the first, 1 for a pair). D is 1
    (powers of two) but for a lumped train whose meshes have other periods than the first's
    (T_k/T_0 = p_k/q_k, :meth:`~jaxgear.scenes.Scene.mesh_periods`): D = lcm(q_k) (35 for
    the embedded ``two-stage``, 127/35), so that every mesh's period is a whole number of steps
    and the table holds each mesh over its own period instead of the span
    (:class:`~jaxgear.dynamics.MeshTable`; docs/trains.md, "Long spans"). The doublings keep
    the number of compiled programs small.

    Args:
        model: a dynamic model (concrete values: not under ``jax.jit``).
        speeds: pinion speed(s) Ω (rad/s), concrete.
        modes: the modes to resolve (default :func:`mesh_averaged_modes` of the model).

    Returns:
        int array of N_s, the shape of ``speeds``.

    Raises:
        ValueError: traced speeds or model (pass an explicit ``steps_per_period`` under jit).
    """
    try:
        sp = np.asarray(speeds, dtype=float)
        w = float(excited_omega(mesh_averaged_modes(model) if modes is None else modes))
        planes = model.scene.base_planes
        angle = float(planes[0].mesh_period_angle)
        # each mesh's periods per period of the first: its angle's rate over its period
        rates = [
            (float(b) - float(a)) * angle / float(p.mesh_period_angle)
            for a, b, p in zip(
                model.scene.mesh_angles(0.0), model.scene.mesh_angles(1.0), planes, strict=True
            )
        ]
    except (jax.errors.TracerArrayConversionError, jax.errors.ConcretizationTypeError) as err:
        raise ValueError(
            "steps_per_period=None (automatic) needs concrete speeds and model: under jax.jit, "
            "jax.vmap or jax.grad pass an explicit integer steps_per_period"
        ) from err
    return steps_for_mode(w, angle, sp, max(rates), steps_multiple(model))


def steps_multiple(model: Model) -> int:
    """D of :func:`auto_steps_per_period`: the least N_s dividing every mesh's period into
    whole steps, lcm of the denominators of T_k/T_0 (static); 1 for a hybrid model, a pair and
    a model with manufacturing deviations (tabulated over the span whatever N_s)."""
    return model.steps_multiple()


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
    model: Model,
    speeds,
    *,
    integrator: Newmark | DiffraxIntegrator | None = None,
    contact: ContactLaw | None = None,
    window: SteadyState | None = None,
    direction: str = "independent",
    states: bool = False,
    cell_loads: bool = False,
    pressure: HertzPressure | None = None,
    shard: bool = True,
    chunk_size: int | None = None,
    progress=None,
    blowup: float = 100.0,
    throw: bool = False,
) -> SweepResult:
    """Dynamic response over pinion speeds, for every model.

    Args:
        model: a :class:`DynamicModel` or :class:`HybridModel`
            (:func:`~jaxgear.dynamics.dynamic_model`).
        speeds: pinion speeds (rad/s) > 0, shape (S,), ascending for continuation sweeps.
        integrator, contact, window, blowup: as :func:`~jaxgear.dynamics.simulate` (``None``:
            the model kind's default, :func:`resolve_settings`). With automatic steps
            (``steps_per_period=None``) each speed gets its own N_s
            (:func:`auto_steps_per_period`, a power of two); speeds sharing an N_s are run
            together (one compilation per distinct N_s); the kept histories of a sweep with
            several N_s are subsampled to the smallest one (every speed's scalar outputs use its
            own full resolution); continuation carries the state across them.
        direction: "independent" (every speed from the static equilibrium: ``jax.vmap`` for a
            lumped model, ``jax.lax.map`` for a hybrid one (one n² effective compliance at a
            time); with several local devices and ``shard``, the speeds are placed across them
            with ``jax.sharding``: a lumped model's vmap is split, a hybrid model runs one row of
            speeds per device), or, lumped models only, "up"
            or "down" (continuation: each speed starts from the previous steady state,
            ``lax.scan``), or "both" (up and down; ``SweepResult.down`` in the order of
            ``speeds``; one vmap over the two scans when not chunked).
        states: also record the coordinates at the kept steps (``DynamicResult.states``;
            Newmark only).
        cell_loads, pressure: per-cell loads at the kept steps, the largest Hertzian
            pressure per speed, as :func:`~jaxgear.dynamics.simulate` (each speed's, with a
            leading speed axis; the pressure reduced inside the time loop, so a sweep with
            ``pressure`` and without ``cell_loads`` keeps no per-cell record).
        chunk_size: split the sweep into chunks of this many speeds (one compilation; the last
            chunk is padded), calling ``progress(n_done)`` after each (for a progress bar;
            Ctrl-C is honoured between chunks). Continuation carries the state across chunks.
        throw: raise when any speed fails (off by default: read ``results.result``).

    Returns:
        :class:`SweepResult`.

    Raises:
        ValueError: bad settings or speeds (before any work).
        eqx.EquinoxRuntimeError: with ``throw``, a failure code at some speed (the message
            names it).
    """
    if direction not in ("independent", "up", "down", "both"):
        raise ValueError(f"direction = {direction!r}: allowed 'independent', 'up', 'down', 'both'")
    integrator, law, window = resolve_settings(model, integrator, contact, window, states)
    pressure = check_pressure(pressure, len(model.scene.base_planes))
    if direction != "independent" and not model.continues:
        raise ValueError(
            f"direction = {direction!r}: a {type(model).__name__} sweeps independent speeds only "
            "(allowed 'independent')"
        )
    speeds = jnp.asarray(speeds, model.dtype)
    traced = isinstance(speeds, jax.core.Tracer)
    if (
        speeds.ndim != 1
        or speeds.shape[0] < 1
        or (not traced and not bool(np.all(np.asarray(speeds) > 0)))
    ):
        raise ValueError("speeds must be a non-empty 1-D array of pinion speeds > 0 (rad/s)")
    check_real("speeds", speeds, "rad/s", lo=0.0, lo_open=True, where="speed_sweep")  # finite
    if chunk_size is not None:
        check_integer("chunk_size", chunk_size, 1)
    if not blowup > 0:
        raise ValueError(f"blowup = {blowup!r}: allowed > 0")
    outputs = Outputs(bool(states), bool(cell_loads), pressure, blowup)
    sweep = _Sweep(model, shard, chunk_size)

    def fixed(sp, n, d, tick, modes=None, start=None):
        prepared = model.prepare(integrator, law, window, int(n), outputs, modes)
        return sweep.run(prepared, sp, d, tick, start)

    if integrator.steps_per_period is not None:
        return _thrown(fixed(speeds, integrator.steps_per_period, direction, progress), throw)
    modes = model.averaged_modes()
    ns = auto_steps_per_period(model, np.asarray(speeds), modes)
    if np.all(ns == ns[0]):
        return _thrown(fixed(speeds, ns[0], direction, progress, modes), throw)
    n_min = int(ns.min())
    done = [0]

    def run(sp, n, d, start=None):
        base = done[0]

        def tick(k):
            if progress is not None:
                progress(base + k)

        r = fixed(sp, n, d, tick, modes, start).results
        done[0] += int(sp.shape[0])
        return _subsample(r, int(n) // n_min)

    if direction == "independent":
        parts, order = [], []
        for n in np.unique(ns):
            idx = np.nonzero(ns == n)[0]
            parts.append(run(speeds[idx], n, "independent"))
            order.append(idx)
        inv = np.argsort(np.concatenate(order))
        return _thrown(
            SweepResult(speeds, jax.tree_util.tree_map(lambda *a: jnp.concatenate(a)[inv], *parts)),
            throw,
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
        return _thrown(SweepResult(speeds, continuation(speeds, ns)), throw)
    down = _flip(continuation(speeds[::-1], ns[::-1]))
    if direction == "down":
        return _thrown(SweepResult(speeds, down), throw)
    return _thrown(SweepResult(speeds, continuation(speeds, ns), down), throw)


def _thrown(res: SweepResult, throw: bool) -> SweepResult:
    """``res``, raising (``eqx.error_if``, also under ``jax.jit``: the check rides on the
    dynamic factors returned) when ``throw`` and a speed failed."""
    if not throw:
        return res

    down = None if res.down is None else checked(res.down, "speed_sweep")
    return SweepResult(res.speeds, checked(res.results, "speed_sweep"), down)


def band_dynamic_factor(
    model: Model,
    speeds,
    *,
    integrator: Newmark = Newmark(32),
    contact: ContactLaw = SmoothContact(1e-7, 50),
    window: SteadyState = SteadyState(20, 4),
    p: float = 16.0,
) -> Float[Array, ""]:
    """A smooth dynamic factor over a speed band, differentiable with respect to the
    modifications (and the torque) of the model: the objective of an optimisation over speeds.

    Per speed, the p-mean (mean of (F/F_s)^p)^(1/p) of the mesh force over the kept steps (a
    smooth lower bound of the dynamic factor that tends to it as p grows), for each mesh; over the
    speeds and meshes, the p-mean again (the worst speed and mesh, smoothly). The sweep of :func:`speed_sweep` with 32 fixed
    steps per period and the smooth contact law by default, for gradients.

    Args:
        model: a :class:`DynamicModel` or :class:`HybridModel`. speeds: the band's pinion
            speeds (rad/s), shape (S,). integrator: Newmark with a fixed ``steps_per_period``.
            contact, window: as :func:`speed_sweep`. p: the order of the p-means (>= 1).

    Returns:
        the band's dynamic factor (-), a scalar. Trace-safe (``jax.grad``, ``jax.jit``): the
        integer settings are checked, the speeds only when concrete.

    Raises:
        ValueError: automatic steps, p < 1, bad settings (before any computation).
    """
    if not p >= 1:
        raise ValueError(f"p = {p!r}: out of range, allowed >= 1")
    if not isinstance(integrator, Newmark) or integrator.steps_per_period is None:
        raise ValueError(
            f"integrator = {integrator!r}: allowed Newmark(steps_per_period=N), N an integer "
            ">= 4 (a fixed step count: the band is differentiated)"
        )
    r = speed_sweep(
        model, speeds, integrator=integrator, contact=contact, window=window, shard=False
    ).results
    # per speed and mesh, then over both (the worst mesh at the worst speed, smoothly)
    per_speed = jnp.stack(
        [
            jnp.mean((m.mesh_force / m.static_force[:, None]) ** p, axis=1) ** (1.0 / p)
            for m in r.meshes
        ],
        axis=1,
    )
    return jnp.mean(per_speed**p) ** (1.0 / p)


def _subsample(r, m: int):
    """Keep every m-th recorded step (ending on each period's last step) of a batched result;
    ``time_step`` becomes the spacing of the kept records, m Δt."""
    if m == 1:
        return r
    hist = ("time", "theta", "bearing_force", "rim_radial", "rim_axial")
    if r.states is not None:
        hist += ("states",)
    per_mesh = ("mesh_force", "transmission_error", "line_force", "static_te")
    if r.meshes[0].line_load is not None:
        per_mesh += ("line_load", "cell_s", "cell_z", "cell_mask")

    def records(x):
        leaves = [getattr(x, h) for h in hist]
        return leaves + [getattr(mesh, h) for mesh in x.meshes for h in per_mesh]

    r = eqx.tree_at(records, r, [a[:, m - 1 :: m] for a in records(r)])
    return eqx.tree_at(lambda x: x.time_step, r, r.time_step * m)


class _Sweep:
    """The speeds of a sweep at one resolved step count on any engine
    (:class:`~jaxgear.dynamics.AbstractDynamicModel`): independent speeds in one call (or in
    chunks, padded to whole rows of the local devices), continuation up, down or both (in
    chunks, carrying the state across them)."""

    def __init__(self, model: AbstractDynamicModel, shard: bool, chunk_size: int | None):
        self.model, self.shard, self.chunk_size = model, shard, chunk_size

    def run(self, prepared, speeds, direction: str, progress, start=None) -> SweepResult:
        """:class:`SweepResult` of ``speeds`` (S,) from ``start`` ((X, Ẋ); None: the model's
        own start), ``progress(n_done)`` after each chunk."""
        model = self.model

        def independent(sp):
            return model.independent(prepared, sp, start=start, shard=self.shard)

        def scan(sp, state=start):
            return model.continuation(prepared, sp, start=state)

        if self.chunk_size is None or isinstance(speeds, jax.core.Tracer):
            if direction == "independent":
                return SweepResult(speeds, independent(speeds))
            if direction == "up":
                return SweepResult(speeds, scan(speeds))
            if direction == "down":
                return SweepResult(speeds, _flip(scan(speeds[::-1])))
            both = scan(jnp.stack([speeds, speeds[::-1]]))  # one vmap over the two scans
            up = jax.tree_util.tree_map(lambda a: a[0], both)
            return SweepResult(speeds, up, jax.tree_util.tree_map(lambda a: a[1][::-1], both))

        size = int(self.chunk_size)
        if direction == "independent":
            n_dev = len(jax.local_devices()) if self.shard else 1
            size = -(-size // n_dev) * n_dev
            return SweepResult(speeds, in_chunks(independent, speeds, size, progress))

        def continuation(sp, base=0):
            state = start

            def run(ch):
                nonlocal state
                r = scan(ch, state)
                ok = bool(r.result[-1] == 0)
                state = (r.final_state[0][-1], r.final_state[1][-1]) if ok else start
                return r

            tick = None if progress is None else (lambda k: progress(base + k))
            return in_chunks(run, sp, size, tick)

        if direction == "up":
            return SweepResult(speeds, continuation(speeds))
        if direction == "down":
            return SweepResult(speeds, _flip(continuation(speeds[::-1])))
        # progress counts both passes: S + S
        S = speeds.shape[0]
        return SweepResult(speeds, continuation(speeds), _flip(continuation(speeds[::-1], S)))
