"""Damping models as classes (seed (2.34)–(2.36)): an abstract damping with the methods that
build C for each engine, and its implementations, :class:`RayleighDamping`,
:class:`ModalDamping`, :class:`CompositeDamping` and :class:`NoDamping`. A new damping model
is one more subclass here; the case file's names map to these objects at the edge
(:func:`jaxgear.io.spec_damping`, :func:`jaxgear.io.Damping`).

Both engines add the scene's bearing damping to whatever the model builds: it is a physical
element of the structure, not part of the modal or Rayleigh model.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._util import as_float
from ..scenes import DynamicScene
from ._modal import ModalAnalysis

__all__ = [
    "AbstractDamping",
    "CompositeDamping",
    "ModalDamping",
    "NoDamping",
    "RayleighDamping",
    "damping_matrix",
]


class AbstractDamping(eqx.Module):
    """A viscous damping model. A lumped model's C is built once from the modes of the
    time-averaged system (:meth:`matrix`); a hybrid model's at each speed, as a constant part
    and a mesh share that follows the mesh as the wheel turns (:meth:`hybrid`)."""

    #: whether :meth:`hybrid` needs the modes of (M, K + K̄), K̄ the mesh stiffness averaged
    #: round a wheel revolution (a dense eigen-analysis per speed)
    needs_modes: ClassVar[bool] = False

    @abc.abstractmethod
    def matrix(self, scene: DynamicScene, modes: ModalAnalysis) -> Float[Array, "n n"]:
        """C of a lumped scene (units of K·s), (n, n), from the modes of the time-averaged
        system ``modes`` (mass-normalised Φ; their ``mesh_stiffness`` K̄_m), bearings
        excluded."""

    @abc.abstractmethod
    def hybrid(self, M, K, modes: ModalAnalysis | None) -> tuple:
        """A hybrid scene's C(k) = C + c_m Rᵀ K̄_m(k) R in mesh period k, bearings excluded:
        (C (n, n), c_m (a scalar, or None: no mesh share), R (n, n), or None: the
        identity). ``M``, ``K``: the structure's (n, n); ``modes``: those of (M, K + K̄)
        when :attr:`needs_modes`, else None."""

    def residual_damping(self) -> Float[Array, ""] | float:
        """β_r (s) of a modal basis's static correction (its Kelvin–Voigt lag): Rayleigh's β,
        else 0."""
        return 0.0


class NoDamping(AbstractDamping):
    """No damping model: only the scene's bearing damping (if it has one)."""

    def matrix(self, scene, modes):
        return jnp.zeros_like(scene.mass())

    def hybrid(self, M, K, modes):
        return jnp.zeros_like(M), None, None


class RayleighDamping(AbstractDamping):
    """Rayleigh damping (2.34): C = a_R M + b_R (K + K̄_m).

    Attributes:
        alpha: a_R (1/s). beta: b_R (s). For a hybrid model K̄_m(k) is the mesh stiffness
            of mesh period k (exact and sparse on the window: c_m = b_R, R = I).
    """

    alpha: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    beta: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)

    def matrix(self, scene, modes):
        K = modes.mesh_stiffness + scene.stiffness()
        return self.alpha * scene.mass() + self.beta * K

    def hybrid(self, M, K, modes):
        return self.alpha * M + self.beta * K, self.beta, None

    def residual_damping(self):
        return self.beta


def _modal(M, modes: ModalAnalysis, xi):
    """M Φ diag(2 ξ_i ω_i) Φᵀ M (2.35): c_i = 2 ξ_i √(k_i m_i) per mode; rigid modes
    undamped (ω = 0)."""
    MP = M @ modes.shapes
    return MP @ jnp.diag(2.0 * xi * modes.omega) @ MP.T


class ModalDamping(AbstractDamping):
    """Modal damping (2.35): one ratio ξ for every mode, C = M Φ diag(2 ξ ω_i) Φᵀ M.

    Attributes:
        ratio: ξ (-). For a hybrid model the modes are those of (M, K + K̄), K̄ the mesh
            stiffness averaged round the revolution (no mesh share).
    """

    ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.05)

    needs_modes: ClassVar[bool] = True

    def matrix(self, scene, modes):
        return _modal(scene.mass(), modes, jnp.broadcast_to(self.ratio, modes.omega.shape))

    def hybrid(self, M, K, modes):
        MP = M @ modes.shapes
        return MP @ ((2.0 * self.ratio * modes.omega)[:, None] * MP.T), None, None


class CompositeDamping(AbstractDamping):
    """Composite damping (2.36): ξ_i = ξ_mesh e_i + ξ_structure (1 − e_i), e_i the mode's
    mesh strain-energy share.

    For a hybrid model in a form linear in the mesh stiffness of the period: C(k) =
    2 ξ_s M Φ Ω Φᵀ M + 2 (ξ_m − ξ_s) Rᵀ K̄_m(k) R, R = Φ' Ω'^(-1/2) Φ'ᵀ M (Φ', Ω' the elastic
    modes; the rigid ones, which the mesh does not strain, left out): c_m = 2 (ξ_m − ξ_s). In
    modal coordinates its diagonal is (2.36)'s, 2 ω_i (ξ_s + (ξ_m − ξ_s) e_i(k)) with the mesh
    energy share e_i(k) of period k; it keeps the modes' coupling 2 (ξ_m − ξ_s) φ_iᵀ K̄_m(k)
    φ_j / √(ω_i ω_j) that (2.36) drops, and stays positive semi-definite in every period
    (ξ_m >= ξ_s), where (2.36) on the modes of one period put the mesh share on the stations
    under the mesh then, and subtracting it to re-add the period's ran away (negative damping
    on rim-local modes).

    Attributes:
        mesh_ratio: ξ_mesh (-), 0.07. structure_ratio: ξ_structure (-), 0.01.
    """

    mesh_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.07)
    structure_ratio: Float[Array, ""] = eqx.field(converter=as_float, default=0.01)

    needs_modes: ClassVar[bool] = True

    def matrix(self, scene, modes):
        e = modes.mesh_energy
        xi = self.mesh_ratio * e + self.structure_ratio * (1.0 - e)
        return _modal(scene.mass(), modes, xi)

    def hybrid(self, M, K, modes):
        Phi, omega = modes.shapes, modes.omega
        MP = M @ Phi
        C = MP @ ((2.0 * self.structure_ratio * omega)[:, None] * MP.T)
        s = jnp.where(modes.rigid, 0.0, 1.0 / jnp.sqrt(jnp.where(modes.rigid, 1.0, omega)))
        R = Phi @ (s[:, None] * MP.T)
        return C, 2.0 * (self.mesh_ratio - self.structure_ratio), R


def damping_matrix(
    scene: DynamicScene, modes: ModalAnalysis, damping: AbstractDamping
) -> Float[Array, "n n"]:
    """Viscous damping matrix C of a lumped scene (units of K·s), shape (n, n): the model's
    (:meth:`AbstractDamping.matrix`) plus the scene's bearing damping
    (:meth:`~jaxgear.scenes.DynamicScene.bearing_damping`, e.g. :class:`LumpedPair` with 6×6
    bearing damping matrices; zeros without bearings) whatever the model (:class:`NoDamping`
    included)."""
    return damping.matrix(scene, modes) + scene.bearing_damping()
