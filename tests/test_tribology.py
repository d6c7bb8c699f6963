"""EHL film, friction and mesh power loss along the path of contact (jaxgear.tribology).

References: GEARpie's FZG reports (cfernandesFEUP/GEARpie, REPORT/C14.txt at commit 039d496 and
REPORT/H501.txt at 45f9b44; their inputs from the same commits' GEAR_LIBRARY and
LUBRICANT_LIBRARY: the oils' ASTM D341 constants give ν₄₀ and ν₁₀₀ below, the density at 15 °C,
its expansion, Gold's α at the oil temperature and X_L); the line-contact film formulas written
again here in NumPy from the papers; Ohlendorf's closed-form H_V, the limit of the integrated
sliding loss for a load shared evenly among the pairs in contact; central differences.

GEARpie's method differs from jaxgear's in three documented ways, which the comparisons undo
explicitly (docs/tribology.md): its rigid load sharing (here: the result's line loads replaced
by F_n over the contact length, ``_uniform``); its Grubin film with the contact modulus E* where
Grubin's W has E' = 2E* (h × 2^(−1/11)), its entrainment speed in the normal section (u/cos β_b)
and its inlet shear-heating factor φ_T (0.996 / 0.999 as reported); its Schlenk load F_bn over
the smallest total contact length where ISO/TR 14179-2 has F_bt/b (equal for both pairs here).
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

E, NU = 206e9, 0.3
RA = (0.6e-6, 0.6e-6)
SPEED = 1500 * 2 * math.pi / 60  # pinion, rad/s
TORQUE = 200.0  # pinion, N·m
PPP = 128

# GEARpie's oils (ASTM D341 constants m, n with c = 0.7, ρ₁₅, α_T, Gold's α at 75 °C, X_L)
M320 = {
    "m": 9.0658,
    "n": 3.4730,
    "rho15": 902.0,
    "expansion": 5.8e-4,
    "alpha": 71.05e-9,
    "xl": 0.85,
}
P68 = {"m": 7.9787, "n": 3.0914, "rho15": 859.0, "expansion": 5.5e-4, "alpha": 9.92e-9, "xl": 0.65}


def _astm(oil, t_c):
    """ν (m²/s) of GEARpie's ASTM D341 fit at t_c (°C)."""
    return (-0.7 + 10 ** (10 ** (oil["m"] - oil["n"] * math.log10(t_c + 273.15)))) * 1e-6


def _lubricant(oil, t_c=75.0):
    return tr.Lubricant(
        _astm(oil, 40.0), _astm(oil, 100.0), oil["rho15"], oil["alpha"], t_c, oil["expansion"]
    )


def _fzg_pair(teeth, module, shifts, face, helix_deg):
    """GEARpie's FZG pair: zero-backlash centre distance and its addendum reduction k m_n
    (DIN 3960: tip radius r + m_n (1 + x − k)), rack fillet 0.38 m_n."""

    def pair(k):
        members = [jg.Member(z, x, 1.0 - k, 1.25, face, 0.38) for z, x in zip(teeth, shifts)]
        return jg.GearPair(*members, module, math.radians(20.0), math.radians(helix_deg))

    p0 = pair(0.0)
    a0 = module * sum(teeth) / (2 * math.cos(math.radians(helix_deg)))
    return pair(sum(shifts) - (p0.center_distance - a0) / module)


@functools.cache
def _c14():
    pair = _fzg_pair((16, 24), 4.5e-3, (0.1817, 0.1715), 0.014, 0.0)
    return pair, _solve(pair, 1)


@functools.cache
def _h501():
    pair = _fzg_pair((20, 30), 3.5e-3, (0.1809, 0.0891), 0.023, 15.0)
    return pair, _solve(pair, 24)


def _mesh(pair, slices):
    s, k = jg.stiffness_table(
        pair,
        jg.Weber(),
        youngs_modulus=E,
        poisson_ratio=NU,
        line_load=TORQUE / pair.pitch_radii[0] / pair.face_width,
    )
    return jg.MeshModel.from_pair(pair, s, k, slices)


def _solve(pair, slices):
    return jg.quasi_static(_mesh(pair, slices), None, TORQUE, positions_per_pitch=PPP).mesh


def _uniform(pair, res):
    """The result with GEARpie's rigid load sharing: F_n over the contact length at each
    position, on every cell on the flanks."""
    n = res.line_load.shape[-1]
    cell = pair.face_width / (n * math.cos(pair.base_helix_angle))
    f_n = TORQUE / (pair.base_radii[0] * math.cos(pair.base_helix_angle))
    length = jnp.sum(res.cell_mask, axis=(1, 2)) * cell
    w = jnp.where(res.cell_mask, f_n / length[:, None, None], 0.0)
    return eqx.tree_at(lambda r: r.line_load, res, w)


def _run(pair, res, oil, **kw):
    return tr.mesh_tribology(pair, res, _lubricant(oil), TORQUE, SPEED, RA, E, NU, **kw)


def _mean_loaded(x, out):
    return float(np.mean(np.asarray(x)[np.asarray(out.loaded)]))


# -- GEARpie C14 ------------------------------------------------------------------------------


def test_c14_geometry_friction_and_loss_factor_match_gearpie():
    pair, _ = _c14()
    assert round(pair.transverse_contact_ratio, 2) == 1.44
    r_w1 = pair.center_distance / (1 + pair.gear_ratio)
    assert TORQUE / r_w1 == pytest.approx(5464.5, rel=1e-4)  # F_t
    assert tr.ohlendorf_loss_factor(pair) == pytest.approx(0.1950, abs=5e-5)
    lub = _lubricant(M320)
    assert float(lub.kinematic_viscosity()) * 1e6 == pytest.approx(53.10, abs=0.005)
    assert float(lub.dynamic_viscosity) * 1e3 == pytest.approx(46.23, abs=0.005)
    mu = tr.Schlenk(M320["xl"]).coefficient(pair, lub, TORQUE, SPEED, RA)
    assert float(mu) == pytest.approx(0.0483, abs=5e-5)


def test_c14_pitch_pressure_and_power_loss_match_gearpie():
    pair, res = _c14()
    uni = _uniform(pair, res)
    out = _run(pair, uni, M320, friction=tr.Schlenk(M320["xl"]))
    # p₀ at the pitch point (single-pair contact): the cells within half a step of s_C
    s_c = tr.pitch_point_roll(pair)
    near = np.asarray(out.loaded) & (np.abs(np.asarray(out.cell_s) - s_c) < pair.base_pitch / PPP)
    assert near.any()
    p0 = np.asarray(out.max_pressure)[near]
    assert p0.mean() * 1e-6 == pytest.approx(1347.3, rel=2e-3)
    # P_VZP = P_in H_V μ; GEARpie's H_VL 0.1945 (its numerical integration of the same sharing)
    assert float(out.mean_power_loss) == pytest.approx(295.17, rel=0.01)
    # the largest local sliding loss μ w v_g, at the start of the path (25.57 W/mm)
    assert float(jnp.max(out.local_loss)) * 1e-3 == pytest.approx(25.57, rel=0.01)
    # with jaxgear's own (elastic) load sharing: less load at the ends of the path, where the
    # sliding is fastest, so a lower loss (the method differs: 1.4 % here)
    own = _run(pair, res, M320, friction=tr.Schlenk(M320["xl"]))
    assert 0.95 * 295.17 < float(own.mean_power_loss) < float(out.mean_power_loss)
    assert float(own.efficiency) == pytest.approx(1 - float(own.mean_power_loss) / (TORQUE * SPEED))


def test_c14_central_film_matches_gearpie_grubin():
    """GEARpie's h0C average along AE (1.28 µm) is Grubin's formula with E* in W (× 2^(−1/11)
    against Grubin's E') and its inlet shear-heating factor 0.996; the cells of the positions
    sample the path evenly, so their mean is the average along AE."""
    pair, res = _c14()
    out = _run(pair, _uniform(pair, res), M320, film=tr.Grubin())
    h = _mean_loaded(out.central_film, out) * 2 ** (-1 / 11) * 0.996
    assert h * 1e6 == pytest.approx(1.28, rel=0.01)


# -- GEARpie H501 -----------------------------------------------------------------------------


def test_h501_power_loss_and_film_match_gearpie():
    pair, res = _h501()
    assert round(pair.transverse_contact_ratio, 2) == 1.46
    assert round(pair.overlap_ratio, 2) == 0.54
    uni = _uniform(pair, res)
    # the same μ as GEARpie's (0.0353) and its rigid sharing: its P_VZP = P_in H_VL μ
    out = _run(pair, uni, P68, friction=tr.GivenFriction(0.0353))
    assert float(out.mean_power_loss) == pytest.approx(207.46, rel=0.01)
    assert float(out.loss_factor) == pytest.approx(0.1869, rel=0.01)
    # Ohlendorf's closed form, GEARpie's 0.1639 (ε₁, ε₂ and cos β_b as here)
    assert tr.ohlendorf_loss_factor(pair) == pytest.approx(0.1639, abs=5e-4)
    # Schlenk: ISO/TR 14179-2's load F_bt/b; GEARpie's F_bn over the smallest total contact
    # length. H501's smallest total contact length is one whole line, b/cos β_b, so the two
    # loads agree and so do the μ (0.0353)
    lub = _lubricant(P68)
    mu = float(tr.Schlenk(P68["xl"]).coefficient(pair, lub, TORQUE, SPEED, RA))
    assert mu == pytest.approx(0.0353, rel=0.01)  # 0.03535
    n = res.line_load.shape[-1]
    l_min = (
        float(jnp.min(jnp.sum(res.cell_mask, axis=(1, 2))))
        * pair.face_width
        / (n * math.cos(pair.base_helix_angle))
    )
    assert l_min == pytest.approx(pair.face_width / math.cos(pair.base_helix_angle), rel=0.01)
    # h0C 0.16 µm (two digits): Grubin with E* in W, GEARpie's normal-section speeds u/cos β_b
    # and φ_T 0.999
    g = _run(pair, uni, P68, film=tr.Grubin())
    h = (
        _mean_loaded(g.central_film, g)
        * 2 ** (-1 / 11)
        * math.cos(pair.base_helix_angle) ** (-8 / 11)
        * 0.999
    )
    assert h * 1e6 == pytest.approx(0.16, abs=0.005)


# -- the film formulas against a separate evaluation ---------------------------------------


def _reference_films(R, u, w, eta, alpha, e1, nu1, e2, nu2):
    """Dowson (1968) h_min, Dowson–Toyoda (1979) h_c, Pan–Hamrock (1989) h_min and h_c, written
    from the papers in their dimensional form with E' = 2/((1 − ν₁²)/E₁ + (1 − ν₂²)/E₂)."""
    ep = 2.0 / ((1 - nu1**2) / e1 + (1 - nu2**2) / e2)
    U, G, W = eta * u / (ep * R), alpha * ep, w / (ep * R)
    return {
        "dh_min": 2.65 * R * U**0.7 * G**0.54 / W**0.13,
        "dh_c": 3.06 * R * U**0.69 * G**0.56 / W**0.10,
        "ph_min": 1.714 * R * U**0.694 * G**0.568 / W**0.128,
        "ph_c": 2.922 * R * U**0.692 * G**0.470 / W**0.166,
    }


@pytest.mark.parametrize(
    "R, u, w, eta, alpha",
    [
        (0.01, 5.0, 4e5, 0.046, 20e-9),  # a gear contact near the pitch point
        (0.004, 1.0, 1e6, 0.01, 15e-9),  # tight curvature, slow, heavy load
        (0.05, 20.0, 1e5, 0.2, 30e-9),  # large radius, fast, viscous
    ],
)
def test_film_formulas_against_separate_evaluation(R, u, w, eta, alpha):
    ref = _reference_films(R, u, w, eta, alpha, E, NU, E, NU)
    e_star = jg.contact_modulus(E, NU)
    dh = tr.film_thickness(tr.DowsonHigginson(), R, u, w, eta, alpha, e_star)
    ph = tr.film_thickness(tr.PanHamrock(), R, u, w, eta, alpha, e_star)
    assert float(dh.minimum) == pytest.approx(ref["dh_min"], rel=1e-12)
    assert float(dh.central) == pytest.approx(ref["dh_c"], rel=1e-12)
    assert float(ph.minimum) == pytest.approx(ref["ph_min"], rel=1e-12)
    assert float(ph.central) == pytest.approx(ref["ph_c"], rel=1e-12)
    # both minimum-film formulas describe the same physics: within 30 % of each other
    assert float(ph.minimum) == pytest.approx(float(dh.minimum), rel=0.3)


def test_film_at_a_vanishing_load_is_finite_with_a_zero_derivative():
    """A load far below any gear contact's (the smooth contact law gives 1e-276 N/m to corner
    cells beyond the path of contact that do not touch, and 0 where it underflows) is taken at
    the load group W = 1e-12: the film is the formula's at that W (written again here from the
    papers), its derivative in w is 0 and finite (W^-0.13's would overflow), and a load with
    W above 1e-12 keeps the formula's own film."""
    R, u, eta, alpha = 0.0075, 2.5, 0.046, 20e-9
    e_star = jg.contact_modulus(E, NU)
    w_floor = 1e-12 * 2.0 * e_star * R  # the load at W = 1e-12
    ref = _reference_films(R, u, w_floor, eta, alpha, E, NU, E, NU)
    for kind, key in ((tr.DowsonHigginson(), "dh"), (tr.PanHamrock(), "ph")):
        for w in (0.0, 2.2e-276, 1e-3 * w_floor):
            h = tr.film_thickness(kind, R, u, w, eta, alpha, e_star)
            assert float(h.minimum) == pytest.approx(ref[f"{key}_min"], rel=1e-12)
            assert float(h.central) == pytest.approx(ref[f"{key}_c"], rel=1e-12)
            dh = jax.grad(
                lambda x, k=kind: tr.film_thickness(k, R, u, x, eta, alpha, e_star).minimum
            )
            assert float(dh(jnp.asarray(w))) == 0.0
        above = _reference_films(R, u, 10.0 * w_floor, eta, alpha, E, NU, E, NU)
        h = tr.film_thickness(kind, R, u, 10.0 * w_floor, eta, alpha, e_star)
        assert float(h.minimum) == pytest.approx(above[f"{key}_min"], rel=1e-12)


# -- the integrated loss in Ohlendorf's limit ---------------------------------------------


@pytest.mark.parametrize("ppp", [64, 256])
def test_integrated_loss_factor_tends_to_ohlendorf_under_uniform_sharing(ppp):
    """A spur pair, the load shared evenly among the pairs in contact: the integrated H_V is
    Ohlendorf's closed form up to the sampling of the positions (O(1/P))."""
    pair, _ = _c14()
    res = jg.quasi_static(_mesh(pair, 1), None, TORQUE, positions_per_pitch=ppp).mesh
    out = _run(pair, _uniform(pair, res), M320, friction=tr.GivenFriction(0.05))
    err = abs(float(out.loss_factor) / tr.ohlendorf_loss_factor(pair) - 1)
    assert err < 8.0 / ppp
    assert float(out.mean_power_loss) == pytest.approx(
        0.05 * tr.ohlendorf_loss_factor(pair) * TORQUE * SPEED, rel=8.0 / ppp
    )


# -- gradients, float32, bad input --------------------------------------------------------


@functools.cache
def _objective():
    pair, _ = _c14()
    mesh = _mesh(pair, 4)
    lub = _lubricant(M320)
    theta = jg.mesh_positions(mesh, 32)

    def f(p):  # p = (tip relief depth, crowning depth) in µm
        mods = jg.Modifications.symmetric(
            jg.MemberModification(
                tip_relief_depth=p[0] * 1e-6, tip_relief_extent=0.3, crowning_depth=p[1] * 1e-6
            )
        )
        res = jg.quasi_static(mesh, mods, TORQUE, theta, contact=jg.SmoothContact(1e-7))
        out = tr.mesh_tribology(
            pair, res, lub, TORQUE, SPEED, RA, E, NU, friction=tr.Schlenk(M320["xl"])
        )
        return jnp.stack([out.efficiency * 100.0, out.min_specific_film])

    return jax.jit(f), jax.jit(jax.jacrev(f))


def test_gradients_wrt_relief_and_crowning_match_central_differences():
    """d(efficiency %, min λ)/d(tip relief depth, crowning depth) against central differences
    (two steps agreeing: no kink crossed). Crowning of a spur pair moves load across the face,
    not between the pairs in contact nor along the path: the efficiency does not depend on it
    (its derivative ~1e-19), min λ does (the most loaded slice)."""
    f, jac = _objective()
    p0, h = np.array([12.0, 4.0]), 1e-3
    g = np.asarray(jac(jnp.asarray(p0)))  # (2 outputs, 2 parameters)
    for i in range(2):
        e = np.zeros(2)
        e[i] = h
        fd = (np.asarray(f(jnp.asarray(p0 + e))) - np.asarray(f(jnp.asarray(p0 - e)))) / (2 * h)
        fd2 = (np.asarray(f(jnp.asarray(p0 + e / 2))) - np.asarray(f(jnp.asarray(p0 - e / 2)))) / h
        np.testing.assert_allclose(fd2, fd, rtol=1e-5, atol=1e-9)
        np.testing.assert_allclose(g[:, i], fd, rtol=1e-4, atol=1e-9)
    assert np.all(np.abs(g[:, 0]) > 1e-6) and abs(g[1, 1]) > 1e-6
    assert abs(g[0, 1]) < 1e-9


def test_float32_matches_float64():
    pair, res = _c14()
    ref = _run(pair, res, M320)
    names = ("mean_power_loss", "efficiency", "min_specific_film", "friction_coefficient")
    want = {name: float(getattr(ref, name)) for name in names}
    with jax.enable_x64(False):
        res32 = jax.tree.map(lambda x: x.astype(np.float32) if x.dtype == np.float64 else x, res)
        out = _run(pair, res32, M320)
        assert out.central_film.dtype == np.float32
        for name in names:
            assert float(getattr(out, name)) == pytest.approx(want[name], rel=1e-4), name


@pytest.mark.parametrize(
    "kwargs, match",
    [
        ({"viscosity_100": 400e-6}, "viscosity_100 = 0.0004 m²/s is out of range"),
        ({"density": 100.0}, "density = 100"),
        ({"pressure_viscosity": -1e-9}, "pressure_viscosity = -1e-09"),
        ({"oil_temperature": 300.0}, "oil_temperature = 300"),
    ],
)
def test_lubricant_bad_input(kwargs, match):
    args = {
        "viscosity_40": 320e-6,
        "viscosity_100": 22e-6,
        "density": 900.0,
        "pressure_viscosity": 20e-9,
        "oil_temperature": 75.0,
    }
    with pytest.raises(ValueError, match=match) as err:
        tr.Lubricant(**{**args, **kwargs})
    assert "\n" not in str(err.value)


def test_mesh_tribology_bad_input():
    pair, res = _c14()
    lub = _lubricant(M320)
    with pytest.raises(ValueError, match="speed = -1") as err:
        tr.mesh_tribology(pair, res, lub, TORQUE, -1.0, RA, E, NU)
    assert "\n" not in str(err.value)
    with pytest.raises(ValueError, match="roughness"):
        tr.mesh_tribology(pair, res, lub, TORQUE, SPEED, (0.6e-6, 1.0), E, NU)
    with pytest.raises(ValueError, match="value = 2"):
        tr.GivenFriction(2.0)
    with pytest.raises(ValueError, match="lubricant_factor = 0"):
        tr.Schlenk(0.0)
