"""``jaxgear run`` on a gearbox (a case of :class:`jaxgear.io.GearboxForm`): each stage's own
run (its case at the operating point carried from the previous stage: a planetary stage's load
sharing, meshes, modes and sweep, a pair's TE and load maps, and each stage's ``[rating]``: every
mesh of every rated stage, at the carried point) into ``stage<k>/``, then the whole
chain's torsional natural frequencies (:func:`jaxgear.gearbox_modes`) with the stage that holds
most of each mode's kinetic energy, into ``summary.json`` and ``modes.json``."""

from __future__ import annotations

import os

import numpy as np

from .. import gearbox_modes
from ..io import write_json

__all__ = ["chain_modes", "gearbox_run_files", "gearbox_run_lines", "least_safety"]

#: a mode below this fraction of the highest frequency is the free chain's rigid-body mode
RIGID = 1e-6


def chain_modes(form) -> list[dict]:
    """The chain's modes: ``frequency_Hz``, ``type`` ("rigid body", or ``stage<k>``: the stage
    with the largest share of the mode's kinetic energy) and ``stage_energy`` (the shares)."""
    chain = form.torsional()
    modes = gearbox_modes(chain)
    f = np.asarray(modes.frequencies)
    shares = np.asarray(modes.stage_energy)
    rows = []
    for j, fj in enumerate(f):
        rigid = fj < RIGID * f[-1]
        rows.append(
            {
                "frequency_Hz": float(fj),
                "type": "rigid body" if rigid else f"stage{int(np.argmax(shares[:, j])) + 1}",
                "stage_energy": [float(v) for v in shares[:, j]],
            }
        )
    return rows


def gearbox_run_files(form, case, out: str, args, complete: bool, run_stage) -> dict:
    """The stages' runs (``run_stage(stage_case, folder, args, None)``: ``jaxgear run``'s work
    on one case) into ``out/stage<k>``, then the chain's modes; returns the summary."""
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
    modes = chain_modes(form)
    write_json(os.path.join(out, "modes.json"), {"case": case.name, "torsional_chain": modes})
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
    }
    write_json(os.path.join(out, "summary.json"), result)
    return result


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
    lines.append(
        "torsional chain: "
        + ", ".join(f"{m['frequency_Hz']:.4g} Hz ({m['type']})" for m in elastic[:6])
        + (" ..." if len(elastic) > 6 else "")
        + " (modes.json)"
    )
    return lines
