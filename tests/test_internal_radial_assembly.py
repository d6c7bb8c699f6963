"""The radial-assembly ("trimming") margin of an internal pair (InternalGearPair.
radial_assembly_margin): against the published limits of SDP/SI's Table 5-3a (Elements of Metric
Gear Technology, D785; KHK's Gear Technical Reference gives the same table), which lists, for a
20° pinion-type cutter of z_c teeth without profile shift cutting a standard internal gear, the
fewest ring teeth z_2 free of trimming interference; the table's cutter and ring are built as
public internal pairs."""

import math

import pytest
from _planetary_stage import geometry

import jaxgear as jg

ALPHA = math.radians(20.0)
MODULE = 1e-3

# SDP/SI D785 Table 5-3a (α = 20°, x_c = x_2 = 0): cutter teeth z_c -> the smallest z_2
TABLE_5_3A = {
    15: 34, 16: 34, 17: 35, 18: 36, 19: 37, 20: 38, 21: 39, 22: 40, 24: 42, 25: 43, 27: 45,
    28: 46, 30: 48, 31: 49, 32: 50, 33: 51, 34: 52, 35: 53, 38: 56, 40: 58, 42: 60, 44: 62,
    48: 66, 50: 68, 56: 74, 60: 78, 64: 82, 66: 84, 80: 98, 96: 114, 100: 118,
}  # fmt: skip


def _cutter_in_ring(z_c: int, z_2: int) -> jg.InternalGearPair:
    """The table's cutter (z_c teeth, addendum 1.25 m: its tip cuts the ring's root) in a
    standard ring of z_2 teeth (addendum 1 m; dedendum 1.3 m, clear of the cutter's tip), at the
    standard centre distance (α_w = α). The cutter's dedendum puts its form circle on its base
    circle (the rack-generation undercut limit, ISO 21771), so that the ring's tip may meet its
    whole involute: the cutter is a tool, its root plays no part, and the margin depends on
    neither dedendum."""
    form = z_c / 2 * math.sin(ALPHA) ** 2  # h = r sin² α: roll 0 at the form circle
    fillet = 0.25
    cutter = jg.Member(
        z_c,
        addendum_coeff=1.25,
        dedendum_coeff=form + fillet * (1 - math.sin(ALPHA)) - 1e-9,
        fillet_radius_coeff=fillet,
        face_width=0.01,
    )
    ring = jg.Member(-z_2, addendum_coeff=1.0, dedendum_coeff=1.3, face_width=0.01)
    return jg.InternalGearPair(cutter, ring, MODULE, ALPHA)


def _involute_interference(z_c: int, z_2: int) -> bool:
    """KHK's condition for an internal pair free of involute interference fails: z_c/z_2 <
    1 − tan α_a2/tan α_w (the ring's tip meets the cutter's line of action inside its base
    circle), with the ring's tip radius z_2/2 − 1 and base radius z_2/2 cos α (in modules),
    α_w = α."""
    tan_a2 = math.sqrt((z_2 / 2 - 1) ** 2 / (z_2 / 2 * math.cos(ALPHA)) ** 2 - 1)
    return z_c / z_2 < 1 - tan_a2 / math.tan(ALPHA)


@pytest.mark.parametrize("z_c", sorted(TABLE_5_3A))
def test_published_trimming_limits(z_c):
    """The margin is >= 0 at the table's z_2 and < 0 one tooth fewer. The pairs of the smaller
    cutters (z_c <= 22) also have involute interference by KHK's condition: InternalGearPair
    refuses them, so the table is checked through the pair from z_c = 24 on (22 of its 31
    rows)."""
    z_2 = TABLE_5_3A[z_c]
    if _involute_interference(z_c, z_2):
        assert z_c <= 22
        with pytest.raises(ValueError, match="involute interference"):
            _cutter_in_ring(z_c, z_2)
        return
    assert not _involute_interference(z_c, z_2 - 1)
    assert _cutter_in_ring(z_c, z_2).radial_assembly_margin >= 0.0
    assert _cutter_in_ring(z_c, z_2 - 1).radial_assembly_margin < 0.0


def test_the_pair_reports_its_margin_and_is_not_refused():
    """A planetary stage's planet-ring pair (19/17/-53, x 0.3/0.3) can be pushed in radially; a
    pair of 7 teeth difference that passes every check (z1 = 20, ring addendum 0.6 m) cannot,
    and is still built (planets are mounted axially). The summary key is the attribute. The
    operating pressure angle enters the margin (D785 (5-9), (5-10)) only through
    (|z2|/z1 − 1) inv α_w: the same planet-ring pair 20 µm closer (the same radii, a smaller
    α_w) changes it by exactly that."""
    pr = geometry(z_s=19, z_p=17, x_s=0.3, x_p=0.3).planet_ring
    tight = jg.InternalGearPair(
        jg.Member(20, face_width=0.02),
        jg.Member(-27, addendum_coeff=0.6, face_width=0.02),
        2e-3,
        ALPHA,
    )
    for pair, sign in ((pr, 1.0), (tight, -1.0)):
        margin = pair.radial_assembly_margin
        assert pair.summary()["radial_assembly_margin_rad"] == margin
        assert math.copysign(1.0, margin) == sign and abs(margin) > 1e-3
    closer = jg.InternalGearPair(
        pr.pinion, pr.gear, pr.normal_module, pr.normal_pressure_angle,
        center_distance=pr.center_distance - 20e-6,
    )
    assert closer.tip_radii == pr.tip_radii and closer.base_radii == pr.base_radii
    inv = [math.tan(p.operating_pressure_angle) - p.operating_pressure_angle for p in (pr, closer)]
    assert inv[0] - inv[1] > 1e-4
    ratio = -pr.gear.teeth / pr.pinion.teeth
    want = pr.radial_assembly_margin + (ratio - 1) * (inv[1] - inv[0])
    assert closer.radial_assembly_margin == pytest.approx(want, rel=1e-12, abs=1e-15)
