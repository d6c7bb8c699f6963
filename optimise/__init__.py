"""optimise: gradient-based tooth-modification design on the jaxgear quasi-static model.

Objectives are objects (:class:`TeRms`, :class:`TePeakToPeak`, :class:`RobustTeRms` over a torque
range, :class:`MaxLineLoad`, :class:`LoadCentroid` across the face, :class:`LineLoadLp` of the
line load, :class:`DynamicFactor` over a speed band, :class:`LeastSafetyFactor` of the rating, the
tribology objectives :class:`MeshPowerLoss`, :class:`EfficiencyLoss`, :class:`MinSpecificFilm`,
:class:`MaxFlashTemperature` of a :class:`MeshLubrication`, the acoustic objectives
:class:`EquivalentRadiatedPower` and :class:`RadiatedSoundPower` of a housed gearbox over a speed
range along an :class:`AcousticPath`) on the rigid mesh or on any scene
(the hybrid scene at speed included), design variables normalised and bounded by
reparametrisation; any optimistix quasi-Newton minimiser or optax gradient transformation
solves it (:func:`minimise`, L-BFGS by default); the Master Curve and the (Γ, E) contour map of TE RMS; robust design against
sampled deviations (:func:`robust_problem`, a :class:`Mean` or :class:`Quantile` statistic). A
rolling bearing's clearance is a variable of the structure (:class:`Clearance`, through a
:class:`BearingDesign` at the bearings' held operating point, :func:`bearing_design`).
Case-file names map to these objects in :mod:`jaxgear.io` (``case_problem``).
"""

from ._acoustics import (
    AbstractAcousticObjective as AbstractAcousticObjective,
    AcousticPath as AcousticPath,
    EquivalentRadiatedPower as EquivalentRadiatedPower,
    RadiatedSoundPower as RadiatedSoundPower,
    SurfaceRadiation as SurfaceRadiation,
)
from ._bearings import BearingDesign as BearingDesign, bearing_design as bearing_design
from ._master_curve import contour_map as contour_map, master_curve as master_curve
from ._minimise import (
    OptimisationResult as OptimisationResult,
    minimise as minimise,
    minimise_batch as minimise_batch,
)
from ._objectives import (
    CENTROID_SCALE as CENTROID_SCALE,
    AbstractObjective as AbstractObjective,
    AbstractQuasiStaticObjective as AbstractQuasiStaticObjective,
    AbstractStatistic as AbstractStatistic,
    DynamicFactor as DynamicFactor,
    LineLoadLp as LineLoadLp,
    LoadCentroid as LoadCentroid,
    Max as Max,
    MaxLineLoad as MaxLineLoad,
    Mean as Mean,
    Quantile as Quantile,
    RobustTeRms as RobustTeRms,
    TePeakToPeak as TePeakToPeak,
    TeRms as TeRms,
    line_load_lp as line_load_lp,
    load_centroid as load_centroid,
)
from ._problem import (
    OBJECTIVE_DESIGNS_STRUCTURE as OBJECTIVE_DESIGNS_STRUCTURE,
    OBJECTIVE_UNITS as OBJECTIVE_UNITS,
    OBJECTIVES as OBJECTIVES,
    Problem as Problem,
    Smoothing as Smoothing,
    make_problem as make_problem,
    zero_fluctuation_depth as zero_fluctuation_depth,
)
from ._robust import RobustProblem as RobustProblem, robust_problem as robust_problem
from ._safety import LeastSafetyFactor as LeastSafetyFactor, soft_min as soft_min
from ._tribology import (
    AbstractTribologyObjective as AbstractTribologyObjective,
    EfficiencyLoss as EfficiencyLoss,
    MaxFlashTemperature as MaxFlashTemperature,
    MeshLubrication as MeshLubrication,
    MeshPowerLoss as MeshPowerLoss,
    MinSpecificFilm as MinSpecificFilm,
)
from ._variables import (
    VARIABLES as VARIABLES,
    AbstractKind as AbstractKind,
    Clearance as Clearance,
    Depth as Depth,
    EndExtent as EndExtent,
    Extent as Extent,
    Variable as Variable,
    tip_relief_slots as tip_relief_slots,
    variables_of as variables_of,
)

__version__ = "0.1.0"
