"""Gradient-based minimisation with optimistix (L-BFGS with backtracking Armijo, or Adam).

One jitted ``optimistix.minimise`` call per run: the whole loop stays on the device, compiled
once per problem structure and method (start, tolerance, iteration cap and learning rate are
traced values, so new values do not recompile). A thin wrapper solver adds the iteration cap
(accepted iterations, not line-search evaluations) and reports each accepted iterate to the host
through ``jax.debug.callback``: the callback fills the history and the progress bar; it does not
stop the loop or wait for Python between iterations.
"""

from __future__ import annotations

import itertools
import threading
import time
import warnings
from typing import Any

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optax
import optimistix as optx
from tqdm.auto import tqdm

from ._problem import Problem

__all__ = ["OptimisationResult", "minimise"]

# evaluation safety cap per allowed iteration (a line search that never accepts still stops)
_EVALUATIONS_PER_ITERATION = 50


class _Capped(optx.AbstractMinimiser):
    """Wraps an optimistix minimiser: stops after ``options["max_iterations"]`` accepted
    iterations (result ``nonlinear_max_steps_reached``) and reports each accepted iterate.

    Supports the quasi-Newton solvers (an iterate is accepted when the line search accepts it; the
    first accepted point is the start) and ``OptaxMinimiser`` (every step is an iteration).
    """

    solver: optx.AbstractMinimiser
    rtol: Any
    atol: Any
    norm: Any

    def __init__(self, solver):
        self.solver = solver
        self.rtol, self.atol, self.norm = solver.rtol, solver.atol, solver.norm

    def _iterations(self, state):
        if isinstance(self.solver, optx.OptaxMinimiser):
            return state.step
        return state.num_accepted_steps - 1  # the first accepted point is y0

    def init(self, fn, y, args, options, f_struct, aux_struct, tags):
        inner = self.solver.init(fn, y, args, options, f_struct, aux_struct, tags)
        return inner, jnp.array(0)

    def step(self, fn, y, args, options, state, tags):
        inner, n_steps = state
        new_y, new_inner, aux = self.solver.step(fn, y, args, options, inner, tags)
        if isinstance(self.solver, optx.OptaxMinimiser):
            # evaluated the incoming point y (iterate ``inner.step``) at value new_inner.f
            accepted, k, point, value = jnp.array(True), inner.step, y, new_inner.f
        else:
            accepted = new_inner.num_accepted_steps > inner.num_accepted_steps
            k, point, value = new_inner.num_accepted_steps - 1, new_y, new_inner.f_info.f
        jax.debug.callback(_report, options["run"], accepted, k, point, value)
        return new_y, (new_inner, n_steps + 1), aux

    def terminate(self, fn, y, args, options, state, tags):
        inner, n_steps = state
        done, result = self.solver.terminate(fn, y, args, options, inner, tags)
        capped = jnp.invert(done) & (
            (self._iterations(inner) >= options["max_iterations"])
            | (n_steps >= options["max_evaluations"])
        )
        result = optx.RESULTS.where(capped, optx.RESULTS.nonlinear_max_steps_reached, result)
        return done | capped, result

    def postprocess(self, fn, y, aux, args, options, state, tags, result):
        return self.solver.postprocess(fn, y, aux, args, options, state[0], tags, result)


# -- host side of the per-iteration report ------------------------------------------------------
_RUNS: dict[int, dict] = {}
_RUN_IDS = itertools.count()
_LOCK = threading.Lock()


def _report(run, accepted, k, u, value):
    if not bool(accepted):
        return
    rec = _RUNS.get(int(run))
    if rec is None:
        return
    k = int(k)
    rec["history"][k] = (np.array(u), float(value))
    bar = rec["bar"]
    if bar is not None and k > bar.n:
        bar.update(min(k, bar.total) - bar.n)
        bar.set_postfix(objective=f"{float(value):.5g}", refresh=False)


def _objective(u, problem: Problem):
    return problem.value(problem.bounded(u))


@eqx.filter_jit
def _solve(problem, method, u0, tol, learning_rate, max_iterations, run):
    """One optimistix solve; ``method`` is static, every other argument is traced."""
    if method == "lbfgs":
        inner = optx.LBFGS(rtol=tol, atol=tol)
    else:
        inner = optx.OptaxMinimiser(optax.adam(learning_rate), rtol=tol, atol=tol)
    options = {
        "max_iterations": max_iterations,
        "max_evaluations": _EVALUATIONS_PER_ITERATION * (max_iterations + 1),
        "run": run,
    }
    sol = optx.minimise(
        _objective, _Capped(inner), u0, problem, options, max_steps=None, throw=False
    )
    inner_state, n_steps = sol.state
    if method == "lbfgs":
        value = inner_state.f_info.f  # the returned point is the last accepted one
        iterations = inner_state.num_accepted_steps - 1
    else:  # the returned point is the update after the last evaluated one
        value = _objective(sol.value, problem)
        iterations = inner_state.step
        n_steps = n_steps + 1
        jax.debug.callback(_report, run, jnp.array(True), iterations, sol.value, value)
    converged = sol.result == optx.RESULTS.successful
    capped = sol.result == optx.RESULTS.nonlinear_max_steps_reached
    return sol.value, value, iterations, n_steps, converged, capped


class OptimisationResult(eqx.Module):
    """Outcome of :func:`minimise` (normalised design values; see ``Problem.to_physical``).

    Attributes:
        x0, x: initial and final design values, shape (n,).
        value0, value: scaled smooth-mode objective at x0 and x.
        history_x: design values at each accepted iterate (start first, ``x`` last), shape
            (iterations+1, n); recorded on the host by a ``jax.debug.callback`` from inside the
            solve.
        history_value: objective at those iterates, shape (iterations+1,).
        iterations: accepted optimiser iterations. evaluations: objective(+gradient)
            evaluations, rejected line-search trials included. converged: optimistix's stopping
            rule met (not the iteration cap or a failure).
        wall_time_s: seconds, compile included.
    """

    x0: np.ndarray
    x: np.ndarray
    value0: float
    value: float
    history_x: np.ndarray
    history_value: np.ndarray
    iterations: int
    evaluations: int
    converged: bool
    wall_time_s: float


def minimise(
    problem: Problem,
    x0,
    *,
    method: str = "lbfgs",
    max_iterations: int = 100,
    tol: float = 1e-7,
    learning_rate: float = 0.05,
    progress: bool = True,
) -> OptimisationResult:
    """Minimise ``problem.value`` (smooth contact) from normalised start ``x0``.

    The optimiser runs in the unbounded variables u (``Problem.bounded``) as one jitted
    ``optimistix.minimise`` call, compiled once per problem structure and method: ``x0``,
    ``tol``, ``max_iterations`` and ``learning_rate`` are traced, new values do not recompile.

    Args:
        problem: the problem (bounds by reparametrisation).
        x0: start, normalised units, shape (n,), inside the bounds.
        method: "lbfgs" (``optimistix.LBFGS``, backtracking Armijo line search) or "adam"
            (``optimistix.OptaxMinimiser(optax.adam(learning_rate))``).
        max_iterations: cap on accepted iterations (line-search trials are not iterations).
        tol: ``rtol = atol`` of optimistix's Cauchy criterion: stop when two successive accepted
            iterates differ by less than ``tol·(1 + |u|)`` in every component of u and their
            objectives by less than ``tol·(1 + |f|)``.
        learning_rate: Adam step.
        progress: a tqdm bar, advanced from inside the solve by ``jax.debug.callback`` at each
            accepted iterate.

    Raises:
        ValueError: unknown method, x0 of the wrong size or outside the bounds.
        FloatingPointError: the objective became non-finite.

    Warns:
        UserWarning: the iteration cap was reached before the stopping rule (``converged`` is
            False), or the solver stopped otherwise without converging.
    """
    if method not in ("lbfgs", "adam"):
        raise ValueError(f"method = {method!r}: allowed 'lbfgs', 'adam'")
    x0 = np.asarray(x0, dtype=float).reshape(-1)
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    if x0.shape != lo.shape:
        raise ValueError(
            f"x0 has {x0.size} values for {len(problem.names)} variables {problem.names}"
        )
    if np.any(x0 < lo) or np.any(x0 > hi):
        raise ValueError(
            f"start {dict(zip(problem.names, x0.tolist()))} is outside the bounds "
            f"{dict(zip(problem.names, zip(lo.tolist(), hi.tolist())))}"
        )
    t0 = time.perf_counter()
    bar = tqdm(total=max_iterations, desc=f"optimise ({method})", disable=not progress)
    with _LOCK:
        run = next(_RUN_IDS)
    rec = _RUNS[run] = {"history": {}, "bar": bar}
    real = jnp.result_type(float)
    try:
        u, value, iterations, n_eval, converged, capped = _solve(
            problem,
            method,
            problem.unbounded(x0),
            jnp.asarray(np.asarray(tol, dtype=float), dtype=real),
            jnp.asarray(np.asarray(learning_rate, dtype=float), dtype=real),
            jnp.asarray(int(max_iterations)),
            jnp.asarray(run),
        )
        value = float(value)  # blocks until the solve, and its callbacks, are done
        jax.effects_barrier()
    finally:
        del _RUNS[run]
    it = int(iterations)
    bar.total = max(it, 1)  # stopped early: the bar ends full, not at it/max_iterations
    bar.n = it
    bar.set_postfix(objective=f"{value:.5g}", refresh=False)
    bar.refresh()
    bar.close()
    if not np.isfinite(value):
        raise FloatingPointError(
            "optimisation produced a non-finite objective; check the bounds "
            "and the smooth contact width"
        )
    hist = rec["history"]
    ks = sorted(hist)
    hist_u = np.stack([hist[k][0] for k in ks])
    hist_v = np.asarray([hist[k][1] for k in ks])
    # Problem.bounded in numpy: an eager jnp call would compile once per history length
    hist_x = lo + (hi - lo) / (1.0 + np.exp(-hist_u))
    hist_x[0] = x0
    converged, capped = bool(converged), bool(capped)
    if capped:
        warnings.warn(
            f"optimiser stopped at the iteration cap ({max_iterations}) before convergence; "
            "the result may not be an optimum (raise max_iterations)",
            UserWarning,
            stacklevel=2,
        )
    elif not converged:
        warnings.warn(
            f"optimiser stopped after {it} iterations without meeting its stopping rule "
            "(line search failed); the result may not be an optimum",
            UserWarning,
            stacklevel=2,
        )
    return OptimisationResult(
        x0=np.asarray(x0),
        x=np.asarray(problem.bounded(u)),
        value0=float(hist_v[0]),
        value=value,
        history_x=hist_x,
        history_value=hist_v,
        iterations=it,
        evaluations=int(n_eval),
        converged=converged,
        wall_time_s=time.perf_counter() - t0,
    )
