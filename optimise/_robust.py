"""Robust tooth-modification design against sampled manufacturing deviations (docs/robust.md,
"Robust optimisation").

The objective is a statistic (the mean, or a quantile) over N fixed deviation realisations
(common random numbers: drawn once from a :class:`jaxgear.DeviationSampler`, so the objective is
a deterministic, differentiable function of the design) of each realisation's quasi-static TE
RMS over a span of whole pinion revolutions, in the problem's smooth contact law; its gradient
goes through every realisation (``jax.vmap`` of the quasi-static solve). Solve it with
:func:`optimise.minimise` like any :class:`Problem`.
"""

from __future__ import annotations

import math

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

import jaxgear as jg

from ._objectives import AbstractStatistic, Mean, TeRms
from ._problem import Problem, base_plane

__all__ = ["RobustProblem", "robust_problem"]


class RobustProblem(eqx.Module):
    """A :class:`Problem` (its variables, bounds, torque and smooth law) whose objective is a
    statistic of the TE RMS over deviation realisations. Build with :func:`robust_problem`.

    Attributes:
        problem: the deterministic problem (:class:`TeRms` objective) whose variables, bounds,
            design torque and contact law are used.
        deviations: the N realisations, a :class:`jaxgear.Deviations` whose arrays have a
            leading axis (N, ...).
        theta: pinion angles of the span (rad), (P,).
        scale: the statistic at the problem's starting modifications (``problem.base``, exact
            contact) (m): the objective is 1 there.
        statistic: the statistic over the realisations (:class:`Mean`, :class:`Quantile`, ...).
    """

    problem: Problem
    deviations: jg.Deviations
    theta: Float[Array, " P"]
    scale: Float[Array, ""]
    statistic: AbstractStatistic

    # the optimiser's interface (optimise.minimise), forwarded to the problem
    @property
    def lower(self):
        return self.problem.lower

    @property
    def upper(self):
        return self.problem.upper

    @property
    def names(self):
        return self.problem.names

    def bounded(self, u):
        return self.problem.bounded(u)

    def unbounded(self, x):
        return self.problem.unbounded(x)

    def to_physical(self, x) -> dict:
        return self.problem.to_physical(x)

    def modifications(self, x) -> jg.Modifications:
        return self.problem.modifications(x)

    def te_rms(
        self, x: Float[Array, " n"], contact: jg.ContactLaw | None = None
    ) -> Float[Array, " N"]:
        """Each realisation's TE RMS (m) over the span at design ``x``, shape (N,), in
        ``contact`` (default: the problem's smooth law; :class:`jaxgear.ExactContact` for the
        design as the exact law sees it)."""
        mods, law = self.problem.modifications(x), self.problem._law(contact)
        return _te_rms(self.problem.at_design(x), self.deviations, self.theta, mods, law)

    def reduce(self, values: Float[Array, " N"]) -> Float[Array, ""]:
        """The statistic of ``values``."""
        return self.statistic(values)

    def value(self, x: Float[Array, " n"], contact: jg.ContactLaw | None = None):
        """The scaled objective: the statistic of the realisations' TE RMS / its value at the
        unmodified design."""
        return self.reduce(self.te_rms(x, contact)) / self.scale


def _te_rms(p: Problem, deviations, theta, mods, law) -> Float[Array, " N"]:
    """Each realisation's TE RMS (m) over the span ``theta`` for modifications ``mods``."""

    def one(dev):
        m = jg.Modifications(mods.pinion, mods.gear, deviations=dev)
        r = jg.quasi_static(
            p.mesh, m, p.design_torque, theta, speed=p.speed, contact=law, throw=False
        )
        return r.te_rms

    return jax.vmap(one)(deviations)


def robust_problem(
    problem: Problem,
    sampler: jg.DeviationSampler,
    key,
    samples: int,
    *,
    revolutions: int = 1,
    positions_per_pitch: int = 8,
    statistic: AbstractStatistic = Mean(),
) -> RobustProblem:
    """The robust version of ``problem`` (a :class:`Problem` with the :class:`TeRms` objective on a
    mesh or scene of one gear pair): realisation i of the deviations is
    ``sampler(jax.random.fold_in(key, i))``, i < ``samples``, fixed for the whole optimisation.

    Args:
        problem: from :func:`optimise.make_problem` with the :class:`TeRms` objective.
        sampler: a :class:`jaxgear.DeviationSampler`. key: a ``jax.random`` key.
        samples: N >= 1.
        revolutions: pinion revolutions of the span (>= 1).
        positions_per_pitch: positions per mesh period over the span (>= 2).
        statistic: :class:`Mean` (expected TE RMS, the default) or a :class:`Quantile` (e.g.
            ``Quantile(0.9)``), any :class:`AbstractStatistic`.

    Raises:
        ValueError: a problem whose objective is not te_rms, samples, revolutions or
            positions_per_pitch out of range, an unknown statistic (one line each).
    """
    if not isinstance(problem.objective, TeRms):
        raise ValueError(
            f"problem objective = {problem.objective.name!r}: allowed 'te_rms' (the statistic is "
            "taken over the realisations' TE RMS)"
        )
    for name, v, lo in (
        ("samples", samples, 1),
        ("revolutions", revolutions, 1),
        ("positions_per_pitch", positions_per_pitch, 2),
    ):
        if isinstance(v, bool) or not isinstance(v, int) or v < lo:
            raise ValueError(f"{name} = {v!r} is out of range: allowed an integer >= {lo}")
    if not isinstance(statistic, AbstractStatistic):
        raise ValueError(
            f"statistic = {statistic!r} is out of range: allowed optimise.Mean() or "
            "optimise.Quantile(q) with q in (0, 1)"
        )
    plane = base_plane(problem.mesh)
    z1 = round(2 * math.pi * float(plane.base_radius_pinion) / float(plane.base_pitch))
    theta = jg.mesh_positions(plane, positions_per_pitch, revolutions * z1)
    keys = jax.vmap(lambda i: jax.random.fold_in(key, i))(jnp.arange(samples))
    deviations = jax.vmap(sampler)(keys)
    scale = statistic(_te_rms(problem, deviations, theta, problem.base, jg.ExactContact()))
    return RobustProblem(problem, deviations, theta, scale, statistic)
