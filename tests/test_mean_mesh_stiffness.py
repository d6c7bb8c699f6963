"""The mean mesh stiffness K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ (seed (2.34)) has one home,
:func:`jaxgear.dynamics.cell_stiffness`: the lumped model sums it over its mesh table, the hybrid
model's :func:`jaxgear.dynamics.mean_mesh_stiffness` over the cells' windows. On a lumped 3D pair
(a span of one mesh period) both must equal a plain NumPy sum over the quasi-static positions."""

import jax
import jax.numpy as jnp
import numpy as np
import pytest

import jaxgear as jg
import jaxgear.io as jio
from jaxgear.dynamics import dynamic_model, mean_mesh_stiffness, modal_analysis
from jaxgear.scenes import TorsionalDynamics

SPP = 8  # positions per mesh period


@pytest.fixture(scope="module")
def lumped():
    case = jio.load_case("accessory-spur")
    scene = TorsionalDynamics(
        case.mesh_model(slices=6), 1e-3, 4e-3, 1.0, 1.0, 1.0, 1.0, has_motor=False, has_load=False
    )
    return case, scene


def _cells_and_vectors(scene, theta):
    cells = scene.mesh.cells(theta)
    return cells, scene.cell_vectors(cells)


def _reference(scene, mods, torque):
    """⟨Σ_c k l V Vᵀ⟩ over the loaded cells (line load > 0) at θ_j = (j + ½) Δθ / SPP, written
    out cell by cell from the scene's structure vectors."""
    period = float(scene.mesh.mesh_period_angle)
    theta = (np.arange(SPP) + 0.5) * period / SPP
    qs = jg.quasi_static(scene, mods, torque, jnp.asarray(theta))
    line_load = np.asarray(qs.meshes[0].line_load)
    # one compiled program (an eager vmap compiles the cells' operations one by one)
    cells, V = jax.jit(jax.vmap(lambda t: _cells_and_vectors(scene, t)))(jnp.asarray(theta))
    V = np.asarray(V)  # (P, L, N, n)
    k, length, mask = (np.asarray(a) for a in (cells.stiffness, cells.length, cells.mask))
    n = V.shape[-1]
    K, kbar = np.zeros((n, n)), 0.0
    for j, a, b in zip(*np.nonzero(mask & (line_load > 0)), strict=True):
        kl = k[j, a, b] * length[j, a, b]
        K += kl * np.outer(V[j, a, b], V[j, a, b])
        kbar += kl
    return K / SPP, kbar / SPP


def test_one_mean_mesh_stiffness_for_the_lumped_and_the_hybrid_engines(lumped):
    case, scene = lumped
    torque = jnp.asarray(case.torque)
    K_ref, kbar_ref = _reference(scene, case.modifications, torque)
    K = np.asarray(mean_mesh_stiffness(scene, case.modifications, torque, SPP))
    scale = np.abs(K_ref).max()
    assert scale > 0
    np.testing.assert_allclose(K, K_ref, rtol=0, atol=1e-12 * scale)
    # the lumped engine's K̄_m (its modes' mesh stiffness) and its k̄ from its own mesh table
    model = dynamic_model(scene, case.modifications, torque, positions_per_pitch=SPP)
    assert float(model.mesh_stiffness_mean) == pytest.approx(kbar_ref, rel=1e-12)
    modes = modal_analysis(scene, jnp.asarray(K_ref))
    elastic = ~np.asarray(modes.rigid)
    np.testing.assert_allclose(
        np.asarray(model.modes.omega)[elastic], np.asarray(modes.omega)[elastic], rtol=1e-10
    )
