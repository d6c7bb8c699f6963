"""Hertzian contact pressure on the flanks (jaxgear.contact_pressure).

References: ISO 6336-2's nominal contact stress σ_H0 = Z_H Z_E Z_ε √(F_t (u + 1)/(d₁ b u)) computed
here by hand from the standard's factors (Z_ε = 1 in single-pair contact); Hertz's half-width of
a line contact written in the plane-strain modulus form a² = 8 w R (1 − ν²)/(π E) with the pitch
point's relative radius from the pitch diameters; Hertz's p₀ ∝ √w.
"""

from __future__ import annotations

import json
import math

import jax
import numpy as np
import pytest
from _examples import load_example

import jaxgear as jg
from jaxgear import io as jio
from jaxgear.cli.run import run_case

PPP = 128


@pytest.fixture(scope="module")
def spur():
    """The accessory spur pair, unmodified, uniform mesh stiffness (a uniform load across the
    face in single-pair contact), exact contact."""
    # theoretical path: Hertz's p₀ ∝ √w below needs a contact pattern that the load does not move
    case = jio.load_case("accessory-spur").replace(
        stiffness=jg.Uniform(1.4e10),
        slices=4,
        positions_per_pitch=PPP,
        contact_geometry=jg.TheoreticalPath(),
    )
    res = jg.quasi_static(case.mesh_model(), None, case.torque, positions_per_pitch=PPP)
    return case, res


def _pitch_point_cells(case, res):
    """Cells within half a position step of the pitch point, at positions of single-pair
    contact (one contact line loaded: contact length below 1.5 b)."""
    pair = case.pair
    z1, z2 = pair.pinion.teeth, pair.gear.teeth
    r_w1 = pair.center_distance * z1 / (z1 + z2)  # operating pitch radius
    s_p = r_w1 * math.sin(pair.operating_pressure_angle) - pair.start_roll
    single = np.asarray(res.contact_length) < 1.5 * pair.face_width
    step = pair.base_pitch / PPP
    near = np.asarray(res.cell_mask) & (np.abs(np.asarray(res.cell_s) - s_p) < 0.5 * step)
    return near & single[:, None, None]


def test_pitch_point_pressure_equals_iso_6336_2_nominal_contact_stress(spur):
    """At the pitch point in single-pair contact the cell pressure equals σ_H0 of ISO 6336-2
    (Z_H, Z_E, Z_ε = 1, F_t at the reference diameter) within 2 % (measured 3e-5)."""
    case, res = spur
    pair = case.pair
    p = np.asarray(jg.contact_pressure(pair, res, case.youngs_modulus, case.poisson_ratio)[0])
    cells = _pitch_point_cells(case, res)
    assert cells.sum() >= 2
    u = pair.gear.teeth / pair.pinion.teeth
    d1 = 2 * pair.pitch_radii[0]
    b = min(pair.pinion.face_width, pair.gear.face_width)
    f_t = 2 * case.torque / d1
    a_t, a_w = pair.transverse_pressure_angle, pair.operating_pressure_angle
    z_h = math.sqrt(2 * math.cos(a_w) / (math.cos(a_t) ** 2 * math.sin(a_w)))  # spur, β = 0
    nu, E = case.poisson_ratio, case.youngs_modulus
    z_e = math.sqrt(1 / (math.pi * 2 * (1 - nu**2) / E))
    sigma_h0 = z_h * z_e * math.sqrt(f_t * (u + 1) / (d1 * b * u))
    np.testing.assert_allclose(p[cells], sigma_h0, rtol=2e-2)


def test_half_width_follows_hertz_line_contact(spur):
    """The half-width at the pitch point equals Hertz's a = √(8 w R (1 − ν²)/(π E)) with
    w = F_n/b and R = (d_w1 sin α_wt / 2) u/(u + 1), within 2 %; and p₀ = 2w/(π a)."""
    case, res = spur
    pair = case.pair
    pr = jg.contact_pressure(pair, res, case.youngs_modulus, case.poisson_ratio)
    cells = _pitch_point_cells(case, res)
    u = pair.gear.teeth / pair.pinion.teeth
    d_w1 = 2 * pair.center_distance / (1 + u)
    R = 0.5 * d_w1 * math.sin(pair.operating_pressure_angle) * u / (u + 1)
    w = case.torque / pair.base_radii[0] / min(pair.pinion.face_width, pair.gear.face_width)
    nu, E = case.poisson_ratio, case.youngs_modulus
    a = math.sqrt(8 * w * R * (1 - nu**2) / (math.pi * E))
    np.testing.assert_allclose(np.asarray(pr.half_width)[cells], a, rtol=2e-2)
    load = np.asarray(res.line_load)[cells]
    np.testing.assert_allclose(
        np.asarray(pr.max_pressure)[cells], 2 * load / (math.pi * a), rtol=2e-2
    )


def test_pressure_is_zero_off_the_flanks_and_grows_as_the_root_of_the_load(spur):
    """No pressure on cells off the flanks or unloaded; four times the torque doubles the
    pressure (Hertz: p₀ ∝ √w, the unmodified pair's contact pattern unchanged), to 1e-9."""
    case, res = spur
    pr = jg.contact_pressure(case.pair, res, case.youngs_modulus, case.poisson_ratio)
    p = np.asarray(pr.max_pressure)
    idle = ~np.asarray(res.cell_mask) | (np.asarray(res.line_load) <= 0)
    assert np.all(p[idle] == 0) and np.all(np.asarray(pr.half_width)[idle] == 0)
    four = jg.quasi_static(case.mesh_model(), None, 4 * case.torque, positions_per_pitch=PPP)
    p4 = np.asarray(jg.contact_pressure(case.pair, four, case.youngs_modulus, 0.3).max_pressure)
    np.testing.assert_allclose(p4, 2 * p, rtol=1e-9, atol=1e-9 * p.max())


def test_pressure_runs_under_jit_and_its_gradient_matches_differences(spur):
    """Under jit the same maximum; the gradient of the largest pressure with respect to the
    torque (through the quasi-static solve) matches central differences (rtol 1e-5), on the
    mesh with cells beyond the path (the case files' default): its unloaded corner cells
    (w = 0, where √w has no derivative) must not make it NaN."""
    case, res = spur
    mesh = case.replace(contact_geometry=jg.BeyondPath()).mesh_model()

    def peak(torque):
        r = jg.quasi_static(mesh, None, torque, positions_per_pitch=16)
        return jg.contact_pressure(case.pair, r, 210e9, 0.3).max_pressure.max()

    eager = float(np.asarray(jg.contact_pressure(case.pair, res, 210e9, 0.3)[0]).max())
    f = jax.jit(lambda r: jg.contact_pressure(case.pair, r, 210e9, 0.3).max_pressure.max())
    assert float(f(res)) == pytest.approx(eager, rel=1e-12)
    t, h = case.torque, 1e-3 * case.torque
    # the gradient and the differences' values from one compiled program
    value_and_grad = jax.jit(jax.value_and_grad(peak))
    fd = (float(value_and_grad(t + h)[0]) - float(value_and_grad(t - h)[0])) / (2 * h)
    assert float(value_and_grad(t)[1]) == pytest.approx(fd, rel=1e-5)


# slow: the same run (run_case on accessory-spur) is tests/test_cli.py's default
# test_quickstart_example_runs, which asserts these outputs of it
@pytest.mark.slow
def test_jaxgear_run_writes_the_pressure(tmp_path):
    """``jaxgear run``'s quasi-static files (its sweep left out): ``max_contact_pressure_Pa`` per
    contact law, the pressure per position
    in ``mesh_stiffness.csv`` and ``pressure_map.png``; its maximum equals the largest column
    value (one field, two outputs)."""
    out = tmp_path / "out"
    run_case(jio.load_case("accessory-spur"), str(out), show_progress=False)
    s = json.loads((out / "summary.json").read_text())
    q = s["quasi_static"]["exact"]
    assert 5e8 < q["max_contact_pressure_Pa"] < 2e9 and q["contact_half_width_at_max_m"] > 0
    header = (out / "mesh_stiffness.csv").read_text().splitlines()[0].split(",")
    col = header.index("max_contact_pressure_exact_modified_Pa")
    data = np.loadtxt(out / "mesh_stiffness.csv", delimiter=",", skiprows=1)
    assert data[:, col].max() == pytest.approx(q["max_contact_pressure_Pa"], rel=1e-9)
    assert (out / "pressure_map.png").stat().st_size > 0


@pytest.mark.slow
def test_pressure_across_the_face_against_crowning_at_speed():
    """docs/bench/pressure_crowning.{png,json} (the seed's Fig. IV-47 form; examples/pressure_crowning.py):
    the power pair's hybrid scene at 3000 rad/s, quasi-static and dynamic. Recomputed at 0 and
    10 µm (the dynamic run at 10 µm) against the committed curves (rtol 1e-6, dynamic 1e-4);
    the committed curves: the lowest peak pressure at 5 µm (914 MPa, against 1026 MPa without
    crowning, at the web-side edge), the peak rising with deeper crowning (1092 MPa at 20 µm),
    the cantilevered edge unloaded from 5 µm and both edges from 20 µm. Dynamic: the peaks
    1065, 944, 985, 1037, 1083 MPa (the lowest at 5 µm, the dynamic load adding 4 % without
    crowning), the dynamic factor lowest at 10 µm (1.059; 1.120 without crowning), the seed's
    IV-47/48 choice."""
    import pathlib

    root = pathlib.Path(__file__).parents[1]
    ex = load_example("pressure_crowning")
    stored = json.loads((root / "docs" / "bench" / "pressure_crowning.json").read_text())
    case = jio.load_case("power-helical-flexible")
    from jaxgear.io import static_scene

    scene, _ = static_scene(case)
    for i in (0, 2):  # 0 and 10 µm
        _, p = ex.pressure_across_face(case, scene, stored["crowning_um"][i])
        np.testing.assert_allclose(p, stored["pressure_Pa"][i], rtol=1e-6)
    peaks = [max(p) for p in stored["pressure_Pa"]]
    assert int(np.argmin(peaks)) == 1 and np.all(np.diff(peaks[1:]) > 0)
    np.testing.assert_allclose(np.array(peaks)[[0, 1, 4]] / 1e6, [1026, 914, 1092], atol=1)
    edges = np.array([(p[0], p[-1]) for p in stored["pressure_Pa"]])
    assert np.all(edges[1:, 1] == 0) and edges[0, 1] > 0 and np.all(edges[-1] == 0)
    bodies = ex.load_bodies(case.scene)
    pd, df = ex.dynamic_pressure_across_face(case, bodies, stored["crowning_um"][2])
    np.testing.assert_allclose(pd, stored["pressure_dynamic_Pa"][2], rtol=1e-4)
    assert df == pytest.approx(stored["dynamic_factor"][2], rel=1e-4)
    dyn = [max(p) for p in stored["pressure_dynamic_Pa"]]
    np.testing.assert_allclose(np.array(dyn) / 1e6, [1065, 944, 985, 1037, 1083], atol=1)
    assert int(np.argmin(stored["dynamic_factor"])) == 2
    np.testing.assert_allclose(
        np.array(stored["dynamic_factor"])[[0, 2]], [1.120, 1.059], atol=5e-4
    )
