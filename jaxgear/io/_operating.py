"""The rolling bearings of a case's lumped 3D scene at their operating point
(:func:`operating_point`): the fixed point of :func:`jaxgear.dynamics.bearings_at_operating_point`
on the scene the case's form builds on given shafts (:meth:`~jaxgear.io.CaseForm.bearing_scene`),
found once per case, scene and torque; below the case (which builds its train on it) and the
case's models."""

from __future__ import annotations

from typing import Any

from ..dynamics import OperatingPoint, bearings_at_operating_point

__all__ = ["operating_point"]

#: the operating points found (:func:`operating_point`), by the case and its scene's identity
#: (the case kept, so that its identity is not reused); the newest few
_OPERATING: dict = {}
_OPERATING_KEPT = 4


def operating_point(case: Any, spec: Any = None, torque: float | None = None) -> OperatingPoint:
    """The rolling bearings of a ``lumped3d`` pair or train case's shafts (its ``[scene]``, or
    ``spec``, a :class:`~jaxgear.io.SceneSpec`) at their operating point:
    :func:`jaxgear.dynamics.bearings_at_operating_point` on the case's quasi-static scene on the
    ground (its form's :meth:`~jaxgear.io.CaseForm.bearing_scene`: a pair's
    :func:`~jaxgear.scenes.lumped_pair`, a train's :func:`~jaxgear.scenes.lumped_train` of
    :meth:`~jaxgear.io.Case.train_spec`), its mesh models, modifications, torque and positions
    per pitch, exact contact, the output's rotation held; ``torque`` another pinion (input)
    torque, N·m, for a load spectrum's bin. Found once per case, scene and torque. The bearings
    stand on the ground there, a housing (the case's ``[housing]``) rigid: its compliance moves
    the bearings' loads only where a shaft is statically indeterminate; the housed scene then
    holds the bearings' stiffness at that point.

    Raises:
        TypeError: a case whose form takes no rolling bearings (a planetary stage).
        ValueError: what :func:`~jaxgear.dynamics.bearings_at_operating_point` refuses, in
            one line.
    """
    spec = case.scene if spec is None else spec
    torque = case.torque if torque is None else float(torque)
    key = (id(case), id(spec), torque)
    if key in _OPERATING:
        return _OPERATING[key][2]
    build, shafts, extra_z = case.form.bearing_scene(case, spec)
    point = bearings_at_operating_point(
        build, shafts, case.mesh_modifications(), torque,
        hold=lambda scene: (scene.torque_dofs[1],), extra_z=extra_z,
        positions_per_pitch=case.positions_per_pitch)
    while len(_OPERATING) >= _OPERATING_KEPT:
        _OPERATING.pop(next(iter(_OPERATING)))
    _OPERATING[key] = (case, spec, point)
    return point
