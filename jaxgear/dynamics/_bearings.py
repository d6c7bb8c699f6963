"""The mean bearing forces of a quasi-static solution (the part of the case builders
that takes a scene, not a case)."""

from __future__ import annotations

import functools

import numpy as np

from .._quasi_static import QuasiStaticResult
from ..scenes import Grounded

__all__ = ["bearing_forces"]


@functools.singledispatch
def _bearing_scene(scene):
    """The scene whose bearings carry the load: the scene itself."""
    return scene


@_bearing_scene.register
def _(scene: Grounded):
    """A :class:`~jaxgear.scenes.Grounded` scene's bearings are its base's (the grounding
    spring is no bearing)."""
    return _bearing_scene(scene.base)


def bearing_forces(scene, res: QuasiStaticResult) -> dict:
    """Mean bearing force (N) per component name over the positions of ``res`` (fixed frame).

    Args:
        scene: the scene ``res`` was solved on (a lumped or hybrid scene with bearings, or one
            :func:`~jaxgear.scenes.grounded` wraps).
        res: its :class:`~jaxgear.QuasiStaticResult`, P positions.

    Returns:
        ``{reaction name: mean force (N)}`` over the P positions, in the scene's
        ``reaction_names`` order.
    """
    base = _bearing_scene(scene)
    F = np.asarray(base.bearing_forces(res.theta, res.x))  # (P, r)
    return dict(zip(base.reaction_names, F.mean(axis=0).tolist()))
