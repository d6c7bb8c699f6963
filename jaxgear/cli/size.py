"""``jaxgear size SPEC.toml --out DIR``: every candidate of a sizing spec rated
(:func:`jaxgear.sizing.size`), the table of them all written (``sizing.csv``; ``sizing.parquet``
the same for queries; ``sizing.json`` the spec's summary and the ranked feasible
candidates), the feasible ones printed lightest first; ``--write K`` writes candidate K (a
row number of the table) as a case file, ``candidate_K.toml``, that ``jaxgear run`` rates to
the same numbers (docs/sizing.md)."""

from __future__ import annotations

import csv
import math
import os
import time

import numpy as np

from .. import sizing
from ..io import SchemaError, atomic_open, candidate_case_text, load_sizing_spec, write_json
from ._paths import check_foreign_files, check_output_dir, staged_outputs
from ._progress import progress

__all__ = ["run_size", "write_table"]


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
                row.append("" if isinstance(v, float) and math.isnan(v) else repr(v))
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
            f"{c['eps_beta'][i]:5.3f}")


def run_size(args) -> int:
    try:
        spec, tables = load_sizing_spec(args.spec)
    except SchemaError as err:
        raise ValueError(f"{args.spec}: {err}") from None
    out = check_output_dir(args.out or os.path.join("jaxgear-out", tables["name"], "size"))
    check_foreign_files(out, "size", force=args.force)
    n = len(sizing.enumerate_candidates(spec))
    if args.write is not None and not 0 <= args.write < n:
        raise ValueError(f"--write {args.write}: out of range, allowed a candidate row 0 … "
                         f"{n - 1} (this spec enumerates {n})")
    bar = None if args.quiet else progress(total=n, desc=f"jaxgear size {tables['name']}",
                                           unit="candidate")

    def step(done, total):
        if bar is not None:
            bar.update(done - bar.n)

    t0 = time.perf_counter()
    try:
        table = sizing.size(spec, progress=step)
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
    ranked = table.ranked()
    cols = table.columns
    if args.write is not None:
        geometric = [k for k in sizing.GEOMETRIC
                     if table.failed[args.write, list(sizing.CHECKS).index(k)]]
        if geometric:
            raise ValueError(
                f"--write {args.write}: candidate {args.write} has no valid geometry "
                f"({', '.join(geometric)}): its case file would not load; allowed a candidate "
                "that fails none of " + ", ".join(sizing.GEOMETRIC) + " (sizing.csv's rejected "
                "column; nothing written)")
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
    }
    if refining:
        summary |= {"refine_objective": spec.refine_objective,
                    "refined": int(table.columns["refined"].sum()),
                    "refine_converged": int(table.columns["refine_converged"].sum())}
    with staged_outputs(out, "size") as work:
        write_table(os.path.join(work, "sizing.csv"), table)
        _write_parquet(os.path.join(work, "sizing.parquet"), table)
        write_json(os.path.join(work, "sizing.json"), summary)
        if args.write is not None:
            k = args.write
            row = {name: v[k] for name, v in cols.items()}
            with atomic_open(os.path.join(work, f"candidate_{k}.toml"), "w") as f:
                f.write(candidate_case_text(tables, spec, row, k))
    if not args.quiet:
        print(f"{tables['name']}: {len(table)} candidates, {int(table.feasible.sum())} feasible "
              f"({seconds:.2f} s) → {out}/sizing.csv")
        if ranked.size:
            print("  (lightest first; S_H, S_F the least of the two gears)")
            print("    row   m_n  z1/z2     a (mm)  b (mm)  mass (kg)  S_H    S_F    ε_α    ε_β")
            for i in ranked[: args.top]:
                print(_line(int(i), cols))
        if args.write is not None:
            print(f"  candidate {args.write} → {out}/candidate_{args.write}.toml")
    return 0
