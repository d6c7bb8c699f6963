"""``jaxgear run`` on a planetary stage (a case of :class:`jaxgear.io.PlanetaryForm`): the speed
ratio and member speeds (Willis), the load sharing among the planets with the pin errors
(K_γ, both lumped models, and for a helical stage the 3D model's with each mesh's face load
factor K_Hβ), the natural frequencies with their mode types, the mesh phases, the
Campbell diagram with the mesh orders in the carrier frame and, for a stage given by its gears,
each of its two meshes' quasi-static TE and stiffness on the rigid mesh (the sun–planet and
planet–ring meshes of one planet: the other planets' are the same up to phase).

Files (atomically, into the run's folder): ``summary.json``, ``modes.json``, ``campbell.png``
and, with gears, ``mesh_<sun>-<planet>.csv`` and ``mesh_<planet>-<ring>.csv`` (TE and mesh
stiffness over two mesh periods); with ``[deviations]``, ``hunting.csv`` and ``hunting.png``
(K_γ and every mesh's TE with the deviations of every tooth over the hunting period).
"""

from __future__ import annotations

import dataclasses
import math
import os

import numpy as np

import fem_prep

from .. import contact_pressure, quasi_static
from ..planetary import (
    LUMPED_MODELS,
    TURN_POSITIONS,
    ConstantMeshes,
    ModeType,
    PlanetaryModes,
    Unbalances,
    campbell,
    classify_modes,
    constant_mesh_sharing,
    load_sharing,
    lumped_mode_models,
    lumped_sharing_models,
    mesh_phases,
    planetary_modes,
    planetary_quasi_static,
    ring_resonances,
    sharing_over_turn,
)
from ..io import planetary_kind, ratings_of, write_csv, write_json
from ._planetary_hunting_run import hunting_line, hunting_section
from ._planetary_rating import (
    K_GAMMA_SOURCE,
    K_GAMMA_SOURCES,
    measured_k_h_alpha,
    measured_k_v,
    rating_k_gamma,
    rating_section,
    stage_contact_model,
    stage_loads,
    stage_root_stress,
)
from ._plots import new_figure
from ._plots._figure import legend_below_and_save
from ._rating_report import RATE  # the compiled rating (tests use the run's program)
from ._spectrum_report import mesh_spectrum_run_lines
from ._summary import environment_summary, mesh_settings_summary, result_summary
from ._tribology_run import efficiency_run_line, planetary_tribology_outputs

__all__ = [
    "K_GAMMA_SOURCE",
    "K_GAMMA_SOURCES",
    "MESH_ORDERS",
    "MODELS",
    "RATE",
    "TURN_POSITIONS",
    "campbell_section",
    "face_load_section",
    "lowest_frequency",
    "measured_k_h_alpha",
    "measured_k_v",
    "mesh_sections",
    "housing_modes_summary",
    "housing_shares",
    "mode_list",
    "mode_models",
    "phases_summary",
    "planet_pass_per_input",
    "planetary_files",
    "planetary_lines",
    "ring_campbell",
    "ring_crossings",
    "ring_operating_shape",
    "rating_k_gamma",
    "rating_section",
    "ring_section",
    "sharing_models",
    "sharing_summary",
    "stage_contact_model",
    "spatial_model",
    "stage_loads",
    "stage_root_stress",
    "turn_sharing",
    "unbalance_summary",
    "type_counts",
]

#: the lumped models every run reports, by their name in the outputs (in this order; the
#: model's rule, :data:`jaxgear.planetary.LUMPED_MODELS`)
MODELS = LUMPED_MODELS


def _of_case(models: dict, case) -> dict:
    """``models`` ({name: kind}) as ``case`` runs them (:func:`jaxgear.io.planetary_kind`: on
    its ``[housing]`` where it has one); ``case`` None: as given."""
    if case is None:
        return models
    return {name: planetary_kind(case, model) for name, model in models.items()}


def mode_models(stage, case=None) -> dict:
    """The models whose modes a run lists, by name (:func:`jaxgear.planetary.lumped_mode_models`:
    :data:`MODELS`, and for a helical stage also ``"spatial"``). Its load sharing, face load and
    sweep: :func:`spatial_model`. With ``case``, each as the case runs it
    (:func:`jaxgear.io.planetary_kind`: a housed case's on its housing)."""
    return _of_case(lumped_mode_models(stage), case)


def spatial_model(spec, stage, case=None):
    """The 3D lumped model (:class:`jaxgear.planetary.SpatialPlanetary`) for a helical stage whose
    axial and tilting supports hold the load-sharing stage (:meth:`~jaxgear.io.PlanetarySpec.
    sharing_stage`; the model's choice, :func:`jaxgear.planetary.planetary_model_for`); None
    for a spur stage or one whose supports are not given (the case keys ``axial_N_per_um``,
    ``tilt_Nm_per_rad``, ``pin_axial_N_per_um``, ``pin_tilt_Nm_per_rad``). With ``case``, as
    the case runs it (:func:`jaxgear.io.planetary_kind`: a housed case's on its housing)."""
    model = lumped_sharing_models(spec.sharing_stage(stage)).get("spatial")
    return model if model is None or case is None else planetary_kind(case, model)


def sharing_models(spec, stage, case=None) -> dict:
    """The models of the run's load sharing, by name (:func:`jaxgear.planetary.
    lumped_sharing_models` of the load-sharing stage: :data:`MODELS`, and ``"spatial"`` where
    :func:`spatial_model` gives it); with ``case``, each as the case runs it
    (:func:`jaxgear.io.planetary_kind`: a housed case's on its housing)."""
    return _of_case(lumped_sharing_models(spec.sharing_stage(stage)), case)


#: the mesh-frequency harmonics drawn on the Campbell diagram
MESH_ORDERS = (1, 2, 3)
#: a frequency below this share of the highest is a rigid mode's
RIGID_SHARE = 1e-6
#: speeds of the Campbell diagram
CAMPBELL_SPEEDS = 41


def planetary_files(form, case, out: str, args, complete: bool,
                    sweep: dict | None = None) -> dict:
    """The files of a planetary case (module docstring) into ``out``; returns the summary
    (``"complete": complete``). With ``sweep`` (the run's planetary speed sweep, ``sweep.json``'s
    content: :func:`jaxgear.cli.planetary_sweep.planetary_sweep`), the rating's measured K_v
    (:func:`measured_k_v`)."""
    spec = form.spec
    stage = spec.stage(case)
    speeds = spec.speeds(case.speed)
    torques = spec.torques(case.torque)
    k_s, k_r = (float(np.max(np.asarray(k))) for k in stage.mesh_stiffnesses())
    models = sharing_models(spec, stage, case)  # a housed case's on its housing
    summary = {
        "case": case.name,
        "complete": bool(complete),
        "planetary": {
            "form": "gears" if case.pairs else "lumped",
            "teeth": dict(zip(("sun", "planet", "ring"), spec.teeth, strict=True)),
            "planets": spec.n_planets,
            "planet_angles_deg": [math.degrees(p) for p in spec.planet_angles],
            "fixed": spec.fixed.name.lower(),
            "input": spec.input.name.lower(),
            "output": spec.output.name.lower(),
            "speed_ratio": spec.ratio(),
            "speeds_rad_s": speeds,
            "torques_Nm": torques,
            "mesh_frequency_carrier_frame_Hz": spec.mesh_frequency(case.speed),
            "center_distance_m": spec.center_distance,
            "pressure_angles_deg": {
                "sun": math.degrees(spec.pressure_angles[0]),
                "ring": math.degrees(spec.pressure_angles[1]),
            },
            "mesh_stiffness_N_per_m": {
                "sun": k_s,
                "ring": k_r,
                "source": spec.mesh_stiffness.summary(),
            },
        },
        "operating": {"torque_Nm": case.torque, "speed_rad_s": case.speed},
        "load_sharing": sharing_summary(spec, stage, torques, models),
        "mesh_phases": phases_summary(spec),
    }
    if spec.unbalanced:
        summary["unbalances"] = unbalance_summary(spec)
    if float(stage.helix_angle) != 0.0:  # a helical stage: the 3D model's face load
        summary["face_load"] = face_load_section(spec, stage, torques, case)
    modes = {name: mode_list(model, stage) for name, model in mode_models(stage, case).items()}
    write_json(os.path.join(out, "modes.json"), {"case": case.name, **modes})
    summary["modes"] = {
        "file": "modes.json",
        **{f"{name}_lowest_Hz": lowest_frequency(v) for name, v in modes.items()},
        **{f"{name}_type_counts": type_counts(modes[name]) for name in ("planar", "spatial")
           if name in modes},
        **housing_modes_summary(modes),
    }
    summary["campbell"] = campbell_section(case, spec, stage, os.path.join(out, "campbell.png"))
    if spec.ring_model.flexible:
        summary["ring"] = ring_section(case, spec, stage, out)
    if case.deviations is not None:  # [deviations]: every tooth's, over the hunting period
        summary["hunting"] = hunting_section(case, spec, stage, out)
    if case.pairs:
        solved = []
        summary["meshes"] = mesh_sections(case, out, solved)
        summary["mesh"] = mesh_settings_summary(case)
        # [lubricant]: each mesh's film and sliding loss, the stage's efficiency
        tribology = planetary_tribology_outputs(case, out, solved)
        if tribology is not None:
            summary["tribology"] = tribology
    loads, k_v = None, None
    if ratings_of(case) is not None:
        loads = stage_loads(case, spec, stage, models)
        # the sweep's meshes (build_dynamic_model's: the case's dynamic meshes): their contact
        # model, which each measured K_v row states
        contact = stage_contact_model(spec.dynamic_meshes(case, case.slices))
        k_v = measured_k_v(sweep, case.speed, summary["load_sharing"], contact)
    rating = rating_section(case, out, *rating_k_gamma(summary["load_sharing"]),
                            face_load=summary.get("face_load"), loads=loads, k_v=k_v)
    if rating is not None:
        summary["rating"] = rating
    summary["environment"] = environment_summary(np.asarray(stage.planet_angles).dtype)
    write_json(os.path.join(out, "summary.json"), summary)
    return summary


def unbalance_summary(spec) -> dict:
    """The mass unbalances the run's dynamics apply (``summary.json``'s ``unbalances``), as the
    case gives them: U (kg m) and phases (rad) of the sun, ring, carrier and each planet
    (:class:`jaxgear.planetary.Unbalances`' fields)."""
    return {
        f"{f.name}_{'rad' if f.name.endswith('phase') else 'kg_m'}": np.asarray(u).tolist()
        for f, u in zip(dataclasses.fields(Unbalances), spec.unbalances, strict=True)
    }


def sharing_summary(spec, stage, torques: dict, models: dict = MODELS) -> dict:
    """Load sharing under the sun's torque with the pin errors, per model of ``models``
    ({name: model kind}; the 3D model's mesh forces are along the tooth normal); with
    eccentricities (:class:`jaxgear.planetary.Eccentricities`, taken at the mesh travel 0 in
    ``k_gamma``) also K_γ over a turn (:func:`turn_sharing`)."""
    held = spec.sharing_stage(stage)
    e = np.asarray(spec.tangential_pin_errors)
    eps = np.asarray(spec.radial_pin_errors)
    out = {"tangential_pin_errors_m": e.tolist(), "radial_pin_errors_m": eps.tolist()}
    if spec.eccentric:
        names = ("sun_m", "sun_phase_rad", "ring_m", "ring_phase_rad", "carrier_m",
                 "carrier_phase_rad")
        out["eccentricities"] = dict(zip(names, spec.eccentricities, strict=True))
        if spec.planet_runout:
            runout, phase = spec.planet_runout
            out["eccentricities"]["planet_m"] = np.asarray(runout).tolist()
            out["eccentricities"]["planet_phase_rad"] = np.asarray(phase).tolist()
    for name, model in models.items():
        r = load_sharing(model, held, abs(torques["sun"]), e, eps)
        out[name] = {
            "sun_mesh_forces_N": np.asarray(r.sun_mesh_forces).tolist(),
            "ring_mesh_forces_N": np.asarray(r.ring_mesh_forces).tolist(),
            "k_gamma": float(r.k_gamma),
        }
        if spec.eccentric:
            out[name]["over_turn"] = turn_sharing(model, held, abs(torques["sun"]), e, eps)
    return out


def face_load_section(spec, stage, torques: dict, case=None) -> dict:
    """A helical stage's face load (``summary.json``'s ``face_load``): the 3D model
    (:class:`jaxgear.planetary.SpatialPlanetary`) solved with one unilateral spring per mesh spread
    over the face (:class:`jaxgear.planetary.ConstantMeshes` at two Gauss points, the stage's mesh
    stiffness), the stage of the load sharing, the sun's torque and the pin errors, at the mesh
    travel 0: each mesh's transverse force, its face load factor K_Hβ (ISO 6336-1's linear
    distribution across the face, from the members' tilts and the helical meshes' axial forces) and
    K_γ. ``case``: the 3D model as the case runs it (:func:`spatial_model`)."""
    model = spatial_model(spec, stage, case)
    if model is None:
        return {"skipped": "the 3D model's axial and tilting supports do not hold the stage: "
                "give every member's axial_N_per_um and tilt_Nm_per_rad and the planets' "
                "pin_axial_N_per_um and pin_tilt_Nm_per_rad"}
    held = spec.sharing_stage(stage)
    e = np.asarray(spec.tangential_pin_errors)
    eps = np.asarray(spec.radial_pin_errors)
    q = constant_mesh_sharing(model, held, abs(torques["sun"]), e, eps, np.zeros(1))
    n = spec.n_planets
    k = np.asarray(q.k_h_beta)
    return {
        "model": "spatial (3D lumped), constant mesh springs at two Gauss points across the face",
        "mesh_names": [f"sun-planet {i + 1}" for i in range(n)]
        + [f"ring-planet {i + 1}" for i in range(n)],
        "k_h_beta": k.tolist(),
        "k_h_beta_max": float(k.max()),
        "transverse_forces_N": np.concatenate(
            [np.asarray(q.sun_mesh_forces[0]), np.asarray(q.ring_mesh_forces[0])]).tolist(),
        "k_gamma": float(q.k_gamma[0]),
        "face_width_m": float(stage.face_width),
    }


def turn_sharing(model, held, torque: float, e, eps) -> dict:
    """K_γ over one turn of the ring relative to the carrier (``sharing_summary``'s
    ``over_turn``): :func:`jaxgear.planetary.sharing_over_turn` at its
    :data:`TURN_POSITIONS` travels (:func:`jaxgear.planetary.turn_travel`), presented."""
    q = sharing_over_turn(model, held, torque, e, eps)
    x, r_r = np.asarray(q.travel), float(held.ring.base_radius)
    k = np.asarray(q.k_gamma)
    return {
        "mesh_travel_m": x.tolist(),
        "carrier_angle_relative_to_ring_deg": np.degrees(x / r_r).tolist(),
        "k_gamma": k.tolist(),
        "k_gamma_max": float(k.max()),
        "sun_mesh_forces_N": np.asarray(q.sun_mesh_forces).tolist(),
    }


#: carrier positions over 1/N of a turn at which the flexible ring's load sharing is solved
RING_POSITIONS = 9
#: the ring's mode shapes written to ring.vtu
RING_VTU_MODES = 8


def ring_section(case, spec, stage, out: str) -> dict:
    """A flexible ring's effect (``[planetary.ring] model = "condensed"``): the planar model's
    load sharing with the pin errors, the rigid ring against the condensed one (one spring per
    mesh at the stage's mesh stiffness, sun free, ring and carrier held: the stage of
    :func:`sharing_summary`) at :data:`RING_POSITIONS` carrier positions over 1/N of a turn;
    the ring's deflection at the ring meshes; its lowest in-plane nodal-diameter frequencies
    and which of them the planets' mesh harmonics excite, at which carrier and input speed
    (``resonances``, :func:`ring_crossings`: the one list that ``ring_campbell.png`` draws, its
    ``campbell`` section saying how many lie in the drawn range); ``ring.vtu`` (the ring's mode shapes and its deflected
    shape at the first position, :func:`ring_operating_shape`); ``ring_campbell.png``."""
    rm = spec.ring_model
    st = rm.stations()
    held = spec.sharing_stage(stage)
    torque = abs(spec.torques(case.torque)["sun"])
    n = spec.n_planets
    x = np.linspace(0.0, float(stage.ring.base_radius) * 2 * math.pi / n, RING_POSITIONS)
    e = np.asarray(spec.tangential_pin_errors)
    eps = np.asarray(spec.radial_pin_errors)
    model = MODELS["planar"]
    rigid = planetary_quasi_static(model, held, ConstantMeshes(), torque, x, e, eps)
    flex = planetary_quasi_static(model, held, ConstantMeshes(), torque, x, e, eps,
                                  ring=rm.ring())
    prep = fem_prep.prepare_ring(rm.body)
    station = np.asarray(rm.ring().station_rows(held, x[0])).T @ np.asarray(
        flex.ring_mesh_forces[0])
    fem_prep.write_ring_vtu(prep, os.path.join(out, "ring.vtu"), n_modes=RING_VTU_MODES,
                            point_data={DEFLECTION: ring_operating_shape(prep, station)})
    resonances = ring_crossings(spec, st.nd_frequencies)
    campbell = ring_campbell(case, spec, st.nd_frequencies,
                             os.path.join(out, "ring_campbell.png"), resonances)
    return {
        "body": rm.source,
        "stations": int(st.compliance.shape[0]),
        "carrier_positions_rad": (x / float(stage.ring.base_radius)).tolist(),
        "k_gamma_rigid": float(np.max(np.asarray(rigid.k_gamma))),
        "k_gamma_condensed": float(np.max(np.asarray(flex.k_gamma))),
        "ring_mesh_forces_condensed_N": np.asarray(flex.ring_mesh_forces).tolist(),
        "ring_deflection_max_m": float(np.max(np.abs(np.asarray(flex.ring_deflection)))),
        "nd_frequencies_Hz": {str(k): v for k, v in st.nd_frequencies.items()},
        "resonances": resonances,
        "file": "ring.vtu",
        "vtu_deflection": f"{DEFLECTION}: the deflected shape at the first carrier position "
        "(the condensed solve's ring-mesh forces), beside the mode shapes",
        "campbell": campbell,
    }


#: ring.vtu's point data of the deflected shape at the operating point
DEFLECTION = "deflection_operating_m"


def ring_operating_shape(prep, station_forces) -> np.ndarray:
    """The FE ring's deflected shape (m, (n_nodes, 3)) under in-plane forces at its tooth
    stations (N, (Z, 2): ``CondensedRing.station_rows(stage, x).T @ P``, the ring-mesh forces P
    spread on the stations' hats), each spread across the face width on the station's axial
    masters with the trapezoid weights of ``fem_prep.ring_master_compliance`` (the compliance
    the solve used): the condensed model's static response, recovered on the full mesh."""
    teeth, nax, _ = prep.master_dofs.shape
    w = np.ones(nax) if nax == 1 else np.r_[0.5, np.ones(nax - 2), 0.5]
    loads = np.zeros((teeth, nax, 3))
    forces = np.asarray(station_forces).reshape(teeth, 2)
    loads[:, :, :2] = (w / w.sum())[None, :, None] * forces[:, None, :]
    return prep.static(loads).reshape(-1, 3)


#: the mesh harmonics h drawn on the ring's Campbell diagram (h = 0: the mean loads carried round)
RING_HARMONICS = 2


def planet_pass_per_input(spec) -> float:
    """|ω_c − ω_r| per rad/s of the input: how fast the planets move round the ring (the carrier
    speed when the ring is fixed)."""
    w = spec.speeds(1.0)
    return abs(w["carrier"] - w["ring"])


def ring_crossings(spec, nd_frequencies: dict) -> list[dict]:
    """The one list of the ring's resonances with the planets' mesh harmonics (the ``ring``
    section's ``resonances``, drawn by :func:`ring_campbell`): :func:`jaxgear.planetary.ring_resonances`
    for h = 0..:data:`RING_HARMONICS` (h = 0: the mean loads carried round), each entry
    ``nd``, ``harmonic``, ``order`` (|h z_r ∓ n|: a line of the Campbell diagram, the rule of
    docs/planetary.md, "Which ring modes the planets excite"), ``frequency_hz`` (f_n),
    ``carrier_speed_hz`` (the speed Ω/2π of the planets round the ring at the crossing, rev/s,
    f_n / order) and ``input_speed_rad_s`` (2π f_n / (order Ω per input)), sorted by speed;
    [] when the planets do not move round the ring."""
    per_input = planet_pass_per_input(spec)
    if not per_input:
        return []
    return [
        {**r, "input_speed_rad_s": r["carrier_speed_hz"] * 2 * math.pi / per_input}
        for r in ring_resonances(nd_frequencies, spec.n_planets, int(spec.teeth[2]),
                                 RING_HARMONICS)
    ]


def ring_campbell(case, spec, nd_frequencies: dict, path: str,
                  resonances: list | None = None) -> dict:
    """The ring's Campbell diagram against the input speed, drawn into ``path``: each
    nodal-diameter frequency f_n (Hz, ``nd_frequencies`` {n: f_n}; a ring held, its modes do not
    change with the speed) and the excitation lines of the rule of docs/planetary.md ("Which
    ring modes the planets excite", :func:`jaxgear.planetary.ring_excitation`): the mesh harmonic h of N
    planets moving round the ring at Ω = |ω_c − ω_r| excites the n-diameter mode where
    h z_r ∓ n ≡ 0 (mod N), at the frequency |h z_r ∓ n| Ω/2π, for h = 0..:data:`RING_HARMONICS`;
    each line is drawn in its mode's colour and its crossing with f_n (a resonance) marked. The
    lines and crossings are ``resonances`` (:func:`ring_crossings`; None: computed here): one
    line per resonance, each line meeting its mode once.

    Returns the section's keys: the file, the speed range (input, rad/s), Ω per input speed and
    ``shown``, how many of the ``resonances`` (the first, by speed) lie in the drawn range."""
    z_r, n = int(spec.teeth[2]), spec.n_planets
    per_input = planet_pass_per_input(spec)
    if resonances is None:
        resonances = ring_crossings(spec, nd_frequencies)
    nds = sorted(int(k) for k in nd_frequencies)
    mesh = [c["input_speed_rad_s"] for c in resonances if c["harmonic"] > 0]
    top = max(1.5 * case.speed, 1.2 * max(mesh, default=0.0), 1e-9)
    shown = [c for c in resonances if c["input_speed_rad_s"] <= top]
    fig, ax = new_figure()
    styles = {0: ":", 1: "--", 2: "-."}
    colours = {m: f"C{i % 10}" for i, m in enumerate(nds)}
    speeds = np.array([0.0, top])
    for m in nds:
        ax.axhline(nd_frequencies[m], color=colours[m], lw=1.4,
                   label=f"ND {m}: {nd_frequencies[m]:.4g} Hz")
    for line in resonances:
        ax.plot(speeds, line["order"] * per_input * speeds / (2 * math.pi),
                styles.get(line["harmonic"], "-"), color=colours[line["nd"]], lw=0.8)
    for h in range(RING_HARMONICS + 1):
        ax.plot([], [], styles.get(h, "-"), color="0.3", lw=0.8,
                label=f"h = {h}: |{h} z_r ∓ n| Ω/2π" if h else "h = 0: n Ω/2π (mean loads)")
    if shown:
        ax.plot([c["input_speed_rad_s"] for c in shown], [c["frequency_hz"] for c in shown],
                "o", mfc="none", color="k", label="resonance")
    if case.speed > 0:
        ax.axvline(case.speed, color="k", lw=0.8, ls=(0, (1, 3)),
                   label=f"operating {case.speed:g} rad/s")
    ax.set_xlim(0, top)
    ax.set_ylim(0, 1.15 * max(nd_frequencies.values()))
    ax.set_xlabel(f"input ({spec.input.name.lower()}) speed (rad/s)")
    ax.set_ylabel("frequency (Hz, the ring's frame)")
    ax.set_title(f"{case.name}: ring nodal-diameter modes and the planets' excitation "
                 f"({n} planets, z_r = {z_r}; excited where h z_r ∓ n ≡ 0 mod {n})")
    ax.grid(alpha=0.3)
    legend_below_and_save(fig, ax, path, None)
    return {
        "file": "ring_campbell.png",
        "input_speeds_rad_s": [0.0, top],
        "planet_pass_speed_per_input": per_input,
        "shown": len(shown),
    }


def phases_summary(spec) -> dict:
    z_s, _, z_r = spec.teeth
    g_s, g_r = mesh_phases(z_s, z_r, np.asarray(spec.planet_angles))
    return {"sun_planet": np.asarray(g_s).tolist(), "ring_planet": np.asarray(g_r).tolist()}


def mode_list(model, stage) -> list:
    """``modes.json``'s list of ``model``'s modes of ``stage``: each one's frequency, type and
    multiplicity (:func:`jaxgear.planetary.classify_modes`); a kind on a mount's
    (:meth:`~jaxgear.planetary.AbstractPlanetaryModel.mount`) also ``housing_kinetic_energy_share``
    (:func:`housing_shares`), and a mode whose share exceeds :data:`HOUSING_DOMINATED` is
    typed ``"housing"`` (the classifier's types are the stage's symmetry classes, which a
    mode of the box alone has not)."""
    m = planetary_modes(model, stage)
    types = classify_modes(*_stage_part(m, model, stage), stage)
    share = housing_shares(model, stage, m.shapes)
    return [
        {"frequency_Hz": float(f), "multiplicity": int(k),
         "type": "housing" if share is not None and share[i] > HOUSING_DOMINATED else t.value,
         **({} if share is None else {"housing_kinetic_energy_share": float(share[i])})}
        for i, (f, (t, k)) in enumerate(zip(np.asarray(m.frequencies), types, strict=True))
    ]


def _stage_part(modes, model, stage) -> tuple:
    """(modes, kind) that :func:`~jaxgear.planetary.classify_modes` types: ``model``'s own,
    or a kind on a mount's shapes on the stage's coordinates with the kind on the ground
    (:meth:`~jaxgear.planetary.AbstractPlanetaryModel.unmounted`). The housing joins the held
    member's rotation about the axis (and motion along it), coordinates of the rotational class, so
    a mode's stage part keeps the class of the whole; a mode that is mostly the housing's is typed
    ``"housing"`` after (:func:`mode_list`)."""
    if model.mount() is None:
        return modes, model
    base = model.unmounted()
    n = len(base.dof_names(stage))
    return PlanetaryModes(modes.frequencies, modes.shapes[:n]), base


def housing_shares(model, stage, shapes) -> np.ndarray | None:
    """Each mode's (columns of ``shapes``, (n + h, m)) share of its kinetic energy in the
    housing of a kind on a mount ``model``: e_i = Σ_{j ∈ housing}
    φ_ji (M φ_i)_j / φ_iᵀ M φ_i over the housing's h coordinates (the last h: its seats' and
    its modal ones), M the model's mass matrix (the stage's and the housing's M_h, which do not
    couple: their coupling is in K); None for an unhoused kind."""
    mount = model.mount()
    if mount is None:
        return None
    phi = np.asarray(shapes)
    energy = phi * (np.asarray(model.mass_matrix(stage)) @ phi)
    h = int(mount.size)
    return energy[-h:].sum(axis=0) / energy.sum(axis=0)


#: a mode is the housing's where its kinetic energy share there exceeds this
HOUSING_DOMINATED = 0.5


def housing_modes_summary(modes: dict) -> dict:
    """``summary.json``'s ``modes`` keys of a housed stage (``modes``: {name: mode list} with
    ``housing_kinetic_energy_share``; {} without): per model the number of modes whose
    kinetic energy lies mostly in the housing (share > :data:`HOUSING_DOMINATED`) and the
    lowest of them (Hz; None where none)."""
    out = {}
    for name, v in modes.items():
        if not any("housing_kinetic_energy_share" in m for m in v):
            continue
        housed = [m["frequency_Hz"] for m in v
                  if m["housing_kinetic_energy_share"] > HOUSING_DOMINATED]
        out[f"{name}_housing_dominated"] = len(housed)
        out[f"{name}_lowest_housing_dominated_Hz"] = min(housed, default=None)
    return out


def lowest_frequency(modes: list) -> float | None:
    """The lowest natural frequency above the rigid modes' (those below 1e-6 × the highest:
    a member free to turn has one at 0 Hz, which round-off leaves at ~1e-4 Hz)."""
    f = np.array([m["frequency_Hz"] for m in modes])
    above = f[f > RIGID_SHARE * f.max()]
    return float(above.min()) if above.size else None


def type_counts(modes: list) -> dict:
    """Distinct frequencies per mode type (a degenerate pair counted once)."""
    out = {t.value: 0 for t in ModeType}
    seen = set()
    for m in modes:
        out.setdefault(m["type"], 0)  # "housing": a housed stage's (mode_list)
        key = (m["type"], round(m["frequency_Hz"], 6))
        if key not in seen:
            seen.add(key)
            out[m["type"]] += 1
    return out


def campbell_section(case, spec, stage, path: str) -> dict:
    """The planar model's frequencies in the carrier frame against the input speed (Coriolis
    and centripetal terms at the carrier speed), the output held in rotation
    (:meth:`~jaxgear.io.PlanetarySpec.held_stage`: the free mechanism mode would diverge under
    the centripetal term), with the mesh orders k z_s |ω_s − ω_c|/(2π); drawn into ``path``.
    The planar model as the case runs it (:func:`jaxgear.io.planetary_kind`: a housed case's on
    its housing, whose coordinates do not turn)."""
    per_input = spec.speeds(1.0)  # every speed per rad/s of the input
    f_mesh = spec.mesh_frequency(1.0)  # Hz per rad/s of the input
    model = planetary_kind(case, MODELS["planar"])
    housed = model.mount() is not None
    f0 = np.asarray(planetary_modes(model, stage).frequencies)
    nonzero = f0[f0 > RIGID_SHARE * max(f0.max(), 1.0)]
    reach = nonzero[min(1, nonzero.size - 1)] * 1.2 / f_mesh if nonzero.size else 1.0
    top = max(1.5 * case.speed, reach)
    inputs = np.linspace(0.0, top, CAMPBELL_SPEEDS)
    held = spec.held_stage(stage)
    freqs = np.asarray(campbell(model, held, inputs * per_input["carrier"]))
    fig, ax = new_figure()
    for j in range(freqs.shape[1]):
        ax.plot(
            inputs,
            freqs[:, j],
            color="0.3",
            lw=0.8,
            label=(f"natural frequencies (planar{', on the housing' if housed else ''})"
                   if j == 0 else None),
        )
    for k in MESH_ORDERS:
        ax.plot(
            inputs,
            k * f_mesh * inputs,
            "--",
            lw=1.2,
            label=f"mesh order {k}: {k} z_s |ω_s − ω_c|/2π",
        )
    if case.speed > 0:
        ax.axvline(case.speed, color="tab:red", lw=0.8, label=f"operating {case.speed:g} rad/s")
    ax.set_ylim(0, 1.1 * float(nonzero.max() if nonzero.size else 1.0))
    ax.set_xlim(0, top)
    ax.set_xlabel(f"input ({spec.input.name.lower()}) speed (rad/s)")
    ax.set_ylabel("frequency in the carrier frame (Hz)")
    ax.set_title(
        f"{case.name}: Campbell diagram, {spec.n_planets} planets; modes of the stage with "
        f"the {spec.fixed.name.lower()} (fixed) and the {spec.output.name.lower()} (output) "
        "held in rotation, the input free"
    )
    ax.grid(alpha=0.3)
    legend_below_and_save(fig, ax, path, None)
    return {
        "file": "campbell.png",
        "input_speeds_rad_s": inputs.tolist(),
        "carrier_speeds_rad_s": (inputs * per_input["carrier"]).tolist(),
        "mesh_frequency_per_input_rad_s_Hz": f_mesh,
        "held": spec.output.name.lower(),
        **({"model": "planar on the housing"} if housed else {}),
    }


def mesh_sections(case, out: str, results: list | None = None) -> dict:
    """Each mesh's quasi-static TE and stiffness (rigid mesh, exact contact, the case's
    modifications) at the mean planet load; ``mesh_<name>.csv``. ``results``: a list to fill
    with each mesh's :class:`~jaxgear.QuasiStaticResult` (the film and sliding loss's)."""
    res = {}
    for k in range(len(case.pairs)):
        one = case.mesh_case(k)
        name = case.mesh_name(k)
        r = quasi_static(
            one.mesh_model(),
            one.modifications,
            one.torque,
            positions_per_pitch=one.positions_per_pitch,
            periods=2,
        )
        p = contact_pressure(one.pair, r, one.youngs_modulus, one.poisson_ratio)
        if results is not None:
            results.append(r)
        write_csv(
            os.path.join(out, f"mesh_{name}.csv"),
            ["theta_rad", "te_m", "mesh_stiffness_N_per_m"],
            [np.asarray(r.theta), np.asarray(r.transmission_error), np.asarray(r.mesh_stiffness)],
        )
        res[name] = {
            "internal": one.pair.pinion.teeth * one.pair.gear.teeth < 0,
            "driving_torque_Nm": one.torque,
            "normal_load_N": one.normal_load,
            "driving_speed_relative_to_carrier_rad_s": one.speed,
            "geometry": one.pair.summary(),
            "quasi_static": result_summary(r, None, p),
            "file": f"mesh_{name}.csv",
        }
    return res


def turn_words(sharing: dict) -> str:
    """The closing words of the load-sharing line: K_γ's largest over a turn with the
    eccentricities (none without)."""
    turn = sharing["planar"].get("over_turn")
    if turn is None:
        return ""
    return (f"; with the eccentricities, over a turn: planar up to {turn['k_gamma_max']:.4f}, "
            f"torsional up to {sharing['torsional']['over_turn']['k_gamma_max']:.4f}")


def planetary_lines(form, case, summary: dict) -> list[str]:
    """What ``jaxgear run`` prints for a planetary case."""
    p = summary["planetary"]
    ls = summary["load_sharing"]
    m = summary["modes"]
    lines = [
        f"planetary stage {case.name}: {p['planets']} planets, {p['fixed']} fixed, "
        f"{p['input']} → {p['output']}, speed ratio ω_in/ω_out {p['speed_ratio']:.6g} (Willis; "
        f"the output turns {1 / p['speed_ratio']:.6g} × the input), "
        f"mesh frequency {p['mesh_frequency_carrier_frame_Hz']:.4g} Hz (carrier frame)",
        f"load sharing K_γ: planar {ls['planar']['k_gamma']:.4f}, torsional "
        f"{ls['torsional']['k_gamma']:.4f}"
        + ("" if ls.get("spatial") is None else f", 3D {ls['spatial']['k_gamma']:.4f}")
        + " (pin errors "
        f"{', '.join(f'{e * 1e6:g}' for e in ls['tangential_pin_errors_m'])} µm tangential)"
        + turn_words(ls),
        f"lowest natural frequency: planar {m['planar_lowest_Hz']:.5g} Hz, torsional "
        f"{m['torsional_lowest_Hz']:.5g} Hz; planar mode types "
        + ", ".join(f"{k} {v}" for k, v in m["planar_type_counts"].items() if v)
        + " (modes.json, campbell.png)"
        + ("" if "planar_housing_dominated" not in m else
           f"; on the housing: {m['planar_housing_dominated']} planar modes mostly the "
           "housing's" + ("" if m["planar_lowest_housing_dominated_Hz"] is None else
                          f", the lowest {m['planar_lowest_housing_dominated_Hz']:.5g} Hz")),
    ]
    fl = summary.get("face_load", {})
    if fl.get("k_h_beta") is not None:
        lines.append(
            f"face load factor K_Hβ (3D model, the members' tilts and the helical axial forces): "
            f"max {fl['k_h_beta_max']:.4f} ("
            + ", ".join(f"{n} {k:.4f}" for n, k in zip(fl["mesh_names"], fl["k_h_beta"],
                                                         strict=True)) + ")"
        )
    r = summary.get("ring")
    if r is not None:
        low = ", ".join(f"ND{k} {f:.4g} Hz" for k, f in list(r["nd_frequencies_Hz"].items())[:4])
        lines.append(
            f"flexible ring {r['body']}: K_γ rigid {r['k_gamma_rigid']:.4f} → condensed "
            f"{r['k_gamma_condensed']:.4f}, ring deflection max "
            f"{r['ring_deflection_max_m'] * 1e6:.3g} µm; {low}; {len(r['resonances'])} "
            "ND crossings with the planets' mesh harmonics (ring.vtu, ring_campbell.png)"
        )
    if summary.get("hunting") is not None:
        lines.append(hunting_line(summary["hunting"]))
    rt = summary.get("rating")
    if rt is not None:
        lines.append(
            "rating (" + rt["method"] + "): " + "; ".join(
                f"{name} S_H {min(h):.3g}, S_F {min(f):.3g} (K_γ {k:.4f})"
                for name, h, f, k in zip(
                    rt["meshes"], rt["pitting"]["S_H"], rt["bending"]["S_F"],
                    rt["K_gamma"]["value"], strict=True,
                )
            ) + " (rating.md)"
        )
        lines += mesh_spectrum_run_lines(rt["meshes"], rt.get("spectrum"))
    for name, mesh in summary.get("meshes", {}).items():
        q = mesh["quasi_static"]
        lines.append(
            f"mesh {name}{' (internal)' if mesh['internal'] else ''}: TE ptp "
            f"{q['te_ptp_m'] * 1e6:.4f} µm, K mean {q['mesh_stiffness_mean_N_per_m'] / 1e6:.2f} "
            f"N/µm, max line load {q['max_line_load_N_per_m'] / 1e3:.1f} N/mm, max pressure "
            f"{q['max_contact_pressure_Pa'] / 1e6:.0f} MPa"
        )
    return lines + efficiency_run_line(summary.get("tribology"))
