"""Gear dynamics with unilateral contact (DESIGN.md §6, seed (2.31)-(2.37)).

:func:`dynamic_model` builds a :class:`DynamicModel` (time-averaged mesh stiffness, modal analysis,
damping) from a dynamic scene; :func:`simulate` integrates one speed to steady state (Newmark with
the exact contact loop, or a diffrax solver); :func:`speed_sweep` vmaps (or continues) over speeds.
:func:`build_dynamic_model` does it from a case's ``[scene]`` (:class:`SceneSpec`).
"""

from ._config import DIFFRAX_SOLVERS as DIFFRAX_SOLVERS
from ._from_case import (
    SceneSpec as SceneSpec,
)
from ._from_case import (
    build_dynamic_model as build_dynamic_model,
)
from ._from_case import (
    quasi_static_3d as quasi_static_3d,
)
from ._modal import (
    Damping as Damping,
)
from ._modal import (
    ModalAnalysis as ModalAnalysis,
)
from ._modal import (
    damping_matrix as damping_matrix,
)
from ._modal import (
    modal_analysis as modal_analysis,
)
from ._model import (
    DynamicModel as DynamicModel,
)
from ._model import (
    MeshTable as MeshTable,
)
from ._model import (
    dynamic_model as dynamic_model,
)
from ._model import (
    mesh_table as mesh_table,
)
from ._simulate import (
    DynamicResult as DynamicResult,
)
from ._simulate import (
    SweepResult as SweepResult,
)
from ._simulate import (
    simulate as simulate,
)
from ._sweep import speed_sweep as speed_sweep
