"""Design variables of optimisation (docs/design.md, "Optimisation").

Design variables are named like the case file: ``tip_relief.depth``, ``tip_relief.extent``,
``root_relief.depth``, ``root_relief.extent``, ``crowning.depth``, ``end_relief.depth``,
``end_relief.extent``, each optionally prefixed by ``pinion.`` or ``gear.``; without a prefix a
variable acts on both members at once (symmetric modification). A :class:`Variable` is one of
them parsed: its ``MemberModification`` field, its members and its kind
(:class:`AbstractKind`: :class:`Depth`, :class:`Extent`, :class:`EndExtent`), which normalises,
bounds and writes it in case-file units.

A rolling bearing's clearance is a variable of the structure, not of the flanks:
``<shaft>.bearings[<k>].clearance`` (``pinion_shaft.bearings[0].clearance``; a train's shaft by
its name), of kind :class:`Clearance`, in µm (negative: a preload): the field its bearing kind
declares (``clearance_field``: the diametral clearance, a tapered roller pair's axial end
play). What a variable acts on is
declared by its kind (:attr:`AbstractKind.acts_on`): ``"modifications"`` (written into the
flanks' :class:`jaxgear.Modifications`) or ``"structure"`` (the scene's bearing stiffness,
:class:`optimise.BearingDesign`, docs/bearings.md, "As a design variable").

Normalisation: depths are E* = E/δ_m with δ_m = F_n / K̄ the mean static deflection of the
unmodified mesh at the design torque (K̄ its mean mesh stiffness); extents are Γ itself; a
clearance is its value in µm.
"""

from __future__ import annotations

import abc
import functools
import re
from typing import ClassVar

import equinox as eqx

import jaxgear as jg

__all__ = [
    "VARIABLES",
    "AbstractKind",
    "Clearance",
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
#: a bearing's variable: ``<shaft>.bearings[<k>].<quantity>`` (quantity a key of _BEARING_KINDS)
_BEARING = re.compile(r"^([A-Za-z_][\w.-]*?)\.bearings\[(\d+)\]\.(\w+)$")


# -- design variables ----------------------------------------------------------------------------
class AbstractKind(eqx.Module):
    """How a design variable is normalised, bounded and written in case-file units, and what it
    acts on.

    Class attributes:
        acts_on: ``"modifications"`` (the variable's value is written into the flanks'
            :class:`jaxgear.Modifications`, :meth:`optimise.Problem.modifications`) or
            ``"structure"`` (it changes the scene's stiffness,
            :meth:`optimise.Problem.at_design`).
        rounds_end_relief: the end relief start is rounded over one slice while a variable of
            this kind is designed.
    """

    acts_on: ClassVar[str] = "modifications"
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


class Clearance(AbstractKind):
    """A rolling bearing's clearance, designed in µm (x = c / 1 µm; negative: a preload): the
    field its kind declares (``clearance_field``: the diametral clearance P_d, a tapered roller
    pair's axial end play e); default bounds (−5, 20) µm. It acts on the structure: the bearing's
    tangent stiffness at its held load (:class:`optimise.BearingDesign`), which also checks
    the bounds against the bearing's own range."""

    acts_on: ClassVar[str] = "structure"

    def to_model(self, x, delta_m):
        return x * 1e-6

    def to_file(self, x, delta_m):
        return x

    def from_file(self, v, delta_m):
        return v

    def file_value(self, value):
        return value * 1e6

    def default_bounds(self):
        return (-5.0, 20.0)

    def check_bounds(self, name, lo, hi):
        pass  # the bearing's range: BearingDesign.check_bounds

    def unmodified_at(self, value):
        return True  # a clearance adds no flank modification


_KINDS = {"depth": Depth(), "extent": Extent(0.98), "end_extent": EndExtent()}
#: a bearing's quantity -> its kind
_BEARING_KINDS = {"clearance": Clearance()}


class Variable(eqx.Module):
    """One design variable: a :class:`jaxgear.MemberModification` field on one or both members,
    or a quantity of one bearing of the structure.

    Attributes:
        name: as written (``pinion.tip_relief.depth``, ``gear_shaft.bearings[1].clearance``).
        base: without the member prefix (a bearing's: its name). field: the
            ``MemberModification`` field (a bearing's: its quantity, ``clearance``). members:
            ``("pinion",)``, ``("gear",)`` or both (a bearing's: none). kind: its normalisation
            and what it acts on (:class:`Depth`, :class:`Extent`, :class:`EndExtent`,
            :class:`Clearance`). shaft, bearing: a bearing's shaft name and index on it (None
            for a modification).
    """

    name: str = eqx.field(static=True)
    base: str = eqx.field(static=True)
    field: str = eqx.field(static=True)
    members: tuple[str, ...] = eqx.field(static=True)
    kind: AbstractKind
    shaft: str | None = eqx.field(static=True, default=None)
    bearing: int | None = eqx.field(static=True, default=None)

    @classmethod
    def parse(cls, name: str) -> Variable:
        """The variable of a name (see the module docstring).

        Raises:
            ValueError: an unknown variable.
        """
        name = name.strip()
        hit = _BEARING.match(name)
        if hit and hit.group(3) in _BEARING_KINDS:
            shaft, k, quantity = hit.group(1), int(hit.group(2)), hit.group(3)
            return cls(name, name, quantity, (), _BEARING_KINDS[quantity], shaft, k)
        head, _, rest = name.partition(".")
        members = _MEMBERS.get(head)
        base = rest if members else name
        if base not in VARIABLES:
            allowed = ", ".join(sorted(VARIABLES))
            raise ValueError(
                f"variables: {name!r} is an unknown design variable, allowed {allowed}, "
                "optionally prefixed by 'pinion.' or 'gear.', or <shaft>.bearings[<k>]."
                f"{'|'.join(_BEARING_KINDS)} (a rolling bearing's, µm)"
            )
        field, kind = VARIABLES[base]
        return cls(name, base, field, members or ("pinion", "gear"), _KINDS[kind])

    def case_value(self, mods: jg.Modifications) -> float:
        """The variable's value in ``mods`` (its first member's), in case-file units (a
        modification's: a bearing's value is its design's, :meth:`optimise.Problem.case_values`).
        """
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
