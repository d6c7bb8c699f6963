"""Planetary dynamics in the carrier frame (jaxgear.planetary.planetary_dynamics): against a
reference written here from scratch (Kahraman's torsional equations with the ring and carrier
rigidly held, the meshes' stiffness k0 b n(t) from the contact lines counted here, integrated by
scipy's DOP853 segment by segment between the instants a line enters or leaves), per-mesh DF
within 1 % at three speeds, one near a resonance; the zero-speed limit; the speed sweep; the
phasing's cancellation of the net mesh force at the mesh order; the ring transducer's
sidebands."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import eigh

import jaxgear as jg
import jaxgear.planetary as jp
from _planetary_stage import K0, SEQ, WIDTH, counted_stiffness, geometry, stage

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0
ZETA = 0.05


@pytest.fixture(scope="module")
def seq():
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    return geo, st, meshes


def reference(geo, st, meshes, mesh_speed, periods, keep):
    """Kahraman's torsional model, ring and carrier rigid (u_r = u_c = 0): coordinates
    (u_s, u_1..u_N), u = r_b theta; delta_sn = u_s + u_n, delta_rn = -u_n; the mesh stiffness
    k0 b n(t) with n the lines counted at the travel x = v t; modal damping ZETA on the modes of
    the mean stiffness (eps_alpha lines on average); DOP853 between the switching instants."""
    n = st.n_planets
    r_s, r_p = geo.sun_planet.base_radii
    m = np.diag([float(st.sun.polar_inertia) / r_s**2]
                + [float(st.planet.polar_inertia) / r_p**2] * n)
    v_s = np.zeros((n, n + 1))
    v_s[:, 0] = 1.0
    v_s[np.arange(n), 1 + np.arange(n)] = 1.0
    v_r = np.zeros((n, n + 1))
    v_r[np.arange(n), 1 + np.arange(n)] = -1.0
    f = np.zeros(n + 1)
    f[0] = TORQUE / r_s

    def stiffness(x):
        k_s, k_r = counted_stiffness(geo, meshes, x)
        return v_s.T @ (k_s[:, None] * v_s) + v_r.T @ (k_r[:, None] * v_r), k_s, k_r

    eps_s = geo.sun_planet.transverse_contact_ratio
    eps_r = geo.planet_ring.transverse_contact_ratio
    k_mean = K0 * WIDTH * (eps_s * v_s.T @ v_s + eps_r * v_r.T @ v_r)
    lam, phi = eigh(k_mean, m)
    c = m @ phi @ np.diag(2 * ZETA * np.sqrt(lam)) @ phi.T @ m
    p_b = geo.sun_planet.base_pitch
    # the instants a contact line crosses s = 0 or s = g_alpha on any mesh
    t_end = periods * p_b / mesh_speed
    shifts = np.concatenate([-np.asarray(meshes.sun_phases) * p_b,
                             float(meshes.ring_offset) - np.asarray(meshes.ring_phases) * p_b])
    ends = [0.0] * n + [0.0] * n
    g = [geo.sun_planet.path_of_contact] * n + [geo.planet_ring.path_of_contact] * n
    cuts = {0.0, t_end}
    for sh, g_a, _ in zip(shifts, g, ends, strict=True):
        for edge in (0.0, g_a):
            for i in range(-periods - 5, periods + 5):
                t = (edge - sh + i * p_b) / mesh_speed
                if 0.0 < t < t_end:
                    cuts.add(t)
    cuts = np.array(sorted(cuts))
    k0, _, _ = stiffness(0.0)
    y = np.concatenate([np.linalg.solve(k0, f), np.zeros(n + 1)])
    t_keep = t_end - keep * p_b / mesh_speed
    samples = np.linspace(t_keep, t_end, 384 * keep + 1)
    out_t, out_f = [], []
    for a, b in zip(cuts[:-1], cuts[1:], strict=True):
        k, k_s, k_r = stiffness(mesh_speed * 0.5 * (a + b))
        rhs_m = np.linalg.inv(m)

        def rhs(t, z, k=k):
            q, qd = z[: n + 1], z[n + 1 :]
            return np.concatenate([qd, rhs_m @ (f - c @ qd - k @ q)])

        inside = samples[(samples >= a) & (samples < b)]
        if b > t_keep:  # the kept window: dense sampling plus the segment's ends
            inside = np.unique(np.concatenate([[a], inside, [b]]))
        sol = solve_ivp(rhs, (a, b), y, method="DOP853", rtol=1e-11, atol=1e-16,
                        t_eval=inside if b > t_keep else None)
        y = sol.y[:, -1]
        if b > t_keep:
            q = sol.y[: n + 1]
            out_t.append(sol.t)
            out_f.append(np.concatenate([k_s[:, None] * (v_s @ q), k_r[:, None] * (v_r @ q)]))
    forces = np.concatenate(out_f, axis=1)
    nominal = TORQUE / (n * r_s)
    return forces.max(axis=1) / nominal, forces, np.sqrt(lam) / (2 * np.pi)


STEPS = 384  # per mesh period: the stiffness jumps as lines enter make Newmark first order in dt
PERIODS, KEEP = 24, 3


def _speed(st, meshes, freq):
    """The carrier speed (rad/s) whose mesh frequency is ``freq`` (Hz), the ring held."""
    return freq * float(meshes.mesh_period()) / float(st.ring.base_radius)


def _check_against_reference(geo, st, meshes, got, omega):
    want, forces, _ = reference(geo, st, meshes, omega * float(st.ring.base_radius), PERIODS,
                                KEEP)
    assert forces.min() > 0  # every mesh in contact: the reference holds
    df = np.concatenate([np.asarray(d) for d in got.dynamic_factors])
    np.testing.assert_allclose(df, want, rtol=0.01)  # measured 0.11 %, 0.12 %, 0.20 %
    return df


# default tier: tests/test_planetary_dynamics.py::test_planar_dynamics_at_speed_against_a_rotating_frame_reference (planetary_dynamics at speed against a DOP853 reference, planar)
@pytest.mark.slow
def test_torsional_dynamics_near_a_resonance_against_the_reference(seq):
    """Fast twin of the sweep below: one speed, the mesh frequency at 0.9 of the first mode."""
    geo, st, meshes = seq
    _, _, freqs = reference(geo, st, meshes, 1.0, 1, 1)
    run = jp.PlanetaryRun(TORQUE, steps_per_period=STEPS, periods=PERIODS, keep_periods=KEEP,
                          damping_ratio=ZETA)
    omega = _speed(st, meshes, 0.9 * freqs[0])
    got = jp.planetary_dynamics(jp.TorsionalPlanetary(), st, meshes, run, jnp.asarray(omega))
    assert int(got.result) == 0
    df = _check_against_reference(geo, st, meshes, got, omega)
    assert df.max() > 2.4  # amplified near the resonance (DF 2.58 in the reference)


@pytest.mark.slow
def test_torsional_speed_sweep_against_the_reference(seq):
    """Mesh frequencies 0.5, 0.9 and 1.6 times the first mode's, vmapped in one sweep."""
    geo, st, meshes = seq
    _, _, freqs = reference(geo, st, meshes, 1.0, 1, 1)
    run = jp.PlanetaryRun(TORQUE, steps_per_period=STEPS, periods=PERIODS, keep_periods=KEEP,
                          damping_ratio=ZETA)
    speeds = jnp.array([_speed(st, meshes, r * freqs[0]) for r in (0.5, 0.9, 1.6)])
    got = jp.planetary_speed_sweep(jp.TorsionalPlanetary(), st, meshes, run, speeds)
    assert np.all(np.asarray(got.result) == 0)
    for i, omega in enumerate(np.asarray(speeds)):
        one = jax.tree.map(lambda a, i=i: a[i], got)
        _check_against_reference(geo, st, meshes, one, omega)


# default tier: tests/test_planetary_model.py::test_simulate_at_a_very_low_speed_is_the_quasi_static_solve (same claim, torsional, at 1e-3 of the nominal force)
@pytest.mark.slow
def test_zero_speed_limit_torsional(seq):
    """Fast twin of the planar test below (the resonance test's compiled run): at 1e-7 rad/s
    the recorded forces are the quasi-static ones at the same travels, to 1e-8 (the difference
    falls as (S Omega)^2: the inertia of Newmark's steps)."""
    geo, st, meshes = seq
    run = jp.PlanetaryRun(TORQUE, steps_per_period=STEPS, periods=PERIODS, keep_periods=KEEP,
                          damping_ratio=0.0)
    model = jp.TorsionalPlanetary()
    # a float64 speed, as the resonance test's: the same compiled run; the quasi-static solve at
    # 48 travels, as the transducer test's and tests/test_planetary_model.py's (one program)
    got = jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(np.float64(1e-7)))
    static = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), got.travel[::24],
                                       np.zeros(3))
    np.testing.assert_allclose(got.sun_mesh_forces[::24], static.sun_mesh_forces, rtol=1e-8)
    np.testing.assert_allclose(got.ring_mesh_forces[::24], static.ring_mesh_forces, rtol=1e-8)


@pytest.mark.slow
def test_zero_speed_limit_is_the_quasi_static_solution(seq):
    """At a carrier speed of 1e-6 rad/s the recorded forces are the quasi-static ones at the
    same mesh travels (planar model, a pin error, damped), to 1e-8 (measured 2e-9: after a jump
    of the stiffness average acceleration leaves the stiff modes alternating, undamped at
    dt >> their period; at 1e-4 rad/s 2e-7)."""
    geo, st, meshes = seq
    errors = np.array([10e-6, 0.0, 0.0])
    run = jp.PlanetaryRun(TORQUE, steps_per_period=32, periods=3, keep_periods=1,
                          damping_ratio=ZETA, tangential_pin_errors=errors)
    model = jp.PlanarPlanetary()
    got = jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(1e-6))
    assert int(got.result) == 0
    static = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), got.travel, errors)
    np.testing.assert_allclose(got.sun_mesh_forces, static.sun_mesh_forces, rtol=1e-8)
    np.testing.assert_allclose(got.ring_mesh_forces, static.ring_mesh_forces, rtol=1e-8)
    # the dynamic K_γ (peak-based) of the quasi-static forces: each planet's peak over the mean
    peaks = np.asarray(static.sun_mesh_forces).max(axis=0)
    assert float(got.k_gamma) == pytest.approx(peaks.max() / peaks.mean(), rel=1e-8)


def _harmonics(signal, harmonics):
    """Complex amplitudes of mesh harmonics 1..harmonics of a signal sampled over one period."""
    return np.fft.rfft(signal, axis=0)[1 : harmonics + 1] / signal.shape[0]


@pytest.mark.parametrize(
    "params, n",
    [(SEQ, 3), (dict(z_s=20, z_p=16, x_s=0.2, x_p=0.2), 4),
     (dict(z_s=18, z_p=16, x_s=0.2, x_p=0.2), 4)],
)
def test_net_mesh_excitation_cancellation_follows_the_phasing_rule(params, n):
    """The sun meshes' stiffness k_sn(x) from the contact cells over a mesh period
    (``planetary_mesh_stiffness``: the excitation the rule is about, a planet's mesh force
    under a constant deflection) summed on the sun along the lines of action and as a torque:
    at each mesh harmonic l = 1..4 the net force and the net torque vanish (relative to N times
    one mesh's harmonic, < 1e-9) exactly where ``phasing_excites`` says, and survive elsewhere
    (force > 0.5, torque > 0.99): 19/3 sequential (l z_s mod 3 = 1 or 2: force only; l = 3:
    torque only), 20/4 in phase (torque only), 18/4 sequential (l = 1, 3: mod 4 = 2, neither;
    l = 2, 4: torque only). The lines counted by hand give the same k_sn (to 1e-12)."""
    geo = geometry(**params)
    st = stage(geo, n)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    per = 48
    x = np.asarray(meshes.positions(per))
    k_s, k_r = jp.planetary_mesh_stiffness(jp.TorsionalPlanetary(), st, meshes, x)
    f = np.asarray(k_s)  # (per, n)
    for i, xi in enumerate(x):
        want_s, want_r = counted_stiffness(geo, meshes, xi)
        np.testing.assert_allclose(f[i], want_s, rtol=1e-12)
        np.testing.assert_allclose(k_r[i], want_r, rtol=1e-12)
    psi = np.asarray(st.planet_angles) - geo.sun_pressure_angle  # psi_sn
    # the force of mesh n on the sun: -F (-sin psi_sn, cos psi_sn); its torque -r_bs F
    fx, fy = f @ np.sin(psi), -(f @ np.cos(psi))
    torque = f.sum(1)
    one = np.abs(_harmonics(f[:, 0], 4))
    force = np.hypot(np.abs(_harmonics(fx, 4)), np.abs(_harmonics(fy, 4))) / (n * one)
    torq = np.abs(_harmonics(torque, 4)) / (n * one)
    assert one.min() > 1e-3 * f.mean()  # every harmonic present in one mesh
    for ell in range(1, 5):
        kind = jp.phasing_excites(params["z_s"], n, ell)
        force_on = kind is jp.ModeType.TRANSLATIONAL
        torque_on = kind is jp.ModeType.ROTATIONAL
        assert (force[ell - 1] > 0.5) if force_on else (force[ell - 1] < 1e-9), (ell, kind)
        assert (torq[ell - 1] > 0.99) if torque_on else (torq[ell - 1] < 1e-9), (ell, kind)


def test_ring_transducer_sidebands_at_multiples_of_the_planet_count(seq):
    """A transducer on the ring sees the planets' ring-mesh forces through a planet-pass window;
    over one carrier turn (z_r = 53 mesh periods, the ring held) its spectrum has lines only at
    orders that are multiples of N = 3 (McFadden & Smith 1985: the sidebands m z_r + j with
    m z_r + j = k N): the mesh order 53 itself is absent, the lines at 51 and 54 are there."""
    geo, st, meshes = seq
    per, z_r = 48, 53  # 48 travels: the zero-speed test's quasi-static program
    x = meshes.positions(per)
    res = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, meshes, np.asarray(TORQUE), x,
                                    np.zeros(3))
    forces = np.tile(np.asarray(res.ring_mesh_forces), (z_r, 1))  # one carrier turn
    theta_c = 2 * np.pi * (np.arange(per * z_r) + 0.5) / (per * z_r)
    y = jp.ring_transducer_signal(jnp.asarray(forces), jnp.asarray(theta_c), st.planet_angles)
    orders, amp = jp.order_spectrum(y, per * z_r)
    k = np.rint(orders).astype(int)
    assert np.allclose(orders, k)
    off = amp[(k % 3 != 0)]
    assert off.max() < 1e-9 * amp.max()
    assert amp[53] < 1e-9 * amp.max() and amp[51] > 1e-3 * amp.max()
    assert amp[54] > 1e-3 * amp.max()
    # a planet-pass window of one planet alone (no phasing) puts a line at the mesh order
    single = jp.ring_transducer_signal(jnp.asarray(forces[:, :1]), jnp.asarray(theta_c),
                                       st.planet_angles[:1])
    _, amp1 = jp.order_spectrum(single, per * z_r)
    assert amp1[53] > 1e-2 * amp1.max()


def test_planar_dynamics_at_speed_against_a_rotating_frame_reference():
    """The planar model at a carrier speed of 1500 rad/s (mesh frequency 12.7 kHz), every member
    on its bearings (a soft sun bearing, 1e7 N/m): against Lin & Parker's planar matrices
    assembled independently (tests/test_planetary.py's ``reference_planar``), each mass's
    rotating-frame terms written here (m (x'' - 2 Omega y' - Omega^2 x),
    m (y'' + 2 Omega x' - Omega^2 y)), the meshes' stiffness k0 b n(t) from the counted lines,
    the same modal damping, DOP853 between the switching instants, from the same start over the
    same 24 periods (the soft sun's mode, ~460 Hz, has not died out: both carry the same
    transient): per-mesh DF within 1 % (measured 0.08 %), where leaving the rotating-frame terms
    out of the reference moves it by more than 3 % (measured 5.7 %)."""
    from test_planetary import reference_planar

    geo = geometry(**SEQ)
    member = jp.PlanetaryMember
    sp, pr = geo.sun_planet, geo.planet_ring
    r_s, r_p = sp.base_radii
    r_r, a = pr.base_radii[1], geo.center_distance
    soft = 1e9
    st = jp.PlanetaryStage.equally_spaced(
        3,
        sun=member(1.2, 0.4 * 1.2 * r_s**2, r_s, 1e7, 0.0),
        ring=member(6.0, 6.0 * r_r**2, r_r, soft, soft * r_r**2),
        carrier=member(5.0, 0.5 * 5.0 * a**2, a, soft, soft * a**2),
        planet=member(0.8, 0.5 * 0.8 * r_p**2, r_p, 5e8, 0.0),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=5e8,
        ring_mesh_stiffness=5e8,
    )
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    omega = 1500.0
    n, size = 3, 18
    psi = np.asarray(st.planet_angles)
    masses = [5.0, 6.0, 1.2, 0.8]
    inertias = [float(m.polar_inertia) for m in (st.carrier, st.ring, st.sun, st.planet)]
    radii = [a, r_r, r_s, r_p]
    bearings = [(soft, soft), (soft, soft), (1e7, 1e7)]
    torsion = [soft, soft, 0.0, 0.0]  # on u = r theta
    a_s, a_r = geo.sun_pressure_angle, geo.ring_pressure_angle
    m_ref, k_b = reference_planar(masses, inertias, radii, bearings, torsion, psi, a_s, a_r,
                                  np.zeros(n), np.zeros(n), (5e8, 5e8))
    unit = np.ones(n)
    _, k_unit_s = reference_planar(masses, inertias, radii, [(0, 0)] * 3, [0] * 4, psi, a_s,
                                   a_r, unit, 0 * unit, (0.0, 0.0))
    # each mesh's deflection row, from the sum of unit springs one at a time
    rows = []
    for which in range(2 * n):
        k_s1 = np.eye(n)[which] if which < n else 0 * unit
        k_r1 = np.eye(n)[which - n] if which >= n else 0 * unit
        _, k1 = reference_planar(masses, inertias, radii, [(0, 0)] * 3, [0] * 4, psi, a_s, a_r,
                                 k_s1, k_r1, (0.0, 0.0))
        row = k1[:, np.argmax(np.abs(np.diag(k1)))] / np.sqrt(np.abs(k1).max())
        rows.append(row / row[np.argmax(np.abs(row))] * np.sqrt(np.diag(k1).max()))
    v = np.array(rows)
    # fix each row's sign: the sun (ring) rotation enters +1
    for j in range(2 * n):
        i = 8 if j < n else 5
        v[j] *= np.sign(v[j, i])
        np.testing.assert_allclose(np.outer(v[j], v[j]), reference_planar(
            masses, inertias, radii, [(0, 0)] * 3, [0] * 4, psi, a_s, a_r,
            np.eye(n)[j] if j < n else 0 * unit, np.eye(n)[j - n] if j >= n else 0 * unit,
            (0.0, 0.0))[1], atol=1e-12)
    g = np.zeros((size, size))
    kc = np.zeros((size, size))
    for b in range(size // 3):
        mb = m_ref[3 * b, 3 * b]
        g[3 * b, 3 * b + 1], g[3 * b + 1, 3 * b] = -2 * mb, 2 * mb
        kc[3 * b, 3 * b] = kc[3 * b + 1, 3 * b + 1] = mb
    f = np.zeros(size)
    f[8] = TORQUE / r_s
    p_b = sp.base_pitch
    speed = r_r * omega
    shifts = np.concatenate([-np.asarray(meshes.sun_phases) * p_b,
                             float(meshes.ring_offset) - np.asarray(meshes.ring_phases) * p_b])
    g_a = [sp.path_of_contact] * n + [pr.path_of_contact] * n
    x0 = 0.5 * p_b / STEPS  # the library's first travel

    def kmesh(x):
        k_s, k_r = counted_stiffness(geo, meshes, x)
        k = np.concatenate([k_s, k_r])
        return v.T @ (k[:, None] * v), k, v

    eps = [sp.transverse_contact_ratio] * n + [pr.transverse_contact_ratio] * n
    k_mean = v.T @ ((K0 * WIDTH * np.array(eps))[:, None] * v)
    lam, phi = eigh(k_b + k_mean, m_ref)
    c = m_ref @ phi @ np.diag(2 * ZETA * np.sqrt(np.clip(lam, 0, None))) @ phi.T @ m_ref
    t_end = PERIODS * p_b / speed
    cuts = {0.0, t_end}
    for sh, ga in zip(shifts, g_a, strict=True):
        for edge in (0.0, ga):
            for i in range(-PERIODS - 5, PERIODS + 5):
                t = (edge - sh + i * p_b - x0) / speed
                if 0.0 < t < t_end:
                    cuts.add(t)
    cuts = np.array(sorted(cuts))
    def integrate(spin):
        return _integrate(k_b - spin**2 * kc, c + spin * g, m_ref, f, kmesh, x0, speed, cuts,
                          t_end - KEEP * p_b / speed, size, n)

    want = integrate(omega) / (TORQUE / (n * r_s))
    still = integrate(0.0) / (TORQUE / (n * r_s))
    assert np.abs(still / want - 1).max() > 0.03  # the rotating-frame terms matter here
    run = jp.PlanetaryRun(TORQUE, steps_per_period=STEPS, periods=PERIODS, keep_periods=KEEP,
                          damping_ratio=ZETA)
    got = jp.planetary_dynamics(jp.PlanarPlanetary(), st, meshes, run, jnp.asarray(omega))
    assert int(got.result) == 0 and float(got.sun_mesh_forces.min()) > 0
    df = np.concatenate([np.asarray(d) for d in got.dynamic_factors])
    np.testing.assert_allclose(df, want, rtol=0.01)


def _integrate(k_eff, c_eff, m, f, kmesh, x0, speed, cuts, t_keep, size, n):
    """M q'' + c_eff q' + (k_eff + K_mesh(x)) q = f from the static state at x0, DOP853 on each
    segment between switching instants; the largest force of each mesh over t > t_keep."""
    k0m, _, _ = kmesh(x0)
    y = np.concatenate([np.linalg.solve(k_eff + k0m, f), np.zeros(size)])
    minv = np.linalg.inv(m)
    peaks = np.zeros(2 * n)
    for lo, hi in zip(cuts[:-1], cuts[1:], strict=True):
        km, k, v = kmesh(x0 + speed * 0.5 * (lo + hi))
        a_mat = np.block([[np.zeros((size, size)), np.eye(size)],
                          [-minv @ (k_eff + km), -minv @ c_eff]])
        b_vec = np.concatenate([np.zeros(size), minv @ f])
        sol = solve_ivp(lambda t, z, a_mat=a_mat, b_vec=b_vec: a_mat @ z + b_vec, (lo, hi), y,
                        method="DOP853", rtol=1e-10, atol=1e-15,
                        t_eval=np.linspace(lo, hi, 24) if hi > t_keep else None)
        y = sol.y[:, -1]
        if hi > t_keep:
            peaks = np.maximum(peaks, (k[:, None] * (v @ sol.y[:size])).max(axis=1))
    return peaks


# default tier: tests/test_planetary_dynamics.py::test_dynamic_load_sharing_of_a_synthetic_force_history (the engagement jump's K_γ, analytic) and ::test_dynamic_k_gamma_constant_meshes_pin_error_is_the_quasi_static
@pytest.mark.slow
def test_quasi_static_speed_resolved_engagement_jump_floating_sun():
    """The diagnostic on a floating sun (planar model, no sun bearing, a 10 µm pin
    error) at a mesh frequency of 40 Hz, far below the stage's mesh modes (2.9 to 12 kHz), the
    step resolving them (dt f = 12 kHz / (40 Hz x 9000) = 1/30). Constant meshes: the dynamic
    K_γ is 1 (a floating sun between equally spaced planets balances only equal mesh forces, so
    the pin error cannot unload a planet; the sun's centripetal load m_s Ω² e is 2e-8 of the
    mesh force here), to 1e-6. Contact meshes (one or two lines of uniform stiffness: k steps by
    r = 2 as a line enters): each planet's time-mean sun-mesh force is the quasi-static solve's
    at the same travels (1e-6 of the nominal force: no 2 : 1 : 1 split), the largest force over
    the nominal is r (the deflection is continuous across an instantaneous stiffness step, so
    the entering line takes its share at once and the mesh force jumps by k_after / k_before:
    measured 1.998, within 1 %), and the per-instant ratio max_t max_j F_j / mean_j F_j (computed
    here from the forces) is 3 r / (r + 2) = 1.5 (the other two planets at their nominal force at
    that instant; measured 1.502, within 1 %): it counts the dynamic factor twice. The reported
    dynamic K_γ is peak-based (each planet's peak over the mean planet's: every planet peaks
    alike at r), 1 to 1e-3, and the mean-load K_γ is the quasi-static solve's time-mean shares'
    (1e-6)."""
    geo = geometry(**SEQ)
    st = stage(geo, 3, sun_bearing=0.0)
    errors = np.array([10e-6, 0.0, 0.0])
    model = jp.PlanarPlanetary()
    contact = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    k_s, _ = jp.planetary_mesh_stiffness(model, st, contact, contact.positions(960))
    k1 = np.asarray(k_s)[:, 0]
    r = float(np.max(np.roll(k1, -1) / k1))
    assert r == pytest.approx(2.0, rel=1e-9)  # one line to two of the same stiffness
    run = jp.PlanetaryRun(TORQUE, steps_per_period=9000, periods=3, keep_periods=2,
                          damping_ratio=ZETA, tangential_pin_errors=errors)
    omega = jnp.asarray(_speed(st, contact, 40.0))
    fs = TORQUE / (3 * float(st.sun.base_radius))
    # the constant meshes' forces hardly vary in time: 48 steps per period, the run of
    # test_dynamic_k_gamma_constant_meshes_pin_error_is_the_quasi_static (one compiled program)
    slow = jp.PlanetaryRun(TORQUE, steps_per_period=48, periods=3, keep_periods=2,
                           damping_ratio=ZETA, tangential_pin_errors=errors)
    const = jp.planetary_dynamics(model, st, jp.ConstantMeshes(contact.mesh_period()), slow,
                                  omega)
    assert float(const.k_gamma) == pytest.approx(1.0, abs=1e-6)
    got = jp.planetary_dynamics(model, st, contact, run, omega)
    assert int(got.result) == 0
    f = np.asarray(got.sun_mesh_forces)
    static = jp.planetary_quasi_static(model, st, contact, np.asarray(TORQUE), got.travel,
                                       errors)
    fq = np.asarray(static.sun_mesh_forces)
    np.testing.assert_allclose(f.mean(axis=0), fq.mean(axis=0), atol=1e-6 * fs)
    assert fq.max() / fs == pytest.approx(1.0, abs=1e-6)  # quasi-statically no peak
    assert f.max() / fs == pytest.approx(r, rel=0.01)
    per_instant = float(np.max(f.max(axis=1) / f.mean(axis=1)))
    assert per_instant == pytest.approx(3 * r / (r + 2), rel=0.01)
    assert float(got.k_gamma) == pytest.approx(1.0, abs=1e-3)
    qm = fq.mean(axis=0)
    assert float(got.k_gamma_mean_load) == pytest.approx(qm.max() / qm.mean(), abs=1e-6)
    assert float(const.k_gamma_mean_load) == pytest.approx(1.0, abs=1e-6)


def test_dynamic_load_sharing_of_a_synthetic_force_history():
    """jaxgear.planetary.dynamic_load_sharing against analytic values. Three paths over one
    period, each a mean M_j plus a cosine of amplitude A_j at its own phase, sampled so that
    each peak lies on a sample: peak-based K_γ = max(M + A) / mean(M + A), mean-load K_γ =
    max M / mean M. The engagement pattern (each path jumps to 2 F0 at its own instant, the
    others at F0): peak-based 1, mean-load 1, where the per-instant ratio is 1.5. Constant
    forces (a static sharing): both equal max F / mean F. A sweep's leading axis is kept; JAX
    input gives the same, and its gradient the analytic one; bad shapes refused."""
    t = np.arange(120) / 120.0
    m = np.array([1.0e4, 1.1e4, 0.95e4])
    a = np.array([2.0e3, 5.0e2, 4.0e3])
    phase = np.array([0.0, 1.0 / 3.0, 0.5])  # each on a sample (120 / 3, 120 / 2)
    f = m + a * np.cos(2 * np.pi * (t[:, None] - phase))
    got = jp.dynamic_load_sharing(f)
    p = m + a
    assert float(got.k_gamma) == pytest.approx(p.max() / p.mean(), rel=1e-12)
    assert float(got.k_gamma_mean_load) == pytest.approx(m.max() / m.mean(), rel=1e-12)
    # the engagement pattern: one path at a time at 2 F0
    f0 = 7.0e3
    jump = np.full((9, 3), f0)
    jump[1, 0] = jump[4, 1] = jump[7, 2] = 2 * f0
    got = jp.dynamic_load_sharing(jump)
    assert float(got.k_gamma) == pytest.approx(1.0, abs=1e-15)
    assert np.max(jump.max(axis=1) / jump.mean(axis=1)) == pytest.approx(1.5)
    const = np.tile([1.2e4, 1.0e4, 0.8e4], (120, 1))
    got = jp.dynamic_load_sharing(const)
    assert float(got.k_gamma) == pytest.approx(1.2, rel=1e-12)
    assert float(got.k_gamma_mean_load) == pytest.approx(1.2, rel=1e-12)
    # a sweep: (s, t, n) gives (s,)
    both = jp.dynamic_load_sharing(np.stack([f, const]))
    np.testing.assert_allclose(both.k_gamma, [p.max() / p.mean(), 1.2], rtol=1e-12)
    # JAX input, and d K_γ / d F at the largest path's peak: 1 / mean P - P_max / (n mean P^2)
    j = jp.dynamic_load_sharing(jnp.asarray(f))
    assert float(j.k_gamma) == pytest.approx(p.max() / p.mean(), rel=1e-12)
    grad = np.asarray(jax.grad(lambda x: jp.dynamic_load_sharing(x).k_gamma)(jnp.asarray(f)))
    i, k = int(np.argmax(f[:, 2])), 2  # path 3 has the largest peak (1.35e4)
    want = 1 / p.mean() - p.max() / (3 * p.mean() ** 2)
    assert grad[i, k] == pytest.approx(want, rel=1e-12)
    for bad in (np.ones(3), np.ones((0, 3)), np.ones((4, 0))):
        with pytest.raises(ValueError, match=r"^dynamic_load_sharing: sun_mesh_forces shape"):
            jp.dynamic_load_sharing(bad)


def test_dynamic_k_gamma_constant_meshes_pin_error_is_the_quasi_static():
    """Constant mesh stiffness, a held sun and a 10 µm pin error on planet 1 (planar model),
    at a mesh frequency of 40 Hz, far below the stage's modes: the forces do not vary in time,
    so the peak-based and the mean-load dynamic K_γ both equal the quasi-static K_γ of
    jaxgear.planetary.load_sharing (the linear solve of the same stage, a separate code path), to
    1e-6 (the rotating frame's terms at Ω ≈ 1 rad/s move it by far less); K_γ well above 1 here."""
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    errors = np.array([10e-6, 0.0, 0.0])
    model = jp.PlanarPlanetary()
    contact = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    meshes = jp.ConstantMeshes(contact.mesh_period())
    run = jp.PlanetaryRun(TORQUE, steps_per_period=48, periods=3, keep_periods=2,
                          damping_ratio=ZETA, tangential_pin_errors=errors)
    got = jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(_speed(st, contact, 40.0)))
    assert int(got.result) == 0
    want = float(jp.load_sharing(model, st, TORQUE, errors).k_gamma)
    assert want > 1.05
    assert float(got.k_gamma) == pytest.approx(want, abs=1e-6)
    assert float(got.k_gamma_mean_load) == pytest.approx(want, abs=1e-6)
