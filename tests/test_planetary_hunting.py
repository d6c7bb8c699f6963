"""Per-tooth deviations of a planetary stage over its hunting period (jaxgear.planetary.PlanetaryTeeth,
jaxgear.planetary.DeviationMeshes): the tooth bookkeeping against an enumeration written here (the sun's
and the ring's teeth rolled along their base circles to each planet's line of action, a planet
tooth's two flanks drawn as involutes and cut with both lines), one planet tooth's pitch
deviation seen exactly where that tooth is in mesh (sun and ring, that planet), the hunting
period lcm(z_s, z_p, z_r) and no shorter one, zero deviations giving the contact meshes' results
exactly, and K_gamma with a pin error and deviations against a spring model written here."""

import jax
import numpy as np
import pytest
from scipy.optimize import brentq

import jaxgear as jg
import jaxgear.planetary as jp
from _planetary_stage import K0, SEQ, geometry, rigid_path_forces, stage

jax.config.update("jax_enable_x64", True)

Z_S, Z_P, Z_R = 19, 17, 53  # SEQ: 19/17/-53, three planets (sequentially phased)
ALPHA_N = np.radians(20.0)
TORQUE = 1000.0
N_POS = 60  # every solve below has this many positions: one compiled program for the file


def seq_stage():
    """The SEQ stage's (geometry, three-planet stage, uniform contact meshes, tooth bookkeeping)."""
    geo = geometry(**SEQ)
    st = stage(geo, 3)
    contact = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    teeth = jp.PlanetaryTeeth.from_geometry(geo, st.planet_angles)
    return geo, st, contact, teeth


@pytest.fixture(scope="module")
def seq():
    return seq_stage()


def _inv(a):
    return np.tan(a) - a


def drawn_sun_ring_travel(geo):
    """D (m, modulo a planet turn z_p p_b): how far a planet tooth's contact on the ring line
    runs ahead of its contact on the sun line, from the planet's involute flanks drawn in its
    frame (teeth centred at c0 + 2 pi j / z_p, the flank facing counter-clockwise loaded by
    the sun, the other by the ring) cut with both lines of action; s from each pair's
    engagement point (the planet's tip on the sun line, the ring's tip on the ring line). The
    drawing also fixes the senses used: turning the planet clockwise moves every contact
    forward on both lines, and tooth j + 1 runs one base pitch behind tooth j on each."""
    sp, pr = geo.sun_planet, geo.planet_ring
    a = geo.center_distance
    m_t, a_t = sp.transverse_module, sp.transverse_pressure_angle
    r_p = Z_P * m_t / 2
    r_bp, r_ap = r_p * np.cos(a_t), sp.tip_radii[1]
    r_br, r_ar = pr.base_radii[1], pr.tip_radii[1]
    s_t = m_t * (np.pi / 2 + 2 * sp.gear.profile_shift * np.tan(ALPHA_N))
    p_b = 2 * np.pi * r_bp / Z_P

    def flank(R, c, sign):
        th = c + sign * (s_t / (2 * r_p) + _inv(a_t) - _inv(np.arccos(r_bp / R)))
        return np.array([R * np.cos(th), R * np.sin(th)])

    def contacts(c0, nu, h, direction, sign):
        out = []
        grid = np.linspace(r_bp * (1 + 1e-9), r_ap, 300)
        for j in range(Z_P):
            c = c0 + 2 * np.pi * j / Z_P
            g = np.array([nu @ flank(R, c, sign) - h for R in grid])
            for i in np.nonzero(np.sign(g[:-1]) != np.sign(g[1:]))[0]:
                R = brentq(lambda R: nu @ flank(R, c, sign) - h, grid[i], grid[i + 1],
                           xtol=1e-15)
                t = flank(R * (1 + 1e-7), c, sign) - flank(R * (1 - 1e-7), c, sign)
                if abs(t @ direction) / np.linalg.norm(t) < 1e-5:
                    out.append((j, flank(R, c, sign)))
        return out

    a_s, a_r = geo.sun_pressure_angle, geo.ring_pressure_angle
    n = np.array([np.sin(a_s), np.cos(a_s)])
    nu_s = np.array([np.cos(a_s), -np.sin(a_s)])
    t_eng_s = -np.sqrt(r_ap**2 - r_bp**2)
    m = np.array([-np.sin(a_r), np.cos(a_r)])
    nu_r = np.array([np.cos(a_r), np.sin(a_r)])
    centre = np.array([-a, 0.0])
    t_ring = -(centre + r_br * nu_r - r_bp * nu_r) @ m
    roots = t_ring + np.array([-1, 1]) * np.sqrt(r_ar**2 - r_br**2)
    t_eng_r = roots[(roots > 0) & (roots < np.sqrt(r_ap**2 - r_bp**2))][0]

    def lines(c0):
        # the sun loads the flanks facing counter-clockwise (+), the ring those facing clockwise
        sun = {j: (p + r_bp * nu_s) @ n - t_eng_s for j, p in contacts(c0, nu_s, -r_bp, n, 1.0)
               if (p + r_bp * nu_s) @ n < 0}
        ring = {j: (p - r_bp * nu_r) @ (-m) - t_eng_r
                for j, p in contacts(c0, nu_r, r_bp, -m, -1.0) if (p - r_bp * nu_r) @ (-m) > 0}
        return sun, ring

    sun, ring = lines(0.05)
    eps = 1e-4
    sun2, ring2 = lines(0.05 - eps)  # the planet turned clockwise
    for a_, b_ in ((sun, sun2), (ring, ring2)):
        assert len(a_) >= 2
        for j in a_:
            assert b_[j] - a_[j] == pytest.approx(r_bp * eps, rel=1e-6)  # forward
            if j + 1 in a_:
                assert a_[j] - a_[j + 1] == pytest.approx(p_b, rel=1e-9)  # one pitch behind
    j, k = next(iter(sun)), next(iter(ring))
    # tooth j's ring contact would be (k - j) pitches ahead of tooth k's
    return float(np.mod(ring[k] + (k - j) * p_b - sun[j], Z_P * p_b))


@pytest.fixture(scope="module")
def drawn_d(seq):
    return drawn_sun_ring_travel(seq[0])


def enumerate_teeth(geo, psi, d, x):
    """The teeth in contact at the mesh travel x, counted here: per planet n, the sun lines
    [(s, sun tooth, planet tooth)] and the ring lines [(s, planet tooth, ring tooth)].

    The sun's teeth roll along its base circle: sun tooth t is on planet 1's line at
    s = x - t p_b (tooth 0 enters there at x = 0), and planet n's line is r_bs (psi_n - psi_1)
    further along the sun's base circle (the sun turns counter-clockwise). The ring turns
    clockwise: ring tooth u is on planet 1's line at x + Delta - u p_b (Delta = d mod p_b) and
    reaches planet n's r_br (psi_n - psi_1) sooner. Planet n's tooth k enters its sun mesh at
    x = (k + gamma_n) p_b, gamma_n = frac(z_s (psi_n - psi_1) / 2 pi) (Parker & Lin's phase),
    and its ring flank is d ahead of its sun flank (the drawing)."""
    sp, pr = geo.sun_planet, geo.planet_ring
    p_b = sp.base_pitch
    r_bs, r_br = sp.base_radii[0], pr.base_radii[1]
    g_s, g_r = sp.path_of_contact, pr.path_of_contact
    out = []
    for dpsi in np.asarray(psi) - psi[0]:
        gamma = np.mod(Z_S * dpsi / (2 * np.pi), 1.0)
        sun, ring = [], []
        for t in range(Z_S):
            s = np.mod(x - t * p_b - r_bs * dpsi, Z_S * p_b)
            if s <= g_s:
                sun.append((s, t, int(round((x - gamma * p_b - s) / p_b)) % Z_P))
        for u in range(Z_R):
            s = np.mod(x + np.mod(d, p_b) - u * p_b + r_br * dpsi, Z_R * p_b)
            if s <= g_r:
                ring.append((s, int(round((x - gamma * p_b - s + d) / p_b)) % Z_P, u))
        out.append((sorted(sun), sorted(ring)))
    return out


def library_teeth(contact, teeth, xs):
    """The same from the library at each travel of ``xs``: each planet's cells in contact
    (mid-face slice) with PlanetaryTeeth's teeth of their lines."""
    p_b = contact.sun_mesh.base_pitch

    @jax.jit
    def at(x):
        rows = []
        for mesh, arc, fn in (
            (contact.sun_mesh, x - contact.sun_phases * p_b, teeth.sun_mesh_teeth),
            (contact.ring_mesh, x + contact.ring_offset - contact.ring_phases * p_b,
             teeth.ring_mesh_teeth),
        ):
            cells = jax.vmap(mesh.cells)(arc / mesh.base_radius_pinion)
            a, b = fn(x, cells.line[0])
            rows.append((cells.s[..., 0], cells.mask[..., 0], a[..., 0], b[..., 0]))
        return rows

    out = []
    for x in xs:
        rows = [[np.asarray(v) for v in r] for r in at(x)]
        out.append([tuple(sorted((float(s[n, i]), int(a[n, i]), int(b[n, i]))
                                 for i in np.nonzero(m[n])[0]) for s, m, a, b in rows)
                    for n in range(teeth.n_planets)])
    return out


def test_bookkeeping_against_teeth_counted_here(seq, drawn_d):
    """At 40 travels spread over a hunting period (and one past it), every planet's sun and
    ring lines in contact carry the teeth counted by rolling the sun and ring along their base
    circles and by the drawn planet flanks (the library's Delta_rs agreeing with the drawing);
    H = lcm(19, 17, 53) = 17119 mesh periods."""
    geo, st, contact, teeth = seq
    p_b = float(contact.sun_mesh.base_pitch)
    assert teeth.teeth == (Z_S, Z_P, Z_R)
    assert jp.planetary_hunting_periods(Z_S, Z_P, Z_R) == teeth.hunting_periods == 17119
    d_lib = float(contact.ring_offset)
    assert min(abs(d_lib - np.mod(drawn_d, p_b)), p_b - abs(d_lib - np.mod(drawn_d, p_b))) < 1e-9
    rng = np.random.default_rng(3)
    xs = np.concatenate([rng.uniform(0.0, 17120 * p_b, 36), [0.37 * p_b, 5.71 * p_b,
                                                              17119.4 * p_b, 903.2 * p_b]])
    psi = np.asarray(st.planet_angles)
    kinds = set()
    for x, got in zip(xs, library_teeth(contact, teeth, xs), strict=True):
        want = enumerate_teeth(geo, psi, drawn_d, x)
        for n in range(3):
            for w, g in zip(want[n], got[n], strict=True):
                assert [t[1:] for t in g] == [t[1:] for t in w], (x / p_b, n)
                np.testing.assert_allclose([t[0] for t in g], [t[0] for t in w],
                                           atol=1e-9 * p_b)
                kinds.add(len(g))
    assert kinds == {1, 2}  # single and double contact both met


def _one_tooth(z, tooth, f):
    """Single pitch deviations that move tooth ``tooth`` alone by f (m): f_pt,k = +f,
    f_pt,k+1 = -f (F_p,k = f, every other F_p,n = 0)."""
    fpt = np.zeros(z)
    fpt[tooth], fpt[(tooth + 1) % z] = f, -f
    return fpt


def _deviations(sun=None, planets=None, ring=None, profile=None):
    """Every member given (zeros where not set): one pytree structure for the whole file."""
    g = lambda v, z: jg.GearDeviations(np.zeros(z) if v is None else v,  # noqa: E731
                                       profile_slope=0.0 if profile is None else profile[z])
    planets = planets or [None] * 3
    return jp.PlanetaryDeviations(g(sun, Z_S), tuple(g(p, Z_P) for p in planets), g(ring, Z_R))


def _solve(model, st, meshes, x, errors=np.zeros(3)):
    assert len(x) == N_POS
    r = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), np.asarray(x), errors)
    assert np.all(np.asarray(r.result) == 0)
    return r


# default tier: tests/test_planetary_hunting.py::test_one_planet_tooth_is_seen_where_it_meshes_and_every_planet_turn (away from the moved tooth the deviation meshes are the contact meshes, TE to 1e-15)
@pytest.mark.slow
def test_zero_deviations_are_the_contact_meshes(seq, nominal):
    """Every deviation 0: forces, TE, displacements and K_gamma of the contact meshes
    (1e-12), plain, with a pin error and with tip relief on both pairs."""
    geo, st, contact, teeth = seq
    x, plain = nominal
    errors = np.array([8e-6, 0.0, -3e-6])
    tip = jg.Modifications.symmetric(jg.MemberModification(tip_relief_depth=12e-6,
                                                            tip_relief_extent=0.3))
    relieved = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0),
                                              modifications=(tip, tip))
    model = jp.TorsionalPlanetary()
    for c, e, want in ((contact, np.zeros(3), plain), (relieved, errors, None)):
        want = want or _solve(model, st, c, x, e)
        got = _solve(model, st, jp.DeviationMeshes(c, teeth, _deviations()), x, e)
        for name in ("sun_mesh_forces", "ring_mesh_forces", "sun_te", "ring_te", "k_gamma",
                     "displacement"):
            w, g = np.asarray(getattr(want, name)), np.asarray(getattr(got, name))
            np.testing.assert_allclose(g, w, rtol=1e-12, atol=1e-12 * np.abs(w).max())


@pytest.fixture(scope="module")
def nominal(seq):
    """The contact meshes' solve (torsional, no deviation) at the travels of the one-tooth
    test, shared with the zero-deviation test (one compiled program)."""
    geo, st, contact, teeth = seq
    x = np.asarray(contact.positions(3, 20))
    return x, _solve(jp.TorsionalPlanetary(), st, contact, x)


def _contact_windows(geo, psi, d, x, planet, tooth):
    """(on the sun line, on the ring line): at each travel, whether planet ``planet``'s tooth
    ``tooth`` is in contact, from :func:`enumerate_teeth`."""
    sun, ring = [], []
    for xi in x:
        s_lines, r_lines = enumerate_teeth(geo, psi, d, xi)[planet]
        sun.append(any(k == tooth for _, _, k in s_lines))
        ring.append(any(k == tooth for _, k, _ in r_lines))
    return np.array(sun), np.array(ring)


def test_one_planet_tooth_is_seen_where_it_meshes_and_every_planet_turn(seq, drawn_d, nominal):
    """Planet 2's tooth 5 moved 4 um (its single pitch deviations +f, -f): the forces and TE
    change exactly at the travels where that tooth is in contact with the sun or the ring
    (counted here), nowhere else; the mesh whose TE drops most is planet 2's sun mesh while
    the tooth is on the sun line and its ring mesh while on the ring line; planet 2 takes more
    load, the others less; the pattern repeats after one planet turn (17 mesh periods) and
    not after fewer."""
    geo, st, contact, teeth = seq
    f = 4e-6
    p_b = float(contact.sun_mesh.base_pitch)
    devs = _deviations(planets=[None, _one_tooth(Z_P, 5, f), None])
    meshes = jp.DeviationMeshes(contact, teeth, devs)
    model = jp.TorsionalPlanetary()
    x, nominal = nominal  # 20 mesh periods: the tooth passes both meshes
    got = _solve(model, st, meshes, x)
    d_f = np.asarray(got.sun_mesh_forces) - np.asarray(nominal.sun_mesh_forces)
    d_te = np.concatenate([np.asarray(got.sun_te) - np.asarray(nominal.sun_te),
                           np.asarray(got.ring_te) - np.asarray(nominal.ring_te)], axis=1)
    on_sun, on_ring = _contact_windows(geo, np.asarray(st.planet_angles), drawn_d, x, 1, 5)
    assert on_sun.sum() >= 3 and on_ring.sum() >= 3 and not np.any(on_sun & on_ring)
    event = np.abs(d_f).max(axis=1) > 1e-6 * TORQUE
    np.testing.assert_array_equal(event, on_sun | on_ring)
    assert np.abs(d_te[~event]).max() < 1e-15
    assert np.all(d_f[event, 1] > 0) and np.all(d_f[event][:, [0, 2]] < 0)
    worst = np.argmin(d_te, axis=1)
    assert np.all(worst[on_sun] == 1) and np.all(worst[on_ring] == 3 + 1)
    assert np.all(d_te[on_sun | on_ring].min(axis=1) < -f)  # the tooth's material, and more
    # one planet turn later the same; a shift of 1 to 16 mesh periods is not a period (the
    # contact meshes alone repeat every mesh period)
    later = _solve(model, st, meshes, x + Z_P * p_b)
    np.testing.assert_allclose(later.sun_mesh_forces, got.sun_mesh_forces, rtol=1e-9)
    np.testing.assert_allclose(later.ring_te, got.ring_te, rtol=1e-9, atol=1e-15)
    full = d_te[: 3 * Z_P]  # one planet turn (3 positions per mesh period) ...
    both = np.concatenate([full, full])  # ... and the next: 0 to 34 mesh periods
    per = 3  # positions per mesh period
    for k in range(1, Z_P):
        assert np.abs(both[k * per:] - both[: len(both) - k * per]).max() > 0.5 * f, k


def _drawn(seed):
    """Sun, every planet and ring drawn at ISO 1328-1 class 6 (runout left to the stage)."""
    rng = np.random.default_rng(seed)
    geo = geometry(**SEQ)
    sp = geo.sun_planet
    out = []
    for z, w in ((Z_S, 0.03), (Z_P, 0.03), (Z_P, 0.03), (Z_P, 0.03), (Z_R, 0.03)):
        d = z * sp.normal_module
        tol = jg.iso1328_tolerances(sp.normal_module, d, w, 6)
        out.append(np.asarray(jg.sample_gear_deviations(rng, z, tol).single_pitch))
    return out


def test_hunting_period_and_no_shorter_one(seq):
    """Sun, planets and ring drawn at ISO 1328-1 class 6: the stage's forces and TE at 12
    travels come back after H = 17119 mesh periods (1e-8), and not after H / 19, H / 17 or
    H / 53 (each prime factor removed: the smallest period divides H, so H is the smallest)."""
    geo, st, contact, teeth = seq
    p_b = float(contact.sun_mesh.base_pitch)
    sun, *planets, ring = _drawn(7)
    meshes = jp.DeviationMeshes(contact, teeth, _deviations(sun, planets, ring))
    h = teeth.hunting_periods
    base = np.asarray(contact.positions(4, 3)) + 3 * p_b
    shifts = [0, h, h // 19, h // 17, h // 53]
    x = np.concatenate([base + k * p_b for k in shifts])
    r = _solve(jp.TorsionalPlanetary(), st, meshes, x)
    f = np.concatenate([np.asarray(r.sun_mesh_forces), np.asarray(r.ring_mesh_forces)], 1)
    te = np.concatenate([np.asarray(r.sun_te), np.asarray(r.ring_te)], 1)
    blocks = np.split(np.concatenate([f, 1e9 * te], 1), len(shifts))
    scale = np.abs(blocks[0]).max()
    np.testing.assert_allclose(blocks[1], blocks[0], atol=1e-8 * scale)
    for b in blocks[2:5]:
        assert np.abs(b - blocks[0]).max() > 1e-3 * scale
    assert float(np.ptp(np.asarray(r.k_gamma)[:12])) > 1e-3


def test_k_gamma_with_a_pin_error_and_deviations_against_a_spring_model(seq, drawn_d):
    """A 6 um tangential error on planet 1's pin, the planets' teeth drawn at class 6 and a
    profile slope on every sun and ring tooth: at each travel, the series-spring model of
    tests/_planetary_stage.py with each mesh's offset the stiffness-weighted material of its
    lines in contact (uniform k0 b per line, the teeth and rolls counted here): K_gamma and the
    forces within 1e-6 (torsional model), K_gamma within 1 % (planar, stiff pins)."""
    geo, st, contact, teeth = seq
    sp, pr = geo.sun_planet, geo.planet_ring
    _, *planets, _ = _drawn(11)
    slope = {Z_S: np.linspace(-3e-6, 3e-6, Z_S), Z_R: np.linspace(2e-6, -2e-6, Z_R)}
    slope[Z_P] = np.zeros(Z_P)
    devs = _deviations(planets=planets, profile=slope)
    meshes = jp.DeviationMeshes(contact, teeth, devs)
    errors = np.array([6e-6, 0.0, 0.0])
    cum = [np.cumsum(p) - p[0] for p in planets]
    g_s, g_r = sp.path_of_contact, pr.path_of_contact

    # the sun's flank at roll u = s / g, the planet's at 1 - u (it is the driven gear)
    def sun_material(n, s, t, k):
        return slope[Z_S][t] * (s / g_s - 0.5) + cum[n][k]

    def ring_material(n, s, k, u):
        return cum[n][k] + slope[Z_R][u] * (1 - s / g_r - 0.5)

    assert_spring_model(seq, drawn_d, meshes, errors, sun_material, ring_material)


def assert_spring_model(seq, drawn_d, meshes, errors, sun_material, ring_material):
    """At 4 x 15 travels, the series-spring model of tests/_planetary_stage.py with each mesh's
    offset the mean material of its lines in contact (uniform k0 b per line; the teeth and rolls
    counted by :func:`enumerate_teeth`; ``sun_material(n, s, sun tooth, planet tooth)`` and
    ``ring_material(n, s, planet tooth, ring tooth)`` give a line's material, m) against
    ``meshes``' quasi-static solve with the pin ``errors``: forces and K_gamma within 1e-6
    (torsional model), K_gamma within 1 % (planar, stiff pins)."""
    geo, st, contact, _ = seq
    sp = geo.sun_planet
    x = np.asarray(contact.positions(4, 15))
    psi = np.asarray(st.planet_angles)
    pins = np.stack([errors, np.zeros(3)], axis=1)
    forces = []
    for xi in x:
        c_s, c_r, k_s, k_r = [], [], [], []
        for n, (s_lines, r_lines) in enumerate(enumerate_teeth(geo, psi, drawn_d, xi)):
            e_s = [sun_material(n, s, t, k) for s, t, k in s_lines]
            e_r = [ring_material(n, s, k, u) for s, k, u in r_lines]
            k_s.append(K0 * 0.03 * len(e_s))
            k_r.append(K0 * 0.03 * len(e_r))
            c_s.append(np.mean(e_s))  # equal line stiffnesses: the mean of the lines'
            c_r.append(np.mean(e_r))
        # the pin error moves planet 1 tangentially: c = -p . n (sun), -p . m (ring)
        f, _ = rigid_path_forces(TORQUE, sp.base_radii[0], psi, geo.sun_pressure_angle,
                                 geo.ring_pressure_angle, np.array(k_s), np.array(k_r),
                                 pins=pins, mesh_offsets=(np.array(c_s), np.array(c_r)))
        forces.append(f)
    forces = np.array(forces)
    k_hand = forces.max(axis=1) / forces.mean(axis=1)
    assert forces.min() > 0 and np.ptp(k_hand) > 0.02
    got = _solve(jp.TorsionalPlanetary(), st, meshes, x, errors)
    np.testing.assert_allclose(got.sun_mesh_forces, forces, rtol=1e-6)
    np.testing.assert_allclose(got.k_gamma, k_hand, rtol=1e-6)
    planar = _solve(jp.PlanarPlanetary(), st, meshes, x, errors)
    np.testing.assert_allclose(planar.k_gamma, k_hand, rtol=1e-2)


def test_bad_inputs_are_one_line(seq):
    geo, st, contact, teeth = seq
    cases = [
        (lambda: jp.DeviationMeshes(contact, teeth, jp.PlanetaryDeviations(
            sun=jg.GearDeviations(np.zeros(18)))), "sun has 18 teeth"),
        (lambda: jp.DeviationMeshes(contact, teeth, jp.PlanetaryDeviations(
            planets=(None, None))), "planets has 2 entries"),
        (lambda: jp.PlanetaryDeviations(ring=jg.GearDeviations(np.zeros(53), runout=1e-6)),
         "ring.runout"),
        (lambda: jp.PlanetaryDeviations(sun=np.zeros(19)), "sun"),
        (lambda: jp.planetary_hunting_periods(19, 0, 53), "z_planet"),
        # the dynamics lay out one mesh period's cells: refused, not repeated silently
        (lambda: jp.planetary_dynamics(
            jp.TorsionalPlanetary(), st, jp.DeviationMeshes(contact, teeth, _deviations()),
            jp.PlanetaryRun(TORQUE, steps_per_period=8, periods=2, keep_periods=1),
            jax.numpy.asarray(60.0)), "change from one mesh period to the next"),
    ]
    for make, words in cases:
        with pytest.raises(ValueError) as err:
            make()
        msg = str(err.value)
        assert words in msg and "\n" not in msg, msg


EXAMPLE = "examples/planetary-hunting.toml"


def _example():
    import pathlib
    import tomllib

    root = pathlib.Path(__file__).resolve().parent.parent
    return tomllib.loads((root / EXAMPLE).read_text("utf-8")), root


def test_case_keys_draw_every_member_in_order_and_refuse_in_one_line():
    """examples/planetary-hunting.toml: class 6 drawn with default_rng(1) in the order sun,
    the sun-side flanks of planet 1, 2, 3, ring, then their ring-side flanks (each from its own
    ISO 1328-1 tolerances, redrawn here), planet 2's pitch deviations replaced by the file's
    on both flanks, no runout (the stage's); revolutions "hunting" is 17119 mesh periods (901
    sun turns); bad keys and values are one line naming them."""
    import copy

    import jaxgear.io as jio

    data, _ = _example()
    case = jio.parse_train(copy.deepcopy(data))
    devs, st = case.deviations, case.deviation_settings
    assert isinstance(devs, jp.PlanetaryDeviations)
    assert st["mesh_periods"] == 2 * Z_S and st["hunting_periods"] == 17119
    rng = np.random.default_rng(1)
    sp = case.pairs[0]
    planet_2 = (devs.planet(1).sun_flank, devs.planet(1).ring_flank)
    for member, z in ((devs.sun, Z_S), *((devs.planet(i).sun_flank, Z_P) for i in range(3)),
                      (devs.ring, Z_R), *((devs.planet(i).ring_flank, Z_P) for i in range(3))):
        tol = jg.iso1328_tolerances(3e-3, z * 3e-3, 0.03, 6)
        want = jg.sample_gear_deviations(rng, z, tol)
        assert float(member.runout) == 0.0
        for name in ("profile_slope", "profile_form", "helix_slope", "helix_form"):
            np.testing.assert_allclose(getattr(member, name), getattr(want, name), rtol=1e-12)
        if all(member is not g for g in planet_2):
            np.testing.assert_allclose(member.single_pitch, want.single_pitch, rtol=1e-12)
    given = np.zeros(Z_P)
    given[5], given[6] = 4e-6, -4e-6
    for g in planet_2:
        np.testing.assert_allclose(g.single_pitch, given, atol=1e-18)
    assert float(sp.transverse_pressure_angle) == float(devs.sun.reference_pressure_angle)
    hunting = copy.deepcopy(data)
    hunting["deviations"]["revolutions"] = "hunting"
    st = jio.parse_train(hunting).deviation_settings
    assert (st["revolutions_count"], st["mesh_periods"]) == (901, 17119)

    def bad(change, words):
        d = copy.deepcopy(data)
        change(d)
        with pytest.raises(ValueError) as err:
            jio.parse_train(d)
        msg = str(err.value)
        assert all(w in msg for w in words) and "\n" not in msg, msg

    bad(lambda d: d["deviations"].update(planet_4={}), ["planet_4", "allowed"])
    bad(lambda d: d["deviations"]["planet_2"].update(runout_um=5.0),
        ["[deviations.planet_2] runout_um", "planet_runout_um"])
    bad(lambda d: d["deviations"]["planet_2"].update(pitch_um=[1.0] * Z_P), ["sum to 17"])
    bad(lambda d: d["deviations"].update(sun={"pitch_um": [0.0] * 18}), ["pitch_um"])
    bad(lambda d: d["deviations"].update(revolutions="hunting", positions_per_pitch=64),
        ["revolutions", "allowed <= 400000"])
    bad(lambda d: d["deviations"].update(revolutions=0), ["revolutions = 0"])


def test_deviations_refused_in_a_train_and_in_the_lumped_form():
    """[deviations] in a gear train's file and in a planetary stage given in the lumped form
    (no teeth): one line each, before any work."""
    import tomllib

    import jaxgear.io as jio

    for name, words in (("accessory-idler-train", "not in a gear train's case"),
                        ("lin-parker-1999", "allowed only with [[gears]]")):
        data = tomllib.loads(jio.embedded_case_text(name))
        data["deviations"] = {"grade": 6}
        with pytest.raises(ValueError) as err:
            jio.parse_train(data)
        msg = str(err.value)
        assert "[deviations]" in msg and words in msg and "\n" not in msg, msg


# a first-look step: the sweep warns that it under-resolves the top mode (tests/test_planetary_step_resolution.py)
@pytest.mark.filterwarnings("ignore:.*time step under-resolved")
@pytest.mark.slow
def test_jaxgear_run_writes_the_hunting_span(tmp_path, capsys):
    """``jaxgear run`` on examples/planetary-hunting.toml: hunting.csv and hunting.png, the
    summary's span (2 sun turns = 38 mesh periods at 4 positions, of a hunting period of
    17119), K_gamma over it equal to the planar solve of the stage with the case's deviations
    written here from the public API, the printed line."""
    import json

    import jaxgear.io as jio
    from jaxgear.cli import main

    _, root = _example()
    out = tmp_path / "run"
    assert main(["run", str(root / EXAMPLE), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "deviations per tooth (grade 6, seed 1): 38 mesh periods" in printed
    h = json.loads((out / "summary.json").read_text())["hunting"]
    assert (h["mesh_periods"], h["hunting_periods"], h["positions"]) == (38, 17119, 152)
    assert h["unconverged_positions"] == 0 and (out / "hunting.png").stat().st_size > 0
    table = np.genfromtxt(out / "hunting.csv", delimiter=",", names=True)
    case = jio.load_case(str(root / EXAMPLE))
    spec = case.form.spec
    geo = jg.PlanetaryGeometry(case.pairs[0], case.pairs[1], spec.center_distance, 0.0)
    contact = spec.dynamic_meshes(case, 1)
    meshes = jp.DeviationMeshes(contact, jp.PlanetaryTeeth.from_geometry(
        geo, np.asarray(spec.planet_angles)), case.deviations)
    x = np.asarray(contact.positions(4, 38))
    r = jp.planetary_quasi_static(jp.PlanarPlanetary(), spec.sharing_stage(spec.stage(case)),
                                  meshes, np.asarray(abs(spec.torques(case.torque)["sun"])), x,
                                  np.asarray(spec.tangential_pin_errors),
                                  np.asarray(spec.radial_pin_errors))
    np.testing.assert_allclose(table["mesh_travel_m"], x, rtol=1e-10)  # the CSV: 12 digits
    np.testing.assert_allclose(table["k_gamma"], r.k_gamma, rtol=1e-9)
    np.testing.assert_allclose(table["ring_te_m_planet_2"], r.ring_te[:, 1], rtol=1e-9,
                               atol=1e-15)
    assert h["k_gamma_max"] == pytest.approx(float(np.max(r.k_gamma)), rel=1e-12)
