"""A parallel pair in lumped 3D form as a gearbox stage kind (docs/gearbox.md, "A parallel
stage in lumped 3D form"): the whole kind in this one module, on the
:class:`~jaxgear.dynamics.AbstractStage` interface.

The stage is a :class:`~jaxgear.scenes.LumpedPair` scene (:func:`~jaxgear.scenes.lumped_pair`:
Timoshenko shafts, bearings, rigid gear bodies, 6 DOFs per shaft node u_x, u_y, u_z, phi_x,
phi_y, phi_z, optionally a flexible housing's coordinates after the shafts'). Its coordinates in
the coupled gearbox are the scene's, unchanged (m for a translation, rad for a rotation). Both
shafts' phi_z are rotations about the same +z axis, the sense of
:class:`~jaxgear.gearbox.PairGearboxStage`'s theta: the mesh's rigid-body approach is
cos(beta_b) (r_b1 phi_z1 + r_b2 phi_z2) at the gear nodes, the torsional pair's
cos(beta_b) (r_b1 theta_1 + r_b2 theta_2). The shafts of the gearbox join the stage at the
scene's torque nodes (:attr:`~jaxgear.scenes.ShaftSpec.torque_z`: ``input`` on the pinion
shaft, ``output`` on the gear shaft), where the scene's own external torques act.

Its contact cells are the scene's (:meth:`~jaxgear.scenes.AssembledScene.cell_row`: the
structure vectors V = [n, (M - O1) x n, -n, -(M - O2) x n] at the two gear nodes, seed (2.9)) at
pinion angle x / r_b1, x the mesh travel, with the initial separations of the pair's
modifications (:func:`jaxgear.quasi_static`'s ``separation``), as the scene's own dynamics
(:func:`jaxgear.dynamics.dynamic_model`) tabulates them. The bearings hold the translations and
tilts; the drive rotation is free in the scene and held in the gearbox by the output spring and
the shafts. The bearings' viscous damping (:class:`~jaxgear.scenes.Bearing`'s ``damping``) is
carried as a constant damping term with the rotating frame's (:meth:`speed_terms`).

The torsional chain (:class:`~jaxgear.gearbox.GearboxTorsional`, :func:`gearbox_modes`) sees the
stage condensed statically onto its two torque-node rotations (Guyan, :meth:`matrices`).
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np

from .._baseplane import on_the_path
from .._modifications import Modifications
from .._quasi_static import separation
from .._util import as_float, check_instance
from ..dynamics import AbstractStage
from ..scenes import LumpedPair
from ._chain import mean_cell_stiffness

__all__ = ["LumpedPairGearboxStage"]

#: mesh positions per period of the torsional chain's mean mesh stiffness (:meth:`matrices`)
CHAIN_POSITIONS = 64


class LumpedPairGearboxStage(AbstractStage):
    """A parallel pair in lumped 3D form in the gearbox (module docstring): the scene's shafts,
    bearings and gear bodies, its contact cells on its 6-DOF gear nodes.

    Attributes:
        scene: the :class:`~jaxgear.scenes.LumpedPair` (:func:`~jaxgear.scenes.lumped_pair`;
            with or without a housing).
        input: static, 0 when the previous stage (or the gearbox's input torque) drives the
            pinion shaft at its torque node, 1 the gear shaft (the other shaft's torque node is
            the output).
        modifications: the pair's flank modifications (the cells' initial separations).

    Raises:
        ValueError: ``scene`` not a :class:`~jaxgear.scenes.LumpedPair`, ``input`` not 0 or 1,
            a mesh with coast flanks (one line each).
    """

    scene: LumpedPair
    input: int = eqx.field(static=True, default=0)
    modifications: Modifications = eqx.field(default_factory=Modifications)
    #: its scene's bearings sit in a housing the gearbox shares
    takes_housing: ClassVar[bool] = True

    def __check_init__(self):
        check_instance("scene", self.scene, LumpedPair, "a jaxgear.scenes.LumpedPair",
                       "LumpedPairGearboxStage")
        if self.input not in (0, 1):
            raise ValueError(f"LumpedPairGearboxStage: input = {self.input!r}: out of range, "
                             "allowed 0 (pinion shaft), 1 (gear shaft)")
        check_instance("modifications", self.modifications, Modifications,
                       "a jaxgear.Modifications", "LumpedPairGearboxStage")
        if self.scene.mesh.coast:
            raise ValueError("LumpedPairGearboxStage: the scene's mesh has coast = True: allowed "
                             "False (the coupled model carries the loaded flanks)")

    # -- the scene's parts ------------------------------------------------------------------
    def _radii(self):
        mesh = self.scene.mesh
        return jnp.stack([mesh.base_radius_pinion, mesh.base_radius_gear])

    def _torque_dofs(self) -> tuple[int, int]:
        """(pinion shaft's, gear shaft's) torque-node phi_z (static)."""
        return self.scene.torque_dofs

    def coordinates(self):
        """The scene's coordinates: ``"<node> <dof>"`` on its named nodes (``pinion``,
        ``gear``, ``input``, ``output``, a housing's seats; coincident nodes joined by "/"),
        ``"q<i>"`` elsewhere (dof u_x, u_y, u_z in m, phi_x, phi_y, phi_z in rad)."""
        dofs = ("u_x", "u_y", "u_z", "phi_x", "phi_y", "phi_z")
        width = self.scene.structure.node_dofs
        names = {}
        for key, first in self.scene.structure.nodes:
            names.setdefault(first, []).append(key)
        out = []
        for i in range(self.scene.structure.size):
            first = i - i % width if width == 6 else i
            keys = names.get(first)
            out.append(f"{'/'.join(keys)} {dofs[i - first]}" if keys and width == 6
                       else f"q{i}")
        return tuple(out)

    def coordinate_ends(self):
        t = self._torque_dofs()
        return t[self.input], t[1 - self.input]

    def _mean_mesh(self, positions):
        return mean_cell_stiffness(on_the_path(self).cell_row, self.mesh_period(), positions)

    def dynamic_parts(self, positions):
        m, k = self.scene.mass(), self.scene.stiffness()
        return m, k, self._mean_mesh(positions), jnp.zeros(m.shape[0], m.dtype)

    def cell_row(self, x):
        mesh = self.scene.mesh
        cells, _, delta0 = separation(mesh, self.modifications, x / mesh.base_radius_pinion)
        return self.scene.cell_row((cells,), (delta0,))

    def mesh_forces(self, forces):
        return jnp.cos(self.scene.mesh.base_helix_angle) * jnp.sum(forces, axis=-1,
                                                                  keepdims=True)

    def mesh_names(self):
        return ("pair",)

    def mesh_period(self):
        return self.scene.mesh.base_pitch

    def kinematics(self, input_speed, input_torque):
        r = self._radii()
        r_in, r_out = r[self.input], r[1 - self.input]
        w = as_float(input_speed)
        torque = jnp.abs(as_float(input_torque))
        return (-w * r_in / r_out, torque * r_out / r_in, r_in * jnp.abs(w),
                jnp.reshape(torque / r_in, (1,)))

    def speed_terms(self, carrier_speed):
        """(the bearings' viscous damping (units of K s), zeros): the scene's structure turns
        in the fixed frame (no Coriolis or centripetal terms); the bearing damping rides here
        as the one damping the coupled model adds to its modal damping."""
        c = self.scene.bearing_damping()
        return c, jnp.zeros_like(c)

    def mount(self):
        """The :class:`~jaxgear.scenes.HousingMount` the scene's bearings sit in (its
        structure's; the housing's coordinates end the scene's), or None: a grounded scene."""
        return self.scene.structure.mount

    # -- the torsional chain's view ---------------------------------------------------------
    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def ends(self):
        return self.input, 1 - self.input

    def matrices(self):
        """(M, K) on the two torque-node rotations (kg m^2, N m/rad), ``theta_pinion``,
        ``theta_wheel`` in :class:`~jaxgear.gearbox.PairGearboxStage`'s sense: the scene with
        its mean mesh stiffness (over :data:`CHAIN_POSITIONS` positions) condensed statically
        onto them (Guyan, T = [I; -K_ii^-1 K_ie]: M = T^T M T, K = T^T K T), so that K holds the
        mesh, shaft and bearing compliances in series."""
        k = self.scene.stiffness() + self._mean_mesh(CHAIN_POSITIONS)
        m = self.scene.mass()
        ends = np.asarray(self._torque_dofs())
        inner = np.setdiff1d(np.arange(k.shape[0]), ends)
        T = jnp.zeros((k.shape[0], 2), k.dtype).at[ends].set(jnp.eye(2, dtype=k.dtype))
        T = T.at[inner].set(-jnp.linalg.solve(k[np.ix_(inner, inner)], k[np.ix_(inner, ends)]))
        return T.T @ m @ T, T.T @ k @ T
