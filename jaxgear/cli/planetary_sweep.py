"""``jaxgear sweep`` on a planetary stage (a case of :class:`jaxgear.io.PlanetaryForm`), and the
sweep section of ``jaxgear run`` on one: :func:`jaxgear.dynamics.planetary_speed_sweep`'s
Newmark in the carrier frame (planar model: Coriolis and centripetal terms at the carrier
speed; for a helical stage whose axial and tilting supports hold it, the 3D model with the
gyroscopic moments of the members' spin), every mesh at once, over the **input member's
speeds** (rad/s, fixed frame, as the case's ``[operating] speed_rad_s``); the dynamic factor
per mesh and the dynamic load sharing per speed, and the ring transducer's order spectrum at the worst speed.

The dynamic stage is the load-sharing stage (:meth:`jaxgear.io.PlanetarySpec.sharing_stage`):
the sun loaded by its torque |T_s| and free in rotation, the ring and the carrier held in
rotation (a fixed member, or a driven one of large inertia), the planets and every translation
on their bearings; the meshes are the gears' contact cells (:class:`~jaxgear.ContactMeshes`,
time-varying stiffness, contact loss) or, in the lumped form, the constant mesh springs
(:class:`~jaxgear.ConstantMeshes`: no parametric excitation, a dynamic factor of 1 unless pin
errors move the planets). The ring is the case's (``[planetary.ring]``): rigid, or a condensed
ring as its ``dynamics`` key says (massless, with mass, or modal;
:meth:`~jaxgear.io.RingModelSpec.dynamic_ring`), in the sweep and the spectrum. At input speed ω_in the carrier turns at Ω = ω_c(ω_in) and the mesh
travels at v = r_bs |ω_s − ω_c| (Willis, :meth:`~jaxgear.io.PlanetarySpec.speeds`).

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
from tqdm.auto import tqdm

from .. import ConstantMeshes, PlanarPlanetary, RigidRing, SpatialPlanetary, planetary_modes
from ..dynamics import (
    PlanetaryRun,
    order_spectrum,
    planetary_dynamics,
    planetary_speed_sweep,
    ring_transducer_signal,
)
from ..io import CaseWarning, write_json
from ._plots import new_figure
from ._plots._figure import legend_below_and_save
from ._sweep_json import write_sweep_csv
from .planetary import (
    MESH_ORDERS,
    RIGID_SHARE,
    campbell_section,
    planetary_files,
    planetary_lines,
    spatial_model,
)

__all__ = [
    "DEFAULT_PERIODS",
    "DEFAULT_STEPS",
    "RUN_SPEEDS",
    "RUN_SWEEP_FILES",
    "SPECTRUM_SIDEBANDS",
    "planetary_run",
    "planetary_run_files",
    "planetary_run_lines",
    "planetary_sweep",
    "run_speeds",
    "step_resolution",
    "sweep_lines",
    "sweep_summary",
]

#: Newmark steps per mesh period (rounded up to a multiple of the planet count, so that the
#: planets' phases fall on the steps, :func:`jaxgear.dynamics.planetary_dynamics`)
DEFAULT_STEPS = 64
#: the fewest Newmark steps per period of the stage's highest natural frequency below which
#: the sweep warns (:func:`step_resolution`): the average-acceleration rule has no numerical
#: damping but lengthens a period T by about (2π dt / T)² / 12 and filters what it cannot resolve
STEPS_PER_TOP_PERIOD = 10
#: mesh periods integrated per speed (the first ones settle the transient)
DEFAULT_PERIODS = 40
#: ``jaxgear run``'s first-look sweep: this many input speeds from 0.2 to 1.2 × the operating one
#: (and the operating one: :func:`run_speeds`)
RUN_SPEEDS = (0.2, 1.2, 8)
#: planet-pass sidebands marked on each side of a mesh order in ``ring_spectrum.png``
SPECTRUM_SIDEBANDS = 3
#: the files of ``jaxgear run``'s sweep/ of a planetary stage
RUN_SWEEP_FILES = ("sweep.json", "sweep.csv", "dynamic_factor.png", "campbell.png",
                   "ring_spectrum.png")
#: the lowest amplitude drawn in ``ring_spectrum.png``, relative to its largest (log scale)
SPECTRUM_RANGE = 1e-7
#: the dynamic model of the sweep (a helical stage whose supports hold it: the 3D model,
#: :func:`~jaxgear.cli.planetary.spatial_model`)
MODEL = PlanarPlanetary()
#: the sweep's model in words, by its kind
MODEL_WORDS = {
    PlanarPlanetary: "planar (carrier frame)",
    SpatialPlanetary: "3D lumped (carrier frame, the spin's gyroscopic moments)",
}


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
    """The :class:`~jaxgear.dynamics.PlanetaryRun` of a sweep of ``case``: the sun's torque
    |T_s| (Willis, from the input torque), the case's pin errors, damping ratio 0.05, and the
    options given (None: :data:`DEFAULT_STEPS` rounded up to a multiple of N,
    :data:`DEFAULT_PERIODS`, 4 kept periods). One-line ``ValueError`` naming the option."""
    spec = form.spec
    n = spec.n_planets
    given = {"--steps-per-period": steps_per_period, "--periods": periods,
             "--keep-periods": keep_periods}
    for name, v in given.items():
        if v is not None and v < 1:
            raise ValueError(f"{name} = {v}: out of range, allowed >= 1")
    steps = steps_per_period or n * -(-DEFAULT_STEPS // n)
    if steps < 8:
        raise ValueError(f"--steps-per-period = {steps}: out of range, allowed >= 8")
    periods = periods or DEFAULT_PERIODS
    keep = keep_periods or min(4, periods)
    if keep > periods:
        raise ValueError(f"--keep-periods = {keep}: out of range, allowed <= --periods = {periods}")
    return PlanetaryRun(
        abs(spec.torques(case.torque)["sun"]),
        steps_per_period=steps,
        periods=periods,
        keep_periods=keep,
        tangential_pin_errors=np.asarray(spec.tangential_pin_errors),
        radial_pin_errors=np.asarray(spec.radial_pin_errors),
    )


def step_resolution(model, stage, f_mesh, steps: int, n_planets: int) -> dict:
    """Whether the sweep's time step resolves the stage's highest natural frequency f_max
    (Hz: :func:`jaxgear.planetary_modes` of ``model`` on ``stage``, the stage as ``jaxgear
    modes`` and the Campbell diagram take it, members on their supports): at mesh frequency
    f_mesh (Hz, the swept speeds', (s,)) and ``steps`` per mesh period, n = steps f_mesh /
    f_max steps per period of f_max. Below :data:`STEPS_PER_TOP_PERIOD` at the lowest swept
    speed, Newmark's average acceleration (no numerical damping, period elongation) filters
    those modes (the impacts of teeth entering mesh) and the dynamic factor comes out low:
    one ``CaseWarning`` line naming ``--steps-per-period`` (a planetary case has no key for it),
    its value, f_max and the steps per mesh period (a multiple of ``n_planets``) that give
    n >= 10 there.

    Returns ``sweep.json``'s ``steps_resolution``: ``f_max_Hz``, ``steps_per_top_period_min``
    (n at the lowest speed), ``resolved`` (bool), ``steps_per_period_resolved`` (that
    suggestion)."""
    f_max = float(np.max(np.asarray(planetary_modes(model, stage).frequencies)))
    lo = float(np.min(np.asarray(f_mesh, dtype=float)))
    n_min = steps * lo / f_max
    need = n_planets * math.ceil(STEPS_PER_TOP_PERIOD * f_max / lo / n_planets)
    while need * lo / f_max < STEPS_PER_TOP_PERIOD:  # the same test as n's, rounding included
        need += n_planets
    resolved = bool(n_min >= STEPS_PER_TOP_PERIOD)
    if not resolved:
        warnings.warn(
            f"--steps-per-period = {steps}: time step under-resolved, n = {n_min:.3g} steps "
            f"per period of the stage's highest natural frequency {f_max:.4g} Hz at the lowest "
            f"speed's mesh frequency {lo:.4g} Hz (< {STEPS_PER_TOP_PERIOD}: the dynamic factor "
            f"comes out low); --steps-per-period >= {need} resolves it",
            CaseWarning, stacklevel=3)
    return {"f_max_Hz": f_max, "steps_per_top_period_min": n_min, "resolved": resolved,
            "steps_per_period_resolved": need}


def _dynamic_setup(form, case, slices=None):
    """(spec, the dynamic stage, its meshes, the model): ``slices`` per contact line (None: 1
    for spur gears, exact there, else the case's ``[mesh] slices``); the model
    :data:`MODEL`, or the 3D one for a helical stage whose supports hold it
    (:func:`~jaxgear.cli.planetary.spatial_model`; its constant mesh springs, in the lumped
    form, at two Gauss points across the face)."""
    spec = form.spec
    full = spec.stage(case)
    stage = spec.sharing_stage(full)
    spur = not case.pairs or float(case.pairs[0].helix_angle) == 0.0
    n = slices or (1 if spur else case.slices)
    meshes = spec.dynamic_meshes(case, n)
    model = spatial_model(spec, full)
    if model is None:
        return spec, stage, meshes, MODEL
    if not case.pairs:  # the lumped form's springs spread over the face, as the 3D K's
        meshes = ConstantMeshes(meshes.base_pitch, face_points=model.face_points)
    return spec, stage, meshes, model


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
) -> dict:
    """Sweep the input speeds ``speeds`` (rad/s, (s,), > 0) of a planetary case (module
    docstring) and write its files into ``out_dir``; returns ``sweep.json``'s content.

    ``sweep.json``: the keys of :func:`sweep_summary`, the Campbell diagram's file and
    ``ring_spectrum`` (the ring transducer at the worst speed)."""
    t0 = time.perf_counter()
    summary, (stage, meshes, run, ring, model) = sweep_summary(
        form, case, speeds, steps_per_period=steps_per_period, periods=periods,
        keep_periods=keep_periods, slices=slices,
    )
    spec = form.spec
    summary["campbell"] = campbell_section(
        case, spec, spec.stage(case), os.path.join(out_dir, "campbell.png")
    )["file"]
    summary["ring_spectrum"] = ring_spectrum(
        form, case, stage, meshes, run, summary["speed_of_max_rad_s"],
        os.path.join(out_dir, "ring_spectrum.png"), ring, model,
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
) -> tuple[dict, tuple]:
    """The sweep of :func:`planetary_sweep` without its files, spectrum and Campbell diagram:
    (``sweep.json``'s numbers, (the dynamic stage, its meshes, the run, the ring model)).

    Keys: ``speeds_rad_s`` (input), ``carrier_speeds_rad_s``, ``mesh_frequency_Hz`` (carrier
    frame), ``mesh_names`` (``sun-planet 1..N``, then ``ring-planet 1..N``),
    ``dynamic_factor_mesh`` (s, 2N: each mesh's largest force over the kept periods over the
    nominal T_s/(N r_bs)), ``dynamic_factor`` (the worst mesh per speed), ``k_gamma`` (dynamic
    load sharing per speed), their maxima and where, ``natural_frequencies_Hz`` (the sweep's model at
    the stage's constant mesh stiffness) and ``crossings``; ``steps_resolution``
    (:func:`step_resolution`, its ``CaseWarning`` before the sweep); ``ring_model`` (words) and
    ``ring``: the ring model of the sweep (``[planetary.ring]``: ``model``, and for a condensed ring
    ``body``, ``dynamics``, ``modes``); for a condensed ring ``ring_deflection_max_m`` per speed
    (the largest elastic ring displacement at a ring mesh over the kept periods, m) and its
    maximum ``max_ring_deflection_m``."""
    spec, stage, meshes, model = _dynamic_setup(form, case, slices)
    ring = spec.ring_model.dynamic_ring()
    run = planetary_run(form, case, steps_per_period, periods, keep_periods)
    speeds = np.asarray(speeds, dtype=float)
    f_mesh = spec.mesh_frequency(1.0)  # Hz per rad/s of the input
    resolution = step_resolution(model, spec.stage(case), speeds * f_mesh, run.steps_per_period,
                                 spec.n_planets)  # before the work: its warning first
    per_input = spec.speeds(1.0)
    carrier = speeds * per_input["carrier"]
    mesh_speed = speeds * spec.mesh_speed(1.0)
    r = _sweep(model, stage, meshes, run, carrier, mesh_speed, ring)
    df_s, df_r = (np.asarray(d) for d in r.dynamic_factors)
    per_mesh = np.concatenate([df_s, df_r], axis=1)  # (s, 2N)
    worst = per_mesh.max(axis=1)
    k_gamma = np.asarray(r.k_gamma)
    i = int(np.nanargmax(worst))
    n = spec.n_planets
    names = [f"sun-planet {k + 1}" for k in range(n)] + [f"ring-planet {k + 1}" for k in range(n)]
    f0 = np.asarray(planetary_modes(model, stage).frequencies)
    natural = f0[f0 > RIGID_SHARE * max(float(f0.max()), 1.0)]
    summary = {
        "case": case.name,
        "kind": "planetary",
        "model": MODEL_WORDS[type(model)],
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
        "max_dynamic_factor": float(worst[i]),
        "speed_of_max_rad_s": float(speeds[i]),
        "max_dynamic_factor_mesh": per_mesh.max(axis=0).tolist(),
        "max_k_gamma": float(k_gamma.max()),
        "result": np.asarray(r.result).astype(int).tolist(),
        "sun_torque_Nm": float(run.sun_torque),
        "nominal_mesh_force_N": float(np.asarray(r.static_force).reshape(-1)[0]),
        "steps_per_period": run.steps_per_period,
        "periods": run.periods,
        "keep_periods": run.keep_periods,
        "steps_resolution": resolution,
        "damping_ratio": float(run.damping_ratio),
        "natural_frequencies_Hz": natural.tolist(),
        "crossings": crossings(natural, f_mesh, speeds),
        "ring": spec.ring_model.summary(),
    }
    if spec.ring_model.flexible:
        w = np.max(np.abs(np.asarray(r.ring_deflection)), axis=(1, 2))
        summary["ring_deflection_max_m"] = w.tolist()
        summary["max_ring_deflection_m"] = float(w.max())
    summary["platform"] = {
        "device": str(jax.devices()[0].platform),
        "dtype": str(np.asarray(r.time).dtype),
        "python": platform.python_version(),
    }
    summary["notes"] = (
        "dynamic stage: the sun loaded by |T_s| and free in rotation, ring and carrier held; "
        "dynamic factor: each mesh's largest transverse force over the kept periods over the "
        "nominal T_s/(N r_bs) (pin errors included); k_gamma: the most loaded planet's sun-mesh "
        "force over the planets' mean, largest over the kept periods"
    )
    return summary, (stage, meshes, run, ring, model)


def _sweep(model, stage, meshes, run, carrier, mesh_speed, ring):
    """:func:`planetary_speed_sweep` when the ring is fixed (its mesh speed r_br |Ω|), else the
    same run vmapped with the mesh speed given; ``ring`` the ring model."""
    if math.isclose(float(mesh_speed[0]), float(stage.ring.base_radius) * abs(carrier[0]),
                    rel_tol=1e-12):
        return planetary_speed_sweep(model, stage, meshes, run, jnp.asarray(carrier), ring=ring)
    one = jax.vmap(lambda om, v: planetary_dynamics(model, stage, meshes, run, om, v,
                                                    ring=ring))
    return one(jnp.asarray(carrier), jnp.asarray(mesh_speed))


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
    """Each mesh's dynamic factor and the dynamic K_γ against the input speed, the mesh-order
    crossings of the natural frequencies as vertical lines; an under-resolved time step
    (``steps_resolution``) said in the title."""
    fig, ax = new_figure()
    s = np.asarray(summary["speeds_rad_s"])
    df = np.asarray(summary["dynamic_factor_mesh"])
    n = df.shape[1] // 2
    for j, name in enumerate(summary["mesh_names"]):
        ax.plot(s, df[:, j], "o-" if j < n else "s--", ms=3, lw=1.0, label=name)
    ax.plot(s, summary["k_gamma"], "^:", color="k", ms=3, lw=1.0, label="dynamic K_γ")
    styles = {1: "tab:red", 2: "tab:purple", 3: "tab:brown"}
    seen = set()
    for c in summary["crossings"]:
        k = c["order"]
        ax.axvline(c["speed_rad_s"], color=styles.get(k, "0.5"), lw=0.7, ls="-.",
                   label=None if k in seen else f"mesh order {k} × natural frequency")
        seen.add(k)
    ax.set_xlabel(f"{summary['speed_of']} speed (rad/s)")
    ax.set_ylabel("dynamic factor, K_γ (-)")
    res = summary.get("steps_resolution") or {}
    flag = ("" if res.get("resolved", True) else
            f"\ntime step under-resolved, dynamic factors low: "
            f"{res['steps_per_top_period_min']:.2g} steps per period of {res['f_max_Hz']:.0f} Hz"
            f"\n(--steps-per-period >= {res['steps_per_period_resolved']} resolves it)")
    ax.set_title(f"{case.name}: dynamic factor per mesh ({summary['model']}, "
                 f"{summary['ring_model']}){flag}", fontsize=10)
    ax.grid(alpha=0.3)
    legend_below_and_save(fig, ax, path, None)


def ring_spectrum(form, case, stage, meshes, run, speed: float, path: str,
                  ring=None, model=MODEL) -> dict:
    """The ring transducer (:func:`~jaxgear.dynamics.ring_transducer_signal`, at angle 0) at
    input ``speed`` over one whole turn of the carrier relative to the ring (z_r mesh periods,
    after the run's transient), its order spectrum (orders of that turn) drawn into ``path``;
    returns its keys: the mesh order's amplitude and the planet-pass sidebands'. ``ring``: the
    sweep's ring model (None: rigid); ``model`` its model kind."""
    spec = form.spec
    z_r = int(spec.teeth[2])
    w = spec.speeds(speed)
    rel = w["carrier"] - w["ring"]
    settle = run.periods - run.keep_periods
    one_turn = PlanetaryRun(
        run.sun_torque,
        steps_per_period=run.steps_per_period,
        periods=settle + z_r,
        keep_periods=z_r,
        damping_ratio=run.damping_ratio,
        tangential_pin_errors=run.tangential_pin_errors,
        radial_pin_errors=run.radial_pin_errors,
    )
    d = planetary_dynamics(model, stage, meshes, one_turn, jnp.asarray(w["carrier"]),
                           jnp.asarray(spec.mesh_speed(speed)),
                           ring=RigidRing() if ring is None else ring)
    theta = jnp.asarray(np.asarray(d.time) * rel)
    y = ring_transducer_signal(d.ring_mesh_forces, theta, stage.planet_angles)
    orders, amp = order_spectrum(y, run.steps_per_period * z_r)
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
    ax.set_title(f"{case.name}: ring transducer at {speed:.4g} rad/s (input), one carrier turn")
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
    }


def sweep_lines(case, s: dict) -> list[str]:
    """What ``jaxgear sweep`` prints for a planetary case."""
    i = int(np.argmax(s["dynamic_factor"]))
    worst = s["mesh_names"][int(np.argmax(s["dynamic_factor_mesh"][i]))]
    nat = ", ".join(f"{f:.4g}" for f in s["natural_frequencies_Hz"][:6])
    line = (
        f"{case.name}: {len(s['speeds_rad_s'])} input speeds, max dynamic factor "
        f"{s['max_dynamic_factor']:.4f} ({worst}) at {s['speed_of_max_rad_s']:.4g} rad/s, "
        f"max dynamic K_γ {s['max_k_gamma']:.4f}; {_ring_words(s)}"
        + f"; first natural frequencies {nat} Hz; "
        f"{sum(1 for v in s['result'] if v)} diverged; {s['elapsed_s']:.1f} s"
    )
    return [line]


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
    maximum, the largest dynamic K_γ. A bar over the two stages (unless ``args.quiet``)."""
    speeds = run_speeds(case)
    bar = tqdm(total=2, desc=f"jaxgear run {case.name}", disable=bool(args.quiet))
    bar.set_postfix_str(f"dynamic sweep, {speeds.size} speeds")
    sub = os.path.join(out, "sweep")
    os.makedirs(sub, exist_ok=True)
    sw = planetary_sweep(form, case, speeds, sub)
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
        "steps_per_period": sw["steps_per_period"],
        "steps_resolution": sw["steps_resolution"],
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
    line = (
        f"dynamic factor ({d['model']}, {len(d['speeds_rad_s'])} {d['speed_of']} speeds "
        f"{d['speeds_rad_s'][0]:.4g}–{d['speeds_rad_s'][-1]:.4g} rad/s): max "
        f"{d['max_dynamic_factor']:.4f} at {d['speed_of_max_rad_s']:.4g} rad/s, dynamic K_γ max "
        f"{d['max_k_gamma']:.4f}, {_ring_words(d)} ({d['files']})"
    )
    return [*planetary_lines(form, case, summary), line]
