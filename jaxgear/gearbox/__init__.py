"""A gearbox: stages (parallel pairs, planetary stages) in series joined by torsional shafts.

* the torsional chain (:class:`GearboxTorsional`) and its modes (:func:`gearbox_modes`);
* the coupled dynamic model (:func:`gearbox_dynamics`, :func:`gearbox_speed_sweep`,
  :func:`gearbox_coupled_modes`): every stage's contact cells at once in one Newmark run
  (docs/gearbox.md); :class:`GearboxModel` is it as a :class:`jaxgear.dynamics.AbstractDynamicModel`
  (:func:`jaxgear.dynamics.simulate`, :func:`jaxgear.dynamics.speed_sweep`);
* the stages satisfy the one stage contract, :class:`jaxgear.dynamics.AbstractStage`
  (:class:`PairGearboxStage`, constant springs; a :class:`jaxgear.planetary.PlanetaryModel`
  given its input and output members, :class:`PlanetaryGearboxStage` its constructor in the
  gearbox's argument order; a pair's :class:`jaxgear.dynamics.DynamicModel` given its input
  side, :class:`TorsionalPairGearboxStage` and :class:`LumpedPairGearboxStage` its
  constructors); ``AbstractGearboxStage`` is that contract's former name, served with a
  ``DeprecationWarning``;
* stage kinds added on the stage interface alone: :class:`CompoundPlanetaryStage` (stepped
  planets) in ``_compound``; :class:`LumpedPairGearboxStage` (a parallel pair in lumped 3D
  form: shafts and bearings, the pair's model) in ``_lumped``.
* what an NVH engineer reads off it (:func:`campbell_crossings`, :func:`housing_spectrum`): every
  stage's mesh orders against the coupled modes, and the force spectrum at a housing-fixed point
  (a ring mount, McFadden & Smith 1985; a parallel stage's bearing).
* its gear whine in the frequency domain (:func:`gearbox_whine`): each stage's mesh orders from
  the quasi-periodic balance on the torus of the stages' mesh phases (docs/whine.md).
"""

from ._chain import (
    GearboxModes as GearboxModes,
    GearboxTorsional as GearboxTorsional,
    PairGearboxStage as PairGearboxStage,
    PlanetaryGearboxStage as PlanetaryGearboxStage,
    TorsionalPairGearboxStage as TorsionalPairGearboxStage,
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

#: names that left this package, by their new home (served with a ``DeprecationWarning``)
_RENAMED = {"AbstractGearboxStage": ("jaxgear.dynamics", "AbstractStage")}


def __getattr__(name: str):
    """A renamed name (``_RENAMED``): its object from the new home, with a
    ``DeprecationWarning`` naming it."""
    if name not in _RENAMED:
        raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
    import importlib
    import warnings

    home, new = _RENAMED[name]
    warnings.warn(
        f"jaxgear.gearbox.{name} is {home}.{new} (the one stage contract); the old name will "
        "be removed in the next release",
        DeprecationWarning,
        stacklevel=2,
    )
    return getattr(importlib.import_module(home), new)
