"""A case file's optimisation problem: the names of ``[optimise]`` (and of the ``jaxgear
optimise`` options) mapped to :mod:`optimise` objects, and :func:`optimise.make_problem` on the
case's model objects.

This is the one place where objective, statistic and optimiser names become objects:
:data:`OBJECTIVES` (``objective = "te_rms"`` → :class:`optimise.TeRms`, ...),
:data:`STATISTICS` (``reduce = "max"`` → :class:`optimise.Max`, ...) and :data:`OPTIMISERS`
(``method = "lbfgs"`` → ``optimistix.LBFGS``, ``"adam"`` → ``optax.adam``). A new objective is
one class in :mod:`optimise` plus its name here.
"""

from __future__ import annotations

import copy
import json
import re
import tomllib
from collections.abc import Callable
from typing import NamedTuple

import equinox as eqx
import jax.numpy as jnp
import numpy as np
import optax
import optimistix as optx

import jaxgear as jg
import jaxgear.bearings as jb
import jaxgear.scenes as js
import optimise as op
from fem_prep.schema import atomic_write
from optimise import Problem, make_problem

from ._acoustic_path import case_acoustic_path, case_radiation, housed_acoustics
from ._case import Case, TrainForm
from ._case_file import parse_case
from ._case_model import static_scene
from ._load import load_case
from ._lubricant_table import tribology_of
from ._modifications_table import case_text_with_modifications, modifications_with
from ._operating import operating_point
from ._optimise_table import (
    ACOUSTIC_OBJECTIVES,
    BEARING_NAME,
    check_train_design,
    designs_structure,
)
from ._rating_table import RatingCase, rating_of

__all__ = [
    "OBJECTIVES",
    "OPTIMISERS",
    "SEAT_TOLERANCE_MM",
    "STATISTICS",
    "BearingChoice",
    "bearing_choices",
    "case_bearing_design",
    "case_problem",
    "case_text_with_bearing",
    "case_text_with_clearance",
    "check_choice_text",
    "clearance_key",
    "design_case_text",
    "design_modifications",
    "objective_from_name",
    "optimiser_from_name",
    "write_choice_case",
    "write_design_case",
]

def _quantile(quantile=None, **_) -> op.Quantile:
    if quantile is None:
        raise ValueError("reduce = 'quantile' needs its level: quantile = q in (0, 1) (e.g. 0.9)")
    return op.Quantile(float(quantile))


# ``reduce = "..."``: the statistic over the torques of robust_te_rms and the tribology
# objectives, over the speeds of the acoustic objectives (``quantile``: its level q in (0, 1))
STATISTICS: dict[str, Callable[..., op.AbstractStatistic]] = {
    "max": lambda **_: op.Max(),
    "mean": lambda **_: op.Mean(),
    "quantile": _quantile,
}

DEFAULT_TOL = 1e-7  # rtol = atol of the optimiser's stopping rule
DEFAULT_LEARNING_RATE = 0.05  # Adam's step


def _robust(torque, torques=None, reduce="max", quantile=None, **_) -> op.RobustTeRms:
    torques = np.array([float(torque)]) if torques is None else torques
    return op.RobustTeRms(torques, _statistic(reduce, quantile))


def _dynamic(torque, speeds=None, integrator=None, window=None, **_) -> op.DynamicFactor:
    settings = {"integrator": integrator, "window": window}
    given = {k: v for k, v in settings.items() if v is not None}
    return op.DynamicFactor([] if speeds is None else speeds, **given)


def _least_safety(torque, rating: RatingCase | None = None, te_limit=None, **_):
    if rating is None:
        raise ValueError(
            "objective = 'least_safety' needs the case's [rating] table (ISO 6336 method B: "
            "life_h, viscosity_40C_mm2_s, roughness_Rz_flank_um, roughness_Rz_root_um)"
        )
    return op.LeastSafetyFactor(
        rating.geometry, rating.operating, rating.settings, te_limit=te_limit
    )


def _lubrication(case: Case) -> op.MeshLubrication | None:
    """The lubricated mesh of a pair case's ``[lubricant]`` (None without the table)."""
    inputs = tribology_of(case)
    if inputs is None:
        return None
    return op.MeshLubrication(
        case.pair,
        inputs.lubricant,
        inputs.speed,
        inputs.roughness,
        case.youngs_modulus,
        case.poisson_ratio,
        film=inputs.film,
        friction=inputs.friction,
    )


def _tribology(kind):
    """The builder of a tribology objective ``kind``: the case's lubricated mesh, the torque
    range (None: the design torque) and its statistic."""

    def build(torque, lubrication=None, torques=None, reduce="max", quantile=None, **_):
        if lubrication is None:
            raise ValueError(
                f"objective = {kind.name!r} needs the case's [lubricant] table (the oil, its "
                "temperature and the flanks' roughness; docs/tribology.md)"
            )
        return kind(lubrication, torques, _statistic(reduce, quantile))

    return build


def _acoustic(kind):
    """The builder of an acoustic objective ``kind``: its acoustic path (an
    :class:`optimise.AcousticPath`; :func:`case_problem` builds a housed case's,
    :func:`case_acoustic_path`), the statistic over the path's speeds, the A weighting, and
    (sound power) the cached radiation (:func:`case_radiation`)."""

    def build(torque, acoustic_path=None, reduce="max", a_weighted=True, radiation=None,
              quantile=None, **_):
        if acoustic_path is None:
            raise ValueError(
                f"objective = {kind.name!r} needs acoustic_path = optimise.AcousticPath(...) "
                "(the housed gearbox, its speeds and orders; docs/acoustics.md)"
            )
        extra = {} if radiation is None else {"radiation": radiation}
        if kind is op.RadiatedSoundPower and radiation is None:
            raise ValueError(
                "objective = 'sound_power' needs radiation = optimise.SurfaceRadiation(...) (the "
                "cached radiation resistance at the path's frequencies)"
            )
        weighted = True if a_weighted is None else bool(a_weighted)
        return kind(acoustic_path, _statistic(reduce, quantile), weighted, **extra)

    return build


# ``objective = "..."``: the objective object, from the design torque (N·m) and the settings
# (torques, reduce, lp_order, speeds, integrator, window, rating, te_limit, lubrication,
# acoustic_path, a_weighted, radiation)
OBJECTIVES: dict[str, Callable[..., op.AbstractObjective]] = {
    "te_rms": lambda torque, **_: op.TeRms(),
    "te_ptp": lambda torque, **_: op.TePeakToPeak(),
    "robust_te_rms": _robust,
    "max_line_load": lambda torque, **_: op.MaxLineLoad(),
    "load_centroid": lambda torque, **_: op.LoadCentroid(),
    "line_load_lp": lambda torque, lp_order=8.0, **_: op.LineLoadLp(lp_order),
    "dynamic_factor": _dynamic,
    "least_safety": _least_safety,
    "power_loss": _tribology(op.MeshPowerLoss),
    "efficiency_loss": _tribology(op.EfficiencyLoss),
    "min_specific_film": _tribology(op.MinSpecificFilm),
    "max_flash_temperature": _tribology(op.MaxFlashTemperature),
    "erp": _acoustic(op.EquivalentRadiatedPower),
    "sound_power": _acoustic(op.RadiatedSoundPower),
}

# ``method = "..."``: the optimiser object (an optimistix minimiser or an optax transformation)
OPTIMISERS: dict[str, Callable[..., object]] = {
    "lbfgs": lambda tol=DEFAULT_TOL, **_: optx.LBFGS(rtol=tol, atol=tol),
    "adam": lambda tol=DEFAULT_TOL, learning_rate=DEFAULT_LEARNING_RATE, **_: (
        optx.OptaxMinimiser(optax.adam(learning_rate), rtol=tol, atol=tol)
    ),
}


# the keywords case_problem takes besides its own
_SETTINGS = {
    "torques",
    "reduce",
    "lp_order",
    "speeds",
    "integrator",
    "window",
    "contact",
    "relief_blend",
    "end_relief_blend",
    "bounds",
    "speed",
    "te_limit",
    "acoustic_path",
    "a_weighted",
    "radiation",
    "quantile",
    "progress",
}


def _lookup(table: dict, what: str, name: str):
    try:
        return table[name]
    except (KeyError, TypeError):
        raise ValueError(
            f"{what} = {name!r} is unknown: allowed {', '.join(table)}"
        ) from None


def _statistic(name: str, quantile=None) -> op.AbstractStatistic:
    return _lookup(STATISTICS, "reduce", name)(quantile=quantile)


def objective_from_name(name: str, torque, **settings) -> op.AbstractObjective:
    """The objective object of a case-file name (:data:`OBJECTIVES`).

    Args:
        name: e.g. "te_rms", "robust_te_rms", "dynamic_factor".
        torque: the design torque (N·m): the torque range of "robust_te_rms" when none is given.
        settings: ``torques`` (N·m, (T,)) and ``reduce`` ("max" | "mean" | "quantile", with
            ``quantile`` its level in (0, 1)) of "robust_te_rms",
            ``lp_order`` of "line_load_lp", ``speeds`` (rad/s), ``integrator``, ``window`` of
            "dynamic_factor", ``rating`` (the case's :class:`RatingCase`,
            :func:`rating_of`) and ``te_limit`` (the TE RMS limit, m, > 0, or None) of
            "least_safety", ``lubrication`` (the case's :class:`optimise.MeshLubrication`, from
            its ``[lubricant]``), ``torques`` and ``reduce`` of the tribology objectives
            ("power_loss", "efficiency_loss", "min_specific_film", "max_flash_temperature");
            ``acoustic_path`` (an :class:`optimise.AcousticPath`), ``reduce`` over its speeds,
            ``a_weighted`` (default True) and ``radiation`` (an
            :class:`optimise.SurfaceRadiation`, "sound_power" only) of the acoustic objectives
            ("erp", "sound_power"); the others are ignored.

    Raises:
        ValueError: an unknown name or reduce, settings out of range (as the objective class),
            "least_safety" without ``rating`` (the case has no ``[rating]`` table), a
            tribology objective without ``lubrication`` (no ``[lubricant]``), an acoustic
            objective without ``acoustic_path`` ("sound_power": or without ``radiation``).
    """
    return _lookup(OBJECTIVES, "objective", name)(torque, **settings)


def optimiser_from_name(name: str, **settings):
    """The optimiser object of a case-file ``method`` (:data:`OPTIMISERS`), for
    :func:`optimise.minimise`: "lbfgs" → ``optimistix.LBFGS(rtol=tol, atol=tol)``, "adam" →
    ``optimistix.OptaxMinimiser(optax.adam(learning_rate), rtol=tol, atol=tol)``.

    Args:
        name: "lbfgs" or "adam".
        settings: ``tol`` (default 1e-7), ``learning_rate`` (Adam, default 0.05).

    Raises:
        ValueError: an unknown name.
    """
    return _lookup(OPTIMISERS, "method", name)(**settings)


def design_modifications(case: Case) -> jg.Modifications:
    """The :class:`jaxgear.Modifications` a case's design starts from and the design variables
    are written into: a pair's own; a train's one modification on every gear (its
    ``[modifications]`` common to every gear) as both members of every mesh."""
    if not isinstance(case.form, TrainForm):
        return case.modifications
    first = case.gear_modifications[0]
    return jg.Modifications(pinion=first, gear=first)


def case_bearing_design(case: Case) -> op.BearingDesign:
    """The rolling bearings of a ``lumped3d`` pair or train case at their operating point
    (:func:`operating_point`, found once), as design variables name them: each shaft by its
    table without ``scene.`` (``pinion_shaft``, ``gear_shaft``; a train's ``shafts.<name>``):
    :func:`optimise.bearing_design`.

    Raises:
        ValueError: a case without rolling bearings from their geometry (one line)."""
    shafts = case.form.bearing_shafts(case)
    if shafts is None:
        raise ValueError(
            "[optimise] vars: a bearing's clearance is a design variable of a lumped3d case "
            "whose shafts stand on rolling bearings from their geometry; this case has none")
    names = tuple(n.removeprefix("scene.") for n in shafts.names)
    extra_z = case.form.bearing_scene(case, case.scene)[2]
    return op.bearing_design(operating_point(case), names, extra_z)


class BearingChoice(NamedTuple):
    """One candidate of :func:`bearing_choices`: its ``name``, the ``case`` with it, its
    clearance's optimum (``clearance_um``, and where it started, ``start_um``; µm of its kind's
    clearance field, a tapered pair's end play; the start where the clearance is not
    optimised), the objective there and at the start (``value``, ``start_value``: the
    objective's units, unscaled, the problem's smooth law; each candidate's problem scales by
    its own unmodified design, so the unscaled values are what compares), the optimiser's
    ``result`` (None: evaluated as is), whether its bore ``bore_mm`` ``fits`` the shaft's
    diameter ``seat_mm`` (:data:`SEAT_TOLERANCE_MM`; a candidate that does not fit has no
    ``case``, values or result: None) and its ISO 281 basic rating life L10 at the held load
    ``life_Mrev`` (millions of revolutions; None where the kind has no rating or no C)."""

    name: str
    case: Case | None
    clearance_um: float | None
    start_um: float | None
    value: float | None
    start_value: float | None
    result: op.OptimisationResult | None
    fits: bool = True
    bore_mm: float | None = None
    seat_mm: float | None = None
    life_Mrev: float | None = None


#: how far a candidate's bore may differ from its shaft's diameter and still fit (mm): the
#: nominal sizes agree (a catalogue's bore converted from inches, 25.00122 mm for 25 mm), the
#: fit's interference being the shaft's tolerance class, which the model does not hold
SEAT_TOLERANCE_MM = 0.01

def _check_choice(case: Case, bearing: str, candidates: dict, objective: str) -> tuple[str, int]:
    """(shaft, k) of a bearing choice's ``bearing`` name, or one line refusing the case, the
    name, the candidates or the objective."""
    if isinstance(case.form, TrainForm) or case.scene is None or not case.scene.lumped:
        raise ValueError(f"bearing = {bearing!r}: a bearing choice runs on a pair case whose "
                         "[scene] is lumped3d (its shafts on rolling bearings); this case's is "
                         f"{'a train' if isinstance(case.form, TrainForm) else 'not'}")
    hit = BEARING_NAME.match(bearing.strip())
    shafts = (case.raw.get("scene") or {})
    if hit is None or hit.group(1) not in shafts or not int(hit.group(2)) < len(
            shafts[hit.group(1)].get("bearings", ())):
        raise ValueError(f"bearing = {bearing!r}: allowed <shaft>.bearings[<k>] of the case's "
                         "[scene] (e.g. 'pinion_shaft.bearings[0]')")
    if not candidates:
        raise ValueError("candidates is empty: allowed {name: the bearing's table}")
    if not designs_structure(objective):
        raise ValueError(f"objective = {objective!r} does not take a designed structure: "
                         "allowed an objective a bearing's stiffness acts on (not "
                         "dynamic_factor)")
    return hit.group(1), int(hit.group(2))


def _candidate(case: Case, shaft: str, k: int, name: str, table: dict) -> Case:
    """The case with bearing ``k`` of ``shaft`` the candidate's ``table`` at the same position,
    its clearance key (:func:`clearance_key`) the case bearing's where the table gives none."""
    data = copy.deepcopy(case.raw)
    old = data["scene"][shaft]["bearings"][k]
    data["scene"][shaft]["bearings"][k] = {"position_mm": old["position_mm"]} | dict(table)
    try:
        candidate = parse_case(data, case.name)
        key = clearance_key(getattr(candidate.scene, shaft).bearings[k].rolling)
        if key in old and key not in table:  # the start: the case's clearance
            data["scene"][shaft]["bearings"][k][key] = old[key]
            candidate = parse_case(data, case.name)
    except ValueError as err:
        raise ValueError(f"candidate {name!r}: {err}") from None
    return candidate


def _bearing_table(case: Case, shaft: str, k: int) -> dict:
    """The case-file table of bearing ``k`` of ``[scene.<shaft>]`` (the ``case``'s raw keys)."""
    return dict(case.raw["scene"][shaft]["bearings"][k])


def bearing_choices(
    case: Case,
    bearing: str,
    candidates: dict,
    objective: str = "te_rms",
    *,
    optimise_clearance: bool = True,
    max_iterations: int = 10,
    bounds: tuple[float, float] | None = None,
    report: Callable[[int, BearingChoice], None] | None = None,
    **settings,
) -> tuple[BearingChoice, ...]:
    """Bearing choice by enumeration: each candidate bearing at the position ``bearing`` of a
    ``lumped3d`` pair case whose bore fits the shaft (its diameter within
    :data:`SEAT_TOLERANCE_MM`), its clearance optimised (:func:`case_problem` with the
    variable ``<bearing>.clearance``, :func:`optimise.minimise` from the candidate's own
    clearance) or, with ``optimise_clearance`` False, evaluated at it; ranked by the objective,
    best first, the candidates that do not fit after them (not ranked, in the given order). A
    discrete choice is not a gradient variable: each candidate is a case of its own (its
    operating point, its model).

    Args:
        case: a pair case whose ``[scene]`` is ``lumped3d``.
        bearing: the bearing's name, ``pinion_shaft.bearings[0]``.
        candidates: ``{name: table}``, each table the bearing's case-file keys without
            ``position_mm`` (``{"catalogue": "6205"}``, or a ``kind`` with its geometry; its
            clearance key, ``clearance_um`` or a tapered pair's ``end_play_um``, the start,
            default the case bearing's or the kind's default).
        objective: an objective name (:data:`OBJECTIVES`) that takes a designed structure.
        optimise_clearance: optimise each candidate's clearance (else evaluate it as given).
        max_iterations: the optimiser's iterations per candidate (int >= 1).
        bounds: the clearance's bounds (µm), default the variable's.
        report: called with (index, :class:`BearingChoice`) as each candidate is done (the
            order of ``candidates``), e.g. a progress line.
        settings: the objective's settings (:func:`case_problem`).

    Raises:
        ValueError: a case that is not a pair case with a ``lumped3d`` ``[scene]``, a bearing
            name that is not ``<shaft>.bearings[<k>]`` of it, no candidate, an objective that
            does not take a designed structure; what loading a candidate's case refuses (one
            line, the candidate named), before any solve; what :func:`case_problem` refuses.
    """
    shaft, k = _check_choice(case, bearing, candidates, objective)
    variable = f"{bearing.strip()}.clearance"
    given = {} if bounds is None else {"bounds": {variable: tuple(bounds)}}
    cases = {name: _candidate(case, shaft, k, name, table)
             for name, table in candidates.items()}  # every refusal before any solve
    out, unfit = [], []
    for i, (name, candidate) in enumerate(cases.items()):
        spec = getattr(candidate.scene, shaft)
        bore, seat = (float(spec.bearings[k].rolling.bore) * 1e3, float(spec.diameter) * 1e3)
        if abs(bore - seat) > SEAT_TOLERANCE_MM:
            choice = BearingChoice(name, None, None, None, None, None, None, False, bore, seat)
            unfit.append(choice)
        else:
            problem = case_problem(candidate, variable, objective, **given, **settings)
            x0 = problem.from_physical(problem.case_values(candidate.modifications))
            scale = float(problem.scale)
            if optimise_clearance:
                res = op.minimise(problem, x0, max_iterations=max_iterations, progress=False)
                x, value, value0 = float(res.x[0]), res.value * scale, res.value0 * scale
            else:
                res, x = None, float(x0[0])
                value = value0 = float(eqx.filter_jit(_value)(problem, jnp.asarray(x0))) * scale
            choice = BearingChoice(name, candidate, x, float(x0[0]), value, value0, res, True,
                                   bore, seat, _life_Mrev(problem))
            out.append(choice)
        if report is not None:
            report(i, choice)
    return tuple(sorted(out, key=lambda c: c.value)) + tuple(unfit)


def _value(problem: Problem, x):
    return problem.value(x)


def _life_Mrev(problem: Problem) -> float | None:
    """ISO 281's basic rating life L10 (millions of revolutions) of the problem's one designed
    bearing at its held load, or None where its kind has no rating life or no C."""
    var = problem.variables[0]
    kind = problem.bearings.kind(var)
    if kind.life_exponent is None or kind.dynamic_rating is None:
        return None
    i, j = problem.bearings.slot(var)
    f = np.asarray(problem.bearings.loads[i][j], float)
    life = jb.rating_life(kind, float(np.hypot(f[0], f[1])), float(f[2]), 1.0)
    return float(life.revolutions) / 1e6


def case_problem(
    case: Case,
    variables,
    objective: str = "te_rms",
    *,
    slices: int | None = None,
    scene: js.Scene | None = None,
    positions_per_pitch: int | None = None,
    **settings,
) -> Problem:
    """The :class:`optimise.Problem` of a case: its rigid mesh (or ``scene``), its
    modifications as the starting design, its torque as the design torque, its positions per
    pitch and its smooth contact width.

    An acoustic objective ("erp", "sound_power") without an ``acoustic_path`` runs on the
    housed case's own (:func:`case_acoustic_path`: its lumped 3D scene with the housing, the
    ``[whine]`` speeds and the orders in the housing's band; that scene is the structure),
    "sound_power" with the radiation of its ``[acoustics]`` (:func:`case_radiation`;
    ``progress``: a bar over its BEM solves). A variable of a rolling bearing
    (``pinion_shaft.bearings[0].clearance``, µm) acts on the case's scene at the bearings'
    operating point (:func:`case_bearing_design`, the loads held): the acoustic path's scene, or
    for a quasi-static objective without ``scene`` the case's quasi-static lumped 3D scene
    (:func:`static_scene`) instead of its rigid mesh. A housed train case takes the acoustic
    objectives only, on its lumped 3D scene with the housing: its design is one modification on
    every gear (:func:`design_modifications`; variables without a member prefix).

    Args:
        case: a :class:`Case` (:func:`jaxgear.io.load_case`).
        variables: as :func:`optimise.make_problem`.
        objective: an objective name (:data:`OBJECTIVES`).
        slices: slices per contact line of the rigid mesh (default the case's).
        scene: the structure to optimise on instead of the case's rigid mesh, e.g. the hybrid
            scene of :func:`static_scene`; its mesh replaces ``slices``.
        positions_per_pitch: default the case's.
        settings: the objective's settings (:func:`objective_from_name`: ``torques``,
            ``reduce``, ``lp_order``, ``speeds``, ``integrator``, ``window``, ``te_limit`` in
            m; "least_safety" rates with the case's ``[rating]``, the tribology objectives
            with its ``[lubricant]``), the smoothing
            (``contact``, default ``SmoothContact`` of the case's width; ``relief_blend``,
            ``end_relief_blend``: :class:`optimise.Smoothing`) and the other keywords of
            :func:`optimise.make_problem` (``bounds``, ``speed``).

    Raises:
        ValueError: an unknown objective name, "least_safety" on a case without ``[rating]``,
            an acoustic objective on a case without ``[housing]`` and ``[whine]`` ("sound_power":
            or without ``[acoustics]``), a train case with another objective, a prefixed
            variable or a ``[modifications.<gear>]`` table, a bearing's variable on a case
            without rolling bearings from their geometry, as :func:`optimise.make_problem`
            otherwise.
    """
    unknown = sorted(set(settings) - _SETTINGS)
    if unknown:
        raise TypeError(f"case_problem() got an unexpected keyword argument {unknown[0]!r}")
    if isinstance(case.form, TrainForm):  # its housing's noise, one modification on every gear
        check_train_design(objective, variables, case.raw.get("modifications"), case.gear_names,
                           case.span_periods)
    smoothing = {k: settings.pop(k, None) for k in ("contact", "relief_blend", "end_relief_blend")}
    problem_settings = {k: settings.pop(k) for k in ("bounds", "speed") if k in settings}
    progress = bool(settings.pop("progress", False))
    if objective in ACOUSTIC_OBJECTIVES and settings.get("acoustic_path") is None:
        housed = housed_acoustics(case)
        settings["acoustic_path"] = case_acoustic_path(case, objective, housed=housed)
        if objective == "sound_power" and settings.get("radiation") is None:
            settings["radiation"] = case_radiation(case, settings["acoustic_path"], housed,
                                                   progress=progress)
    if objective in ACOUSTIC_OBJECTIVES and scene is None:
        scene = settings["acoustic_path"].model.scene  # the path's own structure
    structural = [v for v in op.variables_of(variables) if v.kind.acts_on == "structure"]
    if structural:
        problem_settings["bearings"] = case_bearing_design(case)
        if scene is None and objective not in ACOUSTIC_OBJECTIVES:
            scene = static_scene(case, slices=slices)[0]  # the bearings' scene, loads held
    train = isinstance(case.form, TrainForm)  # rated and lubricated per pair only
    goal = objective_from_name(
        objective, case.torque, rating=None if train else rating_of(case),
        lubrication=None if train else _lubrication(case), **settings
    )
    if smoothing["contact"] is None:
        smoothing["contact"] = goal.default_contact(case.smooth_width)
    mesh = case.mesh_model(slices=slices) if scene is None else scene
    return make_problem(
        mesh,
        design_modifications(case),
        case.torque,
        variables,
        goal,
        positions_per_pitch=int(positions_per_pitch or case.positions_per_pitch),
        smoothing=op.Smoothing(**smoothing),
        **problem_settings,
    )


# -- a design written back as a case file ------------------------------------------------------
#: the flank modifications a design is made of (their ``depth_um`` 0: the bare flanks)
_DESIGN_MODIFICATIONS = ("tip_relief", "root_relief", "crowning", "end_relief")


def design_case_text(
    text: str, case: Case, problem: Problem, parameters: dict | None, *, unmodified: bool = False
) -> str:
    """The case file ``text`` (of ``case``) with the design ``parameters`` (case-file units by
    variable name, :meth:`optimise.Problem.to_physical`: ``depth_um`` for depths, fractions
    for extents; None: the case's own values) written into its ``[modifications]`` (each
    variable on its members; every other entry and line, comments included, kept:
    :func:`case_text_with_modifications`). ``unmodified``: every relief's and crowning's
    ``depth_um`` the case gives written 0 (the bare flanks, :meth:`optimise.Problem.unmodified`:
    extents, shapes and deviations kept). A bearing's clearance is written as its kind's
    clearance key (:func:`clearance_key`: ``clearance_um``, a tapered roller pair's
    ``end_play_um``) into its ``[[scene.<shaft>.bearings]]`` table
    (:func:`case_text_with_clearance`).

    Raises:
        ValueError: modifications or a bearing table this cannot rewrite (one line)."""
    values, clearances = {}, []
    for var in problem.variables if parameters is not None else ():
        if var.kind.acts_on == "structure":
            key = clearance_key(problem.bearings.kind(var))
            clearances.append((var.shaft, var.bearing, parameters[var.name], key))
            continue
        mod, quantity = var.base.split(".")
        key = "depth_um" if quantity == "depth" else "extent"
        values[(var.members, mod, key)] = parameters[var.name]
    table = case.raw.get("modifications") or {}
    if unmodified:
        given = {*table, *table.get("pinion", {}), *table.get("gear", {})}
        for mod in _DESIGN_MODIFICATIONS:
            if mod in given:
                values[(("pinion", "gear"), mod, "depth_um")] = 0.0
    out = case_text_with_modifications(text, modifications_with(table, values))
    for shaft, k, value, key in clearances:
        out = case_text_with_clearance(out, shaft, k, value, key)
    return out


_TABLE_HEADER = re.compile(r"^\s*\[")


def clearance_key(kind) -> str:
    """The case-file key (µm) of a rolling bearing kind's clearance field
    (``kind.clearance_field``): ``clearance_um``, a tapered roller pair's ``end_play_um``."""
    return f"{kind.clearance_field}_um"


def _bearing_lines(lines: list[str], shaft: str, k: int, what: str) -> tuple[int, int]:
    """(header, end) line indices of the k-th ``[[scene.<shaft>.bearings]]`` table of a case
    file's ``lines`` (its keys lie between); one line refusing a bearing the text does not
    give so (``what`` is written back)."""
    header = re.compile(rf"^\s*\[\[\s*scene\.{re.escape(shaft)}\.bearings\s*\]\]")
    starts = [i for i, line in enumerate(lines) if header.match(line)]
    if not k < len(starts):
        raise ValueError(
            f"{shaft}.bearings[{k}]: the case file does not give it as a "
            f"[[scene.{shaft}.bearings]] table: write it so to have the {what} written back")
    start = starts[k]
    end = next((j for j in range(start + 1, len(lines)) if _TABLE_HEADER.match(lines[j])),
               len(lines))
    return start, end


def case_text_with_clearance(text: str, shaft: str, k: int, clearance_um: float,
                             key: str = "clearance_um") -> str:
    """A case file's TOML ``text`` with bearing ``k`` of ``[scene.<shaft>]`` given
    ``clearance_um`` as ``key`` (``clearance_um``, a tapered pair's ``end_play_um``: its line
    replaced, or added under the table's header); every other line, comments included, kept.

    Raises:
        ValueError: the bearing is not the k-th ``[[scene.<shaft>.bearings]]`` table of the
            text (an inline array of tables, a train's shaft), one line."""
    lines = text.splitlines()
    start, end = _bearing_lines(lines, shaft, k, "design")
    new = f"{key} = {float(clearance_um)!r}  # the design written by jaxgear optimise"
    for j in range(start + 1, end):
        if re.match(rf"^\s*{key}\s*=", lines[j]):
            lines[j] = new
            break
    else:
        lines.insert(start + 1, new)
    out = "\n".join(lines) + "\n"
    tomllib.loads(out)  # a parse error here is a bug of this writer, not the user's
    return out


def write_design_case(
    path, text: str, case: Case, problem: Problem, parameters: dict | None, *,
    unmodified: bool = False,
) -> Case:
    """Write the case file ``text`` (of ``case``) with the design ``parameters`` as its
    ``[modifications]`` (:func:`design_case_text`, with ``unmodified``; full precision) to
    ``path``, atomically:
    the new file is loaded (:func:`load_case`, relative paths from its own folder) before it
    replaces anything at ``path``. Returns the loaded case, whose modifications are the design.

    Raises:
        ValueError: the case's modifications cannot be rewritten, or the written case does not
            load (one line): nothing is left at ``path``."""
    return _write_case_text(path, design_case_text(text, case, problem, parameters,
                                                   unmodified=unmodified))


def _write_case_text(path, new: str) -> Case:
    """Write the case file text ``new`` to ``path`` atomically, loaded (:func:`load_case`)
    before it replaces anything; returns the loaded case (ValueError: it does not load)."""
    loaded = []

    def write(tmp):
        with open(tmp, "w", encoding="utf-8") as f:
            f.write(new)
        try:
            loaded.append(load_case(tmp))
        except (ValueError, FileNotFoundError) as err:
            raise ValueError(f"the design's case does not load: {err}") from None

    atomic_write(path, write)
    return loaded[0]


def _toml_value(value) -> str:
    """A scalar of a bearing's table as TOML writes it (a text, a boolean, a number)."""
    if isinstance(value, str):
        return json.dumps(value)  # a TOML basic string: a catalogue name
    if isinstance(value, bool):
        return "true" if value else "false"
    return repr(value)


def case_text_with_bearing(text: str, shaft: str, k: int, table: dict) -> str:
    """A case file's TOML ``text`` with bearing ``k`` of ``[scene.<shaft>]`` replaced by
    ``table`` (its keys, scalars, written under the table's header; the table's own comment
    lines kept, its keys removed); every other line kept.

    Raises:
        ValueError: the bearing is not the k-th ``[[scene.<shaft>.bearings]]`` table of the
            text, one line."""
    lines = text.splitlines()
    start, end = _bearing_lines(lines, shaft, k, "choice")
    kept = [line for line in lines[start + 1:end] if not line.strip()
            or line.lstrip().startswith("#")]
    new = [f"{key} = {_toml_value(v)}" for key, v in table.items()]
    out = "\n".join(lines[:start + 1] + new + kept + lines[end:]) + "\n"
    tomllib.loads(out)  # a parse error here is a bug of this writer, not the user's
    return out


def check_choice_text(text: str, bearing: str) -> None:
    """Whether :func:`write_choice_case` can rewrite ``bearing`` (``<shaft>.bearings[<k>]``) in
    the case file ``text``: checked before a choice's work. Raises ValueError (one line): a
    bearing the text does not give as a ``[[scene.<shaft>.bearings]]`` table."""
    hit = BEARING_NAME.match(bearing.strip())
    if hit is None:
        raise ValueError(f"bearing = {bearing!r}: allowed <shaft>.bearings[<k>]")
    _bearing_lines(text.splitlines(), hit.group(1), int(hit.group(2)), "choice")


def write_choice_case(path, text: str, case: Case, bearing: str, choice: BearingChoice) -> Case:
    """Write the case file ``text`` (of ``case``) with bearing ``bearing``
    (``<shaft>.bearings[<k>]``) the candidate ``choice`` of :func:`bearing_choices` (its table,
    its clearance key at ``choice.clearance_um``: :func:`case_text_with_bearing`) to ``path``,
    atomically, the new file loaded before it replaces anything. Returns the loaded case.

    Raises:
        ValueError: a candidate that does not fit, a bearing the text does not give as a
            table, a written case that does not load (one line): nothing left at ``path``."""
    if not choice.fits:
        raise ValueError(f"candidate {choice.name!r} does not fit the shaft: allowed a ranked "
                         "candidate")
    shaft, k = _check_choice(case, bearing, {choice.name: {}}, "te_rms")
    table = _bearing_table(choice.case, shaft, k)
    rolling = getattr(choice.case.scene, shaft).bearings[k].rolling
    table[clearance_key(rolling)] = float(choice.clearance_um)
    return _write_case_text(path, case_text_with_bearing(text, shaft, k, table))
