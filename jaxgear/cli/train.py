"""``jaxgear run`` on a gear-train case: the quasi-static contact of every mesh at once, per-mesh
TE, mesh stiffness and load maps, and the layout with its mesh phasing (JSON, CSV, PNG)."""

from __future__ import annotations

import os

import numpy as np

from .. import Modifications, contact_pressure, quasi_static
from ..dynamics import bearing_forces
from ..io import TrainCase, load_bodies, write_csv, write_json
from ._case_kinds import gear_glossary
from ._housing_run import hybrid_seats_section
from ._plots import face_maps, mesh_stiffness_plot, train_phasing_plot, transmission_error_plot
from ._progress import inner_bars, progress
from ._summary import environment_summary, mesh_settings_summary, result_summary
from ._sweep_json import column_tag
from .scene import body_outputs, first_peak

__all__ = ["format_train_table", "run_train", "train_model_words"]


def train_model_words(case, bodies=None) -> str:
    """The model a train's quasi-static figures show, in words: ``torsional train``, ``lumped
    3D train (shafts, bearings)`` or, with condensed FE bodies, ``lumped 3D train, <gear>
    a condensed FE body`` (``bodies``: per gear, None for a rigid one)."""
    if not case.lumped:
        return "torsional train"
    if not case.flexible or bodies is None:
        return "lumped 3D train (shafts, bearings)"
    flex = [n for n, b in zip(case.gear_names, bodies, strict=False) if b is not None]
    return "lumped 3D train, " + ", ".join(flex) + (" a condensed FE body" if len(flex) == 1
                                                    else " condensed FE bodies")


def run_train(
    case: TrainCase,
    out_dir: str,
    *,
    show_progress: bool = True,
    complete: bool = True,
    results: dict | None = None,
) -> dict:
    """The quasi-static analysis of a train case, written to ``out_dir``.

    The contact of every mesh is solved at once on the train's structure (torsional, or lumped
    3D with shafts and bearings, its flexible gears condensed FE bodies; the output held;
    :meth:`~jaxgear.io.TrainCase.static_train`) over two periods of the first mesh (a
    two-stage train: over its span, :attr:`~jaxgear.io.TrainCase.span_periods` periods of the
    first mesh, after which every mesh repeats), exact
    and smooth, with and without the case's modifications. Files (atomically): ``summary.json``
    (``gears``, ``meshes``: per mesh its gears, geometry, phase, torque and the ``quasi_static``
    figures of a pair case; a lumped 3D train: ``bearing_forces_mean_N`` per contact law, fixed
    frame), ``te.csv`` and ``mesh_stiffness.csv`` (a column per mesh, design
    and contact law, against the input angle), ``transmission_error.png``,
    ``mesh_stiffness.png``, ``load_map_<driving>-<driven>.png`` and
    ``pressure_map_<driving>-<driven>.png`` per mesh and ``phasing.png``
    (layout and mesh phasing); with flexible gears ``body_<gear>.vtu`` per body, deformed at the
    position of the largest line load (``body_vtu`` in the summary).

    ``results``: a dict to fill with the coupled quasi-static results of the case's
    modifications (``"exact"``, ``"smooth"``: :class:`~jaxgear.QuasiStaticResult`, every mesh)
    and the structure's mesh models (``"base_planes"``), for the rating's measured factors
    (:func:`jaxgear.cli.rating_outputs`' ``model``, :func:`jaxgear.cli.train_loads`).

    Returns:
        The summary dict (also in ``summary.json``).
    """
    os.makedirs(out_dir, exist_ok=True)
    steps = progress(total=6, desc=f"jaxgear run {case.name}", disable=not show_progress)
    steps.set_postfix_str("meshes and layout")
    bodies = load_bodies(case.scene, progress=inner_bars(show_progress)) if case.flexible else None
    scene = case.static_train(bodies=bodies)
    layout = case.layout()
    steps.update()
    ppp = case.positions_per_pitch
    span = case.span_periods
    res = {}
    for label, mods in (("unmodified", Modifications()), ("modified", case.mesh_modifications())):
        for mode in ("exact", "smooth"):
            steps.set_postfix_str(f"quasi-static, {label}, {mode} contact")
            res[label, mode] = quasi_static(
                scene,
                mods,
                case.torque,
                contact=case.contact_law(mode),
                positions_per_pitch=ppp,
                periods=2 if span == 1 else span,
            )
            steps.update()
    if results is not None:
        results.update({m: res["modified", m] for m in ("exact", "smooth")})
        results["base_planes"] = scene.base_planes
    n_meshes = len(case.pairs)
    names = [case.mesh_name(k) for k in range(n_meshes)]
    pressure = {  # each mesh's Hertzian contact pressure
        (key, k): contact_pressure(pair, r.meshes[k], case.youngs_modulus, case.poisson_ratio)
        for key, r in res.items()
        for k, pair in enumerate(case.pairs)
    }
    members = case.members()
    base_radii = [None] * case.n_gears
    for pair, (g, h) in zip(case.pairs, case.gears, strict=True):
        base_radii[g], base_radii[h] = pair.base_radii
    inertias = case.gear_inertias()
    torques = case.mesh_torques
    output = case.shaft_of.index(case.output)  # a gear of the balancing output's shaft
    period = float(scene.base_planes[0].mesh_period_angle)  # the first mesh's, input angle
    meshes = []
    for k, (pair, (g, h)) in enumerate(zip(case.pairs, case.gears, strict=True)):
        ratio = float(layout.ratios[g])
        meshes.append(
            {
                "name": names[k],
                "driving": case.gear_names[g],
                "driven": case.gear_names[h],
                "angle_deg": float(np.degrees(case.angles[k])),
                "ratio": ratio,
                "phase_rad": float(layout.phases[k]),
                "phase_mesh_periods": float(layout.phases[k] * pair.pinion.teeth / (2 * np.pi)),
                "torque_driving_Nm": float(torques[k]),
                "normal_load_N": float(
                    torques[k] / (pair.base_radii[0] * np.cos(pair.base_helix_angle))
                ),
                "geometry": pair.summary(),
                "quasi_static": {
                    m: result_summary(res["modified", m], k, pressure[("modified", m), k])
                    for m in ("exact", "smooth")
                },
                "quasi_static_unmodified": {
                    m: result_summary(res["unmodified", m], k, pressure[("unmodified", m), k])
                    for m in ("exact", "smooth")
                },
            }
        )
    summary = {
        "case": case.name,
        "kind": "train",
        "complete": bool(complete),
        "gears": [
            {
                "name": case.gear_names[i],
                "shaft": case.gear_names[case.shaft_of.index(case.shaft_of[i])],
                "teeth": members[i].teeth,
                "centre_m": [float(v) for v in layout.centres[i][:2]],
                "spin": int(layout.spins[i]),
                "speed_ratio": float(layout.ratios[i]),
                "tooth_angle_rad": float(layout.tooth_angles[i] % (2 * np.pi)),
                "base_radius_m": float(base_radii[i]),
                "inertia_kg_m2": float(inertias[i]),
            }
            for i in range(case.n_gears)
        ],
        "meshes": meshes,
        "span_periods": span,
        "operating": {
            "torque_Nm": case.torque,
            "loads_Nm": {case.gear_names[g]: float(t) for g, t in case.loads},
            "output": case.gear_names[output],
            "output_torque_Nm": float(
                case.torque
                * (1.0 - sum(case.shares().values()))
                * layout.ratios[0]
                / layout.ratios[output]
            ),
        },
        "mesh": mesh_settings_summary(case),
        **(
            {
                "bearing_forces_mean_N": {
                    m: bearing_forces(scene, res["modified", m]) for m in ("exact", "smooth")
                }
            }
            if case.lumped
            else {}
        ),
        **(
            {"flexible_gears": [n for n, b in zip(case.gear_names, bodies) if b is not None]}
            if case.flexible
            else {}
        ),
        "environment": environment_summary(np.asarray(res["modified", "exact"].theta).dtype),
    }
    steps.set_postfix_str("files and plots")
    theta = np.asarray(res["modified", "exact"].theta)
    designs = ("unmodified", "modified")
    laws = ("exact", "smooth")

    def columns(field: str, unit: str) -> dict:
        return {
            f"{field}_{m}_{lab}_{column_tag(names[k])}_{unit}": np.asarray(
                getattr(res[lab, m].meshes[k], field)
            )
            for k in range(n_meshes)
            for lab in designs
            for m in laws
        }

    te_cols = columns("transmission_error", "m")
    write_csv(os.path.join(out_dir, "te.csv"), ["theta_rad", *te_cols], [theta, *te_cols.values()])
    k_cols = columns("mesh_stiffness", "N_per_m")
    write_csv(
        os.path.join(out_dir, "mesh_stiffness.csv"),
        ["theta_rad", *k_cols],
        [theta, *k_cols.values()],
    )
    x = theta / period
    # a long span (two-stage: 127 periods) drawn whole is a solid band: the plots show two
    # periods of the slowest mesh (at least 3 of the input's), te.csv keeps the span
    n_shown = plotted_periods(case, layout, float(x[-1]) + 0.5 / ppp)
    win = x < n_shown
    shown = (
        ""
        if win.all()
        else (
            f"\nfirst {n_shown:.3g} of {span} input mesh periods (te.csv and mesh_stiffness.csv: all)"
        )
    )
    glossary = _gear_glossary(case)
    model = train_model_words(case, bodies)  # which model every figure shows
    transmission_error_plot(
        os.path.join(out_dir, "transmission_error.png"),
        x[win],
        {
            f"{names[k]}": {
                m: np.asarray(res["modified", m].meshes[k].transmission_error)[win] for m in laws
            }
            for k in range(n_meshes)
        },
        title=f"{case.name}: transmission error per mesh at {case.torque:g} N·m (input), "
        f"modified, {model}{shown}{glossary}",
        driver="input",
    )
    mesh_stiffness_plot(
        os.path.join(out_dir, "mesh_stiffness.png"),
        x[win],
        {
            f"{names[k]} ({lab})": np.asarray(res[lab, "exact"].meshes[k].mesh_stiffness)[win]
            for k in range(n_meshes)
            for lab in designs
        },
        title=f"{case.name}: mesh stiffness per mesh ({case.stiffness_model}, loaded cells), "
        f"{model}{shown}{glossary}",
        note=(None if not case.flexible else
              "K = Σ k l over the loaded cells; a condensed body's cells leave out its foundation "
              "term (its FE rim carries that compliance):\nnot the whole mesh's stiffness"),
        driver="input",
    )
    for k, pair in enumerate(case.pairs):
        face_maps(
            out_dir,
            (f"load_map_{names[k]}.png", f"pressure_map_{names[k]}.png"),
            res["modified", "exact"].meshes[k],
            pressure[("modified", "exact"), k].max_pressure,
            pair,
            ppp,
            f"of {case.name}'s {names[k]} (exact, modified, {model})",
        )
    if case.flexible:  # each body deformed where the largest line load of any mesh is
        qs = res["modified", "exact"]
        peak = np.max(
            [np.asarray(m.line_load).reshape(theta.size, -1).max(axis=1) for m in qs.meshes], 0
        )
        names_of = {g: n for g, n in enumerate(case.gear_names)}
        k = first_peak(peak)  # the first of a plateau's equal peaks, not round-off's pick
        # with the rim and web stresses there, as a pair's hybrid scene reports them
        summary["body_vtu"], summary["body_stress"], summary["body_stress_vtu"] = body_outputs(
            out_dir, scene, bodies, qs, k, names_of
        )
        if (seated := hybrid_seats_section(case)) is not None:  # [housing]: the seats
            summary["housing"] = seated
    marks = {}
    for k, pair in enumerate(case.pairs):
        g = case.gears[k][0]
        # the input positions where mesh k's angle ratio θ + phase is a whole mesh period
        per_mesh = 2 * np.pi / pair.pinion.teeth / layout.ratios[g]  # input rad per period
        first = (-layout.phases[k] / layout.ratios[g]) % per_mesh
        marks[names[k]] = (
            np.asarray(res["unmodified", "exact"].meshes[k].mesh_stiffness)[win],
            np.arange(first, x[win][-1] * period, per_mesh) / period,
        )
    train_phasing_plot(
        os.path.join(out_dir, "phasing.png"),
        layout,
        case.pairs,
        list(zip(case.gear_names, case.tip_radii(), base_radii, strict=True)),
        names,
        x[win],
        marks,
        title=f"{case.name}: layout and mesh phasing (unmodified flanks, exact contact){shown}"
        f"{glossary}",
    )
    steps.update()
    steps.close()
    write_json(os.path.join(out_dir, "summary.json"), summary)
    return summary


def plotted_periods(case, layout, computed: float) -> float:
    """How many of the input's mesh periods the TE, stiffness and phasing plots show: two
    periods of the slowest mesh, at least three of the input's, at most the ``computed`` ones
    (the CSV files keep them all)."""
    slowest = max(  # the slowest mesh's period, in input mesh periods
        case.pairs[0].pinion.teeth / (pair.pinion.teeth * float(layout.ratios[g]))
        for pair, (g, _) in zip(case.pairs, case.gears, strict=True)
    )
    return min(computed, max(3.0, 2.0 * slowest))


def _gear_glossary(case) -> str:
    """:func:`~jaxgear.cli._case_kinds.gear_glossary` as a title's last line ("" if none)."""
    text = gear_glossary(case.gear_names)
    return "\n" + text if text else ""


def format_train_table(summary: dict) -> str:
    """A short plain-text table of a train's main figures, a line per mesh and design."""
    lines = [
        f"train {summary['case']}: {len(summary['gears'])} gears, {len(summary['meshes'])} "
        f"meshes, input torque {summary['operating']['torque_Nm']:g} N·m, balancing torque on gear "
        f"{summary['operating']['output']!r} {summary['operating']['output_torque_Nm']:.4g} N·m",
        f"{'':30s}{'ε_α':>7s}{'phase':>8s}{'TE mean µm':>12s}{'TE ptp µm':>11s}"
        f"{'K mean N/µm':>13s}{'max N/mm':>10s}",
    ]
    for m in summary["meshes"]:
        for key, lab in (("quasi_static_unmodified", "unmodified"), ("quasi_static", "modified")):
            q = m[key]["exact"]
            lines.append(
                f"{m['name'] + ' ' + lab:30s}{m['geometry']['transverse_contact_ratio']:7.3f}"
                f"{m['phase_mesh_periods']:8.3f}{q['te_mean_m'] * 1e6:12.4f}"
                f"{q['te_ptp_m'] * 1e6:11.4f}{q['mesh_stiffness_mean_N_per_m'] / 1e6:13.2f}"
                f"{q['max_line_load_N_per_m'] / 1e3:10.1f}"
            )
    return "\n".join(lines)
