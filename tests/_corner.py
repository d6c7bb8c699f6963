"""Where a cell's contact force acts, written here for the tests whose references are laws
(rigid-body motion, force and moment balances) that must also hold for the cells beyond the
theoretical path (docs/extended-contact.md, "Where it acts").

On the path a cell's force acts at its line-of-action point M along the line's normal n. Beyond
it the tip owner's corner touches the flank owner's involute: the contact point is the corner
P = Q + o_t t + o_v v (``jaxgear.CornerContact.offset``, from the tooth forms; Q the
line-of-action point, t the line's transverse direction, v the in-plane unit vector from the
driving gear's centre towards the line), and the force acts along the flank owner's involute
normal there. That normal is found here from P alone, not from the code's ε: an involute's
normal is tangent to its base circle, so it is the line through P at the distance r_bF from the
flank owner's centre, taken on the side of the line of action. A helical cell keeps the line's
axial part a sin β_b (the gap is transverse; the docs' approximation).
"""

from __future__ import annotations

import math

import numpy as np

import jaxgear as jg

__all__ = ["cell_points_normals", "ring_pair"]


def ring_pair():
    """The internal mesh the extended-contact tests share: a 21-tooth pinion (x = 0.4) in a
    72-tooth ring, m = 4 mm, α = 20°, 30 mm face."""
    return jg.InternalGearPair(
        jg.Member(teeth=21, face_width=0.03, profile_shift=0.4),
        jg.Member(teeth=-72, face_width=0.03, profile_shift=0.0),
        normal_module=0.004,
        normal_pressure_angle=math.radians(20.0),
    )


def _inplane(x):
    x = np.array(x, float)
    x[..., 2] = 0.0
    return x


def cell_points_normals(pair, s, points, direction, normal, centres):
    """(P, n): the contact points (..., 3) (m) and the driving gear's outward unit normals
    (..., 3) of cells at base-plane coordinates ``s`` (...) (m) whose line-of-action points are
    ``points`` (..., 3) (m), on a mesh line of transverse direction ``direction`` (3,) and
    normal ``normal`` (3,); ``centres``: the driving and the driven gear's centres (3,) each.
    On the path [0, g_α]: (points, normal)."""
    s = np.asarray(s, float)
    M = np.asarray(points, float)
    t = np.asarray(direction, float)
    n0 = np.asarray(normal, float)
    O = [np.asarray(c, float) for c in centres]
    beyond = (s < 0.0) | (s > pair.path_of_contact)
    P, n = np.array(M), np.broadcast_to(n0, M.shape).copy()
    if not np.any(beyond):
        return P, n
    corner = jg.CornerContact(pair, s[beyond])
    d1 = _inplane(M[beyond] - O[0])
    v = d1 - (d1 @ t)[..., None] * t
    v /= np.linalg.norm(v, axis=-1, keepdims=True)
    P[beyond] = M[beyond] + corner.offset[..., 0:1] * t + corner.offset[..., 1:2] * v
    # the flank owner: the driving gear before the start (the driven gear's tip touches it),
    # the driven gear after the end
    rb = np.where(s[beyond] < 0.0, pair.base_radii[0], pair.base_radii[1])
    OF = np.where((s[beyond] < 0.0)[..., None], O[0], O[1])
    d = _inplane(P[beyond] - OF)
    r = np.linalg.norm(d, axis=-1, keepdims=True)
    e = d / r
    ez = np.array([0.0, 0.0, 1.0])
    f = np.cross(ez, e)
    sin = rb[..., None] / r  # |(P − O_F) × n'| = r_bF: the normal is tangent to the base circle
    cos = np.sqrt(1.0 - sin**2)
    candidates = [a * cos * e + b * sin * f for a in (1, -1) for b in (1, -1)]
    # the one nearest the line's normal (ε is a few degrees)
    cb = np.linalg.norm(_inplane(n0))
    best = np.argmax(np.stack([c @ (_inplane(n0) / cb) for c in candidates]), axis=0)
    nt = np.stack(candidates)[best, np.arange(best.size)]
    n[beyond] = cb * nt + n0[2] * ez
    return P, n
