"""``jaxgear run`` on a gearbox (a case of :class:`jaxgear.io.GearboxForm`): each stage's own
run (its case at the operating point carried from the previous stage: a planetary stage's load
sharing, meshes, modes and sweep, a pair's TE and load maps, and each stage's ``[rating]``: every
mesh of every rated stage, at the carried point) into ``stage<k>/``, then the whole
chain's torsional natural frequencies (:meth:`jaxgear.gearbox.GearboxModel.natural_modes`) with the stage that
holds most of each mode's kinetic energy, into ``summary.json`` and ``modes.json``; then the coupled
model (:mod:`jaxgear.gearbox`: every stage on its contact cells in one Newmark run) swept over
the operating range: every mesh's dynamic factor against the input speed and the coupled modes
with their type and the mesh holding most strain energy (``summary.json``'s ``coupled``,
``coupled.json``, ``coupled.png``); the coupled Campbell diagram (every stage's mesh orders
against the coupled modes, and its lumped stages' rolling bearings' tones, ``campbell.json``,
``campbell.png``) and the force spectrum at two
housing-fixed points, stage 1's ring mount and the parallel stage's bearing, from one coupled
run at the rated input speed (``housing_spectrum.json``, ``housing_spectrum.png``; the
summary's ``campbell`` and ``housing_spectrum``); with ``[whine]``, the whole coupled gearbox's
gear whine (:func:`jaxgear.gearbox.gearbox_whine` on the coupled chain) into ``whine/``
through the pair's writers (:func:`jaxgear.cli._whine_run.whine_outputs`). With a
gearbox-level ``[housing]`` (its lumped 3D stages in one box) ``modes.json`` holds the coupled
modes with the housing's share of each mode's kinetic energy instead of the torsional chain's
(which refuses a shared housing), and the whine writes the housing's ERP and named points
(:mod:`jaxgear.cli._housing_run`)."""

from __future__ import annotations

import os
import time

import numpy as np

from ..acoustics import housing_acoustics
from ..dynamics import (
    DIRECTIONS,
    MAX_STEPS_PER_SPEED,
    MIN_STEPS_PER_PERIOD,
    DynamicModel,
    SteadyState,
    speed_sweep,
)
from ..gearbox import (
    OPERATING_RUN,
    GearboxRun,
    PairGearboxStage,
    campbell_crossings,
    coordinate_names,
    coupled_mode_table,
    gearbox_coupled_modes,
    gearbox_whine,
    housing_lines,
    housing_spectrum,
    line_amplitudes,
    mesh_frequencies,
    mesh_names,
    window_share,
)
from ..io import (
    HousedAcoustics,
    SceneSpec,
    build_dynamic_model,
    housing_surface,
    spec_integrator,
    write_json,
)
from ..planetary import PlanetaryModel
from ._bearing_report import bearing_run_lines, bearing_tone_orders, gearbox_bearing_outputs
from ._plots import (
    coupled_dynamic_factor_plot,
    gearbox_campbell_plot,
    housing_spectrum_plot,
)
from ._sweep_json import write_sweep_csv
from ._sweep_kinds import check_case_options
from ._tribology_run import efficiency_run_line, gearbox_tribology
from ._whine_run import SolvedWhine, whine_outputs, whine_run_line

__all__ = [
    "chain_modes",
    "check_gearbox_sweep",
    "coupled_campbell",
    "coupled_response",
    "coupled_sweep",
    "gearbox_run_files",
    "gearbox_run_lines",
    "gearbox_sweep_files",
    "gearbox_sweep_lines",
    "gearbox_whine_outputs",
    "housing_point_spectrum",
    "least_safety",
    "rating_dynamic_factors",
    "whine_mesh_names",
]

#: the coupled sweep's input speeds, as fractions of the operating point's input speed
COUPLED_SPEEDS = np.linspace(0.2, 1.2, 6)
#: the coupled run's time plan: the model's automatic one (the engine's step from the highest
#: excited mode, its span from settling) with the constants of a gearbox case's operating
#: point (:data:`jaxgear.gearbox.OPERATING_RUN`, :meth:`jaxgear.io.GearboxForm.dynamic_model`;
#: measured on nrel-5mw-gearbox: docs/gearbox.md, "Resolution and cost")
COUPLED_RUN = {"steps_per_period": None, "periods": None, **OPERATING_RUN}


def chain_modes(form) -> list[dict]:
    """The gearbox's modes as ``jaxgear modes`` lists them (:func:`jaxgear.cli.modes.typed_modes`
    of its dynamic model's :meth:`~jaxgear.gearbox.GearboxModel.natural_modes`): the torsional
    chain's, each with ``frequency_Hz``, ``type`` ("rigid body", or ``stage<k>``: the stage with
    the largest share of the mode's kinetic energy) and ``stage_energy`` (the shares); with the
    gearbox's ``[housing]`` the coupled modes, each a :func:`~jaxgear.gearbox.coupled_mode_table`
    row with ``stage_energy`` and ``housing_energy`` (the housing coordinates' share; with the
    stages' it sums to 1)."""
    from .modes import typed_modes  # cli.modes lists every form's modes

    model = form.dynamic_model()
    data = typed_modes(model, model.natural_modes())
    return next(v for v in data.values() if isinstance(v, list))


def gearbox_run_files(form, case, out: str, args, complete: bool, run_stage) -> dict:
    """The stages' runs (``run_stage(stage_case, folder, args, None)``: ``jaxgear run``'s work
    on one case) into ``out/stage<k>``, then the chain's modes; the lumped 3D stages' rolling
    bearings at the carried point (the summary's ``bearings``,
    :func:`~jaxgear.cli._bearing_report.gearbox_bearing_outputs`); returns the summary."""
    stages = []
    for k, s in enumerate(form.stages):
        label = form.stage_name(k)
        summary = run_stage(s.case, os.path.join(out, label), args, None)
        stages.append(
            {
                "stage": label,
                "case": s.case.name,
                "speed_ratio": s.ratio,
                "input_speed_rad_s": s.input_speed,
                "input_torque_Nm": s.input_torque,
                "output_speed_rad_s": s.output_speed,
                "output_torque_Nm": s.output_torque,
                "shaft_Nm_per_rad": s.shaft_stiffness,
                "folder": label,
                "summary": summary,
            }
        )
    tribology = gearbox_tribology(stages, out)  # every stage with [lubricant]: in series
    modes = chain_modes(form)
    key = "torsional_chain" if form.housing is None else "coupled_with_housing"
    write_json(os.path.join(out, "modes.json"), {"case": case.name, key: modes})
    coupled = coupled_sweep(form, out)
    coupled["rating_dynamic_factors"] = rating_dynamic_factors(stages, coupled,
                                                               form.stages[0].input_speed)
    write_json(os.path.join(out, "coupled.json"), coupled)  # with the stages' K_v beside
    campbell = coupled_campbell(form, case, out)
    spectrum = housing_point_spectrum(form, case, out)
    result = {
        "case": case.name,
        "complete": complete,
        "gearbox": {
            "speed_ratio": form.ratio(),
            "step_up": 1.0 / form.ratio(),
            "stage_speed_ratios": [s.ratio for s in form.stages],
        },
        "stages": stages,
        "torsional_modes": modes,
        "coupled": coupled,
        "campbell": campbell,
        "housing_spectrum": spectrum,
    }
    if tribology is not None:
        result["tribology"] = tribology
    bearings = gearbox_bearing_outputs(form, case, stages)  # its lumped stages' rolling bearings
    if bearings is not None:
        result["bearings"] = bearings
    write_json(os.path.join(out, "summary.json"), result)
    return result


def _coupled_setup(form):
    """(the coupled chain, its GearboxRun (:data:`COUPLED_RUN`), the first stage, the output
    hold: the last shaft's stiffness)."""
    chain = form.coupled()
    first = form.stages[0]
    hold = form.output_hold()
    return chain, GearboxRun(first.input_torque, hold, **COUPLED_RUN), first, hold


def coupled_sweep(form, out: str) -> dict:
    """The coupled model over the operating range (:data:`COUPLED_SPEEDS` of the first stage's
    input speed, the gearbox's torque): every mesh's dynamic factor (max / static from the
    torque ratios) at each speed, and the coupled modes; the last stage's output held by the
    last shaft's stiffness (the generator is not in the chain). The sweep is
    :func:`jaxgear.dynamics.speed_sweep` of the case's dynamic model
    (:meth:`jaxgear.io.GearboxForm.dynamic_model`, :func:`jaxgear.io.build_dynamic_model`'s) on
    its automatic plan (the step from the highest excited mode, the span from settling), the
    steps integrated and the spread of the recorded window's two halves reported beside the
    factors (:func:`coupled_response`). Written to ``coupled.json`` and ``coupled.png``;
    returns the summary's ``coupled`` section."""
    model = form.dynamic_model()
    first = form.stages[0]
    speeds = first.input_speed * COUPLED_SPEEDS
    res = speed_sweep(model, speeds).results
    result = {
        "input_speeds_rad_s": [float(w) for w in speeds],
        "input_torque_Nm": float(first.input_torque),
        "output_hold_Nm_per_rad": float(form.output_hold()),
        "time_plan": dict(COUPLED_RUN),
        **coupled_response(model, res),
    }
    write_json(os.path.join(out, "coupled.json"), result)
    coupled_dynamic_factor_plot(os.path.join(out, "coupled.png"), speeds,
                                np.asarray(res.dynamic_factors), result["mesh_names"])
    return result


def coupled_response(model, res) -> dict:
    """The keys of a coupled sweep's response ``res`` (:class:`~jaxgear.gearbox.GearboxDynamics`
    with a leading speed axis (S,)) of ``model`` (a :class:`~jaxgear.gearbox.GearboxModel`):
    ``steps_integrated``, ``steps_recorded``, ``mesh_names``, ``static_force_N`` (m),
    ``dynamic_factor_mesh`` (S, m), ``mesh_speeds_m_s`` (S, stages), ``result``,
    ``max_dynamic_factor``, ``worst_mesh``, ``modes`` (the coupled modes, typed:
    :func:`~jaxgear.gearbox.coupled_mode_table`), ``highest_excited_mode_Hz`` (mesh share >=
    5 %), ``steps_per_mode_period`` per speed and ``window_halves_spread`` per speed (the
    largest relative difference of a mesh's peak force between the recorded window's two
    halves: the window's own uncertainty on a quasi-periodic response)."""
    chain = model.chain
    names = list(mesh_names(chain))
    df = np.asarray(res.dynamic_factors)
    result = {
        "steps_integrated": int(np.asarray(res.steps)[0]),
        "steps_recorded": int(np.asarray(res.time).shape[1]),
        "mesh_names": names,
        "static_force_N": [float(f) for f in np.asarray(res.static_forces)[0]],
        "dynamic_factor_mesh": df.tolist(),
        "mesh_speeds_m_s": np.asarray(res.mesh_speeds).tolist(),
        "result": [int(r) for r in np.asarray(res.result)],
        "max_dynamic_factor": float(np.max(df)),
        "worst_mesh": names[int(np.argmax(np.max(df, axis=0)))],
        "modes": coupled_mode_table(chain, gearbox_coupled_modes(chain, model.run)),
    }
    # the resolution of the highest mode the meshes excite (its mesh share >= 5 %): the
    # automatic plan takes the run's steps_per_mode per its period at the lowest speed
    excited = [m["frequency_Hz"] for m in result["modes"]
               if m["type"] != "rigid body" and m["mesh_total"] >= 0.05]
    dt = np.asarray(res.time)[:, 1] - np.asarray(res.time)[:, 0]
    f_exc = max(excited, default=0.0)
    result["highest_excited_mode_Hz"] = f_exc
    result["steps_per_mode_period"] = [float(1.0 / (d * f_exc)) if f_exc else None for d in dt]
    # the window's own uncertainty: a quasi-periodic response (the stages' mesh periods are
    # incommensurate), whose maximum over the recorded window's two halves differs
    f = np.asarray(res.mesh_forces)
    half = f.shape[1] // 2
    peak = [np.max(f[:, :half], axis=1), np.max(f[:, half:], axis=1)]
    result["window_halves_spread"] = np.max(np.abs(peak[0] - peak[1])
                                            / np.maximum(peak[0], peak[1]), axis=1).tolist()
    return result


# -- jaxgear sweep on a gearbox -----------------------------------------------------------------

#: the files of ``jaxgear sweep`` on a gearbox
GEARBOX_SWEEP_FILES = ("sweep.json", "sweep.csv", "dynamic_factor.png")


def _integrator(solver: str | None, steps_per_period: int | None):
    """The integrator of a solver name and ``--steps-per-period`` (a case file's
    ``[scene.integration]`` words, :func:`jaxgear.io.spec_integrator`; None: Newmark)."""
    return spec_integrator(SceneSpec(solver=solver or "newmark",
                                     steps_per_period=steps_per_period))


def _settings(model, case, *, solver=None, contact=None, periods=None, steps_per_period=None,
              keep_periods=None):
    """(integrator, contact law, window) of a gearbox sweep from ``jaxgear sweep``'s options:
    None where none was given (the model's own, :meth:`~jaxgear.gearbox.GearboxModel.
    default_settings`: Newmark with the automatic step, the exact law, the automatic span
    from settling keeping the run's blocks); ``periods`` ``"auto"`` the automatic span."""
    integrator = (None if solver is None and steps_per_period is None
                  else _integrator(solver, steps_per_period))
    law = None if contact is None else case.contact_law(contact)
    fixed = None if periods in (None, "auto") else int(periods)
    window = None
    if fixed is not None or keep_periods is not None:
        keep = int(keep_periods or model.default_settings()[2].keep_periods)
        window = SteadyState(fixed, keep if fixed is None else min(keep, fixed))
    return integrator, law, window


def check_gearbox_sweep(form, case, *, direction="independent", solver=None, contact=None,
                        periods=None, steps_per_period=None, keep_periods=None, vtu_speed=None,
                        slices=None) -> None:
    """``jaxgear sweep``'s options on a gearbox checked before any file is touched: the step
    count within the coupled run's range (>= 8 per period of the fastest excited mesh), what
    the coupled model's kind (:func:`jaxgear.io.dynamic_model_kind`,
    :class:`~jaxgear.gearbox.GearboxModel`) cannot run, asked of its contract before any model
    is built (:func:`~jaxgear.cli._sweep_kinds.check_case_options`: ``--direction``,
    ``--solver``, ``--contact``, ``--vtu-speed``), and given periods (blocks: the slowest
    excited mesh's period, of the built model) within the engine's bound of steps per speed.
    One-line ``ValueError``."""
    if steps_per_period is not None and steps_per_period < 8:
        raise ValueError(f"--steps-per-period = {steps_per_period}: out of range, allowed >= 8 "
                         "(steps per period of the gearbox's fastest excited mesh)")
    check_case_options(case, direction=direction, solver=solver, contact=contact,
                       vtu_speed=vtu_speed)
    if periods not in (None, "auto"):  # the blocks' steps within the engine's bound
        model, _ = build_dynamic_model(case, slices=slices)
        steps = steps_per_period or MIN_STEPS_PER_PERIOD
        block = max(1, round(steps / min(model.mesh_rates())))
        if int(periods) * block > MAX_STEPS_PER_SPEED:
            at = (f"{steps} time steps per period of the fastest excited mesh "
                  + ("(--steps-per-period)" if steps_per_period else "(at least, automatic)"))
            raise ValueError(
                f"--periods = {periods}: out of range, allowed <= "
                f"{MAX_STEPS_PER_SPEED // block} blocks of {block} steps at {at}: "
                f"{int(periods) * block:.3g} time steps per speed, allowed <= "
                f"{MAX_STEPS_PER_SPEED:.3g} (fewer periods or steps per period)")
    if contact is not None:
        case.contact_law(contact)


def gearbox_sweep_files(form, case, speeds, out_dir: str, *, direction="independent",
                        solver=None, contact=None, periods=None, steps_per_period=None,
                        keep_periods=None, vtu_speed=None, slices=None,
                        show_progress=True) -> dict:
    """``jaxgear sweep`` on a gearbox (options checked by :func:`check_gearbox_sweep`): the
    coupled model (:func:`jaxgear.io.build_dynamic_model`) swept over the first stage's input
    ``speeds`` (rad/s, (S,)) by :func:`jaxgear.dynamics.speed_sweep` with the options given
    (:func:`_settings`; none given: the model's automatic step and its span from settling);
    written into ``out_dir`` (:data:`GEARBOX_SWEEP_FILES`): ``sweep.json`` (the case, the
    settings, ``settle_s`` (the automatic span's settling time, None for given periods),
    ``speed_of``, ``speeds_rad_s``, the worst mesh's ``dynamic_factor`` per speed,
    ``max_dynamic_factor_mesh`` and ``speed_of_max_rad_s``, and :func:`coupled_response`'s
    keys: each mesh's dynamic factor per speed, named by :func:`jaxgear.gearbox.mesh_names`),
    ``sweep.csv`` (a row per speed) and ``dynamic_factor.png`` (one curve per mesh). Returns
    ``sweep.json``'s content."""
    t0 = time.perf_counter()
    model, _ = build_dynamic_model(case, slices=slices)
    integrator, law, window = _settings(model, case, solver=solver, contact=contact,
                                        periods=periods, steps_per_period=steps_per_period,
                                        keep_periods=keep_periods)
    speeds = np.asarray(speeds, dtype=float)
    res = speed_sweep(model, speeds, integrator=integrator, contact=law, window=window,
                      direction=DIRECTIONS[direction]).results
    response = coupled_response(model, res)
    df = np.asarray(response["dynamic_factor_mesh"])
    worst = df.max(axis=1)
    i = int(np.argmax(worst))
    summary = {
        "case": case.name,
        "kind": "gearbox",
        "model": "coupled gearbox (every stage's contact cells in one Newmark run)",
        "solver": solver or "newmark",
        "contact": contact or "exact",
        "direction": direction,
        "steps_per_period": steps_per_period or "auto",
        "periods": "auto" if periods in (None, "auto") else int(periods),
        "keep_periods": int((window or model.default_settings()[2]).keep_periods),
        # the automatic span: the settling time of the slowest decaying mode the meshes
        # excite (GearboxModel.settle_time), then the kept blocks
        "settle_s": (float(model.settle_time()) if window is None or window.periods is None
                     else None),
        "speed_of": "input (stage 1's input member)",
        "torque_Nm": float(model.run.input_torque),
        "output_hold_Nm_per_rad": float(model.run.output_stiffness),
        "speeds_rad_s": speeds.tolist(),
        "dynamic_factor": worst.tolist(),
        "speed_of_max_rad_s": float(speeds[i]),
        "max_dynamic_factor_mesh": df.max(axis=0).tolist(),
        **response,
    }
    summary["elapsed_s"] = time.perf_counter() - t0
    write_json(os.path.join(out_dir, "sweep.json"), summary)
    write_sweep_csv(os.path.join(out_dir, "sweep.csv"), summary)
    coupled_dynamic_factor_plot(os.path.join(out_dir, "dynamic_factor.png"), speeds, df,
                                summary["mesh_names"])
    return summary


def gearbox_sweep_lines(form, case, s: dict) -> list[str]:
    """What ``jaxgear sweep`` prints for a gearbox (``s``: its ``sweep.json``)."""
    elastic = [m for m in s["modes"] if m["type"] != "rigid body"]
    per_mode = [v for v in s["steps_per_mode_period"] if v is not None]
    resolution = (f", {min(per_mode):.3g} steps per period of the "
                  f"{s['highest_excited_mode_Hz']:.4g} Hz mode the meshes excite"
                  if per_mode else "")
    return [
        f"{case.name}: {len(s['speeds_rad_s'])} input speeds, {len(s['mesh_names'])} meshes, "
        f"max dynamic factor {s['max_dynamic_factor']:.4f} ({s['worst_mesh']}) at "
        f"{s['speed_of_max_rad_s']:.4g} rad/s; {s['steps_integrated']} steps a speed"
        f"{resolution}; first coupled modes "
        + ", ".join(f"{m['frequency_Hz']:.4g}" for m in elastic[:6]) + " Hz; "
        f"{sum(1 for v in s['result'] if v)} diverged; {s['elapsed_s']:.1f} s"
    ]


def _mesh_kinds(names: list[str], k: int) -> dict[str, list[int]]:
    """Stage ``k``'s (from 1) meshes in the coupled model's ``names`` (``"<k>:<mesh>"``) by
    kind (a planetary stage's ``sun-planet``, ``ring-planet``, each over its planets; a pair's
    ``pair``), in the order the model names them: ``{kind: [columns]}``."""
    kinds: dict[str, list[int]] = {}
    for j, name in enumerate(names):
        stage, _, mesh = name.partition(":")
        if stage == str(k):
            kinds.setdefault(mesh.rsplit(" ", 1)[0] if mesh[-1].isdigit() else mesh,
                             []).append(j)
    return kinds


def rating_dynamic_factors(stages: list[dict], coupled: dict, rated_speed: float) -> list[dict]:
    """The coupled model's dynamic factor at the rated input speed beside the K_v each rated
    stage's rating uses, one row per rated mesh (a planetary stage's two: its sun-planet and
    planet-ring ratings against the coupled model's sun-planet and ring-planet meshes, the
    largest over the planets; a pair's one): ``stage``, ``mesh`` (the rating's name),
    ``K_v_rated`` and ``K_v_source`` (what the rating used: ISO 6336-1 method B, given, or the
    measured one that ``[rating] use_measured`` names), ``coupled_dynamic_factor`` (largest mesh
    force over its static one in the coupled run at ``rated_speed``, rad/s, the first stage's
    input; interpolated linearly in the sweep's speeds when none is the rated one, and said so),
    ``coupled_meshes`` and ``rated_with`` ("K_v": the coupled factor is reported, not rated
    with). ``stages``: the gearbox summary's ``stages`` (each with its run's ``summary``);
    ``coupled``: :func:`coupled_sweep`'s section."""
    speeds = np.asarray(coupled["input_speeds_rad_s"], dtype=float)
    df = np.asarray(coupled["dynamic_factor_mesh"], dtype=float)
    at = np.flatnonzero(np.isclose(speeds, rated_speed, rtol=1e-9))
    if at.size:
        rated, how = df[at[0]], "at the rated input speed"
    else:
        rated = np.array([np.interp(rated_speed, speeds, df[:, j]) for j in range(df.shape[1])])
        how = "interpolated linearly to the rated input speed between the sweep's speeds"
    rows = []
    for k, stage in enumerate(stages, start=1):
        rating = (stage.get("summary") or {}).get("rating")
        if rating is None:
            continue
        kv = rating["factors"]["K_v"]
        names = rating.get("meshes")
        values, sources = kv["value"], kv["source"]
        if names is None:  # one rated mesh
            names, values, sources = [stage["case"]], [values], [sources]
        kinds = _mesh_kinds(coupled["mesh_names"], k)
        if len(kinds) != len(names):  # no one-to-one match: the stage's meshes, all of them
            kinds = {"all": [j for cols in kinds.values() for j in cols]}
            pairs = [(n, v, s, "all") for n, v, s in zip(names, values, sources, strict=True)]
        else:
            pairs = list(zip(names, values, sources, kinds, strict=True))
        for name, value, source, kind in pairs:
            cols = kinds[kind]
            rows.append({
                "stage": stage["stage"],
                "mesh": name,
                "K_v_rated": float(value),
                "K_v_source": source,
                "coupled_dynamic_factor": float(np.max(rated[cols])),
                "coupled_meshes": [coupled["mesh_names"][j] for j in cols],
                "coupled_at": how,
                "rated_with": "K_v",
            })
    return rows


#: the Campbell diagram's mesh harmonics
CAMPBELL_HARMONICS = (1, 2, 3)
#: the housing spectrum's run: carrier revolutions recorded and steps per period of the fastest
#: mesh (docs/gearbox.md, "Campbell diagram and housing spectrum": its orders' convergence)
SPECTRUM_RUN = {"revolutions": 2, "steps_per_period": 16}
#: the ring-mount window's power p: ((1 + cos phi) / 2)^p (jaxgear.planetary.ring_transducer_signal)
WINDOW_POWER = 4
#: the stored spectra: at most this many points (peak-hold over groups of bins); around stage
#: 1's mesh frequency (± 5 planet-pass frequencies) every bin
SPECTRUM_POINTS = 3000


def coupled_campbell(form, case, out: str) -> dict:
    """The coupled Campbell diagram over 0 to the largest of :data:`COUPLED_SPEEDS` × the rated
    input speed: each stage's mesh harmonics :data:`CAMPBELL_HARMONICS` against the coupled
    modes (at rest), every crossing with the mode's type, its mesh and the exciting stage's
    share of its strain energy (:func:`jaxgear.gearbox.campbell_crossings`). Written to
    ``campbell.json`` and ``campbell.png``; returns the summary's ``campbell`` section."""
    chain, run, first, _ = _coupled_setup(form)
    modes = gearbox_coupled_modes(chain, run)
    top = float(first.input_speed * COUPLED_SPEEDS[-1])
    crossings = campbell_crossings(chain, modes, top, CAMPBELL_HARMONICS)
    data = {
        "case": case.name,
        "operating_speed_rad_s": float(first.input_speed),
        "max_speed_rad_s": top,
        "harmonics": list(CAMPBELL_HARMONICS),
        "mesh_Hz_per_rad_s": [float(v) for v in np.asarray(mesh_frequencies(chain, 1.0))],
        "modes": coupled_mode_table(chain, modes),
        "crossings": crossings,
        "bearing_tones": bearing_tone_orders(case),  # orders of the input speed
    }
    write_json(os.path.join(out, "campbell.json"), data)
    gearbox_campbell_plot(os.path.join(out, "campbell.png"), data)
    marked = [c for c in crossings if c["marked"]]
    near = min(marked, key=lambda c: abs(c["speed_rad_s"] - first.input_speed), default=None)
    return {"crossings": len(crossings), "marked": len(marked), "nearest_to_rated": near}


def _peak_hold(f, a, points):
    g = max(1, -(-f.size // points))
    n = f.size // g * g
    return f[:n].reshape(-1, g)[:, 0], a[:n].reshape(-1, g).max(axis=1)


def housing_point_spectrum(form, case, out: str) -> dict:
    """The force spectrum at stage 1's ring mount and the parallel stage's bearing from one
    coupled run at the rated input speed (:func:`jaxgear.gearbox.housing_spectrum`,
    :data:`SPECTRUM_RUN`, the planet-pass window's power :data:`WINDOW_POWER`), with every
    stage's mesh harmonics, the planet-pass sidebands and the McFadden-Smith lines read at
    their frequencies (:func:`jaxgear.gearbox.housing_lines`). Written to
    ``housing_spectrum.json`` and ``housing_spectrum.png``; returns the summary's
    ``housing_spectrum`` section (None for a gearbox without a planetary and a parallel
    stage). The parallel stage's bearing: a torsional pair's mesh force, a lumped 3D pair's
    output-shaft bearings (:func:`jaxgear.gearbox.housing_signals`); a ring on the gearbox's
    ``[housing]`` is read on its seat (k_t (θ_r − θ_seat))."""
    chain, run, first, _ = _coupled_setup(form)
    planetary = [i for i, s in enumerate(chain.stages) if isinstance(s, PlanetaryModel)]
    pairs = [i for i, s in enumerate(chain.stages)
             if isinstance(s, (PairGearboxStage, DynamicModel))]
    if not planetary or not pairs:
        return None
    w = float(first.input_speed)
    hs = housing_spectrum(chain, run, w, window_power=WINDOW_POWER, **SPECTRUM_RUN)
    sig = hs.signals
    lines = housing_lines(chain, w)
    f = [r["frequency_Hz"] for r in lines]
    ring = line_amplitudes(sig.time, sig.ring_point, f)
    bearing = line_amplitudes(sig.time, sig.bearing, f)
    rows = [dict(r, ring=float(a), bearing=float(b)) for r, a, b in zip(lines, ring, bearing,
                                                                       strict=True)]
    k, b = planetary[0], pairs[-1]
    n = chain.stages[k].stage.n_planets
    fc, f1 = abs(float(hs.carrier_frequency[k])), float(hs.mesh_frequency[k])
    top = 3.3 * float(np.max(hs.mesh_frequency))
    keep = hs.frequency <= top
    fr, ar = _peak_hold(hs.frequency[keep], hs.ring_point[keep], SPECTRUM_POINTS)
    _, ab = _peak_hold(hs.frequency[keep], hs.bearing[keep], SPECTRUM_POINTS)
    near = np.abs(hs.frequency - f1) <= 5 * n * fc
    data = {
        "case": case.name,
        "input_speed_rad_s": w,
        "ring_stage": k + 1,
        "bearing_stage": b + 1,
        "planets": n,
        "window_power": WINDOW_POWER,
        "support_share": window_share(WINDOW_POWER),
        "time_plan": dict(SPECTRUM_RUN, time_step_s=hs.time_step, settle_s=hs.settle_time,
                          record_s=float(sig.time[-1] - sig.time[0] + hs.time_step)),
        "result": int(hs.dynamics.result),
        "mesh_frequency_Hz": [float(v) for v in hs.mesh_frequency],
        "carrier_frequency_Hz": [float(v) for v in hs.carrier_frequency],
        "lines": rows,
        "spectrum": {"frequency_Hz": fr.tolist(), "ring_point_N": ar.tolist(),
                     "bearing_N": ab.tolist(), "peak_hold_bins": round(
                         (fr[1] - fr[0]) / (hs.frequency[1] - hs.frequency[0]))},
        "spectrum_fine": {"frequency_Hz": hs.frequency[near].tolist(),
                          "ring_point_N": hs.ring_point[near].tolist()},
    }
    write_json(os.path.join(out, "housing_spectrum.json"), data)
    housing_spectrum_plot(os.path.join(out, "housing_spectrum.png"), data)
    ms = [r for r in rows if r["kind"] == "McFadden-Smith" and r["stage"] == k + 1
          and r["harmonic"] == 1]
    own = [r for r in rows if r["kind"] == "mesh" and r["stage"] == b + 1]
    return {
        "input_speed_rad_s": w,
        "ring_stage": k + 1,
        "bearing_stage": b + 1,
        "carrier_Hz": fc,
        "planet_pass_Hz": n * fc,
        "ring_mesh_Hz": f1,
        "ring_mesh_line_N": float(line_amplitudes(sig.time, sig.ring_point, [f1])[0]),
        "mcfadden_smith_lines": [{"frequency_Hz": r["frequency_Hz"], "offset_fc": r["sideband"],
                                  "ring_N": r["ring"]} for r in ms],
        "bearing_orders": [{"label": r["label"], "frequency_Hz": float(r["frequency_Hz"]),
                            "bearing_N": r["bearing"]} for r in own],
        "time_step_s": hs.time_step,
    }


def whine_mesh_names(chain) -> list[str]:
    """Each coupled mesh's name in the whine's files: ``stage<k>_<the stage's mesh name>``."""
    return [f"stage{k + 1}_{n}" for k, s in enumerate(chain.stages) for n in s.mesh_names()]


def gearbox_whine_outputs(form, case, out: str) -> dict | None:
    """The whole coupled gearbox's whine over its ``[whine]`` speeds (the first stage's input
    member's, rad/s): :func:`jaxgear.gearbox.gearbox_whine` on the coupled chain and run of the
    coupled sweep (:func:`_coupled_setup`: the gearbox's torque, the last shaft's stiffness as
    the output hold, :data:`COUPLED_RUN`'s modal damping and mean positions), the table's
    :class:`~jaxgear.dynamics.QuasiPeriodicBalance` and positions per stage; written into
    ``out/whine`` by the pair's writers (whine.json, whine.csv, the order plots and waterfalls,
    each mesh's orders of its own mesh frequency). Returns the summary's ``whine`` section,
    None without ``[whine]``."""
    inputs = form.whine
    if inputs is None:
        return None
    chain, run, _, _ = _coupled_setup(form)
    housed = None
    if chain.housing is not None:  # [housing]: its named points checked before the whine
        body, spec = form.housing_body, form.housing
        surface = housing_surface(spec, body)
        acoustics = housing_acoustics(body.condensed, surface, loss_factor=spec.loss_factor)
        n = len(coordinate_names(chain))
        housed = HousedAcoustics(body, surface, acoustics, n - int(chain.housing.size))
    w = gearbox_whine(chain, run, np.asarray(inputs.speeds), inputs.method,
                      positions=inputs.positions)
    return whine_outputs(case, out, SolvedWhine(inputs, w, tuple(whine_mesh_names(chain)),
                                                housed))


def least_safety(stage_summary: dict) -> str:
    """The words a gearbox's stage line ends with when the stage is rated (its ``[rating]``,
    at the carried operating point): the least S_H and S_F over its meshes and gears, and where
    the stage's ``rating.md`` is; "" for a stage without a rating."""
    rating = stage_summary.get("rating")
    if rating is None:
        return ""
    h, f = (float(np.min(rating[p][k])) for p, k in (("pitting", "S_H"), ("bending", "S_F")))
    return f"; rated: least S_H {h:.3g}, S_F {f:.3g} (rating.md)"


def gearbox_run_lines(form, case, summary: dict) -> list[str]:
    """What ``jaxgear run`` prints for a gearbox (after each stage's own lines)."""
    g = summary["gearbox"]
    lines = [
        f"gearbox {case.name}: {len(form.stages)} stages, speed ratio ω_in/ω_out "
        f"{g['speed_ratio']:.6g} (the output turns {g['step_up']:.6g} × the input); stages "
        + ", ".join(f"1:{1 / r:.4f}" for r in g["stage_speed_ratios"])
    ]
    for s in summary["stages"]:
        lines.append(
            f"{s['stage']} ({s['case']}): in {s['input_speed_rad_s']:.6g} rad/s, "
            f"{s['input_torque_Nm']:.6g} N·m; out {s['output_speed_rad_s']:.6g} rad/s, "
            f"{s['output_torque_Nm']:.6g} N·m ({s['folder']}/)" + least_safety(s["summary"])
        )
    elastic = [m for m in summary["torsional_modes"] if m["type"] != "rigid body"]
    housed = bool(elastic) and "housing_energy" in elastic[0]
    lines.append(
        ("coupled modes with the housing: " if housed else "torsional chain: ")
        + ", ".join(f"{m['frequency_Hz']:.4g} Hz ({m['type']}"
                    + (f", housing {m['housing_energy']:.0%}" if housed else "") + ")"
                    for m in elastic[:6])
        + (" ..." if len(elastic) > 6 else "")
        + " (modes.json)"
    )
    c = summary.get("coupled")
    if c is not None:
        lines.append(
            f"coupled model (every mesh in one run, {len(c['input_speeds_rad_s'])} input speeds "
            f"{c['input_speeds_rad_s'][0]:.4g}-{c['input_speeds_rad_s'][-1]:.4g} rad/s): "
            f"largest dynamic factor {c['max_dynamic_factor']:.4g} ({c['worst_mesh']}"
            + (f"; {min(c['steps_per_mode_period']):.3g} steps per period of the "
               f"{c['highest_excited_mode_Hz']:.4g} Hz mode the meshes excite, "
               f"{c['steps_integrated']} steps a speed"
               if c.get("steps_per_mode_period") and None not in c["steps_per_mode_period"]
               else "") + "); "
            "modes " + ", ".join(f"{m['frequency_Hz']:.4g} Hz ({m['type']}, {m['mesh']})"
                                 for m in c["modes"][:4] if m["type"] != "rigid body")
            + " (coupled.json, coupled.png)"
        )
    for r in (c or {}).get("rating_dynamic_factors", []):
        lines.append(
            f"{r['stage']} {r['mesh']}: rated with K_v {r['K_v_rated']:.4g} ({r['K_v_source']}); "
            f"the coupled gearbox's dynamic factor {r['coupled_dynamic_factor']:.4g} "
            f"({r['coupled_at']}) is not rated with "
            "(coupled.json rating_dynamic_factors)")
    cb = summary.get("campbell")
    if cb is not None:
        near = cb["nearest_to_rated"]
        lines.append(
            f"coupled Campbell diagram: {cb['crossings']} crossings of the mesh orders with the "
            f"coupled modes, {cb['marked']} with >= 5 % of the mode's strain energy in the "
            "exciting stage's meshes"
            + (f"; nearest the rated speed: stage {near['stage']}'s {near['harmonic']}× mesh at "
               f"{near['speed_rad_s']:.4g} rad/s, {near['frequency_Hz']:.4g} Hz "
               f"({near['type']}, {near['mesh']})" if near else "") + " (campbell.png)")
    hs = summary.get("housing_spectrum")
    if hs is not None:
        ms = ", ".join(f"{r['frequency_Hz']:.4g} Hz ({r['offset_fc']:+d} f_c) {r['ring_N']:.3g} N"
                       for r in hs["mcfadden_smith_lines"])
        own = ", ".join(f"{r['label']} {r['frequency_Hz']:.4g} Hz {r['bearing_N']:.3g} N"
                        for r in hs["bearing_orders"])
        lines.append(
            f"housing spectrum at {hs['input_speed_rad_s']:.4g} rad/s: stage "
            f"{hs['ring_stage']}'s ring mount, "
            f"planet pass {hs['planet_pass_Hz']:.4g} Hz, lines {ms} beside the mesh frequency "
            f"{hs['ring_mesh_Hz']:.4g} Hz ({hs['ring_mesh_line_N']:.3g} N); stage "
            f"{hs['bearing_stage']}'s bearing at its mesh harmonics {own} (housing_spectrum.png)")
    return (lines + efficiency_run_line(summary.get("tribology"))
            + bearing_run_lines(summary.get("bearings"))
            + whine_run_line(summary.get("whine")))
