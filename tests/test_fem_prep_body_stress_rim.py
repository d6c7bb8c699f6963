"""The thin-rim effect as stress in a condensed body, against ISO 6336-3's rim thickness factor
Y_B = 1.6 ln(2.242 h_t/s_R) (0.5 < s_R/h_t < 1.2; 1 above).

A small webbed wheel (the 30-tooth, m = 2 mm wheel of tests/data/hybrid-test-wheel.toml: root
radius 27.5 mm, tooth depth h_t = 2.25 m = 4.5 mm, a 3 mm web, a 10 mm wide rim) is built by
fem_prep with its rim from r_f − s_R to r_f for several s_R/h_t, condensed (Guyan: exact for
loads on the masters), and loaded at one rim station with the tooth force of the hybrid test
train's idler (90 N·m on the 30 mm pitch radius: F_t = 3000 N, F_r = F_t tan 20°, over the
station's axial masters), the bearing held. The measure is the largest tensile hoop stress of
the rim's elements within 1.5 pitches of the loaded station (element means of the recovered
quadratic field, two elements through the rim): the rim's bending under the tooth, the stress
Y_B stands for at the tooth root. docs/rating.md states the ratios and why they differ from
Y_B's."""

import itertools
import math

import numpy as np
import pytest

from fem_prep import body_stress, parse_body, prepare

H_T_MM = 4.5  # tooth depth of the m = 2 mm wheel (h_a + h_f = 2.25 m)
ROOT_MM = 27.5
F_T = 3000.0  # N: 90 N·m on the 30-tooth wheel's 30 mm pitch radius


def _body(ratio: float, rim_elements: int, circ_mm: float, size_mm: float, axial: int) -> str:
    s_r = ratio * H_T_MM
    return f"""name = "thin-rim-{ratio}"
[body]
bore_radius_mm = 8.0
hub_outer_radius_mm = 12.0
hub_width_mm = 16.0
web_thickness_mm = 3.0
rim_inner_radius_mm = {ROOT_MM - s_r}
rim_outer_radius_mm = {ROOT_MM}
rim_width_mm = 10.0
[[bearings]]
axial_position_mm = 0.0
coupling = "rigid"
width_mm = 16.0
[material]
youngs_modulus_GPa = 210.0
poisson_ratio = 0.3
density_kg_m3 = 7800.0
[mesh]
element = "hex20"
size_mm = {size_mm}
rim_size_mm = {s_r / rim_elements}
circumferential_size_mm = {circ_mm}
[condensation]
method = "guyan"
teeth = 30
axial_master_nodes = {axial}
[modal]
n_frequencies = 1
"""


def rim_hoop_under_a_tooth(ratio, rim_elements=2, circ_mm=3.14, size_mm=3.0, axial=3) -> float:
    """The largest tensile hoop stress (Pa) of the rim elements within 1.5 pitches of the
    loaded rim station (module docstring), of the wheel with s_R/h_t = ``ratio``, ``axial``
    master nodes across the station."""
    p = prepare(parse_body(_body(ratio, rim_elements, circ_mm, size_mm, axial)))
    cond, cp = p.condensed, p.coupled
    column = {int(d): i for i, d in enumerate(cond.master_dofs)}
    e_r = cp.rim_positions[0, 0, :2] / np.hypot(*cp.rim_positions[0, 0, :2])
    e_t = np.array([-e_r[1], e_r[0]])
    force = F_T * e_t - F_T * math.tan(math.radians(20.0)) * e_r  # on the station, N
    f = np.zeros(cond.K.shape[0])
    n_axial = cp.rim_dofs.shape[1]
    for j in range(n_axial):
        for c in (0, 1):
            f[column[int(cp.rim_dofs[0, j, c])]] += force[c] / n_axial
    held = np.isin(cond.master_dofs, cp.bearing_dofs.ravel())
    free = np.ones(f.size, dtype=bool)
    free[: held.size][held] = False
    q = np.zeros(f.size)
    q[free] = np.linalg.solve(cond.K[np.ix_(free, free)], f[free])
    _, s = body_stress(p, q)
    centre = p.mesh.nodes[p.mesh.cells[:, :8]].mean(axis=1)
    angle = np.arctan2(centre[:, 1], centre[:, 0]) - math.atan2(e_r[1], e_r[0])
    angle = (angle + math.pi) % (2 * math.pi) - math.pi
    near = (s.region == 2) & (np.abs(angle) < 1.5 * 2 * math.pi / 30)
    return float(s.hoop[near].max())


def y_b(ratio: float) -> float:
    """ISO 6336-3 method B's rim thickness factor at s_R/h_t = ``ratio``."""
    return max(1.0, 1.6 * math.log(2.242 / ratio))


def test_thin_rim_hoop_stress_rises_as_the_rim_thins():
    """A coarse wheel (one element through the rim, one per pitch around it, 10 mm elsewhere,
    two axial masters per station): the rim's tensile hoop stress under the tooth at
    s_R/h_t = 0.6 is above the one at 1.2 (measured 1.64 times)."""
    thick, thin = (rim_hoop_under_a_tooth(r, 1, 6.28, 10.0, axial=2) for r in (1.2, 0.6))
    assert thick > 0 and thin > 1.3 * thick


#: s_R/h_t of the study, the thick reference rim first, and the rim stress over the one at
#: s_R/h_t = 1.2 (where Y_B is still 1) measured on the 3 mm / two-elements-through-the-rim mesh
RATIOS = (2.0, 1.2, 1.0, 0.8, 0.6)
OVER_1_2 = {2.0: 0.7071, 1.2: 1.0, 1.0: 1.190, 0.8: 1.356, 0.6: 1.580}
MPA = {2.0: 23.4, 1.2: 33.1, 1.0: 39.4, 0.8: 44.9, 0.6: 52.3}  # the rim hoop stresses


@pytest.mark.slow
def test_thin_rim_stress_ratios_against_iso_y_b():
    """The rim's hoop stress under the tooth rises monotonically as s_R/h_t falls from 2 to 0.6;
    its ratios to the rim at s_R/h_t = 1.2 are the figures of docs/rating.md (within 1 %):
    1.190, 1.356, 1.580 at 1.0, 0.8, 0.6, against Y_B's 1.292, 1.649, 2.109 (below Y_B, and
    further below as the rim thins); and above s_R/h_t = 1.2, where Y_B = 1, the rim's stress
    still falls (0.707 of it at s_R/h_t = 2)."""
    hoop = {r: rim_hoop_under_a_tooth(r) for r in RATIOS}
    values = [hoop[r] for r in RATIOS]
    assert all(b > a for a, b in itertools.pairwise(values))
    for r in RATIOS:
        assert hoop[r] / hoop[1.2] == pytest.approx(OVER_1_2[r], rel=0.01)
        assert hoop[r] == pytest.approx(MPA[r] * 1e6, rel=0.01)
    for r in (1.0, 0.8, 0.6):
        assert 1.0 < hoop[r] / hoop[1.2] < y_b(r) / y_b(1.2)
    assert y_b(0.6) == pytest.approx(2.109, abs=1e-3)  # 1.6 ln(2.242/0.6)
    assert y_b(1.2) == pytest.approx(1.0, abs=1e-4)  # the formula meets 1 at s_R/h_t = 1.2
