"""optimise: objectives, statistics and optimisers are objects passed straight through; the
names of case files map to them in jaxgear.io (the one place)."""

from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import optax
import optimistix as optx
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.rating as jr
import optimise as op
from _rating_cases import rated_accessory_case


@pytest.fixture(scope="module")
def case():
    return jio.load_case("accessory-spur").replace(slices=3, positions_per_pitch=16)


@pytest.fixture(scope="module")
def problem(case):
    return jio.case_problem(case, "tip_relief.depth", "te_rms", relief_blend=0.0)


def test_case_file_names_map_to_objects(case):
    """Every objective name of the case files gives its class, whose name is that name."""
    rating = jio.rating_of(rated_accessory_case(3, 16))
    oiled = jio.load_case("examples/fzg-c14-lubricated.toml")
    inputs = jio.tribology_of(oiled)
    lubrication = op.MeshLubrication(
        oiled.pair, inputs.lubricant, inputs.speed, inputs.roughness, 206e9, 0.3
    )
    settings = dict(
        torques=[40.0, 80.0],
        reduce="mean",
        lp_order=6.0,
        speeds=[1000.0],
        rating=rating,
        lubrication=lubrication,
    )
    for name in jio.OBJECTIVES:
        if name in ("erp", "sound_power"):  # built on an acoustic path: test_optimise_acoustics
            with pytest.raises(ValueError, match="needs acoustic_path"):
                jio.objective_from_name(name, case.torque, **settings)
            continue
        obj = jio.objective_from_name(name, case.torque, **settings)
        assert isinstance(obj, op.AbstractObjective) and obj.name == name
    assert op.OBJECTIVES == tuple(jio.OBJECTIVES)
    robust = jio.objective_from_name("robust_te_rms", case.torque, **settings)
    assert isinstance(robust.statistic, op.Mean)
    np.testing.assert_array_equal(robust.torques(case.torque), [40.0, 80.0])
    assert float(jio.objective_from_name("line_load_lp", case.torque, lp_order=6.0).order) == 6.0
    least = jio.objective_from_name("least_safety", case.torque, rating=rating, te_limit=1e-6)
    assert isinstance(least, op.LeastSafetyFactor) and least.te_limit == 1e-6
    assert least.geometry is rating.geometry and least.settings is rating.settings
    assert isinstance(jio.optimiser_from_name("lbfgs"), optx.LBFGS)
    assert isinstance(jio.optimiser_from_name("adam"), optx.OptaxMinimiser)
    for what, call in (
        ("objective = 'te_max'", lambda: jio.objective_from_name("te_max", 80.0)),
        ("method = 'bfgs'", lambda: jio.optimiser_from_name("bfgs")),
        ("reduce = 'min'", lambda: jio.objective_from_name("robust_te_rms", 80.0, reduce="min")),
    ):
        with pytest.raises(ValueError, match=f"{what} is unknown: allowed"):
            call()
    # least_safety rates the pair: without the case's [rating] it names the table
    with pytest.raises(ValueError, match=r"'least_safety' needs the case's \[rating\] table"):
        jio.objective_from_name("least_safety", case.torque)
    with pytest.raises(ValueError, match=r"'least_safety' needs the case's \[rating\] table"):
        jio.case_problem(case, "pinion.crowning.depth", "least_safety")


def test_a_new_objective_is_one_class(case, problem):
    """A user objective (here TE RMS squared, in m²) is one subclass passed to make_problem; its
    scaled value at the start is the square of the TE RMS objective's."""

    class TeRmsSquared(op.AbstractQuasiStaticObjective):
        name: ClassVar[str] = "te_rms_squared"
        units: ClassVar[str] = "m2"

        def of_result(self, result, problem):
            return result.te_rms**2

    p = op.make_problem(
        case.mesh_model(),
        case.modifications,
        case.torque,
        "tip_relief.depth",
        TeRmsSquared(),
        positions_per_pitch=case.positions_per_pitch,
        smoothing=op.Smoothing(jg.SmoothContact(case.smooth_width), relief_blend=0.0),
    )
    x = jnp.asarray([0.8])
    assert float(p.value(x)) == pytest.approx(float(problem.value(x)) ** 2, rel=1e-12)


def test_minimise_takes_solver_objects(problem):
    """BFGS and a bare optax transformation go straight through; a minimiser whose state the
    loop cannot read is refused in one line."""
    for solver in (optx.BFGS(rtol=1e-7, atol=1e-7), optax.adam(0.05)):
        with pytest.warns(UserWarning, match="iteration cap"):
            r = op.minimise(problem, [0.5], solver, max_iterations=1, progress=False)
        assert r.iterations == 1 and r.history_x.shape == (2, 1)
        assert r.value <= r.value0
    with pytest.raises(ValueError, match="solver = GradientDescent: allowed"):
        op.minimise(problem, [0.5], optx.GradientDescent(0.1, 1e-7, 1e-7), progress=False)


def test_statistics_reduce_as_named():
    v = jnp.asarray([1.0, 4.0, 2.0, 3.0])
    assert float(op.Mean()(v)) == 2.5 and float(op.Max()(v)) == 4.0
    assert float(op.Quantile(0.5)(v)) == pytest.approx(2.5)
    with pytest.raises(ValueError, match="Quantile level = 1.5 is out of range"):
        op.Quantile(1.5)


def test_least_safety_value_is_the_inverse_soft_min_of_the_rating_by_hand():
    """LeastSafetyFactor on the rated accessory pair (2 slices, 8 positions): its value is
    1/S̃ with S̃ = −log Σ exp(−κ S)/κ written here in NumPy over the four safety factors of
    ``jaxgear.rating.rate`` given the K_Hβ measured on the same quasi-static result (K_Hα, K_Fα
    ISO 6336-1's method B); S̃ lies within log(4)/κ below the least S; a TE
    limit at half the TE RMS adds ``penalty`` × 1² exactly."""
    rcase = rated_accessory_case(2, 8)
    rating = jio.rating_of(rcase)
    res = jg.quasi_static(
        rcase.mesh_model(), rcase.modifications, rcase.torque, positions_per_pitch=8
    )
    least = jio.objective_from_name("least_safety", rcase.torque, rating=rating)
    khb = float(jg.rating.face_load_factor(res))
    given = jr.GivenFactors(K_Hbeta=khb)  # K_Hα, K_Fα: ISO's method B
    r = jr.rate(
        rating.geometry, rating.operating, eqx.tree_at(lambda s: s.given, rating.settings, given)
    )
    S = np.concatenate([np.asarray(r.pitting.S_H), np.asarray(r.bending.S_F)])
    kappa = least.sharpness
    soft = -np.log(np.sum(np.exp(-kappa * S))) / kappa
    assert S.min() - np.log(4) / kappa <= soft <= S.min()
    assert float(least.of_result(res, None)) == pytest.approx(1.0 / soft, rel=1e-10)
    limited = jio.objective_from_name(
        "least_safety", rcase.torque, rating=rating, te_limit=0.5 * float(res.te_rms)
    )
    assert float(limited.of_result(res, None)) == pytest.approx(
        1.0 / soft + limited.penalty, rel=1e-10
    )
