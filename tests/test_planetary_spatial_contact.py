"""The 3D lumped model's contact cells at their contact points (jaxgear.planetary.SpatialPlanetary
with jaxgear.planetary.ContactMeshes): each cell's spring acts at its own point of the plane of
action (its roll along the line of action and its axial position), so that the members' tilts see
the real moment arms of the contact lines. Checked against a spring model of the contact lines
assembled here from the geometry (tests/test_planetary_spatial_dynamics.py: Reference, its supports
from a potential energy, each cell at the pinion's tangent point plus its roll towards the pitch
point)."""

import copy
import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest

import _planetary_stage as ps
import jaxgear as jg
import jaxgear.planetary as jp
from test_planetary_spatial_dynamics import Reference, spatial_stage

TORQUE = 1000.0
SLICES = 4


@pytest.fixture(scope="module")
def tilting():
    """19/17/-53, 3 planets, beta = 20 deg, Uniform k0, 4 slices per line; every member on
    soft axial (3e8 N/m) and tilting (4e5 N m/rad) supports, so that the planets tilt on their
    pins under the couples of their meshes' axial forces."""
    geo = ps.geometry(**ps.SEQ, helix=np.radians(20.0))
    st = spatial_stage(geo, abs(float(geo.sun_planet.base_helix_angle)), 3e8, 4e5)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0),
                                            n_slices=SLICES)
    return geo, st, meshes


def _hand(ref, x):
    """The reference's linear solve at the mesh travel x: (q, transverse mesh forces)."""
    k_mesh, rows = ref.cells(x)
    f = np.zeros(ref.size)
    f[6 * 2 + 5] = TORQUE / float(ref.st.sun.base_radius)
    q = np.linalg.solve(ref.k + k_mesh, f)
    return q, rows @ q


def _zeta_tilts(model, st):
    """The indices of the tilts about the planets' radial axes and of the central members'."""
    names = model.dof_names(st)
    return [names.index(f"theta_zeta_{i + 1}") for i in range(st.n_planets)] + [
        names.index(f"theta_{a}_{m}") for m in "crs" for a in "xy"]


def test_cell_springs_at_their_contact_points_against_the_contact_lines(tilting):
    """Three mesh travels over a period: the cells' stiffness sum k l V^T V (ContactMeshes'
    rows on the 3D model) against the reference's springs k0 l at each contact point, and the
    mesh forces' rows (1e-9 of the largest entry); with the reference's supports, the linear
    solve under the sun torque agrees (1e-9), and the tilts about the planets' radial axes and
    the central members' differ by more than 10 % from the reference's with every cell at the
    pitch point (the moment arms along the line of action matter)."""
    geo, st, meshes = tilting
    model = jp.SpatialPlanetary()
    p_b = float(geo.sun_planet.base_pitch)
    zero = np.zeros(st.n_planets)
    ref = Reference(st, geo, meshes, SLICES)
    pitch = copy.copy(ref)
    pitch.at_pitch = True

    @eqx.filter_jit
    def rows(x):
        row = meshes.cell_row(model, st, x, (zero, zero))
        kl = jnp.where(row.mask, row.k * row.length, 0.0)
        # (2N, c): each mesh's cells, cos beta_b k l
        force = jax.jacobian(meshes.mesh_forces)(kl) * kl[None, :]
        return jnp.einsum("ci,c,cj->ij", row.V, kl, row.V), force @ row.V

    tilts = _zeta_tilts(model, st)
    f = np.zeros(ref.size)
    f[model.dof_names(st).index("u_s")] = TORQUE / float(st.sun.base_radius)
    for x in np.array([0.13, 0.47, 0.81]) * p_b:
        k_got, f_got = (np.asarray(a) for a in rows(x))
        k_ref, f_ref = ref.cells(x)
        np.testing.assert_allclose(k_got, k_ref, rtol=0, atol=1e-9 * np.abs(k_ref).max())
        np.testing.assert_allclose(f_got, f_ref, rtol=0, atol=1e-9 * np.abs(f_ref).max())
        q = np.linalg.solve(ref.k + k_got, f)
        q_ref, _ = _hand(ref, x)
        np.testing.assert_allclose(q, q_ref, rtol=0, atol=1e-9 * np.abs(q_ref).max())
        q_pitch, _ = _hand(pitch, x)
        assert np.abs(q_ref[tilts] - q_pitch[tilts]).max() > 0.1 * np.abs(q_ref[tilts]).max()


@pytest.mark.slow  # ~7 s of CPU, the 3D contact solve's compilation; rows: the test above
def test_contact_solve_with_cells_at_their_contact_points_against_the_spring_model(tilting):
    """Three mesh travels over a period: the contact solve's coordinates (the members' tilts
    among them) and transverse mesh forces against the reference's linear solve with a spring
    k0 l at each contact point (every cell loaded: unilateral = linear), 1e-9 of the largest."""
    geo, st, meshes = tilting
    model = jp.SpatialPlanetary()
    x = np.array([0.13, 0.47, 0.81]) * float(geo.sun_planet.base_pitch)
    got = jp.planetary_quasi_static(model, st, meshes, np.asarray(TORQUE), x)
    assert np.all(np.asarray(got.result) == 0)
    ref = Reference(st, geo, meshes, SLICES)
    for i, xi in enumerate(x):
        q, forces = _hand(ref, xi)
        np.testing.assert_allclose(np.asarray(got.displacement[i]), q, rtol=0,
                                   atol=1e-9 * np.abs(q).max())
        f_got = np.concatenate([got.sun_mesh_forces[i], got.ring_mesh_forces[i]])
        np.testing.assert_allclose(f_got, forces, rtol=1e-9)


def test_spur_cells_keep_the_planar_solution_whatever_their_points():
    """beta_b = 0: a point moved along the line of action keeps its moment arm about every axis
    that loads the normal (the normal has no axial part): the rows per metre along the line are
    zero, and the contact solve stays the planar model's (tests/test_planetary_spatial.py)."""
    geo = ps.geometry(**ps.SEQ)
    st = spatial_stage(geo, 0.0, ps.HELD, ps.HELD)
    model = jp.SpatialPlanetary()
    x_s, x_r = (np.asarray(x) for x in model.line_rows(st))
    scale = np.abs(np.asarray(model.face_rows(st)[0][0])).max()  # the rows' size, 1
    assert np.abs(x_s).max() < 1e-12 * scale and np.abs(x_r).max() < 1e-12 * scale
    # helical: a point sigma along the line (direction d, the sun's push) loads the normal
    # n = cos b d + sin b e_z through the sun's tilt theta by n . (theta x sigma d) =
    # sigma sin b theta . (d x e_z), over cos b on the transverse-equivalent row
    beta = np.radians(20.0)
    helical = spatial_stage(geo, beta, ps.HELD, ps.HELD)
    x_s = np.asarray(model.line_rows(helical)[0])
    line = np.asarray(helical.planet_angles) - float(helical.sun_pressure_angle)
    names = model.dof_names(helical)
    sun_tilts = [names.index("theta_x_s"), names.index("theta_y_s")]
    np.testing.assert_allclose(x_s[:, sun_tilts],
                               np.tan(beta) * np.stack([np.cos(line), np.sin(line)], -1),
                               rtol=1e-12)
    assert np.abs(np.asarray(jp.PlanarPlanetary().line_rows(st)[0])).max() == 0.0


def test_pitch_points_are_the_pinions_roll_at_the_pitch_point(tilting):
    """ContactMeshes' pitch points: the pinion's roll at the pitch point (r_b1 tan alpha_w: the
    sun's on the sun pair, the planet's on the ring pair) less its start roll, on the path of
    contact."""
    geo, _, meshes = tilting
    for pair, got in zip((geo.sun_planet, geo.planet_ring), np.asarray(meshes.pitch_points),
                         strict=True):
        r_b1, alpha = float(pair.base_radii[0]), float(pair.operating_pressure_angle)
        assert got == pytest.approx(r_b1 * np.tan(alpha) - float(pair.start_roll), rel=1e-12)
        assert 0.0 < got < float(pair.path_of_contact)


def test_a_left_hand_stage_is_the_mirror_of_the_right_hand_one(tilting):
    """The stage mirrored through its mid-plane (z -> -z) turns right-hand planets into left-hand
    ones (helix_angle -beta_b) and leaves every force alone: the cells' stiffness and the linear
    solve under the sun torque give the same transverse mesh forces (1e-9), the axial
    translations and the tilts mirrored (z -> -z; a tilt theta -> (-theta_x, -theta_y))."""
    geo, st, meshes = tilting
    model = jp.SpatialPlanetary()
    left = dataclasses.replace(st, helix_angle=-st.helix_angle)
    zero = np.zeros(st.n_planets)
    x = 0.37 * float(geo.sun_planet.base_pitch)

    @eqx.filter_jit
    def solve(s):
        row = meshes.cell_row(model, s, x, (zero, zero))
        kl = jnp.where(row.mask, row.k * row.length, 0.0)
        bare = dataclasses.replace(s, sun_mesh_stiffness=0.0, ring_mesh_stiffness=0.0)
        k = model.stiffness_matrix(bare) + jnp.einsum("ci,c,cj->ij", row.V, kl, row.V)
        f = jnp.zeros(k.shape[0]).at[6 * 2 + 5].set(TORQUE / s.sun.base_radius)  # u_s
        q = jnp.linalg.solve(k, f)
        return q, (jax.jacobian(meshes.mesh_forces)(kl) * kl[None, :]) @ row.V @ q

    out = [tuple(np.asarray(a) for a in solve(s)) for s in (st, left)]
    (q_r, f_r), (q_l, f_l) = out
    np.testing.assert_allclose(f_l, f_r, rtol=1e-9)
    mirror = np.tile([1.0, 1.0, -1.0, -1.0, -1.0, 1.0], q_r.shape[0] // 6)
    np.testing.assert_allclose(q_l, mirror * q_r, rtol=0, atol=1e-9 * np.abs(q_r).max())
