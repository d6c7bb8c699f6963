"""A gear train as a scene: a structure with several meshes, its rigid rotation and the span of
first-mesh periods after which every mesh repeats (docs/trains.md). The torsional
(:func:`~jaxgear.scenes.torsional_train`) and the lumped 3D trains
(:func:`~jaxgear.scenes.lumped_train`) are both a :class:`GearTrain`; this module holds what they
share: the class, the shaft speeds and torques of the meshes, and the span.
"""

from __future__ import annotations

import fractions
import math

import equinox as eqx
from jaxtyping import Array, Float

from ._scene import DynamicScene
from ._structure import AssembledScene

__all__ = [
    "MAX_SCENE_PERIODS",
    "GearTrain",
    "mesh_period_ratios",
    "mesh_teeth",
    "scene_span",
    "shaft_speeds",
    "shaft_torques",
]


class GearTrain(AssembledScene, DynamicScene):
    """A gear train: a structure (one rotation per shaft, or 6-DOF shaft nodes) with one mesh per
    pair of gears in contact (build with :func:`~jaxgear.scenes.torsional_train` or
    :func:`~jaxgear.scenes.lumped_train`). The input torque T acts on the input shaft, each
    loaded shaft takes its share of the input power and the balancing output the rest
    (:func:`shaft_torques`); the chain turns freely (its rigid rotation :attr:`rigid`).

    Attributes:
        rigid: the rigid rotation (n,): each shaft's rotation per unit base-plane advance of the
            input (ω_s / r_b,0 on every rotation of shaft s, in the sense it turns).
        periods: static, the periods of the first mesh after which the cells of every mesh
            repeat together (:func:`scene_span`): 1 for an idler train; 37 for 23-37 then 29-41
            on the 37's shaft (one turn of that shaft).
        period_ratios: static, each mesh's period in periods of the first, exact
            (:func:`mesh_period_ratios`; 37/29 for the second mesh there); None: 1 for every
            mesh.
    """

    rigid: Float[Array, " n"]
    periods: int = eqx.field(static=True, default=1)
    period_ratios: tuple | None = eqx.field(static=True, default=None)

    def rigid_modes(self):
        return self.rigid[:, None]

    def scene_periods(self) -> int:
        """:attr:`periods`: first-mesh periods after which every mesh's cells repeat."""
        return self.periods

    def mesh_periods(self):
        """:attr:`period_ratios` (each mesh's period in periods of the first)."""
        if self.period_ratios is None:
            return super().mesh_periods()
        return self.period_ratios


def mesh_teeth(plane) -> tuple[int, int]:
    """A mesh's (driving, driven) tooth counts, 2π r_b / p_bt rounded (exact whatever the float
    width of the base plane: the spans and speed ratios of a train are ratios of these)."""
    p = float(plane.base_pitch)
    return tuple(
        round(2.0 * math.pi * float(r) / p)
        for r in (plane.base_radius_pinion, plane.base_radius_gear)
    )


def shaft_speeds(links, base_radii, n: int) -> list:
    """Each shaft's speed per unit input speed, ω_s (unsigned), from the meshes.

    Args:
        links: each mesh's (driving, driven) shafts, listed from the input (shaft 0) outwards.
        base_radii: each mesh's (driving, driven) base radii (m), or anything in their ratio:
            the trains pass the tooth counts (:func:`mesh_teeth`), exact in float32 too.
        n: the number of shafts.

    Raises:
        ValueError: a mesh whose driving shaft does not turn yet, a shaft driven twice or one
            that meshes with none (one line).
    """
    omega = [None] * n
    omega[0] = 1.0
    for k, ((g, h), (r1, r2)) in enumerate(zip(links, base_radii, strict=True)):
        if omega[g] is None:
            raise ValueError(
                f"meshes[{k}]: driving gear {g} does not turn yet (list the meshes from the input "
                "gear 0 outwards)"
            )
        if omega[h] is not None:
            raise ValueError(f"meshes[{k}]: gear {h} is driven twice (allowed: once)")
        omega[h] = omega[g] * float(r1) / float(r2)
    if any(w is None for w in omega):
        raise ValueError(f"gears {[i for i, w in enumerate(omega) if w is None]} mesh with none")
    return omega


def shaft_torques(links, omega, shares) -> tuple[dict, int]:
    """The external torque on each loaded shaft per unit input torque, in its direction of
    motion: +1 on the input (shaft 0), −share_s ω_0/ω_s on each shaft with a share of the input
    power, and −(1 − Σ shares) ω_0/ω_o on the balancing output o, the one shaft that drives no
    other and has no share (the torques balance the power: Σ T_s ω_s = 0).

    Args:
        links: each mesh's (driving, driven) shafts. omega: :func:`shaft_speeds`.
        shares: ``{shaft: share}``, 0 < share, their sum < 1 (``None``: no share).

    Returns:
        ({shaft: torque per unit input torque}, o).

    Raises:
        ValueError: no or several shafts left for the balancing output, shares out of range.
    """
    n = len(omega)
    shares = {} if shares is None else {int(g): float(v) for g, v in shares.items()}
    driving = {g for g, _ in links}
    free = [i for i in range(n) if i not in driving and i not in shares]
    if len(free) != 1:
        raise ValueError(
            f"the train has output gears {free} without a share of the input power (allowed: "
            "exactly one, the balancing output)"
        )
    o = free[0]
    if 0 in shares or any(not 0.0 < v < 1.0 for v in shares.values()):
        raise ValueError(f"shares = {shares}: allowed gears other than the input, each in (0, 1)")
    rest = 1.0 - sum(shares.values())
    if not rest > 0.0:
        raise ValueError(f"shares = {shares}: their sum {1.0 - rest:.6g} leaves the output none")
    torques = {0: 1.0, o: -rest / omega[o]}
    torques.update({g: -v / omega[g] for g, v in shares.items()})
    return torques, o


#: the longest span of first-mesh periods a train may repeat over (a table row per step of it)
MAX_SCENE_PERIODS = 1000


def mesh_period_ratios(periods) -> tuple[fractions.Fraction, ...]:
    """Each mesh's period T_k / T_0 in periods of the first mesh, exact, from the periods T_k
    (input rad, floats): the fraction of tooth counts of denominator <= 10⁶ within 1e-9 (127/35
    for the second stage of the embedded ``two-stage`` case: a 35-tooth pinion on the 127-tooth
    wheel's shaft).

    Raises:
        ValueError: a ratio that is no such fraction."""
    out = []
    for k, t in enumerate(periods):
        r = t / periods[0]
        f = fractions.Fraction(r).limit_denominator(10**6)
        if abs(float(f) - r) > 1e-9 * r:
            raise ValueError(
                f"meshes[{k}]: its period is {r:.12g} periods of mesh 0, not a ratio of tooth "
                "counts (allowed: the meshes repeat together)"
            )
        out.append(f)
    return tuple(out)


def scene_span(periods) -> int:
    """The least q such that q T_0 is a whole number of every mesh period T_k (input rad), from
    the exact ratios T_k / T_0 of tooth counts (:func:`mesh_period_ratios`): the least common
    multiple of their numerators.

    Raises:
        ValueError: a ratio that is no such fraction, or q above MAX_SCENE_PERIODS."""
    q = 1
    for f in mesh_period_ratios(periods):
        q = math.lcm(q, f.numerator)
    if q > MAX_SCENE_PERIODS:
        raise ValueError(
            f"the meshes repeat together every {q} periods of mesh 0 (allowed: at most "
            f"{MAX_SCENE_PERIODS}; choose tooth counts with common factors)"
        )
    return q
