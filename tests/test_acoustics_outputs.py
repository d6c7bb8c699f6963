"""Radiated noise from a housing: the housing's outer skin closed by
caps over its bores (fem_prep.housing.closed_outer_surface) against the box's analytic area and
volume, and the acoustic outputs of ``jaxgear run`` (jaxgear.cli's acoustic_outputs, the
``[acoustics]`` table) on radiators whose power is known: a baffled rigid piston (Rayleigh),
a pulsating sphere (ERP and BEM)."""

from __future__ import annotations

import math

import jax
import numpy as np
import pytest
from scipy import special

import fem_prep.acoustics as fa
import jaxgear.acoustics as ja
import jaxgear.io as jio
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    closed_outer_surface,
    mesh_box,
    outer_surface,
)
from jaxgear.cli.run import acoustic_outputs

L, W, H, T = 0.3, 0.2, 0.16, 0.01
BORES = (Bore("x-", (0.1, 0.08), 0.025), Bore("x+", (0.1, 0.08), 0.025), Bore("z+", (0.2, 0.1), 0.03))


def _housing(size=0.02, element=None):
    box = HousingBox(L, W, H, T, bores=BORES, feet=(Foot((0.0, 0.03), (0.0, 0.03)),))
    return mesh_box(box, size, element=element)


@pytest.mark.parametrize("element", [None, Tet4()])
def test_closed_outer_surface_is_the_box(element):
    """The skin with its bores capped: every edge in exactly two triangles, every normal
    outward (n · (x - centre) > 0 on a box), area 2(LW + LH + WH) and enclosed volume L W H
    exactly (the caps lie in the walls' outer planes), one cap per bore, each in its wall's
    plane and of area π r² up to the staircase of cells (within perimeter × cell diagonal), the
    skin's area plus the caps' the box's."""
    hm = _housing(element=element)
    skin = outer_surface(hm)
    rs = closed_outer_surface(hm, skin)
    s = rs.surface
    edges = np.sort(np.concatenate([s.triangles[:, [0, 1]], s.triangles[:, [1, 2]],
                                    s.triangles[:, [2, 0]]]), axis=1)
    _, counts = np.unique(edges, axis=0, return_counts=True)
    assert np.all(counts == 2)
    centre = np.array([L / 2, W / 2, H / 2])
    assert np.all(np.sum(s.normals * (s.centroids - centre), axis=1) > 0)
    box_area = 2 * (L * W + L * H + W * H)
    assert s.areas.sum() == pytest.approx(box_area, rel=1e-12)
    v = s.vertices[s.triangles]
    volume = np.einsum("ij,ij->", v[:, 0], np.cross(v[:, 1], v[:, 2])) / 6
    assert volume == pytest.approx(L * W * H, rel=1e-12)
    assert len(rs.cap_vertices) == len(BORES)
    assert skin.area + rs.cap_area == pytest.approx(box_area, rel=1e-12)
    h = 0.02 * math.sqrt(2)
    cap_of_triangle = s.triangles[rs.cap_triangles, 2]  # the fan's centre
    for b, c in zip(BORES, rs.cap_vertices, strict=True):
        axis = "xyz".index(b.wall[0])
        plane = 0.0 if b.wall[1] == "-" else (L, W, H)[axis]
        mine = rs.cap_triangles[cap_of_triangle == c]
        pts = np.unique(s.triangles[mine])
        assert np.allclose(s.vertices[pts, axis], plane, atol=1e-12)
        area = s.areas[mine].sum()
        assert abs(area - math.pi * b.radius**2) <= 2 * math.pi * b.radius * h


def test_closed_outer_surface_normal_operator():
    """The vertex normal displacement of a rigid translation u = (1, 0, 0): +1 on the x+ wall's
    vertices off its edges, -1 on the x- wall's, 0 on the y and z walls', and on each cap's
    centre the wall's value (the rim's mean: the cap interpolates)."""
    hm = _housing()
    rs = closed_outer_surface(hm)
    s = rs.surface
    u = np.tile([1.0, 0.0, 0.0], hm.n_dofs // 3)
    d = rs.normal_operator @ u
    x = s.vertices
    inner = np.all((x > 1e-9) & (x < np.array([L, W, H]) - 1e-9), axis=1)
    on = lambda axis, value: np.isclose(x[:, axis], value) & np.all(
        [(x[:, k] > 1e-9) & (x[:, k] < (L, W, H)[k] - 1e-9) for k in range(3) if k != axis],
        axis=0)
    assert not inner.any()
    assert np.allclose(d[on(0, L)], 1.0) and np.allclose(d[on(0, 0.0)], -1.0)
    for axis in (1, 2):
        for value in (0.0, (L, W, H)[axis]):
            assert np.allclose(d[on(axis, value)], 0.0, atol=1e-12)
    expected = [-1.0, 1.0, 0.0]  # the x-, x+ and z+ bores
    assert np.allclose(d[rs.cap_vertices], expected, atol=1e-12)


def test_closed_outer_surface_on_midside_nodes_carries_the_quadratic_field():
    """A Tet10 plate bending in its (1,1) shape, u_z = sin(πx/a) sin(πy/b) at every FE node:
    the mean square normal velocity of the BEM skin's P1 field (vᵀ M v, M its mass matrix)
    against ∫ (u_h·n)² dS of the quadratic FE field by scikit-fem's facet quadrature on the
    quadratic faces (order 6, independent of the skin). On the corner nodes alone the P1 field
    falls 23 % and 6.8 % short (4 × 3 and 8 × 6 cells); cut on the midside nodes 6.2 % and
    1.7 %: a quarter (P1's O(h²) with h halved), within 2 % on 8 × 6 cells. The cut skin is
    closed, of the same area, its vertices every skin node."""
    from skfem import FacetBasis, Functional
    from skfem.helpers import dot

    from fem_prep.housing import mesh_plate

    a, b = 0.4, 0.3
    for cells, corner_err, mid_err in (((4, 3), 0.20, 0.07), ((8, 6), 0.06, 0.02)):
        hm = mesh_plate(a, b, 0.01, cells)
        skin = outer_surface(hm)
        x = hm.nodes
        u = np.zeros((len(x), 3))
        u[:, 2] = np.sin(np.pi * x[:, 0] / a) * np.sin(np.pi * x[:, 1] / b)
        u = u.ravel()
        fb = FacetBasis(hm.mesh, hm.basis.elem, facets=skin.facets, intorder=6)
        exact = Functional(lambda w: dot(w["u"], w.n) ** 2).assemble(fb, u=fb.interpolate(u))
        err = {}
        for mid in (False, True):
            rs = closed_outer_surface(hm, skin, midside_nodes=mid)
            v = rs.normal_operator @ u
            err[mid] = float(v @ rs.surface.mass_matrix() @ v) / exact - 1
            e = np.sort(np.concatenate([rs.surface.triangles[:, [0, 1]],
                                        rs.surface.triangles[:, [1, 2]],
                                        rs.surface.triangles[:, [2, 0]]]), axis=1)
            assert np.all(np.unique(e, axis=0, return_counts=True)[1] == 2)
            assert rs.surface.areas.sum() == pytest.approx(skin.area, rel=1e-12)
        assert err[False] < -corner_err and -mid_err < err[True] < 0
        assert abs(err[True]) < abs(err[False]) / 3
        nodes = np.unique(hm.scalar_basis.get_dofs(skin.facets).flatten())
        assert sorted(rs.mesh_vertices) == sorted(nodes)


def test_closed_outer_surface_refuses_bad_input():
    with pytest.raises(TypeError, match="HousingMesh"):
        closed_outer_surface("box")
    with pytest.raises(ValueError, match="DOFs"):
        closed_outer_surface(_housing(), outer_surface(_housing(0.04)))


# -- the power and pressure between grid frequencies (jaxgear.acoustics) ------------------------


def test_vertex_areas_are_a_third_of_each_triangle_round_the_vertex():
    """``RadiatingSurface.vertex_areas`` (the area an intensity map divides a vertex's power
    by): on a regular tetrahedron of edge 2√2 each vertex meets three faces of area 2√3, so
    its share is 2√3 (by hand); on the housing's closed skin the shares are the row sums of the
    P1 mass matrix (assembled apart, 1e-12) and sum to the surface's area."""
    tet = fa.RadiatingSurface(
        np.array([[1.0, 1.0, 1.0], [1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, -1.0, 1.0]]),
        np.array([[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]]))
    np.testing.assert_allclose(tet.vertex_areas, [2 * math.sqrt(3)] * 4, rtol=1e-14)
    skin = closed_outer_surface(_housing(0.04)).surface
    np.testing.assert_allclose(skin.vertex_areas, skin.mass_matrix().sum(axis=1), rtol=1e-12)
    assert skin.vertex_areas.sum() == pytest.approx(skin.areas.sum(), rel=1e-12)


def test_power_between_grid_frequencies_is_exact_for_a_power_law():
    """R(f) = (f/f₀)^m R₀ (a compact source: m = 2 a monopole, 4 a dipole): the log-log
    interpolation gives W(f) = (f/f₀)^m v^H R₀ v at any f inside the grid, and NaN outside."""
    rng = np.random.default_rng(0)
    n, r = 7, 3
    L0 = rng.normal(size=(n, r)) + 1j * rng.normal(size=(n, r))
    v = rng.normal(size=(5, n)) + 1j * rng.normal(size=(5, n))
    grid = np.array([100.0, 150.0, 400.0, 1000.0])
    f = np.array([100.0, 123.0, 399.0, 777.0, 1000.0])
    w0 = np.sum(np.abs(v @ L0.conj()) ** 2, axis=1)
    for m in (2, 4):
        L = (grid[:, None, None] / 100.0) ** (m / 2) * L0
        W = ja.radiated_power_at(v, f, L, grid)
        np.testing.assert_allclose(W, (f / 100.0) ** m * w0, rtol=1e-12)
    assert np.all(np.isnan(ja.radiated_power_at(v[:2], [99.0, 1001.0], L, grid)))


def test_intensity_between_grid_frequencies_sums_to_the_power():
    """The radiated intensity I_j = Re(v_j* (R v)_j) / A_j: at a grid frequency from R = L Lᴴ
    itself; for R(f) = (f/f₀)^m R₀ (a compact source) (f/f₀)^m I₀ at any f inside the grid (the
    pattern fixed, the level the power law's); and between grid frequencies of an R that is no
    power law (two radiation modes of different slopes) its total Σ I_j A_j equals
    radiated_power_at's W, which the map prints beside it (1e-12); NaN outside the grid."""
    rng = np.random.default_rng(1)
    n, r = 6, 2
    L0 = rng.normal(size=(n, r)) + 1j * rng.normal(size=(n, r))
    v = rng.normal(size=(4, n)) + 1j * rng.normal(size=(4, n))
    areas = rng.uniform(0.5, 2.0, n)
    grid = np.array([100.0, 180.0, 500.0])
    f = np.array([100.0, 131.0, 180.0, 444.0])
    R0 = L0 @ L0.conj().T
    I0 = np.real(v.conj() * (v @ R0.T)) / areas
    L = (grid[:, None, None] / 100.0) ** 1.5 * L0
    np.testing.assert_allclose(ja.radiated_intensity_at(v, f, L, grid, areas),
                               (f[:, None] / 100.0) ** 3 * I0, rtol=1e-12)
    slopes = np.array([1.0, 2.0])  # mode k's resistance ∝ f^(2 slope_k)
    L2 = (grid[:, None, None] / 100.0) ** slopes[None, None, :] * L0
    I = np.asarray(ja.radiated_intensity_at(v, f, L2, grid, areas))
    np.testing.assert_allclose(I @ areas, ja.radiated_power_at(v, f, L2, grid), rtol=1e-12)
    assert np.all(np.isnan(ja.radiated_intensity_at(v[:1], 501.0, L2, grid, areas)))


def test_power_between_grid_frequencies_plate_and_gradient():
    """A baffled plate's (1,1) and (2,1) modes (Rayleigh) at frequencies a quarter (in log) into
    the intervals of a grid of ratio 1.1 between grid frequencies: within 1 % of the power from R
    computed at those frequencies, and converging as the square of the step (the same
    frequencies halfway into a grid of ratio √1.1: the error at least halves; t(1 − t)h² gives
    a third); the gradient with respect to the velocity's real part matches central
    differences."""
    plate = fa.rectangular_panel(1.0, 0.8, 10, 8)
    x, y = plate.vertices[:, 0], plate.vertices[:, 1]
    v = np.stack([np.sin(np.pi * x) * np.sin(np.pi * y / 0.8),
                  np.sin(2 * np.pi * x) * np.sin(np.pi * y / 0.8)]) * 1e-3 + 0j
    coarse = 200.0 * 1.1 ** np.arange(8)
    fine = 200.0 * 1.1 ** (np.arange(15) / 2)
    mid = coarse[:-1] * 1.1**0.25
    exact = fa.radiation_resistance(plate, mid, method=fa.Rayleigh(), cache=False)
    errors = []
    for grid in (coarse, fine):
        rr = fa.radiation_resistance(plate, grid, method=fa.Rayleigh(), cache=False)
        for k in range(2):
            vk = np.broadcast_to(v[k], (len(mid), len(x)))
            W = np.asarray(ja.radiated_power_at(vk, mid, rr.factors, grid))
            errors.append(np.max(np.abs(W / exact.power(vk) - 1)))
    assert max(errors[:2]) < 0.01
    assert errors[2] < errors[0] / 2 and errors[3] < errors[1] / 2
    grid = coarse
    rr = fa.radiation_resistance(plate, grid, method=fa.Rayleigh(), cache=False)
    g = jax.jit(jax.grad(lambda a: ja.radiated_power_at(a + 0j, mid[2], rr.factors, grid)))(
        v[0].real
    )
    e = np.zeros_like(v[0].real)
    e[17], h = 1.0, 1e-6
    fd = (ja.radiated_power_at(v[0] + h * e, mid[2], rr.factors, grid)
          - ja.radiated_power_at(v[0] - h * e, mid[2], rr.factors, grid)) / (2 * h)
    assert float(g[17]) == pytest.approx(float(fd), rel=1e-6)


# -- acoustic_outputs (jaxgear run's acoustics/) ------------------------------------------------


def _csv(path):
    import csv

    with open(path) as fh:
        rows = list(csv.DictReader(fh))
    return {k: np.array([float(r[k]) for r in rows]) for k in rows[0]}


#: IEC 61672-1 Table 3, the A weighting at nominal frequencies (dB)
IEC_A = {315.0: -6.6, 500.0: -3.2, 630.0: -1.9, 800.0: -0.8, 1000.0: 0.0}


def test_acoustic_outputs_baffled_piston(tmp_path):
    """A rigid piston of radius a = 0.1 m in a baffle (Rayleigh), v₀ = 1 mm/s, at orders 1 and 2
    of speeds putting order 1 at 315 … 1000 Hz: each order's W within 1 % of
    ½ρc πa² v₀² (1 − J₁(2ka)/ka) (Kinsler §7.5), L_WA = L_W + A(f) within 0.1 dB of IEC 61672-1
    Table 3, the overall the energetic sum of the orders, the on-axis microphone at z = 2 m
    within 0.2 dB of |p| = 2ρc v₀ |sin(k(√(z² + a²) − z)/2)|, every file written, and the
    intensity map's total (Σ I_j A_j over intensity.vtu, A_j a third of each triangle round
    vertex j) the printed power of each order at the map's speed (order 1's frequency between
    the grid's; 1e-9)."""
    import meshio

    a, v0 = 0.1, 1e-3
    disc = fa.disc_panel(a, 8)
    f1 = np.array(sorted(IEC_A))
    speeds = 2 * np.pi * f1
    orders = np.array([1.0, 2.0])
    vel = np.full((len(speeds), 2, disc.n_vertices), v0 + 0j)
    table = {"method": "rayleigh", "frequencies": 16, "cache": False,
             "microphones": [{"name": "axis", "position_mm": [0.0, 0.0, 2000.0]}]}
    sec = acoustic_outputs(disc, vel, speeds, orders, str(tmp_path), table, name="piston")
    out = tmp_path / "acoustics"
    for f in ("sound_power.csv", "sound_power.json", "sound_power.png", "microphones.csv",
              "microphones.png", "intensity.vtu", "intensity.png"):
        assert (out / f).stat().st_size > 0 and f"acoustics/{f}" in sec["files"]
    d = _csv(out / "sound_power.csv")
    rho_c, c = fa.AIR.impedance, fa.AIR.sound_speed
    for o in (1, 2):
        ka = 2 * np.pi * o * f1 * a / c
        W = 0.5 * rho_c * np.pi * a**2 * v0**2 * (1 - special.j1(2 * ka) / ka)
        np.testing.assert_allclose(d[f"order_{o}_W_W"], W, rtol=0.01)
    LA = d["order_1_LWA_dBA"] - d["order_1_LW_dB"]
    np.testing.assert_allclose(LA, [IEC_A[f] for f in f1], atol=0.1)
    total = 10 * np.log10((d["order_1_W_W"] + d["order_2_W_W"]) / 1e-12)
    np.testing.assert_allclose(d["overall_LW_dB"], total, atol=1e-9)
    m = _csv(out / "microphones.csv")
    z = 2.0
    k = 2 * np.pi * m["frequency_Hz"] / c
    p = 2 * rho_c * v0 * np.abs(np.sin(k * (np.hypot(z, a) - z) / 2))
    np.testing.assert_allclose(m["axis_Lp_dB"], 20 * np.log10(p / np.sqrt(2) / 20e-6), atol=0.2)
    s_map = int(np.flatnonzero(speeds == sec["map_speed_rad_s"])[0])
    grid = np.asarray(sec["grid_Hz"])
    f_map = np.asarray(sec["frequency_Hz"])[s_map]
    assert not np.any(np.isclose(f_map[0], grid, rtol=1e-6))  # order 1 between grid points
    share = np.zeros(disc.n_vertices)
    for corner in range(3):
        np.add.at(share, disc.triangles[:, corner], disc.areas / 3)
    mesh = meshio.read(out / "intensity.vtu")
    for j, o in enumerate((1, 2)):
        total = float(mesh.point_data[f"order_{o}_intensity_W_m2"] @ share)
        assert total == pytest.approx(sec["power_W"][s_map][j], rel=1e-9)


def test_acoustic_outputs_erp_of_a_pulsating_sphere(tmp_path):
    """erp-only on a sphere breathing uniformly (v₀): W = ½ρc S v₀² with S the polyhedron's area
    at every speed, the intensity in intensity.vtu ½ρc v₀² at every vertex (read back with
    meshio); the e^{iωt} amplitudes' phase does not matter."""
    import meshio

    s = fa.sphere_surface(1.0, 2)
    v0 = 2e-3
    speeds = np.array([100.0, 200.0, 300.0])
    vel = v0 * np.exp(0.3j) * np.ones((3, 1, s.n_vertices))
    sec = acoustic_outputs(s, vel, speeds, [1.0], str(tmp_path),
                           {"method": "erp-only", "cache": False})
    W = 0.5 * fa.AIR.impedance * s.areas.sum() * v0**2
    np.testing.assert_allclose(np.asarray(sec["power_W"])[:, 0], W, rtol=1e-12)
    mesh = meshio.read(tmp_path / "acoustics" / "intensity.vtu")
    np.testing.assert_allclose(mesh.point_data["order_1_intensity_W_m2"],
                               0.5 * fa.AIR.impedance * v0**2, rtol=1e-12)


def test_acoustics_table_refuses_bad_input(tmp_path):
    for bad, match in (
        ({"method": "fmm"}, "method"),
        ({"band_Hz": [400.0, 100.0]}, "band_Hz"),
        ({"frequencies": 0}, "frequencies"),
        ({"bogus": 1}, "unknown key"),
        ({"method": "erp-only", "microphones": [{"position_mm": [0.0, 0.0, 1.0]}]}, "erp-only"),
        ({"microphones": [{"position_mm": [0.0, 1.0]}]}, "position_mm"),
        ({"microphones": [{"name": "a", "position_mm": [0.0, 0.0, 1.0]},
                          {"name": "a", "position_mm": [0.0, 0.0, 2.0]}]}, "name"),
    ):
        with pytest.raises(ValueError, match=match):
            jio.parse_acoustics(bad)
    s = fa.sphere_surface(1.0, 1)
    with pytest.raises(ValueError, match="velocities"):
        acoustic_outputs(s, np.ones((2, 1, 3)), [1.0, 2.0], [1.0], str(tmp_path), {})
    with pytest.raises(ValueError, match="speeds"):
        acoustic_outputs(s, np.ones((1, 1, s.n_vertices)), [-1.0], [1.0], str(tmp_path), {})
    with pytest.raises(TypeError, match="RadiatingSurface"):
        acoustic_outputs("s", np.ones((1, 1, 3)), [1.0], [1.0], str(tmp_path), {})
