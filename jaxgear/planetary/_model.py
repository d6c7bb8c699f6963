"""A planetary stage's dynamics as a dynamics engine (docs/planetary.md, "Dynamics in the
carrier frame"): :class:`PlanetaryModel`, the :class:`~jaxgear.dynamics.AbstractDynamicModel`
of :func:`~jaxgear.planetary.planetary_dynamics`, so that :func:`jaxgear.dynamics.simulate`
and :func:`jaxgear.dynamics.speed_sweep`, the automatic step
(:func:`jaxgear.dynamics.auto_steps_per_period`: the rule of
:func:`~jaxgear.planetary.time_plan`) and the mesh-averaged modes
(:func:`jaxgear.dynamics.mesh_averaged_modes`: :func:`~jaxgear.planetary.planetary_mesh_modes`)
serve a stage as they serve pairs and trains.

The speed of the entries is the **input member's** speed ω_in (rad/s, fixed frame): the carrier
turns at Ω = ``carrier_per_input`` ω_in and the meshes travel at v = ``mesh_speed_per_input``
ω_in (Willis, the case's roles); by default the carrier is the input and the ring is held
(Ω = ω_in, v = r_br |Ω|, :func:`~jaxgear.planetary.planetary_dynamics`' own default).

The response of a run is the stage's :class:`~jaxgear.planetary.PlanetaryDynamics` (each
mesh's force over the kept periods, the dynamic factors per mesh, K_γ), not a pair's
:class:`~jaxgear.dynamics.DynamicResponse`: :meth:`PlanetaryModel.independent` documents it."""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact
from .._util import as_float, check_instance
import numpy as np

from ..dynamics import (
    AbstractDynamicModel,
    HarmonicBalance,
    ModalAnalysis,
    Newmark,
    Outputs,
    SteadyState,
    TransmissionErrorSource,
    auto_steps_per_period,
    check_whine_speeds,
    settling_time,
    speed_sweep,
)
from ._dynamics import (
    PlanetaryDynamics,
    PlanetaryRun,
    planetary_dynamics,
    planetary_mesh_modes,
    planetary_stage_system,
)
from ._housed import check_carrier_speed
from ._meshes import AbstractPlanetaryMeshes
from ._plan import (
    KEEP_OTHER,
    KEEP_PERIODIC,
    SweepRecords,
    TimePlan,
    carrier_periodic,
    grouped_records,
    program_span,
    settled_periods,
    speed_groups,
    time_plan,
)
from ._ring import AbstractRingModel, RigidRing
from ._stage import AbstractPlanetaryModel, PlanetaryStage
from ._whine import planetary_whine

__all__ = ["PlanetaryModel", "PlanetaryPrepared", "PlanetarySpan", "sweep_records"]


class PlanetaryPrepared(eqx.Module):
    """A planetary run's speed-independent part (:meth:`PlanetaryModel.prepare`): the
    :class:`~jaxgear.planetary.PlanetaryRun` of its step count and window, the contact law,
    and ``steps``: None, or the N_s of a run that shares one compiled program with other step
    counts (:meth:`PlanetaryModel.prepare_steps`: ``run`` counts blocks of the smallest N_s,
    :attr:`~jaxgear.planetary.PlanetaryRun.mesh_steps`)."""

    run: PlanetaryRun
    law: ContactLaw
    steps: int | None = eqx.field(static=True, default=None)


class PlanetarySpan(eqx.Module):
    """The automatic span of a planetary run (``SteadyState(periods=None)``) resolved over its
    speeds (:meth:`PlanetaryModel.resolve_window`): each speed's step count N_s and mesh
    periods (its settling time's whole mesh periods, then ``keep_periods``:
    :func:`~jaxgear.planetary.settled_periods`), static tuples (s,)."""

    steps: tuple = eqx.field(static=True)
    periods: tuple = eqx.field(static=True)
    keep_periods: int = eqx.field(static=True)


class PlanetaryModel(AbstractDynamicModel):
    """A planetary stage's carrier-frame dynamics (:func:`~jaxgear.planetary.planetary_dynamics`:
    Newmark on the 2N meshes' contact cells, the Coriolis and centripetal terms at the carrier
    speed) as an :class:`~jaxgear.dynamics.AbstractDynamicModel`.

    Attributes:
        kind: the lumped model kind (:class:`~jaxgear.planetary.TorsionalPlanetary`,
            :class:`~jaxgear.planetary.PlanarPlanetary`,
            :class:`~jaxgear.planetary.SpatialPlanetary`; a case's:
            :func:`~jaxgear.planetary.planetary_model_for`).
        stage: the stage (ring or carrier held in rotation).
        meshes: :class:`~jaxgear.planetary.ContactMeshes` or
            :class:`~jaxgear.planetary.ConstantMeshes` (meshes that repeat every mesh period).
        run: the sun torque (N m), damping ratio and pin errors (m) of the runs
            (:class:`~jaxgear.planetary.PlanetaryRun`; its step counts are replaced by the
            run's integrator and window).
        carrier_per_input: Ω / ω_in (-), the carrier's speed per input speed (fixed frame).
        mesh_speed_per_input: v / ω_in (m/s per rad/s), the mesh travel speed per input speed;
            None: the ring held, v = r_br |Ω|.
        ring: :class:`~jaxgear.planetary.RigidRing` (default) or a flexible ring model.

    ``scene`` (and :attr:`stage`) is the stage and ``torque`` the sun torque T_s (N m): the
    engine entries read neither (they ask the model's methods); ``mods`` is None (a stage's
    deviations live in its meshes).

    Raises:
        ValueError: a kind, stage, meshes, run or ring of another type, ``carrier_per_input``
            zero without a ``mesh_speed_per_input``, ``mesh_speed_per_input`` not > 0 (one
            line).
    """

    scene: PlanetaryStage
    mods: None
    torque: Float[Array, ""]
    kind: AbstractPlanetaryModel
    meshes: AbstractPlanetaryMeshes
    run: PlanetaryRun
    carrier_per_input: Float[Array, ""]
    mesh_speed_per_input: Float[Array, ""] | None
    ring: AbstractRingModel

    def __init__(
        self,
        kind: AbstractPlanetaryModel,
        stage: PlanetaryStage,
        meshes: AbstractPlanetaryMeshes,
        run: PlanetaryRun,
        carrier_per_input=1.0,
        mesh_speed_per_input=None,
        ring: AbstractRingModel = RigidRing(),
    ):
        self.kind, self.scene, self.meshes, self.run, self.ring = kind, stage, meshes, run, ring
        self.mods = None
        # another run type is refused in one line by __check_init__
        self.torque = run.sun_torque if isinstance(run, PlanetaryRun) else None
        self.carrier_per_input = as_float(carrier_per_input)
        self.mesh_speed_per_input = (
            None if mesh_speed_per_input is None else as_float(mesh_speed_per_input)
        )

    #: a planetary run starts from the quasi-static state at its first travel: no
    #: continuation from one speed to the next
    continues: ClassVar[bool] = False
    #: the harmonic balance over one mesh period (no torus of several mesh frequencies)
    whine_methods: ClassVar[tuple[type, ...]] = (HarmonicBalance, TransmissionErrorSource)
    #: ``SteadyState(periods=None)``: the span from the stage's settling time
    #: (:meth:`resolve_window`, :func:`~jaxgear.planetary.time_plan`'s rule)
    automatic_span: ClassVar[bool] = True

    def __check_init__(self):
        where = "PlanetaryModel"
        check_instance("kind", self.kind, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary, "
                       "SpatialPlanetary)", where)
        check_instance("stage", self.stage, PlanetaryStage, "a jaxgear.planetary.PlanetaryStage", where)
        check_instance("meshes", self.meshes, AbstractPlanetaryMeshes,
                       "a planetary meshes kind", where)
        check_instance("run", self.run, PlanetaryRun, "a jaxgear.planetary.PlanetaryRun", where)
        check_instance("ring", self.ring, AbstractRingModel,
                       "a jaxgear ring model (RigidRing, CondensedRing, CraigBamptonRing)", where)
        check_carrier_speed(self.kind, self.carrier_per_input,
                            "PlanetaryModel (carrier_per_input times the input speed)")
        v = self.mesh_speed_per_input
        if v is None and not float(self.carrier_per_input) != 0.0:
            raise ValueError(
                f"carrier_per_input = {float(self.carrier_per_input)!r}: out of range, allowed "
                "!= 0 where mesh_speed_per_input is None (the ring held: v = r_br |Ω|)"
            )
        if v is not None and not float(v) > 0.0:
            raise ValueError(
                f"mesh_speed_per_input = {float(v)!r} m/s per rad/s: out of range, allowed > 0"
            )

    # --- what the engine entries read ------------------------------------------------------

    @property
    def stage(self) -> PlanetaryStage:
        """The stage (the model's ``scene``)."""
        return self.scene

    @property
    def mesh(self):
        raise AttributeError("PlanetaryModel: a planetary stage has no pair mesh model (mesh)")

    @property
    def static_force(self) -> Float[Array, ""]:
        """The nominal transverse mesh force T_s / (N r_bs) (N)."""
        return self.run.sun_torque / (self.stage.n_planets * self.stage.sun.base_radius)

    @property
    def dtype(self):
        return self.run.sun_torque.dtype

    def mesh_count(self) -> int:
        """2N: the sun meshes, then the ring meshes."""
        return 2 * self.stage.n_planets

    def scene_periods(self) -> int:
        return 1  # every mesh passes teeth at the same rate

    def coast_flanks(self) -> bool:
        return False

    def _mesh_speed(self, speed):
        """v (m/s) at input speed ``speed`` (rad/s)."""
        if self.mesh_speed_per_input is None:
            return self.stage.ring.base_radius * jnp.abs(self.carrier_per_input * speed)
        return self.mesh_speed_per_input * speed

    def mesh_period_angle(self):
        """The input's rotation over one mesh period (rad): p_b / (v / ω_in) (p_b the base
        pitch; f_mesh = v / p_b)."""
        return self.meshes.mesh_period() / self._mesh_speed(1.0)

    def mesh_rates(self) -> list[float]:
        return [1.0] * self.mesh_count()

    def structure_matrices(self) -> tuple:
        """(M, K_b): the stage's mass and its structure without the meshes (the run's pin
        errors' offsets in the holds), each (n_dof, n_dof)."""
        s = planetary_stage_system(self.kind, self.stage, self.meshes, self.run, 1)
        return s.m, s.k_b

    def whine(self, speeds, method, *, positions: int = 256, contact=ExactContact()):
        """The stage's gear whine in the frequency domain at the input ``speeds`` (rad/s):
        :func:`~jaxgear.planetary.planetary_whine` at the carrier and mesh speeds they give
        (:func:`jaxgear.dynamics.whine_response` delegates here)."""
        check_whine_speeds(speeds, "input")
        s = jnp.atleast_1d(jnp.asarray(speeds, self.dtype))
        w = planetary_whine(self.kind, self.stage, self.meshes, self.run,
                            self.carrier_per_input * s, method, mesh_speeds=self._mesh_speed(s),
                            ring=self.ring, positions=positions, contact=contact)
        return eqx.tree_at(lambda r: r.speed, w, s)

    # --- the engine ------------------------------------------------------------------------

    def default_settings(self):
        """Newmark with automatic steps (the pairs' rule with N_s a multiple of the planet
        count, :func:`~jaxgear.planetary.time_plan`'s), the exact contact law, and the
        automatic span (:meth:`sweep_window`: each speed's settling time in whole mesh periods,
        :meth:`resolve_window`) with :data:`~jaxgear.planetary.KEEP_PERIODIC` (2) kept where
        the stage repeats every mesh period in the carrier frame
        (:func:`~jaxgear.planetary.carrier_periodic`), else
        :data:`~jaxgear.planetary.KEEP_OTHER` (4): a run with every setting left out is
        ``jaxgear sweep``'s at that speed."""
        return Newmark(), ExactContact(), self.sweep_window()

    def flexible_ring(self) -> bool:
        """Whether the ring is a condensed (flexible) one."""
        return not isinstance(self.ring, RigidRing)

    def sweep_window(self, periods: int | None = None, keep: int | None = None) -> SteadyState:
        """The window of a sweep (:func:`~jaxgear.planetary.time_plan`'s rule): ``periods``
        None the automatic span, ``keep`` None :data:`~jaxgear.planetary.KEEP_PERIODIC` (2)
        where the stage is :func:`~jaxgear.planetary.carrier_periodic`, else
        :data:`~jaxgear.planetary.KEEP_OTHER` (4), at most ``periods``."""
        periodic = carrier_periodic(self.stage, self.flexible_ring())
        keep = keep or (KEEP_PERIODIC if periodic else KEEP_OTHER)
        if periods is not None:
            keep = min(keep, int(periods))
        return SteadyState(periods, keep)

    def time_plan(self, speeds, steps: int | None = None,
                  window: SteadyState | None = None) -> tuple[TimePlan, ModalAnalysis]:
        """The :class:`~jaxgear.planetary.TimePlan` of a run over the input ``speeds`` (rad/s,
        (s,)) and the mesh-averaged modes it reads (:meth:`averaged_modes`): ``steps`` None
        the automatic step (:func:`~jaxgear.dynamics.auto_steps_per_period`, the rule of
        :func:`~jaxgear.planetary.time_plan`), ``window`` (default :meth:`sweep_window`) its
        periods (None: the automatic span) and kept periods. Nothing integrated."""
        window = self.sweep_window() if window is None else window
        modes = self.averaged_modes()
        sp = np.asarray(speeds, dtype=float)
        plan = time_plan(modes, sp, 1.0 / float(self.mesh_period_angle()),
                         self.stage.n_planets, float(self.run.damping_ratio),
                         carrier_periodic(self.stage, self.flexible_ring()), steps,
                         window.periods, window.keep_periods)
        if steps is None:  # the engine's own rule (the same, on the mesh period's angle)
            plan = plan._replace(steps=auto_steps_per_period(self, sp, modes).astype(int))
        return plan, modes

    def resolve_window(self, window, speeds, steps, modes=None) -> PlanetarySpan:
        """The automatic span at the concrete ``speeds`` (S,) and step counts ``steps`` (S,):
        each speed's settling time t_s (:func:`~jaxgear.dynamics.settling_time` of ``modes``,
        default :meth:`averaged_modes`, at the run's damping ratio) in whole mesh periods, then
        ``window.keep_periods`` (:class:`PlanetarySpan`)."""
        modes = self.averaged_modes() if modes is None else modes
        settle, _ = settling_time(modes, float(self.run.damping_ratio))
        f_mesh = np.asarray(speeds, dtype=float) * (1.0 / float(self.mesh_period_angle()))
        periods = settled_periods(settle, f_mesh, window.keep_periods)
        return PlanetarySpan(tuple(int(n) for n in np.asarray(steps)),
                             tuple(int(p) for p in periods), int(window.keep_periods))

    def check_integrator(self, integrator) -> None:
        if not isinstance(integrator, Newmark) or integrator.basis is not None:
            raise ValueError(
                f"integrator = {type(integrator).__name__}(...): a planetary stage runs Newmark "
                "in coordinates "
                "(allowed jaxgear.dynamics.Newmark(steps_per_period), no basis)"
            )

    def span_periods(self) -> int:
        return 1

    def steps_multiple(self) -> int:
        """N: the planets' phases fall on the steps (:func:`~jaxgear.planetary.time_plan`)."""
        return int(self.stage.n_planets)

    def averaged_modes(
        self, *, speed=0.0, positions_per_pitch: int = 64, contact: ContactLaw = ExactContact()
    ) -> ModalAnalysis:
        """:func:`~jaxgear.planetary.planetary_mesh_modes` of the stage at
        ``positions_per_pitch`` travels of a mesh period (``speed`` and ``contact`` not
        used: the meshes' cells are averaged loaded or not, as the run's damping takes them)."""
        return planetary_mesh_modes(self.kind, self.stage, self.meshes, self.run,
                                    int(positions_per_pitch))

    def _run_of(self, steps: int, periods: int, keep: int, outputs: Outputs) -> PlanetaryRun:
        base = self.run
        return PlanetaryRun(
            base.sun_torque, steps_per_period=int(steps), periods=int(periods),
            keep_periods=int(keep), damping_ratio=base.damping_ratio,
            tangential_pin_errors=base.tangential_pin_errors,
            radial_pin_errors=base.radial_pin_errors, cell_loads=bool(outputs.cell_loads),
            ring_cell_space=True,
        )

    @staticmethod
    def _check_outputs(outputs: Outputs) -> None:
        if outputs.states or outputs.pressure is not None:
            raise ValueError(
                "outputs: a planetary run records its coordinates always and no Hertzian "
                "pressure (allowed Outputs(cell_loads=...))"
            )

    def prepare(self, integrator, law, window, steps_per_period, outputs, modes=None):
        """The :class:`PlanetaryPrepared` of ``steps_per_period`` steps per mesh period and the
        ``window`` (its periods and kept periods); ``outputs.cell_loads`` records the cells'
        forces (:attr:`~jaxgear.planetary.PlanetaryDynamics.cell_forces`).

        Raises:
            ValueError: ``outputs`` asking for states or a pressure; N_s < 8."""
        self._check_outputs(outputs)
        periods = window.periods
        if isinstance(window, PlanetarySpan):  # the longest span of the speeds at this N_s
            own = [p for n, p in zip(window.steps, window.periods, strict=True)
                   if n == int(steps_per_period)]
            periods = max(own or window.periods)
        run = self._run_of(steps_per_period, periods, window.keep_periods, outputs)
        return PlanetaryPrepared(run, law)

    def prepare_steps(self, integrator, law, window, steps, outputs, modes=None):
        """One compiled program for the step counts ``steps`` (ascending): blocks of the
        smallest N_s, the window's periods and kept periods of the largest
        (:func:`~jaxgear.planetary.steps_sweep`'s form), each speed at its own N_s
        (:attr:`~jaxgear.planetary.PlanetaryRun.mesh_steps`): a speed at N_s runs and keeps
        N_top / N_s times the window's mesh periods (the same steps)."""
        self._check_outputs(outputs)
        if isinstance(window, PlanetarySpan):  # the longest settling, keep periods of N_top
            lo, blocks, keep_blocks = program_span(window.steps, window.periods,
                                                   window.keep_periods)
        else:
            lo, top = int(min(steps)), int(max(steps))
            blocks, keep_blocks = window.periods * (top // lo), window.keep_periods * (top // lo)
        run = self._run_of(lo, blocks, keep_blocks, outputs)
        return lambda n: PlanetaryPrepared(run, law, int(n))

    def independent(self, prepared, speeds, *, start=None, shard: bool = False):
        """The stage's :class:`~jaxgear.planetary.PlanetaryDynamics` (the response type of
        this kind: its records of the kept periods, ``dynamic_factors`` per mesh, ``k_gamma``,
        ``result``) at each input speed of ``speeds`` (rad/s, (S,): every field with a
        leading axis S, ``jax.vmap``) or at one scalar speed, each from the quasi-static
        state at its first travel. ``shard`` is not used (one device).

        Raises:
            ValueError: a ``start`` state (a planetary run starts from its quasi-static
                state)."""
        if start is not None:
            raise ValueError("start: a planetary run starts from its quasi-static state "
                             "(allowed None)")
        run = prepared.run
        if prepared.steps is not None:
            n = jnp.asarray(prepared.steps, self.dtype)
            run = eqx.tree_at(lambda r: r.mesh_steps, run, n, is_leaf=lambda x: x is None)

        def one(speed) -> PlanetaryDynamics:
            return planetary_dynamics(self.kind, self.stage, self.meshes, run,
                                      self.carrier_per_input * speed, self._mesh_speed(speed),
                                      prepared.law, self.ring)

        speeds = jnp.asarray(speeds, self.dtype)
        return one(speeds) if speeds.ndim == 0 else jax.vmap(one)(speeds)


def sweep_records(model: PlanetaryModel, speeds, plan: TimePlan,
                  grouped: bool | None = None, contact: ContactLaw | None = None) -> SweepRecords:
    """The records of a sweep of ``model`` over the input ``speeds`` (rad/s, (s,)) on its
    ``plan`` (:meth:`PlanetaryModel.time_plan`), through :func:`jaxgear.dynamics.speed_sweep`:
    the plan's steps (automatic or given) and span (automatic, or the given periods), each
    group of :func:`~jaxgear.planetary.speed_groups` one sweep (one compiled program, each
    speed at its own N_s: :meth:`PlanetaryModel.prepare_steps`); ``grouped`` None: one
    program per N_s for a flexible ring, one for all speeds otherwise. Each speed's own last
    ``plan.keep`` mesh periods (:class:`~jaxgear.planetary.SweepRecords`, the input of
    :func:`~jaxgear.planetary.sweep_factors`); ``contact``: the contact law (None: the
    model's default, :meth:`PlanetaryModel.default_settings`)."""
    sp = np.asarray(speeds, dtype=float)
    grouped = model.flexible_ring() if grouped is None else bool(grouped)
    integrator = Newmark(None if plan.automatic[0] else int(plan.steps[0]))
    window = SteadyState(None if plan.automatic[1] else int(plan.periods[0]), plan.keep)

    def program(idx):
        return speed_sweep(model, sp[idx], integrator=integrator, contact=contact,
                           window=window).results

    return grouped_records(plan, speed_groups(plan, grouped), program)
