"""A published sizing task reproduced (examples/sizing/nrel-5mw-stage3.toml, docs/sizing.md "A
published sizing task"): the third, parallel helical stage of the NREL 5 MW reference gearbox.

Sources, typed here and in the example's header:
[1] A. R. Nejad, Y. Guo, Z. Gao, T. Moan, "Development of a 5 MW reference gearbox for offshore
    wind turbines", Wind Energy 19 (2016) 1089-1106, doi:10.1002/we.1884, Table V, third stage
    (the published design).
[2] the KISSsoft rating report of that stage (KISSsoft Release 03/2017 A, ISO 6336:2006 method
    B), gfsReboucas/Drivetrain, @NREL_5MW/stage_03.rtf (the requirements as it states them and
    the published rating; the same report tests/test_rating_kisssoft.py transcribes).

Checked: the example spec states the published inputs; the published design is one of the
enumerated candidates; its row of the sizing table reproduces the report's geometry to its
printed digits and its safety factors once the load factors the report takes differently are
put back (the stated differences), and it is feasible; and with the published design's own
safety factors as the minimums it is the lightest candidate."""

from __future__ import annotations

import dataclasses
import math
import pathlib
import tomllib

import equinox as eqx
import numpy as np
import pytest

import jaxgear.io as jio
import jaxgear.rating as jr
import jaxgear.sizing as js

EXAMPLE = pathlib.Path(__file__).resolve().parents[1] / "examples" / "sizing"
EXAMPLE = EXAMPLE / "nrel-5mw-stage3.toml"

# the requirements as [2] prints them (the header and sections 1, 3, 4 of the report)
POWER_W = 5000e3                    # Power (kW) [P] 5000.000
SPEED_RPM = 1165.9                  # Speed (1/min) [n], gear 1
TORQUE_NM = 40953.0                 # Torque (Nm) [T], gear 1 (rounded from its own speed)
RATIO = 3.958                       # Gear ratio [u]
K_A = 1.25                          # Application factor [KA]
LIFE_H = 175200.0                   # Required service life (h) [H]
SIGMA_H_LIM, SIGMA_F_LIM = 1500e6, 430e6   # 18CrNiMo7-6, ISO 6336-5 MQ (N/mm² in the report)
E_MODULUS, POISSON = 206000e6, 0.3
S_H_MIN, S_F_MIN = 1.25, 1.56       # Required safety [SHmin], [SFmin]
GRADE = 6                           # Accuracy grade [Q-ISO 1328:1995]
NU_40 = 220e-6                      # Kinem. viscosity oil at 40 °C (mm²/s) [nu40] 220.00
RZ_FLANK, RZ_ROOT = 4.8e-6, 20e-6   # [RZH], [RZF] (µm)
TIP_RELIEF = 2.0e-6                 # Tip relief (µm) [Ca] 2.0
TIP_ALTERATION = -0.938e-3          # Tip alteration (mm) [k*mn], both gears
RACK = (1.25, 0.38, 1.0)            # ISO 53:1998 profile A: h_fP*, ρ_fP*, h_aP*
# the published design [1] (Table V; the report prints the same, x2 to four decimals)
M_N, ALPHA_N, BETA = 14e-3, 20.0, 10.0
Z1, Z2 = 24, 95
X1, X2, X2_REPORT = 0.480, 0.669, 0.6691
FACE_WIDTH, CENTRE_DISTANCE = 0.360, 0.861
# the report's printed results of that design ([2], mm and dimensionless)
PRINTED = {
    "reference_diameter": (341.183, 1350.517), "tip_diameter": (380.747, 1395.376),
    "root_diameter": (319.623, 1334.252), "tip_thickness": (8.800, 11.034),
    "eps_alpha": 1.463, "eps_beta": 1.421,
    "K_v": 1.092, "K_Hbeta": 1.15, "K_Fbeta": 1.136, "K_Halpha": 1.069,
    "S_H": (1.81, 1.88), "S_F": (3.26, 3.09),
}


@pytest.fixture(scope="module")
def spec():
    return jio.load_sizing_spec(str(EXAMPLE))[0]


@pytest.fixture(scope="module")
def table(spec):
    return js.size(spec)


def _published_row(columns) -> int:
    rows = np.flatnonzero((np.abs(columns["normal_module_m"] - M_N) < 1e-12)
                          & (columns["z1"] == Z1) & (columns["z2"] == Z2))
    assert rows.size == 1, rows
    return int(rows[0])


def test_the_example_states_the_published_requirements(spec):
    """The example's spec is the task as published: load, ratio, material, life, K_A, the
    required safety, the method, accuracy, lubricant, roughness, the basic rack and angles."""
    s = spec.settings
    omega = SPEED_RPM * math.pi / 30
    assert float(spec.operating.speed) == pytest.approx(omega, rel=1e-15)
    assert float(spec.operating.torque) == pytest.approx(POWER_W / omega, rel=1e-14)
    assert float(spec.operating.torque) == pytest.approx(TORQUE_NM, rel=2e-5)  # its rounding
    assert spec.ratio == RATIO and abs(Z2 / Z1 / RATIO - 1) < 1e-4
    np.testing.assert_array_equal(s.material.sigma_h_lim, [SIGMA_H_LIM] * 2)
    np.testing.assert_array_equal(s.material.sigma_f_lim, [SIGMA_F_LIM] * 2)
    assert isinstance(s.material.treatment, jr.CaseHardened)
    assert float(s.material.youngs_modulus) == E_MODULUS
    assert float(s.material.poisson_ratio) == POISSON
    assert float(s.application_factor) == K_A
    assert float(s.life) == pytest.approx(LIFE_H * 3600, rel=1e-15)
    assert (float(s.min_safety_pitting), float(s.min_safety_bending)) == (S_H_MIN, S_F_MIN)
    assert isinstance(s.standard, jr.Edition2006) and s.accuracy.grade == GRADE
    assert float(s.lubrication.viscosity_40) == pytest.approx(NU_40, rel=1e-15)
    np.testing.assert_allclose(s.lubrication.roughness_flank, [RZ_FLANK] * 2, rtol=1e-15)
    np.testing.assert_allclose(s.lubrication.roughness_root, [RZ_ROOT] * 2, rtol=1e-15)
    assert float(s.tip_relief) == pytest.approx(TIP_RELIEF, rel=1e-15)
    assert spec.normal_pressure_angle == pytest.approx(math.radians(ALPHA_N), rel=1e-15)
    assert spec.helix_angle == pytest.approx(math.radians(BETA), rel=1e-15)
    assert (spec.dedendum_coeff, spec.fillet_radius_coeff) == RACK[:2]
    assert spec.addendum_coeff == pytest.approx(RACK[2] + TIP_ALTERATION / M_N, rel=1e-15)
    assert spec.profile_shift == (X1, X2)


def test_the_published_design_is_enumerated(spec):
    """The published m_n, z1/z2 is a candidate, with the published shifts and face width; its
    centre distance, the zero-backlash distance of Table V's shifts (printed to three
    decimals), is Table V's 861 mm to 1.2 µm (the report's x2 0.6691 gives 861.000)."""
    c = js.enumerate_candidates(spec)
    k = _published_row({"normal_module_m": c.normal_module, "z1": c.z1, "z2": c.z2})
    assert (c.x1[k], c.x2[k], c.face_width[k]) == (X1, X2, FACE_WIDTH)
    assert abs(c.centre_distance[k] - CENTRE_DISTANCE) < 1.2e-6


# default tier: tests/test_sizing.py::test_a_written_candidate_rates_to_the_tables_numbers (a
# row's geometry and rating against the case reader's, on the small spec's compiled program)
@pytest.mark.slow
def test_the_published_design_rates_to_its_published_rating(table):
    """The published design's row against the report. Geometry to the printed digits: half a
    unit of the last (0.5 µm, 5e-4), plus, on the wheel, what the fourth decimal of x2 (0.6691
    in the report, 0.669 here) moves: 2.8 µm on its diameters, 0.2 µm on its tip thickness.

    The load factors are where the two differ, by what each states: the report's K_v (1.092)
    has a gear body factor C_R = 0.898 for its bored blanks, jaxgear's ISO 6336-1 method B
    solid blanks (a higher K_v, under 1 %); its K_Hβ (1.15) is given by the user, jaxgear's is
    ISO's method B at grade 6 with no shaft deflection (within 0.5 %); its K_Hα (1.069) comes
    from deviations and running-in it does not print, jaxgear's from grade 6's tolerances
    (lower, by under 3 %). So jaxgear's safety factors are higher, by up to 3 %; with the
    report's factors put back (S_H ∝ (K_v K_Hβ K_Hα)^-1/2, S_F ∝ (K_v K_Fβ K_Fα)^-1, K_Fα =
    K_Hα, K_Fβ = K_Hβ^N_F with N_F = (b/h)²/(1 + b/h + (b/h)²), ISO 6336-1 clause 7) every
    other factor of the chain must agree: within 0.5 % (the printed 1.81 is ±0.28 %)."""
    c, k = table.columns, _published_row(table.columns)
    assert table.feasible[k] and table.reasons()[k] == ""
    mm = lambda name: np.array([c[f"{name}_{i}_m"][k] for i in (1, 2)]) * 1e3
    for name in ("reference_diameter", "tip_diameter", "root_diameter", "tip_thickness"):
        moved = 2.8e-3 if name != "tip_thickness" else 0.2e-3
        off = np.abs(mm(name) - PRINTED[name])
        assert off[0] <= 0.5e-3 + 1e-9 and off[1] <= 0.5e-3 + moved, (name, off)
    for name in ("eps_alpha", "eps_beta"):
        assert abs(c[name][k] - PRINTED[name]) <= 5e-4 + 1e-5, name
    kv, khb, kha = (c[n][k] for n in ("K_v", "K_Hbeta", "K_Halpha"))
    assert 0 < kv / PRINTED["K_v"] - 1 < 0.01
    assert abs(khb / PRINTED["K_Hbeta"] - 1) < 0.005
    assert -0.03 < kha / PRINTED["K_Halpha"] - 1 < 0
    s_h = np.array([c["S_H1"][k], c["S_H2"][k]])
    s_f = np.array([c["S_F1"][k], c["S_F2"][k]])
    b_h = FACE_WIDTH / ((c["tip_diameter_1_m"][k] - c["root_diameter_1_m"][k]) / 2)
    n_f = b_h**2 / (1 + b_h + b_h**2)
    # the report's K_Fβ from its K_Hβ by the same exponent (it prints 1.136 for 1.1365)
    assert PRINTED["K_Hbeta"] ** n_f == pytest.approx(PRINTED["K_Fbeta"], rel=1e-3)
    h = math.sqrt(kv * khb * kha / (PRINTED["K_v"] * PRINTED["K_Hbeta"] * PRINTED["K_Halpha"]))
    f = (kv * khb**n_f * kha) / (PRINTED["K_v"] * PRINTED["K_Fbeta"] * PRINTED["K_Halpha"])
    np.testing.assert_allclose(s_h * h, PRINTED["S_H"], rtol=5e-3)
    np.testing.assert_allclose(s_f * f, PRINTED["S_F"], rtol=5e-3)
    assert np.all(s_h >= PRINTED["S_H"]) and np.all(s_h / PRINTED["S_H"] - 1 < 0.03)
    assert np.all(s_f >= PRINTED["S_F"]) and np.all(s_f / PRINTED["S_F"] - 1 < 0.03)


# default tier: tests/test_sizing.py::test_jaxgear_size_writes_the_table_and_a_candidate (a
# row written as a case file) and test_a_written_candidate_rates_to_the_tables_numbers
@pytest.mark.slow
def test_the_published_row_written_as_a_case_is_the_published_pair(spec, table):
    """``--write`` of the published row gives the pair of the embedded case ``nrel-5mw-stage3``
    (Table V's design, typed separately from the report and the paper): the same members and
    tooth form, the same flanks and tips; its centre distance the zero-backlash one of the
    shifts, the case's Table V 861 mm to 1.2 µm."""
    tables = jio.load_sizing_spec(str(EXAMPLE))[1]
    k = _published_row(table.columns)
    row = {name: v[k] for name, v in table.columns.items()}
    written = jio.parse_case(tomllib.loads(jio.candidate_case_text(tables, spec, row, k))).pair
    published = jio.load_case("nrel-5mw-stage3").pair
    for member in ("pinion", "gear"):
        assert getattr(written, member) == getattr(published, member), member
    for name in ("normal_module", "normal_pressure_angle", "helix_angle"):
        assert float(getattr(written, name)) == pytest.approx(
            float(getattr(published, name)), rel=1e-15), name
    np.testing.assert_allclose(written.tip_radii, published.tip_radii, rtol=1e-15)
    np.testing.assert_allclose(written.root_radii, published.root_radii, rtol=1e-15)
    assert abs(float(written.center_distance) - float(published.center_distance)) < 1.2e-6


# default tier: tests/test_sizing.py::test_rejections_agree_with_the_pairs_own_checks (the
# minimum safety factors reject) and test_a_written_candidate_rates_to_the_tables_numbers
# (ranked lightest first among the feasible)
@pytest.mark.slow
def test_with_its_own_safety_factors_as_minimums_the_published_design_is_the_lightest(spec, table):
    """At the required minimums (S_Hmin 1.25, S_Fmin 1.56) lighter candidates meet them (the
    published stage holds 45 % and 98 % more); with the minimums raised to the published
    design's printed least safety factors (1.81, 3.09) the lightest feasible candidate, by
    the blank mass, is the published design (the next, 16 mm 21/83, is 0.1 % heavier: a change
    of the blank model may swap them)."""
    k = _published_row(table.columns)
    mass = table.columns["mass_kg"]
    assert table.feasible[k] and np.any(table.feasible & (mass < mass[k]))
    settings = eqx.tree_at(lambda s: (s.min_safety_pitting, s.min_safety_bending),
                           spec.settings, (min(PRINTED["S_H"]), min(PRINTED["S_F"])))
    raised = js.size(dataclasses.replace(spec, settings=settings))
    assert int(raised.ranked()[0]) == k
