"""The acoustic objectives of optimise: the equivalent radiated power and the
radiated sound power of a housed gearbox over speeds, and the gradient of the whole chain
(tip relief → quasi-static TE → whine → housing → surface velocity → power) against central
differences.

References, each apart from the code under test: central differences of the chain; the sound
power of the vertex velocities evaluated by fem_prep's NumPy radiation resistance
(``RadiationResistance.power``, the dense R, not the JAX low-rank form); the A weighting and the
statistics written out in the test."""

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
import pytest
from _housing import ALUMINIUM, ROTATION, accessory_box, one_way_seats

import fem_prep.acoustics as fa
import jaxgear as jg
import jaxgear.io as jio
import optimise as op
from fem_prep.housing import (
    Bore,
    Foot,
    HousingBox,
    Tet4,
    condensed_housing,
    mesh_box,
    outer_surface,
)
from jaxgear.acoustics import a_weighting, housing_acoustics
from jaxgear.dynamics import HarmonicBalance


@pytest.fixture(scope="module")
def housed():
    """The relieved accessory-spur pair (lumped 3D, 2 slices) and the box's skin, one way."""
    case = jio.load_case("accessory-spur")
    model, _ = jio.build_dynamic_model(case, slices=2)
    mesh = mesh_box(accessory_box(float(case.pair.center_distance)), 0.05, element=Tet4())
    ch = condensed_housing(mesh, ALUMINIUM, 6000.0, cache=False)
    surface = outer_surface(mesh)
    ac = housing_acoustics(ch, surface, loss_factor=0.02)
    names = model.scene.reaction_names
    return case, model, mesh, surface, ac, one_way_seats(names), names


def _path(housed, speeds, orders=(1, 2), H=4):
    _, model, _, _, ac, seats, names = housed
    return op.AcousticPath(
        model, ac, speeds, orders, HarmonicBalance(H), positions=32,
        seats=seats, axes=names, rotation=ROTATION,
    )


def _with_depth(mods, d):
    return eqx.tree_at(
        lambda m: (m.pinion.tip_relief_depth, m.gear.tip_relief_depth), mods, (d, d)
    )


@pytest.mark.slow  # about 1 min on the 2-core host (the lumped 3D whine and its gradient)
def test_erp_chain_gradient_matches_central_differences(housed):
    """d(ERP of orders 1-2 at one speed, A-weighted)/d(tip relief depth of both members) by
    jax.grad through the whole chain equals the central difference (step 1e-6 of the depth)
    to 1e-5; the value under jit equals the eager one to 1e-9; the ERP objective's value equals
    the orders' ERP A-weighted and summed by hand."""
    case, model, *_ = housed
    obj = op.EquivalentRadiatedPower(_path(housed, [400.0]), op.Max())
    d0 = float(model.mods.pinion.tip_relief_depth)

    def value(d):
        return obj.at_torque(None, _with_depth(model.mods, d), case.torque, jg.ExactContact())

    grad = float(jax.grad(value)(jnp.asarray(d0)))
    step = 1e-6 * d0
    fd = float(value(d0 + step) - value(d0 - step)) / (2 * step)
    assert grad != 0.0 and float(value(d0)) > 0
    np.testing.assert_allclose(grad, fd, rtol=1e-5)
    # under jit the whine's balance runs on the scene's contact coordinates, eagerly on the
    # basis of the cells' structure vectors: two bases of the same space, the same power
    np.testing.assert_allclose(float(jax.jit(value)(d0)), float(value(d0)), rtol=1e-9)
    # the value: ½ ρ c Σ |v|² A per order, times 10^(A(f)/10), summed
    freq, vn = obj.path.surface_velocity(model.mods, case.torque, jg.ExactContact())
    ac = obj.path.housing
    p = 0.5 * 1.21 * 343.0 * np.sum(np.abs(np.asarray(vn)) ** 2 * np.asarray(ac.areas), axis=-1)
    f = np.asarray(freq)
    # IEC 61672-1 closed form, written out here
    f1, f2, f3, f4 = 20.598997, 107.65265, 737.86223, 12194.217
    ra = f4**2 * f**4 / ((f**2 + f1**2) * np.sqrt((f**2 + f2**2) * (f**2 + f3**2)) * (f**2 + f4**2))
    a = 20 * np.log10(ra) + 2.0
    np.testing.assert_allclose(a, np.asarray(a_weighting(f)), atol=0.01)
    np.testing.assert_allclose(float(value(d0)), np.sum(p * 10 ** (a / 10)), rtol=1e-3)


def _top_wall(mesh, surface, top=0.2):
    """The skin's facets on the top wall z = ``top`` as a flat radiating surface (their corner
    vertices and triangles) and the map from the skin facets' normal velocities to its vertices'
    (each vertex the area-weighted mean of the top facets that share it)."""
    f = surface.facets
    on = np.abs(surface.centroids[:, 2] - top) < 1e-9
    corners = mesh.mesh.facets[:, f[on]].T  # (F_top, 3) vertex indices
    nodes, tri = np.unique(corners, return_inverse=True)
    tri = tri.reshape(-1, 3)
    xyz = mesh.mesh.p[:, nodes].T
    up = np.cross(xyz[tri[:, 1]] - xyz[tri[:, 0]], xyz[tri[:, 2]] - xyz[tri[:, 0]])[:, 2] > 0
    tri = np.where(up[:, None], tri, tri[:, ::-1])  # counter-clockwise seen from above
    plate = fa.RadiatingSurface(xyz, tri)
    vm = np.zeros((nodes.size, f.size))
    cols = np.nonzero(on)[0]
    for k, t in enumerate(tri):
        vm[t, cols[k]] += surface.areas[cols[k]]
    vm /= vm.sum(axis=1, keepdims=True)
    return plate, vm


@pytest.mark.slow  # about 20 s on the 2-core host (the lumped 3D whine and its gradient)
def test_sound_power_chain_gradient_and_value(housed):
    """The sound power of the top wall as a baffled panel (its Rayleigh radiation resistance,
    cached at the path's frequencies; orders 1-2 at one speed, not weighted): the objective's
    value equals fem_prep's dense R on the same vertex velocities (NumPy) to 1e-6, and its
    derivative with respect to the tip relief depth by jax.grad through the whole chain equals
    the central difference to 1e-5."""
    case, model, mesh, surface, _, *_ = housed
    path = _path(housed, [400.0])
    plate, vm = _top_wall(mesh, surface)
    freqs = path.frequencies()  # (1, 2)
    rr = fa.radiation_resistance(plate, freqs.ravel(), method=fa.Rayleigh(), cache=False)
    L = np.asarray(rr.factors).reshape(*freqs.shape, *np.shape(rr.factors)[1:])
    rad = op.SurfaceRadiation(jnp.asarray(vm), jnp.asarray(L))
    obj = op.RadiatedSoundPower(path, op.Max(), False, radiation=rad)
    freq, vn = path.surface_velocity(model.mods, case.torque, jg.ExactContact())
    np.testing.assert_allclose(np.asarray(freq), freqs, rtol=1e-9)
    v = np.asarray(vn)[0] @ vm.T  # (2, n)
    ref = sum(float(np.real(np.conj(v[o]) @ rr.matrix(o) @ v[o])) for o in range(2))
    d0 = float(model.mods.pinion.tip_relief_depth)

    def value(d):
        return obj.at_torque(None, _with_depth(model.mods, d), case.torque, jg.ExactContact())

    assert ref > 0
    np.testing.assert_allclose(float(value(d0)), ref, rtol=1e-6)
    grad = float(jax.grad(value)(jnp.asarray(d0)))
    step = 1e-6 * d0
    fd = float(value(d0 + step) - value(d0 - step)) / (2 * step)
    assert grad != 0.0
    np.testing.assert_allclose(grad, fd, rtol=1e-5)


@pytest.mark.slow  # about 1 min on the 2-core host (three speeds, the problem's gradient)
def test_statistics_over_speeds_and_problem_scale(housed):
    """Over three speeds: Max, Mean and Quantile(0.5) of the per-speed powers as written out;
    the problem built on the path's scene is scaled by the unmodified design's value (exact
    contact) and its gradient wrt (depth, extent, crowning) is finite and matches central
    differences in the depth to 1e-4."""
    case, model, *_ = housed
    path = _path(housed, [300.0, 500.0, 700.0])
    mean = op.EquivalentRadiatedPower(path, op.Mean())
    per = np.asarray(mean.per_speed(model.mods, case.torque, jg.ExactContact()))
    for stat, ref in ((op.Max(), per.max()), (op.Mean(), per.mean()),
                      (op.Quantile(0.5), np.median(per))):
        obj = op.EquivalentRadiatedPower(path, stat)
        got = float(obj.at_torque(None, model.mods, case.torque, jg.ExactContact()))
        np.testing.assert_allclose(got, ref, rtol=1e-12)
    prob = op.make_problem(
        model.scene, model.mods, case.torque,
        "tip_relief.depth,tip_relief.extent,crowning.depth", mean, positions_per_pitch=32,
    )
    zero = jg.Modifications()
    unmod = float(np.mean(np.asarray(mean.per_speed(zero, case.torque, jg.ExactContact()))))
    np.testing.assert_allclose(float(prob.scale), unmod, rtol=1e-12)
    x = jnp.asarray([1.0, 0.3, 0.5])
    g = np.asarray(jax.grad(prob.value)(x))
    assert np.all(np.isfinite(g)) and g[0] != 0
    h = 1e-5
    fd = float(prob.value(x.at[0].add(h)) - prob.value(x.at[0].add(-h))) / (2 * h)
    np.testing.assert_allclose(g[0], fd, rtol=1e-4)


@pytest.mark.slow  # about 6 s on the 2-core host (the lumped model and the housing)
def test_bad_inputs(housed):
    case, model, _, _, ac, seats, names = housed
    ok = {"seats": seats, "axes": names, "rotation": ROTATION}
    with pytest.raises(ValueError, match="speeds"):
        op.AcousticPath(model, ac, [0.0], **ok)
    with pytest.raises(ValueError, match="orders"):
        op.AcousticPath(model, ac, [100.0], (0, 1), HarmonicBalance(4), **ok)
    with pytest.raises(ValueError, match="orders"):
        op.AcousticPath(model, ac, [100.0], (5,), HarmonicBalance(4), **ok)
    with pytest.raises(ValueError, match="positions"):
        op.AcousticPath(model, ac, [100.0], (1,), HarmonicBalance(8), positions=16, **ok)
    with pytest.raises(ValueError, match="seats, axes"):
        op.AcousticPath(model, ac, [100.0], seats=seats[:3], axes=names[:3])
    with pytest.raises(ValueError, match="coupled"):
        op.AcousticPath(model, ac, [100.0])
    with pytest.raises(TypeError, match="housing"):
        op.AcousticPath(model, None, [100.0], **ok)
    path = op.AcousticPath(model, ac, [100.0], (1,), HarmonicBalance(4), positions=32, **ok)
    with pytest.raises(ValueError, match="statistic"):
        op.EquivalentRadiatedPower(path, "max")
    with pytest.raises(ValueError, match="factors"):
        op.RadiatedSoundPower(
            path, radiation=op.SurfaceRadiation(jnp.zeros((3, ac.areas.size)),
                                                jnp.zeros((2, 1, 3, 1), complex)))
    with pytest.raises(ValueError, match="structure"):
        op.make_problem(case.mesh_model(slices=2), model.mods, case.torque, "tip_relief.depth",
                        op.EquivalentRadiatedPower(path))
    # the names map to the objects in jaxgear.io, with the path given
    erp = jio.objective_from_name("erp", case.torque, acoustic_path=path, reduce="mean")
    assert isinstance(erp, op.EquivalentRadiatedPower) and isinstance(erp.statistic, op.Mean)
    with pytest.raises(ValueError, match="needs radiation"):
        jio.objective_from_name("sound_power", case.torque, acoustic_path=path)


@pytest.mark.slow  # about 1 min on the 2-core host (three L-BFGS runs on the whine chain)
def test_quiet_relief_example_lowers_the_erp(tmp_path):
    """examples/quiet_relief.py reduced (2 slices, 3 speeds, H = 4, 32 positions, 6 L-BFGS
    iterations, a 2 × 2 sample, 5 sweep speeds): both ERP runs end below their starts (the
    nearly unmodified and the TE-optimal designs) in the optimiser's smooth law; in exact
    contact the quiet design's mean ERP is below the unmodified design's and the TE-optimal
    design's; the record's figures are finite and the figure is written."""
    from _examples import load_example

    ex = load_example("quiet_relief")
    rec = ex.main(tmp_path, slices=2, speeds=(200.0, 400.0, 600.0), sweep_speeds=5, n_grid=2,
                  max_iterations=6, harmonics=4, positions=32)
    for run in rec["erp_runs"].values():
        assert run["value"] < run["value0"]
    d = rec["designs"]
    assert d["quiet"]["erp_mean_W"] < d["unmodified"]["erp_mean_W"]
    assert d["quiet"]["erp_mean_W"] < d["te_optimal"]["erp_mean_W"]
    assert all(np.all(np.isfinite(v)) for v in rec["sweep"]["overall_dBA"].values())
    assert (tmp_path / "quiet_relief.png").stat().st_size > 20_000


# the coupled path: housing frame -> scene frame (the shafts' axis, scene z, along the box's
# length x; the shafts' plane, scene x, across its width y; scene y its height z)
R_COUPLED = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])


@pytest.mark.slow  # about 1 min on the 2-core host (the housed scene's whine and gradient)
def test_coupled_path_against_the_housing_under_its_bearing_forces():
    """An undamped scene that carries a box housing (jaxgear.scenes.Housing, loss factor 0):
    the skin velocity the coupled path reads from the whine's housing coordinates equals the
    one-way response of the same condensed housing (housing_response, η = 0) to the coupled
    whine's own bearing forces put on the seats (rotated into the housing's frame) to 1e-6 of
    its largest entry: the housing's equation of motion, solved apart. The ERP's derivative with
    respect to the tip relief depth through the coupled chain matches central differences to
    1e-5."""
    from jaxgear.acoustics import housing_response, seat_forces
    from jaxgear.dynamics import NoDamping, dynamic_model, whine_response
    from jaxgear.scenes import Housing, lumped_pair

    case = jio.load_case("accessory-spur").replace(slices=2)
    a, t, width, height = float(case.pair.center_distance), 0.01, 0.25, 0.16
    length = 0.1 + t
    off = np.array([-(width / 2 - a / 2), -height / 2, -length / 2])
    bores = tuple(Bore(w, (x - off[0], height / 2), 0.025) for w in ("x-", "x+") for x in (0.0, a))
    feet = tuple(Foot((x0, x0 + 0.03), (y0, y0 + 0.03))
                 for x0 in (0.0, length - 0.03) for y0 in (0.0, width - 0.03))
    mesh = mesh_box(HousingBox(length, width, height, t, bores=bores, feet=feet), 0.04,
                    element=Tet4())
    ch = condensed_housing(mesh, ALUMINIUM, 8000.0, cache=False)
    housing = Housing.of(ch, loss_factor=0.0, rotation=R_COUPLED, offset=off)
    s = case.scene
    scene = lumped_pair(case.pair, case.mesh_model(), s.pinion_shaft, s.gear_shaft,
                        masses=(1.0, 2.5), inertias=((1e-3, 2e-3), (4e-3, 8e-3)), housing=housing)
    # undamped (the model's modal damping would reach the housing's coordinates too)
    model = dynamic_model(scene, case.modifications, case.torque, NoDamping())
    ac = housing_acoustics(ch, outer_surface(mesh), loss_factor=0.0)
    path = op.AcousticPath(model, ac, [450.0], (1, 2), HarmonicBalance(4), positions=32)
    freq, vn = path.surface_velocity(model.mods, case.torque, jg.ExactContact())
    # the reference: the coupled whine's bearing forces on the nearest seats (scene frame)
    w = whine_response(model, [450.0], HarmonicBalance(4), positions=32)
    centres = off + np.array([sd.centre for sd in mesh.seats]) @ R_COUPLED.T
    names = scene.reaction_names
    seats = []
    for n in names:
        shaft, z = n.split()[0], float(n.split("z=")[1].split("mm")[0]) * 1e-3
        spec = s.pinion_shaft if shaft == "pinion" else s.gear_shaft
        p = np.array([0.0 if shaft == "pinion" else a, 0.0, z - spec.gear_z])
        seats.append(int(np.argmin(np.linalg.norm(centres - p, axis=1))))
    loads = seat_forces(w.bearing_force[:, 1:3], seats, names, len(ch.seat_names), R_COUPLED.T)
    ref = housing_response(ac, loads, freq).normal_velocity
    np.testing.assert_allclose(np.asarray(vn), np.asarray(ref), rtol=0,
                               atol=1e-6 * float(np.max(np.abs(np.asarray(ref)))))
    obj = op.EquivalentRadiatedPower(path, op.Max(), False)
    d0 = float(model.mods.pinion.tip_relief_depth)

    def value(d):
        return obj.at_torque(None, _with_depth(model.mods, d), case.torque, jg.ExactContact())

    grad = float(jax.grad(value)(jnp.asarray(d0)))
    step = 1e-6 * d0
    fd = float(value(d0 + step) - value(d0 - step)) / (2 * step)
    assert grad != 0.0
    np.testing.assert_allclose(grad, fd, rtol=1e-5)
