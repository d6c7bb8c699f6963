"""ISO 6336-3 bending (and ISO 6336-2 pitting) against a published commercial calculation report.

Source: three KISSsoft reports (KISSsoft Release 03/2017 A, "Calculation method ISO 6336:2006
Method B"), published with the NREL 5 MW reference gearbox model in the public repository
gfsReboucas/Drivetrain (commit 4a88df348fc70d04254c84bd375bb2bab0d15d0d), files
``@NREL_5MW/stage_03.rtf`` (the helical parallel stage: z 24/95, m_n 14 mm, β 10°, the stage the
load-capacity issue calls "a wind-turbine helical stage rated by a commercial code"),
``@NREL_5MW/stage_02.rtf`` and ``@NREL_5MW/stage_01.rtf`` (spur planetary stages; their
external sun/planet meshes). The printed values are typed in below with the report's rounding;
each is asserted within 0.5 % (the issue's tolerance; a value printed with three digits, e.g.
Y_F = 1.18, carries up to 0.42 % of rounding).

The report rates to the 2006 edition, so the rating runs with ``jg.rating.Edition2006()`` (Y_β =
1 − ε_β β/120°); the report's own load factors K_v = 1.092, K_Hβ = 1.15 (user specified there),
K_Hα = K_Fα = 1.069 are given (its K_v comes from a gear body factor C_R = 0.898 and bored blanks,
which jaxgear's method B K_v does not model), and K_Fβ = 1.136 is computed from K_Hβ.
The tip diameters are the report's (its tip alteration k m_n enters as the addendum
coefficient 1 + k) and the centre distance is the zero-backlash one of the nominal profile
shifts (the report's a = 861 mm and 584 mm carry tooth thickness allowances).
"""

import math

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.rating as jr

RPM = 2 * math.pi / 60
RATE = eqx.filter_jit(jr.rate)


def _pair(z, x, mn_mm, beta_deg, tip_alteration_mm, face_mm, rho_fp=0.38):
    m = {
        "addendum_coeff": 1.0 + tip_alteration_mm / mn_mm,
        "dedendum_coeff": 1.25,
        "fillet_radius_coeff": rho_fp,
        "face_width": face_mm * 1e-3,
    }
    return jg.GearPair(
        jg.Member(z[0], x[0], **m),
        jg.Member(z[1], x[1], **m),
        mn_mm * 1e-3,
        math.radians(20.0),
        math.radians(beta_deg),
    )


def _stage_03():
    """stage_03.rtf: 5000 kW, n_1 1165.9 1/min, T_1 40 953 N·m, K_A 1.25, 175 200 h,
    18CrNiMo7-6 case-hardened (σ_Hlim 1500, σ_Flim 430 N/mm²), ν_40 220 mm²/s, R_z 4.8 µm
    flank and 20 µm root, ISO 53 profile A (1.25/0.38/1.0), S_Hmin 1.25, S_Fmin 1.56."""
    pair = _pair((24, 95), (0.48, 0.6691), 14.0, 10.0, -0.938, 360.0)
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 430e6, 206e9, 0.3, 7830.0, jr.CaseHardened()),
        lubrication=jr.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=175_200 * 3600.0,
        application_factor=1.25,
        given=jr.GivenFactors(K_v=1.092, K_Hbeta=1.15, K_Halpha=1.069, K_Falpha=1.069),
        min_safety_pitting=1.25,
        min_safety_bending=1.56,
        standard=jg.rating.Edition2006(),
    )
    return pair, settings, jr.OperatingPoint(40953.0, 1165.9 * RPM)


MN3 = 14e-3
# (symbol, printed value(s) [gear 1, gear 2] or scalar, how to read it from the rating)
STAGE_03_PRINTED = [
    # 1. geometry
    ("eps_alpha", 1.463, lambda r, p: p.transverse_contact_ratio),
    ("eps_beta", 1.421, lambda r, p: p.overlap_ratio),
    ("z_n", [25.037, 99.104], lambda r, p: r.bending.form.virtual_teeth),
    # 2. factors
    ("K_Fbeta", 1.136, lambda r, p: r.factors.K_Fbeta),
    ("N_L (1e6)", [12255.788, 3096.199], lambda r, p: r.pitting.cycles / 1e6),
    # 3. tooth root strength
    ("Y_F", [1.18, 1.24], lambda r, p: r.bending.Y_F),
    ("Y_S", [2.28, 2.35], lambda r, p: r.bending.Y_S),
    ("alpha_Fen (deg)", [23.89, 22.20], lambda r, p: np.degrees(r.bending.form.alpha_Fen)),
    ("h_F (mm)", [14.06, 16.11], lambda r, p: r.bending.form.h_Fe * 1e3),
    ("s_Fn (mm)", [31.18, 32.75], lambda r, p: r.bending.form.s_Fn * 1e3),
    ("rho_F (mm)", [5.95, 5.39], lambda r, p: r.bending.form.rho_F * 1e3),
    ("h_F*", [1.004, 1.151], lambda r, p: r.bending.form.h_Fe / MN3),
    ("s_Fn*", [2.227, 2.340], lambda r, p: r.bending.form.s_Fn / MN3),
    ("rho_F*", [0.425, 0.385], lambda r, p: r.bending.form.rho_F / MN3),
    ("q_s", [2.620, 3.036], lambda r, p: r.bending.form.q_s),
    ("Y_beta", 0.917, lambda r, p: r.bending.Y_beta),
    ("Y_DT", 1.0, lambda r, p: r.bending.Y_DT),
    ("Y_B", [1.0, 1.0], lambda r, p: r.bending.Y_B),
    ("sigma_F0 (N/mm2)", [117.92, 127.69], lambda r, p: r.bending.sigma_F0 / 1e6),
    ("sigma_F (N/mm2)", [195.64, 211.85], lambda r, p: r.bending.sigma_F / 1e6),
    ("Y_delta_rel_T", [1.001, 1.005], lambda r, p: r.bending.Y_delta_rel_T),
    ("Y_R_rel_T", [0.957, 0.957], lambda r, p: r.bending.Y_R_rel_T),
    ("Y_X", [0.910, 0.910], lambda r, p: r.bending.Y_X),
    ("Y_NT", [0.850, 0.870], lambda r, p: r.bending.Y_NT),
    ("Y_ST", 2.0, lambda r, p: r.bending.Y_ST),
    ("sigma_FP (N/mm2)", [408.43, 419.69], lambda r, p: r.bending.sigma_FP / 1e6),
    ("sigma_FG (N/mm2)", [637.15, 654.72], lambda r, p: r.bending.sigma_FG / 1e6),
    ("S_F", [3.26, 3.09], lambda r, p: r.bending.S_F),
    # 4. safety against pitting
    ("Z_H", 2.307, lambda r, p: r.pitting.Z_H),
    ("Z_E", 189.812, lambda r, p: r.pitting.Z_E / 1e3),
    ("Z_eps", 0.827, lambda r, p: r.pitting.Z_epsilon),
    ("Z_beta", 1.008, lambda r, p: r.pitting.Z_beta),
    ("sigma_H0 (N/mm2)", 570.79, lambda r, p: r.pitting.sigma_H0 / 1e6),
    ("Z_B, Z_D", [1.0, 1.0], lambda r, p: r.pitting.Z_BD),
    ("sigma_H (N/mm2)", [739.61, 739.61], lambda r, p: r.pitting.sigma_H / 1e6),
    ("Z_L", 1.020, lambda r, p: r.pitting.Z_L),
    ("Z_v", 1.022, lambda r, p: r.pitting.Z_v),
    ("Z_R", 1.007, lambda r, p: r.pitting.Z_R),
    ("Z_W", 1.0, lambda r, p: r.pitting.Z_W),
    ("Z_X", 1.0, lambda r, p: r.pitting.Z_X),
    ("Z_NT", [0.850, 0.881], lambda r, p: r.pitting.Z_NT),
    ("sigma_HP (N/mm2)", [1070.64, 1109.85], lambda r, p: r.pitting.sigma_HP / 1e6),
    ("sigma_HG (N/mm2)", [1338.30, 1387.31], lambda r, p: r.pitting.sigma_HG / 1e6),
    ("S_H", [1.81, 1.88], lambda r, p: r.pitting.S_H),
]


def test_kisssoft_helical_stage_every_printed_bending_and_pitting_value_within_half_a_percent():
    pair, settings, op = _stage_03()
    rating = RATE(jr.RatingGeometry.of(pair), op, settings)
    bad = {}
    for symbol, printed, get in STAGE_03_PRINTED:
        ours = np.atleast_1d(np.asarray(get(rating, pair), dtype=float))
        want = np.broadcast_to(np.asarray(printed, dtype=float), ours.shape)
        err = ours / want - 1
        if np.any(np.abs(err) > 5e-3):
            bad[symbol] = (ours.tolist(), want.tolist())
    assert not bad, bad
    assert rating.method == "ISO 6336:2006 method B"
    # F_t = 240 064.4 N at the reference circle and v = 20.83 m/s (printed)
    d1 = pair.pitch_radii[0] * 2
    assert 2 * 40953.0 / d1 == pytest.approx(240064.4, rel=1e-4)
    assert 1165.9 * RPM * d1 / 2 == pytest.approx(20.83, rel=5e-4)


def test_2019_edition_differs_from_2006_by_the_helix_factor_alone():
    """The 2019 edition's Y_β carries 1/cos³ β (written from the text as recalled; no printed
    2019 example was found): σ_F0 of the stage is 1/cos³ 10° = 1.0472 times the 2006 one, and
    nothing else of the rating moves."""
    pair, settings, op = _stage_03()
    geometry = jr.RatingGeometry.of(pair)
    old = RATE(geometry, op, settings)
    new = RATE(geometry, op, eqx.tree_at(lambda s: s.standard, settings, jg.rating.Edition2019()))
    ratio = 1 / math.cos(math.radians(10.0)) ** 3
    np.testing.assert_allclose(new.bending.sigma_F0 / old.bending.sigma_F0, ratio, rtol=1e-12)
    np.testing.assert_allclose(new.bending.S_F * ratio, old.bending.S_F, rtol=1e-12)
    np.testing.assert_allclose(new.pitting.S_H, old.pitting.S_H, rtol=1e-14)
    assert new.method == "ISO 6336:2019 method B"


# (report, z, x, m_n mm, tip alteration mm, printed [Y_F, Y_S, h_F*, s_Fn*, ρ_F*, α_Fen °] of
# the sun and of the planet in its mesh with the sun)
SPUR_MESHES = [
    (
        "stage_02.rtf",
        (18, 36),
        (0.389, 0.5039),
        21.0,
        -1.750,
        [[1.47, 2.04, 1.159, 2.132, 0.453, 25.74], [1.38, 2.18, 1.225, 2.271, 0.414, 24.68]],
    ),
    (
        "stage_01.rtf",
        (19, 17),
        (0.617, 0.8021),
        45.0,
        -10.861,
        [[1.56, 2.06, 1.441, 2.248, 0.403, 30.75], [1.44, 2.14, 1.450, 2.314, 0.382, 33.33]],
    ),
]


@pytest.mark.parametrize("report, z, x, mn_mm, k_mm, printed", SPUR_MESHES)
def test_kisssoft_spur_sun_planet_tooth_form_within_half_a_percent(
    report, z, x, mn_mm, k_mm, printed
):
    """Y_F, Y_S and the root section of the external sun/planet mesh of the planetary stages
    (spur, large profile shifts, tip shortening), the report's section 3."""
    pair = _pair(z, x, mn_mm, 0.0, k_mm, 491.0)
    f = jg.rating.tooth_form_factors(jr.RatingGeometry.of(pair))
    mn = mn_mm * 1e-3
    ours = np.stack(
        [f.Y_F, f.Y_S, f.h_Fe / mn, f.s_Fn / mn, f.rho_F / mn, np.degrees(f.alpha_Fen)], -1
    )
    np.testing.assert_allclose(ours, printed, rtol=5e-3, err_msg=report)


def test_life_factors_are_iso_power_laws():
    """ISO 6336-2/-3 write the life factors as power laws of N_L (Z_NT = (5·10⁷/N_L)^0.0307,
    Y_NT = (3·10⁶/N_L)^0.02 for case-hardened steel past the knee): the curve through the
    points reproduces them to the printed exponents' rounding (3e-4), where the former
    interpolation, linear in the factor, was 0.26 % (Y_NT) and 0.33 % (Z_NT) high at 10⁹."""
    t = jr.CaseHardened()
    n = np.array([1e8, 1e9, 3e9])
    np.testing.assert_allclose(t.z_nt(n), (5e7 / n) ** 0.0307, rtol=3e-4)
    np.testing.assert_allclose(t.y_nt(n), (3e6 / n) ** 0.02, rtol=3e-4)


# The whole spur rating of the sun/planet mesh of both planetary stages, the reports' sections
# 1-4. The report rates each planet's mesh with the sun: F_t = T_sun/(p r_sun) with p = 3
# planets, at the speeds relative to the carrier (n_sun − n_carrier = n_sun z_ring/(z_sun +
# z_ring); the report's v and N_L are these), with a load sharing factor K_γ = 1.10 that
# multiplies like K_A (σ_H ∝ √(K_A K_γ K_v K_Hβ K_Hα), σ_F ∝ K_A K_γ K_v K_Fβ K_Fα): jaxgear has
# no K_γ, so it rates with K_A K_γ = 1.375 as its application factor (the same products).
# The sun meets 3 planets a turn (N_L = 3 × turns); the planet's tooth is loaded on alternate
# flanks by the sun and the ring, which the report rates with Y_M = 0.7 (jaxgear's
# ToothLoading). K_Hβ (user specified there) and K_Hα = K_Fα = 1.00 are given; K_Fβ is
# computed. The report's K_v (method B with its own gear body factor C_R = 0.862, which
# jaxgear's K_v does not model) is printed to two digits only (1.06, 1.01), so it is recovered to
# four from two other printed values of the same report, the contact stress at the operating
# pitch circle σ_Hw = σ_H0 √(K_A K_γ K_v K_Hβ K_Hα) and σ_H0: K_v = (σ_Hw/σ_H0)²/(K_A K_γ K_Hβ
# K_Hα) = 1.0612 and 1.0054 (each within the printed K_v's rounding). σ_Hw then checks only
# σ_H0 again, but σ_F (through K_Fβ, not K_Hβ) checks the recovered K_v independently.
def _spur_values(f_t, v, eps_a, alpha_wt, z_n, n_l, k_fb, bending, pitting):
    """The printed values of one report as (symbol, printed, reader) rows."""
    rows = [
        ("F_t (N)", f_t, lambda r, p, o: 2 * o.torque / (2 * p.pitch_radii[0])),
        ("v (m/s)", v, lambda r, p, o: o.speed * p.pitch_radii[0]),
        ("eps_alpha", eps_a, lambda r, p, o: p.transverse_contact_ratio),
        (
            "alpha_wt (deg)",
            alpha_wt,
            lambda r, p, o: np.degrees(jr.RatingGeometry.of(p).derived().operating_pressure_angle),
        ),
        ("z_n", z_n, lambda r, p, o: r.bending.form.virtual_teeth),
        ("N_L (1e6)", n_l, lambda r, p, o: r.pitting.cycles / 1e6),
        ("K_Fbeta", k_fb, lambda r, p, o: r.factors.K_Fbeta),
    ]
    b = ("Y_F", "Y_S", "h_F (mm)", "alpha_Fen (deg)", "s_Fn (mm)", "rho_F (mm)", "Y_beta",
         "Y_DT", "Y_B", "sigma_F0", "sigma_F", "Y_delta_rel_T", "Y_R_rel_T", "Y_X", "Y_NT", "Y_M",
         "Y_ST", "sigma_FP", "sigma_FG", "S_F")
    readers_b = {
        "h_F (mm)": lambda r: r.bending.form.h_Fe * 1e3,
        "alpha_Fen (deg)": lambda r: np.degrees(r.bending.form.alpha_Fen),
        "s_Fn (mm)": lambda r: r.bending.form.s_Fn * 1e3,
        "rho_F (mm)": lambda r: r.bending.form.rho_F * 1e3,
    }
    for name, printed in zip(b, bending, strict=True):
        if name in readers_b:
            get = readers_b[name]
        elif name.startswith("sigma"):
            get = (lambda n: lambda r: getattr(r.bending, n) / 1e6)(name)
        else:
            get = (lambda n: lambda r: getattr(r.bending, n))(name)
        rows.append((name, printed, (lambda g: lambda r, p, o: g(r))(get)))
    h = ("Z_H", "Z_E", "Z_epsilon", "Z_beta", "sigma_H0", "Z_BD", "sigma_H", "Z_L", "Z_v", "Z_R",
         "Z_W", "Z_NT", "Z_X", "sigma_HP", "sigma_HG", "S_H")
    for name, printed in zip(h, pitting, strict=True):
        scale = 1e6 if name.startswith("sigma") else 1e3 if name == "Z_E" else 1.0
        rows.append(
            (name, printed, (lambda n, s: lambda r, p, o: getattr(r.pitting, n) / s)(name, scale))
        )
    return rows


# (report, z (sun, planet), x, m_n mm, k m_n mm, b mm, T_sun N·m, z_ring, K_Hβ,
#  (σ_Hw, σ_H0) N/mm², the printed rows)
def _stage_02_by_default(rows):
    """The report rows, stage 2's (the first) in the default tier and stage 1's in the slow
    tier: the same claim against a second report (its rows, the same code path)."""
    return [rows[0], *(pytest.param(*r, marks=pytest.mark.slow) for r in rows[1:])]



SPUR_REPORTS = [
    (
        "stage_02.rtf",
        (18, 36), (0.389, 0.5039), 21.0, -1.750, 550.0, 162105.5, 93, 2.06, (994.13, 573.40),
        _spur_values(
            285900.438, 4.88, 1.370, 24.169, [18.0, 36.0], [7782.3, 1297.1], 1.94,
            # Y_F, Y_S, h_F, α_Fen, s_Fn, ρ_F, Y_β, Y_DT, Y_B, σ_F0, σ_F, Y_δrelT, Y_RrelT,
            # Y_X, Y_NT, Y_M, Y_ST, σ_FP, σ_FG, S_F
            [[1.47, 1.38], [2.04, 2.18], [24.33, 25.73], [25.74, 24.68], [44.78, 47.70],
             [9.52, 8.69], 1.00, 1.00, [1.00, 1.00], [73.95, 74.21], [209.38, 210.14],
             [0.999, 1.002], [0.957, 0.957], [0.840, 0.840], [0.854, 0.886], [1.0, 0.7], 2.00,
             [377.95, 275.24], [589.60, 429.38], [2.82, 2.04]],
            # Z_H, Z_E, Z_ε, Z_β, σ_H0, Z_B/Z_D, σ_H, Z_L, Z_v, Z_R, Z_W, Z_NT, Z_X, σ_HP, σ_HG,
            # S_H
            [2.25, 189.81, 0.936, 1.000, 573.40, [1.08, 1.00], [1071.17, 994.13], 1.020, 0.982,
             1.007, 1.000, [0.857, 0.905], 1.000, [1036.34, 1094.89], [1295.42, 1368.61],
             [1.21, 1.38]],
        ),
    ),
    (
        "stage_01.rtf",
        (19, 17), (0.617, 0.8021), 45.0, -10.861, 491.0, 999650.9, 56, 1.15, (958.15, 759.92),
        _spur_values(
            779454.877, 1.60, 1.115, 28.118, [19.0, 17.0], [1124.7, 419.0], 1.12,
            [[1.56, 1.44], [2.06, 2.14], [64.83, 65.24], [30.75, 33.33], [101.18, 104.13],
             [18.12, 17.19], 1.00, 1.00, [1.00, 1.00], [113.46, 108.94], [175.90, 168.90],
             [1.003, 1.005], [0.957, 0.957], [0.800, 0.800], [0.888, 0.906], [1.0, 0.7], 2.00,
             [375.71, 268.82], [586.11, 419.35], [3.33, 2.48]],
            [2.06, 189.81, 0.981, 1.000, 759.92, [1.04, 1.05], [996.13, 1002.73], 1.020, 0.961,
             1.024, 1.000, [0.909, 0.937], 1.000, [1094.89, 1128.55], [1368.61, 1410.69],
             [1.37, 1.41]],
        ),
    ),
]


# default tier for stage_01: stage_02's rows (the same claim against the other report)
@pytest.mark.parametrize(
    "report, z, x, mn_mm, k_mm, b_mm, t_sun, z_ring, k_hb, sigma_hw_h0, printed",
    _stage_02_by_default(SPUR_REPORTS),
)
def test_kisssoft_spur_sun_planet_rating_every_printed_value_within_half_a_percent(
    report, z, x, mn_mm, k_mm, b_mm, t_sun, z_ring, k_hb, sigma_hw_h0, printed
):
    """ISO 6336-2 and ISO 6336-3 method B (2006 edition) of a spur pair, every factor and stress
    of the report's sections 1-4 (stage_02: 5000 kW, n_sun 294.5 1/min, T_sun 162 105.5 N·m;
    stage_01: n_sun 47.8 1/min, T_sun 999 650.9 N·m; both 3 planets, K_A 1.25, K_γ 1.10,
    175 200 h, 18CrNiMo7-6 case-hardened σ_Hlim 1500, σ_Flim 430 N/mm², ν_40 220 mm²/s, R_z 4.8
    µm flank and 20 µm root, ISO 53 profile A, grade 6, S_Hmin 1.25, S_Fmin 1.56) within 0.5 %;
    the sun is member 0 (the pinion of the rating), the planet member 1, the planet's values
    those printed for its mesh with the sun."""
    pair = _pair(z, x, mn_mm, 0.0, k_mm, b_mm)
    k_a, k_gamma = 1.25, 1.10
    sigma_hw, sigma_h0 = sigma_hw_h0
    k_v = (sigma_hw / sigma_h0) ** 2 / (k_a * k_gamma * k_hb * 1.0)
    settings = jr.RatingSettings(
        material=jr.RatingMaterial(1500e6, 430e6, 206e9, 0.3, 7830.0, jr.CaseHardened()),
        lubrication=jr.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=175_200 * 3600.0,
        application_factor=k_a * k_gamma,
        given=jr.GivenFactors(K_v=k_v, K_Hbeta=k_hb, K_Halpha=1.0, K_Falpha=1.0),
        min_safety_pitting=1.25,
        min_safety_bending=1.56,
        standard=jg.rating.Edition2006(),
        loading=jr.ToothLoading((3.0, 1.0), (1.0, 0.7)),
    )
    n_sun = 5000e3 / t_sun / RPM  # 1/min, from P = T ω
    n_rel = n_sun * z_ring / (z[0] + z_ring)  # the sun relative to the carrier
    op = jr.OperatingPoint(t_sun / 3, n_rel * RPM)
    rating = RATE(jr.RatingGeometry.of(pair), op, settings)
    bad = {}
    for symbol, value, get in printed:
        ours = np.atleast_1d(np.asarray(get(rating, pair, op), dtype=float))
        want = np.broadcast_to(np.asarray(value, dtype=float), ours.shape)
        if np.any(np.abs(ours / want - 1) > 5e-3):
            bad[symbol] = (ours.tolist(), want.tolist())
    assert not bad, (report, bad)
    assert len(printed) == 43
    assert rating.factors.sources["K_Fbeta"] == "ISO 6336-1 method B"


# The internal planet/ring meshes of the same two reports (sections 1-4, the third column and
# the planet's values after the slash). The ring (gear 3) is 34CrNiMo6 through hardened (σ_Hlim
# 700, σ_Flim 290 N/mm², HB 240, yield point σ_0.2 1000 N/mm², R_z 8.0 µm flank and 20 µm root,
# ISO 53 profile B 1.25/0.30/1.0, no tip alteration); the planet case-hardened as above
# (jg.rating.PairTreatment). Z_W = 1.135 of the ring is ISO 6336-2's work hardening factor of a
# through-hardened gear against a surface-hardened one, 1.2 − (HB − 130)/1700; the ring's ρ'
# (Y_δrelT) comes from its printed yield point through ISO 6336-3's slip-layer table
# (jg.rating.ThroughHardened(proof_stress=1000e6): the row σ_0.2 = 1000 N/mm², ρ' = 0.0014 mm; the
# report's tensile strength, 1200 N/mm², lies outside the table, so the yield point is what
# selects the row: the printed Y_δrelT 1.005 and 1.003 check it). The rating runs at the planet's speed relative to the carrier with the
# planet's torque T_sun/p · z_planet/z_sun (the report's F_t and v are the sun mesh's, the same
# at the reference circles of one module); the planet is member 0, its flank loaded once per
# relative turn here (and by the sun on its other flank: Y_M = 0.7), the ring's tooth p = 3
# times per relative turn of the planet carrier. K_v is recovered as for the sun mesh, from
# the printed σ_Hw/σ_H0 of this mesh (stage_02 prints K_v = max(K_v12, K_v23) = 1.06, stage_01
# K_v = 1.05 for this mesh). The ring's root section (s_Fn, ρ_F, dsFn) is the one the report
# prints from its pinion-type cutter simulation (z0 = 30 and 36, x0 = 0), given with
# jg.rating.GivenRootSection: ISO's substitute rack (jg.rating.SubstituteRack) is cruder; everything else —
# d_en, α_Fen, h_F, Y_F, Y_S, the stresses and all the pitting factors — is computed.
def _ring_values(eps_a, alpha_wt, n_l, k_fb, bending, pitting):
    rows = [
        ("eps_alpha", eps_a, lambda r, p, o: p.transverse_contact_ratio),
        (
            "alpha_wt (deg)",
            alpha_wt,
            lambda r, p, o: np.degrees(
                jr.InternalRatingGeometry.of(p).derived().operating_pressure_angle
            ),
        ),
        ("N_L (1e6)", n_l, lambda r, p, o: r.pitting.cycles / 1e6),
        ("K_Fbeta", k_fb, lambda r, p, o: r.factors.K_Fbeta),
    ]
    return rows + _spur_values(1.0, 1.0, 1.0, 1.0, [1.0, 1.0], 1.0, 1.0, bending, pitting)[7:]


# (report, z (sun, planet, ring), x (planet, ring), m_n mm, planet tip alteration mm, b mm,
#  T_sun N·m, K_Hβ, (σ_Hw, σ_H0) N/mm², the ring's printed (s_Fn, ρ_F, dsFn) mm, rows)
RING_REPORTS = [
    (
        "stage_02.rtf",
        (18, 36, -93), (0.5039, 0.1171), 21.0, -1.750, 550.0, 162105.5, 1.15, (404.76, 312.44),
        (56.76, 8.78, 1998.168),
        _ring_values(
            1.618, 15.630, [1297.1, 1506.3], 1.14,
            [[1.01, 1.20], [2.48, 2.34], [18.48, 30.32], [22.21, 18.63], [47.70, 56.76],
             [8.69, 8.78], 1.00, 1.00, [1.00, 1.00], [61.98, 69.12], [102.77, 114.61],
             [1.002, 1.005], [0.957, 0.957], [0.840, 0.904], [0.886, 0.883], [0.7, 1.0], 2.00,
             [275.24, 285.18], [429.38, 444.89], [4.18, 3.88]],
            [2.85, 189.81, 0.891, 1.000, 312.44, [1.00, 1.00], [404.76, 404.76], 1.038, 0.961,
             1.026, [1.000, 1.135], [0.905, 0.901], 1.000, [1110.71, 585.77], [1388.39, 732.21],
             [3.43, 1.81]],
        ),
    ),
    (
        "stage_01.rtf",
        (19, 17, -56), (0.8021, -0.5013), 45.0, -10.861, 491.0, 999650.9, 1.15, (758.46, 588.62),
        (129.40, 22.24, 2673.522),
        _ring_values(
            1.278, 17.161, [419.0, 381.6], 1.12,
            [[1.14, 1.27], [2.38, 2.13], [49.53, 78.40], [29.87, 19.59], [104.13, 129.40],
             [17.19, 22.24], 1.00, 1.00, [1.00, 1.00], [95.70, 95.32], [154.50, 153.89],
             [1.005, 1.003], [0.957, 0.957], [0.800, 0.850], [0.906, 0.907], [0.7, 1.0], 2.00,
             [268.82, 275.09], [419.35, 429.14], [2.71, 2.79]],
            [2.71, 189.81, 0.952, 1.000, 588.62, [1.00, 1.00], [758.46, 758.46], 1.038, 0.916,
             1.025, [1.000, 1.135], [0.937, 0.940], 1.000, [1095.16, 581.89], [1368.95, 727.36],
             [1.80, 0.96]],
        ),
    ),
]


def ring_mesh_rating(z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section):
    """The planet/ring pair, settings and operating point of one report (comment above)."""
    mm = 1e-3
    planet = jg.Member(
        z[1], x[0], addendum_coeff=1.0 + k_mm / mn_mm, dedendum_coeff=1.25,
        fillet_radius_coeff=0.38, face_width=b_mm * mm,
    )
    ring = jg.Member(
        z[2], x[1], dedendum_coeff=1.25, fillet_radius_coeff=0.30, face_width=b_mm * mm
    )
    pair = jg.InternalGearPair(planet, ring, mn_mm * mm, math.radians(20.0))
    k_a, k_gamma = 1.25, 1.10
    sigma_hw, sigma_h0 = sigma_hw_h0
    k_v = (sigma_hw / sigma_h0) ** 2 / (k_a * k_gamma * k_hb * 1.0)
    treatment = jr.PairTreatment(
        jr.CaseHardened(), jr.ThroughHardened(slip_layer_m=0.0014e-3, brinell_hardness=240.0)
    )
    settings = jr.RatingSettings(
        material=jr.RatingMaterial((1500e6, 700e6), (430e6, 290e6), 206e9, 0.3, 7830.0, treatment),
        lubrication=jr.Lubrication(220e-6, np.array([4.8e-6, 8.0e-6]), 20e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=175_200 * 3600.0,
        application_factor=k_a * k_gamma,
        given=jr.GivenFactors(K_v=k_v, K_Hbeta=k_hb, K_Halpha=1.0, K_Falpha=1.0),
        min_safety_pitting=1.25,
        min_safety_bending=1.56,
        standard=jg.rating.Edition2006(),
        loading=jr.ToothLoading((1.0, 3.0), (0.7, 1.0)),
    )
    n_sun = 5000e3 / t_sun / RPM
    n_carrier = n_sun * z[0] / (z[0] - z[2])  # ring fixed (Willis)
    n_planet = (n_sun - n_carrier) * z[0] / z[1]  # relative to the carrier
    op = jr.OperatingPoint(t_sun / 3 * z[1] / z[0], n_planet * RPM)
    geometry = jr.InternalRatingGeometry.of(pair, jg.rating.GivenRootSection(*(v * mm for v in section)))
    return pair, geometry, op, settings


# default tier for stage_01: stage_02's rows (the same claim against the other report)
@pytest.mark.parametrize(
    "report, z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section, printed",
    _stage_02_by_default(RING_REPORTS),
)
def test_kisssoft_spur_planet_ring_rating_every_printed_value_within_half_a_percent(
    report, z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section, printed
):
    """ISO 6336-2 and -3 method B (2006 edition) of the internal planet/ring mesh: every factor
    and stress the reports print for it (sections 1-4) within 0.5 %, both members."""
    pair, geometry, op, settings = ring_mesh_rating(
        z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section
    )
    rating = RATE(geometry, op, settings)
    bad = {}
    for symbol, value, get in printed:
        ours = np.atleast_1d(np.asarray(get(rating, pair, op), dtype=float))
        want = np.broadcast_to(np.asarray(value, dtype=float), ours.shape)
        if np.any(np.abs(ours / want - 1) > 5e-3):
            bad[symbol] = (ours.tolist(), want.tolist())
    assert not bad, (report, bad)
    assert len(printed) == 40
    # F_t at the reference circles and v: the report's sun-mesh values
    f_t = 2 * op.torque / (z[1] * mn_mm * 1e-3)
    assert float(f_t) == pytest.approx({18: 285900.438, 19: 779454.877}[z[0]], rel=1e-5)
    # the dedendum-side section the report prints as h_F*, s_Fn* (per m_n)
    form = rating.bending.form
    mn = mn_mm * 1e-3
    hstar = {18: [0.880, 1.444], 19: [1.101, 1.742]}[z[0]]
    np.testing.assert_allclose(form.h_Fe / mn, hstar, rtol=5e-3)


# The ring's root section from the reports' own pinion-type cutters (jg.rating.ShaperCutterSection:
# z0 = 30 and 36, x0 = 0, ρ_a0 = 0.3 m_n, the tip circle cutting the ring's root circle, which
# reproduces the reports' root form diameters d_Ff 1987.879 and 2662.682 mm within 0.01 mm,
# tests/test_rating_cutter.py) in place of the printed section: the chord's diameter d_sFn is
# the report's within 0.02 %, s_Fn 1.3 % and 2.1 % over it, but ρ_F 11 % and 39 % under the
# printed 8.78 and 22.24 mm. The printed ρ_F is not the generated fillet's curvature at the 60°
# point (ρ_a0 plus the trochoid's: 7.78 and 13.57 mm; the whole fillet of stage 1 stays within
# 13.5-14.0 mm, the tip rounding's centre passing near the cutting pitch circle), nor the
# rack's ρ_fP (6.3, 13.5 mm), nor the external method B's ρ_F formula with the cutter's or the
# ring's tooth count (tried: none within 4 % for both stages); the report says "calculation of
# roF and sFn according to ISO 6336-3:2007-04-01", whose internal-gear formula was not found.
# So the ring's σ_F0 lies between the report's and the substitute rack's: 3.6 % and 17.9 % over
# the printed 69.12 and 95.32 N/mm² (the rack: 20 % and 37 %), conservative.
CUTTER = {"stage_02.rtf": (30, (56.76, 8.78, 1998.168), 71.60, 83.26),
          "stage_01.rtf": (36, (129.40, 22.24, 2673.522), 112.35, 130.35)}


# default tier for stage_01: stage_02's rows (the same claim against the other report)
@pytest.mark.parametrize(
    "report, z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section, printed",
    _stage_02_by_default(RING_REPORTS),
)
def test_kisssoft_ring_section_from_the_reports_cutter(
    report, z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section, printed
):
    """The ring's root section and σ_F0 from the report's pinion-type cutter against the
    printed ones (comment above: d_sFn within 0.02 %, s_Fn within 2.5 % over, ρ_F under, σ_F0
    the figure stated there within 0.1 %, over the report's and under the substitute rack's);
    the planet's values do not move."""
    z0, (s_fn, rho_f, d_s), sigma_cutter, sigma_rack = CUTTER[report]
    pair, given, op, settings = ring_mesh_rating(
        z, x, mn_mm, k_mm, b_mm, t_sun, k_hb, sigma_hw_h0, section
    )
    geometry = jr.InternalRatingGeometry.of(pair, jg.rating.ShaperCutterSection(z0))
    ours = RATE(geometry, op, settings)
    form = ours.bending.form
    mm = 1e-3
    # d_sFn from the moment arm: h_Fe = √(r_s² − s_Fn²/4) − (the load line's crossing), the
    # crossing the same for every section (tests/test_rating_internal.py draws it)
    g_form = RATE(given, op, settings).bending.form
    cross = np.sqrt((d_s * mm / 2) ** 2 - (s_fn * mm / 2) ** 2) - float(g_form.h_Fe[1])
    d_ours = 2 * np.hypot(float(form.h_Fe[1]) + cross, float(form.s_Fn[1]) / 2) / mm
    assert d_ours == pytest.approx(d_s, rel=2e-4)
    assert 1.0 < float(form.s_Fn[1]) / mm / s_fn < 1.025
    assert float(form.rho_F[1]) / mm < rho_f
    sigma = ours.bending.sigma_F0 / 1e6
    assert float(sigma[1]) == pytest.approx(sigma_cutter, rel=1e-3)
    printed_sigma = float(printed[[r[0] for r in printed].index("sigma_F0")][1][1])
    assert printed_sigma < float(sigma[1]) < sigma_rack
    np.testing.assert_allclose(sigma[0], RATE(given, op, settings).bending.sigma_F0[0] / 1e6,
                               rtol=1e-12)
