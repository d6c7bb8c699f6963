"""The ``jaxgear`` command line's options and its table of commands.

Every subcommand's options are declared here and nothing is computed (``optimise`` and
``master-curve`` declare theirs in :mod:`._optimise_options`, which reads the objective and
optimiser names from :mod:`jaxgear.io`). Each command is a name in :data:`COMMANDS`, mapped to the function that
runs it as ``"module:function"``; :func:`jaxgear.cli.main` imports that module once, after the
options are checked (:func:`._options.check_options`).
"""

from __future__ import annotations

import argparse
import dataclasses
from importlib.metadata import PackageNotFoundError, version

__all__ = ["BENCHMARKS", "COMMANDS", "Command", "SOLVER_NAMES", "build_parser"]


@dataclasses.dataclass(frozen=True)
class Command:
    """A subcommand: ``target``, the function that runs it (``"module:function"``, called with
    the parsed arguments, returns the exit status) and whether it computes with JAX (float64
    and the persistent compilation cache are switched on before it runs: all but ``prep``)."""

    target: str
    jax: bool = True


#: every subcommand by its name on the command line
COMMANDS = {
    "run": Command("jaxgear.cli.run:run_command"),
    "cases": Command("jaxgear.cli.cases:run_cases"),
    "optimise": Command("jaxgear.cli._optimise:run_optimise"),
    "master-curve": Command("jaxgear.cli._optimise:run_master_curve"),
    "sweep": Command("jaxgear.cli.sweep:run_sweep"),
    "modes": Command("jaxgear.cli.modes:run_modes"),
    "robust": Command("jaxgear.cli.robust:run_robust"),
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


def _version() -> str:
    try:
        return version("jaxgear")
    except PackageNotFoundError:  # pragma: no cover - source tree not installed
        return "unknown"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``jaxgear``: one subparser per :data:`COMMANDS` entry; ``args.command`` is
    the subcommand's name; ``args.out`` and ``args.json`` are None where a command has no such
    option."""
    # imported here, not with the table of commands: the console script reads COMMANDS before
    # these imports (fem_prep, the optimisers; :mod:`jaxgear.cli._start`)
    from fem_prep import add_build_arguments

    from ._optimise_options import add_parsers as add_optimise_parsers

    p = argparse.ArgumentParser(prog="jaxgear", description="Differentiable gear dynamics in JAX.")
    p.add_argument("--version", action="version", version=f"jaxgear {_version()}")
    p.set_defaults(out=None, json=None)
    sub = p.add_subparsers(dest="command", required=True)
    _add_run(sub)
    _add_cases(sub)
    _add_bench(sub)
    pr = sub.add_parser("prep", help="fem_prep: mesh and condense a gear body (= fem-prep build)")
    add_build_arguments(pr)
    _add_sweep(sub)
    _add_modes(sub)
    _add_robust(sub)
    add_optimise_parsers(sub)
    return p


def _add_run(sub) -> None:
    r = sub.add_parser(
        "run",
        help="the main job: quasi-static analysis of a case, and the speed sweep and "
        "optimisation its [scene] and [optimise] ask for",
    )
    r.add_argument(
        "case",
        nargs="?",
        default="accessory-spur",
        help="TOML case file or embedded case name (default: accessory-spur)",
    )
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/)")
    r.add_argument(
        "--json", help="also write the summary to this file (its folder is created if missing)"
    )
    r.add_argument("--quiet", action="store_true", help="no progress bar")
    r.add_argument(
        "--keep-partial",
        action="store_true",
        help="write into the output folder as the run goes and keep what a failed or "
        "interrupted run wrote, summary.json saying \"complete\": false (a run refused for "
        "its input still leaves the earlier results; default: the files appear when the run "
        "completes; a failed run leaves the earlier results)",
    )


def _add_cases(sub) -> None:
    c = sub.add_parser("cases", help="list the embedded cases, or print / write one")
    c.add_argument("name", nargs="?", help="an embedded case: print its case file")
    c.add_argument("--write", metavar="FILE", help="write the case file to FILE instead")
    c.add_argument("--force", action="store_true", help="replace FILE if it exists")


def _add_bench(sub) -> None:
    b = sub.add_parser(
        "bench",
        help="benchmark runs (speed vs a baseline, speed-vs-accuracy charts; from a source "
        "checkout)",
    )
    b.add_argument("what", choices=list(BENCHMARKS), help="which benchmark")
    b.add_argument("--out", default="jaxgear-out/bench", help="output folder")
    b.add_argument("--quick", action="store_true", help="a small, fast version (smoke test)")
    b.add_argument(
        "--cases",
        metavar="NAME[,NAME…]",
        help="xla-cache: the embedded cases to run twice (default: all; --quick: accessory-spur)",
    )


def _add_sweep(sub) -> None:
    s = sub.add_parser("sweep", help="dynamic factor vs speed (Newmark/diffrax, [scene] table)")
    s.add_argument("case", help="TOML case file or embedded case name")
    s.add_argument(
        "--speeds",
        required=True,
        help="START:STOP:N pinion speeds (rad/s; a planetary stage: its input member's)",
    )
    s.add_argument(
        "--direction",
        default="independent",
        choices=["independent", "up", "down", "both"],
        help="independent speeds (vmap) or continuation sweeps (default: independent)",
    )
    s.add_argument(
        "--solver",
        choices=SOLVER_NAMES,
        help="time integrator (default: [scene.integration] solver, else newmark)",
    )
    s.add_argument("--contact", choices=["exact", "smooth"], help="contact law")
    s.add_argument("--periods", type=int, help="mesh periods per speed")
    s.add_argument("--keep-periods", type=int, help="steady-state periods kept")
    s.add_argument(
        "--steps-per-period",
        type=int,
        help="time steps per mesh period (default: [scene.integration], else automatic: 40 per "
        "period of the highest mode the mesh excites, at least 64 per mesh period)",
    )
    s.add_argument("--slices", type=int, help="override [mesh] slices")
    s.add_argument(
        "--vtu-speed",
        type=float,
        help="pinion speed (rad/s): VTU time series (vtu/body_<member>.pvd) of the condensed "
        "bodies over the kept periods at that speed",
    )
    s.add_argument(
        "--out",
        help="output folder (default: jaxgear-out/<case>/sweep-START-STOP-N/, apart from the "
        "sweep/ of jaxgear run, which its summary.json describes)",
    )
    s.add_argument("--quiet", action="store_true", help="no progress bar")


def _add_modes(sub) -> None:
    m = sub.add_parser(
        "modes", help="natural frequencies (Hz) with their mode types, for any case (modes.json)"
    )
    m.add_argument("case", help="TOML case file or embedded case name")
    m.add_argument("--out", help="output folder (default: jaxgear-out/<case>/modes/)")
    m.add_argument("--quiet", action="store_true", help="no progress output")


def _add_robust(sub) -> None:
    r = sub.add_parser(
        "robust",
        help="Monte Carlo over ISO 1328-1 deviations: TE, line load and dynamic-factor "
        "distributions with percentiles ([robust] table)",
    )
    r.add_argument("case", help="TOML case file or embedded case name")
    r.add_argument("--grade", type=int, help="ISO 1328-1 flank tolerance class 1-11")
    r.add_argument("--samples", type=int, help="number of realisations (>= 2)")
    r.add_argument("--seed", type=int, help="random seed (>= 0)")
    r.add_argument("--out", help="output folder (default: jaxgear-out/<case>/robust/)")
    r.add_argument(
        "--coordinator-address",
        help="jax.distributed coordinator HOST:PORT (process 0's host), with --num-processes",
    )
    r.add_argument("--num-processes", type=int, help="jax.distributed: processes (one per host)")
    r.add_argument("--process-id", type=int, help="jax.distributed: this process, 0 … N-1")
    r.add_argument("--quiet", action="store_true", help="no summary line")
