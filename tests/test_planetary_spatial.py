"""The 3D lumped model of a helical planetary stage (jaxgear.planetary.SpatialPlanetary) against
references written here: Lin & Parker's planar model and a hand-assembled axial-tilting system at
beta_b = 0, the mode structure Eritenel & Parker (2009) prove for equally spaced planets, the
statics of a helical stage under a sun torque, the rigid-body motions of a free stage, and the
stiffness as the Hessian of a potential energy written from the 3D kinematics of rigid bodies."""

import dataclasses
import json
import tomllib

import _planetary_stage as ps

import numpy as np
import pytest
import scipy.linalg
from _toml import case_toml

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import main

A = np.radians(22.0)  # both pressure angles
R_S, R_P = 0.03, 0.025  # base radii (m)
R_C = (R_S + R_P) / np.cos(A)  # planet-circle radius: the radii fit (pitch points coincide)
R_R = R_S + 2.0 * R_P
K_MESH = 5e8
BETA = np.radians(20.0)


def stage(n=4, beta=BETA, width=0.03, angles=None, held=True, k_mesh=K_MESH, k_ring=K_MESH):
    m = jp.PlanetaryMember
    g = 1.0 if held else 0.0
    sun = m(1.5, 0.5 * 1.5 * R_S**2, R_S, 1e8 * g, 0.0, 5e7 * g, 1e6 * g, 9e-4)
    ring = m(5.0, 5.0 * R_R**2, R_R, 1e9 * g, 1e9 * R_R**2 * g, 1e9 * g, 1e7 * g)
    carrier = m(4.0, 0.6 * 4.0 * R_C**2, R_C, 1e8 * g, 1e8 * R_C**2 * g, 1e8 * g, 2e6 * g)
    planet = m(0.8, 0.5 * 0.8 * R_P**2, R_P, (1e8, 1.3e8), 0.0, 5e7, (5e5, 6e5), 2e-4)
    kw = {
        "sun": sun,
        "ring": ring,
        "carrier": carrier,
        "planet": planet,
        "sun_pressure_angle": A,
        "ring_pressure_angle": A,
        "sun_mesh_stiffness": k_mesh,
        "ring_mesh_stiffness": k_ring,
        "helix_angle": beta,
        "face_width": width,
    }
    if angles is None:
        return jp.PlanetaryStage.equally_spaced(n, **kw)
    return jp.PlanetaryStage(planet_angles=angles, **kw)


def frequencies(k, m):
    lam = scipy.linalg.eigh(np.asarray(k), np.asarray(m), eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi)


def out_of_plane(st):
    """The axial-tilting system of a spur stage written by hand: per member (z, tilt 1, tilt 2);
    the meshes' tilting stiffness k b^2/12 (k b^2 cos^2 beta_b / 12 at beta_b = 0) on the
    relative tilt seen across the face, the pins' axial and tilting springs, the central
    bearings."""
    n, psi, b = st.n_planets, np.asarray(st.planet_angles), float(st.face_width)
    size = 3 * (3 + n)
    k = np.zeros((size, size))
    mass = []
    for j, mem in enumerate((st.carrier, st.ring, st.sun)):
        t = np.asarray(mem.tilt_stiffness)
        k[3 * j : 3 * j + 3, 3 * j : 3 * j + 3] += np.diag([float(mem.axial_stiffness), *t])
    for mem in (st.carrier, st.ring, st.sun) + (st.planet,) * n:
        mass += [float(mem.mass), float(mem.tilt_inertia), float(mem.tilt_inertia)]
    p = st.planet
    k_s, k_r = (np.broadcast_to(np.asarray(v), (n,)) for v in st.mesh_stiffnesses())
    for i in range(n):
        c, s = np.cos(psi[i]), np.sin(psi[i])
        e_z, e_e = np.array([c, s]), np.array([-s, c])
        pl = 9 + 3 * i
        # pin, axial: z_c + r_c (theta_cx sin psi - theta_cy cos psi) - z_n
        v = np.zeros(size)
        v[[0, 1, 2, pl]] = [1.0, R_C * s, -R_C * c, -1.0]
        k += float(p.axial_stiffness) * np.outer(v, v)
        for axis, kt, col in ((e_z, p.tilt_stiffness[0], 1), (e_e, p.tilt_stiffness[1], 2)):
            v = np.zeros(size)
            v[[1, 2, pl + col]] = [axis[0], axis[1], -1.0]
            k += float(kt) * np.outer(v, v)
        # meshes: theta x e_z = (theta_y, -theta_x) for a central member, theta_eta e_zeta -
        # theta_zeta e_eta for a planet; projected on the transverse line of action
        for central, line, km in ((2, psi[i] - A, k_s[i]), (1, psi[i] + A, k_r[i])):
            nt = np.array([-np.sin(line), np.cos(line)])
            v = np.zeros(size)
            v[3 * central + 1] = -nt[1]
            v[3 * central + 2] = nt[0]
            v[pl + 1] = nt @ e_e  # -(n . (-e_eta)) theta_zeta
            v[pl + 2] = -(nt @ e_z)
            k += km * b**2 / 12.0 * np.outer(v, v)
    return k, np.diag(mass)


def test_spur_decouples_into_planar_and_axial_tilting():
    st = stage(n=4, beta=0.0, angles=np.array([0.0, 1.4, 3.3, 4.9]))
    model = jp.SpatialPlanetary()
    k, m = model.stiffness_matrix(st), model.mass_matrix(st)
    t = np.asarray(model.reduction(st))
    planar_idx = np.flatnonzero(t.sum(0))
    other = np.setdiff1d(np.arange(k.shape[0]), planar_idx)
    assert np.max(np.abs(np.asarray(k)[np.ix_(planar_idx, other)])) < 1e-12 * np.max(np.abs(k))
    f3 = np.sort(frequencies(k, m))
    planar = jp.PlanarPlanetary()
    fp = frequencies(planar.stiffness_matrix(st), planar.mass_matrix(st))
    fo = frequencies(*out_of_plane(st))
    ref = np.sort(np.concatenate([fp, fo]))
    np.testing.assert_allclose(f3, ref, rtol=1e-9, atol=1e-9 * ref.max())


@pytest.mark.parametrize("n", [3, 4, 5])
def test_helical_mode_types_of_equally_spaced_planets(n):
    # unequal sun and ring mesh stiffnesses: with equal ones (and equal pressure angles) the
    # planets' tilt about e_zeta meets the central members only through the harmonics +-1 and
    # appears, still centre, in the rotational-axial family too (a coincidence of the values)
    st = stage(n=n, k_ring=6.5e8)
    model = jp.SpatialPlanetary()
    modes = jp.planetary_modes(model, st)
    f = np.asarray(modes.frequencies)
    phi = np.asarray(modes.shapes)
    assert f[0] > 1.0  # every member held
    # a rotational-axial mode can be nearly a planet mode (the planets' tilt about e_zeta,
    # central amplitudes ~1e-4): classify_modes types it by its planets' harmonic 0 (the
    # projection on the rotational subspace), not by how little the central members move
    types = jp.classify_modes(modes, model, st)
    # count the groups by frequency here (a tolerance), and the types by what moves
    counts = {}
    for g in ps.frequency_groups(f):
        kind, mult = types[g[0]]
        assert mult == len(g)
        counts.setdefault(kind, []).append(len(g))
    T = jp.ModeType
    assert counts[T.ROTATIONAL_AXIAL] == [1] * 12
    assert counts[T.TRANSLATIONAL_TILTING] == [2] * 12
    assert counts.get(T.PLANET, []) == ([n - 3] * 6 if n > 3 else [])
    assert T.MIXED not in counts
    central = slice(0, 18)
    psi = np.asarray(st.planet_angles)
    for j, (kind, _) in enumerate(types):
        shape = phi[:, j]
        planets = shape[18:].reshape(n, 6)
        scale = np.max(np.abs(shape))
        if kind is T.ROTATIONAL_AXIAL:
            # every planet moves alike in its own frame; the central members neither
            # translate in the plane nor tilt
            np.testing.assert_allclose(planets, planets[[0] * n], atol=1e-7 * scale)
            assert np.max(np.abs(shape.reshape(-1, 6)[:3][:, [0, 1, 3, 4]])) < 1e-7 * scale
            assert np.max(np.abs(shape.reshape(-1, 6)[:3][:, [2, 5]])) > 1e-9 * scale
        elif kind is T.PLANET:
            # the central members still; the planets' motions (each in its own frame) have no
            # harmonic 0 nor 1 around the stage: sum p_n = sum p_n exp(i psi_n) = 0
            assert np.max(np.abs(shape[central])) < 1e-7 * scale
            for h in (np.ones(n), np.cos(psi), np.sin(psi)):
                np.testing.assert_allclose(h @ planets, 0.0, atol=1e-7 * scale)
        else:
            # translational-tilting: the central members neither turn nor move axially, and
            # the planets' motions are of harmonic 1 only: p_n = a cos psi_n + b sin psi_n
            assert np.max(np.abs(shape.reshape(-1, 6)[:3][:, [2, 5]])) < 1e-7 * scale
            basis = np.stack([np.cos(psi), np.sin(psi)], -1)
            fit = basis @ np.linalg.lstsq(basis, planets, rcond=None)[0]
            np.testing.assert_allclose(planets, fit, atol=1e-7 * scale)


def test_helical_statics_under_sun_torque():
    """Ring held, carrier held in rotation, sun torque T: each sun mesh carries
    F = T / (N r_bs cos beta) along the tooth normal, the sun's axial bearing takes
    N F sin beta = T tan beta / r_bs, the ring's the opposite, each planet's pin a tilting
    moment F sin beta (r_wr - r_ws) about e_eta; the sun and carrier do not tilt."""
    n, beta, torque = 4, np.radians(25.0), 300.0
    st = stage(n=n, beta=beta, width=0.0)
    model = jp.SpatialPlanetary()
    k = np.asarray(model.stiffness_matrix(st))
    names = model.dof_names(st)
    f = np.zeros(k.shape[0])
    f[names.index("u_s")] = torque / R_S
    q = np.linalg.solve(k, f)
    v_s, v_r = (np.asarray(v) for v in model.mesh_deflection_rows(st))
    force = K_MESH * (v_s @ q)
    expected = torque / (n * R_S * np.cos(beta))
    np.testing.assert_allclose(force, expected, rtol=1e-9)
    np.testing.assert_allclose(K_MESH * (v_r @ q), expected, rtol=1e-9)  # planets turn freely
    sun_axial = float(st.sun.axial_stiffness) * q[names.index("z_s")]
    np.testing.assert_allclose(sun_axial, -torque * np.tan(beta) / R_S, rtol=1e-9)
    ring_axial = float(st.ring.axial_stiffness) * q[names.index("z_r")]
    np.testing.assert_allclose(ring_axial, torque * np.tan(beta) / R_S, rtol=1e-9)
    for name in ("theta_x_s", "theta_y_s", "theta_x_c", "theta_y_c", "z_c"):
        assert abs(q[names.index(name)]) < 1e-9 * np.max(np.abs(q))
    r_wp = R_P / np.cos(A)
    for i in range(n):
        e_eta = np.array([-np.sin(st.planet_angles[i]), np.cos(st.planet_angles[i])])
        carrier_tilt = e_eta @ q[[names.index("theta_x_c"), names.index("theta_y_c")]]
        pin = float(st.planet.tilt_stiffness[1]) * (
            carrier_tilt - q[names.index(f"theta_eta_{i + 1}")]
        )
        np.testing.assert_allclose(pin, -expected * np.sin(beta) * 2 * r_wp, rtol=1e-9)


def test_free_stage_stiffness_is_psd_with_its_rigid_motions():
    st = stage(n=4, held=False, angles=np.array([0.2, 1.9, 3.3, 4.9]))
    model = jp.SpatialPlanetary()
    k = np.asarray(model.stiffness_matrix(st))
    np.testing.assert_allclose(k, k.T, rtol=0, atol=1e-12 * np.max(np.abs(k)))
    lam = np.linalg.eigvalsh(0.5 * (k + k.T))
    assert lam[0] > -1e-12 * lam[-1]
    # the planar model's free motions (Lin & Parker's, checked as independent code), the three
    # out-of-plane motions of the whole stage (z, tilts), and the screw motions of the sun and
    # the ring along their helices (z with u = -z tan beta_b on the sun, +z tan beta_b on the
    # ring: no mesh compresses)
    planar = np.asarray(jp.PlanarPlanetary().stiffness_matrix(st))
    lp = np.linalg.eigvalsh(planar)
    null = int(np.sum(lam < 1e-10 * lam[-1]))
    assert null == int(np.sum(lp < 1e-10 * lp[-1])) + 3 + 2
    assert lam[null] > 1e-6 * lam[-1]
    names = model.dof_names(st)
    psi = np.asarray(st.planet_angles)

    def rigid(d, w):
        """the whole stage moving as one body: translation d, small rotation w (rad)."""
        q = np.zeros(len(names))
        for tag, r in (("c", R_C), ("r", R_R), ("s", R_S)):
            q[[names.index(f"{c}_{tag}") for c in ("x", "y", "z")]] = d
            q[[names.index(f"theta_{c}_{tag}") for c in "xy"]] = w[:2]
            q[names.index(f"u_{tag}")] = r * w[2]
        for i, p in enumerate(psi):
            axes = np.array([[np.cos(p), np.sin(p), 0], [-np.sin(p), np.cos(p), 0], [0, 0, 1]])
            centre = d + np.cross(w, R_C * axes[0])
            q[[names.index(f"{c}_{i + 1}") for c in ("zeta", "eta", "z")]] = axes @ centre
            q[[names.index(f"theta_{c}_{i + 1}") for c in ("zeta", "eta")]] = axes[:2] @ w
            q[names.index(f"u_{i + 1}")] = R_P * w[2]
        return q

    for d, w in [
        ((1, 0, 0), (0, 0, 0)),
        ((0, 1, 0), (0, 0, 0)),
        ((0, 0, 1), (0, 0, 0)),
        ((0, 0, 0), (1, 0, 0)),
        ((0, 0, 0), (0, 1, 0)),
        ((0, 0, 0), (0, 0, 1)),
    ]:
        q = rigid(np.array(d, float), np.array(w, float))
        assert np.linalg.norm(k @ q) < 1e-9 * np.max(np.abs(k)) * np.linalg.norm(q)
    tan = np.tan(float(st.helix_angle))
    for tag, sign in (("s", -1.0), ("r", 1.0)):
        q = np.zeros(len(names))
        q[names.index(f"z_{tag}")] = 1.0
        q[names.index(f"u_{tag}")] = sign * tan
        assert np.linalg.norm(k @ q) < 1e-9 * np.max(np.abs(k)) * np.linalg.norm(q)
        q[names.index(f"u_{tag}")] = -sign * tan  # the other hand: not free
        assert np.linalg.norm(k @ q) > 1e-3 * np.max(np.abs(k)) * np.linalg.norm(q)


def test_stiffness_is_the_second_derivative_of_the_potential_energy():
    """V(q) written from the rigid-body kinematics in the carrier frame: a point at rho of a
    member moves by d + theta x rho; a mesh's deflection across the face delta(s) = delta_0 +
    delta_1 s, its energy (k / b) int delta^2 ds / 2 = k (delta_0^2 + delta_1^2 b^2 / 12) / 2;
    K_ij = V(e_i + e_j) - V(e_i) - V(e_j) (V quadratic)."""
    psi = np.array([0.1, 1.7, 3.0, 4.6])
    k_s, k_r = np.array([5e8, 4e8, 6e8, 4.5e8]), np.array([3.6e8, 4.8e8, 3.2e8, 4e8])
    st = stage(angles=psi, beta=np.radians(-15.0), k_mesh=k_s, k_ring=k_r)
    beta, b = float(st.helix_angle), float(st.face_width)
    centrals = (st.carrier, st.ring, st.sun)
    p = st.planet
    ez = np.array([0.0, 0.0, 1.0])

    def frame(ang):
        return np.array([np.cos(ang), np.sin(ang), 0.0]), np.array([-np.sin(ang), np.cos(ang), 0])

    def body(q, j):
        """(translation, rotation) of member j in the carrier frame, each (batch, 3)."""
        c = q[:, 6 * j : 6 * j + 6]
        if j < 3:
            r = float(centrals[j].base_radius)
            return c[:, :3], np.stack([c[:, 3], c[:, 4], c[:, 5] / r], -1)
        e1, e2 = frame(psi[j - 3])
        d = np.outer(c[:, 0], e1) + np.outer(c[:, 1], e2) + np.outer(c[:, 2], ez)
        return d, np.outer(c[:, 3], e1) + np.outer(c[:, 4], e2) + np.outer(c[:, 5] / R_P, ez)

    def point(q, j, rho):
        d, w = body(q, j)
        return d + np.cross(w, rho)

    def energy(q):
        v = np.zeros(q.shape[0])
        for j, mem in enumerate(centrals):
            kb = np.concatenate(
                [
                    np.asarray(mem.bearing_stiffness),
                    [float(mem.axial_stiffness)],
                    np.asarray(mem.tilt_stiffness),
                    [float(mem.torsional_u)],
                ]
            )
            v += 0.5 * (q[:, 6 * j : 6 * j + 6] ** 2) @ kb
        kp = np.asarray(p.bearing_stiffness)
        kt = np.asarray(p.tilt_stiffness)
        for i, ang in enumerate(psi):
            j = 3 + i
            e1, e2 = frame(ang)
            gap = point(q, 0, R_C * e1) - body(q, j)[0]
            v += 0.5 * (
                kp[0] * (gap @ e1) ** 2
                + kp[1] * (gap @ e2) ** 2
                + float(p.axial_stiffness) * (gap @ ez) ** 2
            )
            tilt = body(q, 0)[1] - body(q, j)[1]
            v += 0.5 * (kt[0] * (tilt @ e1) ** 2 + kt[1] * (tilt @ e2) ** 2)
            for c, r_c, line, sz, side, km in (
                (2, R_S, ang - A, 1.0, -1.0, k_s[i]),
                (1, R_R, ang + A, -1.0, 1.0, k_r[i]),
            ):
                n = np.array(
                    [-np.cos(beta) * np.sin(line), np.cos(beta) * np.cos(line), sz * np.sin(beta)]
                )
                rho_c, rho_p = r_c / np.cos(A) * e1, side * R_P / np.cos(A) * e1
                d0 = (point(q, c, rho_c) - point(q, j, rho_p)) @ n
                d1 = (point(q, c, rho_c + ez) - point(q, j, rho_p + ez)) @ n - d0
                v += 0.5 * km * (d0**2 + d1**2 * b**2 / 12.0)
        return v

    size = 6 * 7
    eye = np.eye(size)
    single = energy(eye)
    pairs = energy((eye[:, None, :] + eye[None, :, :]).reshape(-1, size)).reshape(size, size)
    ref = pairs - single[:, None] - single[None, :]
    k = np.asarray(jp.SpatialPlanetary().stiffness_matrix(st))
    np.testing.assert_allclose(k, ref, rtol=0, atol=1e-12 * np.max(np.abs(ref)))


def test_spatial_inputs_are_refused_in_one_line():
    with pytest.raises(ValueError, match="helix_angle"):
        stage(beta=2.0)
    with pytest.raises(ValueError, match="face_width"):
        stage(width=-1e-3)
    with pytest.raises(ValueError, match="axial_stiffness"):
        jp.PlanetaryMember(1.0, 1.0, 0.1, 0.0, 0.0, -1.0)
    with pytest.raises(ValueError, match="tilt_stiffness"):
        jp.PlanetaryMember(1.0, 1.0, 0.1, 0.0, 0.0, 0.0, (1.0, -1.0))


def _lumped_case(**planetary):
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["planetary"].update(planetary)
    return data


def test_case_keys_build_the_helical_stage():
    data = _lumped_case(helix_angle_deg=-18.0, face_width_mm=40.0)
    data["planetary"]["sun"].update(
        axial_N_per_um=50.0, tilt_Nm_per_rad=2e6, diametral_inertia_kg_m2=3e-4
    )
    data["planetary"]["planet"].update(pin_axial_N_per_um=80.0, pin_tilt_Nm_per_rad=4e5)
    case = jio.parse_train(data)
    st = case.form.spec.stage(case)
    assert float(st.helix_angle) == pytest.approx(np.radians(-18.0), rel=1e-12)
    assert float(st.face_width) == pytest.approx(0.04, rel=1e-12)
    assert float(st.sun.axial_stiffness) == pytest.approx(5e7, rel=1e-12)
    np.testing.assert_allclose(st.sun.tilt_stiffness, [2e6, 2e6], rtol=1e-12)
    assert float(st.sun.tilt_inertia) == pytest.approx(3e-4, rel=1e-12)
    assert float(st.ring.tilt_inertia) == pytest.approx(0.5 * float(st.ring.polar_inertia))
    assert float(st.planet.axial_stiffness) == pytest.approx(8e7, rel=1e-12)
    np.testing.assert_allclose(st.planet.tilt_stiffness, [4e5, 4e5], rtol=1e-12)
    # without the new keys: a spur stage, no axial or tilting support
    case0 = jio.parse_train(_lumped_case())
    st0 = case0.form.spec.stage(case0)
    assert float(st0.helix_angle) == 0.0 and float(st0.sun.axial_stiffness) == 0.0


@pytest.mark.parametrize(
    ("where", "key", "value", "words"),
    [
        (None, "helix_angle_deg", 95.0, "[planetary] helix_angle_deg = 95: out of range"),
        (None, "face_width_mm", -1.0, "[planetary] face_width_mm = -1: out of range"),
        ("sun", "axial_N_per_um", -2.0, "[planetary.sun] axial_N_per_um = -2: out of range"),
        (
            "planet",
            "pin_tilt_Nm_per_rad",
            -1.0,
            "[planetary.planet] pin_tilt_Nm_per_rad = -1: out of range",
        ),
    ],
)
def test_bad_spatial_keys_are_one_line(where, key, value, words):
    data = _lumped_case()
    (data["planetary"] if where is None else data["planetary"][where])[key] = value
    with pytest.raises(Exception) as err:
        jio.parse_train(data)
    text = str(err.value)
    assert words in text and "\n" not in text, text


def test_load_sharing_on_the_3d_model_at_beta_zero_is_the_planar_one():
    """load_sharing takes the 3D model: with pin errors and beta_b = 0 its mesh forces are the
    planar model's (the planes decouple)."""
    errors = np.array([20e-6, 0.0, -5e-6, 0.0])
    st = stage(n=4, beta=0.0, angles=np.array([0.0, 1.4, 3.3, 4.9]))
    planar = jp.load_sharing(jp.PlanarPlanetary(), st, 300.0, errors)
    spatial = jp.load_sharing(jp.SpatialPlanetary(), st, 300.0, errors)
    np.testing.assert_allclose(spatial.sun_mesh_forces, planar.sun_mesh_forces, rtol=1e-9)
    np.testing.assert_allclose(spatial.ring_mesh_forces, planar.ring_mesh_forces, rtol=1e-9)
    assert float(planar.k_gamma) > 1.05  # the errors do unshare the planets


# -- the contact solve (planetary_quasi_static) on the 3D model ---------------------------------


def _with_supports(st, beta_b, axial, tilt):
    """A stage of tests/_planetary_stage.py made 3D: base helix angle beta_b, the face width of
    its gears, every member's axial (N/m) and tilting (N m/rad) support."""
    rep = dataclasses.replace
    kw = {"axial_stiffness": axial, "tilt_stiffness": tilt}
    return rep(st, helix_angle=beta_b, face_width=ps.WIDTH, sun=rep(st.sun, **kw),
               ring=rep(st.ring, **kw), carrier=rep(st.carrier, **kw),
               planet=rep(st.planet, **kw))


@pytest.fixture(scope="module")
def helical():
    """19/17/-53, 3 planets, beta = 15 deg, Uniform k0, 6 slices per contact line; the 3D stage
    with stiff and with soft axial and tilting supports."""
    geo = ps.geometry(**ps.SEQ, helix=np.radians(15.0))
    st = ps.stage(geo, 3)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0), n_slices=6)
    beta_b = abs(float(geo.sun_planet.base_helix_angle))
    return (geo, meshes, _with_supports(st, beta_b, ps.HELD, ps.HELD),
            _with_supports(st, beta_b, 2e8, 2e5))


# default tier: tests/test_planetary_spatial.py::test_helical_k_gamma_with_one_pin_error_against_a_spring_model (the 3D contact solve against a spring model) and tests/test_planetary_spatial.py::test_load_sharing_on_the_3d_model_at_beta_zero_is_the_planar_one
@pytest.mark.slow
def test_contact_solve_at_beta_zero_is_the_planar_one():
    """Spur stage (19/17/-53, 2 slices per line so that the cells spread over the face), stiff
    axial and tilting supports, a pin error: the 3D model's mesh forces, TE and K_gamma over the
    period are the planar model's (the planes decouple; asserted 1e-9)."""
    geo = ps.geometry(**ps.SEQ)
    st = _with_supports(ps.stage(geo, 3), 0.0, ps.HELD, ps.HELD)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0), n_slices=2)
    x = np.asarray(meshes.positions(12))
    errors = np.array([15e-6, 0.0, -4e-6])
    spatial = jp.planetary_quasi_static(jp.SpatialPlanetary(), st, meshes, np.asarray(800.0), x,
                                        errors)
    # the planar model on one slice per line (a spur line's slices share its load evenly: the
    # planar solve does not depend on them) at the same 12 travels: the compiled solve of
    # tests/test_planetary_mesh.py's planar tests
    whole = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0))
    planar = jp.planetary_quasi_static(jp.PlanarPlanetary(), st, whole, np.asarray(800.0), x,
                                       errors)
    assert np.all(np.asarray(spatial.result) == 0)
    for name in ("sun_mesh_forces", "ring_mesh_forces", "sun_te", "ring_te", "k_gamma"):
        a, b = np.asarray(getattr(spatial, name)), np.asarray(getattr(planar, name))
        np.testing.assert_allclose(a, b, rtol=1e-9, atol=1e-9 * np.abs(b).max())
    assert float(planar.k_gamma_max) > 1.05


def test_constant_meshes_over_the_face_are_the_lumped_3d_stiffness():
    """ConstantMeshes(face_points=2) on the 3D model, every mesh loaded, is load_sharing with
    its stiffness matrix (the mesh spread over the face, Gauss points +-b/(2 sqrt 3)): the same
    coordinates, and transverse mesh forces cos beta_b times its normal ones (1e-9)."""
    errors = np.array([20e-6, 0.0, -5e-6, 0.0])
    st = stage(n=4)
    model = jp.SpatialPlanetary()
    want = jp.load_sharing(model, st, 300.0, errors)
    got = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(face_points=2),
                                    np.asarray(300.0), np.array([0.0, 1e-3]), errors)
    c = np.cos(BETA)
    for i in range(2):
        # (the planets' rotation spring FLOATING_PLANET of the contact solve: ~1e-10 here)
        np.testing.assert_allclose(got.sun_mesh_forces[i], c * want.sun_mesh_forces, rtol=1e-9)
        np.testing.assert_allclose(got.ring_mesh_forces[i], c * want.ring_mesh_forces,
                                   rtol=1e-9)
        np.testing.assert_allclose(got.displacement[i], want.displacement, rtol=1e-9,
                                   atol=1e-10 * np.abs(want.displacement).max())


def _lines(s, g_alpha, p_b):
    """Contact lines on [0, g_alpha] of a mesh whose lines sit at s + i p_b (any i)."""
    s0 = np.mod(s, p_b)
    return sum(((s0 + i * p_b >= 0.0) & (s0 + i * p_b <= g_alpha)).astype(float)
               for i in range(-3, 8))


def test_helical_k_gamma_with_one_pin_error_against_a_spring_model(helical):
    """A 15 um tangential error on planet 1's pin, beta = 15 deg, stiff supports: a series-spring
    model written here, each mesh's transverse stiffness cos^2 beta_b k0 sum l over the cells in
    contact, the lines counted slice by slice on the helical layout (slice j's lines at s = x -
    gamma p_b - z_j tan beta_b + i p_b), rigid centres and pins: F_j = k_j (u_s - e_j (cos a_s +
    cos a_r)), k_j = k_sn k_rn / (k_sn + k_rn), sum F_j = T / r_bs. The 3D model's K_gamma within
    1 % at every position."""
    geo, meshes, stiff, _ = helical
    sp, pr = geo.sun_planet, geo.planet_ring
    p_b, beta_b = float(sp.base_pitch), float(stiff.helix_angle)
    slices = 6
    z = (np.arange(slices) + 0.5) * ps.WIDTH / slices
    length = ps.WIDTH / slices / np.cos(beta_b)
    g_s, g_r = np.asarray(meshes.sun_phases), np.asarray(meshes.ring_phases)
    off = float(meshes.ring_offset)
    errors = np.array([15e-6, 0.0, 0.0])
    torque = 1000.0
    c = np.cos(geo.sun_pressure_angle) + np.cos(geo.ring_pressure_angle)
    r_s = float(sp.base_radii[0])
    x = np.asarray(meshes.positions(6))
    k_hand = []
    for xi in x:
        k = []
        for shift, g_alpha in ((xi - g_s * p_b, sp.path_of_contact),
                               (xi + off - g_r * p_b, pr.path_of_contact)):
            n_lines = sum(_lines(shift - zj * np.tan(beta_b), float(g_alpha), p_b) for zj in z)
            k.append(np.cos(beta_b) ** 2 * ps.K0 * length * n_lines)
        k = k[0] * k[1] / (k[0] + k[1])
        u_s = (torque / r_s + np.sum(k * errors * c)) / np.sum(k)
        f = k * (u_s - errors * c)
        assert f.min() > 0
        k_hand.append(f.max() / f.mean())
    k_hand = np.array(k_hand)
    assert k_hand.max() > 1.1
    got = jp.planetary_quasi_static(jp.SpatialPlanetary(), stiff, meshes, np.asarray(torque), x,
                                    errors)
    np.testing.assert_allclose(got.k_gamma, k_hand, rtol=1e-2)


def test_helical_axial_force_balance_per_member(helical):
    """Soft axial and tilting supports, beta = 15 deg, a pin error: on each member the helical
    meshes' axial components (the transverse forces times tan beta_b, with the sign of the
    normal's axial part: + on the sun, - on the ring) equal its bearing's reaction; each pin's
    axial force, written from the carrier's point r_c e_zeta less the planet centre, equals the
    planet's meshes' and the carrier's bearing takes the pins' sum (1e-9 of the axial load)."""
    geo, meshes, _, soft = helical
    model = jp.SpatialPlanetary()
    x = np.asarray(meshes.positions(6))
    got = jp.planetary_quasi_static(model, soft, meshes, np.asarray(1000.0), x,
                                    np.array([15e-6, 0.0, 0.0]))
    assert np.all(np.asarray(got.result) == 0)
    tan = np.tan(float(soft.helix_angle))
    names = model.dof_names(soft)
    q = np.asarray(got.displacement)
    f_s, f_r = np.asarray(got.sun_mesh_forces), np.asarray(got.ring_mesh_forces)
    scale = tan * f_s.sum(1)
    k_z = float(soft.sun.axial_stiffness)  # every member's (and pin's) the same here

    def close(a, b):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-9 * scale.max())

    close(k_z * q[:, names.index("z_s")], -tan * f_s.sum(1))
    close(k_z * q[:, names.index("z_r")], tan * f_r.sum(1))
    pins = []
    r_c = float(soft.carrier.base_radius)
    for i, p in enumerate(np.asarray(soft.planet_angles)):
        pin = k_z * (q[:, names.index("z_c")] + r_c * (np.sin(p) * q[:, names.index("theta_x_c")]
                     - np.cos(p) * q[:, names.index("theta_y_c")]) - q[:, names.index(f"z_{i + 1}")])
        close(pin, tan * (f_r[:, i] - f_s[:, i]))
        pins.append(pin)
    close(k_z * q[:, names.index("z_c")], -np.sum(pins, 0))
    assert np.abs(q[:, names.index("z_s")]).max() > 1e-7  # a real axial motion


def test_face_load_factor_of_a_tilted_mesh_against_the_iso_linear_distribution():
    """ConstantMeshes(face_points=2) on the 3D model, soft tilting supports: each mesh's K_Hbeta
    against ISO 6336-1's linear distribution written here, 1 + F_beta_y c / (2 F_m / b), with the
    misalignment across the face F_beta_y = b |d delta / dz| from the members' relative tilt
    (rigid-body kinematics: a point at rho + z e_z moves by d + w x (rho + z e_z), so the
    normal deflection's slope is n . ((w_central - w_planet) x e_z)) and F_m / b = F_n / b,
    c b = k (1e-9). The supports stiffened 10^4 times, K_Hbeta -> 1."""
    # four planets at two travels: the previous test's shapes (one compiled program)
    st = stage(n=4, k_ring=6.5e8)
    model = jp.SpatialPlanetary()
    got = jp.planetary_quasi_static(model, st, jp.ConstantMeshes(face_points=2),
                                    np.asarray(300.0), np.array([0.0, 1e-3]), np.zeros(4))
    q = np.asarray(got.displacement[0])
    b, beta = float(st.face_width), float(st.helix_angle)
    ez = np.array([0.0, 0.0, 1.0])
    names = model.dof_names(st)
    k_s, k_r = (np.broadcast_to(np.asarray(v), (4,)) for v in st.mesh_stiffnesses())
    want = []
    for central, tag, sz, k, f_t in (("s", "s", 1.0, k_s, got.sun_mesh_forces[0]),
                                     ("r", "r", -1.0, k_r, got.ring_mesh_forces[0])):
        for i, p in enumerate(np.asarray(st.planet_angles)):
            e1 = np.array([np.cos(p), np.sin(p), 0.0])
            e2 = np.array([-np.sin(p), np.cos(p), 0.0])
            line = p - A if central == "s" else p + A
            n = np.array([-np.cos(beta) * np.sin(line), np.cos(beta) * np.cos(line),
                          sz * np.sin(beta)])
            w_c = np.array([q[names.index(f"theta_x_{tag}")], q[names.index(f"theta_y_{tag}")],
                            0.0])
            w_p = (q[names.index(f"theta_zeta_{i + 1}")] * e1
                   + q[names.index(f"theta_eta_{i + 1}")] * e2)
            slope = n @ np.cross(w_c - w_p, ez)  # the spin about e_z: no slope across the face
            f_n = float(f_t[i]) / np.cos(beta)
            want.append(1.0 + b * abs(slope) * k[i] / (2.0 * f_n))
    want = np.array(want)
    assert want.max() > 1.05 and want.max() < 2.0  # tilted, every Gauss point loaded
    np.testing.assert_allclose(got.k_h_beta, want, rtol=1e-9)  # constant meshes: both travels alike
    stiff = dataclasses.replace(
        st, **{m: dataclasses.replace(getattr(st, m),
                                      tilt_stiffness=1e4 * getattr(st, m).tilt_stiffness,
                                      axial_stiffness=1e4 * getattr(st, m).axial_stiffness)
               for m in ("sun", "ring", "carrier", "planet")})
    held = jp.planetary_quasi_static(model, stiff, jp.ConstantMeshes(face_points=2),
                                     np.asarray(300.0), np.array([0.0, 1e-3]), np.zeros(4))
    assert np.asarray(held.k_h_beta).max() < 1.0 + 0.01 * (want.max() - 1.0)


def test_a_tilting_member_turning_with_the_carrier_whirls_as_a_spinning_disc():
    """The sun unmeshed (sun mesh stiffness 0) on its isotropic tilting bearing k_t, turning
    with the carrier at Omega: in the inertial frame a disc spinning at Omega whirls at
    omega = (+-J Omega + sqrt(J^2 Omega^2 + 4 I_d k_t)) / (2 I_d) (forward, backward: the
    classic rotor on tilting springs); in the carrier frame the forward whirl is seen at
    omega_f - Omega, the backward at omega_b + Omega. campbell's 3D frequencies hold both."""
    st = stage(n=3, k_mesh=0.0)
    omega = 500.0
    f = np.asarray(jp.campbell(jp.SpatialPlanetary(), st, np.array([omega])))[0]
    i_d, j, k_t = float(st.sun.tilt_inertia), float(st.sun.polar_inertia), 1e6
    root = np.sqrt((j * omega) ** 2 + 4 * i_d * k_t)
    w_f, w_b = (j * omega + root) / (2 * i_d), (-j * omega + root) / (2 * i_d)
    for w in (abs(w_f - omega), w_b + omega):
        hz = w / (2 * np.pi)
        assert np.min(np.abs(f - hz)) < 1e-9 * hz, (hz, f[np.argmin(np.abs(f - hz))])
    # without the rotating frame's terms the pair would sit at sqrt(k_t / I_d) -+ Omega
    plain = np.sqrt(k_t / i_d)
    assert np.min(np.abs(f - (plain - omega) / (2 * np.pi))) > 1e-3 * plain / (2 * np.pi)


def test_jaxgear_modes_lists_the_3d_modes_of_a_helical_stage(tmp_path):
    """`jaxgear modes` on a helical lumped stage (three equally spaced planets) adds the 3D
    model's modes: 6 (3 + N) of them with Eritenel & Parker's structure for N = 3 (no planet
    modes, N - 3 = 0: 12 rotational-axial modes and 12 translational-tilting pairs), beside the
    planar ones; a spur stage lists no 3D modes."""
    data = _lumped_case(helix_angle_deg=20.0, face_width_mm=30.0)
    for m in ("sun", "ring", "carrier"):
        data["planetary"][m].update(axial_N_per_um=100.0, tilt_Nm_per_rad=1e6)
    data["planetary"]["planet"].update(pin_axial_N_per_um=80.0, pin_tilt_Nm_per_rad=4e5)
    path = tmp_path / "helical.toml"
    path.write_text(case_toml(data))
    assert main(["modes", str(path), "--out", str(tmp_path / "h")]) == 0
    modes = json.loads((tmp_path / "h" / "modes.json").read_text())
    spatial = modes["spatial"]
    assert len(spatial) == 6 * (3 + 3) and len(modes["planar"]) == 3 * (3 + 3)
    kinds = [(m["type"], m["multiplicity"]) for m in spatial]
    assert kinds.count(("rotational-axial", 1)) == 12
    assert kinds.count(("translational-tilting", 2)) == 24
    assert not any(t == "planet" for t, _ in kinds)
    path.write_text(case_toml(_lumped_case()))
    assert main(["modes", str(path), "--out", str(tmp_path / "s")]) == 0
    assert "spatial" not in json.loads((tmp_path / "s" / "modes.json").read_text())


def _helical_case(tmp_path):
    data = _lumped_case(helix_angle_deg=20.0, face_width_mm=30.0)
    for m in ("sun", "ring", "carrier"):
        data["planetary"][m].update(axial_N_per_um=100.0, tilt_Nm_per_rad=1e6)
    data["planetary"]["planet"].update(pin_axial_N_per_um=80.0, pin_tilt_Nm_per_rad=4e5)
    data["planetary"]["tangential_pin_errors_um"] = [10.0, 0.0, 0.0]
    return data


# a first-look step: the sweep warns that it under-resolves the top mode (tests/test_planetary_step_resolution.py)
@pytest.mark.filterwarnings("ignore:.*time step under-resolved")
@pytest.mark.slow  # ~20 s of CPU (modes, Campbell, three solves, two sweeps); properties: above
def test_jaxgear_run_reports_the_3d_load_sharing_face_load_and_sweep(tmp_path, capsys):
    """`jaxgear run` on a helical lumped case (lin-parker-1999 at beta = 20 deg, a 10 um pin
    error, every axial and tilting support given): summary.json's load sharing holds the 3D
    model's K_gamma beside the planar and torsional ones, `face_load` each mesh's K_Hbeta from
    the 3D contact solve (ConstantMeshes at two Gauss points), whose K_gamma is the linear 3D
    solve's (every mesh loaded: 1e-9), and the dynamic-factor sweep runs the 3D model; the
    printed lines name them. Without the supports (a free screw motion along the helices) the
    3D sections are skipped in words and the sweep stays planar; a spur case has neither."""
    data = _helical_case(tmp_path)
    path = tmp_path / "helical.toml"
    path.write_text(case_toml(data))
    assert main(["run", str(path), "--out", str(tmp_path / "h")]) == 0
    text = capsys.readouterr().out
    summary = json.loads((tmp_path / "h" / "summary.json").read_text())
    ls = summary["load_sharing"]
    assert set(ls) >= {"planar", "torsional", "spatial"}
    assert ls["spatial"]["k_gamma"] > 1.01
    fl = summary["face_load"]
    assert fl["k_gamma"] == pytest.approx(ls["spatial"]["k_gamma"], rel=1e-9)
    assert len(fl["k_h_beta"]) == 6 and 1.0 < fl["k_h_beta_max"] < 2.0
    assert summary["dynamics"]["model"].startswith("3D")
    assert ", 3D " in text and "K_Hβ" in text and "3D lumped" in text
    bare = _lumped_case(helix_angle_deg=20.0, face_width_mm=30.0)
    path.write_text(case_toml(bare))
    assert main(["run", str(path), "--out", str(tmp_path / "b"), "--quiet"]) == 0
    summary = json.loads((tmp_path / "b" / "summary.json").read_text())
    assert "spatial" not in summary["load_sharing"] and "skipped" in summary["face_load"]
    assert summary["dynamics"]["model"].startswith("planar")
    path.write_text(case_toml(_lumped_case()))
    assert main(["run", str(path), "--out", str(tmp_path / "s"), "--quiet"]) == 0
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert "spatial" not in summary["load_sharing"] and "face_load" not in summary


def test_the_lumped_models_a_stage_runs(tmp_path):
    """:func:`jaxgear.planetary.lumped_mode_models` and :func:`~jaxgear.planetary.
    lumped_sharing_models` on the stages themselves: a spur stage runs the planar and the
    torsional model, in that order; a helical stage lists the 3D model's modes always, and
    shares its load by it only where its axial and tilting supports hold the load-sharing
    stage (without them the 3D stiffness is singular)."""
    import jaxgear.planetary as jp

    def stages(data):
        case = jio.parse_train(data)
        spec = case.form.spec
        stage = spec.stage(case)
        return stage, spec.sharing_stage(stage)

    def kinds(models):
        return [(name, type(m).__name__) for name, m in models.items()]

    two = [("planar", "PlanarPlanetary"), ("torsional", "TorsionalPlanetary")]
    three = two + [("spatial", "SpatialPlanetary")]
    spur, spur_held = stages(_lumped_case())
    assert kinds(jp.lumped_mode_models(spur)) == two
    assert kinds(jp.lumped_sharing_models(spur_held)) == two
    free, free_held = stages(_lumped_case(helix_angle_deg=20.0, face_width_mm=30.0))
    assert kinds(jp.lumped_mode_models(free)) == three
    assert kinds(jp.lumped_sharing_models(free_held)) == two
    held, held_held = stages(_helical_case(tmp_path))
    assert kinds(jp.lumped_sharing_models(held_held)) == three
    assert jp.LUMPED_MODELS == {"planar": jp.PlanarPlanetary(), "torsional": jp.TorsionalPlanetary()}


def test_the_run_takes_the_3d_model_only_where_its_supports_hold_the_stage(tmp_path):
    """`jaxgear run`'s choice (cli.planetary.spatial_model): a helical stage with every axial and
    tilting support given -> the 3D model; the same without them (each member free to screw
    along its helix: the 3D stiffness of the load-sharing stage singular) or a spur stage ->
    none (the run stays planar)."""
    from jaxgear.cli.planetary import spatial_model

    def choice(data):
        case = jio.parse_train(data)
        spec = case.form.spec
        return spatial_model(spec, spec.stage(case))

    assert isinstance(choice(_helical_case(tmp_path)), jp.SpatialPlanetary)
    assert choice(_lumped_case(helix_angle_deg=20.0, face_width_mm=30.0)) is None
    assert choice(_lumped_case()) is None
