"""The tooth-root stress map of a load distribution: each cell's load times the fillet stress of
a unit load at the cell's position on the member's flank, from the plane FE tooth model
(:func:`fem_prep.fillet_influence`, computed once per member and passed in as a table).

A transverse slice of face width b/N carries, on one tooth, one contact point at a time; the
transverse component of its normal load per unit face width is the cell's line load w (N/m):
w/cos β_b of normal load per unit face width (the cell's contact length is (b/N)/cos β_b), times
cos β_b for the transverse part. The fillet of that tooth in that slice then carries
w · g(ρ), g(ρ) the largest fillet surface stress per unit load at roll distance ρ (Pa per N/m),
interpolated linearly between the table's radii. For a helical member the table is that of ISO
6336-3's normal section (``fillet_influence(..., section=fem_prep.NormalSection())``, what
``jaxgear run`` uses): the virtual spur tooth loaded at the cell's height on the tooth, with
w cos β/cos β_b per unit length along the helix folded into g, so the map is w · g(ρ) still
(docs/rating.md, "Helical teeth in the normal section"). Slices are independent (plane strain per
slice, as the thin-slice mesh stiffness): no coupling across the face width, and the load of a
neighbouring tooth is not superposed on this tooth's fillet. Pure ``jax.numpy``: differentiable
with respect to the loads, for quasi-static (:class:`jaxgear.MeshResult`) and dynamic cell loads
alike.
"""

from __future__ import annotations

import equinox as eqx
import jax
import jax.numpy as jnp
from jaxtyping import Array, Bool, Float

from .._geometry import AbstractGearPair
from .._util import check_instance

__all__ = ["RootStressMap", "root_stress_map"]


class RootStressMap(eqx.Module):
    """Root stress of one member per cell of a load distribution.

    Attributes:
        stress: the largest fillet stress of the member's tooth that carries the cell's load
            (Pa), shape (P, L, N) (positions, contact lines, slices); 0 off the flanks.
        roll: the member's roll distance at each cell (m), (P, L, N).
        cell_s, cell_z: the cells' base-plane coordinates (m), (P, L, N).
        mask: cells on the flanks, (P, L, N).
    """

    stress: Float[Array, "P L N"]
    roll: Float[Array, "P L N"]
    cell_s: Float[Array, "P L N"]
    cell_z: Float[Array, "P L N"]
    mask: Bool[Array, "P L N"]

    @property
    def max(self) -> Float[Array, ""]:
        """The largest root stress over the map (Pa)."""
        return jnp.max(self.stress)

    def soft_max(self, width) -> Float[Array, ""]:
        """A smooth upper bound of :attr:`max` for gradients (Pa): ``width`` log Σ exp(σ/width)
        over every cell (0 off the flanks), between :attr:`max` and :attr:`max` + ``width``
        log(P L N); its gradient is the softmax-weighted sum of the cells' gradients, where
        :attr:`max`'s jumps from cell to cell.

        Args:
            width: the smoothing (Pa), > 0; e.g. 1e6 (1 MPa) on stresses of hundreds of MPa.

        Raises:
            ValueError: ``width`` (a number) not > 0.
        """
        if isinstance(width, int | float) and not width > 0:
            raise ValueError(
                f"RootStressMap.soft_max: width = {width!r} is out of range, allowed > 0 (Pa)"
            )
        return width * jax.nn.logsumexp(self.stress / width)


def root_stress_map(
    pair: AbstractGearPair, result, member: int, roll_table, stress_per_load
) -> RootStressMap:
    """The root-stress map of ``member`` (0 pinion, 1 gear) under the cell loads of ``result``
    (module docstring).

    Args:
        pair: the :class:`jaxgear.GearPair` or :class:`jaxgear.InternalGearPair` of the
            result (the ring is member 1: its table from ``fem_prep.fillet_influence`` of
            :func:`jaxgear.internal_tooth_geometry`, its roll distances
            :meth:`~jaxgear.InternalGearPair.roll_distance`'s).
        result: one mesh's cell loads: ``line_load`` (N/m), ``cell_s``, ``cell_z`` (m) and
            ``cell_mask`` of shape (P, L, N) (a :class:`jaxgear.MeshResult`, a one-mesh
            quasi-static result, or dynamic cell loads with the same fields).
        member: 0 (pinion) or 1 (gear).
        roll_table: (K,) roll distances ρ (m) of the unit loads, increasing, covering the
            member's active profile (``fem_prep.fillet_influence(...).roll``). Cells outside
            it (contact beyond the theoretical path) take the nearest end's value
            (``jnp.interp`` holds the ends): the tip's for a member touching with its tip
            corner, the start of active profile's, an upper bound, below it.
        stress_per_load: (K,) the largest fillet stress per unit load at each (Pa per N/m;
            ``fem_prep.fillet_influence(...).peak``).

    Returns:
        :class:`RootStressMap` (Pa). Source: the plane FE tooth model (docs/rating.md, "FE root
        stress"); ISO 6336-3's σ_F0 rates the same tooth with the load at the outer point of
        single pair contact.

    Raises:
        ValueError: ``member`` not 0 or 1, or the tables of different lengths.
    """
    check_instance(
        "pair",
        pair,
        AbstractGearPair,
        "a jaxgear.GearPair or InternalGearPair",
        "root_stress_map",
    )
    if member not in (0, 1):
        raise ValueError(f"root_stress_map: member = {member!r} is out of range, allowed 0 or 1")
    rt, sp = jnp.asarray(roll_table), jnp.asarray(stress_per_load)
    if rt.shape != sp.shape or rt.ndim != 1:
        raise ValueError(
            f"root_stress_map: roll_table {rt.shape} and stress_per_load {sp.shape} must be "
            "two (K,) tables"
        )
    roll = pair.roll_distance(result.cell_s, member)
    load = jnp.where(result.cell_mask, jnp.maximum(result.line_load, 0.0), 0.0)
    stress = load * jnp.interp(roll, rt, sp)
    return RootStressMap(stress, roll, result.cell_s, result.cell_z, result.cell_mask)
