"""The rating of a planetary stage's two meshes in ``jaxgear run`` (``[rating]``): ISO 6336
method B per planet path with the load sharing factor K_γ multiplying the load as K_A does
(docs/rating.md, "Planetary stages in `jaxgear run`"), and where K_γ comes from when the case
does not give it (the run's load sharing: the 3D lumped model's for a helical stage on its
supports, else the planar model's)."""

from __future__ import annotations

import dataclasses
import functools
import os
import warnings
from typing import NamedTuple

import numpy as np

import fem_prep

from .. import (
    InternalGearPair,
    internal_tooth_geometry,
    tooth_geometry,
)
from ..io import CaseWarning, ratings_of
from ..rating import (
    MeasuredFactor,
    RootStressMap,
    ShaperCutterSection,
    contact_model,
    planet_dynamic_factors,
    planet_face_factors,
    planet_transverse_factor,
    root_stress_map,
    with_load_sharing,
)
from ..planetary import (
    ContactMeshes,
    DeviationMeshes,
    PlanetMeshLoads,
    RigidRing,
    planet_mesh_loads,
    planetary_quasi_static,
    rating_sharing_model,
)
from ._plots import root_stress_plot
from ._rating_inputs import modification_inputs
from ._rating_report import (
    RATE,
    ROOT_STRESS_RADII,
    _pick,
    measured_rating,
    stacked_meshes,
    write_rating_md,
)
from ._rating_sheet import inputs_of, k_v_note, rating_lines
from ._spectrum_report import spectrum_lines, spectrum_section
from ._stress_outputs import active_radii, fillet_table
from ._sweep_json import column_tag
from .scene import first_peak

__all__ = [
    "FACE_LOAD_SOURCE",
    "K_GAMMA_SOURCE",
    "K_GAMMA_SOURCES",
    "RING_ROOT_STRESS",
    "STAGE_ALPHA_SOURCE",
    "STAGE_AT_SPEED",
    "STAGE_ROOT_STRESS",
    "SWEEP_K_V_SOURCE",
    "MeshLoads",
    "StageAtSpeed",
    "StageLoads",
    "measured_k_h_alpha",
    "measured_k_h_beta",
    "measured_k_v",
    "rating_at_speed",
    "rating_k_gamma",
    "rating_section",
    "stage_at_speed",
    "stage_contact_model",
    "stage_loads",
    "stage_rating_lines",
    "stage_root_stress",
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


@functools.singledispatch
def stage_contact_model(meshes) -> str:
    """The contact model of a planetary stage's meshes kind, as its measured factors state it
    (:func:`jaxgear.rating.contact_model` of its mesh models): a meshes kind without tooth
    contact (:class:`jaxgear.planetary.ConstantMeshes`, a lumped model's springs) none."""
    return contact_model(())


@stage_contact_model.register
def _(meshes: ContactMeshes) -> str:  # the gears' contact cells: the sun's and the ring's mesh
    return contact_model((meshes.sun_mesh, meshes.ring_mesh))


@stage_contact_model.register
def _(meshes: DeviationMeshes) -> str:  # the contact cells with per-tooth deviations
    return stage_contact_model(meshes.contact)


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
    meshes, then the n ring/planet meshes): each the largest over the planets
    (:func:`jaxgear.rating.planet_face_factors`), with :data:`FACE_LOAD_SOURCE` and its contact model (the 3D
    model's constant mesh springs, no tooth contact: :func:`jaxgear.rating.contact_model` of
    no mesh model); ``None`` where the run has no face load (a spur stage; a helical stage
    whose supports do not hold it: ``skipped``)."""
    k = (face_load or {}).get("k_h_beta")
    if k is None:
        return None
    source = FACE_LOAD_SOURCE.format(n=len(k) // 2)
    springs = contact_model(())
    return [MeasuredFactor(value, source, springs).entry() for value in planet_face_factors(k)]


#: where a planetary mesh's measured K_v comes from (:func:`measured_k_v`)
SWEEP_K_V_SOURCE = (
    "jaxgear planetary speed sweep ({model}, {ring}, {count} input speeds {lo:.4g}–{hi:.4g} "
    "rad/s, the case's pin errors): each planet's mesh's dynamic factor interpolated linearly "
    "at the operating input speed {speed:.4g} rad/s, over its static share of the mean path "
    "load ({sharing} load sharing, K_γ's), the largest of the {n} planets' meshes"
)
#: appended to :data:`SWEEP_K_V_SOURCE` where the sweep's step does not resolve the stage's
#: highest natural frequency (``steps_resolution``,
#: :func:`jaxgear.planetary.step_resolution`)
UNRESOLVED_K_V = (" (time step under-resolved: n = {n:.3g} steps per period of {f:.4g} Hz at "
                  "the lowest speed, < 20; --steps-per-period >= {need} resolves it)")


def measured_k_v(sweep: dict | None, speed: float, sharing: dict,
                 contact: str) -> list[dict] | None:
    """The ``rating.measured`` K_v of the stage's two rated meshes (``sun-planet``,
    ``planet-ring``) from the planetary speed sweep ``sweep`` (``sweep.json``'s content,
    :func:`jaxgear.cli.planetary_sweep.sweep_summary`: ``speeds_rad_s`` of the input,
    ``dynamic_factor_mesh`` (s, 2N), the n sun/planet meshes then the n ring/planet meshes,
    each the largest mesh force over the nominal T_s/(N r_bs)) at the operating input
    ``speed`` (rad/s, the case's ``[operating] speed_rad_s``), as a pair's
    (:func:`jaxgear.cli.measured_dynamic_factor`: each mesh's curve interpolated linearly,
    nothing outside the swept range). Each planet j's mesh is divided by its static share
    s_j = F_j / mean(F) of the run's load sharing ``sharing`` (``summary.json``'s
    ``load_sharing``: the model whose K_γ the rating takes, :func:`rating_k_gamma`), so that
    K_v is the mesh's dynamic load over its static one (ISO 6336-1) and the rating's
    K_γ K_v does not count the static unequal sharing twice; with equal sharing s_j = 1. The
    largest over the planets (:func:`jaxgear.rating.planet_dynamic_factors`), with :data:`SWEEP_K_V_SOURCE` (and :data:`UNRESOLVED_K_V` where
    the sweep's ``steps_resolution`` is not resolved), ``comparable`` and ``note``: whether it
    is comparable with ISO's K_v, from the mesh frequency at ``speed`` against the sweep model's
    first mode (:func:`jaxgear.cli._rating_sheet.k_v_note`), and ``contact``, the contact
    model of the sweep's meshes (:func:`stage_contact_model`). None without a sweep or outside
    its speeds."""
    if sweep is None:
        return None
    speeds = np.asarray(sweep["speeds_rad_s"], dtype=float)
    if not speeds[0] <= speed <= speeds[-1]:
        return None
    curves = np.asarray(sweep["dynamic_factor_mesh"], dtype=float)
    n = len(sweep["mesh_names"]) // 2
    name = rating_sharing_model(sharing)
    source = SWEEP_K_V_SOURCE.format(
        model=sweep["model"], ring=sweep["ring_model"], count=speeds.size, lo=speeds[0],
        hi=speeds[-1], speed=speed, sharing=name, n=n)
    res = sweep.get("steps_resolution")
    if res is not None and not res["resolved"]:
        source += UNRESOLVED_K_V.format(n=res["steps_per_top_period_min"], f=res["f_max_Hz"],
                                        need=res["steps_per_period_resolved"])
    comparable = note = None
    if sweep.get("mesh_frequency_Hz") and sweep.get("natural_frequencies_Hz"):
        mesh_hz = float(np.interp(speed, speeds, np.asarray(sweep["mesh_frequency_Hz"])))
        comparable, note = k_v_note(mesh_hz, float(sweep["natural_frequencies_Hz"][0]),
                                    "the sweep model's first mode", contact)
    values = planet_dynamic_factors(speeds, curves, speed, sharing[name]["sun_mesh_forces_N"],
                                    sharing[name]["ring_mesh_forces_N"])
    return [MeasuredFactor(value, source, contact, comparable, note).entry() for value in values]


#: the stage's quasi-static solve that the rating's measured K_Hα and root-stress maps read
#: (:func:`stage_loads`), as their sources name it
STAGE_LOADS = (
    "jaxgear stage quasi-static ({model} lumped model on the gears' contact cells, the planets "
    "phased: {slices} slices, {positions} positions over a mesh period, exact contact, the "
    "case's modifications and pin errors)"
)
#: where a planetary mesh's measured K_Hα comes from (:func:`measured_k_h_alpha`)
STAGE_ALPHA_SOURCE = (
    "{source}: largest mean line load of one tooth pair over that of all loaded cells, max over "
    "a mesh period, the largest of the {n} planets' meshes"
)
#: where a planetary mesh's root-stress map comes from (:func:`stage_root_stress`)
STAGE_ROOT_STRESS = (
    "plane FE tooth (fem_prep.fillet_influence, m_n/18, ISO's normal section; a ring's tooth as "
    "its cutter generates it, transverse section) × the cell loads "
    "of planet {planet}'s mesh (the largest mean mesh force of the {n}), {source}, largest over "
    "the passage"
)
#: the ring's entry in the planet/ring mesh's root stress without its pinion-type cutter (the
#: one place it is decided: :func:`_member_table`): the FE model would have only the stand-in
#: circular fillet, whose peak fillet stress differs from the generated form's by up to ~20 %
#: for small cutters (docs/rating.md, "The ring's root stress")
RING_ROOT_STRESS = "not computed (no ring cutter)"


#: one planet's one mesh of the stage's solve (:class:`jaxgear.planetary.PlanetMeshLoads`)
MeshLoads = PlanetMeshLoads


class StageLoads(NamedTuple):
    """The stage's quasi-static loads per mesh kind (:func:`stage_loads`).

    Attributes:
        meshes: (sun/planet, planet/ring): each a tuple of one :class:`MeshLoads` per planet.
        forces: (sun/planet, planet/ring): each planet's mesh force (N, transverse, the mean
            over the positions), (n_planets,).
        source: :data:`STAGE_LOADS` filled in.
        contact_model: the contact model of the solve's meshes (:func:`stage_contact_model`).
        paths: (sun/planet, planet/ring): each mesh model's theoretical path of contact g_α
            (m), where the measured K_Hα reads its pairs (cells beyond it, a tip corner's
            contact, are not pairs: :func:`jaxgear.rating.transverse_load_factor`); None: every
            cell is on the path.
        peak_forces: (sun/planet, planet/ring): each planet's largest mesh force over the
            positions (N, transverse), (n_planets,); None where not recorded.
    """

    meshes: tuple
    forces: tuple
    source: str
    contact_model: str
    paths: tuple | None = None
    peak_forces: tuple | None = None

    def most_loaded(self, k: int) -> int:
        """The planet (0-based) whose mesh of kind ``k`` carries the largest mean force, the
        first of those within 1e-9 of it (equal sharing: planet 1, not round-off's pick:
        :func:`jaxgear.cli.scene.first_peak`)."""
        return first_peak(self.forces[k])

    def peak_planet(self, k: int) -> int:
        """The planet (0-based) whose mesh of kind ``k`` carries the largest force at any
        position, the first of those within :data:`SPEED_TIE_RTOL` of it: the static twin of
        :meth:`StageAtSpeed.most_loaded` (the same pick in the quasi-static limit)."""
        return first_peak(self.peak_forces[k], SPEED_TIE_RTOL)


def stage_loads(case, spec, stage, models: dict, ring=None) -> StageLoads | None:
    """The stage's quasi-static solve over one mesh period on the gears' contact cells
    (:class:`jaxgear.planetary.ContactMeshes` of :meth:`jaxgear.io.PlanetarySpec.dynamic_meshes`:
    the case's ``[mesh]`` stiffness model, slices and positions per pitch, each pair's
    modifications, the planets phased; each mesh the model its pair case builds,
    :meth:`jaxgear.io.Case.mesh_model`: the stiffness table at the mean planet load), with the
    load-sharing model whose K_γ the rating takes (of ``models``, {name: model}: the last of
    :data:`K_GAMMA_SOURCES` present, as :func:`rating_k_gamma`; the ring rigid, as there), on
    the load-sharing stage (the sun loaded by its torque, ring and
    carrier held) with the case's pin errors and eccentricities, exact contact
    (:func:`jaxgear.planetary.planetary_quasi_static`; ``ring`` its ring model, None: rigid): each
    planet's sun/planet and planet/ring cell loads. None for a stage without gears, or (with a
    one-line ``CaseWarning``) where the contact solve fails at a position."""
    if not case.pairs:
        return None
    name = rating_sharing_model(models)
    meshes = spec.dynamic_meshes(case, case.slices)
    x = meshes.positions(case.positions_per_pitch)
    q = planetary_quasi_static(
        models[name], spec.sharing_stage(stage), meshes,
        np.asarray(abs(spec.torques(case.torque)["sun"])), x,
        np.asarray(spec.tangential_pin_errors), np.asarray(spec.radial_pin_errors),
        ring=RigidRing() if ring is None else ring,
    )
    if np.any(np.asarray(q.result) != 0):
        warnings.warn("[rating] the stage's quasi-static solve on the contact cells did not "
                      "converge at every position: no measured K_Halpha, no root-stress map",
                      CaseWarning, stacklevel=2)
        return None
    kinds = planet_mesh_loads(meshes, x, q.cell_line_load)
    per_position = [np.asarray(f) for f in (q.sun_mesh_forces, q.ring_mesh_forces)]
    forces = tuple(np.mean(f, axis=0) for f in per_position)
    source = STAGE_LOADS.format(model=name, slices=case.slices,
                                positions=case.positions_per_pitch)
    paths = tuple(float(m.path_of_contact) for m in (meshes.sun_mesh, meshes.ring_mesh))
    return StageLoads(tuple(kinds), forces, source, stage_contact_model(meshes), paths,
                      tuple(np.max(f, axis=0) for f in per_position))


def measured_k_h_alpha(loads: StageLoads | None) -> list[dict] | None:
    """The ``rating.measured`` K_Hα of the stage's two rated meshes from its quasi-static loads
    (:func:`stage_loads`): each planet's mesh measured as a pair's
    (:func:`jaxgear.rating.transverse_load_factor`: the load sharing between the tooth pairs in
    contact on the theoretical path, ``loads.paths``), the largest over the planets, with
    :data:`STAGE_ALPHA_SOURCE` and the solve's contact model; None without loads."""
    if loads is None:
        return None
    source = STAGE_ALPHA_SOURCE.format(source=loads.source, n=len(loads.meshes[0]))
    paths = (None, None) if loads.paths is None else loads.paths
    return [MeasuredFactor(planet_transverse_factor(kind, g), source, loads.contact_model).entry()
            for kind, g in zip(loads.meshes, paths, strict=True)]


@functools.singledispatch
def section_cutter(root_section):
    """The ring's pinion-type cutter (:class:`fem_prep.ShaperCutter`) of an internal pair's
    rating ``root_section``: ``None`` for ISO's substitute rack (no cutter given)."""
    return None


@section_cutter.register
def _shaper_section_cutter(root_section: ShaperCutterSection):
    """:class:`jaxgear.rating.ShaperCutterSection`'s cutter (z0, x0, ρ_a0/m_n): the one ISO's σ_F0 of
    the ring is computed with."""
    rho = root_section.tip_radius_coeff
    return fem_prep.ShaperCutter(
        root_section.teeth, float(root_section.profile_shift), None if rho is None else float(rho)
    )


@functools.singledispatch
def _member_tooth(pair, member: int, rating):
    """The tooth form whose FE table maps ``member`` of an external pair:
    :func:`jaxgear.tooth_geometry` (``rating``, the mesh's :class:`jaxgear.io.RatingCase`,
    unused)."""
    return tooth_geometry(pair, member)


@_member_tooth.register
def _internal_member_tooth(pair: InternalGearPair, member: int, rating):
    """The planet as an external member; the ring's tooth generated by the cutter of the
    mesh's rating (:func:`section_cutter` of its root section: the cutter ISO's σ_F0 uses),
    :func:`jaxgear.internal_tooth_geometry` with it (fem_prep's default form of a ring with a
    cutter, :class:`fem_prep.ShaperFillet`); None without a cutter (:data:`RING_ROOT_STRESS`)."""
    if member == 0:
        return tooth_geometry(pair, 0)
    cutter = section_cutter(rating.geometry.root_section)
    return None if cutter is None else internal_tooth_geometry(pair, cutter)


def _member_table(pair, member: int, table, tooth):
    """The FE fillet stress per unit load of ``member`` (0, 1) of a stage mesh's ``pair``
    (``table(tooth, radii)`` as :func:`jaxgear.cli.root_stress_outputs`'s, over the member's
    active profile) for its ``tooth`` (:func:`_member_tooth`'s: the ring's from its cutter, in
    the transverse section), or None for a ring without a cutter (:data:`RING_ROOT_STRESS`)."""
    return None if tooth is None else table(tooth, active_radii(pair, member, ROOT_STRESS_RADII))


@functools.singledispatch
def _form_label(tooth) -> str:
    """What a map's panel adds to the member's name about its tooth form: nothing for an
    external tooth (or a ring not mapped)."""
    return ""


@_form_label.register
def _generated_label(tooth: fem_prep.InternalToothGeometry) -> str:
    return f" (cutter z0 = {tooth.cutter.teeth})"  # the ring's form: its cutter's


def stage_root_stress(case, out: str, k: int, section: dict, loads: StageLoads,
                      table=fillet_table) -> None:
    """Mesh ``k``'s root-stress map (0 sun/planet, 1 planet/ring) into its rating ``section``
    and ``root_stress_map_<mesh>.png`` in ``out``: the most loaded planet's cell loads of the
    stage's quasi-static solve (:func:`stage_loads`, :meth:`StageLoads.most_loaded`) times each
    member's FE fillet stress per unit load (:func:`jaxgear.rating.root_stress_map`,
    :data:`~jaxgear.cli.ROOT_STRESS_RADII` load cases per member, ``table`` by default the
    process-cached :func:`jaxgear.cli.fillet_table`), as a pair's
    (:func:`jaxgear.cli.root_stress_outputs`): ``root_stress.{max_Pa, iso_sigma_F0_Pa,
    fe_over_iso}`` per member [pinion, gear], ``load_radii``, ``planet`` (1-based), ``file``,
    ``source``. The ring's tooth is the one generated by the cutter of the mesh's rating
    (:func:`section_cutter` of its root section, the cutter ISO's σ_F0 uses too); without one the
    ring's entries are None and its panel says :data:`RING_ROOT_STRESS`. The FE stress includes
    what the planet's loads include (its share K_γ of the sun torque, the sharing between tooth
    pairs, the modifications); σ_F0 is ISO's nominal one at the mean planet path's load."""
    pair, planet = case.pairs[k], loads.most_loaded(k)
    mesh = loads.meshes[k][planet]
    rating = ratings_of(case)[k]
    maps, teeth = [], [_member_tooth(pair, i, rating) for i in (0, 1)]
    for i in (0, 1):
        t = _member_table(pair, i, table, teeth[i])
        maps.append(None if t is None else root_stress_map(pair, mesh, i, t.roll, t.peak))
    peak = [None if m is None else float(m.max) for m in maps]
    iso = section["bending"]["sigma_F0_Pa"]
    name = case.mesh_name(k)
    section["root_stress"] = {
        "max_Pa": peak,
        "iso_sigma_F0_Pa": iso,
        "fe_over_iso": [None if p is None else p / q for p, q in zip(peak, iso, strict=True)],
        "load_radii": ROOT_STRESS_RADII,
        "planet": planet + 1,
        "file": f"root_stress_map_{name}.png",
        "source": STAGE_ROOT_STRESS.format(planet=planet + 1, n=len(loads.meshes[k]),
                                           source=loads.source),
    }
    gears = [case.gear_names[g] for g in case.gears[k]]
    names = [g + _form_label(t) if m is not None else f"{g}: root stress\n{RING_ROOT_STRESS}"
             for g, m, t in zip(gears, maps, teeth, strict=True)]
    root_stress_plot(
        os.path.join(out, section["root_stress"]["file"]), maps,
        f"{case.name} {name}: root stress over a tooth passage, planet {planet + 1} (the most "
        "loaded; plane FE × the stage's quasi-static cell loads)", names)


def rating_k_gamma(sharing: dict) -> tuple[float, str]:
    """(K_γ, source) for the rating when ``[rating] K_gamma`` does not give it, from the run's
    load sharing (``summary.json``'s ``load_sharing``, :func:`jaxgear.cli.planetary.
    sharing_summary`): the last model of :data:`K_GAMMA_SOURCES` the run has, i.e. the 3D
    model's where the run has it (a helical stage whose axial and tilting supports hold it,
    :func:`jaxgear.cli.planetary.spatial_model`), else the planar model's; each at the travel 0
    with the case's pin errors and eccentricities."""
    name = rating_sharing_model(sharing)
    return float(sharing[name]["k_gamma"]), K_GAMMA_SOURCES[name]


def rating_section(case, out: str, k_gamma: float, source: str = K_GAMMA_SOURCE,
                   face_load: dict | None = None, loads: StageLoads | None = None,
                   table=fillet_table, k_v: list[dict] | None = None) -> dict | None:
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
    (:func:`jaxgear.cli._rating_report.rated_with_measured`). With the stage's quasi-static
    ``loads`` (:func:`stage_loads`), each mesh's ``measured.K_Halpha`` (:func:`measured_k_h_alpha`,
    the same use) and its root-stress map (:func:`stage_root_stress`, ``table`` the FE fillet
    stress per unit load). With ``k_v`` (:func:`measured_k_v`: the run's planetary speed
    sweep), each mesh's ``measured.K_v``, the same use. ``None`` (nothing written) without
    ``[rating]``."""
    rcs = ratings_of(case)
    if rcs is None:
        return None
    names = [case.mesh_name(k) for k in range(len(rcs))]
    measured = {key: v for key, v in (("K_Hbeta", measured_k_h_beta(face_load)),
                                      ("K_Halpha", measured_k_h_alpha(loads)),
                                      ("K_v", k_v)) if v is not None}
    named = dict.fromkeys(n for rc in rcs for n in rc.use_measured)
    unmeasured = [n for n in named if n not in measured]
    if unmeasured:
        warnings.warn(
            f"[rating] use_measured: {', '.join(unmeasured)} not measured on this planetary "
            "stage's meshes (K_Halpha of a stage given by its gears, K_Hbeta of a helical stage "
            "on its axial and tilting supports, K_v by jaxgear run's speed sweep): rated with "
            "ISO's", CaseWarning, stacklevel=2)
    sections, ratings = [], []
    for k, (name, rc) in enumerate(zip(names, rcs, strict=True)):
        given = rc.k_gamma is not None
        kg = float(rc.k_gamma) if given else float(k_gamma)
        k_a = float(rc.settings.application_factor)
        # K_γ multiplies the load as K_A does (jaxgear.rating.with_load_sharing)
        settings = with_load_sharing(rc.settings, kg)
        rating = RATE(rc.geometry, rc.operating, settings)
        for note in rating.scope_notes():
            warnings.warn(f"[rating] {name}: {note}", CaseWarning, stacklevel=2)
        section = rating.summary()
        section["modification_inputs"] = modification_inputs(rc, rating)
        if measured:
            section["measured"] = {key: v[k] for key, v in measured.items()}
            section, rating = measured_rating(dataclasses.replace(rc, settings=settings), section,
                                              rating)
        if loads is not None:
            stage_root_stress(case, out, k, section, loads, table)
        section["factors"]["K_A"] = {"value": k_a, "source": "given"}
        section |= {  # K_γ of the run's load sharing: its linear mesh springs, no tooth contact
            "K_gamma": ({"value": kg, "source": "given"} if given else
                        MeasuredFactor(kg, source, contact_model(())).entry()),
            "torque_per_planet_path_Nm": float(rc.operating.torque),
            "speed_relative_to_carrier_rad_s": float(rc.operating.speed),
        }
        # [rating.spectrum] (ISO 6336-6): the input's bins carried to the mesh, K_A = 1 K_γ
        spectrum = spectrum_section(rc, out, f"spectrum_{column_tag(name)}.csv", kg)
        if spectrum is not None:
            section["spectrum"] = spectrum
        sections.append(section)
        ratings.append(rating)
    write_rating_md(out, stage_rating_lines(case, sections, ratings))
    return stacked_meshes(names, sections)


def stage_rating_lines(case, sections: list[dict], ratings=None) -> list[str]:
    """``rating.md`` of a planetary stage: one table per mesh of its ``sections`` (each mesh's
    own rating section, :func:`rating_section`'s before stacking), with its K_γ row;
    ``ratings``: each section's :class:`jaxgear.rating.Rating` (None: rated again for the
    report)."""
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
    rcs = ratings_of(case)
    for k, section in enumerate(sections):
        kg = section["K_gamma"]["value"]
        rc = rcs[k]
        settings = with_load_sharing(rc.settings, kg)
        rating = None if ratings is None else ratings[k]
        lines += rating_lines(section, f"{case.name}, mesh {case.mesh_name(k)}", heading="##",
                              inputs=inputs_of(case, k, rc, settings, rating))
        if section.get("spectrum") is not None:  # [rating.spectrum]: the input's, carried
            lines += [""] + spectrum_lines(section["spectrum"], heading="###") + [""]
    return lines


#: where a planetary mesh's root-stress map at speed comes from (:func:`stage_at_speed`)
STAGE_AT_SPEED = (
    "the stage's dynamic run ({model}, {ring}, {slices} slices, {steps} steps per mesh period, "
    "{periods} periods, the last {keep} kept; Newmark, exact contact, the case's modifications "
    "and pin errors) at the operating input speed {speed:.4g} rad/s: its cell loads at the kept "
    "steps × the plane FE fillet stress per unit load; static: the stage's quasi-static solve "
    "at the same slices and mesh travels"
)


#: planets whose largest mesh forces at speed agree within this relative distance are tied and
#: the first of them is mapped (:meth:`StageAtSpeed.most_loaded`): the Newmark solve's
#: equilibrium residue spreads equal paths' peaks by up to ~4e-8 (measured on
#: ``nrel-5mw-planetary`` at 1e-6 of its speed), above :data:`jaxgear.cli.scene.PEAK_RTOL`,
#: and the planets' maps at the same loads differ by up to 3 % (each planet's tooth passage
#: is sampled at its own phase of the steps), so round-off would pick the planet otherwise
SPEED_TIE_RTOL = 1e-6


class StageAtSpeed(NamedTuple):
    """The stage's cell loads over the kept steps of one dynamic run (:func:`stage_at_speed`).

    Attributes:
        meshes: (sun/planet, planet/ring): each a tuple of one :class:`MeshLoads` per planet,
            over the kept steps (t, n_lines, n_slices).
        peak_forces: (sun/planet, planet/ring): each planet's largest transverse mesh force
            over the kept steps (N), (n_planets,).
        nominal_force: T_s / (N r_bs) (N), what the sweep's dynamic factors divide by.
        static: :class:`StageLoads` of the stage's quasi-static solve at the same slices and
            mesh travels (one mesh period); None where its contact solve failed.
        speed: the run's input speed (rad/s). result: its result code (0: successful).
        slices: slices per contact line. steps_per_period: Newmark steps per mesh period.
        source: :data:`STAGE_AT_SPEED` filled in.
    """

    meshes: tuple
    peak_forces: tuple
    nominal_force: float
    static: StageLoads
    speed: float
    result: int
    slices: int
    steps_per_period: int
    source: str

    def most_loaded(self, k: int) -> int:
        """The planet (0-based) whose mesh of kind ``k`` carries the largest force at speed, the
        first of those within :data:`SPEED_TIE_RTOL` (1e-6) of it: equal paths tie as in
        :meth:`StageLoads.most_loaded`, whatever the dynamic solve's residue decides."""
        return first_peak(self.peak_forces[k], SPEED_TIE_RTOL)


def stage_at_speed(case, spec, stage, models: dict, dynamics, meshes, words: dict,
                   ring=None) -> StageAtSpeed:
    """The stage's cell loads at speed from one dynamic run ``dynamics``
    (:class:`jaxgear.planetary.PlanetaryDynamics` of ``meshes``, a
    :class:`~jaxgear.planetary.ContactMeshes`, with ``PlanetaryRun(cell_loads=True)``): each cell's
    line load, its force over its length (N/m), placed at each kept step's travel by
    :meth:`jaxgear.planetary.ContactMeshes.planet_cells`; beside it the stage's quasi-static solve
    (:func:`stage_loads` with ``models``, the ring model ``ring``, None: rigid) at the same
    slices and the same travels modulo the mesh period (``positions_per_pitch`` = the run's
    steps per period: both at the mid-points (i + 1/2) p_b / S). ``words``: ``model``,
    ``ring``, ``periods``, ``keep`` and ``speed`` (rad/s, the input's) for
    :data:`STAGE_AT_SPEED`. Raises ``ValueError`` (one line) for a run without cell forces."""
    if dynamics.cell_forces is None:
        raise ValueError("stage_at_speed: dynamics.cell_forces is None: allowed a run of "
                         "PlanetaryRun(cell_loads=True)")
    x = np.asarray(dynamics.travel)
    slices = int(meshes.sun_mesh.n_slices)
    steps = x.size // int(words["keep"])
    kinds = planet_mesh_loads(meshes, x, dynamics.cell_forces, per_length=True)
    static = stage_loads(case.replace(slices=slices, positions_per_pitch=steps), spec, stage,
                         models, ring)
    peaks = tuple(np.max(np.asarray(f), axis=0)
                  for f in (dynamics.sun_mesh_forces, dynamics.ring_mesh_forces))
    source = STAGE_AT_SPEED.format(slices=slices, steps=steps, **words)
    return StageAtSpeed(kinds, peaks, float(dynamics.static_force), static,
                        float(words["speed"]), int(dynamics.result), slices, steps, source)


def _period_envelope(rmap, steps: int):
    """A map over the kept steps reduced to one mesh period (the cells repeat every period):
    each cell's largest stress over the kept periods, the last period's cells (what
    ``root_stress_map_<mesh>_speed.png`` draws)."""
    def last(a):
        a = np.asarray(a)
        return a.reshape((-1, steps) + a.shape[1:])[-1]

    stress = np.asarray(rmap.stress)
    stress = stress.reshape((-1, steps) + stress.shape[1:]).max(axis=0)
    return RootStressMap(stress, last(rmap.roll), last(rmap.cell_s), last(rmap.cell_z),
                         last(rmap.mask))


def _mesh_at_speed(case, out: str, k: int, section: dict, at: StageAtSpeed, table) -> None:
    """Mesh ``k``'s ``root_stress.at_speed`` (:func:`rating_at_speed`) into its ``section`` and
    ``root_stress_map_<mesh>_speed.png`` into ``out``."""
    pair, rating, name = case.pairs[k], ratings_of(case)[k], case.mesh_name(k)
    planet, still = at.most_loaded(k), at.static.peak_planet(k)
    fast, rest = at.meshes[k][planet], at.static.meshes[k][still]
    maps, static = [], []
    for i in (0, 1):
        tooth = _member_tooth(pair, i, rating)
        t = _member_table(pair, i, table, tooth)
        maps.append(None if t is None else root_stress_map(pair, fast, i, t.roll, t.peak))
        static.append(None if t is None else root_stress_map(pair, rest, i, t.roll, t.peak))
    peak = [None if m is None else float(m.max) for m in maps]
    still_peak = [None if m is None else float(m.max) for m in static]
    section["root_stress"]["at_speed"] = {
        "speed_rad_s": at.speed,
        "max_Pa": peak,
        "static_max_Pa": still_peak,
        "ratio": [None if a is None else a / b for a, b in zip(peak, still_peak, strict=True)],
        "dynamic_factor": float(at.peak_forces[k][planet]) / at.nominal_force,
        "dynamic_factor_tooth": fast.tooth_force() / rest.tooth_force(),
        "planet": planet + 1,
        "static_planet": still + 1,
        "slices": at.slices,
        "steps_per_period": at.steps_per_period,
        "result": at.result,
        "file": f"root_stress_map_{name}_speed.png",
        "speed_of": f"the operating input speed, planet {planet + 1}: the largest mesh force "
                    "at speed",
        "static_of": f"the stage's quasi-static solve at the same {at.slices} slices and mesh "
                     f"travels, planet {still + 1}",
        "source": at.source,
    }
    gears = [case.gear_names[g] for g in case.gears[k]]
    names = [g if m is not None else f"{g}: root stress\n{RING_ROOT_STRESS}"
             for g, m in zip(gears, maps, strict=True)]
    root_stress_plot(
        os.path.join(out, section["root_stress"]["at_speed"]["file"]),
        [None if m is None else _period_envelope(m, at.steps_per_period) for m in maps],
        f"{case.name} {name} at {at.speed:.4g} rad/s (input): root stress, planet {planet + 1}, "
        "largest over the kept periods (FE × dynamic cell loads)",
        names)


def rating_at_speed(case, out: str, rating: dict, at: StageAtSpeed,
                    table=fillet_table) -> dict:
    """The stage's ``rating`` section (:func:`rating_section`'s, stacked per mesh) with each
    mesh's root stress at speed (returned; ``rating.md`` rewritten): the loads ``at``
    (:func:`stage_at_speed`) of the planet whose mesh carries the largest force at speed
    (:meth:`StageAtSpeed.most_loaded`, per mesh kind) times each member's FE fillet stress per
    unit load (:func:`jaxgear.rating.root_stress_map`, the same tables as the quasi-static map,
    ``table``), and the static map of the quasi-static solve at the same slices and travels
    (its planet with the largest mesh force, :meth:`StageLoads.peak_planet`: the same pick
    as at speed, so that the ratio is 1 in the quasi-static limit). Adds
    ``root_stress.at_speed`` per mesh, the pairs' keys
    (:func:`jaxgear.cli.at_speed_sections`: ``speed_rad_s`` (the input's), ``max_Pa``,
    ``static_max_Pa``, ``ratio`` per member [pinion, gear], ``dynamic_factor`` (the planet's
    largest mesh force over T_s/(N r_bs), the sweep's definition), ``dynamic_factor_tooth``
    (its largest tooth force over the static one), ``slices``, ``result``, ``source``) and
    ``planet``, ``static_planet`` (1-based), ``steps_per_period``, ``file``
    (``root_stress_map_<mesh>_speed.png``: each cell's largest stress over the kept periods),
    ``speed_of``, ``static_of`` (rating.md's words); a ring without its cutter ``None`` as in
    the quasi-static map. Unchanged without a quasi-static root-stress map, or without the
    static solve beside the run (its contact solve failed: :func:`stage_loads`' warning)."""
    if rating.get("root_stress") is None or at.static is None:
        return rating
    rest = dict(rating)
    names = rest.pop("meshes")  # each mesh's own section (the inverse of stacked_meshes)
    sections = [_pick(rest, k) for k in range(len(names))]
    for k, section in enumerate(sections):
        _mesh_at_speed(case, out, k, section, at, table)
    write_rating_md(out, stage_rating_lines(case, sections))
    return stacked_meshes(names, sections)
