"""The exact cell-space contact solve on a factored window compliance (hybrid scenes).

:func:`jaxgear.solve_contact_cells` factors I + S C S afresh at every active-set pass
(S = diag √(k l w)). When C = V_W G V_Wᵀ, k and l are those of a cached position
(:class:`jaxgear.scenes.WindowCompliance`), the inverse B = (I + S_F C S_F)⁻¹ of the position's
full contact set F (every cell on the flanks, w = 1) is formed once per scene, and a pass is:

* the first pass (all cells of F in contact: where the active-set iteration of the seed (II-25)
  starts) as products: v = B S (a + E α), with α from the r × r balance Eᵀ P = b;
* a later pass with the cells D = F ∖ A out of contact by a Schur complement on D:
  (A_AA)⁻¹ = B_AA − B_AD (B_DD)⁻¹ B_DA. When D is one whole contact line (a spur pair's tip or
  root relief lifts lines whole), B_:D (B_DD)⁻¹ is cached too, and the pass is products only;
  otherwise one Cholesky factorisation on the smaller of D and A (at most ⌈c/2⌉ cells,
  gathered to that fixed size with identity padding): of B_DD, or of (I + S C S)_AA itself
  when the active set is the smaller. Under ``jax.vmap`` that factorisation runs only on the
  positions that need it, gathered in chunks (:func:`jaxgear._util.only_where_needed`): a
  vmapped ``cond`` or while loop would factor the whole batch whenever one position needs it
  (in a 41 × 41 relief map that was 0.76 s of 1.85 s).

Exact contact only: the smooth law's Newton matrices (weights φ' in (0, 1)) are not subsets of
F. Gradients: the iteration runs on stopped values; the answer with the final active set held
is linear in the loads and gaps (a, b), and a custom JVP applies that linear map (products and
the final pass's factor) to their tangents, so a forward run costs no extra solve. The cached
C, E, k, l are constants of the scene: no gradient flows into them.
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp

from ._contact import ContactSolution, ExactContact, _finish
from ._util import only_where_needed

__all__ = ["CellFactor", "line_factors", "solve_factored_cells"]

_EXACT = ExactContact()  # the law _finish reads (φ = max(0, Δ))


class _Consts(NamedTuple):
    """The constant parts of one position: B (c, c), C (c, c), E (c, r), s = √(k l) (c,), the
    mask (c,) as 0/1, the contact lines' cells ``lines`` (G, g) (padding c), ``K_line`` (G, c, g): B_:D (B_DD)⁻¹ for D each line's masked cells, and
    ``YF`` (1 + G, c, r): R(S E) on the full set and with each line out."""

    B: jax.Array
    C: jax.Array
    E: jax.Array
    s: jax.Array
    maskf: jax.Array
    lines: jax.Array
    K_line: jax.Array
    YF: jax.Array


class _Factor(NamedTuple):
    """How a pass with a given active set is solved: ``line`` the contact line that is out of
    contact whole (−1: none), else the Schur factor on J (the dropped cells when ``use_d``,
    else the active ones; padding c) with Cholesky factor L."""

    line: jax.Array
    J: jax.Array
    use_d: jax.Array
    L: jax.Array


def _rigid_amplitudes(F, y0, YF, r2):
    """α from the r × r balance Fᵀ (y0 + YF α) = r2 (r may be 0)."""
    if F.shape[1] == 0:
        return jnp.zeros((0,), y0.dtype)
    Z = F.T @ YF
    rhs = r2 - F.T @ y0
    if Z.shape == (1, 1):
        return rhs / Z[0, 0]
    return jnp.linalg.solve(Z, rhs)


def _one_hot(idx, c: int, dtype):
    """(len(idx), c) rows e_idx (a zero row for the padding index c)."""
    return (idx[:, None] == jnp.arange(c)[None, :]).astype(dtype)


def _no_factor(k: _Consts) -> _Factor:
    c = k.B.shape[0]
    half = (c + 1) // 2
    return _Factor(
        jnp.array(-1, jnp.int32),
        jnp.full((half,), c, jnp.int32),
        jnp.array(True),
        jnp.eye(half, dtype=k.B.dtype),
    )


def _generic(B, C, s, maskf, w):
    """The Schur factor on the smaller of D and A: (J, use_d, L); B, C (c, c), s, maskf, w (c,)."""
    c = B.shape[0]
    half = (c + 1) // 2
    dropped = maskf - w
    use_d = jnp.sum(dropped) <= half
    pick = jnp.where(use_d, dropped, w)
    # the picked cells first, in order (a stable sort: XLA's scatter on CPU is slow)
    order = jnp.argsort(pick <= 0, stable=True)[:half].astype(jnp.int32)
    valid = jnp.arange(half) < jnp.sum(pick > 0)
    J = jnp.where(valid, order, c)
    Jc = jnp.minimum(J, c - 1)
    eye = jnp.eye(half, dtype=B.dtype)
    QD = B[Jc[:, None], Jc[None, :]]
    QA = eye + s[Jc][:, None] * C[Jc[:, None], Jc[None, :]] * s[Jc][None, :]
    Q = jnp.where(use_d, QD, QA)
    Q = jnp.where(valid[:, None] & valid[None, :], Q, eye)
    return J, use_d, jnp.linalg.cholesky(Q)


_generic_where_needed = only_where_needed(_generic)


def _factor(k: _Consts, w) -> _Factor:
    """The factor of the pass with weights ``w`` (0/1, inside the mask)."""
    dropped = k.maskf - w
    line = jnp.array(-1, jnp.int32)
    if k.lines.shape[0]:
        # D = line l's cells on the flanks: all of them dropped, and no other cell
        c = k.B.shape[0]
        idx = jnp.minimum(k.lines, c - 1)
        on = jnp.where(k.lines < c, k.maskf[idx], 0.0)  # (G, g)
        n_on = jnp.sum(on, axis=1)
        match = (jnp.sum(on * dropped[idx], axis=1) == n_on) & (jnp.sum(dropped) == n_on)
        match = match & (n_on > 0)
        line = jnp.where(jnp.any(match), jnp.argmax(match), -1).astype(jnp.int32)
    need = jnp.any(dropped > 0) & (line < 0)
    none = _no_factor(k)
    J, use_d, L = _generic_where_needed(
        need, (none.J, none.use_d, none.L), k.B, k.C, k.s, k.maskf, w
    )
    return _Factor(line, J, use_d, L)


def _generic_mu(B, Hw, Z, fac: _Factor):
    """μ of the Schur factor on J (on D: B_DD μ_D = −Z_D; on A: the solution on A itself)."""
    c = B.shape[0]
    valid = (fac.J < c)[:, None]
    Jc = jnp.minimum(fac.J, c - 1)
    rhs = jnp.where(valid, jnp.where(fac.use_d, -Z[Jc], Hw[Jc]), 0.0)
    sol = jax.scipy.linalg.cho_solve((fac.L, True), rhs)
    return _one_hot(fac.J, c, Hw.dtype).T @ sol


def _generic_R(B, Hw, Z, fac: _Factor):
    """R on the Schur factor on J: on D, B (W H + μ) = Z + B μ; on A, μ itself."""
    mu = _generic_mu(B, Hw, Z, fac)
    return jnp.where(fac.use_d, Z + B @ mu, mu)


def _generic_pass(B, Hw, J, use_d, L):
    """(y0, YF) of a pass with the Schur factor (J, use_d, L): Hw = W [S r1, S E] (c, 1 + r)."""
    R = _generic_R(B, Hw, B @ Hw, _Factor(jnp.array(-1, jnp.int32), J, use_d, L))
    return R[:, 0], R[:, 1:]


_generic_pass_where_needed = only_where_needed(_generic_pass)


def _line_part(k: _Consts, Z, fac: _Factor):
    """(on a cached line, Z − B_:D (B_DD)⁻¹ Z_D): one whole line D out of contact."""
    c = k.B.shape[0]
    cells = jnp.minimum(k.lines, c - 1)  # padding: a zero column of K_line
    # every line's product, then the one out (a gather of K_line copies (c, g) per pass)
    parts = jnp.einsum("gcj,gjm->gcm", k.K_line, Z[cells])
    return fac.line >= 0, Z - parts[jnp.maximum(fac.line, 0)]


def _restricted(k: _Consts, w, H, fac: _Factor | None):
    """R = (A_w)⁻¹ W H on the active cells (zero elsewhere), A_w = I + W S C S W: H (c, m);
    the tangent map's form (no while loop: it must transpose).

    On D: R = B (W H + μ) with B_DD μ_D = −(B W H)_D (μ zero off D); on A: R_A = (A_AA)⁻¹ H_A."""
    Hw = w[:, None] * H
    Z = k.B @ Hw
    if fac is None:  # the full contact set: a product
        return Z
    R = _generic_R(k.B, Hw, Z, fac)
    if k.lines.shape[0]:
        on_line, by_line = _line_part(k, Z, fac)
        R = jnp.where(on_line, by_line, R)
    return w[:, None] * R


def _solve_pass(k: _Consts, w, g, fac: _Factor | None):
    """(y0, YF) = (R(S r1), R(S E)) of a pass on stopped values: S E's columns from the cache
    on the full set and with a cached line out; the Schur factor on J only at the positions
    that need it (:func:`jaxgear._util.only_where_needed`)."""
    Z = k.B @ (w * g)
    if fac is None:
        return Z, k.YF[0]
    y0, YF = Z, k.YF[0]
    on_line = jnp.array(False)
    if k.lines.shape[0]:
        on_line, by_line = _line_part(k, Z[:, None], fac)
        y0 = jnp.where(on_line, by_line[:, 0], y0)
        YF = jnp.where(on_line, k.YF[1 + jnp.maximum(fac.line, 0)], YF)
    c = k.B.shape[0]
    need = ~on_line & jnp.any(fac.J < c)
    Hw = w[:, None] * jnp.concatenate([g[:, None], k.s[:, None] * k.E], axis=1)
    y0, YF = _generic_pass_where_needed(need, (y0, YF), k.B, Hw, fac.J, fac.use_d, fac.L)
    return w * y0, w[:, None] * YF


def _pass(k: _Consts, w, r1, r2, fac, YF=None):
    """One linear solve with the cell weights ``w``: (gap Δ (c,), α (r,), cell forces P (c,),
    YF = R(S E) (c, r)). With ``YF`` given (that of the same active set): the tangent map,
    linear in r1, r2 (no while loop: it must transpose)."""
    F = k.s[:, None] * k.E
    if YF is None:
        y0, YF = _solve_pass(k, w, k.s * r1, fac)
    else:
        y0 = _restricted(k, w, (k.s * r1)[:, None], fac)[:, 0]
    alpha = _rigid_amplitudes(w[:, None] * F, y0, YF, r2)
    P = k.s * (y0 + YF @ alpha)
    return r1 - k.C @ P + k.E @ alpha, alpha, P, YF


@jax.custom_jvp
def _held(k, w, fac, YF, gap, alpha, force, r1, r2):
    """(gap, α, P) of the final pass, found on stopped values; its JVP is the linear solve with
    the final active set held (:func:`_pass` with the final factor and R(S E) on the
    tangents)."""
    return gap, alpha, force


@_held.defjvp
def _held_jvp(primals, tangents):
    k, w, fac, YF, gap, alpha, force, _, _ = primals
    dr1, dr2 = tangents[-2], tangents[-1]
    return (gap, alpha, force), _pass(k, w, dr1, dr2, fac, YF)[:3]


def line_factors(B, E, kl, mask, lines):
    """The cached parts of a pass with one whole contact line out of contact: K_line
    (G, c, g), B_:D (B_DD)⁻¹ for D each line's cells on the flanks (zero columns off the flanks
    and on the padding), and YF (1 + G, c, r), R(S E) on the full set and with each line out.

    Args:
        B: (I + S_F C S_F)⁻¹ of the full contact set, (c, c) (dimensionless). E: the cells'
            rigid-body approach per unit amplitude, (c, r). kl: k l (N/m), zero off the
            flanks (c,). mask: cells on the flanks (c,), bool. lines: each line's cells (G, g)
            (padding c).

    Returns:
        (K_line (G, c, g), YF (1 + G, c, r)): :class:`CellFactor`'s ``K_line`` and ``YF``.

    No value checks (traced arrays, a scene's cached constants): a compliance C that is not
    symmetric positive semidefinite gives NaN factors, not an error.
    """
    B, E, kl, mask, lines = (jnp.asarray(x) for x in (B, E, kl, mask, lines))
    c = B.shape[0]
    idx = jnp.minimum(lines, c - 1)
    valid = (lines < c) & mask[idx]
    YF0 = B @ (jnp.where(mask, jnp.sqrt(kl), 0.0)[:, None] * E)

    def one(i, v, line):
        eye = jnp.eye(i.shape[0], dtype=B.dtype)
        Q = jnp.where(v[:, None] & v[None, :], B[i[:, None], i[None, :]], eye)
        Qi = jax.scipy.linalg.cho_solve(jax.scipy.linalg.cho_factor(Q), eye)
        K = jnp.where(v[None, :], B[:, i], 0.0) @ (0.5 * (Qi + Qi.T))
        out = jnp.any(line[:, None] == jnp.arange(c)[None, :], axis=0)
        w = (mask & ~out).astype(B.dtype)
        return K, w[:, None] * (YF0 - K @ YF0[i])

    K, YF = jax.vmap(one)(idx, valid, lines)
    return K, jnp.concatenate([YF0[None], YF], axis=0)


class CellFactor(NamedTuple):
    """The cached, constant parts of one position's cell problem (a
    :class:`jaxgear.scenes.WindowCompliance` slice holds the same fields and serves as well).

    Attributes:
        B: (I + S_F C S_F)⁻¹, (c, c). C: cell compliance (m/N), (c, c). E: (c, r).
        kl: k l per cell (N/m), zero off the mask, (c,). mask: cells on the flanks (c,).
        lines, K_line, YF: the contact lines' cells (G, g) (padding c) and
            :func:`line_factors` (None: no line is cached; every later pass is factored).
    """

    B: jax.Array
    C: jax.Array
    E: jax.Array
    kl: jax.Array
    mask: jax.Array
    lines: jax.Array | None = None
    K_line: jax.Array | None = None
    YF: jax.Array | None = None


def solve_factored_cells(
    factor: CellFactor, a, b, k, max_iterations: int
) -> tuple[ContactSolution, jax.Array, jax.Array]:
    """The exact contact problem of :func:`jaxgear.solve_contact_cells`
    (Δ − a + C P(Δ) − E α = 0, Eᵀ P(Δ) = b, P = k l max(Δ, 0)) with B = (I + S_F C S_F)⁻¹
    given (S_F = diag √(k l) on the mask, identity off it): see the module docstring.

    Args:
        factor: the cached, constant parts (:class:`CellFactor`, or an object with its
            fields, such as a :class:`jaxgear.scenes.WindowCompliance` slice).
        a: free gaps (m), (c,). b: loads on the rigid-body modes, (r,).
        k: cell stiffness per unit length (N/m²), (c,) (for the force density).
        max_iterations: cap on active-set passes (>= 1).

    Returns:
        (solution, P (N), α), as :func:`jaxgear.solve_contact_cells`.

    Example:
        ``line_factors`` once per position, then ``solve_factored_cells(CellFactor(B, C, E,
        kl, mask, lines, *line_factors(B, E, kl, mask, lines)), a, b, k, 100)``; under
        ``jax.vmap`` over gaps and loads, the factorisation runs only where a position needs
        it.
    """
    B, C, E, kl, mask = factor.B, factor.C, factor.E, factor.kl, factor.mask
    lines, K_line, YF = factor.lines, factor.K_line, factor.YF
    sg = jax.lax.stop_gradient
    B, C, E, kl = (sg(jnp.asarray(x)) for x in (B, C, E, kl))
    mask = jnp.asarray(mask)
    maskf = mask.astype(kl.dtype)
    c = B.shape[0]
    if lines is None:
        lines = jnp.zeros((0, 1), jnp.int32)
        K_line = jnp.zeros((0, c, 1), B.dtype)
        YF = (B @ (jnp.sqrt(kl)[:, None] * E))[None]
    lines = jnp.asarray(lines, jnp.int32)
    consts = _Consts(
        B, C, E, jnp.sqrt(kl), maskf, lines, sg(jnp.asarray(K_line)), sg(jnp.asarray(YF))
    )
    a_, b_ = sg(a), sg(b)

    gap, alpha, force, YF = _pass(consts, maskf, a_, b_, None)
    new = maskf * (gap > 0).astype(maskf.dtype)

    def cond(state):
        *_, it, changed = state
        return changed & (it < max_iterations)

    def body(state):
        *_, new, it, _ = state
        fac = _factor(consts, new)
        gap, alpha, force, YF = _pass(consts, new, a_, b_, fac)
        nxt = maskf * (gap > 0).astype(maskf.dtype)
        return new, fac, YF, gap, alpha, force, nxt, it + 1, jnp.any(nxt != new)

    init = (
        maskf,
        _no_factor(consts),
        YF,
        gap,
        alpha,
        force,
        new,
        jnp.array(1),
        jnp.any(new != maskf),
    )
    w, fac, YF, gap, alpha, force, _, it, changed = jax.lax.while_loop(cond, body, init)
    gap, alpha, force = _held(consts, w, fac, YF, gap, alpha, force, a, b)
    sol = _finish(gap, gap, k, kl, mask, _EXACT, it, jnp.where(changed, 1, 0))
    return sol, force, alpha
