"""Rolling bearings from their geometry: load distribution, stiffness, life and tones.

The bearing kinds are classes behind one contract (:class:`AbstractRollingBearing`):
:class:`DeepGrooveBall`, :class:`AngularContactBall`, :class:`CylindricalRoller`,
:class:`TaperedRoller` from catalogue geometry in SI, and :class:`LinearSpring`, the linear
spring the scenes use today. A kind gives the load its rings pass for a displacement
(:meth:`~AbstractRollingBearing.load`, the rolling elements' Hertz loads summed: Jones, Harris &
Kotzalas, Lim & Singh), its 5×5 stiffness at an operating point (``jax.jacfwd``), and
:func:`solve_displacement` the displacement that carries a load. ISO 281's basic rating life
(:func:`rating_life`, :func:`spectrum_life` under a :class:`BearingSpectrum`) and the bearing
tones (:func:`bearing_tones`) complete it; :func:`catalogue` builds a few embedded bearings.
A lumped 3D pair's bearings take them (:class:`jaxgear.scenes.Bearing` ``rolling=``) at the
operating point of its quasi-static solve (:func:`jaxgear.dynamics.bearings_at_operating_point`;
docs/bearings.md, "How it enters the scenes").
"""

from ._catalogue import CATALOGUE as CATALOGUE, catalogue as catalogue
from ._hertz import (
    line_contact_constant as line_contact_constant,
    line_pressure as line_pressure,
    point_contact as point_contact,
    point_contact_constant as point_contact_constant,
)
from ._kinds import (
    AbstractRollingBearing as AbstractRollingBearing,
    AngularContactBall as AngularContactBall,
    CylindricalRoller as CylindricalRoller,
    DeepGrooveBall as DeepGrooveBall,
    LinearSpring as LinearSpring,
    TaperedRoller as TaperedRoller,
)
from ._life import (
    BearingLife as BearingLife,
    BearingSpectrum as BearingSpectrum,
    rating_life as rating_life,
    spectrum_life as spectrum_life,
)
from ._solve import BearingState as BearingState, solve_displacement as solve_displacement
from ._tones import BearingTones as BearingTones, bearing_tones as bearing_tones
