"""Mode types of the 3D lumped model (jaxgear.planetary.classify_modes on
jaxgear.planetary.SpatialPlanetary) where two types share a frequency: with equal sun and ring mesh
stiffnesses and pressure angles the planets' tilt about their radial axes meets the central members
only through the harmonics +-1, so its harmonic-0 mode (rotational-axial, central members all but
still) has the frequency of a planet mode for N >= 4. The counts Eritenel & Parker (2009) prove for
N equally spaced planets (12 rotational-axial modes, 12 translational-tilting pairs, 6 planet
frequencies of multiplicity N - 3) hold there too; the shared group is checked here by its own
harmonics."""

import numpy as np
import pytest
from _planetary_stage import frequency_groups
from test_planetary_spatial import stage

import jaxgear as jg
import jaxgear.planetary as jp


@pytest.mark.parametrize("n", [4, 5])
def test_a_rotational_axial_mode_sharing_a_planet_modes_frequency_is_typed_by_projection(n):
    """Equal mesh stiffnesses (5e8 N/m both), N = 4, 5: 12 rotational-axial modes, 24
    translational-tilting (12 pairs), 6 (N - 3) planet modes, none mixed, and one group of
    N - 2 equal frequencies typed 1 rotational-axial + (N - 3) planet. In that group's span
    (its shapes, any basis) the test finds by its own least squares a shape in which every
    planet moves alike in its own frame (harmonic 0) with the central members still to 1e-6
    of it (the planets tilting about e_zeta), and the rest of the span has no planet
    harmonic 0 or 1 (planet modes, 1e-7)."""
    st = stage(n=n)  # k_ring = k_sun
    model = jp.SpatialPlanetary()
    modes = jp.planetary_modes(model, st)
    types = jp.classify_modes(modes, model, st)
    T = jp.ModeType
    kinds = [k for k, _ in types]
    assert kinds.count(T.ROTATIONAL_AXIAL) == 12
    assert kinds.count(T.TRANSLATIONAL_TILTING) == 24
    assert kinds.count(T.PLANET) == 6 * (n - 3)
    assert T.MIXED not in kinds
    f = np.asarray(modes.frequencies)
    phi = np.asarray(modes.shapes)
    psi = np.asarray(st.planet_angles)
    shared = [g for g in frequency_groups(f) if len({kinds[j] for j in g}) > 1]
    assert len(shared) == 1
    g = shared[0]
    assert len(g) == n - 2
    assert [types[j] for j in g] == [(T.ROTATIONAL_AXIAL, 1)] + [(T.PLANET, n - 3)] * (n - 3)
    block = phi[:, g]
    planets = block[18:].reshape(n, 6, len(g))
    spread = (planets - planets.mean(axis=0)).reshape(-1, len(g))
    _, sv, vt = np.linalg.svd(spread)
    alike = block @ vt[-1]  # the combination whose planets move alike
    scale = np.abs(alike).max()
    assert sv[-1] < 1e-7 * sv[0]
    assert np.abs(alike[:18]).max() < 1e-6 * scale
    assert np.abs(alike[18:]).max() == pytest.approx(scale)
    tilt = alike[18:].reshape(n, 6)[0]
    assert np.argmax(np.abs(tilt)) == 3  # theta_zeta
    rest = block @ vt[:-1].T
    planets = rest[18:].reshape(n, 6, -1)
    for h in (np.ones(n), np.cos(psi), np.sin(psi)):
        np.testing.assert_allclose(np.einsum("n,nck->ck", h, planets), 0.0,
                                   atol=1e-7 * np.abs(rest).max())


def test_unequal_spacing_keeps_the_share_rule():
    """Planets not equally spaced: no cyclic symmetry to project on; each group typed by the
    central members' shares as before (mixed modes appear, N = 4 at 0, 1.4, 3.3, 4.9 rad)."""
    st = stage(n=4, angles=np.array([0.0, 1.4, 3.3, 4.9]))
    model = jp.SpatialPlanetary()
    types = jp.classify_modes(jp.planetary_modes(model, st), model, st)
    assert jp.ModeType.MIXED in {k for k, _ in types}
