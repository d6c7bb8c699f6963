"""Steady-state response at one speed: :func:`simulate` and the result containers."""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Bool, Float, Int

from .._baseplane import CellRow
from .._contact import ContactLaw, ExactContact, _phi, contact_law
from .._results import DynamicsResult, error_if_failed
from .._util import check_integer, rms_about_mean
from ._diffrax import _diffrax
from ._model import DynamicModel, MeshTable, _prepare, _Prepared
from ._newmark import newmark
from ._settings import (
    MAX_STEPS_PER_SPEED,
    MESH_ENERGY_MIN,
    MIN_STEPS_PER_PERIOD,
    STEPS_PER_MODE,
    UNDER_RESOLVED_STEPS,
    DiffraxIntegrator,
    Newmark,
    SteadyState,
    _Config,
    _config,
    _divergence_code,
    check_integrator,
    check_window,
)

__all__ = ["DynamicResult", "SweepResult", "auto_steps_per_period", "simulate", "static_start"]


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
        steps_per_period: time steps per mesh period N_s actually used (automatic or given).
        steps_per_mode_period: N_s f_mesh / f_max, time steps per period of the highest mode the
            mesh excites (mesh-energy share >= 5 %; docs/dynamics.md "Time step and accuracy").
        under_resolved: steps_per_mode_period < 20: the dynamic factor may be off by more than
            1 % (underestimated by 3-30 % below ~13 at low speed with a stepwise stiffness).
        final_state: (X, Ẋ, Ẍ) at the end (continuation start), each shape (n,).
        iterations: max contact passes per step (Newmark) or ODE steps taken (diffrax).
        result: 0 ok, else a key of :class:`~jaxgear.DynamicsResult` code.
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
    steps_per_period: Int[Array, ""]
    steps_per_mode_period: Float[Array, ""]
    under_resolved: Bool[Array, ""]
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


def _with_acceleration(model, table, X, Xd, law):
    scene = model.scene
    gap = table.V[0] @ X - table.delta0[0]
    f = jnp.where(table.mask[0], table.k[0] * table.length[0] * _phi(gap, law)[0], 0.0)
    Xdd = jnp.linalg.solve(
        scene.mass(),
        scene.external_load(model.torque)
        - model.damping @ Xd
        - scene.stiffness() @ X
        - table.V[0].T @ f,
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
):
    """``n_steps`` Newmark steps (:func:`~jaxgear.dynamics._newmark.newmark`, the contact in
    coordinates) on the rows of the mesh table from row 1 on (step n ends at row (n + 1) mod N_s).

    ``state``: (X, Ẋ, Ẍ, result code, most contact passes). Records per step (``record``): the
    mesh force Σ P (N), the TE (m), the force per contact line (N, (L,)), the bearing forces R X
    (N, (r,)), and (X, Ẋ) with ``record_states``."""
    scene = model.scene
    M, Ks, F = scene.mass(), scene.stiffness(), scene.external_load(model.torque)
    u = scene.te_vector()
    R = scene.reaction_matrix()
    cb = jnp.cos(model.mesh.base_helix_angle)
    fs = model.static_force
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    P = table.theta.shape[0]

    def cells_at(j):
        return CellRow(
            None, table.V[j], table.k[j], table.length[j], table.delta0[j], table.mask[j]
        )

    def check(X, Xd, forces):
        return _divergence_code(Xd, X, jnp.sum(forces), M, fs, e_ref, cfg.blowup)

    def kept(X, Xd, forces):
        te = (u @ X - table.e_max[0]) / cb
        lines = jnp.sum(forces.reshape(table.n_lines, -1), axis=1)
        out = (jnp.sum(forces), te, lines, R @ X)
        return out + (X, Xd) if record_states else out

    rows = ((jnp.arange(n_steps) + 1) % P)[None, :]
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
    )


def _one_speed(model: DynamicModel, table: MeshTable, static, speed, state, cfg: _Config, law):
    P = cfg.steps_per_period
    mesh = model.mesh
    period = mesh.mesh_period_angle / speed
    dt = period / P
    n_keep = cfg.keep_periods * P
    n_trans = (cfg.periods - cfg.keep_periods) * P
    if cfg.newmark:
        # the transient unrecorded, then the kept periods recorded: n_trans is whole mesh
        # periods, so the second scan meets the same table rows (memory ∝ keep_periods only)
        carry0 = (*state, jnp.array(0), jnp.array(0))
        carry, _ = _newmark(model, table, dt, carry0, n_trans, cfg, law, record=False)
        carry, (fm, te, lines, reac) = _newmark(
            model, table, dt, carry, n_keep, cfg, law, record=True
        )
        X, Xd, Xdd, code, it = carry
        final = (X, Xd, Xdd)
    else:
        final, (fm, te, lines, reac), code, it = _diffrax(model, table, speed, dt, state, cfg, law)
    fs = model.static_force
    j = (jnp.arange(n_keep) + 1) % P
    static_lines = jnp.sum(
        (static.static_force_density * table.length).reshape(P, table.n_lines, -1), axis=2
    )
    u = model.scene.te_vector()
    cb = jnp.cos(mesh.base_helix_angle)
    static_te = (static.static_x @ u - table.e_max) / cb
    last = fm[n_keep - P :]
    prev = fm[n_keep - 2 * P : n_keep - P]
    finite = jnp.all(jnp.isfinite(fm)) & jnp.all(jnp.isfinite(te))
    code = jnp.where((code == 0) & ~finite, 2, code)
    time = (n_trans + 1 + jnp.arange(n_keep)) * dt
    # f_mesh / f_max = Ω (2π/z1)^-1 / (ω_max / 2π)
    per_mode = P * 2 * jnp.pi * speed / (mesh.mesh_period_angle * _excited_omega(model))
    return DynamicResult(
        speed=speed,
        mesh_frequency=speed / mesh.mesh_period_angle,
        time=time,
        theta=table.theta[j],
        mesh_force=fm,
        transmission_error=te,
        line_force=lines,
        static_te=static_te[j],
        bearing_force=reac,
        bearing_force_max=jnp.max(jnp.abs(reac), axis=0),
        bearing_force_static=jnp.max(
            jnp.abs(static.static_x @ model.scene.reaction_matrix().T), axis=0
        ),
        dynamic_factor=jnp.max(fm) / fs,
        dynamic_factor_tooth=jnp.max(lines) / jnp.max(static_lines),
        te_rms=rms_about_mean(te),
        te_mean=jnp.mean(te),
        contact_loss=jnp.mean((fm < 1e-3 * fs).astype(fm.dtype)),
        periodicity=jnp.max(jnp.abs(last - prev)) / fs,
        steps_per_period=jnp.asarray(P),
        steps_per_mode_period=per_mode,
        under_resolved=per_mode < UNDER_RESOLVED_STEPS,
        final_state=final,
        iterations=jnp.asarray(it),
        result=jnp.asarray(code),
    )


def _excited_omega(model: DynamicModel):
    """Highest natural frequency (rad/s) among the modes the mesh excites: elastic modes with a
    mesh strain-energy share >= ``MESH_ENERGY_MIN`` (inf-safe: the highest elastic one if none)."""
    modes = model.modes
    elastic = ~modes.rigid
    excited = elastic & (modes.mesh_energy >= MESH_ENERGY_MIN)
    excited = jnp.where(jnp.any(excited), excited, elastic)
    return jnp.max(jnp.where(excited, modes.omega, 0.0))


def auto_steps_per_period(model: DynamicModel, speeds) -> np.ndarray:
    """Automatic time steps per mesh period at each pinion speed (the default of
    :func:`simulate` and :func:`~jaxgear.dynamics.speed_sweep`).

    N_s = the smallest power of two >= max(64, 40 · f_max / f_mesh): at least 40 steps per period
    of the highest mode the mesh excites (f_max, mesh-energy share >= 5 %) and 64 per mesh period
    (f_mesh = Ω z1 / 2π). Powers of two keep the number of compiled cell tables small.

    Args:
        model: :class:`DynamicModel` (concrete values: not under ``jax.jit``).
        speeds: pinion speed(s) Ω (rad/s), concrete.

    Returns:
        int array of N_s, the shape of ``speeds``.

    Raises:
        ValueError: traced speeds or model (pass an explicit ``steps_per_period`` under jit).
    """
    try:
        sp = np.asarray(speeds, dtype=float)
        w = float(_excited_omega(model))
        angle = float(model.mesh.mesh_period_angle)
    except (jax.errors.TracerArrayConversionError, jax.errors.ConcretizationTypeError) as err:
        raise ValueError(
            "steps_per_period=None (automatic) needs concrete speeds and model: under jax.jit, "
            "jax.vmap or jax.grad pass an explicit integer steps_per_period"
        ) from err
    return steps_for_mode(w, angle, sp)


def steps_for_mode(omega_max, mesh_period_angle, speeds) -> np.ndarray:
    """N_s = the smallest power of two >= max(64, 40 · f_max / f_mesh) at each pinion speed
    (rad/s, concrete): the rule of :func:`auto_steps_per_period` for the highest excited mode
    ``omega_max`` (rad/s), with f_mesh = Ω / θ_m (Hz), θ_m = ``mesh_period_angle`` = 2π/z1."""
    sp = np.asarray(speeds, dtype=float)
    if np.any(~(sp > 0)):
        raise ValueError("speeds must be > 0 rad/s")
    ratio = float(omega_max) * float(mesh_period_angle) / (2 * np.pi * sp)  # f_max / f_mesh
    n = np.maximum(MIN_STEPS_PER_PERIOD, np.ceil(STEPS_PER_MODE * ratio))
    if np.any(n > MAX_STEPS_PER_SPEED):
        low = (
            STEPS_PER_MODE
            * float(omega_max)
            * float(mesh_period_angle)
            / (2 * np.pi * MAX_STEPS_PER_SPEED)
        )
        raise ValueError(
            f"speeds: {sp.min():.6g} rad/s would need {n.max():.3g} time steps per mesh period "
            f"to resolve the highest mode the mesh excites ({omega_max / (2 * np.pi):.6g} Hz): "
            f"allowed >= {low:.3g} rad/s (a slower pinion is quasi-static: jaxgear run)"
        )
    return (2 ** np.ceil(np.log2(n))).astype(int)


def _prep(model, law: ContactLaw, steps_per_period: int) -> _Prepared:
    return _prepare(model.scene, model.mods, model.torque, law, steps_per_period)


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
    law = contact_law(contact, model.mesh.base_pitch.dtype)
    return _static_start(_prep(model, law, int(steps_per_period)))


@eqx.filter_jit
@eqx.debug.assert_max_traces(max_traces=None)  # counted (tests: no retracing)
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
            df = error_if_failed(r.dynamic_factor, r.result, DynamicsResult, "simulate")
            r = eqx.tree_at(lambda x: x.dynamic_factor, r, df)
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


def simulate(
    model: DynamicModel,
    speed,
    *,
    integrator: Newmark | DiffraxIntegrator = Newmark(),
    contact: ContactLaw = ExactContact(),
    window: SteadyState = SteadyState(),
    state0=None,
    blowup: float = 100.0,
    throw: bool = True,
) -> DynamicResult:
    """Steady-state dynamic response at one pinion speed.

    Args:
        model: :class:`DynamicModel` from :func:`dynamic_model`.
        speed: pinion speed Ω (rad/s), > 0, scalar (traced: no recompilation per speed).
        integrator: :class:`~jaxgear.dynamics.Newmark` (default; automatic steps per period) or
            :class:`~jaxgear.dynamics.DiffraxIntegrator`. With automatic steps
            (``steps_per_period=None``: :func:`auto_steps_per_period`, needs a concrete speed)
            the result reports ``steps_per_mode_period`` and flags ``under_resolved`` (< 20).
        contact: :class:`~jaxgear.ExactContact` (active set, II-25; default) or
            :class:`~jaxgear.SmoothContact` (for gradients and the diffrax solvers).
        window: :class:`~jaxgear.dynamics.SteadyState`: mesh periods integrated and kept
            (default 60 and 4; the lumped dynamics keep >= 2).
        state0: (X, Ẋ) to start from (default: static equilibrium, zero vibration velocity).
        blowup: divergence bound: mesh force > blowup·F_s or kinetic energy > blowup² · F_s²/2k̄.
        throw: raise ``eqx.EquinoxRuntimeError`` on a non-zero result (``eqx.error_if``: works
            under ``jax.jit``, ``jax.vmap`` and ``jax.grad`` too).

    Returns:
        :class:`DynamicResult`.

    Raises:
        ValueError: settings that are not settings objects, a window too short or a run too
            large (before any work); automatic steps with a traced speed.
        eqx.EquinoxRuntimeError: divergence or contact-loop failure (with ``throw``).
    """
    integrator = check_integrator(integrator)
    window = check_window(window)
    dtype = model.mesh.base_pitch.dtype
    law = contact_law(contact, dtype)
    steps_per_period = integrator.steps_per_period
    if steps_per_period is None:
        steps_per_period = int(auto_steps_per_period(model, speed))
    cfg = _config(integrator, window, steps_per_period, blowup)
    speed = jnp.asarray(speed, dtype)
    prep = _prep(model, law, cfg.steps_per_period)
    if state0 is None:
        state0 = _static_start(prep)
    state0 = (jnp.asarray(state0[0], dtype), jnp.asarray(state0[1], dtype))
    return _run(model, prep, speed, state0, law, cfg, "single", bool(throw))
