"""The FE contact reference (benchmarks/extended_contact_fe.py) checked against analytic
facts, so that its record (docs/bench/extended_contact_fe.json) can serve as the evidence for
contact beyond the theoretical path.

The reference is a 2-D plane-strain FE model of the unmodified accessory-spur pair (P2
triangles, 5 teeth per member, exact unilateral contact with brute-force node-to-segment gaps);
here on coarse meshes (h = m_n/4 and m_n/6):

* rigid teeth: the generated flanks are conjugate (every pair's smallest gap ~0 along its
  theoretical path, never negative), and the first and last touch are at the theoretical start
  and end of contact (ISO 21771's path of contact from the radii and centre distance);
* equilibrium: the contact forces' moment about the pinion is the torque, and the normal load
  with one pair in contact is T/r_b1 (every involute normal is tangent to the base circle);
* the single-pair mesh stiffness in mid-path is of the order of ISO 6336-1's c' (±30 %);
* the start of contact under load is premature and grows with the load; there the entering tip
  corner's rigid gap is the loaded pinion's rigid approach less the entering teeth's own
  displacement under the loaded pair's force (rim torsion and foundation: a fraction of it);
* convergence between the two meshes.
"""

import json
import pathlib

import numpy as np
import pytest

import jaxgear as jg
from benchmarks.extended_contact_fe import (
    accessory_spur_pair,
    build_pair,
    end_of_contact,
    single_pair_stiffness,
    start_of_contact,
)

PAIR, TORQUE, E, NU = accessory_spur_pair()
TP = TORQUE / PAIR.face_width  # N·m per m of face width


@pytest.fixture(scope="module")
def coarse():
    return build_pair(PAIR, size=PAIR.normal_module / 4, youngs_modulus=E, poisson_ratio=NU)


@pytest.fixture(scope="module")
def finer():
    return build_pair(PAIR, size=PAIR.normal_module / 6, youngs_modulus=E, poisson_ratio=NU)


def test_rigid_flanks_are_conjugate_along_the_theoretical_path(coarse):
    pm = coarse
    for s in np.linspace(0.02e-3, pm.g_alpha - 0.02e-3, 9):
        c = pm.candidates(pm.theta(s))
        gap = c["gap"][c["pair"] == 0]
        assert gap.min() > -1e-10, s  # no interpenetration of the rigid forms
        assert gap.min() < 0.05e-6, s  # touching (to the contact points' spacing)
    for s in (-0.3e-3, pm.g_alpha + 0.3e-3):  # outside the path: apart by microns
        c = pm.candidates(pm.theta(s))
        assert c["gap"][c["pair"] == 0].min() > 1e-6, s


def test_zero_load_start_and_end_are_the_theoretical_ones(coarse):
    pm = coarse
    # the theoretical path from the radii and the centre distance (ISO 21771), written out
    rb1, rb2 = PAIR.base_radii
    ra1, ra2 = PAIR.tip_radii
    aw = np.arccos((rb1 + rb2) / PAIR.center_distance)
    g_alpha = np.sqrt(ra1**2 - rb1**2) + np.sqrt(ra2**2 - rb2**2) - PAIR.center_distance * np.sin(aw)
    assert pm.g_alpha == pytest.approx(g_alpha, rel=1e-12)
    assert abs(start_of_contact(pm, 0.0)) < 1e-6  # m, vs g_α = 6.07 mm
    assert abs(end_of_contact(pm, 0.0) - g_alpha) < 1e-6


def test_contact_forces_balance_the_torque(coarse):
    pm = coarse
    for s in (-0.5e-3, 0.5e-3, 0.5 * pm.g_alpha, pm.g_alpha + 0.3e-3):
        st = pm.solve(pm.theta(s), TP)
        assert st.arm @ st.p == pytest.approx(TP, rel=1e-9)
        assert np.all(st.p >= 0) and st.deformed_gap.min() > -1e-12
        assert np.abs(st.deformed_gap[st.p > 0]).max() < 1e-11  # loaded points touch (m)
    st = pm.solve(pm.theta(0.5 * pm.g_alpha), TP)  # one pair in contact, on the line of action
    assert st.p.sum() == pytest.approx(TP / pm.rb1, rel=5e-3)


def test_single_pair_stiffness_is_of_the_order_of_iso6336(coarse):
    k_fe = single_pair_stiffness(coarse, TP)  # N/m²
    c_iso = jg.iso6336_single_stiffness(PAIR)  # c' = 17.88 N/(mm·µm), C_M = 0.8 included
    assert 0.7 * c_iso < k_fe < 1.3 * c_iso, (k_fe * 1e-9, c_iso * 1e-9)


def test_loaded_start_is_where_the_corner_gap_meets_the_rigid_approach(coarse):
    pm = coarse
    s_full, s_half = start_of_contact(pm, TP), start_of_contact(pm, 0.5 * TP)
    assert s_full < s_half < -0.02 * pm.g_alpha  # premature, more so under more load
    c = pm.candidates(pm.theta(s_full))
    corner = (c["pair"] == 0) & (c["corner"] == 1)
    st = pm.solve(pm.theta(s_full), TP)
    approach = st.dtheta * c["arm"][corner].max()  # the loaded pinion's rigid approach there
    # the entering corner's rigid gap is closed by the approach less the entering teeth's own
    # displacement under the loaded pair's force (the rims' torsion and the foundations carry
    # them along: a positive fraction of the approach, well below the whole of it)
    ratio = c["gap"][corner].min() / approach
    assert 0.6 < ratio < 0.98, ratio
    # late disengagement, symmetric to within a tenth for this nearly symmetric path
    late = end_of_contact(pm, TP) - pm.g_alpha
    assert late > 0 and late == pytest.approx(-s_full, rel=0.1)


def test_start_of_contact_and_share_converge(coarse, finer):
    g = coarse.g_alpha
    for T in (TP, 0.5 * TP):
        a, b = start_of_contact(coarse, T), start_of_contact(finer, T)
        assert abs(a - b) < 0.005 * g, (a, b)
        for s in (-0.5e-3, 0.0, 0.8e-3):
            la = coarse.solve(coarse.theta(s), T).loads()
            lb = finer.solve(finer.theta(s), T).loads()
            assert la[1] / la.sum() == pytest.approx(lb[1] / lb.sum(), abs=0.02), s


RECORD_PATH = pathlib.Path(__file__).resolve().parents[1] / "docs/bench/extended_contact_fe.json"


def test_the_record_is_converged_and_reproduced_on_a_coarse_mesh(coarse):
    """docs/bench/extended_contact_fe.json (``python benchmarks/extended_contact_fe.py``, h =
    m_n/8): its meshes agree with each other, its zero-load ends are the theoretical ones, and
    the coarse mesh here reproduces its start of contact and the entering pair's share."""
    rec = json.loads(RECORD_PATH.read_text())
    g = rec["geometry"]["path_of_contact_m"] * 1e3  # mm
    assert g == pytest.approx(coarse.g_alpha * 1e3, rel=1e-12)
    assert abs(rec["zero_load"]["s_start_mm"]) < 1e-3
    assert abs(rec["zero_load"]["s_end_minus_g_alpha_mm"]) < 1e-3
    for i, t in enumerate(rec["torques"]):
        runs = [c["torques"][i] for c in rec["convergence"]]
        starts = [r["s_start_mm"] for r in runs]
        ends = [r["s_end_minus_g_alpha_mm"] for r in runs]
        assert max(starts) - min(starts) < 0.005 * g, starts
        assert max(ends) - min(ends) < 0.005 * g, ends
        for key in runs[0]["share_at"]:
            shares = [r["share_at"][key] for r in runs]
            assert max(shares) - min(shares) < 0.02, (key, shares)
        T = t["torque_per_width_Nm_per_m"]
        assert start_of_contact(coarse, T) * 1e3 == pytest.approx(t["s_start_mm"], abs=0.005 * g)
        row = t["approach"][15]  # s = 0
        assert row["s_mm"] == pytest.approx(0.0, abs=1e-12)
        loads = coarse.solve(0.0, T).loads()
        assert loads[1] / loads.sum() == pytest.approx(row["share"], abs=0.02)


def test_the_records_start_of_contact_grows_as_the_root_of_the_torque():
    """Over the record's map (5 … 160 N·m) the premature start and the late end grow with the
    torque as √T: the corner's rigid gap grows quadratically before A (17.8 µm at 1 mm), and
    the deflection that closes it about linearly with the load (to the Hertzian contact's
    slight stiffening)."""
    rec = json.loads(RECORD_PATH.read_text())
    T = np.array([h["torque_Nm"] for h in rec["harris"]])
    start = np.array([h["s_start_mm"] for h in rec["harris"]])
    late = np.array([h["s_end_minus_g_alpha_mm"] for h in rec["harris"]])
    assert np.all(np.diff(start) < 0) and np.all(np.diff(late) > 0)
    for s in (start, late):
        k = s**2 / T  # mm²/(N·m)
        assert k.max() / k.min() < 1.3, k
