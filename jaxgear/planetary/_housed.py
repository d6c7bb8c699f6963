"""A planetary stage whose central members' supports about and along the stage axis are joined
to a condensed housing's seat instead of the ground (docs/planetary.md, "On a housing";
docs/housing.md, "Planetary stages").

The physics is ``PlanetaryOnMount``'s (``_stage.py``: a kind on a
:class:`~jaxgear.scenes.HousingMount`, ``kind.on(mount)``). Here:
:func:`check_carrier_speed`, the refusal of a turning carrier on a mount of all six rows, and
:class:`HousedPlanetary` (deprecated), which builds that kind from a housing, seats, a centre
and ``carrier_held``.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._util import check_instance, is_traced
from ..scenes import Housing, HousingMount
from ._stage import _SUFFIX, AbstractPlanetaryModel, PlanetaryOnMount

__all__ = ["HousedPlanetary", "check_carrier_speed"]


def _entries(value):
    """``seats`` as a tuple of tuples (hashable: a static field); anything else as given, for
    the check to name."""
    try:
        return tuple(tuple(e) if isinstance(e, (list, tuple)) else e for e in value)
    except TypeError:
        return value


def _point(value):
    try:
        return tuple(float(x) for x in value)
    except (TypeError, ValueError):
        return value


def check_carrier_speed(model, carrier_speed, where: str) -> None:
    """Refuse (one line) a turning carrier (``carrier_speed`` (rad/s) != 0, where concrete; a
    traced speed passes) for a kind whose mount joins every support of its members (all six
    rows: the carrier held, :attr:`~jaxgear.scenes.HousingMount.fixed_frame`): its in-plane
    supports join a seat fixed in space, which the turning carrier frame would see through
    cos Ωt and sin Ωt blocks; any other model kind passes."""
    mount = model.mount() if isinstance(model, AbstractPlanetaryModel) else None
    if mount is None or not mount.fixed_frame:
        return
    if carrier_speed is None or is_traced(carrier_speed):
        return
    speed = np.asarray(carrier_speed, dtype=float)
    if np.any(speed != 0.0):
        raise ValueError(
            f"{where}: carrier speed = {speed.tolist()!r} rad/s on a mount that joins every "
            "support (the carrier held), allowed 0 (a star stage): its in-plane supports join "
            "a seat fixed in space, and a turning carrier frame would join them through blocks "
            "carrying cos Ωt and sin Ωt, which the constant structure matrices cannot hold"
        )


class _HousedAlias(type):
    """``HousedPlanetary(...)``, deprecated: it warns and builds the kind on a mount;
    ``isinstance(x, HousedPlanetary)`` asks whether ``x`` is a kind on a mount."""

    def __instancecheck__(cls, obj) -> bool:
        return isinstance(obj, PlanetaryOnMount)

    def __call__(cls, model, housing, seats=(("ring", 0),), centre=(0.0, 0.0, 0.0),
                 carrier_held: bool = False):
        warnings.warn(
            "jaxgear.planetary.HousedPlanetary(model, housing, seats, centre, carrier_held) is "
            "deprecated: use model.on(jaxgear.scenes.HousingMount.on_axis(housing, seats, "
            "centre, carrier_held)), or PlanetaryModel(model, ..., mount=) (the same kind on "
            "the same mount); it will be removed in the next release",
            DeprecationWarning, stacklevel=2)
        where = "HousedPlanetary"
        check_instance("model", model, AbstractPlanetaryModel,
                       "a planetary model kind (TorsionalPlanetary, PlanarPlanetary, "
                       "SpatialPlanetary)", where)
        if model.mount() is not None:
            raise ValueError(f"{where}: model = {model!r}, allowed an unhoused kind")
        check_instance("housing", housing, Housing, "a jaxgear.scenes.Housing", where)
        if not isinstance(carrier_held, bool):
            raise ValueError(f"{where}: carrier_held = {carrier_held!r}, allowed a bool")
        c = np.asarray(_point(centre), dtype=float)
        if c.shape != (3,) or not np.all(np.isfinite(c)):
            raise ValueError(f"{where}: centre = {centre!r}, allowed 3 finite numbers (m)")
        entries, members = _entries(seats), []
        for entry in entries:
            if not (isinstance(entry, tuple) and len(entry) == 2):
                raise ValueError(f"{where}: seats entry {entry!r}, allowed (member, seat index)")
            member = entry[0]
            if member not in _SUFFIX or member in members:
                raise ValueError(
                    f"{where}: seats member {member!r}, allowed one each of 'ring', 'carrier', "
                    "'sun'"
                )
            members.append(member)
        return model.on(HousingMount.on_axis(housing, entries, tuple(c.tolist()),
                                             carrier_held))


class HousedPlanetary(metaclass=_HousedAlias):
    """Deprecated (kept for a release): ``HousedPlanetary(model, housing, seats=(("ring",
    0),), centre=(0, 0, 0), carrier_held=False)`` is ``model.on(HousingMount.on_axis(housing,
    seats, centre, carrier_held))`` (:meth:`~jaxgear.planetary.AbstractPlanetaryModel.on`),
    with a ``DeprecationWarning``; a dynamic model takes ``PlanetaryModel(model, ...,
    mount=)``. ``isinstance(x, HousedPlanetary)`` is whether ``x`` is a kind on a mount."""
