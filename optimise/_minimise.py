"""Gradient-based minimisation with any optimistix quasi-Newton minimiser (L-BFGS by default,
BFGS, DFP) or optax gradient transformation (Adam, ...), passed as an object.

One jitted ``optimistix.minimise`` call per run: the whole loop stays on the device, compiled
once per problem structure and solver structure (the start, the iteration cap and the solver's
``rtol``/``atol`` are traced values, so new values do not recompile). A thin wrapper solver adds
the iteration cap (accepted iterations, not line-search evaluations) and reports each accepted
iterate to the host through ``jax.debug.callback``: the callback fills the history and the
progress bar; it does not stop the loop or wait for Python between iterations.
:func:`minimise_batch` solves several problems of one structure (the same static layout, e.g.
meshes of the same cell counts) in one ``jax.vmap`` of that solve: each problem's iterations are
its own (a finished problem's state is held while the others go on), the callback reports each
problem's iterates to its own history.

How a solver's iterations are read from its state depends on its family (a quasi-Newton state
counts accepted steps, an optax state counts updates): :class:`_Iterations` objects chosen once
per solver type by :func:`_iterations_of` (``functools.singledispatch``), the way
``optimistix.minimise`` takes any ``AbstractMinimiser``.
"""

from __future__ import annotations

import abc
import functools
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

from jaxgear import padded_batch

from ._problem import Problem

__all__ = ["OptimisationResult", "minimise", "minimise_batch"]

# evaluation safety cap per allowed iteration (a line search that never accepts still stops)
_EVALUATIONS_PER_ITERATION = 50
# rtol = atol of the optimistix Cauchy criterion given to a bare optax transformation
DEFAULT_TOL = 1e-7
_DEFAULT_SOLVER = optx.LBFGS(rtol=DEFAULT_TOL, atol=DEFAULT_TOL)


class _Iterations(eqx.Module):
    """How the iterations of one family of optimistix minimisers are read from its state."""

    @abc.abstractmethod
    def count(self, state):
        """Accepted iterations so far (the start is iteration 0)."""

    @abc.abstractmethod
    def step(self, y, new_y, inner, new_inner):
        """(accepted, iteration, point, value) of one solver step, for the report."""

    @abc.abstractmethod
    def final(self, sol, problem, n_steps, run):
        """(value, iterations, steps) of the returned point."""


class _QuasiNewton(_Iterations):
    """``optx.AbstractQuasiNewton`` (BFGS, LBFGS, DFP): an iterate is accepted when the line
    search accepts it; the first accepted point is the start."""

    def count(self, state):
        return state.num_accepted_steps - 1  # the first accepted point is y0

    def step(self, y, new_y, inner, new_inner):
        accepted = new_inner.num_accepted_steps > inner.num_accepted_steps
        return accepted, new_inner.num_accepted_steps - 1, new_y, new_inner.f_info.f

    def final(self, sol, problem, n_steps, run):
        inner_state = sol.state[0]
        # the returned point is the last accepted one
        return inner_state.f_info.f, inner_state.num_accepted_steps - 1, n_steps


class _Optax(_Iterations):
    """``optx.OptaxMinimiser``: every step is an iteration."""

    def count(self, state):
        return state.step

    def step(self, y, new_y, inner, new_inner):
        # evaluated the incoming point y (iterate ``inner.step``) at value new_inner.f
        return jnp.array(True), inner.step, y, new_inner.f

    def final(self, sol, problem, n_steps, run):
        # the returned point is the update after the last evaluated one
        value = _objective(sol.value, problem)
        iterations = sol.state[0].step
        jax.debug.callback(_report, run, jnp.array(True), iterations, sol.value, value)
        return value, iterations, n_steps + 1


@functools.singledispatch
def _iterations_of(solver) -> _Iterations:
    raise ValueError(
        f"solver = {type(solver).__name__}: allowed an optimistix quasi-Newton minimiser "
        "(optimistix.LBFGS, BFGS, DFP), an optimistix.OptaxMinimiser or an optax "
        "GradientTransformation (e.g. optax.adam(0.05))"
    )


@_iterations_of.register
def _(solver: optx.AbstractQuasiNewton) -> _Iterations:
    return _QuasiNewton()


@_iterations_of.register
def _(solver: optx.OptaxMinimiser) -> _Iterations:
    return _Optax()


@functools.singledispatch
def _as_minimiser(solver):
    """An optimistix minimiser as it is (its tolerances as arrays, traced by the solve)."""
    real = jnp.result_type(float)
    rtol = jnp.asarray(np.asarray(solver.rtol, dtype=float), dtype=real)
    atol = jnp.asarray(np.asarray(solver.atol, dtype=float), dtype=real)
    return eqx.tree_at(lambda s: (s.rtol, s.atol), solver, (rtol, atol))


@_as_minimiser.register
def _(solver: optax.GradientTransformation):
    """An optax transformation: ``optimistix.OptaxMinimiser`` with rtol = atol = 1e-7."""
    return _as_minimiser(optx.OptaxMinimiser(solver, rtol=DEFAULT_TOL, atol=DEFAULT_TOL))


class _Capped(optx.AbstractMinimiser):
    """Wraps an optimistix minimiser: stops after ``options["max_iterations"]`` accepted
    iterations (result ``nonlinear_max_steps_reached``) and reports each accepted iterate
    (``iterations`` reads them from the solver's state).
    """

    solver: optx.AbstractMinimiser
    iterations: _Iterations
    rtol: Any
    atol: Any
    norm: Any

    def __init__(self, solver, iterations):
        self.solver, self.iterations = solver, iterations
        self.rtol, self.atol, self.norm = solver.rtol, solver.atol, solver.norm

    def init(self, fn, y, args, options, f_struct, aux_struct, tags):
        inner = self.solver.init(fn, y, args, options, f_struct, aux_struct, tags)
        return inner, jnp.array(0)

    def step(self, fn, y, args, options, state, tags):
        inner, n_steps = state
        new_y, new_inner, aux = self.solver.step(fn, y, args, options, inner, tags)
        accepted, k, point, value = self.iterations.step(y, new_y, inner, new_inner)
        jax.debug.callback(_report, options["run"], accepted, k, point, value)
        return new_y, (new_inner, n_steps + 1), aux

    def terminate(self, fn, y, args, options, state, tags):
        inner, n_steps = state
        done, result = self.solver.terminate(fn, y, args, options, inner, tags)
        capped = jnp.invert(done) & (
            (self.iterations.count(inner) >= options["max_iterations"])
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


def _solve_one(problem, solver, iterations, u0, max_iterations, run):
    """One optimistix solve; the solver's structure is static, its tolerances, the start and the
    cap are traced."""
    options = {
        "max_iterations": max_iterations,
        "max_evaluations": _EVALUATIONS_PER_ITERATION * (max_iterations + 1),
        "run": run,
    }
    sol = optx.minimise(
        _objective,
        _Capped(solver, iterations),
        u0,
        problem,
        options,
        max_steps=None,
        throw=False,
    )
    value, n_iterations, n_steps = iterations.final(sol, problem, sol.state[1], run)
    converged = sol.result == optx.RESULTS.successful
    capped = sol.result == optx.RESULTS.nonlinear_max_steps_reached
    return sol.value, value, n_iterations, n_steps, converged, capped


_solve = eqx.filter_jit(_solve_one)


@eqx.filter_jit
def _solve_batch(arrays, static, solver, iterations, u0, max_iterations, run):
    """:func:`_solve_one` mapped over problems stacked along their arrays' first axis
    (``arrays``; ``static`` their shared rest), starts ``u0`` (B, n) and run ids (B,)."""

    def one(a, u, r):
        return _solve_one(eqx.combine(a, static), solver, iterations, u, max_iterations, r)

    return jax.vmap(one)(arrays, u0, run)


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
    solver: optx.AbstractMinimiser | optax.GradientTransformation | None = None,
    *,
    max_iterations: int = 100,
    progress: bool = True,
) -> OptimisationResult:
    """Minimise ``problem.value`` (smooth contact) from normalised start ``x0`` with ``solver``.

    The optimiser runs in the unbounded variables u (``Problem.bounded``) as one jitted
    ``optimistix.minimise`` call, compiled once per problem structure and solver structure:
    ``x0``, ``max_iterations`` and the solver's ``rtol``/``atol`` are traced, new values do not
    recompile.

    Args:
        problem: the problem (bounds by reparametrisation).
        x0: start, normalised units, shape (n,), inside the bounds.
        solver: an optimistix quasi-Newton minimiser (default
            ``optimistix.LBFGS(rtol=1e-7, atol=1e-7)``, backtracking Armijo line search;
            ``optimistix.BFGS``, ``DFP``), an ``optimistix.OptaxMinimiser``, or an optax
            ``GradientTransformation`` (e.g. ``optax.adam(0.05)``, run as
            ``OptaxMinimiser(solver, rtol=1e-7, atol=1e-7)``). Its ``rtol``/``atol`` are
            optimistix's Cauchy criterion: stop when two successive accepted iterates differ by
            less than ``atol + rtol·|u|`` in every component of u and their objectives by less
            than ``atol + rtol·|f|``.
        max_iterations: cap on accepted iterations (line-search trials are not iterations).
        progress: a tqdm bar, advanced from inside the solve by ``jax.debug.callback`` at each
            accepted iterate.

    Raises:
        ValueError: a solver of another kind, x0 of the wrong size or outside the bounds.
        FloatingPointError: the objective became non-finite.

    Warns:
        UserWarning: the iteration cap was reached before the stopping rule (``converged`` is
            False), or the solver stopped otherwise without converging.
    """
    solver = _as_minimiser(_DEFAULT_SOLVER if solver is None else solver)
    iterations = _iterations_of(solver)
    x0 = _checked_start(problem, x0)
    t0 = time.perf_counter()
    desc = f"optimise ({type(solver).__name__})"
    bar = tqdm(total=max_iterations, desc=desc, disable=not progress)
    with _LOCK:
        run = next(_RUN_IDS)
    rec = _RUNS[run] = {"history": {}, "bar": bar}
    try:
        u, value, n_iterations, n_eval, converged, capped = _solve(
            problem,
            solver,
            iterations,
            problem.unbounded(x0),
            jnp.asarray(int(max_iterations)),
            jnp.asarray(run),
        )
        value = float(value)  # blocks until the solve, and its callbacks, are done
        jax.effects_barrier()
    finally:
        del _RUNS[run]
    it = int(n_iterations)
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
    return _result(problem, x0, rec["history"], u, value, it, n_eval, converged, capped,
                   max_iterations, time.perf_counter() - t0, "")


def _checked_start(problem: Problem, x0) -> np.ndarray:
    """``x0`` as a float array (n,), refused unless it has the problem's size and lies in its
    bounds."""
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
    return x0


def _result(problem, x0, hist, u, value, it, n_eval, converged, capped, max_iterations,
            wall, which) -> OptimisationResult:
    """The :class:`OptimisationResult` of one solve from its host-side history ``hist``
    (iteration → (u, value); entries past the solve's last iteration dropped), warning where it
    stopped unconverged (``which``: the problem's name in the warning, "" for one)."""
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    ks = sorted(k for k in hist if k <= it)
    if not ks:  # nothing accepted before the objective failed (a batch's problem)
        hist = {0: (np.asarray(problem.unbounded(x0)), value)}
        ks = [0]
    hist_u = np.stack([hist[k][0] for k in ks])
    hist_v = np.asarray([hist[k][1] for k in ks])
    # Problem.bounded in numpy: an eager jnp call would compile once per history length
    hist_x = lo + (hi - lo) / (1.0 + np.exp(-hist_u))
    hist_x[0] = x0
    converged, capped = bool(converged), bool(capped)
    if capped:
        warnings.warn(
            f"optimiser stopped{which} at the iteration cap ({max_iterations}) before "
            "convergence; the result may not be an optimum (raise max_iterations)",
            UserWarning,
            stacklevel=3,
        )
    elif not converged:
        warnings.warn(
            f"optimiser stopped{which} after {it} iterations without meeting its stopping rule "
            "(line search failed); the result may not be an optimum",
            UserWarning,
            stacklevel=3,
        )
    return OptimisationResult(
        x0=np.asarray(x0),
        x=np.asarray(problem.bounded(jnp.asarray(u))),
        value0=float(hist_v[0]),
        value=value,
        history_x=hist_x,
        history_value=hist_v,
        iterations=it,
        evaluations=int(n_eval),
        converged=converged,
        wall_time_s=wall,
    )


def _layout(problem: Problem):
    """What must be equal for problems to share one compiled batch: the structure of their
    arrays and their shapes and dtypes, and everything else (the static rest) by value."""
    arrays, static = eqx.partition(problem, eqx.is_array)
    leaves, tree = jax.tree.flatten(arrays)
    rest, rest_tree = jax.tree.flatten(static)
    try:
        hash(tuple(rest))
    except TypeError:  # an unhashable static leaf: a group of its own
        rest = [id(problem)]
    return (tree, tuple((np.shape(v), np.dtype(v.dtype)) for v in leaves), rest_tree,
            tuple(rest))


def minimise_batch(
    problems,
    x0s,
    solver: optx.AbstractMinimiser | optax.GradientTransformation | None = None,
    *,
    max_iterations: int = 100,
) -> list[OptimisationResult]:
    """:func:`minimise` of several problems at once: the problems of one structure (the same
    static layout: their arrays' structure, shapes and dtypes and every other field equal, e.g.
    rigid meshes of the same cell counts) go through one compiled ``jax.vmap`` of the solve
    :func:`minimise` runs, a group padded with copies of its last problem to a power of two up
    to 8, then to a multiple of 8 (``jaxgear.padded_batch``: one program per structure
    and padded size). Each problem keeps its own iterations, stopping rule and iteration cap (a finished
    problem's state is held while the rest of its batch goes on), so its result is
    :func:`minimise`'s to floating-point rounding (batched arithmetic may round differently in
    the last bits, which the line search can carry into differences of the order of the
    solver's tolerances); its history is recorded alike. No progress bar.

    Args:
        problems: the problems, (B,). x0s: their starts, normalised units, (B, n_i), each
            inside its bounds. solver, max_iterations: as :func:`minimise` (one for all).

    Returns:
        One :class:`OptimisationResult` per problem, in order; ``wall_time_s`` its batch's
        (compile included). A problem whose objective became non-finite has a non-finite
        ``value`` and ``converged`` False (:func:`minimise` raises FloatingPointError).

    Raises:
        ValueError: a solver of another kind, ``x0s`` of another count than ``problems``, a
            start of the wrong size or outside its bounds (before any solve).
        equinox.EquinoxRuntimeError: a runtime check inside a batch's solve failed (which
            problem is not known: solve that batch's problems one at a time).

    Warns:
        UserWarning: as :func:`minimise`, naming the problem's index.
    """
    solver = _as_minimiser(_DEFAULT_SOLVER if solver is None else solver)
    iterations = _iterations_of(solver)
    problems = list(problems)
    x0s = list(x0s)
    if len(x0s) != len(problems):
        raise ValueError(f"x0s has {len(x0s)} starts for {len(problems)} problems")
    x0s = [_checked_start(p, x) for p, x in zip(problems, x0s, strict=True)]
    groups: dict = {}
    for i, p in enumerate(problems):
        groups.setdefault(_layout(p), []).append(i)
    out: list = [None] * len(problems)
    for idx in groups.values():
        t0 = time.perf_counter()
        padded = idx + [idx[-1]] * (padded_batch(len(idx)) - len(idx))
        parts = [eqx.partition(problems[i], eqx.is_array) for i in padded]
        arrays = jax.tree.map(lambda *xs: jnp.stack(xs), *[a for a, _ in parts])
        u0 = jnp.stack([problems[i].unbounded(x0s[i]) for i in padded])
        with _LOCK:
            runs = [next(_RUN_IDS) for _ in idx]
        runs += [-1] * (len(padded) - len(idx))  # the copies report to no history
        recs = {r: {"history": {}, "bar": None} for r in runs if r >= 0}
        _RUNS.update(recs)
        try:
            u, value, n_iterations, n_eval, converged, capped = jax.device_get(_solve_batch(
                arrays, parts[0][1], solver, iterations, u0,
                jnp.asarray(int(max_iterations)), jnp.asarray(runs)))
            jax.effects_barrier()
        finally:
            for r in recs:
                del _RUNS[r]
        wall = time.perf_counter() - t0
        for j, i in enumerate(idx):
            v = float(value[j])
            out[i] = _result(problems[i], x0s[i], recs[runs[j]]["history"], u[j], v,
                             int(n_iterations[j]), n_eval[j],
                             bool(converged[j]) and np.isfinite(v), capped[j],
                             max_iterations, wall, f" (problem {i})")
    return out
