"""The Newmark step with unilateral contact: the one time integrator of every scene.

Average acceleration (β = 1/4, γ = 1/2; seed annex 2, (2.1)–(2.6)) for

    M Ẍ + C(t) Ẋ + K X + Σ_c P_c(V_c·X − δ0_c) V_c = F,

with P_c = k_c l_c φ(Δ_c) the cell forces (seed (2.9)/(2.30); docs/dynamics.md, "Model"). Each step
is a static contact problem K_eff X = F_eff − Vᵀ P with K_eff = K + a₀ M + a₁ C, a₀ = 1/(βΔt²),
a₁ = γ/(βΔt), solved in whichever space is smaller (docs/design.md, "Contact laws"):

* **coordinates** (the rigid-node scenes: a few tens of DOFs against tens of cells): the
  cells see every coordinate; :func:`jaxgear.solve_contact` factors K_eff + Vᵀ diag(k l) V at each
  active-set pass (seed II-25);
* **cells** (condensed bodies: thousands of DOFs, the cells on a small window W of them):
  G = K_eff⁻¹ and the products G F, G M, G C once per speed, X* = G F_eff = G F + (G M) u +
  (G C) v (u, v the known parts of Newmark's M and C terms), the gaps Δ = V X*_W − δ0 − C_eff P
  with the window's compliance C_eff = V G_WW Vᵀ (:func:`jaxgear.solve_contact_cells`), then
  X = X* − G_{:W} Vᵀ P on the window's columns: a step costs two n² products and the window's
  compliance, not a factorisation (docs/hybrid.md, "Dynamics");
  or, with a modal basis (:func:`newmark_modal`), m modes of the assembled structure plus the
  static correction of the cells: m² + n (m + w) per step (docs/hybrid.md, "Modal basis").

A mesh damping that follows the mesh (the hybrid scene's Rayleigh and composite models) is a
rank-w change of C per block of steps, taken by Woodbury in the cell space (:class:`MeshDamping`).

One loop serves every space (:class:`_Loop`): the blocks, the steps, the result codes and the
records; a space (:class:`_Coordinates`, :class:`_Cells`, :class:`_Modal`) says how a step's
contact problem is solved in it.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any, NamedTuple

import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._baseplane import CellRow
from .._contact import ContactLaw, solve_contact, solve_contact_cells
from .._results import ContactResult, DynamicsResult

BETA, GAMMA = 0.25, 0.5


class MeshDamping(NamedTuple):
    """The mesh share of the damping, C(p) = C + c_m Rᵀ K̄_m(p) R in block p of steps.

    Attributes:
        block: p ↦ (U (w,), B (w, w), ok): K̄_m(p) = E_Uᵀ B E_U on the window U of coordinates
            (E_U (w, n) picks them) and whether every window of the block lies inside U.
        c_m: its factor (s for Rayleigh, - for the composite).
        R: (n, n), or None for the identity (Rayleigh: C(p) = C + β K̄_m(p)).
    """

    block: Callable
    c_m: Float[Array, ""]
    R: Float[Array, "n n"] | None


class StaticCondensation(NamedTuple):
    """A linear system K X = F condensed onto the coordinates J that the cells reach (static
    condensation: exact where nothing but F acts on the others, I), for solving many contact
    problems of one K (:func:`static_condensation`; not the Craig–Bampton condensation of
    the FE bodies, :func:`fem_prep.condensed`): S X_J = F_J − K_JI K_II⁻¹ F_I with
    S = K_JJ − K_JI K_II⁻¹ K_IJ, then X_I = K_II⁻¹ (F_I − K_IJ X_J).

    Attributes:
        J, I: the kept and the eliminated coordinates (j,) and (n − j,).
        S: the condensed matrix (j, j). KJI: K_JI (j, n − j). H: K_II⁻¹ K_IJ (n − j, j).
        lu: the LU factors of K_II (:func:`jax.scipy.linalg.lu_factor`).
    """

    J: Array
    I: Array
    S: Array
    KJI: Array
    H: Array
    lu: tuple

    def load(self, F) -> tuple[Array, Array]:
        """(F_J − K_JI K_II⁻¹ F_I (j,), K_II⁻¹ F_I (n − j,)) for a load F (n,)."""
        y = jax.scipy.linalg.lu_solve(self.lu, F[self.I])
        return F[self.J] - self.KJI @ y, y

    def expand(self, XJ, y) -> Array:
        """X (n,) from X_J (j,) and y = K_II⁻¹ F_I (:meth:`load`)."""
        n = self.J.shape[0] + self.I.shape[0]
        return jnp.zeros((n,), XJ.dtype).at[self.J].set(XJ).at[self.I].set(y - self.H @ XJ)


def static_condensation(K: Float[Array, "n n"], dofs: tuple) -> StaticCondensation:
    """``K`` (n, n; any square K with K_II invertible) condensed onto the coordinates ``dofs``
    (a static, sorted tuple; :meth:`~jaxgear.scenes.Scene.contact_dofs`):
    :class:`StaticCondensation`."""
    n = K.shape[0]
    kept = set(dofs)
    J = jnp.asarray(dofs)
    I = jnp.asarray([i for i in range(n) if i not in kept], dtype=J.dtype)
    lu = jax.scipy.linalg.lu_factor(K[I[:, None], I[None, :]])
    H = jax.scipy.linalg.lu_solve(lu, K[I[:, None], J[None, :]])
    KJI = K[J[:, None], I[None, :]]
    return StaticCondensation(J, I, K[J[:, None], J[None, :]] - KJI @ H, KJI, H, lu)


def contact_coordinates(scene, n: int, condense: bool = True) -> tuple | None:
    """The coordinates to condense a scene's contact problems onto (static): its
    :meth:`~jaxgear.scenes.Scene.contact_dofs`, or None (solve on all ``n``) where it does not
    name them, where they are all of them, or with ``condense=False``."""
    dofs = scene.contact_dofs() if condense else None
    return None if dofs is None or len(dofs) == n else tuple(dofs)


def _no_steps(inputs, record) -> bool:
    """True when ``inputs`` hold no step (B · S = 0): an unrecorded transient of zero periods
    (``SteadyState(periods, keep_periods=periods)``); a recorded run must have steps."""
    shape = jax.tree.leaves(inputs)[0].shape
    if shape[0] * shape[1]:
        return False
    if record is not None:
        raise ValueError("newmark: no step to record (the kept window is empty)")
    return True


class LinearSystem(NamedTuple):
    """What :func:`newmark` integrates: M Ẍ + C(t) Ẋ + K X = F − Vᵀ P on n coordinates.

    Attributes:
        K, M, C: stiffness, mass and damping (SI per coordinate), (n, n); C may hold a skew
            Coriolis term. F: the constant load (n,).
        mesh_damping: the mesh share of C that follows the mesh (:class:`MeshDamping`; needs
            a window: the cell space), or None.
        dofs: rows on all coordinates only: the coordinates the cells reach (static, sorted;
            :func:`contact_coordinates`); K_eff is condensed onto them once
            (:func:`static_condensation`) and each step's contact solved on them alone. None:
            on all.
    """

    K: Float[Array, "n n"]
    M: Float[Array, "n n"]
    C: Float[Array, "n n"]
    F: Float[Array, " n"]
    mesh_damping: MeshDamping | None = None
    dofs: tuple | None = None


class StepCells(NamedTuple):
    """The cells of a Newmark run's steps (:func:`newmark`): ``at``: a step's entry of the
    inputs ↦ its :class:`CellRow` (all steps the same window kind, None or not); ``law``: the
    contact law. Any object with these two serves (the hybrid scene's ``SceneCells``)."""

    at: Callable[[Any], CellRow]
    law: ContactLaw


def newmark(
    system: LinearSystem,
    dt,
    state,
    inputs,
    cells: StepCells,
    record: Callable[[Array, Array, Array, Any], Any] | None,
    *,
    checks: tuple = (None, None),
    keep_blocks: int | None = None,
    load: Callable[[Any], Array] | None = None,
):
    """Integrate ``inputs``' steps by Newmark average acceleration with the contact loop.

    Args:
        system: :class:`LinearSystem` (K, M, C, F, the mesh damping, the contact coordinates).
        dt: time step Δt (s).
        state: (X, Ẋ, Ẍ, result code, most contact passes), the first three (n,).
        inputs: one entry per step, leading shape (B, S): B blocks of S steps (the blocks of
            the mesh damping, e.g. mesh periods; B = 1 without it). An entry is whatever
            ``cells.at`` takes (a table row index, a pinion angle).
        cells: :class:`StepCells` (entry ↦ :class:`CellRow`, the contact law).
        record: (X, Ẋ, P, entry) ↦ a pytree kept for every recorded step, P the cell forces
            (N), (c,), entry the step's entry of ``inputs`` (to reduce per-cell values that
            depend on the position inside the loop); None keeps nothing (a transient).
        checks: (check, block_check). check: (X, Ẋ, P) ↦ a :class:`~jaxgear.DynamicsResult`
            code of the step (e.g. the mesh force beyond its bound: code 3), 0 if none, or
            None; the loop itself flags contact loops that did not converge, non-finite states
            and cells outside the mesh damping's window. block_check: (X, Ẋ) ↦ a result code
            of the state at the end of each block, or None: the place for a check that costs a
            product with an n × n matrix (the kinetic energy ½ ẊᵀMẊ), paid once per block
            (e.g. mesh period) instead of every step; it fires at the end of the block in
            which the state crossed its bound.
        keep_blocks: record only the last ``keep_blocks`` blocks (the steady-state window: the
            blocks before integrate without records), or None: every block.
        load: entry ↦ a load (n,) added to F at the step's end (a time-varying force: a
            rotating unbalance), or None (F alone).

    Returns:
        (the final state, the records flattened over the recorded blocks, leading axis
        min(B, keep_blocks)·S, or None). The result code keeps the first failure of the run.
    """
    if _no_steps(inputs, record):  # a steady-state window with no transient before it
        return state, None
    first = jax.tree.map(lambda x: x[0, 0], inputs)
    K, M, C, F, mesh_damping, dofs = system
    if jax.eval_shape(cells.at, first).idx is None:
        if mesh_damping is not None:
            raise ValueError("a mesh damping needs the cell space (a window of coordinates)")
        space = _Coordinates(K, M, C, F, dt, dofs)
    else:
        space = _Cells(K, M, C, F, dt, mesh_damping)
    loop = _Loop(space, cells, *checks, load=load)
    return _scan_blocks(loop.run_block, state, inputs, record, keep_blocks)


def newmark_counted(
    system: LinearSystem,
    dt,
    state,
    first,
    count,
    cells: StepCells,
    record: Callable[[Array, Array, Array, Any], Any] | None,
    size: int = 0,
    *,
    checks: tuple = (None, None),
):
    """:func:`newmark` over a traced number of steps (one block, no mesh damping): the
    entries ``first + 1``, ..., ``first + count`` (``count`` an int that may be traced, e.g. a
    whole number of mesh periods of a step count N_s that is an argument of the compiled
    program: one program serves every N_s of a sweep). ``lax.fori_loop`` with traced bounds; the
    same step as :func:`newmark` (bit for bit the same arithmetic).

    Args:
        system, dt, state, cells, checks: as :func:`newmark` (``cells.at`` takes a step index;
            the contact in coordinates: no window, no mesh damping).
        first: the step before the first entry (int, may be traced).
        count: the steps to run (int, may be traced), 0 <= count <= ``size`` when recording.
        record: as :func:`newmark`, or None (a transient: nothing kept).
        size: the length of the record buffer (static): the records of step i < ``count`` at
            row i, the rows from ``count`` on zero.

    Returns:
        (the final state, the records with leading axis ``size``, or None).
    """
    K, M, C, F, mesh_damping, dofs = system
    if mesh_damping is not None or jax.eval_shape(cells.at, first).idx is not None:
        raise ValueError("newmark_counted: the contact in coordinates only (no window)")
    loop = _Loop(_Coordinates(K, M, C, F, dt, dofs), cells, *checks)
    blk, ok = loop.space.block(None)
    first = jnp.asarray(first)
    if record is None:

        def body(i, carry):
            return loop.step(carry, first + 1 + i, blk, ok, None)[0]

        return jax.lax.fori_loop(0, count, body, state), None
    shapes = jax.eval_shape(lambda c: loop.step(c, first + 1, blk, ok, record)[1], state)
    buffer = jax.tree.map(lambda s: jnp.zeros((size,) + s.shape, s.dtype), shapes)

    def body_rec(i, carry_buf):
        carry, buf = carry_buf
        carry, out = loop.step(carry, first + 1 + i, blk, ok, record)
        return carry, jax.tree.map(lambda b, o: b.at[i].set(o), buf, out)

    return jax.lax.fori_loop(0, count, body_rec, (state, buffer))


class _Loop:
    """The Newmark loop of :func:`newmark` and :func:`newmark_modal` in any space (the
    coordinates, the cell space, a modal basis: :class:`_Space`): blocks of steps, each step's
    contact problem solved by the space, its result code (the first failure sticks: the
    contact loop, non-finite states, the caller's ``check``, a window outside the block's mesh
    damping window), the records of the kept blocks and the ``block_check`` at each block's
    end."""

    def __init__(self, space, cells, check, block_check, load=None):
        self.space, self.cells_at, self.law = space, cells.at, cells.law
        self.check, self.block_check, self.load = check, block_check, load

    def step(self, carry, entry, blk, ok, keep):
        """One step from ``carry`` (the state, its result code and most contact passes) at
        ``entry``, in a block of quantities ``blk`` (window inside it: ``ok``): (the new carry,
        ``keep(X, Ẋ, P, entry)`` or None)."""
        space = self.space
        *x, code, it = carry
        extra = None if self.load is None else self.load(entry)
        xn, sol, P, inside = space.step(tuple(x), self.cells_at(entry), blk, self.law, extra)
        checked = None if self.check is None else self.check(xn[0], xn[1], P)
        new = _step_result(sol, space.finite(xn), checked)
        new = _first(new, jnp.where(inside & ok, 0, DynamicsResult.window_overflow))
        carry = (*xn, _first(code, new), jnp.maximum(it, sol.iterations))
        if keep is None:
            return carry, None
        X, Xd = space.observed(xn)
        return carry, keep(X, Xd, P, entry)

    def run_block(self, carry, p_in, keep):
        p, entries = p_in
        blk, ok = self.space.block(p)
        carry, out = jax.lax.scan(lambda c, e: self.step(c, e, blk, ok, keep), carry, entries)
        if self.block_check is not None:
            *x, code, it = carry
            carry = (*x, _first(code, self.block_check(x[0], x[1])), it)
        return carry, out


class _Space:
    """The coordinates a Newmark run steps in (average acceleration, β = 1/4, γ = 1/2): the
    scheme's constants and how a step's contact problem is solved there. ``x`` is the state
    without the result code and the contact passes: (X, Ẋ, Ẍ) on the coordinates, (q, q̇, q̈,
    r, ṙ, r̈) in a modal basis; a step's check and a block's check get its first two."""

    def __init__(self, dt):
        self.dt = dt
        self.a0, self.a1 = 1.0 / (BETA * dt * dt), GAMMA / (BETA * dt)

    def block(self, p):
        """The quantities of block ``p`` (its mesh damping's; None without) and whether every
        window of the block lies inside its mesh damping's window."""
        return None, jnp.array(True)

    def known(self, x, xd, xdd):
        """Newmark's known parts of a step's velocity and acceleration terms, (v, u): the
        damping force is C (a₁ x_{n+1} − v), the inertia M (a₀ x_{n+1} − u)."""
        b, g, dt = BETA, GAMMA, self.dt
        v = self.a1 * x + (g / b - 1.0) * xd + dt * (0.5 * g / b - 1.0) * xdd
        u = self.a0 * x + xd / (b * dt) + (0.5 / b - 1.0) * xdd
        return v, u

    def finite(self, x) -> tuple:
        """The parts of a new state that must be finite."""
        return (x[0], x[1])

    def observed(self, x) -> tuple:
        """(X, Ẋ) on the coordinates, what the records get."""
        return (x[0], x[1])


class _Coordinates(_Space):
    """The contact in coordinates (the rigid-node scenes): each step's contact problem
    K_eff X = F_eff − Vᵀ P factored by :func:`jaxgear.solve_contact`, on the coordinates the
    cells reach (``dofs``: :func:`static_condensation` of K_eff, once) or on all (None)."""

    def __init__(self, K, M, C, F, dt, dofs):
        super().__init__(dt)
        self.M, self.C, self.F = M, C, F
        self.Keff = K + self.a0 * M + self.a1 * C
        self.reduced = None if dofs is None else static_condensation(self.Keff, dofs)

    def step(self, x, row, blk, law, extra=None):
        X, Xd, Xdd = x
        v, u = self.known(X, Xd, Xdd)
        Feff = self.F + self.M @ u + self.C @ v
        if extra is not None:
            Feff = Feff + extra
        reduced = self.reduced
        if reduced is None:
            Ks, Fs, Vs = self.Keff, Feff, row.V
        else:  # on the coordinates the cells reach
            (Fs, y), Ks, Vs = reduced.load(Feff), reduced.S, row.V[:, reduced.J]
        sol = solve_contact(Ks, Fs, Vs, row.k, row.length, row.delta0, row.mask, law)
        Xn = sol.x if reduced is None else reduced.expand(sol.x, y)
        P = sol.force_density * row.length
        Xdn, Xddn = _update(Xn, X, Xd, Xdd, self.a0, self.dt)
        return (Xn, Xdn, Xddn), sol, P, jnp.array(True)


class _Cells(_Space):
    """The contact in the cell space (condensed bodies): G = K_eff⁻¹ and G F, G M, G C once
    per speed, each step's gaps on the window's compliance
    (:func:`jaxgear.solve_contact_cells`), a block's mesh damping (:class:`MeshDamping`) by
    Woodbury on G."""

    def __init__(self, K, M, C, F, dt, mesh_damping: MeshDamping | None):
        super().__init__(dt)
        self.G = G = jnp.linalg.inv(K + self.a0 * M + self.a1 * C)
        self.dtype, self.n = K.dtype, K.shape[0]
        # G F_eff = G F + (G M) u + (G C) v: two n² reads a step, not three
        self.GF, self.GM, self.GC = G @ F, G @ M, G @ C
        self.mesh_damping = mesh_damping
        if mesh_damping is not None:
            R = mesh_damping.R
            self.GR = G if R is None else G @ R.T  # G Rᵀ (n, n): G Wᵀ = (G Rᵀ)[:, U]

    def block(self, p):
        if self.mesh_damping is None:
            return None, jnp.array(True)
        block, c_m, R = self.mesh_damping
        G, dtype = self.G, self.dtype
        U, B, ok = block(p)
        w = U.shape[0]
        if R is None:  # W = E_U

            def project(x):  # W x, x (n,) or (n, m)
                return x[U]

        else:
            W = R[U]

            def project(x):
                return W @ x

        # the block's effective stiffness is K_eff + a₁ c_m Wᵀ B W: Woodbury on G,
        # G_p = G − (G Wᵀ) Q (W G), Q = (I + A W G Wᵀ)⁻¹ A, A = a₁ c_m B
        A = (self.a1 * c_m) * B
        GW = self.GR[:, U]  # G Wᵀ (n, w)
        GU = GW if R is None else G[:, U]  # G E_Uᵀ (n, w)
        Q = jnp.linalg.solve(jnp.eye(w, dtype=dtype) + A @ project(GW), A)
        GUU = GU[U] - GW[U] @ Q @ project(GU)  # G_p on U
        pos = jnp.full((self.n,), w, jnp.int32).at[U].set(jnp.arange(w, dtype=jnp.int32))
        return (U, B, c_m, project, GW, GU, Q, GUU, pos), ok

    def step(self, x, row, blk, law, extra=None):
        X, Xd, Xdd = x
        G, dtype = self.G, self.dtype
        v, u = self.known(X, Xd, Xdd)
        idx = row.idx
        inside = jnp.array(True)
        y = self.GF + self.GM @ u + self.GC @ v  # G F_eff
        if extra is not None:
            y = y + G @ extra
        if blk is None:
            Gw = G[idx[:, None], idx[None, :]]
            xs = y
        else:
            U, B, c_m, project, GW, GU, Q, GUU, pos = blk
            # the block's mesh damping's force Wᵀ c_m B W v: G Wᵀ = GW
            y = y + GW @ (c_m * (B @ project(v)))
            xs = y - GW @ (Q @ project(y))  # G_p F_eff (Woodbury)
            j = pos[idx]
            inside = jnp.all(j < U.shape[0])
            Gw = GUU[j[:, None], j[None, :]]
        sol, P = _window_contact(row, Gw, xs[idx], law, dtype)
        z = row.V.T @ P
        if blk is None:  # G_p[:, idx] z: the columns of the window, not an n² product
            Xn = xs - G[:, idx] @ z
        else:
            yz = GU @ jnp.zeros((U.shape[0],), dtype).at[j].add(z, mode="drop")
            Xn = xs - (yz - GW @ (Q @ project(yz)))
        Xdn, Xddn = _update(Xn, X, Xd, Xdd, self.a0, self.dt)
        return (Xn, Xdn, Xddn), sol, P, inside


class ModalStructure(NamedTuple):
    """The structure of :func:`newmark_modal`: m modal coordinates q plus the static correction
    of the forces, X = D q + G (F − Vᵀ P) (docs/hybrid.md, "Modal basis").

    Attributes:
        D: (n, m) the modes with their static residual, D = Φ_m − G K Φ_m (-).
        G: (n, n) the residual flexibility (m/N per coordinate): the part of the structure's
            flexibility outside the m modes; zero with all modes.
        xF: (n,) G F, the static correction of the constant load F (m).
    """

    D: Float[Array, "n m"]
    G: Float[Array, "n n"]
    xF: Float[Array, " n"]


class ModalSystem(NamedTuple):
    """What :func:`newmark_modal` integrates: the reduced structure and its damping.

    Attributes:
        Kr, Mr, Cr: the reduced stiffness, mass and damping Dᵀ K D, Dᵀ M D, Dᵀ C D, (m, m)
            (C without the mesh share). Fr: Dᵀ F (m,). space: :class:`ModalStructure`.
        residual_damping: β_r (s), >= 0.
        mesh_damping: :class:`MeshDamping` with ``R`` None (on the coordinates of U, as the
            cell space's) or the reduced map (n, m) (W_r = R[U]: c_m W_rᵀ B W_r on q), or None.
    """

    Kr: Float[Array, "m m"]
    Mr: Float[Array, "m m"]
    Cr: Float[Array, "m m"]
    Fr: Float[Array, " m"]
    space: ModalStructure
    residual_damping: Any = 0.0
    mesh_damping: MeshDamping | None = None


def newmark_modal(
    system: ModalSystem,
    dt,
    state,
    inputs,
    cells: StepCells,
    record: Callable[[Array, Array, Array, Any], Any] | None,
    *,
    checks: tuple = (None, None),
    keep_blocks: int | None = None,
    load: Callable[[Any], Array] | None = None,
):
    """:func:`newmark` in a modal basis with the static correction of the cells: the same
    average-acceleration scheme and contact loop (the cells of each step solved exactly on their
    window by :func:`jaxgear.solve_contact_cells`) for M_r q̈ + C_r q̇ + K_r q = Dᵀ f,
    X = D q + r, r + β_r ṙ = G f, f = F − Vᵀ P (+ the mesh damping's forces): the static
    correction r has no inertia; with ``residual_damping`` β_r (Rayleigh's β K on the
    residual, exact for it: Qᵀ K D = 0) it is a Kelvin–Voigt element, by Newmark's relations
    r_{n+1} = ρ (G f_{n+1} + β_r v_r), ρ = 1/(1 + a₁ β_r), v_r the known part of its velocity
    (docs/hybrid.md, "Modal basis").

    Each step: q* = G_r F_eff,r (G_r = (K_r + a₀ M_r + a₁ C_r)⁻¹, m × m, once per speed), the
    window's gaps from X*_W = D_W q* + (G F)_W, the contact problem on the window compliance
    H_WW = D_W G_r D_Wᵀ + ρ G_WW (the modes' effective flexibility plus the residual one), then
    q = q* − G_r D_Wᵀ Vᵀ P and X = D q + r: m² + n (m + w) per step instead of n². The
    residual r, ṙ, r̈ is carried on every coordinate, so that a mesh damping on the window's
    coordinates (Rayleigh's c_m K̄_m(p), ``R`` None) acts on the whole approach of the cells, static correction included: its force
    c_m B (v_U − a₁ X_U) on the block's window U (v the known part of Newmark's velocity) is
    solved with X_U, H'_UU = (H_UU⁻¹ + a₁ c_m B)⁻¹ (w³ per block). A mapped mesh damping
    (the composite's R) acts on the modal coordinates only: c_m (R D)_Uᵀ B (R D)_U in C_r.

    Args:
        system: :class:`ModalSystem` (the reduced structure, β_r and the mesh damping).
        dt, inputs, cells: as :func:`newmark` (``cells.at`` must give a window).
        state: (q, q̇, q̈, r, ṙ, r̈, result code, most contact passes): q's (m,), r's (n,).
        record: (X, Ẋ, P, entry) ↦ a pytree kept for every step (X = D q + r, Ẋ = D q̇ + ṙ),
            or None.
        checks: (check, block_check): (q, q̇, P) ↦ a result code of the step, or None;
            (q, q̇) ↦ a result code at the end of each block (on the reduced state: the
            kinetic energy is ½ q̇ᵀ M_r q̇), or None. keep_blocks, load: as :func:`newmark`
            (the load on the coordinates: Dᵀ on the modes, G on the residual).

    Returns:
        As :func:`newmark`; the state as ``state``.
    """
    if _no_steps(inputs, record):  # a steady-state window with no transient before it
        return state, None
    first = jax.tree.map(lambda x: x[0, 0], inputs)
    if jax.eval_shape(cells.at, first).idx is None:
        raise ValueError("the modal basis needs the cell space (a window of coordinates)")
    loop = _Loop(_Modal(system, dt), cells, *checks, load=load)
    return _scan_blocks(loop.run_block, state, inputs, record, keep_blocks)


class _Modal(_Space):
    """The contact in a modal basis with the static correction of the cells
    (:func:`newmark_modal`): G_r = K_eff,r⁻¹ once per speed, the window's compliance from the
    modes' and the residual's flexibility, a block's mesh damping on the window's coordinates
    (``R`` None: with X_U, w³ per block) or on the modal coordinates (a map)."""

    def __init__(self, system: ModalSystem, dt):
        super().__init__(dt)
        Kr, Mr, Cr, Fr, space, residual_damping, mesh_damping = system
        self.Mr, self.Cr, self.Fr = Mr, Cr, Fr
        self.dtype = Kr.dtype
        self.D, self.G, xF = space
        self.n = self.D.shape[0]
        self.Keff = Kr + self.a0 * Mr + self.a1 * Cr
        self.Gr = jnp.linalg.inv(self.Keff)
        self.beta_r = residual_damping
        self.rho = 1.0 / (1.0 + self.a1 * residual_damping)  # the residual's step flexibility
        self.xFr = self.rho * xF
        self.mesh_damping = mesh_damping
        self.local = mesh_damping is not None and mesh_damping.R is None
        if mesh_damping is None:  # the effective compliance on every coordinate (n, n)
            self.H = self.D @ self.Gr @ self.D.T + self.rho * self.G

    def block(self, p):
        if self.mesh_damping is None:
            return None, jnp.array(True)
        D, G, Gr, rho, a1 = self.D, self.G, self.Gr, self.rho, self.a1
        block, c_m, Wmap = self.mesh_damping
        U, B, ok = block(p)
        w = U.shape[0]
        DU = D[U]
        S = HUU = None
        Gp, Cp = Gr, self.Cr
        if self.local:  # c_m B on X_U: H'_UU = (I + a₁ c_m H_UU B)⁻¹ H_UU
            HUU = DU @ Gr @ DU.T + rho * G[U[:, None], U[None, :]]
            eye = jnp.eye(w, dtype=self.dtype)
            S = jnp.linalg.solve(eye + (a1 * c_m) * (HUU @ B), jnp.eye(w))
            H2 = S @ HUU  # (not symmetrised: a Coriolis term makes G_r unsymmetric)
        else:  # mapped: c_m W_rᵀ B W_r on the modal coordinates
            WD = Wmap[U]
            Cm = c_m * (WD.T @ B @ WD)
            Cp = self.Cr + Cm
            Gp = jnp.linalg.inv(self.Keff + a1 * Cm)
            H2 = DU @ Gp @ DU.T + rho * G[U[:, None], U[None, :]]
        pos = jnp.full((self.n,), w, jnp.int32).at[U].set(jnp.arange(w, dtype=jnp.int32))
        return (U, B, c_m, DU, S, HUU, H2, Gp, Cp, pos), ok

    def step(self, x, row, blk, law, extra=None):
        q, qd, qdd, r, rd, rdd = x
        D, G, a0, a1, rho, dtype = self.D, self.G, self.a0, self.a1, self.rho, self.dtype
        v, u = self.known(q, qd, qdd)
        vr, _ = self.known(r, rd, rdd)
        r0 = self.xFr + (rho * self.beta_r) * vr  # the residual before the step's forces
        Gp, Cp = (self.Gr, self.Cr) if blk is None else blk[7:9]
        Feff = self.Fr + self.Mr @ u + Cp @ v
        if extra is not None:  # a time-varying load: on the modes and the residual
            Feff, r0 = Feff + D.T @ extra, r0 + rho * (G @ extra)
        qs = Gp @ Feff
        idx = row.idx
        inside = jnp.array(True)
        if blk is None:  # the window's coordinates
            Hw = self.H[idx[:, None], idx[None, :]]
            Dr, j = D[idx], jnp.arange(idx.shape[0])
            x0 = Dr @ qs + r0[idx]
        else:  # the block's coordinates U, the window's at positions j
            U, B, c_m, DU, S, HUU, H2, _, _, pos = blk
            j = pos[idx]
            inside = jnp.all(j < U.shape[0])
            Hw = H2[j[:, None], j[None, :]]
            Dr = DU
            x0 = Dr @ qs + r0[U]
            if self.local:  # with the mesh damping's force on U (v_X = D v_q + v_r)
                vU = DU @ v + vr[U]
                x0 = S @ (x0 + HUU @ (c_m * (B @ vU)))
        sol, P = _window_contact(row, Hw, x0[j], law, dtype)
        # the forces on U (the window's when U is None): −Vᵀ P and the mesh damping's
        fU = -jnp.zeros(x0.shape, dtype).at[j].add(row.V.T @ P, mode="drop")
        if blk is not None and self.local:
            fU = fU + c_m * (B @ (vU - a1 * (x0 + H2 @ fU)))
        rows = idx if blk is None else U
        qn = qs + Gp @ (Dr.T @ fU)
        rn = r0 + rho * (fU @ G[rows])  # G symmetric: G_{:U} f = (fᵀ G_U:)ᵀ
        qdn, qddn = _update(qn, q, qd, qdd, a0, self.dt)
        rdn, rddn = _update(rn, r, rd, rdd, a0, self.dt)
        return (qn, qdn, qddn, rn, rdn, rddn), sol, P, inside

    def finite(self, x) -> tuple:
        # X = D q + r is finite where q and r are (D @ q only at the recorded steps)
        return (x[0], x[3], x[1])

    def observed(self, x) -> tuple:
        return (self.D @ x[0] + x[3], self.D @ x[1] + x[4])


def _window_contact(row, W, x, law: ContactLaw, dtype):
    """One step's contact problem in the window of ``row``'s cells: compliance V W Vᵀ (W the
    window's compliance on the coordinates the cells reach), free approach V x − δ₀, no
    constraint rows (:func:`jaxgear.solve_contact_cells`). Returns (solution, cell forces P)."""
    c = row.V.shape[0]
    sol, P, _ = solve_contact_cells(
        row.V @ W @ row.V.T,
        row.V @ x - row.delta0,
        jnp.zeros((c, 0), dtype),
        jnp.zeros((0,), dtype),
        row.k,
        row.length,
        row.mask,
        law,
    )
    return sol, P


def _scan_blocks(run_block, state, inputs, record, keep_blocks):
    """Scan ``run_block(carry, (p, entries), keep)`` over the B blocks of ``inputs``: the last
    ``keep_blocks`` (all with None) recorded with ``record``; returns the final carry and the
    records flattened over the recorded blocks (or None).

    One scan over all B blocks, so that the step (the contact solve) is traced and compiled
    once: with a transient (keep_blocks < B) each block records into a buffer of the kept
    blocks, the transient blocks into its first slot, which the first kept block overwrites
    (the records of a step are a few products of its state, the contact solve its cost)."""
    n_blocks = jax.tree.leaves(inputs)[0].shape[0]
    kept = n_blocks if keep_blocks is None or record is None else min(int(keep_blocks), n_blocks)
    blocks = (jnp.arange(n_blocks), inputs)
    if kept == n_blocks:
        carry, out = jax.lax.scan(lambda c, b: run_block(c, b, record), state, blocks)
    else:
        transient = n_blocks - kept
        first = jax.tree.map(lambda x: x[0], blocks)
        shapes = jax.eval_shape(lambda c, b: run_block(c, b, record)[1], state, first)
        buffer = jax.tree.map(lambda s: jnp.zeros((kept,) + s.shape, s.dtype), shapes)

        def body(c, b):
            carry, buf = c
            carry, rec = run_block(carry, b, record)
            slot = jnp.maximum(b[0] - transient, 0)
            buf = jax.tree.map(
                lambda x, r: jax.lax.dynamic_update_index_in_dim(x, r, slot, 0), buf, rec
            )
            return (carry, buf), None

        (carry, out), _ = jax.lax.scan(body, (state, buffer), blocks)
    if record is None:
        return carry, None
    return carry, jax.tree.map(lambda x: x.reshape((x.shape[0] * x.shape[1],) + x.shape[2:]), out)


def _update(xn, x, xd, xdd, a0, dt):
    """Newmark average acceleration (β, γ = BETA, GAMMA): the velocity and acceleration at the
    step's end from its displacement ``xn`` and the state (x, ẋ, ẍ) at its start, a0 = 1/(β Δt²)."""
    xddn = a0 * (xn - x - dt * xd - dt * dt * (0.5 - BETA) * xdd)
    return xd + dt * ((1.0 - GAMMA) * xdd + GAMMA * xddn), xddn


def _step_result(sol, states, checked):
    """A step's result code, the first failure of: the contact loop not converged, non-finite
    ``states`` or contact solution, the caller's ``checked`` code (or None)."""
    new = jnp.where(
        sol.result == ContactResult.max_iterations,
        DynamicsResult.contact_not_converged,
        DynamicsResult.successful,
    )
    finite = jnp.all(jnp.stack([jnp.all(jnp.isfinite(x)) for x in states]))
    finite = finite & (sol.result != ContactResult.non_finite)
    new = _first(new, jnp.where(finite, 0, DynamicsResult.non_finite))
    return new if checked is None else _first(new, checked)


def _first(code, new):
    """The first failure sticks: ``code`` unless it is 0, then ``new``."""
    return jnp.where(code == 0, new, code)
