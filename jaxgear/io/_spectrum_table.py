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
from typing import Annotated, ClassVar

import pydantic

from fem_prep import schema as sc

from ..rating import LoadSpectrum
from ._sections import NEEDED, Section, number, number_list, one_of

__all__ = ["SPECTRUM_KEYS", "SpectrumSection", "parse_spectrum"]

RPM = 2 * math.pi / 60
WHERE = "rating.spectrum"
BIN_KEYS = ("torque_Nm", "speed_rpm")
BIN_TIMES = ("hours", "cycles", "time_share")
SERIES_KEYS = ("series_torque_Nm", "series_speed_rpm", "series_step_s", "levels")
TORQUE = "[0, 1e+09]"
SPEED = "[0, 1e+06]"
#: a speed key: one number for every bin (sample) or one per bin (sample)
_SPEEDS = one_of(number=number(SPEED), array=number_list(SPEED))
#: a bin time key: one value per bin, each >= 0
_TIMES = number_list("[0, inf)")


class SpectrumSection(Section):
    """``[rating.spectrum]`` as the file gives it (module docstring), checked whole: each key's
    type and range, then the form (bins or a series, not both), the keys the form needs, one bin
    time, every list as long as its torques; :func:`parse_spectrum` builds the
    :class:`jaxgear.rating.LoadSpectrum` with the rating's life. The keys of a form are required
    within it (the reference lists them as required)."""

    WHERE: ClassVar[str] = WHERE
    # (in the order a reader meets their errors)
    torque_Nm: Annotated[number_list(TORQUE, min_length=1) | None, NEEDED] = None
    speed_rpm: Annotated[_SPEEDS | None, NEEDED] = None
    hours: Annotated[_TIMES | None, NEEDED] = None
    cycles: Annotated[_TIMES | None, NEEDED] = None
    time_share: Annotated[_TIMES | None, NEEDED] = None
    series_torque_Nm: Annotated[number_list(TORQUE, min_length=2) | None, NEEDED] = None
    series_speed_rpm: Annotated[_SPEEDS | None, NEEDED] = None
    series_step_s: Annotated[number("(0, 1e+06]") | None, NEEDED] = None
    levels: number("[1, 1000]", integer=True) = 20

    @property
    def series(self) -> bool:
        """Whether the spectrum is a sampled history (else bins)."""
        return bool(self.given & set(SERIES_KEYS))

    @pydantic.model_validator(mode="before")
    @classmethod
    def _one_form(cls, data, info):
        """The form first (by the keys given, before their values): bins or a series, and
        one bin time."""
        if not isinstance(data, dict) or set(data) - set(cls.model_fields):
            return data  # an unknown key: reported first
        where = _where(info)
        series = [k for k in SERIES_KEYS if k in data]
        bins = [k for k in (*BIN_KEYS, *BIN_TIMES) if k in data]
        if series and bins:
            raise sc.fail(where, bins[0], f"give bins (torque_Nm, speed_rpm, hours | cycles | "
                          f"time_share) or a series (series_torque_Nm, ...), not both "
                          f"({series[0]} is given too)")
        times = [k for k in BIN_TIMES if k in data]
        if len(times) > 1:
            raise sc.fail(where, "hours", f"{times[0]} and {times[1]} both given: give one of "
                          "hours, cycles, time_share")
        return data

    @pydantic.model_validator(mode="after")
    def _form(self, info):
        where = _where(info)
        series = self.series
        torque_key, speed_key = (("series_torque_Nm", "series_speed_rpm") if series
                                 else BIN_KEYS)
        for key in (torque_key, speed_key):
            if getattr(self, key) is None:
                raise sc.fail(where, key, "missing required key")
        torque, speed = getattr(self, torque_key), getattr(self, speed_key)
        each = f"one per {'sample' if series else 'bin'} of {torque_key}"
        if isinstance(speed, list) and len(speed) != len(torque):
            raise sc.fail(where, speed_key, f"must be an array of {len(torque)} numbers ({each})",
                          speed)
        if series:
            if self.series_step_s is None:
                raise sc.fail(where, "series_step_s", "missing required key")
            if not max(torque) > 0:
                raise sc.fail(where, "series_torque_Nm", "out of range: no sample above 0 N·m",
                              torque)
            return self
        times = [k for k in BIN_TIMES if k in self.given]
        if not times:
            raise sc.fail(where, "hours", "missing: give one of hours, cycles, time_share")
        values = getattr(self, times[0])
        if len(values) != len(torque):
            raise sc.fail(where, times[0], f"must be an array of {len(torque)} numbers ({each})",
                          values)
        if times[0] == "time_share" and not sum(values) > 0:
            raise sc.fail(where, "time_share", "out of range: the shares must add up to > 0",
                          values)
        return self


def _where(info) -> str:
    """The table's name in the file's messages: the reader's context's ``spectrum_where`` (a
    gearbox's ``"load_spectrum"``), else ``rating.spectrum`` (a pair's, read within its
    ``[rating]``)."""
    return (info.context or {}).get("spectrum_where", WHERE)


#: the keys of ``[rating.spectrum]``
SPECTRUM_KEYS = set(SpectrumSection.model_fields)


def _per_entry(value, n: int) -> list[float]:
    """A speed key (one number for all ``n`` entries, or a list of ``n``) as ``n`` numbers."""
    return [float(v) for v in value] if isinstance(value, list) else [float(value)] * n


def parse_spectrum(table: dict | SpectrumSection, life: float,
                   where: str = WHERE) -> LoadSpectrum:
    """``[rating.spectrum]`` (module docstring; a table, or its :class:`SpectrumSection`) as a
    :class:`jaxgear.rating.LoadSpectrum` (SI); ``life`` the rating's life (s, ``[rating]
    life_h``) that ``time_share`` and a series are scaled to; ``where`` the table's name in
    the file's messages (a gearbox's ``"load_spectrum"``: the same keys, of its input member).

    Raises:
        SchemaError: an unknown key, keys of two forms (or two bin times), a list of another
            length than ``torque_Nm``, a value out of range, no loaded turning bin; one line
            naming the key, its value and the allowed range.
    """
    section = (table if isinstance(table, SpectrumSection) else SpectrumSection.read(
        table, where, context={"spectrum_where": where}))
    try:
        if section.series:
            return _series(section, life)
        return _bins(section, life, where)
    except ValueError as err:  # the model's own check (no loaded, turning bin)
        if isinstance(err, sc.SchemaError):
            raise
        raise sc.fail(where, None, str(err)) from None


def _bins(s: SpectrumSection, life: float, where: str = WHERE) -> LoadSpectrum:
    torque = list(s.torque_Nm)
    speed = [w * RPM for w in _per_entry(s.speed_rpm, len(torque))]
    if s.cycles is not None:
        try:
            return LoadSpectrum.from_cycles(torque, speed, list(s.cycles))
        except ValueError as err:
            raise sc.fail(where, "cycles", str(err).split(": ", 1)[-1], s.cycles) from None
    if s.hours is not None:
        return LoadSpectrum(torque, speed, [h * 3600.0 for h in s.hours])
    return LoadSpectrum(torque, speed, list(s.time_share)).scaled_to(life)


def _series(s: SpectrumSection, life: float) -> LoadSpectrum:
    torque = list(s.series_torque_Nm)
    speed = [w * RPM for w in _per_entry(s.series_speed_rpm, len(torque))]
    return LoadSpectrum.from_time_series(torque, speed, s.series_step_s, s.levels).scaled_to(life)
