"""Planetary stages: the stage and its model kinds, its meshes, ring, runout, per-tooth
deviations, modal analysis and load sharing, and its carrier-frame dynamics (docs/planetary.md).

The names a user reaches for first (the stage, its members, the model kinds, the mesh kinds,
:func:`planetary_quasi_static`, :func:`load_sharing`, :func:`planetary_modes`) are re-exported
from :mod:`jaxgear` too; the rest lives here only. Modules:

- ``_stage``: :class:`PlanetaryStage`, :class:`PlanetaryMember`, the model kinds
  (:class:`TorsionalPlanetary`, :class:`PlanarPlanetary`), the Willis speed ratio and the
  assembly condition;
- ``_spatial``: :class:`SpatialPlanetary` (six coordinates per member);
- ``_meshes``: the meshes as cells (:class:`ConstantMeshes`, :class:`ContactMeshes`), the
  sun–ring offset, the quasi-static solve, each planet's cell loads of a solve on its own
  mesh's cells (:func:`planet_mesh_loads`), a lumped model's constant mesh stiffness from a
  mesh's own (:func:`lumped_mesh_stiffness`);
- ``_ring``: the flexible ring (:class:`RigidRing`, :class:`CondensedRing`,
  :class:`CraigBamptonRing`);
- ``_runout``: eccentricities and unbalances; ``_hunting``: per-tooth deviations and the
  hunting period;
- ``_housed``: a kind on a :class:`~jaxgear.scenes.HousingMount`
  (:meth:`AbstractPlanetaryModel.on`, :class:`PlanetaryModel` ``mount=``: its members'
  supports about and along the axis join a condensed housing's seat) and the deprecated
  :class:`HousedPlanetary`;
- ``_analysis``: modes, mode types, Campbell diagram, mesh phasing, load sharing;
- ``_dynamics``: :func:`planetary_dynamics`, :func:`planetary_speed_sweep`,
  :func:`planetary_mesh_modes`, the dynamic load sharing factor (:func:`dynamic_load_sharing`),
  the ring transducer and the order spectrum (on
  :func:`jaxgear.dynamics.newmark`, the engine every dynamic model steps with);
- ``_model``: :class:`PlanetaryModel`, the stage's dynamics as a
  :class:`jaxgear.dynamics.AbstractDynamicModel` (:func:`jaxgear.dynamics.simulate` and
  :func:`jaxgear.dynamics.speed_sweep` run it), and given its input and output members a
  gearbox stage (:class:`jaxgear.dynamics.AbstractStage`, the one stage contract);
- ``_plan``: the time plan of a run over speeds (:func:`plan_sweep`, :func:`time_plan`: steps
  per mesh period, span, kept periods), every speed in one program (:func:`steps_sweep`), the
  factors read from its records (:func:`sweep_factors`), whether anything excites the stage
  (:func:`excitation`), the lumped model a stage's supports allow
  (:func:`planetary_model_for`), the lumped models a stage's analysis runs
  (:func:`lumped_mode_models`, :func:`lumped_sharing_models`) and its load sharing on one
  spring per mesh (:func:`constant_mesh_sharing`), over a turn (:func:`turn_travel`,
  :func:`sharing_over_turn`);
- ``_whine``: the stage's gear whine in the frequency domain (:func:`planetary_whine`,
  :class:`PlanetaryWhine`) and the central members' support reactions
  (:func:`support_reactions`).
"""

from ._analysis import (
    LoadSharing as LoadSharing,
    ModeType as ModeType,
    PlanetaryModes as PlanetaryModes,
    campbell as campbell,
    classify_modes as classify_modes,
    load_sharing as load_sharing,
    mesh_phases as mesh_phases,
    phasing_excites as phasing_excites,
    planetary_modes as planetary_modes,
)
from ._dynamics import (
    DynamicLoadSharing as DynamicLoadSharing,
    PlanetaryDynamics as PlanetaryDynamics,
    PlanetaryRun as PlanetaryRun,
    PlanetaryStageSystem as PlanetaryStageSystem,
    dynamic_load_sharing as dynamic_load_sharing,
    order_spectrum as order_spectrum,
    planetary_dynamics as planetary_dynamics,
    planetary_mesh_modes as planetary_mesh_modes,
    planetary_cell_row as planetary_cell_row,
    planetary_speed_sweep as planetary_speed_sweep,
    planetary_stage_system as planetary_stage_system,
    ring_transducer_signal as ring_transducer_signal,
)
from ._housed import HousedPlanetary as HousedPlanetary
from ._hunting import (
    DeviationMeshes as DeviationMeshes,
    PlanetaryDeviations as PlanetaryDeviations,
    PlanetaryTeeth as PlanetaryTeeth,
    PlanetFlanks as PlanetFlanks,
    planetary_hunting_periods as planetary_hunting_periods,
)
from ._meshes import (
    AbstractPlanetaryMeshes as AbstractPlanetaryMeshes,
    ConstantMeshes as ConstantMeshes,
    ContactMeshes as ContactMeshes,
    PlanetaryQuasiStatic as PlanetaryQuasiStatic,
    PlanetMeshLoads as PlanetMeshLoads,
    planet_mesh_loads as planet_mesh_loads,
    LUMPED_STIFFNESS_POSITIONS as LUMPED_STIFFNESS_POSITIONS,
    lumped_mesh_stiffness as lumped_mesh_stiffness,
    planetary_mesh_stiffness as planetary_mesh_stiffness,
    planetary_quasi_static as planetary_quasi_static,
    sun_ring_offset as sun_ring_offset,
)
from ._model import (
    PlanetaryModel as PlanetaryModel,
    PlanetaryPrepared as PlanetaryPrepared,
    PlanetarySpan as PlanetarySpan,
    sweep_records as sweep_records,
)
from ._plan import (
    EXCITATION_POSITIONS as EXCITATION_POSITIONS,
    HOLDS_3D as HOLDS_3D,
    KEEP_OTHER as KEEP_OTHER,
    KEEP_PERIODIC as KEEP_PERIODIC,
    LUMPED_MODELS as LUMPED_MODELS,
    NO_EXCITATION_TOL as NO_EXCITATION_TOL,
    STEPS_PER_TOP_PERIOD as STEPS_PER_TOP_PERIOD,
    TURN_POSITIONS as TURN_POSITIONS,
    SweepFactors as SweepFactors,
    SweepRecords as SweepRecords,
    TimePlan as TimePlan,
    carrier_periodic as carrier_periodic,
    constant_mesh_sharing as constant_mesh_sharing,
    eccentric as eccentric,
    excitation as excitation,
    grouped_records as grouped_records,
    holds_stage as holds_stage,
    lumped_mode_models as lumped_mode_models,
    lumped_sharing_models as lumped_sharing_models,
    plan_sweep as plan_sweep,
    program_span as program_span,
    rating_sharing_model as rating_sharing_model,
    settled_periods as settled_periods,
    sharing_over_turn as sharing_over_turn,
    planetary_model_for as planetary_model_for,
    speed_groups as speed_groups,
    speed_run as speed_run,
    step_resolution as step_resolution,
    steps_sweep as steps_sweep,
    sweep_factors as sweep_factors,
    time_plan as time_plan,
    turn_travel as turn_travel,
)
from ._ring import (
    AbstractRingModel as AbstractRingModel,
    CondensedRing as CondensedRing,
    CraigBamptonRing as CraigBamptonRing,
    RigidRing as RigidRing,
    ring_contact_angles as ring_contact_angles,
    ring_excitation as ring_excitation,
    ring_resonances as ring_resonances,
)
from ._spatial import SpatialPlanetary as SpatialPlanetary
from ._stage import (
    AbstractPlanetaryModel as AbstractPlanetaryModel,
    Central as Central,
    Eccentricities as Eccentricities,
    PlanarPlanetary as PlanarPlanetary,
    PlanetaryMember as PlanetaryMember,
    PlanetaryStage as PlanetaryStage,
    TorsionalPlanetary as TorsionalPlanetary,
    Unbalances as Unbalances,
    central_speeds as central_speeds,
    central_torques as central_torques,
    check_assembly as check_assembly,
    closest_planets as closest_planets,
    max_planets as max_planets,
    speed_ratio as speed_ratio,
)
from ._whine import (
    PlanetaryWhine as PlanetaryWhine,
    SupportReactions as SupportReactions,
    planetary_whine as planetary_whine,
    support_reactions as support_reactions,
)
