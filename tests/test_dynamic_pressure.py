"""Dynamic contact pressure: the per-cell loads a dynamic run records (``cell_loads=True``), the
largest Hertzian pressure it tracks in its time loop (``pressure=HertzPressure(...)``), and the
files and keys ``jaxgear sweep`` writes from them.

References: the quasi-static solver at a speed far below every resonance (the loads and
pressures of the same cells at the same positions), the run's own per-line forces (a separate
record of the loop: Σ line load × cell length over a line's cells), Hertz's formula applied
after the run (:func:`jaxgear.contact_pressure`) to the recorded loads, and the rigid mesh's
quasi-static solution for the static maximum of ``sweep.json``.
"""

import json
import pathlib
import tomllib
from types import SimpleNamespace

import numpy as np
import pytest
from _toml import ACCESSORY_PAIR

import fem_prep
import jaxgear as jg
import jaxgear.io as jio
from jaxgear.cli import OUTPUT_FILES, main
from jaxgear.cli.sweep import dynamic_pressure_map
from jaxgear.dynamics import (
    HertzPressure,
    Newmark,
    Outputs,
    SteadyState,
    dynamic_model,
    simulate,
    speed_sweep,
)
from jaxgear.io import build_dynamic_model, static_scene
from jaxgear.scenes import TorsionalDynamics, disc_inertia

DATA = pathlib.Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def accessory():
    """The accessory spur pair (its 15 µm tip relief: a continuous mesh stiffness, so that the
    low-speed response is the quasi-static one) on the torsional scene, 4 slices."""
    case = jio.load_case("accessory-spur").replace(slices=4)
    p = case.pair
    scene = TorsionalDynamics(
        case.mesh_model(),
        disc_inertia(case.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(case.density, p.tip_radii[1], p.gear.face_width),
    )
    hertz = HertzPressure(p, case.youngs_modulus, case.poisson_ratio)
    return case, scene, hertz


def _pressure(case, result):
    return np.asarray(
        jg.contact_pressure(case.pair, result, case.youngs_modulus, case.poisson_ratio).max_pressure
    )


def test_low_speed_cell_loads_and_pressures_are_the_quasi_static_ones(accessory):
    """At 2 rad/s (mesh frequency 14 Hz against the 6.2 kHz torsional mode; Δt ≈ T_n/10) the
    recorded cells are the quasi-static solver's at the same positions (same s, z and mask) and
    carry its loads: measured max |Δw| = 4.4e-4 of the largest load, max |Δp₀| = 4.7e-3 of the
    largest pressure (p₀ ∝ √w: the relative error of a lightly loaded cell doubles and grows
    as w → 0), 2.2e-4 relative on the cells loaded above a tenth of the largest load; the
    largest pressure 1.8e-4 relative. Tolerances: 2e-3, 1e-2, 1e-3, 1e-3."""
    case, scene, hertz = accessory
    model = dynamic_model(scene, case.modifications, case.torque, positions_per_pitch=32)
    r = simulate(
        model,
        2.0,
        integrator=Newmark(2000),
        window=SteadyState(3, 2),
        outputs=Outputs(cell_loads=True, pressure=hertz),
    )
    assert int(r.result) == 0
    assert r.line_load.shape == (4000, scene.mesh.n_lines, 4)
    qs = jg.quasi_static(scene.mesh, case.modifications, case.torque, theta=r.theta)
    # the low-speed limit of the dynamics (tests/test_dynamics.py's slow
    # test_low_speed_limit_matches_quasi_static, the same run on 2 slices): dynamic factors
    # 1 within 5e-3, the TE the quasi-static one within 5e-3 of its mean, its RMS within 5 %
    assert abs(float(r.dynamic_factor) - 1.0) < 5e-3
    assert abs(float(r.dynamic_factor_tooth) - 1.0) < 5e-3
    te_qs = np.asarray(qs.transmission_error)
    assert np.max(np.abs(np.asarray(r.transmission_error) - te_qs)) < 5e-3 * np.mean(te_qs)
    assert float(r.te_rms) == pytest.approx(float(qs.te_rms), rel=0.05)
    for name in ("cell_s", "cell_z", "cell_mask"):
        np.testing.assert_array_equal(np.asarray(getattr(r, name)), np.asarray(getattr(qs, name)))
    w, w_qs = np.asarray(r.line_load), np.asarray(qs.line_load)
    assert np.max(np.abs(w - w_qs)) < 2e-3 * w_qs.max()
    p, p_qs = _pressure(case, r), _pressure(case, qs)
    assert np.max(np.abs(p - p_qs)) < 1e-2 * p_qs.max()
    loaded = w_qs > 0.1 * w_qs.max()
    np.testing.assert_allclose(p[loaded], p_qs[loaded], rtol=1e-3)
    assert float(r.max_pressure) == pytest.approx(p_qs.max(), rel=1e-3)
    # one speed: the largest pressure of the time loop is the largest of the recorded loads'
    # (test_in_loop_max_pressure_is_the_max_of_the_recorded_pressures: a sweep's speeds)
    assert float(r.max_pressure) == pytest.approx(p.max(), rel=1e-12)


# default tier: tests/test_dynamic_pressure.py::test_in_loop_max_pressure_is_the_max_of_the_recorded_pressures (same claim, cell loads summing to the line forces, on the torsional scene's sweep)
@pytest.mark.slow
def test_cell_loads_sum_to_the_line_forces(accessory):
    """Σ over a contact line's cells of line load × cell length is the line force the loop
    records separately (``line_force``), to round-off: the accessory pair's lumped 3D scene
    (shafts, bearings) in a two-speed sweep (the torsional scene's, at a resonance and above:
    test_in_loop_max_pressure_is_the_max_of_the_recorded_pressures, on its sweep's records)."""
    case, scene, _ = accessory
    length = np.asarray(scene.mesh.cells(0.0).length)
    kw = {  # N_s = the model's 64 positions per pitch: its table's program, compiled once
        "integrator": Newmark(64),
        "window": SteadyState(4, 2),
        "outputs": Outputs(cell_loads=True),
    }
    assert case.scene.model == "lumped3d"
    model3d, _ = build_dynamic_model(case)
    s = speed_sweep(model3d, [700.0, 950.0], **kw).results
    lf = np.asarray(s.line_force)
    assert lf.shape == (2, 128, scene.mesh.n_lines)
    np.testing.assert_allclose(
        (np.asarray(s.line_load) * length).sum(-1), lf, atol=1e-12 * lf.max()
    )


def test_in_loop_max_pressure_is_the_max_of_the_recorded_pressures(accessory):
    """The largest pressure reduced in the time loop (p₀² = w E*/(π R) per cell and step, the
    maximum kept) is the maximum of :func:`jaxgear.contact_pressure` applied after the run to
    the recorded loads of the same run: a two-speed vmapped sweep (a resonance and above it;
    one speed's :func:`simulate`: test_low_speed_cell_loads_and_pressures_are_the_quasi_static_ones).
    Its static counterpart is the rigid mesh's quasi-static maximum at the same positions (the
    model's static solution; 1e-9). At the resonance p₀/p₀,static = 1.27 with contact beyond the
    path (the case files' default; dynamic factor 1.68, √1.68 = 1.30; on the theoretical path
    1.30 and 1.75)."""
    case, scene, hertz = accessory
    model = dynamic_model(scene, case.modifications, case.torque)
    kw = {"integrator": Newmark(64), "window": SteadyState(30, 4)}
    speeds = [866.0, 1500.0]
    s = speed_sweep(model, speeds, outputs=Outputs(cell_loads=True, pressure=hertz), **kw).results
    # the torsional scene's cell loads sum over each contact line to the line force the loop
    # records separately (test_cell_loads_sum_to_the_line_forces: the lumped 3D scene's)
    length = np.asarray(scene.mesh.cells(0.0).length)
    lf = np.asarray(s.line_force)
    assert lf.shape == (2, 4 * 64, scene.mesh.n_lines)
    np.testing.assert_allclose(
        (np.asarray(s.line_load) * length).sum(-1), lf, atol=1e-12 * lf.max()
    )
    qs = jg.quasi_static(scene.mesh, case.modifications, case.torque, positions_per_pitch=64)
    static = _pressure(case, qs).max()
    np.testing.assert_allclose(np.asarray(s.max_pressure_static), static, rtol=1e-9)
    assert float(s.max_pressure[0] / s.max_pressure_static[0]) == pytest.approx(1.27, abs=0.01)
    for i in range(2):
        p = np.asarray(
            jg.contact_pressure(
                case.pair,
                _Cells(s.line_load[i], s.cell_s[i], s.cell_mask[i]),
                case.youngs_modulus,
                case.poisson_ratio,
            ).max_pressure
        )
        assert float(s.max_pressure[i]) == pytest.approx(p.max(), rel=1e-12)
    # without cell_loads a sweep keeps no per-cell record, and the maxima are unchanged
    lean = speed_sweep(model, speeds, outputs=Outputs(pressure=hertz), **kw).results
    assert lean.line_load is None and lean.cell_s is None
    np.testing.assert_allclose(
        np.asarray(lean.max_pressure), np.asarray(s.max_pressure), rtol=1e-12
    )


class _Cells:
    """One speed's recorded cells (what :func:`jaxgear.contact_pressure` reads)."""

    def __init__(self, line_load, cell_s, cell_mask):
        self.line_load, self.cell_s, self.cell_mask = line_load, cell_s, cell_mask


def test_hertz_pressure_settings_errors(accessory):
    case, scene, _ = accessory
    model = dynamic_model(scene, case.modifications, case.torque)
    with pytest.raises(ValueError, match="pressure: 2 gear pairs for a scene of 1 gear mesh"):
        simulate(
            model, 900.0, outputs=Outputs(pressure=HertzPressure((case.pair, case.pair), 2e11, 0.3))
        )
    with pytest.raises(ValueError, match="pressure = "):
        simulate(model, 900.0, outputs=Outputs(pressure=(2e11, 0.3)))
    with pytest.raises(ValueError, match="youngs_modulus = -1"):
        HertzPressure(case.pair, -1.0, 0.3)
    with pytest.raises(ValueError, match="poisson_ratio = 0.5"):
        HertzPressure(case.pair, 2e11, 0.5)
    with pytest.raises(ValueError, match="pairs = "):
        HertzPressure("accessory-spur", 2e11, 0.3)
    assert HertzPressure(case.pair, 2e11, 0.3).pairs == (case.pair,)


CASE = (
    """
name = "tiny-pressure"
"""
    + ACCESSORY_PAIR
    + """[mesh]
stiffness = "uniform"
stiffness_per_length_N_per_mm_per_um = 14.0
slices = 2
[modifications]
tip_relief = { depth_um = 15.0, extent = 0.25 }
[scene]
model = "torsional"
[scene.damping]
model = "modal"
ratio = 0.05
[scene.integration]
steps_per_period = 32
periods = 6
keep_periods = 2
"""
)


def test_cli_sweep_writes_the_pressure_keys_and_files(tmp_path):
    """``jaxgear sweep`` writes the largest pressure per speed, the quasi-static maximum at rest
    (the rigid mesh's quasi-static solution on the same 32 positions: the torsional pair's
    static loads), the pressure against speed and the pressure map at the speed of the largest
    dynamic factor: every file of :data:`OUTPUT_FILES` ``["sweep"]`` but a train's and a planetary
    stage's ring spectrum."""
    path = tmp_path / "tiny.toml"
    path.write_text(CASE)
    out = tmp_path / "out"
    assert main(["sweep", str(path), "--speeds", "500:1500:4", "--out", str(out), "--quiet"]) == 0
    names = {p.name for p in out.iterdir() if not p.name.startswith(".")}
    assert names == {n for n in OUTPUT_FILES["sweep"] if "*" not in n} - {"ring_spectrum.png"}
    for png in ("contact_pressure.png", "pressure_map_dynamic.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG"
    data = json.loads((out / "sweep.json").read_text())
    case = jio.load_case(path)
    qs = jg.quasi_static(case.mesh_model(), case.modifications, case.torque, positions_per_pitch=32)
    static = _pressure(case, qs).max()
    assert data["max_contact_pressure_static_Pa"] == pytest.approx(static, rel=1e-9)
    p = np.asarray(data["max_contact_pressure_Pa"])
    assert p.shape == (4,) and np.all(p > 0.9 * static)
    m = data["pressure_map_dynamic"]
    i = int(np.argmax(data["dynamic_factor"]))
    assert m["speed_rad_s"] == data["speeds_rad_s"][i]
    assert m["files"] == ["pressure_map_dynamic.png"]
    # the map's run is the sweep's speed again, from the same start: the same maximum
    assert m["max_contact_pressure_Pa"] == pytest.approx(p[i], rel=1e-9)


def test_pressure_map_run_is_a_fresh_run_at_the_worst_speed():
    """``dynamic_pressure_map`` (``jaxgear sweep``'s map at the speed of the largest dynamic
    factor) returns its run: at the speed of the largest dynamic factor among the speeds that
    ran to the end (a diverged speed of a larger factor passed over), with its cell loads, the
    run a fresh ``simulate`` of the same model and settings gives (``jaxgear run`` hands it to
    the root stress at speed instead of simulating it again). The sweep's results stand in as
    the three dynamic factors and result codes the map reads."""
    case = jio.parse_case(tomllib.loads(CASE))
    model, spec = build_dynamic_model(case)
    law = case.contact_law(spec.contact)
    hertz = HertzPressure(case.pair, case.youngs_modulus, case.poisson_ratio)
    speeds = np.array([500.0, 900.0, 1300.0])
    mesh = SimpleNamespace(dynamic_factor=np.array([1.1, 1.3, 1.5]))
    sweep = SimpleNamespace(meshes=(mesh,), result=np.array([0, 0, 2]))
    got = dynamic_pressure_map(case, model, spec, law, sweep, speeds, hertz)
    run = got["run"]
    assert float(run.speed) == 900.0 == got["summary"]["speed_rad_s"]
    fresh = simulate(
        model,
        900.0,
        integrator=Newmark(32),
        contact=law,
        window=SteadyState(6, 2),
        outputs=Outputs(cell_loads=True),
    )
    np.testing.assert_allclose(run.line_load, fresh.line_load, rtol=1e-12, atol=0)
    assert _pressure(case, run).max() == pytest.approx(
        got["summary"]["max_contact_pressure_Pa"], rel=1e-12
    )


@pytest.mark.slow
def test_sweep_hands_over_its_run_at_the_worst_speed(tmp_path):
    """``sweep_case_run`` returns, beside ``sweep.json``'s dict, the run its pressure map read:
    at the speed of the largest dynamic factor, with the case's settings and its cell loads,
    the run a fresh ``simulate`` of the case's model gives (``jaxgear run`` hands it to the
    root stress at speed instead of simulating it again); the run's Hertzian maximum is the
    map's. (The fast test above checks the map's run on a hand-made sweep.)"""
    from jaxgear.cli.sweep import sweep_case_run

    path = tmp_path / "tiny.toml"
    path.write_text(CASE)
    case = jio.load_case(path)
    data, run = sweep_case_run(
        case, np.array([500.0, 900.0, 1300.0]), str(tmp_path / "out"), show_progress=False
    )
    i = int(np.argmax(data["dynamic_factor"]))
    assert (
        float(run.speed) == data["speeds_rad_s"][i] == data["pressure_map_dynamic"]["speed_rad_s"]
    )
    model, spec = build_dynamic_model(case)
    fresh = simulate(
        model,
        data["speeds_rad_s"][i],
        integrator=Newmark(32),
        contact=case.contact_law(spec.contact),
        window=SteadyState(6, 2),
        outputs=Outputs(cell_loads=True),
    )
    np.testing.assert_allclose(run.line_load, fresh.line_load, rtol=1e-12, atol=0)
    assert float(run.dynamic_factor) == pytest.approx(data["dynamic_factor"][i], rel=1e-12)
    assert _pressure(case, run).max() == pytest.approx(
        data["pressure_map_dynamic"]["max_contact_pressure_Pa"], rel=1e-12
    )


@pytest.mark.slow
def test_hybrid_cell_loads_and_in_loop_max(fem_prep_cache):
    """The hybrid Newmark (condensed test wheel, cell space) records the same quantities: the
    loads sum to the line forces, the in-loop maximum is that of the recorded pressures."""
    case = jio.load_case(DATA / "hybrid-test-case.toml")
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    scene = static_scene(case, bodies=(None, body))[0]
    model = dynamic_model(scene, case.modifications, case.torque)
    hertz = HertzPressure(case.pair, case.youngs_modulus, case.poisson_ratio)
    r = simulate(
        model,
        900.0,
        integrator=Newmark(16),
        window=SteadyState(6, 2),
        outputs=Outputs(cell_loads=True, pressure=hertz),
    )
    assert int(r.result) == 0 and r.line_load.shape == (32, scene.mesh.n_lines, 4)
    length = np.asarray(scene.mesh.cells(0.0).length)
    lf = np.asarray(r.line_force)
    np.testing.assert_allclose(
        (np.asarray(r.line_load) * length).sum(-1), lf, atol=1e-12 * lf.max()
    )
    assert float(r.max_pressure) == pytest.approx(_pressure(case, r).max(), rel=1e-12)
    assert float(r.max_pressure_static) > 0
