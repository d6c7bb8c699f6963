"""The NREL 5 MW stage-3 bearings from their geometry against the published stiffnesses
(benchmarks/nrel_stage3_bearings.py, its record docs/bench/nrel_stage3_bearings.json).

- The transcription: the benchmark's table (Nejad et al. 2016 via gfsReboucas/Drivetrain)
  against the embedded nrel-5mw-stage3-housed's springs, which transcribe the same table
  independently (radial the mean of K_y and K_z, tilt of K_beta and K_gamma, axial K_x), and
  each ISO bore code (a designation's last two digits times 5 mm) against the bore.
- The published case's bearing loads in the record against statics by hand: each shaft's
  bearings carry the helical mesh's axial force 2 T sin β / (m_n z_1) and its transverse
  force T / r_b1 along the line of action at the working pressure angle.
- The record's stiffnesses re-computed from its loads (HS-A in the default tier, every figure
  and the loads' quasi-static solve in the slow tier).
- The example case file's bearings: the estimated rollers, the tapered pairs (one node each,
  its rows at the published case's two positions); the pairs at the example's own operating
  point (the record) against statics: the pinion's pair carries the whole mesh axial force
  (HS-A has no ribs), each pair's rows' axial loads differ by its axial load; (slow) the
  record's pairs re-computed.
- The record's whine on the published springs against the embedded housed case's regression
  record (the same run); the whine on the bearings from geometry is the record's alone (two
  housed runs of minutes: not re-run by a test).
"""

from __future__ import annotations

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest

from benchmarks import nrel_stage3_bearings as nrel

ROOT = Path(__file__).resolve().parents[1]
RECORD = json.loads((ROOT / "docs" / "bench" / "nrel_stage3_bearings.json").read_text("utf-8"))
HOUSED = tomllib.loads((ROOT / "jaxgear" / "cases" / "nrel-5mw-stage3-housed.toml").read_text(
    "utf-8"))
EXAMPLE = tomllib.loads((ROOT / "examples" / "nrel-5mw-stage3-rolling.toml").read_text("utf-8"))


def test_table_matches_the_embedded_cases_transcription():
    """Each bearing's published stiffnesses as nrel-5mw-stage3-housed writes them (N/µm,
    N·m/rad; IMS-A without an axial key: 0), and the bore of each ISO-coded designation."""
    for name, row in nrel.TABLE.items():
        spring = HOUSED["scene"][row["shaft"]]["bearings"][row["index"]]
        assert spring["radial_N_per_um"] == pytest.approx((row["K_y"] + row["K_z"]) / 2e6)
        assert spring.get("axial_N_per_um", 0.0) == pytest.approx(row["K_x"] / 1e6)
        assert spring["tilt_Nm_per_rad"] == pytest.approx((row["K_beta"] + row["K_gamma"]) / 2)
        codes = [t for t in row["designation"].split() if t.isdigit()]
        if codes:  # the ISO series (LM 567949/910 is an inch series: no bore code)
            assert int(codes[0][-2:]) * 5 == row["d"], name


def _hand_mesh():
    """The helical mesh's forces on the pinion at its torque T, by hand: the axial
    F_a = 2 T sin β / (m_n z_1), the transverse F_bt = T / r_b1 along the transverse line of
    action (r_b1 = m_n z_1 cos α_t / (2 cos β), tan α_t = tan α_n / cos β), which meets the
    centre line at the working pressure angle α_wt, cos α_wt = a cos α_t / a_w with
    a = m_n (z_1 + z_2) / (2 cos β)."""
    p = HOUSED["pair"]
    T = HOUSED["operating"]["torque_Nm"]
    m, z1, z2 = p["normal_module_mm"] * 1e-3, HOUSED["pinion"]["teeth"], HOUSED["gear"]["teeth"]
    beta, alpha_n = math.radians(p["helix_angle_deg"]), math.radians(p["normal_pressure_angle_deg"])
    alpha_t = math.atan(math.tan(alpha_n) / math.cos(beta))
    r_b1 = m * z1 * math.cos(alpha_t) / (2 * math.cos(beta))
    a = m * (z1 + z2) / (2 * math.cos(beta))
    alpha_wt = math.acos(a * math.cos(alpha_t) / (p["center_distance_mm"] * 1e-3))
    return 2 * T * math.sin(beta) / (m * z1), T / r_b1, alpha_wt


def test_recorded_loads_against_statics():
    """Each shaft's bearings carry the mesh's axial force (the pinion's along −z, the wheel's
    along +z) and its transverse force F_bt, the pinion's and the wheel's equal and opposite,
    along the line of action (|F_x| / |F_y| = tan α_wt, the centres along x): 1e-3 (the
    scene's mean mesh force), the direction 5e-3."""
    F_a, F_bt, alpha_wt = _hand_mesh()
    loads = {n: np.asarray(v["case_load_N"]) for n, v in RECORD["bearings"].items()}
    pinion = sum(loads[n] for n in ("HS-A", "HS-B", "HS-C"))
    wheel = sum(loads[n] for n in ("IMS-A", "IMS-B", "IMS-C"))
    assert -pinion[2] == pytest.approx(F_a, rel=1e-3)
    assert wheel[2] == pytest.approx(F_a, rel=1e-3)
    np.testing.assert_allclose(pinion[:2], -wheel[:2], rtol=1e-3)
    assert math.hypot(*pinion[:2]) == pytest.approx(F_bt, rel=1e-3)
    assert abs(pinion[0] / pinion[1]) == pytest.approx(math.tan(alpha_wt), rel=5e-3)


def test_recorded_cylindrical_stiffness_recomputed():
    """HS-A from geometry at the record's load, zero clearance: its radial and tilt figures
    re-computed (1e-6; the others in the slow tier's whole record)."""
    for name in ("HS-A",):
        rec = RECORD["bearings"][name]
        got = nrel.stiffness_figures(nrel.bearing(name), np.asarray(rec["evaluated_load_N"]))
        for key in ("radial_along", "radial_across", "tilt_along", "tilt_across"):
            assert got[key] == pytest.approx(rec["geometry"]["0um"][key], rel=1e-6), key


def test_example_bearings_are_the_table_and_the_rule():
    """The example's HS-A and IMS-A and each tapered pair's rows: the table's boundary dimensions
    and :func:`jaxgear.bearings.estimated_rollers`'s rollers (mm), a pair's α = atan(e/1.5); a
    pair one node at the centre of the published case's two bearings, its rows' mid-planes at
    their positions (row_spacing_mm their distance), zero end play."""
    import jaxgear.bearings as jb

    for row in nrel.TABLE.values():
        if row["type"] == "CRB":
            b = EXAMPLE["scene"][row["shaft"]]["bearings"][row["index"]]
        else:  # HS-B, HS-C (IMS-B, IMS-C): one pair, the shaft's second bearing
            b = EXAMPLE["scene"][row["shaft"]]["bearings"][1]
            published = [HOUSED["scene"][row["shaft"]]["bearings"][i]["position_mm"]
                         for i in (1, 2)]
            assert b["kind"] == "tapered_roller_pair" and b["end_play_um"] == 0.0
            assert b["position_mm"] == pytest.approx(sum(published) / 2, rel=1e-12)
            assert b["row_spacing_mm"] == pytest.approx(published[1] - published[0], rel=1e-12)
            assert math.tan(math.radians(b["contact_angle_deg"])) == pytest.approx(
                row["e"] / 1.5, rel=1e-12)
        est = jb.estimated_rollers(row["d"], row["D"], row["B"])
        assert (b["bore_mm"], b["outer_diameter_mm"], b["width_mm"]) == (
            row["d"], row["D"], row["B"])
        assert b["rollers"] == est["elements"]
        for key, arg in (("roller_diameter_mm", "element_diameter"),
                         ("roller_length_mm", "effective_length"),
                         ("pitch_diameter_mm", "pitch_diameter")):
            assert b[key] == pytest.approx(est[arg], rel=1e-12), key


def test_recorded_pairs_against_statics():
    """The record's pairs at the example's operating point: the pinion's pair carries the whole
    mesh axial force 2 T sin β / (m_n z_1) (HS-A has no ribs; 1e-3), the wheel's pair its
    share beside IMS-A's none; each pair's F_z is its rows' axial loads' difference (the rows'
    own frames; 1e-9); the shaft's radial loads sum to the mesh's F_bt (1e-3); the spread
    s + 2 (d_m/2) tan α by hand (O)."""
    F_a, F_bt, _ = _hand_mesh()
    rec = RECORD["pairs_at_operating_point"]
    hs, ims = rec["pairs"]["HS-B/C"], rec["pairs"]["IMS-B/C"]
    assert -hs["load_N"][2] == pytest.approx(F_a, rel=1e-3)
    assert ims["load_N"][2] == pytest.approx(F_a, rel=1e-3)
    for pair, (row, z) in ((hs, ("HS-B", 100.0)), (ims, ("IMS-B", 100.0))):
        rows = pair["rows"]
        # O: row 0 (at −z) carries +z, row 1 the other way
        assert rows[0]["axial_N"] - rows[1]["axial_N"] == pytest.approx(
            pair["load_N"][2], rel=1e-9, abs=1e-9 * abs(rows[0]["axial_N"]))
        t = nrel.TABLE[row]
        a = 0.5 * (t["D"] + t["d"]) / 2 * t["e"] / 1.5 * 1e-3
        assert pair["spread_m"] == pytest.approx(z * 1e-3 + 2 * a, rel=1e-12)
    for shaft, names in (("HS-A", "HS-B/C"), ("IMS-A", "IMS-B/C")):
        f = np.asarray(rec["cylindrical_loads_N"][shaft]) + np.asarray(rec["pairs"][names][
            "load_N"])
        assert math.hypot(f[0], f[1]) == pytest.approx(F_bt, rel=1e-3)


@pytest.mark.slow  # the published case's quasi-static solve and twelve bearing solves, ~40 s
def test_record_recomputed():
    """Every figure of the record's comparison re-computed (the loads from the published case's
    quasi-static solve 1e-6 of the largest, the stiffnesses 1e-6), and the stage-1 spherical
    bearings'."""
    got = nrel.compare()
    for name, rec in RECORD["bearings"].items():
        f = np.asarray(rec["case_load_N"])
        np.testing.assert_allclose(got[name]["case_load_N"], f, rtol=0,
                                   atol=1e-6 * np.abs(f).max())
        for c, g in rec["geometry"].items():
            for key in ("radial_along", "radial_across", "axial", "tilt_along", "tilt_across"):
                assert got[name]["geometry"][c][key] == pytest.approx(g[key], rel=1e-6,
                                                                     abs=1e-3), (name, c, key)
    sph = nrel.spherical_at_design_load()
    for name, rec in RECORD["spherical_stage1"].items():
        for key in ("radial_along", "axial", "tilt", "radial_load_N"):
            assert sph[name][key] == pytest.approx(rec[key], rel=1e-6, abs=1e-3), (name, key)


@pytest.mark.slow  # the example's operating point: a few quasi-static solves, ~60 s
def test_recorded_pairs_recomputed():
    """The record's pairs at the example's operating point re-computed (loads 1e-6 of the
    largest, the stiffness's diagonal 1e-6)."""
    got = nrel.pairs_at_operating_point()
    for name, rec in RECORD["pairs_at_operating_point"]["pairs"].items():
        f = np.asarray(rec["load_N"])
        np.testing.assert_allclose(got["pairs"][name]["load_N"], f, rtol=0,
                                   atol=1e-6 * np.abs(f).max())
        np.testing.assert_allclose(got["pairs"][name]["stiffness_diagonal"],
                                   rec["stiffness_diagonal"], rtol=1e-6)


def test_recorded_published_whine_is_the_embedded_cases_run():
    """The record's whine on the published springs is what the embedded nrel-5mw-stage3-housed
    writes (its regression record, the same command): the overall ERP at each speed and the
    order-1 TE amplitude (1e-6)."""
    ref = json.loads((ROOT / "tests" / "data" / "regression" / "run-nrel-5mw-stage3-housed.json"
                      ).read_text("utf-8"))["results"]
    got = RECORD["whine"]["published springs"]
    np.testing.assert_allclose(got["speeds_rad_s"], ref["whine/housing.json"]["speeds_rad_s"])
    np.testing.assert_allclose(got["overall_erp_dB"],
                               ref["whine/housing.json"]["overall_erp_level_dB"], rtol=1e-6)
    whine = ref["whine/whine.json"]
    k = whine["orders"].index(1.0)
    te = [a[k][0] * 1e6 for a in whine["transmission_error_m"]["amplitude"]]
    np.testing.assert_allclose(got["te_order1_um"], te, rtol=1e-6)
