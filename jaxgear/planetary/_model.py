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
:class:`~jaxgear.dynamics.DynamicResponse`: :meth:`PlanetaryModel.independent` documents it.

A model given its ``input`` and ``output`` members (two of :class:`~jaxgear.planetary.Central`,
the third held) is also a gearbox stage: :class:`PlanetaryModel` satisfies the stage contract
:class:`jaxgear.dynamics.AbstractStage`, and a :class:`jaxgear.gearbox.GearboxTorsional` takes it
as one of its stages (its coordinates u = r theta scaled to rotations theta (rad) so that the
shafts join rotations; translations stay in m; Willis' relation on base radii for the members'
speeds, from which ``carrier_per_input`` and ``mesh_speed_per_input`` then follow)."""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact
from .._util import as_float, check_instance, is_traced
from ..dynamics import (
    AbstractDynamicModel,
    AbstractStage,
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
from ..scenes import HousingMount
from ._dynamics import (
    PlanetaryDynamics,
    PlanetaryRun,
    planetary_cell_row,
    planetary_dynamics,
    planetary_mesh_modes,
    planetary_stage_system,
)
from ._housed import check_carrier_speed
from ._meshes import AbstractPlanetaryMeshes, ConstantMeshes
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
from ._stage import AbstractPlanetaryModel, Central, PlanetaryStage, TorsionalPlanetary
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


def _role_speeds(stage: PlanetaryStage, input: Central, output: Central, input_speed):
    """((omega_c, omega_r, omega_s) (rad/s, fixed frame), the index of each central member in
    it): Willis' relation on base radii (r_bs w_s + r_br w_r = (r_bs + r_br) w_c; the radii are
    in the tooth counts' ratio) with the member that is neither ``input`` nor ``output`` held
    and the ``input`` member at ``input_speed`` (rad/s)."""
    r_s, r_r = stage.sun.base_radius, stage.ring.base_radius
    held = ({Central.CARRIER, Central.RING, Central.SUN} - {input, output}).pop()
    a = jnp.array([[-(r_s + r_r), r_r, r_s], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    idx = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}
    a = a.at[1, idx[held]].set(1.0).at[2, idx[input]].set(1.0)
    w = jnp.linalg.solve(a, jnp.stack([0.0 * input_speed, 0.0 * input_speed, input_speed]))
    return w, idx


def _roles_given(stage, input, output) -> bool:
    """Whether the members' roles can set the speeds (checked in one line afterwards)."""
    return (isinstance(stage, PlanetaryStage) and isinstance(input, Central)
            and isinstance(output, Central) and input != output)


class PlanetaryModel(AbstractDynamicModel, AbstractStage):
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
        carrier_per_input: Ω / ω_in (-), the carrier's speed per input speed (fixed frame);
            None (default): 1, or the roles' (below).
        mesh_speed_per_input: v / ω_in (m/s per rad/s), the mesh travel speed per input speed;
            None: the ring held, v = r_br |Ω|, or the roles' (below).
        ring: :class:`~jaxgear.planetary.RigidRing` (default) or a flexible ring model.
        input, output: static, two different :class:`~jaxgear.planetary.Central` members (the
            third held), or None (default): the members' roles, which make the model a gearbox
            stage (:class:`jaxgear.dynamics.AbstractStage`) and set ``carrier_per_input`` and
            ``mesh_speed_per_input`` by Willis' relation on base radii (r_bs ω_s + r_br ω_r =
            (r_bs + r_br) Ω, the third member at rest; v = r_bs |ω_s − Ω|): both are then left
            None.
        mount: keyword, a :class:`~jaxgear.scenes.HousingMount` the stage's central members
            stand on (docs/planetary.md, "On a housing": its joints ``"ring"``, ``"carrier"``,
            ``"sun"`` at the stage centre, :meth:`~jaxgear.scenes.HousingMount.on_axis`; its
            housing placed in the stage's scene frame), or None (default): the stage on the
            ground. Read back as :meth:`mount`; the engines run :attr:`mounted_kind` (the kind
            on it: its coordinates then the housing's). A ``kind`` given on a mount
            (:meth:`~jaxgear.planetary.AbstractPlanetaryModel.on`) is taken apart into its
            kind and its mount.

    ``scene`` (and :attr:`stage`) is the stage and ``torque`` the sun torque T_s (N m): the
    engine entries read neither (they ask the model's methods); ``mods`` is None (a stage's
    deviations live in its meshes).

    Raises:
        ValueError: a kind, stage, meshes, run, ring or mount of another type, a kind on a
            mount with a ``mount`` too, ``carrier_per_input``
            zero without a ``mesh_speed_per_input``, ``mesh_speed_per_input`` not > 0; one of
            ``input`` and ``output`` without the other, either not a ``Central`` member, the
            two the same, or given with ``carrier_per_input`` or ``mesh_speed_per_input`` (one
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
    housing_mount: HousingMount | None
    input: Central | None = eqx.field(static=True)
    output: Central | None = eqx.field(static=True)

    def __init__(
        self,
        kind: AbstractPlanetaryModel,
        stage: PlanetaryStage,
        meshes: AbstractPlanetaryMeshes,
        run: PlanetaryRun,
        carrier_per_input=None,
        mesh_speed_per_input=None,
        ring: AbstractRingModel = RigidRing(),
        *,
        input: Central | None = None,
        output: Central | None = None,
        mount: HousingMount | None = None,
    ):
        if isinstance(kind, AbstractPlanetaryModel) and kind.mount() is not None:
            if mount is not None:
                raise ValueError("PlanetaryModel: a kind on a mount and mount= both given: "
                                 "allowed one (the kind on the ground and mount=)")
            kind, mount = kind.unmounted(), kind.mount()
        self.kind, self.scene, self.meshes, self.run, self.ring = kind, stage, meshes, run, ring
        self.housing_mount = mount
        self.mods = None
        # another run type is refused in one line by __check_init__
        self.torque = run.sun_torque if isinstance(run, PlanetaryRun) else None
        self.input, self.output = input, output
        roles = input is not None or output is not None
        if roles and (carrier_per_input is not None or mesh_speed_per_input is not None):
            raise ValueError(
                "PlanetaryModel: carrier_per_input or mesh_speed_per_input given with the "
                "input and output members: allowed None (Willis' relation of the members sets "
                "them)")
        if roles and _roles_given(stage, input, output):
            w, _ = _role_speeds(stage, input, output, 1.0)
            carrier_per_input = w[0]
            mesh_speed_per_input = stage.sun.base_radius * jnp.abs(w[2] - w[0])
        self.carrier_per_input = as_float(1.0 if carrier_per_input is None else carrier_per_input)
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
    #: a housing its central members' supports join (``mount=``), as a model and as a gearbox
    #: stage
    takes_housing: ClassVar[bool] = True

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
        if self.housing_mount is not None:
            check_instance("mount", self.housing_mount, HousingMount,
                           "a jaxgear.scenes.HousingMount or None", where)
            self.kind.on(self.housing_mount)  # its joints: central members on the stage axis
        if (self.input is None) != (self.output is None):
            raise ValueError(f"{where}: input = {self.input!r}, output = {self.output!r}: "
                             "allowed both central members or neither")
        for name, member in (("input", self.input), ("output", self.output)):
            if member is not None and not isinstance(member, Central):
                raise ValueError(f"{where}: {name} = {member!r}: allowed a "
                                 "jaxgear.planetary.Central member (SUN, RING, CARRIER)")
        if self.input is not None and self.input == self.output:
            raise ValueError(f"{where}: input = output = {self.input!r}: allowed two different "
                             "central members")
        check_carrier_speed(self.mounted_kind, self.carrier_per_input,
                            "PlanetaryModel (carrier_per_input times the input speed)")
        v = self.mesh_speed_per_input
        if v is None and not is_traced(self.carrier_per_input) and not (
                float(self.carrier_per_input) != 0.0):
            raise ValueError(
                f"carrier_per_input = {float(self.carrier_per_input)!r}: out of range, allowed "
                "!= 0 where mesh_speed_per_input is None (the ring held: v = r_br |Ω|)"
            )
        if v is not None and not is_traced(v) and not float(v) > 0.0:
            raise ValueError(
                f"mesh_speed_per_input = {float(v)!r} m/s per rad/s: out of range, allowed > 0"
            )

    # --- what the engine entries read ------------------------------------------------------

    @property
    def stage(self) -> PlanetaryStage:
        """The stage (the model's ``scene``)."""
        return self.scene

    @property
    def mounted_kind(self) -> AbstractPlanetaryModel:
        """The kind on :meth:`mount` (:meth:`~jaxgear.planetary.AbstractPlanetaryModel.on`:
        its coordinates then the housing's, the joined supports on their seats), or ``kind``
        on the ground: the kind every engine entry of the model runs."""
        return self.kind.on(self.housing_mount)

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
        s = planetary_stage_system(self.mounted_kind, self.stage, self.meshes, self.run, 1)
        return s.m, s.k_b

    def whine(self, speeds, method, *, positions: int = 256, contact=ExactContact()):
        """The stage's gear whine in the frequency domain at the input ``speeds`` (rad/s):
        :func:`~jaxgear.planetary.planetary_whine` at the carrier and mesh speeds they give
        (:func:`jaxgear.dynamics.whine_response` delegates here)."""
        check_whine_speeds(speeds, "input")
        s = jnp.atleast_1d(jnp.asarray(speeds, self.dtype))
        w = planetary_whine(self.mounted_kind, self.stage, self.meshes, self.run,
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
        return planetary_mesh_modes(self.mounted_kind, self.stage, self.meshes, self.run,
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
            return planetary_dynamics(self.mounted_kind, self.stage, self.meshes, run,
                                      self.carrier_per_input * speed, self._mesh_speed(speed),
                                      prepared.law, self.ring)

        speeds = jnp.asarray(speeds, self.dtype)
        return one(speeds) if speeds.ndim == 0 else jax.vmap(one)(speeds)

    # --- the stage contract (jaxgear.dynamics.AbstractStage): the model in a gearbox --------
    # its coordinates u = r theta scaled to theta (rad) so that the shafts join rotations;
    # translations stay in m. The run's pin errors are the stage's; its sun torque is not read
    # (the gearbox carries the torque through the stages' kinematics).

    def check_stage(self, where: str) -> None:
        """Refuse (one line naming ``where``) a model that cannot stand in a gearbox: no
        ``input`` and ``output`` members, a flexible ring (the coupled model takes a rigid
        ring's cells), a kind without contact cells, or a mount that joins every support (the
        carrier held, :attr:`~jaxgear.scenes.HousingMount.fixed_frame`) whose carrier is the
        input or output member (it turns)."""
        if self.input is None:
            raise ValueError(f"{where}: a PlanetaryModel without its input and output members: "
                             "allowed PlanetaryModel(..., input=, output=) (two Central "
                             "members, the third held)")
        if self.flexible_ring():
            raise ValueError(f"{where}: ring {type(self.ring).__name__}: allowed RigidRing (the "
                             "coupled gearbox takes a rigid ring's cells)")
        if not self.kind.contact_solve:
            raise ValueError(f"{where}: model {type(self.kind).__name__} has no contact cells: "
                             "allowed TorsionalPlanetary, PlanarPlanetary (either on a mount)")
        mount = self.housing_mount
        if (mount is not None and mount.fixed_frame
                and Central.CARRIER in (self.input, self.output)):
            role = "input" if self.input == Central.CARRIER else "output"
            raise ValueError(f"{where}: a mount that joins every support (the carrier held) "
                             f"with the carrier the {role} member: allowed a star stage (sun "
                             "and ring the shafts' members, the carrier held)")

    def _scale(self):
        """r per coordinate: a rotation's u = r theta radius (the planet's, a central
        member's), 1 for a translation."""
        st = self.stage
        radius = {"c": st.carrier.base_radius, "r": st.ring.base_radius,
                  "s": st.sun.base_radius}
        r = [radius.get(n[2:], st.planet.base_radius) if n.startswith("u_") else 1.0
             for n in self.mounted_kind.dof_names(st)]
        return jnp.stack([jnp.asarray(v, dtype=st.planet_angles.dtype) for v in r])

    def coordinates(self):
        """The kind's coordinates (``dof_names``), each rotation's ``u_<m>`` (m) named
        ``theta_<m>`` (rad)."""
        return tuple(("theta_" + n[2:]) if n.startswith("u_") else n
                     for n in self.mounted_kind.dof_names(self.stage))

    def coordinate_ends(self):
        names = self.mounted_kind.dof_names(self.stage)
        key = {Central.CARRIER: "u_c", Central.RING: "u_r", Central.SUN: "u_s"}
        return names.index(key[self.input]), names.index(key[self.output])

    def dynamic_parts(self, positions):
        """(M, K_b, K̄_m, F) of :func:`~jaxgear.planetary.planetary_stage_system` (the run's
        pin errors) on :meth:`coordinates`."""
        parts = planetary_stage_system(self.mounted_kind, self.stage, self.meshes, self.run,
                                       positions)
        r = self._scale()
        rr = r[:, None] * r[None, :]
        return rr * parts.m, rr * parts.k_b, rr * parts.k_mean, r * parts.f

    def cell_row(self, x):
        row = planetary_cell_row(self.mounted_kind, self.stage, self.meshes, self.run, x)
        return row._replace(V=row.V * self._scale()[None, :])

    def mesh_forces(self, forces):
        return self.meshes.mesh_forces(forces)

    def on_flanks(self, sign):
        """The stage on the flanks its static load takes: with ``sign`` < 0 (the planets drive
        the sun: carrier in and sun out) its meshes'
        :meth:`~jaxgear.planetary.ContactMeshes.other_flanks` (the sun-ring phase within a
        planet of the other flanks), chosen leaf by leaf so that ``sign`` may be traced
        (meshes whose cells do not depend on the flanks give themselves: the same stage)."""
        other = self.meshes.other_flanks()
        # only the leaves the other flanks change are selected (the rest are the same arrays:
        # the tables are not copied)
        meshes = jax.tree.map(
            lambda a, b: jnp.where(sign < 0, b, a) if eqx.is_array(a) and a is not b else a,
            self.meshes, other)
        return eqx.tree_at(lambda s: s.meshes, self, meshes)

    def mesh_names(self):
        n = self.stage.n_planets
        return (tuple(f"sun-planet {i + 1}" for i in range(n))
                + tuple(f"ring-planet {i + 1}" for i in range(n)))

    def mesh_period(self):
        return self.meshes.mesh_period()

    def excited(self):
        return not isinstance(self.meshes, ConstantMeshes)

    def kinematics(self, input_speed, input_torque):
        st = self.stage
        w, idx = _role_speeds(st, self.input, self.output, as_float(input_speed))
        out_speed = w[idx[self.output]]
        # power: |T_out| = |T_in w_in / w_out|; the sun's torque T_s = r_bs (over the torque's
        # lever of the input member: r_bs, r_br or r_bs + r_br) T_in; each mesh N r_bs F = T_s
        r_s, r_r = st.sun.base_radius, st.ring.base_radius
        lever = {Central.SUN: r_s, Central.RING: r_r, Central.CARRIER: r_s + r_r}[self.input]
        torque = jnp.abs(as_float(input_torque))
        out_torque = torque * jnp.abs(as_float(input_speed) / out_speed)
        f = torque / (lever * st.n_planets)
        v = r_s * jnp.abs(w[2] - w[0])  # the mesh travel in the carrier frame
        return out_speed, out_torque, v, jnp.full((2 * st.n_planets,), f)

    def speed_terms(self, carrier_speed):
        """(C_Omega, K_Omega) of the kind at ``carrier_speed`` (rad/s), on a mount the
        housing's damping C_h on its coordinates added to C_Omega (the coupled model's
        constant damping term, which carries a lumped stage's housing damping as well)."""
        r = self._scale()
        rr = r[:, None] * r[None, :]
        st = self.stage
        kind, mount = self.mounted_kind, self.housing_mount
        c = carrier_speed * rr * kind.gyroscopic_matrix(st)
        if mount is not None:
            h = mount.size
            c = c.at[-h:, -h:].add(jnp.asarray(mount.C, c.dtype))
        return c, -carrier_speed**2 * rr * kind.centripetal_matrix(st)

    def mount(self):
        """The :class:`~jaxgear.scenes.HousingMount` the stage stands on (``mount=``: its
        housing's coordinates end :meth:`coordinates`; its joints the joined members), or
        None: the stage on the ground."""
        return self.housing_mount

    def carrier_speed(self, input_speed):
        """The carrier's speed (rad/s) at the input member's ``input_speed``."""
        return _role_speeds(self.stage, self.input, self.output, as_float(input_speed))[0][0]

    def dof_names(self):
        """The torsional chain's rotations: carrier, ring, sun, then each planet's."""
        return ("theta_c", "theta_r", "theta_s") + tuple(
            f"theta_{i + 1}" for i in range(self.stage.n_planets)
        )

    def matrices(self):
        """(M, K) of :class:`~jaxgear.planetary.TorsionalPlanetary` (Kahraman 1994) on the
        rotations (kg m^2, N m/rad), u = r theta: R M R and R K R, R = diag(r)."""
        model, st = TorsionalPlanetary(), self.stage
        r = jnp.concatenate(
            [
                jnp.stack([st.carrier.base_radius, st.ring.base_radius, st.sun.base_radius]),
                jnp.broadcast_to(st.planet.base_radius, (st.n_planets,)),
            ]
        )
        scale = r[:, None] * r[None, :]
        return scale * model.mass_matrix(st), scale * model.stiffness_matrix(st)

    def ends(self):
        # TorsionalPlanetary's order: u_c, u_r, u_s (Central's carrier, ring, sun)
        order = {Central.CARRIER: 0, Central.RING: 1, Central.SUN: 2}
        return order[self.input], order[self.output]


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
