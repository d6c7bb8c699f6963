"""Sound radiation from a vibrating surface (``docs/acoustics.md``): the exterior boundary-element
solve on a closed surface (bempp-cl, Burton–Miller against the irregular frequencies), the
Rayleigh integral for a flat panel in a rigid baffle, the pressure at field points
(microphones), and the radiation resistance matrix R per frequency (W = vᴴ R v), built once and
cached for :mod:`jaxgear.acoustics` to evaluate the power and its gradient in JAX.

NumPy/SciPy/bempp-cl; never imports JAX.
"""

from ._bem import (
    BEMBackend as BEMBackend,
    BurtonMiller as BurtonMiller,
    Direct as Direct,
    Formulation as Formulation,
    Numba as Numba,
    OpenCL as OpenCL,
    bem_field_pressure as bem_field_pressure,
    bem_field_transfer as bem_field_transfer,
    bem_impedance as bem_impedance,
    bem_operators as bem_operators,
    default_backend as default_backend,
)
from ._rayleigh import (
    rayleigh_pressure as rayleigh_pressure,
    rayleigh_resistance as rayleigh_resistance,
    rayleigh_transfer as rayleigh_transfer,
)
from ._resistance import (
    BEM as BEM,
    ERP as ERP,
    RADIATION_FORMAT as RADIATION_FORMAT,
    RadiationMethod as RadiationMethod,
    RadiationResistance as RadiationResistance,
    Rayleigh as Rayleigh,
    radiation_resistance as radiation_resistance,
)
from ._surface import (
    AIR as AIR,
    Fluid as Fluid,
    RadiatingSurface as RadiatingSurface,
    box_surface as box_surface,
    disc_panel as disc_panel,
    rectangular_panel as rectangular_panel,
    sphere_surface as sphere_surface,
)
