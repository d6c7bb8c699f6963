"""Case files and output files: the one place that maps the names in a case file to the model's
objects. Loading and validating cases (TOML, units in key names) into the one case type,
:class:`Case` (a gear train; a pair is a train of one mesh; ``TrainCase`` is another name for
it), holding the :class:`MeshSettings` and its file's :class:`CaseForm`; its
``[scene]`` (:class:`SceneSpec`) and the objects it names (:func:`spec_integrator`,
:func:`Damping`, :func:`spec_window`, :func:`load_bodies`); the model of a case
(:func:`build_dynamic_model`, :func:`static_scene`, :func:`quasi_static_scene`); a housed
case's whine, ERP and radiated sound power (:func:`case_sound`); the embedded
cases, a case's optimisation problem, and atomic writers. JSON/CSV only: plots live in
:mod:`jaxgear.cli`. The model (:mod:`jaxgear`, :mod:`jaxgear.scenes`, :mod:`jaxgear.dynamics`)
never imports this package: it takes the objects built here, never a case."""

from ._acoustic_path import (
    HOUSING_BAND as HOUSING_BAND,
    HousedAcoustics as HousedAcoustics,
    HousingBand as HousingBand,
    case_acoustic_path as case_acoustic_path,
    case_radiation as case_radiation,
    closed_skin as closed_skin,
    housed_acoustics as housed_acoustics,
    housing_band as housing_band,
    radiation_grid as radiation_grid,
    surface_radiation as surface_radiation,
    surface_sound_power as surface_sound_power,
)
from ._acoustics_table import (
    ACOUSTICS_KEYS as ACOUSTICS_KEYS,
    ACOUSTICS_METHODS as ACOUSTICS_METHODS,
    AcousticsInputs as AcousticsInputs,
    AcousticsSection as AcousticsSection,
    acoustics_of as acoustics_of,
    parse_acoustics as parse_acoustics,
)
from ._bearings_table import (
    BearingLifeSettings as BearingLifeSettings,
    BearingsSection as BearingsSection,
    bearing_life_of as bearing_life_of,
)
from ._case import (
    BearingShafts as BearingShafts,
    Case as Case,
    CaseForm as CaseForm,
    MeshSettings as MeshSettings,
    PairForm as PairForm,
    TrainCase as TrainCase,
    TrainForm as TrainForm,
)
from ._case_file import SchemaError as SchemaError, parse_case as parse_case
from ._case_sound import (
    CaseSound as CaseSound,
    HousedErp as HousedErp,
    HousedRadiation as HousedRadiation,
    case_sound as case_sound,
    case_whine as case_whine,
    housed_erp as housed_erp,
    housed_radiation as housed_radiation,
    housed_run as housed_run,
)
from ._case_model import (
    PAIR_SCENES as PAIR_SCENES,
    bearing_spectrum_lives as bearing_spectrum_lives,
    build_dynamic_model as build_dynamic_model,
    case_bearings as case_bearings,
    check_case_whine as check_case_whine,
    dynamic_model_kind as dynamic_model_kind,
    planetary_kind as planetary_kind,
    quasi_static_scene as quasi_static_scene,
    static_scene as static_scene,
)
from ._deviations_table import (
    deviation_kinds_from_names as deviation_kinds_from_names,
    parse_deviations as parse_deviations,
)
from ._gearbox_file import (
    PAIR_INPUTS as PAIR_INPUTS,
    PLANETARY_MODELS as PLANETARY_MODELS,
    GearboxForm as GearboxForm,
    GearboxStage as GearboxStage,
)
from ._housing_table import (
    HousingBody as HousingBody,
    HousingSpec as HousingSpec,
    check_housing_band as check_housing_band,
    housing_surface as housing_surface,
)
from ._load import (
    check_case as check_case,
    embedded_case_text as embedded_case_text,
    list_cases as list_cases,
    load_case as load_case,
    published_rating as published_rating,
)
from ._lubricant_table import (
    FILM_FORMULAS as FILM_FORMULAS,
    LUBRICANT_KEYS as LUBRICANT_KEYS,
    LubricantSection as LubricantSection,
    TribologyInputs as TribologyInputs,
    parse_lubricant as parse_lubricant,
    tribology_of as tribology_of,
)
from ._micropitting_table import (
    MICROPITTING_KEYS as MICROPITTING_KEYS,
    MicropittingInputs as MicropittingInputs,
    parse_micropitting as parse_micropitting,
)
from ._modifications_table import (
    case_text_with_modifications as case_text_with_modifications,
    modifications_with as modifications_with,
    parse_modifications as parse_modifications,
)
from ._names import (
    contact_law_from_name as contact_law_from_name,
    foundation_from_name as foundation_from_name,
    stiffness_from_name as stiffness_from_name,
)
from ._operating import operating_point as operating_point
from ._optimise_table import (
    ACOUSTIC_OBJECTIVES as ACOUSTIC_OBJECTIVES,
    OPTIMISE_DEFAULTS as OPTIMISE_DEFAULTS,
    TORQUE_RANGE_OBJECTIVES as TORQUE_RANGE_OBJECTIVES,
    check_train_design as check_train_design,
    objective_units as objective_units,
    parse_optimise as parse_optimise,
)
from ._planetary_spec import (
    InternalMeshForm as InternalMeshForm,
    PlanetaryForm as PlanetaryForm,
    PlanetarySpec as PlanetarySpec,
)
from ._plausibility import CaseWarning as CaseWarning, plausibility as plausibility
from ._problem import (
    OBJECTIVES as OBJECTIVES,
    OPTIMISERS as OPTIMISERS,
    SEAT_TOLERANCE_MM as SEAT_TOLERANCE_MM,
    STATISTICS as STATISTICS,
    BearingChoice as BearingChoice,
    bearing_choices as bearing_choices,
    case_bearing_design as case_bearing_design,
    case_problem as case_problem,
    case_text_with_bearing as case_text_with_bearing,
    case_text_with_clearance as case_text_with_clearance,
    check_choice_text as check_choice_text,
    clearance_key as clearance_key,
    design_case_text as design_case_text,
    design_modifications as design_modifications,
    objective_from_name as objective_from_name,
    optimiser_from_name as optimiser_from_name,
    write_choice_case as write_choice_case,
    write_design_case as write_design_case,
)
from ._rating_table import (
    TREATMENTS as TREATMENTS,
    RatingCase as RatingCase,
    RatingSection as RatingSection,
    parse_rating as parse_rating,
    parse_train_rating as parse_train_rating,
    rating_of as rating_of,
    ratings_of as ratings_of,
)
from ._robust_table import parse_robust as parse_robust
from ._scene_spec import (
    DAMPING_MODELS as DAMPING_MODELS,
    INTEGRATORS as INTEGRATORS,
    Damping as Damping,
    SceneSpec as SceneSpec,
    load_bodies as load_bodies,
    spec_damping as spec_damping,
    spec_integrator as spec_integrator,
    spec_window as spec_window,
)
from ._scene_table import parse_scene as parse_scene
from ._scuffing_table import (
    SCUFFING_KEYS as SCUFFING_KEYS,
    ScuffingInputs as ScuffingInputs,
    parse_scuffing as parse_scuffing,
)
from ._sections import Range as Range, Section as Section, range_of as range_of
from ._sizing_spec import (
    SIZING_STAGES as SIZING_STAGES,
    SizingSection as SizingSection,
    candidate_case_text as candidate_case_text,
    housed_case_text as housed_case_text,
    load_sizing_spec as load_sizing_spec,
    parse_sizing_spec as parse_sizing_spec,
    sizing_dynamics_settings as sizing_dynamics_settings,
    sizing_te_settings as sizing_te_settings,
    unstaged_objective as unstaged_objective,
)
from ._sizing_sound import (
    SoundAcoustics as SoundAcoustics,
    SoundLayout as SoundLayout,
    SoundSection as SoundSection,
    sizing_sound as sizing_sound,
    sound_layout as sound_layout,
)
from ._train_file import parse_train as parse_train
from ._whine_table import (
    WHINE_KEYS as WHINE_KEYS,
    WHINE_METHODS as WHINE_METHODS,
    WhineInputs as WhineInputs,
    WhineSection as WhineSection,
    parse_whine as parse_whine,
    whine_of as whine_of,
)
from ._writers import (
    NonFiniteOutput as NonFiniteOutput,
    atomic_open as atomic_open,
    write_csv as write_csv,
    write_json as write_json,
    write_vtu as write_vtu,
)
