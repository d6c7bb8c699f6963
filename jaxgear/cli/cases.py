"""``jaxgear cases``: the embedded cases as a table (rated or not, run time, what each is),
or one case's file (printed or written).

The listing reads the case folder's names only (no model, no JAX: it answers at once); what
each case is (:func:`jaxgear.cli.case_line` of the loaded case), whether it is rated and how
long its ``jaxgear run`` takes are stored in :data:`CASE_INDEX` (the lines and ratings are
checked against the case files by the tests; the times are measured: :data:`MEASURED`), and how
long a first run takes longer when the case's FE bodies and housing are not built yet in
:data:`FE_BUILD` (:data:`FE_BUILD_MEASURED`; the tests check it against its benchmark's record
and that exactly the cases with FE bodies or a housing have one)."""

from __future__ import annotations

import importlib.resources

__all__ = ["CASE_INDEX", "FE_BUILD", "FE_BUILD_MEASURED", "MEASURED", "case_table", "run_cases"]

#: where :data:`CASE_INDEX`'s run times come from
MEASURED = (
    "wall time of `jaxgear run CASE --quiet`, first run (empty compilation cache) and second, on "
    "an idle 2-core CPU (AMD EPYC), measured 2026-11-27 (docs/bench/bench_run_cases_idle*.json); "
    "'~' marks an estimate from the CPU seconds (user + system) of both runs measured on the same "
    "machine under load (1-minute load average 2.6-13.6) on 2026-11-28 "
    "(docs/bench/bench_run_cases_loaded_s42.json): idle wall time taken as 0.76 of the first "
    "run's CPU seconds and 0.85 of the second's, the medians of those ratios over the cases "
    "measured idle (0.71-0.80 and 0.77-1.02); two-stage and nrel-5mw-gearbox measured idle on "
    "2026-11-28 on that day's host of the 2-core VM (an Intel Xeon, about 2x the AMD EPYC's "
    "speed on the test suite; docs/bench/bench_gearbox_coupled.json, and the two-stage "
    "timings beside docs/bench/bench_run_cases_two_stage_settled.json). "
    "power-helical-housed estimated alike from its runs on 2026-11-28 under load "
    "(59 s and 29 s of CPU), nrel-5mw-stage3-housed alike on 2026-11-28 (78 s and 36 s of "
    "CPU); nrel-5mw-planetary-housed alike on 2026-11-29 (101 s and 68 s of CPU); "
    "fzg-h951 alike on 2026-11-29 (23 s and 9 s of CPU); "
    "nrel-5mw-star alike on 2026-11-29 (73 s and 44 s of CPU); "
    "two-stage-housed from one first run under load on 2026-11-28 (300 s of CPU; "
    "its second run taken at two-stage's ratio of second to first, not measured). Under load, "
    "wall time is "
    "several times longer (nrel-5mw-planetary: 703 s and 217 s at a load of 8-14)"
)

#: name -> (what the case is: :func:`jaxgear.cli.case_line`; rated: ``yes`` where its file has
#: ``[rating]`` (``jaxgear run`` writes rating.md), a gearbox's rated stages, else ``-``; first
#: run, s; second run, s; measured, else estimated: :data:`MEASURED`)
CASE_INDEX: dict[str, tuple[str, str, float, float, bool]] = {
    "accessory-idler-train": (
        "train z 45/61/86, m_n 1.5 mm, T 80 N·m (input), weber stiffness, torsional scene",
        "-",
        23,
        12,
        True,
    ),
    "accessory-spur": (
        "z 45/86, m_n 1.5 mm, β 0.0°, T 80 N·m, weber stiffness, lumped3d scene",
        "-",
        26,
        15,
        True,
    ),
    "accessory-spur-flexible": (
        "z 45/86, m_n 1.5 mm, β 0.0°, T 80 N·m, weber stiffness, lumped3d scene with condensed "
        "bodies",
        "-",
        19,
        14,
        True,
    ),
    "flexible-idler": (
        "train z 45/61/86, m_n 1.5 mm, T 80 N·m (input), weber stiffness, lumped3d scene",
        "-",
        16,
        10,
        True,
    ),
    "fzg-h951": (
        "z 38/57, m_n 1.75 mm, β 15.0°, T 200 N·m, weber stiffness",
        "yes",
        18,
        8,
        False,
    ),
    "lin-parker-1999": (
        "planetary z sun 28, ring 92 (lumped), 3 planets, ring fixed, sun → carrier, T 100 N·m "
        "(input)",
        "-",
        17,
        15,
        False,
    ),
    "nrel-5mw-gearbox": (
        "gearbox of 3 stages (nrel-5mw-planetary, nrel-5mw-stage2, nrel-5mw-stage3), ratio "
        "1:96.3542",
        "3 of 3 stages",
        104,
        58,
        True,
    ),
    "nrel-5mw-planetary": (
        "planetary z 19/17/-56, 3 planets, ring fixed, carrier → sun, T 3.946e+06 N·m (input)",
        "yes",
        76,
        37,
        False,
    ),
    "nrel-5mw-planetary-housed": (
        "planetary z 19/17/-56, 3 planets, ring fixed, carrier → sun, T 3.946e+06 N·m (input) "
        "on a flexible housing",
        "-",
        77,
        58,
        False,
    ),
    "nrel-5mw-star": (
        "planetary z 19/17/-56, 3 planets, carrier fixed, sun → ring, T 999653 N·m (input)",
        "-",
        56,
        37,
        False,
    ),
    "nrel-5mw-stage2": (
        "planetary z 18/36/-93, 3 planets, ring fixed, carrier → sun, T 999650 N·m (input)",
        "yes",
        27,
        14,
        True,
    ),
    "nrel-5mw-stage3": (
        "z 24/95, m_n 14 mm, β 10.0°, T 40953 N·m, iso6336 stiffness",
        "yes",
        13,
        11,
        True,
    ),
    "nrel-5mw-stage3-housed": (
        "z 24/95, m_n 14 mm, β 10.0°, T 40953 N·m, iso6336 stiffness, lumped3d scene on a "
        "flexible housing",
        "yes",
        60,
        31,
        False,
    ),
    "power-helical": (
        "z 35/68, m_n 2.5 mm, β 12.0°, T 310 N·m, weber stiffness",
        "yes",
        12,
        10,
        True,
    ),
    "power-helical-flexible": (
        "z 35/68, m_n 2.5 mm, β 12.0°, T 310 N·m, weber stiffness, lumped3d scene with condensed "
        "bodies",
        "-",
        24,
        16,
        True,
    ),
    "power-helical-housed": (
        "z 35/68, m_n 2.5 mm, β 12.0°, T 310 N·m, weber stiffness, lumped3d scene on a flexible "
        "housing",
        "yes",
        45,
        25,
        False,
    ),
    "two-stage-housed": (
        "train z 28/127/35/68, m_n 1.5/2.5 mm, T 70 N·m (input), weber stiffness, lumped3d scene "
        "on a flexible housing (hst = high-speed train, stage 1, lst = low-speed train, stage 2)",
        "-",
        230,
        200,
        False,
    ),
    "two-stage": (
        "train z 28/127/35/68, m_n 1.5/2.5 mm, T 70 N·m (input), weber stiffness, lumped3d scene "
        "(hst = high-speed train, stage 1, lst = low-speed train, stage 2)",
        "-",
        82,
        73,
        True,
    ),
}


#: where :data:`FE_BUILD`'s seconds come from
FE_BUILD_MEASURED = (
    "the seconds of building the case's FE parts that fem_prep caches ($FEM_PREP_CACHE, "
    "default ~/.cache/jaxgear/fem_prep), which a first run on a fresh install builds before its "
    "own work (RUN assumes them built): its condensed bodies, measured idle on the 2-core AMD "
    "EPYC on 2026-11-27 (bodies_s of docs/bench/bench_run_cases_idle_flexible.json, the "
    "bodies built in a process of their own, the runs of RUN's figures after them); its "
    "housing, estimated as 1.7 x the CPU seconds of its build measured under load (1-minute "
    "load average 12-16) on 2026-11-29 (the cold-builds benchmark, "
    "docs/bench/bench_cold_builds.json), 1.7 the ratio of the idle wall time to those CPU "
    "seconds of the three bodies' builds measured both ways (1.68-1.71). Not counted: the "
    "tooth and fillet FE tables of the fe2d stiffness and of [rating], cached alike "
    "(power-helical's: 1.4 CPU s in the same record)"
)

#: name -> (seconds of building the case's condensed bodies and housing on an empty fem_prep
#: cache, measured idle (True) or estimated (False): :data:`FE_BUILD_MEASURED`); a case not
#: named has none
FE_BUILD: dict[str, tuple[float, bool]] = {
    "accessory-spur-flexible": (62.9, True),
    "flexible-idler": (26.3, True),
    "power-helical-flexible": (136.5, True),
    "power-helical-housed": (2.9, False),
    "nrel-5mw-stage3-housed": (4.4, False),
    "nrel-5mw-planetary-housed": (0.7, False),
    "two-stage-housed": (6.7, False),
}


def _folder():
    """The embedded cases' folder (as :func:`jaxgear.io.list_cases` reads it)."""
    return importlib.resources.files("jaxgear") / "cases"


def case_table() -> list[str]:
    """The lines of ``jaxgear cases``: a header, one row per embedded case (name, rated, run
    time of its first and second ``jaxgear run``, what it is: :data:`CASE_INDEX`; a case not
    in it, ``?``), and a note on where the times come from. Reads the folder's names only."""
    # fem_prep.schema.embedded_names' rule (fem_prep itself not imported: seconds)
    names = sorted(p.name[:-5] for p in _folder().iterdir() if p.name.endswith(".toml"))
    rows = [("NAME", "RATED", "RUN 1st/2nd", "COLD", "WHAT")]
    for name in names:
        what, rated, first, second, measured = CASE_INDEX.get(name, ("?", "?", 0, 0, False))
        run = ("" if measured else "~") + f"{first:.0f}/{second:.0f} s"
        build, build_measured = FE_BUILD.get(name, (None, True))
        mark = "" if measured and build_measured else "~"
        cold = "-" if build is None else f"{mark}{first + build:.0f} s"
        rows.append((name, rated, run, cold, what))
    widths = [max(len(r[k]) for r in rows) for k in range(4)]
    lines = ["  ".join(c.ljust(w) for c, w in zip(r[:4], widths)) + "  " + r[4] for r in rows]
    lines.append(
        "RUN: jaxgear run CASE, first run / second run (compilation cache filled), wall seconds "
        "on an idle 2-core CPU (several times longer on a loaded one), the case's FE bodies and "
        "housing built already; '~' an estimate from CPU seconds measured under load. COLD: the "
        "first run when they are not (a fresh install: the run builds them first), RUN's first "
        "plus the build's time; '-': the case has none. RATED: writes rating.md."
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
