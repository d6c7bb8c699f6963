"""Power loss and efficiency of a gear train, a planetary stage and a gearbox, from each mesh's
own sliding loss (:func:`mesh_tribology` on that mesh's line loads), by a series power flow.

Each element k (a mesh, or a whole stage of a gearbox) has its efficiency η_k = 1 − P_VZP,k /
P_k at the lossless power P_k it transmits (its driving torque times its driving speed: a
mesh's :attr:`MeshTribology.input_power`). The power that reaches it is the lossless one less
what the elements upstream of it (on the way from the input) lose::

    P'_k = P_k Π_{j ∈ up(k)} η_j,    loss_k = (1 − η_k) P'_k,
    P_out = P_in − Σ_k loss_k,        η = P_out / P_in

(the energy balance, by construction). In a series chain every P_k is the input power, and the
sum telescopes: η = Π_k η_k. A train whose shafts take power off on the way (``[operating]
loads``) has meshes of smaller P_k beyond them; up(k) follows the gears and shafts from the
input (:func:`train_efficiency`).

A planetary stage: friction loss is μ w v_g, and the sliding speed v_g is the same in every
frame; in the carrier's frame the stage is a fixed-axis train (sun → planet → ring), whose
meshes transmit the rolling power n_p T_k |ω_k − ω_c| (n_p planets, T_k the driving member's
torque per planet path, ω_k its speed): :func:`planetary_efficiency` is that series flow with
the stage's input power P_in = |T_in ω_in| in the fixed frame. It is the torque form of
Müller's (H. W. Müller, Die Umlaufgetriebe, 1971; also Kreines) basic formulas: for the sun
driving, the carrier driven and the ring fixed, η = 1 − (1 − η₀) z_r/(z_s + z_r), η₀ = η_sp
η_pr the fixed-carrier efficiency (the test suite writes it separately).

A gearbox: its stages in series (:func:`gearbox_efficiency`), each stage's efficiency its own
(a pair's :class:`MeshTribology`, a train's or a stage's :class:`PowerFlow`). docs/tribology.md,
"Trains, planetary stages and gearboxes".
"""

from __future__ import annotations

from collections.abc import Sequence

import equinox as eqx
import jax.numpy as jnp
import numpy as np
from jaxtyping import Array, Float

from .._util import check_real
from ._mesh import MeshTribology

__all__ = [
    "PowerFlow",
    "gearbox_efficiency",
    "planetary_efficiency",
    "power_flow",
    "train_efficiency",
]


class PowerFlow(eqx.Module):
    """Losses along a series power flow of k elements (meshes or stages), each (k,):

    Attributes:
        transmitted: P_k, the lossless power through element k (W).
        power: P'_k = P_k Π_{j ∈ up(k)} η_j, the power that reaches it (W).
        element_efficiency: η_k (-). loss: (1 − η_k) P'_k (W).
        input_power: P_in (W), scalar.
        upstream: up(k), the elements on the way from the input to element k (static).
    """

    transmitted: Float[Array, " k"]
    power: Float[Array, " k"]
    element_efficiency: Float[Array, " k"]
    loss: Float[Array, " k"]
    input_power: Float[Array, ""]
    upstream: tuple = eqx.field(static=True)

    @property
    def total_loss(self) -> Float[Array, ""]:
        """Σ loss_k (W)."""
        return jnp.sum(self.loss)

    @property
    def output_power(self) -> Float[Array, ""]:
        """P_out = P_in − Σ loss_k (W): the energy balance."""
        return self.input_power - self.total_loss

    @property
    def efficiency(self) -> Float[Array, ""]:
        """η = P_out / P_in (-); a series chain's Π η_k."""
        return self.output_power / self.input_power

    def summary(self, names: Sequence[str] | None = None) -> dict:
        """A JSON-ready dict (W, -): per element lists in order (``names`` their names)."""
        k = int(self.transmitted.shape[0])
        out = {"names": list(names)} if names is not None else {}
        out |= {
            "transmitted_power_W": [float(v) for v in self.transmitted],
            "power_W": [float(v) for v in self.power],
            "loss_W": [float(v) for v in self.loss],
            "efficiency_each": [float(v) for v in self.element_efficiency],
            "input_power_W": float(self.input_power),
            "total_loss_W": float(self.total_loss),
            "output_power_W": float(self.output_power),
            "efficiency": float(self.efficiency),
        }
        if k and names is not None and len(out["names"]) != k:
            raise ValueError(f"PowerFlow.summary: names has {len(out['names'])} entries: "
                             f"allowed {k}, one per element")
        return out


def power_flow(efficiency, transmitted, input_power, upstream=None) -> PowerFlow:
    """The series power flow of k elements (module docstring).

    Args:
        efficiency: (k,) η_k of each element at its lossless power, each in (0, 1].
        transmitted: (k,) P_k (W, > 0). input_power: P_in (W, > 0).
        upstream: up(k) per element, a sequence of k sequences of indices < k (None: a series
            chain, up(k) = 0..k−1).

    Returns:
        :class:`PowerFlow`; differentiable in ``efficiency``, ``transmitted``, ``input_power``.

    Raises:
        ValueError: lengths that differ, an efficiency outside (0, 1], a power not > 0, an
            upstream index not below its element's; one line naming the argument.
    """
    w = "power_flow"
    check_real("efficiency", efficiency, lo=0.0, hi=1.0, lo_open=True, shape=(None,),
               shape_text="(k,)", where=w)
    k = int(np.shape(efficiency)[0])
    check_real("transmitted", transmitted, "W", lo=0.0, lo_open=True, shape=(k,),
               shape_text=f"({k},), as efficiency", where=w)
    check_real("input_power", input_power, "W", lo=0.0, lo_open=True, shape=(), where=w)
    if upstream is None:
        upstream = tuple(tuple(range(i)) for i in range(k))
    upstream = tuple(tuple(int(j) for j in u) for u in upstream)
    if len(upstream) != k:
        raise ValueError(f"{w}: upstream has {len(upstream)} entries: allowed {k}, one per element")
    for i, u in enumerate(upstream):
        if any(j < 0 or j >= i for j in u):
            raise ValueError(f"{w}: upstream[{i}] = {list(u)}: allowed indices in [0, {i}) "
                             "(the elements are listed from the input outwards)")
    eta = jnp.asarray(efficiency)
    p = jnp.asarray(transmitted, dtype=eta.dtype)
    factor = jnp.stack([jnp.prod(eta[jnp.asarray(u, dtype=int)]) if u else jnp.ones((), eta.dtype)
                        for u in upstream])
    reach = p * factor
    return PowerFlow(
        transmitted=p,
        power=reach,
        element_efficiency=eta,
        loss=(1.0 - eta) * reach,
        input_power=jnp.asarray(input_power, dtype=eta.dtype),
        upstream=upstream,
    )


def _meshes(meshes, where: str) -> list:
    meshes = list(meshes)
    if not meshes:
        raise ValueError(f"{where}: meshes is empty: allowed one MeshTribology per mesh")
    for i, m in enumerate(meshes):
        if not isinstance(m, (MeshTribology, PowerFlow)):  # each carries its efficiency, P_in
            raise ValueError(f"{where}: meshes[{i}] = {type(m).__name__}: allowed a "
                             "jaxgear.tribology.MeshTribology or PowerFlow")
    return meshes


def _train_upstream(gears, shafts) -> tuple:
    """up(k) of each mesh of a train: the meshes on the way from the input shaft to mesh k's
    driving gear (a tree of shafts)."""
    driven_by = {}  # shaft → the mesh that drives it
    for j, (_, h) in enumerate(gears):
        driven_by.setdefault(shafts[h], j)
    up = []
    for g, _ in gears:
        chain, s, seen = [], shafts[g], set()
        while s in driven_by and s not in seen:
            seen.add(s)
            j = driven_by[s]
            chain.append(j)
            s = shafts[gears[j][0]]
        up.append(tuple(sorted(chain)))
    return tuple(up)


def train_efficiency(meshes, gears=None, shafts=None, input_power=None) -> PowerFlow:
    """Power loss and efficiency of a gear train (module docstring) from its meshes' own
    sliding loss.

    Args:
        meshes: (m,) :class:`MeshTribology` of each mesh, listed from the input outwards, each
            at its driving gear's torque and speed (its ``input_power`` the lossless power it
            transmits).
        gears: each mesh's (driving, driven) gear indices (None: a series chain, mesh k
            driving mesh k + 1). shafts: each gear's shaft index (None: a shaft per gear).
        input_power: P_in (W) (None: the first mesh's ``input_power``; give it when a load
            takes power off the input shaft).

    Returns:
        :class:`PowerFlow` of the meshes; a series chain's efficiency is Π η_k.

    Raises:
        ValueError: no meshes, gears of another length, a mesh driven before it is reached, as
            :func:`power_flow`; one line naming the argument.
    """
    w = "train_efficiency"
    meshes = _meshes(meshes, w)
    m = len(meshes)
    if gears is None:
        gears = tuple((k, k + 1) for k in range(m))
    gears = tuple((int(g), int(h)) for g, h in gears)
    if len(gears) != m:
        raise ValueError(f"{w}: gears has {len(gears)} entries: allowed {m}, one per mesh")
    n_gears = 1 + max(max(g, h) for g, h in gears)
    shafts = tuple(range(n_gears)) if shafts is None else tuple(int(s) for s in shafts)
    if len(shafts) < n_gears:
        raise ValueError(f"{w}: shafts has {len(shafts)} entries: allowed one per gear "
                         f"({n_gears})")
    upstream = _train_upstream(gears, shafts)
    for k, u in enumerate(upstream):
        if any(j >= k for j in u):
            raise ValueError(f"{w}: gears[{k}] = {gears[k]} is driven by a later mesh: allowed "
                             "the meshes listed from the input outwards")
    eta = jnp.stack([jnp.asarray(x.efficiency) for x in meshes])
    p = jnp.stack([jnp.asarray(x.input_power) for x in meshes])
    p_in = meshes[0].input_power if input_power is None else input_power
    return power_flow(eta, p, jnp.asarray(p_in, dtype=eta.dtype), upstream)


def planetary_efficiency(meshes, n_planets: int, input_power) -> PowerFlow:
    """Power loss and efficiency of a planetary stage (module docstring) from its two meshes'
    own sliding loss, in the carrier's frame.

    Args:
        meshes: (sun–planet, planet–ring) :class:`MeshTribology`, each of one planet path at
            its mean load: the driving member's torque per path and its speed relative to the
            carrier (the sun's |ω_s − ω_c|, the planet's |ω_p − ω_c|), so that its
            ``input_power`` is the rolling power per path.
        n_planets: n_p (int >= 1): each mesh's loss counts n_p times.
        input_power: the stage's input power |T_in ω_in| (W, > 0) in the fixed frame.

    Returns:
        :class:`PowerFlow` of the two meshes (each element all n_p paths of that mesh).

    Raises:
        ValueError: not two meshes, ``n_planets`` not an integer >= 1, as :func:`power_flow`;
            one line naming the argument.
    """
    w = "planetary_efficiency"
    meshes = _meshes(meshes, w)
    if len(meshes) != 2:
        raise ValueError(f"{w}: meshes has {len(meshes)} entries: allowed 2 (sun-planet, "
                         "planet-ring)")
    if isinstance(n_planets, bool) or int(n_planets) != n_planets or n_planets < 1:
        raise ValueError(f"{w}: n_planets = {n_planets!r} is out of range: allowed an integer "
                         ">= 1")
    eta = jnp.stack([jnp.asarray(x.efficiency) for x in meshes])
    p = jnp.stack([jnp.asarray(x.input_power) for x in meshes]) * float(n_planets)
    return power_flow(eta, p, jnp.asarray(input_power, dtype=eta.dtype))


def gearbox_efficiency(stages) -> PowerFlow:
    """A gearbox's power loss and efficiency: its stages in series (module docstring), each
    with its own ``efficiency`` and ``input_power`` (a pair's :class:`MeshTribology`, a train's
    or a planetary stage's :class:`PowerFlow`), listed from the input; P_in the first stage's.

    Raises:
        ValueError: no stages, a stage without ``efficiency`` and ``input_power``, as
            :func:`power_flow`; one line naming the argument.
    """
    stages = _meshes(stages, "gearbox_efficiency")
    eta = jnp.stack([jnp.asarray(s.efficiency) for s in stages])
    p = jnp.stack([jnp.asarray(s.input_power) for s in stages])
    return power_flow(eta, p, p[0])
