"""fem_prep: offline finite-element pre-processing of flexible gear bodies.

NumPy/SciPy/scikit-fem only (never imports JAX).  A body file (TOML, see ``docs/fem_prep.md``)
describes a thin-rimmed/-webbed gear body; fem_prep meshes it with quadratic hexahedra, assembles
K, M and the centrifugal load, condenses it on the rim nodes under the teeth and the bearing
nodes (Guyan, Craig-Bampton or Herting, seed (2.3)-(2.5)), analyses its modes (nodal diameters,
seed (3.2), resonance orders (3.9)) and writes a versioned ``.npz``, a ``.vtu`` and a
``summary.json``.  Arrays are NumPy, SI units, node coordinates ``(n, 3)``.
"""

from ._assemble import Operators as Operators
from ._assemble import assemble_operators as assemble_operators
from ._body import Body as Body
from ._cli import add_build_arguments as add_build_arguments
from ._cli import run_build as run_build
from ._body import embedded_bodies as embedded_bodies
from ._body import load_body as load_body
from ._body import parse_body as parse_body
from ._condense import Condensed as Condensed
from ._condense import MasterSet as MasterSet
from ._condense import condense as condense
from ._condense import couple_bearings as couple_bearings
from ._condense import frequency_error_vs_modes as frequency_error_vs_modes
from ._condense import select_masters as select_masters
from ._io import FORMAT_VERSION as FORMAT_VERSION
from ._io import CondensedBody as CondensedBody
from ._io import build as build
from ._io import cache_dir as cache_dir
from ._io import load_condensed as load_condensed
from ._io import save_condensed as save_condensed
from ._io import summary_dict as summary_dict
from ._io import write_vtu as write_vtu
from ._mesh import BodyMesh as BodyMesh
from ._mesh import mesh_body as mesh_body
from ._modal import ModeFamily as ModeFamily
from ._modal import critical_speeds as critical_speeds
from ._modal import identify_modes as identify_modes
from ._modal import nodal_diameter_spectrum as nodal_diameter_spectrum
from ._modal import resonance_orders as resonance_orders
from ._prepare import Prepared as Prepared
from ._prepare import prepare as prepare
from ._solver import factorize as factorize
from ._solver import shift_invert_modes as shift_invert_modes

__version__ = "0.1.0"
