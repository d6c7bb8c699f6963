"""Acoustics of the gearbox: the housing's vibration at its outer surface and the equivalent
radiated power (ERP) from the bearing forces at its seats (docs/whine.md, "Housing and ERP").

JAX, differentiable; the housing's geometry and condensation come from
:mod:`fem_prep.housing` (NumPy), loaded lazily by the caller.
"""

from ._erp import (
    HousingAcoustics as HousingAcoustics,
    HousingResponse as HousingResponse,
    erp as erp,
    erp_db as erp_db,
    housing_acoustics as housing_acoustics,
    housing_response as housing_response,
    seat_forces as seat_forces,
    total_level as total_level,
)
