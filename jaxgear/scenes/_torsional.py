"""Torsional scenes: rotations of the pinion and gear (and of a motor and a load), quasi-static
and dynamic, and the 1-DOF relative-approach reduction (seed (2.31); docs/design.md, "Structure
and dynamics").
"""

from __future__ import annotations

import math

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import MeshModel
from .._util import as_float
from ._rigid import RigidMesh
from ._scene import DynamicScene, Scene

__all__ = ["RelativeApproach", "TorsionalDynamics", "TorsionalPair", "disc_inertia"]


class TorsionalPair(Scene):
    """Two rotations X = (θ1, θ2) (rad, each positive in its direction of motion).

    The pinion carries the input torque T; the gear is held by an output shaft of torsional
    stiffness ``output_stiffness`` (N·m/rad) to a fixed load. Approach: V = cos β_b (r_b1, −r_b2).
    The transmission error is independent of the shaft stiffness (statically determinate chain),
    which the tests use as a check of the structure-vector plumbing.
    """

    mesh: MeshModel
    output_stiffness: Float[Array, ""] = eqx.field(converter=as_float, default=1e5)

    def _v(self):
        cb = jnp.cos(self.mesh.base_helix_angle)
        return jnp.stack([cb * self.mesh.base_radius_pinion, -cb * self.mesh.base_radius_gear])

    def stiffness(self):
        z = jnp.zeros_like(self.output_stiffness)
        return jnp.stack([jnp.stack([z, z]), jnp.stack([z, self.output_stiffness])])

    def external_load(self, torque):
        return jnp.stack([torque, jnp.zeros_like(torque)])

    def cell_vectors(self, cells):
        return jnp.broadcast_to(self._v(), cells.s.shape + (2,))

    def te_vector(self):
        return self._v()


def disc_inertia(density: float, radius: float, width: float) -> float:
    """Polar moment of inertia ρ π b r⁴ / 2 of a solid disc (kg·m²): a gear blank of tip radius
    ``radius`` (m) and face width ``width`` (m)."""
    return density * math.pi * width * radius**4 / 2.0


class TorsionalDynamics(DynamicScene):
    """Torsional model: (motor,) pinion, gear (, load) rotations (rad), seed I-3; docs/dynamics.md,
    "Scenes".

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
        return cb * self.mesh.base_radius_pinion * self._unit(
            self.pinion_index
        ) - cb * self.mesh.base_radius_gear * self._unit(self.gear_index)

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
            raise ValueError(
                "the relative-approach reduction needs a pinion-gear pair without "
                "motor/load shafts: drop them or use the full torsional model"
            )
        cb = jnp.cos(self.mesh.base_helix_angle)
        m_eq = 1.0 / (
            cb**2
            * (
                self.mesh.base_radius_pinion**2 / self.inertia_pinion
                + self.mesh.base_radius_gear**2 / self.inertia_gear
            )
        )
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
