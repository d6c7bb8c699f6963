"""The steady-state response of every dynamic model at one speed (:class:`DynamicResponse`), a
speed sweep's results (:class:`SweepResult`), and the one place where a run's records become
them (:func:`steady_state`): lumped and hybrid models fill the same fields the same way
(docs/dynamics.md, "Time integration": the outputs per speed)."""

from __future__ import annotations

import equinox as eqx
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float, Int

from .._results import DynamicsResult, error_if_failed, raise_if_failed
from .._util import is_traced, of_the_one_mesh, only_one_mesh, rms_about_mean, safe_sqrt
from ._settings import UNDER_RESOLVED_STEPS

__all__ = ["DynamicResponse", "DynamicResult", "MeshDynamics", "Records", "SweepResult"]


class MeshDynamics(eqx.Module):
    """Steady-state response of one gear mesh at one speed (K recorded steps; a sweep adds a
    leading speed axis to every leaf).

    Attributes:
        mesh_force: dynamic flank-normal mesh force Σ p l over the mesh's cells (N), shape (K,).
        static_force: the static mesh force F_s (N): T/(r_b1 cos β_b) for the mesh of a pair
            (the mean quasi-static force of the mesh over a mesh period, which equals it).
        transmission_error: dynamic TE (u·X − e_ref)/cos β_b (m), shape (K,).
        line_force: force per contact line (one tooth pair) (N), shape (K, n_lines).
        static_te: quasi-static TE at the same positions (m), shape (K,) (a hybrid model's at
            the same place in the first mesh period, the body stations then under the mesh,
            with the centrifugal load at the speed).
        dynamic_factor: max mesh force / static mesh force F_s (-).
        dynamic_factor_tooth: max tooth force / max quasi-static tooth force (-).
        te_rms: RMS of the dynamic TE about its mean (m). te_mean: its mean (m).
        contact_loss: fraction of recorded steps with total contact loss (mesh force < 1e-3 F_s).
        periodicity: max |F_m(last period) − F_m(previous period)| / F_s (-); NaN with one kept
            period.
        max_pressure: the largest Hertzian contact pressure p₀ = √(w E*/(π R)) over the
            mesh's cells and the kept steps (Pa), reduced inside the time loop; None unless the
            run tracks it (``pressure=`` :class:`~jaxgear.dynamics.HertzPressure` of
            :func:`~jaxgear.dynamics.simulate` or :func:`~jaxgear.dynamics.speed_sweep`; K. L.
            Johnson, *Contact Mechanics*, §4.3; the seed's Fig. IV-44 is its quasi-static
            counterpart per position).
        max_pressure_static: the largest quasi-static one over the run's positions of a mesh
            period (Pa), from the loads of ``static_te``'s solution (a lumped model's at rest,
            a hybrid model's with the centrifugal load at the speed); None likewise.
        line_load: the line load of every cell at the kept steps (N per metre of contact line,
            flank-normal), shape (K, L, N) (L contact lines of N slices; 0 off the flanks and
            out of contact); None unless recorded (``cell_loads=True``). Σ over a line's cells
            of ``line_load`` × the cell length is ``line_force``.
        coast_share: with coast flanks (backlash; docs/backlash.md), the fraction of recorded
            steps with the coast flanks in contact (coast force > 1e-3 F_s); None without.
            ``mesh_force`` is then the drive flanks' force less the coast flanks' (negative on
            the coast side) and ``contact_loss`` the steps with neither flank in contact.
        impacts_drive, impacts_coast: re-contacts over the recorded steps (a flank's force
            rising through 1e-3 F_s after a loss of its contact), each flank; None without
            coast flanks.
        cell_s: the cells' base-plane coordinate along the line of action at those steps (m),
            (K, L, N). cell_z: across the face (m), (K, L, N). cell_mask: on the flanks, (K, L,
            N). None unless recorded. With them :func:`jaxgear.contact_pressure` and
            :func:`jaxgear.load_map` take a dynamic mesh as they take a quasi-static one.
    """

    mesh_force: Float[Array, " K"]
    static_force: Float[Array, ""]
    transmission_error: Float[Array, " K"]
    line_force: Float[Array, "K L"]
    static_te: Float[Array, " K"]
    dynamic_factor: Float[Array, ""]
    dynamic_factor_tooth: Float[Array, ""]
    te_rms: Float[Array, ""]
    te_mean: Float[Array, ""]
    contact_loss: Float[Array, ""]
    periodicity: Float[Array, ""]
    max_pressure: Float[Array, ""] | None = None
    max_pressure_static: Float[Array, ""] | None = None
    line_load: Float[Array, "K L N"] | None = None
    cell_s: Float[Array, "K L N"] | None = None
    cell_z: Float[Array, "K L N"] | None = None
    cell_mask: Bool[Array, "K L N"] | None = None
    coast_share: Float[Array, ""] | None = None
    impacts_drive: Int[Array, ""] | None = None
    impacts_coast: Int[Array, ""] | None = None


class DynamicResponse(eqx.Module):
    """Steady-state response at one speed (K = keep_periods · N_s recorded steps; a sweep adds a
    leading speed axis to every leaf), for every model (:func:`jaxgear.dynamics.dynamic_model`):
    the structure's records and, per gear mesh, a :class:`MeshDynamics`. (Its ``result`` holds
    a code of :class:`jaxgear.DynamicsResult`, the result codes; ``DynamicResult`` is this
    class's former name, kept as an alias.)

    A scene of one gear mesh reads that mesh's response directly on this object
    (``mesh_force``, ``static_force``, ``transmission_error``, ``line_force``, ``static_te``,
    ``dynamic_factor``, ``dynamic_factor_tooth``, ``te_rms``, ``te_mean``, ``contact_loss``,
    ``periodicity``, ``max_pressure``, ``max_pressure_static``, ``line_load``, ``cell_s``,
    ``cell_z``, ``cell_mask``: see :class:`MeshDynamics`); a scene of several meshes reads them
    from ``meshes[k]``.

    Attributes:
        speed: pinion speed Ω (rad/s). mesh_frequency: Ω z1 / 2π (Hz).
        time: the recorded times (s), shape (K,), on the clock of the nominal motion θ = Ω t:
            a run starts at t = Δt/2 from its first position θ = Δθ/2 (the mid-point of the
            first step, where the cells are tabulated: contact-line ends off the edges of the
            base plane), so step n ends at t = (n + 3/2) Δt, at the angle whose cells it took
            (``theta`` = Ω ``time``, modulo the table's period for a lumped model). The records
            are in phase with a continuous-time solution read at ``time`` (docs/design.md,
            "Gear trains: layout and mesh phasing"). time_step: their spacing (s): the run's
            Δt, or a multiple of it where a sweep with several N_s subsampled the records
            (:func:`~jaxgear.dynamics.speed_sweep`).
        theta: pinion angle at the recorded steps (rad), (K,): modulo one mesh period for a
            lumped model (the positions of its cell table; modulo the span of a two-stage
            train, :meth:`~jaxgear.scenes.Scene.scene_periods` periods), the angle turned from
            the start for a hybrid model (where the bodies' stations are).
        bearing_force: support force components R X (N), fixed frame, shape (K, r) (r = 0 for
            torsional scenes; :meth:`DynamicScene.reaction_matrix`, a hybrid scene's
            :meth:`~jaxgear.scenes.HybridPair.bearing_forces`). bearing_force_max: max |R X|
            over the kept periods, shape (r,). bearing_force_static: max over positions of the
            static one.
        steps_per_period: time steps per mesh period N_s actually used (automatic or given).
        steps_per_mode_period: N_s f_mesh / f_max, time steps per period of the highest mode the
            mesh excites (mesh-energy share >= 5 %; docs/dynamics.md "Time step and accuracy");
            NaN where the run had no modal analysis (a hybrid model with a fixed step count).
        under_resolved: steps_per_mode_period < 20: the dynamic factor may be off by more than
            1 % (underestimated by 3-30 % below ~13 at low speed with a stepwise stiffness).
        final_state: (X, Ẋ, Ẍ) at the end (continuation start), each shape (n,).
        iterations: max contact passes per step (Newmark) or ODE steps taken (diffrax).
        result: 0 ok, else a :class:`~jaxgear.DynamicsResult` code.
        rim_radial, rim_axial: a hybrid model's rim displacement at the stations of every
            condensed member, member after member (each in its body frame, the axial master
            plane nearest mid-face), radial and axial (m), shape (K, Σ Z): a flexible wheel's
            (K, Z); (K, 0) with every member rigid and for lumped models. Split them per member
            with :func:`jaxgear.dynamics.rim_stations`, read them with
            :func:`jaxgear.dynamics.rim_waves`.
        meshes: one :class:`MeshDynamics` per gear mesh, in the scene's mesh order.
        states: the coordinates X at the recorded steps (K, n) when asked for (``states=True``
            of :func:`~jaxgear.dynamics.simulate` and :func:`~jaxgear.dynamics.speed_sweep`),
            else None.
    """

    speed: Float[Array, ""]
    mesh_frequency: Float[Array, ""]
    time: Float[Array, " K"]
    time_step: Float[Array, ""]
    theta: Float[Array, " K"]
    bearing_force: Float[Array, "K r"]
    bearing_force_max: Float[Array, " r"]
    bearing_force_static: Float[Array, " r"]
    steps_per_period: Int[Array, ""]
    steps_per_mode_period: Float[Array, ""]
    under_resolved: Bool[Array, ""]
    final_state: tuple
    iterations: Int[Array, ""]
    result: Int[Array, ""]
    rim_radial: Float[Array, "K Z"]
    rim_axial: Float[Array, "K Z"]
    meshes: tuple[MeshDynamics, ...]
    states: Float[Array, "K n"] | None = None

    @property
    def mesh(self) -> MeshDynamics:
        """The response of the scene's one gear mesh."""
        return only_one_mesh(self.meshes, "responses")

    def force_ratios(self) -> tuple[Float[Array, "... K"], ...]:
        """Each mesh's force over its static force F/F_s (-) at every recorded step: one
        array (..., K) per mesh (a sweep's (S, K))."""
        return tuple(m.mesh_force / m.static_force[..., None] for m in self.meshes)

    mesh_force = of_the_one_mesh("mesh_force")
    static_force = of_the_one_mesh("static_force")
    transmission_error = of_the_one_mesh("transmission_error")
    line_force = of_the_one_mesh("line_force")
    static_te = of_the_one_mesh("static_te")
    dynamic_factor = of_the_one_mesh("dynamic_factor")
    dynamic_factor_tooth = of_the_one_mesh("dynamic_factor_tooth")
    te_rms = of_the_one_mesh("te_rms")
    te_mean = of_the_one_mesh("te_mean")
    contact_loss = of_the_one_mesh("contact_loss")
    periodicity = of_the_one_mesh("periodicity")
    max_pressure = of_the_one_mesh("max_pressure")
    max_pressure_static = of_the_one_mesh("max_pressure_static")
    line_load = of_the_one_mesh("line_load")
    cell_s = of_the_one_mesh("cell_s")
    cell_z = of_the_one_mesh("cell_z")
    cell_mask = of_the_one_mesh("cell_mask")
    coast_share = of_the_one_mesh("coast_share")
    impacts_drive = of_the_one_mesh("impacts_drive")
    impacts_coast = of_the_one_mesh("impacts_coast")


#: the former name of :class:`DynamicResponse` (deprecated: it read as ``jaxgear.DynamicsResult``,
#: the result codes); kept as an alias
DynamicResult = DynamicResponse


class SweepResult(eqx.Module):
    """Speed sweep over S speeds.

    Attributes:
        speeds: pinion speeds (rad/s), shape (S,).
        results: :class:`DynamicResponse` per speed (leaves with a leading S axis), in the order of
            ``speeds``: the independent, up or down sweep.
        down: with ``direction="both"``, the down sweep (same order as ``speeds``); else None.
    """

    speeds: Float[Array, " S"]
    results: DynamicResponse
    down: DynamicResponse | None = None

    @property
    def dynamic_factor(self) -> Float[Array, " S"]:
        return self.results.dynamic_factor


def checked(r: DynamicResponse, name: str) -> DynamicResponse:
    """``r`` raising ``eqx.EquinoxRuntimeError`` where its result code is not 0, the check
    riding on every mesh's dynamic factor and on the code (what a caller reads: under a
    caller's ``jax.jit`` a check on an output nobody reads would be dropped). A concrete ``r``
    (no caller's trace) is checked on the host: an ``eqx.error_if`` on concrete values compiles
    a program of its own holding a Python callback, which JAX's persistent compilation cache
    never stores (each run compiled it again)."""
    if not is_traced(r.result):
        raise_if_failed(r.result, DynamicsResult, name)
        return r

    def guarded(x):  # a kind's own response (a planetary stage's) has no MeshDynamics
        meshes = x.meshes if isinstance(x, DynamicResponse) else ()
        return [m.dynamic_factor for m in meshes] + [x.result]

    return eqx.tree_at(
        guarded, r, [error_if_failed(v, r.result, DynamicsResult, name) for v in guarded(r)]
    )


def _impacts(in_contact, valid=None) -> Int[Array, ""]:
    """Re-contacts: steps in contact after a step out of contact, (K,) booleans (over the
    ``valid`` (K,) records only; None: all)."""
    new = in_contact[1:] & ~in_contact[:-1]
    return jnp.sum(new if valid is None else new & valid[1:])


class Records(eqx.Module):
    """What one speed's run recorded over its K kept steps, m meshes: the one input of
    :func:`steady_state`, filled by every engine (lumped and hybrid) the same way.

    Attributes:
        speed (rad/s), time_step (s), mesh_period_angle 2π/z1 (rad): scalars.
        steps_per_period: N_s (static). transient_steps: steps run before the kept ones (whole
            periods; static).
        theta (K,), bearing_force (K, r): the records. Per mesh: mesh_force (K, m),
            transmission_error (K, m), line_force (a tuple of (K, L_k), one per mesh),
            static_te (K, m); static_force: F_s (N), (m,); static_line_force: the largest
            quasi-static force on one contact line (N), (m,).
        bearing_force_static: the static support forces at the table positions (P, r).
        omega_excited: the highest natural frequency the mesh excites (rad/s; NaN: unknown).
        final_state: (X, Ẋ, Ẍ). iterations, code: the run's most contact passes and result code.
        rim: (radial, axial) rim records, each (K, Z). states: (K, n) or None.
        scene_steps: the steps of one scene period (None: N_s; a two-stage train's span): the
            periodicity compares the last two of them (static).
        pressure: None, or (the largest p₀² over each mesh's cells per kept step (K, m), the
            largest quasi-static one per position (P, m)) (Pa²): each mesh's
            ``max_pressure`` and ``max_pressure_static``.
        cells: None, or per mesh (line load (N/m), s (m), z (m), mask), each (K, L_k, N_k).
        coast_force: None, or each mesh's coast flanks' force (N), (K, m) (``mesh_force`` then
            the drive force less it): the coast share and the impact counts.
        kept: None (all K records kept), or the number of valid records (int, traced) of a run
            whose N_s is an argument of its program: the first ``kept`` of a buffer of K;
            ``steps_per_period``, ``transient_steps`` and ``scene_steps`` are then traced too,
            and the statistics are masked to the valid records.
    """

    speed: Float[Array, ""]
    time_step: Float[Array, ""]
    mesh_period_angle: Float[Array, ""]
    theta: Float[Array, " K"]
    mesh_force: Float[Array, "K m"]
    static_force: Float[Array, " m"]
    transmission_error: Float[Array, "K m"]
    line_force: tuple
    static_line_force: Float[Array, " m"]
    static_te: Float[Array, "K m"]
    bearing_force: Float[Array, "K r"]
    bearing_force_static: Float[Array, "P r"]
    omega_excited: Float[Array, ""]
    final_state: tuple
    iterations: Int[Array, ""]
    code: Int[Array, ""]
    rim: tuple
    steps_per_period: int | Int[Array, ""]
    transient_steps: int | Int[Array, ""]
    states: Float[Array, "K n"] | None = None
    scene_steps: int | Int[Array, ""] | None = None
    pressure: tuple | None = None
    cells: tuple | None = None
    coast_force: Float[Array, "K m"] | None = None
    kept: Int[Array, ""] | None = None

    def valid(self, K: int):
        """The valid records of K: None (all), or a (K,) mask."""
        return None if self.kept is None else jnp.arange(K) < self.kept


def _max(x, valid, axis=None):
    """max of ``x`` over ``axis`` (None: all), over the ``valid`` (K,) leading entries only
    (None: all)."""
    if valid is not None:
        x = jnp.where(valid.reshape(valid.shape + (1,) * (x.ndim - 1)), x, -jnp.inf)
    return jnp.max(x, axis=axis)


def _mean(x, valid):
    """mean of ``x`` (K,) over its ``valid`` entries (None: all)."""
    if valid is None:
        return jnp.mean(x)
    return jnp.sum(jnp.where(valid, x, 0)) / jnp.sum(valid)


def _rms_about_mean(x, valid):
    """:func:`jaxgear._util.rms_about_mean` of ``x`` (K,) over its ``valid`` entries."""
    if valid is None:
        return rms_about_mean(x)
    d = x - _mean(x, valid)
    return safe_sqrt(_mean(d * d, valid))


def _history(r, take):
    """``r`` (a :class:`DynamicResponse`, one speed or batched) with ``take`` applied to each of
    its histories (the per-step records: times, angles, bearing forces, rim, states, each
    mesh's forces, TE, line forces, static TE and cell loads)."""
    hist = ("time", "theta", "bearing_force", "rim_radial", "rim_axial")
    if r.states is not None:
        hist += ("states",)
    per_mesh = ("mesh_force", "transmission_error", "line_force", "static_te")
    if r.meshes[0].line_load is not None:
        per_mesh += ("line_load", "cell_s", "cell_z", "cell_mask")

    def records(x):
        leaves = [getattr(x, h) for h in hist]
        return leaves + [getattr(mesh, h) for mesh in x.meshes for h in per_mesh]

    return eqx.tree_at(records, r, [take(a) for a in records(r)])


def thinned(r, m, take):
    """``r`` keeping every m-th record (ending on each period's last step): ``take(a, m)`` of
    each history; ``time_step`` becomes the spacing of the kept records, m Δt."""
    r = _history(r, lambda a: take(a, m))
    return eqx.tree_at(lambda x: x.time_step, r, r.time_step * m)


def _mesh_dynamics(r: Records, k: int) -> MeshDynamics:
    """Mesh ``k``'s :class:`MeshDynamics` from the K records ``r`` (:func:`steady_state`); the
    periodicity compares the last two scene periods (``scene_steps``, default N_s)."""
    fm, fs, te = r.mesh_force[:, k], r.static_force[k], r.transmission_error[:, k]
    lines, static_line_force = r.line_force[k], r.static_line_force[k]
    P = r.steps_per_period if r.scene_steps is None else r.scene_steps
    coast = None if r.coast_force is None else r.coast_force[:, k]
    K = fm.shape[0]
    valid = r.valid(K)
    p_max = p_static = None
    if r.pressure is not None:
        p_max = jnp.sqrt(_max(r.pressure[0][:, k], valid))
        p_static = jnp.sqrt(jnp.max(r.pressure[1][:, k]))
    cells = (None,) * 4 if r.cells is None else r.cells[k]
    if valid is not None:  # the last two periods of the first ``kept`` records, masked
        i = jnp.arange(K)
        last = (i >= r.kept - P) & valid
        d = jnp.abs(fm - fm[jnp.maximum(i - P, 0)])
        periodicity = jnp.max(jnp.where(last, d, -jnp.inf)) / fs
        periodicity = jnp.where(r.kept >= 2 * P, periodicity, jnp.nan)
    elif K >= 2 * P:
        periodicity = jnp.max(jnp.abs(fm[K - P :] - fm[K - 2 * P : K - P])) / fs
    else:
        periodicity = jnp.asarray(jnp.nan, fm.dtype)
    thr = 1e-3 * fs
    loss = fm < thr
    share = imp_d = imp_c = None
    if coast is not None:  # fm = drive − coast: the flanks' own forces
        on_coast, on_drive = coast > thr, fm + coast > thr
        loss = ~on_coast & ~on_drive
        share = _mean(on_coast.astype(fm.dtype), valid)
        imp_d, imp_c = _impacts(on_drive, valid), _impacts(on_coast, valid)
    return MeshDynamics(
        mesh_force=fm,
        static_force=jnp.asarray(fs, fm.dtype),
        transmission_error=te,
        line_force=lines,
        static_te=r.static_te[:, k],
        dynamic_factor=_max(fm, valid) / fs,
        dynamic_factor_tooth=_max(lines, valid) / static_line_force,
        te_rms=_rms_about_mean(te, valid),
        te_mean=_mean(te, valid),
        contact_loss=_mean(loss.astype(fm.dtype), valid),
        periodicity=periodicity,
        max_pressure=p_max,
        max_pressure_static=p_static,
        line_load=cells[0],
        cell_s=cells[1],
        cell_z=cells[2],
        cell_mask=cells[3],
        coast_share=share,
        impacts_drive=imp_d,
        impacts_coast=imp_c,
    )


def steady_state(r: Records) -> DynamicResponse:
    """The :class:`DynamicResponse` of one speed's :class:`Records` over its K kept steps: each
    mesh's statistics (:class:`MeshDynamics`), the bearing maxima, the clock of the records and
    the resolution flags; a non-finite record turns a zero result code into 2."""
    P = r.steps_per_period
    fm, te = r.mesh_force, r.transmission_error
    K = fm.shape[0]
    valid = r.valid(K)
    finite = jnp.all(jnp.isfinite(fm)) & jnp.all(jnp.isfinite(te))
    code = jnp.where((r.code == 0) & ~finite, 2, r.code)
    meshes = tuple(_mesh_dynamics(r, k) for k in range(fm.shape[1]))
    speed, time_step, mesh_period_angle = r.speed, r.time_step, r.mesh_period_angle
    # f_mesh / f_max = Ω (2π/z1)^-1 / (ω_max / 2π)
    per_mode = P * 2 * jnp.pi * speed / (mesh_period_angle * r.omega_excited)
    return DynamicResponse(
        speed=speed,
        mesh_frequency=speed / mesh_period_angle,
        # step n ends at θ = (n + 3/2) Δθ (the table's mid-points), t = θ/Ω
        time=(r.transient_steps + 1.5 + jnp.arange(K)) * time_step,
        time_step=jnp.asarray(time_step, fm.dtype),
        theta=r.theta,
        bearing_force=r.bearing_force,
        bearing_force_max=_max(jnp.abs(r.bearing_force), valid, axis=0),
        bearing_force_static=jnp.max(jnp.abs(r.bearing_force_static), axis=0),
        steps_per_period=jnp.asarray(P),
        steps_per_mode_period=per_mode,
        under_resolved=per_mode < UNDER_RESOLVED_STEPS,
        final_state=r.final_state,
        iterations=jnp.asarray(r.iterations),
        result=jnp.asarray(code),
        rim_radial=r.rim[0],
        rim_axial=r.rim[1],
        meshes=meshes,
        states=r.states,
    )
