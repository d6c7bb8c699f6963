"""The lumped planetary stage (docs/planetary.md): its natural modes against the frequencies
Lin & Parker (1999) print for their example system, the mode structure they prove, an
eigen-solution assembled here from the paper's equations in plain NumPy (not the library's
matrices), the rotating-frame terms, the torsional model against Kahraman's form written
here, the Willis ratios and the assembly condition."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg

import jaxgear as jg
import jaxgear.planetary as jp

ALPHA = np.radians(24.6)


def lin_parker_stage(n, angles=None):
    """Lin & Parker 1999, Table 1: their example system (I/r^2 in kg, k_u in N/m)."""
    member = jp.PlanetaryMember.lumped
    fields = {
        "sun": member(0.4, 0.39, 77.4e-3 / 2, 1e8, 0.0),
        "ring": member(2.35, 3.0, 275.0e-3 / 2, 1e8, 1e9),
        "carrier": member(5.43, 6.29, 176.8e-3 / 2, 1e8, 0.0),
        "planet": member(0.66, 0.61, 100.3e-3 / 2, 1e8, 0.0),
        "sun_pressure_angle": ALPHA,
        "ring_pressure_angle": ALPHA,
        "sun_mesh_stiffness": 5e8,
        "ring_mesh_stiffness": 5e8,
    }
    if angles is None:
        return jp.PlanetaryStage.equally_spaced(n, **fields)
    return jp.PlanetaryStage(planet_angles=angles, **fields)


# The natural frequencies (Hz) Lin & Parker (1999) print for the Table 1 system, by type:
# rotational (single), translational (pairs), planet modes (multiplicity N - 3). Read from the
# transcription of the paper's table in a public repository (a test of a Python port of
# Lin & Parker's model, file tests of "Lin_Parker_99"); the paper itself was not at hand.
PRINTED = {
    3: (
        [0.0, 1475.7, 1930.3, 2658.3, 7462.8, 11775.3],
        [743.2, 1102.4, 1896.0, 2276.4, 6986.3, 9647.9],
        [],
    ),
    4: (
        [0.0, 1536.6, 1970.6, 2625.7, 7773.6, 13071.1],
        [727.0, 1091.0, 1892.8, 2342.5, 7189.9, 10437.6],
        [1808.2, 5963.8, 6981.7],
    ),
    5: (
        [0.0, 1567.4, 2006.1, 2614.8, 8065.4, 14253.1],
        [710.0, 1072.0, 1888.1, 2425.3, 7382.4, 11172.3],
        [1808.2, 5963.8, 6981.7],
    ),
}


@pytest.mark.parametrize("n", [3, 4, 5])
def test_lin_parker_example_frequencies_and_mode_types(n):
    stage = lin_parker_stage(n)
    model = jp.PlanarPlanetary()
    modes = jp.planetary_modes(model, stage)
    f = np.asarray(modes.frequencies)
    types = jp.classify_modes(modes, model, stage)
    by = {
        t: sorted({round(float(x), 6) for x, (tt, _) in zip(f, types, strict=True) if tt == t})
        for t in jp.ModeType
    }
    mult = {t: {m for tt, m in types if tt == t} for t in jp.ModeType}
    rot, tra, pla = PRINTED[n]
    # the structure Lin & Parker prove: 6 rotational (multiplicity 1), 6 translational pairs,
    # 3 planet-mode frequencies of multiplicity N - 3, nothing mixed
    assert len(f) == 3 * (n + 3)
    assert len(by[jp.ModeType.ROTATIONAL]) == 6 and mult[jp.ModeType.ROTATIONAL] == {1}
    assert len(by[jp.ModeType.TRANSLATIONAL]) == 6 and mult[jp.ModeType.TRANSLATIONAL] == {2}
    assert len(by[jp.ModeType.PLANET]) == (3 if n > 3 else 0)
    assert mult[jp.ModeType.PLANET] <= {n - 3}
    assert not by[jp.ModeType.MIXED]
    # the printed frequencies (0.1 Hz rounding; three of N = 4's differ by up to 0.04 %)
    for computed, printed in (
        (by[jp.ModeType.ROTATIONAL], rot),
        (by[jp.ModeType.TRANSLATIONAL], tra),
        (by[jp.ModeType.PLANET], pla),
    ):
        np.testing.assert_allclose(computed, printed, rtol=5e-4, atol=0.06)
    # planet modes: the central members still; mass-normalised shapes
    phi = np.asarray(modes.shapes)
    m = np.asarray(model.mass_matrix(stage))
    np.testing.assert_allclose(phi.T @ m @ phi, np.eye(len(f)), atol=1e-9)
    planet = [j for j, (t, _) in enumerate(types) if t == jp.ModeType.PLANET]
    assert np.abs(phi[:9, planet]).max(initial=0.0) < 1e-9 * np.abs(phi).max()
    # rotational modes: every planet moves alike in its own (zeta, eta, u)
    rotational = [j for j, (t, _) in enumerate(types) if t == jp.ModeType.ROTATIONAL]
    planets = phi[9:, rotational].reshape(n, 3, -1)
    np.testing.assert_allclose(
        planets, np.broadcast_to(planets[:1], planets.shape), atol=1e-9 * np.abs(phi).max()
    )


# -- an independent planar model, from the paper's equations, in plain NumPy -------------------


def reference_planar(masses, inertias, radii, bearings, torsion, angles, a_s, a_r, k_s, k_r, pin):
    """M, K of Lin & Parker's planar model: members c, r, s (index 0, 1, 2), then the planets;
    K assembled as sum k a a^T with a the gradient of each spring's deflection."""
    n = len(angles)
    size = 9 + 3 * n
    K = np.zeros((size, size))

    def spring(k, terms):
        a = np.zeros(size)
        for i, c in terms:
            a[i] += c
        K[:, :] += k * np.outer(a, a)

    for h in range(3):  # central bearings: x, y, u
        spring(bearings[h][0], [(3 * h, 1.0)])
        spring(bearings[h][1], [(3 * h + 1, 1.0)])
        spring(torsion[h], [(3 * h + 2, 1.0)])
    for j, psi in enumerate(angles):
        z, e, u = 9 + 3 * j, 10 + 3 * j, 11 + 3 * j
        ps, pr = psi - a_s, psi + a_r
        # sun-planet: -x_s sin psi_s + y_s cos psi_s - zeta sin a_s - eta cos a_s + u_s + u_p
        spring(
            k_s[j],
            [
                (6, -np.sin(ps)),
                (7, np.cos(ps)),
                (z, -np.sin(a_s)),
                (e, -np.cos(a_s)),
                (8, 1.0),
                (u, 1.0),
            ],
        )
        # ring-planet: -x_r sin psi_r + y_r cos psi_r + zeta sin a_r - eta cos a_r + u_r - u_p
        spring(
            k_r[j],
            [
                (3, -np.sin(pr)),
                (4, np.cos(pr)),
                (z, np.sin(a_r)),
                (e, -np.cos(a_r)),
                (5, 1.0),
                (u, -1.0),
            ],
        )
        # planet pin on the carrier, radial and tangential
        spring(pin[0], [(0, np.cos(psi)), (1, np.sin(psi)), (z, -1.0)])
        spring(pin[1], [(0, -np.sin(psi)), (1, np.cos(psi)), (2, 1.0), (e, -1.0)])
        spring(torsion[3], [(u, 1.0)])
    diag = []
    for h in range(3 + n):
        i = min(h, 3)
        diag += [masses[i], masses[i], inertias[i] / radii[i] ** 2]
    return np.diag(diag), K


def _random_stage(rng, n, angles):
    member = jp.PlanetaryMember
    raw = {
        "masses": rng.uniform(0.5, 5.0, 4),
        "inertias": rng.uniform(1e-3, 5e-2, 4),
        "radii": np.array([0.09, 0.14, 0.04, 0.02]),
        "bearings": rng.uniform(1e7, 1e9, (4, 2)),
        "torsion": np.array([rng.uniform(1e6, 1e7), 5e7, 2e5, 0.0]),
        "angles": angles,
        "a_s": np.radians(21.0),
        "a_r": np.radians(23.5),
        "k_s": rng.uniform(2e8, 6e8, n),
        "k_r": rng.uniform(3e8, 8e8, n),
    }
    members = [
        member(
            raw["masses"][i],
            raw["inertias"][i],
            raw["radii"][i],
            raw["bearings"][i],
            raw["torsion"][i],
        )
        for i in range(4)
    ]
    stage = jp.PlanetaryStage(
        carrier=members[0],
        ring=members[1],
        sun=members[2],
        planet=members[3],
        planet_angles=angles,
        sun_pressure_angle=raw["a_s"],
        ring_pressure_angle=raw["a_r"],
        sun_mesh_stiffness=raw["k_s"],
        ring_mesh_stiffness=raw["k_r"],
    )
    # the reference takes k_u = k_theta / r^2 on u = r theta
    torsion_u = raw.pop("torsion") / raw["radii"] ** 2
    pin = raw["bearings"][3]
    return stage, reference_planar(torsion=torsion_u, pin=pin, **raw)


@pytest.mark.parametrize("n", [3, 4, 6])
def test_planar_model_against_an_independent_numpy_eigen_solution(n):
    rng = np.random.default_rng(n)
    # unequal spacing (each planet up to a fifth of the spacing off its equal place, so that
    # the planets' base circles stay apart: PlanetaryStage refuses overlapping planets),
    # per-planet stiffness
    angles = 2 * np.pi * (np.arange(n) + rng.uniform(-0.2, 0.2, n)) / n
    stage, (m_ref, k_ref) = _random_stage(rng, n, angles)
    model = jp.PlanarPlanetary()
    np.testing.assert_allclose(model.mass_matrix(stage), m_ref, rtol=1e-12)
    w2 = scipy.linalg.eigh(k_ref, m_ref, eigvals_only=True)
    f_ref = np.sqrt(np.clip(w2, 0.0, None)) / (2 * np.pi)
    f = np.asarray(jp.planetary_modes(model, stage).frequencies)
    np.testing.assert_allclose(f, f_ref, rtol=1e-9)


def test_campbell_against_a_point_mass_in_a_rotating_frame():
    """The carrier-frame equations of each mass, m (x'' - 2 Omega y' - Omega^2 x) = F_x,
    m (y'' + 2 Omega x' - Omega^2 y) = F_y, written here with the independent M, K: the
    first-order eigenvalues (``numpy.linalg.eig``) against :func:`jaxgear.planetary.campbell` (skew
    form, Hermitian ``eigh``), 0 to 800 rad/s; the translational pairs split with speed."""
    rng = np.random.default_rng(7)
    stage, (m_ref, k_ref) = _random_stage(rng, 4, np.arange(4) * np.pi / 2)
    size = m_ref.shape[0]
    g_ref, kc_ref = np.zeros((size, size)), np.zeros((size, size))
    for b in range(size // 3):
        m = m_ref[3 * b, 3 * b]
        g_ref[3 * b, 3 * b + 1], g_ref[3 * b + 1, 3 * b] = -2 * m, 2 * m
        kc_ref[3 * b, 3 * b] = kc_ref[3 * b + 1, 3 * b + 1] = m
    speeds = np.array([0.0, 300.0, 800.0])
    want = []
    for omega in speeds:
        a = np.block(
            [
                [np.zeros_like(m_ref), np.eye(size)],
                [
                    -np.linalg.solve(m_ref, k_ref - omega**2 * kc_ref),
                    -np.linalg.solve(m_ref, omega * g_ref),
                ],
            ]
        )
        lam = np.linalg.eigvals(a)
        assert np.abs(lam.real).max() < 1e-6 * np.abs(lam).max()  # stable: pure imaginary
        want.append(np.sort(np.abs(lam.imag))[::2] / (2 * np.pi))
    model = jp.PlanarPlanetary()
    got = np.asarray(jp.campbell(model, stage, speeds))
    np.testing.assert_allclose(got, np.array(want), rtol=1e-9)
    g = np.asarray(model.gyroscopic_matrix(stage))
    np.testing.assert_array_equal(g, -g.T)
    # identical, equally spaced planets: a translational pair at rest splits at speed
    alike = cooley_parker_stage(4)  # isotropic bearings, every member held in rotation
    rest, fast = np.asarray(jp.campbell(model, alike, np.array([0.0, 800.0])))
    types = jp.classify_modes(jp.planetary_modes(model, alike), model, alike)
    pair = [j for j, (t, _) in enumerate(types) if t == jp.ModeType.TRANSLATIONAL][:2]
    assert rest[pair[1]] - rest[pair[0]] < 1e-9 * rest[pair[0]]
    assert fast[pair[1]] - fast[pair[0]] > 1e-3 * rest[pair[0]]


def test_campbell_refuses_a_speed_past_divergence():
    """Lin & Parker's example leaves the carrier free to turn: with the planets' centripetal
    term the rigid rotation has negative stiffness at any speed."""
    with pytest.raises(eqx.EquinoxRuntimeError, match="past divergence"):
        jp.campbell(jp.PlanarPlanetary(), lin_parker_stage(3), np.array([100.0]))


def test_torsional_model_against_kahramans_form():
    """Torsional model: rigid centres and pins, the planet centre turns with the carrier, so
    delta_sn = u_s + u_n - u_c cos a_s and delta_rn = u_r - u_n - u_c cos a_r; the carrier
    carries the planets' masses on its coordinate (u_c = r_c theta_c)."""
    rng = np.random.default_rng(3)
    n = 5
    stage, (m_pl, _) = _random_stage(rng, n, 2 * np.pi * np.arange(n) / n)
    a_s, a_r = float(stage.sun_pressure_angle), float(stage.ring_pressure_angle)
    k_s, k_r = (np.asarray(k) for k in stage.mesh_stiffnesses())
    size = 3 + n
    K = np.zeros((size, size))
    for j in range(n):
        for k, row in (
            (k_s[j], {2: 1.0, 3 + j: 1.0, 0: -np.cos(a_s)}),
            (k_r[j], {1: 1.0, 3 + j: -1.0, 0: -np.cos(a_r)}),
        ):
            a = np.zeros(size)
            for i, c in row.items():
                a[i] += c
            K += k * np.outer(a, a)
    for i, mem in enumerate((stage.carrier, stage.ring, stage.sun)):
        K[i, i] += float(mem.torsional_stiffness) / float(mem.base_radius) ** 2
    m = np.diag([m_pl[2, 2] + n * m_pl[9, 9], m_pl[5, 5], m_pl[8, 8]] + [m_pl[11, 11]] * n)
    model = jp.TorsionalPlanetary()
    np.testing.assert_allclose(model.stiffness_matrix(stage), K, rtol=1e-12, atol=1e-3)
    w2 = scipy.linalg.eigh(K, m, eigvals_only=True)
    np.testing.assert_allclose(
        jp.planetary_modes(model, stage).frequencies,
        np.sqrt(np.clip(w2, 0, None)) / (2 * np.pi),
        rtol=1e-9,
    )
    # identical planets: 4 rotational modes, one planet mode of multiplicity N - 1
    alike = jp.PlanetaryStage(
        **{**_fields(stage), "sun_mesh_stiffness": 4e8, "ring_mesh_stiffness": 5e8}
    )
    types = jp.classify_modes(jp.planetary_modes(model, alike), model, alike)
    assert [t for t, _ in types].count(jp.ModeType.ROTATIONAL) == 4
    assert {m for t, m in types if t == jp.ModeType.PLANET} == {n - 1}  # planets alone


# -- kinematics --------------------------------------------------------------------------------


def test_willis_ratios_exact():
    c = jp.Central
    zs, zr = 19, 56
    assert jp.speed_ratio(zs, zr, c.RING, c.SUN, c.CARRIER) == pytest.approx(1 + zr / zs, rel=1e-14)
    assert jp.speed_ratio(zs, zr, c.CARRIER, c.SUN, c.RING) == pytest.approx(-zr / zs, rel=1e-14)
    assert jp.speed_ratio(zs, zr, c.SUN, c.RING, c.CARRIER) == pytest.approx(1 + zs / zr, rel=1e-14)
    assert jp.speed_ratio(zs, zr, c.RING, c.CARRIER, c.SUN) == pytest.approx(
        zs / (zs + zr), rel=1e-14
    )
    with pytest.raises(ValueError, match="three different members"):
        jp.speed_ratio(zs, zr, c.RING, c.RING, c.SUN)
    with pytest.raises(ValueError, match="z_ring = 10 is out of range"):
        jp.speed_ratio(zs, 10, c.RING, c.SUN, c.CARRIER)


def test_torsional_rigid_mode_is_the_willis_ratio():
    """A geometry-consistent stage (module 3 mm, z_s 21, z_p 27, z_r 75, 20 deg), ring held,
    sun and carrier free: the torsional model's zero-frequency mode turns the sun
    1 + z_r/z_s times the carrier."""
    mn, zs, zp, zr, a = 3e-3, 21, 27, 75, np.radians(20.0)
    member = jp.PlanetaryMember.lumped
    stage = jp.PlanetaryStage.equally_spaced(
        4,
        sun=member(1.0, 0.5, mn * zs * np.cos(a) / 2, 1e8, 0.0),
        ring=member(3.0, 2.0, mn * zr * np.cos(a) / 2, 1e8, 1e9),
        carrier=member(4.0, 3.0, mn * (zs + zp) / 2, 1e8, 0.0),
        planet=member(0.8, 0.6, mn * zp * np.cos(a) / 2, 1e8, 0.0),
        sun_pressure_angle=a,
        ring_pressure_angle=a,
        sun_mesh_stiffness=4e8,
        ring_mesh_stiffness=4e8,
    )
    jp.check_assembly(zs, zr, stage.planet_angles)
    model = jp.TorsionalPlanetary()
    modes = jp.planetary_modes(model, stage)
    assert float(modes.frequencies[0]) < 1e-6 * float(modes.frequencies[1])
    u = np.asarray(modes.shapes[:, 0])
    theta_s = u[2] / float(stage.sun.base_radius)
    theta_c = u[0] / float(stage.carrier.base_radius)
    assert theta_s / theta_c == pytest.approx(
        jp.speed_ratio(zs, zr, jp.Central.RING, jp.Central.SUN, jp.Central.CARRIER), rel=1e-9
    )


def test_assembly_condition_and_input_errors():
    jp.check_assembly(19, 56, 2 * np.pi * np.arange(3) / 3)  # 75 / 3 = 25
    with pytest.raises(ValueError, match=r"planet 2 at 90 deg cannot be assembled"):
        jp.check_assembly(19, 56, 2 * np.pi * np.arange(4) / 4)  # 75 / 4
    jp.check_assembly(20, 70, np.radians([0.0, 120.0, 236.0]))  # 90 * 236 / 360 = 59
    with pytest.raises(ValueError, match=r"PlanetaryMember: mass = -1 kg|mass = -1 is out"):
        jp.PlanetaryMember(mass=-1.0, polar_inertia=1.0, base_radius=0.1)
    with pytest.raises(ValueError, match="sun_pressure_angle = 1.6 rad is out of range"):
        lin_parker_stage(3).__class__(**{**_fields(lin_parker_stage(3)), "sun_pressure_angle": 1.6})
    with pytest.raises(ValueError, match=r"sun_mesh_stiffness must have shape \(\) or \(3,\)"):
        lin_parker_stage(3).__class__(
            **{**_fields(lin_parker_stage(3)), "sun_mesh_stiffness": np.ones(4)}
        )


def _fields(stage):
    return {k: getattr(stage, k) for k in stage.__dataclass_fields__}


def test_frequency_gradient_against_finite_difference():
    model = jp.PlanarPlanetary()

    def f1(k_mesh):
        stage = jp.PlanetaryStage(**{**_fields(lin_parker_stage(3)), "sun_mesh_stiffness": k_mesh})
        return jp.planetary_modes(model, stage).frequencies[5]  # a rotational (single) mode

    k0 = 5e8
    g = jax.grad(f1)(jnp.asarray(k0))
    h = 1e4
    fd = (f1(k0 + h) - f1(k0 - h)) / (2 * h)
    assert float(g) == pytest.approx(float(fd), rel=1e-5)


@pytest.mark.parametrize("what", [
    # default tier: tests/test_planetary.py::test_float32_runs[campbell] (float32 against float64 on the same stage)
    pytest.param("modes_and_load_sharing", marks=pytest.mark.slow), "campbell"])
def test_float32_runs(what):
    """With x64 off the modes, the load sharing and the Campbell frequencies run in float32
    and agree with float64 (a moderate conditioning: bearings 1e8 N/m, Cooley & Parker's
    example)."""
    model = jp.PlanarPlanetary()
    errors = np.array([20e-6, 0.0, 0.0, 0.0])
    out = {}
    for x64 in (False, True):
        with jax.enable_x64(x64):
            stage = cooley_parker_stage(4)
            out[x64] = (
                (
                    jp.planetary_modes(model, stage).frequencies,
                    jp.load_sharing(model, stage, 200.0, errors).k_gamma,
                )
                if what == "modes_and_load_sharing"
                else (jp.campbell(model, stage, np.array([0.0, 300.0])),)
            )
    for low, high in zip(out[False], out[True], strict=True):
        assert low.dtype == np.float32
        np.testing.assert_allclose(low, high, rtol=1e-3)


# Cooley & Parker (2012), Table 1 example at zero carrier speed, and the dimensionless natural
# frequencies omega / sqrt(k_p / m_p) they list for N = 3, 4, 5 (same transcription as above).
COOLEY_PARKER = {
    3: [
        0.9296,
        1.090,
        1.358,
        1.931,
        5.566,
        7.741,
        *[0.7432, 1.018, 1.265, 1.487, 4.976, 6.282] * 2,
    ],
    4: [
        0.9077,
        1.046,
        1.317,
        2.013,
        5.809,
        8.383,
        *[0.7199, 1.001, 1.317, 1.481, 5.153, 6.488] * 2,
        0.9617,
        4.320,
        5.672,
    ],
    5: [
        0.8802,
        1.019,
        1.281,
        2.090,
        6.030,
        8.986,
        *[0.6992, 0.9863, 1.344, 1.496, 5.317, 6.693] * 2,
        *[0.9617, 4.320, 5.672] * 2,
    ],
}


def cooley_parker_stage(n):
    """Cooley & Parker (2012), Table 1: m_s 3, m_r 7.64, m_c 12, m_p 1.86 kg; I/r^2 1.75, 8.09,
    6.80, 1.25 kg; base diameters 55.75, 109.7, 27.0 mm, planet circle 88.6 mm; k_sp = k_rp =
    1e8, k_s 2e7, k_r 1e8, k_c 5e7, k_p 1e7 N/m; k_su 2e7, k_ru = k_cu = 1e8 N/m; 20 deg."""
    member = jp.PlanetaryMember.lumped
    return jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(3.0, 1.75, 55.75e-3 / 2, 2e7, 2e7),
        ring=member(7.64, 8.09, 109.7e-3 / 2, 1e8, 1e8),
        carrier=member(12.0, 6.80, 88.6e-3 / 2, 5e7, 1e8),
        planet=member(1.86, 1.25, 27.0e-3 / 2, 1e7, 0.0),
        sun_pressure_angle=np.radians(20.0),
        ring_pressure_angle=np.radians(20.0),
        sun_mesh_stiffness=1e8,
        ring_mesh_stiffness=1e8,
    )


@pytest.mark.parametrize("n", [3, 4, 5])
def test_cooley_parker_example_at_rest(n):
    """m_s 3, m_r 7.64, m_c 12, m_p 1.86 kg; I/r^2 1.75, 8.09, 6.80, 1.25 kg; base diameters
    55.75, 109.7, 27.0 mm, planet circle 88.6 mm; k_sp = k_rp = 10^8, k_s 2e7, k_r 1e8, k_c 5e7,
    k_p 1e7 N/m; k_su 2e7, k_ru = k_cu = 1e8 N/m; 20 deg."""
    stage = cooley_parker_stage(n)
    modes = jp.planetary_modes(jp.PlanarPlanetary(), stage)
    got = np.asarray(modes.frequencies) * 2 * np.pi / np.sqrt(1e7 / 1.86)
    printed = np.sort(COOLEY_PARKER[n])
    digit = 10.0 ** (np.floor(np.log10(printed)) - 3)  # 4 significant digits
    # within 0.6 of the printed last digit (one value, 1.2805 at N = 5, rounds the other way)
    assert np.all(np.abs(got - printed) <= 0.6 * digit), np.abs(got - printed) / digit
    types = jp.classify_modes(modes, jp.PlanarPlanetary(), stage)
    assert [t for t, _ in types].count(jp.ModeType.ROTATIONAL) == 6
    assert [t for t, _ in types].count(jp.ModeType.PLANET) == 3 * (n - 3)


def test_one_trace_for_new_values_and_vmap_over_a_stiffness():
    """New values of the same stage structure reuse the compiled solve; a sweep of the mesh
    stiffness runs under vmap and matches one-by-one solves."""
    model = jp.PlanarPlanetary()

    @eqx.filter_jit
    @eqx.debug.assert_max_traces(max_traces=1)
    def lowest_rotational(stage):
        return jp.planetary_modes(model, stage).frequencies[5]

    def with_k(k):
        return jp.PlanetaryStage(**{**_fields(lin_parker_stage(3)), "ring_mesh_stiffness": k})

    singles = [float(lowest_rotational(with_k(jnp.asarray(k)))) for k in (3e8, 5e8, 7e8)]
    assert singles[0] < singles[1] < singles[2]
    swept = jax.vmap(lambda k: jp.planetary_modes(model, with_k(k)).frequencies[5])(
        jnp.array([3e8, 5e8, 7e8])
    )
    np.testing.assert_allclose(swept, singles, rtol=1e-12)
