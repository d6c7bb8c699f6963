"""``jaxgear sweep`` on a planetary stage (a case of :class:`jaxgear.io.PlanetaryForm`), and the
sweep section of ``jaxgear run`` on one: the case's dynamic model
(:func:`jaxgear.io.build_dynamic_model`, a :class:`jaxgear.planetary.PlanetaryModel`) run by
:func:`jaxgear.dynamics.speed_sweep` (:func:`jaxgear.planetary.sweep_records`), Newmark in the
carrier frame (planar model: Coriolis and centripetal terms at the carrier
speed; for a helical stage whose axial and tilting supports hold it, the 3D model with the
gyroscopic moments of the members' spin), every mesh at once, over the **input member's
speeds** (rad/s, fixed frame, as the case's ``[operating] speed_rad_s``); the dynamic factor
per mesh and the dynamic load sharing per speed, and the ring transducer's order spectrum at the worst speed.

The dynamic stage is the load-sharing stage (:meth:`jaxgear.io.PlanetarySpec.sharing_stage`):
the sun loaded by its torque |T_s| and free in rotation, the ring and the carrier held in
rotation (a fixed member, or a driven one of large inertia), the planets and every translation
on their bearings; the meshes are the gears' contact cells
(:class:`~jaxgear.planetary.ContactMeshes`, time-varying stiffness, contact loss) or, in the lumped
form, the constant mesh springs (:class:`~jaxgear.planetary.ConstantMeshes`: no parametric
excitation, a dynamic factor of 1 unless pin errors move the planets). The ring is the case's
(``[planetary.ring]``): rigid, or a condensed ring as its ``dynamics`` key says (massless, with
mass, or modal; :meth:`~jaxgear.io.RingModelSpec.dynamic_ring`), in the sweep and the spectrum. At
input speed ω_in the carrier turns at Ω = ω_c(ω_in) and the mesh travels at v = r_bs |ω_s − ω_c|
(Willis, :meth:`~jaxgear.io.PlanetarySpec.speeds`).

The time discretisation is the model's (:meth:`~jaxgear.planetary.PlanetaryModel.time_plan`,
docs/planetary.md "Time step and span of a sweep"): each speed its own N_s (>= 40 steps per
period of the highest mode the meshes excite, the pairs' rule), a span from the damping's
settling time (the engine's automatic window, ``SteadyState(periods=None)``), every speed in
one compiled program (:attr:`~jaxgear.planetary.PlanetaryRun.mesh_steps`; a flexible ring's
speeds one program per N_s, :func:`speed_groups`), the settled state checked. This module
keeps the options' checks, the warnings naming them, the output sections and the plots.

Files (atomically, into the sweep's folder): ``sweep.json``, ``sweep.csv``,
``dynamic_factor.png`` (each mesh's dynamic factor against the input speed, the natural
frequencies' mesh-order crossings marked), ``campbell.png`` (the run's Campbell diagram in the
carrier frame) and ``ring_spectrum.png`` (the ring transducer at the worst speed, one whole
turn of the carrier relative to the ring: the mesh orders k z_r and their planet-pass
sidebands, the multiples of N about z_r).
"""

from __future__ import annotations

import math
import os
import platform
import time
import warnings

import jax
import jax.numpy as jnp
import numpy as np
from matplotlib.transforms import blended_transform_factory

from ..dynamics import (
    MAX_STEPS_PER_SPEED,
    MIN_STEPS_PER_PERIOD,
    SETTLE_TOL,
    SETTLED_TOL,
    Newmark,
    SteadyState,
    simulate,
)
from ..io import CaseWarning, build_dynamic_model, write_json
from ..planetary import (
    NO_EXCITATION_TOL,
    PlanarPlanetary,
    PlanetaryModel,
    PlanetaryRun,
    RigidRing,
    SpatialPlanetary,
    TimePlan,
    carrier_periodic,
    excitation,
    order_spectrum,
    planetary_modes,
    ring_transducer_signal,
    speed_groups,
    speed_run,
    sweep_factors,
    sweep_records,
)
from ._planetary_rating import stage_contact_model
from ._planetary_steps import check_plan_size, resolution_checked
from ._plots import new_figure
from ._plots._figure import legend_below_and_save
from ._progress import progress
from ._rating_sheet import sweep_excitation
from ._sweep_json import write_sweep_csv
from ._sweep_kinds import check_case_options
from .planetary import (
    MESH_ORDERS,
    RIGID_SHARE,
    campbell_section,
    planetary_files,
    planetary_lines,
)

__all__ = [
    "RUN_SPEEDS",
    "RUN_SWEEP_FILES",
    "SPECTRUM_SIDEBANDS",
    "SWEEP_FILES",
    "check_planetary_sweep",
    "model_words",
    "planetary_run",
    "planetary_run_files",
    "planetary_run_lines",
    "planetary_sweep",
    "planetary_sweep_files",
    "run_speeds",
    "sweep_lines",
    "sweep_summary",
    "sweep_time_plan",
    "turn_steps",
]

#: ``jaxgear run``'s first-look sweep: this many input speeds from 0.2 to 1.2 × the operating one
#: (and the operating one: :func:`run_speeds`)
RUN_SPEEDS = (0.2, 1.2, 8)
#: planet-pass sidebands marked on each side of a mesh order in ``ring_spectrum.png``
SPECTRUM_SIDEBANDS = 3
#: the files of ``jaxgear run``'s sweep/ of a planetary stage (its Campbell diagram is the
#: run's own ``campbell.png``, one folder up: the same figure, not written twice)
RUN_SWEEP_FILES = ("sweep.json", "sweep.csv", "dynamic_factor.png", "ring_spectrum.png")
#: the files of ``jaxgear sweep`` on a planetary stage
SWEEP_FILES = (*RUN_SWEEP_FILES, "campbell.png")
#: the most Newmark steps of a ring spectrum's integrated turn (a stage not periodic in the
#: carrier frame: :func:`turn_steps`): the turn's records (every coordinate of a flexible ring
#: at every step) stay within ~100 MB
TURN_MAX_STEPS = 2**16
#: the lowest amplitude drawn in ``ring_spectrum.png``, relative to its largest (log scale)
SPECTRUM_RANGE = 1e-7
#: per-mesh dynamic-factor curves closer than this share of the plotted range are drawn once
COINCIDE_SHARE = 1e-3
#: crossing lines closer than this share of the speed range share one label (7 pt text)
LABEL_GAP = 0.015
#: the dynamic model of the sweep (a helical stage whose supports hold it: the 3D model,
#: :func:`~jaxgear.cli.planetary.spatial_model`)
MODEL = PlanarPlanetary()
#: the sweep's model in words, by its kind
MODEL_WORDS = {
    PlanarPlanetary: "planar (carrier frame)",
    SpatialPlanetary: "3D lumped (carrier frame, the spin's gyroscopic moments)",
}


def model_words(kind) -> str:
    """The sweep's model kind in words (:data:`MODEL_WORDS`; a kind on a mount's: the kind
    on the ground's, on the housing)."""
    if kind.mount() is not None:
        return MODEL_WORDS[type(kind.unmounted())] + ", the held member on the housing's seat"
    return MODEL_WORDS[type(kind)]


def run_speeds(case) -> np.ndarray:
    """``jaxgear run``'s speeds (rad/s of the input, increasing): :data:`RUN_SPEEDS` × the
    operating speed, and the operating speed itself (the rating's measured K_v is the sweep
    there, not a straight line between speeds ~15 % apart:
    :func:`~jaxgear.cli.planetary.measured_k_v`)."""
    lo, hi, n = RUN_SPEEDS
    return np.union1d(np.linspace(lo, hi, n), [1.0]) * case.speed


def planetary_run(
    form, case, steps_per_period=None, periods=None, keep_periods=None
) -> PlanetaryRun:
    """The :class:`~jaxgear.planetary.PlanetaryRun` of a sweep of ``case``: the sun's torque
    |T_s| (Willis, from the input torque), the case's pin errors, damping ratio 0.05, and the
    options given; None takes a placeholder (64 steps, 2 periods, 1 kept) that
    :func:`time_plan` replaces speed by speed. One-line ``ValueError`` naming the option,
    before any work."""
    spec = form.spec
    given = {"--steps-per-period": steps_per_period, "--periods": periods,
             "--keep-periods": keep_periods}
    for name, v in given.items():
        if v is not None and v < 1:
            raise ValueError(f"{name} = {v}: out of range, allowed >= 1")
    if periods is not None and periods < 2:  # the engine's window (jaxgear.dynamics.SteadyState)
        raise ValueError(f"--periods = {periods}: out of range, allowed >= 2")
    if steps_per_period is not None and steps_per_period < 8:
        raise ValueError(f"--steps-per-period = {steps_per_period}: out of range, allowed >= 8")
    if keep_periods is not None and periods is not None and keep_periods > periods:
        raise ValueError(f"--keep-periods = {keep_periods}: out of range, allowed <= "
                         f"--periods = {periods}")
    # the pairs' bound (jaxgear.cli.sweep.sweep_spec), at the fewest steps a period can take;
    # the time plan checks the steps it takes (check_plan_size)
    steps = steps_per_period or MIN_STEPS_PER_PERIOD
    for name, count in (("--periods", periods), ("--keep-periods", keep_periods)):
        if count is not None and count * steps > MAX_STEPS_PER_SPEED:
            at = (f"{steps} time steps per mesh period (--steps-per-period)" if steps_per_period
                  else f"at least {steps} time steps per mesh period (automatic)")
            raise ValueError(
                f"{name} = {count}: out of range, allowed <= {MAX_STEPS_PER_SPEED // steps} with "
                f"{at}: {count * steps:.3g} time steps per speed, allowed <= "
                f"{MAX_STEPS_PER_SPEED:.3g} (fewer periods or steps per period)")
    return PlanetaryRun(
        abs(spec.torques(case.torque)["sun"]),
        steps_per_period=steps_per_period or MIN_STEPS_PER_PERIOD,
        periods=periods or max(2, keep_periods or 1),
        keep_periods=keep_periods or 1,
        tangential_pin_errors=np.asarray(spec.tangential_pin_errors),
        radial_pin_errors=np.asarray(spec.radial_pin_errors),
    )


def check_planetary_sweep(form, case, *, direction="independent", solver=None, contact=None,
                          periods=None, steps_per_period=None, keep_periods=None,
                          vtu_speed=None, slices=None) -> None:
    """``jaxgear sweep``'s options on a planetary stage checked before any file is touched:
    the counts' ranges (:func:`planetary_run`), then what the stage's dynamic model kind
    (:func:`jaxgear.io.dynamic_model_kind`, :class:`~jaxgear.planetary.PlanetaryModel`)
    cannot run, asked of its contract before any model is built
    (:func:`~jaxgear.cli._sweep_kinds.check_case_options`: ``--direction``, ``--solver``,
    ``--contact``, ``--vtu-speed``). One-line ``ValueError``."""
    periods = None if periods == "auto" else periods
    planetary_run(form, case, steps_per_period, periods, keep_periods)
    check_case_options(case, direction=direction, solver=solver, contact=contact,
                       vtu_speed=vtu_speed)


def planetary_sweep_files(form, case, speeds, out_dir: str, *, direction="independent",
                          solver=None, contact=None, periods=None, steps_per_period=None,
                          keep_periods=None, vtu_speed=None, slices=None,
                          show_progress=True) -> dict:
    """``jaxgear sweep`` on a planetary stage (options checked by
    :func:`check_planetary_sweep`): :func:`planetary_sweep` at the given counts (None, and
    ``periods`` ``"auto"``: the model's time plan) and contact law (None: the model's).
    ``direction``, ``solver``, ``vtu_speed`` and ``show_progress`` are those the check
    allowed (independent speeds, Newmark; no bar: the sweep is one compiled program)."""
    return planetary_sweep(
        form, case, speeds, out_dir, steps_per_period=steps_per_period,
        periods=None if periods == "auto" else periods, keep_periods=keep_periods,
        slices=slices, contact=None if contact is None else case.contact_law(contact),
    )


def sweep_time_plan(form, case, speeds, *, steps_per_period=None, periods=None,
                    keep_periods=None, slices=None) -> TimePlan:
    """The :class:`TimePlan` that :func:`sweep_summary` runs ``case`` with at the input
    ``speeds`` (rad/s, (s,)) and the options given (None: the rule), without integrating: the
    case's dynamic model's (:func:`jaxgear.io.build_dynamic_model`,
    :meth:`jaxgear.planetary.PlanetaryModel.time_plan`)."""
    planetary_run(form, case, steps_per_period, periods, keep_periods)  # the options' checks
    dyn, _ = build_dynamic_model(case, slices=slices)
    return _plan(form.spec, dyn, np.asarray(speeds, dtype=float),
                 (steps_per_period, periods, keep_periods))


def _plan(spec, dyn, speeds, given) -> TimePlan:
    """The time plan of the dynamic model ``dyn`` (:meth:`jaxgear.planetary.PlanetaryModel.
    time_plan`, the model's preparation step); ``given``: (steps, periods, keep); a plan that
    cannot run refused in one line naming the option
    (:func:`~jaxgear.cli._planetary_steps.check_plan_size`), before any integration."""
    flexible = dyn.flexible_ring()
    plan, modes = dyn.time_plan(speeds, given[0], dyn.sweep_window(given[1], given[2]))
    # recorded per step: the coordinates (a flexible ring's 2 z_r stations too), the 2N mesh
    # forces, N ring deflections, time and travel
    values = (int(np.asarray(modes.omega).size) + 2 * spec.teeth[2] * flexible
              + 3 * spec.n_planets + 2)
    check_plan_size(plan, speeds, speed_groups(plan, flexible), values,
                    dict(zip(("--periods", "--steps-per-period", "--keep-periods"),
                             (given[1], given[0], given[2]), strict=True)))
    return plan


def planetary_sweep(
    form,
    case,
    speeds,
    out_dir: str,
    *,
    steps_per_period: int | None = None,
    periods: int | None = None,
    keep_periods: int | None = None,
    slices: int | None = None,
    campbell_file: str | None = None,
    contact=None,
) -> dict:
    """Sweep the input speeds ``speeds`` (rad/s, (s,), > 0) of a planetary case (module
    docstring) and write its files into ``out_dir`` (:data:`SWEEP_FILES`); returns
    ``sweep.json``'s content.

    ``sweep.json``: the keys of :func:`sweep_summary`, the Campbell diagram's file and
    ``ring_spectrum`` (the ring transducer at the worst speed). ``campbell_file``: where the
    same Campbell diagram is written already, relative to ``out_dir`` (``jaxgear run``'s
    ``../campbell.png``): not drawn again, ``campbell`` names it. ``contact``: the contact
    law of the sweep and of the ring spectrum's run (None: the model's,
    :meth:`~jaxgear.planetary.PlanetaryModel.default_settings`)."""
    t0 = time.perf_counter()
    summary, (stage, meshes, run, ring, model, settled) = sweep_summary(
        form, case, speeds, steps_per_period=steps_per_period, periods=periods,
        keep_periods=keep_periods, slices=slices, contact=contact,
    )
    spec = form.spec
    summary["campbell"] = campbell_file or campbell_section(
        case, spec, spec.stage(case), os.path.join(out_dir, "campbell.png")
    )["file"]
    summary["ring_spectrum"] = ring_spectrum(
        case, stage, meshes, run, summary["speed_of_max_rad_s"],
        os.path.join(out_dir, "ring_spectrum.png"), ring, model, settled, contact,
    )
    summary["elapsed_s"] = time.perf_counter() - t0
    write_json(os.path.join(out_dir, "sweep.json"), summary)
    write_sweep_csv(os.path.join(out_dir, "sweep.csv"), summary)
    dynamic_factor_plot(case, summary, os.path.join(out_dir, "dynamic_factor.png"))
    return summary


def sweep_summary(
    form,
    case,
    speeds,
    *,
    steps_per_period: int | None = None,
    periods: int | None = None,
    keep_periods: int | None = None,
    slices: int | None = None,
    contact=None,
) -> tuple[dict, tuple]:
    """The sweep of :func:`planetary_sweep` without its files, spectrum and Campbell diagram:
    (``sweep.json``'s numbers, (the dynamic stage, its meshes, the worst speed's run, the ring
    model, the model, the worst speed's last kept mesh period (time (s), ring-mesh forces (N))
    where the stage is carrier-periodic, else None)).

    Keys: ``speeds_rad_s`` (input), ``carrier_speeds_rad_s``, ``mesh_frequency_Hz`` (carrier
    frame), ``mesh_names`` (``sun-planet 1..N``, then ``ring-planet 1..N``),
    ``dynamic_factor_mesh`` (s, 2N: each mesh's largest force over the kept periods over the
    nominal T_s/(N r_bs)), ``dynamic_factor`` (the worst mesh per speed), ``k_gamma`` (the
    dynamic load sharing factor per speed, peak-based: each planet path's peak sun-mesh force
    over the mean of the paths' peaks) and ``k_gamma_mean_load`` (the time-mean shares' K_γ;
    both :func:`jaxgear.planetary.dynamic_load_sharing`), their maxima and where, ``natural_frequencies_Hz`` (the sweep's model at
    the stage's constant mesh stiffness) and ``crossings``; the time discretisation
    (:func:`time_plan`, every speed in one compiled program at its own step): ``steps_per_period``
    and ``periods`` per speed (N_s, the mesh periods integrated), ``keep_periods``,
    ``steps_resolution`` (:func:`step_resolution`, its ``CaseWarning`` before the sweep),
    ``settling`` (``f_min_Hz``, ``settle_s``, ``tolerance``, ``carrier_periodic``,
    ``automatic``), ``periodicity`` per speed (max |F(last kept period) − F(the one before)|
    over the nominal force; None with one kept period) and ``settled`` (False, with one
    ``CaseWarning``, where a carrier-periodic stage's exceeds :data:`SETTLED_TOL`); ``ring_model`` (words) and
    ``ring``: the ring model of the sweep (``[planetary.ring]``: ``model``, and for a condensed ring
    ``body``, ``dynamics``, ``modes``); for a condensed ring ``ring_deflection_max_m`` per speed
    (the largest elastic ring displacement at a ring mesh over the kept periods, m) and its
    maximum ``max_ring_deflection_m``; with a ``contact`` law given (a
    :class:`~jaxgear.ContactLaw`; None: the model's), ``contact``: its kind."""
    spec = form.spec
    planetary_run(form, case, steps_per_period, periods, keep_periods)  # the options' checks
    dyn, _ = build_dynamic_model(case, slices=slices)
    stage, meshes, ring, model, base = dyn.stage, dyn.meshes, dyn.ring, dyn.mounted_kind, dyn.run
    speeds = np.asarray(speeds, dtype=float)
    f_mesh = spec.mesh_frequency(1.0)  # Hz per rad/s of the input
    flexible = dyn.flexible_ring()
    periodic = carrier_periodic(stage, flexible)
    plan = _plan(spec, dyn, speeds, (steps_per_period, periods, keep_periods))
    resolution = resolution_checked(plan, speeds * f_mesh, spec.n_planets)  # before the work
    carrier = speeds * spec.speeds(1.0)["carrier"]
    rec = sweep_records(dyn, speeds, plan, contact=contact)
    n = spec.n_planets
    fs = rec.static_force
    per_mesh, k_gamma, periodicity, deflection, k_mean = sweep_factors(rec, plan, n)
    code = rec.result
    period_of = rec.periods  # mesh periods integrated
    excite = excitation(model, stage, meshes, base, flexible)
    excite["words"] = None if excite["excited"] else (
        "no excitation (constant mesh stiffness, no pin errors): dynamic factor = 1, K_γ = 1")
    if not excite["excited"]:  # the response is the static one: round-off is all that moves
        excite["round_off_deviation"] = float(np.nanmax(np.abs(
            np.concatenate([per_mesh.ravel(), k_gamma, k_mean]) - 1.0)))
        per_mesh[:], k_gamma[:], k_mean[:] = 1.0, 1.0, 1.0
    worst = per_mesh.max(axis=1)
    # the worst speed (the ring spectrum's); with nothing to excite, the operating speed's
    # nearest (not one chosen by round-off)
    i = (int(np.nanargmax(worst)) if excite["excited"] else
         int(np.argmin(np.abs(speeds - case.speed))))
    run_i = speed_run(base, plan, i)
    settled_turn = None
    if periodic:  # the worst speed's last mesh period: the ring spectrum's turn from it
        last = slice(-int(plan.steps[i]), None)
        settled_turn = (rec.time[i][last], rec.forces[i][last, n:])
    unsettled = periodic and plan.keep >= 2 and bool(np.nanmax(periodicity) > SETTLED_TOL)
    if unsettled:
        k = int(np.nanargmax(periodicity))
        warnings.warn(
            f"speed {speeds[k]:.4g} rad/s: not settled, the last kept mesh period differs from "
            f"the one before by {periodicity[k]:.3g} of the nominal mesh force (> "
            f"{SETTLED_TOL}; --periods {int(period_of[k])}): a longer transient or a response "
            "that does not repeat every mesh period (contact loss near a resonance); "
            "--periods larger tells which", CaseWarning, stacklevel=2)
    names = [f"sun-planet {k + 1}" for k in range(n)] + [f"ring-planet {k + 1}" for k in range(n)]
    f0 = np.asarray(planetary_modes(model, stage).frequencies)
    natural = f0[f0 > RIGID_SHARE * max(float(f0.max()), 1.0)]
    summary = {
        "case": case.name,
        "kind": "planetary",
        "model": model_words(model),
        "ring_model": spec.ring_model.words(),
        "meshes": type(meshes).__name__,
        "speed_of": f"input ({spec.input.name.lower()})",
        "speeds_rad_s": speeds.tolist(),
        "carrier_speeds_rad_s": carrier.tolist(),
        "mesh_frequency_Hz": (speeds * f_mesh).tolist(),
        "mesh_names": names,
        "dynamic_factor_mesh": per_mesh.tolist(),
        "dynamic_factor": worst.tolist(),
        "k_gamma": k_gamma.tolist(),
        "k_gamma_mean_load": k_mean.tolist(),
        "max_dynamic_factor": float(worst[i]),
        "speed_of_max_rad_s": float(speeds[i]),
        "max_dynamic_factor_mesh": per_mesh.max(axis=0).tolist(),
        "max_k_gamma": float(k_gamma.max()),
        "max_k_gamma_mean_load": float(k_mean.max()),
        "excitation": excite,
        "result": code.tolist(),
        "sun_torque_Nm": float(base.sun_torque),
        "nominal_mesh_force_N": fs,
        "steps_per_period": plan.steps.tolist(),
        "periods": period_of.tolist(),
        "keep_periods": plan.keep,
        "steps_resolution": resolution,
        "settling": {
            "f_min_Hz": plan.f_min_Hz, "settle_s": plan.settle_s, "tolerance": SETTLE_TOL,
            "carrier_periodic": periodic, "automatic": bool(plan.automatic[1]),
        },
        "periodicity": [None if math.isnan(v) else float(v) for v in periodicity],
        "settled": not unsettled,
        "damping_ratio": float(base.damping_ratio),
        "natural_frequencies_Hz": natural.tolist(),
        "crossings": crossings(natural, f_mesh, speeds),
        "ring": spec.ring_model.summary(),
    }
    # what the factors are where every mesh frequency is far below the modes (None: not so)
    excite["far_below_resonance"] = (
        sweep_excitation(speeds * f_mesh, float(natural[0]), stage_contact_model(meshes))
        if natural.size and excite["words"] is None else None)
    if contact is not None:
        summary["contact"] = type(contact).__name__
    if spec.ring_model.flexible:
        summary["ring_deflection_max_m"] = deflection.tolist()
        summary["max_ring_deflection_m"] = float(deflection.max())
    summary["platform"] = {
        "device": str(jax.devices()[0].platform),
        "dtype": str(rec.time[0].dtype),
        "python": platform.python_version(),
    }
    summary["notes"] = (
        "dynamic stage: the sun loaded by |T_s| and free in rotation, ring and carrier held; "
        "dynamic factor: each mesh's largest transverse force over the kept periods over the "
        "nominal T_s/(N r_bs) (pin errors included); k_gamma: the dynamic load sharing factor, "
        "peak-based: the largest planet path's peak sun-mesh force over the kept periods over "
        "the mean of the paths' peaks (each path's dynamic factor over the mean path's; the "
        "per-instant ratio would count the dynamic factor a second time); k_gamma_mean_load: "
        "the same of the paths' time-mean forces"
    )
    return summary, (stage, meshes, run_i, ring, model, settled_turn)


def crossings(natural, f_mesh: float, speeds) -> list[dict]:
    """Where a mesh order k (:data:`MESH_ORDERS`) meets a natural frequency f within the
    swept input speeds: ω_in = f / (k f_mesh) (``f_mesh``: Hz per rad/s of the input)."""
    lo, hi = float(np.min(speeds)), float(np.max(speeds))
    out = []
    for k in MESH_ORDERS:
        for f in natural:
            s = float(f) / (k * f_mesh) if f_mesh > 0 else math.inf
            if lo <= s <= hi:
                out.append({"order": k, "frequency_Hz": float(f), "speed_rad_s": s})
    return out


def dynamic_factor_plot(case, summary: dict, path: str) -> None:
    """Each mesh's dynamic factor and the dynamic K_γ against the input speed (meshes whose
    curves coincide, within :data:`COINCIDE_SHARE` of the range, drawn once and named
    together), the mesh-order crossings of the natural frequencies as vertical lines, each
    labelled with its frequency and order (lines closer than :data:`LABEL_GAP` of the speed
    range under one label); an under-resolved time step (``steps_resolution``) said in the
    title; a stage with nothing to excite (``excitation``) one line at 1 and the words."""
    fig, ax = new_figure()
    s = np.asarray(summary["speeds_rad_s"])
    df = np.asarray(summary["dynamic_factor_mesh"])
    n = df.shape[1] // 2
    quiet = (summary.get("excitation") or {}).get("words")
    if quiet:  # nothing excites the stage: one line at 1, not the meshes' round-off
        ax.plot(s, np.ones_like(s), "o-", color="k", ms=3, lw=1.0,
                label="every mesh's dynamic factor and K_γ: 1")
        ax.set_ylim(0.9, 1.1)
        ax.ticklabel_format(axis="y", useOffset=False)
        ax.text(0.5, 0.75, quiet, transform=ax.transAxes, ha="center", va="center",
                fontsize=9, bbox={"facecolor": "white", "edgecolor": "0.6"})
    else:  # meshes whose curves coincide (planets sharing alike) drawn once, named together
        span = float(np.ptp(df)) or 1.0
        groups: list[list[int]] = []
        for j in range(df.shape[1]):
            same = next((g for g in groups if (g[0] < n) == (j < n) and np.max(
                np.abs(df[:, g[0]] - df[:, j])) <= COINCIDE_SHARE * span), None)
            if same is None:
                groups.append([j])
            else:
                same.append(j)
        names = summary["mesh_names"]
        for g in groups:
            label = names[g[0]] if len(g) == 1 else (
                names[g[0]].rsplit(" ", 1)[0] + " " + ", ".join(
                    names[j].rsplit(" ", 1)[1] for j in g) + " (coincide)")
            ax.plot(s, df[:, g[0]], "o-" if g[0] < n else "s--", ms=3, lw=1.0, label=label)
        ax.plot(s, summary["k_gamma"], "^:", color="k", ms=3, lw=1.0, label="dynamic K_γ (peak-based)")
    styles = {1: "tab:red", 2: "tab:purple", 3: "tab:brown"}
    seen = set()
    trans = blended_transform_factory(ax.transData, ax.transAxes)
    lo, hi = float(np.min(s)), float(np.max(s))
    cross = sorted(summary["crossings"], key=lambda c: c["speed_rad_s"])
    clusters: list[list[dict]] = []  # lines closer than a label's width share one label
    for c in cross:
        if clusters and c["speed_rad_s"] - clusters[-1][-1]["speed_rad_s"] < LABEL_GAP * (
                hi - lo or 1.0):
            clusters[-1].append(c)
        else:
            clusters.append([c])
    for cl in clusters:  # every line labelled at its top
        for c in cl:
            k = c["order"]
            ax.axvline(c["speed_rad_s"], color=styles.get(k, "0.5"), lw=0.7, ls="-.",
                       label=None if k in seen else f"mesh order {k} × natural frequency")
            seen.add(k)
        text = ", ".join(f"{c['frequency_Hz']:.0f} Hz / {c['order']}" for c in cl)
        ax.text(cl[0]["speed_rad_s"], 0.985, text, transform=trans, rotation=90, fontsize=7,
                color=styles.get(cl[0]["order"], "0.35") if len(cl) == 1 else "0.3", va="top",
                ha="center", bbox={"boxstyle": "square,pad=0.15", "fc": "white", "ec": "none"})
    ax.set_xlabel(f"{summary['speed_of']} speed (rad/s)")
    ax.set_ylabel("dynamic factor, K_γ (-)")
    res = summary.get("steps_resolution") or {}
    flag = ("" if res.get("resolved", True) else
            f"\ntime step under-resolved, dynamic factors low: "
            f"{res['steps_per_top_period_min']:.2g} steps per period of {res['f_max_Hz']:.0f} Hz"
            f"\n(--steps-per-period >= {res['steps_per_period_resolved']} resolves it)")
    ax.set_title(f"{case.name}: " + ("no excitation, dynamic factor = 1 " if quiet else
                 "dynamic factor per mesh ") + f"({summary['model']}, "
                 f"{summary['ring_model']}){flag}", fontsize=10)
    ax.grid(alpha=0.3)
    legend_below_and_save(fig, ax, path, None)


def ring_spectrum(case, stage, meshes, run, speed: float, path: str, ring=None, model=MODEL,
                  settled=None, contact=None) -> dict:
    """The ring transducer (:func:`~jaxgear.planetary.ring_transducer_signal`, at angle 0) at
    input ``speed`` over one whole turn of the carrier relative to the ring (z_r mesh periods,
    after the run's transient), its order spectrum (orders of that turn) drawn into ``path``;
    returns its keys: the mesh order's amplitude and the planet-pass sidebands', and how the
    turn was had (``turn``). ``ring``: the sweep's ring model (None: rigid); ``model`` its
    model kind. ``settled``: None, or (time (s), ring-mesh forces (N)) of one settled mesh
    period, (S,) and (S, N), of a stage periodic in the carrier frame
    (:func:`carrier_periodic`): the turn's forces are that period's repeated z_r times (no
    integration; equal to the integrated turn to 1e-9 of the nominal force on a test stage);
    else the turn is integrated after ``run``'s settling time, at ``run``'s step or, past
    :data:`TURN_MAX_STEPS` steps for the turn, a coarser one (:func:`turn_steps`), with the
    ``contact`` law (None: the model's).
    Where the mesh order's amplitude is round-off (below :data:`NO_EXCITATION_TOL` of the mean
    load: nothing excites the meshes, :func:`excitation`), the title says so: the planets'
    passing alone shows."""
    spec = case.form.spec
    z_r = int(spec.teeth[2])
    w = spec.speeds(speed)
    rel = w["carrier"] - w["ring"]
    if settled is None:
        steps = turn_steps(run.steps_per_period, z_r, spec.n_planets)
        time_turn, forces = _integrated_turn(stage, meshes, run, spec, speed, ring, model, steps,
                                             contact)
    else:
        steps = run.steps_per_period
        time_turn, forces = _repeated_turn(*settled, z_r)
    theta = jnp.asarray(time_turn * rel)
    y = ring_transducer_signal(jnp.asarray(forces), theta, stage.planet_angles)
    orders, amp = order_spectrum(y, steps * z_r)
    n = spec.n_planets
    # with the planets' window, the mesh order's energy appears at the multiples of N about
    # it (McFadden & Smith 1985): the orders j N within SPECTRUM_SIDEBANDS N of z_r
    near_mesh = range(z_r - SPECTRUM_SIDEBANDS * n, z_r + SPECTRUM_SIDEBANDS * n + 1)
    marks = [m for m in near_mesh if m % n == 0]
    fig, ax = new_figure()
    top = min(len(orders) - 1, 2 * z_r + (SPECTRUM_SIDEBANDS + 1) * n)
    ax.vlines(orders[1 : top + 1], 1e-30, amp[1 : top + 1] * 1e-3, color="0.2", lw=1.0,
              label="ring transducer (kN)")
    for k in (1, 2):
        if k * z_r <= top:
            ax.axvline(k * z_r, color="tab:red", lw=0.8, ls="--",
                       label="mesh orders k z_r" if k == 1 else None)
    side = [m for m in marks if 0 < m <= top]
    ax.plot(side, amp[side] * 1e-3, "o", mfc="none", color="tab:blue",
            label=f"planet-pass sidebands: orders j N about z_r = {z_r} (N = {n})")
    peak = float(np.max(amp[1 : top + 1])) * 1e-3
    if peak > 0:  # the planet-pass orders dwarf the mesh orders: a log scale shows both
        ax.set_yscale("log")
        ax.set_ylim(peak * SPECTRUM_RANGE, peak * 2.0)
    ax.set_xlabel("order of the carrier's turn relative to the ring (-)")
    ax.set_ylabel("amplitude (kN)")
    excited = not (z_r < len(amp) and amp[z_r] < NO_EXCITATION_TOL * abs(amp[0]))
    ax.set_title(f"{case.name}: ring transducer at {speed:.4g} rad/s (input), one carrier turn"
                 + ("" if excited else "; no excitation (the mesh orders are round-off): the "
                    "planets' passing only"))
    ax.grid(alpha=0.3)
    legend_below_and_save(fig, ax, path, None)
    near = [m for m in marks if 0 < m < len(amp)]
    return {
        "file": "ring_spectrum.png",
        "speed_rad_s": speed,
        "sensor_angle_deg": 0.0,
        "mesh_order": z_r,
        "mesh_order_amplitude_N": float(amp[z_r]) if z_r < len(amp) else None,
        "sideband_orders": near,
        "sideband_amplitudes_N": [float(amp[m]) for m in near],
        "mean_N": float(amp[0]),
        "turn": "one settled mesh period repeated" if settled is not None else "integrated",
        "turn_steps_per_period": int(steps),
        "mesh_orders_excited": bool(excited),
    }


def _repeated_turn(time_one, forces_one, z_r: int):
    """(time (s), forces) of z_r mesh periods from one settled period's (S,), (S, N): the
    times continue with the step dt, the forces repeat."""
    S = time_one.shape[0]
    dt = (time_one[-1] - time_one[0]) / (S - 1)
    return time_one[0] + dt * np.arange(z_r * S), np.tile(forces_one, (z_r, 1))


def turn_steps(steps: int, z_r: int, n_planets: int) -> int:
    """The steps per mesh period of an integrated turn (z_r mesh periods): the sweep's
    ``steps``, or, where the turn would exceed :data:`TURN_MAX_STEPS`, the largest
    ``n_planets`` × 2^j within it (at least 8 n_planets; the spectrum of such a stage is then
    a coarser look than its sweep, ``ring_spectrum``'s ``turn_steps_per_period`` says)."""
    n = int(steps)
    while n * z_r > TURN_MAX_STEPS and n % 2 == 0 and n // 2 >= 8 * n_planets:
        n //= 2
    return n


def _integrated_turn(stage, meshes, run, spec, speed, ring, model, steps, contact=None):
    """(time (s), ring-mesh forces (N)) of one turn integrated: ``run``'s settling time, then
    z_r kept mesh periods, at ``steps`` per mesh period."""
    z_r = int(spec.teeth[2])
    settle = math.ceil((run.periods - run.keep_periods) * run.steps_per_period / steps)
    dyn = PlanetaryModel(model, stage, meshes, run, spec.speeds(1.0)["carrier"],
                         spec.mesh_speed(1.0), RigidRing() if ring is None else ring)
    d = simulate(dyn, float(speed), integrator=Newmark(int(steps)), contact=contact,
                 window=SteadyState(settle + z_r, z_r))
    return np.asarray(d.time), np.asarray(d.ring_mesh_forces)


def sweep_lines(case, s: dict) -> list[str]:
    """What ``jaxgear sweep`` prints for a planetary case."""
    i = int(np.argmax(s["dynamic_factor"]))
    worst = s["mesh_names"][int(np.argmax(s["dynamic_factor_mesh"][i]))]
    nat = ", ".join(f"{f:.4g}" for f in s["natural_frequencies_Hz"][:6])
    quiet = (s.get("excitation") or {}).get("words")
    line = (
        f"{case.name}: {len(s['speeds_rad_s'])} input speeds, "
        + (quiet if quiet else
           f"max dynamic factor {s['max_dynamic_factor']:.4f} ({worst}) at "
           f"{s['speed_of_max_rad_s']:.4g} rad/s, max dynamic K_γ {s['max_k_gamma']:.4f} "
           f"(peak-based; mean-load {s['max_k_gamma_mean_load']:.4f})")
        + f"; {_ring_words(s)}"
        + f"; first natural frequencies {nat} Hz; "
        f"{sum(1 for v in s['result'] if v)} diverged; {s['elapsed_s']:.1f} s"
    )
    note = s["excitation"].get("far_below_resonance")
    return [line] + ([f"  note: {note}"] if note else [])


def _ring_words(s: dict) -> str:
    """The sweep's ring model in words, with its largest deflection over the sweep where the
    ring is flexible (``s``: ``sweep.json`` or the run's ``dynamics`` section)."""
    w = s.get("max_ring_deflection_m")
    return s["ring_model"] + ("" if w is None else f", ring deflection max {w * 1e6:.3g} µm")


def planetary_run_files(form, case, out: str, args, complete: bool) -> dict:
    """``jaxgear run`` on a planetary case: a first-look sweep into ``out``/sweep
    (:func:`run_speeds`, the defaults of :func:`planetary_run`), then the stage's files
    (:func:`~jaxgear.cli.planetary.planetary_files`, the rating's measured K_v from the sweep)
    and ``summary.json``'s ``dynamics``: the worst mesh's dynamic factor per speed, each mesh's
    maximum, the dynamic K_γ per speed and its largest (peak-based, and the mean-load one
    beside it: :func:`jaxgear.planetary.dynamic_load_sharing`). A bar over the two stages (unless ``args.quiet``)."""
    speeds = run_speeds(case)
    bar = progress(total=2, desc=f"jaxgear run {case.name}", disable=bool(args.quiet))
    bar.set_postfix_str(f"dynamic sweep, {speeds.size} speeds")
    sub = os.path.join(out, "sweep")
    os.makedirs(sub, exist_ok=True)
    sw = planetary_sweep(form, case, speeds, sub, campbell_file="../campbell.png")
    bar.update()
    bar.set_postfix_str("load sharing, modes, Campbell, meshes, rating")
    summary = planetary_files(form, case, out, args, False, sw)  # the rating's measured K_v
    bar.update()
    bar.close()
    summary["dynamics"] = {
        "model": sw["model"],
        "speed_of": sw["speed_of"],
        "speeds_rad_s": sw["speeds_rad_s"],
        "dynamic_factor": sw["dynamic_factor"],
        "max_dynamic_factor": sw["max_dynamic_factor"],
        "speed_of_max_rad_s": sw["speed_of_max_rad_s"],
        "mesh_names": sw["mesh_names"],
        "max_dynamic_factor_mesh": sw["max_dynamic_factor_mesh"],
        "k_gamma": sw["k_gamma"],
        "max_k_gamma": sw["max_k_gamma"],
        "k_gamma_mean_load": sw["k_gamma_mean_load"],
        "max_k_gamma_mean_load": sw["max_k_gamma_mean_load"],
        "excitation": sw["excitation"],
        "steps_per_period": sw["steps_per_period"],
        "steps_resolution": sw["steps_resolution"],
        **{k: sw[k] for k in ("periods", "settled") if k in sw},  # the span, its check
        "ring_model": sw["ring_model"],
        "ring": sw["ring"],
        **{k: sw[k] for k in ("max_ring_deflection_m",) if k in sw},  # a flexible ring's
        "files": ", ".join(f"sweep/{n}" for n in RUN_SWEEP_FILES),
    }
    summary["complete"] = bool(complete)
    write_json(os.path.join(out, "summary.json"), summary)
    return summary


def planetary_run_lines(form, case, summary: dict) -> list[str]:
    """What ``jaxgear run`` prints for a planetary case: the stage's lines and the sweep's."""
    d = summary["dynamics"]
    quiet = (d.get("excitation") or {}).get("words")
    line = (
        f"dynamic factor ({d['model']}, {len(d['speeds_rad_s'])} {d['speed_of']} speeds "
        f"{d['speeds_rad_s'][0]:.4g}–{d['speeds_rad_s'][-1]:.4g} rad/s): "
        + (quiet if quiet else
           f"max {d['max_dynamic_factor']:.4f} at {d['speed_of_max_rad_s']:.4g} rad/s, "
           f"dynamic K_γ max {d['max_k_gamma']:.4f} (peak-based; mean-load "
           f"{d['max_k_gamma_mean_load']:.4f})")
        + f", {_ring_words(d)} ({d['files']})"
    )
    far = d["excitation"].get("far_below_resonance")
    note = [f"  note: {far}"] if far else []
    return [*planetary_lines(form, case, summary), line, *note]
