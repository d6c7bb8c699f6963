"""Both bodies rigid: the 1-DOF flank-normal approach (seed (2.9) with V = 1)."""

from __future__ import annotations

import jax.numpy as jnp

from .._backlash import cell_flank
from .._baseplane import MeshModel
from .._util import check_instance
from ._scene import Scene

__all__ = ["RigidMesh"]


class RigidMesh(Scene):
    """Both bodies rigid: one coordinate, the flank-normal approach δ (m), V = 1 for every drive
    cell and −1 for every coast cell (the approach opens the coast flanks)."""

    mesh: MeshModel

    def __check_init__(self):
        check_instance("mesh", self.mesh, MeshModel, "a jaxgear.MeshModel", "RigidMesh")

    def stiffness(self):
        return jnp.zeros((1, 1), dtype=self.mesh.face_width.dtype)

    def external_load(self, torque):
        return jnp.reshape(self.mesh.normal_load(torque), (1,))

    def cell_vectors(self, cells):
        return cell_flank(cells)[..., None]

    def te_vector(self):
        return jnp.ones((1,), dtype=self.mesh.face_width.dtype)
