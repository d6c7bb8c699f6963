"""Flash temperature and scuffing along the path of contact (jaxgear.tribology.mesh_scuffing).

References: Jaeger's surface temperature of a moving band source at high Péclet number,
integrated here by quadrature (Blok's constant 1.11 is its maximum under a Hertzian flux);
Blok's formula written again here in NumPy; ISO/TS 6336-20's closed form in the TS's own units
(X_M = 50 K N^−¾ s^½ m^−½ mm for steel, w in N/mm, v in m/s, a in mm) written here; the
FZG A/8.3/90 pinion torques of ISO 14635-1 (load stages 9, 10, 12: 302.0, 372.6, 534.5 N·m);
the uniform-load-sharing limit in which jaxgear's path-based θ_fl must equal the TS's with its
X_Γ; central differences.
"""

from __future__ import annotations

import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.tribology as tr
from test_tribology import _mesh  # the same pair table (Weber at 200 N·m)

E, NU = 206e9, 0.3
RA = (0.6e-6, 0.6e-6)
SPEED = 1500 * 2 * math.pi / 60
TORQUE = 200.0
PPP = 64
B_STEEL = tr.STEEL_THERMAL_CONTACT_COEFFICIENT


def _lubricant(t_c=90.0):
    # an ISO VG 100 mineral oil (ν₄₀ 100 mm²/s, ν₁₀₀ 11 mm²/s)
    return tr.Lubricant(100e-6, 11e-6, 880.0, 20e-9, t_c, 6e-4)


def _pair(teeth, module, shifts, face, helix_deg):
    members = [jg.Member(z, x, 1.0, 1.25, face, 0.38) for z, x in zip(teeth, shifts)]
    return jg.GearPair(*members, module, math.radians(20.0), math.radians(helix_deg))


@functools.cache
def _spur():
    pair = _pair((16, 24), 4.5e-3, (0.1817, 0.1715), 0.014, 0.0)  # FZG C-type
    return pair, jg.quasi_static(_mesh(pair, 1), None, TORQUE, positions_per_pitch=PPP).mesh


@functools.cache
def _helical():
    pair = _pair((20, 30), 3.5e-3, (0.1809, 0.0891), 0.023, 15.0)
    return pair, jg.quasi_static(_mesh(pair, 12), None, TORQUE, positions_per_pitch=PPP).mesh


def _uniform(pair, res):
    """The load shared evenly among the lines in contact: F_n over the contact length."""
    n = res.line_load.shape[-1]
    cell = pair.face_width / (n * math.cos(pair.base_helix_angle))
    f_n = TORQUE / (pair.base_radii[0] * math.cos(pair.base_helix_angle))
    length = jnp.sum(res.cell_mask, axis=(1, 2)) * cell
    w = jnp.where(res.cell_mask, f_n / length[:, None, None], 0.0)
    return eqx.tree_at(lambda r: r.line_load, res, w)


def _scuff(pair, res, limits=None, friction=None, **kw):
    lub = _lubricant()
    trib = tr.mesh_tribology(
        pair, res, lub, TORQUE, SPEED, RA, E, NU, friction=friction or tr.GivenFriction(0.05)
    )
    limits = limits or tr.ScuffingLimits(fzg_load_stage=10)
    return trib, tr.mesh_scuffing(pair, res, trib, lub, E, NU, limits, **kw)


# -- Blok's constant: Jaeger's band source ------------------------------------------------------


def _jaeger_max():
    """max over ξ of ∫_{−1}^{ξ} √(1 − t²)/√(ξ − t) dt (t = ξ − σ², Gauss–Legendre)."""
    x, wts = np.polynomial.legendre.leggauss(400)
    best = 0.0
    for xi in np.linspace(0.5, 0.8, 301):
        top = math.sqrt(xi + 1.0)
        sig = 0.5 * top * (x + 1.0)
        f = 2.0 * np.sqrt(np.clip(1.0 - (xi - sig**2) ** 2, 0.0, None))
        best = max(best, 0.5 * top * float(np.dot(wts, f)))
    return best


def test_blok_constant_is_jaeger_maximum_under_a_hertzian_flux():
    """A flux q(x) = q₀√(1 − x²/b²) of total μ w v_g on one body moving at v: the surface
    temperature θ(x) = ∫ q(x′) / (B √(π v (x − x′))) dx′ (1-D conduction into a half space,
    Jaeger 1942), whose maximum is θ = 2 I_max/π^{3/2} μ w v_g/(B √(v b)). Blok's formula with
    the other body insulated (B₂ → 0) is 1.11 μ w v_g/(B √v √(2b))."""
    i_max = _jaeger_max()
    mu, w, vg, v, b = 0.05, 4e5, 3.0, 8.0, 2e-4
    jaeger = 2.0 * i_max / math.pi**1.5 * mu * w * vg / (B_STEEL * math.sqrt(v * b))
    # v₁ − v₂ = v_g with v₁ = v; B₂ = 0 puts all the heat into body 1
    blok = float(tr.blok_flash_temperature(mu, w, v, v - vg, b, B_STEEL, 0.0))
    assert blok == pytest.approx(jaeger, rel=2e-3)


@pytest.mark.parametrize(
    "mu, w, v1, v2, b, b1, b2",
    [
        (0.05, 3e5, 6.0, 2.0, 1.5e-4, B_STEEL, B_STEEL),
        (0.08, 8e5, 1.0, 9.0, 3e-4, 12e3, 15e3),  # a faster gear flank, two materials
        (0.03, 1e5, 20.0, 19.0, 5e-5, B_STEEL, B_STEEL),  # near the pitch point
    ],
)
def test_blok_against_separate_evaluation(mu, w, v1, v2, b, b1, b2):
    # the heat split so both flanks reach the same maximum: q₁/q₂ = B₁√v₁/(B₂√v₂)
    q = mu * w * abs(v1 - v2)
    q1 = q * b1 * math.sqrt(v1) / (b1 * math.sqrt(v1) + b2 * math.sqrt(v2))
    ref = 0.785 * q1 / (b1 * math.sqrt(v1 * b))  # 1.11/√2 = 0.785
    got = float(tr.blok_flash_temperature(mu, w, v1, v2, b, b1, b2))
    assert got == pytest.approx(ref, rel=1e-3)


# -- two flank materials: each flank's own B_M with its own speed --------------------------------

B_OTHER = 9000.0  # W s^½/(m² K): a gear flank of another material than the steel pinion


def _hand_flash(pair, s, w, mu, b1, b2):
    """Blok's θ_fl at base-plane coordinate s (m) and line load w (N/m) of the spur FZG C pair,
    written here from the pair's centre distance, base and tip radii: ρ₁ from the gear's tip
    (point A), each flank's speed v_i = ω_i ρ_i, the heat split q₁/q₂ = B₁√v₁/(B₂√v₂) so that
    both flanks reach one temperature, θ = 0.785 q₁/(B₁ √(v₁ b_H)) (the pinion's side)."""
    rb1, rb2 = pair.base_radii
    t1t2 = math.sqrt(pair.center_distance**2 - (rb1 + rb2) ** 2)
    rho1 = t1t2 - math.sqrt(pair.tip_radii[1] ** 2 - rb2**2) + s
    rho2 = t1t2 - rho1
    v1 = SPEED * rho1
    v2 = SPEED * pair.pinion.teeth / pair.gear.teeth * rho2
    radius = rho1 * rho2 / (rho1 + rho2)
    e_star = 1.0 / (2.0 * (1.0 - NU**2) / E)
    b_h = math.sqrt(4.0 * w * radius / (math.pi * e_star))
    q = mu * w * abs(v1 - v2)
    q1 = q * b1 * math.sqrt(v1) / (b1 * math.sqrt(v1) + b2 * math.sqrt(v2))
    return 1.11 / math.sqrt(2.0) * q1 / (b1 * math.sqrt(v1 * b_h))


@pytest.mark.parametrize("coefficients", [(B_STEEL, B_OTHER), (B_OTHER, B_STEEL)])
def test_flash_temperature_with_two_flank_materials_against_a_hand_evaluation(coefficients):
    """FZG C14 (spur) with dissimilar B_M: at positions in the approach (the gear flank the
    faster) and the recess (the pinion flank the faster) jaxgear's θ_fl equals Blok's formula
    evaluated by hand with each flank's own B_M and own speed (1e-9)."""
    pair, res = _spur()
    _, out = _scuff(pair, res, thermal_coefficients=coefficients)
    loaded = np.asarray(out.loaded)
    s = np.asarray(res.cell_s)
    w = np.asarray(res.line_load)
    fl = np.asarray(out.flash_temperature)
    g = pair.path_of_contact
    for fraction in (0.08, 0.2, 0.35, 0.65, 0.8, 0.92):  # approach below the pitch point ≈ 0.46
        idx = np.unravel_index(np.argmin(np.where(loaded, abs(s - fraction * g), np.inf)), s.shape)
        assert abs(s[idx] / g - fraction) < 0.02
        want = _hand_flash(pair, float(s[idx]), float(w[idx]), 0.05, *coefficients)
        assert float(fl[idx]) == pytest.approx(want, rel=1e-9), fraction


def test_equal_coefficients_unchanged_by_the_flank_order():
    """One material on both flanks: the flank order does not matter (the formula is symmetric);
    the hand evaluation agrees on the whole path."""
    pair, res = _spur()
    _, out = _scuff(pair, res)
    loaded = np.asarray(out.loaded)
    s = np.asarray(res.cell_s)[loaded]
    w = np.asarray(res.line_load)[loaded]
    want = [_hand_flash(pair, float(a), float(b), 0.05, B_STEEL, B_STEEL) for a, b in zip(s, w)]
    np.testing.assert_allclose(np.asarray(out.flash_temperature)[loaded], want, rtol=1e-9)


def test_thermal_contact_coefficient_and_steel_thermo_elastic_factor():
    # λ 45 W/(m K), ρ 7850 kg/m³, c 440 J/(kg K)
    assert float(tr.thermal_contact_coefficient(45.0, 7850.0, 440.0)) == pytest.approx(
        math.sqrt(45.0 * 7850.0 * 440.0)
    )
    # the TS's X_M = E_r^¼/B_M: 50 K N^−¾ s^½ m^−½ mm for steel (E_r = E/(1 − ν²))
    x_m = (E / (1 - NU**2)) ** 0.25 / B_STEEL * 1e3
    assert x_m == pytest.approx(50.0, rel=1e-3)


# -- the TS's closed form in its own units ------------------------------------------------------


def _ts_mm(pair, gamma, x_gamma, mu):
    """ISO/TS 6336-20's θ_fl for a spur pair in the TS's units (X_M = 50)."""
    u = pair.gear_ratio
    a = pair.center_distance * 1e3  # mm
    alpha = pair.operating_pressure_angle
    w_bn = TORQUE / (pair.base_radii[0] * pair.face_width) * 1e-3  # N/mm
    v_t = SPEED * pair.center_distance / (1 + u)  # m/s
    x_g = (
        0.6215
        * math.sin(alpha) ** 0.25
        * math.sqrt(1 + u)
        * abs(math.sqrt(1 + gamma) - math.sqrt(1 - gamma / u))
        / ((1 + gamma) * (u - gamma)) ** 0.25
    )
    return mu * 50.0 * x_g * (x_gamma * w_bn) ** 0.75 * v_t**0.5 / a**0.25


@pytest.mark.parametrize("gamma, x_gamma", [(-0.35, 0.5), (0.2, 1.0), (0.6, 0.5)])
def test_ts_closed_form_in_the_ts_units(gamma, x_gamma):
    pair, _ = _spur()
    got = float(tr.ts_flash_temperature(pair, gamma, x_gamma, 0.05, TORQUE, SPEED, E, NU))
    assert got == pytest.approx(_ts_mm(pair, gamma, x_gamma, 0.05), rel=1e-3)


# -- the uniform-load-sharing limit -----------------------------------------------------------


def _gamma(pair, s):
    return (pair.start_roll + s) / (
        pair.base_radii[0] * math.tan(pair.operating_pressure_angle)
    ) - 1


def test_path_flash_temperature_equals_ts_under_uniform_sharing_spur():
    """Spur: X_Γ = 1/n, n the pairs in contact at the position (1 in single contact, ½ in
    double): jaxgear's path-based θ_fl from the line loads equals the TS's closed form."""
    pair, res = _spur()
    _, out = _scuff(pair, _uniform(pair, res))
    loaded = np.asarray(out.loaded)
    n_pairs = np.sum(np.asarray(res.cell_mask), axis=(1, 2))
    x_gamma = np.broadcast_to((1.0 / n_pairs)[:, None, None], loaded.shape)[loaded]
    assert set(np.round(1.0 / x_gamma).astype(int)) == {1, 2}
    s = np.asarray(res.cell_s)[loaded]
    ts = np.asarray(
        tr.ts_flash_temperature(pair, _gamma(pair, s), x_gamma, 0.05, TORQUE, SPEED, E, NU)
    )
    np.testing.assert_allclose(np.asarray(out.flash_temperature)[loaded], ts, rtol=1e-9, atol=1e-9)
    # the largest θ_fl at the start or end of the path (fast sliding), zero at the pitch point
    s_max = s[np.argmax(np.asarray(out.flash_temperature)[loaded])]
    assert min(s_max, pair.path_of_contact - s_max) < 0.1 * pair.path_of_contact


def test_path_flash_temperature_equals_ts_under_uniform_sharing_helical():
    """Helical: the speeds normal to the contact line (× cos β_b), R in the normal section and
    X_Γ = w/w_Bn per cell reproduce the TS's form with its cos^¾ β_b."""
    pair, res = _helical()
    _, out = _scuff(pair, _uniform(pair, res))
    loaded = np.asarray(out.loaded)
    w_bn = TORQUE / (pair.base_radii[0] * pair.face_width)
    x_gamma = np.asarray(_uniform(pair, res).line_load)[loaded] / w_bn
    s = np.asarray(res.cell_s)[loaded]
    ts = np.asarray(
        tr.ts_flash_temperature(pair, _gamma(pair, s), x_gamma, 0.05, TORQUE, SPEED, E, NU)
    )
    np.testing.assert_allclose(np.asarray(out.flash_temperature)[loaded], ts, rtol=1e-9, atol=1e-9)


# -- the methods' temperatures and safety factors ---------------------------------------------


def test_fzg_pinion_torque_matches_iso_14635():
    for stage, torque in ((9, 302.0), (10, 372.6), (12, 534.5)):
        assert tr.fzg_pinion_torque(stage) == pytest.approx(torque, rel=5e-3)


def test_safety_factors_from_the_temperatures():
    pair, res = _spur()
    _, out = _scuff(pair, res)
    oil = 90.0
    fl = np.asarray(out.flash_temperature)
    mask = np.asarray(res.cell_mask)
    # θ_flm: the mean over the cells on the path (they sample it evenly)
    assert float(out.mean_flash_temperature) == pytest.approx(fl[mask].mean(), rel=1e-12)
    theta_m = oil + 0.47 * float(out.mean_flash_temperature)
    assert float(out.bulk_temperature) == pytest.approx(theta_m, rel=1e-12)
    theta_b = theta_m + fl.max()
    assert float(out.max_contact_temperature) == pytest.approx(theta_b, rel=1e-12)
    theta_s = 80.0 + 2.25 * 100.0  # load stage 10, X_W = X_L = 1
    assert float(out.safety_factor) == pytest.approx((theta_s - oil) / (theta_b - oil), rel=1e-12)
    theta_int = oil + (0.7 + 1.5) * float(out.mean_flash_temperature)
    assert float(out.integral_temperature) == pytest.approx(theta_int, rel=1e-12)
    t1t = 372.6
    theta_int_s = 80 + 0.23 * t1t + 1.5 * 0.2 * t1t * (100.0 / 100.0) ** 0.02
    assert float(out.integral_safety_factor) == pytest.approx(theta_int_s / theta_int, rel=1e-12)
    # a given scuffing temperature and bulk temperature
    _, given = _scuff(
        pair,
        res,
        tr.ScuffingLimits(scuffing_temperature=300.0, integral_scuffing_temperature=350.0),
        bulk=tr.GivenBulkTemperature(100.0),
    )
    assert float(given.safety_factor) == pytest.approx(
        (300.0 - oil) / (100.0 + fl.max() - oil), rel=1e-9
    )
    assert float(given.integral_temperature) == pytest.approx(
        100.0 + 1.5 * float(out.mean_flash_temperature), rel=1e-9
    )
    assert set(out.summary()) >= {"max_flash_temperature_K", "scuffing_safety_factor"}
    # spray lubrication, a gear in two meshes: X_S X_mp in both methods' bulk temperatures
    # (ISO/TR 13989-1 eqs. (22), (23) and -2 eqs. (20), (21) as hakangunes258/mekanika gives them)
    _, spray = _scuff(pair, res, bulk=tr.FlashBulkTemperature(1.2, meshes=2))
    xs_xmp = 1.2 * 1.5
    flm = float(out.mean_flash_temperature)
    assert float(spray.bulk_temperature) == pytest.approx(oil + 0.47 * xs_xmp * flm, rel=1e-12)
    assert float(spray.integral_bulk_temperature) == pytest.approx(
        oil + 0.7 * xs_xmp * flm, rel=1e-12
    )


def test_own_load_sharing_lowers_the_peak_flash_temperature():
    """jaxgear's elastic sharing unloads the ends of the path (the tip corners), where sliding
    is fastest: its largest θ_fl is below the uniform sharing's."""
    pair, res = _spur()
    _, own = _scuff(pair, res)
    _, uni = _scuff(pair, _uniform(pair, res))
    assert float(own.max_flash_temperature) < float(uni.max_flash_temperature)
    assert float(own.max_flash_temperature) > 0.5 * float(uni.max_flash_temperature)


# -- gradients, float32, bad input --------------------------------------------------------


@functools.cache
def _objective():
    pair, _ = _spur()
    mesh = _mesh(pair, 4)
    lub = _lubricant()
    theta = jg.mesh_positions(mesh, 32)
    limits = tr.ScuffingLimits(fzg_load_stage=10)

    def f(depth_um):
        mods = jg.Modifications.symmetric(
            jg.MemberModification(tip_relief_depth=depth_um * 1e-6, tip_relief_extent=0.3)
        )
        res = jg.quasi_static(mesh, mods, TORQUE, theta, contact=jg.SmoothContact(1e-7))
        trib = tr.mesh_tribology(pair, res, lub, TORQUE, SPEED, RA, E, NU)
        out = tr.mesh_scuffing(pair, res, trib, lub, E, NU, limits)
        return jnp.stack([out.max_flash_temperature, out.safety_factor, out.integral_safety_factor])

    return jax.jit(f), jax.jit(jax.jacrev(f))


def test_gradients_wrt_tip_relief_match_central_differences():
    f, jac = _objective()
    d0, h = 12.0, 1e-3
    g = np.asarray(jac(jnp.asarray(d0)))
    fd = (np.asarray(f(jnp.asarray(d0 + h))) - np.asarray(f(jnp.asarray(d0 - h)))) / (2 * h)
    fd2 = (np.asarray(f(jnp.asarray(d0 + h / 2))) - np.asarray(f(jnp.asarray(d0 - h / 2)))) / h
    assert np.all(np.abs(g) > 1e-6)
    np.testing.assert_allclose(fd2, fd, rtol=1e-4)  # no kink crossed
    np.testing.assert_allclose(g, fd, rtol=1e-4)


def test_float32_matches_float64():
    pair, res = _spur()
    _, ref = _scuff(pair, res)
    names = (
        "max_flash_temperature",
        "mean_flash_temperature",
        "safety_factor",
        "integral_safety_factor",
    )
    want = {name: float(getattr(ref, name)) for name in names}
    with jax.enable_x64(False):
        res32 = jax.tree.map(lambda x: x.astype(np.float32) if x.dtype == np.float64 else x, res)
        _, out = _scuff(pair, res32)
        assert out.flash_temperature.dtype == np.float32
        for name in names:
            assert float(getattr(out, name)) == pytest.approx(want[name], rel=1e-4), name


def test_bad_input():
    pair, res = _spur()
    lub = _lubricant()
    trib = tr.mesh_tribology(pair, res, lub, TORQUE, SPEED, RA, E, NU)
    limits = tr.ScuffingLimits(fzg_load_stage=10)
    cases = [
        (lambda: tr.ScuffingLimits(fzg_load_stage=15), "fzg_load_stage = 15"),
        (lambda: tr.ScuffingLimits(scuffing_temperature=300.0), "fzg_load_stage = None"),
        (lambda: tr.FlashBulkTemperature(meshes=0), "meshes = 0"),
        (lambda: tr.GivenBulkTemperature(500.0), "value = 500"),
        (
            lambda: tr.mesh_scuffing(
                pair, res, trib, lub, E, NU, limits, thermal_coefficients=(B_STEEL, -1.0)
            ),
            "thermal_coefficients",
        ),
        (lambda: tr.mesh_scuffing(pair, res, res, lub, E, NU, limits), "tribology"),
        (lambda: tr.thermal_contact_coefficient(0.0, 7850.0, 440.0), "conductivity = 0"),
    ]
    for call, match in cases:
        with pytest.raises(ValueError, match=match) as err:
            call()
        assert "\n" not in str(err.value)
