"""The small housed cases the housing and acoustics tests share: a soft box round the
accessory-spur pair (E = 7 GPa, coarse 40 mm Tet4 cells: condensed in a few seconds) as a case
file's ``[housing]``, a short ``[whine]`` (3 speeds, 2 harmonics), and the case written with
them (slices reduced to 4)."""

from __future__ import annotations

import jaxgear.io as jio

__all__ = ["HOUSING_TABLE", "WHINE_TABLE", "housed_case"]

# a soft box (E = 7 GPa) round the accessory-spur pair, coarse Tet4 cells (a few seconds)
HOUSING_TABLE = """
[housing]
width_mm = 250.0
height_mm = 160.0
wall_thickness_mm = 10.0
bore_diameter_mm = 50.0
mesh_size_mm = 40.0
element = "tet4"
youngs_modulus_GPa = 7.0
density_kg_m3 = 2700.0
cutoff_Hz = 6000.0
loss_factor = 0.0
[housing.points_mm]
top = [50.0, 80.0, 0.0]
"side wall" = [175.0, 0.0, 20.0]
"""

WHINE_TABLE = """
[whine]
speed_min_rad_s = 40.0
speed_max_rad_s = 160.0
speeds = 3
harmonics = 2
positions_per_period = 16
"""


def housed_case(tmp_path, table=HOUSING_TABLE, whine="", damping=None, extra=""):
    """The accessory-spur case (4 slices) with ``table``, ``whine`` and ``extra`` appended
    (``damping``: the ``[scene.damping]`` body instead of the composite model), written to
    ``tmp_path/housed.toml`` and loaded."""
    text = jio.embedded_case_text("accessory-spur").replace("slices = 40", "slices = 4")
    if damping is not None:
        text = text.replace('[scene.damping]\nmodel = "composite"', f"[scene.damping]\n{damping}")
    path = tmp_path / "housed.toml"
    path.write_text(text + table + whine + extra)
    return jio.load_case(str(path))
