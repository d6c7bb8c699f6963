"""Gear sizing: the macro-geometry of an external pair from requirements. A :class:`SizingSpec`
states the load, ratio, material, life, minimum safety factors and limits, and the ranges
searched (normal modules of ISO 54's series, pinion teeth); :func:`enumerate_candidates` lists
every (m_n, z1, z2) in them within the ratio tolerance and the centre-distance window;
:func:`size` rates them all at once (geometry, validity, ISO 6336 with
:class:`jaxgear.rating.TracedTeethRatingGeometry` under ``jit(vmap)``) into a
:class:`SizingTable` with the reasons each rejected candidate fails. Imported on its own
(``import jaxgear.sizing``); the spec file and ``jaxgear size`` are :mod:`jaxgear.io`'s and the
CLI's. SI units throughout (docs/sizing.md)."""

from ._candidates import (
    Candidates as Candidates,
    enumerate_candidates as enumerate_candidates,
    ratio_pairs as ratio_pairs,
)
from ._refine import (
    MARGIN as MARGIN,
    OBJECTIVES as OBJECTIVES,
    STARTS as STARTS,
    TOLERANCE as TOLERANCE,
    refine as refine,
)
from ._size import (
    CHECKS as CHECKS,
    GEOMETRIC as GEOMETRIC,
    OUTPUTS as OUTPUTS,
    SizingTable as SizingTable,
    blank_mass as blank_mass,
    candidate_outputs as candidate_outputs,
    size as size,
)
from ._spec import (
    ISO54_FIRST as ISO54_FIRST,
    ISO54_SECOND as ISO54_SECOND,
    SizingSpec as SizingSpec,
    module_series as module_series,
)
