"""``jaxgear robust CASE --grade 6 --samples 1000``: Monte Carlo over ISO 1328-1 deviation
realisations (docs/robust.md): the distributions of the quasi-static TE RMS, peak-to-peak TE and
largest line load over the span, and of the dynamic factor per speed, with percentiles and their
confidence intervals; ``robust.json``, ``samples.csv``, ``robust_distributions.png``,
``robust_speed_bands.png``. With ``--num-processes N`` it runs as process ``--process-id`` of N
joined by ``jax.distributed`` (one per host), the realisations sharded over every process's
devices; process 0 writes the files."""

from __future__ import annotations

import dataclasses
import os
import time

import jax
import jax.numpy as jnp
import numpy as np
from matplotlib.ticker import MaxNLocator

from fem_prep.resources import memory_allowed

from .. import (
    DeviationSampler,
    Modifications,
    QuasiStaticMetrics,
    io as case_io,
    mesh_positions,
    quasi_static,
    robust_samples,
    sample_statistics,
)
from ..dynamics import DynamicMetrics, Newmark, SteadyState, dynamic_model
from ..io import SchemaError, TrainForm, build_dynamic_model, parse_robust, write_csv, write_json
from ..scenes import TorsionalDynamics, disc_inertia
from ._case_kinds import refuse_stages
from ._distributed import join_processes
from ._paths import OUTPUT_FILES, check_case_outputs, staged_outputs
from ._plots import new_figure, savefig

__all__ = ["ROBUST_FILES", "run_robust"]

#: the files ``jaxgear robust`` writes (:data:`jaxgear.cli.OUTPUT_FILES`)
ROBUST_FILES = OUTPUT_FILES["robust"]


def _settings(case, args) -> dict:
    refuse_stages(case, "robust")
    if isinstance(case.form, TrainForm):
        raise ValueError(
            f"case {case.name!r}: a gear train ([[gears]], [[meshes]]); jaxgear robust samples "
            "the deviations of one pair: allowed a pair case ([pair], [pinion], [gear])"
        )
    grade = None if case.deviation_settings is None else case.deviation_settings.get("grade")
    teeth = (case.pair.pinion.teeth, case.pair.gear.teeth)
    try:
        st = parse_robust(case.raw.get("robust", {}), teeth, grade_from_deviations=grade)
    except SchemaError as err:
        raise ValueError(str(err)) from None
    for name in ("grade", "samples", "seed"):
        if getattr(args, name) is not None:
            st[name] = getattr(args, name)
    if st["grade"] is None:
        raise ValueError(
            "grade: missing, allowed an ISO 1328-1 flank tolerance class 1-11 (--grade, "
            "[robust] grade or [deviations] grade)"
        )
    if st["speeds_rad_s"] and case.scene is not None and case.scene.hybrid:
        raise ValueError(
            "[robust] speeds_rad_s: the dynamic factor of condensed bodies is not sampled "
            "(allowed a lumped [scene] or none)"
        )
    check_robust_size(st, "--samples" if args.samples is not None else "[robust] samples")
    return st


def robust_bytes_per_sample(speeds: int) -> int:
    """About the memory one realisation takes at its peak (bytes), ``speeds`` the
    dynamic-factor speeds: 4 quasi-static figures and 3 per speed in float64, held about 4
    times (on the device, on the host, masked, scaled), ``samples.csv``'s text (about 40
    characters a value, twice while written) and the order-statistic confidence intervals
    (:func:`jaxgear.sample_statistics`: a few float64 arrays and a Python float per
    realisation, about 120 bytes)."""
    values = 4 + 3 * speeds
    columns = 5 + speeds
    return 8 * 4 * values + 40 * columns + 120


def check_robust_size(st: dict, name: str) -> None:
    """Refuse, before any work, a run whose realisations need more than half this machine's
    memory (:func:`robust_bytes_per_sample`): one line naming ``name`` (``--samples`` or
    ``[robust] samples``), its value and the most realisations allowed."""
    per = robust_bytes_per_sample(len(st["speeds_rad_s"]))
    have = memory_allowed()
    need = float(st["samples"]) * per
    if need > have:
        most = int(have // per)
        raise ValueError(
            f"{name} = {st['samples']}: out of range, allowed <= {most} on this machine (about "
            f"{per} bytes per realisation: {need / 1e9:.3g} GB, allowed <= {have / 1e9:.3g} GB, "
            "half its memory): fewer samples"
        )


def _dynamic_problem(case, st, mesh):
    """The dynamic problem of the case at the [robust] speeds: its lumped [scene] (else a
    torsional pair on solid-disc inertias), the span ``revolutions`` × z1 mesh periods."""
    if case.scene is not None:  # a lumped one (_settings refuses condensed bodies)
        model, _ = build_dynamic_model(case)
    else:
        p = case.pair
        inertia = [
            disc_inertia(case.density, r, m.face_width)
            for r, m in zip(p.tip_radii, (p.pinion, p.gear), strict=True)
        ]
        model = dynamic_model(TorsionalDynamics(mesh, *inertia), case.modifications, case.torque)
    span = st["revolutions"] * case.pair.pinion.teeth
    model = dataclasses.replace(model, deviation_span=span)
    speeds = jnp.asarray(st["speeds_rad_s"], model.damping.dtype)
    window = SteadyState(st["transient_periods"] + span, span)
    return DynamicMetrics(model, speeds, Newmark(st["steps_per_period"]), window)


def run_robust(args) -> int:
    join_processes(args)
    case = case_io.load_case(args.case)
    st = _settings(case, args)
    out_dir = args.out or os.path.join("jaxgear-out", case.name, "robust")
    writer = jax.process_index() == 0
    if writer:
        check_case_outputs(case, "robust", out_dir, force=args.force)
    try:
        sampler = DeviationSampler.for_grade(
            case.pair,
            st["grade"],
            members=tuple(st["members"]),
            kinds=case_io.deviation_kinds_from_names(st["kinds"]),
        )
    except ValueError as err:
        raise ValueError(f"[robust] grade = {st['grade']}: {err}") from None
    mesh = case.mesh_model()
    z1 = case.pair.pinion.teeth
    theta = mesh_positions(mesh, st["positions_per_pitch"], st["revolutions"] * z1)
    mods = Modifications(case.modifications.pinion, case.modifications.gear)
    problem = QuasiStaticMetrics(
        mesh, mods, jnp.asarray(case.torque), theta, case.contact_law("exact")
    )
    key = jax.random.key(st["seed"])
    t0 = time.perf_counter()
    qs = robust_samples(problem, sampler, key, st["samples"], batch_size=st["batch_size"])
    t_qs = time.perf_counter() - t0
    dyn = None
    t_dyn = 0.0
    if st["speeds_rad_s"]:
        t0 = time.perf_counter()
        dyn = robust_samples(
            _dynamic_problem(case, st, mesh),
            sampler,
            key,
            st["samples"],
            batch_size=max(1, st["batch_size"] // len(st["speeds_rad_s"])),
        )
        t_dyn = time.perf_counter() - t0
    if not writer:
        return 0
    pc, conf = st["percentiles"], st["confidence"]
    ok = qs.result == 0
    if not ok.any():
        raise ValueError("every realisation failed its quasi-static contact solve")
    scale = {"te_rms_um": 1e6, "te_ptp_um": 1e6, "max_line_load_N_per_mm": 1e-3}
    fields = {
        "te_rms_um": "te_rms",
        "te_ptp_um": "te_ptp",
        "max_line_load_N_per_mm": "max_line_load",
    }
    values = {k: np.asarray(getattr(qs, f))[ok] * scale[k] for k, f in fields.items()}
    # the nominal gears (no deviation) over the same positions: a line on each histogram
    nom = quasi_static(mesh, mods, case.torque, theta=theta, contact=case.contact_law("exact"))
    nominal = {
        "te_rms_um": float(nom.te_rms) * 1e6,
        "te_ptp_um": float(nom.te_ptp) * 1e6,
        "max_line_load_N_per_mm": float(np.max(np.asarray(nom.line_load))) * 1e-3,
    }
    summary = {
        "case": case.name,
        "settings": st,
        "tolerances_um": {
            tag: (None if g is None else _tolerances_um(g))
            for tag, g in (("pinion", sampler.pinion), ("gear", sampler.gear))
        },
        "realisation": "i-th realisation drawn from jax.random.fold_in(jax.random.key(seed), i)",
        "quasi_static": {
            "failed": int((~ok).sum()),
            **{k: sample_statistics(v, pc, conf) for k, v in values.items()},
            "nominal": nominal,
        },
        "processes": jax.process_count(),
        "devices": jax.device_count(),
        "seconds": {"quasi_static": round(t_qs, 3), "dynamics": round(t_dyn, 3)},
        "confidence_intervals": "mean: normal approximation; percentiles: order statistics "
        "of binomial ranks (distribution-free), docs/robust.md",
    }
    cols = [np.arange(st["samples"]), qs.te_rms, qs.te_ptp, qs.max_line_load, qs.result]
    names = ["sample", "te_rms_m", "te_ptp_m", "max_line_load_N_per_m", "qs_result"]
    bands = None
    if dyn is not None:
        per_speed = []
        for j, w in enumerate(st["speeds_rad_s"]):
            good = np.asarray(dyn.result[:, j]) == 0
            entry = {"speed_rad_s": w, "failed": int((~good).sum())}
            if good.sum() >= 2:
                entry["dynamic_factor"] = sample_statistics(dyn.dynamic_factor[good, j], pc, conf)
                entry["dte_rms_um"] = sample_statistics(dyn.te_rms[good, j] * 1e6, pc, conf)
            per_speed.append(entry)
            cols.append(dyn.dynamic_factor[:, j])
            names.append(f"dynamic_factor_{w:g}")
        summary["dynamics"] = per_speed
        bands = per_speed
    # the files appear together when they are all written; the earlier ones are left until then
    with staged_outputs(out_dir, "robust") as work:
        write_json(os.path.join(work, "robust.json"), summary)
        write_csv(os.path.join(work, "samples.csv"), names, [np.asarray(c) for c in cols])
        _plots(work, case.name, st, values, summary["quasi_static"], bands, nominal)
    if not args.quiet:
        q = summary["quasi_static"]["te_rms_um"]
        print(
            f"{case.name}: {st['samples']} realisations of grade {st['grade']}: TE RMS mean "
            f"{q['mean']:.3f} µm, P95 {q['percentiles'][f'{pc[-1]:g}']['value']:.3f} µm "
            f"→ {out_dir}"
        )
    return 0


def _tolerances_um(g) -> dict:
    names = ("f_pT", "F_pT", "f_HaT", "f_faT", "F_aT", "f_HbT", "f_fbT", "F_bT", "F_rT")
    return {n: round(float(v) * 1e6, 6) for n, v in zip(names, g.tolerances, strict=True)}


def _plots(out_dir, name, st, values, stats, bands, nominal=None) -> None:
    labels = {
        "te_rms_um": "TE RMS (µm)",
        "te_ptp_um": "TE peak-to-peak (µm)",
        "max_line_load_N_per_mm": "max line load (N/mm)",
    }
    fig, _ = new_figure((11, 3.8))
    fig.clear()
    axes = fig.subplots(1, 3)
    no_interval = False
    for ax, (k, v) in zip(axes, values.items(), strict=True):
        ax.hist(v, bins=max(10, min(60, int(np.sqrt(v.size)))), color="0.7")
        ax.yaxis.set_major_locator(MaxNLocator(integer=True))  # counts are whole
        pcs = list(stats[k]["percentiles"].items())
        for j, (p, e) in enumerate(pcs):
            ax.axvline(e["value"], color="C3", lw=1)
            lo, hi = e["ci"]
            star = ""
            if lo is not None and hi is not None:
                ax.axvspan(lo, hi, color="C3", alpha=0.15)
            else:  # too few realisations for a distribution-free interval of this percentile
                star, no_interval = "*", True
            # tags inside the axes, the lower percentiles left of their line, the upper right
            left = j < len(pcs) / 2
            ax.text(
                e["value"],
                0.97 - 0.09 * (j % 2),
                f"P{p}{star}",
                transform=ax.get_xaxis_transform(),
                ha="right" if left else "left",
                va="top",
                color="C3",
                fontsize=9,
                bbox={"boxstyle": "square,pad=0.1", "fc": "white", "ec": "none", "alpha": 0.8},
            )
        if nominal is not None:
            ax.axvline(nominal[k], color="k", ls="--", lw=1.2, label="nominal gears")
        ax.set_xlabel(labels[k])
    axes[0].set_ylabel("realisations")
    if nominal is not None:
        axes[0].legend(fontsize=8, loc="center right")
    revs = st["revolutions"]
    fig.suptitle(
        f"{name}: {values['te_rms_um'].size} realisations, ISO 1328-1 grade {st['grade']} "
        f"({revs} pinion revolution{'' if revs == 1 else 's'}); percentiles with "
        f"{st['confidence']:.0%} intervals (shaded)"
        + ("\n* too few realisations for this percentile's interval" if no_interval else "")
    )
    savefig(fig, os.path.join(out_dir, "robust_distributions.png"))
    if not bands:
        return
    fig, ax = new_figure()
    w = np.array([b["speed_rad_s"] for b in bands if "dynamic_factor" in b])
    if w.size:
        d = [b["dynamic_factor"] for b in bands if "dynamic_factor" in b]
        pcs = list(d[0]["percentiles"])
        lo = np.array([x["percentiles"][pcs[0]]["value"] for x in d])
        hi = np.array([x["percentiles"][pcs[-1]]["value"] for x in d])
        ax.fill_between(w, lo, hi, color="C0", alpha=0.25, label=f"P{pcs[0]}–P{pcs[-1]}")
        for p in pcs[1:-1]:
            ax.plot(w, [x["percentiles"][p]["value"] for x in d], "C0-o", ms=3, label=f"P{p}")
        ax.plot(w, [x["mean"] for x in d], "k--", lw=1, label="mean")
    ax.set_xlabel("pinion speed (rad/s)")
    ax.set_ylabel("dynamic factor")
    ax.set_title(f"{name}: dynamic factor over realisations, grade {st['grade']}")
    ax.legend()
    savefig(fig, os.path.join(out_dir, "robust_speed_bands.png"))
