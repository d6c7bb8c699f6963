"""Sweeps that settle before they are read (docs/dynamics.md, "Settled sweeps"): the one rule
for every dynamic model, pairs, trains and planetary stages, of how long a run lasts before its
kept periods are read, and the continuation sweep of a lumped model that runs each speed until
its steady state repeats.

The rule: the slowest decaying mode the meshes excite (an elastic mode with >= 5 % of its
strain energy in the meshes, :data:`MESH_ENERGY_MIN`) sets the settling time
t_s = ln(1 / :data:`SETTLE_TOL`) / min_i(ξ_i ω_i) (ξ_i its damping ratio, ω_i its natural
frequency): a transient started at the quasi-static state has decayed to 1e-3 of its start
after t_s, the span of an independent run is ``keep + ceil(t_s f_mesh)`` mesh periods, and a
speed is settled when its kept forces change by less than :data:`SETTLED_TOL` of the nominal
mesh force."""

from __future__ import annotations

import math
from typing import NamedTuple

import jax
import jax.numpy as jnp
import numpy as np

from ._modal import ModalAnalysis, excited_omega
from ._model import AbstractDynamicModel
from ._result import SweepResult
from ._settings import MAX_STEPS_PER_SPEED, MESH_ENERGY_MIN, Newmark, Outputs, SteadyState
from ._sweep import _host, _subsample, auto_steps_per_period, resolve_settings

__all__ = [
    "CAP_ENERGY_MIN",
    "CAP_FACTOR",
    "SETTLED_TOL",
    "SETTLE_TOL",
    "SettledSweep",
    "modal_damping_ratios",
    "settled_sweep",
    "settling_time",
    "unsettled_lines",
]

#: the transient's amplitude left, relative to its start, when the kept periods begin: the
#: settling time t_s = ln(1 / SETTLE_TOL) / (ξ ω) of the slowest decaying mode the meshes excite
#: (:func:`settling_time`)
SETTLE_TOL = 1e-3
#: the change of the kept mesh forces (over the nominal mesh force) above which a speed is not
#: settled: one warning line (:func:`settled_sweep`; the planetary sweep's check)
SETTLED_TOL = 1e-2
#: a speed of a settled sweep runs at most CAP_FACTOR times the span of an independent run
#: (:func:`settled_sweep`)
CAP_FACTOR = 2
#: the cap of a settled sweep's speed also lets the slowest decaying elastic mode with at least
#: this share of its strain energy in the meshes settle (:func:`settling_time` over those modes):
#: a mode under the rule's 5 % share but lighter damped rings for longer than the rule's modes,
#: and a speed whose mesh frequency is near it drives it (accessory-spur at 296.6 rad/s: its
#: 1933 Hz shaft mode, 3.8 % share, ξ = 1.2 %, decays 18 times slower than its mesh mode)
CAP_ENERGY_MIN = 1e-2
#: where a window holds one scene period (judged by its return), a continued speed first runs
#: block // LEAD_DIVISOR mesh periods (at least 1) unrecorded, its windows then from that mesh
#: position (:func:`settled_sweep`)
LEAD_DIVISOR = 8


def modal_damping_ratios(modes: ModalAnalysis, damping) -> np.ndarray:
    """The damping ratio of each mode, ξ_i = φ_iᵀ C φ_i / (2 ω_i) (mass-normalised shapes φ_i,
    ``modes.shapes``; ``damping`` C the model's damping matrix, units of K·s, (n, n)); NaN for
    the rigid-body modes. The modal projection of any damping model (Rayleigh, modal,
    composite: the ξ_i it was built from). Returns float (n,)."""
    phi = np.asarray(modes.shapes, dtype=float)
    omega = np.asarray(modes.omega, dtype=float)
    c = np.einsum("ji,jk,ki->i", phi, np.asarray(damping, dtype=float), phi)
    rigid = np.asarray(modes.rigid) | ~(omega > 0)
    return np.where(rigid, np.nan, c / (2.0 * np.where(rigid, 1.0, omega)))


def settling_time(
    modes, damping_ratio, energy_min: float = MESH_ENERGY_MIN
) -> tuple[float, float]:
    """(t_s (s), ω (rad/s) of the mode that sets it): t_s = ln(1 / :data:`SETTLE_TOL`) /
    min_i(ξ_i ω_i) over the modes the meshes excite (elastic, >= ``energy_min`` of their
    strain energy in the meshes, default :data:`MESH_ENERGY_MIN`; where none does, the one
    :func:`~jaxgear.dynamics.excited_omega` picks). ``modes``: any modal analysis with
    ``omega`` (rad/s), ``rigid`` and ``mesh_energy`` ((n,) each: a pair's or train's
    :class:`ModalAnalysis`, a planetary stage's mesh modes); ``damping_ratio``: ξ, one for every
    mode (a float) or per mode ((n,), :func:`modal_damping_ratios`); ``energy_min``: the
    share in [0, 1] (a settled sweep's cap reads :data:`CAP_ENERGY_MIN`). Undamped (ξ ω = 0):
    t_s = inf. The planetary sweep's span (:func:`jaxgear.cli.planetary_sweep.time_plan`) and the
    pairs' and trains' (:func:`settled_sweep`) both read it."""
    omega = np.asarray(modes.omega, dtype=float)
    rigid = np.asarray(modes.rigid)
    excited = ~rigid & (np.asarray(modes.mesh_energy) >= energy_min)
    if not np.any(excited):
        excited = omega == float(excited_omega(modes))
    ratio = np.broadcast_to(np.asarray(damping_ratio, dtype=float), omega.shape)
    rate = np.where(excited, np.nan_to_num(ratio) * omega, np.inf)
    i = int(np.argmin(rate))
    if not rate[i] > 0:
        return math.inf, float(omega[i])
    return math.log(1.0 / SETTLE_TOL) / float(rate[i]), float(omega[i])


def _state_change(end, start, mass, stiffness, k_mesh: float, static_forces) -> float:
    """The mesh force a window's change of state could carry, over the smallest static mesh
    force: E = ½ ΔẊᵀ M ΔẊ + ½ ΔXᵀ K̄ ΔX of Δ = end − start ((X, Ẋ) at the same mesh position:
    zero on a periodic orbit), and a mesh spring of stiffness k̄ holding all of it carries at
    most √(2 k̄ E) (K̄ = K_s + K̄_m the mesh-averaged stiffness, k̄ the mean mesh stiffness)."""
    dx = np.asarray(end[0]) - np.asarray(start[0])
    dv = np.asarray(end[1]) - np.asarray(start[1])
    energy = 0.5 * (dv @ mass @ dv + dx @ stiffness @ dx)
    return float(np.sqrt(2.0 * k_mesh * max(energy, 0.0)) / np.min(static_forces))


def _free_decay(modes, ratios, mass, t_w):
    """The modal free decay over a window of t_w seconds: (Φ, ΦᵀM, G), G (n, 2, 2) per mode,
    G_i = E_i (E_i − I)⁻¹ with E_i = exp(A_i t_w), A_i = [[0, 1], [−ω_i², −2 ξ_i ω_i]] the
    mode's free vibration in (q_i, q̇_i) (ξ_i its damping ratio); zero for rigid modes. A
    transient e₀ that decays freely over the window, e₁ = E e₀, leaves a return
    Δ = e₁ − e₀ = (E − I) e₀, so e₁ = G Δ (:func:`_shoot`)."""
    phi = np.asarray(modes.shapes, dtype=float)
    om = np.asarray(modes.omega, dtype=float)
    rigid = np.asarray(modes.rigid) | ~(om > 0)
    g = np.zeros((om.size, 2, 2))
    for i in np.flatnonzero(~rigid):
        w, z = om[i], float(np.nan_to_num(ratios[i]))
        a = np.array([[0.0, 1.0], [-w * w, -2.0 * z * w]])
        lam, vec = np.linalg.eig(a * t_w)
        e = np.real(vec @ np.diag(np.exp(lam)) @ np.linalg.inv(vec))
        g[i] = e @ np.linalg.pinv(e - np.eye(2))
    return phi, phi.T @ mass, g


def _shoot(end, start, fly):
    """A window's end state less the transient it still holds, estimated from its return
    (end − start at the same mesh position) by the modes' free decay (:func:`_free_decay`):
    the next window's start, closer to the periodic orbit (the modal damping model and the
    mesh-averaged modes are an approximation: the next window is judged by its own return as
    every window, so the estimate decides only how many windows a speed runs)."""
    phi, pm, g = fly
    dq, dv = pm @ (end[0] - start[0]), pm @ (end[1] - start[1])
    e = np.einsum("nij,nj->ni", g, np.stack([dq, dv], axis=1))
    dtype = np.asarray(end[0]).dtype
    return (end[0] - phi @ e[:, 0]).astype(dtype), (end[1] - phi @ e[:, 1]).astype(dtype)


def unsettled_lines(s: "SettledSweep", tol: float = SETTLED_TOL) -> list[str]:
    """One line per speed of the settled sweep ``s`` that reached its cap unsettled: the
    speed, its periods, its change over the static mesh force and the ``periods`` that run
    every speed longer (the case file's key and ``--periods``)."""
    sp = np.asarray(s.sweep.speeds)
    return [
        f"speed {sp[i]:.6g} rad/s: not settled after {int(s.periods[i])} mesh periods, its kept "
        f"forces change by {s.change[i]:.3g} of the static mesh force (> {tol:g}): run every "
        f"speed longer with --periods {2 * int(s.periods[i])} ([scene.integration] periods)"
        for i in np.flatnonzero(~s.settled & np.isfinite(s.change))
    ]


class SettledSweep(NamedTuple):
    """A sweep run until each speed settled (:func:`settled_sweep`).

    Attributes:
        sweep: the :class:`SweepResult` (each speed's last window; ``down`` None).
        periods: mesh periods (of the first mesh) each speed ran, int (S,).
        change: the change of each speed's last window over the static mesh force (-), (S,)
            (:func:`settled_sweep`); NaN where the speed failed.
        settled: ``change`` <= ``tol``, bool (S,).
        cap: the most periods a speed may run, int (S,): :data:`CAP_FACTOR` times the span of
            an independent run at that speed (``keep + ceil(t_s f_mesh)``) or, where longer,
            ``keep + ceil(t_c f_mesh)`` (t_c the settling time of the modes with
            :data:`CAP_ENERGY_MIN` of their strain energy in the meshes), in whole windows, at
            least four, plus the lead (:func:`settled_sweep`).
        settle_s: the settling time t_s (s) (:func:`settling_time`).
        f_min_Hz: the frequency of the mode that sets it (Hz).
        window: the periods of one window (a whole number of the scene's period), the last
            ``keep`` of them recorded.
        keep: the kept periods.
        phase: the mesh position of each speed's windows and final state, in whole periods
            of the first mesh from the scene's start, int (S,) (0 unless a lead ran:
            :func:`settled_sweep`); a run continuing from ``sweep.results.final_state``
            starts there (:func:`~jaxgear.dynamics.simulate`'s ``start_period``).
    """

    sweep: SweepResult
    periods: np.ndarray
    change: np.ndarray
    settled: np.ndarray
    cap: np.ndarray
    settle_s: float
    f_min_Hz: float
    window: int
    keep: int
    phase: np.ndarray | None = None


def settled_sweep(
    model: AbstractDynamicModel,
    speeds,
    *,
    integrator: Newmark | None = None,
    contact=None,
    keep_periods: int | None = None,
    outputs: Outputs | None = None,
    descending: bool = False,
    tol: float = SETTLED_TOL,
    progress=None,
) -> SettledSweep:
    """Each speed run until its steady state repeats, by continuation (docs/dynamics.md,
    "Settled sweeps"): the speeds in order (ascending; ``descending``: from the last), the first
    from the static equilibrium, each next one from the previous speed's final state, its
    vibration velocity scaled by the ratio of the speeds (the same response over the mesh
    angle); each speed runs windows of ``window`` mesh periods (``keep_periods`` kept, rounded
    up to the scene's period: each window ends at the mesh position where it began) from its
    own last state until settled: the change of a window, at most ``tol`` of each mesh's static
    force, is the largest of the last kept period against the one before (the records'
    periodicity, where they hold two scene periods), and the kept forces against the window
    before's or, for a continued speed's first window, the mesh force its change of state could
    carry (:func:`_state_change`: zero on a periodic orbit, whose state repeats at the same mesh
    position). Where the kept periods hold one scene period (the records have no periodicity,
    e.g. a train whose meshes repeat together only after the whole window), every window but
    the very first from rest is judged by its own return, its end state against its start,
    over 1 − ρ (ρ = SETTLE_TOL^(T_w / t_s), the slowest excited mode's decay over the window's
    T_w: the transient its records can still hold). There (Newmark), a continued speed first
    runs a lead of ``window // LEAD_DIVISOR`` periods unrecorded (the speed change's fast
    transient, the heavily damped mesh modes', dies in it), its windows then from the mesh
    position where the lead ended (``phase``); a window that does not return within ``tol``
    hands the next one its end state less the transient the modes' free decay over the window
    leaves in it, estimated from its return (:func:`_shoot`), so that such a speed settles in
    the lead and two windows rather than three (the next window is judged by its own return:
    the estimate decides only how many windows run); or until its cap: :data:`CAP_FACTOR`
    times the span an independent run needs (``keep +
    ceil(t_s f_mesh)``, :func:`settling_time` with the model's modal damping ratios) or, where
    longer, ``keep + ceil(t_c f_mesh)``, t_c the settling time of every mode with at least
    :data:`CAP_ENERGY_MIN` of its strain energy in the meshes (a lighter coupled, lighter damped
    mode that a speed near its resonance drives rings longer than the rule's modes), at least
    four windows. A speed at its cap unsettled has ``settled`` False (``jaxgear sweep`` and
    ``jaxgear run`` print one warning line per such speed, naming its change and the
    ``periods`` that run it longer; :func:`unsettled_lines`). So
    the settling is paid once (at the first speed, the slowest: the fewest periods), and a
    speed whose neighbour's state is close settles in one window.

    Args:
        model: a dynamic model whose kind
            :attr:`~jaxgear.dynamics.AbstractDynamicModel.settles` (a lumped
            :class:`~jaxgear.dynamics.DynamicModel`): it continues from speed to speed and
            gives its damping and mean mesh stiffness
            (:meth:`~jaxgear.dynamics.AbstractDynamicModel.settling_measures`).
        speeds: pinion (input) speeds (rad/s) > 0, ascending, concrete, (S,).
        integrator, contact, outputs: as :func:`~jaxgear.dynamics.speed_sweep` (None: its
            defaults; automatic
            steps: each speed its own N_s, the histories at the smallest).
        keep_periods: the kept periods (default the model's, 4), >= the scene's period.
        descending: continue from the last speed down (records in the order of ``speeds``).
        tol: the settled bound, > 0. progress: ``progress(n_done)`` after each speed.

    Returns:
        :class:`SettledSweep`.

    Raises:
        ValueError: a model kind that does not settle, speeds not ascending or not > 0, a
            ``tol`` <= 0, bad settings (before any work).
    """
    if not model.settles:  # what the model kind declares (AbstractDynamicModel.settles)
        raise ValueError(
            f"model = {type(model).__name__}: a settled sweep continues from speed to speed; "
            "allowed a kind that settles, a lumped DynamicModel (a hybrid model or a planetary "
            "stage: speed_sweep with a SteadyState)"
        )
    if not tol > 0:
        raise ValueError(f"tol = {tol!r}: out of range, allowed > 0")
    sp = np.asarray(speeds, dtype=float)
    if sp.ndim != 1 or sp.size < 1 or not np.all(sp > 0) or not np.all(np.isfinite(sp)):
        raise ValueError("speeds must be a non-empty 1-D array of pinion speeds > 0 (rad/s)")
    if np.any(np.diff(sp) < 0):
        raise ValueError("speeds: allowed ascending pinion speeds (rad/s) for a settled sweep")
    default_keep = model.default_settings()[2].keep_periods
    keep = int(default_keep if keep_periods is None else keep_periods)
    q = model.span_periods()
    block = q * -(-keep // q)  # a whole number of scene periods: each window ends where it began
    integrator, law, window, outputs = resolve_settings(
        model, integrator, contact, SteadyState(max(block, 2), keep), outputs or Outputs()
    )
    damping, k_mesh = model.settling_measures()
    k_mesh = float(k_mesh)
    modes = model.averaged_modes()
    ratios = modal_damping_ratios(modes, damping)
    t_s, w_min = settling_time(modes, ratios)
    # the modes a cap must let settle: the rule's and the lighter coupled ones (>= 1 % share)
    t_c = max(settling_time(modes, ratios, CAP_ENERGY_MIN)[0], t_s)
    angle = float(model.mesh_period_angle())
    if integrator.steps_per_period is None:
        ns = np.asarray(auto_steps_per_period(model, sp, modes), dtype=int)
    else:
        ns = np.full(sp.shape, int(integrator.steps_per_period))
    rule = keep + np.ceil(np.minimum(t_s * sp / angle, 1e9)).astype(np.int64)
    slow = keep + np.ceil(np.minimum(t_c * sp / angle, 1e9)).astype(np.int64)
    # the cap: twice an independent run's span (a continued speed starts closer than the rest
    # state does) or the span that lets the modes with >= 1 % share settle, where longer
    # (lighter damped, they ring longest where the mesh frequency is near theirs), >= 4 windows
    blocks = np.maximum(-(-np.maximum(CAP_FACTOR * rule, slow) // block), 4)
    # bounded as one run's steps are: a speed's windows together at most MAX_STEPS_PER_SPEED
    blocks = np.maximum(np.minimum(blocks, MAX_STEPS_PER_SPEED // (block * ns)), 2)
    steps_of = None
    if integrator.traced_steps and len(set(ns.tolist())) > 1:
        steps_of = model.prepare_steps(
            integrator, law, window, tuple(sorted(set(ns.tolist()))), outputs, modes
        )
    prepared: dict = {}

    def prepare(n: int):
        if n not in prepared:
            if steps_of is not None:
                prepared[n] = steps_of(n)
            else:
                prepared[n] = model.prepare(integrator, law, window, n, outputs, modes)
        return prepared[n]

    n_min = int(ns.min())
    thin = steps_of is None  # a program per N_s: the histories subsampled here
    order = np.arange(sp.size)[::-1] if descending else np.arange(sp.size)
    records: list = [None] * sp.size
    periods = np.zeros(sp.size, dtype=int)
    change = np.full(sp.size, np.nan)
    mass, structure = model.structure_matrices()
    mass = np.asarray(mass)
    stiff = np.asarray(structure) + np.asarray(modes.mesh_stiffness)
    # records of one scene period (judged by their return) on Newmark: a continued speed's
    # first window runs after a lead of `lead` periods, every window from the mesh position
    # `phase` (one compiled program: the kind's independent_at, where it runs_from_position)
    by_return = keep < 2 * q  # the records hold one scene period: no periodicity
    at = by_return and isinstance(integrator, Newmark) and model.runs_from_position
    lead = max(block // LEAD_DIVISOR, 1) if at else 0
    phases = np.zeros(sp.size, dtype=int)
    phase = 0  # the mesh position (periods of the first mesh) of `state`

    def run(n: int, speed: float, state, phase: int, ahead: int):
        """(the window's response, the state where its window starts)."""
        v = jnp.asarray(speed, model.dtype)
        if not at:
            return model.independent(prepare(n), v, start=state), state
        return model.independent_at(prepare(n), v, phase * n, state, ahead * n)

    state, last_speed = None, None
    for done, i in enumerate(order):
        s = float(sp[i])
        led = 0  # the lead this speed runs (a continued speed's)
        if state is not None:  # the same response over the mesh angle: Ẋ ∝ Ω
            state = (state[0], state[1] * (s / last_speed))
            led = lead
        ahead = led
        # the slowest excited mode's decay over one window at this speed: ρ = SETTLE_TOL^(T_w /
        # t_s) (T_w = block mesh periods); a window whose end state returns to its start within
        # d has at most d / (1 - ρ) of transient left at its start (a contraction by ρ)
        rho = SETTLE_TOL ** (block * angle / s / t_s) if math.isfinite(t_s) else 1.0
        fly = _free_decay(modes, ratios, mass, block * angle / s) if by_return else None
        prev = None
        for b in range(int(blocks[i])):
            r, begin = run(int(ns[i]), s, state, phase, ahead)
            r = _host(r)
            periods[i] = led + (b + 1) * block
            if int(r.result) != 0:
                state, phase = None, 0
                break
            if ahead:  # the window began after the lead: judged from there
                phase, ahead = (phase + lead) % q, 0
                state = begin
            fs = np.asarray([float(m.static_force) for m in r.meshes])
            fm = np.stack([np.asarray(m.mesh_force) / f for m, f in zip(r.meshes, fs)])
            # the last kept period against the one before (NaN: fewer than two scene periods)
            periodic = [float(m.periodicity) for m in r.meshes]
            per = max(float(np.nan_to_num(v)) for v in periodic)
            judged = state is not None and not any(np.isfinite(periodic))
            if judged:
                # a window of one scene period (the kept periods hold one: no periodicity of
                # the records, and the window before's records begin with the transient of the
                # speed change): the window's own return, its end state against its start,
                # over 1 - ρ (the transient its records can still hold)
                back = _state_change(r.final_state, state, mass, stiff, k_mesh, fs)
                change[i] = back / (1.0 - rho) if rho < 1.0 else math.inf
            elif prev is not None:  # the window's forces against the window before's
                change[i] = max(float(np.max(np.abs(fm - prev))), per)
            elif state is not None:  # a continued speed's first window: its end state
                change[i] = max(_state_change(r.final_state, state, mass, stiff, k_mesh, fs), per)
            end = (np.asarray(r.final_state[0]), np.asarray(r.final_state[1]))
            if judged and not change[i] <= tol:  # the next window from the estimated orbit
                end = _shoot(end, (np.asarray(state[0]), np.asarray(state[1])), fly)
            state = (jax.device_put(end[0]), jax.device_put(end[1]))
            if change[i] <= tol:
                break
            prev = fm
        last_speed = s
        phases[i] = phase
        if thin and int(ns[i]) != n_min:
            one = jax.tree.map(lambda a: np.asarray(a)[None], r)
            r = jax.tree.map(lambda a: a[0], _subsample(one, int(ns[i]) // n_min))
        records[i] = r
        if progress is not None:
            progress(done + 1)
    results = jax.tree.map(lambda *a: jax.device_put(np.stack(a)), *records)
    settled = np.asarray(change <= tol)
    cap = blocks * block + lead
    return SettledSweep(
        SweepResult(jnp.asarray(sp, model.dtype), results),
        periods,
        change,
        settled,
        cap.astype(int),
        float(t_s),
        w_min / (2 * math.pi),
        int(block),
        keep,
        phases,
    )
