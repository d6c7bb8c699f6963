"""The exterior BEM of fem_prep.acoustics (bempp-cl, Burton–Miller) against analytic radiators:
the pulsating and the oscillating sphere converging under refinement, Burton–Miller through an
irregular frequency, the power against the far-field intensity over an enclosing sphere, and
the BEM against the Rayleigh integral on a thin baffled panel.

Slow: bempp-cl builds its kernels once per process (OpenCL on PoCL, the default where it
imports: about 20 s; numba's compile: minutes on a loaded machine) and the finest sphere (1026
vertices) is a dense solve; the fast checks of the acoustic chain (Rayleigh, JAX) are in
tests/test_acoustics.py. The sphere of level 5 (4098 vertices), where the oscillating sphere
comes within 1 %, is opt-in (``JAXGEAR_TEST_FINE_BEM=1``): its test (levels 4 and 5, bempp's
compile included) took 10 min of CPU (18 min of wall time on the shared 2-core host) and 3.5 GB.
"""

from __future__ import annotations

import os

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
    triangles' O(h²); measured: pulsating -6.7, -1.7, -0.44 %; oscillating -18, -4.9, -1.26 %;
    level 5, test_oscillating_sphere_within_one_percent_at_level_5: -0.11 %, -0.32 %).
    The pulsating sphere is within 1 % at the finest mesh (1026 vertices); the oscillating one,
    whose power goes as the sixth power of the radius at low ka and so feels the inscribed
    polyhedron more, is within 1.5 % there and its Richardson extrapolation of the last two
    meshes (h² → 0) is within 1 % (both within 0.1 %)."""
    assert _pulsating(1.0) == pytest.approx(1.304e-3, rel=5e-4)
    errors = {"pulsating": [], "oscillating": []}
    for level, (s, R) in sorted(spheres.items()):
        uniform = np.full(s.n_vertices, V0 + 0j)
        along_z = V0 * s.vertices[:, 2] / A + 0j  # v·n of a rigid translation v₀ e_z
        errors["pulsating"].append(float(ja.radiated_power(uniform, R)) / _pulsating(1.0) - 1)
        errors["oscillating"].append(float(ja.radiated_power(along_z, R)) / _oscillating(1.0) - 1)
    for name, e in errors.items():
        richardson = (4 * e[2] - e[1]) / 3
        e = np.abs(e)
        assert e[0] > 3 * e[1] > 9 * e[2], (name, e)
        assert abs(richardson) < 0.01, (name, richardson)
    assert abs(errors["pulsating"][2]) < 0.01
    assert abs(errors["oscillating"][2]) < 0.015


@pytest.mark.skipif(
    not os.environ.get("JAXGEAR_TEST_FINE_BEM"),
    reason="the level-5 sphere (4098 vertices) takes 10 min of CPU of dense BEM (18 min on the "
    "shared 2-core host) and 3.5 GB: "
    "set JAXGEAR_TEST_FINE_BEM=1",
)
def test_oscillating_sphere_within_one_percent_at_level_5():
    """The finest mesh of the issue's evidence: on the octahedral sphere of level 5 (4098
    vertices) at ka = 1 the oscillating sphere's power is within 1 % of
    ½ (4πa²ρc/3) (ka)⁴/(4 + (ka)⁴) v₀² (measured -0.32 %) and the pulsating sphere's within
    0.25 % of 1.304e-3 W (measured -0.11 %), each error a quarter of level 4's within 20 %
    (the flat triangles' O(h²))."""
    errors = []
    for level in (4, 5):
        s = fa.sphere_surface(A, level)
        R = fa.radiation_resistance(s, [F_KA1], cache=False, progress=True).matrix(0)
        uniform = np.full(s.n_vertices, V0 + 0j)
        along_z = V0 * s.vertices[:, 2] / A + 0j
        errors.append((float(ja.radiated_power(along_z, R)) / _oscillating(1.0) - 1,
                       float(ja.radiated_power(uniform, R)) / _pulsating(1.0) - 1))
    (o4, p4), (o5, p5) = errors
    assert abs(o5) < 0.01 and abs(p5) < 0.0025, errors
    assert 0.2 < o5 / o4 < 0.3 and 0.2 < p5 / p4 < 0.3, errors


def test_burton_miller_through_the_irregular_frequency():
    """Near ka = π (the first interior Dirichlet eigenvalue of the sphere; the inscribed
    polyhedron of 66 vertices has it between ka = 3.2 and 3.25) the direct equation alone
    fails on the pulsating sphere (measured: -27 % at ka = 3.25), while Burton–Miller stays
    at the coarse mesh's own error (-4.2 % at every ka of the scan; -6.7 % at ka = 1)."""
    s = fa.sphere_surface(A, 2)
    v = np.full(s.n_vertices, V0 + 0j)
    worst = {"direct": 0.0, "burton-miller": 0.0}
    for ka in (3.0, 3.1, 3.2, 3.25):
        f = ka * AIR.sound_speed / (2 * np.pi * A)
        for form in (fa.Direct(), fa.BurtonMiller()):
            R = fa.radiation_resistance(s, [f], method=fa.BEM(form), cache=False).matrix(0)
            err = abs(float(ja.radiated_power(v, R)) / _pulsating(ka) - 1)
            worst[str(form)] = max(worst[str(form)], err)
    assert worst["burton-miller"] < 0.05
    assert worst["direct"] > 0.2


def test_backends_agree_and_the_adjoint_is_the_transpose():
    """On the sphere of 66 vertices at ka = 1.5: bempp-cl's adjoint double layer K' equals the
    transpose of its double layer K (the Galerkin identity bem_impedance uses instead of a
    fourth assembly) to its quadrature's 1e-4; the OpenCL back end's operators, where a CPU
    OpenCL driver imports, equal numba's to 1e-12 (the backend is not in the cache key), and a
    second frequency reuses its built kernels."""
    s = fa.sphere_surface(A, 2)
    k = 1.5 / A
    ops = fa.bem_operators(s, k, with_adjoint=True, backend=fa.Numba())
    K = ops["double_layer"]
    assert np.linalg.norm(ops["adjoint_double_layer"] - K.T) < 1e-4 * np.linalg.norm(K)
    import bempp_cl.api as bempp

    if not fa.OpenCL().available(bempp):
        pytest.skip("no CPU OpenCL driver (pip install pyopencl pocl-binary-distribution)")
    for kk in (k, 0.7 * k):
        ref = ops if kk == k else fa.bem_operators(s, kk, backend=fa.Numba())
        cl = fa.bem_operators(s, kk, with_adjoint=kk == k, backend=fa.OpenCL())
        for name, a in ref.items():
            assert np.linalg.norm(cl[name] - a) <= 1e-12 * np.linalg.norm(a), name


def _sphere_quadrature(radius, n_theta=24, n_phi=48):
    u, wu = np.polynomial.legendre.leggauss(n_theta)
    phi = 2 * np.pi * np.arange(n_phi) / n_phi
    C, P = np.meshgrid(u, phi, indexing="ij")
    s = np.sqrt(1 - C**2)
    pts = radius * np.stack([s * np.cos(P), s * np.sin(P), C], -1).reshape(-1, 3)
    return pts, (radius**2 * np.outer(wu, np.full(n_phi, 2 * np.pi / n_phi))).ravel()


def test_bem_power_equals_far_field_intensity():
    """A sphere (258 vertices) vibrating in an asymmetric complex pattern at ka = 2: vᴴ R v
    equals ∫ |p|²/(2ρc) dS over an enclosing sphere of radius 100 m (kr = 200), p by the
    representation formula at the points, within 1 % (measured 1.4e-4)."""
    s = fa.sphere_surface(A, 3)
    x, y, z = s.vertices.T
    v = V0 * (1 + x + 0.5j * y * z - 0.3 * x * y)
    f = 2 * AIR.sound_speed / (2 * np.pi * A)
    Z = fa.bem_impedance(s, f)
    MZ = s.mass_matrix() @ Z
    W = float(ja.radiated_power(v, 0.25 * (MZ + MZ.conj().T)))
    pts, w = _sphere_quadrature(100.0)
    p = fa.bem_field_pressure(s, f, v, pts, impedance=Z)
    W_far = np.sum(w * np.abs(p) ** 2) / (2 * AIR.impedance)
    assert W_far == pytest.approx(W, rel=0.01)


def test_bem_against_rayleigh_on_a_thin_breathing_box():
    """A thin 1 m × 0.8 m box whose top and bottom faces vibrate in the plate's (1, 1) mode,
    mirror images of each other (sides still), radiates by symmetry as the top face would on a
    rigid baffle raised by half the thickness t: twice the baffled panel's power as t → 0. At
    ka = 1 the BEM's power is within 3 % of twice Rayleigh's at t = 0.1 m (measured -2.5 %),
    within 2 % at t = 0.05 m (-1.3 %), the gap closing linearly in t, and the extrapolation
    to t = 0 within 0.5 % (-0.2 %)."""
    a, b, f = 1.0, 0.8, AIR.sound_speed / (2 * np.pi)
    gaps = []
    for nx, ny, t in ((10, 8, 0.1), (20, 16, 0.05)):
        box = fa.box_surface(a, b, t, nx, ny, 1)
        x, y, z = box.vertices.T
        mode = np.sin(np.pi * x / a) * np.sin(np.pi * y / b)
        v = np.where(np.isclose(np.abs(z), t / 2), mode, 0.0) + 0j
        W = float(ja.radiated_power(v, fa.BEM().resistance(box, f, AIR)))
        plate = fa.rectangular_panel(a, b, nx, ny)  # the box's first vertices: its top face
        W_r = float(ja.radiated_power(v[: plate.n_vertices], fa.rayleigh_resistance(plate, f)))
        gaps.append(W / (2 * W_r) - 1)
    assert abs(gaps[0]) < 0.03 and abs(gaps[1]) < 0.02
    assert 1.5 < gaps[0] / gaps[1] < 2.5  # first order in t
    assert abs(2 * gaps[1] - gaps[0]) < 0.005


def test_field_transfer_against_bempp_and_the_pulsating_sphere(tmp_path):
    """The microphones' transfer T (fem_prep.acoustics.bem_field_transfer, 3-point quadrature
    in NumPy) against bempp-cl's potentials (bem_field_pressure) for a random velocity at points
    3 m off (within 0.5 %), and acoustic_outputs (method bem) on the pulsating sphere of 258
    vertices at ka = 1 with one grid frequency: W within 2.5 % of 1.304e-3 W (the mesh's -1.7 %)
    and the microphone at r = 3 m within 0.2 dB of
    |p| = ρc v₀ (a/r) ka / √(1 + (ka)²) (Kinsler et al. §7.1)."""
    from jaxgear.cli.run import acoustic_outputs

    s = fa.sphere_surface(A, 3)
    rng = np.random.default_rng(1)
    v = rng.normal(size=s.n_vertices) + 1j * rng.normal(size=s.n_vertices)
    pts = np.array([[3.0, 0.0, 0.0], [0.0, -2.0, 2.5], [1.0, 1.0, 3.0]])
    Z = fa.bem_impedance(s, F_KA1)
    ref = fa.bem_field_pressure(s, F_KA1, v, pts, impedance=Z)
    np.testing.assert_allclose(fa.bem_field_transfer(s, F_KA1, Z, pts) @ v, ref, rtol=5e-3)
    speed = 2 * np.pi * F_KA1  # order 1 at ka = 1
    vel = np.full((1, 1, s.n_vertices), V0 + 0j)
    table = {"method": "bem", "frequencies": 1, "cache": False,
             "microphones": [{"name": "r3", "position_mm": [0.0, 0.0, 3000.0]}]}
    sec = acoustic_outputs(s, vel, [speed], [1.0], str(tmp_path), table)
    assert sec["power_W"][0][0] == pytest.approx(_pulsating(1.0), rel=0.025)
    p = AIR.impedance * V0 * (A / 3.0) / np.sqrt(2.0)  # the peak amplitude at ka = 1
    Lp = 20 * np.log10(p / np.sqrt(2.0) / 20e-6)  # of the rms
    assert sec["microphones"]["r3"]["Lp_dB"][0][0] == pytest.approx(Lp, abs=0.2)
