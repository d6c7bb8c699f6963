"""The rating of a planetary stage's two meshes in ``jaxgear run`` (``[rating]``): ISO 6336
method B per planet path with the load sharing factor K_γ multiplying the load as K_A does
(docs/rating.md, "Planetary stages in `jaxgear run`"), and where K_γ comes from when the case
does not give it (the run's load sharing: the 3D lumped model's for a helical stage on its
supports, else the planar model's)."""

from __future__ import annotations

import dataclasses
import warnings

import equinox as eqx

from ..io import CaseWarning, ratings_of
from ._rating_report import (
    RATE,
    rated_with_measured,
    rating_lines,
    stacked_meshes,
    write_rating_md,
)

__all__ = [
    "FACE_LOAD_SOURCE",
    "K_GAMMA_SOURCE",
    "K_GAMMA_SOURCES",
    "measured_k_h_beta",
    "rating_k_gamma",
    "rating_section",
]

#: where a planetary mesh's K_γ comes from when ``[rating] K_gamma`` does not give it
K_GAMMA_SOURCE = (
    "jaxgear load sharing (planar lumped model, the case's pin errors): the most loaded planet "
    "path's mesh force over the mean"
)
#: the same per load-sharing model of the run (``summary.json``'s ``load_sharing`` names)
K_GAMMA_SOURCES = {
    "planar": K_GAMMA_SOURCE,
    "spatial": "jaxgear load sharing (3D lumped model of the helical stage on its axial and "
    "tilting supports, the case's pin errors): the most loaded planet path's mesh force over "
    "the mean",
}


#: where a planetary mesh's measured K_Hβ comes from (``summary.json``'s ``face_load``:
#: :func:`jaxgear.cli.planetary.face_load_section`), ``{n}`` the number of planets
FACE_LOAD_SOURCE = (
    "jaxgear face load (3D lumped model of the helical stage on its axial and tilting supports, "
    "constant mesh springs at two Gauss points across the face, the case's pin errors): ISO "
    "6336-1's linear distribution across the face from the members' tilts and the helical axial "
    "forces, the largest of the {n} planets' meshes"
)


def measured_k_h_beta(face_load: dict | None) -> list[dict] | None:
    """The ``rating.measured`` K_Hβ of the stage's two rated meshes (``sun-planet``,
    ``planet-ring``) from the run's ``face_load`` section (its ``k_h_beta``: the n sun/planet
    meshes, then the n ring/planet meshes): each the largest over the planets (the rating is of
    the most loaded path, as K_γ), with :data:`FACE_LOAD_SOURCE`; ``None`` where the run has no
    face load (a spur stage; a helical stage whose supports do not hold it: ``skipped``)."""
    k = (face_load or {}).get("k_h_beta")
    if k is None:
        return None
    n = len(k) // 2
    source = FACE_LOAD_SOURCE.format(n=n)
    return [{"value": float(max(k[:n])), "source": source},
            {"value": float(max(k[n:])), "source": source}]


def rating_k_gamma(sharing: dict) -> tuple[float, str]:
    """(K_γ, source) for the rating when ``[rating] K_gamma`` does not give it, from the run's
    load sharing (``summary.json``'s ``load_sharing``, :func:`jaxgear.cli.planetary.
    sharing_summary`): the last model of :data:`K_GAMMA_SOURCES` the run has, i.e. the 3D
    model's where the run has it (a helical stage whose axial and tilting supports hold it,
    :func:`jaxgear.cli.planetary.spatial_model`), else the planar model's; each at the travel 0
    with the case's pin errors and eccentricities."""
    name = [n for n in K_GAMMA_SOURCES if n in sharing][-1]
    return float(sharing[name]["k_gamma"]), K_GAMMA_SOURCES[name]


def rating_section(case, out: str, k_gamma: float,
                   source: str = K_GAMMA_SOURCE, face_load: dict | None = None) -> dict | None:
    """``[rating]`` of a planetary stage (:func:`jaxgear.io.parse_planetary_rating`): each mesh
    (``sun-planet``, ``planet-ring``: the ring rated as an internal gear) rated by ISO 6336
    method B at one planet path's mean load with the load sharing factor K_γ (``[rating]
    K_gamma`` if given, else ``k_gamma``, the stage's load sharing with the pin errors, whose
    origin ``source`` names: :func:`rating_k_gamma`)
    multiplying the load as K_A does (σ_H ∝ √(K_A K_γ K_v K_Hβ K_Hα), σ_F ∝ K_A K_γ K_v K_Fβ
    K_Fα; σ_H0, σ_F0 nominal, as ISO 6336-1 and the KISSsoft reports write it), at its driving
    member's speed relative to the carrier; ``rating.md`` (one table per mesh)
    written into ``out``; the ``summary.json`` section as a train's (per-mesh lists, ``meshes``
    naming them) with ``K_gamma`` (value, source), ``torque_per_planet_path_Nm`` (the mean, before
    K_γ) and ``speed_relative_to_carrier_rad_s``. With the run's ``face_load`` (a helical stage
    on its supports: :func:`jaxgear.cli.planetary.face_load_section`), each mesh's
    ``measured.K_Hbeta`` (:func:`measured_k_h_beta`), reported in ``rating.md`` beside ISO's and
    rated with in its place when ``[rating] use_measured`` names it, as a pair's
    (:func:`jaxgear.cli._rating_report.rated_with_measured`). ``None`` (nothing written) without
    ``[rating]``."""
    rcs = ratings_of(case)
    if rcs is None:
        return None
    names = [case.mesh_name(k) for k in range(len(rcs))]
    lines = [
        f"# {case.name}: load capacity of every mesh of the planetary stage",
        "",
        "Each mesh rated for one planet path: the sun/planet mesh with the sun as the pinion, "
        "the planet/ring mesh with the planet as the pinion and the ring as an internal gear "
        "(ISO 6336-2/-3's internal-gear rules: Z_D = 1, the ring's root section at the 60° "
        "tangent), at the path's mean load times the load sharing factor K_γ and at the "
        "driving member's speed relative to the carrier. The planet's teeth are loaded on "
        "alternate flanks by the sun and the ring: Y_M = 0.7 (ISO 6336-3, mean stress "
        "influence factor); the sun's and the ring's meet every planet each relative turn.",
        "",
    ]
    measured = measured_k_h_beta(face_load)
    named = dict.fromkeys(n for rc in rcs for n in rc.use_measured)
    unmeasured = [n for n in named if measured is None or n != "K_Hbeta"]
    if unmeasured:
        warnings.warn(
            f"[rating] use_measured: {', '.join(unmeasured)} not measured on a planetary "
            "stage's meshes (K_Hbeta only, of a helical stage on its axial and tilting "
            "supports): rated with ISO's", CaseWarning, stacklevel=2)
    sections = []
    for k, (name, rc) in enumerate(zip(names, rcs, strict=True)):
        given = rc.k_gamma is not None
        kg = float(rc.k_gamma) if given else float(k_gamma)
        k_a = float(rc.settings.application_factor)
        # K_γ multiplies the load as K_A does (ISO 6336-1: F_t K_A K_γ in every load factor
        # and stress; σ_H0, σ_F0 at the nominal F_t of one planet path)
        settings = eqx.tree_at(lambda s: s.application_factor, rc.settings, k_a * kg)
        rating = RATE(rc.geometry, rc.operating, settings)
        for note in rating.scope_notes():
            warnings.warn(f"[rating] {name}: {note}", CaseWarning, stacklevel=2)
        section = rating.summary()
        if measured is not None:
            section["measured"] = {"K_Hbeta": measured[k]}
            section = rated_with_measured(dataclasses.replace(rc, settings=settings), section)
        section["factors"]["K_A"] = {"value": k_a, "source": "given"}
        section |= {
            "K_gamma": {"value": kg, "source": "given" if given else source},
            "torque_per_planet_path_Nm": float(rc.operating.torque),
            "speed_relative_to_carrier_rad_s": float(rc.operating.speed),
        }
        sections.append(section)
        lines += rating_lines(section, f"{case.name}, mesh {name}", heading="##")
        lines.append(f"| K_γ | {kg:.4f} |  | {section['K_gamma']['source']} |")
        lines += [
            "",
            f"K_γ = {kg:.4f} ({section['K_gamma']['source']}), a factor of the load as K_A "
            f"(one planet path: {section['torque_per_planet_path_Nm']:.6g} N·m on the pinion, "
            "mean).",
            "",
        ]
    write_rating_md(out, lines)
    return stacked_meshes(names, sections)
