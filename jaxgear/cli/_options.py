"""Command-line options that need no case file: ranges, counts and output paths, checked before
JAX or the model is imported (one-line ``ValueError`` messages). NumPy and the output paths'
checks (fem_prep) are imported where used: ``jaxgear cases`` imports this module and neither."""

from __future__ import annotations

import math
import os
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import numpy as np

__all__ = [
    "EXTENT_BOUNDS",
    "MAX_SPEED",
    "MAX_SPEEDS",
    "RPM",
    "check_options",
    "parse_range",
    "range_values",
]


# the Γ interval ``master-curve`` searches (master_curve_case's extent bounds)
EXTENT_BOUNDS = (0.02, 0.98)

# ``jaxgear sweep --speeds``: at most this many speeds in one sweep, and pinion speeds up to this
# (rad/s, about 955 000 rpm: beyond any gear; the time step count bounds the low end per case)
MAX_SPEEDS = 10_000
MAX_SPEED = 1e5

#: rad/s per 1/min (rpm): ``--speeds-rpm`` and ``--speed-rpm`` are read in rpm and carried on in
#: rad/s, the unit of the API and of ``--speeds``/``--speed``
RPM = math.pi / 30


def _rpm_to_rad_s(args, rpm: str, rad_s: str, *, is_range: bool, min_points: int = 1) -> None:
    """``args.<rpm>`` (1/min: a number, or a ``START:STOP:N`` range checked as ``--<rpm>``
    with its values in rpm) carried to ``args.<rad_s>`` in rad/s; nothing when not given.
    argparse keeps the two options apart (one or the other)."""
    value = getattr(args, rpm)
    if value is None:
        return
    option = "--" + rpm.replace("_", "-")
    if not is_range:
        if not math.isfinite(value):
            raise ValueError(f"{option} {value}: expected a finite speed in 1/min")
        setattr(args, rad_s, value * RPM)
        return
    a, b, n = parse_range(value, option, positive=True, min_points=min_points)
    setattr(args, rad_s, f"{a * RPM!r}:{b * RPM!r}:{n}")


def parse_range(
    text: str, option: str, *, positive: bool = False, min_points: int = 1
) -> tuple[float, float, int]:
    """``START:STOP:N`` (or one number) → (start, stop, n), checked: numbers, N >= ``min_points``,
    START < STOP when N > 1, START > 0 with ``positive``. One-line ``ValueError`` otherwise."""
    parts = str(text).split(":")
    try:
        if len(parts) == 1:
            a = b = float(parts[0])
            n = 1
        elif len(parts) == 3:
            a, b, n = float(parts[0]), float(parts[1]), int(parts[2])
        else:
            raise ValueError
    except ValueError:
        raise ValueError(f"{option} {text!r}: expected START:STOP:N (e.g. 40:120:5)") from None
    if not (math.isfinite(a) and math.isfinite(b)):
        raise ValueError(f"{option} {text!r}: START and STOP must be finite numbers")
    if n < min_points:
        raise ValueError(f"{option} {text!r}: N = {n} must be >= {min_points}")
    if n > 1 and not a < b:
        raise ValueError(f"{option} {text!r}: START must be below STOP (reversed or empty range)")
    if positive and not a > 0:
        raise ValueError(f"{option} {text!r}: values must be > 0")
    return a, b, n


def range_values(text: str, option: str, **checks) -> np.ndarray:
    """The values of a checked ``START:STOP:N`` range, ``linspace(START, STOP, N)``."""
    import numpy as np

    a, b, n = parse_range(text, option, **checks)
    return np.linspace(a, b, n)


def _check_robust(args) -> None:
    """``jaxgear robust``: the grade, samples and seed in range; the ``jax.distributed``
    options together and in range."""
    for name, lo, hi in (("grade", 1, 11), ("samples", 2, None), ("seed", 0, None)):
        v = getattr(args, name)
        if v is not None and (v < lo or (hi is not None and v > hi)):
            allowed = f"[{lo}, {hi}]" if hi is not None else f">= {lo}"
            raise ValueError(f"--{name} = {v}: out of range, allowed {allowed}")
    _check_distributed(args)


def _check_distributed(args) -> None:
    """The ``jax.distributed`` options (``robust``, ``size``): together and in range."""
    dist = (args.coordinator_address, args.num_processes, args.process_id)
    if any(v is not None for v in dist):
        if any(v is None for v in dist):
            raise ValueError(
                "--coordinator-address, --num-processes and --process-id go together "
                f"(given {args.coordinator_address!r}, {args.num_processes!r}, "
                f"{args.process_id!r})"
            )
        host, _, port = args.coordinator_address.rpartition(":")
        if not host or not port.isdigit() or not 0 < int(port) < 65536:
            raise ValueError(
                f"--coordinator-address = {args.coordinator_address!r}: allowed HOST:PORT "
                "(port 1-65535)"
            )
        if args.num_processes < 1:
            raise ValueError(f"--num-processes = {args.num_processes}: out of range, allowed >= 1")
        if not 0 <= args.process_id < args.num_processes:
            raise ValueError(
                f"--process-id = {args.process_id}: out of range, allowed [0, "
                f"{args.num_processes - 1}]"
            )


def _check_optimise(args) -> None:
    """``jaxgear optimise``: the iteration bound, the torque range of ``robust_te_rms``; the
    speeds given in rpm carried to rad/s."""
    _rpm_to_rad_s(args, "speed_rpm", "speed", is_range=False)
    _rpm_to_rad_s(args, "speeds_rpm", "speeds", is_range=True)
    if args.max_iterations is not None and args.max_iterations < 1:
        raise ValueError(f"--max-iterations {args.max_iterations}: must be >= 1")
    if args.torques is not None:
        parse_range(args.torques, "--torques", positive=True)
        if args.objective is not None and args.objective != "robust_te_rms":
            raise ValueError(
                f"--torques applies to --objective robust_te_rms only, not {args.objective}"
            )


def _check_master_curve(args) -> None:
    """``jaxgear master-curve``: the extents inside :data:`EXTENT_BOUNDS`."""
    a, b, _ = parse_range(args.extents, "--extents")
    lo, hi = EXTENT_BOUNDS
    if not (lo <= a and b <= hi):
        raise ValueError(f"--extents {args.extents!r}: extents must lie in [{lo}, {hi}]")


def _speed_option(args, name: str) -> tuple[str, object, str, float]:
    """(the option as given, its value, its unit, rad/s per unit) of ``--NAME`` (rad/s) or
    ``--NAME-rpm`` (1/min), whichever was given (argparse keeps them apart)."""
    rpm = getattr(args, f"{name}_rpm")
    option = "--" + name.replace("_", "-")
    if rpm is not None:
        return f"{option}-rpm", rpm, "rpm", RPM
    return option, getattr(args, name), "rad/s", 1.0


def _check_sweep(args) -> None:
    """``jaxgear sweep``: the speeds, the integration counts and the VTU speed in range, each
    message in the option's own unit; the speeds given in rpm then carried to rad/s."""
    option, text, unit, scale = _speed_option(args, "speeds")
    a, b, n = parse_range(text, option, positive=True, min_points=2)
    if n > MAX_SPEEDS:
        raise ValueError(
            f"{option} {text!r}: N = {n} speeds, allowed <= {MAX_SPEEDS} (one run "
            "per speed: split the band into several sweeps)"
        )
    if b * scale > MAX_SPEED:
        raise ValueError(
            f"{option} {text!r}: STOP = {b:.6g} {unit}, allowed <= {MAX_SPEED / scale:.6g} "
            f"{unit} (pinion speed)"
        )
    for opt, lo, hi in (
        ("periods", 2, 10**6),
        ("keep_periods", 2, 10**6),
        ("steps_per_period", 4, 10**6),
        ("slices", 1, 10**4),
    ):
        v = getattr(args, opt)
        if v is not None and v != "auto" and not lo <= v <= hi:
            raise ValueError(f"--{opt.replace('_', '-')} {v}: out of range, allowed [{lo}, {hi:g}]")
    p, k = args.periods, args.keep_periods
    if p not in (None, "auto") and k is not None and k > p:
        raise ValueError(f"--keep-periods {k}: out of range, allowed <= --periods {p}")
    vtu, v, vtu_unit, vtu_scale = _speed_option(args, "vtu_speed")
    if v is not None and not (math.isfinite(v) and a * scale <= v * vtu_scale <= b * scale):
        lo, hi = a * scale / vtu_scale, b * scale / vtu_scale
        raise ValueError(
            f"{vtu} {v:.6g}: out of range, allowed a speed of the sweep, "
            f"[{lo:.6g}, {hi:.6g}] {vtu_unit}"
        )
    _rpm_to_rad_s(args, "speeds_rpm", "speeds", is_range=True, min_points=2)
    _rpm_to_rad_s(args, "vtu_speed_rpm", "vtu_speed", is_range=False)


def _no_checks(args) -> None:
    """A command whose options need no check beyond argparse's and the output paths'."""


#: each command's own checks (by its name on the command line); the others have none
def _check_size(args) -> None:
    """``jaxgear size``: the spec a file; ``--write`` and ``--top`` not negative (``--write``'s
    upper bound follows the spec: checked once it is read)."""
    if not os.path.isfile(args.spec):
        raise ValueError(f"{args.spec}: no such sizing spec file")
    for name in ("write", "top"):
        v = getattr(args, name)
        if v is not None and v < 0:
            raise ValueError(f"--{name} {v}: out of range, allowed >= 0")
    if args.chunk < 1:
        raise ValueError(f"--chunk {args.chunk}: out of range, allowed >= 1")
    _check_distributed(args)


_CHECKS = {
    "size": _check_size,
    "robust": _check_robust,
    "optimise": _check_optimise,
    "master-curve": _check_master_curve,
    "sweep": _check_sweep,
}


def check_options(args) -> None:
    """Check the command-line options that need no case file (ranges, counts, output paths);
    raises ValueError with a one-line message. Runs before JAX or the model is imported."""
    _CHECKS.get(args.command, _no_checks)(args)
    if args.out is not None or args.json is not None:
        from ._paths import check_output_dir, check_output_file
    if args.out is not None:
        check_output_dir(args.out)
    if args.json is not None:  # the files the case names: once it is loaded (check_case_outputs)
        inputs = {args.case: "the case file"} if os.path.isfile(args.case) else None
        check_output_file(args.json, inputs=inputs, force=args.force)
