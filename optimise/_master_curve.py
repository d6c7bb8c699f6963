"""Contour map of the objective in the (Γ, E) plane and the Master Curve (docs/design.md,
"Optimisation").

The Master Curve gives, for each relief extent Γ, the relief depth E minimising TE RMS at the
design load (Velex, Bruyère & Houser, JMD 2011). Here each Γ is solved independently and in
parallel (``jax.vmap``): a coarse grid in E* gives the bracket of a root search
(``optimistix.root_find`` with ``optimistix.Bisection``) on dJ/dE* = 0, using the exact implicit
gradient of the smooth model.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optimistix as optx

import jaxgear as jg

from ._problem import EXACT, Problem
from ._variables import tip_relief_slots

__all__ = ["contour_map", "master_curve"]


def _slots(problem: Problem) -> tuple[int, int]:
    """The positions (depth, extent) of the tip relief variables.

    Raises:
        ValueError: the problem's variables are not exactly the tip relief depth and extent.
    """
    slots = tip_relief_slots(problem.names)
    if slots is None:
        raise ValueError(
            f"the (Γ, E) map needs exactly the variables tip_relief.depth and "
            f"tip_relief.extent, got {problem.names}"
        )
    return slots


def _xy(problem: Problem, extent, depth):
    """Design vector with ``depth`` (E*) and ``extent`` (Γ) at the tip-relief variable slots."""
    i_d, i_g = _slots(problem)
    x = jnp.zeros(len(problem.names), dtype=jnp.result_type(float))
    return x.at[i_d].set(depth).at[i_g].set(extent)


@eqx.filter_jit
def _grid(problem, extents, depths, contact):
    f = lambda g, e: problem.value(_xy(problem, g, e), contact)  # noqa: E731
    return jax.vmap(lambda g: jax.vmap(lambda e: f(g, e))(depths))(extents)


def contour_map(
    problem: Problem, extents, depths, contact: jg.ContactLaw | None = EXACT
) -> np.ndarray:
    """Scaled objective on the (Γ, E*) grid by nested ``vmap``.

    Args:
        problem: a problem whose variables are tip_relief.depth and tip_relief.extent.
        extents: Γ values, shape (nG,). depths: E* values (E/δ_m), shape (nE,).
        contact: the contact law (default exact; None: the problem's smooth law).

    Returns:
        objective / unmodified objective, shape (nG, nE).
    """
    _slots(problem)
    return np.asarray(_grid(problem, jnp.asarray(extents), jnp.asarray(depths), contact))


@eqx.filter_jit
def _pairs(problem, extents, depths, contact):
    return jax.vmap(lambda g, e: problem.value(_xy(problem, g, e), contact))(extents, depths)


@eqx.filter_jit
def _refine(problem, extents, lo, hi, iterations):
    """Root of dJ/dE* in [lo, hi] for each extent: ``optimistix.root_find`` (Bisection) under
    ``vmap``; an unbracketed interval (dJ/dE* of one sign) gives the end that is the minimum."""

    def dj(e, g):
        return jax.grad(lambda ee: problem.value(_xy(problem, g, ee)))(e)

    # stops when the bracket is below 1e-10 (relative); ``iterations`` caps the bisections
    solver = optx.Bisection(rtol=1e-10, atol=1e-10, flip=False)

    def one(g, a, b):
        ga, gb = dj(a, g), dj(b, g)
        bracketed = (ga < 0) & (gb > 0)
        sol = optx.root_find(
            dj,
            solver,
            0.5 * (a + b),
            args=g,
            options={"lower": a, "upper": b},
            max_steps=iterations,
            throw=False,
        )
        return jnp.where(bracketed, sol.value, jnp.where(ga >= 0, a, b))

    return jax.vmap(one)(extents, lo, hi)


def master_curve(problem: Problem, extents, *, coarse_depths=None, iterations: int = 30) -> dict:
    """Optimal relief depth for each extent at the design load.

    Args:
        problem: tip_relief.depth / tip_relief.extent problem (single torque).
        extents: Γ values, shape (nG,), inside the problem's extent bounds.
        coarse_depths: E* grid for the warm start (default 41 points over the depth bounds).
        iterations: cap on the bisection steps per extent (static: a new value recompiles).

    Returns:
        dict with ``extent`` (nG,), ``depth_star`` (nG,) E*, ``depth_m`` (nG,) E (m),
        ``te_rms_exact_m`` and ``te_rms_smooth_m`` (nG,) at the optimum, ``on_bound`` (nG,)
        bool: the optimum depth lies on a bound of the depth interval (no interior minimum was
        found there: not a true optimum).
    """
    i_d, i_g = _slots(problem)
    extents = np.asarray(extents, dtype=float)
    lo_g, hi_g = float(problem.lower[i_g]), float(problem.upper[i_g])
    if extents.size == 0 or np.any(extents < lo_g) or np.any(extents > hi_g):
        raise ValueError(
            f"extents = {extents.tolist()}: must be non-empty and inside ({lo_g}, {hi_g})"
        )
    lo_e, hi_e = float(problem.lower[i_d]), float(problem.upper[i_d])
    depths = np.linspace(lo_e, hi_e, 41) if coarse_depths is None else np.asarray(coarse_depths)
    grid = contour_map(problem, extents, depths, None)
    k = np.argmin(grid, axis=1)
    a = depths[np.maximum(k - 1, 0)]
    b = depths[np.minimum(k + 1, len(depths) - 1)]
    e_star = np.asarray(
        _refine(problem, jnp.asarray(extents), jnp.asarray(a), jnp.asarray(b), int(iterations))
    )
    on_bound = (e_star <= lo_e + 1e-6 * (hi_e - lo_e)) | (e_star >= hi_e - 1e-6 * (hi_e - lo_e))
    scale = float(problem.scale)
    exact = np.asarray(_pairs(problem, jnp.asarray(extents), jnp.asarray(e_star), EXACT))
    smooth = np.asarray(_pairs(problem, jnp.asarray(extents), jnp.asarray(e_star), None))
    return {
        "extent": extents,
        "depth_star": e_star,
        "depth_m": e_star * float(problem.delta_m),
        "te_rms_exact_m": exact * scale,
        "te_rms_smooth_m": smooth * scale,
        "on_bound": on_bound,
        "coarse_depths": depths,
        "coarse_grid": grid,
    }
