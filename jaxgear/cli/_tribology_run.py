"""``jaxgear run``'s film and sliding loss along the path of contact, for a case with
``[lubricant]`` (:func:`jaxgear.tribology.mesh_tribology` on the run's modified exact-contact
quasi-static result): a pair's ``tribology.json``, ``tribology.csv`` (every loaded cell) and
``tribology.png`` (:func:`~jaxgear.cli.plots.path_of_contact_plot`: line load, film, λ, local
sliding loss and Blok's flash temperature along the path,
:func:`jaxgear.tribology.mesh_flash_temperature`); with the scuffing keys of ``[lubricant]``, the
contact temperature and the scuffing safety factors (:func:`jaxgear.tribology.mesh_scuffing`) in
the same files; with its micropitting keys, the micropitting safety factor of ISO/TS 6336-22
(:func:`jaxgear.tribology.mesh_micropitting`). A train's or a planetary stage's
meshes each write the pair's files as ``tribology_<mesh>.csv`` and ``.png``, and the whole its
efficiency (:func:`jaxgear.tribology.train_efficiency`,
:func:`jaxgear.tribology.planetary_efficiency`) into ``tribology.json`` and ``tribology.csv`` (a
row per mesh); a gearbox its stages' in series (:func:`jaxgear.tribology.gearbox_efficiency`)."""

from __future__ import annotations

import os

import numpy as np

from ..io import tribology_of, write_csv, write_json
from ..tribology import (
    mesh_flash_temperature,
    mesh_micropitting,
    mesh_scuffing,
    mesh_tribology,
    pitch_point_roll,
    planetary_efficiency,
    power_flow,
    train_efficiency,
)
from ._plots import path_of_contact_plot
from ._rating_sheet import oil_warning, verdict
from ._sweep_json import column_tag

__all__ = [
    "efficiency_run_line",
    "gearbox_tribology",
    "mesh_tribology_files",
    "planetary_tribology_outputs",
    "train_tribology_outputs",
    "tribology_outputs",
    "tribology_rating_lines",
    "tribology_run_line",
]


def tribology_outputs(case, out_dir: str, result) -> dict | None:
    """Film and loss of ``case``'s mesh from ``result`` (its quasi-static result at
    ``case.torque``); None without ``[lubricant]``. Returns the summary section."""
    inputs = tribology_of(case)
    if inputs is None:
        return None
    section, _ = mesh_tribology_files(
        case.pair, result, result.theta, inputs, case.torque, inputs.speed, case, out_dir,
        "tribology", case.name,
    )
    write_json(os.path.join(out_dir, "tribology.json"), section)
    return section


def mesh_tribology_files(pair, result, theta, inputs, torque, speed, case, out_dir: str,
                         stem: str, label: str) -> tuple[dict, object]:
    """One mesh's film, loss (and with the scuffing keys, flash temperature) from ``result``
    (a one-mesh result or a train's ``MeshResult``, at the positions ``theta``) at its driving
    ``torque`` (N·m) and ``speed`` (rad/s): ``<stem>.csv`` (every loaded cell) and
    ``<stem>.png`` written; returns (its section, the :class:`jaxgear.tribology.MeshTribology`)."""
    out = mesh_tribology(
        pair,
        result,
        inputs.lubricant,
        torque,
        speed,
        inputs.roughness,
        case.youngs_modulus,
        case.poisson_ratio,
        film=inputs.film,
        friction=inputs.friction,
    )
    section = {
        "film_formula": inputs.film.name,
        "friction": inputs.friction.name,
        "speed_rad_s": float(speed),
        "viscosity_at_oil_temperature_mm2_s": float(inputs.lubricant.kinematic_viscosity()) * 1e6,
        "dynamic_viscosity_Pa_s": float(inputs.lubricant.dynamic_viscosity),
        **out.summary(),
        "files": ["tribology.json", f"{stem}.csv", f"{stem}.png"],
    }
    loaded = np.asarray(out.loaded)
    theta = np.broadcast_to(np.asarray(theta)[:, None, None], loaded.shape)[loaded]
    cols = {
        "theta_rad": theta,
        "s_m": np.asarray(out.cell_s)[loaded],
        "line_load_N_per_m": np.asarray(out.line_load)[loaded],
        "entrainment_speed_m_s": np.asarray(out.entrainment_speed)[loaded],
        "sliding_speed_m_s": np.asarray(out.sliding_speed)[loaded],
        "max_pressure_Pa": np.asarray(out.max_pressure)[loaded],
        "central_film_m": np.asarray(out.central_film)[loaded],
        "minimum_film_m": np.asarray(out.minimum_film)[loaded],
        "specific_film": np.asarray(out.specific_film)[loaded],
        "local_loss_W_per_m": np.asarray(out.local_loss)[loaded],
    }
    if inputs.scuffing is None:
        # Blok's flash temperature along the path needs no scuffing limits: drawn and written
        # beside the film and the loss, with no safety factor
        flash = np.asarray(
            mesh_flash_temperature(pair, out, case.youngs_modulus, case.poisson_ratio)
        )[loaded]
        cols["flash_temperature_K"] = flash
        section["max_flash_temperature_K"] = float(flash.max()) if flash.size else 0.0
    else:
        scuff = mesh_scuffing(
            pair,
            result,
            out,
            inputs.lubricant,
            case.youngs_modulus,
            case.poisson_ratio,
            inputs.scuffing.limits,
            bulk=inputs.scuffing.bulk,
        )
        section["scuffing"] = {"bulk_temperature_rule": inputs.scuffing.bulk.name}
        section["scuffing"] |= scuff.summary()
        flash = np.asarray(scuff.flash_temperature)[loaded]
        cols["flash_temperature_K"] = flash
        cols["contact_temperature_C"] = np.asarray(scuff.contact_temperature)[loaded]
    if inputs.micropitting is not None:
        mp_in = inputs.micropitting
        mp = mesh_micropitting(
            pair,
            out,
            inputs.lubricant,
            inputs.roughness,
            case.youngs_modulus,
            case.poisson_ratio,
            mp_in.permissible,
            bulk_temperature=mp_in.bulk_temperature,
            lubrication_factor=mp_in.lubrication_factor,
        )
        section["micropitting"] = {
            "method": "ISO/TS 6336-22 with jaxgear's line loads at every loaded cell",
            "permissible_source": mp_in.source,
            "bulk_temperature_rule": "given"
            if mp_in.bulk_temperature is not None
            else "ts-6336-22",
            **mp.summary(),
        }
        cols["micropitting_specific_film"] = np.asarray(mp.specific_film)[loaded]
    write_csv(os.path.join(out_dir, f"{stem}.csv"), list(cols), list(cols.values()))
    path_of_contact_plot(
        os.path.join(out_dir, f"{stem}.png"),
        cols["s_m"],
        cols["line_load_N_per_m"],
        cols["central_film_m"],
        cols["minimum_film_m"],
        cols["specific_film"],
        cols["local_loss_W_per_m"],
        pitch=pitch_point_roll(pair),
        flash=flash,
        title=f"{label}: film, sliding loss and flash temperature along the path of contact "
        f"({inputs.film.name}, μ {section['friction_coefficient']:.4f}, {float(speed):g} rad/s)",
    )
    return section, out


def train_tribology_outputs(case, out_dir: str, result) -> dict | None:
    """A train's film and loss per mesh from its coupled quasi-static ``result`` (every mesh,
    at ``case.torque``) and its efficiency (:func:`jaxgear.tribology.train_efficiency`: the
    meshes' series power flow along the gears and shafts); None without ``[lubricant]``."""
    inputs = tribology_of(case)
    if inputs is None:
        return None
    at = case.replace(speed=inputs.speed)
    entries = []
    for k in range(len(case.pairs)):
        one = case.form.mesh_case(at, k)
        entries.append((case.pairs[k], result.meshes[k], result.theta, abs(one.torque),
                        abs(one.speed)))
    return _meshes_outputs(
        case, out_dir, inputs, entries,
        lambda outs: train_efficiency(outs, case.gears, case.shaft_of,
                                      input_power=case.torque * inputs.speed),
        "series power flow of the meshes along the gears and shafts (a chain: the product of "
        "the meshes' efficiencies)",
    )


def planetary_tribology_outputs(case, out_dir: str, results) -> dict | None:
    """A planetary stage's film and loss per mesh from each mesh's quasi-static result at one
    planet path's mean load (``results``, sun–planet then planet–ring, as
    :func:`jaxgear.cli.planetary.mesh_sections` solves them), each at its driving member's
    speed relative to the carrier, and the stage's efficiency
    (:func:`jaxgear.tribology.planetary_efficiency`: the rolling power in the carrier's frame,
    n_p paths per mesh); None without ``[lubricant]``."""
    inputs = tribology_of(case)
    if inputs is None:
        return None
    spec = case.form.spec
    at = case.replace(speed=inputs.speed)
    entries = []
    for k, r in enumerate(results):
        one = case.form.mesh_case(at, k)
        entries.append((case.pairs[k], r, r.theta, abs(one.torque), abs(one.speed)))
    member = spec.input.name.lower()
    p_in = abs(spec.torques(case.torque)[member] * spec.speeds(inputs.speed)[member])
    n_p = int(spec.n_planets)
    return _meshes_outputs(
        case, out_dir, inputs, entries,
        lambda outs: planetary_efficiency(outs, n_p, p_in),
        f"the meshes' rolling power in the carrier's frame, {n_p} planet paths each, in series "
        "(sun-planet, planet-ring); input power in the fixed frame",
    )


def _meshes_outputs(case, out_dir: str, inputs, entries, efficiency, method: str) -> dict:
    """Each mesh's files (:func:`mesh_tribology_files`, ``tribology_<mesh>.csv/.png``), the
    ``efficiency(outs)`` :class:`jaxgear.tribology.PowerFlow`, ``tribology.csv`` (one row per
    mesh) and ``tribology.json``; returns the summary section."""
    names = [case.mesh_name(k) for k in range(len(entries))]
    meshes, outs = {}, []
    for name, (pair, result, theta, torque, speed) in zip(names, entries, strict=True):
        stem = f"tribology_{column_tag(name)}"
        section, out = mesh_tribology_files(pair, result, theta, inputs, torque, speed, case,
                                            out_dir, stem, f"{case.name} {name}")
        meshes[name] = {"torque_Nm": float(torque)} | section
        outs.append(out)
    flow = efficiency(outs)
    overall = {"method": method} | flow.summary(names)
    write_csv(
        os.path.join(out_dir, "tribology.csv"),
        ["mesh", "torque_Nm", "speed_rad_s", "transmitted_power_W", "power_W", "loss_W",
         "efficiency", "friction_coefficient", "min_specific_film", "loss_factor_integrated"],
        [
            list(range(1, len(names) + 1)),
            [meshes[n]["torque_Nm"] for n in names],
            [meshes[n]["speed_rad_s"] for n in names],
            overall["transmitted_power_W"],
            overall["power_W"],
            overall["loss_W"],
            overall["efficiency_each"],
            [meshes[n]["friction_coefficient"] for n in names],
            [meshes[n]["min_specific_film"] for n in names],
            [meshes[n]["loss_factor_integrated"] for n in names],
        ],
    )
    section = {
        "film_formula": inputs.film.name,
        "friction": inputs.friction.name,
        "speed_rad_s": inputs.speed,
        "meshes": meshes,
        "overall": overall,
        "files": ["tribology.json", "tribology.csv",
                  *(f for n in names for f in meshes[n]["files"][1:])],
    }
    write_json(os.path.join(out_dir, "tribology.json"), section)
    return section


def gearbox_tribology(stages: list[dict], out_dir: str) -> dict | None:
    """A gearbox's efficiency from its stages' own ``tribology`` sections (``stages``: the
    gearbox summary's entries, each with its stage's ``summary``): the stages in series
    (:func:`jaxgear.tribology.power_flow`, as :func:`jaxgear.tribology.gearbox_efficiency`
    builds it), ``tribology.json`` and ``tribology.csv``
    (one row per stage) written; None unless every stage has a ``[lubricant]``."""
    found = [s["summary"].get("tribology") for s in stages]
    if not found or any(t is None for t in found):
        return None
    each = [t.get("overall", t) for t in found]  # a train's or a stage's overall; a pair's own
    # the stages in series from their runs' efficiencies and input powers: the flow
    # gearbox_efficiency builds of the stages' own MeshTribology or PowerFlow
    p_in = [t["input_power_W"] for t in each]
    flow = power_flow([t["efficiency"] for t in each], p_in, p_in[0])
    names = [s["stage"] for s in stages]
    section = {
        "method": "the stages in series, each stage's efficiency its own run's (its meshes' "
                  "sliding loss)",
        **flow.summary(names),
        "files": ["tribology.json", "tribology.csv"],
    }
    write_csv(
        os.path.join(out_dir, "tribology.csv"),
        ["stage", "transmitted_power_W", "power_W", "loss_W", "efficiency"],
        [list(range(1, len(names) + 1)), section["transmitted_power_W"], section["power_W"],
         section["loss_W"], section["efficiency_each"]],
    )
    write_json(os.path.join(out_dir, "tribology.json"), section)
    return section


def efficiency_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of a train's, a stage's or a gearbox's efficiency (nothing
    without one)."""
    if section is None:
        return []
    flow = section.get("overall", section)
    per = ", ".join(f"{n} {100 * e:.2f} %" for n, e in
                    zip(flow["names"], flow["efficiency_each"], strict=True))
    line = (
        f"efficiency {100 * flow['efficiency']:.2f} % (loss {flow['total_loss_W']:.4g} W of "
        f"{flow['input_power_W']:.4g} W; {per}){_hottest_mesh(section)} (tribology.json)"
    )
    return [line]


def _hottest_mesh(section: dict) -> str:
    """``, max flash temperature X K (mesh)``: Blok's largest flash temperature over a train's
    or a stage's meshes (``section["meshes"]``; their scuffing sections' where they have one),
    or "" without meshes."""
    flashes = {
        name: m.get("scuffing", m).get("max_flash_temperature_K")
        for name, m in section.get("meshes", {}).items()
    }
    flashes = {n: f for n, f in flashes.items() if f is not None}
    if not flashes:
        return ""
    name = max(flashes, key=flashes.get)
    return f", max flash temperature {flashes[name]:.1f} K ({name})"


def tribology_run_line(section: dict | None) -> list[str]:
    """What ``jaxgear run`` prints of the ``tribology`` section (nothing without one)."""
    if section is None:
        return []
    lines = []
    if "scuffing" in section:
        sc = section["scuffing"]
        lines.append(
            f"scuffing: max flash temperature {sc['max_flash_temperature_K']:.1f} K, θ_B,max "
            f"{sc['max_contact_temperature_C']:.1f} °C (θ_S {sc['scuffing_temperature_C']:.0f}), "
            f"S_B {sc['scuffing_safety_factor']:.2f}; θ_int {sc['integral_temperature_C']:.1f} °C "
            f"(θ_intS {sc['integral_scuffing_temperature_C']:.0f}), S_intS "
            f"{sc['integral_scuffing_safety_factor']:.2f} (tribology.json)"
        )
    if "micropitting" in section:
        mp = section["micropitting"]
        lines.append(
            f"micropitting (ISO/TS 6336-22): λ_GF,min {mp['min_specific_film']:.3f}, λ_GFP "
            f"{mp['permissible_specific_film']:.3f} ({mp['permissible_source']}), S_λ "
            f"{mp['safety_factor']:.2f}, θ_M {mp['bulk_temperature_C']:.1f} °C (tribology.json)"
        )
    # Blok's largest flash temperature: the scuffing line's where there is one, else here
    flash = (
        f", max flash temperature {section['max_flash_temperature_K']:.1f} K"
        if "max_flash_temperature_K" in section and "scuffing" not in section
        else ""
    )
    film = (
        f"film and loss ({section['film_formula']}, μ {section['friction_coefficient']:.4f} "
        f"{section['friction']}): min λ {section['min_specific_film']:.2f}, P_VZP "
        f"{section['mean_power_loss_W']:.1f} W, mesh efficiency "
        f"{100 * section['efficiency']:.2f} %, H_V {section['loss_factor_integrated']:.4f} "
        f"(Ohlendorf {section['loss_factor_ohlendorf']:.4f}){flash} (tribology.json)"
    )
    return [film, *lines]


#: the scuffing safety factors' minimum in rating.md: the limit itself (no minimum is read from
#: the case; the TSs' own recommendations were not available to check)
SCUFFING_MIN_SAFETY = 1.0


def tribology_rating_lines(section: dict | None, case=None) -> list[str]:
    """``rating.md``'s tribology lines (the scuffing and micropitting safety factors of
    ``jaxgear run``'s ``tribology`` section; nothing without them): the scuffing safety factors
    with their minimum (:data:`SCUFFING_MIN_SAFETY`) and verdicts, and the oil they are rated
    with, against the pitting rating's (``case``'s ``[rating] viscosity_40C_mm2_s``; a warning
    where they differ)."""
    if section is None or not ({"scuffing", "micropitting"} & set(section)):
        return []
    lines = ["", "## Scuffing and micropitting (jaxgear's line loads; docs/tribology.md)", ""]
    if "scuffing" in section:
        sc = section["scuffing"]
        s_min = SCUFFING_MIN_SAFETY
        lines += [
            "| safety factor | value | required minimum | verdict | method |",
            "|---|---|---|---|---|",
            f"| S_B | {sc['scuffing_safety_factor']:.2f} | S_Bmin = {s_min:g} | "
            f"{verdict(sc['scuffing_safety_factor'], s_min)} | flash temperature (ISO/TS "
            f"6336-20): θ_B,max {sc['max_contact_temperature_C']:.1f} °C, θ_S "
            f"{sc['scuffing_temperature_C']:.0f} °C, max θ_fl {sc['max_flash_temperature_K']:.1f}"
            " K |",
            f"| S_intS | {sc['integral_scuffing_safety_factor']:.2f} | S_intSmin = {s_min:g} | "
            f"{verdict(sc['integral_scuffing_safety_factor'], s_min)} | integral temperature "
            f"(ISO/TS 6336-21): θ_int {sc['integral_temperature_C']:.1f} °C, θ_intS "
            f"{sc['integral_scuffing_temperature_C']:.0f} °C |",
            "",
            f"The scuffing minimum {s_min:g} is the limit itself: no minimum is read from the "
            "case; agree one as for S_Hmin and S_Fmin.",
        ]
        lines += _oil_lines(case)
    if "micropitting" in section:
        mp = section["micropitting"]
        lines.append(
            f"- Micropitting (ISO/TS 6336-22): λ_GF,min {mp['min_specific_film']:.3f}, λ_GFP "
            f"{mp['permissible_specific_film']:.3f} ({mp['permissible_source']}), S_λ "
            f"{mp['safety_factor']:.2f} (θ_M {mp['bulk_temperature_C']:.1f} °C)"
        )
    return lines


def _oil_lines(case) -> list[str]:
    """The oil the scuffing is rated with (``[lubricant]``: ν₄₀, ν₁₀₀, θ_oil) and whether the
    pitting rating's Z_L uses the same (``[rating] viscosity_40C_mm2_s``; a warning where not)."""
    inputs = None if case is None else tribology_of(case)
    if inputs is None:
        return []
    oil = inputs.lubricant
    out = [
        "",
        f"Oil ([lubricant]): ν₄₀ {float(oil.viscosity_40) * 1e6:.6g} mm²/s, ν₁₀₀ "
        f"{float(oil.viscosity_100) * 1e6:.6g} mm²/s at θ_oil {float(oil.oil_temperature):.6g} °C.",
    ]
    nu40 = None if case.rating is None else case.rating.viscosity_40C_mm2_s
    if nu40 is not None:
        warning = oil_warning(nu40 * 1e-6, oil)
        out.append(warning or "The pitting rating's Z_L uses the same oil ([rating] "
                   "viscosity_40C_mm2_s).")
    return out
