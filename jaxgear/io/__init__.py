"""Case files and output files: the one place that maps the names in a case file to the model's
objects. Loading and validating cases (TOML, units in key names) into the one case type,
:class:`Case` (a gear train; a pair is a train of one mesh; ``TrainCase`` is another name for
it), holding the :class:`MeshSettings` and its file's :class:`CaseForm`; its
``[scene]`` (:class:`SceneSpec`) and the objects it names (:func:`spec_integrator`,
:func:`Damping`, :func:`spec_window`, :func:`load_bodies`); the model of a case
(:func:`build_dynamic_model`, :func:`static_scene`, :func:`quasi_static_scene`); the embedded
cases, a case's optimisation problem, and atomic writers. JSON/CSV only: plots live in
:mod:`jaxgear.cli`. The model (:mod:`jaxgear`, :mod:`jaxgear.scenes`, :mod:`jaxgear.dynamics`)
never imports this package: it takes the objects built here, never a case."""

from ._case import (
    Case as Case,
)
from ._case import (
    CaseForm as CaseForm,
)
from ._case import (
    MeshSettings as MeshSettings,
)
from ._case import (
    PairForm as PairForm,
)
from ._case import (
    TrainCase as TrainCase,
)
from ._case import (
    TrainForm as TrainForm,
)
from ._case_file import SchemaError as SchemaError
from ._case_file import parse_case as parse_case
from ._case_model import (
    PAIR_SCENES as PAIR_SCENES,
)
from ._case_model import (
    build_dynamic_model as build_dynamic_model,
)
from ._case_model import (
    quasi_static_scene as quasi_static_scene,
)
from ._case_model import (
    static_scene as static_scene,
)
from ._deviations_table import (
    deviation_kinds_from_names as deviation_kinds_from_names,
)
from ._deviations_table import (
    parse_deviations as parse_deviations,
)
from ._load import (
    embedded_case_text as embedded_case_text,
)
from ._load import (
    list_cases as list_cases,
)
from ._load import (
    load_case as load_case,
)
from ._modifications_table import parse_modifications as parse_modifications
from ._names import (
    contact_law_from_name as contact_law_from_name,
)
from ._names import (
    foundation_from_name as foundation_from_name,
)
from ._names import (
    stiffness_from_name as stiffness_from_name,
)
from ._optimise_table import parse_optimise as parse_optimise
from ._planetary_spec import (
    InternalMeshForm as InternalMeshForm,
)
from ._planetary_spec import (
    PlanetaryForm as PlanetaryForm,
)
from ._planetary_spec import (
    PlanetarySpec as PlanetarySpec,
)
from ._plausibility import CaseWarning as CaseWarning
from ._plausibility import plausibility as plausibility
from ._problem import (
    OBJECTIVES as OBJECTIVES,
)
from ._problem import (
    OPTIMISERS as OPTIMISERS,
)
from ._problem import (
    STATISTICS as STATISTICS,
)
from ._problem import (
    case_problem as case_problem,
)
from ._problem import (
    objective_from_name as objective_from_name,
)
from ._problem import (
    optimiser_from_name as optimiser_from_name,
)
from ._rating_table import (
    TREATMENTS as TREATMENTS,
)
from ._rating_table import (
    RatingCase as RatingCase,
)
from ._rating_table import (
    parse_rating as parse_rating,
)
from ._rating_table import (
    rating_of as rating_of,
)
from ._robust_table import parse_robust as parse_robust
from ._scene_spec import (
    DAMPING_MODELS as DAMPING_MODELS,
)
from ._scene_spec import (
    INTEGRATORS as INTEGRATORS,
)
from ._scene_spec import (
    Damping as Damping,
)
from ._scene_spec import (
    SceneSpec as SceneSpec,
)
from ._scene_spec import (
    load_bodies as load_bodies,
)
from ._scene_spec import (
    spec_damping as spec_damping,
)
from ._scene_spec import (
    spec_integrator as spec_integrator,
)
from ._scene_spec import (
    spec_window as spec_window,
)
from ._scene_table import parse_scene as parse_scene
from ._train_file import parse_train as parse_train
from ._writers import (
    atomic_open as atomic_open,
)
from ._writers import (
    write_csv as write_csv,
)
from ._writers import (
    write_json as write_json,
)
from ._writers import (
    write_vtu as write_vtu,
)
