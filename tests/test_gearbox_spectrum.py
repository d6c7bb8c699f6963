"""The coupled gearbox's Campbell diagram and housing-point spectrum (jaxgear.gearbox:
mesh_frequencies, campbell_crossings, housing_spectrum; docs/gearbox.md), against references
written here: the mesh orders from tooth counts and Willis, the McFadden & Smith (1985) lines of
a ring-fixed sensor for equally spaced planets derived from the tooth counts and the window's
Fourier coefficients, a synthetic signal with known lines, and the modes' strain energies."""

import math
import runpy
from pathlib import Path

import equinox as eqx
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.planetary as jp
from jaxgear import gearbox as gb

ROOT = Path(__file__).resolve().parents[1]
two_stage = runpy.run_path(str(ROOT / "examples" / "gearbox_two_stage.py"))["two_stage"]

MODULE, ALPHA, K_U = 4e-3, np.radians(20.0), 1.4e10


def sequential_chain(zs=21, zp=29, zr=79, n=4):
    """The two-stage example's build with 21/29/-79 teeth (4 equally spaced planets: (21 + 79)
    / 4 = 25 whole, z_r = 3 mod 4: sequentially phased) and the pair on its constant spring
    (no excitation but the planetary stage's, so the steady state has the carrier's period)."""
    b1, b2 = 0.05, 0.08
    geo = jg.planetary_geometry(jg.Member(zs, face_width=b1),
                                jg.Member(zp, face_width=b1, dedendum_coeff=1.3),
                                jg.Member(-zr, face_width=b1), MODULE, ALPHA)
    psi = 2 * np.pi * np.arange(n) / n
    meshes = jp.ContactMeshes.from_geometry(geo, psi, jg.Uniform(K_U), 1)
    r_s, r_p = (float(r) for r in geo.sun_planet.base_radii)
    r_r = float(geo.planet_ring.base_radii[1])
    m, k_mesh = jp.PlanetaryMember, K_U * b1 * 1.5
    stage = jp.PlanetaryStage(
        sun=m(1.0, 1.6e-3, r_s), ring=m(10.0, 2.0, r_r, torsional_stiffness=1e9),
        carrier=m(10.0, 0.5, 0.1), planet=m(4.44, 8.0e-3, r_p), planet_angles=psi,
        sun_pressure_angle=geo.sun_pressure_angle, ring_pressure_angle=geo.ring_pressure_angle,
        sun_mesh_stiffness=k_mesh, ring_mesh_stiffness=k_mesh)
    planetary = gb.PlanetaryGearboxStage(stage, jp.Central.CARRIER, jp.Central.SUN, meshes)
    pair = jg.GearPair(jg.Member(24, face_width=b2), jg.Member(32, face_width=b2), MODULE, ALPHA)
    parallel = gb.PairGearboxStage((5.2e-3, 0.0165), pair.base_radii, K_U * b2 * 1.6, input=1)
    return gb.GearboxTorsional((planetary, parallel), [5e5]), gb.GearboxRun(5000.0, 5e5)


def test_mesh_orders_from_tooth_counts():
    """Stage 1 (20/30/-80, ring held, carrier in at Omega): the ring-planet mesh frequency in
    the carrier frame z_r Omega / 2 pi, the sun's speed (1 + z_r / z_s) Omega (Willis); the
    pair's 32-tooth wheel on the sun: 32 (1 + 80/20) Omega / 2 pi."""
    chain, _ = two_stage()
    omega = 37.0
    f = np.asarray(gb.mesh_frequencies(chain, omega))
    sun = (1 + 80 / 20) * omega
    np.testing.assert_allclose(f, [80 * omega / (2 * np.pi), 32 * sun / (2 * np.pi)], rtol=1e-12)
    np.testing.assert_allclose(np.asarray(gb.carrier_frequencies(chain, omega)),
                               [omega / (2 * np.pi), 0.0], atol=1e-12)
    # sun-planet mesh alike: z_s |omega_s - omega_c| = 20 (5 - 1) Omega = z_r Omega
    assert 20 * (sun - omega) == pytest.approx(80 * omega)


def _strain_shares(chain, run, modes):
    """Each stage's meshes' share of each mode's strain energy, from the stages' mean mesh
    stiffness (their dynamic_parts) and the eigenvalue omega^2 = phi^T (K + K_m) phi."""
    phi = np.asarray(modes.analysis.shapes)
    w2 = (2 * np.pi * np.asarray(modes.analysis.frequency)) ** 2
    out, i = [], 0
    # each stage's parts by one compiled program (eagerly, several hundred small ones)
    parts = eqx.filter_jit(lambda s: s.dynamic_parts(run.mean_positions))
    for s in chain.stages:
        k_m = np.asarray(parts(s)[2])
        p = phi[i:i + k_m.shape[0]]
        out.append(np.einsum("in,ij,jn->n", p, k_m, p) / w2)
        i += k_m.shape[0]
    return np.array(out)


def test_campbell_crossings_slopes_and_labels():
    chain, run = two_stage()
    modes = gb.gearbox_coupled_modes(chain, run)
    top = 200.0
    rows = gb.campbell_crossings(chain, modes, top, harmonics=(1, 2))
    slope = {1: 80 / (2 * np.pi), 2: 32 * 5 / (2 * np.pi)}  # Hz per rad/s of the carrier
    freqs = np.asarray(modes.analysis.frequency)
    elastic = ~np.asarray(modes.analysis.rigid)
    shares = _strain_shares(chain, run, modes)
    table = gb.coupled_mode_table(chain, modes)
    # every crossing written here is found, and nothing else
    expected = sorted((f / (h * slope[k]), k, h, j) for k in (1, 2) for h in (1, 2)
                      for j, f in enumerate(freqs) if elastic[j] and f / (h * slope[k]) <= top)
    assert len(rows) == len(expected) > 0
    for r, (speed, k, h, j) in zip(rows, expected, strict=True):
        assert (r["stage"], r["harmonic"], r["mode"]) == (k, h, j)
        assert r["speed_rad_s"] == pytest.approx(speed, rel=1e-12)
        assert r["stage_mesh_energy"] == pytest.approx(shares[k - 1, j], abs=1e-6)
        assert r["marked"] == (shares[k - 1, j] >= 0.05)
        assert (r["type"], r["mesh"]) == (table[j]["type"], table[j]["mesh"])
        if r["type"] == "mesh":  # the meshes hold the largest of three parts: >= 1/3
            assert shares[:, j].sum() >= 1 / 3 - 1e-6


def test_spectrum_recovers_synthetic_lines():
    """Lines of known amplitude, one on the record's grid, two off it, and a DC: read back at
    their frequencies (Hann: the grid's lines to the off-grid lines' sidelobes, which fall as
    1 / k^3 over k bins: 1e-6 here; 1e-3 off the grid), and the FFT's peak bins."""
    T, n = 2.0, 4000
    t = 0.3 + np.arange(n) * T / n
    lines = [(0.0, 1.5), (50.0, 2.0), (123.3, 0.7), (300.77, 0.05)]
    x = sum(a * np.cos(2 * np.pi * f * t + 0.4 * i) for i, (f, a) in enumerate(lines))
    got = gb.line_amplitudes(t, x, [f for f, _ in lines])
    np.testing.assert_allclose(got[:2], [1.5, 2.0], rtol=1e-6)
    np.testing.assert_allclose(got[2:], [0.7, 0.05], rtol=1e-3)
    f, a = gb.amplitude_spectrum(t, x)
    assert f[1] == pytest.approx(1 / T)
    assert a[np.argmin(abs(f - 50.0))] == pytest.approx(2.0, rel=1e-6)
    rect = gb.line_amplitudes(t, x, [50.0], window="rect")
    assert rect[0] == pytest.approx(2.0, rel=2e-3)
    with pytest.raises(ValueError, match="window"):
        gb.line_amplitudes(t, x, [1.0], window="flat")


def window_coefficients(power, ks):
    """c_k = (1 / 2 pi) integral of w(phi) exp(-i k phi) of the planet-pass window
    w = ((1 + cos phi) / 2)^p = cos^2p(phi / 2) = 4^-p sum_j C(2p, j) exp(i (j - p) phi):
    C(2p, p + k) / 4^p for |k| <= p, else 0."""
    return np.array([math.comb(2 * power, power + k) / 4.0**power if abs(k) <= power else 0.0
                     for k in ks])


@pytest.fixture(scope="module")
def sequential():
    chain, run = sequential_chain()
    return chain, gb.housing_spectrum(chain, run, 60.0, revolutions=2, steps_per_period=16)


def test_ring_point_lines_mcfadden_smith(sequential):
    """A sensor on the ring of a stage with N = 4 equally spaced identical planets and z_r = 79
    (ring held, carrier at f_c): planet n's ring force is planet 1's a quarter revolution on,
    F_rn(t) = sum_m a_m exp(i m z_r (psi_n + omega_c t)), so the windowed sum holds only the
    lines p f_c with p = 0 (mod 4), of two-sided amplitude N sum_m a_m c_(p - m z_r), c_k the
    window's Fourier coefficients (the window ((1 + cos phi) / 2)^4: |k| <= 4): at the mesh
    frequency 79 f_c nothing, the largest line at 80 f_c (k = +1, c = 56/256) and a smaller one
    at 76 f_c (k = -3, c = 8/256): McFadden and Smith's asymmetry; none at 84 f_c (k = 5)."""
    _chain, hs = sequential
    sig = hs.signals
    t = np.asarray(sig.time)
    fc = float(hs.carrier_frequency[0])
    assert fc == pytest.approx(60.0 / (2 * np.pi))
    assert (t[-1] - t[0] + hs.time_step) * fc == pytest.approx(2.0, rel=1e-12)  # 2 revolutions
    p = np.arange(40, 130)
    amp = gb.line_amplitudes(t, sig.ring_meshes, p * fc)
    n, zr, power = 4, 79, 4
    kept = p % n == 0
    # (the rest: the start's transient after 8 time constants, a few 1e-9 of the largest)
    assert np.max(amp[~kept]) < 1e-7 * np.max(amp)
    assert p[np.argmax(amp)] == 80
    # the amplitudes predicted from planet 1's own ring force and the window
    f1 = np.asarray(hs.dynamics.mesh_forces)[:, n]
    ms = np.arange(-2, 3)
    a_m = np.array([np.mean(f1 * np.exp(-1j * m * zr * 2 * np.pi * fc * t)) for m in ms])
    pred = np.array([2 * abs(n * np.sum(a_m * window_coefficients(power, q - ms * zr)))
                     for q in p[kept]])
    # to 1e-6 of the largest line (the sampled window's aliased tail, the transient's rest)
    np.testing.assert_allclose(amp[kept], pred, rtol=1e-6, atol=1e-6 * pred.max())
    assert amp[p == 80][0] > 3 * amp[p == 76][0]
    assert amp[p == 84][0] < 1e-7 * amp[p == 80][0]


def test_ring_support_and_bearing(sequential):
    """The ring's mean support reaction is the ring meshes' mean force (the ring at rest on
    average: k_t theta_r = r_br sum_n F_rn); the ring point adds the window's share, its mean
    C(8, 4) / 4^4 = 70/256; the pair's bearing force is its mesh force (torsional pair, centres held)."""
    _chain, hs = sequential
    sig = hs.signals
    f = np.asarray(hs.dynamics.mesh_forces)
    assert np.mean(sig.ring_support) == pytest.approx(np.mean(f[:, 4:8].sum(axis=1)), rel=1e-9)
    np.testing.assert_allclose(sig.ring_point, sig.ring_meshes + sig.ring_support * 70 / 256,
                               rtol=1e-12)
    np.testing.assert_allclose(sig.bearing, f[:, 8], rtol=1e-12)


def test_housing_lines_positions():
    """The lines the summary reads for the two-stage example at 60 rad/s: z_r = 80 = 0 (mod 4):
    the McFadden-Smith line is the mesh frequency itself; the planet-pass sidebands 4 f_c
    apart."""
    chain, _ = two_stage()
    fc = 60.0 / (2 * np.pi)
    lines = gb.housing_lines(chain, 60.0, harmonics=(1,), sidebands=1)
    got = {(r["kind"], r["stage"], r["sideband"]): r["frequency_Hz"] for r in lines}
    assert got[("McFadden-Smith", 1, 0)] == pytest.approx(80 * fc)
    assert got[("planet pass", 1, 1)] == pytest.approx(84 * fc)
    assert got[("planet pass", 2, -1)] == pytest.approx(160 * fc - 4 * fc)
    assert got[("mesh", 1, 0)] == pytest.approx(got[("McFadden-Smith", 1, 0)], rel=1e-12)


def test_refusals():
    chain, run = two_stage()
    with pytest.raises(TypeError, match="ring_stage"):
        gb.housing_spectrum(chain, run, 60.0, ring_stage=1)
    with pytest.raises(ValueError, match="input_speed"):
        gb.housing_spectrum(chain, run, 0.0)
    with pytest.raises(ValueError, match="revolutions"):
        gb.housing_spectrum(chain, run, 60.0, revolutions=0)
    with pytest.raises(ValueError, match="max_speed"):
        gb.campbell_crossings(chain, None, -1.0)
    with pytest.raises(ValueError, match="modes"):
        gb.campbell_crossings(chain, None, 1.0)
    with pytest.raises(TypeError, match="ring_stage"):
        gb.housing_lines(chain, 60.0, ring_stage=1)


def test_jaxgear_run_campbell(tmp_path):
    """jaxgear run's Campbell section of a gearbox on the two-stage case file (20/30/-80, 4
    planets, carrier in; the pair's 32-tooth wheel on the sun): files written; the mesh orders'
    slopes 80 / 2 pi and 32 (1 + 80/20) / 2 pi Hz per rad/s; the crossings counted."""
    import json

    from jaxgear.cli.gearbox import coupled_campbell
    from jaxgear.io import load_case

    case = load_case(str(ROOT / "tests" / "data" / "gearbox" / "two-stage-gearbox.toml"))
    c = coupled_campbell(case.form, case, str(tmp_path))
    for name in ("campbell.json", "campbell.png"):
        assert (tmp_path / name).is_file()
    data = json.loads((tmp_path / "campbell.json").read_text())
    np.testing.assert_allclose(data["mesh_Hz_per_rad_s"], [80 / (2 * np.pi), 160 / (2 * np.pi)],
                               rtol=1e-12)
    assert c["crossings"] == len(data["crossings"]) > 0


# default tier: tests/test_gearbox_spectrum.py::test_ring_point_lines_mcfadden_smith (housing_spectrum's lines) and ::test_housing_lines_positions (the lines the summary reads)
@pytest.mark.slow
def test_jaxgear_run_campbell_and_housing_spectrum(tmp_path):
    """jaxgear run's Campbell and housing-spectrum sections of a gearbox on the two-stage case
    file (20/30/-80, 4 planets, carrier in at 100 rad/s; the pair's 32-tooth wheel on the sun):
    files written; the mesh orders' slopes 80 / 2 pi and 32 (1 + 80/20) / 2 pi Hz per rad/s;
    z_r = 80 = 0 (mod 4): the McFadden-Smith line is the mesh frequency itself; the bearing's
    orders the pair's harmonics."""
    from jaxgear.cli.gearbox import coupled_campbell, housing_point_spectrum
    from jaxgear.io import load_case

    case = load_case(str(ROOT / "tests" / "data" / "gearbox" / "two-stage-gearbox.toml"))
    c = coupled_campbell(case.form, case, str(tmp_path))
    h = housing_point_spectrum(case.form, case, str(tmp_path))
    for name in ("campbell.json", "campbell.png", "housing_spectrum.json",
                 "housing_spectrum.png"):
        assert (tmp_path / name).is_file()
    import json

    data = json.loads((tmp_path / "campbell.json").read_text())
    np.testing.assert_allclose(data["mesh_Hz_per_rad_s"], [80 / (2 * np.pi), 160 / (2 * np.pi)],
                               rtol=1e-12)
    assert c["crossings"] == len(data["crossings"])
    fc = 100.0 / (2 * np.pi)
    assert h["planet_pass_Hz"] == pytest.approx(4 * fc)
    assert [r["offset_fc"] for r in h["mcfadden_smith_lines"]] == [0]
    assert h["mcfadden_smith_lines"][0]["frequency_Hz"] == pytest.approx(80 * fc)
    np.testing.assert_allclose([r["frequency_Hz"] for r in h["bearing_orders"]],
                               [160 * fc * k for k in (1, 2, 3)], rtol=1e-12)
