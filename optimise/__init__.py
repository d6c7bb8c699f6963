"""optimise: gradient-based tooth-modification design on the jaxgear quasi-static model.

Objectives (TE RMS / peak-to-peak at one load or over a torque range, maximum line load), design
variables normalised and bounded by reparametrisation, optax loops (L-BFGS, Adam), the Master
Curve and the (Γ, E) contour map of TE RMS.
"""

from ._master_curve import contour_map as contour_map
from ._master_curve import master_curve as master_curve
from ._minimise import OptimisationResult as OptimisationResult
from ._minimise import minimise as minimise
from ._problem import (
    OBJECTIVES as OBJECTIVES,
)
from ._problem import (
    VARIABLES as VARIABLES,
)
from ._problem import (
    Problem as Problem,
)
from ._problem import (
    make_problem as make_problem,
)
from ._problem import (
    parse_range as parse_range,
)
from ._problem import (
    zero_fluctuation_depth as zero_fluctuation_depth,
)

__version__ = "0.1.0"
