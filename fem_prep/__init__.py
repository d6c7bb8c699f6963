"""fem_prep: offline finite-element pre-processing of flexible gear bodies.

NumPy/SciPy/scikit-fem only (never imports JAX).  A body file (TOML, see ``docs/fem_prep.md``)
describes a thin-rimmed/-webbed gear body; fem_prep meshes it with quadratic hexahedra, assembles
K, M, the centrifugal load and the rotating-frame matrices (gyroscopic, spin softening, stress
stiffening of the centrifugal prestress), condenses it on the rim nodes under the teeth and the bearing
nodes (Guyan, Craig-Bampton or Herting, seed (2.3)-(2.5)), analyses its modes (nodal diameters,
seed (3.2), resonance orders (3.9)) and writes a versioned ``.npz``, a ``.vtu`` and a
``summary.json``.  Arrays are NumPy, SI units, node coordinates ``(n, 3)``.

:mod:`fem_prep.checks` and :mod:`fem_prep.files` (public, JAX-free) hold the input-file checks and
the atomic writers shared with jaxgear's case files; :mod:`fem_prep.schema` is the body-file reader,
the one place where the names in a body file become objects: the element (:class:`Hex20`,
:class:`Hex27`), the bearing coupling (:class:`Rigid`, :class:`Averaging`), the rim coupling
(:class:`Distributing`, :class:`Nodal`), the condensation method (:class:`Guyan`,
:class:`CraigBampton`, :class:`Herting`) and the support (:class:`Bearings`, :class:`Free`).

:mod:`fem_prep.housing` is the gearbox housing: a box or a mesh file, condensed at its bearing
seats (Craig–Bampton up to a cut-off frequency).
"""

from ._assemble import Operators as Operators, assemble_operators as assemble_operators
from ._body_stress import (
    REGIONS as REGIONS,
    BodyStress as BodyStress,
    body_stress as body_stress,
    condensed_body_stress as condensed_body_stress,
    element_stresses as element_stresses,
    full_displacement as full_displacement,
    write_stress_vtu as write_stress_vtu,
)
from ._body import (
    Body as Body,
    Condensation as Condensation,
    Material as Material,
    MeshSettings as MeshSettings,
)
from ._condense import (
    Condensed as Condensed,
    CraigBampton as CraigBampton,
    Guyan as Guyan,
    Herting as Herting,
    RotatingOperators as RotatingOperators,
    condense as condense,
    frequency_error_vs_modes as frequency_error_vs_modes,
)
from ._couplings import (
    Averaging as Averaging,
    Distributing as Distributing,
    MasterSet as MasterSet,
    Nodal as Nodal,
    Rigid as Rigid,
    couple_masters as couple_masters,
    select_masters as select_masters,
)
from ._elements import Hex20 as Hex20, Hex27 as Hex27
from ._internal_tooth import (
    InternalToothForm as InternalToothForm,
    ShaperFillet as ShaperFillet,
    generate_internal_tooth as generate_internal_tooth,
)
from ._internal_fe import DEFAULT_RING_DEPTH as DEFAULT_RING_DEPTH  # registers the ring's FE
from ._io import (
    FORMAT_VERSION as FORMAT_VERSION,
    CondensedBody as CondensedBody,
    build as build,
    cache_dir as cache_dir,
    cache_key as cache_key,
    condensed as condensed,
    load_condensed as load_condensed,
    save_condensed as save_condensed,
    summary_dict as summary_dict,
    write_vtu as write_vtu,
)
from ._mesh import BodyMesh as BodyMesh, mesh_body as mesh_body
from ._modal import (
    ModeFamily as ModeFamily,
    critical_speeds as critical_speeds,
    identify_modes as identify_modes,
    nodal_diameter_spectrum as nodal_diameter_spectrum,
    resonance_orders as resonance_orders,
)
from ._prepare import Bearings as Bearings, Free as Free, Prepared as Prepared, prepare as prepare
from ._rim import RimFit as RimFit, rim_fit as rim_fit
from ._ring import (
    BoltedFlange as BoltedFlange,
    ElasticFoundation as ElasticFoundation,
    FreeRing as FreeRing,
    PreparedRing as PreparedRing,
    RingBody as RingBody,
    mesh_ring as mesh_ring,
    mode_nodal_diameter as mode_nodal_diameter,
    prepare_ring as prepare_ring,
    ring_master_compliance as ring_master_compliance,
    thin_ring_frequency as thin_ring_frequency,
    write_ring_vtu as write_ring_vtu,
)
from ._ring_stations import (
    RingStations as RingStations,
    embedded_ring_text as embedded_ring_text,
    embedded_rings as embedded_rings,
    load_ring_body as load_ring_body,
    ring_craig_bampton as ring_craig_bampton,
    ring_interior_modes as ring_interior_modes,
    ring_nd_frequencies as ring_nd_frequencies,
    ring_station_mass as ring_station_mass,
    ring_stations as ring_stations,
)
from ._root_stress import (
    ClampedBore as ClampedBore,
    FilletInfluence as FilletInfluence,
    FilletStress as FilletStress,
    NormalSection as NormalSection,
    PlaneStrainStress as PlaneStrainStress,
    RimSupport as RimSupport,
    RingSegment as RingSegment,
    RootSection as RootSection,
    TransverseSection as TransverseSection,
    WebbedRim as WebbedRim,
    fillet_influence as fillet_influence,
    fillet_stress as fillet_stress,
    plane_strain_stress as plane_strain_stress,
)
from ._root_stress_cache import cached_fillet_influence as cached_fillet_influence
from ._solver import (
    BlockLanczos as BlockLanczos,
    CholmodFactor as CholmodFactor,
    EigenSolver as EigenSolver,
    Lanczos as Lanczos,
    PardisoFactor as PardisoFactor,
    SolverError as SolverError,
    SolverWarning as SolverWarning,
    SparseFactor as SparseFactor,
    SupernodalFactor as SupernodalFactor,
    eigenvalue_count as eigenvalue_count,
    factorize as factorize,
    shift_invert_modes as shift_invert_modes,
)
from ._tooth_fe import (
    SectorModel as SectorModel,
    ToothCompliance as ToothCompliance,
    mesh_sector as mesh_sector,
    plane_strain_point_loads as plane_strain_point_loads,
    tooth_compliance as tooth_compliance,
)
from ._tooth_profile import (
    CircularFillet as CircularFillet,
    FilletForm as FilletForm,
    InternalCircularFillet as InternalCircularFillet,
    InternalToothProfile as InternalToothProfile,
    ToothProfile as ToothProfile,
    TrochoidFillet as TrochoidFillet,
    tooth_profile as tooth_profile,
)
from . import housing as housing
from .checks import SchemaError as SchemaError
from .cli import add_build_arguments as add_build_arguments, main as main, run_build as run_build
from .schema import (
    embedded_bodies as embedded_bodies,
    embedded_body_text as embedded_body_text,
    load_body as load_body,
    parse_body as parse_body,
)
from .tooth_form import (
    InternalToothGeometry as InternalToothGeometry,
    ShaperCutter as ShaperCutter,
    ToothForm as ToothForm,
    ToothGeometry as ToothGeometry,
    generate_tooth as generate_tooth,
)

__version__ = "0.1.0"
