"""The exact cell-space contact solve on a factored window compliance (hybrid scenes).

:func:`jaxgear.solve_contact_cells` factors I + S C S afresh at every active-set pass
(S = diag √(k l w)). When C = V_W G V_Wᵀ, k and l are those of a cached position
(:class:`jaxgear.scenes.WindowCompliance`), the inverse B = (I + S_F C S_F)⁻¹ of the position's
full contact set F (every cell on the flanks, w = 1) is formed once per scene, and a pass is:

* the first pass (all cells of F in contact: where the active-set iteration of the seed (II-25)
  starts) as products: v = B S (a + E α), with α from the r × r balance Eᵀ P = b;
* a later pass with the cells D = F ∖ A out of contact by a Schur complement on the smaller of
  D and A (at most ⌈c/2⌉ cells, gathered to that fixed size with identity padding): on D,
  (A_AA)⁻¹ = B_AA − B_AD (B_DD)⁻¹ B_DA (one Cholesky factorisation of B_DD), or on A, a
  factorisation of (I + S C S)_AA itself when the active set is the smaller.

Exact contact only: the smooth law's Newton matrices (weights φ' in (0, 1)) are not subsets of
F. Gradients: the iteration runs on stopped values; the answer with the final active set held
is linear in the loads and gaps (a, b), and a custom JVP applies that linear map (products and
the final pass's factor) to their tangents, so a forward run costs no extra solve. The cached
C, E, k, l are constants of the scene: no gradient flows into them.
"""

from __future__ import annotations

import jax
import jax.numpy as jnp

from ._contact import ContactSolution, ExactContact, _finish

__all__ = ["solve_factored_cells"]


def _rigid_amplitudes(F, y0, YF, r2):
    """α from the r × r balance Fᵀ (y0 + YF α) = r2 (r may be 0)."""
    if F.shape[1] == 0:
        return jnp.zeros((0,), y0.dtype)
    Z = F.T @ YF
    rhs = r2 - F.T @ y0
    if Z.shape == (1, 1):
        return rhs / Z[0, 0]
    return jnp.linalg.solve(Z, rhs)


def _factor(B, C, s, w, maskf, half):
    """The Schur factor of the pass with weights ``w`` (0/1, inside the mask): (J, use_D, L).

    J: the dropped cells D = F ∖ A if |D| <= half, else the active ones A, gathered to
    ``half`` entries (padding index c); L: the Cholesky factor of B_JJ (on D) or of
    (I + S C S)_JJ (on A), identity on the padding."""
    c = B.shape[0]
    dropped = maskf - w
    use_d = jnp.sum(dropped) <= half
    pick = jnp.where(use_d, dropped, w)
    J = jnp.nonzero(pick > 0, size=half, fill_value=c)[0].astype(jnp.int32)
    valid = J < c
    Jc = jnp.minimum(J, c - 1)
    eye = jnp.eye(half, dtype=B.dtype)
    QD = B[Jc[:, None], Jc[None, :]]
    QA = eye + s[Jc][:, None] * C[Jc[:, None], Jc[None, :]] * s[Jc][None, :]
    Q = jnp.where(use_d, QD, QA)
    Q = jnp.where(valid[:, None] & valid[None, :], Q, eye)
    return J, use_d, jnp.linalg.cholesky(Q)


def _restricted(B, w, H, fac):
    """R = (A_w)⁻¹ W H on the active cells (zero elsewhere), A_w = I + W S C S W: H (c, m).

    On D: R = B (W H + μ) with B_DD μ_D = −(B W H)_D (μ zero off D); on A: R_A = (A_AA)⁻¹ H_A."""
    Hw = w[:, None] * H
    Z = B @ Hw
    if fac is None:  # the full contact set: a product
        return Z
    J, use_d, L = fac
    c = B.shape[0]
    valid = (J < c)[:, None]
    Jc = jnp.minimum(J, c - 1)
    rhs = jnp.where(valid, jnp.where(use_d, -Z[Jc], Hw[Jc]), 0.0)
    mu = (
        jnp.zeros(Hw.shape, Hw.dtype)
        .at[J]
        .add(jax.scipy.linalg.cho_solve((L, True), rhs), mode="drop")
    )
    return w[:, None] * jnp.where(use_d, B @ (Hw + mu), mu)


def _pass(B, C, E, s, w, r1, r2, fac, linear: bool = False):
    """One linear solve with the cell weights ``w``: (gap Δ (c,), α (r,), cell forces P (c,)).
    ``linear``: the tangent map (the columns of E solved apart, so that it stays linear in
    r1, r2)."""
    F = s[:, None] * E
    if linear:
        YF = _restricted(B, w, F, fac)
        y0 = _restricted(B, w, (s * r1)[:, None], fac)[:, 0]
    else:
        R = _restricted(B, w, jnp.concatenate([(s * r1)[:, None], F], axis=1), fac)
        y0, YF = R[:, 0], R[:, 1:]
    alpha = _rigid_amplitudes(w[:, None] * F, y0, YF, r2)
    P = s * (y0 + YF @ alpha)
    return r1 - C @ P + E @ alpha, alpha, P


@jax.custom_jvp
def _held(B, C, E, s, w, fac, gap, alpha, force, r1, r2):
    """(gap, α, P) of the final pass, found on stopped values; its JVP is the linear solve with
    the final active set held (:func:`_pass` with the final factor on the tangents)."""
    return gap, alpha, force


@_held.defjvp
def _held_jvp(primals, tangents):
    B, C, E, s, w, fac, gap, alpha, force, _, _ = primals
    dr1, dr2 = tangents[-2], tangents[-1]
    return (gap, alpha, force), _pass(B, C, E, s, w, dr1, dr2, fac, linear=True)


def solve_factored_cells(
    B, C, E, kl, mask, a, b, k, max_iterations: int
) -> tuple[ContactSolution, jax.Array, jax.Array]:
    """The exact contact problem of :func:`jaxgear.solve_contact_cells`
    (Δ − a + C P(Δ) − E α = 0, Eᵀ P(Δ) = b, P = k l max(Δ, 0)) with B = (I + S_F C S_F)⁻¹
    given (S_F = diag √(k l) on the mask, identity off it): see the module docstring.

    Args:
        B: (c, c), C: cell compliance (m/N), (c, c), E: (c, r), kl: k l per cell (N/m), zero
            off the mask, (c,), mask: cells on the flanks (c,): the cached, constant parts.
        a: free gaps (m), (c,). b: loads on the rigid-body modes, (r,).
        k: cell stiffness per unit length (N/m²), (c,) (for the force density).
        max_iterations: cap on active-set passes (>= 1).

    Returns:
        (solution, P (N), α), as :func:`jaxgear.solve_contact_cells`.
    """
    sg = jax.lax.stop_gradient
    B, C, E, kl = (sg(jnp.asarray(x)) for x in (B, C, E, kl))
    mask = jnp.asarray(mask)
    maskf = mask.astype(kl.dtype)
    s = jnp.sqrt(kl)
    half = (B.shape[0] + 1) // 2
    a_, b_ = sg(a), sg(b)

    gap, alpha, force = _pass(B, C, E, s, maskf, a_, b_, None)
    new = maskf * (gap > 0).astype(maskf.dtype)
    c = B.shape[0]
    fac0 = (
        jnp.full((half,), c, jnp.int32),
        jnp.array(True),
        jnp.eye(half, dtype=B.dtype),
    )

    def cond(state):
        *_, it, changed = state
        return changed & (it < max_iterations)

    def body(state):
        _, _, _, _, _, new, it, _ = state
        fac = _factor(B, C, s, new, maskf, half)
        gap, alpha, force = _pass(B, C, E, s, new, a_, b_, fac)
        nxt = maskf * (gap > 0).astype(maskf.dtype)
        return new, fac, gap, alpha, force, nxt, it + 1, jnp.any(nxt != new)

    init = (maskf, fac0, gap, alpha, force, new, jnp.array(1), jnp.any(new != maskf))
    w, fac, gap, alpha, force, _, it, changed = jax.lax.while_loop(cond, body, init)
    gap, alpha, force = _held(B, C, E, s, w, fac, gap, alpha, force, a, b)
    sol = _finish(gap, gap, k, kl, mask, _EXACT, it, jnp.where(changed, 1, 0))
    return sol, force, alpha


_EXACT = ExactContact()  # the law _finish reads (φ = max(0, Δ))
