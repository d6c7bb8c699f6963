"""The compound planetary stage with stepped planets (jaxgear.gearbox.CompoundPlanetaryStage, a
stage kind added on the gearbox's stage interface alone; docs/gearbox.md): Willis' ratios of
the stepped train, its torsional matrices against ones written here, the simple stage as its
limit z_p1 = z_p2, the planets' mesh phasing, the quasi-static torque balance of a coupled run
and a coupled run of the stage driving a spur pair."""

import math

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg

import jaxgear as jg
import jaxgear.planetary as jp
from jaxgear import gearbox as gb

M_N, ALPHA = 4e-3, math.radians(20.0)
K_U = 1.4e10  # N/m per m of contact line
B = 0.05
# the stepped stage: sun 20, planet 30 (on the sun) / 22 (on the ring), ring 72, one module and
# one centre distance (20 + 30 = 72 - 22 = 50 teeth: a = 100 mm)
Z_S, Z_P1, Z_P2, Z_R = 20, 30, 22, 72
RB = 0.5 * M_N * math.cos(ALPHA)  # base radius per tooth (m)
INERTIAS = (0.5, 2.0, 1.6e-3, 9.0e-3)  # carrier, ring, sun, planet (kg m^2)
M_P = 5.0  # kg
C = jp.Central


def _pairs(z_p2=Z_P2, z_r=Z_R, ded=1.4):
    sun = jg.GearPair(jg.Member(Z_S, face_width=B), jg.Member(Z_P1, face_width=B), M_N, ALPHA,
                      center_distance=0.1)
    ring = jg.InternalGearPair(jg.Member(z_p2, face_width=B, dedendum_coeff=ded),
                               jg.Member(-z_r, face_width=B), M_N, ALPHA, center_distance=0.1)
    return sun, ring


def _meshes(pairs):
    return tuple(jg.MeshModel.from_pair(p, *jg.stiffness_table(p, jg.Uniform(K_U)), 1)
                 for p in pairs)


def _stage(input=C.SUN, output=C.CARRIER, psi=None, cells=True, held=1e9, **kw):
    pairs = _pairs()
    psi = 2 * np.pi * np.arange(4) / 4 if psi is None else psi
    return gb.CompoundPlanetaryStage.from_pairs(
        *pairs, psi, INERTIAS, M_P, (K_U * B * 1.6, K_U * B * 1.9), held, input, output,
        _meshes(pairs) if cells else None, **kw)


def _hz(m, k):
    lam = scipy.linalg.eigh(k, m, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)


# -- kinematics -------------------------------------------------------------------------------


@pytest.mark.parametrize("input, output, ratio", [
    (C.SUN, C.CARRIER, 1 + Z_R * Z_P1 / (Z_S * Z_P2)),  # ring held
    (C.SUN, C.RING, -Z_R * Z_P1 / (Z_S * Z_P2)),  # carrier held (a star stage)
    (C.RING, C.CARRIER, 1 + Z_S * Z_P2 / (Z_R * Z_P1)),  # sun held
    (C.CARRIER, C.SUN, 1 / (1 + Z_R * Z_P1 / (Z_S * Z_P2))),  # ring held, speed increaser
])
def test_willis_ratio_of_the_stepped_train(input, output, ratio):
    """omega_in / omega_out of the stepped 2K-H train from the tooth counts (ring held, sun to
    carrier: 1 + z_r z_p1 / (z_s z_p2)), and the rigid motion at those speeds (each planet's
    turn relative to the carrier from the sun mesh's rolling, z_p1 (w_p - w_c) = -z_s (w_s -
    w_c)) strains no mesh."""
    stage = _stage(input, output, cells=False)
    out_speed = float(stage.kinematics(1.0, 1.0)[0])
    assert 1.0 / out_speed == pytest.approx(ratio, rel=1e-12)
    w = np.asarray(stage.speeds(1.0))  # carrier, ring, sun
    w_p = w[0] - Z_S * (w[2] - w[0]) / Z_P1
    # the ring mesh rolls too: z_r (w_r - w_c) = z_p2 (w_p - w_c)
    assert Z_R * (w[1] - w[0]) == pytest.approx(Z_P2 * (w_p - w[0]), abs=1e-12)
    q = np.concatenate([w, np.full(4, w_p)])
    _, k = stage.matrices()
    k = np.asarray(k)
    held = {C.CARRIER: 0, C.RING: 1, C.SUN: 2}[({C.CARRIER, C.RING, C.SUN} - {input, output}).pop()]
    assert q[held] == 0.0
    assert np.max(np.abs(k @ q)) < 1e-9 * np.max(np.abs(k)) * np.max(np.abs(q))


def test_carrier_frequency_of_the_stepped_stage():
    """jaxgear.gearbox.carrier_frequencies on a compound stage (ring held, sun in at 1 rad/s):
    the carrier turns at 1 / (1 + z_r z_p1 / (z_s z_p2)) rad/s, from the tooth counts (the
    stage's frame speed, as a planetary stage's; a parallel pair's is 0)."""
    chain = gb.GearboxTorsional((_stage(cells=False),), [])
    got = float(gb.carrier_frequencies(chain, 1.0)[0])
    assert got == pytest.approx(1.0 / (1 + Z_R * Z_P1 / (Z_S * Z_P2)) / (2 * math.pi),
                                rel=1e-12)


# -- the torsional matrices and modes ---------------------------------------------------------


def _reference(teeth, psi, r_per_tooth, k_mesh, held, hold):
    """(M, K) on (theta_c, theta_r, theta_s, theta_1..N), written from the spec: the planets'
    mass m_p on the carrier at a, the deflections r_bs th_s + r_bp1 th_n - (r_bs + r_bp1) th_c
    and r_br th_r - r_bp2 th_n - (r_br - r_bp2) th_c, the held member's spring."""
    z_s, z_p1, z_p2, z_r = teeth
    (c1, c2), n = r_per_tooth, len(psi)
    r_s, r_p1, r_p2, r_r = z_s * c1, z_p1 * c1, z_p2 * c2, z_r * c2
    a = (z_s + z_p1) * c1 / math.cos(ALPHA)
    m = np.diag([INERTIAS[0] + n * M_P * a**2, INERTIAS[1], INERTIAS[2]] + [INERTIAS[3]] * n)
    k = np.zeros((3 + n, 3 + n))
    for j in range(n):
        v = np.zeros(3 + n)
        v[[0, 2, 3 + j]] = [-(r_s + r_p1), r_s, r_p1]
        k += k_mesh[0] * np.outer(v, v)
        v = np.zeros(3 + n)
        v[[0, 1, 3 + j]] = [-(r_r - r_p2), r_r, -r_p2]
        k += k_mesh[1] * np.outer(v, v)
    k[held, held] += hold
    return m, k, (r_s, r_p1, r_p2, r_r), a


def test_torsional_modes_against_matrices_written_here():
    """Three stepped planets 18 / 36-24 / 78 (two modules, unequally spaced, assembling:
    (z_s z_p2 + z_r z_p1) / gcd(z_p1, z_p2) = 270 per turn), sun held: jaxgear.gearbox.gearbox_modes
    of the one-stage chain and the coupled model's modes (constant meshes, the carrier output held
    by run.output_stiffness) against scipy's eigensolve of (M, K) assembled here."""
    teeth, c = (18, 36, 24, 78), (0.5 * 3e-3 * math.cos(ALPHA), 0.5 * 4.5e-3 * math.cos(ALPHA))
    psi = 2 * np.pi * np.array([0, 88, 181]) / 270
    k_mesh = (6e8, 9e8)
    m, k, radii, a = _reference(teeth, psi, c, k_mesh, held=2, hold=3e8)
    stage = gb.CompoundPlanetaryStage(teeth, radii, a, INERTIAS, M_P, psi, k_mesh, 3e8,
                                      C.RING, C.CARRIER)
    got = np.asarray(gb.gearbox_modes(gb.GearboxTorsional((stage,), [])).frequencies)
    want = _hz(m, k)
    assert want[0] < 1e-3 and got[0] < 1e-3  # the ring and carrier free: the train turns
    np.testing.assert_allclose(got[1:], want[1:], rtol=1e-9)
    k_out = 4e7
    k[0, 0] += k_out
    run = gb.GearboxRun(100.0, k_out)
    got = np.asarray(gb.gearbox_coupled_modes(gb.GearboxTorsional((stage,), []), run)
                     .analysis.frequency)
    np.testing.assert_allclose(got, _hz(m, k), rtol=1e-9)


def _simple_limit():
    """The example's simple stage 20/30/80 (docs/gearbox.md) as a PlanetaryGearboxStage and as
    a CompoundPlanetaryStage with z_p1 = z_p2 = 30, the same inertias and meshes."""
    geo = jg.planetary_geometry(jg.Member(20, face_width=B),
                                jg.Member(30, face_width=B, dedendum_coeff=1.3),
                                jg.Member(-80, face_width=B), M_N, ALPHA)
    psi = 2 * np.pi * np.arange(4) / 4
    meshes = jp.ContactMeshes.from_geometry(geo, psi, jg.Uniform(K_U), 1)
    r_s, r_p = (float(r) for r in geo.sun_planet.base_radii)
    r_r = float(geo.planet_ring.base_radii[1])
    k_s, k_r = 8e8, 9e8
    member = jp.PlanetaryMember
    stage = jp.PlanetaryStage(
        sun=member(1.0, INERTIAS[2], r_s), ring=member(10.0, INERTIAS[1], r_r,
                                                       torsional_stiffness=1e9),
        carrier=member(10.0, INERTIAS[0], float(geo.center_distance)),
        planet=member(M_P, INERTIAS[3], r_p), planet_angles=psi,
        sun_pressure_angle=geo.sun_pressure_angle, ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=k_s, ring_mesh_stiffness=k_r)
    simple = gb.PlanetaryGearboxStage(stage, C.CARRIER, C.SUN, meshes)
    compound = gb.CompoundPlanetaryStage.from_pairs(
        geo.sun_planet, geo.planet_ring, psi, INERTIAS, M_P, (k_s, k_r), 1e9, C.CARRIER, C.SUN,
        (meshes.sun_mesh, meshes.ring_mesh), ring_offset=jg.planetary.sun_ring_offset(geo))
    return simple, compound


def test_equal_planet_gears_give_the_simple_stage():
    """z_p1 = z_p2 and r_bp1 = r_bp2: the torsional chain's modes, the coupled model's modes on
    the contact cells, and the cells themselves at several mesh travels (on the drive flanks
    and on the other ones, carrier in and sun out) are PlanetaryGearboxStage's (Kahraman's
    model through jaxgear.planetary, an independent implementation)."""
    simple, compound = _simple_limit()
    for f in (lambda s: gb.gearbox_modes(gb.GearboxTorsional((s,), [])).frequencies,
              lambda s: gb.gearbox_coupled_modes(gb.GearboxTorsional((s,), []),
                                                 gb.GearboxRun(100.0, 3e7)).analysis.frequency):
        want, got = np.asarray(f(simple)), np.asarray(f(compound))
        elastic = want > 1e-3
        np.testing.assert_allclose(got[elastic], want[elastic], rtol=1e-9)
        assert np.all(got[~elastic] < 1e-3)
    assert compound.mesh_period() == pytest.approx(float(simple.mesh_period()), rel=1e-12)
    # the rows through one compiled program per kind of stage (eagerly, each call's many small
    # programs); the same function of the stage's leaves
    rows = eqx.filter_jit(lambda stage, x: stage.cell_row(x))
    for sign in (1.0, -1.0):
        a, b = simple.on_flanks(sign), compound.on_flanks(sign)
        for x in (0.0, 3.1e-3, 7.7e-3, 11.2e-3):
            ra, rb = rows(a, jnp.asarray(x)), rows(b, jnp.asarray(x))
            np.testing.assert_array_equal(np.asarray(ra.mask), np.asarray(rb.mask))
            np.testing.assert_allclose(np.asarray(rb.V), np.asarray(ra.V), rtol=1e-12,
                                       atol=1e-15)
            np.testing.assert_allclose(np.asarray(rb.k * rb.length),
                                       np.asarray(ra.k * ra.length), rtol=1e-12)


# -- the meshes' phasing ----------------------------------------------------------------------


def test_mesh_phasing_follows_each_central_members_teeth():
    """Four planets at unequal angles that assemble (multiples of 2 pi / 1300: (z_s z_p2 + z_r
    z_p1) / gcd = 1300), tip relief on both meshes (the cells' initial separations vary along
    the path): planet n's sun-mesh cells at x are planet 1's at x - gamma_sn p_bs, gamma_sn =
    frac(z_s psi_n / 2 pi); its ring-mesh cells at x are planet 1's at x - gamma_rn p_br / rho,
    gamma_rn = frac(-z_r psi_n / 2 pi), rho = r_bp2 / r_bp1 (Parker & Lin 2004 mesh by mesh);
    the ring mesh repeats every 2 pi r_bp1 / z_p2 of sun-mesh travel, the sun mesh every p_bs."""
    psi = 2 * np.pi * np.array([0, 326, 649, 975]) / 1300
    tip = jg.MemberModification(tip_relief_depth=15e-6, tip_relief_extent=0.25)
    mods = (jg.Modifications.symmetric(tip), jg.Modifications.symmetric(tip))
    stage = _stage(psi=psi, modifications=mods)
    c = 2  # cells per mesh (one slice, two lines)
    p_s, p_r = 2 * np.pi * RB, 2 * np.pi * RB  # base pitches: m_n pi cos(alpha), one module
    rho = Z_P2 / Z_P1
    g_s, g_r = np.mod(Z_S * psi / (2 * np.pi), 1.0), np.mod(-Z_R * psi / (2 * np.pi), 1.0)
    assert np.ptp(g_s) > 0.1 and np.ptp(g_r) > 0.1

    row_at = eqx.filter_jit(stage.cell_row)  # one compiled program for the 49 travels

    def per_mesh(x):  # per mesh: sum of k l, sum of delta0 over the cells in contact
        row = row_at(jnp.asarray(x))
        on = np.asarray(row.mask)
        kl = np.where(on, np.asarray(row.k * row.length), 0.0).reshape(8, c).sum(-1)
        d0 = np.where(on, np.asarray(row.delta0), 0.0).reshape(8, c).sum(-1)
        return np.stack([kl / 1e9, d0 / 1e-6])  # (2, 8)

    spread = []
    for x in 0.7e-3 + 1.9e-3 * np.arange(7):
        got = per_mesh(x)
        spread.append(got[1])
        for n in range(1, 4):
            np.testing.assert_allclose(got[:, n], per_mesh(x - g_s[n] * p_s)[:, 0], rtol=1e-9,
                                       atol=1e-9)
            np.testing.assert_allclose(got[:, 4 + n], per_mesh(x - g_r[n] * p_r / rho)[:, 4],
                                       rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(per_mesh(x + 2 * np.pi * Z_P1 * RB / Z_P2)[:, 4:], got[:, 4:],
                                   rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(per_mesh(x + p_s)[:, :4], got[:, :4], rtol=1e-9, atol=1e-9)
    assert np.ptp(np.asarray(spread)) > 1.0  # the relief shows (um)


# -- coupled runs -----------------------------------------------------------------------------


def test_quasi_static_torque_balance_of_a_coupled_run():
    """The stage alone (sun in 500 N m, ring held, carrier out held by a spring) at a sun speed
    whose mesh frequencies lie far below its modes (0.5 rad/s: 1.3 Hz against kHz), over a
    window of whole periods of both meshes (15 sun-mesh, 11 ring-mesh periods): each mesh's mean
    force is the static one, F_s = T / (N r_bs) and F_r = F_s r_bp1 / r_bp2 (the planet's
    moment balance), and the carrier's spring carries T (1 + z_r z_p1 / (z_s z_p2))."""
    torque, k_out = 500.0, 5e6
    chain = gb.GearboxTorsional((_stage(),), [])
    run = gb.GearboxRun(torque, k_out, steps_per_period=256, periods=16, keep_periods=15)
    out = gb.gearbox_dynamics(chain, run, 0.5)
    f_s = torque / (4 * Z_S * RB)
    want = np.array([f_s] * 4 + [f_s * Z_P1 / Z_P2] * 4)
    np.testing.assert_allclose(np.asarray(out.static_forces), want, rtol=1e-12)
    assert int(out.result) == 0
    f = np.asarray(out.mesh_forces)
    np.testing.assert_allclose(np.mean(f, axis=0), want, rtol=1e-5)
    carrier = k_out * np.mean(np.asarray(out.displacement)[:, 0])
    assert carrier == pytest.approx(torque * (1 + Z_R * Z_P1 / (Z_S * Z_P2)), rel=1e-5)


# default tier: tests/test_gearbox_compound.py::test_quasi_static_torque_balance_of_a_coupled_run (the stepped stage's coupled run, static forces) and ::test_equal_planet_gears_give_the_simple_stage (its cells on both flanks)
@pytest.mark.slow
def test_coupled_run_of_the_stage_driving_a_pair():
    """The stepped stage (carrier in 5000 N m at 10 rad/s, ring held, sun out: its planets drive
    the sun, the other flanks) whose sun drives a spur pair 36 / 24 through a shaft, every mesh on
    its contact cells. The three mesh frequencies stand 15 : 11 : 32.5 (sun : ring : pair), so
    the whole excitation repeats every 30 sun-mesh periods; with 36 steps per pair period a block
    (the sun mesh's period) is 78 whole steps. One Newmark run settles: the dynamic factors over
    a window of one whole pattern (30 blocks) after 60 and after 90 blocks agree within 1e-4;
    every factor is finite and above 1; the static forces are the torque ratios'."""
    stage = _stage(C.CARRIER, C.SUN)
    pair = jg.GearPair(jg.Member(24, face_width=0.08), jg.Member(36, face_width=0.08), M_N, ALPHA)
    mesh = jg.MeshModel.from_pair(pair, *jg.stiffness_table(pair, jg.Uniform(K_U)), 1)
    par = gb.TorsionalPairGearboxStage((5.2e-3, 0.02), pair.base_radii, K_U * 0.08 * 1.6,
                                       input=1, mesh=mesh)
    chain = gb.GearboxTorsional((stage, par), [5e5])
    assert gb.mesh_names(chain)[-1] == "2:pair" and len(gb.mesh_names(chain)) == 9
    # one run of 120 blocks keeping the last 60: its two windows of 30 blocks are those of runs
    # of 90 and 120 blocks keeping 30 (the same steps from the same start; one compiled program
    # and 120 blocks integrated instead of two and 210)
    run = gb.GearboxRun(5000.0, 5e5, steps_per_period=36, periods=120, keep_periods=60)
    out = gb.gearbox_dynamics(chain, run, 10.0)
    assert int(out.result) == 0 and out.time.shape == (60 * 78,)
    forces, static = np.asarray(out.mesh_forces), np.asarray(out.static_forces)
    dfs = [np.max(half, axis=0) / static for half in np.split(forces, 2)]
    np.testing.assert_allclose(np.maximum(*dfs), np.asarray(out.dynamic_factors), rtol=1e-15)
    t_sun = 5000.0 / (1 + Z_R * Z_P1 / (Z_S * Z_P2))
    f_s = t_sun / (4 * Z_S * RB)
    np.testing.assert_allclose(np.asarray(out.static_forces),
                               [f_s] * 4 + [f_s * Z_P1 / Z_P2] * 4 + [t_sun / (36 * RB)],
                               rtol=1e-12)
    assert np.all(np.isfinite(dfs[1])) and np.all(dfs[1] > 1.0)
    np.testing.assert_allclose(dfs[0], dfs[1], rtol=1e-4)


def test_bad_inputs_one_line():
    with pytest.raises(ValueError, match="input = output"):
        _stage(C.SUN, C.SUN)
    with pytest.raises(ValueError, match="planet_angles"):  # 3 equally spaced: 2600 / 6
        _stage(psi=2 * np.pi * np.arange(3) / 3)
    with pytest.raises(ValueError, match="r_bp1 / r_bs"):
        gb.CompoundPlanetaryStage((20, 30, 22, 72), (0.04, 0.05, 0.04, 0.12), 0.1, INERTIAS, M_P,
                                  [0.0], (1e8, 1e8), 1e9, C.SUN, C.CARRIER)
    sun, _ = _meshes(_pairs())
    with pytest.raises(ValueError, match="ring_mesh"):
        gb.CompoundPlanetaryStage.from_pairs(*_pairs(), [0.0], INERTIAS, M_P, (1e8, 1e8), 1e9,
                                             C.SUN, C.CARRIER, (sun, None))
    with pytest.raises(ValueError, match="held_stiffness"):
        _stage(held=0.0)
