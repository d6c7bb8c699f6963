"""Rolling bearings as design variables: a bearing's clearance (its kind's
``clearance_field``: the diametral clearance, or a tapered roller pair's axial end play;
negative: a preload) acting on the scene's stiffness (docs/bearings.md, "As a design
variable").

The bearings' operating point is found once (:func:`jaxgear.dynamics.bearings_at_operating_point`,
NumPy around compiled solves) and each designed bearing's load F_b held there. Its tangent
stiffness is then a JAX function of its clearance c,

    K_b(c) = stiffness6(solve_displacement(kind(c), F_b).displacement)

through the displacement solve's implicit derivative, and the scene the objective runs on is
the operating point's with K_b(c) − K_b(c₀) added where its assembly put the bearing
(:func:`jaxgear.dynamics.with_bearing_stiffness`: the shaft node, and on a housing its seat).
K_b(c₀), a constant, is computed once, when the design is built (:func:`bearing_design`), not
at every evaluation.
What this holds fixed: the bearings' loads (exact where each shaft is statically determinate,
its bearings' loads statics'; an approximation where the bearings' stiffness shares a load:
two bearings sharing an axial load as the shaft tilts, three on a shaft, the mesh's load over
the face), the other bearings at their operating point, and whatever a model built once from
the operating point's scene holds (a :class:`jaxgear.dynamics.DynamicModel`'s damping matrix).
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from jaxgear.bearings import AbstractRollingBearing, solve_displacement
from jaxgear.dynamics import OperatingPoint, with_bearing_stiffness

__all__ = ["BearingDesign", "bearing_design"]


def _held_stiffness(kind: AbstractRollingBearing, load, clearance) -> Float[Array, "6 6"]:
    """K_b(c) (6, 6): the tangent stiffness of ``kind`` with its clearance field
    (``kind.clearance_field``: the diametral clearance, a tapered pair's end play) at
    ``clearance`` (m) where it carries ``load`` (5,) (N, N·m)."""
    kind = eqx.tree_at(lambda k: getattr(k, k.clearance_field), kind, clearance)
    return kind.stiffness6(solve_displacement(kind, load).displacement)


class BearingDesign(eqx.Module):
    """The rolling bearings of a scene whose clearances are design variables, at their held
    operating point (build with :func:`bearing_design`; module docstring).

    Attributes:
        shafts: the :class:`~jaxgear.scenes.ShaftSpec` of the scene at the operating point
            (:attr:`jaxgear.dynamics.OperatingPoint.shafts`), in its order (static).
        names: each shaft's name in variable names (``pinion_shaft``, ``gear_shaft``; a
            train's shaft names), static.
        extra_z: the scene's more node positions per shaft (m), or None (static).
        loads: per shaft, per bearing, the held load (5,) (N, N·m) of a rolling bearing, None
            for a linear one.
        held: per shaft, per bearing, K_b(c₀) (6, 6) (N/m, N/rad, N·m/rad): the tangent
            stiffness at the held load with the operating point's clearance c₀ of a rolling
            bearing that declares a clearance field (None for the others), computed once by
            :func:`bearing_design`; :meth:`apply` subtracts it.
    """

    shafts: tuple = eqx.field(static=True)
    names: tuple[str, ...] = eqx.field(static=True)
    extra_z: tuple | None = eqx.field(static=True)
    loads: tuple
    held: tuple

    def slot(self, var) -> tuple[int, int]:
        """(shaft index, bearing index) of a bearing variable.

        Raises:
            ValueError: an unknown shaft, a bearing index out of range, a bearing that is
                not a rolling bearing from its geometry (one line each)."""
        if var.shaft not in self.names:
            raise ValueError(f"variables: {var.name!r}: unknown shaft {var.shaft!r}, allowed "
                             f"{', '.join(self.names)}")
        i = self.names.index(var.shaft)
        bearings = self.shafts[i].bearings
        if not var.bearing < len(bearings):
            raise ValueError(f"variables: {var.name!r}: {var.shaft} has {len(bearings)} "
                             f"bearings, allowed bearings[0] to bearings[{len(bearings) - 1}]")
        rolling = bearings[var.bearing].rolling
        if rolling is None or not rolling.rolling_elements:
            raise ValueError(
                f"variables: {var.name!r} is a linear bearing (a stiffness): allowed on a "
                "rolling bearing from its geometry (kind = ..., or catalogue = ...)")
        if rolling.clearance_field is None:
            raise ValueError(
                f"variables: {var.name!r} is a {type(rolling).__name__}, which declares no "
                "clearance: allowed on a rolling bearing with a clearance field")
        return i, var.bearing

    def kind(self, var) -> AbstractRollingBearing:
        """The rolling bearing kind of a bearing variable (its clearance the operating point's;
        the variable sets its field ``clearance_field``)."""
        i, j = self.slot(var)
        return self.shafts[i].bearings[j].rolling

    def clearance(self, var) -> float:
        """The variable's value at the operating point (m): its bearing's clearance field (the
        diametral clearance, a tapered pair's end play)."""
        return _clearance_of(self.kind(var))

    def case_value(self, var) -> float:
        """The variable's value at the operating point, in case-file units (µm)."""
        return var.kind.file_value(self.clearance(var))

    def check_bounds(self, var, lo: float, hi: float) -> None:
        """Refuses bounds (µm) outside the bearing's own range of its clearance field (its
        kind's check, :meth:`~jaxgear.bearings.AbstractRollingBearing.with_clearance`, one
        line naming the variable)."""
        kind = self.kind(var)
        for v in (lo, hi):
            try:
                kind.with_clearance(var.kind.to_model(float(v), 1.0))
            except ValueError as err:
                raise ValueError(f"bounds of {var.name!r} = ({lo}, {hi}) µm: {err}") from None

    def stiffness(self, var, clearance) -> Float[Array, "6 6"]:
        """K_b(c) (6, 6) of the variable's bearing at clearance ``clearance`` (m), its load
        held."""
        i, j = self.slot(var)
        return _held_stiffness(self.kind(var), self.loads[i][j], clearance)

    def apply(self, scene, variables, clearances):
        """``scene`` (assembled on :attr:`shafts`) with each variable's bearing at its clearance
        (m, its clearance field's value, one per variable, in order): K_b(c) − K_b(c₀) added
        where the bearing sits (:func:`jaxgear.dynamics.with_bearing_stiffness`), K_b(c₀) the
        one :attr:`held` (computed once); at c₀ exactly ``scene`` evaluated eagerly, to
        round-off compiled (K_b(c₀) traced and held may differ in their last bits)."""
        changes = {}
        for var, c in zip(variables, clearances, strict=True):
            i, j = self.slot(var)
            changes[i, j] = self.stiffness(var, c) - jax.lax.stop_gradient(self.held[i][j])
        return with_bearing_stiffness(scene, self.shafts, changes, self.extra_z)


def bearing_design(point: OperatingPoint, names, extra_z=None) -> BearingDesign:
    """The :class:`BearingDesign` of an operating point.

    Args:
        point: the scene's rolling bearings at their operating point
            (:func:`jaxgear.dynamics.bearings_at_operating_point`,
            :func:`jaxgear.io.operating_point`); the scene the problem runs on must be
            assembled on ``point.shafts``.
        names: each shaft's name (as variables name it), one per shaft.
        extra_z: the scene's more node positions per shaft (m), or None.

    Raises:
        ValueError: not one name per shaft, a name twice (one line).
    """
    names = tuple(str(n) for n in names)
    if len(names) != len(point.shafts) or len(set(names)) != len(names):
        raise ValueError(f"bearing_design: names = {names!r}: allowed one distinct name per "
                         f"shaft ({len(point.shafts)})")
    loads = tuple(tuple(None if f is None else jnp.asarray(np.asarray(f, float)) for f in row)
                  for row in point.loads)
    held = tuple(
        tuple(_held_at_c0(b.rolling, f) for b, f in zip(shaft.bearings, row, strict=True))
        for shaft, row in zip(point.shafts, loads, strict=True))
    return BearingDesign(tuple(point.shafts), names, extra_z, loads, held)


def _held_at_c0(kind, load):
    """K_b(c₀) (6, 6) of a rolling bearing ``kind`` that declares a clearance field, at its
    held ``load`` and its own clearance c₀ (None: a linear bearing, a kind without a clearance
    field, no held load)."""
    if load is None or kind is None or kind.clearance_field is None:
        return None
    return _held_stiffness(kind, load, jnp.asarray(_clearance_of(kind)))


def _clearance_of(kind: AbstractRollingBearing) -> float:
    """The value (m) of the clearance field ``kind.clearance_field`` of a rolling bearing."""
    return float(getattr(kind, kind.clearance_field))
