"""The ``jaxgear`` command line's options and its table of commands.

Every subcommand's options are declared here and nothing is computed (``optimise`` and
``master-curve`` declare theirs in :mod:`._optimise_options`, which imports nothing either). Each command is a name in :data:`COMMANDS`, mapped to the function that
runs it as ``"module:function"``; :func:`jaxgear.cli.main` imports that module once, after the
options are checked (:func:`._options.check_options`).

This module imports neither the model nor JAX: :func:`build_parser` adds the options of the
one subcommand on the command line (:func:`command_of`), so that ``jaxgear --help`` and a
subcommand's ``--help`` need nothing else. Speeds: ``--speeds``/``--speed`` in rad/s,
``--speeds-rpm``/``--speed-rpm`` in 1/min (the case files' ``speed_rpm``), one or the other.
"""

from __future__ import annotations

import argparse
import sys
import dataclasses
import textwrap
from importlib.metadata import PackageNotFoundError, version

__all__ = [
    "ALL",
    "BENCHMARKS",
    "COMMANDS",
    "SOLVER_NAMES",
    "Command",
    "build_parser",
    "command_of",
]


@dataclasses.dataclass(frozen=True)
class Command:
    """A subcommand: ``target``, the function that runs it (``"module:function"``, called with
    the parsed arguments, returns the exit status); whether it computes with JAX (float64
    and the persistent compilation cache are switched on before it runs: all but ``prep`` and
    ``cases``); whether it needs the model (the package :mod:`jaxgear`, JAX and equinox,
    loaded before it runs, its options checked: all but ``cases``, which reads the case files'
    text only)."""

    target: str
    jax: bool = True
    model: bool = True


#: every subcommand by its name on the command line
COMMANDS = {
    "run": Command("jaxgear.cli.run:run_command"),
    "cases": Command("jaxgear.cli.cases:run_cases", jax=False, model=False),
    "optimise": Command("jaxgear.cli._optimise:run_optimise"),
    "master-curve": Command("jaxgear.cli._optimise:run_master_curve"),
    "sweep": Command("jaxgear.cli.sweep:run_sweep"),
    "modes": Command("jaxgear.cli.modes:run_modes"),
    "robust": Command("jaxgear.cli.robust:run_robust"),
    "size": Command("jaxgear.cli.size:run_size"),
    "bench": Command("jaxgear.cli.bench:run_bench"),
    "prep": Command("jaxgear.cli.bench:run_prep", jax=False),
}

#: ``jaxgear bench WHAT``: the function that runs it, in the source checkout's benchmark package
#: (:mod:`jaxgear.cli.bench` finds it)
BENCHMARKS = {
    "quasi-static": "bench_quasi_static",
    "optimise": "bench_optimise",
    "dynamics": "bench_dynamics",
    "hybrid": "bench_hybrid",
    "hybrid-sweep": "bench_hybrid_sweep",
    "modal-basis": "bench_modal_basis",
    "stiffness": "bench_stiffness",
    "trains": "bench_trains",
    "robust": "bench_robust",
    "xla-cache": "bench_xla_cache",
}

#: ``jaxgear sweep --solver``: Newmark or a diffrax solver
SOLVER_NAMES = [
    "newmark",
    "tsit5",
    "dopri5",
    "dopri8",
    "bosh3",
    "heun",
    "midpoint",
    "ralston",
    "euler",
    "kvaerno3",
    "kvaerno4",
    "kvaerno5",
    "implicit_euler",
]

#: ``jaxgear sweep --contact``: the contact laws by their case-file names
#: (:func:`jaxgear.io.contact_law_from_name`)
CONTACT_NAMES = ["exact", "smooth"]


def _version() -> str:
    try:
        return version("jaxgear")
    except PackageNotFoundError:  # pragma: no cover - source tree not installed
        return "unknown"


#: :func:`build_parser`'s ``command`` for a parser with every subcommand's options
ALL = "*"

#: one command per subcommand: what ``jaxgear COMMAND --help`` shows under "example"
EXAMPLES = {
    "run": "jaxgear run power-helical --out results/ph",
    "cases": "jaxgear cases accessory-spur --write my-case.toml",
    "bench": "jaxgear bench xla-cache --quick",
    "prep": "jaxgear prep accessory-wheel --quiet",
    "sweep": "jaxgear sweep my-case.toml --speeds-rpm 2000:30000:60   # or --speeds in rad/s",
    "modes": "jaxgear modes lin-parker-1999",
    "robust": "jaxgear robust accessory-spur --grade 6 --samples 100",
    "size": "jaxgear size examples/sizing/helical.toml --out results/sizing --write 0",
    "optimise": "jaxgear optimise accessory-spur --vars tip_relief.depth,tip_relief.extent",
    "master-curve": "jaxgear master-curve accessory-spur --extents 0.1:0.5:9",
}


class _Parser(argparse.ArgumentParser):
    """An argument parser whose usage errors are one line: ``jaxgear sweep: error: argument
    --periods: ... (jaxgear sweep --help lists the options)``, exit status 2 (argparse prints
    the whole usage first)."""

    #: the command whose ``--help`` the hint names (``jaxgear optimise``: the top parser reports
    #: a subcommand's unrecognized arguments)
    help_of: str | None = None

    def error(self, message: str):
        if message.endswith("required: COMMAND"):  # a bare ``jaxgear``: its help, as --help
            self.print_help(sys.stderr)
        hint = f"{self.help_of or self.prog} --help lists the options"
        self.exit(2, f"{self.prog}: error: {message} ({hint})\n")


def periods_value(text: str) -> int | str:
    """``--periods``: an integer, or ``auto`` (each speed until it settles, as the case files'
    ``[scene.integration] periods = "auto"``); the range is checked with the other options."""
    if text.strip().lower() == "auto":
        return "auto"
    try:
        return int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(
            f"{text!r}: allowed an integer in [2, 1e+06] or auto"
        ) from None


def command_of(argv: list[str]) -> str | None:
    """The subcommand a command line names: its first word (``jaxgear``'s own options,
    ``--help`` and ``--version``, take no value), or None when it names none."""
    return next((a for a in argv if not a.startswith("-")), None)


def _subparser(sub, name: str, help: str, description: str | None = None):
    """``sub.add_parser`` with the house's help layout: the example of :data:`EXAMPLES` under
    the options, the description as written (its line breaks kept)."""
    return sub.add_parser(
        name,
        help=help,
        description=textwrap.fill(description or help[:1].upper() + help[1:] + ".", 79),
        epilog=f"example:\n  {EXAMPLES[name]}",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )


def build_parser(command: str | None = ALL) -> argparse.ArgumentParser:
    """The parser of ``jaxgear``: one subparser per :data:`COMMANDS` entry; ``args.command`` is
    the subcommand's name; ``args.out`` and ``args.json`` are None where a command has no such
    option. ``command``: the subcommand whose options are added (:func:`command_of` of the
    command line; None: none, for ``jaxgear --help``); :data:`ALL` (default) every one's."""
    p = _Parser(
        prog="jaxgear",
        description=textwrap.fill(
            "Differentiable gear dynamics in JAX. Speeds: --speeds/--speed in rad/s, "
            "--speeds-rpm/--speed-rpm in 1/min (as the case files' speed_rpm).",
            79,
        ),
        epilog="example:\n  jaxgear cases                  # the embedded cases\n"
        "  jaxgear run accessory-spur     # analyse one (jaxgear-out/accessory-spur/)\n"
        "  jaxgear COMMAND --help         # a command's options, with an example",
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    if command in COMMANDS:
        p.help_of = f"jaxgear {command}"
    p.add_argument("--version", action="version", version=f"jaxgear {_version()}")
    p.set_defaults(out=None, json=None)
    sub = p.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for name, add in _ADDERS.items():
        parser = _subparser(sub, name, *_HELP[name])
        if command == ALL or command == name:
            add(parser)
    return p


def _add_prep(pr) -> None:
    # imported here: fem_prep's options are read for ``jaxgear prep`` only
    from fem_prep import add_build_arguments

    add_build_arguments(pr)


def _add_optimise(o) -> None:
    from ._optimise_options import add_optimise_arguments

    add_optimise_arguments(o)
    o.add_argument("--force", action="store_true", help=FORCE_HELP + " and the --write file")


def _add_master_curve(m) -> None:
    from ._optimise_options import add_master_curve_arguments

    add_master_curve_arguments(m)
    m.add_argument("--force", action="store_true", help=FORCE_HELP)


def _add_run(r) -> None:
    r.add_argument(
        "case",
        nargs="?",
        default="accessory-spur",
        help="TOML case file or embedded case name (default: accessory-spur)",
    )
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/)")
    r.add_argument(
        "--json",
        metavar="FILE",
        help="also write the summary to this new file (its folder is created if missing; never "
        "the case file or a file it names)",
    )
    r.add_argument("--force", action="store_true", help=FORCE_HELP + " and the --json FILE")
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument(
        "--keep-partial",
        action="store_true",
        help="write into the output folder as the run goes and keep what a failed or "
        "interrupted run wrote, summary.json saying \"complete\": false (a run refused for "
        "its input still leaves the earlier results; default: the files appear when the run "
        "completes; a failed run leaves the earlier results)",
    )


#: the help of ``--force`` on the commands that write into an output folder
FORCE_HELP = (
    "replace files in the output folder that jaxgear did not write there but that bear names "
    "it writes (refused without it)"
)


def _add_cases(c) -> None:
    c.add_argument(
        "name", nargs="?", help="an embedded case: print its case file (default: list them all)"
    )
    c.add_argument("--write", metavar="FILE", help="write the case file to FILE instead")
    c.add_argument("--force", action="store_true", help="replace FILE if it exists")


def _add_bench(b) -> None:
    b.add_argument("what", choices=list(BENCHMARKS), help="which benchmark")
    b.add_argument(
        "--out", default="jaxgear-out/bench", help="output folder (default: jaxgear-out/bench)"
    )
    b.add_argument("--force", action="store_true", help=FORCE_HELP)
    b.add_argument("--quick", action="store_true", help="a small, fast version (smoke test)")
    b.add_argument(
        "--cases",
        metavar="NAME[,NAME…]",
        help="xla-cache: the embedded cases to run twice (default: all; --quick: accessory-spur)",
    )


def _add_sweep(s) -> None:
    s.add_argument("case", help="TOML case file or embedded case name")
    speeds = s.add_mutually_exclusive_group(required=True)
    speeds.add_argument(
        "--speeds",
        help="START:STOP:N pinion speeds in rad/s (a planetary stage: its input member's; a "
        "gearbox: its first stage's input member's)",
    )
    speeds.add_argument(
        "--speeds-rpm",
        metavar="SPEEDS_RPM",
        help="the same in 1/min (rpm, the case files' speed_rpm), instead of --speeds",
    )
    s.add_argument(
        "--direction",
        default="independent",
        choices=["independent", "up", "down", "both"],
        help="independent speeds (vmap) or continuation sweeps (default: independent; with "
        "periods auto a lumped scene's speeds continue upwards, each until it settles)",
    )
    s.add_argument(
        "--solver",
        choices=SOLVER_NAMES,
        help="time integrator (default: [scene.integration] solver, else newmark)",
    )
    s.add_argument(
        "--contact",
        choices=CONTACT_NAMES,
        help="contact law (default: [scene] contact, else exact)",
    )
    s.add_argument(
        "--periods",
        type=periods_value,
        help="mesh periods per speed, or auto: each speed until it settles (default: "
        "[scene.integration] periods, else auto)",
    )
    s.add_argument(
        "--keep-periods",
        type=int,
        help="steady-state periods kept, the last of --periods (default: [scene.integration])",
    )
    s.add_argument(
        "--steps-per-period",
        type=int,
        help="time steps per mesh period (default: [scene.integration], else automatic: 40 per "
        "period of the highest mode the mesh excites, at least 64 per mesh period)",
    )
    s.add_argument("--slices", type=int, help="slices across the face (default: [mesh] slices)")
    vtu = s.add_mutually_exclusive_group()
    vtu.add_argument(
        "--vtu-speed",
        type=float,
        help="pinion speed (rad/s): VTU time series (vtu/body_<member>.pvd) of the condensed "
        "bodies over the kept periods at that speed",
    )
    vtu.add_argument(
        "--vtu-speed-rpm",
        type=float,
        metavar="VTU_SPEED_RPM",
        help="the same in 1/min (rpm), instead of --vtu-speed",
    )
    s.add_argument(
        "--out",
        help="output folder (default: jaxgear-out/<case>/sweep-START-STOP-N/, apart from the "
        "sweep/ of jaxgear run, which its summary.json describes)",
    )
    s.add_argument("--force", action="store_true", help=FORCE_HELP)
    s.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_modes(m) -> None:
    m.add_argument("case", help="TOML case file or embedded case name")
    m.add_argument("--out", help="output folder (default: jaxgear-out/<case>/modes/)")
    m.add_argument("--force", action="store_true", help=FORCE_HELP)
    m.add_argument("--quiet", action="store_true", help="no progress output")


def _add_robust(r) -> None:
    r.add_argument("case", help="TOML case file or embedded case name")
    r.add_argument(
        "--grade",
        type=int,
        help="ISO 1328-1 flank tolerance class 1-11 (default: [robust] grade, else "
        "[deviations] grade)",
    )
    r.add_argument(
        "--samples",
        type=int,
        help="number of realisations, >= 2 (default: [robust] samples, else 200)",
    )
    r.add_argument(
        "--seed", type=int, help="random seed, >= 0 (default: [robust] seed, else 0)"
    )
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/robust/)")
    r.add_argument("--force", action="store_true", help=FORCE_HELP)
    _add_distributed(r)
    r.add_argument("--quiet", action="store_true", help="no summary line")


def _add_distributed(p) -> None:
    """The ``jax.distributed`` options of the commands that run on several processes
    (``robust``, ``size``)."""
    p.add_argument(
        "--coordinator-address",
        help="jax.distributed coordinator HOST:PORT (process 0's host), with --num-processes",
    )
    p.add_argument("--num-processes", type=int, help="jax.distributed: processes (one per host)")
    p.add_argument("--process-id", type=int, help="jax.distributed: this process, 0 … N-1")


def _add_size(s) -> None:
    s.add_argument("spec", help="TOML sizing spec ([operating], [material], [rating], [sizing])")
    s.add_argument("--out", help="output folder (default: jaxgear-out/<spec name>/size/)")
    s.add_argument("--write", type=int, metavar="K",
                   help="also write candidate K (a row of sizing.csv) as a case file, "
                   "candidate_K.toml, that jaxgear run rates (with [sound]: its housed case "
                   "too, candidate_K_housed.toml)")
    s.add_argument("--top", type=int, default=20,
                   help="feasible candidates printed, lightest first (default: 20)")
    s.add_argument("--te", type=int, metavar="N",
                   help="the transmission-error stage for the N best feasible candidates "
                   "(default: the spec's te_candidates, 3; 0: none)")
    s.add_argument("--dynamics", type=int, metavar="N",
                   help="the dynamics stage (K_v over speed, whine) for N candidates of the "
                   "first Pareto fronts (default: the spec's dynamics_candidates, 3; 0: none)")
    s.add_argument("--sound", type=int, metavar="N",
                   help="the sound stage (a housing's ERP over the [sound] speeds) for N "
                   "candidates of the first Pareto fronts, a spec with [sound] (default: its "
                   "candidates, 1; 0: none)")
    s.add_argument("--refine", action="store_true",
                   help="refine each candidate's helix angle, profile shifts and face width by "
                   "gradients (as [sizing] refine = true)")
    s.add_argument("--force", action="store_true", help=FORCE_HELP)
    s.add_argument("--chunk", type=int, default=2048,
                   help="candidates per call of the compiled program, per device (default: "
                   "2048); the results store (OUT/store/) keeps each finished chunk, and a rerun "
                   "of the same spec and chunk resumes from it")
    _add_distributed(s)
    s.add_argument("--quiet", action="store_true", help="no progress bar nor ranked list")


#: each subcommand's one-line help (``jaxgear --help``) and, where it says more, description
_HELP = {
    "run": (
        "the main job: quasi-static analysis of a case, and the speed sweep and optimisation "
        "its [scene] and [optimise] ask for",
    ),
    "cases": (
        "list the embedded cases (kind, rated or not, run time, and a first run's with its "
        "FE bodies and housing still to build), or print / write one",
    ),
    "bench": (
        "benchmark runs (speed vs a baseline, speed-vs-accuracy charts; from a source "
        "checkout)",
    ),
    "prep": (
        "fem_prep: mesh and condense a gear body (= fem-prep build)",
        "Mesh and condense a gear body with fem_prep (= fem-prep build).",
    ),
    "sweep": (
        "dynamic factor vs speed (Newmark/diffrax, [scene] table)",
        "Dynamic factor vs speed (Newmark/diffrax, the case's [scene] table). Speeds in rad/s "
        "(--speeds) or in 1/min (--speeds-rpm, as the case files' speed_rpm).",
    ),
    "modes": ("natural frequencies (Hz) with their mode types, for any case (modes.json)",),
    "robust": (
        "Monte Carlo over ISO 1328-1 deviations: TE, line load and dynamic-factor "
        "distributions with percentiles ([robust] table)",
    ),
    "optimise": (
        "gradient-based optimisation of tooth modifications",
        "Gradient-based optimisation of tooth modifications (the case's [optimise] table, the "
        "options below override it). Speeds in rad/s (--speed, --speeds) or in 1/min "
        "(--speed-rpm, --speeds-rpm, as the case files' speed_rpm).",
    ),
    "master-curve": ("Master Curve: optimal tip relief depth for each extent",),
    "size": (
        "gear sizing: every (module, z1, z2) of a spec's ranges rated (ISO 6336), the "
        "feasible ones ranked by mass",
        "Gear sizing from requirements: every (normal module, z1, z2) of the spec's ranges "
        "within the ratio tolerance and the centre-distance window, its geometry, validity and "
        "ISO 6336 rating, in one table (sizing.csv) with the reason each rejected candidate "
        "fails; the feasible ones printed lightest first; the Pareto front over the spec's "
        "objectives ([pareto]: mass, margin, with [lubricant] the mesh loss) with its chosen "
        "design and a figure per pair of objectives.",
    ),
}

#: each subcommand's options, in the order ``jaxgear --help`` lists the subcommands
_ADDERS = {
    "run": _add_run,
    "cases": _add_cases,
    "bench": _add_bench,
    "prep": _add_prep,
    "sweep": _add_sweep,
    "modes": _add_modes,
    "robust": _add_robust,
    "optimise": _add_optimise,
    "master-curve": _add_master_curve,
    "size": _add_size,
}
