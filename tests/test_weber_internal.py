"""Weber's thin-slice model for an internal pair (jaxgear.Weber(ring_cutter=...),
jaxgear.member_compliance on an InternalGearPair's ring) against: a potential-energy beam
integral written here on the generated tooth (the load's line and lever from the contact point
and its involute normal, as in Chen & Shao, Mech. Mach. Theory 2013, for internal teeth;
scipy's adaptive quadrature), the external Weber compliance in the limit of a large ring and
cutter (both tend to the rack tooth), and ISO 6336-1 method B's c_γα with its internal-gear
rule; and its one-line refusals."""

import math

import numpy as np
import pytest
from scipy.integrate import quad

import fem_prep as fp
import jaxgear as jg

A = math.radians(20.0)
E, NU = 206e9, 0.3


def _nrel_stage2(helix=0.0):
    pair = jg.InternalGearPair(
        jg.Member(36, profile_shift=0.5039, face_width=0.55),
        jg.Member(-93, profile_shift=0.1171, face_width=0.55, fillet_radius_coeff=0.3),
        21e-3, A, helix,
    )
    return pair, fp.ShaperCutter(30, 0.0, 0.3)


def _reference_compliance(pair, cutter, rho2):
    """Compliance (m/N per m of face width) of the ring's tooth at roll distance rho2, by the
    potential energy of a plane-strain cantilever on the root circle: the unit load at the
    contact point P along the flank normal (the involute's tangent by central differences, ISO
    21771's internal half angle), the moment about each section's centre M(y) = (P − C(y)) × F,
    the beam from the root circle to the section where M = 0 (Weber's cantilever), bending
    M²/(E' I), shear 1.2 F_b²/(G A), compression F_a²/(E' A), plus Weber's (1.3) half-plane
    term with S the root chord."""
    form = fp.generate_internal_tooth(jg.internal_tooth_geometry(pair, cutter), n_fillet=200)
    rb, rf = pair.base_radii[1], pair.root_radii[1]
    mt, at = pair.transverse_module, pair.transverse_pressure_angle
    s_t = mt * (math.pi / 2 + 2 * pair.gear.profile_shift * math.tan(pair.normal_pressure_angle))

    def flank(r):
        a = math.acos(rb / r)
        psi = s_t / (2 * pair.pitch_radii[1]) - (math.tan(at) - at) + (math.tan(a) - a)
        return np.array([r * math.sin(psi), r * math.cos(psi)])

    r = math.hypot(rho2, rb)
    p = flank(r)
    h = 1e-6 * r
    tangent = flank(r + h) - flank(r - h)
    f = np.array([tangent[1], -tangent[0]]) / np.linalg.norm(tangent)  # unit load
    f_b, f_a = f[0], f[1]  # across and along the centre line

    def moment(yc):  # about the centre line's point at radius yc
        return p[0] * f[1] - (p[1] - yc) * f[0]

    y_cross = p[1] - p[0] * f[1] / f[0]
    assert abs(moment(y_cross)) < 1e-12 * r
    u = max(rf - y_cross, 0.0)
    ep = E / (1 - NU**2)
    g_mod = E / (2 * (1 + NU))

    def energy(y):
        d = 2 * float(form.half_thickness(rf - y))
        m = moment(rf - y)
        return m**2 / (ep * d**3 / 12) + 1.2 * f_b**2 / (g_mod * d) + f_a**2 / (ep * d)

    # break points at the fillet's nodes (its thickness is interpolated between them)
    nodes = rf - np.hypot(form.fillet[:, 0], form.fillet[:, 1])
    brk = sorted(y for y in nodes if 0 < y < u)
    c, _ = quad(energy, 0.0, u, points=brk or None, epsabs=0, epsrel=1e-10, limit=2000)
    alpha = math.atan2(abs(f_a), abs(f_b))
    s_root = 2 * float(form.half_thickness(rf))
    ratio = u / s_root
    c += math.cos(alpha) ** 2 / E * (5.2 * ratio**2 + 1.0 * ratio + 1.4 * (1 + 0.3 * math.tan(alpha) ** 2))
    return c


def test_ring_compliance_against_a_potential_energy_integral():
    """jaxgear's ring tooth compliance along its active flank against the potential-energy
    integral written here (1e-6 relative: Gauss–Legendre 400 points against adaptive quadrature
    on the same tooth form), spur and a small ring whose load line crosses outside the root."""
    small = jg.InternalGearPair(
        jg.Member(17, profile_shift=0.4, face_width=0.5),
        jg.Member(-56, profile_shift=-0.5013, face_width=0.5, fillet_radius_coeff=0.3), 45e-3, A)
    for pair, cutter, fractions in ((*_nrel_stage2(), np.linspace(0.0, 1.0, 4)),
                                    (small, fp.ShaperCutter(36, 0.0, 0.3), [1.0])):
        rho = pair.roll_distance(pair.path_of_contact * np.asarray(fractions), 1)
        mine = jg.member_compliance(pair, 1, rho, E, NU, jg.WeberFoundation(), ring_cutter=cutter)
        ref = [_reference_compliance(pair, cutter, r) for r in rho]
        np.testing.assert_allclose(mine, ref, rtol=1e-6)


def test_large_ring_tends_to_the_external_weber_compliance():
    """Ring teeth of a large internal gear cut by a large cutter and the teeth of a large
    external gear tend to the rack tooth: Weber's compliances (tooth and foundation) at equal
    heights 0.9-1.9 m_n above the root circle differ by O(1/z); 4× the teeth cut the largest
    difference by more than 3 (measured 2.7 % → 0.68 %)."""
    mn = 1e-3
    diffs = []
    for n in (400, 1600):
        ext = jg.GearPair(jg.Member(40, face_width=0.01),
                          jg.Member(n, profile_shift=0.2, face_width=0.01), mn, A)
        ring = jg.InternalGearPair(jg.Member(40, face_width=0.01, profile_shift=0.3),
                                   jg.Member(-n, profile_shift=0.2, face_width=0.01), mn, A)
        h = np.linspace(0.9, 1.9, 6) * mn
        r_e, r_i = ext.root_radii[1] + h, ring.root_radii[1] - h
        c_e = jg.member_compliance(ext, 1, np.sqrt(r_e**2 - ext.base_radii[1] ** 2), E, NU,
                                   jg.WeberFoundation())
        c_i = jg.member_compliance(ring, 1, np.sqrt(r_i**2 - ring.base_radii[1] ** 2), E, NU,
                                   jg.WeberFoundation(),
                                   ring_cutter=fp.ShaperCutter(n * 3 // 4, 0.0, 0.25))
        diffs.append(np.max(np.abs(c_i / c_e - 1)))
    assert diffs[1] < diffs[0] / 3 and diffs[1] < 0.01, diffs


def test_internal_mesh_stiffness_against_iso6336():
    """The internal pair's mean Weber mesh stiffness (∫ k ds / p_bt) over ISO 6336-1 method B's
    c_γα (the ring's virtual teeth infinite): 1.16 on the NREL stage-2 ring mesh (spur),
    inside the band the external pairs show (the same teeth as an external pair: 1.21); the
    pinion's compliance is the external tooth's (member 0 unchanged)."""
    pair, cutter = _nrel_stage2()
    s, k = jg.stiffness_table(pair, jg.Weber(ring_cutter=cutter), line_load=1e6)
    ratio = np.trapezoid(k, s) / pair.base_pitch / jg.iso6336_mesh_stiffness(pair)
    assert 1.10 < ratio < 1.22, ratio
    ext = jg.GearPair(jg.Member(36, profile_shift=0.5039, face_width=0.55),
                      jg.Member(93, profile_shift=-0.1171, face_width=0.55,
                                fillet_radius_coeff=0.3), 21e-3, A)
    rho = pair.roll_distance(s[:3], 0)
    np.testing.assert_allclose(
        jg.member_compliance(pair, 0, rho, E, NU, jg.WeberFoundation()),
        jg.member_compliance(ext, 0, rho, E, NU, jg.WeberFoundation()), rtol=1e-13)
    # helical: per unit contact line, the transverse slice over cos β_b
    hel, _ = _nrel_stage2(math.radians(8.0))
    s_h, k_h = jg.stiffness_table(hel, jg.Weber(ring_cutter=cutter), line_load=1e6)
    assert np.all(np.isfinite(k_h)) and np.all(k_h > 0)


def test_refusals_in_one_line():
    """An internal pair with Weber and no cutter, with Sainsot's foundation, and a non-cutter
    refuse in one line before any work."""
    pair, cutter = _nrel_stage2()
    for model, pattern in (
        (jg.Weber(), r"^Weber: ring_cutter = None is out of range for an InternalGearPair"),
        (jg.Weber(jg.SainsotFoundation(), cutter), r"^foundation = 'sainsot' is out of range"),
    ):
        with pytest.raises(ValueError, match=pattern) as info:
            jg.stiffness_table(pair, model)
        assert "\n" not in str(info.value)
    with pytest.raises(ValueError, match=r"ring_cutter"):
        jg.Weber(ring_cutter=30)
    # an external pair ignores the ring cutter (one Weber for a stage's two meshes)
    ext = jg.GearPair(jg.Member(20, face_width=0.01), jg.Member(40, face_width=0.01), 2e-3, A)
    np.testing.assert_array_equal(jg.stiffness_table(ext, jg.Weber(ring_cutter=cutter))[1],
                                  jg.stiffness_table(ext, jg.Weber())[1])


def test_case_file_ring_cutter_keys():
    """The ring's ``[[gears]]`` entry gives its cutter (``cutter_teeth``, ``cutter_profile_shift``,
    ``cutter_tip_radius_coeff``): ``[mesh] stiffness = "weber"`` then builds
    ``Weber(ring_cutter=ShaperCutter(...))`` and both meshes of the NREL stage 1 tabulate
    (Weber over ISO 6336's mean: 1.33 sun–planet, 1.21 ring–planet at the case's load). Without
    the keys, with the keys on an external gear, a key without ``cutter_teeth``, out of range,
    or a cutter that cannot cut the ring: one line naming the key, before any work."""
    import copy
    import tomllib

    import jaxgear.io as jio

    base = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    for key in ("cutter_teeth", "cutter_profile_shift", "cutter_tip_radius_coeff"):
        base["gears"][2].pop(key)  # the embedded ring's cutter: the keys given below instead

    def case(gear="ring1", **keys):
        data = copy.deepcopy(base)
        data["mesh"]["stiffness"] = "weber"
        next(g for g in data["gears"] if g["name"] == gear).update(keys)
        return data

    parsed = jio.parse_train(case(cutter_teeth=36))
    assert parsed.stiffness == jg.Weber(ring_cutter=fp.ShaperCutter(36, 0.0, None))
    ratios = [
        np.trapezoid(m.stiffness_k, m.stiffness_s) / np.trapezoid(i.stiffness_k, i.stiffness_s)
        for m, i in zip(parsed.mesh_models(), jio.parse_train(base).mesh_models(), strict=True)
    ]
    np.testing.assert_allclose(ratios, [1.33, 1.21], atol=0.01)
    for data, pattern in (
        (case(), r"^\[mesh\] stiffness = 'weber': 'weber' cannot take it: Weber: ring_cutter = "
                 r"None .*allowed 'uniform', 'iso6336', 'fe2d', or 'weber' with the internal "
                 r"gear's "
                 r"cutter_teeth \(\[\[gears\]\]\)$"),
        (case("sun1", cutter_teeth=30), r"^\[gears\.sun1\] cutter_teeth = 30: belongs to an "
                                        r"internal gear"),
        (case(cutter_profile_shift=0.2), r"^\[gears\.ring1\] cutter_profile_shift = 0\.2: "
                                         r".*give cutter_teeth too$"),
        (case(cutter_teeth=50), r"^\[gears\.ring1\] cutter_teeth = 50: out of range, allowed "
                                r"\[11, 46\]$"),
        (case(cutter_teeth=36, cutter_profile_shift=1.5),
         r"^\[gears\.ring1\] cutter_profile_shift = 1\.5 cannot cut the ring .*no cutting "
         r"mesh.*allowed cutter_profile_shift in \[-0\.10, 0\.44\]"),
    ):
        with pytest.raises(ValueError, match=pattern) as info:
            jio.parse_train(data)
        assert "\n" not in str(info.value)
