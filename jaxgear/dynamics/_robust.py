"""Monte Carlo over deviation realisations at speed (docs/robust.md, "Dynamics with
deviations"): :class:`DynamicMetrics`, the problem :func:`jaxgear.robust_samples` maps over
realisations, giving the dynamic factor and the dynamic TE RMS per speed."""

from __future__ import annotations

import equinox as eqx
from jaxtyping import Array, Float, Int

from .._contact import ContactLaw, ExactContact
from .._deviations import Deviations
from .._modifications import Modifications
from ._settings import Batching
from ._sweep import speed_sweep

__all__ = ["DynamicMetrics", "DynamicRobustMetrics"]


class DynamicRobustMetrics(eqx.Module):
    """What one realisation gives at each speed of :class:`DynamicMetrics` (shape (S,); with a
    leading sample axis (N, S) from :func:`robust_samples`).

    Attributes:
        dynamic_factor: max dynamic mesh force / static mesh force over the kept span (-).
        te_rms: RMS of the dynamic TE about its mean over the kept span (m).
        result: :class:`~jaxgear.DynamicsResult` code per speed (0: converged).
    """

    dynamic_factor: Float[Array, "*N S"]
    te_rms: Float[Array, "*N S"]
    result: Int[Array, "*N S"]


class DynamicMetrics(eqx.Module):
    """The dynamic problem a realisation is evaluated on: ``model`` (a lumped
    :class:`~jaxgear.dynamics.DynamicModel`, its damping built once for the nominal gears) with
    the realisation's deviations on its modifications, run at each of ``speeds`` by
    :func:`~jaxgear.dynamics.speed_sweep` (independent speeds) over the deviations' span
    (:func:`~jaxgear.dynamics.span_periods`: the model's ``revolutions``, else the hunting period
    of the deviating gears; the window's ``keep_periods`` must cover it).

    Attributes:
        model: the lumped dynamic model (nominal modifications; its own deviations replaced).
        speeds: pinion speeds (rad/s), (S,). integrator: a
            :class:`~jaxgear.dynamics.Newmark` with a fixed ``steps_per_period`` (the same
            compiled program for every realisation). window: the
            :class:`~jaxgear.dynamics.SteadyState`. contact: the contact law.
    """

    model: eqx.Module
    speeds: Float[Array, " S"]
    integrator: eqx.Module
    window: eqx.Module
    contact: ContactLaw = ExactContact()

    def __call__(self, deviations: Deviations) -> DynamicRobustMetrics:
        mods = self.model.mods
        mods = Modifications(mods.pinion, mods.gear, deviations=deviations)
        model = eqx.tree_at(lambda m: m.mods, self.model, mods)
        r = speed_sweep(
            model,
            self.speeds,
            integrator=self.integrator,
            contact=self.contact,
            window=self.window,
            batching=Batching(shard=False),
            throw=False,
        ).results
        return DynamicRobustMetrics(
            dynamic_factor=r.dynamic_factor, te_rms=r.te_rms, result=r.result
        )
