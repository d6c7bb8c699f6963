"""Tooth modifications and deviations, differentiable in their parameters (docs/design.md,
"Modifications, initial separation and TE").

Sign convention: a deviation ``e`` is normal to the flank, in metres, positive where material is
*added* (seed II-13). Reliefs and crowning remove material, so their depths (>= 0) enter with a
minus sign. The pair's deviation at a cell is the sum of the pinion's and the gear's.

Profile coordinate of a member: the roll fraction u ∈ [0, 1] along its *active* profile, 0 at its
start of active profile and 1 at its tip. With the base-plane coordinate s ∈ [0, g_α]
(docs/design.md, "Base plane and sign conventions"; s = 0: engagement at the gear tip), the
pinion has u = s/g_α and the gear u = 1 − s/g_α. Tip relief of extent Γ acts on u > 1 − Γ, root
relief on u < Γ, where Γ is the relief length along the line of action over g_α = ε_α p_bt (seed
(3.1)).

Lead coordinate: ζ = z/b ∈ [0, 1] across the effective face width.
"""

from __future__ import annotations

import abc
from typing import ClassVar

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from ._deviations import Deviations
from ._util import NamedKind, as_float, check_instance, check_real, is_traced

__all__ = [
    "AbstractEndReliefEdges",
    "AbstractReliefShape",
    "BothEdges",
    "EdgeZ0",
    "EdgeZ1",
    "LinearRelief",
    "MemberModification",
    "Modifications",
    "ParabolicRelief",
]

# the documented range of each parameter (name: unit, lo, hi, lo_open): checked on concrete
# values when a MemberModification is built (traced ones, under jit/vmap/grad, are not known)
_RANGES = {
    "tip_relief_depth": ("m", 0.0, None, False),
    "tip_relief_extent": ("", 0.0, 1.0, True),
    "root_relief_depth": ("m", 0.0, None, False),
    "root_relief_extent": ("", 0.0, 1.0, True),
    "crowning_depth": ("m", 0.0, None, False),
    "end_relief_depth": ("m", 0.0, None, False),
    "end_relief_extent": ("", 0.0, 0.5, True),
    "helix_slope_deviation": ("m", None, None, False),
    "relief_blend": ("", 0.0, None, False),
    "end_relief_blend": ("", 0.0, None, False),
    "profile_deviation_roll": ("", None, None, False),
    "profile_deviation": ("m", None, None, False),
}


def _clamp(x, blend):
    """x ∈ ℝ clamped to [0, 1]; ``blend`` > 0 rounds the lower kink (x = 0) with a softplus of
    that width in x units, so the deviation of a fixed point is smooth in the relief parameters;
    0 keeps the sharp kink."""
    if jnp.ndim(blend) == 0:  # one width: only the branch taken runs (a softplus at every
        # cell costs an exp and a log1p each, most of a relief's time; a batched width, under
        # vmap, becomes the select below)
        x = jax.lax.cond(blend > 0, _softplus_clamp, _sharp_clamp, x, blend)
    else:
        x = jnp.where(blend > 0, _softplus_clamp(x, blend), _sharp_clamp(x, blend))
    return jnp.minimum(x, 1.0)


def _softplus_clamp(x, blend):
    safe = jnp.where(blend > 0, blend, 1.0)
    return safe * jax.nn.softplus(x / safe)


def _sharp_clamp(x, blend):
    return jnp.maximum(x, 0.0)


def _end_ramp(x, blend):
    """Linear end relief ramp on x ∈ ℝ: 0 below 0, x, 1 above 1.

    ``blend`` > 0 rounds the kink at the relief start (x = 0) with the parabola
    (x + blend/2)²/(2 blend) on |x| <= blend/2 (C¹; unchanged outside that band, at most blend/8
    above the sharp ramp); 0 keeps the sharp kink.
    """
    h = 0.5 * blend
    safe = jnp.where(blend > 0, blend, 1.0)
    rounded = jnp.where(x < -h, 0.0, jnp.where(x > h, x, (x + h) ** 2 / (2.0 * safe)))
    return jnp.minimum(jnp.where(blend > 0, rounded, jnp.maximum(x, 0.0)), 1.0)


class AbstractReliefShape(NamedKind):
    """The shape of a tip or root relief along the roll fraction (seed II-13; docs/design.md,
    "Modifications, initial separation and TE"): the relief depth times :meth:`ramp` of the
    normalised coordinate x ∈ [0, 1] (0 at the relief start, 1 at the tip or at the start of
    active profile). A new shape is one subclass with its :meth:`shape` (and its case-file name
    in :mod:`jaxgear.io`)."""

    @abc.abstractmethod
    def shape(self, x: Float[Array, "..."]) -> Float[Array, "..."]:
        """The relief fraction (0 … 1) at x ∈ [0, 1] (already clamped), same shape."""

    def ramp(self, x: Float[Array, "..."], blend) -> Float[Array, "..."]:
        """The relief fraction at x ∈ ℝ: :meth:`shape` of x clamped to [0, 1], zero below 0,
        one above 1; ``blend`` > 0 rounds the kink at the relief start (x = 0) with a softplus
        of that width in x units (0: sharp)."""
        return self.shape(_clamp(x, blend))


class LinearRelief(AbstractReliefShape):
    """Linear relief: depth ∝ x (case-file name "linear")."""

    name: ClassVar[str] = "linear"

    def shape(self, x):
        return x


class ParabolicRelief(AbstractReliefShape):
    """Parabolic relief: depth ∝ x² (case-file name "parabolic")."""

    name: ClassVar[str] = "parabolic"

    def shape(self, x):
        return x * x


class AbstractEndReliefEdges(NamedKind):
    """The face edge(s) a lead end relief acts on; z is the base-plane face coordinate of
    docs/design.md, "Base plane and sign conventions", ζ = z/b. A one-sided relief is the seed's
    IV-33 lead modification of the overloaded edge."""

    @abc.abstractmethod
    def ramp(self, zeta: Float[Array, "..."], extent, blend) -> Float[Array, "..."]:
        """The end relief fraction (0 … 1, linear) at lead fraction ``zeta`` (broadcast), the
        relief ``extent`` (fraction of the face width at each relieved edge) and the start's
        rounding ``blend`` in units of the extent (:func:`_end_ramp`)."""


def _z0_ramp(zeta, extent, blend):
    return _end_ramp((extent - zeta) / extent, blend)


def _z1_ramp(zeta, extent, blend):
    return _end_ramp((zeta - (1.0 - extent)) / extent, blend)


class BothEdges(AbstractEndReliefEdges):
    """Both face edges, symmetric (case-file name "both"; the default)."""

    name: ClassVar[str] = "both"

    def ramp(self, zeta, extent, blend):
        return _z0_ramp(zeta, extent, blend) + _z1_ramp(zeta, extent, blend)


class EdgeZ0(AbstractEndReliefEdges):
    """The z = 0 edge only, ζ < extent (case-file name "z0")."""

    name: ClassVar[str] = "z0"

    def ramp(self, zeta, extent, blend):
        return _z0_ramp(zeta, extent, blend)


class EdgeZ1(AbstractEndReliefEdges):
    """The z = b edge only, ζ > 1 − extent (case-file name "z1")."""

    name: ClassVar[str] = "z1"

    def ramp(self, zeta, extent, blend):
        return _z1_ramp(zeta, extent, blend)


class MemberModification(eqx.Module):
    """Modifications of one member's flank (SI units, depths in m, extents as fractions).

    Attributes:
        tip_relief_depth: E (m), >= 0, at the tip.
        tip_relief_extent: Γ ∈ (0, 1], fraction of the path of contact g_α.
        root_relief_depth, root_relief_extent: likewise at the start of active profile.
        crowning_depth: lead crowning C_β (m), >= 0, parabolic, depth at each face edge.
        end_relief_depth: linear lead end relief (m) at the relieved face edge(s), >= 0.
        end_relief_extent: its length at each relieved end as a fraction of the face width,
            (0, 0.5].
        end_relief_blend: rounding width of the end relief start, in lead-fraction units (0:
            sharp start): a parabola over that width centred on the start, C¹, the ramp unchanged
            outside it. Optimisation sets it to one slice, 1/N, so that objectives sampled at
            the slice centres are smooth in the end relief extent.
        helix_slope_deviation: f_Hβ (m), signed: material added at z = b, removed at z = 0
            (linear across the face, zero at mid-face); models a misalignment too.
        profile_deviation_roll: roll fractions u (ascending), shape (n,).
        profile_deviation: user profile deviation (m) at those u, shape (n,), interpolated.
        relief_blend: rounding width of the tip/root relief start, in roll-fraction units (0:
            sharp start). Optimisation sets it to about one position step so that objectives
            sampled at discrete positions are smooth in the relief extent.
        tip_relief_shape, root_relief_shape: an :class:`AbstractReliefShape`,
            :class:`LinearRelief` (default) or :class:`ParabolicRelief` (no leaves: a new shape
            recompiles).
        end_relief_edge: which face edge(s) the end relief acts on, an
            :class:`AbstractEndReliefEdges`: :class:`BothEdges` (default, symmetric),
            :class:`EdgeZ0` (the z = 0 edge only, ζ < extent) or :class:`EdgeZ1` (the z = b
            edge only, ζ > 1 − extent); z is the base-plane face coordinate of docs/design.md,
            "Base plane and sign conventions". A one-sided relief is the seed's IV-33 lead
            modification of the overloaded edge.

    Raises:
        ValueError: (one line naming the attribute, its value and the allowed range) an unknown
            shape or edge, profile arrays of other shapes, and, on concrete values (traced ones,
            under jit/vmap/grad, are not known here), a value that is not finite or outside
            its range above: depths and blends >= 0, extents in (0, 1] ((0, 0.5] for the end
            relief), roll fractions strictly ascending.
    """

    tip_relief_depth: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    tip_relief_extent: Float[Array, ""] = eqx.field(converter=as_float, default=0.25)
    root_relief_depth: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    root_relief_extent: Float[Array, ""] = eqx.field(converter=as_float, default=0.25)
    crowning_depth: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    end_relief_depth: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    end_relief_extent: Float[Array, ""] = eqx.field(converter=as_float, default=0.1)
    helix_slope_deviation: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    profile_deviation_roll: Float[Array, " n"] = eqx.field(converter=as_float, default=(0.0, 1.0))
    profile_deviation: Float[Array, " n"] = eqx.field(converter=as_float, default=(0.0, 0.0))
    relief_blend: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    end_relief_blend: Float[Array, ""] = eqx.field(converter=as_float, default=0.0)
    tip_relief_shape: AbstractReliefShape = LinearRelief()
    root_relief_shape: AbstractReliefShape = LinearRelief()
    end_relief_edge: AbstractEndReliefEdges = BothEdges()

    def __check_init__(self):
        for name in ("tip_relief_shape", "root_relief_shape"):
            check_instance(
                name,
                getattr(self, name),
                AbstractReliefShape,
                "jaxgear.LinearRelief() or jaxgear.ParabolicRelief()",
                "MemberModification",
            )
        check_instance(
            "end_relief_edge",
            self.end_relief_edge,
            AbstractEndReliefEdges,
            "jaxgear.BothEdges(), jaxgear.EdgeZ0() (the z = 0 edge) or jaxgear.EdgeZ1() (the "
            "z = b edge)",
            "MemberModification",
        )
        if (
            self.profile_deviation_roll.shape != self.profile_deviation.shape
            or self.profile_deviation.ndim != 1
            or self.profile_deviation.shape[0] < 2
        ):
            raise ValueError(
                "profile_deviation: roll_fraction and deviation_um must be 1-D lists "
                "of the same length >= 2"
            )
        # the documented ranges, on concrete values (any shape: a batch of modifications for
        # jax.vmap is checked entry by entry)
        for name, (unit, lo, hi, lo_open) in _RANGES.items():
            check_real(
                name,
                getattr(self, name),
                unit,
                lo=lo,
                hi=hi,
                lo_open=lo_open,
                where="MemberModification",
            )
        roll = self.profile_deviation_roll
        # NumPy on the host: jnp here compiled three programs at import (the class-level
        # default Modifications()), before the CLI switches JAX's persistent cache on
        if not is_traced(roll) and not bool(np.all(np.diff(np.asarray(roll)) > 0)):
            raise ValueError(
                f"MemberModification: profile_deviation_roll = {roll.tolist()} is out of range: "
                "allowed strictly ascending roll fractions"
            )

    def deviation(self, u: Float[Array, "..."], zeta: Float[Array, "..."]) -> Float[Array, "..."]:
        """Normal deviation e (m) at roll fraction ``u`` and lead fraction ``zeta`` (broadcast)."""
        tip = self.tip_relief_depth * self.tip_relief_shape.ramp(
            (u - (1.0 - self.tip_relief_extent)) / self.tip_relief_extent,
            self.relief_blend / self.tip_relief_extent,
        )
        root = self.root_relief_depth * self.root_relief_shape.ramp(
            (self.root_relief_extent - u) / self.root_relief_extent,
            self.relief_blend / self.root_relief_extent,
        )
        xi = 2.0 * zeta - 1.0
        crown = self.crowning_depth * xi * xi
        le = self.end_relief_extent
        end = self.end_relief_depth * self.end_relief_edge.ramp(
            zeta, le, self.end_relief_blend / le
        )
        slope = self.helix_slope_deviation * (zeta - 0.5)
        if self.profile_deviation.shape[0] == 2:  # a straight line: no table search needed
            r, d = self.profile_deviation_roll, self.profile_deviation
            w = jnp.clip((u - r[0]) / (r[1] - r[0]), 0.0, 1.0)
            prof = d[0] + (d[1] - d[0]) * w
        else:
            prof = jnp.interp(u, self.profile_deviation_roll, self.profile_deviation)
        return prof + slope - tip - root - crown - end


class Modifications(eqx.Module):
    """Flank modifications of both members, and optionally their manufacturing deviations.

    Attributes:
        pinion, gear: :class:`MemberModification` of each member.
        deviations: per-tooth manufacturing deviations (:class:`~jaxgear.Deviations`, ISO
            1328-1) or None (perfect teeth). They depend on the tooth pair and the absolute angle,
            so :meth:`deviation` leaves them out: :func:`~jaxgear.separation` adds them per cell
            (docs/deviations.md).

    Example:
        >>> tip = MemberModification(tip_relief_depth=15e-6, tip_relief_extent=0.25)
        >>> mods = Modifications.symmetric(tip)
    """

    pinion: MemberModification = eqx.field(default_factory=MemberModification)
    gear: MemberModification = eqx.field(default_factory=MemberModification)
    deviations: Deviations | None = None

    def __check_init__(self):
        allowed = "a jaxgear.MemberModification"
        for tag in ("pinion", "gear"):
            check_instance(tag, getattr(self, tag), MemberModification, allowed, "Modifications")
        if self.deviations is not None:
            allowed = "a jaxgear.Deviations or None"
            check_instance("deviations", self.deviations, Deviations, allowed, "Modifications")

    @classmethod
    def symmetric(cls, member: MemberModification) -> "Modifications":
        """The same modification on both members."""
        return cls(pinion=member, gear=member)

    def rating_inputs(self) -> tuple[Float[Array, ""], Float[Array, ""]]:
        """ISO 6336-1's modification inputs of the pair: the tip relief C_a (m; K_v's B_k,
        clause 6) and the crowning C_β (m; K_Hβ's B₂, clause 7), each the larger of the two
        members' ``tip_relief_depth`` and ``crowning_depth`` (0: none). Differentiable in the
        depths (almost everywhere)."""
        ca = jnp.maximum(self.pinion.tip_relief_depth, self.gear.tip_relief_depth)
        cb = jnp.maximum(self.pinion.crowning_depth, self.gear.crowning_depth)
        return ca, cb

    def deviation(
        self, s_fraction: Float[Array, "..."], zeta: Float[Array, "..."]
    ) -> Float[Array, "..."]:
        """Pair deviation e (m) at base-plane fraction s/g_α and lead fraction z/b."""
        return self.pinion.deviation(s_fraction, zeta) + self.gear.deviation(1.0 - s_fraction, zeta)
