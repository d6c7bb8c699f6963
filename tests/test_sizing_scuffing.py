"""Scuffing in the sizing (ISO/TS 6336-20's closed form, jaxgear.tribology.ts_scuffing, and the
sizing's scuffing check).

References, each written here: the TS's load-sharing factor X_Γ at its corner points (the
buttress form's 1/3 steps, (Q − 2)/15, 1/ε_α, the buttressing factor); K_Bγ and μ_mC by hand
in the TS's units (N/mm, m/s, mm, mPa·s, µm); one candidate's θ_fl, θ_fl,max, θ_flm, θ_M and S_B
by Blok's formula with involute kinematics in NumPy on a dense grid (the positions Γ_A…Γ_E from
ISO/TR 13989-1's tan α_a formulas, the base circles from the reference ones); the FZG A/8.3/90
test gear (ISO 14635-1: z 16/24, m 4.5 mm, x 0.8532/−0.5, a 91.5 mm, b 20 mm, d_a 88.77/112.5
mm, 2170 1/min) at its failure load stage S with the test's bulk temperature θ_MT = 80 + 0.85 S²
°C: its θ_B,max must be the TS's θ_S = 80 + 2.25 S², S_B = 1, the TS's calibration; jaxgear's
path-based θ_fl (mesh_scuffing) with the TS's X_Γ loads; the spec keys' one-line refusals.
"""

from __future__ import annotations

import copy
import functools
import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from test_sizing import SPEC

import jaxgear.io as jio
import jaxgear.sizing as js
import jaxgear.tribology as tr

LUBRICANT = {"viscosity_40C_mm2_s": 100.0, "viscosity_100C_mm2_s": 11.0, "density_kg_m3": 880.0,
             "pressure_viscosity_per_GPa": 20.0, "oil_temperature_C": 90.0,
             "roughness_Ra_um": 0.6, "fzg_load_stage": 8}
S_B_MIN = 1.5
B_M = 13795.0  # ISO/TS 6336-20's steel B_M, 13.795 N/(mm s^½ K), in W s^½/(m² K)


def _data(lubricant=None, **rating):
    data = copy.deepcopy(SPEC)
    data["lubricant"] = dict(LUBRICANT) if lubricant is None else lubricant
    data["rating"].update({"min_safety_scuffing": S_B_MIN} | rating)
    return data


@functools.cache
def _sized():
    spec, tables = jio.parse_sizing_spec(_data())
    return spec, tables, js.size(spec)


def _refused(data, message):
    with pytest.raises(ValueError) as err:
        jio.parse_sizing_spec(data)
    text = str(err.value)
    assert text.startswith(message) and "\n" not in text, text


# -- the TS's factors by hand -------------------------------------------------------------------


def test_load_sharing_corner_points_by_hand():
    ga, gb, gd, ge = -0.6, 0.1, 0.3, 1.0  # p_b = Γ_D − Γ_A = Γ_E − Γ_B; ε_α = 1.78 (spur)
    ea = 1.0 + (gb - ga) / (gd - ga)

    def x(g, eb=0.0, bb=0.0, grade=6, piece=None):
        return float(tr.ts_load_sharing(g, ga, gb, gd, ge, ea, eb, bb, grade, piece))

    # spur, grade 6 (Q = 7): 1/3 at A and E, 2/3 at B⁻ and D⁺, 1 on B…D
    assert x(ga) == pytest.approx(1 / 3)
    assert x(gb, piece=0) == pytest.approx(2 / 3)
    assert x(gb) == pytest.approx(1.0) and x(0.2) == pytest.approx(1.0)
    assert x(gd) == pytest.approx(1.0)
    assert x(gd, piece=2) == pytest.approx(2 / 3)
    assert x(ge) == pytest.approx(1 / 3)
    assert x(0.5 * (ga + gb)) == pytest.approx(0.5)
    # the two pairs in double contact (Γ and Γ + p_b, p_b = Γ_D − Γ_A) share the load
    for g in (-0.55, -0.3, 0.05):
        assert x(g) + x(g + (gd - ga), piece=2) == pytest.approx(1.0)
    # grade 9: X_Q = (9 − 2)/15 at A and E, X_Q + 1/3 before B
    assert x(ga, grade=9) == pytest.approx(7 / 15)
    assert x(gb, grade=9, piece=0) == pytest.approx(7 / 15 + 1 / 3)
    # helical, ε_β >= 1: 1/ε_α in the middle, × 1.3 at A and E (buttressing over 0.2 sin β_b)
    bb = math.radians(20.0)
    assert x(0.2, eb=1.4, bb=bb) == pytest.approx(1 / ea)
    assert x(ga, eb=1.4, bb=bb) == pytest.approx(1.3 / ea)
    assert x(ge - 0.1 * math.sin(bb), eb=1.4, bb=bb) == pytest.approx(1.15 / ea)
    # ε_β = 0.4: the spur form and 1/ε_α in proportion, the buttressing 1 + 0.3 ε_β
    assert x(0.2, eb=0.4, bb=bb) == pytest.approx(0.6 + 0.4 / ea)
    assert x(ga, eb=0.4, bb=bb) == pytest.approx((0.6 / 3 + 0.4 / ea) * 1.12)
    # single contact (ε_α < 1): all the load on one pair
    assert float(tr.ts_load_sharing(0.0, ga, gb, gd, ge, 0.9, 0.0, 0.0)) == 1.0


@pytest.mark.parametrize("eps_gamma, want", [
    (1.6, 1.0), (2.0, 1.0), (2.75, 1 + 0.2 * math.sqrt(0.75 * 2.25)), (3.5, 1.3), (4.2, 1.3)])
def test_helical_load_factor_by_hand(eps_gamma, want):
    assert float(tr.helical_load_factor(eps_gamma)) == pytest.approx(want, rel=1e-12)


def test_friction_coefficient_by_hand():
    """μ_mC = 0.045 (w_Bt K_Bγ/(v_ΣC ρ_redC))^0.2 η^−0.05 X_R X_L, X_R = 2.2 (R_a/ρ_redC)^0.25,
    in N/mm, m/s, mm, mPa·s, µm."""
    w, v, rho, eta, ra, xl = 350.0, 4.2, 9.5, 12.0, 0.45, 0.8
    want = 0.045 * (w / (v * rho)) ** 0.2 * eta**-0.05 * 2.2 * (ra / rho) ** 0.25 * xl
    got = tr.ts_friction_coefficient(w * 1e3, v, rho * 1e-3, eta * 1e-3, ra * 1e-6, xl)
    assert float(got) == pytest.approx(want, rel=1e-12)


# -- one candidate against Blok's formula by hand -----------------------------------------------


def _blok_reference(spec, row):
    """θ_fl along the path (dense), θ_fl,max, θ_flm, μ_mC, θ_M, θ_B,max and S_B of one
    candidate by hand: Blok's flash temperature with involute kinematics (module docstring)."""
    c = {k: float(v[row]) for k, v in _sized()[2].columns.items() if np.ndim(v)}
    lub = spec.scuffing.lubricant
    z1, z2 = c["z1"], c["z2"]
    u = z2 / z1
    an, beta = spec.normal_pressure_angle, c["helix_angle_rad"]
    at = math.atan(math.tan(an) / math.cos(beta))
    bb = math.atan(math.tan(beta) * math.cos(at))
    awt, a, b = c["operating_pressure_angle_rad"], c["centre_distance_m"], c["face_width_m"]
    d1, d2 = c["reference_diameter_1_m"], c["reference_diameter_2_m"]
    db1, db2 = d1 * math.cos(at), d2 * math.cos(at)
    tan_a1 = math.sqrt((c["tip_diameter_1_m"] / db1) ** 2 - 1)
    tan_a2 = math.sqrt((c["tip_diameter_2_m"] / db2) ** 2 - 1)
    ga = -u * (tan_a2 / math.tan(awt) - 1)
    ge = tan_a1 / math.tan(awt) - 1
    gb = ge - 2 * math.pi / (z1 * math.tan(awt))
    gd = ga + 2 * math.pi / (z1 * math.tan(awt))
    ea, eb = c["eps_alpha"], c["eps_beta"]
    assert ga < gb < gd < ge and eb < 1.0  # a helical pair of ε_β < 1: every part of X_Γ

    def x_gamma(g, piece):  # the buttress form, interpolated to 1/ε_α by ε_β, buttressed
        spur = (1 / 3 + (g - ga) / (3 * (gb - ga)), 1.0, 1 / 3 + (ge - g) / (3 * (ge - gd)))[piece]
        width = 0.2 * math.sin(bb)
        ramp = max(0.0, 1 - (g - ga) / width, 1 - (ge - g) / width)
        return ((1 - eb) * spur + eb / ea) * (1 + 0.3 * eb * ramp)

    k_by = 1.0 if ea + eb <= 2 else 1 + 0.2 * math.sqrt((ea + eb - 2) * (5 - ea - eb))
    t_eff = float(spec.operating.torque) * 1.25 * c["K_v"] * c["K_Hbeta"] * c["K_Halpha"] * k_by
    omega = float(spec.operating.speed)
    # μ_mC in the TS's units
    rw1 = a / (1 + u)
    rho_c = a * math.sin(awt) * u / (1 + u) ** 2 * 1e3  # mm
    w_bt = 2 * t_eff / d1 / b * 1e-3  # N/mm
    v_sum = 2 * omega * rw1 * math.sin(awt)
    eta = float(lub.dynamic_viscosity) * 1e3  # mPa·s
    mu = 0.045 * (w_bt / (v_sum * rho_c)) ** 0.2 * eta**-0.05 * 2.2 * (0.6 / rho_c) ** 0.25
    # Blok: normal line load, the flanks' speeds normal to the line, R in the normal section
    e_star = 210e9 / (2 * (1 - 0.3**2))
    rb1 = db1 / 2

    def flash(g, piece):
        rho1 = rb1 * math.tan(awt) * (1 + g)
        rho2 = a * math.sin(awt) - rho1
        w = x_gamma(g, piece) * t_eff / (rb1 * b)
        v1, v2 = omega * rho1 * math.cos(bb), omega / u * rho2 * math.cos(bb)
        r = rho1 * rho2 / (rho1 + rho2) / math.cos(bb)
        b_h = math.sqrt(4 * w * r / (math.pi * e_star))
        return (1.11 * mu * w * abs(v1 - v2)
                / (B_M * (math.sqrt(v1) + math.sqrt(v2)) * math.sqrt(2 * b_h)))

    area, peak = 0.0, 0.0
    for piece, (lo, hi) in enumerate(((ga, gb), (gb, gd), (gd, ge))):
        g = np.linspace(lo, hi, 4001)
        f = np.array([flash(v, piece) for v in g])
        area += np.trapezoid(f, g)
        peak = max(peak, f.max())
    mean = area / (ge - ga)
    oil = float(lub.oil_temperature)
    theta_m = oil + 0.47 * mean
    theta_s = 80 + (0.85 + 1.4) * 8**2
    s_b = (theta_s - oil) / (theta_m + peak - oil)
    return {"mu_mC": mu, "theta_fl_max_K": peak, "theta_M_C": theta_m,
            "theta_B_max_C": theta_m + peak, "S_B": s_b}


def test_one_candidate_against_blok_by_hand():
    """The table's μ_mC, θ_fl,max, θ_M, θ_B,max and S_B of a helical candidate (ε_β < 1: every
    part of X_Γ) equal Blok's formula by hand on a dense grid: μ_mC exactly, θ_fl,max to the
    64-point grid's miss of an interior maximum (1e-4), θ_M − θ_oil (0.47 θ_flm) to its
    trapezoidal rule (2e-4)."""
    spec, _, table = _sized()
    c = table.columns
    rows = np.flatnonzero(np.isfinite(c["S_B"]) & (c["eps_alpha"] + c["eps_beta"] < 2.5))
    row = int(rows[np.argmin(c["S_B"][rows])])
    want = _blok_reference(spec, row)
    assert c["mu_mC"][row] == pytest.approx(want["mu_mC"], rel=1e-12)
    assert c["theta_fl_max_K"][row] == pytest.approx(want["theta_fl_max_K"], rel=1e-4)
    oil = float(spec.scuffing.lubricant.oil_temperature)  # θ_flm to 2e-4 (64 points a piece)
    assert c["theta_M_C"][row] - oil == pytest.approx(want["theta_M_C"] - oil, rel=2e-4)
    assert c["S_B"][row] == pytest.approx(want["S_B"], rel=1e-4)


# -- the FZG A/8.3/90 test at its failure load stage ---------------------------------------------


def _fzg_a(stage, bulk=None, dtype=None):
    m, z1, z2, a, b = 4.5e-3, 16, 24, 91.5e-3, 20e-3
    alpha = math.radians(20.0)
    rb1, rb2 = z1 * m / 2 * math.cos(alpha), z2 * m / 2 * math.cos(alpha)
    awt = math.acos((rb1 + rb2) / a)
    da = (88.77e-3, 112.5e-3)
    ea = (math.sqrt((da[0] / 2) ** 2 - rb1**2) + math.sqrt((da[1] / 2) ** 2 - rb2**2)
          - a * math.sin(awt)) / (math.pi * m * math.cos(alpha))
    lub = tr.Lubricant(100e-6, 11e-6, 880.0, 20e-9, 90.0, 6e-4)  # FZG test at 90 °C, VG 100
    speed = 2170 * math.pi / 30
    return tr.ts_scuffing(z1, z2 / z1, a, awt, 0.0, z1 * m, da, b, (ea, 0.0),
                          tr.fzg_pinion_torque(stage), speed, 1.0, lub, (0.35e-6, 0.35e-6),
                          tr.ScuffingLimits(stage), 206e9, 0.3, bulk=bulk)


@pytest.mark.parametrize("stage", [8, 10, 12])
def test_fzg_a_test_gear_fails_at_its_load_stage(stage):
    """The TS's θ_S is the FZG A test gear's own contact temperature at the load stage it
    fails: θ_S = θ_MT + θ_fl,max,T with the test's bulk temperature θ_MT = 80 + 0.85 S² and its
    flash temperature 1.4 S² (X_W = 1). With that bulk temperature, the closed form's θ_fl,max
    of the test gear is 1.4 S² and S_B = 1, to 3 % (R_a 0.35 µm, an ISO VG 100 oil at 90 °C:
    μ_mC 0.057 to 0.067 over the stages)."""
    r = _fzg_a(stage, tr.GivenBulkTemperature(80.0 + 0.85 * stage**2))
    assert float(r.max_flash_temperature) == pytest.approx(1.4 * stage**2, rel=0.03)
    assert float(r.safety_factor) == pytest.approx(1.0, abs=0.03)
    # with the TS's own bulk rule (θ_oil + 0.47 θ_flm, below the test's) S_B is above 1
    assert 1.1 < float(_fzg_a(stage).safety_factor) < 1.4


def test_safety_factor_gradient_matches_central_differences():
    """d S_B/d b, d S_B/d T and d S_B/d ε_α of the FZG A gear (spur, ε_γ < 2: K_Bγ = 1 on its
    flat part, where a root of 0 would give NaN) by jax.grad against central differences:
    finite, to 1e-6 (the refinement's gradients)."""
    m, z1, a = 4.5e-3, 16, 91.5e-3
    alpha = math.radians(20.0)
    awt = math.acos((z1 + 24) * m / 2 * math.cos(alpha) / a)
    lub = tr.Lubricant(100e-6, 11e-6, 880.0, 20e-9, 90.0, 6e-4)
    def s_b(b, torque, ea):
        return tr.ts_scuffing(z1, 1.5, a, awt, 0.0, z1 * m, (88.77e-3, 112.5e-3), b, (ea, 0.0),
                              torque, 227.0, 1.0, lub, (0.35e-6, 0.35e-6), tr.ScuffingLimits(10),
                              206e9, 0.3).safety_factor

    f = jax.jit(s_b)
    x0 = (0.02, 372.6, 1.3611)  # ε_α about the gear's; any in (1, 2) serves
    grad = jax.jit(jax.grad(s_b, argnums=(0, 1, 2)))(*x0)
    for k, h in enumerate((1e-6, 1e-3, 1e-6)):
        args_p, args_m = list(x0), list(x0)
        args_p[k], args_m[k] = x0[k] + h, x0[k] - h
        fd = (float(f(*args_p)) - float(f(*args_m))) / (2 * h)
        assert np.isfinite(float(grad[k]))
        assert float(grad[k]) == pytest.approx(fd, rel=1e-6, abs=1e-12)


@pytest.mark.parametrize("change, message", [
    ({"torque": -3.0}, "ts_scuffing: torque = -3 N·m is out of range: allowed > 0"),
    ({"roughness": (0.3e-6,)}, "ts_scuffing: roughness"),
    ({"limits": 10}, "ts_scuffing: limits"),
    ({"points": 1}, "ts_scuffing: points = 1 is out of range: allowed an integer >= 2"),
])
def test_closed_form_refuses_bad_arguments_in_one_line(change, message):
    args = {"torque": 300.0, "roughness": (0.3e-6, 0.3e-6), "limits": tr.ScuffingLimits(8),
            "points": 64}
    args |= change
    with pytest.raises(ValueError) as err:
        tr.ts_scuffing(16, 1.5, 0.0915, 0.39, 0.0, 0.072, (0.0888, 0.1125), 0.02, (1.4, 0.0),
                       args["torque"], 227.0, 1.0, tr.Lubricant(100e-6, 11e-6, 880.0, 20e-9, 90.0),
                       args["roughness"], args["limits"], 206e9, 0.3, points=args["points"])
    assert str(err.value).startswith(message) and "\n" not in str(err.value)


def test_closed_form_runs_batched_in_float32():
    """vmap over the load stage's torques, x64 off: float32 throughout, the float64 numbers to
    float32 accuracy."""
    stages = np.array([8.0, 9.0, 10.0])
    want = [float(_fzg_a(int(s)).max_flash_temperature) for s in stages]
    with jax.enable_x64(False):
        one = _fzg_a(8)
        torque = jnp.asarray(3.726 * stages**2, jnp.float32)
        got = jax.vmap(lambda t: _fzg_a_torque(t))(torque)
    assert one.safety_factor.dtype == jnp.float32 and got.dtype == jnp.float32
    np.testing.assert_allclose(np.asarray(got), want, rtol=2e-5)


def _fzg_a_torque(torque):
    r = _fzg_a(8)  # the geometry; the torque replaced
    m, z1, a = 4.5e-3, 16, 91.5e-3
    alpha = math.radians(20.0)
    awt = math.acos((z1 + 24) * m / 2 * math.cos(alpha) / a)
    lub = tr.Lubricant(100e-6, 11e-6, 880.0, 20e-9, 90.0, 6e-4)
    ea = float(r.positions[3] - r.positions[0]) * z1 * math.tan(awt) / (2 * math.pi)
    return tr.ts_scuffing(z1, 1.5, a, awt, 0.0, z1 * m, (88.77e-3, 112.5e-3), 20e-3, (ea, 0.0),
                          torque, 2170 * math.pi / 30, 1.0, lub, (0.35e-6, 0.35e-6),
                          tr.ScuffingLimits(8), 206e9, 0.3).max_flash_temperature


# -- jaxgear's path-based flash temperature with the TS's load sharing ----------------------------


def test_path_flash_temperature_with_the_ts_load_sharing_matches_the_closed_form():
    """mesh_scuffing (Blok at jaxgear's cells) with line loads X_Γ(Γ) w_Bn (the TS's X_Γ at each
    cell's Γ) and μ = μ_mC gives the closed form's θ_fl at each cell to 1e-9 and its θ_fl,max to
    the 64-per-pitch positions' sampling (1 %, the cells miss the step at B or D by up to a
    position): the two methods agree where their loads do."""
    from test_flash import NU, PPP, SPEED, TORQUE, E, _gamma, _lubricant, _spur

    pair, res = _spur()
    lub = _lubricant()
    u, a, awt = pair.gear_ratio, pair.center_distance, pair.operating_pressure_angle
    da = tuple(2 * r for r in pair.tip_radii)
    d1 = pair.pinion.teeth * pair.normal_module
    ea = pair.transverse_contact_ratio
    closed = tr.ts_scuffing(pair.pinion.teeth, u, a, awt, 0.0, d1, da, pair.face_width,
                            (ea, 0.0), TORQUE, SPEED, 1.0, lub, (0.6e-6, 0.6e-6),
                            tr.ScuffingLimits(10), E, NU)
    ga, gb, gd, ge = (float(v) for v in closed.positions)
    s = np.asarray(res.cell_s)
    g = _gamma(pair, s)
    mask = np.asarray(res.cell_mask)
    x = np.asarray(tr.ts_load_sharing(g, ga, gb, gd, ge, ea, 0.0, 0.0))
    w = np.where(mask, x * TORQUE / (pair.base_radii[0] * pair.face_width), 0.0)
    loaded = eqx.tree_at(lambda r: r.line_load, res, jnp.asarray(w))
    mu = float(closed.friction_coefficient)
    trib = tr.mesh_tribology(pair, loaded, lub, TORQUE, SPEED, (0.6e-6, 0.6e-6), E, NU,
                             friction=tr.GivenFriction(mu))
    out = tr.mesh_scuffing(pair, loaded, trib, lub, E, NU, tr.ScuffingLimits(10))
    on = np.asarray(out.loaded)
    ts = np.asarray(tr.ts_flash_temperature(pair, g[on], x[on], mu, TORQUE, SPEED, E, NU))
    np.testing.assert_allclose(np.asarray(out.flash_temperature)[on], ts, rtol=1e-9)
    assert float(out.max_flash_temperature) == pytest.approx(
        float(closed.max_flash_temperature), rel=1e-2)
    assert PPP >= 64


# -- the spec's keys -----------------------------------------------------------------------------


BAD = [
    (_data(min_safety_scuffing=0.2), "[rating] min_safety_scuffing = 0.2"),
    (_data(lubricant={k: v for k, v in LUBRICANT.items() if k != "fzg_load_stage"}),
     ("[rating] min_safety_scuffing = 1.5: not read: the scuffing check needs [lubricant] "
      "with fzg_load_stage")),
    (_data(lubricant=LUBRICANT | {"fzg_load_stage": 15}), "[lubricant] fzg_load_stage = 15"),
    (_data(lubricant=LUBRICANT | {"film": "grubin"}), "[lubricant] film"),
    (_data(lubricant=LUBRICANT | {"bulk_temperature_C": 120.0, "bulk_lubrication_factor": 1.2}),
     "[lubricant] bulk_lubrication_factor = 1.2: not read"),
]


@pytest.mark.parametrize("data,message", BAD, ids=[m.split(":")[0] for _, m in BAD])
def test_bad_scuffing_keys_are_refused_in_one_line(data, message):
    _refused(data, message)


def test_without_scuffing_keys_the_sizing_has_no_scuffing():
    data = _data()
    del data["lubricant"]["fzg_load_stage"], data["rating"]["min_safety_scuffing"]
    spec, _ = jio.parse_sizing_spec(data)
    assert spec.scuffing is None and spec.mesh_loss is not None
    spec, _ = jio.parse_sizing_spec(_data())
    assert float(spec.scuffing.min_safety) == S_B_MIN
    assert spec.scuffing.limits.flash() == 80 + 2.25 * 64


def test_scuffing_rejects_candidates_pitting_and_bending_accept():
    """The check is S_B >= S_Bmin on the table's S_B; some candidates fail it alone (reason
    "scuffing"); the least margin takes S_B/S_Bmin."""
    _, _, table = _sized()
    c = table.columns
    j = list(js.CHECKS).index("scuffing")
    rated = np.isfinite(c["S_B"])
    np.testing.assert_array_equal(table.failed[rated, j], c["S_B"][rated] < S_B_MIN)
    reasons = np.array(table.reasons())
    assert (reasons == "scuffing").sum() >= 1
    only = reasons == "scuffing"
    assert np.all(c["S_B"][only] < S_B_MIN)
    margin = np.minimum.reduce([np.minimum(c["S_H1"], c["S_H2"]) / 1.1,
                                np.minimum(c["S_F1"], c["S_F2"]) / 1.4, c["S_B"] / S_B_MIN])
    np.testing.assert_allclose(c["least_margin"][rated], margin[rated], rtol=1e-12)


def test_scuffing_safety_is_an_objective_of_the_front():
    """``S_B`` as a maximised objective: the front over (mass, S_B) is the feasible candidates
    no other feasible one dominates, found here by a brute-force comparison; without the
    scuffing keys the objective is refused in one line."""
    spec, _ = jio.parse_sizing_spec(_data(min_safety_scuffing=1.0))  # some candidates pass
    table = js.size(spec)
    front = js.pareto_front(table, (("mass_kg", "min"), ("S_B", "max")))
    c, ok = table.columns, table.feasible
    mass, s_b = c["mass_kg"], c["S_B"]
    want = [i for i in np.flatnonzero(ok)
            if not any((mass[j] <= mass[i]) and (s_b[j] >= s_b[i])
                       and ((mass[j] < mass[i]) or (s_b[j] > s_b[i]))
                       for j in np.flatnonzero(ok))]
    got = np.flatnonzero(front.rank == 1)
    np.testing.assert_array_equal(np.sort(got), np.sort(want))
    assert len(want) >= 2
    data = _data()
    data["pareto"] = {"minimise": ["mass_kg"], "maximise": ["S_B"]}
    spec, _ = jio.parse_sizing_spec(data)
    assert spec.objectives == (("mass_kg", "min"), ("S_B", "max"))
    del data["lubricant"]["fzg_load_stage"], data["rating"]["min_safety_scuffing"]
    _refused(data, "[pareto] maximise = ['S_B']: 'S_B' needs the scuffing rating")


def test_a_written_candidate_case_loads_without_the_sizing_key():
    """``--write K``: the case keeps the spec's [lubricant] (its scuffing keys: a case run
    rates scuffing by the contact solve, mesh_scuffing) and drops [rating]
    min_safety_scuffing (a comment), and loads."""
    spec, tables, table = _sized()
    k = int(np.flatnonzero(np.isfinite(table.columns["S_B"]))[0])
    row = {name: v[k] for name, v in table.columns.items()}
    text = jio.candidate_case_text(tables, spec, row, k)
    assert "\nmin_safety_scuffing" not in text and "# the sizing's min_safety_scuffing" in text
    assert "fzg_load_stage = 8" in text
    case = jio.parse_case(__import__("tomllib").loads(text))
    assert case is not None


# -- the refinement and float32 (slow tier: each its own compile) --------------------------------


@pytest.mark.slow
def test_refined_designs_meet_the_scuffing_limit():
    """β and the shifts refined with S_B/S_Bmin − 1 >= 0 among the constraints: every refined
    row passes every check, S_B >= S_Bmin re-rated one at a time by candidate_outputs; a row
    failing scuffing alone as enumerated is refined into a feasible design."""
    data = _data()
    data["sizing"].update({"helix_angle_deg": [8.0, 20.0], "profile_shift_min": -0.5,
                           "profile_shift_max": 1.0})
    spec, _ = jio.parse_sizing_spec(data)
    table = js.size(spec)
    reasons = np.array(table.reasons())
    rows = np.r_[np.flatnonzero(reasons == "scuffing")[:2], np.flatnonzero(reasons == "")[:1]]
    assert rows.size >= 2
    ref = js.refine(spec, table, rows=rows, starts=3)
    c = ref.columns
    assert c["refined"][rows].sum() >= 1
    for k in rows[c["refined"][rows] == 1]:
        assert ref.feasible[k]
        o, passed = js.candidate_outputs(
            spec, c["normal_module_m"][k], float(c["z1"][k]), float(c["z2"][k]), c["x1"][k],
            c["x2"][k], c["face_width_m"][k], helix_angle=c["helix_angle_rad"][k])
        out = dict(zip(js.OUTPUTS, np.asarray(o), strict=True))
        assert bool(np.all(np.asarray(passed))) and out["S_B"] >= S_B_MIN
        assert out["S_B"] == pytest.approx(c["S_B"][k], rel=1e-9)
    assert not np.any(ref.feasible[rows] & (c["S_B"][rows] < S_B_MIN))


@pytest.mark.slow
def test_sizing_with_scuffing_runs_in_float32():
    """x64 off: the whole sizing program (rating and scuffing, vmapped) runs in float32 and
    gives the float64 table's S_B to float32 accuracy and the same scuffing verdicts away
    from the limit."""
    _, _, table64 = _sized()
    k = int(np.flatnonzero(np.isfinite(table64.columns["S_B"]))[0])
    c = {name: v[k] for name, v in table64.columns.items()}
    with jax.enable_x64(False):
        spec, _ = jio.parse_sizing_spec(_data())
        table = js.size(spec)
        f32 = [jnp.asarray(c[n], jnp.float32)
               for n in ("normal_module_m", "z1", "z2", "x1", "x2", "face_width_m")]
        o, _ = js.candidate_outputs(spec, *f32)
    assert o.dtype == jnp.float32  # the program's numbers; the table holds them as float64
    s_b = table.columns["S_B"]
    ok = np.isfinite(table64.columns["S_B"])
    np.testing.assert_allclose(s_b[ok], table64.columns["S_B"][ok], rtol=2e-4)
    j = list(js.CHECKS).index("scuffing")
    away = ok & (np.abs(table64.columns["S_B"] / S_B_MIN - 1) > 1e-3)
    np.testing.assert_array_equal(table.failed[away, j], table64.failed[away, j])
