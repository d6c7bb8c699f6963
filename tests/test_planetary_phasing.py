"""Mesh phasing of a planetary stage (Parker & Lin 2004): the phases from the tooth counts and
the planet angles, checked on the turning sun's tooth pattern, and the in-phase and
sequentially-phased cases of the rule on which mesh harmonics reach the central members,
measured here by summing the N mesh forces (their directions and phases) over a mesh period."""

import numpy as np
import pytest

import jaxgear.planetary as jp

ALPHA_S = np.radians(22.0)


def test_phases_on_the_turning_sun_tooth_pattern():
    """The sun's tooth pattern seen at angle psi when the sun has turned phi (ccw, relative to
    the carrier) repeats planet 1's pattern a turn psi later: the lag in mesh periods is
    z_s psi / 2 pi (mod 1)."""
    zs, zr, n = 25, 71, 4
    psi = 2 * np.pi * np.arange(n) / n
    gamma_s, gamma_r = jp.mesh_phases(zs, zr, psi)

    def state(position, phi):  # where a sun tooth stands, in tooth pitches
        return np.mod(zs * (position - phi) / (2 * np.pi), 1.0)

    phi = np.linspace(0, 2 * np.pi / zs, 7)
    for j in range(n):
        lag_turn = gamma_s[j] * 2 * np.pi / zs  # the lag, as a sun turn
        np.testing.assert_allclose(state(psi[j], phi), state(psi[0], phi - lag_turn), atol=1e-9)
    np.testing.assert_allclose(gamma_s, [0.0, 0.25, 0.5, 0.75], atol=1e-12)
    # assembled planets: the ring-planet phases equal the sun-planet phases
    np.testing.assert_allclose(gamma_r, gamma_s, atol=1e-12)


def _harmonics(gamma, directions, harmonic):
    """Amplitude of harmonic l of the net torque (per unit radius) and net force of N meshes
    with forces F_n(t) = sum_l cos(2 pi l (t/T - gamma_n)) along ``directions`` (n, 2),
    by a DFT over one mesh period."""
    tau = np.arange(64) / 64
    forces = sum(np.cos(2 * np.pi * h * (tau[None, :] - gamma[:, None])) for h in range(1, 9))
    torque = forces.sum(axis=0)
    net = directions.T @ forces  # (2, 64)
    basis = np.exp(-2j * np.pi * harmonic * tau) / 32
    return abs(torque @ basis), np.linalg.norm(net @ basis)


def _rule(z, n, harmonic):
    """Parker & Lin's rule written here: k = l z mod N; torque if k = 0, force if k = +-1."""
    k = harmonic * z % n
    return k == 0, k in (1, n - 1)


@pytest.mark.parametrize(
    "zs, zr, n",
    [
        (24, 72, 4),  # in phase: z_s / N integer
        (25, 71, 4),  # sequentially phased
        (19, 56, 3),  # sequentially phased, 3 planets
        (27, 73, 5),  # sequentially phased, k = 2: harmonics 1 and 4 reach no central member
        (26, 70, 6),
    ],
)
def test_net_mesh_force_harmonics_follow_the_phasing_rule(zs, zr, n):
    psi = 2 * np.pi * np.arange(n) / n
    jp.check_assembly(zs, zr, psi)
    gamma_s, gamma_r = jp.mesh_phases(zs, zr, psi)
    sun_dirs = np.stack([-np.sin(psi - ALPHA_S), np.cos(psi - ALPHA_S)], axis=1)
    ring_dirs = np.stack([-np.sin(psi + ALPHA_S), np.cos(psi + ALPHA_S)], axis=1)
    seen = set()
    for harmonic in range(1, 9):
        torque_on, force_on = _rule(zs, n, harmonic)
        for gamma, dirs in ((gamma_s, sun_dirs), (gamma_r, ring_dirs)):
            torque, force = _harmonics(gamma, dirs, harmonic)
            assert (torque > 1e-6 * n) == torque_on, (harmonic, torque)
            assert (force > 1e-6 * n) == force_on, (harmonic, force)
            if torque_on:
                assert torque == pytest.approx(n, rel=1e-9)  # all N add up
        expected = (
            jp.ModeType.ROTATIONAL
            if torque_on
            else jp.ModeType.TRANSLATIONAL
            if force_on
            else jp.ModeType.PLANET
        )
        assert jp.phasing_excites(zs, n, harmonic) == expected
        seen.add(expected)
    if zs % n == 0:  # in phase: no net force at any harmonic, the torque at every one
        assert seen == {jp.ModeType.ROTATIONAL}
    if (zs, n) == (27, 5):
        assert jp.ModeType.PLANET in seen


def test_phasing_input_errors():
    with pytest.raises(ValueError, match="n_planets = 2 is out of range"):
        jp.phasing_excites(20, 2, 1)
    with pytest.raises(ValueError, match="z_ring = 20 is out of range"):
        jp.mesh_phases(20, 20, [0.0, 1.0])
