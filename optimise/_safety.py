"""The load-capacity objective: raise the least ISO 6336 safety factor of a pair through its tooth
modifications, under a transmission-error constraint (docs/rating.md, "Optimising the least
safety factor").

The modifications act on the rating in two ways. Through the load map: the face load factor
K_Hβ (:func:`jaxgear.rating.face_load_factor`: a crowning or a helix correction that meets a
misalignment evens the face load) is measured on the quasi-static result and rates the pair in
place of ISO 6336-1's (K_Fβ = K_Hβ^N_F). And through ISO's own modification inputs, as
``jaxgear run`` rates a case file: the design's tip relief is K_v's C_a (B_k: a relief matched
to the tooth deflection lowers K_v) and its crowning K_Hβ's C_β
(:meth:`jaxgear.rating.RatingSettings.with_modifications`). K_Hα and K_Fα are ISO 6336-1's method B,
not the load sharing measured on the load map (:func:`jaxgear.rating.transverse_load_factor`): that
measure rises with any tip relief even on perfect gears (the relieved pair takes less load
where two pairs are in contact, so the other carries more per unit length than the mean,
while no pair ever carries more than the single pair contact that Z_ε, Z_B and Y_F already
rate), so it would remove every relief, against ISO's intent for K_Hα (docs/rating.md). K_A,
K_v and every other factor are the rating's. The objective is 1/S̃ with S̃ the soft minimum of
the four safety factors (S_H and S_F of pinion and gear), plus a quadratic penalty on the TE RMS
above a limit; divided by its unmodified value, it is 1 at the unmodified design and below 1
where the least safety factor is higher.
"""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Float

import jaxgear as jg
import jaxgear.rating as jr

from ._objectives import AbstractQuasiStaticObjective

__all__ = ["LeastSafetyFactor", "soft_min"]


def soft_min(values: Float[Array, " n"], sharpness: float) -> Float[Array, ""]:
    """The soft minimum −log(Σ exp(−κ v))/κ of ``values`` (κ = ``sharpness`` > 0, in 1/units
    of the values): below the minimum by at most log(n)/κ, smooth in every value."""
    return -jax.nn.logsumexp(-sharpness * jnp.asarray(values)) / sharpness


class LeastSafetyFactor(AbstractQuasiStaticObjective):
    """1/soft-min(S_H, S_F of both gears) of the rating with the measured K_Hβ and the design's
    tip relief and crowning as ISO's C_a and C_β, plus ``penalty`` (TE_rms/``te_limit`` − 1)²
    above the TE limit (module docstring).

    Attributes:
        geometry: the pair's :class:`jaxgear.rating.RatingGeometry` (``RatingGeometry.of(pair)``).
        operating: the rating's :class:`jaxgear.rating.OperatingPoint` (its torque is the design
            torque of the problem).
        settings: :class:`jaxgear.rating.RatingSettings`; its given K_Hβ is replaced by the
            measured one, its tip relief and crowning by the design's.
        te_limit: the TE RMS (m) above which the penalty acts, > 0, or None (no constraint).
        sharpness: κ of the soft minimum (default 50: within log(4)/50 = 0.028 of the least S).
        penalty: the weight of the squared relative excess of TE RMS (default 100).

    Raises:
        ValueError: ``te_limit`` <= 0, ``sharpness`` or ``penalty`` <= 0.
    """

    geometry: jr.RatingGeometry
    operating: jr.OperatingPoint
    settings: jr.RatingSettings
    te_limit: float | None = eqx.field(default=None, static=True)
    sharpness: float = eqx.field(default=50.0, static=True)
    penalty: float = eqx.field(default=100.0, static=True)

    name: ClassVar[str] = "least_safety"
    units: ClassVar[str] = "inverse_S"

    def __check_init__(self):
        for key in ("sharpness", "penalty"):
            v = getattr(self, key)
            if not float(v) > 0:
                raise ValueError(f"LeastSafetyFactor: {key} = {v!r}: allowed > 0")
        if self.te_limit is not None and not float(self.te_limit) > 0:
            raise ValueError(f"LeastSafetyFactor: te_limit = {self.te_limit!r} m: allowed > 0")

    def rating(
        self, result: jg.QuasiStaticResult, modifications: jg.Modifications | None = None
    ) -> jr.Rating:
        """The rating of a design: K_Hβ (and K_Fβ = K_Hβ^N_F) measured on ``result``, K_Hα and
        K_Fα ISO 6336-1's method B (given ones kept), ISO's tip relief C_a and crowning C_β
        those of ``modifications`` (the design's; None: the settings' own)."""
        old = self.settings.given
        given = jr.GivenFactors(
            K_v=old.K_v,
            K_Hbeta=jg.rating.face_load_factor(result),
            K_Fbeta=old.K_Fbeta,
            K_Halpha=old.K_Halpha,
            K_Falpha=old.K_Falpha,
        )
        settings = eqx.tree_at(lambda s: s.given, self.settings, given)
        if modifications is not None:
            settings = settings.with_modifications(modifications)
        return jr.rate(self.geometry, self.operating, settings)

    def safety_factors(
        self, result: jg.QuasiStaticResult, modifications: jg.Modifications | None = None
    ) -> Float[Array, " 4"]:
        """(S_H pinion, S_H gear, S_F pinion, S_F gear) of :meth:`rating`."""
        r = self.rating(result, modifications)
        return jnp.concatenate([r.pitting.S_H, r.bending.S_F])

    def scale(self, unmodified, torque):
        """1/S̃ of the unmodified design (no modification: C_a the running-in C_ay; no
        penalty: an unmodified design's TE may be far above the limit that the modifications
        are to keep)."""
        s = self.safety_factors(unmodified, jg.Modifications())
        return float(1.0 / soft_min(s, self.sharpness))

    def at_torque(self, problem, mods, torque, contact):
        """The objective of design ``mods`` at ``torque``: its quasi-static result rated with
        the design's own tip relief and crowning (:meth:`rating`)."""
        return self._value(self.solve(problem, mods, torque, contact), mods)

    def of_result(self, result, problem):
        """The objective of ``result`` rated with the settings' own tip relief and crowning
        (:meth:`at_torque` rates a design with its own)."""
        return self._value(result, None)

    def _value(self, result, modifications):
        value = 1.0 / soft_min(self.safety_factors(result, modifications), self.sharpness)
        if self.te_limit is None:
            return value
        excess = jax.nn.relu(result.te_rms / self.te_limit - 1.0)
        return value + self.penalty * excess**2
