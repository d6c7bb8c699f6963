"""The coupled gearbox as a dynamics engine (docs/gearbox.md, "The coupled model"):
:class:`GearboxModel`, the :class:`~jaxgear.dynamics.AbstractDynamicModel` of the coupled
Newmark run of :func:`~jaxgear.gearbox.gearbox_dynamics`, so that
:func:`jaxgear.dynamics.simulate` and :func:`jaxgear.dynamics.speed_sweep`, the automatic step
(:func:`jaxgear.dynamics.auto_steps_per_period`), the automatic span
(:func:`jaxgear.dynamics.settling_time`), the mesh-averaged modes
(:func:`jaxgear.dynamics.mesh_averaged_modes`: :func:`~jaxgear.gearbox.gearbox_coupled_modes`)
and :func:`jaxgear.dynamics.whine_response` serve a gearbox as they serve pairs, trains and
planetary stages; ``jaxgear modes`` lists its :meth:`GearboxModel.natural_modes` (each mode's
kinetic energy per stage in the common :class:`~jaxgear.dynamics.ModalAnalysis`).

The speed of the entries is the **first stage's input member's** speed ω_in (rad/s); every
other member's speed and every stage's mesh travel follow from the stages' kinematics.

The clock of a gearbox run (the kind's own reading of the settings, :meth:`GearboxModel.prepare`):

* ``Newmark(steps_per_period=S)``: S steps per period of the **fastest excited mesh** (the
  fastest mesh of a stage with contact cells, :meth:`~jaxgear.dynamics.AbstractStage.excited`):
  the model's "first mesh" of the contract (:meth:`GearboxModel.mesh_period_angle`);
* ``SteadyState(periods=B, keep_periods=K)``: B **blocks** integrated, the last K recorded, a
  block the **slowest excited mesh's** period rounded to whole steps (every stage's meshes pass
  at least one period in a block).

The response of a run is :class:`~jaxgear.gearbox.GearboxDynamics` (each mesh's force over the
recorded blocks, the dynamic factors per mesh in :func:`~jaxgear.gearbox.mesh_names`' order, the
result code), not a pair's :class:`~jaxgear.dynamics.DynamicResponse`.
"""

from __future__ import annotations

import dataclasses
import math
from typing import ClassVar

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import AbstractContactLaw, ContactLaw, ExactContact
from .._util import as_float, check_instance, check_real
from ..dynamics import (
    SETTLE_TOL,
    AbstractDynamicModel,
    ModalAnalysis,
    Newmark,
    Outputs,
    QuasiPeriodicBalance,
    SteadyState,
    auto_steps_per_period,
    matrix_modal_analysis,
    resolve_settings,
    settling_time,
    simulate,
    speed_sweep,
)
from ._chain import GearboxTorsional
from ._coupled import (
    GearboxDynamics,
    GearboxRun,
    _assemble,
    _check,
    _coupled_modes,
    _excited_periods,
    _kinematics,
    _run,
    _sweep,
    mesh_names,
)

__all__ = [
    "OPERATING_RUN",
    "GearboxModel",
    "GearboxPrepared",
    "gearbox_dynamics",
    "gearbox_speed_sweep",
]

#: the plan constants of a gearbox case's coupled model at its operating point
#: (:meth:`jaxgear.io.GearboxForm.dynamic_model`; measured on nrel-5mw-gearbox, docs/gearbox.md
#: "Resolution and cost"): 24 steps per period of the highest mode the meshes excite, 3 time
#: constants of the slowest decaying excited mode to settle from the quasi-static start, 4
#: blocks (the slowest mesh's periods) recorded, K̄_m over 32 positions a mesh period
OPERATING_RUN = {"steps_per_mode": 24, "settle": 3.0, "keep_periods": 4, "mean_positions": 32}


class GearboxPrepared(eqx.Module):
    """A gearbox run's speed-independent part (:meth:`GearboxModel.prepare`): the
    :class:`~jaxgear.gearbox.GearboxRun` of its plan (``steps_per_period`` S, ``periods`` B
    blocks, ``keep_periods``), the contact law, and the plan in the form the Newmark run takes
    (static): ``block`` steps per block, ``fast`` the fastest excited mesh's period times the
    input speed (rad of the input member)."""

    run: GearboxRun
    law: ContactLaw
    block: int = eqx.field(static=True)
    fast: float = eqx.field(static=True)


class GearboxModel(AbstractDynamicModel):
    """A gearbox's coupled dynamics (:func:`~jaxgear.gearbox.gearbox_dynamics`: every stage's
    contact cells in one Newmark run, the shafts, the output hold, modal damping on the modes of
    (M, K + K̄_m)) as an :class:`~jaxgear.dynamics.AbstractDynamicModel` (module docstring: its
    speed, its clock, its response).

    Attributes:
        chain: the stages and shafts (:class:`~jaxgear.gearbox.GearboxTorsional`), the model's
            ``scene``.
        run: :class:`~jaxgear.gearbox.GearboxRun`: the input torque T (N m), the output hold
            (N m/rad), the damping ratio, the mean positions of K̄_m, and the automatic plan's
            ``steps_per_mode`` and ``settle``; its explicit ``steps_per_period``, ``periods``
            and ``keep_periods`` are not read by the engine entries (their integrator and
            window are; :func:`~jaxgear.gearbox.gearbox_dynamics` passes the run's).

    ``torque`` is the input torque T (N m); ``mods`` is None (a stage's deviations live in its
    meshes).

    Raises:
        ValueError: a chain or run of another type (one line).
    """

    scene: GearboxTorsional
    mods: None
    torque: Float[Array, ""]
    run: GearboxRun

    def __init__(self, chain: GearboxTorsional, run: GearboxRun):
        check_instance("chain", chain, GearboxTorsional, "a jaxgear.gearbox.GearboxTorsional",
                       "GearboxModel")
        check_instance("run", run, GearboxRun, "a jaxgear.gearbox.GearboxRun", "GearboxModel")
        self.scene, self.run, self.mods = chain, run, None
        self.torque = run.input_torque

    #: a coupled run starts from the quasi-static state at rest: no continuation
    continues: ClassVar[bool] = False
    #: the quasi-periodic balance on the torus of the stages' mesh phases
    #: (:func:`~jaxgear.gearbox.gearbox_whine`)
    whine_methods: ClassVar[tuple[type, ...]] = (QuasiPeriodicBalance,)
    #: ``SteadyState(periods=None)``: the blocks from the settling time (:meth:`resolve_window`)
    automatic_span: ClassVar[bool] = True
    #: the housing its stages share (:attr:`~jaxgear.gearbox.GearboxTorsional.housing`)
    takes_housing: ClassVar[bool] = True

    # --- what the engine entries read ------------------------------------------------------

    @property
    def chain(self) -> GearboxTorsional:
        """The stages and shafts (the model's ``scene``)."""
        return self.scene

    @property
    def mesh(self):
        raise AttributeError("GearboxModel: a gearbox has no pair mesh model (mesh)")

    @property
    def static_force(self) -> Float[Array, " m"]:
        """Each mesh's static force from the torque ratios (N), (m,), in
        :func:`~jaxgear.gearbox.mesh_names`' order."""
        kin = _kinematics(self.chain, 1.0, self.run.input_torque)
        return jnp.concatenate([f for _, _, f in kin])

    @property
    def dtype(self):
        return self.run.input_torque.dtype

    def mesh_count(self) -> int:
        """Every stage's meshes (:func:`~jaxgear.gearbox.mesh_names`)."""
        return len(mesh_names(self.chain))

    def scene_periods(self) -> int:
        return 1  # a block holds at least one period of every excited mesh

    def coast_flanks(self) -> bool:
        return False  # each stage on the flanks its torque loads

    def mesh_period_angle(self):
        """The input member's rotation (rad) over one period of the fastest excited mesh (the
        reference of ``steps_per_period``): f_ref = ω_in / θ_ref."""
        return _excited_periods(self.chain)[0]

    def mesh_rates(self) -> list[float]:
        """Each mesh's periods per period of the fastest excited mesh (a stage's meshes alike;
        below 1 for an excited stage, a stage of constant springs as its kinematics give)."""
        fast = _excited_periods(self.chain)[0]
        kin = _kinematics(self.chain, 1.0, 1.0)
        return [fast * float(abs(v)) / float(s.mesh_period())
                for s, (_, v, _) in zip(self.chain.stages, kin, strict=True)
                for _ in s.mesh_names()]

    def structure_matrices(self) -> tuple:
        """(M, K_s): the coupled mass and the structure's stiffness with the shafts and the
        output hold (no mesh, no rotating-frame terms), each (n, n)."""
        return _structure_matrices(self.chain, self.run, jnp.ones((), self.dtype))

    def steps_per_mode(self) -> int:
        """The automatic step's steps per period of the highest excited mode (the run's
        ``steps_per_mode``)."""
        return int(self.run.steps_per_mode)

    def whine(self, speeds, method, *, positions=64, contact=ExactContact()):
        """The gearbox's gear whine in the frequency domain at the input ``speeds`` (rad/s,
        scalar or (S,)): :func:`~jaxgear.gearbox.gearbox_whine` of the chain and run
        (:func:`jaxgear.dynamics.whine_response` delegates here)."""
        from ._whine import gearbox_whine

        return gearbox_whine(self.chain, self.run, speeds, method, positions=positions,
                             law=contact)

    # --- the engine ------------------------------------------------------------------------

    def default_settings(self):
        """Newmark with automatic steps (:func:`~jaxgear.dynamics.auto_steps_per_period`, the
        run's ``steps_per_mode`` per period of the highest excited mode at the lowest speed),
        the exact contact law, and the automatic span (:meth:`resolve_window`) keeping the
        run's ``keep_periods`` blocks."""
        return Newmark(), ExactContact(), SteadyState(None, int(self.run.keep_periods))

    def check_integrator(self, integrator) -> None:
        if not isinstance(integrator, Newmark) or integrator.basis is not None:
            raise ValueError(
                f"integrator = {type(integrator).__name__}: a gearbox runs Newmark in its coupled "
                "coordinates "
                "(allowed jaxgear.dynamics.Newmark(steps_per_period), no basis)"
            )

    def span_periods(self) -> int:
        return 1

    def steps_multiple(self) -> int:
        return 1

    def averaged_modes(
        self, *, speed=0.0, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
    ) -> ModalAnalysis:
        """The coupled modes of (M, K + K̄_m) (:func:`~jaxgear.gearbox.gearbox_coupled_modes`'
        ``analysis``: the system the run's modal damping takes, K̄_m over the run's
        ``mean_positions``; ``speed``, ``positions_per_pitch`` and ``contact`` not used)."""
        return _coupled_modes(self.chain, self.run).analysis

    def natural_modes(
        self, *, speed=0.0, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
    ) -> ModalAnalysis:
        """The gearbox's natural modes as a user reads them (``jaxgear modes``, the chain's
        ``modes.json`` of ``jaxgear run``), each with every stage's share of its kinetic energy
        (:attr:`~jaxgear.dynamics.ModalAnalysis.kinetic`, groups ``stage1``, ``stage2``, ...
        from the first stage):

        * without a shared housing, the torsional chain's modes
          (:meth:`GearboxTorsional.matrices`, as :func:`~jaxgear.gearbox.gearbox_modes`: one
          rotation per member, each stage's mean mesh stiffness, the shafts; both ends free,
          so one rigid-body mode at 0 Hz), not the coupled system of the runs
          (:meth:`averaged_modes`: the output held, the cells' mean stiffness);
        * with one (the chain's view cannot take it), the coupled modes
          (:meth:`averaged_modes`), the housing's coordinates the last group, ``housing``.

        ``speed``, ``positions_per_pitch`` and ``contact`` are not used."""
        if self.chain.housing is None:
            return _chain_modes(self.chain)
        coupled = _coupled_modes(self.chain, self.run)
        kinetic = jnp.concatenate([coupled.stage_energy, coupled.housing_energy[None]])
        groups = _stage_groups(self.chain) + ("housing",)
        return dataclasses.replace(coupled.analysis, kinetic=kinetic, groups=groups)

    def settle_time(self, modes: ModalAnalysis | None = None) -> float:
        """t_s (s): :func:`~jaxgear.dynamics.settling_time` of the coupled modes at the run's
        damping ratio (the slowest decaying mode the meshes excite), scaled to the run's
        ``settle`` time constants where it gives them (None: the engine's ln(1 / SETTLE_TOL))."""
        modes = self.averaged_modes() if modes is None else modes
        t_s, _ = settling_time(modes, float(self.run.damping_ratio))
        if self.run.settle is not None:
            t_s *= float(self.run.settle) / math.log(1.0 / SETTLE_TOL)
        return t_s

    def resolve_window(self, window, speeds, steps, modes=None) -> SteadyState:
        """The automatic span over the concrete input ``speeds`` (S,): the settling time t_s
        (:meth:`settle_time`) in whole blocks at the highest speed (a block: the slowest excited
        mesh's period), then ``window.keep_periods`` blocks; one window for every speed (the
        same steps: a slower speed settles in fewer blocks)."""
        _, slow = _excited_periods(self.chain)
        w = float(np.max(np.abs(np.asarray(speeds, dtype=float))))
        blocks = math.ceil(self.settle_time(modes) / (slow / w)) + int(window.keep_periods)
        return SteadyState(max(2, blocks), int(window.keep_periods))

    @staticmethod
    def _check_outputs(outputs: Outputs) -> None:
        if outputs.states or outputs.cell_loads or outputs.pressure is not None:
            raise ValueError(
                "outputs: a gearbox run records its coordinates and mesh forces always and no "
                "cell loads or pressure (allowed Outputs())"
            )

    def prepare(self, integrator, law, window, steps_per_period, outputs, modes=None):
        """The :class:`GearboxPrepared` of ``steps_per_period`` steps per period of the fastest
        excited mesh and ``window`` (its blocks and kept blocks, module docstring).

        Raises:
            ValueError: ``outputs`` asking for states, cell loads or a pressure; N_s < 8."""
        self._check_outputs(outputs)
        base = self.run
        run = GearboxRun(
            base.input_torque, base.output_stiffness, steps_per_period=int(steps_per_period),
            periods=int(window.periods), keep_periods=int(window.keep_periods),
            damping_ratio=base.damping_ratio, mean_positions=base.mean_positions,
            steps_per_mode=base.steps_per_mode, settle=base.settle,
        )
        fast, slow = _excited_periods(self.chain)
        block = max(1, round(int(steps_per_period) * slow / fast))
        return GearboxPrepared(run, law, block, fast)

    def prepare_steps(self, integrator, law, window, steps, outputs, modes=None):
        """One compiled program for the step counts ``steps`` of a sweep: every speed at the
        largest N_s (the lowest speed's: the highest excited mode resolved at every speed), the
        same blocks (:meth:`resolve_window`)."""
        prepared = self.prepare(integrator, law, window, int(max(steps)), outputs, modes)
        return lambda n: prepared

    def independent(self, prepared, speeds, *, start=None, shard: bool = False):
        """The :class:`~jaxgear.gearbox.GearboxDynamics` (this kind's response) at each input
        speed of ``speeds`` (rad/s, (S,): every field with a leading axis S, ``jax.vmap``) or
        at one scalar speed, each from the quasi-static state at rest. ``shard`` is not used.

        Raises:
            ValueError: a ``start`` state."""
        if start is not None:
            raise ValueError("start: a gearbox run starts from its quasi-static state "
                             "(allowed None)")
        run = prepared.run
        plan = (int(run.steps_per_period), prepared.block, prepared.fast, int(run.periods))
        speeds = as_float(speeds)
        if speeds.ndim == 0:
            return _run(self.chain, run, speeds, prepared.law, *plan)
        return _sweep(self.chain, run, speeds, prepared.law, *plan)


def _stage_groups(chain: GearboxTorsional) -> tuple[str, ...]:
    """The kinetic-energy groups of a chain's stages, ``stage1``, ``stage2``, ..."""
    return tuple(f"stage{k + 1}" for k in range(len(chain.stages)))


@eqx.filter_jit
def _chain_modes(chain: GearboxTorsional) -> ModalAnalysis:
    """The torsional chain's modes, K φ = ω² M φ on (M, K) of :meth:`GearboxTorsional.matrices`
    (one modal solve, :func:`~jaxgear.dynamics.matrix_modal_analysis`, no mesh-averaged part),
    with each stage's share of each mode's kinetic energy, e_s = Σ_{j∈s} φ_j (M φ)_j over the
    stage's rotations (M block-diagonal per stage: the shares sum to 1)."""
    m, k = chain.matrices()
    modes = matrix_modal_analysis(m, k, jnp.zeros_like(k))
    energy = modes.shapes * (m @ modes.shapes)
    owner = np.asarray(chain.stage_of_dof())  # static: each rotation's stage
    belongs = jnp.asarray(owner[None, :] == np.arange(len(chain.stages))[:, None], energy.dtype)
    per_stage = belongs @ energy
    per_stage = per_stage / per_stage.sum(axis=0, keepdims=True)
    return dataclasses.replace(modes, kinetic=per_stage, groups=_stage_groups(chain))


@eqx.filter_jit
def _structure_matrices(chain, run, speed):
    """(M, K_s) of :meth:`GearboxModel.structure_matrices`: one compiled program (the stages'
    parts evaluated op by op took seconds of small compilations)."""
    m, _, k, *_ = _assemble(chain, run, speed)
    return m, k


def gearbox_dynamics(
    chain: GearboxTorsional,
    run: GearboxRun,
    input_speed: float,
    law: AbstractContactLaw = ExactContact(),
) -> GearboxDynamics:
    """The steady response of the whole gearbox at one input speed: one Newmark run (average
    acceleration, :func:`jaxgear.dynamics.newmark`) of the coupled system (module docstring)
    with every mesh's contact cells at once, each stage's at its own mesh travel x_k = v_k t,
    from the quasi-static state at t = dt / 2 at rest; the last ``run.keep_periods`` blocks
    recorded. :func:`jaxgear.dynamics.simulate` of the
    :class:`~jaxgear.gearbox.GearboxModel` of ``chain`` and ``run`` on the run's plan
    (``Newmark(run.steps_per_period)``, ``SteadyState(run.periods, run.keep_periods)``).

    Args:
        chain: the stages and shafts (:class:`~jaxgear.gearbox.GearboxTorsional`); a stage's
            meshes are its contact cells (a planetary stage's ``meshes``, a pair's ``mesh``) or,
            without them, its constant mesh springs.
        run: :class:`GearboxRun` (torque, output hold, steps, damping).
        input_speed: the first stage's input member's speed (rad/s, != 0; a negative speed
            turns the input the other way, the plan from its magnitude); the other members'
            speeds follow from the stages' kinematics (Willis for a planetary stage).
        law: the contact law.

    Returns:
        :class:`GearboxDynamics`; ``dynamic_factors`` per mesh in :func:`mesh_names`' order.

    Raises:
        ValueError: an argument of another kind (one line).
        ValueError: ``input_speed`` zero or not finite (one line).
    """
    _check(chain, run, law, "gearbox_dynamics")
    check_real("input_speed", input_speed, "rad/s", shape=(), where="gearbox_dynamics")
    if float(input_speed) == 0.0:
        raise ValueError("gearbox_dynamics: input_speed = 0 rad/s: allowed a nonzero speed")
    model, integrator, window = GearboxModel(chain, run), *_plan_of(run)
    if float(input_speed) > 0.0:
        return simulate(model, input_speed, integrator=integrator, contact=law, window=window,
                        throw=False)
    return _reversed(model, jnp.asarray(input_speed, model.dtype), integrator, law, window)


def gearbox_speed_sweep(
    chain: GearboxTorsional,
    run: GearboxRun,
    input_speeds: Float[Array, " s"],
    law: AbstractContactLaw = ExactContact(),
) -> GearboxDynamics:
    """:func:`gearbox_dynamics` at each input speed (rad/s, (s,), nonzero), vectorised with
    ``jax.vmap``: every field gains a leading axis (s,). :func:`jaxgear.dynamics.speed_sweep`
    of the :class:`~jaxgear.gearbox.GearboxModel` on the run's plan (automatic: one plan for
    every speed, the step of the lowest, the span of the highest)."""
    _check(chain, run, law, "gearbox_speed_sweep")
    speeds = jnp.reshape(as_float(input_speeds), (-1,))
    check_real("input_speeds", speeds, "rad/s", shape=(None,), where="gearbox_speed_sweep")
    if not bool(jnp.all(speeds != 0.0)):
        raise ValueError("gearbox_speed_sweep: an input speed of 0 rad/s: allowed nonzero speeds")
    model, integrator, window = GearboxModel(chain, run), *_plan_of(run)
    if bool(jnp.all(speeds > 0.0)):
        return speed_sweep(model, speeds, integrator=integrator, contact=law,
                           window=window).results
    return _reversed(model, speeds, integrator, law, window)


def _plan_of(run: GearboxRun) -> tuple:
    """The engine's integrator and window of ``run``'s plan (None: automatic)."""
    return Newmark(run.steps_per_period), SteadyState(run.periods, run.keep_periods)


def _reversed(model, speeds, integrator, law, window):
    """A run or sweep with an input turning backwards (a speed < 0; the engine entries take
    speeds > 0): planned by the engine on the speeds' magnitudes (the plan depends on them
    alone), then run at the signed speeds by the model."""
    integrator, law, window, outputs = resolve_settings(model, integrator, law, window)
    mag = np.abs(np.atleast_1d(np.asarray(speeds, dtype=float)))
    n, modes = integrator.steps_per_period, None
    if n is None:
        modes = model.averaged_modes()
        n = int(np.max(auto_steps_per_period(model, mag, modes)))
    if window.periods is None:
        window = model.resolve_window(window, mag, np.full(mag.shape, n), modes)
    prepared = model.prepare(integrator, law, window, int(n), outputs, modes)
    return model.independent(prepared, speeds)
