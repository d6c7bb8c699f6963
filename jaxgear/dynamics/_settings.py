"""The settings of the dynamics, as objects (the way ``diffrax.diffeqsolve`` takes a solver, a
step-size controller and ``SaveAt``): the integrator (:class:`Newmark` or
:class:`DiffraxIntegrator`) and the steady-state window (:class:`SteadyState`); the contact law
is :class:`jaxgear.ExactContact` or :class:`jaxgear.SmoothContact`, the damping
:class:`jaxgear.io.Damping`, and the operating point (torque, speed) an argument of the
solvers. Also the run-size guard and the divergence checks the integrators share.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable
from typing import TYPE_CHECKING, ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import optimistix

from fem_prep.resources import check_memory

from .._geometry import GearPair
from .._util import check_integer

if TYPE_CHECKING:
    import diffrax

__all__ = [
    "Batching",
    "DIFFRAX_ADJOINTS",
    "DIFFRAX_SOLVERS",
    "MAX_STEPS_PER_SPEED",
    "DiffraxIntegrator",
    "HertzPressure",
    "ModalBasis",
    "Newmark",
    "Outputs",
    "SteadyState",
    "check_run_size",
]

# time steps one speed may integrate (periods × steps per mesh period): 2^22 is hours of Newmark
MAX_STEPS_PER_SPEED = 2**22

def _diffrax():
    """The diffrax module, imported when a diffrax solver is first asked for (about 0.5 s of
    import that a Newmark run, the default, does not pay)."""
    import diffrax  # lazy: an optional heavy dependency of the Newmark default

    return diffrax


class _SolverName(eqx.Module):
    """A diffrax solver class as a case file names it (:data:`DIFFRAX_SOLVERS`), by its name in
    diffrax (``"Tsit5"``: diffrax is imported only when the solver is built): :meth:`of` its
    object for a :class:`DiffraxIntegrator`'s tolerances and step control."""

    cls: str = eqx.field(static=True)

    def of(self, rtol: float, atol: float, adaptive: bool) -> diffrax.AbstractSolver:
        """The solver object (an explicit solver: the class's default)."""
        return getattr(_diffrax(), self.cls)()


class _ImplicitSolverName(_SolverName):
    """An implicit diffrax solver by name: at constant steps (``adaptive=False``) its root
    finder (``diffrax.VeryChord``, max norm) takes the integrator's tolerances (with a PID
    controller it takes the controller's, the class's default)."""

    def of(self, rtol: float, atol: float, adaptive: bool) -> diffrax.AbstractSolver:
        dfx = _diffrax()
        if adaptive:
            return getattr(dfx, self.cls)()
        root_finder = dfx.VeryChord(rtol=rtol, atol=atol, norm=optimistix.max_norm)
        return getattr(dfx, self.cls)(root_finder=root_finder)


class _AdjointName(eqx.Module):
    """A diffrax adjoint by name (:data:`DIFFRAX_ADJOINTS`), by its class name in diffrax."""

    cls: str = eqx.field(static=True)

    def of(self) -> diffrax.AbstractAdjoint:
        return getattr(_diffrax(), self.cls)()


#: the diffrax solvers by the names of the case files (``[scene.integration] solver``) and the
#: CLI (``--solver``): the one place those names map to solver objects (for :mod:`jaxgear.io`)
DIFFRAX_SOLVERS = {
    "tsit5": _SolverName("Tsit5"),
    "dopri5": _SolverName("Dopri5"),
    "dopri8": _SolverName("Dopri8"),
    "bosh3": _SolverName("Bosh3"),
    "heun": _SolverName("Heun"),
    "midpoint": _SolverName("Midpoint"),
    "ralston": _SolverName("Ralston"),
    "euler": _SolverName("Euler"),
    "kvaerno3": _ImplicitSolverName("Kvaerno3"),
    "kvaerno4": _ImplicitSolverName("Kvaerno4"),
    "kvaerno5": _ImplicitSolverName("Kvaerno5"),
    "implicit_euler": _ImplicitSolverName("ImplicitEuler"),
}

#: the diffrax adjoints by name: "reverse" (``diffrax.RecursiveCheckpointAdjoint``, for
#: ``jax.grad``) and "forward" (``diffrax.ForwardMode``, for ``jax.jvp``/``jax.jacfwd``)
DIFFRAX_ADJOINTS = {
    "reverse": _AdjointName("RecursiveCheckpointAdjoint"),
    "forward": _AdjointName("ForwardMode"),
}


def _by_name(table: dict, key):
    """``table[key]`` where ``key`` is one of its names, else None (an object given as is)."""
    try:
        return table.get(key)
    except TypeError:  # unhashable: not a name
        return None


def check_run_size(periods: int, steps_per_period: int, recorded_steps: int, values: int) -> None:
    """Refuse, before any work, a run that cannot finish: more than
    :data:`MAX_STEPS_PER_SPEED` time steps per speed, or records (``recorded_steps`` ×
    ``values`` float64 per speed) above half the machine's memory. One-line ``ValueError`` that
    names the settings to change."""
    n = int(periods) * int(steps_per_period)
    if n > MAX_STEPS_PER_SPEED:
        raise ValueError(
            f"periods = {int(periods)} × steps_per_period = {int(steps_per_period)} = {n:.3g} "
            f"time steps per speed: allowed <= {MAX_STEPS_PER_SPEED:.3g} (fewer periods, or "
            "fewer steps per period)"
        )
    check_memory(f"periods = {int(periods)}", 8.0 * int(recorded_steps) * int(values),
                 "the records of one speed", "fewer periods (or keep_periods), steps per period "
                 "or slices")


def _check_steps(steps_per_period) -> None:
    if steps_per_period is not None:
        check_integer("steps_per_period", steps_per_period, 4)


class ModalBasis(eqx.Module):
    """Integrate a hybrid model in the modal basis of its assembled structure: the ``modes``
    lowest modes of (M, K + K̄), K̄ the loaded mesh stiffness averaged round a wheel revolution
    (at pinion ``speed``, the model's torque), plus the static correction of the cells (the
    residual flexibility of the forces on the structure: the part of K⁻¹ not in the modes, so
    that the quasi-static limit stays exact and the contact sees the full compliance). The
    contact is solved exactly on the cells in the window at every step, as in the cell space;
    only the structural solve shrinks from n² to ~m² plus window products per step
    (docs/hybrid.md, "Modal basis"; R. R. Craig & A. J. Kurdila, *Fundamentals of Structural
    Dynamics*, 2nd ed., Wiley 2006, §14.5, the mode-acceleration method and residual
    flexibility). Pass it as ``Newmark(steps, basis=ModalBasis(m))``.

    Attributes:
        modes: m, the number of modes kept, an integer >= 1 (<= the structure's n coordinates,
            checked when the run starts; m = n is the cell-space result to round-off).
        speed: the pinion speed (rad/s, >= 0) of the quasi-static solve that loads the cells of
            K̄ (centrifugal loads); the basis is computed once per sweep at that speed. Default
            at rest.
        static_correction: add the residual flexibility (default). ``False`` keeps the m modes
            alone (a truncated modal model: the contact then sees too stiff a structure; for
            comparison only).

    Raises:
        ValueError: ``modes`` not an integer >= 1, ``speed`` not a number >= 0.
    """

    modes: int = eqx.field(static=True)
    speed: float = eqx.field(default=0.0, static=True)
    static_correction: bool = eqx.field(default=True, static=True)

    def __check_init__(self):
        check_integer("modes", self.modes, 1)
        v = self.speed
        if isinstance(v, bool) or not (isinstance(v, int | float) and 0 <= v < math.inf):
            raise ValueError(f"speed = {v!r} rad/s is out of range: allowed a finite number >= 0")
        if type(self.static_correction) is not bool:
            raise ValueError(
                f"static_correction = {self.static_correction!r}: allowed True or False"
            )


class Newmark(eqx.Module):
    """Newmark's average-acceleration method (β = 1/4, γ = 1/2: unconditionally stable, second
    order, no numerical damping; seed annex 2) with the contact loop inside each step (II-25).

    Attributes:
        steps_per_period: N_s, time steps per mesh period, an integer >= 4; ``None``: automatic
            (lumped scenes: :func:`~jaxgear.dynamics.auto_steps_per_period`, >= 40 steps per
            period of the highest mode the mesh excites, >= 64 per mesh period, a power of two;
            needs concrete speeds). Static: a new value recompiles.
        basis: ``None`` (the cell space: every coordinate, one n² effective compliance per
            speed) or :class:`ModalBasis` (hybrid models only: the modes of the assembled
            structure plus the static correction of the cells).

    Raises:
        ValueError: ``steps_per_period`` not ``None`` or an integer >= 4; ``basis`` neither
            ``None`` nor a :class:`ModalBasis`.
    """

    steps_per_period: int | None = eqx.field(default=None, static=True)
    basis: ModalBasis | None = eqx.field(default=None, static=True)

    #: no step cap: Newmark takes exactly periods × N_s steps (:attr:`DiffraxIntegrator.max_steps`)
    max_steps: ClassVar[None] = None
    #: its step count can be an argument of one compiled run (a mixed-N_s sweep, one program:
    #: :meth:`~jaxgear.dynamics.AbstractDynamicModel.prepare_steps`)
    traced_steps: ClassVar[bool] = True

    def __check_init__(self):
        _check_steps(self.steps_per_period)
        if self.basis is not None and not isinstance(self.basis, ModalBasis):
            raise ValueError(
                f"basis = {self.basis!r}: allowed None or jaxgear.dynamics.ModalBasis(modes)"
            )


class DiffraxIntegrator(eqx.Module):
    """A diffrax solver on the first-order form M Ẍ = F − C Ẋ − K X − Vᵀ P(X) (lumped scenes;
    use :class:`~jaxgear.SmoothContact`: the exact law's kinks stall adaptive steps).

    Attributes:
        solver: a diffrax solver object (``diffrax.Tsit5()``, ``diffrax.Kvaerno5()``, ...,
            passed straight to ``diffrax.diffeqsolve``; an implicit solver at constant steps
            needs its own ``root_finder`` tolerances), or a name of :data:`DIFFRAX_SOLVERS`
            (``"tsit5"``, ``"kvaerno5"``, ...: its class, an implicit one at constant steps with
            a ``diffrax.VeryChord`` root finder of ``rtol``, ``atol`` and the max norm).
        steps_per_period: the initial step and the sampling of the kept periods, as
            :class:`Newmark`'s (``None``: automatic).
        rtol, atol: PID step-size tolerances on the scaled state (X/x_ref, Ẋ/(x_ref ω_max),
            x_ref the static mesh deflection); with ``adaptive=False``, the implicit solvers'
            root-finder tolerances (by name).
        adaptive: ``False`` for constant steps Δt = period/N_s.
        max_steps: step cap (``None``: 64 × the Newmark step count + 4096).
        adjoint: a diffrax adjoint object, or a name of :data:`DIFFRAX_ADJOINTS`: "reverse"
            (the default: ``diffrax.RecursiveCheckpointAdjoint()``, for ``jax.grad``) or
            "forward" (``diffrax.ForwardMode()``, for ``jax.jvp``/``jax.jacfwd``).

    Raises:
        ValueError: an unknown solver or adjoint, tolerances not > 0, bad step counts.
    """

    solver: diffrax.AbstractSolver = eqx.field(static=True)
    steps_per_period: int | None = eqx.field(static=True)
    rtol: float = eqx.field(static=True)
    atol: float = eqx.field(static=True)
    adaptive: bool = eqx.field(static=True)
    max_steps: int | None = eqx.field(static=True)
    adjoint: diffrax.AbstractAdjoint = eqx.field(static=True)
    #: a diffrax solve's steps are fixed when it compiles (one program per N_s)
    traced_steps: ClassVar[bool] = False

    def __init__(
        self,
        solver: diffrax.AbstractSolver | str = "tsit5",
        steps_per_period: int | None = None,
        rtol: float = 1e-6,
        atol: float = 1e-6,
        adaptive: bool = True,
        max_steps: int | None = None,
        adjoint: diffrax.AbstractAdjoint | str = "reverse",
    ):
        named = _by_name(DIFFRAX_SOLVERS, solver)
        self.solver = solver if named is None else named.of(rtol, atol, adaptive)
        self.steps_per_period, self.rtol, self.atol = steps_per_period, rtol, atol
        self.adaptive, self.max_steps = adaptive, max_steps
        named = _by_name(DIFFRAX_ADJOINTS, adjoint)
        self.adjoint = adjoint if named is None else named.of()

    def __check_init__(self):
        diffrax = _diffrax()
        if not isinstance(self.solver, diffrax.AbstractSolver):
            raise ValueError(
                f"solver = {self.solver!r}: allowed a diffrax solver name "
                f"({', '.join(DIFFRAX_SOLVERS)}) or a diffrax solver object (diffrax.Tsit5(), ...)"
            )
        if not isinstance(self.adjoint, diffrax.AbstractAdjoint):
            raise ValueError(
                f"adjoint = {self.adjoint!r}: allowed 'reverse', 'forward' or a diffrax adjoint "
                "object (diffrax.RecursiveCheckpointAdjoint(), diffrax.ForwardMode())"
            )
        for name in ("rtol", "atol"):
            v = getattr(self, name)
            if isinstance(v, bool) or not (isinstance(v, int | float) and 0 < v < math.inf):
                raise ValueError(f"{name} = {v!r}: allowed a tolerance > 0, finite")
        _check_steps(self.steps_per_period)
        if self.max_steps is not None:
            check_integer("max_steps", self.max_steps, 1)


Integrator = Newmark | DiffraxIntegrator


class SteadyState(eqx.Module):
    """The steady-state window of a run: ``periods`` mesh periods integrated from the start
    state, the last ``keep_periods`` of them recorded (the responses, dynamic factors and
    RMS values are taken over those).

    Attributes:
        periods: mesh periods integrated, an integer >= 2; or None: the model's automatic
            span, its settling time at each speed then ``keep_periods``, resolved over the
            run's speeds and step counts by the model
            (:meth:`~jaxgear.dynamics.AbstractDynamicModel.resolve_window`; the kinds with
            :attr:`~jaxgear.dynamics.AbstractDynamicModel.automatic_span`: a planetary stage).
        keep_periods: mesh periods kept at the end, an integer in [1, periods] (the lumped
            dynamics need >= 2: their periodicity compares the last two).

    Raises:
        ValueError: counts out of those ranges.
    """

    periods: int | None = eqx.field(default=60, static=True)
    keep_periods: int = eqx.field(default=4, static=True)

    def __check_init__(self):
        check_integer("keep_periods", self.keep_periods, 1)
        if self.periods is None:
            return
        check_integer("periods", self.periods, 2)
        if self.keep_periods > self.periods:
            raise ValueError(
                f"keep_periods = {self.keep_periods} must be <= periods = {self.periods}"
            )


def _is_pair(x) -> bool:
    return isinstance(x, GearPair)


def _pairs(pairs) -> tuple:
    """The gear pairs of ``pairs`` (one :class:`~jaxgear.GearPair` or a tuple of them), as a
    tuple (checked by :class:`HertzPressure`)."""
    return tuple(jax.tree.leaves(pairs, is_leaf=_is_pair))


class HertzPressure(eqx.Module):
    """Track the largest Hertzian contact pressure of every mesh during a dynamic run: at each
    kept step the largest p₀ = √(w E*/(π R(s))) over the mesh's cells (Hertz line contact,
    K. L. Johnson, *Contact Mechanics*, 1985, §4.3; :func:`jaxgear.contact_pressure`), reduced
    over the kept steps inside the time loop (no per-cell records); the largest over the
    model's quasi-static positions beside it. Pass it as ``pressure=`` to
    :func:`~jaxgear.dynamics.simulate` or :func:`~jaxgear.dynamics.speed_sweep`; the result's
    :attr:`MeshDynamics.max_pressure` and ``max_pressure_static`` hold them.

    Attributes:
        pairs: the :class:`~jaxgear.GearPair` of each gear mesh, in the scene's mesh order (its
            pinion the mesh's driving gear; one pair for a one-mesh scene, given alone or in a
            tuple): the flanks' radii of curvature.
        youngs_modulus: E of both gears (Pa), > 0. poisson_ratio: ν, in [0, 0.5).

    Raises:
        ValueError: a pair that is not a :class:`~jaxgear.GearPair`, no pair, or a material out
            of range (one line naming the attribute); a run whose scene has another number of
            meshes than ``pairs`` (when the run starts).
    """

    pairs: tuple = eqx.field(static=True, converter=_pairs)
    youngs_modulus: float = eqx.field(static=True)
    poisson_ratio: float = eqx.field(static=True)

    def __check_init__(self):
        if not self.pairs or not all(isinstance(p, GearPair) for p in self.pairs):
            raise ValueError(
                f"pairs = {self.pairs!r}: allowed a jaxgear.GearPair or a tuple of them, one "
                "per gear mesh"
            )
        E, nu = self.youngs_modulus, self.poisson_ratio
        if isinstance(E, bool) or not (isinstance(E, int | float) and 0 < E < math.inf):
            raise ValueError(f"youngs_modulus = {E!r} Pa is out of range: allowed finite > 0 Pa")
        if isinstance(nu, bool) or not (isinstance(nu, int | float) and 0 <= nu < 0.5):
            raise ValueError(f"poisson_ratio = {nu!r} is out of range: allowed [0, 0.5)")


def check_pressure(pressure, meshes: int) -> HertzPressure | None:
    """``pressure`` checked to be None or a :class:`HertzPressure` of ``meshes`` pairs (one line
    naming ``pressure`` otherwise)."""
    if pressure is None:
        return None
    if not isinstance(pressure, HertzPressure):
        raise ValueError(
            f"pressure = {pressure!r}: allowed None or jaxgear.dynamics.HertzPressure(...)"
        )
    if len(pressure.pairs) != meshes:
        raise ValueError(
            f"pressure: {len(pressure.pairs)} gear pairs for a scene of {meshes} gear meshes "
            "(allowed one pair per mesh, in the scene's mesh order)"
        )
    return pressure


def check_integrator(integrator, name: str = "integrator") -> Integrator:
    """``integrator`` checked to be :class:`Newmark` or :class:`DiffraxIntegrator` (one line
    naming ``name`` otherwise)."""
    if not isinstance(integrator, Integrator):
        raise ValueError(
            f"{name} = {integrator!r}: allowed jaxgear.dynamics.Newmark(...) or "
            "jaxgear.dynamics.DiffraxIntegrator(...)"
        )
    return integrator


def check_window(window, name: str = "window") -> SteadyState:
    if not isinstance(window, SteadyState):
        raise ValueError(f"{name} = {window!r}: allowed jaxgear.dynamics.SteadyState(...)")
    return window


@dataclasses.dataclass(frozen=True)
class Outputs:
    """What a run records beside the steady-state statistics, and its divergence bound (the
    ``outputs`` of :func:`~jaxgear.dynamics.simulate` and :func:`~jaxgear.dynamics.speed_sweep`,
    checked there).

    Attributes:
        states: also record the coordinates at the kept steps (``DynamicResponse.states``;
            Newmark only).
        cell_loads: also record every mesh's cell loads at the kept steps: the line load
            (N/m), base-plane s and z (m) and flank mask of every cell, (K, L, N) each
            (:class:`~jaxgear.dynamics.MeshDynamics` ``line_load``, ``cell_s``, ``cell_z``,
            ``cell_mask``; the input of :func:`jaxgear.contact_pressure` and
            :func:`jaxgear.load_map`). Memory ∝ K × cells.
        pressure: :class:`HertzPressure` (the pairs and the material): track each mesh's
            largest Hertzian contact pressure over the kept steps inside the time loop
            (``MeshDynamics.max_pressure``, ``max_pressure_static``; a sweep with ``pressure``
            and without ``cell_loads`` keeps no per-cell record); None: not tracked.
        blowup: divergence bound (> 0), result code 3: mesh force > blowup·F_s or kinetic
            energy > blowup² · F_s²/2k̄ (k̄ the mean mesh stiffness: of the model for a lumped
            one, of the quasi-static positions at the speed for a hybrid one). Data in the
            compiled run (not a setting of it): runs that differ only in ``blowup`` share one
            program.
    """

    states: bool = False
    cell_loads: bool = False
    pressure: HertzPressure | None = None
    blowup: float = 100.0

    def checked(self, meshes: int) -> Outputs:
        """These outputs checked for a scene of ``meshes`` gear meshes (flags as bools; one-line
        ``ValueError`` naming ``pressure`` or ``blowup`` otherwise)."""
        if isinstance(self.blowup, bool | str) or not self.blowup > 0:
            raise ValueError(f"blowup = {self.blowup!r}: allowed > 0")
        pressure = check_pressure(self.pressure, meshes)
        return Outputs(bool(self.states), bool(self.cell_loads), pressure, self.blowup)


def check_outputs(outputs, meshes: int) -> Outputs:
    """``outputs`` checked to be :class:`Outputs` (:meth:`Outputs.checked`)."""
    if not isinstance(outputs, Outputs):
        raise ValueError(f"outputs = {outputs!r}: allowed jaxgear.dynamics.Outputs(...)")
    return outputs.checked(meshes)


@dataclasses.dataclass(frozen=True)
class Batching:
    """How the speeds of :func:`~jaxgear.dynamics.speed_sweep` are run.

    Attributes:
        chunk_size: split the sweep into chunks of this many speeds (one compilation; the last
            chunk is padded), calling ``progress`` after each (Ctrl-C is honoured between
            chunks; continuation carries the state across them); None: the speeds in one call
            (also under ``jax.jit``: traced speeds are never chunked).
        progress: ``progress(n_done)`` after each chunk (for a progress bar), or None.
        shard: with several local devices, place the independent speeds across them
            (``jax.sharding``: a lumped model's vmap is split, a hybrid model runs one row of
            speeds per device; default). Chunks are padded to whole rows of the devices.
    """

    chunk_size: int | None = None
    progress: Callable[[int], object] | None = None
    shard: bool = True

    def checked(self) -> Batching:
        """Raise ``ValueError`` for a ``chunk_size`` that is not None or an integer >= 1."""
        if self.chunk_size is not None:
            check_integer("chunk_size", self.chunk_size, 1)
        return self


def check_batching(batching) -> Batching:
    """``batching`` checked to be :class:`Batching` (:meth:`Batching.checked`)."""
    if not isinstance(batching, Batching):
        raise ValueError(f"batching = {batching!r}: allowed jaxgear.dynamics.Batching(...)")
    return batching.checked()


class _Config(eqx.Module):
    """The resolved settings of one run: the integrator with its step count fixed, the window,
    whether the states and the cell loads are recorded and the Hertz pressure tracked (or None),
    all static under jit, and the divergence bound ``blowup``, data (a weakly typed scalar
    array: the programs of every bound are one, the comparison rounds as with a Python float)."""

    integrator: Integrator = eqx.field(static=True)
    steps_per_period: int = eqx.field(static=True)
    periods: int = eqx.field(static=True)
    keep_periods: int = eqx.field(static=True)
    max_steps: int = eqx.field(static=True)
    blowup: jax.Array
    states: bool = eqx.field(static=True, default=False)
    cell_loads: bool = eqx.field(static=True, default=False)
    pressure: HertzPressure | None = eqx.field(static=True, default=None)
    #: None, or a run whose N_s is an argument of its compiled program (a sweep over several
    #: automatic N_s; ``steps_per_period`` is then the largest, the record buffer's size): the
    #: smallest N_s of the sweep, the resolution its histories are returned at
    history_steps: int | None = eqx.field(static=True, default=None)

    @property
    def newmark(self) -> bool:
        return isinstance(self.integrator, Newmark)


# automatic time step (``steps_per_period=None``), docs/dynamics.md "Time step and accuracy":
# N_s = the smallest power of two >= max(MIN_STEPS_PER_PERIOD, STEPS_PER_MODE · f_max / f_mesh),
# f_max the highest natural frequency among the modes storing >= MESH_ENERGY_MIN of their strain
# energy in the mesh (the modes the mesh excites), f_mesh = Ω z1 / 2π.
STEPS_PER_MODE = 40
MIN_STEPS_PER_PERIOD = 64
MESH_ENERGY_MIN = 0.05
# a run (automatic or user N_s) is flagged ``under_resolved`` below this many steps per period of
# the highest excited mode
UNDER_RESOLVED_STEPS = 20


def _code(code, new):
    return jnp.where(code == 0, new, code)


def _divergence_code(xd, X, fm, M, fs, e_ref, blowup):
    """The divergence check of a state: 2 (non-finite) or 3 (blow-up: mesh force ``fm`` >
    blowup F_s or kinetic energy ½ ẊᵀMẊ > blowup² ``e_ref``), else 0: :func:`_force_code`
    then :func:`_energy_code`."""
    return _code(_force_code(xd, X, fm, fs, blowup), _energy_code(xd, M, e_ref, blowup))


def _force_code(xd, X, fm, fs, blowup):
    """The step's part of the divergence check (no product with an n × n matrix): 2 where X, Ẋ
    or the mesh force ``fm`` is not finite, 3 where fm > blowup F_s, else 0."""
    finite = jnp.all(jnp.isfinite(X)) & jnp.all(jnp.isfinite(xd)) & jnp.isfinite(fm)
    return jnp.where(~finite, 2, jnp.where(fm > blowup * fs, 3, 0))


def _energy_code(xd, M, e_ref, blowup):
    """The kinetic-energy part of the divergence check (one product with M, n²): 2 where
    ½ ẊᵀMẊ is not finite, 3 where it exceeds blowup² ``e_ref``, else 0."""
    ke = 0.5 * xd @ (M @ xd)  # M Ẋ first: a row-major matrix read by rows
    return jnp.where(jnp.isfinite(ke), jnp.where(ke > blowup**2 * e_ref, 3, 0), 2)


def _config(
    integrator,
    window: SteadyState,
    steps_per_period: int,
    outputs: Outputs = Outputs(),
    *,
    min_keep: int = 2,
    values_per_step: int = 16,
    record_all: bool = False,
    cells: int = 0,
) -> _Config:
    """The settings of a run with the integrator's step count resolved to
    ``steps_per_period``; checks the window (at least ``min_keep`` kept periods: 2 for a
    lumped model, which compares the last two) and the run's size, ``values_per_step`` recorded
    per kept step (per step of the whole run with ``record_all``) (before any work);
    ``outputs``: the records asked for (:class:`Outputs`: with ``cell_loads`` the ``cells``
    cells' loads, coordinates and mask at every kept step too) and the divergence bound."""
    blowup, cell_loads = outputs.blowup, outputs.cell_loads
    check_integer("steps_per_period", steps_per_period, 4)
    if window.keep_periods < min_keep:
        why = " (the lumped dynamics compare the last two periods)" if min_keep == 2 else ""
        raise ValueError(
            f"keep_periods = {window.keep_periods} is out of range: allowed an integer >= "
            f"{min_keep}{why}"
        )
    if isinstance(blowup, bool | str) or not blowup > 0:
        raise ValueError(f"blowup = {blowup!r}: allowed > 0")
    n_total = int(window.periods) * int(steps_per_period)
    # records of the kept steps (a lumped run: TE, mesh force, line forces and bearing
    # reactions, ~16 values)
    check_run_size(
        window.periods,
        steps_per_period,
        int(window.periods if record_all else window.keep_periods) * int(steps_per_period),
        values_per_step,
    )
    if cell_loads:  # line load, s, z and mask of every cell at every kept step
        check_run_size(
            window.periods,
            steps_per_period,
            int(window.keep_periods) * int(steps_per_period),
            values_per_step + 4 * int(cells),
        )
    max_steps = integrator.max_steps
    if max_steps is None:
        max_steps = 64 * n_total + 4096
    return _Config(
        integrator,
        int(steps_per_period),
        int(window.periods),
        int(window.keep_periods),
        int(max_steps),
        jnp.asarray(float(blowup)),  # weakly typed: rounds to the model's dtype as a float
        bool(outputs.states),
        bool(cell_loads),
        outputs.pressure,
    )
