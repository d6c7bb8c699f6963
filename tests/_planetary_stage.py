"""Test helpers: two planetary stages built from real pairs (jaxgear.planetary_geometry), their
lumped members, and the contact lines of a spur mesh counted by hand."""

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxgear as jg

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
    member = jg.PlanetaryMember
    sp, pr = geo.sun_planet, geo.planet_ring
    r_s, r_p = sp.base_radii
    r_r, a = pr.base_radii[1], geo.center_distance
    return jg.PlanetaryStage.equally_spaced(
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
