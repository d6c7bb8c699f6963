"""The housings the housing and acoustics tests share: a soft box round the accessory-spur pair
(E = 7 GPa, coarse 40 mm Tet4 cells: condensed in a few seconds) as a case file's ``[housing]``,
a short ``[whine]`` (3 speeds, 2 harmonics) and the case written with them (slices reduced to
4); and, for the one-way path built in Python, an aluminium box round a pair of centre distance
a with its seats (the pinion's bearings on seats 0 and 1, the gear's on 2 and 3) and the
rotation from the lumped scene's axes to the box's."""

from __future__ import annotations

import fem_prep
import jaxgear.io as jio
from fem_prep.housing import Bore, Foot, HousingBox

__all__ = [
    "ALUMINIUM",
    "HOUSING_BOX",
    "HOUSING_TABLE",
    "PLANETARY_BOX",
    "ROTATION",
    "WHINE_TABLE",
    "accessory_box",
    "housed_case",
    "housed_train",
    "one_way_seats",
]

ALUMINIUM = fem_prep.Material(70e9, 0.33, 2700.0)
#: the lumped scene's axes to the box's: z along the shafts (the box's y), x between the
#: centres (its x)
ROTATION = ((1.0, 0.0, 0.0), (0.0, 0.0, 1.0), (0.0, 1.0, 0.0))

#: the box of [housing] round the accessory-spur pair: a soft one (E = 7 GPa), coarse Tet4
#: cells (a few seconds to condense); its cut-off and loss factor follow it
HOUSING_BOX = """
[housing]
width_mm = 250.0
height_mm = 160.0
wall_thickness_mm = 10.0
bore_diameter_mm = 50.0
mesh_size_mm = 40.0
element = "tet4"
youngs_modulus_GPa = 7.0
density_kg_m3 = 2700.0
"""

#: that box undamped, condensed to 6 kHz, with two named points
HOUSING_TABLE = HOUSING_BOX + """cutoff_Hz = 6000.0
loss_factor = 0.0
[housing.points_mm]
top = [50.0, 80.0, 0.0]
"side wall" = [175.0, 0.0, 20.0]
"""

#: a 500 x 500 x 200 mm box of 10 mm walls round a planetary stage's axis, a 300 mm bore in
#: each end wall, coarse Tet4 cells; its Young's modulus {E} (GPa) and cut-off {fc} (Hz) to fill
PLANETARY_BOX = """
[housing]
width_mm = 500.0
height_mm = 500.0
wall_thickness_mm = 10.0
length_mm = 200.0
bore_diameter_mm = 300.0
mesh_size_mm = 60.0
element = "tet4"
youngs_modulus_GPa = {E}
cutoff_Hz = {fc}
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


def housed_train(tmp_path, loss_factor=0.0, extra=""):
    """The lumped 3D idler train of tests/_kinds.py (20 → 30 → 24 teeth, 2 slices, three
    shafts on six bearings; its [modifications] a tip relief common to every gear), undamped
    ([scene.damping] model "none"), in a 200 x 200 mm box of HOUSING_TABLE's material, 27 mm
    bores, 20 mm Tet4 cells, cut-off 6 kHz, ``loss_factor``, no named points, with WHINE_TABLE
    and ``extra`` appended, written to ``tmp_path/train.toml`` and loaded."""
    from _kinds import KINDS

    table = (HOUSING_TABLE.replace("width_mm = 250.0", "width_mm = 200.0")
             .replace("height_mm = 160.0", "height_mm = 200.0")
             .replace("bore_diameter_mm = 50.0", "bore_diameter_mm = 27.0")
             .replace("mesh_size_mm = 40.0", "mesh_size_mm = 20.0")
             .replace("loss_factor = 0.0", f"loss_factor = {loss_factor!r}"))
    table = table[: table.index("[housing.points_mm]")]
    path = tmp_path / "train.toml"
    path.write_text(KINDS["train-lumped3d"] + '[scene.damping]\nmodel = "none"\n' + table
                    + WHINE_TABLE + extra)
    return jio.load_case(str(path))


def accessory_box(a: float) -> HousingBox:
    """A 0.3 x 0.2 x 0.2 m box (8 mm walls) round a pair of centre distance ``a`` (m): the
    pinion's bearings in the walls y = 0 and 0.2 m at (x, z) = (0.08, 0.1) m, the gear's at
    (0.08 + a, 0.1) m (seats 0, 1 and 2, 3), two feet along its ends."""
    return HousingBox(
        0.3, 0.2, 0.2, 0.008,
        bores=(Bore("y-", (0.08, 0.1), 0.025), Bore("y+", (0.08, 0.1), 0.025),
               Bore("y-", (0.08 + a, 0.1), 0.03), Bore("y+", (0.08 + a, 0.1), 0.03)),
        feet=(Foot((0.0, 0.05), (0.0, 0.2)), Foot((0.25, 0.3), (0.0, 0.2))),
    )


def one_way_seats(names) -> tuple[int, ...]:
    """The seat of each bearing force component of a lumped pair (its ``reaction_names``) on a
    box whose pinion bearings sit on seats 0, 1 and the gear's on 2, 3 (the bearing at z = 0 on
    the first of each)."""
    return tuple((0 if "z=0mm" in n else 1) + (2 if n.startswith("gear") else 0) for n in names)


def two_seat_housing(modes: int = 3, seed: int = 3):
    """A small synthetic condensed housing: two seats at z = ∓50 mm (``front``, ``back``) and
    ``modes`` modal coordinates, its stiffness a random symmetric positive definite matrix
    (1e9 scale), unit mass, 1e-3 stiffness-proportional damping; returns (housing, its
    coordinate count)."""
    import numpy as np

    from jaxgear.scenes import Housing

    rng = np.random.default_rng(seed)
    h = 6 * 2 + modes
    a = rng.standard_normal((h, h))
    K = 1e9 * (a @ a.T + h * np.eye(h))
    housing = Housing(K=K, M=np.eye(h), C=1e-3 * K, seat_positions=(
        (0.0, 0.0, -0.05), (0.0, 0.0, 0.05)), seat_names=("front", "back"),
        rotation=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)))
    return housing, h
