"""Where a box housing's parts go, checked before anything is meshed: the room a bore has in an
end wall (within the walls' inner faces, clear of the other bores) and which of a box's sides a
point lies on (its signed distance to the outer faces, whether it is in the cavity).

All lengths in m; a bore's centre ``(u, v)`` in the end walls' plane, from the wall's corner
(the box's width along u, its height along v). NumPy only; nothing is meshed.
"""

from __future__ import annotations

import itertools
from typing import NamedTuple

import numpy as np

__all__ = ["BoreLimit", "bore_limits", "cavity_room"]


def cavity_room(width: float, height: float, wall_thickness: float, centres) -> np.ndarray:
    """Twice the distance from each centre ``(A, 2)`` (m) to the nearest inner face of a box's
    end wall of ``width`` x ``height`` (m) and walls ``wall_thickness`` (m): the largest bore
    diameter (m) the wall holds there, (A,); zero or negative where the centre is not inside
    the cavity's cross-section."""
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    t = float(wall_thickness)
    u, v = c[:, 0], c[:, 1]
    return 2.0 * np.minimum.reduce([u - t, width - t - u, v - t, height - t - v])


class BoreLimit(NamedTuple):
    """The largest diameter (m) a group of bores may share, the other bores as they are, and
    what limits it: ``by`` ``("wall", i)`` the walls' inner faces round bore i (the group's);
    ``("axes", i, j)`` two of the group's bores, i and j, whose centres lie ``diameter``
    apart; ``("bore", i, j)`` the group's bore i and another group's bore j (its diameter
    d_j): 2 |c_i − c_j| − d_j. Zero or negative: the group has no room (an empty range)."""

    diameter: float
    by: tuple


def bore_limits(width: float, height: float, wall_thickness: float, centres, diameters,
                groups) -> list[BoreLimit]:
    """For each group of bores (a list of indices into ``centres``, the bores one key of a
    case file sizes together), the largest diameter they may share: within the walls' inner
    faces (:func:`cavity_room`), clear of each other (two of one group, of diameter d, at
    distance s: d <= s) and of the other groups' bores at their ``diameters`` (d <= 2 s − d_j).

    Args:
        width, height, wall_thickness: the box's end wall (m).
        centres: the bores' centres ``(A, 2)`` (m) in the end walls' plane.
        diameters: each bore's diameter ``(A,)`` (m), for the other groups' limits.
        groups: a sequence of index lists, each bore in at most one.

    Returns:
        One :class:`BoreLimit` per group, in order.
    """
    c = np.asarray(centres, dtype=float).reshape(-1, 2)
    d = np.asarray(diameters, dtype=float).reshape(-1)
    room = cavity_room(width, height, wall_thickness, c)
    out = []
    for group in groups:
        members = [int(i) for i in group]
        cands = [(float(room[i]), ("wall", i)) for i in members]
        for i, j in itertools.combinations(members, 2):
            cands.append((float(np.linalg.norm(c[i] - c[j])), ("axes", i, j)))
        for i in members:
            for j in range(len(c)):
                if j not in members:
                    s = float(np.linalg.norm(c[i] - c[j]))
                    cands.append((2.0 * s - float(d[j]), ("bore", i, j)))
        out.append(BoreLimit(*min(cands, key=lambda x: x[0])))
    return out
