"""A case file's optimisation problem: :func:`optimise.make_problem` on the case's model objects."""

from __future__ import annotations

import jaxgear as jg
from optimise import Problem, make_problem

__all__ = ["case_problem"]


def case_problem(
    case: jg.Case,
    variables,
    objective: str = "te_rms",
    *,
    slices: int | None = None,
    scene: jg.Scene | None = None,
    positions_per_pitch: int | None = None,
    **settings,
) -> Problem:
    """The :class:`optimise.Problem` of a case: its rigid mesh (or ``scene``), its
    modifications as the starting design, its torque as the design torque, its positions per
    pitch and its smooth contact width.

    Args:
        case: a :class:`jaxgear.Case` (:func:`jaxgear.io.load_case`).
        variables, objective: as :func:`optimise.make_problem`.
        slices: slices per contact line of the rigid mesh (default the case's).
        scene: the structure to optimise on instead of the case's rigid mesh, e.g. the hybrid
            scene of :func:`jaxgear.dynamics.static_scene`; its mesh replaces ``slices``.
        positions_per_pitch: default the case's.
        settings: the other keywords of :func:`optimise.make_problem` (torques, bounds,
            speed, speeds, integrator, window, ...).

    Raises:
        ValueError: as :func:`optimise.make_problem`.
    """
    mesh = case.mesh_model(slices=slices) if scene is None else scene
    settings.setdefault(
        "contact",
        jg.SmoothContact(case.smooth_width, 50 if objective == "dynamic_factor" else 100),
    )
    return make_problem(
        mesh,
        case.modifications,
        case.torque,
        variables,
        objective,
        positions_per_pitch=int(positions_per_pitch or case.positions_per_pitch),
        **settings,
    )
