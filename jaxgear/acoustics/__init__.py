"""Acoustics of the gearbox (``docs/acoustics.md``, ``docs/whine.md`` "Housing and ERP"), in JAX
and differentiable: the housing's vibration at its outer surface and its equivalent radiated
power (ERP) from the bearing forces at its seats; the sound power W = Re(vᴴ R v) of a surface's
normal velocity from a cached radiation resistance matrix R (:mod:`fem_prep.acoustics`: the BEM
or the Rayleigh integral), its low-rank form over the radiation modes, the radiation efficiency,
sound power and pressure levels, the power and the microphones' pressure at any frequency of a
band from R at a grid of frequencies (log-log interpolation), a surface's radiated sound over
speeds and orders (:func:`radiated_sound_power`), and the A weighting of IEC 61672-1. The
housing's geometry and condensation come from :mod:`fem_prep.housing` (NumPy), loaded by the
caller.
"""

from ._band import (
    mean_square_pressure_at as mean_square_pressure_at,
    radiated_intensity_at as radiated_intensity_at,
    radiated_power_at as radiated_power_at,
)
from ._erp import (
    HousingAcoustics as HousingAcoustics,
    HousingResponse as HousingResponse,
    erp as erp,
    housing_acoustics as housing_acoustics,
    housing_response as housing_response,
    housing_vibration as housing_vibration,
    seat_forces as seat_forces,
    total_level as total_level,
)
from ._power import (
    P_REF as P_REF,
    W_REF as W_REF,
    radiated_power as radiated_power,
    radiated_power_low_rank as radiated_power_low_rank,
    radiation_efficiency as radiation_efficiency,
    sound_power_level as sound_power_level,
    sound_pressure_level as sound_pressure_level,
)
from ._sound import (
    SoundPower as SoundPower,
    radiated_sound_power as radiated_sound_power,
)
from ._weighting import (
    a_weighted_power_level as a_weighted_power_level,
    a_weighting as a_weighting,
    level_sum as level_sum,
)
