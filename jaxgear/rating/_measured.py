"""Load factors measured on jaxgear's results, and a rating with them in place of the
standard's: the dynamic factor K_v of a speed sweep at the rating's speed (a pair's mesh, a
planetary stage's planets), the transverse load factor K_Hα of a stage's planets
(:func:`jaxgear.rating.transverse_load_factor` of each), the load sharing factor K_γ folded
into the load as K_A is (ISO 6336-1), and the settings that rate with them
(:func:`with_measured`). The face load factor
K_Hβ of one mesh is :func:`jaxgear.rating.face_load_factor`. Concrete values (NumPy): the
results of a run, not traced."""

from __future__ import annotations

import equinox as eqx
import numpy as np

from .._util import check_real
from ._factors import transverse_load_factor

__all__ = [
    "dynamic_factor_at",
    "planet_dynamic_factor",
    "planet_transverse_factor",
    "with_load_sharing",
    "with_measured",
]


def dynamic_factor_at(speeds, dynamic_factor, speed: float) -> float | None:
    """K_v measured by a speed sweep: the sweep's dynamic factor (the largest dynamic mesh
    force over the static one, each mesh's own) interpolated linearly at the rating's ``speed``.
    ISO 6336-1's K_v is the same ratio (the largest dynamic load of the mesh over its static
    one).

    Args:
        speeds: the sweep's speeds (rad/s), (s,), increasing.
        dynamic_factor: the mesh's dynamic factor at each speed (-), (s,).
        speed: the speed to read it at (rad/s, on the axis of ``speeds``).

    Returns:
        K_v (-), or None where ``speed`` is outside the swept range (the sweep says nothing
        there)."""
    speeds = np.asarray(speeds, dtype=float)
    if not speeds[0] <= speed <= speeds[-1]:
        return None
    return float(np.interp(speed, speeds, np.asarray(dynamic_factor, dtype=float)))


def planet_dynamic_factor(speeds, dynamic_factors, speed: float, forces) -> float | None:
    """K_v of one mesh kind of a planetary stage (its sun/planet or its planet/ring meshes)
    from a speed sweep: each planet j's mesh dynamic factor (its largest mesh force over the
    nominal T_s/(N r_bs)) interpolated linearly at ``speed`` and divided by its static share
    s_j = |F_j| / mean |F| of the load sharing whose K_γ the rating takes, so that K_v is the
    mesh's dynamic load over its static one (ISO 6336-1) and K_γ K_v does not count the static
    unequal sharing twice (equal sharing: s_j = 1); the largest over the planets.

    Args:
        speeds: the sweep's input speeds (rad/s), (s,), increasing.
        dynamic_factors: each planet's mesh dynamic factor, (s, N).
        speed: the rating's input speed (rad/s).
        forces: each planet's static mesh force of the load sharing (N), (N,).

    Returns:
        K_v (-), or None outside the swept range."""
    curves = np.asarray(dynamic_factors, dtype=float)
    f = np.abs(np.asarray(forces, dtype=float))
    share = f / f.mean()
    values = [dynamic_factor_at(speeds, curves[:, j], speed) for j in range(curves.shape[1])]
    if values[0] is None:
        return None
    return max(v / share[j] for j, v in enumerate(values) if share[j] > 0)


def planet_transverse_factor(meshes) -> float:
    """K_Hα of one mesh kind of a planetary stage: each planet's mesh measured as a pair's
    (:func:`jaxgear.rating.transverse_load_factor` of its one-mesh result, ``line_load`` and
    ``cell_mask``), the largest over the planets."""
    return max(float(transverse_load_factor(m)) for m in meshes)


def with_load_sharing(settings, k_gamma: float):
    """``settings`` with the load sharing factor K_γ (the mesh load factor of a planet path,
    the most loaded path's load over the mean: 1 for equal sharing) multiplying the load as
    K_A does (ISO 6336-1: F_t K_A K_γ in every load factor and stress; σ_H0, σ_F0 stay at the
    nominal F_t of one path): the application factor K_A K_γ.

    Raises:
        ValueError: ``k_gamma`` <= 0 or not a scalar, in one line."""
    check_real("k_gamma", k_gamma, "", lo=0.0, lo_open=True, shape=(), shape_text="a scalar",
               where="with_load_sharing")
    k_a = float(settings.application_factor)
    return eqx.tree_at(lambda s: s.application_factor, settings, k_a * float(k_gamma))


def with_measured(geometry, settings, measured: dict):
    """``settings`` with the ``measured`` load factors (name → value: ``K_v``, ``K_Hbeta``,
    ``K_Halpha``) given in place of the standard's, as the standard ties them
    (:meth:`jaxgear.rating.AbstractRatingStandard.with_measured`; ISO 6336: each at least 1,
    K_Fα = K_Hα within clause 8's limits, K_Fβ = K_Hβ^N_F): rate with them
    (:func:`jaxgear.rate`). No measured factor: ``settings`` themselves."""
    if not measured:
        return settings
    return settings.standard.with_measured(geometry, settings, dict(measured))
