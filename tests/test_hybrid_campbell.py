"""The modes of a spinning hybrid structure against speed (spin softening and centrifugal stress
stiffening of the condensed bodies) and the Campbell coincidences they give.

References: SciPy's generalized symmetric eigensolver on the full (M, K + K̄_m + Ω² S) at each
speed (not the Rayleigh-Ritz basis of the code), closed-form crossings of Southwell curves
√(ω₀² + s Ω²) with an order line, and a two-mode system whose modes cross."""

from __future__ import annotations

import math
import pathlib
from types import SimpleNamespace

import jax
import jax.numpy as jnp
import numpy as np
import pytest
import scipy.linalg as sla

import fem_prep
from jaxgear import io as jio
from jaxgear.dynamics import (
    campbell_coincidences,
    modal_analysis,
    modes_at_speed,
    nodal_diameter_resonances,
)
from jaxgear.io import static_scene

jax.config.update("jax_enable_x64", True)

DATA = pathlib.Path(__file__).parent / "data"
TOP = 12000.0  # pinion speed (rad/s): the test wheel turns at 8000 rad/s, its modes move by 5 %


@pytest.fixture(scope="module")
def spinning(fem_prep_cache):
    """The hybrid test pair (condensed 30-tooth wheel) with a rank-one mesh stiffness k u uᵀ,
    its modes at rest and on a grid of speeds up to TOP."""
    case = jio.load_case(DATA / "hybrid-test-case.toml")
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    scene = static_scene(case, bodies=(None, body))[0]
    u = np.asarray(scene.te_vector(), dtype=float)
    Km = 1e8 * np.outer(u, u)
    modes = modal_analysis(scene, jnp.asarray(Km))
    at = modes_at_speed(scene, modes, np.linspace(0.0, TOP, 25))
    return scene, Km, modes, at


def _exact(scene, Km, speed, k=16):
    """The k lowest elastic angular frequencies of (M, K + K̄_m + Ω² S), SciPy."""
    K = np.asarray(scene.structure.K) + Km
    S = np.asarray(scene.structure.spin_stiffness)
    lam = sla.eigh(K + speed**2 * S, np.asarray(scene.structure.M), eigvals_only=True)
    lam = lam[lam > 1e-9 * lam.max()]
    return np.sqrt(lam[:k])


def test_modes_at_speed_equal_the_eigen_solution_at_each_speed(spinning):
    """At rest and at three speeds of the grid, the followed modes (sorted) equal SciPy's
    eigenvalues of the full stiffness at speed: the Ritz basis of the 60 lowest modes at rest
    holds the modes at speed to 1e-4 (``error`` at the top speed: 1.9e-5); the modes do move
    (the lowest web pair by −5.2 % at TOP, spin softening winning), and ``shift`` says so."""
    scene, Km, modes, at = spinning
    rigid = np.asarray(modes.rigid)
    om = np.asarray(at.omega)[:, ~rigid]
    for k in (0, 8, 16, 24):
        w = float(at.speeds[k])
        ref = _exact(scene, Km, w)
        np.testing.assert_allclose(np.sort(om[k])[: ref.size], ref, rtol=1e-4)
    moved = np.abs(np.sort(om[-1])[:16] / np.sort(om[0])[:16] - 1)
    assert moved.max() > 0.03, moved
    assert at.error < 1e-4 and at.shift == pytest.approx(moved.max(), rel=1e-3, abs=1e-4)


def test_a_campbell_crossing_is_an_eigenvalue_at_its_speed(spinning):
    """A coincidence of the modes at speed with an order line, Ω*, is a natural frequency of
    the structure at Ω*: SciPy's spectrum at Ω* holds h z Ω* to 0.1 % (linear interpolation
    between grid speeds; the curves are smooth)."""
    scene, Km, _, at = spinning
    omega = np.asarray(at.omega)
    share = np.ones(omega.shape[1])  # every mode counts
    order = 2 * math.pi * 600.0 / 2000.0 * 10  # an order that meets several modes below TOP
    rows = campbell_coincidences(
        omega, share, order, TOP / 1.05, harmonics=(1,), min_share=0.0, speeds=at.speeds
    )
    rows = [r for r in rows if r["speed_rad_s"] < TOP and r["frequency_Hz"] < 2e4][:6]
    assert len(rows) >= 3, rows
    for r in rows:
        ref = _exact(scene, Km, r["speed_rad_s"], k=40) / (2 * math.pi)
        f = r["frequency_Hz"]
        assert np.min(np.abs(ref / f - 1)) < 1e-3, (r, ref)
        assert f == pytest.approx(order * r["speed_rad_s"] / (2 * math.pi), rel=1e-12)


def test_crossings_of_southwell_curves_by_hand():
    """Curves ω(Ω) = √(ω₀² + s Ω²) on a grid of 201 speeds meet the order line r Ω at
    Ω = ω₀/√(r² − s) (closed form) to 1e-4; a mode that outruns the order (r² <= s) never
    does; without a grid the frequencies are constant (Ω = ω₀/(h z), exactly). The (3.9)
    resonances follow the same rule with r = (h Z ± n) z1/Z."""
    grid = np.linspace(0.0, 400.0, 201)
    w0 = np.array([0.0, 1000.0, 2000.0, 1500.0])
    s = np.array([0.0, 4.0, -3.0, 120.0])
    curves = np.sqrt(w0[None] ** 2 + s[None] * grid[:, None] ** 2)
    share = np.array([0.0, 0.5, 0.5, 0.5])
    rows = campbell_coincidences(curves, share, 10.0, 380.0, harmonics=(1, 2), speeds=grid)
    got = {(r["mode"], r["harmonic"]): r["speed_rad_s"] for r in rows}
    for (i, h), speed in got.items():
        assert speed == pytest.approx(w0[i] / math.sqrt((10.0 * h) ** 2 - s[i]), rel=1e-4)
    # mode 3 outruns H1 (s = 120 > 10²) and meets H2 (20² > 120); rigid mode 0 never counts
    assert set(got) == {(1, 1), (1, 2), (2, 1), (2, 2), (3, 2)}
    assert campbell_coincidences(w0, share, 10.0, 380.0, harmonics=(1,))[0]["speed_rad_s"] == 100.0
    # (3.9): Z = 30, z1 = 20, n = 2, h = 1: orders 32 (backward) and 28 (forward) of the wheel
    f = curves / (2 * math.pi)
    nd = nodal_diameter_resonances(f[:, 1:2], [2], 30, 20, speeds=grid)
    for r in nd:
        rate = r["order"] * 20 / 30
        assert r["pinion_speed_rad_s"] == pytest.approx(1000.0 / math.sqrt(rate**2 - 4.0), rel=1e-4)
        assert r["frequency_hz"] == pytest.approx(rate * r["pinion_speed_rad_s"] / (2 * math.pi))
        assert r["frequency_rest_hz"] == pytest.approx(1000.0 / (2 * math.pi))


def test_modes_cross_rather_than_swap():
    """Two uncoupled modes, ω₁² = 1 + 3 Ω² (stiffening) and ω₂² = 4, cross at Ω = 1: each
    column keeps its mode past the crossing (sorting would swap them), and the mesh energy
    share stays with its mode."""
    M = jnp.eye(2)
    K = jnp.diag(jnp.array([1.0, 4.0]))
    Km = jnp.diag(jnp.array([0.5, 0.0]))  # the mesh strains mode 1 only
    scene = SimpleNamespace(
        mass=lambda: M,
        stiffness_parts=lambda: {"structure": K - Km},
        structure=SimpleNamespace(spin_stiffness=jnp.diag(jnp.array([3.0, 0.0]))),
    )
    modes = modal_analysis(scene, Km)
    grid = np.linspace(0.0, 2.0, 21)
    at = modes_at_speed(scene, modes, grid, n_check=2)
    om = np.asarray(at.omega)
    np.testing.assert_allclose(om[:, 0], np.sqrt(1 + 3 * grid**2), rtol=1e-12)
    np.testing.assert_allclose(om[:, 1], 2.0, rtol=1e-12)
    np.testing.assert_allclose(np.asarray(at.mesh_energy)[:, 0], 0.5 / (1 + 3 * grid**2))
    np.testing.assert_allclose(np.asarray(at.mesh_energy)[:, 1], 0.0, atol=1e-15)
