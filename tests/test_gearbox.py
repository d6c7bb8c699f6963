"""The gearbox torsional chain (:class:`jaxgear.gearbox.GearboxTorsional`): the NREL 5 MW reference
gearbox's two planetary stages (the embedded ``nrel-5mw-planetary`` and ``nrel-5mw-stage2``)
and its parallel stage (``nrel-5mw-stage3``) joined by their shafts. Its natural frequencies
against an eigen-solution written here from the members' inertias, radii and stiffnesses
(kinetic and strain energies of Kahraman's torsional planetary model in absolute rotations,
the pair's mesh, the shafts), to 1e-9."""

from __future__ import annotations

import math

import jax
import numpy as np
import pytest
import scipy.linalg

import jaxgear as jg
import jaxgear.gearbox as jgb
import jaxgear.io as jio

jax.config.update("jax_enable_x64", True)

# the parallel stage's torsional data (estimates: steel cylinders of Table V's reference
# diameters and face width 360 mm; the mean mesh stiffness of jaxgear run nrel-5mw-stage3)
PAIR_INERTIAS = (3.75, 921.0)  # kg m^2
PAIR_MESH = 7.668e9  # N/m
SHAFTS = (1.26e9, 1.435e8)  # N m/rad: G pi d^4 / (32 L), d/L 533/500 and 333/666 mm


def _planetary(name):
    case = jio.load_case(name)
    spec = case.form.spec
    return spec.stage(case), spec


def _chain():
    s1, spec1 = _planetary("nrel-5mw-planetary")
    s2, spec2 = _planetary("nrel-5mw-stage2")
    pair = jio.load_case("nrel-5mw-stage3").pair
    stages = (
        jgb.PlanetaryGearboxStage(s1, spec1.input, spec1.output),
        jgb.PlanetaryGearboxStage(s2, spec2.input, spec2.output),
        jgb.PairGearboxStage(PAIR_INERTIAS, pair.base_radii, PAIR_MESH, input=1),
    )
    return jgb.GearboxTorsional(stages, SHAFTS), (s1, s2), pair


def _planetary_reference(st):
    """(M, K) in (theta_c, theta_r, theta_s, theta_1..N) from the energies: the planets ride
    with the carrier (I_c + N m_p r_c^2), the sun mesh compresses by r_s th_s + r_p th_n -
    r_c cos a_s th_c, the ring mesh by r_r th_r - r_p th_n - r_c cos a_r th_c."""
    f = lambda x: float(np.asarray(x))
    n = st.n_planets
    r_c, r_r, r_s, r_p = (f(m.base_radius) for m in (st.carrier, st.ring, st.sun, st.planet))
    a_s, a_r = f(st.sun_pressure_angle), f(st.ring_pressure_angle)
    k_s = np.broadcast_to(np.asarray(st.sun_mesh_stiffness), (n,))
    k_r = np.broadcast_to(np.asarray(st.ring_mesh_stiffness), (n,))
    m = np.diag(
        [
            f(st.carrier.polar_inertia) + n * f(st.planet.mass) * r_c**2,
            f(st.ring.polar_inertia),
            f(st.sun.polar_inertia),
            *[f(st.planet.polar_inertia)] * n,
        ]
    )
    k = np.diag(
        [f(st.carrier.torsional_stiffness), f(st.ring.torsional_stiffness)]
        + [f(st.sun.torsional_stiffness)]
        + [0.0] * n
    )
    for i in range(n):
        v = np.zeros(3 + n)
        v[[0, 2, 3 + i]] = (-r_c * math.cos(a_s), r_s, r_p)
        k += k_s[i] * np.outer(v, v)
        v = np.zeros(3 + n)
        v[[0, 1, 3 + i]] = (-r_c * math.cos(a_r), r_r, -r_p)
        k += k_r[i] * np.outer(v, v)
    return m, k


def reference_frequencies():
    """The NREL chain's natural frequencies (Hz) from the energies written here."""
    return _reference()[0]


def _reference():
    _, (s1, s2), pair = _chain()
    blocks = [_planetary_reference(s1), _planetary_reference(s2)]
    r = np.asarray(pair.base_radii)
    blocks.append((np.diag(PAIR_INERTIAS), PAIR_MESH * np.outer(r, r)))
    m = scipy.linalg.block_diag(*[b[0] for b in blocks])
    k = scipy.linalg.block_diag(*[b[1] for b in blocks])
    # shafts: stage 1's sun (index 2) to stage 2's carrier (6 + 0); stage 2's sun (6 + 2) to
    # the wheel (12 + 1)
    for (i, j), kt in zip(((2, 6), (8, 13)), SHAFTS, strict=True):
        k[np.ix_([i, j], [i, j])] += kt * np.array([[1.0, -1.0], [-1.0, 1.0]])
    lam = scipy.linalg.eigh(k, m, eigvals_only=True)
    return np.sqrt(np.clip(lam, 0.0, None)) / (2 * math.pi), m, k


def test_nrel_gearbox_chain_frequencies_against_an_independent_eigen_solution():
    chain = _chain()[0]
    ref, m, k = _reference()
    modes = jgb.gearbox_modes(chain)
    got = np.asarray(modes.frequencies)
    assert got.shape == (14,)
    # free at the rotor (carrier 1) and the generator (pinion): one rigid-body mode
    assert ref[0] < 1e-6 * ref[-1] and got[0] < 1e-6 * got[-1]
    np.testing.assert_allclose(got[1:], ref[1:], rtol=1e-9)
    np.testing.assert_allclose(np.asarray(modes.stage_energy).sum(axis=0), 1.0, rtol=1e-12)
    m_got, k_got = (np.asarray(a) for a in chain.matrices())
    np.testing.assert_allclose(m_got, m, rtol=1e-12, atol=1e-12 * np.abs(m).max())
    np.testing.assert_allclose(k_got, k, rtol=1e-9, atol=1e-12 * np.abs(k).max())


def test_a_rigid_shaft_chain_of_pairs_has_the_reflected_inertia_frequency():
    """Two pairs joined by a very stiff shaft: the one elastic mode of each mesh, the second
    pair's pinion free; a single pair's frequency is sqrt(k (r1^2/I1 + r2^2/I2)) / 2 pi."""
    k_m, r, inertia = 1e9, (0.05, 0.1), (0.2, 1.0)
    single = jgb.GearboxTorsional((jgb.PairGearboxStage(inertia, r, k_m),), ())
    f = np.asarray(jgb.gearbox_modes(single).frequencies)
    expect = math.sqrt(k_m * (r[0] ** 2 / inertia[0] + r[1] ** 2 / inertia[1])) / (2 * math.pi)
    assert f[0] == pytest.approx(0.0, abs=1e-6 * expect)
    assert f[1] == pytest.approx(expect, rel=1e-12)


def test_chain_errors_are_one_line():
    stage = jgb.PairGearboxStage((1.0, 1.0), (0.1, 0.1), 1e9)
    with pytest.raises(ValueError, match=r"shaft_stiffnesses: shape \(2,\), allowed \(1,\)"):
        jgb.GearboxTorsional((stage, stage), (1.0, 2.0))
    with pytest.raises(ValueError, match="input = 2: out of range"):
        jgb.PairGearboxStage((1.0, 1.0), (0.1, 0.1), 1e9, input=2)
