"""The window compliance of a hybrid scene: the parts of its cell-space contact problem that
depend on the scene and the position only, cached once per scene and reused by every solve at
those positions (docs/hybrid.md, "Statics in the cell space"; :mod:`jaxgear._cell_factor`).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from .._cell_factor import line_factors

__all__ = ["WindowCompliance", "window_compliance"]


class WindowCompliance(eqx.Module):
    """The parts of the cell-space contact problem that depend on the scene and the position
    only, at P positions (:func:`window_compliance`): not on the modifications, the torque, the
    speed or the contact law, so a map, a torque sweep or an optimisation reuses them
    (docs/hybrid.md, "Statics in the cell space"). A quasi-static solve at these positions
    reads one slice per position (the leading axis P; a slice has ``theta`` of shape ()).

    Attributes:
        theta: the scene angles (rad), (P,). idx: each position's window W (P, w).
        V: the structure vectors on it (P, c, w). C: V_W G_WW V_Wᵀ (m/N), (P, c, c).
        E: V_W N_W, (P, c, r). a_torque, a_centrifugal: V_W x_W of the unit torque and of the
            unit speed² centrifugal load (m), (P, c).
        kl: k l of each cell (N/m), zero off the flanks, (P, c). mask: cells on the flanks,
            (P, c).
        B: (I + S C S)⁻¹ with S = diag √(k l) (every cell on the flanks in contact; identity
            off them), (P, c, c): the exact law's first active-set pass is a product with it and
            a later one a Schur complement on it (:mod:`jaxgear._cell_factor`).
        te_rows: V_W (G u)_W of each mesh's TE vector u (m/N), (P, meshes, c): u·X =
            u·G F − te_rows·P + (u·N) α without recovering X.
        lines: each contact line's cells (P, G, g) (G lines of all meshes, g the most slices;
            padding c). K_line: B_:D (B_DD)⁻¹ for D each line's cells on the flanks
            (P, G, c, g): a pass with one whole line out of contact is then products only.
            YF: the solution for the rigid-body columns S E on the full set and with each line
            out, (P, 1 + G, c, r).
    """

    theta: Float[Array, " P"]
    idx: Int[Array, "P w"]
    V: Float[Array, "P c w"]
    C: Float[Array, "P c c"]
    E: Float[Array, "P c r"]
    a_torque: Float[Array, "P c"]
    a_centrifugal: Float[Array, "P c"]
    kl: Float[Array, "P c"]
    mask: Bool[Array, "P c"]
    B: Float[Array, "P c c"]
    te_rows: Float[Array, "P m c"]
    lines: Int[Array, "P G g"]
    K_line: Float[Array, "P G c g"]
    YF: Float[Array, "P G1 c r"]


def _flat(parts):
    """Every mesh's cell array, mesh after mesh (:meth:`CellRow.concat`'s order)."""
    return jnp.concatenate([x.reshape(-1) for x in parts])


def window_compliance(scene, theta) -> WindowCompliance:
    """The position-only parts of the cell-space contact problem of the hybrid scene ``scene``
    (:class:`~jaxgear.scenes.HybridScene`, without a cache) at the scene
    angles ``theta`` (rad), (P,): the windows, structure vectors, C = V_W G_WW V_Wᵀ, E = V_W N_W,
    the free gaps of the unit loads, k l and the mask, the inverse B of the full contact set and
    the TE rows (:class:`WindowCompliance`), vmapped over the positions. Memory:
    P (2 c² + G c g + c w + (2 + G) c r + (4 + meshes) c) floats. One compiled program per
    scene and number of positions."""
    return _window_compliance(scene, jnp.asarray(theta, scene.structure.K.dtype))


@eqx.filter_jit
def _window_compliance(scene, theta) -> WindowCompliance:
    Gu = scene.te_vectors() @ scene.G  # (meshes, n): G symmetric, (G u)ᵀ

    def one(th):
        cells = scene.mesh_cells(th)
        r = scene.window_row(cells, tuple(jnp.zeros_like(c.s) for c in cells))
        Gw = scene.G[r.idx[:, None], r.idx[None, :]]
        C = r.V @ Gw @ r.V.T
        kl = jnp.where(r.mask, r.k * r.length, 0.0)
        s = jnp.sqrt(kl)
        A = jnp.eye(C.shape[0], dtype=C.dtype) + s[:, None] * C * s[None, :]
        B = jax.scipy.linalg.cho_solve(jax.scipy.linalg.cho_factor(A), jnp.eye(A.shape[0]))
        return (
            r.idx,
            r.V,
            C,
            r.V @ scene.N[r.idx],
            r.V @ scene.x_torque[r.idx],
            r.V @ scene.x_centrifugal[r.idx],
            kl,
            r.mask,
            0.5 * (B + B.T),
            Gu[:, r.idx] @ r.V.T,
        )

    parts = jax.vmap(one)(theta)
    # the contact lines: each mesh's (n_lines, n_slices) cells, flattened mesh after mesh
    shapes = [c.mask.shape for c in jax.eval_shape(scene.mesh_cells, theta[0])]
    c_all = sum(n * m for n, m in shapes)
    g = max(m for _, m in shapes)
    rows, start = [], 0
    for n, m in shapes:
        for j in range(n):
            rows.append(list(range(start + j * m, start + (j + 1) * m)) + [c_all] * (g - m))
        start += n * m
    lines = jnp.broadcast_to(jnp.asarray(rows, jnp.int32), (theta.shape[0], len(rows), g))
    K_line, YF = jax.vmap(line_factors)(parts[8], parts[3], parts[6], parts[7], lines)
    return WindowCompliance(theta, *parts, lines, K_line, YF)
