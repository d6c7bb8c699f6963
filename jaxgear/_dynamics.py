"""Time integration of the gear dynamics with unilateral contact, and speed sweeps (DESIGN.md §6).

Equations of motion (seed (2.37), :mod:`jaxgear._dyn_scene`):

    M Ẍ + C Ẋ + K_s X + Σ_c k_c l_c φ(V_c·X − δ0_c(t)) V_c = F,

with the cells and δ0 at the nominal mesh position θ(t) = Ω t + Δθ/2 (Ω: pinion speed, rad/s;
Δθ = 2π/(z1 N_s) the pinion rotation of one time step, N_s steps per mesh period; the half-step
offset keeps contact-line ends off the edges of the base plane, as in the quasi-static positions).
The excitation comes only through δ0(t) and the time-varying cell set (seed III §3.3).

Solvers:

* ``"newmark"``: Newmark average acceleration (β = 1/4, γ = 1/2, seed annex 2, (2.1)-(2.6)). Each
  step is a contact problem K_eff X = F_eff with K_eff = M/(βΔt²) + γC/(βΔt) + K_s, solved by
  :func:`jaxgear.solve_contact`: exact law by the active set of seed II-25 (cells in tension dropped,
  interference outside the contact set checked, repeated), or the smooth softplus law by Newton.
  Because N_s is fixed per mesh period, the cell table (δ0, k, l, V at N_s positions) does not
  depend on the speed: it is built once and indexed by step mod N_s.
* a diffrax solver name (``"tsit5"``, ``"dopri5"``, ``"dopri8"``, ``"kvaerno3"``, ``"kvaerno5"``,
  ...): the first-order form in scaled variables (X/x_ref, Ẋ/(x_ref ω_ref)), adaptive steps with a
  ``PIDController`` (or constant steps with ``adaptive=False``), cells evaluated at θ(t).

Steady state: ``periods`` mesh periods are integrated from the static equilibrium (or a given
state), the last ``keep_periods`` are kept. Outputs: mesh force, dynamic TE, per-tooth force, the
dynamic factor (max dynamic mesh force / static mesh force, global and per tooth), TE RMS, the
contact-loss fraction, and the change between the last two periods (periodicity check).

Divergence is reported through ``result`` (:data:`DYNAMICS_RESULTS`), never as a silent NaN.
"""

from __future__ import annotations

import dataclasses

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float, Int

from ._baseplane import MeshModel
from ._contact import solve_contact
from ._dyn_scene import Damping, DynamicScene, ModalAnalysis, damping_matrix, modal_analysis
from ._modifications import Modifications
from ._quasi_static import mesh_positions, separation

__all__ = [
    "DIFFRAX_SOLVERS",
    "DYNAMICS_RESULTS",
    "DynamicModel",
    "DynamicResult",
    "MeshTable",
    "SweepResult",
    "dynamic_model",
    "mesh_table",
    "simulate",
    "speed_sweep",
]

DYNAMICS_RESULTS = {
    0: "converged",
    1: "contact loop did not converge at some time step (active set still changing)",
    2: "non-finite state: the integration diverged",
    3: "energy blow-up: vibration energy or mesh force beyond the divergence bound",
    4: "ODE solver failed (max_steps reached or step size collapsed)",
}

DIFFRAX_SOLVERS = {"tsit5": "Tsit5", "dopri5": "Dopri5", "dopri8": "Dopri8", "bosh3": "Bosh3",
                   "heun": "Heun", "midpoint": "Midpoint", "ralston": "Ralston", "euler": "Euler",
                   "kvaerno3": "Kvaerno3", "kvaerno4": "Kvaerno4", "kvaerno5": "Kvaerno5",
                   "implicit_euler": "ImplicitEuler"}


# --------------------------------------------------------------------------------------------
# model and cell table


class MeshTable(eqx.Module):
    """Contact cells at the N_s positions of one mesh period (c = n_lines·n_slices cells).

    Attributes:
        theta: pinion angles (rad), shape (P,). V: structure vectors, shape (P, c, n).
        k: cell stiffness per unit length (N/m²), length: cell length (m), delta0: δ0 (m),
        mask: cells on the flanks; all shape (P, c).
        e_max: the reference e_ref = max over the period of max_M e (m), broadcast to (P,):
            δ0 = e_ref − e ≥ 0 and TE = (u·X − e_ref)/cos β_b use one time-constant reference.
        n_lines: static number of contact lines (cells are line-major).
    """

    theta: Float[Array, " P"]
    V: Float[Array, "P c n"]
    k: Float[Array, "P c"]
    length: Float[Array, "P c"]
    delta0: Float[Array, "P c"]
    mask: Bool[Array, "P c"]
    e_max: Float[Array, " P"]
    n_lines: int = eqx.field(static=True)


def mesh_table(scene: DynamicScene, mods: Modifications, steps_per_period: int) -> MeshTable:
    """Cells, δ0 (2.8) and structure vectors at the mid-points of ``steps_per_period`` steps."""
    mesh = scene.mesh
    theta = mesh_positions(mesh, steps_per_period)

    def row(th):
        cells, e_max, d0 = separation(mesh, mods, th)
        V = scene.cell_vectors(cells)
        return (V.reshape(-1, V.shape[-1]), cells.stiffness.reshape(-1), cells.length.reshape(-1),
                d0.reshape(-1), cells.mask.reshape(-1), e_max)

    V, k, ln, d0, mask, e_max = jax.vmap(row)(theta)
    # one time-constant reference: δ0 = e_ref − e. The quasi-static δ0 = max e(t) − e moves its
    # reference with time, which would be a spurious inertial excitation in dynamics.
    e_ref = jnp.max(e_max)
    d0 = jnp.where(mask, d0 + (e_ref - e_max)[:, None], 0.0)
    return MeshTable(theta, V, k, ln, d0, mask, jnp.broadcast_to(e_ref, e_max.shape),
                     n_lines=mesh.n_lines)


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


def _static_rows(scene: DynamicScene, table: MeshTable, torque, mode, width, max_iterations,
                 k_ref):
    """Static contact solution at each table row (the quasi-static reference)."""
    K = scene.stiffness() + _rigid_penalty(scene, k_ref)
    F = scene.external_load(torque)
    return jax.vmap(lambda V, k, ln, d0, m: solve_contact(K, F, V, k, ln, d0, m, mode, width,
                                                          max_iterations))(
        table.V, table.k, table.length, table.delta0, table.mask)


def _k_ref(table: MeshTable):
    kl = jnp.where(table.mask[0], table.k[0] * table.length[0], 0.0)
    return jnp.einsum("c,ci,ci->", kl, table.V[0], table.V[0])


class _Prepared(eqx.Module):
    table: MeshTable
    static_x: Float[Array, "P n"]
    static_force_density: Float[Array, "P c"]
    static_weight: Float[Array, "P c"]
    static_result: Int[Array, " P"]


@eqx.filter_jit
def _prepare(scene, mods, torque, width, steps_per_period: int, contact: str, max_iterations: int):
    """Cell table and static rows (compiled once per scene structure and N_s; shared by the model
    build, every solver, direction and period count)."""
    table = mesh_table(scene, mods, steps_per_period)
    static = _static_rows(scene, table, torque, contact, width, max_iterations, _k_ref(table))
    return _Prepared(table, static.x, static.force_density, static.weight, static.result)


class DynamicModel(eqx.Module):
    """A dynamic scene at an operating torque, with its damping (build with :func:`dynamic_model`).

    Attributes:
        scene: the :class:`DynamicScene` (M, K_s, V). mods: flank modifications (differentiable:
            δ0 is rebuilt from them in every simulation). torque: pinion torque T (N·m).
        damping: the (n, n) damping matrix C, built once from the modal analysis of the
            time-averaged system (held fixed under differentiation wrt ``mods``).
        modes: :class:`ModalAnalysis` of the time-averaged system.
        mesh_stiffness_mean: time-averaged loaded mesh stiffness k̄ = ⟨Σ w k l⟩ (N/m).
    """

    scene: DynamicScene
    mods: Modifications
    torque: Float[Array, ""]
    damping: Float[Array, "n n"]
    modes: ModalAnalysis
    mesh_stiffness_mean: Float[Array, ""]

    @property
    def mesh(self) -> MeshModel:
        return self.scene.mesh

    @property
    def static_force(self) -> Float[Array, ""]:
        """Static flank-normal mesh force F_s = T/(r_b1 cos β_b) (N)."""
        return self.mesh.normal_load(self.torque)

    def critical_speeds(self, harmonic: int = 1) -> Float[Array, " n"]:
        """Pinion speeds (rad/s) where the ``harmonic``-th mesh harmonic meets each natural
        frequency: Ω = ω_i · (2π/z1) / (2π · harmonic) = ω_i / (z1 · harmonic)."""
        return self.modes.omega * self.mesh.mesh_period_angle / (2 * jnp.pi * harmonic)


def dynamic_model(scene: DynamicScene, mods: Modifications | None, torque, damping: Damping | None = None,
                  *, positions_per_pitch: int = 64, contact: str = "exact", width=1e-7,
                  max_iterations: int = 100) -> DynamicModel:
    """Build a :class:`DynamicModel`: time-averaged mesh stiffness, modal analysis, damping.

    The time-averaged mesh stiffness matrix is K̄_m = ⟨Σ_c w_c k_c l_c V_c V_cᵀ⟩ over one mesh
    period, w_c the static contact weights at ``torque`` (loaded cells only, so a tip relief that
    is not in contact does not count); the modal analysis of (M, K_s + K̄_m) gives the damping
    (2.34)-(2.36).

    Args:
        scene: dynamic scene. mods: modifications (``None``: none). torque: pinion torque (N·m).
        damping: :class:`Damping` (default: composite (2.36), 0.07 mesh / 0.01 structure).
        positions_per_pitch: positions per mesh period for the averages.
        contact, width, max_iterations: contact law of the static solve (exact by default).
    """
    if mods is None:
        mods = Modifications()
    if damping is None:
        damping = Damping()
    dtype = scene.mesh.base_pitch.dtype
    torque = jnp.asarray(torque, dtype=dtype)
    if not bool(torque > 0):
        raise ValueError(f"torque = {float(torque)} N·m must be > 0 (the pinion drives)")
    model, codes = _build(scene, mods, torque, damping, jnp.asarray(width, dtype),
                          positions_per_pitch, contact, max_iterations)
    codes = np.asarray(codes)
    bad = codes != 0
    if bad.any():
        raise ValueError(f"static contact solve failed at {int(bad.sum())} positions (result codes "
                         f"{sorted(set(codes[bad].tolist()))}): check the load and the deviations")
    return model


def _build(scene, mods, torque, damping, width, positions_per_pitch, contact, max_iterations):
    prep = _prepare(scene, mods, torque, width, positions_per_pitch, contact, max_iterations)
    return _averaged(scene, mods, torque, damping, prep), prep.static_result


@eqx.filter_jit
def _averaged(scene, mods, torque, damping, prep):
    table = prep.table
    w = prep.static_weight
    kl = jnp.where(table.mask, table.k * table.length, 0.0) * w
    Km = jnp.mean(jnp.einsum("pc,pci,pcj->pij", kl, table.V, table.V), axis=0)
    kbar = jnp.mean(jnp.sum(kl, axis=1))
    modes = modal_analysis(scene, Km)
    C = damping_matrix(scene, modes, damping)
    return DynamicModel(scene=scene, mods=mods, torque=torque, damping=C, modes=modes,
                        mesh_stiffness_mean=kbar)


# --------------------------------------------------------------------------------------------
# results


class DynamicResult(eqx.Module):
    """Steady-state response at one speed (K = keep_periods · N_s recorded steps).

    Attributes:
        speed: pinion speed Ω (rad/s). mesh_frequency: Ω z1 / 2π (Hz).
        time: recorded times (s), shape (K,). theta: mesh position modulo one period (rad), (K,).
        mesh_force: dynamic flank-normal mesh force Σ p l (N), shape (K,).
        transmission_error: dynamic TE (u·X − max e)/cos β_b (m), shape (K,).
        line_force: force per contact line (one tooth pair) (N), shape (K, n_lines).
        static_te: quasi-static TE at the same positions (m), shape (K,).
        bearing_force: support force components R X (N), shape (K, r) (r = 0 for torsional
            scenes; :meth:`DynamicScene.reaction_matrix`). bearing_force_max: max |R X| over the
            kept periods, shape (r,). bearing_force_static: max over positions of the static one.
        dynamic_factor: max mesh force / static mesh force F_s (-).
        dynamic_factor_tooth: max tooth force / max quasi-static tooth force (-).
        te_rms: RMS of the dynamic TE about its mean (m). te_mean: its mean (m).
        contact_loss: fraction of recorded steps with total contact loss (mesh force < 1e-3 F_s).
        periodicity: max |F_m(last period) − F_m(previous period)| / F_s (-).
        final_state: (X, Ẋ, Ẍ) at the end (continuation start), each shape (n,).
        iterations: max contact passes per step (Newmark) or ODE steps taken (diffrax).
        result: 0 ok, else a key of :data:`DYNAMICS_RESULTS`.
    """

    speed: Float[Array, ""]
    mesh_frequency: Float[Array, ""]
    time: Float[Array, " K"]
    theta: Float[Array, " K"]
    mesh_force: Float[Array, " K"]
    transmission_error: Float[Array, " K"]
    line_force: Float[Array, "K L"]
    static_te: Float[Array, " K"]
    bearing_force: Float[Array, "K r"]
    bearing_force_max: Float[Array, " r"]
    bearing_force_static: Float[Array, " r"]
    dynamic_factor: Float[Array, ""]
    dynamic_factor_tooth: Float[Array, ""]
    te_rms: Float[Array, ""]
    te_mean: Float[Array, ""]
    contact_loss: Float[Array, ""]
    periodicity: Float[Array, ""]
    final_state: tuple
    iterations: Int[Array, ""]
    result: Int[Array, ""]


class SweepResult(eqx.Module):
    """Speed sweep over S speeds.

    Attributes:
        speeds: pinion speeds (rad/s), shape (S,).
        results: :class:`DynamicResult` per speed (leaves with a leading S axis), in the order of
            ``speeds``: the independent, up or down sweep.
        down: with ``direction="both"``, the down sweep (same order as ``speeds``); else None.
    """

    speeds: Float[Array, " S"]
    results: DynamicResult
    down: DynamicResult | None = None

    @property
    def dynamic_factor(self) -> Float[Array, " S"]:
        return self.results.dynamic_factor


# --------------------------------------------------------------------------------------------
# integrators


@dataclasses.dataclass(frozen=True)
class _Config:
    solver: str
    contact: str
    steps_per_period: int
    periods: int
    keep_periods: int
    max_iterations: int
    rtol: float
    atol: float
    adaptive: bool
    max_steps: int
    blowup: float


def _phi(gap, mode, width):
    if mode == "exact":
        return jnp.maximum(gap, 0.0)
    return width * jax.nn.softplus(gap / width)


def _code(code, new):
    return jnp.where(code == 0, new, code)


def _divergence_code(xd, X, fm, M, fs, e_ref, blowup):
    finite = jnp.all(jnp.isfinite(X)) & jnp.all(jnp.isfinite(xd)) & jnp.isfinite(fm)
    ke = 0.5 * xd @ M @ xd
    blown = (fm > blowup * fs) | (ke > blowup**2 * e_ref)
    return jnp.where(~finite, 2, jnp.where(blown, 3, 0))


def _newmark(model: DynamicModel, table: MeshTable, dt, state, n_steps: int, cfg: _Config, width,
             record: bool, record_states: bool = False):
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
        Feff = (F + M @ (a0 * X + Xd / (b * dt) + (0.5 / b - 1.0) * Xdd)
                + C @ (a1 * X + (g / b - 1.0) * Xd + dt * (0.5 * g / b - 1.0) * Xdd))
        sol = solve_contact(Keff, Feff, table.V[j], table.k[j], table.length[j], table.delta0[j],
                            table.mask[j], cfg.contact, width, cfg.max_iterations)
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


def _observe(model: DynamicModel, table: MeshTable, X, j, mode, width):
    """Mesh force, TE and line forces at state X (n,) and table row j."""
    u = model.scene.te_vector()
    cb = jnp.cos(model.mesh.base_helix_angle)
    gap = table.V[j] @ X - table.delta0[j]
    f = jnp.where(table.mask[j], table.k[j] * table.length[j] * _phi(gap, mode, width), 0.0)
    return jnp.sum(f), (u @ X - table.e_max[j]) / cb, jnp.sum(f.reshape(table.n_lines, -1), axis=1)


def _diffrax(model: DynamicModel, table: MeshTable, speed, dt, state, cfg: _Config, width):
    import diffrax

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
        speed, width, mods = args
        X, Xd = y[0] * x_ref, y[1] * v_ref
        cells, e_max, d0 = separation(mesh, mods, speed * t + 0.5 * dtheta)
        d0 = jnp.where(cells.mask, d0 + (table.e_max[0] - e_max), 0.0)
        V = scene.cell_vectors(cells).reshape(-1, X.shape[0])
        kl = jnp.where(cells.mask, cells.stiffness * cells.length, 0.0).reshape(-1)
        f = kl * _phi(V @ X - d0.reshape(-1), cfg.contact, width)
        A = Minv @ (F - C @ Xd - Ks @ X - V.T @ f)
        return (Xd / x_ref, A / v_ref)

    cls = getattr(diffrax, DIFFRAX_SOLVERS[cfg.solver])
    if issubclass(cls, diffrax.AbstractImplicitSolver) and not cfg.adaptive:
        import optimistix

        # constant steps: the root finder needs its own tolerances
        solver = cls(root_finder=diffrax.VeryChord(rtol=cfg.rtol, atol=cfg.atol,
                                                   norm=optimistix.max_norm))
    else:
        solver = cls()
    if cfg.adaptive:
        controller = diffrax.PIDController(rtol=cfg.rtol, atol=cfg.atol)
    else:
        controller = diffrax.ConstantStepSize()
    ts = (n_total - n_keep + 1 + jnp.arange(n_keep)) * dt
    X0, Xd0, _ = state
    sol = diffrax.diffeqsolve(diffrax.ODETerm(rhs), solver, t0=0.0, t1=n_total * dt, dt0=dt,
                              y0=(X0 / x_ref, Xd0 / v_ref), args=(speed, width, model.mods),
                              saveat=diffrax.SaveAt(ts=ts), stepsize_controller=controller,
                              max_steps=cfg.max_steps, throw=False)
    Xs, Xds = sol.ys[0] * x_ref, sol.ys[1] * v_ref
    j = (jnp.arange(n_keep) + 1) % P
    fm, te, lines = jax.vmap(lambda X, jj: _observe(model, table, X, jj, cfg.contact, width))(Xs, j)
    code = jnp.where(sol.result == diffrax.RESULTS.successful, 0, 4)
    div = jax.vmap(lambda xd, X, f: _divergence_code(xd, X, f, M, fs, e_ref, cfg.blowup))(Xds, Xs, fm)
    # a failed solve leaves inf in the unreached outputs: report the failure, not the inf
    code = jnp.where(code != 0, code,
                     jnp.where(jnp.any(div == 2), 2, jnp.where(jnp.any(div == 3), 3, 0)))
    Xl, Xdl = Xs[-1], Xds[-1]
    gap = table.V[0] @ Xl - table.delta0[0]
    f = jnp.where(table.mask[0], table.k[0] * table.length[0] * _phi(gap, cfg.contact, width), 0.0)
    Xddl = Minv @ (F - C @ Xdl - Ks @ Xl - table.V[0].T @ f)
    nsteps = jnp.asarray(sol.stats["num_steps"])
    reac = Xs @ scene.reaction_matrix().T
    return (Xl, Xdl, Xddl), (fm, te, lines, reac), code, nsteps


def _with_acceleration(model, table, X, Xd, cfg, width):
    scene = model.scene
    gap = table.V[0] @ X - table.delta0[0]
    f = jnp.where(table.mask[0], table.k[0] * table.length[0] * _phi(gap, cfg.contact, width), 0.0)
    Xdd = jnp.linalg.solve(scene.mass(), scene.external_load(model.torque) - model.damping @ Xd
                           - scene.stiffness() @ X - table.V[0].T @ f)
    return (X, Xd, Xdd)


def _one_speed(model: DynamicModel, table: MeshTable, static, speed, state, cfg: _Config, width):
    P = cfg.steps_per_period
    mesh = model.mesh
    period = mesh.mesh_period_angle / speed
    dt = period / P
    n_keep = cfg.keep_periods * P
    n_trans = (cfg.periods - cfg.keep_periods) * P
    if cfg.solver == "newmark":
        # one scan (one compiled step) over all steps; the kept periods are sliced off the end
        carry0 = (*state, jnp.array(0), jnp.array(0))
        carry, (fm, te, lines, reac) = _newmark(model, table, dt, carry0, n_trans + n_keep, cfg,
                                                width, record=True)
        fm, te, lines, reac = fm[n_trans:], te[n_trans:], lines[n_trans:], reac[n_trans:]
        X, Xd, Xdd, code, it = carry
        final = (X, Xd, Xdd)
    else:
        final, (fm, te, lines, reac), code, it = _diffrax(model, table, speed, dt, state, cfg, width)
    fs = model.static_force
    j = (jnp.arange(n_keep) + 1) % P
    static_lines = jnp.sum((static.static_force_density * table.length).reshape(P, table.n_lines, -1),
                           axis=2)
    u = model.scene.te_vector()
    cb = jnp.cos(mesh.base_helix_angle)
    static_te = (static.static_x @ u - table.e_max) / cb
    last = fm[n_keep - P:]
    prev = fm[n_keep - 2 * P:n_keep - P]
    finite = jnp.all(jnp.isfinite(fm)) & jnp.all(jnp.isfinite(te))
    code = jnp.where((code == 0) & ~finite, 2, code)
    time = (n_trans + 1 + jnp.arange(n_keep)) * dt
    return DynamicResult(
        speed=speed, mesh_frequency=speed / mesh.mesh_period_angle,
        time=time, theta=table.theta[j], mesh_force=fm, transmission_error=te, line_force=lines,
        static_te=static_te[j],
        bearing_force=reac,
        bearing_force_max=jnp.max(jnp.abs(reac), axis=0),
        bearing_force_static=jnp.max(jnp.abs(static.static_x @ model.scene.reaction_matrix().T),
                                     axis=0),
        dynamic_factor=jnp.max(fm) / fs,
        dynamic_factor_tooth=jnp.max(lines) / jnp.max(static_lines),
        te_rms=jnp.std(te), te_mean=jnp.mean(te),
        contact_loss=jnp.mean((fm < 1e-3 * fs).astype(fm.dtype)),
        periodicity=jnp.max(jnp.abs(last - prev)) / fs,
        final_state=final, iterations=jnp.asarray(it), result=jnp.asarray(code))


def _prep(model, width, cfg: _Config) -> _Prepared:
    return _prepare(model.scene, model.mods, model.torque, width, cfg.steps_per_period,
                    cfg.contact, cfg.max_iterations)


def _static_start(prep: _Prepared):
    """(X, Ẋ) of the static equilibrium at the first mesh position, zero vibration velocity."""
    return prep.static_x[0], jnp.zeros_like(prep.static_x[0])


@eqx.filter_jit
def _run(model: DynamicModel, prep: _Prepared, speeds, state0, width, cfg: _Config, mode: str):
    table = prep.table
    static = prep
    state0 = _with_acceleration(model, table, state0[0], state0[1], cfg, width)
    restart = _with_acceleration(model, table, static.static_x[0],
                                 jnp.zeros_like(static.static_x[0]), cfg, width)

    def one(speed, state):
        return _one_speed(model, table, static, speed, state, cfg, width)

    if mode == "single":
        return one(speeds, state0)
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


def _config(solver, contact, steps_per_period, periods, keep_periods, max_iterations, rtol, atol,
            adaptive, max_steps, blowup) -> _Config:
    if solver != "newmark" and solver not in DIFFRAX_SOLVERS:
        raise ValueError(f"solver = {solver!r}: allowed 'newmark' or a diffrax solver "
                         f"({', '.join(DIFFRAX_SOLVERS)})")
    if contact not in ("exact", "smooth"):
        raise ValueError(f"contact = {contact!r}: allowed 'exact', 'smooth'")
    for name, v, lo in (("steps_per_period", steps_per_period, 4), ("periods", periods, 2),
                        ("keep_periods", keep_periods, 2)):
        if int(v) != v or v < lo:
            raise ValueError(f"{name} = {v!r} is out of range: allowed an integer >= {lo}")
    if keep_periods > periods:
        raise ValueError(f"keep_periods = {keep_periods} must be <= periods = {periods}")
    n_total = int(periods) * int(steps_per_period)
    if max_steps is None:
        max_steps = 64 * n_total + 4096
    return _Config(solver, contact, int(steps_per_period), int(periods), int(keep_periods),
                   int(max_iterations), float(rtol), float(atol), bool(adaptive), int(max_steps),
                   float(blowup))


def _raise_on_failure(result, what):
    codes = np.atleast_1d(np.asarray(result))
    bad = codes[codes != 0]
    if bad.size:
        raise eqx.EquinoxRuntimeError(f"{what}: {DYNAMICS_RESULTS[int(bad[0])]} "
                                      f"({bad.size} of {codes.size} speed points)")


def simulate(model: DynamicModel, speed, *, solver: str = "newmark", contact: str = "exact",
             width=1e-7, steps_per_period: int = 64, periods: int = 60, keep_periods: int = 4,
             state0=None, max_iterations: int = 100, rtol: float = 1e-6, atol: float = 1e-6,
             adaptive: bool = True, max_steps: int | None = None, blowup: float = 100.0,
             throw: bool = True) -> DynamicResult:
    """Steady-state dynamic response at one pinion speed.

    Args:
        model: :class:`DynamicModel` from :func:`dynamic_model`.
        speed: pinion speed Ω (rad/s), > 0, scalar (traced: no recompilation per speed).
        solver: "newmark" or a diffrax solver name (:data:`DIFFRAX_SOLVERS`).
        contact: "exact" (active set, II-25) or "smooth" (softplus of ``width`` m; use it for
            gradients and for the diffrax solvers).
        width: smoothing width w (m).
        steps_per_period: N_s, time steps per mesh period (Newmark; the diffrax initial step and
            the sampling of the kept periods). Resolve the highest mode of interest: Δt below a
            tenth of its period (average acceleration has no numerical damping).
        periods: mesh periods integrated; keep_periods: the last ones kept (>= 2).
        state0: (X, Ẋ) to start from (default: static equilibrium, zero vibration velocity).
        max_iterations: cap on contact passes per step.
        rtol, atol: diffrax PID tolerances (scaled state: X/x_ref, Ẋ/(x_ref ω_max), x_ref the
            static mesh deflection). adaptive: False for constant steps Δt = period/N_s.
        max_steps: diffrax step cap (default 64 × the Newmark step count + 4096).
        blowup: divergence bound: mesh force > blowup·F_s or kinetic energy > blowup² · F_s²/2k̄.
        throw: raise ``eqx.EquinoxRuntimeError`` on a non-zero result.

    Returns:
        :class:`DynamicResult`.

    Raises:
        ValueError: bad solver/contact names or step counts (trace time).
        eqx.EquinoxRuntimeError: divergence or contact-loop failure (with ``throw``).
    """
    cfg = _config(solver, contact, steps_per_period, periods, keep_periods, max_iterations, rtol,
                  atol, adaptive, max_steps, blowup)
    dtype = model.mesh.base_pitch.dtype
    speed = jnp.asarray(speed, dtype)
    width = jnp.asarray(width, dtype)
    prep = _prep(model, width, cfg)
    if state0 is None:
        state0 = _static_start(prep)
    state0 = (jnp.asarray(state0[0], dtype), jnp.asarray(state0[1], dtype))
    r = _run(model, prep, speed, state0, width, cfg, "single")
    if throw and not isinstance(r.result, jax.core.Tracer):
        _raise_on_failure(r.result, "simulate")
    return r


def _shard(speeds):
    devices = jax.local_devices()
    n = len(devices)
    pad = (-speeds.shape[0]) % n
    padded = jnp.concatenate([speeds, jnp.full((pad,), speeds[-1], speeds.dtype)])
    mesh = jax.sharding.Mesh(np.array(devices), ("speed",))
    sharding = jax.sharding.NamedSharding(mesh, jax.sharding.PartitionSpec("speed"))
    return jax.device_put(padded, sharding), pad


def _concat(parts, n):
    return jax.tree_util.tree_map(lambda *a: jnp.concatenate(a)[:n], *parts)


def _flip(r):
    return jax.tree_util.tree_map(lambda a: a[::-1], r)


def speed_sweep(model: DynamicModel, speeds, *, direction: str = "independent", shard: bool = True,
                chunk_size: int | None = None, progress=None,
                solver: str = "newmark", contact: str = "exact", width=1e-7,
                steps_per_period: int = 64, periods: int = 60, keep_periods: int = 4,
                max_iterations: int = 100, rtol: float = 1e-6, atol: float = 1e-6,
                adaptive: bool = True, max_steps: int | None = None,
                blowup: float = 100.0) -> SweepResult:
    """Dynamic response over pinion speeds.

    Args:
        model: :class:`DynamicModel`.
        speeds: pinion speeds (rad/s), shape (S,), ascending for continuation sweeps.
        direction: "independent" (every speed from the static equilibrium, ``jax.vmap``, sharded
            over the local devices with ``jax.sharding`` when there are several and ``shard``),
            "up" or "down" (continuation: each speed starts from the previous steady state,
            ``lax.scan``), or "both" (up and down; ``SweepResult.down`` in the order of
            ``speeds``; one vmap over the two scans when not chunked).
        chunk_size: split the sweep into chunks of this many speeds (one compilation; the last
            chunk is padded), calling ``progress(n_done)`` after each (for a progress bar).
            Continuation carries the state across chunks.
        Other arguments: as :func:`simulate`.

    Returns:
        :class:`SweepResult` (never raises on divergence: read ``result`` per speed).
    """
    if direction not in ("independent", "up", "down", "both"):
        raise ValueError(f"direction = {direction!r}: allowed 'independent', 'up', 'down', 'both'")
    cfg = _config(solver, contact, steps_per_period, periods, keep_periods, max_iterations, rtol,
                  atol, adaptive, max_steps, blowup)
    dtype = model.mesh.base_pitch.dtype
    speeds = jnp.asarray(speeds, dtype)
    if speeds.ndim != 1 or speeds.shape[0] < 1:
        raise ValueError("speeds must be a 1-D array of pinion speeds (rad/s)")
    width = jnp.asarray(width, dtype)
    S = speeds.shape[0]
    n_dev = len(jax.local_devices()) if shard else 1
    prep = _prep(model, width, cfg)
    start = _static_start(prep)

    def independent(sp):
        if n_dev > 1:
            padded, _ = _shard(sp)
            r = _run(model, prep, padded, start, width, cfg, "vmap")
            return jax.tree_util.tree_map(lambda a: a[: sp.shape[0]], r)
        return _run(model, prep, sp, start, width, cfg, "vmap")

    if chunk_size is None:
        if direction == "independent":
            return SweepResult(speeds, independent(speeds))
        if direction == "up":
            return SweepResult(speeds, _run(model, prep, speeds, start, width, cfg, "continuation"))
        if direction == "down":
            return SweepResult(speeds, _flip(_run(model, prep, speeds[::-1], start, width, cfg,
                                                  "continuation")))
        up, down = _run(model, prep, speeds, start, width, cfg, "both")
        return SweepResult(speeds, up, down)

    size = max(1, int(chunk_size))
    if direction == "independent":
        size = -(-size // n_dev) * n_dev
    n_chunks = -(-S // size)
    done = [0]

    def chunks(sp):
        pad = n_chunks * size - S
        return jnp.concatenate([sp, jnp.full((pad,), sp[-1], dtype)]).reshape(n_chunks, size)

    def tick(n):
        done[0] += n
        if progress is not None:
            progress(done[0])

    def continuation(sp):
        parts, state = [], start
        for ch in chunks(sp):
            r = _run(model, prep, ch, state, width, cfg, "continuation")
            ok = bool(r.result[-1] == 0)
            state = (r.final_state[0][-1], r.final_state[1][-1]) if ok else start
            parts.append(r)
            tick(min(size, S - len(parts[:-1]) * size))
        return _concat(parts, S)

    if direction == "independent":
        parts = []
        for ch in chunks(speeds):
            parts.append(independent(ch))
            tick(min(size, S - (len(parts) - 1) * size))
        return SweepResult(speeds, _concat(parts, S))
    if direction == "up":
        return SweepResult(speeds, continuation(speeds))
    if direction == "down":
        return SweepResult(speeds, _flip(continuation(speeds[::-1])))
    return SweepResult(speeds, continuation(speeds), _flip(continuation(speeds[::-1])))
