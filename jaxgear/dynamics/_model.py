"""Time integration of the gear dynamics with unilateral contact, and speed sweeps
(docs/dynamics.md, "Model").

Equations of motion (seed (2.37), :mod:`jaxgear._dyn_scene`):

    M Ẍ + C Ẋ + K_s X + Σ_c k_c l_c φ(V_c·X − δ0_c(t)) V_c = F,

with the cells and δ0 at the nominal mesh position θ(t) = Ω t (Ω: pinion speed, rad/s), sampled
at the mid-points of the steps, θ = (i + ½)Δθ (Δθ = 2π/(z1 N_s) the pinion rotation of one time
step, N_s steps per mesh period; the mid-points keep contact-line ends off the edges of the base
plane, as in the quasi-static positions): a run starts at t = Δt/2 from the equilibrium at Δθ/2
and its step i ends at t = (i + 3/2)Δt (docs/design.md, "The clock of the records").
The excitation comes only through δ0(t) and the time-varying cell set (seed III §3.3).

Solvers:

* ``"newmark"``: Newmark average acceleration (β = 1/4, γ = 1/2, seed annex 2, (2.1)-(2.6)). Each
  step is a contact problem K_eff X = F_eff with K_eff = M/(βΔt²) + γC/(βΔt) + K_s, solved by
  :func:`jaxgear.solve_contact`: exact law by the active set of seed II-25 (cells in tension dropped,
  interference outside the contact set checked, repeated), or the smooth softplus law by Newton.
  Because N_s is fixed per mesh period, the cell table (δ0, k, l, V at N_s positions) does not
  depend on the speed: it is built once and indexed by step mod N_s; a train's meshes of other
  periods each by step mod their own period's steps (:class:`MeshTable`).
* a diffrax solver name (``"tsit5"``, ``"dopri5"``, ``"dopri8"``, ``"kvaerno3"``, ``"kvaerno5"``,
  ...): the first-order form in scaled variables (X/x_ref, Ẋ/(x_ref ω_ref)), adaptive steps with a
  ``PIDController`` (or constant steps with ``adaptive=False``), cells evaluated at θ(t).

Steady state: ``periods`` mesh periods are integrated from the static equilibrium (or a given
state), the last ``keep_periods`` are kept. Outputs: mesh force, dynamic TE, per-tooth force, the
dynamic factor (max dynamic mesh force / static mesh force, global and per tooth), TE RMS, the
contact-loss fraction, and the change between the last two periods (periodicity check).

Divergence is reported through ``result`` (:class:`~jaxgear.DynamicsResult`), never as a silent NaN.
"""

from __future__ import annotations

import abc
import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float, Int

from .._baseplane import CellRow, MeshModel, cell_flank, check_positions, split_by_mesh
from .._contact import ContactLaw, ExactContact, SmoothContact, solve_contact
from .._deviations import Deviations
from .._modifications import Modifications
from .._pressure import pressure_factor
from .._quasi_static import mesh_separations, per_mesh_modifications
from .._util import safe_max
from ..scenes import DynamicScene, HybridPair
from ._modal import ModalAnalysis
from ._newmark import contact_coordinates, static_condensation
from ._settings import STEPS_PER_MODE, Integrator, Newmark, Outputs, SteadyState
from ._whine_methods import AbstractWhineMethod

__all__ = [
    "AbstractDynamicModel",
    "MeshTable",
    "cell_geometry",
    "cell_stiffness",
    "cells_from_reference",
    "deviation_periods",
    "mesh_forces",
    "mesh_rows",
    "mesh_table",
    "mesh_te",
    "span_periods",
    "static_mesh_forces",
]


class MeshTable(eqx.Module):
    """Contact cells of every mesh tabulated over its own period at the steps of the first mesh
    (c = Σ_k n_lines_k·n_slices_k cells, mesh after mesh as :meth:`jaxgear.CellRow.concat` joins
    them; docs/trains.md, "Long spans").

    Row r of the table holds every mesh's cells at the scene angle θ_r = (r + ½) Δθ (Δθ = 2π/(z1
    N_s), the first mesh's pinion rotation of one step, N_s :attr:`steps_per_period`). Mesh k
    uses its first ``rows[k]`` rows: at step j it takes row j mod ``rows[k]``. ``rows[k]`` is
    the steps of its own period, N_s T_k/T_0, where that is a whole number and the mesh repeats
    after it (no manufacturing deviations); otherwise the steps of the whole span (one scene
    period, or the deviations' span). The table has max(rows) rows; every mesh repeats after
    :attr:`span` = lcm(rows) steps. A pair (and an idler train) has rows = (N_s, ...), a
    two-stage train of period ratio 127/35 at N_s = 140 has (140, 508) against 127 × 140 =
    17 780 rows of the span. Read rows with :meth:`at` and :meth:`take`, never by indexing the
    fields with a step.

    Attributes:
        theta: scene angles of the rows (rad), shape (R,). V: structure vectors, shape (R, c,
        n). k: cell stiffness per unit length (N/m²), length: cell length (m), delta0: δ0 (m),
        mask: cells on the flanks; all shape (R, c).
        e_max: each mesh's reference e_ref = max over its period of its max_M e (m), broadcast
            to (R, m): δ0 = e_ref − e ≥ 0 and TE = (u·X − e_ref)/cos β_b use one time-constant
            reference per mesh.
        period_angle: the first mesh's period 2π/z1 (rad).
        sizes: static (n_lines, n_slices) of each mesh (each mesh's cells are line-major).
        rows: static, the rows each mesh uses (its period in steps), a tuple of m ints.
        steps_per_period: static N_s.
        flank: +1 drive, −1 coast cells (:attr:`jaxgear.Cells.flank`), shape (R, c).
        steps: None, or a table of a traced step count (one compiled program for every N_s of
            a sweep, docs/dynamics.md "Time step and accuracy"): its N_s (int, <=
            :attr:`steps_per_period`, which then holds the largest N_s the table is sized for;
            every N_s of the sweep a power-of-two fraction of it). The table holds the rows of
            N_s = ``steps`` first (mesh k uses its first ``rows[k]`` × steps /
            steps_per_period), the rows after them unused; :meth:`cell_rows`,
            :meth:`angle` and :attr:`span_steps` read it.
    """

    theta: Float[Array, " R"]
    V: Float[Array, "R c n"]
    k: Float[Array, "R c"]
    length: Float[Array, "R c"]
    delta0: Float[Array, "R c"]
    mask: Bool[Array, "R c"]
    e_max: Float[Array, "R m"]
    period_angle: Float[Array, ""]
    sizes: tuple = eqx.field(static=True)
    rows: tuple = eqx.field(static=True, default=())
    steps_per_period: int = eqx.field(static=True, default=0)
    flank: Float[Array, "R c"] | None = None
    steps: Int[Array, ""] | None = None

    @property
    def span(self) -> int:
        """Steps after which every mesh repeats together: lcm of :attr:`rows` (static; with a
        traced :attr:`steps`, the span of the largest N_s, :attr:`steps_per_period`)."""
        return math.lcm(*self.rows)

    def _scaled(self, n):
        """``n`` steps of N_s = :attr:`steps_per_period` at the table's N_s (:attr:`steps`)."""
        return n if self.steps is None else n * self.steps // self.steps_per_period

    @property
    def span_steps(self):
        """:attr:`span` at the table's N_s: static, or traced with a traced :attr:`steps`."""
        return self._scaled(self.span)

    @property
    def step_count(self):
        """The table's N_s: :attr:`steps_per_period`, or the traced :attr:`steps`."""
        return self.steps_per_period if self.steps is None else self.steps

    def cell_rows(self, steps) -> Int[Array, "... c"]:
        """The table row each cell takes at the steps ``steps`` (int, shape (...)), (..., c):
        step mod the rows of its mesh."""
        steps = jnp.asarray(steps)
        per_cell = np.repeat(np.asarray(self.rows), [L * N for L, N in self.sizes])
        per_cell = self._scaled(jnp.asarray(per_cell))
        return steps[..., None] % per_cell.reshape((1,) * steps.ndim + (-1,))

    def take(self, field, steps):
        """A per-cell field of the table (R, c, ...) at the steps ``steps`` (shape (...)):
        (..., c, ...), each cell from the row of its mesh (:meth:`cell_rows`)."""
        r = self.cell_rows(steps)
        return field[r, jnp.broadcast_to(jnp.arange(field.shape[1]), r.shape)]

    def at(self, step) -> CellRow:
        """Every cell at one step (int): a :class:`jaxgear.CellRow` on all coordinates."""
        V, k, ln, d0, mask = (self.take(f, step) for f in self._cell_fields())
        return CellRow(None, V, k, ln, d0, mask)

    def flank_at(self, steps):
        """:attr:`flank` at the steps ``steps`` (..., c), or None without coast cells."""
        return None if self.flank is None else self.take(self.flank, steps)

    def angle(self, steps) -> Array:
        """The scene angle of the steps ``steps`` (rad): ((j mod span) + ½) Δθ, the angle of
        the rows the steps take."""
        j = (jnp.asarray(steps) % self.span_steps).astype(self.theta.dtype) + 0.5
        return j * self.period_angle / self.step_count  # as the rows' θ

    def _cell_fields(self):
        return (self.V, self.k, self.length, self.delta0, self.mask)

    def fold(self, weights) -> Float[Array, "R c"]:
        """Per-cell ``weights`` over the span's steps (span, c) summed onto the rows each cell
        takes (R, c): Σ_j w_jc f(row_c(j)) = Σ_r W_rc f(r, c)."""
        r = self.cell_rows(jnp.arange(weights.shape[0]))
        c = jnp.broadcast_to(jnp.arange(weights.shape[1]), r.shape)
        return (
            jnp.zeros((self.theta.shape[0], weights.shape[1]), weights.dtype).at[r, c].add(weights)
        )

    def split(self, cell_values) -> tuple:
        """``cell_values`` (..., c) cut into each mesh's (..., n_lines, n_slices)."""
        return split_by_mesh(cell_values, self.sizes)

    def mesh_forces(self, cell_forces) -> tuple[Array, tuple]:
        """Each mesh's force and its forces per contact line (:func:`mesh_forces`)."""
        return mesh_forces(cell_forces, self.sizes)


def mesh_forces(cell_forces, sizes) -> tuple[Array, tuple]:
    """The mesh force Σ P of each mesh (..., m) and its force per contact line, a tuple of
    (..., n_lines) (N), from the cell forces ``cell_forces`` (..., c) (N) of meshes of
    ``sizes`` (n_lines, n_slices), mesh after mesh."""
    lines = tuple(jnp.sum(f, axis=-1) for f in split_by_mesh(cell_forces, sizes))
    return jnp.stack([jnp.sum(f, axis=-1) for f in lines], axis=-1), lines


def _is_deviations(x) -> bool:
    return isinstance(x, Deviations)


def deviations_in(mods) -> list[Deviations]:
    """The manufacturing deviations (:class:`~jaxgear.Deviations`) that ``mods`` carry, in mesh
    order: ``mods`` one :class:`Modifications`, a tuple or list of one per mesh, or None."""
    return [d for d in jax.tree.leaves(mods, is_leaf=_is_deviations) if _is_deviations(d)]


def deviation_periods(mods) -> int:
    """Mesh periods after which the per-tooth deviations that ``mods`` carry repeat (static:
    from the tooth counts, the lengths of their arrays): the least common multiple of the
    deviating members' tooth counts (tooth pair j meets pinion tooth j mod z1 and gear tooth
    j mod z2; a pinion runout repeats every z1 periods, a gear runout every z2); 1 without
    deviations. ``mods``: one :class:`Modifications` or a tuple of one per mesh."""
    teeth = [g.teeth for d in deviations_in(mods) for g in (d.pinion, d.gear) if g is not None]
    return math.lcm(1, *teeth)


def mesh_rows(scene, mods, steps_per_period: int, periods: int) -> tuple[int, ...]:
    """The rows of each mesh in the table of ``steps_per_period`` steps per first-mesh period
    over a span of ``periods`` first-mesh periods (static; :class:`MeshTable`): N_s T_k/T_0,
    the steps of mesh k's own period (:meth:`~jaxgear.scenes.Scene.mesh_periods`), where that
    is a whole number dividing the span's steps and ``mods`` carry no manufacturing deviations;
    else the span's steps N_s × ``periods``. A train whose period ratios have denominators q_k
    tabulates each mesh over its own period when N_s is a multiple of lcm(q_k) (35 for the
    embedded ``two-stage``: 127/35)."""
    span = steps_per_period * periods
    if deviation_periods(mods) > 1:
        return (span,) * len(scene.base_planes)
    out = []
    for f in scene.mesh_periods():
        own = steps_per_period * f
        whole = own.denominator == 1 and span % own.numerator == 0
        out.append(int(own) if whole else span)
    return tuple(out)


def mesh_table(
    scene: DynamicScene,
    mods,
    steps_per_period: int,
    periods: int | None = None,
    *,
    own_periods: bool = True,
) -> MeshTable:
    """Cells of every mesh, δ0 (2.8) and structure vectors at the mid-points of
    ``steps_per_period`` steps per period of the first mesh, each mesh over its own period
    (:func:`mesh_rows`) within a span of ``periods`` periods of the first mesh (default: the
    scene's period, :meth:`~jaxgear.scenes.Scene.scene_periods`; one but for a two-stage train;
    with manufacturing deviations, the span over which they repeat, :func:`span_periods`)
    (``mods``: one :class:`Modifications` for every mesh, or one per mesh). The reference e_ref
    of each mesh is the largest e over its rows, so that δ0 = e_ref − e >= 0 over the span
    (docs/robust.md, "Dynamics with deviations"). ``own_periods=False`` tabulates every mesh
    over the whole span (the long table: the same cells at every step, for comparisons).
    One compiled program per scene and table size (called outside a jit, the table is not
    formed operation by operation)."""
    return _mesh_table(scene, mods, steps_per_period, periods, own_periods)


@eqx.filter_jit
def _mesh_table(scene, mods, steps_per_period, periods, own_periods, steps=None) -> MeshTable:
    # ``steps``: None, or a traced N_s <= steps_per_period (MeshTable.steps): the table of
    # steps_per_period's size holding the rows of N_s = steps first
    planes = scene.base_planes
    mods = per_mesh_modifications(mods, len(planes))
    # one scene period: the first mesh's periods after which every mesh repeats (1 but for a
    # train whose meshes pass teeth at different rates)
    if periods is None:
        periods = scene.scene_periods()
    check_positions(steps_per_period, periods)
    rows = mesh_rows(scene, mods, int(steps_per_period), int(periods))
    if not own_periods:
        rows = (int(steps_per_period) * int(periods),) * len(planes)
    n_rows = max(rows)
    dtype = planes[0].base_pitch.dtype
    # the angles of mesh_positions, (r + ½) Δθ
    n_s = steps_per_period if steps is None else steps
    theta = (jnp.arange(n_rows, dtype=dtype) + 0.5) * planes[0].mesh_period_angle / n_s

    def row(th):
        parts = mesh_separations(scene, mods, th)
        cells = tuple(p[0] for p in parts)
        r = scene.cell_row(cells, tuple(p[2] for p in parts))
        flank = jnp.concatenate([cell_flank(c).reshape(-1) for c in cells])
        return r.V, r.k, r.length, r.delta0, r.mask, jnp.stack([p[1] for p in parts]), flank

    V, k, ln, d0, mask, e_max, flank = jax.vmap(row)(theta)
    # one time-constant reference per mesh, the largest over its own rows: δ0 = e_ref − e. The
    # quasi-static δ0 = max e(t) − e moves its reference with time, which would be a spurious
    # inertial excitation in dynamics. (A coast cell's δ0 = j_bn − e_ref − e: the shift has the
    # other sign.)
    own_rows = jnp.asarray(rows) if steps is None else jnp.asarray(rows) * steps // steps_per_period
    own = jnp.arange(n_rows)[:, None] < own_rows[None, :]  # (R, m)
    # (safe_max: jnp.max's value, a derivative that never divides by a zero count of maxima)
    e_ref = safe_max(jnp.where(own, e_max, -jnp.inf), axis=0)  # (m,)
    sizes = tuple((p.n_lines, p.n_slices) for p in planes)
    of_cell = np.repeat(np.arange(len(planes)), [L * N for L, N in sizes])
    d0 = jnp.where(mask, d0 + flank * (e_ref[None, :] - e_max)[:, of_cell], 0.0)
    return MeshTable(
        theta,
        V,
        k,
        ln,
        d0,
        mask,
        jnp.broadcast_to(e_ref, e_max.shape),
        planes[0].mesh_period_angle,
        sizes=sizes,
        rows=rows,
        steps_per_period=int(steps_per_period),
        flank=flank if any(p.coast for p in planes) else None,
        steps=steps,
    )


def cells_from_reference(scene, mods: tuple, theta, e_ref) -> tuple[tuple, tuple]:
    """Each mesh's cells at the scene angle θ (each at its mesh angle) and their δ0 = e_ref,k − e
    (m) from the meshes' time-constant references ``e_ref`` (m,) (:class:`MeshTable`; 0 off the
    flanks), for the solvers that take the cells at θ(t) instead of the table's rows. ``mods``:
    one per mesh."""
    parts = mesh_separations(scene, mods, theta)
    delta0 = tuple(
        jnp.where(c.mask, d + cell_flank(c) * (e_ref[k] - e), 0.0)
        for k, (c, e, d) in enumerate(parts)
    )
    return tuple(p[0] for p in parts), delta0


def cell_geometry(scene, theta) -> tuple[Array, Array, Array]:
    """Every mesh's cells at the scene angles ``theta`` (K,), each at its mesh angle
    (:meth:`~jaxgear.scenes.Scene.mesh_cells`), joined mesh after mesh as the contact row joins
    them: base-plane s (m), z (m) and the flank mask, each (K, c)."""

    def at(th):
        cells = scene.mesh_cells(th)
        return tuple(
            jnp.concatenate([getattr(c, f).reshape(-1) for c in cells]) for f in ("s", "z", "mask")
        )

    return jax.vmap(at)(theta)


def pressure_factors(pressure, sizes, s, mask) -> Float[Array, "... c"]:
    """E*/(π R) of every cell (Pa per N/m; 0 off the flanks) at base-plane coordinates ``s``
    (..., c) of meshes of ``sizes`` (n_lines, n_slices), mesh after mesh, with each mesh's pair
    and the material of ``pressure`` (:class:`~jaxgear.dynamics.HertzPressure`): a line load w
    gives p₀² = w × this (:func:`jaxgear.pressure_factor`)."""
    E, nu = pressure.youngs_modulus, pressure.poisson_ratio
    parts = zip(pressure.pairs, split_by_mesh(s, sizes), split_by_mesh(mask, sizes), strict=True)
    return jnp.concatenate(
        [
            pressure_factor(pair, ss, mm, E, nu).reshape(s.shape[:-1] + (-1,))
            for pair, ss, mm in parts
        ],
        axis=-1,
    )


def mesh_max(cell_values, sizes) -> Float[Array, "... m"]:
    """The largest of ``cell_values`` (..., c) over each mesh's cells (meshes of ``sizes``, mesh
    after mesh): (..., m)."""
    return jnp.stack(
        [
            jnp.max(v.reshape(v.shape[:-2] + (-1,)), axis=-1)
            for v in split_by_mesh(cell_values, sizes)
        ],
        axis=-1,
    )


def split_cells(line_load, s, z, mask, sizes) -> tuple:
    """Per mesh (line load, s, z, mask), each (..., n_lines, n_slices), from the joined (..., c)
    records of meshes of ``sizes``."""
    parts = [split_by_mesh(v, sizes) for v in (line_load, s, z, mask)]
    return tuple(zip(*parts, strict=True))


def mesh_te(scene, e_ref):
    """X ↦ each mesh's TE (u_k·X − e_ref,k)/cos β_b,k (m), (m,), from its reference
    ``e_ref`` (m,) (the time-constant references of the dynamics, :class:`MeshTable`)."""
    U = scene.te_vectors()
    cb = jnp.stack([jnp.cos(p.base_helix_angle) for p in scene.base_planes])
    return lambda X: (U @ X - e_ref) / cb


def static_mesh_forces(scene, torque, quasi_static_forces) -> Float[Array, " m"]:
    """Each mesh's static force F_s (N), (m,), the scale of its dynamic factor: T/(r_b1 cos β_b)
    at pinion torque T (N·m) for the one mesh of a pair; with several meshes the mean over the
    period of each mesh's ``quasi_static_forces`` (P, m) (N) (for one mesh the two agree by the
    pinion's torque balance)."""
    if quasi_static_forces.shape[1] == 1:
        return scene.base_planes[0].normal_load(torque)[None]
    return jnp.mean(quasi_static_forces, axis=0)


def _rigid_penalty(scene: DynamicScene, k_ref) -> Float[Array, "n n"]:
    """μ Σ (M r)(M r)ᵀ/(rᵀ M r): pins the rigid-body modes of a static problem (F·r = V·r = 0, so
    the solution is unchanged apart from its M-orthogonality to r)."""
    M = scene.mass()
    R = scene.rigid_modes()
    n = M.shape[0]
    if R.shape[1] == 0:
        return jnp.zeros((n, n), M.dtype)
    MR = M @ R
    mu = k_ref / (jnp.trace(M) / n)
    return mu * MR @ jnp.diag(1.0 / jnp.einsum("ir,ij,jr->r", R, M, R)) @ MR.T


#: static rows solved together (vmapped) per batch of a long span: bounds the memory of a
#: span of thousands of steps (lax.map over the batches)
STATIC_BATCH = 1024


def _static_rows(
    scene: DynamicScene, table: MeshTable, torque, law: ContactLaw, k_ref, condensed: bool = True
):
    """Static contact solution at each step of the table's span (:attr:`MeshTable.span`: the
    quasi-static reference), each mesh at its own row.

    The structure is the same at every step: it is condensed once onto the coordinates the
    cells reach (:func:`~jaxgear.dynamics._newmark.static_condensation`; 24 of 102 for the lumped
    ``two-stage`` case), each step's active set (II-25) is solved on those alone, and X is
    recovered. A scene whose cells reach every coordinate (a torsional train), or that does
    not name them, is solved on all, as is every scene with ``condensed=False`` (for
    comparisons)."""
    K = scene.stiffness() + _rigid_penalty(scene, k_ref)
    F = scene.external_load(torque)
    dofs = contact_coordinates(scene, K.shape[0], condensed)
    if dofs is not None:
        reduced = static_condensation(K, dofs)
        K, (F, y) = reduced.S, reduced.load(F)
        # the structure vectors on those coordinates only (the others are zero)
        table = eqx.tree_at(lambda t: t.V, table, table.V[:, :, reduced.J])

    def solve(j):
        r = table.at(j)
        f = table.flank_at(j)
        # coast flanks: start from the loaded (drive) flank (docs/backlash.md)
        start = None if f is None else f > 0
        sol = solve_contact(K, F, r.V, r.k, r.length, r.delta0, r.mask, law, start)
        if dofs is None:
            return sol
        return eqx.tree_at(lambda s: s.x, sol, reduced.expand(sol.x, y))

    steps = jnp.arange(table.span)
    if table.span <= STATIC_BATCH:
        return jax.vmap(solve)(steps)
    if table.steps is None:
        return jax.lax.map(solve, steps, batch_size=STATIC_BATCH)
    # a traced N_s (MeshTable.steps): the batches that hold its span only (a traced count),
    # the rows past it repeating the span's (the same solutions: the same cells)
    n_batches = -(-table.span // STATIC_BATCH)
    first = jax.eval_shape(jax.vmap(solve), steps[:STATIC_BATCH])
    out = jax.tree.map(lambda s: jnp.zeros((n_batches,) + s.shape, s.dtype), first)

    def batch(b, out):
        sol = jax.vmap(solve)(b * STATIC_BATCH + jnp.arange(STATIC_BATCH))
        return jax.tree.map(lambda o, x: o.at[b].set(x), out, sol)

    out = jax.lax.fori_loop(0, -(-table.span_steps // STATIC_BATCH), batch, out)
    rows = steps % table.span_steps
    return jax.tree.map(lambda o: o.reshape((-1,) + o.shape[2:])[rows], out)


def _k_ref(table: MeshTable):
    r = table.at(0)
    kl = jnp.where(r.mask, r.k * r.length, 0.0)
    return jnp.einsum("c,ci,ci->", kl, r.V, r.V)


def cell_stiffness(V, weights) -> Float[Array, "w w"]:
    """Σ w_c V_c V_cᵀ: the stiffness the cells add to the structure (seed (2.34)'s mesh part),
    summed over every leading axis: structure vectors V (..., c, w) (m per unit coordinate,
    on all n coordinates or a window of w), weights w (..., c) (N/m: k l times each cell's
    loaded weight) → (w, w). The one kernel of the mean mesh stiffness K̄_m of every engine:
    the lumped model's over its table (:func:`_mean_mesh_matrix`), the hybrid model's on the
    windows of the positions of a mesh period (:func:`jaxgear.dynamics.mean_mesh_stiffness`)."""
    return jnp.einsum("...c,...ci,...cj->ij", weights, V, V)


def _mean_mesh_matrix(table: MeshTable, kl) -> Float[Array, "n n"]:
    """⟨Σ_c kl_c V_c V_cᵀ⟩ over the span's steps, from the cells' k l w (N/m) at every step
    (span, c): folded onto the table's rows (:meth:`MeshTable.fold`), :func:`cell_stiffness`."""
    return cell_stiffness(table.V, table.fold(kl)) / kl.shape[0]


class _Prepared(eqx.Module):
    """The table and the static solution at every step of its span S (:attr:`MeshTable.span`)."""

    table: MeshTable
    static_x: Float[Array, "S n"]
    static_force_density: Float[Array, "S c"]
    static_weight: Float[Array, "S c"]
    static_result: Int[Array, " S"]
    #: the coordinates the contact problems are condensed onto (:func:`contact_coordinates`),
    #: static; None: solved on every coordinate
    dofs: tuple | None = eqx.field(static=True, default=None)


class _HeldTable(eqx.Module):
    """A built model's own table and static rows (:func:`_prepare` as a run calls it: the
    scene's period, each mesh over its own period, condensed, no traced N_s), with what they
    were solved for: the model's ``(scene, mods, torque)`` (the very arrays), the contact law,
    N_s and the periods. :func:`_held_or_prepare` hands them back to a call with these inputs
    instead of solving them again; any other call (another law or N_s, a model whose scene,
    mods or torque were replaced, traced values) solves its own."""

    prep: _Prepared
    law: ContactLaw
    inputs: tuple
    steps_per_period: int = eqx.field(static=True)
    periods: int = eqx.field(static=True)

    def serves(self, inputs, law, steps_per_period, periods) -> bool:
        """Whether these rows are :func:`_prepare`'s of ``inputs`` = (scene, mods, torque),
        ``law``, ``steps_per_period`` and ``periods`` (own periods, condensed, steps None):
        the same arrays (identity, concrete only) and a law of equal values."""
        if int(steps_per_period) != self.steps_per_period or int(periods) != self.periods:
            return False
        mine, theirs = jax.tree.flatten(self.inputs), jax.tree.flatten(inputs)
        if mine[1] != theirs[1] or any(a is not b for a, b in zip(mine[0], theirs[0])):
            return False
        if any(isinstance(a, jax.core.Tracer) for a in mine[0]):
            return False
        held, asked = jax.tree.flatten(self.law), jax.tree.flatten(law)
        if type(self.law) is not type(law) or held[1] != asked[1]:
            return False
        for a, b in zip(held[0], asked[0]):
            if isinstance(a, jax.core.Tracer) or isinstance(b, jax.core.Tracer):
                return False
            a, b = np.asarray(a), np.asarray(b)
            if a.dtype != b.dtype or a.shape != b.shape or not np.array_equal(a, b):
                return False
        return True


def _held_or_prepare(
    held: _HeldTable | None,
    scene,
    mods,
    torque,
    law: ContactLaw,
    steps_per_period: int,
    periods: int,
    own_periods: bool = True,
    condensed: bool = True,
    steps=None,
) -> _Prepared:
    """:func:`_prepare`'s table and static rows, ``held``'s when it serves these arguments
    (:meth:`_HeldTable.serves`; the same result: the same program on the same inputs)."""
    if (
        held is not None
        and own_periods
        and condensed
        and steps is None
        and held.serves((scene, mods, torque), law, steps_per_period, periods)
    ):
        return held.prep
    return _prepare(
        scene, mods, torque, law, steps_per_period, periods, own_periods, condensed, steps
    )


@eqx.filter_jit
def _prepare(
    scene,
    mods,
    torque,
    law: ContactLaw,
    steps_per_period: int,
    periods=None,
    own_periods: bool = True,
    condensed: bool = True,
    steps=None,
):
    """Cell table and static rows over ``periods`` mesh periods (default the scene's;
    compiled once per scene structure, N_s and span; shared by the model build, every solver,
    direction and period count); ``own_periods``: :func:`mesh_table`'s; ``condensed``:
    :func:`_static_rows`'. ``steps``: None, or a traced N_s (:attr:`MeshTable.steps`; one
    program for every N_s of a sweep, ``steps_per_period`` the largest): the static rows of
    the largest span, those past N_s's span repeating its rows."""
    table = _mesh_table(scene, mods, steps_per_period, periods, own_periods, steps)
    static = _static_rows(scene, table, torque, law, _k_ref(table), condensed)
    dofs = contact_coordinates(scene, table.V.shape[-1], condensed)
    return _Prepared(table, static.x, static.force_density, static.weight, static.result, dofs)


def _prep(
    model: AbstractDynamicModel,
    law: ContactLaw,
    steps_per_period: int,
    own_periods: bool = True,
    condensed: bool = True,
    steps=None,
) -> _Prepared:
    """A lumped model's (:class:`~jaxgear.dynamics.DynamicModel`'s, with its ``held`` table)
    cell table and static rows over its span (:func:`span_periods`), each mesh tabulated over
    its own period (``own_periods=False``: over the span, the long table), the
    static rows solved on the condensed structure (``condensed=False``: on every coordinate);
    ``steps``: None, or an N_s as an array (one program for every N_s, ``steps_per_period``
    the largest: :attr:`MeshTable.steps`)."""
    periods = model.span_periods()
    return _held_or_prepare(
        model.held,
        model.scene,
        model.mods,
        model.torque,
        law,
        steps_per_period,
        periods,
        own_periods,
        condensed,
        steps,
    )


class AbstractDynamicModel(eqx.Module):
    """A dynamics engine: a scene with its mesh at a pinion torque T (N·m), and the way it is
    integrated to steady state (the pattern of diffrax's ``AbstractSolver``: the entries
    :func:`~jaxgear.dynamics.simulate`, :func:`~jaxgear.dynamics.speed_sweep` and
    :func:`~jaxgear.dynamics.band_dynamic_factor` are written once over these methods; a new
    kind of model is one more subclass, not a branch in them).

    Implementations: :class:`~jaxgear.dynamics.DynamicModel` (lumped scenes: the cells in
    coordinates on a mesh table, Newmark or a diffrax solver) and
    :class:`~jaxgear.dynamics.HybridModel` (condensed FE bodies: Newmark in the cell space or
    a modal basis, the damping built per speed), and
    :class:`jaxgear.planetary.PlanetaryModel` (a planetary stage in its carrier frame; its
    response is the stage's :class:`jaxgear.planetary.PlanetaryDynamics`, not a
    :class:`~jaxgear.dynamics.DynamicResponse`: the response type is the kind's, named by
    its :meth:`independent`).

    A run is two calls: :meth:`prepare` (the speed-independent work at one resolved step count:
    the checked run settings, a lumped model's mesh table and static rows, a hybrid model's
    modal basis) and :meth:`independent` or :meth:`continuation` (the speeds).

    What a kind supports beyond a run is declared on it, never looked for on the object: each
    class attribute below names a capability and the method that serves it, whose default here
    refuses in one line before any work (:attr:`continues`: :meth:`continuation`;
    :attr:`whine_methods`: :meth:`whine`; :attr:`settles`: :meth:`settling_measures`;
    :attr:`runs_from_position`: :meth:`independent_at`; :attr:`automatic_span`:
    :meth:`resolve_window`; :attr:`band_factor`: :meth:`mesh_force_ratios`). A kind that
    declares one implements its method. The run settings it takes are declared alike, by
    their types (:attr:`integrators`, :attr:`contact_laws`), so that a command refuses
    another from the class, before building the model.
    """

    scene: eqx.AbstractVar[DynamicScene | HybridPair]
    mods: eqx.AbstractVar[Modifications]
    torque: eqx.AbstractVar[Float[Array, ""]]

    #: whether a sweep may continue from one speed's steady state to the next
    #: (:meth:`continuation`); a model without it sweeps independent speeds only
    continues: ClassVar[bool] = False
    #: the gear whine methods (:class:`~jaxgear.dynamics.AbstractWhineMethod` kinds)
    #: :func:`~jaxgear.dynamics.whine_response` solves for this kind; another is refused
    #: before any work (a case file's ``[whine] method`` at load)
    whine_methods: ClassVar[tuple[type, ...]] = ()
    #: whether :func:`~jaxgear.dynamics.settled_sweep` runs the kind: it continues from speed
    #: to speed (:attr:`continues`) and answers :meth:`settling_measures`; another kind is
    #: refused before any work (``jaxgear sweep`` with ``periods = "auto"`` then resolves the
    #: kind's own window)
    settles: ClassVar[bool] = False
    #: whether :meth:`independent_at` runs a window from any mesh position (Newmark): a settled
    #: sweep's windows of one scene period then begin after a lead where the last one ended,
    #: and :func:`~jaxgear.dynamics.simulate` takes a ``start_period``
    runs_from_position: ClassVar[bool] = False
    #: whether the kind takes a flexible housing (a :class:`~jaxgear.scenes.HousingMount`
    #: seating its bearings or members; a scene's model through its scene kind's own
    #: :attr:`~jaxgear.scenes.Scene.takes_housing`): a case's ``[housing]`` is refused at
    #: load for a kind without it
    takes_housing: ClassVar[bool] = False
    #: the integrator kinds the kind runs (:class:`~jaxgear.dynamics.Newmark`,
    #: :class:`~jaxgear.dynamics.DiffraxIntegrator`): another is refused before any work, from
    #: the class (``jaxgear sweep --solver`` at load, :meth:`runs`) and by
    #: :meth:`check_integrator` on a model (which refuses an instance's other limits too, a
    #: modal basis where the kind has none)
    integrators: ClassVar[tuple[type, ...]] = (Newmark,)
    #: the contact laws the kind runs (:class:`~jaxgear.ExactContact`,
    #: :class:`~jaxgear.SmoothContact`); another is refused before any work (``jaxgear sweep
    #: --contact`` at load, :func:`~jaxgear.dynamics.resolve_settings` on a run)
    contact_laws: ClassVar[tuple[type, ...]] = (ExactContact, SmoothContact)

    @classmethod
    def runs(cls, setting) -> bool:
        """Whether the kind runs ``setting``, an integrator or a contact law, by its type
        (:attr:`integrators`, :attr:`contact_laws`): asked of the class, no model built."""
        return isinstance(setting, cls.integrators + cls.contact_laws)

    #: whether :func:`~jaxgear.dynamics.band_dynamic_factor` runs the kind: its response
    #: gives each mesh's force over its static force at every kept step
    #: (:meth:`mesh_force_ratios`); another kind is refused before any work
    band_factor: ClassVar[bool] = False

    @property
    def mesh(self) -> MeshModel:
        return self.scene.mesh

    @property
    def static_force(self) -> Float[Array, ""]:
        """Static flank-normal mesh force F_s = T/(r_b1 cos β_b) (N)."""
        return self.mesh.normal_load(self.torque)

    @property
    def dtype(self):
        """The floating dtype of the model's arrays (its scene's)."""
        return self.scene.base_planes[0].base_pitch.dtype

    # What the engine entries (resolve_settings, auto_steps_per_period, the settled sweep)
    # read of the model's meshes: by default its scene's, a kind without a scene (a planetary
    # stage) answers them itself.

    def mesh_count(self) -> int:
        """The meshes m of the model (static): the records' per-mesh outputs."""
        return len(self.scene.base_planes)

    def scene_periods(self) -> int:
        """Periods of the first mesh after which every mesh repeats together (static;
        :meth:`~jaxgear.scenes.Scene.scene_periods`)."""
        return self.scene.scene_periods()

    def coast_flanks(self) -> bool:
        """Whether a mesh has coast flanks (backlash; static)."""
        return any(p.coast for p in self.scene.base_planes)

    def mesh_period_angle(self):
        """θ_m: the speed's member's rotation (rad) over one period of the first mesh (2π/z1
        for a pair): f_mesh = Ω / θ_m at speed Ω (rad/s). Concrete or traced."""
        return self.scene.base_planes[0].mesh_period_angle

    def mesh_rates(self) -> list[float]:
        """Each mesh's periods per period of the first, m floats (1 for a pair; concrete:
        a traced model raises JAX's concretization error): its angle's rate over its own
        period."""
        planes = self.scene.base_planes
        angle = float(planes[0].mesh_period_angle)
        return [
            (float(b) - float(a)) * angle / float(p.mesh_period_angle)
            for a, b, p in zip(
                self.scene.mesh_angles(0.0), self.scene.mesh_angles(1.0), planes, strict=True
            )
        ]

    def structure_matrices(self) -> tuple:
        """(M, K_s): the structure's mass and stiffness (no mesh), each (n, n)."""
        return self.scene.mass(), self.scene.stiffness()

    def steps_per_mode(self) -> int:
        """The automatic step's steps per period of the highest excited mode
        (:func:`~jaxgear.dynamics.auto_steps_per_period`; static): :data:`STEPS_PER_MODE`
        (40) by default; a kind whose runs carry their own (a gearbox's ``GearboxRun``)
        answers it."""
        return STEPS_PER_MODE

    @abc.abstractmethod
    def default_settings(self) -> tuple[Integrator, ContactLaw, SteadyState]:
        """The kind's (integrator, contact law, steady-state window) where a run passes None."""

    @abc.abstractmethod
    def check_integrator(self, integrator: Integrator) -> None:
        """Raise ``ValueError`` (one line, before any work) for an integrator the kind cannot
        run (a diffrax solver on a hybrid model, a modal basis on a lumped one)."""

    @abc.abstractmethod
    def span_periods(self) -> int:
        """Periods of the first mesh that a run's records must cover (static)
        (:func:`span_periods`)."""

    @abc.abstractmethod
    def steps_multiple(self) -> int:
        """D of :func:`~jaxgear.dynamics.auto_steps_per_period` (static)."""

    @abc.abstractmethod
    def averaged_modes(
        self, *, speed=0.0, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
    ) -> ModalAnalysis:
        """The modes of (M, K + K̄_m), K̄_m the loaded mesh stiffness averaged over a mesh
        period (:func:`~jaxgear.dynamics.mesh_averaged_modes`)."""

    def natural_modes(
        self, *, speed=0.0, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
    ) -> ModalAnalysis:
        """The natural modes the kind lists to a user (``jaxgear modes``): by default the
        mesh-averaged modes (:meth:`averaged_modes`, the arguments theirs); a kind whose listing
        is another view of it answers its own (a gearbox without a shared housing: its torsional
        chain, :meth:`jaxgear.gearbox.GearboxModel.natural_modes`), with the shares of kinetic
        energy per group of coordinates where it groups them (:attr:`ModalAnalysis.kinetic`)."""
        return self.averaged_modes(
            speed=speed, positions_per_pitch=positions_per_pitch, contact=contact
        )

    @abc.abstractmethod
    def prepare(
        self,
        integrator: Integrator,
        law: ContactLaw,
        window: SteadyState,
        steps_per_period: int,
        outputs: Outputs,
        modes: ModalAnalysis | None = None,
    ) -> eqx.Module:
        """The speed-independent part of a run at ``steps_per_period`` steps per mesh period
        (an int, resolved), with checked settings; ``modes``: the averaged modes when the step
        count was chosen from them (automatic steps), else None. Raises ``ValueError`` for a
        run that does not fit (before any work)."""

    #: whether the kind resolves a window of automatic span (``SteadyState(periods=None)``,
    #: :meth:`resolve_window`)
    automatic_span: ClassVar[bool] = False

    def resolve_window(self, window: SteadyState, speeds, steps, modes=None):
        """The window of a run over the concrete ``speeds`` (S,) at the step counts ``steps``
        (S,) where ``window.periods`` is None (the automatic span; :attr:`automatic_span`
        kinds only, the engine refuses it for the others before any work): what
        :meth:`prepare` and :meth:`prepare_steps` take; ``modes``: the averaged modes where
        the engine computed them, else None. The default returns ``window``."""
        return window

    def prepare_steps(
        self,
        integrator: Integrator,
        law: ContactLaw,
        window: SteadyState,
        steps: tuple[int, ...],
        outputs: Outputs,
        modes: ModalAnalysis | None = None,
    ):
        """One compiled program for the several step counts ``steps`` (the distinct automatic
        N_s of a sweep, ascending): a function N_s ↦ what :meth:`prepare` returns, whose runs
        (:meth:`independent`, :meth:`continuation`) share one compiled program (N_s an
        argument of it, the records of a buffer of the largest N_s, the histories returned
        at the smallest); or None where the kind cannot (each N_s its own program, by
        :meth:`prepare`): the default. Raises ``ValueError`` as :meth:`prepare`."""
        return None

    @abc.abstractmethod
    def independent(self, prepared, speeds, *, start=None, shard: bool = False):
        """The kind's response (a pair's and a train's: :class:`~jaxgear.dynamics.DynamicResponse`;
        a planetary stage's: :class:`jaxgear.planetary.PlanetaryDynamics`; each with a
        ``result`` code) at each of ``speeds`` (S,) (leading axis S)
        or at one scalar speed (no leading axis), each from ``start`` ((X, Ẋ), the kind's own
        start when None); ``shard``: spread the speeds over the local devices."""

    def continuation(self, prepared, speeds, *, start=None):
        """The speeds (S,) one after the other, each from the previous steady state (a failed
        one restarts from the static equilibrium); (2, S): two such scans side by side.
        Models with :attr:`continues` only."""
        raise ValueError(
            f"{type(self).__name__} sweeps independent speeds only (allowed direction "
            "Independent())"
        )

    def independent_at(self, prepared, speed, step, start, lead=0):
        """One speed (a scalar, rad/s) from ``start`` = (X, Ẋ) at the mesh position ``step``
        (an int >= 0, steps of the prepared run) after ``lead`` steps unrecorded: (the
        response of the window that starts at step ``step + lead``, the state (X, Ẋ) there).
        Kinds with :attr:`runs_from_position` only; the default raises ``ValueError`` (one
        line)."""
        raise ValueError(
            f"model = {type(self).__name__}: its runs start at mesh position 0 (allowed "
            "start_period = 0)"
        )

    def settling_measures(self) -> tuple[Float[Array, "n n"], Float[Array, ""]]:
        """(C, k̄): the damping matrix (n, n) whose modal damping ratios set a settled sweep's
        settling time, and the mean loaded mesh stiffness k̄ (N/m) that a state's change is
        weighed by (:func:`~jaxgear.dynamics.settled_sweep`). Kinds with :attr:`settles`
        only; the default raises ``ValueError`` (one line)."""
        raise ValueError(
            f"model = {type(self).__name__}: does not settle (allowed a kind that settles, a "
            "lumped DynamicModel)"
        )

    def mesh_force_ratios(self, response) -> tuple[Float[Array, "... K"], ...]:
        """Each mesh's force over its static force F/F_s (-) at every kept step of the kind's
        ``response`` (what :meth:`independent` returns; a sweep's with a leading speed axis):
        one array (..., K) per mesh, differentiable (the objective of
        :func:`~jaxgear.dynamics.band_dynamic_factor`). Kinds with :attr:`band_factor` only;
        the default raises ``ValueError`` (one line)."""
        raise ValueError(band_refusal(self))

    def check_whine_method(self, method) -> None:
        """Raise ``TypeError`` (one line, before any work) where the kind has no gear whine
        or ``method`` is not one of its :attr:`whine_methods`."""
        kind = type(self).__name__
        if not self.whine_methods:
            raise TypeError(f"model: {kind} has no gear whine (its whine_methods is empty)")
        allowed = ", ".join(f"{c.__name__}(...)" for c in self.whine_methods)
        if not isinstance(method, AbstractWhineMethod):
            raise TypeError(f"method = {method!r}: allowed {allowed}")
        if not isinstance(method, self.whine_methods):
            raise TypeError(
                f"method = {type(method).__name__}(...): not for a {kind} (its whine methods: "
                f"{allowed})"
            )

    def whine(
        self,
        speeds,
        method: AbstractWhineMethod,
        *,
        positions: int = 256,
        contact: ContactLaw = ExactContact(),
    ):
        """The kind's gear whine in the frequency domain at ``speeds`` (rad/s, scalar or (S,)):
        a :class:`~jaxgear.dynamics.WhineResponse`; :func:`~jaxgear.dynamics.whine_response`
        checks ``method`` against :attr:`whine_methods` (:meth:`check_whine_method`) and calls
        this. Kinds with :attr:`whine_methods` implement it; the default raises ``TypeError``
        (one line)."""
        raise TypeError(f"model: {type(self).__name__} has no gear whine (its whine_methods is "
                        "empty)")


def band_refusal(model: AbstractDynamicModel) -> str:
    """The one line that refuses ``model`` a band dynamic factor (its kind has no
    :attr:`~AbstractDynamicModel.band_factor`)."""
    return (
        f"model = {type(model).__name__}: has no band dynamic factor (its band_factor is False: "
        "its response does not give each mesh's force over its static force at every kept "
        "step; allowed a lumped DynamicModel or a HybridModel)"
    )


def span_periods(model: AbstractDynamicModel) -> int:
    """Periods of the first mesh that the mesh table of ``model`` spans, and that the kept
    window of a run must cover (static): the scene's period
    (:meth:`~jaxgear.scenes.Scene.scene_periods`) times, with manufacturing deviations on a
    :class:`DynamicModel`, its ``deviation_span`` or else :func:`deviation_periods` (the
    hunting period of the deviating members: z1 for the pinion's alone, lcm(z1, z2) for both)."""
    return model.span_periods()
