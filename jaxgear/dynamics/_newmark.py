"""Newmark average acceleration (β = 1/4, γ = 1/2, seed annex 2) with the contact loop (II-25)."""

from __future__ import annotations

import jax
import jax.numpy as jnp

from .._contact import ContactLaw, solve_contact
from ._model import DynamicModel, MeshTable
from ._settings import _code, _Config, _divergence_code


def _newmark(
    model: DynamicModel,
    table: MeshTable,
    dt,
    state,
    n_steps: int,
    cfg: _Config,
    law: ContactLaw,
    record: bool,
    record_states: bool = False,
):
    """Newmark average acceleration with the contact loop, ``n_steps`` steps from table row 0."""
    scene = model.scene
    M, C, Ks, F = scene.mass(), model.damping, scene.stiffness(), scene.external_load(model.torque)
    u = scene.te_vector()
    R = scene.reaction_matrix()
    cb = jnp.cos(model.mesh.base_helix_angle)
    fs = model.static_force
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    b, g = 0.25, 0.5
    a0 = 1.0 / (b * dt * dt)
    a1 = g / (b * dt)
    Keff = a0 * M + a1 * C + Ks
    P = table.theta.shape[0]

    def body(carry, n):
        X, Xd, Xdd, code, it = carry
        j = (n + 1) % P
        Feff = (
            F
            + M @ (a0 * X + Xd / (b * dt) + (0.5 / b - 1.0) * Xdd)
            + C @ (a1 * X + (g / b - 1.0) * Xd + dt * (0.5 * g / b - 1.0) * Xdd)
        )
        sol = solve_contact(
            Keff,
            Feff,
            table.V[j],
            table.k[j],
            table.length[j],
            table.delta0[j],
            table.mask[j],
            law,
        )
        Xn = sol.x
        Xddn = a0 * (Xn - X - dt * Xd - dt * dt * (0.5 - b) * Xdd)
        Xdn = Xd + dt * ((1.0 - g) * Xdd + g * Xddn)
        cell_force = sol.force_density * table.length[j]
        fm = jnp.sum(cell_force)
        new = jnp.where(sol.result == 1, 1, jnp.where(sol.result == 3, 2, 0))
        new = _code(new, _divergence_code(Xdn, Xn, fm, M, fs, e_ref, cfg.blowup))
        carry = (Xn, Xdn, Xddn, _code(code, new), jnp.maximum(it, sol.iterations))
        if not record:
            return carry, None
        te = (u @ Xn - table.e_max[j]) / cb
        lines = jnp.sum(cell_force.reshape(table.n_lines, -1), axis=1)
        out = (fm, te, lines, R @ Xn)
        return carry, (out + (Xn, Xdn) if record_states else out)

    return jax.lax.scan(body, state, jnp.arange(n_steps))
