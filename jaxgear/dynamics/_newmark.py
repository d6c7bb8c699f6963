"""The Newmark step with unilateral contact: the one time integrator of every scene.

Average acceleration (β = 1/4, γ = 1/2; seed annex 2, (2.1)–(2.6)) for

    M Ẍ + C(t) Ẋ + K X + Σ_c P_c(V_c·X − δ0_c) V_c = F,

with P_c = k_c l_c φ(Δ_c) the cell forces (seed (2.9)/(2.30); docs/dynamics.md, "Model"). Each step
is a static contact problem K_eff X = F_eff − Vᵀ P with K_eff = K + a₀ M + a₁ C, a₀ = 1/(βΔt²),
a₁ = γ/(βΔt), solved in whichever space is smaller (docs/design.md, "Contact laws"):

* **coordinates** (the rigid-node scenes: a few tens of DOFs against tens of cells): the
  cells see every coordinate; :func:`jaxgear.solve_contact` factors K_eff + Vᵀ diag(k l) V at each
  active-set pass (seed II-25);
* **cells** (condensed bodies: thousands of DOFs, the cells on a small window W of them):
  G = K_eff⁻¹ once per speed, X* = G F_eff, the gaps Δ = V X*_W − δ0 − C_eff P with the window's
  compliance C_eff = V G_WW Vᵀ (:func:`jaxgear.solve_contact_cells`), then X = X* − G_{:W} Vᵀ P: a
  step costs n² and the window's compliance, not a factorisation (docs/hybrid.md, "Dynamics").

A mesh damping that follows the mesh (the hybrid scene's Rayleigh and composite models) is a
rank-w change of C per block of steps, taken by Woodbury in the cell space (:class:`MeshDamping`).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow
from .._contact import ContactLaw, solve_contact, solve_contact_cells
from .._results import ContactResult, DynamicsResult

BETA, GAMMA = 0.25, 0.5


class MeshDamping(NamedTuple):
    """The mesh share of the damping, C(p) = C + c_m Rᵀ K̄_m(p) R in block p of steps.

    Attributes:
        block: p ↦ (U (w,), B (w, w), ok): K̄_m(p) = E_Uᵀ B E_U on the window U of coordinates
            (E_U (w, n) picks them) and whether every window of the block lies inside U.
        c_m: its factor (s for Rayleigh, - for the composite).
        R: (n, n), or None for the identity (Rayleigh: C(p) = C + β K̄_m(p)).
    """

    block: Callable
    c_m: Float[Array, ""]
    R: Float[Array, "n n"] | None


def newmark(
    K: Float[Array, "n n"],
    M: Float[Array, "n n"],
    C: Float[Array, "n n"],
    F: Float[Array, " n"],
    dt,
    state,
    inputs,
    cells_at: Callable[[Any], CellRow],
    law: ContactLaw,
    record: Callable[[Array, Array, Array], Any] | None,
    *,
    check: Callable[[Array, Array, Array], Array] | None = None,
    mesh_damping: MeshDamping | None = None,
    record_entry: bool = False,
):
    """Integrate ``inputs``' steps by Newmark average acceleration with the contact loop.

    Args:
        K, M, C: stiffness, mass and damping (SI per coordinate), (n, n); C may hold a skew
            Coriolis term. F: the constant load (n,).
        dt: time step Δt (s).
        state: (X, Ẋ, Ẍ, result code, most contact passes), the first three (n,).
        inputs: one entry per step, leading shape (B, S): B blocks of S steps (the blocks of
            the mesh damping, e.g. mesh periods; B = 1 without it). An entry is whatever
            ``cells_at`` takes (a table row index, a pinion angle).
        cells_at: entry ↦ :class:`CellRow`; all steps use the same window kind (None or not).
        law: the contact law.
        record: (X, Ẋ, P) ↦ a pytree kept for every step, P the cell forces (N), (c,); None
            keeps nothing (a transient).
        check: (X, Ẋ, P) ↦ a :class:`~jaxgear.DynamicsResult` code of the step (e.g. energy
            blow-up), 0 if none; the loop itself flags contact loops that did not converge,
            non-finite states and cells outside the mesh damping's window.
        mesh_damping: :class:`MeshDamping` or None (needs a window: the cell space).
        record_entry: call ``record(X, Ẋ, P, entry)`` with the step's entry of ``inputs`` (to
            reduce per-cell values that depend on the position inside the loop).

    Returns:
        (the final state, the records flattened over the blocks, leading axis B·S, or None).
        The result code keeps the first failure of the run.
    """
    dtype = K.dtype
    n = K.shape[0]
    b, g = BETA, GAMMA
    a0, a1 = 1.0 / (b * dt * dt), g / (b * dt)
    Keff = K + a0 * M + a1 * C
    first = jax.tree.map(lambda x: x[0, 0], inputs)
    coordinates = jax.eval_shape(cells_at, first).idx is None
    if coordinates and mesh_damping is not None:
        raise ValueError("a mesh damping needs the cell space (a window of coordinates)")
    G = None if coordinates else jnp.linalg.inv(Keff)
    if mesh_damping is not None:
        block, c_m, R = mesh_damping
        GR = G if R is None else G @ R.T  # G Rᵀ (n, n): G Wᵀ = (G Rᵀ)[:, U]

    def run_block(carry, p_in):
        p, entries = p_in
        U = None
        ok = jnp.array(True)
        if mesh_damping is not None:
            U, B, ok = block(p)
            w = U.shape[0]
            if R is None:  # W = E_U

                def project(x):  # W x, x (n,) or (n, m)
                    return x[U]

                def spread(z):  # Wᵀ z
                    return jnp.zeros((n,), dtype).at[U].add(z)

            else:
                W = R[U]

                def project(x):
                    return W @ x

                def spread(z):
                    return W.T @ z

            # the block's effective stiffness is K_eff + a₁ c_m Wᵀ B W: Woodbury on G,
            # G_p = G − (G Wᵀ) Q (W G), Q = (I + A W G Wᵀ)⁻¹ A, A = a₁ c_m B
            A = (a1 * c_m) * B
            GW = GR[:, U]  # G Wᵀ (n, w)
            Q = jnp.linalg.solve(jnp.eye(w, dtype=dtype) + A @ project(GW), A)
            GUU = G[U[:, None], U[None, :]] - GW[U] @ Q @ project(G[:, U])  # G_p on U
            pos = jnp.full((n,), w, jnp.int32).at[U].set(jnp.arange(w, dtype=jnp.int32))

        def solve(v):  # G_p v
            y = G @ v
            return y if U is None else y - GW @ (Q @ project(y))

        def step(carry, entry):
            X, Xd, Xdd, code, it = carry
            row = cells_at(entry)
            v = a1 * X + (g / b - 1.0) * Xd + dt * (0.5 * g / b - 1.0) * Xdd
            Feff = F + M @ (a0 * X + Xd / (b * dt) + (0.5 / b - 1.0) * Xdd) + C @ v
            inside = jnp.array(True)
            if coordinates:
                sol = solve_contact(Keff, Feff, row.V, row.k, row.length, row.delta0, row.mask, law)
                Xn = sol.x
                P = sol.force_density * row.length
            else:
                idx = row.idx
                c = row.V.shape[0]
                if U is None:
                    Gw = G[idx[:, None], idx[None, :]]
                else:
                    Feff = Feff + spread(c_m * (B @ project(v)))  # the block's mesh damping
                    j = pos[idx]
                    inside = jnp.all(j < U.shape[0])
                    Gw = GUU[j[:, None], j[None, :]]
                xs = solve(Feff)
                sol, P, _ = solve_contact_cells(
                    row.V @ Gw @ row.V.T,
                    row.V @ xs[idx] - row.delta0,
                    jnp.zeros((c, 0), dtype),
                    jnp.zeros((0,), dtype),
                    row.k,
                    row.length,
                    row.mask,
                    law,
                )
                Xn = xs - solve(jnp.zeros_like(xs).at[idx].add(row.V.T @ P))
            Xddn = a0 * (Xn - X - dt * Xd - dt * dt * (0.5 - b) * Xdd)
            Xdn = Xd + dt * ((1.0 - g) * Xdd + g * Xddn)
            new = jnp.where(
                sol.result == ContactResult.max_iterations,
                DynamicsResult.contact_not_converged,
                DynamicsResult.successful,
            )
            finite = jnp.all(jnp.isfinite(Xn)) & jnp.all(jnp.isfinite(Xdn))
            finite = finite & (sol.result != ContactResult.non_finite)
            new = _first(new, jnp.where(finite, 0, DynamicsResult.non_finite))
            if check is not None:
                new = _first(new, check(Xn, Xdn, P))
            new = _first(new, jnp.where(inside & ok, 0, DynamicsResult.window_overflow))
            carry = (Xn, Xdn, Xddn, _first(code, new), jnp.maximum(it, sol.iterations))
            if record is None:
                return carry, None
            return carry, (record(Xn, Xdn, P, entry) if record_entry else record(Xn, Xdn, P))

        return jax.lax.scan(step, carry, entries)

    n_blocks = jax.tree.leaves(inputs)[0].shape[0]
    carry, out = jax.lax.scan(run_block, state, (jnp.arange(n_blocks), inputs))
    if record is None:
        return carry, None
    return carry, jax.tree.map(lambda x: x.reshape((x.shape[0] * x.shape[1],) + x.shape[2:]), out)


def _first(code, new):
    """The first failure sticks: ``code`` unless it is 0, then ``new``."""
    return jnp.where(code == 0, new, code)
