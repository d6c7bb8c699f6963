"""Where a corner cell's force acts beyond the theoretical path (docs/extended-contact.md, "Where
it acts"): the structure vectors against central differences of the exact corner gap, the
moments against a contact point and normal placed here by the tooth thickness, and the limits
(the line of action's vectors at λ = 1, ε = 0; today's results with enough tip relief)."""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg
from _corner import ring_pair

import jaxgear as jg
import jaxgear.planetary as jp
import jaxgear.scenes as js
from jaxgear.scenes import Bearing, ShaftSpec, lumped_pair


def _pair(z1=20, z2=40, m=0.004, b=0.02, beta=0.0):
    return jg.GearPair(
        jg.Member(teeth=z1, face_width=b),
        jg.Member(teeth=z2, face_width=b),
        normal_module=m,
        normal_pressure_angle=math.radians(20.0),
        helix_angle=beta,
    )


def _mesh(pair, extended=True, slices=1, stiffness=None):
    s, k = jg.stiffness_table(pair, jg.Weber() if stiffness is None else stiffness)
    return jg.MeshModel.from_pair(
        pair, s, k, slices, contact_geometry=jg.BeyondPath() if extended else jg.TheoreticalPath()
    )


def _on_line(mesh):
    """The mesh with the line of action's geometry beyond the path: λ = 1, ε = 0, no offset."""
    table = jnp.zeros_like(mesh.extension_corner).at[:, 0].set(1.0)
    return eqx.tree_at(lambda m: m.extension_corner, mesh, table)


def _lumped(pair, mesh):
    def shaft():
        return ShaftSpec(
            length=0.1,
            diameter=0.04,
            gear_z=0.05,
            elements=2,
            bearings=(Bearing(0.0, 1e9, 1e9, 0.0), Bearing(0.1, 1e9, 0.0, 0.0)),
        )

    return lumped_pair(pair, mesh, shaft(), shaft(), masses=(1.0, 2.0), inertias=((1e-3,) * 2,) * 2)


@eqx.filter_jit
def _cells(mesh, theta):
    """The mesh's cells at the pinion angle theta (one compiled program per mesh shape)."""
    return mesh.cells(theta)


@eqx.filter_jit
def _vectors(scene, cells):
    """The scene's exact structure vectors of the cells (one compiled program per shape)."""
    return scene.cell_vectors(cells)


def _theta_at(mesh, s):
    """A pinion angle that puts contact line −1 (s < 0) or line 1 (s > g_α) of a spur mesh's
    cells at the base-plane coordinate ``s`` (on the gap table's grid)."""
    pb = float(mesh.base_pitch)
    return (s % pb) / float(mesh.base_radius_pinion)


def _cell(cells, s):
    k = np.argmin(np.abs(np.asarray(cells.s)[:, 0] - s))
    assert abs(float(cells.s[k, 0]) - s) < 1e-12 and bool(cells.mask[k, 0])
    return k


def _gap_derivative(pair, s):
    """−∂gap/∂X (the approach per unit coordinate) of the exact corner gap by central
    differences: the pinion's and the gear's rotation in their directions of motion (rad) and
    each centre's x, y translation (m), in that order."""
    out = []
    for kind, h in (("rotation", 1e-7), ("shift", 1e-8)):
        for j in range(2 if kind == "rotation" else 4):
            d = np.zeros(2 if kind == "rotation" else (2, 2))
            d.flat[j] = h
            plus = jg.CornerContact(pair, s, **{kind: d}).gap
            minus = jg.CornerContact(pair, s, **{kind: -d}).gap
            out.append(-(plus - minus) / (2 * h))
    return np.array(out)


@pytest.mark.parametrize("side", [0, 1])
def test_lumped_and_torsional_vectors_are_the_corner_gap_derivative(side):
    pair = _pair()
    mesh = _mesh(pair)
    span = np.asarray(mesh.extension_span)
    u = np.linspace(0.0, 1.0, mesh.extension_gap.shape[1])[40]  # a grid point of the table
    s = -span[0] * u if side == 0 else float(mesh.path_of_contact) + span[1] * u
    ref = _gap_derivative(pair, s)
    cells = _cells(mesh, jnp.asarray(_theta_at(mesh, s)))
    k = _cell(cells, s)
    # lumped 3D: node DOFs (x, y, z, φx, φy, φz); the gear turns about −z
    scene = _lumped(pair, mesh)
    V = np.asarray(_vectors(scene, cells))[k, 0]
    (m1, m2) = (m.dofs for m in scene.members)
    got = np.array([V[m1[5]], -V[m2[5]], V[m1[0]], V[m1[1]], V[m2[0]], V[m2[1]]])
    np.testing.assert_allclose(got, ref, rtol=1e-6, atol=1e-8)
    # the tip owner's lever arm is shorter than its base radius: not the line of action's
    lam = jg.CornerContact(pair, s).tip_lever
    assert 0.85 < lam < 0.99
    # torsional pair (rotations) and the rigid pair (the pinion's advance, the gear held)
    Vt = np.asarray(_vectors(js.TorsionalPair(mesh), cells))[k, 0]
    np.testing.assert_allclose(Vt, ref[:2], rtol=1e-6)
    Vr = np.asarray(_vectors(js.RigidMesh(mesh), cells))[k, 0, 0]
    assert Vr == pytest.approx(ref[0] / pair.base_radii[0], rel=1e-6)


def test_internal_mesh_torsional_vectors_are_the_corner_gap_derivative():
    ring = ring_pair()
    mesh = _mesh(ring, stiffness=jg.ISO6336())
    span = np.asarray(mesh.extension_span)
    for s in (-0.5 * span[0], float(mesh.path_of_contact) + 0.5 * span[1]):
        ref = _gap_derivative(ring, s)
        cells = _cells(mesh, jnp.asarray(_theta_at(mesh, s)))
        V = np.asarray(_vectors(js.TorsionalPair(mesh), cells))[_cell(cells, s), 0]
        np.testing.assert_allclose(V, ref[:2], rtol=1e-6)


def _psi(pair, member, r):
    """Half angle from a tooth's centre line to its involute flank at radius r (ISO 21771:
    s_t/(2 r_p) + inv α_t − inv α_r), from the tooth thickness."""
    rp, rb = pair.pitch_radii[member], pair.base_radii[member]
    at = pair.transverse_pressure_angle
    ar = math.acos(rb / r)
    return pair.reference_thickness[member] / (2 * rp) + (math.tan(at) - at) - (math.tan(ar) - ar)


def _corner_by_hand(pair, s):
    """The corner contact of an external spur pair at base-plane coordinate s outside [0, g_α],
    placed here by the tooth thickness: the teeth's centre lines at the engagement point A
    (both drive flanks through A), turned by s/r_b1 and −s/r_b2; the tip owner's corner on its
    tip circle; the normal of the mating flank at the corner's radius (the flank X(r) = O +
    r e(c + ψ(r)), dψ/dr = −tan α_r / r, so its tangent is e_r − tan α_r e_φ).
    Returns the contact point P, the pinion's outward unit normal n (both (2,)) and the centres."""
    a = pair.operating_pressure_angle
    rb1, rb2 = pair.base_radii
    O = [np.zeros(2), np.array([pair.center_distance, 0.0])]
    t = np.array([math.sin(a), math.cos(a)])
    A = rb1 * np.array([math.cos(a), -math.sin(a)]) + pair.start_roll * t
    r2A = float(np.hypot(*(A - O[1])))
    c = [
        math.atan2(A[1], A[0]) - _psi(pair, 0, float(np.hypot(*A))) + s / rb1,
        math.atan2(A[1] - O[1][1], A[0] - O[1][0]) - _psi(pair, 1, r2A) - s / rb2,
    ]
    tip, flank = (1, 0) if s < 0 else (0, 1)
    ra = pair.tip_radii[tip]
    ang = c[tip] + _psi(pair, tip, ra)
    P = O[tip] + ra * np.array([math.cos(ang), math.sin(ang)])
    d = P - O[flank]
    r, phi = float(np.hypot(*d)), math.atan2(d[1], d[0])
    ar = math.acos(pair.base_radii[flank] / r)
    er, ephi = np.array([math.cos(phi), math.sin(phi)]), np.array([-math.sin(phi), math.cos(phi)])
    tangent = er - math.tan(ar) * ephi
    n = np.array([tangent[1], -tangent[0]]) / np.hypot(*tangent)
    if n @ t < 0:  # the pinion's outward normal points along the line of action's direction
        n = -n
    return P, n, O


def _cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def test_torque_balance_with_moments_about_the_corner_by_hand():
    # the torsional pair at a position where corner cells before the start and after the end
    # carry load: the pinion's input torque against the moments of the cells' forces along
    # the mating flank's normal through the corner, written here. The gear's shaft reaction
    # keeps the line of action's ratio r_b2/r_b1: the rows drop the corner's broken torque
    # ratio with the pair's rolling (the gear held, docs/extended-contact.md, "The pair's
    # rolling"); the exact moments on the gear differ from it by that ratio (0.64 % measured)
    pair = _pair()
    mesh = _mesh(pair)
    k_out = 1e6
    scene = js.TorsionalPair(mesh, k_out)
    T = 400.0
    pb, g = float(mesh.base_pitch), pair.path_of_contact
    # a line 0.02 p_b before the start, and one 0.02 p_b after the end
    theta = jnp.asarray([0.98 * pb, (g + 0.02 * pb) % pb]) / pair.base_radii[0]
    res = jg.quasi_static(scene, None, T, theta=theta)
    assert np.all(np.asarray(res.result) == 0)
    m = res.meshes[0]
    s_all, load = np.asarray(m.cell_s), np.asarray(m.line_load)
    length = float(pair.face_width)  # one slice, spur: the cell is the face width long
    loa = _on_line(mesh)
    for p in range(len(theta)):
        torque = [0.0, 0.0]
        beyond = 0.0
        for s, w in zip(s_all[p, :, 0], load[p, :, 0], strict=True):
            if w == 0.0:
                continue
            F = w * length
            if 0.0 <= s <= pair.path_of_contact:  # on the path: the line of action
                arms = pair.base_radii
            else:
                P, n, O = _corner_by_hand(pair, s)
                arms = (_cross(P - O[0], n), _cross(P - O[1], -n))
                beyond += F
            torque[0] += F * arms[0]
            torque[1] += F * arms[1]
        assert beyond > 0.01 * T / pair.base_radii[0]  # a corner carries a real load here
        assert torque[0] == pytest.approx(T, rel=2e-6)
        reaction = k_out * float(res.x[p, 1])
        assert reaction == pytest.approx(T * pair.base_radii[1] / pair.base_radii[0], rel=1e-9)
        assert torque[1] == pytest.approx(reaction, rel=0.01)
    # the line of action's lever arms miss the pinion's balance by more than that
    r0 = jg.quasi_static(js.TorsionalPair(loa, k_out), None, T, theta=theta)
    w0 = np.asarray(r0.meshes[0].line_load)[:, :, 0] * length
    s0 = np.asarray(r0.meshes[0].cell_s)[:, :, 0]
    after = s0 > pair.path_of_contact
    assert np.any(w0[after] > 0)
    miss = 0.0
    for s, w in zip(s0[after], w0[after], strict=True):
        P, n, O = _corner_by_hand(pair, s)
        miss += w * (pair.base_radii[0] - _cross(P - O[0], n))
    assert miss > 1e-4 * T


def test_lumped_moments_about_the_corner_by_hand():
    # one corner cell's structure vector on the lumped 3D nodes: [n', (P − O) × n'] with the
    # contact point and the normal written here
    pair = _pair()
    mesh = _mesh(pair)
    scene = _lumped(pair, mesh)
    for s in (-0.6 * float(mesh.extension_span[0]), pair.path_of_contact + 0.02 * pair.base_pitch):
        cells = _cells(mesh, jnp.asarray(_theta_at(mesh, s)))
        k = int(np.argmin(np.abs(np.asarray(cells.s)[:, 0] - s)))
        s = float(cells.s[k, 0])
        V = np.asarray(_vectors(scene, cells))[k, 0]
        P, n, O = _corner_by_hand(pair, s)
        d1, d2 = scene.members[0].dofs, scene.members[1].dofs
        np.testing.assert_allclose(V[list(d1[:2])], n, atol=2e-6)
        np.testing.assert_allclose(V[list(d2[:2])], -n, atol=2e-6)
        assert V[d1[5]] == pytest.approx(_cross(P - O[0], n), rel=2e-6)
        assert V[d2[5]] == pytest.approx(_cross(P - O[1], -n), rel=2e-6)


def _relief(depth):
    return jg.Modifications(
        pinion=jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.3),
        gear=jg.MemberModification(tip_relief_depth=depth, tip_relief_extent=0.3),
    )


def _relieved_results_are_theoretical(pair, mesh, build, T):
    """With enough tip relief (60 µm) no corner touches: the scene ``build`` makes of the
    extended ``mesh`` gives the theoretical model's TE to 1e-12."""
    mods = _relief(60e-6)
    off = _mesh(pair, extended=False, slices=4)
    r1 = jg.quasi_static(build(mesh), mods, T, positions_per_pitch=16)
    r0 = jg.quasi_static(build(off), mods, T, positions_per_pitch=16)
    np.testing.assert_allclose(
        np.asarray(r1.meshes[0].transmission_error),
        np.asarray(r0.meshes[0].transmission_error),
        rtol=1e-12,
        atol=1e-18,
    )


def test_on_the_line_of_action_and_with_tip_relief_results_are_todays():
    pair = _pair(beta=math.radians(12.0))
    mesh = _mesh(pair, slices=4)
    loa = _on_line(mesh)
    T = 300.0
    # at λ = 1, ε = 0 the pinion's advance, its rotation and the 3D nodes agree cell by cell
    # (unmodified teeth: a relief of zero depth, whose runs are the compiled programs of the
    # runs with relief below)
    te = [
        np.asarray(
            jg.quasi_static(sc, _relief(0.0), T, positions_per_pitch=16)
            .meshes[0]
            .transmission_error
        )
        for sc in (loa, js.TorsionalPair(loa, 1e12))
    ]
    np.testing.assert_allclose(te[1], te[0], rtol=1e-9)
    cells = _cells(loa, jnp.asarray(0.01))
    Vl = np.asarray(_lumped(pair, loa).cell_vectors(cells))
    Vm = np.asarray(_lumped(pair, _mesh(pair, extended=False, slices=4)).cell_vectors(cells))
    np.testing.assert_array_equal(Vl[np.asarray(cells.mask)], Vm[np.asarray(cells.mask)])
    # with enough tip relief no corner touches: the theoretical model's results to 1e-12 (the
    # mesh alone and the torsional pair, the programs of the runs above; the lumped 3D pair:
    # the slow test below)
    for build in (lambda m: m, lambda m: js.TorsionalPair(m)):
        _relieved_results_are_theoretical(pair, mesh, build, T)


# default tier: tests/test_extended_contact_normal.py::test_on_the_line_of_action_and_with_tip_relief_results_are_todays (same claim on the mesh alone and the torsional pair); the lumped 3D pair's cell vectors on the extended path: test_lumped_and_torsional_vectors_are_the_corner_gap_derivative
@pytest.mark.slow
def test_with_tip_relief_the_lumped_pair_gives_the_theoretical_results():
    pair = _pair(beta=math.radians(12.0))
    _relieved_results_are_theoretical(
        pair, _mesh(pair, slices=4), lambda m: _lumped(pair, m), 300.0
    )


def _planetary():
    b, m_n = 0.03, 0.003
    geo = jg.planetary_geometry(
        jg.Member(20, face_width=b),
        jg.Member(30, face_width=b, dedendum_coeff=1.3),
        jg.Member(-80, face_width=b),
        m_n,
        math.radians(20.0),
    )
    psi = 2 * np.pi * np.arange(4) / 4
    models = tuple(
        jg.MeshModel.from_pair(
            p, *jg.stiffness_table(p, jg.Uniform(1.4e10)), 1, contact_geometry=jg.BeyondPath()
        )
        for p in (geo.sun_planet, geo.planet_ring)
    )
    r_s, r_p = (float(r) for r in geo.sun_planet.base_radii)
    r_r = float(geo.planet_ring.base_radii[1])
    member = jp.PlanetaryMember
    stage = jp.PlanetaryStage(
        sun=member(1.0, 1e-3, r_s),
        ring=member(10.0, 1.0, r_r, torsional_stiffness=1e9),
        carrier=member(10.0, 1.0, float(geo.center_distance)),
        planet=member(0.5, 1e-3, r_p),
        planet_angles=psi,
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=1e9,
        ring_mesh_stiffness=1e9,
    )
    return geo, models, jp.ContactMeshes.from_models(geo, psi, models), stage


@eqx.filter_jit
def _planetary_row(meshes, model, stage, x):
    """The structure vectors of the stage's cells at the mesh travel x (one compiled program)."""
    zero = jnp.zeros(4)
    return meshes.cell_row(model, stage, x, (zero, zero)).V


@pytest.mark.parametrize("which", ["sun", "ring"])
def test_planetary_rows_are_the_corner_gap_derivative(which):
    # planet 1 sits at ψ = 0: the sun pair's frame is the stage's (the sun at the origin turning
    # counter-clockwise, the planet on +x); the ring pair's (the planet its pinion, turning
    # clockwise in the stage) is the stage's mirrored about the x axis, its centre at −a_w
    geo, models, meshes, stage = _planetary()
    k = 0 if which == "sun" else 1
    pair, mesh = (geo.sun_planet, geo.planet_ring)[k], models[k]
    r_s, r_p = (float(r) for r in geo.sun_planet.base_radii)
    r_r = float(geo.planet_ring.base_radii[1])
    model = jp.PlanarPlanetary()
    names = model.dof_names(stage)
    K, M = (np.asarray(a) for a in (model.stiffness_matrix(stage), model.mass_matrix(stage)))
    lam, phi = scipy.linalg.eigh(K, M)
    phi = phi[:, lam <= 1e-9 * np.abs(lam).max()]
    assert phi.shape[1] >= 1  # the sun and the carrier turn freely
    g, pb = float(mesh.path_of_contact), float(mesh.base_pitch)
    seen = []
    xs = np.linspace(0.0, pb, 64, endpoint=False) + 1e-6
    every = eqx.filter_jit(jax.vmap(lambda x: meshes.planet_cells(x)[k][0]))(jnp.asarray(xs))
    for i, x in enumerate(xs):
        s, on = np.asarray(every.s)[i, 0, :, 0], np.asarray(every.mask)[i, 0, :, 0]
        far = on & (
            (s < -0.3 * float(mesh.extension_span[0]))
            | (s > g + 0.3 * float(mesh.extension_span[1]))
        )
        for line in np.flatnonzero(far):
            if (s[line] < 0) in seen:
                continue
            seen.append(bool(s[line] < 0))
            V = np.asarray(_planetary_row(meshes, model, stage, jnp.asarray(x)))
            V = V[(0 if k == 0 else 4 * models[0].n_lines) + line]
            d = -_gap_derivative(pair, float(s[line]))  # ∂gap/∂(φ1, φ2, x1, y1, x2, y2)
            coords = (
                ("u_s", "u_1", "x_s", "y_s", "zeta_1", "eta_1")
                if k == 0
                else ("u_1", "u_r", "zeta_1", "eta_1", "x_r", "y_r")
            )
            if k == 0:  # u = r_b θ, the planet's motion clockwise
                ref = [-d[0] / r_s, d[1] / r_p, -d[2], -d[3], -d[4], -d[5]]
            else:  # mirrored: both turn clockwise in the stage, y flips
                ref = [d[0] / r_p, d[1] / r_r, -d[2], d[3], -d[4], d[5]]
            # the row the solvers use: the exact one less its part along the pair's rolling ρ
            # (centres fixed, the rotations at the conjugate ratio: no change on the path,
            # whose rotation entries are ±1 with the corner's signs), taken off so that the
            # stage's rigid rotation (u = r_b φ on both) changes the rotations' part no more
            # than the exact row does: a 2 x 2 solve on the two rotation entries; then less
            # its part along the stage's free rigid-body modes Φ_r (mass-normalised, found
            # here by scipy), V − (V Φ_r)(M Φ_r)ᵀ
            assert abs(ref[0 if s[line] > g else 1]) < 0.99  # the tip owner's λ
            ref = list(ref)
            a = np.array(ref[:2])
            rho = np.array([1.0, -np.sign(a[0]) * np.sign(a[1])])
            rigid = np.array([r_s, r_p] if k == 0 else [r_p, r_r])
            ref[:2] = np.linalg.solve(np.array([rho, rigid]), [0.0, a @ rigid])
            full = np.zeros(V.shape)
            full[[names.index(n) for n in coords]] = ref
            full -= (full @ phi) @ (M @ phi).T
            np.testing.assert_allclose(V, full, atol=2e-6)
            assert np.abs(V @ phi).max() < 1e-12 * np.abs(V).max() * np.abs(phi).max()
    assert sorted(seen) == [False, True]


def test_planetary_rolling_with_a_flexible_ring_closes_no_corner():
    # the stage's rolling with the carrier held (the sun turning, the planets turning back, the
    # ring's displacement at every planet along its force: a flexible ring turning on its
    # housing, held by nothing stiff; Lin & Parker's deflections u_s + u_n on the sun mesh,
    # u_r - u_n on the ring mesh) moves the cells along the path, which the cells' positions
    # (the nominal motion) do not follow: no cell's gap may change with it, corner cells
    # included (with the exact lever, 1 - λ per unit roll: a condensed ring turning 4 mm on
    # its housing under load closed the corners by 0.6 mm, the stage's dynamic factor 22)
    from _planetary_stage import stage as held_stage

    geo, models, meshes, _ = _planetary()
    # the ring and the carrier held stiffly: no free drive rotation (whose part the corner rows
    # drop along M R, test above); the ring turns on its stations alone (w)
    stage = held_stage(geo, 4)
    model = jp.PlanarPlanetary()
    names = model.dof_names(stage)
    z = 80
    ring = jp.CondensedRing(np.eye(2 * z).reshape(z, 2, z, 2) * 1e-9)
    n = stage.n_planets
    roll = np.zeros(len(names) + n)
    roll[names.index("u_s")] = 1.0
    roll[[names.index(f"u_{i + 1}") for i in range(n)]] = -1.0
    roll[len(names):] = 1.0  # the ring's displacement along each ring mesh's force (w)

    @eqx.filter_jit
    def rows(x):
        zero = jnp.zeros(n)
        row = meshes.cell_row(model, stage, x, (zero, zero))
        ring_rows = meshes.ring_rows(stage, x, row.k.shape[0])
        k_b = model.stiffness_matrix(stage)
        V = ring.augment(stage, k_b, jnp.zeros(k_b.shape[0]), row.V, ring_rows, x)[2]
        cells = meshes.planet_cells(x)
        s = jnp.concatenate([cells[0][0].s.reshape(-1), cells[1][0].s.reshape(-1)])
        return V, row.mask, s

    g = (float(models[0].path_of_contact), float(models[1].path_of_contact))
    pb = float(models[0].base_pitch)
    corners = 0
    for x in np.linspace(0.0, pb, 16, endpoint=False) + 1e-6:
        V, mask, s = (np.asarray(a) for a in rows(jnp.asarray(x)))
        c_s = n * models[0].n_lines * models[0].n_slices
        beyond = mask & ((s < 0) | (s > np.r_[[g[0]] * c_s, [g[1]] * (s.size - c_s)]))
        # the exact rows' rolling part at a corner is (1 - λ) cos β_b, λ ≤ 0.99 there
        np.testing.assert_allclose(V[mask] @ roll, 0.0, atol=1e-12)
        corners += int(beyond.sum())
    assert corners >= 4


@pytest.fixture(scope="module")
def hybrid(fem_prep_cache):
    """The hybrid test pair beyond the path (its condensed wheel) and, at eight positions over a
    mesh period, its cells, their exact structure vectors and the rows the solvers use (one
    compiled program): (case, scene, thetas, cells, exact V, row idx, row V)."""
    import pathlib

    import fem_prep
    from jaxgear import io as jio
    from jaxgear.io import static_scene

    data = pathlib.Path(__file__).parent / "data"
    case = jio.load_case(data / "hybrid-test-case.toml").replace(contact_geometry=jg.BeyondPath())
    body = fem_prep.condensed(data / "hybrid-test-wheel.toml")
    sc = static_scene(case, bodies=(None, body))[0]
    mesh = sc.mesh
    thetas = np.linspace(0.0, float(mesh.mesh_period_angle), 9)[:-1] + 1e-4

    @eqx.filter_jit
    def rows(th):
        def one(t):
            cells = mesh.cells(t)
            row = sc.window_row((cells,), (jnp.zeros_like(cells.s),))
            return cells, sc.cell_vectors(cells), row.idx, row.V

        return jax.vmap(one)(th)

    return (case, sc, thetas, *rows(jnp.asarray(thetas)))


def test_condensed_body_rigid_motion_is_the_corner_gap_derivative(hybrid):
    # a condensed wheel (hybrid pair) beyond the path: a rigid motion of its rim masters gives
    # the corner gap's derivative (the mortar at the corner with the turned normal); the
    # rotation about the axis to the interface's chord/arc difference (docs/hybrid.md)
    case, sc, thetas, every, Vs, _, _ = hybrid
    pair, member = case.pair, sc.members[1]
    assert isinstance(member, jg.scenes.FlexibleMember)
    g = pair.path_of_contact
    dofs = np.asarray(member.rim_dofs)
    Z, n_ax, _ = dofs.shape
    ang = float(member.station0) + float(member.pitch_angle) * np.arange(Z)
    R = float(member.rim_radius)
    checked = 0
    for p, theta in enumerate(thetas):
        cells = jax.tree.map(lambda a, p=p: a[p], every)
        V = np.asarray(Vs[p])
        s, mask = np.asarray(cells.s), np.asarray(cells.mask)
        rot = float(member.frame_angle(theta))
        for i, j in zip(*np.nonzero(mask & ((s < 0) | (s > g))), strict=True):
            if abs(s[i, j] - (0 if s[i, j] < 0 else g)) < 0.3 * pair.base_pitch * 0.05:
                continue
            d = _gap_derivative(pair, float(s[i, j]))  # −∂gap/∂(φ1, φ2, x1, y1, x2, y2)
            for a_b, w_z, want, tol in (
                (np.array([1.0, 0.0, 0.0]), 0.0, None, 2e-5),  # ε interpolated
                (np.array([0.0, 1.0, 0.0]), 0.0, None, 2e-5),
                (np.zeros(3), 1.0, -d[1], 2e-3),  # the wheel turns about −z
            ):
                X = np.zeros(sc.structure.K.shape[0])
                for k in range(Z):
                    for m in range(n_ax):
                        x = np.array([R * math.cos(ang[k]), R * math.sin(ang[k]), 0.0])
                        X[dofs[k, m]] = a_b + np.cross([0.0, 0.0, w_z], x)
                if want is None:  # the translation in the fixed frame
                    c, sn = math.cos(rot), math.sin(rot)
                    a = np.array([c * a_b[0] - sn * a_b[1], sn * a_b[0] + c * a_b[1]])
                    want = d[4:6] @ a
                got = float(V[i, j] @ X)
                assert got == pytest.approx(want, rel=tol, abs=tol * abs(d[1])), (s[i, j], a_b)
            checked += 1
    assert checked >= 2


def _rolled(V, mask, roll):
    """|V·roll| of every cell in contact reach (the masked ones), (c,)."""
    V = np.asarray(V).reshape(-1, np.asarray(V).shape[-1])
    return np.abs(V[np.asarray(mask).reshape(-1)] @ roll)


def test_a_pairs_rolling_closes_no_corner_in_any_scene_kind():
    # a pair's rolling (both gears turning at the conjugate ratio, centres fixed: θ1 = 1/r_b1,
    # θ2 = 1/r_b2 in their directions of motion, a unit roll of the base plane) moves the cells
    # along the path, which their positions (the nominal motion) do not follow: a rolling held
    # by a soft support (a pair's output shaft, a gearbox's hold) must close no cell's gap,
    # corner cells included; the exact derivative moves a corner by (1 - λ) cos β_b per unit
    # roll. The rows every solver takes: the torsional pair's (quasi-static; and as a gearbox
    # stage takes it), the torsional dynamics', the lumped pair's and a torsional idler
    # train's (the train's rolling: the null space of its meshes' TE vectors, found here).
    # The hybrid pair's: test_hybrid_free_drive_rotation_carries_no_contact_force
    pair = _pair()
    mesh = _mesh(pair)
    idler = _mesh(_pair(40, 30))
    rb1, rb2 = float(mesh.base_radius_pinion), float(mesh.base_radius_gear)
    g = float(mesh.path_of_contact)
    lumped = _lumped(pair, mesh)
    (m1, m2) = (m.dofs for m in lumped.members)
    dyn = js.TorsionalDynamics(mesh, 1e-3, 4e-3, has_motor=True, has_load=True)
    train = js.torsional_train(((mesh, (0, 1)), (idler, (1, 2))), (1e-3, 4e-3, 2e-3))
    U = np.asarray(train.te_vectors())
    train_roll = scipy.linalg.null_space(U)[:, 0]
    assert train_roll.size == 3 and np.abs(train_roll).min() > 0.1 * np.abs(train_roll).max()
    pair_roll = np.array([1.0 / rb1, 1.0 / rb2])
    lumped_roll = np.zeros(lumped.structure.size)
    lumped_roll[m1[5]], lumped_roll[m2[5]] = 1.0 / rb1, -1.0 / rb2  # the gear turns about −z

    @eqx.filter_jit
    def rows(theta):
        cells = mesh.cells(theta)
        zero = (jnp.zeros_like(cells.s),)
        tc = tuple(m.cells(a) for m, a in zip((mesh, idler), train.mesh_angles(theta)))
        return (
            cells,
            js.TorsionalPair(mesh).cell_vectors(cells),
            js.TorsionalPair(mesh).cell_row((cells,), zero).V,
            dyn.cell_row((cells,), zero).V,
            lumped.cell_row((cells,), zero).V,
            train.cell_row(tc, tuple(jnp.zeros_like(c.s) for c in tc)).V,
            jnp.concatenate([c.mask.reshape(-1) for c in tc]),
        )

    corners = 0
    for theta in np.linspace(0.0, float(mesh.mesh_period_angle), 16, endpoint=False) + 1e-4:
        cells, exact, torsional, dynamic, lumped_v, train_v, train_mask = rows(
            jnp.asarray(theta)
        )
        s, mask = np.asarray(cells.s), np.asarray(cells.mask)
        beyond = (mask & ((s < 0) | (s > g))).reshape(-1)
        corners += int(beyond.sum())
        # the exact derivative moves a corner's gap as the pair rolls (λ ≤ 0.99 there)
        moved = _rolled(exact, np.ones_like(mask), pair_roll)
        assert np.all(moved[beyond] > 1e-3), moved[beyond]
        assert np.all(moved[~beyond & mask.reshape(-1)] < 1e-12)
        for V, m, roll in (
            (torsional, mask, pair_roll),
            (dynamic, mask, np.r_[0.0, pair_roll, 0.0]),
            (lumped_v, mask, lumped_roll),
            (train_v, train_mask, train_roll),
        ):
            np.testing.assert_allclose(_rolled(V, m, roll), 0.0, atol=1e-12)
        # on the path the rows are the exact vectors, bit for bit
        on = (mask & (s >= 0) & (s <= g)).reshape(-1)
        np.testing.assert_array_equal(
            np.asarray(torsional)[on], np.asarray(exact).reshape(-1, 2)[on]
        )
    assert corners >= 4


def test_a_torsional_pairs_te_does_not_depend_on_its_output_shaft_beyond_the_path():
    # the torsional pair is statically determinate: its output shaft's twist rolls the pair
    # (0.45 mm at 300 N·m on the default 1e5 N·m/rad, 1.5 mm on 3e4) and must not change the
    # TE, beyond the path too: with the exact levers the corners saw that rolling (the TE
    # moved by up to 10 µm of its 10.7 µm peak-to-peak on 1e5 N·m/rad; on 3e4 the corners
    # closed past the extension's end). The rows take the pinion's lever with the gear held:
    # the rigid pair's (the pinion's advance, the gear held rigidly, as the FE reference),
    # whatever the shaft
    pair = _pair()
    mesh = _mesh(pair)
    solve = eqx.filter_jit(lambda scene: jg.quasi_static(scene, None, 300.0))
    rigid = np.asarray(solve(js.RigidMesh(mesh)).mesh.transmission_error)
    assert np.ptp(rigid) > 5e-6
    for k in (3e4, 1e5, 1e9):
        te = np.asarray(solve(js.TorsionalPair(mesh, k)).mesh.transmission_error)
        np.testing.assert_allclose(te, rigid, rtol=0.0, atol=1e-9 * np.abs(rigid).max())


def test_free_drive_rotation_stays_free_in_a_dynamic_scene():
    # a corner cell's gap changes as the mesh position moves (its vector has a part along the
    # drive rotation R), but a dynamic scene's nominal motion sets the mesh position: the rows
    # the solvers use keep V·R = 0 (the rigid modes' contract), the part along R taken off
    # along M R on the mesh's DOFs; on the path nothing changes
    pair = _pair()
    mesh = _mesh(pair)
    scene = _lumped(pair, mesh)
    s = -0.5 * float(mesh.extension_span[0])
    cells = _cells(mesh, jnp.asarray(_theta_at(mesh, s)))
    k = _cell(cells, s)
    exact = np.asarray(_vectors(scene, cells))
    row = eqx.filter_jit(lambda sc, c: sc.cell_row((c,), (jnp.zeros_like(c.s),)))(scene, cells)
    used = np.asarray(row.V).reshape(exact.shape)
    R = np.asarray(scene.rigid_modes())[:, 0]
    assert abs(exact[k, 0] @ R) > 1e-3 * np.abs(exact[k, 0]).max() * np.abs(R).max()
    assert abs(used[k, 0] @ R) < 1e-12 * np.abs(exact[k, 0]).max() * np.abs(R).max()
    on = (
        np.asarray(cells.mask)
        & (np.asarray(cells.s) >= 0)
        & (np.asarray(cells.s) <= pair.path_of_contact)
    )
    np.testing.assert_array_equal(used[on], exact[on])
    # the difference lies along M R on the two gear nodes
    G = np.asarray(scene.mass()) @ R
    dofs = [d for m in scene.members for d in m.dofs]
    diff = used[k, 0] - exact[k, 0]
    g = np.zeros_like(G)
    g[dofs] = G[dofs]
    np.testing.assert_allclose(diff, (diff @ g) / (g @ g) * g, atol=1e-12 * np.abs(diff).max())
    # the torsional dynamics: the drive rotation is a rigid mode again (no corner stiffness)
    import jaxgear.dynamics as jd

    dyn = jg.scenes.TorsionalDynamics(mesh, 1e-3, 4e-3)
    model = jd.dynamic_model(dyn, None, 400.0)
    modes = jd.mesh_averaged_modes(model)
    assert int(np.sum(np.asarray(modes.rigid))) == 1


def test_hybrid_free_drive_rotation_carries_no_contact_force(hybrid):
    # the hybrid pair's dynamics turn freely as a whole (pinion chain, wheel and its body at
    # the ratio): its rigid mode is the null space of K (two chains, tests/_hybrid_util) that
    # moves no TE, and the rows the solvers use carry no force along it, corner cells too
    # (without the drive-rotation step its mesh-averaged modes had a 36 Hz mode in its place)
    from _hybrid_util import drive_rotations

    case, sc, thetas, every, Vs, idx, rowV = hybrid
    null = drive_rotations(sc)  # (n, 2), K null = 0
    u = np.asarray(sc.meshes[0].te)
    c = np.linalg.svd((u @ null)[None])[2][-1]
    ref = null @ c
    R = np.asarray(sc.rigid_modes())[:, 0]
    np.testing.assert_allclose(
        R / np.linalg.norm(R) * np.sign(R @ ref), ref / np.linalg.norm(ref), atol=1e-9
    )
    g = case.pair.path_of_contact
    beyond = 0
    for p in range(len(thetas)):
        exact = np.asarray(Vs[p])
        V = np.zeros(exact.shape)
        V.reshape(-1, V.shape[-1])[:, np.asarray(idx[p])] = np.asarray(rowV[p])
        s, mask = np.asarray(every.s[p]), np.asarray(every.mask[p])
        corner = mask & ((s < 0) | (s > g))
        beyond += int(corner.sum())
        scale = np.abs(exact).max() * np.abs(R).max()
        assert np.abs(V[mask] @ R).max() < 1e-10 * scale
        if corner.any():  # the exact derivative has a part along it there
            assert np.abs(exact[corner] @ R).max() > 1e-4 * scale
    assert beyond > 0
