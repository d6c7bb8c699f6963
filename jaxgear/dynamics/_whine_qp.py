"""The quasi-periodic harmonic balance of gear whine (docs/whine.md, "Trains of several mesh
frequencies"): a lumped model whose meshes run at G > 1 distinct mesh frequencies ω_1..ω_G (a
two-stage train) linearised about its quasi-static solution on the torus of the G mesh phases.

The meshes are grouped by their period (:meth:`~jaxgear.scenes.Scene.mesh_periods`); group g's
meshes repeat after R_g steps of the table (their own period, :class:`MeshTable` ``rows``) and
its phase is s_g = θ/(Δθ R_g) (θ = Ω t the scene angle, Δθ the table's step). The quasi-static
solution and the tangent mesh stiffness are functions of the G phases, x_qs(s_1..s_G) and
K_m(s_1..s_G): the static contact problem is solved on the torus grid of every combination of
the rows of each group (Π_g R_g solves, each cell at the row of its group's phase; the span of a
two-stage train at N_s = lcm of the period denominators visits exactly this grid; with one
N_g per group, group g's rows are R_g = N_g T_g/T_1 of its own table: each axis its own
resolution), and their G-dimensional Fourier coefficients X̂_k, K̂_k taken. With y = Σ_{h ∈ 𝓗} Y_h e^{i ν_h t},
ν_h = Σ_g h_g ω_g, the balance over the multi-index set 𝓗

    (K_s − ν_h² M + i ν_h C) Y_h + Σ_{j ∈ 𝓗} K̂_{h−j} Y_j = (ν_h² M − i ν_h C) X̂_h,   h ∈ 𝓗,

is solved directly on the low-rank mesh basis (the algebra of
:func:`~jaxgear.dynamics.harmonic_balance`, with multi-index harmonics). 𝓗: every h with one
group's order |h_g| <= H and every other group's |h_g'| <= S (the sidebands):
:class:`QuasiPeriodicBalance`.

Sources: quasi-periodic harmonic balance (multi-dimensional Fourier on the torus): Kim & Noah,
J. Appl. Mech. 58 (1991); Guskov, Sinou & Thouverez, Nonlinear Dyn. 54 (2008); the
parametrically excited multi-mesh system: Liu & Parker, J. Sound Vib. 310 (2008).
"""

from __future__ import annotations

import fractions
import itertools

import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Complex

from .._contact import solve_contact
from .._util import each_solve
from ._model import _k_ref, _rigid_penalty
from ._newmark import contact_coordinates, static_condensation

__all__ = ["quasi_periodic_balance"]


def group_positions(positions, groups: int, where: str = "positions") -> tuple[int, ...]:
    """``positions`` as one positive int per mesh-frequency group: an int for every group, or
    a sequence of ``groups`` ints (static). One-line ValueError otherwise (before any
    computation); the ranges each group needs are the caller's to check."""
    if isinstance(positions, (int, np.integer)) and not isinstance(positions, bool):
        items = (positions,) * groups
    elif isinstance(positions, (tuple, list)) and len(positions) == groups:
        items = tuple(positions)
    else:
        items = ()
    if not items or any(isinstance(p, bool) or not isinstance(p, (int, np.integer)) or p < 1
                        for p in items):
        raise ValueError(f"{where} = {positions!r}: allowed a positive int, or {groups} positive "
                         "ints (one per mesh-frequency group)")
    return tuple(int(p) for p in items)


def mesh_groups(model) -> tuple[tuple[int, ...], tuple[fractions.Fraction, ...]]:
    """Each mesh's mesh-frequency group (static), numbered in the order of the meshes (the
    first mesh's group is 0), and each group's period in periods of the first mesh."""
    periods = tuple(model.scene.mesh_periods())
    distinct: list = []
    of_mesh = []
    for p in periods:
        if p not in distinct:
            distinct.append(p)
        of_mesh.append(distinct.index(p))
    return tuple(of_mesh), tuple(distinct)


def harmonic_set(G: int, H: int, S: int) -> np.ndarray:
    """The multi-indices h (N, G) with, for some group g, |h_g| <= H and |h_g'| <= S for every
    other g' (S <= H); ordered lexicographically, symmetric under h → −h."""
    out = []
    for h in itertools.product(range(-H, H + 1), repeat=G):
        a = np.abs(h)
        if any(a[g] <= H and all(a[q] <= S for q in range(G) if q != g) for g in range(G)):
            out.append(h)
    return np.asarray(out, dtype=int).reshape(-1, G)


def _torus_static(scene, table, torque, law, grid_rows):
    """The static contact solution at every torus grid point: ``grid_rows`` (N, c) the table
    row of each cell there. Returns x (N, n), weight (N, c), force density (N, c), result (N,)."""
    K = scene.stiffness() + _rigid_penalty(scene, _k_ref(table))
    F = scene.external_load(torque)
    dofs = contact_coordinates(scene, K.shape[0])
    V = table.V
    y = None
    if dofs is not None:
        reduced = static_condensation(K, dofs)
        K, (F, y) = reduced.S, reduced.load(F)
        V = V[:, :, reduced.J]
    cells = jnp.arange(table.V.shape[1])

    def solve(rows):
        def take(f):
            return f[rows, cells]

        sol = solve_contact(K, F, take(V), take(table.k), take(table.length),
                            take(table.delta0), take(table.mask), law)
        x = sol.x if dofs is None else reduced.expand(sol.x, y)
        return x, sol.weight, sol.force_density, sol.result

    # one grid point at a time: a batch of points would run solve_contact's LU as one batched
    # LAPACK call, which can deadlock XLA's CPU thread pool (jaxgear._util.each_solve)
    return jax.lax.map(solve, grid_rows)


def torus_grid(table, of_mesh, R) -> tuple[np.ndarray, np.ndarray]:
    """The grid's row indices per group (N, G) (C order over the groups, the last fastest) and
    each cell's row at every grid point (N, c)."""
    idx = np.stack(np.meshgrid(*[np.arange(r) for r in R], indexing="ij"), -1).reshape(-1, len(R))
    of_cell = np.repeat(np.asarray(of_mesh), [L * N for L, N in table.sizes])
    return idx, idx[:, of_cell]


def torus_coefficients(samples, R, wanted) -> jnp.ndarray:
    """The Fourier coefficients ĝ_k = (1/N) Σ g(s) e^{−2πi k·s} on the torus grid
    s_g = (r_g + ½)/R_g, samples (N, ...) in :func:`torus_grid`'s order, at the multi-indices
    ``wanted`` (..., G) (ints; |k_g| < R_g/2 for no aliasing): (..., ...)."""
    G = len(R)
    shape = tuple(R) + samples.shape[1:]
    fx = jnp.fft.fftn(samples.reshape(shape), axes=tuple(range(G))) / np.prod(R)
    wanted = np.asarray(wanted)
    idx = tuple(np.mod(wanted[..., g], R[g]) for g in range(G))
    shift = np.exp(-1j * np.pi * sum(wanted[..., g] / R[g] for g in range(G)))
    out = fx[idx]
    return out * jnp.asarray(shift).reshape(shift.shape + (1,) * (out.ndim - shift.ndim))


def quasi_periodic_balance(
    M, C, K, stiffness_harmonics, force_harmonics, frequencies, *, gauge=None, basis=None
) -> Complex[Array, "N n"]:
    """The quasi-periodic solution y = Σ_i Y_i e^{i ν_i t} of M ÿ + C ẏ + (K + K_m(t)) y = f(t)
    over N multi-index harmonics h_i (frequencies ν_i = h_i·ω of G base frequencies ω), with
    K_m(t) = Σ_k K̂_k e^{i (k·ω) t} and f(t) = Σ_i F̂_i e^{i ν_i t}, truncated to the set:

        (K − ν_i² M + i ν_i C) Y_i + Σ_j K̂_{h_i − h_j} Y_j = F̂_i.

    The set is symmetric (index N − 1 − i the harmonic −h_i, index (N − 1)/2 the mean) and the
    system real in time (K̂_{−k} = conj K̂_k, F̂ likewise): D_i = K + B K̂_0 Bᵀ − ν_i² M + i ν_i C
    is factored for i >= (N − 1)/2 only, and the coupling solved on the N r unknowns Z = Bᵀ Y
    (the algebra of :func:`~jaxgear.dynamics.harmonic_balance` with G-dimensional harmonics),
    with Z_{−h} = conj Z_h: a real system of (N + 1) r unknowns.

    Args:
        M, C, K: (n, n) mass, damping, time-invariant stiffness (SI).
        stiffness_harmonics: K̂_{h_i − h_j}, (N, N, n, n), or (N, N, r, r) on ``basis`` (its
            diagonal blocks K̂_0).
        force_harmonics: F̂_i, (N, n). frequencies: ν_i (rad/s), (N,).
        gauge: None or an (n, n) matrix added to the mean's block (pins rigid-body modes).
        basis: None or B (n, r) with K_m(t) = B K_r(t) Bᵀ.

    Returns:
        Y_i, (N, n) complex.

    Source: quasi-periodic harmonic balance, Kim & Noah, J. Appl. Mech. 58 (1991).
    """
    F = jnp.asarray(force_harmonics)
    N, n = F.shape
    nu = jnp.asarray(frequencies)
    coupling = jnp.asarray(stiffness_harmonics)
    B = jnp.eye(n, dtype=M.dtype) if basis is None else jnp.asarray(basis)
    mid = (N - 1) // 2
    r = B.shape[1]
    K0 = coupling[mid, mid]
    w = nu[mid:]
    D = (
        (K + B @ K0 @ B.T)[None]
        - (w**2)[:, None, None] * M[None]
        + 1j * w[:, None, None] * C[None]
    )
    if gauge is not None:
        D = D.at[0].add(gauge)
    Bc = jnp.broadcast_to(B.astype(F.dtype), (N - mid, n, r))
    half = each_solve(D, jnp.concatenate([F[mid:, :, None], Bc], -1))  # not one batched LU
    sol = jnp.concatenate([jnp.conj(half[1:][::-1]), half], axis=0)  # (N, n, 1 + r)
    DF, DB = sol[..., 0], sol[..., 1:]
    Gm = jnp.einsum("nr,hns->hrs", B, DB)[mid:]  # (P, r, r), P = N − mid rows h >= 0
    g = (DF[mid:] @ B).reshape(-1)
    Kc = coupling * (1.0 - jnp.eye(N, dtype=coupling.real.dtype))[:, :, None, None]
    A = jnp.einsum("hrs,hjsx->hrjx", Gm, Kc[mid:])  # (P, r, N, r): G 𝕂 on the rows h >= 0
    # Z_−h = conj Z_h: A Z = A1 Z_P + A2 conj Z_P (A2: the columns −h, h > 0, in the order of
    # P; none for the mean), solved as a real system of size 2 P r (a quarter of the complex
    # system's work)
    P = N - mid
    A1 = A[:, :, mid:, :].reshape(P * r, P * r)
    A2 = jnp.concatenate(
        [jnp.zeros((P, r, 1, r), A.dtype), A[:, :, :mid, :][:, :, ::-1, :]], axis=2
    ).reshape(P * r, P * r)
    eye = jnp.eye(P * r, dtype=A1.real.dtype)
    top = jnp.concatenate([eye + A1.real + A2.real, A2.imag - A1.imag], axis=1)
    bottom = jnp.concatenate([A1.imag + A2.imag, eye + A1.real - A2.real], axis=1)
    ab = jnp.linalg.solve(jnp.concatenate([top, bottom], axis=0),
                          jnp.concatenate([g.real, g.imag]))
    ZP = (ab[: P * r] + 1j * ab[P * r :]).reshape(P, r)
    Z = jnp.concatenate([jnp.conj(ZP[1:][::-1]), ZP], axis=0)
    KZ = jnp.einsum("hjrs,js->hr", Kc, Z)
    return DF - jnp.einsum("hnr,hr->hn", DB, KZ)
