"""``jaxgear optimise`` and ``jaxgear master-curve``: files and plots.

Entry points: :func:`run_optimise` and :func:`run_master_curve` (``args`` from the parsers of
:func:`jaxgear.cli._optimise_options.add_optimise_arguments` and
``add_master_curve_arguments``). The settings are names (options and the
case's ``[optimise]``); :mod:`jaxgear.io` maps them to objects (:func:`jaxgear.io.case_problem`,
:func:`jaxgear.io.optimiser_from_name`), and the report's sections that differ between
objectives dispatch on the objective's type (``functools.singledispatch``).
"""

from __future__ import annotations

import functools
import os
import time
import warnings

import equinox as eqx
import jax.numpy as jnp
import numpy as np

import jaxgear as jg
import jaxgear.rating as jr
from optimise import (
    VARIABLES,
    AbstractAcousticObjective,
    AbstractTribologyObjective,
    LeastSafetyFactor,
    LineLoadLp,
    LoadCentroid,
    RadiatedSoundPower,
    RobustTeRms,
    TePeakToPeak,
    TeRms,
    Variable,
    contour_map,
    master_curve,
    minimise,
    tip_relief_slots,
    zero_fluctuation_depth,
)

from ..io import (
    ACOUSTIC_OBJECTIVES,
    OPTIMISE_DEFAULTS,
    SEAT_TOLERANCE_MM,
    TORQUE_RANGE_OBJECTIVES,
    BearingChoice,
    Case,
    TrainForm,
    bearing_choices,
    case_problem,
    case_text_with_modifications,
    check_choice_text,
    check_train_design,
    design_modifications,
    embedded_case_text,
    load_case,
    objective_units,
    optimiser_from_name,
    rating_of,
    static_scene,
    tribology_of,
    write_choice_case,
    write_csv,
    write_design_case,
    write_json,
)
from . import _plots
from ._case_kinds import refuse_stages
from ._optimise_options import add_master_curve_arguments, add_optimise_arguments
from ._options import parse_range, range_values
from ._paths import case_inputs, check_case_outputs, check_output_file, clear_outputs
from ._progress import inner_bars, progress as progress_bar
from ._rating_report import measured_factors, measured_rating

__all__ = [
    "PARTIAL",
    "add_master_curve_arguments",
    "add_optimise_arguments",
    "check_settings",
    "check_write",
    "optimise_case",
    "run_master_curve",
    "run_optimise",
    "settings_from_case",
]

# the marker of an unfinished optimisation (see optimise_case)
PARTIAL = "optimum.partial.json"

# the [optimise] table's lists, written as the options write them
_JOINED = {"vars": ",", "torques": ":", "speeds": ":"}


def settings_from_case(case: Case, args=None) -> dict:
    """Optimisation settings: command-line options over the case's ``[optimise]`` table (already
    validated and normalised by :func:`jaxgear.io.parse_optimise` when the case was loaded).

    ``args``: the parsed options (an ``argparse.Namespace``; options left out or None do not
    count), or None (the case alone)."""
    table = dict(case.optimise or {})
    for key, sep in _JOINED.items():
        if key in table:  # vars = [...], torques / speeds = [start, stop, n]
            table[key] = sep.join(str(v) for v in table[key])
    given = {} if args is None else {k: v for k, v in vars(args).items() if v is not None}

    def get(key, default):
        return given.get(key, table.get(key, default))

    d = OPTIMISE_DEFAULTS  # one home: the case-file reference shows the same defaults
    choices = table.get("choices")  # a bearing choice: no vars, each candidate as given
    return {
        "objective": get("objective", d["objective"]),
        "vars": get("vars", None if choices else d["vars"]),
        "choices": choices,
        "torques": get("torques", d["torques"]),
        "reduce": get("reduce", d["reduce"]),
        "method": get("method", d["method"]),
        "max_iterations": int(get("max_iterations", d["max_iterations"])),
        "bounds": {k: tuple(v) for k, v in (table.get("bounds") or {}).items()},
        "speed": given.get("speed"),
        "speeds": get("speeds", d["speeds"]),
        "lp_order": get("lp_order", None),  # None: the objective's own (8)
        "te_limit_um": get("te_limit_um", d["te_limit_um"]),
        "quantile": get("quantile", d["quantile"]),
        "a_weighted": get("a_weighted", None),  # None: the objective's own (A-weighted)
    }


# -- the report's parts that depend on the objective --------------------------------------------
@functools.singledispatch
def _lp_order(objective):
    """The report's ``lp_order``: the objective's L_p order, None for other objectives."""
    return None


@_lp_order.register
def _(objective: LineLoadLp):
    return float(objective.order)


@functools.singledispatch
def _harris_torques(objective, design_torque: float) -> np.ndarray:
    """The Harris map's torques (N·m): 0.25 to 2 times the design torque (15 points, the design
    torque one of them)."""
    harris_t = np.linspace(0.25, 2.0, 15) * design_torque
    harris_t[np.argmin(np.abs(harris_t - design_torque))] = design_torque
    return harris_t


@_harris_torques.register
def _(objective: RobustTeRms, design_torque: float) -> np.ndarray:
    return np.array(objective.torques_Nm, dtype=float)  # the objective's own torque range


@_harris_torques.register
def _(objective: AbstractTribologyObjective, design_torque: float) -> np.ndarray:
    if objective.torques_Nm is None:
        return _harris_torques.dispatch(object)(objective, design_torque)
    return np.array(objective.torques_Nm, dtype=float)  # the objective's own torque range


@functools.singledispatch
def _has_map(objective) -> bool:
    """Whether a 2-variable tip relief problem gets the 41×41 map with the optimiser's path."""
    return False


@_has_map.register(TeRms)
@_has_map.register(TePeakToPeak)
def _(objective) -> bool:
    return True


@functools.singledispatch
def _change(objective, rep: dict) -> str:
    """The terminal line's objective change, start → optimum (exact contact)."""
    units = objective.units
    a, b = (rep[k][f"objective_exact_{units}"] for k in ("initial", "final"))
    return f"{a:.4g} -> {b:.4g} {units}"


@_change.register
def _(objective: LeastSafetyFactor, rep: dict) -> str:
    # the least safety factor itself (exact contact) reads better than 1/S̃
    a, b = (rep["rating"][k]["least_S"] for k in ("initial", "final"))
    return f"least safety factor {a:.4g} -> {b:.4g}"


@functools.singledispatch
def _objective_report(objective, problem, designs: dict, case: Case) -> dict:
    """The report's sections of one objective beyond those of every objective: none.
    ``designs``: ``{label: jaxgear.Modifications}`` (sharp relief starts)."""
    return {}


def _designs_report(objective, problem, shown: dict, case: Case, res) -> dict:
    """:func:`_objective_report` of the designs ``shown``; where a variable acts on the
    structure (a bearing's clearance: an acoustic objective only, :func:`check_settings`), each
    design on its own structure (the start's and the optimum's, :meth:`Problem.at_design`; the
    case's own and its bare flanks on the case's), its sections merged."""
    if all(v.kind.acts_on == "modifications" for v in problem.variables):
        return _objective_report(objective, problem, shown, case)
    xs = {"initial": res.x0, "final": res.x}
    out: dict = {}
    for label, mods in shown.items():
        at = problem.at_design(jnp.asarray(xs[label])) if label in xs else problem
        for key, section in _objective_report(at.objective, at, {label: mods}, case).items():
            out.setdefault(key, {}).update(section)
    return out


def _path_of_contact(mesh) -> float:
    """g_α (m) of the problem's one mesh (a mesh model, or a scene's one base plane): where the
    measured K_Hα reads its pairs (:func:`jaxgear.rating.transverse_load_factor`)."""
    plane = mesh if isinstance(mesh, jg.MeshModel) else mesh.base_planes[0]
    return float(plane.path_of_contact)


def _as_run_rates(case: Case, mods, res, mesh) -> dict:
    """The rating of design ``mods`` as ``jaxgear run`` rates the case file with that design
    (:func:`jaxgear.io.rating_of` of the case with that design: ISO 6336-1's K_Hβ and K_Hα
    unless ``[rating] use_measured`` names them, then those measured on ``res``, the design's
    exact-contact load map on ``mesh``: :func:`jaxgear.cli._rating_report.measured_rating`)."""
    rc = rating_of(case.replace(modifications=mods))
    rating = jr.rate(rc.geometry, rc.operating, rc.settings)
    if rc.use_measured:
        section = {"measured": measured_factors(res, None, 0, mesh)}
        rating = measured_rating(rc, section, rating)[1]
    s_h = np.asarray(rating.pitting.S_H, dtype=float)
    s_f = np.asarray(rating.bending.S_F, dtype=float)
    return {
        "S_H": s_h.tolist(),
        "S_F": s_f.tolist(),
        "least_S": float(min(s_h.min(), s_f.min())),
        "K_Hbeta": float(np.max(np.asarray(rating.factors.K_Hbeta))),
        "use_measured": list(rc.use_measured),
    }


@_objective_report.register
def _(objective: LeastSafetyFactor, problem, designs: dict, case: Case) -> dict:
    """``rating``: the rating in exact contact (sharp relief starts) of the designs, the case's
    own start (``case_start``) and its bare flanks (``unmodified``), with the K_Hβ measured on
    the load map and the design's C_a, C_β (the objective's rating), and the TE limit; each
    with ``as_jaxgear_run``, the rating ``jaxgear run`` gives the case file with that design
    (ISO's K_Hβ unless the case's ``[rating] use_measured`` names it: :func:`_as_run_rates`).
    """
    sharp = problem.sharp()
    rated = {}
    every = dict(designs) | {"case_start": sharp.base, "unmodified": sharp.unmodified()}
    for label, mods in every.items():
        res = jg.quasi_static(
            sharp.mesh,
            mods,
            sharp.design_torque,
            speed=sharp.speed,
            positions_per_pitch=sharp.positions_per_pitch,
        )
        r = objective.rating(res, mods)
        s_h = np.asarray(r.pitting.S_H, dtype=float)
        s_f = np.asarray(r.bending.S_F, dtype=float)
        rated[label] = {
            "S_H": s_h.tolist(),
            "S_F": s_f.tolist(),
            "least_S": float(min(s_h.min(), s_f.min())),
            "K_Hbeta_measured": float(jg.rating.face_load_factor(res)),
            "K_Halpha_measured": float(jg.rating.transverse_load_factor(
                res, path_of_contact=_path_of_contact(sharp.mesh))),
            "te_rms_m": float(res.te_rms),
        }
        if isinstance(sharp.mesh, jg.MeshModel) and not isinstance(case.form, TrainForm):
            rated[label]["as_jaxgear_run"] = _as_run_rates(case, mods, res, sharp.mesh)
    limit = objective.te_limit
    rated["te_limit_m"] = None if limit is None else float(limit)
    rated["notes"] = (
        "ISO 6336:2019 method B with K_Hbeta measured on the exact-contact load map at the "
        "design torque, the design's tip relief and crowning as ISO's C_a and C_beta, K_Halpha "
        "ISO's (K_Halpha_measured is reported, not rated with); S_H, S_F as [pinion, gear]; "
        "as_jaxgear_run: the rating jaxgear run gives the case file with that design (its "
        "[rating] as written: ISO 6336-1's K_Hbeta unless use_measured names K_Hbeta), which "
        "differs from the optimiser's by the K_Hbeta"
    )
    return {"rating": rated}


@eqx.filter_jit
def _exact_value(problem, x):
    """The objective of ``problem`` at ``x`` in exact contact (one compiled program per
    problem's structure: a second run on the same problem reuses it)."""
    return problem.value(x, jg.ExactContact())


@eqx.filter_jit
def _exact_design_value(problem, mods):
    """The objective of ``problem`` for the design ``mods`` (a whole
    :class:`jaxgear.Modifications`) in exact contact (one compiled program, as
    :func:`_exact_value`)."""
    return problem.design_value(mods, jg.ExactContact())


@eqx.filter_jit
def _exact_metrics(problem, x):
    """``problem.metrics`` at ``x`` in exact contact (one compiled program, as
    :func:`_exact_value`)."""
    return problem.metrics(x, jg.ExactContact())


@eqx.filter_jit
def _te_rms_vs_torque(problem, x, torques: tuple):
    """The TE RMS of ``problem``'s design ``x`` at each of ``torques`` (N m, a tuple: static,
    the Harris map's torques a constant of the program)."""
    return problem.te_rms_vs_torque(x, jnp.asarray(torques))


@functools.singledispatch
def _model_name(objective, scene) -> str:
    """The report's ``model``: what the objective was optimised on."""
    return "rigid mesh" if scene is None else "hybrid scene"


@_model_name.register
def _(objective: AbstractAcousticObjective, scene) -> str:
    return "housed lumped 3D scene (the case's acoustic path)"


def _db(watts: float) -> float:
    return 10 * np.log10(watts / 1e-12) if watts > 0 else float("nan")


@_change.register
def _(objective: AbstractAcousticObjective, rep: dict) -> str:
    a, b = (rep[k]["objective_exact_W"] for k in ("initial", "final"))
    weighted = " A-weighted" if objective.a_weighted else ""
    return f"{a:.4g} -> {b:.4g} W ({_db(a):.2f} -> {_db(b):.2f} dB{weighted} re 1 pW)"


@_objective_report.register
def _(objective: AbstractAcousticObjective, problem, designs: dict, case: Case) -> dict:
    """``acoustics``: the path (speeds, orders, the whine's method), the statistic, the
    weighting and, at the start and the optimum (exact contact, sharp relief starts), the power
    at each speed (W and dB re 1 pW; the orders summed, weighted as the objective weights
    them); "sound_power": the radiation's grid."""
    sharp = problem.sharp()
    path = objective.path
    per = eqx.filter_jit(
        lambda mods: objective.per_speed(mods, sharp.design_torque, jg.ExactContact()))
    section = {
        "speeds_rad_s": np.asarray(path.speeds).tolist(),
        "orders": list(path.orders),
        "whine_method": type(path.method).__name__,
        "harmonics": int(path.method.harmonics),
        "positions_per_period": int(path.positions),
        "statistic": type(objective.statistic).__name__,
        "a_weighted": bool(objective.a_weighted),
    }
    if isinstance(objective, RadiatedSoundPower):
        section["radiation_grid_Hz"] = np.asarray(objective.radiation.grid_hz).tolist()
    for label, mods in designs.items():
        w = np.asarray(per(mods), dtype=float)
        # a speed that radiates nothing has no level (null)
        section[label] = {"power_W": w.tolist(), "level_dB": [_db(v) if v > 0 else None for v in w]}
    return {"acoustics": section}


@_change.register
def _(objective: LoadCentroid, rep: dict) -> str:
    # the signed centroid reads better than c²
    a, b = (rep[k]["exact"]["load_centroid"] for k in ("initial", "final"))
    return f"centroid {a:+.4g} -> {b:+.4g} face widths from mid-face (+: towards z = b)"


#: the designs an optimisation compares (``optimum.json``'s ``candidates``), in words
CANDIDATES = {
    "optimum": "the optimiser's optimum",
    "case_start": "the case's own design (the start)",
    "unmodified": "the bare flanks (no relief, no crowning)",
}


def _best(values: dict) -> str:
    """The label of the lowest of ``values`` (``{label: objective}``, :data:`CANDIDATES`' order
    breaking ties: the optimum unless another is lower by more than 1e-9 relative)."""
    best = "optimum"
    for label in ("case_start", "unmodified"):
        v, b = values[label], values[best]
        if v < b - 1e-9 * abs(b):
            best = label
    return best


def optimise_case(case: Case, settings: dict, out_dir: str, progress: bool = True) -> dict:
    """Run one optimisation from the case's current modifications and write its files; returns
    the report (``optimum.json``)."""
    return _optimise(case, settings, out_dir, progress)[0]


def _optimise(case: Case, settings: dict, out_dir: str, progress: bool):
    """:func:`optimise_case`, returning the report and the problem."""
    torques = (
        range_values(settings["torques"], "--torques", positive=True)
        if settings["torques"]
        else None
    )
    scene = None
    speeds = None
    if settings.get("speed") is not None or settings.get("speeds"):
        # the hybrid scene (loaded at --speed; the dynamic_factor band sets its own speeds)
        scene, _ = static_scene(case)
    if settings.get("speeds"):
        speeds = range_values(settings["speeds"], "--speeds", positive=True)
    problem = case_problem(
        case,
        settings["vars"],
        settings["objective"],
        torques=torques,
        reduce=settings["reduce"],
        bounds=settings["bounds"],
        scene=scene,
        lp_order=8.0 if settings.get("lp_order") is None else settings["lp_order"],
        speed=settings.get("speed") or 0.0,
        speeds=speeds,
        te_limit=None if settings.get("te_limit_um") is None else settings["te_limit_um"] * 1e-6,
        quantile=settings.get("quantile"),
        a_weighted=settings.get("a_weighted"),
        progress=progress,
    )
    solver = optimiser_from_name(settings["method"])
    sharp = problem.sharp()  # sharp relief starts: the design as the case file writes it
    start = problem.case_values(design_modifications(case))
    _warn_idle_extents(case, problem.variables)
    # start 5 % of the interval inside the bounds: the reparametrisation's sigmoid is flat at a
    # bound (a depth of 0, no modification yet, would leave the optimiser almost no gradient)
    lo, hi = np.asarray(problem.lower), np.asarray(problem.upper)
    x0 = np.clip(problem.from_physical(start), lo + 0.05 * (hi - lo), hi - 0.05 * (hi - lo))
    # until optimum.json is written, a marker says the folder holds an unfinished run (plots
    # are written before optimum.json): an interruption, a crash or a kill leaves it behind
    partial = os.path.join(out_dir, PARTIAL)
    objective = problem.objective
    marker = {
        "complete": False,
        "case": case.name,
        "objective": objective.name,
        "variables": list(problem.names),
        "stage": "optimiser running",
        "notes": "an unfinished jaxgear optimise: no optimum.json; the plots beside this file, "
        "if any, are not those of a finished run. Removed when optimum.json is written.",
    }
    write_json(partial, marker)
    res = minimise(
        problem, x0, solver, max_iterations=settings["max_iterations"],
        progress=inner_bars(progress)
    )
    marker.update(
        stage="post-processing (exact values, plots)",
        iterations=res.iterations,
        evaluations=res.evaluations,
        converged=res.converged,
        parameters=problem.to_physical(res.x),
    )
    write_json(partial, marker)
    slots = tip_relief_slots(problem.names)
    two_d = slots is not None and _has_map(objective)
    # after the optimiser: exact-contact values, the Harris map and (2 variables) the 41×41 map
    post = progress_bar(
        total=3 if two_d else 2,
        desc="optimise: exact values, Harris map" + (", 41×41 map" if two_d else ""),
        disable=not progress,
    )
    scale = float(problem.scale)
    units = objective.units
    # each evaluation compiled once and called for the start and the optimum (eager calls of the
    # vmapped solve would trace it again each time); module-level programs with the problem an
    # argument, so that a second run of the same problem in one process compiles nothing again
    exact_value = functools.partial(_exact_value, sharp)

    def exact_metrics(x):
        m = {k: float(v) for k, v in _exact_metrics(sharp, jnp.asarray(x)).items()}
        m["load_centroid_mm"] = m["load_centroid"] * float(problem.face_width) * 1e3
        return m

    report = {
        "case": case.name,
        "objective": objective.name,
        "variables": list(problem.names),
        "torques_Nm": np.asarray(problem.torques).tolist(),
        "reduce": settings["reduce"],
        "quantile": settings.get("quantile"),
        "method": settings["method"],
        "model": _model_name(objective, scene),
        "speed_rad_s": settings.get("speed"),
        "mean_static_deflection_m": float(problem.delta_m),
        "lp_order": _lp_order(objective),
        "case_start": start,
        "initial": {
            "parameters": problem.to_physical(res.x0),
            f"objective_exact_{units}": float(exact_value(jnp.asarray(res.x0))) * scale,
            f"objective_smooth_{units}": res.value0 * scale,
            "exact": exact_metrics(res.x0),
        },
        "final": {
            "parameters": problem.to_physical(res.x),
            f"objective_exact_{units}": float(exact_value(jnp.asarray(res.x))) * scale,
            f"objective_smooth_{units}": res.value * scale,
            "exact": exact_metrics(res.x),
        },
        "unmodified_objective": scale,
        "iterations": res.iterations,
        "evaluations": res.evaluations,
        "converged": res.converged,
        "wall_time_s": res.wall_time_s,
        "max_iterations": settings["max_iterations"],
        "notes": "parameters in case-file units (depth_um for depths, fractions for extents); "
        "the optimiser starts from the case's values (case_start) moved at least 5 % of the "
        "interval inside the bounds (initial); "
        "'exact' values use sharp relief starts, the smooth optimisation rounds them over "
        "one position step (relief_blend) and, when end_relief.extent is a variable, the end "
        "relief start over one slice (end_relief_blend); 'exact' holds every objective's quantity at the design torque: "
        "load_centroid is (z̄ − b/2)/b, positive towards the z = b edge of the face; "
        "candidates: the optimum, the case's own design and its bare flanks (every relief and "
        "crowning depth 0) by the same objective in exact contact, best the lowest (the one "
        "--write writes); on_bound: a variable within 0.1 % of the interval of a bound, where "
        "the optimiser was pushing beyond it (widen [optimise] bounds), even when converged; "
        "held: the case's modifications no variable sets, kept at their values",
    }
    # the optimum beside the case's own design and its bare flanks, by the same objective in
    # exact contact: the best of the three is what --write writes
    exact_design = functools.partial(_exact_design_value, sharp)
    key = f"objective_exact_{units}"
    designs = {"optimum": sharp.modifications(jnp.asarray(res.x)), "case_start": sharp.base,
               "unmodified": sharp.unmodified()}
    values = {
        "optimum": report["final"][key],
        "case_start": float(exact_design(designs["case_start"])) * scale,
        "unmodified": float(exact_design(designs["unmodified"])) * scale,
    }
    best = _best(values)
    report["candidates"] = {
        label: {key: values[label], "design": CANDIDATES[label]} for label in values
    }
    report["best"] = best
    report["on_bound"] = problem.on_bounds(res.x)
    report["held"] = problem.held()
    shown = {"initial": sharp.modifications(jnp.asarray(res.x0)), "final": designs["optimum"]}
    if best != "optimum":
        shown[best] = designs[best]
    report.update(_designs_report(objective, problem, shown, case, res))
    post.update()
    os.makedirs(out_dir, exist_ok=True)
    _plots.convergence_plot(
        os.path.join(out_dir, "convergence.png"),
        res.history_value,
        ylabel=_plots.convergence_ylabel(objective.name, scale, units),
        title=f"{case.name}: convergence ({settings['method']}, {res.evaluations} evaluations)",
    )
    t_design = float(problem.design_torque)
    harris_t = _harris_torques(objective, t_design)
    lower = np.asarray(problem.lower, dtype=float)
    harris_key = tuple(float(t) for t in harris_t)  # static: the torques a constant, as before
    te_of = lambda x: np.asarray(  # noqa: E731
        _te_rms_vs_torque(sharp, jnp.asarray(x, dtype=float), harris_key))
    harris = {
        "torque_Nm": harris_t.tolist(),
        "te_rms_initial_m": te_of(res.x0).tolist(),
        "te_rms_optimum_m": te_of(res.x).tolist(),
        "te_rms_unmodified_m": te_of(lower).tolist(),
    }
    # the lower bounds mean "no modification" when every depth variable's lower bound is 0
    unmod = (
        "unmodified design (variables at lower bounds: depth 0)"
        if problem.lower_is_unmodified()
        else "design variables at their lower bounds"
    )
    harris["unmodified_is"] = unmod
    _plots.harris_plot(
        os.path.join(out_dir, "harris.png"),
        harris_t,
        [
            ("initial design", harris["te_rms_initial_m"], "o-"),
            ("optimum", harris["te_rms_optimum_m"], "s-"),
            (unmod, harris["te_rms_unmodified_m"], "k:"),
        ],
        design_torque=t_design,
        ylabel="TE RMS (µm), exact contact",
        title=f"{case.name}: Harris map of the designs",
    )
    report["harris"] = harris
    post.update()
    if two_d:
        i_d, i_g = slots
        G = np.linspace(float(problem.lower[i_g]), float(problem.upper[i_g]), 41)
        E = np.linspace(float(problem.lower[i_d]), float(problem.upper[i_d]), 41)
        grid = contour_map(problem, G, E, None)
        post.update()
        dm = float(problem.delta_m) * 1e6
        words = _plots.OBJECTIVE_WORDS[objective.name]
        _plots.optimiser_path_plot(
            os.path.join(out_dir, "path.png"),
            G,
            E * dm,
            grid * scale * 1e6,
            res.history_x[:, i_g],
            res.history_x[:, i_d] * dm,
            (float(res.x[i_g]), float(res.x[i_d]) * dm),
            label=f"{words} (µm), smooth contact",
            title=f"{case.name}: {words} over tip relief "
            f"extent and depth, {settings['method']} path",
        )
        k = np.unravel_index(np.argmin(grid), grid.shape)
        report["grid_41x41_best"] = {
            "extent": float(G[k[0]]),
            "depth_um": float(E[k[1]] * dm),
            "objective_smooth": float(grid[k]) * scale,
        }
    post.close()
    write_json(os.path.join(out_dir, "optimum.json"), report)
    os.unlink(partial)
    return report, problem


def _warn_idle_extents(case: Case, variables: tuple[Variable, ...]) -> None:
    """Warn about an extent variable whose relief has no depth in the case and no depth variable
    on its members: its gradient is zero and the optimiser leaves it where it starts."""
    for var in variables:
        if not var.base.endswith(".extent"):
            continue
        depth = var.base.replace(".extent", ".depth")
        members = set(var.members)
        if any(d.base == depth and members & set(d.members) for d in variables):
            continue  # the depth is a design variable too
        field = VARIABLES[depth][0]
        mods = design_modifications(case)
        if all(float(getattr(getattr(mods, m), field)) == 0 for m in var.members):
            warnings.warn(
                f"--vars {var.name}: the case's {depth} is 0 for the "
                f"{' and '.join(var.members)}, so the extent has no effect; add {depth} to --vars "
                "or give the case a depth",
                UserWarning,
                stacklevel=2,
            )


def check_settings(settings: dict, case: Case | None = None) -> dict:
    """Check optimisation settings that the option parser cannot: a ``torques`` range only with
    ``robust_te_rms``, and increasing; ``max_iterations >= 1``. Returns ``settings``.

    Raises:
        ValueError: one line naming the setting.
    """
    if settings.get("torques"):
        if settings["objective"] not in TORQUE_RANGE_OBJECTIVES:
            others = ", ".join(TORQUE_RANGE_OBJECTIVES[1:])
            raise ValueError(
                f"torques {settings['torques']!r} apply to the objectives {others} and "
                f"robust_te_rms only, not {settings['objective']}"
            )
        parse_range(settings["torques"], "--torques", positive=True)
    if int(settings["max_iterations"]) < 1:
        raise ValueError(f"max_iterations = {settings['max_iterations']}: must be >= 1")
    variables = settings.get("vars")
    if variables is not None:
        names = [n.strip() for n in str(variables).split(",")]
        allowed = f"{', '.join(VARIABLES)}, optionally prefixed 'pinion.' or 'gear.'"
        if not names or not all(names):
            raise ValueError(f"--vars {variables!r}: empty variable name, allowed {allowed}")
        for n in names:
            try:
                var = Variable.parse(n)
            except ValueError:
                raise ValueError(
                    f"--vars {n!r}: unknown design variable, allowed {allowed}"
                ) from None
            if (var.kind.acts_on != "modifications" and not settings.get("choices")
                    and settings["objective"] not in ACOUSTIC_OBJECTIVES):
                raise ValueError(
                    f"--vars {n!r}: a bearing's clearance is optimised by jaxgear optimise with "
                    f"the objective erp or sound_power (a housed case), not "
                    f"{settings['objective']}; the other objectives take it through the Python "
                    "API (jaxgear.io.case_problem; docs/bearings.md, 'As a design variable')"
                )
        if len(set(names)) != len(names):
            raise ValueError(f"--vars {variables!r}: names a variable twice")
    lp = settings.get("lp_order")
    if lp is not None:
        if settings["objective"] != "line_load_lp":
            raise ValueError(
                f"--lp-order {lp:g} applies to the objective line_load_lp only, "
                f"not {settings['objective']}"
            )
        if not 1 <= lp <= 64:
            raise ValueError(f"--lp-order {lp:g}: out of range, allowed [1, 64]")
    band = settings.get("speeds")
    if (settings["objective"] == "dynamic_factor") != bool(band):
        raise ValueError(
            "--objective dynamic_factor needs --speeds START:STOP:N (its speed band; in a case "
            "file [optimise] speeds = [start, stop, n]) and --speeds applies to it only "
            f"(objective {settings['objective']}, --speeds {band})"
        )
    if band and case is not None and (case.scene is None or not case.scene.hybrid):
        raise ValueError(
            f"--speeds {band}: the dynamic_factor objective needs a case with condensed bodies "
            "([scene.gear_body] or [scene.pinion_body])"
        )
    acoustic = settings["objective"] in ACOUSTIC_OBJECTIVES
    if acoustic and case is not None:
        tables = ("housing", "whine") + (("acoustics",) if settings["objective"] == "sound_power"
                                         else ())
        missing = [t for t in tables if getattr(case, t) is None]
        if missing:
            raise ValueError(
                f"--objective {settings['objective']} radiates the housing's whine: the case "
                f"{case.name!r} has no [{missing[0]}] (allowed a case with "
                f"{' and '.join(f'[{t}]' for t in tables)}; docs/acoustics.md)"
            )
    if settings.get("a_weighted") is not None and not acoustic:
        raise ValueError(
            f"--{'' if settings['a_weighted'] else 'no-'}a-weighted applies to the objectives "
            f"erp and sound_power only, not {settings['objective']}"
        )
    level = settings.get("quantile")
    if (settings.get("reduce") == "quantile") != (level is not None):
        raise ValueError(
            "--reduce quantile needs --quantile Q (its level in (0, 1); in a case file "
            f"[optimise] quantile = q) and --quantile applies to it only (--reduce "
            f"{settings.get('reduce')}, --quantile {level})"
        )
    if level is not None and not 0 < level < 1:
        raise ValueError(f"--quantile {level:g}: out of range, allowed (0, 1)")
    least = settings["objective"] == "least_safety"
    te_limit = settings.get("te_limit_um")
    if te_limit is not None and not least:
        raise ValueError(
            f"--te-limit-um {te_limit:g} applies to the objective least_safety only, "
            f"not {settings['objective']}"
        )
    if te_limit is not None and not 0 < te_limit <= 1e4:
        raise ValueError(f"--te-limit-um {te_limit:g}: out of range, allowed (0, 1e+04] µm")
    if least and case is not None and rating_of(case) is None:
        raise ValueError(
            f"--objective least_safety rates the pair to ISO 6336: the case {case.name!r} has no "
            "[rating] table (life_h, viscosity_40C_mm2_s, roughness_Rz_flank_um, "
            "roughness_Rz_root_um)"
        )
    lubricated = settings["objective"] in TORQUE_RANGE_OBJECTIVES[1:]
    if lubricated and case is not None and tribology_of(case) is None:
        raise ValueError(
            f"--objective {settings['objective']} rates the mesh's film and sliding loss: the "
            f"case {case.name!r} has no [lubricant] table (docs/tribology.md)"
        )
    speed = settings.get("speed")
    if speed is not None:
        if not 0 <= speed <= 1e5:
            raise ValueError(f"--speed {speed:g}: out of range, allowed [0, 1e+05] rad/s")
        if case is not None and (case.scene is None or not case.scene.hybrid):
            raise ValueError(
                f"--speed {speed:g}: needs a case with condensed bodies ([scene.gear_body] or "
                "[scene.pinion_body]); the rigid mesh has no centrifugal load"
            )
        if settings.get("choices"):
            raise ValueError(f"--speed {speed:g}: a bearing choice ([optimise.choices]) runs "
                             "on the case's lumped 3D scene at rest: allowed without --speed")
    return settings


def _pair_case(name_or_path: str, command: str, trains: bool = False):
    """The pair case a command optimises; a train case is refused in one line (``trains``:
    taken, for the checks of its objective, :func:`_check_train`)."""
    case = load_case(name_or_path)
    refuse_stages(case, command)
    if isinstance(case.form, TrainForm) and not trains:
        raise ValueError(
            f"jaxgear {command} optimises a gear pair; {case.name!r} is a train case: run "
            "it with jaxgear run or jaxgear sweep, or optimise one of its meshes as a pair case"
        )
    return case


def _check_train(case: Case, settings: dict) -> None:
    """A train case optimises its housing's noise: an acoustic objective (on a housed train),
    one modification on every gear. Raises ValueError: one line naming the option."""
    if not isinstance(case.form, TrainForm):
        return
    if settings["objective"] not in ACOUSTIC_OBJECTIVES:
        raise ValueError(
            f"--objective {settings['objective']}: {case.name!r} is a train case, whose housing's "
            "noise jaxgear optimise minimises (allowed --objective erp or sound_power on a "
            "train with [housing] and [whine]); optimise one of its meshes as a pair case for "
            "the others"
        )
    # variables without a member prefix, [modifications] common to every gear
    check_train_design(settings["objective"], settings["vars"], case.raw.get("modifications"),
                       case.gear_names, case.span_periods)


def _case_text(name_or_path: str) -> str:
    """The TOML text of a case: its file's, or the embedded case's."""
    if os.path.isfile(name_or_path):
        with open(name_or_path, encoding="utf-8") as f:
            return f.read()
    return embedded_case_text(name_or_path)


def check_write(path: str | None, name_or_path: str, case: Case | None = None, *,
                force: bool = False) -> str | None:
    """``--write PATH``, checked before any work: a ``.toml`` file name whose folder can be
    written, neither an input of the run (the case file, a file ``case`` names) nor, without
    ``force``, an existing file (:func:`~jaxgear.cli._paths.check_output_file`), and a case
    whose ``[modifications]`` can be rewritten. Returns ``path``.

    Raises:
        ValueError: one line naming ``--write`` and the path."""
    if path is None:
        return None
    if not str(path).endswith(".toml"):
        raise ValueError(f"--write {path}: a case file name ending in .toml")
    folder = os.path.dirname(os.path.abspath(path))
    if os.path.exists(folder) and not os.path.isdir(folder):
        raise ValueError(f"--write {path}: its folder {folder} is a file")
    inputs = case_inputs(case) if case is not None else None
    check_output_file(path, "--write", inputs=inputs, force=force)
    case_text_with_modifications(_case_text(name_or_path), {})  # the form can be rewritten
    return path


def run_optimise(args) -> int:
    """``jaxgear optimise``: the entry point (``args`` from the parser of
    :func:`add_optimise_arguments`); returns the exit status."""
    case = _pair_case(args.case, "optimise", trains=True)
    settings = check_settings(settings_from_case(case, args), case)
    if settings["choices"]:
        return _run_choice(case, settings, args)
    _check_train(case, settings)
    write_to = check_write(args.write, args.case, case, force=args.force)
    out = check_case_outputs(case, "optimise",
                             args.out or os.path.join("jaxgear-out", case.name, "optimise"),
                             force=args.force)
    clear_outputs(out, "optimise")  # e.g. path.png of an earlier 2-variable run
    rep, problem = _optimise(case, settings, out, progress=not args.quiet)
    where = "" if rep["speed_rad_s"] is None else f" (hybrid scene at {rep['speed_rad_s']:g} rad/s)"
    value = _change(problem.objective, rep)
    print(
        f"{rep['objective']}{where}: {value} (exact contact), "
        f"{rep['iterations']} iterations, {rep['evaluations']} evaluations, {rep['wall_time_s']:.1f} s"
    )
    for line in _optimum_lines(problem, rep):
        print(line)
    print(f"written to {out}/")
    if write_to is not None:
        best = rep["best"]
        try:
            write_design_case(
                write_to, _case_text(args.case), case, problem,
                rep["final"]["parameters"] if best == "optimum" else None,
                unmodified=best == "unmodified",
            )
        except ValueError as err:
            raise ValueError(f"--write {write_to}: {err}") from None
        print(f"{CANDIDATES[best]} written as a case file: {write_to} (jaxgear run {write_to})")
    return 0


def _choice_line(i: int, total: int, choice: BearingChoice, units: str) -> str:
    """The progress line of one candidate of a bearing choice."""
    head = f"candidate {i + 1}/{total} {choice.name}:"
    if not choice.fits:
        return (f"{head} bore {choice.bore_mm:.4g} mm does not fit the shaft's "
                f"{choice.seat_mm:.4g} mm: not ranked")
    moved = ("" if choice.result is None else
             f" -> {choice.value:.6g} {units}, clearance {choice.start_um:.4g} -> "
             f"{choice.clearance_um:.4g} µm")
    return f"{head} {choice.start_value:.6g} {units}{moved}"


#: the ranking table's columns (choice.json's candidates, choice.csv's header)
_CHOICE_COLUMNS = ("rank", "candidate", "fits", "bore_mm", "seat_mm", "objective_start",
                   "objective", "clearance_start_um", "clearance_um", "life_L10_Mrev",
                   "iterations", "converged")


def _choice_row(rank: int | None, c: BearingChoice) -> dict:
    res = c.result
    return dict(zip(_CHOICE_COLUMNS, (
        rank, c.name, c.fits, c.bore_mm, c.seat_mm, c.start_value, c.value, c.start_um,
        c.clearance_um, c.life_Mrev, None if res is None else res.iterations,
        None if res is None else res.converged), strict=True))


def _run_choice(case: Case, settings: dict, args) -> int:
    """``jaxgear optimise`` of a case with ``[optimise.choices]``: the bearing choice
    (:func:`jaxgear.io.bearing_choices`), its ranking table (``choice.json``, ``choice.csv``)
    and plot (``choice.png``), a line per candidate; ``--write``: the best candidate's
    case."""
    (bearing, candidates), = settings["choices"].items()  # {name: its bearing table}
    variable = f"{bearing}.clearance"
    optimised = settings["vars"] is not None  # [optimise] checked it is the bearing's clearance
    if optimised and [n.strip() for n in str(settings["vars"]).split(",")] != [variable]:
        raise ValueError(f"--vars {settings['vars']!r}: with [optimise.choices] allowed "
                         f"{variable!r} (each candidate's clearance optimised) or no vars")
    write_to = check_write(args.write, args.case, case, force=args.force)
    if write_to is not None:
        try:
            check_choice_text(_case_text(args.case), bearing)
        except ValueError as err:
            raise ValueError(f"--write {write_to}: {err}") from None
    out = check_case_outputs(case, "optimise",
                             args.out or os.path.join("jaxgear-out", case.name, "optimise"),
                             force=args.force)
    torques = (range_values(settings["torques"], "--torques", positive=True)
               if settings["torques"] else None)
    quiet = args.quiet
    total = len(candidates)
    objective = settings["objective"]
    units = objective_units(objective)

    def report(i, choice):
        if not quiet:
            print(_choice_line(i, total, choice, units), flush=True)

    t0 = time.perf_counter()
    bounds = settings["bounds"].get(variable)
    with warnings.catch_warnings():
        warnings.filterwarnings("ignore", message="optimiser stopped at the iteration cap")
        ranked = bearing_choices(
            case, bearing, candidates, objective,
            optimise_clearance=optimised, max_iterations=settings["max_iterations"],
            bounds=bounds, report=report, torques=torques, reduce=settings["reduce"],
            lp_order=8.0 if settings.get("lp_order") is None else settings["lp_order"],
            te_limit=None if settings.get("te_limit_um") is None
            else settings["te_limit_um"] * 1e-6,
            quantile=settings.get("quantile"), a_weighted=settings.get("a_weighted"),
            progress=not quiet)
    fitting = [c for c in ranked if c.fits]
    clear_outputs(out, "optimise")  # e.g. an earlier run's choice.png
    rows = [_choice_row(r + 1 if c.fits else None, c) for r, c in enumerate(ranked)]
    os.makedirs(out, exist_ok=True)
    report_json = {
        "case": case.name, "objective": objective, "units": units, "bearing": bearing,
        "clearance_optimised": optimised, "reduce": settings["reduce"],
        "max_iterations": settings["max_iterations"] if optimised else None,
        "candidates": rows, "best": fitting[0].name if fitting else None,
        "wall_time_s": time.perf_counter() - t0,
        "notes": "each candidate a case of its own (its operating point, its model): the "
        "bearing's table replaced by the candidate's (a catalogue entry, a pair of a tapered "
        "entry's rows, a table of a bearing's keys) at the same position, its clearance "
        "key (clearance_um, a tapered pair's end_play_um) the case bearing's; objective values "
        f"in {units}, unscaled, the optimisation's smooth law; a candidate whose bore differs "
        f"from the shaft's diameter by more than {SEAT_TOLERANCE_MM} mm does not fit and is "
        "not ranked; life_L10_Mrev: ISO 281's basic rating life at the held load (millions of "
        "revolutions; empty without a C)",
    }
    write_json(os.path.join(out, "choice.json"), report_json)
    write_csv(os.path.join(out, "choice.csv"), _CHOICE_COLUMNS,
              [[row[k] for row in rows] for k in _CHOICE_COLUMNS])
    if fitting:
        _plots.bearing_choice_plot(
            os.path.join(out, "choice.png"), [c.name for c in fitting],
            [c.start_value for c in fitting],
            [c.value for c in fitting] if optimised else None,
            ylabel=f"{objective} ({units})",
            title=f"{case.name}: {bearing} by {objective}")
    if not fitting:
        print(f"no candidate fits {bearing}'s shaft: nothing ranked; written to {out}/")
        return 0
    best = fitting[0]
    print(f"{bearing}: best {best.name} ({best.value:.6g} {units}"
          + (f", clearance {best.clearance_um:.4g} µm" if optimised else "")
          + f"); {len(fitting)} of {total} candidates fit; written to {out}/")
    if write_to is not None:
        try:
            write_choice_case(write_to, _case_text(args.case), case, bearing, best)
        except ValueError as err:
            raise ValueError(f"--write {write_to}: {err}") from None
        print(f"{best.name} written as a case file: {write_to} (jaxgear run {write_to})")
    return 0


def _unit(name: str) -> str:
    return " µm" if name.endswith(("depth", "clearance")) else ""


def _optimum_lines(problem, rep: dict) -> list[str]:
    """The terminal lines under the objective's: each variable (and whether it sits on a bound),
    the held modifications, the candidates and which is best, the rating as ``jaxgear run``
    gives it where the objective rates otherwise."""
    lines = []
    lower, upper = (problem.to_physical(b) for b in (problem.lower, problem.upper))
    for i, (k, v) in enumerate(rep["final"]["parameters"].items()):
        line = f"  {k} = {v:.5g}{_unit(k)}"
        side = rep["on_bound"][k]
        if side is not None:
            bound = (lower if side == "lower" else upper)[k]
            line += f"  ON ITS {side.upper()} BOUND ({bound:.5g}{_unit(k)}): not an interior optimum"
            kind = problem.variables[i].kind  # a modification's amount: none at its lower bound
            amount = (kind.unmodified_at(float(problem.lower[i]))
                      and not kind.unmodified_at(float(problem.upper[i])))
            if side == "lower" and amount:
                line += ", none of this modification is best"
            else:
                line += ", the objective still falls beyond it (widen [optimise] bounds)"
        lines.append(line)
    if not rep["converged"]:
        lines.append(
            f"  not converged: stopped at the iteration cap ({rep['iterations']} iterations)")
    if rep["held"]:
        held = ", ".join(f"{k} = {v:.5g}{_unit(k)}" for k, v in rep["held"].items())
        lines.append(f"  held at the case's values (not optimised): {held}")
    lines.append(f"  candidates (exact contact): {_candidates(problem.objective, rep)}; best: "
                 f"{CANDIDATES[rep['best']]}")
    if rep["best"] != "optimum":
        lines.append(f"  the optimiser's optimum is no better than {CANDIDATES[rep['best']]}: "
                     "that is the design --write writes")
    lines += _rating_lines(problem.objective, rep)
    return lines


@functools.singledispatch
def _candidates(objective, rep: dict) -> str:
    """The candidates' objective values, in words, for the terminal line."""
    key = f"objective_exact_{objective.units}"
    return ", ".join(f"{label.replace('_', ' ')} {c[key]:.4g} {objective.units}"
                     for label, c in rep["candidates"].items())


@_candidates.register
def _(objective: LeastSafetyFactor, rep: dict) -> str:
    return ", ".join(f"{label.replace('_', ' ')} least S {rep['rating'][r]['least_S']:.4g}"
                     for label, r in (("optimum", "final"), ("case_start", "case_start"),
                                      ("unmodified", "unmodified")))


@functools.singledispatch
def _rating_lines(objective, rep: dict) -> list[str]:
    """Lines on how ``jaxgear run`` rates the written design where the objective rates it
    otherwise: none."""
    return []


@_rating_lines.register
def _(objective: LeastSafetyFactor, rep: dict) -> list[str]:
    rated = rep["rating"]
    best = "final" if rep["best"] == "optimum" else rep["best"]
    if "as_jaxgear_run" not in rated[best]:
        return []
    start, end = rated["case_start"]["as_jaxgear_run"], rated[best]["as_jaxgear_run"]
    if "K_Hbeta" in end["use_measured"]:
        how = "with the measured K_Hβ ([rating] use_measured), as the optimiser does"
    else:
        how = (f"with ISO 6336-1's K_Hβ ({start['K_Hbeta']:.4g} -> {end['K_Hbeta']:.4g}), the "
               f"optimiser with the K_Hβ measured on the load map "
               f"({rated['case_start']['K_Hbeta_measured']:.4g} -> "
               f"{rated[best]['K_Hbeta_measured']:.4g}; [rating] use_measured = [\"K_Hbeta\"] "
               "rates the case so)")
    line = (f"  jaxgear run rates the case's design and the written one {how}: least safety "
            f"factor {start['least_S']:.4g} -> {end['least_S']:.4g}")
    return [line]


def master_curve_case(case: Case, extents, out_dir: str, progress: bool = True) -> dict:
    """Master Curve and contour map for a case; writes master_curve.json and master_curve.png."""
    t0 = time.perf_counter()
    problem = case_problem(
        case,
        "tip_relief.depth,tip_relief.extent",
        "te_rms",
        relief_blend=0.0,
        bounds={"tip_relief.depth": (0.0, 4.0), "tip_relief.extent": (0.02, 0.98)},
    )
    bar = progress_bar(total=2, desc="master curve: optimum per extent, 41×41 map",
                       disable=not progress)
    mc = master_curve(problem, extents)
    bar.update()
    eps = case.pair.transverse_contact_ratio
    dm = float(problem.delta_m)
    applies = case.stiffness_model == "uniform" and case.pair.helix_angle == 0 and eps < 2
    zf = (
        zero_fluctuation_depth(mc["extent"], eps) * dm
        if applies
        else np.full(len(mc["extent"]), np.nan)
    )
    G = np.linspace(min(0.02, mc["extent"].min()), max(0.7, mc["extent"].max()), 41)
    E = np.linspace(0.0, 4.0, 41)
    grid = contour_map(problem, G, E, jg.ExactContact()) * float(problem.scale)
    bar.update()
    bar.close()
    report = {
        "case": case.name,
        "stiffness": case.stiffness_model,
        "torque_Nm": case.torque,
        "mean_static_deflection_m": dm,
        "unmodified_te_rms_m": float(problem.scale),
        "master_curve": [
            {
                "extent": float(g),
                "depth_um": float(e) * 1e6,
                "te_rms_m": float(t),
                "te_rms_smooth_m": float(s),
                "on_bound": bool(b),
            }
            for g, e, t, s, b in zip(
                mc["extent"],
                mc["depth_m"],
                mc["te_rms_exact_m"],
                mc["te_rms_smooth_m"],
                mc["on_bound"],
                strict=True,
            )
        ],
        "zero_fluctuation_family": (
            {"applies": True, "depth_um": [None if np.isnan(v) else float(v) * 1e6 for v in zf]}
            if applies
            else {"applies": False, "why": "needs spur, uniform stiffness, ε_α < 2"}
        ),
        "wall_time_s": time.perf_counter() - t0,
    }
    os.makedirs(out_dir, exist_ok=True)
    on_bound = [r["on_bound"] for r in report["master_curve"]]
    family = None
    if applies:
        gg = np.linspace((eps - 1) / (2 * eps), (eps - 1) / eps, 200)[1:]
        family = (gg, zero_fluctuation_depth(gg, eps) * dm * 1e6)
    _plots.master_curve_plot(
        os.path.join(out_dir, "master_curve.png"),
        G,
        E * dm * 1e6,
        grid * 1e6,
        mc["extent"],
        mc["depth_m"] * 1e6,
        on_bound=on_bound,
        family=family,
        title=f"{case.name}: TE RMS map and Master Curve at {case.torque:g} N·m",
    )
    write_json(os.path.join(out_dir, "master_curve.json"), report)
    return report


def run_master_curve(args) -> int:
    """``jaxgear master-curve``: the entry point (``args`` from the parser of
    :func:`add_master_curve_arguments`); returns the exit status."""
    extents = range_values(args.extents, "--extents")
    case = _pair_case(args.case, "master-curve")
    out = check_case_outputs(case, "master-curve",
                             args.out or os.path.join("jaxgear-out", case.name, "master-curve"),
                             force=args.force)
    clear_outputs(out, "master-curve")
    rep = master_curve_case(case, extents, out, progress=not args.quiet)
    for row in rep["master_curve"]:
        flag = "  on a bound of the depth interval: not a true optimum" if row["on_bound"] else ""
        print(
            f"  Γ = {row['extent']:.3f}: E = {row['depth_um']:.3f} µm, "
            f"TE RMS = {row['te_rms_m'] * 1e6:.4f} µm{flag}"
        )
    n_bound = sum(bool(r["on_bound"]) for r in rep["master_curve"])
    if n_bound:
        print(
            f"  {n_bound} of {len(rep['master_curve'])} points on a bound of the depth interval "
            "(crosses on master_curve.png): their optimum lies beyond the depths searched"
        )
    print(f"written to {out}/")
    return 0
