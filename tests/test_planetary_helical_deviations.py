"""Per-tooth deviations on a helical planetary stage (jaxgear.planetary.DeviationMeshes with slices across
the face): a helix slope deviation on one planet tooth's sun-side flank, the line-load map of
every mesh against a spring model written here (each cell a spring k0 l on its contact line, the
cells counted here from the base-plane geometry of a helical mesh, the planets' paths in series
as tests/_planetary_stage.py's rigid_path_forces): the map changes on that tooth's contact lines
only beyond a uniform shift of the mesh's approach, tilted across the face as the helix slope
says, and the mesh forces follow k0 l times the deviation summed over the tooth's cells."""

import jax
import numpy as np
import pytest

import _planetary_stage as ps
import jaxgear as jg
import jaxgear.planetary as jp

jax.config.update("jax_enable_x64", True)

TORQUE = 1000.0
SLICES = 8
F_HB = 6e-6  # m: helix slope deviation f_Hbeta of the tooth (ISO 1328-1; + adds at z = b)
TOOTH = 5  # planet 1's tooth


def _cells(arc, p_b, g_alpha, b, beta_b):
    """(pair j, slice i) of the cells on the line of action of a helical mesh whose pinion has
    rolled ``arc`` (m): pair j's contact line lies at s = arc - j p_b - z tan beta_b, cell i at
    z_i = (i + 1/2) b / SLICES, on the flanks where 0 <= s <= g_alpha."""
    k = int(np.floor(arc / p_b))
    z = (np.arange(SLICES) + 0.5) * b / SLICES
    return [(j, i) for j in range(k - 6, k + 2) for i in range(SLICES)
            if 0.0 <= arc - j * p_b - z[i] * np.tan(beta_b) <= g_alpha]


def _spring_model(geo, psi, meshes, x, f_hb):
    """At the mesh travel x: the sun-mesh forces (N, (3,)) and per planet the predicted line
    loads {(mesh, j, i): w} (N/m) of the cells counted here, ``f_hb`` on planet 1's tooth.

    A cell of contact length l = (b / SLICES) / cos beta_b compressed by cos beta_b (a + e)
    (a the mesh's transverse approach, e the deviation along the transverse line: f_Hbeta
    (zeta - 1/2) on the tooth's cells, zeta = z / b) carries the line load w = k0 cos beta_b
    (a + e); the mesh's transverse force is sum k0 l cos^2 beta_b (a + e) = K (a + c), K the
    mesh's stiffness, c the mean e over its cells: an offset c of the path in series."""
    sp, pr = geo.sun_planet, geo.planet_ring
    p_b, b = float(sp.base_pitch), ps.WIDTH
    beta_b = abs(float(sp.base_helix_angle))
    l = b / SLICES / np.cos(beta_b)
    z = (np.arange(SLICES) + 0.5) * b / SLICES
    g_s, g_r = np.asarray(meshes.sun_phases), np.asarray(meshes.ring_phases)
    off = float(meshes.ring_offset)
    k_s, k_r, c_s, lines = [], [], [], []
    for n in range(3):
        sun = _cells(x - g_s[n] * p_b, p_b, sp.path_of_contact, b, beta_b)
        ring = _cells(x + off - g_r[n] * p_b, p_b, pr.path_of_contact, b, beta_b)
        e = np.array([f_hb * (z[i] / b - 0.5) if n == 0 and j % 17 == TOOTH else 0.0
                      for j, i in sun])
        k_s.append(ps.K0 * np.cos(beta_b) ** 2 * l * len(sun))
        k_r.append(ps.K0 * np.cos(beta_b) ** 2 * l * len(ring))
        c_s.append(e.mean())
        lines.append((sun, ring, e))
    f, _ = ps.rigid_path_forces(TORQUE, sp.base_radii[0], psi, geo.sun_pressure_angle,
                                geo.ring_pressure_angle, np.array(k_s), np.array(k_r),
                                mesh_offsets=(np.array(c_s), 0.0))
    maps = []
    for n, (sun, ring, e) in enumerate(lines):
        a_s, a_r = f[n] / k_s[n] - c_s[n], f[n] / k_r[n]
        w = {("sun", j, i): ps.K0 * np.cos(beta_b) * (a_s + e_c)
             for (j, i), e_c in zip(sun, e, strict=True)}
        w.update({("ring", j, i): ps.K0 * np.cos(beta_b) * a_r for j, i in ring})
        maps.append(w)
    return f, maps


@pytest.fixture(scope="module")
def helical():
    """19/17/-53, beta = 20 deg, 30 mm faces, Uniform k0, 8 slices; torsional model (ring and
    carrier held, the sun free): solves with and without the helix slope on planet 1's tooth 5
    (its sun-side flank) at 12 travels while that tooth passes the sun mesh (one compiled
    program: the same DeviationMeshes structure, zero deviations the contact meshes)."""
    geo = ps.geometry(**ps.SEQ, helix=np.radians(20.0))
    st = ps.stage(geo, 3)
    contact = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(ps.K0),
                                             n_slices=SLICES)
    teeth = jp.PlanetaryTeeth.from_geometry(geo, st.planet_angles)
    x = np.linspace(4.6, 9.1, 12) * float(geo.sun_planet.base_pitch)

    def solve(f_hb):
        hs = np.zeros(17)
        hs[TOOTH] = f_hb
        zero = lambda z: jg.GearDeviations(np.zeros(z))  # noqa: E731
        planets = (jp.PlanetFlanks(jg.GearDeviations(np.zeros(17), helix_slope=hs), zero(17)),
                   *(jp.PlanetFlanks(zero(17), zero(17)) for _ in range(2)))
        meshes = jp.DeviationMeshes(contact, teeth,
                                    jp.PlanetaryDeviations(zero(19), planets, zero(53)))
        r = jp.planetary_quasi_static(jp.TorsionalPlanetary(), st, meshes,
                                      np.asarray(TORQUE), x)
        assert np.all(np.asarray(r.result) == 0)
        return r

    return geo, st, contact, x, solve(0.0), solve(F_HB)


def _library_map(contact, r, k, n, mesh, cells, arc, p_b):
    """The library's line loads of the cells ``cells`` [(j, i)] of planet n's ``mesh`` at the
    k-th travel (a cell of pair j sits on line floor(arc / p_b) - j)."""
    w = np.asarray(contact.split_cells(r.cell_line_load)[mesh == "ring"])[k, n]
    top = np.floor(arc / p_b)
    return np.array([w[int(top - j), i] for j, i in cells])


def test_helix_deviation_on_one_tooth_tilts_its_lines_against_a_spring_model(helical):
    """Every mesh's line-load map and the sun-mesh forces at 12 travels, with and without the
    helix slope, against the spring model (1e-9 of the largest line load; every cell on the
    line of action carries load: the linear regime); the change of planet 1's sun-mesh map
    less its uniform part is k0 cos beta_b f_Hbeta (zeta - 1/2) on the tooth's cells (rising
    towards z = b for f_Hbeta > 0) and 0 on every other cell, its mesh force changes by
    K (mean e) through the path in series, and with the tooth's line across the whole face
    (sum of zeta - 1/2 = 0) not at all; the other planets' maps shift uniformly."""
    geo, st, contact, x, plain, dev = helical
    sp = geo.sun_planet
    p_b, b = float(sp.base_pitch), ps.WIDTH
    beta_b = abs(float(sp.base_helix_angle))
    psi = np.asarray(st.planet_angles)
    g_s, g_r = np.asarray(contact.sun_phases), np.asarray(contact.ring_phases)
    off = float(contact.ring_offset)
    z = (np.arange(SLICES) + 0.5) * b / SLICES
    tooth_cells = []
    for k, xi in enumerate(x):
        changes = []
        for r, f_hb in ((plain, 0.0), (dev, F_HB)):
            f, maps = _spring_model(geo, psi, contact, xi, f_hb)
            scale = max(max(w.values()) for w in maps)
            np.testing.assert_allclose(np.asarray(r.sun_mesh_forces)[k], f, rtol=1e-9)
            got_maps = []
            for n in range(3):
                arcs = {"sun": xi - g_s[n] * p_b, "ring": xi + off - g_r[n] * p_b}
                for mesh in ("sun", "ring"):
                    cells = [(j, i) for m, j, i in maps[n] if m == mesh]
                    want = np.array([maps[n][mesh, j, i] for j, i in cells])
                    got = _library_map(contact, r, k, n, mesh, cells, arcs[mesh], p_b)
                    np.testing.assert_allclose(got, want, rtol=0, atol=1e-9 * scale)
                    # every cell on the line of action in contact, none elsewhere
                    w_all = np.asarray(contact.split_cells(r.cell_line_load)[mesh == "ring"])
                    assert np.count_nonzero(w_all[k, n] > 0) == len(cells) and got.min() > 0
                    got_maps.append((mesh, cells, got))
            changes.append(got_maps)
        # planet 1's sun mesh: the change less its uniform part, from the tooth's cells alone
        _, cells, w0 = changes[0][0]
        _, _, w1 = changes[1][0]
        on = np.array([j % 17 == TOOTH for j, _ in cells])
        tooth_cells.append(on.sum())
        d = w1 - w0
        uniform = d[~on]
        assert np.ptp(uniform) < 1e-9 * w0.max()
        zeta = np.array([z[i] / b - 0.5 for _, i in cells])
        np.testing.assert_allclose(d - uniform.mean(), np.where(
            on, ps.K0 * np.cos(beta_b) * F_HB * zeta, 0.0), rtol=0, atol=1e-9 * w0.max())
        if on.any():
            rise = np.polyfit(zeta[on], d[on], 1)[0] if on.sum() > 1 else None
            assert rise is None or rise == pytest.approx(ps.K0 * np.cos(beta_b) * F_HB,
                                                         rel=1e-9)
        # the other planets' meshes: uniform shifts only
        for n in (1, 2):
            for (_, _, a), (_, _, c) in zip(changes[0][2 * n: 2 * n + 2],
                                            changes[1][2 * n: 2 * n + 2], strict=True):
                assert np.ptp(c - a) < 1e-9 * w0.max()
        df = np.asarray(dev.sun_mesh_forces)[k, 0] - np.asarray(plain.sun_mesh_forces)[k, 0]
        if on.sum() == SLICES:  # the tooth's line across the whole face
            assert abs(df) < 1e-9 * float(np.asarray(plain.sun_mesh_forces)[k, 0])
        elif on.any():
            assert abs(df) > 1.0  # N: a part of the line, net material
    # the tooth enters, crosses the whole face and leaves
    assert max(tooth_cells) == SLICES and tooth_cells[0] == 0 and tooth_cells[-1] == 0
    assert len({c for c in tooth_cells if 0 < c < SLICES}) >= 2
