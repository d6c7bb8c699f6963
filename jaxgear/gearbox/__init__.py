"""A gearbox: stages (parallel pairs, planetary stages) in series joined by torsional shafts.

* the torsional chain (:class:`GearboxTorsional`) and its modes (:func:`gearbox_modes`);
* the coupled dynamic model (:func:`gearbox_dynamics`, :func:`gearbox_speed_sweep`,
  :func:`gearbox_coupled_modes`): every stage's contact cells at once in one Newmark run
  (docs/gearbox.md).
"""

from ._chain import (
    AbstractGearboxStage as AbstractGearboxStage,
    GearboxModes as GearboxModes,
    GearboxTorsional as GearboxTorsional,
    PairGearboxStage as PairGearboxStage,
    PlanetaryGearboxStage as PlanetaryGearboxStage,
    gearbox_modes as gearbox_modes,
)
