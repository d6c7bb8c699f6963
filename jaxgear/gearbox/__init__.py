"""A gearbox: stages (parallel pairs, planetary stages) in series joined by torsional shafts.

* the torsional chain (:class:`GearboxTorsional`) and its modes (:func:`gearbox_modes`);
* the coupled dynamic model (:func:`gearbox_dynamics`, :func:`gearbox_speed_sweep`,
  :func:`gearbox_coupled_modes`): every stage's contact cells at once in one Newmark run
  (docs/gearbox.md); :class:`GearboxModel` is it as a :class:`jaxgear.dynamics.AbstractDynamicModel`
  (:func:`jaxgear.dynamics.simulate`, :func:`jaxgear.dynamics.speed_sweep`);
* stage kinds added on the stage interface alone: :class:`CompoundPlanetaryStage` (stepped
  planets) in ``_compound``, :class:`LumpedPairGearboxStage` (a parallel pair in lumped 3D
  form: shafts and bearings) in ``_lumped``.
* what an NVH engineer reads off it (:func:`campbell_crossings`, :func:`housing_spectrum`): every
  stage's mesh orders against the coupled modes, and the force spectrum at a housing-fixed point
  (a ring mount, McFadden & Smith 1985; a parallel stage's bearing).
* its gear whine in the frequency domain (:func:`gearbox_whine`): each stage's mesh orders from
  the quasi-periodic balance on the torus of the stages' mesh phases (docs/whine.md).
"""

from ._chain import (
    AbstractGearboxStage as AbstractGearboxStage,
    GearboxModes as GearboxModes,
    GearboxTorsional as GearboxTorsional,
    PairGearboxStage as PairGearboxStage,
    PlanetaryGearboxStage as PlanetaryGearboxStage,
    gearbox_modes as gearbox_modes,
)
from ._compound import (
    CompoundPlanetaryStage as CompoundPlanetaryStage,
    stepped_planet_phases as stepped_planet_phases,
)
from ._coupled import (
    CoupledModes as CoupledModes,
    GearboxDynamics as GearboxDynamics,
    GearboxRun as GearboxRun,
    coordinate_names as coordinate_names,
    coupled_mode_table as coupled_mode_table,
    gearbox_coupled_modes as gearbox_coupled_modes,
    mesh_names as mesh_names,
)
from ._lumped import LumpedPairGearboxStage as LumpedPairGearboxStage
from ._model import (
    OPERATING_RUN as OPERATING_RUN,
    GearboxModel as GearboxModel,
    GearboxPrepared as GearboxPrepared,
    gearbox_dynamics as gearbox_dynamics,
    gearbox_speed_sweep as gearbox_speed_sweep,
)
from ._spectrum import (
    HousingSignals as HousingSignals,
    HousingSpectrum as HousingSpectrum,
    amplitude_spectrum as amplitude_spectrum,
    campbell_crossings as campbell_crossings,
    carrier_frequencies as carrier_frequencies,
    housing_lines as housing_lines,
    housing_signals as housing_signals,
    housing_spectrum as housing_spectrum,
    line_amplitudes as line_amplitudes,
    mesh_frequencies as mesh_frequencies,
    window_share as window_share,
)
from ._whine import gearbox_whine as gearbox_whine
