"""Integration settings, the contact law φ and the divergence checks shared by the integrators."""

from __future__ import annotations

import dataclasses
import os

import jax
import jax.numpy as jnp

__all__ = ["DIFFRAX_SOLVERS", "MAX_STEPS_PER_SPEED", "check_run_size"]

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


@dataclasses.dataclass(frozen=True)
class _Config:
    solver: str
    contact: str
    steps_per_period: int
    periods: int
    keep_periods: int
    max_iterations: int
    rtol: float
    atol: float
    adaptive: bool
    max_steps: int
    blowup: float
    adjoint: str = "reverse"


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


def _phi(gap, mode, width):
    if mode == "exact":
        return jnp.maximum(gap, 0.0)
    return width * jax.nn.softplus(gap / width)


def _code(code, new):
    return jnp.where(code == 0, new, code)


def _divergence_code(xd, X, fm, M, fs, e_ref, blowup):
    finite = jnp.all(jnp.isfinite(X)) & jnp.all(jnp.isfinite(xd)) & jnp.isfinite(fm)
    ke = 0.5 * xd @ M @ xd
    blown = (fm > blowup * fs) | (ke > blowup**2 * e_ref)
    return jnp.where(~finite, 2, jnp.where(blown, 3, 0))


def _config(
    solver,
    contact,
    steps_per_period,
    periods,
    keep_periods,
    max_iterations,
    rtol,
    atol,
    adaptive,
    max_steps,
    blowup,
    adjoint: str = "reverse",
) -> _Config:
    if adjoint not in ("reverse", "forward"):
        raise ValueError(f"adjoint = {adjoint!r}: allowed 'reverse', 'forward'")
    if solver != "newmark" and solver not in DIFFRAX_SOLVERS:
        raise ValueError(
            f"solver = {solver!r}: allowed 'newmark' or a diffrax solver "
            f"({', '.join(DIFFRAX_SOLVERS)})"
        )
    if contact not in ("exact", "smooth"):
        raise ValueError(f"contact = {contact!r}: allowed 'exact', 'smooth'")
    for name, v, lo in (
        ("steps_per_period", steps_per_period, 4),
        ("periods", periods, 2),
        ("keep_periods", keep_periods, 2),
    ):
        if int(v) != v or v < lo:
            raise ValueError(f"{name} = {v!r} is out of range: allowed an integer >= {lo}")
    if keep_periods > periods:
        raise ValueError(f"keep_periods = {keep_periods} must be <= periods = {periods}")
    n_total = int(periods) * int(steps_per_period)
    # records: TE, mesh force, line forces and bearing reactions of the kept steps (~16 values)
    check_run_size(periods, steps_per_period, int(keep_periods) * int(steps_per_period), 16)
    if max_steps is None:
        max_steps = 64 * n_total + 4096
    return _Config(
        solver,
        contact,
        int(steps_per_period),
        int(periods),
        int(keep_periods),
        int(max_iterations),
        float(rtol),
        float(atol),
        bool(adaptive),
        int(max_steps),
        float(blowup),
        adjoint,
    )
