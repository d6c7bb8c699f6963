"""Gear whine of a train whose meshes run at several mesh frequencies: the quasi-periodic
harmonic balance (:class:`jaxgear.dynamics.QuasiPeriodicBalance`,
:func:`jaxgear.dynamics.quasi_periodic_balance`; docs/whine.md, "Trains of several mesh
frequencies").

References, each written apart from the code:

* a 1-DOF oscillator with two parametric stiffnesses at incommensurate frequencies,
  k(t) = k0 (1 + ε1 cos ω1 t + ε2 cos ω2 t), under a constant load: its regular perturbation
  solution in ε (orders ε for the lines ω1, ω2; ε1 ε2 for the combination tone ω1 + ω2), by hand;
* the time-domain Newmark with unilateral contact (:func:`jaxgear.dynamics.simulate`) on the
  embedded ``two-stage`` case's lumped scene where it keeps contact, its records Fourier
  analysed here at the exact frequencies over the window of the meshes' common period (127
  periods of the first mesh, 35 of the second: every line of the truncation a whole number of
  cycles).
"""

import math

import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear.io as jio
from jaxgear.dynamics import (
    HarmonicBalance,
    Newmark,
    QuasiPeriodicBalance,
    SteadyState,
    quasi_periodic_balance,
    simulate,
    whine_response,
)
from jaxgear.dynamics._whine_qp import mesh_groups
from jaxgear.io._case_model import mesh_frequency_periods

M1, K0, ZETA = 2.0, 8.0e6, 0.03
C1 = 2 * ZETA * math.sqrt(K0 * M1)
F0 = 1.0e3


def _set(H, S):
    """Multi-indices (h1, h2), |h_g| <= H with the other |h| <= S, lexicographic."""
    return np.array(
        [(a, b) for a in range(-H, H + 1) for b in range(-H, H + 1)
         if (abs(a) <= H and abs(b) <= S) or (abs(b) <= H and abs(a) <= S)]
    )


def _two_tone(eps1, eps2, w1, w2, H=4, S=2):
    hs = _set(H, S)
    N = len(hs)
    khat = {(0, 0): K0, (1, 0): K0 * eps1 / 2, (-1, 0): K0 * eps1 / 2,
            (0, 1): K0 * eps2 / 2, (0, -1): K0 * eps2 / 2}
    Kc = np.zeros((N, N, 1, 1), complex)
    for i in range(N):
        for j in range(N):
            Kc[i, j, 0, 0] = khat.get(tuple(hs[i] - hs[j]), 0.0)
    F = np.zeros((N, 1), complex)
    F[(N - 1) // 2, 0] = F0
    nu = hs @ np.array([w1, w2])
    m, c, z = (jnp.array([[v]]) for v in (M1, C1, 0.0))
    Y = quasi_periodic_balance(m, c, z, jnp.asarray(Kc), jnp.asarray(F), jnp.asarray(nu))
    return {tuple(h): complex(Y[i, 0]) for i, h in enumerate(hs)}


def test_two_parametric_stiffnesses_against_the_perturbation_solution():
    """ε1 = ε2 = 1e-3 at ω1 = 0.37 ω_n, ω2 = 0.37 √2 / 3 ω_n (incommensurate): the lines ω1, ω2
    equal −(ε/2) F0/D(ω) (D(ν) = k0 − m ν² + i c ν, first order in ε) and the combination tone
    ω1 + ω2 equals −(k0/2)(ε1 Y_(0,1) + ε2 Y_(1,0))/D(ω1 + ω2) (second order), each to
    O(ε) relative; the mean F0/k0 to O(ε²)."""
    wn = math.sqrt(K0 / M1)
    w1, w2 = 0.37 * wn, 0.37 * math.sqrt(2) / 3 * wn
    e1 = e2 = 1e-3
    Y = _two_tone(e1, e2, w1, w2)

    def D(v):
        return K0 - M1 * v**2 + 1j * C1 * v

    x0 = F0 / K0
    y10 = -(e1 / 2) * K0 * x0 / D(w1)
    y01 = -(e2 / 2) * K0 * x0 / D(w2)
    y11 = -(K0 / 2) * (e1 * y01 + e2 * y10) / D(w1 + w2)
    assert abs(Y[(0, 0)] / x0 - 1) < 1e-5
    for got, ref in ((Y[(1, 0)], y10), (Y[(0, 1)], y01), (Y[(1, 1)], y11)):
        assert abs(got / ref - 1) < 5e-3
    # conjugate symmetry of a real response
    assert abs(Y[(-1, -1)] - np.conj(Y[(1, 1)])) < 1e-12 * abs(Y[(1, 1)])


@pytest.fixture(scope="module")
def two_stage():
    """The embedded ``two-stage`` case, its dynamic model (2 slices) and that model's balance
    QuasiPeriodicBalance(2, 0) at 50 rad/s on one table of 35 positions: built once for the
    tests below (each build solves the case's quasi-static rows)."""
    case = jio.load_case("two-stage")
    model, _ = jio.build_dynamic_model(case, slices=2)
    one = whine_response(model, 50.0, QuasiPeriodicBalance(2, 0), positions=35)
    return case, model, one


def test_bad_inputs(two_stage):
    """One-line errors before any computation."""
    with pytest.raises(ValueError, match="sidebands"):
        QuasiPeriodicBalance(4, 5)
    with pytest.raises(ValueError, match="harmonics"):
        QuasiPeriodicBalance(0, 0)
    case, model, _ = two_stage
    # the groups a case file's [whine] is checked against at load, from its tooth counts: the
    # model's
    assert mesh_frequency_periods(case) == mesh_groups(model)[1]
    for positions, match in ((36, "positions = 36.*multiple of 35"),
                             (35, "positions = 35.*>= 4 harmonics \\+ 1 = 41"),
                             ((140,), "positions = \\(140,\\).*2 positive ints"),
                             ((140, 0), "positions = \\(140, 0\\).*2 positive ints"),
                             ((140, 36), "group 1's .*127/35.*multiple of 35"),
                             ((40, 35), "group 0's .*>= 4 harmonics \\+ 1 = 41")):
        with pytest.raises(ValueError, match=match) as e:
            whine_response(model, 50.0, QuasiPeriodicBalance(10, 0), positions=positions)
        assert "\n" not in str(e.value)


def test_a_failed_static_solve_on_the_torus_grid_is_an_error(two_stage):
    """The torque turned against the drive flanks (the flanks open: no contact anywhere on the
    grid): the balance raises, one line, instead of returning a response about a wrong
    operating point."""
    import equinox as eqx

    _, model, one = two_stage
    opened = eqx.tree_at(lambda m: m.torque, model, -model.torque)
    with pytest.raises(eqx.EquinoxRuntimeError, match="torus grid") as e:
        whine_response(opened, 50.0, QuasiPeriodicBalance(2, 0), positions=35)
    assert "\n" not in str(e.value)
    assert np.all(np.isfinite(np.asarray(one.mesh_force)))


def test_positions_per_group_join_the_groups_tables(two_stage):
    """``positions=(35, 35)`` (each group's table of its own, joined) gives the grid of
    ``positions=35`` (one table for every mesh): the same lines to 1e-12."""
    _, model, one = two_stage
    method = QuasiPeriodicBalance(2, 0)
    joined = whine_response(model, 50.0, method, positions=(35, 35))
    for name in ("coordinates", "transmission_error", "mesh_force", "bearing_force"):
        a, b = np.asarray(getattr(one, name)), np.asarray(getattr(joined, name))
        np.testing.assert_allclose(b, a, rtol=0, atol=1e-12 * np.max(np.abs(a)))


def _time_orders(t, x, freqs):
    """One-sided amplitudes at the angular frequencies ``freqs``: 2 ⟨x e^{−iνt}⟩ over a window
    of whole periods of every line (the rectangle rule on the uniform samples)."""
    t, x = np.asarray(t), np.asarray(x)
    return np.array([2 * np.mean(x * np.exp(-1j * f * t)) for f in freqs])


@pytest.mark.slow
def test_two_stage_against_newmark_mesh_by_mesh():
    """The embedded ``two-stage`` case's lumped 3D scene (4 slices), first mesh at 300 Hz
    (both meshes well below the first mode at 710 Hz), linear regime (no contact loss): each
    mesh's orders 1-2 of its own mesh frequency, in TE and mesh force, within 1 % in amplitude
    and 1° in phase of Newmark's (140 steps per first-mesh period, 3 spans of 127 periods, the
    last kept), QuasiPeriodicBalance(8, 1) on the same 140 positions (a grid of 140 × 508
    points), and on ``positions=(140, 35)``: the second mesh's axis at its own 127 rows (a
    grid of 140 × 127, a quarter of the static solves). The span-periodic HarmonicBalance(16)
    of the two-stage reaches only 16/127 of the first mesh's order 1."""
    case = jio.load_case("two-stage")
    model, _ = jio.build_dynamic_model(case, slices=4)
    speed = 2 * math.pi * 300.0 / 28
    r = simulate(model, speed, integrator=Newmark(140), window=SteadyState(3 * 127, 127))
    for positions in (140, (140, 35)):
        w = whine_response(model, speed, QuasiPeriodicBalance(8, 1), positions=positions)
        assert not np.any(np.asarray(w.contact_loss))
        w1 = 2 * math.pi * float(w.frequency[0])
        groups, orders = np.asarray(w.order_group), np.asarray(w.group_order)
        rel = np.asarray(w.orders)
        np.testing.assert_allclose(rel[groups == 1], np.arange(1, 9) * 35 / 127, rtol=1e-14)
        for k, mesh in enumerate(r.meshes):
            assert float(mesh.contact_loss) == 0.0
            g = w.mesh_group[k]
            pick = [int(np.flatnonzero((groups == g) & (orders == o))[0]) for o in (1, 2)]
            for fd, td in ((w.transmission_error, mesh.transmission_error),
                           (w.mesh_force, mesh.mesh_force)):
                ref = _time_orders(r.time, td, rel[pick] * w1)
                got = np.asarray(fd[0, pick, k])
                np.testing.assert_allclose(np.abs(got) / np.abs(ref), 1.0, atol=0.01)
                np.testing.assert_allclose(np.degrees(np.angle(got / ref)), 0.0, atol=1.0)
    span = whine_response(model, speed, HarmonicBalance(16), positions=140)
    assert float(np.max(np.asarray(span.orders))) < 0.2


@pytest.mark.slow
def test_two_stage_first_mesh_orders_3_to_5_converge_with_the_sampling():
    """The case's own 20 slices at 300 Hz (first mesh): the first mesh's orders 3-5 are set by
    how finely the mesh stiffness is sampled, not by the harmonics kept. The reference is
    Newmark at 560 steps per first-mesh period (its orders 3-5 move by 0.7 % from 280 steps, by
    3.2 % from 140: about second order, so within about 0.25 % of the limit). Measured:
    QuasiPeriodicBalance(8, 0) on 70 positions within 1.65 % and 1.21° of it on the first mesh's
    orders 3-5 (on 35 positions, the benchmark's, 6.5 % and 1.9°), within 0.3 % and 0.03° on the
    rest of both meshes' orders 1-5; H = 16 instead of 8 moves the first mesh's orders 3-5 by
    0.06 % at most (the second mesh's orders 11, 14, 15 and 18, which H = 8 leaves out, lie
    0.8-3.5 % from them in frequency but do not reach them), the second mesh's order 5 by
    0.2 %."""
    model, _ = jio.build_dynamic_model(jio.load_case("two-stage"))
    speed = 2 * math.pi * 300.0 / 28
    w8 = whine_response(model, speed, QuasiPeriodicBalance(8, 0), positions=70)
    w16 = whine_response(model, speed, QuasiPeriodicBalance(16, 0), positions=70)
    r = simulate(model, speed, integrator=Newmark(560), window=SteadyState(3 * 127, 127))
    w1 = 2 * math.pi * float(w8.frequency[0])

    def own(w, k):  # the output index of mesh k's orders 1-5 of its own frequency
        groups, orders = np.asarray(w.order_group), np.asarray(w.group_order)
        return [int(np.flatnonzero((groups == w.mesh_group[k]) & (orders == o))[0])
                for o in range(1, 6)]

    loose = np.array([False, False, True, True, True])  # the first mesh's orders 3-5
    for k, mesh in enumerate(r.meshes):
        pick = own(w8, k)
        for fd, td in (("transmission_error", mesh.transmission_error),
                       ("mesh_force", mesh.mesh_force)):
            ref = _time_orders(r.time, td, np.asarray(w8.orders)[pick] * w1)
            got = np.asarray(getattr(w8, fd))[0, pick, k]
            amp, deg = np.abs(got / ref) - 1, np.degrees(np.angle(got / ref))
            np.testing.assert_array_less(np.abs(amp), np.where(loose & (k == 0), 0.02, 0.004))
            np.testing.assert_array_less(np.abs(deg), np.where(loose & (k == 0), 1.5, 0.1))
            if k == 0:  # H = 16: the first mesh's orders 3-5 as at H = 8
                more = np.asarray(getattr(w16, fd))[0, own(w16, 0), 0]
                np.testing.assert_allclose(more[2:], got[2:], rtol=1e-3)


@pytest.mark.slow
def test_two_stage_each_groups_axis_converges_on_its_own():
    """The case's own 20 slices at 300 Hz, QuasiPeriodicBalance(8, 0), each mesh-frequency
    group's axis of the torus grid refined on its own (``positions`` one per group, steps per
    first-mesh period): doubling the second mesh's axis (127 → 254 rows, the first's at 140)
    moves the second mesh's orders 1-3 by 0.07 % and 0.006° at most (asserted 0.15 %, 0.02°)
    and the first mesh's by 0.007 % (asserted 0.02 %); doubling the first mesh's (70 → 140,
    the second's at 254) leaves the second mesh's lines as they were (< 1e-5, asserted 1e-4).
    Against Newmark at 560 steps per first-mesh period (its orders 1-5 within about 0.4 % of
    the limit), ``positions=(140, 35)`` (140 × 127 = 17 780 static solves, as many as 70
    positions) gives every order 1-5 of both meshes within 0.97 % and 0.38° (the first mesh's
    3-5; asserted 1.2 %, 0.5°) and 0.53 %, 0.09° (the rest; asserted 0.7 %, 0.15°): the
    accuracy of 140 positions for all (140 × 508 = 71 120 solves) on a quarter of the grid."""
    model, _ = jio.build_dynamic_model(jio.load_case("two-stage"))
    speed = 2 * math.pi * 300.0 / 28
    method = QuasiPeriodicBalance(8, 0)
    runs = {p: whine_response(model, speed, method, positions=p)
            for p in ((140, 35), (140, 70), (70, 70))}
    r = simulate(model, speed, integrator=Newmark(560), window=SteadyState(3 * 127, 127))
    w = runs[(140, 35)]
    w1 = 2 * math.pi * float(w.frequency[0])

    def lines(w, k, fd, orders):
        groups, order = np.asarray(w.order_group), np.asarray(w.group_order)
        pick = [int(np.flatnonzero((groups == w.mesh_group[k]) & (order == o))[0])
                for o in orders]
        return np.asarray(getattr(w, fd))[0, pick, k], np.asarray(w.orders)[pick]

    def change(a, b):
        q = b / a
        return np.max(np.abs(np.abs(q) - 1)), np.max(np.abs(np.degrees(np.angle(q))))

    for fd in ("transmission_error", "mesh_force"):
        second = change(lines(runs[(140, 35)], 1, fd, (1, 2, 3))[0],
                        lines(runs[(140, 70)], 1, fd, (1, 2, 3))[0])
        assert second[0] < 1.5e-3 and second[1] < 0.02, second
        first = change(lines(runs[(140, 35)], 0, fd, (1, 2, 3))[0],
                       lines(runs[(140, 70)], 0, fd, (1, 2, 3))[0])
        assert first[0] < 2e-4, first
        still = change(lines(runs[(70, 70)], 1, fd, range(1, 6))[0],
                       lines(runs[(140, 70)], 1, fd, range(1, 6))[0])
        assert still[0] < 1e-4 and still[1] < 1e-2, still
    loose = np.array([False, False, True, True, True])
    for k, mesh in enumerate(r.meshes):
        for fd, td in (("transmission_error", mesh.transmission_error),
                       ("mesh_force", mesh.mesh_force)):
            got, rel = lines(w, k, fd, range(1, 6))
            ref = _time_orders(r.time, td, rel * w1)
            amp, deg = np.abs(got / ref) - 1, np.degrees(np.angle(got / ref))
            np.testing.assert_array_less(np.abs(amp), np.where(loose & (k == 0), 0.012, 0.007))
            np.testing.assert_array_less(np.abs(deg), np.where(loose & (k == 0), 0.5, 0.15))


def test_whine_table_quasi_periodic():
    """``[whine] method = "quasi-periodic"`` maps to QuasiPeriodicBalance with its sidebands;
    sidebands out of range, or with another method, is a one-line error."""
    good = {"speed_min_rad_s": 10.0, "speed_max_rad_s": 100.0, "harmonics": 6,
            "positions_per_period": 35}
    w = jio.parse_whine(good | {"method": "quasi-periodic", "sidebands": 2})
    assert isinstance(w.method, QuasiPeriodicBalance)
    assert (w.method.harmonics, w.method.sidebands) == (6, 2)
    assert jio.parse_whine(good | {"method": "quasi-periodic"}).method.sidebands == 1
    per_group = jio.parse_whine(good | {"method": "quasi-periodic",
                                        "positions_per_period": [140, 35]})
    assert per_group.positions == (140, 35)
    for extra, match in (({"method": "quasi-periodic", "sidebands": 7}, "sidebands.*6"),
                         ({"sidebands": 1}, "sidebands.*quasi-periodic"),
                         ({"positions_per_period": [140, 35]},
                          "positions_per_period = \\[140, 35\\].*quasi-periodic\" only"),
                         ({"method": "quasi-periodic", "positions_per_period": [140, 0]},
                          "positions_per_period = \\[140, 0\\]: element 0 out of range.*\\[1, 8192\\]"),
                         ({"method": "quasi-periodic", "positions_per_period": []},
                              "positions_per_period = \\[\\]: must be an array of at least 1")):
        with pytest.raises(ValueError, match=match) as e:
            jio.parse_whine(good | extra)
        assert "\n" not in str(e.value)


@pytest.mark.slow
def test_run_writes_each_meshs_orders(tmp_path):
    """``jaxgear run``'s whine on the ``two-stage`` case (4 slices) with ``[whine] method =
    "quasi-periodic"`` and each group's positions (``positions_per_period = [70, 35]``):
    whine.json names each output's mesh-frequency group and order, the orders of the second
    mesh are 35/127 of the first's, whine.csv has a row per speed and
    output, and each mesh has its own order plot."""
    import csv
    import json

    from jaxgear.cli.run import whine_outputs

    text = jio.embedded_case_text("two-stage").replace("slices = 20", "slices = 4")
    text += ('\n[whine]\nspeed_min_rad_s = 40.0\nspeed_max_rad_s = 80.0\nspeeds = 3\n'
             'harmonics = 4\nmethod = "quasi-periodic"\nsidebands = 0\n'
             'positions_per_period = [70, 35]\n')  # the first mesh's axis at 70
    path = tmp_path / "two-stage-whine.toml"
    path.write_text(text)
    case = jio.load_case(str(path))
    section = whine_outputs(case, str(tmp_path))
    data = json.loads((tmp_path / "whine" / "whine.json").read_text())
    assert data["order_group"] == [0] + [0] * 4 + [1] * 4
    assert data["group_order"] == [0, 1, 2, 3, 4, 1, 2, 3, 4]
    assert data["mesh_group"] == [0, 1]
    np.testing.assert_allclose(data["orders"][5:], np.arange(1, 5) * 35 / 127, rtol=1e-12)
    with (tmp_path / "whine" / "whine.csv").open() as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == 3 * 9 and "mesh_frequency_group" in rows[0]
    for name in data["meshes"]:
        assert (tmp_path / "whine" / f"te_orders_{name}.png").stat().st_size > 10_000
    assert section["method"] == "QuasiPeriodicBalance"
    assert data["positions_per_period"] == [70, 35]
