"""Figures and properties stated in README.md, the user guide (docs/guide/pair.md and
modifications.md, the README's former long sections) and docs/dynamics.md that no other test
asserts.

Each test quotes the sentence it checks; the tolerance is the one the sentence states (a figure
given as "35 µm" is checked to ±0.5 µm). Where a claim needs a long computation, a smaller but
faithful setting is used and said. Timing figures (the benchmark tables) are measured by
``jaxgear bench …``, not tested.
"""

import csv
import math
import pathlib
import re
import shlex
import subprocess
import sys

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
import optimise as op
from jaxgear.cli import (
    GEARBOX_FILES,
    OUTPUT_FILES,
    PLANETARY_FILES,
    TRAIN_FILES,
    result_summary,
    run_case,
)
from jaxgear.dynamics import Newmark, SteadyState, dynamic_model, speed_sweep
from jaxgear.io import build_dynamic_model, quasi_static_scene
from jaxgear.scenes import TorsionalDynamics, disc_inertia

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_readme_python_api_example_runs():
    """README "Python API": the code block runs as written and its gradient is finite."""
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    section = text[text.index("## Python API") :]
    code = re.search(r"```python\n(.*?)```", section, re.DOTALL).group(1)
    ns = {}
    exec(compile(code, "README.md", "exec"), ns)  # noqa: S102
    assert float(ns["res"].te_rms) > 0
    assert math.isfinite(float(ns["jax"].grad(ns["te_rms"])(15e-6)))


def test_run_case_summary_holds_versions_files_and_two_periods(tmp_path):
    """docs/reference/outputs.md "Every case": "`summary.json` … the Harris map;
    versions", "`te.csv` | TE(θ) over two mesh periods", "`harris_map.png` | TE peak-to-peak
    against torque (0.1–2 × the case torque)". Tiny discretisation (2 slices × 8 positions):
    the claims are about the files, not the figures."""
    case = jio.load_case("accessory-spur").replace(slices=2, positions_per_pitch=8)
    summary = run_case(case, str(tmp_path), harris_points=3, show_progress=False)
    for name in OUTPUT_FILES["run"]:
        # sweep/ and optimise/ come only with a [scene] / [optimise], rating.md with a
        # [rating] (and the root-stress maps), spectrum.csv with a [rating.spectrum],
        # tribology.* with a [lubricant], loaded_path.png with [mesh] extended_contact; TRAIN_FILES with a train, PLANETARY_FILES with a
        # [planetary] stage, GEARBOX_FILES with a gearbox
        skip = TRAIN_FILES + PLANETARY_FILES + GEARBOX_FILES
        only_with = ("rating", "root_stress", "spectrum", "tribology", "loaded_path")
        if "/" not in name and name not in skip and not name.startswith(only_with):
            assert (tmp_path / name).stat().st_size > 0, name
    for name in ("transmission_error.png", "mesh_stiffness.png", "load_map.png", "harris_map.png"):
        data = (tmp_path / name).read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 5000, name
    # docs/getting-started.md "Reading the outputs": its table names every file written here
    page = (ROOT / "docs" / "getting-started.md").read_text(encoding="utf-8")
    table = set(re.findall(r"^\|[^|]*\|", page, re.M))
    named = {n for row in table for n in re.findall(r"`([^`]+)`", row)}
    written = {f.name for f in tmp_path.iterdir() if f.is_file() and not f.name.startswith(".")}
    assert written and written <= named, written - named
    env = summary["environment"]
    assert env["jaxgear"] == jg.__version__ and env["jax"] and env["python"]
    for key in ("transverse_contact_ratio", "overlap_ratio", "base_pitch_m", "center_distance_m"):
        assert key in summary["geometry"]
    q = summary["quasi_static"]["exact"]
    res = jg.quasi_static(case.mesh_model(), None, case.torque)
    pressure = jg.contact_pressure(case.pair, res, case.youngs_modulus, case.poisson_ratio)
    assert set(q) == set(result_summary(res, None, pressure))
    assert {"max_contact_pressure_Pa", "contact_half_width_at_max_m"} <= set(q)
    ref = jg.quasi_static(case.mesh_model(), case.modifications, case.torque, positions_per_pitch=8)
    assert q["te_rms_m"] == pytest.approx(float(ref.te_rms), rel=1e-9)
    # the case's tip relief (near the optimum, E = 15 µm, Γ = 0.25) more than halves the TE
    # fluctuation (examples/quickstart.py, the slow tier's test_quickstart_example_runs)
    assert float(ref.te_rms) < 0.5 * float(res.te_rms)
    # the contact pressure: the summary's maximum is the largest value of its column in
    # mesh_stiffness.csv (one field, two outputs), a Hertzian value for steel
    assert 5e8 < q["max_contact_pressure_Pa"] < 2e9 and q["contact_half_width_at_max_m"] > 0
    with open(tmp_path / "mesh_stiffness.csv", newline="") as f:
        table = list(csv.DictReader(f))
    column = [float(r["max_contact_pressure_exact_modified_Pa"]) for r in table]
    assert max(column) == pytest.approx(q["max_contact_pressure_Pa"], rel=1e-9)
    t = summary["harris_map"]["torque_Nm"]
    assert t[0] == pytest.approx(0.1 * case.torque) and t[-1] == pytest.approx(2 * case.torque)
    with open(tmp_path / "te.csv", newline="") as f:
        rows = list(csv.reader(f))
    assert len(rows) - 1 == 2 * 8  # two mesh periods of 8 positions
    theta = np.array([float(r[0]) for r in rows[1:]])
    period = 2 * math.pi / case.pair.pinion.teeth
    assert theta[-1] - theta[0] == pytest.approx(2 * period * (15 / 16), rel=1e-12)


# default tier: tests/test_cli_scene_curves.py::test_run_writes_the_scene_te_and_stiffness_beside_the_rigid_mesh (jaxgear run's quasi_static_scene on the default case: the scene's mean TE above the rigid mesh's by > 10 um, at 2 slices)
@pytest.mark.slow
def test_lumped3d_mean_te_35um_against_12um_rigid():
    """docs/guide/pair.md: "a `lumped3d` scene also gets `quasi_static_scene` (…): 35 µm mean TE
    for the default case against 12 µm for rigid bodies"; docs/dynamics.md: "the static TE mean is
    ≈ 35 µm (rigid mesh: 12 µm …), the RMS unchanged"; docs/getting-started.md: "the shafts and
    bearings add their deflection along the line of action (mean TE about 35 µm against 12 µm
    for the rigid mesh)". Measured 35.33 and 12.17 µm (jaxgear run's 40 slices and 64
    positions: 35.20 and 12.05 µm); RMS equal to 1e-12.
    8 slices as `jaxgear run` uses (spur without crowning: the slices do not change the TE)."""
    case = jio.load_case("accessory-spur")
    r3, forces = quasi_static_scene(case, slices=8)
    rigid = jg.quasi_static(case.mesh_model(slices=8), case.modifications, case.torque)
    assert float(r3.te_mean) == pytest.approx(35e-6, abs=0.5e-6)
    assert float(rigid.te_mean) == pytest.approx(12e-6, abs=0.5e-6)
    assert float(r3.te_rms) == pytest.approx(float(rigid.te_rms), rel=1e-6)
    assert forces and all(math.isfinite(v) for v in forces.values())


@pytest.mark.parametrize("name", ["accessory-spur", "power-helical"])
def test_active_set_passes(name):
    """docs/guide/pair.md "Contact law": "Newton's method on a piecewise-linear equation started
    with every cell in contact: finite passes (1–5 per position for the embedded cases at their
    torque, at most 6 at a tenth of it)", the case files' default cells beyond the path's ends
    included (their forces along the corner's normal with the tip owner's lever arm). Measured:
    1–3 (accessory-spur, both loads), 3–4 (power-helical unmodified), 3–5 with its relief and
    crowning; 5–6 at 0.1 × torque with them (1–3 and 4–5 on the theoretical path)."""
    case = jio.load_case(name)
    mesh = case.mesh_model()
    for mods in (None, case.modifications):
        it = np.asarray(jg.quasi_static(mesh, mods, case.torque).iterations)
        assert it.min() >= 1 and it.max() <= 5, (mods, np.unique(it))
        it = np.asarray(jg.quasi_static(mesh, mods, 0.1 * case.torque).iterations)
        assert it.max() <= 6, (mods, np.unique(it))


def test_quasi_static_failure_raises_or_returns_a_code():
    """docs/guide/pair.md "Contact law": "Failures (loop not converged, …) raise
    `eqx.EquinoxRuntimeError` or, with `throw=False`, come back as a result code per
    position"; and "Positions are the mid-points of P steps per mesh period"."""
    case = jio.load_case("accessory-spur")
    mesh = case.mesh_model(slices=4)
    kw = {"positions_per_pitch": 16, "contact": jg.ExactContact(1)}
    res = jg.quasi_static(mesh, case.modifications, case.torque, throw=False, **kw)
    codes = np.asarray(res.result)
    assert np.any(codes != 0) and np.any(codes == 0)  # the relief positions need a second pass
    with pytest.raises(eqx.EquinoxRuntimeError):
        jg.quasi_static(mesh, case.modifications, case.torque, **kw)
    step = 2 * math.pi / case.pair.pinion.teeth / 16
    np.testing.assert_allclose(np.asarray(res.theta), (np.arange(16) + 0.5) * step, rtol=1e-12)


@pytest.fixture(scope="module")
def accessory_problem():
    # theoretical path: the landscape the docs quote is the thesis's (its Master Curve)
    case = jio.load_case("accessory-spur").replace(slices=4, contact_geometry=jg.TheoreticalPath())
    return jio.case_problem(
        case, "tip_relief.depth,tip_relief.extent", "te_rms", positions_per_pitch=64, relief_blend=0
    )


def test_objective_normalisation_and_default_bounds(accessory_problem):
    """docs/guide/modifications.md "Objectives": "Each is divided by its unmodified value at the
    design torque, so 1 = no improvement"; "Default bounds: E* ∈ [0, 3], Γ ∈ [0.02, 0.98]"."""
    p = accessory_problem
    assert float(p.value(jnp.array([0.0, 0.3]), jg.ExactContact())) == pytest.approx(1.0, rel=1e-9)
    np.testing.assert_array_equal(np.asarray(p.lower), [0.0, 0.02])
    np.testing.assert_array_equal(np.asarray(p.upper), [3.0, 0.98])


# default tier: tests/test_optimise.py::test_optimiser_reaches_the_grid_optimum_from_three_starts (op.contour_map's TE RMS grid on the small case, its minimum the optimiser's)
@pytest.mark.slow
def test_te_rms_landscape_has_two_valleys(accessory_problem):
    """docs/guide/modifications.md: "The TE RMS landscape of the accessory pair has two valleys:
    the Master Curve (short relief, Γ ≈ 0.26, E ≈ 11.5 µm, …) and a long-relief branch
    (Γ ≈ 0.74, E ≈ 33 µm), both at about 9 % of the unmodified TE RMS". Exact contact, sharp relief
    starts, 64 positions, 4 slices (spur, no lead modification: the slices do not change the
    TE), grid step 0.01 in Γ and 0.5 µm in E. Measured: (0.26, 11.5 µm, 0.092) and (0.74,
    33 µm, 0.092); the best depth at Γ = 0.5 between them gives 0.42."""
    p = accessory_problem
    dm = float(p.delta_m)
    G = np.round(np.arange(0.15, 0.851, 0.01), 2)
    E = np.arange(0.0, 40.01e-6, 0.5e-6)
    grid = op.contour_map(p, G, E / dm, jg.ExactContact())
    valleys = []
    for m in (G < 0.5, G > 0.5):
        sub = grid[m]
        i, j = np.unravel_index(np.argmin(sub), sub.shape)
        valleys.append((G[m][i], E[j], sub[i, j]))
    (g1, e1, v1), (g2, e2, v2) = valleys
    assert g1 == pytest.approx(0.26, abs=0.015) and 11e-6 <= e1 <= 12e-6
    assert g2 == pytest.approx(0.74, abs=0.015) and e2 == pytest.approx(33e-6, abs=1.5e-6)
    assert 0.08 < v1 < 0.1 and 0.08 < v2 < 0.1
    ridge = grid[np.argmin(np.abs(G - 0.5))].min()
    assert ridge > 4 * max(v1, v2)  # two separate valleys, not one


# default tier: tests/test_dynamics.py::test_disc_inertia_and_torsional_frequency (the accessory pair's torsional mode and main critical speed against the analytic two-inertia frequency)
@pytest.mark.slow
def test_torsional_mode_and_critical_speeds_of_the_accessory_pair():
    """docs/dynamics.md: "The torsional mode of the accessory pair (disc inertias, Weber stiffness,
    k̄ = 2.72e8 N/m) is at 6201 Hz, so the main tooth critical speed is 866 rad/s (H2: 433, H3:
    289 rad/s)". Measured 2.7172e8 N/m, 6200.9 Hz, 865.8 / 432.9 / 288.6 rad/s (32 positions;
    exact rack-generated fillet in the Weber model)."""
    c = jio.load_case("accessory-spur")
    p = c.pair
    scene = TorsionalDynamics(
        c.mesh_model(slices=4),
        disc_inertia(c.density, p.tip_radii[0], p.pinion.face_width),
        disc_inertia(c.density, p.tip_radii[1], p.gear.face_width),
    )
    m = dynamic_model(scene, c.modifications, c.torque, positions_per_pitch=32)
    assert float(m.mesh_stiffness_mean) == pytest.approx(2.72e8, abs=0.005e8)
    assert float(m.modes.frequency[1]) == pytest.approx(6201, abs=1.0)
    for h, ref in ((1, 866), (2, 433), (3, 289)):
        assert float(m.critical_speeds(h)[1]) == pytest.approx(ref, abs=0.5)


# default tier: tests/test_regression.py::test_same_numbers_as_recorded[sweep-accessory-spur] (the lumped 3D pair's modes and speed sweep against its record) and tests/test_dynamics.py::test_main_critical_speed_linear_case (the peak at the mode's critical speed)
@pytest.mark.slow
def test_lumped3d_example_peak_and_mode():
    """docs/dynamics.md: "`jaxgear sweep examples/accessory-lumped3d.toml --speeds 200:2000:40`
    (…) puts the main peak (dynamic factor 1.67; …) at 938 rad/s against 939 rad/s predicted by
    the mode at 6728 Hz holding 89 % of its strain energy in the mesh". The sweep here runs the
    peak speed of that grid and its two neighbours only (same model and integration settings).
    Measured: 6727.6 Hz, 88.8 %, 939.36 rad/s; DF 1.549, 1.668, 1.537 with contact beyond the
    path (the case files' default, its corner cells along the corner's normal; 1.548, 1.656,
    1.537 with them along the line of action; 1.575, 1.741, 1.537 on the theoretical path)."""
    case = jio.load_case(str(ROOT / "examples" / "accessory-lumped3d.toml"))
    model, spec = build_dynamic_model(case)
    f = np.asarray(model.modes.frequency)
    e = np.asarray(model.modes.mesh_energy)
    k = int(np.argmax(np.where(np.asarray(model.modes.rigid), -1.0, e)))
    assert f[k] == pytest.approx(6728, abs=1.0)
    assert e[k] == pytest.approx(0.89, abs=0.005)
    assert float(model.critical_speeds()[k]) == pytest.approx(939, abs=0.5)
    grid = np.linspace(200.0, 2000.0, 40)
    speeds = grid[15:18]  # 892, 938, 985 rad/s
    s = speed_sweep(
        model,
        jnp.asarray(speeds),
        integrator=Newmark(spec.steps_per_period),
        window=SteadyState(spec.periods, spec.keep_periods),
    )
    df = np.asarray(s.dynamic_factor)
    assert np.all(np.asarray(s.results.result) == 0)
    assert speeds[1] == pytest.approx(938, abs=0.5)
    assert df[1] == pytest.approx(1.668, abs=0.005) and df[1] > df[0] and df[1] > df[2]


def test_license_and_thesis_citation():
    """pyproject.toml's licence is MIT and LICENSE says so; the README cites the thesis in full
    and calls it "the thesis" (no "the seed"); its set-up commands stay at the top."""
    import tomllib

    meta = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))
    assert meta["project"]["license"] == "MIT"
    lic = (ROOT / "LICENSE").read_text(encoding="utf-8")
    assert lic.startswith("MIT License") and "jaxgear developers" in lic
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    assert text.startswith(
        "# jaxgear\n\n```bash\npip install -e . && jaxgear run\n"
        'pip install -e ".[test]" && python -m pytest -q -m "not slow" -n 2 --dist worksteal --durations=25\n```'
    )
    assert len(text.splitlines()) <= 120  # the README fits on two screens
    for target in re.findall(r"\]\((?!https?:)([^)#]+)", text):  # its links lead somewhere
        assert (ROOT / target).exists(), target
    flat = " ".join(text.split())
    assert (
        "B. Guilbert, *Hybrid modular models for the dynamic study of high-speed "
        "thin-rimmed/-webbed gears*, PhD thesis, INSA Lyon, 2017" in flat
    )
    assert "the seed" not in flat.lower() and "FEM_PREP_CACHE" in flat


def _readme_test_command() -> list[str]:
    """README: "CI runs exactly this, `.ci/run`": the README's test command is .ci/run's line;
    its pytest part, split as the shell does."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8").splitlines()
    command = readme[4]
    assert command.startswith('pip install -e ".[test]" && python -m pytest ')
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8").splitlines()
    assert command in ci
    pytest_part = shlex.split(command.split(" && ", 1)[1])
    assert pytest_part[:3] == ["python", "-m", "pytest"]
    return pytest_part


def test_readme_test_command_is_ci_and_its_hooks_print_the_count_first(request):
    """README: "CI runs exactly this, `.ci/run`" and "It prints `collected N tests` first": the
    README's test command is .ci/run's line, quiet (-q) and on xdist workers (-n); the suite's
    hooks (tests/conftest.py) print the count on a line of its own, once, in the process that
    reports (the run without xdist, or xdist's controller when a worker has collected), never
    in a worker. The command itself run on one test is the slow tier's."""
    args = _readme_test_command()[3:]
    assert "-q" in args and "-n" in args
    hooks = next(
        p
        for p in request.config.pluginmanager.get_plugins()
        if pathlib.Path(getattr(p, "__file__", "") or "") == ROOT / "tests" / "conftest.py"
    )

    class Reporter:
        def __init__(self):
            self.calls = []

        def ensure_newline(self):
            self.calls.append("newline")

        def write_line(self, line):
            self.calls.append(line)

    def config(worker: bool):
        reporter = Reporter()
        pm = type(
            "PM",
            (),
            {"get_plugin": lambda self, name: reporter if name == "terminalreporter" else None},
        )()
        cfg = type("Config", (), {"pluginmanager": pm})()
        if worker:
            cfg.workerinput = {"workerid": "gw0"}
        return cfg, reporter

    cfg, rep = config(worker=False)  # no xdist: at the end of collection, once
    session = type("Session", (), {"config": cfg, "items": [1, 2, 3]})()
    hooks.pytest_collection_finish(session)
    hooks.pytest_collection_finish(session)
    assert rep.calls == ["newline", "collected 3 tests"]
    cfg, rep = config(worker=True)  # a worker prints nothing
    hooks.pytest_collection_finish(type("Session", (), {"config": cfg, "items": [1]})())
    assert rep.calls == []
    cfg, rep = config(worker=False)  # xdist's controller: the first worker's count, once
    node = type("Node", (), {"config": cfg})()
    hooks.pytest_xdist_node_collection_finished(node, ["a", "b"])
    hooks.pytest_xdist_node_collection_finished(node, ["a", "b"])
    assert rep.calls == ["newline", "collected 2 tests"]


# default tier: tests/test_readme_claims.py::test_readme_test_command_is_ci_and_its_hooks_print_the_count_first (the same command line, the hooks that print the count)
@pytest.mark.slow
def test_readme_test_command_is_ci_and_prints_its_count_first(tmp_path):
    """README: "CI runs exactly this, `.ci/run`" and "It prints `collected N tests` first": the
    README's test command is .ci/run's line; run on one test (a subprocess, the command's own
    options: -q and two xdist workers), the count is printed before the first result."""
    pytest_part = _readme_test_command()
    node = "tests/test_structure_counts.py::test_counts_each_kind_of_place_and_leaves_out_checks"
    args = pytest_part[3:]
    done = subprocess.run(
        [sys.executable, "-m", "pytest", *args, "-p", "no:cacheprovider", "--basetemp",
         str(tmp_path / "base"), node],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )  # fmt: skip
    assert done.returncode == 0, done.stdout + done.stderr
    lines = done.stdout.splitlines()
    assert "collected 1 tests" in lines, done.stdout
    first_result = next(i for i, line in enumerate(lines) if line.startswith("."))
    assert lines.index("collected 1 tests") < first_result


def test_moved_claims_are_still_stated():
    """The sentences the tests above check (quoted in their docstrings) are still stated on the
    user-guide pages where the README's long sections moved: a page that changes a figure fails
    here and sends its author to the test that asserts it."""
    claims = {
        "reference/outputs.md": ("TE(θ) over two mesh periods",),
        "guide/pair.md": (
            "35 µm mean TE for the default case against 12 µm for rigid bodies",
            "1–5 per position for the embedded cases at their torque, at most 6 at a tenth of it",
            "come back as a result code per position",
        ),
        "guide/modifications.md": (
            "Each is divided by its unmodified value at the design torque, so 1 = no improvement",
            "Default bounds: E* ∈ [0, 3], Γ ∈ [0.02, 0.98]",
            "Γ ≈ 0.26, E ≈ 11.5 µm",
            "Γ ≈ 0.74, E ≈ 33 µm",
        ),
    }
    for page, stated in claims.items():
        flat = " ".join((ROOT / "docs" / page).read_text(encoding="utf-8").split())
        for claim in stated:
            assert claim in flat, (page, claim)


def test_readme_default_case_figures():
    """README: "the embedded default case (`accessory-spur`: the thesis's Tab. III-1 spur pair
    at 80 N·m)": 45/86 teeth (Tab. III-1), 80 N·m."""
    case = jio.load_case("accessory-spur")
    assert case.torque == 80.0
    assert (case.pair.pinion.teeth, case.pair.gear.teeth) == (45, 86)


def test_readme_jaxgear_run_defaults_to_the_default_case_and_folder(monkeypatch):
    """README: "The first command installs jaxgear and runs the main job on the embedded
    default case (`accessory-spur`, …) into `jaxgear-out/accessory-spur/`": ``jaxgear run``
    without arguments loads that case and takes that folder (stopped there, before any
    computation)."""
    import os

    import jaxgear.cli
    from jaxgear.cli import run as run_module

    flat = " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())
    assert "runs the main job on the embedded default case (`accessory-spur`" in flat
    assert "into `jaxgear-out/accessory-spur/`" in flat
    seen = []

    class Stop(Exception):
        pass

    def folder(case, command, path, *args, **kwargs):
        seen.append(path)
        raise Stop

    monkeypatch.setattr(run_module, "check_case_outputs", folder)
    with pytest.raises(Stop):
        jaxgear.cli.main(["run"])
    assert seen == [os.path.join("jaxgear-out", "accessory-spur")]


def test_readme_command_lines_parse_and_check(monkeypatch, tmp_path):
    """README "Command line": every ``jaxgear`` line of its block is a valid command line (the
    parser and the options' checks accept it, as ``jaxgear`` would before touching a case),
    and the speeds it gives read as stated ("200:3000:60": 60 speeds, 200 to 3000 rad/s)."""
    import jaxgear.cli
    from jaxgear.cli import range_values

    text = (ROOT / "README.md").read_text(encoding="utf-8")
    block = text.split("## Command line", 1)[1].split("```bash\n", 1)[1].split("```", 1)[0]
    lines = [ln.split("#", 1)[0].split() for ln in block.splitlines() if ln.strip()]
    assert len(lines) == 6 and all(ln[0] == "jaxgear" for ln in lines)
    monkeypatch.chdir(tmp_path)  # `jaxgear cases ... --write my-case.toml` writes here
    spec = tmp_path / "examples" / "sizing" / "helical.toml"  # `jaxgear size`'s, from the checkout
    spec.parent.mkdir(parents=True)
    spec.write_text((ROOT / "examples" / "sizing" / "helical.toml").read_text(encoding="utf-8"))

    class Checked(Exception):
        pass

    def stop(command):  # called once the options are checked, before the model or the case
        raise Checked(command)

    for words in lines:
        argv = words[1:]
        try:
            status = jaxgear.cli.main(argv, load_model=stop)
        except Checked as done:
            status = 0
            assert str(done) == argv[0]
        assert status == 0, argv  # a command that needs no model (cases) ran to the end
        if "--speeds" in argv:
            speeds = np.asarray(range_values(argv[argv.index("--speeds") + 1], "--speeds"))
            assert speeds.size == 60 and speeds[0] == 200.0 and speeds[-1] == 3000.0
