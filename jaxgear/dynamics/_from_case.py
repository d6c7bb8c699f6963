"""The dynamic model of a case: its ``[scene]`` settings turned into a scene and a
:class:`DynamicModel` (inertias default to solid discs)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._case import Case
from .._quasi_static import QuasiStaticResult, quasi_static
from ..scenes import ShaftSpec, TorsionalDynamics, disc_inertia, grounded, lumped_pair
from ._modal import Damping
from ._model import dynamic_model

__all__ = ["SceneSpec", "build_dynamic_model", "quasi_static_3d"]


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """A validated ``[scene]`` table (SI units; ``None``: derived default)."""

    model: str = "torsional"
    reduction: str = "none"
    pinion_inertia: float | None = None
    gear_inertia: float | None = None
    motor_inertia: float | None = None
    motor_shaft: float | None = None
    load_inertia: float | None = None
    load_shaft: float | None = None
    damping_model: str = "composite"
    damping_ratio: float = 0.05
    rayleigh_alpha: float = 0.0
    rayleigh_beta: float = 0.0
    mesh_ratio: float = 0.07
    structure_ratio: float = 0.01
    solver: str = "newmark"
    contact: str = "exact"
    steps_per_period: int | None = None  # None: automatic (auto_steps_per_period)
    periods: int = 60
    keep_periods: int = 4
    rtol: float = 1e-6
    atol: float = 1e-6
    pinion_mass: float | None = None
    gear_mass: float | None = None
    pinion_shaft: ShaftSpec | None = None  # lumped3d
    gear_shaft: ShaftSpec | None = None


def build_dynamic_model(case: Case, spec: SceneSpec | None = None, *, slices: int | None = None):
    """The :class:`~jaxgear.DynamicModel` of a case and its scene (default: ``[scene]``).

    Inertias default to solid discs of the tip radius and the member's face width with the case
    density. Returns (model, spec).
    """
    if spec is None:
        spec = case.scene if case.scene is not None else SceneSpec()
    pair = case.pair
    mesh = case.mesh_model(slices=slices)
    i1 = spec.pinion_inertia or disc_inertia(
        case.density, pair.tip_radii[0], pair.pinion.face_width
    )
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    if spec.model == "lumped3d":
        body = []
        for r, b, m, ip in (
            (pair.tip_radii[0], pair.pinion.face_width, spec.pinion_mass, i1),
            (pair.tip_radii[1], pair.gear.face_width, spec.gear_mass, i2),
        ):
            m = m or case.density * math.pi * r * r * b
            body.append((m, (ip / 2 + m * b * b / 12, ip)))  # disc: I_d = I_p/2 + m b²/12
        scene = lumped_pair(
            pair,
            mesh,
            spec.pinion_shaft,
            spec.gear_shaft,
            masses=(body[0][0], body[1][0]),
            inertias=(body[0][1], body[1][1]),
            youngs_modulus=case.youngs_modulus,
            poisson_ratio=case.poisson_ratio,
            density=case.density,
        )
    else:
        has_m, has_l = spec.motor_inertia is not None, spec.load_inertia is not None
        scene = TorsionalDynamics(
            mesh,
            i1,
            i2,
            spec.motor_inertia or 1.0,
            spec.load_inertia or 1.0,
            spec.motor_shaft or 1.0,
            spec.load_shaft or 1.0,
            has_motor=has_m,
            has_load=has_l,
        )
        if spec.reduction == "relative":
            scene = scene.reduced()
    damping = Damping(
        spec.damping_model,
        ratio=spec.damping_ratio,
        alpha=spec.rayleigh_alpha,
        beta=spec.rayleigh_beta,
        mesh_ratio=spec.mesh_ratio,
        structure_ratio=spec.structure_ratio,
    )
    # the time averages (modal analysis, damping) need a fixed grid: 64 positions per period
    # unless the scene fixes the step
    model = dynamic_model(
        scene,
        case.modifications,
        case.torque,
        damping,
        positions_per_pitch=spec.steps_per_period or 64,
    )
    return model, spec


def quasi_static_3d(case: Case, *, slices: int | None = None) -> tuple[QuasiStaticResult, dict]:
    """Quasi-static TE of the case's lumped 3D scene (shaft and bearing compliance; the load
    rotation grounded), with the case's modifications and exact contact.

    Returns:
        (result, mean bearing force (N) per bearing-force component name).

    Raises:
        ValueError: the case has no ``lumped3d`` scene.
    """
    if case.scene is None or case.scene.model != "lumped3d":
        raise ValueError("quasi_static_3d needs a case with [scene] model = 'lumped3d'")
    model, _ = build_dynamic_model(case, slices=slices)
    scene = model.scene
    res = quasi_static(
        grounded(scene, (scene.torque_dofs[1],)),
        case.modifications,
        case.torque,
        positions_per_pitch=case.positions_per_pitch,
    )
    forces = np.asarray(scene.reaction_matrix()) @ np.asarray(res.x).T
    return res, dict(zip(scene.reaction_names, forces.mean(axis=1).tolist()))
