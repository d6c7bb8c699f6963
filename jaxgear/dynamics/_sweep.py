"""The entries of every dynamic model (:class:`~jaxgear.dynamics.DynamicModel` and
:class:`~jaxgear.dynamics.HybridModel`): speed sweeps (:func:`speed_sweep`: vmapped and
device-sharded independent speeds, continuation up and down), the smooth dynamic factor of a
speed band (:func:`band_dynamic_factor`), the automatic time step (:func:`auto_steps_per_period`)
and the modes it resolves (:func:`mesh_averaged_modes`). One speed: :func:`simulate`."""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import (
    AbstractContactLaw,
    ContactLaw,
    ExactContact,
    SmoothContact,
    contact_law,
)
from .._util import check_real, compiled_when_eager
from ._modal import ModalAnalysis, excited_omega, steps_for_mode
from ._model import AbstractDynamicModel, band_refusal
from ._result import SweepResult, checked, thinned
from ._settings import (
    Batching,
    DiffraxIntegrator,
    Newmark,
    Outputs,
    SteadyState,
    check_batching,
    check_integrator,
    check_outputs,
    check_window,
)

__all__ = [
    "DIRECTIONS",
    "AbstractDirection",
    "Both",
    "Down",
    "Independent",
    "Up",
    "auto_steps_per_period",
    "band_dynamic_factor",
    "mesh_averaged_modes",
    "resolve_settings",
    "speed_sweep",
    "steps_multiple",
]

Model = AbstractDynamicModel


class _Passes(abc.ABC):
    """The passes a sweep can make over its speeds (S,) (:attr:`speeds`), each returning the
    batched records of every speed in the order of :attr:`speeds` (leading axis S): the ways of
    running them (in one call, in chunks, in runs of equal automatic step count) implement it,
    an :class:`AbstractDirection` picks the passes."""

    speeds: Array

    @abc.abstractmethod
    def independent(self):
        """Every speed from the model's own start."""

    @abc.abstractmethod
    def ascending(self):
        """Continuation from the first speed to the last, each from the previous steady
        state."""

    @abc.abstractmethod
    def descending(self):
        """Continuation from the last speed to the first, records in the order of
        :attr:`speeds`."""

    def both(self) -> tuple:
        """(:meth:`ascending`, :meth:`descending`)."""
        return self.ascending(), self.descending()


class AbstractDirection(eqx.Module):
    """How :func:`speed_sweep` passes over its speeds (the pattern of diffrax's
    ``AbstractSolver``: a new way of sweeping is one more subclass, not a branch in the sweep).

    Implementations: :class:`Independent` (every speed from the static equilibrium), and, for
    models that continue (:attr:`~jaxgear.dynamics.AbstractDynamicModel.continues`), the
    continuation sweeps :class:`Up`, :class:`Down` and :class:`Both`. The case file's and the
    CLI's names (``--direction``) map to them in :data:`DIRECTIONS`."""

    #: whether the sweep continues from one speed's steady state to the next (a model must
    #: have :attr:`~jaxgear.dynamics.AbstractDynamicModel.continues`)
    continues: ClassVar[bool] = True

    @abc.abstractmethod
    def sweep(self, passes: _Passes) -> SweepResult:
        """The :class:`SweepResult` of ``passes.speeds`` from the passes this direction makes."""


class Independent(AbstractDirection):
    """Every speed from the static equilibrium, independently (``jax.vmap`` for a lumped model,
    ``jax.lax.map`` for a hybrid one, sharded over the local devices): the default."""

    continues: ClassVar[bool] = False

    def sweep(self, passes: _Passes) -> SweepResult:
        return SweepResult(passes.speeds, passes.independent())


class Up(AbstractDirection):
    """Continuation up: each speed (ascending) from the previous speed's steady state
    (``lax.scan``); a failed speed restarts the next from the static equilibrium."""

    def sweep(self, passes: _Passes) -> SweepResult:
        return SweepResult(passes.speeds, passes.ascending())


class Down(AbstractDirection):
    """Continuation down: from the last speed to the first, each from the previous steady
    state; the records in the order of the speeds."""

    def sweep(self, passes: _Passes) -> SweepResult:
        return SweepResult(passes.speeds, passes.descending())


class Both(AbstractDirection):
    """Continuation up and down (:class:`Up` in ``SweepResult.results``, :class:`Down` in
    ``SweepResult.down``, both in the order of the speeds; one vmap over the two scans when not
    chunked): the jump phenomena of a nonlinear resonance."""

    def sweep(self, passes: _Passes) -> SweepResult:
        return SweepResult(passes.speeds, *passes.both())


#: the sweep directions by the names of the case files and the CLI (``--direction``): the one
#: place those names map to objects (for :mod:`jaxgear.io`)
DIRECTIONS = {"independent": Independent(), "up": Up(), "down": Down(), "both": Both()}


def resolve_settings(model, integrator, contact, window, outputs: Outputs = Outputs()):
    """The settings of a run on ``model``, checked, with the model kind's defaults for ``None``
    (:meth:`~jaxgear.dynamics.AbstractDynamicModel.default_settings`: a lumped model Newmark
    with automatic steps, the exact law (100 passes) and 60 periods with 4 kept; a hybrid
    model Newmark with the seed's 64 steps per mesh period (IV-27), the exact law (50 passes)
    and 20 periods with 4 kept); ``outputs``: what the run records (:class:`Outputs`, checked:
    the states with Newmark only, a pressure of the scene's meshes).
    Returns (integrator, contact law in the model's dtype, window, outputs)."""
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
    if isinstance(contact, AbstractContactLaw) and not model.runs(contact):
        allowed = ", ".join(f"{c.__name__}(...)" for c in model.contact_laws)
        raise ValueError(f"contact = {type(contact).__name__}(...): a {type(model).__name__} "
                         f"does not run it (allowed {allowed})")
    q = model.span_periods()
    if window.keep_periods < q:
        why = (
            f"the meshes repeat together every {q} periods of the first mesh (a two-stage train)"
            if q == model.scene_periods()
            else f"the manufacturing deviations span {q} mesh periods (dynamic_model's "
            "revolutions, or the hunting period of the deviating gears)"
        )
        raise ValueError(
            f"window keep_periods = {window.keep_periods}: {why}; allowed keep_periods >= {q}, "
            "so that the kept steps hold every mesh position"
        )
    if isinstance(integrator, DiffraxIntegrator) and model.coast_flanks():
        raise ValueError(
            "integrator: a diffrax solver with backlash (coast flanks) is not modelled: use "
            "jaxgear.dynamics.Newmark"
        )
    if window.periods is None and not model.automatic_span:
        raise ValueError(
            f"window periods = None (the automatic span): a {type(model).__name__} has no "
            "settling rule; allowed an integer >= 2"
        )
    outputs = check_outputs(outputs, model.mesh_count())
    if outputs.states and isinstance(integrator, DiffraxIntegrator):
        raise ValueError("states = True: only Newmark records the states (integrator)")
    return integrator, contact_law(contact, model.dtype), window, outputs


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
    period (the model's :meth:`~jaxgear.dynamics.AbstractDynamicModel.steps_per_mode`) of
    the highest mode the mesh excites (f_max, mesh-energy share >= 5 %,
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
        angle = float(model.mesh_period_angle())
        # each mesh's periods per period of the first: its angle's rate over its period
        rates = [float(r) for r in model.mesh_rates()]
    except (jax.errors.TracerArrayConversionError, jax.errors.ConcretizationTypeError) as err:
        raise ValueError(
            "steps_per_period=None (automatic) needs concrete speeds and model: under jax.jit, "
            "jax.vmap or jax.grad pass an explicit integer steps_per_period"
        ) from err
    return steps_for_mode(
        w, angle, sp, max(rates), steps_multiple(model), int(model.steps_per_mode())
    )


def steps_multiple(model: Model) -> int:
    """D of :func:`auto_steps_per_period`: the least N_s dividing every mesh's period into
    whole steps, lcm of the denominators of T_k/T_0 (static); 1 for a hybrid model, a pair and
    a model with manufacturing deviations (tabulated over the span whatever N_s)."""
    return model.steps_multiple()


def _host(tree):
    """The arrays of ``tree`` as NumPy arrays (a copy to the host; nothing compiled)."""
    return jax.tree.map(np.asarray, tree)


def _device(tree):
    """The arrays of ``tree`` as JAX arrays on the default device (``jax.device_put``, a copy:
    ``jnp.asarray`` of a NumPy array compiles a program per shape)."""
    return jax.tree.map(jax.device_put, tree)


def in_chunks(run, speeds, chunk_size: int, progress=None):
    """``run`` over ``speeds`` (S,) in chunks of ``chunk_size``, one call per chunk from a Python
    loop: the last chunk is padded with its last speed (every chunk runs the same compiled
    program) and the padding dropped; ``progress(n_done)`` after each chunk, and Ctrl-C is
    honoured between chunks. Returns the results concatenated along the speed axis (S, ...).
    The chunks are cut, trimmed and joined on the host (NumPy): a compiled program per chunk
    and leaf shape for these copies would cost more than the copies."""
    sp = np.asarray(speeds)
    n = sp.shape[0]
    parts = []
    for k in range(0, n, chunk_size):
        part = sp[k : k + chunk_size]
        padded = np.concatenate([part, np.full(chunk_size - part.shape[0], part[-1], part.dtype)])
        parts.append(
            jax.tree.map(lambda x, m=part.shape[0]: x[:m], _host(run(jax.device_put(padded))))
        )
        if progress is not None:
            progress(k + part.shape[0])
    return _device(jax.tree.map(lambda *xs: np.concatenate(xs), *parts))


def _flip(r):
    return jax.tree_util.tree_map(lambda a: a[::-1], r)


#: :func:`_flip` of a result on the device, in one program (not one per leaf)
_flip_on_device = compiled_when_eager(_flip)


@compiled_when_eager
def _split_scans(both):
    """Two scans side by side (leading axis 2) cut into the ascending and the descending pass,
    the latter in the order of the speeds (one program, not one per leaf)."""
    up = jax.tree_util.tree_map(lambda a: a[0], both)
    return up, jax.tree_util.tree_map(lambda a: a[1][::-1], both)


def speed_sweep(
    model: Model,
    speeds,
    *,
    integrator: Newmark | DiffraxIntegrator | None = None,
    contact: ContactLaw | None = None,
    window: SteadyState | None = None,
    direction: AbstractDirection = Independent(),
    outputs: Outputs = Outputs(),
    batching: Batching = Batching(),
    throw: bool = False,
) -> SweepResult:
    """Dynamic response over pinion speeds, for every model.

    Args:
        model: a :class:`DynamicModel` or :class:`HybridModel`
            (:func:`~jaxgear.dynamics.dynamic_model`).
        speeds: pinion speeds (rad/s) > 0, shape (S,), ascending for continuation sweeps.
        integrator, contact, window, outputs: as :func:`~jaxgear.dynamics.simulate` (``None``:
            the model kind's default, :func:`resolve_settings`). With automatic steps
            (``steps_per_period=None``) each speed gets its own N_s
            (:func:`auto_steps_per_period`, a power of two); speeds sharing an N_s are run
            together (a lumped model with Newmark: one compiled program for every N_s,
            :meth:`~jaxgear.dynamics.AbstractDynamicModel.prepare_steps`; else one compilation
            per distinct N_s); the kept histories of a sweep with
            several N_s are subsampled to the smallest one (every speed's scalar outputs use its
            own full resolution); continuation carries the state across them.
        direction: how the speeds are passed (:class:`AbstractDirection`):
            :class:`Independent` (default; every speed from the static equilibrium:
            ``jax.vmap`` for a lumped model, ``jax.lax.map`` for a hybrid one (one n² effective
            compliance at a time); with several local devices and ``batching.shard``, the speeds are
            placed across them with ``jax.sharding``: a lumped model's vmap is split, a hybrid
            model runs one row of speeds per device), or, lumped models only, :class:`Up` or
            :class:`Down` (continuation: each speed starts from the previous steady state,
            ``lax.scan``), or :class:`Both` (up and down; ``SweepResult.down`` in the order of
            ``speeds``; one vmap over the two scans when not chunked). By name (a case file,
            ``--direction``): :data:`DIRECTIONS`.
            The outputs of each speed (:class:`Outputs`: states, cell loads, the largest
            Hertzian pressure) with a leading speed axis.
        batching: how the speeds are run (:class:`Batching`: in chunks with a progress
            callback, sharded over the local devices (default) or not).
        throw: raise when any speed fails (off by default: read ``results.result``).

    Returns:
        :class:`SweepResult`.

    Raises:
        ValueError: bad settings or speeds (before any work).
        eqx.EquinoxRuntimeError: with ``throw``, a failure code at some speed (the message
            names it).
    """
    if not isinstance(direction, AbstractDirection):
        raise ValueError(
            f"direction = {direction!r}: allowed a jaxgear.dynamics direction (Independent(), "
            "Up(), Down(), Both(); by name: jaxgear.dynamics.DIRECTIONS)"
        )
    settings = resolve_settings(model, integrator, contact, window, outputs)
    integrator, law, window, outputs = settings
    batching = check_batching(batching)
    if direction.continues and not model.continues:
        raise ValueError(
            f"direction = {direction!r}: a {type(model).__name__} sweeps independent speeds only "
            "(allowed Independent())"
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
    # chunks are a Python loop over concrete speeds
    chunk_size = None if traced else batching.chunk_size
    progress = batching.progress

    def at_steps(n, modes=None, size=None) -> _Sweep:  # size: for one_program's
        prepared = model.prepare(integrator, law, window, int(n), outputs, modes)
        return _Sweep(model, prepared, batching.shard, chunk_size)

    if integrator.steps_per_period is not None:
        if window.periods is None:
            window = _resolved(model, window, speeds, integrator.steps_per_period, None)
        passes = at_steps(integrator.steps_per_period).passes(speeds, progress)
        return _thrown(direction.sweep(passes), throw)
    modes = model.averaged_modes()
    ns = auto_steps_per_period(model, np.asarray(speeds), modes)
    if window.periods is None:
        window = _resolved(model, window, speeds, ns, modes)
    if np.all(ns == ns[0]):
        return _thrown(direction.sweep(at_steps(ns[0], modes).passes(speeds, progress)), throw)
    # several N_s: one program for all where the kind can (N_s an argument of it), the speeds
    # of each N_s in calls of one size (chunks: the batching's, or the largest group's)
    steps = model.prepare_steps(integrator, law, window, tuple(np.unique(ns)), outputs, modes)

    def one_program(n, modes=None, size=None) -> _Sweep:
        return _Sweep(model, steps(int(n)), batching.shard, chunk_size or size)

    make = at_steps if steps is None else one_program
    mixed = _MixedSteps(make, modes, speeds, ns, progress, thinned=steps is not None)
    return _thrown(direction.sweep(mixed), throw)


def _resolved(model: Model, window: SteadyState, speeds, steps, modes):
    """:meth:`~jaxgear.dynamics.AbstractDynamicModel.resolve_window` of an automatic span over
    the concrete ``speeds`` at ``steps`` (an int: every speed's, or (S,))."""
    if isinstance(speeds, jax.core.Tracer):
        raise ValueError(
            "window periods = None (the automatic span) needs concrete speeds: under jax.jit, "
            "jax.vmap or jax.grad pass a window of whole periods"
        )
    sp = np.atleast_1d(np.asarray(speeds, dtype=float))
    ns = np.broadcast_to(np.asarray(steps, dtype=int), sp.shape)
    return model.resolve_window(window, sp, ns, modes)


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
        model: a kind with :attr:`~AbstractDynamicModel.band_factor` (a :class:`DynamicModel`
            or :class:`HybridModel`: each mesh's force over its static force,
            :meth:`~AbstractDynamicModel.mesh_force_ratios`). speeds: the band's pinion
            speeds (rad/s), shape (S,). integrator: Newmark with a fixed ``steps_per_period``.
            contact, window: as :func:`speed_sweep`. p: the order of the p-means (>= 1).

    Returns:
        the band's dynamic factor (-), a scalar. Trace-safe (``jax.grad``, ``jax.jit``): the
        integer settings are checked, the speeds only when concrete.

    Raises:
        TypeError: ``model`` not an :class:`AbstractDynamicModel`. ValueError: a kind without
            :attr:`~AbstractDynamicModel.band_factor` (a planetary stage, a gearbox), automatic
            steps, p < 1, bad settings (before any computation; one line each).
    """
    if not isinstance(model, AbstractDynamicModel):
        raise TypeError(
            f"model: {type(model).__name__}: allowed a jaxgear.dynamics.AbstractDynamicModel "
            "(a lumped DynamicModel, a HybridModel)"
        )
    if not model.band_factor:  # what the model kind declares, before any work
        raise ValueError(band_refusal(model))
    if not p >= 1:
        raise ValueError(f"p = {p!r}: out of range, allowed >= 1")
    if not isinstance(integrator, Newmark) or integrator.steps_per_period is None:
        raise ValueError(
            f"integrator = {integrator!r}: allowed Newmark(steps_per_period=N), N an integer "
            ">= 4 (a fixed step count: the band is differentiated)"
        )
    r = speed_sweep(
        model,
        speeds,
        integrator=integrator,
        contact=contact,
        window=window,
        batching=Batching(shard=False),
    ).results
    # per speed and mesh, then over both (the worst mesh at the worst speed, smoothly)
    per_speed = jnp.stack(
        [jnp.mean(f**p, axis=1) ** (1.0 / p) for f in model.mesh_force_ratios(r)], axis=1
    )
    return jnp.mean(per_speed**p) ** (1.0 / p)


def _subsample(r, m: int):
    """Keep every m-th recorded step (ending on each period's last step) of a batched result;
    ``time_step`` becomes the spacing of the kept records, m Δt."""
    if m == 1:
        return r
    return thinned(r, m, lambda a, m: np.asarray(a)[:, m - 1 :: m])


class _Sweep:
    """A sweep's model at one resolved step count (``prepared`` by
    :meth:`~jaxgear.dynamics.AbstractDynamicModel.prepare`), with how its speeds are run: placed
    over the local devices (``shard``) and split into chunks of ``chunk_size`` speeds (None: in
    one call)."""

    def __init__(self, model: AbstractDynamicModel, prepared, shard: bool, chunk_size):
        self.model, self.prepared, self.shard, self.chunk_size = model, prepared, shard, chunk_size

    def independent(self, speeds, start=None):
        """Each of ``speeds`` (S,) from ``start`` ((X, Ẋ); None: the model's own start)."""
        return self.model.independent(self.prepared, speeds, start=start, shard=self.shard)

    def scan(self, speeds, start=None):
        """Continuation over ``speeds`` (S,), or (2, S) two scans side by side, from ``start``."""
        return self.model.continuation(self.prepared, speeds, start=start)

    def passes(self, speeds, progress, start=None) -> _Passes:
        """The passes over ``speeds`` (S,) from ``start``, ``progress(n_done)`` after each chunk
        (chunked sweeps only)."""
        if self.chunk_size is None:
            return _Whole(self, speeds, start)
        return _Chunked(self, speeds, start, progress)


class _Whole(_Passes):
    """The passes in one call each (the two continuation passes of :meth:`both` in one vmap
    over two scans)."""

    def __init__(self, sweep: _Sweep, speeds, start):
        self.sweep, self.speeds, self.start = sweep, speeds, start

    def independent(self):
        return self.sweep.independent(self.speeds, self.start)

    def ascending(self):
        return self.sweep.scan(self.speeds, self.start)

    def descending(self):
        return _flip_on_device(self.sweep.scan(self.speeds[::-1], self.start))

    def both(self) -> tuple:
        both = self.sweep.scan(jnp.stack([self.speeds, self.speeds[::-1]]), self.start)
        return _split_scans(both)


class _Chunked(_Passes):
    """The passes in chunks of ``sweep.chunk_size`` speeds (:func:`in_chunks`: one compiled
    program, the last chunk padded), ``progress(n_done)`` after each; independent chunks padded
    to whole rows of the local devices, continuation carrying the state across chunks (a failed
    chunk end restarts from ``start``). :meth:`both` counts its two passes S + S."""

    def __init__(self, sweep: _Sweep, speeds, start, progress):
        self.sweep, self.speeds, self.start, self.progress = sweep, speeds, start, progress

    def independent(self):
        n_dev = len(jax.local_devices()) if self.sweep.shard else 1
        size = -(-int(self.sweep.chunk_size) // n_dev) * n_dev

        def run(sp):
            return self.sweep.independent(sp, self.start)

        return in_chunks(run, self.speeds, size, self.progress)

    def _continuation(self, speeds, base: int):
        state = self.start

        def run(ch):
            nonlocal state
            r = _host(self.sweep.scan(ch, state))
            ok = bool(r.result[-1] == 0)
            last = _device((r.final_state[0][-1], r.final_state[1][-1]))
            state = last if ok else self.start
            return r

        progress = self.progress
        tick = None if progress is None else (lambda k: progress(base + k))
        return in_chunks(run, speeds, int(self.sweep.chunk_size), tick)

    def ascending(self):
        return self._continuation(self.speeds, 0)

    def descending(self):
        return _flip(self._continuation(self.speeds[::-1], 0))

    def both(self) -> tuple:
        S = self.speeds.shape[0]
        return self._continuation(self.speeds, 0), _flip(self._continuation(self.speeds[::-1], S))


def _call_size(counts, steps, slack: float = 1.1) -> int:
    """Speeds per call of a one-program mixed sweep (every call one size: one program): the
    largest size whose padded work, the steps run counting the padding of each group's last
    call (sum over groups of N_s · ceil(count/size) · size), is within ``slack`` of the least.
    Padding every group to the largest one instead could run several times the steps where a
    small group has a large N_s. ``counts``, ``steps``: the speeds and N_s of each group."""
    sizes = range(1, max(counts) + 1)
    work = [sum(int(n) * -(-c // s) * s for c, n in zip(counts, steps)) for s in sizes]
    least = min(work)
    return max(s for s, w in zip(sizes, work) if w <= slack * least)


class _MixedSteps(_Passes):
    """The passes of a sweep whose speeds have different automatic step counts ``ns`` (S,): the
    speeds sharing an N_s run together (``at_steps(n, modes, size)`` their :class:`_Sweep`:
    one compiled program for every N_s where the model kind takes N_s as an argument,
    :meth:`~jaxgear.dynamics.AbstractDynamicModel.prepare_steps`, ``thinned``: its histories
    come at the smallest N_s, its calls padded to ``size`` speeds; else one program per N_s),
    the kept histories subsampled to the smallest N_s; continuation runs the runs of equal N_s
    in sweep order, each from the previous run's last state; ``progress(n_done)`` counts every
    speed run."""

    def __init__(self, at_steps, modes, speeds, ns, progress, thinned: bool = False):
        self.at_steps, self.modes, self.speeds, self.ns = at_steps, modes, speeds, ns
        self.progress, self.n_min, self.done = progress, int(ns.min()), 0
        self.host_speeds = np.asarray(speeds)
        self.thinned = thinned

    def _records(self, idx, n, pass_, start=None, size=None):
        """The records of the speeds ``idx`` (indices into :attr:`speeds`, or a slice) at N_s =
        ``n``: ``pass_(passes)`` of their :class:`_Passes` (calls of ``size`` speeds where the
        program takes N_s), subsampled, on the host (NumPy: the runs of other N_s have other
        record lengths, and a compiled program per leaf shape for these copies would cost more
        than the copies)."""
        base = self.done

        def tick(k):
            if self.progress is not None:
                self.progress(base + k)

        speeds = jax.device_put(self.host_speeds[idx])
        r = pass_(self.at_steps(n, self.modes, size).passes(speeds, tick, start))
        self.done += int(speeds.shape[0])
        return _subsample(_host(r), 1 if self.thinned else int(n) // self.n_min)

    def independent(self):
        parts, order = [], []
        groups = [np.nonzero(self.ns == n)[0] for n in np.unique(self.ns)]
        size = _call_size([g.shape[0] for g in groups], [self.ns[g[0]] for g in groups])
        for idx in groups:
            parts.append(self._records(idx, self.ns[idx[0]], lambda p: p.independent(), None, size))
            order.append(idx)
        inv = np.argsort(np.concatenate(order))
        return _device(jax.tree_util.tree_map(lambda *a: np.concatenate(a)[inv], *parts))

    def _continuation(self, order, n_s):
        # runs of equal N_s in sweep order (``order``: the indices of the speeds in it), each
        # continuing from the previous run's last state
        cuts = np.nonzero(np.diff(n_s))[0] + 1
        parts, start = [], None
        runs = np.split(np.arange(order.shape[0]), cuts)
        size = _call_size([run.shape[0] for run in runs], [n_s[run[0]] for run in runs])
        for run in runs:
            r = self._records(order[run], n_s[run[0]], lambda p: p.ascending(), start, size)
            ok = bool(r.result[-1] == 0)
            start = _device((r.final_state[0][-1], r.final_state[1][-1]))
            start = start if ok else None
            parts.append(r)
        return jax.tree_util.tree_map(lambda *a: np.concatenate(a), *parts)

    def ascending(self):
        return _device(self._continuation(np.arange(self.ns.shape[0]), self.ns))

    def descending(self):
        order = np.arange(self.ns.shape[0])[::-1]
        return _device(_flip(self._continuation(order, self.ns[::-1])))

    def both(self) -> tuple:
        down = self.descending()  # down first, as before (the progress counts it first)
        return self.ascending(), down
