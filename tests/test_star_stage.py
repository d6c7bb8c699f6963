"""A star stage (the carrier held, the sun the input, the ring the output) is a planetary case
with ``fixed = "carrier"``: the embedded ``nrel-5mw-star`` (the NREL 5 MW stage-1 gears with the
carrier held) through the Python API and ``jaxgear run|sweep|modes``, against references
written here: Willis' kinematics with the carrier still (ω_r/ω_s = −z_s/z_r, the mesh frequency
z_s ω_s / 2π, the lossless torques), the torsional model of sun, ring, planets and held carrier
assembled from Lin & Parker's mesh deflections and solved by scipy.linalg.eigh, the quasi-static
contact solve at a very low speed, and the quasi-static solve's Fourier coefficients for the
whine's orders."""

import json

import jax
import numpy as np
import pytest
import scipy.linalg
from _planetary_stage import fourier_orders

import jaxgear.dynamics as jd
import jaxgear.io as jio
import jaxgear.planetary as jp

jax.config.update("jax_enable_x64", True)

CASE = "nrel-5mw-star"
Z_S, Z_R = 19, 56


@pytest.fixture(scope="module")
def case():
    return jio.load_case(CASE)


def test_the_star_stage_is_willis_with_the_carrier_still(case):
    """The case's kinematics and the dynamic model's: the carrier still, the ring turning
    backwards at z_s/z_r of the sun (ω_in/ω_out = −z_r/z_s), the mesh frequency z_s ω_s/2π
    (the carrier frame is the fixed frame), the mesh travel r_bs ω_s; the lossless torques sum
    to 0 and so does their power."""
    spec = case.form.spec
    w = spec.speeds(2.0)
    assert w["carrier"] == 0.0
    assert w["ring"] == pytest.approx(-2.0 * Z_S / Z_R, rel=1e-14)
    assert spec.ratio() == pytest.approx(-Z_R / Z_S, rel=1e-14)
    t = spec.torques(float(case.torque))
    assert t["sun"] + t["ring"] + t["carrier"] == pytest.approx(0.0, abs=1e-9 * t["sun"])
    assert t["sun"] * w["sun"] + t["ring"] * w["ring"] == pytest.approx(0.0, abs=1e-9 * t["sun"])
    model, _ = jio.build_dynamic_model(case)
    assert isinstance(model, jp.PlanetaryModel)
    assert float(model.carrier_per_input) == 0.0
    assert 1.0 / float(model.mesh_period_angle()) == pytest.approx(Z_S / (2 * np.pi), rel=1e-12)
    r_bs = float(model.stage.sun.base_radius)
    assert float(model.mesh_speed_per_input) == pytest.approx(r_bs, rel=1e-12)


def torsional_reference(stage, carrier_held: bool = True):
    """The torsional model of a stage written out here (Kahraman 1994; Lin & Parker 1999's
    deflections): coordinates u = r θ of (carrier, ring, sun, planets 1..N), the planets' mass
    on the carrier (their centres move with it), δ_sn = u_s + u_n − u_c cos α_s and
    δ_rn = u_r − u_n − u_c cos α_r, each member's torsional support k_t / r² on its u;
    ``carrier_held=False`` grounds the carrier (its coordinate removed). Natural frequencies
    (Hz, ascending), mass-normalised shapes (scipy.linalg.eigh) and the mass matrix."""
    n = int(stage.n_planets)
    members = (stage.carrier, stage.ring, stage.sun)
    r = [float(m.base_radius) for m in members]
    r_p = float(stage.planet.base_radius)
    m = np.diag([float(stage.carrier.polar_inertia) / r[0] ** 2 + n * float(stage.planet.mass),
                 float(stage.ring.polar_inertia) / r[1] ** 2,
                 float(stage.sun.polar_inertia) / r[2] ** 2]
                + [float(stage.planet.polar_inertia) / r_p**2] * n)
    k = np.diag([float(mb.torsional_stiffness) / rb**2 for mb, rb in zip(members, r)]
                + [0.0] * n)
    k_s = np.broadcast_to(np.asarray(stage.sun_mesh_stiffness, float), (n,))
    k_r = np.broadcast_to(np.asarray(stage.ring_mesh_stiffness, float), (n,))
    cos_s, cos_r = np.cos(float(stage.sun_pressure_angle)), np.cos(float(stage.ring_pressure_angle))
    for j in range(n):
        a = np.zeros(3 + n)
        a[[2, 3 + j, 0]] = 1.0, 1.0, -cos_s  # δ_sn
        b = np.zeros(3 + n)
        b[[1, 3 + j, 0]] = 1.0, -1.0, -cos_r  # δ_rn
        k += k_s[j] * np.outer(a, a) + k_r[j] * np.outer(b, b)
    if not carrier_held:
        m, k = m[1:, 1:], k[1:, 1:]
    lam, phi = scipy.linalg.eigh(k, m)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * np.pi), phi, m


def test_star_torsional_modes_against_a_lumped_model_written_here(case):
    """jaxgear.planetary.planetary_modes of the star stage's torsional model (``jaxgear modes``'
    table) equal the reference assembled here to 1e-9 (the rigid-body mode 0 Hz, the
    reference's below 1e-4 Hz); the rigid-body mode is Willis' star motion (the carrier
    still, the ring backwards at z_s/z_r of the sun: u_r = −u_s on equal base pitches); the
    carrier on its support (1e12 N m/rad, 30 times the meshes' stiffness on it) is nearly the
    grounded one: with the carrier removed every frequency rises (a constraint), by less than
    2 % (measured 1.5 % on the rotational modes, 0 on the planet modes)."""
    stage = case.form.spec.stage(case)
    got = jp.planetary_modes(jp.TorsionalPlanetary(), stage)
    f, phi, m = torsional_reference(stage)
    np.testing.assert_allclose(np.asarray(got.frequencies)[1:], f[1:], rtol=1e-9)
    assert float(got.frequencies[0]) == 0.0 and f[0] < 1e-4
    rigid = np.asarray(got.shapes)[:, 0]  # (u_c, u_r, u_s, u_1..u_N)
    r_r, r_s = float(stage.ring.base_radius), float(stage.sun.base_radius)
    theta_r, theta_s = rigid[1] / r_r, rigid[2] / r_s
    assert theta_r / theta_s == pytest.approx(-Z_S / Z_R, rel=1e-9)
    assert abs(rigid[0]) < 1e-9 * abs(rigid[2])
    grounded, _, _ = torsional_reference(stage, carrier_held=False)
    carrier_mode = np.argmax(m[0, 0] * phi[0] ** 2)  # the mode the carrier's energy is in
    held = np.delete(f, carrier_mode)[1:]
    assert np.all(grounded[1:] >= held * (1 - 1e-12))  # a constraint raises every frequency
    np.testing.assert_allclose(grounded[1:], held, rtol=2e-2)  # measured 1.5e-2


def test_a_held_carrier_s_whine_needs_its_mesh_speeds(case):
    """planetary_whine at a carrier speed of 0 takes the mesh speeds given (a star stage; the
    slow test below runs it); without them (the mesh speed then the ring's r_br |Ω|, which
    Ω = 0 would stop) it refuses in one line before any work."""
    model, _ = jio.build_dynamic_model(case)
    with pytest.raises(ValueError, match=r"^speeds = 0\.0: allowed finite values != 0 rad/s "
                       r"where mesh_speeds is None \(the ring held\)$"):
        jp.planetary_whine(model.kind, model.stage, model.meshes, model.run, 0.0)


@pytest.mark.slow  # about 40 s: the contact dynamics of the stage compiled
def test_star_dynamics_at_a_very_low_speed_is_the_quasi_static_solve(case):
    """jaxgear.dynamics.simulate on the star stage at 1e-3 rad/s of the sun (a mesh period of
    330 s): every recorded mesh force is the quasi-static contact solve's at the same travels
    (jaxgear.planetary.planetary_quasi_static) within 1e-3 of the nominal force (measured
    7.3e-6), so the dynamic factor is the quasi-static one (1.00522 against 1.00521): 1 within
    1 % (the floating sun shares the load equally; what is left is the varying mesh
    stiffness's quasi-static force variation)."""
    model, _ = jio.build_dynamic_model(case)
    r = jd.simulate(model, 1e-3, integrator=jd.Newmark(48), window=jd.SteadyState(3, 1))
    assert isinstance(r, jp.PlanetaryDynamics) and int(r.result) == 0
    static = jp.planetary_quasi_static(model.kind, model.stage, model.meshes,
                                       model.run.sun_torque, r.travel)
    got = np.concatenate([r.sun_mesh_forces, r.ring_mesh_forces], axis=1)
    want = np.concatenate([static.sun_mesh_forces, static.ring_mesh_forces], axis=1)
    fs = float(model.static_force)
    assert np.max(np.abs(got - want)) < 1e-3 * fs
    qs_factor = np.max(want[:, :3]) / fs
    dynamic_factor = np.max(np.asarray(r.dynamic_factors[0]))
    assert dynamic_factor == pytest.approx(qs_factor, rel=1e-3)
    assert 1.0 <= dynamic_factor < 1.01


@pytest.mark.slow  # about 50 s: the whine's contact solves and the reference's compiled
def test_star_whine_first_order_is_at_the_mesh_frequency(case):
    """jaxgear.dynamics.whine_response on the star stage (the carrier still: Ω = 0, which the
    whine took for a ring-held stage's error before): order 1 at z_s ω_s / 2π, and at a very
    low speed every mesh's TE orders 0-4 are the quasi-static solve's Fourier coefficients to
    1e-6 of order 0 (measured 1.6e-7), order 1 present (> 1e-3 of order 0; measured 0.33)."""
    model, _ = jio.build_dynamic_model(case)
    P, H = 32, 4
    speeds = np.array([1e-3, 5.0017])
    w = jd.whine_response(model, speeds, jd.HarmonicBalance(H), positions=P)
    np.testing.assert_allclose(np.asarray(w.frequency), Z_S * speeds / (2 * np.pi), rtol=1e-12)
    np.testing.assert_array_equal(np.asarray(w.carrier_speed), 0.0)
    qs = jp.planetary_quasi_static(model.kind, model.stage, model.meshes, model.run.sun_torque,
                                   model.meshes.positions(P, 1))
    te = fourier_orders(np.concatenate([qs.sun_te, qs.ring_te], axis=1), H + 1)
    got = np.asarray(w.transmission_error[0, : H + 1])
    np.testing.assert_allclose(got, te, atol=1e-6 * np.abs(te[0]).max())
    assert np.abs(te[1]).max() > 1e-3 * np.abs(te[0]).max()
    assert np.all(np.isfinite(np.asarray(w.transmission_error[1])))


@pytest.mark.slow  # about 4 min: the stage's run (dynamic sweep, whine), a sweep, the modes
def test_jaxgear_run_sweep_and_modes_on_the_star_case(tmp_path, case):
    """``jaxgear run``, ``jaxgear sweep`` and ``jaxgear modes`` on the embedded star case exit
    0 with their files: the run's summary the Willis ratio −z_r/z_s and the mesh frequency,
    its whine's first order at z_s ω_s/2π; the sweep's carrier speeds 0; the modes' table the
    torsional reference's."""
    from jaxgear.cli import main

    out = tmp_path / "run"
    assert main(["run", CASE, "--out", str(out), "--quiet"]) == 0
    for name in ("modes.json", "sweep/sweep.json", "whine/whine.json", "campbell.png"):
        assert (out / name).stat().st_size > 0
    stage = json.loads((out / "summary.json").read_text())["planetary"]
    assert (stage["fixed"], stage["input"], stage["output"]) == ("carrier", "sun", "ring")
    assert stage["speed_ratio"] == pytest.approx(-Z_R / Z_S, rel=1e-12)
    speed = float(case.speed)
    assert stage["mesh_frequency_carrier_frame_Hz"] == pytest.approx(Z_S * speed / (2 * np.pi),
                                                                     rel=1e-12)
    whine = json.loads((out / "whine" / "whine.json").read_text())
    np.testing.assert_allclose(whine["fundamental_Hz"],
                               Z_S * np.asarray(whine["speeds_rad_s"]) / (2 * np.pi), rtol=1e-12)
    assert whine["orders"][1] == 1.0
    sweep_dir = tmp_path / "sweep"
    assert main(["sweep", CASE, "--speeds", "1:5:2", "--out", str(sweep_dir), "--quiet"]) == 0
    sweep = json.loads((sweep_dir / "sweep.json").read_text())
    assert sweep["carrier_speeds_rad_s"] == [0.0, 0.0]
    np.testing.assert_allclose(sweep["mesh_frequency_Hz"],
                               Z_S * np.asarray(sweep["speeds_rad_s"]) / (2 * np.pi), rtol=1e-12)
    assert sweep["result"] == [0, 0]
    modes_dir = tmp_path / "modes"
    assert main(["modes", CASE, "--out", str(modes_dir), "--quiet"]) == 0
    torsional = json.loads((modes_dir / "modes.json").read_text())["torsional"]
    f, _, _ = torsional_reference(case.form.spec.stage(case))
    np.testing.assert_allclose([m["frequency_Hz"] for m in torsional][1:], f[1:], rtol=1e-9)


def test_a_star_stage_before_another_gearbox_stage_is_refused_at_load(tmp_path):
    """A star stage's output turns against its input (ratio < 0); the gearbox file carries each
    stage's operating point in its drive direction, so a star followed by another stage is
    refused in one line naming the stage, not run with a negative line load."""
    path = tmp_path / "star-then-pair.toml"
    path.write_text(
        'name = "star-then-pair"\n[operating]\ntorque_Nm = 999653.0\nspeed_rad_s = 5.0017\n'
        '[[stages]]\ncase = "nrel-5mw-star"\n[[stages]]\ncase = "nrel-5mw-stage3"\n'
        'shaft_Nm_per_rad = 1.435e8\npinion_inertia_kg_m2 = 3.75\ngear_inertia_kg_m2 = 921.0\n'
        'mesh_stiffness_N_per_um = 7668.0\ninput = "gear"\n'
    )
    with pytest.raises(ValueError) as err:
        jio.load_case(path)
    msg = str(err.value)
    assert "\n" not in msg
    assert msg.startswith("[stages[0]] case = 'nrel-5mw-star'")
    assert "allowed only as the last stage" in msg
