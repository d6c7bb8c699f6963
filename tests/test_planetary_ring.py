"""The flexible ring gear of a planetary stage (jaxgear.planetary.CondensedRing in
jaxgear.planetary.planetary_quasi_static) and the resonance rule of the ring's nodal-diameter modes
(jaxgear.planetary.ring_excitation).

References: springs in series (a ring compliance c at each planet's station adds 1 / k_r + c);
the rigid ring (the flexible ring 10^3 stiffer, within 0.5 %); the FE ring's static solve under
the solved mesh forces (the ring deflections at the contacts and the support's reactions, 1e-9);
a direct Fourier decomposition of N equally spaced moving point loads (1e-12).
"""

import math

import equinox as eqx
import jax
import numpy as np
import pytest

import fem_prep as fp
import jaxgear as jg
import jaxgear.planetary as jp
from _planetary_stage import K0, SEQ, geometry, stage
from jaxgear.cli import planetary as pr

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0  # N m on the sun
PIN_ERRORS = np.array([15e-6, 0.0, 0.0])  # m, tangential, planet 1
RIM = 0.009  # m, the ring's radial rim thickness under the root circle (3 m_n)


@pytest.fixture(scope="module")
def seq():
    geo = geometry(**SEQ)
    return geo, stage(geo, 3, pin=3e8, sun_bearing=1e8)


def ring_body(geo, support):
    """The SEQ stage's ring (53 teeth, m = 3 mm, b = 30 mm) as a thin rim of 9 mm under its
    root circle, condensed on its 53 root-patch stations (2 axial master planes)."""
    pr = geo.planet_ring
    r_f = float(pr.root_radii[1])
    return fp.RingBody(
        "seq-ring",
        r_f,
        r_f + RIM,
        float(pr.gear.face_width),
        fp.Material(),
        fp.MeshSettings(fp.Hex20(), size=RIM, circumferential_size=0.012),
        fp.Condensation(fp.CraigBampton(), fp.Distributing(), modes=4, teeth=53,
                        axial_master_nodes=2),
        support,
    )


@pytest.fixture(scope="module")
def fe_ring(seq):
    """The ring on a uniform elastic housing (1e11 Pa/m in each direction)."""
    prep = fp.prepare_ring(ring_body(seq[0], fp.ElasticFoundation(1e11, 1e11, 1e11)))
    return prep, fp.ring_master_compliance(prep)[0]


@pytest.fixture(scope="module")
def bolted_ring(seq):
    """The ring bolted to a rigid housing by 6 clamped seats (8 mm each)."""
    prep = fp.prepare_ring(ring_body(seq[0], fp.BoltedFlange(6, 0.008, math.pi / 6)))
    return prep, fp.ring_master_compliance(prep)[0]


def test_station_compliance_adds_in_series(seq):
    """A ring whose stations are independent springs of compliance c along any direction, with
    the planets on stations (x = 0, 12 stations): each ring mesh becomes k_r in series with
    1 / c, so the forces are those of the rigid ring with k_r' = 1 / (1 / k_r + c)."""
    _, st = seq
    c = 4e-9  # m/N
    z = 12
    F = np.zeros((z, 2, z, 2))
    F[np.arange(z), :, np.arange(z), :] = c * np.eye(2)
    x = np.array([0.0])
    model = jp.PlanarPlanetary()
    flex = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS,
                                     ring=jp.CondensedRing(F))
    k_r = float(st.ring_mesh_stiffness)
    series = jp.planetary_quasi_static(model, with_ring_k(st, 1 / (1 / k_r + c)),
                                       jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS)
    np.testing.assert_allclose(flex.sun_mesh_forces, series.sun_mesh_forces, rtol=1e-9)
    np.testing.assert_allclose(flex.ring_mesh_forces, series.ring_mesh_forces, rtol=1e-9)
    np.testing.assert_allclose(flex.ring_deflection, c * np.asarray(flex.ring_mesh_forces),
                               rtol=1e-9)
    rigid = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS)
    assert np.all(np.asarray(rigid.ring_deflection) == 0.0)


def with_ring_k(st, k_r):
    return eqx.tree_at(lambda s: s.ring_mesh_stiffness, st, np.asarray(k_r, float))


# default tier: tests/test_planetary_ring.py::test_station_compliance_adds_in_series (the flexible ring's contact solve against series springs) and tests/test_planetary_ring_dynamics.py::test_stiff_fe_ring_equals_the_rigid_ring_constant_meshes
@pytest.mark.slow
def test_stiff_flexible_ring_equals_rigid_ring_and_soft_one_lowers_k_gamma(seq, fe_ring):
    """The FE ring made 10^3 stiffer (its compliance / 10^3: E x 10^3, linear elasticity)
    equals the lumped rigid ring within 0.5 % (forces and K_gamma); the real ring relieves the
    planet whose pin error overloads it (sun, pins and carrier held, as the series-spring test
    of tests/test_planetary_mesh.py): K_gamma 1.183 -> 1.110 to 1.117, lower at every
    carrier position."""
    geo, _ = seq
    st = stage(geo, 3)
    _, F = fe_ring
    model = jp.PlanarPlanetary()
    # carrier positions over 1/6 of a turn of the planets around the ring (a bolt pitch)
    x = np.linspace(0.0, st.ring.base_radius * 2 * math.pi / 6, 7)
    rigid = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS)
    stiff = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS,
                                      ring=jp.CondensedRing(F / 1e3))
    soft = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), TORQUE, x, PIN_ERRORS,
                                     ring=jp.CondensedRing(F))
    np.testing.assert_allclose(stiff.sun_mesh_forces, rigid.sun_mesh_forces, rtol=5e-3)
    np.testing.assert_allclose(stiff.ring_mesh_forces, rigid.ring_mesh_forces, rtol=5e-3)
    np.testing.assert_allclose(stiff.k_gamma, rigid.k_gamma, rtol=5e-3)
    assert float(rigid.k_gamma[0]) == pytest.approx(1.1832, abs=1e-4)
    assert np.all(np.asarray(soft.k_gamma) < np.asarray(rigid.k_gamma) - 0.05)
    # the torques still balance: T_s = r_bs sum F_s
    np.testing.assert_allclose(st.sun.base_radius * np.asarray(soft.sun_mesh_forces).sum(1),
                               TORQUE, rtol=1e-9)


@pytest.mark.slow
def test_stiff_flexible_ring_equals_rigid_ring_with_real_contact(seq, fe_ring):
    """As the test above, with the meshes from real contact (ContactMeshes, uniform k0, 12
    positions over a mesh period): the ring 10^3 stiffer within 0.5 % of the rigid one (forces),
    and the real ring lowers the period's largest K_gamma (1.731 -> 1.398)."""
    geo, _ = seq
    st = stage(geo, 3)
    _, F = fe_ring
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    x = np.asarray(meshes.positions(12))
    model = jp.PlanarPlanetary()
    rigid = jp.planetary_quasi_static(model, st, meshes, TORQUE, x, PIN_ERRORS)
    stiff = jp.planetary_quasi_static(model, st, meshes, TORQUE, x, PIN_ERRORS,
                                      ring=jp.CondensedRing(F / 1e3))
    soft = jp.planetary_quasi_static(model, st, meshes, TORQUE, x, PIN_ERRORS,
                                     ring=jp.CondensedRing(F))
    np.testing.assert_allclose(stiff.sun_mesh_forces, rigid.sun_mesh_forces, rtol=5e-3)
    np.testing.assert_allclose(stiff.ring_mesh_forces, rigid.ring_mesh_forces, rtol=5e-3)
    assert float(rigid.k_gamma_max) == pytest.approx(1.7306, abs=1e-3)
    assert float(soft.k_gamma_max) < float(rigid.k_gamma_max) - 0.3
    assert np.all(np.asarray(soft.result) == 0)


def test_ring_deflections_and_support_reactions_from_the_fe_ring(seq, bolted_ring):
    """The ring mesh forces of the flexible solve, put on the FE ring's masters (station hats,
    uniform across the face): its displacement along each force at the contacts equals the
    solve's ring deflections, and the bolt seats' reactions balance the mesh forces (force and
    moment about the axis), both to 1e-9."""
    _, st = seq
    prep, F = bolted_ring
    ring = jp.CondensedRing(F)
    x = np.array([0.0, 0.0123])
    got = jp.planetary_quasi_static(jp.PlanarPlanetary(), st, jp.ConstantMeshes(), TORQUE, x,
                                    PIN_ERRORS, ring=ring)
    teeth, nax, _ = prep.master_dofs.shape
    for i, xi in enumerate(x):
        P = np.asarray(got.ring_mesh_forces[i])
        phi = np.asarray(jp.ring_contact_angles(st, xi))
        # hats and directions written here: station k at 2 pi k / 53, e = (sin, -cos)(phi + a_r)
        t = np.mod(phi, 2 * math.pi) / (2 * math.pi / teeth)
        k0 = np.floor(t).astype(int)
        xi_ = t - k0
        a = phi + float(st.ring_pressure_angle)
        e = np.stack([np.sin(a), -np.cos(a)], 1)
        loads = np.zeros((teeth, nax, 3))
        for n in range(3):
            for k, wk in ((k0[n] % teeth, 1 - xi_[n]), ((k0[n] + 1) % teeth, xi_[n])):
                loads[k, :, :2] += wk * P[n] * e[n] / nax
        u = prep.static(loads)
        q = u.reshape(-1, 3)
        # the masters' displacement: the fit, read through the coupled DOFs
        um = _masters(prep, loads)[prep.master_dofs].mean(axis=1)  # (teeth, 3): face mean
        w = np.array([
            sum(wk * e[n] @ um[k, :2]
                for k, wk in ((k0[n] % teeth, 1 - xi_[n]), ((k0[n] + 1) % teeth, xi_[n])))
            for n in range(3)
        ])
        np.testing.assert_allclose(w, got.ring_deflection[i], rtol=1e-9)
        r = prep.support_reactions(u).reshape(-1, 3)
        applied = loads.reshape(-1, 3)
        xm = prep.coupled.rim_positions.reshape(-1, 3)
        scale = np.abs(P).sum()
        np.testing.assert_allclose(r.sum(0) + applied.sum(0), 0.0, atol=1e-9 * scale)
        tz = np.sum(np.cross(prep.mesh.nodes, r)[:, 2]) + np.sum(np.cross(xm, applied)[:, 2])
        assert abs(tz) < 1e-9 * scale * prep.ring.outer_radius
        assert np.abs(q).max() > 0


def test_the_deflected_shape_written_to_ring_vtu(seq, bolted_ring):
    """jaxgear run's ring.vtu deflected shape (jaxgear/cli/planetary.py ring_operating_shape) at
    x = 0: the FE ring's static response to the solve's ring-mesh forces put on the stations
    (E^T P): the loads written here uniform across the face (two axial master planes: the
    trapezoid weights are 1/2, 1/2) give the same field (1e-12); read through the condensed
    solve's masters, its face mean along each force is the solve's ring deflection, and the bolt
    seats' reactions balance the mesh forces written here from their angles (force, 1e-9)."""
    _, st = seq
    prep, F = bolted_ring
    ring = jp.CondensedRing(F)
    # x = 0 first among the stiff-ring test's seven carrier positions: its compiled solve
    x = np.linspace(0.0, st.ring.base_radius * 2 * math.pi / 6, 7)
    got = jp.planetary_quasi_static(jp.PlanarPlanetary(), st, jp.ConstantMeshes(), TORQUE, x,
                                    PIN_ERRORS, ring=ring)
    P = np.asarray(got.ring_mesh_forces[0])
    E = np.asarray(ring.station_rows(st, 0.0))
    u = pr.ring_operating_shape(prep, (E.T @ P).reshape(-1, 2))
    teeth, nax, _ = prep.master_dofs.shape
    assert nax == 2
    loads = np.zeros((teeth, nax, 3))
    loads[:, :, :2] = (E.T @ P).reshape(-1, 2)[:, None, :] / nax
    np.testing.assert_allclose(u, prep.static(loads).reshape(-1, 3), rtol=0,
                               atol=1e-12 * np.abs(u).max())
    um = _masters(prep, loads)[prep.master_dofs].mean(axis=1)  # (teeth, 3): face mean
    np.testing.assert_allclose(E @ um[:, :2].ravel(), got.ring_deflection[0], rtol=1e-9)
    phi = np.asarray(jp.ring_contact_angles(st, 0.0)) + float(st.ring_pressure_angle)
    applied = (P[:, None] * np.stack([np.sin(phi), -np.cos(phi)], 1)).sum(0)
    r = prep.support_reactions(u.ravel()).reshape(-1, 3)
    np.testing.assert_allclose(r.sum(0)[:2] + applied, 0.0, atol=1e-9 * np.abs(P).sum())
    assert np.abs(u).max() > 1e-7  # microns: a visible shape


def _masters(prep, loads):
    """The coupled DOFs (on ``kept``) of the condensed static solve under master loads."""
    c = prep.condensed
    f = np.zeros(c.K.shape[0])
    f[: c.master_dofs.size] = loads.ravel()
    return c.basis @ np.linalg.solve(c.K, f)


@pytest.mark.parametrize("n_planets, ring_teeth", [(3, 53), (4, 52), (5, 97), (3, 99)])
def test_excitation_rule_against_a_fourier_decomposition(n_planets, ring_teeth):
    """N point loads P cos(h Z_r theta_j(t)) moving with the carrier, theta_j = Omega t +
    2 pi j / N: the complex circumferential harmonic n of the load, sampled in time over a
    carrier turn, is a single line at (+/-) order (h Z_r - s n) Omega for the listed (n, s)
    pairs, and zero (1e-12) for every other n."""
    h_max, max_nd = 2, 12
    n_t = 4 * (h_max * ring_teeth + max_nd) + 8
    t = np.arange(n_t) / n_t  # carrier turns (Omega t = 2 pi t)
    theta = 2 * math.pi * (t[:, None] + np.arange(n_planets)[None, :] / n_planets)
    for h in range(h_max + 1):
        load = np.cos(h * ring_teeth * theta)  # (n_t, N)
        nd, order = jp.ring_excitation(n_planets, ring_teeth, h, max_nd)
        for n in range(max_nd + 1):
            # the cos and sin harmonics of the load distribution, as time series
            c = (load * np.cos(n * theta)).sum(1) / math.pi
            s = (load * np.sin(n * theta)).sum(1) / math.pi
            spectrum = np.abs(np.fft.fft(c)) + np.abs(np.fft.fft(s))
            lines = set(np.nonzero(spectrum > 1e-9 * n_t)[0])
            lines = {min(k, n_t - k) for k in lines}
            want = set(order[nd == n].tolist())
            assert lines == want, (h, n, lines, want)
            if not want:
                assert np.abs(c).max() < 1e-12 * n_planets and np.abs(s).max() < 1e-12 * n_planets


def test_excitation_rule_examples():
    # 3 planets, 53 teeth: 53 = 2 (mod 3); h = 1 excites n = 2 (53 - 2 = 51) and n = 1 (54)
    nd, order = jp.ring_excitation(3, 53, 1, 4)
    assert nd.tolist() == [1, 2, 4] and order.tolist() == [54, 51, 57]
    # mean forces (h = 0): the multiples of N at n Omega
    nd, order = jp.ring_excitation(4, 52, 0, 9)
    assert nd.tolist() == [0, 4, 4, 8, 8] and order.tolist() == [0, 4, 4, 8, 8]
    with pytest.raises(ValueError, match="n_planets"):
        jp.ring_excitation(0, 53, 1, 4)


def test_ring_resonances_by_hand():
    """3 planets, 53 teeth, the n = 2 mode at 320 Hz: h = 1 drives it at order 51 (53 - 2 = 51 =
    0 mod 3), h = 2 at order 108 (106 + 2 = 108 = 0 mod 3; 104 is not): carrier speeds 320 / 51
    and 320 / 108 rev/s; h = 0 never (2 is not a multiple of 3)."""
    got = jp.ring_resonances({2: 320.0}, 3, 53, harmonics=2)
    assert [(r["harmonic"], r["order"]) for r in got] == [(2, 108), (1, 51)]
    assert got[0]["carrier_speed_hz"] == pytest.approx(320.0 / 108, rel=1e-15)
    assert got[1]["carrier_speed_hz"] == pytest.approx(320.0 / 51, rel=1e-15)
    # 3 planets, the n = 3 mode: h = 0 at 3 Omega, h = 1 at 53 -/+ 3 = 50, 56 (neither = 0 mod 3)
    got = jp.ring_resonances({3: 900.0}, 3, 53, harmonics=1)
    assert [(r["harmonic"], r["order"]) for r in got] == [(0, 3)]


def test_bad_ring_inputs_one_line(seq):
    _, st = seq
    with pytest.raises(ValueError, match="compliance"):
        jp.CondensedRing(np.zeros((4, 2, 5, 2)))
    with pytest.raises(ValueError, match="ring"):
        jp.planetary_quasi_static(jp.PlanarPlanetary(), st, jp.ConstantMeshes(), TORQUE,
                                  np.array([0.0]), ring="flexible")
