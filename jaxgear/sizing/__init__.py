"""Gear sizing: the macro-geometry of an external pair from requirements. A :class:`SizingSpec`
states the load, ratio, material, life, minimum safety factors and limits, and the ranges
searched (normal modules of ISO 54's series, pinion teeth); :func:`enumerate_candidates` lists
every (m_n, z1, z2) in them within the ratio tolerance and the centre-distance window;
:func:`size` rates them all at once (geometry, validity, ISO 6336 with
:class:`jaxgear.rating.TracedTeethRatingGeometry` under ``jit(vmap)``) into a
:class:`SizingTable` with the reasons each rejected candidate fails. Imported on its own
(``import jaxgear.sizing``); the spec file and ``jaxgear size`` are :mod:`jaxgear.io`'s and the
CLI's. :func:`te_stage` adds the quasi-static transmission error of the best feasible
candidates, plain and with optimised tip relief and crowning. SI units throughout
(docs/sizing.md). The objectives a designer ranks by are columns (:data:`OBJECTIVES`: mass,
envelope volume, least margin, mesh loss and efficiency with :class:`MeshLossInputs`); with a
:class:`ScuffingRequirement` every candidate is rated for scuffing too (ISO/TS 6336-20's closed
form, :func:`jaxgear.tribology.ts_scuffing`: S_B a check beside pitting and bending), and
:func:`pareto_front` sorts the feasible candidates into non-dominated fronts over some of them
and picks a design. :func:`dynamics_stage` runs the candidates of the first fronts through
their lumped torsional dynamic model: the dynamic factor over a speed range, the resonance
speed and the whine."""

from ._candidates import (
    Candidates as Candidates,
    enumerate_candidates as enumerate_candidates,
    ratio_pairs as ratio_pairs,
)
from ._dynamics import (
    DYNAMICS_COLUMNS as DYNAMICS_COLUMNS,
    WHINE_ORDERS as WHINE_ORDERS,
    DynamicsCurves as DynamicsCurves,
    DynamicsSettings as DynamicsSettings,
    candidate_dynamic_model as candidate_dynamic_model,
    dynamics_selection as dynamics_selection,
    dynamics_speeds as dynamics_speeds,
    dynamics_stage as dynamics_stage,
)
from ._objectives import (
    MESH_LOSS_COLUMNS as MESH_LOSS_COLUMNS,
    OBJECTIVES as OBJECTIVES,
    SCUFFING_COLUMNS as SCUFFING_COLUMNS,
    STAGE_OBJECTIVES as STAGE_OBJECTIVES,
    MeshLossInputs as MeshLossInputs,
    ScuffingRequirement as ScuffingRequirement,
    envelope_volume as envelope_volume,
    objective_columns as objective_columns,
)
from ._pareto import (
    CHOICES as CHOICES,
    DEFAULT_OBJECTIVES as DEFAULT_OBJECTIVES,
    MOST_OBJECTIVES as MOST_OBJECTIVES,
    ParetoFront as ParetoFront,
    pareto_front as pareto_front,
)
from ._refine import (
    MARGIN as MARGIN,
    REFINE_OBJECTIVES as REFINE_OBJECTIVES,
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
from ._te import (
    CANDIDATE_MESH as CANDIDATE_MESH,
    TE_COLUMNS as TE_COLUMNS,
    TE_VARIABLES as TE_VARIABLES,
    TeSettings as TeSettings,
    candidate_mesh as candidate_mesh,
    candidate_modifications as candidate_modifications,
    candidate_pair as candidate_pair,
    te_curves as te_curves,
    te_stage as te_stage,
)
