"""A gearbox housing as a flexible body: meshed (a parametric box by the structured mesher or by
gmsh, or a mesh file read by meshio), its bearing seats coupled to 6-DOF master nodes, its bolted
feet clamped, and condensed by Craig–Bampton at the seats with the interior modes up to a cut-off
frequency (``docs/fem_prep.md``, "Housing").

NumPy/SciPy/scikit-fem (gmsh optional: ``pip install 'jaxgear[housing]'``); never imports JAX.
"""

from ._condense import (
    CondensedHousing as CondensedHousing,
    PreparedHousing as PreparedHousing,
    condensed_housing as condensed_housing,
    housing_cutoff_hz as housing_cutoff_hz,
    prepare_housing as prepare_housing,
    write_housing_vtu as write_housing_vtu,
)
from ._estimate import (
    MAX_HOUSING_MODES as MAX_HOUSING_MODES,
    BoxEstimate as BoxEstimate,
    box_modes_below as box_modes_below,
    check_housing_modes as check_housing_modes,
    condensation_bytes as condensation_bytes,
    condensation_seconds as condensation_seconds,
    estimate_box as estimate_box,
)
from ._fit import (
    BoreLimit as BoreLimit,
    bore_limits as bore_limits,
    cavity_room as cavity_room,
)
from ._mesh import (
    Bore as Bore,
    Foot as Foot,
    HousingBox as HousingBox,
    HousingMesh as HousingMesh,
    Seat as Seat,
    Tet4 as Tet4,
    Tet10 as Tet10,
    box_skin_edge as box_skin_edge,
    mesh_box as mesh_box,
    mesh_box_gmsh as mesh_box_gmsh,
    mesh_plate as mesh_plate,
    read_housing_mesh as read_housing_mesh,
)
from ._surface import (
    HousingSurface as HousingSurface,
    RadiatingSkin as RadiatingSkin,
    closed_outer_surface as closed_outer_surface,
    outer_surface as outer_surface,
    write_housing_ods_vtu as write_housing_ods_vtu,
)
