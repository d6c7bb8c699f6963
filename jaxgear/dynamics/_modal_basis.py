"""The modal basis of a hybrid structure with the static correction of its cells
(:class:`~jaxgear.dynamics.ModalBasis`; docs/hybrid.md, "Modal basis").

A hybrid model has n structure coordinates (thousands with condensed bodies). Integrated in the
modal basis, X = D q + G f: q the m' modal coordinates of the kept directions T (the m lowest
modes of (M, K + K̄), K̄ the mesh stiffness averaged round a revolution, plus the members' free
rotations), D = T − G K T those directions with their static residual and G = Q (Qᵀ K Q)⁻¹ Qᵀ the
residual flexibility of the structure on the other directions Q (the mode-acceleration /
static-correction method: R. R. Craig & A. J. Kurdila, *Fundamentals of Structural Dynamics*,
2nd ed., Wiley 2006, §14.5). The cell forces enter through G exactly in statics; with every mode
kept D = T, G = 0 and the full model is recovered.

Here: the basis itself (:func:`modal_space_of`, dense eigen-analyses of the n coordinates, once
per sweep) and the reduced matrices of one speed (:func:`reduced_structure`). The mesh stiffness
K̄ it is built on comes from the hybrid dynamics (:func:`jaxgear.dynamics._hybrid.modal_space`),
the integration loop from :func:`jaxgear.dynamics.newmark` (``newmark_modal``).
"""

from __future__ import annotations

from typing import NamedTuple

import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import static_correction
from ._newmark import ModalStructure

__all__ = ["ModalSpace", "modal_space_of", "reduced_structure"]


class ModalSpace(NamedTuple):
    """The modal basis of a hybrid sweep (:func:`modal_space_of`), computed once per sweep.

    Attributes:
        T: (n, m') the kept directions, M-orthonormal: the m lowest modes of (M, K + K̄) and
            the r softest directions of K on the other modes (r = the scene's members: their
            free rotations, which K alone does not hold); m' = min(m + r, n).
        Q: (n, n − m') the other directions (M-orthonormal, M-orthogonal to T).
        D: (n, m') T with its static residual (:func:`jaxgear._util.static_correction`), or None when the
            structure's stiffness depends on the speed (``rotating_frame``: reduced per speed).
        G: (n, n) the residual flexibility, or None (as D).
    """

    T: Float[Array, "n m"]
    Q: Float[Array, "n k"]
    D: Float[Array, "n m"] | None
    G: Float[Array, "n n"] | None


def split_modes(Phi, m: int, K, r: int):
    """The kept directions T and the others Q (:class:`ModalSpace`) of the modes ``Phi`` (n, n)
    (M-orthonormal, ascending) for the stiffness K (n, n), and Qᵀ K Q (diagonal: σ, (n − m'),):
    T = [Φ_:m, Φ_t W_:r], Q = Φ_t W_r:, with Φ_t the other modes and (σ, W) the eigenpairs of
    Φ_tᵀ K Φ_t, ascending (the r softest directions of the structure without the mesh among the
    other modes: a member's free rotation that the mesh held in K + K̄ must keep its inertia,
    not enter the static correction with an unbounded flexibility)."""
    n = Phi.shape[0]
    if m + r >= n:
        return Phi, Phi[:, n:], Phi[0, n:]
    Pt = Phi[:, m:]
    A = Pt.T @ K @ Pt
    sigma, W = jnp.linalg.eigh(0.5 * (A + A.T))
    Pt = Pt @ W
    return jnp.concatenate([Phi[:, :m], Pt[:, :r]], axis=1), Pt[:, r:], sigma[r:]


def modal_space_of(
    K: Float[Array, "n n"],
    M: Float[Array, "n n"],
    Km: Float[Array, "n n"],
    modes: int,
    members: int,
    *,
    static: bool = True,
    per_speed: bool = False,
) -> ModalSpace:
    """The basis of the structure (K, M) with the averaged mesh stiffness ``Km`` (all (n, n),
    SI): the ``modes`` lowest modes of (M, K + Km) (Cholesky of M, a dense symmetric
    eigenproblem; M-orthonormal, ascending), with the ``members``' free rotations
    (:func:`split_modes`), and their static correction for K (:func:`jaxgear._util.static_correction`;
    ``static=False``: the truncated basis, D = T, G = 0). ``per_speed``: K depends on the speed
    (the rotating frame), D and G are left None and reduced per speed
    (:func:`reduced_structure`)."""
    L = jnp.linalg.cholesky(M)
    A = jax.scipy.linalg.solve_triangular(L, K + Km, lower=True)
    A = jax.scipy.linalg.solve_triangular(L, A.T, lower=True)
    _, Y = jnp.linalg.eigh(0.5 * (A + A.T))
    Phi = jax.scipy.linalg.solve_triangular(L, Y, lower=True, trans="T")
    T, Q, sigma = split_modes(Phi, modes, K, members)
    if per_speed:
        return ModalSpace(T, Q, None, None)
    if Q.shape[1] == 0 or not static:
        return ModalSpace(T, Q, *static_correction(T, Q, K, False))
    G = Q @ (Q.T / sigma[:, None])  # (static_correction's, Qᵀ K Q = diag σ here)
    G = 0.5 * (G + G.T)
    return ModalSpace(T, Q, T - G @ (K @ T), G)


def reduced_structure(
    space: ModalSpace, K, M, C, F, static: bool, rotating_frame: bool
) -> tuple[Float[Array, "m m"], Float[Array, "m m"], Float[Array, "m m"], ModalStructure]:
    """The structure of one speed on the basis ``space``: (Dᵀ K D, Dᵀ M D, Dᵀ C D) (m', m')
    and the :class:`~jaxgear.dynamics._newmark.ModalStructure` (D, G, G F) of
    :func:`~jaxgear.dynamics._newmark.newmark_modal`; K, M, C (n, n) and F (n,) the speed's.
    A basis without D (``per_speed``) is corrected here for this K (its symmetric part: G
    stays symmetric; exact with every mode kept; ``static``: with the static correction). The
    reduced M is symmetrised; K and C too unless ``rotating_frame`` (the skew Coriolis part and
    the load stiffness are kept)."""
    D, G = space.D, space.G
    if D is None:
        D, G = static_correction(space.T, space.Q, 0.5 * (K + K.T), static)
    Mr, Kr, Cr = (0.5 * (A + A.T) for A in (D.T @ M @ D, D.T @ K @ D, D.T @ C @ D))
    if rotating_frame:
        Kr, Cr = D.T @ K @ D, D.T @ C @ D
    return Kr, Mr, Cr, ModalStructure(D, G, G @ F)
