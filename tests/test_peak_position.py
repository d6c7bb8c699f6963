"""The position a run reports its bodies' deformation and stresses at (jaxgear.cli.scene.first_peak):
on a plateau of equal peak line loads (one tooth pair carrying the whole load over part of the
mesh cycle) it is the plateau's first position, whatever round-off puts on top. np.argmax's pick
moved with the BLAS threads and put the idler train's recorded body stress 0.1-4.9 % off."""

import types

import numpy as np

from jaxgear.cli.scene import PEAK_RTOL, first_peak, peak_position

# the idler train's peak line loads (N/m) at its tied positions 1, 2, 3 and 13, as two runs
# with different BLAS threads computed them (np.argmax: 1 in one run, 13 in the other)
PLATEAU = 319253.3317427806


def _peaks(noise):
    peak = np.full(16, 0.8 * PLATEAU)
    peak[[1, 2, 3, 9, 13, 14]] = PLATEAU * (1 + np.asarray(noise) * 1e-15)
    return peak


def test_the_first_of_a_plateau_whatever_the_round_off():
    one, other = _peaks([3, 2, 1, 0, -1, -2]), _peaks([-3, 0, -1, 1, 3, -2])
    assert (np.argmax(one), np.argmax(other)) == (1, 13)  # the round-off's pick moves
    assert first_peak(one) == first_peak(other) == 1


def test_a_peak_above_the_tolerance_wins():
    peak = _peaks([0] * 6)
    peak[13] *= 1 + 10 * PEAK_RTOL
    assert first_peak(peak) == 13
    peak[13] = PLATEAU * (1 + 0.5 * PEAK_RTOL)
    assert first_peak(peak) == 1


def test_peak_position_of_a_one_mesh_result():
    load = np.zeros((16, 3, 4))  # positions x slices x cells
    load[:, 1, 2] = _peaks([-3, 0, -1, 1, 3, -2])
    assert peak_position(types.SimpleNamespace(line_load=load)) == 1
