"""The ring gear body of fem_prep (fem_prep._ring): a thin annulus with internal teeth' root-patch
masters, its housing supports and its Craig-Bampton condensation.

References: the thin ring's in-plane flexural frequencies (Hoppe 1871; Blevins, Table 9-2),
omega_n^2 = E I n^2 (n^2 - 1)^2 / (rho A R^4 (n^2 + 1)), for h / R = 0.05, b / h = 3; the
condensed model against the full FE model; the support reactions against the applied loads.
"""

import math

import meshio
import numpy as np
import pytest
import scipy.linalg

import fem_prep as fp
from fem_prep import schema

R_F, R_O, WIDTH = 0.0975, 0.1025, 0.015  # h / R = 0.05, b / h = 3
SIGMA_FREE = -((2 * math.pi * 200) ** 2)


def ring(size=0.005, circ=0.013, support=None, modes=30, teeth=24, nax=2):
    return fp.RingBody(
        "test-ring",
        R_F,
        R_O,
        WIDTH,
        fp.Material(),
        fp.MeshSettings(fp.Hex20(), size=size, circumferential_size=circ),
        fp.Condensation(
            fp.CraigBampton(), fp.Distributing(), modes=modes, teeth=teeth, axial_master_nodes=nax
        ),
        fp.FreeRing() if support is None else support,
    )


def in_plane_nd(prep, n_modes=14):
    """{n: f (Hz)} of the full model's in-plane flexural modes n = 2, 3, 4 (each a pair)."""
    f, shapes = prep.full_modes(n_modes, sigma=SIGMA_FREE)
    out = {}
    for k in range(n_modes):
        n, inplane = fp.mode_nodal_diameter(prep, shapes[:, k])
        if inplane > 0.9 and n in (2, 3, 4):
            out.setdefault(n, []).append(f[k])
    return out


@pytest.fixture(scope="module")
def free_ring():
    return fp.prepare_ring(ring())


def test_thin_ring_formula_by_hand():
    # omega_2^2 = E I 4 * 9 / (rho A R^4 5) written out for the test ring
    r = ring()
    h, b, R = R_O - R_F, WIDTH, 0.1
    w2 = 210e9 * b * h**3 / 12 * 36 / (7800 * b * h * R**4 * 5)
    assert fp.thin_ring_frequency(r, 2) == pytest.approx(math.sqrt(w2) / (2 * math.pi), rel=1e-14)


def test_free_ring_in_plane_modes_match_thin_ring_theory(free_ring):
    """n = 2, 3, 4: degenerate pairs within 2 % of the thin-ring formula (h / R = 0.05: the
    curved-beam assumptions hold to about (n h / R)^2 / 12 ~ 0.3 % plus the coarse mesh's
    stiffening; the converged FE values are in the slow test)."""
    modes = in_plane_nd(free_ring)
    ref = fp.thin_ring_frequency(free_ring.ring, [2, 3, 4])
    for n, f_ref in zip((2, 3, 4), ref):
        pair = modes[n]
        assert len(pair) == 2
        assert pair[1] == pytest.approx(pair[0], rel=1e-6)
        assert pair[0] == pytest.approx(f_ref, rel=0.02)


def test_condensed_modes_match_full_model(free_ring):
    """The Craig-Bampton model on the root-patch masters: its lowest elastic modes (the n = 2
    in-plane and out-of-plane pairs, n = 3) within 0.1 % of the full FE model's."""
    f_full, _ = free_ring.full_modes(16, sigma=SIGMA_FREE)
    f_c = free_ring.condensed_frequencies()[:16]
    elastic = f_full > 1.0
    assert np.sum(~elastic) == 6  # the free ring's rigid motions
    assert np.all(np.abs(f_c[elastic] / f_full[elastic] - 1) < 1e-3)
    assert np.all(f_c[elastic] >= f_full[elastic] * (1 - 1e-9))  # a Ritz basis: from above


def test_foundation_reactions_balance_tooth_loads():
    """Loads on a few stations of a ring on an elastic foundation: the foundation's reactions
    (recovered from the condensed solve) balance the loads' force and moment about the axis."""
    prep = fp.prepare_ring(
        ring(support=fp.ElasticFoundation(1e13, 1e13, 1e13), modes=4, teeth=12, circ=0.026)
    )
    teeth, nax, _ = prep.master_dofs.shape
    P = np.zeros((teeth, nax, 3))
    P[0, :, :] = [300.0, 1000.0, 50.0]
    P[7, 0, :] = [-250.0, 400.0, 0.0]
    P[9, 1, :] = [0.0, -800.0, -20.0]
    u = prep.static(P)
    r = prep.support_reactions(u).reshape(-1, 3)
    x_m = prep.coupled.rim_positions.reshape(-1, 3)
    x = prep.mesh.nodes
    F = P.reshape(-1, 3)
    scale = np.abs(F).sum()
    assert np.allclose(r.sum(0), -F.sum(0), atol=1e-9 * scale)
    moment = np.cross(x, r).sum(0) + np.cross(x_m, F).sum(0)
    assert np.allclose(moment, 0.0, atol=1e-9 * scale * R_O)


def test_bolted_flange_holds_the_ring_and_stiffens_it():
    """Clamped bolt seats: no rigid mode, and the n = 2 flexural pair above the free ring's."""
    free = ring(modes=10)
    bolted = fp.prepare_ring(
        ring(support=fp.BoltedFlange(bolts=6, seat_arc=0.006), modes=4, teeth=12, circ=0.026)
    )
    f = bolted.condensed_frequencies()
    assert f[0] > fp.thin_ring_frequency(free, 2)
    F, ang = fp.ring_master_compliance(bolted)
    assert F.shape == (12, 2, 12, 2) and np.allclose(ang[1], 2 * math.pi / 12)
    Fm = F.reshape(24, 24)
    assert np.allclose(Fm, Fm.T) and np.all(np.linalg.eigvalsh(Fm) > 0)


def test_bad_ring_inputs_name_the_parameter():
    with pytest.raises(ValueError, match="outer_radius"):
        fp.RingBody(
            "x", 0.1, 0.09, 0.01, fp.Material(), ring().mesh, ring().condensation, fp.FreeRing()
        )
    with pytest.raises(ValueError, match="bolts"):
        fp.BoltedFlange(bolts=0)
    with pytest.raises(ValueError, match="tangential"):
        fp.ElasticFoundation(1e12, 0.0, 1e12)
    with pytest.raises(ValueError, match="FreeRing"):
        fp.ring_master_compliance(fp.prepare_ring(ring(modes=2, teeth=12, circ=0.026)))


def test_elastic_foundation_resultants_by_hand():
    """The foundation's resultant for a rigid translation along x is pi R_o b (k_r + k_t) and
    for a rigid turn theta its torque is 2 pi R_o^3 b k_t theta (int of the springs over the
    outer cylinder), to the quadratic arcs' area error (24 elements around: ~5e-6)."""
    kr, kt, ka = 3e12, 1e12, 2e12
    r = ring(support=fp.ElasticFoundation(kr, kt, ka), teeth=12, circ=0.026)
    bm = fp.mesh_ring(r)
    Ks = r.support.foundation(r, bm)
    x = bm.nodes
    u = np.zeros_like(x)
    u[:, 0] = 1.0
    f = (Ks @ u.ravel()).reshape(-1, 3)
    area = 2 * math.pi * R_O * WIDTH
    assert f[:, 0].sum() == pytest.approx(area * (kr + kt) / 2, rel=2e-5)
    assert abs(f[:, 1].sum()) < 1e-9 * f[:, 0].sum()
    theta = 1e-3
    u = theta * np.stack([-x[:, 1], x[:, 0], np.zeros(len(x))], 1)
    f = (Ks @ u.ravel()).reshape(-1, 3)
    torque = np.sum(x[:, 0] * f[:, 1] - x[:, 1] * f[:, 0])
    assert torque == pytest.approx(area * R_O**2 * kt * theta, rel=2e-5)
    u = np.zeros_like(x)
    u[:, 2] = 1.0
    assert (Ks @ u.ravel()).reshape(-1, 3)[:, 2].sum() == pytest.approx(area * ka, rel=2e-5)


@pytest.mark.slow
def test_free_ring_modes_converge_under_refinement():
    """Three meshes (24, 48, 96 elements around; 2 x 6 across the section): the in-plane
    n = 2, 3, 4 frequencies converge (each refinement's change at least 8 times smaller than
    the previous, quadratic elements), to within 1 % below the thin-ring formula (the shear
    and rotary inertia it neglects lower the ring's frequencies)."""
    f = []
    for circ in (0.026, 0.013, 0.0065):
        modes = in_plane_nd(fp.prepare_ring(ring(size=0.0025, circ=circ, modes=0)))
        f.append([modes[n][0] for n in (2, 3, 4)])
    f = np.array(f)
    d1, d2 = np.abs(f[1] - f[0]), np.abs(f[2] - f[1])
    assert np.all(d2 < d1 / 8)
    ref = fp.thin_ring_frequency(ring(), [2, 3, 4])
    assert np.all(f[2] < ref) and np.all(f[2] > 0.99 * ref)


RING_FILE = """
name = "test-ring"
[ring]
root_radius_mm = 97.5
outer_radius_mm = 102.5
width_mm = 15.0
[support]
kind = "elastic_foundation"
radial_N_per_mm3 = 3000.0
tangential_N_per_mm3 = 1000.0
axial_N_per_mm3 = 2000.0
[mesh]
size_mm = 5.0
circumferential_size_mm = 13.0
[condensation]
modes = 30
teeth = 24
axial_master_nodes = 2
"""


def test_ring_body_file():
    """The ring-gear body file: mm, GPa and N/mm^3 in, the test ring's SI values out; an unknown
    key and an unknown support kind refused in one line naming them."""
    got = schema.parse_ring_body(RING_FILE)
    want = ring(support=fp.ElasticFoundation(3e12, 1e12, 2e12))
    for name in ("root_radius", "outer_radius", "width"):
        assert getattr(got, name) == pytest.approx(getattr(want, name), rel=1e-12)
    assert got.material == want.material
    assert got.support == fp.ElasticFoundation(3e12, 1e12, 2e12)
    assert got.mesh.size == pytest.approx(0.005) and got.mesh.circumferential_size == pytest.approx(
        0.013
    )
    assert got.condensation == want.condensation and got.name == "test-ring"
    with pytest.raises(ValueError, match="bolt_count"):
        schema.parse_ring_body(RING_FILE.replace("[mesh]", "[mesh]\nbolt_count = 3"))
    with pytest.raises(ValueError, match="kind"):
        schema.parse_ring_body(RING_FILE.replace('"elastic_foundation"', '"glued"'))
    bolted_support = '[support]\nkind = "bolted_flange"\nbolts = 6\nseat_arc_mm = 6.0\n'
    bolted = schema.parse_ring_body(
        RING_FILE.split("[support]")[0] + bolted_support + "[mesh]" + RING_FILE.split("[mesh]")[1]
    )
    assert bolted.support == fp.BoltedFlange(6, 0.006, 0.0)


def test_ring_vtu_holds_the_mode_shapes(free_ring, tmp_path):
    """The .vtu read back by meshio: the corner nodes, one hexahedron per element, and a mode
    shape's corner values with its frequency and nodal diameter in its name."""
    path = fp.write_ring_vtu(free_ring, tmp_path / "ring.vtu", n_modes=8, sigma=SIGMA_FREE)
    m = meshio.read(path)
    bm = free_ring.mesh
    assert np.allclose(m.points, bm.nodes[: bm.n_vertices])
    assert np.array_equal(m.cells_dict["hexahedron"], bm.cells)
    f, shapes = free_ring.full_modes(8, sigma=SIGMA_FREE)
    name = next(k for k in m.point_data if k.startswith("mode_07_"))
    assert name == f"mode_07_{f[6]:.0f}Hz_ND2"
    # mode 7 is one of the n = 2 pair (7, 8): in the span of this solve's pair
    pair = shapes[:, 6:8].reshape(-1, 3, 2)[: bm.n_vertices].reshape(-1, 2)
    v = m.point_data[name].ravel()
    c = np.linalg.lstsq(pair, v, rcond=None)[0]
    assert np.linalg.norm(pair @ c - v) < 1e-8 * np.linalg.norm(v)


@pytest.mark.slow
def test_station_mass_and_frequencies_of_the_embedded_test_ring(tmp_path):
    """fem_prep.ring_stations of the embedded coarse test ring (built into a fresh cache, then
    read back equal): the stations' mass (a static reduction onto the 53 stations' in-plane
    displacements) carries the annulus' mass rho pi (R_o^2 - R_f^2) b in a rigid translation
    (within 1e-4: the soft housing bends the static shape a little), and the station model's
    lowest frequencies of nodal diameters 2 and 3 (eig(F^-1, M_u), in degenerate pairs) are the
    Craig-Bampton ring's within 1 %."""
    body = fp.load_ring_body("seq-test-ring")
    st = fp.ring_stations(body, cache=tmp_path)
    again = fp.ring_stations(body, cache=tmp_path)
    np.testing.assert_array_equal(again.compliance, st.compliance)
    assert again.nd_frequencies == st.nd_frequencies
    z = body.condensation.teeth
    M = st.mass.reshape(2 * z, 2 * z)
    u = np.zeros((z, 2))
    u[:, 0] = 1.0
    rho = body.material.density
    annulus = rho * math.pi * (body.outer_radius**2 - body.root_radius**2) * body.width
    assert u.ravel() @ M @ u.ravel() == pytest.approx(annulus, rel=1e-4)
    lam = scipy.linalg.eigh(np.linalg.inv(st.compliance.reshape(2 * z, 2 * z)), M,
                            eigvals_only=True)
    f = np.sqrt(lam) / (2 * math.pi)
    for n in (2, 3):
        ref = st.nd_frequencies[n]
        near = f[np.argmin(np.abs(f - ref))]
        assert near == pytest.approx(ref, rel=1e-2)
        assert np.sum(np.abs(f / ref - 1) < 1e-2) == 2  # a degenerate pair


def test_three_elements_through_the_rim_prepare():
    """Three elements through the rim (the root face's nodal areas integrated on each facet's
    reference face: skfem's FacetBasis inverted the curved elements' map and failed there): the
    ring prepares, and a uniform radial station load on the ring on its uniform elastic housing
    (an axisymmetric, self-balanced load) gives the same radial displacement at every station
    (1e-6)."""
    prep = fp.prepare_ring(ring(size=0.005 / 3, circ=0.04, modes=0, teeth=8,
                                support=fp.ElasticFoundation(1e11, 1e11, 1e11)))
    F, angles = fp.ring_master_compliance(prep)
    radial = np.stack([np.cos(angles), np.sin(angles)], axis=1)  # (Z, 2)
    u = np.einsum("kalb,lb->ka", F, radial)
    ur = np.sum(u * radial, axis=1)
    assert np.all(ur > 0)
    np.testing.assert_allclose(ur, ur.mean(), rtol=1e-6)


@pytest.mark.slow
def test_free_ring_modes_converge_under_radial_refinement():
    """One, two and three elements through the rim (and across the face), the circumferential
    size kept: the in-plane n = 2, 3, 4 frequencies fall monotonically and each change is at
    least twice smaller than the previous (measured 3.4 to 3.7 times)."""
    f = []
    for k in (1, 2, 3):
        modes = in_plane_nd(fp.prepare_ring(ring(size=0.005 / k, circ=0.013, modes=0)))
        f.append([modes[n][0] for n in (2, 3, 4)])
    f = np.array(f)
    d1, d2 = f[0] - f[1], f[1] - f[2]
    assert np.all(d1 > 0) and np.all(d2 > 0)
    assert np.all(d2 < d1 / 2)
