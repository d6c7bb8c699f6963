"""The 3D lumped model of a helical planetary stage (jaxgear.planetary.SpatialPlanetary) in the
carrier-frame dynamics (jaxgear.planetary.planetary_dynamics) and with the gyroscopic moments of the
members' spin relative to the carrier: against a reference written here from the rigid-body
kinematics (its own mass, bearing and pin stiffness, rotating-frame and spin matrices, each cell's
row at its axial position, the lines counted slice by slice, scipy DOP853 between the instants a
line enters or leaves a slice); the spur limit against the planar dynamics; the whirl of a spinning
disc on tilting springs. The Newmark runs are marked slow (a compilation of the 3D model's run
takes ~7 s of CPU); the default tier checks the reference's matrices against the library's and
the spin terms through campbell."""

import dataclasses

import jax
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.linalg import eigh

import _planetary_stage as ps
import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.planetary as jp
from test_planetary_dynamics import _integrate
from test_planetary_spatial import stage as lumped_stage

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0
ZETA = 0.05
EZ = np.array([0.0, 0.0, 1.0])


def spatial_stage(geo, beta_b, axial, tilt, bearing=1e9, pin=5e8):
    """19/17/-53-type stage, 3 planets: ring and carrier held in rotation, every member on
    translational (N/m), axial (N/m) and tilting (N m/rad) supports, the sun free to turn."""
    member = jp.PlanetaryMember
    sp, pr = geo.sun_planet, geo.planet_ring
    r_s, r_p = sp.base_radii
    r_r, a = pr.base_radii[1], geo.center_distance
    kw = {"axial_stiffness": axial, "tilt_stiffness": tilt}
    return jp.PlanetaryStage.equally_spaced(
        3,
        sun=member(1.2, 0.4 * 1.2 * r_s**2, r_s, bearing, 0.0, **kw, diametral_inertia=3e-4),
        ring=member(6.0, 6.0 * r_r**2, r_r, bearing, ps.HELD * r_r**2, **kw),
        carrier=member(5.0, 0.5 * 5.0 * a**2, a, bearing, ps.HELD * a**2, **kw),
        planet=member(0.8, 0.5 * 0.8 * r_p**2, r_p, pin, 0.0, **kw, diametral_inertia=2e-4),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=5e8,
        ring_mesh_stiffness=5e8,
        helix_angle=beta_b,
        face_width=ps.WIDTH,
    )


class Reference:
    """The 3D stage written from the rigid-body kinematics, independently of the library: per
    member (x, y, z, tilt, tilt, u = r_b theta_z) along the carrier frame's axes (central) or
    the planet's (zeta, eta, e_z); a point at rho of a member moves by d + w x rho."""

    def __init__(self, st, geo, meshes, slices, at_pitch=False):
        """``at_pitch``: every cell at its mesh's transverse pitch point (the model before the
        cells had their contact points), to show what the contact points change."""
        self.st, self.geo, self.meshes, self.slices = st, geo, meshes, slices
        self.n = st.n_planets
        self.size = 6 * (3 + self.n)
        self.psi = np.asarray(st.planet_angles)
        self.members = (st.carrier, st.ring, st.sun) + (st.planet,) * self.n
        self.beta = float(st.helix_angle)
        self.k = self._hessian(self._support_energy)
        self.m = np.diag(np.concatenate([
            [float(m.mass)] * 3 + [float(m.tilt_inertia)] * 2
            + [float(m.polar_inertia) / float(m.base_radius) ** 2] for m in self.members]))
        # the cells: (mesh, slice) -> the normal deflection rows at the slice's axial position
        # on the pinion's tangent point and their change per metre of the pinion's roll
        # (the deflection is linear in the point: row(roll) = rows + roll * slopes)
        b = ps.WIDTH
        self.z = (np.arange(slices) + 0.5) * b / slices  # from the face's side, as the cells
        rows = np.zeros((2 * self.n, slices, self.size))
        slopes = np.zeros((2 * self.n, slices, self.size))
        for i in range(self.size):
            q = np.eye(self.size)[i]
            for j, zj in enumerate(self.z):
                rows[:, j, i] = self._mesh_deflections(q, zj - b / 2, 0.0)
                slopes[:, j, i] = self._mesh_deflections(q, zj - b / 2, 1.0) - rows[:, j, i]
        self.rows, self.slopes = rows, slopes
        self.at_pitch = at_pitch

    def frame(self, j):
        if j < 3:
            return np.eye(3)
        p = self.psi[j - 3]
        return np.array([[np.cos(p), -np.sin(p), 0.0], [np.sin(p), np.cos(p), 0.0], [0, 0, 1]])

    def body(self, q, j):
        c = q[6 * j : 6 * j + 6]
        axes = self.frame(j)
        w = axes[:, 0] * c[3] + axes[:, 1] * c[4] + EZ * c[5] / float(self.members[j].base_radius)
        return axes @ c[:3], w

    def point(self, q, j, rho):
        d, w = self.body(q, j)
        return d + np.cross(w, rho)

    def _support_energy(self, q):
        v = 0.0
        for j, mem in enumerate(self.members[:3]):
            kb = np.concatenate([np.asarray(mem.bearing_stiffness), [float(mem.axial_stiffness)],
                                 np.asarray(mem.tilt_stiffness), [float(mem.torsional_u)]])
            v += 0.5 * np.sum(kb * q[6 * j : 6 * j + 6] ** 2)
        p = self.st.planet
        kp = np.concatenate([np.asarray(p.bearing_stiffness), [float(p.axial_stiffness)]])
        kt = np.asarray(p.tilt_stiffness)
        r_c = float(self.st.carrier.base_radius)
        for i in range(self.n):
            axes = self.frame(3 + i)
            gap = self.point(q, 0, r_c * axes[:, 0]) - self.body(q, 3 + i)[0]
            v += 0.5 * np.sum(kp * (axes.T @ gap) ** 2)
            tilt = self.body(q, 0)[1] - self.body(q, 3 + i)[1]
            v += 0.5 * np.sum(kt * (axes[:, :2].T @ tilt) ** 2)
        return v

    def _hessian(self, energy):
        eye = np.eye(self.size)
        one = np.array([energy(e) for e in eye])
        return np.array([[energy(eye[i] + eye[j]) - one[i] - one[j] for j in range(self.size)]
                         for i in range(self.size)])

    def _mesh_deflections(self, q, z, roll):
        """The 2N normal deflections (sun meshes, then ring meshes) at the point of each plane
        of action at the axial position z whose roll distance from the pinion's tangent point
        (the sun's for a sun mesh, the planet's for a ring mesh) is ``roll``: the tangent point
        T on the pinion's base circle, where the line of action touches it, and the unit
        vector from T through the pitch point C (which divides the centre line as the base
        radii do); the point T + roll (C - T) / |C - T| + z e_z."""
        a_s, a_r = self.geo.sun_pressure_angle, self.geo.ring_pressure_angle
        r_c = float(self.st.carrier.base_radius)
        r_p = float(self.st.planet.base_radius)
        out = []
        for central, angle, sz in ((2, a_s, 1.0), (1, a_r, -1.0)):
            r_m = float(self.members[central].base_radius)
            for i, p in enumerate(self.psi):
                line = p - angle if central == 2 else p + angle
                n = np.array([-np.cos(self.beta) * np.sin(line),
                              np.cos(self.beta) * np.cos(line), sz * np.sin(self.beta)])
                e1 = np.array([np.cos(p), np.sin(p), 0.0])
                pitch = r_m / np.cos(angle) * e1
                if central == 2:  # the sun is the pinion: its own tangent point
                    tangent = r_m * np.array([np.cos(line), np.sin(line), 0.0])
                else:  # the planet is the pinion: its tangent point on the ring's side
                    tangent = r_c * e1 + r_p * np.array([np.cos(line), np.sin(line), 0.0])
                u = (pitch - tangent) / np.linalg.norm(pitch - tangent)
                point = tangent + roll * u + z * EZ
                out.append((self.point(q, central, point)
                            - self.point(q, 3 + i, point - r_c * e1)) @ n)
        return np.array(out)

    def rotating(self, omega, v):
        """(C_gyro, K_frame): Omega G + v G_v and -Omega^2 K_Omega + Omega v K_v, from each
        member's rotating-frame equations: a mass m (x'' - 2 Omega y' - Omega^2 x), (y'' +
        2 Omega x' - Omega^2 y); the tilts of a body of diametral inertia I_d and polar J
        spinning at Omega + s v in the frame turning at Omega (Euler): psi = theta_1 + i
        theta_2, I_d psi'' + i (2 I_d Omega - J (Omega + s v)) psi' + (J (Omega + s v) Omega -
        I_d Omega^2) psi; the spin relative to the carrier s v: s = 0 (carrier), -1/r_br (ring),
        1/r_bs (sun), -1/r_bp (planets)."""
        g = np.zeros((self.size, self.size))
        k = np.zeros((self.size, self.size))
        spins = [0.0, -1.0 / float(self.st.ring.base_radius),
                 1.0 / float(self.st.sun.base_radius)] + [
            -1.0 / float(self.st.planet.base_radius)] * self.n
        for j, (mem, s) in enumerate(zip(self.members, spins, strict=True)):
            o = 6 * j
            mass, i_d, i_p = float(mem.mass), float(mem.tilt_inertia), float(mem.polar_inertia)
            g[o, o + 1], g[o + 1, o] = -2 * mass * omega, 2 * mass * omega
            k[o, o] = k[o + 1, o + 1] = -mass * omega**2
            gyro = 2 * i_d * omega - i_p * (omega + s * v)
            g[o + 3, o + 4], g[o + 4, o + 3] = -gyro, gyro
            k[o + 3, o + 3] = k[o + 4, o + 4] = i_p * (omega + s * v) * omega - i_d * omega**2
        return g, k

    def cells(self, x):
        """(K_mesh, force rows (2N, n_dof)) at the mesh travel x: each slice's lines counted
        on the helical layout (s = x - gamma p_b - z tan beta_b + i p_b, plus the ring mesh's
        offset), each cell k0 l along the normal at its contact point (the pinion's roll
        start_roll + s; ``at_pitch``: the pitch point's roll r_b1 tan alpha), the mesh's
        transverse force cos beta_b times the cells' normal forces."""
        sp, pr = self.geo.sun_planet, self.geo.planet_ring
        p_b = float(sp.base_pitch)
        length = ps.WIDTH / self.slices / np.cos(self.beta)
        shifts = np.concatenate([x - np.asarray(self.meshes.sun_phases) * p_b,
                                 x + float(self.meshes.ring_offset)
                                 - np.asarray(self.meshes.ring_phases) * p_b])
        pairs = [sp] * self.n + [pr] * self.n
        k = np.zeros((self.size, self.size))
        force = np.zeros((2 * self.n, self.size))
        for mesh in range(2 * self.n):
            pair = pairs[mesh]
            g_a, start = float(pair.path_of_contact), float(pair.start_roll)
            pitch_roll = float(pair.base_radii[0]) * np.tan(float(pair.operating_pressure_angle))
            for j, zj in enumerate(self.z):
                s0 = np.mod(shifts[mesh] - zj * np.tan(self.beta), p_b)
                for i in range(-3, 8):
                    s = s0 + i * p_b
                    if not 0.0 <= s <= g_a:
                        continue
                    roll = pitch_roll if self.at_pitch else start + s
                    row = self.rows[mesh, j] + roll * self.slopes[mesh, j]
                    k += ps.K0 * length * np.outer(row, row)
                    force[mesh] += np.cos(self.beta) * ps.K0 * length * row
        return k, force

    def mean_cells(self, steps):
        """The cells' stiffness over a period, at the steps' travels (i + 1/2) p_b / steps."""
        p_b = float(self.geo.sun_planet.base_pitch)
        return np.mean([self.cells((i + 0.5) * p_b / steps)[0] for i in range(steps)], axis=0)

    def dynamic_factors(self, omega, v, steps, periods, keep, spin=True):
        """Per-mesh DF (sun meshes, then ring meshes) over the last ``keep`` periods, from the
        library's start (the static state at the travel x0 = p_b / (2 steps), at rest), the same
        modal damping (ZETA on the modes of M and K_b plus the cells' mean stiffness); ``spin``
        False: without the gyroscopic moments of the spin relative to the carrier."""
        lam, phi = eigh(self.k + self.mean_cells(steps), self.m)
        c = self.m @ phi @ np.diag(2 * ZETA * np.sqrt(np.clip(lam, 0, None))) @ phi.T @ self.m
        g, k_frame = self.rotating(omega, v if spin else 0.0)
        f = np.zeros(self.size)
        f[6 * 2 + 5] = TORQUE / float(self.st.sun.base_radius)
        p_b = float(self.geo.sun_planet.base_pitch)
        x0 = 0.5 * p_b / steps
        t_end = periods * p_b / v
        sp, pr = self.geo.sun_planet, self.geo.planet_ring
        shifts = np.concatenate([-np.asarray(self.meshes.sun_phases) * p_b,
                                 float(self.meshes.ring_offset)
                                 - np.asarray(self.meshes.ring_phases) * p_b])
        g_a = [float(sp.path_of_contact)] * self.n + [float(pr.path_of_contact)] * self.n
        cuts = {0.0, t_end}
        for sh, ga in zip(shifts, g_a, strict=True):
            for zj in self.z:
                for edge in (0.0, ga):
                    for i in range(-periods - 8, periods + 8):
                        t = (edge - sh + zj * np.tan(self.beta) + i * p_b - x0) / v
                        if 0.0 < t < t_end:
                            cuts.add(t)
        cuts = np.array(sorted(cuts))

        def kmesh(x):
            k, rows = self.cells(x)
            return k, np.ones(2 * self.n), rows

        peaks = _integrate(self.k + k_frame, c + g, self.m, f, kmesh, x0, v, cuts,
                           t_end - keep * p_b / v, self.size, self.n)
        return peaks / (TORQUE / (self.n * float(self.st.sun.base_radius)))


def test_reference_matrices_are_the_library_ones():
    """The reference's stiffness (bearings and pins from its potential energy) and mass agree
    with the library's 3D model without meshes (1e-9): the two descriptions of one stage."""
    geo = ps.geometry(**ps.SEQ, helix=np.radians(15.0))
    st = spatial_stage(geo, abs(float(geo.sun_planet.base_helix_angle)), 3e8, 4e5)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0), n_slices=2)
    ref = Reference(st, geo, meshes, 2)
    model = jp.SpatialPlanetary()
    bare = dataclasses.replace(st, sun_mesh_stiffness=0.0, ring_mesh_stiffness=0.0)
    k_b = np.asarray(model.stiffness_matrix(bare))
    np.testing.assert_allclose(ref.k, k_b, rtol=0, atol=1e-9 * np.abs(k_b).max())
    np.testing.assert_allclose(ref.m, np.asarray(model.mass_matrix(st)), rtol=1e-12)


def _run(model, st, meshes, omega, steps, periods, keep):
    run = jp.PlanetaryRun(TORQUE, steps_per_period=steps, periods=periods, keep_periods=keep,
                          damping_ratio=ZETA)
    return jp.planetary_dynamics(model, st, meshes, run, jnp.asarray(omega))


@pytest.fixture(scope="module")
def helical():
    geo = ps.geometry(**ps.SEQ, helix=np.radians(15.0))
    beta_b = abs(float(geo.sun_planet.base_helix_angle))
    st = spatial_stage(geo, beta_b, 3e8, 4e5)
    return geo, st


def _against_reference(geo, st, slices, omega, steps, periods, keep):
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0),
                                            n_slices=slices)
    got = _run(jp.SpatialPlanetary(), st, meshes, omega, steps, periods, keep)
    assert int(got.result) == 0 and float(got.sun_mesh_forces.min()) > 0  # every mesh loaded
    df = np.concatenate([np.asarray(d) for d in got.dynamic_factors])
    ref = Reference(st, geo, meshes, slices)
    v = omega * float(st.ring.base_radius)
    return df, ref.dynamic_factors(omega, v, steps, periods, keep), ref


@pytest.mark.slow
def test_helical_dynamics_against_the_reference(helical):
    """beta = 15 deg, 2 slices per line, 600 rad/s carrier speed (mesh frequency 5.06 kHz; the
    rotating frame and the spin terms in both), 384 steps per mesh period, 10 periods from the
    same start, the cells at their contact points in both: per-mesh DF within 2 % (measured
    0.11-0.76 %; with every cell at the pitch point 0.26-0.84 %, 1.0-2.5 % at 128 steps). (The
    spin terms move the reference's DF by 0.1-0.8 % here: campbell's whirl tests below check
    them.) Slow, as every Newmark run of the 3D model: its compilation alone takes ~7 s."""
    geo, st = helical
    df, want, ref = _against_reference(geo, st, 2, 600.0, 384, 10, 2)
    np.testing.assert_allclose(df, want, rtol=0.02)
    assert df.max() > 1.5  # a real dynamic response (DF 2.2 on the sun meshes)


@pytest.mark.slow
def test_spur_limit_of_the_3d_dynamics_is_the_planar_dynamics():
    """beta_b = 0, stiff axial and tilting supports, 2 slices per line, 600 rad/s: the 3D model's
    mesh forces and planar coordinates over the kept steps are the planar model's (1e-6; the
    planes decouple, the spin moments act on the tilts alone)."""
    geo = ps.geometry(**ps.SEQ)
    st = spatial_stage(geo, 0.0, ps.HELD, ps.HELD)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0), n_slices=2)
    planar = _run(jp.PlanarPlanetary(), st, meshes, 600.0, 48, 4, 2)
    spatial = _run(jp.SpatialPlanetary(), st, meshes, 600.0, 48, 4, 2)
    assert int(planar.result) == 0 and int(spatial.result) == 0
    for name in ("sun_mesh_forces", "ring_mesh_forces"):
        a, b = np.asarray(getattr(spatial, name)), np.asarray(getattr(planar, name))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-6 * np.abs(b).max())
    t = np.asarray(jp.SpatialPlanetary().reduction(st))
    q3, q2 = np.asarray(spatial.displacement) @ t.T, np.asarray(planar.displacement)
    np.testing.assert_allclose(q3, q2, rtol=0, atol=1e-6 * np.abs(q2).max())
    assert np.ptp(np.asarray(planar.sun_mesh_forces)) > 0.1 * float(planar.static_force)


def _whirl(j, i_d, k_t, spin):
    """The inertial forward and backward whirl (rad/s) of a disc (polar J, diametral I_d)
    spinning at ``spin`` on isotropic tilting springs k_t: I_d lambda^2 -+ J spin lambda - k_t
    = 0, lambda = (+-J spin + sqrt(J^2 spin^2 + 4 I_d k_t)) / (2 I_d)."""
    root = np.sqrt((j * spin) ** 2 + 4 * i_d * k_t)
    return (j * spin + root) / (2 * i_d), (-j * spin + root) / (2 * i_d)


@pytest.mark.parametrize(("omega", "spin_rel"), [(0.0, 3000.0), (400.0, 1500.0),
                                                  (-300.0, 2000.0)])
def test_a_spinning_member_whirls_forward_and_backward(omega, spin_rel):
    """The sun unmeshed (sun mesh stiffness 0) on its isotropic tilting bearing k_t, the carrier
    at Omega, the mesh travelling at v = r_bs spin_rel (the sun spins at Omega + spin_rel): the
    classic disc on tilting springs whirls at lambda_f, lambda_b (_whirl) in the inertial frame,
    seen from the carrier at |lambda_f - Omega| and lambda_b + Omega. campbell with the mesh
    speed holds both (1e-9); without the spin term (every member turning with the carrier) it
    would not; the pair splits by J (Omega + spin_rel) / I_d."""
    st = lumped_stage(n=3, k_mesh=0.0)
    model = jp.SpatialPlanetary()
    r_s = float(st.sun.base_radius)
    f = np.asarray(jp.campbell(model, st, np.array([omega]), np.array([r_s * spin_rel])))[0]
    i_d, j, k_t = float(st.sun.tilt_inertia), float(st.sun.polar_inertia), 1e6
    w_f, w_b = _whirl(j, i_d, k_t, omega + spin_rel)
    for w in (abs(w_f - omega), w_b + omega):
        hz = w / (2 * np.pi)
        assert np.min(np.abs(f - hz)) < 1e-9 * hz, (hz, f[np.argmin(np.abs(f - hz))])
    np.testing.assert_allclose(w_f - w_b, j * (omega + spin_rel) / i_d, rtol=1e-12)
    plain = np.asarray(jp.campbell(model, st, np.array([omega])))[0]  # spin with the carrier
    w_f0, _ = _whirl(j, i_d, k_t, omega)
    assert np.min(np.abs(plain - abs(w_f0 - omega) / (2 * np.pi))) < 1e-9 * w_f0
    assert np.min(np.abs(plain - abs(w_f - omega) / (2 * np.pi))) > 1e-3 * w_f / (2 * np.pi)


def test_a_planet_tilt_pair_splits_with_the_spin():
    """Equally spaced planets, the planets' tilts held by their pins alone (every mesh spring 0,
    the carrier's tilts 10^12 N m/rad: the pins' base all but still, a coupling ~10^-6): each
    planet is a disc on tilting springs k_t spinning at -v / r_bp relative to the carrier. With
    the carrier still (Omega = 0) its tilt pair, one frequency at rest, splits into the disc's
    forward and backward whirl, J v / (r_bp I_d) apart (2e-6), N times over."""
    base = lumped_stage(n=3, k_mesh=0.0, k_ring=0.0)
    k_t = 5e5
    planet = dataclasses.replace(base.planet, tilt_stiffness=k_t)
    carrier = dataclasses.replace(base.carrier, tilt_stiffness=1e12)
    st = dataclasses.replace(base, planet=planet, carrier=carrier)
    model = jp.SpatialPlanetary()
    r_p = float(st.planet.base_radius)
    i_d, j = float(st.planet.tilt_inertia), float(st.planet.polar_inertia)
    still = np.sqrt(k_t / i_d) / (2 * np.pi)
    f0 = np.asarray(jp.campbell(model, st, np.array([0.0])))[0]
    assert np.sum(np.abs(f0 - still) < 2e-6 * still) == 2 * 3
    v = 200.0  # the planets spin at 8000 rad/s
    f = np.asarray(jp.campbell(model, st, np.array([0.0]), np.array([v])))[0]
    w_f, w_b = _whirl(j, i_d, k_t, -v / r_p)
    got = []
    for w in (abs(w_f), abs(w_b)):
        near = np.abs(f - w / (2 * np.pi)) < 2e-6 * still
        assert np.sum(near) == 3
        got.append(f[near].mean())
    assert abs(w_f - w_b) > 0.1 * abs(w_f)  # a large split: J / I_d = 2 for a thin disc
    np.testing.assert_allclose(abs(got[0] - got[1]) * 2 * np.pi, j * v / r_p / i_d, rtol=2e-5)
