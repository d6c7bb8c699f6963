"""Radiated noise in JAX (``docs/acoustics.md``): the sound power W = Re(vᴴ R v) of a surface's
normal velocity from a cached radiation resistance matrix R (:mod:`fem_prep.acoustics`: the BEM
or the Rayleigh integral), its low-rank form over the radiation modes, the radiation
efficiency, sound power and pressure levels, and the A weighting of IEC 61672-1, all
differentiable.
"""

from ._power import (
    P_REF as P_REF,
    W_REF as W_REF,
    radiated_power as radiated_power,
    radiated_power_low_rank as radiated_power_low_rank,
    radiation_efficiency as radiation_efficiency,
    sound_power_level as sound_power_level,
    sound_pressure_level as sound_pressure_level,
)
from ._weighting import (
    a_weighted_power_level as a_weighted_power_level,
    a_weighting as a_weighting,
    level_sum as level_sum,
)
