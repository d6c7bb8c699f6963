"""``jaxgear run``'s film and sliding loss along the path of contact, for a pair case with
``[lubricant]`` (:func:`jaxgear.tribology.mesh_tribology` on the run's modified exact-contact
quasi-static result): ``tribology.json``, ``tribology.csv`` (every loaded cell) and
``tribology.png`` (:func:`~jaxgear.cli.plots.path_of_contact_plot`); with the scuffing keys of
``[lubricant]``, Blok's flash temperature along the path and the scuffing safety factors
(:func:`jaxgear.tribology.mesh_scuffing`) in the same files; with its micropitting keys, the
micropitting safety factor of ISO/TS 6336-22 (:func:`jaxgear.tribology.mesh_micropitting`)."""

from __future__ import annotations

import os

import numpy as np

from ..io import tribology_of, write_csv, write_json
from ..tribology import mesh_micropitting, mesh_scuffing, mesh_tribology, pitch_point_roll
from ._plots import path_of_contact_plot

__all__ = ["tribology_outputs", "tribology_rating_lines", "tribology_run_line"]


def tribology_outputs(case, out_dir: str, result) -> dict | None:
    """Film and loss of ``case``'s mesh from ``result`` (its quasi-static result at
    ``case.torque``); None without ``[lubricant]``. Returns the summary section."""
    inputs = tribology_of(case)
    if inputs is None:
        return None
    pair = case.pair
    out = mesh_tribology(
        pair,
        result,
        inputs.lubricant,
        case.torque,
        inputs.speed,
        inputs.roughness,
        case.youngs_modulus,
        case.poisson_ratio,
        film=inputs.film,
        friction=inputs.friction,
    )
    section = {
        "film_formula": inputs.film.name,
        "friction": inputs.friction.name,
        "speed_rad_s": inputs.speed,
        "viscosity_at_oil_temperature_mm2_s": float(inputs.lubricant.kinematic_viscosity()) * 1e6,
        "dynamic_viscosity_Pa_s": float(inputs.lubricant.dynamic_viscosity),
        **out.summary(),
        "files": ["tribology.json", "tribology.csv", "tribology.png"],
    }
    loaded = np.asarray(out.loaded)
    theta = np.broadcast_to(np.asarray(result.theta)[:, None, None], loaded.shape)[loaded]
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
    flash = None
    if inputs.scuffing is not None:
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
    write_csv(os.path.join(out_dir, "tribology.csv"), list(cols), list(cols.values()))
    path_of_contact_plot(
        os.path.join(out_dir, "tribology.png"),
        cols["s_m"],
        cols["line_load_N_per_m"],
        cols["central_film_m"],
        cols["minimum_film_m"],
        cols["specific_film"],
        cols["local_loss_W_per_m"],
        pitch=pitch_point_roll(pair),
        flash=flash,
        title=f"{case.name}: film and sliding loss along the path of contact ({inputs.film.name}, "
        f"μ {section['friction_coefficient']:.4f}, {inputs.speed:g} rad/s)",
    )
    write_json(os.path.join(out_dir, "tribology.json"), section)
    return section


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
    film = (
        f"film and loss ({section['film_formula']}, μ {section['friction_coefficient']:.4f} "
        f"{section['friction']}): min λ {section['min_specific_film']:.2f}, P_VZP "
        f"{section['mean_power_loss_W']:.1f} W, mesh efficiency "
        f"{100 * section['efficiency']:.2f} %, H_V {section['loss_factor_integrated']:.4f} "
        f"(Ohlendorf {section['loss_factor_ohlendorf']:.4f}) (tribology.json)"
    )
    return [film, *lines]


def tribology_rating_lines(section: dict | None) -> list[str]:
    """``rating.md``'s tribology lines (the scuffing and micropitting safety factors of
    ``jaxgear run``'s ``tribology`` section; nothing without them)."""
    if section is None or not ({"scuffing", "micropitting"} & set(section)):
        return []
    lines = ["", "## Scuffing and micropitting (jaxgear's line loads; docs/tribology.md)", ""]
    if "scuffing" in section:
        sc = section["scuffing"]
        lines.append(
            f"- Scuffing, flash-temperature method (ISO/TS 6336-20): θ_B,max "
            f"{sc['max_contact_temperature_C']:.1f} °C, θ_S {sc['scuffing_temperature_C']:.0f} °C,"
            f" S_B {sc['scuffing_safety_factor']:.2f}; integral-temperature method (ISO/TS"
            f" 6336-21): θ_int {sc['integral_temperature_C']:.1f} °C, θ_intS"
            f" {sc['integral_scuffing_temperature_C']:.0f} °C, S_intS"
            f" {sc['integral_scuffing_safety_factor']:.2f}"
        )
    if "micropitting" in section:
        mp = section["micropitting"]
        lines.append(
            f"- Micropitting (ISO/TS 6336-22): λ_GF,min {mp['min_specific_film']:.3f}, λ_GFP "
            f"{mp['permissible_specific_film']:.3f} ({mp['permissible_source']}), S_λ "
            f"{mp['safety_factor']:.2f} (θ_M {mp['bulk_temperature_C']:.1f} °C)"
        )
    return lines
