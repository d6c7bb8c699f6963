"""Helpers of the gear-train tests: bearing force sums and the mesh force directions written
from the gear data alone (independent of the layout code)."""

from __future__ import annotations

import math

import numpy as np

__all__ = ["line_direction", "shaft_sum", "spins"]


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
