"""fem_prep: offline finite-element pre-processing of flexible gear bodies.

NumPy/SciPy/scikit-fem only (never imports JAX).  A body file (TOML, see ``docs/fem_prep.md``)
describes a thin-rimmed/-webbed gear body; fem_prep meshes it with quadratic hexahedra, assembles
K, M, the centrifugal load and the rotating-frame matrices (gyroscopic, spin softening, stress
stiffening of the centrifugal prestress), condenses it on the rim nodes under the teeth and the bearing
nodes (Guyan, Craig-Bampton or Herting, seed (2.3)-(2.5)), analyses its modes (nodal diameters,
seed (3.2), resonance orders (3.9)) and writes a versioned ``.npz``, a ``.vtu`` and a
``summary.json``.  Arrays are NumPy, SI units, node coordinates ``(n, 3)``.

:mod:`fem_prep.schema` (public, JAX-free) holds the input-file checks and atomic writers shared with
jaxgear's case files.
"""

from ._assemble import Operators as Operators, assemble_operators as assemble_operators
from ._body import (
    Body as Body,
    Material as Material,
    embedded_bodies as embedded_bodies,
    embedded_body_text as embedded_body_text,
    load_body as load_body,
    parse_body as parse_body,
)
from ._condense import (
    Condensed as Condensed,
    MasterSet as MasterSet,
    condense as condense,
    couple_masters as couple_masters,
    frequency_error_vs_modes as frequency_error_vs_modes,
    select_masters as select_masters,
)
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
from ._prepare import Prepared as Prepared, prepare as prepare
from ._rim import RimFit as RimFit, rim_fit as rim_fit
from ._solver import (
    SolverError as SolverError,
    SolverWarning as SolverWarning,
    factorize as factorize,
    shift_invert_modes as shift_invert_modes,
)
from ._tooth_fe import (
    ToothCompliance as ToothCompliance,
    ToothProfile as ToothProfile,
    mesh_sector as mesh_sector,
    plane_strain_point_loads as plane_strain_point_loads,
    tooth_compliance as tooth_compliance,
    tooth_profile as tooth_profile,
)
from .cli import add_build_arguments as add_build_arguments, main as main, run_build as run_build
from .schema import SchemaError as SchemaError
from .tooth_form import (
    ToothForm as ToothForm,
    ToothGeometry as ToothGeometry,
    generate_tooth as generate_tooth,
)

__version__ = "0.1.0"
