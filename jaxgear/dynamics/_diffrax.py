"""diffrax solvers on the first-order form with the smooth (or exact) contact law."""

from __future__ import annotations

import diffrax
import jax
import jax.numpy as jnp

from .._contact import ContactLaw, _phi
from .._quasi_static import per_mesh_modifications
from ._model import AbstractDynamicModel, MeshTable, cells_from_reference, mesh_te
from ._settings import _Config, _divergence_code


def _cell_forces(table: MeshTable, X, j, law: ContactLaw):
    """The cell forces k l φ(V X − δ0) (N), (c,), at state X (n,) and step j (each mesh at its
    own row of the table)."""
    r = table.at(j)
    return jnp.where(r.mask, r.k * r.length * _phi(r.V @ X - r.delta0, law)[0], 0.0)


def _diffrax(
    model: AbstractDynamicModel, table: MeshTable, speed, dt, state, cfg: _Config, law, static_force
):
    """The run of :func:`~jaxgear.dynamics._lumped._one_speed` by a diffrax solver: the cells of
    every mesh at θ(t) (not the table's rows); ``static_force`` (m,) scales the checks."""
    scene = model.scene
    planes = scene.base_planes
    M, C, Ks, F = scene.mass(), model.damping, scene.stiffness(), scene.external_load(model.torque)
    Minv = jnp.linalg.inv(M)
    fs = jnp.sum(static_force)
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    vmax = jnp.max(jnp.abs(scene.te_vectors()))
    x_ref = fs / model.mesh_stiffness_mean / vmax
    w_ref = jnp.max(model.modes.omega)
    v_ref = x_ref * w_ref
    P = cfg.steps_per_period
    n_total = cfg.periods * P
    n_keep = cfg.keep_periods * P
    dtheta = planes[0].mesh_period_angle / P
    te_of = mesh_te(scene, table.e_max[0])
    e_refs = table.e_max[0]  # (m,)

    def rhs(t, y, args):
        speed, law, mods = args
        mods = per_mesh_modifications(mods, len(planes))
        X, Xd = y[0] * x_ref, y[1] * v_ref
        # δ0 from each mesh's time-constant reference, as the table's
        r = scene.cell_row(*cells_from_reference(scene, mods, speed * t + 0.5 * dtheta, e_refs))
        f = jnp.where(r.mask, r.k * r.length, 0.0) * _phi(r.V @ X - r.delta0, law)[0]
        A = Minv @ (F - C @ Xd - Ks @ X - r.V.T @ f)
        return (Xd / x_ref, A / v_ref)

    opts = cfg.integrator
    if opts.adaptive:
        controller = diffrax.PIDController(rtol=opts.rtol, atol=opts.atol)
    else:
        controller = diffrax.ConstantStepSize()
    ts = (n_total - n_keep + 1 + jnp.arange(n_keep)) * dt
    X0, Xd0, _ = state
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(rhs),
        opts.solver,
        t0=0.0,
        t1=n_total * dt,
        dt0=dt,
        y0=(X0 / x_ref, Xd0 / v_ref),
        args=(speed, law, model.mods),
        saveat=diffrax.SaveAt(ts=ts),
        stepsize_controller=controller,
        max_steps=cfg.max_steps,
        throw=False,
        # reverse mode (grad): checkpointed adjoint; forward mode (jvp, jacfwd): ForwardMode
        adjoint=opts.adjoint,
    )
    Xs, Xds = sol.ys[0] * x_ref, sol.ys[1] * v_ref
    j = n_total - n_keep + 1 + jnp.arange(n_keep)  # the kept samples' steps
    forces = jax.vmap(lambda X, jj: _cell_forces(table, X, jj, law))(Xs, j)  # (K, c)
    fm, lines = table.mesh_forces(forces)
    te = jax.vmap(te_of)(Xs)
    code = jnp.where(sol.result == diffrax.RESULTS.successful, 0, 4)
    div = jax.vmap(lambda xd, X, f: _divergence_code(xd, X, f, M, fs, e_ref, cfg.blowup))(
        Xds, Xs, jnp.sum(fm, axis=1)
    )
    # a failed solve leaves inf in the unreached outputs: report the failure, not the inf
    code = jnp.where(
        code != 0, code, jnp.where(jnp.any(div == 2), 2, jnp.where(jnp.any(div == 3), 3, 0))
    )
    Xl, Xdl = Xs[-1], Xds[-1]
    Vl = table.at(n_total).V  # the last sample's cells
    Xddl = Minv @ (F - C @ Xdl - Ks @ Xl - Vl.T @ _cell_forces(table, Xl, n_total, law))
    nsteps = jnp.asarray(sol.stats["num_steps"])
    reac = Xs @ scene.reaction_matrix().T
    # the cell forces of the kept samples (K, c) when the run records or reduces them
    kept_forces = forces if (cfg.cell_loads or cfg.pressure is not None) else None
    return (Xl, Xdl, Xddl), (fm, te, lines, reac, kept_forces), code, nsteps
