"""The discrete candidates of a sizing: every (m_n, z1, z2) of the searched ranges within the
ratio tolerance and the centre-distance window, with the profile shifts and face width each
takes (:func:`enumerate_candidates`). NumPy: the enumeration is integer bookkeeping."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from .._geometry import inverse_involute, involute
from ._spec import SizingSpec

__all__ = ["RATIO_SLACK", "Candidates", "enumerate_candidates", "ratio_pairs"]

#: the relative slack of the ratio tolerance's bound (a z2/z1 on the bound is in, whatever the
#: binary round-off of u (1 ± tolerance))
RATIO_SLACK = 1e-12


@dataclasses.dataclass(frozen=True)
class Candidates:
    """The enumerated candidates, each field an array of shape (n,) (SI; teeth as integers):
    ``normal_module`` (m), ``z1``, ``z2``, ``x1``, ``x2`` (profile shifts), ``face_width`` (m,
    both gears), ``centre_distance`` (m, the zero-backlash distance of the shifts, ISO 21771).
    Ordered by module, then z1, then z2."""

    normal_module: np.ndarray
    z1: np.ndarray
    z2: np.ndarray
    x1: np.ndarray
    x2: np.ndarray
    face_width: np.ndarray
    centre_distance: np.ndarray

    def __len__(self) -> int:
        return int(self.z1.size)

    def take(self, index) -> Candidates:
        """The candidates at ``index`` (an index array or a mask)."""
        return Candidates(*(getattr(self, f.name)[index] for f in dataclasses.fields(self)))


def ratio_pairs(spec: SizingSpec) -> tuple[np.ndarray, np.ndarray]:
    """Every (z1, z2) of the pinion's range whose ratio z2/z1 lies within the tolerance of the
    target (:data:`RATIO_SLACK` on the bound), z1 then z2 increasing."""
    u, tol = spec.ratio, spec.ratio_tolerance
    z1 = np.arange(spec.pinion_teeth[0], spec.pinion_teeth[1] + 1)
    lo = np.ceil(z1 * u * (1 - tol) * (1 - RATIO_SLACK)).astype(int)
    hi = np.floor(z1 * u * (1 + tol) * (1 + RATIO_SLACK)).astype(int)
    counts = np.maximum(hi - lo + 1, 0)
    zz1 = np.repeat(z1, counts)
    zz2 = np.concatenate([np.arange(a, b + 1) for a, b in zip(lo, hi, strict=True)] or [[]])
    keep = np.abs(zz2 / zz1 - u) <= tol * u * (1 + RATIO_SLACK)
    return zz1[keep], zz2[keep].astype(int)


def enumerate_candidates(spec: SizingSpec) -> Candidates:
    """Every (m_n, z1, z2) of ``spec``'s modules and pinion teeth whose ratio lies within the
    tolerance (|z2/z1 − u| <= tolerance · u) and whose centre distance lies in the window
    (a fixed one: whose profile shift sum lies in ``spec.profile_shift_sum``), with its
    profile shifts and face width (:class:`SizingSpec`).

    Centre distance (ISO 21771): a_w = (d1 + d2)/2 cos α_t / cos α_wt with inv α_wt = inv α_t +
    2 tan α_n (x1 + x2)/(z1 + z2); at a fixed a_w the sum x1 + x2 follows from the same
    relation, x2 = sum − x1.

    Returns:
        :class:`Candidates` (possibly empty).
    """
    z1, z2 = ratio_pairs(spec)
    mods = np.asarray(spec.normal_modules, dtype=float)
    m = np.repeat(mods, z1.size)
    z1, z2 = np.tile(z1, mods.size), np.tile(z2, mods.size)
    an, beta = spec.normal_pressure_angle, spec.helix_angle
    at = math.atan(math.tan(an) / math.cos(beta))
    d1, d2 = z1 * m / math.cos(beta), z2 * m / math.cos(beta)
    x1 = np.full(z1.shape, float(spec.profile_shift[0]))
    if spec.fixed_centre_distance:
        a = spec.centre_distance[0]
        cos_awt = (d1 + d2) * math.cos(at) / (2 * a)
        ok = cos_awt < 1.0
        awt = np.arccos(np.where(ok, cos_awt, 0.5))
        total = (involute(awt) - involute(at)) * (z1 + z2) / (2 * math.tan(an))
        lo, hi = spec.profile_shift_sum
        keep = ok & (total >= lo) & (total <= hi)
        x2 = total - x1
        centre = np.full(z1.shape, float(a))
    else:
        x2 = np.full(z1.shape, float(spec.profile_shift[1]))
        inv_awt = involute(at) + 2 * math.tan(an) * (x1 + x2) / (z1 + z2)
        ok = inv_awt > 0
        awt = inverse_involute(np.where(ok, inv_awt, 1e-3))
        centre = (d1 + d2) / 2 * math.cos(at) / np.cos(awt)
        keep = ok
        if spec.centre_distance is not None:
            keep = keep & (centre >= spec.centre_distance[0]) & (centre <= spec.centre_distance[1])
    b = np.full(z1.shape, float(spec.face_width[1]))
    if spec.face_width_ratio is not None:
        b = np.minimum(b, spec.face_width_ratio * d1)
    out = Candidates(m, z1.astype(int), z2.astype(int), x1, x2, b, centre)
    return out.take(np.flatnonzero(keep))
