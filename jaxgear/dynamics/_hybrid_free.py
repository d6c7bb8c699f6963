"""Free vibration of the hybrid scene about its loaded equilibrium at a fixed mesh position
(:func:`hybrid_free_vibration`): the energy check of the hybrid Newmark."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Float, Int

from .._contact import ExactContact
from .._modifications import Modifications
from .._quasi_static import per_mesh_modifications, quasi_static, separation
from .._util import check_integer
from ..scenes import HybridPair
from ._hybrid_mesh import (
    CellSystem,
    SceneCells,
    _newmark_cells,
    _reference_shift,
    _references,
)

__all__ = ["FreeVibration", "hybrid_free_vibration"]


class FreeVibration(eqx.Module):
    """Free vibration of the hybrid scene about its loaded equilibrium at a fixed mesh position.

    Attributes:
        time: (S,) (s). x: coordinates (S, n). mesh_force: Σ of the cell forces (N), (S,).
        energy: kinetic + strain energy of the vibration about the static equilibrium, over
            the cells in contact there, ½ẊᵀMẊ + ½(X − X_s)ᵀ(K + K_c)(X − X_s) (J), (S,).
        contact_held: True while every cell loaded at equilibrium stays loaded and no other
            cell closes (the system is then linear and the energy a constant of the motion).
        result: as :class:`~jaxgear.dynamics.DynamicResponse`.
    """

    time: Float[Array, " S"]
    x: Float[Array, "S n"]
    mesh_force: Float[Array, " S"]
    energy: Float[Array, " S"]
    contact_held: Array
    result: Int[Array, ""]


def hybrid_free_vibration(
    scene: HybridPair,
    modifications: Modifications | None,
    torque,
    theta,
    velocity,
    time_step,
    n_steps: int,
    *,
    steps_per_period: int = 64,
) -> FreeVibration:
    """Newmark of the undamped hybrid scene with the mesh held at pinion angle ``theta`` (rad):
    the static equilibrium under ``torque`` (N·m) there, set moving with the initial
    ``velocity`` Ẋ(0) (n,) (m/s, rad/s), integrated ``n_steps`` steps of ``time_step`` (s) by
    the cell-space step of a hybrid model's :func:`jaxgear.dynamics.speed_sweep` (same contact
    loop and flank reference, from the quasi-static positions of ``steps_per_period`` steps; no
    centrifugal load, C = 0).

    With the contact held (small ``velocity``) the system is linear and time-invariant and the
    average-acceleration scheme conserves the vibration energy exactly: the energy check of the
    hybrid Newmark.

    Raises:
        ValueError: ``n_steps`` < 1, ``time_step`` <= 0, a ``velocity`` of the wrong shape, or
            a scene of several meshes (this check handles one).
    """
    _ = scene.mesh  # one mesh: a one-line error else, before any computation
    dtype = scene.structure.K.dtype
    n = scene.structure.K.shape[0]
    velocity = jnp.asarray(velocity, dtype)
    if velocity.shape != (n,):
        raise ValueError(f"velocity has shape {velocity.shape}: allowed ({n},)")
    if int(n_steps) != n_steps or n_steps < 1:
        raise ValueError(f"n_steps = {n_steps!r} is out of range: allowed an integer >= 1")
    if not float(time_step) > 0:
        raise ValueError(f"time_step = {time_step!r} s is out of range: allowed > 0")
    check_integer("steps_per_period", steps_per_period, 4)
    mods = Modifications() if modifications is None else modifications
    return _free(
        scene,
        mods,
        jnp.asarray(torque, dtype),
        jnp.asarray(theta, dtype),
        velocity,
        jnp.asarray(time_step, dtype),
        int(n_steps),
        int(steps_per_period),
    )


@eqx.filter_jit
def _free(scene, mods, torque, theta, velocity, dt, n_steps, spp):
    mesh = scene.mesh  # the free vibration handles one mesh (a one-line error else)
    period = (jnp.arange(spp) + 0.5) * mesh.mesh_period_angle / spp
    e_ref, _ = _references(scene, mods, period)
    qs = quasi_static(scene, mods, torque, theta[None], throw=False)  # at rest
    e_th = separation(mesh, mods, theta)[1]
    Xs = qs.x[0] + _reference_shift(scene, e_ref - e_th)
    M = scene.structure.M
    C = jnp.zeros_like(M)
    F = torque * scene.f_torque
    # Ẍ(0) = 0: the start is the static equilibrium, where K X + Σ P V = F
    (_, _, _, code, _), (_, P, _, rec) = _newmark_cells(
        SceneCells(scene, per_mesh_modifications(mods, 1), e_ref, ExactContact(50)),
        CellSystem(scene.structure.K, M, C, F),
        dt,
        (Xs, velocity, jnp.zeros_like(Xs)),
        jnp.full((1, n_steps), theta),
        lambda X, Xd: (X, Xd),
    )
    X, Xd = rec
    cells = mesh.cells(theta)
    idx, Vw = scene.window(cells)
    Vw = Vw.reshape(-1, Vw.shape[-1])
    loaded = qs.line_load[0].reshape(-1) > 0
    kl = jnp.where(loaded, (cells.stiffness * cells.length).reshape(-1), 0.0)
    Kc = jnp.zeros_like(M).at[idx[:, None], idx[None, :]].add(Vw.T @ (kl[:, None] * Vw))
    K = scene.structure.K + Kc
    d = X - Xs[None, :]
    energy = 0.5 * jnp.einsum("si,ij,sj->s", Xd, M, Xd) + 0.5 * jnp.einsum("si,ij,sj->s", d, K, d)
    held = jnp.all((P > 0) == loaded[None, :])
    time = (jnp.arange(n_steps) + 1) * dt
    v0 = 0.5 * velocity @ M @ velocity
    energy = jnp.concatenate([v0[None], energy])
    time = jnp.concatenate([jnp.zeros((1,), time.dtype), time])
    X = jnp.concatenate([Xs[None], X])
    fm = jnp.concatenate([jnp.sum(qs.line_load[0] * cells.length)[None], jnp.sum(P, axis=-1)])
    return FreeVibration(time, X, fm, energy, held, code)
