"""A parallel pair in lumped 3D form as a gearbox stage (docs/gearbox.md, "A parallel stage in
lumped 3D form"): the pair's own dynamic model, :class:`~jaxgear.dynamics.DynamicModel`, given
its input side, which is a :class:`~jaxgear.dynamics.AbstractStage`;
:class:`LumpedPairGearboxStage` is its constructor in the gearbox's argument order.

The stage is a :class:`~jaxgear.scenes.LumpedPair` scene (:func:`~jaxgear.scenes.lumped_pair`:
Timoshenko shafts, bearings, rigid gear bodies, 6 DOFs per shaft node u_x, u_y, u_z, phi_x,
phi_y, phi_z, optionally a flexible housing's coordinates after the shafts'). Its coordinates in
the coupled gearbox are the scene's, unchanged (m for a translation, rad for a rotation). Both
shafts' phi_z are rotations about the same +z axis, the sense of
:class:`~jaxgear.gearbox.PairGearboxStage`'s theta: the mesh's rigid-body approach is
cos(beta_b) (r_b1 phi_z1 + r_b2 phi_z2) at the gear nodes, the torsional pair's
cos(beta_b) (r_b1 theta_1 + r_b2 theta_2). The shafts of the gearbox join the stage at the
scene's torque nodes (:attr:`~jaxgear.scenes.AssembledScene.torque_dofs`: ``input`` on the
pinion shaft, ``output`` on the gear shaft), where the scene's own external torques act.

Its contact cells are the scene's (:meth:`~jaxgear.scenes.AssembledScene.cell_row`: the
structure vectors V = [n, (M - O1) x n, -n, -(M - O2) x n] at the two gear nodes, seed (2.9)) at
pinion angle x / r_b1, x the mesh travel, with the initial separations of the pair's
modifications (:func:`jaxgear.quasi_static`'s ``separation``), as the scene's own dynamics
(:func:`jaxgear.dynamics.dynamic_model`) tabulates them. The bearings hold the translations and
tilts; the drive rotation is free in the scene and held in the gearbox by the output spring and
the shafts. The bearings' viscous damping (:class:`~jaxgear.scenes.Bearing`'s ``damping``) is
carried as a constant damping term with the rotating frame's
(:meth:`~jaxgear.dynamics.DynamicModel.speed_terms`).

The torsional chain (:class:`~jaxgear.gearbox.GearboxTorsional`, :func:`gearbox_modes`) sees the
stage condensed statically onto its two torque-node rotations (Guyan,
:meth:`~jaxgear.dynamics.DynamicModel.matrices`).
"""

from __future__ import annotations

from .._modifications import Modifications
from .._util import check_instance
from ..dynamics import DynamicModel
from ..scenes import LumpedPair

__all__ = ["LumpedPairGearboxStage"]


class LumpedPairGearboxStage(DynamicModel):
    """A parallel pair in lumped 3D form in the gearbox (module docstring): the pair's
    :class:`~jaxgear.dynamics.DynamicModel` built for a gearbox only
    (:func:`~jaxgear.dynamics.stage_model`: no operating torque, modes or damping), in the
    gearbox's argument order (a thin constructor: no method of its own beyond its checks and
    ``modifications``, the model's ``mods``).

    Args:
        scene: the :class:`~jaxgear.scenes.LumpedPair` (:func:`~jaxgear.scenes.lumped_pair`;
            with or without a housing).
        input: 0 when the previous stage (or the gearbox's input torque) drives the pinion
            shaft at its torque node, 1 the gear shaft (the other shaft's torque node is the
            output).
        modifications: the pair's flank modifications (the cells' initial separations).

    Raises:
        ValueError: ``scene`` not a :class:`~jaxgear.scenes.LumpedPair`, ``input`` not 0 or 1,
            ``modifications`` not a :class:`~jaxgear.Modifications`, a mesh with coast flanks
            (one line each).
    """

    def __init__(self, scene: LumpedPair, input: int = 0,
                 modifications: Modifications | None = None):
        where = "LumpedPairGearboxStage"
        check_instance("scene", scene, LumpedPair, "a jaxgear.scenes.LumpedPair", where)
        if isinstance(input, bool) or input not in (0, 1):
            raise ValueError(f"{where}: input = {input!r}: out of range, allowed 0 (pinion "
                             "shaft), 1 (gear shaft)")
        mods = Modifications() if modifications is None else modifications
        check_instance("modifications", mods, Modifications, "a jaxgear.Modifications", where)
        # the model of stage_model: no torque, damping, modes or mean stiffness (a stage's)
        super().__init__(scene, mods, None, None, None, None, input=int(input))

    def __check_init__(self):
        self.check_stage("LumpedPairGearboxStage")

    @property
    def modifications(self) -> Modifications:
        """The pair's flank modifications (the model's ``mods``)."""
        return self.mods
