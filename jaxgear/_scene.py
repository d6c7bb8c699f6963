"""Linear structures that the contact law acts on, through structure vectors (seed (2.9)).

A scene has n generalised coordinates X. The approach of cell c (flank-normal, m) is V_c·X, and
the contact force p_c l_c on the cell acts on the structure as −p_c l_c V_c. Each scene provides:

* ``stiffness()``: the structure's own stiffness K_s, shape (n, n);
* ``external_load(torque)``: generalised external forces F, shape (n,), for pinion torque T;
* ``cell_vectors(cells)``: V for every cell, shape (n_lines, n_slices, n);
* ``te_vector()``: u with u·X the flank-normal rigid-body approach of the mesh (the transmission
  error before the ``− max e`` and 1/cos β_b of DESIGN.md §4).

Later scenes (shafts, bearings, condensed bodies) plug into the same solver by providing these.
"""

from __future__ import annotations

import abc

import equinox as eqx
import jax.numpy as jnp
from ._util import as_float
from jaxtyping import Array, Float

from ._baseplane import Cells, MeshModel

__all__ = ["Scene", "RigidMesh", "TorsionalPair"]




class Scene(eqx.Module):
    """Abstract linear structure seen by the contact law."""

    @abc.abstractmethod
    def stiffness(self) -> Float[Array, "n n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def external_load(self, torque: Float[Array, ""]) -> Float[Array, " n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def cell_vectors(self, cells: Cells) -> Float[Array, "n_lines n_slices n"]:
        """See the module docstring."""

    @abc.abstractmethod
    def te_vector(self) -> Float[Array, " n"]:
        """See the module docstring."""


class RigidMesh(Scene):
    """Both bodies rigid: one coordinate, the flank-normal approach δ (m), V = 1 for every cell."""

    mesh: MeshModel

    def stiffness(self):
        return jnp.zeros((1, 1), dtype=self.mesh.face_width.dtype)

    def external_load(self, torque):
        return jnp.reshape(self.mesh.normal_load(torque), (1,))

    def cell_vectors(self, cells):
        return jnp.ones(cells.s.shape + (1,), dtype=cells.s.dtype)

    def te_vector(self):
        return jnp.ones((1,), dtype=self.mesh.face_width.dtype)


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


class Grounded(Scene):
    """A scene with some coordinates tied to the ground by a stiff spring (for statics).

    Dynamic scenes keep rigid-body modes (the torsional chain turns freely) that make their
    stiffness singular in a quasi-static solve. Grounding the output rotation (the load) removes
    the mode; in a statically determinate torsional chain it changes neither the transmission error
    nor the bearing loads.

    Attributes:
        base: the scene. dofs: grounded coordinate indices (static).
        stiffness_value: spring stiffness in the units of those coordinates (default 1e3 times
            the largest diagonal term of the base stiffness).
    """

    base: Scene
    stiffness_value: Float[Array, ""] = eqx.field(converter=as_float)
    dofs: tuple = eqx.field(static=True)

    @property
    def mesh(self):
        return self.base.mesh

    def stiffness(self):
        K = self.base.stiffness()
        idx = jnp.asarray(self.dofs)
        return K.at[idx, idx].add(self.stiffness_value)

    def external_load(self, torque):
        return self.base.external_load(torque)

    def cell_vectors(self, cells):
        return self.base.cell_vectors(cells)

    def te_vector(self):
        return self.base.te_vector()


def grounded(scene: Scene, dofs, factor: float = 1e3) -> Grounded:
    """Ground ``dofs`` of ``scene`` with springs ``factor`` × the largest diagonal stiffness."""
    k = float(jnp.max(jnp.abs(jnp.diag(scene.stiffness()))))
    return Grounded(scene, factor * max(k, 1.0), tuple(int(d) for d in dofs))
