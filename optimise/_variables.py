"""Design variables of tooth-modification optimisation (docs/design.md, "Optimisation").

Design variables are named like the case file: ``tip_relief.depth``, ``tip_relief.extent``,
``root_relief.depth``, ``root_relief.extent``, ``crowning.depth``, ``end_relief.depth``,
``end_relief.extent``, each optionally prefixed by ``pinion.`` or ``gear.``; without a prefix a
variable acts on both members at once (symmetric modification). A :class:`Variable` is one of
them parsed: its ``MemberModification`` field, its members and its kind
(:class:`AbstractKind`: :class:`Depth`, :class:`Extent`, :class:`EndExtent`), which normalises,
bounds and writes it in case-file units.

Normalisation: depths are E* = E/δ_m with δ_m = F_n / K̄ the mean static deflection of the
unmodified mesh at the design torque (K̄ its mean mesh stiffness); extents are Γ itself.
"""

from __future__ import annotations

import abc
import functools
from typing import ClassVar

import equinox as eqx

import jaxgear as jg

__all__ = [
    "VARIABLES",
    "AbstractKind",
    "Depth",
    "EndExtent",
    "Extent",
    "Variable",
    "tip_relief_slots",
    "variables_of",
]

# variable -> (MemberModification field, kind of variable: a key of _KINDS)
VARIABLES = {
    "tip_relief.depth": ("tip_relief_depth", "depth"),
    "tip_relief.extent": ("tip_relief_extent", "extent"),
    "root_relief.depth": ("root_relief_depth", "depth"),
    "root_relief.extent": ("root_relief_extent", "extent"),
    "crowning.depth": ("crowning_depth", "depth"),
    "end_relief.depth": ("end_relief_depth", "depth"),
    "end_relief.extent": ("end_relief_extent", "end_extent"),
}
_MEMBERS = {"pinion": ("pinion",), "gear": ("gear",)}  # a variable's prefix -> its members


# -- design variables ----------------------------------------------------------------------------
class AbstractKind(eqx.Module):
    """How a design variable is normalised, bounded and written in case-file units."""

    # the end relief start is rounded over one slice when this kind of variable is designed
    rounds_end_relief: ClassVar[bool] = False

    @abc.abstractmethod
    def to_model(self, x, delta_m):
        """Normalised value → the modification's value (SI)."""

    @abc.abstractmethod
    def to_file(self, x: float, delta_m: float) -> float:
        """Normalised value → case-file units."""

    @abc.abstractmethod
    def from_file(self, v: float, delta_m: float) -> float:
        """Case-file units → normalised value."""

    @abc.abstractmethod
    def file_value(self, value: float) -> float:
        """The modification's value (SI) → case-file units."""

    @abc.abstractmethod
    def default_bounds(self) -> tuple[float, float]:
        """Bounds in normalised units when none are given."""

    @abc.abstractmethod
    def check_bounds(self, name: str, lo: float, hi: float) -> None:
        """Raises ValueError for bounds this kind cannot take."""

    @abc.abstractmethod
    def unmodified_at(self, value: float) -> bool:
        """Whether the normalised ``value`` leaves the design unmodified (as far as this
        variable goes)."""


class Depth(AbstractKind):
    """A depth: normalised E* = E/δ_m, written in µm (``depth_um``); default bounds (0, 3)."""

    def to_model(self, x, delta_m):
        return x * delta_m

    def to_file(self, x, delta_m):
        return x * delta_m * 1e6

    def from_file(self, v, delta_m):
        return v * 1e-6 / delta_m

    def file_value(self, value):
        return value * 1e6

    def default_bounds(self):
        return (0.0, 3.0)

    def check_bounds(self, name, lo, hi):
        if lo < 0:
            raise ValueError(f"bounds of {name!r} = ({lo}, {hi}): a depth must be >= 0")

    def unmodified_at(self, value):
        return value == 0


class _AbstractFraction(AbstractKind):
    """A fraction inside (0, 1), designed unnormalised: what :class:`Extent` and
    :class:`EndExtent` share."""

    def to_model(self, x, delta_m):
        return x

    def to_file(self, x, delta_m):
        return x

    def from_file(self, v, delta_m):
        return v

    def file_value(self, value):
        return value

    def check_bounds(self, name, lo, hi):
        if not (0 < lo and hi < 1):
            raise ValueError(
                f"bounds of {name!r} = ({lo}, {hi}): an extent must stay inside (0, 1)"
            )

    def unmodified_at(self, value):
        return True  # an extent alone adds no modification


class Extent(_AbstractFraction):
    """An extent Γ (a fraction, unnormalised), inside (0, 1); ``upper`` the default upper bound
    (0.98 for a relief along the profile, 0.5 for an end relief along the face)."""

    upper: float = eqx.field(static=True)

    def default_bounds(self):
        return (0.02, self.upper)


class EndExtent(_AbstractFraction):
    """The end relief extent (a fraction of the face width), default bounds (0.02, 0.5); its
    relief start is rounded over one slice while it is designed (``end_relief_blend``)."""

    rounds_end_relief: ClassVar[bool] = True

    def default_bounds(self):
        return (0.02, 0.5)


_KINDS = {"depth": Depth(), "extent": Extent(0.98), "end_extent": EndExtent()}


class Variable(eqx.Module):
    """One design variable: a :class:`jaxgear.MemberModification` field on one or both members.

    Attributes:
        name: as written (``pinion.tip_relief.depth``). base: without the member prefix.
        field: the ``MemberModification`` field. members: ``("pinion",)``, ``("gear",)`` or
            both. kind: its normalisation (:class:`Depth`, :class:`Extent`, :class:`EndExtent`).
    """

    name: str = eqx.field(static=True)
    base: str = eqx.field(static=True)
    field: str = eqx.field(static=True)
    members: tuple[str, ...] = eqx.field(static=True)
    kind: AbstractKind

    @classmethod
    def parse(cls, name: str) -> Variable:
        """The variable of a name (see the module docstring).

        Raises:
            ValueError: an unknown variable.
        """
        name = name.strip()
        head, _, rest = name.partition(".")
        members = _MEMBERS.get(head)
        base = rest if members else name
        if base not in VARIABLES:
            allowed = ", ".join(sorted(VARIABLES))
            raise ValueError(
                f"variables: {name!r} is an unknown design variable, allowed {allowed}, "
                "optionally prefixed by 'pinion.' or 'gear.'"
            )
        field, kind = VARIABLES[base]
        return cls(name, base, field, members or ("pinion", "gear"), _KINDS[kind])

    def case_value(self, mods: jg.Modifications) -> float:
        """The variable's value in ``mods`` (its first member's), in case-file units."""
        return self.kind.file_value(float(getattr(getattr(mods, self.members[0]), self.field)))


def tip_relief_slots(names) -> tuple[int, int] | None:
    """The positions (depth, extent) of the tip relief variables when ``names`` are exactly
    ``tip_relief.depth`` and ``tip_relief.extent`` (each optionally with a member prefix), else
    None: the (Γ, E) map of the problem exists."""
    bases = [Variable.parse(n).base for n in names]
    try:
        slots = bases.index("tip_relief.depth"), bases.index("tip_relief.extent")
    except ValueError:  # one of them is not a variable
        return None
    return slots if len(bases) == 2 else None


@functools.singledispatch
def _names(variables) -> list[str]:
    """Variable names of a sequence of names."""
    return list(variables)


@_names.register
def _(variables: str) -> list[str]:
    return [v for v in variables.split(",") if v.strip()]  # "a,b": comma-separated


def variables_of(variables) -> tuple[Variable, ...]:
    """The variables of names (a sequence, or a comma-separated string).

    Raises:
        ValueError: an unknown variable, none, or one named twice.
    """
    out = tuple(Variable.parse(n) for n in _names(variables))
    if not out:
        raise ValueError("variables is empty: give at least one design variable")
    if len({v.name for v in out}) != len(out):
        raise ValueError(f"variables = {','.join(v.name for v in out)!r} names a variable twice")
    return out
