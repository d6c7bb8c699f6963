"""Life under a load spectrum (ISO 6336-6:2019; jaxgear.rating.rate_spectrum): the standard's
Annex C example, a one-bin spectrum against the single-point rating, Miner sums by hand, a
sampled torque history counted into levels against the same bins given explicitly, the case
file's ``[rating.spectrum]`` and ``jaxgear run``'s outputs, one-line errors.

Annex C of ISO 6336-6:2019 ("Example calculation for safety factor from given load spectrum"),
its Table C.2 as transcribed in gfsReboucas/Drivetrain (data/table_C2.csv at 4a88df3; the
standard itself was not at hand): per bin the pinion torque (kN·m), the time in the bin over a
70-day record (s; the header says ``time_70d``), the pinion's 35.2 1/min, the cycles scaled to
30 years, K_Hβ, σ_H × S_H (N/mm²), Z_NT, N_i and U_i = n_i/N_i; with S_H1 = 1.374 and
σ_HP1 = 2400 N/mm², σ_H1 = 1747 N/mm², Z_L = 1.02, Z_v = 0.943, Z_R = 1.01 (the transcription's
``example_load_spectra`` reference column). Bins 1, 2 and 45 to 48 have no time at load and are
left out. Before the figures are asserted the transcription is checked against itself: the cycles
are time × speed scaled 70 days → 30 years of 365 days, U_i = n_i/N_i, ΣU_i = 1, σ_H × S_H ∝
√(T K_Hβ), and Z_NT = σ_H S_H/(σ_Hlim Z_L Z_v Z_R) with σ_Hlim = 1500 N/mm² (a case-hardened
steel, σ_HP1 = 1500 × Z_NT,static 1.6 = 2400).
"""

import copy
import math
import pathlib
import re
import tomllib

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
from jaxgear import cli
from jaxgear.cli import run as cli_run

RPM = 2 * math.pi / 60

# (bin, T kN·m, time s of 70 days, n_i over 30 years, K_Hβ, σ_H·S_H N/mm², Z_NT, N_i, U_i)
TABLE_C2 = [
    (3, 25.4, 24, 2203, 1.31, 2349, 1.61, 9.05e+04, 0.0243),
    (4, 25.3, 14, 1285, 1.31, 2344, 1.61, 9.29e+04, 0.0138),
    (5, 25.3, 9, 825.9, 1.31, 2344, 1.61, 9.29e+04, 0.00889),
    (6, 25.2, 14, 1285, 1.31, 2340, 1.61, 9.54e+04, 0.0135),
    (7, 25.1, 28, 2570, 1.31, 2335, 1.6, 9.79e+04, 0.0262),
    (8, 25, 14, 1285, 1.31, 2330, 1.6, 1.01e+05, 0.0128),
    (9, 24.9, 9, 825.9, 1.31, 2326, 1.6, 1.03e+05, 0.008),
    (10, 24.8, 19, 1744, 1.31, 2321, 1.59, 1.06e+05, 0.0165),
    (11, 24.7, 28, 2570, 1.31, 2316, 1.59, 1.09e+05, 0.0236),
    (12, 24.6, 33, 3028, 1.31, 2312, 1.59, 1.12e+05, 0.0271),
    (13, 24.5, 24, 2203, 1.31, 2307, 1.58, 1.15e+05, 0.0192),
    (14, 24.3, 24, 2203, 1.31, 2297, 1.58, 1.21e+05, 0.0182),
    (15, 24.2, 19, 1744, 1.31, 2293, 1.57, 1.25e+05, 0.014),
    (16, 24, 26, 2386, 1.31, 2283, 1.57, 1.32e+05, 0.0181),
    (17, 23.8, 52, 4772, 1.31, 2274, 1.56, 1.39e+05, 0.0343),
    (18, 23.6, 47, 4313, 1.31, 2264, 1.55, 1.47e+05, 0.0293),
    (19, 23.3, 62, 5690, 1.31, 2250, 1.54, 1.6e+05, 0.0355),
    (20, 23.1, 88, 8076, 1.31, 2240, 1.54, 1.7e+05, 0.0476),
    (21, 22.8, 66, 6057, 1.31, 2225, 1.53, 1.85e+05, 0.0328),
    (22, 22.5, 163, 14960, 1.31, 2211, 1.52, 2.02e+05, 0.0741),
    (23, 22.1, 180, 16520, 1.31, 2191, 1.5, 2.27e+05, 0.0727),
    (24, 21.8, 83, 7617, 1.31, 2176, 1.49, 2.49e+05, 0.0306),
    (25, 21.4, 200, 18350, 1.31, 2156, 1.48, 2.81e+05, 0.0653),
    (26, 20.9, 212, 19460, 1.31, 2131, 1.46, 3.29e+05, 0.0592),
    (27, 20.5, 104, 9544, 1.31, 2110, 1.45, 3.73e+05, 0.0256),
    (28, 20, 238, 21840, 1.31, 2084, 1.43, 4.4e+05, 0.0497),
    (29, 19.4, 253, 23220, 1.31, 2053, 1.41, 5.38e+05, 0.0432),
    (30, 18.8, 200, 18350, 1.31, 2021, 1.39, 6.62e+05, 0.0277),
    (31, 18.2, 206, 18900, 1.31, 1988, 1.37, 8.2e+05, 0.023),
    (32, 17.6, 297, 27260, 1.31, 1955, 1.34, 1.02e+06, 0.0266),
    (33, 16.9, 316, 29000, 1.31, 1916, 1.32, 1.34e+06, 0.0217),
    (34, 16.1, 334, 30650, 1.31, 1870, 1.28, 1.85e+06, 0.0166),
    (35, 15.3, 352, 32300, 1.31, 1823, 1.25, 2.58e+06, 0.0125),
    (36, 14.5, 274, 25150, 1.32, 1785, 1.23, 3.42e+06, 0.00736),
    (37, 13.6, 286, 26250, 1.34, 1742, 1.2, 4.7e+06, 0.00558),
    (38, 12.6, 404, 37080, 1.37, 1693, 1.16, 6.86e+06, 0.0054),
    (39, 11.6, 429, 39370, 1.4, 1643, 1.13, 1.02e+07, 0.00385),
    (40, 10.6, 449, 41210, 1.44, 1593, 1.09, 1.54e+07, 0.00268),
    (41, 9.5, 468, 42950, 1.49, 1534, 1.05, 2.52e+07, 0.0017),
    (42, 8.3, 303, 27810, 1.56, 1467, 1.01, 4.57e+07, 0.000609),
    (43, 7.1, 176, 16150, 1.66, 1398, 0.96, 1.9e+08, 8.48e-05),
    (44, 5.8, 12, 1101, 1.8, 1318, 0.91, 1.31e+09, 8.42e-07),
]
ANNEX = {"S_H1": 1.374, "sigma_HP1": 2400e6, "sigma_H1": 1747e6, "Z_L": 1.02, "Z_v": 0.943,
         "Z_R": 1.01, "sigma_H_lim": 1500e6, "rpm": 35.2}
_COLS = np.array(TABLE_C2, dtype=float).T
BINS, TORQUE, SECONDS, CYCLES, K_HB, SIGMA_S, Z_NT, N_I, U_I = _COLS


def _annex_curve():
    """The pinion's S–N line of the annex: case-hardened Z_NT, σ_Hlim Z_L Z_v Z_R, the static
    strength σ_HP1."""
    a = ANNEX
    ref = a["sigma_H_lim"] * a["Z_L"] * a["Z_v"] * a["Z_R"]
    return jr.SNCurve(jr.CaseHardened.z_nt_points, ref, a["sigma_HP1"])


def test_annex_c_transcription_is_consistent_with_itself():
    scale = 30 * 365 / 70  # 70 days of record → 30 years
    assert np.allclose(SECONDS * ANNEX["rpm"] / 60 * scale, CYCLES, rtol=2e-3)
    assert np.allclose(CYCLES / N_I, U_I, rtol=1e-2)
    assert U_I.sum() == pytest.approx(1.0, abs=2e-3)
    c = SIGMA_S / np.sqrt(TORQUE * K_HB)  # σ_H ∝ √(F_t K_Hβ), every other factor alike
    assert np.allclose(c, c[0], rtol=3e-3)
    a = ANNEX
    z = SIGMA_S * 1e6 / (a["sigma_H_lim"] * a["Z_L"] * a["Z_v"] * a["Z_R"])
    assert np.allclose(z, Z_NT, atol=6e-3)


def test_annex_c_cycles_to_failure_damage_and_safety_factor():
    curve = _annex_curve()
    sigma_h = SIGMA_S * 1e6 / ANNEX["S_H1"]  # the bins' contact stress σ_H,i
    n_fail = np.asarray(curve.cycles_to_failure(SIGMA_S * 1e6))
    # N_i to three digits; beyond 5e7 cycles the line is flat (Z_NT ∝ N^-0.0307), where a
    # stress printed to four digits moves N by up to 1.5 %
    tol = np.where(N_I < 5e7, 1e-2, 2.5e-2)
    assert np.all(np.abs(n_fail / N_I - 1) < tol), np.abs(n_fail / N_I - 1).max()
    damage = np.asarray(jr.miner_damage(SIGMA_S * 1e6, CYCLES, curve))
    assert np.allclose(damage, U_I, rtol=2.5e-2)
    s_h = float(jr.spectrum_safety(sigma_h, CYCLES, curve))
    assert s_h == pytest.approx(ANNEX["S_H1"], abs=6e-4)  # printed 1.374
    # the annex's σ_H1 1747 N/mm² is σ_HP1 / S_H1 (2400/1.374 = 1746.7)
    assert ANNEX["sigma_HP1"] / s_h == pytest.approx(ANNEX["sigma_H1"], abs=0.6e6)
    # the static strength is the annex's σ_HP1: σ_Hlim Z_NT,static (Z_L Z_v Z_R = 1 there)
    assert float(curve.stress(1e3)) == pytest.approx(2400e6, rel=1e-12)
    # the life factor at the last loaded bin: the table's Z_NT 0.91 (two digits)
    ref = float(curve.reference)
    assert float(curve.stress(N_I[-1])) / ref == pytest.approx(0.91, abs=6e-3)


def _tr_example_1(life_h=50_000.0, treatment=None):
    """ISO/TR 6336-30 example 1 (tests/test_rating.py gives its provenance)."""
    m = {"addendum_coeff": 1.0, "dedendum_coeff": 1.4, "face_width": 0.1,
         "fillet_radius_coeff": 0.39}
    pair = jg.GearPair(jg.Member(17, 0.145, **m), jg.Member(103, 0.0, **m), 8e-3,
                       math.radians(20.0), math.radians(15.8), 0.5)
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 500e6, 206e9, 0.3, 7830.0,
                                   treatment or jr.CaseHardened()),
        lubrication=jr.Lubrication(320e-6, 6e-6, 10e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 5),
        life=life_h * 3600.0,
        given=jr.GivenFactors(K_Hbeta=1.16),
        tip_relief=70e-6,
    )
    return jr.RatingGeometry.of(pair), settings, jr.OperatingPoint(9000.0, 360.0 * RPM)


@pytest.mark.parametrize(
    "life_h, treatment",
    [(50_000.0, jr.CaseHardened()), (2_000.0, jr.CaseHardened()),
     (20_000.0, jr.PairTreatment(jr.CaseHardened(), jr.Nitrided()))],
)
def test_one_bin_is_the_single_point_rating_at_that_many_cycles(life_h, treatment):
    # one bin of the life's cycles n: the factor S with σ_G(n) = S σ is the rating's σ_HG/σ_H
    # with Z_NT (Y_NT) at n cycles, for each gear (its own curve where the gears differ)
    geometry, settings, op = _tr_example_1(life_h, treatment)
    one = jr.rate(geometry, op, settings)
    spectrum = jr.LoadSpectrum([float(op.torque)], float(op.speed), [settings.life])
    sr = jr.rate_spectrum(geometry, spectrum, settings)
    assert np.allclose(sr.cycles[0], one.pitting.cycles, rtol=1e-12)
    assert np.allclose(sr.S_H, one.pitting.S_H, rtol=1e-9)
    assert np.allclose(sr.S_F, one.bending.S_F, rtol=1e-9)
    # the damage at the actual stress is n/N(σ), N the cycles where the rating's S would be 1
    assert np.allclose(sr.sigma_H[0], one.pitting.sigma_H, rtol=1e-12)
    life = np.asarray(sr.life_H)
    assert np.all(life > 0)
    assert np.allclose(np.asarray(sr.damage_sum_H) * life, settings.life, rtol=1e-12)


def test_two_bin_miner_sum_by_hand():
    ref, static = 1000e6, 1700e6  # a case-hardened line: corners 1e5 (1.6), 5e7 (1), 1e10 (0.85)
    curve = jr.SNCurve(jr.CaseHardened.z_nt_points, ref, static)
    k1 = math.log(1.6) / math.log(5e7 / 1e5)
    k2 = math.log(1 / 0.85) / math.log(1e10 / 5e7)
    s = np.array([1.2 * ref, 0.9 * ref])
    n = np.array([2e5, 3e8])
    n_a = 1e5 * (1.6 / 1.2) ** (1 / k1)  # each on its segment: N = N_b (f_b / f)^(1/k)
    n_b = 5e7 * (1 / 0.9) ** (1 / k2)
    assert np.allclose(curve.cycles_to_failure(s), [n_a, n_b], rtol=1e-10)
    d = jr.miner_damage(s, n, curve)
    assert float(d.sum()) == pytest.approx(n[0] / n_a + n[1] / n_b, rel=1e-10)
    # the safety factor: the Miner sum of the scaled stresses is 1 there (by hand)
    f = float(jr.spectrum_safety(s, n, curve))
    by_hand = (n[0] / (1e5 * (1.6 * ref / (f * s[0])) ** (1 / k1))
               + n[1] / (5e7 * (ref / (f * s[1])) ** (1 / k2)))
    assert by_hand == pytest.approx(1.0, rel=1e-9)
    # above the static strength: failure at once; below the curve's end: no damage
    assert float(curve.cycles_to_failure(1.01 * static)) == 0.0
    assert float(jr.miner_damage(1.01 * static, 1.0, curve)) == math.inf
    assert float(curve.cycles_to_failure(0.84 * ref)) == math.inf
    assert float(jr.miner_damage(0.84 * ref, 1e12, curve)) == 0.0
    # above the first corner the first segment continues (Annex C: Z_NT 1.61 at 9.05e4)
    assert float(curve.cycles_to_failure(1.65 * ref)) == pytest.approx(
        1e5 * (1.6 / 1.65) ** (1 / k1), rel=1e-10)


def test_a_sampled_history_counted_into_levels_is_the_explicit_bins():
    dt = 0.5
    torque = [100.0, 250.0, 250.0, 400.0, 390.0, 0.0, 120.0, 200.0]
    speed = [10.0, 20.0, 20.0, 30.0, 30.0, 0.0, 10.0, 40.0]
    sp = jr.LoadSpectrum.from_time_series(torque, speed, dt, [0.0, 200.0, 400.0])
    # (0, 200]: 100, 0 (the first level closed below), 120, 200; (200, 400]: 250, 250, 400, 390
    explicit = jr.LoadSpectrum([200.0, 400.0], [(10 + 0 + 10 + 40) / 4, (20 + 20 + 30 + 30) / 4],
                               [4 * dt, 4 * dt])
    for name in ("torque", "speed", "duration"):
        assert np.allclose(getattr(sp, name), getattr(explicit, name), rtol=1e-14), name
    # the cycles are the samples' Σ ω Δt / 2π
    assert float(sp.cycles.sum()) == pytest.approx(sum(speed) * dt / (2 * math.pi), rel=1e-14)
    # equal levels from 0 to the largest sample: 4 levels of 100 N·m, the empty ones dropped
    sp4 = jr.LoadSpectrum.from_time_series(torque, speed, dt, bins=4)
    assert np.allclose(sp4.torque, [100.0, 200.0, 300.0, 400.0])
    assert np.allclose(sp4.duration, [2 * dt, 2 * dt, 2 * dt, 2 * dt])


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: jr.LoadSpectrum([-1.0], 1.0, [1.0]), r"LoadSpectrum: torque\[0\] = -1 N·m is out of range: allowed >= 0"),
        (lambda: jr.LoadSpectrum([1.0, 2.0], 1.0, [1.0]), r"duration must have shape \(2,\)"),
        (lambda: jr.LoadSpectrum([0.0], 1.0, [1.0]), r"no bin with torque, speed and duration"),
        (lambda: jr.LoadSpectrum.from_cycles([1.0], 0.0, [5.0]), r"cycles\[0\] = 5 at speed"),
        (lambda: jr.LoadSpectrum.from_time_series([1.0, -2.0], 1.0, 0.1),
         r"from_time_series: torque\[1\] = -2 N·m is out of range"),
        (lambda: jr.LoadSpectrum.from_time_series([1.0, 5.0], 1.0, 0.1, [0.0, 2.0]),
         r"torque\[1\] = 5 N·m is outside the edges"),
        (lambda: jr.SNCurve(((1e5, 1.0), (5e7, 1.6)), 1e9, 2e9),
         r"SNCurve: points = .* f decreasing"),
        (lambda: jr.rate_spectrum(None, jr.LoadSpectrum([1.0], 1.0, [1.0]), None),
         r"rate_spectrum: geometry"),
    ],
)
def test_bad_input_is_one_line_naming_the_argument(call, message):
    with pytest.raises(ValueError, match=message) as err:
        call()
    assert "\n" not in str(err.value)


def _case(spectrum):
    from test_rating_case import CASE

    d = copy.deepcopy(CASE)
    d["rating"]["spectrum"] = spectrum
    return d


def test_case_file_spectrum_is_the_api_spectrum_and_run_reports_each_bin(tmp_path):
    bins = {"torque_Nm": [9000.0, 7000.0, 0.0], "speed_rpm": 360.0,
            "hours": [20_000.0, 25_000.0, 5_000.0]}
    case = jio.parse_case(_case(bins))
    rc = jio.ratings_of(case)[0]
    want = jr.LoadSpectrum([9000.0, 7000.0, 0.0], 360.0 * RPM, [7.2e7, 9e7, 1.8e7])
    for name in ("torque", "speed", "duration"):
        assert np.allclose(getattr(rc.spectrum, name), getattr(want, name), rtol=1e-12), name
    # cycles and time shares: the same bins
    cycles = {"torque_Nm": [9000.0, 7000.0], "speed_rpm": [360.0, 360.0],
              "cycles": [4.32e8, 5.4e8]}
    sp = jio.ratings_of(jio.parse_case(_case(cycles)))[0].spectrum
    assert np.allclose(sp.duration, [7.2e7, 9e7], rtol=1e-12)
    share = {"torque_Nm": [9000.0, 7000.0], "speed_rpm": 360.0, "time_share": [4.0, 5.0]}
    sp = jio.ratings_of(jio.parse_case(_case(share)))[0].spectrum  # life_h 50 000 h
    assert np.allclose(sp.duration, [50_000 * 3600 * 4 / 9, 50_000 * 3600 * 5 / 9], rtol=1e-12)
    section = cli.rating_outputs(case, str(tmp_path))
    spec = section["spectrum"]
    # rated with K_A = 1 (the case's K_A is 1 too): the API's numbers
    sr = jr.rate_spectrum(rc.geometry, want, rc.settings)
    assert np.allclose(spec["pitting"]["damage"], np.asarray(sr.damage_H), rtol=1e-9)
    assert spec["pitting"]["S_H"] == pytest.approx(np.asarray(sr.S_H).tolist(), rel=1e-9)
    rows = (tmp_path / "spectrum.csv").read_text(encoding="utf-8").splitlines()
    assert len(rows) == 4 and rows[0].startswith("bin,torque_Nm,speed_rpm,hours")
    assert "Load spectrum and life (ISO 6336-6:2019" in (tmp_path / "rating.md").read_text(
        encoding="utf-8")
    lines = cli_run.rating_run_line(section)
    assert lines[1].startswith("load spectrum (ISO 6336-6, 3 bins")
    assert len(lines) == 2 + 1 + 3  # the rating, the spectrum, a header and one line per bin
    d1 = spec["pitting"]["damage"][0]
    assert f"{d1[0]:.3g} / {d1[1]:.3g}" in lines[3]


@pytest.mark.parametrize(
    "spectrum, message",
    [
        ({"torque_Nm": [1.0], "speed_rpm": 360.0}, r"\[rating.spectrum\] hours: missing"),
        ({"torque_Nm": [1.0], "speed_rpm": 360.0, "hours": [1.0], "cycles": [1.0]},
         r"hours and cycles both given"),
        ({"torque_Nm": [-1.0], "speed_rpm": 360.0, "hours": [1.0]},
         r"torque_Nm = \[-1\]: element -1 out of range, allowed \[0, 1e\+09\]"),
        ({"torque_Nm": [1.0, 2.0], "speed_rpm": 360.0, "hours": [1.0]},
         r"hours = \[1\]: must be an array of 2 numbers"),
        ({"torque_Nm": [1.0], "speed_rpm": 360.0, "hours": [1.0], "series_step_s": 1.0},
         r"not both"),
        ({"torque_Nm": [1.0], "speed_rpm": 360.0, "hours": [1.0], "tourqe": 1.0},
         r"unknown key 'tourqe'"),
        ({"series_torque_Nm": [1.0, 2.0], "series_speed_rpm": 360.0, "series_step_s": 0.0},
         r"series_step_s = 0: out of range"),
    ],
)
def test_bad_spectrum_keys_are_one_line_naming_the_key(spectrum, message):
    with pytest.raises(jio.SchemaError, match=message) as err:
        jio.parse_case(_case(spectrum))
    assert "\n" not in str(err.value)


# default tier: tests/test_rating_spectrum.py::test_annex_c_cycles_to_failure_damage_and_safety_factor
# (Miner damage and the spectrum's S against ISO 6336-6 Annex C) and
# ::test_case_file_spectrum_is_the_api_spectrum_and_run_reports_each_bin (a case's spectrum rated)
@pytest.mark.slow
def test_wind_spectrum_example_counts_the_rayleigh_hours_and_writes_its_figure(tmp_path):
    """examples/load_spectrum_wind.py: the hours at load are the Rayleigh share of the winds
    between cut-in and cut-out (analytic), the bins above rated wind carry the case's rated
    pinion torque (5 MW at 1165.9 1/min: 40 953 N·m), and at the loads scaled by the spectrum's
    safety factors the Miner sums are 1 (what S means). About 30 s."""
    from _examples import load_example

    ex = load_example("load_spectrum_wind")
    rec = ex.main(tmp_path)
    assert (tmp_path / "load_spectrum_wind.png").stat().st_size > 10_000
    hours = np.array(rec["hours"])
    assert hours.sum() == pytest.approx(175_200.0, rel=1e-12)
    c = 10.0 / math.gamma(1.5)  # the Rayleigh scale of a 10 m/s mean
    share = math.exp(-((3.0 / c) ** 2)) - math.exp(-((25.0 / c) ** 2))
    assert hours[:-1].sum() == pytest.approx(175_200.0 * share, rel=1e-12)
    rated = [t for w, t in zip(rec["wind_m_s"], rec["torque_Nm"], strict=True) if w and w >= 12]
    assert np.allclose(rated, 5e6 / (1165.9 * RPM), rtol=2e-4)
    for name, damage in rec["damage_share_at_S"].items():
        assert sum(damage) == pytest.approx(1.0, rel=1e-9), name


def _guide_spectrum_case(keep_modifications: bool):
    """docs/guide/rating.md's spectrum tables put into ``power-helical`` in place of its own
    [material], [operating] and [rating], with or without its [modifications]."""
    page = pathlib.Path(__file__).resolve().parents[1] / "docs" / "guide" / "rating.md"
    blocks = re.findall(r"^```toml\n(.*?)^```", page.read_text("utf-8"), re.DOTALL | re.MULTILINE)
    block = next(b for b in blocks if "[rating.spectrum]" in b)
    data = tomllib.loads(jio.embedded_case_text("power-helical"))
    data.update(tomllib.loads(block))
    if not keep_modifications:
        del data["modifications"]
    return jio.rating_of(jio.parse_case(data, "guide"))


# default tier: tests/test_rating_spectrum.py::test_case_file_spectrum_is_the_api_spectrum_and_run_reports_each_bin
# (a case file's spectrum equals the API's, 1e-9); the guide's printed figures at its size here
@pytest.mark.slow
def test_guide_spectrum_figures():
    """The guide's figures: its tables on the bare ``power-helical`` rate as its Python example
    (the API's spectrum on RatingGeometry.of(pair), K_A = 1, accuracy class 6: the same S_F to
    1e-9), the gear's root just under 1 with a bending life of about 15 500 h; with the case's
    modifications kept (tip relief C_a lowers K_v) S_F is 1.06 / 1.04 as the page says."""
    rc = _guide_spectrum_case(keep_modifications=False)
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 500e6, 210e9, 0.3, 7800.0, jr.CaseHardened()),
        lubrication=jr.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jr.GearAccuracy.from_grade(jio.load_case("power-helical").pair, 6),
        life=20_000 * 3600.0,
        application_factor=1.0,
    )
    spectrum = jr.LoadSpectrum(
        torque=[1250.0, 620.0, 310.0, 200.0, 0.0],
        speed=np.array([3000.0, 3000.0, 3000.0, 2400.0, 0.0]) * RPM,
        duration=np.array([200.0, 2_000.0, 12_000.0, 4_300.0, 1_500.0]) * 3600.0,
    )
    api = jr.rate_spectrum(jr.RatingGeometry.of(jio.load_case("power-helical").pair), spectrum,
                           settings)
    case = jr.rate_spectrum(rc.geometry, rc.spectrum,
                            eqx.tree_at(lambda s: s.application_factor, rc.settings, 1.0))
    np.testing.assert_allclose(np.asarray(case.S_F), np.asarray(api.S_F), rtol=1e-9)
    np.testing.assert_allclose(np.asarray(case.S_H), np.asarray(api.S_H), rtol=1e-9)
    assert 0.98 < float(case.S_F[1]) < 1.0 < float(case.S_F[0]) < 1.02
    assert abs(float(case.life_F[1]) / 3600 - 15_500) < 100
    rc = _guide_spectrum_case(keep_modifications=True)
    kept = jr.rate_spectrum(rc.geometry, rc.spectrum,
                            eqx.tree_at(lambda s: s.application_factor, rc.settings, 1.0))
    np.testing.assert_allclose(np.asarray(kept.S_F), [1.06, 1.04], atol=0.005)
