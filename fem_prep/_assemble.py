"""Assembly of stiffness, consistent mass, centrifugal load and the rotating-frame matrices.

All operators are in SI units and act on the interleaved nodal DOF vector of a vector basis
(node k has DOFs 3k, 3k+1, 3k+2 = u_x, u_y, u_z).  The body spins about the z axis.

Rotating frame.  For a body spinning at the signed speed ``Omega`` about +z, the displacement u
measured in the body frame obeys (linearised about the centrifugal prestress)

    M u'' + 2 Omega G u' + (K + Omega**2 (S + K_sigma)) u = Omega**2 f_c + f,

with the gyroscopic (Coriolis) matrix ``G = integral rho v . (e_z x u) dV`` (skew), the spin
softening ``S = -integral rho (u_x v_x + u_y v_y) dV`` (the centripetal term of the
displacement itself) and the stress stiffening ``K_sigma = integral sigma0_ij d_i u_k d_j v_k dV``
of the centrifugal prestress ``sigma0`` at ``Omega = 1`` rad/s (:func:`stress_stiffening_matrix`),
all per unit speed (G) or speed squared (S, K_sigma).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp
import skfem

from ._body import Material

__all__ = ["Operators", "assemble_operators", "stiffness_matrix", "stress_stiffening_matrix"]

#: ``J @ w == cross(e_z, w)``: the gyroscopic matrix is ``kron(M_scalar, J)``.
EZ_CROSS = np.array([[0.0, -1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])


@dataclass(frozen=True)
class Operators:
    """Assembled full-model operators.

    Attributes:
        K: stiffness matrix, ``(n_dofs, n_dofs)`` CSR, N/m.
        M: consistent mass matrix, ``(n_dofs, n_dofs)`` CSR, kg.
        f_centrifugal: centrifugal body-force vector per unit speed squared,
            ``integral rho (x, y, 0) . v dV``, shape ``(n_dofs,)``, N/(rad/s)^2.  The load at
            speed Omega is ``Omega**2 * f_centrifugal`` (seed (2.37)).
        gyroscopic: ``integral rho v . (e_z x u) dV = kron(M_scalar, J)``,
            ``J = [[0, -1, 0], [1, 0, 0], [0, 0, 0]]``, per unit spin speed (``(n_dofs, n_dofs)``
            CSR, kg, skew-symmetric); the rotating-frame Coriolis force is
            ``2 Omega * gyroscopic @ u'``.
        spin_softening: ``-integral rho (u_x v_x + u_y v_y) dV = -kron(M_scalar, diag(1, 1, 0))``
            per unit speed squared (``(n_dofs, n_dofs)`` CSR, kg, symmetric negative
            semi-definite); the stiffness at speed Omega gains ``Omega**2 * spin_softening``.
        mass: total mass (kg).
    """

    K: sp.csr_matrix
    M: sp.csr_matrix
    f_centrifugal: np.ndarray
    gyroscopic: sp.csr_matrix
    spin_softening: sp.csr_matrix
    mass: float


def assemble_operators(basis: skfem.Basis, material: Material, *, chunk: int = 1500) -> Operators:
    """Assemble K, M, the centrifugal vector, the gyroscopic and the spin-softening matrices.

    The shape functions, isoparametric mapping, quadrature and DOF numbering are scikit-fem's.
    The mass and load use scikit-fem forms on the scalar basis (expanded to 3 components);
    the stiffness is integrated with batched NumPy products on the scalar gradients (about 10x
    faster than a generic vector ``BilinearForm``, identical to round-off: a test checks it).
    The stress stiffening depends on the support of the prestress solve and is assembled
    separately (:func:`stress_stiffening_matrix`).

    Args:
        basis: scikit-fem vector basis (``ElementVector`` of a scalar element) whose node k has
            DOFs 3k..3k+2 (true for ``ElementVector``), or the scalar basis itself (same
            operators: the vector basis is used only through its scalar element, and a vector
            basis holds three times the scalar functions at every quadrature point: 1.9 GB
            for a 300 k-DOF Tet10 mesh).
        material: isotropic material (Pa, -, kg/m^3).
        chunk: elements per batch in the stiffness integration (bounds peak memory).

    Returns:
        The :class:`Operators`.
    """
    lam, mu = material.lame
    rho = material.density
    sbasis = scalar_basis(basis) if isinstance(basis.elem, skfem.ElementVector) else basis
    Ms = _scalar_mass(sbasis, rho)
    M = sp.kron(Ms, sp.eye(3), format="csr")
    K = stiffness_matrix(sbasis, lam, mu, chunk=chunk)

    @skfem.LinearForm
    def cx(v, w):
        return rho * w.x[0] * v

    @skfem.LinearForm
    def cy(v, w):
        return rho * w.x[1] * v

    f = np.zeros(3 * sbasis.N)
    f[0::3] = cx.assemble(sbasis)
    f[1::3] = cy.assemble(sbasis)
    G = sp.kron(Ms, sp.csr_matrix(EZ_CROSS), format="csr")
    S = -sp.kron(Ms, sp.diags([1.0, 1.0, 0.0]), format="csr")
    for A in (G, S):
        A.eliminate_zeros()
    return Operators(K=K, M=M, f_centrifugal=f, gyroscopic=G, spin_softening=S, mass=_total_mass(M))


def stress_stiffening_matrix(
    basis: skfem.Basis, material: Material, u: np.ndarray
) -> sp.csr_matrix:
    """Geometric (initial-stress) stiffness of the linear-elastic stress of a displacement field.

    ``K_sigma[(i,k),(j,l)] = delta_kl integral sigma0_ab d_a phi_i d_b phi_j dV`` with
    ``sigma0 = lam tr(eps) I + 2 mu eps``, ``eps = sym grad u`` evaluated at scikit-fem's
    quadrature points of ``basis`` (the quadrature of K), i.e. ``kron(K_scalar, I_3)``:
    the second-order strain energy ``integral sigma0 : (grad u^T grad u) / 2`` of a prestressed
    body.  With ``u`` the centrifugal displacement at 1 rad/s, the stiffness at speed Omega
    gains ``Omega**2 * K_sigma`` (the prestress is linear in ``Omega**2``).

    Args:
        basis: the vector basis ``u`` lives on (interleaved DOFs).
        material: isotropic material of the prestress (Pa).
        u: prestress displacement ``(n_dofs,)`` (m).

    Returns:
        ``(n_dofs, n_dofs)`` CSR, symmetric (N/m per unit of the prestress).
    """
    lam, mu = material.lame
    g = basis.interpolate(np.asarray(u, dtype=float)).grad  # (3, 3, n_el, n_q): d_j u_i
    eps = 0.5 * (g + g.transpose(1, 0, 2, 3))
    tr = eps[0, 0] + eps[1, 1] + eps[2, 2]
    sig = 2.0 * mu * eps
    for a in range(3):
        sig[a, a] += lam * tr

    @skfem.BilinearForm
    def geometric(p, q, w):
        s = w.sig
        return sum(s[a, b] * p.grad[a] * q.grad[b] for a in range(3) for b in range(3))

    Ks = geometric.assemble(scalar_basis(basis), sig=sig).tocsr()
    Ks = (0.5 * (Ks + Ks.T)).tocsr()
    return sp.kron(Ks, sp.eye(3), format="csr")


def scalar_basis(basis: skfem.Basis) -> skfem.Basis:
    """The scalar basis (same mesh, element and quadrature) behind a vector basis (an
    ``ElementVector``'s, as every basis of the body mesh)."""
    return skfem.Basis(basis.mesh, basis.elem.elem, quadrature=basis.quadrature)


def _scalar_mass(sbasis: skfem.Basis, rho: float) -> sp.csr_matrix:
    @skfem.BilinearForm
    def mass(u, v, w):
        return rho * u * v

    return mass.assemble(sbasis).tocsr()


def stiffness_matrix(
    sbasis: skfem.Basis, lam: float, mu: float, *, chunk: int = 1500
) -> sp.csr_matrix:
    """Isotropic linear-elastic stiffness on the interleaved vector DOFs of a scalar basis.

    ``K[(i,a),(j,b)] = int lam d_a phi_i d_b phi_j + mu (delta_ab grad phi_i . grad phi_j +
    d_b phi_i d_a phi_j) dV``.

    Args:
        sbasis: scalar scikit-fem basis (n_loc local functions).
        lam: first Lamé parameter (Pa).
        mu: shear modulus (Pa).
        chunk: elements per batch.

    Returns:
        ``(3 N, 3 N)`` CSR matrix (N/m), node k has DOFs 3k..3k+2.
    """
    nloc = len(sbasis.basis)
    ne = sbasis.nelems
    edofs = sbasis.element_dofs  # (nloc, ne)
    # global vector dofs, local order (i, a) -> 3 * node_i + a
    gd = (3 * edofs.T[:, :, None] + np.arange(3)[None, None, :]).reshape(ne, 3 * nloc)
    n = 3 * sbasis.N
    # the triplets written in place (no per-chunk lists joined by a copy), indices in int32
    # where they fit (SciPy's own index type then): 16 bytes per entry instead of 48 at the
    # peak (a 300 k-DOF Tet10 housing: 53 M entries, 0.85 GB instead of 2.5 GB)
    idx = np.int32 if n < 2**31 - 1 and ne * (3 * nloc) ** 2 < 2**31 - 1 else np.int64
    nn = (3 * nloc) ** 2
    rows = np.empty(ne * nn, dtype=idx)
    cols = np.empty(ne * nn, dtype=idx)
    vals = np.empty(ne * nn)
    for e0 in range(0, ne, chunk):
        sl = slice(e0, min(ne, e0 + chunk))
        # G: (nb, nq, nloc, 3)
        G = np.stack([sbasis.basis[i][0].grad[:, sl, :] for i in range(nloc)], axis=0)
        G = np.ascontiguousarray(G.transpose(2, 3, 0, 1))
        nb, nq = G.shape[0], G.shape[1]
        G = G.reshape(nb, nq, 3 * nloc)
        W = sbasis.dx[sl]  # (nb, nq)
        A = np.matmul((G * W[:, :, None]).transpose(0, 2, 1), G)  # (nb, 3nloc, 3nloc)
        A5 = A.reshape(nb, nloc, 3, nloc, 3)
        Ke = lam * A5 + mu * A5.transpose(0, 1, 4, 3, 2)
        tr = np.einsum("eicjc->eij", A5)
        for a in range(3):
            Ke[:, :, a, :, a] += mu * tr
        g = gd[sl]
        out = slice(e0 * nn, (e0 + nb) * nn)
        rows[out] = np.repeat(g, 3 * nloc, axis=1).ravel()
        cols[out] = np.tile(g, (1, 3 * nloc)).ravel()
        vals[out] = Ke.reshape(nb, -1).ravel()
    K = sp.coo_matrix((vals, (rows, cols)), shape=(n, n))
    del rows, cols, vals
    K = K.tocsr()
    K.sum_duplicates()
    return K


def _total_mass(M: sp.csr_matrix) -> float:
    """Total mass: rigid x-translation kinetic energy, ``e_x^T M e_x`` (kg)."""
    n = M.shape[0]
    ex = np.zeros(n)
    ex[0::3] = 1.0
    return float(ex @ (M @ ex))
