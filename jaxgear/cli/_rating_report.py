"""``jaxgear run``'s load-capacity outputs for a case with a ``[rating]`` table: the
``summary.json`` section (:meth:`jaxgear.rating.Rating.summary`) and ``rating.md``, the factors the
way rating reports print them (symbol, value per gear, the standard's part and clause title),
written atomically."""

from __future__ import annotations

import functools
import os
import warnings
from typing import NamedTuple

import numpy as np

from .. import MeshModel, quasi_static, tooth_geometry
from ..dynamics import Outputs, simulate
from ..io import (
    Case,
    CaseWarning,
    PairForm,
    RatingCase,
    TrainForm,
    atomic_open,
    build_dynamic_model,
    ratings_of,
    spec_integrator,
    spec_window,
)
from ..rating import (
    MeasuredFactor,
    contact_model,
    dynamic_factor_at,
    face_load_factor,
    root_stress_map,
    transverse_load_factor,
    with_measured,
)
from ._bearing_report import bearing_rating_lines
from ._plots import root_stress_plot
from ._rating_inputs import modification_inputs
from ._rating_sheet import RATE, inputs_of, k_v_note, rating_lines
from ._spectrum_report import spectrum_lines, spectrum_section
from ._stress_outputs import active_radii, fillet_table
from ._sweep_json import column_tag
from ._tribology_run import tribology_rating_lines

__all__ = [
    "RATE",
    "ROOT_STRESS_RADII",
    "SCENE_MODELS",
    "ModelLoads",
    "at_speed_sections",
    "measured_dynamic_factor",
    "measured_factors",
    "measured_rating",
    "rated_with_measured",
    "rating_lines",
    "rating_outputs",
    "rating_table_lines",
    "root_stress_at_speed",
    "root_stress_outputs",
    "scene_loads",
    "stacked_meshes",
    "train_loads",
    "train_mesh_results",
    "write_rating_table",
    "write_rating_md",
]


def _lines(case: Case, k: int, section: dict, title: str, heading: str = "#",
           rating=None) -> list[str]:
    """Mesh ``k``'s ``rating.md`` lines (:func:`rating_lines`, with its inputs:
    :func:`jaxgear.cli._rating_sheet.inputs_of`; ``rating`` the :class:`jaxgear.rating.Rating` of
    ``section`` where the caller has it, else the report rates the section again)."""
    rc = ratings_of(case)[k]
    return rating_lines(section, title, heading, inputs_of(case, k, rc, rating=rating))


@functools.singledispatch
def _stack(first, values: list):
    """Per-mesh lists of the meshes' summary values (a train's ``rating`` section)."""
    return list(values)


@_stack.register(dict)
def _(first, values: list):
    return {k: _stack(v, [s[k] for s in values]) for k, v in first.items()}


@functools.singledispatch
def _section_and_table(form, case: Case, sections: list[dict],
                       ratings=None) -> tuple[dict, list[str]]:
    """The case's ``rating`` section and ``rating.md`` lines of its meshes' ``sections``
    (``ratings``: each section's :class:`jaxgear.rating.Rating`, or None: rated again for the
    report)."""
    raise TypeError(f"rating_outputs: no rating report for a case of form {type(form).__name__}")


@_section_and_table.register
def _(form: PairForm, case: Case, sections: list[dict], ratings=None) -> tuple[dict, list[str]]:
    """A pair: its one mesh's section, the case's table."""
    rating = None if ratings is None else ratings[0]
    lines = _lines(case, 0, sections[0], case.name, rating=rating)
    if sections[0].get("spectrum") is not None:  # [rating.spectrum]: ISO 6336-6
        lines += [""] + spectrum_lines(sections[0]["spectrum"])
    return sections[0], lines


@_section_and_table.register
def _(form: TrainForm, case: Case, sections: list[dict], ratings=None) -> tuple[dict, list[str]]:
    """A train: per-mesh lists (``meshes`` names them, in the order of ``[[meshes]]``; per-gear
    values [driving, driven] per mesh); ``rating.md`` one section per mesh."""
    names = [case.mesh_name(k) for k in range(len(sections))]
    lines = [
        f"# {case.name}: load capacity of every mesh",
        "",
        "Each mesh rated with its driving gear as the pinion (pinion / gear = driving / "
        "driven), at its driving gear's torque and speed. A gear in two meshes is rated in each; "
        "an idler (driven in one mesh, driving in the other) has its teeth loaded on alternate "
        "flanks: Y_M = 0.7 (ISO 6336-3:2019, mean stress influence factor).",
        "",
    ]
    for k, (name, sec) in enumerate(zip(names, sections, strict=True)):
        rating = None if ratings is None else ratings[k]
        lines += _lines(case, k, sec, f"{case.name}, mesh {name}", heading="##",
                        rating=rating) + [""]
        if sec.get("spectrum") is not None:  # [rating.spectrum]: the input's, carried
            lines += spectrum_lines(sec["spectrum"], heading="###") + [""]
    return stacked_meshes(names, sections), lines


def stacked_meshes(names: list[str], sections: list[dict]) -> dict:
    """The ``rating`` section of several meshes (a train's, a planetary stage's): each summary
    value as a per-mesh list, ``meshes`` naming them; ``method`` once when every mesh has the
    same edition (a mesh's table may set another)."""
    out = {"meshes": names} | _stack(sections[0], sections)
    methods = out["method"]
    out["method"] = methods[0] if len(set(methods)) == 1 else methods
    return out


def write_rating_md(out_dir: str, lines: list[str]) -> None:
    """``rating.md`` of ``lines``, written atomically into ``out_dir``."""
    with atomic_open(os.path.join(out_dir, "rating.md"), "w") as f:
        f.write("\n".join(lines) + "\n")


#: the model of the rigid mesh alone (both bodies rigid, no shafts), as a measured factor's
#: source names it
RIGID_MESH = "rigid mesh"
MEASURED = (
    "jaxgear load map ({model}, exact contact, case modifications, mesh-period mean): largest "
    "load per unit face width over its mean"
)
USED = "measured (rating.measured, [rating] use_measured; K_Halpha/K_Falpha within ISO's limits)"
MEASURED_ALPHA = (
    "jaxgear load map ({model}, exact contact, case modifications): largest mean line load "
    "of one tooth pair over that of all loaded cells, max over a mesh period"
)


class ModelLoads(NamedTuple):
    """The quasi-static load maps of the model a case runs, when it is more than the rigid mesh
    (a lumped or hybrid pair scene, a coupled train): what ``jaxgear run`` already solved,
    handed to :func:`rating_outputs` for the measured K_Hβ and K_Hα.

    Attributes:
        results: one one-mesh result per mesh of the case, in the case's mesh order, each with
            ``line_load`` (N/m) and ``cell_mask`` (P, L, N) over whole mesh periods (a pair
            scene's :class:`jaxgear.QuasiStaticResult`; a train's ``result.meshes[k]``).
        model: what the model is, as the factors' ``source`` names it (e.g. "lumped scene:
            shafts and bearings", "hybrid scene: condensed bodies", "coupled train: ...").
        meshes: the model's mesh models (its scene's ``base_planes``, the case's mesh order):
            the contact model each factor states (:func:`jaxgear.rating.contact_model`).
    """

    results: tuple
    model: str
    meshes: tuple


#: what each pair scene model of ``jaxgear run`` is (:func:`jaxgear.cli.scene.scene_model`'s
#: names), as a measured factor's source names it
SCENE_MODELS = {
    "lumped3d": "lumped scene: shafts and bearings",
    "hybrid": "hybrid scene: condensed bodies, shafts and bearings",
}
#: what a scene model's load map includes at a speed ω > 0 (rad/s), after its words
_AT_SPEED = {"lumped3d": "", "hybrid": ", at {:.4g} rad/s (centrifugal loads)"}


def scene_loads(curves: dict | None, speed: float) -> ModelLoads | None:
    """The :class:`ModelLoads` of a pair's quasi-static scene as ``jaxgear run`` solved it
    (:func:`jaxgear.cli.scene.scene_outputs`' ``curves``: its ``model``, its scene's
    ``base_planes`` and its exact-contact result with the case's modifications, at the case's
    ``speed`` (rad/s; a hybrid scene's centrifugal loads)); None without a scene."""
    if not curves:
        return None
    kind = curves["model"]
    model = SCENE_MODELS[kind] + (_AT_SPEED[kind].format(speed) if speed > 0 else "")
    return ModelLoads(tuple(curves["results"]["exact"].meshes), model,
                      tuple(curves["base_planes"]))


def train_loads(case: Case, result, meshes: tuple | None = None) -> ModelLoads:
    """The :class:`ModelLoads` of a train's coupled quasi-static solve ``result`` (every mesh
    at once on the train's structure, exact contact, the case's modifications:
    :func:`jaxgear.cli.train.run_train`'s), its model named by the train's scene; ``meshes``
    the structure's mesh models (its ``base_planes``; None: the case's own,
    :meth:`jaxgear.io.Case.mesh_models`, which the structure is built of)."""
    if case.flexible:
        what = "condensed bodies, shafts and bearings"
    elif case.lumped:
        what = "shafts and bearings"
    else:
        what = "torsional"
    planes = case.mesh_models() if meshes is None else meshes
    return ModelLoads(tuple(result.meshes), f"coupled train: {what}", tuple(planes))


def rated_with_measured(rc: RatingCase, section: dict) -> dict:
    """:func:`measured_rating`'s section."""
    return measured_rating(rc, section)[0]


def measured_rating(rc: RatingCase, section: dict, rating=None) -> tuple:
    """(section, rating): the section rated again with the measured factors ``rc.use_measured``
    names that ``section["measured"]`` holds in place of the standard's (their source
    "measured"; :func:`jaxgear.rating.with_measured`), the section's other entries
    (``measured``, ``root_stress``) kept, and the :class:`jaxgear.rating.Rating` it is the summary
    of. Nothing to use: the section itself and ``rating`` (the section's own rating, if the caller
    has it). Rated on ``rc``'s settings (a planetary mesh's with K_γ folded into K_A:
    :func:`jaxgear.cli.planetary.rating_section`)."""
    measured = section.get("measured", {})
    use = {n: measured[n]["value"] for n in rc.use_measured if n in measured}
    if not use:
        return section, rating
    # the model's settings with them given (jaxgear.rating.with_measured: as the standard ties
    # them, ISO's K_Fα = K_Hα within its limits); the factors they set are sourced "measured"
    settings = with_measured(rc.geometry, rc.settings, use)
    rated = RATE(rc.geometry, rc.operating, settings)
    out = rated.summary()
    for name in use:
        for f in rc.settings.standard.measured_factors(name):
            out["factors"][f]["source"] = USED
    return section | out, rated


@functools.singledispatch
def _per_mesh(form, result) -> list:
    """The one-mesh results of ``rating_outputs``' ``result``, by the case's form."""
    raise TypeError(f"rating_outputs: no results for a case of form {type(form).__name__}")


@_per_mesh.register
def _(form: PairForm, result) -> list:  # a pair's one result
    return [result]


@_per_mesh.register
def _(form: TrainForm, result) -> list:  # a train's: one per mesh
    return list(result)


def _path(mesh, result) -> float | None:
    """The theoretical path g_α (m) on which the measured K_Hα reads its pairs
    (:func:`jaxgear.rating.transverse_load_factor`): ``mesh``'s where it has contact beyond the
    path and ``result`` places its cells (``cell_s``); None (every cell a pair's) otherwise."""
    beyond = isinstance(mesh, MeshModel) and mesh.contact_geometry.reaches_beyond_path
    if beyond and hasattr(result, "cell_s"):
        return float(mesh.path_of_contact)
    return None


def _factors(result, model: str, mesh, suffix: str = "") -> dict:
    """K_Hβ and K_Hα measured on one mesh's load map ``result`` of ``model`` (a source's name)
    whose mesh model is ``mesh`` (the contact model they state:
    :func:`jaxgear.rating.contact_model`), as ``rating.measured`` entries (keys with
    ``suffix``; :class:`jaxgear.rating.MeasuredFactor`)."""
    words = contact_model(mesh)
    return {
        f"K_Hbeta{suffix}": MeasuredFactor(
            float(face_load_factor(result)), MEASURED.format(model=model), words).entry(),
        f"K_Halpha{suffix}": MeasuredFactor(
            float(transverse_load_factor(result, path_of_contact=_path(mesh, result))),
            MEASURED_ALPHA.format(model=model),
            words).entry(),
    }


def measured_factors(rigid, model: ModelLoads | None, k: int, mesh=None) -> dict:
    """Mesh ``k``'s ``rating.measured`` K_Hβ and K_Hα: of the model the case runs (``model``'s
    result; without one, the rigid mesh ``rigid`` is that model), and beside them, when the
    case runs more than the rigid mesh, the rigid mesh's as ``K_Hbeta_rigid_mesh``,
    ``K_Halpha_rigid_mesh``. ``mesh``: the rigid mesh's :class:`jaxgear.MeshModel` (the
    contact model its rows state; None: the model's mesh ``k``, which the case builds alike);
    the model's rows state its own mesh ``k``'s."""
    if model is None:
        if mesh is None:
            raise ValueError("measured_factors: mesh = None is out of range: allowed the rigid "
                             "mesh's MeshModel (its rows state its contact model)")
        return _factors(rigid, RIGID_MESH, mesh)
    own = model.meshes[k]
    return (_factors(model.results[k], model.model, own)
            | _factors(rigid, RIGID_MESH, own if mesh is None else mesh, "_rigid_mesh"))


def rating_outputs(
    case: Case,
    out_dir: str,
    result=None,
    root_stress=None,
    model: ModelLoads | None = None,
    *,
    meshes: tuple | None = None,
    write_table: bool = True,
) -> dict | None:
    """The rating of a case with ``[rating]``: writes ``rating.md`` into ``out_dir`` and returns
    the ``summary.json`` section; ``None`` (nothing written) without ``[rating]``. A pair: its
    section (with ``[rating.spectrum]`` its ``spectrum`` entry and ``spectrum.csv``:
    :func:`jaxgear.cli._spectrum_report.spectrum_section`); a train: every mesh rated (:func:`jaxgear.io.ratings_of`), per-mesh lists and a
    table per mesh.

    Args:
        result: a pair's quasi-static result of its rigid mesh, or a train's tuple of one per
            mesh (each mesh alone: :func:`train_mesh_results`), for the sections' ``measured``
            factors (K_Hβ: :func:`jaxgear.rating.face_load_factor`, K_Hα:
            :func:`jaxgear.rating.transverse_load_factor`); reported beside the ISO/given ones, and
            rated with in their place when ``[rating] use_measured`` names them (the factors'
            source then "measured").
        root_stress: with ``result``, a table of the FE fillet stress per unit load
            (``table(tooth, radii)``, e.g. :func:`fillet_table`): each mesh's root-stress map
            too (:func:`root_stress_outputs`; a train's plots ``root_stress_map_<mesh>.png``).
        model: with ``result``, the load maps of the model the case runs when it is more than
            the rigid mesh (:class:`ModelLoads`: a pair's lumped or hybrid scene, a train's
            coupled solve), as solved already by the run: the measured ``K_Hbeta`` and
            ``K_Halpha`` (the ones ``use_measured`` rates with) are then that model's, each
            source naming it, and the rigid mesh's are kept beside them as
            ``K_Hbeta_rigid_mesh`` and ``K_Halpha_rigid_mesh``. The root-stress map stays the
            rigid mesh's.
        meshes: with ``result``, the mesh models ``result`` was solved on (the case's mesh
            order): the contact model every measured row states
            (:func:`jaxgear.rating.contact_model`); None: the case's own
            (:meth:`jaxgear.io.Case.mesh_models`, which the rigid meshes are built of).
        write_table: write ``rating.md`` (``jaxgear run`` writes it once, at the end:
            :func:`write_rating_table`).
    """
    rcs = ratings_of(case)
    if rcs is None:
        return None
    results = None if result is None else _per_mesh(case.form, result)
    if results is not None and meshes is None:
        meshes = case.mesh_models()
    sections, ratings = [], []
    for k, rc in enumerate(rcs):
        rating = RATE(rc.geometry, rc.operating, rc.settings)
        label = case.mesh_label(k)
        for note in rating.scope_notes():
            where = f"[rating] {label}: " if label else "[rating] "
            warnings.warn(f"{where}{note}", CaseWarning, stacklevel=2)
        section = rating.summary() | {"modification_inputs": modification_inputs(rc, rating)}
        if results is not None:
            section["measured"] = measured_factors(results[k], model, k, meshes[k])
            section, rating = measured_rating(rc, section, rating)
            if root_stress is not None:
                name = f"root_stress_map_{label}.png" if label else "root_stress_map.png"
                title = f"{case.name}{' ' + label if label else ''}"
                _root_stress(
                    case.pairs[k],
                    results[k],
                    section,
                    root_stress,
                    os.path.join(out_dir, name),
                    title,
                    float(rc.operating.torque),
                )
        # [rating.spectrum] (ISO 6336-6): a train's mesh its input's, carried to the mesh
        csv_name = f"spectrum_{column_tag(label)}.csv" if label else "spectrum.csv"
        spectrum = spectrum_section(rc, out_dir, csv_name)
        if spectrum is not None:
            section["spectrum"] = spectrum
        sections.append(section)
        ratings.append(rating)
    section, lines = _section_and_table(case.form, case, sections, ratings)
    if write_table:
        write_rating_md(out_dir, lines)
    return section


def write_rating_table(
    case: Case, out_dir: str, section: dict, tribology: dict | None = None,
    bearings: dict | None = None,
) -> None:
    """``rating.md`` of the case's final ``rating`` ``section`` (``summary.json``'s: a train's
    per-mesh lists), written atomically into ``out_dir``: ``jaxgear run`` writes it once, after
    every step that adds to the section (the measured K_v, the root stress at speed); with the
    run's ``tribology`` section, its scuffing and micropitting lines after the rating's; with
    its ``bearings`` section, the rolling bearings' lives after those
    (:func:`jaxgear.cli._bearing_report.bearing_rating_lines`)."""
    lines, extra = rating_table_lines(case, section), tribology_rating_lines(tribology, case)
    extra += bearing_rating_lines(bearings)
    if extra and lines and not lines[-1]:
        extra = extra[1:]  # one blank line between
    write_rating_md(out_dir, lines + extra)


def rating_table_lines(case: Case, section: dict) -> list[str]:
    """The lines of ``rating.md`` of a pair's or a train's ``rating`` ``section``
    (``summary.json``'s; a train's per-mesh lists): each mesh's report
    (:func:`jaxgear.cli._rating_sheet.rating_lines` with the case's inputs and published
    values), what :func:`write_rating_table` writes."""
    return _section_and_table(case.form, case, _mesh_sections(case.form, section))[1]


def train_mesh_results(case: Case) -> tuple | None:
    """Each mesh's quasi-static result on its own rigid mesh (exact contact, its gears'
    modifications, its driving gear's torque, the case's positions per pitch over one mesh
    period: :meth:`jaxgear.io.Case.mesh_case`), for a case with ``[rating]`` (else None): the
    load maps a train's root-stress maps and its ``K_Hbeta_rigid_mesh``,
    ``K_Halpha_rigid_mesh`` are read from, as a pair's are from its rigid mesh (the measured
    ``K_Hbeta``, ``K_Halpha`` of ``jaxgear run`` are the coupled train's: :func:`train_loads`)."""
    if ratings_of(case) is None:
        return None
    cases = [case.mesh_case(k) for k in range(len(case.pairs))]
    return tuple(
        quasi_static(
            c.mesh_model(), c.modifications, c.torque, positions_per_pitch=c.positions_per_pitch
        )
        for c in cases
    )


def measured_dynamic_factor(
    case: Case, out_dir: str, summary: dict, dynamics: dict, *, meshes: tuple | None = None,
    write_table: bool = True
) -> None:
    """K_v measured by jaxgear beside ISO's, for a case with ``[rating]`` (else nothing), per
    mesh: the dynamic factor of the case's speed sweep (``summary.json``'s ``dynamics``:
    ``speeds_rad_s``, the pinion's (a train: the input's) speeds, ``dynamic_factor``, a train's
    ``dynamic_factor_mesh`` of each mesh, ``model``, ``slices``) interpolated linearly at the
    rating's input speed, added to each mesh's ``rating.measured`` (the mesh rated again with
    it when ``[rating] use_measured`` names ``K_v``) and ``rating.md`` rewritten (unless
    ``write_table`` is False: ``jaxgear run`` writes it once, at its end). A rating
    speed outside the swept range adds nothing (the sweep says nothing there). ISO 6336-1's K_v
    and the sweep's dynamic factor are both the largest dynamic load of the mesh over its
    static one (the sweep's: the mesh force over a mesh period at steady state, of the scene's
    model, over the static mesh force; a train's each mesh's own: :func:`_mesh_curves`). Each
    entry says whether it is comparable with ISO's (``comparable``, ``note``: the mesh
    frequency against ISO's mesh resonance, :func:`jaxgear.cli._rating_sheet.k_v_note`) and
    the contact model of the sweep's meshes (``meshes``, the sweep's scene's mesh models in the
    case's mesh order; None: the case's own at the sweep's ``slices``,
    :meth:`jaxgear.io.Case.mesh_models`, which its scene is built of;
    :func:`jaxgear.rating.contact_model`)."""
    rcs = ratings_of(case)
    if rcs is None:
        return
    speeds = np.asarray(dynamics["speeds_rad_s"], dtype=float)
    speed = _input_speed(case, rcs)
    if not speeds[0] <= speed <= speeds[-1]:
        return
    sections = _mesh_sections(case.form, summary["rating"])
    if meshes is None:
        meshes = case.mesh_models(dynamics.get("slices"))
    ratings = []
    for k, curve in enumerate(_mesh_curves(dynamics, len(rcs))):
        label = case.mesh_label(k)
        source = (
            f"jaxgear speed sweep ({dynamics['model']} scene, {dynamics['slices']} slices), "
            f"interpolated at {speed:.4g} rad/s"
            + (f" of the input (mesh {label}'s dynamic factor)" if label else "")
        )
        value = dynamic_factor_at(speeds, curve, speed)
        rc = rcs[k]
        rating = RATE(rc.geometry, rc.operating, rc.settings)
        n = float(rating.factors.details["resonance_ratio_N"])
        mesh_hz = rc.geometry.teeth[0] * float(rc.operating.speed) / (2 * np.pi)
        contact = contact_model(meshes[k])
        comparable, note = k_v_note(
            mesh_hz, mesh_hz / n, "ISO 6336-1's mesh resonance z₁ n_E1", contact
        )
        sections[k].setdefault("measured", {})["K_v"] = MeasuredFactor(
            value, source, contact, comparable, note).entry()
        sections[k], rated = measured_rating(rcs[k], sections[k])
        ratings.append(rated)  # None: the section was not rated again here
    summary["rating"] = _write_sections(case, out_dir, sections, write_table, ratings)


def _input_speed(case: Case, rcs) -> float:
    """The rating's speed of the case's input (rad/s; a pair's pinion): the speed axis of a
    sweep (mesh 0's driving gear turns at its layout ratio to the input)."""
    driving = case.gears[0][0]
    return float(rcs[0].operating.speed) / abs(float(case.layout().ratios[driving]))


def _mesh_curves(dynamics: dict, n: int) -> list[np.ndarray]:
    """Each mesh's dynamic factor against the sweep's speeds: a train's ``dynamic_factor_mesh``
    (speeds × meshes) by column, a pair's (one mesh) ``dynamic_factor``."""
    per = dynamics.get("dynamic_factor_mesh")
    if per is None:
        return [np.asarray(dynamics["dynamic_factor"], dtype=float)]
    per = np.asarray(per, dtype=float).reshape(-1, n)
    return [per[:, k] for k in range(n)]


@functools.singledispatch
def _pick(value, k: int):
    """Mesh ``k``'s entry of a train's stacked ``rating`` value (:func:`_stack`); a value
    common to the meshes (the one edition's ``method``) as it is."""
    return value


@_pick.register(list)
def _(value, k: int):
    return value[k]


@_pick.register(dict)
def _(value, k: int):
    return {key: _pick(v, k) for key, v in value.items()}


@functools.singledispatch
def _mesh_sections(form, section: dict) -> list[dict]:
    """The one-mesh sections of a case's ``rating`` section (the inverse of
    :func:`_section_and_table`): a pair's, itself; a train's, each mesh's entry of its
    per-mesh lists."""
    raise TypeError(f"rating: no mesh sections for a case of form {type(form).__name__}")


@_mesh_sections.register
def _(form: PairForm, section: dict) -> list[dict]:
    return [section]


@_mesh_sections.register
def _(form: TrainForm, section: dict) -> list[dict]:
    rest = dict(section)
    names = rest.pop("meshes")
    return [_pick(rest, k) for k in range(len(names))]


def _write_sections(case: Case, out_dir: str, sections: list[dict], write_table: bool,
                    ratings=None) -> dict:
    """The case's ``rating`` section of its meshes' ``sections`` (a train's per-mesh lists),
    ``rating.md`` rewritten with them when ``write_table`` (``ratings``: each section's
    :class:`jaxgear.rating.Rating` or None, as :func:`_section_and_table`); returns the section."""
    section, lines = _section_and_table(case.form, case, sections, ratings)
    if write_table:
        write_rating_md(out_dir, lines)
    return section


# ------------------------------------------------------------------------------------------
# the root-stress map of jaxgear run

#: FE load cases per member over its active profile (one factorisation each member): the map
#: interpolates linearly between them (within 0.5 % of a direct solve at 9 radii; the
#: rating page of the documentation)
ROOT_STRESS_RADII = 9
ROOT_STRESS = (
    "plane FE tooth (fem_prep.fillet_influence, m_n/18; ISO's normal section: the virtual spur "
    "tooth of a helical gear, each load at its height) × the rigid mesh's quasi-static cell "
    "loads (exact contact, case modifications), largest over the passage"
)


def _root_stress(pair, result, section, table, path: str, title: str, torque: float) -> None:
    """One mesh's root-stress map (:func:`root_stress_outputs`) into ``section`` and ``path``."""
    maps = _member_maps(pair, result, table)
    peak = [float(m.max) for m in maps]
    iso = section["bending"]["sigma_F0_Pa"]
    section["root_stress"] = {
        "max_Pa": peak,
        "iso_sigma_F0_Pa": iso,
        "fe_over_iso": [p / q for p, q in zip(peak, iso, strict=True)],
        "load_radii": ROOT_STRESS_RADII,
        "source": ROOT_STRESS,
    }
    root_stress_plot(
        path,
        maps,
        f"{title}: root stress over a tooth passage at {torque:g} N·m (plane FE × quasi-static "
        "cell loads)",
    )


def root_stress_outputs(
    case: Case, out_dir: str, result, section: dict, table=fillet_table
) -> None:
    """The root-stress map of a one-mesh case with ``[rating]`` (``section``: its
    :func:`rating_outputs` section, completed here): each cell's load of ``result`` (the rigid
    mesh's quasi-static result at the case torque) times the plane FE tooth's fillet stress per
    unit load at the cell's position (:func:`jaxgear.rating.root_stress_map`,
    :data:`ROOT_STRESS_RADII` load cases per member, cached per tooth form by
    :func:`fillet_table`). Adds ``section["root_stress"]``: ``max_Pa`` (the largest root stress
    of each gear over the passage, [pinion, gear]), ``iso_sigma_F0_Pa`` (ISO 6336-3's nominal
    σ_F0 of the rating, no load factor) and ``fe_over_iso``; writes ``root_stress_map.png``
    (each member's stress against the load's position s and z across the face) and rewrites
    ``rating.md`` with the two rows. ``table(tooth, radii)``: the FE fillet stress per unit
    load (``.roll``, ``.peak``), by default :func:`fillet_table`. The FE stress includes what
    the load map includes (load sharing between pairs, tip relief, the face load
    distribution): it is a stress at the case torque, to be compared with σ_F0, not σ_F (which
    adds K_A K_v K_Fβ K_Fα). A train: ``rating_outputs(..., root_stress=fillet_table)``."""
    path = os.path.join(out_dir, "root_stress_map.png")
    _root_stress(case.pair, result, section, table, path, case.name, float(case.torque))
    write_rating_md(out_dir, _lines(case, 0, section, case.name))  # rated from the section


def _member_maps(pair, result, table) -> list:
    """Both members' root-stress maps of ``result``'s cell loads (:data:`ROOT_STRESS_RADII` FE
    load cases per member, ``table`` as :func:`root_stress_outputs`)."""
    maps = []
    for i in (0, 1):
        t = table(tooth_geometry(pair, i), active_radii(pair, i, ROOT_STRESS_RADII))
        maps.append(root_stress_map(pair, result, i, t.roll, t.peak))
    return maps


def root_stress_at_speed(
    case: Case,
    out_dir: str,
    summary: dict,
    dynamics: dict,
    table=fillet_table,
    run=None,
    *,
    write_table: bool = True,
) -> None:
    """The root-stress map at speed, for a case with ``[rating]`` and a speed sweep (else
    nothing): the case's dynamic model (the sweep's: ``dynamics["slices"]`` slices, the
    ``[scene]`` settings) run once at the speed of the sweep's largest dynamic factor
    (``dynamics["speed_of_max_rad_s"]``; a train's: of its worst mesh, the input's speed) with
    its cell loads recorded (:func:`jaxgear.dynamics.simulate`, ``Outputs(cell_loads=True)``),
    then each mesh's map (:func:`at_speed_sections`); rewrites ``rating.md`` (with
    ``write_table``, as :func:`measured_dynamic_factor`). ``run``: that run
    when the caller has it already (the sweep's, at that speed, with its cell loads:
    :func:`jaxgear.cli.sweep.sweep_case_run`), else None: simulated here."""
    section = summary.get("rating") or {}
    if section.get("root_stress") is None:
        return
    speed = float(dynamics["speed_of_max_rad_s"])
    slices = int(dynamics["slices"])
    if run is None or float(run.speed) != speed or run.meshes[0].line_load is None:
        model, spec = build_dynamic_model(case, case.scene, slices=slices)
        run = simulate(
            model,
            speed,
            integrator=spec_integrator(spec),
            contact=case.contact_law(spec.contact),
            window=spec_window(spec),
            outputs=Outputs(cell_loads=True),
            throw=False,
        )
    summary["rating"] = at_speed_sections(
        case, out_dir, section, run, slices, table, write_table=write_table
    )


def at_speed_sections(
    case: Case, out_dir: str, section: dict, run, slices: int, table, *, write_table: bool = True
) -> dict:
    """Each mesh's root-stress map at speed into the case's ``rating`` ``section`` (returned;
    ``rating.md`` rewritten with ``write_table``): mesh k's cell loads of the dynamic run
    ``run`` (one speed, ``Outputs(cell_loads=True)``: ``run.meshes[k]``) at its kept steps
    times the plane FE
    fillet stress per unit load (:func:`jaxgear.rating.root_stress_map`, ``table`` as
    :func:`root_stress_outputs`), and beside it the quasi-static map of the mesh's rigid mesh
    at the same ``slices`` (exact contact, its modifications, its driving gear's torque:
    :meth:`jaxgear.io.Case.mesh_case`). Adds ``root_stress.at_speed`` to each mesh's section:
    ``speed_rad_s`` (the run's, the pinion's; a train's the input's), ``max_Pa`` and
    ``static_max_Pa`` ([pinion, gear]: [driving, driven]), ``ratio`` (at speed / static, per
    gear), the mesh's ``dynamic_factor`` (largest mesh force over the static one) and
    ``dynamic_factor_tooth`` (largest tooth force over the quasi-static one), ``slices`` and the
    run's ``result`` code (a train: per-mesh lists). The map is linear in the cell loads
    (docs/rating.md, "Root stress at speed"); the ratio equals a dynamic factor only where the
    loads at speed are the static ones scaled (a tooth force dynamic factor weighs the tooth's
    whole load, the map the most stressed cell)."""
    sections = _mesh_sections(case.form, section)
    for k, sec in enumerate(sections):
        mesh, one = run.meshes[k], case.mesh_case(k)
        static = quasi_static(one.mesh_model(slices=slices), one.modifications, one.torque)
        at_speed = [float(m.max) for m in _member_maps(case.pairs[k], mesh, table)]
        at_rest = [float(m.max) for m in _member_maps(case.pairs[k], static, table)]
        sec["root_stress"]["at_speed"] = {
            "speed_rad_s": float(run.speed),
            "max_Pa": at_speed,
            "static_max_Pa": at_rest,
            "ratio": [a / b for a, b in zip(at_speed, at_rest, strict=True)],
            "dynamic_factor": float(mesh.dynamic_factor),
            "dynamic_factor_tooth": float(mesh.dynamic_factor_tooth),
            "slices": slices,
            "result": int(run.result),
            "source": "the dynamic model's cell loads at the kept steps of one run at the "
            "sweep's speed of the largest dynamic factor × the plane FE fillet stress per unit "
            "load; static: the rigid mesh's quasi-static map at the same slices",
        }
    return _write_sections(case, out_dir, sections, write_table)
