"""The lumped models' dynamics (:class:`~jaxgear.dynamics.DynamicModel`): Newmark on the mesh
table (the contact in coordinates) or a diffrax solver, one speed to steady state
(:func:`_one_speed`), vmapped or continued over speeds (:func:`_run`). The public entries are
:func:`jaxgear.dynamics.simulate` and :func:`jaxgear.dynamics.speed_sweep`."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp

from .._contact import ContactLaw, ExactContact, _phi, contact_law
from .._util import check_integer
from ._modal import excited_omega
from ._model import (
    DynamicModel,
    MeshTable,
    _prepare,
    _Prepared,
    cell_geometry,
    mesh_max,
    mesh_te,
    pressure_factors,
    span_periods,
    split_cells,
    static_mesh_forces,
)
from ._newmark import newmark
from ._result import checked, steady_state
from ._settings import _Config, _divergence_code

__all__ = ["static_start"]


# --------------------------------------------------------------------------------------------
# integrators


def _with_acceleration(model, table, X, Xd, law):
    scene = model.scene
    r = table.at(0)
    f = jnp.where(r.mask, r.k * r.length * _phi(r.V @ X - r.delta0, law)[0], 0.0)
    Xdd = jnp.linalg.solve(
        scene.mass(),
        scene.external_load(model.torque) - model.damping @ Xd - scene.stiffness() @ X - r.V.T @ f,
    )
    return (X, Xd, Xdd)


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
    static_force=None,
    start: int = 0,
    record_cells: bool = False,
    factors=None,
    dofs: tuple | None = None,
):
    """``n_steps`` Newmark steps (:func:`~jaxgear.dynamics._newmark.newmark`, the contact in
    coordinates) from step ``start`` + 1 on: step n ends at step start + n + 1, whose cells
    each mesh takes from its own rows of the table (:meth:`MeshTable.at`).

    ``state``: (X, Ẋ, Ẍ, result code, most contact passes). ``static_force``: the static mesh
    forces (N), (m,), the scale of the divergence check (default: the model's F_s). Records per
    step (``record``), a dict: each mesh's force Σ P (N, (m,)) ``fm`` and TE (m, (m,)) ``te``,
    the forces per contact line of each mesh (N, a tuple of (L_k,)) ``lines``, the bearing
    forces R X (N, (r,)) ``reac``; (X, Ẋ) ``states`` with ``record_states``; the cell forces P
    (N, (c,)) ``cells`` with ``record_cells``; with ``factors`` (the table's E*/(π R) per row
    and cell, (R, c)), each mesh's largest p₀² = w E*/(π R) over its cells (Pa², (m,)) ``p2``,
    reduced here in the loop. ``dofs``: the coordinates each step's contact is condensed onto
    (:attr:`_Prepared.dofs`; None: every coordinate)."""
    scene = model.scene
    M, Ks, F = scene.mass(), scene.stiffness(), scene.external_load(model.torque)
    R = scene.reaction_matrix()
    fs = jnp.sum(model.static_force if static_force is None else static_force)
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    te_of = mesh_te(scene, table.e_max[0])
    cells_at = table.at

    def check(X, Xd, forces):
        return _divergence_code(Xd, X, jnp.sum(forces), M, fs, e_ref, cfg.blowup)

    def kept(X, Xd, forces, j):
        fm, lines = table.mesh_forces(forces)
        out = {"fm": fm, "te": te_of(X), "lines": lines, "reac": R @ X}
        if table.flank is not None:  # coast flanks: their force counts negative in F_m
            coast, _ = table.mesh_forces(jnp.where(table.flank_at(j) < 0, forces, 0.0))
            out["fm"] = fm - 2.0 * coast
            out["coast"] = coast
        if record_states:
            out["states"] = (X, Xd)
        if record_cells:
            out["cells"] = forces
        if factors is not None:  # line load w = P / l on the flanks
            w = jnp.where(table.take(table.mask, j), forces / table.take(table.length, j), 0.0)
            out["p2"] = mesh_max(w * table.take(factors, j), table.sizes)
        return out

    rows = (jnp.arange(n_steps) + 1 + start)[None, :]
    return newmark(
        Ks,
        M,
        model.damping,
        F,
        dt,
        state,
        rows,
        cells_at,
        law,
        kept if record else None,
        check=check,
        record_entry=True,
        dofs=dofs,
    )


def _static_forces(model: DynamicModel, table: MeshTable, static):
    """Each mesh's static force F_s (N), (m,) (:func:`static_mesh_forces`), and its largest
    quasi-static force on one contact line (N), (m,), over the span's steps."""
    length = table.take(table.length, jnp.arange(table.span))  # (S, c)
    fm, lines = table.mesh_forces(static.static_force_density * length)  # (S, m), (S, L_k)
    max_lines = jnp.stack([jnp.max(f) for f in lines])
    return static_mesh_forces(model.scene, model.torque, fm), max_lines


def _one_speed(model: DynamicModel, table: MeshTable, static, speed, state, cfg: _Config, law):
    P = cfg.steps_per_period
    period_angle = model.scene.base_planes[0].mesh_period_angle
    period = period_angle / speed
    dt = period / P
    n_keep = cfg.keep_periods * P
    n_trans = (cfg.periods - cfg.keep_periods) * P
    fs, static_lines = _static_forces(model, table, static)
    # the cells' base-plane coordinates at the table's rows (the same cells as the table's)
    track = cfg.cell_loads or cfg.pressure is not None
    geometry = cell_geometry(model.scene, table.theta) if track else None
    factors = None
    if cfg.pressure is not None:  # E*/(π R) per row and cell
        factors = pressure_factors(cfg.pressure, table.sizes, geometry[0], table.mask)
    states = forces = p2 = None
    if cfg.newmark:
        # the transient unrecorded, then the kept periods recorded from the row where the
        # transient ended (memory ∝ keep_periods only)
        carry0 = (*state, jnp.array(0), jnp.array(0))
        run = {"cfg": cfg, "law": law, "static_force": fs, "dofs": static.dofs}
        carry, _ = _newmark(model, table, dt, carry0, n_trans, record=False, **run)
        carry, rec = _newmark(
            model,
            table,
            dt,
            carry,
            n_keep,
            record=True,
            record_states=cfg.states,
            start=n_trans,
            record_cells=cfg.cell_loads,
            factors=factors,
            **run,
        )
        fm, te, lines, reac = rec["fm"], rec["te"], rec["lines"], rec["reac"]
        coast = rec.get("coast")
        if cfg.states:
            states = rec["states"][0]
        forces, p2 = rec.get("cells"), rec.get("p2")
        X, Xd, Xdd, code, it = carry
        final = (X, Xd, Xdd)
    else:
        # diffrax is imported only when a diffrax solver is asked for (about 0.5 s of import
        # that a Newmark run, the default, does not pay)
        from ._diffrax import _diffrax

        final, (fm, te, lines, reac, forces), code, it = _diffrax(
            model, table, speed, dt, state, cfg, law, fs
        )
    j = jnp.arange(n_keep) + 1 + n_trans  # the kept steps
    mask = table.take(table.mask, j)  # (K, c)
    line_load = None
    if forces is not None:  # the line loads of the kept steps (N/m), (K, c)
        line_load = jnp.where(mask, forces / table.take(table.length, j), 0.0)
    pressure = cells = None
    if factors is not None:
        if p2 is None:  # diffrax: from the cell forces at the kept samples
            p2 = mesh_max(line_load * table.take(factors, j), table.sizes)
        span = jnp.arange(table.span)
        w_static = jnp.where(table.take(table.mask, span), static.static_force_density, 0.0)
        pressure = (p2, mesh_max(w_static * table.take(factors, span), table.sizes))
    if cfg.cell_loads:
        s, z = (table.take(g, j) for g in geometry[:2])
        cells = split_cells(line_load, s, z, mask, table.sizes)
    static_te = jax.vmap(mesh_te(model.scene, table.e_max[0]))(static.static_x)  # (S, m)
    none = jnp.zeros((n_keep, 0), fm.dtype)
    return steady_state(
        speed=speed,
        time_step=dt,
        mesh_period_angle=period_angle,
        steps_per_period=P,
        transient_steps=n_trans,
        theta=table.angle(j),
        mesh_force=fm,
        static_force=fs,
        transmission_error=te,
        line_force=lines,
        static_line_force=static_lines,
        static_te=static_te[j % table.span],
        bearing_force=reac,
        bearing_force_static=static.static_x @ model.scene.reaction_matrix().T,
        omega_excited=excited_omega(model.modes),
        final_state=final,
        iterations=it,
        code=code,
        rim=(none, none),
        states=states,
        scene_steps=table.span,
        pressure=pressure,
        cells=cells,
        coast_force=coast if cfg.newmark else None,
    )


def _prep(
    model, law: ContactLaw, steps_per_period: int, own_periods: bool = True, condensed: bool = True
) -> _Prepared:
    """The model's cell table and static rows over its span (:func:`span_periods`), each mesh
    tabulated over its own period (``own_periods=False``: over the span, the long table), the
    static rows solved on the condensed structure (``condensed=False``: on every coordinate)."""
    periods = span_periods(model)
    return _prepare(
        model.scene,
        model.mods,
        model.torque,
        law,
        steps_per_period,
        periods,
        own_periods,
        condensed,
    )


def _static_start(prep: _Prepared):
    """(X, Ẋ) of the static equilibrium at the first mesh position, zero vibration velocity."""
    return prep.static_x[0], jnp.zeros_like(prep.static_x[0])


def static_start(
    model: DynamicModel,
    *,
    contact: ContactLaw = ExactContact(),
    steps_per_period: int = 64,
):
    """The state every simulation starts from by default: the static equilibrium at the first
    time step's mesh position and zero vibration velocity, with the ``contact`` law on a table
    of ``steps_per_period`` positions per mesh period.

    Returns:
        (X, Ẋ), each shape (n,) (the scene's generalised coordinates, SI units).
    """
    check_integer("steps_per_period", steps_per_period, 4)
    law = contact_law(contact, model.scene.base_planes[0].base_pitch.dtype)
    return _static_start(_prep(model, law, int(steps_per_period)))


@eqx.filter_jit
def _run(
    model: DynamicModel,
    prep: _Prepared,
    speeds,
    state0,
    law: ContactLaw,
    cfg: _Config,
    mode: str,
    throw: bool = False,
):
    table = prep.table
    static = prep
    state0 = _with_acceleration(model, table, state0[0], state0[1], law)
    restart = _with_acceleration(
        model, table, static.static_x[0], jnp.zeros_like(static.static_x[0]), law
    )

    def one(speed, state):
        return _one_speed(model, table, static, speed, state, cfg, law)

    if mode == "single":
        r = one(speeds, state0)
        if throw:  # eqx.error_if: raises under jit, vmap and grad alike
            r = checked(r, "simulate")
        return r
    if mode == "vmap":
        return jax.vmap(lambda s: one(s, state0))(speeds)

    def scan_dir(sp):
        def body(state, s):
            r = one(s, state)
            # a diverged point restarts the next one from the static equilibrium
            ok = r.result == 0
            nxt = jax.tree_util.tree_map(lambda a, b: jnp.where(ok, a, b), r.final_state, restart)
            return nxt, r

        return jax.lax.scan(body, state0, sp)[1]

    if mode == "continuation":
        return scan_dir(speeds)
    # both directions at once: vmap over (up, reversed)
    both = jax.vmap(scan_dir)(jnp.stack([speeds, speeds[::-1]]))
    up = jax.tree_util.tree_map(lambda a: a[0], both)
    down = jax.tree_util.tree_map(lambda a: a[1][::-1], both)
    return up, down
