"""The lumped engine (:class:`~jaxgear.dynamics.DynamicModel`, an
:class:`~jaxgear.dynamics.AbstractDynamicModel`): Newmark on the mesh table (the contact in
coordinates) or a diffrax solver, one speed to steady state (:func:`_one_speed`), one speed,
vmapped or continued over speeds (:func:`_single`, :func:`_vmapped`, :func:`_scans`). The
public entries :func:`jaxgear.dynamics.simulate` and :func:`jaxgear.dynamics.speed_sweep` call
it through :meth:`DynamicModel.prepare`, :meth:`DynamicModel.independent` and
:meth:`DynamicModel.continuation`."""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._baseplane import on_the_path
from .._contact import ContactLaw, ExactContact, _phi, contact_law
from .._modifications import Modifications
from .._quasi_static import per_mesh_modifications, separation
from .._util import as_float, check_integer
from ..scenes import AssembledScene, DynamicScene
from ._devices import several_devices, shard_speeds
from ._modal import ModalAnalysis, excited_omega
from ._model import (
    AbstractDynamicModel,
    MeshTable,
    _HeldTable,
    _prep,
    _Prepared,
    cell_geometry,
    deviation_periods,
    mesh_max,
    mesh_rows,
    mesh_te,
    pressure_factors,
    split_cells,
    static_mesh_forces,
)
from ._newmark import LinearSystem, StepCells, newmark, newmark_counted
from ._result import Records, steady_state, thinned
from ._stage import AbstractStage, mean_cell_stiffness
from ._settings import (
    DiffraxIntegrator,
    Newmark,
    SteadyState,
    _Config,
    _config,
    _divergence_code,
)
from ._whine import lumped_whine
from ._whine_methods import HarmonicBalance, QuasiPeriodicBalance, TransmissionErrorSource

__all__ = ["DynamicModel", "static_start"]

#: mesh positions per period of the mean cell stiffness of a stage's torsional chain view
#: (:meth:`DynamicModel.matrices`)
CHAIN_POSITIONS = 64


class DynamicModel(AbstractDynamicModel, AbstractStage):
    """A dynamic scene at an operating torque, with its damping (build with
    :func:`~jaxgear.dynamics.dynamic_model`): the lumped engine, the cells in coordinates on a
    mesh table (:class:`MeshTable`), Newmark or a diffrax solver.

    A pair's model given its ``input`` side is also a gearbox stage
    (:class:`~jaxgear.dynamics.AbstractStage`; docs/architecture.md, "One stage contract"): the
    object that :func:`~jaxgear.dynamics.simulate` runs alone is the object a
    :class:`jaxgear.gearbox.GearboxTorsional` takes. The scene kind gives the part of the
    contract on its coordinates (:attr:`~jaxgear.scenes.AssembledScene.torque_dofs`, the
    shafts' joints; ``stage_senses``, ``stage_coordinates``); the model
    the rest once (the mean cell stiffness, the cells at a travel from its modifications'
    separations, the kinematics from the base radii). :func:`~jaxgear.dynamics.stage_model`
    builds a model for a gearbox only: without an operating torque, modes or damping (the
    gearbox's coupled run carries its own), so that it cannot run alone.

    Attributes:
        scene: the :class:`DynamicScene` (M, K_s, V). mods: flank modifications, one
            :class:`~jaxgear.Modifications` for every mesh or a tuple of one per mesh
            (differentiable: δ0 is rebuilt from them in every simulation). torque: pinion
            torque T (N·m).
        damping: the (n, n) damping matrix C, built once from the modal analysis of the
            time-averaged system, plus the scene's bearing damping if it has one
            (:func:`~jaxgear.dynamics.damping_matrix`; held fixed under differentiation wrt
            ``mods``).
        modes: :class:`ModalAnalysis` of the time-averaged system.
        mesh_stiffness_mean: time-averaged loaded mesh stiffness k̄ = ⟨Σ w k l⟩ (N/m) over the
            cells of every mesh.
        deviation_span: mesh periods of the span a run covers when ``mods`` carry manufacturing
            deviations (static; None: the period over which they repeat,
            :func:`~jaxgear.dynamics.deviation_periods`). See
            :func:`~jaxgear.dynamics.span_periods`.
        held: the mesh table and static rows the build solved (over the scene's period at
            its ``positions_per_pitch`` with its contact law; None: none held): a run, a
            settled sweep or :func:`~jaxgear.dynamics.mesh_stiffness_means` asking for these
            very inputs reuses them instead of solving the static contact problem at every
            step of the period again; any other (another law or N_s, the model's scene, mods or torque replaced, traced)
            solves its own.
        input: static, the side the previous stage (or a gearbox's input torque) drives in a
            gearbox: 0 the pinion's torque node, 1 the gear's (the other the output); None: the
            model runs alone only (:meth:`check_stage` refuses it in a gearbox).

    ``torque``, ``damping``, ``modes`` and ``mesh_stiffness_mean`` are None in a model built
    for a gearbox only (:func:`~jaxgear.dynamics.stage_model`), whose runs alone are refused
    in one line.
    """

    scene: DynamicScene
    mods: Modifications | tuple
    torque: Float[Array, ""] | None
    damping: Float[Array, "n n"] | None
    modes: ModalAnalysis | None
    mesh_stiffness_mean: Float[Array, ""] | None
    deviation_span: int | None = eqx.field(static=True, default=None)
    held: _HeldTable | None = None
    input: int | None = eqx.field(static=True, default=None)

    continues: ClassVar[bool] = True
    whine_methods: ClassVar[tuple[type, ...]] = (
        HarmonicBalance, TransmissionErrorSource, QuasiPeriodicBalance)
    settles: ClassVar[bool] = True
    runs_from_position: ClassVar[bool] = True
    #: Newmark in the coordinates, or a diffrax solver on the first-order form
    integrators: ClassVar[tuple[type, ...]] = (Newmark, DiffraxIntegrator)
    band_factor: ClassVar[bool] = True
    #: the housing its scene's bearings sit in (scene kinds that take one: LumpedPair,
    #: LumpedTrain)
    takes_housing: ClassVar[bool] = True

    def __check_init__(self):
        if self.input not in (None, 0, 1):
            raise ValueError(f"DynamicModel: input = {self.input!r}: out of range, allowed 0 "
                             "(the pinion's torque node driven), 1 (the gear's) or None")

    @property
    def runs_alone(self) -> bool:
        """Whether the model was built to run alone (an operating torque, its modes and
        damping: :func:`~jaxgear.dynamics.dynamic_model`), not for a gearbox only
        (:func:`~jaxgear.dynamics.stage_model`)."""
        return self.modes is not None

    def _check_runs(self) -> None:
        if not self.runs_alone:
            raise ValueError(
                "model: a DynamicModel built for a gearbox only (stage_model: no torque, modes "
                "or damping) does not run alone: allowed dynamic_model(scene, mods, torque, "
                "input=...)"
            )

    def critical_speeds(self, harmonic: int = 1) -> Float[Array, " n"]:
        """Pinion speeds (rad/s) where the ``harmonic``-th mesh harmonic meets each natural
        frequency: Ω = ω_i · (2π/z1) / (2π · harmonic) = ω_i / (z1 · harmonic)."""
        self._check_runs()
        return (
            self.modes.omega * self.scene.base_planes[0].mesh_period_angle / (2 * jnp.pi * harmonic)
        )

    def settling_measures(self):
        """(:attr:`damping`, :attr:`mesh_stiffness_mean`)."""
        self._check_runs()
        return self.damping, self.mesh_stiffness_mean

    def mesh_force_ratios(self, response):
        """:meth:`jaxgear.dynamics.DynamicResponse.force_ratios` of ``response``."""
        return response.force_ratios()

    def whine(self, speeds, method, *, positions=256, contact=ExactContact()):
        """The lumped model's gear whine (:func:`~jaxgear.dynamics.whine_response`, whose
        arguments, result and errors these are; docs/whine.md): the harmonic balance about
        its quasi-static solution (:func:`._whine.lumped_whine`)."""
        self._check_runs()
        return lumped_whine(self, speeds, method, positions=positions, contact=contact)

    def default_settings(self):
        """Newmark with automatic steps, the exact law (100 passes), 60 periods with 4 kept."""
        return Newmark(), ExactContact(), SteadyState()

    def check_integrator(self, integrator) -> None:
        if isinstance(integrator, Newmark) and integrator.basis is not None:
            raise ValueError(
                "integrator = Newmark(basis=...): a modal basis is for a hybrid model (allowed "
                "basis=None for a lumped one)"
            )

    def span_periods(self) -> int:
        """The scene's period times, with manufacturing deviations, ``deviation_span`` or else
        their period (:func:`~jaxgear.dynamics.deviation_periods`)."""
        q = self.scene.scene_periods()
        dev = deviation_periods(self.mods)
        if dev == 1:
            return q
        return q * (self.deviation_span if self.deviation_span is not None else dev)

    def steps_multiple(self) -> int:
        """The least N_s dividing every mesh's period into whole steps, lcm of the
        denominators of T_k/T_0; 1 with manufacturing deviations (tabulated over the span
        whatever N_s)."""
        if deviation_periods(self.mods) > 1:
            return 1
        return math.lcm(*(f.denominator for f in self.scene.mesh_periods()))

    def averaged_modes(self, *, speed=0.0, positions_per_pitch=64, contact=ExactContact()):
        """The model's own modes (:attr:`modes`, built with it; the arguments are not used)."""
        self._check_runs()
        return self.modes

    def prepare(self, integrator, law, window, steps_per_period, outputs, modes=None):
        """The mesh table and static rows of ``steps_per_period`` steps per period over the
        model's span (:class:`LumpedRun`); ``modes`` unused (the model's own)."""
        self._check_runs()
        cells = sum(p.n_lines * p.n_slices for p in self.scene.base_planes)
        cfg = _config(integrator, window, int(steps_per_period), outputs, cells=cells)
        return LumpedRun(_prep(self, law, cfg.steps_per_period), law, cfg)

    def prepare_steps(self, integrator, law, window, steps, outputs, modes=None):
        """Newmark: the table and static rows of each N_s of ``steps`` from one compiled
        program (:attr:`MeshTable.steps`, the table of the largest N_s's size, its static rows
        over the largest span), their runs from one program (the records of the largest N_s,
        the histories at the smallest); None with a diffrax solver, or where a mesh's rows are
        not in the same ratio to N_s at every N_s (:func:`mesh_rows`)."""
        self._check_runs()
        if not integrator.traced_steps:
            return None
        steps = sorted(int(n) for n in steps)
        n_min, n_max = steps[0], steps[-1]
        periods = self.span_periods()
        top = mesh_rows(self.scene, self.mods, n_max, periods)
        for n in steps:
            if n_max % n or mesh_rows(self.scene, self.mods, n, periods) != tuple(
                r * n // n_max for r in top
            ):
                return None
        cells = sum(p.n_lines * p.n_slices for p in self.scene.base_planes)
        cfg = _config(integrator, window, n_max, outputs, cells=cells)
        cfg = dataclasses.replace(cfg, history_steps=n_min)

        def at(n):
            if int(n) not in steps:
                raise ValueError(f"steps_per_period = {n}: allowed one of {steps}")
            prep = _prep(self, law, n_max, steps=jnp.asarray(int(n)))
            return LumpedRun(prep, law, cfg)

        return at

    def independent(self, prepared, speeds, *, start=None, shard=False):
        prep, law, cfg = prepared.prep, prepared.law, prepared.cfg
        start = _static_start(prep) if start is None else start
        if jnp.ndim(speeds) == 0:
            return _single(self, prep, speeds, start, law, cfg)
        if several_devices(shard, speeds):
            padded, _ = shard_speeds(speeds)
            r = _vmapped(self, prep, padded, start, law, cfg)
            return jax.tree_util.tree_map(lambda a: a[: speeds.shape[0]], r)
        return _vmapped(self, prep, speeds, start, law, cfg)

    def independent_at(self, prepared, speed, step, start, lead=0):
        """One speed (a scalar, rad/s) from ``start`` = (X, Ẋ) at the scene's step ``step``
        (an int >= 0: the state at that mesh position, the run's first step ending at
        ``step + 1``; :meth:`independent` starts at step 0; None: the static equilibrium at
        step 0's position), after ``lead`` steps unrecorded
        (an int >= 0) before the run's window, Newmark only: a settled sweep's windows
        (:func:`~jaxgear.dynamics.settled_sweep`), every one of them one compiled program
        (``step`` and ``lead`` are arguments of it). Returns (the response, as
        :meth:`independent`'s, of the window that starts at step ``step + lead``; (X, Ẋ)
        where that window starts, after the lead)."""
        if not prepared.cfg.newmark:
            raise ValueError(
                f"integrator = {prepared.cfg!r}: a run from a step other than 0 is Newmark's "
                "(allowed a Newmark integrator)"
            )
        start = _static_start(prepared.prep) if start is None else start
        row, lead = jnp.asarray(step, jnp.int32), jnp.asarray(lead, jnp.int32)
        return _single_at(self, prepared.prep, speed, start, row, lead, prepared.law, prepared.cfg)

    def continuation(self, prepared, speeds, *, start=None):
        start = _static_start(prepared.prep) if start is None else start
        return _scans(self, prepared.prep, speeds, start, prepared.law, prepared.cfg)

    # -- the stage contract (AbstractStage): the scene kind's coordinates, the rest once here

    def check_stage(self, where: str) -> None:
        """Refuse (one line naming ``where``) a model that cannot stand in a gearbox: no
        ``input`` side, a scene that is not a pair's with torque nodes (an
        :class:`~jaxgear.scenes.AssembledScene` of one mesh: a lumped 3D pair, a torsional
        :class:`~jaxgear.scenes.TorsionalDynamics`), a mesh with coast flanks."""
        if self.input is None:
            raise ValueError(
                f"{where}: a DynamicModel without its input side: allowed "
                "dynamic_model(..., input=0 or 1) or stage_model(scene, mods, input=0 or 1)"
            )
        if not isinstance(self.scene, AssembledScene) or len(self.scene.base_planes) != 1:
            raise ValueError(
                f"{where}: a DynamicModel of a {type(self.scene).__name__}: allowed a pair's "
                "scene with torque nodes (a lumped 3D pair, TorsionalDynamics)"
            )
        if self.scene.mesh.coast:
            raise ValueError(
                f"{where}: the scene's mesh has coast = True: allowed False (the coupled model "
                "carries the loaded flanks)"
            )

    def _senses(self):
        return self.scene.stage_senses()

    def _flip(self, a):
        """``a`` (n, n) on the stage's coordinates (:meth:`stage_senses` applied both sides)."""
        s = self._senses()
        return s[:, None] * a * s[None, :]

    def coordinates(self):
        """The scene's coordinates (``stage_coordinates``: a lumped scene's ``"<node> <dof>"``,
        a torsional scene's ``theta_pinion``, ``theta_wheel``), each counted in the common
        sense (``stage_senses``)."""
        return self.scene.stage_coordinates()

    def coordinate_ends(self):
        """The torque nodes' rotations (:attr:`~jaxgear.scenes.AssembledScene.torque_dofs`):
        the input side's, then the other's."""
        t = self.scene.torque_dofs
        return t[self.input], t[1 - self.input]

    def _stage_mods(self) -> Modifications:
        return per_mesh_modifications(self.mods, 1)[0]

    def dynamic_parts(self, positions):
        """(M, K_s, K̄_m, 0): the scene's mass and structure stiffness, its cells' mean
        stiffness over ``positions`` mid-points of a mesh period on the theoretical path
        (:func:`~jaxgear.dynamics.mean_cell_stiffness`), no own load."""
        m, k = self._flip(self.scene.mass()), self._flip(self.scene.stiffness())
        k_mean = mean_cell_stiffness(on_the_path(self).cell_row, self.mesh_period(), positions)
        return m, k, k_mean, jnp.zeros(m.shape[0], m.dtype)

    def cell_row(self, x):
        """The cells at the mesh travel ``x`` (m): pinion angle x / r_b1, the initial
        separations of the model's modifications (:func:`jaxgear.quasi_static`'s), on the
        scene's coordinates (the scene's ``cell_row``) in the common sense."""
        mesh = self.scene.mesh
        cells, _, delta0 = separation(mesh, self._stage_mods(), x / mesh.base_radius_pinion)
        row = self.scene.cell_row((cells,), (delta0,))
        return row._replace(V=row.V * self._senses()[None, :])

    def mesh_forces(self, forces):
        """cos β_b Σ P: the mesh's transverse force (N) from its cell forces."""
        return jnp.cos(self.scene.mesh.base_helix_angle) * jnp.sum(forces, axis=-1,
                                                                  keepdims=True)

    def mesh_names(self):
        return ("pair",)

    def mesh_period(self):
        return self.scene.mesh.base_pitch

    def kinematics(self, input_speed, input_torque):
        """From the base radii: the output turns the other way at ω r_in / r_out, carries
        T r_out / r_in; the mesh travels at r_in |ω|, its static force T / r_in."""
        mesh = self.scene.mesh
        r = jnp.stack([mesh.base_radius_pinion, mesh.base_radius_gear])
        r_in, r_out = r[self.input], r[1 - self.input]
        w = as_float(input_speed)
        torque = jnp.abs(as_float(input_torque))
        return (-w * r_in / r_out, torque * r_out / r_in, r_in * jnp.abs(w),
                jnp.reshape(torque / r_in, (1,)))

    def speed_terms(self, carrier_speed):
        """(the bearings' viscous damping (units of K s), zeros): the scene turns in the fixed
        frame (no Coriolis or centripetal terms); the bearing damping rides here as the one
        damping the coupled model adds to its modal damping."""
        c = self._flip(self.scene.bearing_damping())
        return c, jnp.zeros_like(c)

    def mount(self):
        """The :class:`~jaxgear.scenes.HousingMount` the scene's bearings sit in (its
        structure's, :attr:`~jaxgear.scenes.Structure.mount`: the housing's coordinates end the
        scene's), or None: a grounded scene or a scene kind that takes no housing
        (:attr:`~jaxgear.scenes.Scene.takes_housing`)."""
        return self.scene.structure.mount if self.scene.takes_housing else None

    # -- the torsional chain's view

    def dof_names(self):
        return ("theta_pinion", "theta_wheel")

    def ends(self):
        return self.input, 1 - self.input

    def matrices(self):
        """(M, K) on the two torque nodes' rotations (kg m^2, N m/rad), ``theta_pinion``,
        ``theta_wheel`` in the common sense: the scene with its mean cell stiffness (over
        :data:`CHAIN_POSITIONS` positions) condensed statically onto them (Guyan,
        T = [I; -K_ii^-1 K_ie]: M = T^T M T, K = T^T K T), so that K holds the mesh, shaft
        and bearing compliances in series."""
        m, k, k_mean, _ = self.dynamic_parts(CHAIN_POSITIONS)
        k = k + k_mean
        ends = np.asarray(self.scene.torque_dofs)
        inner = np.setdiff1d(np.arange(k.shape[0]), ends)
        if inner.size == 0:
            return m[np.ix_(ends, ends)], k[np.ix_(ends, ends)]
        T = jnp.zeros((k.shape[0], 2), k.dtype).at[ends].set(jnp.eye(2, dtype=k.dtype))
        T = T.at[inner].set(-jnp.linalg.solve(k[np.ix_(inner, inner)], k[np.ix_(inner, ends)]))
        return T.T @ m @ T, T.T @ k @ T


class LumpedRun(eqx.Module):
    """A lumped run prepared at one step count (:meth:`DynamicModel.prepare`): the mesh table
    and the static rows over the span, the contact law and the run's settings."""

    prep: _Prepared
    law: ContactLaw
    cfg: _Config  # static settings, and the divergence bound as data


# --------------------------------------------------------------------------------------------
# integrators


def _with_acceleration(model, table, X, Xd, law, row=0):
    scene = model.scene
    r = table.at(row)
    f = jnp.where(r.mask, r.k * r.length * _phi(r.V @ X - r.delta0, law)[0], 0.0)
    Xdd = jnp.linalg.solve(
        scene.mass(),
        scene.external_load(model.torque) - model.damping @ Xd - scene.stiffness() @ X - r.V.T @ f,
    )
    return (X, Xd, Xdd)


def _newmark(
    model: DynamicModel,
    run: LumpedRun,
    dt,
    state,
    steps: tuple[int, int],
    static_force,
    *,
    record: bool = False,
    factors=None,
    counted: bool = False,
    window: tuple[int, int] | None = None,
):
    """Newmark steps (:func:`~jaxgear.dynamics._newmark.newmark`, the contact in coordinates)
    of the prepared ``run`` (its table, the coordinates each step's contact is condensed onto,
    :attr:`_Prepared.dofs`, its law and settings): ``steps`` = (start, n), n steps from step
    start + 1 on: step k ends at step start + k + 1, whose cells each mesh takes from its own
    rows of the table (:meth:`MeshTable.at`).

    ``state``: (X, Ẋ, Ẍ, result code, most contact passes). ``static_force``: the static mesh
    forces (N), (m,), the scale of the divergence check. Records per step (``record``), a
    dict: each mesh's force Σ P (N, (m,)) ``fm`` and TE (m, (m,)) ``te``, the forces per
    contact line of each mesh (N, a tuple of (L_k,)) ``lines``, the bearing forces R X (N,
    (r,)) ``reac``; (X, Ẋ) ``states`` when the settings record them; the cell forces P (N,
    (c,)) ``cells`` when they record the cell loads; with ``factors`` (the table's E*/(π R)
    per row and cell, (R, c)), each mesh's largest p₀² = w E*/(π R) over its cells (Pa²,
    (m,)) ``p2``, reduced here in the loop. ``window`` (static, with ``record``): (S, k), the n
    steps in blocks of S (n a multiple of S), the last k blocks recorded in the same loop as
    the blocks before them (one compiled step); None: all recorded."""
    table, cfg = run.prep.table, run.cfg
    start, n_steps = steps
    record_states, record_cells = record and cfg.states, record and cfg.cell_loads
    scene = model.scene
    M, Ks, F = scene.mass(), scene.stiffness(), scene.external_load(model.torque)
    R = scene.reaction_matrix()
    fs = jnp.sum(static_force)
    e_ref = 0.5 * fs**2 / model.mesh_stiffness_mean
    te_of = mesh_te(scene, table.e_max[0])

    def check(X, Xd, forces):
        return _divergence_code(Xd, X, jnp.sum(forces), M, fs, e_ref, cfg.blowup)

    def kept_records(X, Xd, forces, j):
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

    system = LinearSystem(Ks, M, model.damping, F, dofs=run.prep.dofs)
    if table.steps is not None or counted:  # a traced step count, records in a buffer
        size = cfg.keep_periods * cfg.steps_per_period
        return newmark_counted(
            system,
            dt,
            state,
            start,
            n_steps,
            StepCells(table.at, run.law),
            kept_records if record else None,
            size,
            checks=(check, None),
        )
    rows = jnp.arange(n_steps) + 1 + start
    blocks, keep_blocks = (1, None) if window is None else (n_steps // window[0], window[1])
    return newmark(
        system,
        dt,
        state,
        rows.reshape(blocks, -1),
        StepCells(table.at, run.law),
        kept_records if record else None,
        checks=(check, None),
        keep_blocks=keep_blocks,
    )


def _static_forces(model: DynamicModel, table: MeshTable, static):
    """Each mesh's static force F_s (N), (m,) (:func:`static_mesh_forces`), and its largest
    quasi-static force on one contact line (N), (m,), over the span's steps (a table of a
    traced N_s: over the largest span, whose rows repeat the span of its N_s: the same means
    and maxima)."""
    length = table.take(table.length, jnp.arange(table.span))  # (S, c)
    fm, lines = table.mesh_forces(static.static_force_density * length)  # (S, m), (S, L_k)
    max_lines = jnp.stack([jnp.max(f) for f in lines])
    return static_mesh_forces(model.scene, model.torque, fm), max_lines


def _one_speed(
    model: DynamicModel,
    table: MeshTable,
    static,
    speed,
    state,
    cfg: _Config,
    law,
    row0=0,
    lead=None,
):
    # a table of a traced N_s (MeshTable.steps, Newmark only): the step counts are traced, the
    # K records of a buffer of the largest N_s's size hold the first n_keep, the statistics are
    # masked to them and the histories thinned to cfg.history_steps
    P = table.step_count
    period_angle = model.scene.base_planes[0].mesh_period_angle
    period = period_angle / speed
    dt = period / P
    n_keep = cfg.keep_periods * P
    n_trans = (cfg.periods - cfg.keep_periods) * P
    K = cfg.keep_periods * cfg.steps_per_period  # the records (static)
    fs, static_lines = _static_forces(model, table, static)
    # the cells' base-plane coordinates at the table's rows (the same cells as the table's)
    track = cfg.cell_loads or cfg.pressure is not None
    geometry = cell_geometry(model.scene, table.theta) if track else None
    factors = None
    if cfg.pressure is not None:  # E*/(π R) per row and cell
        factors = pressure_factors(cfg.pressure, table.sizes, geometry[0], table.mask)
    states = forces = p2 = None
    if cfg.newmark:
        # the transient and the kept periods, only the kept ones recorded (memory ∝
        # keep_periods only)
        carry0 = (*state, jnp.array(0), jnp.array(0))
        run = LumpedRun(static, law, cfg)
        if lead is not None:  # `lead` steps (traced) before the window, from step row0
            carry0, _ = _newmark(model, run, dt, carry0, (row0, lead), fs, counted=True)
            row0 = row0 + lead
            lead_end = carry0[:2]
        if table.steps is not None:  # traced step counts: two counted loops
            carry, _ = _newmark(model, run, dt, carry0, (row0, n_trans), fs)
            carry, rec = _newmark(
                model, run, dt, carry, (row0 + n_trans, n_keep), fs, record=True, factors=factors
            )
        else:  # one loop over the transient and the kept steps (one compiled Newmark step)
            carry, rec = _newmark(
                model,
                run,
                dt,
                carry0,
                (row0, n_trans + n_keep),
                fs,
                record=True,
                factors=factors,
                window=(P, cfg.keep_periods),
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
    j = jnp.arange(K) + 1 + n_trans + row0  # the kept steps
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
    none = jnp.zeros((K, 0), fm.dtype)
    traced = table.steps is not None
    response = steady_state(
        Records(
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
            static_te=static_te[j % table.span_steps],
            bearing_force=reac,
            bearing_force_static=static.static_x @ model.scene.reaction_matrix().T,
            omega_excited=excited_omega(model.modes),
            final_state=final,
            iterations=it,
            code=code,
            rim=(none, none),
            states=states,
            scene_steps=table.span_steps,
            pressure=pressure,
            cells=cells,
            coast_force=coast if cfg.newmark else None,
            kept=n_keep if traced else None,
        )
    )
    if not traced:
        return response if lead is None else (response, lead_end)
    # the histories at N_s = cfg.history_steps: every m-th record, ending on each period's last
    h = cfg.keep_periods * cfg.history_steps

    def take(a, m):
        return a[(jnp.arange(h) + 1) * m - 1]

    response = thinned(response, P // cfg.history_steps, take)
    return response if lead is None else (response, lead_end)


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
    model._check_runs()
    law = contact_law(contact, model.scene.base_planes[0].base_pitch.dtype)
    return _static_start(_prep(model, law, int(steps_per_period)))


def _starts(model: DynamicModel, prep: _Prepared, state0, law: ContactLaw):
    """(X, Ẋ, Ẍ) of ``state0`` = (X, Ẋ), and of the static equilibrium (the restart of a
    continuation after a failed speed)."""
    table = prep.table
    start = _with_acceleration(model, table, state0[0], state0[1], law)
    zero = jnp.zeros_like(prep.static_x[0])
    return start, _with_acceleration(model, table, prep.static_x[0], zero, law)


@eqx.filter_jit
def _single(model: DynamicModel, prep: _Prepared, speed, state0, law: ContactLaw, cfg: _Config):
    """One speed from ``state0`` = (X, Ẋ)."""
    start, _ = _starts(model, prep, state0, law)
    return _one_speed(model, prep.table, prep, speed, start, cfg, law)


@eqx.filter_jit
def _single_at(
    model: DynamicModel, prep: _Prepared, speed, state0, row, lead, law: ContactLaw, cfg: _Config
):
    """One speed from ``state0`` = (X, Ẋ) at the table's step ``row``, ``lead`` steps before
    its window (traced ints): (the response, the state where its window starts)."""
    start = _with_acceleration(model, prep.table, state0[0], state0[1], law, row)
    return _one_speed(model, prep.table, prep, speed, start, cfg, law, row, lead)


@eqx.filter_jit
def _vmapped(model: DynamicModel, prep: _Prepared, speeds, state0, law: ContactLaw, cfg: _Config):
    """Every speed of ``speeds`` (S,) from ``state0``, side by side (``jax.vmap``)."""
    start, _ = _starts(model, prep, state0, law)
    return jax.vmap(lambda s: _one_speed(model, prep.table, prep, s, start, cfg, law))(speeds)


@eqx.filter_jit
def _scans(model: DynamicModel, prep: _Prepared, speeds, state0, law: ContactLaw, cfg: _Config):
    """The speeds (S,) one after the other from ``state0``, each from the previous steady
    state (``lax.scan``; a diverged point restarts the next one from the static equilibrium);
    (k, S): k such scans side by side (``jax.vmap``)."""
    start, restart = _starts(model, prep, state0, law)

    def scan_dir(sp):
        def body(state, s):
            r = _one_speed(model, prep.table, prep, s, state, cfg, law)
            ok = r.result == 0
            nxt = jax.tree_util.tree_map(lambda a, b: jnp.where(ok, a, b), r.final_state, restart)
            return nxt, r

        return jax.lax.scan(body, start, sp)[1]

    if speeds.ndim == 2:
        return jax.vmap(scan_dir)(speeds)
    return scan_dir(speeds)
