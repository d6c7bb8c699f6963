"""jaxgear.acoustics: the housing's response to its seat loads and the equivalent radiated power:
a piston-like uniform normal velocity against ½ ρ c v² A, the static
response against a separate SciPy solve of the full FE model, and the gradient of the ERP with
respect to tip relief against central differences."""

import math

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.sparse.linalg as spla
from _housing import one_way_seats

import fem_prep
import jaxgear.io as jio
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    condensed_housing,
    mesh_box,
    mesh_plate,
    outer_surface,
    prepare_housing,
    write_housing_ods_vtu,
)
from jaxgear.acoustics import (
    erp,
    housing_acoustics,
    housing_response,
    seat_forces,
    sound_power_level,
    total_level,
)
from jaxgear.dynamics import HarmonicBalance, whine_response

STEEL = fem_prep.Material(210e9, 0.3, 7800.0)
RHO, C = 1.204, 343.2
FEET = (Foot((0.0, 0.05), (0.0, 0.05)), Foot((0.25, 0.3), (0.15, 0.2)))
BORES = (
    Bore("y-", (0.1, 0.12), 0.03),
    Bore("y+", (0.1, 0.12), 0.03),
    Bore("y-", (0.21, 0.12), 0.025),
    Bore("y+", (0.21, 0.12), 0.025),
)


def _box():
    return mesh_box(HousingBox(0.3, 0.2, 0.2, 0.008, bores=BORES, feet=FEET), 0.05,
                    element=Tet4())


def test_uniform_piston_radiates_half_rho_c_v2_area():
    """A plate moving as a rigid piston along its normal (u = u0 e_z everywhere) at f: its two
    faces have |v_n| = 2π f u0 and its edges none, so ERP = ½ ρ c v² (2 a b); a face alone
    gives ½ ρ c v² a b (Tet10 and Tet4)."""
    a, b, u0, f = 0.4, 0.25, 1e-6, 800.0
    v = 2 * math.pi * f * u0
    for element in (None, Tet4()):
        hm = mesh_plate(a, b, 0.01, (4, 3), element=element)
        s = outer_surface(hm)
        u = np.zeros(hm.n_dofs)
        u[2::3] = u0
        vn = 2j * math.pi * f * (s.normal_operator @ u)
        np.testing.assert_allclose(float(erp(vn, s.areas, RHO, C)), RHO * C * v**2 * a * b,
                                   rtol=1e-12)
        top = s.normals[:, 2] > 0.5
        np.testing.assert_allclose(
            float(erp(vn[top], s.areas[top], RHO, C)), 0.5 * RHO * C * v**2 * a * b, rtol=1e-12
        )
        # the skin is the whole boundary of a plate, normals outward
        np.testing.assert_allclose(s.area, 2 * (a * b + 0.01 * (a + b)), rtol=1e-12)
        np.testing.assert_allclose(np.sum(s.normals * s.areas[:, None], axis=0), 0, atol=1e-12)
    assert float(sound_power_level(1e-12)) == 0.0
    np.testing.assert_allclose(float(total_level(jnp.array([1e-12, 1e-12]))),
                               10 * math.log10(2), rtol=1e-12)


@pytest.mark.parametrize("element", [None, Tet4()])
def test_square_operator_integrates_the_fe_field_exactly(element):
    """‖S u‖² of the skin's square_operator S equals ∫_skin (u_h·n)² dS of the FE field u_h
    (the quadratic Tet10 interpolant of a smooth field, or the linear Tet4 one) integrated
    independently by scikit-fem's facet quadrature of the element's own shape functions
    (order 6, exact for the degree-4 integrand), to 1e-10; the facet means' Σ |ū_f|² A_f
    falls short of it (the ERP's old rule)."""
    from skfem import FacetBasis, Functional
    from skfem.helpers import dot

    hm = mesh_plate(0.3, 0.2, 0.02, (3, 2), element=element)
    s = outer_surface(hm)
    x = hm.nodes
    u = np.stack([np.sin(9 * x[:, 0] + 4 * x[:, 1]), np.cos(7 * x[:, 1] - 30 * x[:, 2]),
                  np.sin(11 * x[:, 0]) * np.cos(13 * x[:, 1])], axis=1).ravel() * 1e-6
    fb = FacetBasis(hm.mesh, hm.basis.elem, facets=s.facets, intorder=6)

    @Functional
    def square(w):
        return dot(w["u"], w.n) ** 2

    exact = square.assemble(fb, u=fb.interpolate(u))
    got = float(np.sum((s.square_operator @ u) ** 2))
    assert got == pytest.approx(exact, rel=1e-10)
    means = float(np.sum((s.normal_operator @ u) ** 2 * s.areas))
    assert means < exact * (1 - 1e-3)


@pytest.fixture(scope="module")
def prepared():
    return prepare_housing(_box(), STEEL, cutoff_hz=4000.0)


def test_box_skin_leaves_out_the_inner_walls_and_bores(prepared):
    """The skin of the closed box is its outer faces: the area of the outside less the bores'
    openings (a staircase of cells), normals outward, no facet inside the walls."""
    hm = prepared.mesh
    s = outer_surface(hm)
    outside = 2 * (0.3 * 0.2 + 0.3 * 0.2 + 0.2 * 0.2)
    holes = 2 * math.pi * (0.03**2 + 0.025**2)
    assert abs(s.area - (outside - holes)) < 0.3 * holes
    c = s.centroids
    on_outside = (
        (np.abs(c[:, 0]) < 1e-9) | (np.abs(c[:, 0] - 0.3) < 1e-9)
        | (np.abs(c[:, 1]) < 1e-9) | (np.abs(c[:, 1] - 0.2) < 1e-9)
        | (np.abs(c[:, 2]) < 1e-9) | (np.abs(c[:, 2] - 0.2) < 1e-9)
    )
    assert on_outside.all()
    centre = np.array([0.15, 0.1, 0.1])
    assert np.all(np.sum(s.normals * (c - centre), axis=1) > 0)


def test_static_response_equals_the_full_fe_solve(prepared, tmp_path):
    """A static load at two seats (forces and a moment): the housing's normal displacement at
    every skin facet and at a named point from the condensed model equals a SciPy sparse solve
    of the full clamped FE model (Craig–Bampton is exact in statics) to 1e-8."""
    hm = prepared.mesh
    ch = prepared.condensed_housing()
    s = outer_surface(hm, {"top": (0.15, 0.1, 0.2), "side": (0.3, 0.1, 0.1)})
    ac = housing_acoustics(ch, s, loss_factor=0.0)  # undamped: the real static solve
    load = np.zeros(6 * len(ch.seat_names))
    load[[0, 2, 4]] = (1e3, -2e3, 50.0)  # seat 0: F_x, F_z (N), M_y (N m)
    load[6 * 2 + 1] = 5e2  # seat 2: F_y
    r = housing_response(ac, jnp.asarray(load), 0.0)
    un = np.asarray(ac.normal_map) @ np.real(np.asarray(r.coordinates))
    up = np.asarray(ac.point_map) @ np.real(np.asarray(r.coordinates))
    rhs = np.zeros(prepared.K.shape[0])
    rhs[prepared.seat_dofs.ravel()] = load
    u = prepared.full_field(spla.spsolve(prepared.K.tocsc(), rhs))
    ref, ref_p = s.normal_operator @ u, s.point_operator @ u
    np.testing.assert_allclose(un, ref, rtol=0, atol=1e-8 * np.max(np.abs(ref)))
    np.testing.assert_allclose(up, ref_p, rtol=0, atol=1e-8 * np.max(np.abs(ref)))
    assert float(r.power) == 0.0  # no velocity at f = 0
    # the ODS writer draws the same field
    import meshio

    path = write_housing_ods_vtu(hm, ch, {"static": np.asarray(r.coordinates)}, tmp_path / "o.vtu")
    m = meshio.read(path)
    np.testing.assert_allclose(m.point_data["static_real"].ravel(), u, atol=1e-12)


def test_harmonic_response_against_the_full_fe_solve(prepared):
    """At 0.6 of the first free-seat mode with η = 0.02: the ERP of a unit seat force from the
    condensed housing within 1 % of the full FE model's (complex sparse solve; ½ρc ∫|v_n|² dS
    by the skin's square_operator), below the cut-off."""
    ch = prepared.condensed_housing()
    f = 0.6 * float(ch.modes(1)[0][0])
    s = outer_surface(prepared.mesh)
    ac = housing_acoustics(ch, s, loss_factor=0.02)
    load = np.zeros(6 * len(ch.seat_names))
    load[2] = 1e3
    r = housing_response(ac, jnp.asarray(load, complex), f)
    w2 = (2 * math.pi * f) ** 2
    A = (prepared.K * (1 + 0.02j) - w2 * prepared.M).tocsc()
    rhs = np.zeros(prepared.K.shape[0], complex)
    rhs[prepared.seat_dofs.ravel()] = load
    u = prepared.full_field(spla.spsolve(A, rhs))
    ref = 0.5 * RHO * C * np.sum(np.abs(2j * math.pi * f * (s.square_operator @ u)) ** 2)
    np.testing.assert_allclose(float(r.power), ref, rtol=0.01)


@pytest.mark.slow  # about 30 s on the 2-core host (the lumped 3D whine and its gradient)
def test_erp_gradient_wrt_tip_relief_matches_central_differences():
    """The whine of the relieved ``accessory-spur`` pair in its lumped 3D scene, its bearing
    forces on a small box housing's seats (pinion bearings on seats 0, 1; gear's on 2, 3): the
    derivative of the order-1 ERP at one speed with respect to the tip relief depth of both
    members by jax.grad equals the central difference (step 1e-6 of the depth) to 1e-4."""
    model, _ = jio.build_dynamic_model(jio.load_case("accessory-spur"), slices=2)
    names = model.scene.reaction_names
    seats = one_way_seats(names)
    ch = condensed_housing(_box(), STEEL, 2000.0, cache=False)
    ac = housing_acoustics(ch, outer_surface(_box()))
    speed = 150.0
    d0 = float(model.mods.pinion.tip_relief_depth)

    def power(d):
        mods = eqx.tree_at(
            lambda m: (m.pinion.tip_relief_depth, m.gear.tip_relief_depth), model.mods, (d, d)
        )
        m = eqx.tree_at(lambda m: m.mods, model, mods)
        w = whine_response(m, speed, HarmonicBalance(8), positions=64)
        loads = seat_forces(w.bearing_force[:, 1], seats, names, len(ch.seat_names))
        r = housing_response(ac, loads, w.frequency)
        return r.power[0]

    grad = float(jax.grad(power)(jnp.asarray(d0)))
    step = 1e-6 * d0
    fd = float(power(d0 + step) - power(d0 - step)) / (2 * step)
    assert grad != 0.0 and float(power(d0)) > 0
    np.testing.assert_allclose(grad, fd, rtol=1e-4)


def test_bad_inputs(prepared):
    ch = prepared.condensed_housing()
    s = outer_surface(prepared.mesh)
    with pytest.raises(ValueError, match="loss_factor"):
        housing_acoustics(ch, s, loss_factor=-0.1)
    with pytest.raises(ValueError, match="density"):
        housing_acoustics(ch, s, density=0.0)
    with pytest.raises(ValueError, match="surface"):
        housing_acoustics(ch, outer_surface(mesh_plate(0.1, 0.1, 0.01, (2, 2))))
    ac = housing_acoustics(ch, s)
    with pytest.raises(ValueError, match="loads"):
        housing_response(ac, jnp.zeros(5), 10.0)
    with pytest.raises(TypeError, match="acoustics"):
        housing_response(ch, jnp.zeros(24), 10.0)
    with pytest.raises(ValueError, match="seats"):
        seat_forces(jnp.zeros(3), [0, 1, 9], "xyz", 4)
    with pytest.raises(ValueError, match="axes"):
        seat_forces(jnp.zeros(2), [0, 1], ["x", "w"], 4)
    with pytest.raises(ValueError, match="points"):
        outer_surface(prepared.mesh, {"p": (0.0, 1.0)})
