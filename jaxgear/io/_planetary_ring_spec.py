"""The ring gear's model in a planetary case file: ``[planetary.ring] model`` and ``body``
(docs/planetary.md, "A flexible ring gear"), mapped to :class:`~jaxgear.RigidRing` or
:class:`~jaxgear.CondensedRing`.

.. code-block:: toml

    [planetary.ring]
    torsional_stiffness_Nm_per_rad = 1e12
    model = "condensed"                # or "rigid" (the default)
    body = "seq-ring"                  # a ring body file (fem_prep) or an embedded ring's name
    dynamics = "modal"                 # the ring in the sweep: "quasi-static" (the default),
                                       # "mass" or "modal"
    modes = 24                         # "modal" only: the ring's modes kept, 1..2 Z (default 24)

The ring body's tooth stations must be the ring gear's teeth and, with ``[[gears]]``, its root
radius the ring gear's within :data:`ROOT_TOLERANCE`; refused in one line before any work.

``dynamics`` (:data:`RING_DYNAMICS`) is how the condensed ring enters the dynamic-factor sweep of
``jaxgear run`` and ``jaxgear sweep``: ``"quasi-static"`` the massless ring (its compliance in
series with the ring meshes at every step), ``"mass"`` with its stations' (Guyan) mass and modal
damping at the run's ratio (its nodal-diameter modes respond), ``"modal"`` the same ring in its
``modes`` lowest modes plus the static correction of the others
(:class:`~jaxgear.CondensedRing` ``modes``).
"""

from __future__ import annotations

import abc
import dataclasses

import fem_prep
from fem_prep import schema as sc

from .._planetary_ring import AbstractRingModel, CondensedRing, RigidRing

__all__ = ["RING_DYNAMICS", "RING_MODELS", "CondensedRingSpec", "RigidRingSpec", "RingModelSpec",
           "parse_ring_model"]

#: the ring model's keys in ``[planetary.ring]``
RING_MODEL_KEYS = {"model", "body", "dynamics", "modes"}
#: ``[planetary.ring] dynamics``: how a condensed ring enters the sweep (module docstring)
RING_DYNAMICS = ("quasi-static", "mass", "modal")
#: ``[planetary.ring] modes`` when ``dynamics = "modal"`` does not give it
DEFAULT_RING_MODES = 24
#: the largest relative difference between the ring body's and the ring gear's root radius
ROOT_TOLERANCE = 0.02


class RingModelSpec(abc.ABC):
    """How the case's ring deforms (``[planetary.ring] model``)."""

    #: whether the ring is a flexible body (its outputs: ``jaxgear run``'s ``ring`` section)
    flexible: bool = False

    @abc.abstractmethod
    def ring(self, with_mass: bool = False) -> AbstractRingModel:
        """The library's ring model (with the stations' mass for the dynamics if asked)."""

    @abc.abstractmethod
    def dynamic_ring(self) -> AbstractRingModel:
        """The ring model of the dynamic-factor sweep (``dynamics``, module docstring)."""

    @abc.abstractmethod
    def summary(self) -> dict:
        """The ring model's keys for ``sweep.json`` and ``summary.json``."""

    @abc.abstractmethod
    def words(self) -> str:
        """The ring model in a few words (plot titles, printed lines)."""


@dataclasses.dataclass(frozen=True)
class RigidRingSpec(RingModelSpec):
    """The lumped model's rigid ring (the default)."""

    def ring(self, with_mass=False):
        return RigidRing()

    def dynamic_ring(self):
        return RigidRing()

    def summary(self):
        return {"model": "rigid"}

    def words(self):
        return "rigid ring"


@dataclasses.dataclass(frozen=True)
class CondensedRingSpec(RingModelSpec):
    """A flexible ring: its body (:class:`fem_prep.RingBody`) named by ``body``, condensed on its
    tooth stations once and then read from the fem_prep cache (:func:`fem_prep.ring_stations`).
    """

    body: fem_prep.RingBody
    source: str
    dynamics: str = "quasi-static"
    modes: int | None = None
    flexible = True

    def stations(self) -> fem_prep.RingStations:
        return fem_prep.ring_stations(self.body)

    def ring(self, with_mass=False):
        st = self.stations()
        return CondensedRing(st.compliance, st.mass if with_mass else None)

    def dynamic_ring(self):
        if self.dynamics == "quasi-static":
            return self.ring()
        st = self.stations()
        return CondensedRing(st.compliance, st.mass, self.modes)

    def summary(self):
        out = {"model": "condensed", "body": self.source, "dynamics": self.dynamics}
        if self.modes is not None:
            out["modes"] = self.modes
        return out

    def words(self):
        kind = {"quasi-static": "massless", "mass": "with mass",
                "modal": f"{self.modes} modes"}[self.dynamics]
        return f"condensed ring {self.source} ({kind})"


def _rigid(t: dict, where: str, z_r: int, root_radius: float | None) -> RingModelSpec:
    for key in ("body", "dynamics", "modes"):
        if key in t:
            raise sc.fail(where, key, 'allowed only with model = "condensed"', t[key])
    return RigidRingSpec()


def _condensed(t: dict, where: str, z_r: int, root_radius: float | None) -> RingModelSpec:
    source = sc.string(t, "body", where)
    try:
        body = fem_prep.load_ring_body(source)
    except FileNotFoundError as err:
        raise sc.fail(where, "body", str(err).split(" (")[0] + " (allowed: a ring body file or "
                      f"an embedded ring: {', '.join(fem_prep.embedded_rings())})",
                      source) from None
    except ValueError as err:
        raise sc.SchemaError(f"[{where}] body = {source!r}: {err}") from None
    teeth = body.condensation.teeth
    if teeth != z_r:
        raise sc.fail(where, "body", f"ring body {body.name!r} has {teeth} tooth stations "
                      f"([condensation] teeth); the ring gear has {z_r} teeth (allowed: equal)",
                      source)
    if root_radius is not None:
        diff = abs(body.root_radius - root_radius) / root_radius
        if diff > ROOT_TOLERANCE:
            raise sc.fail(
                where, "body",
                f"ring body {body.name!r} root_radius_mm = {body.root_radius * 1e3:.6g} differs "
                f"from the ring gear's root radius {root_radius * 1e3:.6g} mm by "
                f"{100 * diff:.3g} % (allowed: within {100 * ROOT_TOLERANCE:g} %)", source)
    dynamics = sc.choice(t, "dynamics", where, RING_DYNAMICS, "quasi-static")
    modes = None
    if dynamics == "modal":
        modes = sc.number(t, "modes", where, DEFAULT_RING_MODES, allowed=f"[1, {2 * teeth}]",
                          integer=True, note=f" (2 x the ring body's {teeth} tooth stations)")
    elif "modes" in t:
        raise sc.fail(where, "modes", 'allowed only with dynamics = "modal"', t["modes"])
    return CondensedRingSpec(body, source, dynamics, modes)


#: ``[planetary.ring] model``: the name → its parser (table, where, z_r, root radius (m) or None)
RING_MODELS = {"rigid": _rigid, "condensed": _condensed}


def parse_ring_model(t: dict, z_r: int, root_radius: float | None) -> RingModelSpec:
    """The ring model of ``[planetary.ring]`` (module docstring), validated (one-line
    :class:`~fem_prep.schema.SchemaError`)."""
    where = "planetary.ring"
    return RING_MODELS[sc.choice(t, "model", where, tuple(RING_MODELS), "rigid")](
        t, where, z_r, root_radius)
