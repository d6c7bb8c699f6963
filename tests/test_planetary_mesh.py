"""The 2N meshes of a planetary stage from real contact (jaxgear.planetary.ContactMeshes) and the
quasi-static solve over the carrier turn (jaxgear.planetary.planetary_quasi_static): the sun-ring
offset against contact points on drawn planet flanks, the reduction to load_sharing with constant
springs and with the lines counted by hand, the phase pattern of the planets' forces, K_gamma
with one pin error against a spring model written here, equilibrium and Willis, contact loss."""

import jax
import numpy as np
import pytest
from scipy.optimize import brentq

import jaxgear as jg
import jaxgear.planetary as jp
from _planetary_stage import INPHASE, K0, SEQ, counted_stiffness, geometry, stage, with_meshes
from _tracing import traced

jax.config.update("jax_enable_x64", True)

PER_PERIOD = 12  # a multiple of N = 3 and 4: the planets' phases fall on the positions


@pytest.fixture(scope="module")
def seq():
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    return geo, st, meshes


def _inv(a):
    return np.tan(a) - a


def _drawn_offset(geo, c0):
    """Delta_rs from contact points: the planet's involute flanks drawn in its frame (teeth
    centred at c0 + 2 pi j / z_p, thickness from s_t = m_t (pi/2 + 2 x tan a_n)), cut with both
    lines of action (tangent to the planet's and the other member's base circles, built here),
    keeping the points where the flank's normal lies along the line, on the side of the
    planet's tangent point where the other member is; s from each pair's
    engagement point (the planet's tip circle on the sun line, the ring's tip circle on the
    ring line)."""
    sp, pr = geo.sun_planet, geo.planet_ring
    a = geo.center_distance
    z_p = sp.gear.teeth
    m_t = sp.transverse_module
    a_t = sp.transverse_pressure_angle
    r_p = z_p * m_t / 2
    r_bp = r_p * np.cos(a_t)
    r_ap = sp.tip_radii[1]
    r_br, r_ar = pr.base_radii[1], pr.tip_radii[1]
    s_t = m_t * (np.pi / 2 + 2 * sp.gear.profile_shift * np.tan(ALPHA_N))
    p_b = 2 * np.pi * r_bp / z_p

    def flank(R, c, sign):
        th = c + sign * (s_t / (2 * r_p) + _inv(a_t) - _inv(np.arccos(r_bp / R)))
        return np.array([R * np.cos(th), R * np.sin(th)])

    def contacts(nu, h, direction):
        out = []
        grid = np.linspace(r_bp * (1 + 1e-9), r_ap, 400)
        for j in range(z_p):
            c = c0 + 2 * np.pi * j / z_p
            for sign in (1.0, -1.0):
                g = np.array([nu @ flank(R, c, sign) - h for R in grid])
                for i in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]:
                    R = brentq(lambda R: nu @ flank(R, c, sign) - h, grid[i], grid[i + 1],
                               xtol=1e-15)
                    t = flank(R * (1 + 1e-7), c, sign) - flank(R * (1 - 1e-7), c, sign)
                    if abs(t @ direction) / np.linalg.norm(t) < 1e-5:
                        out.append(flank(R, c, sign))
        return out

    a_s, a_r = geo.sun_pressure_angle, geo.ring_pressure_angle
    # sun line: direction n (contact travels +n), tangent to the planet at -r_bp nu_s
    n = np.array([np.sin(a_s), np.cos(a_s)])
    nu_s = np.array([np.cos(a_s), -np.sin(a_s)])
    assert abs(abs(nu_s @ np.array([-a, 0.0]) + r_bp) - sp.base_radii[0]) < 1e-12  # sun tangent
    t_eng = -np.sqrt(r_ap**2 - r_bp**2)  # the planet's tip, on the sun's side of T_p
    # the sun side of T_p only (beyond it the other flanks touch the line's continuation)
    s_sun = [(p + r_bp * nu_s) @ n - t_eng for p in contacts(nu_s, -r_bp, n)
             if (p + r_bp * nu_s) @ n < 0]
    # ring line: contact travels along -m from T_p = r_bp nu_r
    m = np.array([-np.sin(a_r), np.cos(a_r)])
    nu_r = np.array([np.cos(a_r), np.sin(a_r)])
    centre = np.array([-a, 0.0])
    t_ring = -(centre + r_br * nu_r - r_bp * nu_r) @ m  # the ring's tangent point, along -m
    assert abs(nu_r @ centre + r_br - r_bp) < 1e-12  # tangent to the ring's base circle
    roots = t_ring + np.array([-1, 1]) * np.sqrt(r_ar**2 - r_br**2)
    t_eng = roots[(roots > 0) & (roots < np.sqrt(r_ap**2 - r_bp**2))]
    assert t_eng.size == 1
    s_ring = [(p - r_bp * nu_r) @ (-m) - t_eng[0] for p in contacts(nu_r, r_bp, -m)
              if (p - r_bp * nu_r) @ (-m) > 0]
    assert len(s_sun) >= 1 and len(s_ring) >= 1
    return np.mod(s_ring[0] - s_sun[0], p_b), p_b, s_sun, s_ring


ALPHA_N = np.radians(20.0)


@pytest.mark.parametrize(
    "params",
    [SEQ, INPHASE, dict(z_s=21, z_p=18, x_s=0.2, x_p=0.4), dict(z_s=22, z_p=19, x_s=0.25, x_p=0.35)],
)
def test_sun_ring_offset_against_contact_points_on_drawn_flanks(params):
    geo = geometry(**params)
    want = jp.sun_ring_offset(geo)
    for c0 in (0.0, 0.1234):  # whatever the planet's angle
        got, p_b, s_sun, s_ring = _drawn_offset(geo, c0)
        d = abs(got - want)
        assert min(d, p_b - d) < 1e-9 * p_b
        # the drawn contacts are one base pitch apart on each line
        for s in (s_sun, s_ring):
            r = np.mod(np.asarray(s) - s[0] + p_b / 2, p_b) - p_b / 2
            np.testing.assert_allclose(r, 0.0, atol=1e-9 * p_b)


@pytest.mark.parametrize("model", [jp.TorsionalPlanetary(), jp.PlanarPlanetary()])
def test_constant_meshes_reduce_to_load_sharing(model):
    geo = geometry(**SEQ)
    st = stage(geo, 3, pin=3e8, sun_bearing=1e8)
    errors = np.array([4e-6, 0.0, -2e-6])
    radial = np.array([0.0, 20e-6, 0.0])
    want = jp.load_sharing(model, st, 300.0, errors, radial)
    got = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(), np.asarray(300.0),
                                    np.array([0.0, 1e-3]), errors, radial)
    for i in range(2):
        np.testing.assert_allclose(got.sun_mesh_forces[i], want.sun_mesh_forces, rtol=1e-10)
        np.testing.assert_allclose(got.ring_mesh_forces[i], want.ring_mesh_forces, rtol=1e-10)
        np.testing.assert_allclose(got.displacement[i], want.displacement, rtol=1e-10,
                                   atol=1e-10 * np.abs(want.displacement).max())
        assert float(got.k_gamma[i]) == pytest.approx(float(want.k_gamma), rel=1e-10)


# default tier: tests/test_planetary_mesh.py::test_k_gamma_with_one_pin_error_against_a_spring_model (the same contact solve against the lines counted by hand)
@pytest.mark.slow
def test_uniform_contact_equals_load_sharing_with_the_lines_counted_by_hand(seq):
    """Uniform k0, spur, rigid teeth otherwise: at each position each mesh is k0 b n(x), n the
    lines counted here; load_sharing with those per-planet stiffnesses gives the same forces."""
    geo, st, meshes = seq
    model = jp.TorsionalPlanetary()
    errors = np.array([10e-6, 0.0, 0.0])
    x = np.asarray(meshes.positions(PER_PERIOD))
    got = jp.planetary_quasi_static(model, st, meshes, np.asarray(1000.0), x, errors)
    assert np.all(np.asarray(got.result) == 0)
    seen = set()
    for i, xi in enumerate(x):
        k_s, k_r = counted_stiffness(geo, meshes, xi)
        seen.add((tuple(k_s), tuple(k_r)))
        ref = jp.load_sharing(model, with_meshes(st, k_s, k_r), 1000.0, errors)
        assert float(ref.sun_mesh_forces.min()) > 0  # every mesh loaded
        np.testing.assert_allclose(got.sun_mesh_forces[i], ref.sun_mesh_forces, rtol=1e-10)
        np.testing.assert_allclose(got.ring_mesh_forces[i], ref.ring_mesh_forces, rtol=1e-10)
    assert len(seen) > 3  # the stiffness really varies over the period


# default tier: tests/test_planetary_dynamics.py::test_net_mesh_excitation_cancellation_follows_the_phasing_rule (each planet's contact-cell mesh stiffness at its phase, sequential and in phase)
@pytest.mark.slow
def test_planet_forces_follow_the_mesh_phases(seq):
    """Equally spaced planets, no error: planet n's forces are planet 1's a phase gamma_n later
    (sequential 19/-53, N = 3); in phase (20/-52, N = 4) the planets' forces are equal."""
    geo, st, meshes = seq
    model = jp.PlanarPlanetary()
    x = meshes.positions(PER_PERIOD)
    got = jp.planetary_quasi_static(model, st, meshes, np.asarray(400.0), x, np.zeros(3))
    g_s, g_r = jp.mesh_phases(19, 53, st.planet_angles)
    assert np.allclose(g_s, [0, 1 / 3, 2 / 3]) and np.allclose(g_r, g_s)
    f_s, f_r = np.asarray(got.sun_mesh_forces), np.asarray(got.ring_mesh_forces)
    assert np.ptp(f_s[:, 0]) > 0.2 * f_s.mean()  # a real variation to follow
    for n in range(3):
        shift = int(round(g_s[n] * PER_PERIOD))  # F_n(x) = F_1(x - gamma_n p_b)
        np.testing.assert_allclose(f_s[:, n], np.roll(f_s[:, 0], shift), rtol=1e-9)
        np.testing.assert_allclose(f_r[:, n], np.roll(f_r[:, 0], shift), rtol=1e-9)
    geo4 = geometry(**INPHASE)
    st4 = stage(geo4, 4)
    m4 = jp.ContactMeshes.from_geometry(geo4, st4.planet_angles, jg.Uniform(K0))
    got4 = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st4, m4, np.asarray(400.0), x,
                                     np.zeros(4))
    f4 = np.asarray(got4.sun_mesh_forces)
    np.testing.assert_allclose(f4, f4[:, :1] * np.ones((1, 4)), rtol=1e-9)


def test_k_gamma_with_one_pin_error_against_a_spring_model(seq):
    """A 15 um tangential error on planet 1's pin: per position, a series-spring model written
    here (rigid centres and pins, ring and carrier held, k_sn and k_rn of the lines counted):
    F_j = k_j (u_s - e_j (cos a_s + cos a_r)), k_j = k_sn k_rn / (k_sn + k_rn), sum F_j =
    T / r_bs. K_gamma over the period within 1 % (planar model with stiff pins and bearings)."""
    geo, st, meshes = seq
    errors = np.array([15e-6, 0.0, 0.0])
    torque = 1000.0
    x = np.asarray(meshes.positions(PER_PERIOD))
    c = np.cos(geo.sun_pressure_angle) + np.cos(geo.ring_pressure_angle)
    r_s = geo.sun_planet.base_radii[0]
    k_hand = []
    for xi in x:
        k_s, k_r = counted_stiffness(geo, meshes, xi)
        k = k_s * k_r / (k_s + k_r)
        u_s = (torque / r_s + np.sum(k * errors * c)) / np.sum(k)
        f = k * (u_s - errors * c)
        assert f.min() > 0
        k_hand.append(f.max() / f.mean())
    k_hand = np.array(k_hand)
    assert k_hand.max() > 1.05
    for model, rtol in ((jp.TorsionalPlanetary(), 1e-6), (jp.PlanarPlanetary(), 1e-2)):
        got = jp.planetary_quasi_static(model, st, meshes, np.asarray(torque), x, errors)
        np.testing.assert_allclose(got.k_gamma, k_hand, rtol=rtol)
        assert float(got.k_gamma_max) == pytest.approx(k_hand.max(), rel=rtol)


def test_equilibrium_willis_and_contact_loss(seq):
    """With a pin error large enough to unload planet 1 (its meshes open: force 0, where the
    linear load_sharing gives a negative one), the torques still balance: T_s = r_bs sum F_s,
    the ring's reaction r_br sum F_r = (r_br / r_bs) T_s (Willis: z_r / z_s), the carrier's
    -(T_s + T_r), each to 1e-9."""
    geo, st, meshes = seq
    model = jp.PlanarPlanetary()
    errors = np.array([400e-6, 0.0, 0.0])
    torque = 300.0
    x = meshes.positions(PER_PERIOD)
    got = jp.planetary_quasi_static(model, st, meshes, np.asarray(torque), x, errors)
    f_s, f_r = np.asarray(got.sun_mesh_forces), np.asarray(got.ring_mesh_forces)
    assert np.all(f_s[:, 0] == 0.0) and np.all(f_r[:, 0] == 0.0)  # planet 1 out of contact
    linear = jp.load_sharing(model, with_meshes(st, 3e8, 3e8), torque, errors)
    assert float(linear.sun_mesh_forces[0]) < 0  # what the linear model would say
    r_s, r_r = st.sun.base_radius, st.ring.base_radius
    q = np.asarray(got.displacement)
    names = model.dof_names(st)
    t_ring = st.ring.torsional_stiffness * q[:, names.index("u_r")] / r_r**2 * r_r
    t_carrier = st.carrier.torsional_stiffness * q[:, names.index("u_c")] / st.carrier.base_radius
    np.testing.assert_allclose(r_s * f_s.sum(1), torque, rtol=1e-9)
    np.testing.assert_allclose(r_r * f_r.sum(1), torque * r_r / r_s, rtol=1e-9)
    np.testing.assert_allclose(r_r / r_s, 53 / 19, rtol=1e-12)
    # the ring's support reacts -r_br sum F_r ... as a spring on u_r: k u_r = -sum F_r
    np.testing.assert_allclose(t_ring, -r_r * f_r.sum(1), rtol=1e-6)
    np.testing.assert_allclose(t_carrier, torque * (1 + r_r / r_s), rtol=1e-6)


def test_bad_inputs_one_line():
    geo = geometry(**SEQ)
    with pytest.raises(ValueError, match="cannot be assembled"):
        jp.ContactMeshes.from_geometry(geo, np.radians([0.0, 121.0, 240.0]), jg.Uniform(K0))
    st = stage(geo, 3)
    with pytest.raises(ValueError, match="tangential_pin_errors"):
        jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, jp.ConstantMeshes(), 1.0,
                                  np.zeros(1), np.zeros(2))


# default tier: tests/test_planetary.py::test_float32_runs[campbell] (float32 against float64; float32 is a slow-tier environment property)
@pytest.mark.slow
def test_float32_runs():
    """With x64 off the contact meshes' quasi-static solve runs in float32 (the assembly check
    taking float32 angles) and its K_gamma agrees with float64 to 1e-4 (pins 5e8, sun bearing
    1e8 N/m: a moderate conditioning)."""
    out = {}
    for x64 in (False, True):
        with jax.enable_x64(x64):
            geo = geometry(**SEQ)
            st = stage(geo, 3, pin=5e8, sun_bearing=1e8)
            meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
            got = jp.planetary_quasi_static(jp.PlanarPlanetary(), st, meshes,
                                            np.asarray(1000.0), meshes.positions(PER_PERIOD),
                                            np.array([10e-6, 0.0, 0.0]))
            assert np.all(np.asarray(got.result) == 0)
            out[x64] = np.asarray(got.k_gamma)
            assert out[x64].dtype == (np.float64 if x64 else np.float32)
    np.testing.assert_allclose(out[False], out[True], rtol=1e-4)


def test_a_new_python_torque_reruns_the_program():
    """planetary_quasi_static with a Python-number torque and pin errors: a second torque
    traces nothing (the numbers enter the program as arrays, not as constants of a program per
    value) and gives its own answer: equal sharing of the torque, each sun mesh T / (N r_bs)
    (torsional model, constant meshes, no pin error; to the floating planets' 1e-12 hold)."""
    st = stage(geometry(**SEQ), 3)
    x = jp.ConstantMeshes().positions(4, 1)
    jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, jp.ConstantMeshes(), 700.0, x, 0.0)
    with traced() as names:
        got = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, jp.ConstantMeshes(), 900.0,
                                        x, 0.0)
    assert not [n for n in names if n.endswith("planetary_quasi_static")], names
    want = 900.0 / (3 * float(st.sun.base_radius))
    np.testing.assert_allclose(np.asarray(got.sun_mesh_forces), want, rtol=1e-9)
