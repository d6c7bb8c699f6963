"""Unilateral contact law on a linear structure: exact (active set) and smooth (penalised).

Cell force per unit length ``p = k φ(Δ)``, ``Δ = V·X − δ0`` (seed (2.9)/(2.30); docs/design.md,
"Contact laws"), and equilibrium ``K_s X + Σ_c k_c l_c φ(Δ_c) V_c = F``.

The law is an object, passed as diffrax takes its solver: a :class:`AbstractContactLaw`,
:class:`ExactContact` or :class:`SmoothContact`, each with its iteration cap, its law φ and its
hooks into the two solvers (the answer after the active set, in the coordinates' space and in
the cells' space), so that the solvers never ask which law they hold.

* ``exact``: φ(Δ) = max(0, Δ). Solved by the active-set iteration of the seed (II-25): solve with
  the current contact set, drop the cells in tension, add the cells that interfere, repeat until
  the set is unchanged. It is Newton's method on a piecewise-linear equation; starting from all
  cells in contact it approaches from the stiff side and ends in a finite number of passes.
* ``smooth``: φ_w(Δ) = w·softplus(Δ/w), C^∞, error O(w) (≤ w ln 2 at Δ = 0). Newton's method
  started from the exact solution.

Stopping rules (``result`` 0 only when met; at ``max_iterations`` otherwise code 1,
:class:`~jaxgear.ContactResult` ``max_iterations``, never a silent success):

* exact: the active set is unchanged by a pass (finite; no tolerance).
* smooth: the scaled residual ρ = max_i |r_i| / s_i of the smooth equilibrium equations, where
  s_i sums the magnitudes of the terms of r_i and of (|J| |x|)_i (the rounding of x and δ0
  themselves): a componentwise backward error, independent of the load and length scales
  (N, N·m, m). With m the number of terms in a component (coordinates + cells in contact) and
  ε = ``jnp.finfo(dtype).eps``: converged when ρ <= 2 √m ε (round-off of a sum of m terms,
  random walk), or when a Newton step no longer halves ρ while ρ <= m ε (the worst-case
  round-off floor γ_m reached: more steps cannot improve it). A relative step criterion
  (|dx| <= 8 ε |x|) is not used: on large problems (400 slices) the step stalls at round-off
  above it, and the loop used to run to its cap. The result of the smooth solve is the
  Newton's alone (the active set only gives it its start).

Gradients: the iterations run on stopped gradients. Exact mode: the final linear solve with the
active set held is the differentiable answer (valid away from kinks where a cell enters or leaves
contact). Smooth mode: ``jax.lax.custom_root`` gives the implicit-function-theorem derivatives
dx = −J⁻¹ ∂r/∂p of every order, forward and reverse (J the tangent stiffness at the root).
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar, TypeAlias

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from ._util import check_integer, compiled_when_eager, is_traced, only_where_needed

__all__ = [
    "AbstractContactLaw",
    "ContactLaw",
    "ContactSolution",
    "ExactContact",
    "SmoothContact",
    "solve_contact",
    "solve_contact_cells",
]


class AbstractContactLaw(eqx.Module):
    """A unilateral contact law p = k φ(Δ) and its solution after the active-set iteration.

    Subclasses implement the law (:meth:`phi`), the dtype cast of their leaves (:meth:`astype`)
    and the two solver hooks (:meth:`dense_answer` for :func:`solve_contact`,
    :meth:`cells_answer` for :func:`solve_contact_cells`), which take the active set's exact
    answer and return the law's own.

    Attributes:
        max_iterations: cap on active-set passes (and Newton steps) per contact problem.
        mode: the law's name (``"exact"``, ``"smooth"``).
    """

    mode: eqx.AbstractClassVar[str]  # concrete laws also have a static ``max_iterations``

    @abc.abstractmethod
    def phi(self, gap: Float[Array, " c"]) -> tuple[Float[Array, " c"], Float[Array, " c"]]:
        """(φ(Δ), φ'(Δ)) per cell (m, -), shape (c,) each."""

    @abc.abstractmethod
    def astype(self, dtype) -> AbstractContactLaw:
        """The same law with its array leaves as ``dtype`` (the leaves the solvers trace)."""

    def with_traced_checks(self) -> AbstractContactLaw:
        """The law with run-time checks (``eqx.error_if``) on its traced leaves; none here."""
        return self

    @abc.abstractmethod
    def dense_answer(self, system: tuple, exact: tuple) -> tuple:
        """The answer of :func:`solve_contact` from the active set's.

        Args:
            system: (K_s, F, V, k l, δ0, mask as floats), shapes (n, n), (n,), (c, n), (c,),
                (c,), (c,) (k l zero off the mask).
            exact: (X of the last pass (stopped), active weights, passes, result code).

        Returns:
            (X (n,), iterations, result code).
        """

    @abc.abstractmethod
    def cells_answer(self, system: tuple, exact: tuple) -> tuple:
        """The answer of :func:`solve_contact_cells` from the active set's.

        Args:
            system: (C, a, E, b, k l, mask as floats), shapes (c, c), (c,), (c, r), (r,), (c,),
                (c,).
            exact: ([Δ; α] of the last pass (stopped), active weights, passes, result code);
                the weights and the code are None when the exact answer was given (``start``).

        Returns:
            ([Δ; α] (c + r,), iterations, result code).
        """

    @abc.abstractmethod
    def factored_cells_answer(self, factored_exact, newton, a, b) -> tuple:
        """The answer of a cell-space contact problem whose exact active-set solve runs on a
        cached factor (:func:`jaxgear._cell_factor.solve_factored_cells`, a hybrid scene's
        compliance cache).

        Args:
            factored_exact: ``(a, b) -> (solution, P, α)``, the exact law's answer on the
                factor for the free gaps ``a`` (m, (c,)) and rigid-body loads ``b`` ((r,)).
            newton: ``start -> (solution, P, α)``, :func:`solve_contact_cells` with this law
                from the exact answer ``start`` = (gaps (c,), α (r,), passes).
            a, b: the free gaps and the rigid-body loads of the problem.

        Returns:
            (solution, P (c,), α (r,)), as :func:`solve_contact_cells`.
        """


class ExactContact(AbstractContactLaw):
    """The exact unilateral (Signorini) contact law φ(Δ) = max(0, Δ), solved by the active-set
    iteration of the seed (II-25) (docs/design.md, "Contact laws").

    Attributes:
        max_iterations: cap on active-set passes per contact problem (an integer >= 1; result
            code ``max_iterations`` when reached). Static: a new value recompiles.

    Raises:
        ValueError: ``max_iterations`` not an integer >= 1.
    """

    max_iterations: int = eqx.field(default=100, static=True)
    mode: ClassVar[str] = "exact"

    def __check_init__(self):
        check_integer("max_iterations", self.max_iterations, 1)

    def astype(self, dtype) -> ExactContact:
        return self

    def phi(self, gap):
        return jnp.maximum(gap, 0.0), (gap > 0).astype(gap.dtype)

    def dense_answer(self, system, exact):
        """The linear solve with the final active set held: the differentiable answer."""
        Ks, F, V, kl, delta0, _ = system
        _, active, iterations, result = exact
        Kt, Ft = _assemble(Ks, F, V, kl, delta0, jax.lax.stop_gradient(active))
        return _solve(Kt, Ft), iterations, result

    def cells_answer(self, system, exact):
        C, a, E, b, kl, _ = system
        _, active, iterations, result = exact
        return _bordered_solve(C, E, kl * jax.lax.stop_gradient(active), a, b), iterations, result

    def factored_cells_answer(self, factored_exact, newton, a, b):
        """The factored exact answer itself (differentiable in ``a`` and ``b``)."""
        return factored_exact(a, b)


class SmoothContact(AbstractContactLaw):
    """The smooth contact law φ_w(Δ) = w·softplus(Δ/w): C^∞, within w·ln 2 of the exact law,
    solved by Newton's method started from the exact solution (docs/design.md, "Contact laws").
    Use it for gradients and for the diffrax solvers.

    Attributes:
        width: smoothing width w (m) > 0, a scalar (a leaf: traced under ``jax.jit``, so a new
            width does not recompile; differentiable).
        max_iterations: cap on active-set passes and on Newton steps (an integer >= 1).

    Raises:
        ValueError: a concrete ``width`` that is not finite and > 0, or a bad ``max_iterations``.
    """

    width: Float[Array, ""] | float = 1e-7
    max_iterations: int = eqx.field(default=100, static=True)
    mode: ClassVar[str] = "smooth"

    def __check_init__(self):
        check_integer("max_iterations", self.max_iterations, 1)
        if is_traced(self.width):
            return
        try:
            w = float(self.width)
        except TypeError as err:
            raise ValueError(f"width = {self.width!r}: allowed a scalar > 0 (m)") from err
        if not (math.isfinite(w) and w > 0):
            raise ValueError(f"width = {w!r} m: allowed a finite width > 0 (m)")

    def astype(self, dtype) -> SmoothContact:
        """The same law with its width as a ``dtype`` array (the leaf the solvers trace)."""
        return SmoothContact(jnp.asarray(self.width, dtype), self.max_iterations)

    def with_traced_checks(self) -> SmoothContact:
        """The law with a run-time check that its (traced) width is > 0."""
        width = eqx.error_if(self.width, ~(self.width > 0), "smooth contact width must be > 0 (m)")
        return SmoothContact(width, self.max_iterations)

    def phi(self, gap):
        w = self.width
        return w * jax.nn.softplus(gap / w), jax.nn.sigmoid(gap / w)

    def dense_answer(self, system, exact):
        return _smooth_dense(self, system, exact)

    def cells_answer(self, system, exact):
        return _smooth_cells(self, system, exact)

    def factored_cells_answer(self, factored_exact, newton, a, b):
        """Newton's method from the factored exact answer (found on stopped values)."""
        sg = jax.lax.stop_gradient
        sol, _, alpha = factored_exact(sg(a), sg(b))
        return newton((sol.gap, alpha, sol.iterations))


ContactLaw: TypeAlias = AbstractContactLaw


def contact_law(law, dtype, name: str = "contact") -> ContactLaw:
    """``law`` checked to be a :data:`ContactLaw`, its width cast to ``dtype``; a one-line
    ``ValueError`` naming ``name`` otherwise (a mode string of the former API included)."""
    if not isinstance(law, AbstractContactLaw):
        raise ValueError(
            f"{name} = {law!r}: allowed jaxgear.ExactContact(max_iterations=...) or "
            "jaxgear.SmoothContact(width=..., max_iterations=...)"
        )
    return law.astype(dtype)


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


def _phi(gap, law: ContactLaw):
    """(φ(Δ), φ'(Δ)) of ``law`` (:meth:`AbstractContactLaw.phi`)."""
    return law.phi(gap)


def _assemble(Ks, F, V, kl, delta0, weight):
    """Tangent system of the contact law linearised with cell weights: K_t, F_t."""
    kw = kl * weight
    Kt = Ks + jnp.einsum("c,ci,cj->ij", kw, V, V)
    Ft = F + jnp.einsum("c,c,ci->i", kw, delta0, V)
    return Kt, Ft


def _active_set(solve, gap, maskf, y0, max_iterations, start=None):
    """Active-set iteration of the seed (II-25) on stopped values, from all cells in contact
    (or from the cells of ``start``, a warm start, (c,)).

    ``solve(weight) -> y`` solves the linear problem with cell weights (1 in contact, 0 out);
    ``gap(y)`` gives Δ per cell. Returns (y, active weights, passes, still changing).
    """
    active0 = maskf
    if start is not None:
        active0 = maskf * jax.lax.stop_gradient(start).astype(maskf.dtype)

    def cond(state):
        _, _, it, changed = state
        return changed & (it < max_iterations)

    def body(state):
        _, active, it, _ = state
        y = solve(active)
        new = maskf * (gap(y) > 0).astype(maskf.dtype)
        return y, new, it + 1, jnp.any(new != active)

    return jax.lax.while_loop(cond, body, (y0, active0, jnp.array(0), jnp.array(True)))


def _newton_tolerances(dtype, terms):
    """(tol, floor) of :func:`_newton`'s stopping rule for residual components of m terms."""
    eps = jnp.finfo(dtype).eps
    terms = jnp.asarray(terms, dtype)
    tol = 2 * eps * jnp.sqrt(terms)
    return tol, jnp.maximum(eps * terms, tol)


def _newton(newton_of, y0, max_iterations, terms):
    """Newton iteration on stopped values with the stopping rule of the module docstring.

    ``newton_of(y) -> (dy, rho)``: the Newton correction and the scaled residual ρ(y) (the
    largest componentwise ratio |r_i| / s_i of the residual to the magnitude of its terms);
    ``terms``: the number of terms summed in a residual component (m). Converged when
    ρ <= 2 √m ε, or when a step no longer halves ρ while ρ <= m ε (the round-off floor: γ_m,
    the worst-case rounding of a sum of m terms). Returns (y, steps, converged).
    """
    tol, floor = _newton_tolerances(y0.dtype, terms)

    def converged(rho, rho_prev):
        return (rho <= tol) | ((rho <= floor) & (rho > 0.5 * rho_prev))

    def cond(state):
        _, _, it, rho, rho_prev = state
        return ~converged(rho, rho_prev) & jnp.isfinite(rho) & (it < max_iterations)

    def body(state):
        y, dy, it, rho, _ = state
        y = y - dy
        dy, rho_new = newton_of(y)
        return y, dy, it + 1, rho_new, rho

    dy0, rho0 = newton_of(y0)
    init = (y0, dy0, jnp.array(0), rho0, jnp.array(jnp.inf, y0.dtype))
    y, _, it, rho, rho_prev = jax.lax.while_loop(cond, body, init)
    return y, it, converged(rho, rho_prev)


def _scaled_residual(r, s):
    """max_i |r_i| / s_i (0 where a component and its terms all vanish)."""
    return jnp.max(jnp.abs(r) / jnp.maximum(s, jnp.finfo(s.dtype).tiny))


def _implicit_root(residual, y_root, solve_jacobian=None):
    """``y_root`` (a root of ``residual`` found on stopped values) with derivatives of every
    order, forward and reverse, by the implicit-function theorem dy = −J⁻¹ ∂r/∂p
    (``jax.lax.custom_root``; J the Jacobian of the residual at the root, formed by forward
    differentiation unless ``solve_jacobian(rhs)`` = J⁻¹ rhs is given, linear in rhs)."""

    def tangent_solve(g, y):
        if solve_jacobian is not None:
            return solve_jacobian(y)
        return _solve(jax.jacfwd(g)(y), y)

    return jax.lax.custom_root(residual, y_root, lambda _, y0: y0, tangent_solve)


def _finish(x, gap, k, kl, mask, law, iterations, result):
    phi, weight = _phi(gap, law)
    phi = jnp.where(mask, phi, 0.0)
    weight = jnp.where(mask, weight, 0.0)
    result = jnp.where(jnp.sum(weight * kl) <= 0, 2, result)
    result = jnp.where(jnp.all(jnp.isfinite(x)) & jnp.all(jnp.isfinite(gap)), result, 3)
    return ContactSolution(
        x=x, gap=gap, weight=weight, force_density=k * phi, iterations=iterations, result=result
    )


@compiled_when_eager
def solve_contact(
    Ks: Float[Array, "n n"],
    F: Float[Array, " n"],
    V: Float[Array, "c n"],
    k: Float[Array, " c"],
    length: Float[Array, " c"],
    delta0: Float[Array, " c"],
    mask: Bool[Array, " c"],
    law: ContactLaw = ExactContact(),
    start: Bool[Array, " c"] | None = None,
) -> ContactSolution:
    """Solve the unilateral contact problem on a linear structure (unknowns: the coordinates X).

    Args:
        Ks: structure stiffness (units of F per unit X), shape (n, n). K_s plus the stiffness
            of the cells in contact must be regular: pin a free structure's rigid-body modes
            first (:func:`jaxgear.scenes.rigid_mode_penalty`); a singular matrix is factored
            with a last pivot of rounding noise, exactly 0 on some CPUs (result 3).
        F: external generalised load, shape (n,).
        V: structure vector of each cell (m per unit X), shape (c, n).
        k: cell stiffness per unit contact length k_c (N/m²), shape (c,).
        length: cell length l_c along its contact line (m), shape (c,).
        delta0: initial separation δ0 (m), shape (c,), >= 0 (2.8).
        mask: cells that exist (on the flanks), shape (c,).
        law: :class:`ExactContact` (active set) or :class:`SmoothContact` (softplus ramp of
            its width), with the cap on active-set passes / Newton steps.
        start: the active set's first contact set, shape (c,) (a warm start; no gradient), or
            None: every cell on the flanks (the seed's start). With coast flanks and a
            structure held only by the contact, start from the loaded flank's cells
            (docs/backlash.md): both flanks at once pull the gears through the backlash.

    Returns:
        :class:`ContactSolution`; ``result`` != 0 flags failure (never a silent NaN: callers turn
        it into an error with ``eqx.error_if`` or report it).
    """
    law = contact_law(law, jnp.result_type(k), "law")
    max_iterations = law.max_iterations
    kl = jnp.where(mask, k * length, 0.0)
    sg = jax.lax.stop_gradient
    Ks_, F_, V_, kl_, d0_ = sg(Ks), sg(F), sg(V), sg(kl), sg(delta0)
    maskf = mask.astype(kl.dtype)

    def solve_with(weight):
        Kt, Ft = _assemble(Ks_, F_, V_, kl_, d0_, weight)
        return _solve(Kt, Ft)

    x_ex, active, it_ex, changed = _active_set(
        solve_with,
        lambda x: V_ @ x - d0_,
        maskf,
        jnp.zeros(F.shape, F.dtype),
        max_iterations,
        start,
    )
    result = jnp.where(changed, 1, 0)

    x, iterations, result = law.dense_answer(
        (Ks, F, V, kl, delta0, maskf), (x_ex, active, it_ex, result)
    )
    return _finish(x, V @ x - delta0, k, kl, mask, law, iterations, result)


def _bordered_solve(C, E, d, r1, r2, linear: bool = False):
    """Solve [I + C diag(d), −E; Eᵀ diag(d), 0] [u; α] = [r1; r2] for d >= 0.

    With S = diag(√d) and v = S u: (I + S C S) v − S E α = S r1 and (S E)ᵀ v = r2 — a symmetric
    positive definite matrix (one Cholesky factorisation) and an r × r Schur complement for α;
    then u = r1 − C S v + E α. Returns [u; α]. Without rigid-body modes (r = 0) C need not be
    symmetric (an LU solve). ``linear``: the columns of S E solved apart from S r1, so that the
    map (r1, r2) ↦ [u; α] transposes (a tangent solve in reverse mode).
    """
    s = jnp.sqrt(d)
    A = jnp.eye(C.shape[0], dtype=C.dtype) + s[:, None] * C * s[None, :]
    F = s[:, None] * E
    if E.shape[1] == 0:
        # no rigid-body mode: a dynamic step, where the mass makes K_eff definite; C may be
        # non-symmetric there (the Coriolis term of a turning body frame): an LU solve
        v = jnp.linalg.solve(A, s * r1)
        return r1 - C @ (s * v)
    cf = jax.scipy.linalg.cho_factor(A)
    if linear:
        y0, YF = jax.scipy.linalg.cho_solve(cf, s * r1), jax.scipy.linalg.cho_solve(cf, F)
    else:
        Y = jax.scipy.linalg.cho_solve(cf, jnp.concatenate([(s * r1)[:, None], F], axis=1))
        y0, YF = Y[:, 0], Y[:, 1:]
    alpha = _solve(F.T @ YF, r2 - F.T @ y0)
    v = y0 + YF @ alpha
    u = r1 - C @ (s * v) + E @ alpha
    return jnp.concatenate([u, alpha])


def _smooth_scaled_residual(y, consts, law_static):
    """((r1, r2, d = k l φ'), ρ) of the cell-space smooth problem at y = [Δ; α]: the residual,
    the Newton matrix's weights and the scaled residual ρ of :func:`_newton`'s rule;
    ``consts`` = (C, a, E, b, k l, terms, the law's arrays)."""
    C, a, E, b, kl, _, law_arrays = consts
    c = C.shape[0]
    gap, alpha = y[:c], y[c:]
    phi, dphi = _phi(gap, eqx.combine(law_arrays, law_static))
    p = kl * phi
    r1 = gap - a + C @ p - E @ alpha
    r2 = E.T @ p - b
    # magnitude of the terms of r and of J|y| (the rounding of y itself)
    ag = jnp.abs(gap)
    q = p + kl * dphi * ag
    s1 = 2 * ag + jnp.abs(a) + jnp.abs(C) @ q + 2 * jnp.abs(E) @ jnp.abs(alpha)
    s2 = jnp.abs(E).T @ q + jnp.abs(b)
    res, s = jnp.concatenate([r1, r2]), jnp.concatenate([s1, s2])
    return (r1, r2, kl * dphi), _scaled_residual(res, s)


def _smooth_newton(law_static, max_iterations: int):
    """``fn(y0, consts) -> (y, steps, converged)``: :func:`_newton` on the cell-space smooth
    problem from y0 (the per-position function of :func:`jaxgear._util.only_where_needed`)."""

    def fn(y0, consts):
        C, _, E = consts[:3]

        def newton_of(y):
            (r1, r2, d), rho = _smooth_scaled_residual(y, consts, law_static)
            return _bordered_solve(C, E, d, r1, r2), rho

        return _newton(newton_of, y0, max_iterations, consts[5])

    return fn


@compiled_when_eager
def solve_contact_cells(
    C: Float[Array, "c c"],
    a: Float[Array, " c"],
    E: Float[Array, "c r"],
    b: Float[Array, " r"],
    k: Float[Array, " c"],
    length: Float[Array, " c"],
    mask: Bool[Array, " c"],
    law: ContactLaw = ExactContact(),
    start: tuple | None = None,
) -> tuple[ContactSolution, Float[Array, " c"], Float[Array, " r"]]:
    """The contact problem in the space of the cells (compliance form; for large structures).

    With the structure's compliance G on the complement of its rigid-body modes N (K G b = b
    for every load b with Nᵀb = 0), X = G (F − Vᵀ P) + N α, where P_c = k_c l_c φ(Δ_c) is the
    force of cell c. The unknowns are the gaps Δ (c,) and the rigid-body amplitudes α (r,):

        Δ − a + C P(Δ) − E α = 0,   Eᵀ P(Δ) = b,

    with C = V G Vᵀ (cell compliance, m/N), a = V G F − δ0 (m), E = V N (m per unit α) and
    b = Nᵀ F (the load on the rigid-body modes, which the contact forces must balance). An
    active-set pass solves a (c + r)-square system whatever the size of the structure: the
    structure is factored once, outside (seed (2.30)–(2.31) in the cell space; docs/hybrid.md,
    "Statics in the cell space").

    Args:
        C: cell compliance (m/N), shape (c, c). a: free gaps (m), shape (c,).
        E: rigid-body modes seen by the cells, shape (c, r) (r may be 0, e.g. a Newmark step
            whose effective stiffness is definite). b: their loads, shape (r,).
        k, length, mask, law: as :func:`solve_contact`.
        start: the smooth law only: the exact answer (gaps (c,), α (r,), its active-set passes)
            found elsewhere (a cached scene's factored solve), from which Newton starts instead
            of the active set run here.

    Returns:
        (solution, P, α): ``solution.x`` holds the gaps Δ (the coordinates are recovered by the
        caller, X = G (F − Vᵀ P) + N α), P the cell forces (N), shape (c,), α shape (r,).
    """
    law = contact_law(law, jnp.result_type(k), "law")
    max_iterations = law.max_iterations
    c, r = E.shape
    kl = jnp.where(mask, k * length, 0.0)
    sg = jax.lax.stop_gradient
    maskf = mask.astype(kl.dtype)
    C_, a_, E_, b_, kl_ = sg(C), sg(a), sg(E), sg(b), sg(kl)

    def solve_with(weight):
        return _bordered_solve(C_, E_, kl_ * weight, a_, b_)

    if start is None:
        y_ex, active, it_ex, changed = _active_set(
            solve_with, lambda y: y[:c], maskf, jnp.zeros(c + r, a.dtype), max_iterations
        )
        result = jnp.where(changed, 1, 0)
    elif isinstance(law, ExactContact):
        raise ValueError("solve_contact_cells: start is for the smooth law (its exact answer)")
    else:
        y_ex, it_ex = sg(jnp.concatenate([start[0], start[1]])), start[2]
        active = result = None  # the smooth law's Newton needs neither
    y, iterations, result = law.cells_answer(
        (C, a, E, b, kl, maskf), (y_ex, active, it_ex, result)
    )
    gap, alpha = y[:c], y[c:]
    sol = _finish(gap, gap, k, kl, mask, law, iterations, result)
    return sol, kl * jnp.where(mask, _phi(gap, law)[0], 0.0), alpha


def _smooth_dense(law: SmoothContact, system: tuple, exact: tuple) -> tuple:
    """:meth:`SmoothContact.dense_answer`: Newton's method on the smooth equilibrium from the
    active set's answer (stopped values; the stopping rule of the module docstring), then the
    implicit-function derivatives at the root. The result code is Newton's alone."""
    Ks, F, V, kl, delta0, maskf = system
    x_ex, _, it_ex, _ = exact
    sg = jax.lax.stop_gradient
    Ks_, F_, V_, kl_, d0_ = sg(Ks), sg(F), sg(V), sg(kl), sg(delta0)

    def residual(x):
        phi, _ = law.phi(V @ x - delta0)
        return Ks @ x + V.T @ (kl * phi) - F

    aKs, aV, aF, ad0 = jnp.abs(Ks_), jnp.abs(V_), jnp.abs(F_), jnp.abs(d0_)

    def newton_of(x):
        phi, dphi = sg(law).phi(V_ @ x - d0_)
        r = Ks_ @ x + V_.T @ (kl_ * phi) - F_
        # magnitude of the terms of r and of J|x| (the rounding of x and δ0 itself)
        ax = jnp.abs(x)
        s = 2 * aKs @ ax + aV.T @ (kl_ * (phi + dphi * (aV @ ax + ad0))) + aF
        dx = _solve(Ks_ + jnp.einsum("c,ci,cj->ij", kl_ * dphi, V_, V_), r)
        return dx, _scaled_residual(r, s)

    terms = F.shape[0] + jnp.sum(maskf) + 1
    x_sm, it_sm, ok = _newton(newton_of, sg(x_ex), law.max_iterations, terms)
    x = _implicit_root(residual, sg(x_sm))
    # the smooth answer stands on its own: the active set only gives Newton its start
    return x, it_ex + it_sm, jnp.where(ok, 0, 1)


def _smooth_cells(law: SmoothContact, system: tuple, exact: tuple) -> tuple:
    """:meth:`SmoothContact.cells_answer`: Newton's method in the cells' space from the exact
    answer, only at the positions whose start is not yet a root, then the implicit-function
    derivatives at the root (tangent system: Newton's, [I + C diag(d), −E; Eᵀ diag(d), 0])."""
    C, a, E, b, kl, maskf = system
    y_ex, _, it_ex, _ = exact
    c, r = E.shape
    sg = jax.lax.stop_gradient
    C_, a_, E_, b_, kl_ = sg(C), sg(a), sg(E), sg(b), sg(kl)

    def residual(y):
        p = kl * law.phi(y[:c])[0]
        return jnp.concatenate([y[:c] - a + C @ p - E @ y[c:], E.T @ p - b])

    terms = jnp.sum(maskf) + r + 2
    law_arrays, law_static = eqx.partition(sg(law), eqx.is_array)
    consts = (C_, a_, E_, b_, kl_, terms, law_arrays)
    # Newton from the exact answer, only at the positions whose start is not yet a root
    # (under vmap a while loop factors the whole batch while one position iterates)
    tol = _newton_tolerances(a.dtype, terms)[0]
    need = _smooth_scaled_residual(y_ex, consts, law_static)[1] > tol
    newton = only_where_needed(_smooth_newton(law_static, law.max_iterations))
    y_sm, it_sm, ok = newton(need, (y_ex, jnp.array(0), jnp.array(True)), y_ex, consts)
    d_root = kl_ * eqx.combine(law_arrays, law_static).phi(y_sm[:c])[1]
    y = _implicit_root(
        residual,
        sg(y_sm),
        lambda rhs: _bordered_solve(C_, E_, d_root, rhs[:c], rhs[c:], linear=True),
    )
    # the smooth answer stands on its own: the active set only gives Newton its start
    return y, it_ex + it_sm, jnp.where(ok, 0, 1)
