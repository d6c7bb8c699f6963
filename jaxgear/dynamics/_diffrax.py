"""diffrax solvers on the first-order form with the smooth (or exact) contact law."""

from __future__ import annotations

import diffrax
import jax
import jax.numpy as jnp
import optimistix

from .._contact import ContactLaw, _phi
from .._quasi_static import separation
from ._model import DynamicModel, MeshTable
from ._settings import DIFFRAX_SOLVERS, _Config, _divergence_code


def _observe(model: DynamicModel, table: MeshTable, X, j, law: ContactLaw):
    """Mesh force, TE and line forces at state X (n,) and table row j."""
    u = model.scene.te_vector()
    cb = jnp.cos(model.mesh.base_helix_angle)
    gap = table.V[j] @ X - table.delta0[j]
    f = jnp.where(table.mask[j], table.k[j] * table.length[j] * _phi(gap, law)[0], 0.0)
    return jnp.sum(f), (u @ X - table.e_max[j]) / cb, jnp.sum(f.reshape(table.n_lines, -1), axis=1)


def _diffrax(model: DynamicModel, table: MeshTable, speed, dt, state, cfg: _Config, law):
    scene = model.scene
    mesh = model.mesh
    M, C, Ks, F = scene.mass(), model.damping, scene.stiffness(), scene.external_load(model.torque)
    Minv = jnp.linalg.inv(M)
    fs = model.static_force
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    vmax = jnp.max(jnp.abs(scene.te_vector()))
    x_ref = fs / model.mesh_stiffness_mean / vmax
    w_ref = jnp.max(model.modes.omega)
    v_ref = x_ref * w_ref
    P = cfg.steps_per_period
    n_total = cfg.periods * P
    n_keep = cfg.keep_periods * P
    dtheta = mesh.mesh_period_angle / P

    def rhs(t, y, args):
        speed, law, mods = args
        X, Xd = y[0] * x_ref, y[1] * v_ref
        cells, e_max, d0 = separation(mesh, mods, speed * t + 0.5 * dtheta)
        d0 = jnp.where(cells.mask, d0 + (table.e_max[0] - e_max), 0.0)
        V = scene.cell_vectors(cells).reshape(-1, X.shape[0])
        kl = jnp.where(cells.mask, cells.stiffness * cells.length, 0.0).reshape(-1)
        f = kl * _phi(V @ X - d0.reshape(-1), law)[0]
        A = Minv @ (F - C @ Xd - Ks @ X - V.T @ f)
        return (Xd / x_ref, A / v_ref)

    opts = cfg.integrator
    cls = getattr(diffrax, DIFFRAX_SOLVERS[opts.solver])
    if issubclass(cls, diffrax.AbstractImplicitSolver) and not opts.adaptive:
        # constant steps: the root finder needs its own tolerances
        solver = cls(
            root_finder=diffrax.VeryChord(rtol=opts.rtol, atol=opts.atol, norm=optimistix.max_norm)
        )
    else:
        solver = cls()
    if opts.adaptive:
        controller = diffrax.PIDController(rtol=opts.rtol, atol=opts.atol)
    else:
        controller = diffrax.ConstantStepSize()
    ts = (n_total - n_keep + 1 + jnp.arange(n_keep)) * dt
    X0, Xd0, _ = state
    sol = diffrax.diffeqsolve(
        diffrax.ODETerm(rhs),
        solver,
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
        adjoint=diffrax.ForwardMode()
        if opts.adjoint == "forward"
        else diffrax.RecursiveCheckpointAdjoint(),
    )
    Xs, Xds = sol.ys[0] * x_ref, sol.ys[1] * v_ref
    j = (jnp.arange(n_keep) + 1) % P
    fm, te, lines = jax.vmap(lambda X, jj: _observe(model, table, X, jj, law))(Xs, j)
    code = jnp.where(sol.result == diffrax.RESULTS.successful, 0, 4)
    div = jax.vmap(lambda xd, X, f: _divergence_code(xd, X, f, M, fs, e_ref, cfg.blowup))(
        Xds, Xs, fm
    )
    # a failed solve leaves inf in the unreached outputs: report the failure, not the inf
    code = jnp.where(
        code != 0, code, jnp.where(jnp.any(div == 2), 2, jnp.where(jnp.any(div == 3), 3, 0))
    )
    Xl, Xdl = Xs[-1], Xds[-1]
    gap = table.V[0] @ Xl - table.delta0[0]
    f = jnp.where(table.mask[0], table.k[0] * table.length[0] * _phi(gap, law)[0], 0.0)
    Xddl = Minv @ (F - C @ Xdl - Ks @ Xl - table.V[0].T @ f)
    nsteps = jnp.asarray(sol.stats["num_steps"])
    reac = Xs @ scene.reaction_matrix().T
    return (Xl, Xdl, Xddl), (fm, te, lines, reac), code, nsteps
