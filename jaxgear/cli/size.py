"""``jaxgear size SPEC.toml --out DIR``: every candidate of a sizing spec rated
(:func:`jaxgear.sizing.size`), the table of them all written (``sizing.csv``; ``sizing.parquet``
the same for queries; ``sizing.json`` the spec's summary and the ranked feasible
candidates), the feasible ones printed lightest first; ``--write K`` writes candidate K (a
row number of the table) as a case file, ``candidate_K.toml``, that ``jaxgear run`` rates to
the same numbers; the Pareto front over the spec's objectives (the table's ``pareto_rank``,
the chosen design in ``sizing.json``, ``pareto_X__Y.png`` for each pair of objectives and
``contact_ratios.png``); the dynamics stage's curves of K_v and the whine against speed for
the candidates of the first fronts (``dynamics.csv``, ``dynamic_factor.png``); with a spec's
``[sound]``, the sound stage's housing ERP of the candidates of the first fronts
(:mod:`jaxgear.cli._sizing_sound`: ``sound.csv``, each candidate's housed case and result in
``store/sound/``; ``--write K`` writes ``candidate_K_housed.toml`` too); each finished
chunk of candidates is kept in the results store (``store/``), which a rerun of the same spec
into the same folder resumes from. With ``--num-processes N`` it runs as process
``--process-id`` of N joined by ``jax.distributed``, the chunks spread over every process's
devices; process 0 writes the files (docs/sizing.md)."""

from __future__ import annotations

import contextlib
import csv
import dataclasses
import itertools
import math
import os
import shutil
import time

import jax
import numpy as np

from .. import sizing
from ..io import (
    SIZING_STAGES,
    SchemaError,
    atomic_open,
    candidate_case_text,
    housed_case_text,
    load_sizing_spec,
    sizing_dynamics_settings,
    sizing_sound,
    sizing_te_settings,
    unstaged_objective,
    write_json,
)
from ._distributed import join_processes
from ._paths import check_foreign_files, check_output_dir, staged_outputs
from ._progress import progress
from ._sizing_sound import sound_stage

__all__ = ["STORE", "run_size", "write_table"]

#: the results store's folder inside the output folder (one file per finished chunk)
STORE = "store"


def write_table(path: str, table: sizing.SizingTable) -> None:
    """The table as CSV, atomically: one row per candidate (its row number ``candidate``
    first), every column at full precision (``repr``), a NaN (no rating: an invalid geometry)
    as an empty cell, ``feasible`` 1/0 and ``rejected`` the failed checks joined by ``;``."""
    names = list(table.columns)
    reasons = table.reasons()
    with atomic_open(path, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["candidate", *names, "feasible", "rejected"])
        cols = [table.columns[n] for n in names]
        for i in range(len(table)):
            row = [i]
            for c in cols:
                v = c[i].item()
                row.append("" if isinstance(v, float) and math.isnan(v)
                           else v if isinstance(v, str) else repr(v))
            w.writerow([*row, int(reasons[i] == ""), reasons[i]])


def _write_parquet(path: str, table: sizing.SizingTable) -> None:
    """The table as Parquet (pyarrow, imported here: the other commands never load it),
    atomically."""
    import pyarrow as pa
    import pyarrow.parquet as pq

    data = {"candidate": np.arange(len(table))} | dict(table.columns)
    data |= {"feasible": table.feasible, "rejected": table.reasons()}
    with atomic_open(path, "wb") as f:
        pq.write_table(pa.table(data), f)


def _line(i: int, c: dict) -> str:
    return (f"{i:>7d}  {c['normal_module_m'][i] * 1e3:5.3g}  {c['z1'][i]:3d}/{c['z2'][i]:<4d} "
            f"{c['centre_distance_m'][i] * 1e3:8.2f}  {c['face_width_m'][i] * 1e3:6.1f}  "
            f"{c['mass_kg'][i]:8.3f}  {min(c['S_H1'][i], c['S_H2'][i]):5.3f}  "
            f"{min(c['S_F1'][i], c['S_F2'][i]):5.3f}  {c['eps_alpha'][i]:5.3f}  "
            f"{c['eps_beta'][i]:5.3f}" + (f"  {c['S_B'][i]:5.3f}" if "S_B" in c else ""))


def _store_folder(out: str) -> str:
    """``OUT/store``, the results store (:func:`jaxgear.sizing.size`'s ``store``), refused in
    one line where it leads out of the output folder through a link."""
    store = os.path.join(out, STORE)
    real = os.path.realpath(store)
    if os.path.lexists(store) and os.path.commonpath([real, os.path.realpath(out)]) != \
            os.path.realpath(out):
        raise ValueError(f"--out {out}: {store} leads to {real}, outside the output folder, "
                         "through a symbolic link (jaxgear writes only inside it): remove the link")
    return store


def run_size(args) -> int:
    join_processes(args)
    try:
        spec, tables = load_sizing_spec(args.spec)
    except SchemaError as err:
        raise ValueError(f"{args.spec}: {err}") from None
    out = check_output_dir(args.out or os.path.join("jaxgear-out", tables["name"], "size"))
    writer = jax.process_index() == 0
    if writer:
        check_foreign_files(out, "size", force=args.force)
    store = _store_folder(out)
    made = not os.path.lexists(out)
    n = len(sizing.enumerate_candidates(spec))
    if args.write is not None and not 0 <= args.write < n:
        raise ValueError(f"--write {args.write}: out of range, allowed a candidate row 0 … "
                         f"{n - 1} (this spec enumerates {n})")
    if args.te is not None and args.te < 0:
        raise ValueError(f"--te {args.te}: out of range, allowed an integer >= 0 (the best "
                         "feasible candidates the transmission-error stage evaluates)")
    te_settings = sizing_te_settings(tables, args.te)
    if args.dynamics is not None and args.dynamics < 0:
        raise ValueError(f"--dynamics {args.dynamics}: out of range, allowed an integer >= 0 "
                         "(the candidates of the first Pareto fronts the dynamics stage runs)")
    dyn_settings = sizing_dynamics_settings(tables, args.dynamics)
    if args.sound is not None and args.sound < 0:
        raise ValueError(f"--sound {args.sound}: out of range, allowed an integer >= 0 (the "
                         "candidates of the first Pareto fronts the sound stage runs)")
    sound, sound_n = sizing_sound(tables, args.sound)
    _refuse_unstaged(spec, te_settings, dyn_settings, sound_n)
    bar = None if args.quiet or not writer else progress(
        total=n, desc=f"jaxgear size {tables['name']}", unit="candidate")

    def step(done, total):
        if bar is not None:
            bar.update(done - bar.n)

    t0 = time.perf_counter()
    try:
        table = sizing.size(spec, chunk=args.chunk, progress=step, store=store,
                            restart=args.force)
    finally:
        if bar is not None:
            bar.close()
    refining = bool(args.refine or spec.refine)
    if refining:
        bar = None if args.quiet else progress(total=n, desc=f"refine {tables['name']}",
                                               unit="candidate")
        try:
            table = sizing.refine(spec, table, progress=step)
        finally:
            if bar is not None:
                bar.close()
    seconds = time.perf_counter() - t0
    if not writer:
        return 0
    if args.write is not None:
        geometric = [k for k in sizing.GEOMETRIC
                     if table.failed[args.write, list(sizing.CHECKS).index(k)]]
        if geometric:
            kept = "nothing written"
            if made:  # the folder this run made holds only its store: both removed
                shutil.rmtree(store, ignore_errors=True)
                with contextlib.suppress(OSError):
                    os.rmdir(out)
            else:
                kept = f"no output written; the rated chunks kept in {STORE}/ for a rerun"
            raise ValueError(
                f"--write {args.write}: candidate {args.write} has no valid geometry "
                f"({', '.join(geometric)}): its case file would not load; allowed a candidate "
                "that fails none of " + ", ".join(sizing.GEOMETRIC) + " (sizing.csv's rejected "
                f"column; {kept})")
    table, te_seconds = _te_stage(spec, table, te_settings, args.quiet)
    table, curves, dyn_seconds = _dynamics_stage(spec, table, dyn_settings, args.quiet)
    table, heard, sound_seconds = _sound_stage(spec, tables, table, sound, sound_n, store,
                                               args)
    # the front after the stages that add objectives' columns (the TE and dynamics stages')
    front = sizing.pareto_front(table, spec.objectives, spec.chosen)
    table = dataclasses.replace(table, columns=table.columns | {"pareto_rank": front.rank})
    ranked = table.ranked()
    cols = table.columns
    summary = {
        "spec": tables["name"],
        "candidates": len(table),
        "feasible": int(table.feasible.sum()),
        "rejected_by": {k: int(table.failed[:, j].sum()) for j, k in enumerate(sizing.CHECKS)},
        "checks": sizing.CHECKS,
        "ranked": [int(i) for i in ranked],
        "blank_mass": "solid root cylinder plus half the annulus to the tip, ρ b π (d_a² + "
                      "d_f²)/8 per gear",
        "seconds": round(seconds, 3),
        "chunk": args.chunk,
        "processes": jax.process_count(),
        "devices": jax.device_count(),
        "store": f"{STORE}/: one file per finished chunk of {args.chunk} candidates; a rerun "
                 "of the same spec and chunk rates only the chunks missing",
        "te_stage": {
            "candidates": [int(i) for i in np.flatnonzero(cols["stage"] == "te")],
            "torque_Nm": (float(spec.operating.torque)
                          * np.asarray(te_settings.torque_fractions)).tolist(),
            "variables": list(sizing.TE_VARIABLES),
            "objective": "te_ptp at the rated torque (optimise.TePeakToPeak)",
            "max_iterations": te_settings.max_iterations,
            "mesh": sizing.CANDIDATE_MESH,
            "seconds": round(te_seconds, 3),
        },
    } | _pareto_summary(spec, table, front)
    summary["dynamics_stage"] = _dynamics_summary(spec, table, curves, dyn_seconds)
    if sound is not None:
        summary["sound_stage"] = _sound_summary(heard, sound_seconds, sound)
    if refining:
        summary |= {"refine_objective": spec.refine_objective,
                    "refined": int(table.columns["refined"].sum()),
                    "refine_converged": int(table.columns["refine_converged"].sum())}
    with staged_outputs(out, "size") as work:
        write_table(os.path.join(work, "sizing.csv"), table)
        _write_parquet(os.path.join(work, "sizing.parquet"), table)
        write_json(os.path.join(work, "sizing.json"), summary)
        _pareto_plots(work, table, front, tables["name"])
        if curves.rows.size:
            _dynamics_files(work, spec, table, curves, tables["name"])
        if heard is not None and heard.rows.size:
            _sound_file(work, heard)
        if args.write is not None:
            k = args.write
            row = {name: v[k] for name, v in cols.items()}
            with atomic_open(os.path.join(work, f"candidate_{k}.toml"), "w") as f:
                f.write(candidate_case_text(tables, spec, row, k))
            if row["stage"] == "te":  # its modified flanks beside (their rating differs)
                with atomic_open(os.path.join(work, f"candidate_{k}_modified.toml"), "w") as f:
                    f.write(candidate_case_text(tables, spec, row, k, modified=True))
            if sound is not None:  # its housed model, the sound stage's
                with atomic_open(os.path.join(work, f"candidate_{k}_housed.toml"), "w") as f:
                    f.write(housed_case_text(tables, spec, row, k, sound))
    if not args.quiet:
        print(f"{tables['name']}: {len(table)} candidates, {int(table.feasible.sum())} feasible "
              f"({seconds:.2f} s) → {out}/sizing.csv")
        if ranked.size:
            print("  (lightest first; S_H, S_F the least of the two gears)")
            print("    row   m_n  z1/z2     a (mm)  b (mm)  mass (kg)  S_H    S_F    ε_α    ε_β"
                  + ("    S_B" if "S_B" in cols else ""))
            for i in ranked[: args.top]:
                print(_line(int(i), cols))
        _print_te(table, te_seconds)
        _print_dynamics(spec, table, curves, dyn_seconds)
        _print_sound(table, heard, sound_seconds)
        if front.chosen is not None:
            k = front.chosen
            print(f"  chosen ({_rule_words(front)}): row {k}, "
                  + ", ".join(f"{n} {cols[n][k]:.4g}" for n, _ in front.objectives)
                  + f"; {front.front.size} on the front")
        if args.write is not None:
            print(f"  candidate {args.write} → {out}/candidate_{args.write}.toml")
            if cols["stage"][args.write] == "te":
                print(f"  its optimised flanks → {out}/candidate_{args.write}_modified.toml")
            if sound is not None:
                print(f"  its housed model → {out}/candidate_{args.write}_housed.toml")
    return 0


def _rule_words(front: sizing.ParetoFront) -> str:
    """How the chosen design was picked, in words."""
    names = ", ".join(f"{n} ({s})" for n, s in front.objectives)
    if front.rule == "knee":
        return f"the knee of the front of {names}"
    return f"the best {front.rule} on the front of {names}"


def _pareto_summary(spec, table: sizing.SizingTable, front: sizing.ParetoFront) -> dict:
    """sizing.json's objectives, front and chosen design (and the mesh loss's model)."""
    cols = table.columns
    chosen = None
    if front.chosen is not None:
        k = front.chosen
        keep = ("normal_module_m", "z1", "z2", "x1", "x2", "face_width_m", "centre_distance_m",
                "eps_alpha", "eps_beta", *(n for n, _ in front.objectives))
        chosen = {"row": k, "rule": front.rule, "words": _rule_words(front),
                  "columns": {n: cols[n][k].item() for n in dict.fromkeys(keep)}}
    out = {
        "objectives": [{"column": n, "sense": s} for n, s in front.objectives],
        "pareto_front": [int(i) for i in front.front],
        "chosen": chosen,
        "plots": _plot_names(front),
    }
    if spec.mesh_loss is not None:
        out["mesh_loss"] = ("ISO/TR 14179-2 closed form: P_VZP = mu_mZ H_V T1 omega1, Schlenk's "
                            "mu_mZ at the pitch point (or the given mu), Ohlendorf's H_V; teeth "
                            "sliding only")
    return out


def _plot_names(front: sizing.ParetoFront) -> list[str]:
    """The figures' file names: one per pair of objectives, and the contact ratios'; none
    without a front (no feasible candidate: nothing to draw)."""
    if front.chosen is None:
        return []
    pairs = itertools.combinations([n for n, _ in front.objectives], 2)
    return [f"pareto_{x}__{y}.png" for x, y in pairs] + ["contact_ratios.png"]


def _pareto_plots(folder: str, table: sizing.SizingTable, front: sizing.ParetoFront,
                  name: str) -> None:
    """The Pareto figures (:func:`_plot_names`) into ``folder`` (atomically, the plots' rule)."""
    from ._plots import contact_ratio_plot, pareto_pair_plot

    words = {n: (label, factor) for n, (_, label, factor) in sizing.OBJECTIVES.items()}
    senses = dict(front.objectives)
    n_feasible = int(table.feasible.sum())
    title = f"{name}: {n_feasible} feasible of {len(table)} candidates"
    names = _plot_names(front)
    if not names:
        return
    for (x, y), file in zip(itertools.combinations(senses, 2), names, strict=False):
        pareto_pair_plot(os.path.join(folder, file), table.columns, table.feasible, front.rank,
                         front.chosen, x, y, words=words, senses=senses, title=title)
    contact_ratio_plot(os.path.join(folder, names[-1]), table.columns, table.feasible,
                       front.rank, front.chosen, front.objectives, words=words,
                       title=f"{title}: the objectives over the contact ratios")


def _te_stage(spec, table, settings, quiet):
    """The transmission-error stage (:func:`jaxgear.sizing.te_stage`) with a progress bar;
    (the table with its columns, seconds)."""
    k = min(settings.candidates, int(table.feasible.sum()))
    bar = None if quiet or k == 0 else progress(total=k, desc="transmission-error stage",
                                                unit="candidate")

    def step(done, total):
        if bar is not None:
            bar.update(done - bar.n)

    t0 = time.perf_counter()
    try:
        table = sizing.te_stage(spec, table, settings, progress=step)
    finally:
        if bar is not None:
            bar.close()
    return table, time.perf_counter() - t0


def _print_te(table, seconds: float) -> None:
    c = table.columns
    rows = np.flatnonzero(np.char.startswith(c["stage"].astype(str), "te"))
    if not rows.size:
        return
    print(f"  transmission-error stage ({seconds:.1f} s): TE peak-to-peak (µm) at the rated "
          "torque, the largest over the range; plain → tip relief and crowning optimised")
    print("    row   plain  (max)   modified  (max)   relief (µm, Γ)   crowning (µm)")
    for i in rows:
        if c["stage"][i] != "te":
            print(f"{i:>7d}  failed: a contact solve or the optimiser (stage {c['stage'][i]})")
            continue
        print(f"{i:>7d}  {c['te_ppk_m'][i] * 1e6:6.3f} ({c['te_ppk_max_m'][i] * 1e6:6.3f})"
              f"  {c['te_ppk_modified_m'][i] * 1e6:6.3f} ({c['te_ppk_max_modified_m'][i] * 1e6:6.3f})"
              f"   {c['tip_relief_depth_m'][i] * 1e6:6.2f}, {c['tip_relief_extent'][i]:4.2f}"
              f"     {c['crowning_depth_m'][i] * 1e6:6.3f}")


def _refuse_unstaged(spec, te_settings, dyn_settings, sound: int) -> None:
    """One line where ``--te 0``, ``--dynamics 0`` or ``--sound 0`` turns off the stage of one
    of the spec's objectives (its front would be empty), before any work."""
    bad = unstaged_objective(spec.objectives, {"te": te_settings.candidates,
                                               "dynamics": dyn_settings.candidates,
                                               "sound": sound})
    if bad is None:
        return
    name, stage = bad
    words, _, option = SIZING_STAGES[stage]
    raise ValueError(f"{option} 0: the spec's objective {name!r} is a column of {words}, which "
                     f"this turns off: allowed {option} >= 1 with it ([pareto])")


def _dynamics_stage(spec, table, settings, quiet):
    """The dynamics stage (:func:`jaxgear.sizing.dynamics_stage`) with a progress bar over its
    candidates' speeds; (the table with its columns, the curves, seconds)."""
    k = min(settings.candidates, int(table.feasible.sum()))
    bar = None if quiet or k == 0 else progress(total=k * (settings.speeds + 1),
                                                desc="dynamics stage", unit="speed")

    def step(done, total):
        if bar is not None:
            bar.total = total
            bar.update(done - bar.n)

    t0 = time.perf_counter()
    try:
        table, curves = sizing.dynamics_stage(spec, table, settings, progress=step)
    finally:
        if bar is not None:
            bar.close()
    return table, curves, time.perf_counter() - t0


def _dynamics_summary(spec, table, curves, seconds: float) -> dict:
    """sizing.json's ``dynamics_stage``: what ran, on which model, over which speeds."""
    return {
        "candidates": [int(i) for i in curves.rows],
        "flanks": list(curves.flanks),
        "selection": "the first Pareto fronts over the objectives the stage does not add "
                     "(jaxgear.sizing.dynamics_selection)",
        "model": "lumped torsional pair (jaxgear sweep's of the written case): disc inertias, "
                 "composite damping 7 % mesh / 1 % structure, the rated torque",
        "sweep": "jaxgear.dynamics.settled_sweep, each speed until it settles (Newmark, "
                 "automatic steps, exact contact, 4 kept periods)",
        "whine": f"jaxgear.dynamics.whine_response (HarmonicBalance): the dynamic mesh force's "
                 f"RMS over the mesh orders 1-{sizing.WHINE_ORDERS}",
        "speeds_rad_s": curves.speeds.tolist(),
        "speed_rad_s": float(spec.operating.speed),
        "curves": "dynamics.csv",
        "seconds": round(seconds, 3),
    }


def _dynamics_files(folder: str, spec, table, curves, name: str) -> None:
    """``dynamics.csv`` (per candidate run and speed: K_v, the whine force and its first mesh
    order, settled) and
    ``dynamic_factor.png`` into ``folder`` (atomically)."""
    from ._plots import sizing_dynamics_plot

    with atomic_open(os.path.join(folder, "dynamics.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["candidate", "flanks", "speed_rad_s", "speed_rpm", "dynamic_factor",
                    "whine_force_N", "whine_order1_N", "settled"])
        for j, i in enumerate(curves.rows):
            for s, speed in enumerate(curves.speeds):
                kv, wf = curves.dynamic_factor[j, s], curves.whine_force[j, s]
                f1 = curves.first_order[j, s]
                w.writerow([int(i), curves.flanks[j], repr(float(speed)),
                            repr(float(speed) * 30 / math.pi),
                            "" if math.isnan(kv) else repr(float(kv)),
                            "" if math.isnan(wf) else repr(float(wf)),
                            "" if math.isnan(f1) else repr(float(f1)),
                            int(curves.settled[j, s])])
    sizing_dynamics_plot(os.path.join(folder, "dynamic_factor.png"), curves, table.columns,
                        float(spec.operating.speed),
                        title=f"{name}: the dynamics stage's candidates")


def _print_dynamics(spec, table, curves, seconds: float) -> None:
    if not curves.rows.size:
        return
    c = table.columns
    rpm = 30 / math.pi
    print(f"  dynamics stage ({seconds:.1f} s): lumped torsional model, {curves.speeds.size} "
          f"speeds {curves.speeds[0] * rpm:.0f}-{curves.speeds[-1] * rpm:.0f} 1/min "
          "(dynamics.csv, dynamic_factor.png)")
    print("    row  flanks     K_v max  K_v at speed  resonance (1/min)  whine (N)")
    for i in curves.rows:
        if c["dynamics_stage"][i] == "failed":
            print(f"{i:>7d}  failed: a speed did not run to its end (dynamics.csv)")
            continue
        line = (f"{i:>7d}  {c['dynamics_stage'][i]:<9s} {c['dynamic_factor_max'][i]:7.4f}  "
                f"{c['dynamic_factor_at_speed'][i]:12.4f}  "
                f"{c['resonance_speed_rad_s'][i] * rpm:17.0f}  {c['whine_force_N'][i]:9.2f}")
        if c["dynamics_unsettled"][i] > 0:
            line += f"  ({int(c['dynamics_unsettled'][i])} speeds not settled)"
        print(line)


def _sound_stage(spec, tables, table, section, candidates, store, args):
    """The sound stage (:func:`jaxgear.cli._sizing_sound.sound_stage`, its results in
    ``store/sound/``) with a progress bar over its candidates; (the table with its columns, the
    curves, seconds). A spec without ``[sound]``: no stage, no columns (the table as it was,
    None)."""
    if section is None:
        return table, None, 0.0
    k = min(candidates, int(table.feasible.sum()))
    bar = None if args.quiet or k == 0 else progress(total=k, desc="sound stage",
                                                     unit="candidate")

    def step(done, total, what):
        if bar is not None:
            bar.total = total
            bar.set_postfix_str(what)
            bar.update(done - bar.n)

    t0 = time.perf_counter()
    try:
        table, heard = sound_stage(spec, tables, table, section, candidates,
                                   os.path.join(store, "sound"), restart=args.force,
                                   progress=step)
    finally:
        if bar is not None:
            bar.close()
    return table, heard, time.perf_counter() - t0


def _sound_summary(heard, seconds: float, section) -> dict:
    """sizing.json's ``sound_stage``: what ran, on which model, over which speeds (with
    ``[sound] sound_power = true``: the radiated sound power's settings)."""
    radiation = section.radiation()
    power = {} if radiation is None else {"sound_power": {
        "method": radiation.method,
        "frequencies": radiation.frequencies,
        "rank": radiation.rank,
        "what": "the housing's closed outer skin radiating by [acoustics] (jaxgear run's, "
                "written into each housed case), the overall L_W over the orders in the "
                "housing's band at every speed, not A-weighted; sound_power_peak_dB its largest "
                "over the speeds",
    }}
    return power | {
        "candidates": [int(i) for i in heard.rows],
        "flanks": list(heard.flanks),
        "failed": {str(int(i)): why for i, why in zip(heard.rows, heard.failed, strict=True)
                   if why},
        "selection": "the first Pareto fronts over the objectives the stage does not add "
                     "(jaxgear.sizing.dynamics_selection, stage='sound')",
        "model": "each candidate's housed case (store/sound/candidate_K_housed.toml, "
                 "jaxgear size --write K writes it): the lumped 3D pair on the [sound] layout's "
                 "shafts and bearings in a box housing round its tip circles (fem_prep, "
                 "condensed, cached), run as jaxgear run runs it",
        "erp": "the housing's outer skin, ERP = ½ ρ c Σ |v_n|² A, the overall over the orders in "
               "the housing's band (cut-off / 1.5); erp_peak_dB its largest over the speeds",
        "speeds_rad_s": heard.speeds.tolist(),
        "curves": "sound.csv",
        "candidate_seconds": [None if math.isnan(t) else round(float(t), 3)
                              for t in heard.seconds],
        "seconds": round(seconds, 3),
    }


def _sound_file(folder: str, heard) -> None:
    """``sound.csv``: per candidate run and speed, the overall ERP, the contact loss and the
    overall radiated sound power L_W (empty without ``[sound] sound_power = true``)."""
    with atomic_open(os.path.join(folder, "sound.csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["candidate", "flanks", "speed_rad_s", "speed_rpm", "overall_erp_dB",
                    "contact_loss", "overall_sound_power_dB"])
        for j, i in enumerate(heard.rows):
            if heard.failed[j]:
                continue
            for s, speed in enumerate(heard.speeds):
                v, p = heard.overall_erp_db[j, s], heard.overall_sound_power_db[j, s]
                w.writerow([int(i), heard.flanks[j], repr(float(speed)),
                            repr(float(speed) * 30 / math.pi),
                            "" if math.isnan(v) else repr(float(v)),
                            int(heard.contact_loss[j, s]),
                            "" if math.isnan(p) else repr(float(p))])


def _print_sound(table, heard, seconds: float) -> None:
    if heard is None or not heard.rows.size:
        return
    c = table.columns
    rpm = 30 / math.pi
    print(f"  sound stage ({seconds:.1f} s): housed lumped 3D model, ERP of the housing's skin "
          "(sound.csv, store/sound/)")
    print("    row  flanks     ERP peak (dB re 1 pW)  at (1/min)  contact loss  time (s)")
    for j, i in enumerate(heard.rows):
        if heard.failed[j]:
            print(f"{i:>7d}  failed: {heard.failed[j]}")
            continue
        print(f"{i:>7d}  {c['sound_stage'][i]:<9s} {c['erp_peak_dB'][i]:21.2f}  "
              f"{c['erp_peak_speed_rad_s'][i] * rpm:10.0f}  "
              f"{int(c['sound_contact_loss'][i]):12d}  {heard.seconds[j]:8.1f}"
              + ("" if math.isnan(c["sound_power_peak_dB"][i]) else
                 f"  sound power peak {c['sound_power_peak_dB'][i]:.2f} dB re 1 pW at "
                 f"{c['sound_power_peak_speed_rad_s'][i] * rpm:.0f} 1/min"))
