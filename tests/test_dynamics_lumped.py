"""3D lumped scene: Timoshenko shaft elements, structure vectors, stiff limit, modal energies."""

import math

import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _corner import cell_points_normals

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
from jaxgear.dynamics import Newmark, SteadyState
from jaxgear.scenes import Bearing, ShaftSpec, lumped_pair, shaft_matrices, timoshenko_element


def _timoshenko_ss(E, G, rho, d, L, kappa, mode=1):
    """Simply supported Timoshenko beam: the lower root of
    (ρAω² − κGAk²)(ρIω² − EIk² − κGA) + (κGAk)² = 0, k = nπ/L."""
    A, I = math.pi * d**2 / 4, math.pi * d**4 / 64
    k = mode * math.pi / L
    a = rho * A * rho * I
    b = -(rho * A * (E * I * k**2 + kappa * G * A) + rho * I * kappa * G * A * k**2)
    c = kappa * G * A * k**2 * (E * I * k**2 + kappa * G * A) - (kappa * G * A * k) ** 2
    w2 = (-b - math.sqrt(b * b - 4 * a * c)) / (2 * a)
    return math.sqrt(w2)


def _first_bending_pair(nodes, K, M, L):
    """The two lowest modes whose transverse displacement is the simply supported first bending
    shape: selected by shape (not by a frequency threshold), so neither the free torsion mode,
    whatever BLAS makes of its zero eigenvalue, nor an axial or higher mode can be picked."""
    lam, phi = scipy.linalg.eigh(K, M)
    s = np.sin(math.pi * nodes / L)
    s /= np.linalg.norm(s)
    t = np.zeros(K.shape[0], dtype=bool)
    t[0::6] = t[1::6] = True  # u_x, u_y
    picked = []
    for j in np.argsort(lam):
        v = phi[:, j]
        kinetic = v @ M @ v
        share = (v[t] @ M[np.ix_(t, t)] @ v[t]) / kinetic  # transverse translational share
        ux, uy = v[0::6], v[1::6]
        norm = math.hypot(np.linalg.norm(ux), np.linalg.norm(uy))
        proj = math.hypot(ux @ s, uy @ s) / norm if norm > 0 else 0.0
        if share > 0.5 and proj > 0.99:
            picked.append(lam[j])
        if len(picked) == 2:
            return np.sqrt(np.array(picked))
    raise AssertionError("no first bending pair found")


@pytest.mark.parametrize("d", [0.01, 0.08])  # slender (L/d = 50) and thick (L/d = 6.25)
def test_timoshenko_shaft_matches_simply_supported_beam(d):
    E, nu, rho, L, kappa = 210e9, 0.3, 7800.0, 0.5, 0.9
    G = E / (2 * (1 + nu))
    # supports: springs 1e6 × the beam's own mid-span stiffness 48EI/L³, not an arbitrary 1e16
    # (which made cond(K) ≈ 1e16 and let BLAS rounding turn the free torsion mode into a
    # spurious few-rad/s "mode"); the spring compliance lowers ω by ≈ 1e-6 relative, well inside
    # the 2e-3 tolerance (the discretisation error of 24 elements)
    pinned = 1e6 * 48 * E * (math.pi * d**4 / 64) / L**3
    spec = ShaftSpec(
        length=L,
        diameter=d,
        gear_z=L / 2,
        bearings=(Bearing(0.0, pinned, pinned, 0.0), Bearing(L, pinned, 0.0, 0.0)),
        elements=24,
    )
    shaft = shaft_matrices(spec, E, G, rho)
    nodes, K, M, Kb = shaft.nodes, shaft.K, shaft.M, shaft.K_bearing
    bending = _first_bending_pair(nodes, K + Kb, M, L)  # x–z and y–z planes
    w_ref = _timoshenko_ss(E, G, rho, d, L, kappa)
    np.testing.assert_allclose(bending, w_ref, rtol=2e-3)
    w_eb = (math.pi / L) ** 2 * math.sqrt(E * (math.pi * d**4 / 64) / (rho * math.pi * d**2 / 4))
    if d > 0.05:
        assert w_ref < 0.98 * w_eb  # shear and rotary inertia matter for the thick shaft
    else:
        assert w_ref == pytest.approx(w_eb, rel=2e-3)


def test_element_symmetry_and_rigid_modes():
    K, M = timoshenko_element(210e9, 80.8e9, 7800.0, 0.03, 0.05)
    np.testing.assert_allclose(K, K.T, atol=1e-6 * np.abs(K).max())
    assert np.all(np.linalg.eigvalsh(M) > 0)
    # six rigid-body motions of a straight element cost no strain energy
    L = 0.05
    rig = []
    for d in range(3):
        v = np.zeros(12)
        v[d] = v[6 + d] = 1.0
        rig.append(v)
    # rotation about x: u_y = −φ_x z, about y: u_x = φ_y z, about z: φ_z
    rx = np.zeros(12)
    rx[[3, 9]] = 1.0
    rx[7] = -L
    ry = np.zeros(12)
    ry[[4, 10]] = 1.0
    ry[6] = L
    rz = np.zeros(12)
    rz[[5, 11]] = 1.0
    for v in rig + [rx, ry, rz]:
        assert np.abs(K @ v).max() < 1e-9 * np.abs(K).max()


def _accessory_lumped(case, radial, diameter=0.03, slices=4):
    p = case.pair
    mesh = case.mesh_model(slices=slices)

    def disc(r, b):
        m = case.density * math.pi * r * r * b
        return m, (m * r * r / 4 + m * b * b / 12, m * r * r / 2)

    m1, i1 = disc(p.tip_radii[0], p.pinion.face_width)
    m2, i2 = disc(p.tip_radii[1], p.gear.face_width)

    def shaft():
        return ShaftSpec(
            length=0.1,
            diameter=diameter,
            gear_z=0.05,
            elements=4,
            bearings=(Bearing(0.0, radial, radial, 0.0), Bearing(0.1, radial, 0.0, 0.0)),
        )

    return lumped_pair(p, mesh, shaft(), shaft(), masses=(m1, m2), inertias=(i1, i2))


def test_structure_vectors_reduce_to_torsional_and_rigid_mode_is_free():
    case = jio.load_case("power-helical")
    scene = _accessory_lumped(case, 2e8, slices=3)
    cells = scene.mesh.cells(jnp.asarray(0.01))
    V = np.asarray(scene.cell_vectors(cells))
    assert np.all(V[~np.asarray(cells.mask)] == 0.0)  # a cell off the flanks loads nothing
    mask, s = np.asarray(cells.mask), np.asarray(cells.s)
    V = V[mask]  # (cells on the flanks, n)
    p = case.pair
    on = (s[mask] >= 0.0) & (s[mask] <= p.path_of_contact)
    assert not np.all(on)  # the case file's default contact beyond the path: corner cells
    cb, sb = math.cos(p.base_helix_angle), math.sin(p.base_helix_angle)
    i, j = (member.dofs[0] for member in scene.members)  # the gear nodes
    # torsional part: cos β_b (r_b1 φ_z1 + r_b2 φ_z2), i.e. cos β_b (r_b1 θ1 − r_b2 θ2), on the
    # path; beyond it the moments of the corner's normal through its contact point about the
    # gear axes (tests/_corner.py), to the corner table's interpolation (3e-5)
    np.testing.assert_allclose(V[on, i + 5], cb * p.base_radii[0], rtol=1e-12)
    np.testing.assert_allclose(V[on, j + 5], cb * p.base_radii[1], rtol=1e-12)
    gm = scene.meshes[0]
    P, n = cell_points_normals(
        p, s, np.asarray(gm.points(cells)), np.asarray(gm.direction), np.asarray(gm.normal),
        [np.asarray(m.centre) for m in scene.members],
    )
    arm = [np.cross(P - np.asarray(m.centre), sign * n)[..., 2][mask]
           for m, sign in zip(scene.members, (1.0, -1.0), strict=True)]
    np.testing.assert_allclose(V[~on, i + 5], arm[0][~on], rtol=3e-5)
    np.testing.assert_allclose(V[~on, j + 5], arm[1][~on], rtol=3e-5)
    # helical: axial coupling sin β_b on the translations, opposite on the gear
    np.testing.assert_allclose(V[..., i + 2], sb, rtol=1e-12)
    np.testing.assert_allclose(V[..., j + 2], -sb, rtol=1e-12)
    # tilting couplings vary across the face (lever arm z − b/2)
    assert np.ptp(V[..., i + 3]) > 0 or np.ptp(V[..., i + 4]) > 0
    r = np.asarray(scene.rigid_modes())[:, 0]
    assert np.abs(V[on] @ r).max() < 1e-12
    # a corner cell's exact vector has a part along the drive rotation; the rows the solvers
    # use drop it (docs/extended-contact.md, "The free drive rotation")
    used = np.asarray(scene.cell_row((cells,), (jnp.zeros_like(cells.s),)).V)
    assert np.abs(used @ r).max() < 1e-12
    assert abs(np.asarray(scene.external_load(jnp.asarray(310.0))) @ r) < 1e-9


def test_stiff_shafts_and_bearings_recover_the_rigid_mesh_te():
    case = jio.load_case("accessory-spur")
    qs = jg.quasi_static(
        case.mesh_model(slices=4), case.modifications, case.torque, positions_per_pitch=16
    )
    out = {}
    for radial, d in ((1e14, 0.4), (2e8, 0.03)):
        scene = _accessory_lumped(case, radial, diameter=d)
        static = jg.quasi_static(scene, case.modifications, case.torque, positions_per_pitch=16)
        assert np.all(np.asarray(static.result) == 0)
        out[radial] = np.asarray(static.transmission_error)
    np.testing.assert_allclose(out[1e14], np.asarray(qs.transmission_error), rtol=2e-3)
    # flexible shafts and bearings add to the mean TE, not to its fluctuation (spur, torsional V)
    assert out[2e8].mean() > 2 * out[1e14].mean()
    assert 15e-6 < out[2e8].mean() < 80e-6  # seed Tab. III-4: 19–41 µm with shafts and bearings


def test_lumped_modes_energy_and_simulation():
    case = jio.load_case("accessory-spur")
    scene = _accessory_lumped(case, 2e8)
    model = jd.dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=16)
    modes = model.modes
    assert modes.parts == ("mesh", "pinion_shaft", "gear_shaft", "bearings")
    assert int(np.sum(np.asarray(modes.rigid))) == 1
    e = np.asarray(modes.energy)[:, ~np.asarray(modes.rigid)]
    np.testing.assert_allclose(e.sum(axis=0), 1.0, rtol=1e-9)
    assert np.all(e > -1e-9)
    r = jd.simulate(model, 800.0, integrator=Newmark(16), window=SteadyState(6, 2))
    assert int(r.result) == 0
    assert 1.0 < float(r.dynamic_factor) < 3.0
    # bearing forces: statically, the radial bearing loads balance the mesh force
    names = scene.reaction_names
    assert len(names) == 10 and r.bearing_force.shape == (32, 10)  # x, y (+ z at bearing 0)
    fs = float(model.static_force)
    stat = np.asarray(r.bearing_force_static)
    pin = [i for i, nm in enumerate(names) if nm.startswith("pinion") and "Fz" not in nm]
    # two bearings at equal distance from the gear: each carries half of F_s (x and y parts)
    total = np.hypot(stat[pin[0]] + stat[pin[2]], stat[pin[1]] + stat[pin[3]])
    assert total == pytest.approx(fs, rel=0.02)
    assert np.all(np.asarray(r.bearing_force_max) >= 0.9 * stat)
