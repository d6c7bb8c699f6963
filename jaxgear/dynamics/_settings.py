"""The settings of the dynamics, as objects (the way ``diffrax.diffeqsolve`` takes a solver, a
step-size controller and ``SaveAt``): the integrator (:class:`Newmark` or
:class:`DiffraxIntegrator`) and the steady-state window (:class:`SteadyState`); the contact law
is :class:`jaxgear.ExactContact` or :class:`jaxgear.SmoothContact`, the damping
:class:`jaxgear.dynamics.Damping`, and the operating point (torque, speed) an argument of the
solvers. Also the run-size guard and the divergence checks the integrators share.
"""

from __future__ import annotations

import dataclasses
import os

import equinox as eqx
import jax.numpy as jnp

from .._util import check_integer

__all__ = [
    "DIFFRAX_SOLVERS",
    "MAX_STEPS_PER_SPEED",
    "DiffraxIntegrator",
    "Newmark",
    "SteadyState",
    "check_run_size",
]

# time steps one speed may integrate (periods × steps per mesh period): 2^22 is hours of Newmark
MAX_STEPS_PER_SPEED = 2**22

DIFFRAX_SOLVERS = {
    "tsit5": "Tsit5",
    "dopri5": "Dopri5",
    "dopri8": "Dopri8",
    "bosh3": "Bosh3",
    "heun": "Heun",
    "midpoint": "Midpoint",
    "ralston": "Ralston",
    "euler": "Euler",
    "kvaerno3": "Kvaerno3",
    "kvaerno4": "Kvaerno4",
    "kvaerno5": "Kvaerno5",
    "implicit_euler": "ImplicitEuler",
}


def _memory_bytes() -> float:
    """The machine's physical memory (bytes); inf where the platform does not tell."""
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - non-POSIX
        return float("inf")


def check_run_size(periods: int, steps_per_period: int, recorded_steps: int, values: int) -> None:
    """Refuse, before any work, a run that cannot finish: more than
    :data:`MAX_STEPS_PER_SPEED` time steps per speed, or records (``recorded_steps`` ×
    ``values`` float64 per speed) above half the machine's memory. One-line ``ValueError`` that
    names the settings to change."""
    n = int(periods) * int(steps_per_period)
    if n > MAX_STEPS_PER_SPEED:
        raise ValueError(
            f"periods = {int(periods)} × steps_per_period = {int(steps_per_period)} = {n:.3g} "
            f"time steps per speed: allowed <= {MAX_STEPS_PER_SPEED:.3g} (fewer periods, or "
            "fewer steps per period)"
        )
    need = 8.0 * int(recorded_steps) * int(values)
    have = 0.5 * _memory_bytes()
    if need > have:
        raise ValueError(
            f"periods = {int(periods)}: the records of one speed need about {need / 1e9:.3g} GB, "
            f"allowed <= {have / 1e9:.3g} GB (half this machine's memory): fewer periods (or "
            "keep_periods), steps per period or slices"
        )


def _check_steps(steps_per_period) -> None:
    if steps_per_period is not None:
        check_integer("steps_per_period", steps_per_period, 4)


class Newmark(eqx.Module):
    """Newmark's average-acceleration method (β = 1/4, γ = 1/2: unconditionally stable, second
    order, no numerical damping; seed annex 2) with the contact loop inside each step (II-25).

    Attributes:
        steps_per_period: N_s, time steps per mesh period, an integer >= 4; ``None``: automatic
            (lumped scenes: :func:`~jaxgear.dynamics.auto_steps_per_period`, >= 40 steps per
            period of the highest mode the mesh excites, >= 64 per mesh period, a power of two;
            needs concrete speeds). Static: a new value recompiles.

    Raises:
        ValueError: ``steps_per_period`` not ``None`` or an integer >= 4.
    """

    steps_per_period: int | None = eqx.field(default=None, static=True)

    def __check_init__(self):
        _check_steps(self.steps_per_period)


class DiffraxIntegrator(eqx.Module):
    """A diffrax solver on the first-order form M Ẍ = F − C Ẋ − K X − Vᵀ P(X) (lumped scenes;
    use :class:`~jaxgear.SmoothContact`: the exact law's kinks stall adaptive steps).

    Attributes:
        solver: a name of :data:`DIFFRAX_SOLVERS` (``"tsit5"``, ``"kvaerno5"``, ...).
        steps_per_period: the initial step and the sampling of the kept periods, as
            :class:`Newmark`'s (``None``: automatic).
        rtol, atol: PID step-size tolerances on the scaled state (X/x_ref, Ẋ/(x_ref ω_max),
            x_ref the static mesh deflection); with ``adaptive=False``, the implicit solvers'
            root-finder tolerances.
        adaptive: ``False`` for constant steps Δt = period/N_s.
        max_steps: step cap (``None``: 64 × the Newmark step count + 4096).
        adjoint: "reverse" (checkpointed adjoint, for ``jax.grad``) or "forward"
            (``diffrax.ForwardMode``, for ``jax.jvp``/``jax.jacfwd``).

    Raises:
        ValueError: an unknown solver or adjoint, tolerances not > 0, bad step counts.
    """

    solver: str = eqx.field(default="tsit5", static=True)
    steps_per_period: int | None = eqx.field(default=None, static=True)
    rtol: float = eqx.field(default=1e-6, static=True)
    atol: float = eqx.field(default=1e-6, static=True)
    adaptive: bool = eqx.field(default=True, static=True)
    max_steps: int | None = eqx.field(default=None, static=True)
    adjoint: str = eqx.field(default="reverse", static=True)

    def __check_init__(self):
        if self.solver not in DIFFRAX_SOLVERS:
            raise ValueError(
                f"solver = {self.solver!r}: allowed a diffrax solver name "
                f"({', '.join(DIFFRAX_SOLVERS)})"
            )
        if self.adjoint not in ("reverse", "forward"):
            raise ValueError(f"adjoint = {self.adjoint!r}: allowed 'reverse', 'forward'")
        for name in ("rtol", "atol"):
            v = getattr(self, name)
            if not (isinstance(v, int | float) and v > 0):
                raise ValueError(f"{name} = {v!r}: allowed a tolerance > 0")
        _check_steps(self.steps_per_period)
        if self.max_steps is not None:
            check_integer("max_steps", self.max_steps, 1)


Integrator = Newmark | DiffraxIntegrator


class SteadyState(eqx.Module):
    """The steady-state window of a run: ``periods`` mesh periods integrated from the start
    state, the last ``keep_periods`` of them recorded (the responses, dynamic factors and
    RMS values are taken over those).

    Attributes:
        periods: mesh periods integrated, an integer >= 2.
        keep_periods: mesh periods kept at the end, an integer in [1, periods] (the lumped
            dynamics need >= 2: their periodicity compares the last two).

    Raises:
        ValueError: counts out of those ranges.
    """

    periods: int = eqx.field(default=60, static=True)
    keep_periods: int = eqx.field(default=4, static=True)

    def __check_init__(self):
        check_integer("periods", self.periods, 2)
        check_integer("keep_periods", self.keep_periods, 1)
        if self.keep_periods > self.periods:
            raise ValueError(
                f"keep_periods = {self.keep_periods} must be <= periods = {self.periods}"
            )


def check_integrator(integrator, name: str = "integrator") -> Integrator:
    """``integrator`` checked to be :class:`Newmark` or :class:`DiffraxIntegrator` (one line
    naming ``name`` otherwise)."""
    if not isinstance(integrator, Integrator):
        raise ValueError(
            f"{name} = {integrator!r}: allowed jaxgear.dynamics.Newmark(...) or "
            "jaxgear.dynamics.DiffraxIntegrator(...)"
        )
    return integrator


def check_window(window, name: str = "window") -> SteadyState:
    if not isinstance(window, SteadyState):
        raise ValueError(f"{name} = {window!r}: allowed jaxgear.dynamics.SteadyState(...)")
    return window


@dataclasses.dataclass(frozen=True)
class _Config:
    """The resolved settings of one run (static under jit): the integrator with its step count
    fixed, the window, the divergence bound and whether the states are recorded."""

    integrator: Integrator
    steps_per_period: int
    periods: int
    keep_periods: int
    max_steps: int
    blowup: float
    states: bool = False

    @property
    def newmark(self) -> bool:
        return isinstance(self.integrator, Newmark)


# automatic time step (``steps_per_period=None``), docs/dynamics.md "Time step and accuracy":
# N_s = the smallest power of two >= max(MIN_STEPS_PER_PERIOD, STEPS_PER_MODE · f_max / f_mesh),
# f_max the highest natural frequency among the modes storing >= MESH_ENERGY_MIN of their strain
# energy in the mesh (the modes the mesh excites), f_mesh = Ω z1 / 2π.
STEPS_PER_MODE = 40
MIN_STEPS_PER_PERIOD = 64
MESH_ENERGY_MIN = 0.05
# a run (automatic or user N_s) is flagged ``under_resolved`` below this many steps per period of
# the highest excited mode
UNDER_RESOLVED_STEPS = 20


def _code(code, new):
    return jnp.where(code == 0, new, code)


def _divergence_code(xd, X, fm, M, fs, e_ref, blowup):
    finite = jnp.all(jnp.isfinite(X)) & jnp.all(jnp.isfinite(xd)) & jnp.isfinite(fm)
    ke = 0.5 * xd @ M @ xd
    blown = (fm > blowup * fs) | (ke > blowup**2 * e_ref)
    return jnp.where(~finite, 2, jnp.where(blown, 3, 0))


def _config(
    integrator,
    window: SteadyState,
    steps_per_period: int,
    blowup,
    states: bool = False,
    *,
    min_keep: int = 2,
    values_per_step: int = 16,
    record_all: bool = False,
) -> _Config:
    """The settings of a run with the integrator's step count resolved to
    ``steps_per_period``; checks the window (at least ``min_keep`` kept periods: 2 for a
    lumped model, which compares the last two) and the run's size, ``values_per_step`` recorded
    per kept step (per step of the whole run with ``record_all``) (before any work)."""
    check_integer("steps_per_period", steps_per_period, 4)
    if window.keep_periods < min_keep:
        why = " (the lumped dynamics compare the last two periods)" if min_keep == 2 else ""
        raise ValueError(
            f"keep_periods = {window.keep_periods} is out of range: allowed an integer >= "
            f"{min_keep}{why}"
        )
    if not blowup > 0:
        raise ValueError(f"blowup = {blowup!r}: allowed > 0")
    n_total = int(window.periods) * int(steps_per_period)
    # records of the kept steps (a lumped run: TE, mesh force, line forces and bearing
    # reactions, ~16 values)
    check_run_size(
        window.periods,
        steps_per_period,
        int(window.periods if record_all else window.keep_periods) * int(steps_per_period),
        values_per_step,
    )
    max_steps = getattr(integrator, "max_steps", None)
    if max_steps is None:
        max_steps = 64 * n_total + 4096
    return _Config(
        integrator,
        int(steps_per_period),
        int(window.periods),
        int(window.keep_periods),
        int(max_steps),
        float(blowup),
        bool(states),
    )
