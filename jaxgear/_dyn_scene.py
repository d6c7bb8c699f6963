"""Dynamic scenes: inertias, shafts, modal analysis and damping (DESIGN.md §6, seed (2.31)-(2.36)).

A dynamic scene is a :class:`~jaxgear.Scene` (structure stiffness K_s, external load F, structure
vectors V, TE vector u) with a mass matrix M. The equations of motion, in generalised coordinates
X measured from the nominal rigid-body motion (the pinion turning at constant speed Ω), are

    M Ẍ + C Ẋ + K_s X + Σ_c k_c l_c φ(V_c·X − δ0_c(t)) V_c = F,                  (2.37)

with the contact cells, their stiffnesses and their initial separations δ0 evaluated at the
nominal mesh position θ = Ω t (the vibration angles, of order 1e-4 rad, are neglected in the cell
layout: the small-displacement hypothesis of the seed, III §3.2).

Scenes:

* :class:`TorsionalDynamics`: pinion and gear rotations (rad, each positive in its direction of
  motion), optionally a motor inertia coupled to the pinion and a load inertia coupled to the gear
  by torsional shafts: 2, 3 or 4 DOF. The torque T drives the motor (or the pinion), the load (or
  the gear) resists with T r_b2/r_b1: the chain has one rigid-body mode, which carries no mesh
  deflection (V·r = 0) and no net load (F·r = 0).
* :class:`RelativeApproach`: the 1-DOF reduction of the rigid pinion-gear pair, X = the
  flank-normal approach x = cos β_b (r_b1 θ1 − r_b2 θ2) (m), equivalent mass
  m_eq = 1 / (cos² β_b (r_b1²/I1 + r_b2²/I2)) (kg).

Damping (2.34)-(2.36) is built from the modal analysis of the time-averaged system
(:func:`modal_analysis`), by :func:`damping_matrix`.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from ._baseplane import MeshModel
from ._scene import RigidMesh, Scene
from ._util import as_float

__all__ = [
    "Damping",
    "DynamicScene",
    "ModalAnalysis",
    "RelativeApproach",
    "TorsionalDynamics",
    "damping_matrix",
    "disc_inertia",
    "modal_analysis",
]


def disc_inertia(density: float, radius: float, width: float) -> float:
    """Polar moment of inertia ρ π b r⁴ / 2 of a solid disc (kg·m²): a gear blank of tip radius
    ``radius`` (m) and face width ``width`` (m)."""
    return density * math.pi * width * radius**4 / 2.0


class DynamicScene(Scene):
    """Abstract scene with inertia: adds :meth:`mass`, :meth:`rigid_modes` and the named parts of
    the structure stiffness (for the strain-energy shares of the modal analysis)."""

    def mass(self) -> Float[Array, "n n"]:
        raise NotImplementedError  # abstract

    def reaction_matrix(self) -> Float[Array, "r n"]:
        """Rows R with R X the support (bearing) force components (N); none by default."""
        M = self.mass()
        return jnp.zeros((0, M.shape[0]), M.dtype)

    def rigid_modes(self) -> Float[Array, "n r"]:
        """Rigid-body modes r (columns, r may be 0) with V·r = 0 and F·r = 0."""
        raise NotImplementedError  # abstract

    def stiffness_parts(self) -> dict[str, Float[Array, "n n"]]:
        """Named structure stiffness matrices summing to :meth:`stiffness`."""
        raise NotImplementedError  # abstract


class TorsionalDynamics(DynamicScene):
    """Torsional model: (motor,) pinion, gear (, load) rotations (rad), seed I-3 / DESIGN.md §6.

    Attributes:
        mesh: the gear mesh.
        inertia_pinion, inertia_gear: polar inertias I1, I2 (kg·m²).
        inertia_motor, inertia_load: motor and load inertias (kg·m²), used when ``has_motor`` /
            ``has_load``.
        shaft_motor, shaft_load: torsional stiffnesses of the motor-pinion and gear-load shafts
            (N·m/rad).
        has_motor, has_load: static flags (DOF count 2 + has_motor + has_load).
    """

    mesh: MeshModel
    inertia_pinion: Float[Array, ""] = eqx.field(converter=as_float)
    inertia_gear: Float[Array, ""] = eqx.field(converter=as_float)
    inertia_motor: Float[Array, ""] = eqx.field(converter=as_float, default=1.0)
    inertia_load: Float[Array, ""] = eqx.field(converter=as_float, default=1.0)
    shaft_motor: Float[Array, ""] = eqx.field(converter=as_float, default=1e5)
    shaft_load: Float[Array, ""] = eqx.field(converter=as_float, default=1e5)
    has_motor: bool = eqx.field(static=True, default=False)
    has_load: bool = eqx.field(static=True, default=False)

    @property
    def n_dof(self) -> int:
        return 2 + int(self.has_motor) + int(self.has_load)

    @property
    def pinion_index(self) -> int:
        return int(self.has_motor)

    @property
    def gear_index(self) -> int:
        return int(self.has_motor) + 1

    def _unit(self, i):
        return jnp.zeros(self.n_dof, dtype=self.mesh.face_width.dtype).at[i].set(1.0)

    def _v(self):
        cb = jnp.cos(self.mesh.base_helix_angle)
        return (cb * self.mesh.base_radius_pinion * self._unit(self.pinion_index)
                - cb * self.mesh.base_radius_gear * self._unit(self.gear_index))

    def mass(self):
        d = [self.inertia_pinion, self.inertia_gear]
        if self.has_motor:
            d = [self.inertia_motor] + d
        if self.has_load:
            d = d + [self.inertia_load]
        return jnp.diag(jnp.stack(d))

    def stiffness_parts(self):
        out = {}
        if self.has_motor:
            e = self._unit(0) - self._unit(1)
            out["motor_shaft"] = self.shaft_motor * jnp.outer(e, e)
        if self.has_load:
            g = self.gear_index
            e = self._unit(g) - self._unit(g + 1)
            out["load_shaft"] = self.shaft_load * jnp.outer(e, e)
        return out

    def stiffness(self):
        K = jnp.zeros((self.n_dof, self.n_dof), dtype=self.mesh.face_width.dtype)
        for part in self.stiffness_parts().values():
            K = K + part
        return K

    def external_load(self, torque):
        ratio = self.mesh.base_radius_gear / self.mesh.base_radius_pinion
        return torque * self._unit(0) - torque * ratio * self._unit(self.n_dof - 1)

    def cell_vectors(self, cells):
        return jnp.broadcast_to(self._v(), cells.s.shape + (self.n_dof,))

    def te_vector(self):
        return self._v()

    def rigid_modes(self):
        rp, rg = 1.0 / self.mesh.base_radius_pinion, 1.0 / self.mesh.base_radius_gear
        r = jnp.where(jnp.arange(self.n_dof) <= self.pinion_index, rp, rg)
        return r[:, None]

    def reduced(self) -> RelativeApproach:
        """The 1-DOF relative-approach reduction (only for a rigid pinion-gear chain)."""
        if self.has_motor or self.has_load:
            raise ValueError("the relative-approach reduction needs a pinion-gear pair without "
                             "motor/load shafts: drop them or use the full torsional model")
        cb = jnp.cos(self.mesh.base_helix_angle)
        m_eq = 1.0 / (cb**2 * (self.mesh.base_radius_pinion**2 / self.inertia_pinion
                               + self.mesh.base_radius_gear**2 / self.inertia_gear))
        return RelativeApproach(self.mesh, m_eq)


class RelativeApproach(DynamicScene):
    """1-DOF relative approach x (m, flank-normal) with equivalent mass m_eq (kg); V = 1.

    The external load is the static normal mesh force F_n = T/(r_b1 cos β_b) (N)."""

    mesh: MeshModel
    equivalent_mass: Float[Array, ""] = eqx.field(converter=as_float)

    def mass(self):
        return jnp.reshape(self.equivalent_mass, (1, 1))

    def stiffness_parts(self):
        return {}

    # the structure is the rigid mesh's; only the mass is added
    def stiffness(self):
        return RigidMesh(self.mesh).stiffness()

    def external_load(self, torque):
        return RigidMesh(self.mesh).external_load(torque)

    def cell_vectors(self, cells):
        return RigidMesh(self.mesh).cell_vectors(cells)

    def te_vector(self):
        return RigidMesh(self.mesh).te_vector()

    def rigid_modes(self):
        return jnp.zeros((1, 0), dtype=self.mesh.face_width.dtype)


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
    return ModalAnalysis(omega=omega, frequency=omega / (2 * jnp.pi), shapes=Phi, energy=energy,
                         rigid=rigid, mesh_stiffness=mesh_stiffness, parts=tuple(parts))


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
            raise ValueError(f"damping model = {self.model!r}: allowed 'rayleigh', 'modal', "
                             "'composite', 'none'")


def damping_matrix(scene: DynamicScene, modes: ModalAnalysis, damping: Damping) -> Float[Array, "n n"]:
    """Viscous damping matrix C (units of K·s), shape (n, n).

    Modal/composite: C = M Φ diag(2 ξ_i ω_i) Φᵀ M with mass-normalised Φ, i.e. c_i = 2 ξ_i
    √(k_i m_i) per mode (2.35); rigid-body modes are undamped. Rayleigh: a_R M + b_R K̄ (2.34).
    """
    M = scene.mass()
    if damping.model == "none":
        return jnp.zeros_like(M)
    if damping.model == "rayleigh":
        K = modes.mesh_stiffness + scene.stiffness()
        return damping.alpha * M + damping.beta * K
    if damping.model == "modal":
        xi = jnp.broadcast_to(damping.ratio, modes.omega.shape)
    else:
        e = modes.mesh_energy
        xi = damping.mesh_ratio * e + damping.structure_ratio * (1.0 - e)
    MP = M @ modes.shapes
    return MP @ jnp.diag(2.0 * xi * modes.omega) @ MP.T
