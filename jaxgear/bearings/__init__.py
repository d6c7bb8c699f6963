"""Rolling bearings from their geometry: load distribution, stiffness, life and tones.

The bearing kinds are classes behind one contract (:class:`AbstractRollingBearing`):
:class:`DeepGrooveBall`, :class:`AngularContactBall`, :class:`CylindricalRoller`,
:class:`TaperedRoller`, :class:`SphericalRoller` (double row, self-aligning),
:class:`TaperedRollerPair` (two tapered rows facing both ways, one node) from catalogue
geometry in SI, and :class:`LinearSpring`, the linear
spring the scenes use today. A kind gives the load its rings pass for a displacement
(:meth:`~AbstractRollingBearing.load`, the rolling elements' Hertz loads summed: Jones, Harris &
Kotzalas, Lim & Singh), its 5×5 stiffness at an operating point (``jax.jacfwd``), and
:func:`solve_displacement` the displacement that carries a load. ISO 281's basic and modified
rating life (:func:`rating_life`, :func:`modified_life`; :func:`spectrum_life` and
:func:`spectrum_modified_life` under a :class:`BearingSpectrum`), ISO/TS 16281's reference
rating life from the element loads (:func:`reference_life`, balls and the rollers' laminae;
:func:`spectrum_reference_life` under a load spectrum), the three at a
bearing's operating point (:func:`operating_life`) and the bearing tones
(:func:`bearing_tones`) complete it; :func:`catalogue` builds a few embedded bearings
(:func:`estimated_rollers`, :func:`estimated_balls`: the rules that estimate a roller or ball
set from boundary dimensions).
A lumped 3D pair's bearings take them (:class:`jaxgear.scenes.Bearing` ``rolling=``) at the
operating point of its quasi-static solve (:func:`jaxgear.dynamics.bearings_at_operating_point`;
docs/bearings.md, "How it enters the scenes").
"""

from ._catalogue import (
    CATALOGUE as CATALOGUE,
    catalogue as catalogue,
    estimated_balls as estimated_balls,
    estimated_rollers as estimated_rollers,
)
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
    SphericalRoller as SphericalRoller,
    TaperedRoller as TaperedRoller,
    TaperedRollerPair as TaperedRollerPair,
)
from ._life import (
    ISO281_CONTAMINATION as ISO281_CONTAMINATION,
    ISO281_RELIABILITY as ISO281_RELIABILITY,
    BearingLife as BearingLife,
    BearingSpectrum as BearingSpectrum,
    ModifiedLife as ModifiedLife,
    fatigue_load_limit as fatigue_load_limit,
    life_modification_factor as life_modification_factor,
    modified_life as modified_life,
    rated_viscosity as rated_viscosity,
    rating_life as rating_life,
    reliability_factor as reliability_factor,
    spectrum_life as spectrum_life,
    spectrum_modified_life as spectrum_modified_life,
)
from ._operating import OperatingLife as OperatingLife, operating_life as operating_life
from ._reference import (
    ReferenceLife as ReferenceLife,
    reference_life as reference_life,
    spectrum_reference_life as spectrum_reference_life,
)
from ._solve import BearingState as BearingState, solve_displacement as solve_displacement
from ._tones import BearingTones as BearingTones, bearing_tones as bearing_tones
