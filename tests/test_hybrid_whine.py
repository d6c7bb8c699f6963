"""Gear whine of the hybrid model (condensed FE bodies) in the frequency domain
(jaxgear.dynamics.whine_response on a HybridModel; docs/whine.md, "Hybrid model"), on the small
test pair of tests/test_hybrid_dynamics.py (its 30-tooth webbed wheel condensed, 341
coordinates). References: the scene's own cell vectors one mesh period on (the cyclic shift),
the quasi-static solve at low speed, and the hybrid Newmark (the time domain it linearises)."""

from __future__ import annotations

import json
import pathlib

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.dynamics import (
    HarmonicBalance,
    ModalDamping,
    Newmark,
    SteadyState,
    TransmissionErrorSource,
    cyclic_shift,
    dynamic_model,
    simulate,
    whine_response,
)
from jaxgear.io import static_scene

DATA = pathlib.Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def setup(fem_prep_cache):
    case = jio.load_case(DATA / "hybrid-test-case.toml").replace(
        contact_geometry=jg.TheoreticalPath()
    )
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    return case, static_scene(case, bodies=(None, body))[0]


def _full_vectors(scene, theta):
    """Every cell's structure vector on all coordinates at pinion angle θ (c, n), and the mask
    (one compiled program for every angle: eagerly, the cells' operations compile one by one)."""
    V, mask = _cell_vectors(scene, jnp.asarray(theta, dtype=float))
    n = scene.structure.K.shape[0]
    return np.asarray(V).reshape(-1, n), np.asarray(mask).reshape(-1)


@eqx.filter_jit
def _cell_vectors(scene, theta):
    cells = scene.mesh.cells(theta)
    return scene.cell_vectors(cells), cells.mask


def test_the_cyclic_shift_moves_the_cells_by_one_tooth(setup):
    """The shift P of the test pair: orthogonal, it leaves the structure's K, M and bearing
    damping and the centrifugal and torque loads unchanged (to 1e-12 of their largest entry),
    and the cells one mesh period on are the cells now shifted: V(θ + T) = V(θ) Pᵀ (1e-12 of
    the largest entry, at three positions). The condensation kept 10 interface-fixed modes:
    the tenth is one of a nodal-diameter pair whose partner it cut, the one coordinate left out."""
    _, scene = setup
    sh = cyclic_shift(scene)
    keep, P = np.asarray(sh.keep), np.asarray(sh.P)
    n = scene.structure.K.shape[0]
    assert n - keep.size == 1
    np.testing.assert_allclose(P @ P.T, np.eye(keep.size), atol=1e-12)
    mats = (scene.structure.K, scene.structure.M, scene.bearing_damping())
    for A in (np.asarray(a)[np.ix_(keep, keep)] for a in mats):
        assert np.abs(P @ A @ P.T - A).max() <= 1e-12 * max(np.abs(A).max(), 1e-300)
    for f in (scene.structure.f_centrifugal, scene.f_torque):
        f = np.asarray(f)[keep]
        assert np.abs(P @ f - f).max() <= 1e-12 * np.abs(f).max()
    T = float(scene.base_planes[0].mesh_period_angle)
    for theta in (0.01, 0.4 * T, 0.9 * T):
        V0, m0 = _full_vectors(scene, theta)
        V1, m1 = _full_vectors(scene, theta + T)
        assert np.array_equal(m0, m1)
        assert np.abs(V0[:, np.setdiff1d(np.arange(n), keep)]).max() == 0.0
        err = np.abs(V1[:, keep] - V0[:, keep] @ P.T).max()
        assert err <= 1e-12 * np.abs(V0).max()
    # the twist: P = U e^{2πiν} Uᴴ with ν = n/30, the nodal-diameter classes of the wheel
    U, nu = np.asarray(sh.U), np.asarray(sh.nu)
    np.testing.assert_allclose((U * np.exp(2j * np.pi * nu)) @ U.conj().T, P, atol=1e-10)
    assert np.all(np.abs(nu * 30 - np.round(nu * 30)) < 1e-9)


def test_at_low_speed_the_orders_are_the_quasi_static_te(setup):
    """At 2 rad/s (mesh frequency 6.4 Hz, far below the structure's modes) the TE's orders
    0-3 are the Fourier coefficients of the quasi-static TE at the same 32 positions (the
    static solve, its own reference each), to 1e-4 of the mean TE; the mesh force's mean is
    the static force and its orders vanish next to it (1e-4 F_s: the pair's torque balance)."""
    case, scene = setup
    model = dynamic_model(scene, case.modifications, case.torque, ModalDamping(0.05))
    w = whine_response(model, 2.0, HarmonicBalance(4), positions=32)
    T = float(scene.base_planes[0].mesh_period_angle)
    theta = (np.arange(32) + 0.5) * T / 32
    qs = jg.quasi_static(scene, case.modifications, case.torque, jnp.asarray(theta), speed=2.0)
    te = np.asarray(qs.transmission_error)
    k = np.arange(4)
    ref = np.exp(-2j * np.pi * k[:, None] * (np.arange(32) + 0.5)[None] / 32) @ te / 32
    ref[1:] *= 2
    got = np.asarray(w.transmission_error)[0, :4, 0]
    assert np.abs(got - ref).max() < 1e-4 * abs(ref[0])
    fm = np.asarray(w.mesh_force)[0, :, 0]
    fs = float(w.static_force[0])
    assert abs(fm[0] / fs - 1) < 1e-4 and np.abs(fm[1:]).max() < 1e-4 * fs
    assert not bool(w.contact_loss.any())


def _orders(t, q, omega, count=4):
    """One-sided orders 0..count-1 of the records q (K, ...) at times t (K,) over whole
    periods of 2π/ω."""
    E = np.exp(-1j * omega * np.outer(np.arange(count), t))
    c = E @ q.reshape(len(t), -1) / len(t)
    c[1:] *= 2
    return c


def _against_newmark(case, scene, tol, order3):
    """The harmonic balance (H = 32 on 256 positions) and the mean-stiffness model against the
    hybrid Newmark (256 steps per mesh period, 30 periods, 4 kept) at 600 rad/s, modal damping
    5 %: TE, mesh force and the largest bearing force component, orders 1-2 within ``tol``
    (relative) and 0.5°, order 3 within ``order3``."""
    model = dynamic_model(scene, case.modifications, case.torque, ModalDamping(0.05))
    speed = 600.0
    w = whine_response(model, speed, HarmonicBalance(32), positions=256)
    ts = whine_response(model, speed, TransmissionErrorSource(32), positions=256)
    r = simulate(model, speed, integrator=Newmark(256), window=SteadyState(30, 4))
    t = np.asarray(r.time)
    om = 2 * np.pi * float(w.frequency[0])
    assert not bool(w.contact_loss.any())
    bearing = _orders(t, np.asarray(r.bearing_force), om)
    i = int(np.argmax(np.abs(bearing[1])))
    for name, ref, got, src in (
        ("TE", r.transmission_error, w.transmission_error[0, :, 0], ts.transmission_error[0, :, 0]),
        ("mesh force", r.mesh_force, w.mesh_force[0, :, 0], ts.mesh_force[0, :, 0]),
        ("bearing", None, w.bearing_force[0, :, i], ts.bearing_force[0, :, i]),
    ):
        ref = bearing[:, i] if ref is None else _orders(t, np.asarray(ref), om)[:, 0]
        got = np.asarray(got)[:4]
        amp = np.abs(got) / np.abs(ref) - 1
        phase = np.degrees(np.angle(got / ref))
        src = np.asarray(src)[:4]
        print(name, "amplitude", amp[1:], "phase (deg)", phase[1:])
        print(
            "  TE source",
            np.abs(src[1:]) / np.abs(ref[1:]) - 1,
            np.angle(src[1:] / ref[1:], deg=True),
        )
        assert np.all(np.abs(amp[1:3]) < tol), (name, amp)
        assert np.all(np.abs(phase[1:3]) < 0.5), (name, phase)
        assert abs(amp[3]) < order3, (name, amp)
    return w


@pytest.mark.slow
def test_against_the_hybrid_newmark(setup):
    """(Slow: about 6 min.) On the theoretical path: orders 1-2 of the TE, the mesh force and
    the largest bearing force component within 0.5 % and 0.5° of the hybrid Newmark (measured
    within 0.05 % and 0.07° of the 256-step run, 0.02 % and 0.02° of 1024 steps; the Newmark's
    own 256-to-1024 change is below 0.03 % on orders 1-2), order 3 within 0.5 % (0.16 %).
    Before the harmonics beyond H were completed (docs/whine.md, "Hybrid model") order 2 was
    −1.5 % here, falling only as 1/H. The mean-stiffness model is reported beside it."""
    case, scene = setup
    w = _against_newmark(case, scene, 5e-3, 5e-3)
    assert float(w.nonlinearity.max()) < 5e-3


@pytest.mark.slow
def test_jaxgear_run_on_a_hybrid_case_with_whine(tmp_path, fem_prep_cache):
    """(Slow: about 3 min.) `jaxgear run` on the hybrid test pair with a `[whine]` table
    writes the whine outputs of a lumped case: whine.json/csv with the TE, mesh force and
    bearing force orders at each speed, and the four figures."""
    from jaxgear.cli import main

    text = (DATA / "hybrid-test-case.toml").read_text()
    text = text.replace('"hybrid-test-wheel.toml"', repr(str(DATA / "hybrid-test-wheel.toml")))
    text += (
        "\n[whine]\nspeed_min_rad_s = 300.0\nspeed_max_rad_s = 600.0\nspeeds = 2\n"
        "harmonics = 4\npositions_per_period = 32\n"
    )
    path = tmp_path / "hybrid-whine.toml"
    path.write_text(text)
    out = tmp_path / "run"
    assert main(["run", str(path), "--out", str(out), "--quiet"]) == 0
    w = json.loads((out / "whine" / "whine.json").read_text())
    assert w["speeds_rad_s"] == [300.0, 600.0] and w["harmonics"] == 4
    te = np.asarray(w["transmission_error_m"]["amplitude"])
    assert te.shape == (2, 5, 1) and np.all(te[:, 1] > 0)
    assert len(w["bearing_components"]) == np.asarray(w["bearing_force_N"]["amplitude"]).shape[2]
    for name in ("te_orders", "bearing_orders", "te_waterfall", "bearing_waterfall"):
        assert (out / "whine" / f"{name}.png").stat().st_size > 1000


def test_a_hybrid_train_with_whine_is_a_one_line_error(tmp_path):
    """``[whine]`` in a train case with a condensed idler: the hybrid frequency domain takes a
    pair; one line naming ``[whine]`` when the case is loaded."""
    text = (DATA / "hybrid-test-train.toml").read_text()
    text = text.replace('"hybrid-test-wheel.toml"', repr(str(DATA / "hybrid-test-wheel.toml")))
    path = tmp_path / "train-whine.toml"
    path.write_text(text + "\n[whine]\nspeed_min_rad_s = 100.0\nspeed_max_rad_s = 200.0\n")
    with pytest.raises(ValueError, match=r"^\[whine\].*condensed bodies of a train") as err:
        jio.load_case(path)
    assert "\n" not in str(err.value)


def test_hybrid_whine_refuses_what_it_does_not_cover(setup):
    """The turning frames' terms and a method that is not a whine method: one line each,
    naming the argument."""
    case, scene = setup
    model = dynamic_model(scene, case.modifications, case.torque, rotating_frame=True)
    with pytest.raises(ValueError, match="rotating_frame") as err:
        whine_response(model, 100.0, HarmonicBalance(2), positions=16)
    assert "\n" not in str(err.value)
    model = dynamic_model(scene, case.modifications, case.torque)
    with pytest.raises(TypeError, match="method"):
        whine_response(model, 100.0, "harmonic-balance", positions=16)
    with pytest.raises(ValueError, match="positions"):
        whine_response(model, 100.0, HarmonicBalance(8), positions=16)


@pytest.mark.slow
def test_a_housed_hybrid_pair_on_a_stiff_box_tends_to_the_grounded_pair(setup):
    """(Slow: about 2 min.) The pinion's shaft in the two seats of a box housing 1000 × stiffer
    than steel, the condensed wheel's shaft on the ground: the cyclic shift is the identity on
    the housing's coordinates, and the whine at 300 rad/s (H = 8 on 64 positions) is the
    grounded pair's: TE and mesh force orders 1-2 within 1e-4 and 0.01° (measured 1.5e-5,
    4e-4°), order 3 within 2e-3 (3.9e-4)."""
    from fem_prep.housing import Bore, Foot, HousingBox, Tet4, mesh_box, prepare_housing
    from jaxgear.scenes import Housing, hybrid_pair

    case = jio.load_case(DATA / "hybrid-test-case.toml")  # corner cells on, as measured
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    a, t, width, height = case.pair.center_distance, 0.008, 0.16, 0.12
    length = 0.08 + t  # the end walls' mid-planes at the pinion's bearings (±40 mm)
    off = np.array([-(width / 2 - a / 2), -height / 2, -length / 2])
    bores = tuple(Bore(w, (-off[0], height / 2), 0.014) for w in ("x-", "x+"))
    f = 0.025
    feet = tuple(
        Foot((x0, x0 + f), (y0, y0 + f)) for x0 in (0.0, length - f) for y0 in (0.0, width - f)
    )
    box = HousingBox(length, width, height, t, bores=bores, feet=feet)
    ph = prepare_housing(
        mesh_box(box, 0.03, element=Tet4()), fem_prep.Material(210e12, 0.3, 7800.0), 5000.0
    )
    rot = np.array([[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]])
    housing = Housing.of(ph.condensed_housing(), rotation=rot, offset=off)

    def scene(seats):
        s = case.scene
        return hybrid_pair(
            case.pair,
            case.mesh_model(flexible=(False, True)),
            s.pinion_shaft,
            s.gear_shaft,
            bodies=(None, body),
            masses=(0.3, 1.0),
            inertias=((1e-4, 2e-4), (1e-3, 1e-3)),
            housing=None if seats is None else housing,
            seats=seats,
        )

    out = []
    for seats in (None, [0, 1, None, None]):
        model = dynamic_model(scene(seats), case.modifications, case.torque, ModalDamping(0.05))
        out.append(whine_response(model, 300.0, HarmonicBalance(8), positions=64))
    for name in ("transmission_error", "mesh_force"):
        g, h = (np.asarray(getattr(w, name))[0, 1:4, 0] for w in out)
        rel, phase = np.abs(h / g - 1), np.degrees(np.abs(np.angle(h / g)))
        assert np.all(rel[:2] < 1e-4) and rel[2] < 2e-3 and np.all(phase < 0.01), (name, rel)
