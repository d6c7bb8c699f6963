"""The hybrid model against the seed's flexible-body results (docs/hybrid.md, "Evidence"), on the
embedded bodies (documented approximations of the seed's undimensioned drawings): orders and
magnitudes, and the quantities that do not depend on the missing dimensions. Slow: each body is
condensed once (30–70 s) into a temporary fem_prep cache."""

from __future__ import annotations

import dataclasses
import pathlib

import numpy as np
import pytest
from _examples import load_example

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.dynamics import bearing_forces
from jaxgear.io import static_scene

pytestmark = pytest.mark.slow


@pytest.fixture(scope="module")
def cache(fem_prep_cache):
    return fem_prep_cache


@pytest.fixture(scope="module")
def power(cache):
    case = jio.load_case("power-helical-flexible")
    body = fem_prep.condensed("power-helical-wheel")
    out = {}
    sc, _ = static_scene(case, bodies=(None, body))
    for speed in (0.0, 3000.0):
        out[speed] = (sc, jg.quasi_static(sc, case.modifications, case.torque, speed=speed))
    return case, out


def test_power_pinion_bearing_loads_sum_to_the_seed_values(power):
    """Seed Tab. III-6 (pinion bearings, H1): ΣS = −2007 − 1438 = −3445 N along the centre line,
    ΣT = −3402 − 3427 = −6829 N across it. The sums depend only on the mesh force, so they are
    comparable whatever the shaft dimensions (the per-bearing split is not: the seed's shaft is
    undimensioned). Within 1 %."""
    _, out = power
    sc, res = out[0.0]
    f = bearing_forces(sc, res)
    S = sum(v for k, v in f.items() if k.startswith("pinion") and k.endswith("Fx"))
    T = sum(v for k, v in f.items() if k.startswith("pinion") and k.endswith("Fy"))
    assert S == pytest.approx(-3445.0, rel=1e-2)
    assert T == pytest.approx(-6829.0, rel=1e-2)


def _slice_loads(res):
    """Max line load per slice (N/m) over positions and lines, and slice centres z (m)."""
    return np.asarray(res.line_load).max(axis=(0, 1)), np.asarray(res.cell_z)[0, 0]


def test_power_peak_load_over_the_web_rim_joint_and_the_rim_growth_at_speed(power):
    """Seed III-17: at rest the peak load sits over the web-rim joint (the web meets the rim
    12 mm off mid-face, 8 mm from the z = 0 edge of the face). Seed III-25/26: at 3000 rad/s
    (pinion) the rim grows by ≈ 80 µm (free ring: 54 µm) and the load moves
    towards the cantilevered edge (z = b). Measured: peak at 10.5 mm, growth 52.6 µm, load
    centroid +2.1 mm, load on the cantilevered quarter × 15.6."""
    case, out = power
    load0, z = _slice_loads(out[0.0][1])
    load1, _ = _slice_loads(out[3000.0][1])
    z_web = 0.5 * case.pair.face_width - 12e-3
    assert abs(z[np.argmax(load0)] - z_web) <= 4e-3
    growth = float(out[3000.0][0].rim_radial_growth(3000.0)[1])
    assert 40e-6 <= growth <= 100e-6
    centroid = lambda q: float(np.sum(q * z) / np.sum(q))  # noqa: E731
    assert centroid(load1) - centroid(load0) > 1e-3
    edge = slice(-8, None)  # the cantilevered quarter of the face
    assert load1[edge].sum() > 1.5 * load0[edge].sum()


def test_accessory_te_mean_order_rigidified_lumped_flexible(cache):
    """TE mean of the accessory pair: H1 with a rigidified wheel (E × 1000) < the rigid-node
    lumped scene (Init) < H1 with the steel wheel. The rigidified wheel drops the Weber
    foundation term (the FE rim replaces it) and its rigid hub clamps the shaft between its two
    bearing nodes, both stiffer than Init; the web and rim add more compliance than the
    foundation term they replace. Measured 31.2 < 35.2 < 45.9 µm. (We read the seed's
    III-8 as "Init < H1 rigid < H1 flexible", 19 → 41 µm; the seed's Init model keeps details
    we cannot reconstruct, so only the flexible wheel's increase is compared.)"""
    case = jio.load_case("accessory-spur-flexible").replace(speed=0.0)
    flexible = fem_prep.condensed("accessory-wheel")
    text = (pathlib.Path(fem_prep.__file__).parent / "bodies" / "accessory-wheel.toml").read_text()
    stiff = text.replace("youngs_modulus_GPa = 210.0", "youngs_modulus_GPa = 210000.0")
    assert stiff != text
    rigidified = fem_prep.condensed(fem_prep.parse_body(stiff))
    lumped = case.replace(scene=dataclasses.replace(case.scene, gear_body=None))
    te = [
        float(jg.quasi_static(static_scene(c, bodies=bs)[0], c.modifications, c.torque).te_mean)
        for c, bs in ((case, (None, rigidified)), (lumped, None), (case, (None, flexible)))
    ]
    assert te[0] < te[1] < te[2], te
    assert te[2] > 1.2 * te[1]  # the thin web: +30 %


def test_accessory_te_rms_order_init_h1_h2(cache):
    """Seed Tab. III-4, unmodified accessory pair: TE RMS Init 2.92 > H1 2.36 > H2 1.79 µm
    (flexible wheel, then wheel and pinion flexible: the thin web and the pinion body smooth the
    mesh stiffness fluctuation). Ours (approximated bodies): 2.32 > 1.89 > 1.45 µm; the ratios
    to Init, 0.81 and 0.63 (seed 0.81 and 0.61), within 0.7–0.95 and 0.5–0.8."""
    case = jio.load_case("accessory-spur-flexible").replace(speed=0.0)
    wheel = fem_prep.condensed("accessory-wheel")
    pinion = fem_prep.condensed("accessory-pinion")
    lumped = case.replace(scene=dataclasses.replace(case.scene, gear_body=None))
    rms = [
        float(jg.quasi_static(static_scene(c, bodies=bs)[0], None, c.torque).te_rms)
        for c, bs in ((lumped, None), (case, (None, wheel)), (case, (pinion, wheel)))
    ]
    assert rms[0] > rms[1] > rms[2], rms
    assert 0.7 <= rms[1] / rms[0] <= 0.95
    assert 0.5 <= rms[2] / rms[0] <= 0.8


def test_power_crowning_optimum_at_speed(cache):
    """Seed IV-47/48: at 3000 rad/s a light crowning minimises the maximum line load of the power
    pair (the seed's compromise ≈ 10 µm, with edge contact lost at 20 µm). Ours (the case's
    10 µm tip relief, crowning per member): gradient optimum 3.8 µm, the web-side edge unloaded
    from 16 µm (docs/bench/crowning_at_speed.png): optimum in 2–10 µm, the edge unloaded by 20 µm."""
    import jax.numpy as jnp

    import optimise

    case = jio.load_case("power-helical-flexible")
    scene, _ = static_scene(case)
    problem = jio.case_problem(
        case, "crowning.depth", "max_line_load", scene=scene, speed=3000.0, relief_blend=0.0
    )
    res = optimise.minimise(problem, np.array([0.3]), progress=False)
    best = problem.to_physical(res.x)["crowning.depth"]
    assert 2.0 <= best <= 10.0, best
    x20 = jnp.asarray(problem.from_physical({"crowning.depth": 20.0}))
    r = jg.quasi_static(scene, problem.modifications(x20), case.torque, speed=3000.0)
    edge = np.asarray(r.line_load).max(axis=(0, 1))
    assert edge[0] == 0.0 and edge[-1] == 0.0


def test_power_crowning_against_the_dynamic_factor_at_speed(cache):
    """Seed IV-47/48 by the seed's own criterion: "crowning 5–20 µm: above 10 µm the edges
    unload and K_v rises, so ≈ 10 µm". docs/bench/crowning_dynamic_factor.{png,json}
    (examples/crowning_dynamic_factor.py): the power pair's dynamic factor over 2800–3200 rad/s
    (hybrid Newmark, exact contact, Rayleigh D1) against the crowning per member. Recomputed
    here at 0, 7.5 and 15 µm against the committed scan (rtol 1e-3); the committed scan is least
    in 5–10 µm, within 1.1 % of its least there, and rises steadily above 10 µm (15 and 20 µm
    more than 2 % above its minimum), and the gradient optimum of the band's smooth dynamic
    factor lies in the seed's 5–10 µm with its exact band maximum within 1 % of the scan's
    minimum;
    the gradient at 12.5 µm is recomputed against central differences (rtol 1e-3)."""
    import json

    root = pathlib.Path(__file__).parents[1]
    ex = load_example("crowning_dynamic_factor")
    stored = json.loads((root / "docs" / "bench" / "crowning_dynamic_factor.json").read_text())
    depths = np.asarray(stored["crowning_depth_um"])
    df = np.asarray(stored["dynamic_factor"])
    case, scene, problem = ex.setup()
    pick = [int(np.argmin(np.abs(depths - d))) for d in (0.0, 7.5, 15.0)]
    again = ex.scan(case, scene, problem, depths[pick])
    np.testing.assert_allclose(again, df[pick], rtol=1e-3)

    band = df.max(axis=1)
    lo = band.min()
    flat = (depths >= 5.0) & (depths <= 10.0)
    assert 5.0 <= depths[np.argmin(band)] <= 10.0
    assert np.all(band[flat] <= 1.008 * lo), band  # docs/guide/flexible.md: "within 0.8 %"
    above = depths >= 10.0
    assert np.all(np.diff(band[above]) > 0), band  # rises steadily above 10 µm
    assert np.all(band[depths >= 15.0] > 1.02 * lo), band
    opt = stored["optimum"]
    assert 5.0 <= opt["crowning_um"] <= 10.0
    assert opt["crowning_um"] == pytest.approx(7.8, abs=0.05)  # docs/guide/flexible.md's figure
    assert max(opt["dynamic_factor_exact"]) <= 1.01 * lo
    g = ex.gradient_check(problem, 12.5)
    assert g["grad_per_um"] == pytest.approx(g["fd_per_um"], rel=1e-3)
    assert g["grad_per_um"] > 0  # the band's dynamic factor rises with crowning above 10 µm
