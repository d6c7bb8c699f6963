"""The kinds of gear whine method (:func:`jaxgear.dynamics.whine_response`; docs/whine.md): how
the harmonic balance couples the harmonics of the response. Each dynamic model kind names the
methods it solves in its ``whine_methods`` (:class:`~jaxgear.dynamics.AbstractDynamicModel`),
so that a method a kind does not take is refused before any work."""

from __future__ import annotations

from typing import ClassVar

import equinox as eqx
import numpy as np

from .._util import check_integer, is_traced

__all__ = [
    "AbstractWhineMethod",
    "HarmonicBalance",
    "QuasiPeriodicBalance",
    "TransmissionErrorSource",
    "check_whine_speeds",
]


def check_whine_speeds(speeds, member: str = "pinion") -> None:
    """Raise ``ValueError`` (one line, before any work) unless ``speeds`` is a scalar or (S,) of
    finite speeds > 0 rad/s of ``member`` (the word the message names: "pinion", "input");
    traced speeds (under jit or grad) are checked for their shape only."""
    if np.ndim(speeds) > 1 or np.size(speeds) == 0:
        raise ValueError(
            f"speeds = {speeds!r}: allowed {member} speeds > 0 rad/s, scalar or (S,)"
        )
    if not is_traced(speeds):
        sp = np.asarray(speeds, dtype=float)
        if not np.all(np.isfinite(sp)) or np.any(sp <= 0):
            raise ValueError(f"speeds = {speeds!r}: allowed finite {member} speeds > 0 rad/s")


class AbstractWhineMethod(eqx.Module):
    """How :func:`whine_response` couples the harmonics of the response: a kind passed as an
    object. ``harmonics``: H, the harmonics of the span's fundamental kept (h = −H..H; an int
    >= 1, static)."""

    harmonics: eqx.AbstractVar[int]
    #: whether the stiffness harmonics K̂_{h≠0} couple the response harmonics
    parametric: ClassVar[bool]

    def __check_init__(self):
        check_integer("harmonics", self.harmonics, 1)


class HarmonicBalance(AbstractWhineMethod):
    """The multi-harmonic method: every stiffness harmonic K̂_{h−j}, |h−j| <= 2H, couples
    response harmonic j into h (the parametric excitation: sidebands, the coupling of the mesh
    orders, parametric resonances). One complex linear system of (2H+1) n unknowns per speed.
    Exact for the linear periodic system as H grows (the only truncation)."""

    harmonics: int = eqx.field(static=True, default=16)
    parametric: ClassVar[bool] = True


class QuasiPeriodicBalance(AbstractWhineMethod):
    """The quasi-periodic multi-harmonic method, for a model whose meshes run at G > 1 distinct
    mesh frequencies ω_1..ω_G (a two-stage train; docs/whine.md, "Trains of several mesh
    frequencies"): the quasi-static solution and the tangent mesh stiffness sampled on the torus
    of the G mesh phases, and the response balanced over the multi-index harmonics h = (h_1..h_G)
    at the frequencies Σ_g h_g ω_g with, for one group g, |h_g| <= ``harmonics`` (its own
    orders, coupled parametrically) and every other group's |h_g'| <= ``sidebands`` (the
    sidebands h_g ω_g ± h_g' ω_g'). It neglects the combination tones with more than
    ``sidebands`` orders of two groups at once (e.g. 2 ω_1 + 2 ω_2 at sidebands 1) and every
    harmonic beyond ``harmonics``. With G = 1 the set is |h| <= H and the method is
    :class:`HarmonicBalance` over one mesh period.

    Args:
        harmonics: H, each group's own orders kept (int >= 1, static).
        sidebands: S, the orders of the other groups around them (int, 0 <= S <= H, static).
    """

    harmonics: int = eqx.field(static=True, default=10)
    sidebands: int = eqx.field(static=True, default=1)
    parametric: ClassVar[bool] = True

    def __check_init__(self):
        check_integer("sidebands", self.sidebands, 0)
        if self.sidebands > self.harmonics:
            raise ValueError(
                f"sidebands = {self.sidebands}: allowed 0 <= sidebands <= harmonics = "
                f"{self.harmonics}"
            )


class TransmissionErrorSource(AbstractWhineMethod):
    """The time-invariant model: the mean stiffness K_s + K̂_0 excited by the quasi-static
    motion x_qs(θ) (whose mesh component is the loaded static TE); each harmonic solved alone,
    (K_s + K̂_0 − (hω)² M + i hω C) Y_h = ((hω)² M − i hω C) X̂_h. It neglects the modulation
    of the dynamic part by the varying stiffness (docs/whine.md)."""

    harmonics: int = eqx.field(static=True, default=16)
    parametric: ClassVar[bool] = False
