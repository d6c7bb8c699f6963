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
    cell and −1 for every coast cell (the approach opens the coast flanks).

    δ is the pinion's advance r_b1 φ1 cos β_b with the gear held (as the plane-strain FE
    reference holds it). Beyond the theoretical path (``mesh.contact_geometry``) a cell's force
    acts along the geometry's normal (docs/extended-contact.md, "Where it acts"): after the end
    of the path the pinion's tip corner touches, and its lever arm is λ r_b1, so V = λ(s) there
    (the derivative of the corner gap with respect to δ); before the start the pinion is the
    flank owner, V = 1."""

    mesh: MeshModel

    def __check_init__(self):
        check_instance("mesh", self.mesh, MeshModel, "a jaxgear.MeshModel", "RigidMesh")

    def stiffness(self):
        return jnp.zeros((1, 1), dtype=self.mesh.face_width.dtype)

    def external_load(self, torque):
        return jnp.reshape(self.mesh.normal_load(torque), (1,))

    def cell_vectors(self, cells):
        lever = self.mesh.contact_geometry.lever_ratios(self.mesh, cells.s)[0]
        return (cell_flank(cells) * lever)[..., None]

    def te_vector(self):
        return jnp.ones((1,), dtype=self.mesh.face_width.dtype)
