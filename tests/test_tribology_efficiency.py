"""Efficiency of a gear train, a planetary stage and a gearbox from each mesh's own sliding loss
(jaxgear.tribology.train_efficiency, planetary_efficiency, gearbox_efficiency).

References written here: the product of the meshes' efficiencies of a series chain and the
energy balance (input − Σ losses = output); for a planetary stage with the sun driving, the
carrier driven and the ring fixed, Müller's basic formula η = 1 − (1 − η₀) z_r/(z_s + z_r)
(H. W. Müller, Die Umlaufgetriebe, 1971; Kreines), η₀ = η_sp η_pr the fixed-carrier
efficiency of the same meshes, with each mesh's torque and speed relative to the carrier
written from Willis' equation by hand (not from the case's mesh_case)."""

from __future__ import annotations

import json
import math
import pathlib
import tomllib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.tribology as tr
from jaxgear.cli import (
    efficiency_run_line,
    gearbox_tribology,
    planetary_tribology_outputs,
    train_tribology_outputs,
)

EXAMPLES = pathlib.Path(__file__).resolve().parents[1] / "examples"
LUBRICANT = {
    "viscosity_40C_mm2_s": 320.0,
    "viscosity_100C_mm2_s": 24.0,
    "density_kg_m3": 900.0,
    "pressure_viscosity_per_GPa": 20.0,
    "oil_temperature_C": 70.0,
    "roughness_Ra_um": 0.5,
}


def _loss(eta, power):
    """One element of efficiency ``eta`` carrying ``power`` (W): a one-element power flow."""
    return tr.power_flow([eta], [power], power)


def test_series_flow_is_the_product_and_balances_energy():
    eta = np.array([0.99, 0.985, 0.97])
    flow = tr.power_flow(eta, [1e4, 1e4, 1e4], 1e4)
    assert float(flow.efficiency) == pytest.approx(0.99 * 0.985 * 0.97, rel=1e-14)
    assert float(flow.input_power - flow.total_loss) == pytest.approx(float(flow.output_power))
    # the power reaching the third mesh is what the first two passed on
    assert float(flow.power[2]) == pytest.approx(1e4 * 0.99 * 0.985, rel=1e-14)
    # dη/dη₂ = η₁ η₃ (central differences on the product's own derivative)
    g = jax.jit(jax.grad(lambda e: tr.power_flow(e, jnp.full(3, 1e4), 1e4).efficiency))(
        jnp.asarray(eta)
    )
    assert float(g[1]) == pytest.approx(0.99 * 0.97, rel=1e-12)


def test_a_compound_train_and_a_branch_follow_the_shafts():
    # gears 0→1, 2 on 1's shaft → 3: the second mesh is downstream of the first
    flow = tr.train_efficiency([_loss(0.98, 500.0), _loss(0.97, 500.0)], ((0, 1), (2, 3)),
                               (0, 1, 1, 2))
    assert flow.upstream == ((), (0,))
    assert float(flow.efficiency) == pytest.approx(0.98 * 0.97, rel=1e-14)
    # two meshes off the input gear (power split 300 + 200 W): side by side, no product
    flow = tr.train_efficiency([_loss(0.98, 300.0), _loss(0.97, 200.0)], ((0, 1), (0, 2)),
                               input_power=500.0)
    assert flow.upstream == ((), ())
    by_hand = 500.0 - 0.02 * 300.0 - 0.03 * 200.0
    assert float(flow.output_power) == pytest.approx(by_hand, rel=1e-14)
    stages = tr.gearbox_efficiency([flow, _loss(0.99, 500.0)])
    assert float(stages.efficiency) == pytest.approx(by_hand / 500.0 * 0.99, rel=1e-14)


@pytest.mark.parametrize(
    "call, message",
    [
        (lambda: tr.power_flow([0.9, 1.2], [1.0, 1.0], 1.0), r"power_flow: efficiency"),
        (lambda: tr.power_flow([0.9], [1.0, 1.0], 1.0), r"power_flow: transmitted"),
        (lambda: tr.power_flow([0.9, 0.9], [1.0, 1.0], 1.0, ((), (1,))), r"upstream\[1\]"),
        (lambda: tr.train_efficiency([]), r"train_efficiency: meshes is empty"),
        (lambda: tr.planetary_efficiency([_loss(0.9, 1.0)], 3, 1.0), r"allowed 2"),
        (lambda: tr.planetary_efficiency([_loss(0.9, 1.0)] * 2, 0, 1.0), r"n_planets = 0"),
        (lambda: tr.gearbox_efficiency([1.0]), r"gearbox_efficiency: meshes\[0\]"),
    ],
)
def test_bad_input_is_one_line(call, message):
    with pytest.raises(ValueError, match=message) as err:
        call()
    assert "\n" not in str(err.value)


@pytest.fixture(scope="module")
def stage():
    """nrel-5mw-planetary driven by its sun (the ring fixed, the carrier the output), coarse
    (8 positions per pitch, 4 slices), with a lubricant; each mesh solved at one planet path's
    mean load: (case, results)."""
    data = tomllib.loads(jio.embedded_case_text("nrel-5mw-planetary"))
    data["planetary"]["input"] = "sun"
    data["mesh"].update(positions_per_pitch=8, slices=4)
    data["operating"] = {"torque_Nm": 1.0e6, "speed_rad_s": 5.0}
    data["lubricant"] = LUBRICANT
    for key in ("rating",):
        data.pop(key)
    for key in ("sigma_H_lim_MPa", "sigma_F_lim_MPa", "treatment", "brinell_hardness_HB",
                "proof_stress_MPa"):
        data["material"].pop(key)
    case = jio.parse_train(data)
    results = []
    for k in range(2):
        one = case.form.mesh_case(case, k)
        results.append(jg.quasi_static(one.mesh_model(), one.modifications, one.torque,
                                       positions_per_pitch=8, periods=1))
    return case, results


def test_planetary_efficiency_is_muellers_formula(stage, tmp_path):
    case, results = stage
    z_s, z_p, z_r, n_p = 19, 17, 56, 3
    t_s, w_s = 1.0e6, 5.0
    w_c = w_s * z_s / (z_s + z_r)  # Willis, the ring fixed
    sp, pr = case.pairs
    force = t_s / n_p / sp.base_radii[0]  # per planet path, on the line of action
    torques = (force * sp.base_radii[0], force * pr.base_radii[0])
    speeds = (w_s - w_c, (w_s - w_c) * z_s / z_p)  # the sun's and the planet's, carrier frame
    inputs = jio.tribology_of(case)
    meshes = [
        tr.mesh_tribology(pair, r, inputs.lubricant, t, w, inputs.roughness,
                          case.youngs_modulus, case.poisson_ratio, friction=inputs.friction)
        for pair, r, t, w in zip(case.pairs, results, torques, speeds, strict=True)
    ]
    flow = tr.planetary_efficiency(meshes, n_p, t_s * w_s)
    eta_0 = float(meshes[0].efficiency * meshes[1].efficiency)
    mueller = 1.0 - (1.0 - eta_0) * z_r / (z_s + z_r)
    assert float(flow.efficiency) == pytest.approx(mueller, abs=1e-12)
    assert 0.9 < float(flow.efficiency) < 1.0 and eta_0 < float(flow.efficiency)
    # jaxgear run's files: the same stage from the case's own carrier-frame points
    section = planetary_tribology_outputs(case, str(tmp_path), results)
    overall = json.loads((tmp_path / "tribology.json").read_text())["overall"]
    assert overall["efficiency"] == pytest.approx(mueller, rel=1e-10)
    assert overall["input_power_W"] - overall["total_loss_W"] == pytest.approx(
        overall["output_power_W"], rel=1e-12)
    assert section["meshes"]["sun1-planet1"]["speed_rad_s"] == pytest.approx(speeds[0])
    rows = (tmp_path / "tribology.csv").read_text().splitlines()
    assert len(rows) == 3 and rows[0].startswith("mesh,")
    assert (tmp_path / "tribology_planet1_ring1.png").exists()
    assert "efficiency" in efficiency_run_line(section)[0]


def test_idler_train_efficiency_is_the_meshes_product(tmp_path):
    """examples/idler-train-lubricated.toml (the embedded idler train with an oil; torsional,
    coarse here): each mesh's loss at its driving gear's torque and speed by hand (T z_idler /
    z_input, ω z_input / z_idler), the train's efficiency their product and the energy
    balance; the gearbox of this train and a stage of 95 % their product."""
    data = tomllib.loads(EXAMPLES.joinpath("idler-train-lubricated.toml").read_text())
    data["mesh"].update(slices=4, positions_per_pitch=8)
    data["operating"]["speed_rad_s"] = 300.0
    case = jio.parse_train(data)
    r = jg.quasi_static(case.static_train(), case.mesh_modifications(), case.torque,
                        contact=case.contact_law("exact"), positions_per_pitch=8, periods=1)
    section = train_tribology_outputs(case, str(tmp_path), r)
    overall = section["overall"]
    inputs = jio.tribology_of(case)
    each = []
    for k, (t, w) in enumerate(((80.0, 300.0), (80.0 * 61 / 45, 300.0 * 45 / 61))):
        m = tr.mesh_tribology(case.pairs[k], r.meshes[k], inputs.lubricant, t, w,
                              inputs.roughness, case.youngs_modulus, case.poisson_ratio,
                              friction=inputs.friction)
        each.append(float(m.efficiency))
    assert overall["efficiency_each"] == pytest.approx(each, rel=1e-10)
    assert overall["efficiency"] == pytest.approx(math.prod(each), rel=1e-12)
    assert overall["input_power_W"] == pytest.approx(80.0 * 300.0)
    assert overall["input_power_W"] - sum(overall["loss_W"]) == pytest.approx(
        overall["output_power_W"], rel=1e-12)
    box = gearbox_tribology(
        [{"stage": "stage1", "summary": {"tribology": section}},
         {"stage": "stage2", "summary": {"tribology": {"efficiency": 0.95,
                                                       "input_power_W": 24000.0}}}],
        str(tmp_path))
    assert box["efficiency"] == pytest.approx(math.prod(each) * 0.95, rel=1e-12)
    assert gearbox_tribology([{"stage": "stage1", "summary": {}}], str(tmp_path)) is None


def test_a_train_files_lubricant_is_checked_at_load():
    data = tomllib.loads(EXAMPLES.joinpath("idler-train-lubricated.toml").read_text())
    assert jio.tribology_of(jio.parse_train(data)).speed == pytest.approx(628.3)
    data["lubricant"]["oil_temperature_C"] = 300.0
    with pytest.raises(ValueError, match=r"\[lubricant\] oil_temperature_C = 300") as err:
        jio.parse_train(data)
    assert "\n" not in str(err.value)
    lumped = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))  # no [[gears]]
    lumped["lubricant"] = LUBRICANT
    with pytest.raises(ValueError, match=r"lubricant .*allowed only with \[\[gears\]\]"):
        jio.parse_train(lumped)
