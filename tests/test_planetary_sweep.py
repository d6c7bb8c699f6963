"""``jaxgear sweep`` on a planetary stage (jaxgear/cli/planetary_sweep.py): the sweep's dynamic
factors at each input speed are :func:`jaxgear.planetary.planetary_dynamics` called through the
Python API on a stage built here by hand (the pairs from :func:`jaxgear.planetary_geometry`, the
carrier speed and the mesh speed from Willis by hand), to 1e-12; the files are written into a
staging folder and moved in place (none left on a refused option); the command line end to end.

The stage: 19/17/−53, m_n 3 mm, b 30 mm, 3 planets, ring fixed, carrier in, sun out (the
sequentially phased stage of tests/_planetary_stage.py), a few mesh periods per speed. Fast:
the same definition on the lumped lin-parker-1999 (one spring per mesh, a sun eccentricity
exciting it), through ``sweep_summary`` (the sweep without its files).
"""

from __future__ import annotations

import json
import tomllib
import math

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import main, planetary_sweep as ps

M, B, ALPHA = 3e-3, 0.03, math.radians(20.0)
Z_S, Z_P, Z_R = 19, 17, 53
X_S, X_P = 0.3, 0.3
T_IN = 400.0  # N m on the carrier
W_IN = 30.0  # rad/s of the carrier
MEMBERS = {  # mass (kg), inertia (kg m^2), radial bearing (N/um); ring and carrier held
    "sun": (1.2, 1.2e-3, 100.0),
    "ring": (6.0, 0.12, 1000.0),
    "carrier": (5.0, 0.02, 1000.0),
}
PLANET = (0.8, 3e-4, 500.0, 500.0)
K_MESH = 400.0  # N/um, the lumped models' constant mesh stiffness

CASE = f"""
name = "small-stage"
[material]
youngs_modulus_GPa = 206.0
poisson_ratio = 0.3
[[gears]]
name = "sun"
teeth = {Z_S}
normal_module_mm = {M * 1e3}
normal_pressure_angle_deg = 20.0
profile_shift = {X_S}
face_width_mm = {B * 1e3}
[[gears]]
name = "planet"
teeth = {Z_P}
normal_module_mm = {M * 1e3}
normal_pressure_angle_deg = 20.0
profile_shift = {X_P}
face_width_mm = {B * 1e3}
[[gears]]
name = "ring"
teeth = {-Z_R}
normal_module_mm = {M * 1e3}
normal_pressure_angle_deg = 20.0
profile_shift = {-(X_S + 2 * X_P)}
face_width_mm = {B * 1e3}
[mesh]
stiffness = "uniform"
stiffness_per_length_N_per_mm_per_um = 14.0
[operating]
torque_Nm = {T_IN}
speed_rad_s = {W_IN}
[planetary]
sun_gear = "sun"
planet_gear = "planet"
ring_gear = "ring"
planets = 3
fixed = "ring"
input = "carrier"
sun_mesh_stiffness_N_per_um = {K_MESH}
ring_mesh_stiffness_N_per_um = {K_MESH}
tangential_pin_errors_um = [10.0, 0.0, 0.0]
""" + "".join(
    f"""[planetary.{name}]
mass_kg = {m}
inertia_kg_m2 = {i}
bearing_N_per_um = {k}
""" + ("torsional_stiffness_Nm_per_rad = 1e9\n" if name == "ring" else "")
    for name, (m, i, k) in MEMBERS.items()
) + f"""[planetary.planet]
mass_kg = {PLANET[0]}
inertia_kg_m2 = {PLANET[1]}
pin_radial_N_per_um = {PLANET[2]}
pin_tangential_N_per_um = {PLANET[3]}
"""

# the runs here check definitions on a few coarse steps and periods, on purpose: the sweep's
# warnings that they do not resolve the stage's top mode (tests/test_planetary_step_resolution.py)
# and that six periods at that step are not settled (tests/test_planetary_step_plan.py) are
# expected
pytestmark = [pytest.mark.filterwarnings("ignore:.*time step under-resolved"),
              pytest.mark.filterwarnings("ignore:.*not settled")]

SPEEDS = np.array([20.0, 45.0])  # rad/s of the carrier
RUN = {"steps_per_period": 24, "periods": 6, "keep_periods": 2}


@pytest.fixture(scope="module")
def case_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("case") / "small-stage.toml"
    path.write_text(CASE)
    return path


@pytest.fixture(scope="module")
def swept(case_path, tmp_path_factory):
    case = jio.load_case(str(case_path))
    out = tmp_path_factory.mktemp("sweep")
    return case, out, ps.planetary_sweep(case.form, case, SPEEDS, str(out), **RUN)


def _by_hand(case):
    """The same run through the Python API, the stage written here: ring and carrier held
    (1e3 x the mesh stiffness on u = r theta), the sun free in rotation, the sun's torque by
    Willis T_s = T_in z_s / (z_s + z_r), Omega = the carrier's speed, v = r_br Omega."""
    geo = jg.planetary_geometry(
        jg.Member(Z_S, profile_shift=X_S, face_width=B),
        jg.Member(Z_P, profile_shift=X_P, face_width=B),
        jg.Member(-Z_R, profile_shift=-(X_S + 2 * X_P), face_width=B),
        M,
        ALPHA,
    )
    r_s, r_p = geo.sun_planet.base_radii
    r_r = geo.planet_ring.base_radii[1]
    a = geo.center_distance
    hold = 1e3 * K_MESH * 1e6
    member = jp.PlanetaryMember
    stage = jp.PlanetaryStage.equally_spaced(
        3,
        sun=member(MEMBERS["sun"][0], MEMBERS["sun"][1], r_s, 100e6, 0.0),
        ring=member(MEMBERS["ring"][0], MEMBERS["ring"][1], r_r, 1000e6, hold * r_r**2),
        carrier=member(MEMBERS["carrier"][0], MEMBERS["carrier"][1], a, 1000e6, hold * a**2),
        planet=member(PLANET[0], PLANET[1], r_p, (PLANET[2] * 1e6, PLANET[3] * 1e6), 0.0),
        sun_pressure_angle=geo.sun_pressure_angle,
        ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=K_MESH * 1e6,
        ring_mesh_stiffness=K_MESH * 1e6,
    )
    # the case's cells: beyond the theoretical path ([mesh] extended_contact's default)
    meshes = jp.ContactMeshes.from_geometry(geo, stage.planet_angles, jg.Uniform(case.stiffness.k0),
                                            contact_geometry=jg.BeyondPath())
    run = jp.PlanetaryRun(T_IN * Z_S / (Z_S + Z_R), tangential_pin_errors=np.array([10e-6, 0, 0]),
                          **RUN)
    return stage, meshes, run, r_r


# the module's runs compile three Newmark loops on contact cells (the sweep, the ring
# transducer's turn, the run by hand): about 25 s of CPU, over the fast suite's 5 s; the fast
# twins: the lumped-form sweep at the end of this file (the DF-per-mesh definition against
# planetary_dynamics) and tests/test_planetary_case.py's refusal (the dispatch)
@pytest.mark.slow
def test_the_sweep_is_planetary_dynamics_at_each_speed(swept):
    case, _, s = swept
    stage, meshes, run, r_r = _by_hand(case)
    for i, w in enumerate(SPEEDS):
        d = jp.planetary_dynamics(jp.PlanarPlanetary(), stage, meshes, run, jnp.asarray(w),
                                  jnp.asarray(r_r * w))
        df_s, df_r = (np.asarray(x) for x in d.dynamic_factors)
        np.testing.assert_allclose(s["dynamic_factor_mesh"][i], np.concatenate([df_s, df_r]),
                                   rtol=1e-12)
        assert s["k_gamma"][i] == pytest.approx(float(d.k_gamma), rel=1e-12)
    # the mesh frequency in the carrier frame: z_r Omega / 2 pi with the ring fixed
    np.testing.assert_allclose(s["mesh_frequency_Hz"], Z_R * SPEEDS / (2 * math.pi), rtol=1e-12)
    assert s["max_dynamic_factor"] == pytest.approx(max(map(max, s["dynamic_factor_mesh"])))
    assert s["result"] == [0, 0]


@pytest.mark.slow
def test_the_files_and_keys(swept):
    _, out, s = swept
    assert {p.name for p in out.iterdir()} == set(ps.SWEEP_FILES)
    on_disk = json.loads((out / "sweep.json").read_text())
    assert on_disk["mesh_names"] == [f"sun-planet {k}" for k in (1, 2, 3)] + [
        f"ring-planet {k}" for k in (1, 2, 3)
    ]
    assert on_disk["dynamic_factor_mesh"] == s["dynamic_factor_mesh"]
    spec = on_disk["ring_spectrum"]
    # the sidebands are the multiples of N about the mesh order z_r
    assert spec["mesh_order"] == Z_R and all(o % 3 == 0 for o in spec["sideband_orders"])
    assert spec["speed_rad_s"] == s["speed_of_max_rad_s"]


@pytest.mark.slow
def test_jaxgear_sweep_end_to_end_and_refusals(case_path, tmp_path, capsys):
    out = tmp_path / "cli"
    argv = ["sweep", str(case_path), "--speeds", "20:45:2", "--steps-per-period", "24",
            "--periods", "6", "--keep-periods", "2", "--out", str(out), "--quiet"]
    assert main(argv) == 0
    printed = capsys.readouterr().out
    assert "small-stage: 2 input speeds, max dynamic factor" in printed
    assert set(ps.SWEEP_FILES) <= {p.name for p in out.iterdir()}
    assert json.loads((out / "sweep.json").read_text())["speeds_rad_s"] == [20.0, 45.0]
    for extra, words in (
        (["--vtu-speed", "30"], "--vtu-speed = 30.0: a PlanetaryModel has no condensed body"),
        (["--keep-periods", "9"], "--keep-periods 9: out of range, allowed <= --periods 6"),
    ):
        bad = tmp_path / "bad"
        assert main(argv[:-3] + extra + ["--out", str(bad), "--quiet"]) == 2
        err = capsys.readouterr().err.strip()
        assert words in err and "\n" not in err and not bad.exists()


# -- a fast twin: the lumped form (one spring per mesh), a turning sun eccentricity ----------

LP = {"sun": (0.4, 0.39, 38.7e-3, 100.0), "ring": (2.35, 3.0, 137.5e-3, 100.0),
      "carrier": (5.43, 6.29, 88.4e-3, 100.0), "planet": (0.66, 0.61, 50.15e-3, 100.0)}
LP_TEETH = (28, 92)
LP_TORQUE, LP_ECC, LP_PHASE = 2000.0, 20e-6, 30.0  # N m on the sun (input), m, deg
LP_SPEEDS = np.array([150.0, 900.0])  # rad/s of the sun
LP_RUN = {"steps_per_period": 12, "periods": 4, "keep_periods": 2}


def _lumped_by_hand():
    """Lin & Parker's Table 1 (the embedded lin-parker-1999), written here from the paper's
    values: ring and carrier held in rotation (1e3 x the 5e8 N/m mesh stiffness on u = r theta),
    the sun free in rotation, 20 um of sun eccentricity at 30 deg, a 10 um pin error."""
    member = jp.PlanetaryMember.lumped
    hold = 1e3 * 5e8
    m = {k: member(v[0], v[1], v[2], v[3] * 1e6, hold if k in ("ring", "carrier") else 0.0)
         for k, v in LP.items()}
    alpha = math.radians(24.6)
    stage = jp.PlanetaryStage.equally_spaced(
        3, **m, sun_pressure_angle=alpha, ring_pressure_angle=alpha, sun_mesh_stiffness=5e8,
        ring_mesh_stiffness=5e8,
        eccentricities=jp.Eccentricities(sun=LP_ECC, sun_phase=math.radians(LP_PHASE)))
    z_s, z_r = LP_TEETH
    meshes = jp.ConstantMeshes(2 * math.pi * LP["sun"][2] / z_s)
    run = jp.PlanetaryRun(LP_TORQUE, tangential_pin_errors=np.array([10e-6, 0.0, 0.0]),
                          radial_pin_errors=np.zeros(3), **LP_RUN)
    return stage, meshes, run


def test_the_lumped_sweep_is_planetary_dynamics_at_each_speed():
    """Two speeds, a few periods of the embedded lin-parker-1999 (ring fixed, sun in) with a
    sun eccentricity: each mesh's dynamic factor in the sweep's summary is the largest of that
    mesh's force over the kept steps over T_s / (N r_bs), computed here from
    planetary_dynamics on the stage built by hand at the carrier speed and the mesh speed of
    Willis written here; K_gamma likewise."""
    data = tomllib.loads(jio.embedded_case_text("lin-parker-1999"))
    data["operating"]["torque_Nm"] = LP_TORQUE
    data["planetary"].update(tangential_pin_errors_um=[10.0, 0.0, 0.0],
                             sun_eccentricity_um=LP_ECC * 1e6,
                             sun_eccentricity_phase_deg=LP_PHASE)
    case = jio.parse_train(data)
    s, _ = ps.sweep_summary(case.form, case, LP_SPEEDS, **LP_RUN)
    stage, meshes, run = _lumped_by_hand()
    z_s, z_r = LP_TEETH
    r_s = LP["sun"][2]
    nominal = LP_TORQUE / (3 * r_s)
    omega_c = LP_SPEEDS * z_s / (z_s + z_r)  # Willis, ring fixed
    v = r_s * (LP_SPEEDS - omega_c)  # the sun's speed relative to the carrier times r_bs
    # vmapped as a sweep runs it (the compiled run is shared; its inputs are built here)
    runs = jax.vmap(lambda om, vi: jp.planetary_dynamics(jp.PlanarPlanetary(), stage, meshes,
                                                         run, om, vi))(jnp.asarray(omega_c),
                                                                       jnp.asarray(v))
    for i, w in enumerate(LP_SPEEDS):
        d = jax.tree.map(lambda a, i=i: a[i], runs)
        f = np.concatenate([np.asarray(d.sun_mesh_forces), np.asarray(d.ring_mesh_forces)], 1)
        np.testing.assert_allclose(s["dynamic_factor_mesh"][i], f.max(0) / nominal, rtol=1e-9)
        f_s = f[:, :3]  # K_γ peak-based: each planet's peak over the mean of the peaks
        peaks, means = f_s.max(0), f_s.mean(0)
        assert s["k_gamma"][i] == pytest.approx(peaks.max() / peaks.mean(), rel=1e-9)
        assert s["k_gamma_mean_load"][i] == pytest.approx(means.max() / means.mean(), rel=1e-9)
        assert s["carrier_speeds_rad_s"][i] == pytest.approx(omega_c[i], rel=1e-12)
        assert s["mesh_frequency_Hz"][i] == pytest.approx(z_s * (w - omega_c[i]) / (2 * math.pi),
                                                          rel=1e-12)
    assert s["result"] == [0, 0]
    assert s["nominal_mesh_force_N"] == pytest.approx(nominal, rel=1e-12)
    # the eccentricity and the pin error load one mesh above the nominal force (the soft sun
    # bearing and pins of 1e8 N/m take most of it: DF 1.0053 and 1.0059)
    assert min(s["dynamic_factor"]) > 1.003
    assert s["max_dynamic_factor"] == pytest.approx(max(s["dynamic_factor"]))
