"""Load capacity: ratings of external and internal pairs behind one seam, the rating standard.

One rating at an operating point: :func:`rate` (load factors, pitting, bending) of a pair's
rating geometry (:class:`RatingGeometry`, :class:`InternalRatingGeometry`) under
:class:`RatingSettings` (material, lubrication, accuracy, life, the standard). The standard is
a kind passed as an object (:class:`AbstractRatingStandard`): ISO 6336 method B in its editions
:class:`Edition2006` and :class:`Edition2019` (the default); a second standard is a subclass
written beside them. The load factors jaxgear measures on its results (K_v of a speed sweep,
K_Hβ and K_Hα of a load map, K_γ of the load sharing), the row each is reported as with the
contact model that produced it (:class:`MeasuredFactor`, :func:`contact_model`) and the settings
that rate with them (:func:`with_measured`) live here too. The tooth form
factors (ISO 6336-3), the load factors (ISO 6336-1, with K_Hβ and K_Hα from a contact solution)
and the finite-element root-stress map live here too. Life under a load spectrum (ISO 6336-6:
:class:`LoadSpectrum`, :func:`rate_spectrum`, a train's or a planetary stage's meshes
:func:`rate_train_spectrum`, Palmgren–Miner on the rating's S–N lines
:class:`SNCurve`) lives here too. What a user reaches for first (``rate``,
``pitting_rating``, ``bending_rating``, the results, the settings and material classes, the
geometries) is re-exported at :mod:`jaxgear`'s top level; the rest is reached as
``jaxgear.rating.X``.
"""

from ._bending import (
    ToothFormFactors as ToothFormFactors,
    member_form as member_form,
    section_factors as section_factors,
    tooth_form_factors as tooth_form_factors,
)
from ._factors import (
    LoadFactors as LoadFactors,
    face_load_factor as face_load_factor,
    iso6336_load_factors as iso6336_load_factors,
    transverse_factor_limits as transverse_factor_limits,
    transverse_load_factor as transverse_load_factor,
)
from ._geometry import (
    AbstractRatingGeometry as AbstractRatingGeometry,
    RatingGeometry as RatingGeometry,
    TracedTeethRatingGeometry as TracedTeethRatingGeometry,
)
from ._internal import (
    AbstractRootSection as AbstractRootSection,
    GivenRootSection as GivenRootSection,
    InternalRatingGeometry as InternalRatingGeometry,
    ShaperCutterSection as ShaperCutterSection,
    SubstituteRack as SubstituteRack,
)
from ._iso6336 import (
    FACTOR_CLAUSES as FACTOR_CLAUSES,
    AbstractEdition as AbstractEdition,
    BendingRating as BendingRating,
    Edition2006 as Edition2006,
    Edition2019 as Edition2019,
    PittingRating as PittingRating,
    factor_clause as factor_clause,
)
from ._load_spectrum import (
    LoadSpectrum as LoadSpectrum,
    SNCurve as SNCurve,
    SpectrumRating as SpectrumRating,
    miner_damage as miner_damage,
    rate_spectrum as rate_spectrum,
    rate_train_spectrum as rate_train_spectrum,
    spectrum_safety as spectrum_safety,
)
from ._material import (
    AbstractTreatment as AbstractTreatment,
    CaseHardened as CaseHardened,
    Nitrided as Nitrided,
    PairTreatment as PairTreatment,
    ThroughHardened as ThroughHardened,
)
from ._measured import (
    EXTENDED_CONTACT as EXTENDED_CONTACT,
    MESH_SPRINGS as MESH_SPRINGS,
    THEORETICAL_CONTACT as THEORETICAL_CONTACT,
    MeasuredFactor as MeasuredFactor,
    contact_model as contact_model,
    dynamic_factor_at as dynamic_factor_at,
    planet_dynamic_factor as planet_dynamic_factor,
    planet_dynamic_factors as planet_dynamic_factors,
    planet_face_factors as planet_face_factors,
    planet_transverse_factor as planet_transverse_factor,
    with_load_sharing as with_load_sharing,
    with_measured as with_measured,
)
from ._rate import (
    Rating as Rating,
    bending_rating as bending_rating,
    load_factors as load_factors,
    pitting_rating as pitting_rating,
    rate as rate,
)
from ._root_stress import RootStressMap as RootStressMap, root_stress_map as root_stress_map
from ._settings import (
    RATING_RANGES as RATING_RANGES,
    GearAccuracy as GearAccuracy,
    GivenFactors as GivenFactors,
    Lubrication as Lubrication,
    OperatingPoint as OperatingPoint,
    RatingMaterial as RatingMaterial,
    RatingSettings as RatingSettings,
    ToothLoading as ToothLoading,
)
from ._standard import AbstractRatingStandard as AbstractRatingStandard
