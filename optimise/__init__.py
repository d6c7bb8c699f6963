"""optimise: gradient-based tooth-modification design on the jaxgear quasi-static model.

Objectives (TE RMS / peak-to-peak at one load or over a torque range, maximum line load, load
centroid across the face, L_p norm of the line load) on the rigid mesh or on any scene (the hybrid
scene at speed included), design variables normalised and bounded by reparametrisation,
optimistix solves (L-BFGS, Adam), the Master Curve and the (Γ, E) contour map of TE RMS.
"""

from ._master_curve import contour_map as contour_map, master_curve as master_curve
from ._robust import RobustProblem as RobustProblem, robust_problem as robust_problem
from ._minimise import OptimisationResult as OptimisationResult, minimise as minimise
from ._problem import (
    CENTROID_SCALE as CENTROID_SCALE,
    OBJECTIVE_UNITS as OBJECTIVE_UNITS,
    OBJECTIVES as OBJECTIVES,
    VARIABLES as VARIABLES,
    Problem as Problem,
    line_load_lp as line_load_lp,
    load_centroid as load_centroid,
    make_problem as make_problem,
    zero_fluctuation_depth as zero_fluctuation_depth,
)

__version__ = "0.1.0"
