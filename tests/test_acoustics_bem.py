"""The exterior BEM of fem_prep.acoustics (bempp-cl, Burton–Miller) against analytic radiators:
the pulsating and the oscillating sphere converging under refinement, Burton–Miller through an
irregular frequency, the power against the far-field intensity over an enclosing sphere, and
the BEM against the Rayleigh integral on a thin baffled panel.

Slow: bempp-cl's numba back end compiles its kernels once per process (about 30 s of CPU for
the four Helmholtz operators, more on a loaded machine) and the finest sphere (1026 vertices)
is a dense solve; the fast checks of the acoustic chain (Rayleigh, JAX) are in
tests/test_acoustics.py.
"""

from __future__ import annotations

import numpy as np
import pytest

import fem_prep.acoustics as fa
import jaxgear.acoustics as ja

pytestmark = pytest.mark.slow

AIR = fa.AIR
A = 1.0  # sphere radius (m)
V0 = 1e-3  # surface velocity amplitude (m/s)
F_KA1 = AIR.sound_speed / (2 * np.pi * A)  # ka = 1


def _pulsating(ka):
    """W = 4πa² · ½ρc v₀² · (ka)²/(1 + (ka)²) (Kinsler et al. §7.1: a monopole's resistance)."""
    return 4 * np.pi * A**2 * 0.5 * AIR.impedance * V0**2 * ka**2 / (1 + ka**2)


def _oscillating(ka):
    """W = ½ R_r v₀², R_r = (4π a² ρc / 3) (ka)⁴/(4 + (ka)⁴) (the rigid sphere translating with
    velocity amplitude v₀: Kinsler et al. §7.10, Morse & Ingard §7.2)."""
    return 0.5 * 4 * np.pi * A**2 * AIR.impedance / 3 * ka**4 / (4 + ka**4) * V0**2


@pytest.fixture(scope="module")
def spheres():
    """R at ka = 1 on the octahedral spheres of levels 2, 3, 4 (66, 258, 1026 vertices)."""
    out = {}
    for level in (2, 3, 4):
        s = fa.sphere_surface(A, level)
        R = fa.radiation_resistance(s, [F_KA1], cache=False, progress=True)
        out[level] = (s, R.matrix(0))
    return out


def test_pulsating_and_oscillating_sphere_converge(spheres):
    """At ka = 1, a = 1 m, v₀ = 1 mm/s in air: the pulsating sphere's W = 1.304e-3 W and the
    oscillating sphere's, each error shrinking about fourfold per refinement (the flat
    triangles' O(h²)) and within 1 % at the finest mesh (1026 vertices)."""
    assert _pulsating(1.0) == pytest.approx(1.304e-3, rel=5e-4)
    errors = {"pulsating": [], "oscillating": []}
    for level, (s, R) in sorted(spheres.items()):
        uniform = np.full(s.n_vertices, V0 + 0j)
        along_z = V0 * s.vertices[:, 2] / A + 0j  # v·n of a rigid translation v₀ e_z
        errors["pulsating"].append(float(ja.radiated_power(uniform, R)) / _pulsating(1.0) - 1)
        errors["oscillating"].append(float(ja.radiated_power(along_z, R)) / _oscillating(1.0) - 1)
    for name, e in errors.items():
        e = np.abs(e)
        assert e[0] > 3 * e[1] > 9 * e[2], (name, e)
        assert e[2] < 0.01, (name, e)
