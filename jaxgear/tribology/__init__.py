"""Tribology of the mesh: the elastohydrodynamic film along the path of contact, the specific
film thickness λ, the tooth friction and the sliding power loss and efficiency, all from
jaxgear's own line loads (:func:`jaxgear.quasi_static`) and differentiable.

The lubricant (:class:`Lubricant`: Walther's viscosity–temperature line through ν₄₀ and ν₁₀₀,
density, pressure–viscosity coefficient), the film formula as a kind (:class:`DowsonHigginson`,
:class:`PanHamrock`, :class:`Grubin`), the friction law as a kind (:class:`Schlenk` as ISO/TR
14179-2 gives it, :class:`GivenFriction`), Ohlendorf's tooth loss factor
(:func:`ohlendorf_loss_factor`) and the mesh's film and loss along the path of contact
(:func:`mesh_tribology` → :class:`MeshTribology`); Blok's flash temperature along the path and
the scuffing safety factors of ISO/TS 6336-20 and -21 (:func:`mesh_scuffing` →
:class:`MeshScuffing`; the flash temperature alone: :func:`mesh_flash_temperature`), and
their closed form from the geometry alone with the TS's load sharing and μ_mC (:func:`ts_scuffing`
→ :class:`TSScuffing`, the sizing's); the
micropitting safety factor of ISO/TS 6336-22 (:func:`mesh_micropitting` →
:class:`MeshMicropitting`); the power loss and efficiency of a gear train, a planetary stage and a
gearbox from their meshes' own sliding loss, by a series power flow (:func:`train_efficiency`,
:func:`planetary_efficiency`, :func:`gearbox_efficiency` → :class:`PowerFlow`).
docs/tribology.md.
"""

from ._efficiency import (
    PowerFlow as PowerFlow,
    gearbox_efficiency as gearbox_efficiency,
    planetary_efficiency as planetary_efficiency,
    power_flow as power_flow,
    train_efficiency as train_efficiency,
)
from ._film import (
    AbstractFilmFormula as AbstractFilmFormula,
    DowsonHigginson as DowsonHigginson,
    FilmThickness as FilmThickness,
    Grubin as Grubin,
    PanHamrock as PanHamrock,
    film_thickness as film_thickness,
)
from ._flash import (
    STEEL_THERMAL_CONTACT_COEFFICIENT as STEEL_THERMAL_CONTACT_COEFFICIENT,
    AbstractBulkTemperature as AbstractBulkTemperature,
    FlashBulkTemperature as FlashBulkTemperature,
    GivenBulkTemperature as GivenBulkTemperature,
    MeshScuffing as MeshScuffing,
    ScuffingLimits as ScuffingLimits,
    blok_flash_temperature as blok_flash_temperature,
    fzg_integral_scuffing_temperature as fzg_integral_scuffing_temperature,
    fzg_pinion_torque as fzg_pinion_torque,
    fzg_scuffing_temperature as fzg_scuffing_temperature,
    mesh_flash_temperature as mesh_flash_temperature,
    mesh_scuffing as mesh_scuffing,
    thermal_contact_coefficient as thermal_contact_coefficient,
    ts_flash_temperature as ts_flash_temperature,
)
from ._loss import (
    AbstractFriction as AbstractFriction,
    GivenFriction as GivenFriction,
    Schlenk as Schlenk,
    ohlendorf_formula as ohlendorf_formula,
    ohlendorf_loss_factor as ohlendorf_loss_factor,
    pitch_point_roll as pitch_point_roll,
)
from ._lubricant import Lubricant as Lubricant
from ._mesh import MeshTribology as MeshTribology, mesh_tribology as mesh_tribology
from ._micropitting import (
    MeshMicropitting as MeshMicropitting,
    TSMicropittingFilm as TSMicropittingFilm,
    figure_a1_permissible_film as figure_a1_permissible_film,
    mesh_micropitting as mesh_micropitting,
    micropitting_bulk_temperature as micropitting_bulk_temperature,
    pressure_viscosity_temperature_factor as pressure_viscosity_temperature_factor,
)
from ._ts_scuffing import (
    SCUFFING_POINTS as SCUFFING_POINTS,
    TSScuffing as TSScuffing,
    helical_load_factor as helical_load_factor,
    ts_friction_coefficient as ts_friction_coefficient,
    ts_load_sharing as ts_load_sharing,
    ts_scuffing as ts_scuffing,
)
