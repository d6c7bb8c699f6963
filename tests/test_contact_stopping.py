"""Stopping rules of the contact solvers: never a silent success at the cap.

* A solve stopped by ``max_iterations`` before its criterion returns
  ``ContactResult.max_iterations`` (and raises with ``throw=True``), smooth and exact, direct and
  compliance (cell-space) forms.
* A 14 mm module helical pair with ``iso6336`` stiffness at 400 slices: the old relative-step
  rule (|dx| <= 8 ε |x|) could not be met there (the step stalls at round-off) and Newton ran to
  its cap of 100 steps at a quarter of the positions with result 0; the scaled-residual rule
  converges in a few steps.
* Independent reference: on the rigid mesh the smooth problem is one monotone scalar equation
  Σ_c k_c l_c w softplus((x − δ0_c)/w) = F_n, solved here by bracketing (scipy brentq) in NumPy,
  with the cell data of the case; the solver's approach x must match it to round-off (float64)
  and to single precision (float32).
"""

import importlib.resources

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import pytest
from scipy.optimize import brentq

import jaxgear as jg
import jaxgear.dynamics
import jaxgear.io as jio
from jaxgear import ContactResult, separation
from jaxgear.cli import scene_outputs
from jaxgear.io import static_scene

WIDTH = 1e-7  # smoothing width (m)


def _big_helical(tmp_path, slices: int):
    """power-helical scaled to a 14 mm normal module (face width 224 mm), iso6336 stiffness,
    ``slices`` slices, no modification."""
    text = (importlib.resources.files("jaxgear") / "cases" / "power-helical.toml").read_text()
    for old, new in (
        ("normal_module_mm = 2.5", "normal_module_mm = 14.0"),
        ("face_width_mm = 40.0", "face_width_mm = 224.0"),
        ('stiffness = "weber"', 'stiffness = "iso6336"'),
        ("slices = 40", f"slices = {slices}"),
        ('tip_relief = { depth_um = 10.0, extent = 0.2, shape = "linear" }', ""),
        ("crowning = { depth_um = 5.0 }", ""),
    ):
        assert old in text
        text = text.replace(old, new)
    path = tmp_path / f"big-helical-{slices}.toml"
    path.write_text(text)
    case = jio.load_case(path)
    return case, case.mesh_model()


def _reference_approach(mesh, theta, torque, width, dtype=np.float64):
    """Root x (m) of Σ k l w softplus((x − δ0)/w) = F_n by brentq, in NumPy."""
    cells, _, delta0 = separation(mesh, jg.Modifications(), theta)
    mask = np.asarray(cells.mask).reshape(-1)
    kl = (np.asarray(cells.stiffness) * np.asarray(cells.length)).reshape(-1)[mask]
    d0 = np.asarray(delta0).reshape(-1)[mask].astype(np.float64)
    fn = float(mesh.normal_load(torque))

    def f(x):
        return np.sum(kl * width * np.logaddexp(0.0, (x - d0) / width)) - fn

    hi = fn / kl.sum() + d0.max() + 10 * width
    return brentq(f, d0.min() - 50 * width, hi, xtol=1e-22, rtol=4 * np.finfo(float).eps)


def test_smooth_quasi_static_at_its_cap_returns_the_failure_code(tmp_path):
    """One Newton step cannot meet the tolerance (ρ ~ 1e-5 after it): code 1 at every position,
    never 0; the active set (all cells in contact, unmodified flanks) converged in its one pass,
    so the code is the Newton's."""
    case, mesh = _big_helical(tmp_path, 40)
    # the premise (every cell in contact in one pass) is the theoretical path's: no corner cells
    mesh = mesh.with_contact_geometry(jg.TheoreticalPath())
    exact = jg.quasi_static(
        mesh, None, case.torque, positions_per_pitch=8, contact=jg.ExactContact(1)
    )
    assert np.all(np.asarray(exact.result) == 0)
    res = jg.quasi_static(
        mesh,
        None,
        case.torque,
        contact=jg.SmoothContact(WIDTH, max_iterations=1),
        positions_per_pitch=8,
        throw=False,
    )
    assert np.all(np.asarray(res.result) == ContactResult.max_iterations)
    with pytest.raises(eqx.EquinoxRuntimeError, match="did not converge at max_iterations"):
        jg.quasi_static(
            mesh,
            None,
            case.torque,
            contact=jg.SmoothContact(WIDTH, max_iterations=1),
            positions_per_pitch=8,
        )


def test_exact_quasi_static_at_its_cap_returns_the_failure_code():
    """power-helical with tip relief and crowning needs up to 3 active-set passes."""
    case = jio.load_case("power-helical")
    mesh = case.mesh_model(slices=8)
    full = jg.quasi_static(mesh, case.modifications, case.torque, positions_per_pitch=8)
    passes = np.asarray(full.iterations)
    assert np.any(passes >= 2)
    res = jg.quasi_static(
        mesh,
        case.modifications,
        case.torque,
        positions_per_pitch=8,
        contact=jg.ExactContact(1),
        throw=False,
    )
    # capped where the set changed in its first pass, converged where one pass was enough
    expected = np.where(passes >= 2, int(ContactResult.max_iterations), 0)
    np.testing.assert_array_equal(np.asarray(res.result), expected)


def _cell_problem(dtype):
    """The rigid mesh in the space of the cells: C = 0, E = 1 (one rigid mode, the approach α),
    a = −δ0, b = F_n: Δ_c = α − δ0_c and Σ k l φ_w(Δ) = F_n."""
    rng = np.random.default_rng(18)
    c = 200
    d0 = rng.uniform(0.0, 2e-6, c)
    kl = np.full(c, 1.3e10 * 1e-3)  # k = 13 N/(mm·µm), l = 1 mm
    fn = 2e3
    args = (
        jnp.zeros((c, c), dtype),
        jnp.asarray(-d0, dtype),
        jnp.ones((c, 1), dtype),
        jnp.asarray([fn], dtype),
        jnp.asarray(kl / 1e-3, dtype),
        jnp.full(c, 1e-3, dtype),
        jnp.ones(c, bool),
    )

    def f(x):
        return np.sum(kl * WIDTH * np.logaddexp(0.0, (x - d0) / WIDTH)) - fn

    ref = brentq(f, 0.0, 1e-4, xtol=1e-22, rtol=4 * np.finfo(float).eps)
    return args, ref


@pytest.mark.parametrize("dtype, rtol", [(jnp.float64, 1e-12), (jnp.float32, 1e-5)])
def test_cell_space_smooth_matches_brentq_and_flags_its_cap(dtype, rtol):
    args, ref = _cell_problem(dtype)
    sol, force, alpha = jg.solve_contact_cells(*args, jg.SmoothContact(WIDTH))
    assert alpha.dtype == dtype
    assert int(sol.result) == 0
    assert int(sol.iterations) <= 20
    assert float(alpha[0]) == pytest.approx(ref, rel=rtol)
    assert float(jnp.sum(force)) == pytest.approx(2e3, rel=rtol)
    capped, _, _ = jg.solve_contact_cells(*args, jg.SmoothContact(WIDTH, 1))
    assert int(capped.result) == ContactResult.max_iterations


def test_400_slices_iso6336_converges_in_few_steps_and_matches_brentq(tmp_path):
    """34 of 128 positions used to stop at 101 iterations with result 0 here."""
    case, mesh = _big_helical(tmp_path, 400)
    # the reference's balance takes every cell's vector as 1 (the line of action) and the
    # premise (every cell in contact in one pass) is the theoretical path's: no corner cells
    mesh = mesh.with_contact_geometry(jg.TheoreticalPath())
    theta = jg.mesh_positions(mesh, 16)
    res = jg.quasi_static(
        mesh, None, case.torque, theta, contact=jg.SmoothContact(WIDTH), throw=False
    )
    assert np.all(np.asarray(res.result) == 0)
    # 1 active-set pass (all cells in contact) + Newton's 2-4 steps
    assert int(np.max(np.asarray(res.iterations))) <= 6
    x = np.asarray(res.x)[:, 0]
    for i in range(0, theta.shape[0], 3):
        ref = _reference_approach(mesh, theta[i], case.torque, WIDTH)
        assert x[i] == pytest.approx(ref, rel=1e-12, abs=0)


def test_400_slices_float32_runs_and_converges(tmp_path):
    """float32 at 400 slices: the tolerance comes from the dtype's ε (not float64's)."""
    case, mesh = _big_helical(tmp_path, 400)
    cells, _, delta0 = separation(mesh, jg.Modifications(), jnp.asarray(0.01))
    f32 = jnp.float32
    n = cells.s.size
    sol = jg.solve_contact(
        jnp.zeros((1, 1), f32),
        jnp.asarray([mesh.normal_load(case.torque)], f32),
        jnp.ones((n, 1), f32),
        cells.stiffness.reshape(-1).astype(f32),
        cells.length.reshape(-1).astype(f32),
        delta0.reshape(-1).astype(f32),
        cells.mask.reshape(-1),
        jg.SmoothContact(jnp.asarray(WIDTH, f32)),
    )
    assert sol.x.dtype == f32
    assert int(sol.result) == 0
    assert int(sol.iterations) <= 10
    ref = _reference_approach(mesh, jnp.asarray(0.01), case.torque, WIDTH)
    assert float(sol.x[0]) == pytest.approx(ref, rel=1e-5)


def test_scene_outputs_run_at_the_case_slices(tmp_path, monkeypatch):
    """``jaxgear run``'s scene solve (load maps of a hybrid case, lumped 3D TE) uses the case's
    ``[mesh] slices`` (it ran at min(slices, 8) without saying so) and records them."""
    case = jio.load_case("accessory-spur").replace(slices=12)
    used = []

    def spy(*args, **kw):
        scene, bodies = static_scene(*args, **kw)
        used.append(int(scene.mesh.n_slices))
        return scene, bodies

    monkeypatch.setattr(jio, "static_scene", spy)
    out = scene_outputs(case, str(tmp_path))
    assert used == [12]
    assert out["slices"] == 12
