"""Gradient-based minimisation with optax (L-BFGS with zoom line search, or Adam).

The loop runs as jitted chunks of ``lax.while_loop`` iterations; between chunks Python updates a
progress bar and checks the stopping rule, so a long run shows progress without host callbacks.
"""

from __future__ import annotations

import functools
import time
import warnings

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import optax

from ._problem import Problem

__all__ = ["OptimisationResult", "minimise"]

_OPTIMISERS: dict = {}


def _optimiser(method: str, learning_rate: float):
    """One optax transformation per (method, rate), reused so compiled chunks are reused too."""
    key = (method, float(learning_rate) if method == "adam" else None)
    if key not in _OPTIMISERS:
        _OPTIMISERS[key] = (
            optax.lbfgs(linesearch=optax.scale_by_zoom_linesearch(max_linesearch_steps=20))
            if method == "lbfgs"
            else optax.adam(learning_rate)
        )
    return _OPTIMISERS[key]


def _objective(problem: Problem, u):
    return problem.value(problem.bounded(u), "smooth")


_value = eqx.filter_jit(_objective)


@eqx.filter_jit
def _run_chunk(problem, opt, method, chunk, tol, u, state, value, n_eval):
    """Up to ``chunk`` optimiser iterations in a ``lax.while_loop`` (stops early when done)."""
    fn = functools.partial(_objective, problem)

    def cond(c):
        return (c[3] < chunk) & ~c[5]

    def body(c):
        u, state, value, k, n_eval, _ = c
        if method == "lbfgs":
            v, g = optax.value_and_grad_from_state(fn)(u, state=state)
            updates, state = opt.update(g, state, u, value=v, grad=g, value_fn=fn)
            n_eval = n_eval + 1 + optax.tree_utils.tree_get(state, "num_linesearch_steps")
        else:
            v, g = jax.value_and_grad(fn)(u)
            updates, state = opt.update(g, state, u)
            n_eval = n_eval + 1
        u_new = optax.apply_updates(u, updates)
        v_new = optax.tree_utils.tree_get(state, "value") if method == "lbfgs" else fn(u_new)
        done = (jnp.abs(v_new - v) <= tol * jnp.maximum(jnp.abs(v), 1e-12)) & (
            jnp.linalg.norm(g) < jnp.sqrt(tol)
        )
        return u_new, state, v_new, k + 1, n_eval, done

    return jax.lax.while_loop(cond, body, (u, state, value, jnp.array(0), n_eval, jnp.array(False)))


class OptimisationResult(eqx.Module):
    """Outcome of :func:`minimise` (normalised design values; see ``Problem.to_physical``).

    Attributes:
        x0, x: initial and final design values, shape (n,).
        value0, value: scaled smooth-mode objective at x0 and x.
        history_x: design values after each iteration, shape (iterations+1, n).
        history_value: objective after each iteration, shape (iterations+1,).
        iterations: optimiser iterations. evaluations: objective(+gradient) evaluations,
            line-search evaluations included. converged: stopping rule met (not max_iterations).
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
    chunk: int = 1,
    progress: bool = True,
) -> OptimisationResult:
    """Minimise ``problem.value`` (smooth contact) from normalised start ``x0``.

    Args:
        problem: the problem (bounds by reparametrisation).
        x0: start, normalised units, shape (n,), inside the bounds.
        method: "lbfgs" (``optax.lbfgs`` with zoom line search) or "adam".
        max_iterations: iteration cap. tol: stop when the objective changes by less than ``tol``
            (relative) over an iteration and the gradient norm in u is below ``sqrt(tol)``.
        learning_rate: Adam step. chunk: iterations per jitted chunk (progress granularity).

    Raises:
        ValueError: unknown method, x0 of the wrong size or outside the bounds.

    Warns:
        UserWarning: the iteration cap was reached before the stopping rule (``converged`` is
            False).
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
    opt = _optimiser(method, learning_rate)
    u0 = problem.unbounded(x0)
    state = opt.init(u0)
    u = u0
    value0 = float(_value(problem, u0))
    value = jnp.asarray(value0)
    hist_x, hist_v = [np.asarray(x0)], [value0]
    it, n_eval, done = 0, jnp.array(1), False
    from tqdm.auto import tqdm  # progress only; imported on use

    bar = tqdm(total=max_iterations, desc=f"optimise ({method})", disable=not progress)
    while it < max_iterations and not done:
        u, state, value, k, n_eval, done_arr = _run_chunk(
            problem, opt, method, chunk, tol, u, state, value, n_eval
        )
        k = int(k)
        it += k
        done = bool(done_arr)
        hist_x.append(np.asarray(problem.bounded(u)))
        hist_v.append(float(value))
        bar.update(k)
        bar.set_postfix(objective=f"{float(value):.5g}")
        if k == 0:
            break
    if done or it < max_iterations:  # stopped early: the bar ends full, not at it/max_iterations
        bar.total = max(it, 1)
        bar.n = it
        bar.refresh()
    bar.close()
    if not np.all(np.isfinite(hist_v[-1])):
        raise FloatingPointError(
            "optimisation produced a non-finite objective; check the bounds "
            "and the smooth contact width"
        )
    if not done:
        warnings.warn(
            f"optimiser stopped at the iteration cap ({max_iterations}) before convergence; "
            "the result may not be an optimum (raise max_iterations)",
            UserWarning,
            stacklevel=2,
        )
    return OptimisationResult(
        x0=np.asarray(x0),
        x=np.asarray(problem.bounded(u)),
        value0=value0,
        value=float(value),
        history_x=np.asarray(hist_x),
        history_value=np.asarray(hist_v),
        iterations=it,
        evaluations=int(n_eval),
        converged=bool(done),
        wall_time_s=time.perf_counter() - t0,
    )
