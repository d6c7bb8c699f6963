"""Objectives and statistics of tooth-modification optimisation, as classes passed as objects
(docs/design.md, "Optimisation").

An objective is an :class:`AbstractObjective`: it says how the unscaled objective is computed at
one torque for given modifications (:meth:`AbstractObjective.at_torque`), its scale (the
unmodified design's value, :meth:`AbstractObjective.scale`), the torques it is evaluated at and
how their values are reduced to one number. The quasi-static objectives
(:class:`AbstractQuasiStaticObjective`) read one :class:`jaxgear.QuasiStaticResult`
(:meth:`AbstractQuasiStaticObjective.of_result`); :class:`DynamicFactor` runs the hybrid Newmark
over a speed band. A new objective is one new subclass here; its case-file name goes into
:mod:`jaxgear.io` (``jaxgear/io/_problem.py``), the one place that maps names to objects.

A statistic (:class:`AbstractStatistic`: :class:`Mean`, :class:`Max`, :class:`Quantile`) reduces
values over torques (:class:`RobustTeRms`) or over deviation realisations
(:func:`optimise.robust_problem`) to one number.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

import jaxgear as jg
from jaxgear.dynamics import Newmark, SteadyState, band_dynamic_factor, dynamic_model
from jaxgear.scenes import HybridPair, cache_window_compliance

__all__ = [
    "CENTROID_SCALE",
    "AbstractObjective",
    "AbstractQuasiStaticObjective",
    "AbstractStatistic",
    "DynamicFactor",
    "LineLoadLp",
    "LoadCentroid",
    "Max",
    "MaxLineLoad",
    "Mean",
    "Quantile",
    "RobustTeRms",
    "TePeakToPeak",
    "TeRms",
    "line_load_lp",
    "load_centroid",
]

# the load_centroid objective is c²/CENTROID_SCALE = (c / 0.1)²: 1 for a centroid 10 % of the
# face width off centre (the unmodified pair is often centred, c = 0: no scale to take from it)
CENTROID_SCALE = 0.01
LP_ORDER_RANGE = (1.0, 64.0)
MAX_SPEED = 1e5  # rad/s, the top of a dynamic_factor speed band


# -- statistics ----------------------------------------------------------------------------------
class AbstractStatistic(eqx.Module):
    """Reduces values (over torques, over deviation realisations) to one number."""

    @abc.abstractmethod
    def __call__(self, values: Float[Array, " N"]) -> Float[Array, ""]:
        """The statistic of ``values``, shape (N,), in their units."""


class Mean(AbstractStatistic):
    """The mean (an expected value over realisations, the mean over torques)."""

    def __call__(self, values):
        return jnp.mean(values)


class Max(AbstractStatistic):
    """The maximum (the worst case)."""

    def __call__(self, values):
        return jnp.max(values)


class Quantile(AbstractStatistic):
    """The quantile of level ``level`` in (0, 1) (``jnp.quantile``, linear interpolation;
    differentiable almost everywhere), e.g. ``Quantile(0.9)``.

    Raises:
        ValueError: a level outside (0, 1) or not a number.
    """

    level: float = eqx.field(static=True)

    def __check_init__(self):
        v = self.level
        if isinstance(v, bool) or not isinstance(v, float | int) or not 0 < v < 1:
            raise ValueError(f"Quantile level = {v!r} is out of range: allowed a number in (0, 1)")

    def __call__(self, values):
        return jnp.quantile(values, self.level)


# -- objectives -----------------------------------------------------------------------------------
def load_centroid(res: jg.QuasiStaticResult, face_width) -> Float[Array, ""]:
    """Load centroid across the face over the mesh positions, as a fraction of the face width.

    c = (z̄ − b/2)/b with z̄ = Σ q z / Σ q, the sums over every cell on the flanks at every
    position of ``res`` (q the line load, N/m; the cells have equal lengths, so q weights like
    the cell force). z is the base-plane face coordinate (docs/design.md, "Base plane and sign
    conventions"), z ∈ [0, b]: c > 0 means
    the load sits towards the z = b edge, c < 0 towards the z = 0 edge, c = 0 centred; |c| <= 1/2.
    On the hybrid scenes the body's axial coordinate is z − b/2 (for the power wheel
    ``power-helical-wheel`` the web meets the rim at z = 8 mm and z = b is the cantilevered edge).

    Args:
        res: a quasi-static result (any scene; exact or smooth contact).
        face_width: b (m).

    Returns:
        c, dimensionless, differentiable in the modifications (smooth contact everywhere, exact
        contact away from changes of the contact set).
    """
    q = jnp.where(res.cell_mask, res.line_load, 0.0)
    zbar = jnp.sum(q * res.cell_z) / jnp.sum(q)
    return zbar / face_width - 0.5


def line_load_lp(res: jg.QuasiStaticResult, p=8.0) -> Float[Array, ""]:
    """L_p norm of the line load over the load map (N/m): a smooth surrogate of its maximum.

    ‖q‖_p = (mean over the flank cells and positions of q^p)^(1/p), the mean taken over every
    cell on the flanks at every position of ``res`` (loaded or not; a count fixed by the
    geometry). It rises towards ``max q`` as p grows (‖q‖_p <= max q, and ‖q‖_∞ = max q) and,
    unlike the maximum, has a gradient that sees every loaded cell.

    Args:
        res: a quasi-static result.
        p: the order, >= 1 (default 8).

    Returns:
        ‖q‖_p in N/m.
    """
    q = jnp.maximum(jnp.where(res.cell_mask, res.line_load, 0.0), 0.0)
    ref = jax.lax.stop_gradient(jnp.max(q))  # ‖q‖_p is 1-homogeneous: no gradient is lost
    ref = jnp.where(ref > 0, ref, 1.0)
    n = jnp.sum(res.cell_mask)
    return ref * (jnp.sum((q / ref) ** p) / n) ** (1.0 / p)


class AbstractObjective(eqx.Module):
    """An objective of :class:`optimise.Problem`: its unscaled value at one torque, its scale,
    its torques and their reduction.

    Class attributes:
        name: the objective's name in case files and reports (``[optimise] objective``).
        units: the unit of the unscaled objective, as used in report keys ("m", "N_per_m", ...).
        designs_structure: whether a variable that acts on the structure (a bearing's
            clearance) may change the structure it runs on (:meth:`with_structure`).
    """

    name: ClassVar[str]
    units: ClassVar[str]
    designs_structure: ClassVar[bool] = True

    @abc.abstractmethod
    def at_torque(
        self, problem, mods: jg.Modifications, torque, contact: jg.ContactLaw
    ) -> Float[Array, ""]:
        """The unscaled objective (``units``) of ``mods`` at ``torque`` (N·m) in the law
        ``contact``, on the structure and settings of ``problem`` (the
        :class:`optimise.Problem` that evaluates it: its ``mesh``, ``speed``,
        ``positions_per_pitch``, ``face_width``)."""

    @abc.abstractmethod
    def scale(self, unmodified: jg.QuasiStaticResult, torque) -> float:
        """The value the objective is divided by (``units``): the unmodified design's value at
        the design torque ``torque`` (N·m; exact contact), ``unmodified``, for most
        objectives."""

    @abc.abstractmethod
    def prepare(self, scene, positions_per_pitch: int):
        """The structure the evaluations run on, prepared once for every iteration.

        Raises:
            ValueError: a structure this objective cannot be evaluated on.
        """

    def with_structure(self, change) -> AbstractObjective:
        """The objective on the structure ``change(scene)`` makes of its own: itself, for an
        objective that runs on the problem's ``mesh`` (which :meth:`optimise.Problem.at_design`
        changes); an objective that holds its own structure replaces it."""
        return self

    def default_contact(self, width) -> jg.SmoothContact:
        """The smooth law of the objective and its gradients when none is given: width ``width``
        (m), 100 Newton steps."""
        return jg.SmoothContact(width, 100)

    def torques(self, design_torque: float) -> np.ndarray:
        """The torques (N·m) the objective is evaluated at, (T,): the design torque."""
        return np.array([float(design_torque)])

    def reduce(self, values: Float[Array, " T"]) -> Float[Array, ""]:
        """The values at :meth:`torques` reduced to one: the value (the maximum of one)."""
        return jnp.max(values)

    def metric_order(self) -> float:
        """p of the ``line_load_lp`` metric reported beside the objective: 8."""
        return 8.0


class AbstractQuasiStaticObjective(AbstractObjective):
    """An objective read from the quasi-static solution at the torque
    (:func:`jaxgear.quasi_static` on the problem's structure, at its speed and positions per
    pitch): :meth:`of_result`."""

    @abc.abstractmethod
    def of_result(self, result: jg.QuasiStaticResult, problem) -> Float[Array, ""]:
        """The unscaled objective of one quasi-static result (``units``); ``problem`` the
        :class:`optimise.Problem` (None for the unmodified design's scale)."""

    def at_torque(self, problem, mods, torque, contact):
        return self.of_result(self.solve(problem, mods, torque, contact), problem)

    @staticmethod
    def solve(problem, mods, torque, contact) -> jg.QuasiStaticResult:
        """The quasi-static solve of design ``mods`` at ``torque`` on ``problem``'s mesh, speed
        and positions (what :meth:`at_torque` rates)."""
        return jg.quasi_static(
            problem.mesh,
            mods,
            torque,
            speed=problem.speed,
            contact=contact,
            positions_per_pitch=problem.positions_per_pitch,
        )

    def scale(self, unmodified, torque):
        return float(self.of_result(unmodified, None))

    def prepare(self, scene, positions_per_pitch):
        """The scene with its window compliance cached (a hybrid scene's, once for every
        iteration: :func:`jaxgear.scenes.cache_window_compliance`)."""
        return cache_window_compliance(scene, positions_per_pitch=positions_per_pitch)


class TeRms(AbstractQuasiStaticObjective):
    """TE RMS (m) over the mesh positions at the design torque."""

    name: ClassVar[str] = "te_rms"
    units: ClassVar[str] = "m"

    def of_result(self, result, problem):
        return result.te_rms


class TePeakToPeak(AbstractQuasiStaticObjective):
    """TE peak-to-peak (m) over the mesh positions at the design torque."""

    name: ClassVar[str] = "te_ptp"
    units: ClassVar[str] = "m"

    def of_result(self, result, problem):
        return result.te_ptp


def _torque_range(t) -> Float[Array, " T"]:
    return jnp.asarray(np.asarray(t, dtype=float).reshape(-1))


class RobustTeRms(AbstractQuasiStaticObjective):
    """TE RMS (m) at each of ``torques`` (N·m, (T,), vmapped) reduced by ``statistic``
    (default :class:`Max`, the worst case; :class:`Mean` the mean): a design for a load range.

    Raises:
        ValueError: an empty torque range, a torque <= 0, a statistic that is not one.
    """

    torques_Nm: Float[Array, " T"] = eqx.field(converter=_torque_range)
    statistic: AbstractStatistic = eqx.field(default_factory=Max)

    name: ClassVar[str] = "robust_te_rms"
    units: ClassVar[str] = "m"

    def __check_init__(self):
        t = np.asarray(self.torques_Nm)
        if t.size == 0:
            raise ValueError("torques is empty: give at least one torque (N·m)")
        if np.any(t <= 0):
            raise ValueError(f"torques = {t.tolist()} N·m: allowed > 0 N·m only")
        if not isinstance(self.statistic, AbstractStatistic):
            raise ValueError(
                f"statistic = {self.statistic!r}: allowed optimise.Max(), Mean() or Quantile(q)"
            )

    def of_result(self, result, problem):
        return result.te_rms

    def torques(self, design_torque):
        return np.asarray(self.torques_Nm)

    def reduce(self, values):
        return self.statistic(values)


class MaxLineLoad(AbstractQuasiStaticObjective):
    """The maximum line load (N/m) over the load map at the design torque."""

    name: ClassVar[str] = "max_line_load"
    units: ClassVar[str] = "N_per_m"

    def of_result(self, result, problem):
        return result.max_line_load


class LoadCentroid(AbstractQuasiStaticObjective):
    """The square c² of the load centroid's offset from mid-face (:func:`load_centroid`; 0 =
    centred load), scaled by ``CENTROID_SCALE`` = 0.01: (c/0.1)², 1 for a centroid 10 % of the
    face width off centre (the unmodified pair, the scale of the other objectives, is often
    centred)."""

    name: ClassVar[str] = "load_centroid"
    units: ClassVar[str] = "face_fraction_squared"

    def of_result(self, result, problem):
        return load_centroid(result, problem.face_width) ** 2

    def scale(self, unmodified, torque):
        return CENTROID_SCALE


class LineLoadLp(AbstractQuasiStaticObjective):
    """The L_p norm of the line load over the load map (N/m, :func:`line_load_lp`), a smooth
    surrogate of its maximum, of order ``order`` in [1, 64] (default 8).

    Raises:
        ValueError: an order outside [1, 64].
    """

    order: Float[Array, ""] = eqx.field(default=8.0, converter=lambda p: jnp.asarray(float(p)))

    name: ClassVar[str] = "line_load_lp"
    units: ClassVar[str] = "N_per_m"

    def __check_init__(self):
        p = float(self.order)
        if not LP_ORDER_RANGE[0] <= p <= LP_ORDER_RANGE[1]:
            raise ValueError(
                f"lp_order = {p:g}: out of range, allowed [{LP_ORDER_RANGE[0]:g}, "
                f"{LP_ORDER_RANGE[1]:g}]"
            )

    def of_result(self, result, problem):
        return line_load_lp(result, self.order)

    def scale(self, unmodified, torque):
        return float(line_load_lp(unmodified, float(self.order)))

    def metric_order(self):
        """The objective's own order."""
        return float(self.order)


def _newmark_default() -> Newmark:
    return Newmark(32)


def _window_default() -> SteadyState:
    return SteadyState(20, 4)


class DynamicFactor(AbstractObjective):
    """The smooth dynamic factor over a speed band (:func:`jaxgear.dynamics.band_dynamic_factor`:
    the hybrid Newmark at each of ``speeds``, centrifugal loads included, p-means; the seed's
    Rayleigh damping D1). Needs a scene with condensed bodies
    (:class:`jaxgear.scenes.HybridPair`). Not scaled (a dynamic factor is already relative to
    the static mesh force).

    Attributes:
        speeds: pinion speeds of the band (rad/s), (S,), in (0, 1e5].
        integrator: the Newmark (``steps_per_period`` given; default ``Newmark(32)``).
        window: the steady-state window (default ``SteadyState(20, 4)``).

    Raises:
        ValueError: an empty band or a speed outside (0, 1e5] rad/s, an integrator that is not
            ``Newmark(steps_per_period=N)``, a window that is not a ``SteadyState``.
    """

    speeds: Float[Array, " S"] = eqx.field(converter=_torque_range)
    integrator: Newmark = eqx.field(default_factory=_newmark_default)
    window: SteadyState = eqx.field(default_factory=_window_default)

    name: ClassVar[str] = "dynamic_factor"
    units: ClassVar[str] = "dimensionless"
    # its model's modes and damping are built from the scene (NumPy) at every evaluation, on a
    # hybrid scene (whose shafts take no rolling bearings from their geometry)
    designs_structure: ClassVar[bool] = False

    def __check_init__(self):
        s = np.asarray(self.speeds)
        if s.size == 0 or np.any(~(s > 0)) or np.any(s > MAX_SPEED):
            raise ValueError(
                f"speeds = {s.tolist()} rad/s: the dynamic_factor band needs pinion speeds in "
                f"(0, {MAX_SPEED:.0e}] rad/s"
            )
        if not isinstance(self.window, SteadyState):
            raise ValueError(f"window = {self.window!r}: allowed a jaxgear.dynamics.SteadyState")
        if not isinstance(self.integrator, Newmark) or self.integrator.steps_per_period is None:
            raise ValueError(
                f"integrator = {self.integrator!r}: the dynamic_factor objective takes "
                "Newmark(steps_per_period=N)"
            )

    def at_torque(self, problem, mods, torque, contact):
        return band_dynamic_factor(
            dynamic_model(problem.mesh, mods, torque),
            self.speeds,
            integrator=self.integrator,
            contact=contact,
            window=self.window,
        )

    def scale(self, unmodified, torque):
        return 1.0

    def prepare(self, scene, positions_per_pitch):
        if not isinstance(scene, HybridPair):
            raise ValueError(
                "objective = 'dynamic_factor' needs a scene with condensed bodies (a "
                "jaxgear.scenes.HybridPair): the hybrid Newmark runs over the speed band"
            )
        return scene

    def default_contact(self, width):
        """50 Newton steps (the hybrid dynamics' cap)."""
        return jg.SmoothContact(width, 50)
