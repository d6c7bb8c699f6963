"""Dynamic model: the [scene] table, `jaxgear sweep`, sharded sweeps, diffrax solvers."""

import json
import pathlib
import re
import textwrap
import warnings

import numpy as np
import pytest
from _devices import run_on_cpu_devices
from _examples import load_example
from _toml import ACCESSORY_PAIR

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
from jaxgear.cli import main
from jaxgear.dynamics import DiffraxIntegrator, Newmark, SteadyState
from jaxgear.io import SceneSpec, build_dynamic_model, parse_scene

ROOT = pathlib.Path(__file__).resolve().parents[1]


SHAFT = {
    "length_mm": 100.0,
    "diameter_mm": 30.0,
    "gear_position_mm": 50.0,
    "bearings": [
        {"position_mm": 0.0, "radial_N_per_um": 200.0, "axial_N_per_um": 100.0},
        {"position_mm": 100.0, "radial_N_per_um": 200.0},
    ],
}


def test_scene_defaults_and_validation():
    assert parse_scene(None) == SceneSpec()
    s = parse_scene(
        {
            "model": "torsional",
            "motor_inertia_kg_m2": 0.01,
            "motor_shaft_stiffness_Nm_per_rad": 2e4,
            "damping": {"model": "rayleigh", "alpha_per_s": 20.0, "beta_s": 1e-6},
            "integration": {
                "solver": "kvaerno5",
                "contact": "smooth",
                "periods": 10,
                "keep_periods": 3,
            },
        }
    )
    assert s.motor_inertia == 0.01 and s.damping_model == "rayleigh" and s.rayleigh_beta == 1e-6
    assert s.solver == "kvaerno5" and s.periods == 10
    bad = [
        ({"inertia": 1.0}, "'inertia'"),
        ({"damping": {"zeta": 0.1}}, "'zeta'"),
        ({"integration": {"dt": 1e-6}}, "'dt'"),
        ({"model": "lumped3d"}, "pinion_shaft"),
        (
            {"model": "lumped3d", "pinion_shaft": {**SHAFT, "bore": 1}, "gear_shaft": SHAFT},
            "'bore'",
        ),
        (
            {
                "model": "lumped3d",
                "pinion_shaft": {
                    **SHAFT,
                    "bearings": [{"position_mm": 0.0, "radial_N_per_um": 200.0, "stiff": 1}],
                },
                "gear_shaft": SHAFT,
            },
            "'stiff'",
        ),
        (
            {
                "model": "lumped3d",
                "pinion_shaft": {**SHAFT, "gear_position_mm": 500.0},
                "gear_shaft": SHAFT,
            },
            "beyond the shaft length",
        ),
        (
            {
                "model": "lumped3d",
                "pinion_shaft": SHAFT,
                "gear_shaft": SHAFT,
                "motor_inertia_kg_m2": 1.0,
            },
            "torsional",
        ),
        ({"pinion_shaft": SHAFT}, "lumped3d"),
        ({"model": "beam"}, "model"),
        ({"motor_inertia_kg_m2": 0.01}, "go together"),
        ({"pinion_inertia_kg_m2": -1.0}, "pinion_inertia_kg_m2"),
        ({"damping": {"model": "modal", "ratio": 2.0}}, "ratio"),
        ({"integration": {"solver": "rk4"}}, "solver"),
        ({"integration": {"periods": 3, "keep_periods": 4}}, "keep_periods"),
        (
            {
                "reduction": "relative",
                "load_inertia_kg_m2": 1.0,
                "load_shaft_stiffness_Nm_per_rad": 1e4,
            },
            "relative",
        ),
    ]
    for table, match in bad:
        with pytest.raises(ValueError, match=match):
            parse_scene(table)


def test_solver_names_match_the_library(capsys):
    """``jaxgear sweep --solver`` offers exactly the library's integrators (as its help lists)."""
    from jaxgear.dynamics import DIFFRAX_SOLVERS

    assert main(["sweep", "--help"]) == 0
    (choices,) = set(re.findall(r"--solver \{([^}]*)\}", capsys.readouterr().out))
    assert set(choices.split(",")) == {"newmark", *DIFFRAX_SOLVERS}


def test_case_scene_builds_the_four_dof_model():
    case = jio.load_case("accessory-spur").replace(slices=2)
    scene = parse_scene(
        {
            "motor_inertia_kg_m2": 5e-3,
            "motor_shaft_stiffness_Nm_per_rad": 2e4,
            "load_inertia_kg_m2": 4e-2,
            "load_shaft_stiffness_Nm_per_rad": 6e4,
            "integration": {"steps_per_period": 16},
        }
    )
    model, spec = build_dynamic_model(case.replace(scene=scene))
    assert model.scene.n_dof == 4 and spec.steps_per_period == 16
    assert model.modes.parts == ("mesh", "motor_shaft", "load_shaft")


CASE = (
    """
name = "tiny-sweep"
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
steps_per_period = 16
periods = 6
keep_periods = 2
"""
)


def test_cli_sweep_writes_json_and_plots(tmp_path, capsys):
    case = tmp_path / "tiny.toml"
    case.write_text(CASE)
    out = tmp_path / "out"
    # the tiny case fixes few steps per mesh period: the slow speeds are flagged
    with warnings.catch_warnings():  # shown by the CLI as one stderr line, not raised
        warnings.simplefilter("default")
        rc = main(
            [
                "sweep",
                str(case),
                "--speeds",
                "300:1100:5",
                "--direction",
                "both",
                "--out",
                str(out),
                "--quiet",
            ]
        )
    assert rc == 0
    captured = capsys.readouterr()
    assert "jaxgear: warning: 4 of 5 speeds are under-resolved" in captured.err
    data = json.loads((out / "sweep.json").read_text())
    assert any(data["under_resolved"])
    assert all(u == (s < 20) for u, s in zip(data["under_resolved"], data["steps_per_mode_period"]))
    assert data["speeds_rad_s"] == pytest.approx(np.linspace(300, 1100, 5).tolist())
    for key in (
        "dynamic_factor",
        "dynamic_factor_down",
        "dynamic_factor_tooth",
        "te_rms_m",
        "contact_loss",
        "result",
    ):
        assert len(data[key]) == 5, key
    assert all(v > 0.9 for v in data["dynamic_factor"])
    assert data["critical_speeds"][0]["harmonic"] == 1
    for png in ("dynamic_factor.png", "campbell.png"):
        assert (out / png).read_bytes()[:4] == b"\x89PNG"
    # sweep.csv beside sweep.json: a row per speed, the same numbers (12 significant digits)
    table = np.genfromtxt(out / "sweep.csv", delimiter=",", names=True)
    assert len(table) == 5
    for key in ("speed_rad_s", "dynamic_factor", "dynamic_factor_down", "te_rms_m"):
        ref = data["speeds_rad_s" if key == "speed_rad_s" else key]
        np.testing.assert_allclose(table[key], ref, rtol=1e-11)
    assert "max dynamic factor" in captured.out
    # bad input: exit status 2 with the offending key named
    bad = tmp_path / "bad.toml"
    bad.write_text(CASE.replace('model = "torsional"', 'model = "torsional"\nshafts = 2'))
    assert main(["sweep", str(bad), "--speeds", "300:1100:5", "--out", str(out)]) == 2
    assert "'shafts'" in capsys.readouterr().err
    assert main(["sweep", str(case), "--speeds", "300:100:5", "--out", str(out)]) == 2


# default tier: tests/test_dynamics_sweep.py::test_chunked_sweep_is_the_whole_sweep_with_progress (a batched sweep equals the whole one; the split over 4 forced CPU devices needs this subprocess)
@pytest.mark.slow
def test_sharded_sweep_matches_unsharded_on_four_cpu_devices():
    script = textwrap.dedent("""
        import jax, numpy as np
        jax.config.update("jax_enable_x64", True)
        import jaxgear.dynamics as jd
        import jaxgear.io as jio
        from jaxgear.dynamics import Newmark, SteadyState
        from jaxgear.io import build_dynamic_model, parse_scene
        case = jio.load_case("accessory-spur").replace(slices=2)
        spec = parse_scene({"integration": {"steps_per_period": 16, "periods": 4,
                                            "keep_periods": 2}})
        model, _ = build_dynamic_model(case, spec)
        speeds = np.linspace(300.0, 1200.0, 6)   # 6 speeds on 4 devices: padded to 8
        kw = dict(integrator=Newmark(16), window=SteadyState(4, 2))
        a = jd.speed_sweep(model, speeds, batching=jd.Batching(shard=True), **kw)
        b = jd.speed_sweep(model, speeds, batching=jd.Batching(shard=False), **kw)
        assert len(jax.local_devices()) == 4
        np.testing.assert_allclose(a.dynamic_factor, b.dynamic_factor, rtol=1e-10)
        print("OK", len(jax.local_devices()))
    """)
    assert "OK 4" in run_on_cpu_devices(script)


@pytest.fixture(scope="module")
def small_model():
    case = jio.load_case("accessory-spur").replace(slices=2)
    spec = parse_scene(
        {"damping": {"model": "modal", "ratio": 0.05}, "integration": {"steps_per_period": 32}}
    )
    return build_dynamic_model(case, spec)[0]


# default tier: tests/test_mesh_table.py::test_diffrax_records_take_each_mesh_at_its_own_row (same claim, Tsit5 with the smooth law agrees with Newmark on each dynamic factor within 0.5 %, on the torsional two-stage train)
@pytest.mark.slow
def test_diffrax_explicit_agrees_with_newmark(small_model):
    kw = dict(contact=jg.SmoothContact(1e-7), window=SteadyState(8, 2))
    nm = jd.simulate(small_model, 700.0, integrator=Newmark(32), **kw)
    tsit5 = DiffraxIntegrator("tsit5", 32, rtol=1e-7, atol=1e-7)
    ts = jd.simulate(small_model, 700.0, integrator=tsit5, **kw)
    assert int(ts.result) == 0
    assert float(ts.dynamic_factor) == pytest.approx(float(nm.dynamic_factor), rel=5e-3)
    assert float(ts.te_rms) == pytest.approx(float(nm.te_rms), rel=2e-2)


@pytest.mark.slow
def test_diffrax_implicit_agrees_with_newmark(small_model):
    kw = dict(contact=jg.SmoothContact(1e-7), window=SteadyState(8, 2))
    nm = jd.simulate(small_model, 700.0, integrator=Newmark(32), **kw)
    kvaerno5 = DiffraxIntegrator("kvaerno5", 32, rtol=1e-7, atol=1e-7)
    kv = jd.simulate(small_model, 700.0, integrator=kvaerno5, **kw)
    assert int(kv.result) == 0
    assert float(kv.dynamic_factor) == pytest.approx(float(nm.dynamic_factor), rel=5e-3)


@pytest.mark.slow
def test_continuation_matches_independent_away_from_jumps(small_model):
    speeds = np.linspace(200.0, 500.0, 4)
    kw = dict(integrator=Newmark(32), window=SteadyState(30, 2))
    ind = jd.speed_sweep(small_model, speeds, **kw)
    up = jd.speed_sweep(small_model, speeds, direction=jd.Up(), batching=jd.Batching(3), **kw)
    np.testing.assert_allclose(up.dynamic_factor, ind.dynamic_factor, rtol=2e-3)


@pytest.mark.slow
def test_example_tip_relief_lowers_the_peak_and_removes_the_jump(tmp_path):

    mod = load_example("speed_sweep")
    out = mod.main(str(tmp_path), n_speeds=16, periods=30)
    (up_r, down_r), (up_u, down_u) = out["curves"]["tip relief 15 µm"], out["curves"]["unmodified"]
    assert max(up_r.max(), down_r.max()) < 0.6 * max(up_u.max(), down_u.max())  # Fig. IV-4
    assert np.abs(up_u - down_u).max() > 0.3 > np.abs(up_r - down_r).max()
    assert (tmp_path / "speed_sweep.png").exists()


# default tier: tests/test_regression.py::test_same_numbers_as_recorded[sweep-accessory-spur] (same claim, jaxgear sweep on a lumped 3D pair: its model, energy parts, 60 frequencies, 10 bearing forces, results, against the record)
@pytest.mark.slow
def test_cli_sweep_lumped3d_scene(tmp_path, no_figures):
    text = CASE + textwrap.dedent("""
        [scene.pinion_shaft]
        length_mm = 100.0
        diameter_mm = 30.0
        gear_position_mm = 50.0
        elements = 2
        bearings = [{ position_mm = 0.0, radial_N_per_um = 200.0, axial_N_per_um = 100.0 },
                    { position_mm = 100.0, radial_N_per_um = 200.0 }]
        [scene.gear_shaft]
        length_mm = 100.0
        diameter_mm = 35.0
        gear_position_mm = 50.0
        torque_position_mm = 100.0
        elements = 2
        bearings = [{ position_mm = 0.0, radial_N_per_um = 300.0, axial_N_per_um = 100.0 },
                    { position_mm = 100.0, radial_N_per_um = 300.0 }]
    """)
    text = text.replace('model = "torsional"', 'model = "lumped3d"')
    case = tmp_path / "lumped.toml"
    case.write_text(text)
    out = tmp_path / "out"
    with warnings.catch_warnings():  # shown by the CLI as one stderr line, not raised
        warnings.simplefilter("default")
        rc = main(
            [
                "sweep",
                str(case),
                "--speeds",
                "400:1200:3",
                "--periods",
                "4",
                "--out",
                str(out),
                "--quiet",
            ]
        )
    assert rc == 0
    data = json.loads((out / "sweep.json").read_text())
    assert data["model"] == "lumped3d"
    assert data["modal_energy_parts"] == ["mesh", "pinion_shaft", "gear_shaft", "bearings"]
    assert all(r == 0 for r in data["result"])
    assert len(data["natural_frequencies_Hz"]) == 6 * (3 + 3)  # 3 nodes per shaft
    assert len(data["bearing_names"]) == 10 and len(data["bearing_force_max_N"][0]) == 10
    assert max(data["bearing_force_static_N"]) > 0


def test_chunked_sweep_is_the_whole_sweep_with_progress(small_model):
    """Chunks (the last one padded) give the unchunked numbers, in both directions; progress
    counts the speeds done, S per direction; a chunk size below 1 is refused before any work."""
    speeds = np.array([300.0, 400.0, 500.0])
    kw = dict(integrator=Newmark(16), window=SteadyState(4, 2))
    whole = jd.speed_sweep(small_model, speeds, direction=jd.Both(), **kw)
    done = []
    chunked = jd.speed_sweep(
        small_model, speeds, direction=jd.Both(), batching=jd.Batching(2, done.append), **kw
    )
    assert done == [2, 3, 5, 6]
    for a, b in ((whole.results, chunked.results), (whole.down, chunked.down)):
        np.testing.assert_allclose(b.dynamic_factor, a.dynamic_factor, rtol=1e-12)
        np.testing.assert_allclose(b.transmission_error, a.transmission_error, rtol=1e-12)
    with pytest.raises(ValueError, match=r"chunk_size = 0 is out of range"):
        jd.speed_sweep(small_model, speeds, batching=jd.Batching(chunk_size=0), **kw)
