"""The radial-assembly ("trimming") margin of an internal pair (jaxgear._internal.
radial_assembly_margin, the attribute InternalGearPair.radial_assembly_margin): against the
published limits of SDP/SI's Table 5-3a (Elements of Metric Gear Technology, D785; KHK's
Gear Technical Reference gives the same table), which lists, for a 20° pinion-type cutter of
z_c teeth without profile shift cutting a standard internal gear, the fewest ring teeth z_2
free of trimming interference."""

import math

import numpy as np
import pytest
from _planetary_stage import geometry

import jaxgear as jg
from jaxgear._internal import radial_assembly_margin

ALPHA = math.radians(20.0)

# SDP/SI D785 Table 5-3a (α = 20°, x_c = x_2 = 0): cutter teeth z_c -> the smallest z_2
TABLE_5_3A = {
    15: 34, 16: 34, 17: 35, 18: 36, 19: 37, 20: 38, 21: 39, 22: 40, 24: 42, 25: 43, 27: 45,
    28: 46, 30: 48, 31: 49, 32: 50, 33: 51, 34: 52, 35: 53, 38: 56, 40: 58, 42: 60, 44: 62,
    48: 66, 50: 68, 56: 74, 60: 78, 64: 82, 66: 84, 80: 98, 96: 114, 100: 118,
}  # fmt: skip


def _standard_margin(z_c: int, z_2: int) -> float:
    """The margin at the standard centre distance (module 1, α_w = α): the cutter's tip
    radius z_c/2 + 1.25 (it cuts the ring's root, dedendum 1.25), the ring's z_2/2 - 1."""
    rb = np.array([z_c, z_2]) / 2 * math.cos(ALPHA)
    return radial_assembly_margin(z_c, -z_2, z_c / 2 + 1.25, z_2 / 2 - 1.0, rb[0], rb[1], ALPHA)


@pytest.mark.parametrize("z_c", sorted(TABLE_5_3A))
def test_published_trimming_limits(z_c):
    """The margin is >= 0 at the table's z_2 and < 0 one tooth fewer (every entry but where
    one fewer has no involute at the ring's tip: z_2 - 1 < 34, the table's limit there)."""
    z_2 = TABLE_5_3A[z_c]
    assert _standard_margin(z_c, z_2) >= 0.0
    if (z_2 - 1) / 2 - 1.0 > (z_2 - 1) / 2 * math.cos(ALPHA):
        assert _standard_margin(z_c, z_2 - 1) < 0.0
    else:
        assert z_2 == 34


def test_the_pair_reports_its_margin_and_is_not_refused():
    """The pair's attribute and summary key are the function at its own radii and operating
    pressure angle: a planetary stage's planet-ring pair (19/17/-53, x 0.3/0.3) can be pushed
    in radially; a pair of 7 teeth difference that passes every check (z1 = 20, ring addendum
    0.6 m) cannot, and is still built (planets are mounted axially)."""
    pr = geometry(z_s=19, z_p=17, x_s=0.3, x_p=0.3).planet_ring
    tight = jg.InternalGearPair(
        jg.Member(20, face_width=0.02),
        jg.Member(-27, addendum_coeff=0.6, face_width=0.02),
        2e-3,
        ALPHA,
    )
    for pair, sign in ((pr, 1.0), (tight, -1.0)):
        want = radial_assembly_margin(
            pair.pinion.teeth,
            pair.gear.teeth,
            *pair.tip_radii,
            *pair.base_radii,
            pair.operating_pressure_angle,
        )
        assert pair.radial_assembly_margin == want
        assert pair.summary()["radial_assembly_margin_rad"] == want
        assert math.copysign(1.0, want) == sign and abs(want) > 1e-3
