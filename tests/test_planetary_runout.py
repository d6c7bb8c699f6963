"""A planet's own runout (jaxgear.planetary.Eccentricities.planet) and the members' mass unbalance
(jaxgear.planetary.Unbalances): K_gamma over a planet turn against a spring model written here from the
directions of the forces on the planet; the unbalance's response far from resonance against the
static deflection U omega^2 / k (k written here from the geometry), near a translational mode
against the single-mode estimate of the modal damping, and its line at the member's own order;
the case keys and their refusals."""

import math
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _planetary_stage import A_R, A_S, K_MESH, R_P, R_R, R_S, lin_parker_stage as stage

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
import jaxgear.cli.planetary as pr

TORQUE = 3000.0
E = 30e-6  # m
F_NOM = TORQUE / (4 * R_S)


def spring_model(offsets, n):
    """Rigid centres, pins, ring and carrier; the sun free to turn under TORQUE. Each planet
    path is its sun mesh and ring mesh in series (the planet turns freely between them): the
    force F_n = k (u + o_n), k = k_s k_r / (k_s + k_r), o_n the path's opening offsets summed,
    u the sun's roll (m) from r_bs sum F_n = T."""
    k = K_MESH / 2
    o = np.asarray(offsets)
    u = TORQUE / R_S / (n * k) - o.mean()
    f = k * (u + o)
    return f, f.max() / f.mean()


def planet_offsets(e_zeta, e_eta):
    """The two meshes' compression change when the planet's toothed centre moves by
    (e_zeta, e_eta) (radial outward, tangential counter-clockwise): the sun pushes the planet
    forward and away from it, along (sin a_s, cos a_s); the ring pushes it forward and inward,
    along (-sin a_r, cos a_r) (the separating forces point away from the pushing member); a move
    along a force opens that mesh."""
    d_s = np.array([np.sin(A_S), np.cos(A_S)])
    d_r = np.array([-np.sin(A_R), np.cos(A_R)])
    e = np.array([e_zeta, e_eta])
    return -e @ d_s - e @ d_r


def test_planet_runout_over_a_planet_turn_against_the_spring_model():
    """Planet 1's toothed centre stands off its pin by E in a direction that turns with the
    planet: -x / r_bp relative to the carrier (the sun turning counter-clockwise drives the
    external planet the other way). K_gamma over one planet turn: torsional model exact
    (1e-9), planar (pins and bearings 1e13 N/m) within 1e-3 of the mean force and 1 %."""
    beta, n = 0.4, 4
    ecc = jp.Eccentricities(planet=np.array([E, 0, 0, 0]), planet_phase=beta)
    st = stage(n, ecc)
    x = np.arange(24) * 2 * np.pi * R_P / 24
    want_f, want_k = [], []
    for xi in x:
        a = beta - xi / R_P
        o = np.zeros(n)
        o[0] = planet_offsets(E * np.cos(a), E * np.sin(a))
        f, kg = spring_model(o, n)
        want_f.append(f)
        want_k.append(kg)
    want_f, want_k = np.array(want_f), np.array(want_k)
    assert want_k.max() > 1.1 and want_f.min() > 0  # a real spread, every mesh loaded
    for model, tol in ((jp.TorsionalPlanetary(), 1e-9), (jp.PlanarPlanetary(), 1e-3)):
        got = jax.vmap(lambda xi, m=model: jp.load_sharing(m, st, TORQUE, jnp.zeros(n),
                                                           travel=xi))(jnp.asarray(x))
        np.testing.assert_allclose(got.sun_mesh_forces, want_f, rtol=0, atol=tol * F_NOM)
        np.testing.assert_allclose(got.k_gamma, want_k, rtol=min(tol, 1e-2))
    # the contact solve (one unilateral spring per mesh) and the dynamics at a crawl
    q = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, jp.ConstantMeshes(),
                                  jnp.asarray(TORQUE), jnp.asarray(x[::6]))
    np.testing.assert_allclose(q.sun_mesh_forces, want_f[::6], rtol=1e-9)


# default tier: tests/test_planetary_eccentricity.py::test_dynamics_at_a_crawl_follow_the_turning_eccentricity (turning offsets in planetary_dynamics at a crawl) and tests/test_planetary_runout.py::test_planet_runout_over_a_planet_turn_against_the_spring_model
@pytest.mark.slow
def test_planet_runout_in_the_dynamics_at_a_crawl():
    """planetary_dynamics at 1e-7 rad/s over one planet turn (8 mesh periods of the constant
    meshes): the recorded forces are the spring model's at the recorded travels (1e-8)."""
    beta, n = -1.0, 4
    st = stage(n, jp.Eccentricities(planet=np.array([0, E, 0, 0]), planet_phase=beta))
    meshes = jp.ConstantMeshes(base_pitch=2 * np.pi * R_P / 8)
    run = jp.PlanetaryRun(jnp.asarray(TORQUE), steps_per_period=12, periods=8, keep_periods=8)
    r = jp.planetary_dynamics(jp.TorsionalPlanetary(), st, meshes, run, 1e-7)
    assert int(r.result) == 0
    for xi, f in zip(np.asarray(r.travel)[::5], np.asarray(r.sun_mesh_forces)[::5]):
        a = beta - xi / R_P
        o = np.zeros(n)
        o[1] = planet_offsets(E * np.cos(a), E * np.sin(a))
        np.testing.assert_allclose(f, spring_model(o, n)[0], rtol=0, atol=1e-8 * F_NOM)


def _whirl(r, idx, turn):
    """The complex amplitude c of x + i y = c e^(i turn) (the forward whirl at the turning
    angle ``turn`` (rad, per recorded step) over whole turns) and the complex order spectrum of
    x + i y (orders per turn of ``turn``, amplitudes)."""
    X = np.asarray(r.displacement)
    z = X[:, idx[0]] + 1j * X[:, idx[1]]
    z = z - z.mean()
    c = np.mean(z * np.exp(-1j * turn))
    return c, np.abs(np.fft.fft(z)) / z.size


# the unbalance tests' run (planar model, constant meshes, 16 steps per mesh period, 30 sun or
# planet turns of 8 mesh periods, the last turn kept, 5 % damping): one compiled program for the
# three of them (their stages differ in values only, the speeds are arrays)
UNBALANCE_RUN = jp.PlanetaryRun(jnp.asarray(TORQUE), steps_per_period=16, periods=8 * 30,
                                keep_periods=8, damping_ratio=0.05)


def _unbalance_run(st, meshes, carrier_speed, mesh_speed):
    """planetary_dynamics of the unbalance tests at the carrier speed (rad/s) and the mesh
    travel speed (m/s) given."""
    r = jp.planetary_dynamics(jp.PlanarPlanetary(), st, meshes, UNBALANCE_RUN,
                              jnp.asarray(carrier_speed, float), jnp.asarray(mesh_speed, float))
    assert int(r.result) == 0
    return r


def test_sun_unbalance_far_from_resonance_is_the_static_deflection():
    """Ring held, carrier at Omega: the sun spins at omega_s = Omega (1 + r_br / r_bs) and its
    unbalance U whirls it forward at omega_s - Omega in the carrier frame. Far below the sun's
    translational modes the whirl radius is the static U omega_s^2 / k, k = k_b + (N/2) k_sp
    k_rp / (k_sp + k_rp): the sun bearing and the N planet paths (the sun's translation
    projected on the N lines of action, sum n n^T = N/2 I) (within 1 %); in phase with the
    unbalance; and the spectrum of x_s + i y_s has its line at order +1 of the sun's turn
    relative to the carrier."""
    n, k_b, U, beta = 4, 1e8, 2e-5, 0.3
    # a planet unbalance array of zeros: the stage of the next tests (one compiled run)
    st = stage(n, unb=jp.Unbalances(sun=U, sun_phase=beta, planet=np.zeros(n)),
               sun_bearing=k_b)
    omega = 250.0
    w_s = omega * (1 + R_R / R_S)
    k = k_b + n / 2 * K_MESH / 2
    assert w_s / math.sqrt(k / 0.4) < 0.04  # far below the sun's translation on k
    meshes = jp.ConstantMeshes(base_pitch=2 * np.pi * R_S / 8)  # 8 periods per sun turn
    r = _unbalance_run(st, meshes, omega, R_R * omega)  # the ring held: v = r_br Omega
    turn = beta + np.asarray(r.travel) / R_S
    c, spectrum = _whirl(r, (6, 7), turn)
    static = U * w_s**2 / k
    assert abs(c) == pytest.approx(static, rel=1e-2)
    assert abs(np.angle(c)) < 0.02  # below resonance: in phase
    assert np.argmax(spectrum) == 1 and spectrum[-1] < 1e-3 * spectrum[1]


def test_planet_unbalance_whirls_backwards_at_the_planet_order():
    """A planet turns -x / r_bp relative to the carrier: its unbalance's force, and its
    response on (zeta, eta), has its largest line at order -1 of the planet's turn (the last FFT
    bin); the +1 line is the ellipse of the planet's unequal radial and tangential support (pin
    in series with the carrier's translation, or with its torsion), smaller; the other planets,
    not loaded by it, respond less."""
    n = 4
    st = stage(n, unb=jp.Unbalances(planet=np.array([2e-5, 0, 0, 0])))
    meshes = jp.ConstantMeshes(base_pitch=2 * np.pi * R_P / 8)
    r = _unbalance_run(st, meshes, 250.0, R_R * 250.0)
    turn = -np.asarray(r.travel) / R_P
    c1, s1 = _whirl(r, (9, 10), turn)
    c2, _ = _whirl(r, (12, 13), turn)
    assert np.argmax(s1) == s1.size - 1 and s1[1] < 0.5 * s1[-1]
    assert np.sort(s1)[-3] < 1e-3 * s1[-1]  # no other order
    assert abs(c2) < abs(c1)


def test_sun_unbalance_at_a_translational_mode_against_the_single_mode_estimate():
    """Carrier fixed (no Coriolis term: the carrier frame is inertial), the sun spun at the
    frequency of its translational pair (omega_n, from the stage's M and K, checked against Lin
    & Parker in tests/test_planetary.py): the whirl radius against the single-mode estimate
    U omega^2 |sum_pair phi phi^T e| / (2 zeta omega_n^2) (the modal damping of the run,
    zeta on every mode), within 5 % (the other modes' share), and against the sum over every
    mode within 1 % (the Newmark period error and the start's transient). The unbalance is
    small enough for every mesh to stay loaded."""
    n, k_b, U, zeta = 4, 1e8, 2e-7, 0.05
    st = stage(n, unb=jp.Unbalances(sun=U, planet=np.zeros(n)), sun_bearing=k_b)
    model = jp.PlanarPlanetary()
    M = np.asarray(model.mass_matrix(st))
    K = np.asarray(model.stiffness_matrix(st))
    w2, phi = scipy.linalg.eigh(K, M)
    w = np.sqrt(np.abs(w2))
    share = phi[6] ** 2 + phi[7] ** 2  # the sun's translation in each mode
    i = int(np.argmax(share))
    pair = np.flatnonzero(np.abs(w - w[i]) < 1e-6 * w[i])
    assert pair.size == 2
    wn = w[i]
    # the sun's forward whirl for a unit rotating force (e_x - i e_y) phasor on the sun
    f = np.zeros(M.shape[0], complex)
    f[6], f[7] = 1.0, -1.0j
    def response(modes):
        X = sum(phi[:, m] * (phi[:, m] @ f) / (w[m] ** 2 - wn**2 + 2j * zeta * w[m] * wn)
                for m in modes)
        return (X[6] + 1j * X[7]) / 2 * U * wn**2  # the forward coefficient
    single, every = response(pair), response(range(len(w)))
    # the carrier fixed, the sun spun at wn: v = r_bs wn; 8 mesh periods per sun turn
    meshes = jp.ConstantMeshes(base_pitch=2 * np.pi * R_S / 8)
    assert zeta == float(UNBALANCE_RUN.damping_ratio)
    r = _unbalance_run(st, meshes, 0.0, R_S * wn)
    c, spectrum = _whirl(r, (6, 7), np.asarray(r.travel) / R_S)
    assert abs(c) == pytest.approx(abs(every), rel=1e-2)
    assert abs(c) == pytest.approx(abs(single), rel=5e-2)
    assert np.argmax(spectrum) == 1


def _lin_parker(**planetary):
    d = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    d["planetary"].update(planetary)
    return d


def test_case_keys_map_to_the_objects_and_bad_values_are_one_line():
    case = jio.parse_train(_lin_parker(
        planet_runout_um=[12.0, 0.0, 0.0], planet_runout_phase_deg=[90.0, 0.0, 0.0],
        sun_unbalance_g_mm=50.0, sun_unbalance_phase_deg=-30.0, carrier_unbalance_g_mm=7.0,
        planet_unbalance_g_mm=[0.0, 3.0, 0.0]))
    st = case.form.spec.stage(case)
    np.testing.assert_allclose(st.eccentricities.planet, [12e-6, 0, 0])
    np.testing.assert_allclose(st.eccentricities.planet_phase, [math.pi / 2, 0, 0])
    u = st.unbalances
    assert float(u.sun) == pytest.approx(50e-6) and float(u.carrier) == pytest.approx(7e-6)
    assert float(u.sun_phase) == pytest.approx(math.radians(-30.0))
    np.testing.assert_allclose(u.planet, [0, 3e-6, 0])
    assert case.form.spec.eccentric and case.form.spec.unbalanced
    # summary.json echoes them in SI units: the planets' runout beside the central members'
    # eccentricities, the unbalances in kg m
    spec = case.form.spec
    ecc = pr.sharing_summary(spec, st, spec.torques(case.torque),
                             {"torsional": jp.TorsionalPlanetary()})["eccentricities"]
    np.testing.assert_allclose(ecc["planet_m"], [12e-6, 0, 0])
    np.testing.assert_allclose(ecc["planet_phase_rad"], [math.pi / 2, 0, 0])
    echo = pr.unbalance_summary(spec)
    assert echo["sun_kg_m"] == pytest.approx(50e-6) and echo["carrier_kg_m"] == pytest.approx(7e-6)
    assert echo["sun_phase_rad"] == pytest.approx(math.radians(-30.0))
    np.testing.assert_allclose(echo["planet_kg_m"], [0, 3e-6, 0])
    plain = jio.parse_train(_lin_parker())
    assert plain.form.spec.stage(plain).unbalances is None and not plain.form.spec.eccentric
    for keys, words in (
        ({"planet_runout_um": [1.0, 2.0]}, "planet_runout_um = [1, 2]: must be an array of 3"),
        ({"planet_runout_um": [1.0, 2.0, -1.0]}, "element -1 out of range, allowed [0, 10000]"),
        ({"planet_runout_phase_deg": [1.0, 0.0, 0.0]}, "given without planet_runout_um"),
        ({"sun_unbalance_g_mm": -1.0}, "sun_unbalance_g_mm = -1: out of range"),
        ({"ring_unbalance_phase_deg": 5.0}, "given without ring_unbalance_g_mm"),
        ({"planet_unbalance_g_mm": [1.0]}, "planet_unbalance_g_mm = [1]: must be an array"),
    ):
        with pytest.raises(ValueError, match=None) as err:
            jio.parse_train(_lin_parker(**keys))
        msg = str(err.value)
        assert "\n" not in msg and words in msg and msg.startswith("[planetary]")


def test_api_refusals():
    with pytest.raises(ValueError, match="Eccentricities: planet must have shape"):
        stage(4, jp.Eccentricities(planet=np.zeros(3)))
    with pytest.raises(ValueError, match=r"Unbalances: planet\[0\] = -1 kg m is out of range"):
        jp.Unbalances(planet=np.array([-1.0, 0, 0]))


@pytest.mark.slow
def test_unbalance_with_the_modal_ring_equals_the_station_model():
    """The unbalance's load in newmark_modal (on the modes by D^T, on the static correction by
    G) against the station model's coordinate solve (another formulation and solver of the same
    equations): the embedded seq-test-ring with every mode (m = 2Z = 106), a sun and a planet
    unbalance, 60 rad/s: the mesh forces and the coordinates to 1e-9 of the largest (forces
    measured 9e-12); the unbalance moves the sun (x_s, y_s) against the run without it, by at least half the
    rigid-support static estimate."""
    import equinox as eqx
    from _planetary_stage import SEQ, geometry, stage as gear_stage

    import fem_prep as fp

    geo = geometry(**SEQ)
    st = eqx.tree_at(lambda s: s.unbalances, gear_stage(geo, 3, pin=3e8, sun_bearing=1e8),
                     jp.Unbalances(sun=1e-4, planet=np.array([1e-5, 0, 0])),
                     is_leaf=lambda x: x is None)
    rings = fp.ring_stations(fp.load_ring_body("seq-test-ring"))
    F, M = np.asarray(rings.compliance), np.asarray(rings.mass)
    run = jp.PlanetaryRun(1000.0, steps_per_period=12, periods=6, keep_periods=2)
    meshes = jp.ConstantMeshes(base_pitch=geo.planet_ring.base_pitch)
    modal = jp.planetary_dynamics(jp.PlanarPlanetary(), st, meshes, run, 60.0,
                                  ring=jp.CondensedRing(F, M, modes=106))
    station = jp.planetary_dynamics(jp.PlanarPlanetary(), st, meshes, run, 60.0,
                                    ring=jp.CondensedRing(F, M))
    assert int(modal.result) == 0 and int(station.result) == 0
    want = np.asarray(station.sun_mesh_forces)
    np.testing.assert_allclose(modal.sun_mesh_forces, want, rtol=0,
                               atol=1e-9 * np.max(np.abs(want)))
    # the unbalance shows: the forces differ from the run without it
    plain = jp.planetary_dynamics(jp.PlanarPlanetary(), eqx.tree_at(
        lambda s: s.unbalances, st, None), meshes, run, 60.0, ring=jp.CondensedRing(F, M))
    X, X0 = np.asarray(station.displacement), np.asarray(plain.displacement)
    np.testing.assert_allclose(modal.displacement, X, rtol=0, atol=1e-9 * np.max(np.abs(X)))
    # the sun's whirl is at least of the order of U w_s^2 / (k_b + (N/2) k k / 2k), softer with
    # the flexible ring and pins (rigid-support estimate written here)
    w_s = 60.0 * (1 + float(st.ring.base_radius / st.sun.base_radius))
    rigid = 1e-4 * w_s**2 / (1e8 + 1.5 * 5e8 / 2)
    assert np.max(np.abs(X[:, 6:8] - X0[:, 6:8])) > 0.5 * rigid
