"""jaxgear: differentiable gear dynamics in JAX.

The top level is the gear pair's model, what a user reaches for first: the pair and its geometry
(:class:`GearPair`, :class:`InternalGearPair`, :class:`Member`), its modifications, the
mesh-stiffness kinds and the mesh model (:class:`MeshModel`), the contact laws, the
quasi-static solve (:func:`quasi_static`) and the results it returns, contact pressure, the
ISO 1328 deviations and their Monte Carlo sampling. Each subpackage's names are reached in the
subpackage, which ``import jaxgear`` loads: :mod:`jaxgear.scenes` (structures),
:mod:`jaxgear.dynamics` (runs, sweeps, modes, whine), :mod:`jaxgear.planetary` (planetary
stages), :mod:`jaxgear.gearbox` (stages joined by shafts), :mod:`jaxgear.rating` (load capacity,
ISO 6336); :mod:`jaxgear.tribology`, :mod:`jaxgear.acoustics`, :mod:`jaxgear.sizing` (gear sizing from
requirements), :mod:`jaxgear.bearings` (rolling bearings from their geometry) and the case files,
:mod:`jaxgear.io`, are imported on their own. A name that left the top level still resolves here
for one release, with a ``DeprecationWarning`` naming its home (``_MOVED_TO`` below). The
application (:mod:`jaxgear.cli`) is not imported here.

Float64 is not switched on here: the CLI, the tests and the examples do it
(``jax.config.update("jax_enable_x64", True)``), or set ``JAX_ENABLE_X64=1``.
"""

from importlib.metadata import PackageNotFoundError as _PackageNotFoundError, version as _version

from ._baseplane import CellRow as CellRow, Cells as Cells, MeshModel as MeshModel
from ._cell_factor import (
    CellFactor as CellFactor,
    line_factors as line_factors,
    solve_factored_cells as solve_factored_cells,
)
from ._compiled import (
    CompiledQuasiStatic as CompiledQuasiStatic,
    compile_quasi_static as compile_quasi_static,
)
from ._contact import (
    AbstractContactLaw as AbstractContactLaw,
    ContactLaw as ContactLaw,
    ContactSolution as ContactSolution,
    ExactContact as ExactContact,
    SmoothContact as SmoothContact,
    solve_contact as solve_contact,
    solve_contact_cells as solve_contact_cells,
)
from ._contact_geometry import (
    AbstractContactGeometry as AbstractContactGeometry,
    BeyondPath as BeyondPath,
    TheoreticalPath as TheoreticalPath,
)
from ._deviations import (
    Deviations as Deviations,
    GearDeviations as GearDeviations,
    ISO1328Tolerances as ISO1328Tolerances,
    hunting_revolutions as hunting_revolutions,
    iso1328_round as iso1328_round,
    iso1328_tolerances as iso1328_tolerances,
    iso1328_tolerances_array as iso1328_tolerances_array,
    sample_gear_deviations as sample_gear_deviations,
)
from ._extended import (
    CornerContact as CornerContact,
    corner_table as corner_table,
    extension_table as extension_table,
)
from ._geometry import (
    AbstractGearPair as AbstractGearPair,
    GearPair as GearPair,
    Member as Member,
    inverse_involute as inverse_involute,
    involute as involute,
)
from ._internal import (
    InternalGearPair as InternalGearPair,
    PlanetaryGeometry as PlanetaryGeometry,
    internal_tooth_geometry as internal_tooth_geometry,
    planetary_geometry as planetary_geometry,
)
from ._maps import (
    LoadedPath as LoadedPath,
    harris_map as harris_map,
    load_map as load_map,
    loaded_path as loaded_path,
)
from ._modifications import (
    AbstractEndReliefEdges as AbstractEndReliefEdges,
    AbstractReliefShape as AbstractReliefShape,
    BothEdges as BothEdges,
    EdgeZ0 as EdgeZ0,
    EdgeZ1 as EdgeZ1,
    LinearRelief as LinearRelief,
    MemberModification as MemberModification,
    Modifications as Modifications,
    ParabolicRelief as ParabolicRelief,
)
from ._pressure import (
    ContactPressure as ContactPressure,
    contact_modulus as contact_modulus,
    contact_pressure as contact_pressure,
    relative_radius as relative_radius,
)
from ._quasi_static import (
    MeshResult as MeshResult,
    QuasiStaticResult as QuasiStaticResult,
    mesh_positions as mesh_positions,
    quasi_static as quasi_static,
    separation as separation,
)
from ._results import (
    ContactResult as ContactResult,
    CutterResult as CutterResult,
    DynamicsResult as DynamicsResult,
)
from ._robust import (
    AbstractDeviationKind as AbstractDeviationKind,
    DeviationSampler as DeviationSampler,
    GearSampler as GearSampler,
    HelixDeviation as HelixDeviation,
    PitchDeviation as PitchDeviation,
    ProfileDeviation as ProfileDeviation,
    QuasiStaticMetrics as QuasiStaticMetrics,
    RobustMetrics as RobustMetrics,
    RunoutDeviation as RunoutDeviation,
    robust_samples as robust_samples,
    sample_mesh as sample_mesh,
    sample_metrics as sample_metrics,
    sample_statistics as sample_statistics,
)
from ._spectrum import TESpectrum as TESpectrum, te_spectrum as te_spectrum
from ._stiffness import (
    AbstractFoundation as AbstractFoundation,
    MemberFoundations as MemberFoundations,
    NoFoundation as NoFoundation,
    SainsotFoundation as SainsotFoundation,
    WeberFoundation as WeberFoundation,
    iso6336_blank_factor as iso6336_blank_factor,
    iso6336_mesh_stiffness as iso6336_mesh_stiffness,
    iso6336_pair_blank_factor as iso6336_pair_blank_factor,
    iso6336_single_stiffness as iso6336_single_stiffness,
    iso6336_virtual_teeth as iso6336_virtual_teeth,
    member_compliance as member_compliance,
    sainsot_coefficients as sainsot_coefficients,
    sainsot_fit_check as sainsot_fit_check,
    tooth_geometry as tooth_geometry,
    tooth_mass as tooth_mass,
    weber_profile as weber_profile,
)
from ._stiffness_models import (
    FE2D as FE2D,
    ISO6336 as ISO6336,
    AbstractStiffness as AbstractStiffness,
    MeshConditions as MeshConditions,
    Uniform as Uniform,
    Weber as Weber,
    stiffness_table as stiffness_table,
)
from ._util import padded_batch as padded_batch, safe_max as safe_max
# the subpackages load with the model (``import jaxgear`` then ``jaxgear.rating.rate``); their
# names are reached there, not here
from . import (
    dynamics as dynamics,
    gearbox as gearbox,
    planetary as planetary,
    rating as rating,
    scenes as scenes,
)

try:
    __version__ = _version("jaxgear")
except _PackageNotFoundError:  # running from a source tree that is not installed
    __version__ = "0+unknown"


# Names that left the top level for a subpackage: still reachable here for one release, each
# access warning with its new home (PEP 562 module ``__getattr__``). Not in ``dir(jaxgear)``.
_MOVED_TO = {  # new home -> the names that moved there
    "scenes": """
        Grounded grounded RigidMesh Scene TorsionalPair
    """,
    "planetary": """
        AbstractPlanetaryMeshes AbstractPlanetaryModel AbstractRingModel campbell Central
        check_assembly classify_modes CondensedRing ConstantMeshes ContactMeshes
        CraigBamptonRing DeviationMeshes Eccentricities load_sharing LoadSharing mesh_phases
        ModeType phasing_excites PlanarPlanetary planetary_hunting_periods
        planetary_mesh_stiffness planetary_modes planetary_quasi_static PlanetaryDeviations
        PlanetaryMember PlanetaryModes PlanetaryQuasiStatic PlanetaryStage PlanetaryTeeth
        PlanetFlanks RigidRing ring_contact_angles ring_excitation ring_resonances
        SpatialPlanetary speed_ratio sun_ring_offset TorsionalPlanetary Unbalances
    """,
    "gearbox": """
        gearbox_modes GearboxModes GearboxTorsional PairGearboxStage PlanetaryGearboxStage
    """,
    "rating": """
        AbstractEdition AbstractRootSection AbstractTreatment bending_rating BendingRating
        CaseHardened Edition2006 Edition2019 face_load_factor factor_clause FACTOR_CLAUSES
        GearAccuracy GivenFactors GivenRootSection InternalRatingGeometry load_factors
        LoadFactors Lubrication member_form Nitrided OperatingPoint PairTreatment pitting_rating
        PittingRating rate Rating RatingGeometry RatingMaterial RatingSettings root_stress_map
        RootStressMap section_factors ShaperCutterSection SubstituteRack ThroughHardened
        tooth_form_factors ToothFormFactors ToothLoading transverse_factor_limits
        transverse_load_factor
    """,
    "io": """
        Case TrainCase contact_law_from_name
    """,
}
_MOVED = {name: home for home, names in _MOVED_TO.items() for name in names.split()}
# Names that left the top level and were renamed in their new home: name -> (home, new name)
_RENAMED = {"AbstractGearboxStage": ("dynamics", "AbstractStage")}


def __getattr__(name: str):
    """A moved name (``_MOVED``; ``_RENAMED``: under its new name): its object from the new home,
    with a ``DeprecationWarning``."""
    home, new = _RENAMED.get(name, (_MOVED.get(name), name))
    if home is None:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib
    import warnings

    warnings.warn(
        f"jaxgear.{name} moved to jaxgear.{home}.{new}; the top-level name will be removed in "
        "the next release",
        DeprecationWarning,
        stacklevel=2,
    )
    return getattr(importlib.import_module(f"{__name__}.{home}"), new)
