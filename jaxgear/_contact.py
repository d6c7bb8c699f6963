"""Unilateral contact law on a linear structure: exact (active set) and smooth (penalised).

Cell force per unit length ``p = k φ(Δ)``, ``Δ = V·X − δ0`` (seed (2.9)/(2.30), DESIGN.md §5), and
equilibrium ``K_s X + Σ_c k_c l_c φ(Δ_c) V_c = F``.

* ``exact``: φ(Δ) = max(0, Δ). Solved by the active-set iteration of the seed (II-25): solve with
  the current contact set, drop the cells in tension, add the cells that interfere, repeat until
  the set is unchanged. It is Newton's method on a piecewise-linear equation; starting from all
  cells in contact it approaches from the stiff side and ends in a finite number of passes.
* ``smooth``: φ_w(Δ) = w·softplus(Δ/w), C^∞, error O(w) (≤ w ln 2 at Δ = 0). Newton's method
  started from the exact solution.

Gradients: the iterations run on stopped gradients. Exact mode: the final linear solve with the
active set held is the differentiable answer (valid away from kinks where a cell enters or leaves
contact). Smooth mode: ``jax.lax.custom_root`` gives the implicit-function-theorem derivatives
dx = −J⁻¹ ∂r/∂p of every order, forward and reverse (J the tangent stiffness at the root).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

__all__ = ["ContactSolution", "solve_contact"]


class ContactSolution(eqx.Module):
    """Solution of one contact problem.

    Attributes:
        x: generalised coordinates X, shape (n,).
        gap: Δ = V·X − δ0 per cell (m), shape (c,) (positive = interpenetration/approach).
        weight: dφ/dΔ per cell (exact: 1 in contact, 0 out), shape (c,).
        force_density: p = k φ(Δ) per cell (N/m), shape (c,), zero outside the mask.
        iterations: passes used. result: 0 ok, else a :class:`~jaxgear.ContactResult` code.
    """

    x: Float[Array, " n"]
    gap: Float[Array, " c"]
    weight: Float[Array, " c"]
    force_density: Float[Array, " c"]
    iterations: Int[Array, ""]
    result: Int[Array, ""]


def _solve(A, b):
    """Dense solve; a division for one coordinate (the rigid mesh), which XLA runs much faster."""
    if A.shape == (1, 1):
        return b / A[0, 0]
    return jnp.linalg.solve(A, b)


def _phi(gap, mode: str, width):
    if mode == "exact":
        return jnp.maximum(gap, 0.0), (gap > 0).astype(gap.dtype)
    return width * jax.nn.softplus(gap / width), jax.nn.sigmoid(gap / width)


def _assemble(Ks, F, V, kl, delta0, weight):
    """Tangent system of the contact law linearised with cell weights: K_t, F_t."""
    kw = kl * weight
    Kt = Ks + jnp.einsum("c,ci,cj->ij", kw, V, V)
    Ft = F + jnp.einsum("c,c,ci->i", kw, delta0, V)
    return Kt, Ft


def solve_contact(
    Ks: Float[Array, "n n"],
    F: Float[Array, " n"],
    V: Float[Array, "c n"],
    k: Float[Array, " c"],
    length: Float[Array, " c"],
    delta0: Float[Array, " c"],
    mask: Bool[Array, " c"],
    mode: str = "exact",
    width: Float[Array, ""] | float = 1e-7,
    max_iterations: int = 100,
) -> ContactSolution:
    """Solve the unilateral contact problem on a linear structure.

    Args:
        Ks: structure stiffness (units of F per unit X), shape (n, n).
        F: external generalised load, shape (n,).
        V: structure vector of each cell (m per unit X), shape (c, n).
        k: cell stiffness per unit contact length k_c (N/m²), shape (c,).
        length: cell length l_c along its contact line (m), shape (c,).
        delta0: initial separation δ0 (m), shape (c,), >= 0 (2.8).
        mask: cells that exist (on the flanks), shape (c,).
        mode: "exact" (active set) or "smooth" (softplus ramp of ``width`` m).
        width: smoothing width w (m), smooth mode only.
        max_iterations: cap on active-set passes / Newton steps.

    Returns:
        :class:`ContactSolution`; ``result`` != 0 flags failure (never a silent NaN: callers turn
        it into an error with ``eqx.error_if`` or report it).
    """
    if mode not in ("exact", "smooth"):
        raise ValueError(f"contact mode = {mode!r}: allowed 'exact', 'smooth'")
    kl = jnp.where(mask, k * length, 0.0)
    sg = jax.lax.stop_gradient
    Ks_, F_, V_, kl_, d0_ = sg(Ks), sg(F), sg(V), sg(kl), sg(delta0)
    maskf = mask.astype(kl.dtype)

    def solve_with(weight):
        Kt, Ft = _assemble(Ks_, F_, V_, kl_, d0_, weight)
        return _solve(Kt, Ft)

    # exact active set from all cells in contact
    def cond(state):
        _, _, it, changed = state
        return changed & (it < max_iterations)

    def body(state):
        _, active, it, _ = state
        x = solve_with(active)
        new = maskf * ((V_ @ x - d0_) > 0).astype(kl.dtype)
        return x, new, it + 1, jnp.any(new != active)

    x0 = jnp.zeros(F.shape, F.dtype)
    x_ex, active, it_ex, changed = jax.lax.while_loop(
        cond, body, (x0, maskf, jnp.array(0), jnp.array(True))
    )
    result = jnp.where(changed, 1, 0)

    if mode == "exact":
        weight = sg(active)
        Kt, Ft = _assemble(Ks, F, V, kl, delta0, weight)
        x = _solve(Kt, Ft)
        iterations = it_ex
    else:
        tiny = jnp.finfo(F.dtype).eps

        def residual(x):
            phi, _ = _phi(V @ x - delta0, "smooth", width)
            return Ks @ x + V.T @ (kl * phi) - F

        # Newton on stopped values, from the exact solution
        def ncond(state):
            _, it, step = state
            return (step > 8 * tiny) & (it < max_iterations)

        def nbody(state):
            x, it, _ = state
            phi, dphi = _phi(V_ @ x - d0_, "smooth", sg(width))
            r = Ks_ @ x + V_.T @ (kl_ * phi) - F_
            Kt = Ks_ + jnp.einsum("c,ci,cj->ij", kl_ * dphi, V_, V_)
            dx = _solve(Kt, r)
            step = jnp.max(jnp.abs(dx)) / jnp.maximum(jnp.max(jnp.abs(x)), tiny)
            return x - dx, it + 1, step

        x_sm, it_sm, step = jax.lax.while_loop(
            ncond, nbody, (sg(x_ex), jnp.array(0), jnp.array(jnp.inf, F.dtype))
        )

        def tangent_solve(g, y):
            # g is the residual linearised at the root: the SPD tangent K_s + Σ k l φ' V Vᵀ
            return _solve(jax.jacfwd(g)(y), y)

        # value: the Newton root; derivatives of every order, forward and reverse, by the
        # implicit-function theorem dx = −J⁻¹ ∂r/∂p (jax.lax.custom_root)
        x = jax.lax.custom_root(residual, sg(x_sm), lambda _, x0: x0, tangent_solve)
        result = jnp.where(step > 1e3 * tiny, 1, result)
        iterations = it_ex + it_sm
    gap = V @ x - delta0
    phi, weight = _phi(gap, mode, width)
    phi = jnp.where(mask, phi, 0.0)
    weight = jnp.where(mask, weight, 0.0)
    result = jnp.where(jnp.sum(weight * kl) <= 0, 2, result)
    result = jnp.where(jnp.all(jnp.isfinite(x)), result, 3)
    return ContactSolution(
        x=x, gap=gap, weight=weight, force_density=k * phi, iterations=iterations, result=result
    )
