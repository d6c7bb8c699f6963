"""Gear dynamics with unilateral contact (seed (2.31)-(2.37); docs/design.md, "Structure and
dynamics").

Settings are objects, as diffrax takes them: the integrator (:class:`Newmark`,
:class:`DiffraxIntegrator`; a hybrid model's Newmark can take a :class:`ModalBasis`), the
contact law (:class:`jaxgear.ExactContact`, :class:`jaxgear.SmoothContact`), the damping (a
:class:`AbstractDamping`: :class:`RayleighDamping`, :class:`ModalDamping`,
:class:`CompositeDamping`, :class:`NoDamping`; :func:`jaxgear.io.Damping` maps the case
file's names to them) and the steady-state window (:class:`SteadyState`); the speed is an
argument.

A dynamics engine is an object, an :class:`AbstractDynamicModel` (as diffrax's solvers are
``AbstractSolver`` s): :func:`dynamic_model` builds the one of a scene's kind at a torque, a
:class:`DynamicModel` (lumped scenes: time-averaged mesh stiffness, modal analysis, damping)
or a :class:`HybridModel` (condensed bodies: damping built per speed). The entries are written
once over its methods (``prepare`` a run at one step count, then ``independent`` or
``continuation`` speeds): :func:`simulate` (one speed to steady state: Newmark with the exact
contact loop, or a diffrax solver for lumped models), :func:`speed_sweep` (vmapped, sharded or
continued over speeds) and :func:`band_dynamic_factor` (a smooth worst dynamic factor over a
band, for gradients); every engine's records (:class:`Records`) become one result type,
:class:`DynamicResponse` (:func:`steady_state`; in a :class:`SweepResult` for a sweep). All of
them step with :func:`newmark`, the one Newmark loop with unilateral contact, which also
integrates any M, C, K, F and cells given by hand.
:func:`whine_response` gives a lumped model's steady state in the frequency domain instead:
linearised about its quasi-static solution, a harmonic balance over the time-varying mesh
stiffness (:class:`HarmonicBalance`, :class:`TransmissionErrorSource`; a train of several mesh frequencies: :class:`QuasiPeriodicBalance`; docs/whine.md).
:func:`jaxgear.io.build_dynamic_model` does it from a case's ``[scene]``
(:class:`jaxgear.io.SceneSpec`): the model takes objects, never a case.

What a gearbox asks of each of its stages is one contract, :class:`AbstractStage` (a planetary
stage's :class:`jaxgear.planetary.PlanetaryModel` given its input and output members satisfies
it, as the gearbox's stage kinds do).
"""

from ._damping import (
    AbstractDamping as AbstractDamping,
    CompositeDamping as CompositeDamping,
    ModalDamping as ModalDamping,
    NoDamping as NoDamping,
    RayleighDamping as RayleighDamping,
    damping_matrix as damping_matrix,
)
from ._bearings import (
    OperatingPoint as OperatingPoint,
    bearing_forces as bearing_forces,
    bearings_at_operating_point as bearings_at_operating_point,
    SpectrumLife as SpectrumLife,
    operating_lives as operating_lives,
    spectrum_lives as spectrum_lives,
    with_bearing_stiffness as with_bearing_stiffness,
)
from ._build import (
    dynamic_model as dynamic_model,
    mesh_energy_shares as mesh_energy_shares,
    mesh_stiffness_means as mesh_stiffness_means,
    stage_model as stage_model,
)
from ._hybrid import HybridModel as HybridModel, HybridRun as HybridRun
from ._hybrid_damping import (
    RevolutionDamping as RevolutionDamping,
    revolution_damping as revolution_damping,
)
from ._hybrid_free import (
    FreeVibration as FreeVibration,
    hybrid_free_vibration as hybrid_free_vibration,
)
from ._hybrid_mesh import mean_mesh_stiffness as mean_mesh_stiffness
from ._hybrid_whine import (
    CyclicShift as CyclicShift,
    cyclic_shift as cyclic_shift,
    hybrid_whine as hybrid_whine,
)
from ._lumped import (
    DynamicModel as DynamicModel,
    LumpedRun as LumpedRun,
    static_start as static_start,
)
from ._modal import (
    ModalAnalysis as ModalAnalysis,
    ModesAtSpeed as ModesAtSpeed,
    campbell_coincidences as campbell_coincidences,
    excited_omega as excited_omega,
    gear_nodal_diameter_resonances as gear_nodal_diameter_resonances,
    matrix_modal_analysis as matrix_modal_analysis,
    modal_analysis as modal_analysis,
    modes_at_speed as modes_at_speed,
    nodal_diameter_modes as nodal_diameter_modes,
    nodal_diameter_resonances as nodal_diameter_resonances,
    steps_for_mode as steps_for_mode,
)
from ._model import (
    AbstractDynamicModel as AbstractDynamicModel,
    MeshTable as MeshTable,
    cell_stiffness as cell_stiffness,
    deviation_periods as deviation_periods,
    mesh_rows as mesh_rows,
    mesh_table as mesh_table,
    span_periods as span_periods,
)
from ._modal_basis import ModalSpace as ModalSpace, reduced_structure as reduced_structure
from ._newmark import (
    LinearSystem as LinearSystem,
    MeshDamping as MeshDamping,
    ModalStructure as ModalStructure,
    ModalSystem as ModalSystem,
    StepCells as StepCells,
    newmark as newmark,
    newmark_modal as newmark_modal,
)
from ._result import (
    DynamicResponse as DynamicResponse,
    DynamicResult as DynamicResult,
    MeshDynamics as MeshDynamics,
    Records as Records,
    SweepResult as SweepResult,
    steady_state as steady_state,
)
from ._settings import (
    DIFFRAX_ADJOINTS as DIFFRAX_ADJOINTS,
    DIFFRAX_SOLVERS as DIFFRAX_SOLVERS,
    MAX_STEPS_PER_SPEED as MAX_STEPS_PER_SPEED,
    MESH_ENERGY_MIN as MESH_ENERGY_MIN,
    MIN_STEPS_PER_PERIOD as MIN_STEPS_PER_PERIOD,
    STEPS_PER_MODE as STEPS_PER_MODE,
    UNDER_RESOLVED_STEPS as UNDER_RESOLVED_STEPS,
    DiffraxIntegrator as DiffraxIntegrator,
    HertzPressure as HertzPressure,
    Batching as Batching,
    ModalBasis as ModalBasis,
    Newmark as Newmark,
    Outputs as Outputs,
    SteadyState as SteadyState,
)
from ._rim import rim_stations as rim_stations, rim_waves as rim_waves
from ._robust import DynamicMetrics as DynamicMetrics, DynamicRobustMetrics as DynamicRobustMetrics
from ._settle import (
    CAP_ENERGY_MIN as CAP_ENERGY_MIN,
    SETTLE_TOL as SETTLE_TOL,
    SETTLED_TOL as SETTLED_TOL,
    SettledSweep as SettledSweep,
    modal_damping_ratios as modal_damping_ratios,
    settled_sweep as settled_sweep,
    settling_time as settling_time,
    unsettled_lines as unsettled_lines,
)
from ._simulate import simulate as simulate, simulate_on_table as simulate_on_table
from ._stage import AbstractStage as AbstractStage, mean_cell_stiffness as mean_cell_stiffness
from ._sweep import (
    DIRECTIONS as DIRECTIONS,
    AbstractDirection as AbstractDirection,
    Both as Both,
    Down as Down,
    Independent as Independent,
    Up as Up,
    auto_steps_per_period as auto_steps_per_period,
    band_dynamic_factor as band_dynamic_factor,
    mesh_averaged_modes as mesh_averaged_modes,
    resolve_settings as resolve_settings,
    speed_sweep as speed_sweep,
    steps_multiple as steps_multiple,
)
from ._whine import (
    MAX_WHINE_GRID as MAX_WHINE_GRID,
    MAX_WHINE_WORK as MAX_WHINE_WORK,
    WHINE_WORK_PER_CPU_S as WHINE_WORK_PER_CPU_S,
    AbstractWhineMethod as AbstractWhineMethod,
    HarmonicBalance as HarmonicBalance,
    QuasiPeriodicBalance as QuasiPeriodicBalance,
    TransmissionErrorSource as TransmissionErrorSource,
    WhineResponse as WhineResponse,
    WhineSize as WhineSize,
    check_whine_speeds as check_whine_speeds,
    balance_harmonics as balance_harmonics,
    check_whine_size as check_whine_size,
    fourier_coefficients as fourier_coefficients,
    group_rows as group_rows,
    harmonic_balance as harmonic_balance,
    whine_response as whine_response,
    whine_size as whine_size,
)
from ._whine import _mesh_basis as mesh_basis  # noqa: F401  (its public name)
from ._whine_qp import (
    group_positions as group_positions,
    harmonic_set as harmonic_set,
    quasi_periodic_balance as quasi_periodic_balance,
    torus_coefficients as torus_coefficients,
)
