"""The damping of a hybrid model (seed (2.34)–(2.36); docs/hybrid.md, "Global system"): its
constant part and its mesh share that follows the mesh as the wheel turns, built at each
speed from the quasi-static cells of the run's step positions (:func:`_speed_damping`), and the
same period by period over a revolution for checks (:func:`revolution_damping`)."""

from __future__ import annotations

from collections.abc import Callable
from typing import NamedTuple

import jax.numpy as jnp
from jaxtyping import Array, Float

from .._contact import ContactLaw, ExactContact, contact_law
from .._util import check_integer
from ..scenes import HybridPair
from ._hybrid_mesh import (
    _loaded,
    _mesh_block,
    _period_statics,
    _revolution_mesh_stiffness,
    _revolution_periods,
)
from ._damping import AbstractDamping
from ._modal import modal_analysis
from ._model import AbstractDynamicModel

__all__ = ["RevolutionDamping", "revolution_damping"]


class _HybridDamping(NamedTuple):
    """The damping of the hybrid Newmark, C(k) = C + c_m Rᵀ K̄_m(k) R in mesh period k, with
    K̄_m(k) the mesh stiffness averaged over period k's quasi-static positions on the stations
    under the mesh then (it turns with the wheel).

    Attributes:
        C: the constant part (units of K·s), (n, n), the bearings' damping included.
        c_m: the factor of the mesh share (s for Rayleigh, - for the composite), or None when
            the model has no mesh share (modal, "none"): C(k) = C.
        R: the map of the mesh share (n, n) (-), or None: the identity (Rayleigh, C(k) = C +
            β K̄_m(k), exact and sparse on the window).
    """

    C: Float[Array, "n n"]
    c_m: Float[Array, ""] | None
    R: Float[Array, "n n"] | None


def _damping(scene: HybridPair, Km, damping: AbstractDamping) -> _HybridDamping:
    """The damping of the hybrid scene (seed (2.34)–(2.36)) as its constant part and its mesh
    share that follows the mesh as the wheel turns (:class:`_HybridDamping`,
    :meth:`~jaxgear.dynamics.AbstractDamping.hybrid`), plus the scene's bearing damping.
    ``Km``: the mesh stiffness averaged round the revolution, K̄ (n, n), whose system
    (M, K + K̄) gives the modes (ω_i, φ_i) of the models that need them
    (:attr:`~jaxgear.dynamics.AbstractDamping.needs_modes`; None for the others)."""
    M = scene.structure.M
    modes = modal_analysis(scene, Km) if damping.needs_modes else None
    C, c_m, R = damping.hybrid(M, scene.structure.K, modes)
    return _HybridDamping(C + scene.bearing_damping(), c_m, R)


def _speed_damping(
    model: AbstractDynamicModel, speed, law: ContactLaw, spp: int, host_checked: bool = False
):
    """The quasi-static result at the ``spp`` step positions of the first mesh period at speed
    Ω (:func:`_period_statics`), the mesh stiffness of period p, ``block(p)``
    (:func:`_mesh_block` on the cells loaded there), and the damping (:func:`_damping`; the modal
    models' modes with K̄_m averaged round the wheel). ``host_checked``: as
    :func:`_period_statics`."""
    scene = model.scene
    period_angle = scene.base_planes[0].mesh_period_angle
    qs, _ = _period_statics(scene, model.mods, model.torque, speed, spp, law, host_checked)
    loaded = _loaded(qs)

    def block(p):  # K̄_m(p) on the stations under the meshes in period p
        return _mesh_block(scene, qs.theta + p * period_angle, loaded)

    Km = None
    if model.damping.needs_modes:
        Km = _revolution_mesh_stiffness(scene, block, _revolution_periods(scene))
    return qs, block, _damping(scene, Km, model.damping)


class RevolutionDamping(NamedTuple):
    """The damping of a hybrid model at one speed over a wheel revolution (seed (2.34)–(2.36)),
    C(k) = C + c_m Wᵀ K̄_m(k) W in mesh period k, with K̄_m(k) the mesh stiffness averaged over
    the period's quasi-static positions on the rim stations under the meshes then (U) and W the
    rows U of R (of the identity when R is None).

    Attributes:
        constant: C, the part that does not follow the mesh, bearings included (N·s/m per
            coordinate), (n, n).
        mesh_factor: c_m (s for Rayleigh, - for the composite), or None: no mesh share.
        mesh_map: R (n, n), or None: the identity.
        periods: mesh periods of a revolution (the least common multiple of the condensed
            members' tooth counts).
        block: k ↦ (U (w,), K̄_m(k) on U (w, w), whether every window of period k lies in U).
    """

    constant: Float[Array, "n n"]
    mesh_factor: Float[Array, ""] | None
    mesh_map: Float[Array, "n n"] | None
    periods: int
    block: Callable

    def at(self, k) -> tuple[Float[Array, "n n"], Array]:
        """C(k) (n, n) in mesh period ``k`` and whether the period's windows lie inside U."""
        if self.mesh_factor is None:
            return self.constant, jnp.array(True)
        U, B, ok = self.block(k)
        n = self.constant.shape[0]
        W = jnp.eye(n, dtype=B.dtype)[U] if self.mesh_map is None else self.mesh_map[U]
        return self.constant + self.mesh_factor * (W.T @ B @ W), ok


def revolution_damping(
    model: AbstractDynamicModel,
    speed,
    *,
    steps_per_period: int = 16,
    contact: ContactLaw | None = None,
) -> RevolutionDamping:
    """The damping a hybrid model's Newmark run uses at pinion ``speed`` Ω (rad/s) with
    ``steps_per_period`` steps per mesh period and the contact law ``contact`` (default:
    exact), period by period over a wheel revolution (:class:`RevolutionDamping`): to check
    its symmetry and positive semi-definiteness, or its modal diagonal against (2.36)."""
    dtype = model.scene.structure.K.dtype
    law = contact_law(ExactContact() if contact is None else contact, dtype)
    check_integer("steps_per_period", steps_per_period, 1)
    _, block, damp = _speed_damping(model, jnp.asarray(speed, dtype), law, steps_per_period)
    return RevolutionDamping(damp.C, damp.c_m, damp.R, _revolution_periods(model.scene), block)
