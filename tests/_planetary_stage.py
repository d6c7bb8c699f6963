"""Test helpers: two planetary stages built from real pairs (jaxgear.planetary_geometry), their
lumped members, and the contact lines of a spur mesh counted by hand."""

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxgear as jg
import jaxgear.planetary as jp

HELD = 1e13  # N/m on a translation or on u = r theta: "rigid"
MODULE, ALPHA_N, WIDTH = 3e-3, np.radians(20.0), 0.03
K0 = 1.4e10  # N/m per m of contact line


def geometry(z_s, z_p, x_s, x_p, helix=0.0):
    z_r = z_s + 2 * z_p
    members = (
        jg.Member(z_s, profile_shift=x_s, face_width=WIDTH),
        jg.Member(z_p, profile_shift=x_p, face_width=WIDTH),
        jg.Member(-z_r, profile_shift=-(x_s + 2 * x_p), face_width=WIDTH),
    )
    return jg.planetary_geometry(*members, MODULE, ALPHA_N, helix)


# 19/17/-53, 3 planets: sequentially phased (19/3 not an integer); odd planet tooth count
SEQ = dict(z_s=19, z_p=17, x_s=0.3, x_p=0.3)
# 20/16/-52, 4 planets: in phase (20/4 = 5); even planet tooth count
INPHASE = dict(z_s=20, z_p=16, x_s=0.2, x_p=0.2)


def stage(geo, n, pin=HELD, sun_bearing=HELD, k_mesh=5e8):
    """Ring and carrier held in rotation and translation, the sun and the planets free to turn."""
    member = jp.PlanetaryMember
    sp, pr = geo.sun_planet, geo.planet_ring
    r_s, r_p = sp.base_radii
    r_r, a = pr.base_radii[1], geo.center_distance
    return jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(1.2, 0.4 * 1.2 * r_s**2, r_s, sun_bearing, 0.0),
        ring=member(6.0, 6.0 * r_r**2, r_r, HELD, HELD * r_r**2),
        carrier=member(5.0, 0.5 * 5.0 * a**2, a, HELD, HELD * a**2),
        planet=member(0.8, 0.5 * 0.8 * r_p**2, r_p, pin, 0.0),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=k_mesh,
        ring_mesh_stiffness=k_mesh,
    )


def lines_in_contact(s, g_alpha, p_b):
    """Spur contact lines on [0, g_alpha] of a mesh whose lines sit at s + i p_b (any i)."""
    s0 = np.mod(s, p_b)
    count = 0
    for i in range(-2, 6):
        si = s0 + i * p_b
        count += (si >= 0.0) & (si <= g_alpha)
    return count


def counted_stiffness(geo, meshes, x):
    """k_sn(x), k_rn(x) (N/m): K0 b times the lines counted by hand at the mesh travel x, the
    sun meshes at x - gamma_s p_b, the ring meshes at x + Delta_rs - gamma_r p_b."""
    sp, pr = geo.sun_planet, geo.planet_ring
    p_b = sp.base_pitch
    g_s = np.asarray(meshes.sun_phases)
    g_r = np.asarray(meshes.ring_phases)
    off = float(meshes.ring_offset)
    n_s = lines_in_contact(x - g_s * p_b, sp.path_of_contact, p_b)
    n_r = lines_in_contact(x + off - g_r * p_b, pr.path_of_contact, p_b)
    return K0 * WIDTH * n_s, K0 * WIDTH * n_r


def with_meshes(st, k_s, k_r):
    """The stage with other constant mesh stiffnesses (N/m, () or (n_planets,))."""
    return eqx.tree_at(lambda s: (s.sun_mesh_stiffness, s.ring_mesh_stiffness), st,
                       (jnp.asarray(k_s, float), jnp.asarray(k_r, float)))


def rigid_path_forces(torque, r_sun, psi, a_s, a_r, k_s, k_r, sun_centre=(0.0, 0.0),
                      ring_centre=(0.0, 0.0), pins=None, mesh_offsets=(0.0, 0.0)):
    """An independent spring model of load sharing, written from the geometry of the forces
    (not from the library's matrices): rigid centres and pins, ring and carrier held, the sun
    free to turn only. Planet j at psi_j (unit vectors r_j outward, t_j counter-clockwise).

    The sun, driving counter-clockwise, pushes planet j along n_j = cos a_s t_j + sin a_s r_j
    (the drive plus the separating radial component, outward); the ring pushes it along
    m_j = cos a_r t_j - sin a_r r_j (its separating component points inward, the ring's
    teeth being outside). Moving a body by a vector d changes a mesh's compression by d along
    the force that body exerts (d . n for the sun, d . m for the ring) and moving the planet by
    p changes both by -p . n, -p . m. So with the sun's toothed centre at ``sun_centre``, the
    ring's at ``ring_centre`` (m, fixed-frame vectors in the carrier frame) and pin j at
    ``pins[j]`` (m, (t, r) components: tangential, radial), path j's offsets are
    c_sj = s . n_j - p_j . n_j and c_rj = g . m_j - p_j . m_j. The planet's moment balance
    k_s (u_s + u_j + c_sj) = k_r (-u_j + c_rj) puts the two meshes in series:
    F_j = k_eq (u_s + c_sj + c_rj), k_eq = k_s k_r / (k_s + k_r), and the sun's
    sum F_j = T / r_s gives u_s = (T / r_s - sum k_eq c) / sum k_eq, c_j = c_sj + c_rj (with
    equal k_eq: F_j = T / (N r_s) + k_eq (c_j - mean c)). ``mesh_offsets`` (c_s, c_r) (m, ()
    or (N,)): further compressions of each path's sun and ring mesh (material on the teeth in
    contact), added to c_sj and c_rj; ``k_s``, ``k_r``: () or (N,).

    Returns:
        (F (N, (N,)), K_gamma = max F / mean F).
    """
    psi = np.asarray(psi, float)
    r = np.stack([np.cos(psi), np.sin(psi)], axis=-1)
    t = np.stack([-np.sin(psi), np.cos(psi)], axis=-1)
    n = np.cos(a_s) * t + np.sin(a_s) * r
    m = np.cos(a_r) * t - np.sin(a_r) * r
    p = np.zeros_like(r) if pins is None else (
        np.asarray(pins)[:, :1] * t + np.asarray(pins)[:, 1:] * r)
    c = (n @ np.asarray(sun_centre) - np.sum(p * n, -1)) + (
        m @ np.asarray(ring_centre) - np.sum(p * m, -1))
    c = c + np.asarray(mesh_offsets[0]) + np.asarray(mesh_offsets[1])
    k_eq = np.broadcast_to(k_s * k_r / (k_s + k_r), c.shape)
    if np.all(k_eq == k_eq[0]):
        forces = torque / (len(psi) * r_sun) + k_eq * (c - c.mean())
    else:
        u_s = (torque / r_sun - np.sum(k_eq * c)) / np.sum(k_eq)
        forces = k_eq * (u_s + c)
    return forces, forces.max() / forces.mean()


# Lin & Parker's example masses, inertias and base radii (sun, ring, carrier, planet), unequal
# pressure angles: the lumped stage of the eccentricity, runout and unbalance tests
A_S, A_R = np.radians(24.6), np.radians(20.0)
R_S, R_R, R_C, R_P = 77.4e-3 / 2, 275.0e-3 / 2, 176.8e-3 / 2, 100.3e-3 / 2
K_MESH = 5e8


def lin_parker_stage(n, ecc=None, unb=None, sun_bearing=HELD, pin=HELD):
    """n equally spaced planets; ring and carrier held (HELD), the pins of stiffness ``pin``,
    the sun free to turn on its bearing ``sun_bearing``; eccentricities ``ecc`` (none by
    default) and unbalances ``unb`` (None)."""
    member = jp.PlanetaryMember.lumped
    return jp.PlanetaryStage.equally_spaced(
        n,
        sun=member(0.4, 0.39, R_S, sun_bearing, 0.0),
        ring=member(2.35, 3.0, R_R, HELD, HELD),
        carrier=member(5.43, 6.29, R_C, HELD, HELD),
        planet=member(0.66, 0.61, R_P, pin, 0.0),
        sun_pressure_angle=A_S,
        ring_pressure_angle=A_R,
        sun_mesh_stiffness=K_MESH,
        ring_mesh_stiffness=K_MESH,
        eccentricities=jp.Eccentricities() if ecc is None else ecc,
        unbalances=unb,
    )


#: the flexible-ring dynamics tests' operating point: sun torque (N m) and planet 1's
#: tangential pin error (m)
RING_TORQUE = 1000.0
RING_PIN_ERRORS = np.array([15e-6, 0.0, 0.0])


def ring_run(st, ring, meshes=None, omega=60.0, periods=6, steps=24, keep=3):
    """planetary_dynamics of stage ``st`` with ``ring`` (planar model, constant meshes unless
    given) at the carrier speed ``omega`` (rad/s), 5 % damping; asserts it succeeded."""
    run = jp.PlanetaryRun(RING_TORQUE, steps_per_period=steps, periods=periods,
                          keep_periods=keep, damping_ratio=0.05,
                          tangential_pin_errors=RING_PIN_ERRORS)
    r = jp.planetary_dynamics(jp.PlanarPlanetary(), st, meshes or jp.ConstantMeshes(), run,
                              jnp.asarray(omega), ring=ring)
    assert int(r.result) == 0
    return r


def mesh_force_error(r, ref) -> float:
    """The largest mesh-force difference over the largest mesh force (-)."""
    got = np.concatenate([r.sun_mesh_forces, r.ring_mesh_forces], axis=1)
    want = np.concatenate([ref.sun_mesh_forces, ref.ring_mesh_forces], axis=1)
    return float(np.max(np.abs(got - want)) / np.max(np.abs(want)))


def frequency_groups(f, rtol=1e-7):
    """Index groups of the sorted frequencies ``f`` that agree within ``rtol`` of the largest."""
    groups, start = [], 0
    for j in range(1, len(f) + 1):
        if j == len(f) or f[j] - f[j - 1] > rtol * f[-1]:
            groups.append(list(range(start, j)))
            start = j
    return groups


def seq_ring_case() -> dict:
    """A small stage (19/17/-53 teeth, m 3 mm, b 30 mm, 3 planets, ring fixed, carrier in) whose
    ring is the embedded coarse test ring, and a 3 um tangential error on planet 1's pin (every
    mesh stays loaded), as a case-file dict."""
    def gear(name, teeth, x):
        return {"name": name, "teeth": teeth, "normal_module_mm": 3.0,
                "normal_pressure_angle_deg": 20.0, "profile_shift": x, "face_width_mm": 30.0}

    member = {"mass_kg": 1.0, "inertia_kg_m2": 1e-3}
    return {
        "name": "seq-flexible-ring",
        "gears": [gear("sun", 19, 0.3), gear("planet", 17, 0.3), gear("ring", -53, -0.9)],
        "mesh": {"stiffness": "iso6336", "positions_per_pitch": 8},
        "operating": {"torque_Nm": 1000.0, "speed_rad_s": 20.0},
        "planetary": {
            "sun_gear": "sun", "planet_gear": "planet", "ring_gear": "ring", "planets": 3,
            "fixed": "ring", "input": "carrier", "tangential_pin_errors_um": [3.0, 0.0, 0.0],
            "sun": {**member, "bearing_N_per_um": 1e4},  # held: a floating sun shares evenly
            "ring": {"mass_kg": 6.0, "inertia_kg_m2": 0.05, "bearing_N_per_um": 1e4,
                     "torsional_stiffness_Nm_per_rad": 1e10, "model": "condensed",
                     "body": "seq-test-ring"},
            "carrier": {**member, "bearing_N_per_um": 1e4},
            "planet": {**member, "pin_radial_N_per_um": 1e4, "pin_tangential_N_per_um": 1e4},
        },
    }


def fourier_orders(signal, n):
    """One-sided harmonics 0..n-1 of ``signal`` (P, m) sampled at the mid-points s = (r+½)/P."""
    s = (np.arange(signal.shape[0]) + 0.5) / signal.shape[0]
    c = np.array([np.mean(signal * np.exp(-2j * np.pi * h * s)[:, None], axis=0)
                  for h in range(n)])
    c[1:] *= 2
    return c
