"""The main job: quasi-static analysis of a case, written as JSON, CSV and PNG (``jaxgear run``)."""

from __future__ import annotations

import functools
import math
import os
import sys

import numpy as np

from .. import (
    Modifications,
    contact_pressure,
    harris_map,
    io as case_io,
    loaded_path,
    quasi_static,
)
from ..io import (
    Case,
    GearboxForm,
    InternalMeshForm,
    PairForm,
    PlanetaryForm,
    TrainForm,
    whine_of,
    write_csv,
    write_json,
)
from . import scene as cli_scene, sweep as cli_sweep
from ._acoustics_run import acoustic_outputs, acoustics_run_line  # noqa: F401 (the hook)
from ._bearing_report import bearing_outputs, bearing_run_lines
from ._deviation_run import deviation_line, deviation_outputs
from ._optimise import check_settings, optimise_case, settings_from_case
from ._paths import check_case_outputs, staged_outputs
from ._plots import (
    LUMPED_STIFFNESS_NOTE,
    SCENE_STIFFNESS_NOTE,
    face_maps,
    harris_plot,
    loaded_path_plot,
    mesh_stiffness_plot,
    transmission_error_plot,
)
from ._progress import progress
from ._rating_report import (
    measured_dynamic_factor,
    rating_outputs,
    root_stress_at_speed,
    scene_loads,
    train_loads,
    train_mesh_results,
    write_rating_table,
)
from ._spectrum_report import mesh_spectrum_run_lines, spectrum_run_lines
from ._stress_outputs import fillet_table
from ._summary import (
    environment_summary,
    format_table,
    has_modifications,
    mesh_settings_summary,
    result_summary,
    stiffness_line,
    stiffness_reference,
)
from ._tribology_run import (
    efficiency_run_line,
    train_tribology_outputs,
    tribology_outputs,
    tribology_run_line,
)
from ._whine_run import whine_outputs, whine_run_line
from .gearbox import gearbox_run_files, gearbox_run_lines, gearbox_whine_outputs
from .planetary_speed import planetary_rated_run_files
from .planetary_sweep import planetary_run_lines
from .scene import SCENE_LABELS
from .train import format_train_table, run_train

__all__ = [
    "HOUSED_MIN_SPEEDS",
    "RUN_SWEEP_SLICES",
    "acoustic_outputs",
    "first_look_speeds",
    "format_table",
    "rating_run_line",
    "result_summary",
    "run_case",
    "run_sweep_speeds",
    "stiffness_line",
    "train_rating_run_line",
]

# slices per contact line of the dynamic sweep that `jaxgear run` adds for a lumped scene
RUN_SWEEP_SLICES = 8
#: the fewest speeds of a housed case's first-look sweep (:func:`first_look_speeds`)
HOUSED_MIN_SPEEDS = 5


def run_case(
    case: Case,
    out_dir: str,
    *,
    harris_points: int = 16,
    show_progress: bool = True,
    complete: bool = True,
    scene: dict | None = None,
) -> dict:
    """Compute geometry, mesh stiffness, quasi-static TE (exact and smooth, with and without the
    case's modifications), the load map and the Harris map, and write them to ``out_dir``.

    Files (written atomically): ``summary.json``, ``te.csv``, ``mesh_stiffness.csv``,
    ``transmission_error.png``, ``mesh_stiffness.png``, ``load_map.png``, ``pressure_map.png``
    (the Hertzian contact pressure, :func:`~jaxgear.contact_pressure`), ``harris_map.png``; with
    ``[deviations]`` also ``deviations/`` (the TE over whole revolutions with the deviations per
    tooth and its order spectrum, :func:`~jaxgear.cli._deviation_run.deviation_outputs`) and
    ``summary.json``'s ``deviations``. The other files are for the perfect gears (no deviations).

    ``summary.json`` says ``"complete": complete`` (``jaxgear run`` passes False when a sweep or
    an optimisation follows, and rewrites it at the end).

    ``scene``: the case's scene results (:func:`jaxgear.cli.scene.scene_outputs`' ``curves``:
    ``model`` and ``results``, one mesh period at the rigid mesh's first positions, repeated
    over the second: the quasi-static scene is periodic in the mesh period): their TE and mesh
    stiffness are added to the CSV files (``te_<model>_<contact>_modified[_at_rest]_m``,
    ``mesh_stiffness_<model>_...``) and drawn beside the rigid mesh's, each labelled with its
    model. Every other file is the rigid mesh's (both bodies rigid), and says so, but for a
    ``[rating]``'s measured K_Hβ and K_Hα, read on the scene's load map (the rigid mesh's
    beside them). ``rating.md`` is written here when ``complete`` (else by the step that
    completes the run: :func:`jaxgear.cli.write_rating_table`).

    Returns:
        The summary dict (also in ``summary.json``).
    """
    os.makedirs(out_dir, exist_ok=True)
    mesh = case.mesh_model()
    ppp = case.positions_per_pitch
    none = Modifications()
    steps = progress(total=7, desc=f"jaxgear run {case.name}", disable=not show_progress)
    res = {}
    for label, mods in (("unmodified", none), ("modified", case.modifications)):
        for mode in ("exact", "smooth"):
            steps.set_postfix_str(f"quasi-static, {label}, {mode} contact")
            res[label, mode] = quasi_static(
                mesh,
                mods,
                case.torque,
                contact=case.contact_law(mode),
                positions_per_pitch=ppp,
                periods=2,
            )
            steps.update()
    torques = np.linspace(0.1, 2.0, harris_points) * case.torque
    torques[np.argmin(np.abs(torques - case.torque))] = case.torque  # a point of the Harris map
    steps.set_postfix_str(f"Harris map, {harris_points} torques")
    harris = {
        label: harris_map(mesh, mods, torques, positions_per_pitch=ppp)
        for label, mods in (("unmodified", none), ("modified", case.modifications))
    }
    path_map = {}
    # where contact really starts and ends (docs/extended-contact.md)
    if mesh.contact_geometry.reaches_beyond_path:
        path_map = {
            label: loaded_path(mesh, mods, torques, positions_per_pitch=ppp)
            for label, mods in (("unmodified", none), ("modified", case.modifications))
        }
    steps.update()
    steps.set_postfix_str("contact pressure")
    pair = case.pair
    pressure = {
        key: contact_pressure(pair, r, case.youngs_modulus, case.poisson_ratio)
        for key, r in res.items()
    }
    steps.update()
    steps.set_postfix_str("files and plots")

    summary = {
        "case": case.name,
        "complete": bool(complete),
        "geometry": pair.summary(),
        "operating": {"torque_Nm": case.torque, "normal_load_N": case.normal_load},
        "mesh": mesh_settings_summary(case),
        "quasi_static": {
            m: result_summary(res["modified", m], None, pressure["modified", m])
            for m in ("exact", "smooth")
        },
        "quasi_static_unmodified": {
            m: result_summary(res["unmodified", m], None, pressure["unmodified", m])
            for m in ("exact", "smooth")
        },
        "harris_map": {
            "torque_Nm": torques.tolist(),
            "te_ptp_unmodified_m": harris["unmodified"].tolist(),
            "te_ptp_modified_m": harris["modified"].tolist(),
        },
        "environment": environment_summary(mesh.base_pitch.dtype),
    }
    reference = stiffness_reference(case, res["unmodified", "exact"])
    if reference:  # the model's own figures (iso6336: c_γα) beside the mean they fix
        summary["mesh_stiffness_reference"] = reference
    if path_map:
        summary["loaded_path"] = {
            "torque_Nm": torques.tolist(),
            "path_of_contact_m": float(mesh.path_of_contact),
            **{
                f"{key}_{label}_m": np.asarray(getattr(lp, key)).tolist()
                for label, lp in path_map.items()
                for key in ("start", "end", "relief_start", "relief_end")
            },
        }
    if case.coast:  # backlash and the coast flanks (docs/backlash.md)
        summary["backlash"] = {
            "backlash_normal_m": pair.normal_backlash,
            "backlash_transverse_m": pair.transverse_backlash,
            "backlash_circumferential_m": pair.circumferential_backlash,
            "tooth_thickness_allowance_m": [
                pair.pinion.tooth_thickness_allowance,
                pair.gear.tooth_thickness_allowance,
            ],
            "coast_angle_rad": float(mesh.coast_angle),
        }
    theta = np.asarray(res["modified", "exact"].theta)
    cols = {
        f"te_{m}_{lab}_m": np.asarray(res[lab, m].transmission_error)
        for lab in ("unmodified", "modified")
        for m in ("exact", "smooth")
    }
    kcols = {
        f"mesh_stiffness_{m}_{lab}_N_per_m": np.asarray(res[lab, m].mesh_stiffness)
        for lab in ("unmodified", "modified")
        for m in ("exact", "smooth")
    }
    # the scene's own curves (shafts, bearings, condensed bodies) beside the rigid mesh's
    scene_res = _scene_columns(scene, theta)
    for key, (te, k) in scene_res.items():
        cols[f"te_{key}_m"] = te
        kcols[f"mesh_stiffness_{key}_N_per_m"] = k
    write_csv(os.path.join(out_dir, "te.csv"), ["theta_rad", *cols], [theta, *cols.values()])
    lcols = {
        "contact_length_exact_modified_m": np.asarray(res["modified", "exact"].contact_length),
        # the largest Hertzian pressure on the flanks at each position (seed IV-44)
        "max_contact_pressure_exact_modified_Pa": np.asarray(
            pressure["modified", "exact"].max_pressure
        ).max(axis=(1, 2)),
    }
    write_csv(
        os.path.join(out_dir, "mesh_stiffness.csv"),
        ["theta_rad", *kcols, *lcols],
        [theta, *kcols.values(), *lcols.values()],
    )

    period = 2 * math.pi / pair.pinion.teeth
    x = theta / period
    modified = has_modifications(case.modifications)
    # without modifications the modified curves are the unmodified ones: drawn once
    designs = ({"unmodified": "unmodified", "modified": "modified"} if modified else
               {"unmodified": "no modifications"})
    rigid = "rigid mesh" if scene_res else ""  # a case with a scene: say which model
    te_curves = {
        f"{rigid} {words}".strip(): {
            m: np.asarray(res[lab, m].transmission_error) for m in ("exact", "smooth")
        }
        for lab, words in designs.items()
    }
    k_curves = {
        f"{rigid} {words} (loaded cells)".strip(): np.asarray(res[lab, "exact"].mesh_stiffness)
        for lab, words in designs.items()
    }
    what = ""
    if scene_res:
        model = scene["model"]
        name = SCENE_LABELS[model].split(" (")[0]
        for state, by_contact in _scene_states(scene_res).items():  # as solved, at rest
            label = " ".join((name, *state.split("_"))).strip()
            te_curves[f"{label}, modified"] = {m: te for m, (te, _) in by_contact.items()}
            k_curves[f"{label} modified (loaded cells)"] = by_contact["exact"][1]
        what = f"\nrigid mesh and {SCENE_LABELS[model]}"
    k_note = te_note = None
    if scene_res:  # say what each stiffness is (a condensed body's is not the rigid mesh's)
        k_note = SCENE_STIFFNESS_NOTE if case.flexible else LUMPED_STIFFNESS_NOTE
    if pair.overlap_ratio > 0:  # helical: the slices' steps are the model's, not an error
        k_note = (k_note + "\n" if k_note else "") + (
            f"helical: K jumps by one slice's stiffness when one of the {case.slices} slices of "
            "a contact line enters or leaves contact\n(the path's ends; with relief, its start: "
            "one-position spikes); smaller with more [mesh] slices"
        )
        te_note = (
            f"helical: the unmodified TE's corners are its {case.slices} slices entering and "
            "leaving contact one at a time (finer with more [mesh] slices)"
        )
    transmission_error_plot(
        os.path.join(out_dir, "transmission_error.png"),
        x,
        te_curves,
        title=f"{case.name}: transmission error at {case.torque:g} N·m{what}",
        note=te_note,
    )
    mesh_stiffness_plot(
        os.path.join(out_dir, "mesh_stiffness.png"),
        x,
        k_curves,
        title=f"{case.name}: time-varying mesh stiffness ({case.stiffness_model}){what}",
        note=k_note,
    )
    face_maps(
        out_dir,
        ("load_map.png", "pressure_map.png"),
        res["modified", "exact"],
        pressure["modified", "exact"].max_pressure,
        pair,
        ppp,
        f"of {case.name} over a tooth passage (rigid mesh, exact, "
        f"{'modified' if modified else 'no modifications'})",
    )
    harris_plot(
        os.path.join(out_dir, "harris_map.png"),
        torques,
        [
            ("no relief", harris["unmodified"], "o-"),
            ("case modifications", harris["modified"], "s-"),
        ] if modified else [("no modifications (the case has none)", harris["unmodified"], "o-")],
        design_torque=case.torque,
        ylabel="TE peak-to-peak (µm), exact contact",
        title=f"{case.name}: Harris map (rigid mesh)",
    )
    if path_map:
        loaded_path_plot(
            os.path.join(out_dir, "loaded_path.png"),
            path_map if modified else {"no modifications": path_map["unmodified"]},
            design_torque=case.torque,
            title=f"{case.name}: the loaded path of contact (rigid mesh, exact contact)",
        )
    steps.update()  # the four plots
    if case.deviations is not None:  # the span with the manufacturing deviations per tooth
        steps.set_postfix_str("TE with the deviations per tooth")
        summary["deviations"] = deviation_outputs(case, mesh, os.path.join(out_dir, "deviations"))
    steps.close()
    # [rating]: ISO 6336 load capacity; K_Hβ, K_Hα measured on the load map of the model the
    # case runs (its scene's, solved already, beside the rigid mesh's); the FE root stress;
    # rating.md written by the step that completes the run
    rating = rating_outputs(
        case,
        out_dir,
        result=res["modified", "exact"],
        root_stress=fillet_table,
        model=scene_loads(scene, case.speed),
        meshes=(mesh,),  # the contact model the measured rows state
        write_table=complete,
    )
    if rating is not None:
        summary["rating"] = rating
    # [lubricant]: film and sliding loss along the path of contact (tribology.json)
    tribology = tribology_outputs(case, out_dir, res["modified", "exact"])
    if tribology is not None:
        summary["tribology"] = tribology
    # rolling bearings from geometry: their loads, lives and tones (docs/bearings.md)
    bearings = bearing_outputs(case.form, case)
    if bearings is not None:
        summary["bearings"] = bearings
    if complete and rating is not None and (tribology or bearings):  # rating.md with them
        write_rating_table(case, out_dir, rating, tribology, bearings)

    write_json(os.path.join(out_dir, "summary.json"), summary)
    return summary


def _scene_columns(scene: dict | None, theta) -> dict:
    """{column key: (TE (m), K (N/m))} of the scene's curves at the rigid mesh's positions
    ``theta`` (``<model>_<contact>_modified`` and ``<model>_exact_modified_at_rest``): a scene
    result over the first of ``theta``'s mesh periods is repeated over the others (the
    quasi-static scene is periodic in the mesh period)."""
    if not scene:
        return {}
    out = {}
    for key, r in scene["results"].items():
        t = np.asarray(r.theta)
        reps = theta.size // max(t.size, 1)
        if reps * t.size != theta.size or not np.allclose(t, theta[: t.size], rtol=0, atol=1e-12):
            raise ValueError("the scene's results are not at the rigid mesh's positions")
        contact, _, rest = key.partition("_")
        out[f"{scene['model']}_{contact}_modified{'_' + rest if rest else ''}"] = (
            np.tile(np.asarray(r.transmission_error), reps),
            np.tile(np.asarray(r.mesh_stiffness), reps),
        )
    return out


def _scene_states(columns: dict) -> dict:
    """The scene's curves (:func:`_scene_columns`) by the state they were solved in ("": at the
    case's speed, "at_rest") and then by contact law: {state: {contact: (TE, K)}}, in the
    order of the columns."""
    out: dict = {}
    for key, curves in columns.items():
        contact, _, state = key.split("_", 1)[1].partition("_modified")
        out.setdefault(state.lstrip("_"), {})[contact] = curves
    return out


def run_command(args) -> int:
    """``jaxgear run``: quasi-static files, then the sweep and optimisation the case asks for.

    The files are written into a staging folder and moved into the output folder only when the
    run completes (:func:`~jaxgear.cli._paths.staged_outputs`): a failed or interrupted run
    leaves the earlier results; ``--keep-partial`` writes into the folder itself and leaves
    what a failed run wrote, with ``summary.json`` saying ``"complete": false`` (but a run
    refused for its input, whose earlier results come back as they were)."""
    case = case_io.load_case(args.case)
    out = check_case_outputs(case, "run", args.out or os.path.join("jaxgear-out", case.name),
                             [("--json", args.json)], force=args.force)
    settings = optimise_settings(case)  # checked before anything is computed
    check_run_case(case)
    # refused at load where too large; else their estimates printed
    sizes = (case.housing_size(), case_io.check_case_whine(case))
    for size in sizes if not args.quiet else ():
        if size is not None:
            print(size.line(), file=sys.stderr)
    with staged_outputs(out, "run", keep_partial=args.keep_partial) as work:
        # an interrupted --keep-partial run leaves complete files and a summary saying it is
        # not complete
        write_json(os.path.join(work, "summary.json"), {"case": case.name, "complete": False})
        summary = run_kind(case, work, args, settings)
    if args.json:
        write_json(args.json, summary)
    print(f"written to {out}/")
    return 0


def check_run_case(case) -> None:
    """Refuse, before any work, a case whose dynamic sweep (``jaxgear run`` sweeps a lumped
    scene) cannot run (:func:`~jaxgear.cli.sweep.sweep_spec`: e.g. ``[scene.integration]
    periods`` × steps per period above what one speed may integrate; one line naming the key,
    its value and the allowed range); a housed case whose housing's band lies below the sweep's
    lowest speed (the first look keeps to the band: it would sweep crawling speeds whose time
    plans do not fit, :func:`first_look_speeds`)."""
    if case.scene is None or case.scene.hybrid:  # (a train's flexible gears: a hybrid scene)
        return
    cli_sweep.sweep_spec(case)
    hb = case_io.housing_band(case)
    if hb is not None:  # the first look's sweep keeps to the band: it must hold its lowest speed
        low = float(run_sweep_speeds(case.form)[0])
        case_io.check_housing_band(
            case.housing,
            (hb.mesh_order * low / (2 * math.pi),
             f"order 1 of the mesh frequency at its lowest speed, {low:g} rad/s"),
            what="the speeds of jaxgear run's dynamic factor sweep",
        )


def optimise_settings(case) -> dict | None:
    """The checked settings of the case's ``[optimise]`` table
    (:func:`jaxgear.cli.check_settings`), None without one (a train has none) or where it is a
    bearing choice (``[optimise.choices]``: ``jaxgear optimise`` runs it, not ``jaxgear
    run``)."""
    if case.optimise is None or case.optimise.get("choices"):
        return None
    return check_settings(settings_from_case(case))


def run_kind(case: Case, out: str, args, settings) -> dict:
    """``jaxgear run``'s work on a case, into ``out``: the quasi-static files of its meshes (by
    the case's form, :func:`quasi_static_files`), then what the case asks for: the dynamic
    factor sweep of a ``[scene]`` without condensed bodies, the optimisation of an
    ``[optimise]`` table; prints the tables (:func:`run_lines`); returns the summary.
    ``settings``: :func:`optimise_settings`."""
    summary_path = os.path.join(out, "summary.json")
    sweep = sweeps(case)
    whine = whine_of(case) is not None  # [whine]: the frequency-domain whine after the rest
    last = not sweep and settings is None and not whine
    summary = quasi_static_files(case.form, case, out, args, last)
    if sweep:  # the case has a dynamic scene: add its dynamic factor curve
        dynamics, worst_run = _sweep_section(case, out, args.quiet)
        summary["dynamics"] = dynamics
        # K_v measured, beside ISO's
        measured_dynamic_factor(case, out, summary, dynamics, write_table=False)
        # the root-stress map at speed, from the sweep's run at that speed (not run again)
        root_stress_at_speed(case, out, summary, dynamics, run=worst_run, write_table=False)
        write_json(summary_path, summary)
    if settings is not None:  # the case asks for an optimisation too
        rep = optimise_case(case, settings, os.path.join(out, "optimise"), progress=not args.quiet)
        summary["optimise"] = {
            k: rep[k]
            for k in (
                "objective",
                "variables",
                "initial",
                "final",
                "iterations",
                "evaluations",
                "converged",
                "on_bound",
                "held",
                "candidates",
                "best",
            )
        }
        write_json(summary_path, summary)
    if whine:
        summary["whine"] = (gearbox_whine_outputs(case.form, case, out)  # the coupled chain's
                            if isinstance(case.form, GearboxForm) else whine_outputs(case, out))
        write_json(summary_path, summary)
    if not last:
        # rating.md once, of the final section (a planetary stage's: written by its own files)
        if summary.get("rating") is not None and not isinstance(case.form, PlanetaryForm):
            write_rating_table(case, out, summary["rating"], summary.get("tribology"),
                               summary.get("bearings"))
        summary["complete"] = True
        write_json(summary_path, summary)
    lines = run_lines(case.form, case, summary)
    if case.optimise is not None and case.optimise.get("choices"):  # not run here: say so
        lines.append("[optimise.choices]: jaxgear run leaves the bearing choice; jaxgear "
                     "optimise on this case file ranks its candidates")
    print("\n".join(lines))
    return summary


def sweeps(case: Case) -> bool:
    """``jaxgear run`` adds a dynamic factor sweep (:func:`_sweep_section`): the case has a
    ``[scene]`` without condensed bodies (with them, ``jaxgear sweep`` runs it)."""
    return case.scene is not None and not case.flexible


@functools.singledispatch
def quasi_static_files(form, case: Case, out: str, args, complete: bool) -> dict:
    """The quasi-static files ``jaxgear run`` writes for a case of ``form``
    (:class:`~jaxgear.io.CaseForm`) into ``out``; returns the summary (``"complete":
    complete``)."""
    raise TypeError(f"jaxgear run: no quasi-static files for a case of form {type(form).__name__}")


@quasi_static_files.register
def _(form: PairForm, case: Case, out: str, args, complete: bool) -> dict:
    """A pair's: :func:`run_case` (with ``[deviations]`` its deviation span), with a lumped
    scene first its quasi-static scene (``summary.json``'s ``quasi_static_scene``: so that
    te.csv and its plots have the scene's curves beside the rigid mesh's)."""
    scene_section, curves = None, {}
    if case.lumped:
        scene_section = cli_scene.scene_outputs(
            case, os.path.join(out, "scene"), progress=not args.quiet, curves=curves
        )
    summary = run_case(
        case,
        out,
        show_progress=not args.quiet,
        complete=complete and scene_section is None,
        scene=curves or None,
    )
    if scene_section is not None:
        summary["quasi_static_scene"] = scene_section
        summary["complete"] = bool(complete)
        if complete and summary.get("rating") is not None:  # the run ends here
            write_rating_table(case, out, summary["rating"], summary.get("tribology"),
                               summary.get("bearings"))
        write_json(os.path.join(out, "summary.json"), summary)
    return summary


@quasi_static_files.register
def _(form: TrainForm, case: Case, out: str, args, complete: bool) -> dict:
    """A train's: every mesh at once on the train's structure (:func:`run_train`); with
    ``[rating]`` every mesh rated (``rating.md``, ``summary.json``'s ``rating``)."""
    coupled = {}
    summary = run_train(
        case, out, show_progress=not args.quiet, complete=complete, results=coupled
    )
    rating = rating_outputs(  # measured K_Hβ, K_Hα: the coupled solve's, each mesh alone beside
        case,
        out,
        train_mesh_results(case),
        root_stress=fillet_table,
        model=train_loads(case, coupled["exact"], coupled["base_planes"]),
        write_table=complete,
    )
    if rating is not None:
        summary["rating"] = rating
    # [lubricant]: every mesh's film and sliding loss on the coupled solve, the efficiency
    tribology = train_tribology_outputs(case, out, coupled["exact"])
    if tribology is not None:
        summary["tribology"] = tribology
    # rolling bearings from geometry: their loads, lives and tones (docs/bearings.md)
    bearings = bearing_outputs(case.form, case)
    if bearings is not None:
        summary["bearings"] = bearings
    if complete and rating is not None and bearings:  # rating.md with them
        write_rating_table(case, out, rating, tribology, bearings)
    if rating is not None or tribology is not None or bearings is not None:
        write_json(os.path.join(out, "summary.json"), summary)
    return summary


# a planetary stage's files and lines, with its first-look sweep (cli/planetary_sweep.py) and
# its root stress at speed (cli/planetary_speed.py)
quasi_static_files.register(PlanetaryForm, planetary_rated_run_files)


@quasi_static_files.register
def _(form: GearboxForm, case: Case, out: str, args, complete: bool) -> dict:
    return gearbox_run_files(form, case, out, args, complete, run_kind)  # each stage's own run


@quasi_static_files.register
def _(form: InternalMeshForm, case: Case, out: str, args, complete: bool) -> dict:
    """A train of one internal mesh: its rigid mesh as a pair's (:func:`run_case`)."""
    return run_case(case, out, show_progress=not args.quiet, complete=complete)


def _pair_of(values) -> str:
    return " / ".join(f"{v:.3g}" for v in values)


def rating_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of a pair's ``rating`` section (nothing without one): the
    safety factors S_H and S_F, pinion / gear."""
    if section is None:
        return []
    h, f = (_pair_of(section[p][k]) for p, k in (("pitting", "S_H"), ("bending", "S_F")))
    return [f"rating ({section['method']}, pinion / gear): S_H {h}, S_F {f} (rating.md)"] + (
        spectrum_run_lines(section.get("spectrum"))  # [rating.spectrum]: the damage per bin
    )


def train_rating_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of a train's ``rating`` section (nothing without one): each
    mesh's S_H and S_F, driving / driven."""
    if section is None:
        return []
    per = "; ".join(
        f"{name} S_H {_pair_of(h)}, S_F {_pair_of(f)}"
        for name, h, f in zip(
            section["meshes"], section["pitting"]["S_H"], section["bending"]["S_F"], strict=True
        )
    )
    return [f"rating ({section['method']}, driving / driven): {per} (rating.md)"] + (
        mesh_spectrum_run_lines(section["meshes"], section.get("spectrum"))
    )


@functools.singledispatch
def run_lines(form, case: Case, summary: dict) -> list[str]:
    """What ``jaxgear run`` prints at the end for a case of ``form``, from its ``summary``."""
    raise TypeError(f"jaxgear run: no table for a case of form {type(form).__name__}")


@run_lines.register
def _(form: PairForm, case: Case, summary: dict) -> list[str]:
    lines = [format_table(summary, case.stiffness, has_modifications(case.modifications))]
    if case.deviations is not None:  # run_case added the span with the deviations
        lines.append(deviation_line(summary["deviations"]))
    if case.lumped:
        lines.extend(cli_scene.scene_lines(summary["quasi_static_scene"]))
    if case.flexible:
        lines.append(
            f"speed sweep with the condensed bodies: jaxgear sweep {case.name} --speeds A:B:N "
            "(not run by jaxgear run: 15-25 s per speed on a 2-core CPU, into "
            f"jaxgear-out/{case.name}/sweep-A-B-N/)"
        )
    if sweeps(case):
        d = summary["dynamics"]
        lines.append(
            f"dynamic factor: max {d['max_dynamic_factor']:.3f} at "
            f"{d['speed_of_max_rad_s']:.0f} rad/s (pinion), sweep "
            f"{d['speeds_rad_s'][0]:.4g}-{d['speeds_rad_s'][-1]:.4g} rad/s"
        )
        lines.extend(housing_band_lines(d))
    return (
        lines
        + rating_run_line(summary.get("rating"))
        + tribology_run_line(summary.get("tribology"))
        + bearing_run_lines(summary.get("bearings"))
        + whine_run_line(summary.get("whine"))
    )


@run_lines.register
def _(form: TrainForm, case: Case, summary: dict) -> list[str]:
    lines = [format_train_table(summary)]
    if sweeps(case):
        d = summary["dynamics"]
        per = ", ".join(  # a train of one mesh: its own
            f"{n} {v:.3f}"
            for n, v in zip(
                [case.mesh_name(k) for k in range(len(case.pairs))],
                d.get("max_dynamic_factor_mesh", [d["max_dynamic_factor"]]),
                strict=True,
            )
        )
        lines.append(
            f"dynamic factor: max {d['max_dynamic_factor']:.3f} at {d['speed_of_max_rad_s']:.0f} "
            f"rad/s (input), per mesh {per}; sweep {d['speeds_rad_s'][0]:.4g}-"
            f"{d['speeds_rad_s'][-1]:.4g} rad/s"
        )
        lines.extend(housing_band_lines(d))
    if case.flexible:
        lines.append(
            f"speed sweep with the condensed bodies: jaxgear sweep {case.name} --speeds A:B:N "
            "(not run by jaxgear run: a hybrid train takes tens of seconds per speed on a 2-core "
            f"CPU), into jaxgear-out/{case.name}/sweep-A-B-N/"
        )
    return (
        lines
        + train_rating_run_line(summary.get("rating"))
        + efficiency_run_line(summary.get("tribology"))
        + bearing_run_lines(summary.get("bearings"))
        + whine_run_line(summary.get("whine"))
    )


@run_lines.register
def _(form: PlanetaryForm, case: Case, summary: dict) -> list[str]:
    return planetary_run_lines(form, case, summary) + whine_run_line(summary.get("whine"))


run_lines.register(GearboxForm, gearbox_run_lines)


@run_lines.register
def _(form: InternalMeshForm, case: Case, summary: dict) -> list[str]:
    return [format_table(summary, case.stiffness, has_modifications(case.modifications))]


@functools.singledispatch
def run_sweep_speeds(form) -> np.ndarray:
    """The pinion (input) speeds (rad/s) of the dynamic factor sweep ``jaxgear run`` adds for a
    case of ``form`` (:class:`~jaxgear.io.CaseForm`): a pair's (and a train of one internal
    mesh's) 60 speeds from 100 to 3000 rad/s; a train's 30 over the same range (every 100 rad/s:
    a first look, each speed of a train integrating every mesh over the span after which they
    repeat together; ``jaxgear sweep CASE --speeds 100:3000:60`` runs more). A housed case
    runs those within its housing's band (:func:`first_look_speeds`)."""
    return np.linspace(100.0, 3000.0, 60)


@run_sweep_speeds.register
def _(form: TrainForm) -> np.ndarray:
    return np.linspace(100.0, 3000.0, 30)


run_sweep_speeds.register(InternalMeshForm, run_sweep_speeds.dispatch(object))


def first_look_speeds(case) -> tuple[np.ndarray, dict | None]:
    """The speeds of the dynamic factor sweep ``jaxgear run`` adds for ``case`` and, where the
    housing stops it, ``summary.json``'s ``dynamics.housing_band`` (else None).

    Without ``[housing]``: :func:`run_sweep_speeds`. With it, the sweep keeps to the speeds
    where the model holds: the speeds of :func:`run_sweep_speeds` up to the housing's speed
    limit Ω_b (:func:`jaxgear.io.housing_band`: every mesh's order-1 frequency within
    the housing's band, cut-off / 1.5; above it the housing's modes beyond the cut-off, which
    the condensation leaves out, count); where fewer than :data:`HOUSED_MIN_SPEEDS` of them
    lie there, that many evenly from Ω_b / HOUSED_MIN_SPEEDS to Ω_b. The section names the
    cut-off, the band, the highest mesh order, Ω_b, the first look's range and a one-line
    ``note`` (printed by ``jaxgear run``); ``jaxgear sweep CASE --speeds A:B:N`` runs any
    speeds (and says how many lie above Ω_b)."""
    speeds = run_sweep_speeds(case.form)
    hb = case_io.housing_band(case)
    if hb is None or speeds[-1] <= hb.speed_limit:
        return speeds, None
    limit = hb.speed_limit
    kept = speeds[speeds <= limit]
    if kept.size < HOUSED_MIN_SPEEDS:
        kept = np.linspace(limit / HOUSED_MIN_SPEEDS, limit, HOUSED_MIN_SPEEDS)
    who = "pinion" if len(case.pairs) == 1 else "input"
    note = (
        f"dynamic factor sweep {kept[0]:.4g}-{kept[-1]:.4g} rad/s only (of the first look's "
        f"{speeds[0]:g}-{speeds[-1]:g}): above {limit:.4g} rad/s the order-1 mesh frequency "
        f"({hb.mesh_order:.4g} per {who} turn) leaves the housing's band, {hb.band_hz:.4g} Hz = "
        f"cut-off {hb.cutoff_hz:.4g} Hz / {case_io.HOUSING_BAND:g}, and the housing's modes "
        f"beyond the cut-off are not in the model; jaxgear sweep {case.name} --speeds A:B:N runs "
        "other speeds"
    )
    section = {
        "cutoff_Hz": hb.cutoff_hz,
        "band_limit_Hz": hb.band_hz,
        "mesh_order": hb.mesh_order,
        "speed_limit_rad_s": limit,
        "first_look_rad_s": [float(speeds[0]), float(speeds[-1])],
        "note": note,
    }
    return kept, section


def housing_band_lines(dynamics: dict) -> list[str]:
    """What ``jaxgear run`` prints of a first-look sweep the housing stopped
    (:func:`first_look_speeds`: its note), nothing otherwise."""
    band = dynamics.get("housing_band")
    return [] if band is None else [band["note"]]


def _sweep_section(case, out: str, quiet: bool) -> dict:
    """The dynamic factor sweep ``jaxgear run`` adds for a case's scene (the speeds of
    :func:`first_look_speeds`, a housed case's within its housing's band, into ``out``/sweep, at no more than ``RUN_SWEEP_SLICES`` slices per
    contact line; ``jaxgear sweep --slices`` runs the case's own) and ``summary.json``'s
    ``dynamics``: the dynamic factor curve and its maximum (a train's: the worst mesh per speed,
    with each mesh's under ``dynamic_factor_mesh``), and the sweep's run at the speed of the
    largest dynamic factor with its cell loads (:func:`~jaxgear.cli.sweep.sweep_case_run`; None
    when no speed ran to the end)."""
    slices = min(case.slices, RUN_SWEEP_SLICES)
    speeds, band = first_look_speeds(case)
    sw, worst_run = cli_sweep.sweep_case_run(
        case,
        speeds,
        os.path.join(out, "sweep"),
        slices=slices,
        show_progress=not quiet,
    )
    df = np.asarray(sw["dynamic_factor"], dtype=float)
    out = {
        "model": case.scene.model,
        "slices": slices,
        "speeds_rad_s": sw["speeds_rad_s"],
        "dynamic_factor": sw["dynamic_factor"],
        "max_dynamic_factor": float(np.nanmax(df)),
        "speed_of_max_rad_s": float(sw["speeds_rad_s"][int(np.nanargmax(df))]),
        "files": ", ".join(f"sweep/{name}" for name in _sweep_files(sw)),
        **mesh_dynamics(sw),
    }
    if band is not None:
        out["housing_band"] = band
    return out, worst_run


def mesh_dynamics(sw: dict) -> dict:
    """``summary.json``'s ``dynamics`` keys per mesh, as the sweep ``sw``
    (:func:`jaxgear.cli.sweep.sweep_case`'s summary) holds them: a case of several meshes has
    them (``mesh_names``, ``dynamic_factor_mesh``); a case of one mesh none (its mesh's are the
    section's own)."""
    names = sw.get("mesh_names")
    if names is None:
        return {}
    per = np.asarray(sw["dynamic_factor_mesh"], dtype=float)  # (S, m)
    return {
        "mesh_names": names,
        "dynamic_factor_mesh": sw["dynamic_factor_mesh"],
        "max_dynamic_factor_mesh": [float(v) for v in np.nanmax(per, axis=0)],
    }


def _sweep_files(sw: dict) -> list[str]:
    """The files a sweep wrote, by its summary (:func:`jaxgear.cli.sweep.sweep_case`)."""
    files = ["sweep.json", "dynamic_factor.png", "campbell.png", "contact_pressure.png"]
    return files + list((sw.get("pressure_map_dynamic") or {}).get("files", ()))
