"""jaxgear: differentiable gear dynamics in JAX.

Public API (everything else lives in private modules). Float64 is not switched on here: the CLI,
the tests and the examples do it (``jax.config.update("jax_enable_x64", True)``), or set
``JAX_ENABLE_X64=1``.
"""

from ._baseplane import Cells as Cells, MeshModel as MeshModel
from ._case import Case as Case, list_cases as list_cases, load_case as load_case, parse_case as parse_case
from ._contact import (
    RESULT_MESSAGES as RESULT_MESSAGES,
    ContactSolution as ContactSolution,
    solve_contact as solve_contact,
)
from ._geometry import (
    GearPair as GearPair,
    Member as Member,
    involute as involute,
    inverse_involute as inverse_involute,
)
from ._modifications import MemberModification as MemberModification, Modifications as Modifications
from ._quasi_static import (
    QuasiStaticResult as QuasiStaticResult,
    mesh_positions as mesh_positions,
    quasi_static as quasi_static,
)
from ._run import harris_map as harris_map, load_map as load_map, run_case as run_case
from ._scene import (
    Grounded as Grounded,
    RigidMesh as RigidMesh,
    Scene as Scene,
    TorsionalPair as TorsionalPair,
    grounded as grounded,
)
from ._stiffness import (
    iso6336_mesh_stiffness as iso6336_mesh_stiffness,
    iso6336_single_stiffness as iso6336_single_stiffness,
    stiffness_table as stiffness_table,
    weber_profile as weber_profile,
)
from ._dyn_scene import (
    Damping as Damping,
    DynamicScene as DynamicScene,
    ModalAnalysis as ModalAnalysis,
    RelativeApproach as RelativeApproach,
    TorsionalDynamics as TorsionalDynamics,
    damping_matrix as damping_matrix,
    disc_inertia as disc_inertia,
    modal_analysis as modal_analysis,
)
from ._dyn_lumped import (
    Bearing as Bearing,
    LumpedPair as LumpedPair,
    ShaftSpec as ShaftSpec,
    lumped_pair as lumped_pair,
    timoshenko_element as timoshenko_element,
)
from ._dynamics import (
    DYNAMICS_RESULTS as DYNAMICS_RESULTS,
    DynamicModel as DynamicModel,
    DynamicResult as DynamicResult,
    SweepResult as SweepResult,
    dynamic_model as dynamic_model,
    simulate as simulate,
    speed_sweep as speed_sweep,
)

__version__ = "0.1.0"
