"""The tribology objectives of optimise: mesh power loss, loss of efficiency,
minimum specific film thickness and maximum flash temperature along the path of contact, on the
FZG C14 case (examples/fzg-c14-lubricated.toml).

References: the sliding loss Σ μ w |v₁ − v₂| l written again here in NumPy from the result's line
loads and the involute kinematics (roll distances ρ₁ = ρ_A + s, ρ₂ from the pair; v = ω ρ);
central differences of the scaled objectives in the smooth law (two step sizes agreeing: no kink
crossed); float32 against float64."""

import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import optimise as op

jax.config.update("jax_enable_x64", True)

CASE = "examples/fzg-c14-lubricated.toml"
PPP = 16
VARS = "tip_relief.depth,tip_relief.extent,crowning.depth"
X0 = np.array([0.9, 0.35, 0.6])  # E*, Γ, crowning E*: a relief near the TE-optimal one


@pytest.fixture(scope="module")
def case():
    # theoretical path: GEARpie's C14 reference (rigid sharing on the path of contact) and the
    # example's figures; with the case file's default contact beyond the path the unmodified loss
    # is 310 W
    return jio.load_case(CASE).replace(contact_geometry=jg.TheoreticalPath())


@pytest.fixture(scope="module")
def beyond():
    # the case file as written: contact beyond the path of contact (the default)
    c = jio.load_case(CASE)
    assert c.contact_geometry == jg.BeyondPath()
    return c


def _problem(case, objective, **settings):
    return jio.case_problem(case, VARS, objective, positions_per_pitch=PPP, **settings)


def test_power_loss_objective_is_the_sliding_loss_by_hand(case):
    """The unscaled power_loss objective of a design in exact contact is Σ μ w |v₁ − v₂| l over
    the loaded cells, averaged over the positions, with Schlenk's μ of the case; efficiency_loss
    is that over T ω₁; the scale is the unmodified design's loss (GEARpie's C14 P_VZP is
    295.17 W with rigid load sharing: within 2 %)."""
    prob = _problem(case, "power_loss")
    loss = np.asarray(prob.sharp().per_torque(jnp.asarray(X0)))[0]
    inputs = jio.tribology_of(case)
    pair, omega = case.pair, inputs.speed
    res = jg.quasi_static(
        prob.sharp().mesh,
        prob.sharp().modifications(jnp.asarray(X0)),
        case.torque,
        positions_per_pitch=PPP,
    )
    w = np.asarray(res.line_load)
    s = np.asarray(res.cell_s)
    on = np.asarray(res.cell_mask) & (w > 0)
    s = np.where(on, s, 0.0)
    v1 = omega * np.asarray(pair.roll_distance(jnp.asarray(s), 0))
    v2 = omega / abs(float(pair.gear_ratio)) * np.asarray(pair.roll_distance(jnp.asarray(s), 1))
    mu = float(inputs.friction.coefficient(pair, inputs.lubricant, case.torque, omega,
                                           jnp.asarray(inputs.roughness)))
    length = float(pair.face_width) / w.shape[-1]  # spur: β_b = 0
    by_hand = np.mean(np.sum(np.where(on, mu * w * np.abs(v1 - v2), 0.0), axis=(1, 2))) * length
    assert loss == pytest.approx(by_hand, rel=1e-9)
    assert float(prob.scale) == pytest.approx(295.17, rel=0.02)
    eff = _problem(case, "efficiency_loss")
    e = float(np.asarray(eff.sharp().per_torque(jnp.asarray(X0)))[0])
    assert e == pytest.approx(by_hand / (case.torque * omega), rel=1e-9)


def test_torque_range_and_statistic_from_the_case_names(case):
    """``torques`` and ``reduce`` map to the objective's torque range and statistic: the mean
    over two torques is the mean of the single-torque objectives' unscaled values."""
    rng = _problem(case, "min_specific_film", torques=[150.0, 250.0], reduce="mean")
    assert isinstance(rng.objective, op.MinSpecificFilm)
    assert isinstance(rng.objective.statistic, op.Mean)
    per = np.asarray(rng.sharp().per_torque(jnp.asarray(X0)))
    assert per.shape == (2,) and per[1] > per[0]  # 1/λ_min rises with the load
    lub = rng.objective.lubrication
    singles = []
    for t in (150.0, 250.0):
        res = jg.quasi_static(
            rng.sharp().mesh, rng.sharp().modifications(jnp.asarray(X0)), t,
            positions_per_pitch=PPP,
        )
        singles.append(1.0 / float(lub.tribology(res, t).min_specific_film))
    np.testing.assert_allclose(per, singles, rtol=1e-9)
    with pytest.raises(ValueError, match=r"'power_loss' needs the case's \[lubricant\] table"):
        jio.case_problem(jio.load_case("accessory-spur"), VARS, "power_loss")
    table = jio.parse_optimise({"objective": "power_loss", "torques": [100.0, 300.0, 3]})
    assert table["torques"] == [100.0, 300.0, 3]
    with pytest.raises(ValueError, match="applies to objective = 'robust_te_rms' or a tribology"):
        jio.parse_optimise({"objective": "te_rms", "torques": [100.0, 300.0, 3]})


_AT_X0: dict = {}  # float64 (value, gradient) at X0 of each objective beyond the path


# two fixed random directions (seeded, unit length) of the directional-derivative checks
DIRECTIONS = np.random.default_rng(54).standard_normal((2, 3))
DIRECTIONS /= np.linalg.norm(DIRECTIONS, axis=1, keepdims=True)


def _central_differences(prob, name, cache=None, per_variable=False):
    """The smooth law's gradient of the scaled objective at X0 and its central differences at
    steps 1e-4 and 5e-5 (agreeing: no kink crossed): along the two fixed random ``DIRECTIONS``
    against the gradient's projections on them (four differences instead of one per variable),
    or with ``per_variable`` along each variable against its component. The values come from
    the gradient's own compiled program (value_and_grad at X0 ± h): one compilation for both
    sides. ``cache``: a dict that keeps (value, gradient) at X0 under ``name``."""
    value_and_grad = jax.jit(jax.value_and_grad(lambda x: prob.value(x)))

    def f(x):
        return value_and_grad(x)[0]

    v0, g = value_and_grad(jnp.asarray(X0))
    g = np.asarray(g)
    if cache is not None:
        cache[name] = (float(v0), g)
    assert np.all(np.isfinite(g)), (name, g)
    scale = np.max(np.abs(g))
    for d in np.eye(3) if per_variable else DIRECTIONS:
        e = 1e-4 * d
        fd = (float(f(jnp.asarray(X0 + e))) - float(f(jnp.asarray(X0 - e)))) / 2e-4
        fd2 = (float(f(jnp.asarray(X0 + e / 2))) - float(f(jnp.asarray(X0 - e / 2)))) / 1e-4
        assert fd2 == pytest.approx(fd, abs=1e-4 * scale)
        assert g @ d == pytest.approx(fd, abs=1e-4 * scale), (name, d)
    return g, scale


@pytest.mark.parametrize(
    "name", ["power_loss", "efficiency_loss", "min_specific_film", "max_flash_temperature"]
)
def test_gradients_beyond_the_path_match_central_differences(beyond, name):
    """With contact beyond the path of contact (the case file's default): d(scaled objective)/
    d(tip relief depth, tip relief extent, crowning depth) in the smooth law is finite and
    matches central differences (relative 1e-4 of the largest component), and every component
    is non-zero. The smooth law gives the corner cells beyond the path that do not touch a
    vanishing load (1e-276 N/m), at which the film formula's W^-0.13 has an overflowing
    derivative: the film is evaluated at W >= 1e-12 (jaxgear.tribology.film_thickness), so
    1/λ_min's gradient is finite. Crowning changes the loss here: at the positions where a
    corner cell beyond the path touches, only the middle of the face touches there, so crowning
    (which relieves the fully touching pair by its mean over the face but the corner's touching
    slices by less) moves load to the corner pair at the end of the path, where the sliding is
    fastest: the loss rises with crowning. The differences: along two fixed random directions
    (each variable along its own: the slow test below)."""
    g, _ = _central_differences(_problem(beyond, name), name, _AT_X0)
    assert np.all(np.abs(g) > 1e-3), g
    if name in ("power_loss", "efficiency_loss"):
        assert g[2] > 0.0


@pytest.mark.slow  # test_gradients_beyond_the_path_match_central_differences keeps the claim
@pytest.mark.parametrize(
    "name", ["power_loss", "efficiency_loss", "min_specific_film", "max_flash_temperature"]
)
def test_gradients_beyond_the_path_match_central_differences_per_variable(beyond, name):
    """As the directional check above, each component against its own central differences."""
    _central_differences(_problem(beyond, name), name, per_variable=True)


def test_power_loss_on_the_path_does_not_depend_on_crowning(case):
    """On the theoretical path of contact every contact line of a spur pair lies at one s and
    touches along the whole face at the design point: crowning c(y) shifts each pair's
    approach by its mean over the face alike, so each pair's total load, and with it the loss
    Σ μ w v_g l (v_g a function of s alone), does not depend on the crowning depth (checked on
    each pair's load summed over the face, and on the objective's gradient), while the tip
    relief's components match central differences (the gradient's projections on two fixed random
    directions, its crowning component zero)."""
    prob = _problem(case, "power_loss")
    g, scale = _central_differences(prob, "power_loss")
    assert abs(g[0]) > 1e-3 and abs(g[1]) > 1e-3
    assert abs(g[2]) < 1e-8 * scale
    law = prob.contact

    def pair_loads(x):
        r = jg.quasi_static(prob.mesh, prob.modifications(x), case.torque, contact=law,
                            positions_per_pitch=PPP)
        return jnp.sum(r.line_load, axis=-1), r.line_load

    (_, w), (dpair, dw) = jax.jvp(pair_loads, (jnp.asarray(X0),), (jnp.asarray([0.0, 0.0, 1.0]),))
    assert float(jnp.max(jnp.abs(dw))) > 1e4  # the load moves across the face ...
    assert float(jnp.max(jnp.abs(dpair))) < 1e-8 * float(jnp.max(w))  # ... not between pairs


@pytest.mark.parametrize("name", [
    # default tier: the min_specific_film case below (a tribology objective built and
    # differentiated in float32 against float64)
    pytest.param("efficiency_loss", marks=pytest.mark.slow),
    "min_specific_film",
])
def test_float32_objective_and_gradient(beyond, name):
    """The problem built and evaluated in float32, with contact beyond the path, gives the
    float64 value and gradient within float32's reach (the gradient finite). The float64
    reference: the gradient test's value and gradient at X0 when it ran in this process."""
    if name not in _AT_X0:
        ref = _problem(beyond, name)
        v, g = jax.jit(jax.value_and_grad(lambda y: ref.value(y)))(jnp.asarray(X0))
        _AT_X0[name] = (float(v), np.asarray(g))
    v64, g64 = _AT_X0[name]
    with jax.enable_x64(False):
        p32 = _problem(jio.load_case(CASE), name)  # loaded in float32
        x = jnp.asarray(X0, dtype=jnp.float32)
        v32, g32 = jax.jit(jax.value_and_grad(lambda y: p32.value(y)))(x)
        assert v32.dtype == jnp.float32 and g32.dtype == jnp.float32
        assert math.isfinite(float(v32))
        assert float(v32) == pytest.approx(v64, rel=2e-4)
        np.testing.assert_allclose(np.asarray(g32), g64, atol=2e-3 * np.max(np.abs(g64)))


def test_bad_lubrication_one_line(case):
    inputs = jio.tribology_of(case)
    args = (case.pair, inputs.lubricant, inputs.speed, inputs.roughness, 206e9, 0.3)
    with pytest.raises(ValueError, match=r"MeshLubrication: speed = -1.0 rad/s is out of range"):
        op.MeshLubrication(*args[:2], -1.0, *args[3:])
    with pytest.raises(ValueError, match=r"roughness = \(1.0, 1.0\) m is out of range"):
        op.MeshLubrication(*args[:3], (1.0, 1.0), *args[4:])
    with pytest.raises(ValueError, match="lubricant = float: allowed a jaxgear.tribology"):
        op.MeshLubrication(args[0], 1.0, *args[2:])
    lub = op.MeshLubrication(*args)
    with pytest.raises(ValueError, match=r"torques = \[-5.0\] N·m: allowed"):
        op.MeshPowerLoss(lub, [-5.0])


def test_cli_settings_take_the_tribology_objectives(case):
    """``jaxgear optimise``'s settings: a torque range goes with a tribology objective; a case
    without ``[lubricant]`` is refused in one line naming the table."""
    from jaxgear.cli import check_settings

    ok = {"objective": "max_flash_temperature", "torques": "100:300:3", "max_iterations": 5}
    assert check_settings(ok, case) is ok
    with pytest.raises(ValueError, match=r"'accessory-spur' has no \[lubricant\] table"):
        check_settings({**ok, "torques": None}, jio.load_case("accessory-spur"))


# default tier: tests/test_optimise_tribology.py::test_power_loss_objective_is_the_sliding_loss_by_hand
# (the example's power-loss objective by hand), tests/test_optimise_objects.py::
# test_a_new_objective_is_one_class (its weighted sum: a new objective is one class)
@pytest.mark.slow
def test_te_vs_power_loss_example_front(tmp_path):
    """examples/te_vs_power_loss.py at a small size (7 × 7 designs, 16 positions, two weights,
    two L-BFGS steps): its front is the non-dominated set of its map (checked by brute force
    over every pair of designs), ordered by rising TE and falling loss, from the TE-optimal to
    the loss-optimal design; the figure is written."""
    from _examples import load_example

    ex = load_example("te_vs_power_loss")
    # one weight: each weight is a static setting of the example's objective, one more L-BFGS
    # program to compile
    rec = ex.main(tmp_path, n_grid=7, positions=16, max_iterations=2, weights=(1.0,))
    m = np.load(tmp_path / "te_vs_power_loss_map.npz")
    te, loss = m["te"] * 1e6, m["loss"]
    dominated = [
        any((te[j] <= te[i] and loss[j] < loss[i]) or (te[j] < te[i] and loss[j] <= loss[i])
            for j in range(te.size))
        for i in range(te.size)
    ]
    front = {(round(d["te_ptp_um"], 9), round(d["power_loss_W"], 6)) for d in rec["front"]}
    want = {(round(t, 9), round(w, 6)) for t, w, d in zip(te, loss, dominated) if not d}
    assert front == want
    fr = rec["front"]
    assert all(a["te_ptp_um"] < b["te_ptp_um"] and a["power_loss_W"] > b["power_loss_W"]
               for a, b in zip(fr, fr[1:]))
    assert fr[0]["te_ptp_um"] == pytest.approx(float(te.min()))
    assert fr[-1]["power_loss_W"] == pytest.approx(float(loss.min()))
    assert rec["loss_optimal"]["power_loss_W"] < rec["unmodified"]["power_loss_W"]
    assert [w["weight"] for w in rec["weighted_sums"]] == [1.0]
    assert (tmp_path / "te_vs_power_loss.png").stat().st_size > 20_000
