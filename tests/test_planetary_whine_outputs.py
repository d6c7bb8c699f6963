"""The planetary whine's outputs (for a planetary stage): each mesh's TE and
the central members' support reactions per order. At a low speed the orders are the Fourier
coefficients of the separate quasi-static contact solve (jaxgear.planetary.planetary_quasi_static at
the same mid-point travels), and the ring's support reaction is its meshes' forces by the ring's
statics written out here from Lin & Parker's mesh directions (not the support rows' code)."""

import json
import pathlib

import jax
import numpy as np
import pytest
from _planetary_stage import K0, SEQ, fourier_orders, geometry, stage

import jaxgear as jg
import jaxgear.io as jio
import jaxgear.planetary as jp
from jaxgear.cli import main
from jaxgear.dynamics import HarmonicBalance, whine_response

jax.config.update("jax_enable_x64", True)

P, H = 32, 4


def _model(sun_bearing=2e8, ring_bearing=3e9):
    geo = geometry(**SEQ)
    st = stage(geo, 3, sun_bearing=sun_bearing)
    st = jp.PlanetaryStage.equally_spaced(
        3, sun=st.sun, carrier=st.carrier, planet=st.planet,
        ring=jp.PlanetaryMember(st.ring.mass, st.ring.polar_inertia, st.ring.base_radius,
                                ring_bearing, st.ring.torsional_stiffness),
        sun_pressure_angle=st.sun_pressure_angle, ring_pressure_angle=st.ring_pressure_angle,
        sun_mesh_stiffness=st.sun_mesh_stiffness, ring_mesh_stiffness=st.ring_mesh_stiffness)
    meshes = jp.ContactMeshes.from_geometry(geo, st.planet_angles, jg.Uniform(K0))
    run = jp.PlanetaryRun(1000.0, tangential_pin_errors=np.array([4e-6, 0.0, 0.0]))
    return jp.PlanetaryModel(jp.PlanarPlanetary(), st, meshes, run)


@pytest.mark.slow  # about 13 s of CPU (two contact solves compiled: the balance's, the reference's)
def test_low_speed_orders_are_the_quasi_static_fourier_coefficients():
    """At a mesh frequency 7e-7 of the excited mode's (12 kHz): every mesh's TE and force, orders 0-4, equal
    the quasi-static solve's coefficients to 1e-6 of order 0 (the damping force ∝ speed:
    measured 1e-4 at 1e-4 of it); the
    ring's support force (carrier-frame x, y) and torque are Σ_n F_rn (sin ψ_rn, −cos ψ_rn)
    and −r_br Σ_n F_rn (the ring's statics, ψ_rn = ψ_n + α_r), the carrier's and the ring's
    torques add to the sun torque in order 0 and cancel in the others."""
    model = _model()
    speed = 1e-3  # rad/s on the carrier: a mesh frequency 7e-7 of the excited mode's
    w = whine_response(model, speed, HarmonicBalance(H), positions=P)
    st, run = model.stage, model.run
    qs = jp.planetary_quasi_static(model.kind, st, model.meshes, run.sun_torque,
                                   model.meshes.positions(P, 1), run.tangential_pin_errors)
    assert not np.any(np.asarray(w.contact_loss))
    te = fourier_orders(np.concatenate([qs.sun_te, qs.ring_te], axis=1), 5)
    fm = fourier_orders(np.concatenate([qs.sun_mesh_forces, qs.ring_mesh_forces], axis=1), 5)
    got_te, got_f = np.asarray(w.transmission_error[0, :5]), np.asarray(w.mesh_force[0, :5])
    np.testing.assert_allclose(got_te, te, atol=1e-6 * np.abs(te[0]).max())
    np.testing.assert_allclose(got_f, fm, atol=1e-6 * np.abs(fm[0]).max())
    assert np.abs(te[1:]).max() > 1e-3 * np.abs(te[0]).max()  # the orders are there
    # the ring's statics (Lin & Parker's ring-mesh direction on x_r, y_r, u_r)
    psi_r = np.asarray(st.planet_angles) + float(st.ring_pressure_angle)
    f_r = np.asarray(qs.ring_mesh_forces)
    ring_xy = np.stack([f_r @ np.sin(psi_r), -(f_r @ np.cos(psi_r))], axis=1)
    ring_torque = -float(st.ring.base_radius) * f_r.sum(axis=1)
    names = list(w.bearing_names)
    assert names == ["carrier x", "carrier y", "ring x", "ring y", "sun x", "sun y"]
    ref = fourier_orders(ring_xy, 5)
    got = np.asarray(w.bearing_force[0, :5, 2:4])
    np.testing.assert_allclose(got, ref, atol=1e-6 * np.abs(ref).max())
    assert np.abs(ref[1:]).max() > 1e-3 * np.abs(ref).max()
    moments = list(w.moment_names)
    assert moments == ["carrier torque", "ring torque"]  # the sun is free to turn
    tr = fourier_orders(ring_torque[:, None], 5)[:, 0]
    np.testing.assert_allclose(np.asarray(w.support_moment[0, :5, 1]), tr,
                               atol=1e-6 * abs(tr[0]))
    total = np.asarray(w.support_moment[0, :5].sum(axis=-1))
    np.testing.assert_allclose(total.real[0], float(run.sun_torque), rtol=1e-6)
    np.testing.assert_allclose(np.abs(total[1:]), 0.0, atol=1e-6 * float(run.sun_torque))


def test_fixed_frame_lines_are_the_turned_signal_s_spectrum():
    """What a support fixed in space receives: carrier-frame orders (random, H = 4, two members)
    rebuilt over one carrier turn with the mesh frequency 53 times the carrier's (the ring
    held), turned by the carrier angle into the fixed frame and Fourier-analysed: line k of the
    carrier frequency is order h's at k = 53 h + 1 (h = -H..H), its amplitude and frequency
    those of PlanetaryWhine.fixed_frame_lines."""
    rng = np.random.default_rng(3)
    H, omega = 4, 0.7  # carrier speed (rad/s)
    F = rng.normal(size=(1, H + 1, 5)) + 1j * rng.normal(size=(1, H + 1, 5))
    F[:, 0] = F[:, 0].real  # the mean is real
    zeros = np.zeros((1, H + 1, 1))
    w = jp.PlanetaryWhine(
        speed=np.array([omega]), frequency=np.array([53 * omega / (2 * np.pi)]),
        orders=np.arange(H + 1.0), coordinates=zeros, sun_mesh_force=zeros,
        ring_mesh_force=zeros, static_force=np.array(1.0), min_mesh_force=np.ones((1, 1)),
        contact_loss=np.zeros((1, 1), bool), nonlinearity=np.zeros((1, 1)),
        transmission_error=zeros, bearing_force=F, support_moment=zeros,
        bearing_names=("carrier x", "carrier y", "ring x", "ring z", "ring y"),
        moment_names=("ring torque",), carrier_speed=np.array([omega]))
    members, freq, amp = w.fixed_frame_lines()
    assert members == ("carrier", "ring")
    n_t = 2048
    t = np.arange(n_t) / n_t * 2 * np.pi / omega
    xy = np.real(np.exp(1j * np.outer(t, np.arange(H + 1) * 53 * omega)) @ F[0])  # (t, 5)
    z = np.stack([xy[:, 0] + 1j * xy[:, 1], xy[:, 2] + 1j * xy[:, 4]], axis=1)
    Zh = np.fft.fft(np.exp(1j * omega * t)[:, None] * z, axis=0) / n_t  # fixed frame
    k = 53 * np.arange(-H, H + 1) + 1
    np.testing.assert_allclose(np.asarray(amp[0]), np.abs(Zh[k % n_t]), rtol=1e-9)
    np.testing.assert_allclose(np.asarray(freq[0]), np.abs(k) * omega / (2 * np.pi), rtol=1e-12)


def test_support_reactions_drop_a_floating_member():
    """A floating sun (no bearing) has no support row; every row is zero on the planets."""
    model = _model(sun_bearing=0.0)
    sup = jp.support_reactions(model.kind, model.stage)
    assert sup.force_names == ("carrier x", "carrier y", "ring x", "ring y")
    n_central = 9
    assert np.all(np.asarray(sup.forces)[:, n_central:] == 0.0)
    np.testing.assert_allclose(np.asarray(sup.forces)[2, 3], 3e9)  # k_r on x_r
    with pytest.raises(ValueError, match="model") as e:
        jp.support_reactions("planar", model.stage)
    assert "\n" not in str(e.value)


def _stage_case(tmp_path, whine: str) -> pathlib.Path:
    """examples/planetary-hunting.toml without its per-tooth deviations, with ``whine``."""
    text = (pathlib.Path(__file__).parents[1] / "examples" / "planetary-hunting.toml").read_text()
    text = text[: text.index("\n[deviations]") + 1].replace('"planetary-hunting"', '"pw"')
    path = tmp_path / "pw.toml"
    path.write_text(text + whine)
    return path


def test_a_planetary_case_reads_its_whine_table(tmp_path):
    case = jio.load_case(str(_stage_case(tmp_path, "[whine]\nspeed_min_rad_s = 1.0\n"
                                         "speed_max_rad_s = 9.0\nspeeds = 3\n")))
    assert jio.whine_of(case).speeds == [1.0, 5.0, 9.0]
    example = jio.load_case(str(pathlib.Path(__file__).parents[1] / "examples"
                                / "planetary-whine.toml"))
    assert jio.whine_of(example).method.harmonics == 8
    with pytest.raises(ValueError, match="harmonics") as e:
        jio.load_case(str(_stage_case(tmp_path, "[whine]\nspeed_min_rad_s = 1.0\n"
                                      "speed_max_rad_s = 9.0\nharmonics = 0\n")))
    assert "\n" not in str(e.value)


@pytest.mark.slow  # about 110 s on the shared 2-core host (the stage's first-look sweep first)
def test_run_writes_a_planetary_stages_whine(tmp_path, capsys):
    """``jaxgear run`` on the three-planet stage of examples/planetary-hunting.toml with
    ``[whine]``: whine.json/csv, the order plots and waterfalls of the 6 meshes' TE and of the
    sun, carrier and ring support forces; at 0.01 rad/s (carrier) every mesh's TE orders 0-3
    are the Fourier coefficients of the quasi-static contact solve of the case's stage
    (jaxgear.planetary.planetary_quasi_static at the same 32 mid-point travels) to 1e-6; the
    resonant speeds (mesh frequency near the first modes) are flagged with contact loss, the
    low-speed one is not."""
    path = _stage_case(tmp_path, "[whine]\nspeed_min_rad_s = 0.01\nspeed_max_rad_s = 300.0\n"
                                 "speeds = 4\nharmonics = 4\npositions_per_period = 32\n")
    out = tmp_path / "o"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "whine (HarmonicBalance, H = 4, 4 speeds" in printed
    for name in ("whine.json", "whine.csv", "te_orders.png", "te_waterfall.png",
                 "bearing_orders.png", "bearing_waterfall.png",
                 "support_fixed_frame_waterfall.png"):
        assert (out / "whine" / name).stat().st_size > 0
    d = json.loads((out / "whine" / "whine.json").read_text())
    assert d["meshes"] == [f"{m}-planet{k}" for m in ("sun", "ring") for k in (1, 2, 3)]
    assert d["bearing_components"] == ["carrier x", "carrier y", "ring x", "ring y", "sun x",
                                       "sun y"]
    assert d["support_moment_components"] == ["carrier torque", "ring torque"]
    assert 0.01 not in d["linear_result_invalid_at_rad_s"]
    assert d["linear_result_invalid_at_rad_s"] and "carrier frame" in d["frame"]
    # the output says where the linear result does not hold
    assert "the linear (frequency-domain) result does not hold there" in d["validity"]
    assert "the linear result does not hold there" in printed
    ff = d["support_fixed_frame"]
    assert ff["members"] == ["carrier", "ring", "sun"] and len(ff["carrier_frame_order"]) == 9
    assert np.shape(ff["amplitude_N"]) == (4, 9, 3)
    # the headline says what it sums and gives the largest single mesh, read off whine.json
    te1 = np.array(d["transmission_error_m"]["amplitude"])[:, 1, :]
    one = json.loads((out / "summary.json").read_text())["whine"]
    assert one["te_order_1_is_root_sum_square_of_meshes"] == 6
    np.testing.assert_allclose(one["max_te_order_1_one_mesh_um"], te1.max() * 1e6, rtol=1e-12)
    np.testing.assert_allclose(one["max_te_order_1_um"],
                               np.sqrt((te1**2).sum(axis=1)).max() * 1e6, rtol=1e-12)
    k = int(np.argmax(te1.max(axis=0)))
    assert one["max_te_order_1_one_mesh"] == d["meshes"][k]
    assert f"root-sum-square of the 6 meshes, max {one['max_te_order_1_um']:.3g} µm" in printed
    assert f"one mesh max {one['max_te_order_1_one_mesh_um']:.3g} µm ({d['meshes'][k]}" in printed
    model, _ = jio.build_dynamic_model(jio.load_case(str(path)))
    run = model.run
    qs = jp.planetary_quasi_static(model.kind, model.stage, model.meshes, run.sun_torque,
                                   model.meshes.positions(32, 1), run.tangential_pin_errors,
                                   run.radial_pin_errors)
    ref = np.abs(fourier_orders(np.concatenate([qs.sun_te, qs.ring_te], axis=1), 4))
    got = np.array(d["transmission_error_m"]["amplitude"])[0, :4]
    np.testing.assert_allclose(got, ref, atol=1e-6 * ref.max())
    assert ref[1:].max() > 1e-2 * ref.max()


if __name__ == "__main__":
    pytest.main([__file__, "-q", "-n", "0"])
