"""``jaxgear cases``: the embedded cases as a table (kind, rated or not, run time, what each is),
or one case's file (printed or written).

The listing reads the case files' text only (no model, no JAX: it answers at once); what each
case is (:func:`jaxgear.cli.case_line` of the loaded case) and how long its ``jaxgear run``
takes are stored in :data:`CASE_INDEX` (the lines are checked against the loaded cases by the
tests; the times are measured, see there)."""

from __future__ import annotations

import importlib.resources
import tomllib

__all__ = ["CASE_INDEX", "MEASURED", "case_table", "run_cases"]

#: where :data:`CASE_INDEX`'s run times come from
MEASURED = (
    "wall time of `jaxgear run CASE --quiet`, first run (empty compilation cache) and second, on "
    "an idle 2-core CPU (AMD EPYC), measured 2026-11-27 (docs/bench/bench_run_cases_idle*.json); "
    "'~' marks an estimate (measured under load: idle wall time taken as 3/4 of the CPU seconds "
    "of docs/bench/bench_run_cases.json, 2026-11-26)"
)

#: name -> (what the case is: :func:`jaxgear.cli.case_line`; first run, s; second run, s;
#: measured, else estimated: :data:`MEASURED`)
CASE_INDEX: dict[str, tuple[str, float, float, bool]] = {
    "accessory-idler-train": (
        "train z 45/61/86, m_n 1.5 mm, T 80 N·m (input), weber stiffness, torsional scene",
        23,
        12,
        True,
    ),
    "accessory-spur": (
        "z 45/86, m_n 1.5 mm, β 0.0°, T 80 N·m, weber stiffness, lumped3d scene",
        26,
        15,
        True,
    ),
    "accessory-spur-flexible": (
        "z 45/86, m_n 1.5 mm, β 0.0°, T 80 N·m, weber stiffness, lumped3d scene with condensed "
        "bodies",
        19,
        14,
        True,
    ),
    "flexible-idler": (
        "train z 45/61/86, m_n 1.5 mm, T 80 N·m (input), weber stiffness, lumped3d scene",
        16,
        10,
        True,
    ),
    "lin-parker-1999": (
        "planetary z sun 28, ring 92 (lumped), 3 planets, ring fixed, sun → carrier, T 100 N·m "
        "(input)",
        7,
        6,
        False,
    ),
    "nrel-5mw-gearbox": (
        "gearbox of 3 stages (nrel-5mw-planetary, nrel-5mw-stage2, nrel-5mw-stage3), ratio "
        "1:96.3542",
        44,
        26,
        True,
    ),
    "nrel-5mw-planetary": (
        "planetary z 19/17/-56, 3 planets, ring fixed, carrier → sun, T 3.946e+06 N·m (input)",
        9,
        8,
        False,
    ),
    "nrel-5mw-stage2": (
        "planetary z 18/36/-93, 3 planets, ring fixed, carrier → sun, T 999650 N·m (input)",
        27,
        14,
        True,
    ),
    "nrel-5mw-stage3": (
        "z 24/95, m_n 14 mm, β 10.0°, T 40953 N·m, iso6336 stiffness",
        13,
        11,
        True,
    ),
    "power-helical": (
        "z 35/68, m_n 2.5 mm, β 12.0°, T 310 N·m, weber stiffness",
        12,
        10,
        True,
    ),
    "power-helical-flexible": (
        "z 35/68, m_n 2.5 mm, β 12.0°, T 310 N·m, weber stiffness, lumped3d scene with condensed "
        "bodies",
        24,
        16,
        True,
    ),
    "two-stage": (
        "train z 28/127/35/68, m_n 1.5/2.5 mm, T 70 N·m (input), weber stiffness, lumped3d scene "
        "(hst = high-speed train, stage 1, lst = low-speed train, stage 2)",
        74,
        65,
        True,
    ),
}


def _folder():
    """The embedded cases' folder (as :func:`jaxgear.io.list_cases` reads it)."""
    return importlib.resources.files("jaxgear") / "cases"


def _kind(data: dict) -> str:
    """A case file's kind by its tables: gearbox (``[[stages]]``), planetary (``[planetary]``),
    train (``[[gears]]``/``[[meshes]]``), else pair (:func:`jaxgear.io.load_case` reads them so)."""
    if "stages" in data:
        return "gearbox"
    if "planetary" in data:
        return "planetary"
    return "train" if "gears" in data or "meshes" in data else "pair"


def _rated(data: dict, files: dict[str, dict]) -> str:
    """``yes`` for a case with ``[rating]`` (``jaxgear run`` writes rating.md), a gearbox's
    rated stages (``2 of 3 stages``), else ``-``."""
    if "rating" in data:
        return "yes"
    stages = data.get("stages")
    if isinstance(stages, list):
        rated = sum("rating" in files.get(s.get("case"), {}) for s in stages if isinstance(s, dict))
        return f"{rated} of {len(stages)} stages" if rated else "-"
    return "-"


def case_table() -> list[str]:
    """The lines of ``jaxgear cases``: a header, one row per embedded case (name, kind, rated,
    run time of its first and second ``jaxgear run`` from :data:`CASE_INDEX`, what it is), and
    a note on where the times come from. Reads the files' text only."""
    folder = _folder()
    files = {
        p.name[:-5]: tomllib.loads(p.read_text("utf-8"))
        for p in sorted(folder.iterdir(), key=lambda p: p.name[:-5])
        if p.name.endswith(".toml")
    }
    rows = [("NAME", "KIND", "RATED", "RUN 1st/2nd", "WHAT")]
    for name, data in files.items():
        what, first, second, measured = CASE_INDEX.get(name, ("", None, None, False))
        if first is None:
            run = "?"
        else:
            run = ("" if measured else "~") + f"{first:.0f}/{second:.0f} s"
        rows.append((name, _kind(data), _rated(data, files), run, what))
    widths = [max(len(r[k]) for r in rows) for k in range(4)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r[:4], widths)) + "  " + r[4] for r in rows]
    lines.append(
        "RUN: jaxgear run CASE, first run / second run (compilation cache filled), idle 2-core "
        "CPU; '~' an estimate. RATED: writes rating.md."
    )
    return lines


def run_cases(args) -> int:
    """``jaxgear cases``: the table of :func:`case_table`; with NAME its case file (to stdout or,
    with ``--write FILE``, to a new file to start from: ``jaxgear run FILE`` runs it)."""
    if args.name is None:
        if args.write is not None:
            raise ValueError("--write needs a case NAME (jaxgear cases NAME --write FILE)")
        print("\n".join(case_table()))
        return 0
    from fem_prep.schema import embedded_text, print_or_write  # fem_prep: for a file only

    text = embedded_text(_folder(), args.name, "case")
    what = f"embedded case {args.name!r}"
    print_or_write(text, args.write, force=args.force, what=what, next_command="jaxgear run")
    return 0
