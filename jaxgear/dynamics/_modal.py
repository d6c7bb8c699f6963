"""Modal analysis of the time-averaged system and damping models (seed (2.34)-(2.36))."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import as_float
from ..scenes import DynamicScene

__all__ = ["Damping", "ModalAnalysis", "damping_matrix", "modal_analysis"]


class ModalAnalysis(eqx.Module):
    """Modes of the time-averaged system K̄ φ = ω² M φ, sorted by frequency.

    Attributes:
        omega: natural angular frequencies (rad/s), shape (n,) (0 for rigid-body modes).
        frequency: ω/2π (Hz), shape (n,).
        shapes: mass-normalised mode shapes Φ (columns, Φᵀ M Φ = I), shape (n, n).
        energy: share of modal strain energy per part, shape (n_parts, n), columns summing to 1
            for the elastic modes (0 for rigid modes); row 0 is the mesh, then the scene's parts.
        parts: static names of the energy rows ("mesh", then the scene's stiffness parts).
        rigid: True for rigid-body modes, shape (n,).
        mesh_stiffness: the time-averaged mesh stiffness matrix K̄_m (units of K), shape (n, n).
    """

    omega: Float[Array, " n"]
    frequency: Float[Array, " n"]
    shapes: Float[Array, "n n"]
    energy: Float[Array, "n_parts n"]
    rigid: Array
    mesh_stiffness: Float[Array, "n n"]
    parts: tuple = eqx.field(static=True)

    @property
    def mesh_energy(self) -> Float[Array, " n"]:
        """Share e_i of modal strain energy stored in the mesh (2.36), shape (n,)."""
        return self.energy[0]


def modal_analysis(scene: DynamicScene, mesh_stiffness: Float[Array, "n n"]) -> ModalAnalysis:
    """Modal analysis of the time-averaged system (the basis of the damping models (2.34)-(2.36)).

    Args:
        scene: the dynamic scene (M, K_s and its parts).
        mesh_stiffness: time-averaged mesh stiffness matrix K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over
            a mesh period (w_c: static contact weights), shape (n, n).

    Returns:
        :class:`ModalAnalysis` (strain-energy shares as in the seed's Tab. IV-8).
    """
    M = scene.mass()
    parts = {"mesh": mesh_stiffness, **scene.stiffness_parts()}
    K = sum(parts.values())
    L = jnp.linalg.cholesky(M)
    Linv = jnp.linalg.inv(L)
    A = Linv @ K @ Linv.T
    A = 0.5 * (A + A.T)
    lam, Y = jnp.linalg.eigh(A)
    Phi = Linv.T @ Y
    scale = jnp.max(jnp.abs(lam))
    rigid = lam <= 1e-9 * scale
    lam = jnp.where(rigid, 0.0, lam)
    omega = jnp.sqrt(lam)
    strain = jnp.stack([jnp.einsum("in,ij,jn->n", Phi, P, Phi) for P in parts.values()])
    total = jnp.sum(strain, axis=0)
    energy = jnp.where(rigid[None, :], 0.0, strain / jnp.where(rigid, 1.0, total)[None, :])
    return ModalAnalysis(
        omega=omega,
        frequency=omega / (2 * jnp.pi),
        shapes=Phi,
        energy=energy,
        rigid=rigid,
        mesh_stiffness=mesh_stiffness,
        parts=tuple(parts),
    )


class Damping(eqx.Module):
    """Damping model (seed (2.34)-(2.36)).

    Attributes:
        model: "rayleigh" (C = a_R M + b_R K̄), "modal" (one ratio ξ for every mode, (2.35)) or
            "composite" (ξ_i = ξ_mesh e_i + ξ_structure (1 − e_i), (2.36)); static.
        ratio: ξ (-) for "modal".
        alpha: a_R (1/s), beta: b_R (s) for "rayleigh".
        mesh_ratio, structure_ratio: the composite's ξ_mesh (0.07) and ξ_structure (0.01).
    """

    model: str = eqx.field(static=True, default="composite")
    ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.05)
    alpha: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    beta: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    mesh_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.07)
    structure_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.01)

    def __check_init__(self):
        if self.model not in ("rayleigh", "modal", "composite", "none"):
            raise ValueError(
                f"damping model = {self.model!r}: allowed 'rayleigh', 'modal', 'composite', 'none'"
            )


def damping_matrix(
    scene: DynamicScene, modes: ModalAnalysis, damping: Damping
) -> Float[Array, "n n"]:
    """Viscous damping matrix C (units of K·s), shape (n, n).

    Modal/composite: C = M Φ diag(2 ξ_i ω_i) Φᵀ M with mass-normalised Φ, i.e. c_i = 2 ξ_i
    √(k_i m_i) per mode (2.35); rigid-body modes are undamped. Rayleigh: a_R M + b_R K̄ (2.34).
    A scene with bearing damping (``scene.bearing_damping()``, e.g. :class:`LumpedPair` with
    6×6 bearing damping matrices) adds it to C whatever the model ("none" included): it is a
    physical element of the structure, not part of the modal/Rayleigh model.
    """
    M = scene.mass()
    bearing = getattr(scene, "bearing_damping", None)
    Cb = jnp.zeros_like(M) if bearing is None else bearing()
    if damping.model == "none":
        return Cb
    if damping.model == "rayleigh":
        K = modes.mesh_stiffness + scene.stiffness()
        return damping.alpha * M + damping.beta * K + Cb
    if damping.model == "modal":
        xi = jnp.broadcast_to(damping.ratio, modes.omega.shape)
    else:
        e = modes.mesh_energy
        xi = damping.mesh_ratio * e + damping.structure_ratio * (1.0 - e)
    MP = M @ modes.shapes
    return MP @ jnp.diag(2.0 * xi * modes.omega) @ MP.T + Cb
