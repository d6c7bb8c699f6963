"""Steady-state response of a dynamic model at one speed: :func:`simulate`."""

from __future__ import annotations

import jax.numpy as jnp

from .._contact import ContactLaw, ExactContact
from .._util import check_integer, check_real
from ._lumped import DynamicModel, LumpedRun
from ._model import AbstractDynamicModel, _prep
from ._result import DynamicResponse, checked
from ._settings import (
    DiffraxIntegrator,
    Newmark,
    Outputs,
    SteadyState,
    _config,
)
from ._sweep import _resolved, auto_steps_per_period, resolve_settings

__all__ = ["simulate", "simulate_on_table"]


def simulate(
    model: AbstractDynamicModel,
    speed,
    *,
    integrator: Newmark | DiffraxIntegrator | None = None,
    contact: ContactLaw | None = None,
    window: SteadyState | None = None,
    state0=None,
    outputs: Outputs = Outputs(),
    throw: bool = True,
    start_period: int = 0,
) -> DynamicResponse:
    """Steady-state dynamic response at one pinion speed.

    Args:
        model: a :class:`DynamicModel` or :class:`HybridModel` from :func:`dynamic_model`.
        speed: pinion speed Ω (rad/s), > 0, scalar (traced: no recompilation per speed).
        integrator: :class:`~jaxgear.dynamics.Newmark` or (lumped models)
            :class:`~jaxgear.dynamics.DiffraxIntegrator`. Default: automatic steps per period
            for a lumped model, the seed's 64 for a hybrid one. With automatic steps
            (``steps_per_period=None``: :func:`auto_steps_per_period`, needs a concrete speed)
            the result reports ``steps_per_mode_period`` and flags ``under_resolved`` (< 20).
        contact: :class:`~jaxgear.ExactContact` (active set, II-25; default, 100 passes for a
            lumped model, 50 for a hybrid one) or :class:`~jaxgear.SmoothContact` (for
            gradients and the diffrax solvers).
        window: :class:`~jaxgear.dynamics.SteadyState`: mesh periods integrated and kept
            (default 60 and 4 for a lumped model, which keeps >= 2; 20 and 4 for a hybrid one).
        state0: (X, Ẋ) to start from (lumped models; default: the static equilibrium, zero
            vibration velocity; a hybrid model starts from the quasi-static state at the speed).
        outputs: what the run records beside the statistics (:class:`Outputs`: the states at
            the kept steps (Newmark only), every mesh's cell loads there, the largest Hertzian
            pressure tracked in the time loop) and its divergence bound (``blowup``, result
            code 3). Default: none of them, blowup 100.
        throw: raise ``eqx.EquinoxRuntimeError`` on a non-zero result (``eqx.error_if``: works
            under ``jax.jit``, ``jax.vmap`` and ``jax.grad`` too).
        start_period: the mesh position of ``state0``, whole periods of the first mesh from
            the scene's start (an int >= 0; a lumped model with Newmark and a ``state0``: a
            settled sweep's final state, :attr:`SettledSweep.phase`); default 0.

    Returns:
        :class:`DynamicResponse`.

    Raises:
        ValueError: settings that are not settings objects, a window too short or a run too
            large (before any work); automatic steps with a traced speed; ``state0`` for a
            hybrid model; a ``pressure`` of another number of pairs than the scene's meshes.
        eqx.EquinoxRuntimeError: divergence or contact-loop failure (with ``throw``).
    """
    check_real("speed", speed, "rad/s", lo=0.0, lo_open=True, shape=(), where="simulate")
    settings = resolve_settings(model, integrator, contact, window, outputs)
    integrator, law, window, outputs = settings
    if state0 is not None and not model.continues:
        raise ValueError("state0: a hybrid model starts from its quasi-static state (allowed None)")
    check_integer("start_period", start_period, 0)
    if start_period and (state0 is None or not isinstance(integrator, Newmark)):
        raise ValueError(
            f"start_period = {start_period}: a Newmark run from a state0 only (allowed 0 "
            "without a state0 or with a diffrax solver)"
        )
    if start_period and not model.runs_from_position:  # what the model kind declares
        raise ValueError(
            f"start_period = {start_period}: a {type(model).__name__} runs from mesh position 0 "
            "(allowed 0)"
        )
    steps_per_period, modes = integrator.steps_per_period, None
    if steps_per_period is None:
        modes = model.averaged_modes()
        steps_per_period = int(auto_steps_per_period(model, speed, modes))
    if window.periods is None:
        window = _resolved(model, window, speed, steps_per_period, modes)
    prepared = model.prepare(integrator, law, window, steps_per_period, outputs, modes)
    dtype = model.dtype
    if state0 is not None:
        state0 = (jnp.asarray(state0[0], dtype), jnp.asarray(state0[1], dtype))
    if start_period:
        r = model.independent_at(
            prepared, jnp.asarray(speed, dtype), int(start_period) * steps_per_period, state0
        )[0]
    else:
        r = model.independent(prepared, jnp.asarray(speed, dtype), start=state0)
    return checked(r, "simulate") if throw else r


def simulate_on_table(
    model: DynamicModel,
    speed,
    steps_per_period: int,
    window: SteadyState,
    *,
    own_periods: bool = True,
    condensed: bool = True,
    contact: ContactLaw = ExactContact(),
):
    """:func:`simulate` of a lumped model at one speed with Newmark and ``steps_per_period``
    steps, on the table of each mesh's own period (what :func:`simulate` does) or, with
    ``own_periods=False``, on the long table of the span (every mesh at every step of it, as
    before the own-period tables); the contact problems (the static rows, the quasi-static
    reference at every step of the span, and each Newmark step's) solved on the structure
    condensed onto the coordinates the cells reach (what :func:`simulate` does) or, with
    ``condensed=False``, on every coordinate (as before): for comparisons and ``jaxgear bench
    trains``. Returns (:class:`DynamicResponse`, the prepared table and static rows)."""
    integrator, law, window, _ = resolve_settings(model, Newmark(steps_per_period), contact, window)
    cfg = _config(integrator, window, int(steps_per_period))
    prep = _prep(model, law, int(steps_per_period), own_periods, condensed)
    r = model.independent(LumpedRun(prep, law, cfg), jnp.asarray(speed, model.damping.dtype))
    return checked(r, "simulate"), prep
