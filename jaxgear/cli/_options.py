"""Command-line options that need no case file: ranges, counts and output paths, checked before
JAX or the model is imported (one-line ``ValueError`` messages)."""

from __future__ import annotations

import math

import numpy as np

__all__ = [
    "EXTENT_BOUNDS",
    "MAX_SPEED",
    "MAX_SPEEDS",
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
    a, b, n = parse_range(text, option, **checks)
    return np.linspace(a, b, n)


def check_options(args) -> None:
    """Check the command-line options that need no case file (ranges, counts, output paths);
    raises ValueError with a one-line message. Runs before JAX or the model is imported."""
    from ._paths import check_output_dir, check_output_file

    cmd = args.command
    if cmd == "robust":
        from .robust import check_robust_options

        check_robust_options(args)
        if args.out is not None:
            check_output_dir(args.out)
    if cmd == "optimise":
        if args.max_iterations is not None and args.max_iterations < 1:
            raise ValueError(f"--max-iterations {args.max_iterations}: must be >= 1")
        if args.torques is not None:
            parse_range(args.torques, "--torques", positive=True)
            if args.objective is not None and args.objective != "robust_te_rms":
                raise ValueError(
                    f"--torques applies to --objective robust_te_rms only, not {args.objective}"
                )
    if cmd == "master-curve":
        a, b, _ = parse_range(args.extents, "--extents")
        lo, hi = EXTENT_BOUNDS
        if not (lo <= a and b <= hi):
            raise ValueError(f"--extents {args.extents!r}: extents must lie in [{lo}, {hi}]")
    if cmd == "sweep":
        a, b, n = parse_range(args.speeds, "--speeds", positive=True, min_points=2)
        if n > MAX_SPEEDS:
            raise ValueError(
                f"--speeds {args.speeds!r}: N = {n} speeds, allowed <= {MAX_SPEEDS} (one run "
                "per speed: split the band into several sweeps)"
            )
        if b > MAX_SPEED:
            raise ValueError(
                f"--speeds {args.speeds!r}: STOP = {b:.6g} rad/s, allowed <= {MAX_SPEED:.0e} "
                "rad/s (pinion speed)"
            )
        for opt, lo, hi in (
            ("periods", 2, 10**6),
            ("keep_periods", 2, 10**6),
            ("steps_per_period", 4, 10**6),
            ("slices", 1, 10**4),
        ):
            v = getattr(args, opt)
            if v is not None and not lo <= v <= hi:
                raise ValueError(
                    f"--{opt.replace('_', '-')} {v}: out of range, allowed [{lo}, {hi:g}]"
                )
        p, k = args.periods, args.keep_periods
        if p is not None and k is not None and k > p:
            raise ValueError(f"--keep-periods {k}: out of range, allowed <= --periods {p}")
        v = args.vtu_speed
        if v is not None and not (math.isfinite(v) and a <= v <= b):
            raise ValueError(
                f"--vtu-speed {v:.6g}: out of range, allowed a speed of the sweep, "
                f"[{a:.6g}, {b:.6g}] rad/s"
            )
    if getattr(args, "out", None) is not None:
        check_output_dir(args.out)
    if getattr(args, "json", None) is not None:
        check_output_file(args.json)
