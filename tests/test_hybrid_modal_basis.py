"""Hybrid dynamics in the modal basis of the assembled structure: m modes of
(M, K + K̄) plus the static correction of the cells (docs/hybrid.md, "Modal basis"), on the
small test wheel. References: the cell-space Newmark of the same model (every coordinate) and
the quasi-static solution at a very low speed."""

from __future__ import annotations

import pathlib

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import fem_prep
import jaxgear as jg
from jaxgear import io as jio
from jaxgear.dynamics import (
    Batching,
    HybridModel,
    ModalBasis,
    Newmark,
    Outputs,
    SteadyState,
    dynamic_model,
    speed_sweep,
)
from jaxgear.io import Damping, build_dynamic_model, static_scene

DATA = pathlib.Path(__file__).parent / "data"


@pytest.fixture(scope="module")
def setup(fem_prep_cache):
    jax.config.update("jax_enable_x64", True)
    # the scene of tests/test_hybrid_dynamics.py (the theoretical path), whose runs' compiled
    # programs the cell-space references here read back
    case = jio.load_case(DATA / "hybrid-test-case.toml").replace(
        contact_geometry=jg.TheoreticalPath()
    )
    body = fem_prep.condensed(DATA / "hybrid-test-wheel.toml")
    return case, static_scene(case, bodies=(None, body))[0]


def _sweep(setup, speeds, basis, *, damping=None, spp=16, window=None, rotating_frame=False):
    """The sweep of the test scene at ``speeds`` (rad/s) in ``basis`` (None: cell space), by
    default with the settings of tests/test_hybrid_dynamics.py's runs of the same scene (its
    ``RUN``: Newmark 16, 3 periods with 1 kept, the states recorded) one speed per call, so that
    the cell-space reference is the program that module compiled (read back from the run's
    compilation cache)."""
    case, scene = setup
    window = SteadyState(3, 1) if window is None else window
    model = dynamic_model(
        scene, case.modifications, case.torque, damping, rotating_frame=rotating_frame
    )
    return speed_sweep(
        model,
        jnp.asarray(speeds),
        integrator=Newmark(spp, basis=basis),
        window=window,
        outputs=Outputs(states=True),
        batching=Batching(chunk_size=1),
    ).results


@pytest.mark.parametrize(
    "damping",
    [
        pytest.param(None, id="rayleigh"),
        pytest.param(Damping("modal", ratio=0.05), id="modal", marks=pytest.mark.slow),
        pytest.param(Damping("composite"), id="composite", marks=pytest.mark.slow),
        pytest.param("rotating", id="rayleigh-rotating-frame", marks=pytest.mark.slow),
    ],
)
def test_all_modes_is_the_cell_space_result(setup, damping):
    """With every mode kept (D = Φ, no residual) the modal-basis Newmark is the cell-space one
    written in modal coordinates: the same mesh forces, TE and bearing forces to round-off, for
    the three damping models (Rayleigh's mesh share on the window's coordinates, the
    composite's through its map on the modal coordinates, modal without a mesh share), and with
    the turning frames' terms (the reduction per speed). An independent check of the transformation, the start state and the damping's mapping."""
    n = setup[1].structure.K.shape[0]
    speeds = [700.0, 2500.0]
    rot = isinstance(damping, str)  # the turning frames' terms: the reduction per speed
    damping = None if rot else damping
    ref = _sweep(setup, speeds, None, damping=damping, rotating_frame=rot)
    r = _sweep(setup, speeds, ModalBasis(n), damping=damping, rotating_frame=rot)
    assert np.all(np.asarray(r.result) == 0)
    fm = np.asarray(ref.mesh_force)
    np.testing.assert_allclose(np.asarray(r.mesh_force), fm, rtol=0, atol=1e-9 * fm.max())
    te = np.asarray(ref.transmission_error)
    np.testing.assert_allclose(
        np.asarray(r.transmission_error), te, rtol=0, atol=1e-9 * np.abs(te).max()
    )
    bf = np.asarray(ref.bearing_force)
    np.testing.assert_allclose(
        np.asarray(r.bearing_force), bf, rtol=0, atol=1e-9 * np.abs(bf).max()
    )
    X = np.asarray(ref.final_state[0])
    np.testing.assert_allclose(np.asarray(r.final_state[0]), X, rtol=0, atol=1e-9 * np.abs(X).max())


@pytest.mark.slow
def test_dynamic_factor_converges_with_the_modes(setup):
    """The dynamic factor against m (of n = 341), Rayleigh damping, 32 steps per period, at
    900 and 2500 rad/s (the mesh frequency 2.9 and 8 kHz, the 20th mode 8.7 kHz): the largest
    relative error falls with m. Measured (nodal rim masters): 3.9 % (m = 20), 1.4 % (60),
    0.02 % (200); without the static correction m = 20 is 13 % off."""
    speeds = [900.0, 2500.0]
    window = SteadyState(10, 2)
    ref = np.asarray(_sweep(setup, speeds, None, spp=32, window=window).dynamic_factor)
    err = {}
    for m in (20, 60, 200):
        r = _sweep(setup, speeds, ModalBasis(m), spp=32, window=window)
        assert np.all(np.asarray(r.result) == 0)
        err[m] = float(np.max(np.abs(np.asarray(r.dynamic_factor) / ref - 1)))
    assert err[20] > err[60] > err[200]
    assert err[60] < 0.03
    assert err[200] < 3e-3
    r = _sweep(setup, speeds, ModalBasis(20, static_correction=False), spp=32, window=window)
    bare = float(np.max(np.abs(np.asarray(r.dynamic_factor) / ref - 1)))
    assert bare > 1.5 * err[20]


# default tier: test_all_modes_is_the_cell_space_result[rayleigh] (the modal-basis Newmark) and test_the_static_correction_keeps_the_static_flexibility (ten modes with the correction keep the static TE compliance)
@pytest.mark.slow
def test_quasi_static_limit_with_few_modes(setup):
    """At 2 rad/s (mesh frequency 6 Hz, far below the modes) ten modes with the static
    correction follow the quasi-static TE and mesh force, as the cell space does: the static
    correction keeps the structure's static flexibility exact (docs/hybrid.md, "Modal
    basis"); that the ten modes alone (no correction) miss the contact's compliance is
    test_the_static_correction_keeps_the_static_flexibility's (and, in the Newmark, the slow
    test_quasi_static_limit_needs_the_static_correction's)."""
    case, scene = setup
    speed = 2.0
    window = SteadyState(3, 1)
    r = _sweep(setup, [speed], ModalBasis(10), window=window)
    th = np.asarray(r.theta)[0]
    qs = jg.quasi_static(scene, case.modifications, case.torque, jnp.asarray(th), speed=speed)
    te_qs = np.asarray(qs.transmission_error)
    f_qs = np.sum(
        np.asarray(qs.line_load) * np.asarray(scene.mesh.cells(0.0).length)[None], axis=(1, 2)
    )
    fs = float(np.asarray(r.static_force)[0])
    np.testing.assert_allclose(np.asarray(r.mesh_force)[0], f_qs, atol=5e-3 * fs)
    te = np.asarray(r.transmission_error)[0]
    np.testing.assert_allclose(te, te_qs, atol=1e-2 * te_qs.mean())


@pytest.mark.slow
def test_quasi_static_limit_needs_the_static_correction(setup):
    """(Slow: a Newmark program of its own. The default test of the same claim on the basis
    itself: test_the_static_correction_keeps_the_static_flexibility.) At 2 rad/s the ten modes
    alone (no static correction) miss the quasi-static TE by more than 10 % of its mean: the
    contact's compliance needs the correction."""
    case, scene = setup
    speed = 2.0
    bare = _sweep(setup, [speed], ModalBasis(10, static_correction=False))
    th = np.asarray(bare.theta)[0]
    qs = jg.quasi_static(scene, case.modifications, case.torque, jnp.asarray(th), speed=speed)
    te_qs = np.asarray(qs.transmission_error)
    te_bare = np.asarray(bare.transmission_error)[0]
    assert np.max(np.abs(te_bare - te_qs)) > 0.1 * te_qs.mean()


def test_the_static_correction_keeps_the_static_flexibility(setup):
    """The basis itself (:func:`jaxgear.dynamics._modal_basis.modal_space_of`) on the test
    structure held by a mesh spring, K_h = K + k u uᵀ (u the TE vector, k = 1e8 N/m), its basis
    built for K_h: the static response X = D q + G f to a unit load f = u (q from
    Dᵀ K_h D q = Dᵀ f) gives the TE compliance uᵀ X
    of the full structure (a least-squares solve on all 341 coordinates; the common rotation
    is free and u is orthogonal to it) to 1e-9 with the static correction, while the ten modes
    alone (D = T, G = 0) miss it by more than 5 % (measured 12.6 %): the statics of
    test_quasi_static_limit_with_few_modes's claim, without a Newmark program."""
    from jaxgear.dynamics._modal_basis import modal_space_of

    scene = setup[1]
    K, M = np.asarray(scene.structure.K), np.asarray(scene.structure.M)
    u = np.asarray(scene.te_vector(), dtype=float)
    Kh = K + 1e8 * np.outer(u, u)
    exact = float(u @ np.linalg.lstsq(Kh, u, rcond=None)[0])
    space_of = jax.jit(modal_space_of, static_argnums=(3, 4), static_argnames="static")
    miss = {}
    for static in (True, False):
        _, _, D, G = (
            np.asarray(a) for a in space_of(Kh, M, np.zeros_like(Kh), 10, 1, static=static)
        )
        q = np.linalg.lstsq(D.T @ Kh @ D, D.T @ u, rcond=None)[0]
        miss[static] = abs(float(u @ (D @ q + G @ u)) / exact - 1.0)
    assert miss[True] < 1e-9 and miss[False] > 0.05, miss


def test_bad_settings(setup):
    """One-line ValueErrors, before any work."""
    n = setup[1].structure.K.shape[0]
    for bad in (0, -3, 2.5, "60", None):
        with pytest.raises(ValueError, match="modes"):
            ModalBasis(bad)
    with pytest.raises(ValueError, match="speed"):
        ModalBasis(10, speed=-1.0)
    with pytest.raises(ValueError, match="basis"):
        Newmark(16, basis=40)
    with pytest.raises(ValueError, match=rf"allowed 1 … {n}"):
        _sweep(setup, [100.0], ModalBasis(n + 1))
    lumped_case = jio.load_case(DATA.parents[1] / "examples" / "accessory-lumped3d.toml")
    lumped = build_dynamic_model(lumped_case)[0]
    assert not isinstance(lumped, HybridModel)
    with pytest.raises(ValueError, match="modal basis is for a hybrid model"):
        speed_sweep(lumped, jnp.asarray([100.0]), integrator=Newmark(16, basis=ModalBasis(4)))


def test_case_key():
    """``[scene.integration] modal_basis = m`` reaches the integrator; bad values are one-line
    errors naming the key and the allowed range."""
    from jaxgear.io import parse_scene, spec_integrator

    shaft = {
        "length_mm": 80.0,
        "diameter_mm": 25.0,
        "gear_position_mm": 40.0,
        "torque_position_mm": 0.0,
        "bearings": [
            {"position_mm": 0.0, "radial_N_per_um": 200.0, "axial_N_per_um": 100.0},
            {"position_mm": 80.0, "radial_N_per_um": 200.0},
        ],
    }
    base = {"model": "lumped3d", "pinion_shaft": shaft, "gear_shaft": shaft}
    hybrid = {**base, "gear_body": {"body": "accessory-wheel"}}
    it = spec_integrator(parse_scene({**hybrid, "integration": {"modal_basis": 60}}))
    assert it == Newmark(None, basis=ModalBasis(60))
    assert spec_integrator(parse_scene({**hybrid, "integration": {"modal_basis": False}})) == (
        Newmark(None)
    )
    for bad, why in ((0, r"allowed \[1, 1e\+06\]"), (2.5, "integer"), (True, "integer")):
        with pytest.raises(ValueError, match=rf"\[scene.integration\] modal_basis = .*{why}"):
            parse_scene({**hybrid, "integration": {"modal_basis": bad}})
    with pytest.raises(ValueError, match="modal_basis .* condensed body"):
        parse_scene({**base, "integration": {"modal_basis": 60}})
    with pytest.raises(ValueError, match="modal_basis .* solver = 'newmark'"):
        parse_scene({**hybrid, "integration": {"modal_basis": 60, "solver": "tsit5"}})
