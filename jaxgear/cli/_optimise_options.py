"""The options of ``jaxgear optimise`` and ``jaxgear master-curve`` (argparse only: the commands
themselves live in :mod:`._optimise`, loaded when they run). This module imports neither the
model nor JAX, so that both commands' ``--help`` answers at once and their options are checked
before the model loads: the choices are the names as the command line shows them, of what
:mod:`jaxgear.io` maps to objects (``OBJECTIVES``, ``STATISTICS``, ``OPTIMISERS``) and of
:data:`optimise.VARIABLES` (the design variables); the test suite holds each tuple here to
the keys there."""

from __future__ import annotations

import argparse

__all__ = [
    "OBJECTIVE_NAMES",
    "OPTIMISER_NAMES",
    "STATISTIC_NAMES",
    "VARIABLE_NAMES",
    "add_master_curve_arguments",
    "add_optimise_arguments",
]

#: ``--objective``: the keys of :data:`jaxgear.io.OBJECTIVES`
OBJECTIVE_NAMES = (
    "te_rms",
    "te_ptp",
    "robust_te_rms",
    "max_line_load",
    "load_centroid",
    "line_load_lp",
    "dynamic_factor",
    "least_safety",
    "power_loss",
    "efficiency_loss",
    "min_specific_film",
    "max_flash_temperature",
    "erp",
    "sound_power",
)
#: ``--reduce``: the keys of :data:`jaxgear.io.STATISTICS`
STATISTIC_NAMES = ("max", "mean", "quantile")
#: ``--method``: the keys of :data:`jaxgear.io.OPTIMISERS`
OPTIMISER_NAMES = ("lbfgs", "adam")
#: ``--vars``: the keys of :data:`optimise.VARIABLES`
VARIABLE_NAMES = (
    "tip_relief.depth",
    "tip_relief.extent",
    "root_relief.depth",
    "root_relief.extent",
    "crowning.depth",
    "end_relief.depth",
    "end_relief.extent",
)


def add_optimise_arguments(o) -> None:
    """Add the options of ``jaxgear optimise`` to its argparse parser (its implementation:
    :func:`jaxgear.cli._optimise.run_optimise`). Speeds in rad/s (``--speed``, ``--speeds``)
    or in 1/min (``--speed-rpm``, ``--speeds-rpm``), one or the other."""
    o.add_argument("case", help="TOML case file or embedded case name")
    o.add_argument(
        "--objective",
        choices=OBJECTIVE_NAMES,
        help="objective (default te_rms, or the case's [optimise]); load_centroid: the load "
        "centroid's offset from mid-face squared (0 = centred), line_load_lp: the L_p norm of the "
        "line load over the load map (a smooth maximum, see --lp-order), least_safety: raise the "
        "least ISO 6336 safety factor (a case with [rating]; see --te-limit-um); power_loss, "
        "efficiency_loss, min_specific_film (as 1/λ), max_flash_temperature: the mesh's "
        "tribology (a case with [lubricant]); erp, sound_power: the housing's radiated power over "
        "the [whine] speeds (a housed case: [housing] and [whine]; sound_power: and "
        "[acoustics], its radiation method and grid)",
    )
    o.add_argument(
        "--te-limit-um",
        type=float,
        help="TE RMS limit (µm) of the least_safety objective, > 0: a penalty acts above it "
        "(default none)",
    )
    o.add_argument(
        "--vars",
        help="comma-separated design variables, e.g. tip_relief.depth,tip_relief.extent "
        f"(allowed: {', '.join(VARIABLE_NAMES)}, optionally prefixed pinion./gear.; default: the "
        "case's [optimise] vars, else tip_relief.depth,tip_relief.extent)",
    )
    o.add_argument(
        "--torques",
        help="START:STOP:N torque range (N·m) of the robust_te_rms and tribology objectives",
    )
    speed = o.add_mutually_exclusive_group()
    speed.add_argument(
        "--speed",
        type=float,
        help="pinion speed (rad/s): optimise on the hybrid scene at that speed, centrifugal loads "
        "included (a case with [scene.gear_body] or [scene.pinion_body]; default: at rest)",
    )
    speed.add_argument(
        "--speed-rpm",
        type=float,
        metavar="SPEED_RPM",
        help="the same in 1/min (rpm, the case files' speed_rpm), instead of --speed",
    )
    o.add_argument(
        "--lp-order",
        type=float,
        help="p of the line_load_lp objective, in [1, 64] (default 8)",
    )
    speeds = o.add_mutually_exclusive_group()
    speeds.add_argument(
        "--speeds",
        help="START:STOP:N pinion speed band (rad/s) of the dynamic_factor objective (hybrid "
        "Newmark on a case with condensed bodies)",
    )
    speeds.add_argument(
        "--speeds-rpm",
        metavar="SPEEDS_RPM",
        help="the same in 1/min (rpm), instead of --speeds",
    )
    o.add_argument(
        "--reduce",
        choices=STATISTIC_NAMES,
        help="robust_te_rms, tribology objectives: worst case, mean or quantile over the "
        "torques; erp, sound_power: over the [whine] speeds (default: the case's [optimise], "
        "else the worst case)",
    )
    o.add_argument(
        "--quantile",
        type=float,
        help="the level q in (0, 1) of --reduce quantile (e.g. 0.9)",
    )
    o.add_argument(
        "--a-weighted",
        action=argparse.BooleanOptionalAction,
        help="erp, sound_power: sum the orders A-weighted (IEC 61672-1; the default) or, with "
        "--no-a-weighted, as they are",
    )
    o.add_argument("--method", choices=OPTIMISER_NAMES, help="optimiser (default lbfgs)")
    o.add_argument("--max-iterations", type=int, help="iteration cap (default 100)")
    o.add_argument("--out", help="output folder (default jaxgear-out/<case>/optimise)")
    o.add_argument(
        "--write",
        metavar="NEW.toml",
        help="also write the optimum as a case file: the case with its [modifications] set to "
        "the optimum (every other line kept), loadable by jaxgear run NEW.toml (a new file: "
        "never the case file or a file it names)",
    )
    o.add_argument(
        "--quiet", action="store_true", help="no progress bar (the result lines are printed)"
    )


def add_master_curve_arguments(m) -> None:
    """Add the options of ``jaxgear master-curve`` to its argparse parser (its implementation:
    :func:`jaxgear.cli._optimise.run_master_curve`)."""
    m.add_argument("case", help="TOML case file or embedded case name")
    m.add_argument(
        "--extents",
        default="0.05:0.6:12",
        help="START:STOP:N relief extents Γ (default: 0.05:0.6:12)",
    )
    m.add_argument("--out", help="output folder (default jaxgear-out/<case>/master-curve)")
    m.add_argument("--quiet", action="store_true", help="no progress bar")
