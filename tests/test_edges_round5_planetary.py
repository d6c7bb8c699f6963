"""Planetary inputs held to the pairs' standard (round 5 of the edges): geometry that
cannot exist (overlapping or coinciding planets, a ring inside its sun, a planet circle of a
millimetre), absurd values (stiffnesses, pressure angles, torques, denormals), messages that name
the right key and unit, and the sweep's memory/time bounds, each refused in one line before any
work, in both case forms (gear and lumped), through the command line and in the Python API; each
neighbour that can exist accepted.

The overlap criterion is written here on its own: planets n and m at ψ_n, ψ_m on the planet
circle of radius a have centres 2 a |sin((ψ_m − ψ_n)/2)| apart; they overlap where that is less
than twice their radius (the tip radius r_a = m_n (z/2 + h_a* + x) of a spur planet; the base
radius in the lumped form, which has no tip)."""

import importlib.resources
import math

import numpy as np
import pytest
from _planetary_stage import K0, MODULE, SEQ, geometry

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from fem_prep import schema as sc
from jaxgear.cli import main

LP, N1, N2 = "lin-parker-1999", "nrel-5mw-planetary", "nrel-5mw-stage2"
LP_ANGLES = "planet_angles_deg = [0.0, 120.0, 240.0]"
# Lin & Parker 1999, Table 1 (the embedded case): planet circle a, planet base radius r_bp (mm)
LP_A, LP_R_P, LP_R_S, LP_K_S = 88.4, 50.15, 38.7, 5e8


def _text(name: str, *subs) -> str:
    text = (importlib.resources.files("jaxgear") / "cases" / f"{name}.toml").read_text()
    for old, new in subs:
        assert old in text, old
        text = text.replace(old, new, 1)
    return text


def _load(tmp_path, name, *subs):
    path = tmp_path / "case.toml"
    path.write_text(_text(name, *subs))
    return jio.load_case(path)


def _refused(tmp_path, name, subs, needles, absent=()):
    with pytest.raises(sc.SchemaError) as info:
        _load(tmp_path, name, *subs)
    msg = str(info.value)
    assert "\n" not in msg
    for n in needles:
        assert n in msg, msg
    for n in absent:
        assert n not in msg, msg
    return msg


def _chord(a, deg):
    """The distance of two planet centres deg apart on the circle of radius a."""
    return 2 * a * abs(math.sin(math.radians(deg) / 2))


# --------------------------------------------------------------------------------------------
# case files: refused at load in one line naming the key, the value as written, the range


NREL1_TIP_MM = 45.0 * (17 / 2 + 0.7586 + 0.802)  # planet1: m_n (z/2 + h_a* + x)
NREL2_TIP_MM = 21.0 * (36 / 2 + 0.9167 + 0.504)  # planet2
NREL2_RING_BASE_M = 93 * 21e-3 * math.cos(math.radians(20.0)) / 2  # spur: z m cos α / 2

REFUSED = {
    # overlapping or coinciding planets, lumped form (base circles: 2 r_bp = 100.3 mm)
    "lp-planets-6": (LP, ((LP_ANGLES, "planets = 6"),), (
        "[planetary] planets = 6:", "overlap", f"{_chord(LP_A, 60):.6g} mm apart",
        f"{2 * LP_R_P:.6g} mm", "allowed planets <= 5")),
    "lp-coinciding": (LP, ((LP_ANGLES, "planet_angles_deg = [0, 0, 240]"),), (
        "[planetary] planet_angles_deg = [0, 0, 240]:", "planets 1 and 2", "0 mm apart")),
    "lp-3-deg-apart": (LP, ((LP_ANGLES, "planet_angles_deg = [0, 3, 120, 240]"),), (
        "[planetary] planet_angles_deg = [0, 3, 120, 240]:", "planets 1 and 2",
        f"{_chord(LP_A, 3):.6g} mm apart")),
    "lp-60-deg-apart": (LP, ((LP_ANGLES, "planet_angles_deg = [0, 60, 180, 240]"),), (
        "[planetary] planet_angles_deg", f"{_chord(LP_A, 60):.6g} mm apart")),
    # gear form: tip circles
    "nrel1-4.8-deg": (N1, (("planets = 3", "planet_angles_deg = [0, 4.8, 9.6]"),), (
        "[planetary] planet_angles_deg = [0, 4.8, 9.6]:", "tip",
        f"{_chord(863.0, 4.8):.6g} mm apart", f"{2 * NREL1_TIP_MM:.6g} mm")),
    "nrel2-37-planets": (N2, (("planets = 3", "planets = 37"),), (
        "[planetary] planets = 37:", "tip", f"{2 * NREL2_TIP_MM:.6g} mm",
        "allowed planets <= 4")),
    # the lumped form's radii
    "lp-ring-inside-sun": (LP, (("base_radius_mm = 137.5", "base_radius_mm = 30.0"),), (
        "[planetary.ring] base_radius_mm = 30: out of range, allowed >",)),
    "lp-planet-circle-1mm": (LP, (("base_radius_mm = 88.4", "base_radius_mm = 1.0"),), (
        "[planetary.carrier] base_radius_mm = 1: out of range, allowed (",)),
    "lp-planet-circle-200mm": (LP, (("base_radius_mm = 88.4", "base_radius_mm = 200.0"),), (
        "[planetary.carrier] base_radius_mm = 200: out of range, allowed (",)),
    "lp-ring-sun-plus-1": (LP, (("ring_teeth = 92", "ring_teeth = 29"),), (
        "[planetary] ring_teeth = 29: out of range, allowed [34, 10000]",)),
    "lp-ring-sun-plus-5": (LP, (("ring_teeth = 92", "ring_teeth = 33"),), (
        "[planetary] ring_teeth = 33: out of range, allowed [34, 10000]",)),
    # absurd values
    "lp-mesh-1e-300": (LP, (("sun_mesh_stiffness_N_per_um = 500.0",
                             "sun_mesh_stiffness_N_per_um = 1e-300"),), (
        "[planetary] sun_mesh_stiffness_N_per_um = 1e-300: out of range, allowed [0.001, 1e+06]",)),
    "lp-mesh-denormal": (LP, (("ring_mesh_stiffness_N_per_um = 500.0",
                               "ring_mesh_stiffness_N_per_um = 5e-324"),), (
        "[planetary] ring_mesh_stiffness_N_per_um = 4.94066e-324: out of range",)),
    "lp-ring-held-1e-300": (LP, (("torsional_stiffness_N_per_um = 1000.0",
                                  "torsional_stiffness_N_per_um = 1e-300"),), (
        ("[planetary.ring] torsional_stiffness_N_per_um = 1e-300: out of range, allowed "
         "[0.001, 1e+09]"),
    )),
    "nrel2-ring-held-1e-300": (N2, (("torsional_stiffness_Nm_per_rad = 1e12",
                                     "torsional_stiffness_Nm_per_rad = 1e-300"),), (
        ("[planetary.ring] torsional_stiffness_Nm_per_rad = 1e-300: out of range, allowed "
         f"[{1e3 * NREL2_RING_BASE_M ** 2:.6g}, 1e+20]"),)),
    "lp-pressure-angle-89.9": (LP, (("sun_pressure_angle_deg = 24.6",
                                     "sun_pressure_angle_deg = 89.9"),), (
        "[planetary] sun_pressure_angle_deg = 89.9: out of range, allowed [10, 50]",)),
    "lp-pressure-angle-denormal": (LP, (("ring_pressure_angle_deg = 24.6",
                                         "ring_pressure_angle_deg = 5e-324"),), (
        "[planetary] ring_pressure_angle_deg = 4.94066e-324: out of range",)),
    # the lumped form's torque floor: a sun-mesh deflection of 1e-7 µm, |T_s| / (N r_bs k_s)
    "lp-torque-1e-300": (LP, (("torque_Nm = 100.0", "torque_Nm = 1e-300"),), (
        ("[operating] torque_Nm = 1e-300: out of range, allowed "
         f"[{1e-13 * LP_K_S * 3 * LP_R_S * 1e-3:.3g}, 1e+12]"),)),
    "lp-torque-denormal": (LP, (("torque_Nm = 100.0", "torque_Nm = 5e-324"),), (
        "[operating] torque_Nm = 4.94066e-324: out of range",)),
    "lp-pin-denormal": (LP, (("pin_radial_N_per_um = 100.0", "pin_radial_N_per_um = 5e-324"),), (
        "[planetary.planet] pin_radial_N_per_um = 4.94066e-324: out of range, allowed [0.001",)),
    # the gear form's torque floor: the pairs' line load of 1e-6 N/mm on each sun mesh
    "nrel2-torque-1e-300": (N2, (("torque_Nm = 9.9965e5", "torque_Nm = 1e-300"),), (
        "[operating] torque_Nm = 1e-300: out of range, allowed [",)),
    # messages naming the right thing
    "nrel2-ring-15-teeth": (N2, (("teeth = -93", "teeth = -15"),), (
        "[gears.ring2] teeth = -15:", "sun", "allowed <= -19"), ("cutter",)),
    "nrel2-ring-20-teeth": (N2, (("teeth = -93", "teeth = -20"),), (
        "[gears.ring2] cutter_teeth = 30:", "20 teeth are too few"), ("[11, 10]",)),
    "nrel2-center-distance-1": (N2, (("# center_distance_mm:", "center_distance_mm = 1.0 #"),), (
        "[planetary] center_distance_mm = 1: out of range, allowed [584.003, 584.004]",)),
    "nrel2-center-distance-600": (N2, (("# center_distance_mm:",
                                        "center_distance_mm = 600.0 #"),), (
        "[planetary] center_distance_mm = 600: out of range, allowed [584.003, 584.004]",),
        ("contact ratio",)),
    "nrel2-center-distance-denormal": (N2, (("# center_distance_mm:",
                                             "center_distance_mm = 5e-324 #"),), (
        "[planetary] center_distance_mm = 4.94066e-324: out of range (subnormal",)),
}


@pytest.mark.parametrize(("name", "subs", "needles", "absent"),
                         [(*v, ()) if len(v) == 3 else v for v in REFUSED.values()],
                         ids=list(REFUSED))
def test_planetary_case_refused_at_load(tmp_path, name, subs, needles, absent):
    _refused(tmp_path, name, subs, needles, absent)


ACCEPTED = {
    # neighbours that can exist: each refused input's nearest valid one
    "lp-planets-5": (LP, ((LP_ANGLES, "planets = 5"),)),  # 2a sin 36° = 103.9 > 100.3 mm
    "lp-90-deg-apart": (LP, ((LP_ANGLES, "planet_angles_deg = [0, 90, 180, 270]"),)),
    "lp-planet-circle-60mm": (LP, (("base_radius_mm = 88.4", "base_radius_mm = 60.0"),)),
    "lp-ring-sun-plus-6": (LP, (("ring_teeth = 92", "ring_teeth = 34"),
                                (LP_ANGLES, "planets = 2"))),  # (28 + 34)/2 assembles
    "lp-mesh-0.001": (LP, (("sun_mesh_stiffness_N_per_um = 500.0",
                            "sun_mesh_stiffness_N_per_um = 0.001"),)),
    "lp-ring-held-0.001": (LP, (("torsional_stiffness_N_per_um = 1000.0",
                                 "torsional_stiffness_N_per_um = 0.001"),)),
    "lp-pressure-angle-50": (LP, (("sun_pressure_angle_deg = 24.6",
                                   "sun_pressure_angle_deg = 50.0"),)),
    "lp-torque-1e-5": (LP, (("torque_Nm = 100.0", "torque_Nm = 1e-5"),)),
    "nrel2-center-distance-584.003": (N2, (("# center_distance_mm:",
                                            "center_distance_mm = 584.003 #"),)),
}


@pytest.mark.parametrize(("name", "subs"), list(ACCEPTED.values()), ids=list(ACCEPTED))
def test_planetary_neighbours_accepted(tmp_path, name, subs):
    case = _load(tmp_path, name, *subs)
    assert isinstance(case.form, jio.PlanetaryForm)


@pytest.mark.parametrize("n", [3, 4, 5, 6])
def test_lumped_planet_count_by_the_overlap_criterion(tmp_path, n):
    """Lin & Parker's stage (z_s + z_r = 120 assembles 3 to 6 planets): refused exactly where
    the test's own criterion 2 a sin(π/N) < 2 r_bp says the base circles overlap."""
    overlap = _chord(LP_A, 360 / n) < 2 * LP_R_P
    if overlap:
        _refused(tmp_path, LP, ((LP_ANGLES, f"planets = {n}"),), ("overlap",))
    else:
        assert _load(tmp_path, LP, (LP_ANGLES, f"planets = {n}")).form.spec.n_planets == n


def test_embedded_planetary_cases_still_load():
    for name in (LP, N1, N2, "nrel-5mw-gearbox"):
        assert jio.load_case(name).name == name


# the gearbox's torque floor: stage 2's line load of 1e-6 N/mm on each of its 3 sun meshes
# (b 550 mm, r_bs = 18 × 21 cos 20° / 2 mm, its input the carrier: T_c = T_s (18 + 93)/18),
# carried through stage 1's speed-up 1 + 56/19 (its output torque the input's over it)
GEARBOX_FLOOR = (1e-6 * 1e3 * 0.55 * 3 * 18 * 21e-3 * math.cos(math.radians(20.0)) / 2
                 * (18 + 93) / 18 * (1 + 56 / 19))


@pytest.mark.parametrize(
    ("old", "new", "needles"),
    [
        ("torque_Nm = 3.946e6", "torque_Nm = 5e-324",
         ("[operating] torque_Nm = 4.94066e-324: out of range (subnormal",)),
        ("torque_Nm = 3.946e6", "torque_Nm = 1e-3",
         (f"[operating] torque_Nm = 0.001: out of range, allowed [{GEARBOX_FLOOR:.3g}",)),
        ("mesh_stiffness_N_per_um = 7668.0", "mesh_stiffness_N_per_um = 1e-300",
         ("[stages[2]] mesh_stiffness_N_per_um = 1e-300: out of range, allowed [0.001, 1e+06]",)),
    ],
    ids=["torque-denormal", "torque-1e-3", "mesh-1e-300"],
)
def test_gearbox_absurd_values(tmp_path, old, new, needles):
    _refused(tmp_path, "nrel-5mw-gearbox", ((old, new),), needles)


def test_gearbox_torque_above_its_floor(tmp_path):
    case = _load(tmp_path, "nrel-5mw-gearbox", ("torque_Nm = 3.946e6", "torque_Nm = 0.01"))
    assert case.torque == pytest.approx(0.01)


def test_gearbox_whose_stage_is_itself(tmp_path):
    """It read as 'not valid TOML: nested too deeply' (a RecursionError)."""
    path = tmp_path / "loop.toml"
    path.write_text(
        'name = "loop"\n[operating]\ntorque_Nm = 3.946e6\nspeed_rad_s = 1.2671\n'
        '[[stages]]\ncase = "nrel-5mw-stage2"\n[[stages]]\ncase = "loop.toml"\n'
        "shaft_Nm_per_rad = 1.26e9\n"
    )
    with pytest.raises(sc.SchemaError) as info:
        jio.load_case(path)
    msg = str(info.value)
    assert "contains itself" in msg and "loop.toml" in msg, msg
    assert "TOML" not in msg


# --------------------------------------------------------------------------------------------
# the command line: one line on stderr, exit 2, nothing written


@pytest.mark.parametrize(
    ("name", "subs", "key"),
    [
        (LP, ((LP_ANGLES, "planets = 6"),), "[planetary] planets = 6"),
        (LP, (("torque_Nm = 100.0", "torque_Nm = 1e-300"),), "[operating] torque_Nm"),
        (N2, (("planets = 3", "planets = 37"),), "[planetary] planets = 37"),
    ],
)
def test_run_refuses_before_writing(tmp_path, capsys, name, subs, key):
    path = tmp_path / "bad.toml"
    path.write_text(_text(name, *subs))
    out = tmp_path / "out"
    status = main(["run", str(path), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1 and key in err[0] and "allowed" in err[0], err
    assert not out.exists()


@pytest.mark.parametrize(
    ("extra", "option", "needle"),
    [
        # 1e6 periods at >= 64 steps: 6.4e7 steps per speed (a RESOURCE_EXHAUSTED traceback)
        (["--periods", "1000000", "--keep-periods", "2"], "--periods = 1000000",
         "allowed <= 65536"),
        # the first count over 2^22 / 64 = 65536 periods
        (["--periods", "65537"], "--periods = 65537", "allowed <= 65536"),
        # within that, but over 2^22 steps at the plan's own steps per period
        (["--periods", "65536"], "--periods = 65536", "time steps per speed"),
        # 1e6 steps per period over the settling periods (no answer in 100 s)
        (["--steps-per-period", "1000000"], "--steps-per-period = 1000000",
         "time steps per speed"),
    ],
    ids=["periods-1e6", "periods-65537", "periods-65536", "steps-1e6"],
)
def test_planetary_sweep_bounds(tmp_path, capsys, extra, option, needle):
    out = tmp_path / "out"
    status = main(["sweep", LP, "--speeds", "50:100:2", "--out", str(out), "--quiet", *extra])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert err[0].startswith(f"jaxgear: error: {option}:"), err[0]
    assert needle in err[0] and "4.19e+06" in err[0], err[0]
    assert not out.exists() or not any(p.is_file() for p in out.rglob("*"))


@pytest.mark.parametrize("command", ["robust", "optimise"])
@pytest.mark.parametrize(("case", "what"), [(LP, "planetary stages"),
                                            ("nrel-5mw-gearbox", "gearboxes")])
def test_pair_commands_refuse_stages(tmp_path, capsys, command, case, what):
    out = tmp_path / "out"
    status = main([command, case, "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1, err
    assert f"jaxgear {command} does not take {what} yet" in err[0], err[0]
    assert "0 meshes" not in err[0]
    assert not out.exists()


# --------------------------------------------------------------------------------------------
# the Python API: ValueError naming the argument


def _lp_fields():
    member = jp.PlanetaryMember.lumped
    return {
        "sun": member(0.4, 0.39, LP_R_S * 1e-3, 1e8, 0.0),
        "ring": member(2.35, 3.0, 137.5e-3, 1e8, 1e9),
        "carrier": member(5.43, 6.29, LP_A * 1e-3, 1e8, 1e9),
        "planet": member(0.66, 0.61, LP_R_P * 1e-3, 1e8, 0.0),
        "sun_pressure_angle": np.radians(24.6),
        "ring_pressure_angle": np.radians(24.6),
        "sun_mesh_stiffness": 5e8,
        "ring_mesh_stiffness": 5e8,
    }


@pytest.mark.parametrize(
    "angles", [[0.0, 0.0, 0.0], [0.0, 2 * np.pi, 1.0], [0.0, np.radians(3.0), 2.0, 4.0]]
)
def test_stage_refuses_overlapping_planets(angles):
    with pytest.raises(ValueError, match=r"^PlanetaryStage: planets \d and \d .* overlap"):
        jp.PlanetaryStage(planet_angles=angles, **_lp_fields())


@pytest.mark.parametrize("n", [3, 4, 5, 6, 7, 10**7])
def test_equally_spaced_planets_by_the_overlap_criterion(n):
    if _chord(LP_A, 360 / n) < 2 * LP_R_P:  # the test's own criterion (base circles)
        with pytest.raises(ValueError, match=r"n_planets = \d+ is out of range: allowed \[1, 5\]"):
            jp.PlanetaryStage.equally_spaced(n, **_lp_fields())
    else:
        assert jp.PlanetaryStage.equally_spaced(n, **_lp_fields()).n_planets == n


@pytest.mark.parametrize("n", [3, 4, 6])
def test_contact_meshes_refuse_overlapping_tip_circles(n):
    """The SEQ stage (19/17/-53, m_n 3 mm): 72 teeth assemble 3, 4 and 6 equally spaced planets;
    refused exactly where 2 a_w sin(π/N) < 2 r_a, r_a = m_n (z_p/2 + 1 + x_p)."""
    geo = geometry(**SEQ)
    r_a = MODULE * (SEQ["z_p"] / 2 + 1 + SEQ["x_p"])
    psi = 2 * np.pi * np.arange(n) / n
    if 2 * float(geo.center_distance) * math.sin(math.pi / n) < 2 * r_a:
        with pytest.raises(ValueError, match=r"^ContactMeshes: planets .* overlap.*tip radius"):
            jp.ContactMeshes.from_geometry(geo, psi, jg.Uniform(K0))
    else:
        assert jp.ContactMeshes.from_geometry(geo, psi, jg.Uniform(K0)) is not None


def test_contact_meshes_refuse_two_planets_at_one_angle():
    geo = geometry(**SEQ)
    with pytest.raises(ValueError, match=r"planets 1 and 2 .* 0 m apart"):
        jp.ContactMeshes.from_geometry(geo, [0.0, 0.0, 2 * np.pi / 3], jg.Uniform(K0))


def _stage():
    return jp.PlanetaryStage.equally_spaced(3, **_lp_fields())


@pytest.mark.parametrize(
    ("torque", "errors", "name"),
    [
        (np.nan, [0.0, 0.0, 0.0], "sun_torque"),
        (0.0, [1e-5, 0.0, 0.0], "sun_torque"),  # it returned K_γ = 4.99e14
        (-100.0, [0.0, 0.0, 0.0], "sun_torque"),
        (100.0, [np.inf, 0.0, 0.0], "tangential_pin_errors"),
        (np.inf, [0.0, 0.0, 0.0], "sun_torque"),
    ],
)
def test_load_sharing_refuses_bad_arguments(torque, errors, name):
    with pytest.raises(ValueError, match=rf"^load_sharing: {name}\S* = .* out of range") as info:
        jp.load_sharing(jp.PlanarPlanetary(), _stage(), torque, np.asarray(errors))
    assert "singular" not in str(info.value)


def test_load_sharing_small_pin_error_at_a_torque():
    """The neighbour: a positive torque with a pin error shares the load (K_γ a little over
    1: the displaced planet carries more or less, the mean stays the nominal share)."""
    r = jp.load_sharing(jp.PlanarPlanetary(), _stage(), 100.0, np.array([1e-6, 0.0, 0.0]))
    f = np.asarray(r.sun_mesh_forces)
    np.testing.assert_allclose(f.mean(), 100.0 / (3 * LP_R_S * 1e-3), rtol=1e-6)
    assert 1.0 < float(r.k_gamma) < 2.0


@pytest.mark.parametrize("speed", [np.nan, 1e300, -np.inf, 1e5 * (1 + 1e-9)])
def test_campbell_refuses_bad_carrier_speed(speed):
    with pytest.raises(ValueError, match=r"^campbell: carrier_speeds\[0\] = .* allowed "
                                         r"\[-100000, 100000\] rad/s"):
        jp.campbell(jp.PlanarPlanetary(), _stage(), np.array([speed]))


def test_campbell_refuses_bad_mesh_speed():
    with pytest.raises(ValueError, match=r"^campbell: mesh_speeds\[0\] = nan"):
        jp.campbell(jp.PlanarPlanetary(), _stage(), np.array([10.0]), np.array([np.nan]))


def test_campbell_at_a_speed_in_range_is_finite():
    f = np.asarray(jp.campbell(jp.PlanarPlanetary(), _stage(), np.array([0.0, 10.0])))
    assert np.all(np.isfinite(f))
    # at rest the carrier frame's frequencies are the stage's own
    np.testing.assert_allclose(
        f[0], np.asarray(jp.planetary_modes(jp.PlanarPlanetary(), _stage()).frequencies),
        rtol=1e-6, atol=1e-3)
