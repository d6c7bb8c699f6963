"""The internal pair's rating rules (jaxgear.rating.InternalRatingGeometry) against references
written here independently: a rack tooth drawn point by point (ISO 6336-3's substitute rack of an
internal gear), the ring's involute flank and load line drawn in the plane (the load point, its
direction α_Fen and the bending moment arm h_Fe), the single pair contact factor from the
internal pair's own relative radius of curvature (jaxgear.relative_radius of the NumPy pair),
the work hardening factor's formula, and the gradients of S_H and S_F against central
differences. The published values (KISSsoft reports of the NREL 5 MW ring meshes) are in
tests/test_rating_kisssoft.py."""

import math

import equinox as eqx
import jax
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr

MM = 1e-3
RATE = eqx.filter_jit(jr.rate)


def _pair(zp=36, zr=-93, xp=0.5039, xr=0.1171, mn=21.0, k=-1.75, b=550.0, rho_ring=0.30, ha=1.0):
    planet = jg.Member(
        zp, xp, addendum_coeff=ha + k / mn, dedendum_coeff=1.25, fillet_radius_coeff=0.38,
        face_width=b * MM,
    )
    ring = jg.Member(zr, xr, dedendum_coeff=1.25, fillet_radius_coeff=rho_ring, face_width=b * MM)
    return jg.InternalGearPair(planet, ring, mn * MM, math.radians(20.0))


def _settings(pair):
    return jr.RatingSettings(
        material=jr.RatingMaterial(
            (1500e6, 700e6), (430e6, 290e6),
            treatment=jr.PairTreatment(jr.CaseHardened(), jr.ThroughHardened(brinell_hardness=240.0)),
        ),
        lubrication=jr.Lubrication(220e-6, 4.8e-6, 20e-6),
        accuracy=jr.GearAccuracy.from_grade(pair, 6),
        life=20_000 * 3600.0,
        application_factor=1.25,
    )


def test_substitute_rack_section_is_the_drawn_rack_tooth_at_its_60_degree_tangent():
    """s_Fn and the chord's depth of jg.rating.SubstituteRack against a rack tooth drawn here: the
    flank line at α_n through half a pitch's quarter at the reference line, the tip rounding
    ρ_fP found as the circle tangent to that line and to the root line, sampled, and the point
    where its tangent makes 60° with the centre line located by interpolation."""
    mn, an, hfp, rfp = 21.0, math.radians(20.0), 1.25 * 21.0, 0.30 * 21.0
    # v down from the reference line (root at v = hfp), u from the tooth centre line
    v_c = hfp - rfp
    # the centre lies at distance rfp from the flank u = π m/4 + v tan α on the space side
    n = np.array([math.cos(an), -math.sin(an)])  # unit normal of the flank line (u, v)
    u_c = (rfp + n @ np.array([math.pi * mn / 4, 0.0]) - n[1] * v_c) / n[0]
    t = np.linspace(0.0, math.pi / 2, 200001)  # the arc from the root (t = 0) up the fillet
    u, v = u_c - rfp * np.sin(t), v_c + rfp * np.cos(t)
    slope = np.degrees(np.arctan2(-np.gradient(v), -np.gradient(u)))  # against the root line
    i = np.argmin(np.abs(slope - 30.0))  # 30° to the root line = 60° to the centre line
    s_drawn, depth_drawn = 2 * u[i], hfp - v[i]
    pair = _pair()
    geometry = jr.InternalRatingGeometry.of(pair)
    s_fn, rho_f, d_s = jg.rating.SubstituteRack().section(geometry, geometry.derived())
    assert float(s_fn) == pytest.approx(s_drawn * MM, rel=1e-6)
    assert float(rho_f) == pytest.approx(rfp * MM, rel=1e-12)
    assert float((2 * pair.root_radii[1] - d_s) / 2) == pytest.approx(depth_drawn * MM, rel=1e-4)


@pytest.mark.parametrize("zr, xr", [(-93, 0.1171), (-56, -0.5013)])
def test_ring_load_direction_and_moment_arm_against_the_drawn_flank(zr, xr):
    """α_Fen and h_Fe of the internal gear against a construction in the plane: the load point
    on the ring's flank at its outer point of single contact (from the path of contact of the
    NumPy pair: the pinion's tip roll less one base pitch, the ring's roll a_w sin α_wt
    further), placed on the ring's involute (tooth half angle s_t/d + inv α_y − inv α_t, the
    internal tooth widening outward), the load line tangent to the base circle through it, its
    crossing with the tooth centre line, and the chord of a given section."""
    zp = 36 if zr == -93 else 17
    pair = _pair(zp=zp, zr=zr, xp=0.5039 if zr == -93 else 0.8021, xr=xr,
                 mn=21.0 if zr == -93 else 45.0, k=-1.75 if zr == -93 else -10.861)
    mn = pair.normal_module
    section = (2.7 * mn, 0.42 * mn, 2 * pair.root_radii[1] - 0.2 * mn)
    geometry = jr.InternalRatingGeometry.of(pair, jg.rating.GivenRootSection(*section))
    form = jg.rating.tooth_form_factors(geometry)
    # drawn: the load point
    rb1, rb2 = pair.base_radii
    roll1 = math.sqrt(pair.tip_radii[0] ** 2 - rb1**2) - pair.base_pitch
    roll2 = roll1 + pair.center_distance * math.sin(pair.operating_pressure_angle)
    r_en = math.hypot(roll2, rb2)
    a_en = math.acos(rb2 / r_en)
    inv = lambda a: math.tan(a) - a  # noqa: E731
    psi = pair.reference_thickness[1] / (2 * pair.pitch_radii[1]) + inv(a_en) - inv(
        pair.transverse_pressure_angle
    )
    p = r_en * np.array([math.sin(psi), math.cos(psi)])
    # the base-circle tangent point of the flank's normal, the one beyond P (the involute of
    # a ring's right flank unwinds from larger polar angles)
    tang = rb2 * np.array([math.sin(psi + a_en), math.cos(psi + a_en)])
    d = tang - p
    incline = math.atan2(-d[1], d[0])  # the load line against the centre line's normal
    y_cross = p[1] - p[0] * d[1] / d[0]  # where the line meets the centre line u = 0
    y_chord = math.sqrt((section[2] / 2) ** 2 - (section[0] / 2) ** 2)
    assert abs(math.degrees(float(form.alpha_Fen[1]) - incline)) < 1e-9
    assert float(form.h_Fe[1]) == pytest.approx(y_chord - y_cross, rel=1e-9)
    assert float(form.s_Fn[1]) == section[0]


def test_single_pair_factor_from_the_pairs_own_relative_curvature():
    """Z_B of the pinion = max(1, √(R(C)/R(B))) with R = jaxgear.relative_radius of the NumPy
    InternalGearPair (ρ1ρ2/(ρ2 − ρ1)) at the pitch point C and at the pinion's inner point of
    single contact B (its tip less one base pitch); a pair with the pitch point inside the path
    (M₁ > 1) and the NREL ring mesh (the path entirely above the pinion's pitch circle, Z_B = 1);
    Z_D = 1."""
    for pair in (_pair(zp=20, zr=-60, xp=0.0, xr=-0.5, mn=3.0, k=0.0, b=30.0, ha=0.8), _pair()):
        geometry = jr.InternalRatingGeometry.of(pair)
        ours = np.asarray(geometry.single_pair_factors(geometry.derived()))
        rb1 = pair.base_radii[0]
        s_c = rb1 * math.tan(pair.operating_pressure_angle) - pair.start_roll
        s_b = math.sqrt(pair.tip_radii[0] ** 2 - rb1**2) - pair.base_pitch - pair.start_roll
        r = np.asarray(jg.relative_radius(pair, np.array([s_c, s_b])))
        np.testing.assert_allclose(ours, [max(1.0, math.sqrt(r[0] / r[1])), 1.0], rtol=1e-10)
    assert math.sqrt(r[0] / r[1]) < 1.0  # the NREL mesh
    first = jr.InternalRatingGeometry.of(_pair(zp=20, zr=-60, xp=0.0, xr=-0.5, mn=3.0, k=0.0, b=30.0, ha=0.8))
    assert float(first.single_pair_factors(first.derived())[0]) > 1.0


def test_work_hardening_factor_of_a_soft_ring_against_a_hardened_planet():
    """Z_W = 1.2 − (HB − 130)/1700 for the through-hardened gear against a case-hardened one,
    1 for the hardened gear, and 1 for two through-hardened gears (ISO 6336-2)."""
    soft = jr.ThroughHardened(brinell_hardness=240.0)
    both = np.asarray(jr.PairTreatment(jr.CaseHardened(), soft).work_hardening_factors())
    np.testing.assert_allclose(both, [1.0, 1.2 - 110.0 / 1700.0], rtol=1e-15)
    np.testing.assert_allclose(soft.work_hardening_factors(), [1.0, 1.0])
    np.testing.assert_allclose(jr.CaseHardened().work_hardening_factors(), [1.0, 1.0])


# default tier: tests/test_rating_cutter.py::test_rating_derivative_through_the_cutter_section_against_central_differences
# (the internal pair's rating derivative, its ring section from the cutter) and
# tests/test_rating.py::test_safety_factor_gradients_match_central_differences
@pytest.mark.slow
def test_internal_rating_gradients_match_central_differences():
    """dS_H/dx1 and dS_F/dx1 (planet and ring) of the internal pair by jax.grad against central
    differences (float64; K_v, K_Hβ, K_Hα computed by ISO 6336-1 method B, the substitute rack
    for the ring)."""
    pair = _pair(zp=20, zr=-60, xp=0.1, xr=-0.5, mn=3.0, k=0.0, b=30.0, ha=0.8)
    geometry = jr.InternalRatingGeometry.of(pair)
    settings = _settings(pair)
    op = jr.OperatingPoint(150.0, 150.0)

    def safety(x1):
        g = geometry.replace(profile_shift=jax.numpy.stack([x1, geometry.profile_shift[1]]))
        r = jr.rate(g, op, settings)
        return jax.numpy.concatenate([r.pitting.S_H, r.bending.S_F])

    x1 = geometry.profile_shift[0]
    # one compiled function: the values (for the differences) and the forward derivative
    both = jax.jit(lambda x: jax.jvp(safety, (x,), (jax.numpy.ones_like(x),)))
    grad = np.asarray(both(x1)[1])
    h = 1e-6
    fd = (np.asarray(both(x1 + h)[0]) - np.asarray(both(x1 - h)[0])) / (2 * h)
    np.testing.assert_allclose(grad, fd, rtol=1e-6, atol=1e-9)
    assert np.all(np.abs(grad) > 0)


def test_rate_refuses_what_is_no_rating_geometry_in_one_line():
    pair = _pair()
    with pytest.raises(ValueError, match=r"^rate: geometry = .*InternalRatingGeometry$"):
        jr.rate(pair, jr.OperatingPoint(1.0, 1.0), _settings(pair))
    with pytest.raises(ValueError, match=r"root_section"):
        jr.InternalRatingGeometry.of(pair, "rack")
    with pytest.raises(ValueError, match=r"s_Fn"):
        jg.rating.GivenRootSection(-1.0, 1.0, 1.0)


STAGE2_RATING = """
[rating]
application_factor = 1.25
K_gamma = 1.10
K_v = 1.0612
K_Hbeta = 1.15
K_Halpha = 1.0
K_Falpha = 1.0
life_h = 175200.0
viscosity_40C_mm2_s = 220.0
roughness_Rz_flank_um = { sun2 = 4.8, planet2 = 4.8, ring2 = 8.0 }
roughness_Rz_root_um = 20.0
edition = 2006

[rating.sun2-planet2]
K_Hbeta = 2.06
"""


def _rated_stage2(tmp_path, extra=STAGE2_RATING):
    """The embedded nrel-5mw-stage2 (the report's materials' strengths) with its [rating] table
    replaced by ``extra`` (the report's load factors given)."""
    text = jio.embedded_case_text("nrel-5mw-stage2")
    text = text[: text.index("\n[rating]")] + "\n"
    path = tmp_path / "stage2.toml"
    path.write_text(text + extra)
    return jio.load_case(str(path))


def test_planetary_stage_rates_both_meshes_per_planet_path_with_k_gamma(tmp_path):
    """``jaxgear run``'s rating of a planetary stage (jaxgear.cli.planetary.rating_section) on
    the embedded NREL 5 MW stage 2 with the KISSsoft report's load factors (K_A 1.25, K_γ 1.10,
    K_v 1.0612, K_Hβ 2.06 and 1.15, K_Hα = K_Fα = 1, 2006 edition): the load path (the sun's torque per
    planet, the speeds relative to the carrier, K_γ in the load) gives the report's σ_H0 and
    σ_H of both meshes within 0.5 % (sun/planet 573.40, [1071.17, 994.13]; planet/ring 312.44,
    404.76 N/mm²; the case's ring x is 0.1168 where the report has 0.1171); the ring is rated
    as an internal gear; rating.md has a table per mesh."""
    from jaxgear.cli.planetary import rating_section

    case = _rated_stage2(tmp_path)
    sec = rating_section(case, str(tmp_path), 1.0)
    assert sec["meshes"] == ["sun2-planet2", "planet2-ring2"]
    assert sec["K_gamma"]["value"] == [1.10, 1.10] and sec["K_gamma"]["source"] == ["given"] * 2
    np.testing.assert_allclose(
        np.asarray(sec["pitting"]["sigma_H0_Pa"]) / 1e6, [573.40, 312.44], rtol=5e-3
    )
    np.testing.assert_allclose(
        np.asarray(sec["pitting"]["sigma_H_Pa"]) / 1e6,
        [[1071.17, 994.13], [404.76, 404.76]],
        rtol=5e-3,
    )
    assert sec["pitting"]["Z_BD"][1][1] == 1.0  # Z_D of the ring
    md = (tmp_path / "rating.md").read_text()
    assert "mesh sun2-planet2" in md and "mesh planet2-ring2" in md and "| K_γ | 1.100 (given) |" in md


def test_planetary_rating_takes_the_stages_k_gamma_when_not_given(tmp_path):
    """Without ``[rating] K_gamma`` the section rates with the K_γ passed in (the run's planar
    load sharing) and names its source; σ_H scales with √K_γ (K_γ multiplies the load as K_A,
    the load factors given)."""
    from jaxgear.cli.planetary import K_GAMMA_SOURCE, rating_section

    free = _rated_stage2(tmp_path, STAGE2_RATING.replace("K_gamma = 1.10\n", ""))
    sec = rating_section(free, str(tmp_path), 1.21)
    assert sec["K_gamma"] == {"value": [1.21, 1.21], "source": [K_GAMMA_SOURCE] * 2,
                              "contact_model": [jg.rating.MESH_SPRINGS] * 2}
    np.testing.assert_allclose(
        np.asarray(sec["pitting"]["sigma_H_Pa"]) / 1e6,
        np.sqrt(1.21 / 1.10) * np.array([[1071.17, 994.13], [404.76, 404.76]]),
        rtol=5e-3,
    )


def test_planetary_rating_refused_in_one_line_before_work(tmp_path):
    """A [rating] key of a train's that a planetary stage does not know, and K_gamma out of its
    range, name the key in one line at load time."""
    with pytest.raises(ValueError, match=r"K_gamma"):
        _rated_stage2(tmp_path, STAGE2_RATING.replace("K_gamma = 1.10", "K_gamma = 0.5"))
    with pytest.raises(ValueError, match=r"wrong_key"):
        _rated_stage2(tmp_path, STAGE2_RATING.replace("edition", "wrong_key = 1.0\nedition"))


# default tier: tests/test_rating_internal.py::test_planetary_stage_rates_both_meshes_per_planet_path_with_k_gamma
# (rating_section of a stage against its report, 0.5 %); Y_δrelT by hand from proof_stress_MPa:
# tests/test_rating_slip_layer.py::test_case_key_proof_stress_selects_rho_and_y_delta_rel_t
@pytest.mark.slow
def test_nrel_stage1_case_is_rated_as_the_report(tmp_path):
    """The embedded nrel-5mw-planetary's ``[rating]`` (the KISSsoft report of stage 1: the
    strengths, per-gear treatments, K_A, life, oil, roughness, profiles A and B, the 2006
    edition; the ring's root section from the report's pinion-type cutter, z0 = 36) through
    ``jaxgear run``'s rating section with the report's K_γ = 1.10: the nominal stresses that
    do not depend on the ring's section are the report's within 0.5 % (σ_H0 759.92 and 588.62,
    σ_F0 of the sun mesh 113.46 and 108.94, of the planet in the ring mesh 95.70 N/mm²; the
    case's ring x is −0.5012, the report's −0.5013), the ring's σ_F0 is the cutter section's
    (17.9 % over the report's 95.32, tests/test_rating_kisssoft.py); rating.md has a table
    per mesh. The ring's Y_δrelT: ISO 6336-3's (1 + √(ρ' χ*))/(1 + √(ρ' χ*_T)) by hand at the
    case's yield point (proof_stress_MPa = 1000: ρ' = 0.0014 mm) with the rating's q_s
    (1e-12), and over the printed 1.003 by under 1.1 % (the cutter section's ρ_F, 39 % under
    the printed, raises its q_s: with the printed section it is 1.0026, as printed)."""
    from jaxgear.cli.planetary import rating_section

    case = jio.load_case("nrel-5mw-planetary")
    sec = rating_section(case, str(tmp_path), 1.10)
    assert sec["meshes"] == ["sun1-planet1", "planet1-ring1"]
    np.testing.assert_allclose(
        np.asarray(sec["pitting"]["sigma_H0_Pa"]) / 1e6, [759.92, 588.62], rtol=5e-3
    )
    sigma_f0 = np.asarray(sec["bending"]["sigma_F0_Pa"]) / 1e6
    np.testing.assert_allclose(sigma_f0[0], [113.46, 108.94], rtol=5e-3)
    assert sigma_f0[1][0] == pytest.approx(95.70, rel=5e-3)
    assert sigma_f0[1][1] == pytest.approx(95.32 * 1.179, rel=5e-3)
    md = (tmp_path / "rating.md").read_text()
    assert "mesh sun1-planet1" in md and "mesh planet1-ring1" in md
    ring = jio.ratings_of(case)[1]
    assert ring.settings.material.treatment.gear.slip_layer == pytest.approx(0.0014e-3)
    q_s = float(jr.rate(ring.geometry, ring.operating, ring.settings).bending.form.q_s[1])
    rho = 0.0014  # mm
    by_hand = (1 + math.sqrt(rho * (1 + 2 * q_s) / 5)) / (1 + math.sqrt(rho * 1.2))
    y_delta = sec["bending"]["Y_delta_rel_T"][1][1]
    assert y_delta == pytest.approx(by_hand, rel=1e-12)
    assert 1.0 < y_delta / 1.003 < 1.011

