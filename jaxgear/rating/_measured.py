"""Load factors measured on jaxgear's results, and a rating with them in place of the
standard's: the dynamic factor K_v of a speed sweep at the rating's speed (a pair's mesh, a
planetary stage's planets), the transverse load factor K_Hα and the face load factor K_Hβ of a
stage's planets (:func:`jaxgear.rating.transverse_load_factor` of each, the largest of the
3D model's K_Hβ: :func:`planet_face_factors`), the load sharing factor K_γ folded
into the load as K_A is (ISO 6336-1), and the settings that rate with them
(:func:`with_measured`). The face load factor
K_Hβ of one mesh is :func:`jaxgear.rating.face_load_factor`. Concrete values (NumPy): the
results of a run, not traced.

A measured factor is reported as a :class:`MeasuredFactor`, which cannot be made without the
words of the contact model that produced it (:func:`contact_model`: the theoretical path of
contact, the extended one, or mesh springs without tooth contact), so that no measured factor
is shown beside ISO's without that caveat."""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable

import equinox as eqx
import numpy as np

from .._baseplane import MeshModel
from .._contact_geometry import BeyondPath, TheoreticalPath
from .._util import check_instance, check_real
from ._factors import transverse_load_factor

__all__ = [
    "EXTENDED_CONTACT",
    "MESH_SPRINGS",
    "THEORETICAL_CONTACT",
    "MeasuredFactor",
    "contact_model",
    "dynamic_factor_at",
    "planet_dynamic_factor",
    "planet_dynamic_factors",
    "planet_face_factors",
    "planet_transverse_factor",
    "with_load_sharing",
    "with_measured",
]


#: a mesh with contact beyond the theoretical path (``MeshModel.contact_geometry`` a
#: :class:`~jaxgear.BeyondPath`)
EXTENDED_CONTACT = BeyondPath.description
#: a mesh with contact on the theoretical path only (a :class:`~jaxgear.TheoreticalPath`)
THEORETICAL_CONTACT = TheoreticalPath.description
#: a model without tooth contact (a lumped model's linear mesh springs)
MESH_SPRINGS = "no tooth contact (linear mesh springs of a constant stiffness)"


def contact_model(meshes) -> str:
    """The words of the contact model of a run's meshes, the caveat every measured factor
    carries (:class:`MeasuredFactor`): each mesh model's ``contact_geometry``'s
    ``description`` (:class:`jaxgear.MeshModel`): :data:`EXTENDED_CONTACT` beyond the path,
    :data:`THEORETICAL_CONTACT` on it; :data:`MESH_SPRINGS` for no mesh model (an empty
    sequence: a lumped model's constant mesh springs, no contact path). Meshes that differ: each named by its position
    ("mesh 1: ...; mesh 2: ...").

    Args:
        meshes: one :class:`jaxgear.MeshModel` or a sequence of them (a scene's
            ``base_planes``; a planetary stage's ``(sun_mesh, ring_mesh)``), or an empty one.

    Raises:
        ValueError: an entry that is not a MeshModel, in one line."""
    planes = (meshes,) if isinstance(meshes, MeshModel) else tuple(
        meshes if isinstance(meshes, Iterable) else (meshes,))
    for k, m in enumerate(planes):
        check_instance(f"meshes[{k}]", m, MeshModel, "a jaxgear.MeshModel",
                       where="contact_model")
    if not planes:
        return MESH_SPRINGS
    words = [m.contact_geometry.description for m in planes]
    if len(set(words)) == 1:
        return words[0]
    return "; ".join(f"mesh {k + 1}: {w}" for k, w in enumerate(words))


@dataclasses.dataclass(frozen=True)
class MeasuredFactor:
    """A load factor measured on jaxgear's results, as a rating report shows it beside the
    standard's: a row cannot be made without the contact model that produced it.

    Attributes:
        value: the factor (-), or None where the run says nothing (a speed outside a sweep).
        source: where it comes from (the model and the solve), non-empty.
        contact_model: the contact model's words (:func:`contact_model`), non-empty.
        comparable: whether it is comparable with the standard's (None: not said).
        note: why (None: the report's standing words for the factor).

    Raises:
        ValueError: an empty or missing ``source`` or ``contact_model``, in one line."""

    value: float | None
    source: str
    contact_model: str
    comparable: bool | None = None
    note: str | None = None

    def __post_init__(self):
        for name in ("source", "contact_model"):
            v = getattr(self, name)
            if not isinstance(v, str) or not v.strip():
                raise ValueError(f"MeasuredFactor: {name} = {v!r} is out of range: allowed a "
                                 "non-empty string (a measured factor states its "
                                 f"{name.replace('_', ' ')})")
        if self.value is not None:
            object.__setattr__(self, "value", float(self.value))

    def entry(self) -> dict:
        """The row as ``summary.json``'s ``rating.measured`` holds it: ``value``, ``source``,
        ``contact_model`` (and ``comparable``, ``note`` where given)."""
        out = {"value": self.value, "source": self.source, "contact_model": self.contact_model}
        if self.comparable is not None:
            out["comparable"] = self.comparable
        if self.note is not None:
            out["note"] = self.note
        return out

    @classmethod
    def of_entry(cls, entry: dict, name: str = "") -> MeasuredFactor:
        """The row of a ``rating.measured`` entry (:meth:`entry`'s dict).

        Raises:
            ValueError: an entry without ``contact_model`` (or ``source``), in one line."""
        for key in ("source", "contact_model"):
            if key not in entry:
                raise ValueError(f"measured factor {name or '?'}: no {key} (a measured factor "
                                 "is never shown without the contact model that produced it)")
        return cls(entry.get("value"), entry["source"], entry["contact_model"],
                   entry.get("comparable"), entry.get("note"))


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


def _kinds(name: str, values, where: str) -> tuple[np.ndarray, int]:
    """``values`` (..., 2N) as floats and N: the N sun/planet meshes', then the N
    planet/ring meshes' (a planetary stage's mesh order); one line when the last axis is not
    an even length >= 2."""
    a = np.asarray(values, dtype=float)
    if a.ndim < 1 or a.shape[-1] < 2 or a.shape[-1] % 2:
        raise ValueError(f"{where}: {name} has shape {a.shape}, allowed (..., 2N): the N "
                         "sun/planet meshes' then the N planet/ring meshes' (N >= 1)")
    return a, a.shape[-1] // 2


def planet_dynamic_factors(speeds, dynamic_factors, speed: float, sun_forces,
                           ring_forces) -> tuple[float | None, float | None]:
    """K_v of a planetary stage's two mesh kinds (sun/planet, planet/ring) from a speed sweep:
    :func:`planet_dynamic_factor` of each kind's planets.

    Args:
        speeds: the sweep's input speeds (rad/s), (s,), increasing.
        dynamic_factors: each mesh's dynamic factor (its largest force over the nominal
            T_s/(N r_bs)), (s, 2N): the N sun/planet meshes, then the N planet/ring meshes
            (:func:`jaxgear.planetary.sweep_factors`' order).
        speed: the rating's input speed (rad/s).
        sun_forces, ring_forces: each planet's static sun-mesh and ring-mesh force of the load
            sharing whose K_γ the rating takes (N), (N,) each.

    Returns:
        (K_v of the sun/planet meshes, K_v of the planet/ring meshes), each None outside the
        swept range.

    Raises:
        ValueError: ``dynamic_factors`` not (s, 2N), in one line."""
    curves, n = _kinds("dynamic_factors", dynamic_factors, "planet_dynamic_factors")
    curves = curves.reshape(-1, 2 * n)
    return (planet_dynamic_factor(speeds, curves[:, :n], speed, sun_forces),
            planet_dynamic_factor(speeds, curves[:, n:], speed, ring_forces))


def planet_face_factors(k_h_beta) -> tuple[float, float]:
    """K_Hβ of a planetary stage's two mesh kinds (sun/planet, planet/ring) from its meshes'
    face load factors: each kind's largest over the planets (the rating is of the most loaded
    path, as K_γ).

    Args:
        k_h_beta: each mesh's K_Hβ (-), (2N,): the N sun/planet meshes', then the N
            planet/ring meshes' (:class:`jaxgear.planetary.PlanetaryQuasiStatic`'s
            ``k_h_beta`` at one travel, the 3D model's).

    Returns:
        (K_Hβ of the sun/planet meshes, K_Hβ of the planet/ring meshes).

    Raises:
        ValueError: ``k_h_beta`` not (2N,), in one line."""
    k, n = _kinds("k_h_beta", k_h_beta, "planet_face_factors")
    if k.ndim != 1:
        raise ValueError(f"planet_face_factors: k_h_beta has shape {k.shape}, allowed (2N,)")
    return float(max(k[:n])), float(max(k[n:]))


def planet_transverse_factor(meshes, path_of_contact: float | None = None) -> float:
    """K_Hα of one mesh kind of a planetary stage: each planet's mesh measured as a pair's
    (:func:`jaxgear.rating.transverse_load_factor` of its one-mesh result, ``line_load``,
    ``cell_mask`` and, with ``path_of_contact`` (g_α of the kind's mesh model, m), ``cell_s``:
    the pairs read on the theoretical path, a corner's contact beyond it not a pair), the
    largest over the planets."""
    return max(float(transverse_load_factor(m, path_of_contact=path_of_contact))
               for m in meshes)


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
    (:func:`jaxgear.rating.rate`). No measured factor: ``settings`` themselves."""
    if not measured:
        return settings
    return settings.standard.with_measured(geometry, settings, dict(measured))
