"""The ``[scene]`` table of a case and the ``jaxgear sweep`` command (docs/dynamics.md).

``[scene]`` selects and parameterises the dynamic model (units in key names, SI after parsing):

.. code-block:: toml

    [scene]
    model = "torsional"                  # or "lumped3d" (shafts + bearings, see docs/dynamics.md)
    reduction = "none"                   # or "relative": the 1-DOF relative approach
    pinion_inertia_kg_m2 = 2.4e-4        # default: solid disc, tip radius × face width × density
    gear_inertia_kg_m2 = 2.3e-3
    motor_inertia_kg_m2 = 1e-2           # optional, needs motor_shaft_stiffness_Nm_per_rad
    motor_shaft_stiffness_Nm_per_rad = 2e4
    load_inertia_kg_m2 = 5e-2            # optional, needs load_shaft_stiffness_Nm_per_rad
    load_shaft_stiffness_Nm_per_rad = 5e4
    [scene.damping]
    model = "composite"                  # "composite" (2.36) | "modal" (2.35) | "rayleigh" (2.34) | "none"
    mesh_ratio = 0.07                    # composite: ξ_i = mesh_ratio e_i + structure_ratio (1 − e_i)
    structure_ratio = 0.01
    ratio = 0.05                         # modal: one ξ for every mode
    alpha_per_s = 0.0                    # rayleigh: C = α M + β K̄
    beta_s = 0.0
    [scene.integration]
    solver = "newmark"                   # or a diffrax solver: tsit5, dopri5, kvaerno5, ...
    contact = "exact"                    # or "smooth" (width: [mesh] smooth_width_um)
    steps_per_period = 64
    periods = 60
    keep_periods = 4
    rtol = 1e-6                          # diffrax PID controller (scaled state)
    atol = 1e-6
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import os
import platform
import time
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # importing this module stays free of JAX (the CLI builds its parser early)
    from ._case import Case

__all__ = [
    "SceneSpec",
    "add_sweep_parser",
    "build_dynamic_model",
    "parse_scene",
    "run_sweep",
    "sweep_case",
]

_SCENE_KEYS = {"model", "reduction", "pinion_inertia_kg_m2", "gear_inertia_kg_m2",
               "motor_inertia_kg_m2", "motor_shaft_stiffness_Nm_per_rad", "load_inertia_kg_m2",
               "load_shaft_stiffness_Nm_per_rad", "damping", "integration", "pinion_mass_kg",
               "gear_mass_kg", "pinion_shaft", "gear_shaft"}
_SHAFT_KEYS = {"length_mm", "diameter_mm", "gear_position_mm", "torque_position_mm", "elements",
               "bearings"}
_BEARING_KEYS = {"position_mm", "radial_N_per_um", "axial_N_per_um", "tilt_Nm_per_rad"}
_DAMPING_KEYS = {"model", "ratio", "alpha_per_s", "beta_s", "mesh_ratio", "structure_ratio"}
_INTEGRATION_KEYS = {"solver", "contact", "steps_per_period", "periods", "keep_periods", "rtol",
                     "atol"}


@dataclasses.dataclass(frozen=True)
class SceneSpec:
    """A validated ``[scene]`` table (SI units; ``None``: derived default)."""

    model: str = "torsional"
    reduction: str = "none"
    pinion_inertia: float | None = None
    gear_inertia: float | None = None
    motor_inertia: float | None = None
    motor_shaft: float | None = None
    load_inertia: float | None = None
    load_shaft: float | None = None
    damping_model: str = "composite"
    damping_ratio: float = 0.05
    rayleigh_alpha: float = 0.0
    rayleigh_beta: float = 0.0
    mesh_ratio: float = 0.07
    structure_ratio: float = 0.01
    solver: str = "newmark"
    contact: str = "exact"
    steps_per_period: int = 64
    periods: int = 60
    keep_periods: int = 4
    rtol: float = 1e-6
    atol: float = 1e-6
    pinion_mass: float | None = None
    gear_mass: float | None = None
    pinion_shaft: object = None  # ShaftSpec (lumped3d)
    gear_shaft: object = None


def _parse_shaft(table, where: str):
    from ._dyn_lumped import Bearing, ShaftSpec

    if not isinstance(table, dict):
        raise ValueError(f"[{where}] must be a table")
    _unknown(table, _SHAFT_KEYS, f"[{where}] ")
    for key in ("length_mm", "diameter_mm", "gear_position_mm", "bearings"):
        if key not in table:
            raise ValueError(f"missing required key [{where}] {key}")
    length = _number(table, "length_mm", where) * 1e-3
    diameter = _number(table, "diameter_mm", where) * 1e-3
    gear_z = _number(table, "gear_position_mm", where, nonneg=True) * 1e-3
    torque_z = (_number(table, "torque_position_mm", where, nonneg=True) * 1e-3
                if "torque_position_mm" in table else 0.0)
    elements = _number(table, "elements", where, integer=True) if "elements" in table else 4
    bearings = table["bearings"]
    if not isinstance(bearings, list) or not bearings:
        raise ValueError(f"[{where}] bearings must be a non-empty list of tables, e.g. "
                         "[{ position_mm = 0.0, radial_N_per_um = 200.0 }]")
    out = []
    for i, b in enumerate(bearings):
        w = f"{where}.bearings[{i}]"
        if not isinstance(b, dict):
            raise ValueError(f"[{w}] must be a table")
        _unknown(b, _BEARING_KEYS, f"[{w}] ")
        if "position_mm" not in b:
            raise ValueError(f"missing required key [{w}] position_mm")
        out.append(Bearing(
            z=_number(b, "position_mm", w, nonneg=True) * 1e-3,
            radial=_number(b, "radial_N_per_um", w, nonneg=True) * 1e6 if "radial_N_per_um" in b else 2e8,
            axial=_number(b, "axial_N_per_um", w, nonneg=True) * 1e6 if "axial_N_per_um" in b else 0.0,
            tilt=_number(b, "tilt_Nm_per_rad", w, nonneg=True) if "tilt_Nm_per_rad" in b else 0.0))
    for name, z in (("gear_position_mm", gear_z), ("torque_position_mm", torque_z),
                    *((f"bearings[{i}].position_mm", b.z) for i, b in enumerate(out))):
        if z > length * (1 + 1e-12):
            raise ValueError(f"[{where}] {name} = {z * 1e3:g} is beyond the shaft length "
                             f"{length * 1e3:g} mm")
    if not any(b.axial > 0 for b in out):
        raise ValueError(f"[{where}] needs an axial stiffness on at least one bearing "
                         "(axial_N_per_um > 0)")
    if sum(b.radial > 0 for b in out) < 2 and not any(b.tilt > 0 for b in out):
        raise ValueError(f"[{where}] needs two radial bearings (or a tilt stiffness) to hold "
                         "the shaft")
    return ShaftSpec(length=length, diameter=diameter, gear_z=gear_z, bearings=tuple(out),
                     torque_z=torque_z, elements=elements)


def _unknown(table: dict, allowed: set, where: str) -> None:
    for key in table:
        if key not in allowed:
            raise ValueError(f"unknown key {where}{key!r} in case file: allowed {sorted(allowed)}")


def _number(table, key, where, *, positive=True, nonneg=False, integer=False, upper=None):
    v = table[key]
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise ValueError(f"[{where}] {key} = {v!r} must be a finite number")
    if integer and int(v) != v:
        raise ValueError(f"[{where}] {key} = {v!r} must be an integer")
    if positive and not nonneg and not v > 0:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed > 0")
    if nonneg and not v >= 0:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed >= 0")
    if upper is not None and not v <= upper:
        raise ValueError(f"[{where}] {key} = {v!r} is out of range: allowed <= {upper}")
    return int(v) if integer else float(v)


def parse_scene(table: dict | None) -> SceneSpec:
    """Validate a ``[scene]`` table (``None`` or ``{}``: the defaults).

    Raises:
        ValueError: unknown keys (named), wrong types, values out of range, inconsistent inputs.
    """
    from ._dynamics import DIFFRAX_SOLVERS

    table = {} if table is None else table
    if not isinstance(table, dict):
        raise ValueError("[scene] must be a table")
    _unknown(table, _SCENE_KEYS, "[scene] ")
    kw: dict = {}
    model = table.get("model", "torsional")
    if model not in ("torsional", "lumped3d"):
        raise ValueError(f"[scene] model = {model!r}: allowed 'torsional', 'lumped3d'")
    if model == "lumped3d":
        for key in ("pinion_shaft", "gear_shaft"):
            if key not in table:
                raise ValueError(f"[scene] model = 'lumped3d' needs a [scene.{key}] table")
            kw[key] = _parse_shaft(table[key], f"scene.{key}")
        for key in ("motor_inertia_kg_m2", "load_inertia_kg_m2", "motor_shaft_stiffness_Nm_per_rad",
                    "load_shaft_stiffness_Nm_per_rad"):
            if key in table:
                raise ValueError(f"[scene] {key} is for model = 'torsional' (lumped3d: the torque "
                                 "acts at the shafts' torque_position_mm)")
        if table.get("reduction", "none") != "none":
            raise ValueError("[scene] reduction applies to model = 'torsional' only")
    else:
        for key in ("pinion_shaft", "gear_shaft", "pinion_mass_kg", "gear_mass_kg"):
            if key in table:
                raise ValueError(f"[scene] {key} is for model = 'lumped3d'")
    for key, field in (("pinion_mass_kg", "pinion_mass"), ("gear_mass_kg", "gear_mass")):
        if key in table:
            kw[field] = _number(table, key, "scene")
    reduction = table.get("reduction", "none")
    if reduction not in ("none", "relative"):
        raise ValueError(f"[scene] reduction = {reduction!r}: allowed 'none', 'relative'")
    kw.update(model=model, reduction=reduction)
    names = {"pinion_inertia_kg_m2": "pinion_inertia", "gear_inertia_kg_m2": "gear_inertia",
             "motor_inertia_kg_m2": "motor_inertia",
             "motor_shaft_stiffness_Nm_per_rad": "motor_shaft",
             "load_inertia_kg_m2": "load_inertia", "load_shaft_stiffness_Nm_per_rad": "load_shaft"}
    for key, field in names.items():
        if key in table:
            kw[field] = _number(table, key, "scene")
    for side in ("motor", "load"):
        if (f"{side}_inertia" in kw) != (f"{side}_shaft" in kw):
            raise ValueError(f"[scene] {side}_inertia_kg_m2 and {side}_shaft_stiffness_Nm_per_rad "
                             "go together: give both or neither")
        if reduction == "relative" and f"{side}_inertia" in kw:
            raise ValueError(f"[scene] reduction = 'relative' is for a rigid pinion-gear pair: "
                             f"remove {side}_inertia_kg_m2 or set reduction = 'none'")
    d = table.get("damping", {})
    if not isinstance(d, dict):
        raise ValueError("[scene.damping] must be a table")
    _unknown(d, _DAMPING_KEYS, "[scene.damping] ")
    dm = d.get("model", "composite")
    if dm not in ("composite", "modal", "rayleigh", "none"):
        raise ValueError(f"[scene.damping] model = {dm!r}: allowed 'composite', 'modal', "
                         "'rayleigh', 'none'")
    kw["damping_model"] = dm
    for key, field in (("ratio", "damping_ratio"), ("mesh_ratio", "mesh_ratio"),
                       ("structure_ratio", "structure_ratio")):
        if key in d:
            kw[field] = _number(d, key, "scene.damping", nonneg=True, upper=1.0)
    for key, field in (("alpha_per_s", "rayleigh_alpha"), ("beta_s", "rayleigh_beta")):
        if key in d:
            kw[field] = _number(d, key, "scene.damping", nonneg=True)
    g = table.get("integration", {})
    if not isinstance(g, dict):
        raise ValueError("[scene.integration] must be a table")
    _unknown(g, _INTEGRATION_KEYS, "[scene.integration] ")
    solver = g.get("solver", "newmark")
    if solver != "newmark" and solver not in DIFFRAX_SOLVERS:
        raise ValueError(f"[scene.integration] solver = {solver!r}: allowed 'newmark', "
                         f"{', '.join(repr(s) for s in DIFFRAX_SOLVERS)}")
    contact = g.get("contact", "exact")
    if contact not in ("exact", "smooth"):
        raise ValueError(f"[scene.integration] contact = {contact!r}: allowed 'exact', 'smooth'")
    kw.update(solver=solver, contact=contact)
    for key, lo in (("steps_per_period", 4), ("periods", 2), ("keep_periods", 2)):
        if key in g:
            v = _number(g, key, "scene.integration", integer=True)
            if v < lo:
                raise ValueError(f"[scene.integration] {key} = {v} is out of range: allowed >= {lo}")
            kw[key] = v
    if kw.get("keep_periods", 4) > kw.get("periods", 60):
        raise ValueError("[scene.integration] keep_periods must be <= periods")
    for key in ("rtol", "atol"):
        if key in g:
            kw[key] = _number(g, key, "scene.integration")
    return SceneSpec(**kw)


def build_dynamic_model(case: Case, spec: SceneSpec | None = None, *, slices: int | None = None):
    """The :class:`~jaxgear.DynamicModel` of a case and its scene (default: ``[scene]``).

    Inertias default to solid discs of the tip radius and the member's face width with the case
    density. Returns (model, spec).
    """
    from ._dyn_scene import Damping, TorsionalDynamics, disc_inertia
    from ._dynamics import dynamic_model

    if spec is None:
        spec = parse_scene(case.raw.get("scene"))
    pair = case.pair
    mesh = case.mesh_model(slices=slices)
    i1 = spec.pinion_inertia or disc_inertia(case.density, pair.tip_radii[0], pair.pinion.face_width)
    i2 = spec.gear_inertia or disc_inertia(case.density, pair.tip_radii[1], pair.gear.face_width)
    if spec.model == "lumped3d":
        from ._dyn_lumped import lumped_pair

        body = []
        for r, b, m, ip in ((pair.tip_radii[0], pair.pinion.face_width, spec.pinion_mass, i1),
                            (pair.tip_radii[1], pair.gear.face_width, spec.gear_mass, i2)):
            m = m or case.density * math.pi * r * r * b
            body.append((m, (ip / 2 + m * b * b / 12, ip)))  # disc: I_d = I_p/2 + m b²/12
        scene = lumped_pair(pair, mesh, spec.pinion_shaft, spec.gear_shaft,
                            masses=(body[0][0], body[1][0]), inertias=(body[0][1], body[1][1]),
                            youngs_modulus=case.youngs_modulus, poisson_ratio=case.poisson_ratio,
                            density=case.density)
    else:
        has_m, has_l = spec.motor_inertia is not None, spec.load_inertia is not None
        scene = TorsionalDynamics(mesh, i1, i2, spec.motor_inertia or 1.0, spec.load_inertia or 1.0,
                                  spec.motor_shaft or 1.0, spec.load_shaft or 1.0,
                                  has_motor=has_m, has_load=has_l)
        if spec.reduction == "relative":
            scene = scene.reduced()
    damping = Damping(spec.damping_model, ratio=spec.damping_ratio, alpha=spec.rayleigh_alpha,
                      beta=spec.rayleigh_beta, mesh_ratio=spec.mesh_ratio,
                      structure_ratio=spec.structure_ratio)
    model = dynamic_model(scene, case.modifications, case.torque, damping,
                          positions_per_pitch=spec.steps_per_period)
    return model, spec


def _parse_speeds(text: str) -> np.ndarray:
    parts = text.split(":")
    if len(parts) != 3:
        raise ValueError(f"--speeds {text!r}: expected START:STOP:N (pinion rad/s, N points)")
    try:
        a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
    except ValueError:
        raise ValueError(f"--speeds {text!r}: START and STOP must be numbers, N an integer") from None
    if not (a > 0 and b > a and n >= 2):
        raise ValueError(f"--speeds {text!r}: need 0 < START < STOP and N >= 2")
    return np.linspace(a, b, n)


def _clean(values) -> list:
    return [float(v) if np.isfinite(v) else None for v in np.asarray(values, dtype=float)]


def _critical(model, s_max: float, n_modes: int = 3, harmonics=(1, 2, 3)) -> list[dict]:
    omega = np.asarray(model.modes.omega)
    rigid = np.asarray(model.modes.rigid)
    energy = np.asarray(model.modes.mesh_energy)
    z1 = 2 * math.pi / float(model.mesh.mesh_period_angle)
    out = []
    # the modes the mesh excites: the largest strain-energy shares in the mesh (seed Tab. IV-8)
    elastic = [i for i in range(omega.size) if not rigid[i] and energy[i] >= 0.05]
    modes = sorted(sorted(elastic, key=lambda i: -energy[i])[:n_modes])
    for i in modes:
        for h in harmonics:
            sp = omega[i] / (z1 * h)
            if sp <= s_max * 1.05:
                out.append({"mode": int(i), "harmonic": int(h), "speed_rad_s": float(sp),
                            "frequency_Hz": float(omega[i] / (2 * math.pi)),
                            "mesh_energy_share": float(energy[i])})
    return out


def sweep_case(case: Case, speeds, out_dir: str, *, direction: str = "independent",
               solver: str | None = None, contact: str | None = None, periods: int | None = None,
               steps_per_period: int | None = None, keep_periods: int | None = None,
               slices: int | None = None, show_progress: bool = True) -> dict:
    """Speed sweep of a case's scene; writes ``sweep.json``, ``dynamic_factor.png`` and
    ``campbell.png`` to ``out_dir`` (atomically) and returns the JSON dict."""
    import jax
    from tqdm.auto import tqdm

    from ._dynamics import speed_sweep
    from ._util import atomic_open

    spec = parse_scene(case.raw.get("scene"))
    over = {k: v for k, v in dict(solver=solver, contact=contact, periods=periods,
                                  steps_per_period=steps_per_period,
                                  keep_periods=keep_periods).items() if v is not None}
    spec = dataclasses.replace(spec, **over)
    if spec.keep_periods > spec.periods:
        raise ValueError(f"keep_periods = {spec.keep_periods} must be <= periods = {spec.periods}")
    if direction not in ("independent", "up", "down", "both"):
        raise ValueError(f"--direction {direction!r}: allowed independent, up, down, both")
    speeds = np.asarray(speeds, dtype=float)
    t0 = time.perf_counter()
    model, spec = build_dynamic_model(case, spec, slices=slices)
    n_dirs = 2 if direction == "both" else 1
    bar = tqdm(total=n_dirs * speeds.size, desc=f"jaxgear sweep {case.name}", unit="speed",
               disable=not show_progress)
    last = [0]

    def progress(n):
        bar.update(n - last[0] if n >= last[0] else n)
        last[0] = n

    chunk = max(1, min(32, -(-speeds.size // 10)))
    res = speed_sweep(model, speeds, direction=direction, chunk_size=chunk, progress=progress,
                      solver=spec.solver, contact=spec.contact, width=case.smooth_width,
                      steps_per_period=spec.steps_per_period, periods=spec.periods,
                      keep_periods=spec.keep_periods, rtol=spec.rtol, atol=spec.atol)
    jax.block_until_ready(res)
    bar.close()
    elapsed = time.perf_counter() - t0
    from ._dynamics import DYNAMICS_RESULTS

    r = res.results
    omega = np.asarray(model.modes.omega)
    summary = {
        "case": case.name, "model": spec.model, "reduction": spec.reduction,
        "solver": spec.solver, "contact": spec.contact, "direction": direction,
        "steps_per_period": spec.steps_per_period, "periods": spec.periods,
        "keep_periods": spec.keep_periods, "damping": spec.damping_model,
        "torque_Nm": case.torque, "static_mesh_force_N": float(model.static_force),
        "mesh_stiffness_mean_N_per_m": float(model.mesh_stiffness_mean),
        "natural_frequencies_Hz": _clean(omega / (2 * math.pi)),
        "mesh_energy_share": _clean(model.modes.mesh_energy),
        "modal_energy_parts": list(model.modes.parts),
        "modal_energy": [_clean(row) for row in np.asarray(model.modes.energy)],
        "critical_speeds": _critical(model, float(speeds.max())),
        "speeds_rad_s": _clean(speeds),
        "mesh_frequency_Hz": _clean(r.mesh_frequency),
        "dynamic_factor": _clean(r.dynamic_factor),
        "dynamic_factor_tooth": _clean(r.dynamic_factor_tooth),
        "te_rms_m": _clean(r.te_rms),
        "te_mean_m": _clean(r.te_mean),
        "contact_loss": _clean(r.contact_loss),
        "periodicity": _clean(r.periodicity),
        "result": [int(v) for v in np.asarray(r.result)],
        "bearing_names": list(getattr(model.scene, "reaction_names", ())),
        "bearing_force_max_N": [_clean(row) for row in np.asarray(r.bearing_force_max)],
        "bearing_force_static_N": _clean(np.asarray(r.bearing_force_static)[0])
        if np.asarray(r.bearing_force_static).size else [],
        "result_messages": {str(k): v for k, v in DYNAMICS_RESULTS.items()},
        "elapsed_s": elapsed,
        "platform": {"jax": jax.__version__, "device": str(jax.devices()[0].platform),
                     "devices": len(jax.local_devices()), "python": platform.python_version()},
    }
    if res.down is not None:
        d = res.down
        summary.update({
            "dynamic_factor_down": _clean(d.dynamic_factor),
            "dynamic_factor_tooth_down": _clean(d.dynamic_factor_tooth),
            "te_rms_m_down": _clean(d.te_rms),
            "contact_loss_down": _clean(d.contact_loss),
            "result_down": [int(v) for v in np.asarray(d.result)],
        })
    os.makedirs(out_dir, exist_ok=True)
    with atomic_open(os.path.join(out_dir, "sweep.json"), "w") as f:
        json.dump(summary, f, indent=2)
    _plots(summary, out_dir, z1=case.pair.pinion.teeth)
    return summary


def _plots(summary: dict, out_dir: str, z1: int) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ._util import atomic_open

    def save(fig, name):
        with atomic_open(os.path.join(out_dir, name), "wb") as f:
            fig.savefig(f, format="png", dpi=120)
        plt.close(fig)

    sp = np.asarray(summary["speeds_rad_s"], dtype=float)
    nan = lambda v: np.asarray([np.nan if x is None else x for x in v], dtype=float)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    label = {"independent": "from static equilibrium", "up": "sweep up", "down": "sweep down",
             "both": "sweep up"}[summary["direction"]]
    df = nan(summary["dynamic_factor"])
    ax.plot(sp, df, "-", color="C0", label=f"mesh force, {label}")
    ax.plot(sp, nan(summary["dynamic_factor_tooth"]), ":", color="C0", lw=1, label="per tooth")
    if "dynamic_factor_down" in summary:
        ax.plot(sp, nan(summary["dynamic_factor_down"]), "--", color="C3", label="mesh force, sweep down")
    loss = nan(summary["contact_loss"]) > 0
    if loss.any():
        ax.plot(sp[loss], df[loss], "o", ms=3, color="C1", label="contact loss")
    bad = np.asarray(summary["result"]) != 0
    if bad.any():
        ax.plot(sp[bad], np.ones(bad.sum()), "x", color="k", label="diverged (see result)")
    for c in summary["critical_speeds"]:
        if sp.min() <= c["speed_rad_s"] <= sp.max():
            ax.axvline(c["speed_rad_s"], color="0.5", ls="--", lw=0.8)
            ax.annotate(f"mode {c['mode']} × H{c['harmonic']}", (c["speed_rad_s"], 1.0),
                        rotation=90, fontsize=7, color="0.4", va="bottom", ha="right")
    ax.set_xlabel("pinion speed (rad/s)")
    ax.set_ylabel("dynamic factor (max / static mesh force)")
    ax.set_title(f"{summary['case']}: {summary['model']} model, {summary['solver']}, "
                 f"{summary['contact']} contact")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, "dynamic_factor.png")

    fig, ax = plt.subplots(figsize=(7, 5))
    s_line = np.linspace(0, sp.max() * 1.05, 50)
    freqs = [f for f, e in zip(nan(summary["natural_frequencies_Hz"]),
                               nan(summary["mesh_energy_share"]), strict=True) if f > 0 and e >= 0.05]
    for h in range(1, 5):
        ax.plot(s_line, h * s_line * z1 / (2 * math.pi), color=f"C{h - 1}", label=f"mesh H{h}")
    for f in freqs:
        ax.axhline(f, color="k", ls="--", lw=0.8)
    for c in summary["critical_speeds"]:
        ax.plot(c["speed_rad_s"], c["frequency_Hz"], "o", color="C3")
    if freqs:
        ax.set_ylim(0, 1.3 * max(max(freqs), sp.max() * z1 / (2 * math.pi)))
    ax.set_xlim(0, s_line[-1])
    ax.set_xlabel("pinion speed (rad/s)")
    ax.set_ylabel("frequency (Hz)")
    ax.set_title("Campbell diagram: mesh harmonics vs modes with ≥ 5 % mesh energy (dashed)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8)
    save(fig, "campbell.png")


_SOLVER_NAMES = ["newmark", "tsit5", "dopri5", "dopri8", "bosh3", "heun", "midpoint", "ralston",
                 "euler", "kvaerno3", "kvaerno4", "kvaerno5", "implicit_euler"]


def add_sweep_parser(subparsers) -> argparse.ArgumentParser:
    """Register ``jaxgear sweep`` on an argparse subparsers object."""
    s = subparsers.add_parser("sweep", help="dynamic factor vs speed (Newmark/diffrax, [scene] table)")
    s.add_argument("case", help="TOML case file or embedded case name")
    s.add_argument("--speeds", required=True, help="START:STOP:N pinion speeds (rad/s)")
    s.add_argument("--direction", default="independent", choices=["independent", "up", "down", "both"],
                   help="independent speeds (vmap) or continuation sweeps (default: independent)")
    s.add_argument("--solver", choices=_SOLVER_NAMES,
                   help="time integrator (default: [scene.integration] solver, else newmark)")
    s.add_argument("--contact", choices=["exact", "smooth"], help="contact law")
    s.add_argument("--periods", type=int, help="mesh periods per speed")
    s.add_argument("--keep-periods", type=int, help="steady-state periods kept")
    s.add_argument("--steps-per-period", type=int, help="time steps per mesh period")
    s.add_argument("--slices", type=int, help="override [mesh] slices")
    s.add_argument("--out", help="output folder (default: jaxgear-out/<case>/sweep/)")
    s.add_argument("--quiet", action="store_true", help="no progress bar")
    return s


def run_sweep(args) -> int:
    """Run ``jaxgear sweep`` (float64 must already be on: the CLI does it). Returns 0."""
    from ._case import load_case

    case = load_case(args.case)
    speeds = _parse_speeds(args.speeds)
    out = args.out or os.path.join("jaxgear-out", case.name, "sweep")
    s = sweep_case(case, speeds, out, direction=args.direction, solver=args.solver,
                   contact=args.contact, periods=args.periods, steps_per_period=args.steps_per_period,
                   keep_periods=args.keep_periods, slices=args.slices, show_progress=not args.quiet)
    df = np.asarray([np.nan if v is None else v for v in s["dynamic_factor"]])
    i = int(np.nanargmax(df)) if np.isfinite(df).any() else 0
    n_bad = sum(1 for v in s["result"] if v)
    print(f"{case.name}: {len(df)} speeds, max dynamic factor {df[i]:.3f} at "
          f"{s['speeds_rad_s'][i]:.1f} rad/s; first natural frequencies "
          f"{', '.join(f'{f:.0f}' for f in [f for f in s['natural_frequencies_Hz'] if f][:6])} Hz; "
          f"{n_bad} diverged; {s['elapsed_s']:.1f} s")
    print(f"written to {out}/")
    return 0
