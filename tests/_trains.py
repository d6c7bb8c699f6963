"""Helpers of the gear-train tests: bearing force sums and the mesh force directions written
from the gear data alone (independent of the layout code)."""

from __future__ import annotations

import math

import numpy as np
from _corner import cell_points_normals

__all__ = ["contact_forces", "line_direction", "shaft_sum", "spins"]


def shaft_sum(forces: dict, shaft: str) -> np.ndarray:
    """The sum (F_x, F_y, F_z) of a shaft's bearing force components (N)."""
    return np.array(
        [
            sum(v for k, v in forces.items() if k.startswith(shaft + " ") and k.endswith(f"F{c}"))
            for c in "xyz"
        ]
    )


def line_direction(case, k: int) -> np.ndarray:
    """The in-plane direction (2,) of the force mesh k's driving gear exerts on its driven gear,
    from the gear data alone: the centre line (angle_deg of the mesh) turned by 90° − α_wt
    towards the driving gear's motion (counter-clockwise for a gear turning about +z)."""
    spin = spins(case)[case.gears[k][0]]
    turn = spin * (math.pi / 2 - case.pairs[k].operating_pressure_angle)
    phi = case.angles[k] + turn
    return np.array([math.cos(phi), math.sin(phi)])


def spins(case) -> list:
    """Each gear's sense of rotation about +z: the input +1, a driven gear the other sense
    than its mate, shaft-mates alike."""
    spin = [None] * case.n_gears
    for i in range(case.n_gears):
        if case.shaft_of[i] == case.shaft_of[0]:
            spin[i] = 1
    for g, h in case.gears:
        for i in range(case.n_gears):
            if case.shaft_of[i] == case.shaft_of[h]:
                spin[i] = -spin[g]
    return spin


def contact_forces(case, result, k: int) -> tuple:
    """(P, F): each cell's contact point (S, L, N, 3) (m) and the force (S, L, N, 3) (N) that
    mesh k's driving gear puts on its driven gear there, from a quasi-static ``result`` of the
    train's static scene: the cell's line load times its length b/(N cos β_b) along the driving
    gear's outward normal, the line of action's on the path, the corner's involute normal
    beyond it (tests/_corner.py); masked cells carry nothing."""
    layout, plane = case.layout(), case.mesh_models()[k]
    line, mesh = layout.lines[k], result.meshes[k]
    g, h = case.gears[k]
    b = float(plane.face_width)
    cell = b / mesh.line_load.shape[-1] / math.cos(float(plane.base_helix_angle))
    f = np.where(mesh.cell_mask, np.asarray(mesh.line_load) * cell, 0.0)
    s, z = np.asarray(mesh.cell_s), np.asarray(mesh.cell_z)
    M = (
        np.asarray(line["tangent_point"])
        + (line["roll_start"] + s)[..., None] * np.asarray(line["direction"])
        + (line["axial"] * (z - b / 2))[..., None] * np.array([0.0, 0.0, 1.0])
    )
    P, n = cell_points_normals(
        case.pairs[k], s, M, line["direction"], line["normal"],
        (layout.centres[g], layout.centres[h]),
    )
    return P, f[..., None] * n
