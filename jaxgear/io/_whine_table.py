"""The case file's ``[whine]`` table: gear whine in the frequency domain over a speed range
(:func:`jaxgear.dynamics.whine_response`, docs/whine.md), checked whole and mapped to the
method object here only.

Keys (file units; ranges as checked)::

    [whine]
    speed_min_rad_s = 50.0          # the input (pinion; a stage's input member) speed range,
                                    # (0, 1e5] rad/s ...
    speed_max_rad_s = 1500.0        # ... > speed_min_rad_s
    speeds = 48                     # speeds, equally spaced, [2, 2000]; default 48
    harmonics = 16                  # H, the orders of the span's fundamental kept, [1, 256]
    method = "harmonic-balance"     # or "te-source" (the mean stiffness: TE as a displacement
                                    # source), or "quasi-periodic" (a train of several mesh
                                    # frequencies: H orders of each mesh's own frequency);
                                    # default "harmonic-balance"
    sidebands = 1                   # "quasi-periodic" only: the other meshes' orders around
                                    # each mesh's, [0, harmonics]; default 1
    positions_per_period = 256      # quasi-static positions per mesh period, [4, 8192], and
                                    # at least 4 harmonics + 1 over the model's span; with
                                    # "quasi-periodic" also a list, one per mesh-frequency
                                    # group, each [1, 8192] (a train's: steps per first-mesh
                                    # period of that group's table; a gearbox's: points per
                                    # that stage's own mesh period), e.g. [140, 35]

``jaxgear run`` on a pair or train case with a lumped scene (torsional or lumped 3D; a pair
without ``[scene]``: the torsional one) or on a planetary stage's case (its lumped stage: the
speeds are the input member's) writes ``whine/whine.json``, ``whine/whine.csv``, the order plots
and the waterfall of the TE and the bearing forces; a gearbox's stages each run their own case's
table.
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal, NamedTuple

import pydantic

from fem_prep import schema as sc

from ..dynamics import (
    AbstractWhineMethod,
    HarmonicBalance,
    QuasiPeriodicBalance,
    TransmissionErrorSource,
)
from ._sections import Section, number, number_list, one_of

__all__ = ["WHINE_KEYS", "WHINE_METHODS", "WhineInputs", "WhineSection", "highest_order_frequency",
           "lowest_order_frequency", "order_frequency_range", "parse_whine", "whine_of"]

WHERE = "whine"
#: ``[whine] method`` names
WHINE_METHODS = {
    "harmonic-balance": HarmonicBalance,
    "te-source": TransmissionErrorSource,
    "quasi-periodic": QuasiPeriodicBalance,
}


class WhineInputs(NamedTuple):
    """``[whine]`` in SI: ``speeds`` (rad/s, a list), the ``method`` object with its H, and
    ``positions`` per mesh period (an int, or with :class:`QuasiPeriodicBalance` a tuple of
    ints, one per mesh-frequency group)."""

    speeds: list[float]
    method: AbstractWhineMethod
    positions: int | tuple[int, ...]


class WhineSection(Section):
    """``[whine]`` as the file gives it (keys and ranges: the module docstring), checked whole;
    :meth:`inputs` its SI inputs."""

    WHERE: ClassVar[str] = WHERE
    speed_min_rad_s: number("(0, 1e+05]")
    speed_max_rad_s: number("(0, 1e+05]")
    speeds: number("[2, 2000]", integer=True) = 48
    harmonics: number("[1, 256]", integer=True) = 16
    method: Literal["harmonic-balance", "te-source", "quasi-periodic"] = "harmonic-balance"
    positions_per_period: one_of(
        number=number("[4, 8192]", integer=True),
        array=number_list("[1, 8192]", min_length=1, integer=True,
                          note=" (one per mesh-frequency group)"),
    ) = 256
    sidebands: number("[0, 256]", integer=True) | None = None

    @pydantic.model_validator(mode="after")
    def _related(self):
        lo, hi, H, name = self.speed_min_rad_s, self.speed_max_rad_s, self.harmonics, self.method
        if not hi > lo:
            raise sc.fail(WHERE, "speed_max_rad_s",
                          f"out of range, allowed > speed_min_rad_s = {lo:g}", hi)
        P = self.positions_per_period
        if isinstance(P, list) and name != "quasi-periodic":
            raise sc.fail(WHERE, "positions_per_period", "a list (one per mesh-frequency group) "
                          f"is for method = \"quasi-periodic\" only (method = \"{name}\"): "
                          "allowed an integer in [4, 8192]", P)
        if not isinstance(P, list) and P < 4 * H + 1:
            raise sc.fail(WHERE, "positions_per_period",
                          f"out of range, allowed >= 4 harmonics + 1 = {4 * H + 1}", P)
        S = self.sidebands
        if name != "quasi-periodic" and S is not None:
            raise sc.fail(WHERE, "sidebands", f"is for method = \"quasi-periodic\" only "
                          f"(method = \"{name}\")", S)
        if S is not None and S > H:
            raise sc.fail(WHERE, "sidebands", f"out of range, allowed [0, harmonics = {H}]", S)
        return self

    def inputs(self) -> WhineInputs:
        """The SI inputs (:class:`WhineInputs`): the speeds equally spaced over the range, the
        method object."""
        lo, hi, n, H = self.speed_min_rad_s, self.speed_max_rad_s, self.speeds, self.harmonics
        speeds = [lo + (hi - lo) * k / (n - 1) for k in range(n)]
        P = self.positions_per_period
        P = tuple(P) if isinstance(P, list) else P
        if self.method != "quasi-periodic":
            return WhineInputs(speeds, WHINE_METHODS[self.method](H), P)
        S = 1 if self.sidebands is None else self.sidebands
        return WhineInputs(speeds, QuasiPeriodicBalance(H, S), P)


#: the keys of ``[whine]``
WHINE_KEYS = set(WhineSection.model_fields)


def parse_whine(table: dict) -> WhineInputs:
    """``[whine]`` (module docstring) as :class:`WhineInputs` (:class:`WhineSection`).

    Raises:
        SchemaError: an unknown key, a value out of range, a range whose maximum is not above
            its minimum, an unknown method; one line naming the key, its value and the allowed
            range.
    """
    return WhineSection.read(table).inputs()


def whine_of(case) -> WhineInputs | None:
    """The ``[whine]`` inputs of a case (:class:`WhineInputs`, of its :attr:`Case.whine
    <jaxgear.io.Case>`), None without the table."""
    section = getattr(case, "whine", None)
    return None if section is None else section.inputs()


def lowest_order_frequency(inputs: WhineInputs, teeth_per_turn, span: int = 1,
                           names=None) -> tuple[float, str]:
    """The lowest frequency (Hz) among the orders > 0 the whine's outputs hold, at the bottom
    of its speed range, and a few words saying which (arguments as
    :func:`highest_order_frequency`): ``"quasi-periodic"`` order 1 of the slowest mesh's own
    frequency; ``"harmonic-balance"``, ``"te-source"`` order 1 / q of the first mesh's."""
    low = min(inputs.speeds)
    t = [float(x) for x in teeth_per_turn]
    if isinstance(inputs.method, QuasiPeriodicBalance):
        k = min(range(len(t)), key=t.__getitem__)
        name = f"mesh {k + 1}" if names is None else names[k]
        return t[k] * low / (2 * math.pi), f"order 1 of {name}'s mesh frequency at {low:g} rad/s"
    which = f"order 1/{span} of the first mesh's frequency" if span > 1 else (
        "order 1 of the mesh frequency")
    return t[0] / span * low / (2 * math.pi), f"{which} at {low:g} rad/s"


def order_frequency_range(inputs: WhineInputs, teeth_per_turn, span: int = 1) -> tuple[float, float]:
    """(lowest, highest) frequency (Hz) among the orders the whine's outputs hold over its
    speeds (the mean left out): :func:`lowest_order_frequency`'s and
    :func:`highest_order_frequency`'s. Arguments as there."""
    return (lowest_order_frequency(inputs, teeth_per_turn, span)[0],
            highest_order_frequency(inputs, teeth_per_turn, span)[0])


def highest_order_frequency(inputs: WhineInputs, teeth_per_turn, span: int = 1,
                            names=None) -> tuple[float, str]:
    """The highest frequency (Hz) among the orders the whine's outputs hold
    (:class:`~jaxgear.dynamics.WhineResponse`'s ``orders`` times its ``frequency``) at the top
    of its speed range, and a few words saying which order of which mesh it is.

    ``"quasi-periodic"``: every mesh's own orders 1..H (H = ``harmonics``), so the largest of
    H f_k over the meshes k. ``"harmonic-balance"``, ``"te-source"``: the orders h / q of the
    first mesh's frequency, h <= H, over a span of q = ``span`` first-mesh periods (1 for a
    pair, for a train whose meshes pass teeth at the first's rate, for a planetary stage's
    mesh frequency), so H f_1 / q.

    Args:
        inputs: the parsed ``[whine]`` (:func:`parse_whine`).
        teeth_per_turn: each mesh's teeth per turn of the input member (its mesh frequency
            over Ω / 2π at input speed Ω; a pair's: the pinion's teeth), the first mesh first.
        span: q, the model's span in first-mesh periods (``Case.span_periods``).
        names: each mesh's name in the words (default "mesh 1", "mesh 2", ...).
    """
    H = int(inputs.method.harmonics)
    top = max(inputs.speeds)
    t = [float(x) for x in teeth_per_turn]
    if isinstance(inputs.method, QuasiPeriodicBalance):
        k = max(range(len(t)), key=t.__getitem__)
        name = f"mesh {k + 1}" if names is None else names[k]
        which = f"order {H} of {name}'s mesh frequency"
        f = H * t[k] * top / (2 * math.pi)
    else:
        which = f"order {H}/{span} of the first mesh's frequency" if span > 1 else (
            f"order {H} of the mesh frequency")
        f = H * t[0] / span * top / (2 * math.pi)
    return f, f"{which} at {top:g} rad/s"
