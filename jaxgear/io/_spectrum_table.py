"""The case file's load spectrum, ``[rating.spectrum]`` of a pair case (ISO 6336-6:2019): bins
of pinion torque and speed with their time or load cycles, or a sampled torque history counted
into levels; checked whole and mapped to a :class:`jaxgear.rating.LoadSpectrum` here only.

Keys (file units; ranges as checked), one of three forms::

    [rating.spectrum]               # bins: one entry per bin, each list as long as torque_Nm
    torque_Nm = [25400.0, 20000.0]  # pinion torque, each [0, 1e9]
    speed_rpm = [35.2, 35.2]        # pinion speed, each [0, 1e6]; or one number for all bins
    hours = [1200.0, 30000.0]       # time in each bin over the life, each >= 0; or
    # cycles = [...]                # the pinion's load cycles (turns) in each bin, each >= 0; or
    # time_share = [0.1, 0.9]       # each bin's share of [rating] life_h, each >= 0 (scaled so
                                    # that the shares add up to the life)

    [rating.spectrum]               # a sampled history, time at level (scaled to life_h)
    series_torque_Nm = [...]        # pinion torque samples, each [0, 1e9], at least 2
    series_speed_rpm = 35.2         # one speed, or a sample per torque sample, each [0, 1e6]
    series_step_s = 0.05            # the sampling interval, (0, 1e6] s
    levels = 20                     # torque levels, [1, 1000], equal widths from 0 to the
                                    # largest sample; default 20

``jaxgear run`` rates each bin at its torque and speed with K_A = 1 (ISO 6336-6: the spectrum
holds the machines' loads) and reports the damage per bin (docs/rating.md, "Load spectrum and
life").
"""

from __future__ import annotations

import math

from fem_prep import schema as sc

from ..rating import LoadSpectrum

__all__ = ["SPECTRUM_KEYS", "parse_spectrum"]

RPM = 2 * math.pi / 60
WHERE = "rating.spectrum"
BIN_TIMES = ("hours", "cycles", "time_share")
SERIES_KEYS = ("series_torque_Nm", "series_speed_rpm", "series_step_s", "levels")
SPECTRUM_KEYS = {"torque_Nm", "speed_rpm", *BIN_TIMES, *SERIES_KEYS}
TORQUE = "[0, 1e+09]"
SPEED = "[0, 1e+06]"


def _speeds(table: dict, key: str, n: int) -> list[float]:
    """``key`` as one number for all ``n`` entries or a list of ``n``."""
    v = table.get(key)
    if isinstance(v, list):
        return sc.number_list(table, key, WHERE, length=n, allowed=SPEED)
    return [sc.number(table, key, WHERE, allowed=SPEED)] * n


def parse_spectrum(table: dict, life: float) -> LoadSpectrum:
    """``[rating.spectrum]`` (module docstring) as a :class:`jaxgear.rating.LoadSpectrum`
    (SI); ``life`` the rating's life (s, ``[rating] life_h``) that ``time_share`` and a series
    are scaled to.

    Raises:
        SchemaError: an unknown key, keys of two forms (or two bin times), a list of another
            length than ``torque_Nm``, a value out of range, no loaded turning bin; one line
            naming the key, its value and the allowed range.
    """
    sc.check_keys(table, SPECTRUM_KEYS, WHERE)
    series = [k for k in SERIES_KEYS if k in table]
    bins = [k for k in ("torque_Nm", "speed_rpm", *BIN_TIMES) if k in table]
    if series and bins:
        raise sc.fail(WHERE, bins[0], f"give bins (torque_Nm, speed_rpm, hours | cycles | "
                      f"time_share) or a series (series_torque_Nm, ...), not both ({series[0]} "
                      "is given too)")
    try:
        if series:
            return _series(table, life)
        return _bins(table, life)
    except ValueError as err:  # the model's own check (no loaded, turning bin)
        if isinstance(err, sc.SchemaError):
            raise
        raise sc.fail(WHERE, None, str(err)) from None


def _bins(table: dict, life: float) -> LoadSpectrum:
    torque = sc.number_list(table, "torque_Nm", WHERE, min_length=1, allowed=TORQUE)
    n = len(torque)
    speed = [w * RPM for w in _speeds(table, "speed_rpm", n)]
    times = [k for k in BIN_TIMES if k in table]
    if len(times) != 1:
        what = "missing" if not times else f"{times[0]} and {times[1]} both given"
        raise sc.fail(WHERE, "hours", f"{what}: give one of hours, cycles, time_share")
    key = times[0]
    values = sc.number_list(table, key, WHERE, length=n, allowed="[0, inf)")
    if key == "cycles":
        try:
            return LoadSpectrum.from_cycles(torque, speed, values)
        except ValueError as err:
            raise sc.fail(WHERE, "cycles", str(err).split(": ", 1)[-1], values) from None
    if key == "hours":
        return LoadSpectrum(torque, speed, [h * 3600.0 for h in values])
    if not sum(values) > 0:
        raise sc.fail(WHERE, "time_share", "out of range: the shares must add up to > 0", values)
    return LoadSpectrum(torque, speed, values).scaled_to(life)


def _series(table: dict, life: float) -> LoadSpectrum:
    torque = sc.number_list(table, "series_torque_Nm", WHERE, min_length=2, allowed=TORQUE)
    speed = [w * RPM for w in _speeds(table, "series_speed_rpm", len(torque))]
    step = sc.number(table, "series_step_s", WHERE, allowed="(0, 1e+06]")
    levels = sc.number(table, "levels", WHERE, 20, allowed="[1, 1000]", integer=True)
    if not max(torque) > 0:
        raise sc.fail(WHERE, "series_torque_Nm", "out of range: no sample above 0 N·m", torque)
    return LoadSpectrum.from_time_series(torque, speed, step, levels).scaled_to(life)
