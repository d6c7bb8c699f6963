"""A gearbox: stages (parallel pairs, planetary stages) in series joined by torsional shafts.

* the torsional chain (:class:`GearboxTorsional`) and its modes (:func:`gearbox_modes`);
* the coupled dynamic model (:func:`gearbox_dynamics`, :func:`gearbox_speed_sweep`,
  :func:`gearbox_coupled_modes`): every stage's contact cells at once in one Newmark run
  (docs/gearbox.md);
* a stage kind added on the stage interface alone: :class:`CompoundPlanetaryStage` (stepped
  planets) in ``_compound``.
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
    gearbox_dynamics as gearbox_dynamics,
    gearbox_speed_sweep as gearbox_speed_sweep,
    mesh_names as mesh_names,
)
